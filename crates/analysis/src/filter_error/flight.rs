//! The filter-error method on the flight model itself: the nonlinear six-degree-of-freedom
//! model, not a linear one, predicts between samples, and a Kalman filter corrects it at
//! every sample (Jategaonkar, *Flight Vehicle System Identification*, §5.9, the filter-error
//! method for nonlinear systems).
//!
//! **States.** The model's state plus the states of three Dryden shaping filters whose
//! outputs are the gust velocities g (north, east, down, m/s): the first-order form
//! (1 + sT)⁻¹ for u and the second-order (1 + √3·sT)/(1 + sT)² for v and w (MIL-F-8785C's
//! spectra, the forms `simulate` flies; JSBSim's `milspec` turbulence flies v and w through
//! first-order approximations, (1 + sT/2)⁻¹, whose spectra agree with these at low frequency
//! and within 4/3 at high), T = L/V with V the flight's mean airspeed
//! (the frozen field of Taylor's hypothesis), each scaled to its stationary deviation σ; and
//! three rotary disturbances, first-order angular accelerations about the body axes with
//! Dryden's rotary time constant 4b/(πV) (rotary gusts act through the rate damping; JSBSim
//! flies them). The model flies in the air the gusts move ([`Model::set_air_offset`]): every
//! force and moment, the airspeed and the accelerometer see them; the rotary disturbance is
//! added to the rates over each step. The filter's error state is the model's (module
//! [`wireflight_flight::linear`]: δp, δv body, δθ, δω) and the eight disturbance states: 20
//! numbers.
//!
//! **Prediction** from sample to sample: the state by the model's own RK4 under the held
//! commands with the gusts held over the step, the gust filters by their exact transition;
//! the covariance P by Φ·P·Φᵀ + Q, Φ the 4th-order Taylor polynomial of exp(Δt·A), A the
//! tangent-linear model's Jacobian with the gust columns (the forces' change per m/s of
//! gust, by forward differences, through the filters' outputs), taken again every
//! `RELINEARISE_S`; Q the gust filters' exact discrete driving noise P∞ − Φ_g·P∞·Φ_gᵀ.
//!
//! **Correction** at every sample: the innovation ν = y − h(x, g) over the measured channels
//! (position, NED velocity, attitude as the rotation from the predicted to the measured
//! attitude in body axes, body rates, airspeed, accelerometer), S = H·P·Hᵀ + R with R the
//! measurement noise measured from the data ([`crate::compare::estimate_noise`], with the
//! model's own error where reference flights measured it), the gain K = P·Hᵀ·S⁻¹, the state
//! moved by K·ν and P by P − K·S·Kᵀ. H is exact for every channel but the accelerometer
//! (forward differences, like the forces).
//!
//! **Windows.** The flight is cut into compare's windows; in each the filter starts from the
//! measured state at its first sample with the measurement noise as its uncertainty and the
//! gusts at their stationary spread. With σ = 0 nothing drives the states: the filter then
//! only estimates each window's start and the innovations are output error's residuals,
//! so the two methods are one code path and their likelihoods compare.
//!
//! **Likelihood.** −ln L = ½ Σ_k (νₖᵀSₖ⁻¹νₖ + ln det Sₖ) over every sample after a window's
//! first. The six intensities maximise it ([`FlightFilter::estimate_gusts`]), each by a
//! golden-section search of ln σ, in turn; their ± from its curvature. The scale
//! lengths, horizontal (u, v) and vertical (w), are searched between two rounds of the
//! intensities and reported only where the data determine them: their ± — the larger of the
//! likelihood's curvature and the scatter of a time scale T measured on a record of length D,
//! T·√(2T/D) — under half the value (a record of some eight time scales or more).
//!
//! **Cost** per pass: per sample one RK4 step and the Kalman update (20 states, up to 16
//! measured rows); per `RELINEARISE_S` one Jacobian (about 17 evaluations of the forces) and
//! its transition. An estimate of the intensities takes about 200 passes.

use glam::{DQuat, DVec3};

use super::Mat;
use rayon::prelude::*;

use crate::compare::{combined, controls_at, CompareConfig, Measured, NoiseEstimate, SIGMA_MIN};
use wireflight_data::{Channel, FlightData};
use wireflight_flight::linear::skew;
use wireflight_flight::model::{Model, State, Vehicle};
use wireflight_flight::turbulence::{DrydenIntensity, TurbulenceLevel};

/// Error-state dimension of the aircraft (a fixed wing).
const AIRCRAFT: usize = 12;
/// Gust axes: north, east, down.
pub const GUST_AXES: usize = 3;
/// States of the gust shaping filters: one for u, two each for v and w, one for each axis
/// of the rotary disturbance.
const GUST_STATES: usize = 8;
/// The first rotary disturbance state.
const ROTARY: usize = 5;
/// Intensities the filter estimates: three gust velocities, three rotary disturbances.
pub const INTENSITIES: usize = 6;
/// Filter states: the aircraft's error state and the gust filters'.
const NA: usize = AIRCRAFT + GUST_STATES;
/// Measurement rows the filter can use: position 3, NED velocity 3, attitude 3, rates 3,
/// airspeed 1, accelerometer 3.
const ROWS: usize = 16;
/// The linearisation (A and its transition) is taken again after this long, s.
pub const RELINEARISE_S: f64 = 0.1;
/// Forward-difference step of the gust columns, m/s.
const GUST_STEP: f64 = 1e-4;
/// Gust intensities searched, m/s: from calm to beyond severe turbulence.
const SIGMA_RANGE: (f64, f64) = (1e-3, 15.0);
/// Correlation lengths searched, m.
const LENGTH_RANGE: (f64, f64) = (20.0, 3000.0);
/// Scale length of the gusts when the data do not determine it, m (between MIL-F-8785C's
/// low-altitude lengths and its 1750 ft above 2000 ft).
pub const DEFAULT_LENGTH_M: f64 = 300.0;
/// Golden-section steps of one search (the bracket shrinks by 0.618 each: ln σ to 3 %, well
/// inside its ±).
const GOLDEN_STEPS: usize = 12;
/// Rotary disturbances searched, rad/s².
const ROTARY_RANGE: (f64, f64) = (1e-4, 50.0);
/// χ² with six degrees of freedom at 0.1 %: six intensities must earn their place.
pub const TURBULENCE_LR_BOUND: f64 = 22.46;
/// χ² with three degrees of freedom at 0.1 %: the gust velocities must earn theirs on top of
/// the rotary disturbance (a missing moment looks like one).
pub const GUST_LR_BOUND: f64 = 16.27;
/// Rounds at most of estimating the gusts on numbers just fitted through the filter and
/// fitting the numbers again with them (`diagnose` and `identify` through turbulence): the
/// gusts estimated once, on numbers that were not yet the filter's, stop short of the
/// likelihood's joint maximum.
pub const SETTLE_ROUNDS: usize = 4;
/// The numbers and the gusts are settled when a round moves no number by more than this
/// share of its σ.
pub const SETTLED_SIGMAS: f64 = 0.1;
/// Smallest gust σ called turbulence, m/s: half of MIL-F-8785C's light turbulence near the
/// ground (0.77–0.88 m/s). Below it, what the filter takes for gusts is as likely the model's
/// own error: 0.1–0.3 m/s on JSBSim's calm c172p flights, with an exact model 0.01–0.05.
pub const MIN_TURBULENCE_MPS: f64 = 0.4;

/// The largest spread of the innovations, over the filter's own account of it, with which
/// gusts may explain a flight: a model the filter cannot follow even with its gusts is wrong
/// in more than the air (JSBSim's calm c172p flown with the untuned c172p model: 54 with
/// "gusts" of 5 m/s; its turbulent flights 1.7–1.8, `simulate`'s 1.0).
pub const MAX_INNOVATION_SPREAD: f64 = 3.0;

/// How a fit compares model and measurements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MethodChoice {
    /// Output error, and the filter-error method where output error leaves the error
    /// unexplained and the gusts are significant.
    #[default]
    Auto,
    /// Output error alone (calm air assumed).
    OutputError,
    /// The filter-error method, whatever the test says.
    FilterError,
}

/// The gust field the filter assumes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GustModel {
    /// Stationary deviation of the north, east and down gusts, m/s.
    pub sigma_mps: [f64; GUST_AXES],
    /// Dryden scale lengths L of the three, m (time scales L/V).
    pub length_m: [f64; GUST_AXES],
    /// Stationary deviation of the rotary disturbance, the angular acceleration turbulence
    /// adds about the body axes x, y, z, rad/s² (MIL-F-8785C's rotary gusts p_g, q_g, r_g
    /// act through the rate damping; JSBSim flies them).
    pub rotary_radps2: [f64; 3],
}

impl GustModel {
    /// Calm air: no gusts (the filter is then output error with estimated starts).
    pub const CALM: GustModel = GustModel {
        sigma_mps: [0.0; GUST_AXES],
        length_m: [DEFAULT_LENGTH_M; GUST_AXES],
        rotary_radps2: [0.0; 3],
    };

    /// Intensity `j`: the gusts' σ (0..3), then the rotary disturbances' (3..6).
    pub fn intensity(&self, j: usize) -> f64 {
        if j < GUST_AXES {
            self.sigma_mps[j]
        } else {
            self.rotary_radps2[j - GUST_AXES]
        }
    }

    /// The same model with intensity `j` set to `v`.
    pub fn with_intensity(mut self, j: usize, v: f64) -> Self {
        if j < GUST_AXES {
            self.sigma_mps[j] = v;
        } else if j < INTENSITIES {
            self.rotary_radps2[j - GUST_AXES] = v;
        }
        self
    }
}

/// The Dryden shaping filters of a gust model at an airspeed, in the filter's gust states
/// z (u: z₀; v: z₁, z₂; w: z₃, z₄), driven by unit white noise: ż = A·z + w, g = C·z.
struct DrydenFilters {
    /// Continuous state matrix (block diagonal).
    a: [[f64; GUST_STATES]; GUST_STATES],
    /// Gust velocities from the states, m/s (σ lives here, so that P∞ does not depend on it).
    c: [[f64; GUST_STATES]; GUST_AXES],
    /// Stationary covariance of the states.
    p_inf: [[f64; GUST_STATES]; GUST_STATES],
    /// Angular acceleration per unit rotary state, rad/s² (its σ), body x, y, z.
    rotary: [f64; 3],
    /// Time constant of the rotary disturbance, s.
    rotary_tau: f64,
}

impl DrydenFilters {
    /// The filters of `g` at `airspeed` for an aircraft of `span` (the rotary disturbance's
    /// time constant is Dryden's 4b/(πV)).
    fn new(g: &GustModel, airspeed: f64, span: f64) -> Self {
        let mut a = [[0.0; GUST_STATES]; GUST_STATES];
        let mut c = [[0.0; GUST_STATES]; GUST_AXES];
        let mut p_inf = [[0.0; GUST_STATES]; GUST_STATES];
        let t = g.length_m.map(|l| (l / airspeed).max(1e-3));
        // u: ż = −z/T + √(2/T)·w is (1 + sT)⁻¹ with unit variance; the noise's √(2/T) is
        // folded into P∞ = 1 (the discrete noise is P∞ − Φ·P∞·Φᵀ, whatever the scaling).
        a[0][0] = -1.0 / t[0];
        p_inf[0][0] = 1.0;
        c[0][0] = g.sigma_mps[0];
        // v, w: z̈ + (2/T)ż + z/T² = w, g = σ√T·(z/T² + √3·ż/T): (1 + √3·sT)/(1 + sT)²
        // with variance σ² (P∞ = diag(T³/4, T/4) under unit noise).
        for (axis, first) in [(1, 1), (2, 3)] {
            let tt = t[axis];
            a[first][first + 1] = 1.0;
            a[first + 1][first] = -1.0 / (tt * tt);
            a[first + 1][first + 1] = -2.0 / tt;
            p_inf[first][first] = tt * tt * tt / 4.0;
            p_inf[first + 1][first + 1] = tt / 4.0;
            let k = g.sigma_mps[axis] * tt.sqrt();
            c[axis][first] = k / (tt * tt);
            c[axis][first + 1] = k * 3f64.sqrt() / tt;
        }
        let rotary_tau = (4.0 * span / (std::f64::consts::PI * airspeed)).max(1e-3);
        for k in 0..3 {
            a[ROTARY + k][ROTARY + k] = -1.0 / rotary_tau;
            p_inf[ROTARY + k][ROTARY + k] = 1.0;
        }
        Self {
            a,
            c,
            p_inf,
            rotary: g.rotary_radps2,
            rotary_tau,
        }
    }

    /// The exact transition over `dt` and its driving noise P∞ − Φ·P∞·Φᵀ.
    fn discrete(
        &self,
        dt: f64,
    ) -> (
        [[f64; GUST_STATES]; GUST_STATES],
        [[f64; GUST_STATES]; GUST_STATES],
    ) {
        let m = Mat::from_rows(&self.a.map(|r| r.map(|v| v * dt)).each_ref().map(|r| &r[..]))
            .map(|m| m.expm())
            .unwrap_or_else(|| Mat::identity(GUST_STATES));
        let phi: [[f64; GUST_STATES]; GUST_STATES] =
            std::array::from_fn(|i| std::array::from_fn(|j| m.at(i, j)));
        let mut q = self.p_inf;
        for i in 0..GUST_STATES {
            for j in 0..GUST_STATES {
                let mut v = 0.0;
                for k in 0..GUST_STATES {
                    for l in 0..GUST_STATES {
                        v += phi[i][k] * self.p_inf[k][l] * phi[j][l];
                    }
                }
                q[i][j] -= v;
            }
        }
        (phi, q)
    }

    /// The gust velocities of states `z`, m/s.
    fn gusts(&self, z: &[f64; GUST_STATES]) -> DVec3 {
        DVec3::from_array(std::array::from_fn(|r| {
            (0..GUST_STATES).map(|k| self.c[r][k] * z[k]).sum()
        }))
    }
}

/// What one pass of the filter over the flight gives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pass {
    /// −ln L (module docs), without the constant ½·ln 2π per row.
    pub neg_log_likelihood: f64,
    /// Innovations counted (samples × measured rows).
    pub residuals: usize,
    /// RMS of the innovations in units of each row's measurement noise: 1 for a right model
    /// that the filter follows, the error "in units of the noise".
    pub noise_units: f64,
    /// RMS of the normalised innovations S^(−½)·ν per row: 1 where the filter's own
    /// account of its uncertainty is right (whatever the gusts).
    pub normalised: f64,
    /// Per full row (position 0..3, NED velocity 3..6, attitude 6..9, rates 9..12, airspeed
    /// 12, accelerometer 13..16), the innovations' RMS in units of the row's noise (0 where
    /// not measured).
    pub rows_noise_units: [f64; ROWS],
    /// Whether the model stayed finite everywhere.
    pub finite: bool,
}

/// The gusts estimated from a flight, and whether they are there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GustEstimate {
    /// Stationary deviation of the north, east and down gusts, m/s.
    pub sigma_mps: [f64; GUST_AXES],
    /// Their 1σ uncertainty, m/s (from the likelihood's curvature).
    pub sigma_se_mps: [f64; GUST_AXES],
    /// Stationary deviation of the rotary disturbance about body x, y, z, rad/s².
    pub rotary_radps2: [f64; 3],
    /// Its 1σ uncertainty, rad/s².
    pub rotary_se_radps2: [f64; 3],
    /// Scale lengths used, m (north, east, down; north and east are one number).
    pub length_m: [f64; GUST_AXES],
    /// Their 1σ uncertainty, m, where the data determine them (under half the length);
    /// None: the default was kept.
    pub length_se_m: [Option<f64>; GUST_AXES],
    /// The filter in calm air (output error with estimated starts).
    pub calm: Pass,
    /// The filter with the estimated gusts.
    pub gusty: Pass,
    /// 2·(−ln L_calm + ln L_gusty).
    pub likelihood_ratio: f64,
    /// The same with the gust velocities alone taken away (the rotary disturbance kept).
    pub gust_likelihood_ratio: f64,
}

impl GustEstimate {
    /// The gusts the estimate describes.
    pub fn model(&self) -> GustModel {
        GustModel {
            sigma_mps: self.sigma_mps,
            length_m: self.length_m,
            rotary_radps2: self.rotary_radps2,
        }
    }

    /// Whether the gusts are significant: the likelihood ratio beats
    /// [`TURBULENCE_LR_BOUND`], the gust velocities' own beats [`GUST_LR_BOUND`], some
    /// gust intensity is more than twice its uncertainty and at least
    /// [`MIN_TURBULENCE_MPS`], and the filter follows the flight with them (its innovations'
    /// spread at most [`MAX_INNOVATION_SPREAD`]).
    pub fn significant(&self) -> bool {
        self.gusty.normalised <= MAX_INNOVATION_SPREAD
            && self.likelihood_ratio > TURBULENCE_LR_BOUND
            && self.gust_likelihood_ratio > GUST_LR_BOUND
            && self
                .sigma_mps
                .iter()
                .zip(&self.sigma_se_mps)
                .any(|(s, se)| *s > 2.0 * se && *s >= MIN_TURBULENCE_MPS)
    }
}

/// Fit the numbers `set` puts into the model (`theta0` their start, `scales` their typical
/// sizes) through the filter on every flight of `flights` (each with its gusts): Gauss–Newton
/// on the whitened innovations of all of them, the gain recomputed at every trial, each step
/// halved until the likelihood falls. With `prior` (a centre and a σ per number), the
/// numbers are held to it as `identify` holds them, so a number the flights do not
/// determine stays where it was. Returns the numbers, their 1σ (Cramér–Rao, the innovations
/// being white; posterior with a prior), and the flights' passes merged.
pub fn fit_flights(
    flights: &[(&FlightFilter, GustModel)],
    model: &Model,
    set: &(dyn Fn(&mut Model, &[f64]) + Sync),
    theta0: &[f64],
    scales: &[f64],
    prior: Option<(&[f64], &[f64])>,
) -> FilterFit {
    let np = theta0.len();
    // The objective's residuals at θ: every flight's whitened innovations, then the prior's.
    let evaluate = |theta: &[f64]| -> (Pass, Vec<f64>) {
        let mut m = model.clone();
        set(&mut m, theta);
        let mut merged = Pass {
            finite: true,
            ..Pass::default()
        };
        let mut r = Vec::new();
        let mut squares = 0.0;
        for (f, g) in flights {
            let (p, w) = f.pass_whitened(&m, g, true);
            merged.neg_log_likelihood += p.neg_log_likelihood;
            merged.finite &= p.finite;
            squares += p.normalised * p.normalised * p.residuals as f64;
            merged.noise_units += p.noise_units * p.noise_units * p.residuals as f64;
            merged.residuals += p.residuals;
            r.extend(w);
        }
        let n = merged.residuals.max(1) as f64;
        merged.normalised = (squares / n).sqrt();
        merged.noise_units = (merged.noise_units / n).sqrt();
        if let Some((centre, sd)) = prior {
            for ((t, t0), s) in theta.iter().zip(centre).zip(sd) {
                let z = (t - t0) / s;
                r.push(z);
                merged.neg_log_likelihood += 0.5 * z * z;
            }
        }
        if !merged.finite {
            merged.neg_log_likelihood = f64::INFINITY;
        }
        (merged, r)
    };
    let mut theta = theta0.to_vec();
    let (mut pass, mut r) = evaluate(&theta);
    let mut info = vec![0.0; np * np];
    let mut iterations = 0;
    for it in 0..FIT_ITERATIONS {
        iterations = it + 1;
        // Forward differences of the residuals, one evaluation per number.
        let columns: Vec<Option<Vec<f64>>> = (0..np)
            .map(|i| {
                let h = 1e-4 * scales[i].abs().max(1e-9);
                let mut t = theta.clone();
                t[i] += h;
                let (p, ri) = evaluate(&t);
                (p.finite && ri.len() == r.len())
                    .then(|| ri.iter().zip(&r).map(|(a, b)| (a - b) / h).collect())
            })
            .collect();
        let Some(columns) = columns.into_iter().collect::<Option<Vec<Vec<f64>>>>() else {
            break;
        };
        let mut grad = vec![0.0; np];
        for i in 0..np {
            grad[i] = columns[i].iter().zip(&r).map(|(a, b)| a * b).sum();
            for j in 0..=i {
                let v: f64 = columns[i].iter().zip(&columns[j]).map(|(a, b)| a * b).sum();
                info[i * np + j] = v;
                info[j * np + i] = v;
            }
        }
        let Some(inv) = wireflight_flight::numeric::invert(&info, np) else {
            break;
        };
        let step: Vec<f64> = (0..np)
            .map(|i| -(0..np).map(|j| inv[i * np + j] * grad[j]).sum::<f64>())
            .collect();
        let mut accepted = false;
        let mut fraction = 1.0;
        for _ in 0..12 {
            let trial: Vec<f64> = theta
                .iter()
                .zip(&step)
                .map(|(t, s)| t + fraction * s)
                .collect();
            let (p, rt) = evaluate(&trial);
            if p.finite && p.neg_log_likelihood < pass.neg_log_likelihood {
                let fall = pass.neg_log_likelihood - p.neg_log_likelihood;
                theta = trial;
                pass = p;
                r = rt;
                accepted = fall > 1e-6 * (1.0 + pass.neg_log_likelihood.abs());
                break;
            }
            fraction *= 0.5;
        }
        if !accepted {
            break;
        }
    }
    let sigma = wireflight_flight::numeric::invert(&info, np)
        .map(|inv| (0..np).map(|i| inv[i * np + i].max(0.0).sqrt()).collect())
        .unwrap_or_else(|| vec![f64::INFINITY; np]);
    FilterFit {
        theta,
        sigma,
        pass,
        iterations,
    }
}

/// Numbers fitted through the filter ([`FlightFilter::fit`], [`fit_flights`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FilterFit {
    /// The fitted numbers.
    pub theta: Vec<f64>,
    /// Their 1σ.
    pub sigma: Vec<f64>,
    /// The filter at the fitted numbers.
    pub pass: Pass,
    /// Gauss–Newton iterations taken.
    pub iterations: usize,
}

/// Gauss–Newton iterations of a fit through the filter at most.
const FIT_ITERATIONS: usize = 10;

/// Why the filter cannot run on a flight.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    /// A point mass has no air to be gusted in.
    #[error("the filter-error method needs a fixed wing (a point mass flies in no air)")]
    PointMass,
    /// The data lack what the filter starts from.
    #[error("the filter-error method needs {0} in the flight data")]
    Missing(&'static str),
    /// Too short to cut a window.
    #[error("the flight is too short for one window of {0} s")]
    TooShort(f64),
}

/// The measured value of every row at one sample (the attitude rows are filled by the
/// innovation, which needs the prediction).
struct Measurement {
    rows: [f64; ROWS],
    quat: DQuat,
}

/// A flight prepared for the filter: its windows, measured rows and their noise.
pub struct FlightFilter<'d> {
    data: &'d FlightData,
    windows: Vec<(usize, usize)>,
    /// Full-row indices (into the 16) the data measure.
    rows: Vec<usize>,
    /// Measurement noise deviation of every full row.
    noise: [f64; ROWS],
    /// Mean airspeed, m/s (the frozen field's speed).
    airspeed_mps: f64,
    /// Wing span, m (the rotary disturbance's time scale).
    span_m: f64,
    /// Scale lengths (north, east, down) where the record does not determine them:
    /// MIL-F-8785C's at the flight's mean height above the origin.
    default_length_m: [f64; GUST_AXES],
    accel: bool,
    max_dt: f64,
    vel_body: Vec<DVec3>,
    quats: Vec<DQuat>,
}

impl<'d> FlightFilter<'d> {
    /// Prepare `data` for `model` with compare's windows and noise (`cfg`); `noise` the
    /// data's measurement noise ([`crate::compare::estimate_noise`]).
    pub fn new(
        model: &Model,
        data: &'d FlightData,
        noise: &NoiseEstimate,
        cfg: &CompareConfig,
    ) -> Result<Self, FilterError> {
        if !matches!(model.vehicle, Vehicle::FixedWing(_)) {
            return Err(FilterError::PointMass);
        }
        let att = data
            .attitude
            .as_ref()
            .ok_or(FilterError::Missing("attitude"))?;
        let rates = data
            .rates_body
            .as_ref()
            .ok_or(FilterError::Missing("body rates"))?;
        let n = data.len();
        let quats: Vec<DQuat> = att
            .iter()
            .map(|e| {
                let mut s = State::default();
                s.set_attitude(*e);
                s.quat()
            })
            .collect();
        // The body velocity as recorded, or the NED one turned into the body.
        let vb: Vec<DVec3> = match (&data.vel_body, &data.vel_ned) {
            (Some(vb), _) => vb.clone(),
            (None, Some(v)) => v
                .iter()
                .zip(&quats)
                .map(|(v, q)| q.inverse() * *v)
                .collect(),
            (None, None) => return Err(FilterError::Missing("a velocity")),
        };
        if att.len() != n || vb.len() != n || rates.len() != n {
            return Err(FilterError::Missing("every channel at every sample"));
        }
        let windows = crate::compare::cut_windows(&data.time, cfg);
        if windows.is_empty() {
            return Err(FilterError::TooShort(cfg.window_s));
        }
        let measured = Measured::of(data);
        let mut rows: Vec<usize> = (0..3).collect();
        for (on, range) in [
            (measured.velocity, 3..6),
            (measured.attitude, 6..9),
            (measured.rates, 9..12),
            (measured.airspeed, 12..13),
            (measured.accel, 13..16),
        ] {
            if on {
                rows.extend(range);
            }
        }
        let noise = match &cfg.model_error {
            Some(m) => combined(noise, m),
            None => *noise,
        };
        let mut sigma = [0.0; ROWS];
        for k in 0..3 {
            sigma[k] = noise.pos_axes[k].max(SIGMA_MIN[0]);
            sigma[3 + k] = noise.vel_axes[k].max(SIGMA_MIN[1]);
            sigma[6 + k] = noise.att_axes[k].max(SIGMA_MIN[2]);
            sigma[9 + k] = noise.rate_axes[k].max(SIGMA_MIN[3]);
            sigma[13 + k] = noise.accel_axes[k].max(SIGMA_MIN[5]);
        }
        sigma[12] = noise.airspeed_mps.max(SIGMA_MIN[4]);
        let airspeed_mps = match &data.airspeed {
            Some(a) if !a.is_empty() => a.iter().sum::<f64>() / a.len() as f64,
            _ => vb.iter().map(|v| v.length()).sum::<f64>() / n.max(1) as f64,
        }
        .max(1.0);
        // The lengths do not depend on the level; the height is the origin's plus the mean
        // height above it (the origin's altitude taken as the ground's).
        let height_m = model.origin.altitude_m
            - data.pos_ned.iter().map(|p| p.z).sum::<f64>() / n.max(1) as f64;
        let lengths = DrydenIntensity::at(TurbulenceLevel::Light, height_m).length_m;
        Ok(Self {
            data,
            windows,
            rows,
            noise: sigma,
            airspeed_mps,
            span_m: model.vehicle.span(),
            default_length_m: lengths,
            accel: measured.accel,
            max_dt: cfg.max_dt,
            vel_body: vb,
            quats,
        })
    }

    /// How long the windows last together, s.
    pub fn recorded_s(&self) -> f64 {
        self.windows
            .iter()
            .map(|&(a, b)| self.data.time[b - 1] - self.data.time[a])
            .sum::<f64>()
            .max(1e-9)
    }

    /// The flight's mean airspeed, m/s.
    pub fn airspeed_mps(&self) -> f64 {
        self.airspeed_mps
    }

    /// One pass of the filter over every window with the gusts `gusts`.
    pub fn pass(&self, model: &Model, gusts: &GustModel) -> Pass {
        self.pass_whitened(model, gusts, false).0
    }

    /// How much the likelihood could fall if the number `set` puts into the model moved
    /// from `value` (by one Gauss–Newton step from there, with the gusts `gusts`): the score
    /// test (Jᵀr)²/(2·JᵀJ) of the whitened innovations r; one pass besides `at`, the pass at
    /// `value` with its whitened innovations ([`FlightFilter::whitened`]).
    pub fn score(
        &self,
        model: &Model,
        set: &(dyn Fn(&mut Model, f64) + Sync),
        value: f64,
        scale: f64,
        gusts: &GustModel,
        at: &[f64],
    ) -> f64 {
        let h = 1e-4 * scale.abs().max(1e-9);
        let mut m = model.clone();
        set(&mut m, value + h);
        let (p, moved) = self.pass_whitened(&m, gusts, true);
        if !p.finite || moved.len() != at.len() {
            return 0.0;
        }
        let (mut jr, mut jj) = (0.0, 0.0);
        for (a, b) in moved.iter().zip(at) {
            let j = (a - b) / h;
            jr += j * b;
            jj += j * j;
        }
        if jj > 0.0 {
            0.5 * jr * jr / jj
        } else {
            0.0
        }
    }

    /// One pass and its whitened innovations L⁻¹·ν (S = L·Lᵀ), every sample in order.
    pub fn whitened(&self, model: &Model, gusts: &GustModel) -> (Pass, Vec<f64>) {
        self.pass_whitened(model, gusts, true)
    }

    /// [`FlightFilter::pass`], and with `white` the whitened innovations L⁻¹·ν (S = L·Lᵀ)
    /// of every sample in order: a fit's residuals.
    fn pass_whitened(&self, model: &Model, gusts: &GustModel, white: bool) -> (Pass, Vec<f64>) {
        let parts: Vec<(Pass, Vec<f64>)> = self
            .windows
            .par_iter()
            .map(|&w| {
                let mut v = Vec::new();
                let p = self.window(model.clone(), w, gusts, white.then_some(&mut v));
                (p, v)
            })
            .collect();
        let white: Vec<f64> = parts.iter().flat_map(|(_, v)| v.iter().copied()).collect();
        let parts: Vec<Pass> = parts.into_iter().map(|(p, _)| p).collect();
        let mut total = Pass {
            finite: true,
            ..Pass::default()
        };
        for p in &parts {
            total.neg_log_likelihood += p.neg_log_likelihood;
            total.residuals += p.residuals;
            total.noise_units += p.noise_units;
            total.normalised += p.normalised;
            for (t, r) in total.rows_noise_units.iter_mut().zip(&p.rows_noise_units) {
                *t += r;
            }
            total.finite &= p.finite;
        }
        let residuals = total.residuals.max(1) as f64;
        let per_row = residuals / self.rows.len().max(1) as f64;
        total.noise_units = (total.noise_units / residuals).sqrt();
        total.normalised = (total.normalised / residuals).sqrt();
        for r in total.rows_noise_units.iter_mut() {
            *r = (*r / per_row).sqrt();
        }
        if !total.finite {
            total.neg_log_likelihood = f64::INFINITY;
        }
        (total, white)
    }

    /// The gusts that maximise the likelihood for `model`, and the test against calm air.
    pub fn estimate_gusts(&self, model: &Model) -> GustEstimate {
        let calm = self.pass(model, &GustModel::CALM);
        let nll = |g: &GustModel| self.pass(model, g).neg_log_likelihood;
        let mut gusts = GustModel {
            sigma_mps: [0.5; GUST_AXES],
            length_m: self.default_length_m,
            rotary_radps2: [0.0; 3],
        };
        let range = |j: usize| {
            if j < GUST_AXES {
                SIGMA_RANGE
            } else {
                ROTARY_RANGE
            }
        };
        let intensities = |gusts: &mut GustModel, count: usize| {
            for j in 0..count {
                let best = golden(range(j), |ln_s| nll(&gusts.with_intensity(j, ln_s.exp())));
                *gusts = gusts.with_intensity(j, best);
            }
        };
        // The intensities in turn, the lengths (horizontal, vertical), the intensities again:
        // each axis drives mostly its own channels, so one more round settles them.
        intensities(&mut gusts, INTENSITIES);
        let mut length_se_m = [None; GUST_AXES];
        let mut best = self.pass(model, &gusts);
        for axes in [&[0usize, 1][..], &[2][..]] {
            let with = |g: &GustModel, l: f64| {
                let mut g = *g;
                axes.iter().for_each(|&a| g.length_m[a] = l);
                g
            };
            let l = golden(LENGTH_RANGE, |ln_l| nll(&with(&gusts, ln_l.exp())));
            let trial = with(&gusts, l);
            let p = self.pass(model, &trial);
            if p.neg_log_likelihood < best.neg_log_likelihood {
                // The likelihood's curvature knows the noise, not that a record holds only so
                // many correlation times: an estimated time scale T from a record of length
                // D scatters by about T·√(2T/D) from one stretch of turbulence to the next.
                let record = self.recorded_s();
                let scatter = l * (2.0 * l / self.airspeed_mps / record).sqrt();
                let se =
                    curvature_se(l, p.neg_log_likelihood, |v| nll(&with(&gusts, v))).max(scatter);
                if se < 0.5 * l {
                    gusts = trial;
                    best = p;
                    axes.iter().for_each(|&a| length_se_m[a] = Some(se));
                }
            }
        }
        intensities(&mut gusts, INTENSITIES);
        let mut gusty = self.pass(model, &gusts);
        // An intensity at the bottom of its range is none on that axis.
        for j in 0..INTENSITIES {
            let g = gusts.with_intensity(j, 0.0);
            let p = self.pass(model, &g);
            if p.neg_log_likelihood <= gusty.neg_log_likelihood {
                gusts = g;
                gusty = p;
            }
        }
        let mut se = [0.0; INTENSITIES];
        for (j, se) in se.iter_mut().enumerate() {
            let s = gusts.intensity(j);
            let h = (0.05 * s).max(0.01 * range(j).1 / SIGMA_RANGE.1);
            let at = |v: f64| nll(&gusts.with_intensity(j, v));
            *se = if s > h {
                curvature_se(s, gusty.neg_log_likelihood, at)
            } else {
                // At zero, the curvature of a one-sided optimum: steps up only.
                let (f1, f2) = (at(s + h), at(s + 2.0 * h));
                let c = (f2 - 2.0 * f1 + gusty.neg_log_likelihood) / (h * h);
                if c > 0.0 {
                    1.0 / c.sqrt()
                } else {
                    f64::INFINITY
                }
            };
        }
        let mut rotary_only = gusts;
        rotary_only.sigma_mps = [0.0; GUST_AXES];
        let without_gusts = self.pass(model, &rotary_only).neg_log_likelihood;
        GustEstimate {
            gust_likelihood_ratio: 2.0 * (without_gusts - gusty.neg_log_likelihood),
            sigma_mps: gusts.sigma_mps,
            sigma_se_mps: [se[0], se[1], se[2]],
            rotary_radps2: gusts.rotary_radps2,
            rotary_se_radps2: [se[3], se[4], se[5]],
            length_m: gusts.length_m,
            length_se_m,
            calm,
            gusty,
            likelihood_ratio: 2.0 * (calm.neg_log_likelihood - gusty.neg_log_likelihood),
        }
    }

    /// Fit the numbers `set` puts into the model (`theta0` their start, `scales` their typical
    /// sizes) through the filter with the gusts `gusts` ([`fit_flights`] on this flight alone,
    /// without a prior).
    pub fn fit(
        &self,
        model: &Model,
        set: &(dyn Fn(&mut Model, &[f64]) + Sync),
        theta0: &[f64],
        scales: &[f64],
        gusts: &GustModel,
    ) -> FilterFit {
        fit_flights(&[(self, *gusts)], model, set, theta0, scales, None)
    }

    /// Of the filter's rows (`self.rows`, with innovations `nu`), those measured at sample
    /// `i`: the rows, their innovations, and how many.
    fn sampled_rows(&self, i: usize, nu: &[f64; ROWS]) -> ([usize; ROWS], [f64; ROWS], usize) {
        let sampling = &self.data.sampling;
        let (mut here, mut nu_here, mut p) = ([0; ROWS], [0.0; ROWS], 0);
        for (r, &row) in self.rows.iter().enumerate() {
            let channel = match row {
                0..3 => Channel::Position,
                3..6 => Channel::Velocity,
                6..9 => Channel::Attitude,
                9..12 => Channel::Rates,
                12 => Channel::Airspeed,
                _ => Channel::Accelerometer,
            };
            if sampling.at(channel, i) {
                here[p] = row;
                nu_here[p] = nu[r];
                p += 1;
            }
        }
        (here, nu_here, p)
    }

    /// The measured rows at sample `i`.
    fn measurement(&self, i: usize) -> Measurement {
        let d = self.data;
        let mut rows = [0.0; ROWS];
        let put = |rows: &mut [f64; ROWS], at: usize, v: DVec3| {
            rows[at..at + 3].copy_from_slice(&v.to_array());
        };
        put(&mut rows, 0, d.pos_ned[i]);
        if let Some(v) = d.vel_ned.as_ref().and_then(|v| v.get(i)) {
            put(&mut rows, 3, *v);
        }
        if let Some(r) = d.rates_body.as_ref().and_then(|v| v.get(i)) {
            put(&mut rows, 9, *r);
        }
        if let Some(a) = d.airspeed.as_ref().and_then(|v| v.get(i)) {
            rows[12] = *a;
        }
        if let Some(a) = d.accel_body.as_ref().and_then(|v| v.get(i)) {
            put(&mut rows, 13, *a);
        }
        Measurement {
            rows,
            quat: self.quats[i],
        }
    }

    /// The filter over one window; `model` is the window's own copy (its air offset carries
    /// the gusts).
    fn window(
        &self,
        mut model: Model,
        (start, end): (usize, usize),
        gusts: &GustModel,
        mut white: Option<&mut Vec<f64>>,
    ) -> Pass {
        let d = self.data;
        let dryden = DrydenFilters::new(gusts, self.airspeed_mps, self.span_m);
        let att = d.attitude.as_ref().map(|a| a[start]).unwrap_or_default();
        let rates = d.rates_body.as_ref().map(|r| r[start]).unwrap_or_default();
        let mut x = State::measured(
            d.pos_ned[start],
            self.vel_body[start],
            att,
            rates,
            &controls_at(d, start),
        );
        let mut z = [0.0; GUST_STATES];
        // The start's uncertainty: what was measured, as noisy as it was measured (the body
        // velocity, turned by a noisy attitude or derived, at least 0.3 m/s); the gusts at
        // their stationary spread.
        let mut cov = [0.0; NA * NA];
        let vel_sd: f64 = 0.3;
        let start_sd: [f64; AIRCRAFT] = [
            self.noise[0],
            self.noise[1],
            self.noise[2],
            vel_sd.max(self.noise[3]),
            vel_sd.max(self.noise[4]),
            vel_sd.max(self.noise[5]),
            self.noise[6].max(1e-3),
            self.noise[7].max(1e-3),
            self.noise[8].max(1e-3),
            self.noise[9].max(1e-3),
            self.noise[10].max(1e-3),
            self.noise[11].max(1e-3),
        ];
        for k in 0..AIRCRAFT {
            cov[k * NA + k] = start_sd[k] * start_sd[k];
        }
        for i in 0..GUST_STATES {
            for j in 0..GUST_STATES {
                cov[(AIRCRAFT + i) * NA + AIRCRAFT + j] = dryden.p_inf[i][j];
            }
        }
        let mut gust_step = (f64::NAN, dryden.discrete(0.0));
        let mut out = Pass {
            finite: true,
            ..Pass::default()
        };
        let mut squares = 0.0;
        let mut phi = [0.0; NA * NA];
        let mut linearised_at = f64::NEG_INFINITY;
        let mut linearised_dt = 0.0;
        let mut scratch = Scratch::default();
        for i in start + 1..end {
            let (t0, t1) = (d.time[i - 1], d.time[i]);
            let dt = t1 - t0;
            let cmd = controls_at(d, i - 1);
            let g = dryden.gusts(&z);
            model.set_air_offset(g);
            if dt != gust_step.0 {
                gust_step = (dt, dryden.discrete(dt));
            }
            let (gust_phi, gust_q) = &gust_step.1;
            if t0 - linearised_at >= RELINEARISE_S - 1e-9 || (dt - linearised_dt).abs() > 1e-9 {
                let a = augmented_jacobian(&mut model, t0, &x, &cmd, &dryden);
                taylor_transition(&a, dt, &mut phi, &mut scratch);
                // The gust filters' own block exactly, as their noise is.
                for r in 0..GUST_STATES {
                    for c in 0..GUST_STATES {
                        phi[(AIRCRAFT + r) * NA + AIRCRAFT + c] = gust_phi[r][c];
                    }
                }
                linearised_at = t0;
                linearised_dt = dt;
            }
            // The state: the model's own steps, the gusts held over them.
            let (steps, h) = Model::substeps(dt, self.max_dt);
            for k in 0..steps {
                x = model.step(t0 + k as f64 * h, &x, &cmd, h);
            }
            // The rotary disturbance's angular acceleration, decaying over the step, added
            // to the rates: ∫ σ·z·e^(−s/τ) ds = σ·z·τ·(1 − e^(−Δt/τ)).
            let tau_r = dryden.rotary_tau;
            let gain = tau_r * (1.0 - (-dt / tau_r).exp());
            let spin = DVec3::from_array(std::array::from_fn(|k| {
                dryden.rotary[k] * z[ROTARY + k] * gain
            }));
            if spin != DVec3::ZERO {
                x.set_omega(x.omega() + spin);
            }
            z = std::array::from_fn(|r| (0..GUST_STATES).map(|c| gust_phi[r][c] * z[c]).sum());
            if !x.is_finite() {
                out.finite = false;
                break;
            }
            // The covariance.
            propagate(&phi, &mut cov, &mut scratch);
            for r in 0..GUST_STATES {
                for c in 0..GUST_STATES {
                    cov[(AIRCRAFT + r) * NA + AIRCRAFT + c] += gust_q[r][c];
                }
            }
            // The innovation and its covariance.
            model.set_air_offset(dryden.gusts(&z));
            let y = self.measurement(i);
            let cmd_now = controls_at(d, i);
            let (pred, hmat) = self.readout(&mut model, t1, &x, &cmd_now, &dryden);
            let mut nu = [0.0; ROWS];
            let turn = (x.quat().inverse() * y.quat).normalize();
            let turn = if turn.w < 0.0 { -turn } else { turn };
            let rot_err = turn.to_scaled_axis();
            for (r, &row) in self.rows.iter().enumerate() {
                nu[r] = if (6..9).contains(&row) {
                    rot_err[row - 6]
                } else {
                    y.rows[row] - pred[row]
                };
            }
            // The rows measured at this sample: a channel at its own rate is updated at its
            // own samples only (a value filled in between is not a measurement).
            let (here, nu, p) = self.sampled_rows(i, &nu);
            if p == 0 {
                continue;
            }
            let Some(update) = kalman_update(&hmat, &here[..p], &self.noise, &nu[..p], &mut cov)
            else {
                out.finite = false;
                break;
            };
            out.neg_log_likelihood += 0.5 * (update.quadratic + update.logdet);
            out.residuals += p;
            out.normalised += update.quadratic;
            if let Some(w) = white.as_deref_mut() {
                w.extend_from_slice(&update.white[..p]);
            }
            for (r, &row) in here[..p].iter().enumerate() {
                let v = (nu[r] / self.noise[row]).powi(2);
                squares += v;
                out.rows_noise_units[row] += v;
            }
            x = model.perturbed(&x, &update.correction[..AIRCRAFT]);
            for (zk, ck) in z.iter_mut().zip(&update.correction[AIRCRAFT..]) {
                *zk += ck;
            }
        }
        // Sums until the pass adds its windows' together ([`FlightFilter::pass`]).
        out.noise_units = squares;
        out
    }

    /// What the model's state reads as on every full row (the attitude rows zero: the
    /// innovation measures it against the prediction), and the rows' Jacobian H over the
    /// filter's error state (full rows × NA). `model` is the window's own copy: its air offset
    /// moves for the accelerometer's gust columns and is put back.
    fn readout(
        &self,
        model: &mut Model,
        t: f64,
        x: &State,
        cmd: &wireflight_data::Controls,
        dryden: &DrydenFilters,
    ) -> ([f64; ROWS], [[f64; NA]; ROWS]) {
        let mut y = [0.0; ROWS];
        let mut h = [[0.0; NA]; ROWS];
        let rot = x.rot();
        let v = x.vel();
        let wind = model.wind_at(x.pos_ned(), t);
        let v_r = v - rot.transpose() * wind;
        let vel_ned = rot * v;
        y[0..3].copy_from_slice(&x.pos_ned().to_array());
        y[3..6].copy_from_slice(&vel_ned.to_array());
        y[9..12].copy_from_slice(&x.omega().to_array());
        y[12] = v_r.length();
        // δp; the NED velocity R·v: R·δv and −R·[v]×·δθ; the attitude δθ; the rates δω.
        let dvel_dtheta = rot * -skew(v);
        for r in 0..3 {
            h[r][r] = 1.0;
            for c in 0..3 {
                h[3 + r][3 + c] = rot.col(c)[r];
                h[3 + r][6 + c] = dvel_dtheta.col(c)[r];
            }
            h[6 + r][6 + r] = 1.0;
            h[9 + r][9 + r] = 1.0;
        }
        // The airspeed |v − Rᵀw|: along v_r, δv; δθ turns the wind, −[Rᵀw]× (v_r grows by
        // Rᵀw × δθ); a gust blows against it, −Rᵀ.
        if y[12] > 0.0 {
            let along = v_r / y[12];
            let dtheta = -skew(rot.transpose() * wind);
            let dgust = -rot.transpose();
            let mut per_gust = [0.0; GUST_AXES];
            for c in 0..3 {
                h[12][3 + c] = along[c];
                h[12][6 + c] = along.dot(dtheta.col(c));
                per_gust[c] = along.dot(dgust.col(c));
            }
            through_filters(&per_gust, dryden, &mut h[12]);
        }
        if self.accel {
            let f0 = model.specific_force(t, x, cmd);
            y[13..16].copy_from_slice(&f0.to_array());
            let jac = model.specific_force_jacobian(t, x, cmd);
            for r in 0..3 {
                h[13 + r][..AIRCRAFT].copy_from_slice(&jac[r][..AIRCRAFT]);
            }
            let g = model.air_offset();
            let mut per_gust = [[0.0; GUST_AXES]; 3];
            for c in 0..GUST_AXES {
                let mut gust = g;
                gust[c] += GUST_STEP;
                model.set_air_offset(gust);
                let f = model.specific_force(t, x, cmd);
                for r in 0..3 {
                    per_gust[r][c] = (f[r] - f0[r]) / GUST_STEP;
                }
            }
            model.set_air_offset(g);
            for r in 0..3 {
                through_filters(&per_gust[r], dryden, &mut h[13 + r]);
            }
        }
        (y, h)
    }
}

/// A row's gust columns from its change per m/s of each gust axis: through the filters'
/// outputs, ∂/∂z = ∂/∂g · C.
fn through_filters(per_gust: &[f64; GUST_AXES], dryden: &DrydenFilters, row: &mut [f64; NA]) {
    for k in 0..GUST_STATES {
        row[AIRCRAFT + k] = (0..GUST_AXES).map(|a| per_gust[a] * dryden.c[a][k]).sum();
    }
}

/// The augmented Jacobian (NA × NA, row-major): the aircraft's error-state Jacobian, the
/// forces' change per gust filter state (forward differences per m/s of gust, through the
/// filters' outputs), and the filters' own dynamics.
fn augmented_jacobian(
    model: &mut Model,
    t: f64,
    x: &State,
    cmd: &wireflight_data::Controls,
    dryden: &DrydenFilters,
) -> [f64; NA * NA] {
    let mut a = [0.0; NA * NA];
    let jac = model.error_jacobian(t, x, cmd);
    for r in 0..AIRCRAFT {
        a[r * NA..r * NA + AIRCRAFT].copy_from_slice(&jac[r][..AIRCRAFT]);
    }
    let g = model.air_offset();
    let f0 = model.derivative(t, x, cmd);
    // Body velocity (state 3..6 → error 3..6) and rates (state 10..13 → error 9..12).
    let rows = [(3, 3), (4, 4), (5, 5), (9, 10), (10, 11), (11, 12)];
    let mut per_gust = [[0.0; GUST_AXES]; AIRCRAFT];
    for c in 0..GUST_AXES {
        let mut gust = g;
        gust[c] += GUST_STEP;
        model.set_air_offset(gust);
        let f = model.derivative(t, x, cmd);
        for &(row, slot) in &rows {
            per_gust[row][c] = (f.0[slot] - f0.0[slot]) / GUST_STEP;
        }
    }
    model.set_air_offset(g);
    for &(row, _) in &rows {
        let mut r = [0.0; NA];
        through_filters(&per_gust[row], dryden, &mut r);
        a[row * NA + AIRCRAFT..(row + 1) * NA].copy_from_slice(&r[AIRCRAFT..]);
    }
    for i in 0..GUST_STATES {
        for j in 0..GUST_STATES {
            a[(AIRCRAFT + i) * NA + AIRCRAFT + j] = dryden.a[i][j];
        }
    }
    // The rotary disturbance drives the rates (error 9..12) directly.
    for k in 0..3 {
        a[(9 + k) * NA + AIRCRAFT + ROTARY + k] = dryden.rotary[k];
    }
    a
}

/// Work space of the matrix products (no allocation per sample).
struct Scratch {
    m1: [f64; NA * NA],
    m2: [f64; NA * NA],
}

impl Default for Scratch {
    fn default() -> Self {
        Self {
            m1: [0.0; NA * NA],
            m2: [0.0; NA * NA],
        }
    }
}

/// c = a·b, NA × NA.
fn mul(a: &[f64; NA * NA], b: &[f64; NA * NA], c: &mut [f64; NA * NA]) {
    for i in 0..NA {
        let row = &mut c[i * NA..(i + 1) * NA];
        row.fill(0.0);
        for k in 0..NA {
            let aik = a[i * NA + k];
            if aik != 0.0 {
                for (cj, bj) in row.iter_mut().zip(&b[k * NA..(k + 1) * NA]) {
                    *cj += aik * bj;
                }
            }
        }
    }
}

/// Φ = I + hA + (hA)²/2 + (hA)³/6 + (hA)⁴/24, the order of the RK4 step the state takes.
fn taylor_transition(a: &[f64; NA * NA], h: f64, phi: &mut [f64; NA * NA], s: &mut Scratch) {
    let ha: [f64; NA * NA] = std::array::from_fn(|k| a[k] * h);
    // Horner: I + hA(I + hA/2(I + hA/3(I + hA/4))).
    let mut acc = [0.0; NA * NA];
    for k in 0..NA {
        acc[k * NA + k] = 1.0;
    }
    for order in (1..=4).rev() {
        mul(&ha, &acc, &mut s.m1);
        for (a, m) in acc.iter_mut().zip(&s.m1) {
            *a = m / order as f64;
        }
        for k in 0..NA {
            acc[k * NA + k] += 1.0;
        }
    }
    *phi = acc;
}

/// P ← Φ·P·Φᵀ.
fn propagate(phi: &[f64; NA * NA], cov: &mut [f64; NA * NA], s: &mut Scratch) {
    mul(phi, cov, &mut s.m1);
    // m2 = m1·Φᵀ
    for i in 0..NA {
        for j in 0..NA {
            s.m2[i * NA + j] = (0..NA).map(|k| s.m1[i * NA + k] * phi[j * NA + k]).sum();
        }
    }
    // Symmetric by construction; averaged so rounding cannot make it drift.
    for i in 0..NA {
        for j in 0..NA {
            cov[i * NA + j] = 0.5 * (s.m2[i * NA + j] + s.m2[j * NA + i]);
        }
    }
}

/// One Kalman update's results.
struct Update {
    /// L⁻¹·ν with S = L·Lᵀ: the innovation whitened.
    white: [f64; ROWS],
    /// K·ν over the filter's states.
    correction: [f64; NA],
    /// νᵀS⁻¹ν.
    quadratic: f64,
    /// ln det S.
    logdet: f64,
}

/// The Kalman update for innovation `nu` on the measured `rows` (of the full `h`, noise
/// `noise`): the correction, νᵀS⁻¹ν and ln det S, and P updated. None when S is
/// not positive definite.
fn kalman_update(
    h: &[[f64; NA]; ROWS],
    rows: &[usize],
    noise: &[f64; ROWS],
    nu: &[f64],
    cov: &mut [f64; NA * NA],
) -> Option<Update> {
    let p = rows.len();
    // PHᵀ (NA × p) and S = H·PHᵀ + R.
    let mut pht = [[0.0; ROWS]; NA];
    for i in 0..NA {
        for (r, &row) in rows.iter().enumerate() {
            pht[i][r] = (0..NA).map(|k| cov[i * NA + k] * h[row][k]).sum();
        }
    }
    let mut s = [[0.0; ROWS]; ROWS];
    for (a, &ra) in rows.iter().enumerate() {
        for b in 0..p {
            s[a][b] = (0..NA).map(|k| h[ra][k] * pht[k][b]).sum();
        }
        s[a][a] += noise[ra] * noise[ra];
    }
    // Cholesky S = LLᵀ.
    let mut l = [[0.0; ROWS]; ROWS];
    for j in 0..p {
        let dsum = s[j][j] - l[j][..j].iter().map(|v| v * v).sum::<f64>();
        if dsum.is_nan() || dsum <= 0.0 || !dsum.is_finite() {
            return None;
        }
        l[j][j] = dsum.sqrt();
        for i in j + 1..p {
            let v = s[i][j]
                - l[i][..j]
                    .iter()
                    .zip(&l[j][..j])
                    .map(|(a, b)| a * b)
                    .sum::<f64>();
            l[i][j] = v / l[j][j];
        }
    }
    let logdet = 2.0 * (0..p).map(|i| l[i][i].ln()).sum::<f64>();
    // S⁻¹ν by two triangular solves.
    // L⁻¹·b (forward) and L⁻ᵀ·z (backward): S⁻¹·b is both, L⁻¹·ν the innovation whitened.
    let forward = |b: &[f64]| -> [f64; ROWS] {
        let mut z = [0.0; ROWS];
        for i in 0..p {
            let v = b[i] - (0..i).map(|k| l[i][k] * z[k]).sum::<f64>();
            z[i] = v / l[i][i];
        }
        z
    };
    let backward = |z: &[f64; ROWS]| -> [f64; ROWS] {
        let mut out = [0.0; ROWS];
        for i in (0..p).rev() {
            let v = z[i] - (i + 1..p).map(|k| l[k][i] * out[k]).sum::<f64>();
            out[i] = v / l[i][i];
        }
        out
    };
    let solve = |b: &[f64]| backward(&forward(b));
    let white = forward(nu);
    let s_inv_nu = backward(&white);
    let quadratic = (0..p).map(|i| nu[i] * s_inv_nu[i]).sum();
    let mut correction = [0.0; NA];
    for (i, c) in correction.iter_mut().enumerate() {
        *c = (0..p).map(|r| pht[i][r] * s_inv_nu[r]).sum();
    }
    // K = PHᵀS⁻¹, row by row (each row of K solves S·kᵀ = (PHᵀ)ᵀ's row), and
    // P ← P − K·(PHᵀ)ᵀ, symmetrised (R is the measured noise, never near zero, so the short
    // form keeps P positive; Joseph's form would cost four times as much).
    let mut k = [[0.0; ROWS]; NA];
    for i in 0..NA {
        k[i] = solve(&pht[i][..p]);
    }
    let mut next = *cov;
    for i in 0..NA {
        for j in 0..=i {
            let v = 0.5
                * (0..p)
                    .map(|r| k[i][r] * pht[j][r] + k[j][r] * pht[i][r])
                    .sum::<f64>();
            next[i * NA + j] -= v;
            if i != j {
                next[j * NA + i] -= v;
            }
        }
    }
    *cov = next;
    Some(Update {
        white,
        correction,
        quadratic,
        logdet,
    })
}

/// The minimiser over `range` (searched in ln) of `f(ln v)`, by golden section.
fn golden(range: (f64, f64), mut f: impl FnMut(f64) -> f64) -> f64 {
    let found: Result<_, std::convert::Infallible> =
        super::golden_ln(range, GOLDEN_STEPS, |v| Ok(f(v)));
    found.map_or(range.0, |(v, _)| v)
}

/// 1σ of a likelihood's minimiser `at` (value `f0` there) from its curvature: central
/// differences 5 % either side.
fn curvature_se(at: f64, f0: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    let h = 0.05 * at.abs().max(1e-6);
    let c = (f(at + h) - 2.0 * f0 + f(at - h)) / (h * h);
    if c > 0.0 && c.is_finite() {
        1.0 / c.sqrt()
    } else {
        f64::INFINITY
    }
}
