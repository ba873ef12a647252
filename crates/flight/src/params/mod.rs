//! Parameter sets of the fixed-wing model (Beard & McLain), read from TOML.
//!
//! The format is `assets/aircraft/aerosonde.toml` (documented in `docs/flight-model.md`):
//! tables `[mass]`, `[geometry]`, `[longitudinal]`, `[lateral]`, `[propulsion]`. Unknown keys
//! are errors (a misspelt coefficient must not silently become zero).

pub mod keys;
pub mod physical;
pub mod suggest;

use std::path::{Path, PathBuf};

use serde::Deserialize;

/// A parameter set that cannot be had: an unknown name, an unreadable file, or contents that
/// are not a valid set. Every message names the set's file (or name).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ParamSetError {
    /// Neither a built-in set nor a file.
    #[error("unknown aircraft `{0}` (built in: aerosonde; or a .toml file)")]
    Unknown(String),
    /// The file could not be read.
    #[error("{}: cannot read", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// TOML syntax, a missing or unknown key, a value of the wrong type.
    #[error("{origin}: bad parameter set: {problem}")]
    Toml {
        /// The file (or name) of the set.
        origin: String,
        /// What the TOML reader says, with the line and column, in one bounded line.
        problem: String,
    },
    /// A number outside its key's range ([`keys::KEYS`]), or not finite.
    #[error("{origin}: {table}.{name} = {value} is outside its range [{lo:e}, {hi:e}] {unit}")]
    OutOfRange {
        /// The file (or name) of the set.
        origin: String,
        /// The key's table.
        table: &'static str,
        /// The key.
        name: &'static str,
        /// The value.
        value: f64,
        /// The least valid value.
        lo: f64,
        /// The greatest valid value.
        hi: f64,
        /// The key's unit.
        unit: &'static str,
    },
    /// An inertia tensor that is singular or not positive definite.
    #[error(
        "{origin}: the inertia tensor is singular or not positive definite (Jx·Jz ≤ \
         Jxz², to 1e-9 relative): jx = {jx}, jz = {jz}, jxz = {jxz}"
    )]
    SingularInertia {
        /// The file (or name) of the set.
        origin: String,
        /// Jx, kg·m².
        jx: f64,
        /// Jz, kg·m².
        jz: f64,
        /// Jxz, kg·m².
        jxz: f64,
    },
}

/// Mass and inertia.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Mass {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Roll inertia Jx, kg·m².
    pub jx: f64,
    /// Pitch inertia Jy, kg·m².
    pub jy: f64,
    /// Yaw inertia Jz, kg·m².
    pub jz: f64,
    /// Product of inertia Jxz, kg·m².
    pub jxz: f64,
}

/// Wing geometry and the baseline's constant air density.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Wing area S, m².
    pub s_wing: f64,
    /// Span b, m.
    pub b: f64,
    /// Mean chord c, m.
    pub c: f64,
    /// Oswald efficiency e.
    pub e: f64,
    /// Constant air density of the baseline, kg/m³.
    pub rho: f64,
}

/// Longitudinal coefficients (per radian).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct Longitudinal {
    pub c_l_0: f64,
    pub c_l_alpha: f64,
    pub c_l_q: f64,
    pub c_l_delta_e: f64,
    pub c_d_p: f64,
    pub c_d_q: f64,
    pub c_d_delta_e: f64,
    pub c_m_0: f64,
    pub c_m_alpha: f64,
    pub c_m_q: f64,
    pub c_m_delta_e: f64,
    /// Steepness M of the stall blend σ(α).
    pub m_blend: f64,
    /// Stall angle α0 of the blend, rad.
    pub alpha0: f64,
}

/// Lateral coefficients (per radian).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct Lateral {
    pub c_y_0: f64,
    pub c_y_beta: f64,
    pub c_y_p: f64,
    pub c_y_r: f64,
    pub c_y_delta_a: f64,
    pub c_y_delta_r: f64,
    pub c_ell_0: f64,
    pub c_ell_beta: f64,
    pub c_ell_p: f64,
    pub c_ell_r: f64,
    pub c_ell_delta_a: f64,
    pub c_ell_delta_r: f64,
    pub c_n_0: f64,
    pub c_n_beta: f64,
    pub c_n_p: f64,
    pub c_n_r: f64,
    pub c_n_delta_a: f64,
    pub c_n_delta_r: f64,
}

/// The simple propeller model: thrust = ½ρ S_prop C_prop ((k_motor δt)² − Va²).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Propulsion {
    /// Propeller disc area, m².
    pub s_prop: f64,
    /// Propeller efficiency coefficient.
    pub c_prop: f64,
    /// Motor constant, m/s per unit throttle.
    pub k_motor: f64,
}

/// A fixed-wing parameter set.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FixedWingParams {
    /// Name, e.g. `aerosonde`.
    pub name: String,
    /// Mass and inertia.
    pub mass: Mass,
    /// Geometry.
    pub geometry: Geometry,
    /// Longitudinal aerodynamics.
    pub longitudinal: Longitudinal,
    /// Lateral aerodynamics.
    pub lateral: Lateral,
    /// Propulsion.
    pub propulsion: Propulsion,
}

/// The Aerosonde set shipped in `assets/aircraft/aerosonde.toml`.
const AEROSONDE_TOML: &str = include_str!("../../../../assets/aircraft/aerosonde.toml");

impl FixedWingParams {
    /// Parse a parameter set from TOML text; `origin` names the source in errors.
    ///
    /// # Errors
    /// TOML syntax errors, missing or unknown keys, non-finite or non-physical values
    /// (mass, inertias, areas, span, chord, density must be > 0).
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, ParamSetError> {
        let p: FixedWingParams = toml::from_str(text).map_err(|e| ParamSetError::Toml {
            origin: origin.to_string(),
            problem: wireflight_data::format::toml_problem(text, &e),
        })?;
        // Every number within its key's range (the ranges `--add aircraft:KEY` fits within):
        // positive sizes, finite coefficients.
        for k in keys::KEYS {
            let v = keys::get(&p, k.name).unwrap_or(f64::NAN);
            let (lo, hi) = k.range;
            if !(v.is_finite() && v >= lo && v <= hi) {
                return Err(ParamSetError::OutOfRange {
                    origin: origin.to_string(),
                    table: k.table,
                    name: k.name,
                    value: v,
                    lo,
                    hi,
                    unit: k.unit,
                });
            }
        }
        if !p.mass.inertia_is_regular() {
            return Err(ParamSetError::SingularInertia {
                origin: origin.to_string(),
                jx: p.mass.jx,
                jz: p.mass.jz,
                jxz: p.mass.jxz,
            });
        }
        Ok(p)
    }

    /// A named built-in set (`aerosonde`) or a TOML file path.
    ///
    /// # Errors
    /// Unknown name / unreadable file / bad contents, naming the file.
    pub fn load(name_or_path: &str) -> Result<Self, ParamSetError> {
        if name_or_path == "aerosonde" {
            return Self::from_toml(AEROSONDE_TOML, "assets/aircraft/aerosonde.toml");
        }
        let path = Path::new(name_or_path);
        if path.extension().is_none() && !path.exists() {
            return Err(ParamSetError::Unknown(name_or_path.to_string()));
        }
        let text = wireflight_fsio::read_config_text(path).map_err(|source| {
            ParamSetError::Unreadable {
                path: path.to_path_buf(),
                source,
            }
        })?;
        Self::from_toml(&text, &path.display().to_string())
    }

    /// The Aerosonde UAV.
    pub fn aerosonde() -> Self {
        Self::from_toml(AEROSONDE_TOML, "aerosonde").expect("the shipped set is valid")
    }
}

impl Mass {
    /// Whether the inertia tensor is positive definite with room to spare: Jx·Jz − Jxz² above
    /// 1e-9 of Jx·Jz (the Γ constants divide by it; closer to singular they are unbounded).
    pub fn inertia_is_regular(&self) -> bool {
        let gamma = self.jx * self.jz - self.jxz * self.jxz;
        gamma.is_finite() && gamma > 1e-9 * (self.jx * self.jz).abs()
    }
}

/// The Γ constants of the rotational equations (Beard & McLain eq. 3.13), precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gammas {
    /// Γ1 … Γ8.
    pub g: [f64; 8],
}

impl Gammas {
    /// From the inertia tensor.
    pub fn new(m: &Mass) -> Self {
        let gamma = m.jx * m.jz - m.jxz * m.jxz;
        Self {
            g: [
                m.jxz * (m.jx - m.jy + m.jz) / gamma,
                (m.jz * (m.jz - m.jy) + m.jxz * m.jxz) / gamma,
                m.jz / gamma,
                m.jxz / gamma,
                (m.jz - m.jx) / m.jy,
                m.jxz / m.jy,
                ((m.jx - m.jy) * m.jx + m.jxz * m.jxz) / gamma,
                m.jx / gamma,
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aerosonde_loads_and_matches_the_spec() {
        let p = FixedWingParams::aerosonde();
        assert_eq!(p.mass.mass_kg, 11.0);
        assert_eq!(p.longitudinal.c_m_q, -38.21);
        assert_eq!(p.propulsion.k_motor, 80.0);
    }

    #[test]
    fn misspelt_or_bad_values_are_errors() {
        let bad = AEROSONDE_TOML.replace("c_l_q", "c_lq");
        let e = FixedWingParams::from_toml(&bad, "x.toml").unwrap_err();
        assert!(format!("{e:#}").contains("x.toml"), "{e:#}");
        let bad = AEROSONDE_TOML.replace("mass_kg = 11.0", "mass_kg = -1.0");
        assert!(FixedWingParams::from_toml(&bad, "x.toml").is_err());
    }

    #[test]
    fn gammas_reduce_to_euler_equations_without_jxz() {
        let m = Mass {
            mass_kg: 1.0,
            jx: 2.0,
            jy: 3.0,
            jz: 5.0,
            jxz: 0.0,
        };
        let g = Gammas::new(&m).g;
        assert_eq!(g[0], 0.0);
        assert!((g[1] - (5.0 * 2.0) / 10.0).abs() < 1e-15); // (Jz−Jy)/Jx
        assert!((g[2] - 0.5).abs() < 1e-15 && (g[7] - 0.2).abs() < 1e-15);
    }
}
