//! The debugged world: the GLOC interpreter inside the glider simulator.
//!
//! Interim: the engine and simulator are not merged yet, so no world can be built and
//! `launch` says so. `World` is uninhabited until then.

use std::path::PathBuf;

use crate::expr::Number;
use crate::program::DebugInfo;
use crate::target::{Named, Notice, Phase, StepEvent, Target};

/// What `launch` needs, already checked for types by the session.
#[derive(Clone, Debug, Default)]
pub struct LaunchConfig {
    pub program: PathBuf,
    pub mission: Option<PathBuf>,
    pub masterdata: Option<PathBuf>,
    pub profile: Option<PathBuf>,
    pub seed: Option<u64>,
    pub cycle_budget: Option<u64>,
    pub max_cycles: Option<u64>,
}

#[derive(Clone, Debug)]
pub enum World {}

pub fn launch(config: &LaunchConfig) -> Result<(World, DebugInfo), String> {
    Err(format!(
        "cannot launch {}: the simulator is not part of this build yet",
        config.program.display()
    ))
}

impl Target for World {
    fn cycle(&self) -> u64 {
        match *self {}
    }
    fn phase(&self) -> Phase {
        match *self {}
    }
    fn pc(&self) -> usize {
        match *self {}
    }
    fn step(&mut self) -> StepEvent {
        match *self {}
    }
    fn take_notices(&mut self) -> Vec<Notice> {
        match *self {}
    }
    fn registers(&self) -> Vec<Number> {
        match *self {}
    }
    fn set_register(&mut self, _: usize, _: Number) -> Result<(), String> {
        match *self {}
    }
    fn variables(&self) -> Vec<Named> {
        match *self {}
    }
    fn variable(&self, _: &str) -> Option<Number> {
        match *self {}
    }
    fn set_variable(&mut self, _: &str, _: Number) -> Result<(), String> {
        match *self {}
    }
    fn sensor_count(&self) -> usize {
        match *self {}
    }
    fn sensor_name(&self, _: usize) -> Option<&str> {
        match *self {}
    }
    fn sensor_index(&self, _: &str) -> Option<usize> {
        match *self {}
    }
    fn sensor(&self, _: usize) -> f64 {
        match *self {}
    }
    fn set_sensor(&mut self, _: usize, _: f64) -> Result<(), String> {
        match *self {}
    }
    fn touched_sensors(&self) -> Vec<usize> {
        match *self {}
    }
    fn vehicle(&self) -> Vec<Named> {
        match *self {}
    }
}
