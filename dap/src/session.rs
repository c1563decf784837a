//! One debug session, the protocol edge: the session token check, each request
//! dispatched through the command table (its answer written as a response, or an
//! error response), the events the handler queued, and the world run in slices so
//! `pause` and `disconnect` are heard mid-run. The one place that names stop reasons
//! and output categories as DAP strings. What a launch loads is `launch`, the
//! breakpoints the client sets `breakpoints`; the commands are `handlers`, which
//! `lib` hands the session (so this module does not import them).

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::Serialize;
use serde_json::{json, Value};

use crate::breakpoints::Breakpoints;
use crate::cancel::Cancellations;
use crate::debugger::{Category, Clock, Debugger, Progress, RunMode, Slice, Stop, StopReason};
use crate::dispatch::{Dispatcher, Failure};
use crate::error::{DebugError, DebugResult};
use crate::features::ClientOptions;
use crate::launch::{self, LaunchArguments};
use crate::protocol::{Malformed, Request, Writer};
use crate::references::{source_of, THREAD_ID};
use crate::types::*;
use crate::world::World;

/// Steps run between two looks at the incoming queue while running, and the longest
/// time between two looks: a request (`pause`, `disconnect`) waits at most this long
/// plus one step.
const SLICE_STEPS: u64 = 50_000;
const SLICE_TIME: Duration = Duration::from_millis(50);

/// Who may use a session. Over stdio the client is the editor that started the
/// adapter; over TCP any local user can connect, so the session needs the secret
/// printed with the port (`gloc dap --port`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Access {
    Open,
    /// The session token a `launch` must carry as its `token` attribute.
    Token(String),
}

/// What the adapter answers before a `launch` carried the token: nothing that
/// reads a file or the program.
const BEFORE_TOKEN: &[&str] = &["initialize", "disconnect"];

/// Whether the main loop goes on after a request.
#[derive(Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    Exit,
}

pub(crate) struct Running {
    pub mode: RunMode,
    pub start: Clock,
    /// The request that started the run (a `cancel` may name it).
    pub request_seq: i64,
    /// The progress shown while the run lasts longer than a slice, and when it last
    /// said which cycle the run is in.
    pub progress: Option<(String, Instant)>,
}

impl Running {
    /// A run about to start from `start`, on behalf of request `request_seq`.
    pub fn new(mode: RunMode, start: Clock, request_seq: i64) -> Running {
        Running {
            mode,
            start,
            request_seq,
            progress: None,
        }
    }
}

/// How often a long run's progress says which cycle it is in.
const PROGRESS_UPDATES: Duration = Duration::from_secs(1);

pub(crate) struct Launched {
    pub debugger: Debugger<World>,
    pub arguments: LaunchArguments,
    pub running: Option<Running>,
    pub stop_on_entry: bool,
}

/// What a handler leaves for after its response, in order.
pub(crate) enum Then {
    /// An event with its body.
    Event(&'static str, Value),
    /// The debugger's pending outputs.
    Outputs,
    /// The outputs, then the `stopped` event.
    Stop(Stop),
    /// End the session.
    Exit,
}

pub struct Session {
    writer: Writer,
    /// The command table requests are dispatched through.
    handlers: &'static Dispatcher<Session>,
    access: Access,
    /// Whether a `launch` carried the token (always, for `Access::Open`).
    authenticated: bool,
    /// Set with `authenticated`, for the reader's framing limits.
    authenticated_flag: Option<Arc<AtomicBool>>,
    pub(crate) initialized: bool,
    pub(crate) launched: Option<Launched>,
    /// The breakpoints the client set, kept across a `restart`.
    pub(crate) breakpoints: Breakpoints,
    /// What the running handler queued for after its response.
    then: Vec<Then>,
    /// The `seq` of the request being handled.
    pub(crate) request_seq: i64,
    /// `cancel`s, noted by the reader thread as they arrive.
    pub(crate) cancellations: Cancellations,
    /// How the client counts lines and columns, and whether it shows progress.
    pub(crate) client: ClientOptions,
}

impl Session {
    /// A session answering through `writer` with the commands of `handlers`.
    pub fn new(writer: Writer, access: Access, handlers: &'static Dispatcher<Session>) -> Session {
        Session {
            writer,
            handlers,
            authenticated: access == Access::Open,
            authenticated_flag: None,
            access,
            initialized: false,
            launched: None,
            breakpoints: Breakpoints::default(),
            then: Vec::new(),
            request_seq: 0,
            cancellations: Cancellations::default(),
            client: ClientOptions::default(),
        }
    }

    /// Shares the list of `cancel`s the reader thread notes.
    pub fn cancelling(mut self, cancellations: Cancellations) -> Session {
        self.cancellations = cancellations;
        self
    }

    pub fn is_running(&self) -> bool {
        self.launched
            .as_ref()
            .is_some_and(|launched| launched.running.is_some())
    }

    /// Also sets `flag` when the session authenticates, before the `launch` that
    /// carried the token is answered.
    pub fn signalling(mut self, flag: Arc<AtomicBool>) -> Session {
        self.authenticated_flag = Some(flag);
        self
    }

    pub fn is_authenticated(&self) -> bool {
        self.authenticated
    }

    /// Answers a frame that is not a usable request. Without a usable `seq` no
    /// response can name its request (the schema requires `request_seq` from 1 to
    /// 2^31 − 1), so the error goes to the client's console as an `output` event
    /// whose `data` holds what could be read (`seq` as sent, `command`), and the
    /// request is not run.
    pub fn respond_malformed(&mut self, malformed: &Malformed) -> io::Result<()> {
        if malformed.request_seq >= 1 {
            return self.writer.respond_error(
                malformed.request_seq,
                &malformed.command,
                &malformed.message,
            );
        }
        let data = match &malformed.raw_seq {
            Some(seq) => Some(json!({ "seq": seq, "command": malformed.command })),
            None if !malformed.command.is_empty() => Some(json!({ "command": malformed.command })),
            None => None,
        };
        self.writer.event(
            "output",
            OutputEventBody {
                category: category_name(Category::Important).into(),
                output: format!(
                    "gloc dap: ignored a malformed message: {}\n",
                    malformed.message
                ),
                source: None,
                line: None,
                data,
            },
        )
    }

    /// Handles one request through the handler table: the response (an error in the
    /// request becomes an error response), then what the handler queued.
    pub fn handle(&mut self, mut request: Request) -> io::Result<Flow> {
        if !self.authenticated {
            if let Some(flow) = self.authenticate(&request)? {
                return Ok(flow);
            }
        }
        self.then.clear();
        self.request_seq = request.seq;
        let arguments = std::mem::take(&mut request.arguments);
        let answer = self.handlers.dispatch(self, &request.command, arguments);
        let body = match answer {
            Ok(body) => body,
            Err(Failure(message)) => {
                self.then.clear();
                self.writer
                    .respond_error(request.seq, &request.command, &message)?;
                return Ok(Flow::Continue);
            }
        };
        self.writer.respond(&request, body)?;
        let mut flow = Flow::Continue;
        for then in std::mem::take(&mut self.then) {
            match then {
                Then::Event(event, body) => self.writer.event(event, body)?,
                Then::Outputs => self.flush_outputs()?,
                Then::Stop(stop) => self.send_stop(stop)?,
                Then::Exit => flow = Flow::Exit,
            }
        }
        Ok(flow)
    }

    /// Queues `then` for after the response of the request being handled.
    pub(crate) fn then(&mut self, then: Then) {
        self.then.push(then);
    }

    /// Queues an event for after the response.
    pub(crate) fn then_event(&mut self, event: &'static str, body: impl Serialize) {
        let body = serde_json::to_value(body).unwrap_or(Value::Null);
        self.then.push(Then::Event(event, body));
    }

    /// Answers `request` with an error and ends the session.
    pub fn refuse(&mut self, request: &Request, message: &str) -> io::Result<Flow> {
        self.writer
            .respond_error(request.seq, &request.command, message)?;
        Ok(Flow::Exit)
    }

    /// Before the token: `initialize` and `disconnect` pass, a `launch` with the right
    /// `token` authenticates the session, anything else is refused; a wrong token
    /// closes the connection. `None` lets the request through to `dispatch`.
    fn authenticate(&mut self, request: &Request) -> io::Result<Option<Flow>> {
        let Access::Token(expected) = &self.access else {
            return Ok(None);
        };
        if BEFORE_TOKEN.contains(&request.command.as_str()) {
            return Ok(None);
        }
        if request.command != "launch" {
            self.writer.respond_error(
                request.seq,
                &request.command,
                "this adapter listens on a TCP port and needs its session token first: send `launch` with the `token` printed by `gloc dap --port`",
            )?;
            return Ok(Some(Flow::Continue));
        }
        let given = request.arguments.get("token").and_then(Value::as_str);
        if given.is_some_and(|given| same_secret(given, expected)) {
            self.authenticated = true;
            if let Some(flag) = &self.authenticated_flag {
                flag.store(true, Ordering::SeqCst);
            }
            return Ok(None);
        }
        let message = if given.is_none() {
            "`launch` needs the `token` attribute: the session token printed by `gloc dap --port`; closing the connection"
        } else {
            "wrong session token; closing the connection"
        };
        self.writer
            .respond_error(request.seq, &request.command, message)?;
        Ok(Some(Flow::Exit))
    }

    pub(crate) fn launched_mut(&mut self) -> DebugResult<&mut Launched> {
        self.launched.as_mut().ok_or(DebugError::NotLaunched)
    }

    /// The client's breakpoints with the debugger they apply to, if launched (a
    /// `set*Breakpoints` before `launch` is kept and applied at the launch).
    pub(crate) fn breakpoints_and_debugger(
        &mut self,
    ) -> (&mut Breakpoints, Option<&mut Debugger<World>>) {
        let debugger = self
            .launched
            .as_mut()
            .map(|launched| &mut launched.debugger);
        (&mut self.breakpoints, debugger)
    }

    /// Loads what `arguments` name (see `launch::launch`) in place of any program
    /// before, and applies the breakpoints the client set. Over TCP no error may
    /// quote what a file holds: diagnostics quote tokens of the line at fault, so
    /// quoted text is blanked out.
    pub(crate) fn launch(&mut self, arguments: LaunchArguments) -> DebugResult<()> {
        let access = &self.access;
        let mut debugger = launch::launch(&arguments, |error| match access {
            Access::Open => error,
            Access::Token(_) => error.map_message(|message| redact_quotes(&message)),
        })?;
        self.breakpoints.reapply(&mut debugger);
        self.launched = Some(Launched {
            debugger,
            stop_on_entry: arguments.stop_on_entry.unwrap_or(false),
            arguments,
            running: None,
        });
        Ok(())
    }

    /// Shows a cancellable progress for a long run (when the client shows them).
    pub(crate) fn start_progress(
        &mut self,
        id: &str,
        title: &str,
        request_seq: i64,
    ) -> io::Result<()> {
        self.writer.event(
            "progressStart",
            ProgressStartEventBody {
                progress_id: id.to_string(),
                title: title.into(),
                request_id: Some(request_seq),
                cancellable: true,
                message: None,
            },
        )
    }

    pub(crate) fn end_progress(&mut self, id: String) -> io::Result<()> {
        self.writer.event(
            "progressEnd",
            ProgressEventBody {
                progress_id: id,
                message: None,
            },
        )
    }

    /// Runs one slice of a forward run and reports a stop or the end.
    pub fn run_slice(&mut self) -> io::Result<Flow> {
        let Some(launched) = &mut self.launched else {
            return Ok(Flow::Continue);
        };
        let Some(running) = &launched.running else {
            return Ok(Flow::Continue);
        };
        let shown = running.progress.clone().map(|(id, _)| id);
        let request_seq = running.request_seq;
        let progress = if self.cancellations.cancelled(request_seq, shown.as_deref()) {
            // A cancelled run stops where the last slice left it (a step boundary).
            Progress::Stopped(Stop {
                reason: StopReason::Pause,
                description: format!("Run cancelled at cycle {}", launched.debugger.clock().cycle),
                text: None,
                hit_breakpoint_ids: Vec::new(),
            })
        } else {
            launched.debugger.run(
                running.mode,
                running.start,
                Slice {
                    steps: SLICE_STEPS,
                    until: Some(Instant::now() + SLICE_TIME),
                },
            )
        };
        if !matches!(progress, Progress::Running) {
            launched.running = None;
        } else if self.client.supports_progress_reporting {
            let cycle = launched.debugger.clock().cycle;
            let Some(running) = &mut launched.running else {
                return Ok(Flow::Continue);
            };
            match &mut running.progress {
                // Longer than one slice: show a progress the user can cancel.
                None => {
                    let id = format!("run-{request_seq}");
                    running.progress = Some((id.clone(), Instant::now()));
                    self.start_progress(&id, "Running", request_seq)?;
                }
                Some((id, updated)) if updated.elapsed() >= PROGRESS_UPDATES => {
                    *updated = Instant::now();
                    let id = id.clone();
                    self.writer.event(
                        "progressUpdate",
                        ProgressEventBody {
                            progress_id: id,
                            message: Some(format!("cycle {cycle}")),
                        },
                    )?;
                }
                Some(_) => {}
            }
        }
        self.flush_outputs()?;
        if let (Some(id), false) = (shown, matches!(progress, Progress::Running)) {
            self.end_progress(id)?;
        }
        match progress {
            Progress::Running => {}
            Progress::Stopped(stop) => self.send_stop(stop)?,
            Progress::Ended { summary } => {
                self.writer.event(
                    "output",
                    OutputEventBody {
                        category: category_name(Category::Note).into(),
                        output: format!("{summary}\n"),
                        source: None,
                        line: None,
                        data: None,
                    },
                )?;
                self.writer
                    .event("exited", ExitedEventBody { exit_code: 0 })?;
                self.writer.event("terminated", ())?;
            }
        }
        Ok(Flow::Continue)
    }

    fn flush_outputs(&mut self) -> io::Result<()> {
        let Some(launched) = &mut self.launched else {
            return Ok(());
        };
        let outputs = launched.debugger.take_outputs();
        let source = source_of(&launched.debugger);
        for output in outputs {
            // Over TCP the adapter's own notices (setup warnings quote the mission's
            // lines) blank quoted text, as launch errors do; the script's prints pass.
            let text = match (&self.access, output.category) {
                (Access::Token(_), Category::Important) => redact_quotes(&output.text),
                _ => output.text,
            };
            self.writer.event(
                "output",
                OutputEventBody {
                    category: category_name(output.category).into(),
                    output: text,
                    source: output.line.map(|_| source.clone()),
                    line: output.line.map(i64::from),
                    data: None,
                },
            )?;
        }
        Ok(())
    }

    fn send_stop(&mut self, stop: Stop) -> io::Result<()> {
        self.flush_outputs()?;
        if let Some(launched) = &mut self.launched {
            launched.debugger.reset_baseline();
        }
        self.writer.event(
            "stopped",
            StoppedEventBody {
                reason: reason_name(stop.reason).into(),
                description: Some(stop.description),
                thread_id: THREAD_ID,
                text: stop.text,
                all_threads_stopped: true,
                hit_breakpoint_ids: if stop.hit_breakpoint_ids.is_empty() {
                    None
                } else {
                    Some(stop.hit_breakpoint_ids)
                },
            },
        )
    }
}

/// The DAP `StoppedEvent.reason` of a stop.
fn reason_name(reason: StopReason) -> &'static str {
    match reason {
        StopReason::Entry => "entry",
        StopReason::Pause => "pause",
        StopReason::Step => "step",
        StopReason::Breakpoint => "breakpoint",
        // Cycle breakpoints are set as function breakpoints.
        StopReason::CycleBreakpoint => "function breakpoint",
        StopReason::DataBreakpoint => "data breakpoint",
        StopReason::InstructionBreakpoint => "instruction breakpoint",
        StopReason::Exception => "exception",
        StopReason::Goto => "goto",
        // Reasons of their own (the schema's list is open): a client shows them as
        // "Paused on waypoint", "Paused on surfacing".
        StopReason::Waypoint => "waypoint",
        StopReason::Surfacing => "surfacing",
    }
}

/// The DAP `OutputEvent.category` of an output.
fn category_name(category: Category) -> &'static str {
    match category {
        Category::Script => "stdout",
        Category::Error => "stderr",
        Category::Note => "console",
        Category::Important => "important",
    }
}

/// `text` with what stands between backquotes or double quotes replaced by `…`.
fn redact_quotes(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut open: Option<char> = None;
    for character in text.chars() {
        match open {
            Some(quote) if character == quote => {
                out.push('…');
                out.push(character);
                open = None;
            }
            Some(_) if character == '\n' => {
                // An unclosed quote ends with its line.
                out.push('…');
                out.push(character);
                open = None;
            }
            Some(_) => {}
            None => {
                out.push(character);
                if character == '`' || character == '"' {
                    open = Some(character);
                }
            }
        }
    }
    if open.is_some() {
        out.push('…');
    }
    out
}

/// Compares a token with the expected one in time that does not depend on where
/// they differ.
fn same_secret(given: &str, expected: &str) -> bool {
    let (given, expected) = (given.as_bytes(), expected.as_bytes());
    given.len() == expected.len()
        && given
            .iter()
            .zip(expected)
            .fold(0u8, |difference, (a, b)| difference | (a ^ b))
            == 0
}
