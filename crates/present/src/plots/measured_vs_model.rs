//! `measured_vs_model.png`: per channel (position, NED velocity, attitude), the measurements
//! and each window's prediction restarted from that window's estimated state, before and
//! (when given) after the added effects.
//!
//! One file per plot: this one holds what the plot shows (the series per panel, angle
//! handling across ±180°) and how it is laid out; the shared look is in [`super::style`].

use glam::DVec3;
use plotters::prelude::*;

use super::style::{
    draw_line, finite_min_max, header, panel, value_range, Key, Root, AFTER, BEFORE, MEASURED,
};
use super::{prediction_windows, window_segments, CanvasError, PlotContext, Segments};
use wireflight_analysis::compare::{Comparison, Prediction};
use wireflight_data::derive::unwrap_angles;
use wireflight_data::FlightData;
use wireflight_geometry::euler::EulerZyx;

/// One quantity plotted against time.
struct Series {
    caption: String,
    /// Axis description with unit.
    y_desc: String,
    measured: Vec<f64>,
    /// Prediction segments of the "before" model, one per window: (t, value).
    before: Segments,
    /// The same for the "after" model.
    after: Segments,
    /// Wrapped angle (degrees): split lines at ±180° jumps.
    wrapped: bool,
}

impl Series {
    /// A quantity that is not a wrapped angle, with its (before, after) prediction segments.
    fn plain(
        caption: String,
        y_desc: String,
        measured: Vec<f64>,
        (before, after): (Segments, Segments),
    ) -> Self {
        Self {
            caption,
            y_desc,
            measured,
            before,
            after,
            wrapped: false,
        }
    }
}

/// Angle segments per window (degrees): unwrapped within the window, then shifted by whole
/// turns to start next to the (unwrapped) measurement.
fn angle_segments(
    data: &FlightData,
    cmp: &Comparison,
    measured_unwrapped: &[f64],
    get: fn(&EulerZyx) -> f64,
) -> Segments {
    let p = &cmp.prediction;
    prediction_windows(cmp)
        .into_iter()
        .filter_map(|(a, k0, len)| {
            let ks: Vec<usize> = (k0..k0 + len)
                .filter(|&k| k < p.index.len() && p.index[k] < data.len())
                .collect();
            if ks.is_empty() {
                return None;
            }
            let raw: Vec<f64> = ks.iter().map(|&k| get(&p.attitude[k])).collect();
            let un = unwrap_angles(&raw);
            let turn = std::f64::consts::TAU;
            let shift = ((measured_unwrapped[a.min(data.len() - 1)] - un[0]) / turn).round() * turn;
            Some(
                ks.iter()
                    .zip(un)
                    .map(|(&k, v)| (data.time[p.index[k]], (v + shift).to_degrees()))
                    .collect(),
            )
        })
        .collect()
}

/// The panels of the plot, row by row: position; NED velocity; attitude (rows whose data or
/// prediction is missing are left out).
fn build_series(ctx: &PlotContext) -> Vec<Vec<Series>> {
    let d = ctx.data;
    let mut rows = Vec::new();
    let after = ctx.after.map(|(c, _)| c);
    let segs = |f: &dyn Fn(&Prediction, usize) -> f64| {
        let f = |p: &Prediction, k: usize, _: usize| f(p, k);
        (
            window_segments(d, ctx.before, &[], &f),
            after
                .map(|a| window_segments(d, a, &[], &f))
                .unwrap_or_default(),
        )
    };

    // Position: North, East and altitude (up reads better than Down).
    let (alt0, alt_caption) = match d.meta.altitude_m {
        Some(a) => (a, "altitude"),
        None => (0.0, "height above origin"),
    };
    let mut row = Vec::new();
    for (caption, axis, get) in [
        (
            "position North",
            "north",
            (|v: DVec3| v.x) as fn(DVec3) -> f64,
        ),
        ("position East", "east", |v: DVec3| v.y),
    ] {
        row.push(Series::plain(
            caption.into(),
            format!("{axis} (m)"),
            d.pos_ned.iter().map(|v| get(*v)).collect(),
            segs(&|p, k| get(p.pos_ned[k])),
        ));
    }
    row.push(Series::plain(
        alt_caption.into(),
        format!("{} (m)", alt_caption.split(' ').next().unwrap_or("height")),
        d.pos_ned.iter().map(|v| alt0 - v.z).collect(),
        segs(&|p, k| alt0 - p.pos_ned[k].z),
    ));
    rows.push(row);

    if let (true, Some(vel)) = (ctx.has_vel, &d.vel_ned) {
        let derived = if d.is_derived("vel_ned") {
            " (derived)"
        } else {
            ""
        };
        let mut row = Vec::new();
        for (caption, axis, get) in [
            (
                "velocity North",
                "north",
                (|v: DVec3| v.x) as fn(DVec3) -> f64,
            ),
            ("velocity East", "east", |v: DVec3| v.y),
            ("velocity Down", "down", |v: DVec3| v.z),
        ] {
            row.push(Series::plain(
                format!("{caption}{derived}"),
                format!("{axis} (m/s)"),
                vel.iter().map(|v| get(*v)).collect(),
                segs(&|p, k| get(p.vel_ned[k])),
            ));
        }
        rows.push(row);
    }

    if let (true, Some(att)) = (ctx.has_att, &d.attitude) {
        let mut row = Vec::new();
        for (caption, axis, get) in [
            (
                "yaw ψ",
                "yaw",
                (|e: &EulerZyx| e.yaw) as fn(&EulerZyx) -> f64,
            ),
            ("pitch θ", "pitch", |e: &EulerZyx| e.pitch),
            ("roll φ", "roll", |e: &EulerZyx| e.roll),
        ] {
            let un = unwrap_angles(&att.iter().map(get).collect::<Vec<_>>());
            let mut measured: Vec<f64> = un.iter().map(|v| v.to_degrees()).collect();
            let mut b = angle_segments(d, ctx.before, &un, get);
            let mut a = after
                .map(|c| angle_segments(d, c, &un, get))
                .unwrap_or_default();
            // Several turns: show wrapped to ±180° (an unwrapped heading over many circles
            // would flatten every detail).
            let (lo, hi) = finite_min_max(measured.iter().copied()).unwrap_or((0.0, 0.0));
            let wrapped = hi - lo > 540.0;
            if wrapped {
                measured.iter_mut().for_each(|v| *v = wrap_deg(*v));
                for seg in b.iter_mut().chain(a.iter_mut()) {
                    seg.iter_mut().for_each(|p| p.1 = wrap_deg(p.1));
                }
            }
            row.push(Series {
                caption: caption.into(),
                y_desc: format!("{axis} (°)"),
                measured,
                before: b,
                after: a,
                wrapped,
            });
        }
        rows.push(row);
    }
    rows
}

/// Draws `measured_vs_model.png` into `root`: a grid of panels, one row per kind of channel.
pub(super) fn draw_measured_vs_model(root: &Root, ctx: &PlotContext) -> Result<(), CanvasError> {
    let mut legend = vec![
        (Key::Line(MEASURED, 1), "measured".to_string()),
        (
            Key::Line(BEFORE.to_rgba(), 2),
            format!("{} (restarted each window)", ctx.model_name),
        ),
    ];
    if let Some(name) = ctx.after_name() {
        legend.push((Key::Line(AFTER.to_rgba(), 2), name));
    }
    let body = header(
        root,
        &format!("Measured vs model — {}", ctx.data_name),
        &ctx.subtitle(", the model restarted from the data at each window start"),
        &legend,
    )?;
    let rows = build_series(ctx);
    let cells = body.split_evenly((rows.len(), 3));
    let t = ctx.data.time.as_slice();
    for (r, row) in rows.iter().enumerate() {
        for (c, s) in row.iter().enumerate() {
            let area = &cells[r * 3 + c];
            let last_row = r + 1 == rows.len();
            let preds = s
                .before
                .iter()
                .chain(&s.after)
                .flat_map(|seg| seg.iter().map(|p| p.1));
            let y = if s.wrapped {
                -190.0..190.0
            } else {
                value_range(&s.measured, preds)
            };
            let mut chart = panel(
                area,
                &s.caption,
                ctx.t_range.clone(),
                y,
                last_row.then_some("time (s)"),
                &s.y_desc,
                6,
                5,
            )?;
            let measured: Vec<(f64, f64)> =
                t.iter().copied().zip(s.measured.iter().copied()).collect();
            let split = |pts: &[(f64, f64)]| {
                if s.wrapped {
                    split_wraps(pts)
                } else {
                    vec![pts.to_vec()]
                }
            };
            for (segs, color) in [(&s.before, BEFORE), (&s.after, AFTER)] {
                for seg in segs {
                    for piece in split(seg) {
                        draw_line(&mut chart, &piece, color.stroke_width(2))?;
                    }
                    // Mark the restart.
                    if let Some(&(t0, v0)) = seg.first() {
                        let yr = chart.y_range();
                        if v0.is_finite() && v0 >= yr.start && v0 <= yr.end {
                            chart.draw_series(std::iter::once(Circle::new(
                                (t0, v0),
                                3,
                                color.filled(),
                            )))?;
                        }
                    }
                }
            }
            // Measurements last, thin and translucent: visible where the model lies on them.
            for piece in split(&measured) {
                draw_line(&mut chart, &piece, MEASURED.stroke_width(1))?;
            }
        }
    }
    Ok(())
}

/// Split a wrapped-angle series (degrees) where it jumps by more than 180°, running each
/// piece out to the ±180° edge it crosses.
fn split_wraps(pts: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for (i, &q) in pts.iter().enumerate() {
        if i > 0 {
            let p = pts[i - 1];
            if (q.1 - p.1).abs() > 180.0 {
                // Where the unwrapped step from p crosses the edge.
                let q_un = q.1 + 360.0 * ((p.1 - q.1) / 360.0).round();
                let edge = if q_un > p.1 { 180.0 } else { -180.0 };
                let f = ((edge - p.1) / (q_un - p.1)).clamp(0.0, 1.0);
                let t = p.0 + f * (q.0 - p.0);
                // `out` starts with one piece and only grows: never empty.
                out.last_mut().expect("non-empty").push((t, edge));
                out.push(vec![(t, -edge)]);
            }
        }
        out.last_mut().expect("non-empty").push(q);
    }
    out
}

/// An angle in degrees wrapped to (−180°, 180°].
fn wrap_deg(a: f64) -> f64 {
    let w = (a + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 {
        180.0
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps() {
        assert_eq!(wrap_deg(190.0), -170.0);
        assert_eq!(wrap_deg(-180.0), 180.0);
        let pieces = split_wraps(&[(0.0, 170.0), (1.0, -170.0), (2.0, -160.0)]);
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0], vec![(0.0, 170.0), (0.5, 180.0)]);
        assert_eq!(pieces[1], vec![(0.5, -180.0), (1.0, -170.0), (2.0, -160.0)]);
    }
}
