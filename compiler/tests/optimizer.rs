//! What each optimizer pass does, on small GBASIC programs whose `-O` GLOC was
//! worked out by hand from `compiler/src/optimize.rs` (the derivation is in the
//! comment above each expectation). `differential.rs` checks that `-O` keeps the
//! behavior; these check that the passes actually change the code.
//!
//! Sensor indices come from `engine/data/sensors-2008.txt`: `c_pitch` 96,
//! `m_pitch` 437, `m_depth` 444.

use gloc_compiler::{
    compile, load_script, CompileOptions, Language, LoadOptions, LoadedScript, Optimization,
};
use gloc_engine::sensors::SensorList;

/// `source` loaded as `gloc check` and `gloc run` load it (compiled, checked as GLOC).
fn load(source: &str, optimization: Optimization) -> LoadedScript {
    load_script(
        source,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions::from(optimization),
    )
}

fn build(source: &str, optimization: Optimization) -> String {
    let sensors = SensorList::embedded();
    let compiled = compile(source, &sensors, &CompileOptions { optimization });
    assert!(
        !compiled.has_errors(),
        "{source}: {:?}",
        compiled.diagnostics
    );
    // The result must also pass the GLOC checker and load.
    let loaded = load(source, optimization);
    assert!(
        loaded.program.is_some(),
        "{source} (optimization {optimization:?}): {:?}",
        loaded.diagnostics
    );
    compiled.code.expect("no errors, so GLOC").gloc_text
}

fn plain(source: &str) -> String {
    build(source, Optimization::Plain)
}

fn optimized(source: &str) -> String {
    build(source, Optimization::Optimized)
}

#[test]
fn constant_folding_turns_an_integer_expression_into_one_load() {
    let source = "dim x as integer\nx = 2 * 3 + 1\nprint x\n";
    // Unoptimized, x is r0 and every value takes a fresh register:
    // loadi 2,r1; loadi 3,r2; mul r1,r2,r3; loadi 1,r4; add r3,r4,r5; mov r5,r0; print r0.
    let unoptimized = plain(source);
    assert!(unoptimized.contains("mul r1,r2,r3\n"), "{unoptimized}");
    assert!(unoptimized.contains("add r3,r4,r5\n"), "{unoptimized}");
    // Folding: mul of the known 2 and 3 becomes `loadi 6,r3`, the add `loadi 7,r5`,
    // and `mov r5,r0` of a known 7 becomes a copy from r5 (the register already
    // holding 7), so `print r0` reads r5. Liveness then drops the loads of 2, 3,
    // 6 and 1 and the dead copy into r0; r5 is renamed r0.
    assert_eq!(
        optimized(source),
        "nregs 1\nnblbs 0\nninstr 2\nloadi 7,r0\nprint r0\n"
    );
}

#[test]
fn constant_folding_widens_integers_and_folds_float_division() {
    // `/` is float division, so 1 / 4 is 0.25 and + 0.5 gives 0.75, exactly. The
    // initial `loadd 0.0` of f and the final copy into f are dead once `print`
    // reads the register holding 0.75.
    let source = "dim f as float\nf = 1 / 4 + 0.5\nprint f\n";
    assert_eq!(
        optimized(source),
        "nregs 1\nnblbs 0\nninstr 2\nloadd 0.75,r0\nprint r0\n"
    );
}

#[test]
fn copy_propagation_reads_the_original_register() {
    let source = "dim a as float\ndim b as float\na = m_depth\nb = a\nc_pitch = b + a\n";
    // Unoptimized (a r0, b r1): loadd 0.0,r0; loadd 0.0,r1; loads 444,r2;
    // mov r2,r0; mov r0,r1; add r1,r0,r3; stores r3,96.
    let unoptimized = plain(source);
    assert!(unoptimized.contains("add r1,r0,r3\n"), "{unoptimized}");
    // After `mov r2,r0` r0 is a copy of r2, so `mov r0,r1` becomes `mov r2,r1`, and
    // then `add r1,r0,r3` reads `add r2,r2,r3`. Both copies and both `loadd 0.0`
    // are then dead. r2 and r3 never live together, so both become r0.
    assert_eq!(
        optimized(source),
        "nregs 1\nnblbs 0\nninstr 3\nloads 444,r0\nadd r0,r0,r0\nstores r0,96\n"
    );
}

#[test]
fn dead_code_removal_drops_a_value_nobody_reads() {
    let source = "dim d as float\ndim twice as float\nd = m_depth\ntwice = d * 2.0\nprint d\n";
    let unoptimized = plain(source);
    assert!(unoptimized.contains("mul "), "{unoptimized}");
    // `twice` is never read: coalescing makes `mul r2,r3,r4; mov r4,r1` into
    // `mul r2,r3,r1`, liveness finds r1 dead after it and removes the mul, then the
    // `loadd 2.0` that fed it, the zero-initialisations and the copy into d (print
    // reads the sensor's register r2 directly).
    assert_eq!(
        optimized(source),
        "nregs 1\nnblbs 0\nninstr 2\nloads 444,r0\nprint r0\n"
    );
}

#[test]
fn dead_code_removal_keeps_a_division_that_can_trap() {
    // q's value is never read, but `div` traps when n is 0, so it stays (its result
    // coalesced straight into q). Registers: r2 (the 7) and n (r0, read before it is
    // written, so it keeps its initial 0) are live together and need two numbers;
    // q is never live and shares the 7's number: 7 → r0, n → r1, q → r0.
    let source = "dim n as integer\ndim q as integer\nq = 7 \\ n\nprint \"x\"\n";
    assert_eq!(
        optimized(source),
        "nregs 2\nnblbs 0\nninstr 3\nloadi 7,r0\ndiv r0,r1,r0\nprints \"x\"\n"
    );
}

#[test]
fn dead_code_removal_keeps_a_float_division_too() {
    // `div` is integer or float by the values at run time, so a dead float `div`
    // stays like an integer one (docs/gbasic.md says so). As in the mul case above
    // the division's result is coalesced into `half` (r1) and the copies and zero
    // initialisations go: loads 444,r2; loadd 2.0,r3; div r2,r3,r1; print r2.
    // r2 is live across everything; r3 and r1 each overlap only r2 and not each
    // other, so r2 → r0, r3 → r1, r1 → r1.
    let source = "dim d as float\ndim half as float\nd = m_depth\nhalf = d / 2.0\nprint d\n";
    assert_eq!(
        optimized(source),
        "nregs 2\nnblbs 0\nninstr 4\nloads 444,r0\nloadd 2.0,r1\ndiv r0,r1,r1\nprint r0\n"
    );
}

#[test]
fn common_subexpressions_are_computed_once() {
    let source = "dim d as float\nd = m_depth\nc_pitch = d * 2.0 + d * 2.0\n";
    // Unoptimized (d r0): loadd 0.0,r0; loads 444,r1; mov r1,r0; loadd 2.0,r2;
    // mul r0,r2,r3; loadd 2.0,r4; mul r0,r4,r5; add r3,r5,r6; stores r6,96.
    // The second 2.0 is a copy of r2, so the second mul reads `mul r1,r2` like the
    // first and becomes `mov r3,r5`; the add reads `add r3,r3,r6`. Four
    // instructions remain plus the store, in two registers (the sensor value and
    // 2.0 are live together; each product can reuse the sensor's register).
    assert_eq!(
        optimized(source),
        "nregs 2\nnblbs 0\nninstr 5\nloads 444,r0\nloadd 2.0,r1\nmul r0,r1,r0\nadd r0,r0,r0\nstores r0,96\n"
    );
}

#[test]
fn register_reuse_gives_values_that_never_overlap_the_same_register() {
    let source = "print m_depth * 2.0\nprint m_pitch * 3.0\n";
    // Unoptimized: six values, six registers, nothing to fold or remove.
    assert_eq!(
        plain(source),
        "nregs 6\nnblbs 0\nninstr 8\nloads 444,r0\nloadd 2.0,r1\nmul r0,r1,r2\nprint r2\nloads 437,r3\nloadd 3.0,r4\nmul r3,r4,r5\nprint r5\n"
    );
    // Interference: only r0–r1 (both live into the first mul) and r3–r4. Greedy
    // coloring in order of first appearance: r0 0, r1 1, r2 0, r3 0, r4 1, r5 0.
    assert_eq!(
        optimized(source),
        "nregs 2\nnblbs 0\nninstr 8\nloads 444,r0\nloadd 2.0,r1\nmul r0,r1,r0\nprint r0\nloads 437,r0\nloadd 3.0,r1\nmul r0,r1,r0\nprint r0\n"
    );
}

#[test]
fn jump_threading_sends_a_branch_past_a_jump_and_labels_are_renumbered() {
    let source =
        "label: top\nif m_depth > 5.0 then goto deep\nyield\ngoto top\nlabel: deep\nprint \"deep\"\n";
    // User labels first (top 0, deep 1), then the if's then 2 and next 3.
    assert_eq!(
        plain(source),
        "nregs 3\nnblbs 4\nninstr 12\nlabel 0\nloads 444,r0\nloadd 5.0,r1\ncmpgt r0,r1,r2\ncbr r2,2,3\nlabel 2\njumpi 1\nlabel 3\nyield\njumpi 0\nlabel 1\nprints \"deep\"\n"
    );
    // Label 2 starts with `jumpi 1`, so the branch goes to 1 directly
    // (`cbr r2,1,3`); `label 2; jumpi 1` is then unreachable and goes. The labels
    // left, in order, are 0, 3, 1 and become 0, 1, 2. r2 is defined when r0 and r1
    // are dead, so it takes r0.
    assert_eq!(
        optimized(source),
        "nregs 2\nnblbs 3\nninstr 10\nlabel 0\nloads 444,r0\nloadd 5.0,r1\ncmpgt r0,r1,r0\ncbr r0,2,1\nlabel 1\nyield\njumpi 0\nlabel 2\nprints \"deep\"\n"
    );
}

#[test]
fn a_branch_on_a_known_condition_folds_away_and_the_last_label_becomes_0() {
    let source =
        "dim x as integer\nx = 3\nif x > 5 then\n  print \"big\"\nendif\nlabel: again\nyield\ngoto again\n";
    // Unoptimized: label `again` is 0, the if's labels 1 and 2; x is r0.
    assert_eq!(
        plain(source),
        "nregs 4\nnblbs 3\nninstr 11\nloadi 3,r1\nmov r1,r0\nloadi 5,r2\ncmpgt r0,r2,r3\ncbr r3,1,2\nlabel 1\nprints \"big\"\nlabel 2\nlabel 0\nyield\njumpi 0\n"
    );
    // 3 > 5 folds to 0, so the cbr becomes `jumpi 2` and `print "big"` is
    // unreachable. `label 2; label 0` in a row merge into 2 (`jumpi 0` becomes
    // `jumpi 2`), then `jumpi 2` right before `label 2` goes, and every register
    // write is dead. What is left is the yield loop, its label renumbered 0.
    assert_eq!(
        optimized(source),
        "nregs 0\nnblbs 1\nninstr 3\nlabel 0\nyield\njumpi 0\n"
    );
}

/// Found by the CI-sized fuzz run (gbasic_compile, 2026-11-27): `n = 10` then `loop
/// while n < 25` folds to a loop with no way out. The plain code compiles (W0111, it
/// traps when the cycle budget runs out); `-O` refused it with E0111, so the flag
/// changed whether the program compiles. Now `-O` keeps the plain code and says why.
#[test]
fn a_loop_folding_proves_endless_keeps_the_plain_code_with_a_warning() {
    let source = "dim n as integer\ndo\n  n = 10\nloop while n < 25\nprint n\nend\n";
    let (plain, optimized) = (
        load(source, Optimization::Plain),
        load(source, Optimization::Optimized),
    );
    assert!(plain.program.is_some(), "{:?}", plain.diagnostics);
    assert!(optimized.program.is_some(), "{:?}", optimized.diagnostics);
    assert_eq!(
        optimized.gloc_text, plain.gloc_text,
        "the plain code is kept"
    );
    let codes = |loaded: &LoadedScript| -> Vec<&str> {
        loaded.diagnostics.iter().map(|d| d.code).collect()
    };
    assert_eq!(codes(&plain), ["W0111"]);
    // The proof is on the `loop while` line (line 4), where the loop jumps back.
    let warning = optimized
        .diagnostics
        .iter()
        .find(|d| d.code == "W2304")
        .expect("W2304 explains why -O was not used");
    let line_start = source.match_indices('\n').nth(2).unwrap().0 + 1;
    assert_eq!(warning.span.start as usize, line_start, "{warning:?}");
    assert!(codes(&optimized).contains(&"W0111"));
    // A loop -O cannot prove endless is still optimized.
    let bounded = "dim n as integer\ndo\n  n = n + 10\nloop while n < 25\nprint n\nend\n";
    assert_ne!(
        load(bounded, Optimization::Optimized).gloc_text,
        load(bounded, Optimization::Plain).gloc_text
    );
}
