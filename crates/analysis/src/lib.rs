//! Model vs measurements: compare a model with flight data, find where it fails, diagnose
//! which physical effect is missing, identify an aircraft's numbers from flights.
//!
//! Pure: flight data come in as [`wireflight_data::FlightData`], results leave as
//! values and as text or JSON ([`report`]); nothing here reads or writes a file.

#![warn(missing_docs)]

pub mod assess;
pub mod compare;
pub mod conditions;
pub mod diagnose;
pub mod discover;
pub mod error_floor;
pub mod filter_error;
mod free;
pub mod identify;
mod lm;
mod profile;
pub mod reference;
pub mod report;

pub use free::KeyError;
