//! Sensor-error specifications as text: the TOML file, the truth record, and the presets.
//!
//! Both texts go through one list of the model's fields ([`fields`]): each field's path as
//! written (`position.north.tau_s`), what kind of number it is, and where it goes. So the file
//! and the record accept exactly the same fields with the same checks, and the record writes
//! every field the file could have set.

use super::{
    AxisError, ChannelRates, EkfGnss, FieldProblem, Independent, Model, SensorErrorsError,
    MAX_RATE_HZ, MAX_SIZE, MAX_TAU_S, PRESETS, TRUTH_KEY,
};

/// What kind of number a field holds, and so its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A standard deviation or walk rate: 0..=[`MAX_SIZE`].
    Size,
    /// A time constant: (0, [`MAX_TAU_S`]].
    Tau,
    /// A rate: (0, [`MAX_RATE_HZ`]].
    Rate,
}

impl Kind {
    fn check(self, v: f64) -> Result<(), FieldProblem> {
        if !v.is_finite() {
            return Err(FieldProblem::NotFinite(v));
        }
        let (ok, range) = match self {
            Self::Size => (
                (0.0..=MAX_SIZE).contains(&v),
                "0 to 1e6 (in the field's unit)",
            ),
            Self::Tau => (v > 0.0 && v <= MAX_TAU_S, "more than 0 s, at most 1e9 s"),
            Self::Rate => (
                v > 0.0 && v <= MAX_RATE_HZ,
                "more than 0 Hz, at most 10000 Hz",
            ),
        };
        if ok {
            Ok(())
        } else {
            Err(FieldProblem::OutOfRange { value: v, range })
        }
    }
}

/// Where a field's number goes.
enum Slot<'a> {
    /// A number that is 0 when absent (or required, [`Field::required`]).
    Number(&'a mut f64),
    /// A number that may be absent.
    Optional(&'a mut Option<f64>),
}

/// One field of a model.
struct Field<'a> {
    path: String,
    kind: Kind,
    required: bool,
    slot: Slot<'a>,
}

impl Field<'_> {
    /// The value, `None` when absent; a number field that is 0 counts as absent (it is the
    /// default, and the record leaves it out).
    fn value(&self) -> Option<f64> {
        match &self.slot {
            Slot::Number(v) => (**v != 0.0 || self.required).then_some(**v),
            Slot::Optional(v) => **v,
        }
    }

    fn set(&mut self, v: f64) {
        match &mut self.slot {
            Slot::Number(s) => **s = v,
            Slot::Optional(s) => **s = Some(v),
        }
    }
}

/// The fields of one axis under `prefix`.
fn axis_fields<'a>(prefix: &str, a: &'a mut AxisError, out: &mut Vec<Field<'a>>) {
    let AxisError {
        size,
        tau_s,
        white,
        walk,
    } = a;
    let field = |name: &str, kind, slot| Field {
        path: format!("{prefix}.{name}"),
        kind,
        required: false,
        slot,
    };
    out.push(field("size", Kind::Size, Slot::Number(size)));
    out.push(field("tau_s", Kind::Tau, Slot::Optional(tau_s)));
    out.push(field("white", Kind::Size, Slot::Number(white)));
    out.push(field("walk", Kind::Size, Slot::Number(walk)));
}

fn rate_field<'a>(table: &str, rate: &'a mut Option<f64>) -> Field<'a> {
    Field {
        path: format!("{table}.rate_hz"),
        kind: Kind::Rate,
        required: false,
        slot: Slot::Optional(rate),
    }
}

/// Every field of a model, in the order the record writes them.
fn fields(model: &mut Model) -> Vec<Field<'_>> {
    let mut out = Vec::new();
    match model {
        Model::Independent(Independent {
            position,
            velocity,
            attitude,
            rates,
            airspeed,
            accel,
            rates_hz:
                ChannelRates {
                    position: position_hz,
                    velocity: velocity_hz,
                    attitude: attitude_hz,
                    rates: rates_hz,
                    airspeed: airspeed_hz,
                    accel: accel_hz,
                },
        }) => {
            let tables = [
                ("position", ["north", "east", "down"], position, position_hz),
                ("velocity", ["north", "east", "down"], velocity, velocity_hz),
                ("attitude", ["roll", "pitch", "yaw"], attitude, attitude_hz),
                ("rates", ["p", "q", "r"], rates, rates_hz),
                ("accel", ["x", "y", "z"], accel, accel_hz),
            ];
            for (table, names, axes, rate) in tables {
                out.push(rate_field(table, rate));
                for (name, a) in names.iter().zip(axes.iter_mut()) {
                    axis_fields(&format!("{table}.{name}"), a, &mut out);
                }
            }
            out.push(rate_field("airspeed", airspeed_hz));
            axis_fields("airspeed", airspeed, &mut out);
        }
        Model::EkfGnss(EkfGnss {
            gnss_rate_hz,
            gnss_horizontal,
            gnss_vertical,
            heading,
            gyro,
            accel,
            airspeed,
            rates_hz:
                ChannelRates {
                    position: position_hz,
                    velocity: velocity_hz,
                    attitude: attitude_hz,
                    rates: rates_hz,
                    airspeed: airspeed_hz,
                    accel: accel_hz,
                },
        }) => {
            out.push(Field {
                path: "gnss.rate_hz".to_string(),
                kind: Kind::Rate,
                required: true,
                slot: Slot::Number(gnss_rate_hz),
            });
            axis_fields("gnss.horizontal", gnss_horizontal, &mut out);
            axis_fields("gnss.vertical", gnss_vertical, &mut out);
            axis_fields("heading", heading, &mut out);
            out.push(rate_field("gyro", rates_hz));
            axis_fields("gyro", gyro, &mut out);
            out.push(rate_field("accel", accel_hz));
            axis_fields("accel", accel, &mut out);
            out.push(rate_field("airspeed", airspeed_hz));
            axis_fields("airspeed", airspeed, &mut out);
            out.push(rate_field("position", position_hz));
            out.push(rate_field("velocity", velocity_hz));
            out.push(rate_field("attitude", attitude_hz));
        }
    }
    out
}

/// The model `name` with every field absent (0), to be filled from a text.
fn blank(name: &str) -> Option<Model> {
    match name {
        "independent" => Some(Model::Independent(Independent::default())),
        "ekf-gnss" => Some(Model::EkfGnss(EkfGnss {
            gnss_rate_hz: 0.0,
            gnss_horizontal: AxisError::ZERO,
            gnss_vertical: AxisError::ZERO,
            heading: AxisError::ZERO,
            gyro: AxisError::ZERO,
            accel: AxisError::ZERO,
            airspeed: AxisError::ZERO,
            rates_hz: ChannelRates::default(),
        })),
        _ => None,
    }
}

/// The preset `name`'s model (numbers: the module documentation's tables).
pub(super) fn preset(name: &str) -> Option<Model> {
    let gm = AxisError::gm;
    match name {
        "independent" => Some(Model::Independent(Independent {
            position: [gm(0.5, 30.0, 0.05), gm(0.5, 30.0, 0.05), gm(1.0, 60.0, 0.1)],
            velocity: [gm(0.05, 5.0, 0.0); 3],
            attitude: [gm(0.2, 5.0, 0.0), gm(0.2, 5.0, 0.0), gm(0.5, 30.0, 0.0)],
            rates: [gm(0.02, 60.0, 0.05); 3],
            airspeed: gm(0.3, 10.0, 0.0),
            accel: [gm(0.02, 60.0, 0.0); 3],
            rates_hz: ChannelRates {
                position: Some(10.0),
                ..ChannelRates::default()
            },
        })),
        "ekf-gnss" => Some(Model::EkfGnss(EkfGnss {
            gnss_rate_hz: 5.0,
            gnss_horizontal: gm(0.5, 30.0, 0.2),
            gnss_vertical: gm(1.0, 30.0, 0.4),
            heading: gm(0.5, 30.0, 0.0),
            gyro: gm(0.01, 60.0, 0.05),
            accel: gm(0.01, 60.0, 0.02),
            airspeed: gm(0.3, 10.0, 0.0),
            rates_hz: ChannelRates::default(),
        })),
        _ => None,
    }
}

/// A value as read from a text: a number, or a description of what it is instead.
type Read = Result<f64, String>;

/// The allowed keys after `prefix` (the root when empty), for an unknown key's message.
fn expected_after(paths: &[String], prefix: &str) -> String {
    let mut keys: Vec<&str> = if prefix.is_empty() {
        vec!["model"]
    } else {
        Vec::new()
    };
    for p in paths {
        let rest = if prefix.is_empty() {
            Some(p.as_str())
        } else {
            p.strip_prefix(prefix).and_then(|r| r.strip_prefix('.'))
        };
        if let Some(key) = rest.and_then(|r| r.split('.').next()) {
            if !keys.contains(&key) {
                keys.push(key);
            }
        }
    }
    keys.join(", ")
}

/// The error of `field` in `file`.
fn field_error(file: &str, field: &str, problem: FieldProblem) -> SensorErrorsError {
    SensorErrorsError::Field {
        file: file.to_string(),
        field: field.to_string(),
        problem,
    }
}

/// What a TOML value is, in words.
fn toml_type(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "a string",
        toml::Value::Integer(_) => "an integer",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "a boolean",
        toml::Value::Datetime(_) => "a date-time",
        toml::Value::Array(_) => "an array",
        toml::Value::Table(_) => "a table",
    }
}

/// The leaves of `table` under `prefix`, as (path, value), checked against the model's
/// `paths`: a key that is not a field nor a table of fields is an error, and so is a table
/// where a number belongs or a number where a table does.
fn leaves(
    table: &toml::Table,
    prefix: &str,
    paths: &[String],
    file: &str,
    out: &mut Vec<(String, Read)>,
) -> Result<(), SensorErrorsError> {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        let is_leaf = paths.contains(&path);
        let dotted = format!("{path}.");
        let is_table = paths.iter().any(|p| p.starts_with(&dotted));
        match value {
            toml::Value::Table(t) if is_table => leaves(t, &path, paths, file, out)?,
            _ if is_leaf => out.push((
                path,
                match value {
                    // Integers are as good as floats: `rate_hz = 10`.
                    toml::Value::Integer(i) => Ok(*i as f64),
                    toml::Value::Float(f) => Ok(*f),
                    other => Err(toml_type(other).to_string()),
                },
            )),
            _ if is_table => {
                return Err(field_error(
                    file,
                    &path,
                    FieldProblem::WrongType {
                        expected: "a table",
                        found: toml_type(value).to_string(),
                    },
                ))
            }
            _ => {
                return Err(field_error(
                    file,
                    &path,
                    FieldProblem::Unknown {
                        expected: expected_after(paths, prefix),
                    },
                ))
            }
        }
    }
    Ok(())
}

/// The model `name` with the fields `entries` (path, value) set and checked: known paths
/// only, each once, numbers in range, required fields present, a time constant for every
/// Gauss–Markov part.
fn assemble(
    name: &str,
    entries: Vec<(String, Read)>,
    file: &str,
) -> Result<Model, SensorErrorsError> {
    let mut model = blank(name)
        .ok_or_else(|| field_error(file, "model", FieldProblem::UnknownModel(name.to_string())))?;
    {
        let mut fs = fields(&mut model);
        let mut seen = vec![false; fs.len()];
        for (path, value) in entries {
            let Some(i) = fs.iter().position(|f| f.path == path) else {
                let prefix = path.rsplit_once('.').map_or("", |(p, _)| p);
                let paths: Vec<String> = fs.iter().map(|f| f.path.clone()).collect();
                return Err(field_error(
                    file,
                    &path,
                    FieldProblem::Unknown {
                        expected: expected_after(&paths, prefix),
                    },
                ));
            };
            if seen[i] {
                return Err(field_error(file, &path, FieldProblem::Duplicate));
            }
            let v = value.map_err(|found| {
                field_error(
                    file,
                    &path,
                    FieldProblem::WrongType {
                        expected: "a number",
                        found,
                    },
                )
            })?;
            fs[i]
                .kind
                .check(v)
                .map_err(|p| field_error(file, &path, p))?;
            fs[i].set(v);
            seen[i] = true;
        }
        if let Some(f) = fs.iter().zip(&seen).find(|(f, s)| f.required && !**s) {
            return Err(field_error(file, &f.0.path, FieldProblem::Missing));
        }
        for f in &fs {
            let Some(prefix) = f.path.strip_suffix(".size") else {
                continue;
            };
            let tau = format!("{prefix}.tau_s");
            let has_tau = fs.iter().any(|g| g.path == tau && g.value().is_some());
            if f.value().is_some_and(|v| v > 0.0) && !has_tau {
                return Err(field_error(file, &tau, FieldProblem::TauNeeded));
            }
        }
    }
    Ok(model)
}

/// The model of a TOML text.
pub(super) fn parse_toml(text: &str, file: &str) -> Result<Model, SensorErrorsError> {
    let mut table: toml::Table =
        text.parse()
            .map_err(|e: toml::de::Error| SensorErrorsError::Toml {
                file: file.to_string(),
                message: wireflight_data::format::toml_problem(text, &e),
            })?;
    let name = match table.remove("model") {
        Some(toml::Value::String(s)) => s,
        Some(other) => {
            return Err(field_error(
                file,
                "model",
                FieldProblem::WrongType {
                    expected: "a string (independent or ekf-gnss)",
                    found: toml_type(&other).to_string(),
                },
            ))
        }
        None => return Err(field_error(file, "model", FieldProblem::Missing)),
    };
    let mut model = blank(&name)
        .ok_or_else(|| field_error(file, "model", FieldProblem::UnknownModel(name.clone())))?;
    let paths: Vec<String> = fields(&mut model).into_iter().map(|f| f.path).collect();
    let mut entries = Vec::new();
    leaves(&table, "", &paths, file, &mut entries)?;
    assemble(&name, entries, file)
}

/// A number in its shortest round-trip form, in scientific notation when very small or
/// large (so that 1e-300 is not 300 zeros).
fn number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// The truth record of `model` (module documentation of [`super`]).
pub(super) fn to_record(model: &Model, seed: u64) -> String {
    let mut m = *model;
    let name = match m {
        Model::Independent(_) => PRESETS[0],
        Model::EkfGnss(_) => PRESETS[1],
    };
    let mut out = format!("model={name} seed={seed}");
    for f in fields(&mut m) {
        if let Some(v) = f.value() {
            out.push_str(&format!(" {}={}", f.path, number(v)));
        }
    }
    out
}

/// A truth record read back: the model and the seed.
pub(super) fn from_record(record: &str) -> Result<(Model, u64), SensorErrorsError> {
    let file = format!("metadata `{TRUTH_KEY}`");
    let mut name = None;
    let mut seed = None;
    let mut entries = Vec::new();
    for token in record.split_whitespace() {
        let Some((key, value)) = token.split_once('=') else {
            return Err(field_error(
                &file,
                token,
                FieldProblem::WrongType {
                    expected: "`key=value`",
                    found: format!("`{token}`"),
                },
            ));
        };
        match key {
            "model" if name.is_some() => {
                return Err(field_error(&file, key, FieldProblem::Duplicate))
            }
            "model" => name = Some(value),
            "seed" if seed.is_some() => {
                return Err(field_error(&file, key, FieldProblem::Duplicate))
            }
            "seed" => {
                seed = Some(value.parse::<u64>().map_err(|_| {
                    field_error(
                        &file,
                        key,
                        FieldProblem::WrongType {
                            expected: "a whole number from 0 to 2^64 - 1",
                            found: format!("`{value}`"),
                        },
                    )
                })?);
            }
            _ => entries.push((
                key.to_string(),
                value.parse::<f64>().map_err(|_| format!("`{value}`")),
            )),
        }
    }
    let name = name.ok_or_else(|| field_error(&file, "model", FieldProblem::Missing))?;
    let seed = seed.ok_or_else(|| field_error(&file, "seed", FieldProblem::Missing))?;
    Ok((assemble(name, entries, &file)?, seed))
}
