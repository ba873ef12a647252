//! What a replay frame says about itself, drawn over the 3D scene in pixel coordinates: the
//! time stamp, the labelled error strip of a comparison (title with units, value axis,
//! time axis, a cursor with the error now), the raw samples as faint dots under the smoothed
//! trail, and an arrow at the frame's edge towards an aircraft the camera does not see.
//!
//! Also the smoothing of the trail ([`smooth_path`]). Pure: no I/O.

use glam::{Mat4, Vec2, Vec3};

use super::font::{draw_label, label_width};
use crate::figures::three_figures;
use crate::render::Segment2;
use wireflight_flight::numeric::format::fixed;
use wireflight_geometry::pipeline::Viewport;

/// Height of the text, pixels, for a frame of this size (7..=16 px, about 1/45 of the height).
pub fn text_height(viewport: Viewport) -> f32 {
    (viewport.height as f32 / 45.0).clamp(7.0, 16.0).round()
}

/// The time stamp, top left: `T 12.3 S / 31.0 S`.
pub fn time_stamp(t: f64, t_end: f64, viewport: Viewport, out: &mut Vec<Segment2>) {
    let h = text_height(viewport);
    draw_label(
        &format!("T {} S / {} S", fixed(t, 1), fixed(t_end, 1)),
        Vec2::new(h, h),
        h,
        out,
    );
}

/// The strip of a comparison frame: where it is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripBox {
    /// Left, right, top, bottom edges of the plot, pixels.
    pub left: f32,
    /// Right edge.
    pub right: f32,
    /// Top edge (the full-scale value).
    pub top: f32,
    /// Bottom edge (zero).
    pub bottom: f32,
}

impl StripBox {
    /// The strip's place in a frame: the bottom fifth, with room for a title above and time
    /// labels below.
    pub fn of(viewport: Viewport) -> Self {
        let (w, h) = (viewport.width as f32, viewport.height as f32);
        let th = text_height(viewport);
        let bottom = h - 1.8 * th;
        let top = (bottom - h / 6.0).max(2.5 * th);
        Self {
            left: 2.0 * th,
            right: (w - 2.0 * th).max(2.0 * th + 1.0),
            top,
            bottom,
        }
    }
}

/// The error over time as a labelled plot: baseline and value axis with ticks, the error as a
/// polyline (per pixel column the largest value, so spikes survive), a cursor at `t` with the
/// error now, a title naming the quantity and its unit, and the times at both ends.
///
/// `time` and `error_m` are per sample (same length, times increasing); `scale_m` is the value
/// at the top of the strip.
#[allow(clippy::too_many_arguments)]
pub fn error_strip(
    time: &[f64],
    error_m: &[f64],
    scale_m: f64,
    t: f64,
    viewport: Viewport,
    title: &str,
    out: &mut Vec<Segment2>,
) {
    let n = time.len().min(error_m.len());
    if n == 0 {
        return;
    }
    let b = StripBox::of(viewport);
    let th = text_height(viewport);
    let seg = |a: Vec2, c: Vec2, out: &mut Vec<Segment2>| out.push(Segment2 { a, b: c });
    let (t0, t1) = (time[0], time[n - 1]);
    let span = (t1 - t0).max(1e-9);
    let peak = if scale_m > 0.0 { scale_m } else { 1.0 };
    let x_of = |s: f64| b.left + ((s - t0) / span) as f32 * (b.right - b.left);
    let y_of = |e: f64| b.bottom - (e / peak).clamp(0.0, 1.0) as f32 * (b.bottom - b.top);
    // Axes: time along the bottom, value up the left, ticks at zero, half and full scale.
    seg(
        Vec2::new(b.left, b.bottom),
        Vec2::new(b.right, b.bottom),
        out,
    );
    seg(Vec2::new(b.left, b.bottom), Vec2::new(b.left, b.top), out);
    for f in [0.5f32, 1.0] {
        let y = b.bottom - f * (b.bottom - b.top);
        seg(Vec2::new(b.left - 0.5 * th, y), Vec2::new(b.left, y), out);
    }
    let small = (0.8 * th).round().max(6.0);
    draw_label(
        &format!("{} M", three_figures(peak)),
        Vec2::new(b.left + 0.4 * th, b.top - 0.1 * small),
        small,
        out,
    );
    draw_label(title, Vec2::new(b.left, b.top - 1.5 * th), th, out);
    // Times at the ends.
    let start = format!("{} S", three_figures(t0));
    let end = format!("{} S", three_figures(t1));
    draw_label(&start, Vec2::new(b.left, b.bottom + 0.4 * th), small, out);
    draw_label(
        &end,
        Vec2::new(b.right - label_width(&end, small), b.bottom + 0.4 * th),
        small,
        out,
    );
    // The error, per pixel column its largest value.
    let columns = (b.right - b.left).max(1.0) as usize;
    let mut column_max = vec![f64::NAN; columns + 1];
    for k in 0..n {
        let c = ((x_of(time[k]) - b.left).max(0.0) as usize).min(columns);
        let e = error_m[k];
        if e.is_finite() && (column_max[c].is_nan() || e > column_max[c]) {
            column_max[c] = e;
        }
    }
    let mut last: Option<Vec2> = None;
    for (c, e) in column_max.iter().enumerate() {
        if e.is_nan() {
            continue;
        }
        let p = Vec2::new(b.left + c as f32, y_of(*e));
        if let Some(q) = last {
            seg(q, p, out);
        }
        last = Some(p);
    }
    // The cursor, with the error now beside it.
    let tc = t.clamp(t0, t1);
    let x = x_of(tc);
    seg(Vec2::new(x, b.top), Vec2::new(x, b.bottom), out);
    let k = time[..n].partition_point(|&s| s <= tc).clamp(1, n) - 1;
    let now = format!("{} M", three_figures(error_m[k]));
    let w = label_width(&now, small);
    let lx = if x + 0.4 * th + w < b.right {
        x + 0.4 * th
    } else {
        x - 0.4 * th - w
    };
    draw_label(&now, Vec2::new(lx, b.top + 0.3 * th), small, out);
}

/// Where `p` (world) lands in the frame: pixel coordinates when it is in front of the eye and
/// inside the frame, else `Err` with the direction from the frame's centre towards it (pixels,
/// y down; for a point behind the eye, the direction it would have, turned round).
pub fn locate(p: Vec3, clip_from_world: Mat4, viewport: Viewport) -> Result<Vec2, Vec2> {
    let c = clip_from_world * p.extend(1.0);
    let w = c.w;
    if w > 1e-6 && c.x.abs() <= w && c.y.abs() <= w {
        return Ok(viewport.to_pixels(Vec2::new(c.x / w, c.y / w)));
    }
    // Direction in NDC (y up) → pixels (y down); behind the eye the projection mirrors.
    let mut d = Vec2::new(c.x, -c.y);
    if w < 0.0 {
        d = -d;
    }
    Err(if d.length_squared() > 0.0 {
        d.normalize()
    } else {
        Vec2::Y
    })
}

/// A small `+` at each raw sample that lands in the frame.
pub fn sample_dots(
    points: &[Vec3],
    clip_from_world: Mat4,
    viewport: Viewport,
    out: &mut Vec<Segment2>,
) {
    for p in points {
        if let Ok(q) = locate(*p, clip_from_world, viewport) {
            out.push(Segment2 {
                a: q - Vec2::X,
                b: q + Vec2::X,
            });
            out.push(Segment2 {
                a: q - Vec2::Y,
                b: q + Vec2::Y,
            });
        }
    }
}

/// An arrow just inside the frame's edge pointing along `direction` (pixels, y down, unit)
/// from the centre, with `label` beside it.
pub fn edge_arrow(direction: Vec2, label: &str, viewport: Viewport, out: &mut Vec<Segment2>) {
    let (w, h) = (viewport.width as f32, viewport.height as f32);
    let th = text_height(viewport);
    let centre = Vec2::new(w / 2.0, h / 2.0);
    let d = if direction.is_finite() && direction.length_squared() > 0.0 {
        direction.normalize()
    } else {
        Vec2::Y
    };
    // Where the ray from the centre meets a box inset from the edges (above the strip).
    let inset = 2.5 * th;
    let half = Vec2::new(
        (w / 2.0 - inset).max(1.0),
        (h / 2.0 - inset - h / 5.0).max(1.0),
    );
    let s = (half.x / d.x.abs().max(1e-6)).min(half.y / d.y.abs().max(1e-6));
    let tip = centre + d * s;
    let len = 2.0 * th;
    let back = tip - d * len;
    let side = Vec2::new(-d.y, d.x) * (0.6 * th);
    let mut push = |a: Vec2, b: Vec2| out.push(Segment2 { a, b });
    push(back, tip);
    push(tip, tip - d * (0.8 * th) + side);
    push(tip, tip - d * (0.8 * th) - side);
    // The label behind the arrow, kept inside the frame.
    let lw = label_width(label, th);
    let at = back - d * (0.6 * th) - Vec2::new(lw / 2.0, th / 2.0);
    let at = Vec2::new(
        at.x.clamp(2.0, (w - lw - 2.0).max(2.0)),
        at.y.clamp(2.0, (h - th - 2.0).max(2.0)),
    );
    draw_label(label, at, th, out);
}

/// Positions smoothed by a local linear fit over ±`half_s` seconds (at least one sample each
/// side): the path a trail should follow when the samples carry noise. Samples are (time,
/// point); times increasing.
pub fn smooth_path(time: &[f64], points: &[Vec3], half_s: f64) -> Vec<Vec3> {
    let n = time.len().min(points.len());
    let time = &time[..n];
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let t = time[i];
        let a = time
            .partition_point(|&s| s < t - half_s)
            .min(i.saturating_sub(1));
        let b = time
            .partition_point(|&s| s <= t + half_s)
            .saturating_sub(1)
            .max((i + 1).min(n - 1));
        // Least squares of p = c0 + c1·(s − t) over a..=b; the value at t is c0.
        let (mut s0, mut s1, mut s2) = (0.0f64, 0.0f64, 0.0f64);
        let (mut p0, mut p1) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
        for k in a..=b {
            let x = time[k] - t;
            let p = points[k].as_dvec3();
            s0 += 1.0;
            s1 += x;
            s2 += x * x;
            p0 += p;
            p1 += p * x;
        }
        let det = s0 * s2 - s1 * s1;
        let c0 = if det.abs() > 1e-12 * s0 * s2.max(1e-300) {
            (p0 * s2 - p1 * s1) / det
        } else {
            p0 / s0
        };
        out.push(c0.as_vec3());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const VP: Viewport = Viewport {
        width: 800,
        height: 600,
    };

    #[test]
    fn smoothing_keeps_lines_and_removes_noise() {
        let time: Vec<f64> = (0..200).map(|k| k as f64 * 0.02).collect();
        let line: Vec<Vec3> = time
            .iter()
            .map(|&t| Vec3::new(25.0 * t as f32, 0.0, 100.0))
            .collect();
        let s = smooth_path(&time, &line, 0.5);
        for (a, b) in s.iter().zip(&line) {
            assert!((*a - *b).length() < 1e-3, "{a} {b}");
        }
        // Alternating ±0.5 m noise across the track is mostly removed.
        let noisy: Vec<Vec3> = line
            .iter()
            .enumerate()
            .map(|(k, p)| *p + Vec3::Y * if k % 2 == 0 { 0.5 } else { -0.5 })
            .collect();
        let s = smooth_path(&time, &noisy, 0.5);
        let worst = s[20..180].iter().map(|p| p.y.abs()).fold(0.0, f32::max);
        assert!(worst < 0.05, "{worst}");
        assert!(smooth_path(&[], &[], 0.5).is_empty());
        assert_eq!(smooth_path(&[1.0], &[Vec3::ONE], 0.5), [Vec3::ONE]);
    }

    #[test]
    fn off_screen_points_give_a_direction() {
        // Identity: NDC = world x, y; w = 1.
        let m = Mat4::IDENTITY;
        assert_eq!(locate(Vec3::ZERO, m, VP), Ok(Vec2::new(400.0, 300.0)));
        let d = locate(Vec3::new(3.0, 0.0, 0.0), m, VP).unwrap_err();
        assert!((d - Vec2::X).length() < 1e-6, "{d}");
        // Above in NDC is up in pixels (y down).
        let d = locate(Vec3::new(0.0, 2.0, 0.0), m, VP).unwrap_err();
        assert!((d + Vec2::Y).length() < 1e-6, "{d}");
        let mut out = Vec::new();
        edge_arrow(Vec2::X, "MODEL 35 M", VP, &mut out);
        assert!(out.len() > 3);
        for s in &out {
            for p in [s.a, s.b] {
                assert!(
                    p.x >= 0.0 && p.x <= 800.0 && p.y >= 0.0 && p.y <= 600.0,
                    "{p}"
                );
            }
        }
    }

    #[test]
    fn the_strip_is_labelled_and_inside_the_frame() {
        let time: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        let err: Vec<f64> = time.iter().map(|t| t * 0.5).collect();
        let mut out = Vec::new();
        error_strip(&time, &err, 5.0, 4.0, VP, "POSITION ERROR, M", &mut out);
        // Axes, ticks, the title, the labels, the curve and the cursor: many segments, all
        // inside the frame.
        assert!(out.len() > 150, "{}", out.len());
        for s in &out {
            for p in [s.a, s.b] {
                assert!(
                    p.x >= 0.0 && p.x <= 800.0 && p.y >= 0.0 && p.y <= 600.0,
                    "{p}"
                );
            }
        }
    }
}
