//! Energy: a used-up battery ends the mission, and the energy by consumer adds
//! up to the total.

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::{default_mission, EndReason, SimConfig, Simulation};

fn sim(config: &SimConfig) -> Simulation {
    Simulation::new(
        &default_mission(),
        Arc::new(SensorList::embedded()),
        None,
        config,
    )
    .expect("the default mission starts")
}

#[test]
fn an_exhausted_battery_ends_the_run() {
    // 1 Wh is 3,600 J; the default mission needs about 10 kJ (its summary in
    // docs/simulator.md), so the battery runs out on the way.
    let mut config = SimConfig::default();
    assert!(config.set("battery_wh", 1.0));
    let mut sim = sim(&config);
    let mut cycles = 0;
    while sim.step_cycle() {
        cycles += 1;
        assert!(cycles < 100_000, "never ended");
    }
    let end = sim.end().expect("the run ended");
    assert_eq!(end.reason, EndReason::BatteryExhausted);
    // It stops in the cycle that used the last joule: at most one cycle's
    // worth past the capacity (hotel 1.31 W and a 4 s pump stroke of 92 cc at
    // 2.49 + 0.0123 × 40 J/cc stay well under 400 J).
    let used = sim.energy_joules();
    assert!((3600.0..4000.0).contains(&used), "{used} J");
    // Without the limit the same mission completes.
    let mut full = self::sim(&SimConfig::default());
    while full.step_cycle() {}
    assert_eq!(full.end().map(|end| end.reason), Some(EndReason::Completed));
    assert!(full.energy_joules() > 3600.0);
}

#[test]
fn energy_by_consumer_adds_up() {
    let mut sim = sim(&SimConfig::default());
    while sim.step_cycle() {}
    let by = sim.energy_use();
    assert!((by.total() - sim.energy_joules()).abs() < 1e-6 * sim.energy_joules());
    // Fig. 2's yo servoes pitch (use_pitch 3): the battery moves at each turn.
    assert!(by.pitch > 0.0 && by.pump > 0.0 && by.hotel > 0.0);
}

#[test]
fn the_science_computer_draws_by_its_power_state() {
    let mut config = SimConfig::default();
    for (name, value) in [
        ("science_on_power", 2.0),
        ("science_sleep_power", 0.1),
        ("science_wake_time", 10.0),
        ("science_wake_joules", 5.0),
    ] {
        assert!(config.set(name, value), "{name}");
    }
    let mut sim = sim(&config);
    let list = sim.sensor_list().clone();
    let command = list.lookup("c_science_on").expect("c_science_on");
    let state = list.lookup("m_science_on").expect("m_science_on");
    // Woken at the start: one wake (5 J), then 2 W for every second flown,
    // waking included; m_science_on reads 1 from the first cycle that starts
    // 10 s or more after the wake.
    assert!(sim.set_sensor(command, 1.0));
    let mut awake_at = None;
    for _ in 0..10 {
        let start = sim.time();
        assert!(sim.step_cycle());
        if sim.sensor(state) == Some(1.0) && awake_at.is_none() {
            awake_at = Some(start);
        }
    }
    let awake_at = awake_at.expect("awake within 10 cycles");
    assert!((10.0..15.0).contains(&awake_at), "awake at {awake_at} s");
    let flown = sim.time();
    let expected = 5.0 + 2.0 * flown;
    assert!(
        (sim.energy_use().science - expected).abs() < 1e-6,
        "{:?}",
        sim.energy_use()
    );
    // Asleep: 0.1 W, and no further wake.
    assert!(sim.set_sensor(command, 0.0));
    for _ in 0..10 {
        assert!(sim.step_cycle());
    }
    let expected = expected + 0.1 * (sim.time() - flown);
    assert!(
        (sim.energy_use().science - expected).abs() < 1e-6,
        "{:?}",
        sim.energy_use()
    );
    assert_eq!(sim.sensor(state), Some(0.0));
    assert_eq!(sim.science_wakes(), 1);
}

#[test]
fn a_battery_started_part_used_sags_and_counts_on() {
    // Half the capacity used: the open-circuit voltage halfway from 13.74 V
    // to 10 V, 11.87 V by hand; the coulomb count continues from 100 Ah.
    let mut sim = sim(&SimConfig::default());
    sim.start_battery(0.5, 100.0);
    assert!(
        (sim.battery_volts() - 11.87).abs() < 1e-9,
        "{}",
        sim.battery_volts()
    );
    assert_eq!(sim.amp_hours(), 100.0);
    // Out of range or after the first cycle: ignored.
    sim.start_battery(1.5, f64::NAN);
    assert!((sim.battery_volts() - 11.87).abs() < 1e-9);
    assert!(sim.step_cycle());
    sim.start_battery(0.0, 0.0);
    assert!(sim.amp_hours() > 100.0);
}
