//! Calibration: the figures of a yo measured from a glider's log (real or
//! simulated, by one function), and the simulator's constants fitted from them.
//!
//! A log becomes a [`Track`]: one row per control cycle of the few sensors the
//! figures need, each held at its last value between updates (a binary log
//! only records changes). [`yo_figures`] measures dive and climb rates, pitch,
//! half-yo time, overshoot, turn latency, cycle period and power the same way
//! for any track; [`fit`] turns a real track into `[simulator]` settings, each
//! with what it was fitted from, and says what it could not fit and why. The
//! flight model's constants are fitted as smerckel/gliderflight's `glidertrim`
//! does: drag and hull volume by least squares on the steady glide's force
//! balance, the battery relation by least squares on tan(pitch).

use crate::flight::{FlightParams, GRAVITY, METRES_PER_INCH};
use crate::simulation::{SimConfig, Simulation};

/// Where a track keeps a sensor's value: the [`Row`] field it fills.
type Field = fn(&mut Row) -> &mut f64;

/// The sensors a track reads, each with the [`Row`] field it fills.
pub const TRACK_FIELDS: [(&str, Field); 13] = [
    ("m_present_time", |row| &mut row.time),
    ("m_depth", |row| &mut row.depth),
    ("m_pitch", |row| &mut row.pitch),
    ("m_ballast_pumped", |row| &mut row.ballast),
    ("c_ballast_pumped", |row| &mut row.c_ballast),
    ("m_battpos", |row| &mut row.battpos),
    ("m_coulomb_current", |row| &mut row.current),
    ("m_coulomb_amphr_total", |row| &mut row.amp_hours),
    ("m_battery", |row| &mut row.volts),
    ("u_cycle_time", |row| &mut row.cycle_time),
    // A row that updates the altitude is one of the altimeter's fixes.
    ("m_altitude", |row| {
        row.altitude_fix = true;
        &mut row.altitude
    }),
    ("m_heading", |row| &mut row.heading),
    ("c_heading", |row| &mut row.c_heading),
];

/// The names of [`TRACK_FIELDS`], in its order (the columns to read from a log).
pub fn track_sensors() -> [&'static str; 13] {
    TRACK_FIELDS.map(|(name, _)| name)
}

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
    /// Heading and commanded heading (rad).
    pub heading: f64,
    pub c_heading: f64,
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
    heading: f64::NAN,
    c_heading: f64::NAN,
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
    /// Adds a cycle: `update(i)` is the new value of `TRACK_FIELDS[i]`'s sensor if the
    /// cycle updated it. Values not updated keep their last value; a cycle
    /// without a time is merged into the next one.
    pub fn push(&mut self, update: impl Fn(usize) -> Option<f64>) {
        let mut row = self.last.unwrap_or(EMPTY);
        row.time = f64::NAN;
        row.altitude_fix = false;
        for (index, (_, field)) in TRACK_FIELDS.iter().enumerate() {
            if let Some(value) = update(index).filter(|value| value.is_finite()) {
                *field(&mut row) = value;
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
        self.push(|index| {
            list.lookup(TRACK_FIELDS[index].0)
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
    /// Median time from a bottom turn's row (the command) to the climb
    /// reaching 90% of its leg's rate ([`turn_time`]) (s) …
    pub bottom_turn_time: f64,
    /// … and from a top turn's row to the dive reaching 90% of its rate (s).
    pub top_turn_time: f64,
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

/// The time from a leg's first row (the turn's command) to its vertical
/// rate reaching 90% of the leg's rate ([`leg_rate`]) (s). The rate between
/// two rows counts at the middle of their interval; the crossing is
/// interpolated linearly between two such rates. NaN if it never does.
fn turn_time(rows: &[Row], leg: Leg) -> f64 {
    let want = TURN_RATE_FRACTION * leg_rate(rows, leg);
    let sign = if leg.dive { 1.0 } else { -1.0 };
    let start = rows[leg.start].time;
    let mut previous: Option<(f64, f64)> = None;
    for pair in rows[leg.start..leg.end].windows(2) {
        let dt = pair[1].time - pair[0].time;
        if dt <= 0.0 || !(pair[1].depth - pair[0].depth).is_finite() {
            continue;
        }
        let rate = sign * (pair[1].depth - pair[0].depth) / dt;
        let at = 0.5 * (pair[0].time + pair[1].time);
        if rate >= want {
            return match previous {
                Some((before_at, before_rate)) if before_rate < want => {
                    before_at + (want - before_rate) / (rate - before_rate) * (at - before_at)
                        - start
                }
                _ => at - start,
            };
        }
        previous = Some((at, rate));
    }
    f64::NAN
}

/// The fraction of a leg's rate that ends a turn ([`turn_time`]).
pub const TURN_RATE_FRACTION: f64 = 0.9;

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
    let (mut bottom_time, mut top_time) = (Vec::new(), Vec::new());
    for (before, after) in legs.iter().zip(legs.iter().skip(1)) {
        if before.end != after.start {
            continue;
        }
        let turn = rows[after.start];
        let (lo, hi) = depth_range(&rows[after.start..after.end]);
        let timing = turn_time(rows, *after);
        if before.dive {
            bottom.push(hi - turn.depth);
            bottom_time.push(timing);
        } else {
            top.push(turn.depth - lo);
            top_time.push(timing);
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
        bottom_turn_time: median(bottom_time).ok_or_else(|| missing("bottom turn time"))?,
        top_turn_time: median(top_time).ok_or_else(|| missing("top turn time"))?,
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

    /// The pump's rates out and in (cc/s): as fitted, else `flight`'s.
    fn pump_rates(&self, flight: &FlightParams) -> (f64, f64) {
        let value = |name: &str, default: f64| {
            self.values
                .iter()
                .find(|fitted| fitted.name == name)
                .map_or(default, |fitted| fitted.value)
        };
        (
            value("pump_rate", flight.pump_rate),
            value("pump_in_rate", flight.pump_in_rate),
        )
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

    let mid = |dive: bool| -> Vec<Row> {
        legs.iter()
            .filter(|leg| leg.dive == dive)
            .flat_map(|leg| middle(rows, *leg).copied())
            .collect()
    };
    let (dive_rows, climb_rows) = (mid(true), mid(false));
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
    let mut flight = defaults.flight.clone();
    flight.pump_max = pump_max;
    let steady = steady_legs(rows, &legs);
    fit_battery_relation(&mut fit, &mut flight, &steady);
    fit_drag_and_volume(&mut fit, &mut flight, &steady);
    fit_pump_lead(&mut fit, &flight, rows, &turn_rows);
    fit_ballast_delay(&mut fit, &mut flight, rows, &turn_rows);
    fit_pitch_swing(&mut fit, &flight, rows, &turn_rows);
    fit_heading_bias(&mut fit, (&dive_rows, &climb_rows));
    fit_timing(&mut fit, rows, &figures);
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
        ("mass", "only the hull volume less the mass shows in a glide; hull_volume is fitted for the configured mass and water_density"),
        ("water_density", "the flight log has no CTD; the .ebd's conductivity, temperature and pressure give it (TEOS-10)"),
        ("hull_compressibility", "a shallow log's 40 m change the hull by 0.02%, below what the rates resolve"),
        ("drag_cd1", "gliderflight holds it (10.5) and fits the zero-lift drag only"),
        ("lift_slope", "gliderflight holds it (aw from the wing's shape, ah 3.8)"),
        ("wing_area", "a reference area: it scales the coefficients, not the flight"),
        ("added_mass_along", "held at gliderflight's: comet's turns would call for several times the glider's own mass, not a slender hull's 0.2; ballast_delay fits them instead"),
        ("added_mass_across", "as added_mass_along"),
        ("altimeter_range", "the glider's altimeter use is set by its own u_alt_* settings, not the water"),
        ("altimeter_fraction", "as altimeter_range"),
        ("altimeter_min_depth", "as altimeter_range"),
        ("ctd_period", "the science log (.ebd) has the CTD's samples; the flight log does not"),
    ] {
        fit.not_fitted.push((name, why.into()));
    }
}

/// Current above the hotel current (A) below which the pump counts as stopped.
const PUMP_QUIET_AMPS: f64 = 0.05;

/// m_battpos spread (in) below which the battery counts as held in place.
const BATTPOS_STILL: f64 = 0.1;

/// A leg in steady flight: its middle rows' medians.
#[derive(Clone, Copy, Debug)]
struct SteadyLeg {
    /// Vertical speed (m/s, > 0 up).
    rise: f64,
    /// Signed pitch (rad), pumped volume (cc), depth (m), battery position (in).
    pitch: f64,
    ballast: f64,
    depth: f64,
    battpos: f64,
}

/// Pitch (rad) below which a row is left out of the flight fits (gliderflight: 11°).
const MIN_FIT_PITCH: f64 = 11.0 * std::f64::consts::PI / 180.0;

fn steady_legs(rows: &[Row], legs: &[Leg]) -> Vec<SteadyLeg> {
    legs.iter()
        .filter_map(|leg| {
            let inside: Vec<&Row> = middle(rows, *leg).collect();
            let values = |field: fn(&Row) -> f64| median(inside.iter().map(|r| field(r)).collect());
            let rate = leg_rate(rows, *leg);
            let steady = SteadyLeg {
                rise: if leg.dive { -rate } else { rate },
                pitch: values(|r| r.pitch)?,
                ballast: values(|r| r.ballast)?,
                depth: values(|r| r.depth)?,
                battpos: values(|r| r.battpos).unwrap_or(f64::NAN),
            };
            (steady.rise.is_finite() && steady.pitch.abs() >= MIN_FIT_PITCH).then_some(steady)
        })
        .collect()
}

/// Least squares for a small system: the `unknowns` coefficients of rows
/// (`coefficients`, `right side`), by the normal equations and Gaussian
/// elimination. `None` when they do not determine the unknowns.
fn least_squares<const N: usize>(rows: &[([f64; N], f64)]) -> Option<[f64; N]> {
    let mut matrix = [[0.0; N]; N];
    let mut vector = [0.0; N];
    for (coefficients, right) in rows {
        for i in 0..N {
            vector[i] += coefficients[i] * right;
            for j in 0..N {
                matrix[i][j] += coefficients[i] * coefficients[j];
            }
        }
    }
    for column in 0..N {
        let pivot = (column..N).max_by(|a, b| {
            matrix[*a][column]
                .abs()
                .total_cmp(&matrix[*b][column].abs())
        })?;
        matrix.swap(column, pivot);
        vector.swap(column, pivot);
        let scale = matrix[column].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if matrix[column][column].abs() <= 1e-12 * scale.max(f64::MIN_POSITIVE) {
            return None;
        }
        for row in column + 1..N {
            let factor = matrix[row][column] / matrix[column][column];
            let pivot_row = matrix[column];
            for (cell, above) in matrix[row].iter_mut().zip(pivot_row).skip(column) {
                *cell -= factor * above;
            }
            vector[row] -= factor * vector[column];
        }
    }
    let mut solution = [0.0; N];
    for row in (0..N).rev() {
        let known: f64 = (row + 1..N).map(|k| matrix[row][k] * solution[k]).sum();
        solution[row] = (vector[row] - known) / matrix[row][row];
    }
    solution.iter().all(|v| v.is_finite()).then_some(solution)
}

/// The battery relation tan θ = T1·ΔV + T2·battpos + T3 by least squares over
/// the steady legs (glidertrim's `estimate_pitch_relation`). A battery held in
/// one place cannot separate T2 from T3: T2 is kept and T3 takes the rest.
fn fit_battery_relation(fit: &mut Fit, flight: &mut FlightParams, steady: &[SteadyLeg]) {
    let rows: Vec<([f64; 3], f64)> = steady
        .iter()
        .filter(|leg| leg.battpos.is_finite())
        .map(|leg| {
            (
                [leg.ballast * 1e-6, leg.battpos * METRES_PER_INCH, 1.0],
                leg.pitch.tan(),
            )
        })
        .collect();
    let battpos: Vec<f64> = rows.iter().map(|(c, _)| c[1] / METRES_PER_INCH).collect();
    let spread = battpos.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - battpos.iter().cloned().fold(f64::INFINITY, f64::min);
    let from = format!(
        "least squares of tan(m_pitch) on m_ballast_pumped and m_battpos over {} steady legs (glidertrim)",
        rows.len()
    );
    if rows.is_empty() {
        for name in ["pitch_t1", "pitch_t2", "pitch_t3"] {
            fit.not_fitted.push((
                name,
                "m_battpos or m_ballast_pumped is not in the log".into(),
            ));
        }
        return;
    }
    if spread >= BATTPOS_STILL {
        if let Some([t1, t2, t3]) = least_squares(&rows) {
            fit.put("pitch_t1", Some(t1), from.clone(), "");
            fit.put("pitch_t2", Some(t2), from.clone(), "");
            fit.put("pitch_t3", Some(t3), from, "");
            (flight.pitch_t1, flight.pitch_t2, flight.pitch_t3) = (t1, t2, t3);
            return;
        }
    }
    let two: Vec<([f64; 2], f64)> = rows.iter().map(|(c, y)| ([c[0], 1.0], *y)).collect();
    let Some([t1, intercept]) = least_squares(&two) else {
        for name in ["pitch_t1", "pitch_t2", "pitch_t3"] {
            fit.not_fitted
                .push((name, "the steady legs all have one pumped volume".into()));
        }
        return;
    };
    let held = median(battpos).unwrap_or(0.0) * METRES_PER_INCH;
    let t3 = intercept - flight.pitch_t2 * held;
    fit.put("pitch_t1", Some(t1), from.clone(), "");
    fit.put(
        "pitch_t3",
        Some(t3),
        format!(
            "{from}, less pitch_t2 × the battery's {:.3} in",
            held / METRES_PER_INCH
        ),
        "",
    );
    fit.not_fitted.push((
        "pitch_t2",
        format!(
            "m_battpos stays within {spread:.3} in (use_pitch 1): T2 cannot be told from T3; the default {} is kept",
            flight.pitch_t2
        ),
    ));
    (flight.pitch_t1, flight.pitch_t3) = (t1, t3);
}

/// Zero-lift drag and hull volume by least squares on the steady glide's
/// force balance (gliderflight's steady model), one equation per steady leg:
/// net buoyancy / g = ρ·S·w²·(Cd0 + Cd1·α²) / (2 g sin³(θ + α)), linear in
/// (hull volume, Cd0) once α is known; α follows Cd0, so ten rounds.
fn fit_drag_and_volume(fit: &mut Fit, flight: &mut FlightParams, steady: &[SteadyLeg]) {
    let rho = flight.water_density;
    let mut solved = None;
    let mut trial = flight.clone();
    for _ in 0..10 {
        let rows: Vec<([f64; 2], f64)> = steady
            .iter()
            .map(|leg| {
                let alpha = trial.steady_angle_of_attack(leg.pitch);
                let glide = leg.pitch + alpha;
                let k = leg.rise * leg.rise * rho * trial.wing_area
                    / (2.0 * GRAVITY * glide.sin().powi(3));
                let squeeze = 1.0 - trial.hull_compressibility * rho * GRAVITY * leg.depth;
                (
                    [rho * squeeze * 1e-3, -k],
                    trial.mass - rho * leg.ballast * 1e-6 + k * trial.drag_cd1 * alpha * alpha,
                )
            })
            .collect();
        let Some([volume, cd0]) = least_squares(&rows) else {
            break;
        };
        if !(cd0 > 0.0 && volume > 0.0) {
            break;
        }
        (trial.hull_volume, trial.drag_cd0) = (volume, cd0);
        solved = Some((volume, cd0));
    }
    let from = format!(
        "least squares on the steady glide's force balance over {} legs (median m_depth rate, m_pitch, m_ballast_pumped), for mass {} kg and water_density {} kg/m³",
        steady.len(),
        flight.mass,
        flight.water_density
    );
    let why = "the steady legs do not determine drag and volume (one direction only?)";
    fit.put("hull_volume", solved.map(|(v, _)| v), from.clone(), why);
    fit.put("drag_cd0", solved.map(|(_, c)| c), from, why);
    if let Some((volume, cd0)) = solved {
        (flight.hull_volume, flight.drag_cd0) = (volume, cd0);
    }
}

/// The log's pumped volume at `time` (cc), between its rows as the pump
/// moved: at its rate `rates` (out, in; cc/s), from the earlier row if it was
/// already moving there, else so as to arrive at the later row's reading (a
/// swing starts between two rows; averaging across them would start it up to
/// a cycle early). Outside the rows, the nearest row's reading.
fn logged_volume(rows: &[Row], time: f64, (out_rate, in_rate): (f64, f64)) -> f64 {
    let later = rows.partition_point(|row| row.time <= time);
    let (Some(a), Some(b)) = (later.checked_sub(1).map(|i| rows[i]), rows.get(later)) else {
        return rows[later.min(rows.len() - 1)].ballast;
    };
    let change = b.ballast - a.ballast;
    let rate = if change > 0.0 { out_rate } else { in_rate };
    if change.abs() <= PUMP_STILL || rate.is_nan() || rate <= 0.0 || b.time <= a.time {
        let span = (b.time - a.time).max(1e-9);
        return a.ballast + change * ((time - a.time) / span).clamp(0.0, 1.0);
    }
    let moving_before = later >= 2 && (a.ballast - rows[later - 2].ballast).abs() > PUMP_STILL;
    let travel = (change.abs() / rate).min(b.time - a.time);
    let start = if moving_before {
        a.time
    } else {
        b.time - travel
    };
    a.ballast + change * ((time - start) / travel).clamp(0.0, 1.0)
}

/// Change of m_ballast_pumped between rows (cc) below which the pump counts as
/// still (its readings step by 0.3 cc).
const PUMP_STILL: f64 = 2.0;

/// The hull's swing toward the battery relation: the natural period and
/// damping at which the relation, fed the log's pumped volume through each
/// turn ([`crate::flight::swing_pitch`]) `flight.ballast_delay` late (as the
/// simulator feeds it) and between rows as the pump moves ([`logged_volume`]),
/// gives the log's pitch best (least squares over the turns' first minute; a
/// grid search, two unknowns).
fn fit_pitch_swing(fit: &mut Fit, flight: &FlightParams, rows: &[Row], turn_rows: &[usize]) {
    let rates = fit.pump_rates(flight);
    let battpos = median(rows.iter().map(|row| row.battpos).collect()).unwrap_or(f64::NAN);
    let error = |period: f64, damping: f64| -> f64 {
        let mut total = 0.0;
        for &turn in turn_rows {
            let start = turn.saturating_sub(1);
            let mut state = (rows[start].pitch, 0.0);
            for pair in rows[start..].windows(2) {
                if pair[1].time - rows[turn].time > PITCH_SWING_WINDOW {
                    break;
                }
                let span = pair[1].time - pair[0].time;
                if !(span > 0.0 && span <= PITCH_SWING_WINDOW) {
                    // A gap, not a turn (and no endless sub-steps over it).
                    break;
                }
                let pieces = (span / PITCH_SWING_DT).ceil().max(1.0);
                let dt = span / pieces;
                for piece in 0..pieces as u32 {
                    let time = pair[0].time + (f64::from(piece) + 0.5) * dt;
                    let volume = logged_volume(rows, time - flight.ballast_delay, rates);
                    let target = flight.battpos_pitch(volume, battpos);
                    state = crate::flight::swing_pitch(state, target, dt, period, damping);
                }
                let miss = state.0 - pair[1].pitch;
                if miss.is_finite() {
                    total += miss * miss;
                }
            }
        }
        total
    };
    let mut best: Option<(f64, f64, f64)> = None;
    for period in PITCH_PERIODS.values() {
        for damping in PITCH_DAMPINGS.values() {
            let miss = error(period, damping);
            if miss > 0.0 && best.is_none_or(|(least, _, _)| miss < least) {
                best = Some((miss, period, damping));
            }
        }
    }
    let best = best.filter(|_| battpos.is_finite());
    let why = "no turn with m_pitch, m_ballast_pumped and m_battpos in the log";
    let from = format!(
        "the swing with which the battery relation, fed m_ballast_pumped ballast_delay late, follows m_pitch best through {} turns",
        turn_rows.len()
    );
    fit.put("pitch_period", best.map(|b| b.1), from.clone(), why);
    fit.put("pitch_damping", best.map(|b| b.2), from, why);
}

/// The pump's lead: how far its swing has run by the row where
/// c_ballast_pumped turns, m_ballast_pumped's change since the row before
/// over the pump's rate; the median over the turns below the surface.
fn fit_pump_lead(fit: &mut Fit, flight: &FlightParams, rows: &[Row], turn_rows: &[usize]) {
    let (out_rate, in_rate) = fit.pump_rates(flight);
    let leads: Vec<f64> = turn_rows
        .iter()
        .filter(|&&turn| turn > 0 && rows[turn].depth > PUMP_LEAD_MIN_DEPTH)
        .map(|&turn| {
            let change = rows[turn].ballast - rows[turn - 1].ballast;
            let rate = if rows[turn].c_ballast > 0.0 {
                out_rate
            } else {
                -in_rate
            };
            change / rate
        })
        .filter(|lead| lead.is_finite() && *lead >= 0.0)
        .collect();
    fit.put(
        "pump_lead",
        median(leads.clone()),
        format!(
            "median m_ballast_pumped run at the row where c_ballast_pumped turns, over the pump's rate, {} turns",
            leads.len()
        ),
        "no turn below the surface with m_ballast_pumped in the log",
    );
}

/// Turns shallower than this (m) are the dive's start at the surface, left
/// out of the pump's lead.
const PUMP_LEAD_MIN_DEPTH: f64 = 0.5;

/// The ballast delay: the one at which the force balance, fed the log's
/// m_pitch and m_ballast_pumped through each turn (linear between rows, the
/// volume `delay` seconds late), gives the log's m_depth best: least squares
/// of the depth travelled from the turn's row over the next
/// [`DELAY_FIT_AFTER`] seconds, a grid search over one unknown. Each turn
/// starts [`DELAY_FIT_BEFORE`] seconds earlier in the steady glide of that
/// row; a turn with no steady glide there (the glider floating) is left out.
fn fit_ballast_delay(fit: &mut Fit, flight: &mut FlightParams, rows: &[Row], turn_rows: &[usize]) {
    let rates = fit.pump_rates(flight);
    let windows: Vec<(&[Row], usize)> = turn_rows
        .iter()
        .filter_map(|&turn| {
            let at = rows[turn].time;
            let first = rows[..turn]
                .iter()
                .rposition(|row| row.time <= at - DELAY_FIT_BEFORE)?;
            let last = turn
                + rows[turn..]
                    .iter()
                    .take_while(|row| row.time <= at + DELAY_FIT_AFTER)
                    .count();
            let window = &rows[first..last];
            // A gap before the lead-in (the glider at the surface, a missing
            // stretch) is no turn to fly through.
            let close = at - window[0].time <= 2.0 * DELAY_FIT_BEFORE;
            let complete = close
                && window.iter().all(|row| {
                    row.depth.is_finite() && row.pitch.is_finite() && row.ballast.is_finite()
                });
            let start = window[0];
            let steady = flight.steady_glide(start.ballast, start.pitch, start.depth);
            (complete && steady != (0.0, 0.0) && last > turn + 1).then_some((window, turn - first))
        })
        .collect();
    let error = |delay: f64| -> f64 {
        windows
            .iter()
            .map(|&(window, turn)| fed_turn_error(flight, window, turn, delay, rates))
            .sum()
    };
    let best = DELAY_GRID
        .values()
        .map(|delay| (error(delay), delay))
        .filter(|(miss, _)| miss.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let best = best.filter(|_| !windows.is_empty()).map(|(_, delay)| delay);
    if let Some(delay) = best {
        flight.ballast_delay = delay;
    }
    fit.put(
        "ballast_delay",
        best,
        format!(
            "the delay with which the force balance, fed m_ballast_pumped and m_pitch, follows m_depth best through {} turns",
            windows.len()
        ),
        "no turn below the surface with m_depth, m_pitch and m_ballast_pumped in the log",
    );
}

/// The squared misses (m²) of the force balance fed a `window` of rows (its
/// row `turn` the turn) with the pumped volume `delay` seconds late: the
/// depth travelled from the turn's row, at each later row.
fn fed_turn_error(
    flight: &FlightParams,
    window: &[Row],
    turn: usize,
    delay: f64,
    rates: (f64, f64),
) -> f64 {
    let at = |time: f64, field: fn(&Row) -> f64| -> f64 {
        let later = window.partition_point(|row| row.time <= time);
        match (later.checked_sub(1).map(|i| window[i]), window.get(later)) {
            (Some(a), Some(b)) if b.time > a.time => {
                field(&a) + (field(b) - field(&a)) * (time - a.time) / (b.time - a.time)
            }
            (Some(a), _) => field(&a),
            (None, _) => field(&window[0]),
        }
    };
    let start = window[0];
    let (speed, sink) = flight.steady_glide(start.ballast, start.pitch, start.depth);
    let mut vehicle = crate::flight::Vehicle::default();
    (vehicle.depth, vehicle.depth_rate) = (start.depth, sink);
    (vehicle.speed, vehicle.pitch) = (speed, start.pitch);
    let mut total = 0.0;
    let mut turn_depth = None;
    for (index, pair) in window.windows(2).enumerate() {
        let (from, row) = (pair[0].time, &pair[1]);
        // Equal steps of at most DELAY_FIT_DT (the window spans at most
        // 2 × DELAY_FIT_BEFORE + DELAY_FIT_AFTER seconds).
        let steps = ((row.time - from) / DELAY_FIT_DT).ceil().clamp(0.0, 1e4);
        let dt = (row.time - from) / steps.max(1.0);
        for step in 0..steps as u32 {
            let middle = from + (f64::from(step) + 0.5) * dt;
            vehicle.pitch = at(middle, |r| r.pitch);
            let volume = logged_volume(window, middle - delay, rates);
            vehicle.glide(dt, volume, f64::INFINITY, flight);
        }
        let index = index + 1;
        if index == turn {
            turn_depth = Some((vehicle.depth, row.depth));
        } else if let Some((model, logged)) = turn_depth {
            let miss = (vehicle.depth - model) - (row.depth - logged);
            total += miss * miss;
        }
    }
    total
}

/// The values a grid search tries.
#[derive(Clone, Copy, Debug)]
enum Grid {
    /// `from × step`, `(from + 1) × step`, … `to × step`.
    Linear { step: f64, from: u32, to: u32 },
    /// `steps + 1` values from `min` to `max` in equal ratios.
    Log { min: f64, max: f64, steps: u32 },
}

impl Grid {
    /// `from × step` to `to × step`.
    const fn linear(step: f64, from: u32, to: u32) -> Grid {
        Grid::Linear { step, from, to }
    }

    /// `steps + 1` values from `min` to `max` in equal ratios.
    const fn log(min: f64, max: f64, steps: u32) -> Grid {
        Grid::Log { min, max, steps }
    }

    fn values(self) -> impl Iterator<Item = f64> {
        let (from, to) = match self {
            Grid::Linear { from, to, .. } => (from, to),
            Grid::Log { steps, .. } => (0, steps),
        };
        (from..=to).map(move |index| match self {
            Grid::Linear { step, .. } => f64::from(index) * step,
            Grid::Log { min, max, steps } => {
                min * (max / min).powf(f64::from(index) / f64::from(steps))
            }
        })
    }
}

/// The ballast delays searched (s): 0 to 15 in quarter seconds.
const DELAY_GRID: Grid = Grid::linear(0.25, 0, 60);
/// The part of a turn compared and the lead-in (s), and the force balance's step
/// there (s).
const DELAY_FIT_AFTER: f64 = 40.0;
const DELAY_FIT_BEFORE: f64 = 30.0;
const DELAY_FIT_DT: f64 = 0.1;

/// The natural periods searched (s, log-spaced) and the damping ratios (steps of
/// 0.05 to 2).
const PITCH_PERIODS: Grid = Grid::log(2.0, 120.0, 60);
const PITCH_DAMPINGS: Grid = Grid::linear(0.05, 1, 40);
/// The part of a turn compared (s).
const PITCH_SWING_WINDOW: f64 = 60.0;
/// The swing's step through a row interval (s), the pump's course resolved.
const PITCH_SWING_DT: f64 = 0.5;

/// The roll bias's heading error: the median of m_heading − c_heading in the
/// middle of the dives and of the climbs.
fn fit_heading_bias(fit: &mut Fit, (dive_rows, climb_rows): (&[Row], &[Row])) {
    let bias = |rows: &[Row]| {
        median(
            rows.iter()
                .map(|row| crate::navigation::angle_difference(row.heading, row.c_heading))
                .collect(),
        )
    };
    let why = "m_heading or c_heading is not in the log";
    fit.put(
        "heading_bias_dive",
        bias(dive_rows),
        "median m_heading − c_heading in the middle of the dives".into(),
        why,
    );
    fit.put(
        "heading_bias_climb",
        bias(climb_rows),
        "median m_heading − c_heading in the middle of the climbs".into(),
        why,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_the_values_searched() {
        let delays: Vec<f64> = DELAY_GRID.values().collect();
        assert_eq!(delays.len(), 61);
        assert_eq!((delays[0], delays[1], delays[60]), (0.0, 0.25, 15.0));
        let dampings: Vec<f64> = PITCH_DAMPINGS.values().collect();
        assert_eq!(dampings.len(), 40);
        assert!((dampings[0] - 0.05).abs() < 1e-12 && (dampings[39] - 2.0).abs() < 1e-12);
        // 2 s to 120 s in 60 equal ratios: the 30th is √(2 × 120) = 15.49 s.
        let periods: Vec<f64> = PITCH_PERIODS.values().collect();
        assert_eq!(periods.len(), 61);
        assert!((periods[30] - 240f64.sqrt()).abs() < 1e-9);
        assert!((periods[0] - 2.0).abs() < 1e-12 && (periods[60] - 120.0).abs() < 1e-9);
    }

    #[test]
    fn least_squares_solves_an_overdetermined_line() {
        // Points (0, 1.1), (1, 2.8), (2, 5.0): by hand the normal equations
        // 5a + 3b = 12.8 and 3a + 3b = 8.9 give a = 1.95, b = 1.016667.
        let rows = [([0.0, 1.0], 1.1), ([1.0, 1.0], 2.8), ([2.0, 1.0], 5.0)];
        let [a, b] = least_squares(&rows).expect("solved");
        assert!((a - 1.95).abs() < 1e-12, "{a}");
        assert!((b - 3.05 / 3.0).abs() < 1e-12, "{b}");
        // One point cannot fix two unknowns.
        assert_eq!(least_squares(&[([1.0, 1.0], 1.0)]), None);
    }

    fn row(time: f64, ballast: f64, c_ballast: f64) -> Row {
        Row {
            time,
            ballast,
            c_ballast,
            ..EMPTY
        }
    }

    #[test]
    fn the_logged_volume_moves_between_rows_as_the_pump_does() {
        // Rows 4.5 s apart; the pump (34.6 cc/s out) has run 36 cc by the second.
        let rows = [
            row(0.0, -230.0, -230.0),
            row(4.5, -194.0, 230.0),
            row(9.0, -38.3, 230.0),
        ];
        let rates = (34.6, 43.7);
        // By hand: the swing started 36 / 34.6 = 1.0405 s before the second row,
        // at 3.4595 s; still at 3 s, 19.3 cc run by 4 s (34.6 × 0.5405 = 18.70).
        assert_eq!(logged_volume(&rows, 3.0, rates), -230.0);
        let at_four = logged_volume(&rows, 4.0, rates);
        assert!((at_four - (-230.0 + 34.6 * (4.0 - (4.5 - 36.0 / 34.6)))).abs() < 1e-9);
        assert!((at_four + 211.30).abs() < 0.01, "{at_four}");
        // Moving at the second row: from there at the rate, 1.5 s × 34.6 = 51.9 cc.
        assert!((logged_volume(&rows, 6.0, rates) + 142.1).abs() < 1e-9);
        // Outside the rows, the nearest reading.
        assert_eq!(logged_volume(&rows, 20.0, rates), -38.3);
    }

    #[test]
    fn the_pump_lead_is_the_swing_run_by_the_turns_row() {
        // Two turns below the surface: 36 cc out at 34.6 cc/s (1.0405 s) and 26 cc
        // in at 43.7 cc/s (0.5950 s): the median of two is their mean, 0.8177 s.
        let mut rows = vec![
            row(0.0, -230.0, -230.0),
            row(4.5, -194.0, 230.0),
            row(9.0, 230.0, 230.0),
            row(13.5, 204.0, -230.0),
        ];
        for row in &mut rows {
            row.depth = 20.0;
        }
        let mut fit = Fit::default();
        fit.put("pump_rate", Some(34.6), String::new(), "");
        fit.put("pump_in_rate", Some(43.7), String::new(), "");
        fit_pump_lead(&mut fit, &FlightParams::default(), &rows, &[1, 3]);
        let lead = fit
            .values
            .iter()
            .find(|f| f.name == "pump_lead")
            .expect("fitted");
        let by_hand = 0.5 * (36.0 / 34.6 + 26.0 / 43.7);
        assert!(
            (lead.value - by_hand).abs() < 1e-9,
            "{} {by_hand}",
            lead.value
        );
    }

    #[test]
    fn the_ballast_delay_fit_finds_the_delay_a_glider_flew_with() {
        // A glider flown by the flight model with the volume acting 3 s late, a row
        // a second, turning at 30 m and 5 m: the fit, fed its rows, finds 3 s. Fine
        // steps: a sub-step flies the pitch and volume of its end, so the default
        // 0.6 s steps fly about 0.3 s early, which the fit would see.
        let truth = FlightParams {
            ballast_delay: 3.0,
            step: 0.05,
            ..FlightParams::default()
        };
        let energy = crate::flight::EnergyParams::default();
        let mut vehicle = crate::flight::Vehicle::default();
        vehicle.depth = 5.0;
        let (mut rows, mut command, mut time) = (Vec::new(), -260.0, 0.0);
        while time < 2400.0 {
            if vehicle.depth > 30.0 && command < 0.0
                || vehicle.depth < 5.0 && command > 0.0 && time > 60.0
            {
                command = -command;
            }
            vehicle.fly(
                1.0,
                command,
                0.405,
                crate::flight::PitchControl::Battpos,
                1000.0,
                &truth,
                &energy,
                0.0,
            );
            time += 1.0;
            rows.push(Row {
                time,
                depth: vehicle.depth,
                pitch: vehicle.pitch,
                ballast: vehicle.ballast,
                c_ballast: command,
                ..EMPTY
            });
        }
        let turn_rows = turns(&rows);
        assert!(turn_rows.len() >= 8, "{}", turn_rows.len());
        let mut fit = Fit::default();
        fit.put("pump_rate", Some(truth.pump_rate), String::new(), "");
        fit.put("pump_in_rate", Some(truth.pump_in_rate), String::new(), "");
        let mut flight = FlightParams {
            ballast_delay: 0.0,
            ..truth.clone()
        };
        fit_ballast_delay(&mut fit, &mut flight, &rows, &turn_rows);
        assert!(
            (flight.ballast_delay - 3.0).abs() <= 0.25,
            "{}",
            flight.ballast_delay
        );
    }

    #[test]
    fn the_turn_fits_step_over_a_gap_instead_of_through_it() {
        // A turn whose row before lies 1e12 s back (and times where adding a tenth
        // of a second is lost): the fits must return, leaving that turn out.
        let mut rows = Vec::new();
        for (time, ballast, c_ballast) in [
            (0.0, -230.0, -230.0),
            (1e12, -194.0, 230.0),
            (1e12 + 4.5, -38.0, 230.0),
            (1e12 + 9.0, 118.0, 230.0),
            (1e12 + 13.5, 230.0, 230.0),
        ] {
            rows.push(Row {
                depth: 30.0,
                pitch: -0.4,
                battpos: 0.405,
                ..row(time, ballast, c_ballast)
            });
        }
        let mut fit = Fit::default();
        let mut flight = FlightParams::default();
        fit_ballast_delay(&mut fit, &mut flight, &rows, &[1]);
        fit_pitch_swing(&mut fit, &flight, &rows, &[1]);
        assert!(fit
            .not_fitted
            .iter()
            .any(|(name, _)| *name == "ballast_delay"));
    }

    #[test]
    fn the_drag_and_volume_fit_inverts_the_steady_glide() {
        // Legs flown by a glider with other constants than the defaults the fit
        // starts from: the fit must find them again from the legs alone.
        let mut truth = FlightParams::default();
        (truth.drag_cd0, truth.hull_volume) = (0.3, 71.6);
        let steady: Vec<SteadyLeg> = [
            (-230.0, -0.45, 30.0),
            (230.0, 0.42, 10.0),
            (-200.0, -0.40, 20.0),
        ]
        .iter()
        .map(|&(ballast, pitch, depth)| SteadyLeg {
            rise: -truth.steady_glide(ballast, pitch, depth).1,
            pitch,
            ballast,
            depth,
            battpos: 0.405,
        })
        .collect();
        let mut fit = Fit::default();
        let mut flight = FlightParams::default();
        fit_drag_and_volume(&mut fit, &mut flight, &steady);
        assert!((flight.drag_cd0 - 0.3).abs() < 1e-6, "{}", flight.drag_cd0);
        assert!(
            (flight.hull_volume - 71.6).abs() < 1e-6,
            "{}",
            flight.hull_volume
        );
        assert_eq!(fit.values.len(), 2);
    }
}
