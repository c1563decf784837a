//! Sensor lists ("Masterdata"): index ⇄ name, units, default and description.
//!
//! A sensor's index is a property of the loaded list, never a constant: the
//! 2008 firmware puts `m_depth` at 444, later lists elsewhere. Names match
//! case-insensitively (the paper writes `SCI_RUHP_BEHS`).

use std::collections::HashMap;

mod files;

pub use files::{
    find_cac, is_crc, load_sensor_file, looks_like_cac, parse_cac, parse_cac_entries,
    parse_masterdata, CacEntry, LoadedSensorList, SensorOrder, MAX_SENSORS,
};

/// The CRC that names the embedded list: its indices 0 to 1384 are those of the
/// 2008 list `813b137d.cac`; what follows (the hook sensors, the coulomb counter)
/// is appended, so no index of `813b137d` moves.
pub const EMBEDDED_CRC: &str = "813b137d";

/// The hook behavior's sensors (gloc's own, after the paper): a list that lacks
/// them gets them appended, in this order, with these units.
pub const HOOK_SENSORS: [(&str, &str); 4] = [
    ("sci_ruhp_dive_depth", "m"),
    ("sci_ruhp_climb_depth", "m"),
    ("sci_ruhp_behs", "enum"),
    ("sci_ruhp_heading", "rad"),
];

/// Index of a sensor in the active sensor list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SensorId(pub u32);

impl SensorId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Who may write a sensor from a script, derived from its name's prefix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// `m_` (measured) and `x_` (computed by the glider): a store is an error.
    ReadOnly,
    /// `f_` (factory settings): a store is allowed with a warning.
    Factory,
    /// Everything else (`c_`, `u_`, `sci_`, …).
    Writable,
}

impl Access {
    pub fn of_name(name: &str) -> Access {
        let lower = name.to_ascii_lowercase();
        if lower.starts_with("m_") || lower.starts_with("x_") {
            Access::ReadOnly
        } else if lower.starts_with("f_") {
            Access::Factory
        } else {
            Access::Writable
        }
    }
}

/// A `sensor:` or a `b_arg:` line of a masterdata file, which read alike:
/// `NAME(UNITS) [DEFAULT] [# comment]`, a `#!` comment giving metadata.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub name: String,
    pub units: String,
    /// The default from the masterdata file; `None` means unset (0.0 at run time).
    pub default: Option<f64>,
    pub description: Option<String>,
    /// What the line's `#!` metadata allows.
    pub allowed: Allowed,
    /// 1-based line in the file it came from (0 for the embedded list).
    pub line: u32,
}

/// The values Control Center allows for a sensor or a behavior argument: the
/// `#! min = …; max = …` and `#! choices = start_when([…])` metadata of its
/// masterdata line. Every surface that checks a value against it or describes it
/// (the mission checks, hovers) asks here.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Allowed {
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// The only values allowed, when the line lists them.
    pub choices: Option<Vec<f64>>,
}

/// Why Control Center refuses a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The line lists its choices and the value is not one of them.
    NotAChoice,
    /// Below `min` or above `max`.
    OutOfRange,
}

impl Allowed {
    /// Why `value` is refused, if it is: first whether it is one of the choices
    /// (when the line lists them), then whether it is within the range.
    pub fn refusal(&self, value: f64) -> Option<Refusal> {
        if self
            .choices
            .as_ref()
            .is_some_and(|choices| !choices.contains(&value))
        {
            return Some(Refusal::NotAChoice);
        }
        let below = self.min.is_some_and(|min| value < min);
        let above = self.max.is_some_and(|max| value > max);
        (below || above).then_some(Refusal::OutOfRange)
    }

    /// The range in words (`0 to 4`, `at least 1`, `at most 1000`), when there is one.
    pub fn range_text(&self) -> Option<String> {
        match (self.min, self.max) {
            (Some(min), Some(max)) => Some(format!("{min} to {max}")),
            (Some(min), None) => Some(format!("at least {min}")),
            (None, Some(max)) => Some(format!("at most {max}")),
            (None, None) => None,
        }
    }

    /// The choices, comma-separated (`0, 1, 2, 4`), when the line lists them.
    pub fn choices_text(&self) -> Option<String> {
        self.choices.as_ref().map(|choices| {
            choices
                .iter()
                .map(|choice| choice.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        })
    }
}

/// A sensor of a list.
pub type Sensor = Setting;

/// One `b_arg:` line of a masterdata `behavior:` section.
pub type BehaviorArg = Setting;

impl Setting {
    /// A name and units alone (a `.cac` line, the embedded list): no default,
    /// description or metadata.
    pub fn new(name: impl Into<String>, units: impl Into<String>, line: u32) -> Setting {
        Setting {
            name: name.into(),
            units: units.into(),
            default: None,
            description: None,
            allowed: Allowed::default(),
            line,
        }
    }

    pub fn access(&self) -> Access {
        Access::of_name(&self.name)
    }

    pub fn initial_value(&self) -> f64 {
        self.default.unwrap_or(0.0)
    }
}

/// A sensor list. Indices are positions in `sensors`.
#[derive(Clone, Debug, Default)]
pub struct SensorList {
    sensors: Vec<Sensor>,
    /// Lower-cased name → index.
    by_name: HashMap<String, SensorId>,
    /// `behavior:` sections of a masterdata file (defaults for the simulator).
    behaviors: Vec<BehaviorDefaults>,
    /// The glider's CRC naming this list (lower-case hex), when known: the
    /// embedded list's, or a `.cac` file's name.
    crc: Option<String>,
}

/// A `behavior: NAME` section of a masterdata file: the default `b_arg:`s.
#[derive(Clone, Debug, PartialEq)]
pub struct BehaviorDefaults {
    pub name: String,
    /// The comment after the name (`behavior: yo # …`), not `#!` metadata.
    pub description: Option<String>,
    /// 1-based line of the `behavior:` line.
    pub line: u32,
    pub args: Vec<BehaviorArg>,
}

impl SensorList {
    /// Builds a list from sensors in index order. A later duplicate name keeps
    /// its index but name lookups find the first.
    pub fn from_sensors(sensors: Vec<Sensor>) -> SensorList {
        let mut by_name = HashMap::with_capacity(sensors.len());
        for (index, sensor) in sensors.iter().enumerate() {
            by_name
                .entry(sensor.name.to_ascii_lowercase())
                .or_insert(SensorId(index as u32));
        }
        SensorList {
            sensors,
            by_name,
            behaviors: Vec::new(),
            crc: None,
        }
    }

    /// Names the list by the glider's CRC (`sensor_list_crc` in a binary log,
    /// the name of a `.cac` file); stored lower-case.
    pub fn with_crc(mut self, crc: &str) -> SensorList {
        self.crc = Some(crc.to_ascii_lowercase());
        self
    }

    /// The CRC naming this list, when known (`813b137d` for the embedded list).
    pub fn crc(&self) -> Option<&str> {
        self.crc.as_deref()
    }

    /// How messages name this list: its CRC, or `the active list`.
    pub fn label(&self) -> &str {
        self.crc().unwrap_or("the active sensor list")
    }

    /// Appends the hook sensors ([`HOOK_SENSORS`]) the list lacks, after its last
    /// index (so no index moves), and returns their names. A real glider's list
    /// never has them: they belong to gloc's hook behavior.
    pub fn add_hook_sensors(&mut self) -> Vec<&'static str> {
        let mut added = Vec::new();
        for (name, units) in HOOK_SENSORS {
            if self.lookup(name).is_some() {
                continue;
            }
            let id = SensorId(self.sensors.len() as u32);
            let mut sensor = Sensor::new(name, units, 0);
            sensor.description = embedded_descriptions()
                .get(name)
                .map(|text| text.to_string());
            self.sensors.push(sensor);
            self.by_name.insert(name.to_string(), id);
            added.push(name);
        }
        added
    }

    /// Attaches the `behavior:` default sections read from a masterdata file.
    pub fn with_behaviors(mut self, behaviors: Vec<BehaviorDefaults>) -> SensorList {
        self.behaviors = behaviors;
        self
    }

    /// The `behavior:` default sections (empty for `.cac` files and the embedded list).
    pub fn behavior_defaults(&self) -> &[BehaviorDefaults] {
        &self.behaviors
    }

    /// The list compiled into the binary: the 1,385 sensors of the 2008
    /// firmware list (`813b137d.cac`) in its index order, then the hook
    /// behavior's sensors 1385 `sci_ruhp_dive_depth`, 1386
    /// `sci_ruhp_climb_depth`, 1387 `sci_ruhp_behs`, 1388 `sci_ruhp_heading`
    /// (where the 2008 `.cac` gets them appended too), then 1389
    /// `m_coulomb_amphr_total` (charge used, published by the simulator; the
    /// 2008 firmware had no coulomb counter).
    pub fn embedded() -> SensorList {
        let descriptions = embedded_descriptions();
        let sensors = EMBEDDED_SENSORS
            .lines()
            .filter_map(|line| {
                let mut fields = line.split_whitespace();
                let _index = fields.next()?;
                let name = fields.next()?;
                let units = fields.next().unwrap_or("nodim");
                let mut sensor = Sensor::new(name, units, 0);
                sensor.description = descriptions.get(name).map(|text| text.to_string());
                Some(sensor)
            })
            .collect();
        SensorList::from_sensors(sensors).with_crc(EMBEDDED_CRC)
    }

    /// The embedded list, built once per process (the identity check compares
    /// against it whenever a file states `# sensors: 813b137d`).
    pub fn embedded_shared() -> &'static SensorList {
        static EMBEDDED: std::sync::OnceLock<SensorList> = std::sync::OnceLock::new();
        EMBEDDED.get_or_init(SensorList::embedded)
    }

    pub fn len(&self) -> usize {
        self.sensors.len()
    }

    pub fn is_empty(&self) -> bool {
        self.sensors.is_empty()
    }

    pub fn get(&self, id: SensorId) -> Option<&Sensor> {
        self.sensors.get(id.index())
    }

    /// Case-insensitive lookup by name.
    pub fn lookup(&self, name: &str) -> Option<SensorId> {
        if name.bytes().any(|byte| byte.is_ascii_uppercase()) {
            self.by_name.get(&name.to_ascii_lowercase()).copied()
        } else {
            self.by_name.get(name).copied()
        }
    }

    pub fn name(&self, id: SensorId) -> Option<&str> {
        self.get(id).map(|sensor| sensor.name.as_str())
    }

    pub fn iter(&self) -> impl Iterator<Item = (SensorId, &Sensor)> {
        self.sensors
            .iter()
            .enumerate()
            .map(|(index, sensor)| (SensorId(index as u32), sensor))
    }

    /// Initial values of every sensor, indexed by `SensorId`.
    pub fn initial_values(&self) -> Vec<f64> {
        self.sensors.iter().map(Sensor::initial_value).collect()
    }
}

/// `INDEX NAME UNITS`, one sensor a line, taken from `813b137d.cac`.
const EMBEDDED_SENSORS: &str = include_str!("../data/sensors-2008.txt");
/// `NAME: description`, in our own words.
const EMBEDDED_DESCRIPTIONS: &str = include_str!("../data/descriptions.txt");

fn embedded_descriptions() -> HashMap<&'static str, &'static str> {
    EMBEDDED_DESCRIPTIONS
        .lines()
        .filter_map(|line| {
            let (name, text) = line.split_once(':')?;
            Some((name.trim(), text.trim()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allowed_values_refuse_by_choice_first_then_by_range() {
        // `#! min = 0; max = 4; choices = c_mode([0, 1, 4])`: 1 is a choice inside
        // the range; 2 is inside the range but not a choice; a range alone refuses
        // only outside it, at both ends inclusive.
        let mode = Allowed {
            min: Some(0.0),
            max: Some(4.0),
            choices: Some(vec![0.0, 1.0, 4.0]),
        };
        assert_eq!(mode.refusal(1.0), None);
        assert_eq!(mode.refusal(2.0), Some(Refusal::NotAChoice));
        assert_eq!(mode.refusal(9.0), Some(Refusal::NotAChoice));
        let depth = Allowed {
            min: Some(1.0),
            max: Some(1000.0),
            choices: None,
        };
        assert_eq!(depth.refusal(1.0), None);
        assert_eq!(depth.refusal(1000.0), None);
        assert_eq!(depth.refusal(0.5), Some(Refusal::OutOfRange));
        assert_eq!(depth.refusal(1000.5), Some(Refusal::OutOfRange));
        // A choice listed outside the range is still refused by the range.
        let odd = Allowed {
            max: Some(2.0),
            ..mode.clone()
        };
        assert_eq!(odd.refusal(4.0), Some(Refusal::OutOfRange));
        assert_eq!(Allowed::default().refusal(-1e9), None);
        // NaN is no number past an end: the range cannot say it is outside.
        assert_eq!(depth.refusal(f64::NAN), None);
    }

    #[test]
    fn allowed_values_in_words() {
        let range = |min, max| {
            Allowed {
                min,
                max,
                choices: None,
            }
            .range_text()
        };
        assert_eq!(range(Some(-0.5), Some(0.5)).as_deref(), Some("-0.5 to 0.5"));
        assert_eq!(range(Some(1.0), None).as_deref(), Some("at least 1"));
        assert_eq!(range(None, Some(1000.0)).as_deref(), Some("at most 1000"));
        assert_eq!(range(None, None), None);
        let choices = Allowed {
            choices: Some(vec![0.0, 2.0, 15.5]),
            ..Allowed::default()
        };
        assert_eq!(choices.choices_text().as_deref(), Some("0, 2, 15.5"));
        assert_eq!(Allowed::default().choices_text(), None);
    }

    #[test]
    fn embedded_list_has_the_paper_indices() {
        let list = SensorList::embedded();
        assert_eq!(list.len(), 1390);
        assert_eq!(list.lookup("m_coulomb_amphr_total"), Some(SensorId(1389)));
        assert_eq!(list.lookup("sci_ruhp_heading"), Some(SensorId(1388)));
        assert_eq!(list.lookup("m_depth"), Some(SensorId(444)));
        assert_eq!(list.lookup("m_pressure"), Some(SensorId(443)));
        assert_eq!(list.lookup("SCI_RUHP_BEHS"), Some(SensorId(1387)));
        assert_eq!(list.name(SensorId(1385)), Some("sci_ruhp_dive_depth"));
    }

    #[test]
    fn embedded_descriptions_cover_the_simulated_sensors() {
        let list = SensorList::embedded();
        for (name, _) in embedded_descriptions() {
            assert!(list.lookup(name).is_some(), "{name} is not in the list");
        }
        let described = list
            .iter()
            .filter(|(_, sensor)| sensor.description.is_some())
            .count();
        assert!(described >= 40, "only {described} descriptions");
        for name in [
            "m_depth",
            "c_pitch",
            "sci_water_temp",
            "u_cycle_time",
            "sci_ruhp_behs",
        ] {
            let id = list.lookup(name).expect("listed");
            assert!(
                list.get(id).and_then(|s| s.description.as_ref()).is_some(),
                "{name}"
            );
        }
    }

    #[test]
    fn access_follows_the_prefix() {
        assert_eq!(Access::of_name("M_DEPTH"), Access::ReadOnly);
        assert_eq!(Access::of_name("x_mission_num"), Access::ReadOnly);
        assert_eq!(Access::of_name("f_max_working_depth"), Access::Factory);
        assert_eq!(Access::of_name("c_pitch"), Access::Writable);
        assert_eq!(Access::of_name("sci_ruhp_behs"), Access::Writable);
    }
}
