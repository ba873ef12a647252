//! Drawing for wireflight: mesh files in, scenes built, rasterized and written out.
//!
//! Data flows one way: [`mesh_files`] loads a model for the geometry crate's pipeline; [`scene`]
//! composes what a frame shows (the aircraft, a world, flights, labels) as a
//! [`LineScene`](wireflight_geometry::lines::LineScene); [`render`] draws it (CPU Bresenham,
//! SVG, GIF, and wgpu with the `gpu` feature); [`output`] writes pictures and frame sets
//! atomically; [`plots`] draws the workbench's plots. [`flythrough`] is the fly-through
//! window's state without a window (its flight, cameras, script, comparison), so the
//! offscreen tests and the window share it.

#![warn(missing_docs)]

mod figures;
pub mod flythrough;
pub mod mesh_files;
pub mod output;
pub mod plots;
pub mod progress;
pub mod render;
pub mod report;
pub mod scene;
