//! The debugger proper, independent of the wire protocol: breakpoints, cycle-level and
//! statement-level stepping, and exact reverse execution from snapshots plus replay.
//!
//! Time is a `Clock` (cycle, steps taken in that cycle), totally ordered. The world is
//! deterministic, so any earlier clock can be reached again by restoring the nearest
//! snapshot at or before it and replaying, re-applying the user's edits (setVariable)
//! from a journal at the clocks where they were made.

use std::collections::{BTreeMap, HashMap};
use std::time::Instant;

use crate::error::{DebugError, DebugResult};
use crate::expr::{self, Number, Watched};
use crate::program::DebugInfo;
use crate::target::{Milestone, Notice, Phase, StepEvent, Target, TrapKind};

/// A point in a run: the cycle, and how many steps were taken in it (0 = its boundary).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Clock {
    pub cycle: u64,
    pub steps: u64,
}

/// What the user asked the run to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunMode {
    Continue,
    /// To the next cycle boundary.
    Next,
    /// One statement (or one instruction with `instruction` granularity).
    StepIn {
        instruction: bool,
    },
    /// To the end of the script's share of the cycle.
    StepOut,
}

/// Why the run stopped (the protocol layer names it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// Paused before the first step (stopOnEntry, restart, the start of the history).
    Entry,
    Pause,
    Step,
    Breakpoint,
    /// A cycle breakpoint (set as a function breakpoint `cycle N` / `every N`).
    CycleBreakpoint,
    /// A watched sensor changed.
    DataBreakpoint,
    InstructionBreakpoint,
    /// A trap, a cycle overrun or an abend that its filter stops on.
    Exception,
    /// A `goto` moved the script's next instruction.
    Goto,
    /// A goto behavior reached its waypoint (the `waypoint` filter).
    Waypoint,
    /// The glider surfaced (the `surfacing` filter).
    Surfacing,
}

/// Why the run stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct Stop {
    pub reason: StopReason,
    pub description: String,
    pub text: Option<String>,
    pub hit_breakpoint_ids: Vec<i64>,
}

/// How much one call of [`Debugger::run`] may do: at most `steps` steps, none begun
/// after `until` (at least one is always taken).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slice {
    pub steps: u64,
    pub until: Option<Instant>,
}

impl Slice {
    /// At most `steps` steps, however long they take (tests and benchmarks).
    pub fn steps(steps: u64) -> Slice {
        Slice { steps, until: None }
    }
}

/// Where a forward run is after a slice of work.
#[derive(Clone, Debug, PartialEq)]
pub enum Progress {
    Running,
    Stopped(Stop),
    Ended { summary: String },
}

/// What kind of thing an output is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// A line the script printed.
    Script,
    /// Something the run went wrong on (a trap, a broken condition).
    Error,
    /// The debugger's own notes (logpoints, behavior changes).
    Note,
    /// What the user must see (setup warnings, an abend).
    Important,
}

/// Something to tell the user, with the source line it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    pub category: Category,
    pub text: String,
    pub line: Option<u32>,
}

/// A breakpoint of any kind: where it stops (`at`: a source line, a cycle, a watched
/// sensor, an instruction) and what it shares with every other kind.
#[derive(Clone, Debug)]
pub struct Breakpoint<At> {
    pub id: i64,
    pub at: At,
    pub condition: Option<String>,
    pub hit_condition: Option<HitCondition>,
    /// A logpoint prints this (with `{expression}`s filled in) instead of stopping.
    pub log_message: Option<String>,
    pub hits: u64,
}

impl<At> Breakpoint<At> {
    /// A breakpoint at `at` with no condition.
    pub fn new(id: i64, at: At) -> Breakpoint<At> {
        Breakpoint {
            id,
            at,
            condition: None,
            hit_condition: None,
            log_message: None,
            hits: 0,
        }
    }
}

/// At a source line's entry.
pub type LineBreakpoint = Breakpoint<u32>;
/// At a cycle boundary.
pub type CycleBreakpoint = Breakpoint<CycleBreakpointKind>;
/// On a change of the sensor with this index, seen at a cycle boundary.
pub type DataBreakpoint = Breakpoint<usize>;
/// Before the instruction at this pc.
pub type InstructionBreakpoint = Breakpoint<Pc>;

/// An instruction's index in the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pc(pub usize);

#[derive(Clone, Copy, Debug)]
pub enum CycleBreakpointKind {
    At(u64),
    Every(u64),
}

/// `N` / `== N` (the N-th hit), `> N`, `>= N`, `< N`, `<= N`, `% N` (every N-th).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HitCondition {
    Equal(u64),
    Greater(u64),
    GreaterEqual(u64),
    Less(u64),
    LessEqual(u64),
    Every(u64),
}

impl HitCondition {
    pub fn parse(text: &str) -> DebugResult<HitCondition> {
        let text = text.trim();
        let (operator, rest) = ["==", ">=", "<=", ">", "<", "%", "="]
            .iter()
            .find_map(|operator| text.strip_prefix(operator).map(|rest| (*operator, rest)))
            .unwrap_or(("==", text));
        let count: u64 = rest.trim().parse().map_err(|_| {
            DebugError::request(format!(
                "hit count `{text}` is not `N`, `>= N`, `> N`, `< N`, `<= N` or `% N`"
            ))
        })?;
        Ok(match operator {
            ">=" => HitCondition::GreaterEqual(count),
            "<=" => HitCondition::LessEqual(count),
            ">" => HitCondition::Greater(count),
            "<" => HitCondition::Less(count),
            "%" if count == 0 => return Err(DebugError::request("`% 0` would never stop")),
            "%" => HitCondition::Every(count),
            _ => HitCondition::Equal(count),
        })
    }

    fn holds(self, hits: u64) -> bool {
        match self {
            HitCondition::Equal(count) => hits == count,
            HitCondition::Greater(count) => hits > count,
            HitCondition::GreaterEqual(count) => hits >= count,
            HitCondition::Less(count) => hits < count,
            HitCondition::LessEqual(count) => hits <= count,
            HitCondition::Every(count) => hits.is_multiple_of(count),
        }
    }
}

/// The exception filters the adapter offers (id, label, description, on by default),
/// each with a condition (a GBASIC expression over the state where it happens): the
/// script's failures and the mission's abort, on by default, and the points of the
/// journey, off until the user turns them on.
pub const EXCEPTION_FILTERS: [(&str, &str, &str, bool); 5] = [
    (
        "trap",
        "Runtime traps",
        "Stop when the script traps (division by zero, bad jump, ...)",
        true,
    ),
    (
        "overrun",
        "Cycle overrun",
        "Stop when the script exceeds its per-cycle instruction budget",
        true,
    ),
    ("abend", "Abend", "Stop when the mission aborts", true),
    (
        "waypoint",
        "Waypoint reached",
        "Stop when a goto behavior reaches its waypoint (x_hit_a_waypoint, judged on the dead-reckoned position)",
        false,
    ),
    (
        "surfacing",
        "Surfacing",
        "Stop when the glider comes up (x_dr_state goes from 1, underwater, to 2, surfaced)",
        false,
    ),
];

/// Which runtime failures and points of the journey stop the run (DAP exception
/// filters). The default: failures stop it, the journey's points do not.
#[derive(Clone, Debug)]
pub struct ExceptionFilters {
    pub overrun: Filter,
    pub trap: Filter,
    pub abend: Filter,
    /// A waypoint reached; off unless asked for.
    pub waypoint: Filter,
    /// A surfacing; off unless asked for.
    pub surfacing: Filter,
}

/// One exception filter: whether it is on, and its GBASIC condition (DAP
/// `exceptionFilterOptions`): an enabled filter with one stops only where it holds,
/// evaluated on the state at the failure.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Filter {
    pub enabled: bool,
    pub condition: Option<String>,
}

impl ExceptionFilters {
    /// Every filter off.
    pub fn off() -> ExceptionFilters {
        ExceptionFilters {
            overrun: Filter::default(),
            trap: Filter::default(),
            abend: Filter::default(),
            waypoint: Filter::default(),
            surfacing: Filter::default(),
        }
    }

    /// The filter with DAP id `id` (one of [`EXCEPTION_FILTERS`]).
    pub fn by_id(&mut self, id: &str) -> Option<&mut Filter> {
        match id {
            "trap" => Some(&mut self.trap),
            "overrun" => Some(&mut self.overrun),
            "abend" => Some(&mut self.abend),
            "waypoint" => Some(&mut self.waypoint),
            "surfacing" => Some(&mut self.surfacing),
            _ => None,
        }
    }
}

impl Default for ExceptionFilters {
    /// The filters on by default in [`EXCEPTION_FILTERS`].
    fn default() -> Self {
        let mut filters = ExceptionFilters::off();
        for (id, _, _, on) in EXCEPTION_FILTERS {
            if let Some(filter) = filters.by_id(id) {
                filter.enabled = on;
            }
        }
        filters
    }
}

/// A change the user made to a paused world, replayed when history passes its clock.
#[derive(Clone, Debug)]
pub enum Edit {
    Register(usize, Number),
    Variable(String, Number),
    Element(String, i64, Number),
    Sensor(usize, f64),
    /// A `goto`: the script's next instruction.
    Pc(usize),
}

/// How much reverse history to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HistoryConfig {
    /// Snapshots kept at most; when full, every other one is dropped and the spacing
    /// doubles, so memory is bounded and replay stays proportional to the spacing.
    pub max_snapshots: usize,
    /// Initial spacing between snapshots, in cycles.
    pub interval: u64,
}

impl Default for HistoryConfig {
    fn default() -> Self {
        HistoryConfig {
            max_snapshots: 256,
            interval: 16,
        }
    }
}

struct History<T> {
    config: HistoryConfig,
    interval: u64,
    snapshots: BTreeMap<Clock, T>,
    journal: Vec<(Clock, Edit)>,
}

pub struct Debugger<T: Target> {
    pub target: T,
    pub info: DebugInfo,
    clock: Clock,
    /// The clock the run started at (the entry point), the floor of reverse execution.
    origin: Clock,
    pub line_breakpoints: Vec<LineBreakpoint>,
    pub cycle_breakpoints: Vec<CycleBreakpoint>,
    pub data_breakpoints: Vec<DataBreakpoint>,
    pub instruction_breakpoints: Vec<InstructionBreakpoint>,
    pub filters: ExceptionFilters,
    /// Run the script's share of a cycle on the fused machine when no stop is possible
    /// inside it (on by default; off steps every instruction, the reference behaviour).
    pub fast_shares: bool,
    /// Values of the watched sensors at the last boundary (or stop).
    baseline: HashMap<usize, f64>,
    history: Option<History<T>>,
    /// Where a fused run must stop (sorted): the pcs where a breakpoint can stop. For
    /// each pc, how many instructions can run fused from it before landing on one.
    stop_pcs: Vec<usize>,
    steps_to_stop: Vec<u64>,
    /// Fused runs so far (for tests and benchmarks: proof the fast path ran).
    fused_runs: u64,
    outputs: Vec<Output>,
    pause_requested: bool,
    ended: Option<String>,
    pub trap: Option<String>,
}

/// What happened in a step that an exception filter may stop on.
enum Happening {
    Abend(String),
    Milestone(Milestone, String),
}

enum Check {
    /// A real run: hit counts advance, logpoints print.
    Live,
    /// A replay looking for breakpoint hits (reverse continue): no side effects.
    Probe,
}

impl<T: Target> Debugger<T> {
    pub fn new(target: T, info: DebugInfo, history: Option<HistoryConfig>) -> Debugger<T> {
        let clock = Clock {
            cycle: target.cycle(),
            steps: 0,
        };
        let history = history.map(|config| {
            let mut snapshots = BTreeMap::new();
            snapshots.insert(clock, target.clone());
            History {
                config,
                interval: config.interval.max(1),
                snapshots,
                journal: Vec::new(),
            }
        });
        let mut debugger = Debugger {
            target,
            info,
            clock,
            origin: clock,
            line_breakpoints: Vec::new(),
            cycle_breakpoints: Vec::new(),
            data_breakpoints: Vec::new(),
            instruction_breakpoints: Vec::new(),
            filters: ExceptionFilters::default(),
            fast_shares: true,
            baseline: HashMap::new(),
            history,
            stop_pcs: Vec::new(),
            steps_to_stop: Vec::new(),
            fused_runs: 0,
            outputs: Vec::new(),
            pause_requested: false,
            ended: None,
            trap: None,
        };
        // What the world said while loading (setup warnings) is shown first.
        debugger.collect_notices();
        debugger
    }

    pub fn clock(&self) -> Clock {
        self.clock
    }

    pub fn has_history(&self) -> bool {
        self.history.is_some()
    }

    pub fn snapshot_count(&self) -> usize {
        self.history
            .as_ref()
            .map_or(0, |history| history.snapshots.len())
    }

    /// How many times the script ran on the fused machine (the fast path) so far.
    pub fn fused_run_count(&self) -> u64 {
        self.fused_runs
    }

    pub fn take_outputs(&mut self) -> Vec<Output> {
        std::mem::take(&mut self.outputs)
    }

    pub fn request_pause(&mut self) {
        self.pause_requested = true;
    }

    pub fn ended(&self) -> Option<&str> {
        self.ended.as_deref()
    }

    /// Re-reads the watched sensors so a data breakpoint fires on the next change only.
    pub fn reset_baseline(&mut self) {
        self.baseline = self
            .data_breakpoints
            .iter()
            .map(|breakpoint| (breakpoint.at, self.target.sensor(breakpoint.at)))
            .collect();
    }

    /// Checks the breakpoints at the current position, for the start of a run that
    /// did not stop on entry (a breakpoint on the very first statement must hit).
    pub fn check_start(&mut self) -> Option<Stop> {
        // The run starts at a cycle boundary: check it as one (cycle breakpoints too).
        let event = if self.clock.steps == 0 {
            StepEvent::CycleBegan
        } else {
            StepEvent::Executed
        };
        match self.after_step(&event, RunMode::Continue, self.clock, Check::Live) {
            Some(Progress::Stopped(stop)) => Some(stop),
            _ => None,
        }
    }

    /// Runs forward for at most `slice.steps` steps, and begins none after
    /// `slice.until`: a step can be slow (a long condition on every line), so a count
    /// alone let one slice run for half a minute with `pause` and `disconnect` unread.
    pub fn run(&mut self, mode: RunMode, start: Clock, slice: Slice) -> Progress {
        if let Some(summary) = &self.ended {
            return Progress::Ended {
                summary: summary.clone(),
            };
        }
        self.refresh_stops();
        let mut steps = 0;
        let mut iterations = 0u32;
        while steps < slice.steps {
            // The clock is read every 16 steps: a step is fast unless a condition or a
            // watch is slow, and reading it costs about as much as a fused step.
            if let Some(until) = slice.until {
                iterations = iterations.wrapping_add(1);
                if iterations.is_multiple_of(16) && Instant::now() >= until {
                    break;
                }
            }
            let before = self.clock;
            let (event, fused_notices) = self.advance(mode);
            steps += if self.clock.steps > before.steps {
                self.clock.steps - before.steps
            } else {
                1
            };
            if let Err(message) = self.replay_edits() {
                self.outputs.push(Output {
                    category: Category::Error,
                    text: format!("could not replay an earlier edit: {message}\n"),
                    line: None,
                });
            }
            let happenings = match fused_notices {
                Some(notices) => self.report_notices(notices),
                None => self.collect_notices(),
            };
            if let Some(stop) = self.filtered_stop(happenings) {
                return Progress::Stopped(stop);
            }
            if let Some(progress) = self.after_step(&event, mode, start, Check::Live) {
                if let Progress::Stopped(_) = progress {
                    self.pause_requested = false;
                }
                return progress;
            }
        }
        Progress::Running
    }

    /// Re-applies the user's edits recorded at the present clock: running forward over
    /// a stretch of history that was edited reproduces the edit.
    fn replay_edits(&mut self) -> DebugResult<()> {
        let Some(history) = &self.history else {
            return Ok(());
        };
        if history
            .journal
            .last()
            .is_none_or(|(clock, _)| *clock < self.clock)
        {
            return Ok(());
        }
        let clock = self.clock;
        let edits: Vec<Edit> = history
            .journal
            .iter()
            .filter(|(at, _)| *at == clock)
            .map(|(_, edit)| edit.clone())
            .collect();
        for edit in &edits {
            apply(&mut self.target, edit)?;
        }
        Ok(())
    }

    /// Recomputes where breakpoints can stop when the breakpoints changed.
    fn refresh_stops(&mut self) {
        let mut stops: Vec<usize> = self
            .instruction_breakpoints
            .iter()
            .map(|breakpoint| breakpoint.at.0)
            .collect();
        if !self.line_breakpoints.is_empty() {
            for pc in 0..self.info.instruction_count() {
                if !self.info.is_line_entry(pc) {
                    continue;
                }
                let line = self.info.line(pc);
                if self
                    .line_breakpoints
                    .iter()
                    .any(|breakpoint| Some(breakpoint.at) == line)
                {
                    stops.push(pc);
                }
            }
        }
        stops.sort_unstable();
        stops.dedup();
        if stops != self.stop_pcs || self.steps_to_stop.len() != self.info.instruction_count() {
            self.steps_to_stop = self.info.steps_to_stop(&stops);
            self.stop_pcs = stops;
        }
    }

    /// How many instructions can run fused now with the same outcome as single steps
    /// (`u64::MAX`: the rest of the share), or `None` to step: part way through a share,
    /// not a step that stops after one statement, no recorded edit left to replay in this
    /// cycle, and no more instructions than it takes to land on a breakpoint. Cycle and
    /// data breakpoints are checked at cycle boundaries only.
    fn fusable(&self, mode: RunMode) -> Option<u64> {
        if matches!(mode, RunMode::StepIn { .. }) {
            return None;
        }
        let limit = self.replay_fusable()?;
        let to_stop = self.steps_to_stop.get(self.target.pc()).copied()?;
        Some(limit.min(to_stop)).filter(|steps| *steps > 1)
    }

    /// What any run needs to go fused: the switch on, the control flow known, part way
    /// through a share, and no edit to replay later in it.
    fn replay_fusable(&self) -> Option<u64> {
        let fusable = self.fast_shares
            && self.info.knows_flow()
            && self.target.phase() == Phase::InScript
            && !self.edits_ahead_in_cycle();
        fusable.then_some(u64::MAX)
    }

    /// True when the journal holds an edit later in the present cycle.
    fn edits_ahead_in_cycle(&self) -> bool {
        let Some(history) = &self.history else {
            return false;
        };
        let clock = self.clock;
        history.journal.last().is_some_and(|(at, _)| *at > clock)
            && history
                .journal
                .iter()
                .any(|(at, _)| at.cycle == clock.cycle && at.steps > clock.steps)
    }

    /// One move of a live run: instructions up to the next possible stop run fused
    /// when `fusable` allows, else one step. A fused run returns the notices it produced
    /// (already taken).
    fn advance(&mut self, mode: RunMode) -> (StepEvent, Option<Vec<Notice>>) {
        if let Some(limit) = self.fusable(mode) {
            if let Some((event, steps)) = self.target.run_share(limit) {
                self.clock.steps += steps;
                self.fused_runs += 1;
                return (event, Some(self.target.take_notices()));
            }
        }
        (self.step_world(), None)
    }

    /// One move of a replay that reports nothing (`travel_to`, reverse continue): fused
    /// when `limit` (the instructions it may run) and the present allow.
    fn advance_quietly(&mut self, limit: Option<u64>) -> StepEvent {
        let limit = limit
            .zip(self.replay_fusable())
            .map(|(a, b)| a.min(b))
            .filter(|steps| *steps > 1);
        if let Some(limit) = limit {
            if let Some((event, steps)) = self.target.run_share(limit) {
                self.clock.steps += steps;
                self.fused_runs += 1;
                return event;
            }
        }
        self.step_world()
    }

    fn step_world(&mut self) -> StepEvent {
        let event = self.target.step();
        if event == StepEvent::CycleBegan {
            self.clock = Clock {
                cycle: self.target.cycle(),
                steps: 0,
            };
            self.take_snapshot();
        } else {
            self.clock.steps += 1;
        }
        event
    }

    /// Turns the world's notices into output; returns what the exception filters may
    /// stop on (an abend, a milestone of the journey).
    fn collect_notices(&mut self) -> Vec<Happening> {
        let notices = self.target.take_notices();
        self.report_notices(notices)
    }

    /// Turns notices into output, a printed line pointing at the line of its `print`.
    fn report_notices(&mut self, notices: Vec<Notice>) -> Vec<Happening> {
        let mut happenings = Vec::new();
        for notice in notices {
            // Only what the script printed points at a source line.
            let (category, text, line) = match notice {
                Notice::Print { text, pc } => (Category::Script, text, self.info.line(pc)),
                Notice::Behavior(text) => (Category::Note, format!("behavior: {text}"), None),
                Notice::Warning(text) => (Category::Important, text, None),
                Notice::Abend(text) => {
                    let shown = format!("abend: {text}");
                    happenings.push(Happening::Abend(text));
                    (Category::Important, shown, None)
                }
                Notice::Milestone(milestone, text) => {
                    let shown = format!("navigation: {text}");
                    happenings.push(Happening::Milestone(milestone, text));
                    (Category::Note, shown, None)
                }
            };
            self.outputs.push(Output {
                category,
                text: format!("{text}\n"),
                line,
            });
        }
        happenings
    }

    /// The first of `happenings` whose exception filter is on and whose condition
    /// holds, as a stop.
    fn filtered_stop(&mut self, happenings: Vec<Happening>) -> Option<Stop> {
        for happening in happenings {
            let (filter, reason, description, text) = match happening {
                Happening::Abend(text) => (
                    self.filters.abend.clone(),
                    StopReason::Exception,
                    "Paused on abend".to_string(),
                    text,
                ),
                Happening::Milestone(Milestone::WaypointReached, text) => (
                    self.filters.waypoint.clone(),
                    StopReason::Waypoint,
                    format!("Paused: {text}"),
                    text,
                ),
                Happening::Milestone(Milestone::Surfaced, text) => (
                    self.filters.surfacing.clone(),
                    StopReason::Surfacing,
                    format!("Paused: {text}"),
                    text,
                ),
            };
            if self.filter_stops(&filter, &Check::Live) {
                return Some(Stop {
                    reason,
                    description,
                    text: Some(text),
                    hit_breakpoint_ids: Vec::new(),
                });
            }
        }
        None
    }

    /// The pc to show: the next instruction, except after the script's share when
    /// it is the `yield` just executed (a trap leaves pc on the trapping instruction).
    pub fn shown_pc(&self) -> usize {
        let pc = self.target.pc();
        if self.target.phase() == Phase::ScriptDone && self.target.script_alive() {
            pc.saturating_sub(1)
        } else {
            pc
        }
    }

    pub fn current_line(&self) -> Option<u32> {
        self.info
            .line(self.shown_pc())
            .or_else(|| self.info.line(self.target.pc()))
    }

    /// Decides whether the run stops after one step: on a trap its filter stops on,
    /// at the mission's end, at a cycle boundary (a pause, a cycle or data
    /// breakpoint, the end of a `next`), on an instruction or line breakpoint where
    /// the script runs next, or where the step mode ends.
    fn after_step(
        &mut self,
        event: &StepEvent,
        mode: RunMode,
        start: Clock,
        check: Check,
    ) -> Option<Progress> {
        match event {
            StepEvent::Trapped { kind, message } => {
                return self.trapped(*kind, message, &check).map(Progress::Stopped);
            }
            StepEvent::MissionEnded { summary } => {
                self.ended = Some(summary.clone());
                return Some(Progress::Ended {
                    summary: summary.clone(),
                });
            }
            _ => {}
        }
        if *event == StepEvent::CycleBegan {
            if let Some(stop) = self.at_boundary(mode, start, &check) {
                return Some(Progress::Stopped(stop));
            }
        }
        let script_can_run = matches!(self.target.phase(), Phase::Boundary | Phase::InScript)
            && self.target.script_alive();
        if script_can_run {
            if let Some(stop) = self.script_breakpoints(&check) {
                return Some(Progress::Stopped(stop));
            }
        }
        self.step_ends(event, mode, script_can_run)
            .map(Progress::Stopped)
    }

    /// A trap: reported (on a live run), and a stop when its filter is on and its
    /// condition holds.
    fn trapped(&mut self, kind: TrapKind, message: &str, check: &Check) -> Option<Stop> {
        let line = self.info.line(self.target.pc());
        let where_ = line
            .map(|line| format!(" at line {line}"))
            .unwrap_or_default();
        let text = format!("{message}{where_} (cycle {})", self.clock.cycle);
        self.trap = Some(text.clone());
        if let Check::Live = check {
            self.outputs.push(Output {
                category: Category::Error,
                text: format!("script trap: {text}\n"),
                line,
            });
        }
        let (filter, name) = match kind {
            TrapKind::CycleOverrun => (self.filters.overrun.clone(), "overrun"),
            TrapKind::Runtime => (self.filters.trap.clone(), "trap"),
        };
        if !self.filter_stops(&filter, check) {
            return None;
        }
        Some(Stop {
            reason: StopReason::Exception,
            description: format!("Paused on {name}: {message}"),
            text: Some(text),
            hit_breakpoint_ids: Vec::new(),
        })
    }

    /// At a cycle boundary: a pause asked for, a cycle breakpoint, a watched sensor
    /// that changed (the baseline moves on), the end of a `next`.
    fn at_boundary(&mut self, mode: RunMode, start: Clock, check: &Check) -> Option<Stop> {
        if let Check::Live = check {
            if self.pause_requested {
                return Some(stopped_body(
                    StopReason::Pause,
                    "Paused at the cycle boundary".into(),
                ));
            }
        }
        let cycle = self.clock.cycle;
        let hit = self.hits(
            check,
            |debugger| &mut debugger.cycle_breakpoints,
            |_, at| match at {
                CycleBreakpointKind::At(at) => cycle == at,
                CycleBreakpointKind::Every(every) => every > 0 && cycle.is_multiple_of(every),
            },
        );
        breakpoint_stop(hit, StopReason::CycleBreakpoint, || {
            format!("Paused at cycle {cycle}")
        })
        .or_else(|| self.data_changes(check))
        .or_else(|| {
            (mode == RunMode::Next && cycle > start.cycle)
                .then(|| stopped_body(StopReason::Step, format!("Cycle {cycle}")))
        })
    }

    /// The data breakpoints whose sensor changed since the baseline, which then
    /// takes the sensors' values now.
    fn data_changes(&mut self, check: &Check) -> Option<Stop> {
        let changed_from = |debugger: &Self, sensor: usize| {
            let before = debugger.baseline.get(&sensor).copied()?;
            let value = debugger.target.sensor(sensor);
            (before.to_bits() != value.to_bits()).then_some(before)
        };
        let hit = self.hits(
            check,
            |debugger| &mut debugger.data_breakpoints,
            |debugger, sensor| changed_from(debugger, sensor).is_some(),
        );
        let changed: Vec<String> = self
            .data_breakpoints
            .iter()
            .filter(|breakpoint| hit.contains(&breakpoint.id))
            .filter_map(|breakpoint| {
                let before = changed_from(self, breakpoint.at)?;
                let name = self.target.sensor_name(breakpoint.at).unwrap_or("?");
                let value = self.target.sensor(breakpoint.at);
                Some(format!("{name}: {before:?} → {value:?}"))
            })
            .collect();
        for breakpoint in &self.data_breakpoints {
            self.baseline
                .insert(breakpoint.at, self.target.sensor(breakpoint.at));
        }
        if hit.is_empty() {
            return None;
        }
        let text = changed.join(", ");
        Some(Stop {
            reason: StopReason::DataBreakpoint,
            description: format!("Paused at cycle {}: {text}", self.clock.cycle),
            text: Some(text),
            hit_breakpoint_ids: hit,
        })
    }

    /// An instruction breakpoint at the next pc, or a line breakpoint where the next
    /// pc enters its line.
    fn script_breakpoints(&mut self, check: &Check) -> Option<Stop> {
        let pc = self.target.pc();
        let hit = self.hits(
            check,
            |debugger| &mut debugger.instruction_breakpoints,
            |_, at| at == Pc(pc),
        );
        breakpoint_stop(hit, StopReason::InstructionBreakpoint, || {
            format!("Paused at instruction {pc}")
        })
        .or_else(|| self.line_breakpoint(check, pc))
    }

    /// A line breakpoint where `pc` enters its line.
    fn line_breakpoint(&mut self, check: &Check, pc: usize) -> Option<Stop> {
        if !self.info.is_line_entry(pc) {
            return None;
        }
        let line = self.info.line(pc);
        let hit = self.hits(
            check,
            |debugger| &mut debugger.line_breakpoints,
            |_, at| Some(at) == line,
        );
        breakpoint_stop(hit, StopReason::Breakpoint, || {
            format!("Paused on line {}", line.unwrap_or(0))
        })
    }

    /// Where the step mode ends: after one instruction, at the next statement or
    /// boundary, at the end of the script's share.
    fn step_ends(&self, event: &StepEvent, mode: RunMode, script_can_run: bool) -> Option<Stop> {
        match mode {
            RunMode::StepIn { instruction: true } => Some(stopped_body(
                StopReason::Step,
                "Stepped one instruction".into(),
            )),
            RunMode::StepIn { instruction: false } => {
                let at_statement = script_can_run && self.info.is_statement_start(self.target.pc());
                (at_statement || *event == StepEvent::CycleBegan)
                    .then(|| stopped_body(StopReason::Step, "Stepped one statement".into()))
            }
            RunMode::StepOut => {
                matches!(event, StepEvent::Yielded | StepEvent::Halted).then(|| {
                    stopped_body(
                        StopReason::Step,
                        format!("End of the script's share of cycle {}", self.clock.cycle),
                    )
                })
            }
            _ => None,
        }
    }

    /// The ids of the breakpoints in `list` whose place `matches` and that pass their
    /// condition and hit count. A logpoint among them prints its message instead (on a
    /// live run; a probe skips it).
    fn hits<At: Copy + 'static>(
        &mut self,
        check: &Check,
        list: fn(&mut Self) -> &mut Vec<Breakpoint<At>>,
        matches: impl Fn(&Self, At) -> bool,
    ) -> Vec<i64> {
        let mut hit = Vec::new();
        for index in 0..list(self).len() {
            let breakpoint = &list(self)[index];
            let at = breakpoint.at;
            if !matches(self, at) {
                continue;
            }
            let breakpoint = &list(self)[index];
            let (id, condition, hit_condition, log_message) = (
                breakpoint.id,
                breakpoint.condition.clone(),
                breakpoint.hit_condition,
                breakpoint.log_message.clone(),
            );
            if log_message.is_some() && matches!(check, Check::Probe) {
                continue;
            }
            if self.passes(condition.as_deref(), hit_condition, check, |debugger| {
                &mut list(debugger)[index].hits
            }) {
                match log_message {
                    Some(message) => {
                        let text = self.interpolate(&message);
                        let line = self.current_line();
                        self.outputs.push(Output {
                            category: Category::Note,
                            text: format!("{text}\n"),
                            line,
                        });
                    }
                    None => hit.push(id),
                }
            }
        }
        hit
    }

    /// Checks a condition and a hit count; on a live run a true condition counts a hit.
    fn passes(
        &mut self,
        condition: Option<&str>,
        hit_condition: Option<HitCondition>,
        check: &Check,
        hits: impl FnOnce(&mut Self) -> &mut u64,
    ) -> bool {
        match self.condition_holds("breakpoint", condition, check) {
            Some(true) => {}
            Some(false) => return false,
            // A broken condition stops, whatever the hit count.
            None => return true,
        }
        match check {
            Check::Probe => true,
            Check::Live => {
                let counter = hits(self);
                *counter += 1;
                let count = *counter;
                hit_condition.is_none_or(|hit_condition| hit_condition.holds(count))
            }
        }
    }

    /// Whether an exception filter stops the run here: it is on, and its condition holds
    /// or cannot be evaluated.
    fn filter_stops(&mut self, filter: &Filter, check: &Check) -> bool {
        filter.enabled
            && self.condition_holds("exception", filter.condition.as_deref(), check) != Some(false)
    }

    /// Whether a breakpoint's or an exception filter's (`what`) condition holds now (no
    /// condition: it does); `None` when it cannot be evaluated, which stops, as in other
    /// debuggers, and says why on a live run.
    fn condition_holds(
        &mut self,
        what: &str,
        condition: Option<&str>,
        check: &Check,
    ) -> Option<bool> {
        let Some(condition) = condition.filter(|text| !text.trim().is_empty()) else {
            return Some(true);
        };
        match self.evaluate(condition) {
            Ok(value) => Some(value.is_true()),
            Err(message) => {
                if let Check::Live = check {
                    self.outputs.push(Output {
                        category: Category::Error,
                        text: format!("{what} condition `{condition}`: {message}\n"),
                        line: None,
                    });
                }
                None
            }
        }
    }

    /// Replaces `{expression}` in a logpoint message by its value.
    pub fn interpolate(&self, message: &str) -> String {
        let mut out = String::new();
        let mut rest = message;
        while let Some(open) = rest.find('{') {
            out.push_str(&rest[..open]);
            let Some(close) = rest[open..].find('}') else {
                out.push_str(&rest[open..]);
                return out;
            };
            let expression = &rest[open + 1..open + close];
            match self.watch(expression) {
                Ok(Watched::Value(value)) => out.push_str(&value.to_string()),
                Ok(Watched::Array { shown, .. }) => out.push_str(&shown),
                Err(message) => out.push_str(&format!("<{message}>")),
            }
            rest = &rest[open + close + 1..];
        }
        out.push_str(rest);
        out
    }

    /// The value of a GBASIC expression on the paused world.
    pub fn evaluate(&self, expression: &str) -> DebugResult<Number> {
        expr::evaluate(expression, &self.info.scope, &self.target)
    }

    /// As [`Debugger::evaluate`], and a whole array named alone is shown.
    pub fn watch(&self, expression: &str) -> DebugResult<Watched> {
        expr::watch(expression, &self.info.scope, &self.target)
    }

    /// Why `expression` can never be evaluated (a syntax, name or type error).
    pub fn check_expression(&self, expression: &str) -> DebugResult<()> {
        expr::check(expression, &self.info.scope, &self.target)
    }

    // -----------------------------------------------------------------------------------
    // Edits

    /// Applies a user edit now and records it so replays reproduce it. An edit in the
    /// past rewrites the future: later journal entries and snapshots are dropped.
    pub fn edit(&mut self, edit: Edit) -> DebugResult<()> {
        apply(&mut self.target, &edit)?;
        let clock = self.clock;
        if let Some(history) = &mut self.history {
            history.journal.retain(|(at, _)| *at <= clock);
            history.journal.push((clock, edit));
            let later: Vec<Clock> = history
                .snapshots
                .range(clock..)
                .map(|(at, _)| *at)
                .filter(|at| *at > clock)
                .collect();
            for at in later {
                history.snapshots.remove(&at);
            }
        }
        self.reset_baseline();
        Ok(())
    }

    // -----------------------------------------------------------------------------------
    // History

    fn take_snapshot(&mut self) {
        let clock = self.clock;
        let Some(history) = &mut self.history else {
            return;
        };
        if !clock.cycle.is_multiple_of(history.interval) || history.snapshots.contains_key(&clock) {
            return;
        }
        history.snapshots.insert(clock, self.target.clone());
        if history.snapshots.len() > history.config.max_snapshots.max(2) {
            history.interval *= 2;
            let interval = history.interval;
            let origin = self.origin;
            history.snapshots.retain(|at, _| {
                *at == origin || (at.steps == 0 && at.cycle.is_multiple_of(interval))
            });
        }
    }

    /// Moves the world to `target` (≤ the present): restore, then replay with the
    /// journal. No breakpoint fires and nothing is printed during the replay.
    fn travel_to(&mut self, target: Clock) -> DebugResult<()> {
        let Some(history) = &self.history else {
            return Err(DebugError::NoHistory);
        };
        let Some((&at, snapshot)) = history.snapshots.range(..=target).next_back() else {
            return Err(DebugError::BeforeHistory);
        };
        let journal: Vec<(Clock, Edit)> = history
            .journal
            .iter()
            .filter(|(clock, _)| *clock >= at && *clock <= target)
            .cloned()
            .collect();
        self.target = snapshot.clone();
        self.clock = at;
        self.trap = None;
        self.ended = None;
        let mut edits = journal.into_iter().peekable();
        loop {
            while let Some((_, edit)) = edits.next_if(|(clock, _)| *clock == self.clock) {
                apply(&mut self.target, &edit)?;
            }
            if self.clock >= target {
                break;
            }
            // The share runs fused when it ends before the target and no edit falls in it.
            let fuse = target.cycle > self.clock.cycle
                && edits
                    .peek()
                    .is_none_or(|(clock, _)| clock.cycle > self.clock.cycle);
            let event = self.advance_quietly(fuse.then_some(u64::MAX));
            if let StepEvent::Trapped { message, .. } = &event {
                self.trap = Some(message.clone());
            }
            if let StepEvent::MissionEnded { summary, .. } = &event {
                self.ended = Some(summary.clone());
                break;
            }
        }
        self.target.take_notices();
        self.reset_baseline();
        Ok(())
    }

    /// Back to the previous cycle boundary (undoes one `next`).
    pub fn step_back(&mut self) -> DebugResult<Stop> {
        if self.history.is_none() {
            return Err(DebugError::NoHistory);
        }
        let target = if self.clock.steps == 0 {
            if self.clock <= self.origin {
                return Ok(stopped_body(
                    StopReason::Step,
                    "Already at the start of the run".into(),
                ));
            }
            Clock {
                cycle: self.clock.cycle - 1,
                steps: 0,
            }
        } else {
            Clock {
                cycle: self.clock.cycle,
                steps: 0,
            }
        };
        let target = target.max(self.origin);
        self.travel_to(target)?;
        Ok(stopped_body(
            StopReason::Step,
            format!("Back to cycle {}", self.clock.cycle),
        ))
    }

    /// Back to the most recent breakpoint hit before now, or the start of the history.
    pub fn reverse_continue(&mut self) -> DebugResult<Stop> {
        self.reverse_continue_unless(&|| false)
    }

    /// `reverse_continue`, which gives up when `cancelled()` turns true (it is asked
    /// between steps): it then stops at the earliest point from which everything up to
    /// where it started was checked for breakpoints (a segment's end, a snapshot).
    pub fn reverse_continue_unless(&mut self, cancelled: &dyn Fn() -> bool) -> DebugResult<Stop> {
        let present = self.clock;
        self.refresh_stops();
        let Some(history) = &self.history else {
            return Err(DebugError::NoHistory);
        };
        let starts: Vec<Clock> = history
            .snapshots
            .range(..present)
            .map(|(at, _)| *at)
            .collect();
        let journal: Vec<(Clock, Edit)> = history.journal.clone();
        let mut segment_end = present;
        for &segment_start in starts.iter().rev() {
            self.travel_to(segment_start)?;
            let mut found: Option<(Clock, Stop)> = None;
            // Edits at the segment start were applied by `travel_to`; later ones here.
            let mut edits = journal
                .iter()
                .filter(|(clock, _)| *clock > segment_start && *clock <= segment_end)
                .peekable();
            while self.clock < segment_end {
                if cancelled() {
                    self.travel_to(segment_end)?;
                    self.outputs.clear();
                    return Ok(stopped_body(
                        StopReason::Pause,
                        format!("Reverse run cancelled at cycle {}", self.clock.cycle),
                    ));
                }
                // Breakpoints count here: no further than the next place one can stop.
                let limit = (segment_end.cycle > self.clock.cycle)
                    .then(|| self.fusable(RunMode::Continue))
                    .flatten();
                let event = self.advance_quietly(limit);
                if let StepEvent::MissionEnded { .. } = event {
                    break;
                }
                if let Some(Progress::Stopped(stop)) =
                    self.after_step(&event, RunMode::Continue, segment_start, Check::Probe)
                {
                    // The segment's end is the next segment's start, which that
                    // segment's replay never checks: it belongs here.
                    if self.clock < present && self.clock <= segment_end {
                        found = Some((self.clock, stop));
                    }
                }
                // Edits take effect where they were made, after the stop there.
                while let Some((_, edit)) = edits.next_if(|(clock, _)| *clock == self.clock) {
                    apply(&mut self.target, edit)?;
                }
                if matches!(event, StepEvent::Trapped { .. }) {
                    self.trap = None;
                }
            }
            if let Some((clock, stop)) = found {
                self.travel_to(clock)?;
                self.outputs.clear();
                return Ok(stop);
            }
            segment_end = segment_start;
        }
        let origin = self.origin;
        self.travel_to(origin)?;
        self.outputs.clear();
        Ok(stopped_body(
            StopReason::Entry,
            "Reached the start of the history".into(),
        ))
    }
}

fn stopped_body(reason: StopReason, description: String) -> Stop {
    Stop {
        reason,
        description,
        text: None,
        hit_breakpoint_ids: Vec::new(),
    }
}

/// A stop at the breakpoints `hit` (their ids, for the client to mark); `None` when
/// none was hit (the description is then not written).
fn breakpoint_stop(
    hit: Vec<i64>,
    reason: StopReason,
    description: impl FnOnce() -> String,
) -> Option<Stop> {
    (!hit.is_empty()).then(|| Stop {
        hit_breakpoint_ids: hit,
        ..stopped_body(reason, description())
    })
}

fn apply<T: Target>(target: &mut T, edit: &Edit) -> DebugResult<()> {
    match edit {
        Edit::Register(index, value) => target.set_register(*index, *value),
        Edit::Variable(name, value) => target.set_variable(name, *value),
        Edit::Element(name, index, value) => target.set_element(name, *index, *value),
        Edit::Sensor(index, value) => target.set_sensor(*index, *value),
        Edit::Pc(pc) => target.set_pc(*pc),
    }
}
