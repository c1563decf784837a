//! The interpreter: type rules, printing, traps (values with pc and line),
//! halt, single-stepping, snapshots and the cycle budget. Every expected
//! value here is worked out by hand from the rules in docs/gloc.md.

use std::collections::HashMap;

use gloc_engine::program::{Pc, Reg, Value};
use gloc_engine::sensors::SensorId;
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig, Status, TrapKind};

mod support;

use support::program;

#[derive(Default)]
struct TestHost {
    sensors: HashMap<u32, f64>,
    stores: Vec<(u32, f64)>,
    lines: Vec<String>,
}

impl Host for TestHost {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        self.sensors.get(&sensor.0).copied().unwrap_or(0.0)
    }
    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.stores.push((sensor.0, value));
        self.sensors.insert(sensor.0, value);
    }
    fn print_line(&mut self, line: &str) {
        self.lines.push(line.to_string());
    }
}

fn machine(text: &str) -> Machine {
    Machine::new(program(text), MachineConfig::default())
}

#[test]
fn integer_and_float_rules() {
    let text = "\
nregs 24
nblbs 0
ninstr 24
loadi -7,r0
loadi 2,r1
loadd 2.0,r2
div r0,r1,r3
mod r0,r1,r4
div r0,r2,r5
add r0,r1,r6
add r0,r2,r7
cmpeq r1,r2,r8
min r1,r2,r9
max r0,r1,r10
neg r0,r11
abs r0,r12
loadd -2.7,r13
d2i r13,r14
i2d r1,r15
sqrt r1,r16
loadi 6,r17
loadi 3,r18
and r17,r18,r19
or r17,r18,r20
xor r17,r18,r21
not r19,r22
yield
";
    let mut machine = machine(text);
    assert_eq!(
        machine.run_cycle(&mut TestHost::default()),
        CycleEnd::Yielded
    );
    let registers = machine.registers();
    let expected = [
        (3, Value::Int(-3)),     // -7 div 2 truncates toward zero
        (4, Value::Int(-1)),     // the remainder takes the sign of -7
        (5, Value::Float(-3.5)), // a float operand makes it float division
        (6, Value::Int(-5)),
        (7, Value::Float(-5.0)),
        (8, Value::Int(1)),     // 2 == 2.0
        (9, Value::Float(2.0)), // mixed min is a float
        (10, Value::Int(2)),
        (11, Value::Int(7)),
        (12, Value::Int(7)),
        (14, Value::Int(-2)), // d2i truncates
        (15, Value::Float(2.0)),
        (16, Value::Float(std::f64::consts::SQRT_2)),
        (19, Value::Int(2)), // 6 & 3
        (20, Value::Int(7)), // 6 | 3
        (21, Value::Int(5)), // 6 ^ 3
        (22, Value::Int(0)), // not 2
    ];
    for (register, value) in expected {
        assert_eq!(registers[register], value, "r{register}");
    }
    // 24 instructions, the yield included.
    assert_eq!(machine.instructions_this_cycle(), 24);
}

#[test]
fn float_division_by_zero_does_not_trap() {
    let text = "nregs 3\nnblbs 0\nninstr 4\nloadd 1.0,r0\nloadi 0,r1\ndiv r0,r1,r2\nyield\n";
    let mut machine = machine(text);
    assert_eq!(
        machine.run_cycle(&mut TestHost::default()),
        CycleEnd::Yielded
    );
    assert_eq!(machine.registers()[2], Value::Float(f64::INFINITY));
}

#[test]
fn printing_joins_items_with_one_space() {
    let text = r#"nregs 3
nblbs 0
ninstr 11
writes "depth"
loads 444,r0
print r0
loadi 128,r1
write r1
loadd 0.1,r2
write r2
loadd 1e-7,r2
write r2
prints "say \"hi\" \\ done"
yield
"#;
    let mut machine = machine(text);
    let mut host = TestHost::default();
    host.sensors.insert(444, 15.0);
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(
        host.lines,
        vec![
            "depth 15.0".to_string(),
            r#"128 0.1 1e-7 say "hi" \ done"#.to_string()
        ]
    );
}

fn expect_trap(text: &str, kind: TrapKind, pc: u32, line: u32) {
    let mut machine = machine(text);
    let mut host = TestHost::default();
    let CycleEnd::Trapped(trap) = machine.run_cycle(&mut host) else {
        panic!("expected a trap");
    };
    assert_eq!((trap.kind, trap.pc, trap.line), (kind, Pc(pc), line));
    assert_eq!(machine.status(), Status::Trapped(trap));
    // The script stays stopped: the host sees nothing more.
    let stores = host.stores.len();
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Trapped(trap));
    assert_eq!(host.stores.len(), stores);
}

#[test]
fn integer_division_by_zero_traps_with_pc_and_line() {
    let text = "nregs 3\nnblbs 0\nninstr 4\nloadi 7,r0\nloadi 0,r1\ndiv r0,r1,r2\nyield\n";
    expect_trap(text, TrapKind::DivisionByZero, 2, 6);
    let text = "nregs 3\nnblbs 0\nninstr 4\nloadi 7,r0\nloadi 0,r1\nmod r0,r1,r2\nyield\n";
    expect_trap(text, TrapKind::DivisionByZero, 2, 6);
}

#[test]
fn memory_traps() {
    let text = "nregs 2\nnblbs 0\nnmem 4\nninstr 3\nloadi 4,r0\nloadm r0,r1\nyield\n";
    expect_trap(
        text,
        TrapKind::MemoryOutOfBounds {
            address: 4,
            size: 4,
        },
        1,
        6,
    );
    let text = "nregs 2\nnblbs 0\nnmem 4\nninstr 3\nloadi -1,r0\nstorem r1,r0\nyield\n";
    expect_trap(
        text,
        TrapKind::MemoryOutOfBounds {
            address: -1,
            size: 4,
        },
        1,
        6,
    );
    let text = "nregs 2\nnblbs 0\nnmem 4\nninstr 3\nloadd 1.5,r0\nloadm r0,r1\nyield\n";
    expect_trap(text, TrapKind::NonIntegerAddress { value: 1.5 }, 1, 6);
    // A whole float is a fine address.
    let text =
        "nregs 2\nnblbs 0\nnmem 4\nninstr 4\nloadd 3.0,r0\nstorem r0,r0\nloadm 3,r1\nyield\n";
    let mut machine = machine(text);
    assert_eq!(
        machine.run_cycle(&mut TestHost::default()),
        CycleEnd::Yielded
    );
    assert_eq!(machine.registers()[1], Value::Float(3.0));
    assert_eq!(machine.memory()[3], Value::Float(3.0));
}

#[test]
fn a_bad_indirect_jump_traps() {
    let text = "nregs 1\nnblbs 2\nninstr 4\nloadi 1,r0\njump r0\nlabel 0\nyield\n";
    // Label 1 is declared but never defined.
    expect_trap(
        text,
        TrapKind::BadIndirectJump {
            value: Value::Int(1),
        },
        1,
        5,
    );
}

#[test]
fn a_cycle_without_yield_overruns_its_budget() {
    // Counts up to sensor 1385 (a million) without yielding.
    let text = "\
nregs 4
nblbs 3
ninstr 12
loads 1385,r0
loadi 0,r1
loadi 1,r2
label 0
cmplt r1,r0,r3
cbr r3,1,2
label 1
add r1,r2,r1
jumpi 0
label 2
yield
halt
";
    let mut machine = Machine::new(program(text), MachineConfig { cycle_budget: 100 });
    let mut host = TestHost::default();
    host.sensors.insert(1385, 1e6);
    let CycleEnd::Trapped(trap) = machine.run_cycle(&mut host) else {
        panic!("expected an overrun");
    };
    assert_eq!(trap.kind, TrapKind::CycleOverrun { budget: 100 });
    assert_eq!(machine.instructions_this_cycle(), 100);
    // 3 set-up instructions, then 97 of the 4-instruction loop body
    // (cmplt cbr add jumpi): 24 whole rounds and one more, so the next
    // instruction is the loop's `cbr` (pc 4, line 9).
    assert_eq!((trap.pc, trap.line), (Pc(4), 9));

    // With a small bound it finishes: 3 + 4 * 5 + cmplt cbr + yield = 26.
    let mut machine = Machine::new(program(text), MachineConfig { cycle_budget: 100 });
    host.sensors.insert(1385, 5.0);
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(machine.instructions_this_cycle(), 26);
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Halted);
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Halted);
}

#[test]
fn falling_off_the_end_halts() {
    let text = "nregs 1\nnblbs 0\nninstr 1\nloadi 1,r0\n";
    let mut machine = machine(text);
    assert_eq!(
        machine.run_cycle(&mut TestHost::default()),
        CycleEnd::Halted
    );
    assert_eq!(machine.status(), Status::Halted);
}

const FIG2: &str = include_str!("../../examples/fig2.gloc");

#[test]
fn stepping_fig2_and_setting_a_register() {
    let mut machine = machine(FIG2);
    let mut host = TestHost::default();
    host.sensors.insert(444, 3.0);
    // loads, loadd, cmpgt: three steps that do not end the cycle.
    for expected_pc in 1..=3 {
        assert_eq!(machine.step(&mut host), None);
        assert_eq!(machine.pc(), Pc(expected_pc));
    }
    assert_eq!(machine.registers()[0], Value::Float(3.0));
    assert_eq!(machine.registers()[2], Value::Int(0));
    // Pretend the depth test held: the branch goes to label 3 (pc 4).
    machine
        .set_register(Reg(2), Value::Int(1))
        .expect("r2 exists");
    assert!(machine.set_register(Reg(8), Value::Int(1)).is_err());
    assert_eq!(machine.step(&mut host), None);
    assert_eq!(machine.pc(), Pc(4));
    // loadi, stores, jumpi 1, then label 1's loads loadd cmplt cbr (3 < 5:
    // to label 5), loadi stores jumpi 2 and the yield of label 2.
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(host.stores, vec![(1387, 128.0), (1387, 0.0)]);
    assert_eq!(machine.instructions_this_cycle(), 4 + 3 + 4 + 3 + 1);
    assert_eq!(machine.cycles_completed(), 1);
    assert!(machine.at_cycle_boundary());
    // The next step starts a new cycle.
    assert_eq!(machine.step(&mut host), None);
    assert_eq!(machine.instructions_this_cycle(), 1);
}

#[test]
fn a_cloned_machine_is_an_independent_snapshot() {
    let mut machine = machine(FIG2);
    let mut host = TestHost::default();
    host.sensors.insert(444, 20.0);
    let snapshot = machine.clone();
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(snapshot.pc(), Pc(0));
    assert_eq!(snapshot.registers()[0], Value::Int(0));
    let mut replayed = snapshot.clone();
    let mut other_host = TestHost::default();
    other_host.sensors.insert(444, 20.0);
    assert_eq!(replayed.run_cycle(&mut other_host), CycleEnd::Yielded);
    assert_eq!(replayed.registers(), machine.registers());
    assert_eq!(replayed.pc(), machine.pc());
    machine.reset();
    assert_eq!(machine.pc(), Pc(0));
    assert_eq!(machine.registers()[0], Value::Int(0));
}

#[test]
fn setting_the_pc_jumps_and_refuses_what_is_not_code() {
    // pc 0 loadi 1,r0; 1 yield; 2 loadi 2,r0; 3 yield; 4 the implicit halt.
    let text = "nregs 1\nnblbs 0\nninstr 4\nloadi 1,r0\nyield\nloadi 2,r0\nyield\n";
    let mut machine = machine(text);
    let mut host = TestHost::default();
    // Between cycles: the next share starts where the pc is set.
    machine.set_pc(Pc(2)).expect("pc 2 is code");
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(machine.registers()[0], Value::Int(2));
    assert_eq!(machine.pc(), Pc(4));
    // The implicit halt is an instruction; past it is not.
    assert!(machine.set_pc(Pc(4)).is_ok());
    assert!(machine.set_pc(Pc(5)).is_err());
    assert_eq!(machine.pc(), Pc(4));
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Halted);
    // A halted script stays halted.
    assert!(machine.set_pc(Pc(0)).is_err());
}
