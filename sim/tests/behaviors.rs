//! Behavior rules of docs/simulator.md checked cycle by cycle: the
//! start_when/stop_when codes 2, 4, 5 and 6, abend's `overtime`, the hook
//! behavior's bits, and a script storing straight to the command sensors
//! while abend's overdepth fires.
//!
//! Every expected cycle below is worked out from the documented rules: the
//! control cycle is 4 s (cycle `n` runs at mission time `4n` s), behaviors
//! step bottom-up, and a behavior's "idle" conditions look at what the
//! behaviors below it commanded so far in this cycle.

use std::sync::Arc;

/// The behaviors' logic is checked against hand-worked 4-second arithmetic:
/// an ideal clock (exact 4 s cycles, turns in the same cycle).
fn ideal_clock() -> SimConfig {
    SimConfig {
        timing: gloc_sim::simulation::TimingParams::ideal(),
        ..SimConfig::default()
    }
}

/// The hook's `bpump_value` 260 cc as `c_ballast_pumped` publishes it: clipped
/// to the pump's 230 cc (`pump_max`), as a real glider clips (comet's log:
/// b_arg 1000, c_ballast_pumped 233).
const PUBLISHED_BPUMP: f64 = 230.0;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::SensorList;
use gloc_sim::behaviors::{AbortReason, BehaviorKind, EventKind};
use gloc_sim::{EndReason, Mission, SimConfig, Simulation};

/// What one cycle did, read after the cycle.
#[derive(Debug)]
struct Cycle {
    /// `(behavior name, event)` in the order they happened.
    events: Vec<(String, EventKind)>,
    /// `m_depth` as published at the start of the cycle (the flight sensors
    /// carry no noise, so this is the depth the behaviors saw).
    depth: f64,
    /// `sci_ruhp_behs` at the end of the cycle.
    behs: f64,
    /// `c_ballast_pumped` at the end of the cycle (after arbitration).
    c_ballast: f64,
    /// Which behavior won the buoyancy this cycle, by name.
    buoyancy_owner: Option<String>,
}

fn list() -> Arc<SensorList> {
    Arc::new(SensorList::embedded())
}

fn index_of(list: &SensorList, name: &str) -> usize {
    list.lookup(name)
        .unwrap_or_else(|| panic!("{name} is in the embedded list"))
        .index()
}

fn compile(text: &str, list: &SensorList) -> Arc<Program> {
    let checked = gloc::check(&gloc::parse(text), list, &CheckOptions::default());
    match checked.program {
        Some(program) => program,
        None => panic!("script does not check: {:?}", checked.diagnostics),
    }
}

/// Flies `mission` (with `script` if any) for at most `max_cycles` cycles and
/// records every cycle.
fn fly(mission: &str, script: Option<&str>, max_cycles: u64) -> (Simulation, Vec<Cycle>) {
    let list = list();
    let mission = Mission::parse("test.mi", mission);
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    let program = script.map(|text| compile(text, &list));
    let mut sim = Simulation::new(&mission, list.clone(), program, &ideal_clock()).expect("starts");
    let depth = list.lookup("m_depth").expect("m_depth");
    let behs = list.lookup("sci_ruhp_behs").expect("sci_ruhp_behs");
    let c_ballast = list.lookup("c_ballast_pumped").expect("c_ballast_pumped");
    let mut cycles = Vec::new();
    for _ in 0..max_cycles {
        if !sim.step_cycle() {
            break;
        }
        let name = |index: usize| sim.behaviors()[index].name.clone();
        cycles.push(Cycle {
            events: sim
                .events()
                .iter()
                .map(|event| (name(event.behavior), event.kind))
                .collect(),
            depth: sim.sensor(depth).expect("m_depth"),
            behs: sim.sensor(behs).expect("sci_ruhp_behs"),
            c_ballast: sim.sensor(c_ballast).expect("c_ballast_pumped"),
            buoyancy_owner: sim.commands().buoyancy.map(|(_, owner)| name(owner)),
        });
    }
    (sim, cycles)
}

/// The cycles in which `behavior` had an event of `kind`'s variant.
fn cycles_with(cycles: &[Cycle], behavior: &str, kind: fn(&EventKind) -> bool) -> Vec<usize> {
    cycles
        .iter()
        .enumerate()
        .filter(|(_, cycle)| {
            cycle
                .events
                .iter()
                .any(|(name, event)| name == behavior && kind(event))
        })
        .map(|(at, _)| at)
        .collect()
}

fn started(event: &EventKind) -> bool {
    matches!(event, EventKind::Started)
}

fn completed(event: &EventKind) -> bool {
    matches!(event, EventKind::Completed)
}

/// A surface behavior with `start_when` CODE above a set_heading that
/// commands the heading (and nothing else) every cycle.
fn surface_over_set_heading(code: u32) -> String {
    format!(
        "behavior: surface\n  b_arg: start_when(enum) {code}\n  b_arg: end_action(enum) 0\n  b_arg: gps_wait_time(s) 60\n\
         behavior: set_heading\n  b_arg: use_heading(enum) 1\n  b_arg: heading_value(rad) 1.0\n"
    )
}

#[test]
fn pitch_idle_and_updown_idle_ignore_a_commanded_heading() {
    // Codes 2 (pitch idle) and 4 (up/down idle) look only at their own
    // actuator: set_heading below commands the heading, not pitch or
    // buoyancy, so both hold at cycle 0. The glider starts at the surface
    // (0 m ≤ u_reqd_depth_at_surface 2 m), so the surface behavior counts as
    // surfaced at once (t = 0 s) and is done when t − 0 ≥ gps_wait_time 60 s:
    // cycle 60 / 4 = 15. end_action 0 ends the mission there, completed.
    for code in [2, 4] {
        let (sim, cycles) = fly(&surface_over_set_heading(code), None, 100);
        assert_eq!(
            cycles_with(&cycles, "surface", started),
            vec![0],
            "code {code}"
        );
        let end = sim.end().expect("the mission ended");
        assert_eq!(end.reason, EndReason::Completed, "code {code}");
        assert_eq!((end.cycle, end.time), (15, 60.0), "code {code}");
    }
    // Code 3 (heading idle) never holds: the heading is commanded every cycle.
    let (sim, cycles) = fly(&surface_over_set_heading(3), None, 100);
    assert!(cycles_with(&cycles, "surface", started).is_empty());
    assert_eq!(sim.end(), None);
}

#[test]
fn pitch_idle_starts_a_behavior_the_cycle_the_yo_below_completes() {
    // start_when 2 on surface above a yo of two half cycles (end_action 0).
    // While active the yo commands pitch every cycle: each leg commands until
    // it is done, and at the dive's turn (10 m) the climb leg (to 3 m) is not
    // yet done, so it commands in the same cycle. In the cycle the climb
    // reaches 3 m the yo completes without commanding, nothing below surface
    // commands pitch, and surface starts in that very cycle — never earlier.
    let mission = "behavior: surface\n  b_arg: start_when(enum) 2\n  b_arg: end_action(enum) 0\n  b_arg: gps_wait_time(s) 60\n\
                   behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: num_half_cycles_to_do(nodim) 2\n  b_arg: d_target_depth(m) 10\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n  b_arg: end_action(enum) 0\n";
    let (sim, cycles) = fly(mission, None, 2000);
    let yo_done = cycles_with(&cycles, "yo", completed);
    assert_eq!(yo_done.len(), 1, "{yo_done:?}");
    assert_eq!(cycles_with(&cycles, "surface", started), yo_done);
    // The yo's climb leg ended at 3 m or shallower.
    assert!(cycles[yo_done[0]].depth <= 3.0);
    // Then surface climbs the last metre and waits its 60 s: completed.
    let end = sim.end().expect("the mission ended");
    assert_eq!(end.reason, EndReason::Completed);
    assert!(end.time >= yo_done[0] as f64 * 4.0 + 60.0, "{end:?}");
}

/// A yo (diving for ever between 12 and 3 m) with `stop_when` CODE above a
/// prepare_to_dive that holds the glider at the surface until the GPS fix.
fn yo_over_prepare_to_dive(stop_when: u32) -> String {
    format!(
        "behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: stop_when(enum) {stop_when}\n  b_arg: end_action(enum) 0\n  b_arg: d_target_depth(m) 12\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n\
         behavior: prepare_to_dive\n  b_arg: start_when(enum) 0\n  b_arg: wait_time(s) 720\n"
    )
}

#[test]
fn updown_idle_stops_a_behavior_when_the_one_below_stops_pumping() {
    // prepare_to_dive starts at t = 0 and commands buoyancy until
    // t − 0 ≥ min(wait_time 720 s, GPS fix 106 s) = 106 s: cycles 0–26
    // (26 × 4 = 104 s). In cycle 27 it is done and commands nothing, so the yo's stop_when 4
    // (up/down idle below it) first holds in cycle 27: the yo completes
    // there (end_action 0: for good). Until then the yo, being higher, wins
    // the buoyancy.
    let (_, cycles) = fly(&yo_over_prepare_to_dive(4), None, 100);
    assert_eq!(cycles_with(&cycles, "yo", started), vec![0]);
    assert_eq!(cycles_with(&cycles, "prepare_to_dive", completed), vec![27]);
    assert_eq!(cycles_with(&cycles, "yo", completed), vec![27]);
    assert!(cycles[..27]
        .iter()
        .all(|cycle| cycle.buoyancy_owner.as_deref() == Some("yo")));
    assert!(cycles[27..]
        .iter()
        .all(|cycle| cycle.buoyancy_owner.is_none()));

    // stop_when 5 (never): the same idle stack does not stop the yo, which
    // has no end of its own (num_half_cycles_to_do −1) and flies on.
    let (_, cycles) = fly(&yo_over_prepare_to_dive(5), None, 100);
    assert_eq!(cycles_with(&cycles, "prepare_to_dive", completed), vec![27]);
    assert!(cycles_with(&cycles, "yo", completed).is_empty());
    assert!(cycles[27..]
        .iter()
        .all(|cycle| cycle.buoyancy_owner.as_deref() == Some("yo")));
}

/// A surface with `start_when` CODE (end_action 0) above a yo of two half
/// cycles that ends with end_action 0, leaving the stack idle.
fn surface_over_a_finite_yo(code: u32) -> String {
    format!(
        "behavior: surface\n  b_arg: start_when(enum) {code}\n  b_arg: end_action(enum) 0\n  b_arg: gps_wait_time(s) 60\n\
         behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: num_half_cycles_to_do(nodim) 2\n  b_arg: d_target_depth(m) 10\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n  b_arg: end_action(enum) 0\n"
    )
}

#[test]
fn never_means_never_even_on_an_idle_stack() {
    // With start_when 1 the surface starts once the yo is done and ends the
    // mission (the control case)...
    let (sim, _) = fly(&surface_over_a_finite_yo(1), None, 2000);
    assert_eq!(sim.end().map(|end| end.reason), Some(EndReason::Completed));
    // ...with start_when 5 it never starts: the glider drifts with the
    // stack idle until the run's limit.
    let (sim, cycles) = fly(&surface_over_a_finite_yo(5), None, 2000);
    assert_eq!(cycles.len(), 2000);
    assert!(cycles_with(&cycles, "surface", started).is_empty());
    assert_eq!(cycles_with(&cycles, "yo", completed).len(), 1);
    assert_eq!(sim.end(), None);
}

/// A periodic surface (`start_when` CODE, when_secs 400 s, end_action 2:
/// resume) above a yo between 20 and 5 m that never ends.
fn periodic_surface(code: u32) -> String {
    format!(
        "behavior: surface\n  b_arg: start_when(enum) {code}\n  b_arg: when_secs(s) 400\n  b_arg: end_action(enum) 2\n  b_arg: gps_wait_time(s) 40\n\
         behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: d_target_depth(m) 20\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 5\n  b_arg: end_action(enum) 2\n"
    )
}

#[test]
fn when_secs_after_the_last_end_counts_from_the_end() {
    // Code 6: when_secs after the behavior's last end, the mission start
    // (t = 0) before its first end. First start: the first t ≥ 0 + 400 s,
    // cycle 400 / 4 = 100. It climbs from the yo's depth (at most ~21 m,
    // 0.15 m/s: under 40 cycles) to 2 m, waits 40 s and completes at a
    // cycle E; it starts again at the first t ≥ 4E + 400, cycle E + 100.
    let (_, cycles) = fly(&periodic_surface(6), None, 400);
    let starts = cycles_with(&cycles, "surface", started);
    let ends = cycles_with(&cycles, "surface", completed);
    assert_eq!(starts[0], 100, "{starts:?}");
    // Climb under 40 cycles, 10 cycles of GPS wait: 110 < E < 150.
    assert!((110..150).contains(&ends[0]), "{ends:?}");
    assert_eq!(starts[1], ends[0] + 100, "starts {starts:?}, ends {ends:?}");

    // Code 9 counts from the last start instead: 100, then 200 (the first
    // surfacing is over by then, E < 150).
    let (_, cycles) = fly(&periodic_surface(9), None, 400);
    let starts = cycles_with(&cycles, "surface", started);
    assert_eq!(&starts[..2], &[100, 200]);
}

#[test]
fn abend_overtime_aborts_at_the_first_cycle_past_the_limit() {
    // overtime 600 s: abend aborts when t > 600. Cycle 150 runs at t = 600
    // (not past it); cycle 151 at t = 604 is the first past it. The yo
    // turns at 20 m (+ ~1 m overshoot), far above the overdepth limit of
    // 30 m, so nothing else aborts first. After the abort the glider
    // climbs and the run ends at the surface.
    let mission = "behavior: abend\n  b_arg: overdepth(m) 30\n  b_arg: overdepth_sample_time(s) 4\n  b_arg: overtime(s) 600\n  b_arg: samedepth_for(s) -1\n\
                   behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: d_target_depth(m) 20\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 5\n";
    let (sim, cycles) = fly(mission, None, 2000);
    let end = sim.end().expect("aborted");
    assert_eq!(end.reason, EndReason::Aborted(AbortReason::Overtime));
    assert_eq!((end.cycle, end.time), (151, 604.0));
    assert!(sim.is_finished());
    assert!(sim.depth() <= 0.3, "ended at {} m", sim.depth());
    // The run went on only to surface: under 22 m at 0.15 m/s, < 40 cycles.
    assert!(cycles.len() < 151 + 40, "{} cycles", cycles.len());
}

/// Hook missions: abend, the script, the hook (climb default 3 m, dive
/// default DIVE m) and, if `with_yo`, a yo between 25 and 2 m below it.
fn hook_mission(dive_default: f64, with_yo: bool) -> String {
    let mut text = format!(
        "behavior: abend\n  b_arg: overdepth(m) 35\n  b_arg: overdepth_sample_time(s) 4\n  b_arg: samedepth_for(s) -1\n\
         behavior: gloc\n\
         behavior: hook\n  b_arg: climb_target_depth(m) 3\n  b_arg: dive_target_depth(m) {dive_default}\n"
    );
    if with_yo {
        text.push_str(
            "behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: d_target_depth(m) 25\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 2\n",
        );
    }
    text
}

/// Waits (yielding) until m_depth > 15 m, then stores `flags` to
/// sci_ruhp_behs (and `climb_depth` to sci_ruhp_climb_depth when given) and
/// halts.
fn set_flags_past_15_m(list: &SensorList, flags: i64, climb_depth: Option<f64>) -> String {
    let depth = index_of(list, "m_depth");
    let behs = index_of(list, "sci_ruhp_behs");
    let climb = index_of(list, "sci_ruhp_climb_depth");
    let mut act = Vec::new();
    if let Some(value) = climb_depth {
        act.push(format!("loadd {value:.1},r3"));
        act.push(format!("stores r3,{climb}"));
    }
    act.push(format!("loadi {flags},r4"));
    act.push(format!("stores r4,{behs}"));
    act.push("halt".to_string());
    let mut body = vec![
        "label 0".to_string(),
        format!("loads {depth},r0"),
        "loadd 15.0,r1".to_string(),
        "cmpgt r0,r1,r2".to_string(),
        "cbr r2,1,2".to_string(),
        "label 1".to_string(),
    ];
    body.extend(act);
    body.extend(["label 2", "yield", "jumpi 0"].map(str::to_string));
    format!(
        "nregs 5\nnblbs 3\nninstr {}\n{}\n",
        body.len(),
        body.join("\n")
    )
}

/// The first cycle at or after `from` for which `test` holds.
fn first(cycles: &[Cycle], from: usize, test: impl Fn(&Cycle) -> bool) -> usize {
    (from..cycles.len())
        .find(|&at| test(&cycles[at]))
        .unwrap_or_else(|| panic!("no such cycle after {from}"))
}

#[test]
fn hook_dive_without_a_dive_depth_goes_to_its_b_arg() {
    // The script stores 64 in cycle 0 (after the hook, which sits below it,
    // has stepped) and never stores again; sci_ruhp_dive_depth stays 0, not
    // positive, so the hook dives to its b_arg dive_target_depth: 12 m here
    // (not the built-in 20). It reads the flag from cycle 1 on and commands
    // the dive (bpump −260 cc) until the first cycle whose depth is ≥ 12 m;
    // in that cycle it clears bit 64 and commands nothing.
    let list = list();
    let behs = index_of(&list, "sci_ruhp_behs");
    let script = format!(
        "nregs 1\nnblbs 1\nninstr 5\nloadi 64,r0\nstores r0,{behs}\nlabel 0\nyield\njumpi 0\n"
    );
    let (sim, cycles) = fly(&hook_mission(12.0, false), Some(&script), 400);
    let dive_depth = list.lookup("sci_ruhp_dive_depth").expect("sensor");
    assert_eq!(sim.sensor(dive_depth), Some(0.0));
    let reached = first(&cycles, 1, |cycle| cycle.depth >= 12.0);
    assert!(cycles[..reached].iter().all(|cycle| cycle.behs == 64.0));
    assert_eq!(cycles[reached].behs, 0.0);
    assert!(cycles[reached - 1].depth < 12.0);
    for cycle in &cycles[1..reached] {
        assert_eq!(cycle.buoyancy_owner.as_deref(), Some("hook"), "{cycle:?}");
        assert_eq!(cycle.c_ballast, -PUBLISHED_BPUMP, "{cycle:?}");
    }
    assert_eq!(cycles[reached].buoyancy_owner, None);
}

#[test]
fn hook_climb_with_a_climb_depth_set_goes_to_that_depth() {
    // The yo dives toward 25 m; at the first cycle S deeper than 15 m the
    // script stores sci_ruhp_climb_depth 8 (positive: it overrides the
    // b_arg climb_target_depth 3) and bit 128. The hook reads them from
    // S + 1, commands the climb (+260 cc) over the yo below it, and in the
    // first cycle C whose depth is ≤ 8 m clears bit 128 and commands
    // nothing: the yo's dive wins again.
    let list = list();
    let script = set_flags_past_15_m(&list, 128, Some(8.0));
    let (_, cycles) = fly(&hook_mission(20.0, true), Some(&script), 400);
    let set = first(&cycles, 0, |cycle| cycle.depth > 15.0);
    assert!(cycles[set..]
        .iter()
        .take(2)
        .all(|cycle| cycle.behs == 128.0));
    let cleared = first(&cycles, set + 1, |cycle| cycle.depth <= 8.0);
    assert!(cycles[set..cleared].iter().all(|cycle| cycle.behs == 128.0));
    assert_eq!(cycles[cleared].behs, 0.0);
    assert!(cycles[cleared - 1].depth > 8.0);
    for cycle in &cycles[set + 1..cleared] {
        assert_eq!(cycle.buoyancy_owner.as_deref(), Some("hook"), "{cycle:?}");
        assert_eq!(cycle.c_ballast, PUBLISHED_BPUMP, "{cycle:?}");
    }
    assert_eq!(cycles[cleared].buoyancy_owner.as_deref(), Some("yo"));
    assert_eq!(cycles[cleared].c_ballast, -PUBLISHED_BPUMP);
}

#[test]
fn hook_with_both_bits_climbs_first_then_dives() {
    // Both bits (192) set at the first cycle S deeper than 15 m: the climb
    // wins (the safe side) to the b_arg 3 m. In the first cycle C1 at ≤ 3 m
    // the hook clears only bit 128 (leaving 64) and commands nothing; from
    // C1 + 1 bit 64 runs the dive to the b_arg 20 m, and in the first cycle
    // C2 at ≥ 20 m the hook clears bit 64 (0).
    let list = list();
    let script = set_flags_past_15_m(&list, 192, None);
    let (_, cycles) = fly(&hook_mission(20.0, true), Some(&script), 600);
    let set = first(&cycles, 0, |cycle| cycle.depth > 15.0);
    let climbed = first(&cycles, set + 1, |cycle| cycle.depth <= 3.0);
    assert!(cycles[set..climbed].iter().all(|cycle| cycle.behs == 192.0));
    assert_eq!(cycles[climbed].behs, 64.0);
    for cycle in &cycles[set + 1..climbed] {
        assert_eq!(cycle.buoyancy_owner.as_deref(), Some("hook"), "{cycle:?}");
        assert_eq!(cycle.c_ballast, PUBLISHED_BPUMP, "{cycle:?}");
    }
    let dived = first(&cycles, climbed + 1, |cycle| cycle.depth >= 20.0);
    assert!(cycles[climbed..dived]
        .iter()
        .all(|cycle| cycle.behs == 64.0));
    assert_eq!(cycles[dived].behs, 0.0);
    for cycle in &cycles[climbed + 1..dived] {
        assert_eq!(cycle.buoyancy_owner.as_deref(), Some("hook"), "{cycle:?}");
        assert_eq!(cycle.c_ballast, -PUBLISHED_BPUMP, "{cycle:?}");
    }
}

#[test]
fn script_stores_to_command_sensors_do_not_beat_abend() {
    // The script asks the hook for a dive to 100 m and, every cycle, stores
    // a full dive (−1000 cc, −0.4538 rad) straight to c_ballast_pumped and
    // c_pitch. Those are published after arbitration (docs/simulator.md), so
    // the stores are overwritten each cycle: the hook's −260 cc is what flies.
    // abend (overdepth 35 m, checked every 4 s) aborts at the first cycle
    // deeper than 35 m; then no script runs, the abort commands the pump's
    // full volume out (+230 cc, `FlightParams::pump_max`) and the run ends
    // at the surface.
    let list = list();
    let index = |name| index_of(&list, name);
    let script = format!(
        "nregs 4\nnblbs 1\nninstr 11\nlabel 0\nloadd 100.0,r0\nstores r0,{dive}\nloadi 64,r1\nstores r1,{behs}\n\
         loadd -1000.0,r2\nstores r2,{ballast}\nloadd -0.4538,r3\nstores r3,{pitch}\nyield\njumpi 0\n",
        dive = index("sci_ruhp_dive_depth"),
        behs = index("sci_ruhp_behs"),
        ballast = index("c_ballast_pumped"),
        pitch = index("c_pitch"),
    );
    let (sim, cycles) = fly(&hook_mission(20.0, false), Some(&script), 2000);
    let end = sim.end().expect("aborted");
    assert_eq!(end.reason, EndReason::Aborted(AbortReason::Overdepth));
    let abort = end.cycle as usize;
    assert_eq!(abort, first(&cycles, 0, |cycle| cycle.depth > 35.0));
    // Before the abort the hook's command is what was published.
    assert!(cycles[1..abort]
        .iter()
        .all(|cycle| cycle.c_ballast == -PUBLISHED_BPUMP));
    // From the abort on, the abort's full pump-out, whatever the script stored.
    assert!(cycles[abort..].iter().all(|cycle| cycle.c_ballast == 230.0));
    assert!(sim.is_finished());
    assert!(sim.depth() <= 0.3, "ended at {} m", sim.depth());
    // abend checks every cycle (0.6 m of travel), then the turn overshoots ~1 m.
    let (_, deepest) = sim.depth_range();
    assert!((35.0..37.0).contains(&deepest), "deepest {deepest}");
}

#[test]
fn the_hook_is_in_the_stack_of_these_missions() {
    // Guard for the tests above: the mission text builds the stack they assume.
    let list = list();
    let mission = Mission::parse("hook.mi", hook_mission(20.0, true));
    let sim = Simulation::new(
        &mission,
        list.clone(),
        Some(compile(&set_flags_past_15_m(&list, 128, None), &list)),
        &ideal_clock(),
    )
    .expect("starts");
    let kinds: Vec<BehaviorKind> = sim.behaviors().iter().map(|b| b.kind).collect();
    assert_eq!(
        kinds,
        vec![
            BehaviorKind::Abend,
            BehaviorKind::Gloc,
            BehaviorKind::Hook,
            BehaviorKind::Yo
        ]
    );
}

#[test]
fn a_yo_without_a_dive_target_flies_the_active_masterdatas_default() {
    // The release-layout fixture's yo section gives d_target_depth 42 (the embedded
    // release table 12): the first dive turns near 42 m with it, near 12 m without.
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/fixtures/sensors/release-layout.masterdata"),
    )
    .expect("fixture");
    let (masterdata, _) =
        gloc_engine::sensors::parse_masterdata(&text, gloc_engine::sensors::SensorOrder::FileOrder);
    let mission_text = "sensor: s_water_depth_avg(m) 100\nbehavior: abend\n  b_arg: overdepth(m) 100\nbehavior: yo\n  b_arg: num_half_cycles_to_do(nodim) 2\n  b_arg: d_target_altitude(m) -1\n";
    let deepest = |options: &gloc_mission::LoadOptions| {
        let mission = Mission::load_text(
            std::path::Path::new("yo.mi"),
            mission_text.to_string(),
            options,
            &mut |_: &std::path::Path| -> std::io::Result<String> {
                Err(std::io::ErrorKind::NotFound.into())
            },
        );
        assert!(!mission.has_errors(), "{}", mission.render_plain());
        let list = list();
        let depth = list.lookup("m_depth").expect("m_depth");
        let mut sim =
            Simulation::new(&mission, list.clone(), None, &ideal_clock()).expect("starts");
        let mut deepest: f64 = 0.0;
        for _ in 0..2000 {
            if !sim.step_cycle() {
                break;
            }
            deepest = deepest.max(sim.sensor(depth).expect("m_depth"));
        }
        deepest
    };
    let from_masterdata = deepest(&gloc_mission::LoadOptions {
        table: Some(gloc_mission::behaviors::BehaviorTable::for_sensors(
            &masterdata,
        )),
        ..gloc_mission::LoadOptions::default()
    });
    let embedded = deepest(&gloc_mission::LoadOptions::default());
    // A turn overshoots its target by about a metre (docs/simulator.md).
    assert!((42.0..45.0).contains(&from_masterdata), "{from_masterdata}");
    assert!((12.0..15.0).contains(&embedded), "{embedded}");
}

/// A script that stores `heading` to sci_ruhp_heading and `flags` to
/// sci_ruhp_behs in its first cycle, then only yields (by name: GLOC takes names).
fn request_heading(heading: &str, flags: i64) -> String {
    format!(
        "nregs 2\nnblbs 1\nninstr 7\nloadd {heading},r0\nstores r0,sci_ruhp_heading\nloadi {flags},r1\nstores r1,sci_ruhp_behs\nlabel 0\nyield\njumpi 0\n"
    )
}

#[test]
fn hook_bit_32_steers_to_sci_ruhp_heading() {
    // East is π/2 rad clockwise from north. The script writes in cycle 0, the
    // hook (below it) reads the request from cycle 1 on and commands that
    // heading every cycle while the bit stays set; the yo below flies the
    // vertical, so the glider makes way east: m_x_lmc (east) grows, m_y_lmc
    // (north) stays small beside it (the fin's roll-bias zig-zag is about zero
    // per leg).
    let list = list();
    let c_heading = list.lookup("c_heading").expect("c_heading");
    let x = list.lookup("m_x_lmc").expect("m_x_lmc");
    let y = list.lookup("m_y_lmc").expect("m_y_lmc");
    let script = request_heading("1.5707963267948966", 32);
    let mission = hook_mission(12.0, true);
    let parsed = Mission::parse("test.mi", &mission);
    let program = compile(&script, &list);
    let mut sim =
        Simulation::new(&parsed, list.clone(), Some(program), &ideal_clock()).expect("starts");
    let mut headings = Vec::new();
    for _ in 0..400 {
        assert!(sim.step_cycle());
        headings.push(sim.sensor(c_heading).expect("c_heading"));
        let owner = sim
            .commands()
            .heading
            .map(|(_, owner)| sim.behaviors()[owner].name.clone());
        assert_eq!(owner.as_deref(), (headings.len() > 1).then_some("hook"));
    }
    assert!(
        // c_heading publishes the command at the next cycle's start.
        headings[2..]
            .iter()
            .all(|heading| (heading - std::f64::consts::FRAC_PI_2).abs() < 1e-12),
        "{:?}",
        &headings[..5]
    );
    let (east, north) = (sim.sensor(x).expect("x"), sim.sensor(y).expect("y"));
    // 400 cycles of 4 s at a horizontal speed of a few tenths of a m/s.
    assert!(east > 100.0, "east {east} m");
    assert!(
        north.abs() < 0.2 * east,
        "north {north} m against east {east} m"
    );
}

#[test]
fn hook_heading_request_wraps_and_a_non_number_commands_nothing() {
    // −π/2 is west, 3π/2 after wrapping into [0, 2π); an infinite heading
    // (1e308 + 1e308) commands no heading.
    let list = list();
    let c_heading = list.lookup("c_heading").expect("c_heading");
    let (sim, _) = fly(
        &hook_mission(12.0, true),
        Some(&request_heading("-1.5707963267948966", 32)),
        10,
    );
    let west = sim.sensor(c_heading).expect("c_heading");
    assert!(
        (west - 3.0 * std::f64::consts::FRAC_PI_2).abs() < 1e-12,
        "{west}"
    );
    let infinite = "nregs 2\nnblbs 1\nninstr 8\nloadd 1e308,r0\nadd r0,r0,r0\nstores r0,sci_ruhp_heading\nloadi 32,r1\nstores r1,sci_ruhp_behs\nlabel 0\nyield\njumpi 0\n";
    let (sim, _) = fly(&hook_mission(12.0, true), Some(infinite), 10);
    assert_eq!(sim.commands().heading, None);
}
