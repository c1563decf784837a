//! Horizontal navigation: where the glider truly is, where it believes it is
//! (dead reckoning, GPS at the surface, the surfacing current estimate), and
//! the firmware's current-corrected steering toward a waypoint.
//!
//! The formulas are the firmware's as measured on comet's real log
//! (`docs/simulator.md`, "Navigation"; domain notes §7): each is a plain
//! function here, tested against the log's own values, and the simulator's
//! [`Navigation`] state calls the same functions every control cycle.
//!
//! Coordinates: local mission coordinates (LMC), metres east (`x`) and north
//! (`y`) of the mission origin; latitude and longitude as the glider logs them,
//! NMEA `[d]ddmm.mmm` (negative south and west). [`Lmc`] is the one projection
//! between them and [`nmea_to_degrees`] / [`degrees_to_nmea`] the one
//! conversion, used by the simulator, its logs and the tests.

use std::f64::consts::{PI, TAU};

/// The masterdata's "never set" value of a latitude or longitude sensor.
pub const NMEA_UNSET: f64 = 69_696_969.0;

/// The start position when a mission sets no `s_ini_lat` / `s_ini_lon`
/// (NMEA): the German Bight, 54°18′ N 7°24′ E, near comet's August 2019 segments.
pub const DEFAULT_START_NMEA: (f64, f64) = (5418.0, 724.0);

/// Below this |pitch| the firmware does not trust the glide angle and dead
/// reckons with the mean speed (11.3°, `m_is_speed_estimated`).
pub const MIN_DR_PITCH: f64 = 11.3 * PI / 180.0;

/// A point or a vector in local mission coordinates (m or m/s; x east, y north).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Xy {
    pub x: f64,
    pub y: f64,
}

impl Xy {
    pub const ZERO: Xy = Xy { x: 0.0, y: 0.0 };

    pub fn new(x: f64, y: f64) -> Xy {
        Xy { x, y }
    }

    pub fn length(self) -> f64 {
        self.x.hypot(self.y)
    }

    pub fn distance(self, other: Xy) -> f64 {
        (other - self).length()
    }

    /// A vector of this length toward `heading` (rad clockwise from north).
    pub fn polar(length: f64, heading: f64) -> Xy {
        let (sin, cos) = heading.sin_cos();
        Xy::new(length * sin, length * cos)
    }
}

impl std::ops::Add for Xy {
    type Output = Xy;
    fn add(self, other: Xy) -> Xy {
        Xy::new(self.x + other.x, self.y + other.y)
    }
}

impl std::ops::Sub for Xy {
    type Output = Xy;
    fn sub(self, other: Xy) -> Xy {
        Xy::new(self.x - other.x, self.y - other.y)
    }
}

impl std::ops::Mul<f64> for Xy {
    type Output = Xy;
    fn mul(self, factor: f64) -> Xy {
        Xy::new(self.x * factor, self.y * factor)
    }
}

/// NMEA `[d]ddmm.mmm` (degrees × 100 + minutes, signed) to decimal degrees.
pub fn nmea_to_degrees(nmea: f64) -> f64 {
    let magnitude = nmea.abs();
    let degrees = (magnitude / 100.0).trunc();
    let minutes = magnitude - degrees * 100.0;
    (degrees + minutes / 60.0).copysign(nmea)
}

/// Decimal degrees to NMEA `[d]ddmm.mmm`.
pub fn degrees_to_nmea(degrees: f64) -> f64 {
    let magnitude = degrees.abs();
    let whole = magnitude.trunc();
    (whole * 100.0 + (magnitude - whole) * 60.0).copysign(degrees)
}

/// Whether a latitude/longitude sensor holds a position (not NaN, not the
/// masterdata's 69696969, within ±180°).
pub fn nmea_is_set(nmea: f64) -> bool {
    nmea.is_finite() && nmea != NMEA_UNSET && nmea.abs() <= 18_000.0
}

/// The local mission coordinates: a plane tangent to the WGS 84 ellipsoid at
/// the origin, x along the parallel and y along the meridian, scaled by the
/// ellipsoid's radii of curvature there. Decision: the firmware projects
/// through UTM and rotates the grid to true north (`x_utm_to_lmc_*`); over the
/// tens of kilometres a mission spans, the two differ by under 0.5%, and a
/// tangent plane needs no zone and inverts exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lmc {
    /// The origin (decimal degrees).
    pub origin_lat: f64,
    pub origin_lon: f64,
    metres_per_degree_lat: f64,
    metres_per_degree_lon: f64,
}

impl Lmc {
    /// The plane around an origin given in decimal degrees. Latitudes are
    /// clipped to ±89.9° so the scale never vanishes.
    pub fn new(origin_lat: f64, origin_lon: f64) -> Lmc {
        const A: f64 = 6_378_137.0;
        const E2: f64 = 0.006_694_379_990_14;
        let lat = origin_lat.clamp(-89.9, 89.9);
        let sin = lat.to_radians().sin();
        let w = 1.0 - E2 * sin * sin;
        let meridian = A * (1.0 - E2) / (w * w.sqrt());
        let normal = A / w.sqrt();
        Lmc {
            origin_lat: lat,
            origin_lon,
            metres_per_degree_lat: meridian * PI / 180.0,
            metres_per_degree_lon: normal * lat.to_radians().cos() * PI / 180.0,
        }
    }

    /// The plane around an origin given in NMEA.
    pub fn from_nmea(lat: f64, lon: f64) -> Lmc {
        Lmc::new(nmea_to_degrees(lat), nmea_to_degrees(lon))
    }

    /// Decimal degrees to local mission coordinates.
    pub fn to_xy(&self, lat: f64, lon: f64) -> Xy {
        let mut dlon = lon - self.origin_lon;
        if dlon > 180.0 {
            dlon -= 360.0;
        } else if dlon < -180.0 {
            dlon += 360.0;
        }
        Xy::new(
            dlon * self.metres_per_degree_lon,
            (lat - self.origin_lat) * self.metres_per_degree_lat,
        )
    }

    /// Local mission coordinates to decimal degrees (latitude, longitude).
    pub fn to_lat_lon(&self, at: Xy) -> (f64, f64) {
        let lat = self.origin_lat + at.y / self.metres_per_degree_lat;
        let mut lon = self.origin_lon + at.x / self.metres_per_degree_lon;
        if lon > 180.0 {
            lon -= 360.0;
        } else if lon < -180.0 {
            lon += 360.0;
        }
        (lat, lon)
    }

    /// NMEA latitude and longitude to local mission coordinates.
    pub fn nmea_to_xy(&self, lat: f64, lon: f64) -> Xy {
        self.to_xy(nmea_to_degrees(lat), nmea_to_degrees(lon))
    }

    /// Local mission coordinates to NMEA (latitude, longitude).
    pub fn xy_to_nmea(&self, at: Xy) -> (f64, f64) {
        let (lat, lon) = self.to_lat_lon(at);
        (degrees_to_nmea(lat), degrees_to_nmea(lon))
    }
}

/// The compass bearing from one point to another (rad, clockwise from north, in [0, 2π)).
pub fn bearing(from: Xy, to: Xy) -> f64 {
    let delta = to - from;
    delta.x.atan2(delta.y).rem_euclid(TAU)
}

/// The angle from `from` to `to`, wrapped to [-π, π).
pub fn angle_difference(to: f64, from: f64) -> f64 {
    (to - from + PI).rem_euclid(TAU) - PI
}

/// The firmware's aim point: the waypoint moved against the believed current
/// by the time the glider needs to get there (`m_dist_to_wpt` / `m_avg_speed`).
/// Without a usable mean speed, the waypoint itself.
pub fn aim_point(position: Xy, waypoint: Xy, water: Xy, avg_speed: f64) -> Xy {
    if avg_speed.is_nan() || avg_speed <= 0.0 {
        return waypoint;
    }
    let time_to_go = position.distance(waypoint) / avg_speed;
    waypoint - water * time_to_go
}

/// `c_heading` toward a waypoint: the bearing from the dead-reckoned position
/// to [`aim_point`], recomputed every cycle. `water` is the believed current
/// (`m_water_vx`, `m_water_vy`), zero when `u_use_current_correction` is 0.
pub fn steer(position: Xy, waypoint: Xy, water: Xy, avg_speed: f64) -> f64 {
    bearing(position, aim_point(position, waypoint, water, avg_speed))
}

/// `m_speed` and `m_is_speed_estimated`: the horizontal speed through the water
/// from the glide angle when |pitch| ≥ 11.3°, otherwise the mean speed.
pub fn dead_reckoning_speed(
    depth_rate: f64,
    pitch: f64,
    angle_of_attack: f64,
    avg_speed: f64,
) -> (f64, bool) {
    if pitch.abs() >= MIN_DR_PITCH {
        let glide = (pitch.abs() + angle_of_attack.abs()).tan();
        (depth_rate.abs() / glide, false)
    } else {
        (avg_speed, true)
    }
}

/// `m_initial_water_vx/vy` at the first fix: the prior segment's current plus
/// the dead-reckoning error (`m_dr_x_ini_err`: first fix − DR surfacing
/// position) spread over the time underwater (`m_dr_time`).
pub fn initial_water_velocity(prior: Xy, initial_error: Xy, dr_time: f64) -> Xy {
    if dr_time.is_nan() || dr_time <= 0.0 {
        return prior;
    }
    prior + initial_error * (1.0 / dr_time)
}

/// `m_dr_x_ta_postfix_drift`: the drift between the first and the last fix
/// (`m_dr_x_postfix_drift`, over `m_dr_postfix_time`) scaled back to the time
/// from surfacing to the first fix (`m_dr_fix_time`) and negated: the part of
/// the initial error that the surface drift, not the current underwater, made.
pub fn time_adjusted_postfix_drift(postfix_drift: Xy, fix_time: f64, postfix_time: f64) -> Xy {
    if postfix_time.is_nan() || postfix_time <= 0.0 || !fix_time.is_finite() {
        return Xy::ZERO;
    }
    postfix_drift * (-fix_time / postfix_time)
}

/// `m_final_water_vx/vy`, taken before the next dive: as the initial estimate,
/// with the surface drift before the first fix taken out
/// (`m_dr_x_actual_err` = initial error + time-adjusted post-fix drift).
pub fn final_water_velocity(prior: Xy, initial_error: Xy, adjusted_drift: Xy, dr_time: f64) -> Xy {
    initial_water_velocity(prior, initial_error + adjusted_drift, dr_time)
}

/// `x_dr_state`: where the surfacing current estimate stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrState {
    /// Dead reckoning underwater.
    Underwater = 1,
    /// At the surface, waiting for the first GPS fix.
    Surfaced = 2,
    /// The first fix came: `m_initial_water_*` computed, fixes each cycle.
    FirstFix = 3,
    /// Leaving the surface: `m_final_water_*` computed.
    PostFix = 4,
}

/// Constants of the horizontal model (`[simulator]` names in `docs/simulator.md`).
#[derive(Clone, Debug, PartialEq)]
pub struct NavParams {
    /// Time constant of the heading's approach to its target (s).
    pub turn_time: f64,
    /// Fastest turn (rad/s).
    pub max_turn_rate: f64,
    /// Heading error the roll bias holds on dives and on climbs (rad; comet:
    /// +16.5° and −13.9°), a zig-zag about the commanded heading.
    pub heading_bias_dive: f64,
    pub heading_bias_climb: f64,
    /// Time constant of `m_avg_speed`, the running mean of `m_speed` (s).
    pub avg_speed_time: f64,
}

impl Default for NavParams {
    fn default() -> NavParams {
        NavParams {
            turn_time: 15.0,
            max_turn_rate: 0.1,
            heading_bias_dive: 16.5 * PI / 180.0,
            heading_bias_climb: -13.9 * PI / 180.0,
            avg_speed_time: 6.0 * 3600.0,
        }
    }
}

/// The mission's environment and initial belief, from its `s_` and `m_` sensors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavSetup {
    /// Start position, NMEA (`s_ini_lat`, `s_ini_lon`); the LMC origin.
    pub start_lat: f64,
    pub start_lon: f64,
    /// The true depth-averaged current (m/s, x east, y north), from
    /// `s_water_speed` and `s_water_direction` (the direction it flows to).
    pub water: Xy,
    /// The glider's belief at the start (`m_water_vx`, `m_water_vy`).
    pub believed_water: Xy,
    /// `m_avg_speed` at the start (m/s).
    pub avg_speed: f64,
    /// Initial heading (rad).
    pub heading: f64,
    /// `u_use_current_correction` ≠ 0.
    pub current_correction: bool,
}

/// One cycle of the vehicle, as the navigation sees it.
#[derive(Clone, Copy, Debug)]
pub struct CycleMotion {
    /// Mission seconds at the end of the cycle.
    pub time: f64,
    /// The cycle's period (s).
    pub period: f64,
    /// Distance flown through the water this cycle (m).
    pub through_water: f64,
    pub depth: f64,
    pub depth_rate: f64,
    pub pitch: f64,
    pub angle_of_attack: f64,
    /// The depth above which the glider is at the surface (`u_reqd_depth_at_surface`).
    pub surface_depth: f64,
    /// The winning heading command of the cycle, if any.
    pub heading_command: Option<f64>,
    /// A surface behavior (or an abort) commands the climb: shallower than
    /// `surface_depth` the glider is then at the surface. A yo's top turn that
    /// overshoots above it is not a surfacing (comet's tops reach 1 m).
    pub surfacing: bool,
}

/// The horizontal state: truth, belief, and the surfacing estimate.
#[derive(Clone, Debug)]
pub struct Navigation {
    pub lmc: Lmc,
    pub params: NavParams,
    /// Seconds at the surface before the first GPS fix (`SimConfig::gps_fix_time`).
    pub first_fix_delay: f64,
    /// Where the glider really is.
    pub true_position: Xy,
    /// The true current.
    pub true_water: Xy,
    /// The true (and measured: the compass is exact) heading (rad).
    pub heading: f64,
    /// `c_heading`: the last heading commanded.
    pub commanded_heading: Option<f64>,
    /// The dead-reckoned position (`m_x_lmc`, `m_y_lmc`).
    pub dead_reckoned: Xy,
    /// `m_water_vx/vy`: the current the glider believes in.
    pub water: Xy,
    pub current_correction: bool,
    pub prior_segment_water: Xy,
    pub initial_water: Xy,
    pub final_water: Xy,
    /// `m_speed`, `m_is_speed_estimated`, `m_avg_speed`.
    pub speed: f64,
    pub speed_estimated: bool,
    pub avg_speed: f64,
    pub dr_state: DrState,
    /// `m_dr_time`, `m_dr_fix_time`, `m_dr_postfix_time` (s; −1 unset).
    pub dr_time: f64,
    pub fix_time: f64,
    pub postfix_time: f64,
    /// `m_dr_surf_x/y_lmc`, `m_dr_x/y_ini_err`, `m_gps_dist_from_dr`.
    pub dr_surface: Xy,
    pub initial_error: Xy,
    pub adjusted_drift: Xy,
    pub gps_dist_from_dr: f64,
    /// The GPS fix of this cycle, if the glider got one (LMC).
    pub gps_fix: Option<Xy>,
    /// The last GPS fix (LMC), for `m_gps_lat/lon`.
    pub last_gps: Option<Xy>,
    /// Mission seconds of the first fix of this surfacing, and the fix.
    first_fix: Option<(f64, Xy)>,
    last_fix_time: f64,
    dive_start: f64,
    surfaced_at: f64,
    /// Surfacings so far, each with the first fix (LMC), for plots.
    pub surfacings: u64,
}

impl Navigation {
    pub fn new(setup: &NavSetup, params: NavParams, first_fix_delay: f64) -> Navigation {
        let lmc = Lmc::from_nmea(setup.start_lat, setup.start_lon);
        let water = if setup.current_correction {
            setup.believed_water
        } else {
            Xy::ZERO
        };
        Navigation {
            lmc,
            params,
            first_fix_delay,
            true_position: Xy::ZERO,
            true_water: setup.water,
            heading: setup.heading.rem_euclid(TAU),
            commanded_heading: None,
            dead_reckoned: Xy::ZERO,
            water,
            current_correction: setup.current_correction,
            prior_segment_water: water,
            initial_water: water,
            final_water: water,
            speed: 0.0,
            speed_estimated: true,
            avg_speed: setup.avg_speed,
            // The mission starts at the surface with the pilot's fix.
            dr_state: DrState::PostFix,
            dr_time: -1.0,
            fix_time: -1.0,
            postfix_time: -1.0,
            dr_surface: Xy::ZERO,
            initial_error: Xy::ZERO,
            adjusted_drift: Xy::ZERO,
            gps_dist_from_dr: 0.0,
            gps_fix: None,
            last_gps: Some(Xy::ZERO),
            first_fix: None,
            last_fix_time: 0.0,
            dive_start: 0.0,
            surfaced_at: 0.0,
            surfacings: 0,
        }
    }

    /// The heading toward `waypoint` the firmware would command now.
    pub fn steer_to(&self, waypoint: Xy) -> f64 {
        steer(self.dead_reckoned, waypoint, self.water, self.avg_speed)
    }

    /// Advances the horizontal state over one cycle the vertical model flew.
    pub fn advance(&mut self, motion: &CycleMotion) {
        let diving = motion.depth_rate > 0.0;
        let underwater = motion.depth > motion.surface_depth;
        let surfaced = !underwater && motion.surfacing;
        // Steering: the heading relaxes toward the command plus the roll
        // bias's error while flying; at the surface the fin does nothing.
        let heading_before = self.heading;
        if let Some(command) = motion.heading_command {
            self.commanded_heading = Some(command);
        }
        if underwater && motion.through_water > 0.0 {
            if let Some(command) = self.commanded_heading {
                let bias = if diving {
                    self.params.heading_bias_dive
                } else {
                    self.params.heading_bias_climb
                };
                let error = angle_difference(command + bias, self.heading);
                let relax = if self.params.turn_time > 0.0 {
                    1.0 - (-motion.period / self.params.turn_time).exp()
                } else {
                    1.0
                };
                let limit = self.params.max_turn_rate.max(0.0) * motion.period;
                let turn = (error * relax).clamp(-limit, limit);
                self.heading = (self.heading + turn).rem_euclid(TAU);
            }
        }
        let mean_heading = heading_before + 0.5 * angle_difference(self.heading, heading_before);
        let through_water = if motion.through_water.is_finite() {
            motion.through_water
        } else {
            0.0
        };
        self.true_position = self.true_position
            + Xy::polar(through_water, mean_heading)
            + self.true_water * motion.period;

        // The glider's own dead reckoning.
        let (speed, estimated) = dead_reckoning_speed(
            motion.depth_rate,
            motion.pitch,
            motion.angle_of_attack,
            self.avg_speed,
        );
        self.speed = if surfaced { 0.0 } else { speed };
        self.speed_estimated = estimated;
        if !surfaced && !estimated && self.params.avg_speed_time > 0.0 {
            let weight = (motion.period / self.params.avg_speed_time).min(1.0);
            self.avg_speed += (speed - self.avg_speed) * weight;
        }
        self.gps_fix = None;
        match self.dr_state {
            DrState::Underwater => {
                if !surfaced || diving {
                    self.dead_reckon(motion.period);
                } else {
                    self.dr_state = DrState::Surfaced;
                    self.surfaced_at = motion.time;
                    self.dr_time = motion.time - self.dive_start;
                    self.dr_surface = self.dead_reckoned;
                    self.first_fix = None;
                }
            }
            DrState::Surfaced => {
                if underwater && diving {
                    // Dove again before a fix: the segment goes on.
                    self.dr_state = DrState::Underwater;
                    self.dead_reckon(motion.period);
                } else if motion.time - self.surfaced_at >= self.first_fix_delay {
                    let fix = self.true_position;
                    self.fix_time = motion.time - self.surfaced_at;
                    self.initial_error = fix - self.dr_surface;
                    self.gps_dist_from_dr = self.initial_error.length();
                    self.initial_water = initial_water_velocity(
                        self.prior_segment_water,
                        self.initial_error,
                        self.dr_time,
                    );
                    if self.current_correction {
                        self.water = self.initial_water;
                    }
                    self.first_fix = Some((motion.time, fix));
                    self.take_fix(fix, motion.time);
                    self.dr_state = DrState::FirstFix;
                    self.surfacings += 1;
                }
            }
            DrState::FirstFix => {
                if underwater || diving {
                    // Leaving: the surface drift comes out of the estimate.
                    if let Some((first_time, first)) = self.first_fix {
                        let last = self.last_gps.unwrap_or(first);
                        self.postfix_time = self.last_fix_time - first_time;
                        self.adjusted_drift = time_adjusted_postfix_drift(
                            last - first,
                            self.fix_time,
                            self.postfix_time,
                        );
                        self.final_water = final_water_velocity(
                            self.prior_segment_water,
                            self.initial_error,
                            self.adjusted_drift,
                            self.dr_time,
                        );
                        if self.current_correction {
                            self.water = self.final_water;
                        }
                        self.prior_segment_water = self.water;
                    }
                    self.dr_state = DrState::PostFix;
                } else {
                    self.take_fix(self.true_position, motion.time);
                }
            }
            DrState::PostFix => {
                if underwater {
                    self.dr_state = DrState::Underwater;
                    self.dive_start = motion.time;
                    self.dr_time = -1.0;
                    self.fix_time = -1.0;
                    self.postfix_time = -1.0;
                    self.dead_reckon(motion.period);
                } else {
                    self.take_fix(self.true_position, motion.time);
                }
            }
        }
    }

    fn dead_reckon(&mut self, period: f64) {
        self.dead_reckoned =
            self.dead_reckoned + Xy::polar(self.speed, self.heading) * period + self.water * period;
    }

    fn take_fix(&mut self, fix: Xy, time: f64) {
        self.gps_fix = Some(fix);
        self.last_gps = Some(fix);
        self.last_fix_time = time;
        self.dead_reckoned = fix;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nmea_round_trips() {
        for nmea in [5418.9684, -4507.25, 724.5959, -12330.001, 0.0, 5959.999] {
            let back = degrees_to_nmea(nmea_to_degrees(nmea));
            assert!((back - nmea).abs() < 1e-9, "{nmea} {back}");
        }
        // 54°18.9684′ by hand.
        assert!((nmea_to_degrees(5418.9684) - (54.0 + 18.9684 / 60.0)).abs() < 1e-12);
        assert!((nmea_to_degrees(-724.5) + (7.0 + 24.5 / 60.0)).abs() < 1e-12);
    }

    #[test]
    fn one_minute_of_latitude_is_a_nautical_mile_near_it() {
        let lmc = Lmc::from_nmea(5418.0, 724.0);
        let north = lmc.nmea_to_xy(5419.0, 724.0);
        // 1′ of latitude at 54° N: 1,855 m on WGS 84 (1,852 m is the mean).
        assert!((north.y - 1855.0).abs() < 2.0, "{north:?}");
        assert!(north.x.abs() < 1e-9);
        // 1′ of longitude: 1,855 m × cos 54.3° ≈ 1,084 m (radius of the parallel).
        let east = lmc.nmea_to_xy(5418.0, 725.0);
        assert!((east.x - 1084.0).abs() < 3.0, "{east:?}");
        let (lat, lon) = lmc.xy_to_nmea(Xy::new(1234.5, -678.9));
        let back = lmc.nmea_to_xy(lat, lon);
        assert!(back.distance(Xy::new(1234.5, -678.9)) < 1e-6);
    }

    #[test]
    fn steering_aims_upstream_of_the_waypoint() {
        // 1,000 m north, a 0.1 m/s current to the east, 0.25 m/s through the
        // water: 4,000 s to go, so aim 400 m west of the waypoint.
        let heading = steer(Xy::ZERO, Xy::new(0.0, 1000.0), Xy::new(0.1, 0.0), 0.25);
        let expected = (-400.0f64).atan2(1000.0).rem_euclid(TAU);
        assert!((heading - expected).abs() < 1e-12);
        // No speed: straight at the waypoint.
        assert_eq!(
            steer(Xy::ZERO, Xy::new(10.0, 0.0), Xy::new(0.1, 0.0), 0.0),
            PI / 2.0
        );
    }

    #[test]
    fn dead_reckoning_speed_from_the_glide_angle_or_the_mean() {
        let (speed, estimated) = dead_reckoning_speed(0.15, -0.45, 0.04, 0.3);
        assert!(!estimated);
        assert!((speed - 0.15 / (0.49f64).tan()).abs() < 1e-12);
        assert_eq!(dead_reckoning_speed(0.0, 0.1, 0.04, 0.3), (0.3, true));
    }

    #[test]
    fn no_nan_from_degenerate_inputs() {
        let lmc = Lmc::new(90.0, 0.0);
        let at = lmc.to_xy(89.0, 10.0);
        assert!(at.x.is_finite() && at.y.is_finite());
        assert_eq!(
            initial_water_velocity(Xy::new(0.1, 0.2), Xy::new(5.0, 5.0), 0.0),
            Xy::new(0.1, 0.2)
        );
        assert_eq!(
            time_adjusted_postfix_drift(Xy::new(1.0, 1.0), 100.0, 0.0),
            Xy::ZERO
        );
    }
}
