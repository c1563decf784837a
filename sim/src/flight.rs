//! The vertical-plane flight model (a force balance) and the power model.
//!
//! After Merckelbach, Berger, Schrum & Mardon (2019, JTECH 36:281) and
//! smerckel/gliderflight's dynamic model (read, not copied): the net buoyancy
//! of the hull (volume `hull_volume`, squeezed by `hull_compressibility` with
//! the pressure) plus the pumped volume, against the glider's `mass`, drives
//! it along its glide path; lift and drag follow the angle of attack (lift
//! slope, zero-lift drag `drag_cd0` plus induced drag `drag_cd1`·α²); added
//! mass along and across the hull makes the speed relax rather than jump.
//! The pitch comes from the battery: held in place (`use_pitch` 1) it follows
//! gliderflight's trim relation tan θ = T1·ΔV + T2·battpos + T3 with a lag
//! (the hull rotating), servoed (`use_pitch` 3) it slews to the command.
//! The pump and the pitch set how long a turn takes, not inertia (domain
//! notes §7: comet's turns take 20.7 and 21.1 s). The pumped volume acts on
//! the buoyancy and the battery relation `ballast_delay` after the pump moves
//! it, as comet's turns show (docs/simulator.md §Turns).

/// comet 154's ballast delay (s), as `gloc calibrate` fits it: the force
/// balance fed the log's pump and pitch follows its depth best through 33 turns.
pub const BALLAST_DELAY_COMET: f64 = 4.75;

/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.81;
/// Metres of battery travel per inch (`m_battpos` is in inches, T2 per metre).
pub const METRES_PER_INCH: f64 = 0.0254;
/// Pitch (rad) below which a steady glide has no angle-of-attack solution
/// worth the name (the glider sinks or rises nearly vertically).
const MIN_GLIDE_PITCH: f64 = 0.02;

/// Flight constants.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightParams {
    /// Sub-cycle integration step (s).
    pub step: f64,
    /// Pumped volume the pump can reach either way (cc).
    pub pump_max: f64,
    /// Pump speed pumping oil out, going up (cc/s): a full swing ±`pump_max`
    /// takes `2 pump_max / pump_rate`.
    pub pump_rate: f64,
    /// Speed of letting oil in, going down (cc/s).
    pub pump_in_rate: f64,
    /// Pitch slew rate of the servoed battery (`use_pitch` 3) (rad/s).
    pub pitch_rate: f64,
    /// With the battery held (`use_pitch` 1) the hull swings toward the
    /// battery relation's pitch as a damped pendulum: its natural period (s) …
    pub pitch_period: f64,
    /// … and its damping ratio (1: critical, < 1 overshoots).
    pub pitch_damping: f64,
    /// The glider's mass (kg).
    pub mass: f64,
    /// Hull volume at the surface with nothing pumped (L).
    pub hull_volume: f64,
    /// Relative loss of hull volume per pascal of pressure (1/Pa).
    pub hull_compressibility: f64,
    /// Sea-water density (kg/m³), the same at every depth.
    pub water_density: f64,
    /// Zero-lift drag coefficient.
    pub drag_cd0: f64,
    /// Induced drag coefficient (per rad²).
    pub drag_cd1: f64,
    /// Lift coefficient per radian of angle of attack (wings and hull).
    pub lift_slope: f64,
    /// Reference (wing) area of the coefficients (m²).
    pub wing_area: f64,
    /// Added mass along the hull, as a fraction of `mass`.
    pub added_mass_along: f64,
    /// Added mass across the hull, as a fraction of `mass`.
    pub added_mass_across: f64,
    /// The battery relation tan θ = T1·ΔV + T2·battpos + T3: T1 per m³ of
    /// pumped volume …
    pub pitch_t1: f64,
    /// … T2 per metre of battery position (> 0 nose down) …
    pub pitch_t2: f64,
    /// … and T3, the trim.
    pub pitch_t3: f64,
    /// Seconds after the pump's volume (`m_ballast_pumped`) changes that it
    /// acts on the glider, on its buoyancy and (battery held) on the battery
    /// relation's pitch ([`Vehicle::acting_volume`]). comet: `gloc calibrate`
    /// fits it from the turns (docs/simulator.md §Turns).
    pub ballast_delay: f64,
}

impl Default for FlightParams {
    /// comet (a shallow Slocum, North Sea, 2019-08-21), fitted by `gloc
    /// calibrate` from comet-2019-222-02-154.dbd and by gliderflight on the
    /// same log; the rest after gliderflight and glidersim (docs/simulator.md).
    fn default() -> FlightParams {
        FlightParams {
            // 8 sub-steps in a 4.5 s cycle.
            step: 0.6,
            pump_max: 230.0,
            pump_rate: 34.6,
            pump_in_rate: 43.7,
            pitch_rate: 0.05,
            // The hull's swing, the drag, the volume and the battery relation:
            // `gloc calibrate` on comet 154 (gliderflight's glidertrim gives
            // Cd0 0.209, Vg 71.549 L, T1 2053 on the same log).
            pitch_period: 16.6,
            pitch_damping: 0.35,
            // glidersim's comet (examples/gs_example.py).
            mass: 73.3,
            hull_volume: 71.547,
            // gliderflight's default.
            hull_compressibility: 5.0e-10,
            // comet 154's CTD (.ebd): TEOS-10 in-situ density, mean of 8,248
            // samples, 1023.8–1024.1.
            water_density: 1024.0,
            drag_cd0: 0.2048,
            // gliderflight: Cd1 as glidertrim holds it, aw from the wing
            // (aspect ratio 7, sweep 43°) plus ah 3.8, S 0.1 m², added mass
            // 0.2 and 0.92 of the mass.
            drag_cd1: 10.49,
            lift_slope: 3.73 + 3.8,
            wing_area: 0.1,
            added_mass_along: 0.2,
            added_mass_across: 0.92,
            pitch_t1: 2080.0,
            // T2 as gliderflight fits it on comet 154 (a held battery cannot
            // separate it from T3); T3 from `gloc calibrate` with it.
            pitch_t2: -39.0,
            pitch_t3: 0.4096,
            ballast_delay: BALLAST_DELAY_COMET,
        }
    }
}

impl FlightParams {
    /// Net upward force (N) at `depth` (m) with `ballast` (cc) pumped.
    pub fn net_buoyancy(&self, ballast: f64, depth: f64) -> f64 {
        let pressure = self.water_density * GRAVITY * depth.max(0.0);
        let volume =
            self.hull_volume * 1e-3 * (1.0 - self.hull_compressibility * pressure) + ballast * 1e-6;
        GRAVITY * (self.water_density * volume - self.mass)
    }

    /// The pitch (rad) the battery relation gives with the battery at
    /// `battpos` (in) and `ballast` (cc) pumped.
    pub fn battpos_pitch(&self, ballast: f64, battpos: f64) -> f64 {
        (self.pitch_t1 * ballast * 1e-6 + self.pitch_t2 * battpos * METRES_PER_INCH + self.pitch_t3)
            .atan()
    }

    /// The steady angle of attack (rad, the sign of the pitch) at `pitch`:
    /// lift and drag balance the buoyancy along a glide path at θ + α, so
    /// α = (Cd0 + Cd1·α²) / (lift slope · tan(|θ| + |α|)). 0 below a pitch
    /// where no steady glide exists.
    pub fn steady_angle_of_attack(&self, pitch: f64) -> f64 {
        let theta = pitch.abs();
        if theta < MIN_GLIDE_PITCH {
            return 0.0;
        }
        let mut alpha: f64 = 0.0;
        // A contraction for any pitch a glider flies: 12 rounds reach 1e-9.
        for _ in 0..12 {
            let next = (self.drag_cd0 + self.drag_cd1 * alpha * alpha)
                / (self.lift_slope * (theta + alpha).tan()).max(1e-9);
            alpha = next.min(std::f64::consts::FRAC_PI_2 - theta);
        }
        alpha * pitch.signum()
    }

    /// Steady glide at `pitch` with `ballast` pumped at `depth`: (horizontal
    /// speed, vertical speed > 0 down) in m/s, 0 when buoyancy and pitch
    /// disagree (a light glider pointing down).
    pub fn steady_glide(&self, ballast: f64, pitch: f64, depth: f64) -> (f64, f64) {
        let force = self.net_buoyancy(ballast, depth);
        let alpha = self.steady_angle_of_attack(pitch);
        let glide = pitch + alpha;
        let drag = self.drag_cd0 + self.drag_cd1 * alpha * alpha;
        let squared = 2.0 * force * glide.sin() / (self.water_density * self.wing_area * drag);
        if squared.is_nan() || squared <= 0.0 || pitch.abs() < MIN_GLIDE_PITCH {
            return (0.0, 0.0);
        }
        let speed = squared.sqrt();
        (speed * glide.cos(), -speed * glide.sin())
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
    /// `use_pitch` 1: the battery stays where the command puts it (the pitch
    /// argument is then the battery position, in); the pitch follows the
    /// battery relation (T1, T2, T3) as the pumped volume changes, and the
    /// battery costs nothing.
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

/// One step of the hull's pitch swinging toward `target` (rad) as a damped
/// pendulum (`period` s, `damping` ratio), in sub-steps short enough for
/// semi-implicit Euler to stay stable: (pitch, pitch rate).
pub fn swing_pitch(
    (mut pitch, mut rate): (f64, f64),
    target: f64,
    dt: f64,
    period: f64,
    damping: f64,
) -> (f64, f64) {
    let omega = std::f64::consts::TAU / period.max(1e-3);
    let steps = (omega * dt / MAX_SWING_STEP).ceil().max(1.0);
    let h = dt / steps;
    for _ in 0..steps as u32 {
        rate += h * (omega * omega * (target - pitch) - 2.0 * damping * omega * rate);
        pitch += h * rate;
    }
    (pitch, rate)
}

/// Largest ω·h of a pitch sub-step ([`swing_pitch`]).
const MAX_SWING_STEP: f64 = 0.25;

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
    /// The steady angle of attack at the present pitch (rad), as the
    /// glider's own dead reckoning uses it.
    pub angle_of_attack: f64,
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
    /// rad/s, the hull's swing with the battery held.
    pitch_velocity: f64,
    /// The pitch `angle_of_attack` was solved for (a dozen tangents a cycle
    /// saved while the pitch holds).
    solved_pitch: f64,
    /// The hull's axes at the last pitch flown (`frame.inverse` all 0 before).
    frame: Frame,
    /// Seconds flown (the clock of the pump's history).
    clock: f64,
    /// The pump's recent motion, for the ballast delay.
    pump_history: PumpHistory,
}

/// Knots kept of the pump's motion: a swing makes two or three, so this
/// covers several swings; a delay reaching past the oldest knot sees the
/// volume the oldest knot had.
const PUMP_KNOTS: usize = 16;

/// The pumped volume's recent course: the (time, volume) knots where its rate
/// changed, in a ring, and the rate since the newest. Between knots the
/// volume moves linearly, so the volume at any time the ring covers is exact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PumpHistory {
    knots: [(f64, f64); PUMP_KNOTS],
    /// Knots held (at most `PUMP_KNOTS`) and the slot the next one goes to.
    count: usize,
    next: usize,
    /// cc/s since the newest knot.
    rate: f64,
}

impl PumpHistory {
    /// The pump moves at `rate` from `time`, where the volume is `volume`.
    fn record(&mut self, time: f64, volume: f64, rate: f64) {
        // A sub-step's rate is its step over its length: equal rates may
        // differ in the last bits between cycles of different periods.
        if self.count > 0 && (rate - self.rate).abs() <= 1e-9 * rate.abs().max(1.0) {
            return;
        }
        self.knots[self.next] = (time, volume);
        self.next = (self.next + 1) % PUMP_KNOTS;
        self.count = (self.count + 1).min(PUMP_KNOTS);
        self.rate = rate;
    }

    /// The i-th knot from the newest (0 is the newest).
    fn back(&self, i: usize) -> (f64, f64) {
        self.knots[(self.next + PUMP_KNOTS - 1 - i) % PUMP_KNOTS]
    }

    /// The volume at `time` (no later than the present), `now` the present
    /// volume.
    fn volume_at(&self, time: f64, now: f64) -> f64 {
        if self.count == 0 {
            return now;
        }
        let newest = self.back(0);
        if time >= newest.0 {
            return newest.1 + self.rate * (time - newest.0);
        }
        let mut later = newest;
        for i in 1..self.count {
            let knot = self.back(i);
            if time >= knot.0 {
                let span = later.0 - knot.0;
                return if span > 0.0 {
                    knot.1 + (later.1 - knot.1) * (time - knot.0) / span
                } else {
                    later.1
                };
            }
            later = knot;
        }
        later.1
    }
}

/// What a sub-step's forces need that does not change within it.
#[derive(Clone, Copy, Debug)]
struct Forces {
    /// Net buoyancy (N, up).
    buoyancy: f64,
    cos: f64,
    sin: f64,
    /// ½ ρ S.
    half_rho_area: f64,
    cd0: f64,
    cd1: f64,
    lift_slope: f64,
    /// The inverse of the mass matrix with added mass (earth axes).
    inverse: [f64; 4],
}

/// The hull's axes at a pitch: its sine and cosine and the inverse mass
/// matrix, kept by the vehicle while the pitch holds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Frame {
    pitch: f64,
    sin: f64,
    cos: f64,
    inverse: [f64; 4],
}

impl Frame {
    fn new(flight: &FlightParams, pitch: f64) -> Frame {
        let (sin, cos) = pitch.sin_cos();
        // Added mass is diagonal in the hull's axes; in earth axes its inverse
        // (with the glider's own mass) is this (gliderflight's mass matrix).
        let mass = flight.mass.max(1e-3);
        let along = flight.added_mass_along * mass;
        let across = flight.added_mass_across * mass;
        let denominator = mass * mass + (along + across) * mass + along * across;
        let (c2, cs) = (cos * cos, cos * sin);
        let m11 = ((across - along) * c2 + along + mass) / denominator;
        let m12 = (across - along) * cs / denominator;
        let m22 = (-(across - along) * c2 + across + mass) / denominator;
        Frame {
            pitch,
            sin,
            cos,
            inverse: [m11, m12, m12, m22],
        }
    }
}

impl Forces {
    fn new(flight: &FlightParams, buoyancy: f64, frame: &Frame) -> Forces {
        Forces {
            buoyancy,
            cos: frame.cos,
            sin: frame.sin,
            half_rho_area: 0.5 * flight.water_density * flight.wing_area,
            cd0: flight.drag_cd0,
            cd1: flight.drag_cd1,
            lift_slope: flight.lift_slope,
            inverse: frame.inverse,
        }
    }

    /// Acceleration (horizontal, up) at velocity (`u` horizontal, `w` up).
    fn acceleration(&self, u: f64, w: f64) -> (f64, f64) {
        let speed = (u * u + w * w).sqrt();
        // The angle of attack: the velocity in the hull's axes.
        let along = u * self.cos + w * self.sin;
        let across = w * self.cos - u * self.sin;
        let alpha = if along > 0.0 && across.abs() < SMALL_ANGLE * along {
            // Flying forward at a small angle (every steady glide): a short
            // series instead of `atan2` (error under 2e-8 rad), a third of
            // the model's time.
            let ratio = across / along;
            let square = ratio * ratio;
            ratio * (1.0 - square * (1.0 / 3.0 - square * (1.0 / 5.0)))
        } else if speed > 0.0 {
            across.atan2(along)
        } else {
            0.0
        };
        let lift = self.lift_slope * alpha;
        let drag = self.cd0 + self.cd1 * alpha * alpha;
        // Drag along −velocity, lift across it: q·C·(velocity / speed).
        let q = self.half_rho_area * speed;
        let fx = q * (-u * drag + w * lift);
        let fy = q * (-u * lift - w * drag) + self.buoyancy;
        let [m11, m12, m21, m22] = self.inverse;
        (m11 * fx + m12 * fy, m21 * fx + m22 * fy)
    }
}

/// Below this acceleration (m/s²) a sub-step is steady flight and one
/// evaluation (Euler) stands for two (Heun): the speed then changes
/// by under 0.1 mm/s in a 0.6 s step, and the two differ by a fraction of that.
const STEADY_ACCELERATION: f64 = 1e-4;

/// Largest |tan α| of the series for the angle of attack ([`Forces::acceleration`]).
const SMALL_ANGLE: f64 = 0.1;

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

    /// Flies `duration` seconds toward the commanded buoyancy (cc, > 0 up)
    /// and pitch (rad, or with [`PitchControl::Battpos`] the battery position
    /// in inches) in water `water_depth` deep, plus `extra_watts` drawn by
    /// the science computer and sensors.
    #[allow(clippy::too_many_arguments)]
    pub fn fly(
        &mut self,
        duration: f64,
        buoyancy: f64,
        pitch: f64,
        control: PitchControl,
        water_depth: f64,
        flight: &FlightParams,
        energy: &EnergyParams,
        extra_watts: f64,
    ) {
        let target_ballast = buoyancy.clamp(-flight.pump_max, flight.pump_max);
        let volts = self.battery_volts(energy).max(1e-3);
        let joules_before = self.energy_joules;
        // Equal sub-steps no longer than `step` (no sliver at the end of a
        // cycle that is not a multiple of it).
        let steps = (duration / flight.step).ceil().max(1.0);
        let dt = duration / steps;
        for _ in 0..steps as u64 {
            self.substep(
                dt,
                target_ballast,
                pitch,
                control,
                water_depth,
                flight,
                energy,
            );
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
        if self.pitch != self.solved_pitch || self.angle_of_attack == 0.0 {
            self.angle_of_attack = flight.steady_angle_of_attack(self.pitch);
            self.solved_pitch = self.pitch;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn substep(
        &mut self,
        dt: f64,
        target_ballast: f64,
        command: f64,
        control: PitchControl,
        water_depth: f64,
        flight: &FlightParams,
        energy: &EnergyParams,
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
        self.pump_history
            .record(self.clock, self.ballast, pump_step / dt.max(1e-9));
        self.ballast += pump_step;
        self.clock += dt;
        if self.ballast != 0.0 {
            let sign = if self.ballast > 0.0 { 1 } else { -1 };
            if self.ballast_sign != 0 && sign != self.ballast_sign {
                self.inflections += 1;
            }
            self.ballast_sign = sign;
        }

        // Pitch: the battery servoes (and costs energy), or stays put and the
        // pumped volume tips the glider, which turns with a lag.
        let pitch_joules = match control {
            PitchControl::Servo => {
                let step =
                    (command - self.pitch).clamp(-flight.pitch_rate * dt, flight.pitch_rate * dt);
                self.pitch += step;
                self.pitch_velocity = 0.0;
                step.abs() * energy.pitch_j_per_rad
            }
            PitchControl::Battpos => {
                let acting = self.acting_volume(flight.ballast_delay);
                let target = flight.battpos_pitch(acting, command);
                (self.pitch, self.pitch_velocity) = swing_pitch(
                    (self.pitch, self.pitch_velocity),
                    target,
                    dt,
                    flight.pitch_period,
                    flight.pitch_damping,
                );
                0.0
            }
        };

        // The pumped volume acts `ballast_delay` after the pump moves it.
        let acting = self.acting_volume(flight.ballast_delay);
        self.glide(dt, acting, water_depth, flight);

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

    /// The pumped volume (cc) that acts on the glider now, on its buoyancy and
    /// its battery relation: the volume `delay` seconds ago
    /// ([`FlightParams::ballast_delay`]).
    pub fn acting_volume(&self, delay: f64) -> f64 {
        if delay <= 0.0 {
            return self.ballast;
        }
        self.pump_history
            .volume_at(self.clock - delay, self.ballast)
    }

    /// Flies `dt` seconds at the present pitch with the buoyancy of `volume`
    /// (cc) pumped: the force balance alone (no pump, pitch or energy), in
    /// water `water_depth` deep. [`Vehicle::fly`]'s sub-steps use it; so does
    /// `gloc calibrate`, feeding it a log's pitch and pumped volume.
    pub fn glide(&mut self, dt: f64, volume: f64, water_depth: f64, flight: &FlightParams) {
        // The force balance, second-order Runge–Kutta (Heun; one evaluation
        // when the glider is in steady flight).
        if self.frame.pitch != self.pitch || self.frame.inverse[0] == 0.0 {
            self.frame = Frame::new(flight, self.pitch);
        }
        let forces = Forces::new(flight, flight.net_buoyancy(volume, self.depth), &self.frame);
        let (u, w) = (self.speed, -self.depth_rate);
        let (a1, b1) = forces.acceleration(u, w);
        let (du, dw) = if a1.abs() + b1.abs() < STEADY_ACCELERATION {
            (a1 * dt, b1 * dt)
        } else {
            let (a2, b2) = forces.acceleration(u + dt * a1, w + dt * b1);
            (0.5 * dt * (a1 + a2), 0.5 * dt * (b1 + b2))
        };
        let (u_next, w_next) = (u + du, w + dw);
        self.depth -= 0.5 * (w + w_next) * dt;
        self.speed = u_next;
        self.depth_rate = -w_next;
        if self.depth <= 0.0 {
            // Floating: the surface stops the glider.
            self.depth = 0.0;
            if self.depth_rate < 0.0 {
                self.depth_rate = 0.0;
                self.speed = 0.0;
            }
        }
        if self.depth >= water_depth {
            // On the bottom.
            self.depth = water_depth;
            if self.depth_rate > 0.0 {
                self.depth_rate = 0.0;
                self.speed = 0.0;
            }
        }
        self.distance += (0.5 * (u + self.speed) * dt).abs();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// comet's yo10.ma holds the battery at 0.405 in (`d_pitch_value`).
    const COMET_BATTPOS: f64 = 0.405;

    fn fly_for(vehicle: &mut Vehicle, seconds: f64, buoyancy: f64, water_depth: f64) {
        vehicle.fly(
            seconds,
            buoyancy,
            COMET_BATTPOS,
            PitchControl::Battpos,
            water_depth,
            &FlightParams::default(),
            &EnergyParams::default(),
            0.0,
        );
    }

    // Expected figures from an independent script (the formulas of the domain
    // notes §7, bisection for α, in Python; its numbers written here):
    // dive pitch atan(2080·(−230e−6) − 39·0.405·0.0254 + 0.4096) = −0.43936
    // rad; at 20 m steady α −0.05887 rad, u 0.28577 m/s, w 0.15546 m/s down;
    // climb pitch 0.45304 rad, u 0.23965, w 0.13396 up. (comet's own dead
    // reckoning: 0.291 m/s on dives, 0.246 on climbs; dive 0.157, climb
    // 0.128 m/s down and up.)
    #[test]
    fn the_steady_model_matches_a_hand_check() {
        let flight = FlightParams::default();
        let dive = flight.battpos_pitch(-230.0, COMET_BATTPOS);
        assert!((dive + 0.43936).abs() < 1e-5, "{dive}");
        assert!((flight.steady_angle_of_attack(dive) + 0.05887).abs() < 1e-5);
        let (u, w) = flight.steady_glide(-230.0, dive, 20.0);
        assert!(
            (u - 0.28577).abs() < 1e-5 && (w - 0.15546).abs() < 1e-5,
            "{u} {w}"
        );
        let climb = flight.battpos_pitch(230.0, COMET_BATTPOS);
        assert!((climb - 0.45304).abs() < 1e-5, "{climb}");
        let (u, w) = flight.steady_glide(230.0, climb, 20.0);
        assert!(
            (u - 0.23965).abs() < 1e-5 && (w + 0.13396).abs() < 1e-5,
            "{u} {w}"
        );
        // Light and pointing down: no steady glide.
        assert_eq!(flight.steady_glide(230.0, dive, 20.0), (0.0, 0.0));
    }

    #[test]
    fn the_force_balance_settles_on_the_steady_glide() {
        let flight = FlightParams::default();
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 250.0, -260.0, 1000.0);
        assert_eq!(vehicle.ballast, -230.0);
        let (u, w) = flight.steady_glide(vehicle.ballast, vehicle.pitch, vehicle.depth);
        assert!((vehicle.pitch + 0.43936).abs() < 1e-4, "{}", vehicle.pitch);
        // Within 0.3%: the hull compresses as it sinks, so the steady glide
        // it chases speeds up a little (5e-6 of the volume per metre).
        assert!(
            (vehicle.depth_rate - w).abs() < 5e-4,
            "{} {w}",
            vehicle.depth_rate
        );
        assert!((vehicle.speed - u).abs() < 5e-4, "{} {u}", vehicle.speed);
        assert!((vehicle.angle_of_attack + 0.05887).abs() < 1e-3);
        assert!(vehicle.energy_joules > 250.0 * 1.39);
    }

    #[test]
    fn the_speed_relaxes_rather_than_jumps() {
        let mut vehicle = Vehicle {
            depth: 10.0,
            ballast: -230.0,
            pitch: -0.43936,
            ..Vehicle::default()
        };
        // From rest, a second later the glider is far from its 0.155 m/s.
        fly_for(&mut vehicle, 1.0, -230.0, 1000.0);
        assert!(
            vehicle.depth_rate > 0.0 && vehicle.depth_rate < 0.1,
            "{}",
            vehicle.depth_rate
        );
    }

    #[test]
    fn an_inflection_turns_the_glider_around() {
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 300.0, -260.0, 1000.0);
        let turn_at = vehicle.depth;
        let mut deepest = turn_at;
        let mut seconds = 0.0;
        while vehicle.depth_rate > -0.9 * 0.134 && seconds < 200.0 {
            fly_for(&mut vehicle, 0.5, 260.0, 1000.0);
            deepest = deepest.max(vehicle.depth);
            seconds += 0.5;
        }
        // The pump's 13 s swing and the hull's pitch set the turn: it carries
        // on down for a metre or so and climbs at 90% of its rate well within
        // a minute (comet: 1.6 m and 19 s, project/tests/calibrate.rs).
        let overshoot = deepest - turn_at;
        assert!((0.5..2.5).contains(&overshoot), "overshoot {overshoot}");
        assert!((10.0..40.0).contains(&seconds), "turn {seconds} s");
        assert_eq!(vehicle.inflections, 1);
    }

    /// How far a servoed turn carries on past the turn (m), from a steady
    /// leg at 100 m: pump and pitch (±0.4538 rad) reverse together.
    fn servoed_overshoot(from: f64) -> f64 {
        let (flight, energy) = (FlightParams::default(), EnergyParams::default());
        let pitch = 0.4538 * from.signum();
        let mut vehicle = Vehicle {
            depth: 100.0,
            ballast: from.clamp(-230.0, 230.0),
            pitch,
            ..Vehicle::default()
        };
        let fly = |vehicle: &mut Vehicle, seconds, buoyancy, pitch| {
            vehicle.fly(
                seconds,
                buoyancy,
                pitch,
                PitchControl::Servo,
                1000.0,
                &flight,
                &energy,
                0.0,
            )
        };
        fly(&mut vehicle, 300.0, from, pitch);
        let start = vehicle.depth;
        let mut furthest: f64 = 0.0;
        for _ in 0..400 {
            fly(&mut vehicle, 0.5, -from, -pitch);
            furthest = furthest.max((start - vehicle.depth) * from.signum());
        }
        furthest
    }

    #[test]
    fn a_servoed_turn_carries_on_until_the_pump_is_past_neutral() {
        // The glider is 71 cc heavy at 100 m (1024 kg/m³ × 71.547 L × (1 −
        // 5e−10 × 1.0e6 Pa) against 73.3 kg, by hand). At the bottom the pump
        // passes that after (230 + 71) / 34.6 = 8.7 s at up to 0.16 m/s:
        // between half that (0.70 m) and that plus 3 s of coasting (1.87 m).
        // At the top: (230 − 71) / 43.7 = 3.6 s at up to 0.13 m/s: 0.24–0.86 m.
        let bottom = servoed_overshoot(-260.0);
        assert!((0.70..1.87).contains(&bottom), "bottom {bottom}");
        let top = servoed_overshoot(260.0);
        assert!((0.24..0.86).contains(&top), "top {top}");
    }

    #[test]
    fn the_buoyancy_follows_the_pump_after_its_delay() {
        // Servoed pitch held still, so only the buoyancy tells the two apart:
        // with a 3 s delay the glider whose pump starts at t = 0 flies exactly
        // as one whose pump never moves for 3 s, and differently after.
        let flight = FlightParams {
            ballast_delay: 3.0,
            ..FlightParams::default()
        };
        let energy = EnergyParams::default();
        let start = Vehicle {
            depth: 20.0,
            ballast: -230.0,
            pitch: -0.4538,
            ..Vehicle::default()
        };
        let fly = |vehicle: &mut Vehicle, seconds: f64, buoyancy: f64| {
            vehicle.fly(
                seconds,
                buoyancy,
                -0.4538,
                PitchControl::Servo,
                1000.0,
                &flight,
                &energy,
                0.0,
            )
        };
        let (mut turning, mut holding) = (start, start);
        fly(&mut turning, 60.0, -230.0);
        fly(&mut holding, 60.0, -230.0);
        fly(&mut turning, 3.0, 230.0);
        fly(&mut holding, 3.0, -230.0);
        assert_eq!(turning.depth, holding.depth);
        assert!((turning.acting_volume(3.0) + 230.0).abs() < 1e-9);
        // The pump ran 3 s at 34.6 cc/s; its volume 1 s ago was 2 s in.
        assert!((turning.ballast - (-230.0 + 3.0 * 34.6)).abs() < 1e-9);
        assert!((turning.acting_volume(1.0) - (-230.0 + 2.0 * 34.6)).abs() < 1e-9);
        fly(&mut turning, 3.0, 230.0);
        fly(&mut holding, 3.0, -230.0);
        assert!(
            turning.depth < holding.depth,
            "{} {}",
            turning.depth,
            holding.depth
        );
    }

    #[test]
    fn a_damped_swing_overshoots_as_a_pendulum_does() {
        // A step of 1 rad: the peak overshoot of a second-order system is
        // exp(−ζπ / √(1 − ζ²)), 0.2054 at ζ = 0.45.
        let mut state = (0.0, 0.0);
        let mut peak: f64 = 0.0;
        for _ in 0..2000 {
            state = swing_pitch(state, 1.0, 0.05, 32.8, 0.45);
            peak = peak.max(state.0);
        }
        assert!((peak - 1.2054).abs() < 0.005, "{peak}");
        assert!((state.0 - 1.0).abs() < 0.02);
    }

    #[test]
    fn surface_and_bottom_clip() {
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 60.0, 260.0, 1000.0);
        assert_eq!(vehicle.depth, 0.0);
        assert_eq!(vehicle.speed, 0.0);
        let mut vehicle = Vehicle::default();
        fly_for(&mut vehicle, 2000.0, -260.0, 40.0);
        assert_eq!(vehicle.depth, 40.0);
        assert_eq!(vehicle.depth_rate, 0.0);
    }

    #[test]
    fn a_servoed_pitch_slews_at_the_pitch_rate() {
        let mut vehicle = Vehicle::default();
        vehicle.fly(
            4.0,
            -260.0,
            -0.4538,
            PitchControl::Servo,
            100.0,
            &FlightParams::default(),
            &EnergyParams::default(),
            0.0,
        );
        // 0.05 rad/s for 4 s.
        assert!((vehicle.pitch + 0.2).abs() < 1e-9, "{}", vehicle.pitch);
        assert!(vehicle.energy_use.pitch > 0.0);
    }
}
