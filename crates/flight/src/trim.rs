//! Trim: the steady, straight, wings-level flight of a fixed-wing model at a given airspeed,
//! in whatever effects the model has (wind, density, propeller torque, …).
//!
//! Unknowns z = (α, β, θ, φ, δe, δa, δr, δt); residuals: the six body accelerations
//! (u̇, v̇, ẇ, ṗ, q̇, ṙ), the inertial climb rate ḋ, and β itself (so a side force is balanced
//! by bank, not by sideslip). Eight equations, eight unknowns, solved by Newton's method with a
//! central-difference Jacobian and step halving. Body rates are zero: straight flight.

use glam::DVec3;

use super::model::{Model, State, Vehicle};
use wireflight_data::Controls;
use wireflight_geometry::euler::EulerZyx;

/// A trimmed flight condition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trim {
    /// The state (position as given, attitude, body velocity, zero rates, surfaces = commands).
    pub state: State,
    /// The commands that hold it.
    pub controls: Controls,
    /// Angle of attack, rad.
    pub alpha: f64,
    /// Largest absolute residual left (accelerations m/s², rad/s², climb rate m/s).
    pub residual: f64,
}

const N: usize = 8;

/// Why a model cannot be trimmed at an airspeed: the aircraft cannot fly that condition.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TrimError {
    /// The model is a point mass.
    #[error("trim needs a fixed-wing model")]
    NotFixedWing,
    /// The airspeed is zero, negative or not finite.
    #[error("no trim at airspeed {0} m/s: level flight needs a positive airspeed")]
    Airspeed(f64),
    /// The model's accelerations are not finite at the starting guess.
    #[error(
        "no trim at {0} m/s: the model's accelerations are not finite there (an effect \
         parameter such as the wind, or the parameter set, is beyond what can fly)"
    )]
    NotFinite(f64),
    /// No unknown (or every one) changes the accelerations: Newton's step cannot be taken.
    #[error(
        "no trim at {0} m/s: the controls and attitude hardly change the accelerations \
         (is the mass or an inertia far too large, or the air density or wing area far too \
         small, for this airspeed?)"
    )]
    Unresponsive(f64),
    /// Some unknowns change nothing in the equations of motion (in words that point at the
    /// input responsible).
    #[error("no trim at {va} m/s: {} changes nothing in the equations of motion", .dead.join(", "))]
    DeadUnknowns {
        /// The airspeed, m/s.
        va: f64,
        /// The unknowns that change nothing.
        dead: Vec<&'static str>,
    },
    /// Newton's method left a residual above 1e-6.
    #[error(
        "no trim at {va} m/s (residual {residual:.2e}): the aircraft cannot hold that speed level"
    )]
    NoConvergence {
        /// The airspeed, m/s.
        va: f64,
        /// The largest residual left.
        residual: f64,
    },
    /// The trim found is beyond the stall angle α0.
    #[error(
        "no trim at {va} m/s below the stall: it would need α = {:.0}° (stall at {:.0}°)",
        .alpha.to_degrees(),
        .alpha0.to_degrees()
    )]
    Stalled {
        /// The airspeed, m/s.
        va: f64,
        /// The angle of attack of the trim, rad.
        alpha: f64,
        /// The stall angle, rad.
        alpha0: f64,
    },
    /// The trim needs a throttle outside 0..1.
    #[error("trim at {va} m/s needs throttle {throttle:.2}, outside 0..1")]
    Throttle {
        /// The airspeed, m/s.
        va: f64,
        /// The throttle it would need.
        throttle: f64,
    },
}

fn build(model: &Model, z: &[f64; N], va: f64, yaw: f64, pos: DVec3) -> (State, Controls) {
    let [alpha, beta, theta, phi, de, da, dr, dt] = *z;
    let attitude = EulerZyx::new(yaw, theta, phi);
    let mut x = State::default();
    x.set_pos_ned(pos);
    x.set_attitude(attitude);
    let v_air = va
        * DVec3::new(
            alpha.cos() * beta.cos(),
            beta.sin(),
            alpha.sin() * beta.cos(),
        );
    let wind = model.wind_at(pos, 0.0);
    x.set_vel(v_air + attitude.to_matrix().transpose() * wind);
    x.set_surfaces(DVec3::new(de, da, dr));
    let cmd = Controls {
        throttle: dt,
        elevator: de,
        aileron: da,
        rudder: dr,
    };
    (x, cmd)
}

fn residuals(model: &Model, z: &[f64; N], va: f64, yaw: f64, pos: DVec3) -> [f64; N] {
    let (x, cmd) = build(model, z, va, yaw, pos);
    let d = model.derivative(0.0, &x, &cmd);
    [
        d.0[3], d.0[4], d.0[5], d.0[10], d.0[11], d.0[12], d.0[2], z[1],
    ]
}

/// Trim a fixed-wing model for straight, wings-level flight at airspeed `va` (m/s), heading
/// `yaw` (rad), position `pos_ned`.
///
/// # Errors
/// A point-mass model, no trim found, a trim beyond the stall angle α0 (residual above 1e-6 after 50 iterations, or a
/// throttle outside 0..1): the aircraft cannot fly that condition.
pub fn trim_level(model: &Model, va: f64, yaw: f64, pos_ned: DVec3) -> Result<Trim, TrimError> {
    if !matches!(model.vehicle, Vehicle::FixedWing(_)) {
        return Err(TrimError::NotFixedWing);
    }
    if !(va.is_finite() && va > 0.0) {
        return Err(TrimError::Airspeed(va));
    }
    let norm = |r: &[f64; N]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut z = [0.05, 0.0, 0.05, 0.0, -0.1, 0.0, 0.0, 0.5];
    let mut r = residuals(model, &z, va, yaw, pos_ned);
    if !r.iter().all(|v| v.is_finite()) {
        return Err(TrimError::NotFinite(va));
    }
    for _ in 0..50 {
        if norm(&r) < 1e-10 {
            break;
        }
        let mut jac = [[0.0; N]; N];
        for j in 0..N {
            let h = 1e-6 * z[j].abs().max(1.0);
            let mut zp = z;
            let mut zm = z;
            zp[j] += h;
            zm[j] -= h;
            let rp = residuals(model, &zp, va, yaw, pos_ned);
            let rm = residuals(model, &zm, va, yaw, pos_ned);
            for i in 0..N {
                jac[i][j] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
        let Some(step) = crate::numeric::solve(jac, r.map(|v| -v)) else {
            return Err(singular_trim(&jac, va));
        };
        // Step halving: accept the first fraction of the Newton step that reduces |r|.
        let mut lambda = 1.0;
        loop {
            let mut zn = z;
            for i in 0..N {
                zn[i] += lambda * step[i];
            }
            let rn = residuals(model, &zn, va, yaw, pos_ned);
            if norm(&rn) < norm(&r) || lambda < 1e-3 {
                z = zn;
                r = rn;
                break;
            }
            lambda *= 0.5;
        }
    }
    let residual = norm(&r);
    if residual.is_nan() || residual >= 1e-6 {
        return Err(TrimError::NoConvergence { va, residual });
    }
    let (state, controls) = build(model, &z, va, yaw, pos_ned);
    if let Vehicle::FixedWing(p) = &model.vehicle {
        // Newton also finds "trims" hanging on the propeller beyond the stall; reject them.
        if z[0].abs() >= p.longitudinal.alpha0 {
            return Err(TrimError::Stalled {
                va,
                alpha: z[0],
                alpha0: p.longitudinal.alpha0,
            });
        }
    }
    if !(0.0..=1.0).contains(&controls.throttle) {
        return Err(TrimError::Throttle {
            va,
            throttle: controls.throttle,
        });
    }
    Ok(Trim {
        state,
        controls,
        alpha: z[0],
        residual,
    })
}

/// Why the trim's Newton step cannot be taken: which unknowns change nothing (a zero column
/// of the Jacobian), in words that point at the input responsible.
fn singular_trim(jac: &[[f64; N]; N], va: f64) -> TrimError {
    const UNKNOWNS: [&str; N] = [
        "the angle of attack",
        "the sideslip",
        "the pitch angle",
        "the bank angle",
        "the elevator",
        "the aileron",
        "the rudder",
        "the throttle (is the thrust zero: k_motor, s_prop or c_prop?)",
    ];
    let size = |j: usize| (0..N).fold(0.0f64, |m, i| m.max(jac[i][j].abs()));
    let largest = (0..N).map(size).fold(0.0f64, f64::max);
    let dead: Vec<&str> = (0..N)
        .filter(|&j| size(j) <= 1e-9 * largest || size(j).is_nan())
        .map(|j| UNKNOWNS[j])
        .collect();
    if dead.is_empty() || dead.len() == N {
        TrimError::Unresponsive(va)
    } else {
        TrimError::DeadUnknowns { va, dead }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{Origin, Wind};
    use crate::params::FixedWingParams;

    fn aerosonde() -> Model {
        Model::new(
            Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
            Origin::default(),
        )
    }

    #[test]
    fn aerosonde_trims_at_25_mps_with_sensible_controls() {
        let t = trim_level(&aerosonde(), 25.0, 0.3, DVec3::new(0.0, 0.0, -100.0)).unwrap();
        assert!(t.alpha > 0.0 && t.alpha < 0.15, "alpha {}", t.alpha);
        assert!(
            t.controls.throttle > 0.2 && t.controls.throttle < 1.0,
            "{:?}",
            t.controls
        );
        assert!(t.controls.elevator.abs() < 0.3);
        assert!(t.controls.aileron.abs() < 1e-9 && t.controls.rudder.abs() < 1e-9);
        let e = t.state.attitude();
        assert!((e.yaw - 0.3).abs() < 1e-9 && e.roll.abs() < 1e-9);
    }

    #[test]
    fn a_trimmed_airplane_feels_one_g_upwards_along_its_own_vertical() {
        // Steady, level, unaccelerated: the accelerometer reads the lift's and thrust's
        // answer to gravity, −g along NED down, seen in body axes; the trim's nose-up pitch
        // turns part of it onto +x.
        let m = aerosonde();
        let t = trim_level(&m, 25.0, 0.3, DVec3::new(0.0, 0.0, -100.0)).unwrap();
        let f = m.specific_force(0.0, &t.state, &t.controls);
        let expected = t.state.rot().transpose() * DVec3::new(0.0, 0.0, -wireflight_data::G0);
        let tol = 1e-6 + 2.0 * t.residual;
        assert!((f - expected).length() < tol, "{f} vs {expected}");
        let theta = t.state.attitude().pitch;
        assert!(
            theta > 0.0 && (f.x - wireflight_data::G0 * theta.sin()).abs() < tol,
            "{f}"
        );
    }

    #[test]
    fn trim_in_wind_is_steady_relative_to_the_air() {
        let mut m = aerosonde();
        m.add_effect(Box::new(Wind {
            ned: DVec3::new(5.0, -3.0, 0.0),
        }))
        .unwrap();
        let t = trim_level(&m, 25.0, 0.0, DVec3::new(0.0, 0.0, -100.0)).unwrap();
        assert!((m.air_data(0.0, &t.state).airspeed - 25.0).abs() < 1e-9);
        let ground_vel = t.state.rot() * t.state.vel();
        assert!(
            (ground_vel - DVec3::new(25.0 * 0.0f64.cos() + 5.0, -3.0, 0.0)).length() < 0.05,
            "{ground_vel}"
        );
    }
}
