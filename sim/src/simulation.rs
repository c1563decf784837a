//! The simulation: sensor array, behavior stack, script, vehicle and water,
//! advanced one control cycle at a time in phases a debugger can stop between.
//!
//! A cycle is three phases:
//! 1. [`Simulation::begin_cycle`]: the clock advances, the measured sensors are
//!    published, and the behaviors *below* the script step (layered control
//!    runs bottom-up). This is the **cycle boundary** a debugger stops at: the
//!    script has not run yet in this cycle.
//! 2. The script's share: [`Simulation::run_script`] (to its `yield`), or
//!    [`Simulation::script_step`] one instruction at a time.
//! 3. [`Simulation::finish_cycle`]: the rest of the script's share if any, the
//!    behaviors above the script, arbitration, and the flight model.
//!
//! [`Simulation::step_cycle`] does all three. Everything is `Clone` and
//! deterministic from the seed, so a debugger can snapshot and replay.
//! Nothing here allocates per cycle in steady state: per-cycle outputs live in
//! buffers that are cleared, not freed.

use std::sync::Arc;

use gloc_engine::program::{Pc, Program};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig, Status, Trap};

use crate::behaviors::{
    build_stack, condition_is_modelled, AbortReason, Behavior, BehaviorEvent, BehaviorKind,
    Commands, HookSensors, NavView, Outcome, ScriptPlacement, Turn, World,
};
use crate::environment::{Rng, TemperatureProfile};
use crate::flight::{EnergyParams, EnergyUse, FlightParams, Vehicle};
use crate::mission::Mission;
use crate::navigation::{
    nmea_is_set, CycleMotion, Lmc, NavParams, NavSetup, Navigation, Xy, DEFAULT_START_NMEA,
};

/// Settings of a run that are not in the mission.
#[derive(Clone, Debug)]
pub struct SimConfig {
    pub seed: u64,
    /// Water depth (m). `None`: the mission's `s_water_depth_avg`, else 40 m.
    pub water_depth: Option<f64>,
    /// `None`: the built-in summer shelf profile, shaped by the mission's
    /// `s_water_temp_surface`, `s_water_temp_bottom`, `s_water_temp_depth_inft`
    /// and `s_water_temp_depth_infb` when it sets them.
    pub profile: Option<TemperatureProfile>,
    pub flight: FlightParams,
    pub energy: EnergyParams,
    /// Per-cycle instruction budget of the script.
    pub cycle_budget: u64,
    /// Seconds at the surface until the simulated GPS has a fix.
    pub gps_fix_time: f64,
    /// `m_present_time` at the start (Unix seconds). Fixed by default so that
    /// runs are reproducible.
    pub start_time: f64,
    /// Standard deviation of the CTD temperature noise (°C).
    pub temperature_noise: f64,
    /// Standard deviation of the CTD pressure noise (bar).
    pub pressure_noise: f64,
    /// Timing and sensors: the control cycle, turns, altimeter.
    pub timing: TimingParams,
    /// The horizontal model: turns, the roll bias's zig-zag, `m_avg_speed`.
    pub navigation: NavParams,
}

/// The control cycle's real period, the turn latency and the altimeter.
#[derive(Clone, Debug, PartialEq)]
pub struct TimingParams {
    /// Mean time a cycle runs past `u_cycle_time` (s).
    pub cycle_overrun: f64,
    /// Standard deviation of a cycle's period (s), seeded.
    pub cycle_jitter: f64,
    /// Cycles from a behavior's turn to the pump moving (1: the same cycle).
    pub turn_cycles: f64,
    /// Seconds before the cycle in which a held turn shows in
    /// `c_ballast_pumped` that the pump starts (comet: its `m_ballast_pumped`
    /// has run 0.5–1.2 s of the swing by that row). Only with `turn_cycles` 2
    /// or more; at most the cycle.
    pub pump_lead: f64,
    /// Largest altitude the altimeter measures (m).
    pub altimeter_range: f64,
    /// The next altimeter fix is due this fraction of the time to the bottom
    /// (altitude / dive rate) after the last (0: every cycle).
    pub altimeter_fraction: f64,
    /// Depth above which the altimeter does not ping (m, `u_alt_min_depth`).
    pub altimeter_min_depth: f64,
    /// Seconds between CTD samples (0: one sample at each cycle's start).
    pub ctd_period: f64,
}

/// comet 154's pump lead (s), as `gloc calibrate` fits it.
pub const PUMP_LEAD_COMET: f64 = 0.91;

impl TimingParams {
    /// An ideal clock: cycles of exactly `u_cycle_time`, the pump turning in
    /// the cycle a behavior turns, the altimeter read every cycle. For tests
    /// of the behaviors' logic against hand-worked 4-second arithmetic.
    pub fn ideal() -> TimingParams {
        TimingParams {
            cycle_overrun: 0.0,
            cycle_jitter: 0.0,
            turn_cycles: 1.0,
            pump_lead: 0.0,
            altimeter_range: f64::INFINITY,
            altimeter_fraction: 0.0,
            altimeter_min_depth: 0.0,
            ctd_period: 0.0,
        }
    }
}

impl Default for TimingParams {
    /// comet-2019-222-02-154.dbd (.ebd for the CTD): its cycles, turns,
    /// altimeter fixes and CTD samples (docs/simulator.md).
    fn default() -> TimingParams {
        TimingParams {
            cycle_overrun: 0.51,
            cycle_jitter: 0.13,
            turn_cycles: 2.0,
            pump_lead: PUMP_LEAD_COMET,
            altimeter_range: 33.0,
            altimeter_fraction: 0.4,
            altimeter_min_depth: 2.0,
            ctd_period: 1.06,
        }
    }
}

impl SimConfig {
    /// Sets one flight or energy constant by the name `gloc.toml`'s `[simulator]`
    /// table and `gloc run --sim` use ([`crate::settings::SIMULATOR_SETTINGS`]).
    /// The caller has checked the value's range; `false`: no such setting.
    pub fn set(&mut self, name: &str, value: f64) -> bool {
        let (flight, energy, timing) = (&mut self.flight, &mut self.energy, &mut self.timing);
        let navigation = &mut self.navigation;
        let field = match name {
            "gps_fix_time" => &mut self.gps_fix_time,
            "turn_time" => &mut navigation.turn_time,
            "max_turn_rate" => &mut navigation.max_turn_rate,
            "heading_bias_dive" => &mut navigation.heading_bias_dive,
            "heading_bias_climb" => &mut navigation.heading_bias_climb,
            "pump_in_rate" => &mut flight.pump_in_rate,
            "pitch_period" => &mut flight.pitch_period,
            "pitch_damping" => &mut flight.pitch_damping,
            "mass" => &mut flight.mass,
            "hull_volume" => &mut flight.hull_volume,
            "hull_compressibility" => &mut flight.hull_compressibility,
            "water_density" => &mut flight.water_density,
            "drag_cd0" => &mut flight.drag_cd0,
            "drag_cd1" => &mut flight.drag_cd1,
            "lift_slope" => &mut flight.lift_slope,
            "wing_area" => &mut flight.wing_area,
            "added_mass_along" => &mut flight.added_mass_along,
            "added_mass_across" => &mut flight.added_mass_across,
            "pitch_t1" => &mut flight.pitch_t1,
            "pitch_t2" => &mut flight.pitch_t2,
            "pitch_t3" => &mut flight.pitch_t3,
            "ballast_delay" => &mut flight.ballast_delay,
            "battery_ohms" => &mut energy.battery_ohms,
            "science_on_power" => &mut energy.science_on_power,
            "science_sleep_power" => &mut energy.science_sleep_power,
            "science_wake_time" => &mut energy.science_wake_time,
            "science_wake_joules" => &mut energy.science_wake_joules,
            "cycle_overrun" => &mut timing.cycle_overrun,
            "cycle_jitter" => &mut timing.cycle_jitter,
            "turn_cycles" => &mut timing.turn_cycles,
            "pump_lead" => &mut timing.pump_lead,
            "altimeter_range" => &mut timing.altimeter_range,
            "altimeter_fraction" => &mut timing.altimeter_fraction,
            "altimeter_min_depth" => &mut timing.altimeter_min_depth,
            "ctd_period" => &mut timing.ctd_period,
            "step" => &mut flight.step,
            "pump_max" => &mut flight.pump_max,
            "pump_rate" => &mut flight.pump_rate,
            "pitch_rate" => &mut flight.pitch_rate,
            "dive_power" => &mut energy.dive_power,
            "climb_power" => &mut energy.climb_power,
            "pump_out_j_per_cc" => &mut energy.pump_out_j_per_cc,
            "pump_out_j_per_cc_m" => &mut energy.pump_out_j_per_cc_m,
            "pump_in_j_per_cc" => &mut energy.pump_in_j_per_cc,
            "pitch_j_per_rad" => &mut energy.pitch_j_per_rad,
            "battery_wh" => &mut energy.battery_wh,
            "volts_full" => &mut energy.volts_full,
            "volts_empty" => &mut energy.volts_empty,
            _ => return false,
        };
        *field = value;
        true
    }
}

impl Default for SimConfig {
    fn default() -> SimConfig {
        SimConfig {
            seed: 1,
            water_depth: None,
            profile: None,
            flight: FlightParams::default(),
            energy: EnergyParams::default(),
            cycle_budget: gloc_engine::vm::DEFAULT_CYCLE_BUDGET,
            // comet 154: the first fix came 106 s after surfacing.
            gps_fix_time: 106.0,
            // 2010-05-24 00:00:00 UTC, the paper's era.
            start_time: 1_274_659_200.0,
            temperature_noise: 0.01,
            pressure_noise: 0.001,
            timing: TimingParams::default(),
            navigation: NavParams::default(),
        }
    }
}

/// Water depth when neither the run nor the mission gives one (m).
pub const DEFAULT_WATER_DEPTH: f64 = 40.0;

/// Why a simulation cannot start.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error("the mission has errors:\n{0}")]
    MissionErrors(String),
    #[error("the mission has no behaviors")]
    EmptyMission,
    /// A setting that sizes the work of a cycle is out of its range ([`CYCLE_TIME`]).
    #[error("{0}")]
    OutOfRange(String),
}

/// The `u_cycle_time` (s) a simulation accepts. A cycle is integrated in steps of at
/// most `step` (0.05 s or more), so a cycle of 1e29 s never ended and one of 1e9 s took
/// a second; an hour is a cycle no glider flies and 72,000 steps at most.
pub const CYCLE_TIME: std::ops::RangeInclusive<f64> = 0.1..=3600.0;

/// How the mission ended (or is ending).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EndReason {
    /// A surface behavior with `end_action` 0 finished.
    Completed,
    /// abend aborted the mission; the glider climbs to the surface.
    Aborted(AbortReason),
    /// The battery's energy (`battery_wh`) is used up: everything stops where
    /// the glider is.
    BatteryExhausted,
}

impl std::fmt::Display for EndReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EndReason::Completed => f.write_str("completed (surfaced with end_action quit)"),
            EndReason::Aborted(reason) => write!(f, "aborted: {}", reason.glider_name()),
            EndReason::BatteryExhausted => f.write_str("battery exhausted"),
        }
    }
}

/// The end of the mission and when it was decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionEnd {
    pub reason: EndReason,
    pub cycle: u64,
    /// Mission seconds.
    pub time: f64,
    /// Depth when it was decided.
    pub depth: f64,
}

/// Where the cycle stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Between cycles: `begin_cycle` comes next.
    BetweenCycles,
    /// At the cycle boundary: sensors published, the script's share not started.
    Boundary,
    /// The script has executed some instructions of this cycle's share.
    ScriptRunning,
    /// The script's share is over (yield, halt, trap, or no script).
    ScriptDone,
    /// The simulation is over: the mission ended and the glider is at the surface.
    Finished,
}

/// Indices of the sensors the simulator publishes or reads, resolved by name
/// once at construction. `None`: the active list lacks the sensor, and it is
/// simply not published.
#[derive(Clone, Copy, Debug, Default)]
struct SensorSlots {
    present_time: Option<usize>,
    cycle_number: Option<usize>,
    depth: Option<usize>,
    pressure: Option<usize>,
    depth_rate: Option<usize>,
    pitch: Option<usize>,
    altitude: Option<usize>,
    water_depth: Option<usize>,
    battery: Option<usize>,
    coulomb: Option<usize>,
    current: Option<usize>,
    speed: Option<usize>,
    ballast: Option<usize>,
    inflections: Option<usize>,
    water_temp: Option<usize>,
    water_pressure: Option<usize>,
    sci_present_time: Option<usize>,
    c_pitch: Option<usize>,
    c_battpos: Option<usize>,
    c_ballast: Option<usize>,
    c_science_on: Option<usize>,
    m_science_on: Option<usize>,
    hook: HookSensors,
    nav: NavSlots,
}

/// The navigation's sensors (`docs/simulator.md`, "Navigation").
#[derive(Clone, Copy, Debug, Default)]
struct NavSlots {
    /// `m_x_lmc`, `m_y_lmc` and `m_lat`, `m_lon`: the dead-reckoned position.
    position: XySlots,
    position_nmea: NmeaSlots,
    heading: Option<usize>,
    c_heading: Option<usize>,
    speed_estimated: Option<usize>,
    avg_speed: Option<usize>,
    water: XySlots,
    initial_water: XySlots,
    final_water: XySlots,
    prior_water: XySlots,
    dr_state: Option<usize>,
    dr_time: Option<usize>,
    dr_fix_time: Option<usize>,
    dr_postfix_time: Option<usize>,
    dr_surface: XySlots,
    initial_error: XySlots,
    adjusted_drift: XySlots,
    gps_dist_from_dr: Option<usize>,
    gps: XySlots,
    gps_nmea: NmeaSlots,
    gps_status: Option<usize>,
    gps_mag_var: Option<usize>,
    waypoint: XySlots,
    waypoint_nmea: NmeaSlots,
    dist_to_wpt: Option<usize>,
    hit_waypoint: Option<usize>,
}

impl NavSlots {
    fn resolve(find: &dyn Fn(&str) -> Option<usize>) -> NavSlots {
        let xy = |x: &str, y: &str| XySlots {
            x: find(x),
            y: find(y),
        };
        let nmea = |lat: &str, lon: &str| NmeaSlots {
            lat: find(lat),
            lon: find(lon),
        };
        NavSlots {
            position: xy("m_x_lmc", "m_y_lmc"),
            position_nmea: nmea("m_lat", "m_lon"),
            heading: find("m_heading"),
            c_heading: find("c_heading"),
            speed_estimated: find("m_is_speed_estimated"),
            avg_speed: find("m_avg_speed"),
            water: xy("m_water_vx", "m_water_vy"),
            initial_water: xy("m_initial_water_vx", "m_initial_water_vy"),
            final_water: xy("m_final_water_vx", "m_final_water_vy"),
            prior_water: xy("x_prior_seg_water_vx", "x_prior_seg_water_vy"),
            dr_state: find("x_dr_state"),
            dr_time: find("m_dr_time"),
            dr_fix_time: find("m_dr_fix_time"),
            dr_postfix_time: find("m_dr_postfix_time"),
            dr_surface: xy("m_dr_surf_x_lmc", "m_dr_surf_y_lmc"),
            initial_error: xy("m_dr_x_ini_err", "m_dr_y_ini_err"),
            adjusted_drift: xy("m_dr_x_ta_postfix_drift", "m_dr_y_ta_postfix_drift"),
            gps_dist_from_dr: find("m_gps_dist_from_dr"),
            gps: xy("m_gps_x_lmc", "m_gps_y_lmc"),
            gps_nmea: nmea("m_gps_lat", "m_gps_lon"),
            gps_status: find("m_gps_status"),
            gps_mag_var: find("m_gps_mag_var"),
            waypoint: xy("c_wpt_x_lmc", "c_wpt_y_lmc"),
            waypoint_nmea: nmea("c_wpt_lat", "c_wpt_lon"),
            dist_to_wpt: find("m_dist_to_wpt"),
            hit_waypoint: find("x_hit_a_waypoint"),
        }
    }
}

/// The slots of a vector's two sensors (east, north), each `None` when the
/// active list lacks it.
#[derive(Clone, Copy, Debug, Default)]
struct XySlots {
    x: Option<usize>,
    y: Option<usize>,
}

/// The slots of a position's NMEA latitude and longitude sensors.
#[derive(Clone, Copy, Debug, Default)]
struct NmeaSlots {
    lat: Option<usize>,
    lon: Option<usize>,
}

/// The sensor array written through slots the active list may lack.
struct SensorWrites<'s>(&'s mut [f64]);

impl SensorWrites<'_> {
    fn put(&mut self, slot: Option<usize>, value: f64) {
        if let Some(index) = slot {
            self.0[index] = value;
        }
    }

    fn put_xy(&mut self, slots: XySlots, value: Xy) {
        self.put(slots.x, value.x);
        self.put(slots.y, value.y);
    }

    /// `position` as NMEA, converted only when the list has either sensor.
    fn put_nmea(&mut self, slots: NmeaSlots, lmc: &Lmc, position: Xy) {
        if slots.lat.is_some() || slots.lon.is_some() {
            let (lat, lon) = lmc.xy_to_nmea(position);
            self.put(slots.lat, lat);
            self.put(slots.lon, lon);
        }
    }
}

impl SensorSlots {
    fn resolve(list: &SensorList) -> SensorSlots {
        let find = |name: &str| list.lookup(name).map(SensorId::index);
        SensorSlots {
            present_time: find("m_present_time"),
            cycle_number: find("m_cycle_number"),
            depth: find("m_depth"),
            pressure: find("m_pressure"),
            depth_rate: find("m_depth_rate"),
            pitch: find("m_pitch"),
            altitude: find("m_altitude"),
            water_depth: find("m_water_depth"),
            battery: find("m_battery"),
            coulomb: find("m_coulomb_amphr_total"),
            current: find("m_coulomb_current"),
            speed: find("m_speed"),
            ballast: find("m_ballast_pumped"),
            inflections: find("m_tot_num_inflections"),
            water_temp: find("sci_water_temp"),
            water_pressure: find("sci_water_pressure"),
            sci_present_time: find("sci_m_present_time"),
            c_pitch: find("c_pitch"),
            c_battpos: find("c_battpos"),
            c_ballast: find("c_ballast_pumped"),
            c_science_on: find("c_science_on"),
            m_science_on: find("m_science_on"),
            hook: HookSensors {
                behs: find("sci_ruhp_behs"),
                dive_depth: find("sci_ruhp_dive_depth"),
                climb_depth: find("sci_ruhp_climb_depth"),
                heading: find("sci_ruhp_heading"),
            },
            nav: NavSlots::resolve(&find),
        }
    }
}

/// Sensor values the simulator gives before the mission's `sensor:` lines when
/// the sensor list has no default of its own.
const SIM_DEFAULTS: &[(&str, f64)] = &[
    ("u_cycle_time", 4.0),
    ("u_reqd_depth_at_surface", 2.0),
    ("f_nominal_pitch", 0.4538),
    ("f_nominal_dive_rate", 0.15),
    ("m_battery", 13.74),
];

/// The script behavior's machine and what it did.
#[derive(Clone, Debug)]
struct Script {
    machine: Machine,
    /// The last end of a share (for the summary and the debugger).
    last_end: Option<CycleEnd>,
}

/// A running simulation. See the module documentation for the phases.
#[derive(Clone, Debug)]
pub struct Simulation {
    sensor_list: Arc<SensorList>,
    mission_name: String,
    sensors: Vec<f64>,
    slots: SensorSlots,
    behaviors: Vec<Behavior>,
    /// Index of the script behavior in `behaviors` (top first), if it runs.
    script_index: Option<usize>,
    script: Option<Script>,
    vehicle: Vehicle,
    flight: FlightParams,
    energy: EnergyParams,
    profile: TemperatureProfile,
    water_depth: f64,
    cycle_time: f64,
    surface_depth: f64,
    start_time: f64,
    temperature_noise: f64,
    pressure_noise: f64,
    rng: Rng,
    timing: TimingParams,
    /// The cycle period's own random stream, so that jitter leaves the sensor
    /// noise of a seed unchanged.
    clock_rng: Rng,
    /// Mission seconds at the start of the next cycle.
    next_time: f64,
    /// The buoyancy command the pump follows, and cycles a turn is still held.
    applied_buoyancy: Option<f64>,
    turn_hold: u32,
    /// The command a held turn takes next cycle, set in its last held cycle
    /// (the pump starts `pump_lead` before that cycle ends).
    turn_starting: Option<f64>,
    /// The science computer: awake, or waking until the given mission second.
    science: Science,
    /// Wakes so far.
    science_wakes: u64,
    /// Mission seconds when the next altimeter ping is due, and the last reading.
    altimeter_due: f64,
    altimeter_reading: f64,
    /// Cycles begun so far; the current cycle's number while one is under way.
    cycle: u64,
    /// Mission seconds at the start of the current cycle.
    time: f64,
    phase: Phase,
    commands: Commands,
    last_surface_time: f64,
    end: Option<MissionEnd>,
    /// Per-cycle outputs (cleared each cycle, capacity kept).
    printed: String,
    /// For each line in `printed`: where it ends (after its `\n`) and the pc of the
    /// instruction that printed it.
    print_sites: Vec<(usize, Pc)>,
    stored: Vec<SensorId>,
    events: Vec<BehaviorEvent>,
    warnings: Vec<String>,
    min_depth: f64,
    max_depth: f64,
    /// The horizontal state (truth, dead reckoning, GPS, current estimate).
    navigation: Navigation,
    /// What the behaviors see of it, and what the goto behaviors report.
    nav_view: NavView,
    /// `s_mag_var` (rad), published as `m_gps_mag_var`.
    mag_var: f64,
}

/// The sensor array a run starts from: the list's defaults, the simulator's own where
/// the list has none (`SIM_DEFAULTS`), then the mission's `sensor:` settings. A setting
/// the list lacks is S0106 (`Mission::check_sensor_settings`, reported by the front ends
/// with a caret).
fn initial_sensors(mission: &Mission, sensor_list: &SensorList) -> Vec<f64> {
    let mut sensors = sensor_list.initial_values();
    for &(name, value) in SIM_DEFAULTS {
        if let Some(id) = sensor_list.lookup(name) {
            if sensor_list
                .get(id)
                .is_some_and(|sensor| sensor.default.is_none())
            {
                sensors[id.index()] = value;
            }
        }
    }
    for setting in &mission.sensor_settings {
        if let Some(id) = sensor_list.lookup(&setting.name) {
            sensors[id.index()] = setting.value;
        }
    }
    sensors
}

/// `u_cycle_time` within [`CYCLE_TIME`], or an error naming where it was set.
fn check_cycle_time(mission: &Mission, cycle_time: f64) -> Result<(), SimError> {
    if !CYCLE_TIME.contains(&cycle_time) {
        // From the mission's last setting of it, or else the sensor list's default.
        let origin = match mission
            .sensor_settings
            .iter()
            .rev()
            .find(|setting| setting.name.eq_ignore_ascii_case("u_cycle_time"))
        {
            Some(setting) => {
                let (path, line, column) = mission.line_col(setting.at.file, setting.name_span);
                format!("{}:{line}:{column}: ", path.display())
            }
            None => "the sensor list's default: ".to_string(),
        };
        let value = if cycle_time.abs() < 1e6 {
            format!("{cycle_time}")
        } else {
            format!("{cycle_time:e}")
        };
        return Err(SimError::OutOfRange(format!(
            "{origin}u_cycle_time {value} s is out of range: the simulator runs cycles of {} to {} s",
            CYCLE_TIME.start(),
            CYCLE_TIME.end()
        )));
    }
    Ok(())
}

/// Warnings for the start and stop conditions the simulator does not model.
fn unmodelled_conditions(mission: &Mission) -> Vec<String> {
    let mut warnings = Vec::new();
    for spec in mission.known_behaviors() {
        for name in ["start_when", "stop_when"] {
            if let Some(code) = spec.arg(name) {
                if !condition_is_modelled(code as i64) {
                    let (path, line, column) = mission.line_col(spec.at.file, spec.at.span);
                    warnings.push(format!(
                        "{}:{line}:{column}: warning: {} {name} {code} is not modelled by the simulator: it never holds",
                        path.display(),
                        spec.name
                    ));
                }
            }
        }
    }
    warnings
}

impl Simulation {
    /// Sets up a mission. `script` is the checked program of the `gloc`
    /// behavior; without one, a `behavior: gloc` in the mission stays idle.
    pub fn new(
        mission: &Mission,
        sensor_list: Arc<SensorList>,
        script: Option<Arc<Program>>,
        config: &SimConfig,
    ) -> Result<Simulation, SimError> {
        if mission.has_errors() {
            return Err(SimError::MissionErrors(mission.render_plain()));
        }
        let mut warnings = Vec::new();
        let sensors = initial_sensors(mission, &sensor_list);
        let mut mission_set = |name: &str| -> Option<f64> {
            mission
                .sensor_settings
                .iter()
                .rev()
                .find(|setting| setting.name.eq_ignore_ascii_case(name))
                .map(|setting| setting.value)
        };
        let water_depth = config
            .water_depth
            .or_else(|| mission_set("s_water_depth_avg").filter(|depth| *depth > 0.0))
            .unwrap_or(DEFAULT_WATER_DEPTH);
        let profile = match &config.profile {
            Some(profile) => profile.clone(),
            None => shelf_profile(&mut mission_set),
        };
        let read = |name: &str, fallback: f64| {
            sensor_list
                .lookup(name)
                .map(|id| sensors[id.index()])
                .filter(|value| *value > 0.0)
                .unwrap_or(fallback)
        };
        let cycle_time = read("u_cycle_time", 4.0);
        check_cycle_time(mission, cycle_time)?;
        let surface_depth = read("u_reqd_depth_at_surface", 2.0);
        let value = |name: &str| sensor_list.lookup(name).map(|id| sensors[id.index()]);
        let navigation = Navigation::new(
            &nav_setup(&mut mission_set, &value, &config.flight),
            config.navigation.clone(),
            config.gps_fix_time,
        );
        let mag_var = mission_set("s_mag_var").filter(|value| value.is_finite());

        // b_arg values ≥ 1,000,000 name u_mission_param_a … _x.
        let param_values: Vec<Option<f64>> = (b'a'..=b'x')
            .map(|letter| {
                sensor_list
                    .lookup(&format!("u_mission_param_{}", letter as char))
                    .map(|id| sensors[id.index()])
            })
            .collect();
        let param = |value: f64| -> f64 {
            if value >= 1_000_000.0 {
                let slot = (value - 1_000_000.0) as usize;
                param_values.get(slot).copied().flatten().unwrap_or(value)
            } else {
                value
            }
        };
        let placement = if script.is_some() {
            ScriptPlacement::Insert
        } else {
            ScriptPlacement::None
        };
        let behaviors = build_stack(mission, &param, config.gps_fix_time, placement);
        if behaviors.is_empty() {
            return Err(SimError::EmptyMission);
        }
        warnings.extend(unmodelled_conditions(mission));
        let slots = SensorSlots::resolve(&sensor_list);
        if behaviors
            .iter()
            .any(|behavior| behavior.kind == BehaviorKind::Hook)
            && slots.hook.behs.is_none()
        {
            warnings.push(
                "warning: the sensor list has no `sci_ruhp_behs`: the hook behavior will command nothing"
                    .to_string(),
            );
        }
        let script_index = match script {
            Some(_) => behaviors
                .iter()
                .position(|behavior| behavior.kind == BehaviorKind::Gloc),
            None => None,
        };
        let script = script.map(|program| Script {
            machine: Machine::new(
                program,
                MachineConfig {
                    cycle_budget: config.cycle_budget,
                },
            ),
            last_end: None,
        });
        // Floating at the surface, pump full out.
        let mut vehicle = Vehicle::default();
        vehicle.ballast = config.flight.pump_max;
        Ok(Simulation {
            sensor_list,
            mission_name: mission.name.clone(),
            sensors,
            slots,
            behaviors,
            script_index,
            script,
            vehicle,
            flight: config.flight.clone(),
            energy: config.energy.clone(),
            profile,
            water_depth,
            cycle_time,
            surface_depth,
            start_time: config.start_time,
            temperature_noise: config.temperature_noise,
            pressure_noise: config.pressure_noise,
            rng: Rng::new(config.seed),
            timing: config.timing.clone(),
            clock_rng: Rng::new(config.seed ^ 0x00C1_0C4C_1C1E),
            next_time: 0.0,
            applied_buoyancy: None,
            turn_hold: 0,
            turn_starting: None,
            science: Science::Asleep,
            science_wakes: 0,
            altimeter_due: 0.0,
            altimeter_reading: -1.0,
            cycle: 0,
            time: 0.0,
            phase: Phase::BetweenCycles,
            commands: Commands::default(),
            last_surface_time: 0.0,
            end: None,
            printed: String::with_capacity(256),
            print_sites: Vec::new(),
            stored: Vec::with_capacity(16),
            events: Vec::with_capacity(16),
            warnings,
            min_depth: 0.0,
            max_depth: 0.0,
            nav_view: NavView::new(navigation.lmc),
            navigation,
            mag_var: mag_var.unwrap_or(0.0),
        })
    }

    /// Runs one whole control cycle. False once the simulation is finished.
    pub fn step_cycle(&mut self) -> bool {
        if !self.begin_cycle() {
            return false;
        }
        self.run_script();
        self.finish_cycle();
        true
    }

    /// Phase 1: advance the clock, publish the measured sensors, step the
    /// behaviors below the script. False (and nothing done) once finished.
    /// Calling it again at the boundary is a no-op.
    pub fn begin_cycle(&mut self) -> bool {
        match self.phase {
            Phase::Finished => return false,
            Phase::BetweenCycles => {}
            _ => return true,
        }
        self.time = self.next_time;
        self.printed.clear();
        self.print_sites.clear();
        self.stored.clear();
        self.events.clear();
        self.commands = Commands::default();
        if self.vehicle.depth <= SURFACED_DEPTH {
            self.last_surface_time = self.time;
        }
        // `x_hit_a_waypoint` shows last cycle's hit, then clears for this one.
        self.publish();
        self.nav_view.hit_waypoint = false;
        let below = match self.script_index {
            Some(index) => index + 1,
            None => 0,
        };
        self.step_behaviors(below, self.behaviors.len());
        self.phase = Phase::Boundary;
        if self.script_index.is_none() {
            self.phase = Phase::ScriptDone;
        }
        true
    }

    /// Phase 2: the script's share of this cycle, to its `yield` (or halt,
    /// trap, overrun). `None` when no script runs this cycle (none loaded, its
    /// behavior not active, already halted or trapped, the mission aborting).
    pub fn run_script(&mut self) -> Option<CycleEnd> {
        if !self.enter_script() {
            return None;
        }
        let end = {
            let (machine, mut host) = self.script_parts()?;
            machine.run_cycle(&mut host)
        };
        self.end_script_share(end);
        Some(end)
    }

    /// Executes one script instruction (for a debugger). `None`: the share
    /// goes on; `Some(end)`: the share is over (or there is none to run:
    /// then `Some(CycleEnd::Yielded)`).
    pub fn script_step(&mut self) -> Option<CycleEnd> {
        self.script_run(1)
    }

    /// Executes at most `max_instructions` script instructions (fused, for a debugger
    /// that knows no breakpoint can stop before them); otherwise as `script_step`.
    pub fn script_run(&mut self, max_instructions: u64) -> Option<CycleEnd> {
        if !self.enter_script() {
            return Some(CycleEnd::Yielded);
        }
        let step = {
            let (machine, mut host) = self.script_parts()?;
            machine.run_for(&mut host, max_instructions)
        };
        match step {
            None => {
                self.phase = Phase::ScriptRunning;
                None
            }
            Some(end) => {
                self.end_script_share(end);
                Some(end)
            }
        }
    }

    /// The script's machine and a [`Host`] view of the sensor array, for a
    /// debugger that inspects or drives the machine itself. Prefer
    /// [`Simulation::script_step`] to step, so the cycle's phase stays right.
    pub fn script_parts(&mut self) -> Option<(&mut Machine, SimHost<'_>)> {
        let script = self.script.as_mut()?;
        Some((
            &mut script.machine,
            SimHost {
                sensors: &mut self.sensors,
                printed: &mut self.printed,
                print_sites: &mut self.print_sites,
                stored: &mut self.stored,
            },
        ))
    }

    /// Phase 3: the rest of the script's share (if a debugger left it
    /// unfinished), the behaviors above the script, arbitration, and the
    /// flight model for one cycle.
    pub fn finish_cycle(&mut self) {
        if self.phase == Phase::Finished {
            return;
        }
        if self.phase == Phase::BetweenCycles && !self.begin_cycle() {
            return;
        }
        if self.phase != Phase::ScriptDone {
            self.run_script();
        }
        if let Some(index) = self.script_index {
            self.step_behaviors(0, index);
        }
        let aborting = matches!(
            self.end,
            Some(MissionEnd {
                reason: EndReason::Aborted(_),
                ..
            })
        );
        let (buoyancy, pitch) = if aborting {
            // An abort surfaces the glider whatever the behaviors want.
            (self.flight.pump_max, crate::behaviors::NOMINAL_PITCH)
        } else {
            (
                self.commands
                    .buoyancy
                    .map(|(value, _)| value)
                    .unwrap_or(self.vehicle.ballast),
                self.commands
                    .pitch
                    .map(|(value, _)| value)
                    .unwrap_or(self.vehicle.pitch),
            )
        };
        let buoyancy = self.turn_latency(buoyancy, aborting);
        let control = if aborting {
            crate::flight::PitchControl::Servo
        } else {
            self.commands.pitch_control
        };
        // The pitch command is an angle, or with the battery held its position (in).
        let slot = match control {
            crate::flight::PitchControl::Servo => self.slots.c_pitch,
            crate::flight::PitchControl::Battpos => self.slots.c_battpos,
        };
        if let Some(index) = slot {
            self.sensors[index] = pitch;
        }
        if let Some(index) = self.slots.c_ballast {
            // The glider clips the command to what its pump can do.
            self.sensors[index] = buoyancy.clamp(-self.flight.pump_max, self.flight.pump_max);
        }
        let period = self.cycle_period();
        let science_watts = self.science_power();
        let distance_before = self.vehicle.distance;
        // The last held cycle of a turn: the pump starts `pump_lead` before its end.
        let lead = match self.turn_starting {
            Some(_) => self.timing.pump_lead.clamp(0.0, period),
            None => 0.0,
        };
        let legs = [
            (period - lead, buoyancy),
            (lead, self.turn_starting.unwrap_or(buoyancy)),
        ];
        let (joules_before, volts) = (
            self.vehicle.energy_joules,
            self.vehicle.battery_volts(&self.energy).max(1e-3),
        );
        for (seconds, volume) in legs {
            if seconds > 0.0 {
                self.vehicle.fly(
                    seconds,
                    volume,
                    pitch,
                    control,
                    self.water_depth,
                    &self.flight,
                    &self.energy,
                    science_watts,
                );
            }
        }
        if lead > 0.0 && period > 0.0 {
            // m_coulomb_current is the cycle's mean, not its last part's.
            self.vehicle.current = (self.vehicle.energy_joules - joules_before) / period / volts;
        }
        self.turn_starting = None;
        self.next_time = self.time + period;
        self.navigation.advance(&CycleMotion {
            time: self.next_time,
            period,
            through_water: self.vehicle.distance - distance_before,
            depth: self.vehicle.depth,
            depth_rate: self.vehicle.depth_rate,
            pitch: self.vehicle.pitch,
            angle_of_attack: self.vehicle.angle_of_attack,
            surface_depth: self.surface_depth,
            heading_command: match aborting {
                true => None,
                false => self.commands.heading.map(|(value, _)| value),
            },
            surfacing: aborting
                || self.end.is_some()
                || self.commands.buoyancy.is_some_and(|(_, owner)| {
                    self.behaviors
                        .get(owner)
                        .is_some_and(|behavior| behavior.kind == BehaviorKind::Surface)
                }),
        });
        if self.vehicle.exhausted(&self.energy) {
            if !matches!(
                self.end.map(|end| end.reason),
                Some(EndReason::Completed | EndReason::BatteryExhausted)
            ) {
                self.end = Some(MissionEnd {
                    reason: EndReason::BatteryExhausted,
                    cycle: self.cycle,
                    time: self.next_time,
                    depth: self.vehicle.depth,
                });
            }
            self.min_depth = self.min_depth.min(self.vehicle.depth);
            self.max_depth = self.max_depth.max(self.vehicle.depth);
            self.cycle += 1;
            self.phase = Phase::Finished;
            return;
        }
        self.min_depth = self.min_depth.min(self.vehicle.depth);
        self.max_depth = self.max_depth.max(self.vehicle.depth);
        self.cycle += 1;
        self.phase = match self.end {
            Some(end) if !matches!(end.reason, EndReason::Aborted(_)) => Phase::Finished,
            Some(_) if self.vehicle.depth <= SURFACED_DEPTH => Phase::Finished,
            _ => Phase::BetweenCycles,
        };
    }

    /// The pump follows a reversed buoyancy command only `turn_cycles` cycles
    /// after the behaviors turned (dynamic control starts the inflection on the
    /// next cycle: comet's logs show the pump moving a cycle after the depth
    /// crossed the target). An abort is not held.
    fn turn_latency(&mut self, wanted: f64, aborting: bool) -> f64 {
        let applied = match self.applied_buoyancy {
            Some(applied) if !aborting => applied,
            _ => {
                self.applied_buoyancy = Some(wanted);
                self.turn_hold = 0;
                return wanted;
            }
        };
        let reversed = applied != 0.0 && wanted.signum() != applied.signum();
        if !reversed {
            self.turn_hold = 0;
            self.applied_buoyancy = Some(wanted);
            return wanted;
        }
        let hold = (self.timing.turn_cycles.round() as u32).saturating_sub(1);
        if self.turn_hold < hold {
            self.turn_hold += 1;
            if self.turn_hold == hold {
                self.turn_starting = Some(wanted);
            }
            return applied;
        }
        self.turn_hold = 0;
        self.applied_buoyancy = Some(wanted);
        wanted
    }

    /// The science computer's state for this cycle, from `c_science_on` (the
    /// script or a behavior sets it; 1 wakes, 0 puts to sleep), and its power.
    /// A wake takes `science_wake_time` at full power plus
    /// `science_wake_joules`; `m_science_on` reads 1 once it is awake.
    fn science_power(&mut self) -> f64 {
        let wanted = self
            .slots
            .c_science_on
            .is_some_and(|index| self.sensors[index] != 0.0 && self.sensors[index].is_finite());
        let energy = &self.energy;
        self.science = match (self.science, wanted) {
            (_, false) => Science::Asleep,
            (Science::Asleep, true) => {
                self.science_wakes += 1;
                self.vehicle.energy_joules += energy.science_wake_joules;
                self.vehicle.energy_use.science += energy.science_wake_joules;
                Science::Waking(self.time + energy.science_wake_time)
            }
            (Science::Waking(until), true) if self.time >= until => Science::Awake,
            (state, true) => state,
        };
        if let Some(index) = self.slots.m_science_on {
            self.sensors[index] = f64::from(u8::from(self.science == Science::Awake));
        }
        match self.science {
            Science::Asleep => energy.science_sleep_power,
            _ => energy.science_on_power,
        }
    }

    /// This cycle's period: `u_cycle_time` plus the mean overrun and a seeded
    /// spread, never below half of `u_cycle_time`.
    fn cycle_period(&mut self) -> f64 {
        let timing = &self.timing;
        let mut period = self.cycle_time + timing.cycle_overrun;
        if timing.cycle_jitter > 0.0 {
            // The sum of two uniforms (triangular): the spread asked for, at a
            // fraction of a normal's cost (no logarithm or cosine per cycle).
            let half_width = timing.cycle_jitter * 6f64.sqrt();
            let sum = self.clock_rng.uniform() + self.clock_rng.uniform() - 1.0;
            period += half_width * sum;
        }
        period.max(0.5 * self.cycle_time)
    }

    fn enter_script(&mut self) -> bool {
        match self.phase {
            Phase::Boundary | Phase::ScriptRunning => {}
            _ => return false,
        }
        let Some(index) = self.script_index else {
            self.phase = Phase::ScriptDone;
            return false;
        };
        if self.phase == Phase::Boundary {
            // The script behavior's own state machine (start_when/stop_when).
            self.step_behaviors(index, index + 1);
        }
        let runnable = self.end.is_none()
            && self.behaviors[index].is_active()
            && self
                .script
                .as_ref()
                .is_some_and(|script| script.machine.status() == Status::Running);
        if !runnable {
            self.phase = Phase::ScriptDone;
        }
        runnable
    }

    fn end_script_share(&mut self, end: CycleEnd) {
        if let Some(script) = self.script.as_mut() {
            script.last_end = Some(end);
        }
        self.phase = Phase::ScriptDone;
    }

    /// Steps behaviors `from..to` (indices top first) bottom-up.
    fn step_behaviors(&mut self, from: usize, to: usize) {
        if self.end.is_some() {
            return;
        }
        let navigation = &self.navigation;
        self.nav_view.position = navigation.dead_reckoned;
        self.nav_view.water = navigation.water;
        self.nav_view.avg_speed = navigation.avg_speed;
        let mut world = World {
            time: self.time,
            depth: self.vehicle.depth,
            depth_rate: self.vehicle.depth_rate,
            altitude: (self.water_depth - self.vehicle.depth).max(0.0),
            battery_volts: self.vehicle.battery_volts(&self.energy),
            last_surface_time: self.last_surface_time,
            surface_depth: self.surface_depth,
            sensors: &mut self.sensors,
            hook_sensors: self.slots.hook,
            commands: &mut self.commands,
            nav: &mut self.nav_view,
        };
        for index in (from..to).rev() {
            let outcome = self.behaviors[index].step(&mut Turn {
                index,
                world: &mut world,
                events: &mut self.events,
            });
            let reason = match outcome {
                Outcome::Continue => continue,
                Outcome::Abort(reason) => EndReason::Aborted(reason),
                Outcome::MissionComplete => EndReason::Completed,
            };
            self.end = Some(MissionEnd {
                reason,
                cycle: self.cycle,
                time: self.time,
                depth: self.vehicle.depth,
            });
            return;
        }
    }

    /// Writes the measured sensors for the start of this cycle.
    fn publish(&mut self) {
        let vehicle = self.vehicle;
        let slots = self.slots;
        let present = self.start_time + self.time;
        let true_altitude = (self.water_depth - vehicle.depth).max(0.0);
        let timing = &self.timing;
        // A ping: when due, diving (or every cycle with fraction 0), below the
        // minimum depth; a fix only within range.
        let diving = vehicle.depth_rate > 0.0 || timing.altimeter_fraction == 0.0;
        if self.time >= self.altimeter_due && diving && vehicle.depth >= timing.altimeter_min_depth
        {
            if true_altitude <= timing.altimeter_range {
                self.altimeter_reading = true_altitude;
            }
            let rate = vehicle.depth_rate.max(MIN_ALTIMETER_RATE);
            self.altimeter_due = self.time + timing.altimeter_fraction * true_altitude / rate;
        }
        let altitude = self.altimeter_reading;
        // The CTD samples every `ctd_period` s on its own clock; the flight
        // computer sees its latest sample, taken up to a period before the
        // cycle's start, at the depth the glider had then.
        let (sample_time, sample_depth) = if self.timing.ctd_period > 0.0 {
            let at = (self.time / self.timing.ctd_period).floor() * self.timing.ctd_period;
            let depth = (vehicle.depth - vehicle.depth_rate * (self.time - at)).max(0.0);
            (at, depth)
        } else {
            (self.time, vehicle.depth)
        };
        let temperature =
            self.profile.temperature(sample_depth) + self.temperature_noise * self.rng.normal();
        let pressure = sample_depth / 10.0 + self.pressure_noise * self.rng.normal();
        let sample_present = self.start_time + sample_time;
        let volts = vehicle.battery_volts(&self.energy);
        let mut sensors = SensorWrites(&mut self.sensors);
        sensors.put(slots.present_time, present);
        sensors.put(slots.sci_present_time, sample_present);
        sensors.put(slots.cycle_number, self.cycle as f64);
        sensors.put(slots.depth, vehicle.depth);
        sensors.put(slots.pressure, vehicle.depth / 10.0);
        sensors.put(slots.depth_rate, vehicle.depth_rate);
        sensors.put(slots.pitch, vehicle.pitch);
        sensors.put(slots.altitude, altitude);
        sensors.put(slots.water_depth, self.water_depth);
        sensors.put(slots.battery, volts);
        sensors.put(slots.coulomb, vehicle.amp_hours);
        sensors.put(slots.current, vehicle.current);
        // The firmware's m_speed: the dead reckoning's (the glide angle's, or the
        // mean speed below 11.3° of pitch; 0 at the surface).
        sensors.put(slots.speed, self.navigation.speed);
        sensors.put(slots.ballast, vehicle.ballast);
        sensors.put(slots.inflections, vehicle.inflections as f64);
        sensors.put(slots.water_temp, temperature);
        sensors.put(slots.water_pressure, pressure.max(0.0));
        publish_navigation(
            &slots.nav,
            &self.navigation,
            &self.nav_view,
            self.mag_var,
            &mut sensors,
        );
    }

    // ----- accessors -----

    /// The cycle under way, or the next one between cycles (0-based).
    pub fn cycle(&self) -> u64 {
        self.cycle
    }

    /// Cycles completed.
    pub fn cycles_done(&self) -> u64 {
        match self.phase {
            Phase::BetweenCycles | Phase::Finished => self.cycle,
            _ => self.cycle,
        }
    }

    /// Mission seconds at the start of the current cycle (between cycles: of the next).
    pub fn time(&self) -> f64 {
        match self.phase {
            Phase::BetweenCycles | Phase::Finished => self.next_time,
            _ => self.time,
        }
    }

    /// `m_present_time` (Unix seconds) matching [`Simulation::time`].
    pub fn present_time(&self) -> f64 {
        self.start_time + self.time()
    }

    /// `u_cycle_time`: the period the glider asks for.
    pub fn cycle_time(&self) -> f64 {
        self.cycle_time
    }

    /// The mean period a cycle really takes: `u_cycle_time` plus the overrun.
    pub fn mean_cycle_period(&self) -> f64 {
        (self.cycle_time + self.timing.cycle_overrun).max(0.5 * self.cycle_time)
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    pub fn is_finished(&self) -> bool {
        self.phase == Phase::Finished
    }

    pub fn depth(&self) -> f64 {
        self.vehicle.depth
    }

    pub fn pitch(&self) -> f64 {
        self.vehicle.pitch
    }

    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }

    pub fn water_depth(&self) -> f64 {
        self.water_depth
    }

    pub fn energy_joules(&self) -> f64 {
        self.vehicle.energy_joules
    }

    pub fn amp_hours(&self) -> f64 {
        self.vehicle.amp_hours
    }

    /// Energy used by each consumer (J).
    pub fn energy_use(&self) -> EnergyUse {
        self.vehicle.energy_use
    }

    /// The battery's terminal voltage now (V).
    pub fn battery_volts(&self) -> f64 {
        self.vehicle.battery_volts(&self.energy)
    }

    /// The water's true temperature at the glider (°C, without the CTD's noise).
    pub fn water_temperature(&self) -> f64 {
        self.profile.temperature(self.vehicle.depth)
    }

    /// Times the science computer was woken.
    pub fn science_wakes(&self) -> u64 {
        self.science_wakes
    }

    /// The battery's capacity (J).
    pub fn battery_joules(&self) -> f64 {
        self.energy.battery_wh * 3600.0
    }

    /// (shallowest, deepest) depth flown so far.
    pub fn depth_range(&self) -> (f64, f64) {
        (self.min_depth, self.max_depth)
    }

    /// How the mission ended, once it has.
    pub fn end(&self) -> Option<MissionEnd> {
        self.end
    }

    /// The behaviors, highest priority first.
    pub fn behaviors(&self) -> &[Behavior] {
        &self.behaviors
    }

    /// Names of the active behaviors, highest priority first.
    pub fn active_behaviors(&self) -> impl Iterator<Item = &str> {
        self.behaviors
            .iter()
            .filter(|behavior| behavior.is_active())
            .map(|behavior| behavior.name.as_str())
    }

    /// This cycle's commands so far (the winners, with the behavior index).
    pub fn commands(&self) -> &Commands {
        &self.commands
    }

    /// What behaviors did this cycle (starts, completions, turns).
    pub fn events(&self) -> &[BehaviorEvent] {
        &self.events
    }

    /// The sensor array, indexed by `SensorId`.
    pub fn sensors(&self) -> &[f64] {
        &self.sensors
    }

    pub fn sensor(&self, id: SensorId) -> Option<f64> {
        self.sensors.get(id.index()).copied()
    }

    /// Sets a sensor (a debugger injecting a value). False when out of range.
    pub fn set_sensor(&mut self, id: SensorId, value: f64) -> bool {
        match self.sensors.get_mut(id.index()) {
            Some(slot) => {
                *slot = value;
                true
            }
            None => false,
        }
    }

    pub fn sensor_list(&self) -> &Arc<SensorList> {
        &self.sensor_list
    }

    pub fn mission_name(&self) -> &str {
        &self.mission_name
    }

    /// Lines the script printed this cycle.
    pub fn printed(&self) -> impl Iterator<Item = &str> {
        self.printed.lines()
    }

    /// What the script printed this cycle, each line ended by `\n` (a debugger compares
    /// its length to find new lines without splitting it).
    pub fn printed_text(&self) -> &str {
        &self.printed
    }

    /// For each line of [`Simulation::printed_text`], in order: the byte where it ends
    /// (after its `\n`) and the pc of the instruction that printed it.
    pub fn print_sites(&self) -> &[(usize, Pc)] {
        &self.print_sites
    }

    /// Sensors the script stored this cycle, in first-store order.
    pub fn stored(&self) -> &[SensorId] {
        &self.stored
    }

    pub fn machine(&self) -> Option<&Machine> {
        self.script.as_ref().map(|script| &script.machine)
    }

    /// How the script's last share ended.
    pub fn script_last_end(&self) -> Option<CycleEnd> {
        self.script.as_ref().and_then(|script| script.last_end)
    }

    /// The trap that stopped the script, if one did.
    pub fn script_trap(&self) -> Option<Trap> {
        match self.script.as_ref()?.machine.status() {
            Status::Trapped(trap) => Some(trap),
            _ => None,
        }
    }

    /// The horizontal state: true and dead-reckoned positions, current, GPS.
    pub fn navigation(&self) -> &Navigation {
        &self.navigation
    }

    /// Sets the true depth-averaged current from now on (m/s, x east, y north):
    /// a forecast's current field, which varies in time and space, sets it
    /// before each cycle. The glider's belief is not touched.
    pub fn set_true_water(&mut self, water: Xy) {
        if water.x.is_finite() && water.y.is_finite() {
            self.navigation.true_water = water;
        }
    }

    /// Sets the water depth under the glider from now on (m, positive): a
    /// forecast's bathymetry sets it before each cycle. Ignored unless finite
    /// and positive.
    pub fn set_water_depth(&mut self, depth: f64) {
        if depth.is_finite() && depth > 0.0 {
            self.water_depth = depth;
        }
    }

    /// Starts the mission's timers `seconds` before the run: the behaviors
    /// last started and ended then (`when_secs` of start_when 6, 9 and 10
    /// counts from there; start_when 12 counts from the last time at the
    /// surface, which a run starting at the surface sets itself). A
    /// forecast that starts at a glider's last fix gives the time since its
    /// surfacing began, so the next timed surfacing comes when the glider's.
    /// Call before the first cycle; a negative or non-finite value is ignored.
    pub fn start_timers_before(&mut self, seconds: f64) {
        if !(seconds.is_finite() && seconds > 0.0) || self.cycle > 0 {
            return;
        }
        for behavior in &mut self.behaviors {
            behavior.shift_timers(-seconds);
        }
    }

    /// Starts the battery part used: `used_fraction` of the energy model's
    /// capacity (`battery_wh`) spent, and `m_coulomb_amphr_total` at
    /// `amp_hours`, as a forecast from a glider's logs finds them. Call before
    /// the first cycle; a value that is not finite, or a fraction outside 0…1,
    /// is ignored.
    pub fn start_battery(&mut self, used_fraction: f64, amp_hours: f64) {
        if self.cycle > 0 {
            return;
        }
        if used_fraction.is_finite() && (0.0..=1.0).contains(&used_fraction) {
            self.vehicle.energy_joules = used_fraction * self.energy.battery_wh * 3600.0;
        }
        if amp_hours.is_finite() {
            self.vehicle.amp_hours = amp_hours;
        }
    }

    /// The waypoint a goto behavior steers to (LMC), if one does.
    pub fn waypoint(&self) -> Option<Xy> {
        self.nav_view.waypoint
    }

    /// What the behaviors know and report of the journey: the glider's belief, the
    /// waypoint, `m_dist_to_wpt` as last steered, and whether a waypoint was reached
    /// in this cycle (cleared when the next cycle begins).
    pub fn nav_view(&self) -> &NavView {
        &self.nav_view
    }

    /// The active goto behavior's waypoint: its place in the behavior's list
    /// (0-based) and the list's length.
    pub fn waypoint_index(&self) -> Option<(usize, usize)> {
        self.behaviors
            .iter()
            .filter(|behavior| behavior.is_active())
            .find_map(Behavior::waypoint_index)
    }

    /// Setup warnings (unknown sensors, unmodelled conditions, missing hook sensors).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

/// The science computer's power state.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Science {
    Asleep,
    /// Waking until this mission second.
    Waking(f64),
    Awake,
}

/// Descent rate (m/s) below which the altimeter's schedule assumes this one.
const MIN_ALTIMETER_RATE: f64 = 0.05;

/// Depth at or above which the glider counts as floating at the surface (m).
const SURFACED_DEPTH: f64 = 0.3;

/// The navigation's start from the mission: `s_ini_lat`/`s_ini_lon` (else
/// [`DEFAULT_START_NMEA`]), the true current from `s_water_speed` and
/// `s_water_direction` (the direction it flows to), the glider's belief from
/// the sensor array (`m_water_vx/vy`, `m_avg_speed`, `u_use_current_correction`,
/// `m_heading`, after the mission's `sensor:` lines).
fn nav_setup(
    mission_set: &mut dyn FnMut(&str) -> Option<f64>,
    value: &dyn Fn(&str) -> Option<f64>,
    flight: &FlightParams,
) -> NavSetup {
    let finite = |value: Option<f64>| value.filter(|value| value.is_finite());
    let (default_lat, default_lon) = DEFAULT_START_NMEA;
    let start = match (mission_set("s_ini_lat"), mission_set("s_ini_lon")) {
        (Some(lat), Some(lon)) if nmea_is_set(lat) && nmea_is_set(lon) && lat.abs() <= 9000.0 => {
            (lat, lon)
        }
        _ => (default_lat, default_lon),
    };
    let speed = finite(mission_set("s_water_speed")).unwrap_or(0.0);
    let direction = finite(mission_set("s_water_direction")).unwrap_or(0.0);
    let believed = Xy::new(
        finite(value("m_water_vx")).unwrap_or(0.0),
        finite(value("m_water_vy")).unwrap_or(0.0),
    );
    // Without a logged mean speed: the steady speed through the water of a
    // dive at full volume and the nominal pitch, half-way down 40 m.
    let nominal = flight
        .steady_glide(
            -flight.pump_max,
            -crate::behaviors::NOMINAL_PITCH,
            DEFAULT_WATER_DEPTH / 2.0,
        )
        .0;
    let avg_speed = finite(value("m_avg_speed"))
        .filter(|speed| *speed > 0.0)
        .unwrap_or(nominal);
    NavSetup {
        start_lat: start.0,
        start_lon: start.1,
        water: Xy::polar(speed, direction),
        believed_water: believed,
        avg_speed,
        heading: finite(value("m_heading")).unwrap_or(0.0),
        current_correction: finite(value("u_use_current_correction")).unwrap_or(0.0) != 0.0,
    }
}

/// Writes the navigation's sensors (those the active list has).
fn publish_navigation(
    slots: &NavSlots,
    navigation: &Navigation,
    view: &NavView,
    mag_var: f64,
    sensors: &mut SensorWrites<'_>,
) {
    let lmc = &navigation.lmc;
    let position = navigation.dead_reckoned;
    sensors.put_xy(slots.position, position);
    sensors.put_nmea(slots.position_nmea, lmc, position);
    sensors.put(slots.heading, navigation.heading);
    if let Some(heading) = navigation.commanded_heading {
        sensors.put(slots.c_heading, heading);
    }
    sensors.put(
        slots.speed_estimated,
        f64::from(u8::from(navigation.speed_estimated)),
    );
    sensors.put(slots.avg_speed, navigation.avg_speed);
    sensors.put_xy(slots.water, navigation.water);
    sensors.put_xy(slots.initial_water, navigation.initial_water);
    sensors.put_xy(slots.final_water, navigation.final_water);
    sensors.put_xy(slots.prior_water, navigation.prior_segment_water);
    sensors.put(slots.dr_state, navigation.dr_state as u8 as f64);
    sensors.put(slots.dr_time, navigation.dr_time);
    sensors.put(slots.dr_fix_time, navigation.fix_time);
    sensors.put(slots.dr_postfix_time, navigation.postfix_time);
    sensors.put_xy(slots.dr_surface, navigation.dr_surface);
    sensors.put_xy(slots.initial_error, navigation.initial_error);
    sensors.put_xy(slots.adjusted_drift, navigation.adjusted_drift);
    sensors.put(slots.gps_dist_from_dr, navigation.gps_dist_from_dr);
    if let Some(fix) = navigation.last_gps {
        sensors.put_nmea(slots.gps_nmea, lmc, fix);
        sensors.put_xy(slots.gps, fix);
    }
    // 0: a valid fix this cycle; 1: none (the glider's "no fix").
    sensors.put(
        slots.gps_status,
        if navigation.gps_fix.is_some() {
            0.0
        } else {
            1.0
        },
    );
    sensors.put(slots.gps_mag_var, mag_var);
    if let Some(waypoint) = view.waypoint {
        sensors.put_xy(slots.waypoint, waypoint);
        sensors.put_nmea(slots.waypoint_nmea, lmc, waypoint);
    }
    sensors.put(slots.dist_to_wpt, view.dist_to_wpt);
    sensors.put(slots.hit_waypoint, f64::from(u8::from(view.hit_waypoint)));
}

fn shelf_profile(mission_set: &mut dyn FnMut(&str) -> Option<f64>) -> TemperatureProfile {
    let TemperatureProfile::Shelf {
        surface,
        bottom,
        center,
        width,
    } = TemperatureProfile::default()
    else {
        return TemperatureProfile::default();
    };
    let surface = mission_set("s_water_temp_surface").unwrap_or(surface);
    let bottom = mission_set("s_water_temp_bottom").unwrap_or(bottom);
    // TWR's simulator sets the top and bottom of the thermocline; the tanh
    // spans about ±2 widths between them.
    let (center, width) = match (
        mission_set("s_water_temp_depth_inft"),
        mission_set("s_water_temp_depth_infb"),
    ) {
        (Some(top), Some(bottom_depth)) if bottom_depth > top => {
            ((top + bottom_depth) / 2.0, (bottom_depth - top) / 4.0)
        }
        _ => (center, width),
    };
    TemperatureProfile::Shelf {
        surface,
        bottom,
        center,
        width,
    }
}

/// The script's view of the world: the sensor array, and this cycle's output.
pub struct SimHost<'a> {
    sensors: &'a mut [f64],
    printed: &'a mut String,
    print_sites: &'a mut Vec<(usize, Pc)>,
    stored: &'a mut Vec<SensorId>,
}

impl Host for SimHost<'_> {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        gloc_engine::vm::sensor_value(self.sensors, sensor)
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        if gloc_engine::vm::set_sensor(self.sensors, sensor, value)
            && !self.stored.contains(&sensor)
        {
            self.stored.push(sensor);
        }
    }

    fn print_line(&mut self, line: &str) {
        self.printed.push_str(line);
        self.printed.push('\n');
    }

    fn print_line_at(&mut self, line: &str, pc: Pc) {
        self.print_line(line);
        self.print_sites.push((self.printed.len(), pc));
    }
}
