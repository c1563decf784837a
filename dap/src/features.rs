//! The answers of the console and Watch requests (`completions`, `evaluate` with
//! children, `setExpression`), of `gotoTargets`/`goto` and of the exception filters'
//! conditions: DAP types in and out over the debugger and `edits`, so the handlers only
//! register them. Positions convert here: DAP columns are UTF-16 code units, 0- or
//! 1-based as the client said in `initialize`; the core works in byte offsets.

use crate::completion::{self, Kind};
use crate::debugger::{Debugger, ExceptionFilters, EXCEPTION_FILTERS};
use crate::edits;
use crate::error::{DebugError, DebugResult};
use crate::expr::{type_name, Watched};
use crate::format::ValueFormat;
use crate::references::{address, ARRAYS};
use crate::target::Target;
use crate::types::*;
use crate::world::World;

/// What the adapter keeps of `initialize`'s arguments, read straight from them: how the
/// client counts lines and columns (both 1-based unless it says otherwise) and whether
/// it shows progress. The rest (its ids, its other capabilities) changes nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub struct ClientOptions {
    pub lines_start_at1: bool,
    pub columns_start_at1: bool,
    pub supports_progress_reporting: bool,
}

impl Default for ClientOptions {
    fn default() -> Self {
        ClientOptions {
            lines_start_at1: true,
            columns_start_at1: true,
            supports_progress_reporting: false,
        }
    }
}

/// The format a request asked for.
pub fn value_format(format: Option<ValueFormatArgument>) -> ValueFormat {
    ValueFormat {
        hex: format.and_then(|format| format.hex).unwrap_or(false),
    }
}

pub fn exception_breakpoint_filters() -> Vec<ExceptionBreakpointsFilter> {
    EXCEPTION_FILTERS
        .iter()
        .map(|(filter, label, description, default)| ExceptionBreakpointsFilter {
            filter: (*filter).into(),
            label: (*label).into(),
            description: Some((*description).into()),
            default: Some(*default),
            supports_condition: Some(true),
            condition_description: Some(
                "a GBASIC expression over the state where it happens, e.g. `m_depth > 10` or `cycle > 100`"
                    .into(),
            ),
        })
        .collect()
}

/// `setExceptionBreakpoints`: the filters to stop on (`filters` and `filterOptions`
/// alike; a condition applies to its filter) and one breakpoint per entry of both
/// lists, in their order, unverified where the condition is not a valid expression
/// (`condition_error` says why, given the condition). An unknown filter is an error.
pub fn exception_filters(
    arguments: &SetExceptionBreakpointsArguments,
    condition_error: impl Fn(&str) -> Option<String>,
) -> DebugResult<(ExceptionFilters, Vec<Breakpoint>)> {
    let options = arguments.filter_options.clone().unwrap_or_default();
    let ids = arguments
        .filters
        .iter()
        .map(|filter| (filter.as_str(), None))
        .chain(
            options
                .iter()
                .map(|option| (option.filter_id.as_str(), option.condition.as_deref())),
        );
    let mut filters = ExceptionFilters::off();
    let mut breakpoints = Vec::new();
    for (id, condition) in ids {
        let condition = condition.filter(|text| !text.trim().is_empty());
        let Some(filter) = filters.by_id(id) else {
            return Err(DebugError::request(format!(
                "unknown exception filter `{id}` (known: {})",
                EXCEPTION_FILTERS.map(|(id, ..)| id).join(", ")
            )));
        };
        match condition.and_then(&condition_error) {
            Some(message) => breakpoints.push(Breakpoint {
                verified: false,
                message: Some(message),
                reason: Some("failed".into()),
                ..Breakpoint::default()
            }),
            None => {
                filter.enabled = true;
                filter.condition = condition.map(str::to_string);
                breakpoints.push(Breakpoint {
                    verified: true,
                    ..Breakpoint::default()
                });
            }
        }
    }
    Ok((filters, breakpoints))
}

/// `completions`: the names completing the word before `column` of the given line of
/// `text`, at most `completion::LIMIT`, in rank order (`sortText` keeps it).
pub fn completions(
    debugger: &Debugger<World>,
    arguments: &CompletionsArguments,
    client: ClientOptions,
) -> Vec<CompletionItem> {
    let line_index = arguments
        .line
        .map(|line| line.saturating_sub(i64::from(client.lines_start_at1)))
        .unwrap_or(0);
    let Some(line) = usize::try_from(line_index)
        .ok()
        .and_then(|index| arguments.text.split('\n').nth(index))
    else {
        return Vec::new();
    };
    let base = i64::from(client.columns_start_at1);
    let column = usize::try_from(arguments.column.saturating_sub(base)).unwrap_or(0);
    let cursor = byte_offset(line, column);
    let found = completion::complete(
        line,
        cursor,
        &edits::vocabulary(debugger),
        completion::LIMIT,
    );
    let start = utf16_len(&line[..found.start]) as i64 + base;
    let length = utf16_len(&line[found.start..found.start + found.length]) as i64;
    found
        .items
        .into_iter()
        .enumerate()
        .map(|(rank, item)| CompletionItem {
            ty: Some(
                match item.kind {
                    Kind::Variable | Kind::Array => "variable",
                    Kind::Constant => "value",
                    Kind::Builtin => "function",
                    Kind::UsedSensor | Kind::Sensor => "field",
                    Kind::Keyword => "keyword",
                }
                .into(),
            ),
            label: item.label,
            detail: Some(item.detail),
            sort_text: Some(format!("{rank:04}")),
            start: Some(start),
            length: Some(length),
        })
        .collect()
}

/// `evaluate`: a value written in the asked format, or, for an expression that names
/// an array (`tsum`), its elements as children. Every context gets the same text, the
/// shortest that reads back to the same value (`print`'s), which is its full precision.
pub fn evaluate(
    debugger: &Debugger<World>,
    arguments: &EvaluateArguments,
) -> DebugResult<EvaluateBody> {
    let format = value_format(arguments.format);
    match debugger.watch(&arguments.expression)? {
        Watched::Value(value) => Ok(EvaluateBody {
            result: format.number(value),
            ty: type_name(value).into(),
            variables_reference: 0,
            indexed_variables: None,
        }),
        Watched::Array { name, shown } => {
            let Some((position, array)) = edits::array(debugger, &name) else {
                return Ok(EvaluateBody {
                    result: shown,
                    ty: "array".into(),
                    variables_reference: 0,
                    indexed_variables: None,
                });
            };
            let length = array.length.unwrap_or(0);
            Ok(EvaluateBody {
                result: array_summary(debugger, &array.name, length, format),
                ty: array.ty.to_string(),
                variables_reference: ARRAYS + position as i64,
                indexed_variables: Some(length as i64),
            })
        }
    }
}

/// `setExpression`: assigns, journaled, and answers the new value as `evaluate` would.
pub fn set_expression(
    debugger: &mut Debugger<World>,
    arguments: &SetExpressionArguments,
) -> DebugResult<SetExpressionBody> {
    let value = edits::assign(debugger, &arguments.expression, &arguments.value)?;
    Ok(SetExpressionBody {
        value: value_format(arguments.format).number(value),
        ty: type_name(value).into(),
        variables_reference: 0,
    })
}

/// The most elements an array's one-line summary lists (its children list them all).
const SUMMARY_ELEMENTS: usize = 100;

/// `[0, 10, 20]`: the array's elements as the Variables view's one-line value.
pub fn array_summary(
    debugger: &Debugger<World>,
    name: &str,
    length: usize,
    format: ValueFormat,
) -> String {
    let shown: Vec<String> = (0..length.min(SUMMARY_ELEMENTS))
        .map(|index| {
            debugger
                .target
                .element(name, index as i64)
                .map(|value| format.number(value))
                .unwrap_or_default()
        })
        .collect();
    let more = if length > SUMMARY_ELEMENTS {
        ", …"
    } else {
        ""
    };
    format!("[{}{more}]", shown.join(", "))
}

/// `gotoTargets`: where a jump to the line lands (see `DebugInfo::goto_targets`); the
/// target's id is its pc.
pub fn goto_targets(
    debugger: &Debugger<World>,
    arguments: &GotoTargetsArguments,
    client: ClientOptions,
) -> DebugResult<Vec<GotoTarget>> {
    let info = &debugger.info;
    let path = arguments.source.path.as_deref().unwrap_or_default();
    if !info.is_same_source(path) {
        return Err(DebugError::request(format!(
            "{path} is not the program being debugged ({})",
            info.source_name()
        )));
    }
    let requested = arguments
        .line
        .saturating_add(i64::from(!client.lines_start_at1));
    let line = u32::try_from(requested)
        .ok()
        .filter(|line| *line >= 1)
        .ok_or_else(|| {
            DebugError::request(format!("line {requested} is not a line of the program"))
        })?;
    let (Some(line), pcs) = info.goto_targets(line) else {
        return Ok(Vec::new());
    };
    let several = pcs.len() > 1;
    Ok(pcs
        .into_iter()
        .map(|pc| {
            let instruction = info.instruction_text.get(pc).map_or("", String::as_str);
            GotoTarget {
                id: pc as i64,
                label: if several {
                    format!("line {line}, pc {pc}: {}", instruction.trim())
                } else {
                    format!("line {line}")
                },
                line: i64::from(line) - i64::from(!client.lines_start_at1),
                instruction_pointer_reference: Some(address(pc)),
            }
        })
        .collect())
}

/// `goto`: jumps (journaled) and says where, for the `stopped` event that follows.
pub fn goto(debugger: &mut Debugger<World>, arguments: &GotoArguments) -> DebugResult<String> {
    let pc = usize::try_from(arguments.target_id).map_err(|_| {
        DebugError::request(format!(
            "goto target {} is not one of gotoTargets'",
            arguments.target_id
        ))
    })?;
    edits::goto(debugger, pc)?;
    let line = debugger
        .info
        .line(pc)
        .map(|line| format!("line {line}, "))
        .unwrap_or_default();
    Ok(format!("Jumped to {line}pc {pc}"))
}

/// The byte offset of UTF-16 column `column` (0-based) in `line`, clamped to its end.
fn byte_offset(line: &str, column: usize) -> usize {
    let mut units = 0;
    for (offset, character) in line.char_indices() {
        if units >= column {
            return offset;
        }
        units += character.len_utf16();
    }
    line.len()
}

fn utf16_len(text: &str) -> usize {
    text.chars().map(char::len_utf16).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_offered_filter_is_one_the_debugger_has_and_failures_stop_by_default() {
        let mut defaults = ExceptionFilters::default();
        for (id, _, _, on) in EXCEPTION_FILTERS {
            let filter = defaults
                .by_id(id)
                .unwrap_or_else(|| panic!("no filter {id}"));
            // The DAP specification's `default` of a filter, and the debugger's.
            assert_eq!(filter.enabled, on, "{id}");
        }
        // Worked out from the issue: traps, overruns and abend stop; the journey's
        // points (a waypoint, a surfacing) do not until asked for.
        let on: Vec<&str> = EXCEPTION_FILTERS
            .iter()
            .filter(|(.., on)| *on)
            .map(|(id, ..)| *id)
            .collect();
        assert_eq!(on, ["trap", "overrun", "abend"]);
    }

    #[test]
    fn client_options_are_read_from_initialize_with_the_protocols_defaults() {
        // The DAP specification: lines and columns start at 1 unless the client says
        // otherwise; progress is reported only to a client that supports it.
        let read = |json: serde_json::Value| {
            serde_json::from_value::<ClientOptions>(json).expect("initialize arguments")
        };
        assert_eq!(read(serde_json::json!({})), ClientOptions::default());
        assert_eq!(
            read(serde_json::json!({ "adapterID": "gloc", "clientID": "vscode" })),
            ClientOptions {
                lines_start_at1: true,
                columns_start_at1: true,
                supports_progress_reporting: false,
            }
        );
        assert_eq!(
            read(serde_json::json!({
                "linesStartAt1": false,
                "columnsStartAt1": false,
                "supportsProgressReporting": true,
                "pathFormat": "path"
            })),
            ClientOptions {
                lines_start_at1: false,
                columns_start_at1: false,
                supports_progress_reporting: true,
            }
        );
    }

    #[test]
    fn utf16_columns_convert_to_bytes_and_back() {
        // `é` is 2 bytes, 1 unit; `𝑥` 4 bytes, 2 units.
        let line = "é𝑥 dep";
        assert_eq!(byte_offset(line, 0), 0);
        assert_eq!(byte_offset(line, 1), 2);
        assert_eq!(byte_offset(line, 3), 6);
        assert_eq!(byte_offset(line, 7), line.len());
        assert_eq!(byte_offset(line, 99), line.len());
        assert_eq!(utf16_len(line), 7);
    }

    #[test]
    fn filters_and_their_conditions() {
        let arguments = SetExceptionBreakpointsArguments {
            filters: vec!["trap".into()],
            filter_options: Some(vec![
                ExceptionFilterOptions {
                    filter_id: "overrun".into(),
                    condition: Some("m_depth > 10".into()),
                    mode: None,
                },
                ExceptionFilterOptions {
                    filter_id: "abend".into(),
                    condition: Some("(".into()),
                    mode: None,
                },
            ]),
        };
        let invalid = |text: &str| (text == "(").then(|| "missing `)`".to_string());
        let (filters, breakpoints) = exception_filters(&arguments, invalid).expect("known filters");
        assert!(filters.trap.enabled && filters.overrun.enabled && !filters.abend.enabled);
        assert_eq!(filters.trap.condition, None);
        assert_eq!(filters.overrun.condition.as_deref(), Some("m_depth > 10"));
        let verified: Vec<bool> = breakpoints.iter().map(|b| b.verified).collect();
        assert_eq!(verified, [true, true, false]);
        assert_eq!(breakpoints[2].message.as_deref(), Some("missing `)`"));
        let unknown = SetExceptionBreakpointsArguments {
            filters: vec!["segfault".into()],
            filter_options: None,
        };
        assert!(exception_filters(&unknown, invalid).is_err());
    }
}
