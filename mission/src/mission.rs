//! Mission files (`.mi`) and mission argument files (`.ma`): parsing and loading.
//!
//! Parsing never fails: it returns what it understood plus diagnostics. Each
//! diagnostic carries the index of the source file it belongs to, so a caller
//! can name the file, line and column. Unknown behaviors and arguments are
//! warnings and are ignored; a missing `.ma` file or a malformed line is an
//! error, and a mission with errors must not be flown.

use std::path::{Path, PathBuf};

use gloc_engine::program::{Instr, Pc, Program};
use gloc_engine::sensors::SensorList;
use gloc_engine::{suggest, Diagnostic, LineIndex, Span};

use std::sync::Arc;

use crate::behaviors::{BehaviorInfo, BehaviorKind, BehaviorTable};
pub use crate::files::ma_file_name;
use crate::files::{Disk, Lookup, MissionFiles, NotLoaded, Place};

/// One text a mission was read from: the `.mi` file, then each `.ma` it loaded.
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
    /// For a `.ma` file: the `args_from_file` line of the `.mi` file that loaded it.
    pub loaded_at: Option<Span>,
    /// The text's lines, built once: every diagnostic is placed with it (one built per
    /// diagnostic took 30 s to report 40,000 bad lines).
    pub lines: LineIndex,
}

impl SourceFile {
    pub fn new(path: PathBuf, text: String, loaded_at: Option<Span>) -> SourceFile {
        SourceFile {
            lines: LineIndex::new(&text),
            path,
            text,
            loaded_at,
        }
    }
}

/// Where something was written: a source file (index into [`Mission::sources`]) and a span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location {
    pub file: usize,
    pub span: Span,
}

/// A diagnostic about one of the mission's source files.
#[derive(Clone, Debug)]
pub struct MissionDiagnostic {
    pub file: usize,
    pub diagnostic: Diagnostic,
}

/// `sensor: NAME(UNITS) VALUE`: a sensor's initial value for this mission.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorSetting {
    pub name: String,
    pub units: String,
    pub value: f64,
    /// The whole line, from `sensor:`.
    pub at: Location,
    /// The sensor's name (in the same file as `at`).
    pub name_span: Span,
}

/// `b_arg: NAME(UNITS) VALUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub name: String,
    pub units: String,
    pub value: f64,
    pub at: Location,
}

/// One `behavior:` block, with the arguments of its `.ma` file merged in.
#[derive(Clone, Debug, PartialEq)]
pub struct BehaviorSpec {
    /// What the simulator flies ([`BehaviorKind::Unknown`]: nothing).
    pub kind: BehaviorKind,
    /// The name as written.
    pub name: String,
    pub args: Vec<Arg>,
    pub at: Location,
    /// Whether the behavior table defines it (its arguments are then kept and
    /// checked even when the simulator does not fly it).
    pub defined: bool,
    /// The table's defaults for this behavior (argument name, value).
    pub defaults: Vec<(String, f64)>,
}

impl BehaviorSpec {
    /// The argument's value as written in the mission, or `None`.
    ///
    /// Decision: a value from the behavior's `.ma` file wins over one in the `.mi`,
    /// wherever the `args_from_file` line is, because the glider re-reads `.ma`
    /// files during a mission (`c_reread_mafiles`, goto_list's `end_action` 6) and
    /// applies them over the behavior's arguments; S0109 names the `.mi` line.
    pub fn arg(&self, name: &str) -> Option<f64> {
        let named = |arg: &&Arg| arg.name.eq_ignore_ascii_case(name);
        self.args
            .iter()
            .rev()
            .filter(|arg| arg.at.file != 0)
            .find(named)
            .or_else(|| self.args.iter().rev().find(named))
            .map(|arg| arg.value)
    }

    /// The behavior table's default for an argument the mission does not set.
    pub fn default(&self, name: &str) -> Option<f64> {
        self.defaults
            .iter()
            .find(|(arg, _)| arg.eq_ignore_ascii_case(name))
            .map(|(_, value)| *value)
    }

    /// The value flown: as written, else the table's default.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.arg(name).or_else(|| self.default(name))
    }

    fn for_behavior(info: Option<&BehaviorInfo>, name: &str, at: Location) -> BehaviorSpec {
        BehaviorSpec {
            kind: info.map_or(BehaviorKind::Unknown, |info| info.kind),
            name: name.to_string(),
            args: Vec::new(),
            at,
            defined: info.is_some(),
            defaults: info.map_or_else(Vec::new, |info| {
                info.args
                    .iter()
                    .filter_map(|arg| Some((arg.name.clone(), arg.default?)))
                    .collect()
            }),
        }
    }
}

/// A waypoint line of a `.ma` file: `LON LAT`, NMEA `dddmm.mmm` (negative: west, south).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    /// The index in [`Mission::behaviors`] of the behavior whose file lists it.
    pub behavior: usize,
    pub lon: f64,
    pub lat: f64,
    pub at: Location,
}

/// A parsed mission.
#[derive(Clone, Debug, Default)]
pub struct Mission {
    /// The mission's name as the glider writes it in logs (`FIG2.MI`).
    pub name: String,
    pub sources: Vec<SourceFile>,
    pub sensor_settings: Vec<SensorSetting>,
    /// Highest priority first.
    pub behaviors: Vec<BehaviorSpec>,
    /// The `<start:b_arg>` … `<end:b_arg>` and waypoint sections of the `.ma` files,
    /// from the start line to the end line.
    pub sections: Vec<Location>,
    pub diagnostics: Vec<MissionDiagnostic>,
    /// The waypoints of the `.ma` files' `<start:waypoints>` sections.
    pub waypoints: Vec<Waypoint>,
    /// The behavior table it was read with (`None`: the embedded one).
    pub table: Option<Arc<BehaviorTable>>,
}

/// How a mission is loaded: where else to look for its `.ma` files.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// A folder the user named for `.ma` files (`--mafiles`, `gloc.toml`'s `mafiles`):
    /// searched first, and trusted wherever it is.
    pub mafiles: Option<PathBuf>,
    /// The behaviors and their arguments (`None`: the embedded table); see
    /// [`BehaviorTable::for_sensors`].
    pub table: Option<Arc<BehaviorTable>>,
}

impl LoadOptions {
    /// The table to read with.
    pub fn table(&self) -> Arc<BehaviorTable> {
        self.table.clone().unwrap_or_else(BehaviorTable::embedded)
    }
}

impl Mission {
    /// Reads a `.mi` file and every `.ma` file it names, by the glider's file rules
    /// ([`crate::files`]). Never fails: an unreadable mission file gives a mission
    /// with one error.
    pub fn load(path: &Path) -> Mission {
        Mission::load_with_options(path, &LoadOptions::default(), &mut Disk)
    }

    /// As [`Mission::load`], reading files through `files` (for tests and the fuzzer).
    pub fn load_with(path: &Path, files: &mut dyn MissionFiles) -> Mission {
        Mission::load_with_options(path, &LoadOptions::default(), files)
    }

    /// As [`Mission::load`], with options, reading files through `files`.
    pub fn load_with_options(
        path: &Path,
        options: &LoadOptions,
        files: &mut dyn MissionFiles,
    ) -> Mission {
        match files.read(path) {
            Ok(text) => Mission::load_text(path, text, options, files),
            Err(error) => Mission::unreadable(path, &error),
        }
    }

    /// A mission whose `.mi` text is at hand (an editor's document, a file the
    /// caller read), its `.ma` files read through `files`.
    pub fn load_text(
        path: &Path,
        text: String,
        options: &LoadOptions,
        files: &mut dyn MissionFiles,
    ) -> Mission {
        let lookup = Lookup::new(files, path, options.mafiles.as_deref());
        parse_mission(path, text, Some(lookup), options.table())
    }

    /// Parses the text of a `.ma` file on its own, as the behavior its
    /// `behavior_name=` line names loads it (an editor's view of the file).
    pub fn parse_args_file(path: impl Into<PathBuf>, text: impl Into<String>) -> Mission {
        parse_args_file(&path.into(), text.into(), BehaviorTable::embedded())
    }

    /// As [`Mission::parse_args_file`], with a behavior table.
    pub fn parse_args_file_with(
        path: impl Into<PathBuf>,
        text: impl Into<String>,
        options: &LoadOptions,
    ) -> Mission {
        parse_args_file(&path.into(), text.into(), options.table())
    }

    /// Reads a `.ma` file through `files` and parses it alone (as
    /// [`Mission::parse_args_file_with`]); an unreadable file gives one S0001 error.
    pub fn load_args_file(
        path: &Path,
        options: &LoadOptions,
        files: &mut dyn MissionFiles,
    ) -> Mission {
        match files.read(path) {
            Ok(text) => parse_args_file(path, text, options.table()),
            Err(error) => Mission::unreadable(path, &error),
        }
    }

    /// A mission whose file could not be read: one S0001 error.
    fn unreadable(path: &Path, error: &std::io::Error) -> Mission {
        let mut mission = Mission {
            name: mission_name(path),
            ..Mission::default()
        };
        mission
            .sources
            .push(SourceFile::new(path.to_path_buf(), String::new(), None));
        mission.diagnostics.push(MissionDiagnostic {
            file: 0,
            diagnostic: Diagnostic::error(
                gloc_engine::codes::mission::CANNOT_READ_MISSION,
                Span::default(),
                format!("cannot read mission file `{}`: {error}", path.display()),
            ),
        });
        mission
    }

    /// The behavior table the mission was read with.
    pub fn table(&self) -> Arc<BehaviorTable> {
        self.table.clone().unwrap_or_else(BehaviorTable::embedded)
    }

    /// Parses mission text that loads no `.ma` files (an `args_from_file` is an error).
    pub fn parse(path: impl Into<PathBuf>, text: impl Into<String>) -> Mission {
        parse_mission(&path.into(), text.into(), None, BehaviorTable::embedded())
    }

    pub fn has_errors(&self) -> bool {
        self.diagnostics
            .iter()
            .any(|entry| entry.diagnostic.is_error())
    }

    /// `path:line:col: severity[code]: message`, one line per diagnostic, for
    /// plain-text output and test messages.
    pub fn render_plain(&self) -> String {
        let mut out = String::new();
        for line in self.rendered() {
            out.push_str(&line);
            out.push('\n');
        }
        out
    }

    /// Each diagnostic as [`Self::render_one`] writes it, in order.
    pub fn rendered(&self) -> Vec<String> {
        self.diagnostics
            .iter()
            .map(|entry| self.render_one(entry))
            .collect()
    }

    /// One diagnostic as `path:line:col: severity[code]: message`.
    pub fn render_one(&self, entry: &MissionDiagnostic) -> String {
        let (path, line, column) = self.line_col(entry.file, entry.diagnostic.span);
        let diagnostic = &entry.diagnostic;
        let mut text = format!(
            "{}:{line}:{column}: {}[{}]: {}",
            path.display(),
            diagnostic.severity,
            diagnostic.code,
            diagnostic.message
        );
        if let Some(help) = &diagnostic.help {
            text.push_str(&format!(" (help: {help})"));
        }
        text
    }

    /// Everything gloc checks in a loaded mission beyond its syntax, against the
    /// active sensor list: what `gloc check`, `gloc run`, the editor and the debugger
    /// show besides [`Mission::diagnostics`].
    pub fn check(&self, sensor_list: &SensorList) -> Vec<MissionDiagnostic> {
        let mut found = self.check_sensor_settings(sensor_list);
        found.extend(crate::checks::check(self));
        found
    }

    /// S0106 for each `sensor:` setting that names a sensor `sensor_list` lacks
    /// (the simulator ignores it), with a caret on the name.
    pub fn check_sensor_settings(&self, sensor_list: &SensorList) -> Vec<MissionDiagnostic> {
        self.sensor_settings
            .iter()
            .filter(|setting| sensor_list.lookup(&setting.name).is_none())
            .map(|setting| MissionDiagnostic {
                file: setting.at.file,
                diagnostic: Diagnostic::warning(
                    gloc_engine::codes::mission::SENSOR_NOT_IN_LIST,
                    setting.name_span,
                    format!(
                        "sensor `{}` is not in the sensor list; the setting is ignored",
                        setting.name
                    ),
                )
                .with_help(
                    match suggest::closest(
                        &setting.name,
                        sensor_list.iter().map(|(_, sensor)| sensor.name.as_str()),
                    ) {
                        Some(close) => format!("did you mean `{close}`?"),
                        None if sensor_list.crc() == Some(gloc_engine::sensors::EMBEDDED_CRC) => {
                            "the active list is the embedded one of 2008 firmware, which lacks \
                             newer sensors: check against the glider's own masterdata \
                             (`--masterdata`)"
                                .to_string()
                        }
                        None => "check the name against the glider's masterdata (`--masterdata`)"
                            .to_string(),
                    },
                ),
            })
            .collect()
    }

    /// The instructions of `program` that store `sci_ruhp_behs` when the mission has
    /// no hook behavior to act on it (each store then has no effect): empty when
    /// the mission has one, or the script never stores it. See
    /// [`Mission::unhooked_store_warning`].
    pub fn unhooked_stores(&self, sensor_list: &SensorList, program: &Program) -> Vec<Pc> {
        if self
            .behaviors
            .iter()
            .any(|spec| spec.kind == BehaviorKind::Hook)
        {
            return Vec::new();
        }
        let Some(behs) = sensor_list.lookup("sci_ruhp_behs") else {
            return Vec::new();
        };
        program
            .instrs
            .iter()
            .enumerate()
            .filter(
                |(_, instr)| matches!(instr, Instr::StoreSensor { sensor, .. } if *sensor == behs),
            )
            .map(|(pc, _)| Pc(pc as u32))
            .collect()
    }

    /// S0107, on the script: `spans` are the stores [`Mission::unhooked_stores`]
    /// found, in the script's own text (the first gets the caret, the others a label).
    pub fn unhooked_store_warning(&self, spans: &[Span]) -> Option<Diagnostic> {
        let (first, others) = spans.split_first()?;
        let path = self.sources.first().map_or_else(
            || self.name.clone(),
            |source| source.path.display().to_string(),
        );
        let mut diagnostic = Diagnostic::warning(
            gloc_engine::codes::mission::HOOK_MISSING,
            *first,
            format!(
                "the script stores `sci_ruhp_behs`, but the mission {path} has no `behavior: hook`: \
                 nothing acts on it"
            ),
        )
        .with_help("add a `behavior: hook` below the script behavior in the mission, or fly a mission that has one");
        for span in others {
            diagnostic = diagnostic.with_label(*span, "stored here too");
        }
        Some(diagnostic)
    }

    /// The file, 1-based line and column of a span in one of the sources.
    pub fn line_col(&self, file: usize, span: Span) -> (&Path, usize, usize) {
        match self.sources.get(file) {
            Some(source) => {
                let (line, column) = source.lines.line_col(&source.text, span.start as usize);
                (source.path.as_path(), line, column)
            }
            None => (Path::new("<mission>"), 1, 1),
        }
    }
}

/// The glider's name for a mission: the file name, upper-cased (`FIG2.MI`).
fn mission_name(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().to_ascii_uppercase())
        .unwrap_or_else(|| "MISSION.MI".to_string())
}

/// Splits a text into lines with their byte offsets, without the line end
/// (`\n` or `\r\n`) and with any `#` comment removed.
fn code_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut offset = 0;
    text.split_inclusive('\n').map(move |raw| {
        let start = offset;
        offset += raw.len();
        let line = raw.trim_end_matches(['\n', '\r']);
        let code = match line.find('#') {
            Some(at) => &line[..at],
            None => line,
        };
        (start, code)
    })
}

/// A word of a line with its absolute byte offset.
#[derive(Clone, Copy)]
struct Word<'a> {
    text: &'a str,
    start: usize,
}

impl Word<'_> {
    fn span(self) -> Span {
        Span::new(self.start, self.start + self.text.len())
    }
}

fn words(line_start: usize, line: &str) -> Vec<Word<'_>> {
    let mut out = Vec::new();
    let mut word_start = None;
    for (at, character) in line.char_indices() {
        if character.is_whitespace() {
            if let Some(start) = word_start.take() {
                out.push(Word {
                    text: &line[start..at],
                    start: line_start + start,
                });
            }
        } else if word_start.is_none() {
            word_start = Some(at);
        }
    }
    if let Some(start) = word_start {
        out.push(Word {
            text: &line[start..],
            start: line_start + start,
        });
    }
    out
}

/// Parses `NAME(UNITS) VALUE` after a `sensor:` or `b_arg:` keyword.
/// `rest` are the words after the keyword; `end` is where the line ends (for
/// "missing" errors).
// One error per malformed line, built once: its size does not matter here.
#[allow(clippy::result_large_err)]
fn parse_setting(
    keyword: Word<'_>,
    rest: &[Word<'_>],
    end: usize,
) -> Result<(String, String, f64), Diagnostic> {
    let Some(first) = rest.first() else {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::EXPECTED_SETTING,
            Span::new(end, end),
            format!("expected `NAME(UNITS) VALUE` after `{}`", keyword.text),
        )
        .with_help("write for example `b_arg: overdepth(m) 30`"));
    };
    // The name and units are one word `name(units)`, but tolerate a space
    // before the parenthesis as some hand-written files have.
    let (name_units, value_words) = if !first.text.contains('(')
        && rest.get(1).is_some_and(|next| next.text.starts_with('('))
    {
        let joined_end = rest[1].start + rest[1].text.len();
        (
            (
                first.text.to_string() + rest[1].text,
                first.start,
                joined_end,
            ),
            &rest[2..],
        )
    } else {
        (
            (
                first.text.to_string(),
                first.start,
                first.start + first.text.len(),
            ),
            &rest[1..],
        )
    };
    let (text, start, name_end) = name_units;
    let Some(open) = text.find('(') else {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::MISSING_UNITS,
            Span::new(start, name_end),
            format!("`{text}` has no units: expected `NAME(UNITS)`"),
        )
        .with_help(format!("write the units in parentheses, e.g. `{text}(m)`")));
    };
    let name = &text[..open];
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::BAD_SETTING_NAME,
            Span::new(start, start + open.max(1)),
            format!("`{name}` is not a valid name: use letters, digits and `_`"),
        ));
    }
    let Some(close) = text[open..].find(')').map(|at| at + open) else {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::MISSING_UNITS,
            Span::new(start + open, name_end),
            "unclosed `(` in the units: expected `)`",
        ));
    };
    if close + 1 != text.len() {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::TRAILING_TEXT,
            Span::new(start + close + 1, name_end),
            "unexpected text after the units: expected whitespace and a value",
        ));
    }
    let units = &text[open + 1..close];
    let Some(value_word) = value_words.first() else {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::MISSING_VALUE,
            Span::new(end, end),
            format!("`{name}` has no value: expected a number after `{text}`"),
        ));
    };
    let value = parse_number(value_word.text).ok_or_else(|| {
        Diagnostic::error(
            gloc_engine::codes::mission::VALUE_NOT_A_NUMBER,
            value_word.span(),
            format!("`{}` is not a number", value_word.text),
        )
        .with_help("write a decimal number such as `30`, `-1` or `0.4538`")
    })?;
    if let Some(extra) = value_words.get(1) {
        return Err(Diagnostic::error(
            gloc_engine::codes::mission::TRAILING_TEXT,
            extra.span(),
            format!(
                "unexpected `{}` after the value (start a comment with `#`)",
                extra.text
            ),
        ));
    }
    Ok((name.to_string(), units.to_string(), value))
}

/// A value as a pilot writes it (`30`, `-0.4538`).
fn format_value(value: f64) -> String {
    format!("{value}")
}

fn parse_number(text: &str) -> Option<f64> {
    // Rust accepts `inf` and `NaN`; a mission value must be a finite number.
    let value: f64 = text.parse().ok()?;
    value.is_finite().then_some(value)
}

struct Parser<'a> {
    mission: Mission,
    /// Where `.ma` files are found; `None` for text that loads none.
    lookup: Option<Lookup<'a>>,
    table: Arc<BehaviorTable>,
    /// A `.ma` file parsed on its own: its text is source 0.
    args_file: bool,
}

fn parse_mission(
    path: &Path,
    text: String,
    lookup: Option<Lookup<'_>>,
    table: Arc<BehaviorTable>,
) -> Mission {
    let mut parser = Parser {
        mission: Mission {
            name: mission_name(path),
            table: Some(table.clone()),
            ..Mission::default()
        },
        lookup,
        table,
        args_file: false,
    };
    parser
        .mission
        .sources
        .push(SourceFile::new(path.to_path_buf(), text, None));
    parser.parse_mi();
    parser.warn_overridden_args();
    parser.mission
}

/// A `.ma` file on its own (an editor opened it): parsed as the behavior its
/// `behavior_name=` line names would load it, so it gets the diagnostics `gloc run`
/// gives it when a mission loads it. The mission has that one behavior with the
/// file's arguments.
fn parse_args_file(path: &Path, text: String, table: Arc<BehaviorTable>) -> Mission {
    let named = code_lines(&text).find_map(|(line_start, code)| {
        let first = *words(line_start, code).first()?;
        let name = first
            .text
            .get(.."behavior_name=".len())
            .filter(|prefix| prefix.eq_ignore_ascii_case("behavior_name="))
            .map(|_| &first.text["behavior_name=".len()..])?;
        Some((name.to_string(), first.span()))
    });
    let mut parser = Parser {
        mission: Mission {
            name: mission_name(path),
            table: Some(table.clone()),
            ..Mission::default()
        },
        lookup: None,
        table,
        args_file: true,
    };
    parser
        .mission
        .sources
        .push(SourceFile::new(path.to_path_buf(), text, None));
    let at = Location {
        file: 0,
        span: named.as_ref().map_or(Span::default(), |(_, span)| *span),
    };
    let name = named
        .as_ref()
        .map_or_else(String::new, |(name, _)| name.clone());
    if let Some((name, span)) = &named {
        let start = span.start as usize + "behavior_name=".len();
        parser.begin_named_behavior(name, Span::new(start, start + name.len()), at);
    } else {
        parser
            .mission
            .behaviors
            .push(BehaviorSpec::for_behavior(None, "", at));
    }
    parser.parse_ma(0, &name);
    parser.mission
}

impl Parser<'_> {
    /// S0109 on each `.mi` argument its behavior's `.ma` file sets again (see
    /// [`BehaviorSpec::arg`]).
    fn warn_overridden_args(&mut self) {
        let mut warnings = Vec::new();
        for spec in &self.mission.behaviors {
            for mi_arg in spec.args.iter().filter(|arg| arg.at.file == 0) {
                let Some(ma_arg) =
                    spec.args.iter().rev().find(|arg| {
                        arg.at.file != 0 && arg.name.eq_ignore_ascii_case(&mi_arg.name)
                    })
                else {
                    continue;
                };
                // The same value in both places changes nothing (the manufacturer's
                // own missions repeat `.ma` values in the `.mi`).
                if ma_arg.value == mi_arg.value {
                    continue;
                }
                let (ma_path, line, _) = self.mission.line_col(ma_arg.at.file, ma_arg.at.span);
                let ma_name = ma_path
                    .file_name()
                    .map_or_else(String::new, |name| name.to_string_lossy().into_owned());
                warnings.push(
                    Diagnostic::warning(
                        gloc_engine::codes::mission::ARG_OVERRIDDEN_BY_MA,
                        mi_arg.at.span,
                        format!(
                            "`{}` is set again in `{ma_name}` (line {line}): the glider flies \
                             the `.ma` value {}, not {}",
                            mi_arg.name,
                            format_value(ma_arg.value),
                            format_value(mi_arg.value)
                        ),
                    )
                    .with_help(format!(
                        "set `{}` in one place: delete this line or the one in `{ma_name}`",
                        mi_arg.name
                    )),
                );
            }
        }
        for warning in warnings {
            self.error(0, warning);
        }
    }

    fn error(&mut self, file: usize, diagnostic: Diagnostic) {
        self.mission
            .diagnostics
            .push(MissionDiagnostic { file, diagnostic });
    }

    fn parse_mi(&mut self) {
        let text = self.mission.sources[0].text.clone();
        if text.contains('\0') {
            let at = text.find('\0').unwrap_or(0);
            self.error(
                0,
                Diagnostic::error(
                    gloc_engine::codes::mission::MISSION_NOT_TEXT,
                    Span::new(at, at + 1),
                    "this is not a text file (it contains a NUL byte)",
                ),
            );
            return;
        }
        for (line_start, code) in code_lines(&text) {
            let words = words(line_start, code);
            let Some(&keyword) = words.first() else {
                continue;
            };
            let end = line_start + code.trim_end().len();
            match keyword.text.to_ascii_lowercase().as_str() {
                "sensor:" => match parse_setting(keyword, &words[1..], end) {
                    Ok((name, units, value)) => {
                        let name_start = words.get(1).map_or(keyword.start, |word| word.start);
                        self.mission.sensor_settings.push(SensorSetting {
                            name_span: Span::new(name_start, name_start + name.len()),
                            name,
                            units,
                            value,
                            at: Location {
                                file: 0,
                                span: Span::new(keyword.start, end),
                            },
                        })
                    }
                    Err(diagnostic) => self.error(0, diagnostic),
                },
                "behavior:" => self.begin_behavior(&words, end),
                "b_arg:" => match parse_setting(keyword, &words[1..], end) {
                    Ok((name, units, value)) => {
                        let at = Location {
                            file: 0,
                            span: Span::new(keyword.start, end),
                        };
                        self.add_arg(0, keyword, name, units, value, at);
                    }
                    Err(diagnostic) => self.error(0, diagnostic),
                },
                _ => self.error(
                    0,
                    Diagnostic::error(
                        gloc_engine::codes::mission::UNEXPECTED_MISSION_LINE,
                        keyword.span(),
                        format!(
                            "unexpected `{}`: expected `sensor:`, `behavior:` or `b_arg:`",
                            keyword.text
                        ),
                    )
                    .with_help("comment the line out with `#` if it is a note"),
                ),
            }
        }
    }

    /// The behavior being filled, or `None` after an unknown behavior.
    fn current(&mut self) -> Option<&mut BehaviorSpec> {
        self.mission.behaviors.last_mut()
    }

    fn begin_behavior(&mut self, words: &[Word<'_>], end: usize) {
        let keyword = words[0];
        let Some(name) = words.get(1) else {
            self.error(
                0,
                Diagnostic::error(
                    gloc_engine::codes::mission::MISSING_BEHAVIOR_NAME,
                    Span::new(end, end),
                    "expected a behavior name after `behavior:`",
                ),
            );
            self.mission.behaviors.push(unknown_spec(keyword));
            return;
        };
        if let Some(extra) = words.get(2) {
            self.error(
                0,
                Diagnostic::error(
                    gloc_engine::codes::mission::TRAILING_TEXT,
                    extra.span(),
                    format!("unexpected `{}` after the behavior name", extra.text),
                ),
            );
        }
        let at = Location {
            file: 0,
            span: Span::new(keyword.start, name.start + name.text.len()),
        };
        self.begin_named_behavior(name.text, name.span(), at);
    }

    /// Opens the block of behavior `name` (written at `name_span`): S0101 with a
    /// "did you mean" when the table lacks it, S0111 when the simulator does not fly it.
    fn begin_named_behavior(&mut self, name: &str, name_span: Span, at: Location) {
        let table = self.table.clone();
        let info = table.behavior(name);
        match info {
            None => {
                let known = table.behaviors().iter().map(|known| known.name.as_str());
                let help = match suggest::closest(name, known) {
                    Some(close) => format!("did you mean `{close}`?"),
                    None => format!(
                        "the behaviors of {}: {}",
                        table.source_name(),
                        table
                            .behaviors()
                            .iter()
                            .map(|known| known.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                };
                self.error(
                    at.file,
                    Diagnostic::warning(
                        gloc_engine::codes::mission::UNKNOWN_BEHAVIOR,
                        name_span,
                        format!(
                            "unknown behavior `{name}` (not in {}): gloc ignores it with its \
                             arguments",
                            table.source_name()
                        ),
                    )
                    .with_help(help),
                );
            }
            Some(info) if !info.is_simulated() => {
                self.error(
                    at.file,
                    Diagnostic::note(
                        gloc_engine::codes::mission::BEHAVIOR_NOT_SIMULATED,
                        name_span,
                        format!(
                            "behavior `{}` is the glider's, but gloc's simulator does not fly \
                             it: `gloc run` leaves it out",
                            info.name
                        ),
                    ),
                );
            }
            Some(_) => {}
        }
        self.mission
            .behaviors
            .push(BehaviorSpec::for_behavior(info, name, at));
    }

    fn add_arg(
        &mut self,
        file: usize,
        keyword: Word<'_>,
        name: String,
        units: String,
        value: f64,
        at: Location,
    ) {
        let Some(current) = self.current() else {
            self.error(
                file,
                Diagnostic::error(
                    gloc_engine::codes::mission::ARG_BEFORE_BEHAVIOR,
                    keyword.span(),
                    "`b_arg:` before any `behavior:` line",
                )
                .with_help("put the argument under the behavior it belongs to"),
            );
            return;
        };
        if !current.defined {
            return;
        }
        let behavior_name = current.name.clone();
        if name.eq_ignore_ascii_case("args_from_file") {
            if file != 0 || self.args_file {
                self.error(
                    file,
                    Diagnostic::warning(
                        gloc_engine::codes::mission::NESTED_ARGS_FROM_FILE,
                        at.span,
                        "`args_from_file` inside a `.ma` file is ignored",
                    ),
                );
                return;
            }
            if value >= 0.0 {
                self.load_ma(&behavior_name, value, at);
            }
            return;
        }
        let table = self.table.clone();
        let info = table.behavior(&behavior_name);
        if let Some(info) = info.filter(|info| info.arg(&name).is_none()) {
            let known = info.args.iter().map(|arg| arg.name.as_str());
            let help = match suggest::closest(&name, known) {
                Some(close) => format!("did you mean `{close}`?"),
                None => format!(
                    "`{behavior_name}` takes: {}",
                    info.args
                        .iter()
                        .map(|arg| arg.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            self.error(
                file,
                Diagnostic::warning(
                    gloc_engine::codes::mission::UNKNOWN_ARGUMENT,
                    at.span,
                    format!(
                        "unknown argument `{name}` for behavior `{behavior_name}` (not in {}): \
                         the glider ignores it and flies the default",
                        table.source_name()
                    ),
                )
                .with_help(help),
            );
            return;
        }
        if let Some(current) = self.current() {
            current.args.push(Arg {
                name,
                units,
                value,
                at,
            });
        }
    }

    fn load_ma(&mut self, behavior: &str, value: f64, at: Location) {
        let number = value as i64;
        let file_name = ma_file_name(behavior, number);
        let found = match self.lookup.as_mut() {
            Some(lookup) => lookup.find(&file_name).map_err(Some),
            None => Err(None),
        };
        let found = match found {
            Ok(found) => found,
            Err(why) => {
                self.error(at.file, ma_not_loaded(why, &file_name, number, at.span));
                return;
            }
        };
        if found.place == Place::BesideMission {
            self.error(
                at.file,
                Diagnostic::note(
                    gloc_engine::codes::mission::MA_BESIDE_MISSION,
                    at.span,
                    format!(
                        "`{}` was read from the mission's own folder: the glider reads it \
                         only from `mafiles/`",
                        found.path.display()
                    ),
                )
                .with_help(format!(
                    "copy it to `mafiles/{file_name}` before sending the mission to a glider"
                )),
            );
        }
        let file = self.mission.sources.len();
        self.mission
            .sources
            .push(SourceFile::new(found.path, found.text, Some(at.span)));
        self.parse_ma(file, behavior);
    }

    /// A line of a `.ma` file's `<start:waypoints>` list: `lon lat` in NMEA DDDMM.MMMM,
    /// kept for the checks (`Mission::waypoints`) and, in a goto_list, flown as its
    /// `wpt_x_N` / `wpt_y_N` (numbered from 0 after those the behavior already has).
    fn waypoint_line(
        &mut self,
        file: usize,
        behavior: &str,
        words: &[Word<'_>],
        (line_start, code): (usize, &str),
        last_end: usize,
    ) {
        let Some(&first) = words.first() else {
            return;
        };
        let numbers = (
            parse_number(first.text),
            words.get(1).and_then(|word| parse_number(word.text)),
        );
        let (Some(lon), Some(lat)) = numbers else {
            self.error(
                file,
                Diagnostic::error(
                    gloc_engine::codes::mission::BAD_WAYPOINT,
                    first.span(),
                    "expected a waypoint `LON LAT` (DDDMM.MMMM DDMM.MMMM)",
                ),
            );
            return;
        };
        if let Some(extra) = words.get(2) {
            // `lon lat | name`: no public documentation says the firmware reads a name
            // there, so it is a warning, not an error.
            let end = words
                .last()
                .map_or(extra.start, |word| word.start + word.text.len());
            self.error(
                file,
                Diagnostic::warning(
                    gloc_engine::codes::mission::WAYPOINT_TRAILING_TEXT,
                    Span::new(extra.start, end),
                    format!(
                        "`{}` after the waypoint's longitude and latitude: the firmware's \
                         documentation has only the two numbers",
                        &code[extra.start - line_start..end - line_start]
                    ),
                )
                .with_help("write a waypoint's name as a comment: `-7032.064 4138.106 # name`"),
            );
        }
        let at = Location {
            file,
            span: Span::new(first.start, last_end),
        };
        if behavior.eq_ignore_ascii_case("goto_list") {
            let number = self.current().map_or(0, |current| {
                current
                    .args
                    .iter()
                    .filter(|arg| arg.name.to_ascii_lowercase().starts_with("wpt_x_"))
                    .count()
            });
            for (axis, value) in [("x", lon), ("y", lat)] {
                let name = format!("wpt_{axis}_{number}");
                self.add_arg(file, first, name, "nmea".into(), value, at);
            }
        }
        let behavior = self.mission.behaviors.len().saturating_sub(1);
        self.mission.waypoints.push(Waypoint {
            behavior,
            lon,
            lat,
            at,
        });
    }

    fn parse_ma(&mut self, file: usize, behavior: &str) {
        let text = self.mission.sources[file].text.clone();
        #[derive(PartialEq)]
        enum Section {
            Outside,
            Args,
            Waypoints,
        }
        let mut section = Section::Outside;
        let mut section_start = 0;
        let mut saw_name = false;
        let mut last_end = 0;
        for (line_start, code) in code_lines(&text) {
            let words = words(line_start, code);
            let Some(&first) = words.first() else {
                continue;
            };
            last_end = line_start + code.trim_end().len();
            let lower = first.text.to_ascii_lowercase();
            match lower.as_str() {
                "<start:b_arg>" | "<start:waypoints>" if section != Section::Outside => {
                    self.error(
                        file,
                        Diagnostic::error(
                            gloc_engine::codes::mission::NESTED_SECTION,
                            first.span(),
                            format!("`{}` inside another section: close it first", first.text),
                        ),
                    );
                }
                "<start:b_arg>" | "<start:waypoints>" => {
                    section = if lower == "<start:b_arg>" {
                        Section::Args
                    } else {
                        Section::Waypoints
                    };
                    section_start = first.start;
                }
                "<end:b_arg>" | "<end:waypoints>"
                    if (section == Section::Args) == (lower == "<end:b_arg>")
                        && section != Section::Outside =>
                {
                    section = Section::Outside;
                    self.mission.sections.push(Location {
                        file,
                        span: Span::new(section_start, last_end),
                    });
                }
                "<end:b_arg>" | "<end:waypoints>" => self.error(
                    file,
                    Diagnostic::error(
                        gloc_engine::codes::mission::UNMATCHED_SECTION_END,
                        first.span(),
                        format!("`{}` without a matching start", first.text),
                    ),
                ),
                _ if lower.starts_with("behavior_name=") && section == Section::Outside => {
                    saw_name = true;
                    let named = &first.text["behavior_name=".len()..];
                    if !self.args_file && !named.eq_ignore_ascii_case(behavior) {
                        self.error(
                            file,
                            Diagnostic::warning(
                                gloc_engine::codes::mission::MA_FOR_OTHER_BEHAVIOR,
                                first.span(),
                                format!(
                                    "this file is for behavior `{named}`, but behavior `{behavior}` loads it"
                                ),
                            ),
                        );
                    }
                }
                "b_arg:" if section == Section::Args => {
                    match parse_setting(first, &words[1..], last_end) {
                        Ok((name, units, value)) => {
                            let at = Location {
                                file,
                                span: Span::new(first.start, last_end),
                            };
                            self.add_arg(file, first, name, units, value, at);
                        }
                        Err(diagnostic) => self.error(file, diagnostic),
                    }
                }
                _ if section == Section::Waypoints => {
                    self.waypoint_line(file, behavior, &words, (line_start, code), last_end);
                }
                _ => self.error(
                    file,
                    Diagnostic::error(
                        gloc_engine::codes::mission::UNEXPECTED_MA_LINE,
                        first.span(),
                        format!(
                            "unexpected `{}`: expected `behavior_name=`, `<start:b_arg>`, `b_arg:` or `<end:b_arg>`",
                            first.text
                        ),
                    ),
                ),
            }
        }
        if section != Section::Outside {
            self.error(
                file,
                Diagnostic::error(
                    gloc_engine::codes::mission::UNCLOSED_SECTION,
                    Span::new(last_end, last_end),
                    "the file ends inside a section: expected `<end:b_arg>` or `<end:waypoints>`",
                ),
            );
        }
        if !saw_name {
            self.error(
                file,
                Diagnostic::warning(
                    gloc_engine::codes::mission::MA_WITHOUT_BEHAVIOR_NAME,
                    Span::default(),
                    format!("no `behavior_name=` line (loaded for `{behavior}`)"),
                ),
            );
        }
    }
}

/// Why the `.ma` file `file_name` that `args_from_file` names cannot be flown, as the
/// diagnostic to show at that line (`None`: the mission has no mafiles folder to look in).
fn ma_not_loaded(why: Option<NotLoaded>, file_name: &str, number: i64, span: Span) -> Diagnostic {
    use gloc_engine::codes::mission::{CANNOT_READ_MA, GENERATED_MA_MISSING};
    let (message, help) = match why {
        None => (
            format!("`args_from_file` needs `{file_name}`, but this mission has no mafiles folder"),
            "save the mission in a `missions` folder beside `mafiles`".to_string(),
        ),
        Some(NotLoaded::Missing { .. }) if number == 99 => {
            return Diagnostic::warning(
                GENERATED_MA_MISSING,
                span,
                format!(
                    "`{file_name}` is not there: number 99 is the file the glider \
                     writes itself during a mission (breadcrumb, ice); gloc flies \
                     the behavior's defaults"
                ),
            )
            .with_help(format!(
                "to fly it in gloc, put a `{file_name}` of your own in `mafiles/`"
            ));
        }
        Some(NotLoaded::Missing { searched }) => {
            let folders = searched
                .iter()
                .map(|folder| format!("`{}`", folder.display()))
                .collect::<Vec<_>>()
                .join(", ");
            (
                format!(
                    "cannot find mission argument file `{file_name}` (in any case) in {folders}"
                ),
                format!(
                    "the glider reads `mafiles/{file_name}` beside the `missions` folder; \
                     name another folder with `--mafiles DIR` or `mafiles` in gloc.toml"
                ),
            )
        }
        Some(NotLoaded::Unreadable { path, reason }) => (
            format!(
                "cannot read mission argument file `{}`: {reason}",
                path.display()
            ),
            "put a regular file in the mission's `mafiles` folder, or name a \
             folder of your own with `--mafiles DIR`"
                .to_string(),
        ),
    };
    Diagnostic::error(CANNOT_READ_MA, span, message).with_help(help)
}

fn unknown_spec(keyword: Word<'_>) -> BehaviorSpec {
    BehaviorSpec::for_behavior(
        None,
        "",
        Location {
            file: 0,
            span: keyword.span(),
        },
    )
}

impl Mission {
    /// The behaviors to fly: without the placeholders that unknown `behavior:` blocks
    /// leave (they keep later `b_arg:` lines from attaching to the previous behavior).
    pub fn known_behaviors(&self) -> impl Iterator<Item = &BehaviorSpec> {
        self.behaviors
            .iter()
            .filter(|spec| spec.kind != BehaviorKind::Unknown)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_sensors_behaviors_and_args() {
        let mission = Mission::parse(
            "m.mi",
            "# comment\nsensor: u_cycle_time(sec) 4.0 # four\nbehavior: abend\n  b_arg: overdepth(m) 30\nbehavior: yo\n\tb_arg: d_target_depth(m) 25\n",
        );
        assert!(mission.diagnostics.is_empty(), "{:?}", mission.rendered());
        assert_eq!(mission.name, "M.MI");
        assert_eq!(mission.sensor_settings[0].name, "u_cycle_time");
        assert_eq!(mission.sensor_settings[0].value, 4.0);
        assert_eq!(mission.behaviors.len(), 2);
        assert_eq!(mission.behaviors[0].kind, BehaviorKind::Abend);
        assert_eq!(mission.behaviors[0].arg("overdepth"), Some(30.0));
        assert_eq!(mission.behaviors[1].arg("d_target_depth"), Some(25.0));
    }

    /// Asserts that the mission's diagnostics, rendered, are as many as `starts` and
    /// begin with them in order; returns them for further checks.
    fn assert_messages(mission: &Mission, starts: &[&str]) -> Vec<String> {
        let messages = mission.rendered();
        assert_eq!(messages.len(), starts.len(), "{messages:?}");
        for (message, start) in messages.iter().zip(starts) {
            assert!(
                message.starts_with(start),
                "{message}\nshould start with {start}"
            );
        }
        messages
    }

    /// Loads `/m/missions/x.mi` holding `mi`; every other file read (the `.ma` files)
    /// holds `ma`, or is not found when `ma` is `None`.
    fn load_x_mi(mi: &str, ma: Option<&str>) -> Mission {
        Mission::load_with(Path::new("/m/missions/x.mi"), &mut |path: &Path| match (
            path.ends_with("x.mi"),
            ma,
        ) {
            (true, _) => Ok(mi.to_string()),
            (false, Some(ma)) => Ok(ma.to_string()),
            (false, None) => Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "not found",
            )),
        })
    }

    #[test]
    fn malformed_value_gives_line_and_column() {
        let mission = Mission::parse(
            "bad.mi",
            "behavior: abend\n    b_arg: overdepth(m) thirty\n",
        );
        // `thirty` starts at column 25 of line 2 (4 spaces + `b_arg: ` + `overdepth(m) `).
        assert_messages(
            &mission,
            &["bad.mi:2:25: error[S0015]: `thirty` is not a number"],
        );
        assert!(mission.has_errors());
    }

    #[test]
    fn missing_units_and_unexpected_lines_are_errors() {
        let mission = Mission::parse(
            "bad.mi",
            "behavior: yo\nb_arg: d_target_depth 25\nfly fast\n",
        );
        assert_messages(
            &mission,
            &["bad.mi:2:8: error[S0011]", "bad.mi:3:1: error[S0003]"],
        );
    }

    #[test]
    fn unknown_behavior_and_argument_are_warnings_with_line() {
        let mission = Mission::parse(
            "w.mi",
            "behavior: yo\n  b_arg: bogus(m) 1\nbehavior: teleport\n  b_arg: where(m) 3\nbehavior: abend\n  b_arg: overdepth(m) 30\n",
        );
        assert_messages(
            &mission,
            &[
                "w.mi:2:3: warning[S0103]: unknown argument `bogus`",
                "w.mi:3:11: warning[S0101]: unknown behavior `teleport`",
            ],
        );
        assert!(!mission.has_errors());
        let kinds: Vec<_> = mission.known_behaviors().map(|spec| spec.kind).collect();
        assert_eq!(kinds, vec![BehaviorKind::Yo, BehaviorKind::Abend]);
        // The argument under the unknown behavior did not attach to `yo`.
        assert_eq!(mission.behaviors[0].args.len(), 0);
    }

    #[test]
    fn missing_ma_file_is_an_error_naming_it() {
        let mission = load_x_mi("behavior: yo\n  b_arg: args_from_file(enum) 12\n", None);
        let messages = assert_messages(&mission, &["/m/missions/x.mi:2:3"]);
        assert!(messages[0].contains("error[S0004]"), "{}", messages[0]);
        // `args_from_file 12` asks for `yo12.ma`; a reader that cannot list folders
        // tries `mafiles/` beside `missions/`, then the mission's own folder.
        assert!(
            messages[0].contains(
                "cannot find mission argument file `yo12.ma` (in any case) in \
                 `/m/mafiles`, `/m/missions`"
            ),
            "{}",
            messages[0]
        );
    }

    #[test]
    fn ma_args_merge_and_bad_ma_lines_name_the_ma_file() {
        let mission = load_x_mi(
            "behavior: yo\n  b_arg: args_from_file(enum) 3\n",
            Some("behavior_name=Yo\n<start:b_arg>\n b_arg: d_target_depth(m) 17\n b_arg: c_target_depth(m) x\n<end:b_arg>\n"),
        );
        assert_messages(&mission, &["/m/mafiles/yo03.ma:4:27: error[S0015]"]);
        assert_eq!(mission.behaviors[0].arg("d_target_depth"), Some(17.0));
    }

    #[test]
    fn an_args_file_alone_is_parsed_as_its_behavior_loads_it() {
        let text = "behavior_name=Yo\n<start:b_arg>\n\tb_arg: d_target_depth(m) 50\n\tb_arg: args_from_file(enum) 3\n<end:b_arg>\n";
        let mission = Mission::parse_args_file("yo10.ma", text);
        // The nested args_from_file is the one problem, on line 4 (a tab, then `b_arg:`).
        assert_messages(&mission, &["yo10.ma:4:2: warning[S0102]"]);
        assert_eq!(mission.behaviors.len(), 1);
        assert_eq!(mission.behaviors[0].kind, BehaviorKind::Yo);
        assert_eq!(mission.behaviors[0].arg("d_target_depth"), Some(50.0));
        // The section runs from `<start:b_arg>` (byte 17) to the end of `<end:b_arg>`.
        assert_eq!(
            mission.sections,
            vec![Location {
                file: 0,
                span: Span::new(17, text.len() - 1)
            }]
        );
    }

    #[test]
    fn an_args_file_naming_an_unknown_behavior_is_warned_at_the_name() {
        let mission = Mission::parse_args_file(
            "x.ma",
            "behavior_name=drift_at_dept\n<start:b_arg>\nb_arg: foo(m) 1\n<end:b_arg>\n",
        );
        // `drift_at_dept` starts after `behavior_name=` (14 characters): column 15.
        let messages = assert_messages(
            &mission,
            &["x.ma:1:15: warning[S0101]: unknown behavior `drift_at_dept`"],
        );
        assert!(
            messages[0].ends_with("(help: did you mean `drift_at_depth`?)"),
            "{}",
            messages[0]
        );
        let missing = Mission::parse_args_file("y.ma", "<start:b_arg>\n<end:b_arg>\n");
        assert!(
            missing
                .rendered()
                .iter()
                .any(|message| message.contains("warning[S0105]")),
            "{:?}",
            missing.rendered()
        );
    }

    #[test]
    fn a_loaded_args_file_knows_the_line_that_loaded_it() {
        let mission = load_x_mi(
            "behavior: yo\n  b_arg: args_from_file(enum) 3\n",
            Some("behavior_name=yo\n<start:b_arg>\n<end:b_arg>\n"),
        );
        assert_messages(&mission, &[]);
        assert_eq!(mission.sources[0].loaded_at, None);
        // `b_arg: args_from_file(enum) 3` is bytes 15..44 of the mission.
        assert_eq!(mission.sources[1].loaded_at, Some(Span::new(15, 44)));
        assert!(mission.sources[1].path.ends_with("mafiles/yo03.ma"));
    }

    #[test]
    fn garbage_never_panics() {
        for text in [
            "\0\u{1}\u{2}",
            "b_arg:",
            "sensor: (",
            "sensor: a(",
            "behavior:",
            "sensor: x(m) 1 2",
            "b_arg: a(m) 1",
            "\u{feff}é(",
            "behavior: yo\nb_arg: a(b)c 1",
            "<start:waypoints>\n1e308 -1e308 | é\n",
            "behavior: goto_list\nb_arg: num_waypoints(nodim) 1e300\nb_arg: wpt_units_0(enum) 2\nb_arg: wpt_x_0(X) 1e300\nb_arg: wpt_y_0(X) -1e300\nbad",
            "behavior: yo\nb_arg: d_target_depth(m) 1e300\nb_arg: c_target_depth(m) -1e300\nb_arg: args_from_file(enum) 1e300\nbad",
        ] {
            let mission = Mission::parse("g.mi", text);
            let _ = mission.render_plain();
            let _ = mission.check(&SensorList::embedded());
            let args = Mission::parse_args_file("g.ma", text);
            let _ = args.render_plain();
            let _ = args.check(&SensorList::embedded());
            assert!(mission.has_errors(), "{text:?} should be an error");
        }
    }
}
