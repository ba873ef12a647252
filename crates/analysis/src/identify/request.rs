//! One identification, finished: the numbers fitted by output error over every flight,
//! refitted through the filter-error method where the flights were flown in gusts (or the
//! method is forced), and checked on the held-out flights. The caller gets it as it stands,
//! to print ([`crate::report::identification`]) or write, never one to patch.

use wireflight_data::FlightData;
use wireflight_flight::model::Model;
use wireflight_flight::params::keys::AircraftKey;

use super::turbulence::{through_turbulence, ThroughTurbulence};
use super::{identify, Identification, IdentifyConfig, IdentifyError};
use crate::compare::compare;
use crate::filter_error::flight::{FilterError, MethodChoice as Method};

/// What an identification is asked.
pub struct Request<'a> {
    /// The model to start from: its parameter set is the prior's centre.
    pub model: &'a Model,
    /// The flights the numbers are fitted on.
    pub flights: &'a [FlightData],
    /// Flights held out of the fit, on which it is checked.
    pub held_out: &'a [FlightData],
    /// The numbers to fit.
    pub free: &'a [&'static AircraftKey],
    /// The windows, the prior, the starting point.
    pub config: IdentifyConfig,
    /// Output error, the filter-error method, or the gusts' test's choice between them.
    pub method: Method,
}

/// A held-out flight's error, in noise units, with the starting set and the identified one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeldOut {
    /// With the starting set.
    pub before: f64,
    /// With the identified set.
    pub after: f64,
}

/// A finished identification.
#[derive(Clone, Debug)]
pub struct Identified {
    /// The model it started from.
    pub base: Model,
    /// The settings it was made with.
    pub config: IdentifyConfig,
    /// The numbers, their σ and correlations, each flight's error before and after (the
    /// filter's values where it ran).
    pub identification: Identification,
    /// The filter-error method's account, where it ran.
    pub turbulence: Option<ThroughTurbulence>,
    /// Each held-out flight's error, in the request's order.
    pub held_out: Vec<HeldOut>,
}

/// What stops an identification.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The output-error fit.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    /// The filter was forced and cannot run.
    #[error("--method filter-error: {0}")]
    Filter(#[source] FilterError),
}

/// Identify `request.free` from `request.flights` (module docs).
///
/// # Errors
/// What stops the output-error fit ([`IdentifyError`]), or a forced filter that cannot run.
pub fn run(request: &Request) -> Result<Identified, RunError> {
    let Request {
        model: base,
        flights,
        held_out,
        free,
        config,
        method,
    } = *request;
    let mut identification = identify(base, flights, free, &config)?;
    let turbulence = through_turbulence(flights, &mut identification, &config, method)
        .map_err(RunError::Filter)?;
    let held_out = held_out
        .iter()
        .map(|d| HeldOut {
            before: compare(base, d, config.compare).noise_units(),
            after: compare(&identification.model, d, config.compare).noise_units(),
        })
        .collect();
    Ok(Identified {
        base: base.clone(),
        config,
        identification,
        turbulence,
        held_out,
    })
}
