//! The battery in a forecast: the logs' last coulomb count
//! (`m_coulomb_amphr_total`, Ah used) against the capacity it counts down
//! from (`f_coulomb_battery_capacity`), the simulator's energy model started
//! from it, and when the charge used reaches the mission's low-battery abort
//! (abend's `remaining_charge_min`, % of the capacity left) within the
//! horizon.
//!
//! Decision: the remaining charge is the coulomb counter's, as the glider
//! judges `remaining_charge_min` (comet: 100 × (1 − 231.2 / 720) = 67.9%,
//! its `m_lithium_battery_relative_charge`); what the forecast spends comes
//! from the simulator's energy model (hotel, pump, pitch; docs/simulator.md),
//! which starts where its voltage is the logs' last `m_battery` (so the
//! charge it draws for its energy is at the glider's voltage, and abend's
//! `undervolts` is judged from there), and whose `m_coulomb_amphr_total`
//! continues the logs' count. The energy model's voltage falls linearly from
//! `volts_full` to `volts_empty` over `battery_wh`, which is not a lithium
//! pack's flat curve: started from the coulomb fraction instead, comet's
//! 32% used would put it at 12.5 V against the 13.7 V comet logged, and the
//! forecast would draw 9% more charge. Without `m_battery`, the coulomb
//! fraction; without the capacity in the logs, the simulator's battery stands
//! in for it (`battery_wh` / `volts_full`, Ah).

use gloc_mission::BehaviorKind;
use gloc_sim::{Mission, SimConfig};

use crate::fly::Start;

/// The abort threshold and what the forecast makes of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BatteryOutlook {
    /// `m_coulomb_amphr_total` at the start (Ah).
    pub used_at_start: f64,
    /// The capacity the count runs down from (Ah), and whether the logs gave
    /// it (`f_coulomb_battery_capacity`) or the simulator's battery stood in.
    pub capacity: f64,
    pub capacity_from_logs: bool,
    /// abend's `remaining_charge_min` (%), `None` when the mission has no abend
    /// (the limit is then the battery running out).
    pub remaining_charge_min: Option<f64>,
    /// `m_coulomb_amphr_total` at which the glider aborts (or runs out) (Ah).
    pub limit: f64,
    /// Unix seconds when the forecast's charge reaches [`Self::limit`], if it
    /// does within the horizon.
    pub reached_at: Option<f64>,
}

impl BatteryOutlook {
    /// The charge left before the limit at the start (Ah; negative: already past it).
    pub fn margin(&self) -> f64 {
        self.limit - self.used_at_start
    }

    /// The remaining charge at the start (% of the capacity).
    pub fn remaining_percent(&self) -> f64 {
        100.0 * (1.0 - self.used_at_start / self.capacity)
    }
}

/// The capacity (Ah) the glider's count runs down from: the logs', else the
/// simulator's battery; and whether the logs gave it.
pub fn capacity(start: &Start, config: &SimConfig) -> (f64, bool) {
    match start.battery_capacity {
        Some(amp_hours) if amp_hours.is_finite() && amp_hours > 0.0 => (amp_hours, true),
        _ => (
            config.energy.battery_wh / config.energy.volts_full.max(1.0),
            false,
        ),
    }
}

/// The fraction of the simulator's battery to start its energy model with
/// used: where its voltage is the logs' `m_battery`, else the coulomb count's
/// fraction of the capacity; `None` when the logs hold neither.
pub fn used_fraction(start: &Start, config: &SimConfig) -> Option<f64> {
    let energy = &config.energy;
    let span = energy.volts_full - energy.volts_empty;
    let volts = start
        .battery
        .filter(|volts| volts.is_finite() && *volts > 0.0);
    if let (Some(volts), true) = (volts, span > 0.0) {
        return Some(((energy.volts_full - volts) / span).clamp(0.0, 1.0));
    }
    let used = start.amp_hours.filter(|ah| ah.is_finite() && *ah >= 0.0)?;
    Some((used / capacity(start, config).0).clamp(0.0, 1.0))
}

/// abend's `remaining_charge_min` (%): as the mission writes it, else the
/// behavior table's default; `None` when the mission has no abend.
pub fn remaining_charge_min(mission: &Mission) -> Option<f64> {
    let spec = mission
        .behaviors
        .iter()
        .find(|spec| spec.kind == BehaviorKind::Abend)?;
    let percent = spec
        .value("remaining_charge_min")
        .unwrap_or_else(|| BehaviorKind::Abend.default_arg("remaining_charge_min"));
    Some(percent.clamp(0.0, 100.0))
}

/// The outlook at `start` for `mission` (reached time unset), `None` without a
/// coulomb count in the logs.
pub fn outlook(start: &Start, mission: &Mission, config: &SimConfig) -> Option<BatteryOutlook> {
    let used_at_start = start.amp_hours.filter(|ah| ah.is_finite() && *ah >= 0.0)?;
    let (capacity, capacity_from_logs) = capacity(start, config);
    let remaining_charge_min = remaining_charge_min(mission);
    Some(BatteryOutlook {
        used_at_start,
        capacity,
        capacity_from_logs,
        remaining_charge_min,
        limit: capacity * (1.0 - remaining_charge_min.unwrap_or(0.0) / 100.0),
        reached_at: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comets_remaining_charge_is_its_coulomb_count_against_the_capacity() {
        // comet's 154.dbd: 231.22 Ah used of f_coulomb_battery_capacity 720 Ah;
        // it logs m_lithium_battery_relative_charge 67.886% then. By hand:
        // 100 × (1 − 231.22 / 720) = 67.886%.
        let outlook = BatteryOutlook {
            used_at_start: 231.22,
            capacity: 720.0,
            capacity_from_logs: true,
            remaining_charge_min: Some(10.0),
            limit: 648.0,
            reached_at: None,
        };
        assert!((outlook.remaining_percent() - 67.886).abs() < 0.001);
        // Abort at 10% left: 648 Ah used, 416.78 Ah from here.
        assert!((outlook.margin() - 416.78).abs() < 1e-9);
    }

    fn start(amp_hours: Option<f64>, volts: Option<f64>) -> Start {
        Start {
            time: 0.0,
            lat: 5418.0,
            lon: 724.0,
            believed: gloc_sim::navigation::Xy::ZERO,
            avg_speed: None,
            waypoint: None,
            timers_elapsed: 0.0,
            amp_hours,
            battery: volts,
            battery_capacity: Some(720.0),
            heading: None,
        }
    }

    #[test]
    fn the_energy_model_starts_at_the_logged_voltage() {
        let config = SimConfig::default();
        // The defaults run 13.74 V full to 10 V empty: 13.68 V is
        // (13.74 − 13.68) / 3.74 = 1.604% used.
        let fraction = used_fraction(&start(Some(231.22), Some(13.68)), &config).expect("some");
        assert!((fraction - 0.06 / 3.74).abs() < 1e-12, "{fraction}");
        // Without the voltage, the coulomb count: 231.22 / 720 = 32.11%.
        let fraction = used_fraction(&start(Some(231.22), None), &config).expect("some");
        assert!((fraction - 231.22 / 720.0).abs() < 1e-12, "{fraction}");
        assert_eq!(used_fraction(&start(None, None), &config), None);
    }
}
