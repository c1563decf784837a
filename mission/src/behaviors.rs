//! The behavior table: every behavior a mission may name, with its arguments, units,
//! defaults and one line of documentation each. The checks, the editor's completion and
//! hover, and the simulator's defaults all read this one table.
//!
//! [`BehaviorTable`] is that table: the active masterdata's `behavior:` sections, or
//! the embedded release table (`data/behaviors.txt`). The `ArgDef` lists below are
//! what the simulator needs of the behaviors it flies when a table leaves a default
//! out, and gloc's own `hook` behavior.

use gloc_engine::sensors::{BehaviorDefaults, SensorList};

/// The behaviors the simulator flies.
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
    /// A `behavior:` the simulator does not fly: one the behavior table has but gloc
    /// does not model (a note, S0111), or one nobody knows (a warning, S0101).
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
    ("goto_list", BehaviorKind::GotoList, "Steers through a list of waypoints with the firmware's current-corrected heading, judged on the dead-reckoned position."),
    ("goto_wpt", BehaviorKind::GotoWpt, "Steers to one waypoint with the firmware's current-corrected heading."),
    ("set_heading", BehaviorKind::SetHeading, "Commands a heading (use_heading 1, heading_value in rad)."),
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
    arg("start_when", "enum", 0.0, "When the behavior starts: 0 immediately, 1 stack idle, 2 pitch idle, 3 heading idle, 4 up/down idle, 5 never, 6 when_secs after its last end, 9 when_secs after its last start, 10 as 9 and up/down idle, 12 no comms for when_secs, 7 m_dist_to_wpt below when_wpt_dist, 8 a waypoint hit, 15 m_dist_to_wpt above when_wpt_dist."),
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

/// An argument as the active behavior table defines it (a masterdata `b_arg:` line).
#[derive(Clone, Debug, PartialEq)]
pub struct ArgInfo {
    pub name: String,
    pub units: String,
    /// `None` when the line gives no default (the firmware then uses 0).
    pub default: Option<f64>,
    /// The line's comment; empty when it has none.
    pub doc: String,
    /// `#! min = …; max = …`: the range Control Center enforces.
    pub range: ArgRange,
    /// `#! choices = start_when([…])`: the only values Control Center allows.
    pub choices: Option<Vec<f64>>,
}

/// The range of an argument's values (`#! min = …; max = …`), either end open.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArgRange {
    pub min: Option<f64>,
    pub max: Option<f64>,
}

impl ArgRange {
    /// Whether `value` lies below the minimum or above the maximum.
    pub fn excludes(self, value: f64) -> bool {
        self.min.is_some_and(|min| value < min) || self.max.is_some_and(|max| value > max)
    }

    /// The range as the mission check and the editor write it (`2 to 5`, `at least
    /// 2`, `at most 5`); `None` when it is open at both ends.
    pub fn text(self) -> Option<String> {
        match (self.min, self.max) {
            (Some(min), Some(max)) => Some(format!("{min} to {max}")),
            (Some(min), None) => Some(format!("at least {min}")),
            (None, Some(max)) => Some(format!("at most {max}")),
            (None, None) => None,
        }
    }
}

/// A behavior as the active table defines it (a masterdata `behavior:` section).
#[derive(Clone, Debug, PartialEq)]
pub struct BehaviorInfo {
    pub name: String,
    /// What the simulator flies for it ([`BehaviorKind::Unknown`]: nothing).
    pub kind: BehaviorKind,
    pub doc: String,
    pub args: Vec<ArgInfo>,
}

impl BehaviorInfo {
    /// The argument `name` (case-insensitive), if the behavior takes it.
    pub fn arg(&self, name: &str) -> Option<&ArgInfo> {
        self.args
            .iter()
            .find(|arg| arg.name.eq_ignore_ascii_case(name))
    }

    /// Whether the simulator flies this behavior (or acts on it, such as abend).
    pub fn is_simulated(&self) -> bool {
        self.kind != BehaviorKind::Unknown
    }
}

/// Where a behavior table came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TableSource {
    /// `mission/data/behaviors.txt`: the manufacturer's release set (see that file).
    Embedded,
    /// The `behavior:` sections of the active masterdata file.
    Masterdata,
}

/// The behaviors a mission may name, with their arguments: the active masterdata's
/// `behavior:` sections when it has them, else gloc's embedded release table, plus
/// gloc's own `hook` and `gloc`. The parser's checks, the simulator's defaults and
/// the editor's completion and hover read it.
#[derive(Clone, Debug, PartialEq)]
pub struct BehaviorTable {
    behaviors: Vec<BehaviorInfo>,
    source: TableSource,
}

/// The embedded release table, in the masterdata format.
const EMBEDDED: &str = include_str!("../data/behaviors.txt");

impl BehaviorTable {
    /// gloc's embedded table (built once).
    pub fn embedded() -> std::sync::Arc<BehaviorTable> {
        static TABLE: std::sync::OnceLock<std::sync::Arc<BehaviorTable>> =
            std::sync::OnceLock::new();
        TABLE
            .get_or_init(|| {
                let (list, _) = gloc_engine::sensors::parse_masterdata(
                    EMBEDDED,
                    gloc_engine::sensors::SensorOrder::FileOrder,
                );
                let mut table = BehaviorTable::from_sections(list.behavior_defaults());
                table.source = TableSource::Embedded;
                std::sync::Arc::new(table)
            })
            .clone()
    }

    /// The table of a sensor list: its masterdata's `behavior:` sections, or the
    /// embedded table when it has none (the embedded sensor list, a `.cac` file).
    pub fn for_sensors(sensor_list: &SensorList) -> std::sync::Arc<BehaviorTable> {
        if sensor_list.behavior_defaults().is_empty() {
            BehaviorTable::embedded()
        } else {
            std::sync::Arc::new(BehaviorTable::from_sections(
                sensor_list.behavior_defaults(),
            ))
        }
    }

    /// A table from masterdata `behavior:` sections (a name given twice: the first
    /// section wins, later ones add arguments it lacks), plus gloc's own behaviors.
    pub fn from_sections(sections: &[BehaviorDefaults]) -> BehaviorTable {
        let mut behaviors: Vec<BehaviorInfo> = Vec::new();
        for section in sections {
            let args = section.args.iter().map(|arg| ArgInfo {
                name: arg.name.clone(),
                units: arg.units.clone(),
                default: arg.default,
                doc: arg.description.clone().unwrap_or_default(),
                range: ArgRange {
                    min: arg.min,
                    max: arg.max,
                },
                choices: arg.choices.clone(),
            });
            match behaviors
                .iter_mut()
                .find(|known| known.name.eq_ignore_ascii_case(&section.name))
            {
                Some(known) => {
                    for arg in args {
                        if known.arg(&arg.name).is_none() {
                            known.args.push(arg);
                        }
                    }
                }
                None => behaviors.push(BehaviorInfo {
                    kind: BehaviorKind::from_name(&section.name).unwrap_or(BehaviorKind::Unknown),
                    doc: section.description.clone().unwrap_or_else(|| {
                        BehaviorKind::from_name(&section.name)
                            .map_or_else(String::new, |kind| kind.doc().to_string())
                    }),
                    name: section.name.clone(),
                    args: args.collect(),
                }),
            }
        }
        for kind in [BehaviorKind::Hook, BehaviorKind::Gloc] {
            if behaviors
                .iter()
                .any(|known| known.name.eq_ignore_ascii_case(kind.name()))
            {
                continue;
            }
            behaviors.push(BehaviorInfo {
                name: kind.name().to_string(),
                kind,
                doc: kind.doc().to_string(),
                args: kind
                    .args()
                    .into_iter()
                    .map(|arg| ArgInfo {
                        name: arg.name.to_string(),
                        units: arg.units.to_string(),
                        default: Some(arg.default),
                        doc: arg.doc.to_string(),
                        range: ArgRange::default(),
                        choices: None,
                    })
                    .collect(),
            });
        }
        BehaviorTable {
            behaviors,
            source: TableSource::Masterdata,
        }
    }

    /// The behavior `name` (case-insensitive: `.ma` files write `Yo`).
    pub fn behavior(&self, name: &str) -> Option<&BehaviorInfo> {
        self.behaviors
            .iter()
            .find(|behavior| behavior.name.eq_ignore_ascii_case(name))
    }

    /// Every behavior, in the table's order.
    pub fn behaviors(&self) -> &[BehaviorInfo] {
        &self.behaviors
    }

    pub fn source(&self) -> &TableSource {
        &self.source
    }

    /// Where the table came from, for messages.
    pub fn source_name(&self) -> &'static str {
        match self.source {
            TableSource::Embedded => "gloc's embedded release table",
            TableSource::Masterdata => "the active masterdata",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_exclude_values_past_their_ends_and_read_as_written() {
        let both = ArgRange {
            min: Some(2.0),
            max: Some(5.0),
        };
        assert!(!both.excludes(2.0) && !both.excludes(5.0));
        assert!(both.excludes(1.9) && both.excludes(5.5));
        assert_eq!(both.text().as_deref(), Some("2 to 5"));
        let floor = ArgRange {
            min: Some(120.0),
            max: None,
        };
        assert!(floor.excludes(60.0) && !floor.excludes(1e9));
        assert_eq!(floor.text().as_deref(), Some("at least 120"));
        let ceiling = ArgRange {
            min: None,
            max: Some(0.5),
        };
        assert_eq!(ceiling.text().as_deref(), Some("at most 0.5"));
        // Open at both ends: nothing is outside, and there is nothing to write.
        let open = ArgRange::default();
        assert!(!open.excludes(-1e300) && !open.excludes(f64::NAN));
        assert_eq!(open.text(), None);
        // NaN is no number past an end (the check cannot say it is out of range).
        assert!(!both.excludes(f64::NAN));
    }
}
