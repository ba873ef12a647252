//! Drawing for wireflight: mesh files in, scenes built, rasterized and written out — the
//! viewer, which knows neither the flight model nor the analysis.
//!
//! Data flows one way: [`mesh_files`] loads a model for the geometry crate's pipeline; [`scene`]
//! composes what a frame shows (the aircraft, a world, flights, labels) as a
//! [`LineScene`](wireflight_geometry::lines::LineScene); [`render`] draws it (CPU Bresenham,
//! SVG, GIF, and wgpu with the `gpu` feature); [`output`] writes pictures and frame sets
//! atomically. [`flythrough`] is the fly-through window's state without a window (its flight,
//! cameras, script, Euler panel), so the offscreen tests and the window share it; a comparison
//! panel joins it through [`flythrough::session::ModelPanel`]. The workbench's plots, HTML
//! report and panels are the `wireflight-present` crate's, above this one.

#![warn(missing_docs)]

pub mod figures;
pub mod flythrough;
pub mod mesh_files;
pub mod output;
pub mod progress;
pub mod render;
pub mod scene;
