//! The flight side of wireflight: the flight model, its effects and integration, simulated
//! flights, and flight data read from files (CSV, column maps, PX4 ULog).
//!
//! Data flows one way: parameter sets and model files ([`params`], [`spec`]) → the model
//! ([`model`], [`aero`], [`effects`]) → flights ([`trim`], [`autopilot`], [`simulate`]) →
//! [`data`], which the analysis crate compares with the model. [`numeric`] holds the small
//! linear algebra and statistics they share.
//!
//! Frames (see `docs/conventions.md`): world **NED** (north, east,
//! down; metres) with its origin at a geodetic point; body **FRD** (forward, right, down);
//! attitude as aerospace z-y-x angles (ψ heading, θ nose-up, φ right-wing-down),
//! R_body→NED = Rz(ψ)·Ry(θ)·Rx(φ). The viewer's Z-up frames relate to these through
//! [`wireflight_geometry::euler::EulerZyx::from_aerospace`] and [`wireflight_geometry::euler::viewer_from_ned`].

#![warn(missing_docs)]

pub mod aero;
pub mod autopilot;
pub mod data;
pub mod derive;
pub mod effects;
pub mod expr;
pub mod linear;
pub mod model;
pub mod numeric;
pub mod params;
pub mod sensing;
pub mod simulate;
pub mod spec;
pub mod trim;
pub mod turbulence;

use std::fmt;
use std::str::FromStr;

/// Standard gravity g0, m/s².
pub const G0: f64 = 9.80665;

/// Model families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VehicleKind {
    /// Position and velocity only; baseline force: gravity.
    PointMass,
    /// 6-DOF rigid body with Beard & McLain aerodynamics.
    FixedWing,
}

impl VehicleKind {
    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            VehicleKind::PointMass => "point-mass",
            VehicleKind::FixedWing => "fixed-wing",
        }
    }
}

impl fmt::Display for VehicleKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A vehicle name that is neither `point-mass` nor `fixed-wing`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown vehicle `{0}` (expected point-mass or fixed-wing)")]
pub struct UnknownVehicle(pub String);

impl FromStr for VehicleKind {
    type Err = UnknownVehicle;
    fn from_str(s: &str) -> Result<Self, UnknownVehicle> {
        match s.trim() {
            "point-mass" => Ok(VehicleKind::PointMass),
            "fixed-wing" => Ok(VehicleKind::FixedWing),
            other => Err(UnknownVehicle(other.to_string())),
        }
    }
}

/// Control commands of a fixed-wing aircraft: throttle 0..1 and surface deflections in
/// radians (Beard & McLain signs). Held constant between samples (zero-order hold).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Controls {
    /// Throttle δt, 0..1.
    pub throttle: f64,
    /// Elevator δe, rad.
    pub elevator: f64,
    /// Aileron δa, rad.
    pub aileron: f64,
    /// Rudder δr, rad.
    pub rudder: f64,
}

impl Controls {
    /// (throttle, elevator, aileron, rudder).
    pub fn to_array(&self) -> [f64; 4] {
        [self.throttle, self.elevator, self.aileron, self.rudder]
    }

    /// From (throttle, elevator, aileron, rudder).
    pub fn from_array([throttle, elevator, aileron, rudder]: [f64; 4]) -> Self {
        Self {
            throttle,
            elevator,
            aileron,
            rudder,
        }
    }
}
