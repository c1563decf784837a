//! An output line never ended by `print` is bounded (hardening, issue 19): past
//! `MAX_OUTPUT_LINE` bytes it goes to the host with the `[continued]` marker and the
//! next item starts a new line. Expected lines are worked out by hand from that rule.

use gloc_engine::gloc::{self, Bound, CheckOptions};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{
    CycleEnd, Host, Machine, MachineConfig, MAX_OUTPUT_LINE, OUTPUT_LINE_CONTINUED,
};

mod support;

#[derive(Default)]
struct Lines(Vec<String>);

impl Host for Lines {
    fn load_sensor(&mut self, _sensor: SensorId) -> f64 {
        0.0
    }
    fn store_sensor(&mut self, _sensor: SensorId, _value: f64) {}
    fn print_line(&mut self, line: &str) {
        self.0.push(line.to_string());
    }
}

#[test]
fn a_line_that_is_never_printed_is_cut_at_the_cap() {
    // One 9-byte item per cycle, never printed.
    let text = "nregs 0\nnblbs 1\nninstr 4\nlabel 0\nwrites \"abcdefghi\"\nyield\njumpi 0\n";
    let mut machine = Machine::new(support::program(text), MachineConfig::default());
    let mut host = Lines::default();
    for _ in 0..20_000 {
        assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    }
    assert_eq!(MAX_OUTPUT_LINE, 65_536);
    // k items take 10k - 1 bytes; the first k over 65,536 is 6,554 (65,539 bytes).
    let full_line = format!(
        "{}{OUTPUT_LINE_CONTINUED}",
        vec!["abcdefghi"; 6_554].join(" ")
    );
    assert_eq!(host.0.len(), 3, "20,000 items make three full lines");
    for line in &host.0 {
        assert_eq!(line, &full_line);
    }
    // 20,000 - 3 × 6,554 = 338 items are still pending: 3,379 bytes.
    assert_eq!(machine.pending_output().len(), 3_379);
}

#[test]
fn a_print_after_a_cut_line_ends_the_new_line() {
    // 70,000 bytes of text in one `writes`, then `write` and `print`.
    let long = "x".repeat(70_000);
    let text = format!(
        "nregs 1\nnblbs 0\nninstr 5\nwrites \"{long}\"\nloadi 7,r0\nwrite r0\nprint r0\nyield\n"
    );
    let mut machine = Machine::new(support::program(&text), MachineConfig::default());
    let mut host = Lines::default();
    assert_eq!(machine.run_cycle(&mut host), CycleEnd::Yielded);
    assert_eq!(
        host.0,
        [format!("{long}{OUTPUT_LINE_CONTINUED}"), "7 7".to_string()]
    );
}

fn output_bytes(text: &str) -> Bound {
    let parsed = gloc::parse(text);
    let checked = gloc::check(&parsed, &SensorList::embedded(), &CheckOptions::default());
    checked.stats.worst_case.expect("a worst case").output_bytes
}

#[test]
fn check_reports_the_worst_case_output_per_cycle() {
    // `writes "abc"` adds 1 + 3 bytes, `write r0` and `print r0` 1 + 24 each: 54.
    let text =
        "nregs 1\nnblbs 1\nninstr 6\nlabel 0\nwrites \"abc\"\nwrite r0\nprint r0\nyield\njumpi 0\n";
    assert_eq!(output_bytes(text), Bound::Finite(54));
    // Either branch: `prints "ab"` (3) or `writes "abcdef"` (7), then `yield`.
    let branches = "nregs 1\nnblbs 3\nninstr 10\nlabel 0\ncbr r0,1,2\nlabel 1\nprints \"ab\"\nyield\njumpi 0\nlabel 2\nwrites \"abcdef\"\nyield\njumpi 0\n";
    assert_eq!(output_bytes(branches), Bound::Finite(7));
    // A loop that writes without `yield` (W0111) has no bound.
    let unbounded = "nregs 2\nnblbs 2\nninstr 6\nlabel 0\nwrites \"a\"\ncmpgt r0,r1,r0\ncbr r0,0,1\nlabel 1\nyield\n";
    assert_eq!(output_bytes(unbounded), Bound::Unbounded);
}
