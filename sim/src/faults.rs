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

use gloc_engine::sensors::{SensorId, SensorList};

use crate::Simulation;

/// The syntax of a fault written as text (`gloc run --fault`), with examples.
pub const FAULT_SYNTAX: &str = "SENSOR:KIND@START[..END] with KIND one of nan, dropout, \
stuck=VALUE, spike=OFFSET and cycles counted from 0 (END excluded), e.g. `m_depth:nan@20`, \
`m_depth:stuck=20@30..60`, `m_depth:spike=100@10..11`, `m_depth:dropout@40..`";

/// Why a fault written as text does not parse.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{text}` is not a fault: {problem}; write {FAULT_SYNTAX}")]
pub struct FaultSyntaxError {
    pub text: String,
    pub problem: String,
}

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

    /// Parses `SENSOR:KIND@START[..END]` (see [`FAULT_SYNTAX`]) against a
    /// sensor list: `m_depth:nan@20`, `m_depth:stuck=20@30..60`,
    /// `m_depth:spike=100@10..11`, `m_depth:dropout@40..` (`40..` and `40`
    /// both last to the end of the mission).
    pub fn parse(text: &str, list: &SensorList) -> Result<Fault, FaultSyntaxError> {
        let error = |problem: String| FaultSyntaxError {
            text: text.to_string(),
            problem,
        };
        let trimmed = text.trim();
        let Some((name, rest)) = trimmed.split_once(':') else {
            return Err(error("no `:` after the sensor name".to_string()));
        };
        let name = name.trim();
        if name.is_empty() {
            return Err(error("the sensor name is missing before `:`".to_string()));
        }
        let Some(sensor) = list.lookup(name) else {
            let names = list.iter().map(|(_, sensor)| sensor.name.as_str());
            let hint = match gloc_engine::suggest::closest(name, names) {
                Some(close) => format!(" (did you mean `{close}`?)"),
                None => String::new(),
            };
            return Err(error(format!(
                "the sensor list has no sensor `{name}`{hint}"
            )));
        };
        let Some((kind, cycles)) = rest.split_once('@') else {
            return Err(error(
                "no `@` before the cycle the fault starts at".to_string(),
            ));
        };
        let kind = parse_kind(kind.trim()).map_err(error)?;
        let (start, end) = parse_cycles(cycles.trim()).map_err(error)?;
        Ok(Fault {
            sensor,
            kind,
            start,
            end,
        })
    }

    fn active(&self, cycle: u64) -> bool {
        cycle >= self.start && self.end.is_none_or(|end| cycle < end)
    }
}

impl std::fmt::Display for FaultKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FaultKind::Dropout => f.write_str("dropout (holds its last value)"),
            FaultKind::Stuck(value) => write!(f, "stuck at {value}"),
            FaultKind::NotANumber => f.write_str("reads NaN"),
            FaultKind::Spike(offset) => write!(f, "spike of {offset:+}"),
        }
    }
}

fn parse_kind(text: &str) -> Result<FaultKind, String> {
    let (word, value) = match text.split_once('=') {
        Some((word, value)) => (word.trim(), Some(value.trim())),
        None => (text, None),
    };
    let number = |what: &str| -> Result<f64, String> {
        let Some(value) = value else {
            return Err(format!("`{word}` needs a value: `{word}={what}`"));
        };
        match value.parse::<f64>() {
            Ok(number) if number.is_finite() => Ok(number),
            _ => Err(format!(
                "the {what} of `{word}` must be a finite number, not `{value}`"
            )),
        }
    };
    let kind = match word.to_ascii_lowercase().as_str() {
        "nan" => FaultKind::NotANumber,
        "dropout" => FaultKind::Dropout,
        "stuck" => return number("VALUE").map(FaultKind::Stuck),
        "spike" => return number("OFFSET").map(FaultKind::Spike),
        "" => return Err("the kind is missing between `:` and `@`".to_string()),
        _ => return Err(format!("unknown kind `{word}`")),
    };
    match value {
        Some(value) => Err(format!(
            "`{word}` takes no value, but `={value}` follows it"
        )),
        None => Ok(kind),
    }
}

fn parse_cycles(text: &str) -> Result<(u64, Option<u64>), String> {
    let cycle = |part: &str, what: &str| -> Result<u64, String> {
        part.trim().parse::<u64>().map_err(|_| {
            format!("the {what} cycle must be a whole number of cycles from 0, not `{part}`")
        })
    };
    match text.split_once("..") {
        None => Ok((cycle(text, "start")?, None)),
        Some((start, end)) => {
            let start = cycle(start, "start")?;
            if end.trim().is_empty() {
                return Ok((start, None));
            }
            let end = cycle(end, "end")?;
            if end <= start {
                return Err(format!(
                    "the end cycle ({end}, excluded) must come after the start ({start})"
                ));
            }
            Ok((start, Some(end)))
        }
    }
}

/// A set of faults and what they remember (the value a dropped-out sensor holds).
#[derive(Clone, Debug, Default)]
pub struct FaultPlan {
    faults: Vec<Fault>,
    /// For each fault, the value a dropout holds (taken when it starts).
    held: Vec<Option<f64>>,
    /// For each fault, the first and last cycle it was applied in.
    applied: Vec<Option<(u64, u64)>>,
    /// Cycles in which at least one fault was applied.
    applied_cycles: u64,
}

impl FaultPlan {
    pub fn new(faults: Vec<Fault>) -> FaultPlan {
        let held = vec![None; faults.len()];
        let applied = vec![None; faults.len()];
        FaultPlan {
            faults,
            held,
            applied,
            applied_cycles: 0,
        }
    }

    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// Each fault with the first and last cycle it was applied in (`None`:
    /// never, the run ended before it began).
    pub fn report(&self) -> impl Iterator<Item = (&Fault, Option<(u64, u64)>)> {
        self.faults.iter().zip(self.applied.iter().copied())
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
        for ((fault, held), applied) in self
            .faults
            .iter()
            .zip(self.held.iter_mut())
            .zip(self.applied.iter_mut())
        {
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
            if sim.set_sensor(fault.sensor, value) {
                any = true;
                let first = applied.map_or(cycle, |(first, _)| first);
                *applied = Some((first, cycle));
            }
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

    #[test]
    fn faults_parse_from_text() {
        let list = SensorList::embedded();
        let depth = list.lookup("m_depth").expect("m_depth");
        let parse = |text| Fault::parse(text, &list);
        assert_eq!(
            parse("m_depth:nan@20"),
            Ok(Fault::from_cycle(depth, FaultKind::NotANumber, 20))
        );
        assert_eq!(
            parse(" m_depth : Stuck = -2.5 @ 30..60 "),
            Ok(Fault::during(depth, FaultKind::Stuck(-2.5), 30, 60))
        );
        assert_eq!(
            parse("m_depth:spike=100@10..11"),
            Ok(Fault::during(depth, FaultKind::Spike(100.0), 10, 11))
        );
        assert_eq!(
            parse("m_depth:dropout@40.."),
            Ok(Fault::from_cycle(depth, FaultKind::Dropout, 40))
        );
    }

    #[test]
    fn bad_fault_text_says_what_is_wrong_and_shows_the_form() {
        let list = SensorList::embedded();
        let problem = |text: &str| match Fault::parse(text, &list) {
            Ok(fault) => panic!("`{text}` parsed as {fault:?}"),
            Err(error) => {
                let message = error.to_string();
                assert!(message.contains("m_depth:nan@20"), "{message}");
                error.problem
            }
        };
        assert_eq!(problem("m_depth"), "no `:` after the sensor name");
        assert_eq!(problem(":nan@1"), "the sensor name is missing before `:`");
        assert_eq!(
            problem("m_dpeth:nan@1"),
            "the sensor list has no sensor `m_dpeth` (did you mean `m_depth`?)"
        );
        assert_eq!(
            problem("m_depth:nan"),
            "no `@` before the cycle the fault starts at"
        );
        assert_eq!(problem("m_depth:melt@1"), "unknown kind `melt`");
        assert_eq!(
            problem("m_depth:@1"),
            "the kind is missing between `:` and `@`"
        );
        assert_eq!(
            problem("m_depth:stuck@1"),
            "`stuck` needs a value: `stuck=VALUE`"
        );
        assert_eq!(
            problem("m_depth:spike=big@1"),
            "the OFFSET of `spike` must be a finite number, not `big`"
        );
        assert_eq!(
            problem("m_depth:stuck=inf@1"),
            "the VALUE of `stuck` must be a finite number, not `inf`"
        );
        assert_eq!(
            problem("m_depth:nan=3@1"),
            "`nan` takes no value, but `=3` follows it"
        );
        assert_eq!(
            problem("m_depth:nan@-1"),
            "the start cycle must be a whole number of cycles from 0, not `-1`"
        );
        assert_eq!(
            problem("m_depth:nan@5..5"),
            "the end cycle (5, excluded) must come after the start (5)"
        );
        assert_eq!(
            problem("m_depth:nan@5..x"),
            "the end cycle must be a whole number of cycles from 0, not `x`"
        );
    }

    #[test]
    fn the_plan_reports_when_each_fault_was_applied() {
        let (_, depth) = simulation();
        // Cycles 0-39 are flown. A fault over 10..15 is applied in cycles
        // 10 to 14; one from 35 on in 35 to 39; one from 50 never.
        let mut plan = FaultPlan::new(vec![
            Fault::during(depth, FaultKind::Spike(1.0), 10, 15),
            Fault::from_cycle(depth, FaultKind::NotANumber, 35),
            Fault::from_cycle(depth, FaultKind::Dropout, 50),
        ]);
        seen(&mut plan, 40);
        let report: Vec<Option<(u64, u64)>> = plan.report().map(|(_, when)| when).collect();
        assert_eq!(report, vec![Some((10, 14)), Some((35, 39)), None]);
        assert_eq!(plan.applied_cycles(), 5 + 5);
    }
}
