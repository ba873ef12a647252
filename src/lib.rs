//! wireflight: a wireframe flight viewer and flight-model workbench.
//!
//! The work is done by the library crates, one layer each, and this crate puts them under
//! one roof (the paths below) with the command line and the window on top ([`app`]):
//!
//! * `wireflight-geometry`: [`euler`], [`camera`], [`clip`], [`pipeline`], [`mesh`] (with the
//!   loaders of `wireflight-draw`), [`lines`] — pure geometry.
//! * `wireflight-fsio`: [`fsio`] — bounded reads, atomic writes.
//! * `wireflight-flight`: [`flight`], [`numeric`] — the flight model and flight data.
//! * `wireflight-analysis`: [`analysis`] — model vs measurements (with `plots` from the
//!   drawing crate).
//! * `wireflight-draw`: [`scene`], [`render`], [`output`], [`progress`] — pictures.
//!
//! See `ARCHITECTURE.md`.

#![warn(missing_docs)]

pub mod app;

pub use wireflight_draw::{output, progress, render, scene};
pub use wireflight_flight::numeric;
pub use wireflight_fsio as fsio;
pub use wireflight_geometry::{camera, clip, euler, lines, pipeline};

/// The flight model and flight data (`wireflight-flight`).
pub mod flight {
    pub use wireflight_flight::*;
}

/// Wireframe models: the geometry crate's meshes and the drawing crate's file loaders.
pub mod mesh {
    pub use wireflight_draw::mesh_files::{gltf, load, load_named, obj, MeshError};
    pub use wireflight_geometry::mesh::*;
}

/// Model vs measurements (`wireflight-analysis`) and its plots (`wireflight-draw`).
pub mod analysis {
    pub use wireflight_analysis::*;
    pub use wireflight_draw::plots;
}
