//! The start state of each window, estimated — not read off.
//!
//! **Warm start.** Least-squares quadratics in time over the first `fit_s` seconds of the
//! window: through positions (→ position and velocity), through the unwrapped attitude
//! angles (→ attitude and, without rate gyros, rates), through measured velocities and body
//! rates. Cheap, but biased where the window starts in a transient (a control step, a roll
//! acceleration): the quadratic cannot follow it, and the open-loop prediction then diverges
//! from the wrong start — an error that is the comparison's, not the model's.
//!
//! **Output-error fit.** The start state is then a free parameter of the comparison, as in
//! aircraft system identification with estimated initial conditions: Levenberg–Marquardt on
//! the model's own prediction over the window (or its first `span` seconds), minimising the
//! noise-weighted misfit of every measured channel — position, velocity, attitude, body
//! rates, airspeed — with the Jacobian of one tangent-linear flight (`sensitivity.rs`;
//! forward differences, one flight per start number, only where that flight diverges). Twelve
//! numbers for a fixed wing (position, NED velocity, roll/pitch/yaw, p/q/r), six for a point
//! mass. Surface positions under actuator lag are not fitted: they follow from the commands.

use glam::DVec3;

use super::predict::{fly_window, Predicted};
use super::Prepared;
use wireflight_flight::model::{Model, State, Vehicle};
use wireflight_flight::numeric::{axpy, dot, gram, quad_fit, solve_in_place};
use wireflight_geometry::euler::EulerZyx;

/// Forward-difference steps of the start parameters: position m, velocity m/s, angles rad,
/// rates rad/s. Small against every noise level of interest, large against rounding (the
/// flown trajectory is smooth in its start state).
const STEPS: [f64; 4] = [1e-4, 1e-4, 1e-6, 1e-6];

/// Stop when the next step promises to lower the misfit (χ², in units of the noise variance)
/// by less than this: far below anything a significance test could see.
pub const ABS_TOL: f64 = 1e-3;
/// ... or by less than this fraction of it. A window's χ² scatters by √(2ν) — about 140 for
/// the 10⁴ residuals of 8 s at 100 Hz — so this is a hundredth of its own noise at the
/// floor; and a model far from the data (χ² of 10⁶ in a window) need not have its start
/// polished to a thousandth of a noise unit.
pub const REL_TOL: f64 = 1e-5;

/// Number of start parameters of a vehicle.
pub fn param_count(model: &Model) -> usize {
    match model.vehicle {
        Vehicle::PointMass => 6,
        Vehicle::FixedWing(_) => 12,
    }
}

/// The start parameters of a state: position, NED velocity, and for a fixed wing roll, pitch,
/// yaw and body rates.
pub fn params_of(model: &Model, x: &State) -> Vec<f64> {
    let p = x.pos_ned();
    match model.vehicle {
        Vehicle::PointMass => {
            let v = x.vel();
            vec![p.x, p.y, p.z, v.x, v.y, v.z]
        }
        Vehicle::FixedWing(_) => {
            let v = x.rot() * x.vel();
            let e = x.attitude();
            let w = x.omega();
            vec![
                p.x, p.y, p.z, v.x, v.y, v.z, e.roll, e.pitch, e.yaw, w.x, w.y, w.z,
            ]
        }
    }
}

/// The state of start parameters, with the given surface positions.
pub fn state_of(model: &Model, q: &[f64], surfaces: DVec3) -> State {
    let mut x = State::default();
    x.set_pos_ned(DVec3::new(q[0], q[1], q[2]));
    let vel = DVec3::new(q[3], q[4], q[5]);
    match model.vehicle {
        Vehicle::PointMass => x.set_vel(vel),
        Vehicle::FixedWing(_) => {
            let att = EulerZyx::new(q[8], q[7], q[6]);
            x.set_attitude(att);
            x.set_vel(att.to_matrix().transpose() * vel);
            x.set_omega(DVec3::new(q[9], q[10], q[11]));
            x.set_surfaces(surfaces);
        }
    }
    x
}

pub(crate) fn step_of(k: usize) -> f64 {
    STEPS[(k / 3).min(3)]
}

impl Prepared<'_> {
    /// Warm start at the first sample of a window (module docs).
    pub fn warm_start(
        &self,
        model: &Model,
        (start, end): (usize, usize),
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
        let mut vel_ned = DVec3::new(vx, vy, vz);
        if let (Some(v), true) = (&d.vel_ned, self.measured.velocity) {
            vel_ned = DVec3::new(fit(&|i| v[i].x).0, fit(&|i| v[i].y).0, fit(&|i| v[i].z).0);
        }
        let mut q = vec![px, py, pz, vel_ned.x, vel_ned.y, vel_ned.z];
        if matches!(model.vehicle, Vehicle::FixedWing(_)) {
            let (att, att_rate) = match &self.unwrapped {
                Some([yaw, pitch, roll]) => {
                    let (y0, yd) = fit(&|i| yaw[i]);
                    let (p0, pd) = fit(&|i| pitch[i]);
                    let (r0, rd) = fit(&|i| roll[i]);
                    (EulerZyx::new(y0, p0, r0), [yd, pd, rd])
                }
                None => (EulerZyx::default(), [0.0; 3]),
            };
            let omega = match (&d.rates_body, self.measured.rates) {
                (Some(w), true) => {
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
            q.extend([att.roll, att.pitch, att.yaw, omega.x, omega.y, omega.z]);
        }
        state_of(model, &q, surfaces)
    }

    /// The samples of a window that the start fit uses: all of them, or the first `span`
    /// seconds.
    pub fn fit_range(&self, (start, end): (usize, usize)) -> (usize, usize) {
        match self.cfg.start_span_s {
            Some(span) => {
                let t_end = self.data.time[start] + span;
                let n = self.data.time[start..end].partition_point(|&t| t < t_end);
                (start, start + n.max(2.min(end - start)))
            }
            None => (start, end),
        }
    }

    /// Fit the start state of a window by Levenberg–Marquardt from `x0` (module docs). The
    /// Jacobian is taken once (tangent-linear), then kept current by Broyden's rank-one
    /// updates (taken afresh when an updated one stops leading downhill); the fit stops when
    /// the next step would lower the misfit by less than [`ABS_TOL`] (in units of the noise
    /// variance: nothing a significance test could see) or a relative [`REL_TOL`].
    pub fn fit_start(
        &self,
        model: &Model,
        window: (usize, usize),
        x0: State,
        scratch: &mut Scratch,
    ) -> StartFit {
        self.fit_start_with(model, window, x0, None, scratch)
    }

    /// [`fit_start`](Self::fit_start) beginning with `jacobian` (column-major, as
    /// [`StartFit::jacobian`]) instead of a fresh forward-difference one: another model's on
    /// the same window, e.g. the base model's when fitting a candidate that differs from it
    /// by an effect. It is kept current by Broyden's updates and taken afresh, like an updated
    /// one, as soon as it stops leading downhill; one of the wrong size is not used.
    pub fn fit_start_with(
        &self,
        model: &Model,
        window: (usize, usize),
        x0: State,
        jacobian: Option<&[f64]>,
        scratch: &mut Scratch,
    ) -> StartFit {
        let span = self.fit_range(window);
        let surfaces = x0.surfaces();
        let np = param_count(model);
        let mut q = params_of(model, &x0);
        let mut r = Vec::new();
        self.window_residuals(model, span, &state_of(model, &q, surfaces), scratch, &mut r);
        scratch.accept();
        let mut sse = sum_sq(&r);
        let m = r.len();
        let mut fit = StartFit {
            state: x0,
            iterations: 0,
            jacobian: Vec::new(),
            residuals: Vec::new(),
            params: np,
        };
        if !sse.is_finite() || m == 0 {
            fit.residuals = r;
            return fit;
        }
        let (mut jac, mut fresh) = match jacobian {
            Some(j) if j.len() == np * m && j.iter().all(|v| v.is_finite()) => (j.to_vec(), false),
            _ => {
                let mut jac = Vec::new(); // column-major
                self.jacobian_at(model, span, &q, surfaces, &r, scratch, &mut jac);
                (jac, true)
            }
        };
        // JᵀJ follows the Jacobian: taken afresh with it, updated with it by Broyden.
        let mut jtj = gram(&jac, np, m);
        let mut lambda = 1e-6;
        let mut trial = Vec::with_capacity(m);
        let mut step = vec![0.0; np];
        let mut iteration = 0;
        let mut tries = 0;
        // Jᵀr, taken afresh with the Jacobian and carried by Broyden's update with it.
        let mut jtr = gradient(&jac, &r, np);
        while iteration < self.cfg.start_iterations && tries < 16 {
            tries += 1;
            let mut a = jtj.clone();
            for k in 0..np {
                a[k * np + k] += lambda * jtj[k * np + k].max(1e-30);
            }
            step.iter_mut().zip(&jtr).for_each(|(s, g)| *s = -g);
            let solved = solve_in_place(&mut a, &mut step, np).is_some();
            // The decrease the linear model promises: χ² − |r + Jδ|² = −2gᵀδ − δᵀJᵀJδ.
            let g_step: f64 = jtr.iter().zip(&step).map(|(g, d)| g * d).sum();
            let quad: f64 = (0..np)
                .map(|a| {
                    (0..np)
                        .map(|b| step[a] * jtj[a * np + b] * step[b])
                        .sum::<f64>()
                })
                .sum();
            let promised = -2.0 * g_step - quad;
            if solved && promised < ABS_TOL.max(REL_TOL * sse) {
                break; // converged: nothing left worth a flight
            }
            if solved {
                let qn: Vec<f64> = q.iter().zip(&step).map(|(a, b)| a + b).collect();
                self.window_residuals(
                    model,
                    span,
                    &state_of(model, &qn, surfaces),
                    scratch,
                    &mut trial,
                );
                let sse_new = sum_sq(&trial);
                if sse_new < sse {
                    iteration += 1;
                    jtr = broyden_update(&mut jac, &mut jtj, &step, &r, &trial, np, m);
                    q = qn;
                    sse = sse_new;
                    std::mem::swap(&mut r, &mut trial);
                    scratch.accept();
                    lambda = (lambda / 10.0).max(1e-12);
                    fresh = false;
                    continue;
                }
            }
            if fresh {
                lambda *= 10.0; // an exact Jacobian overshot: shorter steps
            } else {
                // An updated Jacobian that misleads: take it afresh.
                self.jacobian_at(model, span, &q, surfaces, &r, scratch, &mut jac);
                jtj = gram(&jac, np, m);
                jtr = gradient(&jac, &r, np);
                fresh = true;
            }
        }
        fit.state = state_of(model, &q, surfaces);
        fit.iterations = iteration;
        fit.jacobian = jac;
        fit.residuals = r;
        fit
    }

    /// The Jacobian of the window residuals `r` at start parameters `q` into `jac`
    /// (column-major): from the tangent-linear equations along the accepted flight, the one
    /// `r` came from ([`Prepared::tangent_jacobian`]), or by forward differences where that
    /// flight diverged.
    #[allow(clippy::too_many_arguments)]
    fn jacobian_at(
        &self,
        model: &Model,
        span: (usize, usize),
        q: &[f64],
        surfaces: DVec3,
        r: &[f64],
        scratch: &mut Scratch,
        jac: &mut Vec<f64>,
    ) {
        let tangent =
            self.tangent_jacobian(model, span, q, surfaces, &scratch.accepted_states, r, jac);
        if !tangent || jac.len() != q.len() * r.len() {
            jac.clear();
            jac.resize(q.len() * r.len(), 0.0);
            self.difference_jacobian(model, span, q, surfaces, r, scratch, jac);
        }
    }

    /// Forward-difference Jacobian of the window residuals `r` at start parameters `q`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn difference_jacobian(
        &self,
        model: &Model,
        span: (usize, usize),
        q: &[f64],
        surfaces: DVec3,
        r: &[f64],
        scratch: &mut Scratch,
        jac: &mut [f64],
    ) {
        let m = r.len();
        let mut trial = Vec::with_capacity(m);
        for k in 0..q.len() {
            let h = step_of(k);
            let mut qk = q.to_vec();
            qk[k] += h;
            self.window_residuals(
                model,
                span,
                &state_of(model, &qk, surfaces),
                scratch,
                &mut trial,
            );
            let col = &mut jac[k * m..(k + 1) * m];
            for ((j, a), b) in col.iter_mut().zip(&trial).zip(r) {
                *j = (a - b) / h;
            }
        }
    }

    /// Noise-weighted residuals of the prediction from `x0` over the samples of `span`.
    pub fn window_residuals(
        &self,
        model: &Model,
        span: (usize, usize),
        x0: &State,
        scratch: &mut Scratch,
        out: &mut Vec<f64>,
    ) {
        fly_window(
            model,
            self.data,
            span,
            x0,
            self.cfg.max_dt,
            &mut scratch.predicted,
            &mut scratch.states,
        );
        out.clear();
        for (k, i) in (span.0..span.1).enumerate() {
            self.residual_rows(model, i, &scratch.predicted[k], out);
        }
    }
}

/// A fitted start state.
#[derive(Clone, Debug)]
pub struct StartFit {
    /// The start state.
    pub state: State,
    /// Levenberg–Marquardt iterations taken.
    pub iterations: usize,
    /// The last Jacobian of the weighted residuals (over the fit span) with respect to the
    /// start parameters, column-major, `params` columns; empty when no iteration ran. Near
    /// the optimum it spans the directions in which a start change can absorb an error —
    /// what a parameter fit projects out ([`project_out`]).
    pub jacobian: Vec<f64>,
    /// The weighted residuals over the fit span at the fitted start.
    pub residuals: Vec<f64>,
    /// Number of start parameters (columns).
    pub params: usize,
}

impl StartFit {
    /// A start taken as it is (no fit, no Jacobian).
    pub fn unfitted(state: State) -> Self {
        Self {
            state,
            iterations: 0,
            jacobian: Vec::new(),
            residuals: Vec::new(),
            params: 0,
        }
    }
}

/// Remove from each column of `cols` (column-major, `m` rows) its least-squares fit by the
/// columns of `jac` (column-major, `m` rows; `gram` = JᵀJ, row-major, as
/// [`wireflight_flight::numeric::gram`]): what is left is the part of a residual change that no change
/// of the start state can produce (variable projection).
pub fn project_out(jac: &[f64], gram: &[f64], params: usize, cols: &mut [f64], m: usize) {
    if params == 0 || jac.len() != params * m || gram.len() != params * params || m == 0 {
        return;
    }
    for col in cols.chunks_mut(m) {
        project_column(jac, gram, params, col);
    }
}

/// Replace `col` by col − J·(JᵀJ)⁻¹Jᵀcol and return the coefficients (JᵀJ)⁻¹Jᵀcol (None,
/// leaving `col` as it is, when JᵀJ is singular). `jac` holds `params` columns of
/// `col.len()` rows; `gram` is its JᵀJ.
pub(crate) fn project_column(
    jac: &[f64],
    gram: &[f64],
    params: usize,
    col: &mut [f64],
) -> Option<Vec<f64>> {
    let m = col.len();
    let mut y: Vec<f64> = (0..params)
        .map(|a| dot(&jac[a * m..(a + 1) * m], col))
        .collect();
    let mut g = gram.to_vec();
    solve_in_place(&mut g, &mut y, params)?;
    for (a, ya) in y.iter().enumerate() {
        axpy(-ya, &jac[a * m..(a + 1) * m], col);
    }
    Some(y)
}

/// Reusable buffers of one window's evaluations.
#[derive(Default)]
pub struct Scratch {
    /// Predictions over the window.
    pub predicted: Vec<Predicted>,
    /// The states of that flight, after every integration step.
    pub states: Vec<State>,
    /// Predictions over the fit span from the start a fit ended at (its residuals').
    pub accepted: Vec<Predicted>,
    /// The states of that flight.
    accepted_states: Vec<State>,
}

impl Scratch {
    /// The last flight is the accepted one (its predictions and states are kept).
    fn accept(&mut self) {
        std::mem::swap(&mut self.predicted, &mut self.accepted);
        std::mem::swap(&mut self.states, &mut self.accepted_states);
    }
}

/// Rows of the Jacobian [`broyden_update`] takes at a time (its columns' share stays in the
/// first-level cache through the pass).
const BROYDEN_BLOCK: usize = 256;

/// Broyden's rank-one update of a column-major Jacobian after the step `step` took the
/// residuals from `r_old` to `r_new`: J += u·δᵀ with u = (Δr − Jδ)/(δᵀδ); and of its Gram
/// matrix `jtj` with it: JᵀJ + (Jᵀu)δᵀ + δ(Jᵀu)ᵀ + (uᵀu)δδᵀ (Jᵀu with the old J). Returns
/// the updated Jᵀ·r_new, the next iteration's gradient.
///
/// One pass over the Jacobian in blocks of rows: u, Jᵀu, the update and Jᵀr of a block are
/// all taken while it is in the cache (column by column, a megabyte-sized Jacobian would be
/// read four times).
fn broyden_update(
    jac: &mut [f64],
    jtj: &mut [f64],
    step: &[f64],
    r_old: &[f64],
    r_new: &[f64],
    np: usize,
    m: usize,
) -> Vec<f64> {
    let dd: f64 = step.iter().map(|d| d * d).sum();
    // NaN as well as zero: no step to update with.
    if dd.is_nan()
        || dd <= 0.0
        || jac.len() != np * m
        || jtj.len() != np * np
        || step.len() != np
        || r_old.len() != m
        || r_new.len() != m
    {
        return gradient(jac, r_new, np);
    }
    let mut ju = vec![0.0; np];
    let mut jr = vec![0.0; np];
    let mut uu = 0.0;
    let mut u = [0.0; BROYDEN_BLOCK];
    let mut start = 0;
    while start < m {
        let end = (start + BROYDEN_BLOCK).min(m);
        let u = &mut u[..end - start];
        for ((u, a), b) in u.iter_mut().zip(&r_new[start..end]).zip(&r_old[start..end]) {
            *u = a - b;
        }
        for (k, d) in step.iter().enumerate() {
            axpy(-d, &jac[k * m + start..k * m + end], u);
        }
        u.iter_mut().for_each(|v| *v /= dd);
        uu += dot(u, u);
        for (k, d) in step.iter().enumerate() {
            let col = &mut jac[k * m + start..k * m + end];
            ju[k] += dot(col, u);
            axpy(*d, u, col);
            jr[k] += dot(col, &r_new[start..end]);
        }
        start = end;
    }
    for a in 0..np {
        for b in 0..np {
            jtj[a * np + b] += ju[a] * step[b] + step[a] * ju[b] + uu * step[a] * step[b];
        }
    }
    jr
}

/// Jᵀr for a column-major Jacobian of `np` columns of `r.len()` rows.
fn gradient(jac: &[f64], r: &[f64], np: usize) -> Vec<f64> {
    let m = r.len();
    (0..np)
        .map(|k| jac.get(k * m..(k + 1) * m).map_or(0.0, |col| dot(col, r)))
        .collect()
}

fn sum_sq(r: &[f64]) -> f64 {
    dot(r, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Broyden's update keeps JᵀJ equal to the Gram matrix of the updated Jacobian, makes the
    /// Jacobian reproduce the step's residual change (the secant condition) and returns its
    /// Jᵀr — within one block of rows and across several.
    #[test]
    fn broyden_update_keeps_the_gram_matrix_and_the_secant() {
        for m in [17, 3 * BROYDEN_BLOCK + 9] {
            let np = 3;
            let mut jac: Vec<f64> = (0..np * m)
                .map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.3)
                .collect();
            let mut jtj = gram(&jac, np, m);
            let r_old: Vec<f64> = (0..m).map(|i| (i as f64 * 0.9).sin()).collect();
            let r_new: Vec<f64> = (0..m).map(|i| (i as f64 * 0.4).cos() * 0.5).collect();
            let step = [0.2, -0.7, 0.05];
            let jr = broyden_update(&mut jac, &mut jtj, &step, &r_old, &r_new, np, m);
            let exact = gram(&jac, np, m);
            for (k, g) in jr.iter().enumerate() {
                let plain: f64 = (0..m).map(|i| jac[k * m + i] * r_new[i]).sum();
                assert!(
                    (g - plain).abs() < 1e-10 * plain.abs().max(1.0),
                    "{g} vs {plain}"
                );
            }
            for (a, b) in jtj.iter().zip(&exact) {
                assert!((a - b).abs() < 1e-9 * b.abs().max(1.0), "{m}: {a} vs {b}");
            }
            for i in 0..m {
                let jd: f64 = (0..np).map(|k| jac[k * m + i] * step[k]).sum();
                assert!((jd - (r_new[i] - r_old[i])).abs() < 1e-12, "{m}, row {i}");
            }
        }
    }
}
