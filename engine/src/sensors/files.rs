//! Readers for sensor-list files: the masterdata text file (`sensor:` lines
//! plus `behavior:` default sections) and the `.cac` sensor-list cache
//! (`s: T|F INDEX COLUMN BYTES NAME UNITS`).

use std::collections::HashMap;
use std::path::Path;

use crate::diagnostic::{Diagnostic, Span};
use crate::sensors::{BehaviorDefaults, Sensor, SensorList, Setting};

/// How sensor indices follow from a masterdata file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SensorOrder {
    /// Indices follow the file (firmware before 2014; the paper's era).
    #[default]
    FileOrder,
    /// Indices follow the names sorted after upper-casing (firmware 2014 and later).
    SortedByName,
}

impl SensorOrder {
    /// The names a user writes (`--sensor-order`, `sensor_order` in gloc.toml).
    pub const NAMES: &'static str =
        "`file` (firmware before 2014) or `sorted` (firmware 2014 and later)";

    /// `file` or `sorted`, as a user writes it.
    pub fn from_name(name: &str) -> Option<SensorOrder> {
        match name {
            "file" => Some(SensorOrder::FileOrder),
            "sorted" => Some(SensorOrder::SortedByName),
            _ => None,
        }
    }
}

/// The most sensors a masterdata or `.cac` file may list (E0208, E0206). Real lists
/// have 1,400 to 3,000; the cap keeps a hostile file from taking gigabytes and
/// minutes (10 million `sensor:` lines did).
pub const MAX_SENSORS: usize = 65_536;

/// A sensor list read from a file, with what went wrong reading it.
#[derive(Clone, Debug)]
pub struct LoadedSensorList {
    pub list: SensorList,
    pub diagnostics: Vec<Diagnostic>,
    /// The file's text (lossily decoded), for rendering the diagnostics.
    pub text: String,
    /// The hook sensors the file lacked, appended after its last index.
    pub added_hook_sensors: Vec<&'static str>,
}

/// Reads a masterdata or `.cac` file: `.cac` by extension, or by content
/// when the first meaningful line starts with `s:`.
pub fn load_sensor_file(path: &Path, order: SensorOrder) -> std::io::Result<LoadedSensorList> {
    let is_ccc = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("ccc"));
    let text = if is_ccc {
        // A compressed `.cac` (newer gliders): LZ4 blocks, each after its 2-byte length.
        let bytes = crate::files::read(path, crate::files::SENSOR_LIST)?;
        let bytes = crate::lz4::decompress_all(&bytes, crate::files::SENSOR_LIST.bytes).map_err(
            |problem| {
                std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                        "not a compressed sensor list: the LZ4 block at byte {}: {}",
                        problem.block, problem.message
                    ),
                )
            },
        )?;
        String::from_utf8_lossy(&bytes).into_owned()
    } else {
        crate::files::read_text(path, crate::files::SENSOR_LIST)?
    };
    let is_cac = is_ccc
        || path
            .extension()
            .is_some_and(|extension| extension.eq_ignore_ascii_case("cac"))
        || looks_like_cac(&text);
    if !has_list_line(&text) {
        // Not a sensor list at all (`/etc/passwd`, a secret): one error, and none of
        // its lines quoted, since a diagnostic shows its line.
        return Ok(LoadedSensorList {
            list: SensorList::from_sensors(Vec::new()),
            diagnostics: vec![Diagnostic::error(
                crate::codes::sensors::NO_SENSORS,
                Span::new(0, 0),
                format!(
                    "`{}` is not a sensor list: none of its lines starts with `sensor:` (masterdata) or `s:` (.cac), so none is shown",
                    path.display()
                ),
            )
            .with_help("name the glider's masterdata or a `<crc>.cac` file")],
            text: String::new(),
            added_hook_sensors: Vec::new(),
        });
    }
    let (mut list, diagnostics) = if is_cac {
        parse_cac(&text)
    } else {
        parse_masterdata(&text, order)
    };
    // A `.cac` file is named by the CRC of its list (`1f35be3b.cac`).
    if let Some(crc) = path
        .file_stem()
        .and_then(|stem| stem.to_str())
        .filter(|stem| is_crc(stem))
    {
        list = list.with_crc(crc);
    }
    let added_hook_sensors = if list.is_empty() {
        Vec::new()
    } else {
        list.add_hook_sensors()
    };
    Ok(LoadedSensorList {
        list,
        diagnostics,
        text,
        added_hook_sensors,
    })
}

/// Whether any line of `text` is a sensor-list line (`sensor:` or `s:`).
fn has_list_line(text: &str) -> bool {
    text.lines().any(|line| {
        let line = line.trim_start();
        line.starts_with("sensor:") || line.starts_with("s:")
    })
}

/// Whether a sensor list's text is a `.cac` list (its first meaningful line starts
/// with `s:`) rather than masterdata.
pub fn looks_like_cac(text: &str) -> bool {
    text.lines()
        .map(str::trim)
        .find(|line| !line.is_empty())
        .is_some_and(|line| line.starts_with("s:"))
}

/// The first `<crc>.cac` (or `.CAC`, or the compressed `.ccc`) in `folders`, in order.
pub fn find_cac(crc: &str, folders: &[std::path::PathBuf]) -> Option<std::path::PathBuf> {
    folders.iter().find_map(|folder| {
        [
            format!("{}.cac", crc.to_ascii_lowercase()),
            format!("{}.cac", crc.to_ascii_uppercase()),
            format!("{}.CAC", crc.to_ascii_uppercase()),
            format!("{}.ccc", crc.to_ascii_lowercase()),
            format!("{}.CCC", crc.to_ascii_uppercase()),
        ]
        .into_iter()
        .map(|name| folder.join(name))
        .find(|path| path.is_file())
    })
}

/// True for a sensor-list CRC as gliders write it: eight hex digits.
pub fn is_crc(text: &str) -> bool {
    text.len() == 8 && text.bytes().all(|byte| byte.is_ascii_hexdigit())
}

/// Parses a masterdata file. Never fails: malformed lines are diagnostics
/// and are skipped.
pub fn parse_masterdata(text: &str, order: SensorOrder) -> (SensorList, Vec<Diagnostic>) {
    let mut reader = MasterdataReader::default();
    let mut in_block_comment = false;
    let mut offset = 0usize;
    for (index, raw) in text.split_inclusive('\n').enumerate() {
        let line = raw.trim_end_matches(['\n', '\r']);
        let at = LineAt {
            number: index as u32 + 1,
            base: offset,
            indent: line.len() - line.trim_start().len(),
            length: line.len(),
        };
        offset += raw.len();
        let trimmed = line.trim();
        if trimmed.is_empty() {
            reader.continues = None;
            continue;
        }
        if is_preprocessor(trimmed) {
            continue;
        }
        // The release masterdata wraps its change log and its body in C comments
        // (`/*` … `*/`) and ends with `END`: the firmware reads the `sensor:`,
        // `behavior:` and `b_arg:` lines and passes over the rest. Other text inside
        // a `/* */` block is comment; after `END` nothing is read.
        if trimmed.starts_with("/*") {
            in_block_comment = !trimmed.ends_with("*/") || trimmed.len() < 4;
            reader.continues = None;
            continue;
        }
        if trimmed.starts_with("*/") || trimmed.ends_with("*/") && in_block_comment {
            in_block_comment = false;
            reader.continues = None;
            continue;
        }
        if trimmed == "END" {
            break;
        }
        if let Some(comment) = trimmed.strip_prefix('#') {
            reader.comment_line(comment);
            continue;
        }
        // `keyword: body`; a line without a colon has no keyword (and its first byte may
        // be inside a character, so nothing is sliced at a guessed offset).
        let (keyword, body) = trimmed.split_once(':').unwrap_or(("", ""));
        let body_start = at.base + at.indent + keyword.len() + 1;
        reader.continues = None;
        match keyword {
            "sensor" => {
                if !reader.sensor_line(&at, body, body_start) {
                    break;
                }
            }
            "behavior" => reader.behavior_line(&at, body),
            "b_arg" => reader.arg_line(&at, body, body_start),
            _ if in_block_comment => {}
            _ => reader.diagnostics.push(Diagnostic::warning(
                crate::codes::sensors::NOT_MASTERDATA,
                at.span(),
                "line ignored: a masterdata line starts with `sensor:`, `behavior:`, `b_arg:` or `#`",
            )),
        }
    }
    reader.finish(order)
}

/// Where a masterdata line is: its number, its first byte, its indentation and length.
struct LineAt {
    number: u32,
    base: usize,
    indent: usize,
    length: usize,
}

impl LineAt {
    /// The line's text, without its indentation.
    fn span(&self) -> Span {
        Span::new(self.base + self.indent, self.base + self.length)
    }
}

/// What a masterdata file has given so far, line by line.
#[derive(Default)]
struct MasterdataReader {
    diagnostics: Vec<Diagnostic>,
    sensors: Vec<Sensor>,
    behaviors: Vec<BehaviorDefaults>,
    first_line_of: HashMap<String, (u32, Span)>,
    /// What a following `# …` line continues: a sensor, a b_arg, or nothing.
    continues: Option<Continuation>,
}

impl MasterdataReader {
    /// A `# …` line: more of the description (and `#!` limits) of what it continues.
    fn comment_line(&mut self, comment: &str) {
        let Some(target) = self.continues else {
            return;
        };
        let setting = match target {
            Continuation::Sensor(at) => self.sensors.get_mut(at),
            Continuation::Arg(behavior, arg) => self
                .behaviors
                .get_mut(behavior)
                .and_then(|behavior| behavior.args.get_mut(arg)),
        };
        if let Some(setting) = setting {
            apply_comment(comment, setting);
        }
    }

    /// A `sensor:` line; `false` when the list is full and the rest is not read.
    fn sensor_line(&mut self, at: &LineAt, body: &str, body_start: usize) -> bool {
        if self.sensors.len() == MAX_SENSORS {
            self.diagnostics.push(Diagnostic::error(
                crate::codes::sensors::TOO_MANY_SENSORS,
                at.span(),
                format!("more than {MAX_SENSORS} sensors: the rest of the file is not read"),
            ));
            return false;
        }
        let mut entry = match entry_line(body, body_start) {
            Ok(entry) => entry,
            Err(diagnostic) => {
                self.diagnostics.push(*diagnostic);
                return true;
            }
        };
        self.diagnostics.extend(entry.stray.take());
        let span = entry.name_span;
        let key = entry.name.to_ascii_lowercase();
        if let Some((first_line, first_span)) = self.first_line_of.get(&key) {
            self.diagnostics.push(
                Diagnostic::warning(
                    crate::codes::sensors::DUPLICATE_SENSOR,
                    span,
                    format!(
                        "sensor `{}` is declared again (first on line {first_line}); \
                         lookups by name use line {first_line}",
                        entry.name
                    ),
                )
                .with_label(*first_span, "first declared here"),
            );
        } else {
            self.first_line_of.insert(key, (at.number, span));
        }
        self.sensors.push(entry.into_setting(at.number));
        self.continues = Some(Continuation::Sensor(self.sensors.len() - 1));
        true
    }

    /// A `behavior: NAME [# description]` line: a new section of `b_arg:`s.
    fn behavior_line(&mut self, at: &LineAt, body: &str) {
        let (name, comment) = match body.split_once('#') {
            Some((name, comment)) => (name.trim(), Some(comment)),
            None => (body.trim(), None),
        };
        let description = comment
            .filter(|comment| !comment.starts_with('!'))
            .map(str::trim)
            .filter(|comment| !comment.is_empty())
            .map(str::to_string);
        if name.is_empty() {
            self.diagnostics.push(Diagnostic::error(
                crate::codes::sensors::BAD_MASTERDATA_LINE,
                at.span(),
                "expected a behavior name after `behavior:`",
            ));
            return;
        }
        self.behaviors.push(BehaviorDefaults {
            name: name.to_string(),
            description,
            line: at.number,
            args: Vec::new(),
        });
    }

    /// A `b_arg: NAME(UNITS) [DEFAULT] [# comment]` line of the current behavior.
    fn arg_line(&mut self, at: &LineAt, body: &str, body_start: usize) {
        let Some(behavior_index) = self.behaviors.len().checked_sub(1) else {
            self.diagnostics.push(Diagnostic::warning(
                crate::codes::sensors::NOT_MASTERDATA,
                at.span(),
                "`b_arg:` outside a `behavior:` section is ignored",
            ));
            return;
        };
        let mut entry = match entry_line(body, body_start) {
            Ok(entry) => entry,
            Err(diagnostic) => {
                self.diagnostics.push(*diagnostic);
                return;
            }
        };
        self.diagnostics.extend(entry.stray.take());
        let behavior = &mut self.behaviors[behavior_index];
        behavior.args.push(entry.into_setting(at.number));
        self.continues = Some(Continuation::Arg(behavior_index, behavior.args.len() - 1));
    }

    /// The list, sorted as `order` says, and every diagnostic.
    fn finish(mut self, order: SensorOrder) -> (SensorList, Vec<Diagnostic>) {
        if self.sensors.is_empty() {
            self.diagnostics.push(
                Diagnostic::error(
                    crate::codes::sensors::NO_SENSORS,
                    Span::new(0, 0),
                    "no `sensor:` lines found",
                )
                .with_help("a masterdata line reads `sensor: NAME(UNITS) [DEFAULT] [# comment]`"),
            );
        }
        if order == SensorOrder::SortedByName {
            // Stable, so duplicate names keep their file order.
            self.sensors
                .sort_by_cached_key(|sensor| sensor.name.to_ascii_uppercase());
        }
        (
            SensorList::from_sensors(self.sensors).with_behaviors(self.behaviors),
            self.diagnostics,
        )
    }
}

/// One line of a `.cac` sensor list: `s: T|F INDEX COLUMN BYTES NAME UNITS`.
#[derive(Clone, Debug, PartialEq)]
pub struct CacEntry {
    /// `T`: the sensor is logged (in this list's files).
    pub logged: bool,
    /// The sensor's index in the glider's list.
    pub index: u32,
    /// Its position in a binary log's cycle, or −1 when the log leaves it out.
    pub column: i64,
    /// Value size in a binary log: 1, 2, 4 or 8.
    pub bytes: u8,
    pub name: String,
    pub units: String,
    /// 1-based line in the text.
    pub line: u32,
    /// Byte span of the index field (for diagnostics about it).
    pub index_span: Span,
    /// Byte span of the name field.
    pub name_span: Span,
}

/// Parses the lines of a `.cac` sensor list (also the list embedded in a
/// binary log whose sensor list is not factored out). Never fails: a malformed
/// line is a diagnostic and is skipped. Index checks are the caller's.
pub fn parse_cac_entries(text: &str) -> (Vec<CacEntry>, Vec<Diagnostic>) {
    let mut diagnostics = Vec::new();
    let mut entries = Vec::new();
    let mut offset = 0usize;
    for (index, raw) in text.split_inclusive('\n').enumerate() {
        let line_number = index as u32 + 1;
        let line = raw.trim_end_matches(['\n', '\r']);
        let base = offset;
        offset += raw.len();
        if line.trim().is_empty() {
            continue;
        }
        let fields = fields_with_offsets(line);
        let field_span = |position: usize| {
            fields.get(position).map_or(
                Span::new(base + line.len(), base + line.len()),
                |(at, field)| Span::new(base + at, base + at + field.len()),
            )
        };
        let field = |position: usize| fields.get(position).map(|(_, field)| *field);
        if field(0) != Some("s:") {
            diagnostics.push(
                Diagnostic::error(
                    crate::codes::sensors::BAD_CAC_LINE,
                    field_span(0),
                    "expected a `.cac` line starting with `s:`",
                )
                .with_help("a `.cac` line reads `s: T|F INDEX COLUMN BYTES NAME UNITS`"),
            );
            continue;
        }
        let sensor_index = field(2).and_then(|value| value.parse::<u32>().ok());
        let column = field(3).and_then(|value| value.parse::<i64>().ok());
        let bytes = field(4).and_then(|value| match value {
            "1" | "2" | "4" | "8" => value.parse::<u8>().ok(),
            _ => None,
        });
        let problem = if !matches!(field(1), Some("T" | "F")) {
            Some((1, "expected `T` or `F` (logged or not)"))
        } else if sensor_index.is_none() {
            Some((2, "expected the sensor index, a whole number"))
        } else if column.is_none() {
            Some((3, "expected the column number (or -1)"))
        } else if bytes.is_none() {
            Some((4, "expected the byte size: 1, 2, 4 or 8"))
        } else if field(5).is_none() {
            Some((5, "expected the sensor name"))
        } else {
            None
        };
        if let Some((position, message)) = problem {
            diagnostics.push(
                Diagnostic::error(
                    crate::codes::sensors::BAD_CAC_LINE,
                    field_span(position),
                    message,
                )
                .with_help("a `.cac` line reads `s: T|F INDEX COLUMN BYTES NAME UNITS`"),
            );
            continue;
        }
        entries.push(CacEntry {
            logged: field(1) == Some("T"),
            index: sensor_index.unwrap_or(0),
            column: column.unwrap_or(-1),
            bytes: bytes.unwrap_or(4),
            name: field(5).unwrap_or_default().to_string(),
            units: field(6).unwrap_or("nodim").to_string(),
            line: line_number,
            index_span: field_span(2),
            name_span: field_span(5),
        });
    }
    (entries, diagnostics)
}

/// Parses a `.cac` sensor list. Indices come from the file and must be
/// 0, 1, 2, … without gaps or repeats.
pub fn parse_cac(text: &str) -> (SensorList, Vec<Diagnostic>) {
    let (entries, mut diagnostics) = parse_cac_entries(text);
    let mut slots: Vec<Option<Sensor>> = Vec::new();
    let mut spans: Vec<Span> = Vec::new();
    let mut first_line_of: HashMap<String, (u32, Span)> = HashMap::new();
    for entry in entries {
        let sensor_index = entry.index as usize;
        if sensor_index >= MAX_SENSORS {
            diagnostics.push(Diagnostic::error(
                crate::codes::sensors::BAD_CAC_INDICES,
                entry.index_span,
                format!(
                    "sensor index {sensor_index} is over the limit: a sensor list has at most \
                     {MAX_SENSORS} sensors"
                ),
            ));
            continue;
        }
        if slots.len() <= sensor_index {
            slots.resize(sensor_index + 1, None);
            spans.resize(sensor_index + 1, Span::default());
        }
        if slots[sensor_index].is_some() {
            diagnostics.push(
                Diagnostic::error(
                    crate::codes::sensors::BAD_CAC_INDICES,
                    entry.index_span,
                    format!("sensor index {sensor_index} appears twice"),
                )
                .with_label(spans[sensor_index], "first used here"),
            );
            continue;
        }
        let name = entry.name;
        let name_span = entry.name_span;
        let key = name.to_ascii_lowercase();
        if let Some((first_line, first_span)) = first_line_of.get(&key) {
            diagnostics.push(
                Diagnostic::warning(
                    crate::codes::sensors::DUPLICATE_SENSOR,
                    name_span,
                    format!("sensor `{name}` is listed again (first on line {first_line})"),
                )
                .with_label(*first_span, "first listed here"),
            );
        } else {
            first_line_of.insert(key, (entry.line, name_span));
        }
        spans[sensor_index] = entry.index_span;
        slots[sensor_index] = Some(Sensor::new(name, entry.units, entry.line));
    }
    if let Some(missing) = slots.iter().position(Option::is_none) {
        diagnostics.push(Diagnostic::error(
            crate::codes::sensors::BAD_CAC_INDICES,
            Span::new(0, 0),
            format!("sensor index {missing} is missing: indices must run 0, 1, 2, … without gaps"),
        ));
    }
    if slots.is_empty() {
        diagnostics.push(Diagnostic::error(
            crate::codes::sensors::NO_SENSORS,
            Span::new(0, 0),
            "no `s:` lines found",
        ));
    }
    let sensors: Vec<Sensor> = slots.into_iter().flatten().collect();
    (SensorList::from_sensors(sensors), diagnostics)
}

#[derive(Clone, Copy)]
enum Continuation {
    Sensor(usize),
    Arg(usize, usize),
}

/// `NAME(UNITS) [DEFAULT] [# comment]` after `sensor:` or `b_arg:`.
struct Entry<'a> {
    name: String,
    name_span: Span,
    units: String,
    default: Option<f64>,
    comment: Option<&'a str>,
    /// W0209: text after the default, which the glider ignores.
    stray: Option<Diagnostic>,
}

impl Entry<'_> {
    /// The setting the line gives on line `line`, its comment read.
    fn into_setting(self, line: u32) -> Setting {
        let mut setting = Setting {
            default: self.default,
            ..Setting::new(self.name, self.units, line)
        };
        if let Some(comment) = self.comment {
            apply_comment(comment, &mut setting);
        }
        setting
    }
}

fn entry_line(body: &str, base: usize) -> Result<Entry<'_>, Box<Diagnostic>> {
    let (code, comment) = match body.find('#') {
        Some(at) => (&body[..at], Some(&body[at + 1..])),
        None => (body, None),
    };
    let name_start = code.len() - code.trim_start().len();
    let help = "a masterdata line reads `sensor: NAME(UNITS) [DEFAULT] [# comment]`";
    let Some(open) = code.find('(') else {
        let end = code.trim_end().len().max(name_start);
        return Err(Box::new(
            Diagnostic::error(
                crate::codes::sensors::BAD_MASTERDATA_LINE,
                Span::new(base + name_start, base + end),
                "expected `NAME(UNITS)`: the units in parentheses are missing",
            )
            .with_help(help),
        ));
    };
    let Some(close) = code[open..].find(')').map(|at| open + at) else {
        return Err(Box::new(
            Diagnostic::error(
                crate::codes::sensors::BAD_MASTERDATA_LINE,
                Span::new(base + open, base + code.trim_end().len().max(open + 1)),
                "expected `)` after the units",
            )
            .with_help(help),
        ));
    };
    let name = code[name_start..open].trim();
    let name_span = Span::new(base + name_start, base + open);
    if name.is_empty()
        || !name
            .bytes()
            .all(|byte| byte.is_ascii_alphanumeric() || byte == b'_')
    {
        return Err(Box::new(
            Diagnostic::error(
                crate::codes::sensors::BAD_MASTERDATA_LINE,
                name_span,
                format!("`{name}` is not a sensor name (letters, digits and `_`)"),
            )
            .with_help(help),
        ));
    }
    let units = code[open + 1..close].trim().to_string();
    let rest = &code[close + 1..];
    let mut stray = None;
    let default_text = rest.trim();
    let default = if default_text.is_empty() {
        None
    } else {
        let first = default_text.split_whitespace().next().unwrap_or("");
        let at = close + 1 + (rest.len() - rest.trim_start().len());
        match first.parse::<f64>() {
            Ok(value) if default_text.split_whitespace().count() == 1 => Some(value),
            // The firmware reads the first number and ignores the rest of the line
            // (the 10.5 release masterdata has `sci_ocr507R_channel3(nodim)  0 0`).
            Ok(value) => {
                let extra_at = at + first.len();
                let extra = &code[extra_at..];
                let extra_start = extra_at + (extra.len() - extra.trim_start().len());
                let extra_end = close + 1 + rest.trim_end().len();
                stray = Some(
                    Diagnostic::warning(
                        crate::codes::sensors::STRAY_VALUE,
                        Span::new(base + extra_start, base + extra_end),
                        format!(
                            "`{}` after the default {first} is ignored, as the glider ignores it",
                            code[extra_start..extra_end].trim()
                        ),
                    )
                    .with_help("delete it, or start a comment with `#`"),
                );
                Some(value)
            }
            _ => {
                return Err(Box::new(
                    Diagnostic::error(
                        crate::codes::sensors::BAD_DEFAULT,
                        Span::new(base + at, base + at + default_text.len()),
                        format!("expected a number as the default, found `{default_text}`"),
                    )
                    .with_help(help),
                ))
            }
        }
    };
    Ok(Entry {
        name: name.to_string(),
        name_span,
        units,
        default,
        comment,
        stray,
    })
}

/// A comment after or below an entry: `#! key = value; …` metadata, or text
/// that becomes (part of) the description.
fn apply_comment(comment: &str, setting: &mut Setting) {
    if let Some(metadata) = comment.strip_prefix('!') {
        for pair in metadata.split(';') {
            let Some((key, value)) = pair.split_once('=') else {
                continue;
            };
            let value = value.trim().parse::<f64>().ok();
            match key.trim() {
                "min" => setting.allowed.min = value.or(setting.allowed.min),
                "max" => setting.allowed.max = value.or(setting.allowed.max),
                _ => {}
            }
        }
        apply_choices(metadata, &mut setting.allowed.choices);
        return;
    }
    let text = comment.trim();
    if text.is_empty() {
        return;
    }
    match &mut setting.description {
        Some(existing) => {
            existing.push(' ');
            existing.push_str(text);
        }
        None => setting.description = Some(text.to_string()),
    }
}

/// `#! choices = start_when([0, 1, 2])`: the numbers in the brackets. A `choices`
/// naming a list without giving it (`choices=use_pitch`) sets nothing.
fn apply_choices(metadata: &str, choices: &mut Option<Vec<f64>>) {
    for pair in metadata.split(';') {
        let Some((key, value)) = pair.split_once('=') else {
            continue;
        };
        if key.trim() != "choices" {
            continue;
        }
        let Some(list) = value
            .split_once('[')
            .and_then(|(_, rest)| rest.split_once(']'))
            .map(|(list, _)| list)
        else {
            continue;
        };
        let numbers: Option<Vec<f64>> = list
            .split(',')
            .map(|number| number.trim().parse::<f64>().ok())
            .collect();
        if let Some(numbers) = numbers.filter(|numbers| !numbers.is_empty()) {
            *choices = Some(numbers);
        }
    }
}

fn is_preprocessor(line: &str) -> bool {
    let Some(rest) = line.strip_prefix('#') else {
        return false;
    };
    let word = rest.split_whitespace().next().unwrap_or("");
    // `#if` must be followed by whitespace to tell it from a comment "#iffy".
    matches!(
        word,
        "if" | "ifdef" | "ifndef" | "else" | "elif" | "endif" | "define" | "undef" | "include"
    ) && !rest.starts_with(' ')
}

/// Whitespace-separated fields with their byte offsets in `line`.
fn fields_with_offsets(line: &str) -> Vec<(usize, &str)> {
    let mut fields = Vec::new();
    let mut start = None;
    for (at, character) in line.char_indices() {
        match (character.is_whitespace(), start) {
            (true, Some(from)) => {
                fields.push((from, &line[from..at]));
                start = None;
            }
            (false, None) => start = Some(at),
            _ => {}
        }
    }
    if let Some(from) = start {
        fields.push((from, &line[from..]));
    }
    fields
}
