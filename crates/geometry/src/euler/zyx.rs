//! z-y-x Tait-Bryan angles (yaw ψ, pitch θ, roll φ) and their rotation matrices: [`EulerZyx`].
//!
//! Convention, stated once (README "Conventions" repeats it):
//!
//! * Body axes of the model: nose **+X**, wings **±Y** (left wing +Y), rudder **+Z**.
//! * Yaw ψ is a right-hand rotation about Z, pitch θ about Y, roll φ about X, in radians.
//! * The body→world rotation is `R = Rz(ψ)·Ry(θ)·Rx(φ)`: roll first, then pitch, then yaw
//!   (intrinsic z, y', x''). A body vector `b` becomes the world vector `R·b`.
//! * This is glam's `EulerRot::ZYX` with arguments `(yaw, pitch, roll)`; the matrices below are
//!   written out explicitly (as in the seed lecture) and tested against glam.
//!
//! The inverse [`EulerZyx::from_matrix`] is defined everywhere: at gimbal lock (|θ| = 90°, where
//! only ψ − φ or ψ + φ is determined) it reports the lock and puts all heading into yaw, roll = 0.
//!
//! Flight data use the aerospace frames (world NED, body FRD). Those differ from the viewer's
//! frames (Z up) by a half-turn about X, `D = diag(1, −1, −1)`, so `R_viewer = D·R_ned·D`, which
//! in angles is `(ψ, θ, φ)_viewer = (−ψ, −θ, φ)_ned` ([`EulerZyx::from_aerospace`]).
//!
//! Pure math: no I/O.

use glam::{DMat3, DVec3, Mat3};

/// Tolerance on cos θ below which the angles are reported as gimbal-locked.
///
/// cos θ < 1e-9 means |θ| is within about 2e-7 degrees of 90°; there ψ and φ cannot be told
/// apart in f64 anyway (their split is conditioned by 1/cos θ).
pub const GIMBAL_LOCK_COS: f64 = 1e-9;

/// z-y-x Tait-Bryan angles in radians: yaw ψ about Z, pitch θ about Y, roll φ about X.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EulerZyx {
    /// ψ, rotation about Z (radians).
    pub yaw: f64,
    /// θ, rotation about Y (radians).
    pub pitch: f64,
    /// φ, rotation about X (radians).
    pub roll: f64,
}

/// Whether a matrix → angles conversion met gimbal lock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gimbal {
    /// |θ| < 90°: the three angles are unique (with ψ, φ in (−π, π]).
    Free,
    /// θ = +90°: only ψ − φ is determined; reported as yaw = ψ − φ, roll = 0.
    LockedNoseDown,
    /// θ = −90°: only ψ + φ is determined; reported as yaw = ψ + φ, roll = 0.
    LockedNoseUp,
}

impl Gimbal {
    /// True at either lock.
    pub fn is_locked(self) -> bool {
        self != Gimbal::Free
    }
}

/// Rotation about X by `phi` radians (right-hand): `Rx(φ)`.
pub fn rot_x(phi: f64) -> DMat3 {
    let (s, c) = phi.sin_cos();
    // Columns are the images of the basis vectors.
    DMat3::from_cols(
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, c, s),
        DVec3::new(0.0, -s, c),
    )
}

/// Rotation about Y by `theta` radians (right-hand): `Ry(θ)`.
pub fn rot_y(theta: f64) -> DMat3 {
    let (s, c) = theta.sin_cos();
    DMat3::from_cols(
        DVec3::new(c, 0.0, -s),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(s, 0.0, c),
    )
}

/// Rotation about Z by `psi` radians (right-hand): `Rz(ψ)`.
pub fn rot_z(psi: f64) -> DMat3 {
    let (s, c) = psi.sin_cos();
    DMat3::from_cols(
        DVec3::new(c, s, 0.0),
        DVec3::new(-s, c, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
    )
}

impl EulerZyx {
    /// Angles in radians.
    pub const fn new(yaw: f64, pitch: f64, roll: f64) -> Self {
        Self { yaw, pitch, roll }
    }

    /// Angles given in degrees.
    pub fn from_degrees(yaw_deg: f64, pitch_deg: f64, roll_deg: f64) -> Self {
        Self::new(
            yaw_deg.to_radians(),
            pitch_deg.to_radians(),
            roll_deg.to_radians(),
        )
    }

    /// `[yaw, pitch, roll]` in degrees.
    pub fn to_degrees(self) -> [f64; 3] {
        [
            self.yaw.to_degrees(),
            self.pitch.to_degrees(),
            self.roll.to_degrees(),
        ]
    }

    /// True when all three angles are finite.
    pub fn is_finite(self) -> bool {
        self.yaw.is_finite() && self.pitch.is_finite() && self.roll.is_finite()
    }

    /// Body→world rotation `R = Rz(ψ)·Ry(θ)·Rx(φ)`, written out element by element.
    ///
    /// ```text
    /// | cψcθ   cψsθsφ − sψcφ   cψsθcφ + sψsφ |
    /// | sψcθ   sψsθsφ + cψcφ   sψsθcφ − cψsφ |
    /// | −sθ    cθsφ            cθcφ          |
    /// ```
    ///
    /// ```
    /// use wireflight_geometry::euler::{EulerZyx, rot_x, rot_y, rot_z};
    /// let e = EulerZyx::from_degrees(30.0, 20.0, 10.0);
    /// let product = rot_z(e.yaw) * rot_y(e.pitch) * rot_x(e.roll);
    /// assert!(e.to_matrix().abs_diff_eq(product, 1e-15));
    /// ```
    pub fn to_matrix(self) -> DMat3 {
        let (sps, cps) = self.yaw.sin_cos();
        let (sth, cth) = self.pitch.sin_cos();
        let (sph, cph) = self.roll.sin_cos();
        DMat3::from_cols(
            DVec3::new(cps * cth, sps * cth, -sth),
            DVec3::new(
                cps * sth * sph - sps * cph,
                sps * sth * sph + cps * cph,
                cth * sph,
            ),
            DVec3::new(
                cps * sth * cph + sps * sph,
                sps * sth * cph - cps * sph,
                cth * cph,
            ),
        )
    }

    /// [`to_matrix`](Self::to_matrix) in f32, for the graphics pipeline.
    pub fn to_mat3(self) -> Mat3 {
        self.to_matrix().as_mat3()
    }

    /// Angles of a rotation matrix, with the gimbal state.
    ///
    /// Away from lock the answer is the unique one with θ ∈ [−90°, 90°], ψ, φ ∈ (−180°, 180°].
    /// At lock (cos θ < [`GIMBAL_LOCK_COS`]) θ = ±90°, roll = 0 and yaw carries the whole
    /// heading (ψ − φ at θ = +90°, ψ + φ at θ = −90°), so `to_matrix` of the result
    /// reproduces the input.
    ///
    /// The input should be a rotation; no check is made. Non-finite input gives NaN angles.
    pub fn from_matrix(r: DMat3) -> (Self, Gimbal) {
        // Element r_ij = row i, column j; glam stores columns.
        let r00 = r.x_axis.x;
        let r10 = r.x_axis.y;
        let r20 = r.x_axis.z;
        let cos_pitch = r00.hypot(r10);
        // atan2 keeps full precision near ±90°, where asin(−r20) would not.
        let pitch = (-r20).atan2(cos_pitch);
        if cos_pitch < GIMBAL_LOCK_COS {
            // Roll = 0: the body Y axis (column 1) is Rz(ψ)·ŷ = (−sψ, cψ, 0).
            let yaw = (-r.y_axis.x).atan2(r.y_axis.y);
            let gimbal = if r20 < 0.0 {
                Gimbal::LockedNoseDown
            } else {
                Gimbal::LockedNoseUp
            };
            let pitch = if r20 < 0.0 {
                std::f64::consts::FRAC_PI_2
            } else {
                -std::f64::consts::FRAC_PI_2
            };
            return (Self::new(yaw, pitch, 0.0), gimbal);
        }
        let yaw = r10.atan2(r00);
        let roll = r.y_axis.z.atan2(r.z_axis.z);
        (Self::new(yaw, pitch, roll), Gimbal::Free)
    }

    /// The same angles normalised: ψ, φ into (−π, π], θ into [−π/2, π/2], by round-tripping
    /// through the matrix.
    pub fn canonical(self) -> (Self, Gimbal) {
        Self::from_matrix(self.to_matrix())
    }

    /// Viewer angles (world X north, Y west, Z up; body nose +X, rudder +Z) from aerospace
    /// angles (world NED, body FRD): `(−ψ, −θ, φ)`. Exact, since `D·R(ψ,θ,φ)·D = R(−ψ,−θ,φ)`
    /// with `D = diag(1, −1, −1)`.
    pub fn from_aerospace(ned: EulerZyx) -> Self {
        Self::new(-ned.yaw, -ned.pitch, ned.roll)
    }

    /// Aerospace angles (NED/FRD) from viewer angles; the inverse of
    /// [`from_aerospace`](Self::from_aerospace) (the map is its own inverse).
    pub fn to_aerospace(self) -> EulerZyx {
        Self::new(-self.yaw, -self.pitch, self.roll)
    }
}

/// World vector in the viewer frame (X north, Y west, Z up) from a NED vector.
pub fn viewer_from_ned(ned: DVec3) -> DVec3 {
    DVec3::new(ned.x, -ned.y, -ned.z)
}

/// NED vector from a viewer-frame vector; the inverse of [`viewer_from_ned`].
pub fn ned_from_viewer(v: DVec3) -> DVec3 {
    DVec3::new(v.x, -v.y, -v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_axis_rotations_turn_the_plane_as_the_seed_says() {
        let nose = DVec3::X;
        let left_wing = DVec3::Y;
        // Yaw +90°: nose swings from +X to +Y.
        assert!((rot_z(90f64.to_radians()) * nose).abs_diff_eq(DVec3::Y, 1e-15));
        // Pitch +90° about +Y: nose goes to −Z (down, in the Z-up viewer world).
        assert!((rot_y(90f64.to_radians()) * nose).abs_diff_eq(-DVec3::Z, 1e-15));
        // Roll +90° about +X: left wing goes up to +Z.
        assert!((rot_x(90f64.to_radians()) * left_wing).abs_diff_eq(DVec3::Z, 1e-15));
    }

    #[test]
    fn gimbal_lock_puts_heading_into_yaw() {
        let e = EulerZyx::from_degrees(70.0, 90.0, 25.0);
        let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
        assert_eq!(gimbal, Gimbal::LockedNoseDown);
        assert_eq!(back.roll, 0.0);
        assert!((back.yaw.to_degrees() - 45.0).abs() < 1e-9, "{back:?}");
        assert!(back.to_matrix().abs_diff_eq(e.to_matrix(), 1e-12));

        let e = EulerZyx::from_degrees(70.0, -90.0, 25.0);
        let (back, gimbal) = EulerZyx::from_matrix(e.to_matrix());
        assert_eq!(gimbal, Gimbal::LockedNoseUp);
        assert!((back.yaw.to_degrees() - 95.0).abs() < 1e-9, "{back:?}");
        assert!(back.to_matrix().abs_diff_eq(e.to_matrix(), 1e-12));
    }
}
