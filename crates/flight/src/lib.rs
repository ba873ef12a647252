//! The flight side of wireflight: the flight model, its effects and integration, and
//! simulated flights. Flight data (the type, the files it is read from and written to) is the
//! crate below, [`wireflight_data`].
//!
//! Data flows one way: parameter sets and model files ([`params`], [`spec`]) → the model
//! ([`model`], [`aero`], [`effects`]) → flights ([`trim`], [`autopilot`], [`simulate`]) →
//! [`wireflight_data::FlightData`], which the analysis crate compares with the model.
//! [`numeric`] holds the small linear algebra and statistics they share.
//!
//! Frames (see `docs/conventions.md`): world **NED** (north, east,
//! down; metres) with its origin at a geodetic point; body **FRD** (forward, right, down);
//! attitude as aerospace z-y-x angles (ψ heading, θ nose-up, φ right-wing-down),
//! R_body→NED = Rz(ψ)·Ry(θ)·Rx(φ). The viewer's Z-up frames relate to these through
//! [`wireflight_geometry::euler::EulerZyx::from_aerospace`] and [`wireflight_geometry::euler::viewer_from_ned`].

#![warn(missing_docs)]

pub mod aero;
pub mod autopilot;
pub mod effects;
pub mod expr;
pub mod linear;
pub mod model;
pub mod numeric;
pub mod params;
pub mod sensing;
pub mod sensor_errors;
pub mod simulate;
pub mod spec;
pub mod trim;
pub mod turbulence;
