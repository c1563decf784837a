//! The simulator settings of `gloc.toml`'s `[simulator]` table and `gloc run --sim`:
//! every documented name reaches its field, and a setting changes the flight.

use std::sync::Arc;

use gloc_engine::config::SIMULATOR_SETTINGS;
use gloc_engine::sensors::SensorList;
use gloc_sim::{default_mission, SimConfig, Simulation};

#[test]
fn every_documented_setting_reaches_a_field() {
    for setting in SIMULATOR_SETTINGS {
        let mut config = SimConfig::default();
        let before = format!("{config:?}");
        // Every default lies below its setting's maximum, so the maximum changes it.
        assert!(
            config.set(setting.name, setting.max),
            "{} is not mapped",
            setting.name
        );
        assert_ne!(
            format!("{config:?}"),
            before,
            "{} changed nothing",
            setting.name
        );
    }
    assert!(!SimConfig::default().set("warp_speed", 1.0));
}

/// Cycles until the default mission (no script) first passes 10 m.
fn cycles_to_ten_metres(config: &SimConfig) -> u64 {
    let mut sim = Simulation::new(
        &default_mission(),
        Arc::new(SensorList::embedded()),
        None,
        config,
    )
    .expect("the default mission starts");
    for cycle in 0..500 {
        if sim.depth() > 10.0 {
            return cycle;
        }
        assert!(sim.step_cycle(), "the mission ended before 10 m");
    }
    panic!("never reached 10 m");
}

#[test]
fn a_faster_dive_rate_reaches_depth_sooner() {
    // At full dive volume the glider sinks at `dive_rate`: 10 m takes at least
    // 10 / 0.16 = 62.5 s by default and 10 / 0.30 = 33 s at twice the rate, the
    // pump and pitch time being the same in both. 29 s is 6.5 cycles of 4.5 s,
    // so the faster glider is there at least 5 cycles earlier (rounding both ways).
    let slow = cycles_to_ten_metres(&SimConfig::default());
    let mut fast_config = SimConfig::default();
    assert!(fast_config.set("dive_rate", 0.30));
    let fast = cycles_to_ten_metres(&fast_config);
    assert!(fast + 5 <= slow, "fast {fast} cycles, slow {slow} cycles");
}
