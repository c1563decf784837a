//! The flags several subcommands share, defined once: what they mean, how they are
//! bounded, and how they become the project layer's [`Overrides`].

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;
use gloc_project::{Overrides, Surface};
use gloc_sim::Simulation;

/// The flags `gloc run` and `gloc batch` share for the mission, the sensor list and the
/// budget (one definition, so both parse and bound them alike).
#[derive(Args, Debug)]
pub struct FlightArgs {
    /// Per-cycle instruction budget, 1 to 1,000,000,000; default: gloc.toml's, else 10,000
    /// (a script that runs longer traps with "cycle overrun").
    #[arg(long, value_name = "N", value_parser = gloc_project::settings::parse_cycle_budget)]
    pub cycle_budget: Option<u64>,
    /// Mission file (`.mi`); default: gloc.toml's, else the embedded Fig. 2 mission.
    #[arg(long, value_name = "M.mi")]
    pub mission: Option<PathBuf>,
    #[command(flatten)]
    pub sensors: SensorListArgs,
    /// A folder searched first for the mission's `.ma` files, before `mafiles/` beside
    /// `missions/` and the mission's own folder; default: gloc.toml's `mafiles`.
    #[arg(long, value_name = "DIR")]
    pub mafiles: Option<PathBuf>,
}

impl FlightArgs {
    /// The settings these flags override (the rest from gloc.toml or the defaults).
    pub fn overrides(&self) -> Overrides {
        self.sensors.overrides(Overrides {
            cycle_budget: self.cycle_budget,
            mission: self.mission.clone(),
            mafiles: self.mafiles.clone(),
            ..Overrides::new(Surface::Cli)
        })
    }
}

/// Simulated time a run may take when neither `--duration` nor `--cycles`
/// is given and the mission does not end by itself.
pub(crate) const DEFAULT_LIMIT_SECONDS: f64 = 24.0 * 3600.0;

/// The most control cycles one run may take (`--cycles`, `--duration`): about 12 years
/// of 4 s cycles, minutes of computing for a plain script.
pub(crate) const MAX_RUN_CYCLES: u64 = 100_000_000;

/// How long `gloc run` and `gloc batch` fly a mission (one definition, so both parse
/// and bound them alike).
#[derive(Args, Debug)]
pub struct LengthArgs {
    /// Simulated duration, e.g. `90m`, `6h`, `30d`; default: until the mission ends, at
    /// most 24 h.
    #[arg(long, conflicts_with = "cycles")]
    pub duration: Option<String>,
    /// Number of control cycles to simulate (at most 100,000,000); default: see --duration.
    #[arg(long)]
    pub cycles: Option<u64>,
}

/// How long a mission flies: simulated seconds (as many cycles as its simulation's
/// cycle time makes of them) or control cycles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Limit {
    Seconds(f64),
    Cycles(u64),
}

impl LengthArgs {
    /// The length these flags give (`None`: neither was given), refused when it is
    /// more than [`MAX_RUN_CYCLES`] control cycles of `cycle_time` seconds.
    pub fn limit(&self, cycle_time: f64) -> anyhow::Result<Option<Limit>> {
        let limit = match (&self.duration, self.cycles) {
            (Some(text), _) => {
                let seconds = parse_duration(text)?;
                if seconds / cycle_time > MAX_RUN_CYCLES as f64 {
                    bail!(
                        "--duration {text} is more than {MAX_RUN_CYCLES} control cycles of {cycle_time} s, the most one run may take"
                    );
                }
                Limit::Seconds(seconds)
            }
            (None, Some(cycles)) if cycles > MAX_RUN_CYCLES => {
                bail!("--cycles {cycles} is more than {MAX_RUN_CYCLES}, the most one run may take")
            }
            (None, Some(cycles)) => Limit::Cycles(cycles),
            (None, None) => return Ok(None),
        };
        Ok(Some(limit))
    }
}

impl Limit {
    /// The control cycles `sim` flies in this length.
    pub fn cycles(self, sim: &Simulation) -> u64 {
        match self {
            Limit::Seconds(seconds) => gloc_project::simulation::cycles_for(seconds, sim),
            Limit::Cycles(cycles) => cycles,
        }
    }
}

/// Parses `90s`, `45m`, `6h`, `30d`, or combinations such as `1h30m`.
fn parse_duration(text: &str) -> anyhow::Result<f64> {
    let trimmed = text.trim();
    let mut total = 0.0;
    let mut number = String::new();
    let mut saw_unit = false;
    for character in trimmed.chars() {
        if character.is_ascii_digit() || character == '.' {
            number.push(character);
            continue;
        }
        let unit = match character {
            's' => 1.0,
            'm' => 60.0,
            'h' => 3600.0,
            'd' => 86400.0,
            _ => bail!(
                "`{text}` is not a duration: use a number with s, m, h or d, such as `90m`, `6h` or `30d`"
            ),
        };
        let value: f64 = number.parse().map_err(|_| {
            anyhow::anyhow!("`{text}` is not a duration: a number must come before `{character}`")
        })?;
        total += value * unit;
        number.clear();
        saw_unit = true;
    }
    if !number.is_empty() || !saw_unit {
        bail!("`{text}` is not a duration: give the unit, such as `90m`, `6h` or `30d`");
    }
    if !(total > 0.0 && total.is_finite()) {
        bail!("`{text}` is not a positive duration");
    }
    Ok(total)
}

/// The sensor list flags `check`, `compile`, `run`, `batch` and `forecast` share: which
/// list, and how a masterdata file's sensors are numbered.
#[derive(Args, Debug)]
pub struct SensorListArgs {
    /// The sensor list (masterdata or `.cac`/`.ccc`); default: gloc.toml's, else the
    /// embedded 2008 list.
    #[arg(long, value_name = "FILE")]
    pub masterdata: Option<PathBuf>,
    /// How a masterdata file's sensors are numbered: `file` or `sorted` (firmware 2014+);
    /// default: gloc.toml's, else `file`.
    #[arg(long, value_name = "ORDER", value_parser = gloc_project::settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
}

impl SensorListArgs {
    /// `overrides` with the sensor list these flags give.
    pub fn overrides(&self, overrides: Overrides) -> Overrides {
        Overrides {
            masterdata: self.masterdata.clone(),
            sensor_order: self.sensor_order,
            ..overrides
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        // Worked by hand: 90 × 60, 6 × 3600, 30 × 86400, 3600 + 30 × 60, 3600 / 2.
        for (text, seconds) in [
            ("90m", 5400.0),
            ("6h", 21600.0),
            ("30d", 2_592_000.0),
            ("1h30m", 5400.0),
            ("0.5h", 1800.0),
        ] {
            assert_eq!(parse_duration(text).expect(text), seconds, "{text}");
        }
        // No unit, an unknown unit, no number, a zero length, nothing.
        for bad in ["6", "6x", "h", "0s", ""] {
            assert!(parse_duration(bad).is_err(), "`{bad}` was taken");
        }
    }

    /// A length is bounded by 100,000,000 cycles: 400,000,000 s of 4 s cycles is
    /// exactly that many (worked by hand), a second more is refused.
    #[test]
    fn a_length_is_bounded_in_cycles() {
        let length = |duration: Option<&str>, cycles: Option<u64>| LengthArgs {
            duration: duration.map(str::to_string),
            cycles,
        };
        assert_eq!(length(None, None).limit(4.0).expect("none"), None);
        assert_eq!(
            length(Some("400000000s"), None)
                .limit(4.0)
                .expect("the most"),
            Some(Limit::Seconds(4e8))
        );
        let refused = length(Some("400000001s"), None)
            .limit(4.0)
            .expect_err("refused");
        assert_eq!(
            refused.to_string(),
            "--duration 400000001s is more than 100000000 control cycles of 4 s, the most one run may take"
        );
        assert_eq!(
            length(None, Some(100_000_000))
                .limit(4.0)
                .expect("the most"),
            Some(Limit::Cycles(100_000_000))
        );
        assert!(length(None, Some(100_000_001)).limit(4.0).is_err());
    }
}
