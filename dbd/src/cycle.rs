//! One cycle of a log: each sensor's state and its latest value.

use std::sync::Arc;

/// What a cycle says about a sensor (the 2 state bits of a binary log).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum State {
    /// Not updated in this cycle (bits 00).
    NotUpdated = 0,
    /// Updated with the value it already had (bits 01); no bytes follow.
    Same = 1,
    /// A new value follows in the cycle (bits 10).
    New = 2,
}

impl State {
    /// Updated in this cycle, with the same or a new value.
    pub fn is_updated(self) -> bool {
        self != State::NotUpdated
    }
}

/// A sensor as a log file has it, in the file's column order.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct FileSensor {
    pub name: String,
    pub units: String,
    /// Value size in a binary log: 1 (i8), 2 (i16), 4 (f32) or 8 (f64).
    pub bytes: u8,
}

/// The sensors of a file, shared by its reader and the cycles it gives.
pub type SensorColumns = Arc<[FileSensor]>;

/// One cycle. A reader reuses one `Cycle`, so memory does not grow with the file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cycle {
    /// Byte offset of the cycle's record (the `d` tag of a binary log, the line of a `.dba`).
    pub offset: u64,
    /// 0 for the file's first cycle.
    pub number: u64,
    /// Per sensor (file column order): updated in this cycle or not.
    pub states: Vec<State>,
    /// Per sensor: the latest value the log gave (this cycle's when updated),
    /// NaN before the first one.
    pub values: Vec<f64>,
    /// The time sensor's value (`m_present_time`, or `sci_m_present_time` in a
    /// science log) when this cycle updated it; NaN otherwise.
    pub time: f64,
    /// The columns this cycle updated (those whose state is not `NotUpdated`),
    /// each once, in no set order: a reader of a wide log (a `.dbd` lists
    /// 2,000 sensors and a cycle updates a few hundred) visits these instead of
    /// every column, and so does every merge on the way.
    pub updated: Vec<usize>,
}

impl Cycle {
    /// The sensor's value when this cycle updated it (with a new or the same value).
    pub fn value(&self, column: usize) -> Option<f64> {
        match self.states.get(column) {
            Some(state) if state.is_updated() => self.values.get(column).copied(),
            _ => None,
        }
    }

    pub(crate) fn reset(&mut self, sensors: usize) {
        self.states.clear();
        self.states.resize(sensors, State::NotUpdated);
        self.values.clear();
        self.values.resize(sensors, f64::NAN);
        self.time = f64::NAN;
        self.number = 0;
        self.offset = 0;
        self.updated.clear();
    }

    /// The start of the next cycle: the columns the last one updated are not
    /// updated any more (the values stay, the latest ones).
    pub(crate) fn clear_updates(&mut self) {
        for &column in &self.updated {
            self.states[column] = State::NotUpdated;
        }
        self.updated.clear();
    }

    /// Column `column` updated in this cycle with `state` (not `NotUpdated`) and
    /// its latest `value`.
    pub(crate) fn update(&mut self, column: usize, state: State, value: f64) {
        if self.states[column] == State::NotUpdated {
            self.updated.push(column);
        }
        self.states[column] = state;
        self.values[column] = value;
    }
}

/// The column of each of `names` among `sensors` (exact names, in the order of
/// `names`); `None` for a name the log does not have.
pub fn columns_of(sensors: &[FileSensor], names: &[&str]) -> Vec<Option<usize>> {
    names
        .iter()
        .map(|name| sensors.iter().position(|sensor| sensor.name == *name))
        .collect()
}

/// The time sensor among `sensors`: `m_present_time`, else `sci_m_present_time`
/// (dbdreader's rule).
pub fn time_column(sensors: &[FileSensor]) -> Option<usize> {
    ["m_present_time", "sci_m_present_time"]
        .iter()
        .find_map(|name| sensors.iter().position(|sensor| sensor.name == *name))
}
