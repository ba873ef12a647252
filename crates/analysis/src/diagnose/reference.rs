//! A diagnosis against reference flights ([`crate::reference`]): the test flight is judged
//! against the floor the model leaves on flights believed normal, and what it finds is
//! reported as a **change from the references**.
//!
//! The selection runs on the test flight in floor units. A model that is not exact leaves
//! structured residuals, so a term may fit the test flight significantly only because it
//! fits the model's own error — which the references share. Every cause kept is therefore
//! fitted on each reference flight too (the same causes together, from the same model): a
//! cause is a change only where some parameter of it differs between the test flight and
//! the references by more than both fits' σ and the scatter between the references allow
//! (the normal test at the family-wise level, shared over every parameter tested). A cause
//! that fits the references as it fits the test flight is the model's own error and is
//! dropped, and so is an effect without parameters (nothing to differ). The causes left are
//! refitted together on the test flight.

use super::fit::Baseline;
use super::joint::{fit_joint, Member};
use super::{diagnose, Candidate, DiagnoseConfig, DiagnoseError, Diagnosis, Verdict};
use crate::compare::Prepared;
use crate::reference::{model_floor, ModelFloor, ReferenceError};
use wireflight_data::FlightData;
use wireflight_flight::model::Model;
use wireflight_flight::numeric::chi2_quantile;

/// One fitted parameter of a cause, on the test flight and on the references.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamChange {
    /// The cause (`aircraft:c_ell_p`, `wind`).
    pub cause: String,
    /// The parameter.
    pub param: String,
    /// Its value fitted on the test flight, and 1σ.
    pub test: (f64, f64),
    /// Its value fitted on the reference flights (their mean), and the 1σ of that mean,
    /// scatter between them included.
    pub reference: (f64, f64),
    /// How many σ of the difference apart the two are.
    pub z: f64,
}

impl ParamChange {
    /// The change of an aircraft number relative to the references' value, in %, and its
    /// 1σ (None for an effect's parameter, whose size is not relative to anything, and where
    /// the references' value is 0).
    pub fn percent(&self) -> Option<(f64, f64)> {
        let r = self.reference.0;
        (r != 0.0 && self.cause.starts_with("aircraft:")).then(|| {
            let sigma = self.test.1.hypot(self.reference.1);
            (100.0 * (self.test.0 / r - 1.0), 100.0 * sigma / r.abs())
        })
    }
}

/// What the references said about a diagnosis.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceVerdict {
    /// The references' names, as given.
    pub names: Vec<String>,
    /// The floor they measured.
    pub floor: ModelFloor,
    /// Every parameter of every cause the selection kept, on the test flight and on the
    /// references.
    pub params: Vec<ParamChange>,
    /// How far apart (σ) a parameter must be to count as changed.
    pub z_critical: f64,
    /// The causes dropped because the references have them as well.
    pub shared: Vec<String>,
    /// The test flight's own measurement noise (the diagnosis's `base_noise` is the floor:
    /// noise and the model's error together).
    pub measured_noise: crate::compare::NoiseEstimate,
}

/// Why a diagnosis against references failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AgainstError {
    /// A reference that cannot be one.
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    /// The diagnosis itself.
    #[error(transparent)]
    Diagnose(#[from] DiagnoseError),
}

/// Diagnose `data` against the reference flights `references` (name, flight; each already
/// accepted by [`crate::reference::check_reference`]): module docs.
///
/// # Errors
/// A reference too short for one window; as [`diagnose`].
pub fn diagnose_against(
    base: &Model,
    data: &FlightData,
    references: &[(&str, &FlightData)],
    extra: &[Box<dyn wireflight_flight::effects::Effect>],
    cfg: &DiagnoseConfig,
) -> Result<Diagnosis, AgainstError> {
    let floor = model_floor(base, references, cfg.compare)?;
    let mut cfg = *cfg;
    cfg.compare.model_error = Some(floor.model_error);
    let mut diag = diagnose(base, data, extra, &cfg)?;
    let measured_noise = Prepared::new(data, cfg.compare).measured_noise;
    let preps: Vec<Prepared> = references
        .iter()
        .map(|(_, d)| Prepared::new(d, cfg.compare))
        .collect();
    let (params, z_critical) = compare_causes(base, &diag.found, &preps, &cfg)?;
    let changed = |c: &Candidate| {
        params
            .iter()
            .any(|p| p.cause == c.effect && p.z > z_critical)
    };
    let shared: Vec<String> = diag
        .found
        .iter()
        .filter(|c| !changed(c))
        .map(|c| c.effect.clone())
        .collect();
    if !shared.is_empty() {
        refit_changes(base, data, &mut diag, &cfg, &changed)?;
    }
    diag.reference = Some(ReferenceVerdict {
        names: references.iter().map(|(n, _)| n.to_string()).collect(),
        floor,
        params,
        z_critical,
        shared,
        measured_noise,
    });
    Ok(diag)
}

/// Every parameter of the causes `found` (fitted on the test flight) against the same causes
/// fitted together on each reference, and the critical z.
fn compare_causes(
    base: &Model,
    found: &[Candidate],
    preps: &[Prepared],
    cfg: &DiagnoseConfig,
) -> Result<(Vec<ParamChange>, f64), DiagnoseError> {
    if found.is_empty() || preps.is_empty() {
        return Ok((Vec::new(), f64::INFINITY));
    }
    let members: Vec<Member> = found.iter().map(Member::of).collect();
    let mut model = base.clone();
    for c in found {
        c.correction.apply(&mut model)?;
    }
    // Each reference's value and σ of every fitted parameter, in the joint fit's order.
    let mut per_reference: Vec<Vec<(f64, f64)>> = Vec::with_capacity(preps.len());
    for prep in preps {
        let start = Baseline::of(base, prep);
        let joint = fit_joint(
            model.clone(),
            members.clone(),
            prep,
            &start,
            cfg.max_iterations,
        )?;
        let values = crate::free::values(&joint.model, &joint.free);
        let np = joint.free.len();
        let sigma = |k: usize| {
            joint
                .cov
                .as_ref()
                .map_or(f64::NAN, |c| c[k * np + k].sqrt())
        };
        per_reference.push(
            values
                .iter()
                .enumerate()
                .map(|(k, v)| (*v, sigma(k)))
                .collect(),
        );
    }
    let mut out = Vec::new();
    let mut k = 0;
    for c in found {
        for (((name, value), held), sigma) in c.params.iter().zip(&c.held).zip(&c.uncertainty) {
            if *held {
                continue;
            }
            let refs: Vec<(f64, f64)> = per_reference
                .iter()
                .filter_map(|r| r.get(k).copied())
                .collect();
            k += 1;
            let n = refs.len() as f64;
            let mean = refs.iter().map(|r| r.0).sum::<f64>() / n;
            // The mean's σ from the fits, and the scatter between flights beyond it: a
            // number the model's error moves from flight to flight moves on the test flight
            // as much.
            let fit_var = refs.iter().map(|r| r.1 * r.1).sum::<f64>() / n;
            let scatter = if refs.len() > 1 {
                refs.iter().map(|r| (r.0 - mean).powi(2)).sum::<f64>() / (n - 1.0)
            } else {
                0.0
            };
            let between = (scatter - fit_var).max(0.0);
            let ref_sigma = (fit_var / n + between / n).sqrt();
            let diff_sigma = (sigma * sigma + ref_sigma * ref_sigma + between).sqrt();
            let z = (value - mean).abs() / diff_sigma;
            out.push(ParamChange {
                cause: c.effect.clone(),
                param: name.clone(),
                test: (*value, *sigma),
                reference: (mean, ref_sigma),
                z: if z.is_nan() { 0.0 } else { z },
            });
        }
    }
    let tested = out.len().max(1) as f64;
    let z_critical = chi2_quantile(1.0 - cfg.alpha / tested, 1.0).sqrt();
    Ok((out, z_critical))
}

/// Refit on the test flight only the causes that changed, and decide again.
fn refit_changes(
    base: &Model,
    data: &FlightData,
    diag: &mut Diagnosis,
    cfg: &DiagnoseConfig,
    changed: &dyn Fn(&Candidate) -> bool,
) -> Result<(), DiagnoseError> {
    let kept: Vec<&Candidate> = diag.found.iter().filter(|c| changed(c)).collect();
    if kept.is_empty() {
        diag.found.clear();
        diag.found_error = diag.base_error;
        diag.found_noise_units = diag.noise_units;
    } else {
        let prep = Prepared::new(data, cfg.compare);
        let mut model = base.clone();
        for c in &kept {
            c.correction.apply(&mut model)?;
        }
        let members: Vec<Member> = kept.iter().map(|c| Member::of(c)).collect();
        let start = Baseline::of(base, &prep);
        let mut joint = fit_joint(model, members, &prep, &start, cfg.max_iterations)?;
        let _ = joint.test_members(&[], base, &prep, cfg.max_iterations)?;
        diag.found = joint.records(base, &diag.base, cfg, diag.candidates);
        diag.found_error = joint.comparison.total;
        diag.found_noise_units = joint.comparison.noise_units();
    }
    diag.verdict = if diag.found.is_empty() {
        if diag.noise_units <= cfg.at_floor {
            Verdict::None
        } else {
            Verdict::Unexplained
        }
    } else if diag.found_noise_units <= cfg.at_floor {
        Verdict::Found(diag.found.iter().map(|c| c.effect.clone()).collect())
    } else {
        Verdict::Unexplained
    };
    diag.alternatives.clear();
    Ok(())
}
