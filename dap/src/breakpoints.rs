//! The breakpoints a client sets, of every kind (source lines, cycles as function
//! breakpoints, data breakpoints on sensors, instructions, exception filters): each
//! request is kept as sent (so a `restart` applies it again to the new program),
//! checked, given ids, and placed in the debugger as a `debugger::Breakpoint`. The
//! answers say, per breakpoint, where it stops or why it cannot.

use crate::debugger::{self, CycleBreakpointKind, Debugger, HitCondition, LineBreakpoint, Pc};
use crate::error::{DebugError, DebugResult};
use crate::features;
use crate::references::{address, parse_address, source_of};
use crate::target::Target;
use crate::types::*;
use crate::world::World;

/// The breakpoints as the client last sent them, and the next id to hand out.
#[derive(Debug)]
pub struct Breakpoints {
    sources: Vec<(String, Vec<SourceBreakpoint>)>,
    functions: Vec<FunctionBreakpoint>,
    data: Vec<DataBreakpoint>,
    instructions: Vec<InstructionBreakpoint>,
    filters: Option<Vec<String>>,
    filter_options: Vec<ExceptionFilterOptions>,
    next_id: i64,
}

impl Default for Breakpoints {
    fn default() -> Self {
        Breakpoints {
            sources: Vec::new(),
            functions: Vec::new(),
            data: Vec::new(),
            instructions: Vec::new(),
            filters: None,
            filter_options: Vec::new(),
            next_id: 1,
        }
    }
}

/// The debugger of the launched program, if there is one.
pub type Loaded<'a> = Option<&'a mut Debugger<World>>;

/// A `set…Breakpoints` request: it replaces the breakpoints of its kind (kept as
/// sent) and answers one breakpoint per request, saying where it stops or why it
/// cannot. The adapter has one handler for all of them.
pub trait BreakpointRequest {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>>;
}

/// `setBreakpoints`: the breakpoints of one source.
impl BreakpointRequest for SetBreakpointsArguments {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>> {
        breakpoints.set_source(self, debugger)
    }
}

/// `setFunctionBreakpoints`: cycle breakpoints (`cycle N`, `every N`).
impl BreakpointRequest for SetFunctionBreakpointsArguments {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>> {
        breakpoints.functions = self.breakpoints;
        Ok(breakpoints.apply_functions(debugger))
    }
}

/// `setDataBreakpoints`: sensors watched for a change at each cycle boundary.
impl BreakpointRequest for SetDataBreakpointsArguments {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>> {
        breakpoints.data = self.breakpoints;
        Ok(breakpoints.apply_data(debugger))
    }
}

/// `setInstructionBreakpoints`.
impl BreakpointRequest for SetInstructionBreakpointsArguments {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>> {
        breakpoints.instructions = self.breakpoints;
        Ok(breakpoints.apply_instructions(debugger))
    }
}

/// `setExceptionBreakpoints`.
impl BreakpointRequest for SetExceptionBreakpointsArguments {
    fn set(self, breakpoints: &mut Breakpoints, debugger: Loaded) -> DebugResult<Vec<Breakpoint>> {
        breakpoints.set_filters(self, debugger)
    }
}

impl Breakpoints {
    /// `setBreakpoints`: replaces the breakpoints of one source (the `lines` of old
    /// clients when there are no `breakpoints`).
    fn set_source(
        &mut self,
        arguments: SetBreakpointsArguments,
        debugger: Loaded,
    ) -> DebugResult<Vec<Breakpoint>> {
        let path = arguments
            .source
            .path
            .clone()
            .ok_or_else(|| DebugError::request("`setBreakpoints` needs `source.path`"))?;
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
        self.sources.retain(|(known, _)| *known != path);
        self.sources.push((path.clone(), breakpoints.clone()));
        Ok(self.apply_source(&path, &breakpoints, debugger))
    }

    /// `setExceptionBreakpoints`, with conditions (`filterOptions`): one breakpoint per
    /// filter and option in the answer, unverified where the condition is not a valid
    /// expression. An unknown filter refuses the request.
    fn set_filters(
        &mut self,
        arguments: SetExceptionBreakpointsArguments,
        debugger: Loaded,
    ) -> DebugResult<Vec<Breakpoint>> {
        let checked = debugger.as_deref();
        let (_, breakpoints) = features::exception_filters(&arguments, |condition| {
            checked.and_then(|debugger| condition_error(debugger, condition))
        })?;
        self.filters = Some(arguments.filters);
        self.filter_options = arguments.filter_options.unwrap_or_default();
        if let Some(debugger) = debugger {
            self.apply_filters(debugger);
        }
        Ok(breakpoints)
    }

    /// Applies everything the client set before to a newly launched program (a
    /// `restart` keeps the breakpoints).
    pub fn reapply(&mut self, debugger: &mut Debugger<World>) {
        let sources = std::mem::take(&mut self.sources);
        for (path, breakpoints) in &sources {
            self.apply_source(path, breakpoints, Some(&mut *debugger));
        }
        self.sources = sources;
        self.apply_functions(Some(&mut *debugger));
        self.apply_data(Some(&mut *debugger));
        self.apply_instructions(Some(&mut *debugger));
        self.apply_filters(debugger);
    }

    fn new_id(&mut self) -> i64 {
        let id = self.next_id;
        self.next_id += 1;
        id
    }

    fn apply_source(
        &mut self,
        path: &str,
        requested: &[SourceBreakpoint],
        debugger: Loaded,
    ) -> Vec<Breakpoint> {
        let ids: Vec<i64> = requested.iter().map(|_| self.new_id()).collect();
        let Some(debugger) = debugger else {
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
        let same_source = debugger.info.is_same_source(path);
        // Replace this source's breakpoints (there is one source per session).
        if same_source {
            debugger.line_breakpoints.clear();
        }
        requested
            .iter()
            .zip(ids)
            .map(|(breakpoint, id)| {
                if !same_source {
                    return unverified(
                        id,
                        breakpoint.line,
                        format!("{path} is not the program being debugged"),
                    );
                }
                match place_line(debugger, breakpoint, id) {
                    Ok(shown) => shown,
                    Err(error) => unverified(id, breakpoint.line, error.to_string()),
                }
            })
            .collect()
    }

    fn apply_functions(&mut self, debugger: Loaded) -> Vec<Breakpoint> {
        let requested = self.functions.clone();
        self.apply(
            &requested,
            debugger,
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
                let kind = kind.ok_or_else(|| DebugError::request(format!(
                    "`{}` is not a cycle breakpoint: write `cycle N` (stop at cycle N) or `every N` (every N cycles)",
                    breakpoint.name
                )))?;
                Ok((kind, Breakpoint::default()))
            },
            |debugger| &mut debugger.cycle_breakpoints,
        )
    }

    fn apply_data(&mut self, mut debugger: Loaded) -> Vec<Breakpoint> {
        let requested = self.data.clone();
        let out = self.apply(
            &requested,
            debugger.as_deref_mut(),
            |debugger, breakpoint| {
                let name = breakpoint
                    .data_id
                    .strip_prefix("sensor:")
                    .unwrap_or(&breakpoint.data_id);
                let sensor = debugger
                    .and_then(|debugger| debugger.target.sensor_index(name))
                    .ok_or_else(|| DebugError::request(format!("`{name}` is not a sensor")))?;
                Ok((sensor, Breakpoint::default()))
            },
            |debugger| &mut debugger.data_breakpoints,
        );
        if let Some(debugger) = debugger {
            debugger.reset_baseline();
        }
        out
    }

    fn apply_instructions(&mut self, debugger: Loaded) -> Vec<Breakpoint> {
        let requested = self.instructions.clone();
        self.apply(
            &requested,
            debugger,
            |debugger, breakpoint| {
                let count = debugger.map_or(0, |debugger| debugger.info.instruction_count());
                let pc = parse_address(&breakpoint.instruction_reference)
                    .and_then(|base| base.checked_add(breakpoint.offset.unwrap_or(0)))
                    .and_then(|pc| usize::try_from(pc).ok())
                    .filter(|pc| *pc < count)
                    .ok_or_else(|| {
                        DebugError::request(format!(
                            "`{}` is not an instruction of the program",
                            breakpoint.instruction_reference
                        ))
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

    fn apply_filters(&mut self, debugger: &mut Debugger<World>) {
        let Some(filters) = &self.filters else {
            return;
        };
        let arguments = SetExceptionBreakpointsArguments {
            filters: filters.clone(),
            filter_options: Some(self.filter_options.clone()),
        };
        let checked = &*debugger;
        if let Ok((chosen, _)) =
            features::exception_filters(&arguments, |condition| condition_error(checked, condition))
        {
            debugger.filters = chosen;
        }
    }

    /// Sets the breakpoints of one kind as requested: each gets a new id, its hit
    /// count is parsed, and `place` finds where it stops (with what the answer shows
    /// of it) or says why it cannot; the accepted ones replace the kind's `list`.
    fn apply<R: Conditions, At>(
        &mut self,
        requested: &[R],
        debugger: Loaded,
        place: impl Fn(Option<&Debugger<World>>, &R) -> DebugResult<(At, Breakpoint)>,
        list: fn(&mut Debugger<World>) -> &mut Vec<debugger::Breakpoint<At>>,
    ) -> Vec<Breakpoint> {
        let mut out = Vec::new();
        let mut accepted = Vec::new();
        for breakpoint in requested {
            let id = self.new_id();
            // A condition that can never be evaluated is refused here, as a line
            // breakpoint's is, rather than stopping at every hit.
            let invalid = breakpoint
                .condition()
                .filter(|text| !text.trim().is_empty())
                .zip(debugger.as_deref())
                .and_then(|(condition, debugger)| condition_error(debugger, condition));
            let placed = match invalid {
                Some(message) => Err(DebugError::request(message)),
                None => breakpoint
                    .hit_condition()
                    .filter(|text| !text.trim().is_empty())
                    .map(HitCondition::parse)
                    .transpose()
                    .and_then(|hit_condition| {
                        Ok((place(debugger.as_deref(), breakpoint)?, hit_condition))
                    }),
            };
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
                Err(error) => out.push(Breakpoint {
                    id: Some(id),
                    verified: false,
                    message: Some(error.to_string()),
                    reason: Some("failed".into()),
                    ..Breakpoint::default()
                }),
            }
        }
        if let Some(debugger) = debugger {
            *list(debugger) = accepted;
        }
        out
    }
}

/// Places one line breakpoint (`id`) in `debugger`: the answer that shows it, or why
/// it cannot be set (no such line, no code there, a condition or hit count that is no
/// such thing).
fn place_line(
    debugger: &mut Debugger<World>,
    breakpoint: &SourceBreakpoint,
    id: i64,
) -> DebugResult<Breakpoint> {
    let refusal = match (breakpoint.line, debugger.info.source_lines) {
        (line, _) if line < 1 => Some(format!("line {line} is not a line: lines start at 1")),
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
        return Err(DebugError::request(message));
    }
    let hit_condition = breakpoint
        .hit_condition
        .as_deref()
        .filter(|text| !text.trim().is_empty())
        .map(HitCondition::parse)
        .transpose()?;
    let line = u32::try_from(breakpoint.line)
        .ok()
        .and_then(|line| debugger.info.resolve_line(line))
        .ok_or_else(|| DebugError::request("no code in this file"))?;
    debugger.line_breakpoints.push(LineBreakpoint {
        condition: breakpoint.condition.clone(),
        hit_condition,
        log_message: breakpoint.log_message.clone(),
        ..LineBreakpoint::new(id, line)
    });
    Ok(Breakpoint {
        id: Some(id),
        verified: true,
        line: Some(i64::from(line)),
        source: Some(source_of(debugger)),
        ..Breakpoint::default()
    })
}

/// Why a breakpoint condition can never be evaluated (a syntax error, an unknown
/// name, a type error); a division by zero on the current values is not a reason,
/// since other values may not divide by zero, so it is checked, not evaluated.
pub fn condition_error(debugger: &Debugger<World>, condition: &str) -> Option<String> {
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

conditions!(FunctionBreakpoint, DataBreakpoint, InstructionBreakpoint);

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
