//! Levenberg–Marquardt on a model's free parameters: the one step both the diagnosis's fit of
//! a candidate (`diagnose::fit`) and the identification (`identify`) take on their normal
//! equations, and the plain Gauss–Newton step beside it.
//!
//! A step works in the scaled parameters (each in units of its typical size) and keeps every
//! value inside its range. It tries damped steps, raising the damping λ tenfold after each
//! that does not lower the objective and lowering it tenfold (to at least 1e-9) when one does;
//! λ carries over to the next step. What the objective is — a linearised profile, with or
//! without a prior — is the caller's.

use crate::free::{set_values, stepped, Free};
use wireflight_flight::model::Model;
use wireflight_flight::numeric::{dot, solve_in_place};

/// Stop fitting parameters when an iteration lowers χ² (in noise units) by less than this.
pub(crate) const FIT_TOL: f64 = 0.01;

/// The damping a fit begins with.
const LAMBDA_START: f64 = 1e-3;

/// The least damping.
const LAMBDA_MIN: f64 = 1e-9;

/// What a full Gauss–Newton step could still lower the linearised misfit by, gᵀA⁻¹g (None
/// when A is singular): below the fit's tolerance, no trial is worth a pass over the windows
/// — without this check a converged fit spends its last iteration on trials that all fail.
pub(crate) fn newton_gain(a: &[f64], g: &[f64]) -> Option<f64> {
    let mut x = g.to_vec();
    let mut m = a.to_vec();
    solve_in_place(&mut m, &mut x, g.len())?;
    let gain = dot(g, &x);
    gain.is_finite().then_some(gain)
}

/// The least Levenberg–Marquardt damping weight of a parameter: a millionth of the largest
/// diagonal of the normal matrix (1 when it is all zero), so a parameter without sensitivity
/// at the current values stays put instead of making the damped system singular.
fn damping_floor(a: &[f64], np: usize) -> f64 {
    let max = (0..np)
        .map(|k| a[k * np + k])
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    if max > 0.0 {
        1e-6 * max
    } else {
        1.0
    }
}

/// One Levenberg–Marquardt trial: solve (A + λ·diag(A)) δ = −g in the scaled parameters and
/// step `theta` by δ·scale, each value kept inside its range; None when the damped system is
/// singular (the caller raises λ). The damping of a parameter the misfit does not see yet (a
/// thermal's radius while its updraft is 0) is floored by [`damping_floor`], or it would keep
/// every step singular.
fn damped_trial(
    a0: &[f64],
    g: &[f64],
    lambda: f64,
    theta: &[f64],
    free: &[Free],
) -> Option<Vec<f64>> {
    let np = free.len();
    let floor = damping_floor(a0, np);
    let mut a = a0.to_vec();
    for k in 0..np {
        a[k * np + k] += lambda * a0[k * np + k].max(floor);
    }
    let mut step: Vec<f64> = g.iter().map(|v| -v).collect();
    solve_in_place(&mut a, &mut step, np)?;
    Some(stepped(theta, &step, free))
}

/// The undamped Gauss–Newton step: solve A δ = −g in the scaled parameters and step `theta`
/// by δ·scale, each value kept inside its range; None when A is singular.
pub(crate) fn newton_trial(a: &[f64], g: &[f64], theta: &[f64], free: &[Free]) -> Option<Vec<f64>> {
    let mut step: Vec<f64> = g.iter().map(|v| -v).collect();
    let mut m = a.to_vec();
    solve_in_place(&mut m, &mut step, free.len())?;
    Some(stepped(theta, &step, free))
}

/// A trial that [`Lm::step`] accepted.
pub(crate) struct Accepted<T> {
    /// Its parameters, as stepped (each inside its range).
    pub(crate) theta: Vec<f64>,
    /// The model with them.
    pub(crate) model: Model,
    /// Its objective.
    pub(crate) objective: f64,
    /// What the evaluation returned besides the objective.
    pub(crate) extra: T,
    /// It lowered the objective by less than the tolerance: the fit has converged.
    pub(crate) converged: bool,
}

/// Levenberg–Marquardt: its damping, carried from step to step, and its settings.
pub(crate) struct Lm {
    lambda: f64,
    /// Trials per step before giving up.
    tries: usize,
    /// The tolerance relative to the objective ([`Lm::tolerance`]).
    relative: f64,
}

impl Lm {
    /// A fit that tries at most `tries` damped steps per step, and converges when a step
    /// lowers the objective by less than [`FIT_TOL`] or `relative` × the objective.
    pub(crate) fn new(tries: usize, relative: f64) -> Self {
        Self {
            lambda: LAMBDA_START,
            tries,
            relative,
        }
    }

    /// The least decrease of `objective` worth a step.
    pub(crate) fn tolerance(&self, objective: f64) -> f64 {
        FIT_TOL.max(self.relative * objective)
    }

    /// One step from `theta` (the free parameters' values in `model`, whose objective is
    /// `objective`) on the normal equations `(a0, g)` of the objective in the scaled
    /// parameters. Each trial's parameters are set into a copy of `model`, and
    /// `evaluate(&trial_model, &trial_theta)` returns its objective and whatever the caller
    /// keeps of that evaluation; the first trial whose objective is finite and lower is
    /// accepted.
    ///
    /// None — the fit stops — when a full Gauss–Newton step could not gain the tolerance,
    /// when the ranges clamp the step to no move (the parameters that would move are at their
    /// bounds, and a shorter step stops there too: an actuator lag fitted to its least τ flew
    /// eight trials a window for nothing), or when no trial lowers the objective.
    pub(crate) fn step<T>(
        &mut self,
        model: &Model,
        free: &[Free],
        theta: &[f64],
        (a0, g): (&[f64], &[f64]),
        objective: f64,
        mut evaluate: impl FnMut(&Model, &[f64]) -> (f64, T),
    ) -> Option<Accepted<T>> {
        if newton_gain(a0, g).is_some_and(|v| v < self.tolerance(objective)) {
            return None;
        }
        for _ in 0..self.tries {
            let Some(trial) = damped_trial(a0, g, self.lambda, theta, free) else {
                self.lambda *= 10.0;
                continue;
            };
            if trial == theta {
                return None;
            }
            let mut m = model.clone();
            set_values(&mut m, free, &trial);
            let (value, extra) = evaluate(&m, &trial);
            if value.is_finite() && value < objective {
                self.lambda = (self.lambda / 10.0).max(LAMBDA_MIN);
                return Some(Accepted {
                    converged: objective - value < self.tolerance(value),
                    theta: trial,
                    model: m,
                    objective: value,
                    extra,
                });
            }
            self.lambda *= 10.0;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::free::{aircraft_free, values};
    use wireflight_data::VehicleKind;
    use wireflight_flight::effects::Origin;
    use wireflight_flight::spec::ModelSpec;

    /// On a quadratic objective in one number the first step lands near its minimum; a
    /// minimum beyond the range is stopped at the bound, where the next step gives up.
    #[test]
    fn a_step_goes_to_the_minimum_and_stops_at_a_bound() {
        let model = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let free = aircraft_free(&model, &["mass_kg"]).unwrap();
        let f = free[0];
        let theta = values(&model, &free);
        // r = (θ − target)/scale: in scaled units A = 1, g = r.
        let run = |target: f64, model: &Model, theta: &[f64], lm: &mut Lm| {
            let r = (theta[0] - target) / f.scale;
            lm.step(model, &free, theta, (&[1.0], &[r]), r * r, |m, t| {
                let v = values(m, &free)[0];
                assert_eq!(v, t[0]);
                (((v - target) / f.scale).powi(2), ())
            })
        };
        let mut lm = Lm::new(8, 1e-6);
        let target = theta[0] + 0.5 * f.scale;
        let step = run(target, &model, &theta, &mut lm).expect("a step");
        assert!(
            (step.theta[0] - target).abs() < 1e-2 * f.scale,
            "{}",
            step.theta[0]
        );
        assert!(step.objective < 1e-4);

        let mut lm = Lm::new(8, 1e-6);
        let beyond = f.range.1 + f.scale;
        let at_bound = run(beyond, &model, &[f.range.1 - 0.1 * f.scale], &mut lm).unwrap();
        assert_eq!(at_bound.theta, [f.range.1]);
        assert!(run(beyond, &at_bound.model, &at_bound.theta, &mut lm).is_none());
    }
}
