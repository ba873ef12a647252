//! Turbulence: what is left when it is random.
//!
//! Output error calls everything the model cannot follow a residual, gusts included: in
//! turbulence no deterministic cause brings the error to the noise, and the causes it does
//! fit are pulled by the gusts' response. Where a diagnosis ends unexplained, the
//! filter-error method ([`crate::filter_error::flight`]) is tried on the model with the
//! causes kept: the gust intensities that maximise the likelihood, and the likelihood-ratio
//! test against calm air. Where the gusts are significant, the verdict is `turbulence`
//! (with the causes kept, if any), the intensities are reported with their ±, and every
//! number of the causes kept is fitted again through the filter, so that it no longer
//! carries the gusts' bias — the gusts and the numbers in turn until neither moves the other
//! (`settle`). A steady wind, a sensor bias or a wrong number stay what they are:
//! they are causes output error finds and keeps, and the filter refits them.
//!
//! In turbulence output error may keep nothing: the gusts' response hides a wrong number from
//! its tests. The filter then searches the aircraft's numbers itself: each scored by how much
//! one Gauss–Newton step on it would raise the filter's likelihood, the best [`SEARCHED`]
//! fitted, and the best of those kept when its likelihood ratio — deflated by the square of
//! the innovations' spread over the filter's own account of it, so that a model that is not
//! exact does not make every number significant — beats the χ² bound at the family-wise
//! level shared over every number (Bonferroni). Up to [`MOST_CAUSES`] numbers are added this
//! way. After each, every number kept is fitted again through the filter together with the
//! new one, and the aircraft number whose likelihood ratio given the others (deflated alike)
//! is weakest goes back to the set's value while it no longer beats that bound — output
//! error's causes included, as output error chose them with the gusts' response in its
//! residuals; then the gusts are estimated again, and the two in turn until settled. (On a
//! c172p flight in light turbulence with the pitch stiffness changed, a search that held what
//! it had kept named the mass beside the pitch stiffness; fitted together, the pitch
//! stiffness explains it and the mass goes.)
//!
//! Against reference flights the search stays off. On JSBSim's c172p in its own light
//! turbulence the filter moves numbers on an *unchanged* flight as well as on a changed one,
//! where calm reference flights cannot show it: above all the force numbers (each fitted
//! alone: the span, wing area, Oswald factor, parasitic drag, propeller and lift slope by
//! 6 to 82 %, likelihood ratios of 1 400 to 3 150; `docs/turbulence.md` has the table), and
//! the roll damping (−35 to −37 %). The same
//! numbers move the same way in every window of the flight, so a test against the scatter
//! between windows does not tell them from a changed number; and once the strongest of them
//! is fitted, the changed pitch stiffness's own signal is gone. The way JSBSim's gusts act on
//! its aircraft is not the filter's; naming those would name the wrong cause, so the verdict
//! is turbulence with the causes output error kept, refitted.

use super::{Candidate, Correction, DiagnoseConfig, Diagnosis, Verdict};
use crate::compare::{estimate_noise, CompareConfig, NoiseEstimate, Prepared};
use crate::filter_error::flight::{
    FilterError, FilterFit, FlightFilter, GustEstimate, GustModel, SETTLED_SIGMAS, SETTLE_ROUNDS,
};
use wireflight_data::FlightData;
use wireflight_flight::model::Model;
use wireflight_flight::numeric::chi2_quantile;
use wireflight_flight::params::keys::KEYS;

/// Aircraft numbers the filter fits in its own search, the best-scored first.
pub const SEARCHED: usize = 6;
/// Numbers the filter's own search adds at most.
pub const MOST_CAUSES: usize = 2;

/// How model and measurements are compared (defined beside the filter, which `identify`
/// uses too).
pub use crate::filter_error::flight::MethodChoice as Method;

/// One number of a cause, fitted by output error and again through the filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Refit {
    /// The cause (`aircraft:c_ell_p`, `wind`, …).
    pub cause: String,
    /// The number (`c_ell_p`, `north_mps`, …).
    pub param: String,
    /// Output error's value.
    pub output_error: f64,
    /// The filter-error method's value.
    pub value: f64,
    /// Its 1σ (scaled up by the innovations' spread where it exceeds the filter's account).
    pub sigma: f64,
    /// Found by the filter's own search, not by output error (its `output_error` is NaN).
    pub added: bool,
}

/// Turbulence found in a flight.
#[derive(Clone, Debug, PartialEq)]
pub struct TurbulenceFinding {
    /// The gusts estimated on the model with the causes kept (refitted).
    pub gusts: GustEstimate,
    /// The causes' numbers refitted through the filter.
    pub refits: Vec<Refit>,
    /// Whether the filter was forced (`--method filter-error`) rather than chosen.
    pub forced: bool,
    /// Against reference flights: the largest gust σ the filter finds on them (north, east,
    /// down, m/s) and its ±, the floor a model that is not exact puts under the estimate.
    pub reference_sigma_mps: Option<([f64; 3], [f64; 3])>,
    /// Whether the filter's own search for a wrong number of the aircraft ran. It does not
    /// in `compare`, nor against reference flights (module docs), so "no cause besides the
    /// gusts" is a finding only where it did.
    pub aircraft_searched: bool,
}

impl TurbulenceFinding {
    /// Whether the gusts are significant: by the likelihood ratio against calm air, and,
    /// against reference flights, above what the filter finds on them on some axis by more
    /// than twice the two ± together.
    pub fn significant(&self) -> bool {
        significant_beyond(&self.gusts, self.reference_sigma_mps.as_ref())
    }
}

/// [`TurbulenceFinding::significant`] of gusts `g` with the references' floor `floor`.
fn significant_beyond(g: &GustEstimate, floor: Option<&([f64; 3], [f64; 3])>) -> bool {
    let beyond = match floor {
        None => true,
        Some((floor, floor_se)) => (0..3).any(|k| {
            let se = g.sigma_se_mps[k].hypot(floor_se[k]);
            g.sigma_mps[k] - floor[k] > 2.0 * se
        }),
    };
    g.significant() && beyond
}

/// The gusts the filter finds on calm reference flights, axis by axis the largest (with its
/// ±): what a model that is not exact leaves that looks like gusts.
fn reference_floor(
    base: &Model,
    references: &[(&str, &FlightData)],
    compare: &CompareConfig,
    model_error: &NoiseEstimate,
) -> ([f64; 3], [f64; 3]) {
    let mut floor = ([0.0; 3], [0.0; 3]);
    // The filter adds the model error to each reference's measured noise itself.
    let compare = CompareConfig {
        model_error: Some(*model_error),
        ..*compare
    };
    for (_, r) in references {
        let Ok(f) = FlightFilter::new(base, r, &estimate_noise(r), &compare) else {
            continue;
        };
        let g = f.estimate_gusts(base);
        for k in 0..3 {
            if g.sigma_mps[k] > floor.0[k] {
                floor.0[k] = g.sigma_mps[k];
                floor.1[k] = if g.sigma_se_mps[k].is_finite() {
                    g.sigma_se_mps[k]
                } else {
                    0.0
                };
            }
        }
    }
    floor
}

/// How one refitted number is put into a model.
#[derive(Clone)]
enum Slot {
    Aircraft(&'static str),
    Effect(String, String),
}

fn set_slots(model: &mut Model, slots: &[Slot], theta: &[f64]) {
    for (s, v) in slots.iter().zip(theta) {
        match s {
            Slot::Aircraft(key) => {
                let _ = model.set_aircraft(key, *v);
            }
            Slot::Effect(effect, param) => {
                if let Some(e) = model.effect_mut(effect) {
                    let _ = e.set_param(param, *v);
                }
            }
        }
    }
}

/// The fitted numbers of `causes` (output error's), fitted again through `filter` with
/// `gusts`, jointly; `model` (which has the causes) and the causes take the filter's values.
/// Returns each number's two values; empty where the causes fit nothing.
fn refit_causes(
    filter: &FlightFilter,
    model: &mut Model,
    causes: &mut [Candidate],
    gusts: &GustModel,
) -> Vec<Refit> {
    let mut slots = Vec::new();
    let mut refits = Vec::new();
    let refit = |c: &Candidate, param: String, value: f64| Refit {
        cause: c.effect.clone(),
        param,
        output_error: value,
        value,
        sigma: f64::NAN,
        added: false,
    };
    for c in causes.iter() {
        match &c.correction {
            Correction::Aircraft(changes) => {
                for ch in changes {
                    slots.push(Slot::Aircraft(ch.key));
                    refits.push(refit(c, ch.key.to_string(), ch.value));
                }
            }
            Correction::Effect(_) => {
                for ((name, value), held) in c.params.iter().zip(&c.held) {
                    if !held {
                        slots.push(Slot::Effect(c.effect.clone(), name.clone()));
                        refits.push(refit(c, name.clone(), *value));
                    }
                }
            }
        }
    }
    if slots.is_empty() {
        return refits;
    }
    fit_refits(filter, model, &slots, &mut refits, gusts);
    // The causes carry the filter's values from here on (the verdict, `--out`).
    update_found(causes, model);
    refits
}

/// The numbers of `refits` (put into the model by `slots`) fitted together through `filter`
/// with `gusts`, from their values; `model` and `refits` take the fit's values, each σ
/// scaled up by the innovations' spread where it exceeds the filter's account.
fn fit_refits(
    filter: &FlightFilter,
    model: &mut Model,
    slots: &[Slot],
    refits: &mut [Refit],
    gusts: &GustModel,
) -> FilterFit {
    let theta0: Vec<f64> = refits.iter().map(|r| r.value).collect();
    let scales: Vec<f64> = theta0.iter().map(|v| v.abs().max(0.01)).collect();
    let set = |m: &mut Model, theta: &[f64]| set_slots(m, slots, theta);
    let fit = filter.fit(model, &set, &theta0, &scales, gusts);
    set_slots(model, slots, &fit.theta);
    let spread = fit.pass.normalised.max(1.0);
    for ((r, v), s) in refits.iter_mut().zip(&fit.theta).zip(&fit.sigma) {
        r.value = *v;
        r.sigma = *s * spread;
    }
    fit
}

/// The filter on the model as given with the causes kept, where it runs: the gusts, and the
/// causes' numbers refitted through it (the two settled, [`settle`]).
struct FilterRun<'d> {
    /// `base` with the causes, their numbers the filter's.
    model: Model,
    filter: FlightFilter<'d>,
    gusts: GustEstimate,
    refits: Vec<Refit>,
    /// The references' floor ([`reference_floor`]), against reference flights.
    reference_sigma_mps: Option<([f64; 3], [f64; 3])>,
}

impl<'d> FilterRun<'d> {
    /// Run the filter on `base` with `causes` (whose values become the filter's) over
    /// `data`, its noise `noise` and `compare`'s windows; `floor`: the reference flights and
    /// the model error they measured. None where the filter cannot run and is not `forced`,
    /// or where the gusts are not significant and it is not `forced`.
    fn start(
        base: &Model,
        causes: &mut [Candidate],
        data: &'d FlightData,
        noise: &NoiseEstimate,
        compare: &CompareConfig,
        floor: Option<(&[(&str, &FlightData)], &NoiseEstimate)>,
        forced: bool,
    ) -> Result<Option<Self>, FilterError> {
        let mut model = base.clone();
        for c in causes.iter() {
            let _ = c.correction.apply(&mut model);
        }
        let filter = match FlightFilter::new(&model, data, noise, compare) {
            Ok(f) => f,
            Err(e) if forced => return Err(e),
            Err(_) => return Ok(None),
        };
        let mut gusts = filter.estimate_gusts(&model);
        let reference_sigma_mps = floor
            .filter(|(references, _)| !references.is_empty())
            .map(|(references, error)| reference_floor(base, references, compare, error));
        if !forced && !significant_beyond(&gusts, reference_sigma_mps.as_ref()) {
            return Ok(None);
        }
        let mut refits = refit_causes(&filter, &mut model, causes, &gusts.model());
        if !refits.is_empty() {
            // The gusts again on the refitted model (the causes no longer hide part of them),
            // and the causes again with those gusts, until neither moves the other.
            settle(
                &filter,
                &mut model,
                &mut gusts,
                &mut refits,
                |m, refits, g| {
                    let slots: Vec<Slot> = refits.iter().map(slot_of).collect();
                    fit_refits(&filter, m, &slots, refits, g);
                    update_found(causes, m);
                },
            );
        }
        Ok(Some(Self {
            model,
            filter,
            gusts,
            refits,
            reference_sigma_mps,
        }))
    }
}

/// `compare` through the filter-error method: with `Method::Auto` only where a diagnosis of
/// the model as compared leaves the flight unexplained (`unexplained`: the caller's, as it
/// has the diagnosis's options), and reported only where the gusts are significant (against
/// reference flights, above their floor); with `Method::FilterError` always. `base` is the
/// model as given; `added` the effects `--add` fitted by output error, fitted again here
/// through the filter (their values become the filter's). Returns the finding and the model
/// with the refitted effects, or None.
///
/// A comparison searches no cause, and where a deterministic one is missing the filter may
/// take its response for gusts (a steady wind for a slow gust): hence the diagnosis first.
///
/// # Errors
/// Only when the filter is forced and cannot run (a point mass, a channel missing).
pub fn compare_through_turbulence(
    base: &Model,
    added: &mut [Candidate],
    prep: &Prepared,
    references: &[(&str, &FlightData)],
    method: Method,
    unexplained: bool,
) -> Result<Option<(TurbulenceFinding, Model)>, FilterError> {
    let forced = method == Method::FilterError;
    if method == Method::OutputError || (!forced && !unexplained) {
        return Ok(None);
    }
    // The filter adds the references' model error to the measured noise itself.
    let compare = prep.config();
    let floor = compare.model_error.as_ref().map(|e| (references, e));
    let Some(run) = FilterRun::start(
        base,
        added,
        prep.data,
        &prep.measured_noise,
        &compare,
        floor,
        forced,
    )?
    else {
        return Ok(None);
    };
    let finding = TurbulenceFinding {
        gusts: run.gusts,
        refits: run.refits,
        forced,
        reference_sigma_mps: run.reference_sigma_mps,
        aircraft_searched: false,
    };
    Ok(Some((finding, run.model)))
}

/// Try the filter-error method on a diagnosis (module docs): with `Method::Auto` only where
/// the verdict is unexplained, and the verdict changes only where the gusts are significant;
/// with `Method::FilterError` always. `base` is the model as given.
///
/// # Errors
/// Only when the filter is forced and cannot run (a point mass, a channel missing).
pub(crate) fn through_turbulence(
    base: &Model,
    d: &mut Diagnosis,
    data: &FlightData,
    references: &[(&str, &FlightData)],
    cfg: &DiagnoseConfig,
    compare: &CompareConfig,
    method: Method,
) -> Result<(), FilterError> {
    let forced = method == Method::FilterError;
    if method == Method::OutputError || (!forced && d.verdict != Verdict::Unexplained) {
        return Ok(());
    }
    let floor = d
        .reference
        .as_ref()
        .map(|r| (references, &r.floor.model_error));
    let Some(run) = FilterRun::start(
        base,
        &mut d.found,
        data,
        &d.base_noise,
        compare,
        floor,
        forced,
    )?
    else {
        return Ok(());
    };
    let FilterRun {
        mut model,
        filter,
        mut gusts,
        mut refits,
        reference_sigma_mps,
    } = run;
    // Against reference flights the search stays off: the filter's values on a turbulent
    // flight and on calm ones differ by more than a changed number where the gust model and
    // the aircraft's response to gusts are not exact (module docs).
    // With stated wandering errors too: the filter weighs them as white noise of their size,
    // so its likelihood overstates what a number explains (on a calm-numbered flight in
    // light turbulence with `ekf-gnss` errors it added the propeller disc and c_y_r).
    let aircraft_searched = gusts.significant() && references.is_empty() && d.error_floor.is_none();
    if aircraft_searched {
        let mut taken: Vec<String> = refits.iter().map(|r| r.param.clone()).collect();
        for _ in 0..MOST_CAUSES {
            let Some(r) = search_number(&filter, &model, &gusts, &taken, cfg) else {
                break;
            };
            let key = KEYS.iter().find(|k| k.name == r.param).map(|k| k.name);
            if let Some(key) = key {
                let _ = model.set_aircraft(key, r.value);
            }
            taken.push(r.param.clone());
            refits.push(r);
            // The causes kept together are fitted together, and a number the others now
            // explain is dropped (an output-error cause included: it was chosen without them).
            let critical = chi2_quantile(1.0 - cfg.alpha / KEYS.len().max(1) as f64, 1.0);
            let found = &mut d.found;
            let mut refit = |m: &mut Model, refits: &mut Vec<Refit>, g: &GustModel| {
                for gone in refit_jointly(&filter, m, base, refits, g, critical) {
                    found.retain(|c| c.effect != gone);
                }
                update_found(found, m);
            };
            refit(&mut model, &mut refits, &gusts.model());
            settle(&filter, &mut model, &mut gusts, &mut refits, refit);
        }
    }
    let finding = TurbulenceFinding {
        gusts,
        refits,
        forced,
        reference_sigma_mps,
        aircraft_searched,
    };
    if finding.significant() {
        let mut names: Vec<String> = d.found.iter().map(|c| c.effect.clone()).collect();
        names.extend(
            finding
                .refits
                .iter()
                .filter(|r| r.added)
                .map(|r| r.cause.clone()),
        );
        d.verdict = Verdict::Turbulence(names);
        // Where output error's error lies, and which numbers would reduce it, describe the
        // gusts' response: no longer evidence of a missing cause.
        d.evidence.clear();
    }
    d.turbulence = Some(finding);
    Ok(())
}

/// The filter's own search for a wrong number of the aircraft (module docs): the best one
/// that is significant, fitted; None when none is.
fn search_number(
    filter: &FlightFilter,
    model: &Model,
    gusts: &GustEstimate,
    taken: &[String],
    cfg: &DiagnoseConfig,
) -> Option<Refit> {
    let g = gusts.model();
    let (at, white) = filter.whitened(model, &g);
    let spread2 = at.normalised.max(1.0).powi(2);
    let mut scored: Vec<(f64, &'static str, f64)> = KEYS
        .iter()
        .filter(|k| !taken.iter().any(|t| t == k.name))
        .filter_map(|k| {
            let v = model.aircraft(k.name)?;
            let scale = (0.1 * v.abs()).max(1e-3);
            let set = |m: &mut Model, x: f64| {
                let _ = m.set_aircraft(k.name, x);
            };
            Some((filter.score(model, &set, v, scale, &g, &white), k.name, v))
        })
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    let critical = chi2_quantile(1.0 - cfg.alpha / KEYS.len().max(1) as f64, 1.0);
    let mut best: Option<(f64, Refit)> = None;
    for &(_, key, v) in scored.iter().take(SEARCHED) {
        let set = |m: &mut Model, x: &[f64]| {
            let _ = m.set_aircraft(key, x[0]);
        };
        let scale = (0.1 * v.abs()).max(1e-3);
        let fit = filter.fit(model, &set, &[v], &[scale], &g);
        let lr = 2.0 * (at.neg_log_likelihood - fit.pass.neg_log_likelihood) / spread2;
        // (A NaN ratio is no evidence either.)
        if lr.is_nan() || lr <= critical {
            continue;
        }
        let sigma = fit.sigma[0] * fit.pass.normalised.max(1.0);
        let refit = Refit {
            cause: format!("aircraft:{key}"),
            param: key.to_string(),
            output_error: f64::NAN,
            value: fit.theta[0],
            sigma,
            added: true,
        };
        if best.as_ref().is_none_or(|(b, _)| lr > *b) {
            best = Some((lr, refit));
        }
    }
    best.map(|(_, r)| r)
}

/// The gusts estimated again on `model`, whose numbers `refits` were just fitted with the
/// gusts `gusts` held, and the numbers fitted again by `refit` with the new gusts held, in
/// turn until a fit moves no number by more than [`SETTLED_SIGMAS`] of its σ (at most
/// [`SETTLE_ROUNDS`] rounds): the likelihood's joint maximum over both. One round of each
/// stops short of it where the gusts were first estimated on numbers that were not yet the
/// filter's. (On a c172p flight in light turbulence, 2.2 m/s, with the pitch stiffness
/// changed to −1.6592, the gusts estimated on the set's value took a pitching disturbance of
/// 0.02 rad/s² the air did not have, and the pitch stiffness fitted with it was −1.6787 ±
/// 0.0078; settled, −1.6585 ± 0.0011, and the disturbance none.)
fn settle(
    filter: &FlightFilter,
    model: &mut Model,
    gusts: &mut GustEstimate,
    refits: &mut Vec<Refit>,
    mut refit: impl FnMut(&mut Model, &mut Vec<Refit>, &GustModel),
) {
    for _ in 0..SETTLE_ROUNDS {
        *gusts = filter.estimate_gusts(model);
        let before = refits.clone();
        refit(model, refits, &gusts.model());
        // (A number without a finite σ cannot be judged by it and does not hold the rest.)
        let settled = refits.len() == before.len()
            && refits.iter().zip(&before).all(|(r, was)| {
                (&r.cause, &r.param) == (&was.cause, &was.param)
                    && ((r.value - was.value).abs() <= SETTLED_SIGMAS * r.sigma
                        || !r.sigma.is_finite())
            });
        if settled {
            return;
        }
    }
    *gusts = filter.estimate_gusts(model);
}

/// How a refitted number is put into a model: an aircraft number of an aircraft cause (one
/// key or several), else an effect's parameter.
fn slot_of(r: &Refit) -> Slot {
    let key = r
        .cause
        .starts_with("aircraft:")
        .then(|| KEYS.iter().find(|k| k.name == r.param))
        .flatten();
    match key {
        Some(k) => Slot::Aircraft(k.name),
        None => Slot::Effect(r.cause.clone(), r.param.clone()),
    }
}

/// The aircraft key a refitted number is, where it is a cause of its own (`aircraft:KEY`, the
/// number `KEY`): the numbers that may be dropped alone.
fn aircraft_key(r: &Refit) -> Option<&'static str> {
    let key = r
        .cause
        .strip_prefix("aircraft:")
        .filter(|k| *k == r.param)?;
    KEYS.iter().find(|k| k.name == key).map(|k| k.name)
}

/// Every number of `refits` fitted through `filter` together, on `model` (which has them and
/// takes the joint values); then, while the weakest aircraft number's likelihood ratio given
/// the others — deflated like the search's — is at most `critical`, it goes back to `base`'s
/// value and leaves `refits`, the rest fitted again. Returns the causes dropped.
fn refit_jointly(
    filter: &FlightFilter,
    model: &mut Model,
    base: &Model,
    refits: &mut Vec<Refit>,
    gusts: &GustModel,
    critical: f64,
) -> Vec<String> {
    let mut dropped = Vec::new();
    // Each round fits the numbers left, so the rounds are bounded by the numbers.
    for _ in 0..=refits.len() {
        let slots: Vec<Slot> = refits.iter().map(slot_of).collect();
        let all = fit_refits(filter, model, &slots, refits, gusts);
        let spread = all.pass.normalised.max(1.0);
        // A joint fit that failed is no evidence against any number: keep them all.
        if refits.len() < 2 || !all.pass.neg_log_likelihood.is_finite() {
            break;
        }
        // The weakest aircraft number given the others: each back at the set's value, the
        // others fitted again without it.
        let mut weakest: Option<(f64, usize, Model, Vec<f64>)> = None;
        for (j, r) in refits.iter().enumerate() {
            let Some(key) = aircraft_key(r) else {
                continue;
            };
            let Some(was) = base.aircraft(key) else {
                continue;
            };
            let mut without = model.clone();
            let _ = without.set_aircraft(key, was);
            let others: Vec<Slot> = slots
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != j)
                .map(|(_, s)| s.clone())
                .collect();
            let theta: Vec<f64> = (0..refits.len())
                .filter(|i| *i != j)
                .map(|i| all.theta[i])
                .collect();
            let scales: Vec<f64> = theta.iter().map(|v| v.abs().max(0.01)).collect();
            let set = |m: &mut Model, x: &[f64]| set_slots(m, &others, x);
            let fit = filter.fit(&without, &set, &theta, &scales, gusts);
            let lr = 2.0 * (fit.pass.neg_log_likelihood - all.pass.neg_log_likelihood)
                / (spread * spread);
            // A fit without the number that failed says nothing for dropping it.
            if lr.is_nan() {
                continue;
            }
            if weakest.as_ref().is_none_or(|(w, ..)| lr < *w) {
                set_slots(&mut without, &others, &fit.theta);
                weakest = Some((lr, j, without, fit.theta));
            }
        }
        match weakest {
            Some((lr, j, without, theta)) if lr <= critical => {
                *model = without;
                let gone = refits.remove(j);
                for (r, v) in refits.iter_mut().zip(theta) {
                    r.value = v;
                }
                dropped.push(gone.cause);
            }
            _ => break,
        }
    }
    dropped
}

/// The causes' numbers as `model` has them (after a fit through the filter).
fn update_found(found: &mut [Candidate], model: &mut Model) {
    for c in found.iter_mut() {
        match &mut c.correction {
            Correction::Aircraft(changes) => {
                for ch in changes.iter_mut() {
                    ch.value = model.aircraft(ch.key).unwrap_or(ch.value);
                }
            }
            Correction::Effect(e) => {
                for (name, value) in c.params.iter_mut() {
                    if let Some(v) = model.effect_mut(&c.effect).and_then(|m| m.param(name)) {
                        *value = v;
                        let _ = e.set_param(name, v);
                    }
                }
            }
        }
    }
}
