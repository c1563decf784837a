//! Glider logs (`gloc-dbd`): the binary reader, its LZ4 form and the `.dba`
//! reader never panic, keep every cycle the size of the sensor list with
//! increasing offsets, and read a plain log and its LZ4-compressed copy alike.

use std::io::Cursor;

use gloc_dbd::lz4::compress;
use gloc_dbd::{CycleSource, DbaReader, DbdReader, SensorListText, SensorLists};

/// Cycles read at most (the input is at most a few kB; this bounds a slow case).
const MAX_CYCLES: usize = 100_000;

/// A factored-out sensor list is the input's own: whatever CRC is asked for.
struct OwnList(String);

impl SensorLists for OwnList {
    fn find(&self, crc: &str) -> Result<SensorListText, String> {
        Ok(SensorListText {
            text: self.0.clone(),
            origin: format!("{crc} (fuzz input)"),
        })
    }
}

/// What a reader produced: each cycle (offset, states, value bits) and how it ended.
#[derive(Debug, PartialEq)]
struct Outcome {
    sensors: usize,
    cycles: Vec<(u64, Vec<u8>, Vec<u64>)>,
    /// The error's message, or the warnings' messages.
    end: Vec<String>,
}

fn drain(mut source: Box<dyn CycleSource>, length: Option<u64>) -> Outcome {
    let sensors = source.sensors().len();
    let mut cycles = Vec::new();
    let mut end = Vec::new();
    let mut last_offset = None;
    loop {
        if cycles.len() >= MAX_CYCLES {
            break;
        }
        match source.next_cycle() {
            Ok(Some(cycle)) => {
                assert_eq!(cycle.states.len(), sensors, "a cycle's states");
                assert_eq!(cycle.values.len(), sensors, "a cycle's values");
                assert!(last_offset < Some(cycle.offset), "offsets increase");
                if let Some(length) = length {
                    assert!(cycle.offset < length, "offset inside the input");
                }
                last_offset = Some(cycle.offset);
                cycles.push((
                    cycle.offset,
                    cycle.states.iter().map(|state| *state as u8).collect(),
                    cycle.values.iter().map(|value| value.to_bits()).collect(),
                ));
            }
            Ok(None) => {
                end.extend(source.take_warnings().into_iter().map(|w| w.message));
                break;
            }
            Err(error) => {
                assert!(error.to_string().starts_with(&error.file));
                end.push(error.message);
                break;
            }
        }
    }
    Outcome { sensors, cycles, end }
}

fn open_binary(log: &[u8], list: &OwnList, compressed: bool) -> Result<Box<dyn CycleSource>, String> {
    DbdReader::new(Cursor::new(log.to_vec()), "fuzz.dbd", compressed, list)
        .map(|reader| Box::new(reader) as Box<dyn CycleSource>)
        .map_err(|error| {
            assert!(error.to_string().starts_with("fuzz.dbd: "));
            error.message
        })
}

/// Byte 0: bit 0 — the rest is LZ4 blocks (.dcd); bit 1 — the rest is a `.dba`.
/// Otherwise the rest is `LIST \0 LOG`: a sensor list for a factored log, then the log.
pub fn check_dbd_bytes(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    if mode & 2 != 0 {
        if let Ok(reader) = DbaReader::new(Cursor::new(rest.to_vec()), "fuzz.dba") {
            drain(Box::new(reader), Some(rest.len() as u64));
        }
        return;
    }
    let (list, log) = match rest.iter().position(|&byte| byte == 0) {
        Some(at) => (&rest[..at], &rest[at + 1..]),
        None => (&rest[..0], rest),
    };
    let list = OwnList(String::from_utf8_lossy(list).into_owned());
    if mode & 1 != 0 {
        if let Ok(reader) = open_binary(log, &list, true) {
            drain(reader, None);
        }
        return;
    }
    // Differential: the plain log and its LZ4 copy read to the same cycles and
    // the same end (errors and warnings name the same problem; LZ4 blocks
    // only add where they are).
    let plain = open_binary(log, &list, false).map(|reader| drain(reader, Some(log.len() as u64)));
    let packed = compress(log);
    let compressed = open_binary(&packed, &list, true).map(|reader| drain(reader, None));
    match (&plain, &compressed) {
        (Ok(a), Ok(b)) => {
            assert_eq!(a.sensors, b.sensors);
            assert_eq!(a.cycles, b.cycles, "plain and compressed cycles differ");
            // A missing end tag is no warning in a compressed file (gliders omit it).
            let a_end: Vec<&String> = a
                .end
                .iter()
                .filter(|m| !m.contains("ends without its end tag"))
                .collect();
            let b_end: Vec<&String> = b.end.iter().collect();
            assert_eq!(a_end, b_end, "plain and compressed end differently");
        }
        (Err(a), Err(b)) => assert_eq!(a, b, "plain and compressed fail differently"),
        _ => panic!("plain {plain:?} but compressed {compressed:?}"),
    }
}
