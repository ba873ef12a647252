//! `airspeed_bias`: the airspeed sensor reads a constant offset from the true airspeed (a
//! pressure sensor's zero that drifted).

use super::super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec, Reading,
};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "airspeed_bias",
    summary: "the airspeed sensor reads a constant offset from the true airspeed",
    applies: Applies::FixedWing,
    params: &[ParamSpec {
        absent: Some(0.0),
        ..ParamSpec::new("bias_mps", "m/s", (-20.0, 20.0), 0.2)
    }],
    make: |_: &EffectContext| Box::new(AirspeedBias { bias_mps: 0.0 }),
};

/// `airspeed_bias`: airspeed read = true airspeed + bias.
#[derive(Clone, Debug, PartialEq)]
pub struct AirspeedBias {
    /// The offset, m/s.
    pub bias_mps: f64,
}

impl Effect for AirspeedBias {
    effect_basics! {
        info: INFO,
        values: bias_mps,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_measurement(&self) -> bool {
        true
    }
    fn channels(&self) -> &'static [Channel] {
        &[Channel::Airspeed]
    }
    fn measure(&self, r: &mut Reading) {
        r.airspeed += self.bias_mps;
    }
}
