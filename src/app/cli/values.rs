//! The value parsers of the options (finite numbers, angles, sizes, planes, time steps) and the
//! small enums that name a choice (camera, projection, backend).

use clap::ValueEnum;

use crate::data::VehicleKind;
use crate::draw::render::Backend;
use crate::geometry::camera::CameraPreset;

pub(super) fn time_step(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v > 0.0 && v <= 1.0 {
        Ok(v)
    } else {
        Err(format!("time step {v} s is outside (0, 1]"))
    }
}

pub(super) fn parse_vehicle(s: &str) -> Result<VehicleKind, String> {
    s.parse()
        .map_err(|e: crate::data::UnknownVehicle| e.to_string())
}

/// Largest noise `simulate` adds, in the option's unit (m, deg, m/s, deg/s, m/s²): beyond it the
/// "measurements" are not of a flight (and would leave the readers' ranges).
const MAX_NOISE: f64 = 1e4;

pub(super) fn noise_sigma(s: &str) -> Result<f64, String> {
    let v = non_negative(s)?;
    if v <= MAX_NOISE {
        Ok(v)
    } else {
        Err(format!(
            "{v:.3e} is more noise than a flight's measurements carry (at most {MAX_NOISE:e})"
        ))
    }
}

pub(super) fn non_negative(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} must not be negative"))
    }
}

/// Camera presets (see [`CameraPreset`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CameraArg {
    /// Behind and above, following the heading.
    Chase,
    /// From ahead (world +X), looking back.
    Front,
    /// From above, +X up the picture.
    Top,
    /// From the right side (world −Y).
    Side,
    /// From the pilot's seat, fixed to the body.
    Cockpit,
}

impl From<CameraArg> for CameraPreset {
    fn from(c: CameraArg) -> Self {
        match c {
            CameraArg::Chase => CameraPreset::Chase,
            CameraArg::Front => CameraPreset::Front,
            CameraArg::Top => CameraPreset::Top,
            CameraArg::Side => CameraPreset::Side,
            CameraArg::Cockpit => CameraPreset::Cockpit,
        }
    }
}

/// Projection kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProjectionArg {
    /// Pinhole perspective.
    Perspective,
    /// Parallel projection framing the model.
    Ortho,
}

/// Rasterizer choice (see [`Backend`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BackendArg {
    /// GPU if any wgpu adapter exists, else CPU.
    Auto,
    /// wgpu only; fails without an adapter.
    Gpu,
    /// Bresenham on the CPU (bit-exact).
    Cpu,
}

impl From<BackendArg> for Backend {
    fn from(b: BackendArg) -> Self {
        match b {
            BackendArg::Auto => Backend::Auto,
            BackendArg::Gpu => Backend::Gpu,
            BackendArg::Cpu => Backend::Cpu,
        }
    }
}

/// A finite float (clap's f64 parser accepts "nan" and "inf").
pub fn finite_f64(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{s}` is not a finite number"))
    }
}

/// An angle in degrees: finite; beyond ±360° reduced to (−180°, 180°] (the same rotation —
/// `fmod` is exact), since the radians of 1e100° overflow the f32 that draws it.
pub(super) fn angle_deg(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v.abs() <= 360.0 {
        return Ok(v);
    }
    let w = v.rem_euclid(360.0);
    Ok(if w > 180.0 { w - 360.0 } else { w })
}

pub(super) fn fov_deg(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v > 0.0 && v < 180.0 {
        Ok(v)
    } else {
        Err(format!("field of view {v}° is outside (0°, 180°)"))
    }
}

pub(super) fn parse_pan(s: &str) -> Result<[f32; 2], String> {
    let (r, u) = s
        .split_once(',')
        .ok_or_else(|| format!("`{s}` is not RIGHT,UP (e.g. 1,0)"))?;
    let r = finite_f64(r.trim())?;
    let u = finite_f64(u.trim())?;
    if r.abs() > 100.0 || u.abs() > 100.0 {
        return Err(format!("pan `{s}` is more than 100 radii"));
    }
    Ok([r as f32, u as f32])
}

/// Largest accepted image side, pixels.
pub const MAX_SIDE: u32 = 16384;

/// Parse `WIDTHxHEIGHT` (e.g. `800x600`), each side in 1..=16384.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT (e.g. 800x600)"))?;
    let side = |t: &str, name: &str| -> Result<u32, String> {
        let v: u32 = t
            .trim()
            .parse()
            .map_err(|_| format!("{name} `{t}` is not a whole number"))?;
        if (1..=MAX_SIDE).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{name} {v} is outside 1..={MAX_SIDE}"))
        }
    };
    Ok((side(w, "width")?, side(h, "height")?))
}
