//! Run logs: CSV, and Slocum's ASCII format (`.dba`) as the glider's own
//! `dbd2asc` writes it, so existing glider tools read our runs.
//!
//! One row per control cycle, formatted into a reused buffer and streamed to
//! the writer: logging allocates nothing per cycle and keeps no history.

use std::io::{self, Write};

use gloc_engine::sensors::{SensorId, SensorList};

/// The log formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogFormat {
    Csv,
    /// Slocum ASCII (`dbd_label:` header, names, units, bytes, rows).
    Dba,
}

impl LogFormat {
    /// From a file name's extension: `.csv` or `.dba` (case-insensitive).
    pub fn from_path(path: &std::path::Path) -> Option<LogFormat> {
        let extension = gloc_engine::files::extension(path)?;
        match extension.as_str() {
            "csv" => Some(LogFormat::Csv),
            "dba" => Some(LogFormat::Dba),
            _ => None,
        }
    }
}

/// What a pilot looks at first, in this order. Sensors absent from the active
/// list are left out.
pub const DEFAULT_LOG_SENSORS: &[&str] = &[
    "m_present_time",
    "m_cycle_number",
    "m_depth",
    "m_pressure",
    "m_depth_rate",
    "m_pitch",
    "m_altitude",
    "m_water_depth",
    "m_speed",
    "m_ballast_pumped",
    "c_ballast_pumped",
    "c_pitch",
    "m_battery",
    "m_coulomb_amphr_total",
    "m_tot_num_inflections",
    "sci_water_temp",
    "sci_water_pressure",
    "sci_ruhp_behs",
    "sci_ruhp_dive_depth",
    "sci_ruhp_climb_depth",
    // Navigation (docs/simulator.md, "Navigation").
    "m_heading",
    "c_heading",
    "m_x_lmc",
    "m_y_lmc",
    "m_lat",
    "m_lon",
    "m_gps_lat",
    "m_gps_lon",
    "m_water_vx",
    "m_water_vy",
    "m_avg_speed",
    "x_dr_state",
    "m_dist_to_wpt",
    "c_wpt_lat",
    "c_wpt_lon",
];

/// Resolves the default set plus `extra` sensors (for example those the
/// script stores), without duplicates.
pub fn default_columns(list: &SensorList, extra: &[SensorId]) -> Vec<SensorId> {
    let mut columns: Vec<SensorId> = DEFAULT_LOG_SENSORS
        .iter()
        .filter_map(|name| list.lookup(name))
        .collect();
    for id in extra {
        if !columns.contains(id) {
            columns.push(*id);
        }
    }
    columns
}

/// Resolves a comma-separated list of sensor names. Unknown names are an
/// error naming them.
pub fn parse_columns(list: &SensorList, names: &str) -> Result<Vec<SensorId>, String> {
    let mut columns = Vec::new();
    let mut unknown = Vec::new();
    for name in names
        .split(',')
        .map(str::trim)
        .filter(|name| !name.is_empty())
    {
        match list.lookup(name) {
            Some(id) if !columns.contains(&id) => columns.push(id),
            Some(_) => {}
            None => unknown.push(name.to_string()),
        }
    }
    if !unknown.is_empty() {
        return Err(format!(
            "unknown sensor(s) for the log: {}",
            unknown.join(", ")
        ));
    }
    if columns.is_empty() {
        return Err("the list of sensors to log is empty".to_string());
    }
    Ok(columns)
}

/// Whether a run log stores the sensor as an 8-byte double: times and latitudes
/// and longitudes need one (NMEA `ddmm.mmmm` in a float is good to 1 m; comet's
/// list logs `m_lat`, `m_gps_lat`, `c_wpt_lat` as 8 bytes); everything else fits a
/// 4-byte float as the glider logs it.
pub fn logged_as_double(sensor: &gloc_engine::sensors::Sensor) -> bool {
    matches!(sensor.units.as_str(), "timestamp" | "lat" | "lon")
}

/// Header facts of a `.dba` file.
#[derive(Clone, Debug)]
pub struct DbaHeader {
    /// E.g. `gloc_sim-2010-144-0-0`.
    pub filename: String,
    pub mission_name: String,
    /// `fileopen_time:` as the glider writes it, `Mon_May_24_00:00:00_2010`.
    pub fileopen_time: String,
}

/// Streams one row per cycle.
pub struct LogWriter<W: Write> {
    out: W,
    format: LogFormat,
    columns: Vec<SensorId>,
    /// Per column: logged as a double (timestamps) rather than a 4-byte float.
    doubles: Vec<bool>,
    numbers: ryu::Buffer,
    integers: itoa::Buffer,
    /// Per column: the last value written (its bits) and its text. Most sensors change
    /// rarely from one cycle to the next, and copying the text is far cheaper than
    /// formatting the number again.
    last: Vec<Formatted>,
    line: Vec<u8>,
    rows: u64,
}

/// A number's text, kept for the next row.
#[derive(Clone, Copy)]
struct Formatted {
    bits: u64,
    length: u8,
    text: [u8; Formatted::CAPACITY],
}

impl Formatted {
    /// Longer than any text `write_number` makes: ryu's at most 24 bytes, itoa's 20.
    const CAPACITY: usize = 32;

    /// Nothing kept yet: `length` 0 never matches.
    const EMPTY: Formatted = Formatted {
        bits: 0,
        length: 0,
        text: [0; Formatted::CAPACITY],
    };
}

impl<W: Write> LogWriter<W> {
    /// Writes the header. `header` is needed for `.dba` only.
    pub fn new(
        mut out: W,
        format: LogFormat,
        columns: Vec<SensorId>,
        list: &SensorList,
        header: &DbaHeader,
    ) -> io::Result<LogWriter<W>> {
        let name = |id: &SensorId| list.name(*id).unwrap_or("unknown").to_string();
        match format {
            LogFormat::Csv => {
                let names: Vec<String> = columns.iter().map(name).collect();
                writeln!(out, "{}", names.join(","))?;
            }
            LogFormat::Dba => {
                writeln!(out, "dbd_label: DBD_ASC(dinkum_binary_data_ascii)file")?;
                writeln!(out, "encoding_ver: 2")?;
                writeln!(out, "num_ascii_tags: 14")?;
                writeln!(out, "all_sensors: 0")?;
                writeln!(out, "filename: {}", header.filename)?;
                writeln!(out, "the8x3_filename: 00000000")?;
                writeln!(out, "filename_extension: dbd")?;
                writeln!(out, "filename_label: {}-dbd(00000000)", header.filename)?;
                writeln!(out, "mission_name: {}", header.mission_name)?;
                writeln!(out, "fileopen_time: {}", header.fileopen_time)?;
                writeln!(out, "sensors_per_cycle: {}", columns.len())?;
                writeln!(out, "num_label_lines: 3")?;
                writeln!(out, "num_segments: 1")?;
                writeln!(out, "segment_filename_0: {}", header.filename)?;
                let mut names = String::new();
                let mut units = String::new();
                let mut bytes = String::new();
                for id in &columns {
                    let sensor = list.get(*id);
                    names.push_str(&name(id));
                    names.push(' ');
                    units.push_str(sensor.map(|s| s.units.as_str()).unwrap_or("nodim"));
                    units.push(' ');
                    bytes.push_str(if sensor.is_some_and(logged_as_double) {
                        "8 "
                    } else {
                        "4 "
                    });
                }
                writeln!(out, "{names}")?;
                writeln!(out, "{units}")?;
                writeln!(out, "{bytes}")?;
            }
        }
        let doubles = columns
            .iter()
            .map(|id| list.get(*id).is_some_and(logged_as_double))
            .collect();
        let column_count = columns.len();
        Ok(LogWriter {
            out,
            format,
            columns,
            doubles,
            numbers: ryu::Buffer::new(),
            integers: itoa::Buffer::new(),
            last: vec![Formatted::EMPTY; column_count],
            line: Vec::with_capacity(512),
            rows: 0,
        })
    }

    pub fn columns(&self) -> &[SensorId] {
        &self.columns
    }

    /// Writes one row from the sensor array.
    pub fn write_row(&mut self, sensors: &[f64]) -> io::Result<()> {
        self.line.clear();
        let separator = match self.format {
            LogFormat::Csv => b',',
            LogFormat::Dba => b' ',
        };
        for (position, id) in self.columns.iter().enumerate() {
            if position > 0 {
                self.line.push(separator);
            }
            let value = sensors.get(id.index()).copied().unwrap_or(f64::NAN);
            let bits = value.to_bits();
            let double = self.doubles.get(position).copied().unwrap_or(true);
            let Some(last) = self.last.get_mut(position) else {
                write_number(
                    &mut self.line,
                    (&mut self.numbers, &mut self.integers),
                    value,
                    double,
                );
                continue;
            };
            if last.length == 0 || last.bits != bits {
                last.bits = bits;
                last.length = format_into(
                    &mut last.text,
                    (&mut self.numbers, &mut self.integers),
                    value,
                    double,
                );
            }
            // A fixed-size copy (a few vector moves, no `memcpy` call), then the surplus
            // cut off.
            let end = self.line.len() + usize::from(last.length);
            self.line.extend_from_slice(&last.text);
            self.line.truncate(end);
        }
        if self.format == LogFormat::Dba {
            // dbd2asc ends every data row with a space.
            self.line.push(b' ');
        }
        self.line.push(b'\n');
        self.rows += 1;
        self.out.write_all(&self.line)
    }

    pub fn rows(&self) -> u64 {
        self.rows
    }

    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Numbers as log text, reusing its buffers (`gloc data convert`; the run log's
/// writer keeps each column's last text as well).
#[derive(Default)]
pub struct NumberText {
    numbers: ryu::Buffer,
    integers: itoa::Buffer,
}

impl NumberText {
    /// Appends `write_number`'s text for `value`.
    pub fn push(&mut self, buffer: &mut Vec<u8>, value: f64, double: bool) {
        write_number(
            buffer,
            (&mut self.numbers, &mut self.integers),
            value,
            double,
        );
    }
}

/// `write_number`'s text written into `text`; returns its length. Finite floats are
/// formatted by ryu and copied (at most 24 bytes; no `unsafe` outside the engine).
fn format_into(
    text: &mut [u8; Formatted::CAPACITY],
    (numbers, integers): (&mut ryu::Buffer, &mut itoa::Buffer),
    value: f64,
    double: bool,
) -> u8 {
    let copy = |text: &mut [u8; Formatted::CAPACITY], from: &[u8]| {
        for (to, byte) in text.iter_mut().zip(from) {
            *to = *byte;
        }
        from.len().min(Formatted::CAPACITY) as u8
    };
    if value.is_nan() {
        return copy(text, b"NaN");
    }
    // Whole, as `value == value.trunc()` asks, without `trunc` (a library call on
    // baseline x86-64): below 1e15 the cast to i64 is exact for whole numbers only.
    if value.abs() < 1e15 && (value as i64) as f64 == value {
        return copy(text, integers.format(value as i64).as_bytes());
    }
    if double && value.is_finite() {
        return copy(text, numbers.format_finite(value).as_bytes());
    }
    let single = value as f32;
    if !double && single.is_finite() {
        return copy(text, numbers.format_finite(single).as_bytes());
    }
    // Infinities (rare): ryu's own spelling.
    let spelled = if double {
        numbers.format(value)
    } else {
        numbers.format(single)
    };
    copy(text, spelled.as_bytes())
}

/// Shortest text that reads back as the same number, without allocating:
/// as an f64 for double columns, as an f32 for the rest (the glider logs
/// those as 4-byte floats). Whole numbers print without a point and
/// not-a-number as `NaN`, as dbd2asc writes them.
fn write_number(
    buffer: &mut Vec<u8>,
    (numbers, integers): (&mut ryu::Buffer, &mut itoa::Buffer),
    value: f64,
    double: bool,
) {
    if value.is_nan() {
        buffer.extend_from_slice(b"NaN");
        return;
    }
    if value == value.trunc() && value.abs() < 1e15 {
        buffer.extend_from_slice(integers.format(value as i64).as_bytes());
        return;
    }
    let text = if double {
        numbers.format(value)
    } else {
        numbers.format(value as f32)
    };
    buffer.extend_from_slice(text.as_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;
    use gloc_engine::sensors::Sensor;

    fn list() -> SensorList {
        let sensor = |name: &str, units: &str| Sensor {
            name: name.to_string(),
            units: units.to_string(),
            default: None,
            description: None,
            allowed: Default::default(),
            line: 0,
        };
        SensorList::from_sensors(vec![
            sensor("m_present_time", "timestamp"),
            sensor("m_depth", "m"),
            sensor("sci_ruhp_behs", "enum"),
        ])
    }

    fn header() -> DbaHeader {
        DbaHeader {
            filename: "gloc-2010-144-0-0".to_string(),
            mission_name: "FIG2.MI".to_string(),
            fileopen_time: "Mon_May_24_00:00:00_2010".to_string(),
        }
    }

    /// The log `format` writes of `rows`, with the test list's default columns.
    fn written(format: LogFormat, rows: &[[f64; 3]]) -> String {
        let list = list();
        let columns = default_columns(&list, &[]);
        let mut writer =
            LogWriter::new(Vec::new(), format, columns, &list, &header()).expect("header");
        for row in rows {
            writer.write_row(row).expect("row");
        }
        String::from_utf8(writer.finish().expect("flush")).expect("utf8")
    }

    #[test]
    fn csv_has_a_header_and_one_row_per_call() {
        let text = written(
            LogFormat::Csv,
            &[[1274659200.0, 15.25, 128.0], [1274659204.0, f64::NAN, 0.0]],
        );
        assert_eq!(
            text,
            "m_present_time,m_depth,sci_ruhp_behs\n1274659200,15.25,128\n1274659204,NaN,0\n"
        );
    }

    #[test]
    fn dba_has_the_dinkum_header_and_label_lines() {
        // 4-byte columns are logged at float precision, as the glider does (row 2).
        let text = written(
            LogFormat::Dba,
            &[
                [1274659200.5, 0.0, 0.0],
                [1274659204.25, 22.995130100020784, 0.1],
            ],
        );
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "dbd_label: DBD_ASC(dinkum_binary_data_ascii)file");
        assert_eq!(lines[2], "num_ascii_tags: 14");
        // 14 tag lines, then names, units, bytes, then the data.
        assert!(lines[..14].iter().all(|line| line.contains(": ")));
        assert_eq!(lines[10], "sensors_per_cycle: 3");
        assert_eq!(lines[14], "m_present_time m_depth sci_ruhp_behs ");
        assert_eq!(lines[15], "timestamp m enum ");
        assert_eq!(lines[16], "8 4 4 ");
        assert_eq!(lines[17], "1274659200.5 0 0 ");
        assert_eq!(lines[18], "1274659204.25 22.99513 0.1 ");
        assert_eq!(lines.len(), 19);
    }

    #[test]
    fn kept_texts_are_the_texts_formatting_again_would_give() {
        // Specials, whole numbers at the 1e15 edge, values that round differently as
        // f32, tiny and huge ones, and a spread of bit patterns (the one seeded generator).
        let mut values = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e15,
            1e15 - 1.0,
            -1e15,
            999_999_999_999_999.5,
            22.995130100020784,
            0.1,
            -0.4538,
            1e-7,
            3.5e38,
            -3.5e38,
            1e300,
            f64::MIN_POSITIVE,
            1274659204.25,
        ];
        let mut rng = gloc_engine::rng::Rng::new(0x9E37_79B9_7F4A_7C15);
        for _ in 0..20_000 {
            let state = rng.next_u64();
            values.push(f64::from_bits(state));
            values.push((state % 2_000_000) as f64 / 1024.0 - 900.0);
        }
        let (mut numbers, mut integers) = (ryu::Buffer::new(), itoa::Buffer::new());
        for value in values {
            for double in [false, true] {
                let mut expected = Vec::new();
                write_number(&mut expected, (&mut numbers, &mut integers), value, double);
                let mut text = [0; Formatted::CAPACITY];
                let length = format_into(&mut text, (&mut numbers, &mut integers), value, double);
                assert_eq!(
                    &text[..usize::from(length)],
                    &expected[..],
                    "{value:?} as {}",
                    if double { "f64" } else { "f32" }
                );
            }
        }
        // And through the writer: the same row twice (the second from the kept texts),
        // then a changed one.
        let text = written(
            LogFormat::Csv,
            &[[1.5, 0.1, 64.0], [1.5, 0.1, 64.0], [2.5, 0.1, f64::NAN]],
        );
        assert_eq!(
            text,
            "m_present_time,m_depth,sci_ruhp_behs\n1.5,0.1,64\n1.5,0.1,64\n2.5,0.1,NaN\n"
        );
    }

    #[test]
    fn columns_parse_by_name_and_report_unknown() {
        let list = list();
        assert_eq!(
            parse_columns(&list, "M_DEPTH, sci_ruhp_behs,m_depth").expect("ok"),
            vec![SensorId(1), SensorId(2)]
        );
        let error = parse_columns(&list, "m_depth,m_dpeth").expect_err("unknown");
        assert!(error.contains("m_dpeth"), "{error}");
        assert_eq!(
            LogFormat::from_path(std::path::Path::new("a.DBA")),
            Some(LogFormat::Dba)
        );
        assert_eq!(LogFormat::from_path(std::path::Path::new("a.txt")), None);
    }
}
