//! Which numbers of the aircraft's parameter set could explain the misfit — all of them at
//! once, by the score test.
//!
//! For every key, the change of each window's residuals per change of the key (one flight per
//! key and window, from the baseline's fitted starts), less what a start change could absorb;
//! the misfit that a least-squares change of that key alone would remove is (d̃ᵀr)²/(d̃ᵀd̃)
//! (exact when the residuals are linear in the key). The most promising keys are then fitted
//! like any candidate, and all scores serve as evidence of which term the misfit points to.

use rayon::prelude::*;

use super::fit::{effect_free, Baseline};
use crate::compare::start::Scratch;
use crate::compare::Prepared;
use crate::free::values;
use crate::lm::newton_gain;
use crate::profile::{normal_equations, Linearised};
use wireflight_flight::effects::Effect;
use wireflight_flight::model::Model;
use wireflight_flight::params::keys::{AircraftKey, KEYS};

/// What one key could do.
#[derive(Clone, Copy, Debug)]
pub struct KeyScore {
    /// The key.
    pub key: &'static AircraftKey,
    /// The misfit (χ², noise units squared) a change of this key alone would remove, to
    /// first order.
    pub reduction: f64,
}

/// Relative finite-difference step of a key (of a tenth of its value, at least 0.01).
const STEP: f64 = 0.01;

/// Score every key of a fixed-wing model's parameter set against the baseline; best first.
/// Empty for a point mass.
pub fn score_aircraft(base: &Model, prep: &Prepared, baseline: &Baseline) -> Vec<KeyScore> {
    // The stall blend cannot be told where the flight never comes near the stall: moved, it
    // absorbs whatever the linear terms miss in the flown range.
    let no_stall = crate::identify::stall_out_of_reach(base, std::iter::once(prep.data)).is_some();
    let perturbed: Vec<(usize, Model, f64)> = KEYS
        .iter()
        .enumerate()
        .filter(|(_, key)| !(no_stall && matches!(key.name, "alpha0" | "m_blend")))
        .filter_map(|(k, key)| {
            let v = base.aircraft(key.name)?;
            let h = STEP * (0.1 * v.abs()).max(0.01);
            let mut m = base.clone();
            m.set_aircraft(key.name, v + h).ok()?;
            Some((k, m, h))
        })
        .collect();
    if perturbed.is_empty() {
        return Vec::new();
    }
    let sums: Vec<Vec<(f64, f64)>> = prep
        .windows
        .par_iter()
        .zip(baseline.fits.par_iter())
        .map(|(&w, fit)| {
            let span = prep.fit_range(w);
            let lin = Linearised::of(base, fit);
            let x = fit.state;
            let r = &fit.residuals;
            let m = r.len();
            let mut scratch = Scratch::default();
            let jtr = lin.jt(r);
            let mut rk = Vec::with_capacity(m);
            let mut d = Vec::with_capacity(m);
            perturbed
                .iter()
                .map(|(_, model, h)| {
                    prep.window_residuals(model, span, &x, &mut scratch, &mut rk);
                    if rk.len() != m {
                        return (0.0, 0.0);
                    }
                    d.clear();
                    d.extend(rk.iter().zip(r).map(|(a, b)| (a - b) / h));
                    lin.projected_products(&d, r, &jtr)
                })
                .collect()
        })
        .collect();
    let mut scores: Vec<KeyScore> = perturbed
        .iter()
        .enumerate()
        .map(|(j, (k, _, _))| {
            let (dr, dd) = sums
                .iter()
                .fold((0.0, 0.0), |(a, b), w| (a + w[j].0, b + w[j].1));
            KeyScore {
                key: &KEYS[*k],
                reduction: if dd > 0.0 { dr * dr / dd } else { 0.0 },
            }
        })
        .collect();
    scores.sort_by(|a, b| b.reduction.total_cmp(&a.reduction));
    scores
}

/// What adding `effect` to `model` could remove of the misfit, to first order: the
/// Gauss–Newton gain gᵀA⁻¹g of its free parameters at their absent values, where the model
/// with the effect is `model` itself and the baseline's start fits are its own (so a wind's
/// columns need no flight). None when a free parameter has no absent value (the effect is
/// never the model without it) or the effect cannot be added.
///
/// Exact when the residuals are linear in the parameters; the screen allows for a fit that
/// removes several times it ([`super::fit::could_be_significant`]).
pub(crate) fn score_effect(
    model: &Model,
    effect: Box<dyn Effect>,
    prep: &Prepared,
    baseline: &Baseline,
) -> Option<f64> {
    let name = effect.name();
    let mut with = model.clone();
    with.add_effect(effect).ok()?;
    let free = effect_free(&mut with, name, &[], prep, false).ok()?;
    if free.is_empty() {
        return None;
    }
    let info = with.effects.iter().find(|e| e.name() == name)?.info();
    let e = with.effect_mut(name)?;
    for f in &free {
        let absent = info.param(f.name)?.absent?;
        e.set_param(f.name, absent).ok()?;
    }
    let theta = values(&with, &free);
    let lin: Vec<Linearised> = baseline
        .fits
        .iter()
        .map(|f| Linearised::of(&with, f))
        .collect();
    let flown: Vec<Vec<f64>> = baseline.fits.iter().map(|f| f.residuals.clone()).collect();
    let (a, g) = normal_equations(&with, (&free, true), &theta, prep, &lin, Some(&flown));
    newton_gain(&a, &g).filter(|v| v.is_finite() && *v >= 0.0)
}
