//! Small logs assembled byte by byte in the test, with the values worked out
//! by hand: both byte orders, every value size, the three states, truncation,
//! corrupt LZ4, a wrong CRC, an empty file, a missing sensor list.

use std::collections::HashMap;
use std::io::Cursor;

use gloc_dbd::lz4::compress;
use gloc_dbd::{
    sensor_list_crc, CacheFolders, CycleSource, DbaReader, DbdReader, NoSensorLists, State,
};

/// Four sensors: a (1 byte), b (2), c (4), m_present_time (8).
const LIST: &str = "s: T    0    0 1 a nodim\n\
                    s: T    1    1 2 b nodim\n\
                    s: T    2    2 4 c nodim\n\
                    s: T    3    3 8 m_present_time timestamp\n";

fn header(crc: &str, factored: bool) -> String {
    format!(
        "dbd_label:    DBD(dinkum_binary_data)file\n\
         encoding_ver:    5\n\
         num_ascii_tags:    8\n\
         mission_name:    TEST.MI\n\
         total_num_sensors:    4\n\
         sensors_per_cycle:    4\n\
         state_bytes_per_cycle:    1\n\
         sensor_list_crc:    {crc}\n\
         sensor_list_factored:    {}\n",
        u8::from(factored)
    )
    .replace("num_ascii_tags:    8", "num_ascii_tags:    9")
}

/// The known cycle and two cycles, little- or big-endian, worked by hand:
/// cycle 1: state 0xAA (all four new): a = -3, b = 258, c = 1.5, t = 100.0;
/// cycle 2: state 0x4A = 01 00 10 10 (a same, b not updated, c and t new):
/// c = 2.5, t = 104.0. Then the end tag.
fn body(big: bool) -> Vec<u8> {
    let mut bytes = vec![b's', b'a'];
    if big {
        bytes.extend_from_slice(&[0x12, 0x34]);
        bytes.extend_from_slice(&[0x42, 0xF6, 0xE9, 0x79]); // 123.456f32
        bytes.extend_from_slice(&[0x41, 0x9D, 0x6F, 0x34, 0x54, 0x7E, 0x69, 0xAD]);
    // 123456789.12345 (struct.pack(">d", …) in Python)
    } else {
        bytes.extend_from_slice(&[0x34, 0x12]);
        bytes.extend_from_slice(&[0x79, 0xE9, 0xF6, 0x42]);
        bytes.extend_from_slice(&[0xAD, 0x69, 0x7E, 0x54, 0x34, 0x6F, 0x9D, 0x41]);
    }
    // Cycle 1.
    bytes.extend_from_slice(&[b'd', 0xAA, 0xFD]);
    if big {
        bytes.extend_from_slice(&[0x01, 0x02]); // 258
        bytes.extend_from_slice(&[0x3F, 0xC0, 0x00, 0x00]); // 1.5
        bytes.extend_from_slice(&[0x40, 0x59, 0, 0, 0, 0, 0, 0]); // 100.0
    } else {
        bytes.extend_from_slice(&[0x02, 0x01]);
        bytes.extend_from_slice(&[0x00, 0x00, 0xC0, 0x3F]);
        bytes.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0x59, 0x40]);
    }
    // Cycle 2.
    bytes.extend_from_slice(&[b'd', 0x4A]);
    if big {
        bytes.extend_from_slice(&[0x40, 0x20, 0x00, 0x00]); // 2.5
        bytes.extend_from_slice(&[0x40, 0x5A, 0, 0, 0, 0, 0, 0]); // 104.0
    } else {
        bytes.extend_from_slice(&[0x00, 0x00, 0x20, 0x40]);
        bytes.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0x5A, 0x40]);
    }
    bytes.push(b'X');
    bytes
}

fn list_crc() -> String {
    format!("{:08x}", sensor_list_crc(LIST.as_bytes()))
}

fn unfactored(big: bool) -> Vec<u8> {
    let mut bytes = header(&list_crc(), false).into_bytes();
    bytes.extend_from_slice(LIST.as_bytes());
    bytes.extend_from_slice(&body(big));
    bytes
}

fn read(bytes: Vec<u8>) -> DbdReader {
    DbdReader::new(Cursor::new(bytes), "test.dbd", false, &NoSensorLists)
        .unwrap_or_else(|error| panic!("{error}"))
}

fn check_two_cycles(mut reader: DbdReader) {
    assert_eq!(reader.sensors().len(), 4);
    assert_eq!(reader.time_column(), Some(3));
    let first = reader.next_cycle().expect("ok").expect("cycle 1").clone();
    assert_eq!(first.states, vec![State::New; 4]);
    assert_eq!(first.values, vec![-3.0, 258.0, 1.5, 100.0]);
    assert_eq!(first.time, 100.0);
    let second = reader.next_cycle().expect("ok").expect("cycle 2").clone();
    assert_eq!(
        second.states,
        vec![State::Same, State::NotUpdated, State::New, State::New]
    );
    assert_eq!(second.value(0), Some(-3.0), "same: the previous value");
    assert_eq!(second.value(1), None, "not updated");
    assert_eq!(second.value(2), Some(2.5));
    assert_eq!(second.time, 104.0);
    assert_eq!(second.number, 1);
    assert!(reader.next_cycle().expect("ok").is_none());
    assert!(reader.take_warnings().is_empty());
}

#[test]
fn little_endian_every_size_and_state() {
    let reader = read(unfactored(false));
    assert_eq!(reader.byte_order(), gloc_dbd::ByteOrder::Little);
    check_two_cycles(reader);
}

#[test]
fn big_endian_every_size_and_state() {
    let reader = read(unfactored(true));
    assert_eq!(reader.byte_order(), gloc_dbd::ByteOrder::Big);
    check_two_cycles(reader);
}

#[test]
fn factored_list_from_a_cache_with_its_crc() {
    let crc = format!("{:08x}", sensor_list_crc(LIST.as_bytes()));
    let mut bytes = header(&crc, true).into_bytes();
    bytes.extend_from_slice(&body(false));
    let lists = HashMap::from([(crc.clone(), LIST.to_string())]);
    let reader = DbdReader::new(Cursor::new(bytes), "f.dbd", false, &lists).expect("reads");
    assert_eq!(reader.sensor_list_crc(), crc);
    check_two_cycles(reader);
}

#[test]
fn compressed_file_reads_like_the_plain_one() {
    let bytes = compress(&unfactored(true));
    let reader =
        DbdReader::new(Cursor::new(bytes), "test.dcd", true, &NoSensorLists).expect("reads");
    check_two_cycles(reader);
}

#[test]
fn truncated_file_keeps_the_complete_cycles_and_warns_with_the_offset() {
    let mut bytes = unfactored(false);
    let header_length = header(&list_crc(), false).len() + LIST.len();
    // Known cycle 16 bytes, cycle 1 is 1 + 1 + 1 + 2 + 4 + 8 = 17 bytes: cycle 2 starts here.
    let second = header_length + 16 + 17;
    assert_eq!(bytes[second], b'd');
    bytes.truncate(second + 4);
    let mut reader = read(bytes);
    assert!(reader.next_cycle().expect("ok").is_some());
    assert!(reader.next_cycle().expect("ok").is_none());
    let warnings = reader.take_warnings();
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].at.offset, second as u64);
    assert!(
        warnings[0].message.contains("ends inside a cycle"),
        "{}",
        warnings[0]
    );
}

#[test]
fn a_file_without_its_end_tag_warns() {
    let mut bytes = unfactored(false);
    bytes.pop();
    let mut reader = read(bytes);
    while reader.next_cycle().expect("ok").is_some() {}
    let warnings = reader.take_warnings();
    assert!(warnings[0].message.contains("end tag"), "{warnings:?}");
}

#[test]
fn corrupt_lz4_block_is_an_error_with_the_block_offset() {
    let good = compress(&unfactored(false));
    // The first block's length, then a payload of the same length that is not LZ4:
    // a literal run announcing 15+ bytes, then an extension byte beyond the input.
    let length = u16::from_be_bytes([good[0], good[1]]) as usize;
    let mut bytes = good[..2].to_vec();
    bytes.extend(std::iter::repeat_n(0xFFu8, length));
    let error = DbdReader::new(Cursor::new(bytes), "bad.dcd", true, &NoSensorLists)
        .err()
        .expect("an error");
    assert_eq!(error.at.block, Some(0));
    assert!(error.message.contains("corrupt LZ4"), "{error}");
    assert!(error.to_string().starts_with("bad.dcd: "), "{error}");
}

#[test]
fn truncated_lz4_block_keeps_what_came_before() {
    // Two blocks: the whole header and the known cycle and cycle 1 in the first,
    // the rest in the second, which is then cut.
    let plain = unfactored(false);
    let split = header(&list_crc(), false).len() + LIST.len() + 16 + 17;
    let mut bytes = Vec::new();
    for part in [&plain[..split], &plain[split..]] {
        let block = lz4_flex::block::compress(part);
        bytes.extend_from_slice(&(block.len() as u16).to_be_bytes());
        bytes.extend_from_slice(&block);
    }
    bytes.truncate(bytes.len() - 3);
    let mut reader =
        DbdReader::new(Cursor::new(bytes), "cut.dcd", true, &NoSensorLists).expect("reads");
    assert!(reader.next_cycle().expect("ok").is_some());
    assert!(reader.next_cycle().expect("ok").is_none());
    let warnings = reader.take_warnings();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].message.contains("ends inside an LZ4 block"),
        "{}",
        warnings[0]
    );
}

#[test]
fn a_list_that_does_not_fit_and_has_another_crc_is_an_error() {
    let other = "s: T    0    0 4 c nodim\n";
    let mut bytes = header("12345678", true).into_bytes();
    bytes.extend_from_slice(&body(false));
    let lists = HashMap::from([("12345678".to_string(), other.to_string())]);
    let error = DbdReader::new(Cursor::new(bytes), "w.dbd", false, &lists)
        .err()
        .expect("an error");
    let text = error.to_string();
    assert!(
        text.contains("12345678")
            && text.contains(&format!("{:08x}", sensor_list_crc(other.as_bytes()))),
        "{text}"
    );
}

#[test]
fn a_list_that_fits_under_another_crc_is_read_with_a_warning() {
    let mut bytes = header("12345678", true).into_bytes();
    bytes.extend_from_slice(&body(false));
    let lists = HashMap::from([("12345678".to_string(), LIST.to_string())]);
    let mut reader = DbdReader::new(Cursor::new(bytes), "w.dbd", false, &lists).expect("reads");
    let warnings = reader.take_warnings();
    assert!(
        warnings[0].message.contains("is not the CRC"),
        "{warnings:?}"
    );
    check_two_cycles(reader);
}

#[test]
fn empty_file_and_text_file_are_clear_errors() {
    let empty = DbdReader::new(Cursor::new(Vec::new()), "e.dbd", false, &NoSensorLists)
        .err()
        .expect("an error");
    assert_eq!(empty.to_string(), "e.dbd: byte 0: the file is empty");
    let text = DbdReader::new(
        Cursor::new(b"time,depth\n1,2\n".to_vec()),
        "t.dbd",
        false,
        &NoSensorLists,
    )
    .err()
    .expect("an error");
    assert!(
        text.message.contains("does not open with `dbd_label:`"),
        "{text}"
    );
    let binary = DbdReader::new(
        Cursor::new(vec![0u8; 10_000]),
        "z.dbd",
        false,
        &NoSensorLists,
    )
    .err()
    .expect("an error");
    assert!(binary.message.contains("not"), "{binary}");
}

#[test]
fn invalid_state_bits_are_an_error_at_their_byte() {
    let mut bytes = unfactored(false);
    let first = header(&list_crc(), false).len() + LIST.len() + 16;
    bytes[first + 1] = 0xFF;
    let mut reader = read(bytes);
    let error = reader.next_cycle().expect_err("an error");
    assert_eq!(error.at.offset, first as u64 + 1);
}

#[test]
fn missing_sensor_list_names_the_crc_and_every_folder() {
    let folder = gloc_testsupport::scratch_dir("dbd-missing");
    std::fs::create_dir_all(&folder).expect("temp folder");
    let path = folder.join("x.dbd");
    let mut bytes = header("abcdef01", true).into_bytes();
    bytes.extend_from_slice(&body(false));
    std::fs::write(&path, bytes).expect("write");
    let cache = folder.join("cache");
    let error = gloc_dbd::open_path(&path, Some(&cache))
        .err()
        .expect("an error");
    let text = error.to_string();
    assert!(
        text.contains("abcdef01.cac") && text.contains("abcdef01.ccc"),
        "{text}"
    );
    for searched in CacheFolders::standard(Some(&cache), &path).folders {
        assert!(text.contains(&searched.display().to_string()), "{text}");
    }
    // Renamed to .txt: refused by its extension, with what it looks like.
    let renamed = folder.join("x.txt");
    std::fs::copy(&path, &renamed).expect("copy");
    let error = gloc_dbd::open_path(&renamed, None).err().expect("an error");
    assert!(error.message.contains("opens like a Slocum log"), "{error}");
    // With the list in the cache folder, compressed (.ccc), it reads.
    std::fs::create_dir_all(&cache).expect("cache");
    let crc = format!("{:08x}", sensor_list_crc(LIST.as_bytes()));
    let mut bytes = header(&crc, true).into_bytes();
    bytes.extend_from_slice(&body(false));
    std::fs::write(&path, bytes).expect("write");
    std::fs::write(cache.join(format!("{crc}.ccc")), compress(LIST.as_bytes())).expect("ccc");
    let mut reader = gloc_dbd::open_path(&path, Some(&cache)).expect("reads");
    assert_eq!(
        reader.next_cycle().expect("ok").expect("cycle").values[1],
        258.0
    );
    std::fs::remove_dir_all(&folder).ok();
}

#[test]
fn dba_reads_values_and_nan_as_not_updated() {
    let text = "dbd_label: DBD_ASC(dinkum_binary_data_ascii)file\n\
                encoding_ver: 2\n\
                num_ascii_tags: 3\n\
                m_present_time m_depth c_pitch \n\
                timestamp m rad \n\
                8 4 4 \n\
                100.5 1.25 NaN \n\
                104 0.1 -0.4 \n";
    let mut reader = DbaReader::new(Cursor::new(text.as_bytes().to_vec()), "a.dba").expect("reads");
    let first = reader.next_cycle().expect("ok").expect("row").clone();
    assert_eq!(first.time, 100.5);
    assert_eq!(first.value(1), Some(1.25));
    assert_eq!(first.value(2), None);
    let second = reader.next_cycle().expect("ok").expect("row").clone();
    // A 4-byte column reads as a float32, as the binary log held it.
    assert_eq!(second.value(1), Some(0.1f32 as f64));
    assert_eq!(second.value(2), Some(-0.4f32 as f64));
    assert!(reader.next_cycle().expect("ok").is_none());
    let bad = "dbd_label: DBD_ASC(x)file\nnum_ascii_tags: 2\na b\nx x\n4 4\n1 zz\n";
    let mut reader = DbaReader::new(Cursor::new(bad.as_bytes().to_vec()), "b.dba").expect("header");
    let error = reader.next_cycle().expect_err("an error");
    // "1 zz": the bad token starts 2 bytes into the line, which starts at byte 44.
    assert_eq!(error.at.offset, bad.find("1 zz").expect("line") as u64 + 2);
}

#[test]
fn merge_puts_the_latest_science_value_at_or_before_each_flight_cycle() {
    // Flight cycles at t = 100 and 104 (the hand-made log above).
    let flight = Box::new(read(unfactored(false)));
    let science = "dbd_label: DBD_ASC(dinkum_binary_data_ascii)file\n\
                   num_ascii_tags: 2\n\
                   sci_m_present_time sci_water_temp \n\
                   timestamp degc \n\
                   8 8 \n\
                   99 10 \n\
                   101 11 \n\
                   103.5 12 \n\
                   105 13 \n";
    let science =
        Box::new(DbaReader::new(Cursor::new(science.as_bytes().to_vec()), "s.dba").expect("reads"));
    let mut merged = gloc_dbd::Merged::new(flight, science);
    let names: Vec<&str> = merged.sensors().iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "a",
            "b",
            "c",
            "m_present_time",
            "sci_m_present_time",
            "sci_water_temp"
        ]
    );
    let first = merged.next_cycle().expect("ok").expect("cycle").clone();
    assert_eq!(first.time, 100.0);
    assert_eq!(first.value(5), Some(10.0), "99 ≤ 100 < 101");
    let second = merged.next_cycle().expect("ok").expect("cycle").clone();
    assert_eq!(second.time, 104.0);
    assert_eq!(second.value(4), Some(103.5));
    assert_eq!(second.value(5), Some(12.0), "103.5 ≤ 104 < 105");
    assert_eq!(second.value(0), Some(-3.0), "flight columns pass through");
    assert!(
        merged.next_cycle().expect("ok").is_none(),
        "105 is after the last flight cycle"
    );
}

#[test]
fn writer_bytes_worked_by_hand_and_read_back() {
    use gloc_dbd::{DbdWriter, ListSensor, LogIdentity, WrittenList};
    let list = WrittenList::new(&[
        ListSensor {
            name: "m_present_time".into(),
            units: "timestamp".into(),
            bytes: 8,
            logged: true,
        },
        ListSensor {
            name: "x_unlogged".into(),
            units: "".into(),
            bytes: 4,
            logged: false,
        },
        ListSensor {
            name: "m_depth".into(),
            units: "m".into(),
            bytes: 4,
            logged: true,
        },
    ]);
    assert_eq!(
        list.text,
        "s: T    0    0 8 m_present_time timestamp\ns: F    1   -1 4 x_unlogged nodim\ns: T    2    1 4 m_depth m\n"
    );
    let identity = LogIdentity {
        full_filename: "gloc-2019-222-0-0".into(),
        the8x3_filename: "00000000".into(),
        filename_extension: "dbd".into(),
        mission_name: "TEST.MI".into(),
        fileopen_time: "Wed_Aug_21_13:54:25_2019".into(),
    };
    let mut writer = DbdWriter::new(Vec::new(), &identity, &list).expect("header");
    writer.write_cycle(&[100.0, 1.5]).expect("cycle");
    writer.write_cycle(&[104.0, 1.5]).expect("cycle");
    let bytes = writer.finish().expect("end");
    let body = &bytes[bytes.len() - (16 + 14 + 10 + 1)..];
    // Known cycle, little-endian.
    assert_eq!(&body[..4], &[b's', b'a', 0x34, 0x12]);
    // Cycle 1: both new = 10 10 00 00 = 0xA0, then 100.0 and 1.5f32.
    assert_eq!(&body[16..18], &[b'd', 0xA0]);
    assert_eq!(&body[18..26], &100.0f64.to_le_bytes());
    assert_eq!(&body[26..30], &[0x00, 0x00, 0xC0, 0x3F]);
    // Cycle 2: only the time changed = 10 00 00 00 = 0x80, then 104.0; then `X`.
    assert_eq!(&body[30..32], &[b'd', 0x80]);
    assert_eq!(&body[32..40], &104.0f64.to_le_bytes());
    assert_eq!(body[40], b'X');
    let lists = HashMap::from([(list.crc.clone(), list.text.clone())]);
    let mut reader = DbdReader::new(Cursor::new(bytes), "w.dbd", false, &lists).expect("reads");
    let first = reader.next_cycle().expect("ok").expect("cycle").clone();
    assert_eq!((first.time, first.value(1)), (100.0, Some(1.5)));
    let second = reader.next_cycle().expect("ok").expect("cycle").clone();
    assert_eq!((second.time, second.value(1)), (104.0, None));
    assert!(reader.next_cycle().expect("ok").is_none());
    assert!(reader.take_warnings().is_empty());
}

#[test]
fn a_header_line_that_is_not_text_at_the_end_is_an_error_at_its_byte() {
    // Found by the fuzz target dbd_read: the last line has no newline and an
    // invalid UTF-8 byte at offset 11; the offset was computed assuming a newline.
    let error = DbdReader::new(
        Cursor::new(b"dbd_label: \xff".to_vec()),
        "u.dbd",
        false,
        &NoSensorLists,
    )
    .err()
    .expect("an error");
    assert_eq!(error.at.offset, 11);
    assert!(error.message.contains("not text"), "{error}");
}
