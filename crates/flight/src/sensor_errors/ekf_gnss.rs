//! The `ekf-gnss` model: an error-state simulation of a navigation filter fusing an IMU with
//! GNSS positions and a heading aid (equations in the module documentation of [`super`]).

use glam::{DMat3, DVec3};

use wireflight_data::{FlightData, G0};

use super::process::{attitude_matrix, clean_dt, Process};
use super::{EkfGnss, SensorErrorTrace};
use crate::numeric::invert;

/// A 9×9 matrix over the error state (δp, δv, ψ), rows of columns.
type M9 = [[f64; 9]; 9];
/// The gain: 9 states × 4 measurements (δp north, east, down; ψ_D).
type Gain = [[f64; 4]; 9];

/// The states the measurements read: δp (0, 1, 2) and the heading error ψ_D (8).
const MEASURED: [usize; 4] = [0, 1, 2, 8];

/// Most Riccati iterations for the gain (it converges in hundreds to a few thousand).
const MAX_RICCATI: usize = 100_000;
/// Most warm-up steps before the first sample.
const MAX_WARM_UP_STEPS: usize = 200_000;
/// Most IMU steps in one GNSS interval the gain is computed for.
const MAX_STEPS_PER_FIX: f64 = 1e6;
/// Smallest measurement standard deviations of the gain: GNSS 1 mm, heading 0.001°, so that
/// a perfect aid still gives a finite gain.
const MIN_POS_SIGMA_M: f64 = 1e-3;
/// Smallest heading-aid standard deviation of the gain, rad (0.001°).
const MIN_HEADING_SIGMA_RAD: f64 = 1.745_329_251_994_33e-5;
/// Smallest process-noise densities of the gain (velocity m²/s³, attitude rad²/s): an IMU
/// without errors would make the Riccati iteration converge only as 1/n.
const MIN_VEL_PSD: f64 = 1e-14;
/// As [`MIN_VEL_PSD`], attitude.
const MIN_ATT_PSD: f64 = 1e-18;

fn zero() -> M9 {
    [[0.0; 9]; 9]
}

fn identity() -> M9 {
    let mut m = zero();
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

fn mul(a: &M9, b: &M9) -> M9 {
    let mut c = zero();
    for i in 0..9 {
        for k in 0..9 {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..9 {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

fn transpose(a: &M9) -> M9 {
    let mut t = zero();
    for i in 0..9 {
        for j in 0..9 {
            t[j][i] = a[i][j];
        }
    }
    t
}

fn add(a: &M9, b: &M9) -> M9 {
    let mut c = *a;
    for i in 0..9 {
        for j in 0..9 {
            c[i][j] += b[i][j];
        }
    }
    c
}

/// a·p·aᵀ.
fn sandwich(a: &M9, p: &M9) -> M9 {
    mul(&mul(a, p), &transpose(a))
}

/// Largest absolute row sum.
fn norm(a: &M9) -> f64 {
    a.iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// A stretch of propagation: its transition and the process noise it accumulates.
#[derive(Clone, Copy)]
struct Segment {
    phi: M9,
    q: M9,
}

impl Segment {
    /// `self`, then `next`.
    fn then(&self, next: &Self) -> Self {
        Self {
            phi: mul(&next.phi, &self.phi),
            q: add(&sandwich(&next.phi, &self.q), &next.q),
        }
    }

    /// `self` repeated `n` times (by squaring: all the pieces are powers of one step, so
    /// their order does not matter).
    fn repeat(&self, mut n: u64) -> Self {
        let mut out = Self {
            phi: identity(),
            q: zero(),
        };
        let mut base = *self;
        while n > 0 {
            if n & 1 == 1 {
                out = out.then(&base);
            }
            base = base.then(&base);
            n >>= 1;
        }
        out
    }
}

/// The steady-state gain, the IMU steps per GNSS interval it assumes, and the GNSS intervals
/// the closed loop needs to shrink a start error to a thousandth.
struct Design {
    gain: Gain,
    steps_per_fix: usize,
    settle_fixes: usize,
}

/// The Gauss–Markov part's low-frequency density plus the white part's, per step `dt`, in
/// the square of the unit per s (module documentation, "The gain").
fn step_variance(spec: &super::AxisError, scale: f64, dt: f64) -> f64 {
    let tau = spec
        .tau_s
        .filter(|t| t.is_finite() && *t > 0.0)
        .unwrap_or(0.0);
    let size = spec.size * scale;
    let white = spec.white * scale;
    (white * dt).powi(2) + 2.0 * size * size * tau * dt
}

/// The steady-state Kalman gain of the 9-state model with f_n = (0, 0, −g₀) at step `dt`.
fn design(m: &EkfGnss, dt: f64) -> Design {
    let deg = 1f64.to_radians();
    let steps = (1.0 / (m.gnss_rate_hz * dt)).round();
    let steps = if steps.is_finite() {
        steps.clamp(1.0, MAX_STEPS_PER_FIX)
    } else {
        1.0
    };
    // One Euler step, as the simulation takes it: δp' = δv, δv' = ψ × f_n = −[f_n]×·ψ.
    let mut f = identity();
    for i in 0..3 {
        f[i][3 + i] = dt;
    }
    f[3][7] = -G0 * dt;
    f[4][6] = G0 * dt;
    let qv = step_variance(&m.accel, 1.0, dt).max(MIN_VEL_PSD * dt);
    let qa = step_variance(&m.gyro, deg, dt).max(MIN_ATT_PSD * dt);
    let mut q = zero();
    for i in 0..3 {
        q[3 + i][3 + i] = qv;
        q[6 + i][6 + i] = qa;
    }
    // `steps` is integral and at most 1e6.
    let interval = Segment { phi: f, q }.repeat(steps as u64);
    let var = |a: &super::AxisError, scale: f64, floor: f64| {
        ((a.size * scale).powi(2) + (a.white * scale).powi(2)).max(floor * floor)
    };
    let r = [
        var(&m.gnss_horizontal, 1.0, MIN_POS_SIGMA_M),
        var(&m.gnss_horizontal, 1.0, MIN_POS_SIGMA_M),
        var(&m.gnss_vertical, 1.0, MIN_POS_SIGMA_M),
        var(&m.heading, deg, MIN_HEADING_SIGMA_RAD),
    ];
    let mut p = zero();
    for i in 0..9 {
        p[i][i] = [100.0, 1.0, 0.01][i / 3];
    }
    let mut gain: Gain = [[0.0; 4]; 9];
    for _ in 0..MAX_RICCATI {
        let prior = add(&sandwich(&interval.phi, &p), &interval.q);
        let Some((k, post)) = update(&prior, &r) else {
            break;
        };
        let converged = k
            .iter()
            .flatten()
            .zip(gain.iter().flatten())
            .all(|(a, b)| (a - b).abs() <= 1e-10 * a.abs() + 1e-15);
        gain = k;
        p = post;
        if converged {
            break;
        }
    }
    // The closed loop over one interval; square it until it has shrunk to a thousandth.
    let mut closed = mul(&i_minus_kh(&gain), &interval.phi);
    let mut settle_fixes = 1usize;
    while norm(&closed) > 1e-3 && settle_fixes < (1 << 20) {
        closed = mul(&closed, &closed);
        settle_fixes *= 2;
    }
    Design {
        gain,
        steps_per_fix: steps as usize,
        settle_fixes,
    }
}

/// I − K·H.
fn i_minus_kh(k: &Gain) -> M9 {
    let mut a = identity();
    for (i, row) in a.iter_mut().enumerate() {
        for (j, &s) in MEASURED.iter().enumerate() {
            row[s] -= k[i][j];
        }
    }
    a
}

/// The Kalman update of the prior covariance with measurement variances `r`: the gain and the
/// posterior (Joseph form, which stays symmetric and positive). `None` if S is singular or
/// anything is not finite.
fn update(prior: &M9, r: &[f64; 4]) -> Option<(Gain, M9)> {
    let mut s = [0.0; 16];
    for (a, &i) in MEASURED.iter().enumerate() {
        for (b, &j) in MEASURED.iter().enumerate() {
            s[a * 4 + b] = prior[i][j] + if a == b { r[a] } else { 0.0 };
        }
    }
    let s_inv = invert(&s, 4)?;
    let mut k: Gain = [[0.0; 4]; 9];
    for (i, row) in k.iter_mut().enumerate() {
        for (b, kb) in row.iter_mut().enumerate() {
            *kb = (0..4)
                .map(|a| prior[i][MEASURED[a]] * s_inv[a * 4 + b])
                .sum();
        }
    }
    let mut krk = zero();
    for i in 0..9 {
        for j in 0..9 {
            krk[i][j] = (0..4).map(|a| k[i][a] * r[a] * k[j][a]).sum();
        }
    }
    let post = add(&sandwich(&i_minus_kh(&k), prior), &krk);
    let finite = post
        .iter()
        .flatten()
        .chain(k.iter().flatten())
        .all(|v| v.is_finite());
    finite.then_some((k, post))
}

/// The navigation error state and its closed loop.
struct Filter {
    gain: Gain,
    dp: DVec3,
    dv: DVec3,
    psi: DVec3,
}

impl Filter {
    /// One Euler step of `dt` with the attitude `r`, the true specific force in NED `f_n` and
    /// the IMU's errors `dw` (gyro, body, rad/s) and `df` (accelerometer, body, m/s²).
    fn propagate(&mut self, dt: f64, r: &DMat3, f_n: DVec3, dw: DVec3, df: DVec3) {
        let dp = self.dv * dt;
        let dv = (self.psi.cross(f_n) + *r * df) * dt;
        let dpsi = (*r * dw) * dt;
        self.dp += dp;
        self.dv += dv;
        self.psi += dpsi;
    }

    /// A fix: GNSS position reading in error by `e`, heading aid by `e_heading` (rad).
    fn fuse(&mut self, e: DVec3, e_heading: f64) {
        let y = [
            self.dp.x - e.x,
            self.dp.y - e.y,
            self.dp.z - e.z,
            self.psi.z - e_heading,
        ];
        let c: [f64; 9] =
            std::array::from_fn(|i| (0..4).map(|j| self.gain[i][j] * y[j]).sum::<f64>());
        self.dp -= DVec3::new(c[0], c[1], c[2]);
        self.dv -= DVec3::new(c[3], c[4], c[5]);
        self.psi -= DVec3::new(c[6], c[7], c[8]);
    }
}

/// The IMU's error generators: gyro (streams 1–3) and accelerometer (4–6), body axes.
struct Imu {
    gyro: [Process; 3],
    accel: [Process; 3],
}

impl Imu {
    /// The errors at the next sample, `dt` after the last (gyro rad/s, accelerometer m/s²).
    fn step(&mut self, dt: f64) -> (DVec3, DVec3) {
        let g = &mut self.gyro;
        let a = &mut self.accel;
        (
            DVec3::new(g[0].step(dt), g[1].step(dt), g[2].step(dt)),
            DVec3::new(a[0].step(dt), a[1].step(dt), a[2].step(dt)),
        )
    }
}

/// The aids' error generators: GNSS north, east (7, 8), down (9), heading (10).
struct Aids {
    gnss: [Process; 3],
    heading: Process,
}

impl Aids {
    /// The readings' errors at a fix `dt` after the last one.
    fn step(&mut self, dt: f64) -> (DVec3, f64) {
        let g = &mut self.gnss;
        (
            DVec3::new(g[0].step(dt), g[1].step(dt), g[2].step(dt)),
            self.heading.step(dt),
        )
    }
}

/// The flight's mean sample interval (or, for fewer than two samples or times that are not
/// numbers, 10 ms or one GNSS interval if shorter).
fn nominal_dt(time: &[f64], rate_hz: f64) -> f64 {
    let n = time.len();
    let mean = if n >= 2 {
        clean_dt((time[n - 1] - time[0]) / (n - 1) as f64)
    } else {
        0.0
    };
    if mean > 0.0 {
        mean
    } else {
        clean_dt(1.0 / rate_hz).clamp(1e-6, 0.01)
    }
}

/// Index of the GNSS epoch at or before `t` (epochs at t₀ + j/rate; a nanosecond's slack
/// so that a sample on an epoch counts as on it despite rounding).
fn epoch(t: f64, t0: f64, rate_hz: f64) -> f64 {
    ((t - t0) * rate_hz + 1e-9).floor()
}

/// The errors of every channel of `d` (whether present or not). Streams: gyro 1–3,
/// accelerometer 4–6, GNSS 7–9, heading aid 10, airspeed 11.
pub(super) fn errors(m: &EkfGnss, d: &FlightData, seed: u64) -> SensorErrorTrace {
    let n = d.len();
    let mut t = SensorErrorTrace::default();
    if n == 0 {
        return t;
    }
    let deg = 1f64.to_radians();
    let dt_nominal = nominal_dt(&d.time, m.gnss_rate_hz);
    let design = design(m, dt_nominal);
    let mut imu = Imu {
        gyro: [1, 2, 3].map(|i| Process::new(&m.gyro, deg, seed, i)),
        accel: [4, 5, 6].map(|i| Process::new(&m.accel, 1.0, seed, i)),
    };
    let mut aids = Aids {
        gnss: [
            Process::new(&m.gnss_horizontal, 1.0, seed, 7),
            Process::new(&m.gnss_horizontal, 1.0, seed, 8),
            Process::new(&m.gnss_vertical, 1.0, seed, 9),
        ],
        heading: Process::new(&m.heading, deg, seed, 10),
    };
    let mut airspeed = Process::new(&m.airspeed, 1.0, seed, 11);
    let mut filter = Filter {
        gain: design.gain,
        dp: DVec3::ZERO,
        dv: DVec3::ZERO,
        psi: DVec3::ZERO,
    };
    // The attitude and true specific force (NED) of sample k.
    let at = |k: usize| {
        let r = attitude_matrix(d.attitude.as_ref().and_then(|a| a.get(k)));
        let f_n = d
            .accel_body
            .as_ref()
            .and_then(|a| a.get(k))
            .map(|f| r * *f)
            .filter(|f| f.is_finite())
            .unwrap_or(DVec3::new(0.0, 0.0, -G0));
        (r, f_n)
    };

    // Warm-up: fly the closed loop before the first sample, with its attitude and specific
    // force, fixes every `steps_per_fix` steps, the last of them at the first sample.
    let (mut r, mut f_n) = at(0);
    let mut e_imu = imu.step(0.0);
    let mut since_fix = 0.0;
    let warm = design
        .steps_per_fix
        .saturating_mul(design.settle_fixes)
        .min(MAX_WARM_UP_STEPS);
    for i in 1..=warm {
        filter.propagate(dt_nominal, &r, f_n, e_imu.0, e_imu.1);
        e_imu = imu.step(dt_nominal);
        since_fix += dt_nominal;
        if i % design.steps_per_fix == 0 && i < warm {
            let (e, h) = aids.step(since_fix);
            filter.fuse(e, h);
            since_fix = 0.0;
        }
    }

    t.pos.reserve_exact(n);
    t.vel.reserve_exact(n);
    t.tilt.reserve_exact(n);
    t.rates.reserve_exact(n);
    t.airspeed.reserve_exact(n);
    t.accel.reserve_exact(n);
    let t0 = d.time[0];
    for k in 0..n {
        let mut dt = 0.0;
        let fix = if k == 0 {
            true
        } else {
            dt = clean_dt(d.time[k] - d.time[k - 1]);
            filter.propagate(dt, &r, f_n, e_imu.0, e_imu.1);
            e_imu = imu.step(dt);
            since_fix += dt;
            (r, f_n) = at(k);
            epoch(d.time[k], t0, m.gnss_rate_hz) > epoch(d.time[k - 1], t0, m.gnss_rate_hz)
        };
        if fix {
            let (e, h) = aids.step(since_fix);
            filter.fuse(e, h);
            since_fix = 0.0;
        }
        t.pos.push(filter.dp);
        t.vel.push(filter.dv);
        t.tilt.push(filter.psi);
        t.rates.push(e_imu.0);
        t.accel.push(e_imu.1);
        t.airspeed.push(airspeed.step(dt));
    }
    t
}
