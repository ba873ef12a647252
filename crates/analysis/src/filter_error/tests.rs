//! The filter-error fit on a short-period model with known truth: calm air (it must give
//! output error's answer), light and moderate vertical gusts (output error biased, the filter
//! not), and a steady offset in calm air (not turbulence).

use super::*;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

const AIRSPEED: f64 = 50.0;
const Z_ALPHA: f64 = -1.2;
const Z_DELTA: f64 = -0.1;
/// True M_α, M_q, M_δ.
const TRUTH: [f64; 3] = [-6.0, -2.5, -9.0];
const ALPHA_NOISE: f64 = 0.002;
const RATE_NOISE: f64 = 0.003;

/// α, q short period; a vertical gust w changes the angle of attack the wing sees by w/V, and
/// the vane reads the air-relative α. Parameters: M_α, M_q, M_δ, then the two outputs' bias.
struct ShortPeriod;

impl LinearModel for ShortPeriod {
    fn parameter_count(&self) -> usize {
        5
    }
    fn system(&self, t: &[f64]) -> System {
        let row = |r: &[f64]| r.to_vec();
        let m = |rows: &[Vec<f64>]| {
            let refs: Vec<&[f64]> = rows.iter().map(|r| r.as_slice()).collect();
            Mat::from_rows(&refs).unwrap_or_else(|| Mat::zeros(0, 0))
        };
        System {
            a: m(&[row(&[Z_ALPHA, 1.0]), row(&[t[0], t[1]])]),
            b: m(&[row(&[Z_DELTA]), row(&[t[2]])]),
            c: Mat::identity(2),
            d: Mat::zeros(2, 1),
            gust_state: m(&[row(&[Z_ALPHA / AIRSPEED]), row(&[t[0] / AIRSPEED])]),
            gust_output: m(&[row(&[1.0 / AIRSPEED]), row(&[0.0])]),
            bias: vec![t[3], t[4]],
        }
    }
    fn gusts(&self) -> Gusts {
        Gusts {
            // L = 300 m at 50 m/s.
            time_constants_s: vec![6.0],
            shape: vec![1.0],
        }
    }
}

fn truth() -> Vec<f64> {
    vec![TRUTH[0], TRUTH[1], TRUTH[2], 0.0, 0.0]
}

/// A 120 s flight at 50 Hz with elevator doublets, flown through gusts of σ `gust` (exact
/// discrete Gauss–Markov), measured with white noise, plus a constant `offset` on the vane.
fn flight(gust: f64, offset: f64, seed: u64) -> Record {
    let dt = 0.02;
    let model = ShortPeriod;
    let disc = discretise(&model, &truth(), dt, gust);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let unit = Normal::new(0.0, 1.0).unwrap();
    let mut x = [0.0; 3];
    x[2] = gust * unit.sample(&mut rng);
    let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
    for k in 0..6000 {
        let t = k as f64 * dt;
        let phase = t % 10.0;
        let de = if phase < 1.0 {
            0.03
        } else if phase < 2.0 {
            -0.03
        } else {
            0.0
        };
        let mut y = vec![0.0; 2];
        disc.h.mul_vec_into(&x, &mut y);
        y[0] += offset + ALPHA_NOISE * unit.sample(&mut rng);
        y[1] += RATE_NOISE * unit.sample(&mut rng);
        outputs.push(y);
        inputs.push(vec![de]);
        let mut next = [0.0; 3];
        disc.phi.mul_vec_into(&x, &mut next);
        for i in 0..3 {
            x[i] = next[i] + disc.gamma.at(i, 0) * de;
        }
        x[2] += disc.gust_q[0].sqrt() * unit.sample(&mut rng);
    }
    Record {
        dt_s: dt,
        inputs,
        outputs,
        noise_sigma: vec![ALPHA_NOISE, RATE_NOISE],
    }
}

/// Start values 30 % off the truth, biases zero.
fn start() -> Vec<f64> {
    vec![TRUTH[0] * 0.7, TRUTH[1] * 1.3, TRUTH[2] * 0.7, 0.0, 0.0]
}

fn worst_relative_error(theta: &[f64]) -> f64 {
    TRUTH
        .iter()
        .zip(theta)
        .map(|(t, e)| ((e - t) / t).abs())
        .fold(0.0, f64::max)
}

#[test]
fn calm_air_the_filter_reduces_to_output_error_and_finds_no_turbulence() {
    let record = flight(0.0, 0.0, 1);
    let test = turbulence_test(&ShortPeriod, &record, &start()).unwrap();
    assert!(!test.turbulence, "LR {}", test.likelihood_ratio);
    for (a, b) in test.output_error.theta.iter().zip(&test.filter_error.theta) {
        assert!((a - b).abs() < 1e-3 * (1.0 + a.abs()), "{a} vs {b}");
    }
    assert!(worst_relative_error(&test.output_error.theta) < 0.01);
}

#[test]
fn light_turbulence_recognised_and_the_filter_is_unbiased_where_output_error_is_not() {
    for (seed, sigma) in [(2, 1.0), (3, 2.0)] {
        let record = flight(sigma, 0.0, seed);
        let test = turbulence_test(&ShortPeriod, &record, &start()).unwrap();
        let oe = worst_relative_error(&test.output_error.theta);
        let fe = worst_relative_error(&test.filter_error.theta);
        eprintln!(
            "σ {sigma}: OE {:?} ({oe:.3}), FE {:?} ({fe:.3}) σ̂ {:.3} ± {:.3}, LR {:.1}, lag1 OE {:.2} FE {:.2}",
            test.output_error.theta,
            test.filter_error.theta,
            test.filter_error.gust_sigma_mps,
            test.filter_error.gust_sigma_se_mps,
            test.likelihood_ratio,
            test.output_error.innovation_lag1,
            test.filter_error.innovation_lag1
        );
        assert!(test.turbulence);
        assert!(fe < 0.10, "filter error off by {fe}");
        assert!(oe > 2.0 * fe, "output error {oe} vs filter error {fe}");
        let intensity = test.filter_error.gust_sigma_mps;
        assert!(
            (intensity - sigma).abs() < 0.25 * sigma,
            "σ̂ {intensity} vs {sigma}"
        );
        assert!(test.filter_error.innovation_lag1.abs() < 0.2);
    }
}

#[test]
fn a_steady_offset_in_calm_air_is_a_bias_not_turbulence() {
    let record = flight(0.0, 0.02, 4);
    let test = turbulence_test(&ShortPeriod, &record, &start()).unwrap();
    assert!(!test.turbulence, "LR {}", test.likelihood_ratio);
    assert!((test.filter_error.theta[3] - 0.02).abs() < 1e-3);
}

#[test]
fn wrong_dimensions_are_a_typed_error_not_a_panic() {
    let mut record = flight(0.0, 0.0, 5);
    record.noise_sigma.pop();
    assert!(matches!(
        fit(&ShortPeriod, &record, &start(), Method::FilterError),
        Err(FitError::Dimensions { .. })
    ));
    let record = flight(0.0, 0.0, 5);
    assert!(matches!(
        fit(&ShortPeriod, &record, &[1.0], Method::OutputError),
        Err(FitError::Dimensions { .. })
    ));
}

#[test]
fn the_matrix_exponential_and_inverse_agree_with_closed_forms() {
    let a = Mat::from_rows(&[&[0.0, 1.0], &[-1.0, 0.0]]).unwrap();
    let e = a.expm();
    assert!((e.at(0, 0) - 1f64.cos()).abs() < 1e-12 && (e.at(0, 1) - 1f64.sin()).abs() < 1e-12);
    let s = Mat::from_rows(&[&[4.0, 2.0], &[2.0, 3.0]]).unwrap();
    let (inv, logdet) = s.spd_inverse_logdet().unwrap();
    assert!((logdet - 8f64.ln()).abs() < 1e-12);
    let id = s.mul(&inv);
    assert!(id.add_scaled(&Mat::identity(2), -1.0).max_abs() < 1e-12);
}
