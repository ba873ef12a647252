//! Where and when the model fails: flight conditions per window correlated with the window's
//! error, and the growth law of the error within a window.
//!
//! The growth law tells the kind of what is missing: with the model started from a state
//! fitted over the first part of the window and then left on its own, a missing *constant
//! acceleration* makes the position error grow ∝ t², a missing *velocity* (e.g. wind carrying
//! the aircraft) ∝ t, a missing moment (attitude error, then acceleration) ∝ t³; errors that
//! do not grow are noise.

use crate::compare::Comparison;
use wireflight_data::FlightData;

/// A condition averaged over each window.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    /// Name, e.g. "airspeed".
    pub name: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// Mean value per window (same order as the comparison's windows).
    pub per_window: Vec<f64>,
    /// Pearson correlation of the window score with this condition; `None` where it has no
    /// meaning (fewer than three windows, or a condition or score that does not vary). For
    /// the heading, the multiple correlation with (cos ψ, sin ψ), which is ≥ 0.
    pub correlation: Option<f64>,
    /// More to say (e.g. the heading at which the error is largest).
    pub note: Option<String>,
}

/// Conditions per window, each with its correlation to the window score; strongest
/// |correlation| first. Conditions the data cannot give are left out.
pub fn conditions(data: &FlightData, cmp: &Comparison, origin_altitude_m: f64) -> Vec<Condition> {
    let scores: Vec<f64> = cmp.windows.iter().map(|w| w.score).collect();
    let mean_over = |f: &dyn Fn(usize) -> f64| -> Vec<f64> {
        cmp.windows
            .iter()
            .map(|w| {
                let (a, b) = w.samples;
                (a..b).map(f).sum::<f64>() / (b - a) as f64
            })
            .collect()
    };
    let mut out = Vec::new();
    let mut push = |name, unit, per_window: Vec<f64>| {
        let correlation = wireflight_flight::numeric::pearson(&per_window, &scores);
        out.push(Condition {
            name,
            unit,
            per_window,
            correlation,
            note: None,
        });
    };
    push(
        "time since start",
        "s",
        cmp.windows
            .iter()
            .map(|w| 0.5 * (w.t0 + w.t1) - data.time[0])
            .collect(),
    );
    push(
        "altitude",
        "m",
        mean_over(&|i| origin_altitude_m - data.pos_ned[i].z),
    );
    push(
        "distance from origin",
        "m",
        mean_over(&|i| data.pos_ned[i].truncate().length()),
    );
    if let Some(v) = &data.vel_ned {
        push("ground speed", "m/s", mean_over(&|i| v[i].length()));
    }
    if let Some(a) = &data.airspeed {
        push("airspeed", "m/s", mean_over(&|i| a[i]));
    }
    if let (Some(att), Some(v)) = (&data.attitude, &data.vel_ned) {
        push(
            "bank angle |φ|",
            "deg",
            mean_over(&|i| att[i].roll.abs().to_degrees()),
        );
        push(
            "angle of attack (ground-relative)",
            "deg",
            mean_over(&|i| {
                let b = att[i].to_matrix().transpose() * v[i];
                b.z.atan2(b.x).to_degrees()
            }),
        );
    }
    if let Some(r) = &data.rates_body {
        push(
            "body rate |ω|",
            "deg/s",
            mean_over(&|i| r[i].length().to_degrees()),
        );
    }
    if let Some(c) = &data.controls {
        push("throttle", "0..1", mean_over(&|i| c[i].throttle));
        push(
            "elevator activity |δe|",
            "deg",
            mean_over(&|i| c[i].elevator.abs().to_degrees()),
        );
        push(
            "aileron activity |δa|",
            "deg",
            mean_over(&|i| c[i].aileron.abs().to_degrees()),
        );
        push(
            "rudder activity |δr|",
            "deg",
            mean_over(&|i| c[i].rudder.abs().to_degrees()),
        );
    }
    if let Some(att) = &data.attitude {
        let cos = mean_over(&|i| att[i].yaw.cos());
        let sin = mean_over(&|i| att[i].yaw.sin());
        out.push(heading_condition(&cos, &sin, &scores));
    }
    let strength = |c: &Condition| c.correlation.map_or(-1.0, f64::abs);
    out.sort_by(|a, b| strength(b).total_cmp(&strength(a)));
    out
}

/// The window score against the heading: the least-squares fit score ≈ a + b·cos ψ + c·sin ψ
/// over the windows (a wind makes the error depend on the heading this way), its multiple
/// correlation R (adjusted for the two regressors), and the heading where the fit peaks.
fn heading_condition(cos: &[f64], sin: &[f64], scores: &[f64]) -> Condition {
    let per_window: Vec<f64> = cos
        .iter()
        .zip(sin)
        .map(|(c, s)| s.atan2(*c).to_degrees().rem_euclid(360.0))
        .collect();
    let n = scores.len();
    let mut correlation = None;
    let mut note = None;
    if n >= 4 {
        let mut a = [[0.0; 3]; 3];
        let mut r = [0.0; 3];
        for k in 0..n {
            let x = [1.0, cos[k], sin[k]];
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] += x[i] * x[j];
                }
                r[i] += x[i] * scores[k];
            }
        }
        if let Some([b0, b1, b2]) = wireflight_flight::numeric::solve(a, r) {
            let fitted: Vec<f64> = (0..n).map(|k| b0 + b1 * cos[k] + b2 * sin[k]).collect();
            let mean = scores.iter().sum::<f64>() / n as f64;
            let ss_tot: f64 = scores.iter().map(|s| (s - mean).powi(2)).sum();
            let ss_fit: f64 = fitted.iter().map(|f| (f - mean).powi(2)).sum();
            if ss_tot > 0.0 {
                // Adjusted for the two regressors, so a handful of windows does not read as
                // a strong dependence.
                let r2 = (ss_fit / ss_tot).clamp(0.0, 1.0);
                let adjusted = 1.0 - (1.0 - r2) * (n as f64 - 1.0) / (n as f64 - 3.0);
                correlation = Some(adjusted.max(0.0).sqrt());
                note = Some(format!(
                    "largest heading toward {:.0}°",
                    b2.atan2(b1).to_degrees().rem_euclid(360.0)
                ));
            }
        }
    }
    Condition {
        name: "heading",
        unit: "deg",
        per_window,
        correlation,
        note,
    }
}

/// How the position error grows within a window once the model flies on its own: exponent k
/// of `e ∝ τ^k`, τ the time since `origin_s` into each window (where the start fit ended: the
/// comparison should have fitted its starts over that span only, so that beyond it the model
/// drifts from a known state). The squared error the measurement noise alone gives,
/// `noise_m2` (position, m²), is taken off first, so noise does not read as "no growth" when
/// a small drift rides on it. Fitted on the RMS per time bin from a fifth of the way on.
pub fn growth_exponent(
    data: &FlightData,
    cmp: &Comparison,
    origin_s: f64,
    noise_m2: f64,
) -> Option<f64> {
    const BINS: usize = 20;
    let span = cmp
        .windows
        .iter()
        .map(|w| w.t1 - w.t0 - origin_s)
        .fold(0.0f64, f64::max);
    if span.is_nan() || span <= 0.0 {
        return None;
    }
    let mut sum = [0.0f64; BINS];
    let mut count = [0.0f64; BINS];
    let p = &cmp.prediction;
    let mut k = 0;
    for w in &cmp.windows {
        for i in w.samples.0..w.samples.1 {
            let tau = data.time[i] - w.t0 - origin_s;
            if tau > 0.0 && k < p.pos_ned.len() {
                let bin = ((tau / span * BINS as f64) as usize).min(BINS - 1);
                sum[bin] += (p.pos_ned[k] - data.pos_ned[i]).length_squared();
                count[bin] += 1.0;
            }
            k += 1;
        }
    }
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for b in BINS / 5..BINS {
        let excess = if count[b] > 0.0 {
            sum[b] / count[b] - noise_m2
        } else {
            0.0
        };
        if excess > 0.0 {
            let tau = (b as f64 + 0.5) / BINS as f64 * span;
            xs.push(tau.ln());
            ys.push(excess.sqrt().ln());
        }
    }
    if xs.len() < 3 {
        return (count.iter().sum::<f64>() > 0.0).then_some(0.0);
    }
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Plain-language reading of a growth exponent.
pub fn explain_growth(k: f64) -> &'static str {
    if k < 0.4 {
        "the error does not grow: measurement noise"
    } else if k < 1.5 {
        "the error grows ∝ t: a velocity offset (e.g. the air moving: wind)"
    } else if k < 2.5 {
        "the error grows ∝ t²: a constant unmodelled acceleration (a force)"
    } else {
        "the error grows ∝ t³ or faster: an unmodelled moment or attitude effect"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_readings() {
        assert!(explain_growth(2.0).contains("t²"));
        assert!(explain_growth(1.0).contains("∝ t:"));
        assert!(explain_growth(0.1).contains("noise"));
    }
}
