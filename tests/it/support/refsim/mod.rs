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
//!
//! std only, no `unsafe`. Everything is `pub` so tests can perturb any number.
#![allow(dead_code)]

use std::fmt::Write as _;

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

// ---------------------------------------------------------------------------------------------
// Environment and effects
// ---------------------------------------------------------------------------------------------

/// Geodetic origin of the local NED frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Origin {
    pub latitude_deg: f64,
    pub longitude_deg: f64,
    pub altitude_m: f64,
}

impl Default for Origin {
    fn default() -> Self {
        Origin {
            latitude_deg: 47.3977,
            longitude_deg: 8.5456,
            altitude_m: 488.0,
        }
    }
}

/// Names of the catalogue effects of `flight-model.md`.
pub const CATALOGUE: [&str; 10] = [
    "wind",
    "drag",
    "density_altitude",
    "gravity_model",
    "earth_rotation",
    "earth_curvature",
    "prop_torque",
    "ground_effect",
    "actuator_lag",
    "gyroscopic",
];

/// Catalogue effects, each optional. `Effects::default()` is the baseline (none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Effects {
    /// `wind`: steady wind NED [north, east, down], m/s.
    pub wind: Option<V3>,
    /// `drag` (point mass): k = ½ρC_D A/m, 1/m.
    pub drag: Option<f64>,
    /// `density_altitude`: ISA ρ(h), h = origin altitude − down.
    pub density_altitude: bool,
    /// `gravity_model`: WGS84 normal gravity.
    pub gravity_model: bool,
    /// `earth_rotation`: Coriolis −2Ω×v.
    pub earth_rotation: bool,
    /// `earth_curvature`: (−g·n/R, −g·e/R, 0).
    pub earth_curvature: bool,
    /// `prop_torque`: k_torque, N·m (l += −k·δt²).
    pub prop_torque: Option<f64>,
    /// `ground_effect`: induced drag × (16h/b)²/(1+(16h/b)²).
    pub ground_effect: bool,
    /// `actuator_lag`: tau_s of every control surface.
    pub actuator_lag: Option<f64>,
    /// `gyroscopic`: k_gyro, kg·m²/s.
    pub gyroscopic: Option<f64>,
    /// Latitude for `gravity_model` / `earth_rotation`; None = the origin's latitude.
    pub latitude_deg: Option<f64>,
    /// `gravity_model` height: false (default) = current height altitude_m(origin) − down,
    /// true = the origin's altitude (constant).
    pub gravity_height_at_origin: bool,
}

impl Effects {
    /// Baseline: no effect.
    pub fn none() -> Self {
        Effects::default()
    }

    /// Add a catalogue effect by name with its parameters:
    /// `wind` [n, e, d]; `drag` [k]; `density_altitude` []; `gravity_model` [] or [lat_deg];
    /// `earth_rotation` [] or [lat_deg]; `earth_curvature` []; `prop_torque` [k_torque];
    /// `ground_effect` []; `actuator_lag` [tau_s]; `gyroscopic` [k_gyro].
    pub fn with(mut self, name: &str, args: &[f64]) -> Result<Self, String> {
        let need = |n: usize| -> Result<(), String> {
            if args.len() == n {
                Ok(())
            } else {
                Err(format!(
                    "effect {name}: expected {n} parameter(s), got {}",
                    args.len()
                ))
            }
        };
        match name {
            "wind" => {
                need(3)?;
                self.wind = Some([args[0], args[1], args[2]]);
            }
            "drag" => {
                need(1)?;
                self.drag = Some(args[0]);
            }
            "density_altitude" => {
                need(0)?;
                self.density_altitude = true;
            }
            "gravity_model" | "earth_rotation" => {
                if args.len() > 1 {
                    return Err(format!(
                        "effect {name}: at most one parameter (latitude_deg)"
                    ));
                }
                if let Some(&lat) = args.first() {
                    self.latitude_deg = Some(lat);
                }
                if name == "gravity_model" {
                    self.gravity_model = true;
                } else {
                    self.earth_rotation = true;
                }
            }
            "earth_curvature" => {
                need(0)?;
                self.earth_curvature = true;
            }
            "prop_torque" => {
                need(1)?;
                self.prop_torque = Some(args[0]);
            }
            "ground_effect" => {
                need(0)?;
                self.ground_effect = true;
            }
            "actuator_lag" => {
                need(1)?;
                self.actuator_lag = Some(args[0]);
            }
            "gyroscopic" => {
                need(1)?;
                self.gyroscopic = Some(args[0]);
            }
            other => return Err(format!("unknown effect `{other}`")),
        }
        Ok(self)
    }

    /// Names of the effects switched on, in catalogue order.
    pub fn names(&self) -> Vec<&'static str> {
        let on = [
            self.wind.is_some(),
            self.drag.is_some(),
            self.density_altitude,
            self.gravity_model,
            self.earth_rotation,
            self.earth_curvature,
            self.prop_torque.is_some(),
            self.ground_effect,
            self.actuator_lag.is_some(),
            self.gyroscopic.is_some(),
        ];
        CATALOGUE
            .iter()
            .zip(on)
            .filter(|(_, o)| *o)
            .map(|(n, _)| *n)
            .collect()
    }
}

/// ISA troposphere density of the catalogue, kg/m³.
pub fn isa_density(h: f64) -> f64 {
    RHO_SL * (1.0 - 0.0065 * h / 288.15).powf(4.2559)
}

/// WGS84 normal gravity of the catalogue at latitude (deg) and height h (m).
pub fn wgs84_gravity(latitude_deg: f64, h: f64) -> f64 {
    let s2 = (latitude_deg * DEG).sin().powi(2);
    9.7803253359 * (1.0 + 0.00193185265241 * s2) / (1.0 - 0.00669437999013 * s2).sqrt()
        - 3.086e-6 * h
}

/// Earth rotation vector in NED at latitude (deg): Ω·(cosλ, 0, −sinλ).
pub fn earth_rate_ned(latitude_deg: f64) -> V3 {
    let (s, c) = (latitude_deg * DEG).sin_cos();
    [EARTH_RATE * c, 0.0, -EARTH_RATE * s]
}

/// Environment derived once from effects + origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Env {
    pub wind: V3,
    pub rho_const: f64,
    pub density_altitude: bool,
    pub altitude0: f64,
    pub gravity_model: bool,
    pub gravity_latitude_deg: f64,
    pub gravity_height_at_origin: bool,
    pub omega: Option<V3>,
    pub curvature: bool,
}

impl Env {
    pub fn new(effects: &Effects, origin: &Origin, rho_const: f64) -> Env {
        let lat = effects.latitude_deg.unwrap_or(origin.latitude_deg);
        Env {
            wind: effects.wind.unwrap_or([0.0; 3]),
            rho_const,
            density_altitude: effects.density_altitude,
            altitude0: origin.altitude_m,
            gravity_model: effects.gravity_model,
            gravity_latitude_deg: lat,
            gravity_height_at_origin: effects.gravity_height_at_origin,
            omega: if effects.earth_rotation {
                Some(earth_rate_ned(lat))
            } else {
                None
            },
            curvature: effects.earth_curvature,
        }
    }

    /// Air density at `down`.
    pub fn rho(&self, down: f64) -> f64 {
        if self.density_altitude {
            isa_density(self.altitude0 - down)
        } else {
            self.rho_const
        }
    }

    /// Gravity magnitude at `down`.
    pub fn g(&self, down: f64) -> f64 {
        if self.gravity_model {
            let h = if self.gravity_height_at_origin {
                self.altitude0
            } else {
                self.altitude0 - down
            };
            wgs84_gravity(self.gravity_latitude_deg, h)
        } else {
            G0
        }
    }

    /// Coriolis + curvature accelerations in NED (gravity itself excluded).
    pub fn extra_accel_ned(&self, pos: V3, vel_ned: V3, g: f64) -> V3 {
        let mut a = [0.0; 3];
        if let Some(om) = self.omega {
            a = v_add(a, v_scale(v_cross(om, vel_ned), -2.0));
        }
        if self.curvature {
            a[0] -= g * pos[0] / EARTH_RADIUS;
            a[1] -= g * pos[1] / EARTH_RADIUS;
        }
        a
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed-wing model
// ---------------------------------------------------------------------------------------------

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

/// Air data (Va, α, β) of a state. β = 0 when Va = 0.
pub fn air_data(env: &Env, x: &FwState) -> (f64, f64, f64) {
    let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
    air_data_r(env, x, &r)
}

fn air_data_r(env: &Env, x: &FwState, r: &M3) -> (f64, f64, f64) {
    let wb = m_t_vec(r, env.wind);
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

    /// Total body force (N) and moment (N·m), excluding gravity and the inertial accelerations.
    pub fn force_moment(&self, x: &FwState, cmd: &Controls) -> (V3, V3) {
        let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        self.force_moment_r(x, cmd, &r)
    }

    fn force_moment_r(&self, x: &FwState, cmd: &Controls, r: &M3) -> (V3, V3) {
        let p = &self.params;
        let (va, alpha, beta) = air_data_r(&self.env, x, r);
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
        f[0] += thrust(p, rho, va, cmd.throttle);
        if let Some(k) = self.effects.prop_torque {
            m = v_add(m, prop_torque_moment(k, cmd.throttle));
        }
        if let Some(k) = self.effects.gyroscopic {
            m = v_add(m, gyroscopic_moment(k, cmd.throttle, pqr));
        }
        (f, m)
    }

    /// Time derivative of the state under constant commands.
    pub fn derivative(&self, x: &FwState, cmd: &Controls) -> FwState {
        let p = &self.params;
        let (phi, theta, psi) = (x[ix::PHI], x[ix::THETA], x[ix::PSI]);
        let r = rot_body_to_ned(phi, theta, psi);
        let (f, mom) = self.force_moment_r(x, cmd, &r);
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

    /// Air data of a state.
    pub fn air_data(&self, x: &FwState) -> (f64, f64, f64) {
        air_data(&self.env, x)
    }
}

// ---------------------------------------------------------------------------------------------
// Integrators
// ---------------------------------------------------------------------------------------------

/// Which integrator advances the state over each output interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Classic RK4, fixed step (the interval is split into ceil(interval/dt_s) equal steps).
    Rk4 { dt_s: f64 },
    /// Dormand–Prince 5(4), adaptive, error per component atol + rtol·|y| (RMS norm).
    DormandPrince { rtol: f64, atol: f64 },
}

impl Integrator {
    /// RK4 with a 1 ms step (the default).
    pub fn rk4_1ms() -> Self {
        Integrator::Rk4 { dt_s: 1e-3 }
    }
    /// Dormand–Prince with atol = rtol·1e-2.
    pub fn dopri(rtol: f64) -> Self {
        Integrator::DormandPrince {
            rtol,
            atol: rtol * 1e-2,
        }
    }
    pub fn describe(&self) -> String {
        match self {
            Integrator::Rk4 { dt_s } => format!("RK4 dt {} ms", dt_s * 1e3),
            Integrator::DormandPrince { rtol, atol } => {
                format!("Dormand-Prince 5(4) rtol {rtol:e} atol {atol:e}")
            }
        }
    }
}

/// Counters of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IntegStats {
    pub evals: u64,
    pub steps: u64,
    pub rejected: u64,
}

/// Advances a state over given spans, remembering the adaptive step between calls.
#[derive(Clone, Debug)]
pub struct Stepper {
    pub integrator: Integrator,
    pub h_next: f64,
    pub stats: IntegStats,
}

fn axpy<const N: usize>(y: &[f64; N], h: f64, terms: &[(f64, &[f64; N])]) -> [f64; N] {
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        *o += h * s;
    }
    out
}

impl Stepper {
    pub fn new(integrator: Integrator) -> Self {
        Stepper {
            integrator,
            h_next: 1e-3,
            stats: IntegStats::default(),
        }
    }

    /// Integrate the autonomous system ẏ = f(y) from 0 to `span`.
    pub fn advance<const N: usize, F: Fn(&[f64; N]) -> [f64; N]>(
        &mut self,
        y: &mut [f64; N],
        span: f64,
        f: F,
    ) {
        if span <= 0.0 {
            return;
        }
        match self.integrator {
            Integrator::Rk4 { dt_s } => {
                let n = ((span / dt_s) - 1e-9).ceil().max(1.0) as usize;
                let h = span / n as f64;
                for _ in 0..n {
                    let k1 = f(y);
                    let k2 = f(&axpy(y, 0.5 * h, &[(1.0, &k1)]));
                    let k3 = f(&axpy(y, 0.5 * h, &[(1.0, &k2)]));
                    let k4 = f(&axpy(y, h, &[(1.0, &k3)]));
                    *y = axpy(
                        y,
                        h / 6.0,
                        &[(1.0, &k1), (2.0, &k2), (2.0, &k3), (1.0, &k4)],
                    );
                    self.stats.evals += 4;
                    self.stats.steps += 1;
                }
            }
            Integrator::DormandPrince { rtol, atol } => self.dopri(y, span, &f, rtol, atol),
        }
    }

    fn dopri<const N: usize, F: Fn(&[f64; N]) -> [f64; N]>(
        &mut self,
        y: &mut [f64; N],
        span: f64,
        f: &F,
        rtol: f64,
        atol: f64,
    ) {
        const A21: f64 = 1.0 / 5.0;
        const A31: f64 = 3.0 / 40.0;
        const A32: f64 = 9.0 / 40.0;
        const A41: f64 = 44.0 / 45.0;
        const A42: f64 = -56.0 / 15.0;
        const A43: f64 = 32.0 / 9.0;
        const A51: f64 = 19372.0 / 6561.0;
        const A52: f64 = -25360.0 / 2187.0;
        const A53: f64 = 64448.0 / 6561.0;
        const A54: f64 = -212.0 / 729.0;
        const A61: f64 = 9017.0 / 3168.0;
        const A62: f64 = -355.0 / 33.0;
        const A63: f64 = 46732.0 / 5247.0;
        const A64: f64 = 49.0 / 176.0;
        const A65: f64 = -5103.0 / 18656.0;
        const B1: f64 = 35.0 / 384.0;
        const B3: f64 = 500.0 / 1113.0;
        const B4: f64 = 125.0 / 192.0;
        const B5: f64 = -2187.0 / 6784.0;
        const B6: f64 = 11.0 / 84.0;
        const E1: f64 = 71.0 / 57600.0;
        const E3: f64 = -71.0 / 16695.0;
        const E4: f64 = 71.0 / 1920.0;
        const E5: f64 = -17253.0 / 339200.0;
        const E6: f64 = 22.0 / 525.0;
        const E7: f64 = -1.0 / 40.0;

        let mut t = 0.0;
        let mut k1 = f(y);
        self.stats.evals += 1;
        let mut h = self.h_next.min(span);
        loop {
            let remaining = span - t;
            let last = h >= remaining * (1.0 - 1e-12);
            let hh = if last { remaining } else { h };
            let k2 = f(&axpy(y, hh, &[(A21, &k1)]));
            let k3 = f(&axpy(y, hh, &[(A31, &k1), (A32, &k2)]));
            let k4 = f(&axpy(y, hh, &[(A41, &k1), (A42, &k2), (A43, &k3)]));
            let k5 = f(&axpy(
                y,
                hh,
                &[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)],
            ));
            let k6 = f(&axpy(
                y,
                hh,
                &[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
            ));
            let y5 = axpy(
                y,
                hh,
                &[(B1, &k1), (B3, &k3), (B4, &k4), (B5, &k5), (B6, &k6)],
            );
            let k7 = f(&y5);
            self.stats.evals += 6;
            let mut acc = 0.0;
            for i in 0..N {
                let e = hh
                    * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
                let sc = atol + rtol * y[i].abs().max(y5[i].abs());
                acc += (e / sc) * (e / sc);
            }
            let err = (acc / N as f64).sqrt();
            let factor = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            if err <= 1.0 {
                *y = y5;
                k1 = k7;
                self.stats.steps += 1;
                if last {
                    self.h_next = h.max(hh * factor).min(1.0);
                    break;
                }
                t += hh;
                h = (hh * factor).min(1.0);
            } else {
                self.stats.rejected += 1;
                h = hh * factor.min(1.0);
            }
            assert!(h > 1e-14, "Dormand-Prince: step size underflow");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Trim
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Manoeuvre schedules and autopilot
// ---------------------------------------------------------------------------------------------

/// Autopilot target step: from `t_s` on, bank `bank_deg` and pitch `pitch_deg` above trim θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetStep {
    pub t_s: f64,
    pub bank_deg: f64,
    pub pitch_deg: f64,
}

/// Open-loop doublet: +amplitude on [start, start+width), −amplitude on [start+width, start+2·width).
/// Amplitude in degrees for surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Doublet {
    pub start_s: f64,
    pub width_s: f64,
    pub amplitude: f64,
}

impl Doublet {
    pub fn new(start_s: f64, width_s: f64, amplitude: f64) -> Self {
        Doublet {
            start_s,
            width_s,
            amplitude,
        }
    }
    pub fn value(&self, t: f64) -> f64 {
        let t = t + TIME_EPS;
        if t >= self.start_s && t < self.start_s + self.width_s {
            self.amplitude
        } else if t >= self.start_s + self.width_s && t < self.start_s + 2.0 * self.width_s {
            -self.amplitude
        } else {
            0.0
        }
    }
}

/// A manoeuvre schedule. All times are flight time (trim at t = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    pub name: String,
    pub duration_s: f64,
    /// Closed loop (autopilot) or open loop from the trim commands.
    pub autopilot: bool,
    /// Bank / pitch target steps (autopilot only). Before the first step: 0, 0.
    pub targets: Vec<TargetStep>,
    /// (t, airspeed above trim m/s) from t on (autopilot only).
    pub airspeed_steps: Vec<(f64, f64)>,
    pub elevator_doublets: Vec<Doublet>,
    pub aileron_doublets: Vec<Doublet>,
    pub rudder_doublets: Vec<Doublet>,
    /// (t, throttle offset) added to the throttle from t on (latest entry wins; before: 0).
    pub throttle_steps: Vec<(f64, f64)>,
}

/// Schedule times are compared with this tolerance, so a change at time T takes effect at the
/// sample whose time is T even when k/rate and T round differently.
pub const TIME_EPS: f64 = 1e-9;

fn latest<T: Copy>(items: &[(f64, T)], t: f64, default: T) -> T {
    let mut out = default;
    let mut best = f64::NEG_INFINITY;
    for &(ti, v) in items {
        if ti <= t + TIME_EPS && ti >= best {
            best = ti;
            out = v;
        }
    }
    out
}

impl Schedule {
    /// Trim held, autopilot on, nothing else.
    pub fn level(duration_s: f64) -> Self {
        Schedule {
            name: "level".into(),
            duration_s,
            autopilot: true,
            targets: vec![],
            airspeed_steps: vec![],
            elevator_doublets: vec![],
            aileron_doublets: vec![],
            rudder_doublets: vec![],
            throttle_steps: vec![],
        }
    }

    /// Trim commands held open loop.
    pub fn trim_hold(duration_s: f64) -> Self {
        Schedule {
            name: "trim_hold".into(),
            autopilot: false,
            ..Schedule::level(duration_s)
        }
    }

    /// Bank/pitch steps at t = 8, 18, 24, 34, 36, 41 s, 45 s long.
    pub fn steps_8_18_24_34_36_41() -> Self {
        let st = |t_s, bank_deg, pitch_deg| TargetStep {
            t_s,
            bank_deg,
            pitch_deg,
        };
        Schedule {
            name: "steps_8_18_24_34_36_41".into(),
            targets: vec![
                st(8.0, 25.0, 0.0),
                st(18.0, 0.0, 4.0),
                st(24.0, -25.0, 4.0),
                st(34.0, 0.0, 0.0),
                st(36.0, 0.0, 5.0),
                st(41.0, 0.0, -2.0),
            ],
            ..Schedule::level(45.0)
        }
    }

    /// Flight test, 60 s: right and left turns, a climb, doublets on every surface, throttle steps.
    pub fn flight_test() -> Self {
        let st = |t_s, bank_deg, pitch_deg| TargetStep {
            t_s,
            bank_deg,
            pitch_deg,
        };
        Schedule {
            name: "flight_test".into(),
            targets: vec![
                st(3.0, 30.0, 0.0),
                st(11.0, 0.0, 0.0),
                st(16.0, -30.0, 0.0),
                st(24.0, 0.0, 0.0),
                st(27.0, 0.0, 6.0),
                st(35.0, 0.0, 0.0),
            ],
            airspeed_steps: vec![(50.0, 3.0), (56.0, 0.0)],
            elevator_doublets: vec![Doublet::new(38.0, 0.6, 3.0)],
            aileron_doublets: vec![Doublet::new(41.0, 0.6, 4.0)],
            rudder_doublets: vec![Doublet::new(44.0, 0.6, 5.0)],
            throttle_steps: vec![(47.0, 0.15), (52.0, -0.1), (57.0, 0.0)],
            ..Schedule::level(60.0)
        }
    }

    /// Open loop from trim, 20 s: doublets on elevator, aileron, rudder and a throttle step.
    pub fn open_loop_doublets() -> Self {
        Schedule {
            name: "open_loop_doublets".into(),
            autopilot: false,
            elevator_doublets: vec![Doublet::new(2.0, 0.5, 3.0)],
            aileron_doublets: vec![Doublet::new(5.0, 0.5, 3.0)],
            rudder_doublets: vec![Doublet::new(8.0, 0.5, 4.0)],
            throttle_steps: vec![(11.0, 0.05), (13.0, 0.0)],
            ..Schedule::level(20.0)
        }
    }

    /// Open loop, 12 windows of `period_s`; every control change falls on a multiple of
    /// `period_s` (window k = [kP, (k+1)P)): aileron ±0.5° in windows 1–2, elevator ±1° in 3–4,
    /// rudder ±1° in 5–6, throttle +0.03 / −0.03 in 7 / 8, aileron ∓0.5° with elevator ∓0.5° in 9–10.
    pub fn window_steps(period_s: f64) -> Self {
        let p = period_s;
        Schedule {
            name: format!("window_steps_{p}"),
            autopilot: false,
            aileron_doublets: vec![Doublet::new(p, p, 0.5), Doublet::new(9.0 * p, p, -0.5)],
            elevator_doublets: vec![
                Doublet::new(3.0 * p, p, 1.0),
                Doublet::new(9.0 * p, p, -0.5),
            ],
            rudder_doublets: vec![Doublet::new(5.0 * p, p, 1.0)],
            throttle_steps: vec![(7.0 * p, 0.03), (8.0 * p, -0.03), (9.0 * p, 0.0)],
            ..Schedule::level(12.0 * p)
        }
    }

    /// Preset by name: `steps_8_18_24_34_36_41`, `flight_test`, `open_loop_doublets`,
    /// `window_steps_<period>` (e.g. `window_steps_4`), `level_<duration>`, `trim_hold_<duration>`.
    pub fn preset(name: &str) -> Option<Schedule> {
        match name {
            "steps_8_18_24_34_36_41" => Some(Schedule::steps_8_18_24_34_36_41()),
            "flight_test" => Some(Schedule::flight_test()),
            "open_loop_doublets" => Some(Schedule::open_loop_doublets()),
            _ => {
                let num = |prefix: &str| -> Option<f64> {
                    name.strip_prefix(prefix)?
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite() && *v > 0.0)
                };
                if let Some(p) = num("window_steps_") {
                    Some(Schedule::window_steps(p))
                } else if let Some(d) = num("level_") {
                    Some(Schedule::level(d))
                } else {
                    num("trim_hold_").map(Schedule::trim_hold)
                }
            }
        }
    }

    /// Every time at which the schedule changes something.
    pub fn change_times(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.targets.iter().map(|s| s.t_s).collect();
        v.extend(self.airspeed_steps.iter().map(|s| s.0));
        v.extend(self.throttle_steps.iter().map(|s| s.0));
        for d in self
            .elevator_doublets
            .iter()
            .chain(&self.aileron_doublets)
            .chain(&self.rudder_doublets)
        {
            v.extend([
                d.start_s,
                d.start_s + d.width_s,
                d.start_s + 2.0 * d.width_s,
            ]);
        }
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// (bank rad, pitch above trim rad) at t.
    pub fn target(&self, t: f64) -> (f64, f64) {
        let items: Vec<(f64, (f64, f64))> = self
            .targets
            .iter()
            .map(|s| (s.t_s, (s.bank_deg * DEG, s.pitch_deg * DEG)))
            .collect();
        latest(&items, t, (0.0, 0.0))
    }

    /// Open-loop offsets at t: (δe, δa, δr in rad, throttle).
    pub fn offsets(&self, t: f64) -> (f64, f64, f64, f64) {
        let s = |ds: &[Doublet]| ds.iter().map(|d| d.value(t)).sum::<f64>() * DEG;
        (
            s(&self.elevator_doublets),
            s(&self.aileron_doublets),
            s(&self.rudder_doublets),
            latest(&self.throttle_steps, t, 0.0),
        )
    }
}

/// Rudder law of the autopilot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RudderMode {
    /// δr = δr_trim − k_beta·β.
    Beta,
    /// δr = δr_trim − k_r·(r_c − r), r_c = g·sinφ·cosθ/Va (coordinated-turn yaw rate).
    YawRate,
}

/// Autopilot gains (surfaces in rad, angles in rad, rates in rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains {
    pub k_phi: f64,
    pub k_phi_i: f64,
    pub k_p: f64,
    pub k_theta: f64,
    pub k_q: f64,
    pub k_theta_i: f64,
    pub k_v: f64,
    pub k_v_i: f64,
    pub k_beta: f64,
    pub k_r: f64,
    pub rudder_mode: RudderMode,
    /// Surface command limit, deg.
    pub max_surface_deg: f64,
}

impl Default for Gains {
    fn default() -> Self {
        Gains {
            k_phi: 0.6,
            k_phi_i: 0.2,
            k_p: 0.03,
            k_theta: 2.5,
            k_q: 0.2,
            k_theta_i: 0.5,
            k_v: 0.05,
            k_v_i: 0.02,
            k_beta: 1.0,
            k_r: 0.5,
            rudder_mode: RudderMode::Beta,
            max_surface_deg: 30.0,
        }
    }
}

/// Autopilot integrator states.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ApState {
    pub i_phi: f64,
    pub i_theta: f64,
    pub i_v: f64,
}

/// Command for flight time `t` given the true state: autopilot (if on) + open-loop offsets.
/// `dt` is the sample period (integrators advance by one sample per call).
#[allow(clippy::too_many_arguments)]
pub fn command_at(
    model: &FwModel,
    sched: &Schedule,
    gains: &Gains,
    tr: &Trim,
    ap: &mut ApState,
    t: f64,
    x: &FwState,
    dt: f64,
) -> Controls {
    let mut c = tr.controls;
    if sched.autopilot {
        let (va, _alpha, beta) = model.air_data(x);
        let (bank_c, pitch_c) = sched.target(t);
        let theta_c = tr.theta + pitch_c;
        let va_c = tr.airspeed + latest(&sched.airspeed_steps, t, 0.0);
        let (phi, theta) = (x[ix::PHI], x[ix::THETA]);
        let (p, q, r) = (x[ix::P], x[ix::Q], x[ix::R]);
        let g = model.env.g(x[ix::D]);
        let e_phi = bank_c - phi;
        // Conditional integration (only near the target) against wind-up during bank steps.
        if e_phi.abs() < 5.0 * DEG {
            ap.i_phi = (ap.i_phi + e_phi * dt).clamp(-0.5, 0.5);
        }
        c.aileron += gains.k_phi * e_phi + gains.k_phi_i * ap.i_phi - gains.k_p * p;
        let e_th = theta_c - theta;
        ap.i_theta = (ap.i_theta + e_th * dt).clamp(-0.5, 0.5);
        // q damping relative to the pitch rate of a steady coordinated turn, g·tanφ·sinφ·cosθ/Va.
        let q_turn = if va > 1.0 {
            g * phi.tan() * phi.sin() * theta.cos() / va
        } else {
            0.0
        };
        c.elevator +=
            -(gains.k_theta * e_th + gains.k_theta_i * ap.i_theta) + gains.k_q * (q - q_turn);
        let e_v = va_c - va;
        ap.i_v = (ap.i_v + e_v * dt).clamp(-20.0, 20.0);
        c.throttle += gains.k_v * e_v + gains.k_v_i * ap.i_v;
        match gains.rudder_mode {
            RudderMode::Beta => c.rudder += -gains.k_beta * beta,
            RudderMode::YawRate => {
                let r_c = if va > 1.0 {
                    g * phi.sin() * theta.cos() / va
                } else {
                    0.0
                };
                c.rudder += -gains.k_r * (r_c - r);
            }
        }
    }
    let (de, da, dr, dth) = sched.offsets(t);
    c.elevator += de;
    c.aileron += da;
    c.rudder += dr;
    c.throttle += dth;
    let lim = gains.max_surface_deg * DEG;
    c.elevator = c.elevator.clamp(-lim, lim);
    c.aileron = c.aileron.clamp(-lim, lim);
    c.rudder = c.rudder.clamp(-lim, lim);
    c.throttle = c.throttle.clamp(0.0, 1.0);
    c
}

// ---------------------------------------------------------------------------------------------
// Noise
// ---------------------------------------------------------------------------------------------

/// xoshiro256** seeded by SplitMix64, normals by Box–Muller.
#[derive(Clone, Debug)]
pub struct Rng {
    s: [u64; 4],
    spare: Option<f64>,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        let mut sm = seed;
        let mut next = || {
            sm = sm.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = sm;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Rng {
            s: [next(), next(), next(), next()],
            spare: None,
        }
    }
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }
    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }
    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let u1 = self.uniform();
        let u2 = self.uniform();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (2.0 * std::f64::consts::PI * u2).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

/// Measurement noise standard deviations per channel. Controls are never noised.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Noise {
    pub position_m: f64,
    pub attitude_deg: f64,
    pub velocity_mps: f64,
    pub rate_dps: f64,
    pub airspeed_mps: f64,
}

impl Noise {
    pub fn none() -> Self {
        Noise::default()
    }
    pub fn new(
        position_m: f64,
        attitude_deg: f64,
        velocity_mps: f64,
        rate_dps: f64,
        airspeed_mps: f64,
    ) -> Self {
        Noise {
            position_m,
            attitude_deg,
            velocity_mps,
            rate_dps,
            airspeed_mps,
        }
    }
    pub fn is_none(&self) -> bool {
        *self == Noise::default()
    }
}

// ---------------------------------------------------------------------------------------------
// Flights and CSV
// ---------------------------------------------------------------------------------------------

/// Vehicle family of a flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VehicleKind {
    FixedWing,
    PointMass,
}

/// One output sample (true, noise-free values).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Row {
    /// Value of the `time_s` column.
    pub time_s: f64,
    /// Flight time (schedule time).
    pub t_flight: f64,
    pub pos: V3,
    pub vel_ned: V3,
    /// Body velocity (fixed wing).
    pub uvw: V3,
    /// φ, θ, ψ in rad, ψ unwrapped.
    pub euler: V3,
    pub pqr: V3,
    pub airspeed: f64,
    pub alpha: f64,
    pub beta: f64,
    /// Commands in force from this row until the next.
    pub controls: Controls,
    /// Surface positions (= commands unless actuator lag).
    pub surfaces: V3,
}

/// A simulated flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Flight {
    pub vehicle: VehicleKind,
    /// `# aircraft:` value (fixed wing).
    pub aircraft: String,
    pub origin: Origin,
    /// `# source:` value.
    pub source: String,
    pub mass_kg: Option<f64>,
    pub reference_area_m2: Option<f64>,
    pub rows: Vec<Row>,
    pub trim: Option<Trim>,
    pub stats: IntegStats,
}

/// Shortest round-trip text of a number, plain decimal notation (no exponent) except for
/// magnitudes below 1e-30 or from 1e15 on, which a flight never has.
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else if x.abs() < 1e-30 || x.abs() >= 1e15 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl Flight {
    /// CSV text per flight-data.md with the given measurement noise (deterministic per seed).
    pub fn to_csv(&self, noise: &Noise, seed: u64) -> String {
        let mut rng = Rng::new(seed);
        let mut s = String::with_capacity(self.rows.len() * 300 + 512);
        let vehicle = match self.vehicle {
            VehicleKind::FixedWing => "fixed-wing",
            VehicleKind::PointMass => "point-mass",
        };
        let _ = writeln!(s, "# vehicle: {vehicle}");
        if self.vehicle == VehicleKind::FixedWing {
            let _ = writeln!(s, "# aircraft: {}", self.aircraft);
        }
        let _ = writeln!(s, "# latitude_deg: {}", fmt_num(self.origin.latitude_deg));
        let _ = writeln!(s, "# longitude_deg: {}", fmt_num(self.origin.longitude_deg));
        let _ = writeln!(s, "# altitude_m: {}", fmt_num(self.origin.altitude_m));
        if let Some(m) = self.mass_kg {
            let _ = writeln!(s, "# mass_kg: {}", fmt_num(m));
        }
        if let Some(a) = self.reference_area_m2 {
            let _ = writeln!(s, "# reference_area_m2: {}", fmt_num(a));
        }
        let _ = writeln!(s, "# source: {}", self.source);
        let fw = self.vehicle == VehicleKind::FixedWing;
        if fw {
            s.push_str(
                "time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps,\
                 p_dps,q_dps,r_dps,airspeed_mps,throttle,elevator_deg,aileron_deg,rudder_deg\n",
            );
        } else {
            s.push_str("time_s,north_m,east_m,down_m,vn_mps,ve_mps,vd_mps\n");
        }
        let mut nz = |sd: f64| if sd > 0.0 { sd * rng.normal() } else { 0.0 };
        for r in &self.rows {
            let mut cells: Vec<f64> = Vec::with_capacity(18);
            cells.push(r.time_s);
            for k in 0..3 {
                cells.push(r.pos[k] + nz(noise.position_m));
            }
            if fw {
                let roll = wrap_deg(r.euler[0] / DEG + nz(noise.attitude_deg));
                let pitch = r.euler[1] / DEG + nz(noise.attitude_deg);
                let yaw = wrap_deg(r.euler[2] / DEG + nz(noise.attitude_deg));
                cells.extend([roll, pitch, yaw]);
            }
            for k in 0..3 {
                cells.push(r.vel_ned[k] + nz(noise.velocity_mps));
            }
            if fw {
                for k in 0..3 {
                    cells.push(r.pqr[k] / DEG + nz(noise.rate_dps));
                }
                cells.push(r.airspeed + nz(noise.airspeed_mps));
                let c = r.controls;
                cells.extend([
                    c.throttle,
                    c.elevator / DEG,
                    c.aileron / DEG,
                    c.rudder / DEG,
                ]);
            }
            for (i, v) in cells.iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                s.push_str(&fmt_num(*v));
            }
            s.push('\n');
        }
        s
    }

    /// Noise-free CSV.
    pub fn to_csv_exact(&self) -> String {
        self.to_csv(&Noise::none(), 0)
    }
}

/// Options of a fixed-wing flight.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightOptions {
    pub params: Params,
    pub effects: Effects,
    pub origin: Origin,
    pub integrator: Integrator,
    pub schedule: Schedule,
    pub gains: Gains,
    pub noise: Noise,
    pub seed: u64,
    /// Output (= autopilot) rate, Hz.
    pub rate_hz: f64,
    /// Recorded duration, s (rows = round(duration·rate) + 1).
    pub duration_s: f64,
    /// Start height above the NED origin (down = −height), m.
    pub start_height_m: f64,
    /// Trim airspeed, m/s.
    pub airspeed_mps: f64,
    pub heading_deg: f64,
    /// `time_s` of the first recorded row.
    pub time_offset_s: f64,
    /// Flight time at which recording starts (initial transient), s; rounded to the sample grid.
    pub record_start_s: f64,
    /// `# aircraft:` value.
    pub aircraft: String,
    /// `# source:` value; None = "refsim (<integrator>, <schedule>)".
    pub source: Option<String>,
}

impl FlightOptions {
    /// Defaults: Aerosonde, baseline effects, default origin, RK4 1 ms, 50 Hz, the schedule's
    /// duration, 200 m, 25 m/s, heading 0, no offsets, no noise, seed 1.
    pub fn new(schedule: Schedule) -> Self {
        FlightOptions {
            params: Params::aerosonde(),
            effects: Effects::none(),
            origin: Origin::default(),
            integrator: Integrator::rk4_1ms(),
            duration_s: schedule.duration_s,
            schedule,
            gains: Gains::default(),
            noise: Noise::none(),
            seed: 1,
            rate_hz: 50.0,
            start_height_m: 200.0,
            airspeed_mps: 25.0,
            heading_deg: 0.0,
            time_offset_s: 0.0,
            record_start_s: 0.0,
            aircraft: "aerosonde".into(),
            source: None,
        }
    }
}

fn valid_pos(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

fn valid_nonneg(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

/// Fly a fixed-wing flight: trim, then per sample: command (ZOH) → integrate to the next sample.
pub fn fly(opts: &FlightOptions) -> Result<Flight, String> {
    if !valid_pos(opts.rate_hz)
        || !valid_nonneg(opts.duration_s)
        || !valid_nonneg(opts.record_start_s)
    {
        return Err("rate must be > 0, duration and record start >= 0".into());
    }
    let model = FwModel::new(&opts.params, &opts.effects, &opts.origin);
    let tr = trim(
        &model,
        opts.airspeed_mps,
        opts.start_height_m,
        opts.heading_deg,
    )?;
    let rate = opts.rate_hz;
    let dt = 1.0 / rate;
    let n_pre = (opts.record_start_s * rate).round() as usize;
    let n_rec = (opts.duration_s * rate).round() as usize;
    let mut x = tr.state;
    let mut ap = ApState::default();
    let mut stepper = Stepper::new(opts.integrator);
    let mut rows = Vec::with_capacity(n_rec + 1);
    for i in 0..=(n_pre + n_rec) {
        let t = i as f64 / rate;
        let cmd = command_at(&model, &opts.schedule, &opts.gains, &tr, &mut ap, t, &x, dt);
        if i >= n_pre {
            let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
            let uvw = [x[ix::U], x[ix::V], x[ix::W]];
            let (va, alpha, beta) = model.air_data(&x);
            rows.push(Row {
                time_s: opts.time_offset_s + (i - n_pre) as f64 / rate,
                t_flight: t,
                pos: [x[ix::N], x[ix::E], x[ix::D]],
                vel_ned: m_vec(&r, uvw),
                uvw,
                euler: [x[ix::PHI], x[ix::THETA], x[ix::PSI]],
                pqr: [x[ix::P], x[ix::Q], x[ix::R]],
                airspeed: va,
                alpha,
                beta,
                controls: cmd,
                surfaces: model.surfaces(&x, &cmd),
            });
        }
        if i < n_pre + n_rec {
            let span = (i + 1) as f64 / rate - t;
            stepper.advance(&mut x, span, |y| model.derivative(y, &cmd));
            if x.iter().any(|v| !v.is_finite()) {
                return Err(format!("state became non-finite at t = {t}"));
            }
        }
    }
    let source = opts.source.clone().unwrap_or_else(|| {
        format!(
            "refsim (independent reference simulator; {}; schedule {})",
            opts.integrator.describe(),
            opts.schedule.name
        )
    });
    Ok(Flight {
        vehicle: VehicleKind::FixedWing,
        aircraft: opts.aircraft.clone(),
        origin: opts.origin,
        source,
        mass_kg: None,
        reference_area_m2: None,
        rows,
        trim: Some(tr),
        stats: stepper.stats,
    })
}

/// Fly and write CSV with `opts.noise` / `opts.seed`.
pub fn flight_csv(opts: &FlightOptions) -> Result<String, String> {
    Ok(fly(opts)?.to_csv(&opts.noise, opts.seed))
}

// ---------------------------------------------------------------------------------------------
// Point mass
// ---------------------------------------------------------------------------------------------

/// Point-mass derivative: state [n, e, d, vn, ve, vd].
pub fn point_mass_derivative(env: &Env, drag: Option<f64>, y: &[f64; 6]) -> [f64; 6] {
    let pos = [y[0], y[1], y[2]];
    let v = [y[3], y[4], y[5]];
    let g = env.g(y[2]);
    let mut a = [0.0, 0.0, g];
    if let Some(k) = drag {
        let vr = v_sub(v, env.wind);
        let scale = if env.density_altitude {
            env.rho(y[2]) / RHO_SL
        } else {
            1.0
        };
        a = v_add(a, v_scale(vr, -k * scale * v_norm(vr)));
    }
    a = v_add(a, env.extra_accel_ned(pos, v, g));
    [v[0], v[1], v[2], a[0], a[1], a[2]]
}

/// Options of a ballistic (point-mass) flight.
#[derive(Clone, Debug, PartialEq)]
pub struct BallisticOptions {
    pub speed_mps: f64,
    /// Launch elevation above the horizon, deg.
    pub elevation_deg: f64,
    /// Launch azimuth from north toward east, deg.
    pub azimuth_deg: f64,
    pub start_height_m: f64,
    /// Effects; `drag` holds k.
    pub effects: Effects,
    pub origin: Origin,
    pub integrator: Integrator,
    pub rate_hz: f64,
    pub duration_s: f64,
    pub time_offset_s: f64,
    pub noise: Noise,
    pub seed: u64,
    pub mass_kg: Option<f64>,
    pub reference_area_m2: Option<f64>,
    /// Stop after the first sample with down > 0 (below the ground plane).
    pub stop_at_ground: bool,
    pub source: Option<String>,
}

impl BallisticOptions {
    /// Launch preset: speed, elevation, azimuth; from the origin (height 0), 50 Hz, 10 s, RK4 1 ms.
    pub fn launch(speed_mps: f64, elevation_deg: f64, azimuth_deg: f64) -> Self {
        BallisticOptions {
            speed_mps,
            elevation_deg,
            azimuth_deg,
            start_height_m: 0.0,
            effects: Effects::none(),
            origin: Origin::default(),
            integrator: Integrator::rk4_1ms(),
            rate_hz: 50.0,
            duration_s: 10.0,
            time_offset_s: 0.0,
            noise: Noise::none(),
            seed: 1,
            mass_kg: None,
            reference_area_m2: None,
            stop_at_ground: false,
            source: None,
        }
    }

    /// Initial NED velocity.
    pub fn initial_velocity(&self) -> V3 {
        let (se, ce) = (self.elevation_deg * DEG).sin_cos();
        let (sa, ca) = (self.azimuth_deg * DEG).sin_cos();
        [
            self.speed_mps * ce * ca,
            self.speed_mps * ce * sa,
            -self.speed_mps * se,
        ]
    }
}

/// Fly a point-mass flight.
pub fn fly_ballistic(opts: &BallisticOptions) -> Result<Flight, String> {
    if !valid_pos(opts.rate_hz) || !valid_nonneg(opts.duration_s) {
        return Err("rate must be > 0 and duration >= 0".into());
    }
    let env = Env::new(&opts.effects, &opts.origin, RHO_SL);
    let v0 = opts.initial_velocity();
    let mut y = [0.0, 0.0, -opts.start_height_m, v0[0], v0[1], v0[2]];
    let n = (opts.duration_s * opts.rate_hz).round() as usize;
    let mut stepper = Stepper::new(opts.integrator);
    let mut rows = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = i as f64 / opts.rate_hz;
        rows.push(Row {
            time_s: opts.time_offset_s + t,
            t_flight: t,
            pos: [y[0], y[1], y[2]],
            vel_ned: [y[3], y[4], y[5]],
            airspeed: v_norm(v_sub([y[3], y[4], y[5]], env.wind)),
            ..Row::default()
        });
        if opts.stop_at_ground && y[2] > 0.0 {
            break;
        }
        if i < n {
            let span = (i + 1) as f64 / opts.rate_hz - t;
            stepper.advance(&mut y, span, |s| {
                point_mass_derivative(&env, opts.effects.drag, s)
            });
        }
    }
    let source = opts.source.clone().unwrap_or_else(|| {
        format!(
            "refsim (independent reference simulator; {}; ballistic launch {} m/s, elevation {} deg, azimuth {} deg)",
            opts.integrator.describe(),
            opts.speed_mps,
            opts.elevation_deg,
            opts.azimuth_deg
        )
    });
    Ok(Flight {
        vehicle: VehicleKind::PointMass,
        aircraft: String::new(),
        origin: opts.origin,
        source,
        mass_kg: opts.mass_kg,
        reference_area_m2: opts.reference_area_m2,
        rows,
        trim: None,
        stats: stepper.stats,
    })
}

/// Fly a ballistic flight and write CSV with `opts.noise` / `opts.seed`.
pub fn ballistic_csv(opts: &BallisticOptions) -> Result<String, String> {
    Ok(fly_ballistic(opts)?.to_csv(&opts.noise, opts.seed))
}
