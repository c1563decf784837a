//! The simulator's settable constants: every name `gloc.toml`'s `[simulator]` table,
//! `gloc run --sim NAME=VALUE`, a batch sweep and a debugger launch may set, with its
//! units, its range and what it means. The simulator owns them (`SimConfig::set` maps
//! each name to its field, and `sim/tests/settings.rs` checks every name is mapped);
//! the project layer checks a file's or a flag's values against them.

/// A constant of the simulator's flight or energy model that `gloc.toml`'s
/// `[simulator]` table and `gloc run --sim NAME=VALUE` may set. The simulator
/// (`gloc-sim`) maps each name to its field; the ranges keep a run finite and
/// meaningful (a 1e-9 s integration step would never finish a cycle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatorSetting {
    pub name: &'static str,
    pub units: &'static str,
    pub min: f64,
    pub max: f64,
    pub about: &'static str,
}

/// Every simulator setting: the flight model first, then the energy model.
pub const SIMULATOR_SETTINGS: &[SimulatorSetting] = &[
    SimulatorSetting {
        name: "step",
        units: "s",
        min: 0.05,
        max: 1.5,
        about: "integration step of the flight model within a 4 s cycle",
    },
    SimulatorSetting {
        name: "pump_max",
        units: "cc",
        min: 1.0,
        max: 2000.0,
        about: "pumped volume the pump reaches either way",
    },
    SimulatorSetting {
        name: "pump_rate",
        units: "cc/s",
        min: 0.1,
        max: 1000.0,
        about: "pump speed (an inflection takes 2 pump_max / pump_rate)",
    },
    SimulatorSetting {
        name: "pump_in_rate",
        units: "cc/s",
        min: 0.1,
        max: 1000.0,
        about: "speed of letting oil in (going down)",
    },
    SimulatorSetting {
        name: "pitch_rate",
        units: "rad/s",
        min: 0.001,
        max: 1.0,
        about: "pitch slew rate of the battery",
    },
    SimulatorSetting {
        name: "pitch_period",
        units: "s",
        min: 0.5,
        max: 600.0,
        about: "natural period of the hull's pitch swinging toward the battery relation with the battery held (use_pitch 1)",
    },
    SimulatorSetting {
        name: "pitch_damping",
        units: "",
        min: 0.01,
        max: 10.0,
        about: "damping ratio of that swing (1: critical, less overshoots)",
    },
    SimulatorSetting {
        name: "mass",
        units: "kg",
        min: 1.0,
        max: 10000.0,
        about: "the glider's mass",
    },
    SimulatorSetting {
        name: "hull_volume",
        units: "L",
        min: 1.0,
        max: 10000.0,
        about: "hull volume at the surface with nothing pumped",
    },
    SimulatorSetting {
        name: "hull_compressibility",
        units: "1/Pa",
        min: 0.0,
        max: 1.0e-8,
        about: "relative loss of hull volume per pascal",
    },
    SimulatorSetting {
        name: "water_density",
        units: "kg/m³",
        min: 900.0,
        max: 1100.0,
        about: "sea-water density",
    },
    SimulatorSetting {
        name: "drag_cd0",
        units: "",
        min: 0.001,
        max: 10.0,
        about: "zero-lift drag coefficient",
    },
    SimulatorSetting {
        name: "drag_cd1",
        units: "1/rad²",
        min: 0.0,
        max: 100.0,
        about: "induced drag coefficient (drag_cd0 + drag_cd1·α²)",
    },
    SimulatorSetting {
        name: "lift_slope",
        units: "1/rad",
        min: 0.01,
        max: 100.0,
        about: "lift coefficient per radian of angle of attack (wings and hull)",
    },
    SimulatorSetting {
        name: "wing_area",
        units: "m²",
        min: 0.001,
        max: 100.0,
        about: "reference area of the lift and drag coefficients",
    },
    SimulatorSetting {
        name: "added_mass_along",
        units: "",
        min: 0.0,
        max: 10.0,
        about: "added mass along the hull, a fraction of mass",
    },
    SimulatorSetting {
        name: "added_mass_across",
        units: "",
        min: 0.0,
        max: 10.0,
        about: "added mass across the hull, a fraction of mass",
    },
    SimulatorSetting {
        name: "pitch_t1",
        units: "1/m³",
        min: -1.0e6,
        max: 1.0e6,
        about: "battery relation tan(pitch) = T1·pumped volume + T2·battpos + T3: T1",
    },
    SimulatorSetting {
        name: "pitch_t2",
        units: "1/m",
        min: -1.0e4,
        max: 1.0e4,
        about: "the battery relation's T2 (battery position in metres, > 0 nose down)",
    },
    SimulatorSetting {
        name: "pitch_t3",
        units: "",
        min: -10.0,
        max: 10.0,
        about: "the battery relation's T3 (the trim)",
    },
    SimulatorSetting {
        name: "cycle_overrun",
        units: "s",
        min: 0.0,
        max: 60.0,
        about: "mean time a control cycle runs past u_cycle_time",
    },
    SimulatorSetting {
        name: "cycle_jitter",
        units: "s",
        min: 0.0,
        max: 10.0,
        about: "standard deviation of the control cycle's period (seeded)",
    },
    SimulatorSetting {
        name: "turn_cycles",
        units: "cycles",
        min: 1.0,
        max: 10.0,
        about: "cycles from a behavior's turn to the pump reversing (1: the same cycle)",
    },
    SimulatorSetting {
        name: "altimeter_range",
        units: "m",
        min: 0.0,
        max: 1.0e7,
        about: "largest altitude the altimeter reads (m_altitude holds its last fix beyond)",
    },
    SimulatorSetting {
        name: "altimeter_fraction",
        units: "",
        min: 0.0,
        max: 10.0,
        about: "next altimeter ping after this fraction of altitude / dive rate (0: every cycle)",
    },
    SimulatorSetting {
        name: "altimeter_min_depth",
        units: "m",
        min: 0.0,
        max: 1000.0,
        about: "depth above which the altimeter does not ping (u_alt_min_depth)",
    },
    SimulatorSetting {
        name: "ctd_period",
        units: "s",
        min: 0.0,
        max: 3600.0,
        about:
            "seconds between CTD samples; the cycle sees the latest (0: one at each cycle's start)",
    },
    SimulatorSetting {
        name: "gps_fix_time",
        units: "s",
        min: 0.0,
        max: 3600.0,
        about: "seconds at the surface until the first GPS fix",
    },
    SimulatorSetting {
        name: "turn_time",
        units: "s",
        min: 0.0,
        max: 600.0,
        about: "time constant of the heading's turn toward its command",
    },
    SimulatorSetting {
        name: "max_turn_rate",
        units: "rad/s",
        min: 0.001,
        max: 1.0,
        about: "fastest turn",
    },
    SimulatorSetting {
        name: "heading_bias_dive",
        units: "rad",
        min: -1.0,
        max: 1.0,
        about: "heading error the roll bias holds on dives (the zig-zag)",
    },
    SimulatorSetting {
        name: "heading_bias_climb",
        units: "rad",
        min: -1.0,
        max: 1.0,
        about: "heading error the roll bias holds on climbs",
    },
    SimulatorSetting {
        name: "dive_power",
        units: "W",
        min: 0.0,
        max: 100.0,
        about: "hotel power while diving",
    },
    SimulatorSetting {
        name: "climb_power",
        units: "W",
        min: 0.0,
        max: 100.0,
        about: "hotel power while climbing or at the surface",
    },
    SimulatorSetting {
        name: "pump_out_j_per_cc",
        units: "J/cc",
        min: 0.0,
        max: 100.0,
        about: "energy to pump oil out (going up), at the surface",
    },
    SimulatorSetting {
        name: "pump_out_j_per_cc_m",
        units: "J/cc/m",
        min: 0.0,
        max: 10.0,
        about: "extra energy to pump oil out per metre of depth",
    },
    SimulatorSetting {
        name: "pump_in_j_per_cc",
        units: "J/cc",
        min: 0.0,
        max: 100.0,
        about: "energy to let oil in (going down)",
    },
    SimulatorSetting {
        name: "pitch_j_per_rad",
        units: "J/rad",
        min: 0.0,
        max: 100000.0,
        about: "energy to move the pitch battery",
    },
    SimulatorSetting {
        name: "battery_wh",
        units: "Wh",
        min: 1.0,
        max: 100000.0,
        about: "battery capacity",
    },
    SimulatorSetting {
        name: "volts_full",
        units: "V",
        min: 1.0,
        max: 100.0,
        about: "battery voltage when full",
    },
    SimulatorSetting {
        name: "volts_empty",
        units: "V",
        min: 0.0,
        max: 100.0,
        about: "battery voltage when empty",
    },
    SimulatorSetting {
        name: "science_on_power",
        units: "W",
        min: 0.0,
        max: 100.0,
        about: "science computer and sensors awake (c_science_on 1); 0: in the hotel load",
    },
    SimulatorSetting {
        name: "science_sleep_power",
        units: "W",
        min: 0.0,
        max: 100.0,
        about: "science computer and sensors asleep (c_science_on 0)",
    },
    SimulatorSetting {
        name: "science_wake_time",
        units: "s",
        min: 0.0,
        max: 3600.0,
        about: "time from c_science_on 1 to m_science_on 1, at science_on_power",
    },
    SimulatorSetting {
        name: "science_wake_joules",
        units: "J",
        min: 0.0,
        max: 100000.0,
        about: "energy of one wake on top of science_on_power",
    },
    SimulatorSetting {
        name: "battery_ohms",
        units: "ohm",
        min: 0.0,
        max: 100.0,
        about: "internal resistance: the voltage sags by ohms x current under load",
    },
];

/// Checks one simulator setting: a known name and a value in its range. The
/// error says what is wrong and what is allowed.
pub fn check_simulator_setting(name: &str, value: f64) -> Result<(), String> {
    let Some(setting) = SIMULATOR_SETTINGS
        .iter()
        .find(|setting| setting.name == name)
    else {
        let known: Vec<&str> = SIMULATOR_SETTINGS
            .iter()
            .map(|setting| setting.name)
            .collect();
        let hint = gloc_engine::suggest::closest(name, known.iter().copied())
            .map(|close| format!("did you mean `{close}`? "))
            .unwrap_or_default();
        return Err(format!(
            "`{name}` is not a simulator setting; {hint}the settings are {}",
            known.join(", ")
        ));
    };
    if !(value.is_finite() && value >= setting.min && value <= setting.max) {
        return Err(format!(
            "`{name}` is {value}; it must be from {} to {} {} ({})",
            setting.min, setting.max, setting.units, setting.about
        ));
    }
    Ok(())
}
