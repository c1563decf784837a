//! gloc-dap: the debug adapter (`gloc dap`). Debugs a GBASIC or GLOC script running on
//! the GLOC interpreter inside the glider simulator, cycle by cycle, forwards and back.
//!
//! Layers: `protocol` (framing, envelope, the one writer), `types` (serde structs),
//! `session` (the protocol edge: token, responses, events, run slices), `launch` (the
//! launch attributes onto the project layer's `Overrides`), `breakpoints` (what the
//! client sets, kept for `restart`), `dispatch` and `handlers` (the command table: one
//! typed handler per command), `error` (`DebugError`), `debugger` (breakpoints,
//! stepping, history; protocol free), `target` (what the debugger needs from a world),
//! `world` (the one such world, over the simulator or a replay), `script` (the
//! `ScriptState` both share), `expr` (GBASIC expressions for conditions and watches),
//! `edits` (setExpression, goto, the console's names), `completion` (filtering and
//! ranking them), `format` (values as `print` writes them, or hex), `features` (the
//! console's, Watch's and goto's answers), `cancel` (`cancel`s noted as they arrive).

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]
// Stdout is the protocol: nothing else may print there.
#![deny(clippy::print_stdout)]

pub mod breakpoints;
pub mod cancel;
pub mod completion;
pub mod debugger;
pub mod dispatch;
pub mod edits;
pub mod error;
pub mod expr;
pub mod features;
pub mod format;
mod handlers;
mod journey;
pub mod launch;
pub mod program;
pub mod protocol;
mod references;
pub mod replay_world;
pub mod script;
pub mod session;
pub mod target;
pub mod types;
pub mod world;

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use protocol::{Frame, Reader, Writer};
use session::{Flow, Session};

pub use launch::LAUNCH_ATTRIBUTES;
pub use session::Access;

/// Limits of `gloc dap --port` (documented in docs/dap.md).
pub mod limits {
    use std::time::Duration;

    /// Authenticated sessions served at once; a `launch` beyond them is refused.
    pub const MAX_SESSIONS: usize = 16;
    /// Connections still waiting for their token; a new one beyond them closes the
    /// oldest, so idle connections can never lock a real client out.
    pub const MAX_UNAUTHENTICATED: usize = 64;
    /// Time a connection has to send a `launch` with the token.
    pub const TOKEN_TIMEOUT: Duration = Duration::from_secs(10);
    /// An authenticated session that is not running and hears nothing for this long
    /// is closed.
    pub const IDLE_TIMEOUT: Duration = Duration::from_secs(30 * 60);
    /// A client that does not read what the adapter writes for this long is dropped.
    pub const WRITE_TIMEOUT: Duration = Duration::from_secs(60);
    /// The framing limits before the token: `initialize` and `launch` are small, and
    /// 64 waiting connections must not hold 64 full-size bodies (64 MiB each).
    pub const BEFORE_TOKEN: gloc_framing::Limits = gloc_framing::Limits {
        max_body: 1024 * 1024,
        ..gloc_framing::LIMITS
    };
    /// The environment variable that may hold the session token (at least
    /// `MIN_TOKEN_CHARS` characters); without it a random one is made.
    pub const TOKEN_VARIABLE: &str = "GLOC_DAP_TOKEN";
    pub const MIN_TOKEN_CHARS: usize = 16;
}

/// Serves one debug session over a byte stream until the client disconnects or closes
/// the stream. A reader thread feeds requests through a channel; this thread owns the
/// session and runs the world in slices between requests.
pub fn serve(
    input: impl Read + Send + 'static,
    output: impl Write + Send + 'static,
) -> io::Result<()> {
    serve_session(input, output, Access::Open, None)
}

/// Serves on stdin/stdout.
pub fn serve_stdio() -> io::Result<()> {
    serve(io::stdin(), io::stdout())
}

/// What a TCP session shares with the listener.
struct Connection {
    stream: TcpStream,
    shared: Arc<Shared>,
    id: u64,
}

#[derive(Default)]
struct Shared {
    /// Connections without the token yet, oldest first.
    unauthenticated: Mutex<VecDeque<(u64, TcpStream)>>,
    sessions: AtomicUsize,
    next_id: AtomicU64,
}

impl Shared {
    fn forget(&self, id: u64) {
        let mut waiting = self
            .unauthenticated
            .lock()
            .unwrap_or_else(|poison| poison.into_inner());
        waiting.retain(|(known, _)| *known != id);
    }
}

/// Listens on 127.0.0.1 only and serves each connection on its own thread, once it
/// presents the session token. `on_listening` learns the bound address (useful with
/// port 0) and the token, to print them.
pub fn serve_tcp(port: u16, on_listening: impl FnOnce(SocketAddr, &str)) -> io::Result<()> {
    let token = session_token()?;
    let listener = TcpListener::bind(("127.0.0.1", port))?;
    on_listening(listener.local_addr()?, &token);
    let shared = Arc::new(Shared::default());
    for stream in listener.incoming() {
        let stream = match stream {
            Ok(stream) => stream,
            Err(error) => {
                // E.g. out of file descriptors: wait for sessions to end.
                eprintln!("gloc dap: cannot accept a connection: {error}");
                thread::sleep(Duration::from_millis(100));
                continue;
            }
        };
        if let Err(error) = accept(stream, &token, &shared) {
            eprintln!("gloc dap: cannot serve a connection: {error}");
        }
    }
    Ok(())
}

fn accept(stream: TcpStream, token: &str, shared: &Arc<Shared>) -> io::Result<()> {
    stream.set_nodelay(true)?;
    stream.set_read_timeout(Some(limits::TOKEN_TIMEOUT))?;
    stream.set_write_timeout(Some(limits::WRITE_TIMEOUT))?;
    let id = shared.next_id.fetch_add(1, Ordering::Relaxed);
    {
        let mut waiting = shared
            .unauthenticated
            .lock()
            .unwrap_or_else(|poison| poison.into_inner());
        while waiting.len() >= limits::MAX_UNAUTHENTICATED {
            if let Some((_, oldest)) = waiting.pop_front() {
                let _ = oldest.shutdown(Shutdown::Both);
            }
        }
        waiting.push_back((id, stream.try_clone()?));
    }
    let input = stream.try_clone()?;
    let output = stream.try_clone()?;
    let connection = Connection {
        stream,
        shared: shared.clone(),
        id,
    };
    let access = Access::Token(token.to_string());
    let spawned = thread::Builder::new()
        .name("dap-session".into())
        // As large as a main thread's: launching compiles the script.
        .stack_size(8 << 20)
        .spawn(move || {
            let shared = connection.shared.clone();
            let stream = connection.stream.try_clone();
            if let Err(error) = serve_session(input, output, access, Some(connection)) {
                eprintln!("gloc dap: session ended with an error: {error}");
            }
            shared.forget(id);
            if let Ok(stream) = stream {
                let _ = stream.shutdown(Shutdown::Both);
            }
        });
    if let Err(error) = spawned {
        shared.forget(id);
        return Err(error);
    }
    Ok(())
}

/// The token from `GLOC_DAP_TOKEN`, or 128 random bits in hex.
fn session_token() -> io::Result<String> {
    if let Ok(token) = std::env::var(limits::TOKEN_VARIABLE) {
        if token.chars().count() < limits::MIN_TOKEN_CHARS || token.chars().any(char::is_whitespace)
        {
            return Err(io::Error::other(format!(
                "{} must hold at least {} characters and no spaces",
                limits::TOKEN_VARIABLE,
                limits::MIN_TOKEN_CHARS
            )));
        }
        return Ok(token);
    }
    let mut bytes = [0u8; 16];
    match std::fs::File::open("/dev/urandom").and_then(|mut random| random.read_exact(&mut bytes)) {
        Ok(()) => {}
        Err(_) => {
            // No /dev/urandom (Windows): SipHash keyed by the OS's randomness
            // (`RandomState`) is unpredictable without its keys.
            use std::hash::{BuildHasher, Hasher};
            for (index, chunk) in bytes.chunks_mut(8).enumerate() {
                let mut hasher = std::collections::hash_map::RandomState::new().build_hasher();
                hasher.write_usize(index);
                hasher.write_u128(
                    std::time::SystemTime::now()
                        .duration_since(std::time::UNIX_EPOCH)
                        .map(|time| time.as_nanos())
                        .unwrap_or(0),
                );
                chunk.copy_from_slice(&hasher.finish().to_le_bytes());
            }
        }
    }
    Ok(bytes.iter().map(|byte| format!("{byte:02x}")).collect())
}

/// The session loop. With a `connection` (TCP), it also enforces the limits: the
/// token timeout, the session cap, the idle timeout, and closing after `disconnect`.
fn serve_session(
    input: impl Read + Send + 'static,
    output: impl Write + Send + 'static,
    access: Access,
    connection: Option<Connection>,
) -> io::Result<()> {
    let (sender, receiver) = mpsc::channel::<Frame>();
    // Until the token is shown, bodies are held to the smaller limit; the session sets
    // the flag before it answers the `launch` that carried the token.
    let authenticated = Arc::new(AtomicBool::new(false));
    let mut reader = Reader::new(input);
    if access != Access::Open {
        reader.limit_until(limits::BEFORE_TOKEN, authenticated.clone());
    }
    // A reverse run holds this thread: the reader notes `cancel`s for it to see.
    let cancellations = cancel::Cancellations::default();
    let noted = cancellations.clone();
    thread::Builder::new()
        .name("dap-reader".into())
        .spawn(move || loop {
            let frame = reader.next_frame();
            if let Frame::Request(request) = &frame {
                if request.command == "cancel" {
                    noted.note(&request.arguments);
                }
            }
            let closed = matches!(frame, Frame::Closed);
            if sender.send(frame).is_err() || closed {
                break;
            }
        })?;
    let mut session = Session::new(Writer::new(Box::new(output)), access, handlers::table())
        .signalling(authenticated)
        .cancelling(cancellations);
    let mut admitted = false;
    let opened = Instant::now();
    let mut last_heard = opened;
    let result = loop {
        // The token timeout is a deadline from the connection's start: a client that
        // trickles a byte now and then does not extend it.
        let waiting_for_token = connection.is_some() && !session.is_authenticated();
        if waiting_for_token && opened.elapsed() >= limits::TOKEN_TIMEOUT {
            break Ok(());
        }
        let wait = if waiting_for_token {
            limits::TOKEN_TIMEOUT.saturating_sub(opened.elapsed())
        } else {
            limits::IDLE_TIMEOUT
        };
        let frame = if session.is_running() {
            match receiver.try_recv() {
                Ok(frame) => Some(frame),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => Some(Frame::Closed),
            }
        } else {
            match receiver.recv_timeout(wait) {
                Ok(frame) => Some(frame),
                Err(RecvTimeoutError::Timeout) => Some(Frame::Idle),
                Err(RecvTimeoutError::Disconnected) => Some(Frame::Closed),
            }
        };
        if !matches!(frame, None | Some(Frame::Idle)) {
            last_heard = Instant::now();
        }
        let flow = match frame {
            None => session.run_slice(),
            Some(Frame::Request(request)) => {
                let launching = !session.is_authenticated() && request.command == "launch";
                match (&connection, launching) {
                    (Some(connection), true) => {
                        admit(&mut session, connection, request, &mut admitted)
                    }
                    _ => session.handle(request),
                }
            }
            Some(Frame::Malformed(malformed)) => session
                .respond_malformed(&malformed)
                .map(|()| Flow::Continue),
            Some(Frame::Idle) if connection.is_none() => Ok(Flow::Continue),
            Some(Frame::Idle) => Ok(idle(&session, last_heard)),
            // The client went away: stop at once, leaving nothing behind.
            Some(Frame::Closed) => Ok(Flow::Exit),
        };
        match flow {
            Ok(Flow::Continue) => {}
            Ok(Flow::Exit) => break Ok(()),
            Err(error) => break Err(error),
        }
    };
    if let Some(connection) = &connection {
        if admitted {
            connection.shared.sessions.fetch_sub(1, Ordering::SeqCst);
        }
        // Close after `disconnect` answered: the client sees the end of the stream.
        let _ = connection.stream.shutdown(Shutdown::Both);
    }
    result
}

/// A `launch` on a connection without the token yet: within the session cap, it may
/// authenticate the session; then the connection leaves the waiting list and gets
/// the idle timeout instead of the token timeout.
fn admit(
    session: &mut Session,
    connection: &Connection,
    request: protocol::Request,
    admitted: &mut bool,
) -> io::Result<Flow> {
    let sessions = &connection.shared.sessions;
    if sessions.fetch_add(1, Ordering::SeqCst) >= limits::MAX_SESSIONS {
        sessions.fetch_sub(1, Ordering::SeqCst);
        return session.refuse(
            &request,
            &format!(
                "the adapter already serves {} sessions (its limit); try again when one ends",
                limits::MAX_SESSIONS
            ),
        );
    }
    let flow = session.handle(request)?;
    if session.is_authenticated() {
        *admitted = true;
        connection.shared.forget(connection.id);
        connection
            .stream
            .set_read_timeout(Some(limits::IDLE_TIMEOUT))?;
    } else {
        sessions.fetch_sub(1, Ordering::SeqCst);
    }
    Ok(flow)
}

/// Nothing heard for a read timeout: a connection without the token is closed; an
/// authenticated one only when it is not running and has been idle for the whole
/// idle timeout.
fn idle(session: &Session, last_heard: Instant) -> Flow {
    if !session.is_authenticated() {
        return Flow::Exit;
    }
    if session.is_running() || last_heard.elapsed() < limits::IDLE_TIMEOUT {
        Flow::Continue
    } else {
        Flow::Exit
    }
}
