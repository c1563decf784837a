//! One handler per DAP command, registered in [`table`]: each takes its typed
//! arguments and the session, and returns its typed body or a [`Failure`]; events
//! that follow the response are queued with [`Session::then`]. The views of the
//! debugger's state that the answers show (frames, scopes, variables, disassembly)
//! are built here too.

use std::sync::OnceLock;

use serde::de::IgnoredAny;

use crate::breakpoints::BreakpointRequest;
use crate::debugger::{Debugger, Edit, RunMode, Stop, StopReason};
use crate::dispatch::{Dispatcher, Failure};
use crate::edits;
use crate::error::{DebugError, DebugResult};
use crate::features::{self, ClientOptions};
use crate::format::ValueFormat;
use crate::launch::{LaunchArguments, RestartArguments};
use crate::program::Language;
use crate::references::{
    address, parse_address, source_of, ALL_SENSORS, ARRAYS, FRAME_ID, SCOPE_NAVIGATION,
    SCOPE_REGISTERS, SCOPE_SENSORS, SCOPE_VARIABLES, SCOPE_VEHICLE, THREAD_ID,
};
use crate::session::{Running, Session, Then};
use crate::target::{Named, Phase, Target};
use crate::types::*;
use crate::world::World;
use gloc_compiler::typed::Ty;

type Answer<T> = Result<T, Failure>;

/// The most instructions one `disassemble` may ask for (the response holds exactly
/// as many, padded with invalid entries where there is no code).
pub const MAX_DISASSEMBLE: i64 = 100_000;

/// What the adapter can do, as `initialize` answers it.
fn capabilities() -> Capabilities {
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

/// Every command the adapter answers, with its handler.
pub fn table() -> &'static Dispatcher<Session> {
    static TABLE: OnceLock<Dispatcher<Session>> = OnceLock::new();
    TABLE.get_or_init(|| {
        Dispatcher::new()
            .on("initialize", initialize)
            .on("launch", launch)
            .on("attach", attach)
            .on("disconnect", disconnect)
            .on("terminate", terminate)
            .on("restart", restart)
            .on("setBreakpoints", set_breakpoints::<SetBreakpointsArguments>)
            .on(
                "setFunctionBreakpoints",
                set_breakpoints::<SetFunctionBreakpointsArguments>,
            )
            .on(
                "setExceptionBreakpoints",
                set_breakpoints::<SetExceptionBreakpointsArguments>,
            )
            .on(
                "setInstructionBreakpoints",
                set_breakpoints::<SetInstructionBreakpointsArguments>,
            )
            .on("dataBreakpointInfo", data_breakpoint_info)
            .on(
                "setDataBreakpoints",
                set_breakpoints::<SetDataBreakpointsArguments>,
            )
            .on("breakpointLocations", breakpoint_locations)
            .on("configurationDone", configuration_done)
            .on("threads", threads)
            .on("continue", continue_)
            .on("next", next)
            .on("stepIn", step_in)
            .on("stepOut", step_out)
            .on("pause", pause)
            .on("stepBack", step_back)
            .on("reverseContinue", reverse_continue)
            .on("stackTrace", stack_trace)
            .on("scopes", scopes)
            .on("variables", variables)
            .on("setVariable", set_variable)
            .on("evaluate", evaluate)
            .on("exceptionInfo", exception_info)
            .on("disassemble", disassemble)
            .on("loadedSources", loaded_sources)
            .on("completions", completions)
            .on("setExpression", set_expression)
            .on("gotoTargets", goto_targets)
            .on("goto", goto)
            .on("cancel", cancel)
    })
}

fn initialize(session: &mut Session, client: ClientOptions) -> Answer<Capabilities> {
    session.client = client;
    session.initialized = true;
    Ok(capabilities())
}

fn launch(session: &mut Session, arguments: LaunchArguments) -> Answer<()> {
    if !session.initialized {
        return Err("send `initialize` before `launch`".into());
    }
    if session.launched.is_some() {
        return Err("a program is already running; `restart` or `disconnect` first".into());
    }
    session.launch(arguments)?;
    if session.launched_mut()?.debugger.has_history() {
        session.then_event(
            "capabilities",
            CapabilitiesEventBody {
                capabilities: Capabilities {
                    supports_step_back: Some(true),
                    ..Capabilities::default()
                },
            },
        );
    }
    session.then_event("initialized", ());
    Ok(())
}

fn attach(_: &mut Session, _: IgnoredAny) -> Answer<()> {
    Err("`attach` is not supported: use `launch`".into())
}

fn disconnect(session: &mut Session, _: DisconnectArguments) -> Answer<()> {
    session.then(Then::Exit);
    Ok(())
}

fn terminate(session: &mut Session, _: IgnoredAny) -> Answer<()> {
    if let Some(launched) = &mut session.launched {
        launched.running = None;
    }
    session.then_event("terminated", ());
    Ok(())
}

fn restart(session: &mut Session, request: RestartArguments) -> Answer<()> {
    let launched = session.launched_mut()?;
    let arguments = request
        .arguments
        .unwrap_or_else(|| launched.arguments.clone());
    session.launched = None;
    session.launch(arguments)?;
    let request_seq = session.request_seq;
    let launched = session.launched_mut()?;
    if launched.stop_on_entry {
        session.then(Then::Stop(stopped(
            StopReason::Entry,
            "Restarted: paused on entry",
        )));
    } else {
        let start = launched.debugger.clock();
        launched.running = Some(Running::new(RunMode::Continue, start, request_seq));
    }
    Ok(())
}

/// `setBreakpoints`, `setFunctionBreakpoints`, `setDataBreakpoints`, … : each
/// replaces the breakpoints of its kind ([`BreakpointRequest`]).
fn set_breakpoints<R: BreakpointRequest>(
    session: &mut Session,
    request: R,
) -> Answer<BreakpointsBody> {
    let (breakpoints, debugger) = session.breakpoints_and_debugger();
    let breakpoints = request.set(breakpoints, debugger)?;
    Ok(BreakpointsBody { breakpoints })
}

fn data_breakpoint_info(
    session: &mut Session,
    arguments: DataBreakpointInfoArguments,
) -> Answer<DataBreakpointInfoBody> {
    let target = &session.launched_mut()?.debugger.target;
    let in_sensor_scope = matches!(
        arguments.variables_reference,
        None | Some(SCOPE_SENSORS) | Some(ALL_SENSORS) | Some(SCOPE_NAVIGATION)
    );
    let sensor = if in_sensor_scope {
        target.sensor_index(arguments.name.trim())
    } else {
        None
    };
    Ok(match sensor {
        Some(index) => {
            let name = target.sensor_name(index).unwrap_or_default();
            DataBreakpointInfoBody {
                data_id: Some(format!("sensor:{name}")),
                description: format!("{name} changes (checked at each cycle boundary)"),
                access_types: Some(vec!["write".into()]),
                can_persist: Some(true),
            }
        }
        None => DataBreakpointInfoBody {
            data_id: None,
            description: format!(
                "`{}` is not a sensor: only sensors can be watched",
                arguments.name
            ),
            access_types: None,
            can_persist: None,
        },
    })
}

fn breakpoint_locations(
    session: &mut Session,
    arguments: BreakpointLocationsArguments,
) -> Answer<BreakpointLocationsBody> {
    let info = &session.launched_mut()?.debugger.info;
    let end = arguments.end_line.unwrap_or(arguments.line);
    let same = arguments
        .source
        .path
        .as_deref()
        .is_some_and(|path| info.is_same_source(path));
    let breakpoints = if same {
        info.lines_with_code()
            .map(i64::from)
            .filter(|line| *line >= arguments.line && *line <= end)
            .map(|line| BreakpointLocation { line })
            .collect()
    } else {
        Vec::new()
    };
    Ok(BreakpointLocationsBody { breakpoints })
}

fn configuration_done(session: &mut Session, _: IgnoredAny) -> Answer<()> {
    let request_seq = session.request_seq;
    let launched = session.launched_mut()?;
    if launched.stop_on_entry {
        session.then(Then::Stop(stopped(StopReason::Entry, "Paused on entry")));
        return Ok(());
    }
    let first = launched.debugger.check_start();
    if first.is_none() {
        let start = launched.debugger.clock();
        launched.running = Some(Running::new(RunMode::Continue, start, request_seq));
    }
    session.then(Then::Outputs);
    if let Some(stop) = first {
        session.then(Then::Stop(stop));
    }
    Ok(())
}

fn threads(_: &mut Session, _: IgnoredAny) -> Answer<ThreadsBody> {
    Ok(ThreadsBody {
        threads: vec![Thread {
            id: THREAD_ID,
            name: "script".into(),
        }],
    })
}

fn continue_(session: &mut Session, arguments: StepArguments) -> Answer<ContinueBody> {
    resume(session, RunMode::Continue, &arguments)?;
    Ok(ContinueBody {
        all_threads_continued: true,
    })
}

fn next(session: &mut Session, arguments: StepArguments) -> Answer<()> {
    resume(session, RunMode::Next, &arguments)
}

fn step_in(session: &mut Session, arguments: StepArguments) -> Answer<()> {
    let instruction = arguments.granularity.as_deref() == Some("instruction");
    resume(session, RunMode::StepIn { instruction }, &arguments)
}

fn step_out(session: &mut Session, arguments: StepArguments) -> Answer<()> {
    resume(session, RunMode::StepOut, &arguments)
}

/// Starts a forward run; `run_slice` carries it out.
fn resume(session: &mut Session, mode: RunMode, _: &StepArguments) -> Answer<()> {
    let request_seq = session.request_seq;
    let launched = session.launched_mut()?;
    if launched.running.is_some() {
        return Err("the program is already running; `pause` first".into());
    }
    let mode = match mode {
        // In GLOC a statement is an instruction.
        RunMode::StepIn { .. } if launched.debugger.info.language == Language::Gloc => {
            RunMode::StepIn { instruction: true }
        }
        other => other,
    };
    let start = launched.debugger.clock();
    launched.running = Some(Running::new(mode, start, request_seq));
    Ok(())
}

fn pause(session: &mut Session, _: IgnoredAny) -> Answer<()> {
    let launched = session.launched_mut()?;
    if launched.running.is_some() {
        launched.debugger.request_pause();
    } else {
        session.then(Then::Stop(stopped(StopReason::Pause, "Paused")));
    }
    Ok(())
}

fn step_back(session: &mut Session, _: IgnoredAny) -> Answer<()> {
    let debugger = paused(session)?;
    let stop = debugger.step_back()?;
    session.then(Then::Stop(stop));
    Ok(())
}

/// Runs backwards to the last breakpoint hit, showing a cancellable progress (when the
/// client shows them); a `cancel` of the request or of the progress, which the reader
/// thread notes while this runs, stops it (`Debugger::reverse_continue_unless`).
fn reverse_continue(session: &mut Session, _: IgnoredAny) -> Answer<()> {
    paused(session)?;
    let request_seq = session.request_seq;
    let progress = format!("reverse-{request_seq}");
    let shows_progress = session.client.supports_progress_reporting;
    if shows_progress {
        session
            .start_progress(&progress, "Running backwards", request_seq)
            .map_err(DebugError::from)?;
    }
    let cancellations = session.cancellations.clone();
    let stop = paused(session)?
        .reverse_continue_unless(&|| cancellations.cancelled(request_seq, Some(&progress)));
    if shows_progress {
        session.end_progress(progress).map_err(DebugError::from)?;
    }
    session.then(Then::Stop(stop?));
    Ok(())
}

fn completions(session: &mut Session, arguments: CompletionsArguments) -> Answer<CompletionsBody> {
    let client = session.client;
    let debugger = &session.launched_mut()?.debugger;
    Ok(CompletionsBody {
        targets: features::completions(debugger, &arguments, client),
    })
}

fn set_expression(
    session: &mut Session,
    arguments: SetExpressionArguments,
) -> Answer<SetExpressionBody> {
    Ok(features::set_expression(paused(session)?, &arguments)?)
}

fn goto_targets(session: &mut Session, arguments: GotoTargetsArguments) -> Answer<GotoTargetsBody> {
    let client = session.client;
    let debugger = &session.launched_mut()?.debugger;
    Ok(GotoTargetsBody {
        targets: features::goto_targets(debugger, &arguments, client)?,
    })
}

fn goto(session: &mut Session, arguments: GotoArguments) -> Answer<()> {
    let description = features::goto(paused(session)?, &arguments)?;
    session.then(Then::Stop(stopped(StopReason::Goto, &description)));
    Ok(())
}

/// The reader thread noted the `cancel` as it arrived; a forward run asks the list
/// between slices, a reverse run between steps. Cancelling what is over does nothing.
fn cancel(_: &mut Session, _: CancelArguments) -> Answer<()> {
    Ok(())
}

/// The debugger of a launched program that is not running.
fn paused(session: &mut Session) -> Answer<&mut Debugger<World>> {
    let launched = session.launched_mut()?;
    if launched.running.is_some() {
        return Err(DebugError::Running.into());
    }
    Ok(&mut launched.debugger)
}

fn stack_trace(session: &mut Session, arguments: StackTraceArguments) -> Answer<StackTraceBody> {
    let debugger = &session.launched_mut()?.debugger;
    let format = features::value_format(arguments.format);
    // One frame (the script has no calls): `startFrame` past it gives none; `levels`
    // 0 or absent means all.
    let stack_frames = match (arguments.start_frame.unwrap_or(0), arguments.levels) {
        (start, _) if start < 0 => return Err(format!("`startFrame` {start} is negative").into()),
        (0, None) => vec![stack_frame(debugger, format)],
        (0, Some(levels)) if levels >= 0 => vec![stack_frame(debugger, format)],
        (_, Some(levels)) if levels < 0 => {
            return Err(format!("`levels` {levels} is negative").into())
        }
        _ => Vec::new(),
    };
    Ok(StackTraceBody {
        stack_frames,
        total_frames: 1,
    })
}

fn scopes(session: &mut Session, _: ScopesArguments) -> Answer<ScopesBody> {
    let debugger = &session.launched_mut()?.debugger;
    let target = &debugger.target;
    Ok(ScopesBody {
        scopes: vec![
            scope(
                "Variables",
                Some("locals"),
                SCOPE_VARIABLES,
                target.variables().len() + debugger.info.scope.constants().len(),
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
            scope(
                "Navigation",
                None,
                SCOPE_NAVIGATION,
                target.navigation().len(),
            ),
        ],
    })
}

fn variables(session: &mut Session, arguments: VariablesArguments) -> Answer<VariablesBody> {
    let debugger = &session.launched_mut()?.debugger;
    Ok(VariablesBody {
        variables: variable_list(debugger, &arguments)?,
    })
}

fn set_variable(session: &mut Session, arguments: SetVariableArguments) -> Answer<SetVariableBody> {
    let debugger = &mut session.launched_mut()?.debugger;
    Ok(SetVariableBody {
        value: set_value(debugger, &arguments)?,
    })
}

/// A value in the asked format, or an array (`tsum`) with its elements as children.
fn evaluate(session: &mut Session, arguments: EvaluateArguments) -> Answer<EvaluateBody> {
    let debugger = &session.launched_mut()?.debugger;
    Ok(features::evaluate(debugger, &arguments)?)
}

fn exception_info(session: &mut Session, _: IgnoredAny) -> Answer<ExceptionInfoBody> {
    let Some(trap) = session.launched_mut()?.debugger.trap.clone() else {
        return Err("the program is not stopped on an exception".into());
    };
    Ok(ExceptionInfoBody {
        exception_id: "trap".into(),
        description: trap,
        break_mode: "always".into(),
    })
}

fn disassemble(session: &mut Session, arguments: DisassembleArguments) -> Answer<DisassembleBody> {
    let debugger = &session.launched_mut()?.debugger;
    Ok(DisassembleBody {
        instructions: instructions(debugger, &arguments)?,
    })
}

fn loaded_sources(session: &mut Session, _: IgnoredAny) -> Answer<LoadedSourcesBody> {
    let debugger = &session.launched_mut()?.debugger;
    Ok(LoadedSourcesBody {
        sources: vec![source_of(debugger)],
    })
}

/// A stop the adapter decides itself (not the debugger's run).
fn stopped(reason: StopReason, description: &str) -> Stop {
    Stop {
        reason,
        description: description.into(),
        text: None,
        hit_breakpoint_ids: Vec::new(),
    }
}

// ---------------------------------------------------------------------------------------
// Views of the debugger's state

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
        evaluate_name: named.evaluate_name,
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

fn variable_list(
    debugger: &Debugger<World>,
    arguments: &VariablesArguments,
) -> DebugResult<Vec<Variable>> {
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
            // The script's constants after its variables (so array positions hold).
            .chain(debugger.info.scope.constants().iter().map(|constant| {
                plain(Named {
                    name: constant.name.clone(),
                    value: constant.value.clone(),
                    ty: match constant.ty {
                        Ty::Float => "float constant",
                        _ => "integer constant",
                    },
                    length: None,
                    element: None,
                    evaluate_name: Some(constant.name.clone()),
                })
            }))
            .collect(),
        reference if reference >= ARRAYS => {
            let position = usize::try_from(reference - ARRAYS).unwrap_or(usize::MAX);
            let array = target
                .variables()
                .into_iter()
                .nth(position)
                .filter(|named| named.length.is_some())
                .ok_or_else(|| {
                    DebugError::request(format!("unknown variablesReference {reference}"))
                })?;
            let length = array.length.unwrap_or(0);
            let start = usize::try_from(arguments.start.unwrap_or(0))
                .unwrap_or(0)
                .min(length);
            let count = match arguments.count {
                Some(count) if count > 0 => usize::try_from(count).unwrap_or(usize::MAX),
                _ => length,
            };
            let element_type = match array.element {
                Some(Ty::Float) => "float",
                _ => "integer",
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
                ty: Some(crate::expr::type_name(value).into()),
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
        SCOPE_NAVIGATION => target.navigation().into_iter().map(plain).collect(),
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
        other => {
            return Err(DebugError::request(format!(
                "unknown variablesReference {other}"
            )))
        }
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

fn set_value(
    debugger: &mut Debugger<World>,
    arguments: &SetVariableArguments,
) -> DebugResult<String> {
    let value = edits::value_of(debugger, &arguments.value)?;
    let format = features::value_format(arguments.format);
    match arguments.variables_reference {
        SCOPE_VARIABLES
            if debugger
                .info
                .scope
                .constants()
                .iter()
                .any(|constant| constant.name.eq_ignore_ascii_case(&arguments.name)) =>
        {
            Err(DebugError::edit(format!(
                "`{}` is a constant; change its `const` line and restart",
                arguments.name
            )))
        }
        SCOPE_VARIABLES => {
            debugger.edit(Edit::Variable(arguments.name.clone(), value))?;
            debugger
                .target
                .variable(&arguments.name)
                .map(|value| format.number(value))
                .ok_or_else(|| DebugError::edit(format!("no variable `{}`", arguments.name)))
        }
        SCOPE_REGISTERS => {
            let index = arguments
                .name
                .strip_prefix('r')
                .and_then(|digits| digits.parse::<usize>().ok())
                .ok_or_else(|| {
                    DebugError::edit(format!("`{}` is not a register", arguments.name))
                })?;
            debugger.edit(Edit::Register(index, value))?;
            debugger
                .target
                .registers()
                .get(index)
                .map(|value| format.number(*value))
                .ok_or_else(|| DebugError::edit(format!("no register `{}`", arguments.name)))
        }
        SCOPE_NAVIGATION if debugger.target.sensor_index(&arguments.name).is_none() => {
            Err(DebugError::edit(format!(
                "`{}` is read-only (the simulator computes it); set one of the rows named by a sensor, such as `m_lat`",
                arguments.name
            )))
        }
        // A navigation row named by its sensor sets the sensor.
        SCOPE_SENSORS | ALL_SENSORS | SCOPE_NAVIGATION => {
            let index = debugger
                .target
                .sensor_index(&arguments.name)
                .ok_or_else(|| DebugError::edit(format!("`{}` is not a sensor", arguments.name)))?;
            debugger.edit(Edit::Sensor(index, value.as_f64()))?;
            Ok(format.sensor(debugger.target.sensor(index)))
        }
        SCOPE_VEHICLE => Err(DebugError::edit(
            "the Vehicle scope is read-only; set a sensor instead",
        )),
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
                .ok_or_else(|| {
                    DebugError::request(format!("unknown variablesReference {reference}"))
                })?;
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
                    DebugError::edit(format!(
                        "`{}` is not an array element like `[3]` or `{array}(3)`",
                        arguments.name
                    ))
                })?;
            debugger.edit(Edit::Element(name.clone(), index, value))?;
            debugger
                .target
                .element(&name, index)
                .map(|value| format.number(value))
                .ok_or_else(|| DebugError::edit(format!("no element `{}`", arguments.name)))
        }
        other => Err(DebugError::request(format!(
            "unknown variablesReference {other}"
        ))),
    }
}

fn instructions(
    debugger: &Debugger<World>,
    arguments: &DisassembleArguments,
) -> DebugResult<Vec<DisassembledInstruction>> {
    let base = parse_address(&arguments.memory_reference).ok_or_else(|| {
        DebugError::request(format!(
            "`{}` is not an instruction address",
            arguments.memory_reference
        ))
    })?;
    let first = base
        .saturating_add(arguments.offset.unwrap_or(0))
        .saturating_add(arguments.instruction_offset.unwrap_or(0));
    let count = arguments.instruction_count;
    if !(0..=MAX_DISASSEMBLE).contains(&count) {
        return Err(DebugError::request(format!(
            "`instructionCount` {count} is outside 0 to {MAX_DISASSEMBLE}"
        )));
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
