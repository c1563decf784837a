//! The Navigation scope: where the glider believes it is and where it is going, in the
//! glider's own sensors as the script and the logs see them (`m_lat`/`m_lon` in NMEA,
//! `m_x_lmc`/`m_y_lmc`, `m_heading`, `c_heading`, the waypoint `c_wpt_*`,
//! `m_dist_to_wpt`, the current estimate `m_water_vx/vy`, `x_dr_state`, the last GPS
//! fix), each named by its sensor (so it evaluates, and a data breakpoint can watch
//! it), with the same values in degrees beside them through the simulator's one NMEA
//! conversion. The simulated world adds the truth (`world`); a replay has only what was
//! recorded. Nothing here computes navigation: the simulator's `Navigation` does.

use gloc_sim::navigation::{nmea_is_set, nmea_to_degrees, Xy};

use crate::script::{float_text, ScriptState};
use crate::target::Named;

/// The navigation sensors shown, in order, with what each holds (the `type` column);
/// those the active list lacks are left out.
const SENSORS: &[(&str, &str)] = &[
    ("m_lat", "NMEA ddmm.mmm, dead-reckoned"),
    ("m_lon", "NMEA dddmm.mmm, dead-reckoned"),
    ("m_x_lmc", "m east of the mission origin, dead-reckoned"),
    ("m_y_lmc", "m north of the mission origin, dead-reckoned"),
    ("m_heading", "rad, clockwise from north"),
    ("c_heading", "rad, commanded"),
    ("c_wpt_lat", "NMEA, the waypoint steered to"),
    ("c_wpt_lon", "NMEA, the waypoint steered to"),
    ("c_wpt_x_lmc", "m east, the waypoint steered to"),
    ("c_wpt_y_lmc", "m north, the waypoint steered to"),
    ("m_dist_to_wpt", "m, from the dead-reckoned position"),
    ("m_water_vx", "m/s east, the current estimate"),
    ("m_water_vy", "m/s north, the current estimate"),
    (
        "x_dr_state",
        "1 underwater, 2 surfaced, 3 first fix, 4 leaving the surface",
    ),
    ("m_gps_lat", "NMEA, the last GPS fix"),
    ("m_gps_lon", "NMEA, the last GPS fix"),
    (
        "m_gps_dist_from_dr",
        "m, the first fix from the dead-reckoned position",
    ),
];

/// The rows read from the sensor array (`sensor(index)`), each followed by its
/// conversion where there is one: a position in decimal degrees, a heading in degrees,
/// the current estimate as a speed and the direction it flows to.
pub(crate) fn sensor_rows(script: &ScriptState, sensor: impl Fn(usize) -> f64) -> Vec<Named> {
    let value_of = |name: &str| script.sensor_index(name).map(&sensor);
    let mut rows = Vec::new();
    for (name, meaning) in SENSORS {
        let Some(value) = value_of(name) else {
            continue;
        };
        rows.push(Named {
            evaluate_name: Some(name.to_string()),
            ..Named::plain(name, float_text(value), meaning)
        });
        match *name {
            "m_lat" | "m_lon" | "c_wpt_lat" | "c_wpt_lon" | "m_gps_lat" | "m_gps_lon"
                if nmea_is_set(value) =>
            {
                let shown = format!("{name} (°)");
                rows.push(Named::plain(
                    &shown,
                    float_text(nmea_to_degrees(value)),
                    "decimal degrees (negative south and west)",
                ));
            }
            "m_heading" | "c_heading" if value.is_finite() => {
                let shown = format!("{name} (°)");
                rows.push(Named::plain(
                    &shown,
                    float_text(value.to_degrees()),
                    "degrees, clockwise from north",
                ));
            }
            _ => {}
        }
    }
    if let (Some(vx), Some(vy)) = (value_of("m_water_vx"), value_of("m_water_vy")) {
        rows.push(Named::plain(
            "current estimate",
            flow(Xy::new(vx, vy)),
            "speed and the direction it flows to",
        ));
    }
    rows
}

/// A current as a speed and the direction it flows to: `0.150 m/s toward 68.8°`.
pub(crate) fn flow(velocity: Xy) -> String {
    let toward = velocity.x.atan2(velocity.y).to_degrees().rem_euclid(360.0);
    format!("{:.3} m/s toward {toward:.1}°", velocity.length())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_current_flows_toward_its_compass_direction() {
        // East is 90°, north-east 45° (the direction it flows to, clockwise from north).
        assert_eq!(flow(Xy::new(0.2, 0.0)), "0.200 m/s toward 90.0°");
        assert_eq!(flow(Xy::new(0.3, 0.4)), "0.500 m/s toward 36.9°");
        assert_eq!(flow(Xy::new(0.0, -0.1)), "0.100 m/s toward 180.0°");
        assert_eq!(flow(Xy::new(-0.1, 0.0)), "0.100 m/s toward 270.0°");
    }
}
