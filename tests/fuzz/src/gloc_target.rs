//! GLOC parser + checker + VM: no panic on any text, spans in bounds, and the
//! print → parse round trip keeps the meaning of every file that parses cleanly.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions, Checked};
use gloc_engine::program::Program;
use gloc_engine::sensors::SensorId;
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};
use gloc_engine::{Diagnostic, Severity};

/// Control cycles a fuzzed program may run; with the small budget below a
/// hostile program costs at most `CYCLES * BUDGET` instructions.
const CYCLES: u32 = 32;
const BUDGET: u64 = 2_000;

pub fn check_gloc(text: &str) {
    let sensors = crate::embedded_sensors();
    let parsed = gloc::parse(text);
    assert_spans_in_bounds(text, &parsed.diagnostics, "parse");
    let checked = gloc::check(&parsed, sensors, &CheckOptions::default());
    assert_spans_in_bounds(text, &checked.diagnostics, "check");
    assert_eq!(
        checked.program.is_some(),
        !checked.diagnostics.iter().any(is_error),
        "program is Some exactly when no diagnostic is an error"
    );
    let canonical = gloc::print(&parsed.file);
    // Printing is idempotent on any input, even with invalid lines kept verbatim.
    let reparsed = gloc::parse(&canonical);
    assert_eq!(
        gloc::print(&reparsed.file),
        canonical,
        "print(parse(print(x))) == print(x)"
    );
    if !parsed.diagnostics.is_empty() {
        if let Some(program) = &checked.program {
            run(program);
        }
        return;
    }
    // A clean parse: the canonical text means the same thing.
    assert!(
        reparsed.diagnostics.is_empty(),
        "the canonical text of a clean file parses cleanly: {:?}\n--- canonical ---\n{canonical}",
        reparsed.diagnostics
    );
    let rechecked = gloc::check(&reparsed, sensors, &CheckOptions::default());
    assert_eq!(
        codes(&checked),
        codes(&rechecked),
        "the same checker diagnostics after the round trip"
    );
    assert_eq!(checked.stats, rechecked.stats, "the same stats");
    match (&checked.program, &rechecked.program) {
        (Some(original), Some(printed)) => {
            assert_same_program(original, printed);
            assert_eq!(run(original), run(printed), "the same run");
        }
        (None, None) => {}
        _ => panic!("the round trip changed whether the file checks"),
    }
}

fn is_error(diagnostic: &Diagnostic) -> bool {
    diagnostic.severity == Severity::Error
}

fn codes(checked: &Checked) -> Vec<&'static str> {
    checked
        .diagnostics
        .iter()
        .map(|diagnostic| diagnostic.code)
        .collect()
}

pub fn assert_spans_in_bounds(text: &str, diagnostics: &[Diagnostic], stage: &str) {
    for diagnostic in diagnostics {
        let spans = std::iter::once(diagnostic.span)
            .chain(diagnostic.labels.iter().map(|label| label.span))
            .chain(diagnostic.fixes.iter().map(|fix| fix.span));
        for span in spans {
            assert!(
                span.start <= span.end
                    && text.is_char_boundary(span.start as usize)
                    && text.is_char_boundary(span.end as usize),
                "{stage}: span {span:?} of {} is not a range of the text ({} bytes)",
                diagnostic.code,
                text.len()
            );
        }
    }
}

fn assert_same_program(original: &Program, printed: &Program) {
    assert_eq!(original.instrs, printed.instrs, "the same instructions");
    assert_eq!(original.texts, printed.texts, "the same texts");
    assert_eq!(original.register_count, printed.register_count);
    assert_eq!(original.memory_size, printed.memory_size);
    assert_eq!(original.label_pcs, printed.label_pcs);
    assert_eq!(original.lines, printed.lines, "the same line per pc");
}

/// What a run did, as comparable events.
#[derive(Debug, Default, PartialEq)]
pub struct Recording {
    pub events: Vec<Event>,
}

#[derive(Debug, PartialEq)]
pub enum Event {
    /// A sensor write, with the value's bits (so NaN equals NaN).
    Store(SensorId, u64),
    Print(String),
    /// The end of a cycle.
    Yield,
    End(String),
}

impl Recording {
    pub fn yields(&self) -> usize {
        self.events
            .iter()
            .filter(|event| matches!(event, Event::Yield))
            .count()
    }

    /// Keeps the events of the first `cycles` cycles.
    pub fn keep_cycles(&mut self, cycles: usize) {
        let mut seen = 0;
        let end = self
            .events
            .iter()
            .position(|event| {
                if matches!(event, Event::Yield) {
                    seen += 1;
                }
                seen > cycles || (seen == cycles && !matches!(event, Event::Yield))
            })
            .unwrap_or(self.events.len());
        self.events.truncate(end);
    }
}

/// A deterministic world: each sensor reads a value that changes every cycle.
struct RecordingHost {
    cycle: u32,
    recording: Recording,
}

impl Host for RecordingHost {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        f64::from(sensor.0 % 97) * 0.5 + f64::from(self.cycle) - 4.0
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.recording
            .events
            .push(Event::Store(sensor, value.to_bits()));
    }

    fn print_line(&mut self, line: &str) {
        self.recording.events.push(Event::Print(line.to_string()));
    }
}

/// Runs a program for a bounded number of cycles and records what it did.
pub fn run(program: &Arc<Program>) -> Recording {
    run_with(program, CYCLES, BUDGET)
}

pub fn run_with(program: &Arc<Program>, cycles: u32, budget: u64) -> Recording {
    let mut machine = Machine::new(
        program.clone(),
        MachineConfig {
            cycle_budget: budget,
        },
    );
    let mut host = RecordingHost {
        cycle: 0,
        recording: Recording::default(),
    };
    for cycle in 0..cycles {
        host.cycle = cycle;
        match machine.run_cycle(&mut host) {
            CycleEnd::Yielded => {
                assert!(machine.at_cycle_boundary(), "a yield ends at a boundary");
                host.recording.events.push(Event::Yield);
            }
            end @ (CycleEnd::Halted | CycleEnd::Trapped(_)) => {
                let described = describe(&end);
                if let CycleEnd::Trapped(trap) = &end {
                    assert!(
                        (trap.pc.0 as usize) < program.instrs.len(),
                        "a trap names a pc of the program"
                    );
                    assert_eq!(trap.line, program.line(trap.pc), "a trap names its line");
                }
                // Ended machines stay ended and run nothing more.
                let again = machine.run_cycle(&mut host);
                assert_eq!(describe(&again), described, "an ended machine stays ended");
                host.recording.events.push(Event::End(described));
                break;
            }
        }
    }
    host.recording
}

/// The end of a run without its span (spans move in the round trip; the
/// pc and the line do not). Debug text so that a NaN in a trap compares equal.
fn describe(end: &CycleEnd) -> String {
    match end {
        CycleEnd::Trapped(trap) => format!(
            "trapped {:?} at pc {} line {}",
            trap.kind, trap.pc.0, trap.line
        ),
        other => format!("{other:?}"),
    }
}
