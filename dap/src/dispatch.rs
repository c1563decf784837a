//! The table of request handlers: each DAP command names one function that takes its
//! typed arguments and returns a typed body or a [`Failure`]; the JSON conversions
//! (arguments in, body out) and the wording of a bad-arguments error are done here,
//! once, for every command.

use std::collections::HashMap;

use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;

use crate::error::DebugError;

/// Why a request failed: the message of its error response.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure(pub String);

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure(message)
    }
}

impl From<DebugError> for Failure {
    fn from(error: DebugError) -> Failure {
        Failure(error.to_string())
    }
}

impl From<&str> for Failure {
    fn from(message: &str) -> Failure {
        Failure(message.to_string())
    }
}

type Erased<S> = Box<dyn Fn(&mut S, Value) -> Result<Value, Failure> + Send + Sync>;

/// Command name → handler, over the state `S` the handlers share.
pub struct Dispatcher<S> {
    handlers: HashMap<&'static str, Erased<S>>,
}

impl<S> Default for Dispatcher<S> {
    fn default() -> Self {
        Dispatcher {
            handlers: HashMap::new(),
        }
    }
}

impl<S: 'static> Dispatcher<S> {
    pub fn new() -> Dispatcher<S> {
        Dispatcher::default()
    }

    /// Registers `handler` for `command`. Its arguments are read from the request's
    /// `arguments` (absent or `null` arrive as `{}`); its body is written as the
    /// response's `body` (omitted when it is `()`).
    pub fn on<A, B>(
        mut self,
        command: &'static str,
        handler: fn(&mut S, A) -> Result<B, Failure>,
    ) -> Self
    where
        A: DeserializeOwned + 'static,
        B: Serialize + 'static,
    {
        let erased = move |state: &mut S, arguments: Value| {
            let arguments: A = serde_json::from_value(arguments)
                .map_err(|error| Failure(format!("invalid arguments for `{command}`: {error}")))?;
            let body = handler(state, arguments)?;
            serde_json::to_value(body).map_err(|error| {
                Failure(format!("cannot write the answer to `{command}`: {error}"))
            })
        };
        self.handlers.insert(command, Box::new(erased));
        self
    }

    /// Runs the handler of `command`: the response body, or why the request failed.
    pub fn dispatch(
        &self,
        state: &mut S,
        command: &str,
        arguments: Value,
    ) -> Result<Value, Failure> {
        match self.handlers.get(command) {
            Some(handler) => handler(state, arguments),
            None => Err(Failure(format!("unknown command `{command}`"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;
    use serde_json::json;

    #[derive(Deserialize, Default)]
    #[serde(default)]
    struct Add {
        by: i64,
    }

    fn add(total: &mut i64, arguments: Add) -> Result<i64, Failure> {
        if arguments.by < 0 {
            return Err("only up".into());
        }
        *total += arguments.by;
        Ok(*total)
    }

    #[test]
    fn typed_handlers_get_their_arguments_and_give_their_bodies() {
        let table = Dispatcher::new().on("add", add);
        let mut total = 1;
        assert_eq!(
            table.dispatch(&mut total, "add", json!({ "by": 2 })),
            Ok(json!(3))
        );
        assert_eq!(table.dispatch(&mut total, "add", json!({})), Ok(json!(3)));
        assert_eq!(
            table.dispatch(&mut total, "add", json!({ "by": -1 })),
            Err(Failure("only up".into()))
        );
        let Err(Failure(message)) = table.dispatch(&mut total, "add", json!({ "by": "x" })) else {
            panic!("took a string for a number")
        };
        assert!(
            message.starts_with("invalid arguments for `add`: "),
            "{message}"
        );
        assert_eq!(
            table.dispatch(&mut total, "sub", json!({})),
            Err(Failure("unknown command `sub`".into()))
        );
        assert_eq!(total, 3);
    }
}
