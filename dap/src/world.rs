//! The debugged world: the GLOC interpreter as one behavior inside the glider
//! simulator, advanced through the simulator's phases (boundary, script share, rest of
//! the cycle) one instruction or one cycle remainder at a time.

use std::sync::Arc;

use gloc_compiler::expression::{scope_of_source_map, ExpressionScope};
use gloc_compiler::Optimization;
use gloc_engine::program::Pc;
use gloc_engine::vm::{CycleEnd, Machine};
use gloc_project::settings::{Origin, Settings};
use gloc_project::simulation::Warning;
use gloc_sim::behaviors::EventKind;
use gloc_sim::navigation::{DrState, Xy};
use gloc_sim::{EndReason, Phase as SimPhase, Simulation};

use crate::error::{DebugError, DebugResult};
use crate::expr::Number;
use crate::journey;
use crate::program::{DebugInfo, Language, SourceLines};
use crate::replay_world::ReplayWorld;
use crate::script::{float_text, render, DebugScript, ScriptState, VariableSlot};
pub use crate::script::{resolve, LaunchConfig};
use crate::target::{Milestone, Named, Notice, Phase, StepEvent, Target};

/// The world being debugged: the script (its [`ScriptState`], shared by every
/// snapshot) and where it runs, the simulator or a recorded deployment (`replay`).
/// The one [`Target`]: what the two runs differ in (how a step advances, where the
/// machine and the sensor array live, what the Vehicle scope shows) is asked of the
/// run, everything about the script of the `ScriptState`.
#[derive(Clone, Debug)]
pub struct World {
    script: Arc<ScriptState>,
    run: Run,
}

/// Where the script runs.
// Not boxed: one world lives per snapshot (at most a few hundred), and the simulated
// one, the common case, then needs no extra allocation per snapshot.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
enum Run {
    Sim(SimWorld),
    Replay(ReplayWorld),
}

/// The script flown in the simulator.
#[derive(Clone, Debug)]
pub(crate) struct SimWorld {
    sim: Simulation,
    /// Bytes of this cycle's printed text already reported.
    printed_reported: usize,
    /// Behavior events of this cycle already reported.
    events_reported: usize,
    abend_reported: bool,
    notices: Vec<Notice>,
    /// The journey as the last cycle left it: the waypoint steered to and its place in
    /// its list, and `x_dr_state` (a milestone is a change of these).
    journey: Journey,
}

/// What the milestones are judged against: the state at the end of the last cycle.
#[derive(Clone, Copy, Debug)]
struct Journey {
    waypoint: Option<Xy>,
    index: Option<(usize, usize)>,
    dr_state: DrState,
}

impl Journey {
    fn of(sim: &Simulation) -> Journey {
        Journey {
            waypoint: sim.waypoint(),
            index: sim.waypoint_index(),
            dr_state: sim.navigation().dr_state,
        }
    }
}

/// Loads the script and the sensor list, then the mission and the profile (or the
/// recording, with `replay`), and opens cycle 0.
pub fn launch(config: &LaunchConfig) -> DebugResult<(World, DebugInfo)> {
    launch_with(config, &resolve(config)?)
}

/// [`launch`] with settings already resolved.
pub fn launch_with(config: &LaunchConfig, settings: &Settings) -> DebugResult<(World, DebugInfo)> {
    let script = load_debug_script(config, settings)?;
    let info = debug_info(&script).with_scope(expression_scope(&script));
    let (run, touched) = if config.replay.is_empty() {
        let touched = script.state.touched.clone();
        (Run::Sim(launch_sim(config, settings, &script)?), touched)
    } else {
        let (replay, touched) = ReplayWorld::launch(config, settings, &script)?;
        (Run::Replay(replay), touched)
    };
    let script = ScriptState {
        touched,
        ..script.state
    };
    let mut world = World {
        script: Arc::new(script),
        run,
    };
    // What loading said, then what opening cycle 0 did.
    if let Run::Sim(sim) = &mut world.run {
        sim.collect();
    }
    Ok((world, info))
}

/// The names a GBASIC script's expressions use: its symbols (from the source map) and
/// the sensor list; a GLOC script has only the sensors (and, in the debugger, registers).
fn expression_scope(script: &DebugScript) -> ExpressionScope {
    match script.state.loaded.source_map() {
        Some(map) => scope_of_source_map(map, script.state.sensor_list.clone()),
        None => ExpressionScope::new(script.state.sensor_list.clone()),
    }
}

fn load_debug_script(config: &LaunchConfig, settings: &Settings) -> DebugResult<DebugScript> {
    let path = &config.program;
    let sensor_list = gloc_project::sensors::load_sensor_list(settings)
        .and_then(gloc_project::sensors::LoadedSensors::into_list)
        .map_err(|error| DebugError::launch(error.to_string()))?;
    // The debugger runs the unoptimized code, so that every line has its instructions.
    let script =
        gloc_project::script::load_script(path, &sensor_list, settings, Optimization::Plain)
            .map_err(|error| DebugError::launch(error.to_string()))?;
    let gloc_project::script::Script {
        text, loaded, hint, ..
    } = script;
    let Some(program) = loaded.program.clone() else {
        // Every diagnostic, warnings too, as `gloc check` lists them.
        let errors: Vec<String> = loaded
            .diagnostics
            .iter()
            .map(|diagnostic| render(path, &text, diagnostic))
            .collect();
        let note = hint
            .map(|hint| format!("\n{}: note: {hint}", path.display()))
            .unwrap_or_default();
        return Err(DebugError::launch(format!(
            "{} has errors:\n{}{note}",
            path.display(),
            errors.join("\n")
        )));
    };
    let mut touched: Vec<usize> = Vec::new();
    for sensor in program.loaded_sensors.iter().chain(&program.stored_sensors) {
        if !touched.contains(&sensor.index()) {
            touched.push(sensor.index());
        }
    }
    let variables = loaded
        .source_map()
        .map(|map| {
            map.variables
                .iter()
                .map(|variable| VariableSlot {
                    name: variable.name.clone(),
                    float: variable.ty == gloc_compiler::typed::Ty::Float,
                    storage: variable.storage,
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(DebugScript {
        path: path.clone(),
        text,
        program,
        state: ScriptState {
            variables,
            lines: SourceLines::of(&loaded),
            loaded,
            touched,
            sensor_list: Arc::new(sensor_list),
            max_cycles: config.max_cycles,
        },
    })
}

/// Lines (the loaded script's one pc → line map) and instruction texts per pc.
fn debug_info(script: &DebugScript) -> DebugInfo {
    let program = &script.program;
    let loaded = &script.state.loaded;
    let gloc_text = loaded.gloc_text.clone().unwrap_or_default();
    let gloc_lines: Vec<&str> = gloc_text.lines().collect();
    let count = program.instrs.len();
    // The line of the GLOC text each instruction was read from (none for the final
    // `halt` added after the script's end): the program's own lines, since even a
    // GBASIC script's program is parsed from its compiled GLOC text.
    let texts = (0..count)
        .map(|pc| (pc + 1 < count).then(|| program.line(Pc(pc as u32))))
        .map(|line| match line {
            Some(line) => gloc_line_text(&gloc_lines, line),
            None => "halt    # end of script".to_string(),
        })
        .collect();
    let language = match loaded.gbasic {
        Some(_) => Language::Gbasic,
        None => Language::Gloc,
    };
    DebugInfo::new(
        script.path.clone(),
        language,
        script.state.lines.clone(),
        texts,
    )
    .with_program(program)
    .with_source_text(&script.text)
}

/// The simulator world: the mission and the profile, cycle 0 opened; the simulation
/// is built by the project layer, as `gloc run` builds it.
fn launch_sim(
    config: &LaunchConfig,
    settings: &Settings,
    script: &DebugScript,
) -> DebugResult<SimWorld> {
    let launch_error = |error: gloc_project::ProjectError| DebugError::launch(error.to_string());
    let sensor_list = &script.state.sensor_list;
    let mission =
        gloc_project::simulation::load_mission(settings, sensor_list).map_err(launch_error)?;
    let flight = gloc_project::simulation::Flight::read(
        config.seed,
        config.profile.as_deref(),
        Origin::LaunchAttribute("profile"),
    )
    .map_err(launch_error)?;
    let plan = gloc_project::simulation::Plan {
        settings,
        sensors: sensor_list,
        mission: &mission,
        script: &script.state.loaded,
        program: &script.program,
    };
    let prepared = gloc_project::simulation::prepare(&plan, flight).map_err(launch_error)?;
    let mut notices: Vec<Notice> = script.warnings().map(Notice::Warning).collect();
    // The mission against the list and the script (S0106, S0107, S012x), as `gloc run`
    // shows them, one line each.
    notices.extend(prepared.warnings.iter().map(|warning| {
        Notice::Warning(match warning {
            Warning::Simulator(line) => line.clone(),
            Warning::Mission(entry) => mission.render_one(entry),
            Warning::Script(diagnostic) => script.render(diagnostic),
        })
    }));
    let mut sim = prepared.simulation;
    if !sim.begin_cycle() {
        return Err(DebugError::launch(
            "the mission ended before its first cycle",
        ));
    }
    Ok(SimWorld {
        journey: Journey::of(&sim),
        sim,
        printed_reported: 0,
        events_reported: 0,
        abend_reported: false,
        notices,
    })
}

fn gloc_line_text(lines: &[&str], line: u32) -> String {
    let text = line
        .checked_sub(1)
        .and_then(|index| lines.get(index as usize))
        .copied()
        .unwrap_or("");
    text.split('#').next().unwrap_or("").trim().to_string()
}

impl SimWorld {
    /// Turns this cycle's new prints, behavior events and an abort into notices.
    fn collect(&mut self) {
        // Called after every step: the common case, nothing new, costs two compares.
        let printed = self.sim.printed_text();
        if printed.len() > self.printed_reported {
            // Each printed line with the pc of its `print` (every line has its site).
            let sites = self.sim.print_sites();
            let mut start = self.printed_reported;
            let first = sites.partition_point(|(end, _)| *end <= start);
            for &(end, pc) in &sites[first..] {
                let text = printed.get(start..end).unwrap_or("");
                self.notices.extend(text.lines().map(|line| Notice::Print {
                    text: line.to_string(),
                    pc: pc.index(),
                }));
                start = end;
            }
            self.printed_reported = printed.len();
        }
        let events = self.sim.events();
        for event in &events[self.events_reported.min(events.len())..] {
            let name = self
                .sim
                .behaviors()
                .get(event.behavior)
                .map(|behavior| behavior.name.clone())
                .unwrap_or_else(|| format!("behavior {}", event.behavior));
            let text = match event.kind {
                EventKind::Started => format!("{name} started"),
                EventKind::Completed => format!("{name} completed"),
                EventKind::Inflection { depth } => format!("{name} turned at {depth:.2} m"),
                EventKind::IgnoredRequest { value } => format!(
                    "{name} ignored sci_ruhp_behs = {value} (not a whole number from 0 to 2147483647)"
                ),
            };
            self.notices.push(Notice::Behavior(format!(
                "cycle {}: {text}",
                self.sim.cycle()
            )));
        }
        self.events_reported = events.len();
        if !self.abend_reported {
            if let Some(end) = self.sim.end() {
                if let EndReason::Aborted(_) = end.reason {
                    self.abend_reported = true;
                    self.notices.push(Notice::Abend(format!(
                        "{} at cycle {} ({:.1} s, depth {:.2} m)",
                        end.reason, end.cycle, end.time, end.depth
                    )));
                }
            }
        }
    }

    fn summary(&self, script: &ScriptState, cut_short: bool) -> String {
        let (shallowest, deepest) = self.sim.depth_range();
        let how = match (self.sim.end(), cut_short) {
            (_, true) => format!("stopped after maxCycles = {}", self.sim.cycle()),
            (Some(end), false) => format!("mission {}", end.reason),
            (None, false) => "mission ended".to_string(),
        };
        let trapped = match self.sim.script_trap() {
            Some(trap) => format!("; script trapped: {}", script.trap_words(&trap)),
            None => match self.sim.script_last_end() {
                Some(CycleEnd::Halted) => "; script halted".to_string(),
                _ => String::new(),
            },
        };
        format!(
            "{}: {how} after {} cycles ({:.0} s); depth {:.2}–{:.2} m; energy {:.0} J{trapped}",
            self.sim.mission_name(),
            self.sim.cycle(),
            self.sim.time(),
            shallowest,
            deepest,
            self.sim.energy_joules(),
        )
    }

    fn phase(&self) -> Phase {
        match self.sim.phase() {
            SimPhase::Boundary | SimPhase::BetweenCycles => Phase::Boundary,
            SimPhase::ScriptRunning => Phase::InScript,
            SimPhase::ScriptDone => Phase::ScriptDone,
            SimPhase::Finished => Phase::Ended,
        }
    }

    fn step(&mut self, script: &ScriptState) -> StepEvent {
        let event = match self.sim.phase() {
            SimPhase::Boundary | SimPhase::ScriptRunning => {
                script.step_event(self.sim.script_step())
            }
            SimPhase::ScriptDone | SimPhase::BetweenCycles => {
                self.sim.finish_cycle();
                self.collect();
                self.milestones();
                let cut_short = script.max_cycles.is_some_and(|max| self.sim.cycle() >= max);
                if self.sim.is_finished() || cut_short {
                    return StepEvent::MissionEnded {
                        summary: self.summary(script, cut_short && !self.sim.is_finished()),
                    };
                }
                self.printed_reported = 0;
                self.events_reported = 0;
                self.sim.begin_cycle();
                StepEvent::CycleBegan
            }
            SimPhase::Finished => {
                return StepEvent::MissionEnded {
                    summary: self.summary(script, false),
                }
            }
        };
        self.collect();
        event
    }

    fn run_share(&mut self, script: &ScriptState, max_steps: u64) -> Option<(StepEvent, u64)> {
        if self.sim.phase() != SimPhase::ScriptRunning {
            return None;
        }
        let executed = |world: &SimWorld| {
            world
                .sim
                .machine()
                .map_or(0, |machine| machine.instructions_this_cycle())
        };
        let before = executed(self);
        let event = script.step_event(self.sim.script_run(max_steps));
        // Every instruction is one step, the one that ends the share included; a share
        // that could not run after all is one step, as `script_step` answers it.
        let steps = executed(self).saturating_sub(before).max(1);
        self.collect();
        Some((event, steps))
    }

    /// Cycle, mission time, depth, pitch, active behaviors, energy.
    fn vehicle(&self, script: &ScriptState) -> Vec<Named> {
        // The vehicle's state, named by the sensor the simulator writes it to at each
        // boundary while the sensor holds exactly the value shown.
        let named = Named::plain;
        let mirrored = |name: &str, value: f64, sensor: &str| {
            let shown = float_text(value);
            let evaluate_name = script
                .sensor_index(sensor)
                .filter(|index| self.sensor(*index).to_bits() == value.to_bits())
                .map(|_| sensor.to_string());
            Named {
                evaluate_name,
                ..named(name, shown, "float")
            }
        };
        let active: Vec<&str> = self.sim.active_behaviors().collect();
        let phase = match self.sim.phase() {
            SimPhase::BetweenCycles => "between cycles",
            SimPhase::Boundary => "cycle boundary",
            SimPhase::ScriptRunning => "script running",
            SimPhase::ScriptDone => "script yielded",
            SimPhase::Finished => "finished",
        };
        vec![
            named("cycle", self.sim.cycle().to_string(), "integer"),
            named("phase", phase.to_string(), "string"),
            named("mission time (s)", float_text(self.sim.time()), "float"),
            mirrored("m_present_time", self.sim.present_time(), "m_present_time"),
            mirrored("depth (m)", self.sim.depth(), "m_depth"),
            mirrored("pitch (rad)", self.sim.pitch(), "m_pitch"),
            named(
                "pitch (deg)",
                float_text(self.sim.pitch().to_degrees()),
                "float",
            ),
            named("active behaviors", active.join(", "), "string"),
            named("energy (J)", float_text(self.sim.energy_joules()), "float"),
            named(
                "charge used (Ah)",
                float_text(self.sim.amp_hours()),
                "float",
            ),
            mirrored("water depth (m)", self.sim.water_depth(), "m_water_depth"),
        ]
    }

    fn sensor(&self, index: usize) -> f64 {
        self.sim.sensors().get(index).copied().unwrap_or(0.0)
    }

    /// After a cycle: a waypoint reached in it and a surfacing (`x_dr_state` 1 → 2)
    /// become milestones, worded with where the glider believes it is and where it is.
    fn milestones(&mut self) {
        let before = self.journey;
        let now = Journey::of(&self.sim);
        self.journey = now;
        let navigation = self.sim.navigation();
        let cycle = self.sim.cycle().saturating_sub(1);
        if self.sim.nav_view().hit_waypoint {
            // The waypoint steered to when the cycle began (the behavior has moved on to
            // the next), or the one steered to now if none was before.
            let reached = before.waypoint.or(now.waypoint);
            let which = match before.index.or(now.index) {
                Some((index, count)) => format!("waypoint {index} (of {count})"),
                None => "the waypoint".to_string(),
            };
            let distances = reached.map_or_else(String::new, |waypoint| {
                let (lat, lon) = navigation.lmc.xy_to_nmea(waypoint);
                format!(
                    " at {} {}: {:.1} m from it by dead reckoning (at the cycle's end the glider is truly {:.1} m from it)",
                    float_text(lat),
                    float_text(lon),
                    self.sim.nav_view().position.distance(waypoint),
                    navigation.true_position.distance(waypoint)
                )
            });
            self.notices.push(Notice::Milestone(
                Milestone::WaypointReached,
                format!("{which} reached in cycle {cycle}{distances}"),
            ));
        }
        if before.dr_state == DrState::Underwater && now.dr_state == DrState::Surfaced {
            let (lat, lon) = navigation.lmc.xy_to_nmea(navigation.dead_reckoned);
            self.notices.push(Notice::Milestone(
                Milestone::Surfaced,
                format!(
                    "surfaced in cycle {cycle} at dead-reckoned {} {}, {:.1} m from where the glider is",
                    float_text(lat),
                    float_text(lon),
                    navigation.dead_reckoned.distance(navigation.true_position)
                ),
            ));
        }
    }

    /// The Navigation scope: the sensors, then the waypoint's place in its list and
    /// the truth the simulator keeps apart from the glider's belief.
    fn navigation(&self, script: &ScriptState) -> Vec<Named> {
        let mut rows = journey::sensor_rows(script, |index| self.sensor(index));
        let navigation = self.sim.navigation();
        if let Some((index, count)) = self.sim.waypoint_index() {
            rows.push(Named::plain(
                "waypoint index",
                format!("{index} of {count}"),
                "the goto behavior's waypoint, numbered from 0 as wpt_x_0",
            ));
        }
        let (lat, lon) = navigation.lmc.xy_to_nmea(navigation.true_position);
        let truth = [
            ("true lat", float_text(lat), "NMEA, where the glider is"),
            ("true lon", float_text(lon), "NMEA, where the glider is"),
            (
                "true x (m)",
                float_text(navigation.true_position.x),
                "m east of the mission origin",
            ),
            (
                "true y (m)",
                float_text(navigation.true_position.y),
                "m north of the mission origin",
            ),
            (
                "dead-reckoning error (m)",
                float_text(navigation.dead_reckoned.distance(navigation.true_position)),
                "m between the belief and the truth",
            ),
            (
                "true current",
                journey::flow(navigation.true_water),
                "s_water_speed toward s_water_direction",
            ),
        ];
        rows.extend(
            truth
                .into_iter()
                .map(|(name, value, ty)| Named::plain(name, value, ty)),
        );
        rows
    }
}

impl Run {
    /// The script's machine (`None`: the simulation runs no script).
    fn machine(&self) -> Option<&Machine> {
        match self {
            Run::Sim(world) => world.sim.machine(),
            Run::Replay(world) => Some(world.machine()),
        }
    }

    fn machine_mut(&mut self) -> Option<&mut Machine> {
        match self {
            Run::Sim(world) => world.sim.script_parts().map(|(machine, _)| machine),
            Run::Replay(world) => Some(world.machine_mut()),
        }
    }
}

impl Target for World {
    fn cycle(&self) -> u64 {
        match &self.run {
            Run::Sim(world) => world.sim.cycle(),
            Run::Replay(world) => world.cycle(),
        }
    }

    fn phase(&self) -> Phase {
        match &self.run {
            Run::Sim(world) => world.phase(),
            Run::Replay(world) => world.phase(),
        }
    }

    fn pc(&self) -> usize {
        self.run.machine().map_or(0, |machine| machine.pc().index())
    }

    fn script_alive(&self) -> bool {
        self.run
            .machine()
            .is_some_and(|machine| machine.status() == gloc_engine::vm::Status::Running)
    }

    fn step(&mut self) -> StepEvent {
        match &mut self.run {
            Run::Sim(world) => world.step(&self.script),
            Run::Replay(world) => world.step(&self.script),
        }
    }

    fn run_share(&mut self, max_steps: u64) -> Option<(StepEvent, u64)> {
        match &mut self.run {
            Run::Sim(world) => world.run_share(&self.script, max_steps),
            // The replay steps: it runs no fused machine.
            Run::Replay(_) => None,
        }
    }

    fn take_notices(&mut self) -> Vec<Notice> {
        match &mut self.run {
            Run::Sim(world) => std::mem::take(&mut world.notices),
            Run::Replay(world) => world.take_notices(),
        }
    }

    fn set_pc(&mut self, pc: usize) -> DebugResult<()> {
        self.script.set_pc(self.run.machine_mut(), pc)
    }

    fn registers(&self) -> Vec<Number> {
        self.script.registers(self.run.machine())
    }

    fn set_register(&mut self, index: usize, value: Number) -> DebugResult<()> {
        self.script
            .set_register(self.run.machine_mut(), index, value)
    }

    fn variables(&self) -> Vec<Named> {
        self.script.variables(self.run.machine())
    }

    fn variable(&self, name: &str) -> Option<Number> {
        self.script.variable(self.run.machine(), name)
    }

    fn set_variable(&mut self, name: &str, value: Number) -> DebugResult<()> {
        self.script
            .set_variable(self.run.machine_mut(), name, value)
    }

    fn element(&self, name: &str, index: i64) -> Option<Number> {
        self.script.element(self.run.machine(), name, index)
    }

    fn set_element(&mut self, name: &str, index: i64, value: Number) -> DebugResult<()> {
        self.script
            .set_element(self.run.machine_mut(), name, index, value)
    }

    fn sensor_count(&self) -> usize {
        self.script.sensor_count()
    }

    fn sensor_name(&self, index: usize) -> Option<&str> {
        self.script.sensor_name(index)
    }

    fn sensor_index(&self, name: &str) -> Option<usize> {
        self.script.sensor_index(name)
    }

    fn sensor(&self, index: usize) -> f64 {
        match &self.run {
            Run::Sim(world) => world.sensor(index),
            Run::Replay(world) => world.sensor(index),
        }
    }

    fn set_sensor(&mut self, index: usize, value: f64) -> DebugResult<()> {
        let done = match &mut self.run {
            Run::Sim(world) => world
                .sim
                .set_sensor(gloc_engine::sensors::SensorId(index as u32), value),
            Run::Replay(world) => world.set_sensor(index, value),
        };
        if done {
            Ok(())
        } else {
            Err(DebugError::edit(format!("there is no sensor {index}")))
        }
    }

    fn touched_sensors(&self) -> Vec<usize> {
        self.script.touched.clone()
    }

    fn vehicle(&self) -> Vec<Named> {
        match &self.run {
            Run::Sim(world) => world.vehicle(&self.script),
            Run::Replay(world) => world.vehicle(&self.script),
        }
    }

    fn navigation(&self) -> Vec<Named> {
        match &self.run {
            Run::Sim(world) => world.navigation(&self.script),
            Run::Replay(world) => journey::sensor_rows(&self.script, |index| world.sensor(index)),
        }
    }
}
