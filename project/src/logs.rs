//! A glider's own logs as the simulator's calibration reads them: the log readers
//! (`gloc-dbd`) meet the simulator's [`Track`] here, so neither crate depends on the other.

use gloc_dbd::{CycleSource, DbdError};
use gloc_sim::calibrate::{track_sensors, Track, MAX_TRACK_ROWS};

/// Reads a log (a `.dbd`, a merge, a deployment) to its end into a [`Track`], at most
/// [`MAX_TRACK_ROWS`] timed cycles (refused at the byte where the limit is passed).
pub fn read_track(source: &mut dyn CycleSource) -> Result<Track, DbdError> {
    let columns = gloc_dbd::columns_of(source.sensors(), &track_sensors());
    let mut track = Track::default();
    while let Some(cycle) = source.next_cycle()? {
        track.push(|field| columns[field].and_then(|column| cycle.value(column)));
        if track.rows.len() > MAX_TRACK_ROWS {
            let at = gloc_dbd::Location {
                offset: cycle.offset,
                block: None,
            };
            return Err(DbdError::new(
                source.file(),
                at,
                format!(
                    "more than {MAX_TRACK_ROWS} timed cycles: calibrate from fewer logs (a few days of yos are plenty)"
                ),
            ));
        }
    }
    Ok(track)
}
