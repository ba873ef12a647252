//! The filter-error method through the library's public interface: a roll mode flown through
//! a rolling gust, its truth simulated independently (fine Euler steps, not the fit's exact
//! discretisation), identified by output error and by the filter.

use wireflight_analysis::filter_error::{
    fit, turbulence_test, Gusts, LinearModel, Mat, Method, Record, System,
};

/// True roll damping L_p (per s) and aileron power L_δ (per s²).
const L_P: f64 = -4.0;
const L_DELTA: f64 = 20.0;
/// A gust velocity of 1 m/s rolls the aircraft as a roll rate of 0.02 rad/s would.
const GUST_TO_RATE: f64 = 0.02;
const TAU: f64 = 4.0;
const RATE_NOISE: f64 = 0.004;

/// ṗ = L_p (p + k g) + L_δ δ, the gyro reads p; parameters L_p, L_δ and the gyro's bias.
struct Roll;

impl LinearModel for Roll {
    fn parameter_count(&self) -> usize {
        3
    }
    fn system(&self, t: &[f64]) -> System {
        let one = |v: f64| Mat::from_rows(&[&[v]]).unwrap_or_else(|| Mat::zeros(1, 1));
        System {
            a: one(t[0]),
            b: one(t[1]),
            c: one(1.0),
            d: one(0.0),
            gust_state: one(t[0] * GUST_TO_RATE),
            gust_output: one(0.0),
            bias: vec![t[2]],
        }
    }
    fn gusts(&self) -> Gusts {
        Gusts {
            time_constants_s: vec![TAU],
            shape: vec![1.0],
        }
    }
}

/// Standard normal samples from a seeded xorshift generator and Box–Muller (the test binary
/// carries no random-number crate).
struct Gaussian(u64);

impl Gaussian {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn sample(&mut self) -> f64 {
        let (a, b) = (self.uniform(), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// 90 s at 50 Hz of aileron doublets, integrated in 1 ms steps through a Gauss–Markov gust.
fn flight(gust_sigma: f64, seed: u64) -> Record {
    let mut unit = Gaussian(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xD1B5_4A32_D192_ED03));
    let fine = 0.001;
    let (mut p, mut g) = (0.0, gust_sigma * unit.sample());
    let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
    for k in 0..4500 {
        let t = k as f64 * 0.02;
        let phase = t % 6.0;
        let aileron = if phase < 0.5 {
            0.02
        } else if phase < 1.0 {
            -0.02
        } else {
            0.0
        };
        inputs.push(vec![aileron]);
        outputs.push(vec![p + RATE_NOISE * unit.sample()]);
        for _ in 0..20 {
            p += fine * (L_P * (p + GUST_TO_RATE * g) + L_DELTA * aileron);
            g += -fine * g / TAU + gust_sigma * (2.0 * fine / TAU).sqrt() * unit.sample();
        }
    }
    Record {
        dt_s: 0.02,
        inputs,
        outputs,
        noise_sigma: vec![RATE_NOISE],
    }
}

#[test]
fn calm_roll_both_methods_agree_and_no_turbulence_is_claimed() {
    let record = flight(0.0, 11);
    let test = turbulence_test(&Roll, &record, &[-2.0, 10.0, 0.0]).unwrap();
    assert!(!test.turbulence, "LR {}", test.likelihood_ratio);
    assert_eq!(test.filter_error.gust_sigma_mps, 0.0);
    assert!((test.output_error.theta[0] - L_P).abs() < 0.02 * L_P.abs());
}

#[test]
fn rolling_gusts_are_recognised_and_the_filter_finds_the_roll_damping() {
    let record = flight(1.5, 12);
    let test = turbulence_test(&Roll, &record, &[-2.0, 10.0, 0.0]).unwrap();
    let fe = &test.filter_error;
    let oe = &test.output_error;
    eprintln!(
        "OE {:?}, FE {:?}, σ̂ {:.3} ± {:.3}, LR {:.0}",
        oe.theta, fe.theta, fe.gust_sigma_mps, fe.gust_sigma_se_mps, test.likelihood_ratio
    );
    assert!(test.turbulence);
    assert!(
        (fe.theta[0] - L_P).abs() < 0.10 * L_P.abs(),
        "{:?}",
        fe.theta
    );
    assert!(
        (fe.theta[1] - L_DELTA).abs() < 0.10 * L_DELTA,
        "{:?}",
        fe.theta
    );
    assert!((fe.gust_sigma_mps - 1.5).abs() < 0.25 * 1.5);
    // Forcing output error on the same flight: a typed result, its innovations far from white.
    let forced = fit(&Roll, &record, &[-2.0, 10.0, 0.0], Method::OutputError).unwrap();
    assert!(forced.innovation_lag1 > 0.5 && fe.innovation_lag1.abs() < 0.2);
}
