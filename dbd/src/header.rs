//! The ASCII header that opens every Slocum log: `key: value` lines.

use std::io::BufRead;

use crate::error::{DbdError, Location};

/// Longest header or sensor-list line accepted (a binary file with no newline
/// must not be read into memory whole).
pub(crate) const MAX_LINE: usize = 4096;

/// The header's `key: value` pairs in file order, with typed getters.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Header {
    pub fields: Vec<(String, String)>,
}

impl Header {
    pub fn get(&self, key: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(name, _)| name == key)
            .map(|(_, value)| value.as_str())
    }

    pub fn get_number(&self, key: &str) -> Option<u64> {
        self.get(key).and_then(|value| value.parse().ok())
    }

    /// `sensor_list_crc`, lower-cased (the `.cac` file's name).
    pub fn sensor_list_crc(&self) -> Option<String> {
        self.get("sensor_list_crc").map(str::to_ascii_lowercase)
    }

    pub fn mission_name(&self) -> Option<&str> {
        self.get("mission_name")
    }

    pub fn fileopen_time(&self) -> Option<&str> {
        self.get("fileopen_time")
    }

    /// `fileopen_time` (`Wed_Aug_21_13:54:25_2019`) as Unix seconds, UTC.
    pub fn fileopen_seconds(&self) -> Option<i64> {
        parse_fileopen_time(self.fileopen_time()?)
    }

    /// The `.dbd`-style name the glider gave the file (`full_filename`, or `filename` in a `.dba`).
    pub fn full_filename(&self) -> Option<&str> {
        self.get("full_filename").or_else(|| self.get("filename"))
    }
}

/// The months as `fileopen_time` names them.
const MONTHS: [&str; 12] = [
    "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
];

/// `Wed_Aug_21_13:54:25_2019` → Unix seconds (UTC).
pub fn parse_fileopen_time(text: &str) -> Option<i64> {
    let parts: Vec<&str> = text
        .split(['_', ' '])
        .filter(|part| !part.is_empty())
        .collect();
    let [_, month, day, time, year] = parts.as_slice() else {
        return None;
    };
    let month = MONTHS.iter().position(|name| name == month)? as i64 + 1;
    let day: i64 = day.parse().ok()?;
    let year: i64 = year.parse().ok()?;
    let mut clock = time.split(':').map(|part| part.parse::<i64>().ok());
    let (hour, minute, second) = (clock.next()??, clock.next()??, clock.next()??);
    Some(days_from_civil(year, month, day) * 86_400 + hour * 3600 + minute * 60 + second)
}

/// Unix seconds (UTC, whole seconds, none before 1970) as the glider writes
/// `fileopen_time`: `Mon_May_24_00:00:00_2010`. The inverse of [`parse_fileopen_time`].
pub fn fileopen_time_text(unix_seconds: f64) -> String {
    let seconds = unix_seconds.max(0.0) as i64;
    let days = seconds.div_euclid(86_400);
    let of_day = seconds.rem_euclid(86_400);
    let (year, month, day) = civil_from_days(days);
    // 1970-01-01 was a Thursday.
    let weekday = ["Thu", "Fri", "Sat", "Sun", "Mon", "Tue", "Wed"][days.rem_euclid(7) as usize];
    let month_name = MONTHS[(month - 1) as usize];
    format!(
        "{weekday}_{month_name}_{day:02}_{:02}:{:02}:{:02}_{year}",
        of_day / 3600,
        of_day % 3600 / 60,
        of_day % 60
    )
}

/// The Unix seconds of 0000-01-01T00:00:00Z and 9999-12-31T23:59:59Z: the times
/// ISO 8601 writes with four-digit years (one outside is no date anyone wrote: a
/// corrupt log).
pub const ISO_YEARS: std::ops::RangeInclusive<f64> = -62_167_219_200.0..=253_402_300_799.0;

/// Unix seconds as ISO 8601 UTC, `2019-08-21T13:54:25Z`, to the millisecond where
/// the time has a fraction (`2019-08-21T13:54:25.500Z`); `None` outside
/// [`ISO_YEARS`] (and for NaN). The one civil-time format of `gloc data` and the
/// forecast's exports.
pub fn iso_time(unix_seconds: f64) -> Option<String> {
    if !ISO_YEARS.contains(&unix_seconds) {
        return None;
    }
    let millis = (unix_seconds * 1000.0).round() as i64;
    let seconds = millis.div_euclid(1000);
    let fraction = millis.rem_euclid(1000);
    let days = seconds.div_euclid(86_400);
    let of_day = seconds.rem_euclid(86_400);
    let (year, month, day) = civil_from_days(days);
    let fraction = if fraction > 0 {
        format!(".{fraction:03}")
    } else {
        String::new()
    };
    Some(format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}{fraction}Z",
        of_day / 3600,
        of_day / 60 % 60,
        of_day % 60
    ))
}

/// Days since 1970-01-01 of a proleptic Gregorian date (Howard Hinnant's algorithm):
/// the one calendar rule for log headers, currents files and NetCDF time units.
pub fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = year.div_euclid(400);
    let year_of_era = year - era * 400;
    let month_index = (month + 9) % 12;
    let day_of_year = (153 * month_index + 2) / 5 + day - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * 146_097 + day_of_era - 719_468
}

/// The date (year, month, day) of a day count since 1970-01-01: the inverse of
/// [`days_from_civil`] (Howard Hinnant's algorithm).
pub fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z - era * 146_097;
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_index + 2) / 5 + 1;
    let month = if month_index < 10 {
        month_index + 3
    } else {
        month_index - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// Reads one line (without its `\n`), at most [`MAX_LINE`] bytes. `Ok(None)` at the end.
pub(crate) fn read_line<R: BufRead>(
    input: &mut R,
    offset: &mut u64,
    file: &str,
    at: impl Fn(u64) -> Location,
) -> Result<Option<String>, DbdError> {
    let start = *offset;
    let mut line = Vec::new();
    loop {
        let available = input
            .fill_buf()
            .map_err(|error| crate::io_error(file, at(*offset), &error))?;
        if available.is_empty() {
            if line.is_empty() {
                return Ok(None);
            }
            break;
        }
        let newline = available.iter().position(|&byte| byte == b'\n');
        let take = newline.map_or(available.len(), |at| at + 1);
        line.extend_from_slice(&available[..take]);
        input.consume(take);
        *offset += take as u64;
        if newline.is_some() {
            line.pop();
            break;
        }
        if line.len() > MAX_LINE {
            return Err(DbdError::new(
                file,
                at(start),
                format!(
                    "a header line longer than {MAX_LINE} bytes: this is not a Slocum log header"
                ),
            ));
        }
    }
    if line.last() == Some(&b'\r') {
        line.pop();
    }
    match String::from_utf8(line) {
        Ok(text) => Ok(Some(text)),
        Err(error) => {
            // `start`, not the end minus the length: the line may end without a
            // newline (found by the fuzz target dbd_read).
            Err(DbdError::new(
                file,
                at(start + error.utf8_error().valid_up_to() as u64),
                "a header line that is not text: this is not a Slocum log header",
            ))
        }
    }
}

/// Reads the header: the first line must be `dbd_label: …`, and
/// `num_ascii_tags` says how many lines there are.
pub(crate) fn read_header<R: BufRead>(
    input: &mut R,
    offset: &mut u64,
    file: &str,
    at: impl Fn(u64) -> Location + Copy,
) -> Result<Header, DbdError> {
    let mut header = Header::default();
    let mut lines = 0u64;
    loop {
        let start = *offset;
        let Some(line) = read_line(input, offset, file, at)? else {
            let message = if lines == 0 {
                "the file is empty"
            } else {
                "the file ends inside its header"
            };
            return Err(DbdError::new(file, at(start), message));
        };
        lines += 1;
        let Some((key, value)) = line.split_once(':') else {
            return Err(not_a_log(file, at(start), lines));
        };
        let key = key.trim();
        if lines == 1 && key != "dbd_label" {
            return Err(not_a_log(file, at(start), lines));
        }
        header
            .fields
            .push((key.to_string(), value.trim().to_string()));
        let tags = header.get_number("num_ascii_tags");
        if lines > 1000 || tags.is_some_and(|tags| lines >= tags) {
            break;
        }
    }
    Ok(header)
}

fn not_a_log(file: &str, at: Location, line: u64) -> DbdError {
    let message = if line == 1 {
        "this is not a Slocum log: it does not open with `dbd_label:`".to_string()
    } else {
        format!("header line {line} is not `key: value`")
    };
    DbdError::new(file, at, message).with_help(
        "gloc reads .dbd .ebd .sbd .tbd .mbd .nbd, their compressed forms (.dcd …) and .dba",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn days_and_dates_go_both_ways() {
        // By hand: 2020-02-29 is day 18321 (`date -u -d 2020-02-29 +%s` / 86400).
        assert_eq!(days_from_civil(2020, 2, 29), 18_321);
        assert_eq!(civil_from_days(18_321), (2020, 2, 29));
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        for days in [-1000, 0, 18_321, 20_000, 60_000] {
            let (y, m, d) = civil_from_days(days);
            assert_eq!(days_from_civil(y, m, d), days);
        }
    }

    #[test]
    fn iso_times_by_hand() {
        let iso = iso_time;
        // `date -u -d @1566395665`: Wed Aug 21 13:54:25 UTC 2019.
        assert_eq!(
            iso(1_566_395_665.0).as_deref(),
            Some("2019-08-21T13:54:25Z")
        );
        assert_eq!(
            iso(1_566_395_665.5).as_deref(),
            Some("2019-08-21T13:54:25.500Z")
        );
        // Less than half a millisecond short of the next second is that second.
        assert_eq!(
            iso(1_566_395_665.999_6).as_deref(),
            Some("2019-08-21T13:54:26Z")
        );
        assert_eq!(iso(0.0).as_deref(), Some("1970-01-01T00:00:00Z"));
        assert_eq!(iso(-1.0).as_deref(), Some("1969-12-31T23:59:59Z"));
        // A leap day: 2020-02-29 is day 18321.
        assert_eq!(
            iso(18_321.0 * 86_400.0).as_deref(),
            Some("2020-02-29T00:00:00Z")
        );
        // The ends of four-digit years, and past them.
        assert_eq!(
            iso(253_402_300_799.0).as_deref(),
            Some("9999-12-31T23:59:59Z")
        );
        assert_eq!(
            iso(-62_167_219_200.0).as_deref(),
            Some("0000-01-01T00:00:00Z")
        );
        assert_eq!(iso(253_402_300_800.0), None);
        assert_eq!(iso(1e300), None);
        assert_eq!(iso(f64::NAN), None);
    }

    #[test]
    fn fileopen_time_is_utc_seconds() {
        // 2019-08-21 13:54:25 UTC = 1566395665 (date -u -d '2019-08-21 13:54:25' +%s).
        assert_eq!(
            parse_fileopen_time("Wed_Aug_21_13:54:25_2019"),
            Some(1_566_395_665)
        );
        assert_eq!(parse_fileopen_time("Thu_Jan__1_00:00:00_1970"), Some(0));
        assert_eq!(parse_fileopen_time("garbage"), None);
    }

    #[test]
    fn fileopen_time_text_is_the_gliders_and_reads_back() {
        // 2010-05-24 00:00:00 UTC was a Monday; 2019-08-21 13:54:25 UTC (above) a Wednesday.
        assert_eq!(
            fileopen_time_text(1_274_659_200.0),
            "Mon_May_24_00:00:00_2010"
        );
        assert_eq!(fileopen_time_text(0.0), "Thu_Jan_01_00:00:00_1970");
        assert_eq!(
            fileopen_time_text(1_566_395_665.0),
            "Wed_Aug_21_13:54:25_2019"
        );
        for seconds in [0, 1_274_659_200, 1_566_395_665, 4_102_444_799] {
            let text = fileopen_time_text(seconds as f64);
            assert_eq!(parse_fileopen_time(&text), Some(seconds), "{text}");
        }
    }
}
