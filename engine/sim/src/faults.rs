//! Fault injection: sensors that drop out, stick, read NaN or spike, applied
//! at each cycle boundary after the measured sensors are published, so that
//! the script and the log see the faulty values while the flight model (and
//! the behaviors, which read the vehicle's true state) fly on.
//!
//! Use [`step_cycle_with_faults`] in place of [`Simulation::step_cycle`]:
//!
//! ```
//! # use std::sync::Arc;
//! # use gloc_engine::sensors::SensorList;
//! # use gloc_sim::{default_mission, SimConfig, Simulation};
//! use gloc_sim::faults::{step_cycle_with_faults, Fault, FaultKind, FaultPlan};
//! let list = Arc::new(SensorList::embedded());
//! let depth = list.lookup("m_depth").expect("m_depth");
//! let mut sim = Simulation::new(&default_mission(), list, None, &SimConfig::default())?;
//! let mut plan = FaultPlan::new(vec![Fault::from_cycle(depth, FaultKind::NotANumber, 10)]);
//! while step_cycle_with_faults(&mut sim, &mut plan) && sim.cycle() < 20 {}
//! assert!(sim.sensor(depth).is_some_and(f64::is_nan));
//! # Ok::<(), gloc_sim::SimError>(())
//! ```

use gloc_engine::sensors::SensorId;

use crate::Simulation;

/// What a faulty sensor reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FaultKind {
    /// The sensor stops updating: it keeps the value it had when the fault began.
    Dropout,
    /// The sensor reads this value, whatever the truth.
    Stuck(f64),
    /// The sensor reads NaN.
    NotANumber,
    /// The sensor reads its true value plus this offset.
    Spike(f64),
}

/// One fault: a sensor, what it reads, and the control cycles (0-based,
/// `start..end`) it lasts; `end: None` lasts to the end of the mission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fault {
    pub sensor: SensorId,
    pub kind: FaultKind,
    pub start: u64,
    pub end: Option<u64>,
}

impl Fault {
    /// A fault from `start` to the end of the mission.
    pub fn from_cycle(sensor: SensorId, kind: FaultKind, start: u64) -> Fault {
        Fault {
            sensor,
            kind,
            start,
            end: None,
        }
    }

    /// A fault during cycles `start..end`.
    pub fn during(sensor: SensorId, kind: FaultKind, start: u64, end: u64) -> Fault {
        Fault {
            sensor,
            kind,
            start,
            end: Some(end),
        }
    }

    fn active(&self, cycle: u64) -> bool {
        cycle >= self.start && self.end.is_none_or(|end| cycle < end)
    }
}

/// A set of faults and what they remember (the value a dropped-out sensor holds).
#[derive(Clone, Debug, Default)]
pub struct FaultPlan {
    faults: Vec<Fault>,
    /// For each fault, the value a dropout holds (taken when it starts).
    held: Vec<Option<f64>>,
    /// Cycles in which at least one fault was applied.
    applied_cycles: u64,
}

impl FaultPlan {
    pub fn new(faults: Vec<Fault>) -> FaultPlan {
        let held = vec![None; faults.len()];
        FaultPlan {
            faults,
            held,
            applied_cycles: 0,
        }
    }

    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// How many cycles had at least one fault applied.
    pub fn applied_cycles(&self) -> u64 {
        self.applied_cycles
    }

    /// Overwrites the faulty sensors of the cycle under way. Call it at the
    /// cycle boundary (after [`Simulation::begin_cycle`]), before the script runs.
    pub fn apply(&mut self, sim: &mut Simulation) {
        let cycle = sim.cycle();
        let mut any = false;
        for (fault, held) in self.faults.iter().zip(self.held.iter_mut()) {
            if !fault.active(cycle) {
                *held = None;
                continue;
            }
            let Some(truth) = sim.sensor(fault.sensor) else {
                continue;
            };
            let value = match fault.kind {
                FaultKind::Dropout => *held.get_or_insert(truth),
                FaultKind::Stuck(value) => value,
                FaultKind::NotANumber => f64::NAN,
                FaultKind::Spike(offset) => truth + offset,
            };
            any |= sim.set_sensor(fault.sensor, value);
        }
        if any {
            self.applied_cycles += 1;
        }
    }
}

/// One whole control cycle with the plan's faults applied at its boundary.
/// False once the simulation is finished (as [`Simulation::step_cycle`]).
pub fn step_cycle_with_faults(sim: &mut Simulation, plan: &mut FaultPlan) -> bool {
    if !sim.begin_cycle() {
        return false;
    }
    plan.apply(sim);
    sim.run_script();
    sim.finish_cycle();
    true
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use gloc_engine::sensors::SensorList;

    use super::*;
    use crate::{default_mission, SimConfig};

    fn simulation() -> (Simulation, SensorId) {
        let list = Arc::new(SensorList::embedded());
        let depth = list.lookup("m_depth").expect("m_depth is in the list");
        let sim = Simulation::new(&default_mission(), list, None, &SimConfig::default())
            .expect("the default mission starts");
        (sim, depth)
    }

    /// The value of `sensor` the script sees in each of the first `cycles` cycles.
    fn seen(plan: &mut FaultPlan, cycles: u64) -> Vec<f64> {
        let (mut sim, depth) = simulation();
        let mut values = Vec::new();
        for _ in 0..cycles {
            assert!(sim.begin_cycle());
            plan.apply(&mut sim);
            values.push(sim.sensor(depth).expect("m_depth"));
            sim.run_script();
            sim.finish_cycle();
        }
        values
    }

    #[test]
    fn each_kind_changes_only_its_cycles() {
        let (_, depth) = simulation();
        let truth = seen(&mut FaultPlan::default(), 40);
        // The glider dives from the start: the true depth changes each cycle.
        assert!(truth[30] > truth[20] + 1.0, "{truth:?}");

        let stuck = seen(
            &mut FaultPlan::new(vec![Fault::during(depth, FaultKind::Stuck(7.5), 20, 30)]),
            40,
        );
        assert_eq!(&stuck[..20], &truth[..20]);
        assert!(stuck[20..30].iter().all(|&value| value == 7.5));
        assert_eq!(&stuck[30..], &truth[30..], "the flight is unchanged");

        let dropout = seen(
            &mut FaultPlan::new(vec![Fault::during(depth, FaultKind::Dropout, 20, 30)]),
            40,
        );
        assert!(dropout[20..30].iter().all(|&value| value == truth[20]));
        assert_eq!(dropout[30], truth[30]);

        let nan = seen(
            &mut FaultPlan::new(vec![Fault::from_cycle(depth, FaultKind::NotANumber, 35)]),
            40,
        );
        assert_eq!(&nan[..35], &truth[..35]);
        assert!(nan[35..].iter().all(|value| value.is_nan()));

        let mut plan = FaultPlan::new(vec![Fault::during(depth, FaultKind::Spike(100.0), 25, 26)]);
        let spike = seen(&mut plan, 40);
        assert_eq!(spike[25], truth[25] + 100.0);
        assert_eq!(spike[26], truth[26]);
        assert_eq!(plan.applied_cycles(), 1);
    }

    #[test]
    fn a_dropout_that_comes_back_holds_the_new_value() {
        let (_, depth) = simulation();
        let truth = seen(&mut FaultPlan::default(), 30);
        let values = seen(
            &mut FaultPlan::new(vec![
                Fault::during(depth, FaultKind::Dropout, 5, 10),
                Fault::during(depth, FaultKind::Dropout, 20, 25),
            ]),
            30,
        );
        assert!(values[5..10].iter().all(|&value| value == truth[5]));
        assert!(values[20..25].iter().all(|&value| value == truth[20]));
        assert_eq!(values[15], truth[15]);
    }
}
