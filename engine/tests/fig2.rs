//! The paper's Fig. 2: round trip, a clean check, the worst case per cycle
//! and a replay of a depth ramp.

use std::sync::Arc;

use gloc_engine::gloc::{self, Bound, CheckOptions};
use gloc_engine::program::{Pc, Program};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

const FIG2: &str = include_str!("../../examples/fig2.gloc");

fn fig2_program() -> Arc<Program> {
    let parsed = gloc::parse(FIG2);
    let checked = gloc::check(&parsed, &SensorList::embedded(), &CheckOptions::default());
    assert_eq!(checked.diagnostics, vec![]);
    checked.program.expect("Fig. 2 checks clean")
}

#[test]
fn fig2_round_trips_byte_for_byte() {
    let parsed = gloc::parse(FIG2);
    assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
    assert_eq!(gloc::print(&parsed.file), FIG2);
}

#[test]
fn fig2_checks_clean_with_its_worst_case() {
    let parsed = gloc::parse(FIG2);
    let checked = gloc::check(&parsed, &SensorList::embedded(), &CheckOptions::default());
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    assert!(checked.program.is_some());
    let stats = checked.stats;
    assert_eq!(
        (stats.registers, stats.labels, stats.statements),
        (8, 7, 27)
    );
    // 27 lines minus 7 labels.
    assert_eq!(stats.instructions, 20);
    let worst = stats.worst_case.expect("analysed");
    // Counted by hand (labels do not execute): from the start, the longest way is
    // loads loadd cmpgt cbr | loadi stores jumpi | loads loadd cmplt cbr |
    // loadi stores jumpi | yield = 15.
    assert_eq!(worst.from_start, Bound::Finite(15));
    // The yields sit at pcs 7 (label 4), 16 (label 6) and 18 (label 2).
    // After pc 7: jumpi 0 then the 15 above = 16. After pc 16: jumpi 1,
    // loads loadd cmplt cbr, loadi stores jumpi, yield = 9. After pc 18:
    // jumpi 2, yield = 2.
    assert_eq!(
        worst.from_yields,
        vec![
            (Pc(7), Bound::Finite(16)),
            (Pc(16), Bound::Finite(9)),
            (Pc(18), Bound::Finite(2)),
        ]
    );
    assert_eq!(worst.max, Bound::Finite(16));
}

/// Replays one depth per cycle and records what the script stores.
struct Ramp {
    depth: f64,
    stores: Vec<(SensorId, f64)>,
}

impl Host for Ramp {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        assert_eq!(sensor, SensorId(444), "Fig. 2 only reads m_depth");
        self.depth
    }
    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.stores.push((sensor, value));
    }
    fn print_line(&mut self, _line: &str) {}
}

#[test]
fn fig2_drives_the_hook_on_a_depth_ramp() {
    // Cycle k (from 0) has depth k m for k = 0..=20, then 40 - k down to 0.
    let depths: Vec<f64> = (0..=20).chain((0..20).rev()).map(f64::from).collect();
    assert_eq!(depths.len(), 41);
    let mut machine = Machine::new(fig2_program(), MachineConfig::default());
    let mut host = Ramp {
        depth: 0.0,
        stores: Vec::new(),
    };
    let mut stores_by_cycle = Vec::new();
    for depth in &depths {
        host.depth = *depth;
        host.stores.clear();
        assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
        stores_by_cycle.push(host.stores.clone());
    }
    // The first cycle with depth > 15 is cycle 16 (16 m): 128 to 1387 there.
    // The first later cycle with depth < 5 is cycle 36 (depth 40 - 36 = 4 m).
    for (cycle, stores) in stores_by_cycle.iter().enumerate() {
        let expected = match cycle {
            16 => vec![(SensorId(1387), 128.0)],
            36 => vec![(SensorId(1387), 0.0)],
            _ => vec![],
        };
        assert_eq!(
            stores, &expected,
            "cycle {cycle} at depth {}",
            depths[cycle]
        );
    }
}
