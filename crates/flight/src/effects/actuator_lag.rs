//! `actuator_lag` (fixed wing): each control surface follows its command through a first-order
//! lag τ·ẋ = cmd − x. The surfaces are states of the model (not measured: a comparison
//! reconstructs them from the command history).

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec};

/// Shortest accepted actuator time constant, s: below this the lag is below any sample
/// interval of interest and the ODE becomes needlessly stiff.
pub const MIN_ACTUATOR_TAU: f64 = 1e-3;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "actuator_lag",
    summary: "first-order lag of each surface (tau_s)",
    applies: Applies::FixedWing,
    params: &[ParamSpec {
        scale_relative: true,
        start: Some(0.1),
        ..ParamSpec::new("tau_s", "s", (MIN_ACTUATOR_TAU, 10.0), 0.02)
    }],
    make: |_: &EffectContext| Box::new(ActuatorLag { tau_s: 0.1 }),
};

/// `actuator_lag` (fixed wing): each surface follows its command, τ·ẋ = cmd − x.
#[derive(Clone, Debug, PartialEq)]
pub struct ActuatorLag {
    /// τ, s (≥ [`MIN_ACTUATOR_TAU`]).
    pub tau_s: f64,
}

impl Effect for ActuatorLag {
    effect_basics! {
        info: INFO,
        values: tau_s,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn actuator_tau(&self) -> Option<f64> {
        Some(self.tau_s.max(MIN_ACTUATOR_TAU))
    }
}
