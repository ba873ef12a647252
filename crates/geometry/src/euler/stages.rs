//! What the three angles do, one at a time: the elementary rotations of a convention in the
//! order they turn the body ([`EulerAngles::steps`]), the freedom left at gimbal lock
//! ([`EulerAngles::lock_coupling`], [`EulerAngles::lock_twin`]), and linear interpolation of
//! the angles against quaternion slerp ([`lerp`], [`slerp`], [`compare_paths`]).
//!
//! These are the stages the `wireflight euler` pictures are drawn from. Pure math: no I/O.

use glam::{DMat3, DQuat, DVec3};

use super::convert::EulerAngles;
use super::sequence::{Axis, Frame};

/// One elementary rotation of a convention, as it turns the body.
///
/// Whatever the frame, `after = rotation(axis_world, angle) · before`: for intrinsic a-b-c the
/// k-th rotation is about the body's k-th axis as the earlier rotations left it
/// (`axis_world = before · ê_k`); for extrinsic a-b-c it is about the fixed world axis
/// (`axis_world = ê_k`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// Which angle turns: 0, 1 or 2 (α, β or γ, in the order the convention gives them).
    pub slot: usize,
    /// The axis named in the sequence (x, y or z).
    pub axis: Axis,
    /// The angle turned, radians.
    pub angle: f64,
    /// The rotation axis in world coordinates at the time of this rotation (unit).
    pub axis_world: DVec3,
    /// Body → world rotation before this step.
    pub before: DMat3,
    /// Body → world rotation after it.
    pub after: DMat3,
}

impl Step {
    /// The attitude part-way through this step: `fraction` 0 is [`before`](Self::before), 1 is
    /// [`after`](Self::after) (up to rounding), turning about [`axis_world`](Self::axis_world)
    /// at a constant rate.
    pub fn partial(&self, fraction: f64) -> DMat3 {
        DMat3::from_axis_angle(self.axis_world, fraction * self.angle) * self.before
    }
}

/// Angles at gimbal lock, and what is left of them: the rotation depends only on
/// `α + coupling·γ` (intrinsic reading), so the first and third rotations turn the body about
/// one and the same world axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockedPair {
    /// ±1: turning the third angle by `d` is turning the first by `coupling·d`.
    pub coupling: f64,
    /// The world axis both turn about (unit): the first axis of the intrinsic reading.
    pub axis_world: DVec3,
}

impl EulerAngles {
    /// The three elementary rotations in the order they turn the body (module docs of
    /// [`Step`]): for intrinsic z-y-x (yaw, pitch, roll) the yaw about Z, then the pitch about
    /// the yawed Y, then the roll about the yawed and pitched X. `steps()[2].after` is
    /// [`to_matrix`](Self::to_matrix) up to rounding (the products differ in grouping).
    pub fn steps(self) -> [Step; 3] {
        let axes = self.convention.sequence.axes();
        let mut before = DMat3::IDENTITY;
        std::array::from_fn(|slot| {
            let axis = axes[slot];
            let angle = self.angles[slot];
            let (axis_world, after) = match self.convention.frame {
                Frame::Intrinsic => (before * axis.unit(), before * axis.rotation(angle)),
                Frame::Extrinsic => (axis.unit(), axis.rotation(angle) * before),
            };
            let step = Step {
                slot,
                axis,
                angle,
                axis_world,
                before,
                after,
            };
            before = after;
            step
        })
    }

    /// At gimbal lock ([`lock`](Self::lock) is not `Free`): the coupling of the first and third
    /// angles and the axis they share. `None` away from lock.
    ///
    /// In the intrinsic reading a-b-c the rotation is then `R_a(α + k·γ)·R_b(β)` with
    /// k = ε·sin β for Tait–Bryan (ε the parity) and k = cos β for proper Euler: the third axis,
    /// turned by `R_a(α)·R_b(β)`, lies along ±a. For an extrinsic convention the roles of the
    /// first and third angle swap (it is the intrinsic reading with the angles reversed).
    pub fn lock_coupling(self) -> Option<LockedPair> {
        if !self.lock().is_locked() {
            return None;
        }
        let intrinsic = self.convention.as_intrinsic();
        let (sin_b, cos_b) = self.angles[1].sin_cos();
        let k = if intrinsic.sequence.is_tait_bryan() {
            intrinsic.sequence.parity() * sin_b
        } else {
            cos_b
        };
        Some(LockedPair {
            coupling: k.signum(),
            axis_world: intrinsic.sequence.axes()[0].unit(),
        })
    }

    /// Other angles with the same rotation, at gimbal lock: the first angle of the intrinsic
    /// reading moved by `shift` radians and the third by `−coupling·shift` (for an extrinsic
    /// convention: the third angle moved by `shift`, the first by `−coupling·shift`). `None`
    /// away from lock, where no other angles in range give the same rotation this way.
    pub fn lock_twin(self, shift: f64) -> Option<EulerAngles> {
        let pair = self.lock_coupling()?;
        let (first, third) = match self.convention.frame {
            Frame::Intrinsic => (0, 2),
            Frame::Extrinsic => (2, 0),
        };
        let mut angles = self.angles;
        angles[first] += shift;
        angles[third] -= pair.coupling * shift;
        Some(EulerAngles::new(self.convention, angles))
    }
}

/// Linear interpolation of the three angles, `a + t·(b − a)` each, in `a`'s convention (`b`'s
/// angles are taken as numbers in that convention: convert first when they are not). The
/// angles are interpolated as given, without wrapping: from 170° to −170° goes the long way
/// through 0°, as a naive interpolator would.
pub fn lerp(a: EulerAngles, b: EulerAngles, t: f64) -> EulerAngles {
    let angles = std::array::from_fn(|i| a.angles[i] + t * (b.angles[i] - a.angles[i]));
    EulerAngles::new(a.convention, angles)
}

/// Spherical linear interpolation between the two attitudes, along the shorter great arc of
/// the unit quaternions (a constant rotation rate about one fixed axis). At exactly half a turn
/// apart both arcs are equally short and glam picks one.
pub fn slerp(a: EulerAngles, b: EulerAngles, t: f64) -> DQuat {
    a.to_quat().slerp(b.to_quat(), t)
}

/// The angle of the rotation taking attitude `a` to attitude `b`, radians in [0, π]: twice the
/// angle between the quaternions, computed with `atan2` so that small angles keep their digits.
pub fn rotation_between(a: DQuat, b: DQuat) -> f64 {
    let d = a.conjugate() * b;
    2.0 * d.xyz().length().atan2(d.w.abs())
}

/// How the two interpolations of [`compare_paths`] differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathComparison {
    /// Largest angle between the Euler-lerp attitude and the slerp attitude at the same `t`,
    /// radians.
    pub max_deviation: f64,
    /// The `t` where that happens.
    pub at: f64,
    /// Total rotation along the Euler-lerp path (sum of the angles between successive
    /// samples), radians: at least the slerp's, more when the path wobbles.
    pub lerp_turn: f64,
    /// Total rotation along the slerp path: the angle between the end attitudes.
    pub slerp_turn: f64,
}

/// Sample both interpolations from `a` to `b` at `samples + 1` evenly spaced `t` (at least 2
/// intervals) and compare them.
pub fn compare_paths(a: EulerAngles, b: EulerAngles, samples: usize) -> PathComparison {
    let n = samples.max(2);
    let mut result = PathComparison {
        max_deviation: 0.0,
        at: 0.0,
        lerp_turn: 0.0,
        slerp_turn: rotation_between(a.to_quat(), b.to_quat()),
    };
    let mut previous = a.to_quat();
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let euler = lerp(a, b, t).to_quat();
        let deviation = rotation_between(euler, slerp(a, b, t));
        if deviation > result.max_deviation {
            result.max_deviation = deviation;
            result.at = t;
        }
        result.lerp_turn += rotation_between(previous, euler);
        previous = euler;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::euler::Convention;

    fn deg(c: &str, a: [f64; 3]) -> EulerAngles {
        EulerAngles::from_degrees(c.parse().unwrap(), a)
    }

    #[test]
    fn zyx_steps_are_yaw_then_pitch_about_the_yawed_y_then_roll_about_the_nose() {
        let e = deg("zyx", [30.0, 60.0, 45.0]);
        let [yaw, pitch, roll] = e.steps();
        assert_eq!(yaw.before, DMat3::IDENTITY);
        assert!(yaw.axis_world.abs_diff_eq(DVec3::Z, 1e-15));
        // Pitch turns about the wing axis after the yaw: Rz(30°)·ŷ.
        let wing = Axis::Z.rotation(30f64.to_radians()) * DVec3::Y;
        assert!(pitch.axis_world.abs_diff_eq(wing, 1e-15));
        // Roll turns about the nose as yaw and pitch left it.
        assert!(roll.axis_world.abs_diff_eq(pitch.after * DVec3::X, 1e-15));
        assert!(roll.after.abs_diff_eq(e.to_matrix(), 1e-15));
        for s in e.steps() {
            assert!(s.partial(1.0).abs_diff_eq(s.after, 1e-15));
            assert!(s.partial(0.0).abs_diff_eq(s.before, 1e-15));
        }
    }

    #[test]
    fn every_convention_ends_at_its_matrix_and_extrinsic_axes_are_fixed() {
        for c in Convention::ALL {
            let e = EulerAngles::new(c, [0.4, -1.1, 2.5]);
            let steps = e.steps();
            assert!(steps[2].after.abs_diff_eq(e.to_matrix(), 1e-14), "{c}");
            for (k, s) in steps.iter().enumerate() {
                assert_eq!(s.axis, c.sequence.axes()[k]);
                if c.frame == Frame::Extrinsic {
                    assert_eq!(s.axis_world, s.axis.unit());
                }
                // The axis is the rotation's: it stays put.
                let turn = s.after * s.before.transpose();
                assert!(
                    (turn * s.axis_world).abs_diff_eq(s.axis_world, 1e-14),
                    "{c}"
                );
            }
        }
    }

    #[test]
    fn lock_twins_have_the_same_matrix_and_turn_about_one_axis() {
        for c in Convention::ALL {
            let locks: &[f64] = if c.sequence.is_tait_bryan() {
                &[90.0, -90.0]
            } else {
                &[0.0, 180.0]
            };
            for &beta in locks {
                let e = deg(&c.to_string(), [50.0, beta, -20.0]);
                let pair = e.lock_coupling().expect("at lock");
                let twin = e.lock_twin(0.7).unwrap();
                assert_ne!(twin.angles, e.angles);
                assert!(
                    twin.to_matrix().abs_diff_eq(e.to_matrix(), 1e-14),
                    "{c} β = {beta}"
                );
                // The first and third rotations of the intrinsic reading turn about one axis.
                let intrinsic = if c.frame == Frame::Intrinsic {
                    e
                } else {
                    e.other_frame()
                };
                let [first, _, third] = intrinsic.steps();
                assert!(first.axis_world.abs_diff_eq(pair.axis_world, 1e-15));
                let along = third.axis_world.dot(pair.axis_world);
                assert!((along.abs() - 1.0).abs() < 1e-14, "{c} β = {beta}");
            }
            assert_eq!(
                deg(&c.to_string(), [50.0, 45.0, -20.0]).lock_twin(0.7),
                None
            );
        }
    }

    #[test]
    fn zyx_lock_nose_down_couples_yaw_minus_roll() {
        // θ = +90°: R = Rz(ψ − φ)·Ry(90°), so (60°, 90°, 0°) = (0°, 90°, −60°).
        let e = deg("zyx", [60.0, 90.0, 0.0]);
        assert_eq!(e.lock_coupling().unwrap().coupling, -1.0);
        let twin = e.lock_twin(-60f64.to_radians()).unwrap();
        let expected = [0.0, 90.0, -60.0];
        for (got, want) in twin.to_degrees().into_iter().zip(expected) {
            assert!((got - want).abs() < 1e-12, "{:?}", twin.to_degrees());
        }
    }

    #[test]
    fn lerp_wobbles_where_slerp_does_not() {
        let a = deg("zyx", [0.0, 0.0, 0.0]);
        let b = deg("zyx", [90.0, 60.0, 90.0]);
        let p = compare_paths(a, b, 64);
        assert!(p.max_deviation > 5f64.to_radians(), "{p:?}");
        assert!(p.lerp_turn > p.slerp_turn * 1.01, "{p:?}");
        // The ends agree.
        assert!(rotation_between(lerp(a, b, 1.0).to_quat(), slerp(a, b, 1.0)) < 1e-12);
        // One angle at a time: the Euler path is the slerp path.
        let c = deg("zyx", [0.0, 70.0, 0.0]);
        let p = compare_paths(a, c, 64);
        assert!(p.max_deviation < 1e-12, "{p:?}");
        assert!((p.lerp_turn - p.slerp_turn).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn rotation_between_is_the_angle_of_the_relative_rotation() {
        let a = deg("zyx", [10.0, 20.0, 30.0]).to_quat();
        let turn = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 2.0).normalize(), 0.3);
        assert!((rotation_between(a, a * turn) - 0.3).abs() < 1e-14);
        assert!((rotation_between(a, -(a * turn)) - 0.3).abs() < 1e-14);
        assert!(rotation_between(a, a) < 1e-15);
    }
}
