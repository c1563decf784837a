//! Project settings, resolved once for every surface: a command-line flag, an
//! editor setting or a launch attribute wins over the nearest `gloc.toml` above the
//! script, which wins over the built-in default. The front ends pass what they were
//! given as [`Overrides`]; every value is checked here, once, into a type that
//! cannot hold a meaningless value, and every error names where the value came from.

use std::fmt;
use std::num::NonZeroU64;
use std::path::{Path, PathBuf};

use gloc_sim::settings::check_simulator_setting;

use crate::config::{
    check_cycle_budget, Config, ConfigError, Placed, CODE_UNREADABLE_CONFIG, MAX_CYCLE_BUDGET,
};
use gloc_engine::sensors::SensorOrder;
use gloc_engine::vm::DEFAULT_CYCLE_BUDGET;

use crate::error::{ErrorKind, ProjectError};

/// The surface that passes overrides in: it decides how a setting is named in an error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Surface {
    /// `gloc check`, `run`, `compile`, `batch`: flags such as `--cycle-budget`.
    #[default]
    Cli,
    /// The language server: the editor's `gloc.*` settings.
    Editor,
    /// The debugger: the attributes of a `launch` request.
    Launch,
}

/// A project setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    Masterdata,
    CycleBudget,
    Mission,
    SensorOrder,
    SensorCache,
    Simulator,
}

impl Setting {
    /// The setting's name on a surface: the flag, the editor setting or the launch attribute.
    pub fn name(self, surface: Surface) -> &'static str {
        use Setting::*;
        match (surface, self) {
            (Surface::Cli, Masterdata) => "--masterdata",
            (Surface::Cli, CycleBudget) => "--cycle-budget",
            (Surface::Cli, Mission) => "--mission",
            (Surface::Cli, SensorOrder) => "--sensor-order",
            (Surface::Cli, SensorCache) => "--sensor-cache",
            (Surface::Cli, Simulator) => "--sim",
            (Surface::Editor, Masterdata) => "gloc.masterdata",
            (Surface::Editor, CycleBudget) => "gloc.cycleBudget",
            (Surface::Editor, Mission) => "gloc.mission",
            (Surface::Editor, SensorOrder) => "gloc.sensorOrder",
            (Surface::Editor, SensorCache) => "gloc.sensorCache",
            (Surface::Editor, Simulator) => "gloc.simulator",
            (Surface::Launch, Masterdata) => "masterdata",
            (Surface::Launch, CycleBudget) => "cycleBudget",
            (Surface::Launch, Mission) => "mission",
            (Surface::Launch, SensorOrder) => "sensorOrder",
            (Surface::Launch, SensorCache) => "sensorCache",
            (Surface::Launch, Simulator) => "simulator",
        }
    }

    /// Where an override of this setting came from.
    pub fn origin(self, surface: Surface) -> Origin {
        let name = self.name(surface);
        match surface {
            Surface::Cli => Origin::Flag(name),
            Surface::Editor => Origin::EditorSetting(name),
            Surface::Launch => Origin::LaunchAttribute(name),
        }
    }
}

/// Where a value came from; an error about the value starts with it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Origin {
    /// The built-in default.
    #[default]
    Default,
    /// A command-line flag, e.g. `--cycle-budget`.
    Flag(&'static str),
    /// An editor setting, e.g. `gloc.cycleBudget`.
    EditorSetting(&'static str),
    /// An attribute of the debugger's `launch` request, e.g. `cycleBudget`.
    LaunchAttribute(&'static str),
    /// A value in a `gloc.toml`, at its line and column (from 1).
    GlocToml {
        path: PathBuf,
        line: usize,
        column: usize,
    },
    /// A whole file (a `gloc.toml` that cannot be read).
    File(PathBuf),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Default => f.write_str("the default"),
            Origin::Flag(name) => f.write_str(name),
            Origin::EditorSetting(name) => write!(f, "editor setting {name}"),
            Origin::LaunchAttribute(name) => write!(f, "launch attribute {name}"),
            Origin::GlocToml { path, line, column } => {
                write!(f, "{}:{line}:{column}", path.display())
            }
            Origin::File(path) => write!(f, "{}", path.display()),
        }
    }
}

/// A value and where it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sourced<T> {
    pub value: T,
    pub origin: Origin,
}

/// A per-cycle instruction budget: 1 to [`MAX_CYCLE_BUDGET`], nothing else.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CycleBudget(NonZeroU64);

impl CycleBudget {
    /// 10,000 instructions per cycle ([`DEFAULT_CYCLE_BUDGET`]).
    pub const DEFAULT: CycleBudget =
        CycleBudget(NonZeroU64::MIN.saturating_add(DEFAULT_CYCLE_BUDGET - 1));
    /// The largest budget allowed.
    pub const MAX: u64 = MAX_CYCLE_BUDGET;

    /// Checks a budget from any source (the rule is `crate::config::check_cycle_budget`).
    pub fn new(budget: u64) -> Result<CycleBudget, String> {
        let budget = check_cycle_budget(budget)?;
        NonZeroU64::new(budget).map(CycleBudget).ok_or_else(|| {
            format!(
                "the cycle budget must be 1 to {MAX_CYCLE_BUDGET} instructions per cycle, not 0"
            )
        })
    }

    pub fn get(self) -> u64 {
        self.0.get()
    }
}

impl Default for CycleBudget {
    fn default() -> Self {
        CycleBudget::DEFAULT
    }
}

impl fmt::Display for CycleBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// What a front end was given (flags, editor settings, launch attributes); `None`
/// where nothing was given. Values are raw: [`Settings::resolve`] checks them.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub surface: Surface,
    pub masterdata: Option<PathBuf>,
    pub cycle_budget: Option<u64>,
    pub mission: Option<PathBuf>,
    pub sensor_order: Option<SensorOrder>,
    pub sensor_cache: Option<PathBuf>,
    /// A folder searched first for a mission's `.ma` files (`--mafiles`).
    pub mafiles: Option<PathBuf>,
    /// Simulator constants, applied after gloc.toml's `[simulator]` (so they win).
    pub simulator: Vec<(String, f64)>,
}

impl Overrides {
    pub fn new(surface: Surface) -> Overrides {
        Overrides {
            surface,
            ..Overrides::default()
        }
    }
}

/// The settings of one script's project, checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// The `gloc.toml` that was read, if any (an input no output may overwrite).
    pub config_path: Option<PathBuf>,
    /// The sensor list replacing the embedded one.
    pub masterdata: Option<Sourced<PathBuf>>,
    pub cycle_budget: Sourced<CycleBudget>,
    /// The mission to fly; `None`: the embedded Fig. 2 mission.
    pub mission: Option<Sourced<PathBuf>>,
    pub sensor_order: SensorOrder,
    /// The folder searched first for a glider log's sensor list.
    pub sensor_cache: Option<PathBuf>,
    /// The folder searched first for a mission's `.ma` files, trusted wherever it is.
    pub mafiles: Option<PathBuf>,
    /// Simulator constants in the order to apply them (gloc.toml's, then the overrides').
    pub simulator: Vec<(String, f64)>,
}

impl Default for Sourced<CycleBudget> {
    fn default() -> Self {
        Sourced {
            value: CycleBudget::DEFAULT,
            origin: Origin::Default,
        }
    }
}

/// Refuses a file that `gloc.toml` names outside the folder holding it (the project
/// tree), symbolic links followed: a gloc.toml in a parent folder, or one a
/// repository brings, could otherwise have `check` print `/etc/passwd` or
/// `/proc/self/environ` as diagnostics. A file the user names (a flag, an editor
/// setting, a launch attribute) may be anywhere. A path that does not exist is left
/// to the reader, which says it cannot be read.
fn within_project(
    path: &Path,
    config: Option<&Path>,
    setting: Setting,
    surface: Surface,
) -> Result<(), String> {
    let folder = match config.and_then(Path::parent) {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        Some(_) => Path::new("."),
        None => return Ok(()),
    };
    let (Ok(real), Ok(root)) = (path.canonicalize(), folder.canonicalize()) else {
        return Ok(());
    };
    if real.starts_with(&root) {
        return Ok(());
    }
    Err(format!(
        "`{}` is outside the project folder `{}` (where gloc.toml is){}: gloc.toml may name only files inside it; to use this file, give it as {}",
        path.display(),
        root.display(),
        if real.as_path() == path {
            String::new()
        } else {
            format!(" (it is `{}`)", real.display())
        },
        setting.origin(surface)
    ))
}

impl Settings {
    /// Finds the `gloc.toml` that applies to `anchor` (a script; the current folder when
    /// `None`) and resolves the overrides over it.
    pub fn resolve(anchor: Option<&Path>, overrides: Overrides) -> Result<Settings, ProjectError> {
        let config = match anchor {
            Some(script) => Config::discover(script),
            None => {
                let here = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
                match Config::find(&here) {
                    Some(path) => Config::load(&path),
                    None => Ok(Config::default()),
                }
            }
        };
        Settings::from_config(config.map_err(config_error)?, overrides)
    }

    /// The one precedence rule: an override wins over `gloc.toml`, which wins over the
    /// default. Every override is checked here.
    pub fn from_config(config: Config, overrides: Overrides) -> Result<Settings, ProjectError> {
        let surface = overrides.surface;
        let from_file = |(line, column): (usize, usize)| match &config.path {
            Some(path) => Origin::GlocToml {
                path: path.clone(),
                line,
                column,
            },
            None => Origin::Default,
        };
        let pick =
            |given: Option<PathBuf>, setting: Setting, file: Option<Placed<PathBuf>>| match given
                .filter(|path| !path.as_os_str().is_empty())
            {
                Some(value) => Ok(Some(Sourced {
                    value,
                    origin: setting.origin(surface),
                })),
                None => match file {
                    Some(Placed { value, at }) => {
                        let origin = from_file(at);
                        match within_project(&value, config.path.as_deref(), setting, surface) {
                            Ok(()) => Ok(Some(Sourced { value, origin })),
                            Err(message) => {
                                Err(ProjectError::new(ErrorKind::Setting, Some(origin), message))
                            }
                        }
                    }
                    None => Ok(None),
                },
            };
        let budget = |budget: u64, origin: Origin| match CycleBudget::new(budget) {
            Ok(value) => Ok(Sourced { value, origin }),
            Err(message) => Err(ProjectError::new(ErrorKind::Setting, Some(origin), message)),
        };
        let cycle_budget = match (overrides.cycle_budget, config.cycle_budget) {
            (Some(given), _) => budget(given, Setting::CycleBudget.origin(surface))?,
            // gloc.toml's budget was checked when it was parsed (E0901).
            (None, Some(file)) => budget(file.value, from_file(file.at))?,
            (None, None) => Sourced::default(),
        };
        for (name, value) in &overrides.simulator {
            check_simulator_setting(name, *value).map_err(|message| {
                ProjectError::new(
                    ErrorKind::Setting,
                    Some(Setting::Simulator.origin(surface)),
                    message,
                )
            })?;
        }
        Ok(Settings {
            masterdata: pick(overrides.masterdata, Setting::Masterdata, config.masterdata)?,
            mission: pick(overrides.mission, Setting::Mission, config.mission)?,
            cycle_budget,
            sensor_order: overrides
                .sensor_order
                .or(config.sensor_order.map(|order| order.value))
                .unwrap_or_default(),
            sensor_cache: overrides
                .sensor_cache
                .filter(|path| !path.as_os_str().is_empty())
                .or(config.sensor_cache.map(|folder| folder.value)),
            mafiles: overrides
                .mafiles
                .filter(|path| !path.as_os_str().is_empty())
                .or(config.mafiles.map(|folder| folder.value)),
            simulator: config
                .simulator
                .into_iter()
                .chain(overrides.simulator)
                .collect(),
            config_path: config.path,
        })
    }

    /// The files these settings name (masterdata, mission, gloc.toml).
    pub fn input_paths(&self) -> impl Iterator<Item = &Path> {
        [
            self.masterdata.as_ref().map(|sourced| &sourced.value),
            self.mission.as_ref().map(|sourced| &sourced.value),
            self.config_path.as_ref(),
        ]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
    }

    pub fn masterdata_path(&self) -> Option<&Path> {
        self.masterdata
            .as_ref()
            .map(|sourced| sourced.value.as_path())
    }

    /// The folders searched for the list a GLOC file's `# sensors:` line names.
    pub fn list_folders(&self, script: Option<&Path>) -> Vec<PathBuf> {
        gloc_engine::gloc::identity::list_folders(
            script,
            self.masterdata_path(),
            self.sensor_cache.as_deref(),
        )
    }
}

/// The `gloc.toml` that applies to a script: the nearest in its folder or above.
pub fn config_path_for(script: &Path) -> Option<PathBuf> {
    Config::find(script)
}

/// Reads the `gloc.toml` at `path`; `unsaved` is an editor's text of it when open
/// (it wins over the file on disk). Errors keep the text, for positions.
pub fn read_config(path: &Path, unsaved: Option<String>) -> Result<Config, ConfigError> {
    match unsaved {
        None => Config::load(path),
        Some(text) => {
            let folder = path.parent().unwrap_or(Path::new("."));
            Config::parse(&text, folder)
                .map(|mut config| {
                    config.path = Some(path.to_path_buf());
                    config
                })
                .map_err(|diagnostic| ConfigError {
                    path: path.to_path_buf(),
                    text: Some(text),
                    diagnostic,
                })
        }
    }
}

/// A `gloc.toml` that cannot be used, as a project error at its line and column.
pub fn config_error(error: ConfigError) -> ProjectError {
    let kind = if error.diagnostic.code == CODE_UNREADABLE_CONFIG {
        ErrorKind::Unreadable
    } else {
        ErrorKind::Setting
    };
    let origin = match &error.text {
        Some(text) => {
            let index = gloc_engine::LineIndex::new(text);
            let (line, column) = index.line_col(text, error.diagnostic.span.start as usize);
            Origin::GlocToml {
                path: error.path.clone(),
                line,
                column,
            }
        }
        None => Origin::File(error.path.clone()),
    };
    ProjectError::new(kind, Some(origin), error.diagnostic.message.clone())
}

/// Parses a cycle budget typed as text (a flag): a whole number, then [`CycleBudget::new`].
pub fn parse_cycle_budget(text: &str) -> Result<u64, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a whole number of instructions"))
}

/// Parses `NAME=VALUE` (`--sim`), checked as gloc.toml's `[simulator]` entries are.
pub fn parse_simulator_setting(text: &str) -> Result<(String, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not NAME=VALUE, e.g. `drag_cd0=0.2`"))?;
    let (name, value) = (name.trim(), value.trim());
    let number: f64 = value
        .parse()
        .map_err(|_| format!("`{value}` is not a number (in `{text}`)"))?;
    check_simulator_setting(name, number)?;
    Ok((name.to_string(), number))
}

/// Parses a sensor order's name (`file` or `sorted`).
pub fn parse_sensor_order(name: &str) -> Result<SensorOrder, String> {
    SensorOrder::from_name(name).ok_or_else(|| format!("expected {}", SensorOrder::NAMES))
}

/// Test support: `/p/gloc.toml` holding `text` (a valid one), parsed.
#[cfg(test)]
pub(crate) fn test_config(text: &str) -> Config {
    let mut config = Config::parse(text, Path::new("/p")).expect("valid gloc.toml");
    config.path = Some(PathBuf::from("/p/gloc.toml"));
    config
}

/// Test support: the settings of `/p/gloc.toml` holding `text`, without overrides.
#[cfg(test)]
pub(crate) fn test_settings(text: &str) -> Settings {
    Settings::from_config(test_config(text), Overrides::default()).expect("valid settings")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_override_wins_over_gloc_toml_which_wins_over_the_default() {
        let file = test_config("cycle_budget = 500\nmasterdata = \"md.mi\"\n");
        let mut overrides = Overrides::new(Surface::Launch);
        overrides.masterdata = Some(PathBuf::from("/q/other.cac"));
        let settings = Settings::from_config(file.clone(), overrides).expect("valid");
        assert_eq!(settings.cycle_budget.value.get(), 500);
        assert_eq!(
            settings.cycle_budget.origin.to_string(),
            "/p/gloc.toml:1:16"
        );
        let masterdata = settings.masterdata.expect("given");
        assert_eq!(masterdata.value, PathBuf::from("/q/other.cac"));
        assert_eq!(masterdata.origin.to_string(), "launch attribute masterdata");
        let default = Settings::from_config(Config::default(), Overrides::default()).expect("ok");
        assert_eq!(default.cycle_budget.value.get(), 10_000);
        assert_eq!(default.cycle_budget.origin, Origin::Default);
        assert!(default.masterdata.is_none());
    }

    #[test]
    fn a_zero_budget_is_refused_with_the_same_words_on_every_surface() {
        let words = "the cycle budget must be 1 to 1000000000 instructions per cycle, not 0";
        for (surface, name) in [
            (Surface::Cli, "--cycle-budget"),
            (Surface::Editor, "editor setting gloc.cycleBudget"),
            (Surface::Launch, "launch attribute cycleBudget"),
        ] {
            let mut overrides = Overrides::new(surface);
            overrides.cycle_budget = Some(0);
            let error = Settings::from_config(Config::default(), overrides).expect_err("zero");
            assert_eq!(error.kind, ErrorKind::Setting);
            assert_eq!(error.to_string(), format!("{name}: {words}"));
        }
        let mut overrides = Overrides::new(Surface::Cli);
        overrides.cycle_budget = Some(MAX_CYCLE_BUDGET + 1);
        assert!(Settings::from_config(Config::default(), overrides).is_err());
        assert!(CycleBudget::new(MAX_CYCLE_BUDGET).is_ok());
        assert!(CycleBudget::new(1).is_ok());
    }

    #[test]
    fn a_bad_gloc_toml_names_its_line_and_column() {
        let folder = gloc_testsupport::scratch_dir("project");
        let toml = folder.join("gloc.toml");
        std::fs::write(&toml, "# budget\ncycle_budget = 0\n").expect("write");
        let error = Settings::resolve(Some(&folder.join("a.gbas")), Overrides::default())
            .expect_err("zero budget");
        // Line 2, column 16: `cycle_budget = ` is 15 characters.
        assert_eq!(
            error.origin,
            Some(Origin::GlocToml {
                path: toml.clone(),
                line: 2,
                column: 16
            })
        );
        assert!(error.message.contains("must be 1 to 1000000000"), "{error}");
        std::fs::remove_dir_all(&folder).ok();
    }

    #[test]
    fn simulator_overrides_are_checked_and_come_after_gloc_toml() {
        let file = test_config("[simulator]\ndrag_cd0 = 0.1\n");
        let mut overrides = Overrides::new(Surface::Cli);
        overrides.simulator = vec![("drag_cd0".into(), 0.3)];
        let settings = Settings::from_config(file.clone(), overrides).expect("valid");
        assert_eq!(
            settings.simulator,
            vec![("drag_cd0".to_string(), 0.1), ("drag_cd0".to_string(), 0.3)]
        );
        let mut overrides = Overrides::new(Surface::Launch);
        overrides.simulator = vec![("drag_c0".into(), 0.3)];
        let error = Settings::from_config(file, overrides).expect_err("unknown name");
        assert!(error.to_string().starts_with("launch attribute simulator: `drag_c0` is not a simulator setting; did you mean `drag_cd0`?"), "{error}");
    }
}
