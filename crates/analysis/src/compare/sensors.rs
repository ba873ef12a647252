//! What the sensors read of a predicted flight: the model's measurement effects
//! ([`wireflight_flight::effects::sensors`]) applied to a window's predictions after it is
//! flown ([`super::predict::fly_window`]), and the same change of the readings' derivatives
//! for the tangent-linear Jacobian.
//!
//! A delayed navigation solution reads, at sample time t, the position and velocity of
//! t − delay: the predictions are interpolated linearly between the window's samples (the
//! error, h²/8 times the second derivative, is 5·10⁻⁵ m at 50 Hz and 1 g). Before the
//! window's first sample the model is flown back ([`super::predict`]); where that flight
//! does not stay finite, the readings extrapolate the window's own by the parabola through
//! three of its samples a delay apart. The Jacobian's rows of a delayed reading are the same
//! combination of the tangent's rows inside the window and, before it, of a forward
//! difference of the short flight back.

use glam::{DMat3, DQuat};

use wireflight_flight::effects::Reading;
use wireflight_flight::model::Model;

/// Where a delayed reading at one sample comes from: up to three samples of the window
/// (indices local to it) and their weights, summing to one.
pub(crate) type Weights = [(usize, f64); 3];

/// The weights of the reading at local sample `k` of a window sampled at `time`, delayed by
/// `delay` s.
pub(crate) fn delay_weights(time: &[f64], k: usize, delay: f64) -> Weights {
    let n = time.len();
    let at = |j: usize| [(j, 1.0), (j, 0.0), (j, 0.0)];
    if k >= n || delay <= 0.0 || n == 1 {
        return at(k.min(n.saturating_sub(1)));
    }
    let tau = time[k] - delay;
    if tau >= time[0] {
        // The last sample at or before τ (never after k: τ < time[k]).
        let j = time[..=k].partition_point(|&t| t <= tau).saturating_sub(1);
        if j >= k {
            return at(k);
        }
        let w = (tau - time[j]) / (time[j + 1] - time[j]);
        return [(j, 1.0 - w), (j + 1, w), (j, 0.0)];
    }
    if n == 2 {
        let w = (tau - time[0]) / (time[1] - time[0]);
        return [(0, 1.0 - w), (1, w), (0, 0.0)];
    }
    // The parabola through samples 0, a, 2a, a about one delay apart: an extrapolation about
    // one node spacing out, whose weights stay small (3, −3, 1 at exactly one spacing).
    let step = (time[n - 1] - time[0]) / (n - 1) as f64;
    let a = ((delay / step).round() as usize).clamp(1, (n - 1) / 2);
    let (i0, i1, i2) = (0, a, 2 * a);
    let (t0, t1, t2) = (time[i0], time[i1], time[i2]);
    let l0 = (tau - t1) * (tau - t2) / ((t0 - t1) * (t0 - t2));
    let l1 = (tau - t0) * (tau - t2) / ((t1 - t0) * (t1 - t2));
    let l2 = (tau - t0) * (tau - t1) / ((t2 - t0) * (t2 - t1));
    [(i0, l0), (i1, l1), (i2, l2)]
}

/// The airspeed read per metre per second of true airspeed at `airspeed` (1 without
/// measurement effects): the slope of the affine sensor.
pub(crate) fn airspeed_gain(model: &Model, airspeed: f64) -> f64 {
    if !model.has_measurement_effects() {
        return 1.0;
    }
    let read = |a: f64| {
        let mut r = Reading {
            pos_ned: glam::DVec3::ZERO,
            vel_ned: glam::DVec3::ZERO,
            quat: DQuat::IDENTITY,
            rates: glam::DVec3::ZERO,
            airspeed: a,
            specific_force: glam::DVec3::ZERO,
        };
        model.measure(&mut r);
        r.airspeed
    };
    read(airspeed + 1.0) - read(airspeed)
}

/// The attitude the sensors read for body attitude `rot` and the body-frame rotation R₀ from
/// the body to the attitude reference (`measure` reads R·R₀): (R·R₀, R₀). Without a
/// misalignment, (R, I).
pub(crate) fn attitude_read(model: &Model, rot: &DMat3) -> (DMat3, DMat3) {
    if !model.has_measurement_effects() {
        return (*rot, DMat3::IDENTITY);
    }
    let mut r = Reading {
        pos_ned: glam::DVec3::ZERO,
        vel_ned: glam::DVec3::ZERO,
        quat: DQuat::IDENTITY,
        rates: glam::DVec3::ZERO,
        airspeed: 0.0,
        specific_force: glam::DVec3::ZERO,
    };
    model.measure(&mut r);
    let r0 = DMat3::from_quat(r.quat);
    (*rot * r0, r0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights reproduce a parabola exactly (inside by linear interpolation only where it
    /// is a line), and sum to one.
    #[test]
    fn delay_weights_read_a_polynomial_back_in_time() {
        let time: Vec<f64> = (0..50).map(|i| 0.02 * i as f64).collect();
        let line = |t: f64| 3.0 - 2.0 * t;
        let parabola = |t: f64| 1.0 + 0.5 * t - 4.0 * t * t;
        for delay in [0.01, 0.02, 0.13, 0.25, 0.5] {
            for k in 0..time.len() {
                let w = delay_weights(&time, k, delay);
                let sum: f64 = w.iter().map(|x| x.1).sum();
                assert!((sum - 1.0).abs() < 1e-12);
                let tau = time[k] - delay;
                let read =
                    |f: &dyn Fn(f64) -> f64| w.iter().map(|&(j, c)| c * f(time[j])).sum::<f64>();
                assert!((read(&line) - line(tau)).abs() < 1e-12, "{delay} {k}");
                if tau < 0.0 {
                    assert!(
                        (read(&parabola) - parabola(tau)).abs() < 1e-10,
                        "{delay} {k}"
                    );
                }
                assert!(w.iter().all(|&(j, c)| j <= k.max(2 * 25) && c.is_finite()));
            }
        }
        assert_eq!(delay_weights(&time, 7, 0.0), [(7, 1.0), (7, 0.0), (7, 0.0)]);
    }
}
