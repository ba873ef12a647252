//! refsim's fixed-wing model: Euler-angle state, forces and moments, full inertia matrix.

use super::*;

/// Controls, radians for the surfaces, throttle 0..1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Controls {
    pub throttle: f64,
    pub elevator: f64,
    pub aileron: f64,
    pub rudder: f64,
}

/// Indices into the 15-element fixed-wing state.
pub mod ix {
    pub const N: usize = 0;
    pub const E: usize = 1;
    pub const D: usize = 2;
    pub const U: usize = 3;
    pub const V: usize = 4;
    pub const W: usize = 5;
    pub const PHI: usize = 6;
    pub const THETA: usize = 7;
    pub const PSI: usize = 8;
    pub const P: usize = 9;
    pub const Q: usize = 10;
    pub const R: usize = 11;
    pub const DE: usize = 12;
    pub const DA: usize = 13;
    pub const DR: usize = 14;
}

/// Fixed-wing state: [n, e, d, u, v, w, φ, θ, ψ, p, q, r, δe_s, δa_s, δr_s].
pub type FwState = [f64; 15];

/// Stall-blend σ(α) of the spec.
pub fn stall_sigma(m: f64, alpha0: f64, alpha: f64) -> f64 {
    let a = (-m * (alpha - alpha0)).exp();
    let b = (m * (alpha + alpha0)).exp();
    (1.0 + a + b) / ((1.0 + a) * (1.0 + b))
}

/// C_L(α) with the stall blend.
pub fn c_lift(p: &Params, alpha: f64) -> f64 {
    let s = stall_sigma(p.m_blend, p.alpha0, alpha);
    let sgn = if alpha > 0.0 {
        1.0
    } else if alpha < 0.0 {
        -1.0
    } else {
        0.0
    };
    let sa = alpha.sin();
    (1.0 - s) * (p.c_l_0 + p.c_l_alpha * alpha) + s * 2.0 * sgn * sa * sa * alpha.cos()
}

/// C_D(α) = C_Dp + induced·(C_L0 + C_Lα α)²/(π e AR); `induced` is the ground-effect factor (1 = none).
pub fn c_drag(p: &Params, alpha: f64, induced: f64) -> f64 {
    let cl = p.c_l_0 + p.c_l_alpha * alpha;
    p.c_d_p + induced * cl * cl / (std::f64::consts::PI * p.e * p.aspect_ratio())
}

/// Ground-effect factor φ = (16h/b)²/(1+(16h/b)²) with h = −down (clamped at 0).
pub fn ground_effect_factor(b: f64, down: f64) -> f64 {
    let x = 16.0 * (-down).max(0.0) / b;
    x * x / (1.0 + x * x)
}

/// Aerodynamic force and moment in body axes (no thrust, no gravity).
/// Surfaces in radians. `induced` multiplies the induced-drag term (ground effect).
/// At Va = 0 the rate terms (c/2Va)·q etc. are taken as 0.
#[allow(clippy::too_many_arguments)]
pub fn aero_force_moment(
    p: &Params,
    rho: f64,
    va: f64,
    alpha: f64,
    beta: f64,
    pqr: V3,
    surf: V3,
    induced: f64,
) -> (V3, V3) {
    let [de, da, dr] = surf;
    let qbar = 0.5 * rho * va * va;
    let (cc, bb) = if va > 0.0 {
        (p.c / (2.0 * va), p.b / (2.0 * va))
    } else {
        (0.0, 0.0)
    };
    let [pr, qr, rr] = pqr;
    let lift = qbar * p.s_wing * (c_lift(p, alpha) + p.c_l_q * cc * qr + p.c_l_delta_e * de);
    let drag =
        qbar * p.s_wing * (c_drag(p, alpha, induced) + p.c_d_q * cc * qr + p.c_d_delta_e * de);
    let (sa, ca) = alpha.sin_cos();
    let fx = -drag * ca + lift * sa;
    let fz = -drag * sa - lift * ca;
    let fy = qbar
        * p.s_wing
        * (p.c_y_0
            + p.c_y_beta * beta
            + p.c_y_p * bb * pr
            + p.c_y_r * bb * rr
            + p.c_y_delta_a * da
            + p.c_y_delta_r * dr);
    let l = qbar
        * p.s_wing
        * p.b
        * (p.c_ell_0
            + p.c_ell_beta * beta
            + p.c_ell_p * bb * pr
            + p.c_ell_r * bb * rr
            + p.c_ell_delta_a * da
            + p.c_ell_delta_r * dr);
    let m = qbar
        * p.s_wing
        * p.c
        * (p.c_m_0 + p.c_m_alpha * alpha + p.c_m_q * cc * qr + p.c_m_delta_e * de);
    let n = qbar
        * p.s_wing
        * p.b
        * (p.c_n_0
            + p.c_n_beta * beta
            + p.c_n_p * bb * pr
            + p.c_n_r * bb * rr
            + p.c_n_delta_a * da
            + p.c_n_delta_r * dr);
    ([fx, fy, fz], [l, m, n])
}

/// Thrust along body x: ½ρ S_prop C_prop ((k_motor δt)² − Va²).
pub fn thrust(p: &Params, rho: f64, va: f64, throttle: f64) -> f64 {
    let km = p.k_motor * throttle;
    0.5 * rho * p.s_prop * p.c_prop * (km * km - va * va)
}

/// `gyroscopic`: moment = −ω × (k_gyro·δt, 0, 0).
pub fn gyroscopic_moment(k_gyro: f64, throttle: f64, pqr: V3) -> V3 {
    v_scale(v_cross(pqr, [k_gyro * throttle, 0.0, 0.0]), -1.0)
}

/// `prop_torque`: rolling moment (−k_torque·δt², 0, 0).
pub fn prop_torque_moment(k_torque: f64, throttle: f64) -> V3 {
    [-k_torque * throttle * throttle, 0.0, 0.0]
}

/// Beard & McLain Γ1…Γ8 form of the rotational dynamics (used only to cross-check).
pub fn gamma_rates(p: &Params, pqr: V3, moment: V3) -> V3 {
    let (jx, jy, jz, jxz) = (p.jx, p.jy, p.jz, p.jxz);
    let g = jx * jz - jxz * jxz;
    let g1 = jxz * (jx - jy + jz) / g;
    let g2 = (jz * (jz - jy) + jxz * jxz) / g;
    let g3 = jz / g;
    let g4 = jxz / g;
    let g5 = (jz - jx) / jy;
    let g6 = jxz / jy;
    let g7 = ((jx - jy) * jx + jxz * jxz) / g;
    let g8 = jx / g;
    let [pp, q, r] = pqr;
    let [l, m, n] = moment;
    [
        g1 * pp * q - g2 * q * r + g3 * l + g4 * n,
        g5 * pp * r - g6 * (pp * pp - r * r) + m / jy,
        g7 * pp * q - g1 * q * r + g4 * l + g8 * n,
    ]
}

/// Air data (Va, α, β) of a state in the steady wind. β = 0 when Va = 0.
pub fn air_data(env: &Env, x: &FwState) -> (f64, f64, f64) {
    air_data_in(x, env.wind)
}

/// Air data (Va, α, β) of a state in the wind `wind` (NED, m/s). β = 0 when Va = 0.
pub fn air_data_in(x: &FwState, wind: V3) -> (f64, f64, f64) {
    let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
    air_data_r(wind, x, &r)
}

fn air_data_r(wind: V3, x: &FwState, r: &M3) -> (f64, f64, f64) {
    let wb = m_t_vec(r, wind);
    let ur = [x[ix::U] - wb[0], x[ix::V] - wb[1], x[ix::W] - wb[2]];
    let va = v_norm(ur);
    let alpha = ur[2].atan2(ur[0]);
    let beta = if va > 0.0 {
        (ur[1] / va).clamp(-1.0, 1.0).asin()
    } else {
        0.0
    };
    (va, alpha, beta)
}

/// The fixed-wing model: parameters, effects and precomputed constants.
#[derive(Clone, Debug, PartialEq)]
pub struct FwModel {
    pub params: Params,
    pub effects: Effects,
    pub env: Env,
    pub j: M3,
    pub j_inv: M3,
}

impl FwModel {
    pub fn new(params: &Params, effects: &Effects, origin: &Origin) -> FwModel {
        let j = params.inertia();
        FwModel {
            params: params.clone(),
            effects: effects.clone(),
            env: Env::new(effects, origin, params.rho),
            j,
            j_inv: m_inv(&j),
        }
    }

    /// Surface deflections acting now: the lagged states, or the commands when no lag.
    pub fn surfaces(&self, x: &FwState, cmd: &Controls) -> V3 {
        if self.effects.actuator_lag.is_some() {
            [x[ix::DE], x[ix::DA], x[ix::DR]]
        } else {
            [cmd.elevator, cmd.aileron, cmd.rudder]
        }
    }

    /// Total body force (N) and moment (N·m), excluding gravity and the inertial accelerations,
    /// in the steady wind.
    pub fn force_moment(&self, x: &FwState, cmd: &Controls) -> (V3, V3) {
        self.force_moment_in(x, cmd, self.env.wind)
    }

    /// [`force_moment`](Self::force_moment) in the wind `wind` (NED, m/s: steady and gusts).
    pub fn force_moment_in(&self, x: &FwState, cmd: &Controls, wind: V3) -> (V3, V3) {
        let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        self.force_moment_r(x, cmd, &r, wind)
    }

    fn force_moment_r(&self, x: &FwState, cmd: &Controls, r: &M3, wind: V3) -> (V3, V3) {
        let p = &self.params;
        let (va, alpha, beta) = air_data_r(wind, x, r);
        let down = x[ix::D];
        let rho = self.env.rho(down);
        let induced = if self.effects.ground_effect {
            ground_effect_factor(p.b, down)
        } else {
            1.0
        };
        let pqr = [x[ix::P], x[ix::Q], x[ix::R]];
        let surf = self.surfaces(x, cmd);
        let (mut f, mut m) = aero_force_moment(p, rho, va, alpha, beta, pqr, surf, induced);
        let t = thrust(p, rho, va, cmd.throttle);
        f[0] += t;
        let hidden = hidden_force_moment(
            &self.effects.hidden_terms,
            rho,
            va,
            alpha,
            beta,
            pqr,
            (cmd.throttle, t),
        );
        (f, m) = (v_add(f, hidden.0), v_add(m, hidden.1));
        if let Some(k) = self.effects.prop_torque {
            m = v_add(m, prop_torque_moment(k, cmd.throttle));
        }
        if let Some(k) = self.effects.gyroscopic {
            m = v_add(m, gyroscopic_moment(k, cmd.throttle, pqr));
        }
        (f, m)
    }

    /// Time derivative of the state under constant commands in the steady wind.
    pub fn derivative(&self, x: &FwState, cmd: &Controls) -> FwState {
        self.derivative_in(x, cmd, self.env.wind)
    }

    /// Time derivative of the state under constant commands in the wind `wind` (NED, m/s:
    /// the steady wind and the gusts of the moment). Only the air-relative velocity sees the
    /// wind; gravity, the kinematics and the Earth's terms use the inertial velocity.
    pub fn derivative_in(&self, x: &FwState, cmd: &Controls, wind: V3) -> FwState {
        let p = &self.params;
        let (phi, theta, psi) = (x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        let r = rot_body_to_ned(phi, theta, psi);
        let (f, mom) = self.force_moment_r(x, cmd, &r, wind);
        let uvw = [x[ix::U], x[ix::V], x[ix::W]];
        let pqr = [x[ix::P], x[ix::Q], x[ix::R]];
        let pos = [x[ix::N], x[ix::E], x[ix::D]];
        let g = self.env.g(x[ix::D]);
        let (sf, cf) = phi.sin_cos();
        let (st, ct) = theta.sin_cos();
        // Gravity in body axes from the Euler angles, as the spec writes it.
        let grav = [-g * st, g * ct * sf, g * ct * cf];
        let vel_ned = m_vec(&r, uvw);
        let extra = m_t_vec(&r, self.env.extra_accel_ned(pos, vel_ned, g));
        let inv_m = 1.0 / p.mass_kg;
        let [u, v, w] = uvw;
        let [pp, q, rr] = pqr;
        let du = rr * v - q * w + f[0] * inv_m + grav[0] + extra[0];
        let dv = pp * w - rr * u + f[1] * inv_m + grav[1] + extra[1];
        let dw = q * u - pp * v + f[2] * inv_m + grav[2] + extra[2];
        // Euler's equations with the full inertia matrix.
        let h = m_vec(&self.j, pqr);
        let wdot = m_vec(&self.j_inv, v_sub(mom, v_cross(pqr, h)));
        // Euler-angle kinematics of the spec.
        let a = q * sf + rr * cf;
        let dphi = pp + a * st / ct;
        let dtheta = q * cf - rr * sf;
        let dpsi = a / ct;
        let (dde, dda, ddr) = match self.effects.actuator_lag {
            Some(tau) => (
                (cmd.elevator - x[ix::DE]) / tau,
                (cmd.aileron - x[ix::DA]) / tau,
                (cmd.rudder - x[ix::DR]) / tau,
            ),
            None => (0.0, 0.0, 0.0),
        };
        [
            vel_ned[0], vel_ned[1], vel_ned[2], du, dv, dw, dphi, dtheta, dpsi, wdot[0], wdot[1],
            wdot[2], dde, dda, ddr,
        ]
    }

    /// Air data of a state in the steady wind.
    pub fn air_data(&self, x: &FwState) -> (f64, f64, f64) {
        air_data(&self.env, x)
    }
}
