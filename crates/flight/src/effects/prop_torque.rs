//! `prop_torque` (fixed wing): the propeller's reaction torque as a rolling moment
//! l += −k_torque·δt².

use glam::DVec3;

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec, Sample};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "prop_torque",
    summary: "rolling moment −k·δt² (k_torque, N·m)",
    applies: Applies::FixedWing,
    params: &[ParamSpec {
        // 0.5 N·m on a small UAV, several hundred on a light aircraft.
        absent: Some(0.0),
        scale_relative: true,
        ..ParamSpec::new("k_torque", "N·m", (-1e6, 1e6), 0.1)
    }],
    make: |_: &EffectContext| Box::new(PropTorque { k_torque: 0.0 }),
};

/// `prop_torque` (fixed wing): rolling moment l += −k_torque·δt².
#[derive(Clone, Debug, PartialEq)]
pub struct PropTorque {
    /// k_torque, N·m.
    pub k_torque: f64,
}

impl Effect for PropTorque {
    effect_basics! {
        info: INFO,
        values: k_torque,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn force_moment_body(&self, s: &Sample) -> (DVec3, DVec3) {
        let dt = s.controls.throttle;
        (DVec3::ZERO, DVec3::new(-self.k_torque * dt * dt, 0.0, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use wireflight_data::Controls;

    #[test]
    fn rolling_moment_is_minus_k_throttle_squared() {
        let s = Sample {
            controls: Controls {
                throttle: 0.5,
                ..Controls::default()
            },
            ..sample()
        };
        let (f, m) = PropTorque { k_torque: 2.0 }.force_moment_body(&s);
        assert_eq!((f, m), (DVec3::ZERO, DVec3::new(-0.5, 0.0, 0.0)));
    }
}
