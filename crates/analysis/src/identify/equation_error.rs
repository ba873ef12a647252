//! The equation-error starting point of an identification: the measured body accelerations
//! and angular accelerations (smoothing differentiator) regressed on the model's at the
//! measured states, by Gauss–Newton with the same prior as the output-error fit. Where a
//! flight has an accelerometer, the force equations take its specific force instead of the
//! differentiated body velocity: the most direct measurement of force a log has, with no
//! differentiation's lag or noise. Biased by noise in the regressors, by actuator lag and by
//! wind — a start, never the answer.

use rayon::prelude::*;

use super::Prior;
use crate::free::{set_values, values, Free};
use crate::lm::newton_trial;
use wireflight_data::derive::{Differentiator, Window};
use wireflight_data::{Channel, Controls, FlightData};
use wireflight_flight::model::{Model, State};

/// At most this many samples of each flight enter the regression (evenly strided).
const EE_SAMPLES: usize = 4000;

/// One sample of the regression: the measured state, the controls, and the measured
/// derivatives of the body velocity (or the accelerometer's specific force) and the body
/// rates.
pub(crate) struct EeSample {
    pub(crate) t: f64,
    pub(crate) state: State,
    pub(crate) controls: Controls,
    pub(crate) measured: [f64; 6],
    /// The first three of `measured` are the accelerometer's.
    pub(crate) accelerometer: bool,
}

impl EeSample {
    /// What `m` makes of the measured quantities at this sample: its body-velocity
    /// derivative (or specific force, where `measured` has the accelerometer's) and its
    /// angular acceleration.
    pub(crate) fn modelled(&self, m: &Model) -> [f64; 6] {
        let d = m.derivative(self.t, &self.state, &self.controls);
        let v = if self.accelerometer {
            m.specific_force(self.t, &self.state, &self.controls)
        } else {
            d.vel()
        };
        let w = d.omega();
        [v.x, v.y, v.z, w.x, w.y, w.z]
    }
}

/// Equation-error estimate of the free parameters (module docs); None when no flight has the
/// channels it needs (attitude, body velocity, rates, controls) or the regression fails.
pub(super) fn equation_error(
    base: &Model,
    flights: &[FlightData],
    free: &[Free],
    prior: &Prior,
) -> Option<Vec<f64>> {
    let samples: Vec<EeSample> = flights.iter().flat_map(ee_samples).collect();
    if samples.len() < 10 * free.len() {
        return None;
    }
    let np = free.len();
    let residuals = |m: &Model| -> Vec<[f64; 6]> {
        samples
            .par_iter()
            .map(|s| {
                let f = s.modelled(m);
                std::array::from_fn(|c| s.measured[c] - f[c])
            })
            .collect()
    };
    // Each component weighted by its RMS misfit at the start (its units and noise differ).
    let r0 = residuals(base);
    let weight: [f64; 6] = std::array::from_fn(|c| {
        let ms = r0.iter().map(|r| r[c] * r[c]).sum::<f64>() / r0.len() as f64;
        if ms > 0.0 && ms.is_finite() {
            1.0 / ms.sqrt()
        } else {
            0.0
        }
    });
    let cost = |r: &[[f64; 6]]| -> f64 {
        r.iter()
            .map(|x| (0..6).map(|c| (x[c] * weight[c]).powi(2)).sum::<f64>())
            .sum()
    };
    let mut theta = values(base, free);
    let mut model = base.clone();
    let mut r = r0;
    let mut c_now = cost(&r) + prior.penalty(&theta);
    if !c_now.is_finite() {
        return None;
    }
    for _ in 0..10 {
        // Forward-difference Jacobian, one model per parameter.
        let cols: Vec<Vec<[f64; 6]>> = (0..np)
            .map(|j| {
                let mut t = theta.clone();
                let h = 0.01 * free[j].scale;
                t[j] += h;
                let mut m = model.clone();
                set_values(&mut m, free, &t);
                let rj = residuals(&m);
                rj.iter()
                    .zip(&r)
                    .map(|(a, b)| std::array::from_fn(|c| (a[c] - b[c]) / 0.01 * weight[c]))
                    .collect()
            })
            .collect();
        let mut a = vec![0.0; np * np];
        let mut g = vec![0.0; np];
        for i in 0..np {
            for (s, ri) in cols[i].iter().zip(&r) {
                g[i] += (0..6).map(|c| s[c] * ri[c] * weight[c]).sum::<f64>();
            }
            for k in i..np {
                let v: f64 = cols[i]
                    .iter()
                    .zip(&cols[k])
                    .map(|(x, y)| (0..6).map(|c| x[c] * y[c]).sum::<f64>())
                    .sum();
                a[i * np + k] = v;
                a[k * np + i] = v;
            }
            a[i * np + i] += prior.weight[i];
            g[i] += prior.weight[i] * (theta[i] - prior.centre[i]) / free[i].scale;
        }
        let trial = newton_trial(&a, &g, &theta, free)?;
        let mut m = base.clone();
        set_values(&mut m, free, &trial);
        let r_trial = residuals(&m);
        let c_trial = cost(&r_trial) + prior.penalty(&trial);
        if !(c_trial.is_finite() && c_trial < c_now) {
            break;
        }
        let gain = c_now - c_trial;
        theta = values(&m, free);
        model = m;
        r = r_trial;
        c_now = c_trial;
        if gain < 1e-6 * c_now {
            break;
        }
    }
    Some(theta)
}

/// The regression samples of one flight (empty without the channels needed).
pub(crate) fn ee_samples(d: &FlightData) -> Vec<EeSample> {
    let (Some(att), Some(vb), Some(rates), Some(controls)) = (
        d.attitude.as_ref(),
        d.vel_body.as_ref(),
        d.rates_body.as_ref(),
        d.controls.as_ref(),
    ) else {
        return Vec::new();
    };
    let n = d.len();
    let diff = Differentiator::with_window(&d.time, Window::default());
    let half = Window::default().half_samples(&d.time);
    if n <= 2 * half + 1 || diff.len() != n {
        return Vec::new();
    }
    let accel = d.accel_body.as_ref().filter(|a| a.len() == n);
    let dv = match accel {
        Some(a) => a.clone(),
        None => diff.apply_vec3(vb),
    };
    let dw = diff.apply_vec3(rates);
    let stride = ((n - 2 * half) / EE_SAMPLES).max(1);
    // Where the rates (and the accelerometer) have their own rates, only their own samples.
    let measured_at = |i: usize| {
        d.sampling.at(Channel::Rates, i)
            && (accel.is_none() || d.sampling.at(Channel::Accelerometer, i))
    };
    (half..n - half)
        .filter(|&i| measured_at(i))
        .step_by(stride)
        .filter_map(|i| {
            let x = State::measured(d.pos_ned[i], vb[i], att[i], rates[i], &controls[i]);
            let measured = [dv[i].x, dv[i].y, dv[i].z, dw[i].x, dw[i].y, dw[i].z];
            (x.is_finite() && measured.iter().all(|v| v.is_finite())).then_some(EeSample {
                t: d.time[i],
                state: x,
                controls: controls[i],
                measured,
                accelerometer: accel.is_some(),
            })
        })
        .collect()
}
