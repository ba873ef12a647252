//! CSV in anyone's column names, read through a column map: which column gives which quantity,
//! in which unit, with which offset.
//!
//! # The map
//! Inline (`--columns`): comma-separated `QUANTITY=COLUMN[:SCALE[:OFFSET]]`, e.g.
//!
//! ```text
//! time=t_us:us,north=x,east=y,down=z,roll=phi:deg,pitch=theta:deg,yaw=psi:deg,airspeed=tas:kt
//! ```
//!
//! or a TOML file (`--columns map.toml`), which can also name columns with `,` `:` or `=` in
//! them and set the delimiter:
//!
//! ```toml
//! delimiter = ";"            # default: `,` (or `;` / tab when the header has no comma)
//! [columns]
//! time = { column = "t_us", unit = "us", offset = -12.5 }
//! north = "x"                # a bare string: the column, in SI units
//! lat = { column = "lat_e7", scale = 1e-7, unit = "deg" }
//! ```
//!
//! SCALE is a unit name ([`UNITS`]: `us`, `deg`, `ft`, `kt`, `deg/s`, `%`, …), a number, or
//! both as `NUMBER*UNIT` (`1e-7*deg`); it converts the column to SI units (seconds, metres,
//! radians, m/s, rad/s, m/s², throttle 0..1). OFFSET (SI, added after scaling) shifts a column, e.g.
//! the time: `time=t:s:-120` makes 120 s read as 0. A unit of the wrong kind for its quantity
//! (`roll=phi:ft`) is an error.
//!
//! Quantities ([`QUANTITIES`]): `time`; the position as `north, east, down` (or `height` for
//! −down) or geodetic `lat, lon, alt` (made local NED about the first row on a flat earth, the
//! origin going into the metadata); `roll, pitch, yaw`; `vn, ve, vd`; `u, v, w`; `p, q, r`;
//! `airspeed`; `throttle, elevator, aileron, rudder`; the accelerometer `ax, ay, az` (specific
//! force in body axes FRD; units `m/s2`, `g`, `mg`, `ft/s2`). Sets come whole (all of
//! `roll, pitch, yaw` or none), as in the project's CSV.
//!
//! # The file
//! `#` lines before the header are metadata (`# vehicle: fixed-wing`), as in the project's
//! CSV; the header is the first other line; unmapped columns are ignored (their cells are not
//! parsed). Errors name the file, the line and the column, as the CSV reader's do.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use super::{METRES_PER_FOOT, MPS_PER_KNOT};

mod reader;
pub use reader::{parse, read, MappedError};

/// The format's name in reports.
pub const FORMAT: &str = "CSV with a column map";

/// Kinds of quantity, for checking units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// s
    Time,
    /// m
    Length,
    /// rad
    Angle,
    /// m/s
    Speed,
    /// rad/s
    AngularRate,
    /// 0..1
    Fraction,
    /// m/s²
    Acceleration,
}

impl Dimension {
    /// The kind in words, with its article: `a time`, `an angle`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Time => "a time",
            Self::Length => "a length",
            Self::Angle => "an angle",
            Self::Speed => "a speed",
            Self::AngularRate => "an angular rate",
            Self::Fraction => "a fraction",
            Self::Acceleration => "an acceleration",
        }
    }

    /// The names of its [`UNITS`], comma-separated.
    fn units(self) -> String {
        names(UNITS.iter().filter(|u| u.2 == self).map(|u| u.0))
    }
}

/// The units a map may name: name, factor to SI, dimension.
pub const UNITS: &[(&str, f64, Dimension)] = &[
    ("s", 1.0, Dimension::Time),
    ("ms", 1e-3, Dimension::Time),
    ("us", 1e-6, Dimension::Time),
    ("µs", 1e-6, Dimension::Time),
    ("ns", 1e-9, Dimension::Time),
    ("min", 60.0, Dimension::Time),
    ("h", 3600.0, Dimension::Time),
    ("m", 1.0, Dimension::Length),
    ("mm", 1e-3, Dimension::Length),
    ("cm", 1e-2, Dimension::Length),
    ("km", 1e3, Dimension::Length),
    ("ft", METRES_PER_FOOT, Dimension::Length),
    ("rad", 1.0, Dimension::Angle),
    ("deg", PI / 180.0, Dimension::Angle),
    ("m/s", 1.0, Dimension::Speed),
    ("mps", 1.0, Dimension::Speed),
    ("km/h", 1.0 / 3.6, Dimension::Speed),
    ("kmh", 1.0 / 3.6, Dimension::Speed),
    ("kt", MPS_PER_KNOT, Dimension::Speed),
    ("kts", MPS_PER_KNOT, Dimension::Speed),
    ("ft/s", METRES_PER_FOOT, Dimension::Speed),
    ("fps", METRES_PER_FOOT, Dimension::Speed),
    ("mph", 0.44704, Dimension::Speed),
    ("rad/s", 1.0, Dimension::AngularRate),
    ("radps", 1.0, Dimension::AngularRate),
    ("deg/s", PI / 180.0, Dimension::AngularRate),
    ("dps", PI / 180.0, Dimension::AngularRate),
    ("%", 0.01, Dimension::Fraction),
    ("m/s2", 1.0, Dimension::Acceleration),
    ("m/s²", 1.0, Dimension::Acceleration),
    ("mps2", 1.0, Dimension::Acceleration),
    ("g", crate::G0, Dimension::Acceleration),
    ("mg", 1e-3 * crate::G0, Dimension::Acceleration),
    ("ft/s2", METRES_PER_FOOT, Dimension::Acceleration),
    ("ft/s²", METRES_PER_FOOT, Dimension::Acceleration),
];

/// Quantities a map may give: name, dimension, what it is.
pub const QUANTITIES: &[(&str, Dimension, &str)] = &[
    ("time", Dimension::Time, "time"),
    ("north", Dimension::Length, "north position"),
    ("east", Dimension::Length, "east position"),
    ("down", Dimension::Length, "down position"),
    ("height", Dimension::Length, "height (−down)"),
    ("lat", Dimension::Angle, "latitude"),
    ("lon", Dimension::Angle, "longitude"),
    ("alt", Dimension::Length, "altitude"),
    ("roll", Dimension::Angle, "roll φ"),
    ("pitch", Dimension::Angle, "pitch θ"),
    ("yaw", Dimension::Angle, "yaw ψ"),
    ("vn", Dimension::Speed, "north velocity"),
    ("ve", Dimension::Speed, "east velocity"),
    ("vd", Dimension::Speed, "down velocity"),
    ("u", Dimension::Speed, "body velocity u"),
    ("v", Dimension::Speed, "body velocity v"),
    ("w", Dimension::Speed, "body velocity w"),
    ("p", Dimension::AngularRate, "roll rate p"),
    ("q", Dimension::AngularRate, "pitch rate q"),
    ("r", Dimension::AngularRate, "yaw rate r"),
    ("airspeed", Dimension::Speed, "airspeed"),
    ("throttle", Dimension::Fraction, "throttle 0..1"),
    ("elevator", Dimension::Angle, "elevator"),
    ("aileron", Dimension::Angle, "aileron"),
    ("rudder", Dimension::Angle, "rudder"),
    ("ax", Dimension::Acceleration, "accelerometer x (forward)"),
    ("ay", Dimension::Acceleration, "accelerometer y (right)"),
    ("az", Dimension::Acceleration, "accelerometer z (down)"),
];

/// Sets that come whole.
const SETS: &[(&str, &[&str])] = &[
    ("attitude", &["roll", "pitch", "yaw"]),
    ("NED velocity", &["vn", "ve", "vd"]),
    ("body velocity", &["u", "v", "w"]),
    ("body rates", &["p", "q", "r"]),
    ("controls", &["throttle", "elevator", "aileron", "rudder"]),
    ("accelerometer", &["ax", "ay", "az"]),
];

/// A column map that cannot be used: the map's file, when it came from one, and what is wrong.
///
/// Displays as `column map: FILE: PROBLEM` (the file part where there is one).
#[derive(Debug, thiserror::Error)]
#[error("column map: {}{problem}", .file.as_deref().map_or(String::new(), |f| format!("{f}: ")))]
pub struct ColumnMapError {
    /// The map's file (`--columns FILE.toml`), if it came from one.
    pub file: Option<String>,
    /// What is wrong.
    pub problem: MapProblem,
}

impl From<MapProblem> for ColumnMapError {
    fn from(problem: MapProblem) -> Self {
        Self {
            file: None,
            problem,
        }
    }
}

/// What is wrong, in a [`ColumnMapError`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MapProblem {
    /// The map's file could not be read.
    #[error("cannot read: {0}")]
    Unreadable(std::io::Error),
    /// The TOML form is not TOML, or has unknown keys: where and what, in one bounded line.
    #[error("{0}")]
    Toml(String),
    /// A delimiter that is not one character.
    #[error("delimiter `{0}` must be one character")]
    Delimiter(String),
    /// An entry of the inline form that cannot be used.
    #[error("entry `{entry}`: {error}")]
    Entry {
        /// The entry as written.
        entry: String,
        /// What is wrong with it.
        error: EntryError,
    },
    /// An entry of the TOML form's `[columns]` that cannot be used.
    #[error("columns.{quantity}: {error}")]
    Column {
        /// The quantity, as written.
        quantity: String,
        /// What is wrong with it.
        error: EntryError,
    },
    /// No time.
    #[error("no `time` (e.g. time=t_s, or time=t_us:us)")]
    NoTime,
    /// Both `down` and `height`.
    #[error("`down` and `height` both given: give one")]
    DownAndHeight,
    /// A local and a geodetic position.
    #[error("both a local position (north, east) and a geodetic one (lat, lon): give one")]
    LocalAndGeodetic,
    /// No position.
    #[error("no position: map north, east and down (or height), or lat, lon and alt")]
    NoPosition,
    /// Part of a local position.
    #[error("the position needs {} too", .0.join(", "))]
    PartialPosition(Vec<&'static str>),
    /// Part of a geodetic position.
    #[error("the geodetic position needs {} too", .0.join(", "))]
    PartialGeodetic(Vec<&'static str>),
    /// Both `alt` and `down` or `height`.
    #[error("`alt` and `down`/`height` both given: give one")]
    AltAndDown,
    /// Part of a set that comes whole.
    #[error(
        "{set} comes as a set: `{mapped}` is mapped, so map {} too",
        .missing.join(", ")
    )]
    PartialSet {
        /// The set (`attitude`, …).
        set: &'static str,
        /// A quantity of it that is mapped.
        mapped: &'static str,
        /// Those that are not.
        missing: Vec<&'static str>,
    },
}

/// What is wrong with one entry of a column map.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EntryError {
    /// Not `QUANTITY=COLUMN…`.
    #[error("not QUANTITY=COLUMN[:SCALE[:OFFSET]]")]
    NotAnEntry,
    /// A quantity not in [`QUANTITIES`].
    #[error(
        "unknown quantity `{0}` (quantities: {known})",
        known = names(QUANTITIES.iter().map(|q| q.0))
    )]
    UnknownQuantity(String),
    /// A quantity given twice.
    #[error("{0} is mapped twice")]
    Twice(&'static str),
    /// An empty column name.
    #[error("no column name")]
    NoColumn,
    /// A unit not in [`UNITS`].
    #[error(
        "unknown unit `{unit}` (units of {}: {})",
        .dimension.name(),
        .dimension.units()
    )]
    UnknownUnit {
        /// The unit as written.
        unit: String,
        /// The quantity's kind.
        dimension: Dimension,
    },
    /// A unit of another kind than the quantity.
    #[error("`{unit}` is {} but {quantity} is {}", .unit_dimension.name(), .dimension.name())]
    WrongUnit {
        /// The unit as written.
        unit: String,
        /// Its kind.
        unit_dimension: Dimension,
        /// The quantity.
        quantity: &'static str,
        /// The quantity's kind.
        dimension: Dimension,
    },
    /// A scale of 0 or not finite.
    #[error("scale `{0}` must be a finite number other than 0")]
    ZeroScale(String),
    /// A scale that is neither a unit nor a number.
    #[error("`{0}` is neither a unit nor a number")]
    NotUnitOrNumber(String),
    /// An offset that is not a finite number.
    #[error("offset `{0}` is not a finite number")]
    BadOffset(String),
}

/// Names, comma-separated.
fn names<'a>(names: impl Iterator<Item = &'a str>) -> String {
    names.collect::<Vec<_>>().join(", ")
}

/// One quantity's source.
#[derive(Clone, Debug, PartialEq)]
pub struct MapEntry {
    /// The quantity (a name of [`QUANTITIES`]).
    pub quantity: &'static str,
    /// The column, as in the header.
    pub column: String,
    /// Factor to SI.
    pub scale: f64,
    /// Added after scaling, SI.
    pub offset: f64,
    /// The unit as written (for the report), or empty.
    pub unit: String,
}

/// Which column gives which quantity (see the module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColumnMap {
    /// The entries, one per quantity.
    pub entries: Vec<MapEntry>,
    /// The cell separator (`None`: `,`, or `;` / tab when the header has no comma).
    pub delimiter: Option<char>,
}

/// The scale of `text`: a unit, a number, or `NUMBER*UNIT`; checked against the dimension.
fn parse_scale(
    text: &str,
    quantity: &'static str,
    dim: Dimension,
) -> Result<(f64, String), EntryError> {
    let text = text.trim();
    let unit = |u: &str| -> Result<f64, EntryError> {
        let (_, f, d) =
            UNITS
                .iter()
                .find(|(n, _, _)| *n == u)
                .ok_or_else(|| EntryError::UnknownUnit {
                    unit: u.to_string(),
                    dimension: dim,
                })?;
        if *d != dim {
            return Err(EntryError::WrongUnit {
                unit: u.to_string(),
                unit_dimension: *d,
                quantity,
                dimension: dim,
            });
        }
        Ok(*f)
    };
    let number = |n: &str| -> Result<f64, EntryError> {
        match n.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v != 0.0 => Ok(v),
            Ok(_) => Err(EntryError::ZeroScale(n.to_string())),
            Err(_) => Err(EntryError::NotUnitOrNumber(n.to_string())),
        }
    };
    if let Some((n, u)) = text.split_once('*') {
        return Ok((number(n)? * unit(u.trim())?, text.to_string()));
    }
    if UNITS.iter().any(|(n, _, _)| *n == text) {
        return Ok((unit(text)?, text.to_string()));
    }
    if text.parse::<f64>().is_ok() {
        return Ok((number(text)?, text.to_string()));
    }
    // Neither: say which units there are.
    unit(text).map(|f| (f, text.to_string()))
}

impl ColumnMap {
    /// The map of `--columns VALUE`: a `.toml` file's, or the inline form.
    ///
    /// # Errors
    /// An unreadable file, and everything [`parse`](Self::parse) and
    /// [`from_toml`](Self::from_toml) reject.
    pub fn from_arg(value: &str) -> Result<Self, ColumnMapError> {
        if value.trim_end().to_ascii_lowercase().ends_with(".toml") {
            let in_file = |problem| ColumnMapError {
                file: Some(value.to_string()),
                problem,
            };
            let text = wireflight_fsio::read_config_text(std::path::Path::new(value))
                .map_err(|e| in_file(MapProblem::Unreadable(e)))?;
            return Self::from_toml(&text).map_err(|e| in_file(e.problem));
        }
        Self::parse(value)
    }

    /// The inline form: `QUANTITY=COLUMN[:SCALE[:OFFSET]],…`.
    ///
    /// # Errors
    /// An entry without `=`, an unknown quantity, a quantity given twice, a bad scale or
    /// offset, a unit of the wrong kind; then what [`check`](Self::check) rejects.
    pub fn parse(spec: &str) -> Result<Self, ColumnMapError> {
        let mut map = ColumnMap::default();
        for entry in spec.split(',').map(str::trim).filter(|e| !e.is_empty()) {
            let bad = |error| MapProblem::Entry {
                entry: entry.to_string(),
                error,
            };
            let (q, rest) = entry
                .split_once('=')
                .ok_or_else(|| bad(EntryError::NotAnEntry))?;
            let mut parts = rest.splitn(3, ':');
            let column = parts.next().unwrap_or("").trim();
            let scale = parts.next();
            let offset = parts.next();
            map.add(q.trim(), column, scale, offset).map_err(bad)?;
        }
        map.check()?;
        Ok(map)
    }

    /// The TOML form (module docs).
    ///
    /// # Errors
    /// TOML syntax, unknown keys, and what [`parse`](Self::parse) rejects.
    pub fn from_toml(text: &str) -> Result<Self, ColumnMapError> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct File {
            delimiter: Option<String>,
            columns: BTreeMap<String, Source>,
        }
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Source {
            Column(String),
            Full(Full),
        }
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Full {
            column: String,
            unit: Option<String>,
            scale: Option<f64>,
            offset: Option<f64>,
        }
        let file: File = toml::from_str(text)
            .map_err(|e| MapProblem::Toml(crate::format::toml_problem(text, &e)))?;
        let mut map = ColumnMap::default();
        if let Some(d) = file.delimiter {
            let mut chars = d.chars();
            match (chars.next(), chars.next()) {
                (Some(c), None) if c != '"' && c != '\n' => map.delimiter = Some(c),
                _ => return Err(MapProblem::Delimiter(d).into()),
            }
        }
        for (q, source) in &file.columns {
            let bad = |error| MapProblem::Column {
                quantity: q.clone(),
                error,
            };
            match source {
                Source::Column(c) => map.add(q, c, None, None).map_err(bad)?,
                Source::Full(f) => {
                    let scale = match (&f.unit, f.scale) {
                        (Some(u), Some(s)) => Some(format!("{s}*{u}")),
                        (Some(u), None) => Some(u.clone()),
                        (None, Some(s)) => Some(format!("{s}")),
                        (None, None) => None,
                    };
                    let offset = f.offset.map(|o| format!("{o}"));
                    map.add(q, &f.column, scale.as_deref(), offset.as_deref())
                        .map_err(bad)?;
                }
            }
        }
        map.check()?;
        Ok(map)
    }

    fn add(
        &mut self,
        quantity: &str,
        column: &str,
        scale: Option<&str>,
        offset: Option<&str>,
    ) -> Result<(), EntryError> {
        let (name, dim, _) = QUANTITIES
            .iter()
            .find(|(n, _, _)| *n == quantity)
            .ok_or_else(|| EntryError::UnknownQuantity(quantity.to_string()))?;
        if self.entries.iter().any(|e| e.quantity == *name) {
            return Err(EntryError::Twice(name));
        }
        if column.is_empty() {
            return Err(EntryError::NoColumn);
        }
        let (scale, unit) = match scale.map(str::trim).filter(|s| !s.is_empty()) {
            Some(s) => parse_scale(s, name, *dim)?,
            None => (1.0, String::new()),
        };
        let offset = match offset.map(str::trim).filter(|s| !s.is_empty()) {
            Some(o) => match o.parse::<f64>() {
                Ok(v) if v.is_finite() => v,
                _ => return Err(EntryError::BadOffset(o.to_string())),
            },
            None => 0.0,
        };
        self.entries.push(MapEntry {
            quantity: name,
            column: column.to_string(),
            scale,
            offset,
            unit,
        });
        Ok(())
    }

    /// The entry of `quantity`.
    pub fn get(&self, quantity: &str) -> Option<&MapEntry> {
        self.entries.iter().find(|e| e.quantity == quantity)
    }

    fn has(&self, quantity: &str) -> bool {
        self.get(quantity).is_some()
    }

    /// Time and a position are mapped (local or geodetic, not both), and sets are whole.
    ///
    /// # Errors
    /// Which quantities are missing or clash.
    pub fn check(&self) -> Result<(), ColumnMapError> {
        let bad = |problem: MapProblem| Err(problem.into());
        if !self.has("time") {
            return bad(MapProblem::NoTime);
        }
        if self.has("down") && self.has("height") {
            return bad(MapProblem::DownAndHeight);
        }
        let local = ["north", "east"].iter().any(|q| self.has(q));
        let geo = ["lat", "lon", "alt"].iter().any(|q| self.has(q));
        let vertical = self.has("down") || self.has("height");
        match (local, geo) {
            (true, true) => return bad(MapProblem::LocalAndGeodetic),
            (false, false) => return bad(MapProblem::NoPosition),
            (true, false) => {
                let miss: Vec<&str> = ["north", "east"]
                    .into_iter()
                    .filter(|q| !self.has(q))
                    .chain((!vertical).then_some("down (or height)"))
                    .collect();
                if !miss.is_empty() {
                    return bad(MapProblem::PartialPosition(miss));
                }
            }
            (false, true) => {
                let miss: Vec<&str> = ["lat", "lon"]
                    .into_iter()
                    .filter(|q| !self.has(q))
                    .chain((!self.has("alt") && !vertical).then_some("alt (or height)"))
                    .collect();
                if !miss.is_empty() {
                    return bad(MapProblem::PartialGeodetic(miss));
                }
                if self.has("alt") && vertical {
                    return bad(MapProblem::AltAndDown);
                }
            }
        }
        for (set, names) in SETS {
            let have: Vec<&str> = names.iter().copied().filter(|q| self.has(q)).collect();
            if !have.is_empty() && have.len() < names.len() {
                let missing: Vec<&str> = names.iter().copied().filter(|q| !self.has(q)).collect();
                return bad(MapProblem::PartialSet {
                    set,
                    mapped: have[0],
                    missing,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
