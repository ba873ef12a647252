//! `earth_rotation`: Coriolis acceleration −2 Ω×v with Ω = 7.292115e-5 rad/s·(cosλ, 0, −sinλ)
//! in NED (the centrifugal part is inside `gravity_model`).

use glam::DVec3;

use super::gravity_model::LATITUDE;
use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, Sample};

/// Earth's rotation rate, rad/s.
pub const EARTH_RATE: f64 = 7.292115e-5;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "earth_rotation",
    summary: "Coriolis −2Ω×v at the origin's latitude",
    applies: Applies::Both,
    params: &[LATITUDE],
    make: |ctx: &EffectContext| {
        Box::new(EarthRotation {
            latitude_deg: ctx.origin.latitude_deg.clamp(-90.0, 90.0),
        })
    },
};

/// Earth's rotation vector in NED at latitude `lat_deg`: Ω·(cos λ, 0, −sin λ), rad/s.
pub fn earth_rotation_ned(lat_deg: f64) -> DVec3 {
    let (s, c) = lat_deg.to_radians().sin_cos();
    EARTH_RATE * DVec3::new(c, 0.0, -s)
}

/// `earth_rotation`: Coriolis acceleration −2 Ω×v.
#[derive(Clone, Debug, PartialEq)]
pub struct EarthRotation {
    /// Latitude, degrees.
    pub latitude_deg: f64,
}

impl Effect for EarthRotation {
    effect_basics! {
        info: INFO,
        values: latitude_deg,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        -2.0 * earth_rotation_ned(self.latitude_deg).cross(s.vel_ned)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;

    #[test]
    fn coriolis_at_45n_deflects_northward_motion_east() {
        let e = EarthRotation { latitude_deg: 45.0 };
        let s = Sample {
            vel_ned: DVec3::new(100.0, 0.0, 0.0),
            ..sample()
        };
        let a = e.accel_ned(&s);
        // Ω×v = ω(0, −100 sin45, 0) for v = 100 north, so a = −2Ω×v = (0, 200ω sin45, 0).
        let expected = 2.0 * EARTH_RATE * 100.0 * 45f64.to_radians().sin();
        assert!(a.x.abs() < 1e-15 && a.z.abs() < 1e-15);
        assert!((a.y - expected).abs() < 1e-12, "{a} vs {expected}");
        assert!((expected - 1.0312e-2).abs() < 1e-5); // ≈ 0.0103 m/s², eastward (right)
                                                      // Eastward motion at 45°N: deflected south and up (Eötvös).
        let s = Sample {
            vel_ned: DVec3::new(0.0, 100.0, 0.0),
            ..sample()
        };
        let a = e.accel_ned(&s);
        assert!(a.x < 0.0 && a.z < 0.0, "{a}");
    }
}
