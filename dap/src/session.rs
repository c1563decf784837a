//! One debug session: dispatches requests on their `command` string, keeps the launch
//! state, and runs the world in slices so `pause` and `disconnect` are heard mid-run.

use std::io;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::cancel::Cancellations;
use crate::debugger::{
    self, Category, Clock, CycleBreakpointKind, Debugger, HistoryConfig, HitCondition,
    LineBreakpoint, Pc, Progress, RunMode, Slice, Stop, StopReason,
};
use crate::dispatch::Failure;
use crate::features::{self, ClientOptions};
use crate::handlers;
use crate::protocol::{Malformed, Request, Writer};
use crate::target::Target;
use crate::types::*;
use crate::world::{self, LaunchConfig, World};

pub use crate::references::THREAD_ID;
pub(crate) use crate::references::{
    address, parse_address, ALL_SENSORS, ARRAYS, FRAME_ID, SCOPE_REGISTERS, SCOPE_SENSORS,
    SCOPE_VARIABLES, SCOPE_VEHICLE,
};
/// Steps run between two looks at the incoming queue while running, and the longest
/// time between two looks: a request (`pause`, `disconnect`) waits at most this long
/// plus one step.
const SLICE_STEPS: u64 = 50_000;
const SLICE_TIME: Duration = Duration::from_millis(50);
/// The most snapshots the `history` launch attribute may ask for. A snapshot is the
/// whole simulation (about 14 KB with Fig. 2's mission), so 4,096 are about 60 MB;
/// `"history": 1000000000` grew by 400 MB in 450,000 cycles and without end.
const MAX_HISTORY_SNAPSHOTS: u64 = 4096;

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

#[derive(Debug, Default, Deserialize)]
#[serde(default)]
pub struct RestartArguments {
    /// The new launch configuration; absent (or `null`) keeps the last one.
    pub arguments: Option<LaunchArguments>,
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

/// Breakpoints as the client last sent them, kept so `restart` can re-apply them.
#[derive(Default)]
pub(crate) struct Requested {
    pub sources: Vec<(String, Vec<SourceBreakpoint>)>,
    pub functions: Vec<FunctionBreakpoint>,
    pub data: Vec<crate::types::DataBreakpoint>,
    pub instructions: Vec<crate::types::InstructionBreakpoint>,
    pub filters: Option<Vec<String>>,
    pub filter_options: Vec<ExceptionFilterOptions>,
}

pub struct Session {
    writer: Writer,
    access: Access,
    /// Whether a `launch` carried the token (always, for `Access::Open`).
    authenticated: bool,
    /// Set with `authenticated`, for the reader's framing limits.
    authenticated_flag: Option<Arc<AtomicBool>>,
    pub(crate) initialized: bool,
    pub(crate) launched: Option<Launched>,
    pub(crate) requested: Requested,
    next_breakpoint_id: i64,
    /// What the running handler queued for after its response.
    then: Vec<Then>,
    /// The `seq` of the request being handled.
    pub(crate) request_seq: i64,
    /// `cancel`s, noted by the reader thread as they arrive.
    pub(crate) cancellations: Cancellations,
    /// How the client counts lines and columns, and whether it shows progress.
    pub(crate) client: ClientOptions,
}

pub(crate) fn capabilities() -> Capabilities {
    Capabilities {
        supports_configuration_done_request: Some(true),
        supports_function_breakpoints: Some(true),
        supports_conditional_breakpoints: Some(true),
        supports_hit_conditional_breakpoints: Some(true),
        supports_evaluate_for_hovers: Some(true),
        exception_breakpoint_filters: Some(features::exception_breakpoint_filters()),
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
        let answer = handlers::table().dispatch(self, &request.command, arguments);
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

    pub(crate) fn launched_mut(&mut self) -> Result<&mut Launched, String> {
        self.launched
            .as_mut()
            .ok_or_else(|| "no program is loaded: send `launch` first".to_string())
    }

    pub(crate) fn launch(&mut self, arguments: LaunchArguments) -> Result<(), String> {
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
                Some(count) if count <= MAX_HISTORY_SNAPSHOTS => Some(HistoryConfig {
                    max_snapshots: usize::try_from(count).unwrap_or(usize::MAX).max(2),
                    ..HistoryConfig::default()
                }),
                _ => {
                    return Err(format!(
                        "`history` must be true, false or a number of snapshots from 1 to {MAX_HISTORY_SNAPSHOTS}, not {number}"
                    ))
                }
            },
            Some(_) => {
                return Err(
                    "`history` must be true, false or a positive number of snapshots".into(),
                )
            }
        };
        // An empty path means "the default", as the editors send it. What the launch
        // leaves open comes from the nearest `gloc.toml` above the program; the
        // project layer decides (`world::resolve`), with errors in the CLI's words.
        let given_path = |value: &Option<String>| {
            value
                .as_deref()
                .filter(|text| !text.trim().is_empty())
                .map(PathBuf::from)
        };
        let config = LaunchConfig {
            mission: given_path(&arguments.mission),
            masterdata: given_path(&arguments.masterdata),
            profile: given_path(&arguments.profile),
            seed: arguments.seed,
            cycle_budget: arguments.cycle_budget,
            max_cycles: arguments.max_cycles,
            replay: replay_paths(arguments.replay.as_ref())?,
            sensor_cache: given_path(&arguments.sensor_cache),
            program: PathBuf::from(program),
        };
        let settings = world::resolve(&config)?;
        check_input(&config.program, "program", &["gbas", "gloc"])?;
        // Files that exist are checked for their kind before anything reads them; a
        // missing one is reported by the project layer, naming where its path came from.
        if let Some(mission) = settings.mission.as_ref().filter(|m| m.value.exists()) {
            check_input(&mission.value, "mission", &["mi"])?;
        }
        if let Some(profile) = &config.profile {
            check_input(profile, "profile", &["csv"])?;
        }
        if let Some(masterdata) = settings.masterdata.as_ref().filter(|m| m.value.exists()) {
            // Real sensor lists are called `masterdata` or `*.cac`: no extension rule.
            check_input(&masterdata.value, "masterdata", &[])?;
        }
        let (world, info) =
            world::launch_with(&config, &settings).map_err(|message| match self.access {
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

    pub(crate) fn set_breakpoints(
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
                        condition: breakpoint.condition.clone(),
                        hit_condition,
                        log_message: breakpoint.log_message.clone(),
                        ..LineBreakpoint::new(id, line)
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

    pub(crate) fn apply_function_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.functions.clone();
        self.apply(
            &requested,
            |_, breakpoint| {
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
                let kind = kind.ok_or_else(|| format!(
                    "`{}` is not a cycle breakpoint: write `cycle N` (stop at cycle N) or `every N` (every N cycles)",
                    breakpoint.name
                ))?;
                Ok((kind, Breakpoint::default()))
            },
            |debugger| &mut debugger.cycle_breakpoints,
        )
    }

    pub(crate) fn apply_data_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.data.clone();
        let out = self.apply(
            &requested,
            |debugger, breakpoint| {
                let name = breakpoint
                    .data_id
                    .strip_prefix("sensor:")
                    .unwrap_or(&breakpoint.data_id);
                let sensor = debugger
                    .and_then(|debugger| debugger.target.sensor_index(name))
                    .ok_or_else(|| format!("`{name}` is not a sensor"))?;
                Ok((sensor, Breakpoint::default()))
            },
            |debugger| &mut debugger.data_breakpoints,
        );
        if let Some(launched) = &mut self.launched {
            launched.debugger.reset_baseline();
        }
        out
    }

    pub(crate) fn apply_instruction_breakpoints(&mut self) -> Vec<Breakpoint> {
        let requested = self.requested.instructions.clone();
        self.apply(
            &requested,
            |debugger, breakpoint| {
                let count = debugger.map_or(0, |debugger| debugger.info.instruction_count());
                let pc = parse_address(&breakpoint.instruction_reference)
                    .and_then(|base| base.checked_add(breakpoint.offset.unwrap_or(0)))
                    .and_then(|pc| usize::try_from(pc).ok())
                    .filter(|pc| *pc < count)
                    .ok_or_else(|| {
                        format!(
                            "`{}` is not an instruction of the program",
                            breakpoint.instruction_reference
                        )
                    })?;
                let shown = Breakpoint {
                    instruction_reference: Some(address(pc)),
                    ..Breakpoint::default()
                };
                Ok((Pc(pc), shown))
            },
            |debugger| &mut debugger.instruction_breakpoints,
        )
    }

    /// Sets the breakpoints of one kind as requested: each gets a new id, its hit
    /// count is parsed, and `place` finds where it stops (with what the answer shows
    /// of it) or says why it cannot; the accepted ones replace the kind's `list`.
    fn apply<R: Conditions, At>(
        &mut self,
        requested: &[R],
        place: impl Fn(Option<&Debugger<World>>, &R) -> Result<(At, Breakpoint), String>,
        list: fn(&mut Debugger<World>) -> &mut Vec<debugger::Breakpoint<At>>,
    ) -> Vec<Breakpoint> {
        let mut out = Vec::new();
        let mut accepted = Vec::new();
        for breakpoint in requested {
            let id = self.new_id();
            let debugger = self.launched.as_ref().map(|launched| &launched.debugger);
            let placed = breakpoint
                .hit_condition()
                .filter(|text| !text.trim().is_empty())
                .map(HitCondition::parse)
                .transpose()
                .and_then(|hit_condition| Ok((place(debugger, breakpoint)?, hit_condition)));
            match placed {
                Ok(((at, shown), hit_condition)) => {
                    accepted.push(debugger::Breakpoint {
                        condition: breakpoint.condition().cloned(),
                        hit_condition,
                        ..debugger::Breakpoint::new(id, at)
                    });
                    out.push(Breakpoint {
                        id: Some(id),
                        verified: true,
                        ..shown
                    });
                }
                Err(message) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(message),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
            }
        }
        if let Some(launched) = &mut self.launched {
            *list(&mut launched.debugger) = accepted;
        }
        out
    }

    pub(crate) fn apply_filters(&mut self) {
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
/// name, a type error); a division by zero on the current values is not a reason,
/// since other values may not divide by zero, so it is checked, not evaluated.
pub(crate) fn condition_error(debugger: &Debugger<World>, condition: &str) -> Option<String> {
    debugger
        .check_expression(condition)
        .err()
        .map(|message| format!("the condition `{condition}` is not valid: {message}"))
}

/// What every requested breakpoint carries besides its place.
trait Conditions {
    fn condition(&self) -> Option<&String>;
    fn hit_condition(&self) -> Option<&str>;
}

macro_rules! conditions {
    ($($kind:ty),*) => {$(
        impl Conditions for $kind {
            fn condition(&self) -> Option<&String> {
                self.condition.as_ref()
            }
            fn hit_condition(&self) -> Option<&str> {
                self.hit_condition.as_deref()
            }
        }
    )*};
}

conditions!(
    FunctionBreakpoint,
    crate::types::DataBreakpoint,
    crate::types::InstructionBreakpoint
);

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

pub(crate) fn source_of(debugger: &Debugger<World>) -> Source {
    Source {
        name: Some(debugger.info.source_name()),
        path: Some(debugger.info.path.display().to_string()),
    }
}
