//! A seeded ensemble over the current's uncertainty: each member flies the
//! mission with the forecast's current plus a constant offset drawn from a
//! normal distribution (σ per component), on scoped threads that take the
//! next member from a shared counter. A member's offset and simulator seed
//! come from the ensemble seed and the member's number only, and results are
//! kept by number, so the same seed gives the same members on any number of
//! threads. Per hour, the convex hull of the members' positions is the region
//! the glider can be in; per surfacing, the hull and spread of the members'
//! n-th surfacings.

use std::sync::atomic::{AtomicUsize, Ordering};

use gloc_engine::rng::Rng;
use gloc_sim::navigation::{Lmc, Xy};
use gloc_sim::SimConfig;

use crate::fly::{fly_with, Extras, Flight, FlightPlan, Outside, StopAt, Track, Truth};
use crate::logs::LogHistory;
use crate::ForecastError;

/// The smallest σ of the current (m/s per component): the accuracy of a
/// glider's depth-averaged current (0.01–0.02 m/s, Rudnick et al.).
pub const MIN_SPREAD: f64 = 0.02;

/// The most members.
pub const MAX_MEMBERS: usize = 100_000;

/// What is wrong with an ensemble of `members`, if anything: 1 to [`MAX_MEMBERS`].
/// Every surface asks here and names its own input in the error.
pub fn check_members(members: usize) -> Result<(), String> {
    if (1..=MAX_MEMBERS).contains(&members) {
        Ok(())
    } else {
        Err(format!("give 1 to {MAX_MEMBERS} members"))
    }
}

/// What an ensemble flies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnsembleOptions {
    pub members: usize,
    pub seed: u64,
    /// σ of the current's offset, x (east) and y (north) (m/s).
    pub spread: Xy,
    /// Threads (at least 1).
    pub threads: usize,
}

/// The region the members occupy at one hour.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// Hours after the start.
    pub hour: usize,
    /// Unix seconds.
    pub time: f64,
    /// The convex hull (decimal degrees lat, lon), counter-clockwise.
    pub hull: Vec<(f64, f64)>,
    /// Members still flying then.
    pub members: usize,
}

/// The spread of the members' n-th surfacing.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfacingSpread {
    /// 1 for the first surfacing after the start.
    pub number: usize,
    pub members: usize,
    pub earliest: f64,
    pub latest: f64,
    pub mean_time: f64,
    /// Mean position (decimal degrees).
    pub mean: (f64, f64),
    /// Distances from the mean (m) within which 95% and all members surface.
    pub radius_95: f64,
    pub radius_max: f64,
    pub hull: Vec<(f64, f64)>,
}

/// An ensemble's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Ensemble {
    pub members: usize,
    pub seed: u64,
    pub spread: Xy,
    /// Each member's current offset, by member number.
    pub offsets: Vec<Xy>,
    pub regions: Vec<Region>,
    pub surfacings: Vec<SurfacingSpread>,
    /// Members whose track left the current or bathymetry grid, with where and
    /// when: they count in the regions up to then.
    pub left_grid: Vec<(usize, String)>,
}

/// The default σ: the spread (standard deviation per component) of the
/// glider's own current estimates in the logs, at least [`MIN_SPREAD`].
pub fn spread_from_history(history: &LogHistory) -> Xy {
    let values: Vec<Xy> = history.estimates.iter().map(|e| e.water).collect();
    if values.len() < 2 {
        return Xy::new(MIN_SPREAD, MIN_SPREAD);
    }
    let count = values.len() as f64;
    let mean = values.iter().fold(Xy::ZERO, |sum, v| sum + *v) * (1.0 / count);
    let variance = values.iter().fold(Xy::ZERO, |sum, v| {
        let d = *v - mean;
        sum + Xy::new(d.x * d.x, d.y * d.y)
    }) * (1.0 / (count - 1.0));
    Xy::new(
        variance.x.sqrt().max(MIN_SPREAD),
        variance.y.sqrt().max(MIN_SPREAD),
    )
}

/// Member `number`'s generator: from the ensemble seed and the number only.
fn member_rng(seed: u64, number: usize) -> Rng {
    let mut mixer = Rng::new(seed ^ (number as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    Rng::new(mixer.next_u64())
}

/// Member `number`'s current offset and simulator seed.
pub fn member_draw(options: &EnsembleOptions, number: usize) -> (Xy, u64) {
    let mut rng = member_rng(options.seed, number);
    let offset = Xy::new(
        options.spread.x * rng.normal(),
        options.spread.y * rng.normal(),
    );
    (offset, rng.next_u64())
}

/// Everything a member needs, shared by the threads.
pub struct EnsembleInput<'a> {
    /// The forecast's own flight: each member adds its offset to the current and
    /// flies with its own seed.
    pub flight: Flight<'a>,
    pub hours: f64,
}

/// Flies the members and reduces them to regions and surfacing spreads.
pub fn run_ensemble(
    input: &EnsembleInput<'_>,
    options: &EnsembleOptions,
) -> Result<Ensemble, ForecastError> {
    let tracks = fly_members(input, options)?;
    Ok(summarize(input, options, &tracks))
}

/// The members' tracks (by number, as [`fly_members`] or [`fly_member`] gave
/// them) reduced to the regions per hour and the surfacing spreads.
pub fn summarize(
    input: &EnsembleInput<'_>,
    options: &EnsembleOptions,
    tracks: &[Track],
) -> Ensemble {
    let lmc = input.flight.start.lmc();
    let offsets = (0..options.members)
        .map(|number| member_draw(options, number).0)
        .collect();
    let hours = input.hours.max(0.0).floor() as usize;
    let mut regions = Vec::with_capacity(hours);
    for hour in 1..=hours {
        let time = input.flight.start.time + hour as f64 * 3600.0;
        let positions: Vec<Xy> = tracks
            .iter()
            .filter_map(|track| {
                track
                    .points
                    .iter()
                    // The first cycle at or after the hour (a cycle is about 4.5 s).
                    .find(|point| point.time >= time - 0.5 && point.time < time + 60.0)
                    .map(|point| lmc.to_xy(point.lat, point.lon))
            })
            .collect();
        if positions.is_empty() {
            continue;
        }
        regions.push(Region {
            hour,
            time,
            hull: hull_degrees(&lmc, &positions),
            members: positions.len(),
        });
    }
    let most = tracks.iter().map(|t| t.surfacings.len()).max().unwrap_or(0);
    let mut surfacings = Vec::with_capacity(most);
    for index in 0..most {
        let found: Vec<(f64, Xy)> = tracks
            .iter()
            .filter_map(|track| track.surfacings.get(index))
            .map(|s| (s.time, lmc.to_xy(s.lat, s.lon)))
            .collect();
        surfacings.push(spread_of(index + 1, &found, &lmc));
    }
    let left_grid = tracks
        .iter()
        .enumerate()
        .filter_map(|(number, track)| track.left_grid.clone().map(|message| (number, message)))
        .collect();
    Ensemble {
        left_grid,
        members: options.members,
        seed: options.seed,
        spread: options.spread,
        offsets,
        regions,
        surfacings,
    }
}

/// Each member's track (a point every hour, and its surfacings), by number.
pub fn fly_members(
    input: &EnsembleInput<'_>,
    options: &EnsembleOptions,
) -> Result<Vec<Track>, ForecastError> {
    let count = options.members.min(MAX_MEMBERS);
    let next = AtomicUsize::new(0);
    let threads = options.threads.clamp(1, count.max(1));
    let results: Vec<Vec<(usize, Result<Track, ForecastError>)>> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let number = next.fetch_add(1, Ordering::Relaxed);
                        if number >= count {
                            break;
                        }
                        done.push((number, fly_member(input, options, number)));
                    }
                    done
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|worker| worker.join().unwrap_or_default())
            .collect()
    });
    let mut tracks: Vec<Option<Track>> = vec![None; count];
    for (number, track) in results.into_iter().flatten() {
        tracks[number] = Some(track?);
    }
    tracks
        .into_iter()
        .enumerate()
        .map(|(number, track)| {
            track.ok_or_else(|| ForecastError::Mission(format!("member {number} did not fly")))
        })
        .collect()
}

/// Member `number`'s track (a point every hour, and its surfacings): the
/// forecast's current plus the member's offset, the simulator seeded with the
/// member's draw. It depends on the ensemble's seed and spread and on `number`
/// only, so members flown apart (threads, processes, machines) are the same.
pub fn fly_member(
    input: &EnsembleInput<'_>,
    options: &EnsembleOptions,
    number: usize,
) -> Result<Track, ForecastError> {
    let plan = FlightPlan {
        seconds: input.hours * 3600.0,
        record_every: 3600.0,
        stop_at_first_fix: StopAt::Horizon,
        outside: Outside::Stop,
    };
    let (offset, seed) = member_draw(options, number);
    let truth = match input.flight.truth {
        Truth::Uniform(water) => Truth::Uniform(*water + offset),
        Truth::Field(field, base) => Truth::Field(field.clone(), *base + offset),
    };
    let config = SimConfig {
        seed,
        ..input.flight.config.clone()
    };
    let flight = Flight {
        config: &config,
        truth: &truth,
        ..input.flight
    };
    fly_with(&flight, &plan, &Extras::default()).map(|flown| flown.track)
}

fn spread_of(number: usize, found: &[(f64, Xy)], lmc: &Lmc) -> SurfacingSpread {
    let count = found.len().max(1) as f64;
    let mean_time = found.iter().map(|(t, _)| t).sum::<f64>() / count;
    let mean = found.iter().fold(Xy::ZERO, |sum, (_, at)| sum + *at) * (1.0 / count);
    let mut distances: Vec<f64> = found.iter().map(|(_, at)| at.distance(mean)).collect();
    distances.sort_by(f64::total_cmp);
    let percentile = |p: f64| -> f64 {
        if distances.is_empty() {
            return 0.0;
        }
        let rank = ((p * distances.len() as f64).ceil() as usize).clamp(1, distances.len());
        distances[rank - 1]
    };
    let points: Vec<Xy> = found.iter().map(|(_, at)| *at).collect();
    SurfacingSpread {
        number,
        members: found.len(),
        earliest: found.iter().map(|(t, _)| *t).fold(f64::INFINITY, f64::min),
        latest: found
            .iter()
            .map(|(t, _)| *t)
            .fold(f64::NEG_INFINITY, f64::max),
        mean_time,
        mean: lmc.to_lat_lon(mean),
        radius_95: percentile(0.95),
        radius_max: distances.last().copied().unwrap_or(0.0),
        hull: hull_degrees(lmc, &points),
    }
}

fn hull_degrees(lmc: &Lmc, points: &[Xy]) -> Vec<(f64, f64)> {
    convex_hull(points)
        .into_iter()
        .map(|at| lmc.to_lat_lon(at))
        .collect()
}

/// The convex hull, counter-clockwise, without repeated or collinear points
/// (Andrew's monotone chain). Fewer than three distinct points: those points.
pub fn convex_hull(points: &[Xy]) -> Vec<Xy> {
    let mut sorted: Vec<Xy> = points
        .iter()
        .copied()
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let cross = |o: Xy, a: Xy, b: Xy| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    let mut hull: Vec<Xy> = Vec::with_capacity(2 * sorted.len());
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &Xy>> = if pass == 0 {
            Box::new(sorted.iter())
        } else {
            Box::new(sorted.iter().rev())
        };
        for &point in ordered {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], point) <= 0.0
            {
                hull.pop();
            }
            hull.push(point);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        // All collinear: the two ends.
        let ends = [sorted[0], sorted[sorted.len() - 1]];
        return ends.to_vec();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ensemble_has_1_to_100000_members() {
        for (members, allowed) in [(0, false), (1, true), (100_000, true), (100_001, false)] {
            assert_eq!(check_members(members).is_ok(), allowed, "{members}");
        }
    }

    #[test]
    fn the_hull_of_a_square_with_inner_points_is_its_corners_counter_clockwise() {
        let points = [
            Xy::new(0.0, 0.0),
            Xy::new(1.0, 0.0),
            Xy::new(1.0, 1.0),
            Xy::new(0.0, 1.0),
            Xy::new(0.5, 0.5),
            Xy::new(0.5, 0.0),
            Xy::new(1.0, 1.0),
        ];
        let hull = convex_hull(&points);
        assert_eq!(
            hull,
            vec![
                Xy::new(0.0, 0.0),
                Xy::new(1.0, 0.0),
                Xy::new(1.0, 1.0),
                Xy::new(0.0, 1.0)
            ]
        );
        // Shoelace area > 0: counter-clockwise.
        let area: f64 = (0..hull.len())
            .map(|i| {
                let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
                a.x * b.y - b.x * a.y
            })
            .sum();
        assert!(area > 0.0);
        let line = convex_hull(&[Xy::new(0.0, 0.0), Xy::new(1.0, 1.0), Xy::new(2.0, 2.0)]);
        assert_eq!(line, vec![Xy::new(0.0, 0.0), Xy::new(2.0, 2.0)]);
        assert_eq!(convex_hull(&[Xy::new(3.0, 4.0)]), vec![Xy::new(3.0, 4.0)]);
    }

    #[test]
    fn members_depend_on_the_seed_and_number_only() {
        let options = EnsembleOptions {
            members: 10,
            seed: 7,
            spread: Xy::new(0.1, 0.05),
            threads: 1,
        };
        let a = member_draw(&options, 3);
        let b = member_draw(
            &EnsembleOptions {
                threads: 8,
                ..options
            },
            3,
        );
        assert_eq!(a, b);
        assert_ne!(member_draw(&options, 4), a);
        // The offsets' spread is the σ asked for (2,000 draws: within 10%).
        let draws: Vec<Xy> = (0..2000).map(|n| member_draw(&options, n).0).collect();
        let sd = |f: fn(&Xy) -> f64| {
            let mean = draws.iter().map(f).sum::<f64>() / 2000.0;
            (draws.iter().map(|d| (f(d) - mean).powi(2)).sum::<f64>() / 1999.0).sqrt()
        };
        assert!((sd(|d| d.x) / 0.1 - 1.0).abs() < 0.1, "{}", sd(|d| d.x));
        assert!((sd(|d| d.y) / 0.05 - 1.0).abs() < 0.1, "{}", sd(|d| d.y));
    }
}
