//! Why a debugger operation failed: one typed error for the whole adapter. Its
//! `Display` is the message the client reads (an error response's `message`), so the
//! words stay in one place; the kind says what went wrong, for code that must decide
//! on it (a launch error over TCP is redacted, an edit replayed is reported, not fatal).

/// What went wrong, with the message for the user.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DebugError {
    /// A request that needs a launched program came before `launch`.
    #[error("no program is loaded: send `launch` first")]
    NotLaunched,
    /// A request that needs the program paused came while it runs.
    #[error("the program is running; `pause` first")]
    Running,
    /// Reverse debugging asked of a launch without history.
    #[error("reverse debugging is off (launch with \"history\": true)")]
    NoHistory,
    /// A point older than the oldest snapshot kept.
    #[error("that point is older than the kept history")]
    BeforeHistory,
    /// A launch attribute, or an input it names, that cannot be used: in the project
    /// layer's words (`launch attribute cycleBudget: …`, `gloc.toml:1:16: …`).
    #[error("{0}")]
    Launch(String),
    /// An expression that cannot be parsed, checked or evaluated on the paused state.
    #[error("{0}")]
    Expression(String),
    /// A change to the paused script or vehicle that cannot be made.
    #[error("{0}")]
    Edit(String),
    /// A request whose arguments name nothing the adapter knows (a reference, an
    /// address, a line, a filter), or that does not fit the session's state.
    #[error("{0}")]
    Request(String),
    /// The client could not be written to.
    #[error("cannot write to the client: {0}")]
    Io(String),
}

impl DebugError {
    /// A launch error with `message`.
    pub fn launch(message: impl Into<String>) -> DebugError {
        DebugError::Launch(message.into())
    }

    /// An expression error with `message`.
    pub fn expression(message: impl Into<String>) -> DebugError {
        DebugError::Expression(message.into())
    }

    /// An edit error with `message`.
    pub fn edit(message: impl Into<String>) -> DebugError {
        DebugError::Edit(message.into())
    }

    /// A request error with `message`.
    pub fn request(message: impl Into<String>) -> DebugError {
        DebugError::Request(message.into())
    }

    /// The same kind of error with its message rewritten (`Launch` errors over TCP
    /// have quoted text blanked out); the unit kinds keep their fixed words.
    pub fn map_message(self, rewrite: impl FnOnce(String) -> String) -> DebugError {
        match self {
            DebugError::Launch(message) => DebugError::Launch(rewrite(message)),
            DebugError::Expression(message) => DebugError::Expression(rewrite(message)),
            DebugError::Edit(message) => DebugError::Edit(rewrite(message)),
            DebugError::Request(message) => DebugError::Request(rewrite(message)),
            DebugError::Io(message) => DebugError::Io(rewrite(message)),
            unit => unit,
        }
    }
}

impl From<std::io::Error> for DebugError {
    fn from(error: std::io::Error) -> DebugError {
        DebugError::Io(error.to_string())
    }
}

/// A result of the adapter.
pub type DebugResult<T> = Result<T, DebugError>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_is_the_display_and_rewriting_keeps_the_kind() {
        assert_eq!(
            DebugError::NotLaunched.to_string(),
            "no program is loaded: send `launch` first"
        );
        let error = DebugError::launch("the mission `x.mi` is missing");
        assert_eq!(error.to_string(), "the mission `x.mi` is missing");
        let rewritten = error.map_message(|message| message.replace("x.mi", "…"));
        assert_eq!(rewritten, DebugError::launch("the mission `…` is missing"));
        assert_eq!(
            DebugError::Running.map_message(|_| String::new()),
            DebugError::Running
        );
    }
}
