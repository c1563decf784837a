//! `gloc`: the one binary. Parses the command line and hands each subcommand
//! to its module; all language knowledge lives in the library crates.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use gloc_compiler::Optimization;

/// `print!` for what a command reports on stdout, through [`output::print`]: a
/// closed pipe (`gloc data info … | head -2`) ends the output quietly instead of
/// panicking.
macro_rules! out {
    ($($arg:tt)*) => { $crate::output::print(format_args!($($arg)*)) };
}

/// `println!` through [`output::print`] (see `out!`).
macro_rules! outln {
    () => { $crate::output::print(format_args!("\n")) };
    ($($arg:tt)*) => {
        $crate::output::print(format_args!("{}\n", format_args!($($arg)*)))
    };
}

mod batch;
mod calibrate;
mod check;
mod compile;
mod data;
mod exit;
mod explain;
mod flags;
mod forecast;
mod loading;
mod output;
mod reindex;
pub mod render;
mod replay;
mod run;
mod signals;
mod simulate;

#[derive(Parser, Debug)]
#[command(
    name = "gloc",
    version,
    about = "Scripting toolchain for the Slocum glider: GLOC, GBASIC, simulator, LSP and DAP"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process: the size of the `run` arguments does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand, Debug)]
enum Command {
    /// Check scripts, missions (`.mi`, `.ma`) and sensor lists and print every diagnostic.
    Check(CheckArgs),
    /// Compile a GBASIC file to GLOC.
    Compile(CompileArgs),
    /// Run a script: on recorded sensor values (--replay) or in the simulator.
    Run(RunArgs),
    /// Rewrite a GLOC file's sensor indices from one sensor list to another, by name.
    Reindex(ReindexArgs),
    /// Fly a script through a sweep of missions on all cores; print one summary table.
    Batch(BatchArgs),
    /// Start the language server on stdio.
    Lsp,
    /// Start the debug adapter (stdio, or a TCP port on 127.0.0.1).
    Dap(DapArgs),
    /// Glider logs (.dbd .ebd .sbd .tbd …, compressed .dcd …, .dba): info, convert, plot.
    #[command(subcommand)]
    Data(data::DataCommand),
    /// Fit the simulator's constants from a glider's own logs; writes a [simulator] table.
    Calibrate(calibrate::CalibrateArgs),
    /// Explain a diagnostic code (`gloc explain E0101`), or list them all.
    Explain(explain::ExplainArgs),
    /// Forecast where a glider will be from its logs and its mission (surfacings, track,
    /// ensembles as GeoJSON, KML, CSV), or hindcast the logs' segments.
    Forecast(forecast::ForecastArgs),
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// `.gloc` or `.gbas` scripts, `.mi` missions, `.ma` argument files (each checked
    /// as the behavior its `behavior_name=` names), masterdata or `.cac` sensor lists.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Print registers, labels, instructions and the worst-case instructions per cycle.
    #[arg(long)]
    pub stats: bool,
    #[command(flatten)]
    pub sensors: crate::flags::SensorListArgs,
    /// Per-cycle instruction budget the worst case is held against (warning W2302), 1 to
    /// 1,000,000,000; default: gloc.toml's, else 10,000.
    #[arg(long, value_name = "N", value_parser = gloc_project::settings::parse_cycle_budget)]
    pub cycle_budget: Option<u64>,
    /// A folder searched first for the mission's `.ma` files, before `mafiles/` beside
    /// `missions/` and the mission's own folder; default: gloc.toml's `mafiles`.
    #[arg(long, value_name = "DIR")]
    pub mafiles: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct CompileArgs {
    /// The GBASIC source.
    pub file: PathBuf,
    /// Where to write the GLOC; default: the source with `.gloc`.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Optimize (default: not optimized, the code the debugger runs).
    #[arg(short = 'O')]
    pub optimize: bool,
    /// Also write the source map (`OUT.map.json`).
    #[arg(long)]
    pub emit_map: bool,
    #[command(flatten)]
    pub sensors: crate::flags::SensorListArgs,
}

#[derive(Args, Debug)]
pub struct RunArgs {
    /// A `.gloc` or `.gbas` script (default: the paper's Fig. 2 script).
    pub script: Option<PathBuf>,
    /// Replay recorded sensor values instead of simulating: one CSV file (a header of
    /// sensor names, one row per cycle) or glider logs (.dbd .ebd .sbd .tbd …, .dcd …,
    /// .dba; several files are a deployment, flight and science logs merged); default: simulate.
    #[arg(long, value_name = "FILES", num_args = 1..)]
    pub replay: Vec<PathBuf>,
    /// With --replay of glider logs: the folder searched first for their sensor lists
    /// (`<crc>.cac` / `.ccc`); default: `sensor_cache` in gloc.toml.
    #[arg(long, value_name = "DIR")]
    pub sensor_cache: Option<PathBuf>,
    /// With --replay: write the sensors the script stored, one row per cycle (default: none).
    #[arg(long, value_name = "OUT.csv")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub flight: flags::FlightArgs,
    /// Temperature profile CSV (`depth_m,temp_degC`); default: the built-in summer shelf profile.
    #[arg(long, value_name = "T.csv")]
    pub profile: Option<PathBuf>,
    #[command(flatten)]
    pub length: flags::LengthArgs,
    /// Seed for sensor noise; default 1.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Log file: `.csv`, Slocum ASCII (`.dba`), or Slocum binary (`.dbd`, plus `.ebd` for the
    /// `sci_` sensors, each with its `<crc>.cac` beside it); default: no log.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Sensors to log, comma-separated (default: what a pilot looks at, plus the sensors the script stores).
    #[arg(long, value_name = "NAMES")]
    pub log_sensors: Option<String>,
    /// Inject a sensor fault (repeatable): SENSOR:KIND@START[..END], KIND one of nan, dropout,
    /// stuck=VALUE, spike=OFFSET; cycles from 0, END excluded. E.g. `m_depth:nan@20`.
    #[arg(long = "fault", value_name = "SENSOR:KIND@START[..END]")]
    pub faults: Vec<String>,
    /// Set a flight or energy constant (repeatable), e.g. `drag_cd0=0.2`; wins over
    /// `[simulator]` in gloc.toml. The names and ranges are in docs/simulator.md.
    #[arg(long = "sim", value_name = "NAME=VALUE", value_parser = gloc_project::settings::parse_simulator_setting)]
    pub simulator: Vec<(String, f64)>,
    /// Write the flight profile: SVG or PNG by the extension (default: no plot).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    /// Extra plot panels, comma-separated: `temperature` (the track coloured by
    /// the water temperature), `battery` (a voltage panel), or a sensor's name
    /// (its own panel, e.g. `sci_ruhp_climb_depth`); default: none (the depth track and
    /// the store events only).
    #[arg(long, value_name = "PANELS", value_delimiter = ',')]
    pub plot_panels: Vec<String>,
    /// How the summary is printed on stderr at the end: `text` (default) or `json` (one line,
    /// for editors; the fields are in docs/simulator.md).
    #[arg(long, value_name = "FORMAT", value_enum, default_value = "text")]
    pub summary: SummaryFormat,
    /// Compile a GBASIC script with the optimizer: the default (kept for old command lines).
    #[arg(short = 'O', conflicts_with = "no_optimize")]
    pub optimize: bool,
    /// Compile a GBASIC script without the optimizer (the code `gloc dap` runs).
    #[arg(long)]
    pub no_optimize: bool,
}

impl RunArgs {
    /// GBASIC runs optimized unless `--no-optimize` says otherwise.
    pub fn optimization(&self) -> Optimization {
        optimized_unless(self.no_optimize)
    }
}

impl BatchArgs {
    /// GBASIC flies optimized unless `--no-optimize` says otherwise.
    pub fn optimization(&self) -> Optimization {
        optimized_unless(self.no_optimize)
    }
}

impl CompileArgs {
    /// `-O` compiles with the optimizer.
    pub fn optimization(&self) -> Optimization {
        if self.optimize {
            Optimization::Optimized
        } else {
            Optimization::Plain
        }
    }
}

/// `--no-optimize` as an [`Optimization`].
fn optimized_unless(no_optimize: bool) -> Optimization {
    if no_optimize {
        Optimization::Plain
    } else {
        Optimization::Optimized
    }
}

#[derive(Args, Debug)]
pub struct BatchArgs {
    /// A `.gloc` or `.gbas` script (default: the paper's Fig. 2 script).
    pub script: Option<PathBuf>,
    #[command(flatten)]
    pub flight: flags::FlightArgs,
    #[command(flatten)]
    pub length: flags::LengthArgs,
    /// Seeds to fly: numbers and inclusive ranges, e.g. `1-100` or `1,5,9-12` (default 1).
    #[arg(long, value_name = "LIST")]
    pub seeds: Option<String>,
    /// A temperature profile CSV to fly (repeatable; `builtin` for the built-in profile);
    /// default: `builtin`.
    #[arg(long = "profile", value_name = "T.csv")]
    pub profiles: Vec<String>,
    /// The faults of one variant, comma-separated as `gloc run --fault` takes them
    /// (repeatable; `none` for a variant without faults); default: `none`.
    #[arg(long = "fault-set", value_name = "FAULTS")]
    pub fault_sets: Vec<String>,
    /// A simulator setting and the values to sweep (repeatable), e.g. `drag_cd0=0.15,0.2`;
    /// default: gloc.toml's `[simulator]`, else the built-in constants.
    #[arg(long = "sim", value_name = "NAME=V1,V2")]
    pub simulator: Vec<String>,
    /// Missions flown at once (default: the number of cores).
    #[arg(long, short = 'j')]
    pub jobs: Option<usize>,
    /// Also write the table as CSV (default: the table on stdout only).
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Compile a GBASIC script without the optimizer (default: optimized).
    #[arg(long)]
    pub no_optimize: bool,
}

#[derive(Args, Debug)]
pub struct ReindexArgs {
    /// The `.gloc` script.
    pub file: PathBuf,
    /// The list its indices are for (default: the list its `# sensors:` line names,
    /// else the embedded list).
    #[arg(long, value_name = "LIST")]
    pub from: Option<PathBuf>,
    /// The list to rewrite them for (masterdata or `.cac`).
    #[arg(long, value_name = "LIST")]
    pub to: PathBuf,
    /// Where to write the result (never the input).
    #[arg(short = 'o', long = "output", value_name = "OUT.gloc")]
    pub output: PathBuf,
    /// How a masterdata file's sensors are numbered: `file` or `sorted` (firmware 2014+);
    /// default: `file`.
    #[arg(long, value_name = "ORDER", value_parser = gloc_project::settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
}

/// The form of `gloc run`'s summary.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SummaryFormat {
    Text,
    Json,
}

#[derive(Args, Debug)]
pub struct DapArgs {
    /// Listen on 127.0.0.1:PORT instead of stdio (0: any free port); default: stdio. Prints the port and
    /// the session token that each client's `launch` must carry (`token` attribute).
    #[arg(long)]
    pub port: Option<u16>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check(args) => check::main(args),
        Command::Compile(args) => compile::main(args),
        Command::Run(args) => run::main(args),
        Command::Reindex(args) => reindex::main(args),
        Command::Batch(args) => batch::main(args),
        Command::Lsp => gloc_lsp_main(),
        Command::Dap(args) => gloc_dap_main(args),
        Command::Data(command) => data::main(command),
        Command::Calibrate(args) => calibrate::main(args),
        Command::Explain(args) => explain::main(args),
        Command::Forecast(args) => forecast::main(args),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            exit::code(exit::of_error(&error))
        }
    }
}

fn gloc_lsp_main() -> anyhow::Result<ExitCode> {
    match gloc_lsp::run_stdio()? {
        gloc_lsp::Ending::Clean => Ok(ExitCode::SUCCESS),
        gloc_lsp::Ending::WithoutShutdown => Ok(ExitCode::from(1)),
    }
}

fn gloc_dap_main(args: DapArgs) -> anyhow::Result<ExitCode> {
    use anyhow::Context as _;
    match args.port {
        None => gloc_dap::serve_stdio().context("debug adapter on stdio")?,
        Some(port) => gloc_dap::serve_tcp(port, |address, token| {
            // One write, so that a client reading chunk by chunk sees the whole line.
            use std::io::Write as _;
            let line = format!("gloc dap: listening on {address} token {token}\n");
            let mut stderr = std::io::stderr().lock();
            let _ = stderr
                .write_all(line.as_bytes())
                .and_then(|()| stderr.flush());
        })
        .with_context(|| format!("debug adapter on 127.0.0.1:{port}"))?,
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every subcommand, nested ones too, with its path (`gloc data info`).
    fn all(command: &clap::Command, path: String, out: &mut Vec<(String, clap::Command)>) {
        out.push((path.clone(), command.clone()));
        for sub in command.get_subcommands() {
            all(sub, format!("{path} {}", sub.get_name()), out);
        }
    }

    #[test]
    fn every_flag_of_every_subcommand_has_a_description() {
        let mut commands = Vec::new();
        all(&Cli::command(), "gloc".into(), &mut commands);
        let mut missing = Vec::new();
        for (path, command) in &commands {
            for argument in command.get_arguments() {
                let name = argument.get_id().as_str();
                if matches!(name, "help" | "version") {
                    continue;
                }
                if argument.get_help().is_none() && argument.get_long_help().is_none() {
                    missing.push(format!("{path} {name}"));
                }
            }
        }
        assert!(missing.is_empty(), "without a description: {missing:?}");
    }

    #[test]
    fn help_shows_every_default() {
        // The defaults, from the code that applies them: the budget (CycleBudget),
        // the seed (SimConfig), the run's length (DEFAULT_LIMIT_SECONDS = 24 h).
        assert_eq!(gloc_project::CycleBudget::DEFAULT.get(), 10_000);
        assert_eq!(gloc_sim::SimConfig::default().seed, 1);
        assert_eq!(flags::DEFAULT_LIMIT_SECONDS, 24.0 * 3600.0);
        let mut root = Cli::command();
        let help = |root: &mut clap::Command, name: &str| {
            root.find_subcommand_mut(name)
                .map(|command| command.render_long_help().to_string())
                .unwrap_or_default()
        };
        let run = help(&mut root, "run");
        for default in [
            "else 10,000",
            "default 1",
            "at most 24 h",
            "the embedded 2008 list",
        ] {
            assert!(
                run.contains(default),
                "run --help lacks `{default}`:\n{run}"
            );
        }
        let check = help(&mut root, "check");
        assert!(check.contains("else 10,000"), "{check}");
        let compile = help(&mut root, "compile");
        assert!(compile.contains("the embedded 2008 list"), "{compile}");
        // Every option that takes a value and has no clap default says its default.
        let mut commands = Vec::new();
        all(&Cli::command(), "gloc".into(), &mut commands);
        let mut silent = Vec::new();
        for (path, command) in &commands {
            for argument in command.get_arguments() {
                let takes_value = argument.get_action().takes_values();
                let optional = !argument.is_required_set() && !argument.is_positional();
                let help = format!(
                    "{}{}",
                    argument
                        .get_help()
                        .map(ToString::to_string)
                        .unwrap_or_default(),
                    argument
                        .get_long_help()
                        .map(ToString::to_string)
                        .unwrap_or_default()
                )
                .to_lowercase();
                // A repeatable flag given no times is simply not applied.
                let said = help.contains("default")
                    || !argument.get_default_values().is_empty()
                    || help.contains("repeatable");
                if takes_value && optional && !said {
                    silent.push(format!("{path} --{}", argument.get_id()));
                }
            }
        }
        assert!(
            silent.is_empty(),
            "options that do not say their default: {silent:?}"
        );
    }
}
