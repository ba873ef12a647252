//! `earth_curvature`: gravity's direction follows the sphere: an extra horizontal
//! acceleration (−g·north/R, −g·east/R, 0), R = 6 371 km.

use glam::DVec3;

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, Sample};

/// Radius of the spherical Earth of `earth_curvature`, m.
pub const EARTH_RADIUS: f64 = 6_371_000.0;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "earth_curvature",
    summary: "gravity turning with the sphere: −g·(n, e)/R",
    applies: Applies::Both,
    params: &[],
    make: |_: &EffectContext| Box::new(EarthCurvature),
};

/// `earth_curvature`: gravity follows the sphere: (−g·n/R, −g·e/R, 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EarthCurvature;

impl Effect for EarthCurvature {
    effect_basics! {
        info: INFO,
        varies_in_time: false,
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        DVec3::new(
            -s.g * s.pos_ned.x / EARTH_RADIUS,
            -s.g * s.pos_ned.y / EARTH_RADIUS,
            0.0,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use wireflight_data::G0;

    #[test]
    fn curvature_pulls_back_toward_the_origin() {
        let s = Sample {
            pos_ned: DVec3::new(6371.0, -637.1, 5.0),
            ..sample()
        };
        let a = EarthCurvature.accel_ned(&s);
        assert!((a - DVec3::new(-1e-3 * G0, 1e-4 * G0, 0.0)).length() < 1e-12);
    }
}
