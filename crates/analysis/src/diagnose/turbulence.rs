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
//! carries the gusts' bias. A steady wind, a sensor bias or a wrong number stay what they are:
//! they are causes output error finds and keeps, and the filter refits them.

use super::{Correction, DiagnoseConfig, Diagnosis, Verdict};
use crate::compare::CompareConfig;
use crate::filter_error::flight::{FilterError, FlightFilter, GustEstimate};
use wireflight_flight::data::FlightData;
use wireflight_flight::model::Model;

/// How model and measurements are compared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Output error, and the filter-error method where output error leaves the error
    /// unexplained and the gusts are significant.
    #[default]
    Auto,
    /// Output error alone (calm air assumed).
    OutputError,
    /// The filter-error method, whatever the test says.
    FilterError,
}

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
    /// Its 1σ.
    pub sigma: f64,
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
}

impl TurbulenceFinding {
    /// Whether the gusts are significant.
    pub fn significant(&self) -> bool {
        self.gusts.significant()
    }
}

/// How one refitted number is put into a model.
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

/// Try the filter-error method on a diagnosis (module docs): with `Method::Auto` only where
/// the verdict is unexplained, and the verdict changes only where the gusts are significant;
/// with `Method::FilterError` always. `base` is the model as given.
///
/// # Errors
/// Only when the filter is forced and cannot run (a point mass, a channel missing).
pub fn through_turbulence(
    base: &Model,
    d: &mut Diagnosis,
    data: &FlightData,
    cfg: &DiagnoseConfig,
    compare: &CompareConfig,
    method: Method,
) -> Result<(), FilterError> {
    let forced = method == Method::FilterError;
    if method == Method::OutputError || (!forced && d.verdict != Verdict::Unexplained) {
        return Ok(());
    }
    let _ = cfg;
    let mut model = base.clone();
    for c in &d.found {
        let _ = c.correction.apply(&mut model);
    }
    let filter = match FlightFilter::new(&model, data, &d.base_noise, compare) {
        Ok(f) => f,
        Err(e) if forced => return Err(e),
        Err(_) => return Ok(()),
    };
    let mut gusts = filter.estimate_gusts(&model);
    if !forced && !gusts.significant() {
        return Ok(());
    }
    // The causes' fitted numbers, refitted through the filter with these gusts.
    let mut slots = Vec::new();
    let mut refits = Vec::new();
    for c in &d.found {
        match &c.correction {
            Correction::Aircraft(changes) => {
                for ch in changes {
                    slots.push(Slot::Aircraft(ch.key));
                    refits.push(Refit {
                        cause: c.effect.clone(),
                        param: ch.key.to_string(),
                        output_error: ch.value,
                        value: ch.value,
                        sigma: f64::NAN,
                    });
                }
            }
            Correction::Effect(_) => {
                for ((name, value), held) in c.params.iter().zip(&c.held) {
                    if !held {
                        slots.push(Slot::Effect(c.effect.clone(), name.clone()));
                        refits.push(Refit {
                            cause: c.effect.clone(),
                            param: name.clone(),
                            output_error: *value,
                            value: *value,
                            sigma: f64::NAN,
                        });
                    }
                }
            }
        }
    }
    if !slots.is_empty() {
        let theta0: Vec<f64> = refits.iter().map(|r| r.value).collect();
        let scales: Vec<f64> = theta0.iter().map(|v| v.abs().max(0.01)).collect();
        let set = |m: &mut Model, theta: &[f64]| set_slots(m, &slots, theta);
        let fit = filter.fit(&model, &set, &theta0, &scales, &gusts.model());
        set_slots(&mut model, &slots, &fit.theta);
        for ((r, v), s) in refits.iter_mut().zip(&fit.theta).zip(&fit.sigma) {
            r.value = *v;
            r.sigma = *s;
        }
        // The causes carry the filter's values from here on (the verdict, `--out`).
        for c in d.found.iter_mut() {
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
        // The gusts again on the refitted model: the causes no longer hide part of them.
        gusts = filter.estimate_gusts(&model);
    }
    let finding = TurbulenceFinding {
        gusts,
        refits,
        forced,
    };
    if finding.significant() {
        d.verdict = Verdict::Turbulence(d.found.iter().map(|c| c.effect.clone()).collect());
        // Where output error's error lies, and which numbers would reduce it, describe the
        // gusts' response: no longer evidence of a missing cause.
        d.evidence.clear();
    }
    d.turbulence = Some(finding);
    Ok(())
}
