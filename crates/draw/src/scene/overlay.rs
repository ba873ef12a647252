//! What a replay frame says about itself, drawn over the 3D scene in pixel coordinates: the
//! time, the aircraft's attitude (aerospace: + nose right, + nose up, + right wing down), speed
//! and altitude in the top corners, the legend of a comparison (which colour is measured,
//! which the model), the labelled error strip of a comparison (title with units, value axis
//! scaled to the model shown, time axis, a cursor with the error now), the raw samples as
//! faint dots under the smoothed trail, and an arrow at the frame's edge towards an aircraft
//! the camera does not see. Text is never drawn over the drawing: [`cut_out`] removes the 3D
//! scene's lines from under every block of text. Units are written as they are (m, s, m/s).
//!
//! Also the smoothing of the trail ([`smooth_path`]). Pure: no I/O.

use glam::{Mat4, Vec2, Vec3};

use super::font::{draw_label, label_width};
use crate::figures::three_figures;
use crate::render::{Rgba, Segment2};
use wireflight_data::format::fixed;
use wireflight_geometry::pipeline::Viewport;

/// Height of the text, pixels, for a frame of this size (7..=16 px, about 1/45 of the height).
pub fn text_height(viewport: Viewport) -> f32 {
    (viewport.height as f32 / 45.0).clamp(7.0, 16.0).round()
}

/// Distance from one line of text to the next, in text heights (room for descenders).
pub const LINE_STEP: f32 = 1.6;

/// A rectangle of the frame, pixels (y down): where text is, or where an arrow may go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Top-left corner.
    pub min: Vec2,
    /// Bottom-right corner.
    pub max: Vec2,
}

impl Rect {
    /// Whether `p` lies inside (edges included).
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// The rectangle grown by `d` on every side.
    pub fn grown(&self, d: f32) -> Self {
        Self {
            min: self.min - Vec2::splat(d),
            max: self.max + Vec2::splat(d),
        }
    }
}

/// Which top corner a block of text sits in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// Left-aligned at the left edge.
    TopLeft,
    /// Right-aligned at the right edge.
    TopRight,
}

/// One line of a corner block: its text, and optionally a short line in a colour before it
/// (a legend's swatch).
#[derive(Clone, Debug, PartialEq)]
pub struct TextLine {
    /// The words.
    pub text: String,
    /// The colour of a swatch drawn before the words.
    pub swatch: Option<Rgba>,
}

impl TextLine {
    /// A line of words alone.
    pub fn plain(text: impl Into<String>) -> Self {
        Self {
            text: text.into(),
            swatch: None,
        }
    }
}

/// A block of lines in a top corner: the words' strokes into `text`, each swatch's into
/// `swatches` (with its colour). Returns the rectangle the block covers.
pub fn corner_block(
    lines: &[TextLine],
    corner: Corner,
    viewport: Viewport,
    text: &mut Vec<Segment2>,
    swatches: &mut Vec<(Rgba, Vec<Segment2>)>,
) -> Rect {
    let th = text_height(viewport);
    let swatch_w = 1.6 * th;
    let widths: Vec<f32> = lines
        .iter()
        .map(|l| {
            label_width(&l.text, th)
                + if l.swatch.is_some() {
                    swatch_w + 0.5 * th
                } else {
                    0.0
                }
        })
        .collect();
    let block_w = widths.iter().copied().fold(0.0, f32::max);
    let w = viewport.width as f32;
    for (k, (line, lw)) in lines.iter().zip(&widths).enumerate() {
        let y = th + k as f32 * LINE_STEP * th;
        let x = match corner {
            Corner::TopLeft => th,
            Corner::TopRight => w - th - lw,
        };
        let mut x_text = x;
        if let Some(color) = line.swatch {
            let mid = (y + 0.5 * th).round() + 0.5;
            let mut segments = Vec::new();
            for dy in [-1.0, 0.0, 1.0] {
                segments.push(Segment2 {
                    a: Vec2::new(x, mid + dy),
                    b: Vec2::new(x + swatch_w, mid + dy),
                });
            }
            swatches.push((color, segments));
            x_text += swatch_w + 0.5 * th;
        }
        draw_label(&line.text, Vec2::new(x_text, y), th, text);
    }
    let left = match corner {
        Corner::TopLeft => th,
        Corner::TopRight => w - th - block_w,
    };
    let rows = lines.len() as f32;
    Rect {
        min: Vec2::new(left, th),
        max: Vec2::new(
            left + block_w,
            th + (rows - 1.0).max(0.0) * LINE_STEP * th + 1.34 * th,
        ),
    }
}

/// The time, attitude, speed and altitude of a frame as lines for the top corners: left the
/// time and the aerospace angles, right the speed and the altitude.
pub fn state_lines(
    t: f64,
    t_end: f64,
    aerospace_deg: [f64; 3],
    speed_mps: Option<f64>,
    altitude_m: f64,
) -> (Vec<TextLine>, Vec<TextLine>) {
    let [yaw, pitch, roll] = aerospace_deg;
    let left = vec![
        TextLine::plain(format!("t {} s / {} s", fixed(t, 1), fixed(t_end, 1))),
        TextLine::plain(format!("yaw {}°", fixed(yaw, 1))),
        TextLine::plain(format!("pitch {}°", fixed(pitch, 1))),
        TextLine::plain(format!("roll {}°", fixed(roll, 1))),
    ];
    let mut right = Vec::new();
    if let Some(v) = speed_mps {
        right.push(TextLine::plain(format!("speed {} m/s", fixed(v, 1))));
    }
    right.push(TextLine::plain(format!("alt {} m", fixed(altitude_m, 1))));
    (left, right)
}

/// Remove from `segments` every part that lies inside one of `boxes`: what is left of each
/// segment outside them (none, one or two pieces per box).
pub fn cut_out(segments: &mut Vec<Segment2>, boxes: &[Rect]) {
    for b in boxes {
        let mut kept = Vec::with_capacity(segments.len());
        for s in segments.drain(..) {
            match inside_span(s, b) {
                None => kept.push(s),
                Some((t0, t1)) => {
                    let at = |t: f32| s.a + (s.b - s.a) * t;
                    if t0 > 0.0 {
                        kept.push(Segment2 { a: s.a, b: at(t0) });
                    }
                    if t1 < 1.0 {
                        kept.push(Segment2 { a: at(t1), b: s.b });
                    }
                }
            }
        }
        *segments = kept;
    }
}

/// The parameter span `[t0, t1]` of segment `s` inside `r` (Liang–Barsky), if any.
fn inside_span(s: Segment2, r: &Rect) -> Option<(f32, f32)> {
    let d = s.b - s.a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, s.a.x - r.min.x),
        (d.x, r.max.x - s.a.x),
        (-d.y, s.a.y - r.min.y),
        (d.y, r.max.y - s.a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 < t1).then_some((t0, t1))
}

/// The full scale of an error strip for errors up to `peak`: the next 1, 2 or 5 × 10ⁿ at or
/// above it, so a model's own errors fill the strip (after a correction, a 1 m error is not
/// drawn flat on the 18 m scale of the model before it).
pub fn strip_scale(peak: f64) -> f64 {
    if !(peak.is_finite() && peak > 0.0) {
        return 1.0;
    }
    let decade = 10f64.powf(peak.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&v| v >= peak * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
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

/// Where a comparison frame's strip begins, pixels from the top: above it the 3D drawing,
/// below it the strip with its title and labels.
pub fn strip_top(viewport: Viewport) -> f32 {
    let th = text_height(viewport);
    StripBox::of(viewport).top - 1.8 * th
}

/// The error over time as a labelled plot: baseline and value axis with ticks, the error as a
/// polyline (per pixel column the largest value, so spikes survive), a cursor at `t` with the
/// error now, a title naming the quantity and its unit, and the times at both ends.
///
/// `time` and `error_m` are per sample (same length, times increasing). The strip's full scale
/// is [`strip_scale`] of these errors' own peak, so every model shown fills it. `before_peak_m`
/// is the peak error of the model this one corrects (the base model, before `--add`): when it
/// is larger than this model's own, the title line says so ("before: peak 18.2 m"), so the fall
/// shows without squashing this model's error flat. Returns the rectangle the strip covers,
/// title and labels included.
#[allow(clippy::too_many_arguments)]
pub fn error_strip(
    time: &[f64],
    error_m: &[f64],
    before_peak_m: f64,
    t: f64,
    viewport: Viewport,
    title: &str,
    out: &mut Vec<Segment2>,
) -> Option<Rect> {
    let n = time.len().min(error_m.len());
    if n == 0 {
        return None;
    }
    let b = StripBox::of(viewport);
    let th = text_height(viewport);
    let seg = |a: Vec2, c: Vec2, out: &mut Vec<Segment2>| out.push(Segment2 { a, b: c });
    let (t0, t1) = (time[0], time[n - 1]);
    let span = (t1 - t0).max(1e-9);
    let own_peak = error_m[..n]
        .iter()
        .copied()
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    let full = strip_scale(own_peak);
    let x_of = |s: f64| b.left + ((s - t0) / span) as f32 * (b.right - b.left);
    let y_of = |e: f64| b.bottom - (e / full).clamp(0.0, 1.0) as f32 * (b.bottom - b.top);
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
        &format!("{} m", three_figures(full)),
        Vec2::new(b.left + 0.4 * th, b.top - 0.1 * small),
        small,
        out,
    );
    let title_y = b.top - 1.5 * th;
    debug_assert!((title_y - 0.3 * th - strip_top(viewport)).abs() < 1e-3);
    let note = (before_peak_m.is_finite() && before_peak_m > own_peak * 1.01)
        .then(|| format!("before: peak {} m", three_figures(before_peak_m)));
    let mut title = title.to_string();
    if let Some(note) = &note {
        let room = b.right - b.left - label_width(note, small) - th;
        if label_width(&title, th) > room {
            // Keep the quantity and the unit, drop the explanation.
            title = title.split(" (").next().unwrap_or(&title).to_string();
        }
        draw_label(
            note,
            Vec2::new(b.right - label_width(note, small), title_y + (th - small)),
            small,
            out,
        );
    }
    draw_label(&title, Vec2::new(b.left, title_y), th, out);
    // Times at the ends.
    let start = format!("{} s", three_figures(t0));
    let end = format!("{} s", three_figures(t1));
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
    let now = format!("{} m", three_figures(error_m[k]));
    let w = label_width(&now, small);
    let lx = if x + 0.4 * th + w < b.right {
        x + 0.4 * th
    } else {
        x - 0.4 * th - w
    };
    draw_label(&now, Vec2::new(lx, b.top + 0.3 * th), small, out);
    Some(Rect {
        min: Vec2::new(0.0, strip_top(viewport)),
        max: Vec2::new(viewport.width as f32, viewport.height as f32),
    })
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

/// An arrow just inside `area` (the part of the frame free of text and strip) pointing along
/// `direction` (pixels, y down, unit) from the area's centre, with `label` behind it, both kept
/// inside the area. Returns the label's rectangle.
pub fn edge_arrow(
    direction: Vec2,
    label: &str,
    area: Rect,
    viewport: Viewport,
    out: &mut Vec<Segment2>,
) -> Rect {
    let th = text_height(viewport);
    let centre = (area.min + area.max) / 2.0;
    let d = if direction.is_finite() && direction.length_squared() > 0.0 {
        direction.normalize()
    } else {
        Vec2::Y
    };
    // Where the ray from the centre meets the area inset by the arrow's size.
    let inset = 1.2 * th;
    let half = ((area.max - area.min) / 2.0 - Vec2::splat(inset)).max(Vec2::ONE);
    let s = (half.x / d.x.abs().max(1e-6)).min(half.y / d.y.abs().max(1e-6));
    let tip = centre + d * s;
    let len = 2.0 * th;
    let back = tip - d * len;
    let side = Vec2::new(-d.y, d.x) * (0.6 * th);
    let mut push = |a: Vec2, b: Vec2| out.push(Segment2 { a, b });
    push(back, tip);
    push(tip, tip - d * (0.8 * th) + side);
    push(tip, tip - d * (0.8 * th) - side);
    // The label behind the arrow, kept inside the area.
    let lw = label_width(label, th);
    let at = back - d * (0.6 * th) - Vec2::new(lw / 2.0, th / 2.0);
    let at = Vec2::new(
        at.x.clamp(area.min.x, (area.max.x - lw).max(area.min.x)),
        at.y.clamp(area.min.y, (area.max.y - 1.34 * th).max(area.min.y)),
    );
    draw_label(label, at, th, out);
    Rect {
        min: at,
        max: at + Vec2::new(lw, 1.34 * th),
    }
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
        let area = Rect {
            min: Vec2::new(0.0, 80.0),
            max: Vec2::new(800.0, 450.0),
        };
        edge_arrow(Vec2::X, "model 35 m", area, VP, &mut out);
        edge_arrow(Vec2::new(-1.0, -1.0), "model 35 m", area, VP, &mut out);
        assert!(out.len() > 3);
        for s in &out {
            for p in [s.a, s.b] {
                assert!(area.grown(1e-3).contains(p), "{p}");
            }
        }
    }

    #[test]
    fn the_strip_is_labelled_and_inside_the_frame() {
        let time: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        let err: Vec<f64> = time.iter().map(|t| t * 0.5).collect();
        let mut out = Vec::new();
        let strip = error_strip(&time, &err, 5.0, 4.0, VP, "position error, m", &mut out).unwrap();
        // Axes, ticks, the title, the labels, the curve and the cursor: many segments, all
        // inside the frame.
        assert!(out.len() > 150, "{}", out.len());
        for s in &out {
            for p in [s.a, s.b] {
                assert!(
                    p.x >= 0.0 && p.x <= 800.0 && p.y >= 0.0 && p.y <= 600.0,
                    "{p}"
                );
                assert!(strip.contains(p), "{p} outside the strip's rectangle");
            }
        }
    }

    /// A model's own errors fill its strip: 1 m of error after a correction is drawn on a 1 m
    /// scale, not flat on the 18 m scale of the model before it, which the title names.
    #[test]
    fn each_model_fills_its_own_strip() {
        assert_eq!(strip_scale(0.93), 1.0);
        assert_eq!(strip_scale(1.0), 1.0);
        assert_eq!(strip_scale(1.2), 2.0);
        assert_eq!(strip_scale(18.2), 20.0);
        assert_eq!(strip_scale(0.031), 0.05);
        assert_eq!(strip_scale(0.0), 1.0);
        let time: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        let err: Vec<f64> = time.iter().map(|t| 0.1 * t).collect(); // peak 0.99 m
        let top_of = |segments: &[Segment2]| {
            // The curve's highest point: the least y of the segments right of the axis.
            let b = StripBox::of(VP);
            segments
                .iter()
                .flat_map(|s| [s.a, s.b])
                .filter(|p| p.x > b.left + 1.0 && p.y >= b.top - 0.5 && p.y <= b.bottom)
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min)
        };
        let (mut alone, mut corrected) = (Vec::new(), Vec::new());
        error_strip(&time, &err, 0.99, 9.9, VP, "position error, m", &mut alone);
        error_strip(
            &time,
            &err,
            18.2,
            9.9,
            VP,
            "position error, m",
            &mut corrected,
        );
        let b = StripBox::of(VP);
        let fill = |y: f32| (b.bottom - y) / (b.bottom - b.top);
        assert!(fill(top_of(&alone)) > 0.95, "{}", fill(top_of(&alone)));
        assert!(
            fill(top_of(&corrected)) > 0.95,
            "{}",
            fill(top_of(&corrected))
        );
        // The corrected strip says how large the error was before: more strokes (the note).
        assert!(
            corrected.len() > alone.len() + 30,
            "{} vs {}",
            corrected.len(),
            alone.len()
        );
    }

    #[test]
    fn cut_out_keeps_what_lies_outside_the_boxes() {
        let r = Rect {
            min: Vec2::new(10.0, 10.0),
            max: Vec2::new(20.0, 20.0),
        };
        let mut segments = vec![
            // Through the box: two pieces.
            Segment2 {
                a: Vec2::new(0.0, 15.0),
                b: Vec2::new(30.0, 15.0),
            },
            // Inside: gone.
            Segment2 {
                a: Vec2::new(12.0, 12.0),
                b: Vec2::new(18.0, 18.0),
            },
            // Outside: kept.
            Segment2 {
                a: Vec2::new(0.0, 0.0),
                b: Vec2::new(30.0, 0.0),
            },
        ];
        cut_out(&mut segments, &[r]);
        assert_eq!(segments.len(), 3, "{segments:?}");
        for s in &segments {
            let mid = (s.a + s.b) / 2.0;
            assert!(!r.grown(-1e-3).contains(mid), "{s:?}");
        }
        assert_eq!(segments[0].b, Vec2::new(10.0, 15.0));
        assert_eq!(segments[1].a, Vec2::new(20.0, 15.0));
    }

    #[test]
    fn corner_blocks_sit_in_their_corners_with_swatches() {
        let (mut text, mut swatches) = (Vec::new(), Vec::new());
        let lines = [
            TextLine::plain("speed 25.0 m/s"),
            TextLine {
                text: "measured".into(),
                swatch: Some([1, 2, 3, 255]),
            },
        ];
        let r = corner_block(&lines, Corner::TopRight, VP, &mut text, &mut swatches);
        assert!(r.max.x <= 800.0 && r.min.x > 600.0, "{r:?}");
        assert_eq!(swatches.len(), 1);
        for s in text.iter().chain(&swatches[0].1) {
            for p in [s.a, s.b] {
                assert!(r.grown(1e-3).contains(p), "{p} outside {r:?}");
            }
        }
    }
}
