//! Derivatives and continuity of sampled flight data: the smoothing [`Differentiator`], angle
//! unwrapping ([`unwrap_angles`], [`unwrap_attitude`]) and body rates from attitude.
//!
//! This is numerical work on plain slices of times, values and angles, not on the file format
//! or [`FlightData`](crate::FlightData), so it lives apart from the data types and readers
//! (which use it to fill in the channels a flight lacks; the crate re-exports these names).
//! It does no I/O.
//!
//! # Differentiating noisy, unevenly sampled data
//! [`Differentiator`] fits a quadratic by least squares to the 2k + 1 samples around each
//! sample (Savitzky–Golay generalised to uneven time steps) and takes the fit's slope at that
//! sample. Near the ends the window keeps its 2k + 1 samples but becomes one-sided (it is
//! shifted to stay inside the data), the usual Savitzky–Golay end treatment. A centred window
//! has no lag (its phase is zero); its cost is a small attenuation of fast motion, and a
//! quadratic fit is exact for quadratic motion. The default half-width ([`Window::default`])
//! is [`DEFAULT_HALF_WIDTH_S`] = 0.2 s, turned into a sample count from the median time step
//! and clamped to [`MIN_HALF_SAMPLES`]..=[`MAX_HALF_SAMPLES`]: with uniform steps the
//! derivative's noise is √(3 / (k(k+1)(2k+1))) · σ/Δt against σ/(√2·Δt) for a central
//! difference (k = 4: 0.18 of it; k = 10: 0.04), while a sinusoid of angular frequency ω is
//! attenuated by about (ωh)²/10 for half-width h seconds (h = 0.2 s: 0.6 % at 0.2 Hz, 4 % at
//! 0.5 Hz, 16 % at 1 Hz) — body motion of aircraft and falling bodies is mostly below 1 Hz,
//! measurement noise is white. [`FlightData::derive_missing_with`] takes another [`Window`].
//!
//! [`FlightData::derive_missing_with`]: crate::FlightData::derive_missing_with

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use wireflight_geometry::euler::EulerZyx;

/// Default half-width of the differentiator's window, seconds (see the module docs).
pub const DEFAULT_HALF_WIDTH_S: f64 = 0.2;

/// Smallest half-width, in samples, that a [`Window::Seconds`] turns into (5-sample windows).
pub const MIN_HALF_SAMPLES: usize = 2;

/// Largest half-width, in samples, that a [`Window::Seconds`] turns into.
pub const MAX_HALF_SAMPLES: usize = 50;

/// Half-width of the [`Differentiator`]'s window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Window {
    /// About this many seconds each side, turned into samples from the median time step and
    /// clamped to [`MIN_HALF_SAMPLES`]..=[`MAX_HALF_SAMPLES`].
    Seconds(f64),
    /// Exactly this many samples each side (at least 1).
    Samples(usize),
}

impl Default for Window {
    /// `Seconds(DEFAULT_HALF_WIDTH_S)`.
    fn default() -> Self {
        Window::Seconds(DEFAULT_HALF_WIDTH_S)
    }
}

impl Window {
    /// The half-width in samples for these sample times.
    pub fn half_samples(self, time: &[f64]) -> usize {
        match self {
            Window::Samples(k) => k.max(1),
            Window::Seconds(h) => {
                let mut steps: Vec<f64> = time
                    .windows(2)
                    .map(|w| w[1] - w[0])
                    .filter(|d| d.is_finite() && *d > 0.0)
                    .collect();
                if steps.is_empty() || !(h.is_finite() && h > 0.0) {
                    return MIN_HALF_SAMPLES;
                }
                let mid = steps.len() / 2;
                let (_, median, _) = steps.select_nth_unstable_by(mid, f64::total_cmp);
                let k = (h / *median).round();
                if k.is_finite() {
                    (k as usize).clamp(MIN_HALF_SAMPLES, MAX_HALF_SAMPLES)
                } else {
                    MAX_HALF_SAMPLES
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Differentiation

/// Smoothing differentiator for unevenly sampled data: at each sample, the slope of the
/// least-squares quadratic through the 2k + 1 nearest samples (one-sided windows of the same
/// size at the ends). See the module docs for the choice of k.
///
/// The weights depend only on the times, so one `Differentiator` serves every channel.
#[derive(Clone, Debug)]
pub struct Differentiator {
    /// Per sample: first index of its window and the weights of the window's samples.
    windows: Vec<(usize, Vec<f64>)>,
}

impl Differentiator {
    /// Weights for sample times `time` (strictly increasing) and half-width `half` samples.
    /// With fewer than three samples in a window the fit is a straight line; with one sample
    /// the derivative is 0. Times that are not strictly increasing give NaN, not a panic.
    pub fn new(time: &[f64], half: usize) -> Self {
        let n = time.len();
        let m = half.saturating_mul(2).saturating_add(1).min(n).max(1);
        let windows = (0..n)
            .map(|i| {
                let lo = i.saturating_sub(half).min(n - m);
                let w = local_fit_weights(&time[lo..lo + m], time[i]);
                (lo, w)
            })
            .collect();
        Self { windows }
    }

    /// With the half-width of `window` for these times.
    pub fn with_window(time: &[f64], window: Window) -> Self {
        Self::new(time, window.half_samples(time))
    }

    /// Number of samples it was built for.
    pub fn len(&self) -> usize {
        self.windows.len()
    }

    /// True when built for no samples.
    pub fn is_empty(&self) -> bool {
        self.windows.is_empty()
    }

    /// Derivative of scalar samples `x` (one per time; missing entries count as 0).
    pub fn apply(&self, x: &[f64]) -> Vec<f64> {
        self.windows
            .iter()
            .map(|(lo, w)| {
                w.iter()
                    .enumerate()
                    .map(|(j, wj)| wj * x.get(lo + j).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect()
    }

    /// Derivative of vector samples `x` (one per time; missing entries count as 0).
    pub fn apply_vec3(&self, x: &[DVec3]) -> Vec<DVec3> {
        self.windows
            .iter()
            .map(|(lo, w)| {
                w.iter()
                    .enumerate()
                    .map(|(j, wj)| *wj * x.get(lo + j).copied().unwrap_or(DVec3::ZERO))
                    .sum()
            })
            .collect()
    }
}

/// Weights w such that Σ w_j x_j is the slope at `t0` of the least-squares quadratic (a line
/// with two samples) through (t_j, x_j).
fn local_fit_weights(t: &[f64], t0: f64) -> Vec<f64> {
    let m = t.len();
    if m < 2 {
        return vec![0.0; m];
    }
    // Scale τ into [−1, 1] for conditioning.
    let s = t.iter().map(|tj| (tj - t0).abs()).fold(0.0f64, f64::max);
    let tau: Vec<f64> = t.iter().map(|tj| (tj - t0) / s).collect();
    if m >= 3 {
        // Normal equations M·c = Aᵀx with rows (1, τ, τ²); slope at τ = 0 is c1 = e1ᵀ M⁻¹ Aᵀx,
        // so w_j = (M⁻¹ e1) · (1, τ_j, τ_j²) / s (M is symmetric).
        let mut mom = [0.0f64; 5];
        for &x in &tau {
            let mut p = 1.0;
            for mk in &mut mom {
                *mk += p;
                p *= x;
            }
        }
        let mat = glam::DMat3::from_cols(
            DVec3::new(mom[0], mom[1], mom[2]),
            DVec3::new(mom[1], mom[2], mom[3]),
            DVec3::new(mom[2], mom[3], mom[4]),
        );
        let det = mat.determinant();
        // A well-spread window has det of order m³; tiny det means samples bunched at ≤ 2 times.
        if det.is_finite() && det > 1e-10 * (m as f64).powi(3) {
            let y = mat.inverse() * DVec3::Y;
            return tau
                .iter()
                .map(|&x| (y.x + y.y * x + y.z * x * x) / s)
                .collect();
        }
    }
    // Straight line: slope = Σ (τ_j − τ̄) x_j / Σ (τ_j − τ̄)².
    let mean = tau.iter().sum::<f64>() / m as f64;
    let ss: f64 = tau.iter().map(|x| (x - mean) * (x - mean)).sum();
    tau.iter().map(|x| (x - mean) / ss / s).collect()
}

/// Removes jumps of more than π between successive angles by adding multiples of 2π, so the
/// result is continuous (e.g. 179°, −179° becomes 179°, 181°). Non-finite entries are passed
/// through and skipped.
pub fn unwrap_angles(angles: &[f64]) -> Vec<f64> {
    let mut prev: Option<f64> = None;
    angles
        .iter()
        .map(|&a| {
            let out = match prev {
                Some(p) => nearest_turn(a, p),
                None => a,
            };
            if out.is_finite() {
                prev = Some(out);
            }
            out
        })
        .collect()
}

/// `a + 2πm` closest to `reference`.
fn nearest_turn(a: f64, reference: f64) -> f64 {
    let m = ((reference - a) / TAU).round();
    if m.is_finite() {
        a + TAU * m
    } else {
        a
    }
}

/// Attitude made continuous from sample to sample, for differentiation. Besides adding whole
/// turns to each angle (as [`unwrap_angles`]), it may switch to the other z-y-x angles of the
/// same rotation, (ψ + π, π − θ, φ + π), when those are nearer to the previous sample: this
/// follows the body through pitch ±90° (where stored angles flip by 180° in yaw and roll) and
/// lets pitch run past ±90°. Every output describes the same rotation as its input.
pub fn unwrap_attitude(attitude: &[EulerZyx]) -> Vec<EulerZyx> {
    let mut prev: Option<EulerZyx> = None;
    attitude
        .iter()
        .map(|&e| {
            let Some(p) = prev else {
                if e.is_finite() {
                    prev = Some(e);
                }
                return e;
            };
            if !e.is_finite() {
                return e;
            }
            let near = |yaw: f64, pitch: f64, roll: f64| {
                EulerZyx::new(
                    nearest_turn(yaw, p.yaw),
                    nearest_turn(pitch, p.pitch),
                    nearest_turn(roll, p.roll),
                )
            };
            let dist = |c: EulerZyx| {
                (c.yaw - p.yaw).powi(2) + (c.pitch - p.pitch).powi(2) + (c.roll - p.roll).powi(2)
            };
            let a = near(e.yaw, e.pitch, e.roll);
            let b = near(e.yaw + PI, PI - e.pitch, e.roll + PI);
            let out = if dist(b) < dist(a) { b } else { a };
            prev = Some(out);
            out
        })
        .collect()
}

/// Body rates (p, q, r) from attitude samples: the attitude is unwrapped
/// ([`unwrap_attitude`]), each angle differentiated with `diff`, and the Euler-angle rates
/// mapped to body rates: p = φ̇ − ψ̇ sinθ, q = θ̇ cosφ + ψ̇ cosθ sinφ,
/// r = −θ̇ sinφ + ψ̇ cosθ cosφ. At exact gimbal lock (|θ| = 90°) ψ and φ are not separately
/// defined by the data and rates there are as good as the data's split between them.
pub fn body_rates_from_attitude(diff: &Differentiator, attitude: &[EulerZyx]) -> Vec<DVec3> {
    let u = unwrap_attitude(attitude);
    let yaw: Vec<f64> = u.iter().map(|e| e.yaw).collect();
    let pitch: Vec<f64> = u.iter().map(|e| e.pitch).collect();
    let roll: Vec<f64> = u.iter().map(|e| e.roll).collect();
    let (dyaw, dpitch, droll) = (diff.apply(&yaw), diff.apply(&pitch), diff.apply(&roll));
    u.iter()
        .zip(dyaw.iter().zip(dpitch.iter().zip(&droll)))
        .map(|(e, (&psi_d, (&theta_d, &phi_d)))| {
            let (sth, cth) = e.pitch.sin_cos();
            let (sph, cph) = e.roll.sin_cos();
            DVec3::new(
                phi_d - psi_d * sth,
                theta_d * cph + psi_d * cth * sph,
                -theta_d * sph + psi_d * cth * cph,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded LCG + Box–Muller: deterministic Gaussian noise without extra dependencies.
    struct Noise(u64);

    impl Noise {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
        fn gauss(&mut self) -> f64 {
            let (u1, u2) = (self.uniform(), self.uniform());
            (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
        }
    }

    /// Non-uniform times: steps drawn in [0.6, 1.4]·dt.
    fn uneven_times(n: usize, dt: f64, noise: &mut Noise) -> Vec<f64> {
        let mut t = vec![0.0];
        for _ in 1..n {
            let last = *t.last().unwrap();
            t.push(last + dt * (0.6 + 0.8 * noise.uniform()));
        }
        t
    }

    fn rms(a: &[f64]) -> f64 {
        (a.iter().map(|x| x * x).sum::<f64>() / a.len() as f64).sqrt()
    }

    #[test]
    fn derivative_of_a_quadratic_is_exact_on_uneven_times() {
        let mut noise = Noise(1);
        let t = uneven_times(60, 0.05, &mut noise);
        let x: Vec<f64> = t.iter().map(|t| 3.0 - 2.0 * t + 7.5 * t * t).collect();
        for half in [1, 2, 4, 9] {
            let d = Differentiator::new(&t, half).apply(&x);
            for (ti, di) in t.iter().zip(&d) {
                let exact = -2.0 + 15.0 * ti;
                assert!(
                    (di - exact).abs() < 1e-9,
                    "half {half} t {ti}: {di} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn derivative_of_a_cubic_is_close() {
        let mut noise = Noise(2);
        let t = uneven_times(200, 0.05, &mut noise);
        let x: Vec<f64> = t.iter().map(|t| t * t * t - 4.0 * t).collect();
        let half = 4;
        let d = Differentiator::new(&t, half).apply(&x);
        let n = t.len();
        for i in 0..n {
            let exact = 3.0 * t[i] * t[i] - 4.0;
            // A quadratic fit leaves the cubic term: the slope error is of order h² (h the
            // window's span, ≤ 2·half·1.4·dt = 0.56 s): ≲ 0.6·h² inside, a few h² at the ends.
            let lo = i.saturating_sub(half).min(n - 2 * half - 1);
            let h = t[lo + 2 * half] - t[lo];
            let bound = if i >= half && i + half < n {
                0.6 * h * h
            } else {
                3.0 * h * h
            };
            assert!(
                (d[i] - exact).abs() < bound,
                "i {i}: {} vs {exact} (bound {bound})",
                d[i]
            );
        }
    }

    #[test]
    fn two_samples_give_the_slope_and_one_gives_zero() {
        let d = Differentiator::new(&[1.0, 3.0], 4).apply(&[5.0, 9.0]);
        assert_eq!(d, vec![2.0, 2.0]);
        let d = Differentiator::new(&[1.0], 4).apply(&[5.0]);
        assert_eq!(d, vec![0.0]);
        assert!(Differentiator::new(&[], 4).is_empty());
    }

    #[test]
    fn smoothing_beats_central_differences_on_noisy_positions() {
        let mut noise = Noise(42);
        let t = uneven_times(1500, 0.05, &mut noise);
        let truth = |t: f64| 40.0 * (0.4 * t).sin() + 0.8 * t * t;
        let truth_d = |t: f64| 16.0 * (0.4 * t).cos() + 1.6 * t;
        let sigma = 0.3;
        let x: Vec<f64> = t
            .iter()
            .map(|&t| truth(t) + sigma * noise.gauss())
            .collect();
        let d = Differentiator::with_window(&t, Window::default()).apply(&x);
        let err_sg: Vec<f64> = (1..t.len() - 1).map(|i| d[i] - truth_d(t[i])).collect();
        let err_cd: Vec<f64> = (1..t.len() - 1)
            .map(|i| (x[i + 1] - x[i - 1]) / (t[i + 1] - t[i - 1]) - truth_d(t[i]))
            .collect();
        let ratio = rms(&err_sg) / rms(&err_cd);
        println!(
            "half {} samples: RMS error {:.4} m/s vs central differences {:.4} m/s, ratio {ratio:.3}",
            Window::default().half_samples(&t),
            rms(&err_sg),
            rms(&err_cd)
        );
        assert!(ratio < 1.0 / 3.0, "ratio {ratio}");
    }

    #[test]
    fn default_window_follows_the_sample_rate() {
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.05).collect();
        assert_eq!(Window::default().half_samples(&t), 4);
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.001).collect();
        assert_eq!(Window::default().half_samples(&t), MAX_HALF_SAMPLES);
        let t: Vec<f64> = (0..100).map(|i| i as f64).collect();
        assert_eq!(Window::default().half_samples(&t), MIN_HALF_SAMPLES);
        assert_eq!(Window::Samples(0).half_samples(&t), 1);
        assert_eq!(Window::Seconds(f64::NAN).half_samples(&t), MIN_HALF_SAMPLES);
    }

    #[test]
    fn unwrap_removes_jumps_across_180_degrees() {
        let deg = |v: &[f64]| v.iter().map(|d: &f64| d.to_radians()).collect::<Vec<_>>();
        let u = unwrap_angles(&deg(&[170.0, 179.0, -179.0, -170.0, 180.0, -175.0, 10.0]));
        let want = deg(&[170.0, 179.0, 181.0, 190.0, 180.0, 185.0, 10.0]);
        for (a, b) in u.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12, "{u:?}");
        }
        assert_eq!(unwrap_angles(&[]), Vec::<f64>::new());
    }

    #[test]
    fn attitude_unwrap_follows_the_body_over_the_vertical() {
        // Pitching nose-over through +90°: stored angles flip yaw and roll by 180°.
        let stored = [
            EulerZyx::from_degrees(10.0, 88.0, 0.0),
            EulerZyx::from_degrees(10.0, 89.5, 0.0),
            EulerZyx::from_degrees(-170.0, 89.0, 180.0),
            EulerZyx::from_degrees(-170.0, 87.5, -180.0),
        ];
        let u = unwrap_attitude(&stored);
        let pitch: Vec<f64> = u.iter().map(|e| e.pitch.to_degrees()).collect();
        for (p, want) in pitch.iter().zip([88.0, 89.5, 91.0, 92.5]) {
            assert!((p - want).abs() < 1e-9, "{pitch:?}");
        }
        for (a, b) in u.iter().zip(&stored) {
            assert!(a.to_matrix().abs_diff_eq(b.to_matrix(), 1e-12));
            assert!((a.yaw.to_degrees() - 10.0).abs() < 1e-9, "{u:?}");
            assert!(a.roll.to_degrees().abs() < 1e-9, "{u:?}");
        }
    }

    #[test]
    fn body_rates_of_a_turn_across_180_have_no_spike() {
        // Constant yaw rate 20°/s, level: r = 20°/s, p = q = 0, through ψ = ±180°.
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
        let att: Vec<EulerZyx> = t
            .iter()
            .map(|t| {
                let (e, _) = EulerZyx::from_degrees(100.0 + 20.0 * t, 0.0, 0.0).canonical();
                e
            })
            .collect();
        let rates = body_rates_from_attitude(&Differentiator::new(&t, 4), &att);
        for r in &rates {
            assert!(
                (r - DVec3::new(0.0, 0.0, 20f64.to_radians())).length() < 1e-9,
                "{r:?}"
            );
        }
    }

    #[test]
    fn body_rates_of_a_banked_pitching_body_match_the_kinematics() {
        // Roll 30°, pitch oscillating, yaw turning: compare with the formulas at exact rates.
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.01).collect();
        let ang = |t: f64| EulerZyx::new(0.3 * t, 0.2 * (0.5 * t).sin(), 0.5 + 0.1 * t);
        let att: Vec<EulerZyx> = t.iter().map(|&t| ang(t)).collect();
        let rates = body_rates_from_attitude(&Differentiator::new(&t, 5), &att);
        for (i, &ti) in t.iter().enumerate() {
            let e = ang(ti);
            let (psi_d, theta_d, phi_d) = (0.3, 0.1 * (0.5 * ti).cos(), 0.1);
            let want = DVec3::new(
                phi_d - psi_d * e.pitch.sin(),
                theta_d * e.roll.cos() + psi_d * e.pitch.cos() * e.roll.sin(),
                -theta_d * e.roll.sin() + psi_d * e.pitch.cos() * e.roll.cos(),
            );
            // One-sided end windows leave an error of order θ'''·h² ≈ 3e-4 rad/s.
            let tol = if (5..395).contains(&i) { 1e-4 } else { 1e-3 };
            assert!((rates[i] - want).length() < tol, "{i}: {:?}", rates[i]);
        }
    }
}
