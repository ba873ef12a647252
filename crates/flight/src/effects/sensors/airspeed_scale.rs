//! `airspeed_scale`: the airspeed sensor reads the true airspeed times a factor (a pitot
//! position error or a mis-calibrated pressure sensor).

use super::super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec, Reading,
};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "airspeed_scale",
    summary: "the airspeed sensor reads the true airspeed times a factor",
    applies: Applies::FixedWing,
    params: &[ParamSpec {
        absent: Some(1.0),
        start: Some(1.0),
        ..ParamSpec::new("factor", "", (0.5, 1.5), 0.01)
    }],
    make: |_: &EffectContext| Box::new(AirspeedScale { factor: 1.0 }),
};

/// `airspeed_scale`: airspeed read = factor × true airspeed.
#[derive(Clone, Debug, PartialEq)]
pub struct AirspeedScale {
    /// The factor.
    pub factor: f64,
}

impl Effect for AirspeedScale {
    effect_basics! {
        info: INFO,
        values: factor,
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
        r.airspeed *= self.factor;
    }
}
