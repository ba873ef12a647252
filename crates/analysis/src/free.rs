//! The numbers a fit moves — parameters of an effect in the model, numbers of the aircraft's
//! parameter set — each with its range and typical size, read from a model and set into one.

use wireflight_flight::effects::Effect;
use wireflight_flight::model::Model;

/// An aircraft number that cannot be fitted.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum KeyError {
    /// No key of the parameter set has this name.
    #[error("unknown aircraft parameter `{0}`")]
    Unknown(String),
    /// This pattern (a name, or a prefix ending in `*`) matches no key.
    #[error(
        "`{0}` matches no aircraft parameter (keys such as c_m_alpha, c_ell_p, mass_kg, jx; a \
         prefix ends in `*`, e.g. c_m_*)"
    )]
    NoMatch(String),
    /// The model is a point mass, which has no parameter set.
    #[error("a point mass has no aircraft parameter `{0}`")]
    PointMass(String),
}

/// The effect named `name` in `model`.
pub(crate) fn effect<'m>(model: &'m Model, name: &str) -> Option<&'m dyn Effect> {
    model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .map(|e| e.as_ref())
}

/// Whose number a fitted parameter is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Owner {
    /// A parameter of the effect of that name.
    Effect(&'static str),
    /// A number of the aircraft's parameter set.
    Aircraft,
}

/// A parameter being fitted: its name, range and typical size, and whose it is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Free {
    pub name: &'static str,
    pub range: (f64, f64),
    pub scale: f64,
    pub owner: Owner,
}

/// Set the free parameters to `theta`, each kept inside its range.
pub(crate) fn set_values(model: &mut Model, free: &[Free], theta: &[f64]) {
    for (f, v) in free.iter().zip(theta) {
        let v = v.clamp(f.range.0, f.range.1);
        let _ = match f.owner {
            Owner::Effect(name) => model
                .effect_mut(name)
                .map_or(Ok(()), |e| e.set_param(f.name, v))
                .is_ok(),
            Owner::Aircraft => model.set_aircraft(f.name, v).is_ok(),
        };
    }
}

/// The current values of the free parameters.
pub(crate) fn values(model: &Model, free: &[Free]) -> Vec<f64> {
    free.iter()
        .map(|f| {
            match f.owner {
                Owner::Effect(name) => effect(model, name).and_then(|e| e.param(f.name)),
                Owner::Aircraft => model.aircraft(f.name),
            }
            .unwrap_or(0.0)
        })
        .collect()
}

/// `theta` moved by `step` (in units of each parameter's scale), each value kept inside its
/// range.
pub(crate) fn stepped(theta: &[f64], step: &[f64], free: &[Free]) -> Vec<f64> {
    theta
        .iter()
        .zip(step)
        .zip(free)
        .map(|((t, s), f)| (t + s * f.scale).clamp(f.range.0, f.range.1))
        .collect()
}

/// Smallest typical size of an aircraft number that is zero in the set (a coefficient of 0:
/// a change of 0.01 is already a large one for most).
const AIRCRAFT_MIN_SCALE: f64 = 0.01;

/// The aircraft numbers `keys` of `model` as free parameters, each scaled by a tenth of its
/// value and kept within its physical range ([`wireflight_flight::params::physical`]).
///
/// # Errors
/// An unknown key; a point mass.
pub(crate) fn aircraft_free(model: &Model, keys: &[&'static str]) -> Result<Vec<Free>, KeyError> {
    keys.iter()
        .map(|&k| {
            let key = wireflight_flight::params::keys::find(k)
                .ok_or_else(|| KeyError::Unknown(k.to_string()))?;
            let v = model
                .aircraft(k)
                .ok_or_else(|| KeyError::PointMass(k.to_string()))?;
            Ok(Free {
                name: key.name,
                range: wireflight_flight::params::physical::fit_range(key, v),
                scale: (0.1 * v.abs()).max(AIRCRAFT_MIN_SCALE),
                owner: Owner::Aircraft,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The messages are those the command line has always printed.
    #[test]
    fn key_errors_name_the_key() {
        assert_eq!(
            KeyError::Unknown("c_q".into()).to_string(),
            "unknown aircraft parameter `c_q`"
        );
        assert_eq!(
            KeyError::NoMatch("c_q_*".into()).to_string(),
            "`c_q_*` matches no aircraft parameter (keys such as c_m_alpha, c_ell_p, mass_kg, jx; \
             a prefix ends in `*`, e.g. c_m_*)"
        );
        assert_eq!(
            KeyError::PointMass("mass_kg".into()).to_string(),
            "a point mass has no aircraft parameter `mass_kg`"
        );
    }
}
