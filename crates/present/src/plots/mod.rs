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
//! * `residuals_per_axis.png` — predicted − measured against time for every axis of every
//!   channel the data have (position, velocity, attitude, body rates, airspeed, α, β), the
//!   model as given light behind the model with the added effects; each axis reaches the
//!   largest error drawn.
//! * `error_vs_condition.png` — when a [`ConditionSeries`] is given, the window score against
//!   that condition, with the correlation in the title.
//!
//! Drawing is into an in-memory RGB buffer (plotters' bitmap backend with the embedded DejaVu
//! Sans subset as its only font), encoded with `png` and written atomically
//! ([`wireflight_fsio::write_atomic`]).
//!
//! Layout: this file holds the public API (file names, sizes, [`write_plots`]) and what the
//! three plots share (the context, the prediction cut into windows); `style.rs` the look
//! (colours, fonts, header, panels, axes, ticks) and the drawing plumbing; one file per plot
//! (`measured_vs_model.rs`, `residuals.rs`, `error_vs_condition.rs`).

mod error_vs_condition;
mod measured_vs_model;
mod residual_axes;
mod residuals;
mod style;

use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::backend::{BitMapBackend, DrawingBackend};
use plotters::drawing::DrawingAreaErrorKind;
use thiserror::Error;

use self::error_vs_condition::draw_error_vs_condition;
use self::measured_vs_model::draw_measured_vs_model;
use self::residual_axes::draw_residual_axes;
use self::residuals::draw_residuals;
use self::style::{render_png, Root};
use wireflight_analysis::compare::{Comparison, Prediction};
use wireflight_data::{Channel, FlightData};
use wireflight_fsio::{FsError, StagedDir};

/// Why the plots could not be written. Every error names the directory or the file.
#[derive(Debug, Error)]
pub enum PlotError {
    /// The comparison has no windows, or the flight no samples.
    #[error("{}: no compared windows to plot", dir.display())]
    NothingToPlot {
        /// The plot directory.
        dir: PathBuf,
    },
    /// The "before" and "after" comparisons have different windows.
    #[error("{}: the two comparisons have {before} and {after} windows", dir.display())]
    WindowCounts {
        /// The plot directory.
        dir: PathBuf,
        /// Windows of the "before" comparison.
        before: usize,
        /// Windows of the "after" comparison.
        after: usize,
    },
    /// A condition series with another count of values than windows.
    #[error("{}: condition `{name}` has {values} values for {windows} windows", path.display())]
    ConditionLength {
        /// The plot file.
        path: PathBuf,
        /// The condition.
        name: String,
        /// Its values.
        values: usize,
        /// The windows.
        windows: usize,
    },
    /// The directory could not be created or staged.
    #[error("{}: cannot create the plot directory", dir.display())]
    CreateDir {
        /// The plot directory.
        dir: PathBuf,
        /// Why.
        #[source]
        source: FsError,
    },
    /// A plot could not be drawn.
    #[error("{}: cannot draw", path.display())]
    Draw {
        /// The plot file.
        path: PathBuf,
        /// Why.
        #[source]
        source: CanvasError,
    },
    /// A file could not be written, or the set not moved into place (the error names it).
    #[error(transparent)]
    Write(#[from] FsError),
}

/// The error of plotters' drawing calls on the in-memory bitmap.
pub type PlottersError =
    DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>;

/// Why a plot could not be drawn on its in-memory canvas.
#[derive(Debug, Error)]
pub enum CanvasError {
    /// The embedded font does not load.
    #[error("the embedded font assets/fonts/DejaVuSans-subset.ttf is not valid")]
    Font,
    /// A plotters call failed.
    #[error("drawing failed")]
    Plotters(#[from] PlottersError),
    /// The PNG encoder failed.
    #[error(transparent)]
    Png(#[from] png::EncodingError),
}

/// File name of the measured-vs-model plot.
pub const MEASURED_VS_MODEL: &str = "measured_vs_model.png";
/// File name of the residual plot.
pub const RESIDUALS: &str = "residuals.png";
/// File name of the per-axis residual plot.
pub const RESIDUALS_PER_AXIS: &str = "residuals_per_axis.png";
/// File name of the error-vs-condition plot.
pub const ERROR_VS_CONDITION: &str = "error_vs_condition.png";

/// Pixel size of `measured_vs_model.png` (a grid of up to 3×3 panels).
pub const MEASURED_VS_MODEL_SIZE: (u32, u32) = (1600, 1000);
/// Pixel size of `residuals.png` (up to four stacked panels).
pub const RESIDUALS_SIZE: (u32, u32) = (1400, 1000);
/// Width of `residuals_per_axis.png`; its height is [`RESIDUALS_PER_AXIS_ROW`] per channel
/// (position, velocity, attitude, rates, air data: those the data have) plus the header.
pub const RESIDUALS_PER_AXIS_WIDTH: u32 = 1500;
/// Height of one row of `residuals_per_axis.png`.
pub const RESIDUALS_PER_AXIS_ROW: u32 = 260;
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
    /// Noise floor of the total score ([`wireflight_analysis::compare::noise_floor`]), drawn on the
    /// window-score panel.
    pub noise_floor: Option<f64>,
    /// The window length the comparison was asked for, s (`--window`): the subtitles say
    /// "6 windows of 8 s" as the text does (default: the windows' mean length, "about").
    pub window_s: Option<f64>,
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
) -> Result<Vec<PathBuf>, PlotError> {
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
) -> Result<Vec<PathBuf>, PlotError> {
    if before.windows.is_empty() || data.is_empty() {
        return Err(PlotError::NothingToPlot {
            dir: dir.to_path_buf(),
        });
    }
    if let Some((a, _)) = after {
        if a.windows.len() != before.windows.len() {
            return Err(PlotError::WindowCounts {
                dir: dir.to_path_buf(),
                before: before.windows.len(),
                after: a.windows.len(),
            });
        }
    }
    if let Some(c) = best {
        if c.per_window.len() != before.windows.len() {
            return Err(PlotError::ConditionLength {
                path: dir.join(ERROR_VS_CONDITION),
                name: c.name.clone(),
                values: c.per_window.len(),
                windows: before.windows.len(),
            });
        }
    }
    let pngs = render_plots(dir, data, before, after, best, info)?;
    // The set is written into a temporary directory and moved in together: a run that is
    // stopped or fails leaves the directory as it was, never a partial set.
    let staged = StagedDir::new(dir).map_err(|source| PlotError::CreateDir {
        dir: dir.to_path_buf(),
        source,
    })?;
    let mut written = Vec::new();
    for (name, bytes) in &pngs {
        wireflight_fsio::write_atomic(&staged.path().join(name), bytes)?;
        written.push(dir.join(name));
    }
    staged.commit_merge()?;
    Ok(written)
}

/// The plots of [`write_plots_with`] drawn in memory, each as (file name, PNG bytes), in the
/// order they are written; `dir` only names them in errors. Each PNG carries its title and
/// subtitle as text chunks (`Title`, `Description`).
pub(crate) fn render_plots(
    dir: &Path,
    data: &FlightData,
    before: &Comparison,
    after: Option<(&Comparison, &str)>,
    best: Option<&ConditionSeries>,
    info: &PlotInfo,
) -> Result<Vec<(&'static str, Vec<u8>)>, PlotError> {
    let ctx = PlotContext::new(data, before, after, info);
    let mut out = Vec::new();
    let mut emit = |name: &'static str,
                    size: (u32, u32),
                    text: Vec<(&str, String)>,
                    draw: &dyn Fn(&Root) -> Result<(), CanvasError>|
     -> Result<(), PlotError> {
        match render_png(size, &text, draw) {
            Ok(bytes) => {
                out.push((name, bytes));
                Ok(())
            }
            Err(source) => Err(PlotError::Draw {
                path: dir.join(name),
                source,
            }),
        }
    };
    let described = |title: String| vec![("Title", title), ("Description", ctx.subtitle(""))];
    emit(
        MEASURED_VS_MODEL,
        MEASURED_VS_MODEL_SIZE,
        described(format!("Measured vs model — {}", ctx.data_name)),
        &|root| draw_measured_vs_model(root, &ctx),
    )?;
    emit(
        RESIDUALS,
        RESIDUALS_SIZE,
        described(residuals::title(&ctx)),
        &|root| draw_residuals(root, &ctx),
    )?;
    let rows = residual_axes::rows(before) as u32;
    emit(
        RESIDUALS_PER_AXIS,
        (
            RESIDUALS_PER_AXIS_WIDTH,
            style::HEADER_H + rows * RESIDUALS_PER_AXIS_ROW,
        ),
        described("Residuals per axis (predicted − measured)".into()),
        &|root| draw_residual_axes(root, &ctx),
    )?;
    if let Some(c) = best {
        emit(
            ERROR_VS_CONDITION,
            ERROR_VS_CONDITION_SIZE,
            described(error_vs_condition::title(&ctx, c)),
            &|root| draw_error_vs_condition(root, &ctx, c),
        )?;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// What is plotted.

/// Everything the three plots share.
struct PlotContext<'a> {
    data: &'a FlightData,
    before: &'a Comparison,
    after: Option<(&'a Comparison, &'a str)>,
    data_name: String,
    model_name: String,
    noise_floor: Option<f64>,
    window_s: Option<f64>,
    t_range: Range<f64>,
    has_vel: bool,
    has_att: bool,
}

impl<'a> PlotContext<'a> {
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
            window_s: info.window_s.filter(|w| w.is_finite() && *w > 0.0),
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
        format!(
            "{} samples over {:.1} s; {}{remark}",
            self.data.len(),
            self.data.duration(),
            windows_text(self.before, self.window_s)
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

/// One line per compared window, each a list of `(t, value)` points.
type Segments = Vec<Vec<(f64, f64)>>;

/// Per compared window, the points `(t, f(prediction, k, i))` of its prediction, `k` indexing
/// the prediction and `i` the data sample it predicts, at the rows that are samples of every
/// channel of `measured` (a row filled in between a channel's samples is no measurement).
fn window_segments(
    data: &FlightData,
    cmp: &Comparison,
    measured: &[Channel],
    f: &dyn Fn(&Prediction, usize, usize) -> f64,
) -> Segments {
    let p = &cmp.prediction;
    let sampled = |i: usize| measured.iter().all(|&c| data.sampling.at(c, i));
    prediction_windows(cmp)
        .into_iter()
        .map(|(_, k0, len)| {
            (k0..k0 + len)
                .filter(|&k| k < p.index.len() && p.index[k] < data.len())
                .filter(|&k| sampled(p.index[k]))
                .map(|k| (data.time[p.index[k]], f(p, k, p.index[k])))
                .collect()
        })
        .collect()
}

/// "6 windows of 8 s" — as `compare` prints it — for the window length asked for; "6 windows
/// of about 7.5 s" (their mean length) when it is not known.
pub fn windows_text(cmp: &Comparison, window_s: Option<f64>) -> String {
    let n = cmp.windows.len();
    let plural = if n == 1 { "" } else { "s" };
    match window_s {
        Some(w) => format!("{n} window{plural} of {w} s"),
        None => {
            let mean = cmp.windows.iter().map(|w| w.t1 - w.t0).sum::<f64>() / n.max(1) as f64;
            format!("{n} window{plural} of about {mean:.1} s")
        }
    }
}
