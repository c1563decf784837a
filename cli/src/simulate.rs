//! `gloc run` without `--replay`: fly a script in the glider simulator.
//!
//! With no options it flies the embedded default mission (the paper's Fig. 2
//! scenario) with the paper's Fig. 2 script. What the script prints goes to
//! stdout as it happens; warnings, the progress bar and the summary go to
//! stderr.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context};
use gloc_compiler::{load_script, Language, LoadOptions, LoadedScript};
use gloc_engine::sensors::SensorList;
use gloc_engine::vm::DEFAULT_CYCLE_BUDGET;
use gloc_sim::faults::{step_cycle_with_faults, Fault, FaultPlan};
use gloc_sim::log::{default_columns, parse_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::plot::{render_svg, Trace};
use gloc_sim::{default_mission, EndReason, Mission, SimConfig, Simulation, TemperatureProfile};

use crate::render::{SourceFile, Tally};

/// Simulated time a run may take when neither `--duration` nor `--cycles`
/// is given and the mission does not end by itself.
const DEFAULT_LIMIT_SECONDS: f64 = 24.0 * 3600.0;

/// Runs shorter than this many cycles get no progress bar.
const PROGRESS_MIN_CYCLES: u64 = 50_000;

pub fn main(args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    if args.out.is_some() {
        bail!("--out belongs to --replay; to log a simulated run use --log FILE.csv or FILE.dba");
    }
    let mut tally = Tally::default();
    let settings = crate::settings::resolve(
        args.script.as_deref(),
        crate::settings::Flags {
            masterdata: args.masterdata.as_deref(),
            cycle_budget: args.cycle_budget,
            mission: args.mission.as_deref(),
            sensor_order: args.sensor_order,
            simulator: &args.simulator,
        },
    )?;
    let sensor_list = match &settings.masterdata {
        Some(path) => match crate::check::load_sensors(path, settings.sensor_order, &mut tally)? {
            Some(list) => list,
            None => return Ok(ExitCode::FAILURE),
        },
        None => SensorList::embedded(),
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
    let mut fault_plan = FaultPlan::new(faults);
    let cycle_budget = settings.cycle_budget.unwrap_or(DEFAULT_CYCLE_BUDGET);
    if cycle_budget == 0 {
        bail!("--cycle-budget must be at least 1");
    }

    let (script_name, script_text) = match &args.script {
        Some(path) => (path.display().to_string(), read_text(path, "script")?),
        None => ("fig2.gloc".to_string(), crate::replay::FIG2.to_string()),
    };
    let language = match &args.script {
        Some(path) => Language::of_path(path),
        None => Language::Gloc,
    };
    let loaded = load_script(
        &script_text,
        language,
        &sensor_list,
        &LoadOptions {
            optimize: args.optimize,
            cycle_budget: Some(cycle_budget),
        },
    );
    let source = SourceFile::new(&script_name, &script_text);
    for diagnostic in &loaded.diagnostics {
        eprint!("{}", source.render(diagnostic));
    }
    let Some(program) = loaded.program.clone() else {
        eprintln!("error: `{script_name}` has errors; nothing was simulated");
        return Ok(ExitCode::FAILURE);
    };

    let mission = match &settings.mission {
        Some(path) => Mission::load(path),
        None => default_mission(),
    };
    for entry in &mission.diagnostics {
        let file = &mission.sources[entry.file.min(mission.sources.len().saturating_sub(1))];
        let display = file.path.display().to_string();
        eprint!(
            "{}",
            SourceFile::new(&display, &file.text).render(&entry.diagnostic)
        );
    }
    if mission.has_errors() {
        eprintln!("error: the mission has errors; nothing was simulated");
        return Ok(ExitCode::FAILURE);
    }

    let profile = match &args.profile {
        Some(path) => {
            let text = read_text(path, "temperature profile")?;
            match TemperatureProfile::from_csv(path, &text) {
                Ok(profile) => Some(profile),
                Err(error) => {
                    eprintln!("{error}");
                    return Ok(ExitCode::FAILURE);
                }
            }
        }
        None => None,
    };
    let mut config = SimConfig {
        seed: args.seed.unwrap_or(1),
        profile,
        cycle_budget,
        ..SimConfig::default()
    };
    for (name, value) in &settings.simulator {
        // Names were checked against the same table when gloc.toml and the flags were read.
        if !config.set(name, *value) {
            bail!("`{name}` is not a simulator setting");
        }
    }
    let mut sim = Simulation::new(
        &mission,
        sensor_list.clone(),
        Some(program.clone()),
        &config,
    )?;
    for warning in sim.warnings() {
        eprintln!("{warning}");
    }

    let (max_cycles, limit_given) = match (&args.duration, args.cycles) {
        (Some(text), _) => {
            let seconds = parse_duration(text)?;
            ((seconds / sim.cycle_time()).ceil() as u64, true)
        }
        (None, Some(cycles)) => (cycles, true),
        (None, None) => (
            (DEFAULT_LIMIT_SECONDS / sim.cycle_time()).ceil() as u64,
            false,
        ),
    };

    let mut log = match &args.log {
        Some(path) => Some(open_log(
            path,
            &args,
            &sensor_list,
            &program,
            &mission,
            &sim,
        )?),
        None => None,
    };
    let mut trace = args.plot.as_ref().map(|_| Trace::default());

    let progress = (std::io::stderr().is_terminal()
        && max_cycles >= PROGRESS_MIN_CYCLES
        && !sim.is_finished())
    .then(|| {
        let bar = indicatif::ProgressBar::new(max_cycles);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} simulating [{bar:40}] {pos}/{len} cycles ({eta} left)",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        bar
    });

    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut printed_lines: u64 = 0;
    let mut last_printed: Vec<String> = Vec::new();
    let started = Instant::now();
    let mut cycles_run: u64 = 0;
    while cycles_run < max_cycles && step_cycle_with_faults(&mut sim, &mut fault_plan) {
        cycles_run += 1;
        for line in sim.printed() {
            printed_lines += 1;
            if let Err(error) = writeln!(out, "{line}") {
                // A closed pipe (`| head`) is not a failure of the run.
                if error.kind() != std::io::ErrorKind::BrokenPipe {
                    return Err(error).context("cannot write the script's output");
                }
            }
            if last_printed.len() == 5 {
                last_printed.remove(0);
            }
            last_printed.push(line.to_string());
        }
        if let Some((writer, path)) = log.as_mut() {
            writer
                .write_row(sim.sensors())
                .with_context(|| format!("cannot write the log `{}`", path.display()))?;
        }
        if let Some(trace) = trace.as_mut() {
            trace.record(&sim);
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
        writer
            .finish()
            .with_context(|| format!("cannot write the log `{}`", path.display()))?;
    }
    if let (Some(trace), Some(path)) = (&trace, &args.plot) {
        let title = format!("{} with {}", mission.name, script_name);
        let svg = render_svg(trace, &title, sim.water_depth())
            .map_err(|error| anyhow::anyhow!("cannot draw the plot: {error}"))?;
        std::fs::write(path, svg)
            .with_context(|| format!("cannot write the plot `{}`", path.display()))?;
    }

    summary(&SummaryFacts {
        sim: &sim,
        loaded: &loaded,
        script_name: &script_name,
        cycles_run,
        wall,
        limit_given,
        printed_lines,
        last_printed: &last_printed,
        log: args.log.as_deref(),
        plot: args.plot.as_deref(),
        faults: &fault_plan,
        fault_texts: &args.faults,
        format: args.summary,
    });
    Ok(ExitCode::SUCCESS)
}

fn read_text(path: &Path, what: &str) -> anyhow::Result<String> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read the {what} `{}`", path.display()))?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

type OpenLog = (LogWriter<BufWriter<File>>, std::path::PathBuf);

fn open_log(
    path: &Path,
    args: &crate::RunArgs,
    sensor_list: &SensorList,
    program: &gloc_engine::program::Program,
    mission: &Mission,
    sim: &Simulation,
) -> anyhow::Result<OpenLog> {
    let Some(format) = LogFormat::from_path(path) else {
        bail!(
            "cannot tell the log format of `{}`: name it `.csv` or `.dba` (Slocum ASCII)",
            path.display()
        );
    };
    let columns = match &args.log_sensors {
        Some(names) => parse_columns(sensor_list, names).map_err(anyhow::Error::msg)?,
        // The pilot's set plus whatever the script writes.
        None => default_columns(sensor_list, &program.stored_sensors),
    };
    let file = File::create(path)
        .with_context(|| format!("cannot create the log `{}`", path.display()))?;
    let header = DbaHeader {
        filename: path
            .file_stem()
            .map(|stem| stem.to_string_lossy().into_owned())
            .unwrap_or_else(|| "gloc".to_string()),
        mission_name: mission.name.clone(),
        fileopen_time: glider_time(sim.present_time()),
    };
    let writer = LogWriter::new(
        BufWriter::with_capacity(1 << 16, file),
        format,
        columns,
        sensor_list,
        &header,
    )
    .with_context(|| format!("cannot write the log `{}`", path.display()))?;
    Ok((writer, path.to_path_buf()))
}

/// Parses `90s`, `45m`, `6h`, `30d`, or combinations such as `1h30m`.
pub fn parse_duration(text: &str) -> anyhow::Result<f64> {
    let trimmed = text.trim();
    let mut total = 0.0;
    let mut number = String::new();
    let mut saw_unit = false;
    for character in trimmed.chars() {
        if character.is_ascii_digit() || character == '.' {
            number.push(character);
            continue;
        }
        let unit = match character {
            's' => 1.0,
            'm' => 60.0,
            'h' => 3600.0,
            'd' => 86400.0,
            _ => bail!(
                "`{text}` is not a duration: use a number with s, m, h or d, such as `90m`, `6h` or `30d`"
            ),
        };
        let value: f64 = number.parse().map_err(|_| {
            anyhow::anyhow!("`{text}` is not a duration: a number must come before `{character}`")
        })?;
        total += value * unit;
        number.clear();
        saw_unit = true;
    }
    if !number.is_empty() || !saw_unit {
        bail!("`{text}` is not a duration: give the unit, such as `90m`, `6h` or `30d`");
    }
    if !(total > 0.0 && total.is_finite()) {
        bail!("`{text}` is not a positive duration");
    }
    Ok(total)
}

/// `Mon_May_24_00:00:00_2010`, the glider's `fileopen_time:` format.
fn glider_time(unix_seconds: f64) -> String {
    let seconds = unix_seconds.max(0.0) as i64;
    let days = seconds.div_euclid(86400);
    let of_day = seconds.rem_euclid(86400);
    let (year, month, day) = civil_from_days(days);
    let weekday = ["Thu", "Fri", "Sat", "Sun", "Mon", "Tue", "Wed"][days.rem_euclid(7) as usize];
    let month_name = [
        "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
    ][(month - 1) as usize];
    format!(
        "{weekday}_{month_name}_{day:02}_{:02}:{:02}:{:02}_{year}",
        of_day / 3600,
        of_day % 3600 / 60,
        of_day % 60
    )
}

/// Days since 1970-01-01 → (year, month, day) (Howard Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z - era * 146_097;
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
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
    format: crate::SummaryFormat,
}

fn summary(facts: &SummaryFacts<'_>) {
    let sim = facts.sim;
    let simulated = facts.cycles_run as f64 * sim.cycle_time();
    let wall = facts.wall.as_secs_f64();
    let speedup = if wall > 0.0 {
        format!("{:.0}×", simulated / wall)
    } else {
        "∞".to_string()
    };
    let (shallowest, deepest) = sim.depth_range();
    let mut lines = vec![
        format!(
            "mission       {} with {}",
            sim.mission_name(),
            facts.script_name
        ),
        format!(
            "cycles        {} ({} s each)",
            facts.cycles_run,
            sim.cycle_time()
        ),
        format!("simulated     {}", human_time(simulated)),
        format!(
            "wall time     {:.3} s ({speedup} faster than real time)",
            wall
        ),
        format!(
            "energy used   {:.1} kJ, {:.3} Ah",
            sim.energy_joules() / 1000.0,
            sim.amp_hours()
        ),
        format!(
            "depth range   {shallowest:.1} – {deepest:.1} m (water {:.0} m)",
            sim.water_depth()
        ),
    ];
    let ended = match sim.end() {
        Some(end) => {
            let how = match end.reason {
                EndReason::Completed => "completed".to_string(),
                EndReason::Aborted(reason) => format!("ABORTED ({})", reason.glider_name()),
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
    };
    lines.push(format!("mission end   {ended}"));
    let script_state = match sim.script_trap() {
        Some(trap) => {
            let line = facts.loaded.line_of_pc(trap.pc).unwrap_or(trap.line);
            format!(
                "TRAPPED at {}:{line}: {} (the vehicle flew on)",
                facts.script_name,
                facts.loaded.trap_message(&trap.kind)
            )
        }
        None => match sim.script_last_end() {
            Some(gloc_engine::vm::CycleEnd::Halted) => "halted".to_string(),
            _ => "ran to the end of the run".to_string(),
        },
    };
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
    for ((fault, applied), text) in facts.faults.report().zip(facts.fault_texts) {
        lines.push(format!(
            "fault         {}",
            fault_line(fault, applied, text, sim)
        ));
    }
    if let Some(path) = facts.log {
        lines.push(format!("log           {}", path.display()));
    }
    if let Some(path) = facts.plot {
        lines.push(format!("plot          {}", path.display()));
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
            "log": facts.log.map(|path| path.display().to_string()),
            "plot": facts.plot.map(|path| path.display().to_string()),
        });
        let _ = writeln!(err, "{json}");
        return;
    }
    for line in lines {
        let _ = writeln!(err, "{line}");
    }
}

/// `m_depth:nan@20: m_depth reads NaN in cycles 20–336 (1m 20s – 22m 24s)`.
fn fault_line(fault: &Fault, applied: Option<(u64, u64)>, text: &str, sim: &Simulation) -> String {
    let name = sim.sensor_list().name(fault.sensor).unwrap_or("the sensor");
    let at = |cycle: u64| human_time(cycle as f64 * sim.cycle_time());
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("90m").expect("ok"), 5400.0);
        assert_eq!(parse_duration("6h").expect("ok"), 21600.0);
        assert_eq!(parse_duration("30d").expect("ok"), 2_592_000.0);
        assert_eq!(parse_duration("1h30m").expect("ok"), 5400.0);
        assert_eq!(parse_duration("0.5h").expect("ok"), 1800.0);
        assert!(parse_duration("6").is_err());
        assert!(parse_duration("6x").is_err());
        assert!(parse_duration("h").is_err());
        assert!(parse_duration("0s").is_err());
        assert!(parse_duration("").is_err());
    }

    #[test]
    fn glider_time_format() {
        // 2010-05-24 00:00:00 UTC was a Monday.
        assert_eq!(glider_time(1_274_659_200.0), "Mon_May_24_00:00:00_2010");
        assert_eq!(glider_time(0.0), "Thu_Jan_01_00:00:00_1970");
    }

    #[test]
    fn human_times() {
        assert_eq!(human_time(65.0), "1m 05s");
        assert_eq!(human_time(3725.0), "1h 02m 05s");
        assert_eq!(human_time(2_592_000.0), "30d 00h 00m 00s");
    }
}
