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

    /// Reads a CSV profile (`depth_m,temp_degC`): `#` comment lines and blank
    /// lines are skipped, a header line is optional. Errors name the line and
    /// column.
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
        let mut seen_data_or_header = false;
        for raw in text.split_inclusive('\n') {
            let start = offset;
            offset += raw.len();
            let line = raw.trim_end_matches(['\n', '\r']);
            let trimmed = line.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').collect();
            let first_is_number = fields[0].trim().parse::<f64>().is_ok();
            if !seen_data_or_header && !first_is_number {
                // The header.
                seen_data_or_header = true;
                continue;
            }
            seen_data_or_header = true;
            if fields.len() < 2 {
                return Err(error(
                    start + line.len(),
                    "expected two columns `depth_m,temp_degC`".to_string(),
                ));
            }
            let mut column_start = start;
            let mut values = [0.0; 2];
            for (slot, field) in fields.iter().take(2).enumerate() {
                let lead = field.len() - field.trim_start().len();
                match field.trim().parse::<f64>() {
                    Ok(value) if value.is_finite() => values[slot] = value,
                    _ => {
                        return Err(error(
                            column_start + lead,
                            format!("`{}` is not a number", field.trim()),
                        ))
                    }
                }
                column_start += field.len() + 1;
            }
            if let Some(&(last_depth, _)) = points.last() {
                if values[0] <= last_depth {
                    return Err(error(
                        start + (line.len() - line.trim_start().len()),
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
            return Err(error(
                0,
                "the profile has no data rows `depth_m,temp_degC`".to_string(),
            ));
        }
        Ok(TemperatureProfile::Table(points))
    }
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

/// A small deterministic generator (SplitMix64): the same seed gives the same
/// run on every machine. Not for cryptography.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rng {
    state: u64,
}

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng { state: seed }
    }

    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

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
        // The shared data folder sits next to the repository, here and in CI.
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/data/amadeus_2014-07-24_temp_profile.csv");
        let text = std::fs::read_to_string(&path).unwrap_or_else(|error| {
            panic!(
                "cannot read {} ({error}): the shared data folder must be at ../shared",
                path.display()
            )
        });
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
        let error = TemperatureProfile::from_csv(path, "0,20\n0,19\n").expect_err("not increasing");
        assert_eq!((error.line, error.column), (2, 1), "{error}");
        assert!(TemperatureProfile::from_csv(path, "# only\n").is_err());
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
