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
/// The rotation of an Euler convention's first angle: its axis, path and gimbal ring.
pub const EULER_FIRST: Rgba = [255, 110, 90, 255];
/// The rotation of the second angle.
pub const EULER_SECOND: Rgba = [255, 215, 70, 255];
/// The rotation of the third angle.
pub const EULER_THIRD: Rgba = [90, 170, 255, 255];
/// [`EULER_FIRST`], dimmed (the other path of a comparison).
pub const EULER_FIRST_DIM: Rgba = [120, 60, 55, 255];
/// [`EULER_THIRD`], dimmed.
pub const EULER_THIRD_DIM: Rgba = [45, 80, 120, 255];
/// The aircraft before a rotation (Euler pictures).
pub const GHOST: Rgba = [40, 100, 60, 255];
/// World X axis at the origin (Euler pictures).
pub const WORLD_X: Rgba = [150, 60, 60, 255];
/// World Y axis.
pub const WORLD_Y: Rgba = [60, 140, 70, 255];
/// World Z axis.
pub const WORLD_Z: Rgba = [70, 90, 170, 255];
/// Captions.
pub const CAPTION: Rgba = [225, 225, 225, 255];
/// Second caption lines.
pub const CAPTION_DIM: Rgba = [150, 155, 165, 255];
/// Lines between the panels of a sheet.
pub const SEPARATOR: Rgba = [60, 66, 84, 255];
/// Text over a frame: time stamps, labels.
pub const TEXT: Rgba = [220, 220, 220, 255];
/// The raw samples under a smoothed trail: faint.
pub const SAMPLE_DOTS: Rgba = [120, 100, 50, 255];
