//! wireflight: a wireframe flight viewer and flight-model workbench.
//!
//! The work is done by the library crates, one layer each, re-exported here under their own
//! names, with the command line and the window on top ([`app`]):
//!
//! * [`geometry`] (`wireflight-geometry`): Euler angles, camera, clipping, projection, meshes,
//!   2D line scenes — pure geometry.
//! * [`fsio`] (`wireflight-fsio`): bounded reads, atomic writes.
//! * [`data`] (`wireflight-data`): flight data and the files it is read from and written to.
//! * [`flight`] (`wireflight-flight`): the flight model, its effects, simulated flights.
//! * [`analysis`] (`wireflight-analysis`): model vs measurements.
//! * [`draw`] (`wireflight-draw`): the viewer — mesh files, scenes, rasterizers, outputs, the
//!   fly-through state.
//! * [`present`] (`wireflight-present`): the workbench's presentation — plots, the HTML
//!   report, comparison tracks, the window's compare and discover panels.
//!
//! See `ARCHITECTURE.md`.

#![warn(missing_docs)]
// The command modules only read, call, write and print; a function that outgrows the limit
// (clippy.toml) has more than one idea in it. CI denies this warning (`.ci/run`).
#![warn(clippy::too_many_lines)]

pub mod app;

pub use wireflight_analysis as analysis;
pub use wireflight_data as data;
pub use wireflight_draw as draw;
pub use wireflight_flight as flight;
pub use wireflight_fsio as fsio;
pub use wireflight_geometry as geometry;
pub use wireflight_present as present;
