//! Hindcasts: each logged segment flown again from its start (the last fix
//! before the dive, the belief the glider dove with, its waypoint and surface
//! timers) in the current the glider found after it, and compared with the
//! real first fix after the surfacing; beside it the null model, the prior
//! current taken as the truth, which is what a forecast made at the dive
//! would have used. The distances are the accuracy a pilot can quote.

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::navigation::Xy;
use gloc_sim::{Mission, SimConfig};

use crate::fly::{
    fly_with, prepare_mission, Extras, Flight, FlightPlan, Outside, Start, StopAt, Truth,
};
use crate::logs::{LogHistory, Segment};
use crate::ForecastError;

/// How far past the real surfacing a hindcast flies at most before it gives
/// up on a surfacing (s).
pub const EXTRA_SECONDS: f64 = 6.0 * 3600.0;

/// One segment's hindcast.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentHindcast {
    pub segment: Segment,
    /// Distance from the real first fix (m) of the simulated first fix with
    /// the found current, and with the prior current (the null model); `None`
    /// when the simulated glider did not surface in time.
    pub miss: Option<f64>,
    pub null_miss: Option<f64>,
    /// Simulated first fix (decimal degrees) and its time (Unix seconds).
    pub simulated: Option<(f64, f64, f64)>,
    /// The error bound a pilot holds a hindcast to: max(150 m, 0.015 m/s ×
    /// time underwater) (the navigation issue's).
    pub bound: f64,
    /// The simulated tracks (decimal degrees lat, lon, a point a minute) with
    /// the found current and with the prior one, for the map.
    pub track: Vec<(f64, f64)>,
    pub null_track: Vec<(f64, f64)>,
    /// The current flown underwater and the drift at the surface (m/s), and
    /// the seconds from the surfacing to the first fix ([`Replay`]).
    pub underwater_current: Xy,
    pub surface_drift: Option<Xy>,
    pub fix_time: f64,
}

/// The shortest `when_secs` of the mission's timed surface behaviors
/// (start_when 9 or 10: every N seconds since the last start).
///
/// A hindcast makes the timed surfacing come due when it brings the
/// simulated first fix to the real one's time ([`hindcast`]); a forecast
/// takes the timers from the surfacing before its start
/// ([`crate::logs::Segment::timers_elapsed`]).
pub fn timed_surface_interval(mission: &Mission) -> Option<f64> {
    mission
        .behaviors
        .iter()
        .filter(|spec| spec.kind == gloc_mission::BehaviorKind::Surface)
        .filter(|spec| matches!(spec.value("start_when").map(|v| v as i64), Some(9 | 10)))
        .filter_map(|spec| spec.value("when_secs"))
        .filter(|secs| secs.is_finite() && *secs > 0.0)
        .min_by(f64::total_cmp)
}

/// The bound of a segment: max(150 m, 0.015 m/s × time underwater).
pub fn bound(underwater: f64) -> f64 {
    (0.015 * underwater).max(150.0)
}

/// Flies every segment whose found current the logs hold.
///
/// Decision: a segment is replayed as the glider's own logs account for it.
/// The glider stopped dead reckoning at the surface `m_dr_time` after its
/// dive and took its first fix `m_dr_fix_time` later (`SimConfig::gps_fix_time`
/// when the logs hold neither); the current it found
/// (`m_initial_water_vx/vy`) spreads everything between its dead reckoning
/// and that fix over `m_dr_time`, the drift at the surface before the fix
/// included. So the replay flies, underwater, the found current less that
/// drift (`m_final_water_vx/vy`, as the firmware takes it out before the next
/// dive) and, at the surface, the drift measured between the surface
/// interval's first and last fix; and it brings the simulated glider up so
/// that its first fix comes when the glider's did (the mission's timed
/// surfacing made due at the moment that achieves it, found by bisection).
/// Both fixes are then at the same time, and the miss measures the
/// navigation and the current, not the phase of the yo the surface timer
/// caught (which a 3% difference in the dive rate moves by minutes over
/// 2.8 hours).
pub fn hindcast(
    history: &LogHistory,
    mission: &Mission,
    sensors: &Arc<SensorList>,
    config: &SimConfig,
) -> Result<Vec<SegmentHindcast>, ForecastError> {
    let mut results = Vec::new();
    for segment in &history.segments {
        let Some(found) = segment.found else {
            continue;
        };
        let replay = Replay::of(segment, found, config);
        let mut config = config.clone();
        config.gps_fix_time = replay.fix_time;
        let mut start = Start::of_segment(segment, history);
        if let Some(interval) = timed_surface_interval(mission) {
            let due = surfacing_due(segment, mission, sensors, &config, &start, interval)?;
            start.timers_elapsed = interval - (due - segment.start.time);
        }
        let prepared = prepare_mission(mission, &start);
        let plan = FlightPlan {
            seconds: segment.end.time - segment.start.time + EXTRA_SECONDS,
            record_every: 60.0,
            stop_at_first_fix: StopAt::FirstSurfacing,
            outside: Outside::Fail,
        };
        let lmc = start.lmc();
        let real = lmc.nmea_to_xy(segment.end.lat, segment.end.lon);
        let fly_in = |water, surface_drift| -> Result<_, ForecastError> {
            let flight = Flight {
                mission: &prepared,
                sensors,
                config: &config,
                start: &start,
                truth: &Truth::Uniform(water),
                bathymetry: None,
            };
            let extras = Extras {
                surface_drift,
                battery_limit: None,
            };
            let track = fly_with(&flight, &plan, &extras)?.track;
            let points: Vec<(f64, f64)> = track.points.iter().map(|p| (p.lat, p.lon)).collect();
            let first = track.surfacings.first().map(|s| {
                (
                    lmc.to_xy(s.lat, s.lon).distance(real),
                    (s.lat, s.lon, s.time),
                )
            });
            Ok((first, points))
        };
        let (with_found, track) = fly_in(replay.underwater, replay.surface_drift)?;
        // The null model: the prior current everywhere, as a forecast made at
        // the dive would have taken it.
        let (with_prior, null_track) = fly_in(segment.prior, None)?;
        results.push(SegmentHindcast {
            segment: *segment,
            miss: with_found.map(|(miss, _)| miss),
            null_miss: with_prior.map(|(miss, _)| miss),
            simulated: with_found.map(|(_, at)| at),
            bound: bound(segment.underwater),
            track,
            null_track,
            underwater_current: replay.underwater,
            surface_drift: replay.surface_drift,
            fix_time: replay.fix_time,
        });
    }
    Ok(results)
}

/// How a segment's surfacing is replayed (see [`hindcast`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Replay {
    /// Seconds from the surfacing to the first fix.
    pub fix_time: f64,
    /// The current underwater (m/s): the found one less the surface drift
    /// before the fix spread over the time underwater.
    pub underwater: Xy,
    /// The drift at the surface (m/s), if the logs measure one.
    pub surface_drift: Option<Xy>,
}

impl Replay {
    /// The replay of `segment`, whose found current is `found`: the firmware's
    /// `m_final_water = m_initial_water + m_dr_ta_postfix_drift / m_dr_time`,
    /// with the time-adjusted post-fix drift `−drift × m_dr_fix_time`.
    pub fn of(segment: &Segment, found: Xy, config: &SimConfig) -> Replay {
        let fix_time = segment
            .fix_time
            .filter(|seconds| seconds.is_finite() && *seconds >= 0.0)
            .unwrap_or(config.gps_fix_time);
        let dr_time = segment
            .dr_time
            .unwrap_or(segment.end.time - fix_time - segment.start.time);
        let underwater = match segment.surface_drift {
            Some(drift) if dr_time > 0.0 => found - drift * (fix_time / dr_time),
            _ => found,
        };
        Replay {
            fix_time,
            underwater,
            surface_drift: segment.surface_drift,
        }
    }
}

/// Bisection steps for the moment the surfacing comes due (over at most
/// [`DUE_WINDOW`] s: 2 s).
const DUE_STEPS: usize = 11;

/// How long before the real first fix the timed surfacing can have come due
/// (s): a climb from any depth a glider flies, and the time to its fix.
pub const DUE_WINDOW: f64 = 3600.0;

/// The moment (Unix seconds) the mission's timed surfacing comes due so that
/// the simulated glider's first fix after the segment comes when the real
/// one's did: the first fix is a non-decreasing function of it, so bisection.
fn surfacing_due(
    segment: &Segment,
    mission: &Mission,
    sensors: &Arc<SensorList>,
    config: &SimConfig,
    start: &Start,
    interval: f64,
) -> Result<f64, ForecastError> {
    let plan = FlightPlan {
        seconds: segment.end.time - segment.start.time + EXTRA_SECONDS,
        record_every: EXTRA_SECONDS,
        stop_at_first_fix: StopAt::FirstSurfacing,
        outside: Outside::Fail,
    };
    let first_fix = |due: f64| -> Result<f64, ForecastError> {
        let mut start = *start;
        start.timers_elapsed = interval - (due - segment.start.time);
        let prepared = prepare_mission(mission, &start);
        let flight = Flight {
            mission: &prepared,
            sensors,
            config,
            start: &start,
            truth: &Truth::Uniform(segment.prior),
            bathymetry: None,
        };
        let track = fly_with(&flight, &plan, &Extras::default())?.track;
        Ok(track
            .surfacings
            .first()
            .map_or(f64::INFINITY, |surfacing| surfacing.time))
    };
    let target = segment.end.time;
    let mut high = target.min(segment.start.time + interval);
    let mut low = (target - DUE_WINDOW).max(segment.start.time).min(high);
    if first_fix(low)? >= target {
        return Ok(low);
    }
    if first_fix(high)? <= target {
        return Ok(high);
    }
    for _ in 0..DUE_STEPS {
        let middle = 0.5 * (low + high);
        if first_fix(middle)? < target {
            low = middle;
        } else {
            high = middle;
        }
    }
    Ok(0.5 * (low + high))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logs::Fix;

    fn segment(fix_time: Option<f64>, dr_time: Option<f64>, drift: Option<Xy>) -> Segment {
        let fix = |time| Fix {
            time,
            lat: 5418.0,
            lon: 724.0,
        };
        Segment {
            start: fix(0.0),
            end: fix(10_300.0),
            prior: Xy::ZERO,
            found: Some(Xy::new(0.4, -0.1)),
            underwater: 10_000.0,
            waypoint: None,
            avg_speed: None,
            timers_elapsed: 0.0,
            surfacing_began: 9_700.0,
            dr_time,
            fix_time,
            surface_drift: drift,
        }
    }

    #[test]
    fn the_surface_drift_before_the_fix_comes_out_of_the_found_current() {
        let config = SimConfig::default();
        let found = Xy::new(0.4, -0.1);
        // Drifting 0.3 m/s east for the 100 s to the fix, spread over 10,000 s
        // underwater: 0.003 m/s less east. By hand: (0.397, −0.1).
        let replay = Replay::of(
            &segment(Some(100.0), Some(10_000.0), Some(Xy::new(0.3, 0.0))),
            found,
            &config,
        );
        assert_eq!(replay.fix_time, 100.0);
        assert!((replay.underwater.x - 0.397).abs() < 1e-12, "{replay:?}");
        assert!((replay.underwater.y + 0.1).abs() < 1e-12, "{replay:?}");
        // Without the glider's account: the simulator's fix delay, and the time
        // from the start fix to the surfacing (10,300 − 106 s) underwater.
        let replay = Replay::of(
            &segment(None, None, Some(Xy::new(0.3, 0.0))),
            found,
            &config,
        );
        assert_eq!(replay.fix_time, config.gps_fix_time);
        let expected = 0.4 - 0.3 * config.gps_fix_time / (10_300.0 - config.gps_fix_time);
        assert!((replay.underwater.x - expected).abs() < 1e-12, "{replay:?}");
        // No drift measured: the found current.
        assert_eq!(
            Replay::of(&segment(None, None, None), found, &config).underwater,
            found
        );
    }
}
