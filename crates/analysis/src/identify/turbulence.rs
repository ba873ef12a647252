//! Identification through turbulence: where the flights were flown in gusts, the numbers
//! output error identified are fitted again by the filter-error method
//! ([`crate::filter_error::flight`]) on every flight together, each flight with the gusts the
//! filter estimates on it, held to the starting set by the same prior; then the gusts again
//! on the refitted set and the numbers again with them, in turn, until a fit moves no number
//! by more than [`SETTLED_SIGMAS`] of its σ (as a diagnosis settles its causes,
//! [`crate::diagnose::turbulence`]). `Method::Auto` does so only where some flight's gusts
//! are significant.

use super::{Identification, IdentifyConfig};
use crate::compare::{compare, estimate_noise};
use crate::filter_error::flight::{
    fit_flights, FilterError, FlightFilter, GustEstimate, MethodChoice as Method, SETTLED_SIGMAS,
    SETTLE_ROUNDS,
};
use wireflight_data::FlightData;
use wireflight_flight::model::Model;

/// What the filter-error method did to an identification.
#[derive(Clone, Debug, PartialEq)]
pub struct ThroughTurbulence {
    /// The gusts on each flight (estimated on the refitted set).
    pub gusts: Vec<GustEstimate>,
    /// Output error's values of the numbers, in the identification's order (the estimates now
    /// hold the filter's).
    pub output_error: Vec<f64>,
    /// Whether the method was forced rather than chosen.
    pub forced: bool,
}

/// Refit `id`'s numbers through the filter on `flights` (module docs); None where the
/// method is output error, or automatic and no flight is turbulent.
///
/// # Errors
/// Only when forced and the filter cannot run on a flight.
pub fn through_turbulence(
    flights: &[FlightData],
    id: &mut Identification,
    cfg: &IdentifyConfig,
    method: Method,
) -> Result<Option<ThroughTurbulence>, FilterError> {
    let forced = method == Method::FilterError;
    if method == Method::OutputError || id.estimates.is_empty() {
        return Ok(None);
    }
    let mut filters = Vec::new();
    for d in flights {
        match FlightFilter::new(&id.model, d, &estimate_noise(d), &cfg.compare) {
            Ok(f) => filters.push(f),
            Err(e) if forced => return Err(e),
            Err(_) => return Ok(None),
        }
    }
    let estimate = |model: &Model| -> Vec<GustEstimate> {
        filters.iter().map(|f| f.estimate_gusts(model)).collect()
    };
    let mut gusts = estimate(&id.model);
    if !forced && !gusts.iter().any(GustEstimate::significant) {
        return Ok(None);
    }
    let keys: Vec<&'static str> = id.estimates.iter().map(|e| e.key.name).collect();
    let set = |m: &mut Model, theta: &[f64]| {
        for (k, v) in keys.iter().zip(theta) {
            let _ = m.set_aircraft(k, *v);
        }
    };
    let output_error: Vec<f64> = id.estimates.iter().map(|e| e.value).collect();
    let centre: Vec<f64> = id.estimates.iter().map(|e| e.start).collect();
    let prior: Vec<f64> = id.estimates.iter().map(|e| e.prior_sigma).collect();
    let scales: Vec<f64> = output_error
        .iter()
        .map(|v| (0.1 * v.abs()).max(1e-3))
        .collect();
    let mut theta = output_error.clone();
    let mut settled = false;
    for round in 0..=SETTLE_ROUNDS {
        if round > 0 {
            gusts = estimate(&id.model);
        }
        let pairs: Vec<(&FlightFilter, _)> = filters
            .iter()
            .zip(&gusts)
            .map(|(f, g)| (f, g.model()))
            .collect();
        let fit = fit_flights(
            &pairs,
            &id.model,
            &set,
            &theta,
            &scales,
            Some((&centre, &prior)),
        );
        let spread = fit.pass.normalised.max(1.0);
        // The first fit is judged against output error's values, which it is meant to move.
        settled = round > 0;
        for ((e, v), s) in id.estimates.iter_mut().zip(&fit.theta).zip(&fit.sigma) {
            let sigma = s * spread;
            settled &= (v - e.value).abs() <= SETTLED_SIGMAS * sigma || !sigma.is_finite();
            e.value = *v;
            e.sigma = sigma;
        }
        set(&mut id.model, &fit.theta);
        theta.clone_from(&fit.theta);
        if settled {
            break;
        }
    }
    if !settled {
        gusts = estimate(&id.model);
    }
    id.after = flights
        .iter()
        .map(|d| compare(&id.model, d, cfg.compare))
        .collect();
    Ok(Some(ThroughTurbulence {
        gusts,
        output_error,
        forced,
    }))
}
