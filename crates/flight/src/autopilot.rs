//! Manoeuvres and the digital autopilot that flies them.
//!
//! A manoeuvre is a schedule of targets (bank, pitch, airspeed) and/or open-loop inputs
//! (doublets, throttle steps) as functions of time. The autopilot turns targets into surface
//! commands with simple successive-loop laws (Beard & McLain ch. 6, reduced):
//!
//! * roll: δa = k_φ (φ_c − φ) − k_p p
//! * pitch: δe = δe_trim − k_θ (θ_c − θ) + k_q q − k_iθ ∫(θ_c − θ)   (δe < 0 pitches up)
//! * airspeed: δt = δt_trim + k_V (V_c − Va) + k_iV ∫(V_c − Va), clamped to 0..1
//! * turn coordination: δr = δr_trim − k_β β
//!
//! It runs at the data's sample rate and its commands are held until the next sample, so the
//! commands recorded in the data are exactly what the aircraft received. Gains were chosen
//! from the Aerosonde's roll (ṗ ≈ 131 δa − 23 p) and pitch (q̇ ≈ −36 δe − 5 q − 100 α)
//! dynamics at 25 m/s for well-damped loops of a few rad/s.

use std::fmt;
use std::str::FromStr;

use super::model::AirData;
use wireflight_data::Controls;
use wireflight_geometry::euler::EulerZyx;

/// Flight manoeuvres `simulate` can fly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Manoeuvre {
    /// Straight and level, autopilot holding wings level, trim pitch and airspeed.
    Level,
    /// 20° bank, pitch 4° above trim: a climbing turn.
    ClimbingTurn,
    /// Open loop from trim: elevator, aileron and rudder doublets in turn, every 20 s.
    Doublets,
    /// Open loop: elevator doublets only.
    ElevatorDoublet,
    /// Open loop: aileron doublets only.
    AileronDoublet,
    /// Open loop: rudder doublets only.
    RudderDoublet,
    /// Two opposite 25°-bank circles, repeated.
    FigureEight,
    /// A test flight: turns both ways and a climb under the autopilot, with doublets on every
    /// surface and throttle steps superimposed.
    FlightTest,
    /// Point mass: launched at 60° elevation, then gravity and whatever effects.
    Ballistic,
}

/// All manoeuvres with their command-line names.
pub const MANOEUVRES: [(&str, Manoeuvre); 9] = [
    ("level", Manoeuvre::Level),
    ("climbing-turn", Manoeuvre::ClimbingTurn),
    ("doublets", Manoeuvre::Doublets),
    ("elevator-doublet", Manoeuvre::ElevatorDoublet),
    ("aileron-doublet", Manoeuvre::AileronDoublet),
    ("rudder-doublet", Manoeuvre::RudderDoublet),
    ("figure-eight", Manoeuvre::FigureEight),
    ("flight-test", Manoeuvre::FlightTest),
    ("ballistic", Manoeuvre::Ballistic),
];

/// A manoeuvre name not in [`MANOEUVRES`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown manoeuvre `{0}` (known: {known})", known = manoeuvre_names())]
pub struct UnknownManoeuvre(pub String);

/// The names of [`MANOEUVRES`], comma-separated.
fn manoeuvre_names() -> String {
    let names: Vec<&str> = MANOEUVRES.iter().map(|(n, _)| *n).collect();
    names.join(", ")
}

impl FromStr for Manoeuvre {
    type Err = UnknownManoeuvre;
    fn from_str(s: &str) -> Result<Self, UnknownManoeuvre> {
        MANOEUVRES
            .iter()
            .find(|(n, _)| *n == s)
            .map(|(_, m)| *m)
            .ok_or_else(|| UnknownManoeuvre(s.to_string()))
    }
}

impl fmt::Display for Manoeuvre {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = MANOEUVRES.iter().find(|(_, m)| m == self).map(|(n, _)| *n);
        f.write_str(name.unwrap_or("?"))
    }
}

impl Manoeuvre {
    /// Whether this manoeuvre is for a point mass (only `ballistic`).
    pub fn is_point_mass(self) -> bool {
        self == Manoeuvre::Ballistic
    }
}

/// A doublet: +amplitude for `width` seconds from `start`, then −amplitude for `width`.
fn doublet(t: f64, start: f64, width: f64, amplitude: f64) -> f64 {
    if t >= start && t < start + width {
        amplitude
    } else if t >= start + width && t < start + 2.0 * width {
        -amplitude
    } else {
        0.0
    }
}

/// Targets of the closed-loop part at time t: (bank φ_c, pitch offset above trim) in rad, or
/// None for open loop.
fn targets(m: Manoeuvre, t: f64) -> Option<(f64, f64)> {
    let deg = f64::to_radians;
    match m {
        Manoeuvre::Level => Some((0.0, 0.0)),
        Manoeuvre::ClimbingTurn => Some((deg(20.0) * (t / 3.0).min(1.0), deg(4.0))),
        Manoeuvre::FigureEight => {
            // A 25° bank turn at 25 m/s takes about 34 s per circle.
            let period = 68.0;
            let phase = t.rem_euclid(period);
            let bank = if phase < period / 2.0 { 25.0 } else { -25.0 };
            Some((deg(bank), deg(1.0)))
        }
        Manoeuvre::FlightTest => {
            // 80 s cycle: level, right turn, level, left turn, climb.
            let phase = t.rem_euclid(80.0);
            let (bank, pitch) = match phase {
                p if p < 8.0 => (0.0, 0.0),
                p if p < 28.0 => (25.0, 1.0),
                p if p < 36.0 => (0.0, 0.0),
                p if p < 56.0 => (-25.0, 1.0),
                p if p < 70.0 => (0.0, 5.0),
                _ => (0.0, -2.0),
            };
            Some((deg(bank), deg(pitch)))
        }
        _ => None,
    }
}

/// Open-loop excitation at time t: (δe, δa, δr, δt) increments.
fn excitation(m: Manoeuvre, t: f64) -> [f64; 4] {
    let deg = f64::to_radians;
    let cycle = |period: f64| t.rem_euclid(period);
    match m {
        Manoeuvre::Doublets => [
            doublet(cycle(20.0), 2.0, 0.5, deg(3.0)),
            doublet(cycle(20.0), 8.0, 0.5, deg(4.0)),
            doublet(cycle(20.0), 14.0, 0.5, deg(4.0)),
            0.0,
        ],
        Manoeuvre::ElevatorDoublet => [doublet(cycle(10.0), 2.0, 0.5, deg(3.0)), 0.0, 0.0, 0.0],
        Manoeuvre::AileronDoublet => [0.0, doublet(cycle(10.0), 2.0, 0.5, deg(4.0)), 0.0, 0.0],
        Manoeuvre::RudderDoublet => [0.0, 0.0, doublet(cycle(10.0), 2.0, 0.5, deg(4.0)), 0.0],
        Manoeuvre::FlightTest => [
            doublet(cycle(13.0), 3.0, 0.4, deg(3.0)),
            doublet(cycle(17.0), 6.0, 0.4, deg(4.0)),
            doublet(cycle(19.0), 9.0, 0.5, deg(4.0)),
            // Throttle steps of ±0.15 for 6 s every 25 s.
            if cycle(25.0) < 6.0 {
                0.15
            } else if cycle(25.0) < 12.0 {
                -0.15
            } else {
                0.0
            },
        ],
        _ => [0.0; 4],
    }
}

/// The autopilot's memory: trim point, integrators.
#[derive(Clone, Debug)]
pub struct Autopilot {
    manoeuvre: Manoeuvre,
    trim: Controls,
    trim_pitch: f64,
    airspeed: f64,
    pitch_integral: f64,
    speed_integral: f64,
}

const MAX_SURFACE: f64 = 0.4; // rad, ≈ 23°

impl Autopilot {
    /// An autopilot flying `manoeuvre` from a trim point (controls and pitch) at `airspeed`.
    pub fn new(manoeuvre: Manoeuvre, trim: Controls, trim_pitch: f64, airspeed: f64) -> Self {
        Self {
            manoeuvre,
            trim,
            trim_pitch,
            airspeed,
            pitch_integral: 0.0,
            speed_integral: 0.0,
        }
    }

    /// Commands for time `t` given the aircraft's attitude (aerospace angles), body rates and
    /// air data; `dt` is the time since the previous call (for the integrators).
    pub fn commands(
        &mut self,
        t: f64,
        dt: f64,
        attitude: EulerZyx,
        rates: [f64; 3],
        air: &AirData,
    ) -> Controls {
        let [de_x, da_x, dr_x, dt_x] = excitation(self.manoeuvre, t);
        let mut c = self.trim;
        if let Some((bank, pitch_offset)) = targets(self.manoeuvre, t) {
            let [p, q, _r] = rates;
            let e_phi = bank - attitude.roll;
            let e_theta = self.trim_pitch + pitch_offset - attitude.pitch;
            let e_v = self.airspeed - air.airspeed;
            self.pitch_integral = (self.pitch_integral + e_theta * dt).clamp(-0.5, 0.5);
            self.speed_integral = (self.speed_integral + e_v * dt).clamp(-20.0, 20.0);
            c.aileron = self.trim.aileron + 0.5 * e_phi - 0.02 * p;
            c.elevator = self.trim.elevator - 1.0 * e_theta + 0.1 * q - 0.3 * self.pitch_integral;
            c.throttle = self.trim.throttle + 0.05 * e_v + 0.01 * self.speed_integral;
            c.rudder = self.trim.rudder - 0.5 * air.beta;
        }
        c.elevator = (c.elevator + de_x).clamp(-MAX_SURFACE, MAX_SURFACE);
        c.aileron = (c.aileron + da_x).clamp(-MAX_SURFACE, MAX_SURFACE);
        c.rudder = (c.rudder + dr_x).clamp(-MAX_SURFACE, MAX_SURFACE);
        c.throttle = (c.throttle + dt_x).clamp(0.0, 1.0);
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (name, m) in MANOEUVRES {
            assert_eq!(name.parse::<Manoeuvre>().unwrap(), m);
            assert_eq!(m.to_string(), name);
        }
        assert!("loop".parse::<Manoeuvre>().is_err());
    }

    #[test]
    fn doublet_shape() {
        assert_eq!(doublet(0.9, 1.0, 0.5, 2.0), 0.0);
        assert_eq!(doublet(1.2, 1.0, 0.5, 2.0), 2.0);
        assert_eq!(doublet(1.7, 1.0, 0.5, 2.0), -2.0);
        assert_eq!(doublet(2.0, 1.0, 0.5, 2.0), 0.0);
    }
}
