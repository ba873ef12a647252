//! Model vs measurements by **multiple shooting**.
//!
//! The flight is cut into windows of `window_s` seconds. In each, the model is restarted from
//! a state estimated from the data and flown open loop with the recorded commands (zero-order
//! hold); its prediction is compared with the measurements sample by sample. This works for
//! stable and divergent dynamics alike: an unstable mode can only grow for one window.
//!
//! **Initial state.** Restarting from a raw noisy sample turns noise into drift, so each
//! window's start is estimated by least squares over its first `fit_s` seconds: a quadratic
//! in time through positions (→ position and velocity), through unwrapped attitude angles
//! (→ attitude), and through measured body rates (→ rates; or the attitude fit's derivative).
//! States no sensor measures — control-surface positions under `actuator_lag` — follow from
//! the command history alone: the lag filter is run over the commands from the first sample.
//!
//! For a **point mass** (six states, cheap to fly) the start is then refined by least squares
//! over the *whole* window: Gauss–Newton on position and velocity, finite-difference
//! Jacobian, minimising the same position + velocity error the score uses. A ballistic
//! trajectory is nearly affine in its initial state, so two steps converge; the residual left
//! is white measurement noise plus the model's own error, which lets windows be long (the
//! small Earth effects need tens of seconds to show) and lets the diagnosis treat samples as
//! independent (see [`super::diagnose`]). The fixed-wing start stays the short-span fit:
//! twelve states of a stiff, sometimes unstable system are not worth refining per evaluation.
//!
//! **Error metric.** Per window and channel, the RMS of the prediction error: position (m),
//! velocity (m/s, NED), attitude (degrees, largest-axis-wrapped). The **total** is the RMS
//! over windows and channels of errors normalised by 1 m, 1 m/s and 1°, so a window's score
//! is `√((e_pos² + e_vel² + e_att²)/k)` with k the number of channels the data has.
//!
//! **Noise floor.** The error left when the model is exactly right: each window's own
//! prediction is taken as the truth, noise of the size measured in the data (residual of local
//! quadratic fits) is added, and the whole procedure — initial-state fit, prediction,
//! scoring — is run on that. What the real comparison shows above this floor is the model's.

use glam::DVec3;

use crate::euler::EulerZyx;
use crate::flight::data::FlightData;
use crate::flight::derive::unwrap_angles;
use crate::flight::model::{Model, State, Vehicle};
use crate::flight::Controls;
use crate::numeric::{attitude_error_deg, quad_fit};

/// Settings of a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareConfig {
    /// Window length, s.
    pub window_s: f64,
    /// Span at each window start used to estimate the initial state, s.
    pub fit_s: f64,
    /// Longest integration step, s.
    pub max_dt: f64,
    /// Use at most this many windows, evenly spread (0 = all). Fitting uses a subset for speed.
    pub max_windows: usize,
    /// Point mass: refine each window's initial position and velocity by least squares over
    /// the whole window (Gauss–Newton), so that what is left is measurement noise plus the
    /// model's own error (see module docs).
    pub refine_point_mass: bool,
}

impl CompareConfig {
    /// The window length that suits a vehicle, s. A fixed wing: 8 s, a few periods of its
    /// short-period and roll modes but short enough that an unstable spiral or phugoid cannot
    /// run away. A point mass: 60 s (in practice, the whole flight), since it has no unstable
    /// mode and its start is fitted over the whole window, and slow effects (drag on a long
    /// fall, the Earth's rotation and curvature) need tens of seconds to show.
    pub fn default_window_s(vehicle: crate::flight::VehicleKind) -> f64 {
        match vehicle {
            crate::flight::VehicleKind::FixedWing => 8.0,
            crate::flight::VehicleKind::PointMass => 60.0,
        }
    }
}

impl Default for CompareConfig {
    fn default() -> Self {
        Self {
            window_s: 8.0,
            fit_s: 0.5,
            max_dt: 0.02,
            max_windows: 0,
            refine_point_mass: true,
        }
    }
}

/// RMS errors per channel (None where the data lack the channel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelErrors {
    /// Position, m.
    pub position_m: f64,
    /// NED velocity, m/s.
    pub velocity_mps: Option<f64>,
    /// Attitude, degrees.
    pub attitude_deg: Option<f64>,
}

impl ChannelErrors {
    /// Combined score: RMS of the channels normalised by 1 m, 1 m/s, 1°.
    pub fn score(&self) -> f64 {
        let mut sum = self.position_m.powi(2);
        let mut k = 1.0;
        for v in [self.velocity_mps, self.attitude_deg].into_iter().flatten() {
            sum += v * v;
            k += 1.0;
        }
        (sum / k).sqrt()
    }

    /// The channel with the largest normalised error.
    pub fn dominant(&self) -> &'static str {
        let mut best = ("position", self.position_m);
        if let Some(v) = self.velocity_mps {
            if v > best.1 {
                best = ("velocity", v);
            }
        }
        if let Some(a) = self.attitude_deg {
            if a > best.1 {
                best = ("attitude", a);
            }
        }
        best.0
    }
}

/// One window of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowResult {
    /// Start time, s.
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// First and one-past-last sample index.
    pub samples: (usize, usize),
    /// RMS errors in this window.
    pub errors: ChannelErrors,
    /// The window's score ([`ChannelErrors::score`]).
    pub score: f64,
}

/// The model's prediction at every sample of the compared windows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prediction {
    /// Sample indices.
    pub index: Vec<usize>,
    /// Predicted position, NED.
    pub pos_ned: Vec<DVec3>,
    /// Predicted NED velocity.
    pub vel_ned: Vec<DVec3>,
    /// Predicted attitude (aerospace angles); identity for a point mass.
    pub attitude: Vec<EulerZyx>,
}

/// Result of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Total score (see module docs).
    pub total: f64,
    /// RMS per channel over all windows.
    pub channels: ChannelErrors,
    /// Windows in time order.
    pub windows: Vec<WindowResult>,
    /// Per-sample prediction.
    pub prediction: Prediction,
}

impl Comparison {
    /// Windows sorted worst first.
    pub fn worst_windows(&self) -> Vec<&WindowResult> {
        let mut w: Vec<&WindowResult> = self.windows.iter().collect();
        w.sort_by(|a, b| b.score.total_cmp(&a.score));
        w
    }
}

/// Estimated measurement noise (standard deviations) of the data's channels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoiseEstimate {
    /// Position, m.
    pub pos_m: f64,
    /// Velocity, m/s.
    pub vel_mps: f64,
    /// Attitude, rad.
    pub att_rad: f64,
    /// Body rates, rad/s.
    pub rate_radps: f64,
}

/// Everything precomputed once per data set and reused across model evaluations.
pub struct Prepared<'a> {
    /// The data.
    pub data: &'a FlightData,
    /// Attitude angles unwrapped per axis (yaw, pitch, roll), rad.
    unwrapped: Option<[Vec<f64>; 3]>,
    /// Window sample ranges.
    pub windows: Vec<(usize, usize)>,
    cfg: CompareConfig,
}

impl<'a> Prepared<'a> {
    /// Cut the data into windows and precompute what every evaluation needs.
    pub fn new(data: &'a FlightData, cfg: CompareConfig) -> Self {
        let unwrapped = data.attitude.as_ref().map(|att| {
            [
                unwrap_angles(&att.iter().map(|e| e.yaw).collect::<Vec<_>>()),
                unwrap_angles(&att.iter().map(|e| e.pitch).collect::<Vec<_>>()),
                unwrap_angles(&att.iter().map(|e| e.roll).collect::<Vec<_>>()),
            ]
        });
        let mut windows = Vec::new();
        let n = data.len();
        let mut start = 0;
        while start + 2 < n {
            let t_end = data.time[start] + cfg.window_s;
            let end = data
                .time
                .partition_point(|&t| t < t_end)
                .max(start + 2)
                .min(n);
            // A trailing stub shorter than half a window joins the window before it (no data
            // is left out, and no window is too short to show anything).
            if data.time[end - 1] - data.time[start] < 0.5 * cfg.window_s {
                if let Some(last) = windows.last_mut() {
                    let last: &mut (usize, usize) = last;
                    last.1 = end;
                    break;
                }
            }
            windows.push((start, end));
            start = end;
        }
        if cfg.max_windows > 0 && windows.len() > cfg.max_windows {
            let step = windows.len() as f64 / cfg.max_windows as f64;
            windows = (0..cfg.max_windows)
                .map(|i| windows[(i as f64 * step) as usize])
                .collect();
        }
        Self {
            data,
            unwrapped,
            windows,
            cfg,
        }
    }

    /// The settings.
    pub fn config(&self) -> CompareConfig {
        self.cfg
    }

    /// Estimated state at the first sample of a window (see module docs).
    pub fn initial_state(&self, model: &Model, start: usize, end: usize) -> State {
        let surfaces = match model.vehicle {
            Vehicle::FixedWing(_) => surfaces_at(model, self.data, start),
            Vehicle::PointMass => DVec3::ZERO,
        };
        self.initial_state_with(model, start, end, surfaces)
    }

    /// [`Self::initial_state`] with the surface positions at `start` already known (see
    /// [`SurfaceTracker`]).
    fn initial_state_with(
        &self,
        model: &Model,
        start: usize,
        end: usize,
        surfaces: DVec3,
    ) -> State {
        let d = self.data;
        let t0 = d.time[start];
        let fit_end = d.time[start..end]
            .partition_point(|&t| t < t0 + self.cfg.fit_s)
            .max(3.min(end - start))
            + start;
        let ts = &d.time[start..fit_end];
        let fit = |vals: &dyn Fn(usize) -> f64| {
            let y: Vec<f64> = (start..fit_end).map(vals).collect();
            quad_fit(ts, &y, t0)
        };
        let (px, vx) = fit(&|i| d.pos_ned[i].x);
        let (py, vy) = fit(&|i| d.pos_ned[i].y);
        let (pz, vz) = fit(&|i| d.pos_ned[i].z);
        let pos = DVec3::new(px, py, pz);
        let mut vel_ned = DVec3::new(vx, vy, vz);
        if let Some(v) = &d.vel_ned {
            // Measured velocities, when present, are smoothed the same way and preferred:
            // they are what the differentiator would otherwise have to reconstruct.
            if !d.is_derived("vel_ned") {
                vel_ned = DVec3::new(fit(&|i| v[i].x).0, fit(&|i| v[i].y).0, fit(&|i| v[i].z).0);
            }
        }
        let mut x = State::default();
        x.set_pos_ned(pos);
        match &model.vehicle {
            Vehicle::PointMass => x.set_vel(vel_ned),
            Vehicle::FixedWing(_) => {
                let (att, att_rate) = match &self.unwrapped {
                    Some([yaw, pitch, roll]) => {
                        let (y0, yd) = fit(&|i| yaw[i]);
                        let (p0, pd) = fit(&|i| pitch[i]);
                        let (r0, rd) = fit(&|i| roll[i]);
                        (EulerZyx::new(y0, p0, r0), [yd, pd, rd])
                    }
                    None => (EulerZyx::default(), [0.0; 3]),
                };
                x.set_attitude(att);
                x.set_vel(att.to_matrix().transpose() * vel_ned);
                let omega = match &d.rates_body {
                    Some(w) if !d.is_derived("rates_body") => {
                        DVec3::new(fit(&|i| w[i].x).0, fit(&|i| w[i].y).0, fit(&|i| w[i].z).0)
                    }
                    _ => {
                        // Body rates from the Euler-angle rates of the fit.
                        let [psi_d, theta_d, phi_d] = att_rate;
                        let (sphi, cphi) = att.roll.sin_cos();
                        let (sth, cth) = att.pitch.sin_cos();
                        DVec3::new(
                            phi_d - psi_d * sth,
                            theta_d * cphi + psi_d * cth * sphi,
                            -theta_d * sphi + psi_d * cth * cphi,
                        )
                    }
                };
                x.set_omega(omega);
                x.set_surfaces(surfaces);
            }
        }
        x
    }

    /// Position + velocity residuals of a point-mass prediction from `x0` over a window.
    fn point_mass_residuals(
        &self,
        model: &Model,
        (start, end): (usize, usize),
        x0: State,
        scratch: &mut Prediction,
        out: &mut Vec<f64>,
    ) {
        let d = self.data;
        *scratch = Prediction::default();
        self.predict(model, start, end, x0, scratch);
        out.clear();
        for (k, i) in (start..end).enumerate() {
            let e = scratch.pos_ned[k] - d.pos_ned[i];
            out.extend([e.x, e.y, e.z]);
            if let Some(v) = &d.vel_ned {
                let e = scratch.vel_ned[k] - v[i];
                out.extend([e.x, e.y, e.z]);
            }
        }
    }

    /// Gauss–Newton refinement of a point mass's initial position and velocity over the whole
    /// window (see module docs). Keeps `x0` when a step does not lower the error.
    fn refine_point_mass(
        &self,
        model: &Model,
        start: usize,
        end: usize,
        x0: State,
        scratch: &mut Prediction,
    ) -> State {
        let get = |x: &State| {
            let (p, v) = (x.pos_ned(), x.vel());
            [p.x, p.y, p.z, v.x, v.y, v.z]
        };
        let set = |x: &mut State, q: &[f64; 6]| {
            x.set_pos_ned(DVec3::new(q[0], q[1], q[2]));
            x.set_vel(DVec3::new(q[3], q[4], q[5]));
        };
        let mut x = x0;
        let (mut r, mut rj) = (Vec::new(), Vec::new());
        self.point_mass_residuals(model, (start, end), x, scratch, &mut r);
        let mut sse: f64 = r.iter().map(|e| e * e).sum();
        for _ in 0..3 {
            let q = get(&x);
            // Jacobian columns by forward differences (1 cm, 1 cm/s: the trajectory is nearly
            // affine in these, so the step size hardly matters).
            let mut jac: Vec<Vec<f64>> = Vec::with_capacity(6);
            for k in 0..6 {
                let mut qk = q;
                qk[k] += 0.01;
                let mut xk = x;
                set(&mut xk, &qk);
                self.point_mass_residuals(model, (start, end), xk, scratch, &mut rj);
                jac.push(rj.iter().zip(&r).map(|(a, b)| (a - b) / 0.01).collect());
            }
            let mut jtj = [[0.0f64; 6]; 6];
            let mut jtr = [0.0f64; 6];
            for a in 0..6 {
                for b in 0..6 {
                    jtj[a][b] = jac[a].iter().zip(&jac[b]).map(|(u, v)| u * v).sum();
                }
                jtr[a] = jac[a].iter().zip(&r).map(|(u, v)| u * v).sum();
            }
            let Some(step) = crate::numeric::solve(jtj, jtr) else {
                break;
            };
            let mut qn = q;
            for k in 0..6 {
                qn[k] -= step[k];
            }
            let mut xn = x;
            set(&mut xn, &qn);
            self.point_mass_residuals(model, (start, end), xn, scratch, &mut rj);
            let sse_new: f64 = rj.iter().map(|e| e * e).sum();
            if !(sse_new < sse) {
                break;
            }
            let converged = sse - sse_new < 1e-9 * sse;
            x = xn;
            sse = sse_new;
            std::mem::swap(&mut r, &mut rj);
            if converged {
                break;
            }
        }
        x
    }

    /// Fly the model through one window from `x0`; returns predictions at each sample.
    fn predict(&self, model: &Model, start: usize, end: usize, x0: State, out: &mut Prediction) {
        let d = self.data;
        let mut x = x0;
        for i in start..end {
            out.index.push(i);
            out.pos_ned.push(x.pos_ned());
            match model.vehicle {
                Vehicle::PointMass => {
                    out.vel_ned.push(x.vel());
                    out.attitude.push(EulerZyx::default());
                }
                Vehicle::FixedWing(_) => {
                    out.vel_ned.push(x.rot() * x.vel());
                    out.attitude.push(x.attitude());
                }
            }
            if i + 1 < end {
                let cmd = controls_at(d, i);
                x = model.advance(d.time[i], &x, &cmd, d.time[i + 1], self.cfg.max_dt);
                if !x.is_finite() {
                    // Diverged: hold the last finite prediction (scored as a large error).
                    for _ in i + 1..end {
                        let k = out.pos_ned.len() - 1;
                        out.index.push(out.index[k] + 1);
                        out.pos_ned.push(out.pos_ned[k]);
                        out.vel_ned.push(out.vel_ned[k]);
                        out.attitude.push(out.attitude[k]);
                    }
                    return;
                }
            }
        }
    }
}

/// Commands in force from sample i (zero for data without controls).
fn controls_at(d: &FlightData, i: usize) -> Controls {
    d.controls.as_ref().map(|c| c[i]).unwrap_or_default()
}

/// Surface positions at sample `upto` under the model's actuator lag (the commands
/// themselves without one): the exact zero-order-hold discretisation of τẋ = cmd − x,
/// started at the first command.
pub fn surfaces_at(model: &Model, d: &FlightData, upto: usize) -> DVec3 {
    let Some(controls) = &d.controls else {
        return DVec3::ZERO;
    };
    let as_vec = |c: &Controls| DVec3::new(c.elevator, c.aileron, c.rudder);
    let tau = model.effects.iter().find_map(|e| e.actuator_tau());
    match tau {
        None => as_vec(&controls[upto]),
        Some(tau) => {
            let mut s = as_vec(&controls[0]);
            for i in 0..upto {
                let a = 1.0 - (-(d.time[i + 1] - d.time[i]) / tau).exp();
                s += a * (as_vec(&controls[i]) - s);
            }
            s
        }
    }
}

/// [`surfaces_at`] for increasing sample indices in O(total samples): the lag filter carries
/// its state from one window start to the next instead of starting over from the first
/// command (which made a comparison O(samples × windows)).
struct SurfaceTracker<'a> {
    data: &'a FlightData,
    tau: Option<f64>,
    index: usize,
    state: DVec3,
    /// (dt, 1 − e^(−dt/τ)) of the last step: uniform sampling needs one `exp`.
    gain_cache: (f64, f64),
}

impl<'a> SurfaceTracker<'a> {
    fn new(model: &Model, data: &'a FlightData) -> Self {
        let state = data
            .controls
            .as_ref()
            .and_then(|c| c.first())
            .map(|c| DVec3::new(c.elevator, c.aileron, c.rudder))
            .unwrap_or(DVec3::ZERO);
        Self {
            data,
            tau: model.effects.iter().find_map(|e| e.actuator_tau()),
            index: 0,
            state,
            gain_cache: (f64::NAN, 0.0),
        }
    }

    /// Surface positions at sample `upto` (≥ every earlier call's).
    fn at(&mut self, upto: usize) -> DVec3 {
        let Some(controls) = &self.data.controls else {
            return DVec3::ZERO;
        };
        let as_vec = |c: &Controls| DVec3::new(c.elevator, c.aileron, c.rudder);
        let Some(tau) = self.tau else {
            return as_vec(&controls[upto]);
        };
        debug_assert!(upto >= self.index);
        let time = &self.data.time;
        for i in self.index..upto {
            let dt = time[i + 1] - time[i];
            if dt != self.gain_cache.0 {
                self.gain_cache = (dt, 1.0 - (-dt / tau).exp());
            }
            self.state += self.gain_cache.1 * (as_vec(&controls[i]) - self.state);
        }
        self.index = self.index.max(upto);
        self.state
    }
}

/// Score predictions against measurements (or against `truth` when given).
fn score_windows(
    prep: &Prepared,
    pred: &Prediction,
    meas_pos: &[DVec3],
    meas_vel: Option<&[DVec3]>,
    meas_att: Option<&[EulerZyx]>,
) -> (Vec<WindowResult>, ChannelErrors) {
    let d = prep.data;
    let mut windows = Vec::with_capacity(prep.windows.len());
    let (mut sp, mut sv, mut sa, mut n) = (0.0, 0.0, 0.0, 0.0);
    let mut k = 0;
    for &(start, end) in &prep.windows {
        let (mut wp, mut wv, mut wa) = (0.0, 0.0, 0.0);
        for i in start..end {
            wp += (pred.pos_ned[k] - meas_pos[i]).length_squared();
            if let Some(v) = meas_vel {
                wv += (pred.vel_ned[k] - v[i]).length_squared();
            }
            if let Some(a) = meas_att {
                wa += attitude_error_deg(&pred.attitude[k], &a[i]).powi(2);
            }
            k += 1;
        }
        let m = (end - start) as f64;
        sp += wp;
        sv += wv;
        sa += wa;
        n += m;
        let errors = ChannelErrors {
            position_m: (wp / m).sqrt(),
            velocity_mps: meas_vel.map(|_| (wv / m).sqrt()),
            attitude_deg: meas_att.map(|_| (wa / m).sqrt()),
        };
        windows.push(WindowResult {
            t0: d.time[start],
            t1: d.time[end - 1],
            samples: (start, end),
            score: errors.score(),
            errors,
        });
    }
    let channels = ChannelErrors {
        position_m: (sp / n).sqrt(),
        velocity_mps: meas_vel.map(|_| (sv / n).sqrt()),
        attitude_deg: meas_att.map(|_| (sa / n).sqrt()),
    };
    (windows, channels)
}

/// Compare a model with prepared data.
pub fn compare_prepared(model: &Model, prep: &Prepared) -> Comparison {
    let d = prep.data;
    let mut pred = Prediction::default();
    let mut scratch = Prediction::default();
    let mut surfaces = SurfaceTracker::new(model, d);
    for &(start, end) in &prep.windows {
        let mut x0 = prep.initial_state_with(model, start, end, surfaces.at(start));
        if prep.cfg.refine_point_mass && matches!(model.vehicle, Vehicle::PointMass) {
            x0 = prep.refine_point_mass(model, start, end, x0, &mut scratch);
        }
        prep.predict(model, start, end, x0, &mut pred);
    }
    let meas_vel = d.vel_ned.as_deref();
    let meas_att = match model.vehicle {
        Vehicle::FixedWing(_) => d.attitude.as_deref(),
        Vehicle::PointMass => None,
    };
    let (windows, channels) = score_windows(prep, &pred, &d.pos_ned, meas_vel, meas_att);
    let total = total_score(&windows);
    Comparison {
        total,
        channels,
        windows,
        prediction: pred,
    }
}

/// RMS of window scores, weighted by window length in samples.
fn total_score(windows: &[WindowResult]) -> f64 {
    let (mut s, mut n) = (0.0, 0.0);
    for w in windows {
        let m = (w.samples.1 - w.samples.0) as f64;
        s += w.score * w.score * m;
        n += m;
    }
    if n > 0.0 {
        (s / n).sqrt()
    } else {
        0.0
    }
}

/// Compare a model with flight data.
pub fn compare(model: &Model, data: &FlightData, cfg: CompareConfig) -> Comparison {
    compare_prepared(model, &Prepared::new(data, cfg))
}

/// Measurement noise of the data, estimated from the residuals of local quadratic fits over
/// ±`half` samples (the fit absorbs the motion; what is left is noise), corrected for the
/// fit's degrees of freedom.
pub fn estimate_noise(d: &FlightData) -> NoiseEstimate {
    let half = 6usize;
    let resid_rms = |get: &dyn Fn(usize) -> f64| -> f64 {
        let n = d.len();
        if n < 2 * half + 1 {
            return 0.0;
        }
        let (mut s, mut m) = (0.0, 0.0);
        let mut i = half;
        while i + half < n {
            let ts = &d.time[i - half..=i + half];
            let ys: Vec<f64> = (i - half..=i + half).map(get).collect();
            let (y0, _) = quad_fit(ts, &ys, d.time[i]);
            s += (ys[half] - y0).powi(2);
            m += 1.0;
            i += half; // thinned: neighbouring residuals share their fits
        }
        // Residual at the centre of a (2h+1)-point quadratic fit has variance σ²(1 − h_ii).
        let npts = (2 * half + 1) as f64;
        let leverage = (3.0 * (3.0 * npts * npts - 7.0)) / (4.0 * npts * (npts * npts - 4.0));
        (s / m / (1.0 - leverage)).sqrt()
    };
    let axis3 = |get: &dyn Fn(usize) -> DVec3| -> f64 {
        let a = resid_rms(&|i| get(i).x);
        let b = resid_rms(&|i| get(i).y);
        let c = resid_rms(&|i| get(i).z);
        ((a * a + b * b + c * c) / 3.0).sqrt()
    };
    let pos_m = axis3(&|i| d.pos_ned[i]);
    let vel_mps = match &d.vel_ned {
        Some(v) if !d.is_derived("vel_ned") => axis3(&|i| v[i]),
        _ => 0.0,
    };
    let att_rad = match &d.attitude {
        Some(att) => {
            let un = [
                unwrap_angles(&att.iter().map(|e| e.yaw).collect::<Vec<_>>()),
                unwrap_angles(&att.iter().map(|e| e.pitch).collect::<Vec<_>>()),
                unwrap_angles(&att.iter().map(|e| e.roll).collect::<Vec<_>>()),
            ];
            axis3(&|i| DVec3::new(un[0][i], un[1][i], un[2][i]))
        }
        None => 0.0,
    };
    let rate_radps = match &d.rates_body {
        Some(w) if !d.is_derived("rates_body") => axis3(&|i| w[i]),
        _ => 0.0,
    };
    NoiseEstimate {
        pos_m,
        vel_mps,
        att_rad,
        rate_radps,
    }
}

/// The error the comparison would show if `model` were exactly right, given measurement noise
/// `noise`: each window's prediction becomes the truth, deterministic pseudo-random noise of
/// that size is added, and the comparison is rerun on the result (see module docs).
pub fn noise_floor(model: &Model, prep: &Prepared, noise: &NoiseEstimate, seed: u64) -> f64 {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let reference = compare_prepared(model, prep);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut gauss = |s: f64| {
        if s > 0.0 {
            Normal::new(0.0, s).expect("finite").sample(&mut rng)
        } else {
            0.0
        }
    };
    let d = prep.data;
    let mut synth = d.clone();
    let p = &reference.prediction;
    for (k, &i) in p.index.iter().enumerate() {
        synth.pos_ned[i] =
            p.pos_ned[k] + DVec3::new(gauss(noise.pos_m), gauss(noise.pos_m), gauss(noise.pos_m));
        if let Some(v) = synth.vel_ned.as_mut() {
            v[i] = p.vel_ned[k]
                + DVec3::new(
                    gauss(noise.vel_mps),
                    gauss(noise.vel_mps),
                    gauss(noise.vel_mps),
                );
        }
        if let (Some(a), Vehicle::FixedWing(_)) = (synth.attitude.as_mut(), &model.vehicle) {
            let e = p.attitude[k];
            a[i] = EulerZyx::new(
                e.yaw + gauss(noise.att_rad),
                e.pitch + gauss(noise.att_rad),
                e.roll + gauss(noise.att_rad),
            );
        }
    }
    // Rates: the truth's rates are not kept per sample; measured ones keep their noise level
    // around the data (a slight over-estimate of the floor, on the safe side).
    // Same times and settings, so the same windows.
    let synth_prep = Prepared::new(&synth, prep.cfg);
    compare_prepared(model, &synth_prep).total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flight::effects::{ActuatorLag, Origin};
    use crate::flight::params::FixedWingParams;

    /// The incremental tracker gives exactly the from-the-start filter, on uneven sampling.
    #[test]
    fn surface_tracker_matches_filtering_from_the_start() {
        let mut data = FlightData::default();
        let mut controls = Vec::new();
        let mut t = 0.0;
        for i in 0..400 {
            data.time.push(t);
            data.pos_ned.push(DVec3::ZERO);
            t += if i % 7 == 0 { 0.03 } else { 0.02 };
            let step = if (i / 50) % 2 == 0 { 0.1 } else { -0.1 };
            controls.push(Controls {
                throttle: 0.5,
                elevator: step,
                aileron: -step,
                rudder: 0.5 * step,
            });
        }
        data.controls = Some(controls);
        let mut model = Model::new(
            Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
            Origin::default(),
        );
        for lagged in [false, true] {
            if lagged {
                model
                    .add_effect(Box::new(ActuatorLag { tau_s: 0.15 }))
                    .unwrap();
            }
            let mut tracker = SurfaceTracker::new(&model, &data);
            for upto in [0, 1, 13, 13, 50, 51, 200, 399] {
                let fast = tracker.at(upto);
                let slow = surfaces_at(&model, &data, upto);
                assert!((fast - slow).length() < 1e-12, "{upto}: {fast} vs {slow}");
            }
        }
    }
}
