//! `accel_bias`: constant offsets of the accelerometer's specific force, body axes.

use glam::DVec3;

use super::super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec, Reading,
};

/// Largest bias accepted, m/s² (a tenth of g is far beyond any working accelerometer's).
const MAX_BIAS: f64 = 5.0;

const fn axis(name: &'static str) -> ParamSpec {
    ParamSpec {
        absent: Some(0.0),
        ..ParamSpec::new(name, "m/s^2", (-MAX_BIAS, MAX_BIAS), 0.05)
    }
}

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "accel_bias",
    summary: "constant offsets of the accelerometer, body axes",
    applies: Applies::FixedWing,
    params: &[axis("x_mps2"), axis("y_mps2"), axis("z_mps2")],
    make: |_: &EffectContext| Box::new(AccelBias::default()),
};

/// `accel_bias`: the accelerometer reads the specific force plus a constant offset.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccelBias {
    /// The offsets along body x, y, z, m/s².
    pub mps2: DVec3,
}

impl Effect for AccelBias {
    effect_basics! {
        info: INFO,
        values: mps2,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_measurement(&self) -> bool {
        true
    }
    fn channels(&self) -> &'static [Channel] {
        &[Channel::Accelerometer]
    }
    fn measure(&self, r: &mut Reading) {
        r.specific_force += self.mps2;
    }
}
