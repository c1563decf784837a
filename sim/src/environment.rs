//! The water around the glider: depth, a temperature profile, and seeded
//! sensor noise.

use std::path::Path;

use gloc_engine::LineIndex;

/// Temperature against depth.
#[derive(Clone, Debug, PartialEq)]
pub enum TemperatureProfile {
    /// The built-in summer shelf profile (domain notes §4):
    /// `T(z) = Tb + (Ts − Tb) · ½ · (1 − tanh((z − zc) / h))`.
    Shelf {
        surface: f64,
        bottom: f64,
        center: f64,
        width: f64,
    },
    /// Measured points `(depth_m, temp_degC)`, depth strictly increasing;
    /// linear in between, constant beyond the ends.
    Table(Vec<(f64, f64)>),
}

impl Default for TemperatureProfile {
    /// A New Jersey shelf in summer: 23 °C at the surface, 9.5 °C Cold Pool
    /// below, thermocline centred at 16 m, 4 m wide.
    fn default() -> TemperatureProfile {
        TemperatureProfile::Shelf {
            surface: 23.0,
            bottom: 9.5,
            center: 16.0,
            width: 4.0,
        }
    }
}

impl TemperatureProfile {
    pub fn temperature(&self, depth: f64) -> f64 {
        match self {
            TemperatureProfile::Shelf {
                surface,
                bottom,
                center,
                width,
            } => {
                bottom
                    + (surface - bottom) * 0.5 * (1.0 - ((depth - center) / width.max(1e-6)).tanh())
            }
            TemperatureProfile::Table(points) => interpolate(points, depth),
        }
    }

    /// Reads a CSV profile. The first line that is not blank or a `#` comment
    /// names the columns; the depth column (`depth_m`, `depth(m)`) and the
    /// temperature column (`temp_degC`, `temperature(degC)`, `sci_water_temp`)
    /// are found by name, in any order, with their units checked; other
    /// columns are ignored. Errors name the line and column.
    pub fn from_csv(path: &Path, text: &str) -> Result<TemperatureProfile, Box<ProfileError>> {
        let index = LineIndex::new(text);
        let error = |offset: usize, message: String| {
            let (line, column) = index.line_col(text, offset);
            Box::new(ProfileError {
                path: path.to_path_buf(),
                line,
                column,
                message,
            })
        };
        let mut points: Vec<(f64, f64)> = Vec::new();
        let mut offset = 0;
        let mut columns: Option<(usize, usize, [String; 2])> = None;
        for raw in text.split_inclusive('\n') {
            let start = offset;
            offset += raw.len();
            let line = raw.trim_end_matches(['\n', '\r']);
            let trimmed = line.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            // Each field with its byte offset in the text.
            let mut fields: Vec<(usize, &str)> = Vec::new();
            let mut at = start;
            for field in line.split(',') {
                fields.push((at, field));
                at += field.len() + 1;
            }
            let Some((depth_column, temp_column, names)) = &columns else {
                columns = Some(header_columns(&fields, start, line, &error)?);
                continue;
            };
            let mut values = [0.0; 2];
            for (slot, &column) in [*depth_column, *temp_column].iter().enumerate() {
                let name = &names[slot];
                let Some(&(field_start, field)) = fields.get(column) else {
                    return Err(error(
                        start + line.len(),
                        format!(
                            "the row has {} column{}; `{name}` is column {}",
                            fields.len(),
                            if fields.len() == 1 { "" } else { "s" },
                            column + 1
                        ),
                    ));
                };
                let lead = field.len() - field.trim_start().len();
                let cell = field.trim();
                if cell.is_empty() {
                    return Err(error(
                        field_start,
                        format!("the `{name}` cell is empty: give a number"),
                    ));
                }
                match cell.parse::<f64>() {
                    Ok(value) if value.is_finite() => values[slot] = value,
                    _ => {
                        return Err(error(
                            field_start + lead,
                            format!("`{cell}` is not a number (column `{name}`)"),
                        ))
                    }
                }
            }
            if let Some(&(last_depth, _)) = points.last() {
                if values[0] <= last_depth {
                    let (field_start, field) = fields[*depth_column];
                    return Err(error(
                        field_start + (field.len() - field.trim_start().len()),
                        format!(
                            "depth {} is not below the previous row's {last_depth}: sort the rows by depth",
                            values[0]
                        ),
                    ));
                }
            }
            points.push((values[0], values[1]));
        }
        if points.is_empty() {
            let message = if columns.is_none() {
                "the profile is empty: a header naming `depth_m` and `temp_degC`, then rows"
            } else {
                "the profile has a header but no data rows"
            };
            return Err(error(text.len(), message.to_string()));
        }
        Ok(TemperatureProfile::Table(points))
    }
}

/// A column name's quantity and unit: `depth_m`, `depth(m)`, `depth [m]`.
fn quantity_and_unit(name: &str) -> (String, Option<String>) {
    let name = name.trim();
    for (open, close) in [('(', ')'), ('[', ']')] {
        if let (Some(at), true) = (name.find(open), name.ends_with(close)) {
            return (
                name[..at].trim().to_ascii_lowercase(),
                Some(name[at + 1..name.len() - 1].trim().to_string()),
            );
        }
    }
    let lower = name.to_ascii_lowercase();
    if lower == "sci_water_temp" {
        return (lower, Some("degC".to_string()));
    }
    match name.rfind('_') {
        Some(at) => (lower[..at].to_string(), Some(name[at + 1..].to_string())),
        None => (lower, None),
    }
}

const DEPTH_NAMES: [&str; 1] = ["depth"];
const TEMP_NAMES: [&str; 4] = ["temp", "temperature", "sci_water_temp", "water_temp"];

/// Finds the depth and temperature columns in a header line and checks their units.
fn header_columns(
    fields: &[(usize, &str)],
    start: usize,
    line: &str,
    error: &dyn Fn(usize, String) -> Box<ProfileError>,
) -> Result<(usize, usize, [String; 2]), Box<ProfileError>> {
    let mut depth = None;
    let mut temp = None;
    for (column, &(at, field)) in fields.iter().enumerate() {
        let (quantity, unit) = quantity_and_unit(field);
        let lead = field.len() - field.trim_start().len();
        let name = field.trim();
        if quantity.parse::<f64>().is_ok() || name.parse::<f64>().is_ok() {
            return Err(error(
                at + lead,
                "the first line must name the columns, e.g. `depth_m,temp_degC` (any order; other columns are ignored)".to_string(),
            ));
        }
        let (slot, wanted, units): (&mut Option<usize>, &str, &[&str]) =
            if DEPTH_NAMES.contains(&quantity.as_str()) {
                (&mut depth, "depth_m", &["m"])
            } else if TEMP_NAMES.contains(&quantity.as_str()) {
                (&mut temp, "temp_degC", &["degC", "C", "°C", "degc"])
            } else {
                continue;
            };
        match unit {
            Some(unit) if units.contains(&unit.as_str()) => {}
            Some(unit) => {
                return Err(error(
                    at + lead,
                    format!(
                        "column `{name}` is in `{unit}`; gloc reads {} (name the column `{wanted}`, converting the values)",
                        units[0]
                    ),
                ))
            }
            None => {
                return Err(error(
                    at + lead,
                    format!("column `{name}` has no unit: name it `{wanted}`"),
                ))
            }
        }
        if slot.is_some() {
            return Err(error(
                at + lead,
                format!(
                    "a second {} column `{name}`",
                    &wanted[..wanted.find('_').unwrap_or(0)]
                ),
            ));
        }
        *slot = Some(column);
    }
    let missing = match (depth, temp) {
        (Some(depth), Some(temp)) => {
            let names = [
                fields[depth].1.trim().to_string(),
                fields[temp].1.trim().to_string(),
            ];
            return Ok((depth, temp, names));
        }
        (None, _) => "depth (`depth_m`)",
        (Some(_), None) => "temperature (`temp_degC`)",
    };
    Err(error(
        start + (line.len() - line.trim_start().len()),
        // The line itself is not quoted: the location points at it, and a header is
        // the file's own text (a debugger over TCP must not echo it).
        format!("the header line has no {missing} column"),
    ))
}

fn interpolate(points: &[(f64, f64)], depth: f64) -> f64 {
    let Some(&(first_depth, first_temp)) = points.first() else {
        return 0.0;
    };
    if depth <= first_depth {
        return first_temp;
    }
    // The tables are short (tens of rows): a binary search keeps long ones fast.
    let after = points.partition_point(|&(point_depth, _)| point_depth < depth);
    match points.get(after) {
        None => points[points.len() - 1].1,
        Some(&(d1, t1)) => {
            let (d0, t0) = points[after - 1];
            t0 + (t1 - t0) * (depth - d0) / (d1 - d0)
        }
    }
}

/// A profile file that could not be read.
#[derive(Clone, Debug)]
pub struct ProfileError {
    pub path: std::path::PathBuf,
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl std::fmt::Display for ProfileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}:{}: error: {}",
            self.path.display(),
            self.line,
            self.column,
            self.message
        )
    }
}

impl std::error::Error for ProfileError {}

/// The one seeded generator, kept in the engine for every crate and test.
pub use gloc_engine::rng::Rng;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shelf_profile_is_warm_above_and_cold_below() {
        let profile = TemperatureProfile::default();
        assert!((profile.temperature(0.0) - 23.0).abs() < 0.1);
        // At the centre the temperature is the mean of surface and bottom.
        assert!((profile.temperature(16.0) - 16.25).abs() < 1e-9);
        assert!((profile.temperature(40.0) - 9.5).abs() < 0.01);
    }

    #[test]
    fn reads_the_amadeus_csv_with_comments() {
        let (path, text) = gloc_testsupport::data_text("amadeus_2014-07-24_temp_profile.csv");
        let profile = TemperatureProfile::from_csv(&path, &text).expect("amadeus profile loads");
        // The notes give 20.2 °C at the surface and 14.7 °C below 25 m.
        assert!(
            (profile.temperature(0.0) - 20.2).abs() < 0.3,
            "{}",
            profile.temperature(0.0)
        );
        assert!(
            (profile.temperature(30.0) - 14.7).abs() < 0.3,
            "{}",
            profile.temperature(30.0)
        );
    }

    #[test]
    fn csv_interpolates_and_reports_errors_with_line_and_column() {
        let path = Path::new("t.csv");
        let profile =
            TemperatureProfile::from_csv(path, "# note\ndepth_m,temp_degC\n0,20\n10,10\n")
                .expect("loads");
        assert_eq!(profile.temperature(5.0), 15.0);
        assert_eq!(profile.temperature(-1.0), 20.0);
        assert_eq!(profile.temperature(50.0), 10.0);
        let error = TemperatureProfile::from_csv(path, "depth_m,temp_degC\n0,20\n1, warm\n")
            .expect_err("bad number");
        assert_eq!((error.line, error.column), (3, 4), "{error}");
        let error = TemperatureProfile::from_csv(path, "depth_m,temp_degC\n0,20\n0,19\n")
            .expect_err("not increasing");
        assert_eq!((error.line, error.column), (3, 1), "{error}");
        assert!(TemperatureProfile::from_csv(path, "# only\n").is_err());
    }

    #[test]
    fn csv_columns_are_read_by_name_with_their_units() {
        let path = Path::new("t.csv");
        // The file: temperature first. 40 °C at 26 m was the old reading.
        let profile =
            TemperatureProfile::from_csv(path, "temp_degC,depth_m\n20,0\n10,26\n").expect("loads");
        assert_eq!(profile.temperature(26.0), 10.0);
        assert_eq!(profile.temperature(13.0), 15.0);
        // Other spellings, and columns that are ignored.
        let profile = TemperatureProfile::from_csv(
            path,
            "n, depth(m) ,temperature [degC]\n5,0,20\n5,10,10\n",
        )
        .expect("loads");
        assert_eq!(profile.temperature(5.0), 15.0);
        let refused = |text: &str| {
            let error = TemperatureProfile::from_csv(path, text).expect_err(text);
            (error.line, error.column, error.message)
        };
        let (line, column, message) = refused("depth_ft,temp_degC\n0,20\n");
        assert_eq!((line, column), (1, 1));
        assert!(message.contains("`ft`"), "{message}");
        let (line, column, message) = refused("depth_m,temp_degF\n0,60\n");
        assert_eq!((line, column), (1, 9));
        assert!(message.contains("`degF`"), "{message}");
        let (_, _, message) = refused("depth,temp_degC\n0,20\n");
        assert!(message.contains("no unit"), "{message}");
        let (line, column, message) = refused("0,20\n1,19\n");
        assert_eq!((line, column), (1, 1));
        assert!(message.contains("name the columns"), "{message}");
        let (_, _, message) = refused("depth_m,salinity_psu\n0,35\n");
        assert!(message.contains("no temperature"), "{message}");
        // An empty cell says which column, never empty backticks.
        let (line, column, message) = refused("depth_m,temp_degC\n0,20\n1,\n");
        assert_eq!((line, column), (3, 3));
        assert!(message.contains("`temp_degC` cell is empty"), "{message}");
        assert!(!message.contains("``"), "{message}");
        let (line, column, message) = refused("depth_m,temp_degC\n0,20\n1\n");
        assert_eq!((line, column), (3, 2));
        assert!(message.contains("column 2"), "{message}");
    }

    #[test]
    fn rng_is_deterministic_and_roughly_normal() {
        let mut a = Rng::new(7);
        let mut b = Rng::new(7);
        assert_eq!(a.next_u64(), b.next_u64());
        let mut rng = Rng::new(1);
        let samples: Vec<f64> = (0..20000).map(|_| rng.normal()).collect();
        let mean = samples.iter().sum::<f64>() / samples.len() as f64;
        let var = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / samples.len() as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.05, "{var}");
    }
}
