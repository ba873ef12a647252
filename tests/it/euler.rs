//! z-y-x Euler angles: the matrix against the product of single-axis rotations and against glam,
//! round trips (random and on a 15° grid), gimbal lock, the seed's body axes, and the aerospace
//! (NED/FRD) conversion.

use std::f64::consts::{FRAC_PI_2, PI};

use crate::support::{angle_distance, assert_close, wrap_angle, Rng};
use glam::{DMat3, DVec3, EulerRot};
use wireflight::geometry::euler::{
    ned_from_viewer, rot_x, rot_y, rot_z, viewer_from_ned, EulerZyx, Gimbal, GIMBAL_LOCK_COS,
};

/// D = diag(1, −1, −1): the half-turn about X between the viewer's frames and NED/FRD.
const D: DMat3 = DMat3::from_cols(
    DVec3::new(1.0, 0.0, 0.0),
    DVec3::new(0.0, -1.0, 0.0),
    DVec3::new(0.0, 0.0, -1.0),
);

/// Random angles, each uniform in [−lim, lim].
fn random_angles(rng: &mut Rng, yaw_lim: f64, pitch_lim: f64, roll_lim: f64) -> EulerZyx {
    EulerZyx::new(
        rng.range(-yaw_lim, yaw_lim),
        rng.range(-pitch_lim, pitch_lim),
        rng.range(-roll_lim, roll_lim),
    )
}

/// Every multiple of `step` degrees in [lo, hi] (both included).
fn grid(lo: i32, hi: i32, step: i32) -> impl Iterator<Item = f64> + Clone {
    (lo..=hi).step_by(step as usize).map(f64::from)
}

fn assert_rotation(r: DMat3, what: &str) {
    assert_close!(r.transpose() * r, DMat3::IDENTITY, 1e-12, "RᵀR for {what}");
    assert_close!(r.determinant(), 1.0, 1e-12, "det R for {what}");
}

// ---------------------------------------------------------------------------------------------
// The matrix
// ---------------------------------------------------------------------------------------------

/// `to_matrix` is Rz(ψ)·Ry(θ)·Rx(φ) and glam's `EulerRot::ZYX` (checked in glam 0.34's source:
/// intrinsic ZYX with arguments (a, b, c) is Rz(a)·Ry(b)·Rx(c)) on 10 000 random angle triples,
/// half over [−π, π]³ and half over [−4π, 4π]³.
#[test]
fn to_matrix_is_rz_ry_rx_and_glam_zyx() {
    let mut rng = Rng::new(0x0E01_E7A5);
    for i in 0..10_000 {
        let lim = if i % 2 == 0 { PI } else { 4.0 * PI };
        let e = random_angles(&mut rng, lim, lim, lim);
        let m = e.to_matrix();
        let product = rot_z(e.yaw) * rot_y(e.pitch) * rot_x(e.roll);
        assert_close!(m, product, 1e-12, "Rz·Ry·Rx at {e:?}");
        let glam_zyx = DMat3::from_euler(EulerRot::ZYX, e.yaw, e.pitch, e.roll);
        assert_close!(m, glam_zyx, 1e-12, "glam ZYX at {e:?}");
        // The same rotation read as extrinsic rotations about fixed X, then Y, then Z.
        let glam_xyz_ex = DMat3::from_euler(EulerRot::XYZEx, e.roll, e.pitch, e.yaw);
        assert_close!(m, glam_xyz_ex, 1e-12, "glam XYZEx at {e:?}");
        // The f32 copy for the pipeline.
        assert_close!(e.to_mat3().as_dmat3(), m, 1e-6, "to_mat3 at {e:?}");
        assert_rotation(m, &format!("{e:?}"));
    }
}

/// glam's own inverse agrees with `from_matrix` away from lock.
#[test]
fn from_matrix_agrees_with_glam_to_euler_away_from_lock() {
    let mut rng = Rng::new(7);
    for _ in 0..5_000 {
        let e = random_angles(&mut rng, PI, 89.0f64.to_radians(), PI);
        let (ours, gimbal) = EulerZyx::from_matrix(e.to_matrix());
        assert_eq!(gimbal, Gimbal::Free);
        let (yaw, pitch, roll) = e.to_matrix().to_euler(EulerRot::ZYX);
        assert_close!(angle_distance(ours.yaw, yaw), 0.0, 1e-9, "yaw at {e:?}");
        assert_close!(ours.pitch, pitch, 1e-9, "pitch at {e:?}");
        assert_close!(angle_distance(ours.roll, roll), 0.0, 1e-9, "roll at {e:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------------

/// Away from lock (|θ| < 89.9°, ψ, φ in the open (−180°, 180°)), angles → matrix → angles is
/// exact to 1e-9 rad, on 20 000 random triples.
#[test]
fn round_trip_angles_exact_away_from_lock() {
    let mut rng = Rng::new(0x5EED);
    let just_under_pi = PI * (1.0 - 1e-12);
    for _ in 0..20_000 {
        let e = random_angles(&mut rng, just_under_pi, 89.9f64.to_radians(), just_under_pi);
        let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
        assert_eq!(gimbal, Gimbal::Free, "{e:?}");
        assert_close!(back.yaw, e.yaw, 1e-9, "yaw of {e:?}");
        assert_close!(back.pitch, e.pitch, 1e-9, "pitch of {e:?}");
        assert_close!(back.roll, e.roll, 1e-9, "roll of {e:?}");
        assert_eq!(e.canonical().0, back);
    }
}

/// A 15° grid over all three angles, both ends of each range included (ψ, φ ∈ [−180°, 180°],
/// θ ∈ [−90°, 90°]): from_matrix always reproduces the matrix; away from lock the angles come
/// back modulo 360° (±180° are the same angle), in the documented ranges.
#[test]
fn round_trip_sweep_15_degree_grid() {
    let mut locked = 0;
    let mut free = 0;
    for yaw in grid(-180, 180, 15) {
        for pitch in grid(-90, 90, 15) {
            for roll in grid(-180, 180, 15) {
                let e = EulerZyx::from_degrees(yaw, pitch, roll);
                let r = e.to_matrix();
                let (back, gimbal) = EulerZyx::from_matrix(r);
                let ctx = format!("({yaw}°, {pitch}°, {roll}°) → {:?}", back.to_degrees());
                assert!(back.is_finite(), "{ctx}");
                assert_close!(back.to_matrix(), r, 1e-12, "matrix round trip {ctx}");
                assert!(
                    (-PI..=PI).contains(&back.yaw) && (-PI..=PI).contains(&back.roll),
                    "{ctx}"
                );
                assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&back.pitch), "{ctx}");
                if pitch.abs() == 90.0 {
                    locked += 1;
                    assert!(gimbal.is_locked(), "{ctx}: {gimbal:?}");
                    assert_eq!(back.roll, 0.0, "{ctx}");
                } else {
                    free += 1;
                    assert_eq!(gimbal, Gimbal::Free, "{ctx}");
                    assert_close!(angle_distance(back.yaw, e.yaw), 0.0, 1e-9, "yaw {ctx}");
                    assert_close!(back.pitch, e.pitch, 1e-9, "pitch {ctx}");
                    assert_close!(angle_distance(back.roll, e.roll), 0.0, 1e-9, "roll {ctx}");
                }
            }
        }
    }
    assert_eq!((locked, free), (2 * 25 * 25, 11 * 25 * 25));
}

/// Any angles at all (θ beyond ±90°, angles beyond ±360°) canonicalise to an equivalent triple.
#[test]
fn canonical_reproduces_the_matrix_for_any_angles() {
    let mut rng = Rng::new(99);
    for _ in 0..10_000 {
        let e = random_angles(&mut rng, 7.0, 7.0, 7.0);
        let (c, _) = e.canonical();
        assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&c.pitch), "{e:?} → {c:?}");
        assert_close!(c.to_matrix(), e.to_matrix(), 1e-12, "{e:?} → {c:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Gimbal lock
// ---------------------------------------------------------------------------------------------

/// At θ = ±90° exactly: the lock is reported, roll = 0, yaw = ψ ∓ φ wrapped into (−π, π], and
/// the matrix is reproduced. Swept over a 15° grid of ψ and φ.
#[test]
fn gimbal_lock_reports_and_reproduces() {
    for (pitch, expected_gimbal, sign) in [
        (90.0, Gimbal::LockedNoseDown, -1.0),
        (-90.0, Gimbal::LockedNoseUp, 1.0),
    ] {
        for yaw in grid(-180, 180, 15) {
            for roll in grid(-180, 180, 15) {
                let e = EulerZyx::from_degrees(yaw, pitch, roll);
                let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
                let ctx = format!("({yaw}°, {pitch}°, {roll}°) → {:?}", back.to_degrees());
                assert_eq!(gimbal, expected_gimbal, "{ctx}");
                assert!(gimbal.is_locked());
                assert_eq!(back.roll, 0.0, "{ctx}");
                assert_eq!(back.pitch, f64::signum(pitch) * FRAC_PI_2);
                let expected_yaw = wrap_angle(e.yaw + sign * e.roll);
                assert_close!(
                    angle_distance(back.yaw, expected_yaw),
                    0.0,
                    1e-9,
                    "yaw = ψ{}φ {ctx}",
                    if sign < 0.0 { '−' } else { '+' }
                );
                assert!((-PI..=PI).contains(&back.yaw), "{ctx}");
                assert_close!(back.to_matrix(), e.to_matrix(), 1e-12, "{ctx}");
            }
        }
    }
}

/// Just off lock (89.99°) the angles are free and round-trip; closer in, down to the lock
/// threshold, the matrix is still reproduced (the ψ/φ split is ill-conditioned there).
#[test]
fn just_off_lock_is_free_and_round_trips() {
    for pitch in [89.99, -89.99] {
        for yaw in grid(-165, 165, 15) {
            for roll in grid(-165, 165, 15) {
                let e = EulerZyx::from_degrees(yaw, pitch, roll);
                let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
                assert_eq!(gimbal, Gimbal::Free, "{e:?}");
                assert_close!(back.yaw, e.yaw, 1e-9, "yaw of {e:?}");
                assert_close!(back.pitch, e.pitch, 1e-9, "pitch of {e:?}");
                assert_close!(back.roll, e.roll, 1e-9, "roll of {e:?}");
            }
        }
    }
    // Approach the lock: 90° − 10^−k degrees.
    for k in 1..=12 {
        for sign in [1.0, -1.0] {
            let pitch = sign * (90.0 - 10f64.powi(-k));
            let e = EulerZyx::from_degrees(40.0, pitch, -25.0);
            let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
            let cos = e.pitch.cos();
            assert_eq!(
                gimbal.is_locked(),
                cos < GIMBAL_LOCK_COS,
                "pitch {pitch}°: cos θ = {cos:e}, {gimbal:?}"
            );
            // Snapping θ to ±90° (and the heading into yaw) moves the matrix by about cos θ,
            // which is below GIMBAL_LOCK_COS when locked.
            let tol = if gimbal.is_locked() {
                1e-12 + cos
            } else {
                1e-12
            };
            assert_close!(
                back.to_matrix(),
                e.to_matrix(),
                tol,
                "pitch {pitch}°, {gimbal:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Body axes (the seed's plane: nose +X, left wing +Y, rudder +Z)
// ---------------------------------------------------------------------------------------------

#[test]
fn yaw_moves_the_nose_toward_plus_y() {
    for deg in [1.0, 30.0, 90.0] {
        let nose = EulerZyx::from_degrees(deg, 0.0, 0.0).to_matrix() * DVec3::X;
        assert!(nose.y > 0.0 && nose.z == 0.0, "yaw {deg}°: {nose}");
        let rad = f64::to_radians(deg);
        assert_close!(nose, DVec3::new(rad.cos(), rad.sin(), 0.0), 1e-15);
    }
    assert_close!(rot_z(FRAC_PI_2) * DVec3::X, DVec3::Y, 1e-15);
}

#[test]
fn pitch_plus_90_sends_the_nose_to_minus_z() {
    let r = EulerZyx::from_degrees(0.0, 90.0, 0.0).to_matrix();
    assert_close!(r * DVec3::X, -DVec3::Z, 1e-15);
    // Small positive pitch: nose down a little (Z-up world).
    let nose = EulerZyx::from_degrees(0.0, 10.0, 0.0).to_matrix() * DVec3::X;
    assert!(nose.z < 0.0, "{nose}");
    // The wing axis is the pitch axis: unmoved.
    assert_close!(r * DVec3::Y, DVec3::Y, 1e-15);
}

#[test]
fn roll_moves_the_left_wing_to_plus_z() {
    let r = EulerZyx::from_degrees(0.0, 0.0, 90.0).to_matrix();
    assert_close!(r * DVec3::Y, DVec3::Z, 1e-15);
    // The rudder goes to the right wing side (−Y); the nose stays.
    assert_close!(r * DVec3::Z, -DVec3::Y, 1e-15);
    assert_close!(r * DVec3::X, DVec3::X, 1e-15);
}

/// Order of application: roll first, then pitch, then yaw (intrinsic z, y', x'').
#[test]
fn rotations_apply_roll_then_pitch_then_yaw() {
    // Yaw 90° then pitch 90° (about the yawed wing axis): the nose points straight down,
    // and the left wing, after yaw, points to −X.
    let r = EulerZyx::from_degrees(90.0, 90.0, 0.0).to_matrix();
    assert_close!(r * DVec3::X, -DVec3::Z, 1e-15);
    assert_close!(r * DVec3::Y, -DVec3::X, 1e-15);
    // Roll 90° then yaw 90°: the left wing, rolled up to +Z, stays up under yaw.
    let r = EulerZyx::from_degrees(90.0, 0.0, 90.0).to_matrix();
    assert_close!(r * DVec3::Y, DVec3::Z, 1e-15);
    assert_close!(r * DVec3::X, DVec3::Y, 1e-15);
}

#[test]
fn rotation_is_orthonormal_with_det_1_on_a_grid() {
    for yaw in grid(-180, 180, 15) {
        for pitch in grid(-90, 90, 15) {
            for roll in grid(-180, 180, 15) {
                let r = EulerZyx::from_degrees(yaw, pitch, roll).to_matrix();
                assert_rotation(r, &format!("({yaw}°, {pitch}°, {roll}°)"));
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Aerospace frames (world NED, body FRD)
// ---------------------------------------------------------------------------------------------

/// D·R_ned·D == R_viewer(from_aerospace(ned)), and a body vector mapped both ways agrees:
/// R_viewer·(D b) == D·(R_ned·b). Also the conversions are inverses.
#[test]
fn aerospace_conversion_is_conjugation_by_d() {
    let mut rng = Rng::new(0xAE20);
    for _ in 0..5_000 {
        let ned = random_angles(&mut rng, PI, FRAC_PI_2, PI);
        let r_ned = ned.to_matrix();
        let viewer = EulerZyx::from_aerospace(ned);
        let r_viewer = viewer.to_matrix();
        assert_close!(D * r_ned * D, r_viewer, 1e-12, "ned {ned:?}");
        assert_eq!(viewer.to_aerospace(), ned);
        assert_eq!(EulerZyx::from_aerospace(viewer.to_aerospace()), viewer);

        let b = DVec3::new(
            rng.range(-10.0, 10.0),
            rng.range(-10.0, 10.0),
            rng.range(-10.0, 10.0),
        );
        let world_ned = r_ned * b;
        assert_close!(
            r_viewer * (D * b),
            D * world_ned,
            1e-11,
            "b {b}, ned {ned:?}"
        );
        assert_close!(
            r_viewer * viewer_from_ned(b),
            viewer_from_ned(world_ned),
            1e-11,
            "via viewer_from_ned"
        );
        assert_eq!(viewer_from_ned(b), D * b);
        assert_eq!(ned_from_viewer(viewer_from_ned(b)), b);
        assert_eq!(viewer_from_ned(ned_from_viewer(b)), b);
    }
}

/// Heading 90° (east) in NED: the nose points east, which is viewer −Y (west is +Y).
#[test]
fn ned_heading_east_points_the_nose_to_viewer_minus_y() {
    let ned = EulerZyx::from_degrees(90.0, 0.0, 0.0);
    assert_close!(
        ned.to_matrix() * DVec3::X,
        DVec3::Y,
        1e-15,
        "NED: east is +Y"
    );
    let nose = EulerZyx::from_aerospace(ned).to_matrix() * DVec3::X;
    assert_close!(nose, -DVec3::Y, 1e-15);
    assert_close!(viewer_from_ned(DVec3::Y), -DVec3::Y, 0.0);
    // West (heading −90°) is viewer +Y.
    let nose =
        EulerZyx::from_aerospace(EulerZyx::from_degrees(-90.0, 0.0, 0.0)).to_matrix() * DVec3::X;
    assert_close!(nose, DVec3::Y, 1e-15);
}

/// Nose-up pitch in NED (θ > 0) points the nose toward viewer +Z (up).
#[test]
fn ned_nose_up_points_the_nose_to_viewer_plus_z() {
    for deg in [5.0, 30.0, 60.0, 89.0] {
        let ned = EulerZyx::from_degrees(0.0, deg, 0.0);
        let nose_ned = ned.to_matrix() * DVec3::X;
        assert!(nose_ned.z < 0.0, "NED up is −Z: {nose_ned}");
        let nose = EulerZyx::from_aerospace(ned).to_matrix() * DVec3::X;
        let rad = f64::to_radians(deg);
        assert_close!(nose, DVec3::new(rad.cos(), 0.0, rad.sin()), 1e-15, "{deg}°");
        assert_close!(nose, viewer_from_ned(nose_ned), 1e-15);
    }
    // Right-wing-down roll in NED (φ > 0, right wing +Y_frd goes down +Z_ned): in the viewer
    // the right wing (body −Y) points down too.
    let ned = EulerZyx::from_degrees(0.0, 0.0, 30.0);
    let right_wing = EulerZyx::from_aerospace(ned).to_matrix() * -DVec3::Y;
    assert!(right_wing.z < 0.0, "{right_wing}");
}
