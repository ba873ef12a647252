//! `error_vs_condition.png`: the window score against one flight condition (one dot per
//! window), with the least-squares trend and the correlation in the title.
//!
//! One file per plot: this one holds the scatter and its trend line; the shared look is in
//! [`super::style`].

use plotters::prelude::*;

use super::style::{
    axis_top, clip_y, draw_hline_dashed, finite_min_max, header, padded, panel, unicode_minus, Key,
    Root, AFTER, BEFORE, NOISE,
};
use super::{CanvasError, ConditionSeries, PlotContext};
use wireflight_data::format::signed;
use wireflight_flight::numeric::pearson;

/// The units the score combines, e.g. "m, m/s, °".
fn score_units(ctx: &PlotContext) -> String {
    [
        Some("m"),
        ctx.has_vel.then_some("m/s"),
        ctx.has_att.then_some("°"),
    ]
    .into_iter()
    .flatten()
    .collect::<Vec<_>>()
    .join(", ")
}

/// The title: the condition and its correlation with the window score — the same Pearson
/// r, to two decimals, as `compare`'s "error correlates with" table — before (and after).
pub(super) fn title(ctx: &PlotContext, cond: &ConditionSeries) -> String {
    let x: &[f64] = &cond.per_window;
    let yb: Vec<f64> = ctx.before.windows.iter().map(|w| w.score).collect();
    let rb = pearson(x, &yb);
    let r_text = |r: Option<f64>| r.map_or("n/a".into(), |r| unicode_minus(signed(r, 2)));
    let mut title = format!("Window error vs {} — r = {}", cond.name, r_text(rb));
    if let Some((a, _)) = ctx.after {
        let ya: Vec<f64> = a.windows.iter().map(|w| w.score).collect();
        title.push_str(&format!(" before, {} after", r_text(pearson(x, &ya))));
    }
    title
}

/// Draws `error_vs_condition.png` into `root`, the window score against `cond`.
pub(super) fn draw_error_vs_condition(
    root: &Root,
    ctx: &PlotContext,
    cond: &ConditionSeries,
) -> Result<(), CanvasError> {
    let x: &[f64] = &cond.per_window;
    let yb: Vec<f64> = ctx.before.windows.iter().map(|w| w.score).collect();
    let ya: Option<Vec<f64>> = ctx
        .after
        .map(|(a, _)| a.windows.iter().map(|w| w.score).collect());
    let title = title(ctx, cond);
    let mut legend = vec![(Key::Dot(BEFORE), ctx.model_name.clone())];
    if let Some(name) = ctx.after_name() {
        legend.push((Key::Dot(AFTER), name));
    }
    legend.push((Key::Dashed(BEFORE), "trend (least squares)".into()));
    if ctx.noise_floor.is_some() {
        legend.push((Key::Dashed(NOISE), "noise floor".into()));
    }
    let body = header(
        root,
        &title,
        &ctx.subtitle("; one dot per window, the condition averaged over it"),
        &legend,
    )?;

    let (xlo, xhi) = finite_min_max(x.iter().copied()).unwrap_or((0.0, 1.0));
    let xr = padded(xlo, xhi);
    let ys: Vec<f64> = yb.iter().chain(ya.iter().flatten()).copied().collect();
    let ytop = axis_top(ys.iter().copied(), ctx.noise_floor, 1.1);
    let unit = cond.unit.trim();
    let x_desc = if unit.is_empty() {
        cond.name.clone()
    } else {
        format!("{} ({unit})", cond.name)
    };
    let area = body.margin(10, 10, 10, 10);
    let mut chart = panel(
        &area,
        "",
        xr.clone(),
        -0.025 * ytop..ytop,
        Some(&x_desc),
        &format!("window error score (RMS of {})", score_units(ctx)),
        10,
        8,
    )?;
    if let Some(f) = ctx.noise_floor {
        draw_hline_dashed(&mut chart, f, NOISE)?;
    }
    // Least-squares line of the "before" scores.
    let pairs: Vec<(f64, f64)> = x
        .iter()
        .zip(&yb)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    if pairs.len() >= 2 {
        let n = pairs.len() as f64;
        let mx = pairs.iter().map(|p| p.0).sum::<f64>() / n;
        let my = pairs.iter().map(|p| p.1).sum::<f64>() / n;
        let sxx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
        if sxx > 0.0 {
            let slope = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
            let line: Vec<(f64, f64)> = [xr.start, xr.end]
                .iter()
                .map(|&xv| (xv, my + slope * (xv - mx)))
                .collect();
            for piece in clip_y(&line, 0.0, ytop) {
                chart.draw_series(DashedLineSeries::new(piece, 9, 6, BEFORE.stroke_width(2)))?;
            }
        }
    }
    let dots = |ys: &[f64], color: RGBColor| -> Vec<Circle<(f64, f64), u32>> {
        x.iter()
            .zip(ys)
            .filter(|(a, b)| a.is_finite() && b.is_finite() && **b <= ytop)
            .map(|(a, b)| Circle::new((*a, *b), 6, color.mix(0.85).filled()))
            .collect()
    };
    chart.draw_series(dots(&yb, BEFORE))?;
    if let Some(ya) = &ya {
        chart.draw_series(dots(ya, AFTER))?;
    }
    Ok(())
}
