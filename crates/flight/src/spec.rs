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

use anyhow::{bail, Context};

use super::data::FlightData;
use super::effects::{catalogue_names, find, Effect, EffectContext, Origin};
use super::model::{Model, Vehicle};
use super::params::FixedWingParams;
use super::VehicleKind;

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

/// The name under which `--add`/`--hidden` address the aircraft's own numbers.
pub const AIRCRAFT: &str = "aircraft";

impl EffectSpec {
    /// Parse `name[:k=v,k=v]`.
    ///
    /// # Errors
    /// Unknown effect name, malformed `k=v`, non-numeric or non-finite value.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (name, rest) = match text.split_once(':') {
            Some((n, r)) => (n.trim(), r),
            None => (text.trim(), ""),
        };
        let aircraft = name == AIRCRAFT;
        if !aircraft && find(name).is_none() {
            return Err(format!(
                "unknown effect `{name}` (known: {}, or aircraft:KEY for the aircraft's own \
                 numbers)",
                catalogue_names().join(", ")
            ));
        }
        let mut params = Vec::new();
        let mut fit = Vec::new();
        for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let Some((k, v)) = kv.split_once('=') else {
                if aircraft {
                    let key = crate::params::keys::find(kv).ok_or_else(|| {
                        format!("`{kv}` in `{text}` is not an aircraft parameter")
                    })?;
                    fit.push(key.name.to_string());
                    continue;
                }
                return Err(format!("`{kv}` in `{text}` is not name=value"));
            };
            if aircraft && crate::params::keys::find(k.trim()).is_none() {
                return Err(format!(
                    "`{}` in `{text}` is not an aircraft parameter",
                    k.trim()
                ));
            }
            let value: f64 = v
                .trim()
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| format!("`{v}` for `{k}` in `{text}` is not a finite number"))?;
            params.push((k.trim().to_string(), value));
        }
        if aircraft && params.is_empty() && fit.is_empty() {
            return Err(format!(
                "`{text}` names no aircraft parameter (aircraft:KEY or aircraft:KEY=VALUE)"
            ));
        }
        Ok(Self {
            name: name.to_string(),
            params,
            fit,
        })
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
    pub fn build(&self, ctx: &EffectContext) -> Result<Box<dyn Effect>, String> {
        let info = find(&self.name).ok_or_else(|| {
            format!(
                "unknown effect `{}` (known: {})",
                self.name,
                catalogue_names().join(", ")
            )
        })?;
        let mut effect = info.build(ctx);
        for (k, v) in &self.params {
            effect
                .set_param(k, *v)
                .map_err(|e| format!("`{}`: {e}", self.to_arg()))?;
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
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let text = wireflight_fsio::read_text(path)
            .with_context(|| format!("{}: cannot read", path.display()))?;
        let mut spec = Self::from_toml(&text)
            .with_context(|| format!("{}: bad model file", path.display()))?;
        spec.base_dir = path.parent().map(Path::to_path_buf);
        Ok(spec)
    }

    /// Parse model-file text.
    ///
    /// # Errors
    /// As [`load`](Self::load), without the file name.
    pub fn from_toml(text: &str) -> anyhow::Result<Self> {
        let table: toml::Table = text.parse()?;
        let vehicle: VehicleKind = match table.get("vehicle") {
            Some(toml::Value::String(s)) => s.parse().map_err(anyhow::Error::msg)?,
            Some(_) => bail!("field `vehicle` must be a string"),
            None => bail!("missing field `vehicle` (point-mass or fixed-wing)"),
        };
        let mut spec = Self::baseline(vehicle);
        if let Some(v) = table.get("aircraft") {
            spec.aircraft = v
                .as_str()
                .context("field `aircraft` must be a string")?
                .to_string();
        }
        let names: Vec<String> = match table.get("effects") {
            None => Vec::new(),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| {
                    v.as_str()
                        .map(str::to_string)
                        .context("field `effects` must list effect names as strings")
                })
                .collect::<anyhow::Result<_>>()?,
            Some(_) => bail!("field `effects` must be an array of names"),
        };
        for name in &names {
            let mut effect = EffectSpec::parse(name).map_err(anyhow::Error::msg)?;
            if let Some(params) = table.get(name.as_str()) {
                let params = params
                    .as_table()
                    .with_context(|| format!("`[{name}]` must be a table of parameters"))?;
                for (k, v) in params {
                    let value = v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .with_context(|| format!("`{name}.{k}` must be a number"))?;
                    effect.params.push((k.clone(), value));
                }
            }
            spec.effects.push(effect);
        }
        for (key, value) in &table {
            let known = ["vehicle", "aircraft", "effects", "origin"].contains(&key.as_str())
                || names.contains(key);
            if !known {
                bail!("unknown field `{key}` (a parameter table for an effect not in `effects`?)");
            }
            if key == "origin" {
                let t = value.as_table().context("`[origin]` must be a table")?;
                for (k, v) in t {
                    let slot = match k.as_str() {
                        "latitude_deg" => 0,
                        "longitude_deg" => 1,
                        "altitude_m" => 2,
                        _ => bail!("unknown field `origin.{k}`"),
                    };
                    let v = v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .with_context(|| format!("`origin.{k}` must be a number"))?;
                    Origin::check_field(k, v).map_err(|e| anyhow::anyhow!("`origin.{k}`: {e}"))?;
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
    pub fn add_effect_list(&mut self, list: &str) -> Result<(), String> {
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
    pub fn build(&self, default_origin: Origin) -> anyhow::Result<Model> {
        let origin = self.origin(default_origin);
        origin.check().map_err(|e| anyhow::anyhow!("origin: {e}"))?;
        let vehicle = match self.vehicle {
            VehicleKind::PointMass => Vehicle::PointMass,
            VehicleKind::FixedWing => {
                Vehicle::FixedWing(Box::new(FixedWingParams::load(&self.aircraft_source())?))
            }
        };
        let mut model = Model::new(vehicle, origin);
        let ctx = model.effect_context();
        for e in &self.effects {
            if e.is_aircraft() {
                if let Some(k) = e.fit.first() {
                    bail!(
                        "`{}`: a model needs a value for aircraft parameter `{k}`",
                        e.to_arg()
                    );
                }
                for (k, v) in &e.params {
                    model.set_aircraft(k, *v).map_err(anyhow::Error::msg)?;
                }
                continue;
            }
            let effect = e.build(&ctx).map_err(anyhow::Error::msg)?;
            model.add_effect(effect).map_err(anyhow::Error::msg)?;
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
    pub fn build(&self, data_path: &Path, data: &FlightData) -> anyhow::Result<Model> {
        let mut spec = match &self.model_file {
            Some(path) => ModelSpec::load(path)?,
            None => {
                let vehicle = self.vehicle.or(data.meta.vehicle).with_context(|| {
                    format!(
                        "{}: no `# vehicle:` metadata; say which model with --vehicle or \
                         --model FILE",
                        data_path.display()
                    )
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
            spec.add_effect_list(list).map_err(anyhow::Error::msg)?;
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
            bail!(
                "{}: a fixed-wing model needs the control columns",
                data_path.display()
            );
        }
        spec.build(origin).context("building the model")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
