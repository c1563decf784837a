//! Whole-mission scenarios, checked on the run's own CSV log.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::SensorList;
use gloc_sim::behaviors::{AbortReason, BehaviorKind};
use gloc_sim::log::{default_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::{default_mission, EndReason, Mission, SimConfig, Simulation};

const FIG2: &str = include_str!("../../examples/fig2.gloc");

fn compile(text: &str, list: &SensorList) -> Arc<Program> {
    let checked = gloc::check(&gloc::parse(text), list, &CheckOptions::default());
    match checked.program {
        Some(program) => program,
        None => panic!("script does not check: {:?}", checked.diagnostics),
    }
}

/// The log of a run, parsed back: column names and rows.
struct Log {
    names: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Log {
    fn column(&self, name: &str) -> Vec<f64> {
        let at = self
            .names
            .iter()
            .position(|known| known == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.names));
        self.rows.iter().map(|row| row[at]).collect()
    }
}

/// Runs a mission with a script until it finishes (or `max_cycles`), logging
/// the default sensor set to CSV in memory, and parses the log back.
fn run_logged(mission: &Mission, script: &str, max_cycles: u64) -> (Simulation, Log) {
    let list = Arc::new(SensorList::embedded());
    let program = compile(script, &list);
    let mut sim = Simulation::new(mission, list.clone(), Some(program), &SimConfig::default())
        .expect("mission starts");
    let columns = default_columns(&list, &[]);
    let header = DbaHeader {
        filename: "test".to_string(),
        mission_name: mission.name.clone(),
        fileopen_time: "now".to_string(),
    };
    let mut writer =
        LogWriter::new(Vec::new(), LogFormat::Csv, columns, &list, &header).expect("header");
    for _ in 0..max_cycles {
        if !sim.step_cycle() {
            break;
        }
        // As `gloc run --log` does: one row at the end of each cycle, with the
        // sensors measured at its start and what was written during it.
        writer.write_row(sim.sensors()).expect("row");
    }
    let text = String::from_utf8(writer.finish().expect("flush")).expect("utf8");
    let mut lines = text.lines();
    let names = lines
        .next()
        .expect("header line")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|line| {
            line.split(',')
                .map(|cell| cell.parse::<f64>().expect("number"))
                .collect()
        })
        .collect();
    (sim, Log { names, rows })
}

/// Depths at which the vertical direction turns: alternately a deepest point
/// (dive turn) and a shallowest point (climb turn), starting with a dive.
fn turns(depths: &[f64]) -> Vec<f64> {
    let mut turns = Vec::new();
    let mut diving = true;
    let mut extreme = depths[0];
    for &depth in depths {
        if diving {
            if depth > extreme {
                extreme = depth;
            } else if depth < extreme - 0.5 {
                turns.push(extreme);
                diving = false;
                extreme = depth;
            }
        } else if depth < extreme {
            extreme = depth;
        } else if depth > extreme + 0.5 {
            turns.push(extreme);
            diving = true;
            extreme = depth;
        }
    }
    turns
}

#[test]
fn fig2_scenario_on_the_default_mission() {
    let (sim, log) = run_logged(&default_mission(), FIG2, 5000);
    let depths = log.column("m_depth");
    let turns = turns(&depths);
    // Reasoning (dive 0.16, climb 0.13 m/s, 4.5 s cycles, the pump turning a
    // cycle after the behavior, servoed turns overshooting 0.7–1.9 m at the
    // bottom and 0.24–0.86 m at the top, flight.rs): the script sees
    // m_depth > 15 first at 15.0–15.7 m and sets bit 128; the hook below it
    // reads the flag the next cycle (+0.7 m), the pump turns a cycle later
    // (+0.7 m) and overshoots 1.6 m: 18–18.7 m. Climbing, the script clears
    // the flag below 5 m (4.4–5 m), the yo's dive_to takes over a cycle later
    // (−0.6 m), the pump a cycle after (−0.6 m), overshoot 1.2 m: 2–2.6 m.
    assert!(turns.len() >= 7, "turns: {turns:?}");
    assert!(
        (15.0..19.0).contains(&turns[0]),
        "first dive turns at {}",
        turns[0]
    );
    assert!(
        (2.0..5.0).contains(&turns[1]),
        "the climb turns at {}",
        turns[1]
    );
    // Then the yo resumes: 25 m plus up to a cycle's travel past the target
    // (0.72 m at 0.16 m/s and 4.5 s), then the turn: the servoed pitch reverses
    // at once, the pump a cycle later, and the glider, heavy until the pump is
    // past neutral (7.9 s at 34.6 cc/s, 3.4 s after the waiting cycle), sinks on
    // for 0.5–1.9 m (flight.rs: a servoed turn overshoots 0.70–1.87 m, less
    // here as the pitch leads): 25.5–28.5 m. Climbing to 2 m:
    // less up to a cycle's travel, the turn's cycle (0.59 m each at 0.13 m/s)
    // and a servoed top turn's 0.24–0.86 m (flight.rs), clipped at the surface:
    // 0–1.4 m.
    for dive in [turns[2], turns[4], turns[6]] {
        assert!(
            (25.5..28.5).contains(&dive),
            "yo dive turns at {dive} ({turns:?})"
        );
    }
    for climb in [turns[3], turns[5]] {
        assert!(
            (0.0..1.4).contains(&climb),
            "yo climb turns at {climb} ({turns:?})"
        );
    }
    // The script's flag, in the log: 128 in the row of the first cycle deeper than 15 m.
    let flags = log.column("sci_ruhp_behs");
    let first_set = flags
        .iter()
        .position(|&flag| flag == 128.0)
        .expect("flag set");
    assert!(depths[first_set] > 15.0 && depths[first_set - 1] <= 15.0);
    // And 0 again in the row of the first later cycle shallower than 5 m.
    let cleared = first_set
        + flags[first_set..]
            .iter()
            .position(|&flag| flag == 0.0)
            .expect("cleared");
    assert!(depths[cleared] < 5.0 && depths[cleared - 1] >= 5.0);
    // The yo did its six half cycles, the stack went idle, surface ended it.
    let end = sim.end().expect("mission ended");
    assert_eq!(end.reason, EndReason::Completed);
    assert!(sim.is_finished());
    assert!(sim.depth() < 0.5);
    // Energy is used and published.
    let charge = log.column("m_coulomb_amphr_total");
    assert!(charge.windows(2).all(|pair| pair[1] >= pair[0]));
    assert!(*charge.last().expect("rows") > 0.0);
}

/// Drives the hook to 100 m every cycle.
const DIVE_TO_100: &str = "nregs 2\nnblbs 1\nninstr 7\nlabel 0\nloadd 100.0,r0\nstores r0,1385\nloadi 64,r1\nstores r1,1387\nyield\njumpi 0\n";

#[test]
fn a_script_cannot_override_abend() {
    let (sim, log) = run_logged(&default_mission(), DIVE_TO_100, 5000);
    let end = sim.end().expect("mission ended");
    assert_eq!(end.reason, EndReason::Aborted(AbortReason::Overdepth));
    let deepest = log.column("m_depth").into_iter().fold(0.0, f64::max);
    // abend checks every 4 s (0.6 m of travel), then the turn overshoots ~1 m:
    // the glider never passes about 31.6 m.
    assert!(deepest > 30.0 && deepest < 33.0, "deepest {deepest}");
    // The abort surfaced the glider and ended the run.
    assert!(sim.is_finished());
    assert!(sim.depth() <= 0.3);
    // The script kept asking for 100 m until the abort.
    let flags = log.column("sci_ruhp_behs");
    assert_eq!(flags[flags.len() / 2], 64.0);
}

#[test]
fn hook_with_flags_clear_commands_nothing() {
    // A script that never touches the hook: sci_ruhp_behs stays 0, so the
    // hook (active every cycle, below the script and above the yo) must
    // command nothing, and the yo below it wins buoyancy and pitch in every
    // cycle until it completes; then the stack is idle and surface (above)
    // ends the mission.
    let idle = "nregs 0\nnblbs 1\nninstr 3\nlabel 0\nyield\njumpi 0\n";
    let list = Arc::new(SensorList::embedded());
    let behs = list.lookup("sci_ruhp_behs").expect("hook sensor");
    let mut sim = Simulation::new(
        &default_mission(),
        list.clone(),
        Some(compile(idle, &list)),
        &SimConfig::default(),
    )
    .expect("starts");
    let index_of = |kind| {
        sim.behaviors()
            .iter()
            .position(|behavior| behavior.kind == kind)
            .unwrap_or_else(|| panic!("the default mission has a {kind:?}"))
    };
    let (hook, yo, surface) = (
        index_of(BehaviorKind::Hook),
        index_of(BehaviorKind::Yo),
        index_of(BehaviorKind::Surface),
    );
    let mut depths = Vec::new();
    let mut yo_cycles = 0;
    while sim.cycle() < 5000 && sim.step_cycle() {
        depths.push(sim.depth());
        assert!(sim.behaviors()[hook].is_active(), "cycle {}", sim.cycle());
        assert_eq!(sim.sensor(behs), Some(0.0));
        let commands = sim.commands();
        let owners = [commands.buoyancy, commands.pitch].map(|winner| winner.map(|(_, at)| at));
        assert!(
            !owners.contains(&Some(hook)),
            "the hook commanded in cycle {}: {commands:?}",
            sim.cycle()
        );
        if sim.behaviors()[yo].is_active() {
            yo_cycles += 1;
            assert_eq!(owners, [Some(yo); 2], "cycle {}", sim.cycle());
        } else {
            assert!(owners
                .iter()
                .all(|owner| owner.is_none() || *owner == Some(surface)));
        }
    }
    assert!(yo_cycles > 100, "the yo flew {yo_cycles} cycles");
    let turns = turns(&depths);
    // As in fig2_scenario_on_the_default_mission: 25.5–28.5 m.
    assert!((25.5..28.5).contains(&turns[0]), "{turns:?}");
    assert_eq!(sim.end().map(|end| end.reason), Some(EndReason::Completed));
}

#[test]
fn nsb3_loads_without_errors_and_flies() {
    let mission = Mission::load(&gloc_testsupport::data("comet/missions/nsb3.mi"));
    let errors = mission.rendered();
    assert!(errors.is_empty(), "{errors:#?}");
    // nsb3.mi plus the 8 .ma files it names.
    assert_eq!(mission.sources.len(), 9);
    assert_eq!(mission.behaviors.len(), 12);
    let yo = mission
        .behaviors
        .iter()
        .find(|spec| spec.name == "yo")
        .expect("yo");
    assert_eq!(yo.arg("d_target_depth"), Some(50.0));
    assert_eq!(yo.arg("d_target_altitude"), Some(4.0));
    // It flies: in 40 m of water the yo turns on the altimeter (4 m).
    let list = Arc::new(SensorList::embedded());
    let mut sim = Simulation::new(&mission, list, None, &SimConfig::default()).expect("starts");
    let mut deepest: f64 = 0.0;
    for _ in 0..2000 {
        sim.step_cycle();
        deepest = deepest.max(sim.depth());
    }
    // Turning at 4 m of altitude (36 m) plus a cycle's travel, the turn's
    // cycle (0.72 m each) and 1.62 m ± 10% of overshoot: 37.4–39.9 m.
    assert!(deepest > 37.4 && deepest < 39.9, "deepest {deepest}");
    assert!(sim.end().is_none());
}

#[test]
fn malformed_mission_file_gives_line_and_column() {
    let folder = gloc_testsupport::scratch_dir("sim-test");
    std::fs::create_dir_all(&folder).expect("temp dir");
    let path = folder.join("bad.mi");
    std::fs::write(
        &path,
        "behavior: abend\n  b_arg: overdepth(m) 30\n  b_arg: overtime(s 60\n",
    )
    .expect("write");
    let mission = Mission::load(&path);
    let text = mission.render_plain();
    assert!(mission.has_errors());
    // `overtime(s` starts at column 10 of line 3.
    assert!(
        text.contains("bad.mi:3:10: error[S0011]: unclosed `(`")
            || text.contains("bad.mi:3:18: error[S0011]"),
        "{text}"
    );
    let error = Simulation::new(
        &mission,
        Arc::new(SensorList::embedded()),
        None,
        &SimConfig::default(),
    )
    .expect_err("refuses to fly");
    assert!(error.to_string().contains("bad.mi:3:"), "{error}");
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn runs_are_deterministic_and_snapshots_replay() {
    let list = Arc::new(SensorList::embedded());
    let program = compile(FIG2, &list);
    let config = SimConfig {
        seed: 42,
        ..SimConfig::default()
    };
    let mut first = Simulation::new(
        &default_mission(),
        list.clone(),
        Some(program.clone()),
        &config,
    )
    .expect("starts");
    for _ in 0..100 {
        first.step_cycle();
    }
    let snapshot = first.clone();
    let mut replay = snapshot.clone();
    for _ in 0..200 {
        first.step_cycle();
        replay.step_cycle();
        assert_eq!(first.sensors(), replay.sensors());
    }
    let mut other = Simulation::new(
        &default_mission(),
        list,
        Some(program),
        &SimConfig { seed: 43, ..config },
    )
    .expect("starts");
    for _ in 0..300 {
        other.step_cycle();
    }
    // Another seed changes the CTD noise and the cycles' spread (so the
    // clock and the flight), not their mean.
    let temp = first
        .sensor_list()
        .lookup("sci_water_temp")
        .expect("sensor");
    assert_ne!(first.sensor(temp), other.sensor(temp));
    assert_ne!(first.time(), other.time());
    let mean = |sim: &Simulation| sim.time() / sim.cycle() as f64;
    assert!((mean(&first) - mean(&other)).abs() < 0.05);
}

#[test]
fn phases_let_a_debugger_step_the_script() {
    let list = Arc::new(SensorList::embedded());
    let program = compile(FIG2, &list);
    let mut sim = Simulation::new(
        &default_mission(),
        list.clone(),
        Some(program),
        &SimConfig::default(),
    )
    .expect("starts");
    let behs = list.lookup("sci_ruhp_behs").expect("hook sensor");
    // Fly to the first cycle where the script will act.
    loop {
        assert!(sim.begin_cycle());
        if sim.depth() > 15.0 {
            break;
        }
        sim.finish_cycle();
    }
    let cycle = sim.cycle();
    assert_eq!(sim.sensor(behs), Some(0.0));
    // Step the script one instruction at a time up to its yield.
    let mut steps = 0;
    while sim.script_step().is_none() {
        steps += 1;
        assert!(steps < 100);
    }
    // The last cycle ended at the `yield` under label 4, so this share starts
    // with its `jumpi 0`, then loads, loadd, cmpgt, cbr, loadi, stores, jumpi,
    // loads, loadd, cmplt, cbr: 12 instructions before the yield.
    assert_eq!(steps, 12);
    assert_eq!(sim.sensor(behs), Some(128.0));
    assert_eq!(sim.stored(), &[behs]);
    sim.finish_cycle();
    assert_eq!(sim.cycle(), cycle + 1);
    // The active behaviors are named, highest first.
    let active: Vec<&str> = sim.active_behaviors().collect();
    assert_eq!(active, vec!["abend", "gloc", "hook", "yo"]);
}

#[test]
fn the_embedded_mission_is_examples_fig2() {
    assert_eq!(
        gloc_sim::DEFAULT_MISSION,
        include_str!("../../examples/fig2.mi")
    );
}

const IDLE: &str = "nregs 0\nnblbs 1\nninstr 3\nlabel 0\nyield\njumpi 0\n";

#[test]
fn surface_every_when_secs_after_its_start() {
    // start_when 9: surface when_secs (20 min) after the behavior last started
    // (the mission start at first); end_action 2 resumes the yo.
    let mission = Mission::parse(
        "periodic.mi",
        "behavior: abend\n  b_arg: overdepth(m) 30\n  b_arg: samedepth_for(s) -1\n\
         behavior: surface\n  b_arg: start_when(enum) 9\n  b_arg: when_secs(s) 1200\n  b_arg: end_action(enum) 2\n  b_arg: gps_wait_time(s) 120\n\
         behavior: yo\n  b_arg: d_target_depth(m) 20\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 4\n",
    );
    let (sim, log) = run_logged(&mission, IDLE, 1200);
    assert!(sim.end().is_none());
    let depths = log.column("m_depth");
    // Cycles at the surface (floating) after the first dive started.
    let surfaced: Vec<usize> = (30..depths.len())
        .filter(|&cycle| depths[cycle] == 0.0)
        .collect();
    let first = surfaced[0];
    // Cycles last 4.51 s on average (u_cycle_time 4 s plus comet's 0.51 s
    // overrun, the default). The first surfacing starts at 1200 s (cycle 266),
    // and the climb from at most 23 m (20 m, a cycle's travel, the turn's
    // cycle and 1.7 m of overshoot) at 0.13 m/s takes under 180 s (40 cycles),
    // plus a servoed turn of about 4 cycles (the pitch slews 52° at 0.05 rad/s).
    assert!(
        (266..310).contains(&first),
        "first surfaced at cycle {first}"
    );
    // The yo's own climbs stop at 4 m less a cycle's travel, the turn's cycle
    // (0.59 m each at 0.13 m/s) and comet's 1.2 m overshoot: 1.6 m or more,
    // never at the surface.
    assert!(surfaced.iter().all(|&cycle| cycle >= 266));
    // It waits at the surface (120 s = 30 cycles), then dives again, and
    // comes back 1200 s after the previous surfacing started.
    let later: Vec<usize> = surfaced
        .iter()
        .copied()
        .filter(|&cycle| cycle > first + 200)
        .collect();
    // 2400 s is cycle 532; the climb and turn as above.
    assert!(
        !later.is_empty() && (532..576).contains(&later[0]),
        "{later:?}"
    );
}

#[test]
fn abend_samedepth_catches_a_glider_stuck_on_the_bottom() {
    // A dive to 50 m in 40 m of water, no altimeter turn, no hover stop: the
    // glider sits on the bottom until abend's samedepth_for (300 s) fires.
    let mission = Mission::parse(
        "stuck.mi",
        "sensor: s_water_depth_avg(m) 40\nbehavior: abend\n  b_arg: samedepth_for(s) 300\n\
         behavior: yo\n  b_arg: d_target_depth(m) 50\n  b_arg: d_target_altitude(m) -1\n  b_arg: d_stop_when_hover_for(s) -1\n",
    );
    let (sim, log) = run_logged(&mission, IDLE, 2000);
    let end = sim.end().expect("aborted");
    assert_eq!(end.reason, EndReason::Aborted(AbortReason::Samedepth));
    // Reaching 40 m takes about 270 s; then 300 s at the same depth, checked
    // every 30 s: the abort comes between 570 and 640 s.
    assert!(
        (560.0..650.0).contains(&end.time),
        "aborted at {} s",
        end.time
    );
    assert_eq!(log.column("m_depth").into_iter().fold(0.0, f64::max), 40.0);
    assert!(sim.is_finished());
}

#[test]
fn random_mission_text_never_panics() {
    // Fragments of real syntax shuffled by a fixed generator: parsing, loading
    // and building the stack must never panic, whatever comes out.
    let pieces = [
        "behavior:",
        " yo",
        " abend",
        " hook",
        " gloc",
        "\n",
        "b_arg:",
        " d_target_depth(m)",
        " (",
        ")",
        " 25",
        " -1",
        " 1e400",
        " NaN",
        "sensor:",
        " u_cycle_time(sec)",
        " 0",
        "#",
        "\r\n",
        " args_from_file(enum)",
        " 10",
        "<start:b_arg>",
        "<end:b_arg>",
        "é",
        "\0",
        " start_when(enum)",
        " 99",
        " 1000003",
    ];
    let mut rng = gloc_testsupport::Rng::new(12345);
    let list = Arc::new(SensorList::embedded());
    for _ in 0..2000 {
        let mut text = String::new();
        for _ in 0..30 {
            text.push_str(rng.pick(&pieces));
        }
        let mission = Mission::parse("r.mi", text);
        let _ = mission.render_plain();
        if let Ok(mut sim) = Simulation::new(&mission, list.clone(), None, &SimConfig::default()) {
            for _ in 0..20 {
                sim.step_cycle();
            }
        }
    }
}
