//! Mission files (`.mi`) and mission argument files (`.ma`) as editor languages:
//! diagnostics from the mission crate's parser (`gloc_mission::mission`, the S-codes
//! `gloc run` prints), behaviors as symbols and folds, completion and hover from the
//! behavior table (`gloc_mission::behaviors::BehaviorTable`: the active masterdata's
//! `behavior:` sections, else the embedded release table), go to
//! the `.ma` file an `args_from_file` loads, and a formatter that keeps the layout.
//!
//! Completion and hover look at the cursor's line only to know which keyword it
//! follows (`b_arg:`, `behavior:`, `sensor:`); what the line means comes from the parser.

use std::path::{Path, PathBuf};

use gloc_engine::sensors::SensorList;
use gloc_engine::{Diagnostic, Span};
use gloc_mission::behaviors::{ArgInfo, BehaviorInfo, BehaviorTable};
use gloc_mission::mission::{ma_file_name, Mission};
use gloc_mission::{Disk, LoadOptions};

use crate::analysis::{Analysis, Completion, CompletionKind, Context, Symbol, SymbolKind};
use crate::lang::{sensor_completions, sensor_markdown};

/// Which of the two mission languages a document is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MissionFile {
    /// A `.mi` mission: `sensor:`, `behavior:` and `b_arg:` lines.
    Mission,
    /// A `.ma` argument file: `behavior_name=` and `<start:b_arg>` sections.
    Args,
}

/// Parses the document as `gloc run` would: a `.mi` loads its `.ma` files from
/// disk by the glider's file rules (`gloc_mission::files`: `mafiles/` beside `missions/`
/// in any case, then beside the `.mi`), reading the document itself from `text`; its
/// behaviors are those of `sensors`' masterdata (else the embedded release table).
/// Without a path (an unsaved buffer) a `.mi` loads no `.ma` files. `mafiles`, when
/// given, is searched first (gloc.toml's `mafiles`).
pub fn parse(
    kind: MissionFile,
    text: &str,
    path: Option<&Path>,
    sensors: &SensorList,
    mafiles: Option<&Path>,
) -> Mission {
    let options = LoadOptions {
        table: Some(BehaviorTable::for_sensors(sensors)),
        mafiles: mafiles.map(Path::to_path_buf),
    };
    match (kind, path) {
        (MissionFile::Args, _) => {
            Mission::parse_args_file_with(path.unwrap_or(Path::new("untitled.ma")), text, &options)
        }
        (MissionFile::Mission, None) => Mission::load_text(
            Path::new("untitled.mi"),
            text.to_string(),
            &options,
            &mut NoFiles,
        ),
        (MissionFile::Mission, Some(path)) => {
            Mission::load_text(path, text.to_string(), &options, &mut Disk)
        }
    }
}

/// An unsaved buffer's files: none (its `args_from_file` lines cannot be followed).
struct NoFiles;

impl gloc_mission::MissionFiles for NoFiles {
    fn read(&mut self, path: &Path) -> std::io::Result<String> {
        Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            format!(
                "the mission is not saved, so `{}` has no folder to be found in",
                path.display()
            ),
        ))
    }
}

/// Diagnostics, behaviors (symbols) and folds of a mission document. A problem in
/// a `.ma` file the mission loads is shown on the `args_from_file` line that
/// loaded it, its message starting with the file, line and column. `.ma` files are
/// found as [`parse`] finds them.
pub fn analyze(
    kind: MissionFile,
    text: &str,
    path: Option<&Path>,
    sensors: &SensorList,
    mafiles: Option<&Path>,
) -> Analysis {
    let mission = parse(kind, text, path, sensors, mafiles);
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    let entries = mission
        .diagnostics
        .iter()
        .cloned()
        .chain(mission.check(sensors));
    for entry in entries {
        if entry.file == 0 {
            diagnostics.push(entry.diagnostic);
            continue;
        }
        let Some(source) = mission.sources.get(entry.file) else {
            continue;
        };
        let (_, line, column) = mission.line_col(entry.file, entry.diagnostic.span);
        let name = source.path.file_name().map_or_else(
            || source.path.display().to_string(),
            |name| name.to_string_lossy().into_owned(),
        );
        let mut moved = entry.diagnostic;
        moved.message = format!("{name}:{line}:{column}: {}", moved.message);
        moved.span = source.loaded_at.unwrap_or_default();
        moved.labels.clear();
        diagnostics.push(moved);
    }
    let blocks = behavior_blocks(&mission, text);
    let symbols = blocks
        .iter()
        .map(|block| Symbol {
            name: block.name.clone(),
            kind: SymbolKind::Behavior,
            definition: Some(block.name_span),
            extent: block.extent,
            references: Vec::new(),
            detail: block.detail.clone(),
            renamable: false,
        })
        .collect();
    let folds = blocks
        .iter()
        .map(|block| block.extent)
        .chain(
            mission
                .sections
                .iter()
                .filter(|section| section.file == 0)
                .map(|section| section.span),
        )
        .collect();
    Analysis {
        diagnostics,
        symbols,
        folds,
        ..Analysis::default()
    }
}

/// Completion at `offset`: keywords at the start of a line, behavior names after
/// `behavior:`, the current behavior's arguments after `b_arg:` (inserted with
/// their units and default), sensors after `sensor:`.
pub fn completions(
    kind: MissionFile,
    text: &str,
    offset: usize,
    sensors: &SensorList,
) -> Vec<Completion> {
    let Some(line) = CursorLine::at(text, offset) else {
        return Vec::new();
    };
    match (line.keyword.as_deref(), line.word_index) {
        (None, 0) => keywords(kind, line.typed_bracket),
        (Some("behavior:"), 1) if kind == MissionFile::Mission => {
            BehaviorTable::for_sensors(sensors)
                .behaviors()
                .iter()
                .map(|behavior| Completion {
                    label: behavior.name.clone(),
                    kind: CompletionKind::Function,
                    detail: Some(format!("behavior, {} arguments", behavior.args.len())),
                    documentation: Some(behavior.doc.clone()),
                    snippet: None,
                    insert_text: None,
                    filter_text: None,
                    sort_text: None,
                })
                .collect()
        }
        (Some("b_arg:"), 1) => {
            let mission = parse_alone(kind, text, sensors);
            let Some(behavior) = behavior_at(&mission, kind, offset) else {
                return Vec::new();
            };
            behavior
                .args
                .iter()
                .map(|arg| Completion {
                    label: arg.name.clone(),
                    kind: CompletionKind::Variable,
                    detail: Some(format!(
                        "({}) default {}",
                        arg.units,
                        arg.default.unwrap_or(0.0)
                    )),
                    documentation: Some(arg_markdown(&behavior, arg)),
                    snippet: Some(format!(
                        "{}({}) ${{1:{}}}",
                        arg.name,
                        arg.units,
                        arg.default.unwrap_or(0.0)
                    )),
                    insert_text: None,
                    filter_text: None,
                    sort_text: None,
                })
                .collect()
        }
        (Some("sensor:"), 1) if kind == MissionFile::Mission => sensor_completions(sensors, true),
        _ => Vec::new(),
    }
}

/// Hover at `offset`: the span of the word under the cursor and its markdown (a
/// behavior, an argument of the behavior it is under, a sensor, `args_from_file`).
pub fn hover(
    kind: MissionFile,
    text: &str,
    offset: usize,
    sensors: &SensorList,
) -> Option<(Span, String)> {
    let line = CursorLine::at_word(text, offset)?;
    let word_span = line.word?;
    let word = text.get(word_span.range())?;
    let mission = parse_alone(kind, text, sensors);
    let markdown = match (line.keyword.as_deref(), line.word_index) {
        (Some("behavior:"), 1) | (Some("behavior_name="), 0) => {
            let table = mission.table();
            let behavior = table.behavior(word)?;
            format!(
                "**behavior {}** · {} arguments{}\n\n{}\n\nFrom {}.",
                behavior.name,
                behavior.args.len(),
                if behavior.is_simulated() {
                    ""
                } else {
                    " · not flown by gloc's simulator"
                },
                behavior.doc,
                table.source_name()
            )
        }
        (Some("b_arg:"), 1) => {
            let behavior = behavior_at(&mission, kind, offset)?;
            if word.eq_ignore_ascii_case("args_from_file") {
                let number = line.value?;
                format!(
                    "**args_from_file**(enum)\n\nLoads the behavior's arguments from `mafiles/{}` (beside the `missions` folder).",
                    ma_file_name(&behavior.name, number as i64)
                )
            } else {
                match behavior.arg(word) {
                    Some(arg) => arg_markdown(&behavior, arg),
                    None => format!(
                        "`{word}` is not an argument of behavior `{}`: the glider ignores it",
                        behavior.name
                    ),
                }
            }
        }
        (Some("sensor:"), 1) => {
            let id = sensors.lookup(word)?;
            sensor_markdown(sensors, id)
        }
        _ => return None,
    };
    Some((word_span, markdown))
}

/// The `.ma` file that the `args_from_file` line under `offset` loads, when the
/// mission (at `path`) loaded it.
pub fn definition(text: &str, offset: usize, path: &Path, context: &Context) -> Option<PathBuf> {
    links(text, path, context)
        .into_iter()
        .find(|(at, _)| at.start as usize <= offset && offset <= at.end as usize)
        .map(|(_, target)| target)
}

/// Every `args_from_file` line of the mission at `path` with the `.ma` file it
/// loaded (for document links and go to definition), found as `gloc run` finds it
/// (the context's `mafiles` first, its sensor list's behaviors): only files that
/// exist, as the file system names them.
pub fn links(text: &str, path: &Path, context: &Context) -> Vec<(Span, PathBuf)> {
    let mission = parse(
        MissionFile::Mission,
        text,
        Some(path),
        &context.sensors,
        context.mafiles.as_deref(),
    );
    let mut links: Vec<(Span, PathBuf)> = mission
        .sources
        .iter()
        .filter_map(|source| {
            let at = source.loaded_at?;
            // `missions/../mafiles/yo10.ma` as the file it is.
            let target =
                std::fs::canonicalize(&source.path).unwrap_or_else(|_| source.path.clone());
            Some((at, target))
        })
        .collect();
    links.sort_by_key(|(at, _)| at.start);
    links
}

/// The text with the glider's layout kept (indentation, alignment, comments and
/// blank lines as written): trailing spaces and tabs are removed and the file
/// ends with one line end. `None` for a file that is not text (a NUL byte).
pub fn format(text: &str) -> Option<String> {
    if text.contains('\0') {
        return None;
    }
    let mut out = String::with_capacity(text.len() + 1);
    for line in text.split_inclusive('\n') {
        out.push_str(
            line.trim_end_matches(['\n', '\r'])
                .trim_end_matches([' ', '\t']),
        );
        if line.ends_with('\n') {
            out.push('\n');
        }
    }
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    Some(out)
}

/// Markdown for an argument: name, units, the behavior and its default, the doc.
fn arg_markdown(behavior: &BehaviorInfo, arg: &ArgInfo) -> String {
    let range = arg
        .range
        .text()
        .map(|range| format!(" · {range}"))
        .unwrap_or_default();
    let range = match &arg.choices {
        Some(choices) => format!(
            "{range} · one of {}",
            choices
                .iter()
                .map(|choice| choice.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        None => range,
    };
    let default = arg
        .default
        .map_or_else(|| "none (0)".to_string(), |value| value.to_string());
    format!(
        "**{}**({}) · {} · default {default}{range}\n\n{}",
        arg.name, arg.units, behavior.name, arg.doc
    )
}

/// The keywords that start a line. After a typed `<` the `<…>` keywords are inserted
/// without it: a client replaces the word before the cursor, and `<` is not part of one.
fn keywords(kind: MissionFile, typed_bracket: bool) -> Vec<Completion> {
    let words: &[(&str, &str)] = match kind {
        MissionFile::Mission => &[
            (
                "behavior:",
                "A behavior, highest priority first: `behavior: NAME`.",
            ),
            (
                "b_arg:",
                "An argument of the behavior above: `b_arg: NAME(UNITS) VALUE`.",
            ),
            (
                "sensor:",
                "A sensor's initial value: `sensor: NAME(UNITS) VALUE`.",
            ),
        ],
        MissionFile::Args => &[
            ("behavior_name=", "The behavior these arguments are for."),
            ("<start:b_arg>", "Opens the arguments."),
            ("b_arg:", "An argument: `b_arg: NAME(UNITS) VALUE`."),
            ("<end:b_arg>", "Closes the arguments."),
            (
                "<start:waypoints>",
                "Opens a waypoint list (`LON LAT` lines, DDDMM.MMMM).",
            ),
            ("<end:waypoints>", "Closes the waypoint list."),
        ],
    };
    words
        .iter()
        .map(|(word, doc)| Completion {
            label: word.to_string(),
            kind: CompletionKind::Keyword,
            detail: None,
            documentation: Some(doc.to_string()),
            snippet: None,
            insert_text: Some(if word.ends_with(':') {
                format!("{word} ")
            } else if typed_bracket {
                word.trim_start_matches('<').to_string()
            } else {
                word.to_string()
            }),
            filter_text: None,
            sort_text: None,
        })
        .collect()
}

/// The document parsed on its own (no `.ma` files read): enough to know which
/// behavior a line belongs to.
fn parse_alone(kind: MissionFile, text: &str, sensors: &SensorList) -> Mission {
    parse(kind, text, None, sensors, None)
}

/// The behavior whose block holds `offset`: the last `behavior:` line before it
/// (a `.ma` file has one, from `behavior_name=`). `None` under an unknown behavior.
fn behavior_at(mission: &Mission, kind: MissionFile, offset: usize) -> Option<BehaviorInfo> {
    let spec = match kind {
        MissionFile::Args => mission.behaviors.first(),
        MissionFile::Mission => mission
            .behaviors
            .iter()
            .rev()
            .find(|spec| spec.at.file == 0 && (spec.at.span.start as usize) < offset),
    }?;
    mission.table().behavior(&spec.name).cloned()
}

/// A behavior as the outline shows it.
struct Block {
    name: String,
    name_span: Span,
    /// From the `behavior:` line to its last argument line (comments after it excluded).
    extent: Span,
    detail: String,
}

fn behavior_blocks(mission: &Mission, text: &str) -> Vec<Block> {
    let specs: Vec<_> = mission
        .behaviors
        .iter()
        .filter(|spec| spec.at.file == 0 && spec.defined)
        .collect();
    let starts: Vec<usize> = mission
        .behaviors
        .iter()
        .filter(|spec| spec.at.file == 0)
        .map(|spec| spec.at.span.start as usize)
        .collect();
    specs
        .iter()
        .map(|spec| {
            let start = spec.at.span.start as usize;
            let end_of_name = spec.at.span.end as usize;
            let next = starts
                .iter()
                .copied()
                .find(|&other| other > start)
                .unwrap_or(text.len());
            let from_file = mission
                .sources
                .iter()
                .filter(|source| {
                    source
                        .loaded_at
                        .is_some_and(|at| (at.start as usize) > start && (at.start as usize) < next)
                })
                .filter_map(|source| source.path.file_name())
                .map(|name| name.to_string_lossy().into_owned())
                .collect::<Vec<_>>();
            let mut detail = format!(
                "{} argument{}",
                spec.args.len(),
                if spec.args.len() == 1 { "" } else { "s" }
            );
            if !from_file.is_empty() {
                detail.push_str(&format!(" (from {})", from_file.join(", ")));
            }
            Block {
                name: spec.name.clone(),
                name_span: Span::new(end_of_name.saturating_sub(spec.name.len()), end_of_name),
                extent: Span::new(start, last_code_end(text, start, next).max(end_of_name)),
                detail,
            }
        })
        .collect()
}

/// The end of the last line between `start` and `end` with something besides a
/// comment, so a block's fold leaves the comments above the next block out.
fn last_code_end(text: &str, start: usize, end: usize) -> usize {
    let Some(region) = text.get(start..end) else {
        return start;
    };
    let mut last = start;
    let mut offset = start;
    for line in region.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or_default();
        if !code.trim().is_empty() {
            last = offset + code.trim_end().len();
        }
        offset += line.len();
    }
    last
}

/// The cursor's line, split into whitespace-separated words before any `#`.
struct CursorLine {
    /// The line's first word when it is a keyword, lower-cased (`b_arg:`), or
    /// `behavior_name=` for a `behavior_name=NAME` line.
    keyword: Option<String>,
    /// Which word the cursor is in or after (0 the first). For `behavior_name=NAME`
    /// the name is word 0.
    word_index: usize,
    /// The name word under the cursor, without a `(units)` part.
    word: Option<Span>,
    /// The value of a `b_arg:`/`sensor:` line, when it reads as a number.
    value: Option<f64>,
    /// For completion: the word being typed starts with `<`.
    typed_bracket: bool,
}

impl CursorLine {
    /// For completion: the words before the cursor; `None` inside a comment.
    fn at(text: &str, offset: usize) -> Option<CursorLine> {
        let offset = floor_boundary(text, offset);
        let line_start = text[..offset].rfind('\n').map_or(0, |at| at + 1);
        let before = &text[line_start..offset];
        if before.contains('#') {
            return None;
        }
        let words: Vec<&str> = before.split_whitespace().collect();
        let typing = !before.ends_with(char::is_whitespace) && !words.is_empty();
        let word_index = if typing { words.len() - 1 } else { words.len() };
        let keyword = words
            .first()
            .filter(|_| word_index > 0)
            .map(|word| word.to_ascii_lowercase())
            .filter(|word| word.ends_with(':'));
        Some(CursorLine {
            keyword,
            word_index,
            word: None,
            value: None,
            typed_bracket: typing && words.last().is_some_and(|word| word.starts_with('<')),
        })
    }

    /// For hover: the whole line, and the name under the cursor.
    fn at_word(text: &str, offset: usize) -> Option<CursorLine> {
        let offset = floor_boundary(text, offset);
        let line_start = text[..offset].rfind('\n').map_or(0, |at| at + 1);
        let line_end = text[offset..]
            .find('\n')
            .map_or(text.len(), |at| offset + at);
        let line = &text[line_start..line_end];
        let code = line.split('#').next().unwrap_or_default();
        if offset > line_start + code.len() {
            return None;
        }
        let is_name = |c: char| c.is_ascii_alphanumeric() || c == '_';
        let column = offset - line_start;
        let word_start = code[..column]
            .rfind(|c: char| !is_name(c))
            .map_or(0, |at| at + 1);
        let word_end = code[column..]
            .find(|c: char| !is_name(c))
            .map_or(code.len(), |at| column + at);
        let words: Vec<(usize, &str)> = code
            .split_whitespace()
            .map(|word| (word.as_ptr() as usize - code.as_ptr() as usize, word))
            .collect();
        let first = words.first()?;
        let lower = first.1.to_ascii_lowercase();
        let word_index = words
            .iter()
            .rposition(|(start, _)| *start <= word_start)
            .unwrap_or(0);
        let keyword = if lower.starts_with("behavior_name=") {
            if word_start != first.0 + "behavior_name=".len() {
                return None;
            }
            Some("behavior_name=".to_string())
        } else {
            // Only a word's leading name counts: not the `m` of `overdepth(m)`.
            if words.get(word_index).map(|(start, _)| *start) != Some(word_start) {
                return None;
            }
            Some(lower).filter(|word| word.ends_with(':'))
        };
        let value = words.last().and_then(|(_, word)| word.parse::<f64>().ok());
        (word_end > word_start).then_some(CursorLine {
            keyword,
            word_index,
            word: Some(Span::new(line_start + word_start, line_start + word_end)),
            value,
            typed_bracket: false,
        })
    }
}

fn floor_boundary(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

#[cfg(test)]
mod tests {
    use super::*;

    fn embedded_context() -> Context {
        Context::new(std::sync::Arc::new(SensorList::embedded()))
    }

    /// The text with its `$0` cursor marker removed, and the marker's offset.
    fn cursor(fixture: &str) -> (String, usize) {
        let offset = fixture.find("$0").expect("a $0 cursor marker");
        (fixture.replace("$0", ""), offset)
    }

    fn labels(kind: MissionFile, fixture: &str) -> Vec<String> {
        let (text, offset) = cursor(fixture);
        completions(kind, &text, offset, &SensorList::embedded())
            .into_iter()
            .map(|item| item.label)
            .collect()
    }

    fn hover_at(kind: MissionFile, fixture: &str) -> Option<(String, String)> {
        let (text, offset) = cursor(fixture);
        hover(kind, &text, offset, &SensorList::embedded())
            .map(|(span, markdown)| (text[span.range()].to_string(), markdown))
    }

    /// The release-layout masterdata fixture as the active sensor list.
    fn fixture_masterdata() -> SensorList {
        let text = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../tests/fixtures/sensors/release-layout.masterdata"),
        )
        .expect("fixture");
        gloc_engine::sensors::parse_masterdata(&text, gloc_engine::sensors::SensorOrder::FileOrder)
            .0
    }

    #[test]
    fn with_a_masterdata_active_its_behavior_sections_drive_the_editor() {
        let sensors = fixture_masterdata();
        // `behavior:` offers the fixture's four sections and gloc's hook and gloc.
        let (text, offset) = cursor("behavior: $0");
        let behaviors: Vec<String> = completions(MissionFile::Mission, &text, offset, &sensors)
            .into_iter()
            .map(|item| item.label)
            .collect();
        assert_eq!(
            behaviors,
            ["abend", "yo", "drift_at_depth", "surface", "hook", "gloc"]
        );
        // yo's arguments are the section's four, with its default and limits.
        let (text, offset) = cursor("behavior: yo\n  b_arg: $0");
        let args = completions(MissionFile::Mission, &text, offset, &sensors);
        let names: Vec<&str> = args.iter().map(|item| item.label.as_str()).collect();
        assert_eq!(
            names,
            [
                "args_from_file",
                "d_target_depth",
                "c_target_depth",
                "num_half_cycles_to_do"
            ]
        );
        assert_eq!(
            args[1].documentation.as_deref(),
            Some("**d_target_depth**(m) · yo · default 42 · 1 to 1000\n\ndive to this depth")
        );
        // Hover on the behavior names the table it came from; diagnostics use it too.
        let (text, offset) = cursor("behavior: drift_at$0_depth\n");
        let (_, markdown) = hover(MissionFile::Mission, &text, offset, &sensors).expect("hover");
        assert!(
            markdown.starts_with("**behavior drift_at_depth** · 2 arguments · not flown")
                && markdown.ends_with("From the active masterdata."),
            "{markdown}"
        );
        let analysis = analyze(
            MissionFile::Mission,
            "behavior: yo\n  b_arg: d_target_depth(m) 2000\n",
            None,
            &sensors,
            None,
        );
        let codes: Vec<&str> = analysis.diagnostics.iter().map(|d| d.code).collect();
        assert_eq!(codes, ["S0120"]);
    }

    /// A folder `<temp>/<name>/{missions,mafiles}` with the given files.
    fn mission_folder(name: &str, files: &[(&str, &str)]) -> PathBuf {
        let root = gloc_testsupport::scratch_dir(&format!("ide-{name}"));
        for (path, text) in files {
            let path = root.join(path);
            std::fs::create_dir_all(path.parent().expect("a parent")).expect("mkdir");
            std::fs::write(&path, text).expect("write");
        }
        root
    }

    #[test]
    fn a_bad_value_is_the_simulators_s0015_on_the_value() {
        let text = "behavior: yo\n  b_arg: d_target_depth(m) deep\n";
        let analysis = analyze(
            MissionFile::Mission,
            text,
            None,
            &SensorList::embedded(),
            None,
        );
        assert_eq!(analysis.diagnostics.len(), 1, "{:?}", analysis.diagnostics);
        let diagnostic = &analysis.diagnostics[0];
        assert_eq!(diagnostic.code, "S0015");
        // `deep` starts after "behavior: yo\n" (13) + "  b_arg: d_target_depth(m) " (27).
        assert_eq!(diagnostic.span, Span::new(40, 44));
    }

    #[test]
    fn a_problem_in_a_loaded_ma_file_is_shown_on_its_args_from_file_line() {
        let mission =
            "behavior: yo\n  b_arg: args_from_file(enum) 3\nsensor: u_no_such_sensor(m) 1\n";
        let root = mission_folder(
            "ma-problem",
            &[
                ("missions/x.mi", mission),
                (
                    "mafiles/yo03.ma",
                    "behavior_name=yo\n<start:b_arg>\n b_arg: c_target_depth(m) x\n<end:b_arg>\n",
                ),
            ],
        );
        let path = root.join("missions/x.mi");
        let analysis = analyze(
            MissionFile::Mission,
            mission,
            Some(&path),
            &SensorList::embedded(),
            None,
        );
        let found: Vec<_> = analysis
            .diagnostics
            .iter()
            .map(|diagnostic| {
                (
                    diagnostic.code,
                    diagnostic.span,
                    diagnostic.message.as_str(),
                )
            })
            .collect();
        // The .ma's `x` is line 3, column 27; the args_from_file line is bytes 15..44;
        // u_no_such_sensor is bytes 53..69 (S0106, as `gloc run` checks it too).
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(found[0].0, "S0015");
        assert_eq!(found[0].1, Span::new(15, 44));
        assert_eq!(found[0].2, "yo03.ma:3:27: `x` is not a number");
        assert_eq!((found[1].0, found[1].1), ("S0106", Span::new(53, 69)));
        let _ = std::fs::remove_dir_all(root);
    }

    #[test]
    fn an_args_file_gets_its_own_diagnostics() {
        let text = "behavior_name=surface\n<start:b_arg>\nb_arg: gps_wait_time(s) 300\nb_arg: bogus(s) 1\n";
        let analysis = analyze(MissionFile::Args, text, None, &SensorList::embedded(), None);
        let codes: Vec<_> = analysis
            .diagnostics
            .iter()
            .map(|d| (d.code, d.span))
            .collect();
        // `b_arg: bogus(s) 1` (bytes 64..81) is unknown; the file ends inside the section
        // (an empty span at 81, the end of the last line).
        assert_eq!(
            codes,
            vec![("S0103", Span::new(64, 81)), ("S0025", Span::new(81, 81))]
        );
    }

    #[test]
    fn behaviors_are_symbols_and_folds_without_the_comments_after_them() {
        let text = "behavior: abend\n  b_arg: overdepth(m) 30\n# next\n\nbehavior: yo\nbehavior: teleport\n";
        let analysis = analyze(
            MissionFile::Mission,
            text,
            None,
            &SensorList::embedded(),
            None,
        );
        let symbols: Vec<_> = analysis
            .symbols
            .iter()
            .map(|symbol| {
                (
                    symbol.name.as_str(),
                    symbol.definition,
                    symbol.extent,
                    symbol.detail.as_str(),
                )
            })
            .collect();
        // abend: name 10..15, block to the end of `b_arg: overdepth(m) 30` (16 + 24 = 40);
        // yo: name 59..61 on a line of its own; the unknown behavior is no symbol.
        assert_eq!(
            symbols,
            vec![
                (
                    "abend",
                    Some(Span::new(10, 15)),
                    Span::new(0, 40),
                    "1 argument"
                ),
                (
                    "yo",
                    Some(Span::new(59, 61)),
                    Span::new(49, 61),
                    "0 arguments"
                ),
            ]
        );
        assert_eq!(analysis.folds, vec![Span::new(0, 40), Span::new(49, 61)]);
        let ma = "behavior_name=yo\n<start:b_arg>\nb_arg: d_target_depth(m) 5\n<end:b_arg>\n";
        let analysis = analyze(MissionFile::Args, ma, None, &SensorList::embedded(), None);
        assert_eq!(analysis.symbols.len(), 1);
        assert_eq!(analysis.symbols[0].definition, Some(Span::new(14, 16)));
        // The section: `<start:b_arg>` at 17 to the end of `<end:b_arg>` (ma.len() - 1).
        assert!(analysis
            .folds
            .contains(&Span::new(17, ma.len() as u32 as usize - 1)));
    }

    #[test]
    fn completion_by_place_on_the_line() {
        assert_eq!(
            labels(MissionFile::Mission, "$0"),
            ["behavior:", "b_arg:", "sensor:"]
        );
        // The 10.5 release masterdata's 19 behaviors, five more of SN 3614's, hook and gloc.
        assert_eq!(labels(MissionFile::Mission, "behavior: $0").len(), 26);
        assert!(labels(MissionFile::Mission, "behavior: y$0").contains(&"yo".to_string()));
        assert!(
            labels(MissionFile::Mission, "sensor: u_cyc$0").contains(&"u_cycle_time".to_string())
        );
        assert!(labels(MissionFile::Mission, "behavior: yo # b_arg: $0").is_empty());
        // Under an unknown behavior there is nothing to offer; after the name, nothing either.
        assert!(labels(MissionFile::Mission, "behavior: teleport\n  b_arg: $0").is_empty());
        assert!(labels(
            MissionFile::Mission,
            "behavior: yo\n  b_arg: d_target_depth(m) $0"
        )
        .is_empty());
        assert_eq!(
            labels(MissionFile::Args, "behavior_name=Yo\n<start:b_arg>\n$0"),
            [
                "behavior_name=",
                "<start:b_arg>",
                "b_arg:",
                "<end:b_arg>",
                "<start:waypoints>",
                "<end:waypoints>"
            ]
        );
    }

    #[test]
    fn a_typed_bracket_is_not_inserted_twice() {
        let insert = |fixture: &str| {
            let (text, offset) = cursor(fixture);
            completions(MissionFile::Args, &text, offset, &SensorList::embedded())
                .into_iter()
                .find(|item| item.label == "<end:b_arg>")
                .and_then(|item| item.insert_text)
        };
        // The client replaces `en` (the word before the cursor), so `<` must not come again.
        assert_eq!(
            insert("<start:b_arg>\n<en$0").as_deref(),
            Some("end:b_arg>")
        );
        assert_eq!(insert("<start:b_arg>\n$0").as_deref(), Some("<end:b_arg>"));
    }

    #[test]
    fn argument_completion_has_units_default_and_doc_of_the_behavior_above() {
        let (text, offset) =
            cursor("behavior: abend\n  b_arg: overdepth(m) 30\nbehavior: yo\n  b_arg: d_ta$0\n");
        let items = completions(MissionFile::Mission, &text, offset, &SensorList::embedded());
        // The 42 `b_arg:` lines of yo's section in the 10.5 release masterdata.
        assert_eq!(items.len(), 42);
        let depth = items
            .iter()
            .find(|item| item.label == "d_target_depth")
            .expect("d_target_depth");
        assert_eq!(depth.detail.as_deref(), Some("(m) default 12"));
        assert_eq!(depth.snippet.as_deref(), Some("d_target_depth(m) ${1:12}"));
        assert_eq!(
            depth.documentation.as_deref(),
            // `d_target_depth(m) 12  #! min = 3.0; max = 1000.0` in the masterdata.
            Some(
                "**d_target_depth**(m) · yo · default 12 · 3 to 1000\n\nDive: turn at this depth."
            )
        );
        assert!(!items.iter().any(|item| item.label == "overdepth"));
        // In a .ma file the behavior is the one `behavior_name=` names.
        let ma = labels(
            MissionFile::Args,
            "behavior_name=Surface\n<start:b_arg>\n  b_arg: $0",
        );
        assert!(
            ma.contains(&"gps_wait_time".to_string()) && ma.contains(&"start_when".to_string())
        );
    }

    #[test]
    fn hover_on_behaviors_arguments_sensors_and_args_from_file() {
        let (word, markdown) = hover_at(
            MissionFile::Mission,
            "behavior: abend\n    b_arg: over$0depth(m) 30\n",
        )
        .expect("hover");
        assert_eq!(word, "overdepth");
        assert!(
            markdown
                .starts_with("**overdepth**(m) · abend · default 10000\n\nAbort deeper than this"),
            "{markdown}"
        );
        // The units are not the argument.
        assert_eq!(
            hover_at(
                MissionFile::Mission,
                "behavior: abend\n    b_arg: overdepth($0m) 30\n"
            ),
            None
        );
        // yo's start_when: `#! choices=start_when([0, 1, 2, 4, 7, 8, 15, 17, 18])`.
        let (_, markdown) = hover_at(
            MissionFile::Mission,
            "behavior: yo\n    b_arg: start_wh$0en(enum) 2\n",
        )
        .expect("hover");
        assert!(
            markdown.starts_with(
                "**start_when**(enum) · yo · default 2 · one of 0, 1, 2, 4, 7, 8, 15, 17, 18"
            ),
            "{markdown}"
        );
        let (word, markdown) = hover_at(MissionFile::Mission, "behavior: y$0o\n").expect("hover");
        assert_eq!(word, "yo");
        assert!(
            markdown.starts_with("**behavior yo** · 42 arguments"),
            "{markdown}"
        );
        let (_, markdown) = hover_at(
            MissionFile::Mission,
            "behavior: goto_list\n  b_arg: args_from$0_file(enum) 10 # see\n",
        )
        .expect("hover");
        assert!(markdown.contains("`mafiles/goto_l10.ma`"), "{markdown}");
        let (word, markdown) =
            hover_at(MissionFile::Mission, "sensor: u_cycle_t$0ime(sec) 4\n").expect("hover");
        assert_eq!(word, "u_cycle_time");
        assert!(markdown.starts_with("**u_cycle_time** (sec)"), "{markdown}");
        let (word, markdown) =
            hover_at(MissionFile::Args, "behavior_name=Go$0to_list\n").expect("hover");
        assert_eq!(word, "Goto_list");
        assert!(markdown.starts_with("**behavior goto_list**"), "{markdown}");
        let (_, markdown) =
            hover_at(MissionFile::Mission, "behavior: yo\n b_arg: bo$0gus(m) 1\n").expect("hover");
        assert_eq!(
            markdown,
            "`bogus` is not an argument of behavior `yo`: the glider ignores it"
        );
        assert_eq!(
            hover_at(MissionFile::Mission, "behavior: yo # the y$0o\n"),
            None
        );
    }

    #[test]
    fn definition_goes_to_the_ma_file_args_from_file_loads() {
        let mission =
            "behavior: surface\n  b_arg: start_when(enum) 9\n  b_arg: args_from_file(enum) 10\n";
        let root = mission_folder(
            "definition",
            &[
                ("missions/d.mi", mission),
                (
                    "mafiles/surfac10.ma",
                    "behavior_name=surface\n<start:b_arg>\n<end:b_arg>\n",
                ),
            ],
        );
        let path = root.join("missions/d.mi");
        let (text, offset) = cursor(&mission.replace("(enum) 10", "(enum) 1$00"));
        let target = definition(&text, offset, &path, &embedded_context()).expect("a target");
        assert!(
            target.ends_with("mafiles/surfac10.ma"),
            "{}",
            target.display()
        );
        // Not on another line.
        assert_eq!(definition(&text, 20, &path, &embedded_context()), None);
        // The one link: `b_arg: args_from_file(enum) 10`; its line starts at 18 + 28 = 46,
        // `b_arg:` at 48 after the indentation, and `10` ends at 48 + 7 + 20 + 3 = 78.
        let links = links(&text, &path, &embedded_context());
        assert_eq!(links.len(), 1);
        assert_eq!(links[0].0, Span::new(48, 78));
        assert!(links[0].1.ends_with("mafiles/surfac10.ma"));
        let _ = std::fs::remove_dir_all(root);
    }

    #[test]
    fn definition_on_comets_real_mission() {
        let data = gloc_testsupport::data("comet");
        let path = data.join("missions/nsb3.mi");
        let text = std::fs::read_to_string(&path).expect("comet's nsb3.mi in data/");
        let line = "b_arg: args_from_file(enum)     10   # read from mafiles/yo10.ma";
        let offset = text.find(line).expect("the yo line") + 8;
        let target = definition(&text, offset, &path, &embedded_context()).expect("a target");
        assert!(target.ends_with("mafiles/yo10.ma"), "{}", target.display());
        // And every problem of the real mission is what `gloc run` reports: none.
        let analysis = analyze(
            MissionFile::Mission,
            &text,
            Some(&path),
            &SensorList::embedded(),
            None,
        );
        let codes: Vec<_> = analysis.diagnostics.iter().map(|d| d.code).collect();
        let run = Mission::load(&path);
        let run_codes: Vec<_> = run
            .diagnostics
            .iter()
            .chain(&run.check_sensor_settings(&SensorList::embedded()))
            .map(|entry| entry.diagnostic.code)
            .collect();
        assert_eq!(codes, run_codes);
    }

    #[test]
    fn no_text_and_no_cursor_makes_it_panic() {
        let sensors = SensorList::embedded();
        for text in [
            "",
            "\0",
            "behavior:",
            "b_arg:",
            "behavior: yo\n b_arg: é(m) ü # ☃\n",
            "behavior_name=\n<start:b_arg>\nb_arg: (\n",
            "sensor: 𝄞(m) 1\r\nbehavior: y𝄞o\r\n  b_arg: args_from_file(enum) 1e300\r\n",
            "  #\n\t\tb_arg: d_target_depth(m)(m) 1 2 3",
        ] {
            for kind in [MissionFile::Mission, MissionFile::Args] {
                let _ = analyze(kind, text, None, &sensors, None);
                for offset in 0..=text.len() + 2 {
                    let _ = completions(kind, text, offset, &sensors);
                    let _ = hover(kind, text, offset, &sensors);
                    let _ = definition(
                        text,
                        offset,
                        Path::new("/nonexistent/missions/m.mi"),
                        &embedded_context(),
                    );
                }
            }
            let _ = format(text);
        }
    }

    #[test]
    fn formatting_trims_line_ends_and_keeps_the_layout() {
        let text = "behavior: yo \t\n\tb_arg: d_target_depth(m)   50   # c  \r\n\n#end";
        assert_eq!(
            format(text).as_deref(),
            Some("behavior: yo\n\tb_arg: d_target_depth(m)   50   # c\n\n#end\n")
        );
        assert_eq!(format("a\0b"), None);
        assert_eq!(format("").as_deref(), Some(""));
    }

    #[test]
    fn formatting_comets_real_files_only_trims_line_ends() {
        let data = gloc_testsupport::data("comet");
        let folder = std::fs::read_dir(data.join("mafiles")).expect("comet's mafiles in data/");
        let mut paths: Vec<PathBuf> = folder
            .filter_map(|entry| Some(entry.ok()?.path()))
            .collect();
        paths.push(data.join("missions/nsb3.mi"));
        assert_eq!(paths.len(), 9);
        for path in paths {
            let text = std::fs::read_to_string(&path).expect("read");
            let formatted = format(&text).expect("text");
            let old: Vec<&str> = text.lines().collect();
            let new: Vec<&str> = formatted.lines().collect();
            assert_eq!(old.len(), new.len(), "{}", path.display());
            for (old, new) in old.iter().zip(&new) {
                assert_eq!(old.trim_end(), *new, "{}", path.display());
            }
            assert!(formatted.ends_with('\n'));
            assert_eq!(format(&formatted).as_deref(), Some(formatted.as_str()));
        }
    }
}
