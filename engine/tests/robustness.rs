//! Thousands of mutated scripts (bytes deleted, duplicated, replaced) go
//! through parse, print, check and a few cycles of the interpreter: nothing
//! may panic, spans stay in bounds, and printing is idempotent.

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{Host, Machine, MachineConfig};

struct NullHost;

impl Host for NullHost {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        f64::from(sensor.0 % 7)
    }
    fn store_sensor(&mut self, _sensor: SensorId, _value: f64) {}
    fn print_line(&mut self, _line: &str) {}
}

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, limit: usize) -> usize {
        (self.next() % limit.max(1) as u64) as usize
    }
}

const ALPHABET: &[u8] = b"r0123456789,.-e #\"\\\nlabeyidstorcmpgtjumhn\r\t\x00\xff";

#[test]
fn mutated_scripts_never_panic() {
    let seeds = [
        include_str!("../../examples/fig2.gloc"),
        include_str!("../../tests/fixtures/gloc/ok/memory.gloc"),
        include_str!("../../tests/fixtures/gloc/ok/printing.gloc"),
        include_str!("../../tests/fixtures/gloc/ok/indirect_jump.gloc"),
        include_str!("../../tests/fixtures/gloc/ok/logic.gloc"),
    ];
    let sensors = SensorList::embedded();
    let mut random = XorShift(0x9e37_79b9_7f4a_7c15);
    let mut programs_run = 0;
    for round in 0..3000 {
        let mut bytes = seeds[round % seeds.len()].as_bytes().to_vec();
        for _ in 0..=random.below(4) {
            let at = random.below(bytes.len());
            match random.below(3) {
                0 if !bytes.is_empty() => {
                    bytes.remove(at);
                }
                1 => bytes.insert(at, ALPHABET[random.below(ALPHABET.len())]),
                _ if !bytes.is_empty() => bytes[at] = ALPHABET[random.below(ALPHABET.len())],
                _ => {}
            }
        }
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let parsed = gloc::parse(&text);
        let printed = gloc::print(&parsed.file);
        assert_eq!(
            gloc::print(&gloc::parse(&printed).file),
            printed,
            "{text:?}"
        );
        let checked = gloc::check(&parsed, &sensors, &CheckOptions::default());
        for diagnostic in &checked.diagnostics {
            assert!((diagnostic.span.end as usize) <= text.len(), "{text:?}");
            assert!(
                text.is_char_boundary(diagnostic.span.start as usize),
                "{text:?}"
            );
        }
        assert_eq!(
            checked.program.is_some(),
            !checked.diagnostics.iter().any(|d| d.is_error())
        );
        if let Some(program) = checked.program {
            programs_run += 1;
            let mut machine = Machine::new(program, MachineConfig { cycle_budget: 500 });
            for _ in 0..5 {
                machine.run_cycle(&mut NullHost);
            }
        }
    }
    assert!(
        programs_run > 100,
        "only {programs_run} mutants were runnable"
    );
}
