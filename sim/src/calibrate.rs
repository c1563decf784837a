//! Calibration: the figures of a yo measured from a glider's log (real or
//! simulated, by one function), and the simulator's constants fitted from them.
//!
//! A log becomes a [`Track`]: one row per control cycle of the few sensors the
//! figures need, each held at its last value between updates (a binary log
//! only records changes). [`yo_figures`] measures dive and climb rates, pitch,
//! half-yo time, overshoot, turn latency, cycle period and power the same way
//! for any track; [`fit`] turns a real track into `[simulator]` settings, each
//! with what it was fitted from, and says what it could not fit and why.

use crate::flight::{EnergyParams, FlightParams, PitchControl, SpeedLaw, Vehicle};
use crate::simulation::{SimConfig, Simulation};

/// The sensors a track reads, in [`Row`] field order.
pub const TRACK_SENSORS: [&str; 11] = [
    "m_present_time",
    "m_depth",
    "m_pitch",
    "m_ballast_pumped",
    "c_ballast_pumped",
    "m_battpos",
    "m_coulomb_current",
    "m_coulomb_amphr_total",
    "m_battery",
    "u_cycle_time",
    "m_altitude",
];

/// One control cycle: each value as last updated (NaN before the first update).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Unix seconds.
    pub time: f64,
    pub depth: f64,
    pub pitch: f64,
    /// Measured pumped volume (cc, > 0 up).
    pub ballast: f64,
    /// Commanded pumped volume (cc).
    pub c_ballast: f64,
    /// Battery position (in).
    pub battpos: f64,
    /// Battery current (A).
    pub current: f64,
    /// Charge used (Ah, a running total).
    pub amp_hours: f64,
    pub volts: f64,
    pub cycle_time: f64,
    /// Height above the bottom (m); `altitude_fix` marks the rows that measured it.
    pub altitude: f64,
    pub altitude_fix: bool,
}

impl Row {
    fn set(&mut self, field: usize, value: f64) {
        let slot = match field {
            0 => &mut self.time,
            1 => &mut self.depth,
            2 => &mut self.pitch,
            3 => &mut self.ballast,
            4 => &mut self.c_ballast,
            5 => &mut self.battpos,
            6 => &mut self.current,
            7 => &mut self.amp_hours,
            8 => &mut self.volts,
            9 => &mut self.cycle_time,
            _ => {
                self.altitude_fix = true;
                &mut self.altitude
            }
        };
        *slot = value;
    }
}

const EMPTY: Row = Row {
    time: f64::NAN,
    depth: f64::NAN,
    pitch: f64::NAN,
    ballast: f64::NAN,
    c_ballast: f64::NAN,
    battpos: f64::NAN,
    current: f64::NAN,
    amp_hours: f64::NAN,
    volts: f64::NAN,
    cycle_time: f64::NAN,
    altitude: f64::NAN,
    altitude_fix: false,
};

/// The most timed cycles a [`Track`] holds: three months of 4 s cycles, about 200 MB
/// (a 66 MB log of cycles carrying only a new time held 6 million, about 1 GB).
pub const MAX_TRACK_ROWS: usize = 2_000_000;

/// A log's rows, one per cycle with a time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    pub rows: Vec<Row>,
    last: Option<Row>,
}

impl Track {
    /// Adds a cycle: `update(i)` is the new value of `TRACK_SENSORS[i]` if the
    /// cycle updated it. Values not updated keep their last value; a cycle
    /// without a time is merged into the next one.
    pub fn push(&mut self, update: impl Fn(usize) -> Option<f64>) {
        let mut row = self.last.unwrap_or(EMPTY);
        row.time = f64::NAN;
        row.altitude_fix = false;
        for field in 0..TRACK_SENSORS.len() {
            if let Some(value) = update(field).filter(|value| value.is_finite()) {
                row.set(field, value);
            }
        }
        self.last = Some(row);
        if row.time.is_finite() && self.rows.last().is_none_or(|last| row.time > last.time) {
            self.rows.push(row);
        }
    }

    /// The water depth under the glider: the median of m_depth + m_altitude
    /// over the altimeter's fixes (m). `None` without a fix.
    pub fn water_depth(&self) -> Option<f64> {
        median(
            self.rows
                .iter()
                .filter(|row| row.altitude_fix && row.altitude > 0.0)
                .map(|row| row.depth + row.altitude)
                .collect(),
        )
    }

    /// Adds the simulation's current sensor values as a row (call after each cycle).
    pub fn record(&mut self, sim: &Simulation) {
        let list = sim.sensor_list();
        self.push(|field| {
            list.lookup(TRACK_SENSORS[field])
                .and_then(|id| sim.sensor(id))
        });
    }
}

/// The figures of a yo, measured the same way for any track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YoFigures {
    /// Median over dive legs of the vertical speed in the middle 60% of the leg (m/s).
    pub dive_rate: f64,
    pub climb_rate: f64,
    /// Median |pitch| in the middle of dive and climb legs (rad).
    pub dive_pitch: f64,
    pub climb_pitch: f64,
    /// Median time between two turns (the commanded volume changing sign) (s).
    pub half_yo_time: f64,
    /// Median depth travelled past a bottom turn's row (m) …
    pub bottom_overshoot: f64,
    /// … and past a top turn's row (m).
    pub top_overshoot: f64,
    /// Median time from the first row above the climb target to the turn's row (s).
    pub turn_latency: f64,
    /// Mean time between cycles, pauses over twice the median left out (s).
    pub cycle_period: f64,
    /// Standard deviation of the same (s).
    pub cycle_spread: f64,
    /// Mean power from the first turn to the last (W), from the charge used and the voltage.
    pub power: f64,
    /// Complete legs measured (dive and climb).
    pub legs: usize,
}

/// A leg: rows `start..end` between two turns, diving or climbing.
#[derive(Clone, Copy, Debug)]
struct Leg {
    start: usize,
    end: usize,
    dive: bool,
}

/// Legs shallower than this are surface manoeuvres, not yo legs (m).
const MIN_LEG_RANGE: f64 = 5.0;

fn median(mut values: Vec<f64>) -> Option<f64> {
    values.retain(|value| value.is_finite());
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    Some(if values.len() % 2 == 1 {
        values[middle]
    } else {
        (values[middle - 1] + values[middle]) / 2.0
    })
}

fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// Row indices where the commanded volume changes sign (the first row of the new sign).
fn turns(rows: &[Row]) -> Vec<usize> {
    let mut turns = Vec::new();
    let mut sign = 0.0;
    for (index, row) in rows.iter().enumerate() {
        if !row.c_ballast.is_finite() || row.c_ballast == 0.0 {
            continue;
        }
        let now = row.c_ballast.signum();
        if sign != 0.0 && now != sign {
            turns.push(index);
        }
        sign = now;
    }
    turns
}

fn depth_range(rows: &[Row]) -> (f64, f64) {
    rows.iter()
        .map(|row| row.depth)
        .filter(|depth| depth.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), depth| {
            (lo.min(depth), hi.max(depth))
        })
}

fn legs(rows: &[Row], turns: &[usize]) -> Vec<Leg> {
    turns
        .windows(2)
        .map(|pair| Leg {
            start: pair[0],
            end: pair[1],
            dive: rows[pair[0]].c_ballast < 0.0,
        })
        .filter(|leg| {
            let (lo, hi) = depth_range(&rows[leg.start..leg.end]);
            hi - lo >= MIN_LEG_RANGE
        })
        .collect()
}

/// The rows of a leg in its middle 60% of depth.
fn middle(rows: &[Row], leg: Leg) -> impl Iterator<Item = &Row> {
    let slice = &rows[leg.start..leg.end];
    let (lo, hi) = depth_range(slice);
    let margin = 0.2 * (hi - lo);
    slice
        .iter()
        .filter(move |row| row.depth >= lo + margin && row.depth <= hi - margin)
}

fn leg_rate(rows: &[Row], leg: Leg) -> f64 {
    let inside: Vec<&Row> = middle(rows, leg).collect();
    match (inside.first(), inside.last()) {
        (Some(first), Some(last)) if last.time > first.time => {
            (last.depth - first.depth).abs() / (last.time - first.time)
        }
        _ => f64::NAN,
    }
}

/// The cycle period's mean and standard deviation, pauses (surface waits, a
/// missing stretch) over twice the median left out.
fn cycle_period(rows: &[Row]) -> Option<(f64, f64)> {
    let steps: Vec<f64> = rows.windows(2).map(|w| w[1].time - w[0].time).collect();
    let typical = median(steps.clone())?;
    let kept: Vec<f64> = steps
        .into_iter()
        .filter(|step| *step > 0.0 && *step < 2.0 * typical)
        .collect();
    let mean = mean(&kept)?;
    let variance = kept.iter().map(|step| (step - mean).powi(2)).sum::<f64>() / kept.len() as f64;
    Some((mean, variance.sqrt()))
}

/// Measures a yo. `climb_target` is the yo's climb target depth (m), for the
/// turn latency. An error says what the track lacks.
pub fn yo_figures(track: &Track, climb_target: f64) -> Result<YoFigures, String> {
    let rows = &track.rows;
    let turns = turns(rows);
    let legs = legs(rows, &turns);
    let (dives, climbs): (Vec<Leg>, Vec<Leg>) = legs.iter().partition(|leg| leg.dive);
    if dives.is_empty() || climbs.is_empty() {
        return Err(format!(
            "the log has {} dive and {} climb legs of {MIN_LEG_RANGE} m or more between turns of c_ballast_pumped; a yo needs one of each",
            dives.len(),
            climbs.len()
        ));
    }
    let rate = |legs: &[Leg]| median(legs.iter().map(|leg| leg_rate(rows, *leg)).collect());
    let pitch = |legs: &[Leg]| {
        median(
            legs.iter()
                .flat_map(|leg| middle(rows, *leg).map(|row| row.pitch.abs()))
                .collect(),
        )
    };
    let missing = |what: &str| format!("cannot measure the {what}: the log lacks the values");
    let mut bottom = Vec::new();
    let mut top = Vec::new();
    let mut latency = Vec::new();
    for (before, after) in legs.iter().zip(legs.iter().skip(1)) {
        if before.end != after.start {
            continue;
        }
        let turn = rows[after.start];
        let (lo, hi) = depth_range(&rows[after.start..after.end]);
        if before.dive {
            bottom.push(hi - turn.depth);
        } else {
            top.push(turn.depth - lo);
            if let Some(cross) = rows[before.start..before.end]
                .iter()
                .find(|row| row.depth <= climb_target)
            {
                latency.push(turn.time - cross.time);
            }
        }
    }
    let (period, spread) = cycle_period(rows).ok_or_else(|| missing("cycle period"))?;
    let first = rows[legs[0].start];
    let last = rows[legs[legs.len() - 1].end];
    let volts: Vec<f64> = rows[legs[0].start..=legs[legs.len() - 1].end]
        .iter()
        .map(|row| row.volts)
        .filter(|volts| volts.is_finite())
        .collect();
    let power = (last.amp_hours - first.amp_hours) * 3600.0 * mean(&volts).unwrap_or(f64::NAN)
        / (last.time - first.time);
    if !power.is_finite() {
        return Err(missing("power (m_coulomb_amphr_total and m_battery)"));
    }
    Ok(YoFigures {
        dive_rate: rate(&dives).ok_or_else(|| missing("dive rate"))?,
        climb_rate: rate(&climbs).ok_or_else(|| missing("climb rate"))?,
        dive_pitch: pitch(&dives).ok_or_else(|| missing("dive pitch"))?,
        climb_pitch: pitch(&climbs).ok_or_else(|| missing("climb pitch"))?,
        half_yo_time: median(
            legs.iter()
                .map(|leg| rows[leg.end].time - rows[leg.start].time)
                .collect(),
        )
        .ok_or_else(|| missing("half-yo time"))?,
        bottom_overshoot: median(bottom).ok_or_else(|| missing("bottom overshoot"))?,
        top_overshoot: median(top).ok_or_else(|| missing("top overshoot"))?,
        turn_latency: median(latency).ok_or_else(|| {
            format!("cannot measure the turn latency: no climb crossed {climb_target} m before its turn")
        })?,
        cycle_period: period,
        cycle_spread: spread,
        power,
        legs: legs.len(),
    })
}

/// One fitted setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Fitted {
    pub name: &'static str,
    pub value: f64,
    /// What it was fitted from (a comment in the written table).
    pub from: String,
}

/// The result of a fit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Fit {
    pub values: Vec<Fitted>,
    /// Settings not fitted, with the reason.
    pub not_fitted: Vec<(&'static str, String)>,
}

impl Fit {
    /// Applies the fitted values to a configuration.
    pub fn apply(&self, config: &mut SimConfig) {
        for fitted in &self.values {
            config.set(fitted.name, fitted.value);
        }
    }

    /// The `[simulator]` table, a comment per value, the unfitted ones listed
    /// as comments at the end.
    pub fn to_toml(&self, sources: &str) -> String {
        let mut text = format!("# Fitted by `gloc calibrate` from {sources}.\n[simulator]\n");
        for fitted in &self.values {
            text.push_str(&format!(
                "{} = {}  # {}\n",
                fitted.name,
                round(fitted.value),
                fitted.from
            ));
        }
        if !self.not_fitted.is_empty() {
            text.push_str("# Not fitted (the simulator's defaults apply):\n");
            for (name, why) in &self.not_fitted {
                text.push_str(&format!("#   {name}: {why}\n"));
            }
        }
        text
    }

    fn put(&mut self, name: &'static str, value: Option<f64>, from: String, why_not: &str) {
        match value.filter(|value| value.is_finite()) {
            Some(value) => self.values.push(Fitted { name, value, from }),
            None => self.not_fitted.push((name, why_not.to_string())),
        }
    }
}

/// Six significant digits: enough for a constant, short in a file.
fn round(value: f64) -> String {
    let text = format!("{value:.6e}");
    let parsed: f64 = text.parse().unwrap_or(value);
    format!("{parsed}")
}

/// Pump rate over the middle 60% of each swing after a turn (cc/s), and the
/// energy per cc above the hotel current (J/cc) with the mean depth (m).
fn pump_swings(
    rows: &[Row],
    turn_rows: &[usize],
    pump_max: f64,
    hotel_current: f64,
) -> (Vec<f64>, Vec<(f64, f64)>) {
    let mut rates = Vec::new();
    let mut energies = Vec::new();
    for &turn in turn_rows {
        let up = rows[turn].c_ballast > 0.0;
        let toward = |row: &Row| if up { row.ballast } else { -row.ballast };
        // The swing: from the turn until the pump is within 5% of full.
        let Some(done) = rows[turn..]
            .iter()
            .position(|row| toward(row) >= 0.95 * pump_max)
            .map(|offset| turn + offset)
        else {
            continue;
        };
        // Rate: the median slope between rows both inside the swing.
        let slopes: Vec<f64> = rows[turn.saturating_sub(1)..=done]
            .windows(2)
            .filter(|pair| pair.iter().all(|row| toward(row).abs() < 0.95 * pump_max))
            .filter(|pair| pair[1].time > pair[0].time)
            .map(|pair| (toward(&pair[1]) - toward(&pair[0])) / (pair[1].time - pair[0].time))
            .collect();
        if let Some(rate) = median(slopes) {
            rates.push(rate);
        }
        // Energy: each row's current held since the previous row, from the
        // turn until the current is back near the hotel current (the pump's
        // motor runs on past the swing while the valve closes).
        let start = turn.saturating_sub(1);
        let quiet = rows[done..]
            .iter()
            .position(|row| row.current < hotel_current + PUMP_QUIET_AMPS)
            .map_or(rows.len() - 1, |offset| done + offset);
        let mut joules = 0.0;
        let mut depth = 0.0;
        for pair in rows[start..=quiet].windows(2) {
            let dt = pair[1].time - pair[0].time;
            joules += (pair[1].current - hotel_current).max(0.0) * pair[1].volts * dt;
            depth += pair[1].depth;
        }
        let moved = toward(&rows[done]) - toward(&rows[start]);
        let count = (quiet - start).max(1) as f64;
        if moved > 0.0 && joules.is_finite() {
            energies.push((joules / moved, depth / count));
        }
    }
    (rates, energies)
}

/// Fits the simulator's constants from a real glider's track. `climb_target`
/// as for [`yo_figures`]; `defaults` supplies the constants that are not
/// fitted but enter a fit (the pump's per-metre energy).
pub fn fit(track: &Track, climb_target: f64, defaults: &SimConfig) -> Result<Fit, String> {
    let figures = yo_figures(track, climb_target)?;
    let rows = &track.rows;
    let turn_rows = turns(rows);
    let legs = legs(rows, &turn_rows);
    let mut fit = Fit::default();
    let n = figures.legs;

    let mid = |dive: bool| -> Vec<Row> {
        legs.iter()
            .filter(|leg| leg.dive == dive)
            .flat_map(|leg| middle(rows, *leg).copied())
            .collect()
    };
    let (dive_rows, climb_rows) = (mid(true), mid(false));
    fit.put(
        "dive_rate",
        Some(figures.dive_rate),
        format!("median m_depth rate in the middle of {n} legs' dives"),
        "",
    );
    fit.put(
        "climb_rate",
        Some(figures.climb_rate),
        "median m_depth rate in the middle of the climbs".into(),
        "",
    );
    let pump_max = median(
        dive_rows
            .iter()
            .chain(climb_rows.iter())
            .map(|row| row.ballast.abs())
            .collect(),
    );
    fit.put(
        "pump_max",
        pump_max,
        "median |m_ballast_pumped| in the middle of the legs".into(),
        "m_ballast_pumped is not in the log",
    );
    let pump_max = pump_max.unwrap_or(defaults.flight.pump_max);

    // Hotel load: current × voltage away from the turns.
    let power = |rows: &[Row]| {
        mean(
            &rows
                .iter()
                .map(|row| row.current * row.volts)
                .collect::<Vec<_>>(),
        )
    };
    fit.put(
        "dive_power",
        power(&dive_rows),
        "mean m_coulomb_current × m_battery in the middle of the dives".into(),
        "m_coulomb_current or m_battery is not in the log",
    );
    fit.put(
        "climb_power",
        power(&climb_rows),
        "mean m_coulomb_current × m_battery in the middle of the climbs".into(),
        "m_coulomb_current or m_battery is not in the log",
    );

    fit_pump_swings(
        &mut fit,
        rows,
        &turn_rows,
        (&dive_rows, &climb_rows),
        pump_max,
        defaults,
    );
    fit_pitch(&mut fit, &figures, (&dive_rows, &climb_rows));
    fit_timing(&mut fit, rows, &figures);
    fit_speed_lag(&mut fit, &figures, defaults);
    fit_battery(&mut fit, rows);
    Ok(fit)
}

/// The pump's rates and energies from its swings at the bottom and top turns.
fn fit_pump_swings(
    fit: &mut Fit,
    rows: &[Row],
    turn_rows: &[usize],
    (dive_rows, climb_rows): (&[Row], &[Row]),
    pump_max: f64,
    defaults: &SimConfig,
) {
    let current = |rows: &[Row]| mean(&rows.iter().map(|row| row.current).collect::<Vec<_>>());
    let bottoms: Vec<usize> = turn_rows
        .iter()
        .copied()
        .filter(|turn| rows[*turn].c_ballast > 0.0)
        .collect();
    let tops: Vec<usize> = turn_rows
        .iter()
        .copied()
        .filter(|turn| rows[*turn].c_ballast < 0.0)
        .collect();
    let (out_rates, out_energy) = pump_swings(
        rows,
        &bottoms,
        pump_max,
        current(dive_rows).unwrap_or(f64::NAN),
    );
    let (in_rates, in_energy) = pump_swings(
        rows,
        &tops,
        pump_max,
        current(climb_rows).unwrap_or(f64::NAN),
    );
    fit.put(
        "pump_rate",
        median(out_rates.clone()),
        format!(
            "median m_ballast_pumped slope over the middle of {} swings out (bottom turns)",
            out_rates.len()
        ),
        "no complete swing out of the pump in the log",
    );
    fit.put(
        "pump_in_rate",
        median(in_rates.clone()),
        format!(
            "median m_ballast_pumped slope over the middle of {} swings in (top turns)",
            in_rates.len()
        ),
        "no complete swing in of the pump in the log",
    );
    let per_metre = defaults.energy.pump_out_j_per_cc_m;
    let out_joules = median(out_energy.iter().map(|(j, _)| *j).collect());
    let out_depth = median(out_energy.iter().map(|(_, d)| *d).collect());
    fit.put(
        "pump_out_j_per_cc",
        match (out_joules, out_depth) {
            (Some(joules), Some(depth)) => Some((joules - per_metre * depth).max(0.0)),
            _ => None,
        },
        format!(
            "m_coulomb_current above the hotel current × m_battery over {} swings out at {:.0} m, less pump_out_j_per_cc_m × depth",
            out_energy.len(),
            out_depth.unwrap_or(f64::NAN)
        ),
        "no swing out with m_coulomb_current in the log",
    );
    fit.put(
        "pump_in_j_per_cc",
        median(in_energy.iter().map(|(j, _)| *j).collect()),
        format!(
            "m_coulomb_current above the hotel current × m_battery over {} swings in",
            in_energy.len()
        ),
        "no swing in with m_coulomb_current in the log",
    );
    let depths: Vec<f64> = out_energy.iter().map(|(_, depth)| *depth).collect();
    let spread = depths.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - depths.iter().cloned().fold(f64::INFINITY, f64::min);
    fit.not_fitted.push((
        "pump_out_j_per_cc_m",
        format!(
            "the swings out span {:.1} m of depth, too little to separate the depth term; the default {per_metre} is kept",
            spread.max(0.0)
        ),
    ));
}

/// Pitch: on the battery position (it stays put) or servoed.
fn fit_pitch(fit: &mut Fit, figures: &YoFigures, (dive_rows, climb_rows): (&[Row], &[Row])) {
    let battpos: Vec<f64> = dive_rows
        .iter()
        .chain(climb_rows.iter())
        .map(|row| row.battpos)
        .filter(|value| value.is_finite())
        .collect();
    let battpos_spread = battpos.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - battpos.iter().cloned().fold(f64::INFINITY, f64::min);
    if !battpos.is_empty() && battpos_spread < BATTPOS_STILL {
        fit.put(
            "battpos_dive_pitch",
            Some(figures.dive_pitch),
            format!(
                "median |m_pitch| in the middle of the dives; m_battpos stays within {battpos_spread:.3} in (use_pitch 1)"
            ),
            "",
        );
        fit.put(
            "battpos_climb_pitch",
            Some(figures.climb_pitch),
            "median |m_pitch| in the middle of the climbs".into(),
            "",
        );
        fit.not_fitted.push((
            "pitch_j_per_rad",
            "the battery does not move between dive and climb in this log".into(),
        ));
    } else {
        fit.not_fitted.push((
            "battpos_dive_pitch",
            "m_battpos moves (servoed pitch) or is not in the log".into(),
        ));
    }
}

/// The control cycle's timing and the turn's latency.
fn fit_timing(fit: &mut Fit, rows: &[Row], figures: &YoFigures) {
    let cycle_time = median(rows.iter().map(|row| row.cycle_time).collect()).unwrap_or(4.0);
    fit.put(
        "cycle_overrun",
        Some((figures.cycle_period - cycle_time).max(0.0)),
        format!(
            "mean m_present_time step {:.3} s less u_cycle_time {cycle_time}",
            figures.cycle_period
        ),
        "",
    );
    fit.put(
        "cycle_jitter",
        Some(figures.cycle_spread),
        "standard deviation of the m_present_time steps".into(),
        "",
    );
    fit.put(
        "turn_cycles",
        Some(1.0 + (figures.turn_latency / figures.cycle_period).round()),
        format!(
            "median {:.1} s from the first cycle above the climb target to c_ballast_pumped turning, plus the cycle that turns",
            figures.turn_latency
        ),
        "",
    );
}

/// The speed's lag: the one the flight model needs to overshoot a turn as the log does
/// (the pump rates and speeds fitted before held fixed).
fn fit_speed_lag(fit: &mut Fit, figures: &YoFigures, defaults: &SimConfig) {
    let mut flight = defaults.flight.clone();
    for fitted in &fit.values {
        let mut probe = SimConfig {
            flight: flight.clone(),
            ..SimConfig::default()
        };
        if probe.set(fitted.name, fitted.value) {
            flight = probe.flight;
        }
    }
    let mut best: Option<(f64, f64, f64)> = None;
    for exponent in EXPONENTS {
        flight.speed_exponent = exponent;
        for step in 0..=LAG_STEPS {
            flight.speed_lag = LAG_MIN * (LAG_MAX / LAG_MIN).powf(step as f64 / LAG_STEPS as f64);
            let error = (model_overshoot(&flight, true) / figures.bottom_overshoot - 1.0).powi(2)
                + (model_overshoot(&flight, false) / figures.top_overshoot - 1.0).powi(2)
                // Of two that overshoot alike, the quicker: a lag also slows
                // every leg's start, which the log does not show.
                + 1e-4 * flight.speed_lag;
            if best.is_none_or(|(least, _, _)| error < least) {
                best = Some((error, flight.speed_lag, exponent));
            }
        }
    }
    let lag = best.map(|(_, lag, _)| lag);
    fit.put(
        "speed_exponent",
        best.map(|(_, _, exponent)| exponent),
        "with speed_lag, the flight model's overshoot at the turns as the log's".into(),
        "",
    );
    fit.put(
        "speed_lag",
        lag,
        format!(
            "the lag at which the flight model overshoots a turn as the log does: {:.2} m at the bottom, {:.2} m at the top (medians)",
            figures.bottom_overshoot, figures.top_overshoot
        ),
        "",
    );
}

/// The battery: what a short log shows of it, and what it cannot.
fn fit_battery(fit: &mut Fit, rows: &[Row]) {
    let volts = median(rows.iter().map(|row| row.volts).collect());
    fit.put(
        "volts_full",
        volts,
        "median m_battery (the battery is far from empty in a short log)".into(),
        "m_battery is not in the log",
    );
    for (name, why) in [
        ("volts_empty", "an empty battery is not in the log"),
        ("battery_wh", "the capacity is not in the log (m_coulomb_amphr_total counts use, not what is left)"),
        ("battery_ohms", "m_battery updates once a minute, never during a pump swing, so its sag under load is not seen"),
        ("angle_of_attack", "needs the speed through water (m_speed is a model output on the glider)"),
        ("max_speed", "needs the speed through water"),
        ("altimeter_range", "the glider's altimeter use is set by its own u_alt_* settings, not the water"),
        ("altimeter_fraction", "as altimeter_range"),
        ("altimeter_min_depth", "as altimeter_range"),
        ("ctd_period", "the science log (.ebd) has the CTD's samples; the flight log does not"),
    ] {
        fit.not_fitted.push((name, why.into()));
    }
}

/// The speed lags searched (s), log-spaced.
const LAG_MIN: f64 = 0.5;
const LAG_MAX: f64 = 120.0;
const LAG_STEPS: u32 = 60;
/// The speed-law exponents searched.
const EXPONENTS: [f64; 13] = [
    0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.75, 1.0, 1.5, 2.0,
];

/// How far the flight model travels past a turn (m): steady at full volume,
/// then the pump reverses at once (the turn's row), until the vertical speed
/// changes sign. `bottom`: a dive turning to a climb.
pub fn model_overshoot(flight: &FlightParams, bottom: bool) -> f64 {
    let energy = EnergyParams::default();
    let (before, after) = if bottom {
        (-flight.pump_max, flight.pump_max)
    } else {
        (flight.pump_max, -flight.pump_max)
    };
    let mut vehicle = Vehicle::default();
    vehicle.depth = 500.0;
    vehicle.ballast = before;
    let law = SpeedLaw::new(flight);
    let fly = |vehicle: &mut Vehicle, seconds: f64, buoyancy: f64| {
        vehicle.fly(
            seconds,
            buoyancy,
            0.0,
            PitchControl::Battpos,
            1000.0,
            flight,
            &law,
            &energy,
            0.0,
        );
    };
    fly(&mut vehicle, 600.0, before);
    let start = vehicle.depth;
    let mut furthest: f64 = 0.0;
    for _ in 0..2000 {
        fly(&mut vehicle, flight.step, after);
        let travelled = if bottom {
            vehicle.depth - start
        } else {
            start - vehicle.depth
        };
        furthest = furthest.max(travelled);
        if travelled < furthest {
            break;
        }
    }
    furthest
}

/// Current above the hotel current (A) below which the pump counts as stopped.
const PUMP_QUIET_AMPS: f64 = 0.05;

/// m_battpos spread (in) below which the battery counts as held in place.
const BATTPOS_STILL: f64 = 0.1;
