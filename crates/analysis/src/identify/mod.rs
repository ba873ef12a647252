//! Identification: many numbers of an aircraft's parameter set fitted together over several
//! flights.
//!
//! * **Output error**, as in the diagnosis (`diagnose::fit`): each flight is cut into
//!   multiple-shooting windows, each window's start state is profiled out, and the parameters
//!   minimise the noise-weighted misfit summed over every window of every flight
//!   (Levenberg–Marquardt on the linearised profile, the starts re-fitted exactly until the
//!   misfit settles).
//! * **A prior toward the starting set**: each number carries a Gaussian prior centred on its
//!   value in the set, σ = `prior` × |value| (at least [`PRIOR_FLOOR`]). A number the data do
//!   not determine stays where it was instead of wandering along a valley of the misfit, and
//!   its posterior σ stays near the prior's: such numbers are reported as *not identified*.
//!   The prior adds s²·Σ((θ − θ₀)/σ₀)² to the misfit, s² the residuals' variance in noise
//!   units (`residual_scale`): 1 when the model fits to the noise, where it moves nothing
//!   the data determine; large when the model's structure is wrong, where a number must not
//!   run off to absorb what no number of the model can.
//! * **Equation error** as a fast starting point: the measured body accelerations and angular
//!   accelerations (smoothing differentiator) regressed on the model's at the measured states,
//!   by Gauss–Newton. It is biased by noise in the regressors, by actuator lag and by wind, so
//!   it is used only when it starts the output-error fit lower than the set does.
//!
//! The covariance is the inverse of the posterior's information, the data's part inflated for
//! correlated residuals as in the diagnosis; |correlation| above [`CONFOUNDED`] names pairs the
//! data cannot separate.
//!
//! [`run`] is the whole of `wireflight identify`'s decision: the fit, the refit through
//! turbulence where it is chosen ([`turbulence`]) and the checks on held-out flights, returned
//! as one finished [`Identified`].

pub(crate) mod equation_error;
mod request;
pub mod turbulence;

pub use request::{run, HeldOut, Identified, Request, RunError};

use equation_error::equation_error;

use crate::compare::{compare_refit, compare_with_fits, CompareConfig, Comparison, Prepared};
use crate::free::{aircraft_free, set_values, values, Free, KeyError};
use crate::lm::{Lm, FIT_TOL};
use crate::profile::{add_into, linear_profile, normal_equations, Linearised, Normal};
use wireflight_data::FlightData;
use wireflight_flight::model::{Model, State};
use wireflight_flight::numeric::invert;
use wireflight_flight::params::keys::{self, AircraftKey};

/// Why an identification could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// An aircraft number that cannot be fitted (a point mass has none).
    #[error(transparent)]
    Key(#[from] KeyError),
    /// No number was asked for.
    #[error("no aircraft parameter to identify")]
    NothingToFit,
    /// A flight is too short for one comparison window.
    #[error("flight {flight} ({duration_s:.2} s) is too short for one {window_s:.1} s window")]
    TooShort {
        /// The flight, counted from 1.
        flight: usize,
        /// Its duration, s.
        duration_s: f64,
        /// The comparison window, s.
        window_s: f64,
    },
    /// The starting model's comparison is not finite.
    #[error("the starting model's comparison is not finite")]
    StartNotFinite,
    /// The identified model's comparison is not finite.
    #[error("the identified model's comparison is not finite")]
    ResultNotFinite,
}

/// Settings of an identification.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdentifyConfig {
    /// Comparison windows (as `compare`).
    pub compare: CompareConfig,
    /// Relative σ of the prior toward the starting set (0.3: a number is expected within
    /// about ±30% of its value in the set).
    pub prior: f64,
    /// Levenberg–Marquardt iterations per linearisation.
    pub iterations: usize,
    /// Try an equation-error regression as the starting point.
    pub equation_error: bool,
}

impl Default for IdentifyConfig {
    fn default() -> Self {
        Self {
            compare: CompareConfig::default(),
            prior: 0.3,
            iterations: 20,
            equation_error: true,
        }
    }
}

/// At most this many rounds of exact start fits and re-linearisation.
const OUTER: usize = 10;

/// Smallest prior σ of a number that is zero (or nearly) in the set.
pub const PRIOR_FLOOR: f64 = 0.01;

/// A number is *identified* when the data shrink its σ below this fraction of the prior's.
pub const IDENTIFIED: f64 = 0.2;

/// Pairs of fitted numbers correlated beyond this are reported as not separable.
pub const CONFOUNDED: f64 = 0.9;

/// One fitted number.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The key.
    pub key: &'static AircraftKey,
    /// Its value in the starting set.
    pub start: f64,
    /// The equation-error estimate, when that start was tried.
    pub equation_error: Option<f64>,
    /// The estimate.
    pub value: f64,
    /// Its standard deviation (posterior).
    pub sigma: f64,
    /// The prior's standard deviation.
    pub prior_sigma: f64,
}

impl Estimate {
    /// The data determine it (σ below [`IDENTIFIED`] × the prior's).
    pub fn identified(&self) -> bool {
        self.sigma.is_finite() && self.sigma < IDENTIFIED * self.prior_sigma
    }

    /// Change from the starting set, in % (None for a number that is 0 in the set).
    pub fn change_percent(&self) -> Option<f64> {
        (self.start != 0.0).then(|| 100.0 * (self.value / self.start - 1.0))
    }
}

/// The outcome of an identification.
#[derive(Clone, Debug)]
pub struct Identification {
    /// The fitted numbers, in the order asked.
    pub estimates: Vec<Estimate>,
    /// Their correlation matrix (row-major); empty when the information matrix is singular.
    pub correlation: Vec<f64>,
    /// Each flight compared with the starting model.
    pub before: Vec<Comparison>,
    /// Each flight compared with the identified model.
    pub after: Vec<Comparison>,
    /// Whether the equation-error estimate was the output-error fit's start.
    pub started_from_equation_error: bool,
    /// The identified model.
    pub model: Model,
    /// Numbers asked for but held at the starting set's value, and why (the stall blend on
    /// flights that never approach the stall).
    pub held: Vec<(&'static str, String)>,
}

/// What a pair of numbers the flights cannot separate does determine: the combination
/// `first + coefficient × second` of least variance (the posterior's direction the data pin
/// down), with its value and σ.
#[derive(Clone, Debug, PartialEq)]
pub struct Combination {
    /// The first number's index in the estimates.
    pub first: usize,
    /// The second's.
    pub second: usize,
    /// The second's coefficient.
    pub coefficient: f64,
    /// The combination's identified value.
    pub value: f64,
    /// Its standard deviation.
    pub sigma: f64,
}

impl Identification {
    /// For every pair the flights cannot separate ([`Self::confounded`]), the combination
    /// they do determine.
    pub fn determined_combinations(&self) -> Vec<Combination> {
        self.confounded()
            .into_iter()
            .filter_map(|(i, k, rho)| {
                let (a, b) = (&self.estimates[i], &self.estimates[k]);
                let (si, sk) = (a.sigma, b.sigma);
                if !(si > 0.0 && sk > 0.0 && si.is_finite() && sk.is_finite()) {
                    return None;
                }
                // Least-variance direction of the 2×2 covariance [[si², c], [c, sk²]].
                let c = rho * si * sk;
                let (p, q) = (si * si, sk * sk);
                let mean = 0.5 * (p + q);
                let lambda = mean - (0.25 * (p - q) * (p - q) + c * c).sqrt();
                // Eigenvector (c, λ − p) or (λ − q, c); the better conditioned one.
                let (x, y) = if (lambda - p).abs() > (lambda - q).abs() {
                    (c, lambda - p)
                } else {
                    (lambda - q, c)
                };
                if x.abs() < 1e-300 {
                    return None;
                }
                let coefficient = y / x;
                let sigma = (lambda.max(0.0)).sqrt() * (1.0 + coefficient * coefficient).sqrt();
                Some(Combination {
                    first: i,
                    second: k,
                    coefficient,
                    value: a.value + coefficient * b.value,
                    sigma,
                })
            })
            .collect()
    }

    /// Pairs (i, k, correlation) with |correlation| > [`CONFOUNDED`].
    pub fn confounded(&self) -> Vec<(usize, usize, f64)> {
        let n = self.estimates.len();
        let mut out = Vec::new();
        if self.correlation.len() != n * n {
            return out;
        }
        for i in 0..n {
            for k in i + 1..n {
                let c = self.correlation[i * n + k];
                if c.abs() > CONFOUNDED {
                    out.push((i, k, c));
                }
            }
        }
        out
    }
}

/// The keys named by `patterns` (names or `prefix*`), in key order without repeats; the
/// aerodynamic coefficients (the `longitudinal` and `lateral` tables) when none are given.
///
/// # Errors
/// A pattern matching no key.
pub fn free_keys(patterns: &[String]) -> Result<Vec<&'static AircraftKey>, KeyError> {
    if patterns.is_empty() {
        return Ok(keys::KEYS
            .iter()
            .filter(|k| k.table == "longitudinal" || k.table == "lateral")
            .collect());
    }
    let mut chosen: Vec<&'static AircraftKey> = Vec::new();
    for p in patterns {
        let found = keys::matching(p);
        if found.is_empty() {
            return Err(KeyError::NoMatch(p.clone()));
        }
        for k in found {
            if !chosen.iter().any(|c| c.name == k.name) {
                chosen.push(k);
            }
        }
    }
    chosen.sort_by_key(|k| keys::KEYS.iter().position(|x| x.name == k.name));
    Ok(chosen)
}

/// A flight being fitted: its windows and each window's linearised start.
struct Flight<'a> {
    prep: Prepared<'a>,
    lin: Vec<Linearised<'static>>,
}

/// The Gaussian prior in the free parameters' scaled units.
struct Prior {
    centre: Vec<f64>,
    /// Weight of (θ − θ₀)/scale squared: (scale/σ₀)².
    weight: Vec<f64>,
    sigma: Vec<f64>,
}

impl Prior {
    fn new(start: &[f64], free: &[Free], relative: f64) -> Self {
        let sigma: Vec<f64> = start
            .iter()
            .map(|v| (relative * v.abs()).max(PRIOR_FLOOR))
            .collect();
        let weight = free
            .iter()
            .zip(&sigma)
            .map(|(f, s)| (f.scale / s).powi(2))
            .collect();
        Self {
            centre: start.to_vec(),
            weight,
            sigma,
        }
    }

    /// Σ((θ − θ₀)/σ₀)².
    fn penalty(&self, theta: &[f64]) -> f64 {
        theta
            .iter()
            .zip(&self.centre)
            .zip(&self.sigma)
            .map(|((t, c), s)| ((t - c) / s).powi(2))
            .sum()
    }
}

/// Identify the numbers `keys` of `base`'s parameter set from `flights` (module docs).
///
/// # Errors
/// A point mass, a flight too short for one window, or a non-finite comparison.
pub fn identify(
    base: &Model,
    flights: &[FlightData],
    keys: &[&'static AircraftKey],
    cfg: &IdentifyConfig,
) -> Result<Identification, IdentifyError> {
    let held = stall_held(base, flights, keys);
    let keys: Vec<&'static AircraftKey> = keys
        .iter()
        .copied()
        .filter(|k| !held.iter().any(|(h, _)| *h == k.name))
        .collect();
    let names: Vec<&'static str> = keys.iter().map(|k| k.name).collect();
    let free = aircraft_free(base, &names)?;
    if free.is_empty() {
        return Err(IdentifyError::NothingToFit);
    }
    let preps: Vec<Prepared> = flights
        .iter()
        .map(|d| Prepared::new(d, cfg.compare))
        .collect();
    for (i, p) in preps.iter().enumerate() {
        if p.windows.is_empty() {
            return Err(IdentifyError::TooShort {
                flight: i + 1,
                duration_s: flights[i].duration(),
                window_s: cfg.compare.window_s,
            });
        }
    }
    let start = values(base, &free);
    let prior = Prior::new(&start, &free, cfg.prior);
    let base_fits: Vec<(Comparison, Vec<Linearised>)> = preps
        .iter()
        .map(|p| {
            let (cmp, fits) = compare_with_fits(base, p, None);
            let lin = fits
                .into_iter()
                .map(|f| Linearised::owned(base, f))
                .collect();
            (cmp, lin)
        })
        .collect();
    let before: Vec<Comparison> = base_fits.iter().map(|(c, _)| c.clone()).collect();
    if before.iter().any(|c| !c.chi2.is_finite()) {
        return Err(IdentifyError::StartNotFinite);
    }
    let chi2_base: f64 = before.iter().map(|c| c.chi2).sum();
    let mut s2 = residual_scale(&before);

    // The equation-error estimate, taken as the start when it fits better.
    let ee = cfg
        .equation_error
        .then(|| equation_error(base, flights, &free, &prior))
        .flatten();
    let mut model = base.clone();
    let mut lins: Vec<Vec<Linearised>> = base_fits.into_iter().map(|(_, lin)| lin).collect();
    let mut from_ee = false;
    if let Some(ee_theta) = &ee {
        let mut m = base.clone();
        set_values(&mut m, &free, ee_theta);
        let fits: Vec<(Comparison, Vec<Linearised>)> = preps
            .iter()
            .map(|p| {
                let (cmp, fits) = compare_with_fits(&m, p, None);
                let lin = fits.into_iter().map(|f| Linearised::owned(&m, f)).collect();
                (cmp, lin)
            })
            .collect();
        let chi2_ee: f64 = fits.iter().map(|(c, _)| c.chi2).sum();
        if chi2_ee.is_finite() && chi2_ee + s2 * prior.penalty(ee_theta) < chi2_base {
            from_ee = true;
            model = m;
            lins = fits.into_iter().map(|(_, lin)| lin).collect();
        }
    }
    let mut theta = values(&model, &free);
    let mut fl: Vec<Flight> = preps
        .into_iter()
        .zip(lins)
        .map(|(prep, lin)| Flight { prep, lin })
        .collect();

    // Output error: LM on the linearised profile, then exact start fits, until they agree and
    // the residual scale (the prior's weight) has settled.
    let mut linear = fit_linearised(
        &mut model,
        &free,
        &mut theta,
        &prior,
        s2,
        &mut fl,
        cfg.iterations,
    );
    let mut after = Vec::new();
    for _ in 0..OUTER {
        let mut exact = 0.0;
        after.clear();
        for f in fl.iter_mut() {
            let starts: Vec<State> = f.lin.iter().map(|l| l.state(&model)).collect();
            let jacobians: Vec<&[f64]> = f.lin.iter().map(|l| &*l.jac).collect();
            let (cmp, fits) = compare_refit(&model, &f.prep, &starts, &jacobians);
            exact += cmp.chi2;
            f.lin = fits
                .into_iter()
                .map(|s| Linearised::owned(&model, s))
                .collect();
            after.push(cmp);
        }
        let s2_now = residual_scale(&after);
        let settled =
            (exact - linear).abs() < FIT_TOL.max(1e-4 * exact) && (s2_now / s2 - 1.0).abs() < 0.05;
        s2 = s2_now;
        if settled || !exact.is_finite() {
            break;
        }
        linear = fit_linearised(
            &mut model,
            &free,
            &mut theta,
            &prior,
            s2,
            &mut fl,
            cfg.iterations,
        );
    }
    if after.iter().any(|c| !c.chi2.is_finite()) {
        return Err(IdentifyError::ResultNotFinite);
    }

    let (cov, correlation) = posterior(&model, &free, &theta, &prior, &fl, &after);
    let estimates = keys
        .iter()
        .enumerate()
        .map(|(i, k)| Estimate {
            key: k,
            start: start[i],
            equation_error: ee.as_ref().map(|e| e[i]),
            value: theta[i],
            sigma: cov
                .as_ref()
                .map_or(f64::NAN, |c| c[i * free.len() + i].max(0.0).sqrt()),
            prior_sigma: prior.sigma[i],
        })
        .collect();
    Ok(Identification {
        estimates,
        correlation,
        before,
        after,
        started_from_equation_error: from_ee,
        model,
        held,
    })
}

/// The largest angle of attack the flights reach (their 99.5th percentile, rad): from the
/// measured NED velocity and attitude (still air), where a flight has both.
pub fn flown_alpha<'a>(flights: impl IntoIterator<Item = &'a FlightData>) -> Option<f64> {
    let mut alpha: Vec<f64> = flights
        .into_iter()
        .filter_map(|d| Some((d.vel_ned.as_ref()?, d.attitude.as_ref()?)))
        .flat_map(|(v, a)| {
            v.iter().zip(a).map(|(v, a)| {
                let b = a.to_matrix().transpose() * *v;
                b.z.atan2(b.x)
            })
        })
        .filter(|a| a.is_finite())
        .collect();
    if alpha.is_empty() {
        return None;
    }
    alpha.sort_by(f64::total_cmp);
    Some(alpha[((alpha.len() - 1) as f64 * 0.995).round() as usize])
}

/// Where the flights never come near the stall of `base`'s set: (the largest α flown, where
/// the blend begins), rad. None where they do, or where it cannot be told.
pub(crate) fn stall_out_of_reach<'a>(
    base: &Model,
    flights: impl IntoIterator<Item = &'a FlightData>,
) -> Option<(f64, f64)> {
    let (alpha0, m) = (base.aircraft("alpha0")?, base.aircraft("m_blend")?);
    let begins = alpha0 - 3.0 / m.max(1e-9);
    let flown = flown_alpha(flights)?;
    (flown < begins).then_some((flown, begins))
}

/// The stall blend's numbers (`alpha0`, `m_blend`) among `keys`, held when the flights never
/// come near the stall: their largest α stays below where the starting set's blend begins
/// (α₀ − 3/M, the blend 5% on). There the data cannot say where a stall is, and a fit moves
/// the blend into the flown range to absorb what the linear terms miss.
fn stall_held(
    base: &Model,
    flights: &[FlightData],
    keys: &[&'static AircraftKey],
) -> Vec<(&'static str, String)> {
    let Some((flown, begins)) = stall_out_of_reach(base, flights) else {
        return Vec::new();
    };
    keys.iter()
        .filter(|k| k.name == "alpha0" || k.name == "m_blend")
        .map(|k| {
            (
                k.name,
                format!(
                    "held: the flights reach α {:.1}°, the stall blend begins near {:.1}°",
                    flown.to_degrees(),
                    begins.to_degrees()
                ),
            )
        })
        .collect()
}

/// The variance of the weighted residuals, in noise units squared: χ²/ν (at least 1),
/// inflated for their lag-1 autocorrelation ρ by (1 + ρ)/(1 − ρ). It is 1 when the misfit is
/// white measurement noise, and much more when the model's structure is wrong — then the
/// prior must weigh as much against the misfit, or a flight's thousands of correlated
/// residuals would drag every number anywhere.
fn residual_scale(comparisons: &[Comparison]) -> f64 {
    let chi2: f64 = comparisons.iter().map(|c| c.chi2).sum();
    let dof: f64 = comparisons.iter().map(|c| c.dof).sum();
    let lag: f64 = comparisons
        .iter()
        .map(|c| c.windows.iter().map(|w| w.lag1_product).sum::<f64>())
        .sum();
    let rho = if chi2 > 0.0 {
        (lag / chi2).clamp(0.0, 0.99)
    } else {
        0.0
    };
    (chi2 / dof.max(1.0)).max(1.0) * (1.0 + rho) / (1.0 - rho)
}

/// Sum of every flight's normal equations, and of their linearised misfits.
fn normal_sum(model: &Model, free: &[Free], theta: &[f64], flights: &[Flight]) -> Normal {
    let np = free.len();
    let mut sum = (vec![0.0; np * np], vec![0.0; np]);
    for f in flights {
        let part = normal_equations(model, (free, false), theta, &f.prep, &f.lin, None);
        add_into(&mut sum, &part);
    }
    sum
}

/// The linearised misfit of every flight at `model`, and each window's start change.
fn profile_sum(model: &Model, flights: &[Flight]) -> (f64, Vec<Vec<Vec<f64>>>) {
    let mut chi2 = 0.0;
    let mut dq = Vec::with_capacity(flights.len());
    for f in flights {
        let (c, d, _) = linear_profile(model, &f.prep, &f.lin);
        chi2 += c;
        dq.push(d);
    }
    (chi2, dq)
}

/// Levenberg–Marquardt on the parameters over the flights' linearised profiles plus the
/// prior weighted by the residual scale `s2` ([`residual_scale`]); updates `model`, `theta`
/// and the windows' starts. Returns the data misfit reached.
fn fit_linearised(
    model: &mut Model,
    free: &[Free],
    theta: &mut Vec<f64>,
    prior: &Prior,
    s2: f64,
    flights: &mut [Flight],
    iterations: usize,
) -> f64 {
    let np = free.len();
    let (mut chi2, _) = profile_sum(model, flights);
    let mut objective = chi2 + s2 * prior.penalty(theta);
    let mut lm = Lm::new(10, 1e-7);
    for _ in 0..iterations {
        let (mut a0, mut g) = normal_sum(model, free, theta, flights);
        // The prior's share, in scaled units: s²·weight·(θ − θ₀)/scale.
        for k in 0..np {
            a0[k * np + k] += s2 * prior.weight[k];
            g[k] += s2 * prior.weight[k] * (theta[k] - prior.centre[k]) / free[k].scale;
        }
        let at: &[Flight] = flights;
        let Some(step) = lm.step(model, free, theta, (&a0, &g), objective, |m, trial| {
            let (c, dq) = profile_sum(m, at);
            (c + s2 * prior.penalty(trial), (c, dq))
        }) else {
            break;
        };
        let (c, dq) = step.extra;
        // The values as set in the model.
        *theta = values(&step.model, free);
        *model = step.model;
        chi2 = c;
        objective = step.objective;
        for (f, d) in flights.iter_mut().zip(&dq) {
            for (l, dw) in f.lin.iter_mut().zip(d) {
                l.q.iter_mut().zip(dw).for_each(|(q, v)| *q += v);
            }
        }
        if step.converged {
            break;
        }
    }
    chi2
}

/// The posterior covariance (own units, row-major) and correlation of the parameters: the
/// data's information (inflated for correlated residuals, as in the diagnosis) plus the
/// prior's.
fn posterior(
    model: &Model,
    free: &[Free],
    theta: &[f64],
    prior: &Prior,
    flights: &[Flight],
    after: &[Comparison],
) -> (Option<Vec<f64>>, Vec<f64>) {
    let np = free.len();
    let (a, _) = normal_sum(model, free, theta, flights);
    let s2 = residual_scale(after);
    let mut info: Vec<f64> = a.iter().map(|v| v / s2).collect();
    for k in 0..np {
        info[k * np + k] += prior.weight[k];
    }
    let Some(inv) = invert(&info, np) else {
        return (None, Vec::new());
    };
    let mut cov = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            cov[i * np + k] = inv[i * np + k] * free[i].scale * free[k].scale;
        }
    }
    if !cov.iter().all(|v| v.is_finite()) {
        return (None, Vec::new());
    }
    let mut corr = vec![0.0; np * np];
    for i in 0..np {
        for k in 0..np {
            let d = (cov[i * np + i] * cov[k * np + k]).sqrt();
            corr[i * np + k] = if d > 0.0 { cov[i * np + k] / d } else { 0.0 };
        }
    }
    (Some(cov), corr)
}
