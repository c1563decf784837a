//! The kinematic vertical-plane flight model and the power model.
//!
//! Not hydrodynamics: the buoyancy pump moves at a fixed rate toward the
//! commanded volume, the vertical speed follows the pumped volume (full
//! volume = the nominal dive or climb rate) with a short lag, pitch slews
//! toward its command, and the horizontal speed follows from the glide angle.
//! An inflection therefore takes time (the pump's travel) and overshoots the
//! target depth by about `rate × (inflection / 4 + lag)`, close to 1 m with the
//! defaults, as real shallow gliders do (domain notes §3).

/// Flight constants.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightParams {
    /// Sub-cycle integration step (s).
    pub step: f64,
    /// Vertical speed at full dive volume (m/s).
    pub dive_rate: f64,
    /// Vertical speed at full climb volume (m/s).
    pub climb_rate: f64,
    /// Pumped volume at which the glider flies at full rate (cc).
    pub pump_max: f64,
    /// Pump speed pumping oil out, going up (cc/s): a full swing ±`pump_max`
    /// takes `2 pump_max / pump_rate`.
    pub pump_rate: f64,
    /// Speed of letting oil in, going down (cc/s).
    pub pump_in_rate: f64,
    /// Time constant of the vertical speed following the pumped volume (s).
    pub speed_lag: f64,
    /// Exponent of the speed law against the net buoyancy ([`SpeedLaw`]).
    pub speed_exponent: f64,
    /// Pitch slew rate of the battery (rad/s).
    pub pitch_rate: f64,
    /// Angle of attack added to the pitch for the glide angle (rad).
    pub angle_of_attack: f64,
    /// Cap on the horizontal speed (m/s) while the pitch is near level.
    pub max_speed: f64,
    /// Pitch (magnitude, rad) the glider settles at diving with the battery
    /// held in place (`use_pitch` 1): the buoyancy, not the battery, tips it.
    pub battpos_dive_pitch: f64,
    /// The same climbing.
    pub battpos_climb_pitch: f64,
}

impl Default for FlightParams {
    /// comet (a shallow Slocum, North Sea, 2019-08-21), fitted by `gloc
    /// calibrate` from comet-2019-222-02-154.dbd; see docs/simulator.md.
    fn default() -> FlightParams {
        FlightParams {
            // 8 sub-steps in a 4.5 s cycle.
            step: 0.6,
            dive_rate: 0.16,
            climb_rate: 0.13,
            pump_max: 230.0,
            pump_rate: 34.6,
            pump_in_rate: 43.7,
            speed_lag: 16.1,
            speed_exponent: 2.0,
            pitch_rate: 0.05,
            angle_of_attack: 2f64.to_radians(),
            max_speed: 0.4,
            battpos_dive_pitch: 0.4485,
            battpos_climb_pitch: 0.4416,
        }
    }
}

/// Power and battery constants.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyParams {
    /// Hotel power while diving (W).
    pub dive_power: f64,
    /// Hotel power while climbing or at the surface (W).
    pub climb_power: f64,
    /// Pumping oil out (going up): J per cc at the surface …
    pub pump_out_j_per_cc: f64,
    /// … plus J per cc per metre of depth.
    pub pump_out_j_per_cc_m: f64,
    /// Letting oil in (going down): J per cc.
    pub pump_in_j_per_cc: f64,
    /// Moving the pitch battery: J per radian of pitch change.
    pub pitch_j_per_rad: f64,
    /// Battery capacity (Wh).
    pub battery_wh: f64,
    /// Battery voltage full and empty, open circuit (V).
    pub volts_full: f64,
    pub volts_empty: f64,
    /// Internal resistance (ohm): the voltage sags by `ohms × current` under load.
    pub battery_ohms: f64,
    /// The science computer and sensors awake (W) and asleep (W), the time a
    /// wake takes (s, drawing `science_on_power`) and the energy of one wake
    /// (J) on top. 0: counted in the hotel load (comet's hotel includes its
    /// science bay, which its log cannot separate).
    pub science_on_power: f64,
    pub science_sleep_power: f64,
    pub science_wake_time: f64,
    pub science_wake_joules: f64,
}

impl Default for EnergyParams {
    /// Hotel, pump and voltage: comet, fitted as the flight constants. The
    /// pump's per-metre term, the pitch battery, the capacity and the empty
    /// voltage: mousebrains/GliderSimulator energy.json (comet's log cannot
    /// give them; see docs/simulator.md).
    fn default() -> EnergyParams {
        EnergyParams {
            dive_power: 1.58,
            climb_power: 1.39,
            pump_out_j_per_cc: 0.51,
            pump_out_j_per_cc_m: 0.0123,
            pump_in_j_per_cc: 0.52,
            // 540 J per battery shift, one shift swings ±26°.
            pitch_j_per_rad: 540.0 / (2.0 * 0.4538),
            battery_wh: 3381.0,
            volts_full: 13.74,
            volts_empty: 10.0,
            battery_ohms: 0.0,
            science_on_power: 0.0,
            science_sleep_power: 0.0,
            science_wake_time: 0.0,
            science_wake_joules: 0.0,
        }
    }
}

/// How the pitch is commanded this cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PitchControl {
    /// `use_pitch` 3: the battery servoes to the commanded angle (and costs energy).
    #[default]
    Servo,
    /// `use_pitch` 1: the battery stays put; the pitch follows the buoyancy
    /// (`battpos_dive_pitch` / `battpos_climb_pitch`) and the battery costs nothing.
    Battpos,
}

/// Energy used by each consumer since the start (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyUse {
    /// The flight computer, sensors and everything always on (hotel load).
    pub hotel: f64,
    /// The buoyancy pump.
    pub pump: f64,
    /// The pitch battery's motor.
    pub pitch: f64,
    /// The science computer and its sensors, on, asleep and waking.
    pub science: f64,
}

impl EnergyUse {
    pub fn total(&self) -> f64 {
        self.hotel + self.pump + self.pitch + self.science
    }
}

/// The vertical speed law: w = k·|V + trim|^e against the net buoyancy
/// (pumped volume V plus the glider's trim, cc). e = ½ is the steady state of
/// lift and drag at a fixed glide angle (drag ∝ speed², gliderflight's
/// model); a real glider's pitch also follows the buoyancy, so `gloc
/// calibrate` fits e from the overshoot at the turns. `trim`
/// and `k` follow from the rates at full volume, so unequal dive and climb
/// rates are a trim: a heavy glider (trim < 0) dives faster than it climbs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedLaw {
    /// cc; > 0: the glider is light.
    pub trim: f64,
    pub k: f64,
    pub exponent: f64,
}

impl SpeedLaw {
    pub fn new(flight: &FlightParams) -> SpeedLaw {
        let exponent = flight.speed_exponent.max(0.05);
        let ratio =
            (flight.climb_rate / flight.dive_rate.max(f64::MIN_POSITIVE)).powf(1.0 / exponent);
        let trim = flight.pump_max * (ratio - 1.0) / (ratio + 1.0);
        let k = flight.dive_rate
            / (flight.pump_max - trim)
                .max(f64::MIN_POSITIVE)
                .powf(exponent);
        SpeedLaw { trim, k, exponent }
    }

    /// Steady vertical speed (m/s, > 0 down) at pumped volume `ballast` (cc, > 0 up).
    pub fn rate(&self, ballast: f64) -> f64 {
        let net = ballast + self.trim;
        let size = net.abs();
        // The common exponents without `powf` (a tenth of a cycle's time).
        let magnitude = if self.exponent == 2.0 {
            size * size
        } else if self.exponent == 0.5 {
            size.sqrt()
        } else if self.exponent == 1.0 {
            size
        } else {
            size.powf(self.exponent)
        };
        -net.signum() * self.k * magnitude
    }
}

/// The vehicle's state between steps. `Copy`: snapshots are cheap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vehicle {
    /// m, 0 at the surface, > 0 below.
    pub depth: f64,
    /// m/s, > 0 going down.
    pub depth_rate: f64,
    /// rad, > 0 nose up.
    pub pitch: f64,
    /// cc, > 0 goes up.
    pub ballast: f64,
    /// Horizontal speed through the water (m/s).
    pub speed: f64,
    /// Horizontal distance flown (m).
    pub distance: f64,
    /// Energy used since the start (J).
    pub energy_joules: f64,
    /// The same by consumer.
    pub energy_use: EnergyUse,
    /// Charge used since the start (Ah).
    pub amp_hours: f64,
    /// Mean current of the last `fly` call (A).
    pub current: f64,
    /// Inflections so far (sign changes of the pumped volume).
    pub inflections: u64,
    /// Sign of the last non-zero pumped volume (0 before any).
    ballast_sign: i8,
}

impl Vehicle {
    /// Open-circuit battery voltage for the energy used so far.
    pub fn open_volts(&self, energy: &EnergyParams) -> f64 {
        let used = self.energy_joules / (energy.battery_wh * 3600.0);
        (energy.volts_full - (energy.volts_full - energy.volts_empty) * used.min(1.0))
            .max(energy.volts_empty)
    }

    /// Battery voltage at the terminals: open circuit less the sag of the last
    /// cycle's mean current through the internal resistance.
    pub fn battery_volts(&self, energy: &EnergyParams) -> f64 {
        (self.open_volts(energy) - energy.battery_ohms * self.current).max(0.0)
    }

    /// The battery's energy is used up.
    pub fn exhausted(&self, energy: &EnergyParams) -> bool {
        self.energy_joules >= energy.battery_wh * 3600.0
    }

    /// Flies `duration` seconds (`law`: [`SpeedLaw::new`] of `flight`, made
    /// once per run) toward the commanded buoyancy (cc, > 0 up) and
    /// pitch (rad; with [`PitchControl::Battpos`] only its sign matters) in
    /// water `water_depth` deep, plus `extra_watts` drawn by the science
    /// computer and sensors.
    #[allow(clippy::too_many_arguments)]
    pub fn fly(
        &mut self,
        duration: f64,
        buoyancy: f64,
        pitch: f64,
        control: PitchControl,
        water_depth: f64,
        flight: &FlightParams,
        law: &SpeedLaw,
        energy: &EnergyParams,
        extra_watts: f64,
    ) {
        let target_ballast = buoyancy.clamp(-flight.pump_max, flight.pump_max);
        let volts = self.battery_volts(energy).max(1e-3);
        let joules_before = self.energy_joules;
        let mut travelled = 0.0;
        // Equal sub-steps no longer than `step` (no sliver at the end of a
        // cycle that is not a multiple of it).
        let steps = (duration / flight.step).ceil().max(1.0);
        let dt = duration / steps;
        for _ in 0..steps as u64 {
            let before = self.depth;
            self.substep(
                dt,
                target_ballast,
                pitch,
                control,
                water_depth,
                flight,
                energy,
                law,
            );
            travelled += (self.depth - before).abs();
        }
        self.energy_joules += extra_watts * duration;
        self.energy_use.science += extra_watts * duration;
        let used = self.energy_joules - joules_before;
        self.amp_hours += used / volts / 3600.0;
        self.current = if duration > 0.0 {
            used / duration / volts
        } else {
            0.0
        };
        // Horizontal speed from the glide angle, once per call: the pitch
        // changes slowly, and a tangent per sub-step was a tenth of the run time.
        let glide = self.pitch.abs() + flight.angle_of_attack;
        self.speed = if self.depth_rate == 0.0 {
            0.0
        } else {
            (self.depth_rate.abs() / glide.tan()).min(flight.max_speed)
        };
        if duration > 0.0 {
            let mean_rate = travelled / duration;
            self.distance += (mean_rate / glide.tan()).min(flight.max_speed) * duration;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn substep(
        &mut self,
        dt: f64,
        target_ballast: f64,
        target_pitch: f64,
        control: PitchControl,
        water_depth: f64,
        flight: &FlightParams,
        energy: &EnergyParams,
        law: &SpeedLaw,
    ) {
        // Pump: out (going up) at pump_rate, in (going down) at pump_in_rate.
        let pump_step =
            (target_ballast - self.ballast).clamp(-flight.pump_in_rate * dt, flight.pump_rate * dt);
        let pump_joules = if pump_step > 0.0 {
            pump_step
                * (energy.pump_out_j_per_cc + energy.pump_out_j_per_cc_m * self.depth.max(0.0))
        } else {
            -pump_step * energy.pump_in_j_per_cc
        };
        self.ballast += pump_step;
        if self.ballast != 0.0 {
            let sign = if self.ballast > 0.0 { 1 } else { -1 };
            if self.ballast_sign != 0 && sign != self.ballast_sign {
                self.inflections += 1;
            }
            self.ballast_sign = sign;
        }

        // Pitch: the battery servoes (and costs energy), or stays put and the
        // buoyancy tips the glider.
        let (target_pitch, j_per_rad) = match control {
            PitchControl::Servo => (target_pitch, energy.pitch_j_per_rad),
            PitchControl::Battpos => {
                let pitch = if self.ballast + law.trim < 0.0 {
                    -flight.battpos_dive_pitch
                } else {
                    flight.battpos_climb_pitch
                };
                (pitch, 0.0)
            }
        };
        let pitch_step =
            (target_pitch - self.pitch).clamp(-flight.pitch_rate * dt, flight.pitch_rate * dt);
        let pitch_joules = pitch_step.abs() * j_per_rad;
        self.pitch += pitch_step;

        // Vertical speed follows the net buoyancy with a lag.
        let wanted_rate = law.rate(self.ballast);
        let blend = (dt / flight.speed_lag.max(dt)).min(1.0);
        self.depth_rate += (wanted_rate - self.depth_rate) * blend;
        self.depth += self.depth_rate * dt;
        if self.depth <= 0.0 {
            // Floating: the surface stops the climb.
            self.depth = 0.0;
            self.depth_rate = self.depth_rate.max(0.0);
        }
        if self.depth >= water_depth {
            // On the bottom.
            self.depth = water_depth;
            self.depth_rate = self.depth_rate.min(0.0);
        }

        // Hotel load.
        let hotel = if self.depth_rate > 0.0 {
            energy.dive_power
        } else {
            energy.climb_power
        };
        let hotel_joules = hotel * dt;
        self.energy_use.hotel += hotel_joules;
        self.energy_use.pump += pump_joules;
        self.energy_use.pitch += pitch_joules;
        self.energy_joules += hotel_joules + pump_joules + pitch_joules;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fly_for(vehicle: &mut Vehicle, seconds: f64, buoyancy: f64, pitch: f64) {
        vehicle.fly(
            seconds,
            buoyancy,
            pitch,
            PitchControl::Servo,
            100.0,
            &FlightParams::default(),
            &SpeedLaw::new(&FlightParams::default()),
            &EnergyParams::default(),
            0.0,
        );
    }

    #[test]
    fn reaches_the_nominal_dive_rate() {
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 400.0, -260.0, -0.4538);
        // Full volume (clipped to 230 cc) gives the dive rate, 0.16 m/s, once
        // the 16 s lag has died out (e^-25).
        assert!(
            (vehicle.depth_rate - 0.16).abs() < 1e-6,
            "{}",
            vehicle.depth_rate
        );
        assert!((vehicle.pitch + 0.4538).abs() < 1e-9);
        // Horizontal speed: 0.16 / tan(26° + 2°) ≈ 0.301 m/s.
        assert!((vehicle.speed - 0.16 / (0.4538f64 + 2f64.to_radians()).tan()).abs() < 1e-6);
        assert!(vehicle.energy_joules > 400.0 * 1.39);
    }

    #[test]
    fn an_inflection_overshoots_as_comet_does() {
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 400.0, -260.0, -0.4538);
        let turn_at = vehicle.depth;
        let mut deepest = turn_at;
        for _ in 0..400 {
            fly_for(&mut vehicle, 0.5, 260.0, 0.4538);
            deepest = deepest.max(vehicle.depth);
        }
        // comet's bottom turns overshoot their turn by 1.62 m (median of 17 in
        // comet-2019-222-02-154.dbd; its first, read by hand from the log:
        // 38.95 m at the turn's row, 40.51 m deepest): the defaults, fitted
        // to that log, land within 10% of it.
        let overshoot = deepest - turn_at;
        assert!((1.46..1.78).contains(&overshoot), "overshoot {overshoot}");
        assert!(vehicle.depth < turn_at - 10.0, "climbing again");
        assert_eq!(vehicle.inflections, 1);
    }

    #[test]
    fn surface_and_bottom_clip() {
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 60.0, 260.0, 0.4538);
        assert_eq!(vehicle.depth, 0.0);
        let mut vehicle = Vehicle::default();
        vehicle.fly(
            2000.0,
            -260.0,
            -0.4538,
            PitchControl::Servo,
            40.0,
            &FlightParams::default(),
            &SpeedLaw::new(&FlightParams::default()),
            &EnergyParams::default(),
            0.0,
        );
        assert_eq!(vehicle.depth, 40.0);
        assert_eq!(vehicle.depth_rate, 0.0);
    }
}
