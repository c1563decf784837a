//! GBASIC compiler: no panic on any text, compiled code always passes the
//! GLOC checker, and `-O` does not change what a program does: the same
//! sensor writes and printed lines, cycle by cycle, for a bounded run.

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};

use crate::gloc_target::{run_with, Event, Recording};

const CYCLES: u32 = 16;
const BUDGET: u64 = 10_000;

pub fn check_gbasic(text: &str) {
    let sensors = crate::embedded_sensors();
    let load = |optimization| {
        load_script(text, Language::Gbasic, sensors, &LoadOptions::from(optimization))
    };
    let plain = load(Optimization::Plain);
    let optimized = load(Optimization::Optimized);
    crate::gloc_target::assert_spans_in_bounds(text, &plain.diagnostics, "gbasic");
    crate::gloc_target::assert_spans_in_bounds(text, &optimized.diagnostics, "gbasic -O");
    assert_eq!(
        plain.has_errors(),
        optimized.has_errors(),
        "-O does not change whether a program compiles"
    );
    let (Some(plain_program), Some(optimized_program)) = (&plain.program, &optimized.program)
    else {
        assert!(
            plain.has_errors(),
            "a program without errors compiles to GLOC that checks: {:?}",
            plain.diagnostics
        );
        return;
    };
    let mut plain_run = run_with(plain_program, CYCLES, BUDGET);
    let mut optimized_run = run_with(optimized_program, CYCLES, BUDGET);
    comparable(&mut plain_run, &mut optimized_run);
    assert_eq!(
        plain_run, optimized_run,
        "-O changed the run\n--- plain ---\n{}\n--- optimized ---\n{}",
        plain.gloc_text.as_deref().unwrap_or_default(),
        optimized.gloc_text.as_deref().unwrap_or_default()
    );
}

/// Makes two runs comparable: an optimized program runs fewer instructions,
/// so a cycle overrun (a budget, not a meaning) may come later or never; both
/// runs are cut to the cycles they both finished. Trap places differ too
/// (pc, line of compiled code): only the trap kind is kept.
fn comparable(first: &mut Recording, second: &mut Recording) {
    let overran = |recording: &Recording| {
        recording
            .events
            .iter()
            .any(|event| matches!(event, Event::End(end) if end.contains("CycleOverrun")))
    };
    if overran(first) || overran(second) {
        let cycles = first.yields().min(second.yields());
        first.keep_cycles(cycles);
        second.keep_cycles(cycles);
    }
    for recording in [first, second] {
        for event in &mut recording.events {
            if let Event::End(end) = event {
                if let Some(cut) = end.find(" at pc ") {
                    end.truncate(cut);
                }
            }
        }
    }
}
