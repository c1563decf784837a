//! Calibrated on comet's own log (comet-2019-222-02-154.dbd in data/), the simulator flying comet's mission
//! (nsb3.mi with its .ma files) reproduces the log's yo: the steady figures
//! within 10%, the turn times and overshoots within 15%, each measured for the
//! real and the simulated log by one function (`calibrate::yo_figures`). The
//! overshoot needs the pump's lead and the ballast delay `gloc calibrate` fits
//! (docs/simulator.md §Turns): without them the simulated glider stops 1.28 /
//! 0.91 m past the turns, 21% and 25% short.
//!
//! comet 154's own turn figures, checked by an independent route (dbdreader's
//! `get_sync` on m_depth and c_ballast_pumped, the same definitions in a short
//! numpy script): from the command to 90% of the next leg's rate 18.72 s at the
//! bottom and 18.86 s at the top (medians of 16 each; the first bottom turn
//! 18.71 s); overshoot 1.621 m at the bottom and 1.216 m at the top.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_sim::calibrate::{fit, yo_figures, Track, YoFigures};
use gloc_sim::{Mission, SimConfig, Simulation};

fn data() -> PathBuf {
    gloc_testsupport::data("")
}

/// comet's yo10.ma: `c_target_depth(m) 3`.
const CLIMB_TARGET: f64 = 3.0;

fn real_track(data: &Path) -> Track {
    let log = data.join("comet/from-glider/comet-2019-222-02-154.dbd");
    let mut source =
        gloc_dbd::open_path(&log, Some(&data.join("cac"))).unwrap_or_else(|e| panic!("{e}"));
    gloc_project::logs::read_track(source.as_mut()).unwrap_or_else(|e| panic!("{e}"))
}

fn simulated_track(data: &Path, config: &SimConfig, seconds: f64) -> Track {
    let mission = Mission::load(&data.join("comet/missions/nsb3.mi"));
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    let (list, problems) = gloc_engine::sensors::parse_cac(
        &std::fs::read_to_string(data.join("cac/1f35be3b.cac")).expect("comet's sensor list"),
    );
    assert!(problems.is_empty(), "{problems:?}");
    let mut sim = Simulation::new(&mission, Arc::new(list), None, config).expect("starts");
    let mut track = Track::default();
    while sim.time() < seconds && sim.step_cycle() {
        track.record(&sim);
    }
    track
}

/// A figure, and how far the simulation may be from the log (a fraction).
type Figure = (&'static str, f64, f64);

fn figures(track: &Track) -> Vec<Figure> {
    let f: YoFigures = yo_figures(track, CLIMB_TARGET).unwrap_or_else(|e| panic!("{e}"));
    vec![
        ("dive rate (m/s)", f.dive_rate, 0.10),
        ("climb rate (m/s)", f.climb_rate, 0.10),
        ("dive pitch (rad)", f.dive_pitch, 0.10),
        ("climb pitch (rad)", f.climb_pitch, 0.10),
        ("half-yo time (s)", f.half_yo_time, 0.10),
        ("turn latency (s)", f.turn_latency, 0.10),
        ("cycle period (s)", f.cycle_period, 0.10),
        ("power (W)", f.power, 0.10),
        ("bottom turn time (s)", f.bottom_turn_time, 0.15),
        ("top turn time (s)", f.top_turn_time, 0.15),
        ("bottom overshoot (m)", f.bottom_overshoot, 0.15),
        ("top overshoot (m)", f.top_overshoot, 0.15),
    ]
}

#[test]
fn calibrated_simulator_reproduces_comets_yo() {
    let data = data();
    let real = real_track(&data);
    let mut config = SimConfig::default();
    let fitted = fit(&real, CLIMB_TARGET, &config).unwrap_or_else(|e| panic!("{e}"));
    fitted.apply(&mut config);
    // The water under comet: its altimeter's fixes (m_depth + m_altitude).
    config.water_depth = real.water_depth();
    assert!(config
        .water_depth
        .is_some_and(|depth| (38.0..46.0).contains(&depth)));
    let span = real.rows.last().map(|r| r.time).unwrap_or(0.0) - real.rows[0].time;
    let simulated = simulated_track(&data, &config, span);
    let (real, simulated) = (figures(&real), figures(&simulated));
    // The log's turn figures as the independent script found them (above).
    let find = |name: &str| real.iter().find(|f| f.0 == name).map(|f| f.1);
    for (name, want) in [
        ("bottom turn time (s)", 18.72),
        ("top turn time (s)", 18.86),
        ("bottom overshoot (m)", 1.621),
        ("top overshoot (m)", 1.216),
    ] {
        let got = find(name).expect("measured");
        assert!(
            (got - want).abs() < 0.01,
            "{name}: {got} by yo_figures, {want} by dbdreader"
        );
    }
    let mut report = String::new();
    let mut failed = Vec::new();
    for ((name, want, allowed), (_, got, _)) in real.iter().zip(&simulated) {
        let off = (got - want) / want;
        if off.abs() > *allowed {
            failed.push(*name);
        }
        report.push_str(&format!(
            "{name:22} real {want:9.4} sim {got:9.4} ({:+.1}%, within {:.0}%)\n",
            100.0 * off,
            100.0 * allowed
        ));
    }
    eprintln!("{}\n{report}", fitted.to_toml("comet"));
    assert!(
        failed.is_empty(),
        "{failed:?} off by more than allowed:\n{report}"
    );
}
