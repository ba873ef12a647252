//! The one boundary between the angles people type and read and the viewer's math.
//!
//! Every attitude angle a person gives (`render --yaw/--pitch/--roll`, `view --gimbal-angles`)
//! or reads (the window's HUD, frame captions, flight data) is **aerospace**: +yaw turns the
//! nose right, +pitch raises it, +roll lowers the right wing (world north-east-down, body
//! forward-right-down). Inside, the viewer works in its own right-handed Z-up frame with
//! `R = Rz(ψ)·Ry(θ)·Rx(φ)` about nose +X, left wing +Y, rudder +Z, where +yaw turns the nose
//! left and +pitch lowers it. The two differ by the half-turn `D = diag(1, −1, −1)` about the
//! nose: `R_viewer = D·R_aero·D`, i.e. `(ψ, θ, φ)_viewer = (−ψ, −θ, φ)_aero`
//! ([`EulerZyx::from_aerospace`]). These functions are the only place that crossing is made.
//!
//! Pure: no I/O.

use glam::DMat3;
use wireflight_geometry::euler::EulerZyx;

/// The viewer's attitude from aerospace yaw, pitch and roll in degrees (+yaw nose right,
/// +pitch nose up, +roll right wing down).
pub fn from_aerospace_degrees(yaw_deg: f64, pitch_deg: f64, roll_deg: f64) -> EulerZyx {
    EulerZyx::from_aerospace(EulerZyx::from_degrees(yaw_deg, pitch_deg, roll_deg))
}

/// Aerospace `[yaw, pitch, roll]` in degrees of a viewer attitude (−0 shown as 0); the inverse
/// of [`from_aerospace_degrees`].
pub fn aerospace_degrees(attitude: EulerZyx) -> [f64; 3] {
    attitude.to_aerospace().to_degrees().map(|a| a + 0.0)
}

/// The half-turn about the nose between the viewer's frames and the aerospace ones,
/// `D = diag(1, −1, −1)` (its own inverse).
pub const D: DMat3 = DMat3::from_diagonal(glam::DVec3::new(1.0, -1.0, -1.0));

/// A body → world rotation in the viewer's frames from one in the aerospace frames (NED world,
/// FRD body): `D·R·D`. Its own inverse, so it also maps a viewer rotation to the aerospace one.
pub fn viewer_from_aerospace(r: DMat3) -> DMat3 {
    D * r * D
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// The signs people expect, checked on the body axes the rotation moves: nose +X, left
    /// wing +Y, up +Z in the viewer's world (Z up).
    #[test]
    fn aerospace_signs_move_the_nose_and_wings_the_expected_way() {
        let nose = |y, p, r| from_aerospace_degrees(y, p, r).to_matrix() * DVec3::X;
        let right_wing = |y, p, r| from_aerospace_degrees(y, p, r).to_matrix() * -DVec3::Y;
        // +pitch: nose up (+Z).
        assert!(nose(0.0, 20.0, 0.0).z > 0.3);
        // +yaw: nose right, i.e. toward the right wing's side (−Y, east).
        assert!(nose(30.0, 0.0, 0.0).y < -0.4);
        // +roll: right wing down.
        assert!(right_wing(0.0, 0.0, 30.0).z < -0.4);
    }

    #[test]
    fn degrees_round_trip_and_match_the_matrix_map() {
        for [y, p, r] in [
            [0.0, 0.0, 0.0],
            [60.0, 89.0, 0.0],
            [-120.0, -30.0, 45.0],
            [10.0, 20.0, -170.0],
        ] {
            let a = from_aerospace_degrees(y, p, r);
            let back = aerospace_degrees(a);
            for (x, want) in back.iter().zip([y, p, r]) {
                assert!((x - want).abs() < 1e-9, "{back:?} vs {y} {p} {r}");
            }
            let aero = EulerZyx::from_degrees(y, p, r).to_matrix();
            assert!(viewer_from_aerospace(aero).abs_diff_eq(a.to_matrix(), 1e-12));
        }
    }
}
