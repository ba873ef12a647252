//! The look of the comparison plots and the drawing plumbing they share: colours, the
//! embedded font and text sizes, the title-and-legend header, a chart panel with its axes,
//! tick labels, clipped and dashed lines, shading, axis ranges, the minus sign of plotted
//! numbers, and rendering to PNG.
//!
//! Kept apart from the three plots so that each of them reads as "what is drawn", and so that
//! one change of style reaches all three.

use std::ops::Range;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, RGBAColor};
use wireflight_data::format::fixed;

use super::CanvasError;

// ---------------------------------------------------------------------------------------------
// Rendering plumbing.

pub(crate) type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans-subset.ttf");

fn ensure_font() -> Result<(), CanvasError> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(CanvasError::Font)
    }
}

/// Draw with `draw` into a white RGB image of `size` and encode it as PNG, with `text` as
/// UTF-8 text chunks (`Title`, `Description`: what the picture says, for programs and tests).
pub(crate) fn render_png(
    size: (u32, u32),
    text: &[(&str, String)],
    draw: &dyn Fn(&Root) -> Result<(), CanvasError>,
) -> Result<Vec<u8>, CanvasError> {
    ensure_font()?;
    let (w, h) = size;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        for (key, value) in text {
            enc.add_itxt_chunk((*key).to_string(), value.clone())?;
        }
        let mut writer = enc.write_header()?;
        writer.write_image_data(&rgb)?;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// Colours and sizes.

pub(super) const MEASURED: RGBAColor = RGBAColor(20, 20, 20, 0.75);
pub(super) const BEFORE: RGBColor = RGBColor(31, 119, 180);
pub(super) const AFTER: RGBColor = RGBColor(44, 160, 44);
/// The "before" model drawn behind the "after" one: the same blue, light.
pub(super) const BEFORE_LIGHT: RGBAColor = RGBAColor(31, 119, 180, 0.35);
pub(super) const NOISE: RGBColor = RGBColor(60, 60, 60);
const TEXT: RGBColor = RGBColor(25, 25, 25);
const SUBTLE: RGBColor = RGBColor(90, 90, 90);
pub(super) const SHADE: RGBAColor = RGBAColor(220, 40, 40, 0.14);
const GRID: RGBAColor = RGBAColor(0, 0, 0, 0.07);

pub(super) const HEADER_H: u32 = 92;
const TITLE_PX: f64 = 26.0;
const SUBTITLE_PX: f64 = 17.0;
const CAPTION_PX: f64 = 18.0;
const LABEL_PX: f64 = 15.0;
const DESC_PX: f64 = 16.0;

// ---------------------------------------------------------------------------------------------
// Header, panels, ticks.

/// A legend entry.
pub(super) enum Key {
    Line(RGBAColor, u32),
    Dashed(RGBColor),
    Dot(RGBColor),
    Band(RGBAColor),
}

/// Title, subtitle and a one-line legend across the top of `root`; returns the area below.
pub(super) fn header<'a>(
    root: &Root<'a>,
    title: &str,
    subtitle: &str,
    legend: &[(Key, String)],
) -> Result<Root<'a>, CanvasError> {
    let (top, rest) = root.split_vertically(HEADER_H);
    let title_style = (FONT, TITLE_PX).into_font().color(&TEXT);
    top.draw(&Text::new(title.to_string(), (24, 10), title_style))?;
    let sub_style = (FONT, SUBTITLE_PX).into_font().color(&SUBTLE);
    top.draw(&Text::new(subtitle.to_string(), (24, 42), sub_style))?;
    // Legend: right-aligned on the title's or the subtitle's line if there is room, else on
    // its own line.
    let key_style = (FONT, LABEL_PX + 1.0).into_font().color(&TEXT);
    let (w, _) = top.dim_in_pixel();
    let widths: Vec<u32> = legend
        .iter()
        .map(|(_, label)| {
            top.estimate_text_size(label, &key_style)
                .map(|(tw, _)| tw + 36 + 22)
                .unwrap_or(200)
        })
        .collect();
    let total: u32 = widths.iter().sum();
    let text_w = |text: &str, px: f64| {
        top.estimate_text_size(text, &(FONT, px).into_font().into_text_style(&top))
            .map(|(tw, _)| tw)
            .unwrap_or(w)
    };
    let right = (w.saturating_sub(total + 16)) as i32;
    let (mut x, y) = if 24 + text_w(title, TITLE_PX) + 40 + total < w {
        (right, 16)
    } else if 24 + text_w(subtitle, SUBTITLE_PX) + 40 + total < w {
        (right, 44)
    } else {
        (24, 68)
    };
    for ((key, label), width) in legend.iter().zip(widths) {
        let cy = y + 9;
        match key {
            Key::Line(c, wdt) => top.draw(&PathElement::new(
                vec![(x, cy), (x + 28, cy)],
                c.stroke_width(*wdt + 1),
            ))?,
            Key::Dashed(c) => {
                for k in 0..3 {
                    top.draw(&PathElement::new(
                        vec![(x + k * 11, cy), (x + k * 11 + 6, cy)],
                        c.stroke_width(2),
                    ))?;
                }
            }
            Key::Dot(c) => top.draw(&Circle::new((x + 14, cy), 5, c.filled()))?,
            Key::Band(c) => {
                top.draw(&Rectangle::new([(x, cy - 8), (x + 28, cy + 8)], c.filled()))?
            }
        }
        top.draw(&Text::new(label.clone(), (x + 36, y), key_style.clone()))?;
        x += width as i32;
    }
    Ok(rest)
}

/// Tick labels with as many decimals as the tick spacing needs ([`fixed`]: never "-0");
/// U+2212 for minus. Axes reaching 1e6 or more, or with steps below 1e-6, are labelled in
/// scientific notation with the digits that tell the ticks apart (never a 100-digit number):
/// what differs from `wireflight_data::format`, which has a fixed count of digits.
pub(super) fn tick_formatter(range: &Range<f64>, n: usize) -> impl Fn(&f64) -> String {
    // The tick step: the smallest 1, 2 or 5 × 10^k giving at most `2n` ticks (plotters may
    // place up to twice as many as asked: a label with too few decimals would repeat).
    let raw = (range.end - range.start).abs() / (2 * n.max(1)) as f64;
    let step = if raw > 0.0 && raw.is_finite() {
        let mag = 10f64.powf(raw.log10().floor());
        [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw * (1.0 - 1e-9))
            .unwrap_or(10.0 * mag)
    } else {
        0.0
    };
    let decimals = if step > 0.0 && step.is_finite() {
        (-(step.log10() + 1e-9).floor() as i32).clamp(0, 6) as usize
    } else {
        0
    };
    let big = range.start.abs().max(range.end.abs());
    let scientific = big.is_finite() && (big >= 1e6 || (step > 0.0 && step < 1e-6));
    let digits = if step > 0.0 && big > 0.0 {
        ((big / step).log10().ceil() as i32).clamp(1, 6) as usize
    } else {
        3
    };
    move |v: &f64| {
        if scientific || !v.is_finite() {
            unicode_minus(format!("{:.*e}", digits, v))
        } else {
            unicode_minus(fixed(*v, decimals))
        }
    }
}

/// A chart of `f64` against `f64` drawn on an in-memory bitmap.
pub(super) type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A panel: caption, axes with descriptions, light grid; returns the chart.
#[allow(clippy::too_many_arguments)]
pub(super) fn panel<'a, 'b>(
    area: &'a Root<'b>,
    caption: &str,
    x: Range<f64>,
    y: Range<f64>,
    x_desc: Option<&str>,
    y_desc: &str,
    x_labels: usize,
    y_labels: usize,
) -> Result<Chart<'a, 'b>, CanvasError> {
    let mut builder = ChartBuilder::on(area);
    if !caption.is_empty() {
        builder.caption(caption, (FONT, CAPTION_PX).into_font().color(&TEXT));
    }
    let mut chart = builder
        .margin_left(8)
        .margin_right(22)
        .margin_top(4)
        .margin_bottom(6)
        .x_label_area_size(if x_desc.is_some() { 48 } else { 26 })
        .y_label_area_size(86)
        .build_cartesian_2d(x.clone(), y.clone())?;
    let fx = tick_formatter(&x, x_labels);
    let fy = tick_formatter(&y, y_labels);
    let mut mesh = chart.configure_mesh();
    mesh.x_labels(x_labels)
        .y_labels(y_labels)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FONT, LABEL_PX).into_font().color(&TEXT))
        .axis_desc_style((FONT, DESC_PX).into_font().color(&TEXT))
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .axis_style(RGBColor(140, 140, 140))
        .y_desc(y_desc);
    if let Some(d) = x_desc {
        mesh.x_desc(d);
    }
    mesh.draw()?;
    Ok(chart)
}

// ---------------------------------------------------------------------------------------------
// Lines and shading.

/// Draw a polyline, split at non-finite points and clipped to the chart's y range.
pub(super) fn draw_line(
    chart: &mut Chart,
    pts: &[(f64, f64)],
    style: ShapeStyle,
) -> Result<(), CanvasError> {
    let y = chart.y_range();
    for piece in clip_y(pts, y.start, y.end) {
        if style.stroke_width > 1 {
            // Wide paths are joined with mitres, which spike far out of the panel at the
            // sharp corners of noisy data; separate segments have no joins.
            chart.draw_series(
                piece
                    .windows(2)
                    .map(|s| PathElement::new(vec![s[0], s[1]], style)),
            )?;
        } else {
            chart.draw_series(std::iter::once(PathElement::new(piece, style)))?;
        }
    }
    Ok(())
}

/// Draw a dashed horizontal line at `y` across the chart (if in range).
pub(super) fn draw_hline_dashed(
    chart: &mut Chart,
    y: f64,
    color: RGBColor,
) -> Result<(), CanvasError> {
    let yr = chart.y_range();
    if !(y.is_finite() && y >= yr.start && y <= yr.end) {
        return Ok(());
    }
    let xr = chart.x_range();
    chart.draw_series(DashedLineSeries::new(
        [(xr.start, y), (xr.end, y)],
        9,
        6,
        color.stroke_width(2),
    ))?;
    Ok(())
}

/// Shade the time spans `spans` over the full height of the chart.
pub(super) fn shade(chart: &mut Chart, spans: &[(f64, f64)]) -> Result<(), CanvasError> {
    let y = chart.y_range();
    chart.draw_series(
        spans
            .iter()
            .map(|&(a, b)| Rectangle::new([(a, y.start), (b, y.end)], SHADE.filled())),
    )?;
    Ok(())
}

/// Split `pts` into pieces inside `lo ≤ y ≤ hi` (exact segment clipping; non-finite points
/// break the line).
pub(super) fn clip_y(pts: &[(f64, f64)], lo: f64, hi: f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let finish = |cur: &mut Vec<(f64, f64)>, out: &mut Vec<Vec<(f64, f64)>>| {
        if cur.len() >= 2 {
            out.push(std::mem::take(cur));
        } else {
            cur.clear();
        }
    };
    for s in pts.windows(2) {
        let (p, q) = (s[0], s[1]);
        let finite = p.0.is_finite() && p.1.is_finite() && q.0.is_finite() && q.1.is_finite();
        if !finite {
            finish(&mut cur, &mut out);
            continue;
        }
        let dy = q.1 - p.1;
        let (t0, t1) = if dy == 0.0 {
            if p.1 >= lo && p.1 <= hi {
                (0.0, 1.0)
            } else {
                (1.0, 0.0)
            }
        } else {
            let (a, b) = ((lo - p.1) / dy, (hi - p.1) / dy);
            (a.min(b).max(0.0), a.max(b).min(1.0))
        };
        if t0 > t1 {
            finish(&mut cur, &mut out);
            continue;
        }
        let at = |t: f64| (p.0 + t * (q.0 - p.0), p.1 + t * dy);
        if t0 > 0.0 || cur.is_empty() {
            finish(&mut cur, &mut out);
            cur.push(at(t0));
        }
        cur.push(at(t1));
        if t1 < 1.0 {
            finish(&mut cur, &mut out);
        }
    }
    finish(&mut cur, &mut out);
    out
}

// ---------------------------------------------------------------------------------------------
// Axis ranges and numbers.

/// Top of an error axis starting at 0: the largest finite value (or the noise floor, if
/// higher) times `headroom`; 1 when there is nothing positive to show.
pub(super) fn axis_top(
    values: impl Iterator<Item = f64>,
    noise_floor: Option<f64>,
    headroom: f64,
) -> f64 {
    let top = finite_min_max(values)
        .map(|m| m.1)
        .unwrap_or(1.0)
        .max(noise_floor.unwrap_or(0.0))
        * headroom;
    if top > 0.0 && top.is_finite() {
        top
    } else {
        1.0
    }
}

pub(super) fn finite_min_max(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((a, b)) => Some((a.min(v), b.max(v))),
        })
}

/// y range for measured values plus predictions: all of the measurements, the predictions as
/// far as one measured span beyond them (a diverged prediction leaves the panel rather than
/// squashing the data), 6% padding.
pub(super) fn value_range(
    measured: &[f64],
    predicted: impl IntoIterator<Item = f64>,
) -> Range<f64> {
    let (mut lo, mut hi) = finite_min_max(measured.iter().copied()).unwrap_or((-1.0, 1.0));
    let span = (hi - lo).max(1e-9 * lo.abs().max(hi.abs())).max(1e-6);
    let reach = span.max(1.0);
    if let Some((plo, phi)) = finite_min_max(predicted) {
        lo = lo.min(plo.max(lo - reach));
        hi = hi.max(phi.min(hi + reach));
    }
    padded(lo, hi)
}

pub(super) fn padded(lo: f64, hi: f64) -> Range<f64> {
    let span = hi - lo;
    let degenerate = span.is_nan() || span <= 1e-9 * lo.abs().max(hi.abs()) || span < 1e-9;
    if degenerate {
        let c = 0.5 * (lo + hi);
        let h = (0.05 * c.abs()).max(0.5);
        return (c - h)..(c + h);
    }
    (lo - 0.06 * span)..(hi + 0.06 * span)
}

/// A number as a plot writes it: with U+2212 (−) for the minus sign, which the hyphen of
/// `wireflight_data::format` stands in for in plain text.
pub(super) fn unicode_minus(s: String) -> String {
    s.replace('-', "\u{2212}")
}

#[cfg(test)]
mod tests {

    #[test]
    fn tick_labels_stay_short_on_huge_and_tiny_axes() {
        for (range, v) in [
            (0.0..1e200, 1e200),
            (-1e8..1e8, -5e7),
            (0.0..3e-9, 1e-9),
            (1e6..1e6 + 1.0, 1e6 + 0.5),
        ] {
            let label = tick_formatter(&range, 5)(&v);
            assert!(label.chars().count() <= 12, "{range:?}: {label}");
        }
        assert_eq!(tick_formatter(&(0.0..10.0), 5)(&4.0), "4");
        assert_eq!(tick_formatter(&(-1.0..1.0), 5)(&-0.5), "\u{2212}0.5");
    }

    use super::*;

    #[test]
    fn clipping_keeps_inside_and_cuts_at_the_edges() {
        let pts = [
            (0.0, 0.0),
            (1.0, 2.0),
            (2.0, 0.0),
            (3.0, f64::NAN),
            (4.0, 0.5),
            (5.0, 0.5),
        ];
        let pieces = clip_y(&pts, -1.0, 1.0);
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert_eq!(pieces[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(pieces[1], vec![(1.5, 1.0), (2.0, 0.0)]);
        assert_eq!(pieces[2], vec![(4.0, 0.5), (5.0, 0.5)]);
        assert!(clip_y(&[(0.0, 5.0), (1.0, 6.0)], 0.0, 1.0).is_empty());
    }

    #[test]
    fn ticks() {
        let f = tick_formatter(&(0.0..1.0), 5);
        assert_eq!(f(&0.4), "0.4");
        assert_eq!(f(&-0.0), "0.0");
        assert_eq!(f(&-0.2), "\u{2212}0.2");
        let g = tick_formatter(&(0.0..1000.0), 5);
        assert_eq!(g(&200.0), "200");
    }

    #[test]
    fn font_covers_what_the_plots_write() {
        use cmap::covers;
        for c in "measured vs model → ψθφ° ² − Δ|".chars() {
            assert!(covers(c), "{c:?}");
        }
    }

    mod cmap {
        /// Whether the embedded font maps `c` to a glyph (format-4 cmap lookup).
        pub fn covers(c: char) -> bool {
            let d = super::FONT_BYTES;
            let be16 = |o: usize| u16::from_be_bytes([d[o], d[o + 1]]) as usize;
            let be32 = |o: usize| u32::from_be_bytes([d[o], d[o + 1], d[o + 2], d[o + 3]]) as usize;
            let tables = be16(4);
            let Some(cmap) = (0..tables)
                .map(|i| 12 + 16 * i)
                .find(|&o| &d[o..o + 4] == b"cmap")
                .map(|o| be32(o + 8))
            else {
                return false;
            };
            let cp = c as usize;
            for i in 0..be16(cmap + 2) {
                let sub = cmap + be32(cmap + 4 + 8 * i + 4);
                if be16(sub) != 4 {
                    continue;
                }
                let segs = be16(sub + 6) / 2;
                let ends = sub + 14;
                let starts = ends + 2 * segs + 2;
                let deltas = starts + 2 * segs;
                let offsets = deltas + 2 * segs;
                for s in 0..segs {
                    let (start, end) = (be16(starts + 2 * s), be16(ends + 2 * s));
                    if cp < start || cp > end {
                        continue;
                    }
                    let delta = be16(deltas + 2 * s);
                    let ro = be16(offsets + 2 * s);
                    let glyph = if ro == 0 {
                        (cp + delta) & 0xffff
                    } else {
                        let g = be16(offsets + 2 * s + ro + 2 * (cp - start));
                        if g == 0 {
                            0
                        } else {
                            (g + delta) & 0xffff
                        }
                    };
                    if glyph != 0 {
                        return true;
                    }
                }
            }
            false
        }
    }
}
