//! gloc-dap: the debug adapter (`gloc dap`). Debugs a GBASIC or GLOC script running on
//! the GLOC interpreter inside the glider simulator, cycle by cycle, forwards and back.
//!
//! Layers: `protocol` (framing, envelope, the one writer), `types` (serde structs),
//! `session` (request dispatch), `debugger` (breakpoints, stepping, history; protocol
//! free), `target` (what the debugger needs from a world), `world` (that, over the
//! engine and simulator), `expr` (GBASIC expressions for conditions and watches).
#![deny(clippy::unwrap_used)]

pub mod debugger;
pub mod expr;
pub mod program;
pub mod protocol;
pub mod replay_world;
pub mod session;
pub mod target;
pub mod types;
pub mod world;

use std::io::{self, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener};
use std::sync::mpsc::{self, TryRecvError};
use std::thread;

use protocol::{read_frame, Frame, Writer};
use session::{Flow, Session};

pub use session::LAUNCH_ATTRIBUTES;

/// Serves one debug session over a byte stream until the client disconnects or closes
/// the stream. A reader thread feeds requests through a channel; this thread owns the
/// session and runs the world in slices between requests.
pub fn serve(
    input: impl Read + Send + 'static,
    output: impl Write + Send + 'static,
) -> io::Result<()> {
    let (sender, receiver) = mpsc::channel::<Frame>();
    thread::Builder::new()
        .name("dap-reader".into())
        .spawn(move || {
            let mut reader = BufReader::new(input);
            loop {
                let frame = read_frame(&mut reader);
                let closed = matches!(frame, Frame::Closed);
                if sender.send(frame).is_err() || closed {
                    break;
                }
            }
        })?;
    let mut session = Session::new(Writer::new(Box::new(output)));
    loop {
        let frame = if session.is_running() {
            match receiver.try_recv() {
                Ok(frame) => Some(frame),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => Some(Frame::Closed),
            }
        } else {
            Some(receiver.recv().unwrap_or(Frame::Closed))
        };
        let flow = match frame {
            None => session.run_slice()?,
            Some(Frame::Request(request)) => session.handle(request)?,
            Some(Frame::Malformed(malformed)) => {
                session.respond_malformed(
                    malformed.request_seq,
                    &malformed.command,
                    &malformed.message,
                )?;
                Flow::Continue
            }
            // The client went away: stop at once, leaving nothing behind.
            Some(Frame::Closed) => Flow::Exit,
        };
        if flow == Flow::Exit {
            return Ok(());
        }
    }
}

/// Serves on stdin/stdout.
pub fn serve_stdio() -> io::Result<()> {
    serve(io::stdin(), io::stdout())
}

/// Listens on 127.0.0.1 only and serves one session per connection, one after the other.
/// `on_listening` learns the bound address (useful with port 0).
pub fn serve_tcp(port: u16, on_listening: impl FnOnce(SocketAddr)) -> io::Result<()> {
    let listener = TcpListener::bind(("127.0.0.1", port))?;
    on_listening(listener.local_addr()?);
    for stream in listener.incoming() {
        let stream = stream?;
        let reader = stream.try_clone()?;
        if let Err(error) = serve(reader, stream) {
            eprintln!("gloc dap: session ended with an error: {error}");
        }
    }
    Ok(())
}
