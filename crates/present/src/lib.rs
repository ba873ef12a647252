//! The workbench's presentation for wireflight: what the analysis's results look like to a
//! person, drawn with the viewer ([`wireflight_draw`]).
//!
//! * [`plots`]: the plots of a comparison as PNG files (plotters);
//! * [`report`]: the self-contained HTML report of `compare` and `diagnose`;
//! * [`track`]: the flight model's track from a comparison, which the viewer draws beside the
//!   measured flight (replays, comparison frames and their overlays);
//! * [`flythrough`]: the fly-through window's compare and discover panels, which run
//!   comparisons, a diagnosis and `discover` on worker threads and join the viewer's session
//!   as its model panel.
//!
//! The viewer below knows neither the flight model nor the analysis; this crate is where the
//! two meet. See `ARCHITECTURE.md`.

#![warn(missing_docs)]

pub mod flythrough;
pub mod plots;
pub mod report;
pub mod track;
