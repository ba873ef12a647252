//! wireflight: a wireframe flight viewer and flight-model workbench.
//!
//! Data flows one way: model ([`mesh`]) → transform ([`euler`], [`camera`]) → clip ([`clip`],
//! in homogeneous space) → project ([`pipeline`]) → compose ([`scene`]) → draw ([`render`])
//! → write ([`output`]). The flight side: [`flight`] models, data and simulation →
//! [`analysis`] (model vs measurements). [`app`] is the command line on top: each command a
//! thin file over these stages. See `ARCHITECTURE.md`.

#![warn(missing_docs)]

pub mod analysis;
pub mod app;
pub mod camera;
pub mod clip;
pub mod clip_io;
pub mod euler;
pub mod flight;
pub mod fsio;
pub mod mesh;
pub mod numeric;
pub mod output;
pub mod pipeline;
pub mod progress;
pub mod render;
pub mod scene;
