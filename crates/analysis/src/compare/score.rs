//! A comparison put together from its windows: the per-channel RMS errors, the total, the
//! misfit and its degrees of freedom, and the per-axis signed mean and RMS that say where the
//! model is off.

use rayon::prelude::*;

use super::attitude::wrap;
use super::predict::Predicted;
use super::start::param_count;
use super::{
    AxisError, ChannelErrors, Comparison, Prediction, Prepared, WindowOutcome, WindowResult,
    MAX_ROWS,
};
use wireflight_data::Channel;
use wireflight_flight::model::{AirData, Model};
use wireflight_geometry::euler::EulerZyx;

/// The comparison of `model` from the outcomes of its windows, in time order.
pub(super) fn assemble(model: &Model, prep: &Prepared, outcomes: Vec<WindowOutcome>) -> Comparison {
    assemble_as(model, prep, outcomes, true)
}

/// [`assemble`], with the per-sample prediction and the per-axis errors only `in_detail`:
/// without, the windows, channel errors, total and misfit alone (what scores a candidate
/// correction; its predictions are a hundred megabytes on an hour at 100 Hz, and their air
/// data and axes a twentieth of a diagnosis).
pub(super) fn assemble_as(
    model: &Model,
    prep: &Prepared,
    outcomes: Vec<WindowOutcome>,
    in_detail: bool,
) -> Comparison {
    let m = prep.measured.for_vehicle(model);
    let samples = if in_detail {
        outcomes.iter().map(|o| o.predicted.len()).sum()
    } else {
        0
    };
    let mut prediction = Prediction::with_capacity(samples);
    let mut windows = Vec::with_capacity(outcomes.len());
    let (mut sp, mut sv, mut sa, mut sr, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut chi2, mut rows) = (0.0, 0usize);
    let air: Vec<Vec<AirData>> = outcomes
        .par_iter()
        .map(|o| match in_detail {
            true => o.predicted.iter().map(Predicted::air).collect(),
            false => Vec::new(),
        })
        .collect();
    for (o, air) in outcomes.into_iter().zip(air) {
        let (start, end) = o.result.samples;
        if in_detail {
            for ((k, i), air) in (start..end).enumerate().zip(air) {
                prediction.push(i, &o.predicted[k], air);
            }
        }
        let w = (end - start) as f64;
        let e = &o.result.errors;
        sp += e.position_m.powi(2) * w;
        sv += e.velocity_mps.unwrap_or(0.0).powi(2) * w;
        sa += e.attitude_deg.unwrap_or(0.0).powi(2) * w;
        sr += e.rate_dps.unwrap_or(0.0).powi(2) * w;
        n += w;
        chi2 += o.result.chi2;
        rows += o.result.residuals;
        windows.push(o.result);
    }
    let n = n.max(1.0);
    let channels = ChannelErrors {
        position_m: (sp / n).sqrt(),
        velocity_mps: m.velocity.then(|| (sv / n).sqrt()),
        attitude_deg: m.attitude.then(|| (sa / n).sqrt()),
        rate_dps: m.rates.then(|| (sr / n).sqrt()),
    };
    let fitted = if prep.cfg.start_iterations > 0 {
        windows.len() * param_count(model)
    } else {
        0
    };
    let axes = match in_detail {
        true => axis_errors(model, prep, &prediction),
        false => Vec::new(),
    };
    Comparison {
        total: total_score(&windows),
        channels,
        windows,
        prediction,
        axes,
        chi2,
        dof: rows.saturating_sub(fitted) as f64,
        colour_floor: prep.cfg.colour_floor.unwrap_or([1.0; MAX_ROWS]),
    }
}

/// RMS of window scores, weighted by window length in samples.
fn total_score(windows: &[WindowResult]) -> f64 {
    let (mut s, mut n) = (0.0, 0.0);
    for w in windows {
        let m = (w.samples.1 - w.samples.0) as f64;
        s += w.score * w.score * m;
        n += m;
    }
    if n > 0.0 {
        (s / n).sqrt()
    } else {
        0.0
    }
}

/// Per-axis signed mean and RMS of predicted − measured. The axes are summed side by side,
/// each in sample order: on an hour at 100 Hz they are millions of terms, a serial stretch of
/// a diagnosis otherwise.
fn axis_errors(model: &Model, prep: &Prepared, p: &Prediction) -> Vec<AxisError> {
    type Term<'a> = Box<dyn Fn(usize, usize) -> f64 + Sync + 'a>;
    let d = prep.data;
    let m = prep.measured.for_vehicle(model);
    // α and β as the measurements give them, in the model's air: from the measured velocity
    // and attitude, less the model's wind (once per sample for both).
    let measured_air: Vec<AirData> = match (m.velocity, m.attitude, &d.vel_ned, &d.attitude) {
        (true, true, Some(v), Some(a)) => p
            .index
            .par_iter()
            .map(|&i| {
                let v_r =
                    a[i].to_matrix().transpose() * (v[i] - model.wind_at(d.pos_ned[i], d.time[i]));
                wireflight_flight::model::air_angles(v_r, 1.0)
            })
            .collect(),
        _ => Vec::new(),
    };
    // Each axis with the channels its measurement needs sampled (both for α and β).
    let mut axes: Vec<(&'static str, &'static str, &'static str, Term, [Channel; 2])> = Vec::new();
    for (k, axis) in ["north", "east", "down"].into_iter().enumerate() {
        let term = move |j: usize, i: usize| p.pos_ned[j][k] - d.pos_ned[i][k];
        axes.push((
            "position",
            axis,
            "m",
            Box::new(term),
            [Channel::Position; 2],
        ));
    }
    if let (true, Some(v)) = (m.velocity, &d.vel_ned) {
        for (k, axis) in ["north", "east", "down"].into_iter().enumerate() {
            let term = move |j: usize, i: usize| p.vel_ned[j][k] - v[i][k];
            axes.push((
                "velocity",
                axis,
                "m/s",
                Box::new(term),
                [Channel::Velocity; 2],
            ));
        }
    }
    if let (true, Some(a)) = (m.attitude, &d.attitude) {
        let angle = |e: &EulerZyx, k: usize| [e.roll, e.pitch, e.yaw][k];
        for (k, axis) in ["roll", "pitch", "yaw"].into_iter().enumerate() {
            let term = move |j: usize, i: usize| {
                wrap(angle(&p.attitude[j], k) - angle(&a[i], k)).to_degrees()
            };
            axes.push((
                "attitude",
                axis,
                "deg",
                Box::new(term),
                [Channel::Attitude; 2],
            ));
        }
    }
    if let (true, Some(w)) = (m.rates, &d.rates_body) {
        for (k, axis) in ["p", "q", "r"].into_iter().enumerate() {
            let term = move |j: usize, i: usize| (p.rates[j][k] - w[i][k]).to_degrees();
            axes.push(("rates", axis, "deg/s", Box::new(term), [Channel::Rates; 2]));
        }
    }
    if let (true, Some(s)) = (m.airspeed, &d.airspeed) {
        let term = move |j: usize, i: usize| p.air[j].airspeed - s[i];
        axes.push((
            "air",
            "airspeed",
            "m/s",
            Box::new(term),
            [Channel::Airspeed; 2],
        ));
    }
    if let (true, Some(a)) = (m.accel, &d.accel_body) {
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let term = move |j: usize, i: usize| p.specific_force[j][k] - a[i][k];
            axes.push((
                "accel",
                axis,
                "m/s^2",
                Box::new(term),
                [Channel::Accelerometer; 2],
            ));
        }
    }
    if !measured_air.is_empty() {
        let air = &measured_air;
        let alpha = move |j: usize, _: usize| (p.air[j].alpha - air[j].alpha).to_degrees();
        let beta = move |j: usize, _: usize| (p.air[j].beta - air[j].beta).to_degrees();
        axes.push((
            "air",
            "alpha",
            "deg",
            Box::new(alpha),
            [Channel::Velocity, Channel::Attitude],
        ));
        axes.push((
            "air",
            "beta",
            "deg",
            Box::new(beta),
            [Channel::Velocity, Channel::Attitude],
        ));
    }
    axes.par_iter()
        .filter_map(|(channel, axis, unit, term, needs)| {
            let (mut s, mut s2, mut n) = (0.0, 0.0, 0.0);
            for v in p
                .index
                .iter()
                .enumerate()
                .filter(|&(_, &i)| needs.iter().all(|&c| d.sampling.at(c, i)))
                .map(|(j, &i)| term(j, i))
                .filter(|v| v.is_finite())
            {
                s += v;
                s2 += v * v;
                n += 1.0;
            }
            (n > 0.0).then(|| AxisError {
                channel,
                axis,
                unit,
                mean: s / n,
                rms: (s2 / n).sqrt(),
            })
        })
        .collect()
}
