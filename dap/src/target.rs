//! What the debugger needs from the thing it debugs: a deterministic, cloneable world
//! (script + simulated vehicle) that advances one small step at a time.
//!
//! The debugger logic (breakpoints, stepping, history) is written against this trait so
//! that it never depends on how the simulator phases a cycle; `world::World` implements
//! it once, for the simulated and the replayed world alike.

use gloc_engine::program::Value as Number;

use crate::error::DebugResult;

/// Where a run is inside a control cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The sensors are updated and the script has not run yet in this cycle.
    Boundary,
    /// The script is part way through its share of the cycle.
    InScript,
    /// The script yielded (or is dead); the vehicle has not moved yet.
    ScriptDone,
    /// The mission is over: nothing more can run.
    Ended,
}

/// What one `Target::step` did.
#[derive(Clone, Debug, PartialEq)]
pub enum StepEvent {
    /// One instruction ran; the script goes on in this cycle.
    Executed,
    /// The script yielded: its share of the cycle is done.
    Yielded,
    /// The script halted for good; the vehicle flies on.
    Halted,
    /// The script stopped on a runtime error (it stays stopped; the vehicle flies on).
    Trapped { kind: TrapKind, message: String },
    /// The vehicle finished the cycle and the next one began (the run is at a boundary).
    CycleBegan,
    /// The mission ended (completed, aborted and surfaced, or out of cycles); `summary`
    /// says how.
    MissionEnded { summary: String },
}

/// Runtime failures the user can choose to stop on (DAP exception filters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrapKind {
    /// The script used up its per-cycle instruction budget.
    CycleOverrun,
    /// Any other runtime trap (division by zero, bad jump, ...).
    Runtime,
}

/// Something the world wants the user to see, in order.
#[derive(Clone, Debug, PartialEq)]
pub enum Notice {
    /// A line the script printed, and the pc of the instruction that printed it.
    Print { text: String, pc: usize },
    /// A setup warning (a mission setting the sensor list lacks, ...).
    Warning(String),
    /// The set of active behaviors changed (a description of the change).
    Behavior(String),
    /// The mission aborted (abend): the reason. The glider surfaces; the run goes on
    /// until it is up.
    Abend(String),
    /// A point of the journey a run can stop at (exception filters `waypoint` and
    /// `surfacing`), and what happened.
    Milestone(Milestone, String),
}

/// Points of the journey the user can choose to stop at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Milestone {
    /// A goto behavior reached its waypoint (judged on the dead-reckoned position, as
    /// the glider judges it): `x_hit_a_waypoint`.
    WaypointReached,
    /// The glider came up: `x_dr_state` went from 1 (underwater) to 2 (surfaced).
    Surfaced,
}

/// A named value in one of the scopes the debugger shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Named {
    pub name: String,
    pub value: String,
    pub ty: &'static str,
    /// For an array: its number of elements (shown as children `name(i)`).
    pub length: Option<usize>,
    /// For an array: the type of its elements (the children's type).
    pub element: Option<gloc_compiler::typed::Ty>,
    /// The GBASIC expression whose value this is (DAP `evaluateName`); `None` for what
    /// no expression names (the phase, the active behaviors, the energy).
    pub evaluate_name: Option<String>,
}

impl Named {
    /// A value the Variables view shows that no expression names.
    pub fn plain(name: &str, value: String, ty: &'static str) -> Named {
        Named {
            name: name.to_string(),
            value,
            ty,
            length: None,
            element: None,
            evaluate_name: None,
        }
    }
}

pub trait Target: Clone {
    /// The current control cycle (the boundary opening it has been passed).
    fn cycle(&self) -> u64;
    fn phase(&self) -> Phase;
    /// The next instruction the script would run (after a trap: the one that trapped).
    fn pc(&self) -> usize;
    /// False once the script halted or trapped (the vehicle flies on).
    fn script_alive(&self) -> bool;
    /// Advances by one instruction or, when the script is done for this cycle, by the rest
    /// of the cycle up to the next boundary.
    fn step(&mut self) -> StepEvent;
    /// Runs at most `max_steps` instructions of the script's share of this cycle at full
    /// speed (the fused machine; `u64::MAX`: to the end of the share): the event the last
    /// of the single steps would have returned and how many steps they would have been.
    /// Only called part way through a share (`Phase::InScript`); `None` when the target
    /// cannot, and the debugger steps.
    fn run_share(&mut self, max_steps: u64) -> Option<(StepEvent, u64)> {
        let _ = max_steps;
        None
    }
    /// Takes what was printed or changed since the last call.
    fn take_notices(&mut self) -> Vec<Notice>;

    /// Moves the script's next instruction to `pc` (a `goto`); refused when the script
    /// halted or trapped, or `pc` is not an instruction.
    fn set_pc(&mut self, pc: usize) -> DebugResult<()>;

    fn registers(&self) -> Vec<Number>;
    fn set_register(&mut self, index: usize, value: Number) -> DebugResult<()>;
    /// Source-level variables (GBASIC names through the source map), in declaration order.
    fn variables(&self) -> Vec<Named>;
    fn variable(&self, name: &str) -> Option<Number>;
    fn set_variable(&mut self, name: &str, value: Number) -> DebugResult<()>;
    /// Element `index` of the GBASIC array `name`.
    fn element(&self, name: &str, index: i64) -> Option<Number>;
    fn set_element(&mut self, name: &str, index: i64, value: Number) -> DebugResult<()>;

    fn sensor_count(&self) -> usize;
    fn sensor_name(&self, index: usize) -> Option<&str>;
    fn sensor_index(&self, name: &str) -> Option<usize>;
    fn sensor(&self, index: usize) -> f64;
    fn set_sensor(&mut self, index: usize, value: f64) -> DebugResult<()>;
    /// The sensors the script loads or stores, in first-use order.
    fn touched_sensors(&self) -> Vec<usize>;
    /// Cycle, mission time, depth, pitch, active behaviors, energy.
    fn vehicle(&self) -> Vec<Named>;
    /// Position and navigation: latitude and longitude, mission coordinates, heading,
    /// the waypoint and the distance to it, the current estimate (and, simulated, the
    /// truth beside the dead-reckoned belief).
    fn navigation(&self) -> Vec<Named>;
}
