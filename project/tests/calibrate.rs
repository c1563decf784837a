//! Calibrated on comet's own log (comet-2019-222-02-154.dbd in data/), the simulator flying comet's mission
//! (nsb3.mi with its .ma files) reproduces the log's yo: every figure within
//! 10%, each measured for the real and the simulated log by one function
//! (`calibrate::yo_figures`).

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

fn figures(track: &Track) -> Vec<(&'static str, f64)> {
    let f: YoFigures = yo_figures(track, CLIMB_TARGET).unwrap_or_else(|e| panic!("{e}"));
    vec![
        ("dive rate (m/s)", f.dive_rate),
        ("climb rate (m/s)", f.climb_rate),
        ("dive pitch (rad)", f.dive_pitch),
        ("climb pitch (rad)", f.climb_pitch),
        ("half-yo time (s)", f.half_yo_time),
        ("bottom overshoot (m)", f.bottom_overshoot),
        ("top overshoot (m)", f.top_overshoot),
        ("turn latency (s)", f.turn_latency),
        ("bottom turn time (s)", f.bottom_turn_time),
        ("top turn time (s)", f.top_turn_time),
        ("cycle period (s)", f.cycle_period),
        ("power (W)", f.power),
    ]
}

#[test]
fn calibrated_simulator_reproduces_comets_yo() {
    compare(&[]);
}

fn compare(skip: &[&str]) {
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
    let mut report = String::new();
    let mut worst: f64 = 0.0;
    for ((name, want), (_, got)) in real.iter().zip(&simulated) {
        let off = (got - want).abs() / want.abs();
        if !skip.contains(name) {
            worst = worst.max(off);
        }
        report.push_str(&format!(
            "{name:22} real {want:9.4} sim {got:9.4} ({:+.1}%)\n",
            100.0 * (got - want) / want
        ));
    }
    eprintln!("{}\n{report}", fitted.to_toml("comet"));
    assert!(worst <= 0.10, "a figure is off by more than 10%:\n{report}");
}
