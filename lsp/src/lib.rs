//! gloc-lsp: the language server for GBASIC (`.gbas`) and GLOC (`.gloc`).
//!
//! A thin shell over the core crates: it keeps the open documents, asks
//! `gloc-engine` and `gloc-compiler` for every answer and converts byte spans
//! to LSP positions in one module (`position`).

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]
// Stdout is the protocol: nothing else may print there.
#![deny(clippy::print_stdout)]

mod document;
mod features;
mod position;
mod server;
mod transport;

use std::collections::HashSet;
use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};

use tokio::io::{AsyncRead, AsyncWrite, AsyncWriteExt};
use tower_lsp_server::jsonrpc::{Error, Id, Request, Response};
use tower_lsp_server::{LspService, Server};
use tower_service::Service;

use gloc_ide::{analysis, lang};

pub use server::{settings_from, Settings, COMPILED_GLOC_COMMAND};

/// The semantic tokens of a GBASIC text computed `runs` times outside the protocol (the
/// analysis once, before): the token count and each run's time. For the benchmark.
#[doc(hidden)]
pub fn time_semantic_tokens(text: &str, runs: usize) -> (usize, Vec<std::time::Duration>) {
    let context = analysis::Context::new(Arc::new(gloc_engine::sensors::SensorList::embedded()));
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
        .finish();
    let service = Guard {
        inner: service,
        requests: Arc::default(),
        shutdown_requested: shutdown_requested.clone(),
    };
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

/// Requests read but not answered yet, and which of them the client cancelled.
#[derive(Default)]
struct Requests {
    queued: HashSet<Id>,
    cancelled: HashSet<Id>,
}

/// Wraps the server where tower-lsp-server calls it, that is as each message is
/// *read*, not when its turn comes (`concurrency_level(1)` runs them one by one):
/// - `$/cancelRequest` marks a queued request, which then answers −32800
///   (RequestCancelled) without running when its turn comes, so a queue of
///   cancelled requests drains at once (tower-lsp-server only cancels what is
///   running, and with one request at a time its cancel arrives too late);
/// - a `shutdown` request is remembered at once, so an `exit` sent right after it
///   (which aborts whatever is still queued) still exits with code 0.
struct Guard<S> {
    inner: S,
    requests: Arc<Mutex<Requests>>,
    shutdown_requested: Arc<AtomicBool>,
}

type Answer<E> = Pin<Box<dyn Future<Output = Result<Option<Response>, E>> + Send>>;

impl<S> Service<Request> for Guard<S>
where
    S: Service<Request, Response = Option<Response>>,
    S::Future: Send + 'static,
    S::Error: 'static,
{
    type Response = Option<Response>;
    type Error = S::Error;
    type Future = Answer<S::Error>;

    fn poll_ready(&mut self, context: &mut Context<'_>) -> Poll<Result<(), S::Error>> {
        self.inner.poll_ready(context)
    }

    fn call(&mut self, request: Request) -> Self::Future {
        let requests = self.requests.clone();
        let id = request.id().cloned();
        {
            let mut requests = requests.lock().unwrap_or_else(|poison| poison.into_inner());
            if request.method() == "$/cancelRequest" {
                let cancelled = request
                    .params()
                    .and_then(|params| params.get("id"))
                    .and_then(|id| serde_json::from_value::<Id>(id.clone()).ok());
                if let Some(cancelled) = cancelled {
                    if requests.queued.contains(&cancelled) {
                        requests.cancelled.insert(cancelled);
                    }
                }
            }
            if let Some(id) = &id {
                requests.queued.insert(id.clone());
            }
        }
        if request.method() == "shutdown" && id.is_some() {
            self.shutdown_requested.store(true, Ordering::SeqCst);
        }
        let answer = self.inner.call(request);
        Box::pin(async move {
            let Some(id) = id else {
                return answer.await;
            };
            let cancelled = {
                let mut requests = requests.lock().unwrap_or_else(|poison| poison.into_inner());
                requests.cancelled.remove(&id)
            };
            let result = if cancelled {
                // Dropped unpolled: the handler never runs.
                drop(answer);
                Ok(Some(Response::from_error(
                    id.clone(),
                    Error::request_cancelled(),
                )))
            } else {
                answer.await
            };
            let mut requests = requests.lock().unwrap_or_else(|poison| poison.into_inner());
            requests.queued.remove(&id);
            requests.cancelled.remove(&id);
            result
        })
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
