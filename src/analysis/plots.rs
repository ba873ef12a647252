//! Plots of a comparison, as PNG files a person reads:
//!
//! * `measured_vs_model.png` — per channel (position N/E and altitude, NED velocity, attitude
//!   in degrees), the measurements and the model's multiple-shooting prediction, one segment
//!   per window restarting from that window's estimated initial state; the "after" model (with
//!   the added effects) in a second colour when given.
//! * `residuals.png` — the window score and the per-sample prediction error of each channel
//!   against time, before (and after), the worst windows shaded, the noise floor (window score)
//!   and the measurement noise (channels) as dashed lines; the title gives the total error
//!   before → after.
//! * `error_vs_condition.png` — when a [`ConditionSeries`] is given, the window score against
//!   that condition, with the correlation in the title.
//!
//! Drawing is into an in-memory RGB buffer (plotters' bitmap backend with the embedded DejaVu
//! Sans subset as its only font), encoded with `png` and written atomically
//! ([`crate::fsio::write_atomic`]).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::Context;
use glam::DVec3;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, RGBAColor};

use super::compare::{estimate_noise, Comparison, Prediction};
use crate::euler::EulerZyx;
use crate::flight::data::FlightData;
use crate::flight::derive::unwrap_angles;
use crate::numeric::{attitude_error_deg, pearson};

/// File name of the measured-vs-model plot.
pub const MEASURED_VS_MODEL: &str = "measured_vs_model.png";
/// File name of the residual plot.
pub const RESIDUALS: &str = "residuals.png";
/// File name of the error-vs-condition plot.
pub const ERROR_VS_CONDITION: &str = "error_vs_condition.png";

/// Pixel size of `measured_vs_model.png` (a grid of up to 3×3 panels).
pub const MEASURED_VS_MODEL_SIZE: (u32, u32) = (1600, 1000);
/// Pixel size of `residuals.png` (up to four stacked panels).
pub const RESIDUALS_SIZE: (u32, u32) = (1400, 1000);
/// Pixel size of `error_vs_condition.png`.
pub const ERROR_VS_CONDITION_SIZE: (u32, u32) = (1200, 800);

/// A flight condition sampled per window, for "error vs condition" plots.
#[derive(Clone, Debug, PartialEq)]
pub struct ConditionSeries {
    /// Name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Value per window.
    pub per_window: Vec<f64>,
}

/// What the plots say about where the comparison came from (all optional).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotInfo {
    /// The data, e.g. its file name (default: the data's `source` metadata).
    pub data_name: Option<String>,
    /// The "before" model, e.g. `fixed-wing aerosonde baseline` (default: "model").
    pub model_name: Option<String>,
    /// Noise floor of the total score ([`super::compare::noise_floor`]), drawn on the
    /// window-score panel.
    pub noise_floor: Option<f64>,
}

/// Write the comparison plots into `dir` (created if missing); returns the files written.
///
/// Equivalent to [`write_plots_with`] with a default [`PlotInfo`] (no noise floor line, the
/// data named by its metadata).
///
/// # Errors
/// No windows to plot, a condition series of the wrong length, a directory that cannot be
/// created, a file that cannot be written (the message names the path).
pub fn write_plots(
    dir: &Path,
    data: &FlightData,
    before: &Comparison,
    after: Option<(&Comparison, &str)>,
    best: Option<&ConditionSeries>,
) -> anyhow::Result<Vec<PathBuf>> {
    write_plots_with(dir, data, before, after, best, &PlotInfo::default())
}

/// [`write_plots`] with names for the titles and the noise floor.
///
/// # Errors
/// As [`write_plots`].
pub fn write_plots_with(
    dir: &Path,
    data: &FlightData,
    before: &Comparison,
    after: Option<(&Comparison, &str)>,
    best: Option<&ConditionSeries>,
    info: &PlotInfo,
) -> anyhow::Result<Vec<PathBuf>> {
    if before.windows.is_empty() || data.is_empty() {
        anyhow::bail!("{}: no compared windows to plot", dir.display());
    }
    if let Some((a, _)) = after {
        if a.windows.len() != before.windows.len() {
            anyhow::bail!(
                "{}: the two comparisons have {} and {} windows",
                dir.display(),
                before.windows.len(),
                a.windows.len()
            );
        }
    }
    if let Some(c) = best {
        if c.per_window.len() != before.windows.len() {
            anyhow::bail!(
                "{}: condition `{}` has {} values for {} windows",
                dir.join(ERROR_VS_CONDITION).display(),
                c.name,
                c.per_window.len(),
                before.windows.len()
            );
        }
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the plot directory", dir.display()))?;
    let ctx = Ctx::new(data, before, after, info);

    let mut written = Vec::new();
    let mut emit = |name: &str,
                    size: (u32, u32),
                    draw: &dyn Fn(&Root) -> anyhow::Result<()>|
     -> anyhow::Result<()> {
        let path = dir.join(name);
        let bytes =
            render_png(size, draw).with_context(|| format!("{}: cannot draw", path.display()))?;
        crate::fsio::write_atomic(&path, &bytes)?;
        written.push(path);
        Ok(())
    };
    emit(MEASURED_VS_MODEL, MEASURED_VS_MODEL_SIZE, &|root| {
        draw_measured_vs_model(root, &ctx)
    })?;
    emit(RESIDUALS, RESIDUALS_SIZE, &|root| {
        draw_residuals(root, &ctx)
    })?;
    if let Some(c) = best {
        emit(ERROR_VS_CONDITION, ERROR_VS_CONDITION_SIZE, &|root| {
            draw_error_vs_condition(root, &ctx, c)
        })?;
    }
    Ok(written)
}

// ---------------------------------------------------------------------------------------------
// Rendering plumbing.

type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

fn ensure_font() -> anyhow::Result<()> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    anyhow::ensure!(
        ok,
        "the embedded font assets/fonts/DejaVuSans-subset.ttf is not valid"
    );
    Ok(())
}

fn draw_err<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow::anyhow!("drawing failed: {e}")
}

/// Draw with `draw` into a white RGB image of `size` and encode it as PNG.
fn render_png(
    size: (u32, u32),
    draw: &dyn Fn(&Root) -> anyhow::Result<()>,
) -> anyhow::Result<Vec<u8>> {
    ensure_font()?;
    let (w, h) = size;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        draw(&root)?;
        root.present().map_err(draw_err)?;
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(&rgb)?;
    }
    Ok(out)
}

const MEASURED: RGBAColor = RGBAColor(20, 20, 20, 0.75);
const BEFORE: RGBColor = RGBColor(31, 119, 180);
const AFTER: RGBColor = RGBColor(44, 160, 44);
const NOISE: RGBColor = RGBColor(60, 60, 60);
const TEXT: RGBColor = RGBColor(25, 25, 25);
const SUBTLE: RGBColor = RGBColor(90, 90, 90);
const SHADE: RGBAColor = RGBAColor(220, 40, 40, 0.14);
const GRID: RGBAColor = RGBAColor(0, 0, 0, 0.07);

const HEADER_H: u32 = 92;
const TITLE_PX: f64 = 26.0;
const SUBTITLE_PX: f64 = 17.0;
const CAPTION_PX: f64 = 18.0;
const LABEL_PX: f64 = 15.0;
const DESC_PX: f64 = 16.0;

/// A legend entry.
enum Key {
    Line(RGBAColor, u32),
    Dashed(RGBColor),
    Dot(RGBColor),
    Band(RGBAColor),
}

/// Title, subtitle and a one-line legend across the top of `root`; returns the area below.
fn header<'a>(
    root: &Root<'a>,
    title: &str,
    subtitle: &str,
    legend: &[(Key, String)],
) -> anyhow::Result<Root<'a>> {
    let (top, rest) = root.split_vertically(HEADER_H);
    let title_style = (FONT, TITLE_PX).into_font().color(&TEXT);
    top.draw(&Text::new(title.to_string(), (24, 10), title_style))
        .map_err(draw_err)?;
    let sub_style = (FONT, SUBTITLE_PX).into_font().color(&SUBTLE);
    top.draw(&Text::new(subtitle.to_string(), (24, 42), sub_style))
        .map_err(draw_err)?;
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
            Key::Line(c, wdt) => top
                .draw(&PathElement::new(
                    vec![(x, cy), (x + 28, cy)],
                    c.stroke_width(*wdt + 1),
                ))
                .map_err(draw_err)?,
            Key::Dashed(c) => {
                for k in 0..3 {
                    top.draw(&PathElement::new(
                        vec![(x + k * 11, cy), (x + k * 11 + 6, cy)],
                        c.stroke_width(2),
                    ))
                    .map_err(draw_err)?;
                }
            }
            Key::Dot(c) => top
                .draw(&Circle::new((x + 14, cy), 5, c.filled()))
                .map_err(draw_err)?,
            Key::Band(c) => top
                .draw(&Rectangle::new([(x, cy - 8), (x + 28, cy + 8)], c.filled()))
                .map_err(draw_err)?,
        }
        top.draw(&Text::new(label.clone(), (x + 36, y), key_style.clone()))
            .map_err(draw_err)?;
        x += width as i32;
    }
    Ok(rest)
}

/// Tick labels with as many decimals as the tick spacing needs; U+2212 for minus.
fn tick_formatter(range: &Range<f64>, n: usize) -> impl Fn(&f64) -> String {
    // The tick step: the smallest 1, 2 or 5 × 10^k giving at most `n` ticks.
    let raw = (range.end - range.start).abs() / n.max(1) as f64;
    let decimals = if raw > 0.0 && raw.is_finite() {
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| *s >= raw * (1.0 - 1e-9))
            .unwrap_or(10.0 * mag);
        (-(step.log10() + 1e-9).floor() as i32).clamp(0, 6) as usize
    } else {
        0
    };
    move |v: &f64| {
        let s = format!("{:.*}", decimals, v);
        let s = if s
            .trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            s.trim_start_matches('-').to_string()
        } else {
            s
        };
        s.replace('-', "\u{2212}")
    }
}

/// A panel: caption, axes with descriptions, light grid; returns the chart.
#[allow(clippy::too_many_arguments)]
fn panel<'a, 'b>(
    area: &'a Root<'b>,
    caption: &str,
    x: Range<f64>,
    y: Range<f64>,
    x_desc: Option<&str>,
    y_desc: &str,
    x_labels: usize,
    y_labels: usize,
) -> anyhow::Result<
    ChartContext<
        'a,
        BitMapBackend<'b>,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
> {
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
        .build_cartesian_2d(x.clone(), y.clone())
        .map_err(draw_err)?;
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
    mesh.draw().map_err(draw_err)?;
    Ok(chart)
}

type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draw a polyline, split at non-finite points and clipped to the chart's y range.
fn draw_line(chart: &mut Chart, pts: &[(f64, f64)], style: ShapeStyle) -> anyhow::Result<()> {
    let y = chart.y_range();
    for piece in clip_y(pts, y.start, y.end) {
        if style.stroke_width > 1 {
            // Wide paths are joined with mitres, which spike far out of the panel at the
            // sharp corners of noisy data; separate segments have no joins.
            chart
                .draw_series(
                    piece
                        .windows(2)
                        .map(|s| PathElement::new(vec![s[0], s[1]], style)),
                )
                .map_err(draw_err)?;
        } else {
            chart
                .draw_series(std::iter::once(PathElement::new(piece, style)))
                .map_err(draw_err)?;
        }
    }
    Ok(())
}

/// Draw a dashed horizontal line at `y` across the chart (if in range).
fn draw_hline_dashed(chart: &mut Chart, y: f64, color: RGBColor) -> anyhow::Result<()> {
    let yr = chart.y_range();
    if !(y.is_finite() && y >= yr.start && y <= yr.end) {
        return Ok(());
    }
    let xr = chart.x_range();
    chart
        .draw_series(DashedLineSeries::new(
            [(xr.start, y), (xr.end, y)],
            9,
            6,
            color.stroke_width(2),
        ))
        .map_err(draw_err)?;
    Ok(())
}

/// Shade the time spans `spans` over the full height of the chart.
fn shade(chart: &mut Chart, spans: &[(f64, f64)]) -> anyhow::Result<()> {
    let y = chart.y_range();
    chart
        .draw_series(
            spans
                .iter()
                .map(|&(a, b)| Rectangle::new([(a, y.start), (b, y.end)], SHADE.filled())),
        )
        .map_err(draw_err)?;
    Ok(())
}

/// Split `pts` into pieces inside `lo ≤ y ≤ hi` (exact segment clipping; non-finite points
/// break the line).
fn clip_y(pts: &[(f64, f64)], lo: f64, hi: f64) -> Vec<Vec<(f64, f64)>> {
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
                out.last_mut().expect("non-empty").push((t, edge));
                out.push(vec![(t, -edge)]);
            }
        }
        out.last_mut().expect("non-empty").push(q);
    }
    out
}

fn wrap_deg(a: f64) -> f64 {
    let w = (a + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 {
        180.0
    } else {
        w
    }
}

/// Top of an error axis starting at 0: the largest finite value (or the noise floor, if
/// higher) times `headroom`; 1 when there is nothing positive to show.
fn axis_top(values: impl Iterator<Item = f64>, noise_floor: Option<f64>, headroom: f64) -> f64 {
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

fn finite_min_max(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
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
fn value_range(measured: &[f64], predicted: impl IntoIterator<Item = f64>) -> Range<f64> {
    let (mut lo, mut hi) = finite_min_max(measured.iter().copied()).unwrap_or((-1.0, 1.0));
    let span = (hi - lo).max(1e-9 * lo.abs().max(hi.abs())).max(1e-6);
    let reach = span.max(1.0);
    if let Some((plo, phi)) = finite_min_max(predicted) {
        lo = lo.min(plo.max(lo - reach));
        hi = hi.max(phi.min(hi + reach));
    }
    padded(lo, hi)
}

fn padded(lo: f64, hi: f64) -> Range<f64> {
    let span = hi - lo;
    let degenerate = span.is_nan() || span <= 1e-9 * lo.abs().max(hi.abs()) || span < 1e-9;
    if degenerate {
        let c = 0.5 * (lo + hi);
        let h = (0.05 * c.abs()).max(0.5);
        return (c - h)..(c + h);
    }
    (lo - 0.06 * span)..(hi + 0.06 * span)
}

/// Upper limit for a non-negative error axis: the 99.5th percentile of `values` (so that a
/// single diverged window does not flatten the rest), at least `at_least`, plus headroom.
fn error_cap(values: &[f64], at_least: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let q = if v.is_empty() {
        0.0
    } else {
        v.sort_by(f64::total_cmp);
        let idx = ((v.len() - 1) as f64 * 0.995).round() as usize;
        v[idx]
    };
    let cap = q.max(at_least) * 1.1;
    if cap > 0.0 && cap.is_finite() {
        cap
    } else {
        1.0
    }
}

fn signed(v: f64, decimals: usize) -> String {
    let s = format!("{:+.*}", decimals, v);
    s.replace('-', "\u{2212}")
}

/// Score with a sensible number of significant digits.
fn fmt_score(v: f64) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    let a = v.abs();
    if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

// ---------------------------------------------------------------------------------------------
// What is plotted.

/// Everything the three plots share.
struct Ctx<'a> {
    data: &'a FlightData,
    before: &'a Comparison,
    after: Option<(&'a Comparison, &'a str)>,
    data_name: String,
    model_name: String,
    noise_floor: Option<f64>,
    t_range: Range<f64>,
    has_vel: bool,
    has_att: bool,
}

impl<'a> Ctx<'a> {
    fn new(
        data: &'a FlightData,
        before: &'a Comparison,
        after: Option<(&'a Comparison, &'a str)>,
        info: &PlotInfo,
    ) -> Self {
        let data_name = info
            .data_name
            .clone()
            .or_else(|| data.meta.source.clone())
            .unwrap_or_else(|| "flight data".into());
        let model_name = info.model_name.clone().unwrap_or_else(|| "model".into());
        let t0 = data.time[0];
        let t1 = data.time[data.len() - 1];
        let t_range = if t1 > t0 {
            t0..t1
        } else {
            (t0 - 0.5)..(t0 + 0.5)
        };
        Self {
            data,
            before,
            after,
            data_name,
            model_name,
            noise_floor: info.noise_floor.filter(|f| f.is_finite()),
            t_range,
            has_vel: before.channels.velocity_mps.is_some() && data.vel_ned.is_some(),
            has_att: before.channels.attitude_deg.is_some() && data.attitude.is_some(),
        }
    }

    fn after_name(&self) -> Option<String> {
        self.after.map(|(_, label)| {
            let label = label.trim();
            if label.is_empty() {
                format!("{} (after)", self.model_name)
            } else {
                format!("{} {label}", self.model_name)
            }
        })
    }

    fn subtitle(&self, remark: &str) -> String {
        let n = self.before.windows.len();
        let mean_len =
            self.before.windows.iter().map(|w| w.t1 - w.t0).sum::<f64>() / n.max(1) as f64;
        format!(
            "{} samples over {:.1} s; {n} window{} of about {:.0} s{remark}",
            self.data.len(),
            self.data.duration(),
            if n == 1 { "" } else { "s" },
            mean_len
        )
    }

    /// Worst windows of the "before" comparison (time spans), at most three and at most a
    /// quarter of them (at least one).
    fn worst_spans(&self) -> Vec<(f64, f64)> {
        let n = (self.before.windows.len() / 4).clamp(1, 3);
        self.before
            .worst_windows()
            .into_iter()
            .take(n)
            .map(|w| (w.t0, w.t1))
            .collect()
    }
}

/// The prediction of each compared window: (first sample, first prediction index, length).
fn prediction_windows(cmp: &Comparison) -> Vec<(usize, usize, usize)> {
    let p = &cmp.prediction;
    let mut out = Vec::new();
    let mut k = 0;
    let mut consistent = true;
    for w in &cmp.windows {
        let (a, b) = w.samples;
        let len = b.saturating_sub(a);
        if k + len > p.index.len() || p.index.get(k) != Some(&a) {
            consistent = false;
            break;
        }
        out.push((a, k, len));
        k += len;
    }
    if consistent && k == p.index.len() {
        return out;
    }
    // Fallback: split wherever the sample index does not advance by one.
    out.clear();
    let mut start = 0;
    for k in 1..=p.index.len() {
        if k == p.index.len() || p.index[k] != p.index[k - 1] + 1 {
            out.push((p.index[start], start, k - start));
            start = k;
        }
    }
    out
}

/// One quantity plotted against time.
struct Series {
    caption: String,
    /// Axis description with unit.
    y_desc: String,
    measured: Vec<f64>,
    /// Prediction segments of the "before" model, one per window: (t, value).
    before: Vec<Vec<(f64, f64)>>,
    /// The same for the "after" model.
    after: Vec<Vec<(f64, f64)>>,
    /// Wrapped angle (degrees): split lines at ±180° jumps.
    wrapped: bool,
}

/// Segments of `f(prediction, k)` per window.
fn pred_segments(
    data: &FlightData,
    cmp: &Comparison,
    f: &dyn Fn(&Prediction, usize) -> f64,
) -> Vec<Vec<(f64, f64)>> {
    let p = &cmp.prediction;
    prediction_windows(cmp)
        .into_iter()
        .map(|(_, k0, len)| {
            (k0..k0 + len)
                .filter(|&k| k < p.index.len() && p.index[k] < data.len())
                .map(|k| (data.time[p.index[k]], f(p, k)))
                .collect()
        })
        .collect()
}

/// Angle segments per window (degrees): unwrapped within the window, then shifted by whole
/// turns to start next to the (unwrapped) measurement.
fn angle_segments(
    data: &FlightData,
    cmp: &Comparison,
    measured_unwrapped: &[f64],
    get: fn(&EulerZyx) -> f64,
) -> Vec<Vec<(f64, f64)>> {
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

fn build_series(ctx: &Ctx) -> Vec<Vec<Series>> {
    let d = ctx.data;
    let mut rows = Vec::new();
    let after = ctx.after.map(|(c, _)| c);
    let segs = |f: &dyn Fn(&Prediction, usize) -> f64| {
        (
            pred_segments(d, ctx.before, f),
            after.map(|a| pred_segments(d, a, f)).unwrap_or_default(),
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
        let (b, a) = segs(&|p, k| get(p.pos_ned[k]));
        row.push(Series {
            caption: caption.into(),
            y_desc: format!("{axis} (m)"),
            measured: d.pos_ned.iter().map(|v| get(*v)).collect(),
            before: b,
            after: a,
            wrapped: false,
        });
    }
    let (b, a) = segs(&|p, k| alt0 - p.pos_ned[k].z);
    row.push(Series {
        caption: alt_caption.into(),
        y_desc: format!("{} (m)", alt_caption.split(' ').next().unwrap_or("height")),
        measured: d.pos_ned.iter().map(|v| alt0 - v.z).collect(),
        before: b,
        after: a,
        wrapped: false,
    });
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
            let (b, a) = segs(&|p, k| get(p.vel_ned[k]));
            row.push(Series {
                caption: format!("{caption}{derived}"),
                y_desc: format!("{axis} (m/s)"),
                measured: vel.iter().map(|v| get(*v)).collect(),
                before: b,
                after: a,
                wrapped: false,
            });
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

fn draw_measured_vs_model(root: &Root, ctx: &Ctx) -> anyhow::Result<()> {
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
                            chart
                                .draw_series(std::iter::once(Circle::new(
                                    (t0, v0),
                                    3,
                                    color.filled(),
                                )))
                                .map_err(draw_err)?;
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

/// Per-sample error of one channel, one segment per window: (t, |error|).
fn error_segments(
    data: &FlightData,
    cmp: &Comparison,
    f: &dyn Fn(&Prediction, usize, usize) -> f64,
) -> Vec<Vec<(f64, f64)>> {
    let p = &cmp.prediction;
    prediction_windows(cmp)
        .into_iter()
        .map(|(_, k0, len)| {
            (k0..k0 + len)
                .filter(|&k| k < p.index.len() && p.index[k] < data.len())
                .map(|k| (data.time[p.index[k]], f(p, k, p.index[k])))
                .collect()
        })
        .collect()
}

fn draw_residuals(root: &Root, ctx: &Ctx) -> anyhow::Result<()> {
    let d = ctx.data;
    let worst = ctx.worst_spans();
    let mut title = format!("Residuals — total error {}", fmt_score(ctx.before.total));
    if let Some((a, _)) = ctx.after {
        title.push_str(&format!(" → {}", fmt_score(a.total)));
    }
    if let Some(f) = ctx.noise_floor {
        title.push_str(&format!("  (noise floor {})", fmt_score(f)));
    }
    let mut legend = vec![(Key::Line(BEFORE.to_rgba(), 2), ctx.model_name.clone())];
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
    let mut channels: Vec<(&str, &str, ErrFn, Option<f64>)> = vec![(
        "position error |Δp|",
        "error (m)",
        Box::new(|p: &Prediction, k, i| (p.pos_ned[k] - d.pos_ned[i]).length()),
        Some(s3 * noise.pos_m),
    )];
    if let (true, Some(v)) = (ctx.has_vel, &d.vel_ned) {
        channels.push((
            "velocity error |Δv|",
            "error (m/s)",
            Box::new(move |p: &Prediction, k, i| (p.vel_ned[k] - v[i]).length()),
            (!d.is_derived("vel_ned")).then_some(s3 * noise.vel_mps),
        ));
    }
    if let (true, Some(att)) = (ctx.has_att, &d.attitude) {
        channels.push((
            "attitude error (rotation angle)",
            "error (°)",
            Box::new(move |p: &Prediction, k, i| attitude_error_deg(&p.attitude[k], &att[i])),
            Some(s3 * noise.att_rad.to_degrees()),
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
    let steps = |c: &Comparison| -> Vec<Vec<(f64, f64)>> {
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
    let top = axis_top(all_scores.iter().copied(), ctx.noise_floor, 1.12);
    let mut chart = panel(
        &areas[0],
        &score_caption,
        ctx.t_range.clone(),
        0.0..top,
        x_desc(0),
        "score",
        10,
        4,
    )?;
    shade(&mut chart, &worst)?;
    for (segs, color) in [(&before_steps, BEFORE), (&after_steps, AFTER)] {
        for s in segs {
            draw_line(&mut chart, s, color.stroke_width(3))?;
        }
    }
    if let Some(f) = ctx.noise_floor {
        draw_hline_dashed(&mut chart, f, NOISE)?;
    }

    for (row, (caption, unit, f, noise_level)) in channels.iter().enumerate() {
        let row = row + 1;
        let b = error_segments(d, ctx.before, f.as_ref());
        let a = ctx
            .after
            .map(|(c, _)| error_segments(d, c, f.as_ref()))
            .unwrap_or_default();
        let values: Vec<f64> = b.iter().chain(&a).flatten().map(|p| p.1).collect();
        let noise_level = noise_level.filter(|v| *v > 0.0 && v.is_finite());
        let cap = error_cap(&values, noise_level.unwrap_or(0.0));
        let mut chart = panel(
            &areas[row],
            caption,
            ctx.t_range.clone(),
            0.0..cap,
            x_desc(row),
            unit,
            10,
            4,
        )?;
        shade(&mut chart, &worst)?;
        for (segs, color) in [(&b, BEFORE), (&a, AFTER)] {
            for s in segs {
                draw_line(&mut chart, s, color.stroke_width(2))?;
            }
        }
        if let Some(level) = noise_level {
            draw_hline_dashed(&mut chart, level, NOISE)?;
        }
    }
    Ok(())
}

/// The units the score combines, e.g. "m, m/s, °".
fn score_units(ctx: &Ctx) -> String {
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

fn draw_error_vs_condition(root: &Root, ctx: &Ctx, cond: &ConditionSeries) -> anyhow::Result<()> {
    let x: &[f64] = &cond.per_window;
    let yb: Vec<f64> = ctx.before.windows.iter().map(|w| w.score).collect();
    let ya: Option<Vec<f64>> = ctx
        .after
        .map(|(a, _)| a.windows.iter().map(|w| w.score).collect());
    let rb = pearson(x, &yb);
    let ra = ya.as_ref().and_then(|y| pearson(x, y));
    let r_text = |r: Option<f64>| r.map(|r| signed(r, 2)).unwrap_or_else(|| "n/a".into());
    let mut title = format!("Window error vs {} — r = {}", cond.name, r_text(rb));
    if ya.is_some() {
        title.push_str(&format!(" before, {} after", r_text(ra)));
    }
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
                chart
                    .draw_series(DashedLineSeries::new(piece, 9, 6, BEFORE.stroke_width(2)))
                    .map_err(draw_err)?;
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
    chart.draw_series(dots(&yb, BEFORE)).map_err(draw_err)?;
    if let Some(ya) = &ya {
        chart.draw_series(dots(ya, AFTER)).map_err(draw_err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
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
    fn ticks_and_wraps() {
        let f = tick_formatter(&(0.0..1.0), 5);
        assert_eq!(f(&0.4), "0.4");
        assert_eq!(f(&-0.0), "0.0");
        assert_eq!(f(&-0.2), "\u{2212}0.2");
        let g = tick_formatter(&(0.0..1000.0), 5);
        assert_eq!(g(&200.0), "200");
        assert_eq!(wrap_deg(190.0), -170.0);
        assert_eq!(wrap_deg(-180.0), 180.0);
        let pieces = split_wraps(&[(0.0, 170.0), (1.0, -170.0), (2.0, -160.0)]);
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0], vec![(0.0, 170.0), (0.5, 180.0)]);
        assert_eq!(pieces[1], vec![(0.5, -180.0), (1.0, -170.0), (2.0, -160.0)]);
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
