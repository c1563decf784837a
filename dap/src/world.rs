//! The debugged world: the GLOC interpreter as one behavior inside the glider
//! simulator, advanced through the simulator's phases (boundary, script share, rest of
//! the cycle) one instruction or one cycle remainder at a time.

use std::path::Path;
use std::sync::Arc;

use gloc_compiler::expression::{scope_of_source_map, ExpressionScope};
use gloc_compiler::{LoadedScript, Optimization};
use gloc_engine::program::Pc;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::CycleEnd;
use gloc_engine::Diagnostic;
use gloc_project::settings::{Origin, Settings};
use gloc_sim::behaviors::EventKind;
use gloc_sim::{EndReason, Phase as SimPhase, Simulation};

use crate::expr::Number;
use crate::program::{DebugInfo, Language, SourceLines};
use crate::replay_world::ReplayWorld;
use crate::script::{
    element_of, float_text, registers_of, set_element_in, set_pc_in, set_register_in,
    set_variable_in, trap_event, trap_words, variable_of, variables_of, DebugScript, VariableSlot,
};
pub use crate::script::{resolve, LaunchConfig};
use crate::target::{Named, Notice, Phase, StepEvent, Target};

/// What never changes during a run; shared by every snapshot.
#[derive(Debug)]
struct Fixed {
    variables: Vec<VariableSlot>,
    lines: SourceLines,
    /// The loaded script, which names traps for the script's author.
    loaded: LoadedScript,
    touched: Vec<usize>,
    max_cycles: Option<u64>,
    sensor_list: Arc<SensorList>,
}

/// The script flown in the simulator.
#[derive(Clone, Debug)]
pub struct SimWorld {
    sim: Simulation,
    fixed: Arc<Fixed>,
    /// Bytes of this cycle's printed text already reported.
    printed_reported: usize,
    /// Behavior events of this cycle already reported.
    events_reported: usize,
    abend_reported: bool,
    notices: Vec<Notice>,
}

/// The world being debugged: the script in the simulator, or the script over a
/// recorded deployment (`replay`); both behind [`Target`].
// Not boxed: one world lives per snapshot (at most a few hundred), and the simulated
// one, the common case, then needs no extra allocation per snapshot.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum World {
    Sim(SimWorld),
    Replay(ReplayWorld),
}

/// Loads the script and the sensor list, then the mission and the profile (or the
/// recording, with `replay`), and opens cycle 0.
pub fn launch(config: &LaunchConfig) -> Result<(World, DebugInfo), String> {
    launch_with(config, &resolve(config)?)
}

/// [`launch`] with settings already resolved.
pub fn launch_with(
    config: &LaunchConfig,
    settings: &Settings,
) -> Result<(World, DebugInfo), String> {
    let script = load_debug_script(config, settings)?;
    let info = debug_info(&script).with_scope(expression_scope(&script));
    let world = if config.replay.is_empty() {
        World::Sim(launch_sim(config, settings, script)?)
    } else {
        World::Replay(ReplayWorld::launch(config, settings, script)?)
    };
    Ok((world, info))
}

/// The names a GBASIC script's expressions use: its symbols (from the source map) and
/// the sensor list; a GLOC script has only the sensors (and, in the debugger, registers).
fn expression_scope(script: &DebugScript) -> ExpressionScope {
    match &script.loaded.source_map {
        Some(map) => scope_of_source_map(map, script.sensor_list.clone()),
        None => ExpressionScope::new(script.sensor_list.clone()),
    }
}

fn load_debug_script(config: &LaunchConfig, settings: &Settings) -> Result<DebugScript, String> {
    let path = &config.program;
    let sensor_list = gloc_project::sensors::load_sensor_list(settings)
        .and_then(gloc_project::sensors::LoadedSensors::into_list)
        .map_err(|error| error.to_string())?;
    // The debugger runs the unoptimized code, so that every line has its instructions.
    let script =
        gloc_project::script::load_script(path, &sensor_list, settings, Optimization::Plain)
            .map_err(|error| error.to_string())?;
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
        return Err(format!(
            "{} has errors:\n{}{note}",
            path.display(),
            errors.join("\n")
        ));
    };
    let mut touched: Vec<usize> = Vec::new();
    for sensor in program.loaded_sensors.iter().chain(&program.stored_sensors) {
        if !touched.contains(&sensor.index()) {
            touched.push(sensor.index());
        }
    }
    let variables = loaded
        .source_map
        .as_ref()
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
    let warnings = loaded
        .diagnostics
        .iter()
        .filter(|diagnostic| !diagnostic.is_error())
        .map(|diagnostic| render(path, &text, diagnostic))
        .collect();
    Ok(DebugScript {
        path: path.clone(),
        text,
        program,
        lines: SourceLines::of(&loaded),
        loaded,
        variables,
        touched,
        sensor_list: Arc::new(sensor_list),
        warnings,
    })
}

/// Lines (the loaded script's one pc → line map) and instruction texts per pc.
fn debug_info(script: &DebugScript) -> DebugInfo {
    let program = &script.program;
    let loaded = &script.loaded;
    let gloc_text = loaded.gloc_text.clone().unwrap_or_default();
    let gloc_lines: Vec<&str> = gloc_text.lines().collect();
    let count = program.instrs.len();
    // The line of the GLOC text each instruction was read from (none for the final
    // `halt` added after the script's end).
    let text_lines: Vec<Option<u32>> = match &loaded.source_map {
        Some(map) => {
            let mut origins = map.pc_origins();
            (0..count)
                .map(|_| origins.next().map(|origin| origin.gloc_line))
                .collect()
        }
        None => (0..count)
            .map(|pc| (pc + 1 < count).then(|| program.line(Pc(pc as u32))))
            .collect(),
    };
    let texts = text_lines
        .into_iter()
        .map(|line| match line {
            Some(line) => gloc_line_text(&gloc_lines, line),
            None => "halt    # end of script".to_string(),
        })
        .collect();
    let language = match loaded.source_map {
        Some(_) => Language::Gbasic,
        None => Language::Gloc,
    };
    DebugInfo::new(script.path.clone(), language, script.lines.clone(), texts)
        .with_program(program)
        .with_source_text(&script.text)
}

/// The simulator world: the mission and the profile, cycle 0 opened; the simulation
/// is built by the project layer, as `gloc run` builds it.
fn launch_sim(
    config: &LaunchConfig,
    settings: &Settings,
    script: DebugScript,
) -> Result<SimWorld, String> {
    let DebugScript {
        path,
        text,
        program,
        lines,
        loaded,
        variables,
        touched,
        sensor_list,
        warnings,
    } = script;
    let mission = gloc_project::simulation::load_mission(settings, &sensor_list)
        .map_err(|error| error.to_string())?;
    let profile = match &config.profile {
        None => None,
        Some(profile_path) => Some(
            gloc_project::simulation::load_profile(
                profile_path,
                Origin::LaunchAttribute("profile"),
            )
            .map_err(|error| error.to_string())?,
        ),
    };
    let sim_config = gloc_project::simulation::sim_config(
        settings,
        gloc_project::simulation::Flight {
            seed: config.seed,
            profile,
            simulator: Vec::new(),
        },
    )
    .map_err(|error| error.to_string())?;
    let mut sim = gloc_project::simulation::build_simulation(
        &mission,
        sensor_list.clone(),
        program.clone(),
        &sim_config,
    )
    .map_err(|error| error.to_string())?;
    let mut notices: Vec<Notice> = warnings
        .into_iter()
        .chain(sim.warnings().iter().cloned())
        .map(Notice::Warning)
        .collect();
    // The mission against the list and the script: S0106 and S0107.
    for entry in mission.check(&sensor_list) {
        notices.push(Notice::Warning(mission.render_one(&entry)));
    }
    let unhooked: Vec<_> = mission
        .unhooked_stores(&sensor_list, &program)
        .into_iter()
        .filter_map(|pc| loaded.span_of_pc(pc))
        .collect();
    if let Some(warning) = mission.unhooked_store_warning(&unhooked) {
        notices.push(Notice::Warning(render(&path, &text, &warning)));
    }
    if !sim.begin_cycle() {
        return Err("the mission ended before its first cycle".into());
    }
    let fixed = Arc::new(Fixed {
        variables,
        lines,
        loaded,
        touched,
        max_cycles: config.max_cycles,
        sensor_list,
    });
    let mut world = SimWorld {
        sim,
        fixed,
        printed_reported: 0,
        events_reported: 0,
        abend_reported: false,
        notices: Vec::new(),
    };
    world.collect();
    notices.append(&mut world.notices);
    world.notices = notices;
    Ok(world)
}

fn gloc_line_text(lines: &[&str], line: u32) -> String {
    let text = line
        .checked_sub(1)
        .and_then(|index| lines.get(index as usize))
        .copied()
        .unwrap_or("");
    text.split('#').next().unwrap_or("").trim().to_string()
}

/// `file:line:column: severity[CODE]: message`: the headline of the one renderer
/// (`gloc_engine::render`), as the CLI prints it.
pub(crate) fn render(path: &Path, text: &str, diagnostic: &Diagnostic) -> String {
    let display = path.display().to_string();
    gloc_engine::render::SourceFile::new(&display, text).headline(diagnostic)
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

    fn summary(&self, cut_short: bool) -> String {
        let (shallowest, deepest) = self.sim.depth_range();
        let how = match (self.sim.end(), cut_short) {
            (_, true) => format!("stopped after maxCycles = {}", self.sim.cycle()),
            (Some(end), false) => format!("mission {}", end.reason),
            (None, false) => "mission ended".to_string(),
        };
        let script = match self.sim.script_trap() {
            Some(trap) => format!(
                "; script trapped: {}",
                trap_words(&trap, &self.fixed.lines, &self.fixed.loaded)
            ),
            None => match self.sim.script_last_end() {
                Some(CycleEnd::Halted) => "; script halted".to_string(),
                _ => String::new(),
            },
        };
        format!(
            "{}: {how} after {} cycles ({:.0} s); depth {:.2}–{:.2} m; energy {:.0} J{script}",
            self.sim.mission_name(),
            self.sim.cycle(),
            self.sim.time(),
            shallowest,
            deepest,
            self.sim.energy_joules(),
        )
    }
}

// The script's state as the debugger sees it, for either world: each takes the
// machine (`None` when there is no script) and the GBASIC variables.

impl Target for SimWorld {
    fn cycle(&self) -> u64 {
        self.sim.cycle()
    }

    fn phase(&self) -> Phase {
        match self.sim.phase() {
            SimPhase::Boundary | SimPhase::BetweenCycles => Phase::Boundary,
            SimPhase::ScriptRunning => Phase::InScript,
            SimPhase::ScriptDone => Phase::ScriptDone,
            SimPhase::Finished => Phase::Ended,
        }
    }

    fn pc(&self) -> usize {
        self.sim.machine().map_or(0, |machine| machine.pc().index())
    }

    fn script_alive(&self) -> bool {
        self.sim
            .machine()
            .is_some_and(|machine| machine.status() == gloc_engine::vm::Status::Running)
    }

    fn step(&mut self) -> StepEvent {
        let event = match self.sim.phase() {
            SimPhase::Boundary | SimPhase::ScriptRunning => match self.sim.script_step() {
                None => StepEvent::Executed,
                Some(CycleEnd::Yielded) => StepEvent::Yielded,
                Some(CycleEnd::Halted) => StepEvent::Halted,
                Some(CycleEnd::Trapped(trap)) => trap_event(&trap, &self.fixed.loaded),
            },
            SimPhase::ScriptDone | SimPhase::BetweenCycles => {
                self.sim.finish_cycle();
                self.collect();
                let cut_short = self
                    .fixed
                    .max_cycles
                    .is_some_and(|max| self.sim.cycle() >= max);
                if self.sim.is_finished() || cut_short {
                    return StepEvent::MissionEnded {
                        summary: self.summary(cut_short && !self.sim.is_finished()),
                    };
                }
                self.printed_reported = 0;
                self.events_reported = 0;
                self.sim.begin_cycle();
                StepEvent::CycleBegan
            }
            SimPhase::Finished => {
                return StepEvent::MissionEnded {
                    summary: self.summary(false),
                }
            }
        };
        self.collect();
        event
    }

    fn run_share(&mut self, max_steps: u64) -> Option<(StepEvent, u64)> {
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
        let event = match self.sim.script_run(max_steps) {
            None => StepEvent::Executed,
            Some(CycleEnd::Yielded) => StepEvent::Yielded,
            Some(CycleEnd::Halted) => StepEvent::Halted,
            Some(CycleEnd::Trapped(trap)) => trap_event(&trap, &self.fixed.loaded),
        };
        // Every instruction is one step, the one that ends the share included; a share
        // that could not run after all is one step, as `script_step` answers it.
        let steps = executed(self).saturating_sub(before).max(1);
        self.collect();
        Some((event, steps))
    }

    fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    fn set_pc(&mut self, pc: usize) -> Result<(), String> {
        set_pc_in(self.sim.script_parts().map(|(machine, _)| machine), pc)
    }

    fn registers(&self) -> Vec<Number> {
        registers_of(self.sim.machine())
    }

    fn set_register(&mut self, index: usize, value: Number) -> Result<(), String> {
        set_register_in(
            self.sim.script_parts().map(|(machine, _)| machine),
            index,
            value,
        )
    }

    fn variables(&self) -> Vec<Named> {
        variables_of(self.sim.machine(), &self.fixed.variables)
    }

    fn variable(&self, name: &str) -> Option<Number> {
        variable_of(self.sim.machine(), &self.fixed.variables, name)
    }

    fn set_variable(&mut self, name: &str, value: Number) -> Result<(), String> {
        let machine = self.sim.script_parts().map(|(machine, _)| machine);
        set_variable_in(machine, &self.fixed.variables, name, value)
    }

    fn element(&self, name: &str, index: i64) -> Option<Number> {
        element_of(self.sim.machine(), &self.fixed.variables, name, index)
    }

    fn set_element(&mut self, name: &str, index: i64, value: Number) -> Result<(), String> {
        let machine = self.sim.script_parts().map(|(machine, _)| machine);
        set_element_in(machine, &self.fixed.variables, name, index, value)
    }

    fn sensor_count(&self) -> usize {
        self.fixed.sensor_list.len()
    }

    fn sensor_name(&self, index: usize) -> Option<&str> {
        self.fixed.sensor_list.name(SensorId(index as u32))
    }

    fn sensor_index(&self, name: &str) -> Option<usize> {
        self.fixed.sensor_list.lookup(name).map(SensorId::index)
    }

    fn sensor(&self, index: usize) -> f64 {
        self.sim.sensors().get(index).copied().unwrap_or(0.0)
    }

    fn set_sensor(&mut self, index: usize, value: f64) -> Result<(), String> {
        if self.sim.set_sensor(SensorId(index as u32), value) {
            Ok(())
        } else {
            Err(format!("there is no sensor {index}"))
        }
    }

    fn touched_sensors(&self) -> Vec<usize> {
        self.fixed.touched.clone()
    }

    fn vehicle(&self) -> Vec<Named> {
        let named = |name: &str, value: String, ty: &'static str| Named {
            name: name.to_string(),
            value,
            ty,
            length: None,
            element: None,
            evaluate_name: None,
        };
        // The vehicle's state, named by the sensor the simulator writes it to at each
        // boundary while the sensor holds exactly the value shown.
        let mirrored = |name: &str, value: f64, sensor: &str| {
            let shown = float_text(value);
            let evaluate_name = self
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
}

/// Calls the same method on whichever world is running.
macro_rules! each_world {
    ($self:ident, $world:ident => $call:expr) => {
        match $self {
            World::Sim($world) => $call,
            World::Replay($world) => $call,
        }
    };
}

impl Target for World {
    fn cycle(&self) -> u64 {
        each_world!(self, world => world.cycle())
    }
    fn phase(&self) -> Phase {
        each_world!(self, world => world.phase())
    }
    fn pc(&self) -> usize {
        each_world!(self, world => world.pc())
    }
    fn script_alive(&self) -> bool {
        each_world!(self, world => world.script_alive())
    }
    fn step(&mut self) -> StepEvent {
        each_world!(self, world => world.step())
    }
    fn run_share(&mut self, max_steps: u64) -> Option<(StepEvent, u64)> {
        each_world!(self, world => world.run_share(max_steps))
    }
    fn take_notices(&mut self) -> Vec<Notice> {
        each_world!(self, world => world.take_notices())
    }
    fn set_pc(&mut self, pc: usize) -> Result<(), String> {
        each_world!(self, world => world.set_pc(pc))
    }
    fn registers(&self) -> Vec<Number> {
        each_world!(self, world => world.registers())
    }
    fn set_register(&mut self, index: usize, value: Number) -> Result<(), String> {
        each_world!(self, world => world.set_register(index, value))
    }
    fn variables(&self) -> Vec<Named> {
        each_world!(self, world => world.variables())
    }
    fn variable(&self, name: &str) -> Option<Number> {
        each_world!(self, world => world.variable(name))
    }
    fn set_variable(&mut self, name: &str, value: Number) -> Result<(), String> {
        each_world!(self, world => world.set_variable(name, value))
    }
    fn element(&self, name: &str, index: i64) -> Option<Number> {
        each_world!(self, world => world.element(name, index))
    }
    fn set_element(&mut self, name: &str, index: i64, value: Number) -> Result<(), String> {
        each_world!(self, world => world.set_element(name, index, value))
    }
    fn sensor_count(&self) -> usize {
        each_world!(self, world => world.sensor_count())
    }
    fn sensor_name(&self, index: usize) -> Option<&str> {
        each_world!(self, world => world.sensor_name(index))
    }
    fn sensor_index(&self, name: &str) -> Option<usize> {
        each_world!(self, world => world.sensor_index(name))
    }
    fn sensor(&self, index: usize) -> f64 {
        each_world!(self, world => world.sensor(index))
    }
    fn set_sensor(&mut self, index: usize, value: f64) -> Result<(), String> {
        each_world!(self, world => world.set_sensor(index, value))
    }
    fn touched_sensors(&self) -> Vec<usize> {
        each_world!(self, world => world.touched_sensors())
    }
    fn vehicle(&self) -> Vec<Named> {
        each_world!(self, world => world.vehicle())
    }
}
