//! What force or moment the model lacks, and the term that adds it (`wireflight discover`).
//!
//! The missing force and moment are read through the equations of motion at the measured
//! states: the measured body accelerations (the smoothing differentiator of the body velocity,
//! or the accelerometer's specific force where the flight has one) and angular accelerations,
//! less the model's at the same state and commands, times the mass and the inertia matrix.
//! The rates' coupling terms ω×Jω are the same in both and cancel: what is left is the force
//! (N) and moment (N·m) the model does not have, on each body axis. A point mass has no body:
//! its forces per unit mass are read along and across its flight path (`point_mass.rs`).
//!
//! The measured derivative is a smoothed one, so the model's accelerations and every regressor
//! pass through the same smoothing (the differentiator of their running integral), integrated
//! as the commands were held: from one sample to the next (docs/flight-data.md).
//!
//! Each axis is regressed on a library of candidate regressors ([`library`]) by forward
//! stepwise selection. The candidates are ranked by their held-out error over five contiguous
//! parts of the flight (fitted on four, the error on the fifth, summed): in closed loop a
//! correlate can remove as much over the whole flight as the true form, but its coefficient
//! does not carry from one part of the flight to another. The first is admitted when its
//! likelihood ratio, counted on the *effective* number of samples (the residuals are coloured
//! by the smoothing and by the model's error: n/(1 + 2Σρₖ) over the lags until the
//! autocorrelation first vanishes), passes χ²₁ at the Bonferroni level over every candidate of
//! every axis, when it removes a material share of what is left, and when it lowers the
//! held-out error on most of the five parts.
//!
//! Biases: the regressors are measured states, so their noise biases every coefficient toward
//! zero (errors in variables); the differentiator smooths over its window, so a force that
//! changes faster is attenuated; a wind the model lacks is read as force. The coefficient is
//! a start: the `add` spec names it as a free coefficient, fitted again by output error when
//! the term is added.

pub mod error_after;
pub mod library;
mod point_mass;

use wireflight_flight::expr::{Axis, Term, Var, VarValues, N_VARS};
use wireflight_flight::model::{Model, Vehicle};
use wireflight_flight::numeric::chi2_quantile;

use crate::identify::equation_error::EeSample;
use wireflight_data::derive::{Differentiator, Window};
use wireflight_data::{Channel, Controls, FlightData};
use wireflight_flight::model::State;

/// The family-wise false-alarm rate of the selection (split over every candidate of every axis).
pub const FALSE_ALARM: f64 = 0.01;
/// The least share of an axis's remaining sum of squares a term must remove.
pub const MATERIAL: f64 = 0.02;
/// The most terms admitted on one axis.
pub const MAX_TERMS_PER_AXIS: usize = 3;
/// At most this many samples enter the regression (evenly strided).
const MAX_SAMPLES: usize = 4000;
/// Contiguous parts of the flight for the validation.
const FOLDS: usize = 5;
/// Longest lag of the autocorrelation sum, samples.
const MAX_LAG: usize = 400;

/// Why no discovery could be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DiscoverError {
    /// The flight lacks what the equations of motion need.
    #[error(
        "the flight has too few usable samples ({0}): discover needs attitude, body velocity, \
         body rates and controls over at least {MIN_SAMPLES} samples"
    )]
    TooFewSamples(usize),
    /// A point mass's flight lacks what its equations of motion need.
    #[error(
        "the flight has too few usable samples ({0}): discover on a point mass needs position \
         and NED velocity over at least {MIN_SAMPLES} samples"
    )]
    TooFewPointMassSamples(usize),
}

/// The fewest samples a discovery is made from.
pub const MIN_SAMPLES: usize = 100;

/// One term found.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundTerm {
    /// The axis it acts on.
    pub axis: Axis,
    /// Its regressor's factors as the term language writes them.
    pub regressors: Vec<String>,
    /// The expression with a free coefficient (`k_l1*qbar*alpha*beta`).
    pub expression: String,
    /// The coefficient's name in `expression`.
    pub coefficient_name: String,
    /// The estimated coefficient, N or N·m per unit of the regressor.
    pub coefficient: f64,
    /// Its standard error (from the effective number of samples).
    pub sigma: f64,
    /// RMS of the axis's missing force or moment before this term (after the axis's earlier
    /// ones), N or N·m.
    pub rms_before: f64,
    /// And after it.
    pub rms_after: f64,
    /// The likelihood ratio of its admission.
    pub likelihood_ratio: f64,
    /// Held-out parts of the flight where it lowered the error, of `FOLDS`.
    pub folds_better: usize,
    /// A physical reading of it.
    pub reading: String,
    /// The `--add` spec that adds it: `term:AXIS=EXPR`.
    pub add: String,
    /// The comparison's error (× the noise) with this term and the terms listed before it
    /// added and fitted, when measured ([`error_after::measure_errors`]).
    pub error_after: Option<f64>,
}

/// One axis's missing force or moment.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisResidual {
    /// The axis.
    pub axis: Axis,
    /// RMS of what the model lacks, N or N·m.
    pub rms: f64,
    /// Its mean.
    pub mean: f64,
    /// RMS after the terms found on it.
    pub rms_after: f64,
    /// The effective number of samples (for the coloured residuals).
    pub effective_samples: f64,
}

/// What `discover` found.
#[derive(Clone, Debug, PartialEq)]
pub struct Discovery {
    /// The terms, best (largest likelihood ratio) first.
    pub terms: Vec<FoundTerm>,
    /// Each axis's missing force or moment.
    pub axes: Vec<AxisResidual>,
    /// Samples of the regression.
    pub samples: usize,
    /// Candidate regressors per axis.
    pub candidates: usize,
    /// The likelihood ratio a term must pass.
    pub threshold: f64,
    /// The comparison's error (× the noise) of the model as given, when measured
    /// ([`error_after::measure_errors`]).
    pub error_before: Option<f64>,
    /// Whether the model is a point mass: the forces per unit mass (m/s²) on its flight-path
    /// axes, or on the wind axes of a recorded body ([`Discovery::wind_axes`]).
    pub point_mass: bool,
    /// A point mass read on the wind axes of the body its flight recorded (every force term it
    /// takes acts on those axes), not on its flight-path axes.
    pub wind_axes: bool,
}

/// Finds the terms the model lacks on this flight (module docs).
///
/// A point mass is read on its flight-path axes, or on the wind axes of the body its flight
/// recorded, forces only (`point_mass.rs`).
///
/// # Errors
/// A flight without the channels the equations of motion need.
pub fn discover(model: &Model, data: &FlightData) -> Result<Discovery, DiscoverError> {
    let Vehicle::FixedWing(params) = &model.vehicle else {
        return point_mass::discover(model, data);
    };
    let Some(series) = series(model, params, data) else {
        return Err(DiscoverError::TooFewSamples(0));
    };
    let library = library::fixed_wing();
    let jm = &params.mass;
    let n_all = series.measured.len();
    let half = Window::default().half_samples(&data.time);
    if n_all <= 2 * half + MIN_SAMPLES {
        return Err(DiscoverError::TooFewSamples(n_all.saturating_sub(2 * half)));
    }
    // Everything through the same filter: the differentiator of the running integral, the
    // smoothing the measured derivative has (a measured acceleration is the smoothed one, and
    // so must the model's and the regressors' be, or a fast manoeuvre reads as a force).
    let diff = Differentiator::with_window(&data.time, Window::default());
    let smooth = |at_row: &[f64], held: &[f64]| -> Vec<f64> {
        diff.apply(&held_integral(&data.time, at_row, held))
    };
    // The rates are read continuously, so their derivative follows the commands as they were
    // held; the accelerometer reads each sample under that sample's commands, and its readings
    // are integrated as samples. The model and the regressors are integrated the way the
    // measurement of their axis was. Each acceleration the model lacks, smoothed once: the
    // differentiator's output is smoothed already, the accelerometer's readings less the
    // model's here.
    let read_as_samples = |c: usize| c < 3 && series.accelerometer;
    let channel = |rows: &[[f64; 6]], c: usize| -> Vec<f64> { rows.iter().map(|m| m[c]).collect() };
    let lacking: Vec<Vec<f64>> = (0..6)
        .map(|c| {
            let (measured, model) = (channel(&series.measured, c), channel(&series.model, c));
            if read_as_samples(c) {
                let d: Vec<f64> = measured.iter().zip(&model).map(|(a, b)| a - b).collect();
                smooth(&d, &d)
            } else {
                let model = smooth(&model, &channel(&series.model_held, c));
                measured.iter().zip(&model).map(|(a, b)| a - b).collect()
            }
        })
        .collect();
    // The rows: every sample whose smoothing window lies inside the flight, strided. Each
    // regressor is read at the row itself: the noise of the measured state enters the model's
    // acceleration there too, but its share of a smoothed regressor is small beside the
    // regressor's own excursions, and a regressor read anywhere else is attenuated where it
    // changes fast (read 0.4 s away, a yawing moment ∝ r·δt was taken for one ∝ q̄·q̂·r̂).
    let translation = match series.accelerometer {
        true => Channel::Accelerometer,
        false => Channel::Velocity,
    };
    let rows = regression_rows(data, half, &[Channel::Rates, translation]);
    let n = rows.len();
    let mass = jm.mass_kg;
    let mut targets: [Vec<f64>; 6] = std::array::from_fn(|_| Vec::with_capacity(n));
    for &i in &rows {
        let d: [f64; 6] = std::array::from_fn(|c| lacking[c][i]);
        // ΔM = J·Δω̇ with J = [[Jx, 0, −Jxz], [0, Jy, 0], [−Jxz, 0, Jz]].
        let missing = [
            mass * d[0],
            mass * d[1],
            mass * d[2],
            jm.jx * d[3] - jm.jxz * d[5],
            jm.jy * d[4],
            jm.jz * d[5] - jm.jxz * d[3],
        ];
        for (t, v) in targets.iter_mut().zip(missing) {
            t.push(v);
        }
    }
    // Each regressor smoothed as the moments' measurement is (commands held), and, with an
    // accelerometer, as its samples are, for the forces.
    let regressors = |as_samples: bool| -> Vec<Vec<f64>> {
        library
            .iter()
            .map(|r| {
                let at_row: Vec<f64> = series.vars.iter().map(|v| r.value(v)).collect();
                let sm = if as_samples {
                    smooth(&at_row, &at_row)
                } else {
                    let held: Vec<f64> = series.vars_held.iter().map(|v| r.value(v)).collect();
                    smooth(&at_row, &held)
                };
                rows.iter().map(|&i| sm[i]).collect()
            })
            .collect()
    };
    let held_columns = regressors(false);
    let sampled_columns = series.accelerometer.then(|| regressors(true));
    if targets
        .iter()
        .chain(&held_columns)
        .chain(sampled_columns.iter().flatten())
        .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(DiscoverError::TooFewSamples(0));
    }
    let axes: Vec<AxisTarget> = Axis::ALL
        .into_iter()
        .zip(targets)
        .enumerate()
        .map(|(c, (axis, y))| AxisTarget {
            axis,
            y,
            columns: match &sampled_columns {
                Some(sampled) if read_as_samples(c) => sampled,
                _ => &held_columns,
            },
        })
        .collect();
    Ok(select_terms(&axes, &library, library::reading, false))
}

/// One axis's missing force or moment at the rows, and the candidates' columns there.
struct AxisTarget<'a> {
    axis: Axis,
    y: Vec<f64>,
    columns: &'a [Vec<f64>],
}

/// The selection on every axis (Bonferroni over all of them), its terms best first.
fn select_terms(
    targets: &[AxisTarget<'_>],
    library: &[library::Regressor],
    reading: fn(Axis, &library::Regressor) -> String,
    point_mass: bool,
) -> Discovery {
    let n = targets.first().map_or(0, |t| t.y.len());
    let threshold = chi2_quantile(
        1.0 - FALSE_ALARM / (targets.len() * library.len()).max(1) as f64,
        1.0,
    );
    let mut terms = Vec::new();
    let mut axes = Vec::new();
    for AxisTarget { axis, y, columns } in targets {
        let axis = *axis;
        let sel = select(y, columns, threshold);
        let mean = y.iter().sum::<f64>() / n.max(1) as f64;
        axes.push(AxisResidual {
            axis,
            rms: rms(y),
            mean,
            rms_after: sel.rms_after,
            effective_samples: sel.effective_samples,
        });
        for (rank, step) in sel.steps.iter().enumerate() {
            let r = &library[step.column];
            let name = format!("k_{}{}", axis.name().to_lowercase(), rank + 1);
            let expression = r.expression(&name);
            // Every printed spec is one the term language takes as written.
            if Term::new(axis.name(), &expression).is_err() {
                continue;
            }
            terms.push(FoundTerm {
                axis,
                regressors: r.names(),
                add: format!("term:{}={}", axis.name(), expression),
                expression,
                coefficient_name: name,
                coefficient: sel.coefficients[rank],
                sigma: sel.sigmas[rank],
                rms_before: step.rms_before,
                rms_after: step.rms_after,
                likelihood_ratio: step.likelihood_ratio,
                folds_better: step.folds_better,
                reading: reading(axis, r),
                error_after: None,
            });
        }
    }
    terms.sort_by(|a, b| b.likelihood_ratio.total_cmp(&a.likelihood_ratio));
    Discovery {
        terms,
        axes,
        samples: n,
        candidates: library.len(),
        threshold,
        error_before: None,
        point_mass,
        wind_axes: false,
    }
}

/// The rows of the regression: every sample of the `measured` channels (their own samples,
/// where a channel has its own rate: a row filled in between is no measurement) whose
/// smoothing window (`half` samples each side) lies inside the flight, strided to at most
/// [`MAX_SAMPLES`].
fn regression_rows(data: &FlightData, half: usize, measured: &[Channel]) -> Vec<usize> {
    let inside: Vec<usize> = (half..data.len().saturating_sub(half))
        .filter(|&i| measured.iter().all(|&c| data.sampling.at(c, i)))
        .collect();
    let stride = (inside.len() / MAX_SAMPLES).max(1);
    inside.into_iter().step_by(stride).collect()
}

/// Every sample's measured accelerations (body velocity's derivative or the specific force;
/// angular), the model's at the same state, and the term language's variables.
struct Series {
    measured: Vec<[f64; 6]>,
    model: Vec<[f64; 6]>,
    /// The model's accelerations at each sample's state under the previous sample's commands:
    /// the end of the interval that leads to the sample, over which those commands were held
    /// (the first sample: under its own).
    model_held: Vec<[f64; 6]>,
    vars: Vec<VarValues>,
    /// The variables likewise under the previous sample's commands.
    vars_held: Vec<VarValues>,
    accelerometer: bool,
}

/// The [`Series`] of a flight; None without the channels or with a value not finite.
fn series(
    model: &Model,
    params: &wireflight_flight::params::FixedWingParams,
    d: &FlightData,
) -> Option<Series> {
    let (att, vb, rates, controls) = (
        d.attitude.as_ref()?,
        d.vel_body.as_ref()?,
        d.rates_body.as_ref()?,
        d.controls.as_ref()?,
    );
    let n = d.len();
    if n < MIN_SAMPLES || [att.len(), vb.len(), rates.len(), controls.len()] != [n; 4] {
        return None;
    }
    let diff = Differentiator::with_window(&d.time, Window::default());
    if diff.len() != n {
        return None;
    }
    let accel = d.accel_body.as_ref().filter(|a| a.len() == n);
    let dv = match accel {
        Some(a) => a.clone(),
        None => diff.apply_vec3(vb),
    };
    let dw = diff.apply_vec3(rates);
    let mut out = Series {
        measured: Vec::with_capacity(n),
        model: Vec::with_capacity(n),
        model_held: Vec::with_capacity(n),
        vars: Vec::with_capacity(n),
        vars_held: Vec::with_capacity(n),
        accelerometer: accel.is_some(),
    };
    for i in 0..n {
        let measured = [dv[i].x, dv[i].y, dv[i].z, dw[i].x, dw[i].y, dw[i].z];
        let sample = |commands: &Controls| EeSample {
            t: d.time[i],
            state: State::measured(d.pos_ned[i], vb[i], att[i], rates[i], commands),
            controls: *commands,
            measured,
            accelerometer: accel.is_some(),
        };
        let own = sample(&controls[i]);
        let held = sample(&controls[i.saturating_sub(1)]);
        let (m, m_held) = (own.modelled(model), held.modelled(model));
        let (vars, vars_held) = (
            variables(model, params, &own),
            variables(model, params, &held),
        );
        let all = [&measured[..], &m, &m_held, &vars, &vars_held];
        if !all.iter().all(|x| x.iter().all(|v| v.is_finite())) {
            return None;
        }
        out.measured.push(measured);
        out.model.push(m);
        out.model_held.push(m_held);
        out.vars.push(vars);
        out.vars_held.push(vars_held);
    }
    Some(out)
}

/// The running trapezoid integral over time (0 at the first sample) of a quantity that reads
/// the commands: `at_row[i]` is it at sample i under sample i's commands, `held[i]` at sample
/// i under sample i − 1's.
///
/// The commands are held from one sample to the next (docs/flight-data.md): over the interval
/// from sample i − 1 to i the quantity follows sample i − 1's commands, from `at_row[i − 1]`
/// to `held[i]`. A trapezoid of `at_row` alone would ramp each command's step over the
/// interval before it, half a sample early, and through the smoothing read as a force
/// wherever a command jumps (a throttle step, an autopilot's aileron).
fn held_integral(time: &[f64], at_row: &[f64], held: &[f64]) -> Vec<f64> {
    let n = time.len().min(at_row.len()).min(held.len());
    let mut out = Vec::with_capacity(n);
    let mut acc = 0.0;
    for i in 0..n {
        if i > 0 {
            acc += 0.5 * (at_row[i - 1] + held[i]) * (time[i] - time[i - 1]);
        }
        out.push(acc);
    }
    out
}

/// The term language's variables at a sample, as the model sees them.
fn variables(
    model: &Model,
    params: &wireflight_flight::params::FixedWingParams,
    s: &EeSample,
) -> VarValues {
    let air = model.air_data(s.t, &s.state);
    let ctl = model.surfaces_in_effect(&s.state, &s.controls);
    let omega = s.state.omega();
    let va = air.airspeed;
    let (half_b, half_c) = if va > 0.1 {
        (
            params.geometry.b / (2.0 * va),
            params.geometry.c / (2.0 * va),
        )
    } else {
        (0.0, 0.0)
    };
    let prop = &params.propulsion;
    let k = prop.k_motor * s.controls.throttle;
    let mut v = [0.0; N_VARS];
    v[Var::Alpha.index()] = air.alpha;
    v[Var::Beta.index()] = air.beta;
    v[Var::PHat.index()] = omega.x * half_b;
    v[Var::QHat.index()] = omega.y * half_c;
    v[Var::RHat.index()] = omega.z * half_b;
    v[Var::P.index()] = omega.x;
    v[Var::Q.index()] = omega.y;
    v[Var::R.index()] = omega.z;
    v[Var::Elevator.index()] = ctl.elevator;
    v[Var::Aileron.index()] = ctl.aileron;
    v[Var::Rudder.index()] = ctl.rudder;
    v[Var::Throttle.index()] = s.controls.throttle;
    v[Var::Thrust.index()] = 0.5 * air.rho * prop.s_prop * prop.c_prop * (k * k - va * va);
    v[Var::Airspeed.index()] = va;
    v[Var::Qbar.index()] = 0.5 * air.rho * va * va;
    v[Var::Rho.index()] = air.rho;
    v[Var::Height.index()] = -s.state.pos_ned().z;
    v[Var::G.index()] = wireflight_data::G0;
    v
}

fn rms(y: &[f64]) -> f64 {
    (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt()
}

/// One admitted step of the selection on an axis.
struct Step {
    column: usize,
    rms_before: f64,
    rms_after: f64,
    likelihood_ratio: f64,
    folds_better: usize,
}

/// The selection on one axis.
struct Selection {
    steps: Vec<Step>,
    coefficients: Vec<f64>,
    sigmas: Vec<f64>,
    rms_after: f64,
    effective_samples: f64,
}

/// The effective number of samples of a residual series: n/(1 + 2Σρₖ), the sum over the lags
/// until the autocorrelation first falls to zero (at most [`MAX_LAG`]).
fn effective_samples(r: &[f64]) -> f64 {
    let n = r.len();
    let c0: f64 = r.iter().map(|v| v * v).sum();
    if n < 2 || c0 <= 0.0 {
        return n as f64;
    }
    let mut tau = 1.0;
    for lag in 1..MAX_LAG.min(n - 1) {
        let c: f64 = r[lag..].iter().zip(r).map(|(a, b)| a * b).sum();
        let rho = c / c0;
        if rho <= 0.0 {
            break;
        }
        tau += 2.0 * rho;
    }
    (n as f64 / tau).max(1.0)
}

/// Least squares of `y` on the chosen columns: the coefficients and the covariance's diagonal
/// without the residual variance; None when singular.
fn least_squares(
    y: &[f64],
    columns: &[Vec<f64>],
    chosen: &[usize],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let k = chosen.len();
    let mut a = vec![0.0; k * k];
    let mut b = vec![0.0; k];
    for (i, &yi) in y.iter().enumerate() {
        for (r, &cr) in chosen.iter().enumerate() {
            let xr = columns[cr][i];
            b[r] += xr * yi;
            for (c, &cc) in chosen.iter().enumerate() {
                a[r * k + c] += xr * columns[cc][i];
            }
        }
    }
    let inv = invert(&a, k)?;
    let coef: Vec<f64> = (0..k)
        .map(|r| (0..k).map(|c| inv[r * k + c] * b[c]).sum())
        .collect();
    let diag = (0..k).map(|r| inv[r * k + r]).collect();
    Some((coef, diag))
}

/// Gauss–Jordan inverse of a small symmetric matrix; None when (nearly) singular.
fn invert(a: &[f64], k: usize) -> Option<Vec<f64>> {
    let mut m = a.to_vec();
    let mut inv = vec![0.0; k * k];
    for i in 0..k {
        inv[i * k + i] = 1.0;
    }
    let scale = (0..k).map(|i| a[i * k + i].abs()).fold(0.0, f64::max);
    for col in 0..k {
        let piv =
            (col..k).max_by(|&x, &y| m[x * k + col].abs().total_cmp(&m[y * k + col].abs()))?;
        if m[piv * k + col].abs() <= 1e-12 * scale || !scale.is_finite() {
            return None;
        }
        for j in 0..k {
            m.swap(col * k + j, piv * k + j);
            inv.swap(col * k + j, piv * k + j);
        }
        let p = m[col * k + col];
        for j in 0..k {
            m[col * k + j] /= p;
            inv[col * k + j] /= p;
        }
        for r in 0..k {
            if r != col {
                let f = m[r * k + col];
                if f != 0.0 {
                    for j in 0..k {
                        m[r * k + j] -= f * m[col * k + j];
                        inv[r * k + j] -= f * inv[col * k + j];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// The most columns one held-out fit carries: the chosen ones and a candidate.
const MAX_FIT: usize = MAX_TERMS_PER_AXIS + 1;

/// Each contiguous part's held-out squared error: `y` fitted on `set`'s columns over the other
/// parts, and the fit's error summed over the part. The sums are gathered in one pass, part by
/// part, and each part's fit is made from the other parts' sums. None when a fit is singular.
fn held_out_errors(
    y: &[f64],
    columns: &[Option<Vec<f64>>],
    set: &[usize],
    fold_of: impl Fn(usize) -> usize,
) -> Option<[f64; FOLDS]> {
    let k = set.len();
    if k > MAX_FIT {
        return None;
    }
    let mut cols: [&[f64]; MAX_FIT] = [&[]; MAX_FIT];
    for (slot, &c) in cols.iter_mut().zip(set) {
        *slot = columns.get(c)?.as_deref().filter(|x| x.len() == y.len())?;
    }
    // Per part: XᵀX, Xᵀy and yᵀy over its samples.
    let mut xx = [[[0.0; MAX_FIT]; MAX_FIT]; FOLDS];
    let mut xy = [[0.0; MAX_FIT]; FOLDS];
    let mut yy = [0.0; FOLDS];
    for (i, &yi) in y.iter().enumerate() {
        let f = fold_of(i).min(FOLDS - 1);
        yy[f] += yi * yi;
        let x: [f64; MAX_FIT] = std::array::from_fn(|r| if r < k { cols[r][i] } else { 0.0 });
        for (r, &xr) in x.iter().enumerate() {
            xy[f][r] += xr * yi;
            for (c, &xc) in x.iter().enumerate() {
                xx[f][r][c] += xr * xc;
            }
        }
    }
    let mut out = [0.0; FOLDS];
    for (f, err) in out.iter_mut().enumerate() {
        // The other parts' sums (the rows and columns past k stay 0).
        let mut a = [[0.0; MAX_FIT]; MAX_FIT];
        let mut b = [0.0; MAX_FIT];
        for g in (0..FOLDS).filter(|&g| g != f) {
            for (ar, xr) in a.iter_mut().zip(&xx[g]) {
                ar.iter_mut().zip(xr).for_each(|(av, xv)| *av += xv);
            }
            b.iter_mut().zip(&xy[g]).for_each(|(bv, xv)| *bv += xv);
        }
        let beta = solve_small(a, b, k)?;
        // Σ (y − xβ)² over the part = yᵀy − 2βᵀXᵀy + βᵀXᵀXβ.
        let mut e = yy[f];
        for ((br, xyr), xxr) in beta.iter().zip(&xy[f]).zip(&xx[f]) {
            e -= 2.0 * br * xyr;
            e += br * xxr.iter().zip(&beta).map(|(m, bc)| m * bc).sum::<f64>();
        }
        *err = e.max(0.0);
    }
    Some(out)
}

/// Solve the k×k system a·x = b (Gaussian elimination with partial pivoting); None when
/// (nearly) singular.
fn solve_small(
    mut a: [[f64; MAX_FIT]; MAX_FIT],
    mut b: [f64; MAX_FIT],
    k: usize,
) -> Option<[f64; MAX_FIT]> {
    let scale = (0..k).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    if !scale.is_finite() {
        return None;
    }
    for col in 0..k {
        let piv = (col..k).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        let (pivot, pivot_b) = (a[col], b[col]);
        for r in col + 1..k {
            let f = a[r][col] / pivot[col];
            a[r][col..k]
                .iter_mut()
                .zip(&pivot[col..k])
                .for_each(|(v, p)| *v -= f * p);
            b[r] -= f * pivot_b;
        }
    }
    let mut x = [0.0; MAX_FIT];
    for r in (0..k).rev() {
        let s: f64 = (r + 1..k).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Forward stepwise selection on one axis (module docs).
///
/// Each step ranks the candidates by their held-out error: fitted (with the terms already
/// chosen) on four of the five contiguous parts of the flight, how far the fit misses on the
/// fifth, summed over the five. In closed loop several regressors follow one another (the
/// rudder follows β, the throttle the airspeed), and over the whole flight a correlate can
/// remove as much as the true form; the held-out error prefers the form whose coefficient
/// carries from one part of the flight to another — the form with the right structure across
/// conditions. The candidate so ranked first is then admitted or not on the whole flight.
fn select(y: &[f64], columns: &[Vec<f64>], threshold: f64) -> Selection {
    let n = y.len();
    // Columns divided by their RMS: the reduction a candidate brings is then a plain
    // projection, whatever its units.
    let unit: Vec<Option<Vec<f64>>> = columns
        .iter()
        .map(|c| {
            let s = rms(c);
            (s > 0.0 && s.is_finite()).then(|| c.iter().map(|v| v / s).collect())
        })
        .collect();
    // An orthonormal basis of the chosen columns, and the residual after them.
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut resid = y.to_vec();
    let mut chosen: Vec<usize> = Vec::with_capacity(MAX_FIT);
    let mut steps = Vec::new();
    let fold_of = |i: usize| (i * FOLDS / n).min(FOLDS - 1);
    let mut x = vec![0.0; n];
    for _ in 0..MAX_TERMS_PER_AXIS {
        let rss: f64 = resid.iter().map(|v| v * v).sum();
        if rss <= 0.0 || !rss.is_finite() {
            break;
        }
        let Some(without) = held_out_errors(y, &unit, &chosen, fold_of) else {
            break;
        };
        // The candidate with the least held-out error, and its error in each part.
        let mut best: Option<(usize, f64, [f64; FOLDS])> = None;
        for (j, col) in unit.iter().enumerate() {
            let Some(col) = col else { continue };
            if chosen.contains(&j) {
                continue;
            }
            // A column (almost) inside the chosen ones adds nothing new.
            x.copy_from_slice(col);
            let xx = orthogonalise(&mut x, &basis);
            if xx <= 1e-8 * n as f64 || !xx.is_finite() {
                continue;
            }
            chosen.push(j);
            let errors = held_out_errors(y, &unit, &chosen, fold_of);
            chosen.pop();
            let Some(errors) = errors else { continue };
            let total: f64 = errors.iter().sum();
            if best.as_ref().is_none_or(|b| total < b.1) {
                best = Some((j, total, errors));
            }
        }
        let Some((j, _, with)) = best else { break };
        let Some(col) = &unit[j] else { break };
        let mut q = col.clone();
        let xx = orthogonalise(&mut q, &basis);
        let norm = xx.sqrt();
        q.iter_mut().for_each(|v| *v /= norm);
        let d: f64 = q.iter().zip(&resid).map(|(a, b)| a * b).sum();
        let gain = d * d;
        let rss_after = (rss - gain).max(0.0);
        let after: Vec<f64> = resid.iter().zip(&q).map(|(r, b)| r - d * b).collect();
        let n_eff = effective_samples(&after);
        let lr = if rss_after > 0.0 {
            n_eff * (rss / rss_after).ln()
        } else {
            f64::INFINITY
        };
        let material = gain >= MATERIAL * rss;
        let folds_better = with.iter().zip(&without).filter(|(a, b)| a < b).count();
        if !(lr > threshold && material && 2 * folds_better > FOLDS) {
            break;
        }
        steps.push(Step {
            column: j,
            rms_before: (rss / n as f64).sqrt(),
            rms_after: (rss_after / n as f64).sqrt(),
            likelihood_ratio: lr,
            folds_better,
        });
        chosen.push(j);
        basis.push(q);
        resid = after;
    }
    let effective = effective_samples(&resid);
    let rss: f64 = resid.iter().map(|v| v * v).sum();
    let (coefficients, sigmas) = match least_squares(y, columns, &chosen) {
        Some((c, diag)) if !chosen.is_empty() => {
            // σ² from the residual variance over the effective samples: (XᵀX)⁻¹·RSS/n_eff
            // is the white-noise value inflated by n/n_eff for the colour.
            let var = rss / (effective - chosen.len() as f64).max(1.0);
            let s = diag.iter().map(|d| (d * var).sqrt());
            (c, s.collect())
        }
        _ => (Vec::new(), Vec::new()),
    };
    if coefficients.len() != steps.len() {
        steps.clear();
    }
    Selection {
        steps,
        coefficients,
        sigmas,
        rms_after: (rss / n as f64).sqrt(),
        effective_samples: effective,
    }
}

/// Remove from `x` its projection on the orthonormal `basis`; its squared norm after.
fn orthogonalise(x: &mut [f64], basis: &[Vec<f64>]) -> f64 {
    for q in basis {
        let d: f64 = x.iter().zip(q).map(|(a, b)| a * b).sum();
        x.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
    }
    x.iter().map(|v| v * v).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` uniform numbers in ±0.5 (xorshift from `seed`).
    fn uniform_noise(n: usize, seed: u64) -> Vec<f64> {
        let mut x = seed;
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x as f64 / u64::MAX as f64) - 0.5
            })
            .collect()
    }

    #[test]
    fn white_noise_has_as_many_effective_samples_as_samples_and_a_smooth_series_fewer() {
        let white = uniform_noise(2000, 12345);
        assert!(effective_samples(&white) > 1500.0);
        let smooth: Vec<f64> = (0..2000).map(|i| (i as f64 * 0.01).sin()).collect();
        assert!(effective_samples(&smooth) < 200.0);
    }

    #[test]
    fn a_command_step_is_integrated_from_the_sample_it_is_held_from() {
        // The quantity is 0 under the first command and 1 under the second, which is held
        // from sample 1: nothing accrues over the first interval.
        let time = [0.0, 1.0, 2.0, 3.0];
        let at_row = [0.0, 1.0, 1.0, 1.0];
        let held = [0.0, 0.0, 1.0, 1.0];
        assert_eq!(
            held_integral(&time, &at_row, &held),
            vec![0.0, 0.0, 1.0, 2.0]
        );
    }

    #[test]
    fn the_held_out_errors_are_each_parts_error_of_the_fit_on_the_others() {
        let n = 500;
        let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.05).sin()).collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.031).cos() + 0.3).collect();
        let noise = uniform_noise(n, 7);
        let y: Vec<f64> = (0..n).map(|i| 2.0 * a[i] - b[i] + noise[i]).collect();
        let fold_of = |i: usize| (i * FOLDS / n).min(FOLDS - 1);
        let cols = vec![Some(a.clone()), Some(b.clone())];
        let errors = held_out_errors(&y, &cols, &[0, 1], fold_of).expect("regular");
        for (f, e) in errors.iter().enumerate() {
            // The fit on the other parts, the long way.
            let (mut aa, mut ab, mut bb, mut ay, mut by) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for i in (0..n).filter(|&i| fold_of(i) != f) {
                aa += a[i] * a[i];
                ab += a[i] * b[i];
                bb += b[i] * b[i];
                ay += a[i] * y[i];
                by += b[i] * y[i];
            }
            let det = aa * bb - ab * ab;
            let (ka, kb) = ((bb * ay - ab * by) / det, (aa * by - ab * ay) / det);
            let direct: f64 = (0..n)
                .filter(|&i| fold_of(i) == f)
                .map(|i| (y[i] - ka * a[i] - kb * b[i]).powi(2))
                .sum();
            assert!(
                (e - direct).abs() <= 1e-9 * direct.max(1.0),
                "{f}: {e} vs {direct}"
            );
        }
    }

    /// A power effect: the moment is t·g, g rising by half in the last part of the flight.
    /// Its regressor is read with noise; a correlate that rises by a fifth there is read
    /// without. Over the whole flight the correlate removes more (98.96% against 98.75%), but
    /// its coefficient does not carry into the last part, and the selection takes the truth.
    #[test]
    fn the_selection_prefers_the_form_that_holds_in_every_part_of_the_flight() {
        let n = 1000;
        let last = |i: usize| i * FOLDS / n == FOLDS - 1;
        let t: Vec<f64> = (0..n).map(|i| (i as f64 * 0.07).sin()).collect();
        let (noise, read_noise) = (uniform_noise(n, 3), uniform_noise(n, 11));
        let truth = |i: usize| t[i] * if last(i) { 1.5 } else { 1.0 };
        let y: Vec<f64> = (0..n).map(|i| truth(i) + 0.05 * noise[i]).collect();
        let read: Vec<f64> = (0..n).map(|i| truth(i) + 0.3 * read_noise[i]).collect();
        let correlate: Vec<f64> = (0..n)
            .map(|i| t[i] * if last(i) { 1.2 } else { 1.0 })
            .collect();
        let removes = |c: &[f64]| {
            let cy: f64 = c.iter().zip(&y).map(|(a, b)| a * b).sum();
            cy * cy / c.iter().map(|v| v * v).sum::<f64>()
        };
        assert!(
            removes(&correlate) > removes(&read),
            "the correlate removes more in all"
        );
        let thr = chi2_quantile(1.0 - 0.01 / 12.0, 1.0);
        let s = select(&y, &[correlate, read], thr);
        assert_eq!(s.steps.first().map(|s| s.column), Some(1));
    }

    #[test]
    fn the_selection_finds_the_one_column_in_the_data_and_nothing_in_noise() {
        let n = 1000;
        let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.05).sin()).collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.031).cos()).collect();
        let noise = uniform_noise(n, 99);
        let y: Vec<f64> = (0..n).map(|i| 3.0 * b[i] + 0.1 * noise[i]).collect();
        let cols = vec![a.clone(), b.clone()];
        let thr = chi2_quantile(1.0 - 0.01 / 12.0, 1.0);
        let s = select(&y, &cols, thr);
        assert_eq!(s.steps.len(), 1);
        assert_eq!(s.steps[0].column, 1);
        assert!((s.coefficients[0] - 3.0).abs() < 0.01);
        let s = select(&noise, &cols, thr);
        assert!(s.steps.is_empty());
    }
}
