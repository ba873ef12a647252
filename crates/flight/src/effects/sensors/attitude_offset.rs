//! `attitude_offset`: the attitude reference is mounted (or aligned) at a fixed roll and
//! pitch to the body axes, so it reads R·R₀ for the body's R, R₀ = Ry(pitch₀)·Rx(roll₀): in
//! level flight roll and pitch read high by the offsets.

use glam::{DMat3, DQuat};

use super::super::{
    effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec, Reading,
};

/// Largest misalignment accepted, degrees.
const MAX_OFFSET: f64 = 15.0;

const fn axis(name: &'static str) -> ParamSpec {
    ParamSpec {
        absent: Some(0.0),
        ..ParamSpec::new(name, "deg", (-MAX_OFFSET, MAX_OFFSET), 0.1)
    }
}

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "attitude_offset",
    summary: "the attitude reference misaligned in roll and pitch",
    applies: Applies::FixedWing,
    params: &[axis("roll_deg"), axis("pitch_deg")],
    make: |_: &EffectContext| Box::new(AttitudeOffset::default()),
};

/// `attitude_offset`: the attitude read is the body's rotated by a fixed roll and pitch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AttitudeOffset {
    /// Roll and pitch of the misalignment, degrees.
    pub deg: [f64; 2],
}

impl AttitudeOffset {
    /// R₀ as a quaternion, body → reference frame.
    fn rotation(&self) -> DQuat {
        let [roll, pitch] = self.deg.map(f64::to_radians);
        DQuat::from_mat3(&(DMat3::from_rotation_y(pitch) * DMat3::from_rotation_x(roll)))
    }
}

impl Effect for AttitudeOffset {
    effect_basics! {
        info: INFO,
        values: deg,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_measurement(&self) -> bool {
        true
    }
    fn channels(&self) -> &'static [Channel] {
        &[Channel::Attitude]
    }
    fn measure(&self, r: &mut Reading) {
        if self.deg != [0.0; 2] {
            r.quat = (r.quat * self.rotation()).normalize();
        }
    }
}
