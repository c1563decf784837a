//! Sensor lists (masterdata, `.cac`) and missions (`.mi`, `.ma`): no panic on
//! any text, spans in bounds, and what parses can be used (sensor names look
//! up to themselves; a mission without errors simulates for a few cycles).

use std::path::Path;
use std::sync::Arc;

use gloc_engine::sensors::{self, SensorList, SensorOrder};
use gloc_sim::{Mission, SimConfig, Simulation};

use crate::gloc_target::assert_spans_in_bounds;

const MISSION_PATH: &str = "fuzz/missions/fuzz.mi";

/// Cycles a fuzzed mission may run (each is a 4 s control cycle).
const MISSION_CYCLES: u32 = 40;

/// Byte 0 picks the format (masterdata in file order, masterdata sorted, `.cac`).
pub fn check_sensor_file_bytes(data: &[u8]) {
    let Some((&format, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let (list, diagnostics) = match format % 3 {
        0 => sensors::parse_masterdata(&text, SensorOrder::FileOrder),
        1 => sensors::parse_masterdata(&text, SensorOrder::default()),
        _ => sensors::parse_cac(&text),
    };
    assert_spans_in_bounds(&text, &diagnostics, "sensor file");
    check_sensor_list(&list);
}

fn check_sensor_list(list: &SensorList) {
    for (id, sensor) in list.iter() {
        assert_eq!(list.get(id).map(|found| &found.name), Some(&sensor.name));
        let found = list
            .lookup(&sensor.name)
            .unwrap_or_else(|| panic!("sensor `{}` is not found by its name", sensor.name));
        // A name listed twice (warning W0203) finds its first entry.
        let first = list.get(found).expect("lookup gives a sensor of the list");
        assert!(
            found <= id && first.name.eq_ignore_ascii_case(&sensor.name),
            "sensor `{}` at {id:?} looks up to `{}` at {found:?}",
            sensor.name,
            first.name
        );
    }
}

/// The input, split at NUL bytes: the `.mi` text, then the `.ma` files, handed
/// out in the order the mission asks for them (one more ask: not found).
pub fn check_mission_bytes(data: &[u8]) {
    let mut chunks = data
        .split(|&byte| byte == 0)
        .map(|chunk| String::from_utf8_lossy(chunk).into_owned());
    let mission_text = chunks.next().unwrap_or_default();
    let mut ma_files: Vec<String> = chunks.collect();
    ma_files.reverse();
    let mut served: Vec<(std::path::PathBuf, String)> = Vec::new();
    let mut read = |path: &Path| -> std::io::Result<String> {
        if path == Path::new(MISSION_PATH) {
            return Ok(mission_text.clone());
        }
        if let Some((_, text)) = served.iter().find(|(known, _)| known == path) {
            return Ok(text.clone());
        }
        let text = ma_files
            .pop()
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"))?;
        served.push((path.to_path_buf(), text.clone()));
        Ok(text)
    };
    let mission = Mission::load_with(Path::new(MISSION_PATH), &mut read);
    for found in &mission.diagnostics {
        let source = &mission.sources[found.file].text;
        assert_spans_in_bounds(source, std::slice::from_ref(&found.diagnostic), "mission");
    }
    if mission.has_errors() {
        return;
    }
    let sensor_list = Arc::new(SensorList::embedded());
    let config = SimConfig::default();
    let Ok(mut simulation) = Simulation::new(&mission, sensor_list, None, &config) else {
        return;
    };
    for _ in 0..MISSION_CYCLES {
        if !simulation.step_cycle() {
            break;
        }
        assert!(simulation.depth().is_finite(), "the depth stays a number");
    }
}
