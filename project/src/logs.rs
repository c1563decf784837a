//! A glider's own logs as the simulator's calibration reads them: the log readers
//! (`gloc-dbd`) meet the simulator's [`Track`] here, so neither crate depends on the other.

use gloc_dbd::{CycleSource, DbdError};
use gloc_sim::calibrate::{Track, TRACK_SENSORS};

/// Reads a log (a `.dbd`, a merge, a deployment) to its end into a [`Track`].
pub fn read_track(source: &mut dyn CycleSource) -> Result<Track, DbdError> {
    let columns: Vec<Option<usize>> = TRACK_SENSORS
        .iter()
        .map(|name| {
            source
                .sensors()
                .iter()
                .position(|sensor| sensor.name == *name)
        })
        .collect();
    let mut track = Track::default();
    while let Some(cycle) = source.next_cycle()? {
        track.push(|field| columns[field].and_then(|column| cycle.value(column)));
    }
    Ok(track)
}
