//! One debug session: dispatches requests on their `command` string, keeps the launch
//! state, and runs the world in slices so `pause` and `disconnect` are heard mid-run.

use std::io;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::cancel::Cancellations;
use crate::debugger::{
    Clock, CycleBreakpoint, CycleBreakpointKind, DataBreakpoint, Debugger, Edit, HistoryConfig,
    HitCondition, InstructionBreakpoint, LineBreakpoint, Progress, RunMode, Stop,
};
use crate::edits;
use crate::features::{self, ClientOptions};
use crate::format::ValueFormat;
use crate::program::Language;
use crate::protocol::{Malformed, Request, Writer};
use crate::target::{Named, Phase, Target};
use crate::types::*;
use crate::world::{self, LaunchConfig, World};

pub const THREAD_ID: i64 = 1;
const FRAME_ID: i64 = 1;
const SCOPE_VARIABLES: i64 = 1;
const SCOPE_REGISTERS: i64 = 2;
const SCOPE_SENSORS: i64 = 3;
const SCOPE_VEHICLE: i64 = 4;
const ALL_SENSORS: i64 = 5;
/// `ARRAYS + i`: the elements of the i-th GBASIC variable (an array).
pub(crate) const ARRAYS: i64 = 1000;
/// Steps run between two looks at the incoming queue while running.
const SLICE_STEPS: u64 = 50_000;

/// The launch attributes the adapter accepts (`editors/vscode/package.json` declares
/// the same names; a test keeps them in step).
pub const LAUNCH_ATTRIBUTES: &[&str] = &[
    "program",
    "mission",
    "masterdata",
    "profile",
    "seed",
    "stopOnEntry",
    "cycleBudget",
    "maxCycles",
    "history",
    "token",
    "replay",
    "sensorCache",
];

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

/// The most instructions one `disassemble` may ask for (the response holds exactly
/// as many, padded with invalid entries where there is no code).
pub const MAX_DISASSEMBLE: i64 = 100_000;

#[derive(Debug, Default, Deserialize, Serialize, Clone)]
#[serde(default, rename_all = "camelCase")]
pub struct LaunchArguments {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mission: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub masterdata: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_on_entry: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle_budget: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_cycles: Option<u64>,
    /// `true`/`false`, or the number of snapshots to keep (0 = off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub history: Option<Value>,
    /// The session token of `gloc dap --port` (never echoed back).
    #[serde(skip_serializing)]
    pub token: Option<String>,
    /// Recorded data to step through instead of simulating: one path or a list
    /// (a CSV file, or glider logs: a deployment, flight and science merged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replay: Option<Value>,
    /// The folder searched first for the glider logs' sensor lists (`<crc>.cac`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor_cache: Option<String>,
}

/// `replay`: a path, a list of paths, or empty (`""`, `[]`, `null`: simulate).
fn replay_paths(value: Option<&Value>) -> Result<Vec<PathBuf>, String> {
    const FORM: &str = "`replay` must be a path or a list of paths (a CSV file or glider logs)";
    let paths: Vec<&str> = match value {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::String(path)) => vec![path.as_str()],
        Some(Value::Array(items)) => items
            .iter()
            .map(|item| item.as_str().ok_or(FORM))
            .collect::<Result<_, _>>()?,
        Some(_) => return Err(FORM.into()),
    };
    Ok(paths
        .into_iter()
        .filter(|path| !path.trim().is_empty())
        .map(PathBuf::from)
        .collect())
}

/// Whether the main loop goes on after a request.
#[derive(Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    Exit,
}

struct Running {
    mode: RunMode,
    start: Clock,
    /// The request that started the run (a `cancel` may name it).
    request_seq: i64,
    /// The progress shown while the run lasts longer than a slice.
    progress: Option<String>,
}

struct Launched {
    debugger: Debugger<World>,
    arguments: LaunchArguments,
    running: Option<Running>,
    stop_on_entry: bool,
}

/// Breakpoints as the client last sent them, kept so `restart` can re-apply them.
#[derive(Default)]
struct Requested {
    sources: Vec<(String, Vec<SourceBreakpoint>)>,
    functions: Vec<FunctionBreakpoint>,
    data: Vec<crate::types::DataBreakpoint>,
    instructions: Vec<crate::types::InstructionBreakpoint>,
    filters: Option<Vec<String>>,
    filter_options: Vec<ExceptionFilterOptions>,
}

pub struct Session {
    writer: Writer,
    access: Access,
    /// Whether a `launch` carried the token (always, for `Access::Open`).
    authenticated: bool,
    /// Set with `authenticated`, for the reader's framing limits.
    authenticated_flag: Option<Arc<AtomicBool>>,
    initialized: bool,
    launched: Option<Launched>,
    requested: Requested,
    next_breakpoint_id: i64,
    /// `cancel`s, noted by the reader thread as they arrive.
    cancellations: Cancellations,
    client: ClientOptions,
}

fn capabilities() -> Capabilities {
    Capabilities {
        supports_configuration_done_request: Some(true),
        supports_function_breakpoints: Some(true),
        supports_conditional_breakpoints: Some(true),
        supports_hit_conditional_breakpoints: Some(true),
        supports_evaluate_for_hovers: Some(true),
        exception_breakpoint_filters: Some(crate::features::exception_breakpoint_filters()),
        supports_set_variable: Some(true),
        supports_restart_request: Some(true),
        supports_log_points: Some(true),
        supports_terminate_request: Some(true),
        supports_data_breakpoints: Some(true),
        supports_disassemble_request: Some(true),
        supports_stepping_granularity: Some(true),
        supports_instruction_breakpoints: Some(true),
        supports_breakpoint_locations_request: Some(true),
        supports_exception_info_request: Some(true),
        supports_loaded_sources_request: Some(true),
        // Announced after launch with a `capabilities` event when history is on.
        supports_step_back: None,
        supports_completions_request: Some(true),
        supports_set_expression: Some(true),
        supports_goto_targets_request: Some(true),
        supports_value_formatting_options: Some(true),
        supports_cancel_request: Some(true),
        supports_exception_filter_options: Some(true),
    }
}

fn arguments<T: for<'de> Deserialize<'de>>(request: &Request) -> Result<T, String> {
    serde_json::from_value(request.arguments.clone())
        .map_err(|error| format!("invalid arguments for `{}`: {error}", request.command))
}

impl Session {
    pub fn new(writer: Writer, access: Access) -> Session {
        Session {
            writer,
            authenticated: access == Access::Open,
            authenticated_flag: None,
            access,
            initialized: false,
            launched: None,
            requested: Requested::default(),
            next_breakpoint_id: 1,
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
                category: "important".into(),
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

    /// Handles one request; an error in the request becomes an error response.
    pub fn handle(&mut self, request: Request) -> io::Result<Flow> {
        if !self.authenticated {
            if let Some(flow) = self.authenticate(&request)? {
                return Ok(flow);
            }
        }
        match self.dispatch(&request) {
            Ok(flow) => Ok(flow),
            Err(message) => {
                self.writer
                    .respond_error(request.seq, &request.command, &message)?;
                Ok(Flow::Continue)
            }
        }
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

    fn dispatch(&mut self, request: &Request) -> Result<Flow, String> {
        let io_error = |error: io::Error| format!("cannot write to the client: {error}");
        match request.command.as_str() {
            "initialize" => {
                let arguments: InitializeArguments = arguments(request)?;
                self.client = ClientOptions::of(&arguments);
                self.initialized = true;
                self.writer
                    .respond(request, capabilities())
                    .map_err(io_error)?;
            }
            "launch" => {
                if !self.initialized {
                    return Err("send `initialize` before `launch`".into());
                }
                if self.launched.is_some() {
                    return Err(
                        "a program is already running; `restart` or `disconnect` first".into(),
                    );
                }
                let launch: LaunchArguments = arguments(request)?;
                self.launch(launch)?;
                self.writer.respond(request, ()).map_err(io_error)?;
                if self
                    .launched
                    .as_ref()
                    .is_some_and(|launched| launched.debugger.has_history())
                {
                    self.writer
                        .event(
                            "capabilities",
                            json!({ "capabilities": { "supportsStepBack": true } }),
                        )
                        .map_err(io_error)?;
                }
                self.writer.event("initialized", ()).map_err(io_error)?;
            }
            "attach" => return Err("`attach` is not supported: use `launch`".into()),
            "disconnect" => {
                let _: DisconnectArguments = arguments(request)?;
                self.writer.respond(request, ()).map_err(io_error)?;
                return Ok(Flow::Exit);
            }
            "terminate" => {
                self.writer.respond(request, ()).map_err(io_error)?;
                if let Some(launched) = &mut self.launched {
                    launched.running = None;
                }
                self.writer.event("terminated", ()).map_err(io_error)?;
            }
            "setBreakpoints" => {
                let arguments: SetBreakpointsArguments = arguments(request)?;
                let breakpoints = self.set_breakpoints(arguments)?;
                self.writer
                    .respond(request, json!({ "breakpoints": breakpoints }))
                    .map_err(io_error)?;
            }
            "setFunctionBreakpoints" => {
                let arguments: SetFunctionBreakpointsArguments = arguments(request)?;
                self.requested.functions = arguments.breakpoints;
                let breakpoints = self.apply_function_breakpoints();
                self.writer
                    .respond(request, json!({ "breakpoints": breakpoints }))
                    .map_err(io_error)?;
            }
            "setExceptionBreakpoints" => {
                let arguments: SetExceptionBreakpointsArguments = arguments(request)?;
                let debugger = self.launched.as_ref().map(|launched| &launched.debugger);
                let (_, breakpoints) = features::exception_filters(&arguments, |condition| {
                    debugger.and_then(|debugger| condition_error(debugger, condition))
                })?;
                self.requested.filters = Some(arguments.filters);
                self.requested.filter_options = arguments.filter_options.unwrap_or_default();
                self.apply_filters();
                self.writer
                    .respond(request, json!({ "breakpoints": breakpoints }))
                    .map_err(io_error)?;
            }
            "setInstructionBreakpoints" => {
                let arguments: SetInstructionBreakpointsArguments = arguments(request)?;
                self.requested.instructions = arguments.breakpoints;
                let breakpoints = self.apply_instruction_breakpoints();
                self.writer
                    .respond(request, json!({ "breakpoints": breakpoints }))
                    .map_err(io_error)?;
            }
            "dataBreakpointInfo" => {
                let arguments: DataBreakpointInfoArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let target = &launched.debugger.target;
                let in_sensor_scope = matches!(
                    arguments.variables_reference,
                    None | Some(SCOPE_SENSORS) | Some(ALL_SENSORS)
                );
                let sensor = if in_sensor_scope {
                    target.sensor_index(arguments.name.trim())
                } else {
                    None
                };
                let body = match sensor {
                    Some(index) => {
                        let name = target.sensor_name(index).unwrap_or_default().to_string();
                        json!({
                            "dataId": format!("sensor:{name}"),
                            "description": format!("{name} changes (checked at each cycle boundary)"),
                            "accessTypes": ["write"],
                            "canPersist": true,
                        })
                    }
                    None => json!({
                        "dataId": null,
                        "description": format!("`{}` is not a sensor: only sensors can be watched", arguments.name),
                    }),
                };
                self.writer.respond(request, body).map_err(io_error)?;
            }
            "setDataBreakpoints" => {
                let arguments: SetDataBreakpointsArguments = arguments(request)?;
                self.requested.data = arguments.breakpoints;
                let breakpoints = self.apply_data_breakpoints();
                self.writer
                    .respond(request, json!({ "breakpoints": breakpoints }))
                    .map_err(io_error)?;
            }
            "breakpointLocations" => {
                let arguments: BreakpointLocationsArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let info = &launched.debugger.info;
                let end = arguments.end_line.unwrap_or(arguments.line);
                let same = arguments
                    .source
                    .path
                    .as_deref()
                    .is_some_and(|path| info.is_same_source(path));
                let lines: Vec<Value> = if same {
                    info.lines_with_code()
                        .filter(|line| {
                            i64::from(*line) >= arguments.line && i64::from(*line) <= end
                        })
                        .map(|line| json!({ "line": line }))
                        .collect()
                } else {
                    Vec::new()
                };
                self.writer
                    .respond(request, json!({ "breakpoints": lines }))
                    .map_err(io_error)?;
            }
            "configurationDone" => {
                let launched = self.launched_mut()?;
                if launched.stop_on_entry {
                    self.writer.respond(request, ()).map_err(io_error)?;
                    self.send_stop(Stop {
                        reason: "entry",
                        description: "Paused on entry".into(),
                        text: None,
                        hit_breakpoint_ids: Vec::new(),
                    })
                    .map_err(io_error)?;
                } else {
                    let first = launched.debugger.check_start();
                    if first.is_none() {
                        let start = launched.debugger.clock();
                        launched.running = Some(Running {
                            mode: RunMode::Continue,
                            start,
                            request_seq: request.seq,
                            progress: None,
                        });
                    }
                    self.writer.respond(request, ()).map_err(io_error)?;
                    self.flush_outputs().map_err(io_error)?;
                    if let Some(stop) = first {
                        self.send_stop(stop).map_err(io_error)?;
                    }
                }
            }
            "threads" => {
                self.writer
                    .respond(
                        request,
                        json!({ "threads": [{ "id": THREAD_ID, "name": "script" }] }),
                    )
                    .map_err(io_error)?;
            }
            "continue" | "next" | "stepIn" | "stepOut" => {
                let arguments: StepArguments = arguments(request)?;
                let instruction = arguments.granularity.as_deref() == Some("instruction");
                let mode = match request.command.as_str() {
                    "continue" => RunMode::Continue,
                    "next" => RunMode::Next,
                    "stepIn" => RunMode::StepIn { instruction },
                    _ => RunMode::StepOut,
                };
                let launched = self.launched_mut()?;
                if launched.running.is_some() {
                    return Err("the program is already running; `pause` first".into());
                }
                let language = launched.debugger.info.language;
                let mode = match mode {
                    // In GLOC a statement is an instruction.
                    RunMode::StepIn { .. } if language == Language::Gloc => {
                        RunMode::StepIn { instruction: true }
                    }
                    other => other,
                };
                let start = launched.debugger.clock();
                launched.running = Some(Running {
                    mode,
                    start,
                    request_seq: request.seq,
                    progress: None,
                });
                let body = if mode == RunMode::Continue {
                    json!({ "allThreadsContinued": true })
                } else {
                    Value::Null
                };
                self.writer.respond(request, body).map_err(io_error)?;
            }
            "pause" => {
                let launched = self.launched_mut()?;
                if launched.running.is_some() {
                    launched.debugger.request_pause();
                    self.writer.respond(request, ()).map_err(io_error)?;
                } else {
                    self.writer.respond(request, ()).map_err(io_error)?;
                    self.send_stop(Stop {
                        reason: "pause",
                        description: "Paused".into(),
                        text: None,
                        hit_breakpoint_ids: Vec::new(),
                    })
                    .map_err(io_error)?;
                }
            }
            "stepBack" | "reverseContinue" => {
                let launched = self.launched_mut()?;
                if launched.running.is_some() {
                    return Err("the program is running; `pause` first".into());
                }
                let stop = if request.command == "stepBack" {
                    launched.debugger.step_back()?
                } else {
                    let progress = format!("reverse-{}", request.seq);
                    if self.client.supports_progress_reporting {
                        self.start_progress(&progress, "Running backwards", request.seq)
                            .map_err(io_error)?;
                    }
                    let cancellations = self.cancellations.clone();
                    let launched = self.launched_mut()?;
                    let stop = launched.debugger.reverse_continue_unless(&|| {
                        cancellations.cancelled(request.seq, Some(&progress))
                    });
                    if self.client.supports_progress_reporting {
                        self.writer
                            .event(
                                "progressEnd",
                                ProgressEventBody {
                                    progress_id: progress,
                                    message: None,
                                },
                            )
                            .map_err(io_error)?;
                    }
                    stop?
                };
                self.writer.respond(request, ()).map_err(io_error)?;
                self.send_stop(stop).map_err(io_error)?;
            }
            "stackTrace" => {
                let arguments: StackTraceArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let format = features::value_format(arguments.format);
                // One frame (the script has no calls): `startFrame` past it gives none;
                // `levels` 0 or absent means all.
                let frames = match (arguments.start_frame.unwrap_or(0), arguments.levels) {
                    (start, _) if start < 0 => {
                        return Err(format!("`startFrame` {start} is negative"))
                    }
                    (0, None) => vec![stack_frame(&launched.debugger, format)],
                    (0, Some(levels)) if levels >= 0 => {
                        vec![stack_frame(&launched.debugger, format)]
                    }
                    (_, Some(levels)) if levels < 0 => {
                        return Err(format!("`levels` {levels} is negative"))
                    }
                    _ => Vec::new(),
                };
                self.writer
                    .respond(request, json!({ "stackFrames": frames, "totalFrames": 1 }))
                    .map_err(io_error)?;
            }
            "scopes" => {
                let _: ScopesArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let target = &launched.debugger.target;
                let scopes = vec![
                    scope(
                        "Variables",
                        Some("locals"),
                        SCOPE_VARIABLES,
                        target.variables().len(),
                    ),
                    scope(
                        "Registers",
                        Some("registers"),
                        SCOPE_REGISTERS,
                        target.registers().len(),
                    ),
                    scope(
                        "Sensors",
                        None,
                        SCOPE_SENSORS,
                        target.touched_sensors().len() + 1,
                    ),
                    scope("Vehicle", None, SCOPE_VEHICLE, target.vehicle().len()),
                ];
                self.writer
                    .respond(request, json!({ "scopes": scopes }))
                    .map_err(io_error)?;
            }
            "variables" => {
                let arguments: VariablesArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let variables = variables(&launched.debugger, &arguments)?;
                self.writer
                    .respond(request, json!({ "variables": variables }))
                    .map_err(io_error)?;
            }
            "setVariable" => {
                let arguments: SetVariableArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let value = set_variable(&mut launched.debugger, &arguments)?;
                self.writer
                    .respond(request, json!({ "value": value }))
                    .map_err(io_error)?;
            }
            "evaluate" => {
                let arguments: EvaluateArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let body = features::evaluate(&launched.debugger, &arguments)?;
                self.writer.respond(request, body).map_err(io_error)?;
            }
            "setExpression" => {
                let arguments: SetExpressionArguments = arguments(request)?;
                let debugger = self.paused()?;
                let body = features::set_expression(debugger, &arguments)?;
                // The response names the new value `value` (evaluate's `result`).
                let mut body = serde_json::to_value(body).map_err(|error| error.to_string())?;
                if let Some(object) = body.as_object_mut() {
                    if let Some(result) = object.remove("result") {
                        object.insert("value".into(), result);
                    }
                }
                self.writer.respond(request, body).map_err(io_error)?;
            }
            "completions" => {
                let arguments: CompletionsArguments = arguments(request)?;
                let client = self.client;
                let launched = self.launched_mut()?;
                let targets = features::completions(&launched.debugger, &arguments, client);
                self.writer
                    .respond(request, json!({ "targets": targets }))
                    .map_err(io_error)?;
            }
            "gotoTargets" => {
                let arguments: GotoTargetsArguments = arguments(request)?;
                let client = self.client;
                let launched = self.launched_mut()?;
                let targets = features::goto_targets(&launched.debugger, &arguments, client)?;
                self.writer
                    .respond(request, json!({ "targets": targets }))
                    .map_err(io_error)?;
            }
            "goto" => {
                let arguments: GotoArguments = arguments(request)?;
                let debugger = self.paused()?;
                let description = features::goto(debugger, &arguments)?;
                self.writer.respond(request, ()).map_err(io_error)?;
                self.send_stop(Stop {
                    reason: "goto",
                    description,
                    text: None,
                    hit_breakpoint_ids: Vec::new(),
                })
                .map_err(io_error)?;
            }
            "cancel" => {
                // The reader thread noted it; a run asks the list between slices (and a
                // reverse run between steps). Cancelling what is over does nothing.
                let _: CancelArguments = arguments(request)?;
                self.writer.respond(request, ()).map_err(io_error)?;
            }
            "exceptionInfo" => {
                let launched = self.launched_mut()?;
                let Some(trap) = launched.debugger.trap.clone() else {
                    return Err("the program is not stopped on an exception".into());
                };
                self.writer
                    .respond(request, json!({ "exceptionId": "trap", "description": trap, "breakMode": "always" }))
                    .map_err(io_error)?;
            }
            "disassemble" => {
                let arguments: DisassembleArguments = arguments(request)?;
                let launched = self.launched_mut()?;
                let instructions = disassemble(&launched.debugger, &arguments)?;
                self.writer
                    .respond(request, json!({ "instructions": instructions }))
                    .map_err(io_error)?;
            }
            "loadedSources" => {
                let launched = self.launched_mut()?;
                let source = source_of(&launched.debugger);
                self.writer
                    .respond(request, json!({ "sources": [source] }))
                    .map_err(io_error)?;
            }
            "restart" => {
                let launched = self.launched_mut()?;
                let mut arguments = launched.arguments.clone();
                if let Some(new) = request.arguments.get("arguments") {
                    arguments = serde_json::from_value(new.clone())
                        .map_err(|error| format!("invalid arguments for `restart`: {error}"))?;
                }
                self.launched = None;
                self.launch(arguments)?;
                self.writer.respond(request, ()).map_err(io_error)?;
                let launched = self.launched_mut()?;
                if launched.stop_on_entry {
                    self.send_stop(Stop {
                        reason: "entry",
                        description: "Restarted: paused on entry".into(),
                        text: None,
                        hit_breakpoint_ids: Vec::new(),
                    })
                    .map_err(io_error)?;
                } else {
                    let start = launched.debugger.clock();
                    launched.running = Some(Running {
                        mode: RunMode::Continue,
                        start,
                        request_seq: request.seq,
                        progress: None,
                    });
                }
            }
            other => return Err(format!("unknown command `{other}`")),
        }
        Ok(Flow::Continue)
    }

    /// The debugger of a launched program that is not running.
    fn paused(&mut self) -> Result<&mut Debugger<World>, String> {
        let launched = self.launched_mut()?;
        if launched.running.is_some() {
            return Err("the program is running; `pause` first".into());
        }
        Ok(&mut launched.debugger)
    }

    fn start_progress(&mut self, id: &str, title: &str, request_seq: i64) -> io::Result<()> {
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

    fn launched_mut(&mut self) -> Result<&mut Launched, String> {
        self.launched
            .as_mut()
            .ok_or_else(|| "no program is loaded: send `launch` first".to_string())
    }

    fn launch(&mut self, arguments: LaunchArguments) -> Result<(), String> {
        let program = arguments
            .program
            .clone()
            .filter(|program| !program.trim().is_empty())
            .ok_or(
                "the launch configuration needs `program`: the .gbas or .gloc script to debug",
            )?;
        let history = match &arguments.history {
            None | Some(Value::Null) | Some(Value::Bool(true)) => Some(HistoryConfig::default()),
            Some(Value::Bool(false)) => None,
            Some(Value::Number(number)) => match number.as_u64() {
                Some(0) => None,
                Some(count) => Some(HistoryConfig {
                    max_snapshots: usize::try_from(count).unwrap_or(usize::MAX).max(2),
                    ..HistoryConfig::default()
                }),
                None => {
                    return Err(
                        "`history` must be true, false or a positive number of snapshots".into(),
                    )
                }
            },
            Some(_) => {
                return Err(
                    "`history` must be true, false or a positive number of snapshots".into(),
                )
            }
        };
        // An empty path means "the default", as the editors send it. What the
        // launch leaves open comes from the nearest `gloc.toml` above the program.
        let given_path = |value: &Option<String>| {
            value
                .as_deref()
                .filter(|text| !text.trim().is_empty())
                .map(PathBuf::from)
        };
        let program = PathBuf::from(program);
        let file_config =
            gloc_engine::config::Config::discover(&program).map_err(|error| error.to_string())?;
        let config = LaunchConfig {
            mission: given_path(&arguments.mission).or(file_config.mission),
            masterdata: given_path(&arguments.masterdata).or(file_config.masterdata),
            profile: given_path(&arguments.profile),
            seed: arguments.seed,
            cycle_budget: match arguments.cycle_budget {
                Some(budget) => Some(
                    gloc_engine::config::check_cycle_budget(budget)
                        .map_err(|message| format!("cycleBudget: {message}"))?,
                ),
                None => file_config.cycle_budget,
            },
            max_cycles: arguments.max_cycles,
            sensor_order: file_config.sensor_order.unwrap_or_default(),
            simulator: file_config.simulator,
            replay: replay_paths(arguments.replay.as_ref())?,
            sensor_cache: given_path(&arguments.sensor_cache).or(file_config.sensor_cache),
            program,
        };
        check_input(&config.program, "program", &["gbas", "gloc"])?;
        if let Some(mission) = &config.mission {
            check_input(mission, "mission", &["mi"])?;
        }
        if let Some(profile) = &config.profile {
            check_input(profile, "profile", &["csv"])?;
        }
        if let Some(masterdata) = &config.masterdata {
            // Real sensor lists are called `masterdata` or `*.cac`: no extension rule.
            check_input(masterdata, "masterdata", &[])?;
        }
        let (world, info) = world::launch(&config).map_err(|message| match self.access {
            Access::Open => message,
            // Over TCP no error may quote what a file holds: diagnostics quote
            // tokens of the line at fault, so quoted text is blanked out.
            Access::Token(_) => redact_quotes(&message),
        })?;
        let debugger = Debugger::new(world, info, history);
        self.launched = Some(Launched {
            debugger,
            stop_on_entry: arguments.stop_on_entry.unwrap_or(false),
            arguments,
            running: None,
        });
        // Re-apply what the client set before (restart keeps breakpoints).
        let sources = std::mem::take(&mut self.requested.sources);
        for (path, breakpoints) in &sources {
            let _ = self.apply_source_breakpoints(path, breakpoints);
        }
        self.requested.sources = sources;
        self.apply_function_breakpoints();
        self.apply_data_breakpoints();
        self.apply_instruction_breakpoints();
        self.apply_filters();
        Ok(())
    }

    fn new_id(&mut self) -> i64 {
        let id = self.next_breakpoint_id;
        self.next_breakpoint_id += 1;
        id
    }

    fn set_breakpoints(
        &mut self,
        arguments: SetBreakpointsArguments,
    ) -> Result<Vec<Breakpoint>, String> {
        let path = arguments
            .source
            .path
            .clone()
            .ok_or("`setBreakpoints` needs `source.path`")?;
        let mut breakpoints = arguments.breakpoints.unwrap_or_default();
        if breakpoints.is_empty() {
            if let Some(lines) = arguments.lines {
                breakpoints = lines
                    .into_iter()
                    .map(|line| SourceBreakpoint {
                        line,
                        ..SourceBreakpoint::default()
                    })
                    .collect();
            }
        }
        self.requested.sources.retain(|(known, _)| *known != path);
        self.requested
            .sources
            .push((path.clone(), breakpoints.clone()));
        Ok(self.apply_source_breakpoints(&path, &breakpoints))
    }

    fn apply_source_breakpoints(
        &mut self,
        path: &str,
        requested: &[SourceBreakpoint],
    ) -> Vec<Breakpoint> {
        let mut ids = Vec::new();
        for _ in requested {
            ids.push(self.new_id());
        }
        let Some(launched) = &mut self.launched else {
            return requested
                .iter()
                .zip(ids)
                .map(|(breakpoint, id)| Breakpoint {
                    id: Some(id),
                    verified: false,
                    line: echo_line(breakpoint.line),
                    message: Some("the program is not launched yet".into()),
                    reason: Some("pending".into()),
                    ..Breakpoint::default()
                })
                .collect();
        };
        let debugger = &mut launched.debugger;
        let same_source = debugger.info.is_same_source(path);
        let source = source_of(debugger);
        // Replace this source's breakpoints (there is one source per session).
        if same_source {
            debugger.line_breakpoints.clear();
        }
        let mut out = Vec::new();
        for (breakpoint, id) in requested.iter().zip(ids) {
            if !same_source {
                out.push(unverified(
                    id,
                    breakpoint.line,
                    format!("{path} is not the program being debugged"),
                ));
                continue;
            }
            let refusal = match (breakpoint.line, debugger.info.source_lines) {
                (line, _) if line < 1 => {
                    Some(format!("line {line} is not a line: lines start at 1"))
                }
                (line, Some(last)) if line > i64::from(last) => Some(format!(
                    "line {line} is past the end of {} ({last} lines)",
                    debugger.info.source_name()
                )),
                _ => breakpoint
                    .condition
                    .as_deref()
                    .filter(|text| !text.trim().is_empty())
                    .and_then(|condition| condition_error(debugger, condition)),
            };
            if let Some(message) = refusal {
                out.push(unverified(id, breakpoint.line, message));
                continue;
            }
            let line = u32::try_from(breakpoint.line)
                .ok()
                .and_then(|line| debugger.info.resolve_line(line));
            let hit_condition = match breakpoint
                .hit_condition
                .as_deref()
                .filter(|text| !text.trim().is_empty())
            {
                Some(text) => match HitCondition::parse(text) {
                    Ok(condition) => Some(condition),
                    Err(message) => {
                        out.push(unverified(id, breakpoint.line, message));
                        continue;
                    }
                },
                None => None,
            };
            match line {
                Some(line) => {
                    debugger.line_breakpoints.push(LineBreakpoint {
                        id,
                        line,
                        condition: breakpoint.condition.clone(),
                        hit_condition,
                        log_message: breakpoint.log_message.clone(),
                        hits: 0,
                    });
                    out.push(Breakpoint {
                        id: Some(id),
                        verified: true,
                        line: Some(i64::from(line)),
                        source: Some(source.clone()),
                        ..Breakpoint::default()
                    });
                }
                None => out.push(unverified(id, breakpoint.line, "no code in this file")),
            }
        }
        out
    }

    fn apply_function_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.functions.clone();
        let mut out = Vec::new();
        let mut accepted = Vec::new();
        for breakpoint in &requested {
            let id = self.new_id();
            let words: Vec<&str> = breakpoint.name.split_whitespace().collect();
            let kind = match words.as_slice() {
                [word, number] if word.eq_ignore_ascii_case("cycle") => {
                    number.parse().ok().map(CycleBreakpointKind::At)
                }
                [word, number] if word.eq_ignore_ascii_case("every") => number
                    .parse()
                    .ok()
                    .filter(|every| *every > 0)
                    .map(CycleBreakpointKind::Every),
                _ => None,
            };
            let hit_condition = breakpoint
                .hit_condition
                .as_deref()
                .filter(|text| !text.trim().is_empty())
                .map(HitCondition::parse)
                .transpose();
            match (kind, hit_condition) {
                (Some(kind), Ok(hit_condition)) => {
                    accepted.push(CycleBreakpoint {
                        id,
                        kind,
                        condition: breakpoint.condition.clone(),
                        hit_condition,
                        hits: 0,
                    });
                    out.push(Breakpoint { id: Some(id), verified: true, ..Breakpoint::default() });
                }
                (_, Err(message)) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(message),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
                (None, _) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(format!(
                        "`{}` is not a cycle breakpoint: write `cycle N` (stop at cycle N) or `every N` (every N cycles)",
                        breakpoint.name
                    )),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
            }
        }
        if let Some(launched) = &mut self.launched {
            launched.debugger.cycle_breakpoints = accepted;
        }
        out
    }

    fn apply_data_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.data.clone();
        let mut out = Vec::new();
        let mut accepted = Vec::new();
        for breakpoint in &requested {
            let id = self.new_id();
            let name = breakpoint
                .data_id
                .strip_prefix("sensor:")
                .unwrap_or(&breakpoint.data_id);
            let sensor = self
                .launched
                .as_ref()
                .and_then(|launched| launched.debugger.target.sensor_index(name));
            let hit_condition = breakpoint
                .hit_condition
                .as_deref()
                .filter(|text| !text.trim().is_empty())
                .map(HitCondition::parse)
                .transpose();
            match (sensor, hit_condition) {
                (Some(sensor), Ok(hit_condition)) => {
                    accepted.push(DataBreakpoint {
                        id,
                        sensor,
                        condition: breakpoint.condition.clone(),
                        hit_condition,
                        hits: 0,
                    });
                    out.push(Breakpoint {
                        id: Some(id),
                        verified: true,
                        ..Breakpoint::default()
                    });
                }
                (_, Err(message)) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(message),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
                (None, _) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(format!("`{name}` is not a sensor")),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
            }
        }
        if let Some(launched) = &mut self.launched {
            launched.debugger.data_breakpoints = accepted;
            launched.debugger.reset_baseline();
        }
        out
    }

    fn apply_instruction_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.instructions.clone();
        let mut out = Vec::new();
        let mut accepted = Vec::new();
        let count = self
            .launched
            .as_ref()
            .map_or(0, |launched| launched.debugger.info.instruction_count());
        for breakpoint in &requested {
            let id = self.new_id();
            let pc = parse_address(&breakpoint.instruction_reference)
                .and_then(|base| base.checked_add(breakpoint.offset.unwrap_or(0)))
                .and_then(|pc| usize::try_from(pc).ok())
                .filter(|pc| *pc < count);
            let hit_condition = breakpoint
                .hit_condition
                .as_deref()
                .filter(|text| !text.trim().is_empty())
                .map(HitCondition::parse)
                .transpose();
            match (pc, hit_condition) {
                (Some(pc), Ok(hit_condition)) => {
                    accepted.push(InstructionBreakpoint {
                        id,
                        pc,
                        condition: breakpoint.condition.clone(),
                        hit_condition,
                        hits: 0,
                    });
                    out.push(Breakpoint {
                        id: Some(id),
                        verified: true,
                        instruction_reference: Some(address(pc)),
                        ..Breakpoint::default()
                    });
                }
                (_, Err(message)) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(message),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
                (None, _) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(format!(
                        "`{}` is not an instruction of the program",
                        breakpoint.instruction_reference
                    )),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
            }
        }
        if let Some(launched) = &mut self.launched {
            launched.debugger.instruction_breakpoints = accepted;
        }
        out
    }

    fn apply_filters(&mut self) {
        let Some(filters) = &self.requested.filters else {
            return;
        };
        let arguments = SetExceptionBreakpointsArguments {
            filters: filters.clone(),
            filter_options: Some(self.requested.filter_options.clone()),
        };
        let Some(launched) = &mut self.launched else {
            return;
        };
        let debugger = &launched.debugger;
        if let Ok((chosen, _)) = features::exception_filters(&arguments, |condition| {
            condition_error(debugger, condition)
        }) {
            launched.debugger.filters = chosen;
        }
    }

    /// Runs one slice of a forward run and reports a stop or the end.
    pub fn run_slice(&mut self) -> io::Result<Flow> {
        let Some(launched) = &mut self.launched else {
            return Ok(Flow::Continue);
        };
        let Some(running) = &launched.running else {
            return Ok(Flow::Continue);
        };
        let shown = running.progress.clone();
        let progress = if self
            .cancellations
            .cancelled(running.request_seq, shown.as_deref())
        {
            // A cancelled run stops where the last slice left it (a step boundary).
            Progress::Stopped(Stop {
                reason: "pause",
                description: format!("Run cancelled at cycle {}", launched.debugger.clock().cycle),
                text: None,
                hit_breakpoint_ids: Vec::new(),
            })
        } else {
            launched
                .debugger
                .run(running.mode, running.start, SLICE_STEPS)
        };
        let request_seq = running.request_seq;
        if !matches!(progress, Progress::Running) {
            launched.running = None;
        } else if shown.is_none() && self.client.supports_progress_reporting {
            // Longer than one slice: show a progress the user can cancel.
            let id = format!("run-{request_seq}");
            if let Some(running) = &mut launched.running {
                running.progress = Some(id.clone());
            }
            self.start_progress(&id, "Running", request_seq)?;
        }
        self.flush_outputs()?;
        if let (Some(id), false) = (shown, matches!(progress, Progress::Running)) {
            self.writer.event(
                "progressEnd",
                ProgressEventBody {
                    progress_id: id,
                    message: None,
                },
            )?;
        }
        match progress {
            Progress::Running => {}
            Progress::Stopped(stop) => self.send_stop(stop)?,
            Progress::Ended { summary } => {
                self.writer.event(
                    "output",
                    OutputEventBody {
                        category: "console".into(),
                        output: format!("{summary}\n"),
                        source: None,
                        line: None,
                        data: None,
                    },
                )?;
                self.writer.event("exited", json!({ "exitCode": 0 }))?;
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
                (Access::Token(_), "important") => redact_quotes(&output.text),
                _ => output.text,
            };
            self.writer.event(
                "output",
                OutputEventBody {
                    category: output.category.into(),
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
                reason: stop.reason.into(),
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

/// A launch input must be a regular file (no FIFO, device or folder) with one of the
/// extensions its kind uses, so that no attribute makes the adapter read an arbitrary
/// file as a script or a mission. The message names the path only.
fn check_input(path: &std::path::Path, kind: &str, extensions: &[&str]) -> Result<(), String> {
    let shown = path.display();
    let metadata = std::fs::metadata(path)
        .map_err(|error| format!("cannot read the {kind} {shown}: {}", io_reason(&error)))?;
    if !metadata.is_file() {
        return Err(format!(
            "the {kind} {shown} is not a regular file (a folder, FIFO or device)"
        ));
    }
    let extension = path
        .extension()
        .and_then(|extension| extension.to_str())
        .unwrap_or("");
    if !extensions.is_empty()
        && !extensions
            .iter()
            .any(|known| extension.eq_ignore_ascii_case(known))
    {
        let known: Vec<String> = extensions.iter().map(|known| format!(".{known}")).collect();
        return Err(format!(
            "the {kind} {shown} is not a {} file; `{kind}` takes {}",
            known.join(" or "),
            known.join(" or ")
        ));
    }
    Ok(())
}

/// An IO error without the OS's error number.
fn io_reason(error: &io::Error) -> String {
    match error.kind() {
        io::ErrorKind::NotFound => "no such file".into(),
        io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => error.to_string(),
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

/// Why a breakpoint condition can never be evaluated (a syntax error, an unknown
/// name), checked on the current values; a division by zero on them is not a
/// reason, since other values may not divide by zero.
fn condition_error(debugger: &Debugger<World>, condition: &str) -> Option<String> {
    match debugger.evaluate(condition) {
        Ok(_) => None,
        Err(message) if message == crate::expr::DIVISION_BY_ZERO => None,
        Err(message) => Some(format!(
            "the condition `{condition}` is not valid: {message}"
        )),
    }
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

/// A line breakpoint that was not set, with the reason.
fn unverified(id: i64, line: i64, message: impl Into<String>) -> Breakpoint {
    Breakpoint {
        id: Some(id),
        verified: false,
        line: echo_line(line),
        message: Some(message.into()),
        reason: Some("failed".into()),
        ..Breakpoint::default()
    }
}

/// A client's line number, echoed back only when it is a line number at all.
fn echo_line(line: i64) -> Option<i64> {
    (1..=i64::from(u32::MAX)).contains(&line).then_some(line)
}

pub(crate) fn address(pc: usize) -> String {
    format!("0x{pc:x}")
}

fn parse_address(text: &str) -> Option<i64> {
    let text = text.trim();
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => i64::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

fn source_of(debugger: &Debugger<World>) -> Source {
    Source {
        name: Some(debugger.info.source_name()),
        path: Some(debugger.info.path.display().to_string()),
    }
}

fn stack_frame(debugger: &Debugger<World>, format: ValueFormat) -> StackFrame {
    let target = &debugger.target;
    let pc = debugger.shown_pc();
    let instruction = debugger
        .info
        .instruction_text
        .get(pc)
        .cloned()
        .unwrap_or_default();
    let line = debugger.current_line().unwrap_or(1);
    let phase = match target.phase() {
        Phase::Boundary => "boundary",
        Phase::InScript => "script",
        Phase::ScriptDone => "after yield",
        Phase::Ended => "ended",
    };
    StackFrame {
        id: FRAME_ID,
        name: format!(
            "cycle {} ({phase}) · {}: {instruction}",
            debugger.clock().cycle,
            format.count(pc)
        ),
        source: Some(source_of(debugger)),
        line: i64::from(line),
        column: 1,
        instruction_pointer_reference: Some(address(pc)),
    }
}

fn scope(name: &str, hint: Option<&str>, reference: i64, count: usize) -> Scope {
    Scope {
        name: name.into(),
        presentation_hint: hint.map(str::to_string),
        variables_reference: reference,
        named_variables: Some(count as i64),
        expensive: false,
    }
}

fn plain(named: Named) -> Variable {
    Variable {
        evaluate_name: Some(named.name.clone()),
        name: named.name,
        value: named.value,
        ty: Some(named.ty.into()),
        variables_reference: 0,
        named_variables: None,
        indexed_variables: None,
    }
}

fn sensor_variable(target: &World, index: usize, format: ValueFormat) -> Variable {
    let name = target.sensor_name(index).unwrap_or("?").to_string();
    Variable {
        evaluate_name: Some(name.clone()),
        name,
        value: format.sensor(target.sensor(index)),
        ty: Some(format!("sensor {index}")),
        variables_reference: 0,
        named_variables: None,
        indexed_variables: None,
    }
}

fn variables(
    debugger: &Debugger<World>,
    arguments: &VariablesArguments,
) -> Result<Vec<Variable>, String> {
    let target = &debugger.target;
    let format = features::value_format(arguments.format);
    let all: Vec<Variable> = match arguments.variables_reference {
        SCOPE_VARIABLES => target
            .variables()
            .into_iter()
            .enumerate()
            .map(|(position, named)| {
                let length = named.length;
                let value = match length {
                    Some(length) => features::array_summary(debugger, &named.name, length, format),
                    None => target
                        .variable(&named.name)
                        .map_or_else(|| named.value.clone(), |value| format.number(value)),
                };
                let mut variable = plain(named);
                variable.value = value;
                if let Some(length) = length {
                    variable.variables_reference = ARRAYS + position as i64;
                    variable.indexed_variables = Some(length as i64);
                }
                variable
            })
            .collect(),
        reference if reference >= ARRAYS => {
            let position = usize::try_from(reference - ARRAYS).unwrap_or(usize::MAX);
            let array = target
                .variables()
                .into_iter()
                .nth(position)
                .filter(|named| named.length.is_some())
                .ok_or_else(|| format!("unknown variablesReference {reference}"))?;
            let length = array.length.unwrap_or(0);
            let start = usize::try_from(arguments.start.unwrap_or(0))
                .unwrap_or(0)
                .min(length);
            let count = match arguments.count {
                Some(count) if count > 0 => usize::try_from(count).unwrap_or(usize::MAX),
                _ => length,
            };
            let element_type = if array.ty.starts_with("float") {
                "float"
            } else {
                "integer"
            };
            return Ok((start..start.saturating_add(count).min(length))
                .map(|index| {
                    let value = target.element(&array.name, index as i64);
                    // Named `[10]`, which clients such as nvim-dap sort numerically; the
                    // GBASIC expression `a(10)` is the evaluateName.
                    Variable {
                        evaluate_name: Some(format!("{}({index})", array.name)),
                        name: format!("[{index}]"),
                        value: value.map(|value| format.number(value)).unwrap_or_default(),
                        ty: Some(element_type.into()),
                        variables_reference: 0,
                        named_variables: None,
                        indexed_variables: None,
                    }
                })
                .collect());
        }
        SCOPE_REGISTERS => target
            .registers()
            .into_iter()
            .enumerate()
            .map(|(index, value)| Variable {
                name: format!("r{index}"),
                value: format.number(value),
                ty: Some(value.type_name().into()),
                variables_reference: 0,
                named_variables: None,
                indexed_variables: None,
                evaluate_name: Some(format!("r{index}")),
            })
            .collect(),
        SCOPE_SENSORS => {
            let mut list: Vec<Variable> = target
                .touched_sensors()
                .into_iter()
                .map(|index| sensor_variable(target, index, format))
                .collect();
            list.push(Variable {
                name: "All sensors".into(),
                value: format!("{} sensors", target.sensor_count()),
                ty: None,
                variables_reference: ALL_SENSORS,
                // Indexed, so clients fetch it lazily in pages (VS Code: 100 at a time).
                named_variables: None,
                indexed_variables: Some(target.sensor_count() as i64),
                evaluate_name: None,
            });
            list
        }
        SCOPE_VEHICLE => target.vehicle().into_iter().map(plain).collect(),
        ALL_SENSORS if arguments.filter.as_deref() == Some("named") => return Ok(Vec::new()),
        ALL_SENSORS => {
            let start = usize::try_from(arguments.start.unwrap_or(0)).unwrap_or(0);
            let count = match arguments.count {
                Some(count) if count > 0 => usize::try_from(count).unwrap_or(usize::MAX),
                _ => target.sensor_count(),
            };
            let end = start.saturating_add(count).min(target.sensor_count());
            return Ok((start.min(end)..end)
                .map(|index| sensor_variable(target, index, format))
                .collect());
        }
        other => return Err(format!("unknown variablesReference {other}")),
    };
    let start = usize::try_from(arguments.start.unwrap_or(0))
        .unwrap_or(0)
        .min(all.len());
    let count = match arguments.count {
        Some(count) if count > 0 => usize::try_from(count).unwrap_or(usize::MAX),
        _ => all.len(),
    };
    Ok(all.into_iter().skip(start).take(count).collect())
}

fn set_variable(
    debugger: &mut Debugger<World>,
    arguments: &SetVariableArguments,
) -> Result<String, String> {
    let value = edits::value_of(debugger, &arguments.value)?;
    let format = features::value_format(arguments.format);
    match arguments.variables_reference {
        SCOPE_VARIABLES => {
            debugger.edit(Edit::Variable(arguments.name.clone(), value))?;
            debugger
                .target
                .variable(&arguments.name)
                .map(|value| format.number(value))
                .ok_or_else(|| format!("no variable `{}`", arguments.name))
        }
        SCOPE_REGISTERS => {
            let index = arguments
                .name
                .strip_prefix('r')
                .and_then(|digits| digits.parse::<usize>().ok())
                .ok_or_else(|| format!("`{}` is not a register", arguments.name))?;
            debugger.edit(Edit::Register(index, value))?;
            debugger
                .target
                .registers()
                .get(index)
                .map(|value| format.number(*value))
                .ok_or_else(|| format!("no register `{}`", arguments.name))
        }
        SCOPE_SENSORS | ALL_SENSORS => {
            let index = debugger
                .target
                .sensor_index(&arguments.name)
                .ok_or_else(|| format!("`{}` is not a sensor", arguments.name))?;
            debugger.edit(Edit::Sensor(index, value.as_f64()))?;
            Ok(format.sensor(debugger.target.sensor(index)))
        }
        SCOPE_VEHICLE => Err("the Vehicle scope is read-only; set a sensor instead".into()),
        reference if reference >= ARRAYS => {
            // The element's name in the array's children (`[3]`), or its expression (`a(3)`).
            let position = usize::try_from(reference - ARRAYS).unwrap_or(usize::MAX);
            let array = debugger
                .target
                .variables()
                .into_iter()
                .nth(position)
                .filter(|named| named.length.is_some())
                .map(|named| named.name)
                .ok_or_else(|| format!("unknown variablesReference {reference}"))?;
            let element = arguments
                .name
                .strip_prefix('[')
                .and_then(|rest| rest.strip_suffix(']'))
                .map(|index| (array.clone(), index))
                .or_else(|| {
                    let (name, index) = arguments.name.strip_suffix(')')?.split_once('(')?;
                    Some((name.to_string(), index))
                });
            let (name, index) = element
                .and_then(|(name, index)| Some((name, index.trim().parse::<i64>().ok()?)))
                .ok_or_else(|| {
                    format!(
                        "`{}` is not an array element like `[3]` or `{array}(3)`",
                        arguments.name
                    )
                })?;
            debugger.edit(Edit::Element(name.clone(), index, value))?;
            debugger
                .target
                .element(&name, index)
                .map(|value| format.number(value))
                .ok_or_else(|| format!("no element `{}`", arguments.name))
        }
        other => Err(format!("unknown variablesReference {other}")),
    }
}

fn disassemble(
    debugger: &Debugger<World>,
    arguments: &DisassembleArguments,
) -> Result<Vec<DisassembledInstruction>, String> {
    let base = parse_address(&arguments.memory_reference).ok_or_else(|| {
        format!(
            "`{}` is not an instruction address",
            arguments.memory_reference
        )
    })?;
    let first = base
        .saturating_add(arguments.offset.unwrap_or(0))
        .saturating_add(arguments.instruction_offset.unwrap_or(0));
    let count = arguments.instruction_count;
    if !(0..=MAX_DISASSEMBLE).contains(&count) {
        return Err(format!(
            "`instructionCount` {count} is outside 0 to {MAX_DISASSEMBLE}"
        ));
    }
    let source = source_of(debugger);
    let mut out = Vec::with_capacity(count as usize);
    let mut last_line = None;
    // Exactly `count` entries, as the spec requires: addresses that hold no code
    // (before 0, past the end, past i64) are "invalid" entries.
    for step in 0..count {
        let Some(pc) = first.checked_add(step) else {
            out.push(DisassembledInstruction {
                address: format!("0x{:x}", (first as i128) + i128::from(step)),
                instruction: String::new(),
                symbol: None,
                location: None,
                line: None,
                presentation_hint: Some("invalid".into()),
            });
            continue;
        };
        let valid = usize::try_from(pc)
            .ok()
            .filter(|pc| *pc < debugger.info.instruction_count());
        match valid {
            Some(pc) => {
                let line = debugger.info.line(pc);
                let new_line = line != last_line;
                last_line = line;
                out.push(DisassembledInstruction {
                    address: address(pc),
                    instruction: debugger.info.instruction_text[pc].clone(),
                    symbol: None,
                    location: if new_line { Some(source.clone()) } else { None },
                    line: line.map(i64::from),
                    presentation_hint: None,
                });
            }
            None => out.push(DisassembledInstruction {
                address: if pc < 0 {
                    format!("-0x{:x}", pc.unsigned_abs())
                } else {
                    format!("0x{pc:x}")
                },
                instruction: String::new(),
                symbol: None,
                location: None,
                line: None,
                presentation_hint: Some("invalid".into()),
            }),
        }
    }
    Ok(out)
}
