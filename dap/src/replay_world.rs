//! The replay world: the script run over a recorded deployment (a CSV file or real
//! glider logs, `gloc_replay::Recording`), one recorded cycle per control cycle. No
//! simulator: at each cycle boundary the recorded values of that cycle are written
//! into the sensor array (a sensor not updated keeps its value, as the script's
//! stores do), then the script runs its share. The whole recording is held in memory
//! and shared by every snapshot, so stepping back costs one sensor array per snapshot.

use std::sync::Arc;

use gloc_engine::program::Pc;
use gloc_engine::sensors::SensorId;
use gloc_engine::vm::{Host, Machine, MachineConfig, Status};
use gloc_replay::{Input, Recording};

use crate::error::{DebugError, DebugResult};
use crate::script::{float_text, DebugScript, LaunchConfig, ScriptState};
use crate::target::{Named, Notice, Phase, StepEvent};

/// The script over a recording: its machine and sensor array, and the recorded cycle
/// it is in. The script's own state is the world's `ScriptState`.
#[derive(Clone, Debug)]
pub(crate) struct ReplayWorld {
    /// The whole recording, shared by every snapshot.
    recording: Arc<Recording>,
    machine: Machine,
    /// The sensor array, indexed by the active list.
    values: Vec<f64>,
    /// The recorded cycle being run (0-based).
    cycle: u64,
    phase: Phase,
    notices: Vec<Notice>,
}

/// The script's view of the sensor array; prints become notices.
struct ReplayHost<'a> {
    values: &'a mut [f64],
    notices: &'a mut Vec<Notice>,
}

impl Host for ReplayHost<'_> {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        gloc_engine::vm::sensor_value(self.values, sensor)
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        gloc_engine::vm::set_sensor(self.values, sensor, value);
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
    /// opens its first cycle. Also answers the sensors the Sensors scope lists: the
    /// script's first, then the recorded ones the list has.
    pub(crate) fn launch(
        config: &LaunchConfig,
        settings: &gloc_project::Settings,
        script: &DebugScript,
    ) -> DebugResult<(ReplayWorld, Vec<usize>)> {
        let input = Input::open(&config.replay, settings.sensor_cache.as_deref())
            .map_err(|error| DebugError::launch(error.to_string()))?;
        let recording = Recording::read(input, &script.state.sensor_list)
            .map_err(|error| DebugError::launch(error.to_string()))?;
        if recording.is_empty() {
            return Err(DebugError::launch(format!(
                "{} has no recorded cycles",
                recording.source
            )));
        }
        let mut notices: Vec<Notice> = script
            .warnings()
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
        let mut touched = script.state.touched.clone();
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
            values: script.state.sensor_list.initial_values(),
            recording: Arc::new(recording),
            machine,
            cycle: 0,
            phase: Phase::Boundary,
            notices,
        };
        world.publish();
        Ok((world, touched))
    }

    /// Writes the current recorded cycle's values into the sensor array.
    fn publish(&mut self) {
        let Some(updates) = self.recording.cycle(self.cycle as usize) else {
            return;
        };
        for &(sensor, value) in updates {
            if let Some(slot) = self.values.get_mut(sensor.index()) {
                *slot = value;
            }
        }
    }

    fn summary(&self, script: &ScriptState, cut_short: bool) -> String {
        let how = if cut_short {
            format!("stopped after maxCycles = {}", self.cycle + 1)
        } else {
            "end of the recording".to_string()
        };
        let trapped = match self.machine.status() {
            Status::Trapped(trap) => format!("; script trapped: {}", script.trap_words(&trap)),
            Status::Halted => "; script halted".to_string(),
            Status::Running => String::new(),
        };
        format!(
            "replay of {}: {how} after {} of {} cycles{trapped}",
            self.recording.source,
            self.cycle + 1,
            self.recording.len()
        )
    }

    pub(crate) fn machine(&self) -> &Machine {
        &self.machine
    }

    pub(crate) fn machine_mut(&mut self) -> &mut Machine {
        &mut self.machine
    }

    pub(crate) fn cycle(&self) -> u64 {
        self.cycle
    }

    pub(crate) fn phase(&self) -> Phase {
        self.phase
    }

    /// One instruction of the script, or the next recorded cycle once its share is done.
    pub(crate) fn step(&mut self, script: &ScriptState) -> StepEvent {
        match self.phase {
            Phase::Ended => StepEvent::MissionEnded {
                summary: self.summary(script, false),
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
                let end = self.machine.step(&mut host);
                self.phase = match end {
                    None => Phase::InScript,
                    Some(_) => Phase::ScriptDone,
                };
                script.step_event(end)
            }
            Phase::ScriptDone => {
                let next = self.cycle + 1;
                let cut_short = script.max_cycles.is_some_and(|max| next >= max);
                if cut_short || next as usize >= self.recording.len() {
                    self.phase = Phase::Ended;
                    return StepEvent::MissionEnded {
                        summary: self.summary(script, cut_short),
                    };
                }
                self.cycle = next;
                self.publish();
                self.phase = Phase::Boundary;
                StepEvent::CycleBegan
            }
        }
    }

    pub(crate) fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    pub(crate) fn sensor(&self, index: usize) -> f64 {
        self.values.get(index).copied().unwrap_or(0.0)
    }

    /// Sets sensor `index`; false when there is none.
    pub(crate) fn set_sensor(&mut self, index: usize, value: f64) -> bool {
        match self.values.get_mut(index) {
            Some(slot) => {
                *slot = value;
                true
            }
            None => false,
        }
    }

    /// The cycle, the phase, the recording and the recorded vehicle's sensors.
    pub(crate) fn vehicle(&self, script: &ScriptState) -> Vec<Named> {
        let named = Named::plain;
        // A recorded sensor, named by itself when the list has it.
        let recorded = |label: &str, sensor: &str| match script.sensor_index(sensor) {
            Some(index) => Named {
                evaluate_name: Some(sensor.to_string()),
                ..named(label, float_text(self.sensor(index)), "float")
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
                    self.recording.source,
                    self.recording.len()
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
