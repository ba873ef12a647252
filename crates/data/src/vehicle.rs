//! What flight data says of its vehicle: the model family ([`VehicleKind`]) and the control
//! commands ([`Controls`]). Plain data: the flight model gives them their meaning.

use std::fmt;
use std::str::FromStr;

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
