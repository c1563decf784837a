//! Fault injection over whole missions (issue: hardening). Sensor dropouts,
//! stuck values, NaN readings and spikes under the paper's Fig. 2 script, and
//! a script that traps or overruns mid-mission. In every case the script
//! stops or copes, abend and the other behaviors keep the vehicle safe, the
//! log has a row for every cycle to the end, and the run says what happened.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::TrapKind;
use gloc_sim::faults::{step_cycle_with_faults, Fault, FaultKind, FaultPlan};
use gloc_sim::log::{default_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::{default_mission, EndReason, SimConfig, Simulation};

const FIG2: &str = include_str!("../../examples/fig2.gloc");
/// More than the default mission needs to end (it ends after about 900 cycles).
const MAX_CYCLES: u64 = 5_000;
/// Water depth of the default mission, and its abend overdepth limit.
const WATER_DEPTH: f64 = 40.0;
const OVERDEPTH: f64 = 30.0;

struct Run {
    sim: Simulation,
    cycles: u64,
    log_rows: usize,
    depth_column: Vec<f64>,
}

fn list() -> Arc<SensorList> {
    Arc::new(SensorList::embedded())
}

fn sensor(list: &SensorList, name: &str) -> SensorId {
    list.lookup(name)
        .unwrap_or_else(|| panic!("{name} is a sensor"))
}

fn compile(text: &str, list: &SensorList) -> Arc<Program> {
    let checked = gloc::check(&gloc::parse(text), list, &CheckOptions::default());
    checked
        .program
        .unwrap_or_else(|| panic!("script does not check: {:?}", checked.diagnostics))
}

/// Runs the default mission with a script and faults, logging every cycle
/// to CSV as `gloc run --log` does, and reads the log back.
fn run(script: &str, faults: Vec<Fault>) -> Run {
    let list = list();
    let program = compile(script, &list);
    let mut sim = Simulation::new(
        &default_mission(),
        list.clone(),
        Some(program),
        &SimConfig::default(),
    )
    .expect("the default mission starts");
    let header = DbaHeader {
        filename: "faults".to_string(),
        mission_name: "fig2".to_string(),
        fileopen_time: "now".to_string(),
    };
    let columns = default_columns(&list, &[]);
    let mut writer =
        LogWriter::new(Vec::new(), LogFormat::Csv, columns, &list, &header).expect("log header");
    let mut plan = FaultPlan::new(faults);
    let mut cycles = 0;
    while cycles < MAX_CYCLES && step_cycle_with_faults(&mut sim, &mut plan) {
        cycles += 1;
        writer.write_row(sim.sensors()).expect("log row");
        let depth = sim.depth();
        assert!(
            depth.is_finite() && (0.0..=WATER_DEPTH).contains(&depth),
            "cycle {cycles}: the vehicle is at {depth} m"
        );
    }
    let text = String::from_utf8(writer.finish().expect("flush")).expect("UTF-8 log");
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().expect("a header line").split(',').collect();
    let depth_at = names
        .iter()
        .position(|name| *name == "m_depth")
        .expect("m_depth is logged");
    let rows: Vec<&str> = lines.collect();
    let depth_column = rows
        .iter()
        .map(|row| {
            let cell = row.split(',').nth(depth_at).expect("a depth cell");
            cell.parse::<f64>()
                .unwrap_or_else(|_| panic!("a logged number, not {cell:?}"))
        })
        .collect();
    Run {
        sim,
        cycles,
        log_rows: rows.len(),
        depth_column,
    }
}

/// Checks that hold after every fault: the mission ended on its own (not
/// at the cycle limit), safely, and the log has every cycle.
fn assert_safe_and_logged(run: &Run) {
    let end = run
        .sim
        .end()
        .unwrap_or_else(|| panic!("the mission ends by itself ({} cycles)", run.cycles));
    assert!(run.sim.is_finished());
    assert_eq!(run.log_rows as u64, run.cycles, "one log row per cycle");
    let (_, deepest) = run.sim.depth_range();
    // abend's overdepth limit, plus what one cycle can overshoot.
    assert!(
        deepest < OVERDEPTH + 2.0,
        "the vehicle stayed above the overdepth limit: deepest {deepest} m, end {end:?}"
    );
    assert!(
        run.sim.depth() < 2.5,
        "the mission ended at the surface: {} m",
        run.sim.depth()
    );
}

#[test]
fn without_faults_the_script_turns_the_glider_at_15_m() {
    let run = run(FIG2, Vec::new());
    assert_safe_and_logged(&run);
    assert_eq!(
        run.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
    assert!(run.sim.script_trap().is_none());
}

#[test]
fn depth_reading_nan_the_script_copes_and_the_mission_completes() {
    let list = list();
    let depth = sensor(&list, "m_depth");
    let run = run(
        FIG2,
        vec![Fault::from_cycle(depth, FaultKind::NotANumber, 20)],
    );
    assert_safe_and_logged(&run);
    // NaN compares false: the script neither traps nor asks for anything;
    // the yo flies on by the vehicle's own depth.
    assert!(run.sim.script_trap().is_none());
    assert_eq!(
        run.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
    // The log shows what the script saw: NaN from cycle 20 on.
    assert!(run.depth_column[..20].iter().all(|value| value.is_finite()));
    assert!(run.depth_column[20..].iter().all(|value| value.is_nan()));
}

#[test]
fn depth_stuck_deep_keeps_asking_for_a_climb_and_the_mission_still_ends() {
    let list = list();
    let depth = sensor(&list, "m_depth");
    // Stuck at 20 m: the script asks the hook to climb (bit 128) for ever.
    let run = run(
        FIG2,
        vec![Fault::from_cycle(depth, FaultKind::Stuck(20.0), 30)],
    );
    assert_safe_and_logged(&run);
    assert!(run.depth_column[30..].iter().all(|&value| value == 20.0));
}

#[test]
fn depth_dropout_holds_the_last_value_and_the_yo_still_ends_the_mission() {
    // Why the yo, not abend, ends it: only the script reads the frozen
    // m_depth. Whatever that value is, the Fig. 2 script can do no more than
    // set bit 128 once (then wait for m_depth < 5 m) and clear it once; the
    // hook clears bit 128 itself when the true depth reaches its 3 m, so the
    // yo (which, like abend, flies by the vehicle's true depth) gets the
    // stack back and does its six half cycles; then the stack is idle and
    // surface (end_action 0) completes the mission. abend sees the same
    // flight as without the fault: turns at 25 m + ~1 m (< 30 m overdepth),
    // always moving (no samedepth), and the mission lasts well under its
    // 7200 s overtime, so it does not abort.
    let list = list();
    let depth = sensor(&list, "m_depth");
    let run = run(FIG2, vec![Fault::from_cycle(depth, FaultKind::Dropout, 40)]);
    assert_safe_and_logged(&run);
    let held = run.depth_column[40];
    assert!(run.depth_column[40..].iter().all(|&value| value == held));
    assert!(run.depth_column[..40].iter().any(|&value| value != held));
    assert!(run.sim.script_trap().is_none());
    assert_eq!(
        run.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
}

#[test]
fn a_depth_spike_makes_the_script_climb_once_and_the_mission_completes() {
    let list = list();
    let depth = sensor(&list, "m_depth");
    let quiet = run(FIG2, Vec::new());
    // One cycle reads 100 m too deep, while the glider is shallow and diving.
    let spiked = run(
        FIG2,
        vec![Fault::during(depth, FaultKind::Spike(100.0), 10, 11)],
    );
    assert_safe_and_logged(&spiked);
    // The log keeps m_depth as the glider does, in 4 bytes: equal to f32 precision.
    assert!((spiked.depth_column[10] - (quiet.depth_column[10] + 100.0)).abs() < 1e-4);
    // The script reacted (the flight differs from the quiet run) and coped.
    assert_ne!(spiked.depth_column[20..40], quiet.depth_column[20..40]);
    assert_eq!(
        spiked.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
}

#[test]
fn faults_on_sensors_the_script_does_not_read_change_nothing() {
    let list = list();
    let pitch = sensor(&list, "m_pitch");
    let quiet = run(FIG2, Vec::new());
    let faulty = run(
        FIG2,
        vec![Fault::from_cycle(pitch, FaultKind::NotANumber, 5)],
    );
    assert_safe_and_logged(&faulty);
    assert_eq!(faulty.cycles, quiet.cycles);
    assert_eq!(faulty.depth_column, quiet.depth_column);
}

/// Fig. 2 with a counter (r8) of the passes through its loop heads (labels
/// 0, 1, 2: at least one per cycle) that runs `failure` at pass 200, well
/// before the mission ends. `failure` gets two free label numbers (N, N+1).
fn failing_script(failure: impl Fn(u32) -> Vec<String>) -> String {
    let mut body = Vec::new();
    let mut next_label = 7; // Fig. 2 uses labels 0-6.
    for line in FIG2.lines().skip(3) {
        body.push(line.to_string());
        if line == "label 0" || line == "label 1" || line == "label 2" {
            let (fail, go_on, spare) = (next_label, next_label + 1, next_label + 2);
            next_label += 4;
            body.extend([
                "loadi 1,r9".to_string(),
                "add r8,r9,r8".to_string(),
                "loadi 200,r9".to_string(),
                "cmpeq r8,r9,r10".to_string(),
                format!("cbr r10,{fail},{go_on}"),
                format!("label {fail}"),
            ]);
            body.extend(failure(spare));
            body.push(format!("label {go_on}"));
        }
    }
    format!(
        "nregs 11\nnblbs {next_label}\nninstr {}\n{}\n",
        body.len(),
        body.join("\n")
    )
}

#[test]
fn a_script_that_traps_mid_mission_stops_and_the_vehicle_flies_on() {
    // Integer division by zero traps.
    let run = run(
        &failing_script(|_| vec!["loadi 0,r9".to_string(), "div r9,r9,r9".to_string()]),
        Vec::new(),
    );
    assert_safe_and_logged(&run);
    let trap = run.sim.script_trap().expect("the script trapped");
    assert_eq!(trap.kind, TrapKind::DivisionByZero);
    assert_eq!(
        run.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
    assert!(
        run.cycles > 300,
        "the mission went on after the trap: {}",
        run.cycles
    );
}

#[test]
fn a_script_that_overruns_mid_mission_stops_and_the_vehicle_flies_on() {
    // A loop without a yield that would end after a million passes (so the
    // checker lets it through with a warning): the per-cycle budget stops it.
    let run = run(
        &failing_script(|label| {
            vec![
                "loadi 1000000,r9".to_string(),
                "loadi 1,r10".to_string(),
                format!("label {label}"),
                "sub r9,r10,r9".to_string(),
                "cmpgt r9,r8,r7".to_string(),
                format!("cbr r7,{label},{}", label + 1),
                format!("label {}", label + 1),
            ]
        }),
        Vec::new(),
    );
    assert_safe_and_logged(&run);
    let trap = run.sim.script_trap().expect("the script overran");
    assert!(
        matches!(trap.kind, TrapKind::CycleOverrun { .. }),
        "{trap:?}"
    );
    assert_eq!(
        run.sim.end().map(|end| end.reason),
        Some(EndReason::Completed)
    );
}
