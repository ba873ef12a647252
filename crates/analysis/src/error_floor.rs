//! The floor a log's wandering errors leave: stated sensor errors, flown through the model.
//!
//! A real log's position, velocity and attitude come out of a navigation filter whose errors
//! wander (seconds to minutes), and its instruments drift. The data's own noise estimate sees
//! only their white part ([`crate::compare::noise`]): against it a right model reads tens or
//! hundreds of "× the noise", and a diagnosis can only end `unexplained`. Where the errors are
//! consistent with the IMU the filter fused (an EKF's), nothing in the log can tell them from
//! a slow disturbance of the flight; what can be said is how much error errors *like these*
//! leave on a right model, and that is what is measured here.
//!
//! **How.** The model as given is compared with the flight as usual; its prediction — each
//! window flown from its fitted start on the recorded commands — stands for a flight the
//! model gets exactly right. Each draw adds the stated errors
//! ([`wireflight_flight::sensor_errors::SensorErrors::apply`], its own seed) to that path at
//! every sample, then white noise per axis up to the flight's own white noise (the part the
//! stated errors' white noise does not already make), and keeps the flight's own sampling:
//! a synthetic flight whose only difference from the model is errors like the log's. On the
//! draws, the model's error beyond their white noise is measured per axis exactly as on
//! reference flights ([`crate::reference::model_floor`]) and scaled so that the draws read 1
//! on average; the flight is then weighed by its own noise and that error together. How far
//! above 1 a right model can read is measured too, on draws the floor was not measured on (each
//! half against the other half's floor): "at the floor" reaches to their mean plus twice their
//! spread (at least the diagnosis's own `at_floor`), because errors that wander for a minute
//! leave few independent samples in a flight and scatter the total. The draws also give each
//! residual row's colour for a sum over the whole flight ([`ErrorFloor::colour`]), which the
//! likelihood ratios and ± take as the least they allow for.
//!
//! The draws' seeds are mixed from one fixed seed (SplitMix64), not consecutive, so that no
//! two draws share structure through their seeds.
//!
//! The floor holds for errors like the stated ones, in kind and size: it cannot tell a log
//! whose errors are twice as large from a model that is wrong. Flights of the same aircraft
//! believed normal measure both together ([`crate::reference`]).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;

use crate::compare::estimate_noise;
use crate::compare::{
    compare, compare_prepared, AxisSums, CompareConfig, Comparison, NoiseEstimate, Prepared,
    MAX_ROWS,
};
use crate::reference::{model_floor, ModelFloor};
use glam::DVec3;
use wireflight_data::FlightData;
use wireflight_flight::model::Model;
use wireflight_flight::numeric::chi2_quantile;
use wireflight_flight::sensor_errors::SensorErrors;
use wireflight_geometry::euler::EulerZyx;

/// Draws of the stated errors a floor is measured on, unless asked otherwise.
pub const DRAWS: usize = 16;
/// The seed the draws' seeds are mixed from: a floor is the same at every run.
pub const SEED: u64 = 0x5eed_f100;

/// The floor stated sensor errors leave on a right model of one flight (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorFloor {
    /// The stated errors' model (`independent`, `ekf-gnss`).
    pub errors: &'static str,
    /// The flight's own (white) measurement noise.
    pub measured_noise: NoiseEstimate,
    /// The model's error on the draws beyond their white noise, per axis: the weights add it
    /// to the flight's own noise.
    pub model_error: NoiseEstimate,
    /// Each draw's error in units of a floor measured on the other draws (about 1).
    pub draws: Vec<f64>,
    /// Each residual row's variance factor for a misfit the same all flight long
    /// ([`crate::compare::colour_factor`]): Σ over the draws of (Σ r)² over Σ r². Errors that
    /// wander longer than the windows correlate the windows too, which no residual's own
    /// autocorrelation within a window shows.
    pub colour: [f64; MAX_ROWS],
    /// A flight's error is "at the floor" up to this many units of it.
    pub at_floor: f64,
}

impl ErrorFloor {
    /// The lowest and highest draw, in units of the floor.
    pub fn draw_range(&self) -> (f64, f64) {
        self.draws
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &u| {
                (lo.min(u), hi.max(u))
            })
    }
}

/// The floor `errors` leave on `model` flown along `data` (module docs), measured on `draws`
/// synthetic flights whose seeds are mixed from `seed`; "at the floor" reaches at least
/// `at_floor`. None when the flight is too short for one window or `draws` is 0.
///
/// A draw is made again each time it is needed (its seed makes it the same) rather than
/// kept: sixteen copies of an hour's flight would be a gigabyte.
pub fn error_floor(
    model: &Model,
    data: &FlightData,
    errors: &SensorErrors,
    cfg: CompareConfig,
    at_floor: f64,
    draws: usize,
    seed: u64,
) -> Option<ErrorFloor> {
    let maker = DrawMaker::new(model, data, errors, cfg, seed)?;
    // Each draw's own floor: the pooled one and each half's are averages of these.
    let floors: Vec<ModelFloor> = (0..draws as u64)
        .into_par_iter()
        .map(|k| {
            let d = maker.draw(k);
            model_floor(model, &[("draw", &d)], cfg).ok()
        })
        .collect::<Option<_>>()?;
    if floors.is_empty() {
        return None;
    }
    let all: Vec<usize> = (0..floors.len()).collect();
    let pooled = pooled_floor(&floors, &all);
    let first: Vec<(f64, AxisSums)> = maker.compared(&all, pooled);
    let colour = colour_of_sums(&first);
    let first = first.iter().map(|(u, _)| u).sum::<f64>() / first.len() as f64;
    if !(first > 0.0 && first.is_finite()) {
        return None;
    }
    // The per-axis errors pooled over the draws read a little off 1 together (the channels'
    // shares differ between the RMS errors and the weighted misfit): each axis's total
    // deviation is scaled by that.
    let measured_noise = estimate_noise(data);
    let model_error = rescaled(&pooled, &measured_noise, first);
    // How far a right model's error strays is measured on draws the floor was not measured
    // on: each half against the other half's floor (scaled alike). A draw against a floor
    // fitted to it reads closer to 1 than a flight does.
    let half = floors.len() / 2;
    let units: Vec<f64> = if half >= 2 {
        let (a, b): (Vec<usize>, Vec<usize>) = all.iter().partition(|&&k| k < half);
        let held_out = |on: &[usize], from: &[usize]| -> Vec<f64> {
            let e = rescaled(&pooled_floor(&floors, from), &measured_noise, first);
            maker.compared(on, e).into_iter().map(|(u, _)| u).collect()
        };
        let mut units = held_out(&a, &b);
        units.extend(held_out(&b, &a));
        units
    } else {
        maker
            .compared(&all, model_error)
            .into_iter()
            .map(|(u, _)| u)
            .collect()
    };
    let n = units.len() as f64;
    let mean = units.iter().sum::<f64>() / n;
    let spread = if units.len() > 1 {
        (units.iter().map(|u| (u - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let reach = mean + 2.0 * spread;
    Some(ErrorFloor {
        errors: errors.name(),
        measured_noise,
        model_error,
        draws: units,
        colour,
        at_floor: if reach.is_finite() {
            reach.max(at_floor)
        } else {
            at_floor
        },
    })
}

/// The model's error of the draws `which`, from each draw's own: per axis the mean square
/// over their samples ([`model_floor`]'s pooling of several references).
fn pooled_floor(floors: &[ModelFloor], which: &[usize]) -> NoiseEstimate {
    let total: f64 = which.iter().map(|&k| floors[k].samples as f64).sum();
    let pool = |get: &dyn Fn(&NoiseEstimate) -> f64| -> f64 {
        let sum: f64 = which
            .iter()
            .map(|&k| floors[k].samples as f64 * get(&floors[k].model_error).powi(2))
            .sum();
        (sum / total.max(1.0)).sqrt()
    };
    let three = |get: &dyn Fn(&NoiseEstimate) -> [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| pool(&|e| get(e)[i]))
    };
    NoiseEstimate {
        pos_axes: three(&|e| e.pos_axes),
        vel_axes: three(&|e| e.vel_axes),
        att_axes: three(&|e| e.att_axes),
        rate_axes: three(&|e| e.rate_axes),
        accel_axes: three(&|e| e.accel_axes),
        airspeed_mps: pool(&|e| e.airspeed_mps),
        ..NoiseEstimate::default()
    }
    .with_rms()
}

/// The model error `e` that, added to the noise `white`, makes each axis's total deviation
/// `by` times what it was: √(by²·(σ²_white + σ²_e) − σ²_white) per axis.
fn rescaled(e: &NoiseEstimate, white: &NoiseEstimate, by: f64) -> NoiseEstimate {
    let one = |e: f64, w: f64| (by * by * (w * w + e * e) - w * w).max(0.0).sqrt();
    let three = |e: [f64; 3], w: [f64; 3]| std::array::from_fn(|k| one(e[k], w[k]));
    NoiseEstimate {
        pos_axes: three(e.pos_axes, white.pos_axes),
        vel_axes: three(e.vel_axes, white.vel_axes),
        att_axes: three(e.att_axes, white.att_axes),
        rate_axes: three(e.rate_axes, white.rate_axes),
        accel_axes: three(e.accel_axes, white.accel_axes),
        airspeed_mps: one(e.airspeed_mps, white.airspeed_mps),
        ..NoiseEstimate::default()
    }
    .with_rms()
}

/// Makes the draws of one flight (module docs): the model's path once, then each draw from
/// it on demand.
struct DrawMaker<'a> {
    model: &'a Model,
    errors: &'a SensorErrors,
    cfg: CompareConfig,
    seed: u64,
    path: FlightData,
    white: NoiseEstimate,
}

impl<'a> DrawMaker<'a> {
    /// None when the flight is too short for one window.
    fn new(
        model: &'a Model,
        data: &FlightData,
        errors: &'a SensorErrors,
        cfg: CompareConfig,
        seed: u64,
    ) -> Option<Self> {
        // The draws are compared with the model as on the flight, weighed by their own noise
        // unless a pass says otherwise.
        let cfg = CompareConfig {
            model_error: None,
            ..cfg
        };
        let prep = Prepared::new(data, cfg);
        if prep.windows.is_empty() {
            return None;
        }
        let cmp = compare_prepared(model, &prep);
        let path = model_path(data, &cmp, prep.measured.for_vehicle(model).attitude);
        Some(Self {
            model,
            errors,
            cfg,
            seed,
            path,
            white: prep.measured_noise,
        })
    }

    /// Draw `k`: the stated errors (its own seed) and the white noise topped up.
    fn draw(&self, k: u64) -> FlightData {
        let mut d = self.path.clone();
        let s = draw_seed(self.seed, k);
        self.errors.apply(&mut d, s);
        top_up_white_noise(&mut d, &self.white, s);
        d
    }

    /// Draws `which` compared with the model, weighed by their noise and `model_error`: each
    /// one's error in noise units and its residual rows' sums.
    fn compared(&self, which: &[usize], model_error: NoiseEstimate) -> Vec<(f64, AxisSums)> {
        let weighed = CompareConfig {
            model_error: Some(model_error),
            ..self.cfg
        };
        which
            .par_iter()
            .map(|&k| {
                let c = compare(self.model, &self.draw(k as u64), weighed);
                (c.noise_units(), c.axis_sums())
            })
            .collect()
    }
}

/// `draws` synthetic flights of `model` along `data` with `errors` (module docs), their seeds
/// mixed from `seed`; empty when the flight is too short for one window. (All at once: for
/// inspection and tests; [`error_floor`] makes them one at a time.)
pub fn synthetic_flights(
    model: &Model,
    data: &FlightData,
    errors: &SensorErrors,
    cfg: CompareConfig,
    draws: usize,
    seed: u64,
) -> Vec<FlightData> {
    match DrawMaker::new(model, data, errors, cfg, seed) {
        Some(maker) => (0..draws as u64).map(|k| maker.draw(k)).collect(),
        None => Vec::new(),
    }
}

/// `data` with every compared sample replaced by the model's prediction `cmp` (attitude,
/// rates and airspeed only where the model has them): the path of a flight the model gets
/// exactly right.
fn model_path(data: &FlightData, cmp: &Comparison, with_attitude: bool) -> FlightData {
    let mut d = data.clone();
    let p = &cmp.prediction;
    for (k, &i) in p.index.iter().enumerate() {
        if i >= d.len() {
            continue;
        }
        d.pos_ned[i] = p.pos_ned[k];
        if let Some(v) = d.vel_ned.as_mut() {
            v[i] = p.vel_ned[k];
        }
        if let Some(f) = d.accel_body.as_mut() {
            f[i] = p.specific_force[k];
        }
        if with_attitude {
            if let Some(a) = d.attitude.as_mut() {
                a[i] = p.attitude[k];
            }
            if let Some(w) = d.rates_body.as_mut() {
                w[i] = p.rates[k];
            }
            if let Some(a) = d.airspeed.as_mut() {
                a[i] = p.air[k].airspeed;
            }
        }
    }
    d
}

/// Add white noise to each axis of `d` until its white noise is the flight's (`white`): the
/// stated errors' own white part counts, the rest is drawn (seeded by `seed`).
fn top_up_white_noise(d: &mut FlightData, white: &NoiseEstimate, seed: u64) {
    let have = estimate_noise(d);
    let extra = |want: f64, has: f64| (want * want - has * has).max(0.0).sqrt();
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x0077_6869_7465);
    let mut gauss = |sigma: f64| -> f64 {
        match Normal::new(0.0, sigma) {
            Ok(n) if sigma > 0.0 => n.sample(&mut rng),
            _ => 0.0,
        }
    };
    let pos: [f64; 3] = std::array::from_fn(|k| extra(white.pos_axes[k], have.pos_axes[k]));
    for p in &mut d.pos_ned {
        *p += DVec3::new(gauss(pos[0]), gauss(pos[1]), gauss(pos[2]));
    }
    let vel: [f64; 3] = std::array::from_fn(|k| extra(white.vel_axes[k], have.vel_axes[k]));
    for v in d.vel_ned.iter_mut().flatten() {
        *v += DVec3::new(gauss(vel[0]), gauss(vel[1]), gauss(vel[2]));
    }
    let att: [f64; 3] = std::array::from_fn(|k| extra(white.att_axes[k], have.att_axes[k]));
    for a in d.attitude.iter_mut().flatten() {
        let (roll, pitch, yaw) = (gauss(att[0]), gauss(att[1]), gauss(att[2]));
        *a = EulerZyx::new(a.yaw + yaw, a.pitch + pitch, a.roll + roll);
    }
    let rate: [f64; 3] = std::array::from_fn(|k| extra(white.rate_axes[k], have.rate_axes[k]));
    for w in d.rates_body.iter_mut().flatten() {
        *w += DVec3::new(gauss(rate[0]), gauss(rate[1]), gauss(rate[2]));
    }
    let air = extra(white.airspeed_mps, have.airspeed_mps);
    for a in d.airspeed.iter_mut().flatten() {
        *a += gauss(air);
    }
    let acc: [f64; 3] = std::array::from_fn(|k| extra(white.accel_axes[k], have.accel_axes[k]));
    for f in d.accel_body.iter_mut().flatten() {
        *f += DVec3::new(gauss(acc[0]), gauss(acc[1]), gauss(acc[2]));
    }
}

/// The seed of draw `k` from `seed`: SplitMix64's finaliser of their sum, so that the draws'
/// seeds share no bits a generator could carry from one to the next.
fn draw_seed(seed: u64, k: u64) -> u64 {
    let mut z = seed.wrapping_add(k.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Each residual row's variance factor of its sum over the flight, from the draws `compared`
/// (a right model's residuals: errors alone): E[(Σ r)²] / E[Σ r²], 1 for white residuals —
/// taken at its upper 90% confidence bound. Over k draws Σ(Σ r)² is the factor times a χ²
/// of k degrees of freedom, so a factor estimated from a dozen draws is half the true one
/// one time in ten; a factor too small makes a wandering error's mean pass for a cause
/// (an attitude offset on a log whose attitude errors wander for a minute). At least 1.
fn colour_of_sums(compared: &[(f64, AxisSums)]) -> [f64; MAX_ROWS] {
    let k = compared.len().max(1) as f64;
    let bound = k / chi2_quantile(0.1, k);
    let (mut sum2, mut chi2) = ([0.0; MAX_ROWS], [0.0; MAX_ROWS]);
    for (_, s) in compared {
        for j in 0..MAX_ROWS {
            sum2[j] += s.sum[j] * s.sum[j];
            chi2[j] += s.chi2[j];
        }
    }
    std::array::from_fn(|j| {
        if chi2[j] > 0.0 {
            (bound * sum2[j] / chi2[j]).max(1.0)
        } else {
            1.0
        }
    })
}
