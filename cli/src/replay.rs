//! `gloc run SCRIPT --replay FILES… [--out OUT.csv] [--cycle-budget N]`: runs a
//! script against recorded sensor values, one control cycle per recorded cycle,
//! and records what it stores.
//!
//! FILES are one CSV file or glider logs (`gloc_replay::Input`), streamed; their
//! sensors are matched to the active list by name, and the ones it lacks are named
//! in one warning. A sensor not updated in a cycle keeps its value. What the script
//! prints goes to stdout as it happens. OUT gets `cycle,<each sensor the script
//! stores>` and one row per cycle (cycles count from 0), with an empty cell where
//! nothing was stored that cycle.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use anyhow::{bail, Context};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};
use gloc_project::script::Script;
use gloc_project::settings::Settings;
use gloc_project::Overrides;
use gloc_replay::{ColumnMap, Input};

use crate::output::AtomicFile;
use crate::render::Tally;

pub fn main(args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    if args.replay.is_empty() {
        bail!("--replay FILES is required here");
    }
    for (given, flag) in [
        (args.flight.mission.is_some(), "--mission"),
        (args.profile.is_some(), "--profile"),
        (args.length.duration.is_some(), "--duration"),
        (args.length.cycles.is_some(), "--cycles"),
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
    let settings = Settings::resolve(
        args.script.as_deref(),
        // A replay flies no mission: the mission flags are not its settings.
        Overrides {
            sensor_cache: args.sensor_cache.clone(),
            mission: None,
            mafiles: None,
            ..args.flight.overrides()
        },
    )?;
    let Some(sensors) = crate::loading::active_sensors(&settings, &mut tally)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    let script = crate::loading::load_script(
        args.script.as_deref(),
        &sensors,
        &settings,
        args.optimization(),
    )?;
    if script.loaded.program.is_none() {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    }
    let config = MachineConfig {
        cycle_budget: settings.cycle_budget.value.get(),
    };
    if let Some(out) = &args.out {
        let inputs: Vec<&Path> = args
            .script
            .as_deref()
            .into_iter()
            .chain(args.replay.iter().map(PathBuf::as_path))
            .chain(settings.input_paths())
            .collect();
        crate::output::check_output(&inputs, "--out", out)?;
    }
    // A recording that is not there is an input that cannot be read (exit code 3).
    for path in &args.replay {
        if let Err(error) = std::fs::metadata(path) {
            return Err(anyhow::Error::new(crate::exit::Unreadable(format!(
                "cannot read the recording `{}`: {error}",
                path.display()
            ))));
        }
    }
    let input = Input::open(&args.replay, settings.sensor_cache.as_deref())?;
    replay(&script, &sensors, input, args.out.as_ref(), config)
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
        gloc_engine::vm::sensor_value(&self.values, sensor)
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        gloc_engine::vm::set_sensor(&mut self.values, sensor, value);
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
    script: &Script,
    sensors: &SensorList,
    mut input: Input,
    out_path: Option<&PathBuf>,
    config: MachineConfig,
) -> anyhow::Result<ExitCode> {
    let columns = ColumnMap::new(input.names(), sensors);
    if let Some(warning) = columns.warning(sensors) {
        eprintln!("{}: {warning}", input.description());
    }

    // Written beside OUT and renamed over it only when the whole replay succeeded.
    let mut out = match out_path {
        Some(path) => Some(
            AtomicFile::create(path)
                .map_err(|error| crate::output::write_error(error, "the output file", path))?,
        ),
        None => None,
    };
    let Some(program) = script.loaded.program.as_ref() else {
        bail!("the script has errors");
    };
    let stored = &script.loaded.stored_sensors;
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
    let mut updates = Vec::new();
    let signal = crate::signals::interrupt_signals()?;
    while input.next_cycle(&mut updates)? {
        let received = signal.load(Ordering::Relaxed);
        if received != 0 {
            eprintln!(
                "interrupted at cycle {cycle} by {} (cycles before it are in the output)",
                crate::signals::signal_name(received)
            );
            break;
        }
        for &(column, value) in &updates {
            let Some(Some(sensor)) = columns.ids.get(column) else {
                continue;
            };
            if let Some(slot) = host.values.get_mut(sensor.index()) {
                *slot = value;
            }
        }
        host.stored_this_cycle.fill(None);
        match machine.run_cycle(&mut host) {
            CycleEnd::Yielded | CycleEnd::Halted => {}
            CycleEnd::Trapped(trap) => {
                if !trapped {
                    trapped = true;
                    eprintln!(
                        "{}: trap in cycle {cycle}: {} (pc {}); the script stops, the replay goes on",
                        crate::render::location_of_pc(script, trap.pc),
                        script.loaded.trap_message(&trap.kind),
                        trap.pc.0
                    );
                }
            }
        }
        if let Some(error) = host.print_error.take() {
            if crate::output::is_closed_pipe(&error) {
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
    if let (Some(out), Some(path)) = (out, out_path) {
        out.commit()
            .map_err(|error| crate::output::write_error(error, "the output file", path))?;
    }
    for warning in input.take_warnings() {
        eprintln!("warning: {warning}");
    }
    drop(host);
    eprintln!(
        "replayed {cycle} cycle{}",
        if cycle == 1 { "" } else { "s" }
    );
    let received = signal.load(Ordering::Relaxed);
    if received != 0 {
        return Ok(ExitCode::from(128 + received as u8));
    }
    Ok(if trapped {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
