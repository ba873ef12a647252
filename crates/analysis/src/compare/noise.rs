//! How noisy the measurements are, told apart from how the aircraft moved.
//!
//! **Estimator.** For each channel axis, the fourth-order differences of consecutive samples,
//! d_i = y_i − 4y_{i+1} + 6y_{i+2} − 4y_{i+3} + y_{i+4}. Smooth motion cancels to h⁴·y⁗
//! (at 50 Hz, 1.6e-7 of the fourth derivative: nothing for a flying aircraft), while white
//! noise of deviation σ gives Var(d) = 70σ². Manoeuvres that are not smooth — a control step
//! puts a kink in the body rates — spoil a handful of differences each, so the scale is taken
//! robustly: σ = 1.4826·MAD(d)/√70 (the median absolute deviation ignores up to half the
//! differences being wild). A local-fit residual (the previous estimator) reads every
//! manoeuvre as noise instead.
//!
//! **Floor.** When the model is right and each window's start is fitted, what is left of the
//! error is the measurement noise itself; the expected error per channel follows from the
//! estimate ([`expected_channel_errors`]), and the comparison's `noise_floor` is the total of
//! those.

use glam::DVec3;

use std::borrow::Cow;

use wireflight_data::{unwrap_angles, Channel, FlightData};

/// Normalising constant of fourth-order differences of white noise: Σ binomial(4, k)² = 70.
const DIFF4_VARIANCE: f64 = 70.0;
/// MAD → standard deviation of a normal distribution.
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// Estimated measurement noise (standard deviations) of the data's channels. A channel the
/// data lack, or that was derived (not measured), reads 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoiseEstimate {
    /// Position, m, per axis (north, east, down).
    pub pos_axes: [f64; 3],
    /// NED velocity, m/s, per axis.
    pub vel_axes: [f64; 3],
    /// Attitude angles, rad, per axis (roll, pitch, yaw).
    pub att_axes: [f64; 3],
    /// Body rates, rad/s, per axis (p, q, r).
    pub rate_axes: [f64; 3],
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
    /// Accelerometer (specific force), m/s², per body axis (x, y, z).
    pub accel_axes: [f64; 3],
    /// Position, m: RMS of the axes.
    pub pos_m: f64,
    /// Velocity, m/s: RMS of the axes.
    pub vel_mps: f64,
    /// Attitude, rad: RMS of the axes.
    pub att_rad: f64,
    /// Body rates, rad/s: RMS of the axes.
    pub rate_radps: f64,
    /// Accelerometer, m/s²: RMS of the axes.
    pub accel_mps2: f64,
}

/// Robust noise deviation of one sampled signal (see the module docs); 0 for fewer than 16
/// samples, where it cannot be told.
pub fn robust_noise(y: &[f64]) -> f64 {
    if y.len() < 16 {
        return 0.0;
    }
    let mut d: Vec<f64> = y
        .windows(5)
        .map(|w| w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4])
        .filter(|v| v.is_finite())
        .collect();
    if d.len() < 8 {
        return 0.0;
    }
    let m = median(&mut d);
    for v in &mut d {
        *v = (*v - m).abs();
    }
    MAD_TO_SIGMA * median(&mut d) / DIFF4_VARIANCE.sqrt()
}

/// The median of `v` (reordered in place); NaN-free input assumed.
fn median(v: &mut [f64]) -> f64 {
    let n = v.len();
    let mid = n / 2;
    let (_, &mut hi, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    if n % 2 == 1 {
        hi
    } else {
        let lo = v[..mid].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        0.5 * (lo + hi)
    }
}

fn axes3(values: &[DVec3]) -> [f64; 3] {
    let pick = |k: usize| -> Vec<f64> { values.iter().map(|v| v[k]).collect() };
    let (x, (y, z)) = rayon::join(
        || robust_noise(&pick(0)),
        || rayon::join(|| robust_noise(&pick(1)), || robust_noise(&pick(2))),
    );
    [x, y, z]
}

fn rms3(a: [f64; 3]) -> f64 {
    ((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) / 3.0).sqrt()
}

impl NoiseEstimate {
    /// The estimate with each channel's RMS over its axes taken from the axes.
    pub(crate) fn with_rms(mut self) -> Self {
        self.pos_m = rms3(self.pos_axes);
        self.vel_mps = rms3(self.vel_axes);
        self.att_rad = rms3(self.att_axes);
        self.rate_radps = rms3(self.rate_axes);
        self.accel_mps2 = rms3(self.accel_axes);
        self
    }
}

/// Measurement noise of every measured channel of the data (derived channels read 0).
pub fn estimate_noise(d: &FlightData) -> NoiseEstimate {
    // Channels side by side: each is a median of every sample's difference, twice.
    let (((pos_axes, vel_axes), (att_axes, (rate_axes, airspeed_mps))), accel_axes) = rayon::join(
        || estimate_kinematics(d),
        || {
            d.accel_body
                .as_deref()
                .map_or([0.0; 3], |a| axes3(&own(d, Channel::Accelerometer, a)))
        },
    );
    NoiseEstimate {
        pos_axes,
        vel_axes,
        att_axes,
        rate_axes,
        airspeed_mps,
        accel_axes,
        ..NoiseEstimate::default()
    }
    .with_rms()
}

/// A channel's values at its own samples ([`wireflight_data::Sampling`]): values filled in
/// between them would read as smooth, hiding the noise.
fn own<'v, T: Copy>(d: &FlightData, channel: Channel, values: &'v [T]) -> Cow<'v, [T]> {
    if d.sampling.is_complete(channel) {
        Cow::Borrowed(values)
    } else {
        Cow::Owned(
            d.sampling
                .rows(channel, values.len())
                .map(|i| values[i])
                .collect(),
        )
    }
}

/// The noise of position, velocity, attitude, rates and airspeed.
#[allow(clippy::type_complexity)]
fn estimate_kinematics(d: &FlightData) -> (([f64; 3], [f64; 3]), ([f64; 3], ([f64; 3], f64))) {
    rayon::join(
        || {
            rayon::join(
                || axes3(&own(d, Channel::Position, &d.pos_ned)),
                || match &d.vel_ned {
                    Some(v) if !d.is_derived("vel_ned") => axes3(&own(d, Channel::Velocity, v)),
                    _ => [0.0; 3],
                },
            )
        },
        || {
            rayon::join(
                || match &d.attitude {
                    Some(att) => {
                        let att = own(d, Channel::Attitude, att);
                        let angle = |k: usize| {
                            let a: Vec<f64> =
                                att.iter().map(|e| [e.roll, e.pitch, e.yaw][k]).collect();
                            robust_noise(&unwrap_angles(&a))
                        };
                        let (roll, (pitch, yaw)) =
                            rayon::join(|| angle(0), || rayon::join(|| angle(1), || angle(2)));
                        [roll, pitch, yaw]
                    }
                    None => [0.0; 3],
                },
                || {
                    rayon::join(
                        || match &d.rates_body {
                            Some(w) if !d.is_derived("rates_body") => {
                                axes3(&own(d, Channel::Rates, w))
                            }
                            _ => [0.0; 3],
                        },
                        || {
                            d.airspeed
                                .as_deref()
                                .map_or(0.0, |a| robust_noise(&own(d, Channel::Airspeed, a)))
                        },
                    )
                },
            )
        },
    )
}

/// The RMS error per channel (position m, velocity m/s, attitude deg, rates deg/s) that a
/// right model leaves on data with this noise: the root of the summed axis variances (the
/// channel errors are lengths of error vectors). The start states fitted per window take a
/// negligible share (12 numbers against thousands of residuals).
pub fn expected_channel_errors(n: &NoiseEstimate) -> [f64; 4] {
    let len = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [
        len(n.pos_axes),
        len(n.vel_axes),
        len(n.att_axes).to_degrees(),
        len(n.rate_axes).to_degrees(),
    ]
}

/// Noise and model error together, per axis: √(σ²_noise + σ²_model).
pub fn combined(noise: &NoiseEstimate, model: &NoiseEstimate) -> NoiseEstimate {
    let add = |a: f64, b: f64| a.hypot(b);
    let add3 = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|k| add(a[k], b[k]));
    NoiseEstimate {
        pos_axes: add3(noise.pos_axes, model.pos_axes),
        vel_axes: add3(noise.vel_axes, model.vel_axes),
        att_axes: add3(noise.att_axes, model.att_axes),
        rate_axes: add3(noise.rate_axes, model.rate_axes),
        accel_axes: add3(noise.accel_axes, model.accel_axes),
        airspeed_mps: add(noise.airspeed_mps, model.airspeed_mps),
        ..NoiseEstimate::default()
    }
    .with_rms()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    #[test]
    fn white_noise_on_a_manoeuvre_with_steps_is_measured_not_the_manoeuvre() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let noise = Normal::new(0.0, 0.2).unwrap();
        // A body rate at 50 Hz: ramps and steps of 30°/s every 2 s (kinks and jumps), plus a
        // slow sine, plus 0.2°/s of noise.
        let y: Vec<f64> = (0..5000)
            .map(|i| {
                let t = i as f64 / 50.0;
                let step = if (t / 2.0).floor() as i64 % 2 == 0 {
                    30.0
                } else {
                    -30.0
                };
                step + 20.0 * (0.7 * t).sin() + noise.sample(&mut rng)
            })
            .collect();
        let s = robust_noise(&y);
        assert!((s - 0.2).abs() < 0.02, "{s}");
        // Without noise, the manoeuvre alone reads as (almost) nothing.
        let clean: Vec<f64> = (0..5000)
            .map(|i| {
                let t = i as f64 / 50.0;
                20.0 * (0.7 * t).sin() + 3.0 * t * t
            })
            .collect();
        assert!(robust_noise(&clean) < 1e-6, "{}", robust_noise(&clean));
    }

    #[test]
    fn too_few_samples_read_zero() {
        assert_eq!(robust_noise(&[1.0, 2.0, 3.0]), 0.0);
    }
}
