//! Worst-case instructions per cycle with and without a caller-supplied
//! loop bound. Expected figures are counted by hand below.

use gloc_engine::gloc::{self, Bound, CheckOptions, LoopBound};
use gloc_engine::program::Pc;
use gloc_engine::sensors::SensorList;

/// pc 0-2: set-up; pc 3-6: the loop (cmplt cbr | add jumpi), header label 0;
/// pc 7: yield; pc 8: halt.
const COUNTING_LOOP: &str = "\
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

#[test]
fn an_unbounded_loop_warns_and_makes_the_worst_case_unbounded() {
    let checked = gloc::check(
        &gloc::parse(COUNTING_LOOP),
        &SensorList::embedded(),
        &CheckOptions::default(),
    );
    let codes: Vec<_> = checked.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, vec!["W0111"]);
    assert!(
        checked.program.is_some(),
        "a warning does not refuse the script"
    );
    let worst = checked.stats.worst_case.expect("analysed");
    assert_eq!(worst.from_start, Bound::Unbounded);
    assert_eq!(worst.from_yields, vec![(Pc(7), Bound::Finite(1))]);
    assert_eq!(worst.max, Bound::Unbounded);
}

#[test]
fn a_loop_bound_from_the_caller_gives_a_finite_worst_case() {
    let options = CheckOptions {
        loop_bounds: vec![LoopBound {
            label: 0,
            max_iterations: 10,
        }],
        ..CheckOptions::default()
    };
    let checked = gloc::check(
        &gloc::parse(COUNTING_LOOP),
        &SensorList::embedded(),
        &options,
    );
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    let worst = checked.stats.worst_case.expect("analysed");
    // One iteration is at most cmplt cbr add jumpi = 4 instructions; the
    // bound allows 10 jumps back, so 11 passes: 44. Then the exit to the
    // yield (1) and the 3 set-up instructions: 48. (The real maximum is 46:
    // the last pass only runs cmplt and cbr; the bound is safe, not exact.)
    assert_eq!(worst.from_start, Bound::Finite(48));
    assert_eq!(worst.from_yields, vec![(Pc(7), Bound::Finite(1))]);
    assert_eq!(worst.max, Bound::Finite(48));
}

#[test]
fn a_bound_on_the_outer_loop_leaves_an_inner_loop_unbounded() {
    // Outer loop at label 0 (bounded), inner busy loop at label 1 (not).
    let text = "\
nregs 2
nblbs 4
ninstr 11
loadi 0,r0
label 0
loads 1385,r1
label 1
cbr r1,1,2
label 2
loadi 1,r1
cbr r0,0,3
label 3
yield
halt
";
    let options = CheckOptions {
        loop_bounds: vec![LoopBound {
            label: 0,
            max_iterations: 3,
        }],
        ..CheckOptions::default()
    };
    let checked = gloc::check(&gloc::parse(text), &SensorList::embedded(), &options);
    let found: Vec<_> = checked
        .diagnostics
        .iter()
        .map(|d| (d.code, d.span.start))
        .collect();
    // The inner loop is the lone `cbr r1,1,2` on line 8.
    let inner = text.find("cbr r1,1,2").expect("present") as u32;
    assert_eq!(found, vec![("W0111", inner)]);
    assert_eq!(
        checked.stats.worst_case.expect("analysed").from_start,
        Bound::Unbounded
    );
}
