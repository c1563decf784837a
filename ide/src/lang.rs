//! Dispatch from a document's language to its adapter (`gloc_lang`,
//! `gbasic_lang`), plus what both languages share: sensor documentation and
//! the guard that turns a panic in the core into a diagnostic.

use std::panic::{catch_unwind, AssertUnwindSafe};

use std::path::Path;

use gloc_engine::sensors::{Access, SensorId, SensorList};
use gloc_engine::{Diagnostic, Span};

use crate::analysis::{Analysis, Completion, CompletionKind, Context, TokenKind};
use crate::Language;
use crate::{gbasic_lang, gloc_lang, masterdata, mission};

/// Code of the diagnostic shown when the core panicked on a document.
pub const CODE_INTERNAL_ERROR: &str = gloc_engine::codes::settings::INTERNAL_ERROR;

pub fn analyze(language: Language, text: &str, context: &Context) -> Analysis {
    analyze_at(language, text, None, context)
}

/// As [`analyze`], for the document at `path`: a mission reads the `.ma` files
/// beside it (`../mafiles/`), as `gloc run` does.
pub fn analyze_at(
    language: Language,
    text: &str,
    path: Option<&Path>,
    context: &Context,
) -> Analysis {
    let outcome = catch_unwind(AssertUnwindSafe(|| match language {
        Language::Gloc => gloc_lang::analyze(text, context),
        Language::Gbasic => gbasic_lang::analyze(text, context),
        Language::Config => Analysis::default(),
        Language::Masterdata => masterdata::analyze(text),
        Language::Mission | Language::MissionArgs => match language.mission_file() {
            Some(kind) => mission::analyze(kind, text, path, &context.sensors),
            None => Analysis::default(),
        },
    }));
    outcome.unwrap_or_else(|_| Analysis {
        diagnostics: vec![Diagnostic::error(
            CODE_INTERNAL_ERROR,
            Span::default(),
            "internal error: the checker crashed on this text; please report it with the file",
        )],
        ..Analysis::default()
    })
}

/// Hover text for a keyword, instruction, directive or built-in.
pub fn word_markdown(language: Language, word: &str, kind: TokenKind) -> Option<String> {
    match language {
        Language::Gloc => gloc_lang::word_markdown(word, kind),
        Language::Gbasic => gbasic_lang::word_markdown(word, kind),
        Language::Config | Language::Mission | Language::MissionArgs | Language::Masterdata => None,
    }
}

/// Markdown describing a sensor: name, index, units, default, access, description.
pub fn sensor_markdown(list: &SensorList, id: SensorId) -> String {
    let Some(sensor) = list.get(id) else {
        return format!(
            "sensor index {} is not in the active sensor list ({} sensors)",
            id.0,
            list.len()
        );
    };
    let access = match sensor.access() {
        Access::ReadOnly => "read-only (a script may not write it)",
        Access::Factory => "factory setting (writable, with a warning)",
        Access::Writable => "writable",
    };
    let mut text = format!(
        "**{}** ({})\n\nsensor {} · {}",
        sensor.name, sensor.units, id.0, access
    );
    if let Some(default) = sensor.default {
        text.push_str(&format!(" · default {default:?}"));
    }
    if let (Some(min), Some(max)) = (sensor.min, sensor.max) {
        text.push_str(&format!(" · range {min:?} to {max:?}"));
    }
    if let Some(description) = &sensor.description {
        text.push_str("\n\n");
        text.push_str(description);
    }
    text
}

/// Completion items for sensors; `only_writable` where a store is expected.
pub fn sensor_completions(list: &SensorList, only_writable: bool) -> Vec<Completion> {
    list.iter()
        .filter(|(_, sensor)| !only_writable || sensor.access() != Access::ReadOnly)
        .map(|(id, sensor)| Completion {
            label: sensor.name.clone(),
            kind: CompletionKind::Sensor,
            detail: Some(format!(
                "sensor {} ({}){}",
                id.0,
                sensor.units,
                match sensor.access() {
                    Access::ReadOnly => ", read-only",
                    Access::Factory => ", factory",
                    Access::Writable => ", writable",
                }
            )),
            documentation: Some(sensor_markdown(list, id)),
            snippet: None,
            insert_text: None,
            filter_text: None,
            sort_text: None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sensor_markdown_names_index_units_and_access() {
        let list = SensorList::embedded();
        let id = list.lookup("m_depth").expect("m_depth");
        let text = sensor_markdown(&list, id);
        assert!(
            text.starts_with("**m_depth** (m)\n\nsensor 444 · read-only"),
            "{text}"
        );
        assert!(text.contains("Measured depth"), "{text}");
        assert!(sensor_markdown(&list, SensorId(99_999)).contains("not in the active sensor list"));
    }

    #[test]
    fn only_writable_sensors_where_a_store_is_expected() {
        let list = SensorList::embedded();
        let all = sensor_completions(&list, false);
        let writable = sensor_completions(&list, true);
        assert_eq!(all.len(), list.len());
        assert!(writable
            .iter()
            .all(|item| !item.label.starts_with("m_") && !item.label.starts_with("x_")));
        assert!(writable.iter().any(|item| item.label == "sci_ruhp_behs"));
        assert!(all.iter().any(|item| item.label == "m_depth"));
    }
}
