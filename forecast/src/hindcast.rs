//! Hindcasts: each logged segment flown again from its start (the last fix
//! before the dive, the belief the glider dove with, its waypoint and surface
//! timers) in the current the glider found after it, and compared with the
//! real first fix after the surfacing; beside it the null model, the prior
//! current taken as the truth, which is what a forecast made at the dive
//! would have used. The distances are the accuracy a pilot can quote.

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::{Mission, SimConfig};

use crate::fly::{fly, prepare_mission, FlightPlan, Outside, Start, StopAt, Truth};
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
}

/// The shortest `when_secs` of the mission's timed surface behaviors
/// (start_when 9 or 10: every N seconds since the last start).
///
/// Decision: a hindcast knows when the real glider began the surfacing
/// that ended a segment; it starts the mission's timers so that the timed
/// surfacing comes due then. The hindcast then measures where the glider
/// comes up, not when (a forecast takes the timers from the surfacing
/// before its start, [`crate::logs::Segment::timers_elapsed`]).
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
        let mut start = Start::of_segment(segment, history);
        if let Some(interval) = timed_surface_interval(mission) {
            let due_after = segment.surfacing_began - segment.start.time;
            if (0.0..=interval).contains(&due_after) {
                start.timers_elapsed = interval - due_after;
            }
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
        let fly_in = |water| -> Result<_, ForecastError> {
            let track = fly(
                &prepared,
                sensors,
                config,
                &start,
                &Truth::Uniform(water),
                None,
                &plan,
            )?;
            let points: Vec<(f64, f64)> = track.points.iter().map(|p| (p.lat, p.lon)).collect();
            let first = track.surfacings.first().map(|s| {
                (
                    lmc.to_xy(s.lat, s.lon).distance(real),
                    (s.lat, s.lon, s.time),
                )
            });
            Ok((first, points))
        };
        let (with_found, track) = fly_in(found)?;
        let (with_prior, null_track) = fly_in(segment.prior)?;
        results.push(SegmentHindcast {
            segment: *segment,
            miss: with_found.map(|(miss, _)| miss),
            null_miss: with_prior.map(|(miss, _)| miss),
            simulated: with_found.map(|(_, at)| at),
            bound: bound(segment.underwater),
            track,
            null_track,
        });
    }
    Ok(results)
}
