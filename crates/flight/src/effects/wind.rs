//! `wind`: steady wind W in NED. Air-relative velocity = velocity − W (fixed wing: body
//! velocity − Rᵀ·W). For a point mass it matters only together with `drag`.

use glam::DVec3;

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec};

/// Largest wind component accepted, m/s (a jet stream is ~100 m/s).
const MAX_WIND: f64 = 200.0;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "wind",
    summary: "steady wind in NED",
    applies: Applies::Both,
    params: &[
        ParamSpec {
            absent: Some(0.0),
            ..ParamSpec::new("north_mps", "m/s", (-MAX_WIND, MAX_WIND), 1.0)
        },
        ParamSpec {
            absent: Some(0.0),
            ..ParamSpec::new("east_mps", "m/s", (-MAX_WIND, MAX_WIND), 1.0)
        },
        ParamSpec {
            absent: Some(0.0),
            ..ParamSpec::new("down_mps", "m/s", (-MAX_WIND, MAX_WIND), 1.0)
        },
    ],
    make: |_: &EffectContext| Box::new(Wind::default()),
};

/// `wind`: steady wind W in NED.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Wind {
    /// W, NED, m/s.
    pub ned: DVec3,
}

impl Effect for Wind {
    effect_basics! {
        info: INFO,
        values: ned,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_uniform_wind(&self) -> bool {
        true
    }
    fn wind_at(&self, _pos_ned: DVec3, _t: f64) -> DVec3 {
        self.ned
    }
}
