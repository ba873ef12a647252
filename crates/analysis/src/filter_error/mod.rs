//! The filter-error method: maximum-likelihood identification through turbulence
//! (Jategaonkar, *Flight Vehicle System Identification*, ch. 5; Maine & Iliff's MMLE3).
//!
//! Output error simulates the model from its start and calls everything it cannot follow a
//! residual; in turbulence the gusts' response is part of the motion, so the residuals are
//! coloured and the parameters that best hide them are biased. The filter-error method runs a
//! Kalman filter inside the fit instead: the model's state is augmented with gust velocities,
//! each a first-order Gauss–Markov process (a Dryden-like spectrum with time constant L/V,
//! zero mean, finite correlation), the filter's innovations are the residuals, and the gust
//! intensity σ is estimated with the parameters.
//!
//! The fit (Maine–Iliff's steady-state variant):
//! - the continuous linear(ised) model and the gust states are discretised exactly (matrix
//!   exponential of the augmented system) at the data's sample interval;
//! - the steady-state gain K and innovation covariance S come from iterating the Riccati
//!   equation to convergence, with process noise on the gust states only and measurement noise
//!   R from the data's noise estimates;
//! - the negative log-likelihood is ½ Σ νᵀS⁻¹ν + ½ N ln det S;
//! - Gauss–Newton on the parameters with K and S held fixed for the iteration, then σ updated
//!   by a bounded one-dimensional search of the full likelihood (gain recomputed), until the
//!   likelihood stops falling.
//!
//! With σ = 0 the gain is zero, the innovations are the simulation's output errors, and the
//! fit is output error's: one code path for both methods.
//!
//! Cost: one Riccati solution per likelihood evaluation ((n+g)³ per iteration, independent of
//! the flight's length), one filter pass per parameter per Gauss–Newton iteration (as output
//! error's sensitivities), and about forty filter passes per intensity update.
//!
//! Turbulence is recognised by a likelihood ratio: twice the fall of the negative
//! log-likelihood from output error's optimum (σ = 0) to the filter's must beat a χ² bound
//! for the one added number. A steady wind or bias is deterministic: with a bias among the
//! model's parameters the zero-mean gust states cannot claim it, and σ stays at zero.

pub mod flight;
mod matrix;

pub use matrix::Mat;

/// A continuous-time linear(ised) model at one parameter vector, deviations from a trim:
/// ẋ = A x + B u + E g,  y = C x + D u + F g + bias,  with g the gust velocities (m/s).
#[derive(Debug, Clone)]
pub struct System {
    /// State matrix, n × n.
    pub a: Mat,
    /// Input matrix, n × m.
    pub b: Mat,
    /// Output matrix, p × n.
    pub c: Mat,
    /// Feed-through, p × m.
    pub d: Mat,
    /// How the gust velocities drive the state, n × g.
    pub gust_state: Mat,
    /// How the gust velocities enter the outputs (air data measure air-relative motion), p × g.
    pub gust_output: Mat,
    /// Constant output offsets, p (a steady wind or sensor bias belongs here, not in σ).
    pub bias: Vec<f64>,
}

/// The gust field's shape: one first-order Gauss–Markov state per gust axis.
#[derive(Debug, Clone)]
pub struct Gusts {
    /// Correlation time L/V of each gust axis, s.
    pub time_constants_s: Vec<f64>,
    /// Each axis' σ relative to the one estimated intensity (Dryden: u, v, w from L's ratio).
    pub shape: Vec<f64>,
}

/// A model whose matrices depend on the parameters being identified.
pub trait LinearModel {
    /// Number of parameters.
    fn parameter_count(&self) -> usize;
    /// The system at parameters `theta`.
    fn system(&self, theta: &[f64]) -> System;
    /// The gust axes.
    fn gusts(&self) -> Gusts;
}

/// A flight's samples at a fixed interval, as deviations from the trim the model is about.
#[derive(Debug, Clone)]
pub struct Record {
    /// Sample interval, s.
    pub dt_s: f64,
    /// Inputs per sample, each of length m.
    pub inputs: Vec<Vec<f64>>,
    /// Measured outputs per sample, each of length p.
    pub outputs: Vec<Vec<f64>>,
    /// Measurement noise σ of each output (from the data's noise estimate).
    pub noise_sigma: Vec<f64>,
}

/// Which residuals the fit minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Simulation residuals (σ held at zero).
    OutputError,
    /// Kalman-filter innovations with the gust intensity estimated.
    FilterError,
}

/// What can stop a fit.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FitError {
    /// The record or model's dimensions disagree.
    #[error("filter-error fit: {what}")]
    Dimensions {
        /// Which dimension is wrong.
        what: String,
    },
    /// The innovation covariance lost positive definiteness (a noise σ of zero or a NaN).
    #[error("filter-error fit: innovation covariance is not positive definite (check the noise σ of every output)")]
    NotPositiveDefinite,
    /// The likelihood became non-finite (an unstable model at the start values).
    #[error("filter-error fit: the likelihood is not finite at the start values")]
    NotFinite,
}

/// A fit's result.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The method used.
    pub method: Method,
    /// Estimated parameters.
    pub theta: Vec<f64>,
    /// Their standard errors (Cramér–Rao, from the Gauss–Newton information).
    pub theta_sigma: Vec<f64>,
    /// Estimated gust intensity, m/s (zero for output error).
    pub gust_sigma_mps: f64,
    /// Its standard error, m/s (from the likelihood's curvature; zero for output error).
    pub gust_sigma_se_mps: f64,
    /// Negative log-likelihood at the estimate.
    pub neg_log_likelihood: f64,
    /// Outer iterations used.
    pub iterations: usize,
    /// Innovations' lag-one autocorrelation, averaged over outputs (whiteness: near zero when
    /// the model and the gust model account for the residuals).
    pub innovation_lag1: f64,
}

/// The turbulence test: output error and filter error on one record, and the verdict.
#[derive(Debug, Clone)]
pub struct TurbulenceTest {
    /// Output error's fit.
    pub output_error: Fit,
    /// The filter's fit.
    pub filter_error: Fit,
    /// 2 (NLL_oe − NLL_fe).
    pub likelihood_ratio: f64,
    /// Whether turbulence is significant.
    pub turbulence: bool,
}

/// χ² with one degree of freedom at 0.1 %: the added intensity must earn its place.
pub const LIKELIHOOD_RATIO_BOUND: f64 = 10.83;

/// Largest gust intensity searched, m/s (severe turbulence is about 7).
const MAX_GUST_SIGMA: f64 = 20.0;
const MIN_GUST_SIGMA: f64 = 1e-4;
const OUTER_ITERATIONS: usize = 40;
const RICCATI_ITERATIONS: usize = 20_000;
const GOLDEN_ITERATIONS: usize = 40;

/// The discretised augmented model at one parameter vector.
struct Discrete {
    phi: Mat,
    gamma: Mat,
    h: Mat,
    d: Mat,
    bias: Vec<f64>,
    gust_q: Vec<f64>,
    states: usize,
    gust_axes: usize,
}

/// The filter's steady state: gain K ((n+g) × p), S⁻¹ and ln det S.
struct Gain {
    k: Mat,
    s_inv: Mat,
    logdet: f64,
}

fn check(model: &dyn LinearModel, record: &Record, theta: &[f64]) -> Result<(), FitError> {
    let dims = |what: String| Err(FitError::Dimensions { what });
    if theta.len() != model.parameter_count() {
        return dims(format!(
            "{} start values for {} parameters",
            theta.len(),
            model.parameter_count()
        ));
    }
    let sys = model.system(theta);
    let gusts = model.gusts();
    let (n, m, p, g) = (
        sys.a.rows,
        sys.b.cols,
        sys.c.rows,
        gusts.time_constants_s.len(),
    );
    let shapes = [
        ("A", sys.a.rows, sys.a.cols, n, n),
        ("B", sys.b.rows, sys.b.cols, n, m),
        ("C", sys.c.rows, sys.c.cols, p, n),
        ("D", sys.d.rows, sys.d.cols, p, m),
        ("E", sys.gust_state.rows, sys.gust_state.cols, n, g),
        ("F", sys.gust_output.rows, sys.gust_output.cols, p, g),
    ];
    for (name, r, c, er, ec) in shapes {
        if (r, c) != (er, ec) {
            return dims(format!("matrix {name} is {r}×{c}, expected {er}×{ec}"));
        }
    }
    if sys.bias.len() != p || record.noise_sigma.len() != p || gusts.shape.len() != g {
        return dims("bias, noise σ and gust shape must match the outputs and gust axes".into());
    }
    if gusts
        .time_constants_s
        .iter()
        .any(|t| t.is_nan() || *t <= 0.0)
    {
        return dims("every gust time constant must be positive".into());
    }
    if record.dt_s.is_nan() || record.dt_s <= 0.0 || record.inputs.len() != record.outputs.len() {
        return dims("the record needs a positive interval and one input per output sample".into());
    }
    for (k, (u, y)) in record.inputs.iter().zip(&record.outputs).enumerate() {
        if u.len() != m || y.len() != p {
            return dims(format!(
                "sample {k}: {} inputs and {} outputs, expected {m} and {p}",
                u.len(),
                y.len()
            ));
        }
    }
    Ok(())
}

fn discretise(model: &dyn LinearModel, theta: &[f64], dt: f64, gust_sigma: f64) -> Discrete {
    let sys = model.system(theta);
    let gusts = model.gusts();
    let (n, m, g) = (sys.a.rows, sys.b.cols, gusts.time_constants_s.len());
    let na = n + g;
    // exp([[Aa, Ba], [0, 0]] dt) holds Φ and the zero-order-hold input matrix Γ.
    let mut big = Mat::zeros(na + m, na + m);
    for i in 0..n {
        for j in 0..n {
            *big.at_mut(i, j) = sys.a.at(i, j) * dt;
        }
        for j in 0..g {
            *big.at_mut(i, n + j) = sys.gust_state.at(i, j) * dt;
        }
        for j in 0..m {
            *big.at_mut(i, na + j) = sys.b.at(i, j) * dt;
        }
    }
    for (j, tau) in gusts.time_constants_s.iter().enumerate() {
        *big.at_mut(n + j, n + j) = -dt / tau;
    }
    let e = big.expm();
    let mut phi = Mat::zeros(na, na);
    let mut gamma = Mat::zeros(na, m);
    for i in 0..na {
        for j in 0..na {
            *phi.at_mut(i, j) = e.at(i, j);
        }
        for j in 0..m {
            *gamma.at_mut(i, j) = e.at(i, na + j);
        }
    }
    let mut h = Mat::zeros(sys.c.rows, na);
    for i in 0..sys.c.rows {
        for j in 0..n {
            *h.at_mut(i, j) = sys.c.at(i, j);
        }
        for j in 0..g {
            *h.at_mut(i, n + j) = sys.gust_output.at(i, j);
        }
    }
    // Exact discrete driving noise of a Gauss–Markov state with stationary σ.
    let gust_q = gusts
        .time_constants_s
        .iter()
        .zip(&gusts.shape)
        .map(|(tau, s)| (gust_sigma * s).powi(2) * (1.0 - (-2.0 * dt / tau).exp()))
        .collect();
    Discrete {
        phi,
        gamma,
        h,
        d: sys.d,
        bias: sys.bias,
        gust_q,
        states: n,
        gust_axes: g,
    }
}

/// The steady-state gain by iterating the Riccati equation from the stationary gust covariance.
fn steady_gain(disc: &Discrete, noise_sigma: &[f64]) -> Result<Gain, FitError> {
    let na = disc.states + disc.gust_axes;
    let p = disc.h.rows;
    let mut r = Mat::zeros(p, p);
    for (i, s) in noise_sigma.iter().enumerate() {
        *r.at_mut(i, i) = s * s;
    }
    let mut q = Mat::zeros(na, na);
    for (j, qj) in disc.gust_q.iter().enumerate() {
        *q.at_mut(disc.states + j, disc.states + j) = *qj;
    }
    if q.max_abs() == 0.0 {
        let (s_inv, logdet) = r
            .spd_inverse_logdet()
            .ok_or(FitError::NotPositiveDefinite)?;
        return Ok(Gain {
            k: Mat::zeros(na, p),
            s_inv,
            logdet,
        });
    }
    let ht = disc.h.t();
    let mut prior = q.clone();
    let mut last = None;
    for _ in 0..RICCATI_ITERATIONS {
        let s = disc.h.mul(&prior).mul(&ht).add_scaled(&r, 1.0);
        let (s_inv, logdet) = s
            .spd_inverse_logdet()
            .ok_or(FitError::NotPositiveDefinite)?;
        let k = prior.mul(&ht).mul(&s_inv);
        let posterior = prior.add_scaled(&k.mul(&disc.h).mul(&prior), -1.0);
        let next = disc
            .phi
            .mul(&posterior)
            .mul(&disc.phi.t())
            .add_scaled(&q, 1.0);
        let change = next.add_scaled(&prior, -1.0).max_abs();
        let scale = prior.max_abs().max(f64::MIN_POSITIVE);
        prior = next;
        last = Some(Gain { k, s_inv, logdet });
        if change <= 1e-12 * scale {
            break;
        }
    }
    last.ok_or(FitError::NotPositiveDefinite)
}

/// The filter's innovations, sample after sample, into `nu` (N·p); no allocation per sample.
fn innovations(disc: &Discrete, gain: &Gain, record: &Record, nu: &mut Vec<f64>) {
    let na = disc.states + disc.gust_axes;
    let p = disc.h.rows;
    nu.clear();
    nu.resize(record.outputs.len() * p, 0.0);
    let mut x = vec![0.0; na];
    let mut x_next = vec![0.0; na];
    let mut hx = vec![0.0; p];
    let mut du = vec![0.0; p];
    let mut bu = vec![0.0; na];
    for (k, (u, y)) in record.inputs.iter().zip(&record.outputs).enumerate() {
        disc.h.mul_vec_into(&x, &mut hx);
        disc.d.mul_vec_into(u, &mut du);
        let v = &mut nu[k * p..(k + 1) * p];
        for i in 0..p {
            v[i] = y[i] - hx[i] - du[i] - disc.bias[i];
        }
        for (i, xi) in x.iter_mut().enumerate() {
            *xi += (0..p).map(|j| gain.k.at(i, j) * v[j]).sum::<f64>();
        }
        disc.phi.mul_vec_into(&x, &mut x_next);
        disc.gamma.mul_vec_into(u, &mut bu);
        for i in 0..na {
            x[i] = x_next[i] + bu[i];
        }
    }
}

fn quadratic(nu: &[f64], s_inv: &Mat) -> f64 {
    let p = s_inv.rows;
    nu.chunks_exact(p)
        .map(|v| {
            (0..p)
                .map(|i| v[i] * (0..p).map(|j| s_inv.at(i, j) * v[j]).sum::<f64>())
                .sum::<f64>()
        })
        .sum()
}

/// Negative log-likelihood with the gain recomputed for (θ, σ).
fn neg_log_likelihood(
    model: &dyn LinearModel,
    record: &Record,
    theta: &[f64],
    gust_sigma: f64,
    nu: &mut Vec<f64>,
) -> Result<f64, FitError> {
    let disc = discretise(model, theta, record.dt_s, gust_sigma);
    let gain = steady_gain(&disc, &record.noise_sigma)?;
    innovations(&disc, &gain, record, nu);
    Ok(0.5 * quadratic(nu, &gain.s_inv) + 0.5 * record.outputs.len() as f64 * gain.logdet)
}

/// One Gauss–Newton step on θ with the gain held at (θ, σ); returns the new θ and the
/// information matrix JᵀS⁻¹J.
fn gauss_newton_step(
    model: &dyn LinearModel,
    record: &Record,
    theta: &[f64],
    gust_sigma: f64,
) -> Result<(Vec<f64>, Mat), FitError> {
    let disc = discretise(model, theta, record.dt_s, gust_sigma);
    let gain = steady_gain(&disc, &record.noise_sigma)?;
    let np = theta.len();
    let p = disc.h.rows;
    let mut nu = Vec::new();
    innovations(&disc, &gain, record, &mut nu);
    let mut jac = vec![Vec::new(); np];
    let (mut plus, mut minus) = (Vec::new(), Vec::new());
    for (i, col) in jac.iter_mut().enumerate() {
        let step = 1e-6 * theta[i].abs().max(1e-2);
        let mut t = theta.to_vec();
        t[i] += step;
        innovations(
            &discretise(model, &t, record.dt_s, gust_sigma),
            &gain,
            record,
            &mut plus,
        );
        t[i] -= 2.0 * step;
        innovations(
            &discretise(model, &t, record.dt_s, gust_sigma),
            &gain,
            record,
            &mut minus,
        );
        // ∂ν/∂θ (the innovations fall as the model's prediction rises).
        *col = plus
            .iter()
            .zip(&minus)
            .map(|(a, b)| (a - b) / (2.0 * step))
            .collect();
    }
    let mut info = Mat::zeros(np, np);
    let mut grad = vec![0.0; np];
    let weighted = |a: &[f64], b: &[f64]| -> f64 {
        a.chunks_exact(p)
            .zip(b.chunks_exact(p))
            .map(|(x, y)| {
                (0..p)
                    .map(|r| x[r] * (0..p).map(|c| gain.s_inv.at(r, c) * y[c]).sum::<f64>())
                    .sum::<f64>()
            })
            .sum()
    };
    for i in 0..np {
        grad[i] = weighted(&jac[i], &nu);
        for j in 0..=i {
            let v = weighted(&jac[i], &jac[j]);
            *info.at_mut(i, j) = v;
            *info.at_mut(j, i) = v;
        }
    }
    // Levenberg's small ridge keeps a badly determined direction from running away.
    let mut damped = info.clone();
    for i in 0..np {
        *damped.at_mut(i, i) *= 1.0 + 1e-9;
    }
    let (inv, _) = damped
        .spd_inverse_logdet()
        .ok_or(FitError::NotPositiveDefinite)?;
    let mut delta = vec![0.0; np];
    inv.mul_vec_into(&grad, &mut delta);
    let next = theta.iter().zip(&delta).map(|(t, d)| t - d).collect();
    Ok((next, info))
}

/// The likelihood's best gust intensity at θ by golden-section search of ln σ, compared with
/// σ = 0 (the boundary, where output error lives).
fn best_gust_sigma(
    model: &dyn LinearModel,
    record: &Record,
    theta: &[f64],
    nu: &mut Vec<f64>,
) -> Result<(f64, f64), FitError> {
    let (s, fs) = golden_ln(
        (MIN_GUST_SIGMA, MAX_GUST_SIGMA),
        GOLDEN_ITERATIONS,
        |s: f64| neg_log_likelihood(model, record, theta, s.exp(), nu),
    )?;
    let f0 = neg_log_likelihood(model, record, theta, 0.0, nu)?;
    Ok(if f0 <= fs { (0.0, f0) } else { (s, fs) })
}

/// The minimiser over `range` (positive; searched in ln) of `f(ln v)` by `steps` steps of
/// golden section, and `f` there; the first error `f` returns stops it.
pub(crate) fn golden_ln<E>(
    range: (f64, f64),
    steps: usize,
    mut f: impl FnMut(f64) -> Result<f64, E>,
) -> Result<(f64, f64), E> {
    let (mut a, mut b) = (range.0.ln(), range.1.ln());
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - ratio * (b - a);
    let mut d = a + ratio * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    for _ in 0..steps {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - ratio * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + ratio * (b - a);
            fd = f(d)?;
        }
    }
    Ok(if fc < fd {
        (c.exp(), fc)
    } else {
        (d.exp(), fd)
    })
}

fn lag1(nu: &[f64], p: usize) -> f64 {
    if p == 0 || nu.len() < 2 * p {
        return 0.0;
    }
    let mut total = 0.0;
    for i in 0..p {
        let col: Vec<f64> = nu.iter().skip(i).step_by(p).copied().collect();
        let mean = col.iter().sum::<f64>() / col.len() as f64;
        let var: f64 = col.iter().map(|v| (v - mean).powi(2)).sum();
        let cov: f64 = col.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum();
        total += if var > 0.0 { cov / var } else { 0.0 };
    }
    total / p as f64
}

/// Fits `model` to `record` from `theta0` by `method`.
pub fn fit(
    model: &dyn LinearModel,
    record: &Record,
    theta0: &[f64],
    method: Method,
) -> Result<Fit, FitError> {
    check(model, record, theta0)?;
    let mut nu = Vec::new();
    let mut theta = theta0.to_vec();
    let mut sigma = 0.0;
    let mut cost = neg_log_likelihood(model, record, &theta, sigma, &mut nu)?;
    if !cost.is_finite() {
        return Err(FitError::NotFinite);
    }
    if method == Method::FilterError {
        (sigma, cost) = best_gust_sigma(model, record, &theta, &mut nu)?;
    }
    let mut info = Mat::zeros(theta.len(), theta.len());
    let mut iterations = 0;
    for it in 0..OUTER_ITERATIONS {
        iterations = it + 1;
        let (mut next, next_info) = gauss_newton_step(model, record, &theta, sigma)?;
        info = next_info;
        // Halve the step until the likelihood (gain recomputed) does not rise.
        let mut next_cost = f64::INFINITY;
        for _ in 0..20 {
            next_cost =
                neg_log_likelihood(model, record, &next, sigma, &mut nu).unwrap_or(f64::INFINITY);
            if next_cost.is_finite() && next_cost <= cost {
                break;
            }
            next = theta
                .iter()
                .zip(&next)
                .map(|(t, n)| 0.5 * (t + n))
                .collect();
        }
        if next_cost.is_nan() || next_cost > cost {
            break;
        }
        theta = next;
        let mut new_cost = next_cost;
        if method == Method::FilterError {
            (sigma, new_cost) = best_gust_sigma(model, record, &theta, &mut nu)?;
        }
        let fall = cost - new_cost;
        cost = new_cost;
        if fall <= 1e-8 * (1.0 + cost.abs()) {
            break;
        }
    }
    let theta_sigma = match info.spd_inverse_logdet() {
        Some((cov, _)) => (0..theta.len())
            .map(|i| cov.at(i, i).max(0.0).sqrt())
            .collect(),
        None => vec![f64::INFINITY; theta.len()],
    };
    let gust_sigma_se_mps = if sigma > 0.0 {
        let h = 0.02 * sigma;
        let fp = neg_log_likelihood(model, record, &theta, sigma + h, &mut nu)?;
        let fm = neg_log_likelihood(model, record, &theta, sigma - h, &mut nu)?;
        let curvature = (fp - 2.0 * cost + fm) / (h * h);
        if curvature > 0.0 {
            1.0 / curvature.sqrt()
        } else {
            f64::INFINITY
        }
    } else {
        0.0
    };
    let neg_log_likelihood = neg_log_likelihood(model, record, &theta, sigma, &mut nu)?;
    Ok(Fit {
        method,
        theta,
        theta_sigma,
        gust_sigma_mps: sigma,
        gust_sigma_se_mps,
        neg_log_likelihood,
        iterations,
        innovation_lag1: lag1(&nu, record.noise_sigma.len()),
    })
}

/// Output error and filter error on one record, and whether the gust intensity is
/// significant by the likelihood ratio.
pub fn turbulence_test(
    model: &dyn LinearModel,
    record: &Record,
    theta0: &[f64],
) -> Result<TurbulenceTest, FitError> {
    let output_error = fit(model, record, theta0, Method::OutputError)?;
    let filter_error = fit(model, record, &output_error.theta, Method::FilterError)?;
    let likelihood_ratio =
        2.0 * (output_error.neg_log_likelihood - filter_error.neg_log_likelihood);
    let turbulence = likelihood_ratio > LIKELIHOOD_RATIO_BOUND
        && filter_error.gust_sigma_mps > 2.0 * filter_error.gust_sigma_se_mps;
    Ok(TurbulenceTest {
        output_error,
        filter_error,
        likelihood_ratio,
        turbulence,
    })
}

#[cfg(test)]
mod tests;
