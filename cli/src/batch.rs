//! `gloc batch`: fly one script through a sweep of missions (seeds, temperature
//! profiles, fault sets, simulator settings: every combination), each mission
//! independent, on all cores, and print one summary table (readable on stdout,
//! CSV with `--csv`). A progress bar shows on a terminal.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use anyhow::{bail, Context};
use gloc_engine::sensors::SensorList;
use gloc_project::settings::{Origin, Settings};
use gloc_sim::faults::{step_cycle_with_faults, Fault, FaultPlan};
use gloc_sim::{EndReason, TemperatureProfile};

use crate::flags::{Limit, DEFAULT_LIMIT_SECONDS};
use crate::render::Tally;
use crate::simulate::{load_mission, load_program, script_state, Script};

/// One mission of the sweep: its seed and its value on each other axis, shared with the
/// other missions that have it (a sweep's memory grows by a few words per mission).
struct Variant {
    seed: u64,
    profile: Arc<Profile>,
    faults: Arc<FaultSet>,
    /// `--sim` values of this mission, applied after gloc.toml's `[simulator]`.
    settings: Arc<Vec<(String, f64)>>,
}

struct Profile {
    /// `builtin` or the profile's path as given.
    label: String,
    profile: Option<TemperatureProfile>,
}

struct FaultSet {
    /// The fault set as given (`none` when empty).
    label: String,
    faults: Vec<Fault>,
}

/// What the table says about one flown mission.
struct Row {
    cycles: u64,
    end: String,
    /// abend aborted the mission.
    aborted: bool,
    script: String,
    printed: u64,
    shallowest: f64,
    deepest: f64,
    energy_kj: f64,
    amp_hours: f64,
    seconds: f64,
}

/// What every mission shares.
struct Shared<'a> {
    plan: gloc_project::simulation::Plan<'a>,
    script_name: &'a str,
    limit: Limit,
}

pub fn main(args: crate::BatchArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let settings = Settings::resolve(args.script.as_deref(), args.flight.overrides())?;
    let Some(sensor_list) = crate::loading::active_sensors(&settings, &mut tally)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    let sensor_list = Arc::new(sensor_list);
    let axes = parse_axes(&args, &sensor_list)?;
    let profiles = load_profiles(axes.profile_names)?;
    if let Some(csv) = &args.csv {
        // Outputs never overwrite inputs (`gloc run`'s rule).
        let inputs: Vec<&Path> = args
            .script
            .as_deref()
            .into_iter()
            .chain(settings.input_paths())
            .chain(args.profiles.iter().map(Path::new))
            .collect();
        crate::output::check_output(&inputs, "--csv", csv)?;
    }
    let variants = sweep(&axes.seeds, profiles, axes.fault_sets, &axes.settings);

    let Some(Script {
        name: script_name,
        text: script_text,
        loaded,
        program,
    }) = load_program(
        args.script.as_deref(),
        &sensor_list,
        &settings,
        args.optimization(),
    )?
    else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    let Some(mission) = load_mission(&settings, &sensor_list)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };

    let limit = axes.limit;
    let shared = Shared {
        plan: gloc_project::simulation::Plan {
            settings: &settings,
            sensors: &sensor_list,
            mission: &mission,
            script: &loaded,
            program: &program,
        },
        script_name: &script_name,
        limit,
    };
    // The mission against the list and the script, and the simulator's own warnings,
    // once for the sweep (they are the same for every variant but a swept setting's).
    // A variant that cannot be prepared shows its error in its row.
    if let Some(first) = variants.first() {
        let prepared = gloc_project::simulation::prepare(
            &shared.plan,
            gloc_project::simulation::Flight {
                seed: Some(first.seed),
                profile: first.profile.profile.clone(),
                simulator: first.settings.to_vec(),
            },
        );
        if let Ok(prepared) = prepared {
            crate::simulate::print_warnings(
                &prepared.warnings,
                &mission,
                &script_name,
                &script_text,
            );
        }
    }
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, variants.len().max(1));
    let progress = crate::render::progress_bar(variants.len() as u64, "flying", "missions");
    let started = Instant::now();
    let rows = fly_all(&shared, &variants, jobs, progress.as_ref());
    let wall = started.elapsed().as_secs_f64();
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }

    report(&variants, &rows, wall, jobs, &args)
}

/// The sweep's axes as the command line gives them, each checked before anything flies.
struct Axes {
    seeds: Vec<u64>,
    profile_names: Vec<String>,
    fault_sets: Vec<FaultSet>,
    /// Each `--sim NAME=V1,V2,…` as its list of settings.
    settings: Vec<Vec<(String, f64)>>,
    limit: Limit,
}

/// Reads and checks every axis and the limit, and refuses a sweep too wide before any
/// profile is read: a typo costs nothing.
fn parse_axes(args: &crate::BatchArgs, sensor_list: &SensorList) -> anyhow::Result<Axes> {
    let seeds = match &args.seeds {
        Some(text) => parse_seeds(text).map_err(|error| anyhow::anyhow!("--seeds {error}"))?,
        None => vec![1],
    };
    let profile_names = if args.profiles.is_empty() {
        vec!["builtin".to_string()]
    } else {
        args.profiles.clone()
    };
    let mut fault_sets = Vec::new();
    for given in if args.fault_sets.is_empty() {
        vec!["none".to_string()]
    } else {
        args.fault_sets.clone()
    } {
        let faults = parse_fault_set(&given, sensor_list)
            .map_err(|error| anyhow::anyhow!("--fault-set `{given}`: {error}"))?;
        let label = if faults.is_empty() {
            "none".to_string()
        } else {
            given
        };
        fault_sets.push(FaultSet { label, faults });
    }
    let mut axes: Vec<Vec<(String, f64)>> = Vec::new();
    for given in &args.simulator {
        axes.push(parse_sweep_setting(given).map_err(|error| anyhow::anyhow!("--sim {error}"))?);
    }
    // The same bound as `gloc run`, in the standard 4 s cycles: every mission of a sweep
    // must be able to finish.
    let limit = args
        .length
        .limit(4.0)?
        .unwrap_or(Limit::Seconds(DEFAULT_LIMIT_SECONDS));
    // The sweep's size is known from the arguments: checked before any profile is read
    // (60 copies of a 16 MB profile were all read, 1 GB, before a sweep too wide).
    let missions = [profile_names.len(), fault_sets.len()]
        .into_iter()
        .chain(axes.iter().map(Vec::len))
        .try_fold(seeds.len(), usize::checked_mul)
        .filter(|missions| *missions <= MAX_MISSIONS);
    if missions.is_none() {
        bail!("the sweep has more than {MAX_MISSIONS} missions: narrow --seeds or the other axes");
    }
    Ok(Axes {
        seeds,
        profile_names,
        fault_sets,
        settings: axes,
        limit,
    })
}

/// Reads each profile once (a profile given twice is shared; `builtin` is none).
fn load_profiles(names: Vec<String>) -> anyhow::Result<Vec<Arc<Profile>>> {
    let mut loaded: std::collections::HashMap<String, Arc<Profile>> =
        std::collections::HashMap::new();
    let mut profiles = Vec::with_capacity(names.len());
    for given in names {
        if let Some(known) = loaded.get(&given) {
            profiles.push(Arc::clone(known));
            continue;
        }
        let profile = if given == "builtin" {
            None
        } else {
            let path = PathBuf::from(&given);
            Some(gloc_project::simulation::load_profile(
                &path,
                Origin::Flag("--profile"),
            )?)
        };
        let profile = Arc::new(Profile {
            label: given.clone(),
            profile,
        });
        loaded.insert(given, Arc::clone(&profile));
        profiles.push(profile);
    }
    Ok(profiles)
}

/// Prints the table (and writes the CSV) and the sweep's speed; the exit code says
/// whether a mission failed or aborted.
fn report(
    variants: &[Variant],
    rows: &[Result<Row, String>],
    wall: f64,
    jobs: usize,
    args: &crate::BatchArgs,
) -> anyhow::Result<ExitCode> {
    let table = table(variants, rows);
    let mut out = std::io::stdout().lock();
    match write_readable(&mut out, &table) {
        Err(error) if !crate::output::is_closed_pipe(&error) => {
            return Err(error).context("cannot write the table");
        }
        _ => {}
    }
    if let Some(path) = &args.csv {
        write_csv(path, &table)?;
    }
    eprintln!(
        "{} missions in {wall:.3} s on {jobs} thread(s): {:.2} missions/s",
        variants.len(),
        variants.len() as f64 / wall.max(f64::MIN_POSITIVE)
    );
    let failed = rows.iter().filter(|row| row.is_err()).count();
    let aborted = rows
        .iter()
        .filter(|row| row.as_ref().is_ok_and(|row| row.aborted))
        .count();
    Ok(if failed > 0 {
        ExitCode::FAILURE
    } else if aborted > 0 {
        eprintln!("{aborted} of {} missions aborted", rows.len());
        crate::exit::code(crate::exit::ABORTED)
    } else {
        ExitCode::SUCCESS
    })
}

/// A sweep wider than this is a mistake (`--seeds 1-1000000000`), not a plan: its table
/// alone would take hundreds of megabytes.
const MAX_MISSIONS: usize = 100_000;

/// Every combination; the seed varies fastest.
fn sweep(
    seeds: &[u64],
    profiles: Vec<Arc<Profile>>,
    fault_sets: Vec<FaultSet>,
    axes: &[Vec<(String, f64)>],
) -> Vec<Variant> {
    let mut settings: Vec<Vec<(String, f64)>> = vec![Vec::new()];
    for axis in axes {
        settings = settings
            .iter()
            .flat_map(|chosen| {
                axis.iter().map(move |value| {
                    let mut next = chosen.clone();
                    next.push(value.clone());
                    next
                })
            })
            .collect();
    }
    let settings: Vec<Arc<Vec<(String, f64)>>> = settings.into_iter().map(Arc::new).collect();
    let fault_sets: Vec<Arc<FaultSet>> = fault_sets.into_iter().map(Arc::new).collect();
    let mut variants = Vec::new();
    for profile in profiles {
        for faults in &fault_sets {
            for chosen in &settings {
                for &seed in seeds {
                    variants.push(Variant {
                        seed,
                        profile: Arc::clone(&profile),
                        faults: Arc::clone(faults),
                        settings: Arc::clone(chosen),
                    });
                }
            }
        }
    }
    variants
}

/// Flies every variant on `jobs` threads; rows in the variants' order.
fn fly_all(
    shared: &Shared<'_>,
    variants: &[Variant],
    jobs: usize,
    progress: Option<&indicatif::ProgressBar>,
) -> Vec<Result<Row, String>> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<Row, String>>>> =
        Mutex::new((0..variants.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                let Some(variant) = variants.get(index) else {
                    break;
                };
                let row = fly(shared, variant);
                if let Ok(mut results) = results.lock() {
                    results[index] = Some(row);
                }
                if let Some(bar) = progress {
                    bar.inc(1);
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .into_iter()
        .map(|row| row.unwrap_or_else(|| Err("not flown (a worker stopped)".to_string())))
        .collect()
}

/// One mission, start to end.
fn fly(shared: &Shared<'_>, variant: &Variant) -> Result<Row, String> {
    let started = Instant::now();
    // The warnings were shown once, from the first variant (`main`).
    let mut sim = gloc_project::simulation::prepare(
        &shared.plan,
        gloc_project::simulation::Flight {
            seed: Some(variant.seed),
            profile: variant.profile.profile.clone(),
            simulator: variant.settings.to_vec(),
        },
    )
    .map_err(|error| error.to_string())?
    .simulation;
    let max_cycles = shared.limit.cycles(&sim);
    let mut plan = FaultPlan::new(variant.faults.faults.clone());
    let mut cycles = 0;
    let mut printed = 0;
    while cycles < max_cycles && step_cycle_with_faults(&mut sim, &mut plan) {
        cycles += 1;
        printed += sim.printed().count() as u64;
    }
    let end = match sim.end() {
        Some(end) => match end.reason {
            EndReason::Completed => format!("completed at cycle {}", end.cycle),
            EndReason::Aborted(reason) => {
                format!("ABORTED ({}) at cycle {}", reason.glider_name(), end.cycle)
            }
            EndReason::BatteryExhausted => format!("BATTERY EXHAUSTED at cycle {}", end.cycle),
        },
        None => "running".to_string(),
    };
    let script = script_state(&sim, shared.plan.script, shared.script_name);
    let (shallowest, deepest) = sim.depth_range();
    Ok(Row {
        cycles,
        end,
        aborted: matches!(sim.end().map(|end| end.reason), Some(EndReason::Aborted(_))),
        script,
        printed,
        shallowest,
        deepest,
        energy_kj: sim.energy_joules() / 1000.0,
        amp_hours: sim.amp_hours(),
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The summary table: a header and one row of cells per mission.
struct Table {
    header: Vec<&'static str>,
    rows: Vec<Vec<String>>,
}

fn table(variants: &[Variant], rows: &[Result<Row, String>]) -> Table {
    let header = vec![
        "mission",
        "seed",
        "profile",
        "faults",
        "settings",
        "cycles",
        "end",
        "script",
        "printed",
        "min_depth_m",
        "max_depth_m",
        "energy_kj",
        "charge_ah",
        "seconds",
    ];
    let rows = variants
        .iter()
        .zip(rows)
        .enumerate()
        .map(|(index, (variant, row))| {
            let settings = if variant.settings.is_empty() {
                "-".to_string()
            } else {
                variant
                    .settings
                    .iter()
                    .map(|(name, value)| format!("{name}={value}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            let mut cells = vec![
                (index + 1).to_string(),
                variant.seed.to_string(),
                variant.profile.label.clone(),
                variant.faults.label.clone(),
                settings,
            ];
            match row {
                Ok(row) => cells.extend([
                    row.cycles.to_string(),
                    row.end.clone(),
                    row.script.clone(),
                    row.printed.to_string(),
                    format!("{:.2}", row.shallowest),
                    format!("{:.2}", row.deepest),
                    format!("{:.1}", row.energy_kj),
                    format!("{:.3}", row.amp_hours),
                    format!("{:.3}", row.seconds),
                ]),
                Err(message) => {
                    cells.push("0".to_string());
                    cells.push(format!("error: {message}"));
                    cells.extend(std::iter::repeat_n("-".to_string(), 7));
                }
            }
            cells
        })
        .collect();
    Table { header, rows }
}

fn write_readable(out: &mut impl Write, table: &Table) -> std::io::Result<()> {
    let mut widths: Vec<usize> = table
        .header
        .iter()
        .map(|name| name.chars().count())
        .collect();
    for row in &table.rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        cells
            .zip(&widths)
            .map(|(cell, width)| format!("{cell:<width$}"))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
    };
    writeln!(out, "{}", line(&mut table.header.iter().copied()))?;
    for row in &table.rows {
        writeln!(out, "{}", line(&mut row.iter().map(String::as_str)))?;
    }
    Ok(())
}

fn write_csv(path: &Path, table: &Table) -> anyhow::Result<()> {
    let mut text = table.header.join(",");
    text.push('\n');
    for row in &table.rows {
        let cells: Vec<String> = row.iter().map(|cell| csv_cell(cell)).collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    crate::output::write_atomically(path, text.as_bytes())
        .map_err(|error| crate::output::write_error(error, "the table", path))
}

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
fn csv_cell(cell: &str) -> String {
    if cell.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", cell.replace('"', "\"\""))
    } else {
        cell.to_string()
    }
}

/// `1-100`, `1,5,9-12`: seeds in the order given, ranges inclusive.
fn parse_seeds(text: &str) -> Result<Vec<u64>, String> {
    let mut seeds = Vec::new();
    for part in text.split(',').map(str::trim) {
        let number = |digits: &str| {
            digits.trim().parse::<u64>().map_err(|_| {
                format!("`{text}`: `{digits}` is not a seed (a whole number ≥ 0); write e.g. `1-100` or `1,5,9-12`")
            })
        };
        match part.split_once('-') {
            Some((first, last)) => {
                let (first, last) = (number(first)?, number(last)?);
                if last < first {
                    return Err(format!("`{text}`: the range `{part}` runs backwards"));
                }
                if last - first >= MAX_MISSIONS as u64 {
                    return Err(format!(
                        "`{text}`: the range `{part}` has more than {MAX_MISSIONS} seeds"
                    ));
                }
                seeds.extend(first..=last);
            }
            None => seeds.push(number(part)?),
        }
        if seeds.len() > MAX_MISSIONS {
            return Err(format!("`{text}` has more than {MAX_MISSIONS} seeds"));
        }
    }
    Ok(seeds)
}

/// `m_depth:nan@20,m_pitch:stuck=0@5..9`: the faults of one mission (`none` or empty:
/// no fault).
fn parse_fault_set(text: &str, list: &SensorList) -> Result<Vec<Fault>, String> {
    let text = text.trim();
    if text.is_empty() || text.eq_ignore_ascii_case("none") {
        return Ok(Vec::new());
    }
    text.split(',')
        .map(|fault| Fault::parse(fault.trim(), list).map_err(|error| error.to_string()))
        .collect()
}

/// `drag_cd0=0.15,0.2`: one simulator setting and the values to sweep, each checked
/// as `gloc run --sim` checks it.
fn parse_sweep_setting(text: &str) -> Result<Vec<(String, f64)>, String> {
    let (name, values) = text.split_once('=').ok_or_else(|| {
        format!("`{text}` is not NAME=VALUE[,VALUE...], e.g. `drag_cd0=0.15,0.2`")
    })?;
    values
        .split(',')
        .map(|value| gloc_project::settings::parse_simulator_setting(&format!("{name}={value}")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_are_lists_and_inclusive_ranges() {
        assert_eq!(parse_seeds("1-3").expect("ok"), [1, 2, 3]);
        assert_eq!(parse_seeds("7, 1,9-10").expect("ok"), [7, 1, 9, 10]);
        // A falling range, no number, an open end, a range of 2^64 seeds.
        for bad in ["5-3", "x", "1-", "0-18446744073709551615"] {
            assert!(parse_seeds(bad).is_err(), "`{bad}` was taken");
        }
    }

    #[test]
    fn a_sweep_is_every_combination_seed_fastest() {
        let axes = vec![
            parse_sweep_setting("drag_cd0=0.15,0.2").expect("ok"),
            parse_sweep_setting("drag_cd1=0.1,0.12,0.14").expect("ok"),
        ];
        let profiles = vec![Arc::new(Profile {
            label: "builtin".to_string(),
            profile: None,
        })];
        let faults = vec![FaultSet {
            label: "none".to_string(),
            faults: Vec::new(),
        }];
        let variants = sweep(&[4, 5], profiles, faults, &axes);
        // 2 × 3 settings × 2 seeds.
        assert_eq!(variants.len(), 12);
        assert_eq!(variants[0].seed, 4);
        assert_eq!(variants[1].seed, 5);
        assert_eq!(
            *variants[1].settings,
            [
                ("drag_cd0".to_string(), 0.15),
                ("drag_cd1".to_string(), 0.1)
            ]
        );
        assert_eq!(
            *variants[11].settings,
            [
                ("drag_cd0".to_string(), 0.2),
                ("drag_cd1".to_string(), 0.14)
            ]
        );
        assert!(parse_sweep_setting("drag_cd0").is_err());
        assert!(parse_sweep_setting("no_such_setting=1").is_err());
    }

    #[test]
    fn csv_cells_are_quoted_when_needed() {
        assert_eq!(csv_cell("ran"), "ran");
        assert_eq!(csv_cell("a,b"), "\"a,b\"");
        assert_eq!(csv_cell("say \"x\""), "\"say \"\"x\"\"\"");
    }
}
