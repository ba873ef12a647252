//! Model vs measurements: compare a model with flight data, find where it fails, diagnose
//! which physical effect is missing.

pub mod compare;
pub mod conditions;
pub mod diagnose;
pub mod identify;
pub mod plots;
pub(crate) mod profile;
pub mod report;
