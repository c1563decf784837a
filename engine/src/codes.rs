//! The one registry of diagnostic codes: every code the engine, the compiler, the
//! simulator and the project settings report, with its severity and its one-line
//! doc. Code sites name a code by its constant (`codes::gloc::UNDEFINED_LABEL`);
//! `docs/diagnostics.md` lists the same codes with the same one-line docs (a test
//! compares them), and `gloc explain CODE` prints an entry.
//!
//! Decision: codes stay `&'static str` in [`Diagnostic`](crate::Diagnostic) (what
//! the protocols and the terminal show), and this table is where a code is made:
//! a code not in it fails `every_code_in_the_sources_is_registered`.

use crate::Severity;

/// One registered code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CodeInfo {
    /// The stable code, e.g. `E0101`.
    pub code: &'static str,
    /// The severity a diagnostic with this code has.
    pub severity: Severity,
    /// What it means, in one line (Markdown, as in `docs/diagnostics.md`).
    pub doc: &'static str,
    /// The part of gloc that reports it: `gloc`, `sensors`, `gbasic`, `mission`, `settings`.
    pub area: &'static str,
}

macro_rules! registry {
    ($( $(#[$area_doc:meta])* $area:ident { $( $name:ident = $code:literal, $severity:ident, $doc:literal; )* } )*) => {
        $(
            $(#[$area_doc])*
            pub mod $area {
                $(
                    #[doc = $doc]
                    pub const $name: &str = $code;
                )*
            }
        )*

        /// Every registered code, in the order of `docs/diagnostics.md`.
        pub const ALL: &[CodeInfo] = &[
            $( $( CodeInfo {
                code: $code,
                severity: Severity::$severity,
                doc: $doc,
                area: stringify!($area),
            }, )* )*
        ];
    };
}

registry! {
    /// GLOC: parsing (E00xx) and checking (E01xx).
    gloc {
        UNKNOWN_INSTRUCTION = "E0001", Error, "unknown instruction (with \"did you mean\")";
        UNEXPECTED_CHARACTER = "E0002", Error, "unexpected character, or binary data";
        OPERAND_COUNT = "E0003", Error, "wrong number of operands";
        OPERAND_KIND = "E0004", Error, "wrong kind of operand";
        BAD_NUMBER_OR_REGISTER = "E0005", Error, "malformed or out-of-range number or register";
        BAD_STRING = "E0006", Error, "unterminated string or unknown escape";
        COMMA = "E0007", Error, "missing or extra comma";
        TOO_MANY_PARSE_ERRORS = "E0008", Error, "more parse errors than are shown (1,000)";
        MISSING_HEADER = "E0010", Error, "missing header line, or an empty file";
        MISPLACED_HEADER = "E0011", Error, "header line after the body, or declared twice";
        HEADER_OVER_LIMIT = "E0012", Error, "header value above the engine's limit";
        SOURCE_TOO_LARGE = "E0013", Error, "script over the size limits (16 MB or 2^19 lines; GBASIC 1 MB): not read at all";
        REGISTER_OUT_OF_RANGE = "E0101", Error, "register out of range (`>= nregs`)";
        LABEL_OUT_OF_RANGE = "E0102", Error, "label out of range (`>= nblbs`)";
        LABEL_DEFINED_TWICE = "E0103", Error, "label defined twice (points at the first definition)";
        UNDEFINED_LABEL = "E0104", Error, "jump or branch to a label that is never defined";
        NINSTR_MISMATCH = "E0105", Error, "`ninstr` does not match the number of lines after the header";
        UNKNOWN_SENSOR_INDEX = "E0107", Error, "sensor index not in the active sensor list";
        STORE_TO_READ_ONLY = "E0108", Error, "store to a read-only sensor (`m_`, `x_`)";
        STORE_TO_FACTORY = "W0109", Warning, "store to a factory setting (`f_`)";
        MEMORY_OUT_OF_RANGE = "E0110", Error, "memory address constant out of range (`>= nmem`)";
        LOOP_WITHOUT_YIELD = "E0111", Error, "a loop without `yield` and without a way out: it would hang the control cycle";
        LOOP_MAY_OVERRUN = "W0111", Warning, "a loop that can repeat without `yield`: it may overrun the cycle";
        UNREACHABLE = "W0112", Warning, "unreachable code";
        INDEX_NAMES_ANOTHER_SENSOR = "E0113", Error, "a sensor index names another sensor in the active list than in the list the file states (`# sensors: CRC`): \"index 444 is `m_depth` in 813b137d but `m_certainly_at_surface` in 1f35be3b\" (one per index)";
        LIST_NOT_STATED = "W0114", Warning, "the file states no list (`# sensors: CRC`) and is checked against a list other than the embedded one: its indices were not verified by name (once, at the first sensor index)";
        LIST_NOT_VERIFIED = "W0115", Warning, "the `# sensors:` line is not a CRC, or the list it names is neither the active, nor the embedded, nor a `<crc>.cac` found beside the script, beside the active list or in the sensor cache folder: not verified by name";
        UNKNOWN_SENSOR_NAME = "E0117", Error, "a sensor named by name (`loads m_depth,r0`) that the active sensor list lacks (\"did you mean\" when one is close)";
        REINDEX_NAME_MISSING = "E0116", Error, "`gloc reindex`: an index whose name the target list lacks (or that is outside the source list); nothing is written";
    }
    /// Sensor lists: masterdata, `.cac` and `.ccc` (E02xx).
    sensors {
        BAD_MASTERDATA_LINE = "E0201", Error, "malformed `sensor:`/`b_arg:` line (name or `(UNITS)` missing)";
        BAD_DEFAULT = "E0202", Error, "the default is not a number";
        DUPLICATE_SENSOR = "W0203", Warning, "a sensor name appears twice (names both lines; lookups use the first)";
        NOT_MASTERDATA = "W0204", Warning, "a line that is not part of the masterdata format, ignored";
        BAD_CAC_LINE = "E0205", Error, "malformed `.cac` line (`s: T\\|F INDEX COLUMN BYTES NAME UNITS`)";
        BAD_CAC_INDICES = "E0206", Error, "`.cac` indices repeat, leave a gap, or reach 65,536 (the most sensors a list may have)";
        NO_SENSORS = "E0207", Error, "no sensors in the file";
        TOO_MANY_SENSORS = "E0208", Error, "more than 65,536 sensors in a masterdata file: the rest is not read";
        STRAY_VALUE = "W0209", Warning, "text after a masterdata default (`0 0`): the glider reads the first number and ignores the rest";
    }
    /// GBASIC, the compiler (E2xxx, W2xxx).
    gbasic {
        SYNTAX = "E2001", Error, "syntax: a token that does not fit here";
        BAD_CHARACTER = "E2002", Error, "a character that starts no token";
        BAD_NUMBER = "E2003", Error, "a number that does not fit (integer beyond 64 bits, float not finite)";
        MISSING_CLOSER = "E2004", Error, "a block (`if`, `while`, `do`, `for`) without its closing word";
        STRAY_CLOSER = "E2005", Error, "a closing word (`endif`, `wend`, `loop`, `next`, `else`) without an open block";
        KEYWORD_AS_NAME = "E2006", Error, "a keyword used as a name";
        BAD_NEXT = "E2007", Error, "`next V` that does not match the loop variable";
        TOO_DEEP = "E2008", Error, "blocks, parentheses or prefix operators nested more than 100 levels deep";
        EXPRESSION_TOO_DEEP = "E2009", Error, "an expression more than 256 operators deep: each term of a chain `1 + 1 + …` is a level; split it into several assignments";
        EXPRESSION_TOO_LONG = "E2010", Error, "a debugger expression (condition, watch, logpoint, `setVariable` value) longer than 64 KiB";
        TOO_MANY_DIAGNOSTICS = "E2011", Error, "more diagnostics than are shown (1,000 per pass)";
        UNDECLARED = "E2101", Error, "a name that is neither declared nor a sensor (\"did you mean\")";
        DUPLICATE = "E2102", Error, "a name declared twice, or reusing a sensor's or built-in's name";
        UNDEFINED_LABEL = "E2103", Error, "`goto` to an undefined label";
        DUPLICATE_LABEL = "E2104", Error, "a label defined twice";
        READ_ONLY_SENSOR = "E2105", Error, "assigning a read-only sensor (`m_`, `x_`)";
        WRONG_KIND = "E2106", Error, "a name used the wrong way (assigning a constant, an array without index, …)";
        TYPE_MISMATCH = "E2201", Error, "a value of the wrong type";
        INDEX_OUT_OF_BOUNDS = "E2202", Error, "a constant index out of bounds";
        BAD_ARRAY_SIZE = "E2203", Error, "an array size that is not a positive integer";
        BAD_ARGUMENTS = "E2204", Error, "a built-in called with the wrong number of arguments";
        DIVISION_BY_ZERO = "E2205", Error, "a constant integer division by zero";
        EXIT_OUTSIDE_LOOP = "E2301", Error, "`exit for/do/while` outside such a loop";
        TOO_LARGE = "E2302", Error, "the program exceeds GLOC's limits (registers, labels, memory)";
        FACTORY_SENSOR = "W2101", Warning, "assigning a factory (`f_`) sensor";
        UNUSED = "W2102", Warning, "a variable declared but never used";
        ZERO_STEP = "W2301", Warning, "a `for` loop with step 0";
        OVER_BUDGET = "W2302", Warning, "the worst case per cycle exceeds the cycle budget given to the loader";
        NOT_OPTIMIZED = "W2303", Warning, "a program too large for `-O` (instructions × registers over 2^30), compiled without it";
        ENDLESS_AFTER_FOLDING = "W2304", Warning, "`-O` proved a loop never ends and never yields (its condition is constant): it would hang the control cycle; the program is compiled without `-O`";
    }
    /// Missions: `.mi` and `.ma` files, and the mission against the list and the script (S-codes).
    mission {
        CANNOT_READ_MISSION = "S0001", Error, "the mission file cannot be read";
        MISSION_NOT_TEXT = "S0002", Error, "the mission file is not a text file (it contains a NUL byte)";
        UNEXPECTED_MISSION_LINE = "S0003", Error, "a `.mi` line that is not `sensor:`, `behavior:` or `b_arg:`";
        CANNOT_READ_MA = "S0004", Error, "`args_from_file` names a `.ma` file that cannot be read, or the mission has no mafiles folder";
        EXPECTED_SETTING = "S0010", Error, "`sensor:` or `b_arg:` without `NAME(UNITS) VALUE` after it";
        MISSING_UNITS = "S0011", Error, "a setting without `(UNITS)`, or with an unclosed `(`";
        BAD_SETTING_NAME = "S0012", Error, "a setting name with characters other than letters, digits and `_`";
        TRAILING_TEXT = "S0013", Error, "unexpected text after the units, the value or the behavior name (a comment starts with `#`)";
        MISSING_VALUE = "S0014", Error, "a setting without a value after its units";
        VALUE_NOT_A_NUMBER = "S0015", Error, "a setting's value is not a number";
        MISSING_BEHAVIOR_NAME = "S0016", Error, "`behavior:` without a behavior name";
        ARG_BEFORE_BEHAVIOR = "S0017", Error, "`b_arg:` before any `behavior:` line";
        NESTED_SECTION = "S0021", Error, "a `.ma` section (`<start:…>`) opened inside another";
        UNMATCHED_SECTION_END = "S0022", Error, "a `.ma` `<end:…>` without a matching start";
        BAD_WAYPOINT = "S0023", Error, "a `.ma` waypoint that is not `LON LAT` (DDDMM.MMMM DDMM.MMMM)";
        UNEXPECTED_MA_LINE = "S0024", Error, "a `.ma` line that is not `behavior_name=`, `<start:b_arg>`, `b_arg:` or `<end:b_arg>`";
        UNCLOSED_SECTION = "S0025", Error, "a `.ma` file that ends inside a section";
        UNKNOWN_BEHAVIOR = "S0101", Warning, "a behavior the behavior table (the active masterdata's, else the embedded release table) does not have, with \"did you mean\": it is ignored with its arguments";
        NESTED_ARGS_FROM_FILE = "S0102", Warning, "`args_from_file` inside a `.ma` file, ignored";
        UNKNOWN_ARGUMENT = "S0103", Warning, "an argument the behavior table does not give the behavior, with \"did you mean\": the glider ignores it and flies the default";
        MA_FOR_OTHER_BEHAVIOR = "S0104", Warning, "a `.ma` file whose `behavior_name=` names another behavior than the one that loads it";
        MA_WITHOUT_BEHAVIOR_NAME = "S0105", Warning, "a `.ma` file without a `behavior_name=` line";
        SENSOR_NOT_IN_LIST = "S0106", Warning, "a mission's `sensor:` line names a sensor the active list lacks; the setting is ignored";
        HOOK_MISSING = "S0107", Warning, "the script stores `sci_ruhp_behs` but the mission has no `behavior: hook`, so nothing acts on it";
        MA_BESIDE_MISSION = "S0108", Note, "a `.ma` file was found beside the `.mi`, not in `mafiles/`, where the glider reads it";
        ARG_OVERRIDDEN_BY_MA = "S0109", Warning, "an argument set in the `.mi` and again, to another value, in the behavior's `.ma` file: the glider flies the `.ma` value";
        GENERATED_MA_MISSING = "S0110", Warning, "`args_from_file` 99 names a `.ma` file the glider writes itself during a mission (breadcrumb, ice) and it is not there: gloc flies the behavior's defaults";
        VALUE_OUT_OF_RANGE = "S0120", Warning, "an argument's value is outside the range the masterdata's `#!` metadata gives it (`min`, `max`)";
        VALUE_NOT_A_CHOICE = "S0127", Warning, "an argument's value is not one of the masterdata's `#! choices` for it (a `start_when` code the behavior does not take)";
        WAYPOINT_NOT_NMEA = "S0121", Warning, "a waypoint that is not NMEA `dddmm.mmm`: minutes of 60 or more, beyond ±90° or ±180°, longitude and latitude swapped, or decimal degrees";
        TARGET_TOO_DEEP = "S0122", Warning, "a yo or dive target deeper than abend's `overdepth` or the mission's water depth (`s_water_depth_avg`)";
        CLIMB_BELOW_DIVE = "S0123", Warning, "a yo's climb target is deeper than its dive target";
        SURFACE_AFTER_OVERTIME = "S0124", Warning, "a surface behavior's interval (`when_secs`) is longer than abend's `overtime`: the mission aborts first";
        NUM_WAYPOINTS_MISMATCH = "S0125", Warning, "`num_waypoints` disagrees with the waypoints listed";
        WAYPOINT_TRAILING_TEXT = "S0126", Warning, "text after a waypoint's two numbers (`lon lat \\| name`): not in the firmware's documented format";
        BEHAVIOR_NOT_SIMULATED = "S0111", Note, "a behavior the glider has (it is in the behavior table) but gloc's simulator does not fly: `gloc run` leaves it out";
    }
    /// Project settings and the editor tools (E09xx).
    settings {
        BAD_CONFIG = "E0901", Error, "`gloc.toml` is not valid: a syntax error, an unknown key (the keys are `masterdata`, `cycle_budget`, `mission`), a value of the wrong type, or a `cycle_budget` outside 1 to 1,000,000,000";
        UNREADABLE_CONFIG = "E0902", Error, "`gloc.toml` exists but cannot be read";
        SENSOR_LIST_UNLOADABLE = "E0903", Error, "the sensor list named by `masterdata` (in `gloc.toml` or the editor settings) cannot be loaded; the message starts with where the path came from (`gloc.toml:LINE:COL` or `editor setting gloc.masterdata`); the embedded 2008 list is used instead";
        BAD_EDITOR_SETTING = "E0904", Error, "an editor setting is refused (a `gloc.cycleBudget` outside 1 to 1,000,000,000), in the words `gloc run` and a debugger launch use; the editor's settings are not used";
        INTERNAL_ERROR = "E0999", Error, "internal error: the checker crashed on this text (please report it with the file)";
    }
}

/// The registry entry of `code` (case-insensitive), if it is registered.
pub fn lookup(code: &str) -> Option<&'static CodeInfo> {
    ALL.iter().find(|info| info.code.eq_ignore_ascii_case(code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique_and_well_formed() {
        let mut seen = std::collections::HashSet::new();
        for info in ALL {
            assert!(seen.insert(info.code), "{} registered twice", info.code);
            let bytes = info.code.as_bytes();
            assert_eq!(bytes.len(), 5, "{}", info.code);
            assert!(bytes[1..].iter().all(u8::is_ascii_digit), "{}", info.code);
            match bytes[0] {
                b'E' => assert_eq!(info.severity, Severity::Error, "{}", info.code),
                b'W' => assert_eq!(info.severity, Severity::Warning, "{}", info.code),
                b'S' => {}
                _ => panic!("{} has no known prefix", info.code),
            }
            assert!(
                !info.doc.is_empty() && !info.doc.contains('\n'),
                "{}",
                info.code
            );
        }
    }

    #[test]
    fn lookup_finds_by_code_in_any_case() {
        assert_eq!(
            lookup("e0104").map(|info| info.code),
            Some(gloc::UNDEFINED_LABEL)
        );
        assert_eq!(lookup("S0107").map(|info| info.area), Some("mission"));
        assert!(lookup("E4242").is_none());
    }
}
