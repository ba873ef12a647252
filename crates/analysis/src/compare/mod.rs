//! Model vs measurements by **multiple shooting with estimated start states**.
//!
//! The flight is cut into windows of `window_s` seconds. In each, the model flies open loop on
//! the recorded commands (zero-order hold) from a start state, and its prediction is compared
//! with the measurements sample by sample. Restarting bounds the growth of unstable modes, so
//! the metric works for stable and divergent dynamics alike.
//!
//! **Start states** are fitted, not read off ([`start`]): warm-started from short quadratic
//! fits, then chosen by Levenberg–Marquardt to minimise the noise-weighted misfit of the
//! model's own prediction to every measured channel over the window. A window that starts in
//! a transient then costs nothing: with the right model the prediction lies on the data, and
//! what is left is measurement noise. Windows are independent and fitted in parallel.
//!
//! **Noise** is measured from the data without the model ([`noise`]): robust fourth-order
//! differences, so manoeuvres are not counted as noise. Each residual is weighted by its
//! channel's noise deviation (never less than [`SIGMA_MIN`]), so the weighted misfit per
//! residual, χ²/ν, is 1 for a right model: [`Comparison::noise_units`] is its root, the error
//! in units of the noise.
//!
//! **Error metric** for people: per window and channel, the RMS of the prediction error —
//! position (m, length of the error vector), NED velocity (m/s), attitude (degrees, the angle
//! of the rotation between the two attitudes), body rates (deg/s) — over the measured
//! channels (derived ones, e.g. velocities differentiated from positions, are not
//! measurements). The **total** is the RMS over channels and windows in units of 1 m, 1 m/s,
//! 1° and 1°/s. The **noise floor** is the total a right model would leave on data with the
//! measured noise ([`noise::expected_channel_errors`]). [`Comparison::axes`] splits the error
//! per axis (signed mean and RMS) to say where it is.

mod attitude;
pub mod noise;
pub mod predict;
mod rows;
mod score;
mod sensitivity;
mod sensors;
pub mod start;

use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use attitude::attitude_error_at;
pub use noise::{combined, estimate_noise, expected_channel_errors, NoiseEstimate};
pub use predict::{controls_at, surfaces_at, Predicted, SurfaceTracker};
use score::{assemble, assemble_as};
use start::{Scratch, StartFit};

use wireflight_data::{unwrap_angles, FlightData};
use wireflight_flight::effects::Channel;
use wireflight_flight::model::{AirData, Model, State, Vehicle};
use wireflight_geometry::euler::EulerZyx;

/// Smallest noise deviation a channel is weighted with: position m, velocity m/s, attitude
/// rad, rates rad/s, airspeed m/s. Noise-free data would otherwise get infinite weights.
pub const SIGMA_MIN: [f64; 6] = [1e-3, 1e-3, 1e-5, 1e-5, 1e-3, 1e-4];

/// Settings of a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareConfig {
    /// Window length, s.
    pub window_s: f64,
    /// Span at each window start of the quadratic warm start, s.
    pub fit_s: f64,
    /// Longest integration step, s.
    pub max_dt: f64,
    /// Use at most this many windows, evenly spread (0 = all).
    pub max_windows: usize,
    /// The first window starts this long after the first sample, s.
    pub offset_s: f64,
    /// Fit each start over the first `span` seconds of its window instead of the whole
    /// window (for a model with a fast unstable mode, where a whole window is
    /// ill-conditioned).
    pub start_span_s: Option<f64>,
    /// Levenberg–Marquardt iterations of each start fit (0: keep the warm start).
    pub start_iterations: usize,
    /// The model's own error per axis, measured on reference flights
    /// ([`crate::reference`]): residuals are weighted by noise and it together. None: by the
    /// measured noise alone.
    pub model_error: Option<NoiseEstimate>,
    /// The least variance factor of each residual row's sum ([`colour_factor`]), where the
    /// flight's errors are known to wander longer than its residuals show (measured on
    /// synthetic flights with them: [`crate::error_floor`]). None: the residuals' own.
    pub colour_floor: Option<[f64; MAX_ROWS]>,
}

impl CompareConfig {
    /// The window length that suits a vehicle, s. A fixed wing: 8 s, a few periods of its
    /// short-period and roll modes but short enough that an unstable spiral or phugoid cannot
    /// run away. A point mass: 60 s (in practice, the whole flight): it has no unstable mode,
    /// and slow effects (drag on a long fall, the Earth's rotation and curvature) need tens of
    /// seconds to show.
    pub fn default_window_s(vehicle: wireflight_data::VehicleKind) -> f64 {
        match vehicle {
            wireflight_data::VehicleKind::FixedWing => 8.0,
            wireflight_data::VehicleKind::PointMass => 60.0,
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
            offset_s: 0.0,
            start_span_s: None,
            start_iterations: 8,
            model_error: None,
            colour_floor: None,
        }
    }
}

/// Which channels of the data are measurements (not derived from others).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Measured {
    /// NED velocity.
    pub velocity: bool,
    /// Attitude angles.
    pub attitude: bool,
    /// Body rates.
    pub rates: bool,
    /// Airspeed.
    pub airspeed: bool,
    /// Accelerometer (specific force, body axes).
    pub accel: bool,
}

impl Measured {
    /// The measured channels of a flight.
    pub fn of(d: &FlightData) -> Self {
        Self {
            velocity: d.vel_ned.is_some() && !d.is_derived("vel_ned"),
            attitude: d.attitude.is_some(),
            rates: d.rates_body.is_some() && !d.is_derived("rates_body"),
            airspeed: d.airspeed.is_some(),
            accel: d.accel_body.is_some(),
        }
    }

    /// Whether `data` (these channels' flight) records `channel` as a measurement the
    /// comparison scores (not derived from another channel).
    pub fn records(self, channel: Channel, data: &FlightData) -> bool {
        match channel {
            Channel::Position => true,
            Channel::Velocity => self.velocity && data.vel_ned.is_some(),
            Channel::Attitude => self.attitude && data.attitude.is_some(),
            Channel::Rates => self.rates && data.rates_body.is_some(),
            Channel::Airspeed => self.airspeed && data.airspeed.is_some(),
            Channel::Accelerometer => self.accel && data.accel_body.is_some(),
        }
    }

    /// The channels a model of this vehicle is scored on (a point mass has no attitude).
    pub fn for_vehicle(self, model: &Model) -> Self {
        match model.vehicle {
            Vehicle::PointMass => Self {
                attitude: false,
                rates: false,
                airspeed: false,
                accel: false,
                ..self
            },
            Vehicle::FixedWing(_) => self,
        }
    }
}

/// RMS errors per channel (None where the data do not measure the channel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelErrors {
    /// Position, m.
    pub position_m: f64,
    /// NED velocity, m/s.
    pub velocity_mps: Option<f64>,
    /// Attitude, degrees.
    pub attitude_deg: Option<f64>,
    /// Body rates, degrees/s.
    pub rate_dps: Option<f64>,
}

impl ChannelErrors {
    /// Combined score: RMS of the channels in units of 1 m, 1 m/s, 1°, 1°/s.
    pub fn score(&self) -> f64 {
        let mut sum = self.position_m.powi(2);
        let mut k = 1.0;
        for v in [self.velocity_mps, self.attitude_deg, self.rate_dps]
            .into_iter()
            .flatten()
        {
            sum += v * v;
            k += 1.0;
        }
        (sum / k).sqrt()
    }

    /// The channel with the largest normalised error.
    pub fn dominant(&self) -> &'static str {
        let mut best = ("position", self.position_m);
        for (name, v) in [
            ("velocity", self.velocity_mps),
            ("attitude", self.attitude_deg),
            ("rates", self.rate_dps),
        ] {
            if let Some(v) = v {
                if v > best.1 {
                    best = (name, v);
                }
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
    /// The fitted start state.
    pub start: State,
    /// Noise-weighted squared misfit of the window, Σ r².
    pub chi2: f64,
    /// Number of weighted residuals.
    pub residuals: usize,
    /// Σ r_k·r_k+1 over consecutive samples of each residual channel: with `chi2`, the lag-1
    /// autocorrelation of the residuals (0 when they are white noise).
    pub lag1_product: f64,
    /// Sums for each residual row of a sample on its own ([`AxisSums`]).
    pub axes: AxisSums,
}

/// Most residual rows a sample has: position, velocity, attitude and rates (3 each),
/// airspeed, accelerometer (3).
pub const MAX_ROWS: usize = 16;

/// Sums over the residuals of each row of a sample on its own (the rows: the axes of
/// position, velocity, attitude, rates, airspeed and accelerometer, of the channels the data
/// score, in that order): where one channel's residuals wander and another's are white,
/// pooling them would hide the wandering.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisSums {
    /// Σ r² per row.
    pub chi2: [f64; MAX_ROWS],
    /// Σ r_k·r_k+1 per row.
    pub lag1: [f64; MAX_ROWS],
    /// Σ r_k·r_k+L per row, L = [`LAG_FAR`].
    pub lag_far: [f64; MAX_ROWS],
    /// Σ r per row.
    pub sum: [f64; MAX_ROWS],
    /// The residuals of each row.
    pub count: [f64; MAX_ROWS],
}

/// The longer lag of [`AxisSums::lag_far`], samples.
pub const LAG_FAR: usize = 10;

/// The variance factor of a sum of `n` residuals whose lag-1 and lag-L ([`LAG_FAR`])
/// autocorrelations are `rho1` and `rho_far`: an AR(1) process of coefficient φ with white
/// noise on it (share 1 − c), whose autocorrelation at lag k is c·φᵏ. φ comes from the ratio of
/// the two lags, so white noise on a wandering error does not pass for a shorter memory (from
/// lag 1 alone, 5% of white variance on an error of 5 s at 50 Hz halves the factor); the
/// factor is (1 − c) + c·(1 + φ)/(1 − φ). A correlation within three standard errors of 0
/// (3/√n) is taken as none: the ratio of two such would make white residuals read as a long
/// memory. At least 1; φ at most 0.9999.
pub fn ar1_factor(rho1: f64, rho_far: f64, n: f64) -> f64 {
    let seen = 3.0 / n.max(1.0).sqrt();
    if rho1.is_nan() || rho1 <= seen {
        return 1.0;
    }
    let rho1 = rho1.min(0.9999);
    if rho_far.is_nan() || rho_far <= seen {
        return (1.0 + rho1) / (1.0 - rho1);
    }
    let phi = (rho_far / rho1)
        .powf(1.0 / (LAG_FAR as f64 - 1.0))
        .clamp(rho1, 0.9999);
    let c = (rho1 / phi).min(1.0);
    ((1.0 - c) + c * (1.0 + phi) / (1.0 - phi)).max(1.0)
}

impl AxisSums {
    fn add(mut self, other: &Self) -> Self {
        for j in 0..MAX_ROWS {
            self.chi2[j] += other.chi2[j];
            self.lag1[j] += other.lag1[j];
            self.lag_far[j] += other.lag_far[j];
            self.sum[j] += other.sum[j];
            self.count[j] += other.count[j];
        }
        self
    }
}

/// How much a misfit reduction from `before` to `after` overstates the evidence because the
/// residuals are correlated in time. Where the flight's errors are stated to wander
/// ([`Comparison::wanders`]): the variance factor of each residual row after
/// ([`ar1_factor`] of its autocorrelations), averaged with the weights of what each
/// row's misfit fell. A reduction in rows whose residuals wander counts for as little as their
/// wandering allows, one in white rows fully, whatever the other rows do; pooling ρ over all
/// rows instead lets white rows dilute it. Each row's factor is at least its
/// [`Comparison::colour_floor`]. Where nothing fell, the rows are weighed by their misfit.
/// Otherwise the pooled lag-1 factor (1 + ρ)/(1 − ρ), ρ at most 0.99. At least 1.
pub fn colour_factor(before: &Comparison, after: &Comparison) -> f64 {
    if !after.wanders() {
        // No stated wandering errors: the residuals' colour is mostly the model's own
        // smooth error, which the windows' scatter (the cluster sandwich) measures; the
        // pooled lag-1 factor stands for the rest.
        let rho = after.residual_autocorrelation().clamp(0.0, 0.99);
        return (1.0 + rho) / (1.0 - rho);
    }
    let (b, a) = (before.axis_sums(), after.axis_sums());
    let factor = |j: usize| {
        let own = if a.chi2[j] > 0.0 {
            ar1_factor(a.lag1[j] / a.chi2[j], a.lag_far[j] / a.chi2[j], a.count[j])
        } else {
            1.0
        };
        own.max(after.colour_floor[j])
    };
    let (mut fell, mut weighed) = (0.0, 0.0);
    for j in 0..MAX_ROWS {
        let d = (b.chi2[j] - a.chi2[j]).max(0.0);
        fell += d;
        weighed += d * factor(j);
    }
    if fell > 0.0 {
        return (weighed / fell).max(1.0);
    }
    // Nothing fell: each row as much as its misfit.
    let total: f64 = a.chi2.iter().sum();
    if total > 0.0 {
        let weighed: f64 = (0..MAX_ROWS).map(|j| a.chi2[j] * factor(j)).sum();
        (weighed / total).max(1.0)
    } else {
        1.0
    }
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
    /// Predicted body rates, rad/s; zero for a point mass.
    pub rates: Vec<DVec3>,
    /// Predicted airspeed, α, β; zero for a point mass.
    pub air: Vec<AirData>,
    /// Predicted accelerometer reading (specific force, body axes), m/s²; zero where the
    /// data have no accelerometer.
    pub specific_force: Vec<DVec3>,
}

impl Prediction {
    /// Room for `n` samples: an hour's predictions are tens of megabytes, not to be copied
    /// as they grow.
    fn with_capacity(n: usize) -> Self {
        Self {
            index: Vec::with_capacity(n),
            pos_ned: Vec::with_capacity(n),
            vel_ned: Vec::with_capacity(n),
            attitude: Vec::with_capacity(n),
            rates: Vec::with_capacity(n),
            air: Vec::with_capacity(n),
            specific_force: Vec::with_capacity(n),
        }
    }

    /// Append a prediction whose air data are `air` (taken apart: α and β cost two inverse
    /// trigonometric functions per sample, and an hour's are taken in parallel).
    fn push(&mut self, i: usize, p: &Predicted, air: AirData) {
        self.index.push(i);
        self.pos_ned.push(p.pos_ned);
        self.vel_ned.push(p.vel_ned);
        self.attitude.push(p.attitude());
        self.rates.push(p.rates);
        self.air.push(air);
        self.specific_force.push(p.specific_force);
    }
}

/// The error along one axis of one channel over the compared samples.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisError {
    /// Channel, e.g. "position".
    pub channel: &'static str,
    /// Axis, e.g. "north".
    pub axis: &'static str,
    /// Unit of the values.
    pub unit: &'static str,
    /// Mean of predicted − measured (a bias), in `unit`.
    pub mean: f64,
    /// RMS of predicted − measured, in `unit`.
    pub rms: f64,
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
    /// Per-axis errors (position N/E/D, velocity N/E/D, roll/pitch/yaw, p/q/r, airspeed, α,
    /// β), for the channels measured.
    pub axes: Vec<AxisError>,
    /// Noise-weighted misfit Σ r² over all windows.
    pub chi2: f64,
    /// Degrees of freedom: residuals minus fitted start parameters.
    pub dof: f64,
    /// The least variance factor of each residual row ([`CompareConfig::colour_floor`]; 1
    /// where none was given).
    pub colour_floor: [f64; MAX_ROWS],
}

impl Comparison {
    /// Windows sorted worst first.
    pub fn worst_windows(&self) -> Vec<&WindowResult> {
        let mut w: Vec<&WindowResult> = self.windows.iter().collect();
        w.sort_by(|a, b| b.score.total_cmp(&a.score));
        w
    }

    /// The error in units of the measurement noise, √(χ²/ν): about 1 for a right model.
    pub fn noise_units(&self) -> f64 {
        (self.chi2 / self.dof.max(1.0)).sqrt()
    }

    /// Lag-1 autocorrelation of the weighted residuals in time, pooled over channels and
    /// windows: near 0 when what is left is white measurement noise, near 1 when it is a
    /// smooth error of the model.
    pub fn residual_autocorrelation(&self) -> f64 {
        let p: f64 = self.windows.iter().map(|w| w.lag1_product).sum();
        if self.chi2 > 0.0 {
            (p / self.chi2).clamp(-1.0, 1.0)
        } else {
            0.0
        }
    }

    /// The number of independent residuals the misfit is worth: ν·(1 − ρ)/(1 + ρ) for
    /// lag-1 autocorrelation ρ (an AR(1) approximation; at least 1).
    pub fn independent_residuals(&self) -> f64 {
        let rho = self.residual_autocorrelation().max(0.0);
        (self.dof * (1.0 - rho) / (1.0 + rho)).max(1.0)
    }

    /// Whether the flight's errors were stated to wander ([`CompareConfig::colour_floor`]).
    pub fn wanders(&self) -> bool {
        self.colour_floor.iter().any(|&f| f > 1.0)
    }

    /// [`AxisSums`] over all windows.
    pub fn axis_sums(&self) -> AxisSums {
        self.windows
            .iter()
            .fold(AxisSums::default(), |acc, w| acc.add(&w.axes))
    }

    /// The fitted start states, one per window (to warm-start another comparison).
    pub fn starts(&self) -> Vec<State> {
        self.windows.iter().map(|w| w.start).collect()
    }
}

/// Everything precomputed once per data set and reused across model evaluations.
pub struct Prepared<'a> {
    /// The data.
    pub data: &'a FlightData,
    /// Attitude angles unwrapped per axis (yaw, pitch, roll), rad.
    unwrapped: Option<[Vec<f64>; 3]>,
    /// Sines and cosines of the measured attitude per sample (roll, pitch, yaw; empty
    /// without attitude): the attitude residuals are taken from them and the predicted
    /// rotation ([`attitude_residuals`]). Shared with the screening subset.
    attitude_trig: Arc<[[f64; 6]]>,
    /// Window sample ranges.
    pub windows: Vec<(usize, usize)>,
    /// The residuals' standard deviations per axis: the measurement noise, or with reference
    /// flights noise and the model's own error together ([`CompareConfig::model_error`]).
    pub noise: NoiseEstimate,
    /// The measurement noise alone, as estimated from the data.
    pub measured_noise: NoiseEstimate,
    /// The measured channels.
    pub measured: Measured,
    /// Weights of the residuals: 1/σ per axis of position, velocity, attitude (roll, pitch,
    /// yaw), rates, and airspeed.
    weights: [[f64; 3]; 4],
    airspeed_weight: f64,
    /// 1/σ per axis of the accelerometer.
    pub(crate) accel_weights: [f64; 3],
    cfg: CompareConfig,
}

/// Cut `n` samples at `time` into windows of `window_s` starting `offset_s` after the first
/// sample; a trailing stub shorter than half a window joins the window before it.
pub(crate) fn cut_windows(time: &[f64], cfg: &CompareConfig) -> Vec<(usize, usize)> {
    let n = time.len();
    let mut windows: Vec<(usize, usize)> = Vec::new();
    if n < 3 || cfg.window_s.is_nan() || cfg.window_s <= 0.0 {
        return windows;
    }
    let mut start = time.partition_point(|&t| t < time[0] + cfg.offset_s.max(0.0));
    while start + 2 < n {
        let t_end = time[start] + cfg.window_s;
        let end = time.partition_point(|&t| t < t_end).max(start + 2).min(n);
        if time[end - 1] - time[start] < 0.5 * cfg.window_s {
            if let Some(last) = windows.last_mut() {
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
    windows
}

impl<'a> Prepared<'a> {
    /// Cut the data into windows, estimate the noise, and precompute what every evaluation
    /// needs.
    pub fn new(data: &'a FlightData, cfg: CompareConfig) -> Self {
        let ((unwrapped, attitude_trig), noise) = rayon::join(
            || {
                let unwrapped = data.attitude.as_ref().map(|att| {
                    [
                        unwrap_angles(&att.iter().map(|e| e.yaw).collect::<Vec<_>>()),
                        unwrap_angles(&att.iter().map(|e| e.pitch).collect::<Vec<_>>()),
                        unwrap_angles(&att.iter().map(|e| e.roll).collect::<Vec<_>>()),
                    ]
                });
                let trig: Arc<[[f64; 6]]> = match &data.attitude {
                    Some(att) => att
                        .par_iter()
                        .map(|e| {
                            let ((sr, cr), (sp, cp), (sy, cy)) =
                                (e.roll.sin_cos(), e.pitch.sin_cos(), e.yaw.sin_cos());
                            [sr, cr, sp, cp, sy, cy]
                        })
                        .collect(),
                    None => Arc::new([]),
                };
                (unwrapped, trig)
            },
            || estimate_noise(data),
        );
        let measured_noise = noise;
        let noise = match &cfg.model_error {
            Some(e) => combined(&noise, e),
            None => noise,
        };
        let w = |s: [f64; 3], min: f64| s.map(|v| 1.0 / v.max(min));
        let weights = [
            w(noise.pos_axes, SIGMA_MIN[0]),
            w(noise.vel_axes, SIGMA_MIN[1]),
            w(noise.att_axes, SIGMA_MIN[2]),
            w(noise.rate_axes, SIGMA_MIN[3]),
        ];
        Self {
            data,
            unwrapped,
            attitude_trig,
            windows: cut_windows(&data.time, &cfg),
            noise,
            measured_noise,
            measured: Measured::of(data),
            weights,
            airspeed_weight: 1.0 / noise.airspeed_mps.max(SIGMA_MIN[4]),
            accel_weights: w(noise.accel_axes, SIGMA_MIN[5]),
            cfg,
        }
    }

    /// The settings.
    pub fn config(&self) -> CompareConfig {
        self.cfg
    }

    /// The same data prepared with at most `max_windows` windows, evenly spread (0: all),
    /// without estimating the noise again: the subset a diagnosis screens candidates on.
    pub fn with_max_windows(&self, max_windows: usize) -> Self {
        let cfg = CompareConfig {
            max_windows,
            ..self.cfg
        };
        Self {
            data: self.data,
            unwrapped: self.unwrapped.clone(),
            attitude_trig: Arc::clone(&self.attitude_trig),
            windows: cut_windows(&self.data.time, &cfg),
            noise: self.noise,
            measured_noise: self.measured_noise,
            measured: self.measured,
            weights: self.weights,
            airspeed_weight: self.airspeed_weight,
            accel_weights: self.accel_weights,
            cfg,
        }
    }
}

/// One window compared: its result, its predictions and (when asked for) its start fit.
struct WindowOutcome {
    result: WindowResult,
    predicted: Vec<Predicted>,
    fit: Option<StartFit>,
}

/// Compare one window, its start fitted from `x_start` (beginning with `jacobian` when given:
/// [`Prepared::fit_start_with`]).
fn compare_window(
    model: &Model,
    prep: &Prepared,
    window: (usize, usize),
    x_start: State,
    jacobian: Option<&[f64]>,
    keep_fit: bool,
) -> WindowOutcome {
    let mut scratch = Scratch::default();
    let fit = (prep.cfg.start_iterations > 0)
        .then(|| prep.fit_start_with(model, window, x_start, jacobian, &mut scratch));
    let x0 = fit.as_ref().map_or(x_start, |f| f.state);
    let mut rows = Vec::new();
    match &fit {
        // The fit flew this start over the whole window last: its residuals and predictions.
        Some(f)
            if prep.fit_range(window) == window
                && scratch.accepted.len() == window.1 - window.0 =>
        {
            rows.clone_from(&f.residuals);
            scratch.predicted = std::mem::take(&mut scratch.accepted);
        }
        _ => prep.window_residuals(model, window, &x0, &mut scratch, &mut rows),
    }
    let chi2: f64 = rows.iter().map(|r| r * r).sum();
    let (residuals, lag1_product, axes) = prep.measured_rows(model, window, &rows);
    let errors = window_errors(model, prep, window, &scratch.predicted);
    WindowOutcome {
        result: WindowResult {
            t0: prep.data.time[window.0],
            t1: prep.data.time[window.1 - 1],
            samples: window,
            score: errors.score(),
            errors,
            start: x0,
            chi2,
            residuals,
            lag1_product,
            axes,
        },
        predicted: std::mem::take(&mut scratch.predicted),
        fit: if keep_fit { fit } else { None },
    }
}

/// The RMS errors of one window's predictions `predicted` (one per sample), each channel over
/// its own samples.
fn window_errors(
    model: &Model,
    prep: &Prepared,
    (start, end): (usize, usize),
    predicted: &[Predicted],
) -> ChannelErrors {
    let d = prep.data;
    let m = prep.measured.for_vehicle(model);
    let on = |channel: Channel, i: usize| d.sampling.at(channel, i);
    let mut sums = [(0.0, 0.0); 4];
    let mut add = |k: usize, e2: f64| {
        sums[k].0 += e2;
        sums[k].1 += 1.0;
    };
    for (p, i) in predicted.iter().zip(start..end) {
        if on(Channel::Position, i) {
            add(0, (p.pos_ned - d.pos_ned[i]).length_squared());
        }
        if let (true, Some(v), true) = (m.velocity, &d.vel_ned, on(Channel::Velocity, i)) {
            add(1, (p.vel_ned - v[i]).length_squared());
        }
        if let (true, Some(a), true) = (m.attitude, &d.attitude, on(Channel::Attitude, i)) {
            add(
                2,
                attitude_error_at(p, &a[i], prep.attitude_trig.get(i)).powi(2),
            );
        }
        if let (true, Some(w), true) = (m.rates, &d.rates_body, on(Channel::Rates, i)) {
            add(3, (p.rates - w[i]).length_squared());
        }
    }
    let rms = |(s, n): (f64, f64)| (s / n.max(1.0)).sqrt();
    ChannelErrors {
        position_m: rms(sums[0]),
        velocity_mps: m.velocity.then(|| rms(sums[1])),
        attitude_deg: m.attitude.then(|| rms(sums[2])),
        rate_dps: m.rates.then(|| rms(sums[3]).to_degrees()),
    }
}

/// Compare a model with prepared data, fitting every window's start from its warm start.
pub fn compare_prepared(model: &Model, prep: &Prepared) -> Comparison {
    compare_from(model, prep, None)
}

/// Compare a model with prepared data, fitting every window's start from `starts` (one per
/// window, e.g. another model's fitted starts; surfaces are recomputed for this model) or,
/// without them, from the warm start.
pub fn compare_from(model: &Model, prep: &Prepared, starts: Option<&[State]>) -> Comparison {
    compare_windows(model, prep, starts, &[], false).0
}

/// [`compare_from`], each window's fit beginning with `jacobians[k]` instead of a fresh
/// Jacobian: another model's on that window (the baseline's, for the baseline with an effect
/// that has nothing to fit), kept current by Broyden's updates ([`Prepared::fit_start_with`]).
pub fn compare_from_jacobians(
    model: &Model,
    prep: &Prepared,
    starts: &[State],
    jacobians: &[&[f64]],
) -> Comparison {
    compare_windows(model, prep, Some(starts), jacobians, false).0
}

/// [`compare_from`], also returning each window's start fit (its Jacobian with respect to the
/// start state: for fitting model parameters with the starts projected out). Memory grows with
/// the windows (samples × channels × 12 numbers each): for a subset of windows.
pub fn compare_with_fits(
    model: &Model,
    prep: &Prepared,
    starts: Option<&[State]>,
) -> (Comparison, Vec<StartFit>) {
    compare_windows(model, prep, starts, &[], true)
}

/// [`compare_with_fits`] from the starts and start Jacobians of linearised windows (`starts[k]`
/// and `jacobians[k]` for window k, e.g. the last fit's, moved to new parameters): each fit
/// begins with its window's Jacobian ([`Prepared::fit_start_with`]) instead of a fresh one.
pub fn compare_refit(
    model: &Model,
    prep: &Prepared,
    starts: &[State],
    jacobians: &[&[f64]],
) -> (Comparison, Vec<StartFit>) {
    compare_windows(model, prep, Some(starts), jacobians, true)
}

fn compare_windows(
    model: &Model,
    prep: &Prepared,
    starts: Option<&[State]>,
    jacobians: &[&[f64]],
    keep_fits: bool,
) -> (Comparison, Vec<StartFit>) {
    let mut tracker = SurfaceTracker::new(model, prep.data);
    let initial: Vec<State> = prep
        .windows
        .iter()
        .enumerate()
        .map(|(k, &w)| {
            let surfaces = tracker.at(w.0);
            match starts.and_then(|s| s.get(k)) {
                Some(x) => {
                    let mut x = *x;
                    x.set_surfaces(surfaces);
                    x
                }
                None => prep.warm_start(model, w, surfaces),
            }
        })
        .collect();
    let outcomes: Vec<WindowOutcome> = prep
        .windows
        .par_iter()
        .zip(initial.par_iter())
        .enumerate()
        .map(|(k, (&w, x))| {
            let jacobian = jacobians.get(k).copied().filter(|j| !j.is_empty());
            compare_window(model, prep, w, *x, jacobian, keep_fits)
        })
        .collect();
    let mut outcomes = outcomes;
    let fits = outcomes.iter_mut().filter_map(|o| o.fit.take()).collect();
    (assemble(model, prep, outcomes), fits)
}

/// Compare corrections of a model (`candidates`) and the model itself (`base`) in one pass
/// over the windows. In each window every candidate's start is fitted from the warm start
/// (with a fresh Jacobian), and `then(k, window, fit)` runs on candidate k's start fit
/// (Jacobian included) while it exists — nothing per window outlives its pass — returning
/// what the caller keeps and, optionally, start parameters predicted for `base` from that
/// fit ([`params_of`](start::params_of)'s). The base's start is then fitted from the first
/// prediction, or from the warm start without one.
///
/// Candidates go first because a model that explains the data has its start near the
/// data's (the warm start), while the base (lacking what they add) is pulled away from it
/// to make up for what it lacks; from a prediction the base's fit takes less than half the
/// flights it takes from the warm start (on the hour benchmark's missing wind: 2.5 flights
/// and 1.3 tangents a window instead of 6 and 2.2, to the same misfit).
///
/// Returns the base's comparison, and each candidate's with what `then` returned per
/// window: its windows, errors, total and misfit, without the per-sample prediction and
/// per-axis errors (a diagnosis reports the base model's).
pub fn compare_corrections<T: Send>(
    base: &Model,
    candidates: &[&Model],
    prep: &Prepared,
    then: impl Fn(usize, (usize, usize), &StartFit) -> (T, Option<Vec<f64>>) + Sync,
) -> (Comparison, Vec<(Comparison, Vec<T>)>) {
    // Surfaces at each window start, per model (its actuator lag, if any); the base's last.
    let surfaces: Vec<Vec<DVec3>> = candidates
        .iter()
        .chain([&base])
        .map(|m| {
            let mut tracker = SurfaceTracker::new(m, prep.data);
            prep.windows.iter().map(|w| tracker.at(w.0)).collect()
        })
        .collect();
    let nc = candidates.len();
    let per_window: Vec<(WindowOutcome, Vec<(WindowOutcome, T)>)> = prep
        .windows
        .par_iter()
        .enumerate()
        .map(|(i, &w)| {
            let mut out = Vec::with_capacity(nc);
            let mut predicted: Option<State> = None;
            for (k, m) in candidates.iter().enumerate() {
                let x = prep.warm_start(m, w, surfaces[k][i]);
                let mut o = compare_window(m, prep, w, x, None, true);
                // Not assembled in detail (below): its predictions are not kept.
                o.predicted = Vec::new();
                let fit = o.fit.take();
                let (extra, start) = match &fit {
                    Some(f) => then(k, w, f),
                    None => then(k, w, &StartFit::unfitted(o.result.start)),
                };
                if predicted.is_none() {
                    predicted = start
                        .filter(|q| q.len() == start::param_count(base))
                        .map(|q| start::state_of(base, &q, surfaces[nc][i]))
                        .filter(State::is_finite);
                }
                out.push((o, extra));
            }
            let x = predicted.unwrap_or_else(|| prep.warm_start(base, w, surfaces[nc][i]));
            (compare_window(base, prep, w, x, None, false), out)
        })
        .collect();
    let mut base_outcomes = Vec::with_capacity(per_window.len());
    let mut by_model: Vec<(Vec<WindowOutcome>, Vec<T>)> = candidates
        .iter()
        .map(|_| (Vec::new(), Vec::new()))
        .collect();
    for (b, window) in per_window {
        base_outcomes.push(b);
        for (k, (o, t)) in window.into_iter().enumerate() {
            by_model[k].0.push(o);
            by_model[k].1.push(t);
        }
    }
    let (base_cmp, cmps) = rayon::join(
        || assemble(base, prep, base_outcomes),
        || {
            candidates
                .par_iter()
                .zip(by_model)
                .map(|(m, (outcomes, extras))| (assemble_as(m, prep, outcomes, false), extras))
                .collect()
        },
    );
    (base_cmp, cmps)
}

/// Compare a model with flight data.
pub fn compare(model: &Model, data: &FlightData, cfg: CompareConfig) -> Comparison {
    compare_prepared(model, &Prepared::new(data, cfg))
}

/// The total a right model would leave on this data: the expected channel errors of the
/// measured noise ([`noise::expected_channel_errors`]) over the channels the comparison
/// scores, combined like [`ChannelErrors::score`].
pub fn noise_floor(model: &Model, prep: &Prepared) -> f64 {
    let m = prep.measured.for_vehicle(model);
    let [pos, vel, att, rate] = expected_channel_errors(&prep.noise);
    ChannelErrors {
        position_m: pos,
        velocity_mps: m.velocity.then_some(vel),
        attitude_deg: m.attitude.then_some(att),
        rate_dps: m.rates.then_some(rate),
    }
    .score()
}

#[cfg(test)]
mod tests {
    use super::*;
    use wireflight_data::VehicleKind;
    use wireflight_flight::autopilot::Manoeuvre;
    use wireflight_flight::effects::Origin;
    use wireflight_flight::simulate::{simulate, Noise, SimSpec};
    use wireflight_flight::spec::ModelSpec;

    /// The lag-1 and lag-L autocorrelations and the count of a series.
    fn autocorrelations(y: &[f64]) -> (f64, f64, f64) {
        let chi2: f64 = y.iter().map(|v| v * v).sum();
        let lag = |k: usize| y.iter().zip(&y[k..]).map(|(a, b)| a * b).sum::<f64>() / chi2;
        (lag(1), lag(LAG_FAR), y.len() as f64)
    }

    /// The variance of the mean of `y` over that of white residuals, measured: the mean of
    /// each of `blocks` blocks, their spread against the samples'.
    fn measured_factor(y: &[f64], blocks: usize) -> f64 {
        let n = y.len() / blocks;
        let var = y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64;
        let means: Vec<f64> = y
            .chunks_exact(n)
            .map(|c| c.iter().sum::<f64>() / n as f64)
            .collect();
        let var_mean = means.iter().map(|m| m * m).sum::<f64>() / means.len() as f64;
        n as f64 * var_mean / var
    }

    /// White residuals read 1; a wandering error read through 5% of white noise reads what a
    /// sum of it varies by (from lag 1 alone it would read half); tiny correlations of white
    /// residuals are not taken for a long memory.
    #[test]
    fn the_colour_factor_is_what_a_sum_of_the_residuals_varies_by() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let white: Vec<f64> = (0..200_000).map(|_| unit.sample(&mut rng)).collect();
        let (r1, rf, n) = autocorrelations(&white);
        assert_eq!(ar1_factor(r1, rf, n), 1.0, "{r1} {rf}");
        // A Gauss–Markov error of τ = 2.5 s at 50 Hz (φ = 0.992) with white noise of 5% of
        // its variance on it.
        let phi: f64 = 0.992;
        let mut x = 0.0;
        let y: Vec<f64> = (0..400_000)
            .map(|_| {
                x = phi * x + (1.0 - phi * phi).sqrt() * unit.sample(&mut rng);
                x + 0.05f64.sqrt() * unit.sample(&mut rng)
            })
            .collect();
        let (r1, rf, n) = autocorrelations(&y);
        let f = ar1_factor(r1, rf, n);
        let truth = measured_factor(&y, 200);
        assert!((f / truth - 1.0).abs() < 0.3, "factor {f} against {truth}");
        let lag1_only = (1.0 + r1) / (1.0 - r1);
        assert!(lag1_only < 0.7 * truth, "{lag1_only} against {truth}");
        // Correlations within three standard errors of zero are none.
        assert_eq!(ar1_factor(0.005, 0.007, 2000.0), 1.0);
        assert!(ar1_factor(f64::NAN, 0.5, 100.0) == 1.0);
    }

    /// The screening subset taken from prepared data is the data prepared with that many
    /// windows: the same windows, noise and weights, without estimating the noise again.
    #[test]
    fn a_subset_of_prepared_data_is_the_data_prepared_with_fewer_windows() {
        let model = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let spec = SimSpec {
            noise: Noise {
                pos_m: 0.5,
                att_deg: 0.3,
                vel_mps: 0.1,
                rate_dps: 0.5,
            },
            ..SimSpec::new(Manoeuvre::FlightTest, 90.0)
        };
        let data = simulate(&model, &spec).unwrap();
        let cfg = CompareConfig::default();
        let full = Prepared::new(&data, cfg);
        for max in [0, 3, 5, 100] {
            let subset = full.with_max_windows(max);
            let direct = Prepared::new(
                &data,
                CompareConfig {
                    max_windows: max,
                    ..cfg
                },
            );
            assert_eq!(subset.windows, direct.windows, "{max}");
            assert_eq!(subset.noise, direct.noise);
            assert_eq!(subset.weights, direct.weights);
            assert_eq!(subset.unwrapped, direct.unwrapped);
            assert_eq!(subset.config(), direct.config());
        }
        assert_eq!(full.with_max_windows(3).windows.len(), 3);
    }
}
