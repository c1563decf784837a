//! Sensor-list files (masterdata and `.cac`) as an editor language, for hover and
//! navigation: the engine's own parsers (`parse_masterdata`, `parse_cac_entries`,
//! the ones `--masterdata` uses) give the diagnostics, every sensor is a symbol at
//! its name (and every masterdata `behavior:` section one), and hover on a sensor's
//! line shows what scripts and missions see of it.

use gloc_engine::sensors::{
    looks_like_cac, parse_cac, parse_cac_entries, parse_masterdata, SensorList, SensorOrder,
};
use gloc_engine::{Occurrences, Span};

use crate::analysis::{Analysis, Symbol, SymbolKind};
use crate::lang::sensor_markdown;

/// A sensor or behavior section and where its name is.
struct Entry {
    name: String,
    kind: SymbolKind,
    name_span: Span,
    line_span: Span,
    detail: String,
}

/// Diagnostics and symbols of a masterdata or `.cac` text (a `.cac` list is told
/// by its content, its first line starting `s:`, as `--masterdata` tells it).
pub fn analyze(text: &str) -> Analysis {
    let (_, diagnostics) = parse(text);
    let symbols = entries(text)
        .into_iter()
        .map(|entry| Symbol {
            name: entry.name,
            kind: entry.kind,
            occurrences: Occurrences::defined_at(entry.name_span),
            extent: entry.line_span,
            detail: entry.detail,
            renamable: false,
        })
        .collect();
    Analysis {
        diagnostics,
        symbols,
        ..Analysis::default()
    }
}

/// Hover on a sensor's line: the sensor as the list describes it (index, units,
/// default, access, the masterdata comment), with the span of its name.
pub fn hover(text: &str, offset: usize) -> Option<(Span, String)> {
    let entry = entries(text).into_iter().find(|entry| {
        entry.kind == SymbolKind::Sensor
            && entry.line_span.start as usize <= offset
            && offset <= entry.line_span.end as usize
    })?;
    let (list, _) = parse(text);
    let id = list.lookup(&entry.name)?;
    Some((entry.name_span, sensor_markdown(&list, id)))
}

fn parse(text: &str) -> (SensorList, Vec<gloc_engine::Diagnostic>) {
    if looks_like_cac(text) {
        parse_cac(text)
    } else {
        parse_masterdata(text, SensorOrder::default())
    }
}

fn entries(text: &str) -> Vec<Entry> {
    let lines = line_spans(text);
    if looks_like_cac(text) {
        let (entries, _) = parse_cac_entries(text);
        return entries
            .into_iter()
            .map(|entry| Entry {
                line_span: lines
                    .get((entry.line as usize).saturating_sub(1))
                    .copied()
                    .unwrap_or(entry.name_span),
                detail: format!("sensor {} ({})", entry.index, entry.units),
                name: entry.name,
                kind: SymbolKind::Sensor,
                name_span: entry.name_span,
            })
            .collect();
    }
    let (list, _) = parse_masterdata(text, SensorOrder::default());
    let named = |line: u32, name: &str, after: &str| -> Option<(Span, Span)> {
        let line_span = *lines.get((line as usize).checked_sub(1)?)?;
        let line_text = text.get(line_span.range())?;
        let keyword = line_text.find(after)? + after.len();
        let start = keyword + line_text[keyword..].find(name)?;
        let name_start = line_span.start as usize + start;
        Some((Span::new(name_start, name_start + name.len()), line_span))
    };
    let sensors = list.iter().filter_map(|(id, sensor)| {
        let (name_span, line_span) = named(sensor.line, &sensor.name, "sensor:")?;
        Some(Entry {
            name: sensor.name.clone(),
            kind: SymbolKind::Sensor,
            name_span,
            line_span,
            detail: format!("sensor {} ({})", id.0, sensor.units),
        })
    });
    let behaviors = list.behavior_defaults().iter().filter_map(|behavior| {
        let (name_span, line_span) = named(behavior.line, &behavior.name, "behavior:")?;
        Some(Entry {
            name: behavior.name.clone(),
            kind: SymbolKind::Behavior,
            name_span,
            line_span,
            detail: format!("{} default arguments", behavior.args.len()),
        })
    });
    let mut all: Vec<Entry> = sensors.chain(behaviors).collect();
    all.sort_by_key(|entry| entry.name_span.start);
    all
}

/// Each line's span, without its line end.
fn line_spans(text: &str) -> Vec<Span> {
    let mut spans = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let content = line.trim_end_matches(['\n', '\r']);
        spans.push(Span::new(offset, offset + content.len()));
        offset += line.len();
    }
    spans
}

#[cfg(test)]
mod tests {
    use super::*;

    const MASTERDATA: &str = "# a masterdata extract\nsensor: m_depth(m) 0   # measured depth\n  sensor: u_cycle_time(sec) 4.0\nbehavior: yo\n  b_arg: d_target_depth(m) 12\n";

    #[test]
    fn sensors_and_behavior_sections_are_symbols_at_their_names() {
        let analysis = analyze(MASTERDATA);
        let symbols: Vec<_> = analysis
            .symbols
            .iter()
            .map(|symbol| {
                (
                    symbol.name.as_str(),
                    symbol.kind,
                    symbol.occurrences.definition,
                    symbol.detail.as_str(),
                )
            })
            .collect();
        // m_depth: line 2 starts at 23, the name at 23 + 8; u_cycle_time: line 3 starts at
        // 23 + 40 = 63, the name at 63 + 10; yo: line 4 starts at 63 + 32 = 95, the name at 95 + 10.
        assert_eq!(
            symbols,
            vec![
                (
                    "m_depth",
                    SymbolKind::Sensor,
                    Some(Span::new(31, 38)),
                    "sensor 0 (m)"
                ),
                (
                    "u_cycle_time",
                    SymbolKind::Sensor,
                    Some(Span::new(73, 85)),
                    "sensor 1 (sec)"
                ),
                (
                    "yo",
                    SymbolKind::Behavior,
                    Some(Span::new(105, 107)),
                    "1 default arguments"
                ),
            ]
        );
    }

    #[test]
    fn hover_on_a_sensor_line_shows_the_files_own_description() {
        let offset = MASTERDATA.find("0   #").expect("the default");
        let (span, markdown) = hover(MASTERDATA, offset).expect("hover");
        assert_eq!(span, Span::new(31, 38));
        assert!(
            markdown.starts_with("**m_depth** (m)\n\nsensor 0 · read-only"),
            "{markdown}"
        );
        assert!(markdown.contains("measured depth"), "{markdown}");
        assert_eq!(hover(MASTERDATA, 2), None);
    }

    #[test]
    fn a_cac_list_is_told_by_its_content() {
        let cac = "s: T    0    0 8 m_present_time timestamp\ns: F    1   -1 4 m_depth m\n";
        let analysis = analyze(cac);
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
        let names: Vec<_> = analysis
            .symbols
            .iter()
            .map(|symbol| symbol.name.as_str())
            .collect();
        assert_eq!(names, ["m_present_time", "m_depth"]);
        // `m_depth` on line 2 (from byte 42) at 42 + 17.
        assert_eq!(
            analysis.symbols[1].occurrences.definition,
            Some(Span::new(59, 66))
        );
        let (span, markdown) = hover(cac, 45).expect("hover");
        assert_eq!(span, Span::new(59, 66));
        assert!(
            markdown.starts_with("**m_depth** (m)\n\nsensor 1"),
            "{markdown}"
        );
    }

    #[test]
    fn no_text_and_no_cursor_makes_it_panic() {
        for text in [
            "",
            "s:",
            "sensor:",
            "sensor: é(m",
            "s: T 1 2 3 𝄞 m\nsensor: x(m) 1\n",
            "behavior:\n b_arg: x(m)\n",
        ] {
            let _ = analyze(text);
            for offset in 0..=text.len() + 2 {
                let _ = hover(text, offset);
            }
        }
    }

    #[test]
    fn bad_lines_are_the_parsers_diagnostics() {
        let analysis = analyze("sensor: broken\nsensor: ok(m) 1\n");
        assert_eq!(analysis.diagnostics.len(), 1, "{:?}", analysis.diagnostics);
        assert_eq!(analysis.symbols.len(), 1);
    }
}
