//! Writing flight-data CSV: [`write()`] a file, or [`to_csv_string`], always in the
//! wireflight dialect (see [`super`] for the format).
//!
//! Kept apart from reading: the writer has one fixed column layout and no error paths beyond
//! invalid data and I/O, so it reads best on its own.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use wireflight_fsio::FsError;

use super::{
    DataError, FlightData, ValidationError, DERIVED_RATES_BODY, DERIVED_VEL_BODY, DERIVED_VEL_NED,
};
use crate::{Channel, Controls};
use wireflight_geometry::euler::EulerZyx;

/// Flight data that cannot be written: invalid, empty, not readable back, or an I/O error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WriteError {
    /// Data that fails [`FlightData::validate`].
    #[error("{}: cannot write flight data: {error}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The invariant broken.
        error: ValidationError,
    },
    /// Data without samples.
    #[error("{}: cannot write flight data: no samples", path.display())]
    NoSamples {
        /// The file.
        path: PathBuf,
    },
    /// Text the reader would reject (a value beyond its ranges, `inf`).
    #[error("cannot write flight data that would not read back: {0}")]
    WouldNotReadBack(DataError),
    /// The file could not be written.
    #[error(transparent)]
    Io(#[from] FsError),
}

/// Writes `data` as wireflight CSV ([`to_csv_string`]) atomically.
///
/// # Errors
/// Data that fails [`FlightData::validate`] or has no samples (the file could not be read
/// back), and I/O errors.
pub fn write(path: &Path, data: &FlightData) -> Result<(), WriteError> {
    if let Err(error) = data.validate() {
        return Err(WriteError::Invalid {
            path: path.to_path_buf(),
            error,
        });
    }
    if data.is_empty() {
        return Err(WriteError::NoSamples {
            path: path.to_path_buf(),
        });
    }
    // Never write a file that the reader rejects (`inf` from huge noise, positions beyond the
    // reader's ranges): say so now rather than when the file is read.
    let text = to_csv_string(data);
    if let Err(e) = super::read::parse(&text, &path.display().to_string()) {
        return Err(WriteError::WouldNotReadBack(e));
    }
    Ok(wireflight_fsio::write_atomic(path, text.as_bytes())?)
}

/// The wireflight CSV text of `data`: metadata lines, the header, one row per sample. Writes
/// the channels that are present and not [derived](FlightData::derived), angles in degrees,
/// rates in deg/s, numbers in shortest round-trip form; a row that is not a sample of a
/// channel ([`FlightData::sampling`]) leaves the channel's cells empty. Expects valid data
/// ([`FlightData::validate`]); missing entries of a short channel are written as `NaN`.
pub fn to_csv_string(data: &FlightData) -> String {
    let mut s = String::new();
    let clean = |v: &str| v.replace(['\n', '\r'], " ");
    let m = &data.meta;
    let mut meta_line = |k: &str, v: String| {
        let _ = writeln!(s, "# {k}: {}", clean(&v));
    };
    if let Some(v) = m.vehicle {
        meta_line("vehicle", v.to_string());
    }
    if let Some(v) = &m.aircraft {
        meta_line("aircraft", v.clone());
    }
    for (k, v) in [
        ("latitude_deg", m.latitude_deg),
        ("longitude_deg", m.longitude_deg),
        ("altitude_m", m.altitude_m),
        ("mass_kg", m.mass_kg),
        ("reference_area_m2", m.reference_area_m2),
    ] {
        if let Some(v) = v {
            meta_line(k, v.to_string());
        }
    }
    if let Some(v) = &m.source {
        meta_line("source", v.clone());
    }
    for (k, v) in &m.other {
        let k = clean(k).replace(':', "_");
        if !k.trim().is_empty() {
            meta_line(k.trim(), v.clone());
        }
    }

    // Only channels read from data are written (derived ones are derived again on reading);
    // the channel names match `derived`, so a caller may mark any channel as derived.
    let keep = |name: &str| !data.is_derived(name);
    let att = data.attitude.as_deref().filter(|_| keep("attitude"));
    let vn = data.vel_ned.as_deref().filter(|_| keep(DERIVED_VEL_NED));
    let vb = data.vel_body.as_deref().filter(|_| keep(DERIVED_VEL_BODY));
    let rates = data
        .rates_body
        .as_deref()
        .filter(|_| keep(DERIVED_RATES_BODY));
    let air = data.airspeed.as_deref().filter(|_| keep("airspeed"));
    let acc = data.accel_body.as_deref().filter(|_| keep("accel_body"));
    let ctl = data.controls.as_deref().filter(|_| keep("controls"));

    let mut header = vec!["time_s", "north_m", "east_m", "down_m"];
    if att.is_some() {
        header.extend(["roll_deg", "pitch_deg", "yaw_deg"]);
    }
    if vn.is_some() {
        header.extend(["vn_mps", "ve_mps", "vd_mps"]);
    }
    if vb.is_some() {
        header.extend(["u_mps", "v_mps", "w_mps"]);
    }
    if rates.is_some() {
        header.extend(["p_dps", "q_dps", "r_dps"]);
    }
    if air.is_some() {
        header.push("airspeed_mps");
    }
    if acc.is_some() {
        header.extend(["ax_mps2", "ay_mps2", "az_mps2"]);
    }
    if ctl.is_some() {
        header.extend(["throttle", "elevator_deg", "aileron_deg", "rudder_deg"]);
    }
    s.push_str(&header.join(","));
    s.push('\n');

    let nan3 = DVec3::splat(f64::NAN);
    let sampled = |channel: Channel, i: usize| data.sampling.at(channel, i);
    let mut row: Vec<Option<f64>> = Vec::with_capacity(header.len());
    for (i, t) in data.time.iter().enumerate() {
        row.clear();
        // A row that is not a sample of a channel leaves its cells empty: the value there
        // was filled in between samples, not measured.
        let mut cells = |on: bool, values: &[f64]| {
            row.extend(values.iter().map(|&v| on.then_some(v)));
        };
        let p = data.pos_ned.get(i).copied().unwrap_or(nan3);
        cells(true, &[*t]);
        cells(sampled(Channel::Position, i), &[p.x, p.y, p.z]);
        if let Some(a) = att {
            let e = a
                .get(i)
                .copied()
                .unwrap_or(EulerZyx::new(f64::NAN, f64::NAN, f64::NAN));
            cells(
                sampled(Channel::Attitude, i),
                &[
                    e.roll.to_degrees(),
                    e.pitch.to_degrees(),
                    e.yaw.to_degrees(),
                ],
            );
        }
        if let Some(v) = vn {
            let v = v.get(i).copied().unwrap_or(nan3);
            cells(sampled(Channel::Velocity, i), &[v.x, v.y, v.z]);
        }
        if let Some(v) = vb {
            let v = v.get(i).copied().unwrap_or(nan3);
            cells(true, &[v.x, v.y, v.z]);
        }
        if let Some(r) = rates {
            let r = r.get(i).copied().unwrap_or(nan3);
            cells(
                sampled(Channel::Rates, i),
                &[r.x.to_degrees(), r.y.to_degrees(), r.z.to_degrees()],
            );
        }
        if let Some(a) = air {
            cells(
                sampled(Channel::Airspeed, i),
                &[a.get(i).copied().unwrap_or(f64::NAN)],
            );
        }
        if let Some(a) = acc {
            let a = a.get(i).copied().unwrap_or(nan3);
            cells(sampled(Channel::Accelerometer, i), &[a.x, a.y, a.z]);
        }
        if let Some(c) = ctl {
            let c = c.get(i).copied().unwrap_or(Controls {
                throttle: f64::NAN,
                elevator: f64::NAN,
                aileron: f64::NAN,
                rudder: f64::NAN,
            });
            cells(
                true,
                &[
                    c.throttle,
                    c.elevator.to_degrees(),
                    c.aileron.to_degrees(),
                    c.rudder.to_degrees(),
                ],
            );
        }
        for (j, v) in row.iter().enumerate() {
            if j > 0 {
                s.push(',');
            }
            if let Some(v) = v {
                let _ = write!(s, "{v}");
            }
        }
        s.push('\n');
    }
    s
}
