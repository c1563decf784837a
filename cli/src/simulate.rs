//! `gloc run` without `--replay`: fly a script in the glider simulator.
//!
//! With no options it flies the embedded default mission (the paper's Fig. 2
//! scenario) with the paper's Fig. 2 script. What the script prints goes to
//! stdout as it happens; warnings, the progress bar and the summary go to
//! stderr.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context};
use gloc_compiler::LoadedScript;
use gloc_engine::sensors::SensorList;
use gloc_project::settings::{Origin, Settings};
use gloc_project::Overrides;
use gloc_sim::behaviors::EventKind;
use gloc_sim::faults::{step_cycle_with_faults, Fault, FaultPlan};
use gloc_sim::log::{default_columns, parse_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::plot::{write_plot, PlotFormat, PlotOptions, Trace};
use gloc_sim::{EndReason, Mission, Simulation};

use crate::flags::{Limit, DEFAULT_LIMIT_SECONDS};
use crate::output::{AtomicFile, Output};
use crate::render::{SourceFile, Tally};

/// Runs shorter than this many cycles get no progress bar.
const PROGRESS_MIN_CYCLES: u64 = 50_000;

pub fn main(args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    check_flags(&args)?;
    let Some(mut run) = prepare_run(&args)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    let flown = fly(&mut run, &args)?;
    finish(run, flown, &args)
}

/// The flags alone, before anything is read or flown: `--out` belongs to a replay, the
/// plot is no input and has a known format, the panels exist.
fn check_flags(args: &crate::RunArgs) -> anyhow::Result<()> {
    if args.out.is_some() {
        bail!("--out belongs to --replay; to log a simulated run use --log FILE.csv or FILE.dba");
    }
    if let Some(plot) = &args.plot {
        // Before anything is flown: the plot is no input (checked again with every input
        // once the settings and the mission are read), and its format is known.
        let inputs: Vec<&Path> = [&args.script, &args.flight.mission, &args.profile]
            .into_iter()
            .filter_map(|path| path.as_deref())
            .collect();
        crate::output::check_outputs(&inputs, &run_outputs(args))?;
        PlotFormat::from_path(plot).map_err(anyhow::Error::msg)?;
    }
    for panel in &args.plot_panels {
        if !matches!(panel.as_str(), "temperature" | "battery") && !panel.contains('_') {
            bail!("--plot-panels: `{panel}` is not a panel; the panels are temperature, battery and sensor names (m_battery, sci_ruhp_behs, …)");
        }
    }
    Ok(())
}

/// A run ready to fly: its inputs read and checked, its simulation prepared.
struct Run {
    sim: Simulation,
    sensor_list: Arc<SensorList>,
    mission: Mission,
    script: Script,
    fault_plan: FaultPlan,
    max_cycles: u64,
    limit_given: bool,
}

/// What flying the run gave, for the summary.
struct Flown {
    cycles_run: u64,
    wall: std::time::Duration,
    printed_lines: u64,
    last_printed: Vec<String>,
    stopped: Option<String>,
    hook_ignored: Option<(u64, f64)>,
    trace: Option<Trace>,
    log_error: Option<anyhow::Error>,
    signal: Arc<std::sync::atomic::AtomicUsize>,
}

/// Reads the settings, the sensor list, the faults, the script, the mission and the
/// profile, prepares the simulation (printing its warnings) and bounds the run; `None`
/// when an input has errors (they were printed).
fn prepare_run(args: &crate::RunArgs) -> anyhow::Result<Option<Run>> {
    let mut tally = Tally::default();
    let settings = Settings::resolve(
        args.script.as_deref(),
        Overrides {
            simulator: args.simulator.clone(),
            ..args.flight.overrides()
        },
    )?;
    let Some(sensor_list) = crate::loading::active_sensors(&settings, &mut tally)? else {
        return Ok(None);
    };
    let sensor_list = Arc::new(sensor_list);
    // Bad faults are a bad command line: stop before anything is flown.
    let faults = args
        .faults
        .iter()
        .map(|text| {
            Fault::parse(text, &sensor_list).map_err(|error| anyhow::anyhow!("--fault {error}"))
        })
        .collect::<anyhow::Result<Vec<Fault>>>()?;
    let fault_plan = FaultPlan::new(faults);

    let Some(script) = load_program(
        args.script.as_deref(),
        &sensor_list,
        &settings,
        args.optimization(),
    )?
    else {
        return Ok(None);
    };
    let Some(mission) = load_mission(&settings, &sensor_list)? else {
        return Ok(None);
    };

    let flight = gloc_project::simulation::Flight::read(
        args.seed,
        args.profile.as_deref(),
        Origin::Flag("--profile"),
    )?;
    let plan = gloc_project::simulation::Plan {
        settings: &settings,
        sensors: &sensor_list,
        mission: &mission,
        script: &script.loaded,
        program: &script.program,
    };
    let prepared = gloc_project::simulation::prepare(&plan, flight)?;
    print_warnings(&prepared.warnings, &mission, &script.name, &script.text);
    let sim = prepared.simulation;

    let limit = args.length.limit(sim.cycle_time())?;
    let limit_given = limit.is_some();
    let max_cycles = limit
        .unwrap_or(Limit::Seconds(DEFAULT_LIMIT_SECONDS))
        .cycles(&sim);

    let inputs: Vec<&Path> = args
        .script
        .iter()
        .map(PathBuf::as_path)
        .chain(settings.input_paths())
        .chain(args.profile.iter().map(PathBuf::as_path))
        .chain(mission.sources.iter().map(|source| source.path.as_path()))
        .collect();
    crate::output::check_outputs(&inputs, &run_outputs(args))?;
    Ok(Some(Run {
        sim,
        sensor_list,
        mission,
        script,
        fault_plan,
        max_cycles,
        limit_given,
    }))
}

/// Flies the run to its limit or its end, writing what the script prints to stdout and
/// the log as it goes; a signal or a log that cannot be written stops it between cycles.
fn fly(run: &mut Run, args: &crate::RunArgs) -> anyhow::Result<Flown> {
    let max_cycles = run.max_cycles;
    let Run {
        sim,
        sensor_list,
        mission,
        script,
        fault_plan,
        ..
    } = run;
    let mut log = match &args.log {
        Some(path) => Some(open_log(
            path,
            args,
            sensor_list,
            &script.loaded.stored_sensors,
            mission,
            sim,
        )?),
        None => None,
    };
    let mut panel_sensors = Vec::new();
    for panel in &args.plot_panels {
        if matches!(panel.as_str(), "temperature" | "battery") {
            continue;
        }
        match sensor_list.lookup(panel) {
            Some(id) => panel_sensors.push((panel.clone(), id)),
            None => bail!("--plot-panels: the sensor list has no sensor `{panel}`"),
        }
    }
    let mut trace = args
        .plot
        .as_ref()
        .map(|_| Trace::with_sensors(&panel_sensors));

    let progress = (max_cycles >= PROGRESS_MIN_CYCLES && !sim.is_finished())
        .then(|| crate::render::progress_bar(max_cycles, "simulating", "cycles"))
        .flatten();

    let signal = crate::signals::interrupt_signals()?;
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut printed_lines: u64 = 0;
    let mut last_printed: Vec<String> = Vec::new();
    let started = Instant::now();
    let mut cycles_run: u64 = 0;
    let mut stopped: Option<String> = None;
    let mut hook_ignored: Option<(u64, f64)> = None;
    let mut log_error: Option<anyhow::Error> = None;
    while cycles_run < max_cycles {
        let received = signal.load(Ordering::Relaxed);
        if received != 0 {
            stopped = Some(format!(
                "interrupted at cycle {cycles_run} by {} (cycles before it are logged)",
                crate::signals::signal_name(received)
            ));
            break;
        }
        if !step_cycle_with_faults(sim, fault_plan) {
            break;
        }
        if hook_ignored.is_none() {
            hook_ignored = sim.events().iter().find_map(|event| match event.kind {
                EventKind::IgnoredRequest { value } => Some((cycles_run, value)),
                _ => None,
            });
        }
        cycles_run += 1;
        for line in sim.printed() {
            printed_lines += 1;
            if let Err(error) = writeln!(out, "{line}") {
                // A closed pipe (`| head`) is not a failure of the run.
                if !crate::output::is_closed_pipe(&error) {
                    return Err(error).context("cannot write the script's output");
                }
            }
            if last_printed.len() == 5 {
                last_printed.remove(0);
            }
            last_printed.push(line.to_string());
        }
        if let Some((writer, path)) = log.as_mut() {
            if let Err(error) = writer.write_row(sim.sensors()) {
                // A full disk stops the run; the summary still comes.
                stopped = Some(format!(
                    "stopped at cycle {cycles_run}: the log could not be written"
                ));
                log_error = Some(crate::output::write_error(error, "the log", path));
                break;
            }
        }
        if let Some(trace) = trace.as_mut() {
            trace.record(sim);
        }
        if let Some(bar) = &progress {
            if cycles_run.is_multiple_of(4096) {
                bar.set_position(cycles_run);
            }
        }
    }
    let wall = started.elapsed();
    let _ = out.flush();
    drop(out);
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    if let Some((writer, path)) = log {
        // Every row written is complete: the loop stops between cycles.
        if log_error.is_none() {
            if let Err(error) = writer.finish() {
                log_error = Some(crate::output::write_error(error, "the log", &path));
            }
        }
    }
    Ok(Flown {
        cycles_run,
        wall,
        printed_lines,
        last_printed,
        stopped,
        hook_ignored,
        trace,
        log_error,
        signal,
    })
}

/// Draws the plot, prints the summary and decides the exit code.
fn finish(run: Run, flown: Flown, args: &crate::RunArgs) -> anyhow::Result<ExitCode> {
    let Run {
        sim,
        mission,
        script,
        fault_plan,
        limit_given,
        ..
    } = run;
    let script_name = &script.name;
    let mut plot_error = None;
    if let (Some(trace), Some(path)) = (&flown.trace, &args.plot) {
        // File names, not paths, in the title.
        let file_name = |name: &str| {
            Path::new(name)
                .file_name()
                .map(|name| name.to_string_lossy().into_owned())
                .unwrap_or_else(|| name.to_string())
        };
        let title = format!(
            "{} with {}",
            file_name(&mission.name),
            file_name(script_name)
        );
        let options = PlotOptions {
            title,
            water_depth: sim.water_depth(),
            temperature: args.plot_panels.iter().any(|panel| panel == "temperature"),
            battery: args.plot_panels.iter().any(|panel| panel == "battery"),
        };
        // Drawn under a temporary name and renamed: a failure leaves the old file, and
        // the summary still comes.
        if let Err(error) = crate::output::write_through_temporary(path, |temporary| {
            write_plot(trace, &options, temporary)
        }) {
            plot_error = Some(error.context(format!("cannot draw the plot `{}`", path.display())));
        }
    }

    summary(&SummaryFacts {
        sim: &sim,
        loaded: &script.loaded,
        script_name,
        cycles_run: flown.cycles_run,
        wall: flown.wall,
        limit_given,
        printed_lines: flown.printed_lines,
        last_printed: &flown.last_printed,
        log: args.log.as_deref(),
        plot: args.plot.as_deref(),
        faults: &fault_plan,
        fault_texts: &args.faults,
        stopped: flown.stopped.as_deref(),
        hook_ignored: flown.hook_ignored,
        log_written: flown.log_error.is_none(),
        plot_written: plot_error.is_none(),
        format: args.summary,
    });
    if let Some(error) = flown.log_error.or(plot_error) {
        return Err(error);
    }
    let received = flown.signal.load(Ordering::Relaxed);
    if received != 0 {
        // The shell's convention for a process ended by a signal.
        return Ok(ExitCode::from(128 + received as u8));
    }
    if matches!(sim.end().map(|end| end.reason), Some(EndReason::Aborted(_))) {
        return Ok(crate::exit::code(crate::exit::ABORTED));
    }
    Ok(ExitCode::SUCCESS)
}

/// A compiled script and its name for messages.
pub(crate) struct Script {
    pub name: String,
    /// The script's text, for messages that quote it.
    pub text: String,
    pub loaded: LoadedScript,
    pub program: Arc<gloc_engine::program::Program>,
}

/// Reads and compiles the script to fly (the paper's Fig. 2 script when none is given),
/// printing its diagnostics; `None` when it has errors (they were printed).
pub(crate) fn load_program(
    script: Option<&Path>,
    sensor_list: &SensorList,
    settings: &Settings,
    optimization: gloc_compiler::Optimization,
) -> anyhow::Result<Option<Script>> {
    let script = crate::loading::load_script(script, sensor_list, settings, optimization)?;
    let Some(program) = script.loaded.program.clone() else {
        eprintln!(
            "error: `{}` has errors; nothing was simulated",
            script.display
        );
        return Ok(None);
    };
    Ok(Some(Script {
        name: script.display,
        text: script.text,
        loaded: script.loaded,
        program,
    }))
}

/// Loads the settings' mission (the embedded Fig. 2 mission when none is given),
/// printing its diagnostics; `None` when it has errors (they were printed). A mission
/// file that cannot be read is an error naming where its path came from.
pub(crate) fn load_mission(
    settings: &Settings,
    sensor_list: &SensorList,
) -> anyhow::Result<Option<Mission>> {
    let mission = gloc_project::simulation::load_mission(settings, sensor_list)?;
    print_mission_diagnostics(&mission, &mission.diagnostics);
    if mission.has_errors() {
        eprintln!("error: the mission has errors; nothing was simulated");
        return Ok(None);
    }
    Ok(Some(mission))
}

/// Renders diagnostics of a mission's files on stderr, each file prepared once (its
/// line index built once, not once per diagnostic).
pub(crate) fn print_mission_diagnostics(
    mission: &Mission,
    entries: &[gloc_sim::mission::MissionDiagnostic],
) {
    let displays: Vec<String> = mission
        .sources
        .iter()
        .map(|file| file.path.display().to_string())
        .collect();
    let mut sources: Vec<Option<SourceFile>> = mission.sources.iter().map(|_| None).collect();
    for entry in entries {
        let index = entry.file.min(mission.sources.len().saturating_sub(1));
        let (Some(slot), Some(file)) = (sources.get_mut(index), mission.sources.get(index)) else {
            continue;
        };
        let source = slot.get_or_insert_with(|| SourceFile::new(&displays[index], &file.text));
        eprint!("{}", source.render(&entry.diagnostic));
    }
}

/// How the script ended the run: trapped (where and why), halted, or running.
pub(crate) fn script_state(sim: &Simulation, loaded: &LoadedScript, script_name: &str) -> String {
    match sim.script_trap() {
        Some(trap) => {
            let line = loaded.line_of_pc(trap.pc).unwrap_or(trap.line);
            format!(
                "TRAPPED at {script_name}:{line}: {} (the vehicle flew on)",
                loaded.trap_message(&trap.kind)
            )
        }
        None => match sim.script_last_end() {
            Some(gloc_engine::vm::CycleEnd::Halted) => "halted".to_string(),
            _ => "ran to the end of the run".to_string(),
        },
    }
}

type OpenLog = (RunLog, PathBuf);

/// The run log: text (CSV, `.dba`) or a binary `.dbd` (+ `.ebd` for the
/// science sensors), each with its `<crc>.cac` beside it.
enum RunLog {
    Text(Box<LogWriter<AtomicFile>>),
    Binary(Vec<BinaryPart>),
}

/// One binary file of a run log and the sensor ids of its columns.
struct BinaryPart {
    writer: gloc_dbd::DbdWriter<AtomicFile>,
    columns: Vec<gloc_engine::sensors::SensorId>,
    values: Vec<f64>,
}

impl RunLog {
    fn write_row(&mut self, sensors: &[f64]) -> std::io::Result<()> {
        match self {
            RunLog::Text(writer) => writer.write_row(sensors),
            RunLog::Binary(parts) => {
                for part in parts {
                    part.values.clear();
                    part.values.extend(
                        part.columns
                            .iter()
                            .map(|id| sensors.get(id.index()).copied().unwrap_or(f64::NAN)),
                    );
                    part.writer.write_cycle(&part.values)?;
                }
                Ok(())
            }
        }
    }

    /// Ends every file and renames it over its target (see [`AtomicFile::commit`]).
    fn finish(self) -> std::io::Result<()> {
        match self {
            RunLog::Text(writer) => writer.finish().and_then(AtomicFile::commit),
            RunLog::Binary(parts) => parts
                .into_iter()
                .try_for_each(|part| part.writer.finish().and_then(AtomicFile::commit)),
        }
    }
}

fn open_log(
    path: &Path,
    args: &crate::RunArgs,
    sensor_list: &SensorList,
    stored_sensors: &[gloc_engine::sensors::SensorId],
    mission: &Mission,
    sim: &Simulation,
) -> anyhow::Result<OpenLog> {
    let binary = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("dbd"));
    let format = LogFormat::from_path(path);
    if format.is_none() && !binary {
        bail!(
            "cannot tell the log format of `{}`: name it `.csv`, `.dba` (Slocum ASCII) or `.dbd` (Slocum binary)",
            path.display()
        );
    }
    let columns = match &args.log_sensors {
        Some(names) => parse_columns(sensor_list, names).map_err(anyhow::Error::msg)?,
        // The pilot's set plus whatever the script writes.
        None => default_columns(sensor_list, stored_sensors),
    };
    let stem = path
        .file_stem()
        .map(|stem| stem.to_string_lossy().into_owned())
        .unwrap_or_else(|| "gloc".to_string());
    if binary {
        let parts = open_binary_log(path, &stem, columns, sensor_list, mission, sim)?;
        return Ok((RunLog::Binary(parts), path.to_path_buf()));
    }
    let file = AtomicFile::create(path)
        .map_err(|error| crate::output::write_error(error, "the log", path))?;
    let header = DbaHeader {
        filename: stem,
        mission_name: mission.name.clone(),
        fileopen_time: gloc_dbd::header::fileopen_time_text(sim.present_time()),
    };
    let writer = LogWriter::new(
        file,
        format.unwrap_or(LogFormat::Csv),
        columns,
        sensor_list,
        &header,
    )
    .map_err(|error| crate::output::write_error(error, "the log", path))?;
    Ok((RunLog::Text(Box::new(writer)), path.to_path_buf()))
}

/// `run.dbd` with the flight sensors (and `m_present_time`), and `run.ebd`
/// with the `sci_` sensors (and `sci_m_present_time`) when any is logged. The
/// flight file's sensor list is the active list without its `sci_` sensors,
/// the science file's those alone, as a glider's two computers have them.
fn open_binary_log(
    path: &Path,
    stem: &str,
    columns: Vec<gloc_engine::sensors::SensorId>,
    sensor_list: &SensorList,
    mission: &Mission,
    sim: &Simulation,
) -> anyhow::Result<Vec<BinaryPart>> {
    let is_science = |id: &gloc_engine::sensors::SensorId| {
        sensor_list
            .name(*id)
            .is_some_and(|name| name.to_ascii_lowercase().starts_with("sci_"))
    };
    let mut parts = Vec::new();
    for (science, extension, time) in [
        (false, "dbd", "m_present_time"),
        (true, "ebd", "sci_m_present_time"),
    ] {
        let mut chosen: Vec<_> = columns
            .iter()
            .copied()
            .filter(|id| is_science(id) == science)
            .collect();
        if chosen.is_empty() {
            continue;
        }
        // The time sensor is always logged; columns follow the list's order.
        chosen.extend(sensor_list.lookup(time));
        let logged: std::collections::HashSet<_> = chosen.iter().copied().collect();
        let mut ordered = Vec::new();
        let mut sensors = Vec::new();
        for (id, sensor) in sensor_list.iter() {
            if is_science(&id) != science {
                continue;
            }
            if logged.contains(&id) {
                ordered.push(id);
            }
            sensors.push(gloc_dbd::ListSensor {
                name: sensor.name.clone(),
                units: sensor.units.clone(),
                bytes: if gloc_sim::log::logged_as_double(sensor) {
                    8
                } else {
                    4
                },
                logged: logged.contains(&id),
            });
        }
        let list = gloc_dbd::WrittenList::new(&sensors);
        let file_path = path.with_extension(extension);
        let folder = file_path.parent().unwrap_or(Path::new(""));
        let cac = folder.join(format!("{}.cac", list.crc));
        // The name is the CRC of the contents: an existing file is this list.
        if !cac.exists() {
            crate::output::write_atomically(&cac, list.text.as_bytes())
                .map_err(|error| crate::output::write_error(error, "the sensor list", &cac))?;
        }
        let identity = gloc_dbd::LogIdentity {
            full_filename: stem.to_string(),
            the8x3_filename: "00000000".to_string(),
            filename_extension: extension.to_string(),
            mission_name: mission.name.clone(),
            fileopen_time: gloc_dbd::header::fileopen_time_text(sim.present_time()),
        };
        let file = AtomicFile::create(&file_path)
            .map_err(|error| crate::output::write_error(error, "the log", &file_path))?;
        let writer = gloc_dbd::DbdWriter::new(file, &identity, &list)
            .map_err(|error| crate::output::write_error(error, "the log", &file_path))?;
        parts.push(BinaryPart {
            writer,
            values: Vec::with_capacity(ordered.len()),
            columns: ordered,
        });
    }
    Ok(parts)
}

/// The files a simulated run writes, with their flags.
fn run_outputs(args: &crate::RunArgs) -> Vec<Output<'_>> {
    [("--log", &args.log), ("--plot", &args.plot)]
        .into_iter()
        .filter_map(|(flag, path)| {
            Some(Output {
                flag,
                path: path.as_deref()?,
            })
        })
        .collect()
}

/// `3h 05m 12s`.
fn human_time(seconds: f64) -> String {
    let total = seconds.round() as u64;
    let (days, hours, minutes, secs) = (
        total / 86400,
        total % 86400 / 3600,
        total % 3600 / 60,
        total % 60,
    );
    if days > 0 {
        format!("{days}d {hours:02}h {minutes:02}m {secs:02}s")
    } else if hours > 0 {
        format!("{hours}h {minutes:02}m {secs:02}s")
    } else {
        format!("{minutes}m {secs:02}s")
    }
}

struct SummaryFacts<'a> {
    sim: &'a Simulation,
    loaded: &'a LoadedScript,
    script_name: &'a str,
    cycles_run: u64,
    wall: std::time::Duration,
    limit_given: bool,
    printed_lines: u64,
    last_printed: &'a [String],
    log: Option<&'a Path>,
    plot: Option<&'a Path>,
    faults: &'a FaultPlan,
    /// The `--fault` arguments as written, in the plan's order.
    fault_texts: &'a [String],
    /// Why the run stopped early (a signal, a log that could not be written).
    stopped: Option<&'a str>,
    /// The first `sci_ruhp_behs` the hook ignored, and its cycle.
    hook_ignored: Option<(u64, f64)>,
    log_written: bool,
    plot_written: bool,
    format: crate::SummaryFormat,
}

/// The summary's wall time and speed-up, to what the clock can tell: a run of a few
/// milliseconds has no meaningful speed-up (a million-fold figure from a 0.000 s
/// run misleads), and a ratio is given to two significant figures.
fn wall_time(wall_seconds: f64, simulated_seconds: f64) -> String {
    if wall_seconds < 0.01 {
        return format!(
            "{:.1} ms (too short to measure the speed-up)",
            wall_seconds * 1000.0
        );
    }
    let ratio = simulated_seconds / wall_seconds;
    if ratio < 10.0 {
        return format!("{wall_seconds:.2} s ({ratio:.1}× real time)");
    }
    let step = 10f64.powi(ratio.log10().floor() as i32 - 1);
    let rounded = (ratio / step).round() * step;
    format!("{wall_seconds:.2} s (about {rounded:.0}× faster than real time)")
}

fn summary(facts: &SummaryFacts<'_>) {
    let sim = facts.sim;
    let simulated = sim.time();
    let wall = facts.wall.as_secs_f64();
    let (shallowest, deepest) = sim.depth_range();
    let mut lines = vec![
        format!(
            "mission       {} with {}",
            sim.mission_name(),
            facts.script_name
        ),
        if sim.mean_cycle_period() == sim.cycle_time() {
            format!(
                "cycles        {} ({} s each)",
                facts.cycles_run,
                sim.cycle_time()
            )
        } else {
            format!(
                "cycles        {} ({:.3} s each on average; u_cycle_time {} s)",
                facts.cycles_run,
                simulated / facts.cycles_run.max(1) as f64,
                sim.cycle_time()
            )
        },
        format!("simulated     {}", human_time(simulated)),
        format!("wall time     {}", wall_time(wall, simulated)),
        format!(
            "energy used   {:.1} kJ, {:.3} Ah",
            sim.energy_joules() / 1000.0,
            sim.amp_hours()
        ),
        {
            let by = sim.energy_use();
            format!(
                "by consumer   hotel {:.1} kJ, pump {:.1} kJ, pitch {:.1} kJ, science {:.1} kJ ({} wakes)",
                by.hotel / 1000.0,
                by.pump / 1000.0,
                by.pitch / 1000.0,
                by.science / 1000.0,
                sim.science_wakes()
            )
        },
        format!(
            "depth range   {shallowest:.1} – {deepest:.1} m (water {:.0} m)",
            sim.water_depth()
        ),
    ];
    let ended = mission_end_text(facts);
    let ended = match facts.stopped {
        Some(stopped) if sim.end().is_none() => stopped.to_string(),
        _ => ended,
    };
    lines.push(format!("mission end   {ended}"));
    let script_state = script_state(sim, facts.loaded, facts.script_name);
    lines.push(format!("script        {script_state}"));
    let printed = if facts.printed_lines == 0 {
        "nothing".to_string()
    } else {
        format!(
            "{} line(s); last: {}",
            facts.printed_lines,
            facts.last_printed.join(" | ")
        )
    };
    lines.push(format!("script printed {printed}"));
    if let Some((cycle, value)) = facts.hook_ignored {
        lines.push(format!(
            "hook          ignored sci_ruhp_behs = {value:?} from cycle {cycle}: not a whole number from 0 to 2147483647"
        ));
    }
    for ((fault, applied), text) in facts.faults.report().zip(facts.fault_texts) {
        lines.push(format!(
            "fault         {}",
            fault_line(fault, applied, text, sim)
        ));
    }
    let not_written = |written: bool| {
        if written {
            ""
        } else {
            " (NOT written: see the error)"
        }
    };
    if let Some(path) = facts.log {
        lines.push(format!(
            "log           {}{}",
            path.display(),
            not_written(facts.log_written)
        ));
    }
    if let Some(path) = facts.plot {
        lines.push(format!(
            "plot          {}{}",
            path.display(),
            not_written(facts.plot_written)
        ));
    }
    let mut err = std::io::stderr().lock();
    if facts.format == crate::SummaryFormat::Json {
        // The same facts as the text, for editors: how the mission and the script ended (the
        // texts of the `mission end` and `script` lines) and the files written.
        let trap_line = sim
            .script_trap()
            .map(|trap| facts.loaded.line_of_pc(trap.pc).unwrap_or(trap.line));
        let json = serde_json::json!({
            "mission": sim.mission_name(),
            "script": facts.script_name,
            "cycles": facts.cycles_run,
            "simulated_seconds": simulated,
            "mission_end": ended,
            "completed": matches!(sim.end(), Some(end) if end.reason == EndReason::Completed),
            "script_state": script_state,
            "trap_line": trap_line,
            "printed_lines": facts.printed_lines,
            "energy_joules": sim.energy_joules(),
            "energy_by_consumer_joules": {
                "hotel": sim.energy_use().hotel,
                "pump": sim.energy_use().pump,
                "pitch": sim.energy_use().pitch,
                "science": sim.energy_use().science,
            },
            "log": facts.log.map(|path| path.display().to_string()),
            "log_written": facts.log.is_some() && facts.log_written,
            "plot": facts.plot.map(|path| path.display().to_string()),
            "plot_written": facts.plot.is_some() && facts.plot_written,
        });
        let _ = writeln!(err, "{json}");
        return;
    }
    for line in lines {
        let _ = writeln!(err, "{line}");
    }
}

/// How the mission ended, as the summary's `mission end` line says it.
fn mission_end_text(facts: &SummaryFacts<'_>) -> String {
    let sim = facts.sim;
    match facts.sim.end() {
        Some(end) => {
            let how = match end.reason {
                EndReason::Completed => "completed".to_string(),
                EndReason::Aborted(reason) => format!("ABORTED ({})", reason.glider_name()),
                EndReason::BatteryExhausted => format!(
                    "BATTERY EXHAUSTED ({:.0} Wh used of {:.0} Wh)",
                    sim.energy_joules() / 3600.0,
                    sim.battery_joules() / 3600.0
                ),
            };
            format!(
                "{how} at cycle {} ({}) at {:.1} m",
                end.cycle,
                human_time(end.time),
                end.depth
            )
        }
        None if facts.limit_given => "still running at the end of the requested time".to_string(),
        None => format!(
            "still running after {} (the default limit; use --duration or --cycles)",
            human_time(DEFAULT_LIMIT_SECONDS)
        ),
    }
}

/// `m_depth:nan@20: m_depth reads NaN in cycles 20–336 (1m 20s – 22m 24s)`.
fn fault_line(fault: &Fault, applied: Option<(u64, u64)>, text: &str, sim: &Simulation) -> String {
    let name = sim.sensor_list().name(fault.sensor).unwrap_or("the sensor");
    let at = |cycle: u64| human_time(cycle as f64 * sim.mean_cycle_period());
    match applied {
        Some((first, last)) if first == last => format!(
            "{text}: {name} {} in cycle {first} ({})",
            fault.kind,
            at(first)
        ),
        Some((first, last)) => format!(
            "{text}: {name} {} in cycles {first}–{last} ({} – {})",
            fault.kind,
            at(first),
            at(last)
        ),
        None => format!(
            "{text}: not injected (the run ended before cycle {})",
            fault.start
        ),
    }
}

/// Prints what preparing a flight found, each with a caret under its place: the
/// simulator's lines, the mission's files (S0106, S012x), the script (S0107).
pub(crate) fn print_warnings(
    warnings: &[gloc_project::simulation::Warning],
    mission: &Mission,
    script_name: &str,
    script_text: &str,
) {
    use gloc_project::simulation::Warning;
    let mut on_mission = Vec::new();
    let mut on_script = Vec::new();
    for warning in warnings {
        match warning {
            Warning::Simulator(line) => eprintln!("{line}"),
            Warning::Mission(entry) => on_mission.push(entry.clone()),
            Warning::Script(diagnostic) => on_script.push(diagnostic),
        }
    }
    print_mission_diagnostics(mission, &on_mission);
    if !on_script.is_empty() {
        let source = SourceFile::new(script_name, script_text);
        for diagnostic in on_script {
            eprint!("{}", source.render(diagnostic));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_time_claims_no_speed_up_the_clock_cannot_tell() {
        // The run: 2,244 s simulated in 0.2 ms printed "0.000 s (11222302×)".
        assert_eq!(
            wall_time(0.0002, 2244.0),
            "0.2 ms (too short to measure the speed-up)"
        );
        // 6 h in 0.5 s: 43,200×, to two significant figures.
        assert_eq!(
            wall_time(0.5, 21_600.0),
            "0.50 s (about 43000× faster than real time)"
        );
        assert_eq!(wall_time(2.0, 6.0), "2.00 s (3.0× real time)");
    }

    #[test]
    fn human_times() {
        assert_eq!(human_time(65.0), "1m 05s");
        assert_eq!(human_time(3725.0), "1h 02m 05s");
        assert_eq!(human_time(2_592_000.0), "30d 00h 00m 00s");
    }
}
