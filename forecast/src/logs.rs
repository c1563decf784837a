//! What a forecast needs from a glider's own logs: every GPS fix, the current
//! estimates the glider made, the waypoint it steered to, its battery, and the
//! segments (last fix before a dive → first fix after the surfacing) a hindcast
//! flies again. Read from any [`CycleSource`] (a `.dbd`, an `.sbd` the glider
//! sent home, a deployment of several), by sensor name, in one pass.

use gloc_dbd::{CycleSource, DbdError};
use gloc_sim::navigation::{nmea_is_set, Xy};

/// The sensors read, in this order (any may be missing from a log).
const SENSORS: [&str; 17] = [
    "m_present_time",
    "m_gps_lat",
    "m_gps_lon",
    "m_water_vx",
    "m_water_vy",
    "c_wpt_lat",
    "c_wpt_lon",
    "m_depth",
    "m_avg_speed",
    "m_coulomb_amphr_total",
    "m_battery",
    "m_heading",
    "m_initial_water_vx",
    "m_initial_water_vy",
    "m_dr_time",
    "m_dr_fix_time",
    "f_coulomb_battery_capacity",
];

#[derive(Clone, Copy)]
enum Column {
    Time,
    GpsLat,
    GpsLon,
    WaterVx,
    WaterVy,
    WptLat,
    WptLon,
    Depth,
    AvgSpeed,
    AmpHours,
    Battery,
    Heading,
    InitialVx,
    InitialVy,
    DrTime,
    DrFixTime,
    Capacity,
}

/// Two fixes further apart than this (s), with the glider deeper than
/// [`UNDERWATER_DEPTH`] between them, bound a dive. At the surface the glider
/// takes a fix every cycle (about 5 s).
pub const FIX_GAP: f64 = 600.0;

/// Deeper than this (m) the glider is underwater (comet's yo tops reach 1 m;
/// `u_reqd_depth_at_surface` is 2 m by default).
pub const UNDERWATER_DEPTH: f64 = 2.0;

/// The most cycles read from logs (a month of 4-second cycles is 650,000).
pub const MAX_CYCLES: usize = 5_000_000;

/// A GPS fix: Unix seconds and NMEA latitude and longitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fix {
    pub time: f64,
    pub lat: f64,
    pub lon: f64,
}

/// A current estimate the glider logged (`m_water_vx/vy`, m/s) and when.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub time: f64,
    pub water: Xy,
}

/// One underwater segment as the logs show it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// The last fix before the dive, and the first after the surfacing.
    pub start: Fix,
    pub end: Fix,
    /// The current the glider navigated with (`m_water_vx/vy` at the dive).
    pub prior: Xy,
    /// The current it found after the segment: the first estimate at or
    /// after the first fix (`m_initial_water_vx/vy`, which becomes
    /// `m_water_vx/vy` when `u_use_current_correction` is 1). `None`: the
    /// logs end before the glider logged one.
    pub found: Option<Xy>,
    /// Seconds from the first cycle deeper than [`UNDERWATER_DEPTH`] to the
    /// last (the time the current acted on the glider underwater).
    pub underwater: f64,
    /// The waypoint steered to during the segment (NMEA lat, lon), if logged.
    pub waypoint: Option<(f64, f64)>,
    /// `m_avg_speed` the glider steered the segment with (its last value at or
    /// before the dive's fix, else the first during the segment), if logged.
    pub avg_speed: Option<f64>,
    /// Seconds from the start of the surfacing before the dive (when the
    /// glider left its last bottom for the surface) to the start fix: how far
    /// the mission's surface timers had run when the segment began.
    pub timers_elapsed: f64,
    /// Unix seconds when the surfacing that ended the segment began (the
    /// glider left its last bottom for the surface).
    pub surfacing_began: f64,
    /// The glider's own account of the surfacing that ended the segment, when
    /// the logs hold it (a full `.dbd`, or the next file's first cycle, which
    /// repeats every value): `m_dr_time`, seconds from its dive to when its dead
    /// reckoning stopped at the surface, and `m_dr_fix_time`, seconds from then
    /// to the first fix.
    pub dr_time: Option<f64>,
    pub fix_time: Option<f64>,
    /// The drift at the surface after the segment (m/s east, north): the last
    /// fix of the surface interval less the first, over the time between them
    /// (the firmware's `m_dr_x/y_postfix_drift` over `m_dr_postfix_time`).
    /// `None` with less than [`MIN_DRIFT_SECONDS`] of fixes.
    pub surface_drift: Option<Xy>,
}

/// The shortest run of fixes (s) a surface drift is measured over.
pub const MIN_DRIFT_SECONDS: f64 = 30.0;

/// Everything read from the logs.
#[derive(Clone, Debug, Default)]
pub struct LogHistory {
    pub fixes: Vec<Fix>,
    /// Each change of `m_water_vx/vy`, in time order.
    pub estimates: Vec<Estimate>,
    /// Each change of `m_initial_water_vx/vy` (full logs only), in time order.
    pub initial_estimates: Vec<Estimate>,
    /// Each change of the waypoint (`c_wpt_lat/lon`, NMEA), in time order.
    pub waypoints: Vec<(f64, (f64, f64))>,
    /// Each change of `m_avg_speed` (m/s), in time order.
    pub avg_speeds: Vec<(f64, f64)>,
    /// Each positive `m_dr_time` and `m_dr_fix_time` (s) logged, with its time.
    pub dr_times: Vec<(f64, f64)>,
    pub dr_fix_times: Vec<(f64, f64)>,
    pub segments: Vec<Segment>,
    /// The latest values at the end of the logs.
    pub last_water: Option<Xy>,
    pub last_waypoint: Option<(f64, f64)>,
    pub last_avg_speed: Option<f64>,
    pub last_amp_hours: Option<f64>,
    pub last_battery: Option<f64>,
    pub last_heading: Option<f64>,
    /// `f_coulomb_battery_capacity` (Ah), the charge the coulomb counter counts down from.
    pub battery_capacity: Option<f64>,
    /// Unix seconds of the last cycle.
    pub end_time: f64,
    /// How far the surface timers had run at the last fix (s), as [`Segment::timers_elapsed`].
    pub last_timers_elapsed: f64,
    /// The logs' deepest and shallowest underwater depths (m), for a current
    /// averaged over the glider's depth range.
    pub depth_range: Option<(f64, f64)>,
}

/// Why logs cannot start a forecast.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    #[error(transparent)]
    Read(#[from] DbdError),
    #[error("{0}")]
    Content(String),
}

/// One cycle's values: (time, depth, …) as read.
struct Sample {
    time: f64,
    depth: Option<f64>,
}

/// Reads logs to their end (at most [`MAX_CYCLES`] timed cycles).
pub fn read_history(source: &mut dyn CycleSource) -> Result<LogHistory, LogError> {
    let columns = gloc_dbd::columns_of(source.sensors(), &SENSORS);
    if columns[Column::Time as usize].is_none() {
        return Err(LogError::Content(format!(
            "{}: no m_present_time: a forecast needs a flight log (.dbd, .sbd, …), not a science log",
            source.file()
        )));
    }
    let mut history = LogHistory::default();
    let mut samples: Vec<Sample> = Vec::new();
    let mut water = (None::<f64>, None::<f64>);
    let mut initial = (None::<f64>, None::<f64>);
    let mut waypoint = (None::<f64>, None::<f64>);
    let mut low = f64::INFINITY;
    let mut high = f64::NEG_INFINITY;
    while let Some(cycle) = source.next_cycle()? {
        let get = |column: Column| columns[column as usize].and_then(|c| cycle.value(c));
        let Some(time) = get(Column::Time).filter(|time| time.is_finite()) else {
            continue;
        };
        if samples.len() >= MAX_CYCLES {
            return Err(LogError::Content(format!(
                "{}: more than {MAX_CYCLES} cycles: forecast from the last days of logs",
                source.file()
            )));
        }
        let depth = get(Column::Depth).filter(|depth| depth.is_finite());
        if let Some(depth) = depth.filter(|depth| *depth > UNDERWATER_DEPTH) {
            low = low.min(depth);
            high = high.max(depth);
        }
        samples.push(Sample { time, depth });
        history.end_time = time;
        let lat = get(Column::GpsLat);
        let lon = get(Column::GpsLon);
        if lat.is_some() || lon.is_some() {
            // A cycle that logs one half of a fix (a log that writes changes
            // only) takes the other half's latest value.
            let latest = |column: Column| {
                columns[column as usize].and_then(|c| cycle.values.get(c).copied())
            };
            let pair = (
                lat.or_else(|| latest(Column::GpsLat)),
                lon.or_else(|| latest(Column::GpsLon)),
            );
            if let (Some(lat), Some(lon)) = pair {
                // A fix equal to the one before is the log repeating it (a new
                // file's first cycle repeats every value), not a new fix.
                let repeated = history
                    .fixes
                    .last()
                    .is_some_and(|last| last.lat == lat && last.lon == lon);
                if nmea_is_set(lat) && nmea_is_set(lon) && lat.abs() <= 9000.0 && !repeated {
                    history.fixes.push(Fix { time, lat, lon });
                }
            }
        }
        let (vx, vy) = (get(Column::WaterVx), get(Column::WaterVy));
        if vx.is_some() || vy.is_some() {
            water = (vx.or(water.0), vy.or(water.1));
            if let (Some(x), Some(y)) = water {
                if x.is_finite() && y.is_finite() {
                    let estimate = Xy::new(x, y);
                    if history.last_water != Some(estimate) {
                        history.estimates.push(Estimate {
                            time,
                            water: estimate,
                        });
                    }
                    history.last_water = Some(estimate);
                }
            }
        }
        let (ix, iy) = (get(Column::InitialVx), get(Column::InitialVy));
        if ix.is_some() || iy.is_some() {
            initial = (ix.or(initial.0), iy.or(initial.1));
            if let (Some(x), Some(y)) = initial {
                let estimate = Xy::new(x, y);
                let changed = history
                    .initial_estimates
                    .last()
                    .is_none_or(|last| last.water != estimate);
                if x.is_finite() && y.is_finite() && changed {
                    history.initial_estimates.push(Estimate {
                        time,
                        water: estimate,
                    });
                }
            }
        }
        let (wlat, wlon) = (get(Column::WptLat), get(Column::WptLon));
        if wlat.is_some() || wlon.is_some() {
            waypoint = (wlat.or(waypoint.0), wlon.or(waypoint.1));
            if let (Some(lat), Some(lon)) = waypoint {
                if nmea_is_set(lat) && nmea_is_set(lon) {
                    if history.last_waypoint != Some((lat, lon)) {
                        history.waypoints.push((time, (lat, lon)));
                    }
                    history.last_waypoint = Some((lat, lon));
                }
            }
        }
        let finite = |value: Option<f64>| value.filter(|value| value.is_finite());
        if let Some(speed) = finite(get(Column::AvgSpeed)).filter(|speed| *speed > 0.0) {
            if history.last_avg_speed != Some(speed) {
                history.avg_speeds.push((time, speed));
            }
            history.last_avg_speed = Some(speed);
        }
        if let Some(amp_hours) = finite(get(Column::AmpHours)) {
            history.last_amp_hours = Some(amp_hours);
        }
        if let Some(volts) = finite(get(Column::Battery)) {
            history.last_battery = Some(volts);
        }
        if let Some(heading) = finite(get(Column::Heading)) {
            history.last_heading = Some(heading);
        }
        if let Some(seconds) = finite(get(Column::DrTime)).filter(|s| *s > 0.0) {
            history.dr_times.push((time, seconds));
        }
        if let Some(seconds) = finite(get(Column::DrFixTime)).filter(|s| *s > 0.0) {
            history.dr_fix_times.push((time, seconds));
        }
        if let Some(amp_hours) = finite(get(Column::Capacity)).filter(|ah| *ah > 0.0) {
            history.battery_capacity = Some(amp_hours);
        }
    }
    if low <= high {
        history.depth_range = Some((low, high));
    }
    history.segments = segments(&history, &samples);
    if let Some(last) = history.fixes.last() {
        history.last_timers_elapsed = timers_elapsed(&history.fixes, &samples, last.time);
    }
    Ok(history)
}

/// The segments between surface intervals: consecutive fixes more than
/// [`FIX_GAP`] apart with the glider underwater between them.
fn segments(history: &LogHistory, samples: &[Sample]) -> Vec<Segment> {
    let mut segments = Vec::new();
    for pair in history.fixes.windows(2) {
        let (start, end) = (pair[0], pair[1]);
        if end.time - start.time < FIX_GAP {
            continue;
        }
        let between = samples_between(samples, start.time, end.time);
        let deep: Vec<f64> = between
            .iter()
            .filter(|sample| sample.depth.is_some_and(|depth| depth > UNDERWATER_DEPTH))
            .map(|sample| sample.time)
            .collect();
        let (Some(first), Some(last)) = (deep.first(), deep.last()) else {
            continue;
        };
        let prior = history
            .estimates
            .iter()
            .rev()
            .find(|estimate| estimate.time < end.time)
            .map_or(Xy::ZERO, |estimate| estimate.water);
        // The first estimate at or after the first fix, before the next
        // dive: `m_initial_water_vx/vy` where logged, else `m_water_vx/vy`.
        let after_fix = |estimates: &[Estimate]| {
            estimates
                .iter()
                .find(|estimate| estimate.time >= end.time && estimate.time <= end.time + FIX_GAP)
                .map(|estimate| estimate.water)
        };
        let found = after_fix(&history.initial_estimates).or_else(|| after_fix(&history.estimates));
        // The waypoint steered to: the last one logged before the dive,
        // else the first logged during it.
        let waypoint = history
            .waypoints
            .iter()
            .rev()
            .find(|(time, _)| *time <= start.time)
            .or_else(|| history.waypoints.iter().find(|(time, _)| *time <= end.time))
            .map(|(_, at)| *at);
        // The speed it steered with (the current correction divides by it), as
        // the waypoint: the last before the dive, else the first during it.
        let avg_speed = history
            .avg_speeds
            .iter()
            .rev()
            .find(|(time, _)| *time <= start.time)
            .or_else(|| {
                history
                    .avg_speeds
                    .iter()
                    .find(|(time, _)| *time <= end.time)
            })
            .map(|(_, speed)| *speed);
        // The surface interval after the segment: from its last underwater
        // cycle to the next dive (or the end of the logs).
        let next_dive = samples[samples.partition_point(|sample| sample.time <= end.time)..]
            .iter()
            .find(|sample| sample.depth.is_some_and(|depth| depth > UNDERWATER_DEPTH))
            .map_or(f64::INFINITY, |sample| sample.time);
        let surfaced = |logged: &[(f64, f64)]| {
            logged
                .iter()
                .find(|(time, _)| *time >= *last && *time < next_dive)
                .map(|(_, seconds)| *seconds)
        };
        segments.push(Segment {
            start,
            end,
            prior,
            found,
            underwater: last - first,
            waypoint,
            avg_speed,
            timers_elapsed: timers_elapsed(&history.fixes, samples, start.time),
            surfacing_began: end.time - timers_elapsed(&history.fixes, samples, end.time),
            dr_time: surfaced(&history.dr_times),
            fix_time: surfaced(&history.dr_fix_times),
            surface_drift: surface_drift(&history.fixes, end, next_dive),
        });
    }
    segments
}

/// The drift (m/s east, north) from the fix `first` to the last fix before
/// `until` of the same surface interval (no gap over [`FIX_GAP`]).
fn surface_drift(fixes: &[Fix], first: Fix, until: f64) -> Option<Xy> {
    let begin = fixes.partition_point(|fix| fix.time < first.time);
    let mut last = first;
    for fix in fixes[begin..].iter().take_while(|fix| fix.time < until) {
        if fix.time - last.time >= FIX_GAP {
            break;
        }
        last = *fix;
    }
    let seconds = last.time - first.time;
    if seconds < MIN_DRIFT_SECONDS {
        return None;
    }
    let lmc = gloc_sim::navigation::Lmc::from_nmea(first.lat, first.lon);
    Some(lmc.nmea_to_xy(last.lat, last.lon) * (1.0 / seconds))
}

fn samples_between(samples: &[Sample], from: f64, to: f64) -> &[Sample] {
    let begin = samples.partition_point(|sample| sample.time < from);
    let end = samples.partition_point(|sample| sample.time <= to);
    &samples[begin..end.max(begin)]
}

/// How long before the fix at `at` the surfacing that led to it began: the
/// glider left its last bottom (the deepest point within [`FIX_GAP`] before
/// the surface interval's first fix) for the surface then. Without a dive in
/// the logs before, the surface interval's own length (a lower bound).
fn timers_elapsed(fixes: &[Fix], samples: &[Sample], at: f64) -> f64 {
    // The surface interval holding `at`: fixes back while no gap.
    let index = fixes.partition_point(|fix| fix.time <= at);
    let mut first = index.saturating_sub(1);
    while first > 0 && fixes[first].time - fixes[first - 1].time < FIX_GAP {
        first -= 1;
    }
    let Some(surface_fix) = fixes.get(first) else {
        return 0.0;
    };
    let before = samples_between(samples, surface_fix.time - FIX_GAP, surface_fix.time);
    let bottom = before
        .iter()
        .filter_map(|sample| sample.depth.map(|depth| (sample.time, depth)))
        .filter(|(_, depth)| *depth > UNDERWATER_DEPTH)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let began = bottom.map_or(surface_fix.time, |(time, _)| time);
    (at - began).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(time: f64, depth: f64) -> Sample {
        Sample {
            time,
            depth: Some(depth),
        }
    }

    #[test]
    fn the_timers_began_at_the_last_bottom_before_the_surface() {
        let fixes = [
            Fix {
                time: 1000.0,
                lat: 5400.0,
                lon: 700.0,
            },
            Fix {
                time: 1005.0,
                lat: 5400.0,
                lon: 700.0,
            },
            Fix {
                time: 1200.0,
                lat: 5400.0,
                lon: 700.0,
            },
        ];
        // Bottom at 700 s (30 m), then up: the surfacing began at 700 s.
        let samples = [
            sample(500.0, 10.0),
            sample(700.0, 30.0),
            sample(800.0, 15.0),
            sample(990.0, 0.5),
            sample(1200.0, 0.2),
        ];
        assert_eq!(timers_elapsed(&fixes, &samples, 1200.0), 500.0);
        // No dive seen before the first fix: the surface interval's length.
        assert_eq!(timers_elapsed(&fixes, &[], 1005.0), 5.0);
    }
}
