//! The thermocline tracker (`examples/thermocline.gbas` with `examples/thermocline.mi`)
//! flown in the simulator: its turns must follow the thermocline that the same
//! algorithm finds on the noise-free profile, computed here independently.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};
use gloc_engine::sensors::SensorList;
use gloc_sim::{Mission, SimConfig, Simulation, TemperatureProfile};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// One cycle's record.
struct Sample {
    depth: f64,
    climb_depth: f64,
    dive_depth: f64,
}

struct Flight {
    samples: Vec<Sample>,
    printed: Vec<String>,
    ended: bool,
}

fn fly(profile: Option<TemperatureProfile>, cycles: usize, optimization: Optimization) -> Flight {
    let sensors = Arc::new(SensorList::embedded());
    let text =
        std::fs::read_to_string(root().join("examples/thermocline.gbas")).expect("the tracker");
    let loaded = load_script(
        &text,
        Language::Gbasic,
        &sensors,
        &LoadOptions::from(optimization),
    );
    assert!(loaded.program.is_some(), "{:?}", loaded.diagnostics);
    let mission = Mission::load(&root().join("examples/thermocline.mi"));
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    let config = SimConfig {
        profile,
        ..SimConfig::default()
    };
    let mut sim = Simulation::new(
        &mission,
        Arc::clone(&sensors),
        loaded.program.clone(),
        &config,
    )
    .expect("simulation");
    let climb = sensors.lookup("sci_ruhp_climb_depth").expect("hook sensor");
    let dive = sensors.lookup("sci_ruhp_dive_depth").expect("hook sensor");
    let mut samples = Vec::with_capacity(cycles);
    let mut printed = Vec::new();
    let mut ended = false;
    for _ in 0..cycles {
        if !sim.step_cycle() {
            ended = true;
            break;
        }
        printed.extend(sim.printed().map(str::to_string));
        assert!(
            sim.script_trap().is_none(),
            "the tracker trapped: {:?}",
            sim.script_trap()
        );
        samples.push(Sample {
            depth: sim.depth(),
            climb_depth: sim.sensor(climb).unwrap_or(0.0),
            dive_depth: sim.sensor(dive).unwrap_or(0.0),
        });
    }
    Flight {
        samples,
        printed,
        ended,
    }
}

/// Turning points of a depth record: (cycle, depth, is_bottom). A turn is taken
/// once the glider has come back 0.5 m from its extreme.
fn turns(samples: &[Sample]) -> Vec<(usize, f64, bool)> {
    let mut turns = Vec::new();
    let mut descending = true;
    let mut extreme = samples.first().map_or(0.0, |sample| sample.depth);
    let mut at = 0;
    for (cycle, sample) in samples.iter().enumerate() {
        let depth = sample.depth;
        if descending {
            if depth > extreme {
                extreme = depth;
                at = cycle;
            } else if depth < extreme - 0.5 {
                turns.push((at, extreme, true));
                descending = false;
                extreme = depth;
                at = cycle;
            }
        } else if depth < extreme {
            extreme = depth;
            at = cycle;
        } else if depth > extreme + 0.5 {
            turns.push((at, extreme, false));
            descending = true;
            extreme = depth;
            at = cycle;
        }
    }
    turns
}

/// Petillo's bounds on a noise-free profile, written independently of the script:
/// 1 m bins 0..=deepest (bin i averaged as T(i + 0.5)), |dT/dz| between
/// neighbours, the mean of those, and the span of the depths (i + 1) where the
/// derivative exceeds the mean; never shallower than 2 m, at least 2 m thick.
fn true_bounds(profile: &TemperatureProfile, deepest_bin: usize) -> (f64, f64) {
    let averages: Vec<f64> = (0..=deepest_bin)
        .map(|bin| profile.temperature(bin as f64 + 0.5))
        .collect();
    let gradients: Vec<f64> = averages
        .windows(2)
        .map(|pair| (pair[1] - pair[0]).abs())
        .collect();
    let mean = gradients.iter().sum::<f64>() / gradients.len() as f64;
    let above: Vec<usize> = (0..gradients.len())
        .filter(|&index| gradients[index] > mean)
        .collect();
    let upper = (above[0] + 1) as f64;
    let lower = (above[above.len() - 1] + 1) as f64;
    let upper = upper.max(2.0);
    (upper, lower.max(upper + 2.0))
}

#[test]
fn twelve_hours_on_the_built_in_profile_turn_at_the_true_bounds() {
    // 12 hours of cycles of 4.51 s on average (u_cycle_time 4 s plus comet's overrun).
    let flight = fly(None, (12.0 * 3600.0 / 4.51) as usize, Optimization::Plain);
    assert!(
        !flight.ended,
        "the mission ended early: {:?}",
        flight.printed.last()
    );
    let turns = turns(&flight.samples);
    let (first_cycle, first_depth, first_is_bottom) = turns[0];
    assert!(
        first_is_bottom && first_depth > 30.0,
        "the first leg is a full-depth dive: {turns:?}"
    );
    // The bins the first dive filled.
    let deepest_bin = flight.samples[..=first_cycle]
        .iter()
        .map(|sample| sample.depth.floor() as usize)
        .max()
        .unwrap_or(0);
    let (upper, lower) = true_bounds(&TemperatureProfile::default(), deepest_bin);
    assert!(
        (8.0..=14.0).contains(&upper) && (18.0..=24.0).contains(&lower),
        "true bounds {upper}–{lower}"
    );
    let later = &turns[1..];
    assert!(
        later.len() > 100,
        "too few turns in 12 hours: {}",
        later.len()
    );
    // Where a turn can land (the simulator's defaults: comet's 0.16 / 0.13
    // m/s, 4.5 s cycles, overshoot 1.62 m at the bottom and 1.22 m at the top,
    // each ± 10%): past the bound by at most three cycles of travel (the
    // cycle the crossing is seen in, the hook's, the pump's turn) plus the
    // overshoot, and never short of it: bottom turns in [lower, lower + 3 ×
    // 0.72 + 1.78], top turns in [upper − 3 × 0.59 − 1.34, upper].
    let close = later
        .iter()
        .filter(|(_, depth, is_bottom)| {
            if *is_bottom {
                (lower..=lower + 3.0 * 0.72 + 1.78).contains(depth)
            } else {
                (upper - 3.0 * 0.59 - 1.34..=upper).contains(depth)
            }
        })
        .count();
    let share = close as f64 / later.len() as f64;
    println!(
        "true bounds {upper}–{lower} m; {close} of {} turns in their windows ({:.1}%)",
        later.len(),
        share * 100.0
    );
    assert!(
        share >= 0.9,
        "only {close} of {} turns in the windows of {upper}/{lower}: {later:?}",
        later.len()
    );
}

#[test]
fn the_amadeus_profile_gives_bounds_of_about_3_and_13_m() {
    // A missing file is a broken checkout, not a reason to pass.
    let (path, text) = gloc_testsupport::data_text("amadeus_2014-07-24_temp_profile.csv");
    let profile = TemperatureProfile::from_csv(&path, &text).expect("the amadeus profile parses");
    // Three hours are plenty for the first profile and several turns.
    let flight = fly(Some(profile), 3 * 3600 / 4, Optimization::Plain);
    let turns = turns(&flight.samples);
    assert!(turns.len() > 4, "{turns:?}");
    // The bounds the script settles on once a few legs have filled its bins.
    let last = flight.samples.last().expect("samples");
    println!(
        "amadeus: climb to {} m, dive to {} m",
        last.climb_depth, last.dive_depth
    );
    // 3 m, or 6 m when the mean |dT/dz| over the bins sampled leaves the 2.5–3.5 m
    // step (0.157 °C/m) out: it is the mean itself with bins to 36 m, under the mean
    // (0.188) with bins to 30 m (cli/tests/thermocline_run.rs works it through).
    assert!(
        (2.0..=4.0).contains(&last.climb_depth) || last.climb_depth == 6.0,
        "upper bound {}",
        last.climb_depth
    );
    assert!(
        (12.0..=14.0).contains(&last.dive_depth),
        "lower bound {}",
        last.dive_depth
    );
}

#[test]
fn well_mixed_water_has_no_thermocline() {
    // comet's water on 2019-08-21 (domain notes §4): 18.4 °C at the surface to
    // 17.9 °C at 42 m, 0.012 °C/m everywhere. Every 1 m derivative is then
    // about 0.012 (plus the CTD noise of 0.01 °C over a bin's samples), far
    // below the tracker's MINGRAD of 0.1 °C/m, so however they compare with
    // their mean there is no thermocline: the tracker keeps flying the full
    // range, from SHALLOWEST (2 m) to the full-depth dive's 40 m
    // (thermocline.mi's 44 m of water less MARGIN).
    let profile = TemperatureProfile::Table(vec![(0.0, 18.4), (42.0, 17.9)]);
    let flight = fly(Some(profile), 3 * 3600 / 4, Optimization::Plain);
    assert!(turns(&flight.samples).len() > 4);
    let last = flight.samples.last().expect("samples");
    assert_eq!(
        (last.climb_depth, last.dive_depth),
        (2.0, 40.0),
        "printed {:?}",
        flight.printed
    );
    assert!(
        flight
            .printed
            .iter()
            .all(|line| line == "thermocline from 2.0 to 40.0 m"),
        "{:?}",
        flight.printed
    );
}

#[test]
fn the_tracker_flies_the_same_with_and_without_optimization() {
    let cycles = 2 * 3600 / 4;
    let plain = fly(None, cycles, Optimization::Plain);
    let optimized = fly(None, cycles, Optimization::Optimized);
    assert_eq!(plain.printed, optimized.printed);
    let depths = |flight: &Flight| {
        flight
            .samples
            .iter()
            .map(|sample| sample.depth.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(depths(&plain), depths(&optimized));
}
