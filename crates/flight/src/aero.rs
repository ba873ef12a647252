//! The fixed-wing aerodynamics of the model (Beard & McLain's, with a propeller): air data
//! of an air-relative velocity, the stall blend, and the forces and moments of the
//! aircraft's parameter set. Pure functions of their inputs; [`super::model::Model`] adds the
//! effects and integrates.

use glam::DVec3;

use super::params::{FixedWingParams, Propulsion};
use crate::numeric::small_atan2;
use wireflight_data::Controls;

/// Aerodynamic angles and airspeed of a fixed-wing state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirData {
    /// Airspeed Va, m/s.
    pub airspeed: f64,
    /// Angle of attack α, rad.
    pub alpha: f64,
    /// Sideslip β, rad.
    pub beta: f64,
    /// Air density, kg/m³.
    pub rho: f64,
    /// sin α, from the velocity's components (w/√(u² + w²): no trigonometry in the forces).
    pub sin_alpha: f64,
    /// cos α (u/√(u² + w²)).
    pub cos_alpha: f64,
}

impl Default for AirData {
    /// Still air: no airspeed, α = β = 0.
    fn default() -> Self {
        Self {
            airspeed: 0.0,
            alpha: 0.0,
            beta: 0.0,
            rho: 0.0,
            sin_alpha: 0.0,
            cos_alpha: 1.0,
        }
    }
}

/// Airspeed below which aerodynamic angles are taken as zero (no division by ~0).
const MIN_AIRSPEED: f64 = 0.1;

/// The flight-path axes of a point mass, as the columns of a rotation to NED: x along the
/// air-relative velocity, y level and to the right (the velocity's heading turned 90°
/// clockwise), z = x × y (downward, in the vertical plane of the velocity).
/// They are the body axes of a point mass that flies wings level with its nose on its
/// velocity: a force term's `X` (negative: drag), `Y` (side force) and `Z` (negative: lift).
/// Where the velocity has no horizontal part the heading is taken as north, and below
/// 0.1 m/s the axes are NED's, so they stay defined everywhere.
pub fn flight_path_axes(air_vel_ned: DVec3) -> glam::DMat3 {
    let va = air_vel_ned.length();
    let horizontal = air_vel_ned.x.hypot(air_vel_ned.y);
    let (x, y) = if va < MIN_AIRSPEED || !va.is_finite() {
        (DVec3::X, DVec3::Y)
    } else if horizontal <= 1e-9 * va {
        (air_vel_ned / va, DVec3::Y)
    } else {
        (
            air_vel_ned / va,
            DVec3::new(-air_vel_ned.y / horizontal, air_vel_ned.x / horizontal, 0.0),
        )
    };
    glam::DMat3::from_cols(x, y, x.cross(y))
}

/// Airspeed, α = atan2(w_r, u_r), β = asin(v_r/Va) of an air-relative body velocity.
///
/// β is taken as atan2(v_r, √(u_r² + w_r²)), the same angle (Va² = u_r² + w_r² + v_r²), and
/// both angles by [`small_atan2`]: in flight they are small, and the library's `atan2` and
/// `asin` were a tenth of the model's derivative.
#[inline]
pub fn air_angles(v_r: DVec3, rho: f64) -> AirData {
    let va = v_r.length();
    if va < MIN_AIRSPEED {
        return AirData {
            airspeed: va,
            alpha: 0.0,
            beta: 0.0,
            rho,
            sin_alpha: 0.0,
            cos_alpha: 1.0,
        };
    }
    // α = atan2(w, u), so sin α = w/√(u² + w²) and cos α = u/√(u² + w²); with no velocity in
    // the symmetry plane α = 0.
    // One division each for the two norms (a division costs several multiplications).
    let in_plane = (v_r.x * v_r.x + v_r.z * v_r.z).sqrt();
    let (sin_alpha, cos_alpha) = if in_plane > 0.0 {
        let inv = 1.0 / in_plane;
        (v_r.z * inv, v_r.x * inv)
    } else {
        (0.0, 1.0)
    };
    AirData {
        airspeed: va,
        alpha: small_atan2(v_r.z, v_r.x),
        beta: small_atan2(v_r.y, in_plane),
        rho,
        sin_alpha,
        cos_alpha,
    }
}

/// Stall blend σ(α) of Beard & McLain:
/// σ = (1 + e1 + e2)/((1 + e1)(1 + e2)), e1 = e^{−M(α−α0)}, e2 = e^{M(α+α0)}.
///
/// Computed as σ = a + b − a·b with the logistic terms a = 1/(1 + e1), b = 1/(1 + e2)
/// (the same expression multiplied out), which stays finite for any α where the quotient
/// of exponentials would overflow to ∞/∞.
pub fn stall_blend(alpha: f64, m: f64, alpha0: f64) -> f64 {
    let a = 1.0 / (1.0 + (-m * (alpha - alpha0)).exp());
    let b = 1.0 / (1.0 + (m * (alpha + alpha0)).exp());
    a + b - a * b
}

/// [`stall_blend`] with `c` = e^{Mα0} given (a model's, taken once): with E = e^{Mα},
/// e1 = c/E and e2 = c·E, so a = E/(E + c) and b = 1/(1 + c·E) — one exponential per
/// evaluation instead of two. Where E or c is not a finite positive number (|Mα| past 709),
/// [`stall_blend`] itself.
pub fn stall_blend_with(alpha: f64, m: f64, alpha0: f64, c: f64) -> f64 {
    let e = (m * alpha).exp();
    let sum = e + c;
    if !(e > 0.0 && sum.is_finite()) {
        return stall_blend(alpha, m, alpha0);
    }
    let a = e / sum;
    let b = 1.0 / (1.0 + c * e);
    a + b - a * b
}

/// The propeller's thrust, N: ½ρ S_prop C_prop ((k_motor δt)² − Va²).
#[inline]
pub fn propeller_thrust(prop: &Propulsion, air: &AirData, throttle: f64) -> f64 {
    let k = prop.k_motor * throttle;
    let va = air.airspeed;
    0.5 * air.rho * prop.s_prop * prop.c_prop * (k * k - va * va)
}

/// Aerodynamic and propulsive force (body) and moment (body) of the fixed-wing model.
/// `induced_factor` multiplies the induced-drag term (ground effect); `sigma` is the stall
/// blend σ(α) ([`stall_blend`], [`stall_blend_with`]).
pub fn aero_force_moment(
    p: &FixedWingParams,
    air: &AirData,
    omega: DVec3,
    ctl: &Controls,
    induced_factor: f64,
    sigma: f64,
) -> (DVec3, DVec3) {
    let lon = &p.longitudinal;
    let lat = &p.lateral;
    let geo = &p.geometry;
    let va = air.airspeed;
    let (alpha, beta) = (air.alpha, air.beta);
    let qbar_s = 0.5 * air.rho * va * va * geo.s_wing;
    // Non-dimensional rates; zero at (almost) zero airspeed where they are undefined.
    let (c2v, b2v) = if va > MIN_AIRSPEED {
        let half_inv = 0.5 / va;
        (geo.c * half_inv, geo.b * half_inv)
    } else {
        (0.0, 0.0)
    };
    let (pr, qr, rr) = (omega.x, omega.y, omega.z);

    let (sa, ca) = (air.sin_alpha, air.cos_alpha);
    let cl_lin = lon.c_l_0 + lon.c_l_alpha * alpha;
    let c_l = (1.0 - sigma) * cl_lin + sigma * 2.0 * alpha.signum() * sa * sa * ca;
    // C_L²/(π·e·AR) with AR = b²/S: one division, not two.
    let induced = geo.s_wing / (std::f64::consts::PI * geo.e * geo.b * geo.b);
    let c_d = lon.c_d_p + induced_factor * cl_lin * cl_lin * induced;

    let lift = qbar_s * (c_l + lon.c_l_q * c2v * qr + lon.c_l_delta_e * ctl.elevator);
    let drag = qbar_s * (c_d + lon.c_d_q * c2v * qr + lon.c_d_delta_e * ctl.elevator);
    let fx_aero = -drag * ca + lift * sa;
    let fz = -drag * sa - lift * ca;
    let fy = qbar_s
        * (lat.c_y_0
            + lat.c_y_beta * beta
            + lat.c_y_p * b2v * pr
            + lat.c_y_r * b2v * rr
            + lat.c_y_delta_a * ctl.aileron
            + lat.c_y_delta_r * ctl.rudder);
    let thrust = propeller_thrust(&p.propulsion, air, ctl.throttle);

    let l = qbar_s
        * geo.b
        * (lat.c_ell_0
            + lat.c_ell_beta * beta
            + lat.c_ell_p * b2v * pr
            + lat.c_ell_r * b2v * rr
            + lat.c_ell_delta_a * ctl.aileron
            + lat.c_ell_delta_r * ctl.rudder);
    let m = qbar_s
        * geo.c
        * (lon.c_m_0
            + lon.c_m_alpha * alpha
            + lon.c_m_q * c2v * qr
            + lon.c_m_delta_e * ctl.elevator);
    let n = qbar_s
        * geo.b
        * (lat.c_n_0
            + lat.c_n_beta * beta
            + lat.c_n_p * b2v * pr
            + lat.c_n_r * b2v * rr
            + lat.c_n_delta_a * ctl.aileron
            + lat.c_n_delta_r * ctl.rudder);
    (DVec3::new(fx_aero + thrust, fy, fz), DVec3::new(l, m, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flight-path axes: x along the velocity, y level and to its right, z = x × y; a
    /// vertical or vanishing velocity still gives a rotation.
    #[test]
    fn flight_path_axes_follow_the_velocity_and_stay_a_rotation() {
        let climbing_east = flight_path_axes(DVec3::new(0.0, 30.0, -40.0));
        assert!((climbing_east.x_axis - DVec3::new(0.0, 0.6, -0.8)).length() < 1e-12);
        assert!((climbing_east.y_axis - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
        assert!((climbing_east.z_axis - DVec3::new(0.0, 0.8, 0.6)).length() < 1e-12);
        for v in [
            DVec3::new(0.0, 0.0, 50.0),
            DVec3::new(0.0, 0.0, -1e-12),
            DVec3::new(3.0, -4.0, 1.0),
        ] {
            let r = flight_path_axes(v);
            assert!((r.determinant() - 1.0).abs() < 1e-12, "{v}");
            assert!(
                (r.transpose() * r).abs_diff_eq(glam::DMat3::IDENTITY, 1e-12),
                "{v}"
            );
            assert_eq!(r.y_axis.z, 0.0, "level: {v}");
        }
    }

    /// The one-exponential stall blend is the two-exponential one to rounding (1e-13: an
    /// exponent of 25 carries 25 units in the last place into either), across α and
    /// sharpnesses, and is that one itself where the exponentials overflow.
    #[test]
    fn stall_blend_with_one_exponential_is_the_blend() {
        for m in [0.5f64, 50.0, 500.0, 5000.0] {
            for alpha0 in [0.1, 0.4712] {
                let c = (m * alpha0).exp();
                for i in -700..=700 {
                    let alpha = i as f64 * std::f64::consts::PI / 700.0;
                    let (got, want) = (
                        stall_blend_with(alpha, m, alpha0, c),
                        stall_blend(alpha, m, alpha0),
                    );
                    assert!(
                        (got - want).abs() <= 1e-13,
                        "M {m}, α0 {alpha0}, α {alpha}: {got} vs {want}"
                    );
                }
            }
        }
    }
}
