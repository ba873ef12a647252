//! `incidence_lift` (point mass, from a recorded attitude): the normal force of a body at
//! incidence, a += k·q̄·(x_b − (x_b·v̂)·v̂), x_b the flight's recorded body x axis.
//!
//! A point mass flies no attitude, but a flight may record the body's: a bomb launched nose
//! above its path and oscillating about it feels a force across the path toward its nose,
//! proportional to the dynamic pressure and to the sine of its angle to the path (the
//! component of its nose normal to the air-relative velocity). The effect reads the attitude
//! of the flight the model was built for ([`super::EffectContext::recorded_attitude`]); a
//! model without one cannot carry it ([`Effect::lacks_channel`]).

use std::sync::Arc;

use glam::DVec3;

use super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec,
    RecordedAttitude, Sample,
};

/// Below this air-relative speed, m/s, the flight path has no direction to be normal to.
const MIN_AIRSPEED: f64 = 0.1;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "incidence_lift",
    summary: "k·q̄·(x_b − (x_b·v̂)v̂) from the recorded attitude, k = S·C_Nα/m (m/s² per Pa)",
    applies: Applies::PointMass,
    params: &[ParamSpec {
        // A store's S·C_Nα/m: the Mk-82's is about 1.5e-3 (0.05 m², C_Nα ≈ 7, 227 kg); a
        // light body's may be ten times that.
        absent: Some(0.0),
        start: Some(1e-3),
        ..ParamSpec::new("k", "m/s² per Pa", (0.0, 0.1), 1e-3)
    }],
    make: |ctx: &EffectContext| {
        Box::new(IncidenceLift {
            k: 1e-3,
            attitude: ctx.recorded_attitude.clone(),
        })
    },
};

/// `incidence_lift` (point mass): a += k·q̄·(x_b − (x_b·v̂)·v̂), x_b the recorded nose.
#[derive(Clone, Debug, PartialEq)]
pub struct IncidenceLift {
    /// S·C_Nα/m, m/s² per pascal of dynamic pressure and unit sine of incidence.
    pub k: f64,
    /// The flight's recorded attitude; `None`: the effect cannot act (and a model refuses it).
    pub attitude: Option<Arc<RecordedAttitude>>,
}

impl Effect for IncidenceLift {
    effect_basics! {
        info: INFO,
        values: k,
        varies_in_space: false,
    }
    fn lacks_channel(&self) -> Option<Channel> {
        self.attitude.is_none().then_some(Channel::Attitude)
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        let Some(attitude) = &self.attitude else {
            return DVec3::ZERO;
        };
        let speed = s.air_vel_ned.length();
        if self.k == 0.0 || speed < MIN_AIRSPEED {
            return DVec3::ZERO;
        }
        let along = s.air_vel_ned / speed;
        let nose = attitude.nose_at(s.t);
        let across = nose - nose.dot(along) * along;
        let qbar = 0.5 * s.rho * speed * speed;
        self.k * qbar * across
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use wireflight_geometry::euler::EulerZyx;

    /// Nose 10° above a level path at every time.
    fn pitched_up() -> Arc<RecordedAttitude> {
        let up = EulerZyx::new(0.3, 10f64.to_radians(), 0.0);
        Arc::new(RecordedAttitude::new(&[0.0, 10.0], &[up, up]).unwrap())
    }

    #[test]
    fn the_force_is_normal_to_the_path_toward_the_nose_and_scales_with_qbar() {
        let lift = IncidenceLift {
            k: 2e-3,
            attitude: Some(pitched_up()),
        };
        let heading = DVec3::new(0.3f64.cos(), 0.3f64.sin(), 0.0);
        let s = Sample {
            t: 5.0,
            air_vel_ned: 100.0 * heading,
            ..sample()
        };
        let a = lift.accel_ned(&s);
        assert!(
            a.dot(heading).abs() < 1e-12 * a.length(),
            "{a} along the path"
        );
        assert!(
            a.z < 0.0 && a.truncate().length() < 1e-12,
            "{a}: not upward"
        );
        let qbar = 0.5 * s.rho * 100.0 * 100.0;
        let want = 2e-3 * qbar * 10f64.to_radians().sin();
        assert!((a.length() - want).abs() < 1e-12 * want, "{a} vs {want}");
        let faster = Sample {
            air_vel_ned: 200.0 * heading,
            ..s
        };
        let ratio = lift.accel_ned(&faster).length() / a.length();
        assert!((ratio - 4.0).abs() < 1e-12, "{ratio}");
        // Flying backwards relative to the air, the nose is still above the path: up again.
        let back = Sample {
            air_vel_ned: -100.0 * heading,
            ..s
        };
        assert!(lift.accel_ned(&back).z < 0.0);
    }

    #[test]
    fn no_force_at_k_zero_at_rest_or_without_an_attitude() {
        let s = Sample {
            t: 1.0,
            air_vel_ned: DVec3::new(50.0, 0.0, 10.0),
            ..sample()
        };
        let zero = IncidenceLift {
            k: 0.0,
            attitude: Some(pitched_up()),
        };
        assert_eq!(zero.accel_ned(&s), DVec3::ZERO);
        let still = IncidenceLift {
            k: 1e-2,
            attitude: Some(pitched_up()),
        };
        let at_rest = Sample {
            air_vel_ned: DVec3::new(0.05, 0.0, 0.0),
            ..s
        };
        assert_eq!(still.accel_ned(&at_rest), DVec3::ZERO);
        let blind = (INFO.make)(&EffectContext::default());
        assert_eq!(blind.accel_ned(&s), DVec3::ZERO);
        assert_eq!(blind.lacks_channel(), Some(Channel::Attitude));
        assert_eq!(still.lacks_channel(), None);
    }
}
