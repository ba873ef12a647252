//! The viewer's colours, in one place: every scene builder (stills, replays, comparison
//! frames and the window) takes its colours from here, so the same thing looks the same
//! everywhere.

use crate::render::Rgba;

/// Background: night sky.
pub const BACKGROUND: Rgba = [8, 12, 24, 255];
/// The aircraft (flown, replayed or measured): phosphor green.
pub const AIRCRAFT: Rgba = [80, 255, 120, 255];
/// The ground grid.
pub const GRID: Rgba = [40, 90, 140, 255];
/// The flown or measured trail.
pub const TRAIL: Rgba = [255, 200, 60, 255];
/// The flight model's aircraft beside the measured one (comparisons).
pub const MODEL_AIRCRAFT: Rgba = [255, 90, 200, 255];
/// The flight model's trail.
pub const MODEL_TRAIL: Rgba = [170, 60, 140, 255];
/// The error-over-time strip of a comparison frame.
pub const ERROR_STRIP: Rgba = [220, 220, 220, 255];
/// Runway markings.
pub const RUNWAY: Rgba = [235, 235, 235, 255];
/// Masts, tower, hangars.
pub const STRUCTURE: Rgba = [255, 150, 60, 255];
/// Hills.
pub const HILL: Rgba = [170, 120, 255, 255];
/// The horizon ring.
pub const HORIZON: Rgba = [110, 200, 255, 255];
/// Text over a frame: time stamps, labels.
pub const TEXT: Rgba = [220, 220, 220, 255];
/// The raw samples under a smoothed trail: faint.
pub const SAMPLE_DOTS: Rgba = [120, 100, 50, 255];
