//! Sensor-list identity: a GLOC file names sensors by index, and indices differ
//! between gliders, so a file may state the list its indices were written for
//! (`# sensors: 813b137d`, a comment line before the first statement). Checked
//! against another list, every index whose name differs is an error (E0113); a file
//! that states nothing, checked against a list other than the embedded one, gets one
//! warning (W0114); a stated list that cannot be found, one warning (W0115).

use crate::diagnostic::{Diagnostic, Span};
use crate::gloc::ast::{self, LineKind, OperandKind, OperandShape};
use crate::gloc::Parsed;
use crate::sensors::{is_crc, SensorList, EMBEDDED_CRC};

/// The codes of this check (E0113, W0114, W0115).
pub const CODES: [&str; 3] = [
    crate::codes::gloc::INDEX_NAMES_ANOTHER_SENSOR,
    crate::codes::gloc::LIST_NOT_STATED,
    crate::codes::gloc::LIST_NOT_VERIFIED,
];

/// What a file's `# sensors: CRC` line says.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StatedList {
    /// Lower-case hex.
    pub crc: String,
    /// The CRC as written.
    pub span: Span,
}

/// The keyword of the line, after `#` and spaces.
const KEYWORD: &str = "sensors:";

/// The `# sensors: CRC` line of a parsed file: the first comment-only line before the
/// first statement whose comment starts `# sensors:`. A malformed one (not eight hex
/// digits) is `Err` with the span of what follows the keyword.
pub fn stated_list(parsed: &Parsed) -> Option<Result<StatedList, Span>> {
    for line in &parsed.file.lines {
        if line.kind.is_statement() {
            return None;
        }
        let (LineKind::Blank, Some(comment)) = (&line.kind, &line.comment) else {
            continue;
        };
        let comment_start = line.span.end as usize - comment.len();
        let body = comment.trim_start_matches('#');
        let after_hash = comment.len() - body.len();
        let trimmed = body.trim_start();
        if !trimmed
            .get(..KEYWORD.len())
            .is_some_and(|word| word.eq_ignore_ascii_case(KEYWORD))
        {
            continue;
        }
        let value = &trimmed[KEYWORD.len()..];
        let value_trimmed = value.trim();
        let value_start = comment_start
            + after_hash
            + (body.len() - trimmed.len())
            + KEYWORD.len()
            + (value.len() - value.trim_start().len());
        let span = Span::new(value_start, value_start + value_trimmed.len());
        return Some(if is_crc(value_trimmed) {
            Ok(StatedList {
                crc: value_trimmed.to_ascii_lowercase(),
                span,
            })
        } else {
            Err(span)
        });
    }
    None
}

/// The CRC a GLOC text's `# sensors:` line states, by a light scan of the lines
/// before the first statement (for callers that must find that list before
/// checking: they look for `<crc>.cac`). `None` for no line or a malformed one.
pub fn stated_crc(text: &str) -> Option<String> {
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let Some(comment) = line.strip_prefix('#') else {
            let word = line.split_whitespace().next().unwrap_or("");
            if ast::DirectiveKind::from_keyword(word).is_some() {
                continue;
            }
            return None;
        };
        let comment = comment.trim_start_matches('#').trim_start();
        if let Some(word) = comment.get(..KEYWORD.len()) {
            if word.eq_ignore_ascii_case(KEYWORD) {
                let value = comment[KEYWORD.len()..].trim();
                return is_crc(value).then(|| value.to_ascii_lowercase());
            }
        }
    }
    None
}

/// The list `text`'s `# sensors: CRC` line names, when it is a third list (neither
/// `active` nor the embedded one, which the checker knows) and `<crc>.cac` is in one
/// of `folders` and loads without errors. The one search the CLI, the language server
/// and the debugger share; `None` otherwise (the checker then says W0115).
pub fn find_written_for(
    text: &str,
    active: &SensorList,
    folders: &[std::path::PathBuf],
) -> Option<std::sync::Arc<SensorList>> {
    let crc = stated_crc(text)?;
    if active.crc() == Some(crc.as_str()) || crc == EMBEDDED_CRC {
        return None;
    }
    let path = crate::sensors::find_cac(&crc, folders)?;
    let loaded =
        crate::sensors::load_sensor_file(&path, crate::sensors::SensorOrder::FileOrder).ok()?;
    let clean = !loaded.diagnostics.iter().any(Diagnostic::is_error);
    clean.then(|| std::sync::Arc::new(loaded.list))
}

/// The folders [`find_written_for`] searches, in order: beside the script, beside
/// the active list's file, then the sensor cache folder (`sensor_cache` in gloc.toml).
pub fn list_folders(
    script: Option<&std::path::Path>,
    active_list: Option<&std::path::Path>,
    sensor_cache: Option<&std::path::Path>,
) -> Vec<std::path::PathBuf> {
    let beside = |file: &std::path::Path| match file.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let mut folders: Vec<std::path::PathBuf> = [script, active_list]
        .into_iter()
        .flatten()
        .map(beside)
        .collect();
    folders.extend(sensor_cache.map(std::path::Path::to_path_buf));
    folders.dedup();
    folders
}

/// The identity diagnostics of a file checked against `active`. `written_for` is the
/// list the file states, when the caller found it (the embedded list needs no caller).
pub fn check_identity(
    parsed: &Parsed,
    active: &SensorList,
    written_for: Option<&SensorList>,
) -> Vec<Diagnostic> {
    let sensor_operands: Vec<(i64, Span)> = sensor_operands(&parsed.file).collect();
    let stated = match stated_list(parsed) {
        Some(Ok(stated)) => stated,
        Some(Err(span)) => {
            return vec![Diagnostic::warning(
                crate::codes::gloc::LIST_NOT_VERIFIED,
                span,
                "`# sensors:` names a sensor list by its CRC, eight hex digits such as `813b137d`; \
                 the sensor indices were not verified by name",
            )
            .with_help("write the `sensor_list_crc` of the glider's list, as in `# sensors: 1f35be3b`")];
        }
        None => {
            if active.crc() == Some(EMBEDDED_CRC) {
                return Vec::new();
            }
            let Some(&(_, span)) = sensor_operands.first() else {
                return Vec::new();
            };
            return vec![Diagnostic::warning(
                crate::codes::gloc::LIST_NOT_STATED,
                span,
                format!(
                    "the sensor indices were not verified by name: this file does not say which \
                     sensor list they were written for, and {} is not the embedded list ({EMBEDDED_CRC})",
                    active.label()
                ),
            )
            .with_help(
                "state the list on the first line, e.g. `# sensors: 813b137d`; \
                 `gloc reindex FILE --from LIST --to LIST` rewrites indices by name",
            )];
        }
    };
    if active.crc() == Some(stated.crc.as_str()) {
        return Vec::new();
    }
    let original = if stated.crc == EMBEDDED_CRC {
        SensorList::embedded_shared()
    } else {
        match written_for.filter(|list| list.crc() == Some(stated.crc.as_str())) {
            Some(list) => list,
            None => {
                return vec![Diagnostic::warning(
                    crate::codes::gloc::LIST_NOT_VERIFIED,
                    stated.span,
                    format!(
                        "this file's indices were written for sensor list {}, which was not found; \
                         they were not verified by name",
                        stated.crc
                    ),
                )
                .with_help(format!(
                    "put `{}.cac` beside the script or in the sensor cache folder",
                    stated.crc
                ))];
            }
        }
    };
    let mut diagnostics = Vec::new();
    for (index, span) in sensor_operands {
        let Some(id) = u32::try_from(index).ok().map(crate::sensors::SensorId) else {
            continue;
        };
        let (Some(was), Some(is)) = (original.name(id), active.name(id)) else {
            continue;
        };
        if was.eq_ignore_ascii_case(is) {
            continue;
        }
        let help = match active.lookup(was) {
            Some(there) => format!(
                "in {} `{was}` is index {}; `gloc reindex` rewrites every index by name",
                active.label(),
                there.0
            ),
            None => format!("{} has no sensor `{was}`", active.label()),
        };
        diagnostics.push(
            Diagnostic::error(
                crate::codes::gloc::INDEX_NAMES_ANOTHER_SENSOR,
                span,
                format!(
                    "index {index} is `{was}` in {} but `{is}` in {}",
                    stated.crc,
                    active.label()
                ),
            )
            .with_help(help)
            .with_label(stated.span, "the list the indices were written for"),
        );
    }
    diagnostics
}

/// Every sensor operand (`loads 444,r0`, `stores r3,1387`) with its span.
pub fn sensor_operands(file: &ast::File) -> impl Iterator<Item = (i64, Span)> + '_ {
    file.lines.iter().flat_map(|line| {
        let operands: &[ast::Operand] = match &line.kind {
            LineKind::Instruction(instruction) => &instruction.operands,
            _ => &[],
        };
        let shapes: &[OperandShape] = match &line.kind {
            LineKind::Instruction(instruction) => instruction.opcode.signature(),
            _ => &[],
        };
        operands
            .iter()
            .zip(shapes)
            .filter_map(|(operand, shape)| match (shape, &operand.kind) {
                (OperandShape::Sensor, OperandKind::Integer(index)) => Some((*index, operand.span)),
                _ => None,
            })
    })
}

/// Rewrites every sensor index of `text` from the list `from` to the list `to` by
/// name, and states `to` in the `# sensors:` line (replaced, or inserted as the first
/// line; removed when `to` has no CRC). Refused, with one E0116 per index, when a
/// name is missing from `to` or an index from `from`; refused when the file has
/// syntax errors (a line that did not parse could hide an index).
pub fn reindex(
    text: &str,
    parsed: &Parsed,
    from: &SensorList,
    to: &SensorList,
) -> Result<String, Vec<Diagnostic>> {
    let syntax: Vec<Diagnostic> = parsed
        .diagnostics
        .iter()
        .filter(|diagnostic| diagnostic.is_error())
        .cloned()
        .collect();
    if !syntax.is_empty() {
        return Err(syntax);
    }
    let mut edits: Vec<(Span, String)> = Vec::new();
    let mut problems = Vec::new();
    for (index, span) in sensor_operands(&parsed.file) {
        let name = u32::try_from(index)
            .ok()
            .and_then(|index| from.name(crate::sensors::SensorId(index)));
        let Some(name) = name else {
            problems.push(Diagnostic::error(
                crate::codes::gloc::REINDEX_NAME_MISSING,
                span,
                format!(
                    "index {index} is not in {} ({} sensors): nothing to rewrite it by",
                    from.label(),
                    from.len()
                ),
            ));
            continue;
        };
        match to.lookup(name) {
            Some(id) => edits.push((span, id.0.to_string())),
            None => problems.push(
                Diagnostic::error(
                    crate::codes::gloc::REINDEX_NAME_MISSING,
                    span,
                    format!(
                        "index {index} is `{name}` in {}, and {} has no sensor `{name}`",
                        from.label(),
                        to.label()
                    ),
                )
                .with_help("this script needs a sensor the target glider does not have"),
            ),
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    match (stated_line_span(parsed), to.crc()) {
        (Some(line), Some(crc)) => edits.push((line, format!("# sensors: {crc}"))),
        (Some(line), None) => edits.push((line, String::new())),
        (None, Some(crc)) => edits.push((Span::new(0, 0), format!("# sensors: {crc}\n"))),
        (None, None) => {}
    }
    edits.sort_by_key(|(span, _)| span.start);
    let mut out = String::with_capacity(text.len() + 24);
    let mut at = 0usize;
    for (span, replacement) in edits {
        let (start, end) = (span.start as usize, span.end as usize);
        out.push_str(text.get(at..start).unwrap_or(""));
        out.push_str(&replacement);
        at = end;
    }
    out.push_str(text.get(at..).unwrap_or(""));
    Ok(out)
}

/// The whole `# sensors:` line, its line end included (to replace or remove it).
fn stated_line_span(parsed: &Parsed) -> Option<Span> {
    let stated = stated_list(parsed)?;
    let span = match stated {
        Ok(stated) => stated.span,
        Err(span) => span,
    };
    let line = parsed
        .file
        .lines
        .iter()
        .find(|line| line.span.start <= span.start && span.end <= line.span.end)?;
    Some(line.span)
}
