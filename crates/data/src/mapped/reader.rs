//! Reading a CSV through a [`ColumnMap`]: the file bounded and checked for UTF-8, then every
//! mapped column parsed, converted to the program's units and checked, with errors naming the
//! file, line and column.

use std::path::Path;

use glam::DVec3;

use super::ColumnMap;
use crate::columns::Quantity;
use crate::read::{flat_earth_ned, line_of, parse_metadata, text_lines};
use crate::report::ImportReport;
use crate::sampling::{fill_attitude, fill_held, fill_linear};
use crate::{Channel, Controls, DataError, DataErrorKind, FlightData, Metadata};
use wireflight_geometry::euler::EulerZyx;

/// A CSV that cannot be read through its column map.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MappedError {
    /// What the project's CSV reader would say: the file, the line, the column, the problem.
    #[error(transparent)]
    Data(#[from] DataError),
    /// Latitudes beyond ±90° once scaled (degrees mapped as radians).
    #[error(
        "{file}: line {line}, column `{column}`: latitude {radians} rad is beyond ±90° \
         (degrees? map it as lat={column}:deg)"
    )]
    Latitude {
        /// The file.
        file: String,
        /// The 1-based line (metadata and blank lines count).
        line: usize,
        /// The latitude's column.
        column: String,
        /// The latitude, rad.
        radians: f64,
    },
}

/// Reads a CSV file through `map` (derived channels filled in) and says what was found.
///
/// # Errors
/// [`DataError`]s naming the file, line and column: unreadable or non-UTF-8 file, no header,
/// a mapped column missing from the header, non-numeric or non-finite cells, values outside
/// the ranges of the project's CSV once scaled (positions ±1e8 m, times ±1e9 s, …: the one
/// table, `Quantity::range`), rows of the wrong length, times that do not increase; latitudes
/// beyond ±90°.
pub fn read(path: &Path, map: &ColumnMap) -> Result<(FlightData, ImportReport), MappedError> {
    let file = path.display().to_string();
    let whole = |kind| DataError {
        file: file.clone(),
        line: None,
        column: None,
        kind,
    };
    // The size limit is --max-input-mb's, applied by the bounded read.
    let bytes =
        wireflight_fsio::read_bytes(path).map_err(|e| whole(DataErrorKind::Unreadable(e)))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        DataError {
            line: Some(line_of(good)),
            ..whole(DataErrorKind::NotUtf8)
        }
    })?;
    parse(&text, &file, map)
}

/// [`read`] on text; `file` names it in errors.
///
/// # Errors
/// As [`read`], less the reading.
pub fn parse(
    text: &str,
    file: &str,
    map: &ColumnMap,
) -> Result<(FlightData, ImportReport), MappedError> {
    let at = |line: usize, column: Option<&str>, kind| {
        MappedError::Data(DataError {
            file: file.to_string(),
            line: Some(line),
            column: column.map(str::to_string),
            kind,
        })
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text_lines(text).enumerate().map(|(i, l)| (i + 1, l.trim()));
    // Metadata, then the header.
    let mut seen = Vec::new();
    let mut meta = Metadata::default();
    let mut header = None;
    let mut last = 1;
    for (n, l) in lines.by_ref() {
        last = n;
        if l.is_empty() {
            continue;
        }
        if let Some(rest) = l.strip_prefix('#') {
            parse_metadata(rest, &mut meta, (n, &mut seen)).map_err(|k| at(n, None, k))?;
            continue;
        }
        header = Some((n, l));
        break;
    }
    let (header_line, header_text) = header.ok_or_else(|| at(last, None, DataErrorKind::Empty))?;
    let delimiter = map.delimiter.unwrap_or_else(|| {
        if header_text.contains(',') {
            ','
        } else if header_text.contains(';') {
            ';'
        } else if header_text.contains('\t') {
            '\t'
        } else {
            ','
        }
    });
    let count = header_text.matches(delimiter).count() + 1;
    if count > crate::MAX_COLUMNS {
        return Err(at(
            header_line,
            None,
            DataErrorKind::TooManyColumns { count },
        ));
    }
    let names: Vec<&str> = header_text.split(delimiter).map(unquote).collect();
    // Each entry's column index.
    let mut index = Vec::with_capacity(map.entries.len());
    for e in &map.entries {
        match names.iter().position(|n| *n == e.column) {
            Some(i) => index.push(i),
            None => {
                let shown: Vec<&str> = names.iter().take(40).copied().collect();
                let more = if names.len() > 40 { ", …" } else { "" };
                return Err(at(
                    header_line,
                    Some(&e.column),
                    DataErrorKind::MissingColumn {
                        names: vec![format!("`{}` (for {})", e.column, e.quantity)],
                        why: format!(
                            "the column map names it but the header has {}{more}",
                            shown.join(", ")
                        ),
                    },
                ));
            }
        }
    }
    // Rows.
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); map.entries.len()];
    // Per entry, whether each row's cell held a value (an empty cell: not sampled then).
    let mut sampled: Vec<Vec<bool>> = vec![Vec::new(); map.entries.len()];
    let time_k = map
        .entries
        .iter()
        .position(|e| e.quantity == "time")
        .unwrap_or(0);
    let ranges: Vec<Option<Quantity>> = map
        .entries
        .iter()
        .map(|e| Quantity::of_mapped(e.quantity))
        .collect();
    let mut prev: Option<(f64, usize)> = None;
    let mut cells: Vec<&str> = Vec::with_capacity(names.len());
    for (n, l) in lines {
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        cells.clear();
        cells.extend(l.split(delimiter));
        if cells.len() != names.len() {
            return Err(at(
                n,
                None,
                DataErrorKind::RowLength {
                    expected: names.len(),
                    found: cells.len(),
                },
            ));
        }
        for (k, e) in map.entries.iter().enumerate() {
            let cell = unquote(cells[index[k]]);
            let empty = cell.trim().is_empty();
            sampled[k].push(!empty);
            if empty {
                if k == time_k {
                    return Err(at(n, Some(&e.column), DataErrorKind::EmptyTime));
                }
                values[k].push(0.0);
                continue;
            }
            let v = match cell.parse::<f64>() {
                Ok(v) if v.is_finite() => v,
                Ok(_) => {
                    return Err(at(
                        n,
                        Some(&e.column),
                        DataErrorKind::NonFinite {
                            value: crate::format::excerpt(cell),
                        },
                    ))
                }
                Err(_) => {
                    return Err(at(
                        n,
                        Some(&e.column),
                        DataErrorKind::NonNumeric {
                            value: crate::format::excerpt(cell),
                        },
                    ))
                }
            };
            let v = v * e.scale + e.offset;
            // The ranges of the project's CSV (`Quantity::range`), in SI after the scale and
            // offset; a latitude beyond ±90° with a hint at the unit it was probably in.
            if let Some(q) = ranges[k] {
                if q == Quantity::Lat && !q.admits(v) {
                    return Err(MappedError::Latitude {
                        file: file.to_string(),
                        line: n,
                        column: e.column.clone(),
                        radians: v,
                    });
                }
                if !q.admits(v) {
                    let value = if e.unit.is_empty() {
                        cell.to_string()
                    } else {
                        format!("{cell} {}", e.unit)
                    };
                    let range = q.range().2;
                    return Err(at(
                        n,
                        Some(&e.column),
                        DataErrorKind::OutOfRange { value, range },
                    ));
                }
            }
            values[k].push(v);
        }
        sampled_together(map, &sampled).map_err(|(column, kind)| at(n, Some(column), kind))?;
        let t = values[time_k][values[time_k].len() - 1];
        if let Some((previous, previous_line)) = prev {
            if t <= previous {
                return Err(at(
                    n,
                    Some(&map.entries[time_k].column),
                    DataErrorKind::NonIncreasingTime {
                        previous,
                        previous_line,
                        current: t,
                    },
                ));
            }
        }
        prev = Some((t, n));
    }
    if values[time_k].is_empty() {
        return Err(at(header_line, None, DataErrorKind::NoRows));
    }
    let time = values[time_k].clone();
    for (k, e) in map.entries.iter().enumerate() {
        let s = &sampled[k];
        if !s.contains(&false) {
            continue;
        }
        if !s.contains(&true) {
            return Err(at(header_line, Some(&e.column), DataErrorKind::NoSamples));
        }
        match e.quantity {
            "throttle" | "elevator" | "aileron" | "rudder" => fill_held(s, &mut values[k]),
            "roll" | "pitch" | "yaw" => {} // the short way round, once they are angles
            _ => fill_linear(&time, s, &mut values[k]),
        }
    }
    let sampled_of = |q: &str| {
        map.entries
            .iter()
            .position(|e| e.quantity == q)
            .map(|k| sampled[k].clone())
    };
    let take = |q: &str| -> Option<Vec<f64>> {
        map.entries
            .iter()
            .position(|e| e.quantity == q)
            .map(|k| values[k].clone())
    };
    let vec3 = |a: &str, b: &str, c: &str| -> Option<Vec<DVec3>> {
        let (x, y, z) = (take(a)?, take(b)?, take(c)?);
        Some((0..x.len()).map(|i| DVec3::new(x[i], y[i], z[i])).collect())
    };
    let time = take("time").unwrap_or_default();
    let n = time.len();
    let down = take("down").or_else(|| take("height").map(|h| h.iter().map(|v| -v).collect()));
    let mut report = ImportReport::new(file, super::FORMAT);
    let pos_ned = match take("lat") {
        Some(lat) => {
            let lon = take("lon").unwrap_or_else(|| vec![0.0; n]);
            // Heights: alt above sea level, or height above the origin.
            let alt = take("alt").or_else(|| down.as_ref().map(|d| d.iter().map(|v| -v).collect()));
            let alt = alt.unwrap_or_else(|| vec![0.0; n]);
            meta.latitude_deg = meta.latitude_deg.or(Some(lat[0].to_degrees()));
            meta.longitude_deg = meta.longitude_deg.or(Some(lon[0].to_degrees()));
            if map.has("alt") {
                meta.altitude_m = meta.altitude_m.or(Some(alt[0]));
            }
            flat_earth_ned(&lat, &lon, &alt)
        }
        None => {
            let (north, east) = (
                take("north").unwrap_or_default(),
                take("east").unwrap_or_default(),
            );
            let down = down.unwrap_or_default();
            (0..n)
                .map(|i| DVec3::new(north[i], east[i], down[i]))
                .collect()
        }
    };
    let mut data = FlightData::new(meta, time, pos_ned);
    data.attitude = vec3("yaw", "pitch", "roll").map(|v| {
        let mut a: Vec<EulerZyx> = v
            .into_iter()
            .map(|a| EulerZyx::new(a.x, a.y, a.z))
            .collect();
        if let Some(s) = sampled_of("roll") {
            fill_attitude(&data.time, &s, &mut a);
        }
        a
    });
    data.vel_ned = vec3("vn", "ve", "vd");
    data.vel_body = vec3("u", "v", "w");
    data.rates_body = vec3("p", "q", "r");
    data.airspeed = take("airspeed");
    data.accel_body = vec3("ax", "ay", "az");
    let position = ["lat", "north", "height"]
        .into_iter()
        .find(|q| map.has(q))
        .unwrap_or("north");
    for (channel, q) in [
        (Channel::Position, position),
        (Channel::Velocity, "vn"),
        (Channel::Attitude, "roll"),
        (Channel::Rates, "p"),
        (Channel::Airspeed, "airspeed"),
        (Channel::Accelerometer, "ax"),
    ] {
        if let Some(s) = sampled_of(q) {
            data.sampling.set(channel, &s);
        }
    }
    data.controls = match (
        take("throttle"),
        take("elevator"),
        take("aileron"),
        take("rudder"),
    ) {
        (Some(t), Some(e), Some(a), Some(r)) => Some(
            (0..n)
                .map(|i| Controls {
                    throttle: t[i],
                    elevator: e[i],
                    aileron: a[i],
                    rudder: r[i],
                })
                .collect(),
        ),
        _ => None,
    };
    if data.meta.source.is_none() {
        data.meta.source = Some(format!(
            "{} (column map)",
            Path::new(file)
                .file_name()
                .map_or(file.to_string(), |f| f.to_string_lossy().into_owned())
        ));
    }
    data.derive_missing();

    // The report: one line per channel, with its columns and units.
    let rate = median_rate(&data.time);
    let describe = |qs: &[&str]| -> String {
        qs.iter()
            .filter_map(|q| map.get(q))
            .map(|e| {
                let mut s = e.column.clone();
                if !e.unit.is_empty() {
                    s.push_str(&format!(" [{}]", e.unit));
                }
                if e.offset != 0.0 {
                    s.push_str(&format!(" {:+}", e.offset));
                }
                s
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let channels: [(&str, &[&str]); 10] = [
        ("time", &["time"]),
        (
            "position",
            &["north", "east", "down", "height", "lat", "lon", "alt"],
        ),
        ("attitude", &["roll", "pitch", "yaw"]),
        ("NED velocity", &["vn", "ve", "vd"]),
        ("body velocity", &["u", "v", "w"]),
        ("body rates", &["p", "q", "r"]),
        ("airspeed", &["airspeed"]),
        ("accelerometer", &["ax", "ay", "az"]),
        ("controls", &["throttle", "elevator", "aileron", "rudder"]),
        ("derived", &[]),
    ];
    for (name, qs) in &channels[..9] {
        if qs.iter().any(|q| map.has(q)) {
            let note = if *name == "position" && map.has("lat") {
                "local NED about the first row (flat earth)"
            } else {
                ""
            };
            report.channel(name, describe(qs), n, rate, true, note);
        }
    }
    if !data.derived.is_empty() {
        report.note(format!("derived: {}", data.derived.join(", ")));
    }
    let unused = names.len() - {
        let mut used = index.clone();
        used.sort_unstable();
        used.dedup();
        used.len()
    };
    if unused > 0 {
        let s = if unused == 1 { "" } else { "s" };
        report.note(format!("{unused} column{s} not mapped (ignored)"));
    }
    if let Some(c) = &data.controls {
        if c.iter().any(|c| !(0.0..=1.0).contains(&c.throttle)) {
            report.note("throttle outside 0..1 (a percentage? map it as throttle=COL:%)");
        }
    }
    report.samples = n;
    report.duration_s = data.duration();
    report.sampled = crate::report::sampled_channels(&data);
    Ok((data, report))
}

/// The sets of quantities sampled together: in one row, all of a set's cells hold values or
/// none does.
const SAMPLED_TOGETHER: [(&str, &[&str]); 6] = [
    ("position", &["north", "east", "down", "height"]),
    ("geodetic position", &["lat", "lon", "alt"]),
    ("attitude", &["roll", "pitch", "yaw"]),
    ("NED velocity", &["vn", "ve", "vd"]),
    ("body velocity", &["u", "v", "w"]),
    ("body rates", &["p", "q", "r"]),
];

/// In the row just read (the last of each `sampled`), every set of [`SAMPLED_TOGETHER`]
/// quantities is all given or all empty; else the first empty column and the error.
fn sampled_together<'m>(
    map: &'m ColumnMap,
    sampled: &[Vec<bool>],
) -> Result<(), (&'m str, DataErrorKind)> {
    for (channel, set) in SAMPLED_TOGETHER {
        let cells: Vec<(usize, bool)> = map
            .entries
            .iter()
            .enumerate()
            .filter(|(_, e)| set.contains(&e.quantity))
            .filter_map(|(k, _)| sampled[k].last().map(|&s| (k, s)))
            .collect();
        let given = cells.iter().find(|c| c.1);
        let empty = cells.iter().find(|c| !c.1);
        if let (Some(&(given, _)), Some(&(empty, _))) = (given, empty) {
            let kind = DataErrorKind::PartlyEmpty {
                channel,
                given: map.entries[given].column.clone(),
            };
            return Err((map.entries[empty].column.as_str(), kind));
        }
    }
    Ok(())
}

/// A cell or name trimmed, with surrounding double quotes removed.
fn unquote(c: &str) -> &str {
    let c = c.trim();
    c.strip_prefix('"')
        .and_then(|c| c.strip_suffix('"'))
        .unwrap_or(c)
        .trim()
}

/// Median sample rate of increasing times, Hz.
fn median_rate(t: &[f64]) -> Option<f64> {
    let mut dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if dt.is_empty() {
        return None;
    }
    let mid = dt.len() / 2;
    let (_, m, _) = dt.select_nth_unstable_by(mid, f64::total_cmp);
    (*m > 0.0).then(|| 1.0 / *m)
}
