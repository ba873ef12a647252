//! Angles in any of the 24 conventions ↔ rotation matrices and unit quaternions, conversion
//! between conventions, and gimbal lock.
//!
//! Every matrix is built from one written-out formula for Tait–Bryan and one for proper Euler
//! (intrinsic; an extrinsic convention is the intrinsic one with the axes and angles reversed),
//! and every inverse reads well-conditioned pairs of elements with `atan2`. For intrinsic z-y-x
//! both are the same floating-point operations as [`EulerZyx`], so the two agree bit for bit.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::{DMat3, DQuat};

use super::sequence::{Convention, Frame, Sequence};
use super::zyx::{EulerZyx, Gimbal, GIMBAL_LOCK_COS};

/// Below this, cos β (Tait–Bryan) or |sin β| (proper Euler) of the middle angle β counts as
/// gimbal lock: the same 1e-9 as [`GIMBAL_LOCK_COS`], about 6e-8 degrees from the singular
/// value. There an error δ in the matrix moves the first and third angles by about δ / 1e-9
/// (their split is conditioned by 1/cos β resp. 1/sin β), so the lock rule is used instead.
pub const LOCK_TOLERANCE: f64 = GIMBAL_LOCK_COS;

/// Whether the middle angle β is at a singular value (gimbal lock).
///
/// At lock the first and third axes coincide (up to sign), so only their sum or difference is
/// determined; see the module docs for the answer given there.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Lock {
    /// β is away from both ends of its range: the three angles are unique in their ranges.
    #[default]
    Free,
    /// β is at the low end of its range: −90° (Tait–Bryan) or 0° (proper Euler).
    Lower,
    /// β is at the high end of its range: +90° (Tait–Bryan) or 180° (proper Euler).
    Upper,
}

impl Lock {
    /// True at either end.
    pub fn is_locked(self) -> bool {
        self != Lock::Free
    }
}

/// Three angles in radians and the convention that gives them meaning.
///
/// `angles[0..3]` go with the convention's axes in order: for intrinsic z-y-x they are yaw,
/// pitch and roll. They build the active body → world rotation (module docs). Any finite values
/// are accepted; the inverse conversions return the principal values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EulerAngles {
    /// What the angles mean.
    pub convention: Convention,
    /// α, β, γ in radians, in the order of the convention's axes.
    pub angles: [f64; 3],
}

/// The answer of an inverse conversion: the principal angles and whether gimbal lock was hit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Solution {
    /// The angles, in the requested convention, in the documented ranges.
    pub euler: EulerAngles,
    /// Whether the middle angle was at a singular value; if so the lock rule was applied.
    pub lock: Lock,
}

/// Why [`EulerAngles::try_from_matrix`] refused a matrix.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum NotRotation {
    /// An element is NaN or infinite.
    #[error("the matrix has a non-finite element")]
    NonFinite,
    /// `max |RᵀR − I|` is above the tolerance.
    #[error("the matrix is not orthonormal: max |RᵀR − I| = {deviation:e} > {tolerance:e}")]
    NotOrthonormal {
        /// `max |RᵀR − I|` over the nine elements.
        deviation: f64,
        /// The tolerance it was held to.
        tolerance: f64,
    },
    /// Orthonormal but with determinant ≤ 0: a reflection, not a rotation.
    #[error("the matrix is a reflection, not a rotation (det = {det})")]
    Reflection {
        /// Its determinant.
        det: f64,
    },
}

/// `x`, except −π becomes π, so that an `atan2` result lies in (−π, π].
fn principal(x: f64) -> f64 {
    if x == -PI {
        PI
    } else {
        x
    }
}

/// Axis indices `(a, b, c)` of an intrinsic sequence, c being the third axis for Tait–Bryan and
/// the unused one for proper Euler, and the parity ε (+1 when a → b is cyclic x → y → z).
fn indices(sequence: Sequence) -> (usize, usize, usize, f64) {
    let [a, b, _] = sequence.axes().map(|axis| axis.index());
    (a, b, 3 - a - b, sequence.parity())
}

/// `R_a(α)·R_b(β)·R_c(γ)` for the intrinsic `sequence`, written out.
///
/// With `m[col][row]` and ε the parity. Tait–Bryan a-b-c:
///
/// ```text
///          col a                  col b                  col c
/// row a  | cβcγ                   −ε cβsγ                ε sβ     |
/// row b  | sαsβcγ + ε cαsγ        cαcγ − ε sαsβsγ        −ε sαcβ  |
/// row c  | sαsγ − ε cαsβcγ        cαsβsγ + ε sαcγ        cαcβ     |
/// ```
///
/// proper Euler a-b-a (c the unused axis):
///
/// ```text
/// row a  | cβ                     sβsγ                   ε sβcγ              |
/// row b  | sαsβ                   cαcγ − sαcβsγ          −ε (sαcβcγ + cαsγ)  |
/// row c  | −ε cαsβ                ε (sαcγ + cαcβsγ)      cαcβcγ − sαsγ       |
/// ```
///
/// The products are grouped as in [`EulerZyx::to_matrix`], so intrinsic z-y-x is bit-identical.
fn intrinsic_matrix(sequence: Sequence, [alpha, beta, gamma]: [f64; 3]) -> DMat3 {
    let (a, b, c, e) = indices(sequence);
    let (sa, ca) = alpha.sin_cos();
    let (sb, cb) = beta.sin_cos();
    let (sg, cg) = gamma.sin_cos();
    let mut m = [[0.0; 3]; 3];
    if sequence.is_tait_bryan() {
        m[a][a] = cb * cg;
        m[a][b] = sa * sb * cg + e * (ca * sg);
        m[a][c] = sa * sg - e * (ca * sb * cg);
        m[b][a] = -e * (cb * sg);
        m[b][b] = ca * cg - e * (sa * sb * sg);
        m[b][c] = ca * sb * sg + e * (sa * cg);
        m[c][a] = e * sb;
        m[c][b] = -e * (sa * cb);
        m[c][c] = ca * cb;
    } else {
        m[a][a] = cb;
        m[a][b] = sa * sb;
        m[a][c] = -e * (ca * sb);
        m[b][a] = sb * sg;
        m[b][b] = ca * cg - sa * cb * sg;
        m[b][c] = e * (sa * cg + ca * cb * sg);
        m[c][a] = e * (sb * cg);
        m[c][b] = -e * (sa * cb * cg + ca * sg);
        m[c][c] = ca * cb * cg - sa * sg;
    }
    DMat3::from_cols_array_2d(&m)
}

/// Principal intrinsic angles of `m` for `sequence`, with the lock rule (third angle 0). The
/// caller has checked that `m` is finite.
///
/// With m_xy = `m[x][y]` (column x, row y) as in [`intrinsic_matrix`].
/// Tait–Bryan: cβ = |(m_cc, m_cb)| from column c, β = atan2(ε·m_ca, cβ) ∈ [−π/2, π/2];
/// α = atan2(−ε·m_cb, m_cc) from column c, γ = atan2(−ε·m_ba, m_aa) from row a (the same
/// elements and operations as [`EulerZyx::from_matrix`]). Proper Euler: sβ = |(m_ab, m_ac)|
/// from column a, β = atan2(sβ, m_aa) ∈ [0, π]; α = atan2(m_ab, −ε·m_ac), γ = atan2(m_ba,
/// ε·m_ca) from row a. At lock γ = 0 and α = atan2(ε·m_bc, m_bb), read from column b, which is
/// then `R_a(α)·ê_b` whatever β is.
fn intrinsic_angles(sequence: Sequence, r: DMat3) -> ([f64; 3], Lock) {
    let (a, b, c, e) = indices(sequence);
    let m = r.to_cols_array_2d();
    let locked_alpha = || principal((e * m[b][c]).atan2(m[b][b]));
    if sequence.is_tait_bryan() {
        let cos_beta = m[c][c].hypot(m[c][b]);
        let sin_beta = e * m[c][a];
        if cos_beta < LOCK_TOLERANCE {
            let (beta, lock) = if sin_beta > 0.0 {
                (FRAC_PI_2, Lock::Upper)
            } else {
                (-FRAC_PI_2, Lock::Lower)
            };
            return ([locked_alpha(), beta, 0.0], lock);
        }
        let alpha = (-e * m[c][b]).atan2(m[c][c]);
        let gamma = (-e * m[b][a]).atan2(m[a][a]);
        let beta = sin_beta.atan2(cos_beta);
        ([principal(alpha), beta, principal(gamma)], Lock::Free)
    } else {
        let sin_beta = m[a][b].hypot(m[a][c]);
        if sin_beta < LOCK_TOLERANCE {
            let (beta, lock) = if m[a][a] < 0.0 {
                (PI, Lock::Upper)
            } else {
                (0.0, Lock::Lower)
            };
            return ([locked_alpha(), beta, 0.0], lock);
        }
        let alpha = m[a][b].atan2(-e * m[a][c]);
        let gamma = m[b][a].atan2(e * m[c][a]);
        let beta = sin_beta.atan2(m[a][a]);
        ([principal(alpha), beta, principal(gamma)], Lock::Free)
    }
}

/// Rotation matrix of a quaternion of any non-zero length (normalised first, by scaling with its
/// largest component so that no square overflows). Zero or non-finite → all NaN.
fn rotation_of_quat(q: DQuat) -> DMat3 {
    let big = q.x.abs().max(q.y.abs()).max(q.z.abs()).max(q.w.abs());
    if !(big > 0.0 && big.is_finite()) {
        return DMat3::from_cols_array(&[f64::NAN; 9]);
    }
    let [x, y, z, w] = (q / big).to_array();
    let s = 2.0 / (x * x + y * y + z * z + w * w);
    DMat3::from_cols_array_2d(&[
        [
            1.0 - s * (y * y + z * z),
            s * (x * y + z * w),
            s * (x * z - y * w),
        ],
        [
            s * (x * y - z * w),
            1.0 - s * (x * x + z * z),
            s * (y * z + x * w),
        ],
        [
            s * (x * z + y * w),
            s * (y * z - x * w),
            1.0 - s * (x * x + y * y),
        ],
    ])
}

impl EulerAngles {
    /// Angles in radians, in the order of `convention`'s axes.
    pub const fn new(convention: Convention, angles: [f64; 3]) -> Self {
        Self { convention, angles }
    }

    /// Angles given in degrees, in the order of `convention`'s axes.
    pub fn from_degrees(convention: Convention, degrees: [f64; 3]) -> Self {
        Self::new(convention, degrees.map(f64::to_radians))
    }

    /// The angles in degrees.
    pub fn to_degrees(self) -> [f64; 3] {
        self.angles.map(f64::to_degrees)
    }

    /// True when all three angles are finite.
    pub fn is_finite(self) -> bool {
        self.angles.iter().all(|a| a.is_finite())
    }

    /// The same rotation in the other frame: intrinsic a-b-c (α, β, γ) ↔ extrinsic c-b-a
    /// (γ, β, α). Exact (nothing is computed).
    pub fn other_frame(self) -> Self {
        let [x, y, z] = self.angles;
        Self::new(self.convention.other_frame(), [z, y, x])
    }

    /// The same angles read as intrinsic (see [`Convention::as_intrinsic`]).
    fn as_intrinsic(self) -> Self {
        match self.convention.frame {
            Frame::Intrinsic => self,
            Frame::Extrinsic => self.other_frame(),
        }
    }

    /// Active body → world rotation matrix: `R_a(α)·R_b(β)·R_c(γ)` for intrinsic a-b-c,
    /// `R_c(γ)·R_b(β)·R_a(α)` for extrinsic a-b-c. Non-finite angles give NaN elements.
    ///
    /// ```
    /// use wireflight_geometry::euler::{Axis, Convention, EulerAngles};
    /// let e = EulerAngles::from_degrees("zxz".parse().unwrap(), [30.0, 20.0, 10.0]);
    /// let [a, b, c] = e.angles;
    /// let product = Axis::Z.rotation(a) * Axis::X.rotation(b) * Axis::Z.rotation(c);
    /// assert!(e.to_matrix().abs_diff_eq(product, 1e-15));
    /// let fixed: Convention = "zxz,extrinsic".parse().unwrap();
    /// let product = Axis::Z.rotation(c) * Axis::X.rotation(b) * Axis::Z.rotation(a);
    /// assert!(EulerAngles::new(fixed, e.angles).to_matrix().abs_diff_eq(product, 1e-15));
    /// ```
    pub fn to_matrix(self) -> DMat3 {
        let e = self.as_intrinsic();
        intrinsic_matrix(e.convention.sequence, e.angles)
    }

    /// The unit quaternion of [`to_matrix`](Self::to_matrix), `q_a(α)·q_b(β)·q_c(γ)` for
    /// intrinsic a-b-c, with w ≥ 0 (of the two quaternions ±q of a rotation). Non-finite angles
    /// give NaN components.
    pub fn to_quat(self) -> DQuat {
        let e = self.as_intrinsic();
        let [a, b, c] = e.convention.sequence.axes();
        let [alpha, beta, gamma] = e.angles;
        let q = a.quat(alpha) * b.quat(beta) * c.quat(gamma);
        if q.w < 0.0 {
            -q
        } else {
            q
        }
    }

    /// The principal angles of rotation matrix `r` in `convention`, and whether gimbal lock
    /// was hit. Never panics.
    ///
    /// Ranges: Tait–Bryan α, γ ∈ (−π, π], β ∈ [−π/2, π/2]; proper Euler α, γ ∈ (−π, π],
    /// β ∈ [0, π]. At lock (cos β resp. |sin β| < [`LOCK_TOLERANCE`]) β is set to the end of its
    /// range and the rule of the module docs applies (intrinsic: γ = 0; extrinsic: α = 0), so
    /// `to_matrix` of the answer reproduces `r` (to about the tolerance).
    ///
    /// `r` should be a rotation; no check is made (see [`try_from_matrix`](Self::try_from_matrix)).
    /// Five elements are read (Tait–Bryan: column c and row a of the intrinsic reading; proper
    /// Euler: column a and row a) through `atan2` of pairs, so a positive uniform scale does not
    /// change the answer away from lock, and a matrix near a rotation gives angles near that
    /// rotation's. A finite matrix always gives finite angles. A matrix with any non-finite
    /// element gives NaN angles and [`Lock::Free`].
    pub fn from_matrix(convention: Convention, r: DMat3) -> Solution {
        if !r.is_finite() {
            return Solution {
                euler: Self::new(convention, [f64::NAN; 3]),
                lock: Lock::Free,
            };
        }
        let intrinsic = convention.as_intrinsic();
        let (angles, lock) = intrinsic_angles(intrinsic.sequence, r);
        let euler = Self::new(intrinsic, angles);
        let euler = if convention == intrinsic {
            euler
        } else {
            euler.other_frame()
        };
        Solution { euler, lock }
    }

    /// [`from_matrix`](Self::from_matrix) after checking that `r` is a rotation:
    /// finite, `max |RᵀR − I| ≤ tolerance`, det > 0.
    ///
    /// # Errors
    ///
    /// [`NotRotation`] saying which check failed.
    pub fn try_from_matrix(
        convention: Convention,
        r: DMat3,
        tolerance: f64,
    ) -> Result<Solution, NotRotation> {
        if !r.is_finite() {
            return Err(NotRotation::NonFinite);
        }
        let deviation = (r.transpose() * r - DMat3::IDENTITY)
            .to_cols_array()
            .into_iter()
            .fold(0.0, |m: f64, d| m.max(d.abs()));
        // A NaN tolerance accepts nothing.
        if deviation > tolerance || tolerance.is_nan() {
            return Err(NotRotation::NotOrthonormal {
                deviation,
                tolerance,
            });
        }
        let det = r.determinant();
        if det <= 0.0 {
            return Err(NotRotation::Reflection { det });
        }
        Ok(Self::from_matrix(convention, r))
    }

    /// The principal angles of quaternion `q` in `convention` (through its matrix, as
    /// [`from_matrix`](Self::from_matrix)). `q` and `−q` give the same answer; a non-unit `q`
    /// is normalised first; a zero or non-finite `q` gives NaN angles and [`Lock::Free`].
    pub fn from_quat(convention: Convention, q: DQuat) -> Solution {
        Self::from_matrix(convention, rotation_of_quat(q))
    }

    /// The same rotation in another convention: the principal angles of `to`, with the lock
    /// rule where `to`'s middle angle is singular. Converting to `self.convention` gives
    /// [`canonical`](Self::canonical).
    pub fn convert(self, to: Convention) -> Solution {
        Self::from_matrix(to, self.to_matrix())
    }

    /// The principal angles of the same rotation in the same convention.
    pub fn canonical(self) -> Solution {
        self.convert(self.convention)
    }

    /// Whether these angles put the middle angle at a singular value (modulo 2π): cos β (Tait–
    /// Bryan) or |sin β| (proper Euler) below [`LOCK_TOLERANCE`]. NaN angles are
    /// [`Lock::Free`].
    pub fn lock(self) -> Lock {
        let (sin_beta, cos_beta) = self.angles[1].sin_cos();
        if self.convention.sequence.is_tait_bryan() {
            match (cos_beta.abs() < LOCK_TOLERANCE, sin_beta > 0.0) {
                (false, _) => Lock::Free,
                (true, true) => Lock::Upper,
                (true, false) => Lock::Lower,
            }
        } else {
            match (sin_beta.abs() < LOCK_TOLERANCE, cos_beta > 0.0) {
                (false, _) => Lock::Free,
                (true, true) => Lock::Lower,
                (true, false) => Lock::Upper,
            }
        }
    }
}

impl From<EulerZyx> for EulerAngles {
    /// Intrinsic z-y-x with `[yaw, pitch, roll]`: the same rotation, exactly.
    fn from(e: EulerZyx) -> Self {
        Self::new(Convention::VIEWER, [e.yaw, e.pitch, e.roll])
    }
}

impl Solution {
    /// For an intrinsic z-y-x solution, the same answer as [`EulerZyx::from_matrix`] gives:
    /// angles and [`Gimbal`] (`Upper` = `LockedNoseDown` at θ = +90°, `Lower` = `LockedNoseUp`).
    /// `None` for any other convention.
    pub fn to_zyx(self) -> Option<(EulerZyx, Gimbal)> {
        if self.euler.convention != Convention::VIEWER {
            return None;
        }
        let [yaw, pitch, roll] = self.euler.angles;
        let gimbal = match self.lock {
            Lock::Free => Gimbal::Free,
            Lock::Upper => Gimbal::LockedNoseDown,
            Lock::Lower => Gimbal::LockedNoseUp,
        };
        Some((EulerZyx::new(yaw, pitch, roll), gimbal))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::euler::Axis;

    /// At lock the first angle takes the whole rotation: for Tait–Bryan a-b-c at β = ±90°,
    /// α + ε·sign(β)·γ; for proper Euler a-b-a, α + γ at β = 0 and α − γ at β = 180°.
    #[test]
    fn lock_puts_the_whole_turn_into_the_first_angle() {
        let (alpha, gamma) = (0.7, -0.3);
        for sequence in Sequence::ALL {
            let e = sequence.parity();
            let cases: [(f64, f64, Lock); 2] = if sequence.is_tait_bryan() {
                [
                    (FRAC_PI_2, alpha + e * gamma, Lock::Upper),
                    (-FRAC_PI_2, alpha - e * gamma, Lock::Lower),
                ]
            } else {
                [
                    (0.0, alpha + gamma, Lock::Lower),
                    (PI, alpha - gamma, Lock::Upper),
                ]
            };
            for (beta, first, lock) in cases {
                let given = EulerAngles::new(Convention::intrinsic(sequence), [alpha, beta, gamma]);
                assert_eq!(given.lock(), lock);
                let s = given.canonical();
                assert_eq!(s.lock, lock, "{sequence} β = {beta}");
                let [a, b, c] = s.euler.angles;
                assert!(
                    (a - first).abs() < 1e-12,
                    "{sequence} β = {beta}: {a} vs {first}"
                );
                assert_eq!((b, c), (beta, 0.0));
                // Extrinsic: the mirror image, the first angle 0.
                let s = given.other_frame().canonical();
                assert_eq!(s.euler.angles[0], 0.0);
                assert!((s.euler.angles[2] - first).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn elemental_quaternions_match_elemental_matrices() {
        for axis in Axis::ALL {
            for deg in [-170.0, -90.0, 0.0, 45.0, 180.0] {
                let angle = f64::to_radians(deg);
                let m = rotation_of_quat(axis.quat(angle));
                assert!(m.abs_diff_eq(axis.rotation(angle), 1e-15), "{axis} {deg}");
                // Any length: the same rotation.
                let m = rotation_of_quat(axis.quat(angle) * -3e200);
                assert!(m.abs_diff_eq(axis.rotation(angle), 1e-15), "{axis} {deg}");
            }
        }
        assert!(rotation_of_quat(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)).is_nan());
    }
}
