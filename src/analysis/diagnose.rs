//! Which physical effect is missing? Try every applicable catalogue effect (and any user
//! effect given), fit its parameters together with every window's start state, rank by how
//! much of the misfit it removes, test whether that is more than fitting noise would give,
//! and say honestly when nothing explains what is left.
//!
//! * **Fitting** (output error with estimated start states): Levenberg–Marquardt on the
//!   effect's free parameters, each window's start re-fitted at every trial (warm-started), so
//!   the misfit is the profile over the starts. The parameter Jacobian is the variable
//!   projection one: the change of each window's residuals with a parameter, less what a start
//!   change could absorb ([`project_out`]). Parameters given by the user, and those known from
//!   the metadata (latitudes, [`ParamSpec::from_origin`]), are held. Each parameter stays in its
//!   range.
//! * **Uncertainty**: the covariance (JᵀJ)⁻¹ of the projected Jacobian of noise-weighted
//!   residuals, scaled by the misfit per residual when it exceeds 1 and by the residuals'
//!   autocorrelation (AR(1): (1+ρ)/(1−ρ)); 1σ, with the correlation matrix. All windows count.
//! * **Significance**: the likelihood-ratio statistic N·ln(χ²₀/χ²₁) over the effectively
//!   independent residuals N (ν·(1−ρ)/(1+ρ): white residuals count fully, a smooth misfit
//!   hardly) against the χ² quantile for the number of fitted parameters at the family-wise
//!   level α split over all candidates (Bonferroni); and the effect must remove at least a
//!   fifth of the misfit above the noise.
//! * **Verdict**: the significant candidate that leaves the least misfit, if it brings the
//!   error to the noise (≤ `at_floor` noise units); a significant candidate that leaves the
//!   error above the noise is only *partial*, and the verdict is then `unexplained`. Without a
//!   significant candidate: `none` when the error is at the noise, `unexplained` when it is not.
//!   [`iterate`] adds the winner and repeats.
//!
//! Long flights are screened on a subset of windows (`screen_windows`), and the best
//! candidates then re-fitted on all of them.

use std::fmt;

use rayon::prelude::*;

use glam::DVec3;

use super::compare::start::{params_of, project_out, state_of, Scratch, StartFit};
use super::compare::{
    compare_from, compare_many, compare_with_fits, noise_floor, CompareConfig, Comparison, Prepared,
};
use crate::flight::data::FlightData;
use crate::flight::effects::{Effect, ParamSpec, CATALOGUE};
use crate::flight::model::{Model, State};
use crate::flight::spec::EffectSpec;
use crate::numeric::{chi2_quantile, invert, solve_in_place};

/// Settings of a diagnosis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagnoseConfig {
    /// Comparison settings used for fitting and scoring.
    pub compare: CompareConfig,
    /// Levenberg–Marquardt iterations per candidate.
    pub max_iterations: usize,
    /// Family-wise significance level of the likelihood-ratio tests.
    pub alpha: f64,
    /// Fit candidates on at most this many windows, evenly spread (0: all), then re-fit the
    /// best on all of them.
    pub screen_windows: usize,
    /// Misfit, in units of the measurement noise, that counts as "at the noise floor".
    pub at_floor: f64,
}

impl Default for DiagnoseConfig {
    fn default() -> Self {
        Self {
            compare: CompareConfig::default(),
            max_iterations: 10,
            alpha: 0.01,
            screen_windows: 24,
            at_floor: 1.25,
        }
    }
}

/// One tried effect.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Effect name.
    pub effect: String,
    /// Parameters after fitting (fitted and held), name → value.
    pub params: Vec<(String, f64)>,
    /// Whether each parameter was held (given, or known from the metadata) rather than fitted.
    pub held: Vec<bool>,
    /// 1σ of each fitted parameter (NaN for held ones, and where the data do not determine
    /// it).
    pub uncertainty: Vec<f64>,
    /// Correlation matrix of the fitted parameters (row-major, `fitted`×`fitted`).
    pub correlation: Vec<f64>,
    /// Number of fitted parameters.
    pub fitted: usize,
    /// Total error without the effect (see the comparison's module docs).
    pub error_before: f64,
    /// Total error with the fitted effect.
    pub error_after: f64,
    /// Fraction of the total error removed, (before − after)/before.
    pub error_reduction: f64,
    /// Misfit in noise units without the effect.
    pub noise_units_before: f64,
    /// Misfit in noise units with the fitted effect.
    pub noise_units_after: f64,
    /// Fraction of the misfit *above the noise* removed (noise units).
    pub excess_removed: f64,
    /// Likelihood-ratio statistic N·ln(χ²₀/χ²₁).
    pub lr_statistic: f64,
    /// The χ² quantile it had to beat.
    pub lr_critical: f64,
    /// Passed the significance test and the materiality threshold.
    pub significant: bool,
    /// Significant, but the error stays above the noise floor with it: part of the answer at
    /// most.
    pub partial: bool,
    /// Windows the fit used.
    pub windows: usize,
    /// The fitted effect, ready to add to the model.
    pub fitted_effect: Box<dyn Effect>,
}

/// What the diagnosis concludes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// This effect is missing, and adding it brings the error to the noise.
    Effect(String),
    /// The error is at the noise floor: nothing is missing that these data could show.
    None,
    /// The error is above the noise floor and no candidate brings it there.
    Unexplained,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Effect(name) => f.write_str(name),
            Verdict::None => f.write_str("none"),
            Verdict::Unexplained => f.write_str("unexplained"),
        }
    }
}

/// Result of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// Total error of the model as given.
    pub base_error: f64,
    /// Total error a right model would leave (measurement noise alone).
    pub noise_floor: f64,
    /// Misfit of the model as given, in noise units (1 = at the floor).
    pub noise_units: f64,
    /// The comparison of the model as given (all windows).
    pub base: Comparison,
    /// Candidates, least misfit left first.
    pub ranking: Vec<Candidate>,
    /// The conclusion.
    pub verdict: Verdict,
    /// Windows of the whole comparison, and of the screening (equal when not screened).
    pub windows: (usize, usize),
    /// The measurement noise of the data.
    pub base_noise: crate::analysis::compare::NoiseEstimate,
}

impl Diagnosis {
    /// The winning candidate, when the verdict is an effect.
    pub fn winner(&self) -> Option<&Candidate> {
        match &self.verdict {
            Verdict::Effect(v) => self.ranking.iter().find(|c| &c.effect == v),
            _ => None,
        }
    }
}

/// The effect named `name` in `model`.
fn effect<'m>(model: &'m Model, name: &str) -> Option<&'m dyn Effect> {
    model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .map(|e| e.as_ref())
}

/// A parameter being fitted: its spec and its index among the effect's values.
#[derive(Clone, Copy)]
struct Free {
    spec: &'static ParamSpec,
    scale: f64,
}

fn set_values(model: &mut Model, name: &str, free: &[Free], theta: &[f64]) {
    if let Some(e) = model.effect_mut(name) {
        for (f, v) in free.iter().zip(theta) {
            let _ = e.set_param(f.spec.name, v.clamp(f.spec.range.0, f.spec.range.1));
        }
    }
}

fn values(model: &Model, name: &str, free: &[Free]) -> Vec<f64> {
    let e = effect(model, name);
    free.iter()
        .map(|f| e.and_then(|e| e.param(f.spec.name)).unwrap_or(0.0))
        .collect()
}

/// One window's start state and the linearisation of its residuals around it: what a change
/// of the start can absorb (the columns of `jac`), projected out of every residual change.
struct Linearised {
    q: Vec<f64>,
    surfaces: DVec3,
    jac: Vec<f64>,
    gram: Vec<f64>,
    params: usize,
}

impl Linearised {
    fn of(model: &Model, fit: &StartFit) -> Self {
        let m = fit.residuals.len();
        let np = fit.params;
        let mut gram = vec![0.0; np * np];
        if fit.jacobian.len() == np * m {
            for a in 0..np {
                for b in a..np {
                    let v: f64 = fit.jacobian[a * m..(a + 1) * m]
                        .iter()
                        .zip(&fit.jacobian[b * m..(b + 1) * m])
                        .map(|(u, w)| u * w)
                        .sum();
                    gram[a * np + b] = v;
                    gram[b * np + a] = v;
                }
            }
        }
        Self {
            q: params_of(model, &fit.state),
            surfaces: fit.state.surfaces(),
            jac: fit.jacobian.clone(),
            gram,
            params: np,
        }
    }

    fn state(&self, model: &Model) -> State {
        state_of(model, &self.q, self.surfaces)
    }

    /// Replace `r` by what no start change can absorb, r − J·(JᵀJ)⁻¹Jᵀr, and return the start
    /// change that absorbs the rest, −(JᵀJ)⁻¹Jᵀr.
    fn project(&self, r: &mut [f64]) -> Vec<f64> {
        let (np, m) = (self.params, r.len());
        if np == 0 || self.jac.len() != np * m {
            return vec![0.0; np];
        }
        let mut y: Vec<f64> = (0..np)
            .map(|a| {
                self.jac[a * m..(a + 1) * m]
                    .iter()
                    .zip(r.iter())
                    .map(|(u, v)| u * v)
                    .sum()
            })
            .collect();
        let mut g = self.gram.clone();
        if solve_in_place(&mut g, &mut y, np).is_none() {
            return vec![0.0; np];
        }
        for (a, ya) in y.iter().enumerate() {
            for (v, j) in r.iter_mut().zip(&self.jac[a * m..(a + 1) * m]) {
                *v -= ya * j;
            }
        }
        y.iter().map(|v| -v).collect()
    }
}

/// The profiled misfit in the linearisation: the projected residuals of every window at the
/// model's parameters, their χ², and each window's start change.
fn linear_profile(model: &Model, prep: &Prepared, lin: &[Linearised]) -> (f64, Vec<Vec<f64>>) {
    let parts: Vec<(f64, Vec<f64>)> = prep
        .windows
        .par_iter()
        .zip(lin.par_iter())
        .map(|(&w, l)| {
            let mut scratch = Scratch::default();
            let mut r = Vec::new();
            prep.window_residuals(
                model,
                prep.fit_range(w),
                &l.state(model),
                &mut scratch,
                &mut r,
            );
            let dq = l.project(&mut r);
            (r.iter().map(|v| v * v).sum(), dq)
        })
        .collect();
    let chi2 = parts.iter().map(|p| p.0).sum();
    (chi2, parts.into_iter().map(|p| p.1).collect())
}

/// Forward-difference step of the parameters, in units of each one's scale.
const PARAM_STEP: f64 = 0.01;

/// The model with each free parameter in turn moved by one difference step.
fn perturbed_models(model: &Model, name: &str, free: &[Free], theta: &[f64]) -> Vec<Model> {
    (0..free.len())
        .map(|j| {
            let mut m = model.clone();
            let mut t = theta.to_vec();
            t[j] += PARAM_STEP * free[j].scale;
            set_values(&mut m, name, free, &t);
            m
        })
        .collect()
}

/// One window's share of the normal equations: A = D̃ᵀD̃ and g = D̃ᵀr, D̃ the change of the
/// residuals per scaled parameter with the start directions projected out.
fn window_normal(
    model: &Model,
    perturbed: &[Model],
    prep: &Prepared,
    window: (usize, usize),
    l: &Linearised,
) -> (Vec<f64>, Vec<f64>) {
    let np = perturbed.len();
    let span = prep.fit_range(window);
    let mut scratch = Scratch::default();
    let x = l.state(model);
    let mut r = Vec::new();
    prep.window_residuals(model, span, &x, &mut scratch, &mut r);
    let m = r.len();
    let mut cols = vec![0.0; np * m];
    let mut rj = Vec::with_capacity(m);
    for (j, pm) in perturbed.iter().enumerate() {
        prep.window_residuals(pm, span, &x, &mut scratch, &mut rj);
        for ((c, a), b) in cols[j * m..(j + 1) * m].iter_mut().zip(&rj).zip(&r) {
            *c = (a - b) / PARAM_STEP;
        }
    }
    project_out(&l.jac, l.params, &mut cols, m);
    let mut a = vec![0.0; np * np];
    let mut g = vec![0.0; np];
    for i in 0..np {
        let ci = &cols[i * m..(i + 1) * m];
        // D̃ is orthogonal to the start directions, so D̃ᵀr = D̃ᵀr̃.
        g[i] = ci.iter().zip(&r).map(|(u, v)| u * v).sum();
        for k in i..np {
            let v: f64 = ci
                .iter()
                .zip(&cols[k * m..(k + 1) * m])
                .map(|(u, v)| u * v)
                .sum();
            a[i * np + k] = v;
            a[k * np + i] = v;
        }
    }
    (a, g)
}

fn add_into(sum: &mut (Vec<f64>, Vec<f64>), part: &(Vec<f64>, Vec<f64>)) {
    sum.0.iter_mut().zip(&part.0).for_each(|(s, v)| *s += v);
    sum.1.iter_mut().zip(&part.1).for_each(|(s, v)| *s += v);
}

/// Normal equations of the profiled misfit in the scaled free parameters, summed over windows
/// (see [`window_normal`]).
fn normal_equations(
    model: &Model,
    name: &str,
    free: &[Free],
    theta: &[f64],
    prep: &Prepared,
    lin: &[Linearised],
) -> (Vec<f64>, Vec<f64>) {
    let np = free.len();
    let perturbed = perturbed_models(model, name, free, theta);
    let parts: Vec<(Vec<f64>, Vec<f64>)> = prep
        .windows
        .par_iter()
        .zip(lin.par_iter())
        .map(|(&w, l)| window_normal(model, &perturbed, prep, w, l))
        .collect();
    let mut sum = (vec![0.0; np * np], vec![0.0; np]);
    for p in &parts {
        add_into(&mut sum, p);
    }
    sum
}

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

/// Levenberg–Marquardt on the parameters over the linearised profile; updates `model`,
/// `theta` and the windows' starts. Returns the linearised χ² reached.
#[allow(clippy::too_many_arguments)]
fn fit_linearised(
    model: &mut Model,
    name: &str,
    free: &[Free],
    theta: &mut Vec<f64>,
    prep: &Prepared,
    lin: &mut [Linearised],
    iterations: usize,
) -> f64 {
    let np = free.len();
    let (mut chi2, mut dq) = linear_profile(model, prep, lin);
    let mut lambda = 1e-3;
    for _ in 0..iterations {
        let (a0, g) = normal_equations(model, name, free, theta, prep, lin);
        let mut accepted = None;
        for _ in 0..8 {
            let mut a = a0.clone();
            for k in 0..np {
                a[k * np + k] += lambda * a0[k * np + k].max(1e-30);
            }
            let mut step: Vec<f64> = g.iter().map(|v| -v).collect();
            if solve_in_place(&mut a, &mut step, np).is_none() {
                lambda *= 10.0;
                continue;
            }
            let trial: Vec<f64> = theta
                .iter()
                .zip(&step)
                .zip(free)
                .map(|((t, s), f)| (t + s * f.scale).clamp(f.spec.range.0, f.spec.range.1))
                .collect();
            let mut m = model.clone();
            set_values(&mut m, name, free, &trial);
            let (c, dq_trial) = linear_profile(&m, prep, lin);
            if c.is_finite() && c < chi2 {
                accepted = Some((trial, m, c, dq_trial));
                lambda = (lambda / 10.0).max(1e-9);
                break;
            }
            lambda *= 10.0;
        }
        let Some((trial, m, c, dq_trial)) = accepted else {
            break;
        };
        let gain = chi2 - c;
        *theta = trial;
        *model = m;
        chi2 = c;
        dq = dq_trial;
        // Move each start to where the linearisation says it belongs at these parameters.
        for (l, d) in lin.iter_mut().zip(&dq) {
            l.q.iter_mut().zip(d).for_each(|(q, d)| *q += d);
        }
        if gain < FIT_TOL.max(1e-6 * chi2) {
            break;
        }
    }
    let _ = dq;
    chi2
}

/// Stop fitting parameters when an iteration lowers χ² (in noise units) by less than this.
const FIT_TOL: f64 = 0.01;

/// Fit the free parameters of the effect `name` (already in `model`) (module docs), starting
/// from the start fits `fits` of the model without it. Returns the comparison at the fitted
/// values, and the parameter covariance.
fn fit(
    model: &mut Model,
    name: &str,
    free: &[Free],
    prep: &Prepared,
    baseline: &Baseline,
    iterations: usize,
) -> (Comparison, Option<Vec<f64>>) {
    let np = free.len();
    let fits = &baseline.fits;
    let starts: Vec<State> = fits.iter().map(|f| f.state).collect();
    if np == 0 {
        return (compare_from(model, prep, Some(&starts)), None);
    }
    let chi2_base: f64 = fits
        .iter()
        .map(|f| f.residuals.iter().map(|r| r * r).sum::<f64>())
        .sum();
    let mut theta = values(model, name, free);
    let mut lin: Vec<Linearised> = fits.iter().map(|f| Linearised::of(model, f)).collect();
    let mut linear = fit_linearised(model, name, free, &mut theta, prep, &mut lin, iterations);
    if !(chi2_base - linear > FIT_TOL.max(1e-6 * chi2_base)) {
        // The effect explains nothing the starts could not: its best values change the misfit
        // by less than a hundredth of a noise unit, so the comparison is the baseline's.
        let (a, _) = normal_equations(model, name, free, &theta, prep, &lin);
        let cov = covariance(&a, free, &baseline.comparison);
        return (baseline.comparison.clone(), cov);
    }
    // The linearisation is around the starts of the model without the effect; the starts are
    // then fitted exactly, and when that changes the misfit by more than the tolerance, the
    // fit is repeated around them.
    let mut exact: Option<(Comparison, Vec<StartFit>)> = None;
    for _ in 0..3 {
        let starts: Vec<State> = lin.iter().map(|l| l.state(model)).collect();
        let (cmp, new_fits) = compare_with_fits(model, prep, Some(&starts));
        let settled = (cmp.chi2 - linear).abs() < FIT_TOL.max(1e-4 * cmp.chi2);
        lin = new_fits.iter().map(|f| Linearised::of(model, f)).collect();
        exact = Some((cmp, new_fits));
        if settled {
            break;
        }
        linear = fit_linearised(model, name, free, &mut theta, prep, &mut lin, iterations);
    }
    let Some((cmp, _)) = exact else {
        unreachable!("the loop runs at least once");
    };
    let (a, _) = normal_equations(model, name, free, &theta, prep, &lin);
    let cov = covariance(&a, free, &cmp);
    (cmp, cov)
}

/// A model's comparison on prepared data together with its windows' start fits: what every
/// candidate effect is fitted from and scored against.
pub struct Baseline {
    /// The comparison.
    pub comparison: Comparison,
    fits: Vec<StartFit>,
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
fn free_params(
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
                spec: p,
                scale: p.scale_at(e.param(p.name).unwrap_or(0.0)),
            });
        }
    }
    Ok(free)
}

/// Try one effect on top of `base`: fit it and score it against the baseline. `fixed` lists
/// parameters not to fit; `candidates` is how many effects are being tried (for the
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
    let free = free_params(&mut model, &name, fixed, prep, true)?;
    let (after, cov) = fit(&mut model, &name, &free, prep, before, cfg.max_iterations);
    make_candidate(
        &model,
        &name,
        &free,
        &before.comparison,
        &after,
        cov,
        cfg,
        candidates,
    )
}

/// The full pass of a screened diagnosis: the base model and the best `top` candidates (at
/// their subset values) compared on every window in one pass; for each candidate, each
/// window's share of the parameters' normal equations is taken while its start fit exists, so
/// no window's Jacobian outlives it. Each candidate's parameters then take one Gauss–Newton
/// step on all windows — the all-window estimate, whose covariance is the all-window one —
/// while its errors are those at the subset values (the two differ by a few of the subset's
/// σ, which changes the misfit by a few units in hundreds of thousands).
fn full_pass(
    base: &Model,
    top: &[Candidate],
    full: &Prepared,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> (Comparison, Vec<Candidate>) {
    struct Fitting {
        model: Model,
        name: String,
        free: Vec<Free>,
        theta: Vec<f64>,
        perturbed: Vec<Model>,
    }
    let fittings: Vec<Fitting> = top
        .iter()
        .filter_map(|c| {
            let mut model = base.clone();
            model.add_effect(c.fitted_effect.clone()).ok()?;
            let held: Vec<String> = c
                .params
                .iter()
                .zip(&c.held)
                .filter(|(_, h)| **h)
                .map(|((k, _), _)| k.clone())
                .collect();
            let free = free_params(&mut model, &c.effect, &held, full, false).ok()?;
            let theta = values(&model, &c.effect, &free);
            let perturbed = perturbed_models(&model, &c.effect, &free, &theta);
            Some(Fitting {
                name: c.effect.clone(),
                model,
                free,
                theta,
                perturbed,
            })
        })
        .collect();
    let mut models: Vec<&Model> = vec![base];
    models.extend(fittings.iter().map(|f| &f.model));
    let results = compare_many(&models, full, None, |k, w, fit| {
        (k > 0).then(|| {
            let f = &fittings[k - 1];
            window_normal(
                &f.model,
                &f.perturbed,
                full,
                w,
                &Linearised::of(&f.model, fit),
            )
        })
    });
    let mut results = results.into_iter();
    let Some((base_cmp, _)) = results.next() else {
        unreachable!("compare_many returns one result per model");
    };
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
                .map(|((t, s), p)| (t + s * p.scale).clamp(p.spec.range.0, p.spec.range.1))
                .collect();
            set_values(&mut model, &f.name, &f.free, &theta);
        }
        let cov = (np > 0).then(|| covariance(&a, &f.free, &after)).flatten();
        if let Ok(c) = make_candidate(
            &model, &f.name, &f.free, &base_cmp, &after, cov, cfg, candidates,
        ) {
            out.push(c);
        }
    }
    (base_cmp, out)
}

/// Build the candidate's record from its fit.
#[allow(clippy::too_many_arguments)]
fn make_candidate(
    model: &Model,
    name: &str,
    free: &[Free],
    before: &Comparison,
    after: &Comparison,
    cov: Option<Vec<f64>>,
    cfg: &DiagnoseConfig,
    candidates: usize,
) -> Result<Candidate, String> {
    let fitted_effect = effect_box(model, name)?;
    let np = free.len();
    let sigma = |k: usize| cov.as_ref().map_or(f64::NAN, |c| c[k * np + k].sqrt());
    let mut params = Vec::new();
    let mut held = Vec::new();
    let mut uncertainty = Vec::new();
    for p in fitted_effect.params() {
        params.push((p.name.to_string(), p.value));
        match free.iter().position(|f| f.spec.name == p.name) {
            Some(k) => {
                held.push(false);
                uncertainty.push(sigma(k));
            }
            None => {
                held.push(true);
                uncertainty.push(f64::NAN);
            }
        }
    }
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
    let level = cfg.alpha / candidates.max(1) as f64;
    let lr_critical = chi2_quantile(1.0 - level, np.max(1) as f64);
    let significant = lr > lr_critical && after.chi2 < before.chi2 && excess_removed >= 0.2;
    Ok(Candidate {
        effect: name.to_string(),
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
        fitted_effect,
    })
}

fn effect_box(model: &Model, name: &str) -> Result<Box<dyn Effect>, String> {
    model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .cloned()
        .ok_or_else(|| format!("effect `{name}` was not added"))
}

/// Add effects to `model` as `--add` does: each spec's given parameters are held, the rest
/// fitted (on `prep`). Returns the fitted candidates, in order.
///
/// # Errors
/// Unknown effects or parameters, values out of range, an effect already in the model.
pub fn add_fitted(
    model: &mut Model,
    prep: &Prepared,
    adds: &[EffectSpec],
    cfg: &DiagnoseConfig,
) -> Result<Vec<Candidate>, String> {
    let mut out = Vec::new();
    for spec in adds {
        let effect = spec.build(&model.effect_context())?;
        let before = Baseline::of(model, prep);
        let cand = try_effect(model, effect, &spec.given(), prep, &before, cfg, 1)?;
        model.add_effect(cand.fitted_effect.clone())?;
        out.push(cand);
    }
    Ok(out)
}

/// The candidates of a diagnosis: every catalogue effect that applies and is not in the model
/// yet, plus the user's.
fn candidate_effects(base: &Model, extra: &[Box<dyn Effect>]) -> Vec<Box<dyn Effect>> {
    let ctx = base.effect_context();
    let kind = base.vehicle.kind();
    CATALOGUE
        .iter()
        .map(|info| info.build(&ctx))
        .chain(extra.iter().cloned())
        .filter(|e| e.applies_to(kind) && !base.has_effect(e.name()))
        .collect()
}

fn rank(ranking: &mut [Candidate]) {
    ranking.sort_by(|a, b| {
        a.noise_units_after
            .total_cmp(&b.noise_units_after)
            .then(a.fitted.cmp(&b.fitted))
    });
}

fn verdict(ranking: &[Candidate], noise_units: f64, at_floor: f64) -> Verdict {
    match ranking.iter().find(|c| c.significant) {
        Some(c) if !c.partial => Verdict::Effect(c.effect.clone()),
        Some(_) => Verdict::Unexplained,
        None if noise_units <= at_floor => Verdict::None,
        None => Verdict::Unexplained,
    }
}

/// Diagnose: try every catalogue effect that applies to the vehicle and is not in the model
/// yet, plus `extra` user effects; rank; decide (module docs).
///
/// # Errors
/// A flight too short for one comparison window.
pub fn diagnose(
    base: &Model,
    data: &FlightData,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
) -> Result<Diagnosis, String> {
    let full = Prepared::new(data, cfg.compare);
    if full.windows.is_empty() {
        return Err(format!(
            "the flight ({} samples, {:.2} s) is too short for one {:.1} s comparison window",
            data.len(),
            data.duration(),
            cfg.compare.window_s
        ));
    }
    let screened = cfg.screen_windows > 0 && full.windows.len() > cfg.screen_windows;
    let screen = screened.then(|| {
        Prepared::new(
            data,
            CompareConfig {
                max_windows: cfg.screen_windows,
                ..cfg.compare
            },
        )
    });
    let prep = screen.as_ref().unwrap_or(&full);
    let baseline = Baseline::of(base, prep);
    let effects = candidate_effects(base, extra);
    let k = effects.len();
    let mut ranking: Vec<Candidate> = effects
        .into_iter()
        .filter_map(|e| try_effect(base, e, &[], prep, &baseline, cfg, k).ok())
        .collect();
    rank(&mut ranking);
    let base_cmp = if screened {
        // The best on the subset, on every window (when it is significant there: otherwise
        // there is nothing to sharpen).
        let top = usize::from(ranking.first().is_some_and(|c| c.significant));
        let (base_cmp, refitted) = full_pass(base, &ranking[..top], &full, cfg, k);
        for c in refitted {
            if let Some(slot) = ranking.iter_mut().find(|r| r.effect == c.effect) {
                *slot = c;
            }
        }
        rank(&mut ranking);
        base_cmp
    } else {
        baseline.comparison
    };
    let noise_units = base_cmp.noise_units();
    Ok(Diagnosis {
        base_error: base_cmp.total,
        noise_floor: noise_floor(base, &full),
        noise_units,
        verdict: verdict(&ranking, noise_units, cfg.at_floor),
        ranking,
        windows: (full.windows.len(), prep.windows.len()),
        base_noise: full.noise,
        base: base_cmp,
    })
}

/// One rung of the `--iterate` ladder.
#[derive(Clone, Debug)]
pub struct Rung {
    /// Effects in the model at this rung.
    pub effects: Vec<String>,
    /// Total error of that model.
    pub error: f64,
    /// The diagnosis made at this rung.
    pub diagnosis: Diagnosis,
}

/// Diagnose, add the winner (with its fitted parameters), repeat until the verdict is not an
/// effect (at most `max_rungs` effects added). Returns the ladder and the final model.
///
/// # Errors
/// As [`diagnose`].
pub fn iterate(
    base: &Model,
    data: &FlightData,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
    max_rungs: usize,
) -> Result<(Vec<Rung>, Model), String> {
    let mut model = base.clone();
    let mut ladder = Vec::new();
    for _ in 0..=max_rungs {
        let diagnosis = diagnose(&model, data, extra, cfg)?;
        let winner = diagnosis.winner().map(|c| c.fitted_effect.clone());
        ladder.push(Rung {
            effects: model.effect_names(),
            error: diagnosis.base_error,
            diagnosis,
        });
        match winner {
            Some(e) if ladder.len() <= max_rungs => {
                if model.add_effect(e).is_err() {
                    break;
                }
            }
            _ => break,
        }
    }
    Ok((ladder, model))
}
