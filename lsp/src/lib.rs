//! gloc-lsp: the language server for GBASIC (`.gbas`) and GLOC (`.gloc`).
//!
//! A thin shell over the core crates: it keeps the open documents, asks
//! `gloc-engine` and `gloc-compiler` for every answer and converts byte spans
//! to LSP positions in one module (`position`).

mod analysis;
mod document;
mod features;
mod gbasic_lang;
mod gloc_lang;
mod lang;
mod position;
mod server;
mod transport;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use tokio::io::{AsyncRead, AsyncWrite, AsyncWriteExt};
use tower_lsp_server::{LspService, Server};

pub use server::{settings_from, Settings, COMPILED_GLOC_COMMAND};

/// The semantic tokens of a GBASIC text computed `runs` times outside the protocol (the
/// analysis once, before): the token count and each run's time. For the benchmark.
#[doc(hidden)]
pub fn time_semantic_tokens(text: &str, runs: usize) -> (usize, Vec<std::time::Duration>) {
    let context = analysis::Context {
        sensors: Arc::new(gloc_engine::sensors::SensorList::embedded()),
        cycle_budget: None,
    };
    let language = document::Language::Gbasic;
    let uri = "file:///bench.gbas".parse().expect("a constant, valid URI");
    let document = document::Document::new(uri, language, 1, text);
    let analysis = lang::analyze(language, text, &context);
    let mut count = 0;
    let times = (0..runs)
        .map(|_| {
            let started = std::time::Instant::now();
            count = features::semantic_tokens(&document, &analysis, &context)
                .data
                .len();
            started.elapsed()
        })
        .collect();
    (count, times)
}

/// How the session ended, for the process exit code (LSP: 0 when `shutdown`
/// came before `exit`, 1 otherwise, e.g. when the client just went away).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    Clean,
    WithoutShutdown,
}

/// Serves one client over a pair of byte streams until `exit` or end of input.
pub async fn serve<I, O>(input: I, output: O) -> Ending
where
    I: AsyncRead + Unpin,
    O: AsyncWrite,
{
    let shutdown_requested = Arc::new(AtomicBool::new(false));
    let flag = shutdown_requested.clone();
    let (service, socket) = LspService::build(move |client| server::Backend::new(client, flag))
        .custom_method(
            transport::INVALID_REQUEST_METHOD,
            server::Backend::invalid_request,
        )
        .custom_method(
            transport::INVALID_NOTIFICATION_METHOD,
            server::Backend::invalid_notification,
        )
        .finish();
    let (pipe_reader, mut pipe_writer) = tokio::io::simplex(1 << 16);
    // One message at a time: a request always sees every edit sent before it.
    let server = Server::new(pipe_reader, output, socket)
        .concurrency_level(1)
        .serve(service);
    tokio::pin!(server);
    tokio::select! {
        () = &mut server => {}
        // End of input closes the pipe; the server then finishes by itself.
        // Dropping a simplex write half does not close the pipe (the read
        // half keeps the stream alive): only `shutdown` signals end of input.
        () = transport::sanitize(input, &mut pipe_writer) => {
            let _ = pipe_writer.shutdown().await;
            server.await
        }
    }
    if shutdown_requested.load(Ordering::SeqCst) {
        Ending::Clean
    } else {
        Ending::WithoutShutdown
    }
}

/// `gloc lsp`: serves on stdin/stdout on a single-threaded runtime.
pub fn run_stdio() -> std::io::Result<Ending> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    let ending = runtime.block_on(serve(tokio::io::stdin(), tokio::io::stdout()));
    // Tokio reads stdin on a blocking thread that only wakes up on input;
    // do not wait for it after `exit` (clients may keep stdin open).
    runtime.shutdown_background();
    Ok(ending)
}
