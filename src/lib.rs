//! wireflight: a wireframe flight viewer and flight-model workbench.
//!
//! Data flows one way: model ([`mesh`]) → transform ([`euler`], [`camera`]) → clip ([`clip`],
//! in homogeneous space) → project ([`pipeline`]) → draw ([`render`]). [`app`] is the
//! command line on top. See `ARCHITECTURE.md`.

#![warn(missing_docs)]

pub mod analysis;
pub mod app;
pub mod camera;
pub mod clip;
pub mod euler;
pub mod flight;
pub mod fsio;
pub mod mesh;
pub mod numeric;
pub mod pipeline;
pub mod render;
