//! A model assessed on one flight: where and how it fails, before and after the effects a
//! user adds, the floor it is judged against, and — where output error leaves the flight
//! unexplained — the gusts and the added numbers through the filter-error method.
//!
//! This is the whole decision of `wireflight compare`, returned as one finished
//! [`Assessment`] that the caller only prints ([`crate::report::assessment_text`]) or writes
//! (plots, frames, a model file, a report page).

use wireflight_data::FlightData;
use wireflight_data::VehicleKind;
use wireflight_flight::model::Model;
use wireflight_flight::sensor_errors::SensorErrors;
use wireflight_flight::spec::EffectSpec;

use crate::compare::{
    compare_prepared, noise_floor, CompareConfig, Comparison, NoiseEstimate, Prepared,
};
use crate::conditions::{conditions, growth_exponent, Condition};
use crate::diagnose::reference::diagnose_against;
use crate::diagnose::screen::KeyScore;
use crate::diagnose::turbulence::{compare_through_turbulence, Method, TurbulenceFinding};
use crate::diagnose::{
    add_fitted, diagnose, promising_numbers, Candidate, DiagnoseConfig, DiagnoseError, Verdict,
};
use crate::error_floor::{error_floor, ErrorFloor, DRAWS as ERROR_DRAWS, SEED as ERROR_SEED};
use crate::filter_error::flight::FilterError;
use crate::reference::{model_floor, ModelFloor, ReferenceError};

/// What an assessment is asked.
pub struct Request<'a> {
    /// The model as given (built without the flight's record when `references` are given,
    /// as it is flown on them too).
    pub model: &'a Model,
    /// The flight.
    pub data: &'a FlightData,
    /// Reference flights of the same aircraft, by name: the model's own error on them is the
    /// floor instead of the noise.
    pub references: &'a [(&'a str, &'a FlightData)],
    /// The log's sensor errors as stated: the floor is the one they leave on a right model
    /// ([`crate::error_floor`]) instead of the noise. Not with `references`.
    pub errors: Option<&'a SensorErrors>,
    /// Effects to add and fit (`--add`).
    pub add: &'a [EffectSpec],
    /// How the flight is cut into windows and fitted.
    pub compare: CompareConfig,
    /// Output error, the filter-error method, or the test's choice between them.
    pub method: Method,
}

/// Where and how one model fails: its comparison, the conditions its error follows and how
/// the error grows inside a window.
#[derive(Clone, Debug)]
pub struct Findings {
    /// The model against the flight.
    pub comparison: Comparison,
    /// The conditions the window scores follow, most correlated first.
    pub conditions: Vec<Condition>,
    /// The exponent of the error's growth inside a window, where it can be measured.
    pub growth: Option<f64>,
}

/// The reference flights' floor.
#[derive(Clone, Debug)]
pub struct ReferenceFloor {
    /// The reference flights' names.
    pub names: Vec<String>,
    /// The model's own error they measure.
    pub floor: ModelFloor,
}

/// A finished assessment.
#[derive(Clone, Debug)]
pub struct Assessment {
    /// The model as given.
    pub base: Model,
    /// The windows and fits used (with the references' model error where given).
    pub config: CompareConfig,
    /// The measurement noise as estimated from the flight.
    pub measured_noise: NoiseEstimate,
    /// The residuals' standard deviations: the noise, or noise and the references' model
    /// error together.
    pub noise: NoiseEstimate,
    /// The floor the model's error is measured against, when reference flights were given.
    pub reference_floor: Option<ReferenceFloor>,
    /// The floor stated sensor errors leave, when they were stated.
    pub error_floor: Option<ErrorFloor>,
    /// The model as given.
    pub before: Findings,
    /// The model with the added effects, when any were added.
    pub after: Option<Findings>,
    /// The model as it ends up: with the added effects at their output-error values (the
    /// model as given where none were added).
    pub final_model: Model,
    /// The added effects, fitted by output error.
    pub fitted: Vec<Candidate>,
    /// The total a right model leaves on these data (or, against references, a model that
    /// errs as on them).
    pub floor: f64,
    /// Whether the model as it ends up is at that floor.
    pub at_floor: bool,
    /// The filter-error method's account, where it ran and found the gusts (or was
    /// forced), and the model with the added effects refitted through it.
    pub turbulence: Option<(TurbulenceFinding, Model)>,
    /// At the floor: the aircraft's numbers the score test says could still explain a
    /// significant part of the error, most promising first.
    pub promising: Vec<KeyScore>,
}

impl Assessment {
    /// The findings of the model as it ends up.
    pub fn last(&self) -> &Findings {
        self.after.as_ref().unwrap_or(&self.before)
    }

    /// The findings whose conditions the text names first: the final model's where the text
    /// lists them (above the floor), else the model as given's.
    pub fn quoted(&self) -> &Findings {
        if self.at_floor {
            &self.before
        } else {
            self.last()
        }
    }

    /// The model a model file keeps: with the filter's values where it ran.
    pub fn kept_model(&self) -> &Model {
        self.turbulence
            .as_ref()
            .map_or(&self.final_model, |(_, m)| m)
    }

    /// What the error is measured in: the references' floor or the noise.
    pub fn unit(&self) -> &'static str {
        if self.reference_floor.is_some() || self.error_floor.is_some() {
            "floor"
        } else {
            "noise"
        }
    }
}

/// What stops an assessment.
#[derive(Debug, thiserror::Error)]
pub enum AssessError {
    /// A reference flight cannot measure the model's error.
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    /// The flight is shorter than a window.
    #[error(
        "too short to compare ({samples} samples over {duration_s:.2} s; a window is {window_s} s)"
    )]
    TooShort {
        /// Its samples.
        samples: usize,
        /// Its duration, s.
        duration_s: f64,
        /// The window, s.
        window_s: f64,
    },
    /// An added effect cannot be fitted.
    #[error("--add: {0}")]
    Add(#[source] DiagnoseError),
    /// The filter was forced and cannot run.
    #[error("--method filter-error: {0}")]
    Filter(#[source] FilterError),
}

impl Findings {
    fn of(model: &Model, data: &FlightData, prep: &Prepared) -> Self {
        let comparison = compare_prepared(model, prep);
        // The growth law needs the model on its own: starts fitted over the first quarter of
        // each window, the drift measured over the rest.
        let cfg = prep.config();
        let fit_span = 0.25 * cfg.window_s;
        let drift_prep = Prepared::new(
            data,
            CompareConfig {
                start_span_s: Some(fit_span),
                ..cfg
            },
        );
        let drift = compare_prepared(model, &drift_prep);
        let noise_m2: f64 = prep.noise.pos_axes.iter().map(|s| s * s).sum();
        Self {
            conditions: conditions(data, &comparison, model.origin.altitude_m),
            growth: growth_exponent(data, &drift, fit_span, noise_m2),
            comparison,
        }
    }
}

/// Assess `request.model` on `request.data` (module docs).
///
/// # Errors
/// A reference flight that cannot be one, a flight shorter than a window, an added effect
/// that cannot be fitted, or a forced filter that cannot run.
pub fn assess(request: &Request) -> Result<Assessment, AssessError> {
    let Request {
        model: base,
        data,
        references,
        errors,
        add,
        mut compare,
        method,
    } = *request;
    let reference_floor = if references.is_empty() {
        None
    } else {
        let floor = model_floor(base, references, compare)?;
        compare.model_error = Some(floor.model_error);
        Some(ReferenceFloor {
            names: references.iter().map(|(n, _)| n.to_string()).collect(),
            floor,
        })
    };
    let mut dcfg = DiagnoseConfig::default();
    let error_floor = match errors {
        Some(errors) if references.is_empty() => {
            let floor = error_floor(
                base,
                data,
                errors,
                compare,
                dcfg.at_floor,
                ERROR_DRAWS,
                ERROR_SEED,
            );
            if let Some(f) = &floor {
                compare.model_error = Some(f.model_error);
                compare.colour_floor = Some(f.colour);
                dcfg.at_floor = f.at_floor;
            }
            floor
        }
        _ => None,
    };
    let prep = Prepared::new(data, compare);
    if prep.windows.is_empty() {
        return Err(AssessError::TooShort {
            samples: data.len(),
            duration_s: data.duration(),
            window_s: compare.window_s,
        });
    }
    dcfg.compare = compare;
    let before = Findings::of(base, data, &prep);
    let mut final_model = base.clone();
    let fitted = add_fitted(&mut final_model, &prep, add, &dcfg).map_err(AssessError::Add)?;
    let after = (!fitted.is_empty()).then(|| Findings::of(&final_model, data, &prep));
    let last = after.as_ref().unwrap_or(&before);
    let floor = noise_floor(&final_model, &prep);
    let at_floor = last.comparison.noise_units() <= dcfg.at_floor;
    let unexplained = method == Method::Auto
        && !at_floor
        && leaves_unexplained(&final_model, data, references, &dcfg);
    // The filter's values of the added effects are in its own account (and the model file);
    // the output-error values stay with the table.
    let mut refitted = fitted.clone();
    let turbulence =
        compare_through_turbulence(base, &mut refitted, &prep, references, method, unexplained)
            .map_err(AssessError::Filter)?;
    // Near the floor the totals alone cannot tell a right model from one with a small wrong
    // number: the score test can, at the cost of one flight per number and window.
    let promising = if at_floor {
        promising_numbers(&final_model, &prep, &dcfg)
    } else {
        Vec::new()
    };
    Ok(Assessment {
        base: base.clone(),
        config: compare,
        measured_noise: prep.measured_noise,
        noise: prep.noise,
        reference_floor,
        error_floor,
        before,
        after,
        final_model,
        fitted,
        floor,
        at_floor,
        turbulence,
        promising,
    })
}

/// Whether a diagnosis of `model` leaves the flight unexplained, the condition for trying
/// the filter: a comparison searches no cause, and where a deterministic one is missing the
/// filter would take its response for gusts (a steady wind for a slow gust). Only a fixed
/// wing has the filter; a flight the diagnosis cannot take (it refuses with its own message
/// under `diagnose`) is not tried either — the comparison itself stands.
fn leaves_unexplained(
    model: &Model,
    data: &FlightData,
    references: &[(&str, &FlightData)],
    cfg: &DiagnoseConfig,
) -> bool {
    if model.vehicle.kind() != VehicleKind::FixedWing {
        return false;
    }
    let verdict = if references.is_empty() {
        diagnose(model, data, &[], cfg).map(|d| d.verdict).ok()
    } else {
        diagnose_against(model, data, references, &[], cfg)
            .map(|d| d.verdict)
            .ok()
    };
    verdict == Some(Verdict::Unexplained)
}
