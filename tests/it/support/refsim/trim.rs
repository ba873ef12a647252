//! refsim's own trim (Newton with a finite-difference Jacobian).

use super::*;

/// A trimmed straight, wings-level, horizontal (γ = 0 w.r.t. the air) flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Trim {
    pub airspeed: f64,
    pub alpha: f64,
    pub beta: f64,
    pub theta: f64,
    pub controls: Controls,
    pub state: FwState,
    /// Largest |u̇, v̇, ẇ, ṗ, q̇, ṙ| at the solution.
    pub max_residual: f64,
    /// Whether the lateral unknowns (β, δa, δr) had to be solved (asymmetric case).
    pub lateral_solved: bool,
}

fn trim_state(z: &[f64; 6], va: f64, height: f64, psi: f64, env: &Env) -> (FwState, Controls) {
    let [alpha, beta, de, dt, da, dr] = *z;
    let theta = alpha; // γ = 0 (φ = 0): θ = α
    let (sa, ca) = alpha.sin_cos();
    let (sb, cb) = beta.sin_cos();
    let air = [va * ca * cb, va * sb, va * sa * cb];
    let r = rot_body_to_ned(0.0, theta, psi);
    let wb = m_t_vec(&r, env.wind);
    let mut x = [0.0; 15];
    x[ix::D] = -height;
    x[ix::U] = air[0] + wb[0];
    x[ix::V] = air[1] + wb[1];
    x[ix::W] = air[2] + wb[2];
    x[ix::THETA] = theta;
    x[ix::PSI] = psi;
    x[ix::DE] = de;
    x[ix::DA] = da;
    x[ix::DR] = dr;
    let c = Controls {
        throttle: dt,
        elevator: de,
        aileron: da,
        rudder: dr,
    };
    (x, c)
}

fn trim_residual(model: &FwModel, z: &[f64; 6], va: f64, height: f64, psi: f64) -> [f64; 6] {
    let (x, c) = trim_state(z, va, height, psi, &model.env);
    let d = model.derivative(&x, &c);
    [d[ix::U], d[ix::V], d[ix::W], d[ix::P], d[ix::Q], d[ix::R]]
}

/// Newton on the unknowns selected by `free` (indices into z = [α, β, δe, δt, δa, δr]) against
/// the residual rows `rows` (indices into [u̇, v̇, ẇ, ṗ, q̇, ṙ]).
fn newton(
    model: &FwModel,
    z: &mut [f64; 6],
    free: &[usize],
    rows: &[usize],
    va: f64,
    height: f64,
    psi: f64,
) -> f64 {
    let norm = |r: &[f64; 6]| rows.iter().map(|&i| r[i].abs()).fold(0.0, f64::max);
    let mut res = trim_residual(model, z, va, height, psi);
    let mut best = norm(&res);
    for _ in 0..60 {
        if best < 1e-14 {
            break;
        }
        let n = free.len();
        let mut jac = vec![vec![0.0; n]; n];
        for (col, &k) in free.iter().enumerate() {
            let h = 1e-6 * (1.0 + z[k].abs());
            let mut zp = *z;
            zp[k] += h;
            let mut zm = *z;
            zm[k] -= h;
            let rp = trim_residual(model, &zp, va, height, psi);
            let rm = trim_residual(model, &zm, va, height, psi);
            for (row, &i) in rows.iter().enumerate() {
                jac[row][col] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
        let rhs: Vec<f64> = rows.iter().map(|&i| -res[i]).collect();
        let Some(dz) = solve_linear(jac, rhs) else {
            break;
        };
        // Damped step: halve until the residual decreases.
        let mut lam = 1.0;
        let mut improved = false;
        for _ in 0..30 {
            let mut zn = *z;
            for (col, &k) in free.iter().enumerate() {
                zn[k] += lam * dz[col];
            }
            let rn = trim_residual(model, &zn, va, height, psi);
            let nn = norm(&rn);
            if nn < best {
                *z = zn;
                res = rn;
                best = nn;
                improved = true;
                break;
            }
            lam *= 0.5;
        }
        if !improved {
            break;
        }
    }
    best
}

/// Trim for straight wings-level flight at `airspeed` (air-relative, horizontal w.r.t. the air),
/// height `height_m` above the NED origin (down = −height), heading `heading_deg`.
/// Unknowns α, δe, δt with β = φ = 0, δa = δr = 0; when the lateral residuals are not exactly zero
/// there (c_ell_0, c_n_0, C_Y0, prop_torque, Coriolis ...) β, δa, δr are solved too (φ stays 0).
/// Ground velocity = air velocity + wind. Surface states = commands.
pub fn trim(
    model: &FwModel,
    airspeed: f64,
    height_m: f64,
    heading_deg: f64,
) -> Result<Trim, String> {
    let psi = heading_deg * DEG;
    let mut z = [0.05, 0.0, -0.02, 0.4, 0.0, 0.0];
    newton(
        model,
        &mut z,
        &[0, 2, 3],
        &[0, 2, 4],
        airspeed,
        height_m,
        psi,
    );
    let r0 = trim_residual(model, &z, airspeed, height_m, psi);
    let lateral = r0[1] != 0.0 || r0[3] != 0.0 || r0[5] != 0.0;
    if lateral {
        newton(
            model,
            &mut z,
            &[0, 1, 2, 3, 4, 5],
            &[0, 1, 2, 3, 4, 5],
            airspeed,
            height_m,
            psi,
        );
    }
    let res = trim_residual(model, &z, airspeed, height_m, psi);
    let max_residual = res.iter().map(|v| v.abs()).fold(0.0, f64::max);
    if max_residual.is_nan() || max_residual >= 1e-10 {
        return Err(format!(
            "trim did not converge at {airspeed} m/s: residual {max_residual:e}"
        ));
    }
    if !(0.0..=1.0).contains(&z[3]) {
        return Err(format!("trim throttle {} outside 0..1", z[3]));
    }
    let (state, controls) = trim_state(&z, airspeed, height_m, psi, &model.env);
    Ok(Trim {
        airspeed,
        alpha: z[0],
        beta: z[1],
        theta: z[0],
        controls,
        state,
        max_residual,
        lateral_solved: lateral,
    })
}
