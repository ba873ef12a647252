//! `gyro_bias`: constant offsets of the measured body rates.

use glam::DVec3;

use super::super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec, Reading,
};

/// Largest bias accepted, °/s (a MEMS gyro's turn-on bias is a fraction of this).
const MAX_BIAS: f64 = 20.0;

const fn axis(name: &'static str) -> ParamSpec {
    ParamSpec {
        absent: Some(0.0),
        ..ParamSpec::new(name, "deg/s", (-MAX_BIAS, MAX_BIAS), 0.1)
    }
}

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "gyro_bias",
    summary: "constant offsets of the measured body rates",
    applies: Applies::FixedWing,
    params: &[axis("p_dps"), axis("q_dps"), axis("r_dps")],
    make: |_: &EffectContext| Box::new(GyroBias::default()),
};

/// `gyro_bias`: the gyros read p, q, r plus a constant offset.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GyroBias {
    /// The offsets of p, q, r, °/s (the unit people quote a gyro's bias in).
    pub dps: DVec3,
}

impl Effect for GyroBias {
    effect_basics! {
        info: INFO,
        values: dps,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_measurement(&self) -> bool {
        true
    }
    fn channels(&self) -> &'static [Channel] {
        &[Channel::Rates]
    }
    fn measure(&self, r: &mut Reading) {
        r.rates += self.dps * std::f64::consts::PI / 180.0;
    }
}
