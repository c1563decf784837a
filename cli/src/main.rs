//! `gloc`: the one binary. Parses the command line and hands each subcommand
//! to its module; all language knowledge lives in the library crates.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

mod check;
mod compile;
pub mod render;
mod replay;
mod run;
mod settings;
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
    /// Check GLOC or GBASIC files and print every diagnostic.
    Check(CheckArgs),
    /// Compile a GBASIC file to GLOC.
    Compile(CompileArgs),
    /// Run a script: on recorded sensor values (--replay) or in the simulator.
    Run(RunArgs),
    /// Start the language server on stdio.
    Lsp,
    /// Start the debug adapter (stdio, or a TCP port on 127.0.0.1).
    Dap(DapArgs),
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// `.gloc` or `.gbas` files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Print registers, labels, instructions and the worst-case instructions per cycle.
    #[arg(long)]
    pub stats: bool,
    /// A masterdata file or a `.cac` sensor list replacing the embedded list.
    #[arg(long, value_name = "FILE")]
    pub masterdata: Option<PathBuf>,
    /// How a masterdata file's sensors are numbered: `file` (default) or `sorted` (firmware 2014+).
    #[arg(long, value_name = "ORDER", value_parser = settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
}

#[derive(Args, Debug)]
pub struct CompileArgs {
    /// The GBASIC source.
    pub file: PathBuf,
    /// Where to write the GLOC (default: the source with `.gloc`).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Optimize.
    #[arg(short = 'O')]
    pub optimize: bool,
    /// Also write the source map (`OUT.map.json`).
    #[arg(long)]
    pub emit_map: bool,
    #[arg(long, value_name = "FILE")]
    pub masterdata: Option<PathBuf>,
    /// How a masterdata file's sensors are numbered: `file` (default) or `sorted` (firmware 2014+).
    #[arg(long, value_name = "ORDER", value_parser = settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
}

#[derive(Args, Debug)]
pub struct RunArgs {
    /// A `.gloc` or `.gbas` script (default: the paper's Fig. 2 script).
    pub script: Option<PathBuf>,
    /// Replay recorded sensor values (CSV: a header of sensor names, one row per cycle) instead of simulating.
    #[arg(long, value_name = "IN.csv")]
    pub replay: Option<PathBuf>,
    /// With --replay: write the sensors the script stored, one row per cycle.
    #[arg(long, value_name = "OUT.csv")]
    pub out: Option<PathBuf>,
    /// Per-cycle instruction budget (a script that runs longer traps with "cycle overrun").
    #[arg(long, value_name = "N")]
    pub cycle_budget: Option<u64>,
    /// Mission file (`.mi`); default: the embedded Fig. 2 mission.
    #[arg(long, value_name = "M.mi")]
    pub mission: Option<PathBuf>,
    #[arg(long, value_name = "FILE")]
    pub masterdata: Option<PathBuf>,
    /// How a masterdata file's sensors are numbered: `file` (default) or `sorted` (firmware 2014+).
    #[arg(long, value_name = "ORDER", value_parser = settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
    /// Temperature profile CSV (`depth_m,temp_degC`); default: the built-in summer shelf profile.
    #[arg(long, value_name = "T.csv")]
    pub profile: Option<PathBuf>,
    /// Simulated duration, e.g. `90m`, `6h`, `30d`.
    #[arg(long, conflicts_with = "cycles")]
    pub duration: Option<String>,
    /// Number of control cycles to simulate.
    #[arg(long)]
    pub cycles: Option<u64>,
    /// Seed for sensor noise.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Log file: `.csv`, or Slocum ASCII (`.dba`).
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Sensors to log, comma-separated (default: what a pilot looks at, plus the sensors the script stores).
    #[arg(long, value_name = "NAMES")]
    pub log_sensors: Option<String>,
    /// Inject a sensor fault (repeatable): SENSOR:KIND@START[..END], KIND one of nan, dropout,
    /// stuck=VALUE, spike=OFFSET; cycles from 0, END excluded. E.g. `m_depth:nan@20`.
    #[arg(long = "fault", value_name = "SENSOR:KIND@START[..END]")]
    pub faults: Vec<String>,
    /// Set a flight or energy constant (repeatable), e.g. `dive_rate=0.2`; wins over
    /// `[simulator]` in gloc.toml. The names and ranges are in docs/simulator.md.
    #[arg(long = "sim", value_name = "NAME=VALUE", value_parser = settings::parse_simulator_setting)]
    pub simulator: Vec<(String, f64)>,
    /// Write an SVG flight profile.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// How the summary is printed on stderr at the end: `text` (default) or `json` (one line,
    /// for editors; the fields are in docs/simulator.md).
    #[arg(long, value_name = "FORMAT", value_enum, default_value = "text")]
    pub summary: SummaryFormat,
    /// Compile a GBASIC script with the optimizer.
    #[arg(short = 'O')]
    pub optimize: bool,
}

/// The form of `gloc run`'s summary.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SummaryFormat {
    Text,
    Json,
}

#[derive(Args, Debug)]
pub struct DapArgs {
    /// Listen on 127.0.0.1:PORT instead of stdio (0: any free port). Prints the port and
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
        Command::Lsp => gloc_lsp_main(),
        Command::Dap(args) => gloc_dap_main(args),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
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
