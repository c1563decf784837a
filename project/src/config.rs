//! `gloc.toml`: per-project settings (masterdata path, cycle budget, mission),
//! found by walking up from a script. The file's format lives here, in the project
//! layer that owns settings ([`crate::settings`] resolves it with the front ends'
//! overrides), so the CLI, the language server and the debug adapter see the same
//! project; the `[simulator]` names and ranges are the simulator's own
//! (`gloc_sim::settings`).
//!
//! The file is small and flat:
//!
//! ```toml
//! masterdata = "config/masterdata.mi"   # or a .cac file; relative to gloc.toml
//! cycle_budget = 2000                    # instructions per control cycle
//! mission = "missions/yo.mi"             # the mission the debugger flies
//! sensor_order = "sorted"                # masterdata indices: "file" (default) or "sorted"
//! sensor_cache = "cac"                   # folder of <crc>.cac / .ccc lists for glider logs
//! mafiles = "shared/mafiles"              # folder searched first for a mission's .ma files
//!
//! [simulator]                            # the flight and energy models' constants
//! drag_cd0 = 0.15                       # see gloc_sim::settings for every name
//! ```
//!
//! Parsing is pure ([`Config::parse`] takes text and returns a [`Diagnostic`]
//! with a byte span into that text on error); [`Config::find`] and
//! [`Config::discover`] are the only functions that touch the file system.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use gloc_engine::diagnostic::{Diagnostic, Span};
use gloc_engine::sensors::SensorOrder;
use gloc_sim::settings::check_simulator_setting;

/// The file name looked for in a script's folder and every folder above it.
pub const FILE_NAME: &str = "gloc.toml";

/// Code of every problem in a `gloc.toml` (syntax, unknown key, wrong type).
pub const CODE_BAD_CONFIG: &str = gloc_engine::codes::settings::BAD_CONFIG;
/// Code of a `gloc.toml` that cannot be read at all.
pub const CODE_UNREADABLE_CONFIG: &str = gloc_engine::codes::settings::UNREADABLE_CONFIG;

/// Settings from a `gloc.toml`. Every field is optional; a missing file is the
/// same as an empty one. Paths are absolute (resolved against the folder that
/// holds the file). Each value keeps where it stands in the file ([`Placed`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Config {
    /// The `gloc.toml` these settings came from, if any.
    pub path: Option<PathBuf>,
    /// A masterdata or `.cac` file replacing the embedded sensor list.
    pub masterdata: Option<Placed<PathBuf>>,
    /// Per-control-cycle instruction budget for running scripts.
    pub cycle_budget: Option<Placed<u64>>,
    /// The mission (`.mi`) the debugger and `gloc run` fly.
    pub mission: Option<Placed<PathBuf>>,
    /// How a masterdata file's sensors are numbered (file order, the default, or
    /// sorted by name as firmware 2014 and later does).
    pub sensor_order: Option<Placed<SensorOrder>>,
    /// The folder searched first for a glider log's sensor list (`<crc>.cac`/`.ccc`).
    pub sensor_cache: Option<Placed<PathBuf>>,
    /// The folder searched first for a mission's `.ma` files (before `mafiles/`
    /// beside `missions/`).
    pub mafiles: Option<Placed<PathBuf>>,
    /// `[simulator]`: flight and energy constants, sorted by name, each
    /// checked against [`gloc_sim::settings::SIMULATOR_SETTINGS`].
    pub simulator: Vec<(String, f64)>,
}

/// A value of a `gloc.toml` and where it stands, `(line, column)` from 1, so that an
/// error about it (a masterdata file that cannot be read) names `gloc.toml:LINE:COLUMN`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed<T> {
    pub value: T,
    pub at: (usize, usize),
}

/// The largest per-cycle instruction budget (`cycle_budget`, `--cycle-budget`, the
/// debugger's `cycleBudget`). A cycle of a billion instructions takes the interpreter
/// a few seconds (about 300 million a second), so every cycle, and with it every run of
/// bounded length, finishes; the default is 10,000 and Fig. 2 needs 16. (The benchmarks
/// measure long single-cycle programs with this budget.)
pub const MAX_CYCLE_BUDGET: u64 = 1_000_000_000;

/// Checks a cycle budget from any source: 1 to [`MAX_CYCLE_BUDGET`].
pub fn check_cycle_budget(budget: u64) -> Result<u64, String> {
    if (1..=MAX_CYCLE_BUDGET).contains(&budget) {
        Ok(budget)
    } else {
        Err(format!(
            "the cycle budget must be 1 to {MAX_CYCLE_BUDGET} instructions per cycle, not {budget}"
        ))
    }
}

/// A `gloc.toml` that could not be used: where it is, and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigError {
    pub path: PathBuf,
    /// The file's text when it could be read (for rendering the diagnostic).
    pub text: Option<String>,
    pub diagnostic: Box<Diagnostic>,
}

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.text {
            Some(text) => {
                let index = gloc_engine::diagnostic::LineIndex::new(text);
                let (line, column) = index.line_col(text, self.diagnostic.span.start as usize);
                write!(
                    f,
                    "{}:{line}:{column}: {}",
                    self.path.display(),
                    self.diagnostic.message
                )
            }
            None => write!(f, "{}: {}", self.path.display(), self.diagnostic.message),
        }
    }
}

impl std::error::Error for ConfigError {}

/// The file as written; kept private so the public type can hold resolved paths.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
/// Values whose errors are found after parsing keep the parser's spans, so a
/// diagnostic points at exactly the key or value, never at a look-alike elsewhere.
struct RawConfig {
    masterdata: Option<toml::Spanned<String>>,
    cycle_budget: Option<toml::Spanned<u64>>,
    mission: Option<toml::Spanned<String>>,
    sensor_order: Option<toml::Spanned<String>>,
    sensor_cache: Option<toml::Spanned<String>>,
    mafiles: Option<toml::Spanned<String>>,
    simulator: Option<std::collections::BTreeMap<toml::Spanned<String>, toml::Value>>,
}

impl Config {
    /// The nearest `gloc.toml` in `start` (a file's folder, or the file itself)
    /// or any folder above it.
    pub fn find(start: &Path) -> Option<PathBuf> {
        // A relative path is searched from its absolute form (`x.gloc`'s parent is ``,
        // whose ancestors end at the current folder), and a file found below the
        // current folder is named relative to it, as the user wrote the path.
        let here = std::env::current_dir().ok();
        let absolute = match &here {
            Some(here) if start.is_relative() => here.join(start),
            _ => start.to_path_buf(),
        };
        let first = if absolute.is_dir() {
            Some(absolute.as_path())
        } else {
            absolute.parent()
        };
        let found = first?
            .ancestors()
            .map(|folder| folder.join(FILE_NAME))
            .find(|candidate| candidate.is_file())?;
        match &here {
            Some(here) if start.is_relative() => Some(
                found
                    .strip_prefix(here)
                    .map_or_else(|_| found.clone(), Path::to_path_buf),
            ),
            _ => Some(found),
        }
    }

    /// Parses the text of a `gloc.toml` that lives in `folder`. Errors carry a
    /// byte span into `text`.
    pub fn parse(text: &str, folder: &Path) -> Result<Config, Box<Diagnostic>> {
        let raw: RawConfig = toml::from_str(text).map_err(|error| {
            let span = error
                .span()
                .map(|range| Span::new(range.start, range.end))
                .unwrap_or_default();
            let message = error.message().trim().to_string();
            Box::new(
                Diagnostic::error(
                    CODE_BAD_CONFIG,
                    span,
                    format!("invalid gloc.toml: {message}"),
                )
                .with_help("the keys are `masterdata` (a path), `cycle_budget` (a positive integer), `mission` (a path), `sensor_order` (\"file\" or \"sorted\"), `sensor_cache` (a folder), `mafiles` (a folder) and the table `[simulator]`"),
            )
        })?;
        let span_of = |range: std::ops::Range<usize>| Span::new(range.start, range.end);
        if let Some(budget) = &raw.cycle_budget {
            if let Err(message) = check_cycle_budget(*budget.get_ref()) {
                return Err(Box::new(Diagnostic::error(
                    CODE_BAD_CONFIG,
                    span_of(budget.span()),
                    format!("invalid gloc.toml `cycle_budget`: {message}"),
                )));
            }
        }
        let sensor_order = match &raw.sensor_order {
            None => None,
            Some(name) => match SensorOrder::from_name(name.get_ref()) {
                Some(order) => Some(order),
                None => {
                    return Err(Box::new(
                        Diagnostic::error(
                            CODE_BAD_CONFIG,
                            span_of(name.span()),
                            format!("invalid gloc.toml: `sensor_order` is `{}`", name.get_ref()),
                        )
                        .with_help(format!("`sensor_order` is {}", SensorOrder::NAMES)),
                    ));
                }
            },
        };
        let mut simulator = Vec::new();
        for (key, value) in raw.simulator.into_iter().flatten() {
            let span = span_of(key.span());
            let name = key.into_inner();
            let number = match value {
                toml::Value::Float(number) => Some(number),
                toml::Value::Integer(number) => Some(number as f64),
                _ => None,
            };
            let checked = match number {
                Some(number) => check_simulator_setting(&name, number).map(|()| number),
                None => Err(format!("`{name}` must be a number")),
            };
            match checked {
                Ok(number) => simulator.push((name, number)),
                Err(message) => {
                    return Err(Box::new(Diagnostic::error(
                        CODE_BAD_CONFIG,
                        span,
                        format!("invalid gloc.toml: {message}"),
                    )))
                }
            }
        }
        let index = gloc_engine::diagnostic::LineIndex::new(text);
        let place = |spanned: &toml::Spanned<String>, value: PathBuf| Placed {
            value,
            at: index.line_col(text, spanned.span().start),
        };
        let path = |value: Option<toml::Spanned<String>>| {
            value.map(|relative| place(&relative, folder.join(relative.get_ref())))
        };
        Ok(Config {
            path: Some(folder.join(FILE_NAME)),
            masterdata: path(raw.masterdata),
            cycle_budget: raw.cycle_budget.map(|budget| Placed {
                value: *budget.get_ref(),
                at: index.line_col(text, budget.span().start),
            }),
            mission: path(raw.mission),
            sensor_order: sensor_order
                .zip(raw.sensor_order)
                .map(|(value, name)| Placed {
                    value,
                    at: index.line_col(text, name.span().start),
                }),
            sensor_cache: path(raw.sensor_cache),
            mafiles: path(raw.mafiles),
            simulator,
        })
    }

    /// Reads and parses one `gloc.toml`.
    pub fn load(path: &Path) -> Result<Config, ConfigError> {
        let text =
            gloc_engine::files::read_text(path, gloc_engine::files::CONFIG).map_err(|error| {
                ConfigError {
                    path: path.to_path_buf(),
                    text: None,
                    diagnostic: Box::new(Diagnostic::error(
                        CODE_UNREADABLE_CONFIG,
                        Span::default(),
                        format!("cannot read gloc.toml: {error}"),
                    )),
                }
            })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        match Config::parse(&text, folder) {
            Ok(mut config) => {
                config.path = Some(path.to_path_buf());
                Ok(config)
            }
            Err(diagnostic) => Err(ConfigError {
                path: path.to_path_buf(),
                text: Some(text),
                diagnostic,
            }),
        }
    }

    /// The settings that apply to a script: the nearest `gloc.toml` above it,
    /// or the defaults when there is none.
    pub fn discover(script: &Path) -> Result<Config, ConfigError> {
        match Config::find(script) {
            Some(path) => Config::load(&path),
            None => Ok(Config::default()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_key_and_resolves_paths_against_the_folder() {
        let text = "masterdata = \"md/masterdata.mi\"\ncycle_budget = 500\nmission = \"m/yo.mi\"\nsensor_cache = \"cac\"\nmafiles = \"shared/ma\"\n";
        let config = Config::parse(text, Path::new("/project")).expect("valid config");
        let placed = |value: &str, at| {
            Some(Placed {
                value: PathBuf::from(value),
                at,
            })
        };
        // Counted by hand: `masterdata = ` is 13 characters, `cycle_budget = ` 15,
        // `mission = ` 10, `sensor_cache = ` 15, `mafiles = ` 10; the value starts one
        // further.
        assert_eq!(
            config.masterdata,
            placed("/project/md/masterdata.mi", (1, 14))
        );
        assert_eq!(
            config.cycle_budget,
            Some(Placed {
                value: 500,
                at: (2, 16)
            })
        );
        assert_eq!(config.mission, placed("/project/m/yo.mi", (3, 11)));
        assert_eq!(config.sensor_cache, placed("/project/cac", (4, 16)));
        assert_eq!(config.sensor_order, None);
        assert_eq!(config.mafiles, placed("/project/shared/ma", (5, 11)));
    }

    /// `text` as a `gloc.toml` in `/p`, which must be valid.
    fn parsed(text: &str) -> Config {
        Config::parse(text, Path::new("/p")).unwrap_or_else(|error| panic!("{text}: {error:?}"))
    }

    /// Asserts that `text` is refused, the error pointing at `at` (the text it
    /// underlines) and its message saying `says`; returns the error.
    fn refused(text: &str, at: &str, says: &str) -> Box<Diagnostic> {
        let error = Config::parse(text, Path::new("/p")).expect_err(text);
        assert_eq!(error.code, CODE_BAD_CONFIG);
        assert_eq!(&text[error.span.range()], at, "{}", error.message);
        assert!(error.message.contains(says), "{}", error.message);
        error
    }

    #[test]
    fn sensor_order_is_file_or_sorted_and_anything_else_points_at_the_value() {
        let sorted = parsed("sensor_order = \"sorted\"\n");
        assert_eq!(
            sorted.sensor_order.map(|order| order.value),
            Some(SensorOrder::SortedByName)
        );
        let file = parsed("sensor_order = \"file\"\n");
        assert_eq!(
            file.sensor_order.map(|order| order.value),
            Some(SensorOrder::FileOrder)
        );
        let error = refused(
            "masterdata = \"m.mi\"\nsensor_order = \"alphabetical\"\n",
            "\"alphabetical\"",
            "`sensor_order` is `alphabetical`",
        );
        assert!(error
            .help
            .as_deref()
            .is_some_and(|help| help.contains("`sorted`")));
    }

    #[test]
    fn simulator_settings_are_checked_by_name_and_range() {
        let text = "[simulator]\ndrag_cd0 = 0.2\nbattery_wh = 800\n";
        let config = parsed(text);
        assert_eq!(
            config.simulator,
            vec![
                ("battery_wh".to_string(), 800.0),
                ("drag_cd0".to_string(), 0.2)
            ]
        );
        refused(
            "cycle_budget = 5\n[simulator]\ndrag_c0 = 0.2\n",
            "drag_c0",
            "did you mean `drag_cd0`?",
        );
        // A 1e-9 s step would never finish a cycle.
        refused("[simulator]\nstep = 1e-9\n", "step", "from 0.05 to 1.5 s");
        refused("[simulator]\nstep = \"fast\"\n", "step", "must be a number");
    }

    #[test]
    fn errors_point_at_the_key_itself_not_at_a_look_alike() {
        // `pump_out_j_per_cc` is a prefix of the key before it, and `step` stands in a
        // comment first: a text search would point at the wrong line.
        let text =
            "# step by step\n[simulator]\npump_out_j_per_cc_m = 0.01\npump_out_j_per_cc = -1\n";
        let error = Config::parse(text, Path::new("/p")).expect_err("negative");
        let at = text.find("pump_out_j_per_cc =").expect("in the text");
        assert_eq!(error.span, Span::new(at, at + "pump_out_j_per_cc".len()));
        let text = "# step by step\n[simulator]\nstep = 9\n";
        let error = Config::parse(text, Path::new("/p")).expect_err("too long");
        let at = text.find("step =").expect("in the text");
        assert_eq!(error.span, Span::new(at, at + 4));
    }

    #[test]
    fn an_empty_file_is_the_default() {
        let config = parsed("");
        assert_eq!(config.masterdata, None);
        assert_eq!(config.cycle_budget, None);
    }

    #[test]
    fn an_unknown_key_points_at_the_key() {
        refused(
            "cycle_budget = 5\nmasterdta = \"x\"\n",
            "masterdta",
            "masterdta",
        );
    }

    #[test]
    fn a_wrong_type_and_a_zero_budget_are_errors() {
        let text = "cycle_budget = \"many\"\n";
        let error = Config::parse(text, Path::new("/p")).expect_err("string budget");
        assert_eq!(&text[error.span.range()], "\"many\"");
        // The span is the offending value, as for the string above.
        let error = Config::parse("cycle_budget = 0", Path::new("/p")).expect_err("zero");
        assert_eq!(error.span, Span::new(15, 16));
        // Above the maximum: a run with it might never finish a cycle.
        refused(
            "cycle_budget = 9223372036854775807",
            "9223372036854775807",
            "1 to 1000000000 ",
        );
        parsed("cycle_budget = 1000000000");
    }

    #[test]
    fn syntax_errors_do_not_panic_and_have_a_span() {
        for text in [
            "masterdata = ",
            "[[[",
            "cycle_budget = -1",
            "\u{0}\u{1}",
            "a = 'é",
        ] {
            let error = Config::parse(text, Path::new("/p")).expect_err(text);
            assert!(error.span.end as usize <= text.len(), "{text:?}");
        }
    }

    #[test]
    fn discover_walks_up_and_reports_bad_files_with_line_and_column() {
        let root = gloc_testsupport::scratch_dir("config-test");
        let nested = root.join("a").join("b");
        std::fs::create_dir_all(&nested).expect("temp dir");
        std::fs::write(root.join(FILE_NAME), "cycle_budget = 77\n").expect("write");
        let script = nested.join("s.gloc");
        let config = Config::discover(&script).expect("found");
        assert_eq!(config.cycle_budget.map(|budget| budget.value), Some(77));
        assert_eq!(config.path, Some(root.join(FILE_NAME)));

        std::fs::write(root.join("a").join(FILE_NAME), "\nmission = 3\n").expect("write");
        let error = Config::discover(&script).expect_err("bad nearer file");
        assert!(
            error.to_string().ends_with(
                "gloc.toml:2:11: invalid gloc.toml: invalid type: integer `3`, expected a string"
            ),
            "{error}"
        );
        std::fs::remove_dir_all(&root).expect("cleanup");
    }
}
