//! The behavior stack: each mission behavior's state machine and the actuator
//! commands it asks for.
//!
//! Behaviors are stepped **bottom-up** once per control cycle, as the paper
//! describes layered control: the lowest-priority behavior runs first and each
//! higher one may overwrite what the lower ones commanded, so for each actuator
//! the highest-priority behavior that commands it wins. A behavior's
//! `start_when` "idle" conditions look at what the behaviors below it have
//! commanded so far in this cycle.

use crate::flight::PitchControl;
use crate::mission::{BehaviorSpec, Mission};

/// The behaviors the simulator knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BehaviorKind {
    Abend,
    Surface,
    Yo,
    DiveTo,
    ClimbTo,
    PrepareToDive,
    SensorsIn,
    Sample,
    GotoList,
    GotoWpt,
    SetHeading,
    /// The hook behavior: spawns climb_to / dive_to from `sci_ruhp_behs`.
    Hook,
    /// The GLOC script behavior.
    Gloc,
    /// A `behavior:` the simulator does not know (warned about, ignored).
    Unknown,
}

/// Each behavior's name as a mission writes it, and one line on what it does here.
const NAMES: &[(&str, BehaviorKind, &str)] = &[
    ("abend", BehaviorKind::Abend, "Always on: aborts the mission on overdepth, overtime, same depth or low battery; the glider climbs and the run ends at the surface."),
    ("surface", BehaviorKind::Surface, "Climbs to the surface, waits for a GPS fix (and a keystroke for end_action 1), then quits or resumes."),
    ("yo", BehaviorKind::Yo, "Alternates dives and climbs between d_target_depth and c_target_depth."),
    ("dive_to", BehaviorKind::DiveTo, "One dive: done past target_depth, at target_altitude, or after hovering for stop_when_hover_for."),
    ("climb_to", BehaviorKind::ClimbTo, "One climb: done above target_depth, or after hovering for stop_when_hover_for."),
    ("prepare_to_dive", BehaviorKind::PrepareToDive, "Holds at the surface until a GPS fix or wait_time."),
    ("sensors_in", BehaviorKind::SensorsIn, "Sets how often the flight sensors are sampled (accepted; commands nothing here)."),
    ("sample", BehaviorKind::Sample, "Switches a science sensor on in the chosen states (accepted; commands nothing here)."),
    ("goto_list", BehaviorKind::GotoList, "Steers through a list of waypoints (accepted; horizontal position is not simulated)."),
    ("goto_wpt", BehaviorKind::GotoWpt, "Steers to one waypoint (accepted; horizontal position is not simulated)."),
    ("set_heading", BehaviorKind::SetHeading, "Commands a heading (use_heading 1); the vertical-plane model does not turn."),
    ("hook", BehaviorKind::Hook, "gloc's hook: runs a climb_to (bit 128) or dive_to (bit 64) that a script requests in sci_ruhp_behs."),
    ("gloc", BehaviorKind::Gloc, "The GLOC script: runs the script once per control cycle, to its yield, at this place in the stack."),
];

/// A behavior argument: its name, units, default and one line on what it sets.
/// Defaults are the masterdata behavior sections' (domain notes §2.3); units and
/// docs follow the masterdata, the real comet missions and `docs/simulator.md`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArgDef {
    pub name: &'static str,
    pub units: &'static str,
    pub default: f64,
    /// Empty when the shared argument of [`COMMON`] says it (a behavior's own default).
    pub doc: &'static str,
}

const fn arg(name: &'static str, units: &'static str, default: f64, doc: &'static str) -> ArgDef {
    ArgDef {
        name,
        units,
        default,
        doc,
    }
}

/// Arguments every behavior with a start/stop state machine accepts.
const COMMON: &[ArgDef] = &[
    arg("start_when", "enum", 0.0, "When the behavior starts: 0 immediately, 1 stack idle, 2 pitch idle, 3 heading idle, 4 up/down idle, 5 never, 6 when_secs after its last end, 9 when_secs after its last start, 10 as 9 and up/down idle, 12 no comms for when_secs."),
    arg("stop_when", "enum", 0.0, "When the behavior stops: 0 on completion, other codes as start_when."),
    arg("when_secs", "sec", 0.0, "Seconds for the timed start_when/stop_when codes (6, 9, 10, 12)."),
    arg("when_wpt_dist", "m", 10.0, "Distance to the waypoint for the waypoint start_when codes (7, 15)."),
    arg("end_action", "enum", 0.0, "After completing: 0 quit the mission, 1 wait for ^C then quit or resume, 2 resume."),
];

const ABEND: &[ArgDef] = &[
    arg(
        "overdepth",
        "m",
        10000.0,
        "Abort deeper than this (< 0 disables; clipped to F_MAX_WORKING_DEPTH).",
    ),
    arg(
        "overdepth_sample_time",
        "sec",
        15.0,
        "How often overdepth is checked.",
    ),
    arg(
        "overtime",
        "sec",
        -1.0,
        "Abort when the mission has run longer than this (< 0 disables).",
    ),
    arg(
        "undervolts",
        "volts",
        10.0,
        "Abort when the battery voltage falls below this.",
    ),
    arg(
        "samedepth_for",
        "sec",
        1800.0,
        "Abort when the depth stays within 0.5 m this long under water (< 0 disables).",
    ),
    arg(
        "samedepth_for_sample_time",
        "sec",
        30.0,
        "How often samedepth_for is checked.",
    ),
    arg(
        "stalled_for",
        "sec",
        1800.0,
        "Abort when the glider is stalled this long (< 0 disables).",
    ),
    arg(
        "stalled_for_sample_time",
        "sec",
        30.0,
        "How often stalled_for is checked.",
    ),
    arg(
        "no_cop_tickle_for",
        "sec",
        48600.0,
        "Abort when the COP watchdog has not been tickled this long.",
    ),
    arg(
        "no_comms_tickle_for",
        "hours",
        72.0,
        "Abort after this long without communications.",
    ),
    arg(
        "max_wpt_distance",
        "m",
        -1.0,
        "Abort when the waypoint is farther than this, MS_ABORT_WPT_TOOFAR (< 0 disables).",
    ),
    arg(
        "chk_sensor_reasonableness",
        "bool",
        1.0,
        "Abort on unreasonable sensor values.",
    ),
    arg(
        "reqd_spare_heap",
        "bytes",
        10000.0,
        "Abort when the free heap falls below this.",
    ),
    arg(
        "leakdetect_sample_time",
        "sec",
        60.0,
        "How often the leak detectors are checked.",
    ),
    arg(
        "vacuum_min",
        "inHg",
        4.0,
        "Abort when the hull vacuum is below this.",
    ),
    arg(
        "vacuum_max",
        "inHg",
        12.0,
        "Abort when the hull vacuum is above this.",
    ),
    arg(
        "vacuum_sample_time",
        "sec",
        30.0,
        "How often the vacuum is checked.",
    ),
    arg(
        "oil_volume_sample_time",
        "sec",
        30.0,
        "How often the oil volume is checked.",
    ),
    arg(
        "remaining_charge_min",
        "%",
        10.0,
        "Abort when the remaining battery charge falls below this.",
    ),
    arg(
        "unreasonable_settings",
        "bool",
        1.0,
        "Abort on unreasonable mission settings.",
    ),
    arg(
        "eng_pressure_mul",
        "nodim",
        1.1,
        "Multiplier of the engine pressure limit.",
    ),
    arg(
        "eng_pressure_div",
        "nodim",
        1.0,
        "Divisor of the engine pressure limit.",
    ),
    arg(
        "eng_pressure_sample_time",
        "sec",
        30.0,
        "How often the engine pressure is checked.",
    ),
    arg(
        "max_allowable_busy_cpu_cycles",
        "cycles",
        3.0,
        "Abort after this many control cycles in a row that overran.",
    ),
];

const SURFACE: &[ArgDef] = &[
    arg("start_when", "enum", 12.0, ""),
    arg("when_secs", "sec", 1200.0, ""),
    arg("end_action", "enum", 1.0, ""),
    arg("gps_wait_time", "sec", 300.0, "How long to wait at the surface for a GPS fix."),
    arg("keystroke_wait_time", "sec", 300.0, "How long to wait at the surface for a ^C (end_action 1)."),
    arg("c_use_bpump", "enum", 2.0, "Climb: buoyancy pump mode (0 autoballast, 2 absolute cc, 3 absolute surface, 5 speed relative)."),
    arg("c_bpump_value", "X", 1000.0, "Climb: buoyancy pump value in cc (> 0 goes up; 1000 pumps fully out)."),
    arg("c_use_pitch", "enum", 3.0, "Climb: pitch mode (1 battery position in inches, 3 servo on pitch in rad)."),
    arg("c_pitch_value", "X", 0.4538, "Climb: pitch value (servo: rad, > 0 nose up; 0.4538 is 26°)."),
    arg("c_stop_when_air_pump", "bool", 1.0, "Climb: stop pumping when the air bladder inflates."),
    arg("c_use_thruster", "enum", 0.0, "Climb: thruster mode (0 off)."),
    arg("c_thruster_value", "X", 0.0, "Climb: thruster value."),
    arg("report_all", "bool", 0.0, "Print every sensor in the surface dialog."),
    arg("strobe_on", "bool", 0.0, "Switch the strobe light on at the surface."),
    arg("printout_cycle_time", "sec", 60.0, "How often the surface dialog prints."),
    arg("sensor_input_wait_time", "sec", 60.0, "How long to wait for sensor input at the surface."),
    arg("end_wpt_dist", "m", 0.0, "Drift until this far from the waypoint (end_action 3)."),
    arg("when_utc_min", "min", -1.0, "start_when 13: the UTC minute (-1 any)."),
    arg("when_utc_hour", "hour", -1.0, "start_when 13: the UTC hour (-1 any)."),
    arg("when_utc_day", "day", -1.0, "start_when 13: the UTC day of the month (-1 any)."),
    arg("when_utc_month", "month", -1.0, "start_when 13: the UTC month (-1 any)."),
    arg("when_utc_on_surface", "bool", 0.0, "start_when 13: the masterdata's surface-at-UTC option (not simulated)."),
    arg("gps_postfix_wait_time", "sec", 60.0, "How long the GPS stays on after its first fix."),
];

const YO: &[ArgDef] = &[
    arg("start_when", "enum", 2.0, ""),
    arg("end_action", "enum", 2.0, ""),
    arg(
        "start_diving",
        "bool",
        1.0,
        "Begin with a dive (1) or a climb (0).",
    ),
    arg(
        "num_half_cycles_to_do",
        "nodim",
        -1.0,
        "Dives plus climbs before the yo completes (< 0 for ever).",
    ),
    arg("d_target_depth", "m", 12.0, "Dive: turn at this depth."),
    arg(
        "d_target_altitude",
        "m",
        5.0,
        "Dive: turn at this height above the bottom (< 0 disables).",
    ),
    arg(
        "d_use_bpump",
        "enum",
        2.0,
        "Dive: buoyancy pump mode (2 absolute cc).",
    ),
    arg(
        "d_bpump_value",
        "X",
        -260.0,
        "Dive: buoyancy pump value in cc (< 0 goes down).",
    ),
    arg(
        "d_use_pitch",
        "enum",
        3.0,
        "Dive: pitch mode (1 battery position in inches, 3 servo on pitch in rad).",
    ),
    arg(
        "d_pitch_value",
        "X",
        -0.4538,
        "Dive: pitch value (servo: rad, < 0 nose down).",
    ),
    arg(
        "d_stop_when_hover_for",
        "sec",
        180.0,
        "Dive: turn after moving vertically slower than 0.02 m/s this long (< 0 disables).",
    ),
    arg(
        "d_stop_when_stalled_for",
        "sec",
        240.0,
        "Dive: turn after being stalled this long.",
    ),
    arg(
        "d_use_thruster",
        "enum",
        0.0,
        "Dive: thruster mode (0 off).",
    ),
    arg("d_thruster_value", "X", 0.0, "Dive: thruster value."),
    arg(
        "d_depth_rate_method",
        "enum",
        3.0,
        "Dive: how the depth rate is computed.",
    ),
    arg(
        "d_wait_for_pitch",
        "bool",
        1.0,
        "Dive: wait for the pitch before pumping.",
    ),
    arg(
        "d_wait_for_ballast",
        "sec",
        100.0,
        "Dive: longest wait for the pump.",
    ),
    arg(
        "d_delta_bpump",
        "X",
        25.0,
        "Dive: buoyancy step in cc when adjusting.",
    ),
    arg(
        "d_time_ratio",
        "nodim",
        1.1,
        "Dive: allowed over expected time of the leg.",
    ),
    arg(
        "d_max_thermal_charge_depth",
        "m",
        10.0,
        "Dive: deepest depth at which the thermal engine charges.",
    ),
    arg("c_target_depth", "m", 3.0, "Climb: turn at this depth."),
    arg(
        "c_target_altitude",
        "m",
        -1.0,
        "Climb: turn at this height above the bottom (< 0 disables).",
    ),
    arg(
        "c_use_bpump",
        "enum",
        2.0,
        "Climb: buoyancy pump mode (2 absolute cc).",
    ),
    arg(
        "c_bpump_value",
        "X",
        260.0,
        "Climb: buoyancy pump value in cc (> 0 goes up).",
    ),
    arg(
        "c_use_pitch",
        "enum",
        3.0,
        "Climb: pitch mode (1 battery position in inches, 3 servo on pitch in rad).",
    ),
    arg(
        "c_pitch_value",
        "X",
        0.4538,
        "Climb: pitch value (servo: rad, > 0 nose up).",
    ),
    arg(
        "c_stop_when_hover_for",
        "sec",
        180.0,
        "Climb: turn after moving vertically slower than 0.02 m/s this long (< 0 disables).",
    ),
    arg(
        "c_stop_when_stalled_for",
        "sec",
        240.0,
        "Climb: turn after being stalled this long.",
    ),
    arg(
        "c_use_thruster",
        "enum",
        0.0,
        "Climb: thruster mode (0 off).",
    ),
    arg("c_thruster_value", "X", 0.0, "Climb: thruster value."),
    arg(
        "c_depth_rate_method",
        "enum",
        3.0,
        "Climb: how the depth rate is computed.",
    ),
    arg(
        "c_wait_for_pitch",
        "bool",
        1.0,
        "Climb: wait for the pitch before pumping.",
    ),
    arg(
        "c_wait_for_ballast",
        "sec",
        100.0,
        "Climb: longest wait for the pump.",
    ),
    arg(
        "c_delta_bpump",
        "X",
        25.0,
        "Climb: buoyancy step in cc when adjusting.",
    ),
    arg(
        "c_time_ratio",
        "nodim",
        1.1,
        "Climb: allowed over expected time of the leg.",
    ),
    arg(
        "initial_inflection",
        "bool",
        1.0,
        "Inflect (pump and pitch) as soon as the behavior starts.",
    ),
];

const DIVE_CLIMB: &[ArgDef] = &[
    arg("target_depth", "m", 10.0, "Done past this depth."),
    arg(
        "target_altitude",
        "m",
        -1.0,
        "Done at this height above the bottom (< 0 disables).",
    ),
    arg(
        "use_bpump",
        "enum",
        2.0,
        "Buoyancy pump mode (2 absolute cc).",
    ),
    arg(
        "bpump_value",
        "X",
        260.0,
        "Buoyancy pump value in cc (> 0 goes up; dive_to's default is -260).",
    ),
    arg(
        "use_pitch",
        "enum",
        3.0,
        "Pitch mode (1 battery position in inches, 3 servo on pitch in rad).",
    ),
    arg(
        "pitch_value",
        "X",
        0.4538,
        "Pitch value (servo: rad, > 0 nose up; dive_to's default is -0.4538).",
    ),
    arg(
        "stop_when_hover_for",
        "sec",
        180.0,
        "Done after moving vertically slower than 0.02 m/s this long (< 0 disables).",
    ),
    arg(
        "stop_when_stalled_for",
        "sec",
        240.0,
        "Done after being stalled this long.",
    ),
    arg(
        "initial_inflection",
        "bool",
        1.0,
        "Inflect (pump and pitch) as soon as the behavior starts.",
    ),
    arg("use_thruster", "enum", 0.0, "Thruster mode (0 off)."),
    arg("thruster_value", "X", 0.0, "Thruster value."),
    arg(
        "depth_rate_method",
        "enum",
        3.0,
        "How the depth rate is computed.",
    ),
    arg(
        "wait_for_pitch",
        "bool",
        1.0,
        "Wait for the pitch before pumping.",
    ),
    arg(
        "wait_for_ballast",
        "sec",
        100.0,
        "Longest wait for the pump.",
    ),
    arg(
        "delta_bpump",
        "X",
        25.0,
        "Buoyancy step in cc when adjusting.",
    ),
    arg(
        "time_ratio",
        "nodim",
        1.1,
        "Allowed over expected time of the leg.",
    ),
];

const PREPARE_TO_DIVE: &[ArgDef] = &[
    arg(
        "wait_time",
        "sec",
        720.0,
        "Longest wait at the surface for a GPS fix before diving.",
    ),
    arg(
        "max_thermal_charge_time",
        "sec",
        1200.0,
        "Longest time to charge the thermal engine at the surface.",
    ),
];

const SENSORS_IN: &[ArgDef] = &[
    arg(
        "c_att_time",
        "sec",
        0.0,
        "Attitude sensor interval (< 0 off, 0 as fast as possible).",
    ),
    arg(
        "c_pressure_time",
        "sec",
        0.0,
        "Pressure (depth) sensor interval (< 0 off, 0 as fast as possible).",
    ),
    arg(
        "c_alt_time",
        "sec",
        0.0,
        "Altimeter interval (< 0 off, 0 as fast as possible).",
    ),
    arg("u_battery_time", "sec", 60.0, "Battery voltage interval."),
    arg("u_vacuum_time", "sec", 60.0, "Hull vacuum interval."),
    arg(
        "c_profile_on",
        "sec",
        0.0,
        "Science profile (CTD) interval (< 0 off, 0 as fast as possible).",
    ),
    arg(
        "c_gps_on",
        "bool",
        0.0,
        "Keep the GPS on under water (1 on, 0 off).",
    ),
    arg(
        "c_science_all_on",
        "sec",
        0.0,
        "Interval of every science sensor at once (< 0 off).",
    ),
    arg("u_leak_time", "sec", 60.0, "Leak detector interval."),
];

const SAMPLE: &[ArgDef] = &[
    arg("sensor_type", "enum", 0.0, "The science sensor: 0 all (c_science_all_on), 1 CTD profile (c_profile_on), 19 FLNTU, 39 logger, 43 DVL."),
    arg("state_to_sample", "enum", 1.0, "Bit mask of the states to sample in: 1 diving, 2 hovering, 4 climbing, 8 at the surface (5: dive or climb)."),
    arg("sample_time_after_state_change", "sec", 15.0, "Wait this long after a change of state before sampling."),
    arg("intersample_time", "sec", 0.0, "Time between samples (< 0 off, 0 as fast as possible)."),
    arg("nth_yo_to_sample", "nodim", 1.0, "Sample every n-th yo."),
    arg("intersample_depth", "m", -1.0, "Depth between samples (< 0 off)."),
    arg("min_depth", "m", -5.0, "Shallowest depth to sample at (negative: on at the surface despite depth noise)."),
    arg("max_depth", "m", 2000.0, "Deepest depth to sample at."),
];

const GOTO_LIST: &[ArgDef] = &[
    arg(
        "num_waypoints",
        "nodim",
        0.0,
        "Waypoints in the list (1 to 8).",
    ),
    arg(
        "num_legs_to_run",
        "nodim",
        -1.0,
        "Legs to run: -1 loop for ever, -2 once through the list.",
    ),
    arg(
        "initial_wpt",
        "enum",
        -2.0,
        "First waypoint: -2 the closest, -1 the one after the last one achieved.",
    ),
    arg(
        "list_stop_when",
        "enum",
        7.0,
        "When a waypoint counts as reached (stop_when codes; 7 within list_when_wpt_dist).",
    ),
    arg(
        "list_when_wpt_dist",
        "m",
        10.0,
        "Distance at which a waypoint counts as reached.",
    ),
    arg(
        "list_when_secs",
        "sec",
        0.0,
        "Seconds for a timed list_stop_when.",
    ),
    arg(
        "wpt_units",
        "enum",
        0.0,
        "Units of the waypoint coordinates.",
    ),
];

const GOTO_WPT: &[ArgDef] = &[
    arg(
        "wpt_units",
        "enum",
        0.0,
        "Units of the waypoint coordinates.",
    ),
    arg("wpt_x", "X", 0.0, "The waypoint's x (longitude)."),
    arg("wpt_y", "X", 0.0, "The waypoint's y (latitude)."),
];

const SET_HEADING: &[ArgDef] = &[
    arg(
        "use_heading",
        "enum",
        1.0,
        "What is commanded: 1 heading, 2 roll, 3 battery roll, 4 fin.",
    ),
    arg(
        "heading_value",
        "X",
        0.0,
        "The heading in rad (or the roll, battery roll or fin value).",
    ),
];

/// Our hook behavior's own defaults, used when the `sci_ruhp_*_depth` sensors
/// are not positive.
const HOOK: &[ArgDef] = &[
    arg(
        "dive_target_depth",
        "m",
        20.0,
        "Bit 64's dive_to target when sci_ruhp_dive_depth is not positive.",
    ),
    arg(
        "dive_target_altitude",
        "m",
        -1.0,
        "Bit 64's dive_to altitude (< 0 disables).",
    ),
    arg(
        "climb_target_depth",
        "m",
        3.0,
        "Bit 128's climb_to target when sci_ruhp_climb_depth is not positive.",
    ),
    arg(
        "bpump_value",
        "cc",
        260.0,
        "Buoyancy pump value of the hook's dives (negated) and climbs.",
    ),
    arg(
        "pitch_value",
        "rad",
        0.4538,
        "Pitch of the hook's dives (negated) and climbs.",
    ),
];

/// `wpt_x_N` / `wpt_y_N` of a goto_list (N a number), described for hover.
const WAYPOINT_ARG: ArgDef = arg(
    "wpt_x_N",
    "X",
    0.0,
    "goto_list waypoint N's x (wpt_x_N, longitude) or y (wpt_y_N, latitude).",
);

impl BehaviorKind {
    /// Case-insensitive: `.ma` files write `Yo` and `Goto_list`.
    pub fn from_name(name: &str) -> Option<BehaviorKind> {
        NAMES
            .iter()
            .find(|(known, _, _)| known.eq_ignore_ascii_case(name))
            .map(|&(_, kind, _)| kind)
    }

    pub fn name(self) -> &'static str {
        NAMES
            .iter()
            .find(|(_, kind, _)| *kind == self)
            .map(|(name, _, _)| *name)
            .unwrap_or("unknown")
    }

    /// One line on what the behavior does in the simulator.
    pub fn doc(self) -> &'static str {
        NAMES
            .iter()
            .find(|(_, kind, _)| *kind == self)
            .map(|(_, _, doc)| *doc)
            .unwrap_or("a behavior the simulator does not know")
    }

    /// Every behavior a mission may name, in the table's order.
    pub fn all() -> impl Iterator<Item = BehaviorKind> {
        NAMES.iter().map(|&(_, kind, _)| kind)
    }

    pub fn all_names() -> String {
        NAMES
            .iter()
            .map(|(name, _, _)| *name)
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn own_args(self) -> &'static [ArgDef] {
        match self {
            BehaviorKind::Abend => ABEND,
            BehaviorKind::Surface => SURFACE,
            BehaviorKind::Yo => YO,
            BehaviorKind::DiveTo | BehaviorKind::ClimbTo => DIVE_CLIMB,
            BehaviorKind::PrepareToDive => PREPARE_TO_DIVE,
            BehaviorKind::SensorsIn => SENSORS_IN,
            BehaviorKind::Sample => SAMPLE,
            BehaviorKind::GotoList => GOTO_LIST,
            BehaviorKind::GotoWpt => GOTO_WPT,
            BehaviorKind::SetHeading => SET_HEADING,
            BehaviorKind::Hook => HOOK,
            BehaviorKind::Gloc | BehaviorKind::Unknown => &[],
        }
    }

    /// The shared start/stop arguments this behavior takes (abend has none).
    fn common_args(self) -> &'static [ArgDef] {
        match self {
            BehaviorKind::Abend | BehaviorKind::Unknown => &[],
            _ => COMMON,
        }
    }

    pub fn known_args(self) -> KnownArgs {
        KnownArgs(self)
    }

    /// Every argument the behavior takes (its own, then the shared ones it does
    /// not redefine), with its default for this behavior and its doc. The
    /// numbered goto_list waypoints (`wpt_x_N`) are not listed; see [`BehaviorKind::arg_def`].
    pub fn args(self) -> Vec<ArgDef> {
        let own = self.own_args();
        own.iter()
            .chain(
                self.common_args()
                    .iter()
                    .filter(|common| !own.iter().any(|arg| arg.name == common.name)),
            )
            .filter_map(|arg| self.arg_def(arg.name))
            .collect()
    }

    /// An argument's definition for this behavior (case-insensitive), or `None`
    /// when the behavior does not take it.
    pub fn arg_def(self, name: &str) -> Option<ArgDef> {
        let lower = name.to_ascii_lowercase();
        if self == BehaviorKind::GotoList && is_waypoint_arg(&lower) {
            return Some(WAYPOINT_ARG);
        }
        let own = self.own_args().iter().find(|arg| arg.name == lower);
        let common = self.common_args().iter().find(|arg| arg.name == lower);
        let found = own.or(common)?;
        Some(ArgDef {
            default: self.default_arg(found.name),
            doc: if found.doc.is_empty() {
                common.map_or("", |common| common.doc)
            } else {
                found.doc
            },
            ..*found
        })
    }

    /// The default of an argument: the behavior's own table first, then the
    /// arguments every behavior shares.
    pub fn default_arg(self, name: &str) -> f64 {
        let defaults = match (self, name) {
            (BehaviorKind::ClimbTo, "bpump_value") => return 260.0,
            (BehaviorKind::DiveTo, "bpump_value") => return -260.0,
            (BehaviorKind::DiveTo, "pitch_value") => return -0.4538,
            (BehaviorKind::DiveTo, "stop_when_hover_for") => return 180.0,
            (BehaviorKind::ClimbTo, "stop_when_hover_for") => return -1.0,
            (BehaviorKind::SetHeading, "stop_when") => return 5.0,
            (BehaviorKind::Gloc, "stop_when") => return 5.0,
            (BehaviorKind::Hook, "stop_when") => return 5.0,
            _ => self.own_args(),
        };
        defaults
            .iter()
            .chain(COMMON)
            .find(|arg| arg.name == name)
            .map(|arg| arg.default)
            .unwrap_or(0.0)
    }
}

/// The argument names a behavior accepts (case-insensitive).
#[derive(Clone, Copy, Debug)]
pub struct KnownArgs(BehaviorKind);

impl KnownArgs {
    pub fn contains(&self, name: &str) -> bool {
        self.0.arg_def(name).is_some()
    }
}

/// `wpt_x_N` / `wpt_y_N` of a goto_list.
fn is_waypoint_arg(name: &str) -> bool {
    let rest = name
        .strip_prefix("wpt_x_")
        .or_else(|| name.strip_prefix("wpt_y_"));
    rest.is_some_and(|digits| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
}

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
}

impl AbortReason {
    /// The glider's name for the abort (`MS_ABORT_OVERDEPTH`).
    pub fn glider_name(self) -> &'static str {
        match self {
            AbortReason::Overdepth => "MS_ABORT_OVERDEPTH",
            AbortReason::Overtime => "MS_ABORT_OVERTIME",
            AbortReason::Samedepth => "MS_ABORT_SAMEDEPTH",
            AbortReason::Undervolts => "MS_ABORT_UNDERVOLTS",
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
}

/// Where the hook behavior's sensors sit in the active list (absent ones are `None`).
#[derive(Clone, Copy, Debug, Default)]
pub struct HookSensors {
    pub behs: Option<usize>,
    pub dive_depth: Option<usize>,
    pub climb_depth: Option<usize>,
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
    Hook(Hook),
    /// The script: run by the simulation itself at this place.
    Script,
    /// Accepted, commands nothing (sensors_in, sample, goto_list, goto_wpt).
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
        let arg = |name: &str| param(spec.arg(name).unwrap_or_else(|| kind.default_arg(name)));
        let logic = match kind {
            BehaviorKind::Abend => Logic::Abend(Abend {
                overdepth: arg("overdepth"),
                overdepth_sample_time: arg("overdepth_sample_time"),
                overtime: arg("overtime"),
                samedepth_for: arg("samedepth_for"),
                samedepth_sample_time: arg("samedepth_for_sample_time"),
                undervolts: arg("undervolts"),
                last_overdepth_check: f64::NEG_INFINITY,
                last_samedepth_sample: f64::NEG_INFINITY,
                samedepth_reference: f64::NAN,
                samedepth_since: 0.0,
            }),
            BehaviorKind::Surface => Logic::Surface(Surface {
                bpump_value: arg("c_bpump_value").abs(),
                pitch_value: pitch_for(arg("c_use_pitch"), arg("c_pitch_value"), Direction::Climb),
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
            BehaviorKind::Gloc => Logic::Script,
            BehaviorKind::SensorsIn
            | BehaviorKind::Sample
            | BehaviorKind::GotoList
            | BehaviorKind::GotoWpt
            | BehaviorKind::Unknown => Logic::Passive,
        };
        Behavior {
            kind,
            name: spec.name.to_ascii_lowercase(),
            state: BehaviorState::WaitingForActivation,
            start_when: arg("start_when") as i64,
            stop_when: arg("stop_when") as i64,
            when_secs: arg("when_secs"),
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
            end_action: 0,
            last_start: 0.0,
            last_end: 0.0,
            logic: Logic::Script,
        }
    }

    pub fn is_active(&self) -> bool {
        self.state == BehaviorState::Active
    }

    /// Steps the behavior's state machine and, when active, its logic.
    /// For the script behavior this only manages activation; the simulation
    /// runs the script itself when `is_active()`.
    pub fn step(
        &mut self,
        index: usize,
        world: &mut World<'_>,
        events: &mut Vec<BehaviorEvent>,
    ) -> Outcome {
        if let Logic::Abend(abend) = &mut self.logic {
            // abend is always on: it has no start/stop state machine.
            self.state = BehaviorState::Active;
            return abend.check(world);
        }
        match self.state {
            BehaviorState::Complete => return Outcome::Continue,
            BehaviorState::WaitingForActivation => {
                if !self.condition(self.start_when, world, Edge::Start) {
                    return Outcome::Continue;
                }
                self.state = BehaviorState::Active;
                self.last_start = world.time;
                self.logic.activate(world);
                events.push(BehaviorEvent {
                    behavior: index,
                    kind: EventKind::Started,
                });
            }
            BehaviorState::Active => {}
        }
        if self.stop_when != 0 && self.condition(self.stop_when, world, Edge::Stop) {
            return self.complete(index, world, events);
        }
        match self.logic.step(index, world, events) {
            Step::Running => Outcome::Continue,
            Step::Done => self.complete(index, world, events),
        }
    }

    fn complete(
        &mut self,
        index: usize,
        world: &World<'_>,
        events: &mut Vec<BehaviorEvent>,
    ) -> Outcome {
        self.last_end = world.time;
        events.push(BehaviorEvent {
            behavior: index,
            kind: EventKind::Completed,
        });
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
            10 => world.time - self.last_start >= self.when_secs && commands.buoyancy.is_none(),
            12 => world.time - world.last_surface_time >= self.when_secs,
            _ => false,
        }
    }
}

/// The start_when/stop_when codes the simulator models.
pub fn condition_is_modelled(code: i64) -> bool {
    matches!(code, 0..=6 | 9 | 10 | 12)
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
            _ => {}
        }
    }

    fn step(
        &mut self,
        index: usize,
        world: &mut World<'_>,
        events: &mut Vec<BehaviorEvent>,
    ) -> Step {
        match self {
            Logic::Yo(yo) => yo.step(index, world, events),
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
                hook.step(index, world, events);
                Step::Running
            }
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

/// The pitch a dive or climb asks for. `use_pitch` 3 gives the angle in
/// radians; the other modes (battery position, pumped fluid) fly the nominal
/// pitch. The sign always follows the direction (< 0 dives).
fn pitch_for(use_pitch: f64, value: f64, direction: Direction) -> f64 {
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
    fn step(
        &mut self,
        index: usize,
        world: &mut World<'_>,
        events: &mut Vec<BehaviorEvent>,
    ) -> Step {
        // At most one turn per cycle: a half-cycle that is done at once (the
        // glider is already past the next target) waits for the next cycle.
        let leg = if self.diving {
            &mut self.dive
        } else {
            &mut self.climb
        };
        if !leg.step(index, world) {
            return Step::Running;
        }
        self.half_cycles_done += 1;
        events.push(BehaviorEvent {
            behavior: index,
            kind: EventKind::Inflection { depth: world.depth },
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
        next.step(index, world);
        Step::Running
    }
}

/// Bit of `sci_ruhp_behs` that runs a climb_to (the paper's value 128).
pub const HOOK_CLIMB_BIT: i64 = 128;
/// Bit of `sci_ruhp_behs` that runs a dive_to (our choice).
pub const HOOK_DIVE_BIT: i64 = 64;
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
    /// Reads `sci_ruhp_behs` each cycle. Bit 128 wins over bit 64 (climbing is
    /// the safe side). When the sub-behavior reaches its depth the hook clears
    /// its bit, so a script can see that it is done, and commands nothing.
    fn step(&mut self, index: usize, world: &mut World<'_>, events: &mut Vec<BehaviorEvent>) {
        let value = world.read(world.hook_sensors.behs);
        let flags = match hook_flags(value) {
            Some(flags) => flags,
            None => {
                if !self.reported_ignored {
                    self.reported_ignored = true;
                    events.push(BehaviorEvent {
                        behavior: index,
                        kind: EventKind::IgnoredRequest { value },
                    });
                }
                0
            }
        };
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
            events.push(BehaviorEvent {
                behavior: index,
                kind: EventKind::Inflection { depth: world.depth },
            });
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
    let mut stack: Vec<Behavior> = crate::mission::known_behaviors(mission)
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
