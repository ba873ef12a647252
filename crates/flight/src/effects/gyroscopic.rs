//! `gyroscopic` (fixed wing): the propeller's angular momentum h = k_gyro·δt along body x
//! adds the moment −ω × (h, 0, 0).

use glam::DVec3;

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec, Sample};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "gyroscopic",
    summary: "propeller angular momentum k·δt along body x (k_gyro)",
    applies: Applies::FixedWing,
    params: &[ParamSpec {
        absent: Some(0.0),
        scale_relative: true,
        ..ParamSpec::new("k_gyro", "kg·m²/s", (-1e6, 1e6), 0.01)
    }],
    make: |_: &EffectContext| Box::new(Gyroscopic { k_gyro: 0.0 }),
};

/// `gyroscopic` (fixed wing): moment += −ω × (k_gyro·δt, 0, 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Gyroscopic {
    /// k_gyro, kg·m²/s.
    pub k_gyro: f64,
}

impl Effect for Gyroscopic {
    effect_basics! {
        info: INFO,
        values: k_gyro,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn force_moment_body(&self, s: &Sample) -> (DVec3, DVec3) {
        let h = DVec3::new(self.k_gyro * s.controls.throttle, 0.0, 0.0);
        (DVec3::ZERO, -s.omega.cross(h))
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use wireflight_data::Controls;

    #[test]
    fn moment_is_minus_omega_cross_h() {
        let s = Sample {
            controls: Controls {
                throttle: 0.5,
                ..Controls::default()
            },
            omega: DVec3::new(0.1, 0.2, 0.3),
            ..sample()
        };
        let (_, m) = Gyroscopic { k_gyro: 4.0 }.force_moment_body(&s);
        // −ω × (2, 0, 0) = −(0, 0.3·2, −0.2·2) = (0, −0.6, 0.4)
        assert!((m - DVec3::new(0.0, -0.6, 0.4)).length() < 1e-15, "{m}");
    }
}
