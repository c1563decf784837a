//! The behavior stack: each mission behavior's state machine and the actuator
//! commands it asks for.
//!
//! Behaviors are stepped **bottom-up** once per control cycle, as the paper
//! describes layered control: the lowest-priority behavior runs first and each
//! higher one may overwrite what the lower ones commanded, so for each actuator
//! the highest-priority behavior that commands it wins. A behavior's
//! `start_when` "idle" conditions look at what the behaviors below it have
//! commanded so far in this cycle.

pub use gloc_mission::behaviors::{ArgDef, BehaviorKind, KnownArgs};
use gloc_mission::mission::{BehaviorSpec, Mission};

use crate::flight::PitchControl;
use crate::navigation::{self, Lmc, Xy};

/// What a behavior is doing, as the glider numbers it in `cc_behavior_state`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BehaviorState {
    WaitingForActivation = 2,
    Active = 3,
    Complete = 4,
}

/// Why an `abend` aborted the mission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AbortReason {
    Overdepth,
    Overtime,
    Samedepth,
    Undervolts,
    /// The waypoint steered to is farther than `max_wpt_distance`.
    WptTooFar,
}

impl AbortReason {
    /// The glider's name for the abort (`MS_ABORT_OVERDEPTH`).
    pub fn glider_name(self) -> &'static str {
        match self {
            AbortReason::Overdepth => "MS_ABORT_OVERDEPTH",
            AbortReason::Overtime => "MS_ABORT_OVERTIME",
            AbortReason::Samedepth => "MS_ABORT_SAMEDEPTH",
            AbortReason::Undervolts => "MS_ABORT_UNDERVOLTS",
            AbortReason::WptTooFar => "MS_ABORT_WPT_TOOFAR",
        }
    }
}

/// Buoyancy (cc, > 0 goes up) and pitch (rad, > 0 nose up) commands, with
/// the index of the behavior that won each.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Commands {
    pub buoyancy: Option<(f64, usize)>,
    pub pitch: Option<(f64, usize)>,
    pub heading: Option<(f64, usize)>,
    /// How the winning pitch command is flown (`use_pitch` 1 or 3).
    pub pitch_control: PitchControl,
}

impl Commands {
    /// "Stack idle": neither the up/down actuator nor pitch is commanded (the
    /// simulator flies in the vertical plane, so heading is left out).
    pub fn stack_idle(&self) -> bool {
        self.buoyancy.is_none() || self.pitch.is_none()
    }

    fn command_vertical(&mut self, buoyancy: f64, pitch: f64, owner: usize) {
        self.command_vertical_with(buoyancy, pitch, PitchControl::Servo, owner);
    }

    fn command_vertical_with(
        &mut self,
        buoyancy: f64,
        pitch: f64,
        control: PitchControl,
        owner: usize,
    ) {
        self.buoyancy = Some((buoyancy, owner));
        self.pitch = Some((pitch, owner));
        self.pitch_control = control;
    }
}

/// What a behavior sees of the world while it steps.
pub struct World<'a> {
    /// Seconds since the mission started.
    pub time: f64,
    pub depth: f64,
    pub depth_rate: f64,
    pub altitude: f64,
    /// Battery voltage (V).
    pub battery_volts: f64,
    /// Mission time when the glider was last at the surface (its last "comms").
    pub last_surface_time: f64,
    /// Depth below which the glider counts as surfaced (`u_reqd_depth_at_surface`).
    pub surface_depth: f64,
    pub sensors: &'a mut [f64],
    pub hook_sensors: HookSensors,
    pub commands: &'a mut Commands,
    /// What the glider knows of its horizontal position, and what the goto
    /// behaviors report back (waypoint, distance, a waypoint hit this cycle).
    pub nav: &'a mut NavView,
}

/// The navigation as the behaviors see it: the glider's belief (dead-reckoned
/// position, believed current, mean speed), never the truth.
#[derive(Clone, Copy, Debug)]
pub struct NavView {
    pub lmc: Lmc,
    /// `m_x_lmc`, `m_y_lmc`.
    pub position: Xy,
    /// `m_water_vx/vy` when `u_use_current_correction` is 1, else zero.
    pub water: Xy,
    /// `m_avg_speed`.
    pub avg_speed: f64,
    /// The waypoint a goto behavior steers to (`c_wpt_x_lmc`, `c_wpt_y_lmc`).
    pub waypoint: Option<Xy>,
    /// `m_dist_to_wpt` (m; −1 before any waypoint).
    pub dist_to_wpt: f64,
    /// `x_hit_a_waypoint`: a waypoint was achieved this cycle.
    pub hit_waypoint: bool,
}

impl NavView {
    pub fn new(lmc: Lmc) -> NavView {
        NavView {
            lmc,
            position: Xy::ZERO,
            water: Xy::ZERO,
            avg_speed: 0.0,
            waypoint: None,
            dist_to_wpt: -1.0,
            hit_waypoint: false,
        }
    }

    /// Steers to `waypoint` for behavior `owner`: reports it and its distance,
    /// and commands the firmware's current-corrected heading.
    fn steer(&mut self, waypoint: Xy, owner: usize, commands: &mut Commands) -> f64 {
        let distance = self.position.distance(waypoint);
        self.waypoint = Some(waypoint);
        self.dist_to_wpt = distance;
        let heading = navigation::steer(self.position, waypoint, self.water, self.avg_speed);
        commands.heading = Some((heading, owner));
        distance
    }
}

/// Where the hook behavior's sensors sit in the active list (absent ones are `None`).
#[derive(Clone, Copy, Debug, Default)]
pub struct HookSensors {
    pub behs: Option<usize>,
    pub dive_depth: Option<usize>,
    pub climb_depth: Option<usize>,
    /// `sci_ruhp_heading`: the heading bit 32 steers to.
    pub heading: Option<usize>,
}

impl World<'_> {
    fn read(&self, index: Option<usize>) -> f64 {
        index
            .and_then(|index| self.sensors.get(index).copied())
            .unwrap_or(0.0)
    }
}

/// What a step asks of the mission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    Continue,
    Abort(AbortReason),
    /// A surface behavior with `end_action` 0 finished: the mission is over.
    MissionComplete,
}

/// Something a behavior did this cycle, for the debugger's output and the plot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BehaviorEvent {
    pub behavior: usize,
    pub kind: EventKind,
}

/// One behavior's turn in a cycle: its place in the stack (which the commands it
/// gives and the events it reports carry), the world it reads and commands, and
/// where its events go.
pub struct Turn<'t, 'a> {
    pub index: usize,
    pub world: &'t mut World<'a>,
    pub events: &'t mut Vec<BehaviorEvent>,
}

impl Turn<'_, '_> {
    /// Reports `kind` as this behavior's event.
    fn report(&mut self, kind: EventKind) {
        self.events.push(BehaviorEvent {
            behavior: self.index,
            kind,
        });
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    Started,
    Completed,
    /// A yo or the hook turned (depth at the turn).
    Inflection {
        depth: f64,
    },
    /// The hook read a `sci_ruhp_behs` that is no request (not a whole number from 0 to
    /// [`HOOK_MAX_FLAGS`]) and ignored it; reported once per run.
    IgnoredRequest {
        value: f64,
    },
}

/// One behavior of the running mission.
#[derive(Clone, Debug)]
pub struct Behavior {
    pub kind: BehaviorKind,
    /// `yo`, `surface`, … as written in the mission.
    pub name: String,
    pub state: BehaviorState,
    start_when: i64,
    stop_when: i64,
    when_secs: f64,
    when_wpt_dist: f64,
    end_action: i64,
    last_start: f64,
    last_end: f64,
    logic: Logic,
}

#[derive(Clone, Debug)]
enum Logic {
    Abend(Abend),
    Surface(Surface),
    Yo(Yo),
    Single(DiveClimb),
    PrepareToDive {
        wait_time: f64,
        gps_fix_time: f64,
        since: f64,
    },
    SetHeading {
        heading: Option<f64>,
    },
    Goto(Goto),
    Hook(Hook),
    /// The script: run by the simulation itself at this place.
    Script,
    /// Accepted, commands nothing (sensors_in, sample).
    Passive,
}

impl Behavior {
    /// Builds the runtime behavior from its mission spec. `param` dereferences
    /// b_arg values ≥ 1,000,000 to `u_mission_param_a…x`, as the glider does.
    pub fn from_spec(
        spec: &BehaviorSpec,
        param: &dyn Fn(f64) -> f64,
        gps_fix_time: f64,
    ) -> Behavior {
        let kind = spec.kind;
        let arg = |name: &str| param(spec.value(name).unwrap_or_else(|| kind.default_arg(name)));
        let logic = match kind {
            BehaviorKind::Abend => Logic::Abend(Abend {
                overdepth: arg("overdepth"),
                overdepth_sample_time: arg("overdepth_sample_time"),
                overtime: arg("overtime"),
                samedepth_for: arg("samedepth_for"),
                samedepth_sample_time: arg("samedepth_for_sample_time"),
                undervolts: arg("undervolts"),
                max_wpt_distance: arg("max_wpt_distance"),
                last_overdepth_check: f64::NEG_INFINITY,
                last_samedepth_sample: f64::NEG_INFINITY,
                samedepth_reference: f64::NAN,
                samedepth_since: 0.0,
            }),
            BehaviorKind::Surface => Logic::Surface(Surface {
                bpump_value: arg("c_bpump_value").abs(),
                pitch_value: servo_pitch(
                    arg("c_use_pitch"),
                    arg("c_pitch_value"),
                    Direction::Climb,
                ),
                wait: arg("gps_wait_time").max(0.0)
                    + if arg("end_action") as i64 == 1 {
                        arg("keystroke_wait_time").max(0.0)
                    } else {
                        0.0
                    },
                surfaced_at: None,
            }),
            BehaviorKind::Yo => Logic::Yo(Yo {
                dive: DiveClimb {
                    direction: Direction::Dive,
                    target_depth: arg("d_target_depth"),
                    target_altitude: arg("d_target_altitude"),
                    bpump_value: arg("d_bpump_value"),
                    pitch_value: pitch_for(
                        arg("d_use_pitch"),
                        arg("d_pitch_value"),
                        Direction::Dive,
                    ),
                    pitch_control: pitch_control(arg("d_use_pitch")),
                    hover_for: arg("d_stop_when_hover_for"),
                    hover_since: None,
                },
                climb: DiveClimb {
                    direction: Direction::Climb,
                    target_depth: arg("c_target_depth"),
                    target_altitude: arg("c_target_altitude"),
                    bpump_value: arg("c_bpump_value"),
                    pitch_value: pitch_for(
                        arg("c_use_pitch"),
                        arg("c_pitch_value"),
                        Direction::Climb,
                    ),
                    pitch_control: pitch_control(arg("c_use_pitch")),
                    hover_for: arg("c_stop_when_hover_for"),
                    hover_since: None,
                },
                start_diving: arg("start_diving") != 0.0,
                half_cycles_to_do: arg("num_half_cycles_to_do") as i64,
                diving: true,
                half_cycles_done: 0,
            }),
            BehaviorKind::DiveTo | BehaviorKind::ClimbTo => {
                let direction = if kind == BehaviorKind::DiveTo {
                    Direction::Dive
                } else {
                    Direction::Climb
                };
                Logic::Single(DiveClimb {
                    direction,
                    target_depth: arg("target_depth"),
                    target_altitude: arg("target_altitude"),
                    bpump_value: arg("bpump_value"),
                    pitch_value: pitch_for(arg("use_pitch"), arg("pitch_value"), direction),
                    pitch_control: pitch_control(arg("use_pitch")),
                    hover_for: arg("stop_when_hover_for"),
                    hover_since: None,
                })
            }
            BehaviorKind::PrepareToDive => Logic::PrepareToDive {
                wait_time: arg("wait_time"),
                gps_fix_time,
                since: 0.0,
            },
            BehaviorKind::SetHeading => Logic::SetHeading {
                heading: (arg("use_heading") as i64 == 1).then(|| arg("heading_value")),
            },
            BehaviorKind::Hook => Logic::Hook(Hook {
                default_dive_depth: arg("dive_target_depth"),
                dive_target_altitude: arg("dive_target_altitude"),
                default_climb_depth: arg("climb_target_depth"),
                bpump_value: arg("bpump_value").abs(),
                pitch_value: arg("pitch_value").abs(),
                running: None,
                hover_since: None,
                reported_ignored: false,
            }),
            BehaviorKind::GotoList => Logic::Goto(Goto::list(spec, &arg)),
            BehaviorKind::GotoWpt => Logic::Goto(Goto {
                waypoints: vec![(arg("wpt_y"), arg("wpt_x"))],
                legs_to_run: -2,
                initial: 0,
                stop_when: 7,
                when_wpt_dist: arg("when_wpt_dist"),
                ..Goto::default()
            }),
            BehaviorKind::Gloc => Logic::Script,
            BehaviorKind::SensorsIn | BehaviorKind::Sample | BehaviorKind::Unknown => {
                Logic::Passive
            }
        };
        Behavior {
            kind,
            name: spec.name.to_ascii_lowercase(),
            state: BehaviorState::WaitingForActivation,
            start_when: arg("start_when") as i64,
            stop_when: arg("stop_when") as i64,
            when_secs: arg("when_secs"),
            when_wpt_dist: arg("when_wpt_dist"),
            end_action: arg("end_action") as i64,
            last_start: 0.0,
            last_end: 0.0,
            logic,
        }
    }

    /// A script behavior inserted by the simulator (the mission had none).
    pub fn script() -> Behavior {
        Behavior {
            kind: BehaviorKind::Gloc,
            name: "gloc".to_string(),
            state: BehaviorState::WaitingForActivation,
            start_when: 0,
            stop_when: 5,
            when_secs: 0.0,
            when_wpt_dist: 0.0,
            end_action: 0,
            last_start: 0.0,
            last_end: 0.0,
            logic: Logic::Script,
        }
    }

    pub fn is_active(&self) -> bool {
        self.state == BehaviorState::Active
    }

    /// For a goto behavior that has its waypoints (it started): the one it steers to,
    /// as its place among them (0-based), and how many there are.
    pub fn waypoint_index(&self) -> Option<(usize, usize)> {
        match &self.logic {
            Logic::Goto(goto) if !goto.in_lmc.is_empty() => Some((goto.current, goto.in_lmc.len())),
            _ => None,
        }
    }

    /// Moves the times the behavior last started and ended by `seconds`
    /// (negative: earlier), for a run that begins part way into a mission.
    pub fn shift_timers(&mut self, seconds: f64) {
        self.last_start += seconds;
        self.last_end += seconds;
    }

    /// Steps the behavior's state machine and, when active, its logic.
    /// For the script behavior this only manages activation; the simulation
    /// runs the script itself when `is_active()`.
    pub fn step(&mut self, turn: &mut Turn<'_, '_>) -> Outcome {
        if let Logic::Abend(abend) = &mut self.logic {
            // abend is always on: it has no start/stop state machine.
            self.state = BehaviorState::Active;
            return abend.check(turn.world);
        }
        match self.state {
            BehaviorState::Complete => return Outcome::Continue,
            BehaviorState::WaitingForActivation => {
                if !self.condition(self.start_when, turn.world, Edge::Start) {
                    return Outcome::Continue;
                }
                self.state = BehaviorState::Active;
                self.last_start = turn.world.time;
                self.logic.activate(turn.world);
                turn.report(EventKind::Started);
            }
            BehaviorState::Active => {}
        }
        if self.stop_when != 0 && self.condition(self.stop_when, turn.world, Edge::Stop) {
            return self.complete(turn);
        }
        match self.logic.step(turn) {
            Step::Running => Outcome::Continue,
            Step::Done => self.complete(turn),
        }
    }

    fn complete(&mut self, turn: &mut Turn<'_, '_>) -> Outcome {
        self.last_end = turn.world.time;
        turn.report(EventKind::Completed);
        // end_action: 0 quit, 1 (wait for ^C, none comes in a simulation) and 2 resume.
        if self.end_action == 0 {
            self.state = BehaviorState::Complete;
            if self.kind == BehaviorKind::Surface {
                return Outcome::MissionComplete;
            }
        } else {
            self.state = BehaviorState::WaitingForActivation;
        }
        Outcome::Continue
    }

    /// start_when / stop_when codes (domain notes §2.2). Codes the simulator
    /// does not model (waypoints, UTC, hovering, …) never hold; loading warns.
    fn condition(&self, code: i64, world: &World<'_>, edge: Edge) -> bool {
        let commands = &*world.commands;
        match code {
            0 => edge == Edge::Start,
            1 => commands.stack_idle(),
            2 => commands.pitch.is_none(),
            3 => commands.heading.is_none(),
            4 => commands.buoyancy.is_none(),
            5 => false,
            6 => world.time - self.last_end >= self.when_secs,
            9 => world.time - self.last_start >= self.when_secs,
            7 => world.nav.dist_to_wpt >= 0.0 && world.nav.dist_to_wpt < self.when_wpt_dist,
            8 => world.nav.hit_waypoint,
            10 => world.time - self.last_start >= self.when_secs && commands.buoyancy.is_none(),
            12 => world.time - world.last_surface_time >= self.when_secs,
            15 => world.nav.dist_to_wpt > self.when_wpt_dist,
            _ => false,
        }
    }
}

/// The start_when/stop_when codes the simulator models.
pub fn condition_is_modelled(code: i64) -> bool {
    matches!(code, 0..=10 | 12 | 15)
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Edge {
    Start,
    Stop,
}

enum Step {
    Running,
    Done,
}

impl Logic {
    fn activate(&mut self, world: &World<'_>) {
        match self {
            Logic::Yo(yo) => {
                yo.diving = yo.start_diving;
                yo.half_cycles_done = 0;
                yo.dive.hover_since = None;
                yo.climb.hover_since = None;
            }
            Logic::Single(single) => single.hover_since = None,
            Logic::Surface(surface) => surface.surfaced_at = None,
            Logic::PrepareToDive { since, .. } => *since = world.time,
            Logic::Hook(hook) => hook.running = None,
            Logic::Goto(goto) => goto.activate(world),
            _ => {}
        }
    }

    fn step(&mut self, turn: &mut Turn<'_, '_>) -> Step {
        let (index, world) = (turn.index, &mut *turn.world);
        match self {
            Logic::Yo(yo) => yo.step(turn),
            Logic::Single(single) => {
                if single.step(index, world) {
                    Step::Done
                } else {
                    Step::Running
                }
            }
            Logic::Surface(surface) => surface.step(index, world),
            Logic::PrepareToDive {
                wait_time,
                gps_fix_time,
                since,
            } => {
                // Hold at the surface until the (simulated) GPS fix or the wait runs out.
                if world.time - *since >= wait_time.min(*gps_fix_time) {
                    return Step::Done;
                }
                world
                    .commands
                    .command_vertical(1000.0, NOMINAL_PITCH, index);
                Step::Running
            }
            Logic::SetHeading { heading } => {
                if let Some(heading) = heading {
                    world.commands.heading = Some((*heading, index));
                }
                Step::Running
            }
            Logic::Hook(hook) => {
                hook.step(turn);
                Step::Running
            }
            Logic::Goto(goto) => goto.step(index, world),
            Logic::Script | Logic::Passive | Logic::Abend(_) => Step::Running,
        }
    }
}

/// The glider's nominal pitch, 26° (`f_nominal_pitch`).
pub const NOMINAL_PITCH: f64 = 0.4538;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Direction {
    Dive,
    Climb,
}

/// `use_pitch` 1 flies on the battery position; every other mode servoes.
fn pitch_control(use_pitch: f64) -> PitchControl {
    if use_pitch as i64 == 1 {
        PitchControl::Battpos
    } else {
        PitchControl::Servo
    }
}

/// The pitch command of a dive or climb: with `use_pitch` 1 the battery
/// position (in, > 0 nose down) the glider holds, otherwise the angle
/// ([`servo_pitch`]).
fn pitch_for(use_pitch: f64, value: f64, direction: Direction) -> f64 {
    if use_pitch as i64 == 1 {
        if value.is_finite() {
            value.clamp(-MAX_BATTPOS, MAX_BATTPOS)
        } else {
            0.0
        }
    } else {
        servo_pitch(use_pitch, value, direction)
    }
}

/// The battery's travel either side of its middle (in): glidersim's shallow
/// glider moves it about ±1–1.65 in.
const MAX_BATTPOS: f64 = 2.0;

/// The pitch angle a servoed dive or climb asks for. `use_pitch` 3 gives the
/// angle in radians; the other modes (battery position, pumped fluid) fly the
/// nominal pitch. The sign always follows the direction (< 0 dives).
fn servo_pitch(use_pitch: f64, value: f64, direction: Direction) -> f64 {
    let magnitude = if use_pitch as i64 == 3 && value.abs() > 0.01 {
        value.abs().min(1.2)
    } else {
        NOMINAL_PITCH
    };
    match direction {
        Direction::Dive => -magnitude,
        Direction::Climb => magnitude,
    }
}

#[derive(Clone, Debug)]
struct Abend {
    overdepth: f64,
    overdepth_sample_time: f64,
    overtime: f64,
    samedepth_for: f64,
    samedepth_sample_time: f64,
    undervolts: f64,
    /// < 0 disables; judged on `m_dist_to_wpt` (the glider's belief), as the glider does.
    max_wpt_distance: f64,
    last_overdepth_check: f64,
    last_samedepth_sample: f64,
    samedepth_reference: f64,
    samedepth_since: f64,
}

impl Abend {
    fn check(&mut self, world: &mut World<'_>) -> Outcome {
        if self.overdepth >= 0.0
            && world.time - self.last_overdepth_check >= self.overdepth_sample_time
        {
            self.last_overdepth_check = world.time;
            if world.depth > self.overdepth {
                return Outcome::Abort(AbortReason::Overdepth);
            }
        }
        if self.overtime >= 0.0 && world.time > self.overtime {
            return Outcome::Abort(AbortReason::Overtime);
        }
        if self.samedepth_for >= 0.0
            && world.time - self.last_samedepth_sample >= self.samedepth_sample_time
        {
            self.last_samedepth_sample = world.time;
            // A glider at the surface is not stuck: only count time below it.
            let submerged = world.depth > world.surface_depth;
            let same = (world.depth - self.samedepth_reference).abs() < SAMEDEPTH_TOLERANCE;
            if !submerged || !same {
                self.samedepth_reference = world.depth;
                self.samedepth_since = world.time;
            } else if world.time - self.samedepth_since >= self.samedepth_for {
                return Outcome::Abort(AbortReason::Samedepth);
            }
        }
        if world.battery_volts < self.undervolts {
            return Outcome::Abort(AbortReason::Undervolts);
        }
        if self.max_wpt_distance >= 0.0 && world.nav.dist_to_wpt > self.max_wpt_distance {
            return Outcome::Abort(AbortReason::WptTooFar);
        }
        Outcome::Continue
    }
}

/// Depth change (m) below which two samedepth samples count as "the same depth".
const SAMEDEPTH_TOLERANCE: f64 = 0.5;

#[derive(Clone, Debug)]
struct Surface {
    bpump_value: f64,
    pitch_value: f64,
    /// Seconds to stay at the surface (GPS, and the keystroke wait for end_action 1).
    wait: f64,
    surfaced_at: Option<f64>,
}

impl Surface {
    fn step(&mut self, index: usize, world: &mut World<'_>) -> Step {
        world
            .commands
            .command_vertical(self.bpump_value, self.pitch_value, index);
        match self.surfaced_at {
            None if world.depth <= world.surface_depth => {
                self.surfaced_at = Some(world.time);
                Step::Running
            }
            Some(at) if world.time - at >= self.wait => Step::Done,
            _ => Step::Running,
        }
    }
}

/// A dive_to or climb_to, standing alone or as a sub-behavior of yo or hook.
#[derive(Clone, Debug)]
struct DiveClimb {
    direction: Direction,
    target_depth: f64,
    target_altitude: f64,
    bpump_value: f64,
    pitch_value: f64,
    /// `use_pitch` 1: fly on the battery position (the pitch follows the buoyancy).
    pitch_control: PitchControl,
    hover_for: f64,
    hover_since: Option<f64>,
}

/// A vertical speed (m/s) below which the glider counts as hovering.
const HOVER_RATE: f64 = 0.02;

impl DiveClimb {
    /// Commands the dive or climb unless it is done; true when done.
    fn step(&mut self, index: usize, world: &mut World<'_>) -> bool {
        if self.reached(world) || self.hovered(world) {
            return true;
        }
        let buoyancy = match self.direction {
            Direction::Dive => -self.bpump_value.abs(),
            Direction::Climb => self.bpump_value.abs(),
        };
        world
            .commands
            .command_vertical_with(buoyancy, self.pitch_value, self.pitch_control, index);
        false
    }

    fn reached(&self, world: &World<'_>) -> bool {
        reached(
            self.direction,
            self.target_depth,
            self.target_altitude,
            world,
        )
    }

    fn hovered(&mut self, world: &World<'_>) -> bool {
        if self.hover_for < 0.0 {
            return false;
        }
        if world.depth_rate.abs() >= HOVER_RATE || world.depth <= world.surface_depth {
            self.hover_since = None;
            return false;
        }
        let since = *self.hover_since.get_or_insert(world.time);
        world.time - since >= self.hover_for
    }
}

fn reached(
    direction: Direction,
    target_depth: f64,
    target_altitude: f64,
    world: &World<'_>,
) -> bool {
    match direction {
        Direction::Dive => {
            world.depth >= target_depth
                || (target_altitude > 0.0 && world.altitude <= target_altitude)
        }
        Direction::Climb => {
            world.depth <= target_depth
                || (target_altitude > 0.0 && world.altitude >= target_altitude)
        }
    }
}

#[derive(Clone, Debug)]
struct Yo {
    dive: DiveClimb,
    climb: DiveClimb,
    start_diving: bool,
    half_cycles_to_do: i64,
    diving: bool,
    half_cycles_done: i64,
}

impl Yo {
    fn step(&mut self, turn: &mut Turn<'_, '_>) -> Step {
        // At most one turn per cycle: a half-cycle that is done at once (the
        // glider is already past the next target) waits for the next cycle.
        let leg = if self.diving {
            &mut self.dive
        } else {
            &mut self.climb
        };
        if !leg.step(turn.index, turn.world) {
            return Step::Running;
        }
        self.half_cycles_done += 1;
        turn.report(EventKind::Inflection {
            depth: turn.world.depth,
        });
        if self.half_cycles_to_do > 0 && self.half_cycles_done >= self.half_cycles_to_do {
            return Step::Done;
        }
        self.diving = !self.diving;
        let next = if self.diving {
            &mut self.dive
        } else {
            &mut self.climb
        };
        next.hover_since = None;
        next.step(turn.index, turn.world);
        Step::Running
    }
}

/// goto_list and goto_wpt: steer through waypoints with the firmware's
/// current-corrected heading (`navigation::steer`), judged on the
/// dead-reckoned position as the glider judges it.
#[derive(Clone, Debug, Default)]
struct Goto {
    /// (latitude, longitude) in NMEA, as the mission gives them.
    waypoints: Vec<(f64, f64)>,
    /// The same in local mission coordinates (set on activation).
    in_lmc: Vec<Xy>,
    /// -1 loop for ever, -2 once through the list, N legs.
    legs_to_run: i64,
    /// -2 the closest, -1 the one after the last achieved, N that one.
    initial: i64,
    /// `list_stop_when`: 7 within `when_wpt_dist` (the only one modelled).
    stop_when: i64,
    when_wpt_dist: f64,
    current: usize,
    legs_done: i64,
    last_achieved: Option<usize>,
}

impl Goto {
    fn list(spec: &BehaviorSpec, arg: &dyn Fn(&str) -> f64) -> Goto {
        // `num_waypoints` caps the list; without it, every waypoint given.
        let stated = arg("num_waypoints");
        let count = if stated > 0.0 {
            (stated as usize).min(MAX_WAYPOINTS)
        } else {
            MAX_WAYPOINTS
        };
        let mut waypoints = Vec::with_capacity(count);
        for number in 0..count {
            let (Some(lon), Some(lat)) = (
                spec.arg(&format!("wpt_x_{number}")),
                spec.arg(&format!("wpt_y_{number}")),
            ) else {
                break;
            };
            waypoints.push((lat, lon));
        }
        Goto {
            waypoints,
            legs_to_run: arg("num_legs_to_run") as i64,
            initial: arg("initial_wpt") as i64,
            stop_when: arg("list_stop_when") as i64,
            when_wpt_dist: arg("list_when_wpt_dist"),
            ..Goto::default()
        }
    }

    fn activate(&mut self, world: &World<'_>) {
        let lmc = world.nav.lmc;
        // Refilled in place: a behavior that resumes allocates nothing.
        self.in_lmc.clear();
        self.in_lmc.extend(
            self.waypoints
                .iter()
                .filter(|(lat, lon)| navigation::nmea_is_set(*lat) && navigation::nmea_is_set(*lon))
                .map(|&(lat, lon)| lmc.nmea_to_xy(lat, lon)),
        );
        let count = self.in_lmc.len();
        if count == 0 {
            return;
        }
        self.legs_done = 0;
        let position = world.nav.position;
        self.current = match self.initial {
            -2 => (0..count)
                .min_by(|&a, &b| {
                    position
                        .distance(self.in_lmc[a])
                        .total_cmp(&position.distance(self.in_lmc[b]))
                })
                .unwrap_or(0),
            -1 => self.last_achieved.map_or(0, |last| (last + 1) % count),
            number => (number.max(0) as usize).min(count - 1),
        };
    }

    fn step(&mut self, index: usize, world: &mut World<'_>) -> Step {
        let count = self.in_lmc.len();
        let Some(&waypoint) = self.in_lmc.get(self.current) else {
            return Step::Running;
        };
        let distance = world.nav.steer(waypoint, index, world.commands);
        if self.stop_when != 7 || distance >= self.when_wpt_dist {
            return Step::Running;
        }
        world.nav.hit_waypoint = true;
        self.last_achieved = Some(self.current);
        self.legs_done += 1;
        let once_through = self.legs_to_run == -2 && self.current + 1 == count;
        if once_through || (self.legs_to_run > 0 && self.legs_done >= self.legs_to_run) {
            return Step::Done;
        }
        self.current = (self.current + 1) % count;
        world
            .nav
            .steer(self.in_lmc[self.current], index, world.commands);
        Step::Running
    }
}

/// The most waypoints a goto_list takes (the masterdata's `wpt_x_0` … `wpt_x_7`
/// are 8; gloc takes more from a `.ma` list, up to this).
const MAX_WAYPOINTS: usize = 64;

/// Bit of `sci_ruhp_behs` that runs a climb_to (the paper's value 128).
pub const HOOK_CLIMB_BIT: i64 = 128;
/// Bit of `sci_ruhp_behs` that runs a dive_to (our choice).
pub const HOOK_DIVE_BIT: i64 = 64;
/// Bit of `sci_ruhp_behs` that steers to `sci_ruhp_heading` (our choice), as
/// set_heading steers to its `heading_value`.
pub const HOOK_HEADING_BIT: i64 = 32;
/// The largest `sci_ruhp_behs` the hook reads as bits (a C `int`). The sensor is a
/// float: a fraction, a negative number, NaN or anything above this (`1e308`, which
/// saturates to all bits set) is no request, so a stuck or garbage value cannot hold
/// the hook in a climb for ever.
pub const HOOK_MAX_FLAGS: f64 = 2_147_483_647.0;

/// The hook's request bits in `value`, or `None` when it is no valid request.
pub fn hook_flags(value: f64) -> Option<i64> {
    (value.fract() == 0.0 && (0.0..=HOOK_MAX_FLAGS).contains(&value)).then_some(value as i64)
}

#[derive(Clone, Debug)]
struct Hook {
    default_dive_depth: f64,
    dive_target_altitude: f64,
    default_climb_depth: f64,
    bpump_value: f64,
    pitch_value: f64,
    running: Option<Direction>,
    hover_since: Option<f64>,
    /// Whether an ignored `sci_ruhp_behs` value was reported (once per run).
    reported_ignored: bool,
}

impl Hook {
    /// Reads `sci_ruhp_behs` each cycle. Bit 32 steers to `sci_ruhp_heading`
    /// for as long as it is set. Bit 128 wins over bit 64 (climbing is
    /// the safe side). When the sub-behavior reaches its depth the hook clears
    /// its bit, so a script can see that it is done, and commands nothing.
    fn step(&mut self, turn: &mut Turn<'_, '_>) {
        let value = turn.world.read(turn.world.hook_sensors.behs);
        let flags = match hook_flags(value) {
            Some(flags) => flags,
            None => {
                if !self.reported_ignored {
                    self.reported_ignored = true;
                    turn.report(EventKind::IgnoredRequest { value });
                }
                0
            }
        };
        let (index, world) = (turn.index, &mut *turn.world);
        if flags & HOOK_HEADING_BIT != 0 {
            // A heading that is no number commands nothing (the fin holds), as
            // set_heading without a usable heading_value does.
            let heading = world.read(world.hook_sensors.heading);
            if heading.is_finite() {
                world.commands.heading = Some((heading.rem_euclid(std::f64::consts::TAU), index));
            }
        }
        let wanted = if flags & HOOK_CLIMB_BIT != 0 {
            Some(Direction::Climb)
        } else if flags & HOOK_DIVE_BIT != 0 {
            Some(Direction::Dive)
        } else {
            None
        };
        let Some(direction) = wanted else {
            self.running = None;
            return;
        };
        if self.running != Some(direction) {
            self.running = Some(direction);
            self.hover_since = None;
        }
        let (bit, sensor, default, altitude) = match direction {
            Direction::Climb => (
                HOOK_CLIMB_BIT,
                world.hook_sensors.climb_depth,
                self.default_climb_depth,
                -1.0,
            ),
            Direction::Dive => (
                HOOK_DIVE_BIT,
                world.hook_sensors.dive_depth,
                self.default_dive_depth,
                self.dive_target_altitude,
            ),
        };
        let from_sensor = world.read(sensor);
        let target = if from_sensor > 0.0 && from_sensor.is_finite() {
            from_sensor
        } else {
            default
        };
        if reached(direction, target, altitude, world) {
            if let Some(behs) = world.hook_sensors.behs {
                world.sensors[behs] = (flags & !bit) as f64;
            }
            self.running = None;
            let depth = world.depth;
            turn.report(EventKind::Inflection { depth });
            return;
        }
        let (buoyancy, pitch) = match direction {
            Direction::Climb => (self.bpump_value, self.pitch_value),
            Direction::Dive => (-self.bpump_value, -self.pitch_value),
        };
        world.commands.command_vertical(buoyancy, pitch, index);
    }
}

/// Builds the runtime stack of a mission (highest priority first), inserting
/// the script behavior directly below the safety behaviors (abend, surface)
/// when the mission has none and `with_script` is `ScriptPlacement::Insert`.
pub fn build_stack(
    mission: &Mission,
    param: &dyn Fn(f64) -> f64,
    gps_fix_time: f64,
    placement: ScriptPlacement,
) -> Vec<Behavior> {
    let mut stack: Vec<Behavior> = mission
        .known_behaviors()
        .map(|spec| Behavior::from_spec(spec, param, gps_fix_time))
        .collect();
    let has_script = stack
        .iter()
        .any(|behavior| behavior.kind == BehaviorKind::Gloc);
    if placement == ScriptPlacement::Insert && !has_script {
        let at = stack
            .iter()
            .take_while(|behavior| {
                matches!(behavior.kind, BehaviorKind::Abend | BehaviorKind::Surface)
            })
            .count();
        stack.insert(at, Behavior::script());
    }
    stack
}

/// Whether a script runs in this simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScriptPlacement {
    /// There is a script: insert its behavior if the mission has none.
    Insert,
    /// No script: a `behavior: gloc` in the mission stays idle.
    None,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_case_insensitive() {
        assert_eq!(
            BehaviorKind::from_name("Goto_list"),
            Some(BehaviorKind::GotoList)
        );
        assert_eq!(BehaviorKind::from_name("YO"), Some(BehaviorKind::Yo));
        assert_eq!(BehaviorKind::from_name("drift"), None);
    }

    #[test]
    fn every_argument_has_units_a_doc_and_one_entry() {
        for kind in BehaviorKind::all() {
            let args = kind.args();
            for arg in &args {
                assert!(!arg.units.is_empty(), "{}: {}", kind.name(), arg.name);
                assert!(
                    arg.doc.ends_with('.'),
                    "{}: {} {:?}",
                    kind.name(),
                    arg.name,
                    arg.doc
                );
                assert_eq!(
                    args.iter().filter(|other| other.name == arg.name).count(),
                    1
                );
                assert!(kind.known_args().contains(arg.name));
            }
            assert!(!kind.doc().is_empty());
        }
        // A behavior's own default with the shared doc; per-behavior defaults.
        let start = BehaviorKind::Surface
            .arg_def("START_WHEN")
            .expect("start_when");
        assert_eq!((start.default, start.units), (12.0, "enum"));
        assert!(start
            .doc
            .starts_with("When the behavior starts: 0 immediately"));
        assert_eq!(
            BehaviorKind::DiveTo
                .arg_def("bpump_value")
                .map(|arg| arg.default),
            Some(-260.0)
        );
        assert_eq!(
            BehaviorKind::ClimbTo
                .arg_def("bpump_value")
                .map(|arg| arg.default),
            Some(260.0)
        );
        assert_eq!(
            BehaviorKind::GotoList
                .arg_def("wpt_y_2")
                .map(|arg| arg.name),
            Some("wpt_x_N")
        );
        assert!(BehaviorKind::Abend.arg_def("start_when").is_none());
        // abend: its 24 own arguments and none of the shared start/stop ones.
        assert_eq!(BehaviorKind::Abend.args().len(), 24);
        // yo: 36 own (start_when and end_action among them) plus stop_when, when_secs, when_wpt_dist.
        assert_eq!(BehaviorKind::Yo.args().len(), 39);
    }

    #[test]
    fn known_args_cover_common_and_waypoints() {
        assert!(BehaviorKind::Yo.known_args().contains("D_TARGET_DEPTH"));
        assert!(BehaviorKind::Yo.known_args().contains("start_when"));
        assert!(BehaviorKind::GotoList.known_args().contains("wpt_x_3"));
        assert!(!BehaviorKind::GotoList.known_args().contains("wpt_x_"));
        assert!(!BehaviorKind::Abend.known_args().contains("start_when"));
        assert_eq!(BehaviorKind::DiveTo.default_arg("bpump_value"), -260.0);
        assert_eq!(BehaviorKind::Surface.default_arg("start_when"), 12.0);
        assert_eq!(BehaviorKind::Yo.default_arg("when_secs"), 0.0);
    }

    #[test]
    fn script_is_inserted_below_abend_and_surface() {
        let mission = Mission::parse(
            "m.mi",
            "behavior: abend\nbehavior: surface\nbehavior: surface\nbehavior: hook\nbehavior: yo\n",
        );
        let stack = build_stack(&mission, &|value| value, 60.0, ScriptPlacement::Insert);
        let kinds: Vec<_> = stack.iter().map(|behavior| behavior.kind).collect();
        assert_eq!(
            kinds,
            vec![
                BehaviorKind::Abend,
                BehaviorKind::Surface,
                BehaviorKind::Surface,
                BehaviorKind::Gloc,
                BehaviorKind::Hook,
                BehaviorKind::Yo
            ]
        );
    }
}
