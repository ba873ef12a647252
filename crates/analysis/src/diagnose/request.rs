//! One diagnosis, finished: against the noise or against reference flights, and through the
//! filter-error method where output error leaves the flight unexplained (or the method is
//! forced). The caller gets the diagnosis as it stands, never one to patch.

use wireflight_data::FlightData;
use wireflight_flight::effects::Effect;
use wireflight_flight::model::Model;
use wireflight_flight::sensor_errors::SensorErrors;

use super::reference::{diagnose_against, AgainstError};
use super::turbulence::{through_turbulence, Method};
use super::{diagnose, DiagnoseConfig, DiagnoseError, Diagnosis};
use crate::error_floor::{error_floor, DRAWS, SEED};
use crate::filter_error::flight::FilterError;

/// What a diagnosis is asked.
pub struct Request<'a> {
    /// The model as given (built without the flight's record when `references` are given,
    /// as it is flown on them too).
    pub model: &'a Model,
    /// The flight.
    pub data: &'a FlightData,
    /// Reference flights of the same aircraft, by name: causes become changes from them.
    pub references: &'a [(&'a str, &'a FlightData)],
    /// The log's sensor errors as stated: the flight is judged against the floor they leave
    /// on a right model ([`crate::error_floor`]). Not with `references`, which measure it.
    pub errors: Option<&'a SensorErrors>,
    /// Candidate effects beyond the catalogue (a model file's terms without values, the
    /// terms `discover` proposes).
    pub declared: &'a [Box<dyn Effect>],
    /// The search's options.
    pub config: DiagnoseConfig,
    /// Output error, the filter-error method, or the test's choice between them.
    pub method: Method,
}

/// What stops a diagnosis.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The diagnosis against the noise.
    #[error(transparent)]
    Diagnose(#[from] DiagnoseError),
    /// The diagnosis against reference flights.
    #[error(transparent)]
    Against(#[from] AgainstError),
    /// The filter was forced and cannot run.
    #[error("--method filter-error: {0}")]
    Filter(#[source] FilterError),
}

/// Diagnose `request.data` (module docs).
///
/// # Errors
/// A flight the diagnosis cannot take, a reference that cannot be one, or a forced filter
/// that cannot run.
pub fn run(request: &Request) -> Result<Diagnosis, RunError> {
    let Request {
        model,
        data,
        references,
        errors,
        declared,
        config,
        method,
    } = *request;
    let mut d = match errors {
        _ if !references.is_empty() => {
            diagnose_against(model, data, references, declared, &config)?
        }
        Some(errors) => diagnose_with_errors(model, data, errors, declared, &config)?,
        None => diagnose(model, data, declared, &config)?,
    };
    // (Against reference flights the diagnosis's noise is their floor, the model's own error
    // included: the filter weighs its innovations by it as output error does.)
    through_turbulence(
        model,
        &mut d,
        data,
        references,
        &config,
        &config.compare,
        method,
    )
    .map_err(RunError::Filter)?;
    Ok(d)
}

/// Diagnose `data` against the floor `errors` leave on a right model: weighed by its noise
/// and that floor together, at the floor up to as far as the floor's own draws reach.
fn diagnose_with_errors(
    model: &Model,
    data: &FlightData,
    errors: &SensorErrors,
    declared: &[Box<dyn Effect>],
    config: &DiagnoseConfig,
) -> Result<Diagnosis, DiagnoseError> {
    let Some(floor) = error_floor(
        model,
        data,
        errors,
        config.compare,
        config.at_floor,
        DRAWS,
        SEED,
    ) else {
        // Too short for one window: the diagnosis says so.
        return diagnose(model, data, declared, config);
    };
    let mut cfg = *config;
    cfg.compare.model_error = Some(floor.model_error);
    cfg.compare.colour_floor = Some(floor.colour);
    cfg.at_floor = floor.at_floor;
    let mut d = diagnose(model, data, declared, &cfg)?;
    d.error_floor = Some(floor);
    Ok(d)
}
