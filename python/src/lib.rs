//! The native half of the `gloc` Python package: conversion only. Every function
//! resolves settings, reads, checks, flies or fits through the same library calls
//! as the CLI (`gloc_project`, `gloc_dbd`, `gloc_sim`) and hands plain Python values
//! (tuples, lists, `bytes` of f64 columns) to `gloc/__init__.py`, which makes the
//! DataFrames and the exceptions a user sees.

#![forbid(unsafe_code)]

mod forecast;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_compiler::{Language, Optimization};
use gloc_dbd::{CycleSource, DbdError, DbdErrorKind, Deployment};
use gloc_engine::sensors::SensorList;
use gloc_engine::{Diagnostic, LineIndex, Severity};
use gloc_project::error::ProjectError;
use gloc_project::script::Script;
use gloc_project::settings::Settings;
use gloc_project::{Overrides, Surface};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

create_exception!(
    _native,
    LogError,
    PyException,
    "A glider log that cannot be read."
);
create_exception!(
    _native,
    ProjectError_,
    PyException,
    "Settings, a sensor list, a script or a mission that cannot be used."
);

/// Read logs: `(names, units, bytes, rows, data, times, time_name, warnings)`,
/// `data` the f64 values row after row (NaN where a cycle did not update the
/// sensor), `times` each cycle's time (`Cycle::time`, NaN when not updated).
type ReadResult = (
    Vec<String>,
    Vec<String>,
    Vec<u8>,
    usize,
    Py<PyArray2<f64>>,
    Py<PyArray1<f64>>,
    Option<String>,
    Vec<String>,
);

/// A diagnostic as Python gets it: code, severity, message, line, column, end line,
/// end column (1-based, columns in characters), help.
type PyDiagnostic = (
    String,
    String,
    String,
    usize,
    usize,
    usize,
    usize,
    Option<String>,
);

/// `gloc.read`: the logs merged as `gloc data convert` and the replay merge them.
#[pyfunction]
#[pyo3(signature = (paths, sensors=None, sensor_cache=None))]
fn read(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    sensors: Option<Vec<String>>,
    sensor_cache: Option<PathBuf>,
) -> PyResult<ReadResult> {
    let read = py.allow_threads(|| read_columns(&paths, sensors.as_deref(), sensor_cache))?;
    // The table is made by numpy (its allocator asks for huge pages, so filling
    // tens of MB costs a fraction of the page faults), NaN, then the updated cells.
    let table = PyArray2::<f64>::zeros(py, [read.rows, read.names.len()], false);
    {
        let mut writable = table.readwrite();
        let cells = writable.as_slice_mut()?;
        cells.fill(f64::NAN);
        for (&cell, &value) in read.cells.iter().zip(&read.values) {
            cells[cell] = value;
        }
    }
    let data = table.unbind();
    // numpy takes the buffer over: no copy of the times.
    let times = PyArray1::from_vec(py, read.times).unbind();
    Ok((
        read.names,
        read.units,
        read.bytes,
        read.rows,
        data,
        times,
        read.time_name,
        read.warnings,
    ))
}

/// Columns of f64 as one `bytes`, column after column, native byte order (numpy's
/// `frombuffer` reads it without a copy).
fn f64_bytes(py: Python<'_>, columns: &[Vec<f64>]) -> PyResult<Py<PyBytes>> {
    let length = columns.iter().map(Vec::len).sum::<usize>() * 8;
    let data = PyBytes::new_with(py, length, |buffer| {
        for (chunk, value) in buffer.chunks_exact_mut(8).zip(columns.iter().flatten()) {
            chunk.copy_from_slice(&value.to_ne_bytes());
        }
        Ok(())
    })?;
    Ok(data.unbind())
}

struct Columns {
    names: Vec<String>,
    units: Vec<String>,
    bytes: Vec<u8>,
    rows: usize,
    /// The updated cells, sparse: each one's index in the row-major table of
    /// `rows` rows of the selected sensors, and its value.
    cells: Vec<usize>,
    values: Vec<f64>,
    times: Vec<f64>,
    time_name: Option<String>,
    warnings: Vec<String>,
}

fn read_columns(
    paths: &[PathBuf],
    sensors: Option<&[String]>,
    sensor_cache: Option<PathBuf>,
) -> PyResult<Columns> {
    let mut source = open_logs(paths, sensor_cache)?;
    let all = source.sensors().clone();
    let selected: Vec<usize> = match sensors {
        None => (0..all.len()).collect(),
        Some(names) => names
            .iter()
            .map(|name| {
                all.iter()
                    .position(|sensor| sensor.name.eq_ignore_ascii_case(name))
                    .ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "`{name}` is not a sensor of these files ({} sensors; `gloc data info --sensors` lists them)",
                            all.len()
                        ))
                    })
            })
            .collect::<PyResult<_>>()?,
    };
    // Row after row, as the cycles come, only the cells a cycle updated (a
    // deployment's table is mostly NaN: comet's, 89 %).
    let width = selected.len();
    let mut targets: Vec<Vec<usize>> = vec![Vec::new(); all.len()];
    for (position, &column) in selected.iter().enumerate() {
        targets[column].push(position);
    }
    let every = sensors.is_none();
    let mut cells: Vec<usize> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut times = Vec::new();
    while let Some(cycle) = source.next_cycle().map_err(log_error)? {
        let row = times.len() * width;
        for &column in &cycle.updated {
            let value = cycle.values[column];
            if every {
                cells.push(row + column);
                values.push(value);
            } else {
                for &position in &targets[column] {
                    cells.push(row + position);
                    values.push(value);
                }
            }
        }
        times.push(cycle.time);
    }
    let time_name = source.time_column().map(|index| all[index].name.clone());
    let warnings = source
        .take_warnings()
        .iter()
        .map(ToString::to_string)
        .collect();
    let pick = |field: &dyn Fn(&gloc_dbd::FileSensor) -> String| {
        selected.iter().map(|&index| field(&all[index])).collect()
    };
    Ok(Columns {
        names: pick(&|sensor| sensor.name.clone()),
        units: pick(&|sensor| sensor.units.clone()),
        bytes: selected.iter().map(|&index| all[index].bytes).collect(),
        rows: times.len(),
        cells,
        values,
        times,
        time_name,
        warnings,
    })
}

/// The deployment of `paths`, with the sensor cache `gloc data` would use (the
/// argument, else `sensor_cache` in the gloc.toml above the first file).
fn open_logs(paths: &[PathBuf], sensor_cache: Option<PathBuf>) -> PyResult<Deployment> {
    let settings = Settings::resolve(
        paths.first().map(PathBuf::as_path),
        Overrides {
            sensor_cache,
            ..Overrides::new(Surface::Cli)
        },
    )
    .map_err(project_error)?;
    Deployment::open(paths, settings.sensor_cache.as_deref()).map_err(log_error)
}

/// A `DbdError` as `gloc._native.LogError(message, file, offset, block, kind)`.
fn log_error(error: DbdError) -> PyErr {
    let kind = match error.kind {
        DbdErrorKind::Content => "content",
        DbdErrorKind::Unreadable => "unreadable",
    };
    LogError::new_err((
        error.to_string(),
        error.file,
        error.at.offset,
        error.at.block,
        kind,
    ))
}

fn project_error(error: ProjectError) -> PyErr {
    ProjectError_::new_err(error.to_string())
}

/// The settings of the project around `anchor` and its active sensor list.
fn project(anchor: Option<&Path>, overrides: Overrides) -> PyResult<(Settings, SensorList)> {
    let settings = Settings::resolve(anchor, overrides).map_err(project_error)?;
    let loaded = gloc_project::sensors::load_sensor_list(&settings).map_err(project_error)?;
    match loaded.errors() {
        Some(error) => Err(project_error(error)),
        None => Ok((settings, loaded.list)),
    }
}

/// A script from a file (its language by extension) or from text.
fn load(
    path: Option<PathBuf>,
    text: Option<String>,
    gbasic: Option<bool>,
    optimization: Optimization,
) -> PyResult<Script> {
    let (settings, sensors) = project(path.as_deref(), Overrides::new(Surface::Cli))?;
    let language = |default: Language| match gbasic {
        Some(true) => Language::Gbasic,
        Some(false) => Language::Gloc,
        None => default,
    };
    match (path, text) {
        (Some(path), None) => {
            let extension = gloc_engine::files::extension(&path);
            if matches!(extension.as_deref(), Some("mi" | "ma" | "cac" | "ccc")) {
                return Err(PyValueError::new_err(format!(
                    "{}: gloc.check and gloc.compile read scripts (.gloc, .gbas); check a mission or a sensor list with `gloc check {}`",
                    path.display(),
                    path.display()
                )));
            }
            let text = gloc_project::script::read_script(&path).map_err(project_error)?;
            Ok(gloc_project::script::load_text(
                Some(&path),
                path.display().to_string(),
                text,
                language(Language::of_path(&path)),
                &sensors,
                &settings,
                optimization,
            ))
        }
        (None, Some(text)) => Ok(gloc_project::script::load_text(
            None,
            "<text>".to_string(),
            text,
            language(Language::Gloc),
            &sensors,
            &settings,
            optimization,
        )),
        _ => Err(PyValueError::new_err(
            "give a script's path or its text, not both",
        )),
    }
}

/// `optimize=True` as the compiler's option (the CLI's `-O`, or `--no-optimize` off).
fn optimization(optimize: bool) -> Optimization {
    if optimize {
        Optimization::Optimized
    } else {
        Optimization::Plain
    }
}

fn diagnostics(text: &str, list: &[Diagnostic]) -> Vec<PyDiagnostic> {
    let index = LineIndex::new(text);
    list.iter()
        .map(|diagnostic| {
            let (line, column) = index.line_col(text, diagnostic.span.start as usize);
            let (end_line, end_column) = index.line_col(text, diagnostic.span.end as usize);
            let severity = match diagnostic.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                _ => "info",
            };
            (
                diagnostic.code.to_string(),
                severity.to_string(),
                diagnostic.message.clone(),
                line,
                column,
                end_line,
                end_column,
                diagnostic.help.clone(),
            )
        })
        .collect()
}

/// `gloc.check`: the diagnostics `gloc check` shows for a script.
#[pyfunction]
#[pyo3(signature = (path=None, text=None, gbasic=None))]
fn check(
    path: Option<PathBuf>,
    text: Option<String>,
    gbasic: Option<bool>,
) -> PyResult<Vec<PyDiagnostic>> {
    let script = load(path, text, gbasic, Optimization::Plain)?;
    Ok(diagnostics(&script.text, &script.loaded.diagnostics))
}

/// `gloc.compile`: GBASIC to GLOC, `(gloc_text or None, diagnostics)`.
#[pyfunction]
#[pyo3(signature = (path=None, text=None, optimize=false))]
fn compile(
    path: Option<PathBuf>,
    text: Option<String>,
    optimize: bool,
) -> PyResult<(Option<String>, Vec<PyDiagnostic>)> {
    let script = load(path, text, Some(true), optimization(optimize))?;
    let found = diagnostics(&script.text, &script.loaded.diagnostics);
    if script.loaded.has_errors() {
        return Ok((None, found));
    }
    Ok((script.loaded.gloc_text.clone(), found))
}

/// What a run gave: `(names, bytes, rows, data, summary, printed)`, `bytes` per
/// column 8 (logged as a double) or 4.
type RunResult = (
    Vec<String>,
    Vec<u8>,
    usize,
    Py<PyBytes>,
    Py<PyDict>,
    Vec<String>,
);

/// `gloc.run`: flies a script on a mission as `gloc run` does, logging the columns
/// `gloc run --log` writes, each value as the log holds it.
#[pyfunction]
#[pyo3(signature = (script, mission=None, seconds=None, cycles=None, seed=None, simulator=Vec::new(), profile=None, optimize=true))]
#[allow(clippy::too_many_arguments)]
fn run(
    py: Python<'_>,
    script: PathBuf,
    mission: Option<PathBuf>,
    seconds: Option<f64>,
    cycles: Option<u64>,
    seed: Option<u64>,
    simulator: Vec<(String, f64)>,
    profile: Option<PathBuf>,
    optimize: bool,
) -> PyResult<RunResult> {
    let flown = py.allow_threads(|| {
        fly(&Request {
            script,
            overrides: Overrides {
                mission,
                simulator,
                ..Overrides::new(Surface::Cli)
            },
            flight: (seed, profile),
            limit: (seconds, cycles),
            optimization: optimization(optimize),
        })
    })?;
    let data = f64_bytes(py, &flown.columns)?;
    let summary = PyDict::new(py);
    summary.set_item("cycles", flown.rows)?;
    summary.set_item("seconds", flown.seconds)?;
    summary.set_item("end", flown.end)?;
    summary.set_item("end_cycle", flown.end_cycle)?;
    let energy = PyDict::new(py);
    for (name, joules) in flown.energy {
        energy.set_item(name, joules)?;
    }
    summary.set_item("energy_joules", energy)?;
    summary.set_item("warnings", flown.warnings)?;
    Ok((
        flown.names,
        flown.bytes,
        flown.rows,
        data,
        summary.unbind(),
        flown.printed,
    ))
}

/// What `gloc.run` was asked: the script, the settings it overrides (as `gloc run`'s
/// flags do), the flight's seed and profile, and its limit in seconds or cycles.
struct Request {
    script: PathBuf,
    overrides: Overrides,
    flight: (Option<u64>, Option<PathBuf>),
    limit: (Option<f64>, Option<u64>),
    optimization: Optimization,
}

struct Flown {
    names: Vec<String>,
    bytes: Vec<u8>,
    rows: usize,
    columns: Vec<Vec<f64>>,
    seconds: f64,
    end: Option<String>,
    end_cycle: Option<u64>,
    energy: Vec<(&'static str, f64)>,
    warnings: Vec<String>,
    printed: Vec<String>,
}

/// The most control cycles one call may fly (`gloc run`'s limit).
const MAX_CYCLES: u64 = 100_000_000;

fn fly(request: &Request) -> PyResult<Flown> {
    let (settings, sensors) = project(Some(&request.script), request.overrides.clone())?;
    let sensors = Arc::new(sensors);
    let script = gloc_project::script::load_script(
        &request.script,
        &sensors,
        &settings,
        request.optimization,
    )
    .map_err(project_error)?;
    let Some(program) = script.loaded.program.clone() else {
        let found = diagnostics(&script.text, &script.loaded.diagnostics);
        return Err(ProjectError_::new_err(format!(
            "`{}` has errors; nothing was simulated: {}",
            script.display,
            found
                .iter()
                .filter(|found| found.1 == "error")
                .map(|found| format!("{}:{}: {} {}", found.3, found.4, found.0, found.2))
                .collect::<Vec<_>>()
                .join("; ")
        )));
    };
    let mission =
        gloc_project::simulation::load_mission(&settings, &sensors).map_err(project_error)?;
    if let Some(error) = mission_errors(&mission, "simulated") {
        return Err(error);
    }
    let (seed, profile) = &request.flight;
    let flight = gloc_project::simulation::Flight::read(
        *seed,
        profile.as_deref(),
        gloc_project::settings::Origin::Flag("profile"),
    )
    .map_err(project_error)?;
    let plan = gloc_project::simulation::Plan {
        settings: &settings,
        sensors: &sensors,
        mission: &mission,
        script: &script.loaded,
        program: &program,
    };
    let prepared = gloc_project::simulation::prepare(&plan, flight).map_err(project_error)?;
    let mut sim = prepared.simulation;
    let max_cycles = match request.limit {
        (Some(seconds), _) if !seconds.is_finite() || seconds < 0.0 => {
            return Err(PyValueError::new_err(
                "duration: give a number of seconds, 0 or more",
            ))
        }
        (Some(seconds), _) => gloc_project::simulation::cycles_for(seconds, &sim),
        (None, Some(cycles)) => cycles,
        (None, None) => gloc_project::simulation::cycles_for(24.0 * 3600.0, &sim),
    };
    if max_cycles > MAX_CYCLES {
        return Err(PyValueError::new_err(format!(
            "{max_cycles} control cycles is more than {MAX_CYCLES}, the most one run may take"
        )));
    }
    let ids = gloc_sim::log::default_columns(&sensors, &script.loaded.stored_sensors);
    let doubles: Vec<bool> = ids
        .iter()
        .map(|id| {
            sensors
                .get(*id)
                .is_some_and(gloc_sim::log::logged_as_double)
        })
        .collect();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); ids.len()];
    let mut printed = Vec::new();
    let mut rows = 0usize;
    let mut faults = gloc_sim::faults::FaultPlan::new(Vec::new());
    while (rows as u64) < max_cycles {
        if !gloc_sim::faults::step_cycle_with_faults(&mut sim, &mut faults) {
            break;
        }
        rows += 1;
        printed.extend(sim.printed().map(ToString::to_string));
        let values = sim.sensors();
        for ((column, id), &double) in columns.iter_mut().zip(&ids).zip(&doubles) {
            let value = values.get(id.index()).copied().unwrap_or(f64::NAN);
            // The log holds a 4-byte float unless the sensor is logged as a double.
            column.push(if double { value } else { value as f32 as f64 });
        }
    }
    let energy = sim.energy_use();
    let end = sim.end();
    let warnings = prepared.warnings.into_iter().map(warning_text).collect();
    Ok(Flown {
        names: ids
            .iter()
            .map(|id| sensors.name(*id).unwrap_or("unknown").to_string())
            .collect(),
        bytes: doubles
            .iter()
            .map(|&double| if double { 8 } else { 4 })
            .collect(),
        rows,
        columns,
        seconds: sim.time(),
        end: end.map(|end| end.reason.to_string()),
        end_cycle: end.map(|end| end.cycle),
        energy: vec![
            ("hotel", energy.hotel),
            ("pump", energy.pump),
            ("pitch", energy.pitch),
            ("science", energy.science),
            ("total", energy.total()),
        ],
        warnings,
        printed,
    })
}

/// A mission with errors as a `ProjectError` naming each (nothing was `done`).
fn mission_errors(mission: &gloc_sim::Mission, done: &str) -> Option<PyErr> {
    mission.has_errors().then(|| mission_error(mission, done))
}

/// The error a mission with errors raises, its diagnostics in one line.
pub(crate) fn mission_error(mission: &gloc_sim::Mission, done: &str) -> PyErr {
    ProjectError_::new_err(format!(
        "the mission has errors; nothing was {done}: {}",
        mission
            .diagnostics
            .iter()
            .map(|entry| format!("{} {}", entry.diagnostic.code, entry.diagnostic.message))
            .collect::<Vec<_>>()
            .join("; ")
    ))
}

/// A warning of `prepare` as one line (its code first where it has one).
pub(crate) fn warning_text(warning: gloc_project::simulation::Warning) -> String {
    match warning {
        gloc_project::simulation::Warning::Simulator(text) => text,
        gloc_project::simulation::Warning::Mission(entry) => {
            format!("{} {}", entry.diagnostic.code, entry.diagnostic.message)
        }
        gloc_project::simulation::Warning::Script(diagnostic) => {
            format!("{} {}", diagnostic.code, diagnostic.message)
        }
    }
}

/// A fit: `(fitted, not_fitted)`, each fitted constant `(name, value, from)`, each
/// one not fitted `(name, why)`.
type Calibration = (Vec<(String, f64, String)>, Vec<(String, String)>);

/// `gloc.calibrate`: the constants `gloc calibrate` fits, `(fitted, not_fitted)`.
#[pyfunction]
#[pyo3(signature = (paths, sensor_cache=None, climb_target=3.0))]
fn calibrate(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    sensor_cache: Option<PathBuf>,
    climb_target: f64,
) -> PyResult<Calibration> {
    py.allow_threads(|| {
        let mut source = open_logs(&paths, sensor_cache)?;
        let track = gloc_project::logs::read_track(&mut source).map_err(log_error)?;
        let fitted =
            gloc_sim::calibrate::fit(&track, climb_target, &gloc_sim::SimConfig::default())
                .map_err(|problem| PyValueError::new_err(format!("cannot calibrate: {problem}")))?;
        Ok((
            fitted
                .values
                .iter()
                .map(|value| (value.name.to_string(), value.value, value.from.clone()))
                .collect(),
            fitted
                .not_fitted
                .iter()
                .map(|(name, why)| (name.to_string(), why.clone()))
                .collect(),
        ))
    })
}

#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("LogError", module.py().get_type::<LogError>())?;
    module.add("ProjectError", module.py().get_type::<ProjectError_>())?;
    module.add_function(wrap_pyfunction!(read, module)?)?;
    module.add_function(wrap_pyfunction!(check, module)?)?;
    module.add_function(wrap_pyfunction!(compile, module)?)?;
    module.add_function(wrap_pyfunction!(run, module)?)?;
    module.add_function(wrap_pyfunction!(calibrate, module)?)?;
    module.add_function(wrap_pyfunction!(forecast::forecast, module)?)?;
    module.add_function(wrap_pyfunction!(forecast::forecast_members, module)?)?;
    module.add_function(wrap_pyfunction!(forecast::forecast_summary, module)?)?;
    Ok(())
}
