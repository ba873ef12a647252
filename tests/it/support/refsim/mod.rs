//! refsim — an independent reference flight simulator used as a test oracle.
//!
//! Written from the specs only (`flight-model.md`, `flight-data.md`, `aerosonde.toml`), with
//! design choices deliberately different from the project's own simulator:
//!
//! * state: NED position, body velocity (u, v, w), **Euler angles** (φ, θ, ψ) integrated with the
//!   Euler-rate kinematics, body rates (p, q, r) and three surface states (δe, δa, δr) for the
//!   actuator lag — 15 numbers in a plain array;
//! * rotational dynamics solved from the full inertia matrix `J·ω̇ = M − ω×(J·ω)` (J inverted once),
//!   not the Γ1…Γ8 shortcut (a test checks that both agree);
//! * integrators: classic RK4 with a fixed small step, or adaptive Dormand–Prince 5(4); each output
//!   interval is integrated on its own so no step straddles a command change (zero-order hold);
//! * own trim (Newton with a finite-difference Jacobian), own autopilot, own RNG (SplitMix64 seeding
//!   xoshiro256**, Box–Muller), own CSV writer.
//! * turbulence (`FlightOptions::turbulence`): Dryden gusts as sums of sinusoids (`gusts.rs`),
//!   their MIL-F-8785C intensities computed here, tabulated once per flight and read at every
//!   integration stage's own time; the air-relative velocity (air data, every aerodynamic force
//!   and moment, the airspeed sensor, the autopilot's air data) sees steady wind + gust.
//!
//! std only, no `unsafe`. Everything is `pub` so tests can perturb any number.
#![allow(dead_code)]

use std::fmt::Write as _;

mod autopilot;
mod env;
mod fixed_wing;
mod flights;
mod gusts;
mod hidden_terms;
mod integrate;
mod noise;
mod point_mass;
mod trim;
pub use autopilot::*;
pub use env::*;
pub use fixed_wing::*;
pub use flights::*;
pub use gusts::*;
pub use hidden_terms::*;
pub use integrate::*;
pub use noise::*;
pub use trim::*;
// The ballistic shot is kept for tests to come; nothing uses it yet.
#[allow(unused_imports)]
pub use point_mass::*;

/// Standard gravity, m/s².
pub const G0: f64 = 9.80665;
/// Earth rotation rate, rad/s (catalogue `earth_rotation`).
pub const EARTH_RATE: f64 = 7.292115e-5;
/// Sphere radius of the catalogue `earth_curvature`, m.
pub const EARTH_RADIUS: f64 = 6_371_000.0;
/// Sea-level ISA density used by `density_altitude`, kg/m³.
pub const RHO_SL: f64 = 1.225;

const DEG: f64 = std::f64::consts::PI / 180.0;

// ---------------------------------------------------------------------------------------------
// Small vector / matrix helpers
// ---------------------------------------------------------------------------------------------

/// 3-vector.
pub type V3 = [f64; 3];
/// 3×3 matrix, row major: `m[row][col]`.
pub type M3 = [[f64; 3]; 3];

pub fn v_add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn v_sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn v_scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub fn v_dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn v_cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn v_norm(a: V3) -> f64 {
    v_dot(a, a).sqrt()
}
pub fn m_mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}
/// a·v
pub fn m_vec(a: &M3, v: V3) -> V3 {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}
/// aᵀ·v
pub fn m_t_vec(a: &M3, v: V3) -> V3 {
    [
        a[0][0] * v[0] + a[1][0] * v[1] + a[2][0] * v[2],
        a[0][1] * v[0] + a[1][1] * v[1] + a[2][1] * v[2],
        a[0][2] * v[0] + a[1][2] * v[1] + a[2][2] * v[2],
    ]
}
/// Inverse by the adjugate (panics on a singular matrix).
pub fn m_inv(a: &M3) -> M3 {
    let c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    let c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    let det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    assert!(det != 0.0 && det.is_finite(), "singular matrix");
    let d = 1.0 / det;
    [
        [
            c00 * d,
            (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * d,
            (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * d,
        ],
        [
            c01 * d,
            (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * d,
            (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * d,
        ],
        [
            c02 * d,
            (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * d,
            (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * d,
        ],
    ]
}

/// R_body→NED = Rz(ψ)·Ry(θ)·Rx(φ), built as the product of the three elementary rotations.
pub fn rot_body_to_ned(phi: f64, theta: f64, psi: f64) -> M3 {
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, cf, -sf], [0.0, sf, cf]];
    let ry = [[ct, 0.0, st], [0.0, 1.0, 0.0], [-st, 0.0, ct]];
    let rz = [[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]];
    m_mul(&m_mul(&rz, &ry), &rx)
}

/// Angle in degrees wrapped into (−180, 180].
pub fn wrap_deg(x: f64) -> f64 {
    let mut y = x.rem_euclid(360.0);
    if y > 180.0 {
        y -= 360.0;
    }
    if y <= -180.0 {
        y += 360.0;
    }
    y
}

/// Solve the n×n system `a·x = b` by Gaussian elimination with partial pivoting.
pub fn solve_linear(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..n {
            let f = a[row][col] / a[col][col];
            if f != 0.0 {
                let (upper, lower) = a.split_at_mut(row);
                for (dst, src) in lower[0][col..n].iter_mut().zip(&upper[col][col..n]) {
                    *dst -= f * src;
                }
                b[row] -= f * b[col];
            }
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= a[i][k] * x[k];
        }
        x[i] = s / a[i][i];
    }
    Some(x)
}

// ---------------------------------------------------------------------------------------------
// Parameters
// ---------------------------------------------------------------------------------------------

/// Fixed-wing parameter set, field names = the keys of `aerosonde.toml`.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    pub name: String,
    // [mass]
    pub mass_kg: f64,
    pub jx: f64,
    pub jy: f64,
    pub jz: f64,
    pub jxz: f64,
    // [geometry]
    pub s_wing: f64,
    pub b: f64,
    pub c: f64,
    pub e: f64,
    pub rho: f64,
    // [longitudinal]
    pub c_l_0: f64,
    pub c_l_alpha: f64,
    pub c_l_q: f64,
    pub c_l_delta_e: f64,
    pub c_d_p: f64,
    pub c_d_q: f64,
    pub c_d_delta_e: f64,
    pub c_m_0: f64,
    pub c_m_alpha: f64,
    pub c_m_q: f64,
    pub c_m_delta_e: f64,
    pub m_blend: f64,
    pub alpha0: f64,
    // [lateral]
    pub c_y_0: f64,
    pub c_y_beta: f64,
    pub c_y_p: f64,
    pub c_y_r: f64,
    pub c_y_delta_a: f64,
    pub c_y_delta_r: f64,
    pub c_ell_0: f64,
    pub c_ell_beta: f64,
    pub c_ell_p: f64,
    pub c_ell_r: f64,
    pub c_ell_delta_a: f64,
    pub c_ell_delta_r: f64,
    pub c_n_0: f64,
    pub c_n_beta: f64,
    pub c_n_p: f64,
    pub c_n_r: f64,
    pub c_n_delta_a: f64,
    pub c_n_delta_r: f64,
    // [propulsion]
    pub s_prop: f64,
    pub c_prop: f64,
    pub k_motor: f64,
}

impl Params {
    /// The Aerosonde values of `aerosonde.toml`, hard-coded.
    pub fn aerosonde() -> Self {
        Params {
            name: "aerosonde".to_string(),
            mass_kg: 11.0,
            jx: 0.824,
            jy: 1.135,
            jz: 1.759,
            jxz: 0.120,
            s_wing: 0.55,
            b: 2.8956,
            c: 0.18994,
            e: 0.9,
            rho: 1.2682,
            c_l_0: 0.23,
            c_l_alpha: 5.61,
            c_l_q: 7.95,
            c_l_delta_e: 0.13,
            c_d_p: 0.043,
            c_d_q: 0.0,
            c_d_delta_e: 0.0135,
            c_m_0: 0.0135,
            c_m_alpha: -2.74,
            c_m_q: -38.21,
            c_m_delta_e: -0.99,
            m_blend: 50.0,
            alpha0: 0.47,
            c_y_0: 0.0,
            c_y_beta: -0.98,
            c_y_p: 0.0,
            c_y_r: 0.0,
            c_y_delta_a: 0.075,
            c_y_delta_r: 0.19,
            c_ell_0: 0.0,
            c_ell_beta: -0.13,
            c_ell_p: -0.51,
            c_ell_r: 0.25,
            c_ell_delta_a: 0.17,
            c_ell_delta_r: 0.0024,
            c_n_0: 0.0,
            c_n_beta: 0.073,
            c_n_p: 0.069,
            c_n_r: -0.095,
            c_n_delta_a: -0.011,
            c_n_delta_r: -0.069,
            s_prop: 0.2027,
            c_prop: 1.0,
            k_motor: 80.0,
        }
    }

    /// (table, key, value) for every number, in the layout of `aerosonde.toml`.
    pub fn entries(&self) -> Vec<(&'static str, &'static str, f64)> {
        vec![
            ("mass", "mass_kg", self.mass_kg),
            ("mass", "jx", self.jx),
            ("mass", "jy", self.jy),
            ("mass", "jz", self.jz),
            ("mass", "jxz", self.jxz),
            ("geometry", "s_wing", self.s_wing),
            ("geometry", "b", self.b),
            ("geometry", "c", self.c),
            ("geometry", "e", self.e),
            ("geometry", "rho", self.rho),
            ("longitudinal", "c_l_0", self.c_l_0),
            ("longitudinal", "c_l_alpha", self.c_l_alpha),
            ("longitudinal", "c_l_q", self.c_l_q),
            ("longitudinal", "c_l_delta_e", self.c_l_delta_e),
            ("longitudinal", "c_d_p", self.c_d_p),
            ("longitudinal", "c_d_q", self.c_d_q),
            ("longitudinal", "c_d_delta_e", self.c_d_delta_e),
            ("longitudinal", "c_m_0", self.c_m_0),
            ("longitudinal", "c_m_alpha", self.c_m_alpha),
            ("longitudinal", "c_m_q", self.c_m_q),
            ("longitudinal", "c_m_delta_e", self.c_m_delta_e),
            ("longitudinal", "m_blend", self.m_blend),
            ("longitudinal", "alpha0", self.alpha0),
            ("lateral", "c_y_0", self.c_y_0),
            ("lateral", "c_y_beta", self.c_y_beta),
            ("lateral", "c_y_p", self.c_y_p),
            ("lateral", "c_y_r", self.c_y_r),
            ("lateral", "c_y_delta_a", self.c_y_delta_a),
            ("lateral", "c_y_delta_r", self.c_y_delta_r),
            ("lateral", "c_ell_0", self.c_ell_0),
            ("lateral", "c_ell_beta", self.c_ell_beta),
            ("lateral", "c_ell_p", self.c_ell_p),
            ("lateral", "c_ell_r", self.c_ell_r),
            ("lateral", "c_ell_delta_a", self.c_ell_delta_a),
            ("lateral", "c_ell_delta_r", self.c_ell_delta_r),
            ("lateral", "c_n_0", self.c_n_0),
            ("lateral", "c_n_beta", self.c_n_beta),
            ("lateral", "c_n_p", self.c_n_p),
            ("lateral", "c_n_r", self.c_n_r),
            ("lateral", "c_n_delta_a", self.c_n_delta_a),
            ("lateral", "c_n_delta_r", self.c_n_delta_r),
            ("propulsion", "s_prop", self.s_prop),
            ("propulsion", "c_prop", self.c_prop),
            ("propulsion", "k_motor", self.k_motor),
        ]
    }

    /// Aspect ratio b²/S.
    pub fn aspect_ratio(&self) -> f64 {
        self.b * self.b / self.s_wing
    }

    /// Inertia matrix of Beard & McLain: [[Jx, 0, −Jxz], [0, Jy, 0], [−Jxz, 0, Jz]] (Jxz = +∫xz dm).
    pub fn inertia(&self) -> M3 {
        [
            [self.jx, 0.0, -self.jxz],
            [0.0, self.jy, 0.0],
            [-self.jxz, 0.0, self.jz],
        ]
    }
}

/// TOML text in the layout of `aerosonde.toml` (`name`, then tables [mass], [geometry],
/// [longitudinal], [lateral], [propulsion]). Numbers use Rust's shortest round-trip `Debug`
/// form, which always is a TOML float (`11.0`, `0.12`, `1e-7`).
pub fn params_to_toml(p: &Params) -> String {
    let mut s = String::new();
    let name: String = p
        .name
        .chars()
        .flat_map(|c| match c {
            '"' => vec!['\\', '"'],
            '\\' => vec!['\\', '\\'],
            c if (c as u32) < 0x20 => vec![' '],
            c => vec![c],
        })
        .collect();
    let _ = writeln!(
        s,
        "# Parameter set written by refsim (independent reference simulator)."
    );
    let _ = writeln!(s, "name = \"{name}\"");
    let mut table = "";
    for (t, k, v) in p.entries() {
        if t != table {
            let _ = writeln!(s, "\n[{t}]");
            table = t;
        }
        let _ = writeln!(s, "{k} = {v:?}");
    }
    s
}
