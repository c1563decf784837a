//! The control cycle's period and the altimeter, with the defaults (comet's).

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::{default_mission, SimConfig, Simulation};

fn sim() -> Simulation {
    Simulation::new(
        &default_mission(),
        Arc::new(SensorList::embedded()),
        None,
        &SimConfig::default(),
    )
    .expect("the default mission starts")
}

#[test]
fn cycles_last_u_cycle_time_plus_the_overrun_with_a_seeded_spread() {
    // u_cycle_time 4 s + 0.51 s, spread 0.13 s (comet-2019-222-02-154.dbd).
    let mut sim = sim();
    let mut periods = Vec::new();
    let mut start = sim.time();
    while sim.step_cycle() {
        periods.push(sim.time() - start);
        start = sim.time();
    }
    let n = periods.len() as f64;
    assert!(n > 200.0);
    let mean = periods.iter().sum::<f64>() / n;
    let sd = (periods.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / n).sqrt();
    // Standard error of the mean 0.13 / sqrt(n) < 0.01; of the spread about 7%.
    assert!((mean - 4.51).abs() < 0.03, "mean {mean}");
    assert!((sd - 0.13).abs() < 0.03, "spread {sd}");
    // None exactly 4 s, none outside the triangular law's ±sqrt(6)·0.13 s.
    let half = 6f64.sqrt() * 0.13;
    assert!(periods.iter().all(|p| (p - 4.51).abs() <= half + 1e-9));
}

#[test]
fn the_altimeter_reads_only_near_the_bottom_while_diving() {
    // Fig. 2 in 40 m of water: the altimeter reaches 33 m, so a fix needs
    // 7 m of depth; it pings while diving, below 2 m, every 0.4 × altitude /
    // dive rate seconds (60 s or more at 25 m of altitude), so few cycles have
    // a new reading.
    let mut sim = sim();
    let list = sim.sensor_list().clone();
    let altitude = list.lookup("m_altitude").expect("m_altitude");
    let mut last = f64::NAN;
    let (mut cycles, mut fixes) = (0, 0);
    while sim.step_cycle() {
        cycles += 1;
        let reading = sim.sensor(altitude).expect("published");
        if reading != last && reading >= 0.0 {
            fixes += 1;
            // The reading is the true altitude at a cycle start deeper than 7 m.
            assert!(reading <= 33.0, "{reading}");
        }
        last = reading;
    }
    assert!(fixes > 0, "no fix in {cycles} cycles");
    assert!(
        (fixes as f64) < 0.2 * cycles as f64,
        "{fixes} fixes in {cycles} cycles"
    );
}

#[test]
fn the_ctd_samples_on_its_own_clock() {
    // comet's CTD: a sample every 1.06 s (its .ebd). The cycle sees the latest
    // sample: sci_m_present_time a whole number of 1.06 s after the start, at
    // most 1.06 s before m_present_time, at the depth of that moment (within
    // 1.06 s × 0.2 m/s of the cycle's, plus the pressure noise).
    let mut sim = sim();
    let list = sim.sensor_list().clone();
    let id = |name: &str| list.lookup(name).expect(name);
    let (now, sampled) = (id("m_present_time"), id("sci_m_present_time"));
    let (depth, pressure) = (id("m_depth"), id("sci_water_pressure"));
    let start = sim.present_time();
    let mut cycles = 0;
    // The default mission's whole flight (over 200 cycles, the test above).
    while cycles < 300 && sim.step_cycle() {
        cycles += 1;
        let read = |sensor| sim.sensor(sensor).expect("published");
        let (now, sampled) = (read(now), read(sampled));
        let periods = (sampled - start) / 1.06;
        assert!((periods - periods.round()).abs() < 1e-6, "{periods}");
        assert!(sampled <= now + 1e-9 && now - sampled < 1.06 + 1e-9);
        assert!((read(pressure) * 10.0 - read(depth)).abs() < 0.25);
    }
    assert!(cycles > 200, "{cycles} cycles");
}

#[test]
fn the_pump_has_run_its_lead_by_the_row_where_the_turn_shows() {
    // comet's m_ballast_pumped has run 0.91 s of a swing by the row where
    // c_ballast_pumped turns (pump_lead): 0.91 × 34.6 = 31.49 cc out from −230 and
    // 0.91 × 43.7 = 39.77 cc in from +230, by hand.
    let mut sim = sim();
    let list = SensorList::embedded();
    let slot = |name: &str| list.lookup(name).expect(name).index();
    let (command, pumped) = (slot("c_ballast_pumped"), slot("m_ballast_pumped"));
    let mut previous: Option<f64> = None;
    let mut turns = 0;
    while sim.step_cycle() {
        let (c, m) = (sim.sensors()[command], sim.sensors()[pumped]);
        if let Some(before) = previous.filter(|before| before * c < 0.0) {
            let expected = if c > 0.0 {
                -230.0 + 0.91 * 34.6
            } else {
                230.0 - 0.91 * 43.7
            };
            assert!(
                (m - expected).abs() < 1e-6,
                "turn to {c} from {before}: {m}"
            );
            turns += 1;
        }
        previous = Some(c).filter(|c| *c != 0.0).or(previous);
    }
    assert!(turns >= 4, "{turns}");
}
