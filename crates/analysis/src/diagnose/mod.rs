//! What is wrong with the model? Try every applicable catalogue effect (and any user effect
//! given) and every number of the aircraft's parameter set — a coefficient, the mass, an
//! inertia: real models are wrong mostly in their own numbers — fit each together with every
//! window's start state, rank them on one scale by how much of the misfit they remove, test
//! whether that is more than fitting noise would give, and say honestly when nothing explains
//! what is left.
//!
//! * **Fitting** (output error with estimated start states): Levenberg–Marquardt on the
//!   effect's free parameters, each window's start re-fitted at every trial (warm-started), so
//!   the misfit is the profile over the starts. The parameter Jacobian is the variable
//!   projection one: the change of each window's residuals with a parameter, less what a start
//!   change could absorb. Parameters given by the user, and those known from the metadata
//!   (latitudes, [`wireflight_flight::effects::ParamSpec::from_origin`]), are held. Each parameter
//!   stays in its range.
//! * **Aircraft numbers** are screened all at once by the score test ([`screen`]); the most
//!   promising ones are fitted as candidates `aircraft:KEY` — those whose score could make
//!   them significant even if the fit removed four times as much (it removed at most 1.31
//!   times as much in the tests' fits).
//! * **Uncertainty**: the covariance (JᵀJ)⁻¹ of the projected Jacobian of noise-weighted
//!   residuals, scaled by the misfit per residual when it exceeds 1 and by the residuals'
//!   autocorrelation (AR(1): (1+ρ)/(1−ρ)); 1σ, with the correlation matrix. All windows count.
//! * **Significance**: the likelihood-ratio statistic N·ln(χ²₀/χ²₁) over the effectively
//!   independent residuals N (ν·(1−ρ)/(1+ρ): white residuals count fully, a smooth misfit
//!   hardly) against the χ² quantile for the number of fitted parameters at the family-wise
//!   level α split over all candidates, the screened aircraft numbers included (Bonferroni);
//!   and the candidate must remove at least a fifth of the misfit above the noise.
//! * **Verdict**: the significant candidate that leaves the least misfit, if it brings the
//!   error to the noise (≤ `at_floor` noise units); a significant candidate that leaves the
//!   error above the noise is only *partial*, and the verdict is then `unexplained`. Without a
//!   significant candidate: `none` when the error is at the noise, `unexplained` when it is not.
//!   An unexplained verdict comes with evidence: where the error is (channel and axis), the
//!   terms of the model that would reduce it most, and the conditions it follows.
//!   [`iterate`] applies the winner and repeats.
//!
//! Long flights are screened on a subset of windows (`screen_windows`), and the best
//! candidates then re-fitted on all of them.

mod fit;
pub mod screen;

use std::fmt;

use rayon::prelude::*;

use fit::{could_be_significant, full_pass};
pub use fit::{try_aircraft, try_effect, Baseline};
use screen::{score_aircraft, KeyScore};

use crate::compare::{noise_floor, AxisError, CompareConfig, Comparison, NoiseEstimate, Prepared};
use crate::free::KeyError;
use wireflight_flight::data::FlightData;
use wireflight_flight::effects::{Effect, ParamError, CATALOGUE};
use wireflight_flight::model::{Model, ModelError};
use wireflight_flight::spec::{EffectSpec, SpecError};

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

/// Why a diagnosis, or a correction, could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiagnoseError {
    /// The flight is too short for one comparison window.
    #[error(
        "the flight ({samples} samples, {duration_s:.2} s) is too short for one {window_s:.1} s \
         comparison window"
    )]
    TooShort {
        /// Samples in the flight.
        samples: usize,
        /// Its duration, s.
        duration_s: f64,
        /// The comparison window, s.
        window_s: f64,
    },
    /// The effect is not in the model.
    #[error("effect `{0}` was not added")]
    NotAdded(String),
    /// A parameter to hold that the effect does not have.
    #[error("effect `{effect}` has no parameter `{param}`")]
    NoParameter {
        /// The effect.
        effect: String,
        /// The parameter named.
        param: String,
    },
    /// An aircraft number that cannot be fitted.
    #[error(transparent)]
    Key(#[from] KeyError),
    /// The model refused a change: an effect that does not apply or is there already, an
    /// aircraft number out of range.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An effect refused a value of one of its parameters.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// An effect spec that does not build.
    #[error(transparent)]
    Spec(#[from] SpecError),
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
    /// The fitted correction, ready to apply to the model.
    pub correction: Correction,
}

impl Candidate {
    /// For a candidate of aircraft numbers, the relative change of each from the set, in %
    /// (empty for an effect).
    pub fn changes_percent(&self) -> Vec<(&'static str, f64)> {
        match &self.correction {
            Correction::Aircraft(changes) => changes
                .iter()
                .map(|c| (c.key, 100.0 * (c.value / c.was - 1.0)))
                .collect(),
            Correction::Effect(_) => Vec::new(),
        }
    }
}

/// A new value of one number of the aircraft's parameter set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AircraftChange {
    /// The key (`c_m_alpha`, `mass_kg`, …).
    pub key: &'static str,
    /// Its value in the model's set.
    pub was: f64,
    /// The fitted value.
    pub value: f64,
}

/// What a candidate changes in the model.
#[derive(Clone, Debug)]
pub enum Correction {
    /// Add this effect, with its fitted parameters.
    Effect(Box<dyn Effect>),
    /// Change numbers of the aircraft's parameter set.
    Aircraft(Vec<AircraftChange>),
}

impl Correction {
    /// Apply it to a model.
    ///
    /// # Errors
    /// The effect does not apply or is already there; a key the model does not have.
    pub fn apply(&self, model: &mut Model) -> Result<(), ModelError> {
        match self {
            Correction::Effect(e) => model.add_effect(e.clone()),
            Correction::Aircraft(changes) => changes
                .iter()
                .try_for_each(|c| model.set_aircraft(c.key, c.value)),
        }
    }
}

/// What the diagnosis concludes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// This correction (an effect name, or `aircraft:KEY`) is what the model lacks: applying
    /// it brings the error to the noise.
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
    pub base_noise: NoiseEstimate,
    /// Every number of the aircraft's set by the misfit it alone could remove (best first;
    /// empty for a point mass).
    pub aircraft_scores: Vec<KeyScore>,
    /// Where the error is and what it points to (for an unexplained or partial verdict).
    pub evidence: Vec<String>,
    /// Other candidates that explain the data as well as the verdict does (misfit left within
    /// [`EQUIVALENT`] of it): these data cannot tell them apart, e.g. ground effect at one
    /// constant height and a smaller induced-drag factor.
    pub alternatives: Vec<String>,
}

/// Two candidates whose misfits left differ by less than this fraction explain the data
/// equally well.
pub const EQUIVALENT: f64 = 0.01;

impl Diagnosis {
    /// The winning candidate, when the verdict is an effect.
    pub fn winner(&self) -> Option<&Candidate> {
        match &self.verdict {
            Verdict::Effect(v) => self.ranking.iter().find(|c| &c.effect == v),
            _ => None,
        }
    }
}

/// Add effects to `model` as `--add` does: each spec's given parameters are held, the rest
/// fitted (on `prep`). A spec named `aircraft` sets the numbers it gives a value
/// (`aircraft:c_m_alpha=-3.3`) and fits those it only names (`aircraft:c_m_alpha`), jointly.
/// Returns the fitted candidates, in order.
///
/// # Errors
/// Unknown effects, parameters or keys, values out of range, an effect already in the model.
pub fn add_fitted(
    model: &mut Model,
    prep: &Prepared,
    adds: &[EffectSpec],
    cfg: &DiagnoseConfig,
) -> Result<Vec<Candidate>, DiagnoseError> {
    let mut out = Vec::new();
    for spec in adds {
        if spec.is_aircraft() {
            for (k, v) in &spec.params {
                model.set_aircraft(k, *v)?;
            }
            let keys: Vec<&'static str> = spec
                .fit
                .iter()
                .map(|k| {
                    wireflight_flight::params::keys::find(k)
                        .map(|key| key.name)
                        .ok_or_else(|| KeyError::Unknown(k.clone()))
                })
                .collect::<Result<_, _>>()?;
            if keys.is_empty() {
                continue;
            }
            let before = Baseline::of(model, prep);
            let cand = try_aircraft(model, &keys, prep, &before, cfg, 1)?;
            cand.correction.apply(model)?;
            out.push(cand);
            continue;
        }
        let effect = spec.build(&model.effect_context())?;
        let before = Baseline::of(model, prep);
        let cand = try_effect(model, effect, &spec.given(), prep, &before, cfg, 1)?;
        cand.correction.apply(model)?;
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
) -> Result<Diagnosis, DiagnoseError> {
    let full = Prepared::new(data, cfg.compare);
    if full.windows.is_empty() {
        return Err(DiagnoseError::TooShort {
            samples: data.len(),
            duration_s: data.duration(),
            window_s: cfg.compare.window_s,
        });
    }
    let screened = cfg.screen_windows > 0 && full.windows.len() > cfg.screen_windows;
    let screen = screened.then(|| full.with_max_windows(cfg.screen_windows));
    let prep = screen.as_ref().unwrap_or(&full);
    let baseline = Baseline::of(base, prep);
    let effects = candidate_effects(base, extra);
    let scores = score_aircraft(base, prep, &baseline);
    // Every screened number counts against the significance level, fitted or not.
    let k = effects.len() + scores.len();
    // Candidates are fitted side by side as well as window by window: a fit's passes over
    // the few screened windows leave a core idle at every pass's end, and another
    // candidate's windows fill it.
    let trials: Vec<Trying> = effects
        .into_iter()
        .map(Trying::Effect)
        .chain(
            scores
                .iter()
                .take(AIRCRAFT_FITS)
                .filter(|s| could_be_significant(&baseline.comparison, s.reduction, cfg, k))
                .map(|s| Trying::Aircraft(s.key.name)),
        )
        .collect();
    let mut ranking: Vec<Candidate> = trials
        .into_par_iter()
        .filter_map(|t| match t {
            Trying::Effect(e) => try_effect(base, e, &[], prep, &baseline, cfg, k).ok(),
            Trying::Aircraft(key) => try_aircraft(base, &[key], prep, &baseline, cfg, k).ok(),
        })
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
    let verdict = verdict(&ranking, noise_units, cfg.at_floor);
    let alternatives = alternatives(&ranking, &verdict);
    let evidence = if verdict == Verdict::Unexplained {
        evidence(&base_cmp, &full, &scores)
    } else {
        Vec::new()
    };
    Ok(Diagnosis {
        base_error: base_cmp.total,
        noise_floor: noise_floor(base, &full),
        noise_units,
        verdict,
        ranking,
        windows: (full.windows.len(), prep.windows.len()),
        base_noise: full.noise,
        base: base_cmp,
        aircraft_scores: scores,
        evidence,
        alternatives,
    })
}

/// The significant, whole candidates other than the verdict that leave as little misfit.
fn alternatives(ranking: &[Candidate], verdict: &Verdict) -> Vec<String> {
    let Verdict::Effect(name) = verdict else {
        return Vec::new();
    };
    let Some(best) = ranking.iter().find(|c| &c.effect == name) else {
        return Vec::new();
    };
    let limit = best.noise_units_after * (1.0 + EQUIVALENT);
    ranking
        .iter()
        .filter(|c| &c.effect != name && c.significant && !c.partial)
        .filter(|c| c.noise_units_after <= limit)
        .map(|c| c.effect.clone())
        .collect()
}

/// A candidate correction to fit.
enum Trying {
    Effect(Box<dyn Effect>),
    Aircraft(&'static str),
}

/// How many of the best-scoring aircraft numbers are fitted as candidates.
const AIRCRAFT_FITS: usize = 5;

/// Where the error of a comparison is, and which terms of the model would reduce it most.
fn evidence(cmp: &Comparison, prep: &Prepared, scores: &[KeyScore]) -> Vec<String> {
    let n = &prep.noise;
    let sigma = |channel: &str, axis: &str| -> Option<f64> {
        let k = match axis {
            "north" | "roll" | "p" => 0,
            "east" | "pitch" | "q" => 1,
            "down" | "yaw" | "r" => 2,
            _ => return (channel == "air" && axis == "airspeed").then_some(n.airspeed_mps),
        };
        match channel {
            "position" => Some(n.pos_axes[k]),
            "velocity" => Some(n.vel_axes[k]),
            "attitude" => Some(n.att_axes[k].to_degrees()),
            "rates" => Some(n.rate_axes[k].to_degrees()),
            _ => None,
        }
    };
    let mut axes: Vec<(f64, &AxisError)> = cmp
        .axes
        .iter()
        .filter_map(|a| {
            let s = sigma(a.channel, a.axis)?;
            (s > 0.0).then(|| (a.rms / s, a))
        })
        .collect();
    axes.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out = Vec::new();
    if !axes.is_empty() {
        let parts: Vec<String> = axes
            .iter()
            .take(3)
            .map(|(ratio, a)| {
                format!(
                    "{} {} ({} {} RMS, {} × its noise)",
                    a.channel,
                    a.axis,
                    wireflight_flight::numeric::format::fixed(a.rms, 3),
                    a.unit,
                    wireflight_flight::numeric::format::fixed(*ratio, 1)
                )
            })
            .collect();
        out.push(format!("the error is largest in {}", parts.join(", ")));
    }
    let excess = (cmp.chi2 - cmp.dof).max(0.0);
    let terms: Vec<String> = scores
        .iter()
        .take(3)
        .filter(|s| excess > 0.0 && s.reduction > 0.01 * excess)
        .map(|s| {
            format!(
                "{} ({}: {}% of the misfit above the noise)",
                s.key.term,
                s.key.name,
                wireflight_flight::numeric::format::fixed(
                    100.0 * (s.reduction / excess).min(1.0),
                    0
                )
            )
        })
        .collect();
    if !terms.is_empty() {
        out.push(format!(
            "the terms of the model that would reduce it most: {}",
            terms.join("; ")
        ));
    }
    out
}

/// One rung of the `--iterate` ladder.
#[derive(Clone, Debug)]
pub struct Rung {
    /// Corrections applied at this rung (effect names, `aircraft:KEY`).
    pub effects: Vec<String>,
    /// Total error of that model.
    pub error: f64,
    /// The diagnosis made at this rung.
    pub diagnosis: Diagnosis,
}

/// Diagnose, apply the best significant candidate (with its fitted parameters, even when it
/// only explains part of the error), repeat until no candidate is significant (at most
/// `max_rungs` applied). Returns the ladder and the final model.
///
/// # Errors
/// As [`diagnose`].
pub fn iterate(
    base: &Model,
    data: &FlightData,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
    max_rungs: usize,
) -> Result<(Vec<Rung>, Model), DiagnoseError> {
    let mut model = base.clone();
    let mut applied = model.effect_names();
    let mut ladder = Vec::new();
    for _ in 0..=max_rungs {
        let diagnosis = diagnose(&model, data, extra, cfg)?;
        // The best significant candidate, even a partial one: the ladder peels one correction
        // at a time when several are missing.
        let winner = diagnosis
            .ranking
            .iter()
            .find(|c| c.significant)
            .map(|c| (c.effect.clone(), c.correction.clone()));
        ladder.push(Rung {
            effects: applied.clone(),
            error: diagnosis.base_error,
            diagnosis,
        });
        match winner {
            Some((label, c)) if ladder.len() <= max_rungs => {
                if c.apply(&mut model).is_err() {
                    break;
                }
                applied.push(label);
            }
            _ => break,
        }
    }
    Ok((ladder, model))
}
