//! Resource bounds (hardening): a GBASIC program with 30,000 labels (0.9 MB) compiles
//! (each label is one GLOC label; GLOC allows 2^20), and a source over the
//! 1 MB GBASIC limit is refused with one clear error; diagnostics are capped per pass.

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};
use gloc_engine::sensors::SensorList;

fn load(text: &str) -> gloc_compiler::LoadedScript {
    load_script(
        text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions::from(Optimization::Plain),
    )
}

#[test]
fn a_program_with_30000_labels_compiles_and_keeps_them_all() {
    let labels = 30_000;
    let mut text = String::new();
    for label in 0..labels {
        // Each label is a state that yields and goes on to the next one.
        let next = (label + 1) % labels;
        text.push_str(&format!("label: s{label}\nyield\ngoto s{next}\n"));
    }
    let loaded = load(&text);
    assert!(
        !loaded.has_errors(),
        "{:?}",
        &loaded.diagnostics[..3.min(loaded.diagnostics.len())]
    );
    let program = loaded.program.expect("a program");
    let defined = program.label_pcs.iter().filter(|pc| pc.is_some()).count();
    assert!(defined >= labels, "{defined} labels defined");
}

#[test]
fn a_gbasic_source_over_1_mb_is_refused() {
    // 1 MB and one byte; in GLOC's limits, over GBASIC's.
    let text = format!("{}#", "' \n".repeat((1 << 20) / 3) + "x");
    assert_eq!(text.len(), gloc_compiler::MAX_GBASIC_BYTES + 1);
    let loaded = load(&text);
    assert!(loaded.program.is_none());
    let codes: Vec<&str> = loaded.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["E0013"], "{:?}", &loaded.diagnostics[..1]);
    assert!(
        loaded.diagnostics[0]
            .message
            .contains("the script is 1.0 MB; gloc reads scripts of at most 1 MB"),
        "{}",
        loaded.diagnostics[0].message
    );
}

#[test]
fn a_thousand_diagnostics_per_pass_then_one_count() {
    // 5,000 undeclared names: the checker keeps 1,000 and counts the rest in one E2011.
    let text = "x = 1\n".repeat(5000);
    let loaded = load(&text);
    let codes: Vec<&str> = loaded.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes.len(), 1001);
    assert!(
        codes[..1000].iter().all(|code| *code == "E2101"),
        "{codes:?}"
    );
    let last = loaded.diagnostics.last().expect("the count");
    assert_eq!(last.code, "E2011");
    assert_eq!(
        last.message,
        "4000 more diagnostics not shown (the first 1000 are listed)"
    );
    // At the last of those not shown: line 5,000.
    assert_eq!(last.span.start as usize, 6 * 4999);
}

#[test]
fn dash_o_on_a_program_beyond_the_liveness_limit_compiles_without_it() {
    // 30,000 `x = 1` lines: 60,000 instructions × 30,001 registers, over 2^30 bits.
    let text = format!("dim x as integer\n{}yield\n", "x = 1\n".repeat(30_000));
    let compiled = gloc_compiler::compile(
        &text,
        &gloc_engine::sensors::SensorList::embedded(),
        &gloc_compiler::CompileOptions {
            optimization: Optimization::Optimized,
        },
    );
    let codes: Vec<&str> = compiled.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["W2303"], "{:?}", compiled.diagnostics);
    let stats = compiled.code.expect("compiled").build.stats;
    assert_eq!(stats.registers, 30_001);
}
