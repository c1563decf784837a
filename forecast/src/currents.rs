//! Depth-averaged currents a forecast flies in: a field in time and space
//! ([`CurrentField`]), read from a CSV time series here (and from an ocean
//! model's NetCDF in [`crate::netcdf`]). Asking a field outside its time span
//! or grid is an error that says where and when.

use std::path::Path;
use std::sync::Arc;

use gloc_dbd::header::days_from_civil;
use gloc_sim::navigation::Xy;

/// Why a currents file could not be used: it cannot be read (the CLI's exit code 3), its
/// content is wrong, or its kind is not one gloc reads (both exit code 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LoadError {
    Unreadable(String),
    Invalid(String),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Unreadable(message) | LoadError::Invalid(message) => f.write_str(message),
        }
    }
}

/// A currents file by its extension, for `gloc forecast --currents` and
/// `gloc.forecast(currents=…)` alike: an ocean model's CF NetCDF (`.nc`, `.nc3`, `.cdf`,
/// `.netcdf`; averaged over `depth_range` where it has levels) or a CSV time series
/// (`.csv`, `time,u,v`); with the field, its description for the forecast's output.
pub fn load(
    path: &Path,
    depth_range: Option<(f64, f64)>,
) -> Result<(Arc<dyn CurrentField>, String), LoadError> {
    let extension = gloc_engine::files::extension(path);
    let unreadable = |error: std::io::Error| {
        LoadError::Unreadable(format!(
            "cannot read the currents `{}`: {error}",
            path.display()
        ))
    };
    let invalid = |message: String| LoadError::Invalid(format!("`{}`: {message}", path.display()));
    match extension.as_deref() {
        Some("nc" | "nc3" | "cdf" | "netcdf") => {
            gloc_engine::files::open_regular(path).map_err(unreadable)?;
            let grid = crate::netcdf::read_currents(path, depth_range).map_err(invalid)?;
            let levels = if grid.levels.is_empty() {
                String::new()
            } else {
                format!(", levels {:?} m averaged", grid.levels)
            };
            let name = format!("currents from {}{levels}", path.display());
            Ok((Arc::new(grid), name))
        }
        Some("csv") => {
            let text = gloc_engine::files::read_text(path, gloc_engine::files::PROFILE)
                .map_err(unreadable)?;
            let series = CurrentSeries::from_csv(&path.display().to_string(), &text)
                .map_err(LoadError::Invalid)?;
            Ok((
                Arc::new(series),
                format!("currents from {}", path.display()),
            ))
        }
        _ => Err(invalid(
            "give an ocean model's NetCDF (.nc) or a CSV time series `time,u,v` (.csv)".to_string(),
        )),
    }
}

/// A current that varies in time and space.
pub trait CurrentField: Send + Sync {
    /// The depth-averaged current (m/s, x east, y north) at Unix second `time`
    /// and decimal degrees `lat`, `lon`; an error outside the field.
    fn at(&self, time: f64, lat: f64, lon: f64) -> Result<Xy, String>;
}

/// A current that varies in time only: `time,u,v` rows (Unix seconds or
/// ISO 8601 UTC, m/s east and north), linear between rows.
#[derive(Clone, Debug, PartialEq)]
pub struct CurrentSeries {
    /// (time, current), strictly increasing in time.
    pub rows: Vec<(f64, Xy)>,
}

/// The most rows a CSV series may have.
pub const MAX_SERIES_ROWS: usize = 1_000_000;

impl CurrentSeries {
    /// Parses the CSV text; `path` names the file in errors (`path:line: …`).
    /// A header row is one whose first field is not a time.
    pub fn from_csv(path: &str, text: &str) -> Result<CurrentSeries, String> {
        let mut rows: Vec<(f64, Xy)> = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line_number = number + 1;
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let Some(time) = fields.first().and_then(|field| parse_time(field)) else {
                if rows.is_empty() && number == 0 {
                    continue; // the header
                }
                return Err(format!(
                    "{path}:{line_number}: `{}` is not a time: give Unix seconds or UTC as 2019-08-21T13:54:06Z",
                    fields.first().copied().unwrap_or("")
                ));
            };
            if fields.len() < 3 {
                return Err(format!(
                    "{path}:{line_number}: expected `time,u,v` (m/s east, north), found {} field(s)",
                    fields.len()
                ));
            }
            let number_at = |index: usize, what: &str| -> Result<f64, String> {
                fields[index]
                    .parse::<f64>()
                    .ok()
                    .filter(|value| value.is_finite() && value.abs() < 20.0)
                    .ok_or_else(|| {
                        format!(
                            "{path}:{line_number}: {what} `{}` is not a current in m/s (a finite number under 20)",
                            fields[index]
                        )
                    })
            };
            let water = Xy::new(number_at(1, "u")?, number_at(2, "v")?);
            if let Some((last, _)) = rows.last() {
                if time <= *last {
                    return Err(format!(
                        "{path}:{line_number}: times must increase: {time} is not after {last}"
                    ));
                }
            }
            if rows.len() >= MAX_SERIES_ROWS {
                return Err(format!(
                    "{path}:{line_number}: more than {MAX_SERIES_ROWS} rows"
                ));
            }
            rows.push((time, water));
        }
        if rows.is_empty() {
            return Err(format!("{path}: no `time,u,v` rows"));
        }
        Ok(CurrentSeries { rows })
    }
}

impl CurrentField for CurrentSeries {
    fn at(&self, time: f64, _lat: f64, _lon: f64) -> Result<Xy, String> {
        let first = self.rows[0];
        let last = self.rows[self.rows.len() - 1];
        if self.rows.len() == 1 {
            return Ok(first.1);
        }
        if time < first.0 || time > last.0 {
            return Err(format!(
                "the currents cover {} to {}; the track needs {}",
                crate::export::iso_time(first.0),
                crate::export::iso_time(last.0),
                crate::export::iso_time(time)
            ));
        }
        let after = self
            .rows
            .partition_point(|row| row.0 <= time)
            .min(self.rows.len() - 1);
        let (t0, a) = self.rows[after - 1];
        let (t1, b) = self.rows[after];
        let f = ((time - t0) / (t1 - t0)).clamp(0.0, 1.0);
        Ok(a + (b - a) * f)
    }
}

/// Unix seconds, or ISO 8601 UTC (`2019-08-21T13:54:06Z`, `2019-08-21 13:54:06`).
pub fn parse_time(text: &str) -> Option<f64> {
    if let Ok(seconds) = text.parse::<f64>() {
        return seconds.is_finite().then_some(seconds);
    }
    let text = text.trim_end_matches('Z');
    let (date, clock) = text.split_once(['T', ' '])?;
    let mut date_parts = date.split('-').map(|part| part.parse::<i64>().ok());
    let (year, month, day) = (
        date_parts.next()??,
        date_parts.next()??,
        date_parts.next()??,
    );
    let mut clock_parts = clock.split(':');
    let hour = clock_parts.next()?.parse::<i64>().ok()?;
    let minute = clock_parts
        .next()
        .map_or(Some(0), |part| part.parse::<i64>().ok())?;
    let second = clock_parts
        .next()
        .map_or(Some(0.0), |part| part.parse::<f64>().ok())?;
    if !(1..=12).contains(&month) || !(1..=31).contains(&day) || hour > 23 || minute > 59 {
        return None;
    }
    let days = days_from_civil(year, month, day);
    Some(days as f64 * 86_400.0 + (hour * 3600 + minute * 60) as f64 + second)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_currents_file_is_read_by_its_extension() {
        let dir = gloc_testsupport::scratch_dir("currents-load");
        // A CSV series: 0.2 m/s east at t = 0 and 0.4 at t = 100, so 0.3 at t = 50.
        let csv = dir.join("c.CSV");
        std::fs::write(&csv, "time,u,v\n0,0.2,0\n100,0.4,0\n").expect("write");
        let (field, name) = load(&csv, None).expect("a CSV series");
        assert_eq!(name, format!("currents from {}", csv.display()));
        let at = field.at(50.0, 54.0, 7.0).expect("inside");
        assert!((at.x - 0.3).abs() < 1e-12 && at.y == 0.0, "{at:?}");
        // Missing: unreadable; another kind: invalid, saying what to give.
        let missing = dir.join("none.nc");
        assert!(
            matches!(load(&missing, None), Err(LoadError::Unreadable(m)) if m.contains("none.nc"))
        );
        let other = dir.join("c.txt");
        std::fs::write(&other, "x").expect("write");
        assert!(
            matches!(load(&other, None), Err(LoadError::Invalid(m)) if m.contains("NetCDF (.nc) or a CSV"))
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn times_parse_as_unix_seconds_or_utc() {
        // 2019-08-21T13:54:06Z is 1566395646 (date -u -d … +%s).
        assert_eq!(parse_time("2019-08-21T13:54:06Z"), Some(1_566_395_646.0));
        assert_eq!(parse_time("2019-08-21 13:54:06"), Some(1_566_395_646.0));
        assert_eq!(parse_time("1566395646"), Some(1_566_395_646.0));
        assert_eq!(parse_time("1970-01-01T00:00:00Z"), Some(0.0));
        assert_eq!(parse_time("yesterday"), None);
    }

    #[test]
    fn a_series_interpolates_in_time_and_refuses_outside_it() {
        let series =
            CurrentSeries::from_csv("c.csv", "time,u,v\n0,0.1,0\n100,0.3,-0.2\n").expect("valid");
        let half = series.at(50.0, 54.0, 7.0).expect("inside");
        assert!((half.x - 0.2).abs() < 1e-12 && (half.y + 0.1).abs() < 1e-12);
        let error = series.at(101.0, 54.0, 7.0).expect_err("after");
        assert!(error.contains("1970-01-01T00:01:41Z"), "{error}");
        let error = CurrentSeries::from_csv("c.csv", "0,0.1,0\n0,0.2,0\n").expect_err("repeat");
        assert!(error.starts_with("c.csv:2: times must increase"), "{error}");
        let error = CurrentSeries::from_csv("c.csv", "0,0.1\n").expect_err("short");
        assert!(error.starts_with("c.csv:1: expected `time,u,v`"), "{error}");
    }
}
