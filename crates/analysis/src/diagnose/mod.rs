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
//!   autocorrelation (AR(1): (1+ρ)/(1−ρ)); where the windows' scatter (a cluster sandwich)
//!   exceeds it beyond chance, that. 1σ, with the correlation matrix. All windows count.
//!   Where the flight's errors are stated to wander ([`crate::error_floor`]), the
//!   autocorrelation factor is each residual row's own where the fit moved it
//!   ([`crate::compare::colour_factor`]), the same that deflates the likelihood ratio.
//! * **Significance**: the likelihood-ratio statistic N·ln(χ²₀/χ²₁) over the effectively
//!   independent residuals N (ν·(1−ρ)/(1+ρ): white residuals count fully, a smooth misfit
//!   hardly; with stated wandering errors ν over [`crate::compare::colour_factor`]) against
//!   the χ² quantile for the number of fitted parameters at the family-wise level α split
//!   over all candidates, the screened aircraft numbers included (Bonferroni);
//!   the candidate must remove at least a fifth of the misfit above the noise, and no fitted
//!   value may end at a limit of its range.
//! * **Several causes** (`joint`): forward selection with backward elimination — the best
//!   significant candidate is kept, every cause kept is refitted together with it, a cause
//!   the others make unnecessary is dropped, and the search repeats on top of them until no
//!   candidate is significant by the same test.
//! * **Verdict**: the causes kept, when together they bring the error to the noise
//!   (≤ `at_floor` noise units); `unexplained` when they leave it above (what was found is
//!   part of the answer), or when nothing is significant and the error is above the noise;
//!   `none` when nothing is significant and the error is at the noise (the noise: with
//!   references their floor, with stated wandering errors the floor those leave). An
//!   unexplained verdict comes with evidence: where the error is (channel and axis), the
//!   terms of the model that would reduce it most, and the conditions it follows.
//!
//! Long flights are screened on a subset of windows (`screen_windows`), and the causes found
//! then fitted on all of them.

mod fit;
mod joint;
pub mod reference;
mod request;
pub mod screen;
pub mod turbulence;

pub use request::{run, Request, RunError};

use std::fmt;

use rayon::prelude::*;

use fit::{could_be_significant, lr_critical, Trial};
pub use fit::{try_aircraft, try_effect, Baseline};
use joint::{fit_joint, full_pass, JointFit, Member};
use screen::{score_aircraft, score_effect, KeyScore};

use crate::compare::{noise_floor, AxisError, CompareConfig, Comparison, NoiseEstimate, Prepared};
use crate::free::KeyError;
use wireflight_data::FlightData;
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
    /// At most this many causes are kept together.
    pub max_causes: usize,
}

impl Default for DiagnoseConfig {
    fn default() -> Self {
        Self {
            compare: CompareConfig::default(),
            max_iterations: 10,
            alpha: 0.01,
            screen_windows: 24,
            at_floor: 1.25,
            max_causes: 5,
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
    /// Whether each fitted parameter ended at the edge of its range (its physical range for
    /// an aircraft number): the data pushed it there, so it is no estimate. A candidate with
    /// one is never significant.
    pub at_limit: Vec<bool>,
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
    /// Fitted together with the causes already kept (their values moved too), rather than
    /// alone on top of them.
    pub joint: bool,
    /// The fitted correction, ready to apply to the model.
    pub correction: Correction,
    /// The comparison of the model with it, on the windows it was fitted on (kept so a
    /// selection that keeps it need not fit it again).
    pub(crate) comparison: Option<std::sync::Arc<Comparison>>,
}

impl Candidate {
    /// For a candidate of aircraft numbers, the relative change of each from the set, in %
    /// (None where the set has 0: the term is new), empty for an effect.
    pub fn changes_percent(&self) -> Vec<(&'static str, Option<f64>)> {
        match &self.correction {
            Correction::Aircraft(changes) => changes
                .iter()
                .map(|c| {
                    (
                        c.key,
                        (c.was != 0.0).then(|| 100.0 * (c.value / c.was - 1.0)),
                    )
                })
                .collect(),
            Correction::Effect(_) => Vec::new(),
        }
    }

    /// Whether any fitted parameter ended at its limit.
    pub fn any_at_limit(&self) -> bool {
        self.at_limit.iter().any(|&l| l)
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
    /// These corrections (effect names, `aircraft:KEY`), fitted together, are what the model
    /// lacks: applying them brings the error to the noise.
    Found(Vec<String>),
    /// The error is at the noise floor: nothing is missing that these data could show.
    None,
    /// The error is above the noise floor and no candidate brings it there.
    Unexplained,
    /// What output error leaves is random: gusts the filter-error method estimates
    /// ([`turbulence`]), with these causes besides (refitted through the filter).
    Turbulence(Vec<String>),
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Found(names) => f.write_str(&names.join(" + ")),
            Verdict::None => f.write_str("none"),
            Verdict::Unexplained => f.write_str("unexplained"),
            Verdict::Turbulence(names) if names.is_empty() => f.write_str("turbulence"),
            Verdict::Turbulence(names) => write!(f, "turbulence + {}", names.join(" + ")),
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
    /// Candidates against the model as given, least misfit left first (the first step's).
    pub ranking: Vec<Candidate>,
    /// The conclusion.
    pub verdict: Verdict,
    /// The causes the selection kept, with their values from the joint fit on every window
    /// (errors from the model as given to all of them applied; each one's likelihood-ratio
    /// test is that of the model without it, given the others). With a `None` verdict,
    /// empty; with an `Unexplained` one, what was found before the selection stopped short
    /// of the noise.
    pub found: Vec<Candidate>,
    /// Total error with every cause found applied (the base error when none was).
    pub found_error: f64,
    /// Misfit with every cause found applied, in noise units.
    pub found_noise_units: f64,
    /// How the selection went: one step per screening of the candidates.
    pub steps: Vec<Step>,
    /// Corrections the significance level was shared over at the first step.
    pub candidates: usize,
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
    /// Against reference flights ([`reference::diagnose_against`]): the floor they measured
    /// and each cause's change from them. None for a diagnosis against the noise alone.
    pub reference: Option<reference::ReferenceVerdict>,
    /// The floor stated sensor errors leave, where the diagnosis was judged against it
    /// ([`crate::error_floor`]). None against the noise alone or against reference flights.
    pub error_floor: Option<crate::error_floor::ErrorFloor>,
    /// The filter-error method's account where it was tried ([`turbulence`]).
    pub turbulence: Option<turbulence::TurbulenceFinding>,
}

/// Two candidates whose misfits left differ by less than this fraction explain the data
/// equally well.
pub const EQUIVALENT: f64 = 0.01;

impl Diagnosis {
    /// `base` with every cause found applied, and the numbers the filter's own search added
    /// in turbulence: the model a model file keeps.
    ///
    /// # Errors
    /// A cause that does not apply to `base` (a diagnosis of another model).
    pub fn model_with_causes(&self, base: &Model) -> Result<Model, ModelError> {
        let mut model = base.clone();
        for c in &self.found {
            c.correction.apply(&mut model)?;
        }
        for r in self.search_added() {
            model.set_aircraft(&r.param, r.value)?;
        }
        Ok(model)
    }

    /// The names of the causes [`Self::model_with_causes`] applies, in its order.
    pub fn cause_names(&self) -> Vec<&str> {
        self.found
            .iter()
            .map(|c| c.effect.as_str())
            .chain(self.search_added().map(|r| r.cause.as_str()))
            .collect()
    }

    /// The numbers the filter's own search found in turbulence.
    fn search_added(&self) -> impl Iterator<Item = &turbulence::Refit> {
        self.turbulence
            .iter()
            .flat_map(|t| t.refits.iter().filter(|r| r.added))
    }

    /// The one cause found, when the verdict names exactly one.
    pub fn winner(&self) -> Option<&Candidate> {
        match (&self.verdict, self.found.as_slice()) {
            (Verdict::Found(names), [c]) if names.len() == 1 => Some(c),
            _ => None,
        }
    }
}

/// One step of the selection: the candidates screened against the model with the causes
/// kept so far, and what the step changed.
#[derive(Clone, Debug)]
pub struct Step {
    /// The causes in the model the candidates were screened against.
    pub effects: Vec<String>,
    /// That model's total error and misfit in noise units (on the screened windows).
    pub error: f64,
    /// See `error`.
    pub noise_units: f64,
    /// The candidates, least misfit left first, each fitted alone on top of that model.
    pub ranking: Vec<Candidate>,
    /// The significant candidate this step added (None: the selection stopped here).
    pub added: Option<String>,
    /// Causes dropped after the addition: given the others, the data no longer needed them.
    pub dropped: Vec<String>,
    /// Other candidates of this step that explain the data as well as the one added
    /// (misfit within [`EQUIVALENT`] of it): these data cannot tell them apart.
    pub alternatives: Vec<String>,
    /// The causes after this step, fitted jointly (on the screened windows).
    pub fitted: Vec<Candidate>,
    /// Total error and misfit in noise units of the joint fit after this step.
    pub error_after: f64,
    /// See `error_after`.
    pub noise_units_after: f64,
}

/// Add effects to `model` as `--add` does: each spec's given parameters are held, the rest
/// fitted (on `prep`). A spec named `aircraft` sets the numbers it gives a value
/// (`aircraft:c_m_alpha=-3.3`) and fits those it only names (`aircraft:c_m_alpha`). Each
/// is fitted in turn on top of the ones before, and then, when there are several, all of
/// them together (`joint`): the values and ± returned are the joint ones, the errors
/// those from the model as given to all of them applied. Returns the fitted candidates, in
/// order.
///
/// # Errors
/// Unknown effects, parameters or keys, values out of range, an effect already in the model.
pub fn add_fitted(
    model: &mut Model,
    prep: &Prepared,
    adds: &[EffectSpec],
    cfg: &DiagnoseConfig,
) -> Result<Vec<Candidate>, DiagnoseError> {
    let original = model.clone();
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
    if out.len() < 2 {
        return Ok(out);
    }
    let members: Vec<Member> = out.iter().map(Member::of).collect();
    let start = Baseline::of(model, prep);
    let mut joint = fit_joint(model.clone(), members, prep, &start, cfg.max_iterations)?;
    let before = Baseline::of(&original, prep).comparison;
    let _ = joint.test_members(&[], &original, prep, cfg.max_iterations)?;
    *model = joint.model.clone();
    Ok(joint.records(&original, &before, cfg, 1))
}

/// The terms a model declares without values (a model file's `[[term]]` with no
/// coefficient given: every coefficient at 0, where it changes nothing), taken out of
/// `model`: they are candidates of the diagnosis, fitted and ranked with the catalogue's,
/// not part of the model it starts from. A term given values stays in the model.
pub fn take_declared_terms(model: &mut Model) -> Vec<Box<dyn Effect>> {
    let is_declared = |e: &dyn Effect| {
        wireflight_flight::effects::term::term_of(e.info()).is_some()
            && e.info()
                .params
                .iter()
                .zip(e.values())
                .all(|(p, v)| p.absent == Some(*v))
    };
    let (declared, kept) = std::mem::take(&mut model.effects)
        .into_iter()
        .partition(|e| is_declared(e.as_ref()));
    model.effects = kept;
    declared
}

/// The candidates of a diagnosis: every catalogue effect that applies and is not in the model
/// yet, plus the user's; a measurement effect only where the flight records a channel it
/// changes (a gyro's bias cannot show in rates differentiated from the attitude), and an
/// effect that acts from a recorded channel only where the model was built with it.
fn candidate_effects(
    base: &Model,
    prep: &Prepared,
    extra: &[Box<dyn Effect>],
) -> Vec<Box<dyn Effect>> {
    let ctx = base.effect_context();
    let kind = base.vehicle.kind();
    let measured = prep.measured.for_vehicle(base);
    CATALOGUE
        .iter()
        .map(|info| info.build(&ctx))
        .chain(extra.iter().cloned())
        .filter(|e| e.applies_to(kind) && !base.has_effect(e.name()))
        .filter(|e| e.lacks_channel().is_none())
        .filter(|e| {
            let channels = e.channels();
            channels.is_empty() || channels.iter().any(|&c| measured.records(c, prep.data))
        })
        .collect()
}

fn rank(ranking: &mut [Candidate]) {
    ranking.sort_by(|a, b| {
        a.noise_units_after
            .total_cmp(&b.noise_units_after)
            .then(a.fitted.cmp(&b.fitted))
    });
}

/// The numbers of the aircraft's set that the score test says could still explain a
/// significant part of `model`'s misfit on `prep` — the screen `diagnose` runs before it
/// fits any (`could_be_significant`) — best first. What `compare` checks before it calls
/// an error near the noise "at the floor". Empty for a point mass.
pub fn promising_numbers(model: &Model, prep: &Prepared, cfg: &DiagnoseConfig) -> Vec<KeyScore> {
    if prep.windows.is_empty() {
        return Vec::new();
    }
    let baseline = Baseline::of(model, prep);
    let scores = score_aircraft(model, prep, &baseline);
    let k = candidate_effects(model, prep, &[]).len() + scores.len();
    scores
        .into_iter()
        .filter(|s| could_be_significant(&baseline.comparison, s.reduction, cfg, k))
        .collect()
}

/// One screening: every candidate fitted alone on top of `model` (on `prep`), ranked. The
/// aircraft numbers in `taken` are not tried again; with `rescreen`, effects whose score
/// could not make them significant are not fitted. Returns the ranking, the aircraft
/// numbers' scores, and how many corrections the significance level is shared over.
fn screen_round(
    model: &Model,
    prep: &Prepared,
    baseline: &Baseline,
    extra: &[Box<dyn Effect>],
    (taken, rescreen): (&[&'static str], bool),
    cfg: &DiagnoseConfig,
) -> (Vec<Candidate>, Vec<KeyScore>, usize) {
    let effects = candidate_effects(model, prep, extra);
    let scores: Vec<KeyScore> = score_aircraft(model, prep, baseline)
        .into_iter()
        .filter(|s| !taken.contains(&s.key.name))
        .collect();
    // Every screened number counts against the significance level, fitted or not.
    let k = effects.len() + scores.len();
    // With causes kept, the effects too are screened by their score first: after the
    // causes that explain the flight, most effects could not be significant, and fitting
    // each again would cost the hour's diagnosis a second full screening (measured: 1.2 s
    // of 5.8 s). Those without absent values are fitted as before.
    let effects: Vec<Box<dyn Effect>> = if !rescreen {
        effects
    } else {
        effects
            .into_par_iter()
            .filter(|e| {
                score_effect(model, e.clone(), prep, baseline)
                    .is_none_or(|r| could_be_significant(&baseline.comparison, r, cfg, k))
            })
            .collect()
    };
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
            Trying::Effect(e) => try_effect(model, e, &[], prep, baseline, cfg, k).ok(),
            Trying::Aircraft(key) => try_aircraft(model, &[key], prep, baseline, cfg, k).ok(),
        })
        .collect();
    rank(&mut ranking);
    (ranking, scores, k)
}

/// The aircraft numbers a joint fit's members change.
fn taken_keys(joint: Option<&JointFit>) -> Vec<&'static str> {
    joint
        .map(|j| {
            j.members
                .iter()
                .flat_map(|m| match &m.trial {
                    Trial::Aircraft(keys) => keys.clone(),
                    Trial::Effect(_) => Vec::new(),
                })
                .collect()
        })
        .unwrap_or_default()
}

/// Forward selection with backward elimination, on `prep`: screen every candidate on top of
/// the causes kept so far; add the best significant one and refit all of them jointly; drop,
/// one at a time, any earlier cause whose removal the data no longer reject (the
/// likelihood-ratio test of the joint fit without it, refitted); repeat until no candidate
/// is significant. A cause dropped once is not added again.
fn select(
    base: &Model,
    prep: &Prepared,
    extra: &[Box<dyn Effect>],
    cfg: &DiagnoseConfig,
) -> Result<Selection, DiagnoseError> {
    let mut model = base.clone();
    let mut baseline = Baseline::of(base, prep);
    let before = baseline.comparison.clone();
    let mut joint: Option<JointFit> = None;
    let mut steps: Vec<Step> = Vec::new();
    let mut first: Option<(Vec<KeyScore>, usize)> = None;
    let mut ever_dropped: Vec<String> = Vec::new();
    // Each round adds one cause and drops at most as many as were added: bounded by twice
    // the causes allowed.
    for _ in 0..=2 * cfg.max_causes {
        let taken = taken_keys(joint.as_ref());
        let rescreen = joint.is_some();
        let (mut ranking, scores, k) =
            screen_round(&model, prep, &baseline, extra, (&taken, rescreen), cfg);
        let k_first = first.get_or_insert((scores, k)).1;
        let effects: Vec<String> = joint
            .as_ref()
            .map(|j| j.members.iter().map(Member::label).collect())
            .unwrap_or_default();
        let room = effects.len() < cfg.max_causes;
        // With causes kept, the most promising candidates — those the test finds real, fitted
        // alone — are fitted together with them and judged so: a cause found first takes up
        // part of a later one's misfit (an actuator lag fitted 0.22 s where 0.15 s and a
        // weaker weathercock stability were the truth), which only a joint fit gives back.
        let mut joint_trials: Vec<(String, JointFit)> = Vec::new();
        if let Some(j) = joint.as_ref().filter(|_| room) {
            let tries: Vec<Candidate> = ranking
                .iter()
                .filter(|c| c.lr_statistic > c.lr_critical && !c.any_at_limit())
                .filter(|c| !ever_dropped.contains(&c.effect))
                .take(JOINT_TRIES)
                .cloned()
                .collect();
            let fits: Vec<(Candidate, JointFit)> = tries
                .into_par_iter()
                .filter_map(|c| {
                    let mut m = model.clone();
                    c.correction.apply(&mut m).ok()?;
                    let mut members = j.members.clone();
                    members.push(Member::of(&c));
                    let jf = fit_joint(m, members, prep, &baseline, cfg.max_iterations).ok()?;
                    let mut rec = jf.records(&model, &baseline.comparison, cfg, k).pop()?;
                    rec.joint = true;
                    Some((rec, jf))
                })
                .collect();
            for (rec, jf) in fits {
                if let Some(slot) = ranking.iter_mut().find(|c| c.effect == rec.effect) {
                    joint_trials.push((rec.effect.clone(), jf));
                    *slot = rec;
                }
            }
            rank(&mut ranking);
        }
        let best = ranking
            .iter()
            .find(|c| c.significant && !ever_dropped.contains(&c.effect))
            .filter(|_| room)
            .cloned();
        let mut step = Step {
            effects,
            error: baseline.comparison.total,
            noise_units: baseline.comparison.noise_units(),
            ranking,
            added: None,
            dropped: Vec::new(),
            alternatives: Vec::new(),
            fitted: Vec::new(),
            error_after: baseline.comparison.total,
            noise_units_after: baseline.comparison.noise_units(),
        };
        let Some(best) = best else {
            step.fitted = joint
                .as_ref()
                .map(|j| j.records(base, &before, cfg, k_first))
                .unwrap_or_default();
            steps.push(step);
            break;
        };
        // The first cause's joint fit is its own fit alone: not repeated.
        let alone = joint
            .is_none()
            .then(|| JointFit::from_candidate(&model, &best, prep))
            .flatten();
        let tried = joint_trials
            .into_iter()
            .find(|(name, _)| *name == best.effect);
        let mut fitted = match (tried, alone) {
            (Some((_, jf)), _) | (None, Some(jf)) => jf,
            (None, None) => {
                let mut trial_model = model.clone();
                best.correction.apply(&mut trial_model)?;
                let mut members: Vec<Member> = joint
                    .as_ref()
                    .map(|j| j.members.clone())
                    .unwrap_or_default();
                members.push(Member::of(&best));
                fit_joint(trial_model, members, prep, &baseline, cfg.max_iterations)?
            }
        };
        // The newest member's test is against the previous joint fit, already optimal
        // without it; the others' need a refit each.
        let mut known = vec![(
            fitted.members.len() - 1,
            fitted.lr_against(&baseline.comparison),
        )];
        loop {
            let without = fitted.test_members(&known, base, prep, cfg.max_iterations)?;
            known.clear();
            let weakest = without
                .into_iter()
                .map(|(i, fit)| {
                    let crit = lr_critical(cfg, k_first, fitted.spans[i].len());
                    (fitted.lr[i] / crit, i, fit)
                })
                // A statistic that is not a number cannot keep a cause either.
                .filter(|(ratio, _, _)| ratio.is_nan() || *ratio <= 1.0)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((_, i, fit)) = weakest else { break };
            let label = fitted.members[i].label();
            step.dropped.push(label.clone());
            ever_dropped.push(label);
            fitted = fit;
            if fitted.members.len() < 2 {
                // One member left: its test is against the model as given.
                known = vec![(0, fitted.lr_against(&before))];
                let _ = fitted.test_members(&known, base, prep, cfg.max_iterations)?;
                break;
            }
        }
        step.alternatives = alternatives(&step.ranking, &best.effect);
        step.added = Some(best.effect.clone());
        step.fitted = fitted.records(base, &before, cfg, k_first);
        step.error_after = fitted.comparison.total;
        step.noise_units_after = fitted.comparison.noise_units();
        steps.push(step);
        model = fitted.model.clone();
        baseline = Baseline::of(&model, prep);
        joint = Some(fitted);
    }
    let (scores, candidates) = first.unwrap_or_default();
    Ok(Selection {
        before,
        steps,
        joint,
        scores,
        candidates,
    })
}

/// What the selection found: its steps, the last joint fit, and the first step's aircraft
/// scores and candidate count (the significance level's family).
struct Selection {
    /// The model as given, compared on the selection's windows.
    before: Comparison,
    steps: Vec<Step>,
    joint: Option<JointFit>,
    scores: Vec<KeyScore>,
    candidates: usize,
}

/// Diagnose: try every catalogue effect that applies to the vehicle and is not in the model
/// yet, plus `extra` user effects, and every promising number of the aircraft's set; keep
/// the significant ones by forward selection with backward elimination, fitted jointly;
/// decide (module docs).
///
/// # Errors
/// A flight too short for one comparison window; a correction the model refuses.
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
    let Selection {
        before,
        steps,
        joint,
        scores,
        candidates: k,
    } = select(base, prep, extra, cfg)?;
    let (base_cmp, joint) = if screened {
        // The causes found on the subset, on every window.
        full_pass(base, joint.as_ref(), &full)
    } else {
        // The selection ran on every window: its comparison of the model as given is this.
        (before, joint)
    };
    let noise_units = base_cmp.noise_units();
    let found = joint
        .as_ref()
        .map(|j| j.records(base, &base_cmp, cfg, k))
        .unwrap_or_default();
    let (found_error, found_noise_units) =
        joint.as_ref().map_or((base_cmp.total, noise_units), |j| {
            (j.comparison.total, j.comparison.noise_units())
        });
    let verdict = if found.is_empty() {
        if noise_units <= cfg.at_floor {
            Verdict::None
        } else {
            Verdict::Unexplained
        }
    } else if found_noise_units <= cfg.at_floor {
        Verdict::Found(found.iter().map(|c| c.effect.clone()).collect())
    } else {
        Verdict::Unexplained
    };
    let ranking = steps.first().map(|s| s.ranking.clone()).unwrap_or_default();
    let alternatives = match found.as_slice() {
        [only] if matches!(verdict, Verdict::Found(_)) => alternatives(&ranking, &only.effect),
        _ => Vec::new(),
    };
    let evidence = if verdict == Verdict::Unexplained {
        evidence(&base_cmp, &full, &scores)
    } else {
        Vec::new()
    };
    Ok(Diagnosis {
        turbulence: None,
        base_error: base_cmp.total,
        noise_floor: noise_floor(base, &full),
        noise_units,
        verdict,
        ranking,
        found,
        found_error,
        found_noise_units,
        steps,
        candidates: k,
        windows: (full.windows.len(), prep.windows.len()),
        base_noise: full.noise,
        base: base_cmp,
        aircraft_scores: scores,
        evidence,
        alternatives,
        reference: None,
        error_floor: None,
    })
}

/// The significant, whole candidates other than the one found that leave as little misfit.
fn alternatives(ranking: &[Candidate], name: &str) -> Vec<String> {
    let Some(best) = ranking.iter().find(|c| c.effect == name) else {
        return Vec::new();
    };
    let limit = best.noise_units_after * (1.0 + EQUIVALENT);
    ranking
        .iter()
        .filter(|c| c.effect != name && c.significant && c.partial == best.partial)
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

/// How many of the candidates the test finds real, fitted alone, are fitted together with
/// the causes kept so far.
const JOINT_TRIES: usize = 4;

/// Where the error of a comparison is, and which terms of the model would reduce it most.
fn evidence(cmp: &Comparison, prep: &Prepared, scores: &[KeyScore]) -> Vec<String> {
    let n = &prep.noise;
    let sigma = |channel: &str, axis: &str| -> Option<f64> {
        let k = match axis {
            "north" | "roll" | "p" | "x" => 0,
            "east" | "pitch" | "q" | "y" => 1,
            "down" | "yaw" | "r" | "z" => 2,
            _ => return (channel == "air" && axis == "airspeed").then_some(n.airspeed_mps),
        };
        match channel {
            "position" => Some(n.pos_axes[k]),
            "velocity" => Some(n.vel_axes[k]),
            "attitude" => Some(n.att_axes[k].to_degrees()),
            "rates" => Some(n.rate_axes[k].to_degrees()),
            "accel" => Some(n.accel_axes[k]),
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
                    wireflight_data::format::fixed(a.rms, 3),
                    a.unit,
                    wireflight_data::format::fixed(*ratio, 1)
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
                wireflight_data::format::fixed(100.0 * (s.reduction / excess).min(1.0), 0)
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
