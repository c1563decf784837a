//! The replay world: the script run over a recorded deployment (a CSV file or real
//! glider logs, `gloc_replay::Recording`), one recorded cycle per control cycle. No
//! simulator: at each cycle boundary the recorded values of that cycle are written
//! into the sensor array (a sensor not updated keeps its value, as the script's
//! stores do), then the script runs its share. The whole recording is held in memory
//! and shared by every snapshot, so stepping back costs one sensor array per snapshot.

use std::sync::Arc;

use gloc_compiler::LoadedScript;
use gloc_engine::program::Pc;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig, Status};
use gloc_replay::{Input, Recording};

use crate::expr::Number;
use crate::program::SourceLines;
use crate::script::{
    element_of, float_text, registers_of, set_element_in, set_pc_in, set_register_in,
    set_variable_in, trap_event, trap_words, variable_of, variables_of, DebugScript, LaunchConfig,
    VariableSlot,
};
use crate::target::{Named, Notice, Phase, StepEvent, Target};

/// What never changes during a replay; shared by every snapshot.
#[derive(Debug)]
struct Fixed {
    recording: Recording,
    variables: Vec<VariableSlot>,
    lines: SourceLines,
    /// The loaded script, which names traps for the script's author.
    loaded: LoadedScript,
    /// The script's sensors first, then the recorded ones the list has.
    touched: Vec<usize>,
    max_cycles: Option<u64>,
    sensor_list: Arc<SensorList>,
}

#[derive(Clone, Debug)]
pub struct ReplayWorld {
    fixed: Arc<Fixed>,
    machine: Machine,
    /// The sensor array, indexed by the active list.
    values: Vec<f64>,
    /// The recorded cycle being run (0-based).
    cycle: u64,
    phase: Phase,
    notices: Vec<Notice>,
    /// How the script last ended its share (for the summary).
    last_end: Option<CycleEnd>,
}

/// The script's view of the sensor array; prints become notices.
struct ReplayHost<'a> {
    values: &'a mut [f64],
    notices: &'a mut Vec<Notice>,
}

impl Host for ReplayHost<'_> {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        self.values.get(sensor.index()).copied().unwrap_or(0.0)
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        if let Some(slot) = self.values.get_mut(sensor.index()) {
            *slot = value;
        }
    }

    fn print_line(&mut self, line: &str) {
        // The machine calls `print_line_at`; a line without its pc has none to name.
        self.print_line_at(line, Pc(u32::MAX));
    }

    fn print_line_at(&mut self, line: &str, pc: Pc) {
        self.notices.push(Notice::Print {
            text: line.to_string(),
            pc: pc.index(),
        });
    }
}

impl ReplayWorld {
    /// Reads the whole recording (sensors matched to the active list by name) and
    /// opens its first cycle.
    pub(crate) fn launch(
        config: &LaunchConfig,
        settings: &gloc_project::Settings,
        script: DebugScript,
    ) -> Result<ReplayWorld, String> {
        let input = Input::open(&config.replay, settings.sensor_cache.as_deref())
            .map_err(|error| error.to_string())?;
        let recording =
            Recording::read(input, &script.sensor_list).map_err(|error| error.to_string())?;
        if recording.is_empty() {
            return Err(format!("{} has no recorded cycles", recording.source));
        }
        let mut notices: Vec<Notice> = script
            .warnings
            .iter()
            .cloned()
            .map(Notice::Warning)
            .chain(
                recording
                    .warnings
                    .iter()
                    .map(|warning| Notice::Warning(format!("{}: {warning}", recording.source))),
            )
            .collect();
        notices.push(Notice::Warning(format!(
            "replaying {} recorded cycles of {}",
            recording.len(),
            recording.source
        )));
        let mut touched = script.touched.clone();
        for id in &recording.recorded {
            if !touched.contains(&id.index()) {
                touched.push(id.index());
            }
        }
        let machine = Machine::new(
            script.program.clone(),
            MachineConfig {
                cycle_budget: settings.cycle_budget.value.get(),
            },
        );
        let mut world = ReplayWorld {
            values: script.sensor_list.initial_values(),
            fixed: Arc::new(Fixed {
                recording,
                variables: script.variables,
                lines: script.lines,
                loaded: script.loaded,
                touched,
                max_cycles: config.max_cycles,
                sensor_list: script.sensor_list,
            }),
            machine,
            cycle: 0,
            phase: Phase::Boundary,
            notices,
            last_end: None,
        };
        world.publish();
        Ok(world)
    }

    /// Writes the current recorded cycle's values into the sensor array.
    fn publish(&mut self) {
        let Some(updates) = self.fixed.recording.cycle(self.cycle as usize) else {
            return;
        };
        for &(sensor, value) in updates {
            if let Some(slot) = self.values.get_mut(sensor.index()) {
                *slot = value;
            }
        }
    }

    fn summary(&self, cut_short: bool) -> String {
        let how = if cut_short {
            format!("stopped after maxCycles = {}", self.cycle + 1)
        } else {
            "end of the recording".to_string()
        };
        let script = match self.machine.status() {
            Status::Trapped(trap) => {
                format!(
                    "; script trapped: {}",
                    trap_words(&trap, &self.fixed.lines, &self.fixed.loaded)
                )
            }
            Status::Halted => "; script halted".to_string(),
            Status::Running => String::new(),
        };
        format!(
            "replay of {}: {how} after {} of {} cycles{script}",
            self.fixed.recording.source,
            self.cycle + 1,
            self.fixed.recording.len()
        )
    }

    fn value_of(&self, name: &str) -> Option<f64> {
        let id = self.fixed.sensor_list.lookup(name)?;
        self.values.get(id.index()).copied()
    }
}

impl Target for ReplayWorld {
    fn cycle(&self) -> u64 {
        self.cycle
    }

    fn phase(&self) -> Phase {
        self.phase
    }

    fn pc(&self) -> usize {
        self.machine.pc().index()
    }

    fn script_alive(&self) -> bool {
        self.machine.status() == Status::Running
    }

    fn step(&mut self) -> StepEvent {
        match self.phase {
            Phase::Ended => StepEvent::MissionEnded {
                summary: self.summary(false),
            },
            Phase::Boundary | Phase::InScript => {
                if self.machine.status() != Status::Running {
                    self.phase = Phase::ScriptDone;
                    return StepEvent::Yielded;
                }
                let mut host = ReplayHost {
                    values: &mut self.values,
                    notices: &mut self.notices,
                };
                match self.machine.step(&mut host) {
                    None => {
                        self.phase = Phase::InScript;
                        StepEvent::Executed
                    }
                    Some(end) => {
                        self.phase = Phase::ScriptDone;
                        self.last_end = Some(end);
                        match end {
                            CycleEnd::Yielded => StepEvent::Yielded,
                            CycleEnd::Halted => StepEvent::Halted,
                            CycleEnd::Trapped(trap) => trap_event(&trap, &self.fixed.loaded),
                        }
                    }
                }
            }
            Phase::ScriptDone => {
                let next = self.cycle + 1;
                let cut_short = self.fixed.max_cycles.is_some_and(|max| next >= max);
                if cut_short || next as usize >= self.fixed.recording.len() {
                    self.phase = Phase::Ended;
                    return StepEvent::MissionEnded {
                        summary: self.summary(cut_short),
                    };
                }
                self.cycle = next;
                self.publish();
                self.phase = Phase::Boundary;
                StepEvent::CycleBegan
            }
        }
    }

    fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    fn set_pc(&mut self, pc: usize) -> Result<(), String> {
        set_pc_in(Some(&mut self.machine), pc)
    }

    fn registers(&self) -> Vec<Number> {
        registers_of(Some(&self.machine))
    }

    fn set_register(&mut self, index: usize, value: Number) -> Result<(), String> {
        set_register_in(Some(&mut self.machine), index, value)
    }

    fn variables(&self) -> Vec<Named> {
        variables_of(Some(&self.machine), &self.fixed.variables)
    }

    fn variable(&self, name: &str) -> Option<Number> {
        variable_of(Some(&self.machine), &self.fixed.variables, name)
    }

    fn set_variable(&mut self, name: &str, value: Number) -> Result<(), String> {
        set_variable_in(Some(&mut self.machine), &self.fixed.variables, name, value)
    }

    fn element(&self, name: &str, index: i64) -> Option<Number> {
        element_of(Some(&self.machine), &self.fixed.variables, name, index)
    }

    fn set_element(&mut self, name: &str, index: i64, value: Number) -> Result<(), String> {
        set_element_in(
            Some(&mut self.machine),
            &self.fixed.variables,
            name,
            index,
            value,
        )
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
        self.values.get(index).copied().unwrap_or(0.0)
    }

    fn set_sensor(&mut self, index: usize, value: f64) -> Result<(), String> {
        match self.values.get_mut(index) {
            Some(slot) => {
                *slot = value;
                Ok(())
            }
            None => Err(format!("there is no sensor {index}")),
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
        // A recorded sensor, named by itself when the list has it.
        let recorded = |label: &str, sensor: &str| match self.value_of(sensor) {
            Some(value) => Named {
                evaluate_name: Some(sensor.to_string()),
                ..named(label, float_text(value), "float")
            },
            None => named(label, "not in the sensor list".to_string(), "float"),
        };
        let phase = match self.phase {
            Phase::Boundary => "cycle boundary",
            Phase::InScript => "script running",
            Phase::ScriptDone => "script yielded",
            Phase::Ended => "finished",
        };
        vec![
            named("cycle", self.cycle.to_string(), "integer"),
            named("phase", phase.to_string(), "string"),
            named(
                "replay of",
                format!(
                    "{} ({} cycles)",
                    self.fixed.recording.source,
                    self.fixed.recording.len()
                ),
                "string",
            ),
            recorded("m_present_time", "m_present_time"),
            recorded("m_depth (m)", "m_depth"),
            recorded("m_pitch (rad)", "m_pitch"),
            recorded("sci_water_temp (°C)", "sci_water_temp"),
        ]
    }
}
