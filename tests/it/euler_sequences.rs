//! All 24 Euler-angle conventions (`wireflight::geometry::euler::{Convention, EulerAngles}`): matrices
//! against products of single-axis rotations and against glam, round trips on a 15° grid over
//! the full ranges and on random angles, quaternions, conversions between every pair, gimbal
//! lock, agreement with `EulerZyx`, bad input, and the seed lecture's statements.

use std::collections::HashSet;
use std::f64::consts::{FRAC_PI_2, PI};

use glam::{DMat3, DQuat, DVec3, EulerRot};
use wireflight::geometry::euler::{
    Axis, Convention, EulerAngles, EulerZyx, Frame, Gimbal, Lock, NotRotation, Sequence,
    LOCK_TOLERANCE,
};

use crate::support::{angle_distance, assert_close, wrap_angle, Rng};

/// Every multiple of 15° in [−180°, 180°] (both ends), in radians: glam's tests/euler.rs grid.
fn grid() -> impl Iterator<Item = f64> + Clone {
    (-180..=180).step_by(15).map(|d| f64::from(d).to_radians())
}

/// Every angle triple of the 15° grid (25³ = 15 625).
fn grid3() -> impl Iterator<Item = [f64; 3]> {
    grid().flat_map(|a| grid().flat_map(move |b| grid().map(move |c| [a, b, c])))
}

fn deg(a: [f64; 3]) -> [f64; 3] {
    a.map(f64::to_degrees)
}

/// `R_a(α)·R_b(β)·R_c(γ)` (intrinsic) or `R_c(γ)·R_b(β)·R_a(α)` (extrinsic), from
/// `Axis::rotation`, i.e. the existing `rot_x`, `rot_y`, `rot_z`.
fn product(e: EulerAngles) -> DMat3 {
    let [a, b, c] = e.convention.sequence.axes();
    let [x, y, z] = e.angles;
    match e.convention.frame {
        Frame::Intrinsic => a.rotation(x) * b.rotation(y) * c.rotation(z),
        Frame::Extrinsic => c.rotation(z) * b.rotation(y) * a.rotation(x),
    }
}

/// The quaternion with w ≥ 0 of the pair ±q.
fn canonical_quat(q: DQuat) -> DQuat {
    if q.w < 0.0 {
        -q
    } else {
        q
    }
}

fn assert_rotation(r: DMat3, ctx: &str) {
    assert_close!(r.transpose() * r, DMat3::IDENTITY, 1e-12, "RᵀR, {ctx}");
    assert_close!(r.determinant(), 1.0, 1e-12, "det, {ctx}");
}

/// The principal solution for any angles (computed independently of the library): for
/// Tait–Bryan β is folded into [−π/2, π/2] by (α+π, π−β, γ+π); for proper Euler into [0, π]
/// by (α+π, −β, γ+π). α and γ are wrapped into (−π, π].
fn expected_principal(sequence: Sequence, [a, b, c]: [f64; 3]) -> [f64; 3] {
    let b = wrap_angle(b);
    let flip = if sequence.is_tait_bryan() {
        b.abs() > FRAC_PI_2
    } else {
        b < 0.0
    };
    if !flip {
        return [wrap_angle(a), b, wrap_angle(c)];
    }
    let b = if sequence.is_tait_bryan() {
        PI.copysign(b) - b
    } else {
        -b
    };
    [wrap_angle(a + PI), b, wrap_angle(c + PI)]
}

/// Whether a middle angle (any value) is at the convention's singular value.
fn at_lock(sequence: Sequence, beta: f64) -> bool {
    if sequence.is_tait_bryan() {
        beta.cos().abs() < 1e-12
    } else {
        beta.sin().abs() < 1e-12
    }
}

/// Angles equal modulo 2π (α, γ) and exactly-ish (β), within `tol`.
fn assert_angles(actual: [f64; 3], expected: [f64; 3], tol: f64, ctx: &str) {
    assert_close!(angle_distance(actual[0], expected[0]), 0.0, tol, "α, {ctx}");
    assert_close!(actual[1], expected[1], tol, "β, {ctx}");
    assert_close!(angle_distance(actual[2], expected[2]), 0.0, tol, "γ, {ctx}");
}

/// The angles in the intrinsic reading: reversed for an extrinsic convention.
fn intrinsic_reading(e: EulerAngles) -> [f64; 3] {
    match e.convention.frame {
        Frame::Intrinsic => e.angles,
        Frame::Extrinsic => e.other_frame().angles,
    }
}

/// The documented ranges: α, γ ∈ (−π, π]; β ∈ [−π/2, π/2] or [0, π].
fn assert_in_ranges(e: EulerAngles, ctx: &str) {
    let [a, b, c] = e.angles;
    let (lo, hi) = e.convention.sequence.middle_range();
    assert!(
        a > -PI && a <= PI && c > -PI && c <= PI,
        "α, γ range: {ctx}"
    );
    assert!((lo..=hi).contains(&b), "β range [{lo}, {hi}]: {ctx}");
}

// ---------------------------------------------------------------------------------------------
// Angles → matrix
// ---------------------------------------------------------------------------------------------

/// On the whole 15° grid, for all 24 conventions: the written-out matrix is the product of the
/// three single-axis rotations, orthonormal with det +1, and glam's `from_euler` with the
/// same-named `EulerRot` (375 000 matrices).
#[test]
fn matrix_is_the_product_of_axis_rotations_and_glam_on_the_grid() {
    for convention in Convention::ALL {
        let rot = convention.to_glam();
        assert_eq!(Convention::from_glam(rot), convention);
        for angles in grid3() {
            let e = EulerAngles::new(convention, angles);
            let ctx = format!("{convention} {:?}", deg(angles));
            let m = e.to_matrix();
            assert_close!(m, product(e), 1e-15, "product, {ctx}");
            let [a, b, c] = angles;
            assert_close!(
                m,
                DMat3::from_euler(rot, a, b, c),
                1e-15,
                "glam {rot:?}, {ctx}"
            );
            assert_rotation(m, &ctx);
        }
    }
}

/// Intrinsic a-b-c with (α, β, γ) is extrinsic c-b-a with (γ, β, α): bit-identical matrices
/// and quaternions, and mirrored inverses (including the lock rule), on the grid.
#[test]
fn intrinsic_abc_is_extrinsic_cba_with_the_angles_reversed() {
    for sequence in Sequence::ALL {
        let intrinsic = Convention::intrinsic(sequence);
        let extrinsic = Convention::extrinsic(sequence.reversed());
        assert_eq!(intrinsic.other_frame(), extrinsic);
        assert_eq!(extrinsic.other_frame(), intrinsic);
        for [a, b, c] in grid3() {
            let i = EulerAngles::new(intrinsic, [a, b, c]);
            let x = EulerAngles::new(extrinsic, [c, b, a]);
            assert_eq!(i.other_frame(), x);
            assert_eq!(
                i.to_matrix(),
                x.to_matrix(),
                "{sequence} {:?}",
                deg([a, b, c])
            );
            assert_eq!(i.to_quat(), x.to_quat());
            let from_i = EulerAngles::from_matrix(intrinsic, i.to_matrix());
            let from_x = EulerAngles::from_matrix(extrinsic, i.to_matrix());
            assert_eq!(from_i.euler.other_frame(), from_x.euler);
            assert_eq!(from_i.lock, from_x.lock);
        }
    }
}

/// glam's inverse (`to_euler`) describes the same rotation as ours for every convention on the
/// grid; away from lock its angles equal ours modulo 2π, except for the proper Euler sequences
/// glam handles with even parity (z-x-z, x-y-x, y-z-y, in both frames), where glam's middle
/// angle is in [−π, 0]: the other solution (α+π, −β, γ+π) of the same rotation.
#[test]
fn from_matrix_agrees_with_glam_to_euler() {
    let negated_middle = [Sequence::ZXZ, Sequence::XYX, Sequence::YZY];
    for convention in Convention::ALL {
        let rot = convention.to_glam();
        for angles in grid3() {
            let m = EulerAngles::new(convention, angles).to_matrix();
            let ours = EulerAngles::from_matrix(convention, m);
            let (a, b, c) = m.to_euler(rot);
            let ctx = format!("{convention} {:?}: glam {:?}", deg(angles), deg([a, b, c]));
            assert_close!(
                DMat3::from_euler(rot, a, b, c),
                m,
                1e-12,
                "glam's angles, {ctx}"
            );
            if ours.lock.is_locked() {
                continue;
            }
            let glam = if negated_middle.contains(&convention.sequence) {
                assert!(b <= 0.0, "glam's β ≤ 0, {ctx}");
                [a + PI, -b, c + PI]
            } else {
                [a, b, c]
            };
            assert_angles(ours.euler.angles, glam, 1e-12, &ctx);
        }
    }
}

/// glam's quaternion `from_euler` is ours up to sign; ours has w ≥ 0; the quaternion's matrix
/// is `to_matrix`, glam's `DQuat::from_mat3` of it is the same quaternion, and it is the product
/// of the three single-axis quaternions.
#[test]
fn quaternions_agree_with_matrices_and_glam_on_the_grid() {
    for convention in Convention::ALL {
        let rot = convention.to_glam();
        for angles in grid3() {
            let e = EulerAngles::new(convention, angles);
            let ctx = format!("{convention} {:?}", deg(angles));
            let q = e.to_quat();
            assert!(q.w >= 0.0, "w ≥ 0, {ctx}");
            assert_close!(q.length(), 1.0, 1e-15, "|q|, {ctx}");
            assert_close!(
                DMat3::from_quat(q),
                e.to_matrix(),
                1e-15,
                "matrix of q, {ctx}"
            );
            let [a, b, c] = angles;
            let glam = canonical_quat(DQuat::from_euler(rot, a, b, c));
            if q.w > 1e-9 {
                assert_close!(q.to_array(), glam.to_array(), 1e-15, "glam, {ctx}");
                let from_m = canonical_quat(DQuat::from_mat3(&e.to_matrix()));
                assert_close!(q.to_array(), from_m.to_array(), 1e-15, "from_mat3, {ctx}");
            } else {
                // Half-turns: q and −q both have w ≈ 0; compare rotations.
                assert_close!(DMat3::from_quat(glam), e.to_matrix(), 1e-15, "{ctx}");
            }
            let [ax, bx, cx] = convention.sequence.axes();
            let elemental = match convention.frame {
                Frame::Intrinsic => ax.quat(a) * bx.quat(b) * cx.quat(c),
                Frame::Extrinsic => cx.quat(c) * bx.quat(b) * ax.quat(a),
            };
            assert_close!(q.to_array(), canonical_quat(elemental).to_array(), 1e-15);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------------

/// The 15° grid over the full ranges, all 24 conventions: `from_matrix` returns finite angles
/// in the documented ranges that reproduce the matrix; away from lock they are the principal
/// solution of the input (computed independently); at lock (β = ±90° resp. 0°/180°) the lock
/// is reported and the lock rule holds. The quaternion route gives the same.
#[test]
fn round_trip_on_the_15_degree_grid() {
    let (mut free, mut locked) = (0, 0);
    for convention in Convention::ALL {
        let intrinsic = convention.as_intrinsic();
        for angles in grid3() {
            let e = EulerAngles::new(convention, angles);
            let m = e.to_matrix();
            let s = EulerAngles::from_matrix(convention, m);
            let ctx = format!(
                "{convention} {:?} → {:?}",
                deg(angles),
                s.euler.to_degrees()
            );
            assert_eq!(s.euler.convention, convention);
            assert!(s.euler.is_finite(), "{ctx}");
            assert_in_ranges(s.euler, &ctx);
            assert_close!(s.euler.to_matrix(), m, 1e-12, "matrix, {ctx}");
            assert_eq!(s.lock, e.lock(), "lock, {ctx}");
            assert_eq!(s, e.canonical());
            // Work in the intrinsic reading (for extrinsic: the angles reversed).
            let (given, got) = (intrinsic_reading(e), intrinsic_reading(s.euler));
            if at_lock(convention.sequence, angles[1]) {
                locked += 1;
                assert!(s.lock.is_locked(), "{ctx}");
                assert_eq!(got[2], 0.0, "third intrinsic angle, {ctx}");
                let (sin_b, cos_b) = given[1].sin_cos();
                let turn = if convention.sequence.is_tait_bryan() {
                    given[0] + intrinsic.sequence.parity() * sin_b.round() * given[2]
                } else {
                    given[0] + cos_b.round() * given[2]
                };
                assert_close!(angle_distance(got[0], turn), 0.0, 1e-12, "first, {ctx}");
            } else {
                free += 1;
                assert_eq!(s.lock, Lock::Free, "{ctx}");
                let expected = expected_principal(intrinsic.sequence, given);
                assert_angles(got, expected, 1e-12, &ctx);
            }
            let via_q = EulerAngles::from_quat(convention, e.to_quat());
            assert_eq!(via_q.lock, s.lock, "{ctx}");
            assert_angles(via_q.euler.angles, s.euler.angles, 1e-12, &ctx);
        }
    }
    assert_eq!(free + locked, 24 * 25 * 25 * 25);
    // Lock rows: Tait–Bryan β = ±90° (2 of 25 values), proper Euler β ∈ {−180°, 0°, 180°}.
    assert_eq!(locked, 12 * 2 * 625 + 12 * 3 * 625);
}

/// 5 000 random principal triples per convention, β at least 0.01° from lock: the angles come
/// back to 1e-9 rad (exactly the input, not just the rotation).
#[test]
fn random_principal_angles_round_trip_exactly() {
    let mut rng = Rng::new(0x00E0_1E24);
    let margin = 0.01f64.to_radians();
    for convention in Convention::ALL {
        let (lo, hi) = convention.sequence.middle_range();
        for _ in 0..5_000 {
            let mut angles = [
                rng.range(-PI, PI),
                rng.range(lo + margin, hi - margin),
                rng.range(-PI, PI),
            ];
            if convention.frame == Frame::Extrinsic {
                angles.swap(0, 2);
            }
            let e = EulerAngles::new(convention, angles);
            let s = EulerAngles::from_matrix(convention, e.to_matrix());
            let ctx = format!("{convention} {:?}", deg(angles));
            assert_eq!(s.lock, Lock::Free, "{ctx}");
            assert_close!(s.euler.angles, angles, 1e-9, "{ctx}");
            let q = EulerAngles::from_quat(convention, e.to_quat());
            assert_close!(q.euler.angles, angles, 1e-9, "quaternion, {ctx}");
            // −q is the same rotation; a non-unit q is normalised.
            let q2 = EulerAngles::from_quat(convention, e.to_quat() * -2.5);
            assert_close!(q2.euler.angles, angles, 1e-9, "−2.5 q, {ctx}");
        }
    }
}

/// Approaching lock, β = singular ∓ 10^−k degrees: lock is reported exactly when cos β (or
/// |sin β|) < LOCK_TOLERANCE, and the matrix is reproduced to 1e-12 plus that distance.
#[test]
fn approaching_lock_switches_at_the_tolerance_and_keeps_the_matrix() {
    for convention in Convention::ALL {
        let (lo, hi) = convention.sequence.middle_range();
        for k in 1..=12 {
            let off = 10f64.powi(-k).to_radians();
            for beta in [lo + off, hi - off] {
                let mut angles = [0.7, beta, -2.1];
                if convention.frame == Frame::Extrinsic {
                    angles.swap(0, 2);
                }
                let e = EulerAngles::new(convention, angles);
                let s = e.canonical();
                let distance = if convention.sequence.is_tait_bryan() {
                    beta.cos().abs()
                } else {
                    beta.sin().abs()
                };
                let ctx = format!("{convention} β = {}°: {s:?}", beta.to_degrees());
                assert_eq!(s.lock.is_locked(), distance < LOCK_TOLERANCE, "{ctx}");
                assert_eq!(e.lock().is_locked(), distance < LOCK_TOLERANCE, "{ctx}");
                let tol = 1e-12 + if s.lock.is_locked() { distance } else { 0.0 };
                assert_close!(s.euler.to_matrix(), e.to_matrix(), tol, "{ctx}");
                if !s.lock.is_locked() && k <= 2 {
                    assert_close!(s.euler.angles, angles, 1e-9, "{ctx}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Conversions
// ---------------------------------------------------------------------------------------------

/// Every ordered pair of the 24 conventions (576), 200 random rotations each: the converted
/// angles give the same rotation, and converting back gives the canonical original.
#[test]
fn conversions_between_every_pair_preserve_the_rotation() {
    let mut rng = Rng::new(0xC0_4E47);
    for from in Convention::ALL {
        for to in Convention::ALL {
            for _ in 0..200 {
                let angles = [
                    rng.range(-4.0 * PI, 4.0 * PI),
                    rng.range(-4.0 * PI, 4.0 * PI),
                    rng.range(-4.0 * PI, 4.0 * PI),
                ];
                let e = EulerAngles::new(from, angles);
                let there = e.convert(to);
                let ctx = format!("{from} → {to}, {:?} → {there:?}", deg(angles));
                assert_eq!(there.euler.convention, to);
                assert_in_ranges(there.euler, &ctx);
                assert_close!(there.euler.to_matrix(), e.to_matrix(), 1e-12, "{ctx}");
                let back = there.euler.convert(from);
                let canonical = e.canonical();
                assert_eq!(back.lock, canonical.lock, "{ctx}");
                assert_angles(back.euler.angles, canonical.euler.angles, 1e-9, &ctx);
            }
        }
    }
}

/// Known conversions in closed form: z-y-x (ψ, θ, φ) = extrinsic x-y-z (φ, θ, ψ); yaw alone is
/// z-y-z at lock with the whole turn in α; z-y-x (0°, 90°, 90°) is x-y-z (90°, 0°, −90°).
#[test]
fn known_conversions() {
    let zyx = EulerAngles::from_degrees(Convention::VIEWER, [30.0, 20.0, 10.0]);
    let s = zyx.convert("xyz,extrinsic".parse().unwrap());
    assert_close!(s.euler.to_degrees(), [10.0, 20.0, 30.0], 1e-12);
    let yaw = EulerAngles::from_degrees(Convention::VIEWER, [40.0, 0.0, 0.0]);
    let s = yaw.convert(Convention::intrinsic(Sequence::ZYZ));
    assert_eq!(s.lock, Lock::Lower);
    assert_close!(s.euler.to_degrees(), [40.0, 0.0, 0.0], 1e-12);
    // z-y-x (0°, 90°, 90°): nose straight down, left wing forward; in x-y-z that is
    // Rx(90°)·Ry(0°)·Rz(−90°).
    let e = EulerAngles::from_degrees(Convention::VIEWER, [0.0, 90.0, 90.0]);
    let s = e.convert(Convention::intrinsic(Sequence::XYZ));
    assert_eq!(s.lock, Lock::Free);
    assert_close!(s.euler.to_matrix() * DVec3::X, -DVec3::Z, 1e-15);
    assert_close!(s.euler.to_matrix() * DVec3::Y, DVec3::X, 1e-15);
    assert_close!(s.euler.to_degrees(), [90.0, 0.0, -90.0], 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The existing z-y-x (EulerZyx)
// ---------------------------------------------------------------------------------------------

/// `EulerAngles::from_matrix` for intrinsic z-y-x equals `EulerZyx::from_matrix` exactly, except
/// that where `EulerZyx` returns −π (outside its documented (−180°, 180°]) the new code returns
/// +π. Returns whether that exception applied.
fn assert_same_as_zyx(r: DMat3, ctx: &str) -> bool {
    let (old, gimbal) = EulerZyx::from_matrix(r);
    let s = EulerAngles::from_matrix(Convention::VIEWER, r);
    let (new, new_gimbal) = s.to_zyx().expect("intrinsic zyx");
    assert_eq!(new_gimbal, gimbal, "{ctx}");
    let plus_pi = |x: f64| if x == -PI { PI } else { x };
    let expected = EulerZyx::new(plus_pi(old.yaw), old.pitch, plus_pi(old.roll));
    assert_eq!(new, expected, "{ctx}");
    expected != old
}

/// Intrinsic z-y-x is `EulerZyx`: bit-identical matrices on the grid and on 20 000 random
/// triples over [−4π, 4π]³, and identical inverses (angles and gimbal state) on those
/// rotations, on exact locks, and on 20 000 arbitrary finite matrices (not rotations), which
/// shows the same elements and operations are used. The one exception: `EulerZyx` can return
/// −π (e.g. yaw −180°, pitch −180°, roll 0° comes back as roll = −180°), the new code +π; on
/// the grid that happens for 1 157 of the 15 625 triples (counted here).
#[test]
fn intrinsic_zyx_is_euler_zyx_exactly() {
    let mut rng = Rng::new(0x2_7C);
    let random = (0..20_000).map(|_| {
        let mut r = || rng.range(-4.0 * PI, 4.0 * PI);
        [r(), r(), r()]
    });
    let mut minus_pi = 0;
    for (i, angles) in grid3().chain(random.collect::<Vec<_>>()).enumerate() {
        let [yaw, pitch, roll] = angles;
        let old = EulerZyx::new(yaw, pitch, roll);
        let new = EulerAngles::new(Convention::VIEWER, angles);
        assert_eq!(EulerAngles::from(old), new);
        assert_eq!(new.to_matrix(), old.to_matrix(), "{:?}", deg(angles));
        if assert_same_as_zyx(old.to_matrix(), &format!("{:?}", deg(angles))) {
            assert!(
                i < 15_625,
                "−π only from exact grid angles: {:?}",
                deg(angles)
            );
            minus_pi += 1;
        }
    }
    assert_eq!(minus_pi, 1157);
    for pitch in [90.0, -90.0] {
        for yaw in grid() {
            for roll in grid() {
                let r = EulerZyx::new(yaw, f64::to_radians(pitch), roll).to_matrix();
                assert_same_as_zyx(r, &format!("lock {pitch}°"));
                let s = EulerAngles::from_matrix(Convention::VIEWER, r);
                let expected = if pitch > 0.0 {
                    Lock::Upper
                } else {
                    Lock::Lower
                };
                assert_eq!(s.lock, expected);
            }
        }
    }
    for _ in 0..20_000 {
        let r = DMat3::from_cols_array(&[0.0; 9].map(|_: f64| rng.range(-2.0, 2.0)));
        assert_same_as_zyx(r, &format!("{r}"));
    }
    assert_eq!(
        EulerAngles::from_matrix(Convention::intrinsic(Sequence::XYZ), DMat3::IDENTITY).to_zyx(),
        None
    );
}

/// The one documented difference: a matrix with a signed zero where `atan2` would give −π.
/// `EulerZyx` returns yaw = −π (outside its documented (−180°, 180°]); the new code returns +π.
#[test]
fn minus_pi_is_returned_as_plus_pi() {
    // Rz(π) written with −0.0 for sin π.
    let r = DMat3::from_cols(
        DVec3::new(-1.0, -0.0, 0.0),
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::Z,
    );
    let (old, _) = EulerZyx::from_matrix(r);
    assert_eq!(old.yaw, -PI);
    let new = EulerAngles::from_matrix(Convention::VIEWER, r);
    assert_eq!(new.euler.angles, [PI, 0.0, 0.0]);
}

// ---------------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------------

/// Non-finite matrices, quaternions and angles never panic: NaN out, `Lock::Free`.
#[test]
fn non_finite_input_gives_nan_without_panicking() {
    for convention in Convention::ALL {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for i in 0..9 {
                let mut a = DMat3::IDENTITY.to_cols_array();
                a[i] = bad;
                let s = EulerAngles::from_matrix(convention, DMat3::from_cols_array(&a));
                assert!(
                    s.euler.angles.iter().all(|x| x.is_nan()),
                    "{convention} {a:?}"
                );
                assert_eq!(s.lock, Lock::Free);
                let err =
                    EulerAngles::try_from_matrix(convention, DMat3::from_cols_array(&a), 1e-9);
                assert_eq!(err, Err(NotRotation::NonFinite));
            }
            let q = DQuat::from_xyzw(0.0, bad, 0.0, 1.0);
            assert!(!EulerAngles::from_quat(convention, q).euler.is_finite());
            let e = EulerAngles::new(convention, [0.1, bad, 0.2]);
            assert!(e.to_matrix().is_nan() && e.to_quat().is_nan());
            assert_eq!(e.lock(), Lock::Free);
            assert!(!e.canonical().euler.is_finite());
        }
        let zero = EulerAngles::from_quat(convention, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0));
        assert!(!zero.euler.is_finite());
    }
}

/// Non-orthonormal input, documented behaviour: a uniform positive scale does not change the
/// angles (×2 bit for bit); a rotation perturbed by 1e-7 gives angles within about that; any
/// finite matrix gives finite angles in range; `try_from_matrix` refuses what is not a rotation.
#[test]
fn non_orthonormal_input() {
    let mut rng = Rng::new(0x5CA1E);
    for convention in Convention::ALL {
        let (lo, hi) = convention.sequence.middle_range();
        for _ in 0..500 {
            let angles = [
                rng.range(-3.0, 3.0),
                rng.range(lo + 0.1, hi - 0.1),
                rng.range(-3.0, 3.0),
            ];
            let r = EulerAngles::new(convention, angles).to_matrix();
            let s = EulerAngles::from_matrix(convention, r);
            assert_eq!(EulerAngles::from_matrix(convention, r * 2.0), s);
            let scaled = EulerAngles::from_matrix(convention, r * 3.7);
            assert_close!(scaled.euler.angles, s.euler.angles, 1e-15);
            let noise = DMat3::from_cols_array(&[0.0; 9].map(|_: f64| rng.range(-1e-7, 1e-7)));
            let near = EulerAngles::from_matrix(convention, r + noise);
            assert_angles(
                near.euler.angles,
                s.euler.angles,
                1e-5,
                &format!("{convention}"),
            );
            let any = DMat3::from_cols_array(&[0.0; 9].map(|_: f64| rng.range(-5.0, 5.0)));
            let garbage = EulerAngles::from_matrix(convention, any);
            assert!(garbage.euler.is_finite(), "{convention} {any}");
            assert_in_ranges(garbage.euler, &format!("{convention} {any}"));

            assert_eq!(EulerAngles::try_from_matrix(convention, r, 1e-12), Ok(s));
            assert!(matches!(
                EulerAngles::try_from_matrix(convention, r * 2.0, 1e-6),
                Err(NotRotation::NotOrthonormal { .. })
            ));
            assert!(matches!(
                EulerAngles::try_from_matrix(convention, -r, 1e-12),
                Err(NotRotation::Reflection { det }) if (det + 1.0).abs() < 1e-12
            ));
        }
        // The zero matrix: finite, no panic.
        assert!(EulerAngles::from_matrix(convention, DMat3::ZERO)
            .euler
            .is_finite());
    }
}

// ---------------------------------------------------------------------------------------------
// The seed lecture (clipping-and-euler-angles.txt)
// ---------------------------------------------------------------------------------------------

/// "There are twelve ways to apply the angles … Euler: z-x-z, x-y-x, y-z-y, z-y-z, x-z-x,
/// y-x-y; Tait-Bryan: x-y-z, y-z-x, z-x-y, x-z-y, z-y-x, y-x-z. … in Euler's set there's always
/// a repeated axis and in Tait-Bryan's set, there's no repeated axis. Why?" Because two
/// consecutive rotations about one axis are one rotation: of the 27 axis triples exactly the
/// 12 without equal neighbours are sequences.
#[test]
fn seed_twelve_sequences() {
    let seed = [
        "z-x-z", "x-y-x", "y-z-y", "z-y-z", "x-z-x", "y-x-y", "x-y-z", "y-z-x", "z-x-y", "x-z-y",
        "z-y-x", "y-x-z",
    ];
    let ours: Vec<String> = Sequence::ALL.iter().map(|s| format!("{s:#}")).collect();
    assert_eq!(ours, seed);
    for (i, s) in Sequence::ALL.into_iter().enumerate() {
        assert_eq!(s.is_proper_euler(), i < 6, "{s}");
        let [a, _, c] = s.axes();
        assert_eq!(a == c, s.is_proper_euler());
        assert_eq!(seed[i].parse::<Sequence>(), Ok(s));
    }
    let mut valid = 0;
    for a in Axis::ALL {
        for b in Axis::ALL {
            for c in Axis::ALL {
                let s = Sequence::from_axes([a, b, c]);
                assert_eq!(s.is_some(), a != b && b != c, "{a}{b}{c}");
                valid += usize::from(s.is_some());
            }
        }
    }
    assert_eq!(valid, 12);
    // Twice about one axis is one rotation: x-x-y with (α, β, γ) is x-y with (α + β, γ).
    let r = Axis::X.rotation(0.3) * Axis::X.rotation(0.4) * Axis::Y.rotation(0.5);
    assert_close!(r, Axis::X.rotation(0.7) * Axis::Y.rotation(0.5), 1e-15);
}

/// "Euler angles must be applied in a particular order": the same three numbers give 24
/// different rotations in the 24 conventions.
#[test]
fn seed_order_matters() {
    let angles = [30f64, 20.0, 10.0].map(f64::to_radians);
    let quats: HashSet<[i64; 4]> = Convention::ALL
        .into_iter()
        .map(|c| {
            let q = EulerAngles::new(c, angles).to_quat();
            q.to_array().map(|x| (x * 1e9).round() as i64)
        })
        .collect();
    assert_eq!(quats.len(), 24);
}

/// "We will be using the fairly common sequence z-y-x. So technically it's a Tait-Bryan
/// rotation … ψ for yaw, θ for pitch, φ for roll; yaw is about the Z axis, pitch about Y, roll
/// about X." The plane: nose +X, wings ±Y, rudder +Z. Yaw: the nose and tail go side to side;
/// pitch: the nose and tail go up and down; roll: the wing tips go up and down.
#[test]
fn seed_yaw_pitch_roll_on_the_plane_model() {
    let viewer: Convention = "z-y-x".parse().unwrap();
    assert_eq!(viewer, Convention::VIEWER);
    assert!(viewer.sequence.is_tait_bryan());
    assert_eq!(viewer.to_glam(), EulerRot::ZYX);
    let (nose, left_wing, rudder) = (DVec3::X, DVec3::Y, DVec3::Z);
    for deg in [-60.0, -15.0, 15.0, 60.0] {
        let yaw = EulerAngles::from_degrees(viewer, [deg, 0.0, 0.0]).to_matrix();
        let pitch = EulerAngles::from_degrees(viewer, [0.0, deg, 0.0]).to_matrix();
        let roll = EulerAngles::from_degrees(viewer, [0.0, 0.0, deg]).to_matrix();
        // Yaw: nose and tail side to side (in the horizontal plane); the rudder stays up.
        assert_close!((yaw * nose).z, 0.0, 0.0);
        assert!((yaw * nose).y.abs() > 0.2 && (yaw * -nose).y == -(yaw * nose).y);
        assert_close!(yaw * rudder, rudder, 0.0);
        // Pitch: nose and tail up and down (in the x-z plane); the wings stay.
        assert_close!((pitch * nose).y, 0.0, 0.0);
        assert!((pitch * nose).z.abs() > 0.2);
        assert_close!(pitch * left_wing, left_wing, 0.0);
        // Roll: wing tips up and down; the nose stays.
        assert!((roll * left_wing).z.abs() > 0.2 && (roll * -left_wing).z == -(roll * left_wing).z);
        assert_close!(roll * nose, nose, 0.0);
    }
    // All three: the z-y-x matrix is Rz(ψ)·Ry(θ)·Rx(φ), the seed's order of construction.
    let e = EulerAngles::from_degrees(viewer, [30.0, 20.0, 10.0]);
    let [psi, theta, phi] = e.angles;
    assert_close!(
        e.to_matrix(),
        Axis::Z.rotation(psi) * Axis::Y.rotation(theta) * Axis::X.rotation(phi),
        1e-15
    );
}

/// Degrees at the boundary, radians inside; `Gimbal` for a z-y-x lock read back via `to_zyx`.
#[test]
fn degrees_and_the_zyx_gimbal_names() {
    let e = EulerAngles::from_degrees(Convention::VIEWER, [70.0, 90.0, 25.0]);
    assert_close!(e.angles[1], FRAC_PI_2, 0.0);
    let (zyx, gimbal) = e.canonical().to_zyx().unwrap();
    assert_eq!(gimbal, Gimbal::LockedNoseDown);
    assert_close!(zyx.to_degrees(), [45.0, 90.0, 0.0], 1e-12);
    let e = EulerAngles::from_degrees(Convention::VIEWER, [70.0, -90.0, 25.0]);
    assert_eq!(e.canonical().to_zyx().unwrap().1, Gimbal::LockedNoseUp);
}
