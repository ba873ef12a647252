//! Model descriptions: which vehicle, which parameter set, which effects with which
//! parameters. Written as a small TOML file or assembled from command-line options:
//!
//! ```toml
//! vehicle = "fixed-wing"        # or "point-mass"
//! aircraft = "aerosonde"        # built-in name or a parameter-set .toml (fixed-wing)
//! effects = ["wind", "density_altitude"]
//!
//! [wind]                        # parameters of an effect; omitted ones keep defaults
//! north_mps = 5.0
//!
//! [origin]                      # optional; defaults to the flight data's metadata
//! latitude_deg = 45.0
//! altitude_m = 0.0
//! ```
//!
//! `--effects a,b` and `--add name[:k=v,...]` on the command line do the same.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::effects::term::TermError;
use super::effects::{
    catalogue_names, find, Effect, EffectContext, Origin, ParamError, RecordedAttitude,
};
use super::expr::Term;
use super::model::{Model, ModelError, Vehicle};
use super::params::{FixedWingParams, ParamSetError};
use wireflight_data::{FlightData, OriginError, UnknownVehicle, VehicleKind};

/// An effect spec, model file or model choice that cannot be used, naming the file, the field
/// or the spec, and the problem.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SpecError {
    /// `--add`/`--effects` or a model file names an effect not in the catalogue.
    #[error(
        "unknown effect `{0}`{hint} (known: {known}, or aircraft:KEY for the aircraft's own \
         numbers)",
        hint = effect_hint(.0, true),
        known = catalogue_names().join(", ")
    )]
    UnknownEffect(String),
    /// An [`EffectSpec`] built whose name is not in the catalogue.
    #[error(
        "unknown effect `{0}`{hint} (known: {known})",
        hint = effect_hint(.0, false),
        known = catalogue_names().join(", ")
    )]
    NotInCatalogue(String),
    /// A key of `aircraft:KEY…` that is not a key of a parameter set.
    #[error(
        "`{key}` in `{spec}` is not an aircraft parameter{hint} (`wireflight keys` lists them)",
        hint = crate::params::keys::did_you_mean(key)
    )]
    NotAircraftParameter {
        /// The key.
        key: String,
        /// The spec it is in.
        spec: String,
    },
    /// A parameter given twice in one spec: which value was meant is not known.
    #[error("`{key}` is given twice in `{spec}`: give each parameter once")]
    RepeatedParameter {
        /// The parameter.
        key: String,
        /// The spec it is in.
        spec: String,
    },
    /// A `k=v` that is not one.
    #[error("`{item}` in `{spec}` is not name=value")]
    NotNameValue {
        /// The item.
        item: String,
        /// The spec it is in.
        spec: String,
    },
    /// A value that is not a finite number.
    #[error("`{value}` for `{key}` in `{spec}` is not a finite number")]
    NotFinite {
        /// The value as written.
        value: String,
        /// Its parameter.
        key: String,
        /// The spec it is in.
        spec: String,
    },
    /// `aircraft` alone.
    #[error("`{0}` names no aircraft parameter (aircraft:KEY or aircraft:KEY=VALUE)")]
    NoAircraftParameter(String),
    /// A parameter the effect refuses (unknown, or out of its range).
    #[error("`{spec}`: {error}")]
    Param {
        /// The spec, as on a command line.
        spec: String,
        /// What the effect says.
        error: ParamError,
    },
    /// `aircraft:KEY` without a value where a model is built.
    #[error("`{spec}`: a model needs a value for aircraft parameter `{key}`")]
    AircraftNeedsValue {
        /// The spec, as on a command line.
        spec: String,
        /// The key without a value.
        key: String,
    },
    /// A model file that could not be read.
    #[error("{}: cannot read", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A model file whose contents are refused.
    #[error("{}: bad model file", path.display())]
    BadFile {
        /// The file.
        path: PathBuf,
        /// What is wrong in it.
        #[source]
        source: Box<SpecError>,
    },
    /// Model-file text that is not TOML: where, and what the TOML reader says (one bounded
    /// line).
    #[error("{0}")]
    Toml(String),
    /// No `vehicle` field.
    #[error("missing field `vehicle` (point-mass or fixed-wing)")]
    MissingVehicle,
    /// An unknown vehicle family.
    #[error(transparent)]
    Vehicle(#[from] UnknownVehicle),
    /// A top-level field of the wrong type.
    #[error("field `{field}` must {expected}")]
    FieldType {
        /// The field.
        field: &'static str,
        /// What it must be or hold.
        expected: &'static str,
    },
    /// An effect's parameter table that is not a table.
    #[error("`[{0}]` must be a table of parameters")]
    EffectTable(String),
    /// `[origin]` that is not a table.
    #[error("`[origin]` must be a table")]
    OriginTable,
    /// A parameter or origin value that is not a number.
    #[error("`{0}` must be a number")]
    NotANumber(String),
    /// A top-level field that is neither a known one nor an effect in `effects`.
    #[error("unknown field `{0}` (a parameter table for an effect not in `effects`?)")]
    UnknownField(String),
    /// A field of `[origin]` that is not one.
    #[error("unknown field `origin.{0}`")]
    UnknownOriginField(String),
    /// A field of `[origin]` out of its range.
    #[error("`origin.{key}`: {0}", key = .0.key)]
    OriginField(OriginError),
    /// The origin the model is built at is out of range.
    #[error("origin: {0}")]
    Origin(OriginError),
    /// The parameter set cannot be had.
    #[error(transparent)]
    ParamSet(#[from] ParamSetError),
    /// The model refuses an effect or an aircraft number.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Neither the choice nor the data's metadata say which vehicle.
    #[error(
        "{}: no `# vehicle:` metadata; say which model with --vehicle or --model FILE",
        data.display()
    )]
    NoVehicle {
        /// The flight-data file.
        data: PathBuf,
    },
    /// A fixed-wing model for data without controls.
    #[error("{}: a fixed-wing model needs the control columns", data.display())]
    NoControls {
        /// The flight-data file.
        data: PathBuf,
    },
    /// A term (`term:AXIS=EXPR`, a model file's `[[term]]`) that does not read: the column
    /// counts in the text as written (the whole `--add` argument, or the file's `expr`).
    #[error("`{spec}`: column {column}: {problem}")]
    Term {
        /// The spec or expression as written.
        spec: String,
        /// The 1-based column, in characters, of the problem.
        column: usize,
        /// What is wrong.
        problem: crate::expr::Problem,
    },
    /// More distinct terms than one run keeps.
    #[error("`{spec}`: {error}")]
    TermRegistry {
        /// The spec.
        spec: String,
        /// What the registry says.
        error: crate::effects::term::TermError,
    },
    /// A `[[term]]` entry that is not `axis = "…"`, `expr = "…"` and coefficient values.
    #[error("`[[term]]` #{index}: {problem}")]
    TermEntry {
        /// The entry's 1-based position in the file.
        index: usize,
        /// What is wrong.
        problem: String,
    },
    /// Building the model of a [`ModelChoice`] failed.
    #[error("building the model")]
    Building(#[source] Box<SpecError>),
}

/// `: did you mean `NAME`?` for the catalogue effect (or, with `aircraft`, that name too)
/// nearest to a mistyped one.
fn effect_hint(given: &str, aircraft: bool) -> String {
    let names = catalogue_names();
    let extra = aircraft.then_some(AIRCRAFT);
    crate::params::suggest::hint(given, names.into_iter().chain(extra))
}

/// One effect with the parameters given explicitly (the rest keep their defaults) — or, under
/// the name `aircraft`, numbers of the aircraft's parameter set: `aircraft:c_m_alpha=-3.3`
/// gives a value, `aircraft:c_m_alpha` names one to fit.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectSpec {
    /// Catalogue name, or `aircraft`.
    pub name: String,
    /// Parameters given, name → value.
    pub params: Vec<(String, f64)>,
    /// Parameters named without a value (`aircraft:KEY`): to be fitted.
    pub fit: Vec<String>,
}

/// How `--add` writes a term: `term:AXIS=EXPR` (coefficients fitted from 0).
pub const TERM_SHORT: &str = "term:";
/// How a term's effect is named, and written with values: `term(AXIS=EXPR):k=v,…`.
pub const TERM_LONG: &str = "term(";

/// One `[[term]]` of a model file: `axis = "m"`, `expr = "k * thrust"`, and optionally a
/// value for each coefficient (`k = 0.8`; the others start at 0).
fn term_entry(index: usize, entry: &toml::Value) -> Result<EffectSpec, SpecError> {
    let bad = |problem: String| SpecError::TermEntry { index, problem };
    let table = entry
        .as_table()
        .ok_or_else(|| bad("must be a table with `axis` and `expr`".into()))?;
    let text = |key: &str| {
        table
            .get(key)
            .ok_or_else(|| bad(format!("missing `{key}`")))?
            .as_str()
            .ok_or_else(|| bad(format!("`{key}` must be a string")))
    };
    let (axis, expr) = (text("axis")?, text("expr")?);
    let term = Term::new(axis, expr).map_err(|e| SpecError::Term {
        spec: if matches!(e.problem, crate::expr::Problem::UnknownAxis(_)) {
            axis.to_string()
        } else {
            expr.to_string()
        },
        column: e.column,
        problem: e.problem,
    })?;
    let mut params = Vec::new();
    for (k, v) in table
        .iter()
        .filter(|(k, _)| !["axis", "expr"].contains(&k.as_str()))
    {
        let value = v
            .as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .ok_or_else(|| bad(format!("`{k}` must be a number (a coefficient's value)")))?;
        params.push((k.clone(), value));
    }
    EffectSpec::of_term(&term, params).map_err(|error| SpecError::TermRegistry {
        spec: format!("{term}"),
        error,
    })
}

/// `k=v,…` of a term's spec: coefficient values.
fn parse_values(spec: &str, rest: &str) -> Result<Vec<(String, f64)>, SpecError> {
    let mut params = Vec::new();
    for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((k, v)) = kv.split_once('=') else {
            return Err(SpecError::NotNameValue {
                item: shown(kv),
                spec: shown(spec),
            });
        };
        let value = finite_value(spec, k, v)?;
        push_once(&mut params, k.trim(), value, spec)?;
    }
    Ok(params)
}

/// Text from a spec as its errors quote it: an excerpt (a 100 kB `--add` is not echoed whole).
fn shown(text: &str) -> String {
    wireflight_data::format::excerpt(text)
}

/// Appends `key = value` to `params`, refusing a key already there.
fn push_once(
    params: &mut Vec<(String, f64)>,
    key: &str,
    value: f64,
    spec: &str,
) -> Result<(), SpecError> {
    if params.iter().any(|(k, _)| k == key) {
        return Err(SpecError::RepeatedParameter {
            key: shown(key),
            spec: shown(spec),
        });
    }
    params.push((key.to_string(), value));
    Ok(())
}

/// `v` as a finite number, or the error naming it, its key and the spec.
fn finite_value(spec: &str, k: &str, v: &str) -> Result<f64, SpecError> {
    v.trim()
        .parse()
        .ok()
        .filter(|x: &f64| x.is_finite())
        .ok_or_else(|| SpecError::NotFinite {
            value: shown(v),
            key: shown(k),
            spec: shown(spec),
        })
}

/// The name under which `--add`/`--hidden` address the aircraft's own numbers.
pub const AIRCRAFT: &str = "aircraft";

impl EffectSpec {
    /// Parse `name[:k=v,k=v]`.
    ///
    /// # Errors
    /// Unknown effect name, malformed `k=v`, non-numeric or non-finite value.
    pub fn parse(text: &str) -> Result<Self, SpecError> {
        if let Some(term) = text.trim_start().strip_prefix(TERM_SHORT) {
            let lead = text.chars().count() - term.chars().count();
            return Self::term(text, term, lead, Vec::new());
        }
        if text.trim_start().starts_with(TERM_LONG) {
            // `term(AXIS=EXPR)` or `term(AXIS=EXPR):k=v,…` (how a term with values is written
            // back, and how a hidden truth gives its coefficients): the name ends at the `)`
            // before the first `:`, since an expression has no `:`.
            let (head, rest) = text.split_once(':').unwrap_or((text, ""));
            let lead = text.chars().count() - text.trim_start().chars().count() + TERM_LONG.len();
            let inner = head.trim().strip_prefix(TERM_LONG).unwrap_or("");
            let Some(inner) = inner.strip_suffix(')') else {
                return Err(SpecError::Term {
                    spec: shown(text),
                    column: head.trim_end().chars().count() + 1,
                    problem: crate::expr::Problem::Unclosed,
                });
            };
            let params = parse_values(text, rest)?;
            return Self::term(text, inner, lead, params);
        }
        let (name, rest) = match text.split_once(':') {
            Some((n, r)) => (n.trim(), r),
            None => (text.trim(), ""),
        };
        let aircraft = name == AIRCRAFT;
        if !aircraft && find(name).is_none() {
            return Err(SpecError::UnknownEffect(shown(name)));
        }
        let not_aircraft = |key: &str| SpecError::NotAircraftParameter {
            key: shown(key),
            spec: shown(text),
        };
        let mut params = Vec::new();
        let mut fit = Vec::new();
        for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let Some((k, v)) = kv.split_once('=') else {
                if aircraft {
                    let key = crate::params::keys::find(kv).ok_or_else(|| not_aircraft(kv))?;
                    if fit.iter().any(|f| f == key.name) {
                        return Err(SpecError::RepeatedParameter {
                            key: shown(kv),
                            spec: shown(text),
                        });
                    }
                    fit.push(key.name.to_string());
                    continue;
                }
                return Err(SpecError::NotNameValue {
                    item: shown(kv),
                    spec: shown(text),
                });
            };
            if aircraft && crate::params::keys::find(k.trim()).is_none() {
                return Err(not_aircraft(k.trim()));
            }
            let value = finite_value(text, k, v)?;
            push_once(&mut params, k.trim(), value, text)?;
        }
        if aircraft && params.is_empty() && fit.is_empty() {
            return Err(SpecError::NoAircraftParameter(shown(text)));
        }
        Ok(Self {
            name: name.to_string(),
            params,
            fit,
        })
    }

    /// A term's spec: `term_text` (`AXIS=EXPR`, beginning `lead` characters into `text`)
    /// read, compiled and interned once; its effect name is the canonical `term(…)`.
    fn term(
        text: &str,
        term_text: &str,
        lead: usize,
        params: Vec<(String, f64)>,
    ) -> Result<Self, SpecError> {
        let term = Term::parse(term_text).map_err(|e| SpecError::Term {
            spec: shown(text),
            column: lead + e.column,
            problem: e.problem,
        })?;
        Self::of_term(&term, params).map_err(|error| SpecError::TermRegistry {
            spec: shown(text),
            error,
        })
    }

    /// The spec of a term read already, with coefficient values given.
    ///
    /// # Errors
    /// Too many distinct terms in one run.
    pub fn of_term(term: &Term, params: Vec<(String, f64)>) -> Result<Self, TermError> {
        let info = crate::effects::term::intern(term)?;
        Ok(Self {
            name: info.name.to_string(),
            params,
            fit: Vec::new(),
        })
    }

    /// Whether it is a term (`term(AXIS=EXPR)`).
    pub fn is_term(&self) -> bool {
        self.name.starts_with(TERM_LONG)
    }

    /// Whether it addresses the aircraft's own numbers rather than an effect.
    pub fn is_aircraft(&self) -> bool {
        self.name == AIRCRAFT
    }

    /// The effect with these parameters (the rest at their defaults for `ctx`). The one place
    /// where a spec becomes an effect.
    ///
    /// # Errors
    /// Unknown effect, unknown parameter, a value outside the parameter's range.
    pub fn build(&self, ctx: &EffectContext) -> Result<Box<dyn Effect>, SpecError> {
        let info = find(&self.name).ok_or_else(|| SpecError::NotInCatalogue(self.name.clone()))?;
        let mut effect = info.build(ctx);
        for (k, v) in &self.params {
            effect.set_param(k, *v).map_err(|error| SpecError::Param {
                spec: self.to_arg(),
                error,
            })?;
        }
        Ok(effect)
    }

    /// Names of the parameters given (these are held, not fitted, by `--add`).
    pub fn given(&self) -> Vec<String> {
        self.params.iter().map(|(k, _)| k.clone()).collect()
    }

    /// `name:k=v,...` as given on a command line (inverse of [`parse`](Self::parse)).
    pub fn to_arg(&self) -> String {
        if self.params.is_empty() && self.fit.is_empty() {
            if let Some(term) = self
                .is_term()
                .then(|| self.name[TERM_LONG.len()..].strip_suffix(')'))
                .flatten()
            {
                return format!("{TERM_SHORT}{term}");
            }
            return self.name.clone();
        }
        let kv: Vec<String> = self
            .params
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .chain(self.fit.iter().cloned())
            .collect();
        format!("{}:{}", self.name, kv.join(","))
    }
}

/// A model description, buildable into a [`Model`].
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSpec {
    /// Vehicle family.
    pub vehicle: VehicleKind,
    /// Parameter set (fixed-wing): built-in name or file path.
    pub aircraft: String,
    /// Effects in order.
    pub effects: Vec<EffectSpec>,
    /// Origin fields given explicitly (latitude, longitude, altitude).
    pub origin: [Option<f64>; 3],
    /// Directory that a relative `aircraft` path is relative to: the model file's (or the
    /// data file's, for metadata); `None`: the working directory.
    pub base_dir: Option<PathBuf>,
}

impl ModelSpec {
    /// The baseline of a vehicle family (Aerosonde for fixed-wing).
    pub fn baseline(vehicle: VehicleKind) -> Self {
        Self {
            vehicle,
            aircraft: "aerosonde".into(),
            effects: Vec::new(),
            origin: [None; 3],
            base_dir: None,
        }
    }

    /// Read a model file.
    ///
    /// # Errors
    /// Unreadable file, bad TOML, unknown keys, effects or parameters — naming the file and
    /// the field.
    pub fn load(path: &Path) -> Result<Self, SpecError> {
        let text =
            wireflight_fsio::read_config_text(path).map_err(|source| SpecError::Unreadable {
                path: path.to_path_buf(),
                source,
            })?;
        let mut spec = Self::from_toml(&text).map_err(|e| SpecError::BadFile {
            path: path.to_path_buf(),
            source: Box::new(e),
        })?;
        spec.base_dir = path.parent().map(Path::to_path_buf);
        Ok(spec)
    }

    /// Parse model-file text.
    ///
    /// # Errors
    /// As [`load`](Self::load), without the file name.
    pub fn from_toml(text: &str) -> Result<Self, SpecError> {
        let table: toml::Table = text
            .parse()
            .map_err(|e| SpecError::Toml(wireflight_data::format::toml_problem(text, &e)))?;
        let vehicle: VehicleKind = match table.get("vehicle") {
            Some(toml::Value::String(s)) => s.parse()?,
            Some(_) => return Err(field_type("vehicle", "be a string")),
            None => return Err(SpecError::MissingVehicle),
        };
        let mut spec = Self::baseline(vehicle);
        if let Some(v) = table.get("aircraft") {
            spec.aircraft = v
                .as_str()
                .ok_or_else(|| field_type("aircraft", "be a string"))?
                .to_string();
        }
        let names: Vec<String> = match table.get("effects") {
            None => Vec::new(),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| {
                    v.as_str()
                        .map(str::to_string)
                        .ok_or_else(|| field_type("effects", "list effect names as strings"))
                })
                .collect::<Result<_, _>>()?,
            Some(_) => return Err(field_type("effects", "be an array of names")),
        };
        let number = |v: &toml::Value, key: String| {
            v.as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .ok_or(SpecError::NotANumber(key))
        };
        for name in &names {
            let mut effect = EffectSpec::parse(name)?;
            if let Some(params) = table.get(name.as_str()) {
                let params = params
                    .as_table()
                    .ok_or_else(|| SpecError::EffectTable(name.clone()))?;
                for (k, v) in params {
                    let value = number(v, format!("{name}.{k}"))?;
                    effect.params.push((k.clone(), value));
                }
            }
            spec.effects.push(effect);
        }
        if let Some(terms) = table.get("term") {
            let terms = terms
                .as_array()
                .ok_or_else(|| field_type("term", "be an array of tables ([[term]])"))?;
            for (i, entry) in terms.iter().enumerate() {
                spec.effects.push(term_entry(i + 1, entry)?);
            }
        }
        for (key, value) in &table {
            let known = ["vehicle", "aircraft", "effects", "origin", "term"]
                .contains(&key.as_str())
                || names.contains(key);
            if !known {
                return Err(SpecError::UnknownField(key.clone()));
            }
            if key == "origin" {
                let t = value.as_table().ok_or(SpecError::OriginTable)?;
                for (k, v) in t {
                    let slot = match k.as_str() {
                        "latitude_deg" => 0,
                        "longitude_deg" => 1,
                        "altitude_m" => 2,
                        _ => return Err(SpecError::UnknownOriginField(k.clone())),
                    };
                    let v = number(v, format!("origin.{k}"))?;
                    Origin::check_field(k, v).map_err(SpecError::OriginField)?;
                    spec.origin[slot] = Some(v);
                }
            }
        }
        Ok(spec)
    }

    /// Add effects named in a comma list (`--effects a,b`).
    ///
    /// # Errors
    /// Unknown names.
    pub fn add_effect_list(&mut self, list: &str) -> Result<(), SpecError> {
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            self.effects.push(EffectSpec::parse(name)?);
        }
        Ok(())
    }

    /// The origin: explicit fields override `default`.
    pub fn origin(&self, default: Origin) -> Origin {
        Origin {
            latitude_deg: self.origin[0].unwrap_or(default.latitude_deg),
            longitude_deg: self.origin[1].unwrap_or(default.longitude_deg),
            altitude_m: self.origin[2].unwrap_or(default.altitude_m),
        }
    }

    /// Build the model. `default_origin` usually comes from the flight data's metadata.
    ///
    /// # Errors
    /// Unknown aircraft, bad parameter names/values, effects for the other vehicle family,
    /// duplicates.
    pub fn build(&self, default_origin: Origin) -> Result<Model, SpecError> {
        self.build_recorded(default_origin, None)
    }

    /// [`build`](Self::build) for a flight that recorded `attitude`: the model and its effects
    /// have it to act from ([`EffectContext::recorded_attitude`]).
    ///
    /// # Errors
    /// As [`build`](Self::build); an effect that acts from an attitude when there is none.
    pub fn build_recorded(
        &self,
        default_origin: Origin,
        attitude: Option<Arc<RecordedAttitude>>,
    ) -> Result<Model, SpecError> {
        let origin = self.origin(default_origin);
        origin.check().map_err(SpecError::Origin)?;
        let vehicle = match self.vehicle {
            VehicleKind::PointMass => Vehicle::PointMass,
            VehicleKind::FixedWing => {
                Vehicle::FixedWing(Box::new(FixedWingParams::load(&self.aircraft_source())?))
            }
        };
        let mut model = Model::new(vehicle, origin);
        model.set_recorded_attitude(attitude);
        let ctx = model.effect_context();
        for e in &self.effects {
            if e.is_aircraft() {
                if let Some(k) = e.fit.first() {
                    return Err(SpecError::AircraftNeedsValue {
                        spec: e.to_arg(),
                        key: k.clone(),
                    });
                }
                for (k, v) in &e.params {
                    model.set_aircraft(k, *v)?;
                }
                continue;
            }
            let effect = e.build(&ctx)?;
            model.add_effect(effect)?;
        }
        Ok(model)
    }

    /// The parameter set to load: a built-in name as it is; a relative file path resolved
    /// from [`base_dir`](Self::base_dir) when the file is there (else as given, from the
    /// working directory).
    pub fn aircraft_source(&self) -> String {
        let given = Path::new(&self.aircraft);
        if let Some(dir) = &self.base_dir {
            let looks_like_file = self.aircraft.ends_with(".toml") || self.aircraft.contains('/');
            if looks_like_file && given.is_relative() {
                let beside = dir.join(given);
                if beside.exists() {
                    return beside.to_string_lossy().into_owned();
                }
            }
        }
        self.aircraft.clone()
    }
}

/// Which flight model to run against a flight: a model file, or the vehicle (and aircraft)
/// of the data's metadata or given explicitly; plus effects by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelChoice {
    /// Model file (TOML).
    pub model_file: Option<PathBuf>,
    /// Vehicle family, overriding the data's `# vehicle:`.
    pub vehicle: Option<VehicleKind>,
    /// Parameter set (name or file), overriding the data's `# aircraft:`.
    pub aircraft: Option<String>,
    /// Effects in the model, comma-separated (`--effects a,b`).
    pub effects: Option<String>,
}

impl ModelChoice {
    /// The model for the flight `data` read from `data_path`: the choice's, with the origin
    /// from the data's metadata. Relative paths in the metadata are resolved from the data
    /// file's directory.
    ///
    /// # Errors
    /// No vehicle known, bad model file or parameter set, unknown effects, a fixed-wing
    /// model for data without controls.
    pub fn build(&self, data_path: &Path, data: &FlightData) -> Result<Model, SpecError> {
        self.build_for(data_path, data, true)
    }

    /// [`build`](Self::build) for a model flown on other flights as well (reference flights):
    /// without the flight's recorded attitude, which an effect must not read on another
    /// flight ([`EffectContext::recorded_attitude`]).
    ///
    /// # Errors
    /// As [`build`](Self::build); an effect that acts from a recorded attitude.
    pub fn build_unrecorded(
        &self,
        data_path: &Path,
        data: &FlightData,
    ) -> Result<Model, SpecError> {
        self.build_for(data_path, data, false)
    }

    /// [`build`](Self::build), with the flight's recorded attitude or without.
    fn build_for(
        &self,
        data_path: &Path,
        data: &FlightData,
        recorded: bool,
    ) -> Result<Model, SpecError> {
        let mut spec = match &self.model_file {
            Some(path) => ModelSpec::load(path)?,
            None => {
                let vehicle =
                    self.vehicle
                        .or(data.meta.vehicle)
                        .ok_or_else(|| SpecError::NoVehicle {
                            data: data_path.to_path_buf(),
                        })?;
                let mut s = ModelSpec::baseline(vehicle);
                if let Some(a) = &data.meta.aircraft {
                    s.aircraft = a.clone();
                    s.base_dir = data_path.parent().map(Path::to_path_buf);
                }
                s
            }
        };
        if let Some(a) = &self.aircraft {
            spec.aircraft = a.clone();
            spec.base_dir = None;
        }
        if let Some(list) = &self.effects {
            spec.add_effect_list(list)?;
        }
        let origin = Origin {
            latitude_deg: data
                .meta
                .latitude_deg
                .unwrap_or(Origin::default().latitude_deg),
            longitude_deg: data.meta.longitude_deg.unwrap_or(0.0),
            altitude_m: data.meta.altitude_m.unwrap_or(0.0),
        };
        if spec.vehicle == VehicleKind::FixedWing && data.controls.is_none() {
            return Err(SpecError::NoControls {
                data: data_path.to_path_buf(),
            });
        }
        let attitude = data
            .attitude
            .as_ref()
            .filter(|_| recorded)
            .and_then(|a| RecordedAttitude::new(&data.time, a))
            .map(Arc::new);
        spec.build_recorded(origin, attitude)
            .map_err(|e| SpecError::Building(Box::new(e)))
    }
}

/// [`SpecError::FieldType`].
fn field_type(field: &'static str, expected: &'static str) -> SpecError {
    SpecError::FieldType { field, expected }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parameter_given_twice_is_refused_not_overwritten() {
        for (spec, key) in [
            ("wind:north_mps=1,north_mps=3", "north_mps"),
            ("nav_delay:delay_s=0.5, delay_s=0.1", "delay_s"),
            ("aircraft:c_m_q=-20,c_m_q=-10", "c_m_q"),
            ("aircraft:c_m_q,c_m_q", "c_m_q"),
            ("term(m=k*q):k=1,k=2", "k"),
        ] {
            let e = EffectSpec::parse(spec).unwrap_err();
            assert!(
                matches!(&e, SpecError::RepeatedParameter { key: k, .. } if k == key),
                "{spec}: {e}"
            );
            assert!(e.to_string().contains("is given twice"), "{e}");
        }
        assert!(EffectSpec::parse("wind:north_mps=1,east_mps=3").is_ok());
    }

    #[test]
    fn model_file_with_effect_parameters() {
        let spec = ModelSpec::from_toml(
            r#"
            vehicle = "fixed-wing"
            aircraft = "aerosonde"
            effects = ["wind", "actuator_lag"]
            [wind]
            north_mps = 5.0
            east_mps = -1
            [origin]
            latitude_deg = 10.0
            "#,
        )
        .unwrap();
        let m = spec.build(Origin::default()).unwrap();
        assert_eq!(m.effect_names(), ["wind", "actuator_lag"]);
        assert_eq!(
            m.effects[0].wind_at(glam::DVec3::ZERO, 0.0),
            glam::DVec3::new(5.0, -1.0, 0.0)
        );
        assert_eq!(m.origin.latitude_deg, 10.0);
    }

    #[test]
    fn bad_model_files_say_what_is_wrong() {
        for (text, needle) in [
            ("effects = []", "vehicle"),
            ("vehicle = \"boat\"", "boat"),
            ("vehicle = \"point-mass\"\neffects = [\"magic\"]", "magic"),
            ("vehicle = \"point-mass\"\n[wind]\nnorth_mps = 1", "wind"),
            (
                "vehicle = \"point-mass\"\neffects = [\"wind\"]\n[wind]\nspeed = 1",
                "",
            ),
        ] {
            let r = ModelSpec::from_toml(text).and_then(|s| s.build(Origin::default()));
            let e = format!("{:#}", r.unwrap_err());
            assert!(e.contains(needle), "{text}: {e}");
        }
        let r = ModelSpec::from_toml("vehicle = \"point-mass\"\neffects = [\"prop_torque\"]")
            .unwrap()
            .build(Origin::default());
        assert!(format!("{:#}", r.unwrap_err()).contains("does not apply"));
    }

    #[test]
    fn effect_spec_round_trips() {
        let e = EffectSpec::parse("wind:north_mps=5,east_mps=-2.5").unwrap();
        assert_eq!(EffectSpec::parse(&e.to_arg()).unwrap(), e);
        assert!(EffectSpec::parse("wind:north_mps=inf").is_err());
        assert!(EffectSpec::parse("wind:north_mps").is_err());
    }

    /// A term's spec: `term:AXIS=EXPR` (blanks aside) and `term(AXIS=EXPR):k=v` name the same
    /// effect, write back as given, and refuse what does not read with the column in the
    /// argument.
    #[test]
    fn term_specs_round_trip_and_name_the_column() {
        let short = EffectSpec::parse("term:m = k * thrust").unwrap();
        assert_eq!(short.name, "term(m=k*thrust)");
        assert!(short.is_term() && short.params.is_empty());
        assert_eq!(short.to_arg(), "term:m=k*thrust");
        assert_eq!(EffectSpec::parse(&short.to_arg()).unwrap(), short);
        let valued = EffectSpec::parse("term(m=k*thrust):k=0.5").unwrap();
        assert_eq!(valued.name, short.name);
        assert_eq!(valued.params, [("k".to_string(), 0.5)]);
        assert_eq!(EffectSpec::parse(&valued.to_arg()).unwrap(), valued);
        for (bad, column) in [
            ("term:m=k*trhust", 10),
            ("term(m=k*(alpha):k=1", 10),
            ("term:q=k*alpha", 6),
        ] {
            match EffectSpec::parse(bad) {
                Err(SpecError::Term { column: c, .. }) => assert_eq!(c, column, "{bad}"),
                other => panic!("{bad}: {other:?}"),
            }
        }
        let spec = ModelSpec::from_toml(
            "vehicle = \"fixed-wing\"\n[[term]]\naxis = \"m\"\nexpr = \"k * thrust\"\nk = 0.5\n",
        )
        .unwrap();
        assert_eq!(spec.effects, [valued]);
    }
}
