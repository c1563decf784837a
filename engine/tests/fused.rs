//! The interpreter's fused ops (`vm/code.rs`) against plain execution, and its
//! two dispatches (the `match` loop and threaded code, `vm/threaded.rs`)
//! against each other.
//!
//! `Machine::step` runs one instruction with one unit of fuel, so it always runs
//! the plain one-to-one code; `run_cycle` runs fused groups wherever they apply,
//! through the `match` loop or the threaded handlers (`Dispatch`).
//! Every script here is run these three ways and must agree at every cycle end:
//! registers, memory, pc, instructions counted, the cycle's end (with a trap's
//! pc), the sensor stores and the printed lines. The scripts cover every fused
//! pattern, jumps into the middle of a group, overlapping registers, constants
//! on either side, float and NaN operands, and budgets that run out inside a
//! group. A few results are also checked against values worked out by hand.

use std::collections::HashMap;
use std::sync::Arc;

use gloc_engine::program::Value;
use gloc_engine::sensors::SensorId;
use gloc_engine::vm::{CycleEnd, Dispatch, Host, Machine, MachineConfig};
use gloc_testsupport::Rng;

mod support;

use support::program;

/// Adds the header to a body of GLOC lines.
fn script(registers: u32, labels: u32, memory: u32, body: &[String]) -> String {
    let mut text = format!(
        "nregs {registers}\nnblbs {labels}\nninstr {}\nnmem {memory}\n",
        body.len()
    );
    for line in body {
        text.push_str(line);
        text.push('\n');
    }
    text
}

#[derive(Default)]
struct Recorder {
    sensors: HashMap<u32, f64>,
    stores: Vec<(u32, u64)>,
    lines: Vec<String>,
}

impl Host for Recorder {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        self.sensors.get(&sensor.0).copied().unwrap_or(f64::NAN)
    }
    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        // Bits, so that two NaN stores compare equal.
        self.stores.push((sensor.0, value.to_bits()));
    }
    fn print_line(&mut self, line: &str) {
        self.lines.push(line.to_string());
    }
}

/// Everything observable after a cycle, with floats as bits (NaN == NaN).
#[derive(Debug, PartialEq)]
struct Observed {
    end: String,
    pc: u32,
    executed: u64,
    registers: Vec<(bool, u64)>,
    memory: Vec<(bool, u64)>,
}

fn bits(values: &[Value]) -> Vec<(bool, u64)> {
    values
        .iter()
        .map(|value| match *value {
            Value::Int(x) => (true, x as u64),
            Value::Float(x) => (false, x.to_bits()),
        })
        .collect()
}

fn observe(machine: &Machine, end: CycleEnd) -> Observed {
    Observed {
        end: format!("{end:?}"),
        pc: machine.pc().0,
        executed: machine.instructions_this_cycle(),
        registers: bits(machine.registers()),
        memory: bits(machine.memory()),
    }
}

/// Runs `cycles` cycles with `run_cycle` through the `match` loop, again
/// through threaded dispatch, and again by single steps; asserts all three
/// agree after every cycle and returns the fused run's final machine.
fn agree(text: &str, cycles: usize, budget: u64, depth: f64) -> Machine {
    let program = program(text);
    let config = MachineConfig {
        cycle_budget: budget,
    };
    let mut fused = Machine::new(Arc::clone(&program), config);
    fused.set_dispatch(Dispatch::Loop);
    let mut threaded = Machine::new(Arc::clone(&program), config);
    threaded.set_dispatch(Dispatch::Threaded);
    let mut stepped = Machine::new(program, config);
    let mut fused_host = Recorder::default();
    let mut threaded_host = Recorder::default();
    let mut stepped_host = Recorder::default();
    for host in [&mut fused_host, &mut threaded_host, &mut stepped_host] {
        host.sensors.insert(444, depth);
    }
    for cycle in 0..cycles {
        let fused_end = fused.run_cycle(&mut fused_host);
        let threaded_end = threaded.run_cycle(&mut threaded_host);
        let stepped_end = loop {
            if let Some(end) = stepped.step(&mut stepped_host) {
                break end;
            }
        };
        assert_eq!(
            observe(&fused, fused_end),
            observe(&stepped, stepped_end),
            "match loop against steps: cycle {cycle}, budget {budget}, script:\n{text}"
        );
        assert_eq!(
            observe(&threaded, threaded_end),
            observe(&fused, fused_end),
            "threaded against the match loop: cycle {cycle}, budget {budget}, script:\n{text}"
        );
        assert_eq!(
            (&fused_host.stores, &fused_host.lines),
            (&stepped_host.stores, &stepped_host.lines),
            "match loop against steps: cycle {cycle}, budget {budget}"
        );
        assert_eq!(
            (&threaded_host.stores, &threaded_host.lines),
            (&fused_host.stores, &fused_host.lines),
            "threaded against the match loop: cycle {cycle}, budget {budget}"
        );
        assert_eq!(
            (threaded.pending_output(), threaded.cycles_completed()),
            (fused.pending_output(), fused.cycles_completed()),
            "threaded against the match loop: cycle {cycle}, budget {budget}"
        );
        if !matches!(fused_end, CycleEnd::Yielded) {
            break;
        }
    }
    fused
}

fn lines(text: &str) -> Vec<String> {
    text.lines().map(str::to_string).collect()
}

#[test]
fn constant_operands_give_the_hand_worked_results() {
    // r0 = 3: 3 + 7 = 10, 3 - 2.5 = 0.5, 3 * 7 = 21, -7 \ 2 = -3, -7 mod 2 = -1,
    // 3 * 0.5 = 1.5, i2d 4 + 1.5 = 5.5; each constant's register keeps the constant.
    let body = lines(
        "loadi 3,r0
loadi 7,r1
add r0,r1,r2
loadd 2.5,r3
sub r0,r3,r4
loadi 7,r5
mul r5,r0,r6
loadi -7,r7
loadi 2,r8
div r7,r8,r9
loadi 2,r10
mod r7,r10,r11
loadd 0.5,r12
mul r0,r12,r13
loadi 4,r14
i2d r14,r15
add r13,r15,r16
yield",
    );
    let machine = agree(&script(17, 0, 0, &body), 1, 10_000, 0.0);
    let expected = [
        Value::Int(3),
        Value::Int(7),
        Value::Int(10),
        Value::Float(2.5),
        Value::Float(0.5),
        Value::Int(7),
        Value::Int(21),
        Value::Int(-7),
        Value::Int(2),
        Value::Int(-3),
        Value::Int(2),
        Value::Int(-1),
        Value::Float(0.5),
        Value::Float(1.5),
        Value::Int(4),
        Value::Float(4.0),
        Value::Float(5.5),
    ];
    assert_eq!(machine.registers(), &expected[..]);
    assert_eq!(machine.instructions_this_cycle(), 18);
}

#[test]
fn compare_and_branch_takes_the_hand_worked_path() {
    // Counts r0 from 0 while r0 < 5 (a constant compare fused with its branch),
    // then checks 5 >= r0 with the constant on the left: 5 loop tests of 4
    // instructions plus the exit test, so 5 * 7 + 3 + ... worked out below.
    let body = lines(
        "loadi 1,r1
label 0
loadi 5,r2
cmplt r0,r2,r3
cbr r3,1,2
label 1
add r0,r1,r0
jumpi 0
label 2
loadi 5,r4
cmpge r4,r0,r4
cbr r4,3,4
label 3
loadi 1,r5
label 4
yield",
    );
    let machine = agree(&script(6, 5, 0, &body), 1, 10_000, 0.0);
    // r0 counts to 5; the last loop test wrote r3 = 0; 5 >= 5 wrote r4 = 1 and
    // took label 3, so r5 = 1.
    assert_eq!(
        machine.registers(),
        &[
            Value::Int(5),
            Value::Int(1),
            Value::Int(5),
            Value::Int(0),
            Value::Int(1),
            Value::Int(1)
        ][..]
    );
    // loadi 1; 6 tests of 3 instructions; 5 bodies of 2; exit test 3; loadi; yield.
    assert_eq!(
        machine.instructions_this_cycle(),
        1 + 6 * 3 + 5 * 2 + 3 + 1 + 1
    );
}

#[test]
fn jumps_into_the_middle_of_a_group_run_its_tail() {
    // Label 1 names the `cmpgt` of a `loadi; cmpgt; cbr` group and label 2 the
    // `add` of a `loadi; add` pair: entering there must not redo the constant.
    let body = lines(
        "loadi 9,r1
loadi 4,r2
cbr r0,1,2
loadi 100,r2
label 1
cmpgt r1,r2,r3
cbr r3,3,4
loadi 50,r4
label 2
add r1,r4,r5
label 3
label 4
yield
jumpi 0
label 0
loadi 1,r0
jumpi 1",
    );
    // Cycle 1: r0 = 0 goes to label 2 with r4 = 0, so r5 = 9 + 0 and no compare
    // ran. Cycle 2: label 0 sets r0 = 1 and enters label 1 with r2 = 4: 9 > 4.
    let machine = agree(&script(6, 5, 0, &body), 2, 10_000, 0.0);
    assert_eq!(machine.registers()[5], Value::Int(9));
    assert_eq!(machine.registers()[2], Value::Int(4));
    assert_eq!(machine.registers()[3], Value::Int(1));
}

#[test]
fn overlapping_registers_and_nan_agree() {
    let body = lines(
        "loads 444,r0
loadd 1.0,r1
cmpeq r0,r1,r1
cbr r1,1,2
label 1
prints \"one\"
label 2
loadi 0,r2
cmpne r2,r0,r2
cbr r2,3,4
label 3
print r2
label 4
loadi 3,r3
add r3,r3,r3
loadd 0.0,r4
mod r0,r4,r5
loadi 0,r6
div r3,r6,r7
yield",
    );
    // m_depth reads NaN: NaN == 1.0 is false (label 2); 0 != NaN is true (r2 = 1,
    // printed); 3 + 3 = 6; NaN mod 0.0 is NaN.
    let text = script(8, 5, 0, &body);
    let machine = agree(&text, 1, 10_000, f64::NAN);
    // The integer division by the constant 0 traps at the plain `div` (pc 15),
    // after the groups before it ran.
    assert_eq!(machine.pc().0, 14);
    assert_eq!(machine.registers()[2], Value::Int(1));
    assert_eq!(machine.registers()[3], Value::Int(6));
}

#[test]
fn every_budget_runs_out_at_the_same_instruction() {
    let body = lines(
        "label 0
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
jumpi 0
label 2
yield
jumpi 2",
    );
    let text = script(7, 3, 0, &body);
    for budget in 1..=80 {
        agree(&text, 3, budget, 0.0);
    }
}

#[test]
fn array_index_checks_and_loop_back_edges_give_the_hand_worked_results() {
    // a(i) = i for i = 0 to 5 over `nmem 5`, with GBASIC's index check before
    // the store (fused into one range check) and the loop's `jumpi 0` landing
    // on the loop test (threaded into it). i = 5 fails the check and traps at
    // the `loadm` of address -1 (pc 10), as the compiled GBASIC would.
    let body = lines(
        "label 0
loadi 6,r1
cmplt r5,r1,r2
cbr r2,1,9
label 1
loadi 0,r6
cmplt r5,r6,r7
loadi 5,r8
cmpge r5,r8,r9
or r7,r9,r7
cbr r7,2,3
label 2
loadi -1,r0
loadm r0,r0
label 3
storem r5,r5
loadi 1,r10
add r5,r10,r5
jumpi 0
label 9
yield",
    );
    let machine = agree(&script(11, 10, 5, &body), 1, 10_000, 0.0);
    assert_eq!(
        machine.memory(),
        &[
            Value::Int(0),
            Value::Int(1),
            Value::Int(2),
            Value::Int(3),
            Value::Int(4)
        ][..]
    );
    assert_eq!(machine.pc().0, 10);
    // i = 5; 5 < 6; 5 < 0 is 0 and 5 >= 5 is 1, or'ed into r7.
    let registers = machine.registers();
    assert_eq!(
        (registers[5], registers[2], registers[7], registers[9]),
        (Value::Int(5), Value::Int(1), Value::Int(1), Value::Int(1))
    );
    assert!(matches!(
        machine.status(),
        gloc_engine::vm::Status::Trapped(trap)
            if matches!(trap.kind, gloc_engine::vm::TrapKind::MemoryOutOfBounds { address: -1, .. })
    ));
}

#[test]
fn a_threaded_loop_test_rewrites_its_constant_every_time_round() {
    // The body overwrites r1, the loop test's constant register; the `jumpi 0`
    // threaded into the test must load 3 again: r0 counts to 3, r1 ends as 3.
    let body = lines(
        "label 0
loadi 3,r1
cmplt r0,r1,r2
cbr r2,1,2
label 1
loadi 1,r3
add r0,r3,r0
loadi 100,r1
jumpi 0
label 2
yield",
    );
    let machine = agree(&script(4, 3, 0, &body), 1, 10_000, 0.0);
    assert_eq!(
        machine.registers(),
        &[Value::Int(3), Value::Int(3), Value::Int(0), Value::Int(1)][..]
    );
}

/// A random script built from the fusable shapes over four registers, with
/// forward branches into labels that may sit inside a group, and a loop that
/// yields every time round.
fn random_script(random: &mut Rng) -> String {
    const ARITH: [&str; 7] = ["add", "sub", "mul", "div", "mod", "min", "max"];
    const CMP: [&str; 6] = ["cmpeq", "cmpne", "cmplt", "cmple", "cmpgt", "cmpge"];
    let labels = 10u32;
    let reg = |random: &mut Rng| format!("r{}", random.below(6));
    // The loop starts with a compare and branch, so that the `jumpi 0` at its end
    // is threaded into it.
    let (a, b, c) = (reg(random), reg(random), reg(random));
    let first_cmp = CMP[random.below(CMP.len() as u64) as usize];
    let first_cmp = format!("{first_cmp} {a},{b},{c}");
    let mut body = vec!["label 0".to_string()];
    // Half the time against a constant (in `b`, which the body may overwrite).
    if random.below(2) == 0 {
        body.push(format!("loadi {},{b}", random.below(5) as i64 - 2));
    }
    body.extend([
        first_cmp,
        format!("cbr {c},1,1"),
        "label 1".to_string(),
        "loads 444,r3".to_string(),
    ]);
    let mut next_label = 2;
    while body.len() < 60 {
        // Sometimes place the next label here, possibly inside a group.
        // The last label is kept for the loop's end, so every branch goes forward.
        if next_label < labels - 1 && random.below(4) == 0 {
            body.push(format!("label {next_label}"));
            next_label += 1;
        }
        let constant = if random.below(2) == 0 {
            format!("loadi {}", random.below(7) as i64 - 2)
        } else {
            format!("loadd {:?}", (random.below(9) as f64 - 3.0) * 0.5)
        };
        let forward = |random: &mut Rng, next_label: u32| {
            next_label + random.below(u64::from(labels - next_label)) as u32
        };
        match random.below(7) {
            0 => {
                let t = reg(random);
                body.push(format!("{constant},{t}"));
                let (a, b) = if random.below(2) == 0 {
                    (reg(random), t)
                } else {
                    (t, reg(random))
                };
                let op = ARITH[random.below(ARITH.len() as u64) as usize];
                body.push(format!("{op} {a},{b},{}", reg(random)));
            }
            1 | 2 => {
                let with_constant = random.below(2) == 0;
                let t = reg(random);
                if with_constant {
                    body.push(format!("{constant},{t}"));
                }
                let (a, b) = if random.below(2) == 0 {
                    (reg(random), t)
                } else {
                    (t, reg(random))
                };
                let c = reg(random);
                let op = CMP[random.below(CMP.len() as u64) as usize];
                body.push(format!("{op} {a},{b},{c}"));
                // Branch forward to labels not yet placed (or to the loop's end).
                let forward = |random: &mut Rng| {
                    next_label + random.below(u64::from(labels - next_label)) as u32
                };
                let (yes, no) = (forward(random), forward(random));
                body.push(format!("cbr {c},{yes},{no}"));
            }
            3 => {
                let t = reg(random);
                body.push(format!("i2d {},{t}", reg(random)));
                body.push(format!("add {},{t},{}", reg(random), reg(random)));
            }
            4 => {
                // GBASIC's array index check, with registers that may overlap.
                let (t_lo, c_lo, t_hi, c_hi, x) = (
                    reg(random),
                    reg(random),
                    reg(random),
                    reg(random),
                    reg(random),
                );
                body.push(format!("loadi {},{t_lo}", random.below(3) as i64 - 1));
                body.push(format!("cmplt {x},{t_lo},{c_lo}"));
                body.push(format!("loadi {},{t_hi}", random.below(4)));
                body.push(format!("cmpge {x},{t_hi},{c_hi}"));
                let d = reg(random);
                if random.below(2) == 0 {
                    body.push(format!("or {c_lo},{c_hi},{d}"));
                } else {
                    body.push(format!("or {c_hi},{c_lo},{d}"));
                }
                let (yes, no) = (forward(random, next_label), forward(random, next_label));
                body.push(format!("cbr {d},{yes},{no}"));
            }
            5 => {
                // Memory through a register address: integers in and out of
                // range, whole and fractional floats (traps end the cycle).
                let (value, address) = (reg(random), reg(random));
                if random.below(2) == 0 {
                    body.push(format!("storem {value},{address}"));
                } else {
                    body.push(format!("loadm {address},{value}"));
                }
            }
            _ => body.push(format!("print {}", reg(random))),
        }
    }
    while next_label < labels {
        body.push(format!("label {next_label}"));
        next_label += 1;
    }
    body.push("yield".to_string());
    // Half the time a step before the back edge, which joins it and the loop test.
    if random.below(2) == 0 {
        body.push(format!(
            "add {},{},{}",
            reg(random),
            reg(random),
            reg(random)
        ));
    }
    body.push("jumpi 0".to_string());
    script(6, labels, 3, &body)
}

#[test]
fn random_scripts_agree_with_stepping() {
    let mut random = Rng::new(0x9e37_79b9_7f4a_7c15);
    for _ in 0..300 {
        let text = random_script(&mut random);
        let budget = 1 + random.below(70);
        agree(&text, 4, budget, 2.5);
        agree(&text, 4, 10_000, 2.5);
    }
}

/// The GLOC scripts of the repository that check clean (the `ok` fixtures, which
/// use every kind of instruction: memory, indirect jumps, logic, printing, and
/// the paper's Fig. 2 script), every budget from 1 to 40 and the default.
#[test]
fn the_repository_scripts_agree_at_every_budget() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut paths: Vec<_> = std::fs::read_dir(root.join("tests/fixtures/gloc/ok"))
        .expect("the ok fixtures are in the repository")
        .map(|entry| entry.expect("a readable entry").path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension == "gloc")
        })
        .collect();
    paths.sort();
    paths.push(root.join("examples/fig2.gloc"));
    assert!(paths.len() >= 7, "{paths:?}");
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("a readable script");
        for budget in (1..=40).chain([10_000]) {
            agree(&text, 6, budget, 12.5);
        }
    }
}

/// Threaded dispatch runs handlers specialised by the loader's type analysis
/// (`r0` only ever holds integers here, so `add r0,r0,r1` skips the tag
/// tests). A debugger can still store a float in `r0` between cycles: the
/// machine must notice and compute with the float, as the `match` loop and
/// single steps do (1.5 + 1.5 = 3.0, worked by hand); an integer stored there
/// keeps the fast handlers and gives 7 + 7.
#[test]
fn a_register_set_against_its_static_type_is_honoured() {
    let text = script(
        2,
        1,
        0,
        &lines("loadi 3,r0\nlabel 0\nyield\nadd r0,r0,r1\njumpi 0"),
    );
    let program = program(&text);
    let config = MachineConfig::default();
    let mut results = Vec::new();
    for dispatch in [Dispatch::Loop, Dispatch::Threaded, Dispatch::Threaded] {
        let mut machine = Machine::new(Arc::clone(&program), config);
        machine.set_dispatch(dispatch);
        let mut host = Recorder::default();
        let mut seen = Vec::new();
        for stored in [Value::Float(1.5), Value::Int(7)] {
            assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
            machine
                .set_register(gloc_engine::program::Reg(0), stored)
                .expect("r0 exists");
            if results.len() == 2 {
                // The third machine steps its way through the cycle.
                while machine.step(&mut host).is_none() {}
            } else {
                assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
            }
            seen.push(bits(machine.registers()));
        }
        results.push(seen);
    }
    assert_eq!(results[0][0][1], (false, 3.0f64.to_bits()), "{results:?}");
    assert_eq!(results[0][1][1], (true, 14), "{results:?}");
    assert_eq!(results[1], results[0], "threaded against the match loop");
    assert_eq!(
        results[2], results[0],
        "threaded then steps against the match loop"
    );
}

/// A `jumpi` to a loop's step (the end of an `if` branch in the body) is one
/// op with the step, the back edge and the test: every budget stops where
/// single steps stop, and the sum of the even numbers 2..=10 is 30 (by hand).
#[test]
fn a_jump_to_a_loop_step_gives_the_hand_worked_sum() {
    let text = script(
        8,
        5,
        0,
        &lines(
            "loadi 1,r0\nloadi 10,r1\nloadi 1,r2\nlabel 0\ncmple r0,r1,r3\ncbr r3,1,3\n\
             label 1\nloadi 2,r4\nmod r0,r4,r4\ncbr r4,2,4\nlabel 4\nadd r5,r0,r5\njumpi 2\n\
             label 2\nadd r0,r2,r0\njumpi 0\nlabel 3\nyield",
        ),
    );
    for budget in (1..=80).chain([10_000]) {
        agree(&text, 3, budget, 0.0);
    }
    let machine = agree(&text, 1, 10_000, 0.0);
    assert_eq!(machine.registers()[5], Value::Int(30));
}
