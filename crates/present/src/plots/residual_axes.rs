//! `residuals_per_axis.png`: predicted − measured against time for every axis of every channel
//! the data have — position N/E/D, velocity N/E/D, roll/pitch/yaw, body rates p/q/r,
//! airspeed, the accelerometer's x/y/z, α, β — the same axes and signs as the per-axis table of `compare`. The model as
//! given is drawn light, the model with the added effects solid on top of it; each axis is
//! symmetric about zero and reaches the largest error drawn (no peak is cut off).
//!
//! One file per plot: this one holds which residuals are shown; the shared look is in
//! [`super::style`].

use glam::DVec3;
use plotters::prelude::*;

use super::style::{
    draw_hline_dashed, header, panel, shade, Key, Root, AFTER, BEFORE, BEFORE_LIGHT, NOISE,
};
use super::{window_segments, CanvasError, PlotContext, Segments};
use wireflight_analysis::compare::{estimate_noise, Comparison, Prediction};
use wireflight_data::{Channel, FlightData};
use wireflight_flight::model::air_angles;

/// One axis's residual: predicted − measured at prediction index `k` of sample `i`.
type Residual<'f> = Box<dyn Fn(&Prediction, usize, usize) -> f64 + 'f>;

/// One panel: its caption, unit, residual and measured noise (1σ, when known).
struct Axis<'f> {
    channel: &'static str,
    axis: &'static str,
    unit: &'static str,
    residual: Residual<'f>,
    noise: Option<f64>,
}

impl Axis<'_> {
    /// The channels whose samples the residual reads: α and β the velocity and the attitude.
    fn measured(&self) -> &'static [Channel] {
        match (self.channel, self.axis) {
            ("position", _) => &[Channel::Position],
            ("velocity", _) => &[Channel::Velocity],
            ("attitude", _) => &[Channel::Attitude],
            ("rates", _) => &[Channel::Rates],
            ("accel", _) => &[Channel::Accelerometer],
            ("air", "airspeed") => &[Channel::Airspeed],
            _ => &[Channel::Velocity, Channel::Attitude],
        }
    }
}

/// An angle difference wrapped to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    if w == -std::f64::consts::PI {
        std::f64::consts::PI
    } else {
        w
    }
}

/// α and β the measurements give in the model's air: the measured velocity less the wind
/// the prediction flew in (its ground velocity less its air velocity), in the measured body
/// axes. Degrees.
fn measured_air_deg(d: &FlightData, p: &Prediction, k: usize, i: usize) -> Option<(f64, f64)> {
    let (v, att) = (d.vel_ned.as_ref()?, d.attitude.as_ref()?);
    let a = p.air.get(k)?;
    let va = a.airspeed;
    let air_body = DVec3::new(
        va * a.alpha.cos() * a.beta.cos(),
        va * a.beta.sin(),
        va * a.alpha.sin() * a.beta.cos(),
    );
    let wind = p.vel_ned[k] - p.attitude[k].to_matrix() * air_body;
    let m = air_angles(att[i].to_matrix().transpose() * (v[i] - wind), 1.0);
    Some((m.alpha.to_degrees(), m.beta.to_degrees()))
}

/// The axes the comparison measured, in the order of its per-axis table.
fn axes<'f>(d: &'f FlightData, cmp: &Comparison) -> Vec<Axis<'f>> {
    let noise = estimate_noise(d);
    let has = |channel: &str, axis: &str| {
        cmp.axes
            .iter()
            .any(|a| a.channel == channel && a.axis == axis)
    };
    let mut out: Vec<Axis> = Vec::new();
    for (k, axis) in ["north", "east", "down"].into_iter().enumerate() {
        if has("position", axis) {
            out.push(Axis {
                channel: "position",
                axis,
                unit: "m",
                residual: Box::new(move |p: &Prediction, j, i| p.pos_ned[j][k] - d.pos_ned[i][k]),
                noise: Some(noise.pos_axes[k]),
            });
        }
    }
    if let Some(v) = &d.vel_ned {
        for (k, axis) in ["north", "east", "down"].into_iter().enumerate() {
            if has("velocity", axis) {
                out.push(Axis {
                    channel: "velocity",
                    axis,
                    unit: "m/s",
                    residual: Box::new(move |p: &Prediction, j, i| p.vel_ned[j][k] - v[i][k]),
                    noise: (!d.is_derived("vel_ned")).then_some(noise.vel_axes[k]),
                });
            }
        }
    }
    if let Some(att) = &d.attitude {
        for (k, axis) in ["roll", "pitch", "yaw"].into_iter().enumerate() {
            if has("attitude", axis) {
                let angle =
                    move |e: &wireflight_geometry::euler::EulerZyx| [e.roll, e.pitch, e.yaw][k];
                out.push(Axis {
                    channel: "attitude",
                    axis,
                    unit: "°",
                    residual: Box::new(move |p: &Prediction, j, i| {
                        wrap(angle(&p.attitude[j]) - angle(&att[i])).to_degrees()
                    }),
                    noise: Some(noise.att_axes[k].to_degrees()),
                });
            }
        }
    }
    if let Some(w) = &d.rates_body {
        for (k, axis) in ["p", "q", "r"].into_iter().enumerate() {
            if has("rates", axis) {
                out.push(Axis {
                    channel: "rates",
                    axis,
                    unit: "°/s",
                    residual: Box::new(move |p: &Prediction, j, i| {
                        (p.rates[j][k] - w[i][k]).to_degrees()
                    }),
                    noise: Some(noise.rate_axes[k].to_degrees()),
                });
            }
        }
    }
    if let Some(s) = &d.airspeed {
        if has("air", "airspeed") {
            out.push(Axis {
                channel: "air",
                axis: "airspeed",
                unit: "m/s",
                residual: Box::new(move |p: &Prediction, j, i| p.air[j].airspeed - s[i]),
                noise: Some(noise.airspeed_mps),
            });
        }
    }
    if let Some(a) = &d.accel_body {
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            if has("accel", axis) {
                out.push(Axis {
                    channel: "accel",
                    axis,
                    unit: "m/s²",
                    residual: Box::new(move |p: &Prediction, j, i| {
                        p.specific_force[j][k] - a[i][k]
                    }),
                    noise: Some(noise.accel_axes[k]),
                });
            }
        }
    }
    if has("air", "alpha") {
        out.push(Axis {
            channel: "air",
            axis: "α",
            unit: "°",
            residual: Box::new(move |p: &Prediction, j, i| {
                measured_air_deg(d, p, j, i)
                    .map_or(f64::NAN, |(alpha, _)| p.air[j].alpha.to_degrees() - alpha)
            }),
            noise: None,
        });
    }
    if has("air", "beta") {
        out.push(Axis {
            channel: "air",
            axis: "β",
            unit: "°",
            residual: Box::new(move |p: &Prediction, j, i| {
                measured_air_deg(d, p, j, i)
                    .map_or(f64::NAN, |(_, beta)| p.air[j].beta.to_degrees() - beta)
            }),
            noise: None,
        });
    }
    out
}

/// Half-height of a symmetric axis that shows every value drawn (and the noise band), with a
/// little room.
fn half_height(segs: &[&Segments], noise: Option<f64>) -> f64 {
    let m = segs
        .iter()
        .flat_map(|s| s.iter().flatten())
        .map(|p| p.1.abs())
        .filter(|v| v.is_finite())
        .fold(noise.unwrap_or(0.0), f64::max);
    if m > 0.0 && m.is_finite() {
        m * 1.08
    } else {
        1.0
    }
}

/// The number of panel rows for a comparison's axes (three panels a row; the air data's
/// airspeed, α and β share one).
pub(super) fn rows(cmp: &Comparison) -> usize {
    let mut channels: Vec<&str> = cmp.axes.iter().map(|a| a.channel).collect();
    channels.dedup();
    channels.len().max(1)
}

/// Draws `residuals_per_axis.png` into `root`.
pub(super) fn draw_residual_axes(root: &Root, ctx: &PlotContext) -> Result<(), CanvasError> {
    let d = ctx.data;
    let mut title = "Residuals per axis (predicted − measured)".to_string();
    let mut legend = Vec::new();
    match ctx.after_name() {
        Some(after) => {
            title.push_str(" — before and after");
            legend.push((
                Key::Line(BEFORE_LIGHT, 2),
                format!("{} (before)", ctx.model_name),
            ));
            legend.push((Key::Line(AFTER.to_rgba(), 2), after));
        }
        None => legend.push((Key::Line(BEFORE.to_rgba(), 2), ctx.model_name.clone())),
    }
    legend.push((Key::Dashed(NOISE), "±1σ measurement noise".into()));
    legend.push((Key::Band(super::style::SHADE), "worst windows".into()));
    let body = header(
        root,
        &title,
        &ctx.subtitle(", each window restarts from its fitted start"),
        &legend,
    )?;
    let axes = axes(d, ctx.before);
    let mut channels: Vec<&str> = axes.iter().map(|a| a.channel).collect();
    channels.dedup();
    let cells = body.split_evenly((channels.len().max(1), 3));
    let worst = ctx.worst_spans();
    let mut col = 0;
    let mut row = 0;
    for (n, a) in axes.iter().enumerate() {
        if n > 0 && axes[n - 1].channel != a.channel {
            row += 1;
            col = 0;
        }
        let measured = a.measured();
        let before = window_segments(d, ctx.before, measured, a.residual.as_ref());
        let after = ctx
            .after
            .map(|(c, _)| window_segments(d, c, measured, a.residual.as_ref()))
            .unwrap_or_default();
        let h = half_height(&[&before, &after], a.noise);
        let last_row = row + 1 == channels.len();
        let mut chart = panel(
            &cells[row * 3 + col],
            &format!("{} {}", a.channel, a.axis),
            ctx.t_range.clone(),
            -h..h,
            last_row.then_some("time (s)"),
            &format!("error ({})", a.unit),
            6,
            5,
        )?;
        shade(&mut chart, &worst)?;
        let (before_style, after_style) = if ctx.after.is_some() {
            (BEFORE_LIGHT.stroke_width(2), AFTER.stroke_width(1))
        } else {
            (BEFORE.stroke_width(2), AFTER.stroke_width(2))
        };
        for s in &before {
            super::style::draw_line(&mut chart, s, before_style)?;
        }
        for s in &after {
            super::style::draw_line(&mut chart, s, after_style)?;
        }
        if let Some(sigma) = a.noise.filter(|s| *s > 0.0 && s.is_finite()) {
            draw_hline_dashed(&mut chart, sigma, NOISE)?;
            draw_hline_dashed(&mut chart, -sigma, NOISE)?;
        }
        col += 1;
    }
    Ok(())
}
