//! The compare panel's "discover": the force and moment the model as ticked lacks on the
//! flight, read by `discover` ([`wireflight_analysis::discover`]), and each of the best terms
//! it proposes fitted alone by output error on top of that model, as `--add` fits one — all
//! on a worker thread ([`super::compare::Compare::start_discover`]). Each term becomes a
//! checkbox row of the panel, with discover's physical reading and estimate beside the fitted
//! coefficient.
//!
//! No window code: the window reads this state, tests drive it directly
//! ([`super::compare::Compare::wait_discover`]).

use std::time::Instant;

use wireflight_analysis::compare::Prepared;
use wireflight_analysis::diagnose::{add_fitted, DiagnoseConfig};
use wireflight_analysis::discover::discover;
use wireflight_data::format::fmt_number;
use wireflight_data::FlightData;
use wireflight_flight::effects::Effect;
use wireflight_flight::expr::Axis;
use wireflight_flight::model::Model;
use wireflight_flight::spec::EffectSpec;

/// How many of discover's terms (best first) become rows: each is fitted, and a row the
/// flight barely supports only crowds the panel (`diagnose --discover` tries as many).
pub const DISCOVERED_ROWS: usize = 5;

/// What discover said of one term, shown beside its row.
#[derive(Clone, Debug, PartialEq)]
pub struct Discovered {
    /// The axis it acts on.
    pub axis: Axis,
    /// Its physical reading ("pitching moment ∝ thrust: a thrust line off the centre of
    /// gravity …").
    pub reading: String,
    /// The coefficient's name in the term (`k_m1`).
    pub coefficient_name: String,
    /// discover's estimate of the coefficient (from the equation error), N or N·m per unit of
    /// the regressor.
    pub estimate: f64,
    /// Its standard error.
    pub sigma: f64,
    /// The `--add` spec that adds the term on the command line.
    pub add: String,
    /// The flight's misfit in units of the noise with the term fitted alone on top of the
    /// model discover read (None where the fit failed).
    pub noise_units_after: Option<f64>,
}

impl Discovered {
    /// The panel's note under the row's parameters: the reading, discover's estimate ± σ and
    /// the misfit with the term fitted.
    pub fn note(&self) -> String {
        let after = self.noise_units_after.map_or_else(
            || "not fitted".to_string(),
            |u| format!("{u:.2} × the noise"),
        );
        format!(
            "{}\ndiscover: {} = {} ± {}; with it {after}",
            self.reading,
            self.coefficient_name,
            fmt_number(self.estimate),
            fmt_number(self.sigma),
        )
    }
}

/// One term found: the makings of its row.
#[derive(Debug)]
pub struct FoundTerm {
    /// The term's effect name (`term(m=k_m1*thrust)`).
    pub name: &'static str,
    /// The term with discover's estimate as its coefficient: what the row adds until (or
    /// where not) fitted.
    pub estimate: Box<dyn Effect>,
    /// The term fitted by output error, and the total error with it (as a diagnosis's
    /// `error_after`), where the fit succeeded.
    pub fitted: Option<(Box<dyn Effect>, f64)>,
    /// What discover said of it.
    pub discovered: Discovered,
}

/// What one discovery found.
#[derive(Debug)]
pub struct Found {
    /// The rows to add or annotate, best first.
    pub terms: Vec<FoundTerm>,
    /// How many terms discover proposed (of which the best [`DISCOVERED_ROWS`] are rows).
    pub proposed: usize,
    /// The misfit in units of the noise of the model discover read.
    pub noise_units_before: f64,
}

/// Where the panel's discovery stands.
#[derive(Debug)]
pub enum Discovering {
    /// Not asked for.
    Off,
    /// Running on its worker thread since then.
    Running(Instant),
    /// Finished.
    Done {
        /// Terms proposed.
        proposed: usize,
        /// Of which rows.
        rows: usize,
        /// The misfit (× the noise) of the model it read.
        noise_units_before: f64,
        /// Seconds it took.
        seconds: f64,
    },
    /// It could not run (the message says why), or its thread died.
    Failed(String),
}

impl Discovering {
    /// A line for the panel.
    pub fn line(&self) -> String {
        match self {
            Discovering::Off => {
                "discover: not run (the force and moment the model lacks, as terms)".into()
            }
            Discovering::Running(t) => {
                format!("discovering… ({:.1} s)", t.elapsed().as_secs_f64())
            }
            Discovering::Done { proposed: 0, .. } => {
                "discover: no term found — the model lacks no force or moment it can read".into()
            }
            Discovering::Done {
                proposed,
                rows,
                noise_units_before,
                seconds,
            } => {
                let terms = if *proposed == 1 { "term" } else { "terms" };
                format!(
                    "discover: {proposed} {terms} found ({rows} as rows, {seconds:.1} s); \
                     the model it read: {noise_units_before:.2} × the noise"
                )
            }
            Discovering::Failed(why) => format!("discover failed: {why}"),
        }
    }
}

/// discover on `data` against `model`, and the best [`DISCOVERED_ROWS`] terms it proposes
/// each fitted alone on top of `model` (comparison settings of `cfg`). A term already in
/// `model` is left out. A term whose fit fails keeps discover's estimate.
///
/// # Errors
/// discover's own: a model or a flight it cannot read (the message).
pub fn find(model: &Model, data: &FlightData, cfg: &DiagnoseConfig) -> Result<Found, String> {
    let found = discover(model, data).map_err(|e| e.to_string())?;
    let prep = Prepared::new(data, cfg.compare);
    let noise_units_before =
        wireflight_analysis::compare::compare_prepared(model, &prep).noise_units();
    let ctx = model.effect_context();
    let mut terms = Vec::new();
    for term in found.terms.iter().take(DISCOVERED_ROWS) {
        // discover prints only specs the term language reads; one that does not is skipped
        // rather than trusted.
        let Ok(spec) = EffectSpec::parse(&term.add) else {
            continue;
        };
        let Ok(mut estimate) = spec.build(&ctx) else {
            continue;
        };
        if model.has_effect(estimate.name()) {
            continue;
        }
        // An estimate outside the coefficient's range leaves it at its start.
        let _ = estimate.set_param(&term.coefficient_name, term.coefficient);
        let name = estimate.name();
        let mut with = model.clone();
        let fitted = add_fitted(&mut with, &prep, std::slice::from_ref(&spec), cfg)
            .ok()
            .and_then(|cands| cands.into_iter().next())
            .and_then(|cand| {
                let effect = with.effects.iter().find(|e| e.name() == name)?.clone();
                Some((effect, cand.error_after, cand.noise_units_after))
            });
        terms.push(FoundTerm {
            name,
            estimate,
            discovered: Discovered {
                axis: term.axis,
                reading: term.reading.clone(),
                coefficient_name: term.coefficient_name.clone(),
                estimate: term.coefficient,
                sigma: term.sigma,
                add: term.add.clone(),
                noise_units_after: fitted.as_ref().map(|f| f.2),
            },
            fitted: fitted.map(|(e, error, _)| (e, error)),
        });
    }
    Ok(Found {
        terms,
        proposed: found.terms.len(),
        noise_units_before,
    })
}
