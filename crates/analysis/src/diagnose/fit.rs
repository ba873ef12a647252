//! Fitting one candidate correction — an effect's parameters, or numbers of the aircraft's
//! parameter set — on the misfit profiled over every window's start state, and scoring it
//! against the model without it.
//!
//! The profile is linearised around the baseline's fitted starts (variable projection: the
//! residual change a parameter causes, less what a start change could absorb), Levenberg–
//! Marquardt runs on that, and the starts are then fitted exactly at the result (repeated
//! when the linearisation was off). The covariance comes from the projected Jacobian.

use super::{AircraftChange, Candidate, Correction, DiagnoseConfig, DiagnoseError};
use crate::compare::start::StartFit;
use crate::compare::{
    colour_factor, compare_from_jacobians, compare_refit, compare_with_fits, Comparison, Prepared,
};
use crate::free::{aircraft_free, effect, values, Free, Owner};
use crate::lm::{Lm, FIT_TOL};
use crate::profile::{
    linear_profile, moving_frame, normal_equations, normal_equations_by_window, Linearised,
};
use wireflight_flight::effects::{Effect, ParamSpec};
use wireflight_flight::model::{Model, State};
use wireflight_flight::numeric::{chi2_quantile, invert};

/// The fitted parameters' covariance in their own units (row-major), or None when the data
/// do not determine them.
///
/// Two estimates, the correlations the first's:
/// * the model-based one, (D̃ᵀD̃)⁻¹ scaled by the misfit per residual when it exceeds 1 and
///   by the residuals' colour where the fit moved them, `colour`
///   ([`crate::compare::colour_factor`]: the same factor that deflates the fit's
///   likelihood ratio, so that a test of one parameter and its ± agree);
/// * with at least three more windows than parameters, the sandwich A⁻¹BA⁻¹ with each
///   window a cluster, B = W/(W−1)·Σ (g_w − ḡ)(g_w − ḡ)ᵀ of the windows' gradient shares
///   `grads`: how much the windows' own pulls on the parameters scatter, whatever makes the
///   residuals inside a window correlated (a model that is not exact, a smooth misfit). It
///   replaces a parameter's model-based σ where it exceeds it by more than the windows'
///   scatter would by chance (the χ² 95% quantile over W − 1).
///
/// Coverage on refsim's flights: docs/workbench.md.
pub(crate) fn covariance(
    a: &[f64],
    free: &[Free],
    (cmp, colour): (&Comparison, f64),
    grads: Option<&[Vec<f64>]>,
) -> Option<Vec<f64>> {
    let np = free.len();
    let inv = invert(a, np)?;
    let s2 = (cmp.chi2 / cmp.dof.max(1.0)).max(1.0) * colour.max(1.0);
    let mut model: Vec<f64> = inv.iter().map(|v| v * s2).collect();
    if let Some((sandwich, windows)) = grads.and_then(|g| sandwich(&inv, g, np)) {
        // The windows' scatter replaces a σ only where it is larger than noise in the
        // scatter of so few windows would make it (its 95% quantile): otherwise a handful of
        // windows would inflate every σ at random.
        let dof = windows as f64 - 1.0;
        let beyond = chi2_quantile(0.95, dof) / dof;
        let sd: Vec<f64> = (0..np)
            .map(|i| {
                let (m, s) = (model[i * np + i], sandwich[i * np + i]);
                if s > beyond * m { s } else { m }.max(0.0).sqrt()
            })
            .collect();
        let old: Vec<f64> = (0..np).map(|i| model[i * np + i].max(0.0).sqrt()).collect();
        for i in 0..np {
            for k in 0..np {
                let corr = model[i * np + k] / (old[i] * old[k]);
                model[i * np + k] = if corr.is_finite() {
                    corr * sd[i] * sd[k]
                } else {
                    model[i * np + k]
                };
            }
        }
    }
    let mut cov = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            cov[i * np + k] = model[i * np + k] * free[i].scale * free[k].scale;
        }
    }
    cov.iter()
        .all(|v| v.is_finite())
        .then_some(cov)
        .filter(|c| (0..np).all(|i| c[i * np + i] >= 0.0))
}

/// The cluster sandwich A⁻¹BA⁻¹ in the scaled parameters (`inv` = A⁻¹), the windows'
/// gradient shares `grads` the clusters; None with fewer than np + 3 windows (the scatter
/// of so few says nothing).
fn sandwich(inv: &[f64], grads: &[Vec<f64>], np: usize) -> Option<(Vec<f64>, usize)> {
    let w = grads.iter().filter(|g| g.len() == np).count();
    if np == 0 || w < np + 3 {
        return None;
    }
    let mut mean = vec![0.0; np];
    for g in grads.iter().filter(|g| g.len() == np) {
        mean.iter_mut().zip(g).for_each(|(m, v)| *m += v / w as f64);
    }
    let mut b = vec![0.0; np * np];
    for g in grads.iter().filter(|g| g.len() == np) {
        for i in 0..np {
            for k in 0..np {
                b[i * np + k] += (g[i] - mean[i]) * (g[k] - mean[k]);
            }
        }
    }
    let f = w as f64 / (w as f64 - 1.0);
    // inv · B · inv
    let mut ib = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            ib[i * np + k] = (0..np)
                .map(|j| inv[i * np + j] * b[j * np + k])
                .sum::<f64>();
        }
    }
    let mut out = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            out[i * np + k] = f
                * (0..np)
                    .map(|j| ib[i * np + j] * inv[j * np + k])
                    .sum::<f64>();
        }
    }
    out.iter().all(|v| v.is_finite()).then_some((out, w))
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
    let mut lm = Lm::new(8, 1e-6);
    for _ in 0..iterations {
        let (a0, g) = normal_equations(model, (free, own), theta, prep, lin, Some(&flown));
        if let Some(dq) = pending.take() {
            move_starts(lin, &dq);
        }
        let at: &[Linearised] = lin;
        let Some(step) = lm.step(model, free, theta, (&a0, &g), chi2, |m, _| {
            let (c, dq, flown) = linear_profile(m, prep, at);
            (c, (dq, flown))
        }) else {
            break;
        };
        *theta = step.theta;
        *model = step.model;
        chi2 = step.objective;
        let (dq, flown_trial) = step.extra;
        flown = flown_trial;
        // Each start belongs where the linearisation puts it at these parameters.
        pending = Some(dq);
        // The baseline's starts are no longer the model's own.
        own &= starts == Starts::Own;
        if step.converged || first_step_only {
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
pub(crate) fn fit(
    model: &mut Model,
    free: &[Free],
    prep: &Prepared,
    baseline: &Baseline,
    (iterations, polish): (usize, bool),
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
        let ((a, _), grads) =
            normal_equations_by_window(model, (free, own), &theta, prep, &lin, flown.as_deref());
        let b = &baseline.comparison;
        let cov = covariance(&a, free, (b, colour_factor(b, b)), Some(&grads));
        return (baseline.comparison.clone(), cov);
    }
    // The linearisation is around the starts of the model without the effect; the starts are
    // then fitted exactly, and when that changes the misfit by more than the tolerance, the
    // fit is repeated around them.
    let mut exact: Option<Comparison> = None;
    //
    // With `polish`, the fit always takes one more pass linearised about its own starts: the
    // misfit's value may agree with the linearisation about the baseline's starts to the
    // tolerance while its slope does not (a joint fit begun from values far from the
    // baseline's ended 2σ from where a fit about its own starts does).
    for pass in 0..3 {
        let starts: Vec<State> = lin.iter().map(|l| l.state(model)).collect();
        let jacobians: Vec<&[f64]> = lin.iter().map(|l| &*l.jac).collect();
        let (cmp, new_fits) = compare_refit(model, prep, &starts, &jacobians);
        let settled =
            (cmp.chi2 - linear).abs() < FIT_TOL.max(1e-4 * cmp.chi2) && !(polish && pass == 0);
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
    let ((a, _), grads) =
        normal_equations_by_window(model, (free, true), &theta, prep, &lin, flown.as_deref());
    let colour = colour_factor(&baseline.comparison, &cmp);
    let cov = covariance(&a, free, (&cmp, colour), Some(&grads));
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
) -> Result<Vec<Free>, DiagnoseError> {
    let info = effect(model, name)
        .map(|e| e.info())
        .ok_or_else(|| DiagnoseError::NotAdded(name.to_string()))?;
    for f in fixed {
        if info.param(f).is_none() {
            return Err(DiagnoseError::NoParameter {
                effect: name.to_string(),
                param: f.clone(),
            });
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
) -> Result<Candidate, DiagnoseError> {
    let (after, cov) = fit(&mut model, free, prep, before, (cfg.max_iterations, false));
    let mut c = make_candidate(
        base,
        &model,
        trial,
        free,
        &before.comparison,
        &after,
        cov,
        cfg,
        candidates,
    )?;
    c.comparison = Some(std::sync::Arc::new(after));
    Ok(c)
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
) -> Result<Candidate, DiagnoseError> {
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
) -> Result<Candidate, DiagnoseError> {
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

/// A significant candidate removes at least this fraction of the misfit above the noise (in
/// noise units): less is too little to matter, however sure the test is of it.
pub(crate) const MATERIAL: f64 = 0.2;

/// The least misfit above the noise, in noise units, that counts as an excess at all: the
/// noise is itself estimated from the data (to a few per cent), so a misfit within this of
/// it is the noise's. Without it a model at 1.001 × the noise has an "excess" that any
/// parameter removes a fifth of — rungs that gain nothing.
pub(crate) const NOISE_SLACK: f64 = 0.02;

/// The fraction of the misfit above the noise that going from `nu_b` to `nu_a` noise units
/// removes: (ν_b − ν_a)/(ν_b − 1), the excess counted as at least [`NOISE_SLACK`]; in
/// [−1.5, 1.5] (a fit that makes things worse shows as negative).
pub(crate) fn excess_removed(nu_b: f64, nu_a: f64) -> f64 {
    if !(nu_b.is_finite() && nu_a.is_finite()) {
        return 0.0;
    }
    ((nu_b - nu_a) / (nu_b - 1.0).max(NOISE_SLACK)).clamp(-1.5, 1.5)
}

/// The likelihood-ratio statistic of `after` (a correction fitted) against `before`:
/// N·ln(χ²₀/χ²₁), N the effectively independent residuals: with stated wandering errors the
/// degrees of freedom over their colour where the misfit fell ([`colour_factor`]), else
/// [`Comparison::independent_residuals`].
pub(crate) fn likelihood_ratio(before: &Comparison, after: &Comparison) -> f64 {
    if after.chi2.is_nan() || after.chi2 <= 0.0 {
        return f64::INFINITY;
    }
    let independent = if after.wanders() {
        (after.dof / colour_factor(before, after)).max(1.0)
    } else {
        after.independent_residuals()
    };
    independent * (before.chi2 / after.chi2).ln()
}

/// The χ² quantile a candidate's likelihood-ratio statistic must beat: the family-wise level
/// split over all `candidates` (Bonferroni), for `np` fitted parameters.
pub(crate) fn lr_critical(cfg: &DiagnoseConfig, candidates: usize, np: usize) -> f64 {
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
    let material = excess_removed(nu_b, nu_a) >= MATERIAL;
    let lr = if after > 0.0 {
        dof * (chi2 / after).ln()
    } else {
        f64::INFINITY
    };
    material && lr > lr_critical(cfg, candidates, 1)
}

/// Build the candidate's record from its fit.
#[allow(clippy::too_many_arguments)]
pub(crate) fn make_candidate(
    base: &Model,
    model: &Model,
    trial: &Trial,
    free: &[Free],
    before: &Comparison,
    after: &Comparison,
    cov: Option<Vec<f64>>,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, DiagnoseError> {
    let np = free.len();
    let sigma = |k: usize| cov.as_ref().map_or(f64::NAN, |c| c[k * np + k].sqrt());
    let mut params = Vec::new();
    let mut held = Vec::new();
    let mut uncertainty = Vec::new();
    let mut at_limit = Vec::new();
    // Ended on a bound of its range: within a millionth of its scale of it.
    let limit = |k: Option<usize>, v: f64| {
        k.is_some_and(|k| {
            let f = &free[k];
            let tol = 1e-6 * f.scale;
            v <= f.range.0 + tol || v >= f.range.1 - tol
        })
    };
    let correction = match trial {
        Trial::Effect(name) => {
            let e = effect(model, name)
                .map(|e| e.clone_box())
                .ok_or_else(|| DiagnoseError::NotAdded(name.clone()))?;
            for p in e.params() {
                params.push((p.name.to_string(), p.value));
                let k = free.iter().position(|f| f.name == p.name);
                held.push(k.is_none());
                uncertainty.push(k.map_or(f64::NAN, sigma));
                at_limit.push(limit(k, p.value));
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
                at_limit.push(limit(Some(k), value));
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
    let excess_removed = excess_removed(nu_b, nu_a);
    let lr = if after.chi2 > 0.0 {
        likelihood_ratio(before, after)
    } else {
        f64::INFINITY
    };
    let lr_critical = lr_critical(cfg, candidates, np);
    let significant = lr > lr_critical
        && after.chi2 < before.chi2
        && excess_removed >= MATERIAL
        && !at_limit.iter().any(|&l| l);
    Ok(Candidate {
        effect: trial.label(),
        params,
        held,
        uncertainty,
        at_limit,
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
        joint: false,
        correction,
        comparison: None,
    })
}

#[cfg(test)]
mod tests;
