//! Inlay hints: the text with each hint written in `⟨…⟩` where it shows.

use super::*;

fn check_hints(fixture: Fixture, expect: Expect) {
    let mut hints = gloc_ide::hints::inlay_hints(&fixture.analysis, 0, fixture.text.len());
    hints.sort_by_key(|hint| hint.offset);
    let mut rendered = fixture.text.clone();
    for hint in hints.iter().rev() {
        rendered.insert_str(hint.offset, &format!("⟨{}⟩", hint.label));
    }
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_cycle_costs_on_the_first_statement_and_after_each_yield() {
    // Compiled as in docs/gbasic.md: label 0; loads, loadd, cmpgt, cbr; label 1;
    // loadi, stores; label 2; yield; jumpi 0. The first cycle runs loads … stores
    // and the yield: 7. After the yield: jumpi 0 and the same 7: 8.
    check_hints(
        Fixture::new(
            Gbasic,
            "label: top\nif m_depth > 15.0 then\n  SCI_RUHP_BEHS = 128\nendif\nyield\ngoto top\n",
        ),
        expect![[r#"
            label: top
            if m_depth > 15.0 then⟨first cycle ≤ 7 instr⟩
              SCI_RUHP_BEHS = 128
            endif
            yield⟨next cycle ≤ 8 instr⟩
            goto top
        "#]],
    );
}

#[test]
fn gloc_sensor_names_and_cycle_costs() {
    // First cycle: loads, stores, yield (3). After the yield: jumpi 0, loads,
    // stores, yield (4). Sensor indices get their names.
    check_hints(
        Fixture::new(
            Gloc,
            "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloads 444,r0\nstores r0,1387\nyield\nlabel 1\njumpi 0\n",
        ),
        expect![[r#"
            nregs 1
            nblbs 2
            ninstr 6
            label 0
            loads 444⟨:m_depth⟩,r0⟨first cycle ≤ 3 instr⟩
            stores r0,1387⟨:sci_ruhp_behs⟩
            yield⟨next cycle ≤ 4 instr⟩
            label 1
            jumpi 0
        "#]],
    );
}

#[test]
fn only_the_hints_inside_the_range() {
    let fixture = Fixture::new(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloads 444,r0\n$0stores r0,1387\nyield$0\nlabel 1\njumpi 0\n",
    );
    let range = fixture.range();
    let labels: Vec<String> =
        gloc_ide::hints::inlay_hints(&fixture.analysis, range.start as usize, range.end as usize)
            .into_iter()
            .map(|hint| hint.label)
            .collect();
    assert_eq!(labels, [":sci_ruhp_behs", "next cycle ≤ 4 instr"]);
}

/// The tooltip's end for a budget from `from` (as the project layer words origins).
fn budget_tooltip(budget: u64, from: Option<&str>) -> String {
    let context = Context {
        cycle_budget: Some(budget),
        cycle_budget_from: from.map(str::to_string),
        ..context()
    };
    let fixture = Fixture::with_context(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r0\nyield\n",
        context,
    );
    let tooltip = fixture
        .analysis
        .hints
        .iter()
        .find_map(|hint| hint.tooltip.clone())
        .expect("a cycle hint");
    let start = tooltip.rfind(" (").expect("the budget part");
    tooltip[start + 1..].to_string()
}

#[test]
fn the_tooltip_names_where_the_budget_came_from() {
    // The default budget is not "from the project settings".
    assert_eq!(
        budget_tooltip(10000, Some("the default")),
        "(the budget is 10000 by default)."
    );
    assert_eq!(
        budget_tooltip(10, Some("gloc.toml:1:16")),
        "(the budget is 10, from gloc.toml:1:16)."
    );
    assert_eq!(
        budget_tooltip(50, Some("editor setting gloc.cycleBudget")),
        "(the budget is 50, from editor setting gloc.cycleBudget)."
    );
}

#[test]
fn the_budget_in_the_tooltip_comes_from_the_settings() {
    let context = Context {
        cycle_budget: Some(10),
        ..context()
    };
    let fixture = Fixture::with_context(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r0\nyield\n",
        context,
    );
    let tooltip = fixture
        .analysis
        .hints
        .iter()
        .find_map(|hint| hint.tooltip.clone())
        .expect("a cycle hint");
    assert!(
        tooltip.ends_with("(the budget is 10, from the project settings)."),
        "{tooltip}"
    );
}
