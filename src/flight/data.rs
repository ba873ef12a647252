//! Flight data: the CSV format of `shared/specs/flight-data.md`.
//!
//! # Reading
//! [`read`] / [`parse`] accept two dialects, told apart by the header:
//!
//! * **wireflight CSV** (the contract): `# key: value` metadata lines, then a header of column
//!   names carrying their units (`time_s`, `north_m`, `roll_deg` or `roll_rad`, `p_dps` or
//!   `p_radps`, …), then rows. Columns come in any order; unknown columns are accepted and
//!   ignored (their cells are not parsed and not retained). Angles are converted to radians.
//! * **JSBSim CSV output**: a `Time` column and property names such as
//!   `/fdm/jsbsim/attitude/phi-rad` (see [`JSBSIM_COLUMNS`] for the names understood). Feet
//!   become metres; the geodetic position (latitude, longitude, height above sea level) becomes
//!   local NED about the first sample on a flat earth of radius [`EARTH_RADIUS_M`]:
//!   north = (lat − lat0)·R, east = (lon − lon0)·R·cos lat0, down = −(h − h0), and the
//!   metadata's origin is set to that first sample.
//!
//! Every error is a [`DataError`] naming the file, the 1-based line (metadata lines count) and,
//! where one is involved, the column. No input makes the reader panic.
//!
//! Channels a file lacks are then derived ([`FlightData::derive_missing`], called by
//! [`parse`] and so by [`read`]): NED velocity from positions, body rates from attitude, body
//! velocity from NED velocity and attitude. [`FlightData::derived`] lists what was derived.
//!
//! # Differentiating noisy, unevenly sampled data
//! [`Differentiator`] fits a quadratic by least squares to the 2k + 1 samples around each
//! sample (Savitzky–Golay generalised to uneven time steps) and takes the fit's slope at that
//! sample. Near the ends the window keeps its 2k + 1 samples but becomes one-sided (it is
//! shifted to stay inside the data), the usual Savitzky–Golay end treatment. A centred window
//! has no lag (its phase is zero); its cost is a small attenuation of fast motion, and a
//! quadratic fit is exact for quadratic motion. The default half-width ([`Window::default`])
//! is [`DEFAULT_HALF_WIDTH_S`] = 0.2 s, turned into a sample count from the median time step
//! and clamped to [`MIN_HALF_SAMPLES`]..=[`MAX_HALF_SAMPLES`]: with uniform steps the
//! derivative's noise is √(3 / (k(k+1)(2k+1))) · σ/Δt against σ/(√2·Δt) for a central
//! difference (k = 4: 0.18 of it; k = 10: 0.04), while a sinusoid of angular frequency ω is
//! attenuated by about (ωh)²/10 for half-width h seconds (h = 0.2 s: 0.6 % at 0.2 Hz, 4 % at
//! 0.5 Hz, 16 % at 1 Hz) — body motion of aircraft and falling bodies is mostly below 1 Hz,
//! measurement noise is white. [`FlightData::derive_missing_with`] takes another [`Window`].
//!
//! # Writing
//! [`write()`] / [`to_csv_string`] write the wireflight dialect: metadata, then the channels
//! that are present and were not derived, angles in degrees, numbers in Rust's shortest
//! round-trip form (so reading back gives the same numbers; angles and rates to within one
//! rounding of the degree↔radian conversion).

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};
use std::fmt::{self, Write as _};
use std::path::Path;

use glam::DVec3;

use super::{Controls, VehicleKind};
use crate::euler::EulerZyx;

/// Metres per foot (exact).
pub const METRES_PER_FOOT: f64 = 0.3048;

/// Metres per second per knot (exact).
pub const MPS_PER_KNOT: f64 = 1852.0 / 3600.0;

/// Earth radius of the flat-earth conversion of JSBSim geodetic positions, m.
pub const EARTH_RADIUS_M: f64 = 6_371_000.0;

/// Default half-width of the differentiator's window, seconds (see the module docs).
pub const DEFAULT_HALF_WIDTH_S: f64 = 0.2;

/// Smallest half-width, in samples, that a [`Window::Seconds`] turns into (5-sample windows).
pub const MIN_HALF_SAMPLES: usize = 2;

/// Largest half-width, in samples, that a [`Window::Seconds`] turns into.
pub const MAX_HALF_SAMPLES: usize = 50;

/// Name recorded in [`FlightData::derived`] when the NED velocity was derived.
pub const DERIVED_VEL_NED: &str = "vel_ned";
/// Name recorded in [`FlightData::derived`] when the body velocity was derived.
pub const DERIVED_VEL_BODY: &str = "vel_body";
/// Name recorded in [`FlightData::derived`] when the body rates were derived.
pub const DERIVED_RATES_BODY: &str = "rates_body";

/// The JSBSim output column names understood, with the quantity each gives. Property names may
/// be written with or without the `/fdm/jsbsim/` prefix; where several give one quantity, the
/// earlier in this list wins. The last entries are captions of JSBSim's built-in output groups.
pub const JSBSIM_COLUMNS: &[(&str, &str)] = &[
    ("Time", "time, s"),
    ("/fdm/jsbsim/simulation/sim-time-sec", "time, s"),
    ("/fdm/jsbsim/position/lat-geod-rad", "latitude, rad"),
    ("/fdm/jsbsim/position/lat-geod-deg", "latitude, deg"),
    (
        "/fdm/jsbsim/position/lat-gc-rad",
        "latitude (geocentric), rad",
    ),
    (
        "/fdm/jsbsim/position/lat-gc-deg",
        "latitude (geocentric), deg",
    ),
    ("/fdm/jsbsim/position/long-gc-rad", "longitude, rad"),
    ("/fdm/jsbsim/position/long-gc-deg", "longitude, deg"),
    (
        "/fdm/jsbsim/position/h-sl-meters",
        "height above sea level, m",
    ),
    ("/fdm/jsbsim/position/h-sl-ft", "height above sea level, ft"),
    ("/fdm/jsbsim/attitude/phi-rad", "roll, rad"),
    ("/fdm/jsbsim/attitude/phi-deg", "roll, deg"),
    ("/fdm/jsbsim/attitude/roll-rad", "roll, rad"),
    ("/fdm/jsbsim/attitude/theta-rad", "pitch, rad"),
    ("/fdm/jsbsim/attitude/theta-deg", "pitch, deg"),
    ("/fdm/jsbsim/attitude/pitch-rad", "pitch, rad"),
    ("/fdm/jsbsim/attitude/psi-rad", "yaw, rad"),
    ("/fdm/jsbsim/attitude/psi-deg", "yaw, deg"),
    ("/fdm/jsbsim/attitude/heading-true-rad", "yaw, rad"),
    ("/fdm/jsbsim/velocities/p-rad_sec", "roll rate p, rad/s"),
    ("/fdm/jsbsim/velocities/q-rad_sec", "pitch rate q, rad/s"),
    ("/fdm/jsbsim/velocities/r-rad_sec", "yaw rate r, rad/s"),
    ("/fdm/jsbsim/velocities/u-fps", "body u, ft/s"),
    ("/fdm/jsbsim/velocities/v-fps", "body v, ft/s"),
    ("/fdm/jsbsim/velocities/w-fps", "body w, ft/s"),
    ("/fdm/jsbsim/velocities/v-north-fps", "north velocity, ft/s"),
    ("/fdm/jsbsim/velocities/v-east-fps", "east velocity, ft/s"),
    ("/fdm/jsbsim/velocities/v-down-fps", "down velocity, ft/s"),
    ("/fdm/jsbsim/velocities/vt-fps", "true airspeed, ft/s"),
    ("/fdm/jsbsim/velocities/vtrue-kts", "true airspeed, kt"),
    ("Latitude Geodetic (deg)", "latitude, deg"),
    ("Latitude (deg)", "latitude (geocentric), deg"),
    ("Longitude (deg)", "longitude, deg"),
    ("Altitude ASL (ft)", "height above sea level, ft"),
    ("Phi (deg)", "roll, deg"),
    ("Theta (deg)", "pitch, deg"),
    ("Psi (deg)", "yaw, deg"),
    ("P (deg/s)", "roll rate p, deg/s"),
    ("Q (deg/s)", "pitch rate q, deg/s"),
    ("R (deg/s)", "yaw rate r, deg/s"),
    ("V_{North} (ft/s)", "north velocity, ft/s"),
    ("V_{East} (ft/s)", "east velocity, ft/s"),
    ("V_{Down} (ft/s)", "down velocity, ft/s"),
];

// ---------------------------------------------------------------------------------------------
// Types

/// The `# key: value` lines before the header.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metadata {
    /// `vehicle`: which model family the data is for.
    pub vehicle: Option<VehicleKind>,
    /// `aircraft`: parameter set for the vehicle, e.g. `aerosonde`.
    pub aircraft: Option<String>,
    /// `latitude_deg`: geodetic latitude of the NED origin, degrees.
    pub latitude_deg: Option<f64>,
    /// `longitude_deg`: longitude of the NED origin, degrees.
    pub longitude_deg: Option<f64>,
    /// `altitude_m`: altitude of the NED origin, m.
    pub altitude_m: Option<f64>,
    /// `mass_kg`: mass of a point-mass body, kg.
    pub mass_kg: Option<f64>,
    /// `reference_area_m2`: reference area of a point-mass body, m².
    pub reference_area_m2: Option<f64>,
    /// `source`: free text, where the data came from.
    pub source: Option<String>,
    /// Any other `key: value` pairs, in file order.
    pub other: Vec<(String, String)>,
}

/// A measured or simulated flight: samples at strictly increasing times. Every channel that is
/// present has one entry per sample.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlightData {
    /// Metadata.
    pub meta: Metadata,
    /// Sample times, s, strictly increasing (need not be uniform).
    pub time: Vec<f64>,
    /// Positions in the local NED frame, m.
    pub pos_ned: Vec<DVec3>,
    /// Aerospace z-y-x angles (yaw ψ, pitch θ, roll φ) of the FRD body in NED, radians.
    pub attitude: Option<Vec<EulerZyx>>,
    /// NED velocity, m/s.
    pub vel_ned: Option<Vec<DVec3>>,
    /// Body (FRD) velocity (u, v, w), m/s.
    pub vel_body: Option<Vec<DVec3>>,
    /// Body rates (p, q, r), rad/s.
    pub rates_body: Option<Vec<DVec3>>,
    /// Airspeed, m/s.
    pub airspeed: Option<Vec<f64>>,
    /// Control commands: throttle 0..1, surfaces in radians; held from each sample to the next.
    pub controls: Option<Vec<Controls>>,
    /// Channels derived rather than read: [`DERIVED_VEL_NED`], [`DERIVED_VEL_BODY`],
    /// [`DERIVED_RATES_BODY`].
    pub derived: Vec<&'static str>,
}

/// Half-width of the [`Differentiator`]'s window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Window {
    /// About this many seconds each side, turned into samples from the median time step and
    /// clamped to [`MIN_HALF_SAMPLES`]..=[`MAX_HALF_SAMPLES`].
    Seconds(f64),
    /// Exactly this many samples each side (at least 1).
    Samples(usize),
}

impl Default for Window {
    /// `Seconds(DEFAULT_HALF_WIDTH_S)`.
    fn default() -> Self {
        Window::Seconds(DEFAULT_HALF_WIDTH_S)
    }
}

impl Window {
    /// The half-width in samples for these sample times.
    pub fn half_samples(self, time: &[f64]) -> usize {
        match self {
            Window::Samples(k) => k.max(1),
            Window::Seconds(h) => {
                let mut steps: Vec<f64> = time
                    .windows(2)
                    .map(|w| w[1] - w[0])
                    .filter(|d| d.is_finite() && *d > 0.0)
                    .collect();
                if steps.is_empty() || !(h.is_finite() && h > 0.0) {
                    return MIN_HALF_SAMPLES;
                }
                let mid = steps.len() / 2;
                let (_, median, _) = steps.select_nth_unstable_by(mid, f64::total_cmp);
                let k = (h / *median).round();
                if k.is_finite() {
                    (k as usize).clamp(MIN_HALF_SAMPLES, MAX_HALF_SAMPLES)
                } else {
                    MAX_HALF_SAMPLES
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Errors

/// A flight-data file that cannot be read: the file, the line, the column, and the problem.
///
/// Displays as `FILE: line N, column `NAME`: PROBLEM` (the line and column parts where known).
#[derive(Debug)]
pub struct DataError {
    /// The file (or the name given to [`parse`]).
    pub file: String,
    /// 1-based line number, counting metadata and blank lines; `None` when the file could not
    /// be read at all.
    pub line: Option<usize>,
    /// The column involved, as written in the header, if any.
    pub column: Option<String>,
    /// The problem.
    pub kind: DataErrorKind,
}

/// What is wrong, in a [`DataError`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {0}")]
    Unreadable(std::io::Error),
    /// The file is not UTF-8 text (the line is where the first bad byte is).
    #[error("not UTF-8 text")]
    NotUtf8,
    /// No header row: the file is empty, blank or metadata only.
    #[error("empty file: no header row")]
    Empty,
    /// A header but no data rows.
    #[error("header only: no data rows")]
    NoRows,
    /// A metadata value that cannot be used.
    #[error("metadata `{key}`: {reason}")]
    BadMetadata {
        /// The key.
        key: String,
        /// Why the value is rejected (quoting it).
        reason: String,
    },
    /// Two columns with the same name, or two giving the same quantity.
    #[error("duplicate column: it gives the same quantity as column {first_index} `{first}`")]
    DuplicateColumn {
        /// The earlier column's name.
        first: String,
        /// The earlier column's 1-based position in the header.
        first_index: usize,
    },
    /// Required columns are absent.
    #[error("missing required column{} {}: {why}", if names.len() == 1 { "" } else { "s" }, names.join(", "))]
    MissingColumn {
        /// The missing columns (with accepted alternatives in parentheses).
        names: Vec<String>,
        /// Why they are required.
        why: String,
    },
    /// A cell that is not a number.
    #[error("not a number: `{value}`")]
    NonNumeric {
        /// The cell as written.
        value: String,
    },
    /// A cell that is NaN or infinite.
    #[error("not a finite number: `{value}`")]
    NonFinite {
        /// The cell as written.
        value: String,
    },
    /// A row with more or fewer cells than the header.
    #[error("the row has {found} cells but the header has {expected}")]
    RowLength {
        /// Cells in the header.
        expected: usize,
        /// Cells in this row.
        found: usize,
    },
    /// A time not after the previous row's.
    #[error("time {current} s is not after {previous} s on line {previous_line}; times must increase strictly")]
    NonIncreasingTime {
        /// The previous row's time, s.
        previous: f64,
        /// Its line.
        previous_line: usize,
        /// This row's time, s.
        current: f64,
    },
}

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.file)?;
        match (&self.line, &self.column) {
            (Some(l), Some(c)) => write!(f, "line {l}, column `{c}`: ")?,
            (Some(l), None) => write!(f, "line {l}: ")?,
            (None, Some(c)) => write!(f, "column `{c}`: ")?,
            (None, None) => {}
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for DataError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            DataErrorKind::Unreadable(e) => Some(e),
            _ => None,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// FlightData methods

impl FlightData {
    /// Data with times and positions only (every optional channel absent).
    pub fn new(meta: Metadata, time: Vec<f64>, pos_ned: Vec<DVec3>) -> Self {
        Self {
            meta,
            time,
            pos_ned,
            ..Self::default()
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Time from the first sample to the last, s (0 with fewer than two samples).
    pub fn duration(&self) -> f64 {
        match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// True when `channel` (e.g. [`DERIVED_VEL_NED`]) was derived rather than read.
    pub fn is_derived(&self, channel: &str) -> bool {
        self.derived.contains(&channel)
    }

    /// Checks the invariants: every present channel has [`len`](Self::len) entries, times
    /// increase strictly, and all values are finite.
    ///
    /// # Errors
    /// A sentence saying what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.len();
        let check_len = |name: &str, m: Option<usize>| match m {
            Some(m) if m != n => Err(format!("{name} has {m} samples but time has {n}")),
            _ => Ok(()),
        };
        check_len("pos_ned", Some(self.pos_ned.len()))?;
        check_len("attitude", self.attitude.as_ref().map(Vec::len))?;
        check_len("vel_ned", self.vel_ned.as_ref().map(Vec::len))?;
        check_len("vel_body", self.vel_body.as_ref().map(Vec::len))?;
        check_len("rates_body", self.rates_body.as_ref().map(Vec::len))?;
        check_len("airspeed", self.airspeed.as_ref().map(Vec::len))?;
        check_len("controls", self.controls.as_ref().map(Vec::len))?;
        for (i, t) in self.time.iter().enumerate() {
            if !t.is_finite() {
                return Err(format!("time[{i}] is not finite"));
            }
            if i > 0 && *t <= self.time[i - 1] {
                return Err(format!(
                    "time[{i}] = {t} is not after time[{}] = {}",
                    i - 1,
                    self.time[i - 1]
                ));
            }
        }
        let vecs = |name: &str, v: Option<&Vec<DVec3>>| -> Result<(), String> {
            match v.and_then(|v| v.iter().position(|x| !x.is_finite())) {
                Some(i) => Err(format!("{name}[{i}] is not finite")),
                None => Ok(()),
            }
        };
        vecs("pos_ned", Some(&self.pos_ned))?;
        vecs("vel_ned", self.vel_ned.as_ref())?;
        vecs("vel_body", self.vel_body.as_ref())?;
        vecs("rates_body", self.rates_body.as_ref())?;
        if let Some(i) = self
            .attitude
            .as_ref()
            .and_then(|a| a.iter().position(|e| !e.is_finite()))
        {
            return Err(format!("attitude[{i}] is not finite"));
        }
        if let Some(i) = self
            .airspeed
            .as_ref()
            .and_then(|a| a.iter().position(|x| !x.is_finite()))
        {
            return Err(format!("airspeed[{i}] is not finite"));
        }
        if let Some(i) = self.controls.as_ref().and_then(|c| {
            c.iter().position(|c| {
                !(c.throttle.is_finite()
                    && c.elevator.is_finite()
                    && c.aileron.is_finite()
                    && c.rudder.is_finite())
            })
        }) {
            return Err(format!("controls[{i}] is not finite"));
        }
        Ok(())
    }

    /// Index of the last sample at or before `t` (`None` before the first sample or when
    /// empty).
    pub fn index_at(&self, t: f64) -> Option<usize> {
        let after = self.time.partition_point(|&s| s <= t);
        after.checked_sub(1)
    }

    /// Controls in force at time `t` under the zero-order hold (the first row's before the
    /// first sample); `None` when the data has no controls.
    pub fn controls_at(&self, t: f64) -> Option<Controls> {
        let c = self.controls.as_ref()?;
        c.get(self.index_at(t).unwrap_or(0)).copied()
    }

    /// Position at time `t`, interpolated linearly between samples and held at the ends;
    /// `None` when empty.
    pub fn position_at(&self, t: f64) -> Option<DVec3> {
        let n = self.len().min(self.pos_ned.len());
        if n == 0 {
            return None;
        }
        let i = match self.index_at(t) {
            None => return Some(self.pos_ned[0]),
            Some(i) if i + 1 >= n => return Some(self.pos_ned[n - 1]),
            Some(i) => i,
        };
        let (t0, t1) = (self.time[i], self.time[i + 1]);
        let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
        Some(self.pos_ned[i].lerp(self.pos_ned[i + 1], s))
    }

    /// [`derive_missing_with`](Self::derive_missing_with) with the default [`Window`].
    /// [`parse`] and [`read`] call this before returning.
    pub fn derive_missing(&mut self) {
        self.derive_missing_with(Window::default());
    }

    /// Fills absent channels that can be computed, and records them in
    /// [`derived`](Self::derived):
    ///
    /// * `vel_ned`: R·vel_body when attitude and body velocity are present (exact), else the
    ///   smoothed derivative of the positions;
    /// * `rates_body`: from the smoothed derivatives of the continuously unwrapped attitude
    ///   ([`body_rates_from_attitude`]);
    /// * `vel_body`: Rᵀ·vel_ned when attitude is present.
    ///
    /// Present channels are never changed. Does nothing with fewer than two samples or when
    /// [`validate`](Self::validate) fails.
    pub fn derive_missing_with(&mut self, window: Window) {
        if self.len() < 2 || self.validate().is_err() {
            return;
        }
        let needs_diff = self.vel_ned.is_none() || self.rates_body.is_none();
        let diff =
            needs_diff.then(|| Differentiator::new(&self.time, window.half_samples(&self.time)));
        let mark = |derived: &mut Vec<&'static str>, name: &'static str| {
            if !derived.contains(&name) {
                derived.push(name);
            }
        };
        if self.vel_ned.is_none() {
            let v = match (&self.attitude, &self.vel_body) {
                (Some(att), Some(vb)) => att
                    .iter()
                    .zip(vb)
                    .map(|(e, v)| e.to_matrix() * *v)
                    .collect(),
                _ => match &diff {
                    Some(d) => d.apply_vec3(&self.pos_ned),
                    None => return,
                },
            };
            self.vel_ned = Some(v);
            mark(&mut self.derived, DERIVED_VEL_NED);
        }
        if self.rates_body.is_none() {
            if let (Some(att), Some(d)) = (&self.attitude, &diff) {
                self.rates_body = Some(body_rates_from_attitude(d, att));
                mark(&mut self.derived, DERIVED_RATES_BODY);
            }
        }
        if self.vel_body.is_none() {
            if let (Some(att), Some(vn)) = (&self.attitude, &self.vel_ned) {
                self.vel_body = Some(
                    att.iter()
                        .zip(vn)
                        .map(|(e, v)| e.to_matrix().transpose() * *v)
                        .collect(),
                );
                mark(&mut self.derived, DERIVED_VEL_BODY);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Differentiation

/// Smoothing differentiator for unevenly sampled data: at each sample, the slope of the
/// least-squares quadratic through the 2k + 1 nearest samples (one-sided windows of the same
/// size at the ends). See the module docs for the choice of k.
///
/// The weights depend only on the times, so one `Differentiator` serves every channel.
#[derive(Clone, Debug)]
pub struct Differentiator {
    /// Per sample: first index of its window and the weights of the window's samples.
    windows: Vec<(usize, Vec<f64>)>,
}

impl Differentiator {
    /// Weights for sample times `time` (strictly increasing) and half-width `half` samples.
    /// With fewer than three samples in a window the fit is a straight line; with one sample
    /// the derivative is 0. Times that are not strictly increasing give NaN, not a panic.
    pub fn new(time: &[f64], half: usize) -> Self {
        let n = time.len();
        let m = half.saturating_mul(2).saturating_add(1).min(n).max(1);
        let windows = (0..n)
            .map(|i| {
                let lo = i.saturating_sub(half).min(n - m);
                let w = local_fit_weights(&time[lo..lo + m], time[i]);
                (lo, w)
            })
            .collect();
        Self { windows }
    }

    /// With the half-width of `window` for these times.
    pub fn with_window(time: &[f64], window: Window) -> Self {
        Self::new(time, window.half_samples(time))
    }

    /// Number of samples it was built for.
    pub fn len(&self) -> usize {
        self.windows.len()
    }

    /// True when built for no samples.
    pub fn is_empty(&self) -> bool {
        self.windows.is_empty()
    }

    /// Derivative of scalar samples `x` (one per time; missing entries count as 0).
    pub fn apply(&self, x: &[f64]) -> Vec<f64> {
        self.windows
            .iter()
            .map(|(lo, w)| {
                w.iter()
                    .enumerate()
                    .map(|(j, wj)| wj * x.get(lo + j).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect()
    }

    /// Derivative of vector samples `x` (one per time; missing entries count as 0).
    pub fn apply_vec3(&self, x: &[DVec3]) -> Vec<DVec3> {
        self.windows
            .iter()
            .map(|(lo, w)| {
                w.iter()
                    .enumerate()
                    .map(|(j, wj)| *wj * x.get(lo + j).copied().unwrap_or(DVec3::ZERO))
                    .sum()
            })
            .collect()
    }
}

/// Weights w such that Σ w_j x_j is the slope at `t0` of the least-squares quadratic (a line
/// with two samples) through (t_j, x_j).
fn local_fit_weights(t: &[f64], t0: f64) -> Vec<f64> {
    let m = t.len();
    if m < 2 {
        return vec![0.0; m];
    }
    // Scale τ into [−1, 1] for conditioning.
    let s = t.iter().map(|tj| (tj - t0).abs()).fold(0.0f64, f64::max);
    let tau: Vec<f64> = t.iter().map(|tj| (tj - t0) / s).collect();
    if m >= 3 {
        // Normal equations M·c = Aᵀx with rows (1, τ, τ²); slope at τ = 0 is c1 = e1ᵀ M⁻¹ Aᵀx,
        // so w_j = (M⁻¹ e1) · (1, τ_j, τ_j²) / s (M is symmetric).
        let mut mom = [0.0f64; 5];
        for &x in &tau {
            let mut p = 1.0;
            for mk in &mut mom {
                *mk += p;
                p *= x;
            }
        }
        let mat = glam::DMat3::from_cols(
            DVec3::new(mom[0], mom[1], mom[2]),
            DVec3::new(mom[1], mom[2], mom[3]),
            DVec3::new(mom[2], mom[3], mom[4]),
        );
        let det = mat.determinant();
        // A well-spread window has det of order m³; tiny det means samples bunched at ≤ 2 times.
        if det.is_finite() && det > 1e-10 * (m as f64).powi(3) {
            let y = mat.inverse() * DVec3::Y;
            return tau
                .iter()
                .map(|&x| (y.x + y.y * x + y.z * x * x) / s)
                .collect();
        }
    }
    // Straight line: slope = Σ (τ_j − τ̄) x_j / Σ (τ_j − τ̄)².
    let mean = tau.iter().sum::<f64>() / m as f64;
    let ss: f64 = tau.iter().map(|x| (x - mean) * (x - mean)).sum();
    tau.iter().map(|x| (x - mean) / ss / s).collect()
}

/// Removes jumps of more than π between successive angles by adding multiples of 2π, so the
/// result is continuous (e.g. 179°, −179° becomes 179°, 181°). Non-finite entries are passed
/// through and skipped.
pub fn unwrap_angles(angles: &[f64]) -> Vec<f64> {
    let mut prev: Option<f64> = None;
    angles
        .iter()
        .map(|&a| {
            let out = match prev {
                Some(p) => nearest_turn(a, p),
                None => a,
            };
            if out.is_finite() {
                prev = Some(out);
            }
            out
        })
        .collect()
}

/// `a + 2πm` closest to `reference`.
fn nearest_turn(a: f64, reference: f64) -> f64 {
    let m = ((reference - a) / TAU).round();
    if m.is_finite() {
        a + TAU * m
    } else {
        a
    }
}

/// Attitude made continuous from sample to sample, for differentiation. Besides adding whole
/// turns to each angle (as [`unwrap_angles`]), it may switch to the other z-y-x angles of the
/// same rotation, (ψ + π, π − θ, φ + π), when those are nearer to the previous sample: this
/// follows the body through pitch ±90° (where stored angles flip by 180° in yaw and roll) and
/// lets pitch run past ±90°. Every output describes the same rotation as its input.
pub fn unwrap_attitude(attitude: &[EulerZyx]) -> Vec<EulerZyx> {
    let mut prev: Option<EulerZyx> = None;
    attitude
        .iter()
        .map(|&e| {
            let Some(p) = prev else {
                if e.is_finite() {
                    prev = Some(e);
                }
                return e;
            };
            if !e.is_finite() {
                return e;
            }
            let near = |yaw: f64, pitch: f64, roll: f64| {
                EulerZyx::new(
                    nearest_turn(yaw, p.yaw),
                    nearest_turn(pitch, p.pitch),
                    nearest_turn(roll, p.roll),
                )
            };
            let dist = |c: EulerZyx| {
                (c.yaw - p.yaw).powi(2) + (c.pitch - p.pitch).powi(2) + (c.roll - p.roll).powi(2)
            };
            let a = near(e.yaw, e.pitch, e.roll);
            let b = near(e.yaw + PI, PI - e.pitch, e.roll + PI);
            let out = if dist(b) < dist(a) { b } else { a };
            prev = Some(out);
            out
        })
        .collect()
}

/// Body rates (p, q, r) from attitude samples: the attitude is unwrapped
/// ([`unwrap_attitude`]), each angle differentiated with `diff`, and the Euler-angle rates
/// mapped to body rates: p = φ̇ − ψ̇ sinθ, q = θ̇ cosφ + ψ̇ cosθ sinφ,
/// r = −θ̇ sinφ + ψ̇ cosθ cosφ. At exact gimbal lock (|θ| = 90°) ψ and φ are not separately
/// defined by the data and rates there are as good as the data's split between them.
pub fn body_rates_from_attitude(diff: &Differentiator, attitude: &[EulerZyx]) -> Vec<DVec3> {
    let u = unwrap_attitude(attitude);
    let yaw: Vec<f64> = u.iter().map(|e| e.yaw).collect();
    let pitch: Vec<f64> = u.iter().map(|e| e.pitch).collect();
    let roll: Vec<f64> = u.iter().map(|e| e.roll).collect();
    let (dyaw, dpitch, droll) = (diff.apply(&yaw), diff.apply(&pitch), diff.apply(&roll));
    u.iter()
        .zip(dyaw.iter().zip(dpitch.iter().zip(&droll)))
        .map(|(e, (&psi_d, (&theta_d, &phi_d)))| {
            let (sth, cth) = e.pitch.sin_cos();
            let (sph, cph) = e.roll.sin_cos();
            DVec3::new(
                phi_d - psi_d * sth,
                theta_d * cph + psi_d * cth * sph,
                -theta_d * sph + psi_d * cth * cph,
            )
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Reading

/// Quantities a column can give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ch {
    Time,
    North,
    East,
    Down,
    Roll,
    Pitch,
    Yaw,
    Vn,
    Ve,
    Vd,
    U,
    V,
    W,
    P,
    Q,
    R,
    Airspeed,
    Throttle,
    Elevator,
    Aileron,
    Rudder,
    Lat,
    Lon,
    Alt,
}

const N_CH: usize = 24;

const ATTITUDE: [Ch; 3] = [Ch::Roll, Ch::Pitch, Ch::Yaw];
const CONTROLS: [Ch; 4] = [Ch::Throttle, Ch::Elevator, Ch::Aileron, Ch::Rudder];
const GROUPS: [(&str, &[Ch]); 5] = [
    ("attitude", &ATTITUDE),
    ("NED velocity", &[Ch::Vn, Ch::Ve, Ch::Vd]),
    ("body velocity", &[Ch::U, Ch::V, Ch::W]),
    ("body rates", &[Ch::P, Ch::Q, Ch::R]),
    ("controls", &CONTROLS),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dialect {
    Wireflight,
    Jsbsim,
}

/// Quantity and factor to SI (radians for angles) of a wireflight column.
fn native_column(name: &str) -> Option<(Ch, f64)> {
    let d = PI / 180.0;
    Some(match name {
        "time_s" => (Ch::Time, 1.0),
        "north_m" => (Ch::North, 1.0),
        "east_m" => (Ch::East, 1.0),
        "down_m" => (Ch::Down, 1.0),
        "roll_deg" => (Ch::Roll, d),
        "roll_rad" => (Ch::Roll, 1.0),
        "pitch_deg" => (Ch::Pitch, d),
        "pitch_rad" => (Ch::Pitch, 1.0),
        "yaw_deg" => (Ch::Yaw, d),
        "yaw_rad" => (Ch::Yaw, 1.0),
        "vn_mps" => (Ch::Vn, 1.0),
        "ve_mps" => (Ch::Ve, 1.0),
        "vd_mps" => (Ch::Vd, 1.0),
        "u_mps" => (Ch::U, 1.0),
        "v_mps" => (Ch::V, 1.0),
        "w_mps" => (Ch::W, 1.0),
        "p_dps" => (Ch::P, d),
        "p_radps" => (Ch::P, 1.0),
        "q_dps" => (Ch::Q, d),
        "q_radps" => (Ch::Q, 1.0),
        "r_dps" => (Ch::R, d),
        "r_radps" => (Ch::R, 1.0),
        "airspeed_mps" => (Ch::Airspeed, 1.0),
        "throttle" => (Ch::Throttle, 1.0),
        "elevator_deg" => (Ch::Elevator, d),
        "elevator_rad" => (Ch::Elevator, 1.0),
        "aileron_deg" => (Ch::Aileron, d),
        "aileron_rad" => (Ch::Aileron, 1.0),
        "rudder_deg" => (Ch::Rudder, d),
        "rudder_rad" => (Ch::Rudder, 1.0),
        _ => return None,
    })
}

/// Quantity, factor to SI and priority (lower wins) of a JSBSim column.
fn jsbsim_column(name: &str) -> Option<(Ch, f64, usize)> {
    let find = |key: &str| JSBSIM_COLUMNS.iter().position(|(n, _)| *n == key);
    // Property names with or without the `/fdm/jsbsim/` prefix.
    let priority = find(name).or_else(|| {
        let short = name.trim_start_matches('/');
        let short = short.strip_prefix("fdm/jsbsim/").unwrap_or(short);
        find(&format!("/fdm/jsbsim/{short}"))
    })?;
    let what = JSBSIM_COLUMNS[priority].1;
    let ch = if what.starts_with("time") {
        Ch::Time
    } else if what.starts_with("latitude") {
        Ch::Lat
    } else if what.starts_with("longitude") {
        Ch::Lon
    } else if what.starts_with("height") {
        Ch::Alt
    } else if what.starts_with("roll,") {
        Ch::Roll
    } else if what.starts_with("pitch,") {
        Ch::Pitch
    } else if what.starts_with("yaw,") {
        Ch::Yaw
    } else if what.starts_with("roll rate") {
        Ch::P
    } else if what.starts_with("pitch rate") {
        Ch::Q
    } else if what.starts_with("yaw rate") {
        Ch::R
    } else if what.starts_with("body u") {
        Ch::U
    } else if what.starts_with("body v") {
        Ch::V
    } else if what.starts_with("body w") {
        Ch::W
    } else if what.starts_with("north") {
        Ch::Vn
    } else if what.starts_with("east") {
        Ch::Ve
    } else if what.starts_with("down") {
        Ch::Vd
    } else {
        Ch::Airspeed
    };
    let scale = if what.ends_with("ft/s") || what.ends_with(", ft") {
        METRES_PER_FOOT
    } else if what.ends_with(", kt") {
        MPS_PER_KNOT
    } else if what.ends_with("deg") || what.ends_with("deg/s") {
        PI / 180.0
    } else {
        1.0
    };
    Some((ch, scale, priority))
}

/// How a missing quantity is named in errors.
fn column_label(dialect: Dialect, ch: Ch) -> &'static str {
    match dialect {
        Dialect::Wireflight => match ch {
            Ch::Time => "time_s",
            Ch::North => "north_m",
            Ch::East => "east_m",
            Ch::Down => "down_m",
            Ch::Roll => "roll_deg (or roll_rad)",
            Ch::Pitch => "pitch_deg (or pitch_rad)",
            Ch::Yaw => "yaw_deg (or yaw_rad)",
            Ch::Vn => "vn_mps",
            Ch::Ve => "ve_mps",
            Ch::Vd => "vd_mps",
            Ch::U => "u_mps",
            Ch::V => "v_mps",
            Ch::W => "w_mps",
            Ch::P => "p_dps (or p_radps)",
            Ch::Q => "q_dps (or q_radps)",
            Ch::R => "r_dps (or r_radps)",
            Ch::Airspeed => "airspeed_mps",
            Ch::Throttle => "throttle",
            Ch::Elevator => "elevator_deg (or elevator_rad)",
            Ch::Aileron => "aileron_deg (or aileron_rad)",
            Ch::Rudder => "rudder_deg (or rudder_rad)",
            Ch::Lat | Ch::Lon | Ch::Alt => "(geodetic position)",
        },
        Dialect::Jsbsim => match ch {
            Ch::Time => "Time",
            Ch::Lat => {
                "/fdm/jsbsim/position/lat-geod-rad (or lat-geod-deg, lat-gc-rad, lat-gc-deg)"
            }
            Ch::Lon => "/fdm/jsbsim/position/long-gc-rad (or long-gc-deg)",
            Ch::Alt => "/fdm/jsbsim/position/h-sl-ft (or h-sl-meters)",
            Ch::Roll => "/fdm/jsbsim/attitude/phi-rad (or phi-deg)",
            Ch::Pitch => "/fdm/jsbsim/attitude/theta-rad (or theta-deg)",
            Ch::Yaw => "/fdm/jsbsim/attitude/psi-rad (or psi-deg)",
            Ch::Vn => "/fdm/jsbsim/velocities/v-north-fps",
            Ch::Ve => "/fdm/jsbsim/velocities/v-east-fps",
            Ch::Vd => "/fdm/jsbsim/velocities/v-down-fps",
            Ch::U => "/fdm/jsbsim/velocities/u-fps",
            Ch::V => "/fdm/jsbsim/velocities/v-fps",
            Ch::W => "/fdm/jsbsim/velocities/w-fps",
            Ch::P => "/fdm/jsbsim/velocities/p-rad_sec",
            Ch::Q => "/fdm/jsbsim/velocities/q-rad_sec",
            Ch::R => "/fdm/jsbsim/velocities/r-rad_sec",
            Ch::Airspeed => "/fdm/jsbsim/velocities/vt-fps",
            Ch::Throttle => "throttle (controls are not read from JSBSim output)",
            Ch::Elevator => "elevator (controls are not read from JSBSim output)",
            Ch::Aileron => "aileron (controls are not read from JSBSim output)",
            Ch::Rudder => "rudder (controls are not read from JSBSim output)",
            Ch::North | Ch::East | Ch::Down => "(NED position)",
        },
    }
}

/// Reads a flight-data file (either dialect; see the module docs) and derives missing
/// channels ([`FlightData::derive_missing`]).
///
/// # Errors
/// [`DataError`] naming the file, line and column: unreadable or non-UTF-8 file, and
/// everything [`parse`] rejects.
pub fn read(path: &Path) -> Result<FlightData, DataError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| DataError {
        file: file.clone(),
        line: None,
        column: None,
        kind: DataErrorKind::Unreadable(e),
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        DataError {
            file: file.clone(),
            line: Some(good.iter().filter(|&&b| b == b'\n').count() + 1),
            column: None,
            kind: DataErrorKind::NotUtf8,
        }
    })?;
    parse(&text, &file)
}

/// Parses flight-data text (either dialect; see the module docs), `name_for_errors` standing
/// for the file in errors, and derives missing channels ([`FlightData::derive_missing`]).
///
/// Rules: blank lines are skipped anywhere; `#` lines before the header are metadata
/// (`# key: value`; `#` lines without a colon are comments), `#` lines after it are comments;
/// cells are separated by commas and trimmed; unknown columns are ignored; a metadata key given
/// twice keeps the last value.
///
/// # Errors
/// [`DataError`]: bad metadata values, no header, no rows, duplicate or missing required
/// columns (time and position always; attitude and controls for `vehicle: fixed-wing`; the
/// rest of a set such as `roll/pitch/yaw` once one of it is present), non-numeric or
/// non-finite cells in columns that are read, rows of the wrong length, times that do not
/// increase.
pub fn parse(text: &str, name_for_errors: &str) -> Result<FlightData, DataError> {
    let err = |line: usize, column: Option<&str>, kind: DataErrorKind| DataError {
        file: name_for_errors.to_string(),
        line: Some(line),
        column: column.map(str::to_string),
        kind,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));

    // Metadata and header.
    let mut meta = Metadata::default();
    let mut last_line = 0;
    let mut header = None;
    for (n, l) in lines.by_ref() {
        last_line = n;
        if l.is_empty() {
            continue;
        }
        if let Some(rest) = l.strip_prefix('#') {
            parse_metadata(rest, &mut meta).map_err(|k| err(n, None, k))?;
            continue;
        }
        header = Some((n, l));
        break;
    }
    let Some((hline, htext)) = header else {
        return Err(err(last_line.max(1), None, DataErrorKind::Empty));
    };
    let names: Vec<&str> = htext
        .split(',')
        .map(|c| {
            let c = c.trim();
            c.strip_prefix('"')
                .and_then(|c| c.strip_suffix('"'))
                .unwrap_or(c)
                .trim()
        })
        .collect();
    let dialect = if !names.contains(&"time_s")
        && names
            .iter()
            .any(|n| *n == "Time" || n.starts_with("/fdm/jsbsim/"))
    {
        Dialect::Jsbsim
    } else {
        Dialect::Wireflight
    };

    // Map columns to quantities: slot = (column index, factor, priority).
    let mut slots: [Option<(usize, f64, usize)>; N_CH] = [None; N_CH];
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, &name) in names.iter().enumerate() {
        if name.is_empty() {
            continue;
        }
        if let Some(&first) = seen.get(name) {
            return Err(err(
                hline,
                Some(name),
                DataErrorKind::DuplicateColumn {
                    first: names[first].to_string(),
                    first_index: first + 1,
                },
            ));
        }
        seen.insert(name, i);
        let mapped = match dialect {
            Dialect::Wireflight => native_column(name).map(|(c, s)| (c, s, 0)),
            Dialect::Jsbsim => jsbsim_column(name),
        };
        let Some((ch, scale, prio)) = mapped else {
            continue;
        };
        match slots[ch as usize] {
            Some((first, _, p)) if dialect == Dialect::Wireflight || p == prio => {
                return Err(err(
                    hline,
                    Some(name),
                    DataErrorKind::DuplicateColumn {
                        first: names[first].to_string(),
                        first_index: first + 1,
                    },
                ));
            }
            Some((_, _, p)) if p < prio => {}
            _ => slots[ch as usize] = Some((i, scale, prio)),
        }
    }
    let has = |ch: Ch| slots[ch as usize].is_some();
    let missing = |chs: &[Ch]| -> Vec<String> {
        chs.iter()
            .filter(|c| !has(**c))
            .map(|c| column_label(dialect, *c).to_string())
            .collect()
    };
    let required: &[Ch] = match dialect {
        Dialect::Wireflight => &[Ch::Time, Ch::North, Ch::East, Ch::Down],
        Dialect::Jsbsim => &[Ch::Time, Ch::Lat, Ch::Lon, Ch::Alt],
    };
    let miss = missing(required);
    if !miss.is_empty() {
        let why = match dialect {
            Dialect::Wireflight => "every flight-data file needs time and NED position",
            Dialect::Jsbsim => {
                "JSBSim output needs Time and the position (latitude, longitude, height above sea level)"
            }
        };
        return Err(err(
            hline,
            None,
            DataErrorKind::MissingColumn {
                names: miss,
                why: why.to_string(),
            },
        ));
    }
    if meta.vehicle == Some(VehicleKind::FixedWing) {
        let miss = missing(&[&ATTITUDE[..], &CONTROLS[..]].concat());
        if !miss.is_empty() {
            return Err(err(
                hline,
                None,
                DataErrorKind::MissingColumn {
                    names: miss,
                    why: "vehicle fixed-wing needs attitude and controls".to_string(),
                },
            ));
        }
    }
    for (group, chs) in GROUPS {
        let miss = missing(chs);
        if !miss.is_empty() && miss.len() < chs.len() {
            let present = chs
                .iter()
                .find(|c| has(**c))
                .and_then(|c| slots[*c as usize]);
            let present = present.map(|(i, _, _)| names[i]).unwrap_or_default();
            return Err(err(
                hline,
                None,
                DataErrorKind::MissingColumn {
                    names: miss,
                    why: format!("{group} columns come as a set and `{present}` is present"),
                },
            ));
        }
    }

    // Rows.
    let used: Vec<(usize, usize, f64)> = slots
        .iter()
        .enumerate()
        .filter_map(|(ch, s)| s.map(|(col, scale, _)| (ch, col, scale)))
        .collect();
    let time_col = slots[Ch::Time as usize].map_or(0, |s| s.0);
    let mut values: [Vec<f64>; N_CH] = std::array::from_fn(|_| Vec::new());
    let mut cells: Vec<&str> = Vec::with_capacity(names.len());
    let mut prev_time: Option<(f64, usize)> = None;
    for (n, l) in lines {
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        cells.clear();
        cells.extend(l.split(','));
        if cells.len() != names.len() {
            return Err(err(
                n,
                None,
                DataErrorKind::RowLength {
                    expected: names.len(),
                    found: cells.len(),
                },
            ));
        }
        for &(ch, col, scale) in &used {
            let v = parse_cell(cells[col]).map_err(|k| err(n, Some(names[col]), k))?;
            values[ch].push(v * scale);
        }
        let t = values[Ch::Time as usize].last().copied().unwrap_or(0.0);
        if let Some((previous, previous_line)) = prev_time {
            if t <= previous {
                return Err(err(
                    n,
                    Some(names[time_col]),
                    DataErrorKind::NonIncreasingTime {
                        previous,
                        previous_line,
                        current: t,
                    },
                ));
            }
        }
        prev_time = Some((t, n));
    }
    if values[Ch::Time as usize].is_empty() {
        return Err(err(hline, None, DataErrorKind::NoRows));
    }

    // Assemble.
    let take = |ch: Ch, values: &mut [Vec<f64>; N_CH]| std::mem::take(&mut values[ch as usize]);
    let vec3 = |a: Vec<f64>, b: Vec<f64>, c: Vec<f64>| -> Vec<DVec3> {
        a.into_iter()
            .zip(b)
            .zip(c)
            .map(|((x, y), z)| DVec3::new(x, y, z))
            .collect()
    };
    let opt3 = |chs: [Ch; 3], values: &mut [Vec<f64>; N_CH]| -> Option<Vec<DVec3>> {
        has(chs[0]).then(|| {
            vec3(
                take(chs[0], values),
                take(chs[1], values),
                take(chs[2], values),
            )
        })
    };
    let time = take(Ch::Time, &mut values);
    let pos_ned = match dialect {
        Dialect::Wireflight => vec3(
            take(Ch::North, &mut values),
            take(Ch::East, &mut values),
            take(Ch::Down, &mut values),
        ),
        Dialect::Jsbsim => {
            let lat = take(Ch::Lat, &mut values);
            let lon = take(Ch::Lon, &mut values);
            let alt = take(Ch::Alt, &mut values);
            let (lat0, lon0, h0) = (lat[0], lon[0], alt[0]);
            meta.latitude_deg = Some(lat0.to_degrees());
            meta.longitude_deg = Some(lon0.to_degrees());
            meta.altitude_m = Some(h0);
            if meta.source.is_none() {
                meta.source = Some("JSBSim CSV output".to_string());
            }
            let coslat0 = lat0.cos();
            lat.iter()
                .zip(&lon)
                .zip(&alt)
                .map(|((la, lo), h)| {
                    let dlon = lo - lon0;
                    let dlon = dlon - TAU * (dlon / TAU).round();
                    DVec3::new(
                        (la - lat0) * EARTH_RADIUS_M,
                        dlon * EARTH_RADIUS_M * coslat0,
                        -(h - h0),
                    )
                })
                .collect()
        }
    };
    let attitude = opt3([Ch::Yaw, Ch::Pitch, Ch::Roll], &mut values).map(|v| {
        v.into_iter()
            .map(|a| EulerZyx::new(a.x, a.y, a.z))
            .collect()
    });
    let vel_ned = opt3([Ch::Vn, Ch::Ve, Ch::Vd], &mut values);
    let vel_body = opt3([Ch::U, Ch::V, Ch::W], &mut values);
    let rates_body = opt3([Ch::P, Ch::Q, Ch::R], &mut values);
    let airspeed = has(Ch::Airspeed).then(|| take(Ch::Airspeed, &mut values));
    let controls = has(Ch::Throttle).then(|| {
        let t = take(Ch::Throttle, &mut values);
        let e = take(Ch::Elevator, &mut values);
        let a = take(Ch::Aileron, &mut values);
        let r = take(Ch::Rudder, &mut values);
        t.into_iter()
            .zip(e)
            .zip(a)
            .zip(r)
            .map(|(((throttle, elevator), aileron), rudder)| Controls {
                throttle,
                elevator,
                aileron,
                rudder,
            })
            .collect()
    });
    let mut data = FlightData {
        meta,
        time,
        pos_ned,
        attitude,
        vel_ned,
        vel_body,
        rates_body,
        airspeed,
        controls,
        derived: Vec::new(),
    };
    data.derive_missing();
    Ok(data)
}

/// One cell as a finite number.
fn parse_cell(cell: &str) -> Result<f64, DataErrorKind> {
    let c = cell.trim();
    match c.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(DataErrorKind::NonFinite {
            value: c.to_string(),
        }),
        Err(_) => Err(DataErrorKind::NonNumeric {
            value: c.to_string(),
        }),
    }
}

/// One metadata line (after the `#`).
fn parse_metadata(rest: &str, meta: &mut Metadata) -> Result<(), DataErrorKind> {
    let Some((key, value)) = rest.split_once(':') else {
        return Ok(()); // a comment
    };
    let (key, value) = (key.trim(), value.trim());
    if key.is_empty() {
        return Ok(());
    }
    let bad = |reason: String| DataErrorKind::BadMetadata {
        key: key.to_string(),
        reason,
    };
    let number = || -> Result<f64, DataErrorKind> {
        match value.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(bad(format!("`{value}` is not a finite number"))),
            Err(_) => Err(bad(format!("`{value}` is not a number"))),
        }
    };
    match key {
        "vehicle" => meta.vehicle = Some(value.parse::<VehicleKind>().map_err(bad)?),
        "aircraft" => meta.aircraft = Some(value.to_string()),
        "latitude_deg" => meta.latitude_deg = Some(number()?),
        "longitude_deg" => meta.longitude_deg = Some(number()?),
        "altitude_m" => meta.altitude_m = Some(number()?),
        "mass_kg" => meta.mass_kg = Some(number()?),
        "reference_area_m2" => meta.reference_area_m2 = Some(number()?),
        "source" => meta.source = Some(value.to_string()),
        _ => meta.other.push((key.to_string(), value.to_string())),
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Writing

/// Writes `data` as wireflight CSV ([`to_csv_string`]) atomically.
///
/// # Errors
/// Data that fails [`FlightData::validate`] or has no samples (the file could not be read
/// back), and I/O errors.
pub fn write(path: &Path, data: &FlightData) -> anyhow::Result<()> {
    if let Err(e) = data.validate() {
        anyhow::bail!("{}: cannot write flight data: {e}", path.display());
    }
    if data.is_empty() {
        anyhow::bail!("{}: cannot write flight data: no samples", path.display());
    }
    crate::fsio::write_atomic(path, to_csv_string(data).as_bytes())
}

/// The wireflight CSV text of `data`: metadata lines, the header, one row per sample. Writes
/// the channels that are present and not [derived](FlightData::derived), angles in degrees,
/// rates in deg/s, numbers in shortest round-trip form. Expects valid data
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
    if ctl.is_some() {
        header.extend(["throttle", "elevator_deg", "aileron_deg", "rudder_deg"]);
    }
    s.push_str(&header.join(","));
    s.push('\n');

    let nan3 = DVec3::splat(f64::NAN);
    for (i, t) in data.time.iter().enumerate() {
        let mut row: Vec<f64> = Vec::with_capacity(header.len());
        let p = data.pos_ned.get(i).copied().unwrap_or(nan3);
        row.extend([*t, p.x, p.y, p.z]);
        if let Some(a) = att {
            let e = a
                .get(i)
                .copied()
                .unwrap_or(EulerZyx::new(f64::NAN, f64::NAN, f64::NAN));
            row.extend([
                e.roll.to_degrees(),
                e.pitch.to_degrees(),
                e.yaw.to_degrees(),
            ]);
        }
        for v in [vn, vb].into_iter().flatten() {
            let v = v.get(i).copied().unwrap_or(nan3);
            row.extend([v.x, v.y, v.z]);
        }
        if let Some(r) = rates {
            let r = r.get(i).copied().unwrap_or(nan3);
            row.extend([r.x.to_degrees(), r.y.to_degrees(), r.z.to_degrees()]);
        }
        if let Some(a) = air {
            row.push(a.get(i).copied().unwrap_or(f64::NAN));
        }
        if let Some(c) = ctl {
            let c = c.get(i).copied().unwrap_or(Controls {
                throttle: f64::NAN,
                elevator: f64::NAN,
                aileron: f64::NAN,
                rudder: f64::NAN,
            });
            row.extend([
                c.throttle,
                c.elevator.to_degrees(),
                c.aileron.to_degrees(),
                c.rudder.to_degrees(),
            ]);
        }
        for (j, v) in row.iter().enumerate() {
            if j > 0 {
                s.push(',');
            }
            let _ = write!(s, "{v}");
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded LCG + Box–Muller: deterministic Gaussian noise without extra dependencies.
    struct Noise(u64);

    impl Noise {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
        fn gauss(&mut self) -> f64 {
            let (u1, u2) = (self.uniform(), self.uniform());
            (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
        }
    }

    /// Non-uniform times: steps drawn in [0.6, 1.4]·dt.
    fn uneven_times(n: usize, dt: f64, noise: &mut Noise) -> Vec<f64> {
        let mut t = vec![0.0];
        for _ in 1..n {
            let last = *t.last().unwrap();
            t.push(last + dt * (0.6 + 0.8 * noise.uniform()));
        }
        t
    }

    fn rms(a: &[f64]) -> f64 {
        (a.iter().map(|x| x * x).sum::<f64>() / a.len() as f64).sqrt()
    }

    #[test]
    fn derivative_of_a_quadratic_is_exact_on_uneven_times() {
        let mut noise = Noise(1);
        let t = uneven_times(60, 0.05, &mut noise);
        let x: Vec<f64> = t.iter().map(|t| 3.0 - 2.0 * t + 7.5 * t * t).collect();
        for half in [1, 2, 4, 9] {
            let d = Differentiator::new(&t, half).apply(&x);
            for (ti, di) in t.iter().zip(&d) {
                let exact = -2.0 + 15.0 * ti;
                assert!(
                    (di - exact).abs() < 1e-9,
                    "half {half} t {ti}: {di} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn derivative_of_a_cubic_is_close() {
        let mut noise = Noise(2);
        let t = uneven_times(200, 0.05, &mut noise);
        let x: Vec<f64> = t.iter().map(|t| t * t * t - 4.0 * t).collect();
        let half = 4;
        let d = Differentiator::new(&t, half).apply(&x);
        let n = t.len();
        for i in 0..n {
            let exact = 3.0 * t[i] * t[i] - 4.0;
            // A quadratic fit leaves the cubic term: the slope error is of order h² (h the
            // window's span, ≤ 2·half·1.4·dt = 0.56 s): ≲ 0.6·h² inside, a few h² at the ends.
            let lo = i.saturating_sub(half).min(n - 2 * half - 1);
            let h = t[lo + 2 * half] - t[lo];
            let bound = if i >= half && i + half < n {
                0.6 * h * h
            } else {
                3.0 * h * h
            };
            assert!(
                (d[i] - exact).abs() < bound,
                "i {i}: {} vs {exact} (bound {bound})",
                d[i]
            );
        }
    }

    #[test]
    fn two_samples_give_the_slope_and_one_gives_zero() {
        let d = Differentiator::new(&[1.0, 3.0], 4).apply(&[5.0, 9.0]);
        assert_eq!(d, vec![2.0, 2.0]);
        let d = Differentiator::new(&[1.0], 4).apply(&[5.0]);
        assert_eq!(d, vec![0.0]);
        assert!(Differentiator::new(&[], 4).is_empty());
    }

    #[test]
    fn smoothing_beats_central_differences_on_noisy_positions() {
        let mut noise = Noise(42);
        let t = uneven_times(1500, 0.05, &mut noise);
        let truth = |t: f64| 40.0 * (0.4 * t).sin() + 0.8 * t * t;
        let truth_d = |t: f64| 16.0 * (0.4 * t).cos() + 1.6 * t;
        let sigma = 0.3;
        let x: Vec<f64> = t
            .iter()
            .map(|&t| truth(t) + sigma * noise.gauss())
            .collect();
        let d = Differentiator::with_window(&t, Window::default()).apply(&x);
        let err_sg: Vec<f64> = (1..t.len() - 1).map(|i| d[i] - truth_d(t[i])).collect();
        let err_cd: Vec<f64> = (1..t.len() - 1)
            .map(|i| (x[i + 1] - x[i - 1]) / (t[i + 1] - t[i - 1]) - truth_d(t[i]))
            .collect();
        let ratio = rms(&err_sg) / rms(&err_cd);
        println!(
            "half {} samples: RMS error {:.4} m/s vs central differences {:.4} m/s, ratio {ratio:.3}",
            Window::default().half_samples(&t),
            rms(&err_sg),
            rms(&err_cd)
        );
        assert!(ratio < 1.0 / 3.0, "ratio {ratio}");
    }

    #[test]
    fn default_window_follows_the_sample_rate() {
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.05).collect();
        assert_eq!(Window::default().half_samples(&t), 4);
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.001).collect();
        assert_eq!(Window::default().half_samples(&t), MAX_HALF_SAMPLES);
        let t: Vec<f64> = (0..100).map(|i| i as f64).collect();
        assert_eq!(Window::default().half_samples(&t), MIN_HALF_SAMPLES);
        assert_eq!(Window::Samples(0).half_samples(&t), 1);
        assert_eq!(Window::Seconds(f64::NAN).half_samples(&t), MIN_HALF_SAMPLES);
    }

    #[test]
    fn unwrap_removes_jumps_across_180_degrees() {
        let deg = |v: &[f64]| v.iter().map(|d: &f64| d.to_radians()).collect::<Vec<_>>();
        let u = unwrap_angles(&deg(&[170.0, 179.0, -179.0, -170.0, 180.0, -175.0, 10.0]));
        let want = deg(&[170.0, 179.0, 181.0, 190.0, 180.0, 185.0, 10.0]);
        for (a, b) in u.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12, "{u:?}");
        }
        assert_eq!(unwrap_angles(&[]), Vec::<f64>::new());
    }

    #[test]
    fn attitude_unwrap_follows_the_body_over_the_vertical() {
        // Pitching nose-over through +90°: stored angles flip yaw and roll by 180°.
        let stored = [
            EulerZyx::from_degrees(10.0, 88.0, 0.0),
            EulerZyx::from_degrees(10.0, 89.5, 0.0),
            EulerZyx::from_degrees(-170.0, 89.0, 180.0),
            EulerZyx::from_degrees(-170.0, 87.5, -180.0),
        ];
        let u = unwrap_attitude(&stored);
        let pitch: Vec<f64> = u.iter().map(|e| e.pitch.to_degrees()).collect();
        for (p, want) in pitch.iter().zip([88.0, 89.5, 91.0, 92.5]) {
            assert!((p - want).abs() < 1e-9, "{pitch:?}");
        }
        for (a, b) in u.iter().zip(&stored) {
            assert!(a.to_matrix().abs_diff_eq(b.to_matrix(), 1e-12));
            assert!((a.yaw.to_degrees() - 10.0).abs() < 1e-9, "{u:?}");
            assert!(a.roll.to_degrees().abs() < 1e-9, "{u:?}");
        }
    }

    #[test]
    fn body_rates_of_a_turn_across_180_have_no_spike() {
        // Constant yaw rate 20°/s, level: r = 20°/s, p = q = 0, through ψ = ±180°.
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
        let att: Vec<EulerZyx> = t
            .iter()
            .map(|t| {
                let (e, _) = EulerZyx::from_degrees(100.0 + 20.0 * t, 0.0, 0.0).canonical();
                e
            })
            .collect();
        let rates = body_rates_from_attitude(&Differentiator::new(&t, 4), &att);
        for r in &rates {
            assert!(
                (r - DVec3::new(0.0, 0.0, 20f64.to_radians())).length() < 1e-9,
                "{r:?}"
            );
        }
    }

    #[test]
    fn body_rates_of_a_banked_pitching_body_match_the_kinematics() {
        // Roll 30°, pitch oscillating, yaw turning: compare with the formulas at exact rates.
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.01).collect();
        let ang = |t: f64| EulerZyx::new(0.3 * t, 0.2 * (0.5 * t).sin(), 0.5 + 0.1 * t);
        let att: Vec<EulerZyx> = t.iter().map(|&t| ang(t)).collect();
        let rates = body_rates_from_attitude(&Differentiator::new(&t, 5), &att);
        for (i, &ti) in t.iter().enumerate() {
            let e = ang(ti);
            let (psi_d, theta_d, phi_d) = (0.3, 0.1 * (0.5 * ti).cos(), 0.1);
            let want = DVec3::new(
                phi_d - psi_d * e.pitch.sin(),
                theta_d * e.roll.cos() + psi_d * e.pitch.cos() * e.roll.sin(),
                -theta_d * e.roll.sin() + psi_d * e.pitch.cos() * e.roll.cos(),
            );
            // One-sided end windows leave an error of order θ'''·h² ≈ 3e-4 rad/s.
            let tol = if (5..395).contains(&i) { 1e-4 } else { 1e-3 };
            assert!((rates[i] - want).length() < tol, "{i}: {:?}", rates[i]);
        }
    }

    #[test]
    fn derive_missing_fills_velocities_and_rates() {
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let pos: Vec<DVec3> = t.iter().map(|&t| DVec3::new(30.0 * t, 0.0, -t)).collect();
        let mut d = FlightData::new(Metadata::default(), t.clone(), pos);
        d.attitude = Some(vec![EulerZyx::from_degrees(90.0, 0.0, 0.0); t.len()]);
        d.derive_missing();
        assert_eq!(
            d.derived,
            vec![DERIVED_VEL_NED, DERIVED_RATES_BODY, DERIVED_VEL_BODY]
        );
        for v in d.vel_ned.as_ref().unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(30.0, 0.0, -1.0), 1e-9), "{v}");
        }
        // Heading east while moving north: the motion is to the left (−v) in the body.
        for v in d.vel_body.as_ref().unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(0.0, -30.0, -1.0), 1e-9), "{v}");
        }
        for r in d.rates_body.as_ref().unwrap() {
            assert!(r.abs_diff_eq(DVec3::ZERO, 1e-12));
        }
        // Idempotent, and present channels are kept.
        let before = d.clone();
        d.derive_missing();
        assert_eq!(d, before);
    }

    #[test]
    fn vel_ned_comes_from_body_velocity_when_it_can() {
        let t = vec![0.0, 1.0, 2.0];
        let mut d = FlightData::new(Metadata::default(), t, vec![DVec3::ZERO; 3]);
        d.attitude = Some(vec![EulerZyx::from_degrees(90.0, 0.0, 0.0); 3]);
        d.vel_body = Some(vec![DVec3::new(10.0, 0.0, 0.0); 3]);
        d.derive_missing();
        assert_eq!(d.derived, vec![DERIVED_VEL_NED, DERIVED_RATES_BODY]);
        for v in d.vel_ned.unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(0.0, 10.0, 0.0), 1e-12));
        }
    }

    #[test]
    fn invalid_data_is_left_alone() {
        let mut d = FlightData::new(Metadata::default(), vec![0.0, 0.0], vec![DVec3::ZERO; 2]);
        d.derive_missing();
        assert!(d.vel_ned.is_none() && d.derived.is_empty());
        let mut d = FlightData::new(Metadata::default(), vec![0.0, 1.0], vec![DVec3::ZERO]);
        assert!(d.validate().is_err());
        d.derive_missing();
        assert!(d.vel_ned.is_none());
    }

    #[test]
    fn lookups_by_time() {
        let mut d = FlightData::new(
            Metadata::default(),
            vec![0.0, 1.0, 3.0],
            vec![DVec3::ZERO, DVec3::X, DVec3::new(3.0, 0.0, 0.0)],
        );
        d.controls = Some(
            (0..3)
                .map(|i| Controls {
                    throttle: i as f64,
                    ..Controls::default()
                })
                .collect(),
        );
        assert_eq!(d.duration(), 3.0);
        assert_eq!(d.index_at(-1.0), None);
        assert_eq!(d.index_at(1.0), Some(1));
        assert_eq!(d.index_at(2.9), Some(1));
        assert_eq!(d.index_at(9.0), Some(2));
        assert_eq!(d.controls_at(2.0).unwrap().throttle, 1.0);
        assert_eq!(d.controls_at(-5.0).unwrap().throttle, 0.0);
        assert_eq!(d.position_at(2.0), Some(DVec3::new(2.0, 0.0, 0.0)));
        assert_eq!(d.position_at(10.0), Some(DVec3::new(3.0, 0.0, 0.0)));
        assert_eq!(FlightData::default().position_at(0.0), None);
        assert_eq!(FlightData::default().duration(), 0.0);
    }

    #[test]
    fn metadata_lines() {
        let text = "# vehicle: point-mass\n#aircraft:ball\n# a comment\n\n# latitude_deg: 45.5\n\
                    # mass_kg: 12\n# weather: fine: really\ntime_s,north_m,east_m,down_m\n0,0,0,0\n";
        let d = parse(text, "m.csv").unwrap();
        assert_eq!(d.meta.vehicle, Some(VehicleKind::PointMass));
        assert_eq!(d.meta.aircraft.as_deref(), Some("ball"));
        assert_eq!(d.meta.latitude_deg, Some(45.5));
        assert_eq!(d.meta.mass_kg, Some(12.0));
        assert_eq!(
            d.meta.other,
            vec![("weather".to_string(), "fine: really".to_string())]
        );
        let e = parse("# vehicle: point-mass\n# mass_kg: heavy\n", "m.csv").unwrap_err();
        let msg = e.to_string();
        assert_eq!(e.line, Some(2));
        assert!(
            msg.contains("m.csv") && msg.contains("line 2") && msg.contains("mass_kg"),
            "{msg}"
        );
        let e = parse("# vehicle: glider\n", "m.csv").unwrap_err();
        assert!(e.to_string().contains("glider"), "{e}");
        let e = parse("# altitude_m: inf\n", "m.csv").unwrap_err();
        assert!(e.to_string().contains("finite"), "{e}");
    }

    #[test]
    fn jsbsim_units_and_flat_earth() {
        let text = "Time,/fdm/jsbsim/position/lat-geod-deg,/fdm/jsbsim/position/long-gc-deg,\
                    /fdm/jsbsim/position/h-sl-ft,/fdm/jsbsim/velocities/vtrue-kts\n\
                    0,10,179.9999,1000,100\n1,10.001,-179.9999,900,100\n";
        let d = parse(text, "j.csv").unwrap();
        assert_eq!(d.meta.latitude_deg, Some(10.0));
        assert!((d.meta.altitude_m.unwrap() - 304.8).abs() < 1e-9);
        let p = d.pos_ned[1];
        assert!(
            (p.x - 0.001f64.to_radians() * EARTH_RADIUS_M).abs() < 1e-6,
            "{p}"
        );
        // Across the antimeridian: 0.0002° east, not 359.9998° west.
        let east = 0.0002f64.to_radians() * EARTH_RADIUS_M * 10f64.to_radians().cos();
        assert!((p.y - east).abs() < 1e-6, "{p}");
        assert!((p.z - 30.48).abs() < 1e-9, "{p}");
        assert!((d.airspeed.as_ref().unwrap()[0] - 51.444).abs() < 1e-3);
    }
}
