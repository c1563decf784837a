//! `gloc run FILE.gloc --replay IN.csv [--out OUT.csv] [--cycle-budget N]`:
//! runs a script against recorded sensor values, one CSV row per control
//! cycle, and records what it stores.
//!
//! IN has a header of sensor names (any case; a `cycle` column is ignored)
//! and one row of numbers per cycle. An empty cell leaves the sensor as it
//! was. What the script prints goes to stdout as it happens. OUT gets
//! `cycle,<each sensor the script stores>` and one row per cycle (cycles count
//! from 0), with an empty cell where nothing was stored that cycle.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::{bail, Context};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::suggest;
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig, DEFAULT_CYCLE_BUDGET};

use crate::render::{SourceFile, Tally};

/// The paper's Fig. 2, the script `gloc run` uses when none is given.
pub const FIG2: &str = include_str!("../../examples/fig2.gloc");

pub fn main(args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    let Some(replay_path) = args.replay.clone() else {
        bail!("--replay IN.csv is required here");
    };
    for (given, flag) in [
        (args.mission.is_some(), "--mission"),
        (args.profile.is_some(), "--profile"),
        (args.duration.is_some(), "--duration"),
        (args.cycles.is_some(), "--cycles"),
        (args.seed.is_some(), "--seed"),
        (args.log.is_some(), "--log"),
        (args.plot.is_some(), "--plot"),
        (!args.faults.is_empty(), "--fault"),
    ] {
        if given {
            bail!("{flag} belongs to the simulator and cannot be used with --replay");
        }
    }
    let mut tally = Tally::default();
    let settings = crate::settings::resolve(
        args.script.as_deref(),
        crate::settings::Flags {
            masterdata: args.masterdata.as_deref(),
            cycle_budget: args.cycle_budget,
            sensor_order: args.sensor_order,
            ..Default::default()
        },
    )?;
    let sensors = match &settings.masterdata {
        Some(path) => match crate::check::load_sensors(path, settings.sensor_order, &mut tally)? {
            Some(list) => list,
            None => return Ok(ExitCode::FAILURE),
        },
        None => SensorList::embedded(),
    };
    let Some(script) = load_script(args.script.as_deref(), &sensors, args.optimized())? else {
        return Ok(ExitCode::FAILURE);
    };
    let config = MachineConfig {
        cycle_budget: settings.cycle_budget.unwrap_or(DEFAULT_CYCLE_BUDGET),
    };
    replay(&script, &sensors, &replay_path, args.out.as_ref(), config)
}

/// Loads the script (`.gloc`, or `.gbas` compiled in memory), printing
/// diagnostics to stderr. `None` when it has errors.
fn load_script(
    path: Option<&Path>,
    sensors: &SensorList,
    optimize: bool,
) -> anyhow::Result<Option<crate::compile::CliScript>> {
    let options = gloc_compiler::LoadOptions {
        optimize,
        cycle_budget: None,
    };
    let script = match path {
        Some(path) => crate::compile::read_script(path, sensors, &options)?,
        None => crate::compile::CliScript {
            display: "<fig2.gloc>".to_string(),
            text: FIG2.to_string(),
            loaded: gloc_compiler::load_script(
                FIG2,
                gloc_compiler::Language::Gloc,
                sensors,
                &options,
            ),
        },
    };
    script.render_all(|text| eprint!("{text}"));
    Ok(script.loaded.program.is_some().then_some(script))
}

/// The replay host: the sensor array, what the script stored this cycle,
/// and printing straight to stdout.
struct ReplayHost<'a> {
    values: Vec<f64>,
    /// Sensor index → column in OUT (`usize::MAX`: not a stored sensor).
    out_column: Vec<usize>,
    stored_this_cycle: Vec<Option<f64>>,
    stdout: std::io::StdoutLock<'a>,
    print_error: Option<std::io::Error>,
}

impl Host for ReplayHost<'_> {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        self.values.get(sensor.index()).copied().unwrap_or(0.0)
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        if let Some(slot) = self.values.get_mut(sensor.index()) {
            *slot = value;
        }
        if let Some(&column) = self.out_column.get(sensor.index()) {
            if let Some(cell) = self.stored_this_cycle.get_mut(column) {
                *cell = Some(value);
            }
        }
    }

    fn print_line(&mut self, line: &str) {
        if self.print_error.is_none() {
            if let Err(error) = writeln!(self.stdout, "{line}").and_then(|()| self.stdout.flush()) {
                self.print_error = Some(error);
            }
        }
    }
}

fn replay(
    script: &crate::compile::CliScript,
    sensors: &SensorList,
    in_path: &Path,
    out_path: Option<&PathBuf>,
    config: MachineConfig,
) -> anyhow::Result<ExitCode> {
    let input = std::fs::read(in_path)
        .with_context(|| format!("cannot read the replay file `{}`", in_path.display()))?;
    let input = String::from_utf8_lossy(&input).into_owned();
    let display = in_path.display().to_string();
    let source = SourceFile::new(&display, &input);
    let mut lines = input
        .split_inclusive('\n')
        .scan(0usize, |offset, line| {
            let start = *offset;
            *offset += line.len();
            Some((start, line.trim_end_matches(['\n', '\r'])))
        })
        .filter(|(_, line)| !line.trim().is_empty());
    let Some((header_offset, header)) = lines.next() else {
        bail!("{display}: the replay file is empty; it needs a header of sensor names");
    };
    // Spreadsheets often start a CSV with a byte-order mark.
    let (header_offset, header) = match header.strip_prefix('\u{feff}') {
        Some(rest) => (header_offset + '\u{feff}'.len_utf8(), rest),
        None => (header_offset, header),
    };
    // Column → sensor (None for an ignored `cycle` column).
    let mut columns: Vec<Option<SensorId>> = Vec::new();
    for (at, name) in cells(header) {
        let name = name.trim_matches('"');
        if name.eq_ignore_ascii_case("cycle") {
            columns.push(None);
            continue;
        }
        match sensors.lookup(name) {
            Some(id) => columns.push(Some(id)),
            None => {
                let hint =
                    suggest::closest(name, sensors.iter().map(|(_, sensor)| sensor.name.as_str()))
                        .map(|close| format!(" (did you mean `{close}`?)"))
                        .unwrap_or_default();
                bail!(
                    "{}: `{name}` is not a sensor in the active sensor list{hint}",
                    source.location(header_offset + at)
                );
            }
        }
    }

    let mut out = match out_path {
        Some(path) => {
            Some(BufWriter::new(File::create(path).with_context(|| {
                format!("cannot create `{}`", path.display())
            })?))
        }
        None => None,
    };
    let Some(program) = script.loaded.program.as_ref() else {
        bail!("the script has errors");
    };
    let stored = &program.stored_sensors;
    let mut out_column = vec![usize::MAX; sensors.len()];
    for (column, sensor) in stored.iter().enumerate() {
        if let Some(slot) = out_column.get_mut(sensor.index()) {
            *slot = column;
        }
    }
    if let Some(out) = out.as_mut() {
        let mut header = String::from("cycle");
        for sensor in stored {
            header.push(',');
            header.push_str(sensors.name(*sensor).unwrap_or("?"));
        }
        writeln!(out, "{header}")?;
    }

    let stdout = std::io::stdout();
    let mut host = ReplayHost {
        values: sensors.initial_values(),
        out_column,
        stored_this_cycle: vec![None; stored.len()],
        stdout: stdout.lock(),
        print_error: None,
    };
    let mut machine = Machine::new(Arc::clone(program), config);
    let mut trapped = false;
    let mut cycle = 0u64;
    let mut row = String::new();
    for (line_offset, line) in lines {
        let mut count = 0;
        for (column, (at, cell)) in cells(line).enumerate() {
            count += 1;
            let Some(sensor) = columns.get(column) else {
                bail!(
                    "{}: this row has more cells than the header has names ({})",
                    source.location(line_offset + at),
                    columns.len()
                );
            };
            let cell = cell.trim();
            if cell.is_empty() {
                continue;
            }
            let Some(sensor) = sensor else { continue };
            let value: f64 = cell.parse().map_err(|_| {
                anyhow::anyhow!(
                    "{}: `{cell}` is not a number (sensor values are decimal numbers such as `12.5`)",
                    source.location(line_offset + at)
                )
            })?;
            if let Some(slot) = host.values.get_mut(sensor.index()) {
                *slot = value;
            }
        }
        if count < columns.len() {
            bail!(
                "{}: this row has {count} cells but the header has {} names",
                source.location(line_offset),
                columns.len()
            );
        }
        host.stored_this_cycle.fill(None);
        match machine.run_cycle(&mut host) {
            CycleEnd::Yielded | CycleEnd::Halted => {}
            CycleEnd::Trapped(trap) => {
                if !trapped {
                    trapped = true;
                    eprintln!(
                        "{}: trap in cycle {cycle}: {} (pc {}); the script stops, the replay goes on",
                        script.location_of_pc(trap.pc),
                        script.loaded.trap_message(&trap.kind),
                        trap.pc.0
                    );
                }
            }
        }
        if let Some(error) = host.print_error.take() {
            if error.kind() == std::io::ErrorKind::BrokenPipe {
                return Ok(ExitCode::SUCCESS);
            }
            return Err(error).context("cannot write to stdout");
        }
        if let Some(out) = out.as_mut() {
            row.clear();
            row.push_str(&cycle.to_string());
            for cell in &host.stored_this_cycle {
                row.push(',');
                if let Some(value) = cell {
                    row.push_str(&value.to_string());
                }
            }
            writeln!(out, "{row}")?;
        }
        cycle += 1;
    }
    if let Some(mut out) = out {
        out.flush().context("cannot write the output file")?;
    }
    drop(host);
    eprintln!(
        "replayed {cycle} cycle{}",
        if cycle == 1 { "" } else { "s" }
    );
    Ok(if trapped {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// The comma-separated cells of a CSV line with their byte offsets.
fn cells(line: &str) -> impl Iterator<Item = (usize, &str)> {
    line.split(',').scan(0usize, |offset, cell| {
        let start = *offset;
        *offset += cell.len() + 1;
        let leading = cell.len() - cell.trim_start().len();
        Some((start + leading, cell.trim()))
    })
}
