//! Small commands that only print what wireflight knows: `keys` (the aircraft's numbers) and
//! `effects` (the catalogue of effects).

pub mod effects;
pub mod keys;
