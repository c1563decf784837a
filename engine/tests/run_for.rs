//! `Machine::run_for(n)` (the debugger's fused run up to the next place a breakpoint could
//! stop) against `n` calls of `step`: after every `n`, the same pc, registers, memory,
//! instruction count, end of the cycle and printed lines, including runs that end inside
//! a fused group and budgets that run out on the way.

use std::sync::Arc;

use gloc_engine::program::Value;
use gloc_engine::sensors::SensorId;
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

mod support;

/// A loop of fused groups (constant operands, compare-and-branch, the loop's back edge)
/// that prints its counter and stores it, then yields.
const SCRIPT: &str = "nregs 8
nblbs 3
ninstr 17
nmem 0
label 0
loadi 7,r1
mul r0,r1,r2
loadi 1000003,r3
mod r2,r3,r2
loadi 10,r4
cmplt r0,r4,r5
cbr r5,1,2
label 1
loadi 1,r6
add r0,r6,r0
print r2
stores r0,1387
jumpi 0
label 2
yield
jumpi 2
";

#[derive(Default)]
struct Recorder {
    stores: Vec<(u32, u64)>,
    lines: Vec<String>,
}

impl Host for Recorder {
    fn load_sensor(&mut self, _: SensorId) -> f64 {
        0.0
    }
    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.stores.push((sensor.0, value.to_bits()));
    }
    fn print_line(&mut self, line: &str) {
        self.lines.push(line.to_string());
    }
}

fn state(machine: &Machine, end: Option<CycleEnd>, host: &Recorder) -> String {
    let bits: Vec<(bool, u64)> = machine
        .registers()
        .iter()
        .map(|value| match *value {
            Value::Int(x) => (true, x as u64),
            Value::Float(x) => (false, x.to_bits()),
        })
        .collect();
    format!(
        "{end:?} pc {} executed {} registers {bits:?} stores {:?} lines {:?}",
        machine.pc().0,
        machine.instructions_this_cycle(),
        host.stores,
        host.lines
    )
}

#[test]
fn running_n_instructions_fused_stops_where_n_steps_stop() {
    let program = support::program(SCRIPT);
    for budget in [1000, 37, 5] {
        let config = MachineConfig {
            cycle_budget: budget,
        };
        for n in 1..=120 {
            let mut fused = Machine::new(Arc::clone(&program), config);
            let mut stepped = Machine::new(Arc::clone(&program), config);
            let (mut fused_host, mut stepped_host) = (Recorder::default(), Recorder::default());
            // Two cycles, each cut into runs of `n`: the same stops both ways.
            for run in 0..40 {
                let fused_end = fused.run_for(&mut fused_host, n);
                let mut stepped_end = None;
                for _ in 0..n {
                    stepped_end = stepped.step(&mut stepped_host);
                    if stepped_end.is_some() {
                        break;
                    }
                }
                assert_eq!(
                    state(&fused, fused_end, &fused_host),
                    state(&stepped, stepped_end, &stepped_host),
                    "budget {budget}, runs of {n}, run {run}"
                );
                if matches!(fused_end, Some(CycleEnd::Trapped(_) | CycleEnd::Halted)) {
                    break;
                }
            }
        }
    }
}
