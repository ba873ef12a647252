//! Reading flight-data CSV: [`read`] a file or [`parse`] text, in either dialect (the format
//! is described in [`super`]).
//!
//! [`parse`] runs four named steps, one function each, in file order: [`read_metadata`] (the
//! `#` lines before the header), [`Header::parse`] (column names, dialect, required columns),
//! [`read_rows`] (cells to SI numbers, increasing times) and [`assemble`] (numbers to
//! [`FlightData`] channels, JSBSim's geodetic position to NED). Reading is kept apart from
//! writing and from the data types because it is the part that checks untrusted input: every
//! rule and every error message of the reader is in this file.

use std::collections::HashMap;
use std::f64::consts::TAU;
use std::path::Path;

use glam::DVec3;

use super::columns::{
    column_label, jsbsim_column, native_column, Dialect, Quantity, ATTITUDE, CONTROLS, GROUPS,
    N_QUANTITIES, QUANTITIES,
};
use super::{DataError, DataErrorKind, FlightData, Metadata, EARTH_RADIUS_M};
use crate::sampling::{Channel, Sampling};
use crate::{Controls, VehicleKind};
use wireflight_geometry::euler::EulerZyx;

/// Reads a flight-data file (either dialect; see the module docs) and derives missing
/// channels ([`FlightData::derive_missing`]).
///
/// # Errors
/// [`DataError`] naming the file, line and column: unreadable or non-UTF-8 file, and
/// everything [`parse`] rejects.
pub fn read(path: &Path) -> Result<FlightData, DataError> {
    let file = path.display().to_string();
    let bytes = wireflight_fsio::read_bytes(path).map_err(|e| DataError {
        file: file.clone(),
        line: None,
        column: None,
        kind: DataErrorKind::Unreadable(e),
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        DataError {
            file: file.clone(),
            line: Some(line_of(good)),
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
/// cells are separated by commas and trimmed; unknown columns are ignored; a metadata key the
/// reader uses (`vehicle`, `aircraft`, the origin, `mass_kg`, `reference_area_m2`, `source`)
/// given twice is an error, other keys are kept in file order.
///
/// # Errors
/// [`DataError`]: bad metadata values, no header, no rows, duplicate or missing required
/// columns (time and position always; attitude and controls for `vehicle: fixed-wing`; the
/// rest of a set such as `roll/pitch/yaw` once one of it is present), non-numeric or
/// non-finite cells in columns that are read, rows of the wrong length, times that do not
/// increase.
pub fn parse(text: &str, name_for_errors: &str) -> Result<FlightData, DataError> {
    let errors = Errors {
        file: name_for_errors,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text_lines(text).enumerate().map(|(i, l)| (i + 1, l.trim()));

    let (meta, header_line, header_text) = read_metadata(&mut lines, &errors)?;
    let header = Header::parse(header_line, header_text, meta.vehicle, &errors)?;
    let mut values = read_rows(lines, &header, &errors)?;
    values.fill(&header, &errors)?;
    let mut data = assemble(meta, &header, values);
    data.derive_missing();
    Ok(data)
}

/// The lines of `text`, ended by `\n`, `\r\n` or a lone `\r` (old Mac files and some
/// loggers end lines with CR alone; read as one line they would give a confusing row-length
/// error), without their ends; like [`str::lines`] otherwise (no empty line after a final end).
pub(super) fn text_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = text;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let Some(i) = rest.find(['\r', '\n']) else {
            return Some(std::mem::take(&mut rest));
        };
        let line = &rest[..i];
        let end = if rest[i..].starts_with("\r\n") { 2 } else { 1 };
        rest = &rest[i + end..];
        Some(line)
    })
}

/// The 1-based line, as [`text_lines`] counts them, of the byte just after `before`.
pub(super) fn line_of(before: &[u8]) -> usize {
    let lone_crs = before
        .iter()
        .enumerate()
        .filter(|&(i, &b)| b == b'\r' && before.get(i + 1) != Some(&b'\n'))
        .count();
    before.iter().filter(|&&b| b == b'\n').count() + lone_crs + 1
}

/// Makes the errors of one parse, all naming the same file.
struct Errors<'a> {
    /// The file (the name given to [`parse`]).
    file: &'a str,
}

impl Errors<'_> {
    /// An error on 1-based `line`, in `column` when one is involved.
    fn at(&self, line: usize, column: Option<&str>, kind: DataErrorKind) -> DataError {
        DataError {
            file: self.file.to_string(),
            line: Some(line),
            column: column.map(str::to_string),
            kind,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Step 1: metadata

/// The `# key: value` lines (and blank lines and comments) before the header. Returns the
/// metadata and the header: its line number and its text.
///
/// # Errors
/// A bad metadata value; [`DataErrorKind::Empty`] when no header follows.
fn read_metadata<'t>(
    lines: &mut impl Iterator<Item = (usize, &'t str)>,
    errors: &Errors,
) -> Result<(Metadata, usize, &'t str), DataError> {
    let mut meta = Metadata::default();
    let mut seen = Vec::new();
    let mut last_line = 0;
    for (n, l) in lines {
        last_line = n;
        if l.is_empty() {
            continue;
        }
        if let Some(rest) = l.strip_prefix('#') {
            parse_metadata(rest, &mut meta, (n, &mut seen)).map_err(|k| errors.at(n, None, k))?;
            continue;
        }
        return Ok((meta, n, l));
    }
    Err(errors.at(last_line.max(1), None, DataErrorKind::Empty))
}

/// One metadata line (after the `#`), on `line`; `seen` holds the keys the reader uses that
/// earlier lines gave, with their lines.
///
/// # Errors
/// A bad value, or a key the reader uses given a second time (which was meant is not known).
pub(super) fn parse_metadata(
    rest: &str,
    meta: &mut Metadata,
    (line, seen): (usize, &mut Vec<(String, usize)>),
) -> Result<(), DataErrorKind> {
    let Some((key, value)) = rest.split_once(':') else {
        return Ok(()); // a comment
    };
    let (key, value) = (key.trim(), value.trim());
    if key.is_empty() {
        return Ok(());
    }
    const USED: [&str; 8] = [
        "vehicle",
        "aircraft",
        "latitude_deg",
        "longitude_deg",
        "altitude_m",
        "mass_kg",
        "reference_area_m2",
        "source",
    ];
    if USED.contains(&key) {
        if let Some((_, first_line)) = seen.iter().find(|(k, _)| k == key) {
            return Err(DataErrorKind::RepeatedMetadata {
                key: key.to_string(),
                first_line: *first_line,
            });
        }
        seen.push((key.to_string(), line));
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
        "vehicle" => {
            meta.vehicle = Some(
                value
                    .parse::<VehicleKind>()
                    .map_err(|e| bad(e.to_string()))?,
            )
        }
        "aircraft" => meta.aircraft = Some(value.to_string()),
        "latitude_deg" | "longitude_deg" | "altitude_m" => {
            let v = number()?;
            crate::check_origin_field(key, v).map_err(|e| bad(e.to_string()))?;
            match key {
                "latitude_deg" => meta.latitude_deg = Some(v),
                "longitude_deg" => meta.longitude_deg = Some(v),
                _ => meta.altitude_m = Some(v),
            }
        }
        "mass_kg" => meta.mass_kg = Some(number()?),
        "reference_area_m2" => meta.reference_area_m2 = Some(number()?),
        "source" => meta.source = Some(value.to_string()),
        _ => meta.other.push((key.to_string(), value.to_string())),
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Step 2: header

/// Where a quantity is read from.
#[derive(Clone, Copy, Debug)]
struct Column {
    /// 0-based position in the header.
    index: usize,
    /// Factor to SI units (radians for angles).
    scale: f64,
    /// Among JSBSim columns giving the same quantity, lower wins (always 0 for wireflight).
    priority: usize,
}

/// The header row understood: the column names, the dialect, and the column of each quantity.
struct Header<'t> {
    /// Its 1-based line number.
    line: usize,
    /// The column names as written, quotes and surrounding spaces removed.
    names: Vec<&'t str>,
    /// Which of the two dialects the names are in.
    dialect: Dialect,
    /// Per quantity (indexed by [`Quantity`]), the column it is read from, if any.
    columns: [Option<Column>; N_QUANTITIES],
}

impl<'t> Header<'t> {
    /// Splits the header row at `line`, tells its dialect, maps its columns to quantities and
    /// checks that the required columns are there (more of them for a fixed-wing `vehicle`).
    ///
    /// # Errors
    /// Duplicate columns, then missing required ones.
    fn parse(
        line: usize,
        text: &'t str,
        vehicle: Option<VehicleKind>,
        errors: &Errors,
    ) -> Result<Self, DataError> {
        let count = text.matches(',').count() + 1;
        if count > crate::MAX_COLUMNS {
            return Err(errors.at(line, None, DataErrorKind::TooManyColumns { count }));
        }
        let names = split_header(text);
        let dialect = Dialect::detect(&names);
        let columns = map_columns(line, &names, dialect, errors)?;
        let header = Header {
            line,
            names,
            dialect,
            columns,
        };
        header.check_required(vehicle, errors)?;
        Ok(header)
    }

    /// True when some column gives `q`.
    fn has(&self, q: Quantity) -> bool {
        self.columns[q as usize].is_some()
    }

    /// The labels (as in errors) of those of `quantities` that no column gives.
    fn missing(&self, quantities: &[Quantity]) -> Vec<String> {
        quantities
            .iter()
            .filter(|q| !self.has(**q))
            .map(|q| column_label(self.dialect, *q).to_string())
            .collect()
    }

    /// Time and position always; attitude and controls for a fixed-wing vehicle; the rest of
    /// a set (such as roll/pitch/yaw) once one of it is present.
    fn check_required(
        &self,
        vehicle: Option<VehicleKind>,
        errors: &Errors,
    ) -> Result<(), DataError> {
        let missing_column = |names: Vec<String>, why: String| {
            errors.at(self.line, None, DataErrorKind::MissingColumn { names, why })
        };
        let required: &[Quantity] = match self.dialect {
            Dialect::Wireflight => &[
                Quantity::Time,
                Quantity::North,
                Quantity::East,
                Quantity::Down,
            ],
            Dialect::Jsbsim => &[Quantity::Time, Quantity::Lat, Quantity::Lon, Quantity::Alt],
        };
        let miss = self.missing(required);
        if !miss.is_empty() {
            let why = match self.dialect {
                Dialect::Wireflight => "every flight-data file needs time and NED position",
                Dialect::Jsbsim => {
                    "JSBSim output needs Time and the position (latitude, longitude, height above sea level)"
                }
            };
            return Err(missing_column(miss, why.to_string()));
        }
        if vehicle == Some(VehicleKind::FixedWing) {
            let miss = self.missing(&[&ATTITUDE[..], &CONTROLS[..]].concat());
            if !miss.is_empty() {
                return Err(missing_column(
                    miss,
                    "vehicle fixed-wing needs attitude and controls".to_string(),
                ));
            }
        }
        for (group, quantities) in GROUPS {
            let miss = self.missing(quantities);
            if !miss.is_empty() && miss.len() < quantities.len() {
                let present = quantities
                    .iter()
                    .find(|q| self.has(**q))
                    .and_then(|q| self.columns[*q as usize]);
                let present = present.map(|c| self.names[c.index]).unwrap_or_default();
                return Err(missing_column(
                    miss,
                    format!("{group} columns come as a set and `{present}` is present"),
                ));
            }
        }
        Ok(())
    }
}

/// The cells of a header row: trimmed, with surrounding double quotes removed.
fn split_header(text: &str) -> Vec<&str> {
    text.split(',')
        .map(|c| {
            let c = c.trim();
            c.strip_prefix('"')
                .and_then(|c| c.strip_suffix('"'))
                .unwrap_or(c)
                .trim()
        })
        .collect()
}

/// The column of each quantity. Unknown and empty names are ignored. Where several JSBSim
/// columns give one quantity, the one listed first in [`super::JSBSIM_COLUMNS`] is used.
///
/// # Errors
/// A name given twice, or two columns giving one quantity (in the wireflight dialect, or at
/// the same JSBSim priority).
fn map_columns(
    line: usize,
    names: &[&str],
    dialect: Dialect,
    errors: &Errors,
) -> Result<[Option<Column>; N_QUANTITIES], DataError> {
    let duplicate = |name: &str, first: usize| {
        errors.at(
            line,
            Some(name),
            DataErrorKind::DuplicateColumn {
                first: names[first].to_string(),
                first_index: first + 1,
            },
        )
    };
    let mut columns: [Option<Column>; N_QUANTITIES] = [None; N_QUANTITIES];
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (index, &name) in names.iter().enumerate() {
        if name.is_empty() {
            continue;
        }
        if let Some(&first) = seen.get(name) {
            return Err(duplicate(name, first));
        }
        seen.insert(name, index);
        let mapped = match dialect {
            Dialect::Wireflight => native_column(name).map(|(q, s)| (q, s, 0)),
            Dialect::Jsbsim => jsbsim_column(name),
        };
        let Some((q, scale, priority)) = mapped else {
            continue;
        };
        match columns[q as usize] {
            Some(first) if dialect == Dialect::Wireflight || first.priority == priority => {
                return Err(duplicate(name, first.index));
            }
            Some(first) if first.priority < priority => {}
            _ => {
                columns[q as usize] = Some(Column {
                    index,
                    scale,
                    priority,
                })
            }
        }
    }
    Ok(columns)
}

// ---------------------------------------------------------------------------------------------
// Step 3: rows

/// The values read, per quantity (indexed by [`Quantity`]), in SI units; empty for quantities
/// no column gives. A row whose cell was empty holds a placeholder until it is filled in
/// ([`Values::fill`]), and `sampled` says which rows held a value.
struct Values {
    /// Per quantity, a value per row.
    values: [Vec<f64>; N_QUANTITIES],
    /// Per quantity, whether each row's cell held a value.
    sampled: [Vec<bool>; N_QUANTITIES],
}

impl Values {
    /// Moves out the values of `q`.
    fn take(&mut self, q: Quantity) -> Vec<f64> {
        std::mem::take(&mut self.values[q as usize])
    }

    /// The rows where `q`'s cell held a value.
    fn sampled(&self, q: Quantity) -> &[bool] {
        &self.sampled[q as usize]
    }

    /// Fills each empty cell of a read quantity from its column's values around it: controls
    /// are held (an empty control cell means "unchanged"; before the first value, the first
    /// value), attitude is left to [`assemble`] (angles go the short way round), the rest is
    /// linear in time and held at the ends.
    fn fill(&mut self, header: &Header, errors: &Errors) -> Result<(), DataError> {
        let time = self.values[Quantity::Time as usize].clone();
        for q in QUANTITIES {
            let Some(column) = header.columns[q as usize] else {
                continue;
            };
            let sampled = &self.sampled[q as usize];
            if sampled.iter().all(|&s| s) {
                continue;
            }
            if !sampled.iter().any(|&s| s) {
                let name = header.names[column.index];
                return Err(errors.at(header.line, Some(name), DataErrorKind::NoSamples));
            }
            let values = &mut self.values[q as usize];
            if CONTROLS.contains(&q) {
                crate::sampling::fill_held(sampled, values);
            } else if !ATTITUDE.contains(&q) {
                crate::sampling::fill_linear(&time, sampled, values);
            }
        }
        Ok(())
    }

    /// Moves out three quantities as vectors.
    fn take_vec3(&mut self, [x, y, z]: [Quantity; 3]) -> Vec<DVec3> {
        let (x, y, z) = (self.take(x), self.take(y), self.take(z));
        x.into_iter()
            .zip(y)
            .zip(z)
            .map(|((x, y), z)| DVec3::new(x, y, z))
            .collect()
    }
}

/// The sets of columns sampled together: a row gives all of a set or none of it.
const SAMPLED_TOGETHER: [(&str, &[Quantity]); 6] = [
    (
        "position",
        &[Quantity::North, Quantity::East, Quantity::Down],
    ),
    (
        "geodetic position",
        &[Quantity::Lat, Quantity::Lon, Quantity::Alt],
    ),
    ("attitude", &ATTITUDE),
    ("NED velocity", &[Quantity::Vn, Quantity::Ve, Quantity::Vd]),
    ("body velocity", &[Quantity::U, Quantity::V, Quantity::W]),
    ("body rates", &[Quantity::P, Quantity::Q, Quantity::R]),
];

/// The data rows after the header: each cell of a column that gives a quantity parsed and
/// scaled to SI. Blank and `#` lines are skipped; cells of unknown columns are not parsed.
///
/// # Errors
/// A row of the wrong length, a cell that is not a finite number, a time not after the
/// previous row's, no rows at all.
fn read_rows<'t>(
    lines: impl Iterator<Item = (usize, &'t str)>,
    header: &Header,
    errors: &Errors,
) -> Result<Values, DataError> {
    let names = &header.names;
    let used: Vec<(usize, Column)> = header
        .columns
        .iter()
        .enumerate()
        .filter_map(|(q, c)| c.map(|c| (q, c)))
        .collect();
    let time_col = header.columns[Quantity::Time as usize].map_or(0, |c| c.index);
    let mut values: [Vec<f64>; N_QUANTITIES] = std::array::from_fn(|_| Vec::new());
    let mut sampled: [Vec<bool>; N_QUANTITIES] = std::array::from_fn(|_| Vec::new());
    let mut cells: Vec<&str> = Vec::with_capacity(names.len());
    let mut prev_time: Option<(f64, usize)> = None;
    for (n, l) in lines {
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        cells.clear();
        cells.extend(l.split(','));
        if cells.len() != names.len() {
            return Err(errors.at(
                n,
                None,
                DataErrorKind::RowLength {
                    expected: names.len(),
                    found: cells.len(),
                },
            ));
        }
        for &(q, column) in &used {
            let empty = cells[column.index].trim().is_empty();
            sampled[q].push(!empty);
            if empty {
                if QUANTITIES[q] == Quantity::Time {
                    return Err(errors.at(n, Some(names[column.index]), DataErrorKind::EmptyTime));
                }
                values[q].push(0.0);
                continue;
            }
            let v = parse_cell(cells[column.index])
                .map_err(|k| errors.at(n, Some(names[column.index]), k))?
                * column.scale;
            let (lo, hi, range) = QUANTITIES[q].range();
            if !(lo..=hi).contains(&v) {
                let value = shown_cell(cells[column.index].trim());
                let kind = DataErrorKind::OutOfRange { value, range };
                return Err(errors.at(n, Some(names[column.index]), kind));
            }
            values[q].push(v);
        }
        check_sampled_together(&sampled, header)
            .map_err(|(column, kind)| errors.at(n, Some(column), kind))?;
        let t = values[Quantity::Time as usize]
            .last()
            .copied()
            .unwrap_or(0.0);
        if let Some((previous, previous_line)) = prev_time {
            if t <= previous {
                return Err(errors.at(
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
    if values[Quantity::Time as usize].is_empty() {
        return Err(errors.at(header.line, None, DataErrorKind::NoRows));
    }
    Ok(Values { values, sampled })
}

/// In the row just read (the last of each `sampled`), every set of
/// [`SAMPLED_TOGETHER`] columns is all given or all empty; else the first empty column and
/// the error.
fn check_sampled_together<'h>(
    sampled: &[Vec<bool>; N_QUANTITIES],
    header: &Header<'h>,
) -> Result<(), (&'h str, DataErrorKind)> {
    for (channel, set) in SAMPLED_TOGETHER {
        let cells: Vec<(Quantity, bool)> = set
            .iter()
            .filter_map(|&q| sampled[q as usize].last().map(|&s| (q, s)))
            .collect();
        let given = cells.iter().find(|(_, s)| *s);
        let empty = cells.iter().find(|(_, s)| !*s);
        if let (Some(&(given, _)), Some(&(empty, _))) = (given, empty) {
            let name =
                |q: Quantity| header.columns[q as usize].map_or("", |c| header.names[c.index]);
            let kind = DataErrorKind::PartlyEmpty {
                channel,
                given: name(given).to_string(),
            };
            return Err((name(empty), kind));
        }
    }
    Ok(())
}

/// One cell as a finite number.
fn parse_cell(cell: &str) -> Result<f64, DataErrorKind> {
    let c = cell.trim();
    match c.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(DataErrorKind::NonFinite {
            value: crate::format::excerpt(c),
        }),
        Err(_) => Err(DataErrorKind::NonNumeric {
            value: crate::format::excerpt(c),
        }),
    }
}

// ---------------------------------------------------------------------------------------------
// Step 4: assembly

/// The values as [`FlightData`] channels (derived channels not yet filled in). A channel is
/// present when its columns are. JSBSim's geodetic position becomes local NED
/// ([`flat_earth_ned`]) and the metadata's origin is set to the first sample.
fn assemble(mut meta: Metadata, header: &Header, mut values: Values) -> FlightData {
    use Quantity as Q;
    let sampling = sampling_of(header, &values);
    let attitude_sampled = values.sampled(Q::Roll).to_vec();
    let time = values.take(Q::Time);
    let pos_ned = match header.dialect {
        Dialect::Wireflight => values.take_vec3([Q::North, Q::East, Q::Down]),
        Dialect::Jsbsim => {
            let lat = values.take(Q::Lat);
            let lon = values.take(Q::Lon);
            let alt = values.take(Q::Alt);
            meta.latitude_deg = Some(lat[0].to_degrees());
            meta.longitude_deg = Some(lon[0].to_degrees());
            meta.altitude_m = Some(alt[0]);
            if meta.source.is_none() {
                meta.source = Some("JSBSim CSV output".to_string());
            }
            flat_earth_ned(&lat, &lon, &alt)
        }
    };
    let mut opt_vec3 = |qs: [Quantity; 3]| header.has(qs[0]).then(|| values.take_vec3(qs));
    let attitude = opt_vec3([Q::Yaw, Q::Pitch, Q::Roll]).map(|v| {
        let mut a: Vec<EulerZyx> = v
            .into_iter()
            .map(|a| EulerZyx::new(a.x, a.y, a.z))
            .collect();
        crate::sampling::fill_attitude(&time, &attitude_sampled, &mut a);
        a
    });
    let vel_ned = opt_vec3([Q::Vn, Q::Ve, Q::Vd]);
    let vel_body = opt_vec3([Q::U, Q::V, Q::W]);
    let rates_body = opt_vec3([Q::P, Q::Q, Q::R]);
    let accel_body = opt_vec3([Q::Ax, Q::Ay, Q::Az]);
    let airspeed = header.has(Q::Airspeed).then(|| values.take(Q::Airspeed));
    let controls = header.has(Q::Throttle).then(|| {
        let t = values.take(Q::Throttle);
        let e = values.take(Q::Elevator);
        let a = values.take(Q::Aileron);
        let r = values.take(Q::Rudder);
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
    FlightData {
        meta,
        time,
        pos_ned,
        attitude,
        vel_ned,
        vel_body,
        rates_body,
        airspeed,
        accel_body,
        controls,
        derived: Vec::new(),
        sampling,
    }
}

/// Which rows are samples of each channel: those where its cells held values.
fn sampling_of(header: &Header, values: &Values) -> Sampling {
    use Quantity as Q;
    let position = match header.dialect {
        Dialect::Wireflight => Q::North,
        Dialect::Jsbsim => Q::Lat,
    };
    let mut sampling = Sampling::all();
    for (channel, q) in [
        (Channel::Position, position),
        (Channel::Velocity, Q::Vn),
        (Channel::Attitude, Q::Roll),
        (Channel::Rates, Q::P),
        (Channel::Airspeed, Q::Airspeed),
        (Channel::Accelerometer, Q::Ax),
    ] {
        if header.has(q) {
            sampling.set(channel, values.sampled(q));
        }
    }
    sampling
}

/// Geodetic positions (radians, radians, metres; at least one sample) as local NED about the
/// first, on a flat earth of radius [`EARTH_RADIUS_M`]: north = (lat − lat0)·R,
/// east = (lon − lon0)·R·cos lat0 (the longitude difference taken across the antimeridian
/// where shorter), down = −(h − h0).
pub(super) fn flat_earth_ned(lat: &[f64], lon: &[f64], alt: &[f64]) -> Vec<DVec3> {
    let (lat0, lon0, h0) = (lat[0], lon[0], alt[0]);
    let coslat0 = lat0.cos();
    lat.iter()
        .zip(lon)
        .zip(alt)
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

/// A cell as an error message quotes it: as written, unless it is too long to read (a
/// 300-digit number), then as its value to four significant digits (`-2.348e299`).
fn shown_cell(cell: &str) -> String {
    const LONGEST: usize = 24;
    if cell.chars().count() <= LONGEST {
        return cell.to_string();
    }
    match cell.parse::<f64>() {
        Ok(v) => format!("{v:.3e}"),
        Err(_) => format!("{}…", cell.chars().take(LONGEST).collect::<String>()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_cells_are_quoted_short() {
        assert_eq!(shown_cell("1e300"), "1e300");
        let long = format!("-2{}", "3".repeat(299));
        assert_eq!(shown_cell(&long), "-2.333e299");
        assert_eq!(shown_cell(&"x".repeat(30)), format!("{}…", "x".repeat(24)));
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
        // A key the reader uses, given twice: which was meant is not known.
        let e = parse("# aircraft: a\n# note: x\n# aircraft: b\n", "m.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "m.csv: line 3: metadata `aircraft` is given twice (first on line 1): give it once"
        );
        // Other keys are kept, in file order.
        let d = parse(
            "# note: a\n# note: b\ntime_s,north_m,east_m,down_m\n0,0,0,0\n",
            "m.csv",
        )
        .unwrap();
        assert_eq!(d.meta.other.len(), 2);
    }

    #[test]
    fn a_lone_cr_ends_a_line() {
        for end in ["\r", "\r\n", "\n", "\n\r"] {
            let text = [
                "# source: x",
                "time_s,north_m,east_m,down_m",
                "0,0,0,0",
                "1,0,0,x",
            ]
            .join(end);
            let e = parse(&text, "c.csv").unwrap_err();
            assert!(
                e.to_string().contains("not a number: `x`") && e.column.is_some(),
                "{end:?}: {e}"
            );
            let text = ["time_s,north_m,east_m,down_m", "0,0,0,0", "1,0,0,1", ""].join(end);
            assert_eq!(parse(&text, "c.csv").unwrap().len(), 2, "{end:?}");
        }
        let lines: Vec<&str> = text_lines("a\rb\r\nc\n\rd\r").collect();
        assert_eq!(lines, ["a", "b", "c", "", "d"]);
        // The line of a bad byte is counted the same way.
        assert_eq!(line_of(b"a\rb\r\nc\n\rd\r"), 6);
        assert_eq!(line_of(b"a\rb\r\nc\n\rd"), 5);
        assert_eq!(line_of(b""), 1);
    }

    #[test]
    fn accelerometer_columns_come_as_a_set_within_fifty_g() {
        let head = "time_s,north_m,east_m,down_m,ax_mps2,ay_mps2,az_mps2\n";
        let d = parse(
            &format!("{head}0,0,0,0,0.5,-0.25,-9.81\n1,1,0,0,0,0,-9.8\n"),
            "a.csv",
        )
        .unwrap();
        let a = d.accel_body.as_ref().unwrap();
        assert_eq!(a[0], DVec3::new(0.5, -0.25, -9.81));
        assert_eq!(a.len(), 2);
        // Without the columns there is no accelerometer (it is never derived).
        let d = parse("time_s,north_m,east_m,down_m\n0,0,0,0\n", "a.csv").unwrap();
        assert!(d.accel_body.is_none());
        // Part of the set: the missing columns named, on the header's line.
        let e = parse(
            "# vehicle: point-mass\ntime_s,north_m,east_m,down_m,ax_mps2,az_mps2\n0,0,0,0,0,0\n",
            "p.csv",
        )
        .unwrap_err();
        assert_eq!(e.line, Some(2));
        let msg = e.to_string();
        assert!(
            msg.starts_with("p.csv: line 2: missing required column ay_mps2: accelerometer"),
            "{msg}"
        );
        // Not finite, and beyond 50 g: the file, line and column.
        for (cell, want) in [
            ("NaN", "not a finite number: `NaN`"),
            ("inf", "not a finite number: `inf`"),
            (
                "-491",
                "`-491` is outside the range of a flight: ±490.3 m/s² (50 g)",
            ),
        ] {
            let text = format!("{head}0,0,0,0,0,0,-9.8\n1,0,0,0,0,{cell},-9.8\n");
            let e = parse(&text, "r.csv").unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("r.csv: line 3, column `ay_mps2`: {want}")
            );
        }
        let text = format!("{head}0,0,0,0,0,0,490\n");
        assert!(parse(&text, "r.csv").is_ok());
    }

    /// A log with navigation at 5 Hz, attitude at 50 Hz and rates at 250 Hz, each at its
    /// own times (the rows are the union of them), as a CSV with empty cells.
    fn multi_rate_csv() -> String {
        let mut s = String::from(
            "# vehicle: fixed-wing\ntime_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,\
             p_dps,q_dps,r_dps,throttle,elevator_deg,aileron_deg,rudder_deg\n",
        );
        for k in 0..=250 {
            let t = f64::from(k) * 0.004;
            let cell = |on: bool, v: String| if on { v } else { String::new() };
            let nav = k % 50 == 0;
            let att = k % 5 == 0;
            let yaw = 170.0 + 40.0 * t; // through ±180°
            s += &format!(
                "{t},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                cell(nav, format!("{}", 25.0 * t)),
                cell(nav, format!("{}", 0.5 * t)),
                cell(nav, "-200".into()),
                cell(att, "0".into()),
                cell(att, "2".into()),
                cell(
                    att,
                    format!("{}", if yaw > 180.0 { yaw - 360.0 } else { yaw })
                ),
                "0",
                "0",
                "40",
                cell(k == 0, "0.5".into()),
                cell(
                    k == 0 || k == 100,
                    if k == 100 { "-3" } else { "-2" }.into()
                ),
                cell(k == 0, "0".into()),
                cell(k == 0, "0".into()),
            );
        }
        s
    }

    #[test]
    fn channels_at_their_own_rates_are_read_at_their_own_times() {
        let d = parse(&multi_rate_csv(), "m.csv").unwrap();
        assert_eq!(d.len(), 251);
        let s = &d.sampling;
        assert_eq!(s.count(Channel::Position, d.len()), 6);
        assert_eq!(s.count(Channel::Attitude, d.len()), 51);
        assert_eq!(s.count(Channel::Rates, d.len()), 251);
        assert!((s.rate_hz(Channel::Position, &d.time).unwrap() - 5.0).abs() < 1e-9);
        assert!((s.rate_hz(Channel::Attitude, &d.time).unwrap() - 50.0).abs() < 1e-9);
        // Every sample is where its file put it; between them, filled in and not a sample.
        assert!(s.at(Channel::Position, 50) && !s.at(Channel::Position, 51));
        assert_eq!(d.pos_ned[50], DVec3::new(5.0, 0.1, -200.0));
        let mid = d.pos_ned[75];
        assert!(
            (mid.x - 7.5).abs() < 1e-9 && (mid.z + 200.0).abs() < 1e-12,
            "{mid}"
        );
        // Attitude goes the short way through ±180°, not back round through 0.
        let a = d.attitude.as_ref().unwrap();
        assert!(a[57].yaw.abs() > 3.0, "{:?}", a[57]);
        // An empty control cell holds the last value.
        let c = d.controls.as_ref().unwrap();
        assert!((c[99].elevator.to_degrees() + 2.0).abs() < 1e-12);
        assert!((c[150].elevator.to_degrees() + 3.0).abs() < 1e-12);
        // The velocity derived from 5 Hz positions is the positions' own slope.
        let v = d.vel_ned.as_ref().unwrap();
        assert!(d.is_derived(crate::DERIVED_VEL_NED));
        assert!((v[125].x - 25.0).abs() < 1e-6, "{}", v[125]);
    }

    #[test]
    fn a_multi_rate_file_round_trips_with_no_sample_invented() {
        let d = parse(&multi_rate_csv(), "m.csv").unwrap();
        let text = crate::to_csv_string(&d);
        let nav_rows = text
            .lines()
            .filter(|l| l.split(',').nth(1) != Some(""))
            .count();
        assert_eq!(
            nav_rows,
            6 + 2,
            "header, metadata and the six samples: {text:.300}"
        );
        let back = parse(&text, "back.csv").unwrap();
        assert_eq!(back.sampling, d.sampling);
        assert_eq!(back.time, d.time);
        assert_eq!(back.pos_ned, d.pos_ned);
    }

    #[test]
    fn empty_cells_are_checked() {
        let head = "time_s,north_m,east_m,down_m,airspeed_mps\n";
        let e = parse(&format!("{head}0,0,0,0,1\n,1,0,0,1\n"), "e.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "e.csv: line 3, column `time_s`: empty: every row needs its time"
        );
        let e = parse(&format!("{head}0,0,0,0,1\n1,1,,0,1\n"), "e.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "e.csv: line 3, column `east_m`: empty while `north_m` has a value: the columns \
             of a channel (position) are sampled together"
        );
        let e = parse(&format!("{head}0,0,0,0,\n1,1,0,0,\n"), "e.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "e.csv: line 1, column `airspeed_mps`: no samples: every cell is empty (leave the \
             column out)"
        );
        let d = parse(&format!("{head}0,0,0,0,\n1,1,0,0,2\n2,,,,3\n"), "e.csv").unwrap();
        assert_eq!(d.airspeed.as_deref(), Some(&[2.0, 2.0, 3.0][..]));
        assert_eq!(d.pos_ned[2], DVec3::new(1.0, 0.0, 0.0));
        assert!(!d.sampling.at(Channel::Airspeed, 0) && !d.sampling.at(Channel::Position, 2));
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
