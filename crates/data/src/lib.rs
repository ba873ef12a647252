//! Flight data for wireflight: [`FlightData`] (samples of a measured or simulated flight), the
//! files it is read from — the project's CSV of `docs/flight-data.md` (and JSBSim's), any CSV
//! through a column map ([`mapped`]), PX4 ULog ([`px4`] on [`ulog`]), each a [`FlightReader`]
//! chosen by [`load`] — and the CSV it is written to. Below the flight model: it knows the
//! vehicle only as plain data ([`VehicleKind`], [`Controls`]), and files only through
//! `wireflight_fsio`.
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
//! The smoothing differentiator that does this, and how its window is chosen, are described
//! in [`mod@derive`], which works on plain slices and knows nothing of [`FlightData`].
//!
//! # Writing
//! [`write()`] / [`to_csv_string`] write the wireflight dialect: metadata, then the channels
//! that are present and were not derived, angles in degrees, numbers in Rust's shortest
//! round-trip form (so reading back gives the same numbers; angles and rates to within one
//! rounding of the degree↔radian conversion).
//!
//! # Layout
//! This file holds the data types ([`FlightData`], [`Metadata`]), the errors ([`DataError`],
//! [`ValidationError`]), the unit constants and the ranges of the origin's metadata
//! ([`ORIGIN_RANGES`]); `vehicle.rs` the vehicle's family and controls, `columns.rs` the column
//! tables and dialect detection, `read.rs` the reader, `write.rs` the writer, `fill.rs` the
//! filling-in of missing channels. [`import`] holds the [`FlightReader`] trait and the list of
//! formats, [`READERS`] (this CSV's, [`mapped`], [`px4`] on [`ulog`]), which say what they
//! found in a [`report::ImportReport`]; a new format is a module with a reader and a line in
//! that list. The differentiator and angle unwrapping live in [`mod@derive`] and are
//! re-exported here. [`mod@format`] is how numbers are written for people, everywhere in
//! wireflight.

#![warn(missing_docs)]

mod columns;
pub mod derive;
mod fill;
pub mod format;
pub mod import;
pub mod mapped;
pub mod px4;
mod read;
pub mod report;
pub mod sampling;
pub mod ulog;
mod vehicle;
mod write;

use std::fmt;

use glam::DVec3;

use wireflight_geometry::euler::EulerZyx;

pub use self::columns::JSBSIM_COLUMNS;
pub use self::derive::{
    body_rates_from_attitude, unwrap_angles, unwrap_attitude, Differentiator, Window,
    DEFAULT_HALF_WIDTH_S, MAX_HALF_SAMPLES, MIN_HALF_SAMPLES,
};
pub use self::import::{load, FlightReader, ImportError, LoadOptions, Loaded, READERS};
pub use self::read::{parse, read};
pub use self::report::ImportReport;
pub use self::sampling::{Channel, Sampling};
pub use self::vehicle::{Controls, UnknownVehicle, VehicleKind};
pub use self::write::{to_csv_string, write, WriteError};

/// The name of the project's CSV format in reports.
pub const CSV_FORMAT: &str = "wireflight CSV";

/// Most columns a flight-data header may have: logs have tens to a few thousand; more is
/// not a log, and its column names alone would take many times the file's size in memory.
pub const MAX_COLUMNS: usize = 100_000;

/// Standard gravity g0, m/s².
pub const G0: f64 = 9.80665;

/// Metres per foot (exact).
pub const METRES_PER_FOOT: f64 = 0.3048;

/// Metres per second per knot (exact).
pub const MPS_PER_KNOT: f64 = 1852.0 / 3600.0;

/// Earth radius of the flat-earth conversion of JSBSim geodetic positions, m.
pub const EARTH_RADIUS_M: f64 = 6_371_000.0;

/// Largest accelerometer reading a reader accepts on any axis, m/s²: 50 g. Airframes break
/// long before (aerobatic aircraft are built for about 10 g, small drones survive crashes of
/// more), so beyond it a number is a unit mistake (mg, raw counts) or a glitch, not a flight.
pub const MAX_ACCEL_MPS2: f64 = 50.0 * G0;

/// The range of each field of the flight's geodetic origin, by its metadata key: latitude
/// within ±90°, longitude −180°..360°, altitude −1e4..1e8 m. The readers hold the metadata to
/// it ([`check_origin_field`]), and the flight model its origin.
pub const ORIGIN_RANGES: [(&str, f64, f64); 3] = [
    ("latitude_deg", -90.0, 90.0),
    ("longitude_deg", -180.0, 360.0),
    ("altitude_m", -1e4, 1e8),
];

/// Name recorded in [`FlightData::derived`] when the NED velocity was derived.
pub const DERIVED_VEL_NED: &str = "vel_ned";
/// Name recorded in [`FlightData::derived`] when the body velocity was derived.
pub const DERIVED_VEL_BODY: &str = "vel_body";
/// Name recorded in [`FlightData::derived`] when the body rates were derived.
pub const DERIVED_RATES_BODY: &str = "rates_body";

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
    /// Accelerometer: the specific force at the centre of gravity in body axes (FRD), m/s² —
    /// the acceleration relative to inertial space less gravity, so a level, unaccelerated
    /// airplane reads about (0, 0, −9.81). Within ±[`MAX_ACCEL_MPS2`] on every axis.
    pub accel_body: Option<Vec<DVec3>>,
    /// Control commands: throttle 0..1, surfaces in radians; held from each sample to the next.
    pub controls: Option<Vec<Controls>>,
    /// Channels derived rather than read: [`DERIVED_VEL_NED`], [`DERIVED_VEL_BODY`],
    /// [`DERIVED_RATES_BODY`].
    pub derived: Vec<&'static str>,
    /// Which rows are samples of each channel ([`mod@sampling`]): channels at their own
    /// rates. Empty for a one-rate flight.
    pub sampling: Sampling,
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
    /// The file could not be read. (The OS error is the [`source`](std::error::Error::source),
    /// not in the message, so that an error chain prints it once.)
    #[error("cannot read the file")]
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
    /// A header with more columns than any flight log has.
    #[error("the header has {count} columns, more than {MAX_COLUMNS} (is this a flight log?)")]
    TooManyColumns {
        /// The columns of the header.
        count: usize,
    },
    /// A metadata key the data read given twice: which value was meant is not known.
    #[error("metadata `{key}` is given twice (first on line {first_line}): give it once")]
    RepeatedMetadata {
        /// The key.
        key: String,
        /// The line of its first value.
        first_line: usize,
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
    /// A number outside what the quantity can be in a flight (see the reader's ranges).
    #[error("`{value}` is outside the range of a flight: {range}")]
    OutOfRange {
        /// The cell as written.
        value: String,
        /// The range, with its unit.
        range: &'static str,
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
    /// An empty time cell: every row is at a time.
    #[error("empty: every row needs its time")]
    EmptyTime,
    /// Some cells of a channel's set empty and others not, in one row.
    #[error("empty while `{given}` has a value: the columns of a channel ({channel}) are sampled together")]
    PartlyEmpty {
        /// The channel.
        channel: &'static str,
        /// A column of the set with a value in this row.
        given: String,
    },
    /// A channel whose every cell is empty.
    #[error("no samples: every cell is empty (leave the column out)")]
    NoSamples,
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

/// A field of the flight's origin outside its range ([`ORIGIN_RANGES`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value} is outside {lo}..={hi}")]
pub struct OriginError {
    /// The field, as named in [`ORIGIN_RANGES`].
    pub key: &'static str,
    /// The value refused.
    pub value: f64,
    /// The least valid value.
    pub lo: f64,
    /// The greatest valid value.
    pub hi: f64,
}

/// Check one field of the origin (`key` as in [`ORIGIN_RANGES`]; other keys pass).
///
/// # Errors
/// The value is outside the field's range (the message names both).
pub fn check_origin_field(key: &str, value: f64) -> Result<(), OriginError> {
    match ORIGIN_RANGES.iter().find(|(k, _, _)| *k == key) {
        Some(&(key, lo, hi)) if !(lo..=hi).contains(&value) => {
            Err(OriginError { key, value, lo, hi })
        }
        _ => Ok(()),
    }
}

/// Flight data that breaks an invariant of [`FlightData`] ([`FlightData::validate`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ValidationError {
    /// A channel with another number of samples than the times.
    #[error("{channel} has {len} samples but time has {expected}")]
    Length {
        /// The channel (`pos_ned`, `attitude`, …).
        channel: &'static str,
        /// Its samples.
        len: usize,
        /// Samples of the time.
        expected: usize,
    },
    /// A time not after the one before it.
    #[error("time[{index}] = {time} is not after time[{}] = {previous}", .index - 1)]
    TimeNotIncreasing {
        /// The sample.
        index: usize,
        /// Its time, s.
        time: f64,
        /// The time of the sample before, s.
        previous: f64,
    },
    /// A value that is NaN or infinite.
    #[error("{channel}[{index}] is not finite")]
    NotFinite {
        /// The channel (`time`, `pos_ned`, …).
        channel: &'static str,
        /// The sample.
        index: usize,
    },
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
    /// The first invariant broken.
    pub fn validate(&self) -> Result<(), ValidationError> {
        let n = self.len();
        let check_len = |channel: &'static str, m: Option<usize>| match m {
            Some(len) if len != n => Err(ValidationError::Length {
                channel,
                len,
                expected: n,
            }),
            _ => Ok(()),
        };
        let not_finite =
            |channel: &'static str, index: usize| ValidationError::NotFinite { channel, index };
        check_len("pos_ned", Some(self.pos_ned.len()))?;
        check_len("attitude", self.attitude.as_ref().map(Vec::len))?;
        check_len("vel_ned", self.vel_ned.as_ref().map(Vec::len))?;
        check_len("vel_body", self.vel_body.as_ref().map(Vec::len))?;
        check_len("rates_body", self.rates_body.as_ref().map(Vec::len))?;
        check_len("airspeed", self.airspeed.as_ref().map(Vec::len))?;
        check_len("accel_body", self.accel_body.as_ref().map(Vec::len))?;
        check_len("controls", self.controls.as_ref().map(Vec::len))?;
        check_len(
            "sampling",
            (!self.sampling.is_all()).then(|| self.sampling.len()),
        )?;
        for (i, t) in self.time.iter().enumerate() {
            if !t.is_finite() {
                return Err(not_finite("time", i));
            }
            if i > 0 && *t <= self.time[i - 1] {
                return Err(ValidationError::TimeNotIncreasing {
                    index: i,
                    time: *t,
                    previous: self.time[i - 1],
                });
            }
        }
        let vecs = |channel: &'static str, v: Option<&Vec<DVec3>>| match v
            .and_then(|v| v.iter().position(|x| !x.is_finite()))
        {
            Some(i) => Err(not_finite(channel, i)),
            None => Ok(()),
        };
        vecs("pos_ned", Some(&self.pos_ned))?;
        vecs("vel_ned", self.vel_ned.as_ref())?;
        vecs("vel_body", self.vel_body.as_ref())?;
        vecs("rates_body", self.rates_body.as_ref())?;
        vecs("accel_body", self.accel_body.as_ref())?;
        if let Some(i) = self
            .attitude
            .as_ref()
            .and_then(|a| a.iter().position(|e| !e.is_finite()))
        {
            return Err(not_finite("attitude", i));
        }
        if let Some(i) = self
            .airspeed
            .as_ref()
            .and_then(|a| a.iter().position(|x| !x.is_finite()))
        {
            return Err(not_finite("airspeed", i));
        }
        if let Some(i) = self.controls.as_ref().and_then(|c| {
            c.iter().position(|c| {
                !(c.throttle.is_finite()
                    && c.elevator.is_finite()
                    && c.aileron.is_finite()
                    && c.rudder.is_finite())
            })
        }) {
            return Err(not_finite("controls", i));
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
