//! Code lens figures: for each label's section, the control cycles that start in
//! it (after the first instruction or a `yield`) and the worst case of them, from
//! the checker's cycle analysis (`Analysis::cycles`).

use gloc_engine::gloc::Bound;
use gloc_engine::Span;

use crate::analysis::{Analysis, SymbolKind};

/// One label's figure.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LabelCycles {
    pub label: String,
    /// The label's name where it is defined (where the lens goes).
    pub definition: Span,
    /// How many control cycles start in the label's section.
    pub starting: usize,
    /// The most instructions one of them can execute (`None`: none starts here).
    pub worst: Option<Bound>,
}

impl LabelCycles {
    /// The lens text.
    pub fn title(&self) -> String {
        let cycles = if self.starting == 1 {
            "1 cycle starts here".to_string()
        } else {
            format!("{} cycles start here", self.starting)
        };
        match self.worst {
            None => "no cycle starts here (no yield in this section)".to_string(),
            Some(Bound::Finite(count)) => format!("≤ {count} instr per cycle ({cycles})"),
            Some(Bound::Unbounded) => format!("unbounded cycle ({cycles}): a loop without yield"),
        }
    }
}

/// Every defined label with the cycles that start in its section, in text order.
pub fn label_cycles(analysis: &Analysis) -> Vec<LabelCycles> {
    let mut labels: Vec<LabelCycles> = analysis
        .symbols
        .iter()
        .filter(|symbol| symbol.kind == SymbolKind::Label)
        .filter_map(|symbol| {
            let definition = symbol.occurrences.definition?;
            let section = symbol.extent.cover(definition);
            let inside: Vec<Bound> = analysis
                .cycles
                .iter()
                .filter(|cycle| {
                    section.start as usize <= cycle.offset && cycle.offset <= section.end as usize
                })
                .map(|cycle| cycle.worst)
                .collect();
            Some(LabelCycles {
                label: symbol.name.clone(),
                definition,
                starting: inside.len(),
                worst: inside.iter().copied().max(),
            })
        })
        .collect();
    labels.sort_by_key(|label| label.definition.start);
    labels
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use gloc_engine::sensors::SensorList;

    use super::*;
    use crate::analysis::Context;

    fn analyze(language: crate::Language, text: &str) -> Analysis {
        let context = Context::new(Arc::new(SensorList::embedded()));
        crate::lang::analyze(language, text, &context)
    }

    #[test]
    fn gbasic_label_sections_count_their_cycles_by_hand() {
        // `top`: `x = 1` (a store: ldi, store), `yield`. `spin`: a `while` with a
        // yield inside and a `goto`. Each section holds exactly one yield, so one
        // cycle starts in each; the first cycle starts before `top`'s yield, on
        // `x = 1`, also inside `top`.
        let text = "dim x as integer\nlabel: top\nx = 1\nyield\nlabel: spin\nwhile 1\n  yield\nwend\ngoto top\n";
        let analysis = analyze(crate::Language::Gbasic, text);
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
        let labels = label_cycles(&analysis);
        let names: Vec<(&str, usize)> = labels
            .iter()
            .map(|label| (label.label.as_str(), label.starting))
            .collect();
        assert_eq!(names, [("top", 2), ("spin", 1)]);
        assert!(labels
            .iter()
            .all(|label| matches!(label.worst, Some(Bound::Finite(_)))));
        // The figures are the hints' figures (one analysis, two views).
        for cycle in &analysis.cycles {
            let Bound::Finite(count) = cycle.worst else {
                panic!("unbounded")
            };
            assert!(analysis.hints.iter().any(|hint| hint.offset == cycle.offset
                && hint.label.ends_with(&format!("≤ {count} instr"))));
        }
    }

    #[test]
    fn a_section_without_yield_says_so_and_unbounded_is_worst() {
        let text = "label: a\nyield\nlabel: b\ngoto a\n";
        let analysis = analyze(crate::Language::Gbasic, text);
        let labels = label_cycles(&analysis);
        assert_eq!(labels[1].worst, None);
        assert_eq!(
            labels[1].title(),
            "no cycle starts here (no yield in this section)"
        );
        let figure = LabelCycles {
            label: "x".into(),
            definition: Span::default(),
            starting: 2,
            worst: [Bound::Finite(7), Bound::Unbounded].into_iter().max(),
        };
        assert_eq!(
            figure.title(),
            "unbounded cycle (2 cycles start here): a loop without yield"
        );
        let figure = LabelCycles {
            worst: Some(Bound::Finite(12)),
            starting: 1,
            ..figure
        };
        assert_eq!(figure.title(), "≤ 12 instr per cycle (1 cycle starts here)");
    }
}
