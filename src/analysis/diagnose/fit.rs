//! Fitting one candidate correction — an effect's parameters, or numbers of the aircraft's
//! parameter set — on the misfit profiled over every window's start state, and scoring it
//! against the model without it.
//!
//! The profile is linearised around the baseline's fitted starts (variable projection: the
//! residual change a parameter causes, less what a start change could absorb), Levenberg–
//! Marquardt runs on that, and the starts are then fitted exactly at the result (repeated
//! when the linearisation was off). The covariance comes from the projected Jacobian.

use super::{AircraftChange, Candidate, Correction, DiagnoseConfig};
use crate::analysis::compare::start::{Scratch, StartFit};
use crate::analysis::compare::{
    compare_corrections, compare_from_jacobians, compare_refit, compare_with_fits, Comparison,
    Prepared,
};
use crate::analysis::profile::{
    add_into, aircraft_free, damped_trial, effect, linear_profile, moving_frame, newton_gain,
    normal_equations, perturbed_models, set_values, values, window_normal_towards, Free,
    Linearised, Owner, FIT_TOL,
};
use crate::flight::effects::{Effect, ParamSpec};
use crate::flight::model::{Model, State};
use crate::numeric::{chi2_quantile, invert, solve_in_place};

/// The fitted parameters' covariance in their own units (row-major), or None when the data
/// do not determine them.
fn covariance(a: &[f64], free: &[Free], cmp: &Comparison) -> Option<Vec<f64>> {
    let np = free.len();
    let inv = invert(a, np)?;
    let rho = cmp.residual_autocorrelation().clamp(0.0, 0.99);
    let s2 = (cmp.chi2 / cmp.dof.max(1.0)).max(1.0) * (1.0 + rho) / (1.0 - rho);
    let mut cov = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            cov[i * np + k] = inv[i * np + k] * s2 * free[i].scale * free[k].scale;
        }
    }
    cov.iter()
        .all(|v| v.is_finite())
        .then_some(cov)
        .filter(|c| (0..np).all(|i| c[i * np + i] >= 0.0))
}

/// Whose start fits a linearised fit begins from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Starts {
    /// The model's without the correction (the baseline's): the candidate's own while its
    /// parameters are at their absent values (it is then that model), until the first step.
    Base,
    /// The candidate's own, fitted exactly at its parameters.
    Own,
}

/// Levenberg–Marquardt on the parameters over the linearised profile; updates `model`,
/// `theta` and the windows' starts. Returns the linearised χ² reached, and each window's
/// residuals of `model` from the starts `lin` ends with when they were flown (no trial was
/// accepted).
///
/// The normal equations are taken at the starts the last accepted trial was flown from,
/// with that flight's residuals — one flight per window less per iteration — and the starts
/// then move to where the linearisation puts them at the new parameters.
///
/// A wind ([`moving_frame`]) begun from the baseline's starts at its absent values stops
/// after its first step: its columns need no flight while the starts are its own, and the
/// exact refit that follows makes them so again, where further passes about the baseline's
/// starts would fly three columns a window each (measured on the hour's screening: 698
/// flights before, 298 after).
#[allow(clippy::too_many_arguments)]
fn fit_linearised(
    model: &mut Model,
    (free, starts): (&[Free], Starts),
    theta: &mut Vec<f64>,
    prep: &Prepared,
    lin: &mut [Linearised],
    iterations: usize,
) -> (f64, Option<Vec<Vec<f64>>>) {
    let mut own = match starts {
        Starts::Own => true,
        Starts::Base => at_absent_values(model, free, theta),
    };
    let first_step_only = starts == Starts::Base && own && moving_frame(model, free).is_some();
    let (mut chi2, _, mut flown) = linear_profile(model, prep, lin);
    // The start changes of the last accepted trial, not yet applied.
    let mut pending: Option<Vec<Vec<f64>>> = None;
    let mut lambda = 1e-3;
    for _ in 0..iterations {
        let (a0, g) = normal_equations(model, (free, own), theta, prep, lin, Some(&flown));
        if let Some(dq) = pending.take() {
            move_starts(lin, &dq);
        }
        if newton_gain(&a0, &g).is_some_and(|v| v < FIT_TOL.max(1e-6 * chi2)) {
            break;
        }
        let mut accepted = None;
        for _ in 0..8 {
            let Some(trial) = damped_trial(&a0, &g, lambda, theta, free) else {
                lambda *= 10.0;
                continue;
            };
            if trial == *theta {
                // The ranges clamp the step to no move: the parameters that would move are at
                // their bounds, and a shorter step stops there too (an actuator lag fitted
                // to its least τ flew eight trials a window for nothing).
                break;
            }
            let mut m = model.clone();
            set_values(&mut m, free, &trial);
            let (c, dq_trial, flown_trial) = linear_profile(&m, prep, lin);
            if c.is_finite() && c < chi2 {
                accepted = Some((trial, m, c, dq_trial, flown_trial));
                lambda = (lambda / 10.0).max(1e-9);
                break;
            }
            lambda *= 10.0;
        }
        let Some((trial, m, c, dq_trial, flown_trial)) = accepted else {
            break;
        };
        let gain = chi2 - c;
        *theta = trial;
        *model = m;
        chi2 = c;
        flown = flown_trial;
        // Each start belongs where the linearisation puts it at these parameters.
        pending = Some(dq_trial);
        // The baseline's starts are no longer the model's own.
        own &= starts == Starts::Own;
        if gain < FIT_TOL.max(1e-6 * chi2) || first_step_only {
            break;
        }
    }
    match pending {
        Some(dq) => {
            move_starts(lin, &dq);
            (chi2, None)
        }
        None => (chi2, Some(flown)),
    }
}

/// Whether every free parameter is an effect's at its absent value: the model with it is
/// then the model without it ([`ParamSpec::absent`]).
fn at_absent_values(model: &Model, free: &[Free], theta: &[f64]) -> bool {
    free.iter().zip(theta).all(|(f, &v)| match f.owner {
        Owner::Effect(name) => effect(model, name)
            .and_then(|e| e.info().param(f.name))
            .and_then(|p| p.absent)
            .is_some_and(|a| a == v),
        Owner::Aircraft => false,
    })
}

/// Move each window's start by its change.
fn move_starts(lin: &mut [Linearised], dq: &[Vec<f64>]) {
    for (l, d) in lin.iter_mut().zip(dq) {
        l.q.iter_mut().zip(d).for_each(|(q, d)| *q += d);
    }
}

/// Fit the free parameters of the effect `name` (already in `model`) (module docs), starting
/// from the start fits `fits` of the model without it. Returns the comparison at the fitted
/// values, and the parameter covariance.
fn fit(
    model: &mut Model,
    free: &[Free],
    prep: &Prepared,
    baseline: &Baseline,
    iterations: usize,
) -> (Comparison, Option<Vec<f64>>) {
    let np = free.len();
    let fits = &baseline.fits;
    let starts: Vec<State> = fits.iter().map(|f| f.state).collect();
    if np == 0 {
        // The effect moves each start little from the baseline's: its fit begins there, with
        // the baseline's Jacobian instead of a fresh one.
        let jacobians: Vec<&[f64]> = fits.iter().map(|f| f.jacobian.as_slice()).collect();
        return (
            compare_from_jacobians(model, prep, &starts, &jacobians),
            None,
        );
    }
    let chi2_base: f64 = fits
        .iter()
        .map(|f| f.residuals.iter().map(|r| r * r).sum::<f64>())
        .sum();
    let mut theta = values(model, free);
    let mut lin: Vec<Linearised> = fits.iter().map(|f| Linearised::of(model, f)).collect();
    // `flown`: each window's residuals of `model` from `lin`'s starts, while they are at hand.
    let (mut linear, mut flown) = fit_linearised(
        model,
        (free, Starts::Base),
        &mut theta,
        prep,
        &mut lin,
        iterations,
    );
    let gain = chi2_base - linear;
    if gain.is_nan() || gain <= FIT_TOL.max(1e-6 * chi2_base) {
        // The effect explains nothing the starts could not: its best values change the misfit
        // by less than a hundredth of a noise unit, so the comparison is the baseline's.
        let own = at_absent_values(model, free, &theta);
        let (a, _) = normal_equations(model, (free, own), &theta, prep, &lin, flown.as_deref());
        let cov = covariance(&a, free, &baseline.comparison);
        return (baseline.comparison.clone(), cov);
    }
    // The linearisation is around the starts of the model without the effect; the starts are
    // then fitted exactly, and when that changes the misfit by more than the tolerance, the
    // fit is repeated around them.
    let mut exact: Option<Comparison> = None;
    for _ in 0..3 {
        let starts: Vec<State> = lin.iter().map(|l| l.state(model)).collect();
        let jacobians: Vec<&[f64]> = lin.iter().map(|l| &*l.jac).collect();
        let (cmp, new_fits) = compare_refit(model, prep, &starts, &jacobians);
        let settled = (cmp.chi2 - linear).abs() < FIT_TOL.max(1e-4 * cmp.chi2);
        flown = Some(new_fits.iter().map(|f| f.residuals.clone()).collect());
        lin = new_fits
            .into_iter()
            .map(|f| Linearised::owned(model, f))
            .collect();
        exact = Some(cmp);
        if settled {
            break;
        }
        (linear, flown) = fit_linearised(
            model,
            (free, Starts::Own),
            &mut theta,
            prep,
            &mut lin,
            iterations,
        );
    }
    let Some(cmp) = exact else {
        unreachable!("the loop runs at least once");
    };
    // The starts are the model's own fits (refitted at least once above).
    let (a, _) = normal_equations(model, (free, true), &theta, prep, &lin, flown.as_deref());
    let cov = covariance(&a, free, &cmp);
    (cmp, cov)
}

/// A model's comparison on prepared data together with its windows' start fits: what every
/// candidate effect is fitted from and scored against.
pub struct Baseline {
    /// The comparison.
    pub comparison: Comparison,
    pub(crate) fits: Vec<StartFit>,
}

impl Baseline {
    /// Compare `model` on `prep`, keeping the start fits.
    pub fn of(model: &Model, prep: &Prepared) -> Self {
        let (comparison, fits) = compare_with_fits(model, prep, None);
        Self { comparison, fits }
    }
}

/// The free parameters of the effect `name` in `model`: all but those `fixed` and those known
/// from the data's metadata. With `reset`, each is first set to its fitting start value.
pub(crate) fn effect_free(
    model: &mut Model,
    name: &str,
    fixed: &[String],
    prep: &Prepared,
    reset: bool,
) -> Result<Vec<Free>, String> {
    let info = effect(model, name)
        .map(|e| e.info())
        .ok_or_else(|| format!("effect `{name}` was not added"))?;
    for f in fixed {
        if info.param(f).is_none() {
            return Err(format!("effect `{name}` has no parameter `{f}`"));
        }
    }
    let known_origin = prep.data.meta.latitude_deg.is_some();
    let is_held =
        |p: &ParamSpec| fixed.iter().any(|f| f == p.name) || (p.from_origin && known_origin);
    let mut free = Vec::new();
    if let Some(e) = model.effect_mut(name) {
        for p in info.params.iter().filter(|p| !is_held(p)) {
            if let (Some(start), true) = (p.start, reset) {
                e.set_param(p.name, start)?;
            }
            free.push(Free {
                name: p.name,
                range: p.range,
                scale: p.scale_at(e.param(p.name).unwrap_or(0.0)),
                owner: Owner::Effect(info.name),
            });
        }
    }
    Ok(free)
}

/// What is tried: an effect added to the model, or numbers of the aircraft's set.
#[derive(Clone, Debug)]
pub(crate) enum Trial {
    Effect(String),
    Aircraft(Vec<&'static str>),
}

impl Trial {
    pub(crate) fn label(&self) -> String {
        match self {
            Trial::Effect(name) => name.clone(),
            Trial::Aircraft(keys) => format!("aircraft:{}", keys.join(",")),
        }
    }
}

/// Fit a trial (already in `model`, its free parameters `free`) and score it against the
/// baseline.
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_trial(
    base: &Model,
    mut model: Model,
    trial: &Trial,
    free: &[Free],
    prep: &Prepared,
    before: &Baseline,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, String> {
    let (after, cov) = fit(&mut model, free, prep, before, cfg.max_iterations);
    make_candidate(
        base,
        &model,
        trial,
        free,
        &before.comparison,
        &after,
        cov,
        cfg,
        candidates,
    )
}

/// Try one effect on top of `base`: fit it and score it against the baseline. `fixed` lists
/// parameters not to fit; `candidates` is how many corrections are being tried (for the
/// significance level).
///
/// # Errors
/// The effect does not apply or is already in the model; a fixed parameter it does not have.
pub fn try_effect(
    base: &Model,
    effect: Box<dyn Effect>,
    fixed: &[String],
    prep: &Prepared,
    before: &Baseline,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, String> {
    let name = effect.name().to_string();
    let mut model = base.clone();
    model.add_effect(effect)?;
    let free = effect_free(&mut model, &name, fixed, prep, true)?;
    fit_trial(
        base,
        model,
        &Trial::Effect(name),
        &free,
        prep,
        before,
        cfg,
        candidates,
    )
}

/// Try new values of numbers of the aircraft's parameter set (fitted jointly), scored against
/// the baseline.
///
/// # Errors
/// A point mass, or an unknown key.
pub fn try_aircraft(
    base: &Model,
    keys: &[&'static str],
    prep: &Prepared,
    before: &Baseline,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, String> {
    let free = aircraft_free(base, keys)?;
    fit_trial(
        base,
        base.clone(),
        &Trial::Aircraft(keys.to_vec()),
        &free,
        prep,
        before,
        cfg,
        candidates,
    )
}

/// The full pass of a screened diagnosis: the best `top` candidates (at their subset values)
/// and the base model compared on every window in one pass; for each candidate, each
/// window's share of the parameters' normal equations is taken while its start fit exists,
/// so no window's Jacobian outlives it. Each candidate's parameters then take one
/// Gauss–Newton step on all windows — the all-window estimate, whose covariance is the
/// all-window one — while its errors are those at the subset values (the two differ by a
/// few of the subset's σ, which changes the misfit by a few units in hundreds of
/// thousands).
///
/// The base model's start in each window is predicted from the first candidate's fit there
/// ([`compare_corrections`]): linearly in the candidate's parameters, with the columns of
/// its normal equations, when the base is the candidate with its parameters moved (an
/// effect whose parameters all have absent values, numbers of the set); else from the
/// base's residuals flown at the candidate's start (one flight).
pub(crate) fn full_pass(
    base: &Model,
    top: &[Candidate],
    full: &Prepared,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> (Comparison, Vec<Candidate>) {
    struct Fitting {
        model: Model,
        trial: Trial,
        free: Vec<Free>,
        theta: Vec<f64>,
        perturbed: Vec<Model>,
        /// The change of the scaled parameters that makes this the base model, if one does.
        to_base: Option<Vec<f64>>,
    }
    let fittings: Vec<Fitting> = top
        .iter()
        .filter_map(|c| {
            let mut model = base.clone();
            c.correction.apply(&mut model).ok()?;
            let (trial, free) = match &c.correction {
                Correction::Effect(e) => {
                    let held: Vec<String> = c
                        .params
                        .iter()
                        .zip(&c.held)
                        .filter(|(_, h)| **h)
                        .map(|((k, _), _)| k.clone())
                        .collect();
                    let name = e.name().to_string();
                    let free = effect_free(&mut model, &name, &held, full, false).ok()?;
                    (Trial::Effect(name), free)
                }
                Correction::Aircraft(changes) => {
                    let keys: Vec<&'static str> = changes.iter().map(|c| c.key).collect();
                    let free = aircraft_free(&model, &keys).ok()?;
                    (Trial::Aircraft(keys), free)
                }
            };
            let theta = values(&model, &free);
            let perturbed = perturbed_models(&model, &free, &theta);
            let to_base = base_values(base, &model, &c.correction, &free).map(|b| {
                b.iter()
                    .zip(&theta)
                    .zip(&free)
                    .map(|((b, t), f)| (b - t) / f.scale)
                    .collect()
            });
            Some(Fitting {
                model,
                trial,
                free,
                theta,
                perturbed,
                to_base,
            })
        })
        .collect();
    let models: Vec<&Model> = fittings.iter().map(|f| &f.model).collect();
    let (base_cmp, results) = compare_corrections(base, &models, full, |k, w, fit| {
        let f = &fittings[k];
        let lin = Linearised::of(&f.model, fit);
        // The fit's residuals are those at its start: no flight for them.
        let at_start = (!fit.residuals.is_empty()).then_some(fit.residuals.as_slice());
        let towards = if k == 0 { f.to_base.as_deref() } else { None };
        // `lin` is the model's own fit: a wind's columns need no flight.
        let (share, start) = window_normal_towards(
            &f.model,
            &f.perturbed,
            &f.free,
            full,
            w,
            &lin,
            at_start,
            (towards, true),
        );
        let start = match start {
            Some(q) => Some(q),
            // Not the candidate with other values: the base's own residuals at its start.
            None if k == 0 && !fit.jacobian.is_empty() => {
                let mut r = Vec::new();
                let span = full.fit_range(w);
                let mut scratch = Scratch::default();
                full.window_residuals(base, span, &lin.state(base), &mut scratch, &mut r);
                (r.len() == fit.residuals.len()).then(|| lin.start_absorbing(&mut r))
            }
            None => None,
        };
        (Some(share), start)
    });
    let mut out = Vec::new();
    for (f, (after, shares)) in fittings.into_iter().zip(results) {
        let np = f.free.len();
        let mut sum = (vec![0.0; np * np], vec![0.0; np]);
        for share in shares.iter().flatten() {
            add_into(&mut sum, share);
        }
        let (a, g) = sum;
        let mut model = f.model;
        let mut step: Vec<f64> = g.iter().map(|v| -v).collect();
        let mut m = a.clone();
        if np > 0 && solve_in_place(&mut m, &mut step, np).is_some() {
            let theta: Vec<f64> = f
                .theta
                .iter()
                .zip(&step)
                .zip(&f.free)
                .map(|((t, s), p)| (t + s * p.scale).clamp(p.range.0, p.range.1))
                .collect();
            set_values(&mut model, &f.free, &theta);
        }
        let cov = (np > 0).then(|| covariance(&a, &f.free, &after)).flatten();
        if let Ok(c) = make_candidate(
            base, &model, &f.trial, &f.free, &base_cmp, &after, cov, cfg, candidates,
        ) {
            out.push(c);
        }
    }
    (base_cmp, out)
}

/// The base model's values of a candidate's free parameters, when the base is the candidate
/// with other values: the set's numbers for an aircraft candidate; for an effect, the
/// absent values of its parameters when every one has one and is free (a held one keeps the
/// effect present).
fn base_values(
    base: &Model,
    model: &Model,
    correction: &Correction,
    free: &[Free],
) -> Option<Vec<f64>> {
    match correction {
        Correction::Aircraft(_) => free.iter().map(|f| base.aircraft(f.name)).collect(),
        Correction::Effect(e) => {
            let info = effect(model, e.name())?.info();
            if info.params.is_empty() || info.params.len() != free.len() {
                return None;
            }
            free.iter()
                .map(|f| info.param(f.name).and_then(|p| p.absent))
                .collect()
        }
    }
}

/// A significant candidate removes at least this fraction of the misfit above the noise (in
/// noise units): less is too little to matter, however sure the test is of it.
pub(crate) const MATERIAL: f64 = 0.2;

/// The χ² quantile a candidate's likelihood-ratio statistic must beat: the family-wise level
/// split over all `candidates` (Bonferroni), for `np` fitted parameters.
fn lr_critical(cfg: &DiagnoseConfig, candidates: usize, np: usize) -> f64 {
    let level = cfg.alpha / candidates.max(1) as f64;
    chi2_quantile(1.0 - level, np.max(1) as f64)
}

/// How many times its first-order reduction of the misfit (the score test's) an aircraft
/// number is allowed to remove when fitted before it is ruled out unfitted. The score is exact
/// when the residuals are linear in the number; over the 130 fits of the `diagnose` and
/// `independent` tests (every number fitted, wrong ones and right ones) the fit removed 0.53
/// to 1.31 times it.
const SCORE_ALLOWANCE: f64 = 4.0;

/// Whether a correction of one number whose score test promises to remove `reduction` of the
/// misfit (χ²) could be significant, even removing [`SCORE_ALLOWANCE`] times that: material
/// ([`MATERIAL`]), and a likelihood ratio above the critical value with every residual
/// independent (an upper bound). A number that could not is not worth its fit: on an hour's
/// flight with a missing wind, fitting five such numbers took a fifth of the diagnosis.
pub(crate) fn could_be_significant(
    before: &Comparison,
    reduction: f64,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> bool {
    let (chi2, dof) = (before.chi2, before.dof.max(1.0));
    let after = (chi2 - SCORE_ALLOWANCE * reduction).max(0.0);
    let (nu_b, nu_a) = ((chi2 / dof).sqrt(), (after / dof).sqrt());
    if !(reduction > 0.0 && nu_b > 1.0) {
        return false;
    }
    let material = (nu_b - nu_a) / (nu_b - 1.0) >= MATERIAL;
    let lr = if after > 0.0 {
        dof * (chi2 / after).ln()
    } else {
        f64::INFINITY
    };
    material && lr > lr_critical(cfg, candidates, 1)
}

/// Build the candidate's record from its fit.
#[allow(clippy::too_many_arguments)]
fn make_candidate(
    base: &Model,
    model: &Model,
    trial: &Trial,
    free: &[Free],
    before: &Comparison,
    after: &Comparison,
    cov: Option<Vec<f64>>,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, String> {
    let np = free.len();
    let sigma = |k: usize| cov.as_ref().map_or(f64::NAN, |c| c[k * np + k].sqrt());
    let mut params = Vec::new();
    let mut held = Vec::new();
    let mut uncertainty = Vec::new();
    let correction = match trial {
        Trial::Effect(name) => {
            let e = effect(model, name)
                .map(|e| e.clone_box())
                .ok_or_else(|| format!("effect `{name}` was not added"))?;
            for p in e.params() {
                params.push((p.name.to_string(), p.value));
                let k = free.iter().position(|f| f.name == p.name);
                held.push(k.is_none());
                uncertainty.push(k.map_or(f64::NAN, sigma));
            }
            Correction::Effect(e)
        }
        Trial::Aircraft(keys) => {
            let mut changes = Vec::new();
            for (k, key) in keys.iter().enumerate() {
                let value = model.aircraft(key).unwrap_or(f64::NAN);
                params.push((key.to_string(), value));
                held.push(false);
                uncertainty.push(sigma(k));
                changes.push(AircraftChange {
                    key,
                    was: base.aircraft(key).unwrap_or(f64::NAN),
                    value,
                });
            }
            Correction::Aircraft(changes)
        }
    };
    let correlation = match &cov {
        Some(c) => (0..np * np)
            .map(|ik| {
                let (i, k) = (ik / np, ik % np);
                c[ik] / (c[i * np + i] * c[k * np + k]).sqrt()
            })
            .collect(),
        None => Vec::new(),
    };
    let (nu_b, nu_a) = (before.noise_units(), after.noise_units());
    let excess_removed = if nu_b > 1.0 {
        ((nu_b - nu_a) / (nu_b - 1.0)).clamp(-1.5, 1.5)
    } else {
        0.0
    };
    let lr = if after.chi2 > 0.0 {
        after.independent_residuals() * (before.chi2 / after.chi2).ln()
    } else {
        f64::INFINITY
    };
    let lr_critical = lr_critical(cfg, candidates, np);
    let significant = lr > lr_critical && after.chi2 < before.chi2 && excess_removed >= MATERIAL;
    Ok(Candidate {
        effect: trial.label(),
        params,
        held,
        uncertainty,
        correlation,
        fitted: np,
        error_before: before.total,
        error_after: after.total,
        error_reduction: if before.total > 0.0 {
            (before.total - after.total) / before.total
        } else {
            0.0
        },
        noise_units_before: nu_b,
        noise_units_after: nu_a,
        excess_removed,
        lr_statistic: lr,
        lr_critical,
        significant,
        partial: significant && nu_a > cfg.at_floor,
        windows: after.windows.len(),
        correction,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::compare::CompareConfig;
    use crate::analysis::profile::Normal;
    use crate::flight::autopilot::Manoeuvre;
    use crate::flight::effects::Origin;
    use crate::flight::simulate::{simulate, Noise, SimSpec};
    use crate::flight::spec::{EffectSpec, ModelSpec};
    use crate::flight::VehicleKind;

    /// Where the model without a wind starts a window, predicted from the fit of the model
    /// with it: within a twentieth of the way from the warm start to the base's own fitted
    /// start, in misfit (0.1–2.4% on this flight's six windows; the full pass then fits the
    /// base's start from there); and the normal equations are those of `window_normal` all
    /// the same.
    #[test]
    fn the_base_start_predicted_from_a_corrections_fit_is_near_the_base_fit() {
        let base = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let mut with = base.clone();
        let wind = EffectSpec::parse("wind:north_mps=4,east_mps=-3").unwrap();
        with.add_effect(wind.build(&base.effect_context()).unwrap())
            .unwrap();
        let spec = SimSpec {
            noise: Noise {
                pos_m: 0.05,
                att_deg: 0.05,
                vel_mps: 0.05,
                rate_dps: 0.2,
            },
            ..SimSpec::new(Manoeuvre::FlightTest, 45.0)
        };
        let data = simulate(&with, &spec).unwrap();
        let prep = Prepared::new(&data, CompareConfig::default());
        let free = effect_free(&mut with.clone(), "wind", &[], &prep, false).unwrap();
        let theta = values(&with, &free);
        let perturbed = perturbed_models(&with, &free, &theta);
        let correction = Correction::Effect(effect(&with, "wind").unwrap().clone_box());
        let absent = base_values(&base, &with, &correction, &free).unwrap();
        assert_eq!(absent, vec![0.0; 3]);
        let towards: Vec<f64> = absent
            .iter()
            .zip(&theta)
            .zip(&free)
            .map(|((b, t), f)| (b - t) / f.scale)
            .collect();
        let mut scratch = Scratch::default();
        let sse = |model: &Model, w: (usize, usize), x: &State, scratch: &mut Scratch| {
            let mut r = Vec::new();
            prep.window_residuals(model, w, x, scratch, &mut r);
            r.iter().map(|v| v * v).sum::<f64>()
        };
        for &w in &prep.windows {
            let surfaces = glam::DVec3::ZERO;
            let fit = prep.fit_start(&with, w, prep.warm_start(&with, w, surfaces), &mut scratch);
            let lin = Linearised::of(&with, &fit);
            let plain = crate::analysis::profile::window_normal(
                &with,
                (&perturbed, &free, false),
                &prep,
                w,
                &lin,
                Some(&fit.residuals),
            );
            // Flown columns, and the wind's own (its fit being the model's own).
            let mut shares = Vec::new();
            for own in [false, true] {
                let (share, q) = window_normal_towards(
                    &with,
                    &perturbed,
                    &free,
                    &prep,
                    w,
                    &lin,
                    Some(&fit.residuals),
                    (Some(&towards), own),
                );
                let predicted =
                    crate::analysis::compare::start::state_of(&base, &q.unwrap(), surfaces);
                let warm = prep.warm_start(&base, w, surfaces);
                let best = prep.fit_start(&base, w, warm, &mut scratch);
                let best_sse: f64 = best.residuals.iter().map(|v| v * v).sum();
                let (at_warm, at_predicted) = (
                    sse(&base, w, &warm, &mut scratch),
                    sse(&base, w, &predicted, &mut scratch),
                );
                assert!(
                    at_predicted - best_sse < 0.05 * (at_warm - best_sse),
                    "window {w:?}, own {own}: χ² {at_predicted:.6e} predicted, {at_warm:.6e} \
                     warm, {best_sse:.6e} fitted"
                );
                shares.push(share);
            }
            assert_eq!(shares[0], plain);
            // The wind's columns are the flown ones: with the Jacobian of differences at the
            // fitted start, where neither is off by the projection's own error (the fit's
            // updated tangent Jacobian projects both to within ~1% of these).
            let q = crate::analysis::compare::start::params_of(&with, &fit.state);
            let mut exact = fit.clone();
            prep.difference_jacobian(
                &with,
                w,
                &q,
                fit.state.surfaces(),
                &fit.residuals,
                &mut scratch,
                &mut exact.jacobian,
            );
            let lin = Linearised::of(&with, &exact);
            let [flown, own] = [false, true].map(|own| {
                let r = Some(fit.residuals.as_slice());
                window_normal_towards(&with, &perturbed, &free, &prep, w, &lin, r, (None, own)).0
            });
            assert_wind_columns_are_flown(&flown, &own, w);
        }
        // Beside an effect of height the wind is no longer a moving frame (the drift changes
        // the height): its columns are flown.
        let mut high = with.clone();
        let density = EffectSpec::parse("density_altitude").unwrap();
        high.add_effect(density.build(&base.effect_context()).unwrap())
            .unwrap();
        let w = prep.windows[0];
        let fit = prep.fit_start(
            &high,
            w,
            prep.warm_start(&high, w, glam::DVec3::ZERO),
            &mut scratch,
        );
        let lin = Linearised::of(&high, &fit);
        let perturbed = perturbed_models(&high, &free, &theta);
        let [flown, own] = [false, true].map(|own| {
            let r = Some(fit.residuals.as_slice());
            window_normal_towards(&high, &perturbed, &free, &prep, w, &lin, r, (None, own)).0
        });
        assert_eq!(flown, own);
    }

    /// The wind's normal equations without flights are the flown ones: the information
    /// matrix to 2e-3 of its diagonal (measured: 5.9e-4 at most, the forward differences'
    /// and RK4's own error), the Newton step within 0.5% of a standard deviation (0.05%).
    fn assert_wind_columns_are_flown(flown: &Normal, own: &Normal, w: (usize, usize)) {
        let np = flown.1.len();
        let (a, b) = (&flown.0, &own.0);
        for i in 0..np {
            for k in 0..np {
                let scale = (a[i * np + i] * a[k * np + k]).sqrt();
                let off = (a[i * np + k] - b[i * np + k]).abs() / scale;
                assert!(
                    off < 2e-3,
                    "window {w:?} A({i}, {k}): {} vs {}",
                    a[i * np + k],
                    b[i * np + k]
                );
            }
        }
        let step = |n: &Normal| {
            let mut s = n.1.clone();
            let mut m = n.0.clone();
            solve_in_place(&mut m, &mut s, np).unwrap();
            s
        };
        let (sa, sb) = (step(flown), step(own));
        let cov = invert(a, np).unwrap();
        for i in 0..np {
            let sigma = cov[i * np + i].sqrt();
            let off = (sa[i] - sb[i]).abs() / sigma;
            assert!(
                off < 5e-3,
                "window {w:?} step {i}: {} vs {} (σ {sigma})",
                sa[i],
                sb[i]
            );
        }
    }

    /// The moving frame changes what a wind's fit costs, not what it finds: fitted on the
    /// airframe (its columns without flights, its first round cut to one step) and on the
    /// airframe with an inert gyroscopic term (k_gyro = 0: the same equations, every column
    /// flown, every round to convergence), the wind agrees to 0.3σ (measured 0.17σ: two fits
    /// each stopped within the fit's tolerance), its ± to 5% (0.6%, 2.9%, 1.3%: both
    /// project with the fits' updated Jacobians, each ~1% from the differences' in a
    /// window) and the misfit left to 2e-4 (8e-5).
    #[test]
    fn a_wind_fitted_as_a_moving_frame_is_the_wind_fitted_with_flights() {
        let airframe = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let mut truth = airframe.clone();
        let wind = EffectSpec::parse("wind:north_mps=4,east_mps=-3,down_mps=0.5").unwrap();
        truth
            .add_effect(wind.build(&airframe.effect_context()).unwrap())
            .unwrap();
        let spec = SimSpec {
            noise: Noise {
                pos_m: 0.05,
                att_deg: 0.05,
                vel_mps: 0.05,
                rate_dps: 0.2,
            },
            ..SimSpec::new(Manoeuvre::FlightTest, 45.0)
        };
        let data = simulate(&truth, &spec).unwrap();
        let prep = Prepared::new(&data, CompareConfig::default());
        let mut inert = airframe.clone();
        let gyro = EffectSpec::parse("gyroscopic:k_gyro=0").unwrap();
        inert
            .add_effect(gyro.build(&airframe.effect_context()).unwrap())
            .unwrap();
        let cfg = DiagnoseConfig::default();
        let [framed, flown] = [&airframe, &inert].map(|base| {
            let before = Baseline::of(base, &prep);
            let wind = crate::flight::effects::find("wind")
                .unwrap()
                .build(&base.effect_context());
            try_effect(base, wind, &[], &prep, &before, &cfg, 1).unwrap()
        });
        assert!(moving_frame(&truth, &[]).is_some() && inert.effects.len() == 1);
        for k in 0..3 {
            let (a, b) = (framed.params[k].1, flown.params[k].1);
            let sigma = flown.uncertainty[k];
            assert!((a - b).abs() < 0.3 * sigma, "{k}: {a} vs {b} (σ {sigma})");
            let ratio = framed.uncertainty[k] / sigma;
            assert!(
                (ratio - 1.0).abs() < 0.05,
                "{k}: σ {} vs {sigma}",
                framed.uncertainty[k]
            );
        }
        let (a, b) = (framed.error_after, flown.error_after);
        assert!((a - b).abs() < 2e-4 * b, "misfit left {a} vs {b}");
    }

    fn comparison(chi2: f64, dof: f64) -> Comparison {
        Comparison {
            total: 1.0,
            channels: Default::default(),
            windows: Vec::new(),
            prediction: Default::default(),
            axes: Vec::new(),
            chi2,
            dof,
        }
    }

    /// A number is fitted when four times its score would remove a fifth of the misfit above
    /// the noise and pass the likelihood-ratio test; never without misfit above the noise.
    #[test]
    fn only_numbers_that_could_be_significant_are_fitted() {
        let cfg = DiagnoseConfig::default();
        // Twelve times the noise: χ²/ν = 144 over 10⁴ residuals, an excess of 11 noise units.
        let far = comparison(1.44e6, 1e4);
        // A fifth of the excess: the noise units fall from 12 to 9.8, χ² to 9.6e5.
        let needed = (1.44e6 - 9.8f64.powi(2) * 1e4) / SCORE_ALLOWANCE;
        assert!(could_be_significant(&far, 1.05 * needed, &cfg, 30));
        assert!(!could_be_significant(&far, 0.95 * needed, &cfg, 30));
        assert!(!could_be_significant(&far, 0.0, &cfg, 30));
        assert!(!could_be_significant(&far, f64::NAN, &cfg, 30));
        // At the noise (and below it) nothing could be material.
        assert!(!could_be_significant(&comparison(1e4, 1e4), 5e3, &cfg, 30));
        assert!(!could_be_significant(
            &comparison(0.9e4, 1e4),
            5e3,
            &cfg,
            30
        ));
        // Just above the noise a material reduction is small, but the test must be passed:
        // 1.1 × noise over 100 residuals is an excess of 21 χ² units.
        let near = comparison(121.0, 100.0);
        assert!(could_be_significant(&near, 20.0, &cfg, 30));
        assert!(!could_be_significant(&near, 0.5, &cfg, 30));
    }
}
