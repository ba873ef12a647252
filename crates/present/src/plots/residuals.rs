//! `residuals.png`: the window score and the per-sample prediction error of each channel
//! against time, before (and after), the worst windows shaded, the noise floor and the
//! measurement noise as dashed lines.
//!
//! One file per plot: this one holds which errors are shown and how they are scaled; the
//! shared look is in [`super::style`].

use plotters::prelude::*;

use super::style::{
    axis_top, draw_hline_dashed, draw_line, header, panel, shade, Key, Root, AFTER, BEFORE,
    BEFORE_LIGHT, NOISE, SHADE,
};
use super::{window_segments, CanvasError, PlotContext, Segments};
use wireflight_analysis::compare::{estimate_noise, Comparison, Prediction};
use wireflight_data::Channel;
use wireflight_draw::figures::three_figures;
use wireflight_flight::numeric::attitude_error_deg;

/// The title of `residuals.png`: the total error before (→ after) and the noise floor.
pub(super) fn title(ctx: &PlotContext) -> String {
    let mut title = format!(
        "Residuals — total error {}",
        three_figures(ctx.before.total)
    );
    if let Some((a, _)) = ctx.after {
        title.push_str(&format!(" → {}", three_figures(a.total)));
    }
    if let Some(f) = ctx.noise_floor {
        title.push_str(&format!("  (noise floor {})", three_figures(f)));
    }
    title
}

/// Draws `residuals.png` into `root`.
pub(super) fn draw_residuals(root: &Root, ctx: &PlotContext) -> Result<(), CanvasError> {
    let d = ctx.data;
    let worst = ctx.worst_spans();
    let title = title(ctx);
    let before_key = if ctx.after.is_some() {
        BEFORE_LIGHT
    } else {
        BEFORE.to_rgba()
    };
    let mut legend = vec![(Key::Line(before_key, 2), ctx.model_name.clone())];
    if let Some(name) = ctx.after_name() {
        legend.push((Key::Line(AFTER.to_rgba(), 2), name));
    }
    legend.push((
        Key::Dashed(NOISE),
        if ctx.noise_floor.is_some() {
            "noise floor / measurement noise (RMS)"
        } else {
            "measurement noise (RMS)"
        }
        .into(),
    ));
    legend.push((
        Key::Band(SHADE),
        format!("worst window{}", if worst.len() == 1 { "" } else { "s" }),
    ));
    let body = header(
        root,
        &title,
        &ctx.subtitle(", errors per sample restart with each window"),
        &legend,
    )?;

    let noise = estimate_noise(d);
    // |error| of a 3-axis quantity with independent noise σ per axis has RMS √3·σ.
    let s3 = 3f64.sqrt();
    type ErrFn<'f> = Box<dyn Fn(&Prediction, usize, usize) -> f64 + 'f>;
    let mut channels: Vec<(&str, &str, ErrFn, Option<f64>, Channel)> = vec![(
        "position error |Δp|",
        "error (m)",
        Box::new(|p: &Prediction, k, i| (p.pos_ned[k] - d.pos_ned[i]).length()),
        Some(s3 * noise.pos_m),
        Channel::Position,
    )];
    if let (true, Some(v)) = (ctx.has_vel, &d.vel_ned) {
        channels.push((
            "velocity error |Δv|",
            "error (m/s)",
            Box::new(move |p: &Prediction, k, i| (p.vel_ned[k] - v[i]).length()),
            (!d.is_derived("vel_ned")).then_some(s3 * noise.vel_mps),
            Channel::Velocity,
        ));
    }
    if let (true, Some(att)) = (ctx.has_att, &d.attitude) {
        channels.push((
            "attitude error (rotation angle)",
            "error (°)",
            Box::new(move |p: &Prediction, k, i| attitude_error_deg(&p.attitude[k], &att[i])),
            Some(s3 * noise.att_rad.to_degrees()),
            Channel::Attitude,
        ));
    }

    let units: Vec<&str> = [
        Some("position m"),
        ctx.has_vel.then_some("velocity m/s"),
        ctx.has_att.then_some("attitude °"),
    ]
    .into_iter()
    .flatten()
    .collect();
    let score_caption = format!("window error score (RMS of {})", units.join(", "));
    let areas = body.split_evenly((channels.len() + 1, 1));
    let n_rows = areas.len();
    let x_desc = |row: usize| (row + 1 == n_rows).then_some("time (s)");

    // Window score.
    let steps = |c: &Comparison| -> Segments {
        c.windows
            .iter()
            .map(|w| vec![(w.t0, w.score), (w.t1, w.score)])
            .collect()
    };
    let before_steps = steps(ctx.before);
    let after_steps = ctx.after.map(|(a, _)| steps(a)).unwrap_or_default();
    let all_scores: Vec<f64> = before_steps
        .iter()
        .chain(&after_steps)
        .map(|s| s[0].1)
        .collect();
    ErrorPanel {
        caption: &score_caption,
        y_desc: "score",
        top: axis_top(all_scores.iter().copied(), ctx.noise_floor, 1.12),
        before: &before_steps,
        after: &after_steps,
        width: 3,
        level: ctx.noise_floor,
    }
    .draw(&areas[0], ctx, x_desc(0), &worst)?;

    // One channel per row.
    for (row, (caption, unit, f, noise_level, channel)) in channels.iter().enumerate() {
        let row = row + 1;
        let measured = [*channel];
        let b = window_segments(d, ctx.before, &measured, f.as_ref());
        let a = ctx
            .after
            .map(|(c, _)| window_segments(d, c, &measured, f.as_ref()))
            .unwrap_or_default();
        let values: Vec<f64> = b.iter().chain(&a).flatten().map(|p| p.1).collect();
        let noise_level = noise_level.filter(|v| *v > 0.0 && v.is_finite());
        ErrorPanel {
            caption,
            y_desc: unit,
            // Every peak shown: the axis reaches the largest error drawn.
            top: axis_top(values.iter().copied(), noise_level, 1.08),
            before: &b,
            after: &a,
            width: 2,
            level: noise_level,
        }
        .draw(&areas[row], ctx, x_desc(row), &worst)?;
    }
    Ok(())
}

/// One panel of the residual plot: an axis from 0 to `top` against time, the worst windows
/// shaded, the before and after lines, and a dashed line at `level` (the noise floor or the
/// measurement noise).
struct ErrorPanel<'s> {
    caption: &'s str,
    y_desc: &'s str,
    top: f64,
    /// Segments of the "before" model, (t, value).
    before: &'s [Vec<(f64, f64)>],
    /// Segments of the "after" model (empty without one).
    after: &'s [Vec<(f64, f64)>],
    /// Line width, pixels.
    width: u32,
    level: Option<f64>,
}

impl ErrorPanel<'_> {
    fn draw(
        &self,
        area: &Root,
        ctx: &PlotContext,
        x_desc: Option<&str>,
        worst: &[(f64, f64)],
    ) -> Result<(), CanvasError> {
        let mut chart = panel(
            area,
            self.caption,
            ctx.t_range.clone(),
            0.0..self.top,
            x_desc,
            self.y_desc,
            10,
            4,
        )?;
        shade(&mut chart, worst)?;
        // With an "after" model the "before" one is drawn light, behind it.
        let before = if self.after.is_empty() {
            BEFORE.stroke_width(self.width)
        } else {
            BEFORE_LIGHT.stroke_width(self.width)
        };
        for (segs, style) in [
            (self.before, before),
            (self.after, AFTER.stroke_width(self.width)),
        ] {
            for s in segs {
                draw_line(&mut chart, s, style)?;
            }
        }
        if let Some(level) = self.level {
            draw_hline_dashed(&mut chart, level, NOISE)?;
        }
        Ok(())
    }
}
