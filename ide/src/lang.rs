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
/// by the glider's file rules (`gloc_mission::files`), as `gloc run` does.
pub fn analyze_at(
    language: Language,
    text: &str,
    path: Option<&Path>,
    context: &Context,
) -> Analysis {
    // The CLI's cap, for every language and every editor feature (tokens, symbols,
    // folding): a document over it is one E0013 error and nothing else (semantic
    // tokens of a 16.8 MB one-line document took 3.6 GB).
    let too_large = match language {
        Language::Gloc => gloc_compiler::source_too_large(text, gloc_compiler::Language::Gloc),
        Language::Gbasic => gloc_compiler::source_too_large(text, gloc_compiler::Language::Gbasic),
        _ => gloc_engine::gloc::source_too_large(text),
    };
    if let Some(too_large) = too_large {
        return Analysis {
            diagnostics: vec![too_large],
            ..Analysis::default()
        };
    }
    let outcome = catch_unwind(AssertUnwindSafe(|| match language {
        Language::Gloc => gloc_lang::analyze(text, context),
        Language::Gbasic => gbasic_lang::analyze(text, context),
        Language::Config => Analysis::default(),
        Language::Masterdata => masterdata::analyze(text),
        Language::Mission | Language::MissionArgs => match language.mission_file() {
            Some(kind) => mission::analyze(kind, text, path, context),
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
    if let Some(range) = sensor.allowed.range_text() {
        text.push_str(&format!(" · range {range}"));
    }
    if let Some(choices) = sensor.allowed.choices_text() {
        text.push_str(&format!(" · one of {choices}"));
    }
    if let Some(description) = &sensor.description {
        text.push_str("\n\n");
        text.push_str(description);
    }
    text
}

/// Completion items for sensors. Where a store goes (`store`), read-only sensors
/// stay findable but rank after the writable ones and say they cannot be stored.
pub fn sensor_completions(list: &SensorList, store: bool) -> Vec<Completion> {
    list.iter()
        .map(|(id, sensor)| {
            let read_only = sensor.access() == Access::ReadOnly;
            let demoted = store && read_only;
            Completion {
                label: sensor.name.clone(),
                kind: CompletionKind::Sensor,
                detail: Some(format!(
                    "sensor {} ({}){}",
                    id.0,
                    sensor.units,
                    match sensor.access() {
                        Access::ReadOnly if demoted =>
                            format!(", {}", crate::completion::READ_ONLY_MARK),
                        Access::ReadOnly => ", read-only".to_string(),
                        Access::Factory => ", factory".to_string(),
                        Access::Writable => ", writable".to_string(),
                    }
                )),
                documentation: Some(sensor_markdown(list, id)),
                insert: None,
                filter_text: None,
                // After names, built-ins and keywords; demoted ones last.
                sort_text: Some(format!("{}{}", if demoted { 9 } else { 5 }, sensor.name)),
            }
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
    fn sensor_markdown_gives_a_range_with_one_end_and_the_choices() {
        // Before, only a range with both ends was shown, in Rust's debug form.
        let text = "sensor: u_min_only(m) 5 #! min = 1\n\
                    sensor: c_mode(enum) 1 #! min = 0; max = 4; choices=c_mode([0, 1, 4])\n";
        let (list, diagnostics) = gloc_engine::sensors::parse_masterdata(
            text,
            gloc_engine::sensors::SensorOrder::FileOrder,
        );
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        let hover = |name| sensor_markdown(&list, list.lookup(name).expect(name));
        assert!(
            hover("u_min_only").ends_with("· default 5.0 · range at least 1"),
            "{}",
            hover("u_min_only")
        );
        assert!(
            hover("c_mode").ends_with("· default 1.0 · range 0 to 4 · one of 0, 1, 4"),
            "{}",
            hover("c_mode")
        );
    }

    #[test]
    fn read_only_sensors_are_marked_and_demoted_where_a_store_goes() {
        let list = SensorList::embedded();
        let read = sensor_completions(&list, false);
        let store = sensor_completions(&list, true);
        assert_eq!(read.len(), list.len());
        assert_eq!(store.len(), list.len());
        let find = |items: &[Completion], name: &str| {
            items
                .iter()
                .find(|item| item.label == name)
                .cloned()
                .expect(name)
        };
        // m_depth is read-only (Access from the masterdata's `m_` prefix).
        let depth = find(&store, "m_depth");
        assert_eq!(depth.sort_text.as_deref(), Some("9m_depth"));
        assert!(depth
            .detail
            .as_deref()
            .is_some_and(|detail| detail.ends_with(crate::completion::READ_ONLY_MARK)));
        assert_eq!(
            find(&read, "m_depth").sort_text.as_deref(),
            Some("5m_depth")
        );
        let behs = find(&store, "sci_ruhp_behs");
        assert_eq!(behs.sort_text.as_deref(), Some("5sci_ruhp_behs"));
    }
}
