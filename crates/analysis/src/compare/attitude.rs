//! The attitude residuals and errors of a prediction against the measured angles, from the
//! predicted rotation and the measured angles' precomputed sines and cosines: no inverse
//! trigonometry of the predicted Euler angles in a fit's flights.

use glam::{DMat3, DVec3};

use super::Predicted;
use wireflight_flight::numeric::{attitude_error_deg, small_atan2};
use wireflight_geometry::euler::EulerZyx;

/// Predicted − measured roll, pitch and yaw, each wrapped into (−π, π], from the predicted
/// rotation and the measured angles' sines and cosines (`trig`: roll, pitch, yaw): the angle
/// of sin(a − b) and cos(a − b) written out with a's sine and cosine as the rotation matrix
/// holds them (for roll r₂₁ and r₂₂, scaled by cos θ), in one `atan2` of a small argument each
/// ([`small_atan2`]) instead of the three of the predicted Euler angles. In gimbal lock, or
/// without `trig`, from the Euler angles themselves.
pub(super) fn attitude_residuals(
    p: &Predicted,
    measured: &EulerZyx,
    trig: Option<&[f64; 6]>,
) -> [f64; 3] {
    let r = DMat3::from_quat(p.quat);
    let (r00, r10, r20) = (r.x_axis.x, r.x_axis.y, r.x_axis.z);
    let (r21, r22) = (r.y_axis.z, r.z_axis.z);
    let cos_pitch = (r00 * r00 + r10 * r10).sqrt();
    match trig {
        Some(&[sr, cr, sp, cp, sy, cy])
            if cos_pitch >= 1e3 * wireflight_geometry::euler::GIMBAL_LOCK_COS =>
        {
            [
                small_atan2(r21 * cr - r22 * sr, r22 * cr + r21 * sr),
                small_atan2(-r20 * cp - cos_pitch * sp, cos_pitch * cp - r20 * sp),
                small_atan2(r10 * cy - r00 * sy, r00 * cy + r10 * sy),
            ]
        }
        _ => {
            let pa = p.attitude();
            [
                wrap(pa.roll - measured.roll),
                wrap(pa.pitch - measured.pitch),
                wrap(pa.yaw - measured.yaw),
            ]
        }
    }
}

/// The angle between the predicted and the measured attitude, degrees
/// ([`attitude_error_deg`]), with the measured rotation built from its angles' sines and
/// cosines (`trig`, as in [`attitude_residuals`]) instead of six more.
pub(super) fn attitude_error_at(
    p: &Predicted,
    measured: &EulerZyx,
    trig: Option<&[f64; 6]>,
) -> f64 {
    let Some(&[sr, cr, sp, cp, sy, cy]) = trig else {
        return attitude_error_deg(&p.attitude(), measured);
    };
    let r = DMat3::from_quat(p.quat);
    let m = DMat3::from_cols(
        DVec3::new(cy * cp, sy * cp, -sp),
        DVec3::new(cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr),
        DVec3::new(cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr),
    );
    // tr(RᵀM) = 1 + 2·cos(angle).
    let trace = r.x_axis.dot(m.x_axis) + r.y_axis.dot(m.y_axis) + r.z_axis.dot(m.z_axis);
    ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos().to_degrees()
}

/// An angle difference wrapped into (−π, π].
pub(super) fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    // Most differences are small: no division for them.
    if a.abs() < PI {
        return a;
    }
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The attitude residuals from the rotation and the measured angles' sines and cosines
    /// are the wrapped differences of the Euler angles: small and large, across ±180° of
    /// roll and yaw, near the vertical, and in gimbal lock (where the angles themselves are
    /// used); the attitude error angle is the one from both Euler angles (to the 1e-5° an
    /// arccosine near 1 resolves: 1.2e-6° is one rounding of the trace).
    #[test]
    fn attitude_residuals_are_the_wrapped_angle_differences() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let trig = |e: &EulerZyx| {
            let ((sr, cr), (sp, cp), (sy, cy)) =
                (e.roll.sin_cos(), e.pitch.sin_cos(), e.yaw.sin_cos());
            [sr, cr, sp, cp, sy, cy]
        };
        let angles = [
            EulerZyx::new(0.3, 0.1, -0.2),
            EulerZyx::new(PI - 0.01, 0.5, -PI + 0.02),
            EulerZyx::new(-3.0, -1.2, 3.1),
            EulerZyx::new(1.0, FRAC_PI_2 - 1e-4, 0.4),
            EulerZyx::new(0.2, -FRAC_PI_2, 0.0),
        ];
        for predicted in &angles {
            for measured in &angles {
                for offset in [0.0, 1e-3, 0.05, 2.0] {
                    let pe = EulerZyx::new(
                        predicted.yaw + offset,
                        predicted.pitch,
                        predicted.roll - offset,
                    );
                    let p = Predicted {
                        quat: glam::DQuat::from_mat3(&pe.to_matrix()).normalize(),
                        ..Predicted::default()
                    };
                    let want = {
                        let a = p.attitude();
                        [
                            wrap(a.roll - measured.roll),
                            wrap(a.pitch - measured.pitch),
                            wrap(a.yaw - measured.yaw),
                        ]
                    };
                    let got = attitude_residuals(&p, measured, Some(&trig(measured)));
                    let (angle, want_angle) = (
                        attitude_error_at(&p, measured, Some(&trig(measured))),
                        attitude_error_deg(&p.attitude(), measured),
                    );
                    assert!((angle - want_angle).abs() < 1e-5, "{angle} vs {want_angle}");
                    for k in 0..3 {
                        let d = (got[k] - want[k]).abs();
                        // ±π are the same angle.
                        let d = d.min((d - 2.0 * PI).abs());
                        assert!(d < 1e-12, "{pe:?} vs {measured:?}: {got:?} vs {want:?}");
                    }
                }
            }
        }
    }
}
