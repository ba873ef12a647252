//! Several corrections fitted together: the parameters of every cause found so far move at
//! once, with every window's start, so no cause keeps the value it took while another was
//! still missing. A wind fitted before the pitch damping is known absorbs part of the
//! damping's misfit (1.42 m/s east instead of 1.5); refitted jointly it returns to the
//! truth.
//!
//! The joint fit is the single-candidate fit ([`super::fit::fit`]) over the union of the
//! members' free parameters; its covariance is the joint one, so each member's ± accounts
//! for what the others could take over. Whether a member is still needed given the others is
//! the likelihood-ratio test of the model without it (refitted) against the joint fit — the
//! same test that admitted it.

use std::ops::Range;

use super::fit::{covariance, effect_free, fit, lr_critical, make_candidate, Baseline, Trial};
use super::{Candidate, Correction, DiagnoseConfig, DiagnoseError};
use crate::compare::start::Scratch;
use crate::compare::{colour_factor, compare_corrections, Comparison, Prepared};
use crate::free::{aircraft_free, effect, set_values, values, Free};
use crate::lm::newton_trial;
use crate::profile::{add_into, perturbed_models, window_normal_towards, Linearised};
use wireflight_flight::model::Model;
use wireflight_flight::numeric::solve_in_place;

/// One cause of a joint fit: an effect (with the parameters the user held), or numbers of
/// the aircraft's set.
#[derive(Clone, Debug)]
pub(crate) struct Member {
    pub(crate) trial: Trial,
    /// An effect's parameters not fitted.
    held: Vec<String>,
}

impl Member {
    /// The member a fitted candidate stands for.
    pub(crate) fn of(c: &Candidate) -> Self {
        match &c.correction {
            Correction::Effect(e) => Self {
                trial: Trial::Effect(e.name().to_string()),
                held: c
                    .params
                    .iter()
                    .zip(&c.held)
                    .filter(|(_, h)| **h)
                    .map(|((k, _), _)| k.clone())
                    .collect(),
            },
            Correction::Aircraft(changes) => Self {
                trial: Trial::Aircraft(changes.iter().map(|c| c.key).collect()),
                held: Vec::new(),
            },
        }
    }

    pub(crate) fn label(&self) -> String {
        self.trial.label()
    }

    /// Take this member out of `model`: its effect removed, its numbers back to `base`'s.
    fn remove_from(&self, model: &mut Model, base: &Model) {
        match &self.trial {
            Trial::Effect(name) => model.effects.retain(|e| e.name() != name.as_str()),
            Trial::Aircraft(keys) => {
                for key in keys {
                    if let Some(v) = base.aircraft(key) {
                        let _ = model.set_aircraft(key, v);
                    }
                }
            }
        }
    }
}

/// Corrections fitted jointly on prepared data.
#[derive(Clone, Debug)]
pub(crate) struct JointFit {
    pub(crate) members: Vec<Member>,
    /// The model with every member at its fitted values.
    pub(crate) model: Model,
    /// The free parameters of all members, member after member.
    pub(crate) free: Vec<Free>,
    /// Each member's slice of `free`.
    pub(crate) spans: Vec<Range<usize>>,
    /// The comparison at the fitted values.
    pub(crate) comparison: Comparison,
    /// The joint covariance of `free` in their units (row-major), when determined.
    pub(crate) cov: Option<Vec<f64>>,
    /// Each member's likelihood-ratio statistic against the model without it (refitted).
    pub(crate) lr: Vec<f64>,
}

/// The free parameters of `members` in `model` (effects' at their current values), and each
/// member's slice of them.
fn joint_free(
    model: &mut Model,
    members: &[Member],
    prep: &Prepared,
) -> Result<(Vec<Free>, Vec<Range<usize>>), DiagnoseError> {
    let mut free = Vec::new();
    let mut spans = Vec::new();
    for m in members {
        let start = free.len();
        match &m.trial {
            Trial::Effect(name) => free.extend(effect_free(model, name, &m.held, prep, false)?),
            Trial::Aircraft(keys) => free.extend(aircraft_free(model, keys)?),
        }
        spans.push(start..free.len());
    }
    Ok((free, spans))
}

/// Fit `members` jointly: `model` has every one of them applied (at its starting values),
/// `baseline` holds start fits to begin from (a model close to it, e.g. without the newest
/// member). `lr` is left empty.
pub(crate) fn fit_joint(
    mut model: Model,
    members: Vec<Member>,
    prep: &Prepared,
    baseline: &Baseline,
    iterations: usize,
) -> Result<JointFit, DiagnoseError> {
    let (free, spans) = joint_free(&mut model, &members, prep)?;
    let (comparison, cov) = fit(&mut model, &free, prep, baseline, (iterations, true));
    Ok(JointFit {
        members,
        model,
        free,
        spans,
        comparison,
        cov,
        lr: Vec::new(),
    })
}

/// The likelihood-ratio statistic of a fit `with` a member against the fit `without` it
/// ([`super::fit::likelihood_ratio`]).
fn lr_statistic(with: &Comparison, without: &Comparison) -> f64 {
    super::fit::likelihood_ratio(without, with)
}

impl JointFit {
    /// The joint fit of one member that is `c`, fitted alone on top of `model`: the same
    /// fit, so none is repeated. None when `c` kept no comparison or does not apply.
    pub(crate) fn from_candidate(model: &Model, c: &Candidate, prep: &Prepared) -> Option<Self> {
        let comparison = (**c.comparison.as_ref()?).clone();
        let mut with = model.clone();
        c.correction.apply(&mut with).ok()?;
        let members = vec![Member::of(c)];
        let (free, spans) = joint_free(&mut with, &members, prep).ok()?;
        // The covariance from the candidate's σ and correlations, over its fitted
        // parameters in their order.
        let sigma: Vec<f64> = c
            .uncertainty
            .iter()
            .zip(&c.held)
            .filter(|(_, h)| !**h)
            .map(|(u, _)| *u)
            .collect();
        let np = free.len();
        let cov = (sigma.len() == np
            && c.correlation.len() == np * np
            && sigma.iter().all(|s| s.is_finite()))
        .then(|| {
            (0..np * np)
                .map(|ik| sigma[ik / np] * sigma[ik % np] * c.correlation[ik])
                .collect()
        });
        Some(Self {
            members,
            model: with,
            free,
            spans,
            comparison,
            cov,
            lr: Vec::new(),
        })
    }

    /// The joint fit without member `k`, refitted (the model as given when it was the only
    /// one).
    pub(crate) fn without(
        &self,
        k: usize,
        base: &Model,
        prep: &Prepared,
        iterations: usize,
    ) -> Result<JointFit, DiagnoseError> {
        let mut model = self.model.clone();
        self.members[k].remove_from(&mut model, base);
        let members: Vec<Member> = self
            .members
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != k)
            .map(|(_, m)| m.clone())
            .collect();
        let baseline = Baseline::of(&model, prep);
        if members.is_empty() {
            return Ok(JointFit {
                members,
                model,
                free: Vec::new(),
                spans: Vec::new(),
                comparison: baseline.comparison,
                cov: None,
                lr: Vec::new(),
            });
        }
        fit_joint(model, members, prep, &baseline, iterations)
    }

    /// Test every member but those in `known` (whose statistic is given) by refitting
    /// without it; fills `lr`. Returns the fits without each member tested.
    pub(crate) fn test_members(
        &mut self,
        known: &[(usize, f64)],
        base: &Model,
        prep: &Prepared,
        iterations: usize,
    ) -> Result<Vec<(usize, JointFit)>, DiagnoseError> {
        let mut lr = Vec::with_capacity(self.members.len());
        let mut fits = Vec::new();
        for k in 0..self.members.len() {
            if let Some((_, v)) = known.iter().find(|(i, _)| *i == k) {
                lr.push(*v);
                continue;
            }
            let without = self.without(k, base, prep, iterations)?;
            lr.push(lr_statistic(&self.comparison, &without.comparison));
            fits.push((k, without));
        }
        self.lr = lr;
        Ok(fits)
    }

    /// The statistic of a newest member whose fit without it is `without` (the previous
    /// rung's joint fit, already optimal without it).
    pub(crate) fn lr_against(&self, without: &Comparison) -> f64 {
        lr_statistic(&self.comparison, without)
    }

    /// Each member as a candidate record: its values and ± from the joint fit (its block of
    /// the joint covariance), errors from `before` (the model as given) to the joint fit,
    /// its own likelihood-ratio test given the others.
    pub(crate) fn records(
        &self,
        base: &Model,
        before: &Comparison,
        cfg: &DiagnoseConfig,
        candidates: usize,
    ) -> Vec<Candidate> {
        let np = self.free.len();
        self.members
            .iter()
            .zip(&self.spans)
            .enumerate()
            .filter_map(|(k, (m, span))| {
                let n = span.len();
                let cov = self.cov.as_ref().map(|c| {
                    let mut sub = vec![0.0; n * n];
                    for (i, gi) in span.clone().enumerate() {
                        for (j, gj) in span.clone().enumerate() {
                            sub[i * n + j] = c[gi * np + gj];
                        }
                    }
                    sub
                });
                let mut c = make_candidate(
                    base,
                    &self.model,
                    &m.trial,
                    &self.free[span.clone()],
                    before,
                    &self.comparison,
                    cov,
                    cfg,
                    candidates,
                )
                .ok()?;
                c.joint = self.members.len() > 1;
                let lr = self.lr.get(k).copied().unwrap_or(f64::NAN);
                if lr.is_finite() || lr == f64::INFINITY {
                    c.lr_statistic = lr;
                    c.lr_critical = lr_critical(cfg, candidates, n);
                    c.significant = lr > c.lr_critical && !c.any_at_limit();
                }
                Some(c)
            })
            .collect()
    }
}

/// The full pass of a screened diagnosis: the model as given (`base`) and the joint fit
/// (at its subset values) compared on every window in one pass; each window's share of the
/// joint parameters' normal equations is taken while its start fit exists, so no window's
/// Jacobian outlives it. The parameters then take one Gauss–Newton step on all windows —
/// the all-window estimate, whose covariance is the all-window one — while the comparison
/// is that at the subset values (the two differ by a few of the subset's σ, which changes
/// the misfit by a few units in hundreds of thousands).
///
/// The base model's start in each window is predicted from the joint fit's there
/// ([`compare_corrections`]): linearly in the parameters, with the columns of the normal
/// equations, when the base is the joint model with its parameters moved (effects whose
/// parameters all have absent values, numbers of the set); else from the base's residuals
/// flown at the joint model's start (one flight).
pub(crate) fn full_pass(
    base: &Model,
    joint: Option<&JointFit>,
    full: &Prepared,
) -> (Comparison, Option<JointFit>) {
    let Some(joint) = joint else {
        let (cmp, _) = compare_corrections(base, &[], full, |_, _, _| ((), None));
        return (cmp, None);
    };
    let model = &joint.model;
    let free = &joint.free;
    let np = free.len();
    let theta = values(model, free);
    let perturbed = perturbed_models(model, free, &theta);
    let to_base: Option<Vec<f64>> = base_values(base, joint).map(|b| {
        b.iter()
            .zip(&theta)
            .zip(free)
            .map(|((b, t), f)| (b - t) / f.scale)
            .collect()
    });
    let (base_cmp, mut results) = compare_corrections(base, &[model], full, |_, w, fit| {
        let lin = Linearised::of(model, fit);
        // The fit's residuals are those at its start: no flight for them.
        let at_start = (!fit.residuals.is_empty()).then_some(fit.residuals.as_slice());
        // `lin` is the model's own fit: a wind's columns need no flight.
        let (share, start) = window_normal_towards(
            model,
            &perturbed,
            free,
            full,
            w,
            &lin,
            at_start,
            (to_base.as_deref(), true),
        );
        let start = match start {
            Some(q) => Some(q),
            // Not the joint model with other values: the base's own residuals at its start.
            None if !fit.jacobian.is_empty() => {
                let mut r = Vec::new();
                let span = full.fit_range(w);
                let mut scratch = Scratch::default();
                full.window_residuals(base, span, &lin.state(base), &mut scratch, &mut r);
                (r.len() == fit.residuals.len()).then(|| lin.start_absorbing(&mut r))
            }
            None => None,
        };
        (Some(share), start)
    });
    let Some((after, shares)) = results.pop() else {
        return (base_cmp, None);
    };
    let mut sum = (vec![0.0; np * np], vec![0.0; np]);
    for share in shares.iter().flatten() {
        add_into(&mut sum, share);
    }
    let (a, g) = sum;
    let mut model = model.clone();
    if let Some(theta) = (np > 0)
        .then(|| newton_trial(&a, &g, &theta, free))
        .flatten()
    {
        set_values(&mut model, free, &theta);
    }
    // Each window's gradient share where the step lands (g_w + A_w·δ, to first order): the
    // shares were taken at the subset's values, and the step's own pull would otherwise
    // read as scatter between windows.
    let mut delta: Vec<f64> = g.iter().map(|v| -v).collect();
    let mut m = a.clone();
    let solved = solve_in_place(&mut m, &mut delta, np).is_some();
    let grads: Vec<Vec<f64>> = shares
        .iter()
        .flatten()
        .map(|(aw, gw)| {
            let mut g = gw.clone();
            if solved {
                for (i, gi) in g.iter_mut().enumerate() {
                    *gi += (0..np).map(|k| aw[i * np + k] * delta[k]).sum::<f64>();
                }
            }
            g
        })
        .collect();
    let cov = (np > 0)
        .then(|| {
            let colour = colour_factor(&base_cmp, &after);
            covariance(&a, free, (&after, colour), Some(&grads))
        })
        .flatten();
    let refitted = JointFit {
        members: joint.members.clone(),
        model,
        free: free.clone(),
        spans: joint.spans.clone(),
        comparison: after,
        cov,
        lr: joint.lr.clone(),
    };
    (base_cmp, Some(refitted))
}

/// The base model's values of the joint fit's free parameters, when the base is the joint
/// model with other values: the set's numbers for aircraft members; for an effect, the
/// absent values of its parameters when every one has one and is free (a held one keeps the
/// effect present).
fn base_values(base: &Model, joint: &JointFit) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(joint.free.len());
    for (m, span) in joint.members.iter().zip(&joint.spans) {
        let free = &joint.free[span.clone()];
        match &m.trial {
            Trial::Aircraft(_) => {
                for f in free {
                    out.push(base.aircraft(f.name)?);
                }
            }
            Trial::Effect(name) => {
                let info = effect(&joint.model, name)?.info();
                if info.params.is_empty() || info.params.len() != free.len() {
                    return None;
                }
                for f in free {
                    out.push(info.param(f.name).and_then(|p| p.absent)?);
                }
            }
        }
    }
    Some(out)
}
