//! The comparison's error after the terms `discover` found: each term's spec added, with the
//! terms before it, and fitted by output error as `compare --add` fits them.
//!
//! The equation error that finds a term says how much of the axis's missing moment it removes;
//! what a user decides on is the flight's error in units of the measurement noise (1 = right
//! model), which only a comparison of the flown model with the flight gives.

use wireflight_flight::model::Model;
use wireflight_flight::spec::EffectSpec;

use super::Discovery;
use crate::compare::{compare_prepared, Prepared};
use crate::diagnose::{add_fitted, DiagnoseConfig};

/// The comparison's error (× the noise) of `model` as given, into `found.error_before`, and
/// after each found term with the terms listed before it (best first), into its
/// `error_after`: the terms' specs added to `model` and fitted by output error together, as
/// `compare --add` adds and fits them. A set of terms that cannot be fitted ends the
/// measuring: that term and those after it keep None.
pub fn measure_errors(model: &Model, prep: &Prepared, found: &mut Discovery, cfg: &DiagnoseConfig) {
    found.error_before = Some(compare_prepared(model, prep).noise_units());
    let mut specs: Vec<EffectSpec> = Vec::with_capacity(found.terms.len());
    for term in &mut found.terms {
        let Ok(spec) = EffectSpec::parse(&term.add) else {
            break;
        };
        specs.push(spec);
        let mut with = model.clone();
        if add_fitted(&mut with, prep, &specs, cfg).is_err() {
            break;
        }
        let units = compare_prepared(&with, prep).noise_units();
        if !units.is_finite() {
            break;
        }
        term.error_after = Some(units);
    }
}
