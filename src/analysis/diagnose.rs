//! Which physical effect is missing? Try every applicable catalogue effect (and any user
//! effect given), fit its parameters, rank by how much of the error it removes, and test
//! whether the improvement is more than fitting noise.
//!
//! * **Fitting** (output error): Levenberg–Marquardt on the per-window scores of the
//!   multiple-shooting comparison ([`super::compare`]), finite-difference Jacobian, parameters
//!   scaled by a typical size each. Parameters given by the user, and latitudes known from the
//!   data's metadata, are held fixed. The covariance `s²(JᵀJ)⁻¹` gives the ± uncertainty.
//! * **Significance**: windows are the independent units (samples within a window are
//!   correlated). The likelihood-ratio statistic `W·ln(SSE₀/SSE₁)` is compared with the χ²
//!   quantile at 1% for the number of fitted parameters (at least 1), so adding parameters has
//!   to buy more than noise would give; and the effect must remove at least a fifth of the
//!   error above the noise floor.
//! * **Verdict**: the significant candidate that removes the most error, or none when the
//!   baseline is already within 20% of the noise floor (few windows) or nothing is significant.
//!   [`iterate`] adds the winner and repeats until nothing is left.

use super::compare::{compare_prepared, estimate_noise, noise_floor, CompareConfig, Prepared};
use crate::flight::data::FlightData;
use crate::flight::effects::{Effect, CATALOGUE};
use crate::flight::model::Model;
use crate::flight::spec::EffectSpec;

/// Settings of a diagnosis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagnoseConfig {
    /// Comparison settings used for fitting and scoring.
    pub compare: CompareConfig,
    /// Levenberg–Marquardt iterations per candidate.
    pub max_iterations: usize,
    /// Significance level of the likelihood-ratio test (0.01 or 0.05).
    pub alpha: f64,
}

impl Default for DiagnoseConfig {
    fn default() -> Self {
        Self {
            compare: CompareConfig {
                max_windows: 32,
                ..CompareConfig::default()
            },
            max_iterations: 12,
            alpha: 0.01,
        }
    }
}

/// One tried effect.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Effect name.
    pub effect: String,
    /// Parameters after fitting (fitted and fixed), name → value.
    pub params: Vec<(String, f64)>,
    /// ± one standard deviation of each fitted parameter (NaN for fixed ones).
    pub uncertainty: Vec<f64>,
    /// Number of fitted parameters.
    pub fitted: usize,
    /// Total error without the effect.
    pub error_before: f64,
    /// Total error with the fitted effect.
    pub error_after: f64,
    /// Fraction of the error removed, (before − after)/before.
    pub error_reduction: f64,
    /// Fraction of the error *above the noise floor* removed.
    pub excess_removed: f64,
    /// Likelihood-ratio statistic W·ln(SSE₀/SSE₁).
    pub lr_statistic: f64,
    /// Passed the significance test and the materiality threshold.
    pub significant: bool,
    /// The fitted effect, ready to add to the model.
    pub fitted_effect: Box<dyn Effect>,
}

/// Result of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// Total error of the model as given.
    pub base_error: f64,
    /// Error expected from measurement noise alone.
    pub noise_floor: f64,
    /// Candidates, most error removed first.
    pub ranking: Vec<Candidate>,
    /// The most likely missing effect, or None.
    pub verdict: Option<String>,
}

impl Diagnosis {
    /// The winning candidate.
    pub fn winner(&self) -> Option<&Candidate> {
        let v = self.verdict.as_ref()?;
        self.ranking.iter().find(|c| &c.effect == v)
    }
}

/// The χ² quantile that `dof` degrees of freedom exceed with probability `alpha`.
fn chi2_critical(dof: usize, alpha: f64) -> f64 {
    crate::numeric::chi2_quantile(1.0 - alpha, dof.max(1) as f64)
}

/// Per-window weighted residuals: score_w·√n_w, so Σ r² = total²·N.
fn residuals(model: &Model, prep: &Prepared) -> Vec<f64> {
    let c = compare_prepared(model, prep);
    c.windows
        .iter()
        .map(|w| w.score * ((w.samples.1 - w.samples.0) as f64).sqrt())
        .collect()
}

fn sse(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// How many independent residuals the likelihood-ratio test may count (see module docs):
/// samples when each window's start is fitted over the whole window (what is left is white
/// measurement noise), otherwise windows (a start fitted from the first `fit_s` carries its
/// error through the window, so its samples are correlated).
fn independent_units(model: &Model, prep: &Prepared) -> f64 {
    let whole_window_fit = prep.config().refine_point_mass
        && matches!(model.vehicle, crate::flight::model::Vehicle::PointMass);
    if whole_window_fit {
        prep.windows.iter().map(|(a, b)| b - a).sum::<usize>() as f64
    } else {
        prep.windows.len() as f64
    }
}

fn total_from_sse(sse: f64, prep: &Prepared) -> f64 {
    let n: usize = prep.windows.iter().map(|(a, b)| b - a).sum();
    (sse / n.max(1) as f64).sqrt()
}

/// Fit the parameters `free` of the effect `name` inside `model` (already added) by
/// Levenberg–Marquardt. Returns (SSE, uncertainties of the free parameters).
fn fit(
    model: &mut Model,
    name: &str,
    free: &[String],
    prep: &Prepared,
    iterations: usize,
) -> (f64, Vec<f64>) {
    let Some(info) = model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .map(|e| e.info())
    else {
        return (f64::NAN, Vec::new());
    };
    let specs: Vec<_> = free.iter().filter_map(|p| info.param(p)).collect();
    let get = |m: &Model| -> Vec<f64> {
        let e = m.effects.iter().find(|e| e.name() == name);
        free.iter()
            .map(|p| e.and_then(|e| e.param(p)).unwrap_or(0.0))
            .collect()
    };
    // The fitter stays inside each parameter's range: a step beyond it lands on the bound.
    let set = |m: &mut Model, v: &[f64]| {
        if let Some(e) = m.effect_mut(name) {
            for (spec, x) in specs.iter().zip(v) {
                let _ = e.set_param(spec.name, x.clamp(spec.range.0, spec.range.1));
            }
        }
    };
    let mut theta = get(model);
    let scales: Vec<f64> = specs
        .iter()
        .zip(&theta)
        .map(|(spec, v)| spec.scale_at(*v))
        .collect();
    let mut r = residuals(model, prep);
    let mut cost = sse(&r);
    let np = free.len();
    let mut lambda = 1e-3;
    // SSE one finite-difference step up each parameter, from the last Jacobian, and the
    // gradient there: the curvature of the SSE for the uncertainty, at no extra cost.
    let mut sse_up = vec![f64::NAN; np];
    let mut grad = vec![0.0; np];
    let mut jac_cost = cost;
    for _ in 0..iterations {
        if np == 0 {
            break;
        }
        // Jacobian in scaled parameters (forward differences of 1% of the scale).
        let mut jac = vec![vec![0.0; np]; r.len()];
        for j in 0..np {
            let h = 0.01 * scales[j];
            let mut t = theta.clone();
            t[j] += h;
            set(model, &t);
            let rp = residuals(model, prep);
            sse_up[j] = sse(&rp);
            for i in 0..r.len() {
                jac[i][j] = (rp[i] - r[i]) / 0.01;
            }
        }
        jac_cost = cost;
        set(model, &theta);
        let mut jtj = vec![vec![0.0; np]; np];
        let mut jtr = vec![0.0; np];
        for i in 0..r.len() {
            for a in 0..np {
                jtr[a] += jac[i][a] * r[i];
                for b in 0..np {
                    jtj[a][b] += jac[i][a] * jac[i][b];
                }
            }
        }
        for (g, v) in grad.iter_mut().zip(&jtr) {
            *g = 2.0 * v;
        }
        let mut improved = false;
        for _ in 0..8 {
            let mut a = jtj.clone();
            for k in 0..np {
                a[k][k] += lambda * jtj[k][k].max(1e-12);
            }
            let Some(step) =
                crate::numeric::solve_rows(&a, &jtr.iter().map(|v| -v).collect::<Vec<_>>())
            else {
                lambda *= 10.0;
                continue;
            };
            let cand: Vec<f64> = theta
                .iter()
                .zip(&step)
                .zip(&scales)
                .map(|((t, s), sc)| t + s * sc)
                .collect();
            set(model, &cand);
            let rc = residuals(model, prep);
            let c = sse(&rc);
            if c.is_finite() && c < cost {
                theta = get(model); // the effect may clamp (e.g. τ ≥ 1 ms)
                r = rc;
                let rel = (cost - c) / cost;
                cost = c;
                lambda = (lambda / 3.0).max(1e-9);
                improved = rel > 1e-4; // below 0.01% of the SSE a step changes no ranking
                break;
            }
            lambda *= 10.0;
        }
        set(model, &theta);
        if !improved {
            break;
        }
    }
    // Uncertainty: the SSE's curvature along each parameter, H = 2(SSE(θ+h) − SSE(θ) − g·h)/h²
    // (h = 1% of the parameter's scale, from the last Jacobian), and the residual variance per
    // independent unit s² = SSE/(units − p): σ² = 2s²/H. Per-window scores are not residuals
    // whose Jacobian gives the SSE's curvature (their square roots are far from zero at the
    // optimum), so s²(JᵀJ)⁻¹ of them would mislead. Correlations between parameters are not
    // shown (σ is each parameter's own).
    let units = independent_units(model, prep);
    let s2 = cost / (units - np as f64).max(1.0);
    let h = 0.01;
    let unc = (0..np)
        .map(|k| {
            let curvature = 2.0 * (sse_up[k] - jac_cost - grad[k] * h) / (h * h);
            if curvature > 0.0 && curvature.is_finite() {
                (2.0 * s2 / curvature).sqrt() * scales[k]
            } else {
                f64::NAN
            }
        })
        .collect();
    (cost, unc)
}

/// Try one effect on top of `base`: fit it and score it. `fixed` lists parameters not to fit.
pub fn try_effect(
    base: &Model,
    effect: Box<dyn Effect>,
    fixed: &[String],
    prep: &Prepared,
    cfg: &DiagnoseConfig,
    before_sse: f64,
    floor: f64,
) -> Result<Candidate, String> {
    let name = effect.name().to_string();
    let mut model = base.clone();
    model.add_effect(effect)?;
    let info = model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .map(|e| e.info())
        .ok_or_else(|| format!("effect `{name}` was not added"))?;
    let held_origin = prep.data.meta.latitude_deg.is_some();
    let free: Vec<String> = info
        .params
        .iter()
        .filter(|p| !fixed.iter().any(|f| f == p.name) && !(p.from_origin && held_origin))
        .map(|p| p.name.to_string())
        .collect();
    if let Some(e) = model.effect_mut(&name) {
        for p in info
            .params
            .iter()
            .filter(|p| free.iter().any(|f| f == p.name))
        {
            if let Some(start) = p.start {
                e.set_param(p.name, start)?;
            }
        }
    }
    let (after_sse, fitted_unc) = fit(&mut model, &name, &free, prep, cfg.max_iterations);
    let effect = model
        .effects
        .iter()
        .find(|e| e.name() == name)
        .ok_or_else(|| format!("effect `{name}` was not added"))?;
    let params: Vec<(String, f64)> = effect
        .params()
        .iter()
        .map(|p| (p.name.to_string(), p.value))
        .collect();
    let uncertainty = params
        .iter()
        .map(|(n, _)| {
            free.iter()
                .position(|f| f == n)
                .map(|k| fitted_unc[k])
                .unwrap_or(f64::NAN)
        })
        .collect();
    let before = total_from_sse(before_sse, prep);
    let after = total_from_sse(after_sse, prep);
    let units = independent_units(&model, prep);
    let lr = if after_sse > 0.0 {
        units * (before_sse / after_sse).ln()
    } else {
        f64::INFINITY
    };
    let excess = (before - floor).max(1e-12);
    let excess_removed = ((before - after) / excess).clamp(-1.5, 1.5);
    // With few independent units (windows) the floor itself is uncertain by tens of percent,
    // so the baseline must clear it by a margin; with thousands of white residuals the
    // likelihood-ratio test alone decides how far above the floor is real.
    let floor_margin = if units > 1000.0 { 1.0 } else { 1.2 };
    let significant = lr > chi2_critical(free.len().max(1), cfg.alpha)
        && after < before
        && excess_removed >= 0.2
        && before > floor_margin * floor;
    Ok(Candidate {
        effect: name,
        params,
        uncertainty,
        fitted: free.len(),
        error_before: before,
        error_after: after,
        error_reduction: if before > 0.0 {
            (before - after) / before
        } else {
            0.0
        },
        excess_removed,
        lr_statistic: lr,
        significant,
        fitted_effect: effect.clone_box(),
    })
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
        let before = sse(&residuals(model, prep));
        let cand = try_effect(model, effect, &spec.given(), prep, cfg, before, 0.0)?;
        model.add_effect(cand.fitted_effect.clone())?;
        out.push(cand);
    }
    Ok(out)
}

/// Diagnose: try every catalogue effect that applies to the vehicle and is not in the model
/// yet, plus `extra` user effects; rank; decide.
pub fn diagnose(
    base: &Model,
    data: &FlightData,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
) -> Diagnosis {
    let prep = Prepared::new(data, cfg.compare);
    let before_sse = sse(&residuals(base, &prep));
    let base_error = total_from_sse(before_sse, &prep);
    let floor = noise_floor(base, &prep, &estimate_noise(data), 0x5eed);
    // Parameters known from the metadata (latitudes) are facts, not unknowns (see
    // `ParamSpec::from_origin`).
    let fixed: Vec<String> = Vec::new();
    let kind = base.vehicle.kind();
    let ctx = base.effect_context();
    let mut candidates: Vec<Box<dyn Effect>> =
        CATALOGUE.iter().map(|info| info.build(&ctx)).collect();
    candidates.extend(extra.iter().cloned());
    let mut ranking: Vec<Candidate> = candidates
        .into_iter()
        .filter(|e| e.applies_to(kind) && !base.has_effect(e.name()))
        .filter_map(|e| try_effect(base, e, &fixed, &prep, cfg, before_sse, floor).ok())
        .collect();
    ranking.sort_by(|a, b| a.error_after.total_cmp(&b.error_after));
    let verdict = ranking
        .iter()
        .find(|c| c.significant)
        .map(|c| c.effect.clone());
    Diagnosis {
        base_error,
        noise_floor: floor,
        ranking,
        verdict,
    }
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

/// Diagnose, add the winner (with its fitted parameters), repeat until nothing significant is
/// left (at most `max_rungs` effects added). Returns the ladder and the final model.
pub fn iterate(
    base: &Model,
    data: &FlightData,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
    max_rungs: usize,
) -> (Vec<Rung>, Model) {
    let mut model = base.clone();
    let mut ladder = Vec::new();
    for _ in 0..=max_rungs {
        let diagnosis = diagnose(&model, data, extra, cfg);
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
    (ladder, model)
}
