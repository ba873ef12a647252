//! A report people can read: one self-contained HTML page of a comparison or a diagnosis —
//! the verdict in words, the ladder of causes, the error per channel and axis before and
//! after, the fitted values with ± and their change from the set, the plots of
//! [`crate::plots`] and a small replay GIF inline (base64), and what to do next. No script,
//! no network: the page is the one file.
//!
//! Pure string building over the analysis crate's values ([`report_html`]) and one atomic
//! write ([`write_report`]).

mod html;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use thiserror::Error;

use self::html::{esc, esc_code, figure, table, STYLE};
use crate::plots::{
    render_plots, windows_text, ConditionSeries, PlotError, PlotInfo, ERROR_VS_CONDITION,
    MEASURED_VS_MODEL, RESIDUALS, RESIDUALS_PER_AXIS,
};
use crate::track::model_track;
use wireflight_analysis::compare::{Comparison, NoiseEstimate};
use wireflight_analysis::conditions::Condition;
use wireflight_analysis::diagnose::turbulence::TurbulenceFinding;
use wireflight_analysis::diagnose::{Candidate, Diagnosis, Verdict};
use wireflight_analysis::filter_error::flight::{
    GUST_LR_BOUND, MAX_INNOVATION_SPREAD, MIN_TURBULENCE_MPS, TURBULENCE_LR_BOUND,
};
use wireflight_analysis::report::{innovations_text, noise_text, verdict_text};
use wireflight_data::format::{fixed, fmt_number, signed};
use wireflight_data::FlightData;
use wireflight_draw::render::gif::GifAnimation;
use wireflight_draw::render::Rasterizer;
use wireflight_draw::scene::replay::ReplayScene;
use wireflight_flight::params::keys;
use wireflight_geometry::clip::Clipper;
use wireflight_geometry::pipeline::Viewport;

/// Why a report could not be made or written. Every error names the report's file.
#[derive(Debug, Error)]
pub enum ReportError {
    /// A plot could not be drawn.
    #[error("{}: cannot draw the report's plots", path.display())]
    Plots {
        /// The report.
        path: PathBuf,
        /// Why.
        #[source]
        source: PlotError,
    },
    /// The replay could not be drawn.
    #[error("{}: cannot draw the report's replay: {message}", path.display())]
    Replay {
        /// The report.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The file could not be written.
    #[error(transparent)]
    Write(#[from] wireflight_fsio::FsError),
}

/// The replay GIF of a report: small and slow, so the page stays small.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplaySize {
    /// Width and height, pixels.
    pub size: (u32, u32),
    /// Frames per second of flight time.
    pub fps: f64,
    /// At most this many frames (the flight is sampled more sparsely beyond).
    pub max_frames: usize,
}

impl Default for ReplaySize {
    fn default() -> Self {
        Self {
            size: (320, 240),
            fps: 2.0,
            max_frames: 120,
        }
    }
}

/// What a report shows.
pub struct Report<'a> {
    /// The command that made it, for the footer (`wireflight diagnose --flight a.csv`).
    pub command: String,
    /// The data's name (its file).
    pub data_name: String,
    /// The measured flight.
    pub data: &'a FlightData,
    /// The model as given, in a few words (`fixed-wing baseline`).
    pub model_name: String,
    /// Its comparison with the data.
    pub before: &'a Comparison,
    /// The comparison with the causes found (diagnose) or the `--add` effects (compare), and
    /// its label (`+ wind + aircraft:c_m_q`).
    pub after: Option<(&'a Comparison, String)>,
    /// The measured noise.
    pub noise: &'a NoiseEstimate,
    /// The total a right model leaves on these data.
    pub noise_floor: f64,
    /// The window length asked for, s.
    pub window_s: f64,
    /// The flight conditions the error follows, strongest first, as the text lists them (the
    /// first is plotted and quoted).
    pub conditions: &'a [Condition],
    /// The diagnosis, for `diagnose`.
    pub diagnosis: Option<&'a Diagnosis>,
    /// The causes fitted: the diagnosis's found causes, or compare's `--add` effects.
    pub fitted: &'a [Candidate],
    /// The replay's size (None: no replay).
    pub replay: Option<ReplaySize>,
    /// Misfit in noise units that counts as at the noise (`DiagnoseConfig::at_floor`).
    pub at_floor: f64,
    /// What the misfit is in units of: `noise`, or `floor` against reference flights or
    /// stated sensor errors.
    pub unit: &'static str,
    /// The filter-error method's account, where it ran (the diagnosis's, or compare's).
    pub turbulence: Option<&'a TurbulenceFinding>,
}

/// Write the report to `path` atomically.
///
/// # Errors
/// Plots or replay that cannot be drawn; a file that cannot be written.
pub fn write_report(path: &Path, report: &Report) -> Result<(), ReportError> {
    let page = report_html(path, report)?;
    wireflight_fsio::write_atomic(path, page.as_bytes())?;
    Ok(())
}

/// "pitch damping `c_m_q`" (for `aircraft:c_m_q`), "the mass `mass_kg`", "`wind` (a steady
/// wind …)": a cause named by what it is, then by its key.
pub fn physical_name(effect: &str) -> String {
    if let Some(key) = effect.strip_prefix("aircraft:") {
        return match keys::find(key) {
            Some(k) => {
                let term = k.term;
                let what = match (term.find('('), term.rfind(')')) {
                    (Some(a), Some(b)) if b > a => &term[a + 1..b],
                    _ => term.split(':').next().unwrap_or(term),
                };
                format!("{} `{key}`", what.trim())
            }
            None => format!("`{effect}`"),
        };
    }
    match wireflight_flight::effects::find(effect) {
        Some(info) => format!("`{effect}` ({})", info.summary.trim_end_matches('.')),
        None => format!("`{effect}`"),
    }
}

/// The page, as one string. `path` names the report in errors.
///
/// # Errors
/// Plots or replay that cannot be drawn.
pub fn report_html(path: &Path, r: &Report) -> Result<String, ReportError> {
    let after = r.after.as_ref().map(|(c, l)| (*c, l.as_str()));
    let condition = r.conditions.first().map(|c| ConditionSeries {
        name: c.name.to_string(),
        unit: c.unit.to_string(),
        per_window: c.per_window.clone(),
    });
    let info = PlotInfo {
        data_name: Some(r.data_name.clone()),
        model_name: Some(r.model_name.clone()),
        noise_floor: Some(r.noise_floor),
        window_s: Some(r.window_s),
    };
    let plots = render_plots(path, r.data, r.before, after, condition.as_ref(), &info).map_err(
        |source| ReportError::Plots {
            path: path.to_path_buf(),
            source,
        },
    )?;
    let png = |name: &str| {
        plots
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, b)| b.as_slice())
    };
    let gif = match r.replay {
        Some(size) => Some(replay_gif(r, size).map_err(|message| ReportError::Replay {
            path: path.to_path_buf(),
            message,
        })?),
        None => None,
    };

    let mut body = String::new();
    let what = if r.diagnosis.is_some() {
        "Diagnosis"
    } else {
        "Comparison"
    };
    let _ = writeln!(
        body,
        "<h1>{what}: {}</h1>\n<p class=\"meta\">{} samples over {} s, {}; model {}</p>\n\
         <p class=\"meta\">{}</p>",
        esc(&r.data_name),
        r.data.len(),
        fixed(r.data.duration(), 1),
        esc(&windows_text(r.before, Some(r.window_s))),
        esc(&r.model_name),
        esc(&noise_text(r.noise))
    );
    body.push_str(&verdict_section(r));
    if let Some(d) = r.diagnosis {
        body.push_str(&ladder_section(d, r.unit));
    }
    body.push_str(&errors_section(r));
    body.push_str(&fitted_section(r));
    body.push_str(&turbulence_section(r));
    body.push_str("<h2>Where the error is</h2>\n");
    if let Some(b) = png(RESIDUALS_PER_AXIS) {
        let caption = match &r.after {
            Some((_, label)) => format!(
                "Predicted − measured on every axis the data have, the model as given (light \
                 blue) behind the model {label} (green); dashed: ±1σ of the measurement noise; \
                 shaded: the worst windows."
            ),
            None => "Predicted − measured on every axis the data have; dashed: ±1σ of the \
                     measurement noise; shaded: the worst windows."
                .to_string(),
        };
        body.push_str(&figure(
            "residuals-per-axis",
            "image/png",
            b,
            "residuals per axis over time",
            &caption,
        ));
    }
    if let Some(b) = png(RESIDUALS) {
        body.push_str(&figure(
            "residuals",
            "image/png",
            b,
            "window score and error size over time",
            "The window score and the size of each channel's error per sample, before and \
             after; dashed: the noise floor and the measurement noise.",
        ));
    }
    if let (Some(b), Some(c)) = (png(ERROR_VS_CONDITION), r.conditions.first()) {
        let r_text = c.correlation.map_or("n/a".to_string(), |v| signed(v, 2));
        body.push_str(&figure(
            "conditions",
            "image/png",
            b,
            "window error against a flight condition",
            &format!(
                "Of the flight conditions, the window error follows {} ({}) most closely: \
                 r = {r_text}, as the text says; one dot per window.",
                c.name, c.unit
            ),
        ));
    }
    if let Some(b) = png(MEASURED_VS_MODEL) {
        body.push_str(&figure(
            "measured-vs-model",
            "image/png",
            b,
            "measured against predicted",
            "Measured (black) and predicted, each window restarted from its fitted start.",
        ));
    }
    if let Some(g) = &gif {
        let model = match &r.after {
            Some((_, label)) => format!("{} {label}", r.model_name),
            None => r.model_name.clone(),
        };
        body.push_str(&figure(
            "replay",
            "image/gif",
            g,
            "replay of the measured and the model's aircraft",
            &format!(
                "Replay: the measured aircraft (green) and the model {model} (magenta), the \
                 position error over time below."
            ),
        ));
    }
    body.push_str(&next_section(r));
    let _ = writeln!(
        body,
        "<footer>Made by <code>{}</code>. One file: the pictures are inline, nothing is \
         fetched.</footer>",
        esc(&r.command)
    );
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>wireflight {} — {}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n\
         <main>\n{body}</main>\n</body>\n</html>\n",
        what.to_lowercase(),
        esc(&r.data_name)
    ))
}

/// "c_m_q=-38.21±0.1 (+0.3% from the set)" parts of a cause, one per parameter, as rows.
fn fitted_rows(c: &Candidate) -> Vec<Vec<String>> {
    let changes = c.changes_percent();
    let previous: Vec<(&str, f64)> = match &c.correction {
        wireflight_analysis::diagnose::Correction::Aircraft(ch) => {
            ch.iter().map(|a| (a.key, a.was)).collect()
        }
        wireflight_analysis::diagnose::Correction::Effect(_) => Vec::new(),
    };
    c.params
        .iter()
        .enumerate()
        .map(|(i, (k, v))| {
            let u = c.uncertainty.get(i).copied().unwrap_or(f64::NAN);
            let sigma = if c.held.get(i).copied().unwrap_or(false) {
                "held".to_string()
            } else if c.at_limit.get(i).copied().unwrap_or(false) {
                "at its limit: not an estimate".to_string()
            } else if u.is_finite() {
                format!("±{}", fmt_number(u))
            } else {
                "not determined".to_string()
            };
            let was = previous
                .iter()
                .find(|(key, _)| key == k)
                .map_or("—".to_string(), |(_, w)| fmt_number(*w));
            let change = match changes.iter().find(|(key, _)| key == k) {
                Some((_, Some(p))) => format!("{}%", signed(*p, 1)),
                Some((_, None)) => "new".to_string(),
                None => "—".to_string(),
            };
            vec![
                esc_code(&physical_name(&c.effect)),
                format!("<code>{}</code>", esc(k)),
                esc(&fmt_number(*v)),
                esc(&sigma),
                esc(&was),
                esc(&change),
            ]
        })
        .collect()
}

/// The verdict in words, with every cause named by what it is.
fn verdict_section(r: &Report) -> String {
    let mut out = String::from("<h2>Verdict</h2>\n");
    let unit = r.unit;
    let Some(d) = r.diagnosis else {
        // compare: the error, and what the added effects do.
        let b = r.before;
        let mut text = format!(
            "The model's error is {} ({} × the {}; a right model leaves {}).",
            fixed(b.total, 3),
            fixed(b.noise_units(), 2),
            if unit == "noise" {
                "measurement noise"
            } else {
                "floor"
            },
            fixed(r.noise_floor, 3)
        );
        let class = match &r.after {
            Some((a, label)) => {
                let names: Vec<String> =
                    r.fitted.iter().map(|c| physical_name(&c.effect)).collect();
                let _ = write!(
                    text,
                    " With {} ({label}) it falls to {} ({} × the {unit}){}.",
                    if names.is_empty() {
                        label.clone()
                    } else {
                        names.join(" and ")
                    },
                    fixed(a.total, 3),
                    fixed(a.noise_units(), 2),
                    if a.noise_units() <= r.at_floor {
                        format!(": at the {unit}")
                    } else {
                        format!(", still above the {unit}")
                    }
                );
                if a.noise_units() <= r.at_floor {
                    "found"
                } else {
                    "unexplained"
                }
            }
            None if b.noise_units() <= r.at_floor => "found",
            None => "unexplained",
        };
        let _ = writeln!(
            out,
            "<div class=\"verdict {class}\" id=\"verdict\"><p>{}</p></div>",
            esc_code(&text)
        );
        return out;
    };
    let names: Vec<String> = d.found.iter().map(|c| physical_name(&c.effect)).collect();
    let fall = format!(
        "the error falls {} → {} ({} × the {unit})",
        fixed(d.base_error, 3),
        fixed(d.found_error, 3),
        fixed(d.found_noise_units, 2)
    );
    let (class, sentence) = match &d.verdict {
        Verdict::Found(_) if d.found.len() == 1 => (
            "found",
            format!(
                "{} {}: with it {fall}.",
                names[0],
                if d.found[0].effect.starts_with("aircraft:") {
                    "is wrong in the set"
                } else {
                    "is missing from the model"
                }
            ),
        ),
        Verdict::Found(_) => (
            "found",
            format!(
                "{} causes at once, fitted together: {}; with them {fall}.",
                d.found.len(),
                names.join(", ")
            ),
        ),
        Verdict::None => (
            "none",
            format!(
                "Nothing is missing that these data can show: the error is at the {unit} ({} \
                 × the {unit}).",
                fixed(d.noise_units, 2)
            ),
        ),
        Verdict::Unexplained if !d.found.is_empty() => (
            "unexplained",
            format!(
                "Unexplained: with {} {fall}, still above the {unit}, and no further candidate \
                 is significant — part of the answer.",
                names.join(" and ")
            ),
        ),
        Verdict::Unexplained => (
            "unexplained",
            format!(
                "Unexplained: the error stays {} × the {unit} and no candidate is significant.",
                fixed(d.noise_units, 2)
            ),
        ),
        Verdict::Turbulence(_) => (
            "found",
            format!(
                "Turbulence: what output error leaves is random, gusts the filter-error method \
                 estimates{}{}.",
                if names.is_empty() {
                    String::new()
                } else {
                    format!(", with {} besides", names.join(" and "))
                },
                if d.turbulence.as_ref().is_some_and(|t| t.aircraft_searched) {
                    ""
                } else {
                    "; the aircraft's numbers were not searched through the filter"
                }
            ),
        ),
    };
    let _ = writeln!(
        out,
        "<div class=\"verdict {class}\" id=\"verdict\">\n<p>{}</p>\n\
         <p class=\"detail\">verdict: {}</p>",
        esc_code(&sentence),
        esc_code(&verdict_text(d))
    );
    if !d.alternatives.is_empty() {
        let alts: Vec<String> = d.alternatives.iter().map(|a| physical_name(a)).collect();
        let _ = writeln!(
            out,
            "<p class=\"detail\">As good an explanation: {} — these data cannot tell them \
             apart.</p>",
            esc_code(&alts.join(", "))
        );
    }
    for e in &d.evidence {
        let _ = writeln!(out, "<p class=\"detail\">evidence: {}</p>", esc(e));
    }
    out.push_str("</div>\n");
    out
}

/// The ladder: each step's model, its error, what it added and dropped.
fn ladder_section(d: &Diagnosis, unit: &str) -> String {
    let mut rows = Vec::new();
    for (i, s) in d.steps.iter().enumerate() {
        let model = if s.effects.is_empty() {
            "baseline".to_string()
        } else {
            format!("+ {}", s.effects.join(" + "))
        };
        rows.push(vec![
            (i + 1).to_string(),
            esc(&model),
            fixed(s.error, 3),
            fixed(s.noise_units, 2),
            s.added
                .as_ref()
                .map_or("— (nothing significant: stop)".to_string(), |a| {
                    esc_code(&physical_name(a))
                }),
            if s.dropped.is_empty() {
                "—".to_string()
            } else {
                esc(&s.dropped.join(", "))
            },
            if s.added.is_some() {
                format!(
                    "{} ({} × {})",
                    fixed(s.error_after, 3),
                    fixed(s.noise_units_after, 2),
                    unit
                )
            } else {
                "—".to_string()
            },
        ]);
    }
    format!(
        "<h2>How the causes were found</h2>\n<p>Each step screens every candidate on top of the \
         causes kept so far, adds the best significant one and refits all of them \
         together.</p>\n{}",
        table(
            &[
                "step",
                "model",
                "error",
                &format!("× {}", unit),
                "added",
                "dropped",
                "after, fitted together"
            ],
            &rows
        )
    )
}

/// The error per channel and per axis, before and after.
fn errors_section(r: &Report) -> String {
    let a = r.after.as_ref().map(|(c, _)| *c);
    let label = r.after.as_ref().map_or("", |(_, l)| l.as_str());
    let after_head = format!("with {}", label.trim_start_matches("+ "));
    let mut out = String::from(
        "<h2>The error, channel by channel and axis by axis</h2>\n<div class=\"tables\">\n<div>\n",
    );
    type Channel = fn(&Comparison) -> Option<f64>;
    let channels: [(&str, Channel, &str); 4] = [
        ("position", |c| Some(c.channels.position_m), "m"),
        ("velocity", |c| c.channels.velocity_mps, "m/s"),
        ("attitude", |c| c.channels.attitude_deg, "°"),
        ("rates", |c| c.channels.rate_dps, "°/s"),
    ];
    let cell = |v: Option<f64>, unit: &str| {
        v.map_or("—".to_string(), |v| format!("{} {unit}", fixed(v, 3)))
    };
    let mut rows: Vec<Vec<String>> = Vec::new();
    for (name, get, unit) in channels {
        let mut row = vec![name.to_string(), esc(&cell(get(r.before), unit))];
        if let Some(a) = a {
            row.push(esc(&cell(get(a), unit)));
        }
        rows.push(row);
    }
    let mut total = vec!["total".to_string(), fixed(r.before.total, 3)];
    let mut units = vec![format!("× {}", r.unit), fixed(r.before.noise_units(), 2)];
    if let Some(a) = a {
        total.push(fixed(a.total, 3));
        units.push(fixed(a.noise_units(), 2));
    }
    rows.push(total);
    rows.push(units);
    let head: Vec<&str> = match a {
        Some(_) => vec!["channel", "model as given", &after_head],
        None => vec!["channel", "error"],
    };
    out.push_str(&table(&head, &rows));
    let _ = writeln!(
        out,
        "<p class=\"note\">{} {}: the total a right model leaves on these \
         data.</p>\n</div>\n<div>",
        if r.unit == "noise" {
            "Noise floor"
        } else {
            "Floor"
        },
        fixed(r.noise_floor, 3)
    );
    let mut rows = Vec::new();
    for x in &r.before.axes {
        let mut row = vec![
            esc(&format!("{} {}", x.channel, x.axis)),
            signed(x.mean, 3),
            fixed(x.rms, 3),
        ];
        if let Some(a) = a {
            match a
                .axes
                .iter()
                .find(|y| y.channel == x.channel && y.axis == x.axis)
            {
                Some(y) => row.extend([signed(y.mean, 3), fixed(y.rms, 3)]),
                None => row.extend(["—".to_string(), "—".to_string()]),
            }
        }
        row.push(esc(x.unit));
        rows.push(row);
    }
    let head: Vec<&str> = match a {
        Some(_) => vec!["axis", "mean", "RMS", "mean after", "RMS after", "unit"],
        None => vec!["axis", "mean", "RMS", "unit"],
    };
    out.push_str(&table(&head, &rows));
    out.push_str(
        "<p class=\"note\">Per axis: predicted − measured over all windows.</p>\n</div>\n\
         </div>\n",
    );
    out
}

/// The fitted values with ± and the change from the set.
fn fitted_section(r: &Report) -> String {
    if r.fitted.is_empty() {
        return String::new();
    }
    let rows: Vec<Vec<String>> = r.fitted.iter().flat_map(fitted_rows).collect();
    format!(
        "<h2>The fitted values</h2>\n{}<p>± is 1σ, from the joint fit of every cause and every \
         window's start.</p>\n",
        table(
            &[
                "cause",
                "parameter",
                "fitted",
                "±1σ",
                "in the set",
                "change"
            ],
            &rows
        )
    )
}

/// The filter-error method's account: the gusts with their ±, the test against calm air,
/// the innovations, and the numbers fitted through the filter beside output error's.
fn turbulence_section(r: &Report) -> String {
    let Some(t) = r.turbulence else {
        return String::new();
    };
    let g = &t.gusts;
    let mut out = String::from("<h2 id=\"turbulence\">Turbulence: the filter-error method</h2>\n");
    let judged = if t.significant() {
        "The gusts are significant"
    } else {
        "The gusts are not significant"
    };
    let _ =
        writeln!(
        out,
        "<p>{judged}{}: the likelihood ratio against calm air is {} (above {} needed), that of \
         the gust velocities alone {} (above {}); a gust σ must be at least {} m/s, and the \
         filter's innovations are {} × the spread it expects for them (at most {}). Output \
         error leaves {} × the noise; the filter's innovations are {}.</p>",
        if t.forced { " (the filter was asked for)" } else { "" },
        fixed(g.likelihood_ratio, 1),
        fixed(TURBULENCE_LR_BOUND, 2),
        fixed(g.gust_likelihood_ratio, 1),
        fixed(GUST_LR_BOUND, 2),
        fixed(MIN_TURBULENCE_MPS, 2),
        fixed(g.gusty.normalised, 2),
        fixed(MAX_INNOVATION_SPREAD, 1),
        fixed(g.calm.noise_units, 2),
        esc(&innovations_text(&g.gusty)),
    );
    let mut rows: Vec<Vec<String>> = ["north", "east", "down"]
        .iter()
        .enumerate()
        .map(|(k, axis)| {
            vec![
                format!("gust {axis}"),
                fixed(g.sigma_mps[k], 2),
                fixed(g.sigma_se_mps[k], 2),
                "m/s".to_string(),
                t.reference_sigma_mps
                    .map_or("—".to_string(), |(f, _)| fixed(f[k], 2)),
            ]
        })
        .collect();
    rows.extend(["x", "y", "z"].iter().enumerate().map(|(k, axis)| {
        vec![
            format!("rotary about {axis}"),
            fixed(g.rotary_radps2[k], 3),
            fixed(g.rotary_se_radps2[k], 3),
            "rad/s²".to_string(),
            "—".to_string(),
        ]
    }));
    out.push_str(&table(
        &[
            "disturbance",
            "σ",
            "±1σ",
            "unit",
            "on the reference flights",
        ],
        &rows,
    ));
    if !t.refits.is_empty() {
        let rows: Vec<Vec<String>> = t
            .refits
            .iter()
            .map(|f| {
                vec![
                    f.cause.clone(),
                    f.param.clone(),
                    fmt_number(f.value),
                    fmt_number(f.sigma),
                    if f.added {
                        "— (found by the filter)".to_string()
                    } else {
                        fmt_number(f.output_error)
                    },
                ]
            })
            .collect();
        out.push_str("<p>The numbers fitted again through the filter:</p>\n");
        out.push_str(&table(
            &[
                "cause",
                "number",
                "through the filter",
                "±1σ",
                "output error",
            ],
            &rows,
        ));
    }
    out
}

/// What to do next, from what was found.
fn next_section(r: &Report) -> String {
    let mut items: Vec<String> = Vec::new();
    let keep = match r.diagnosis {
        Some(_) => "<code>wireflight diagnose … --out model.toml</code>",
        None => "<code>wireflight compare … --add … --out model.toml</code>",
    };
    let found = match r.diagnosis {
        Some(d) => matches!(d.verdict, Verdict::Found(_)) || !d.found.is_empty(),
        None => !r.fitted.is_empty(),
    };
    if found {
        items.push(format!(
            "Keep what was found: {keep} writes the model with these causes and their fitted \
             values, for <code>--model model.toml</code> in every command."
        ));
    }
    if let Some(d) = r.diagnosis {
        let mut same: Vec<String> = d.alternatives.clone();
        for s in &d.steps {
            same.extend(s.alternatives.iter().cloned());
        }
        if !same.is_empty() {
            items.push(format!(
                "These data cannot tell {} apart from what was found: fly a manoeuvre that \
                 varies what they differ in (another height, speed or control input) and \
                 diagnose that flight too.",
                esc_code(
                    &same
                        .iter()
                        .map(|a| physical_name(a))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            ));
        }
        if matches!(d.verdict, Verdict::Unexplained) {
            items.push(
                "The error stays above the noise: look at the axes and the condition above, \
                 and try <code>wireflight identify</code> to fit many numbers of the set \
                 together over several flights."
                    .to_string(),
            );
        }
    }
    if r.fitted.iter().any(|c| c.effect.starts_with("aircraft:")) {
        items.push(
            "Numbers of the set moved: check them on other flights with <code>wireflight \
             identify --flight … --validate …</code>, which fits them over several flights and \
             holds one out."
                .to_string(),
        );
    }
    if items.is_empty() {
        items.push(
            "Run <code>wireflight diagnose</code> to try every effect and every number of the \
             set."
                .to_string(),
        );
    }
    let mut out = String::from("<h2>What to do next</h2>\n<ol class=\"next\">\n");
    for i in items {
        let _ = writeln!(out, "<li>{i}</li>");
    }
    out.push_str("</ol>\n");
    out
}

/// The replay as GIF bytes: both aircraft and the error strip, at `size`.
fn replay_gif(r: &Report, size: ReplaySize) -> Result<Vec<u8>, String> {
    let last = r.after.as_ref().map_or(r.before, |(c, _)| *c);
    let mut track = model_track(r.data, last).map_err(|e| e.to_string())?;
    // One scale for before and after, so the strip shows the error fall.
    let b = &r.before.prediction;
    track.strip_scale_m = b
        .pos_ned
        .iter()
        .zip(&b.index)
        .map(|(p, &i)| (*p - r.data.pos_ned[i]).length())
        .fold(track.strip_scale_m, f64::max);
    let mesh = wireflight_geometry::mesh::plane::builtin_plane();
    let mut replay = ReplayScene::new(r.data, &mesh, Clipper::Blinn)
        .map_err(|e| e.to_string())?
        .with_model(track);
    let (t0, t1) = (r.data.time[0], r.data.time[r.data.len() - 1]);
    let frames = (((t1 - t0) * size.fps).floor() as usize + 1).clamp(1, size.max_frames.max(1));
    let step = if frames > 1 {
        (t1 - t0) / (frames - 1) as f64
    } else {
        0.0
    };
    let viewport = Viewport {
        width: size.size.0,
        height: size.size.1,
    };
    let mut gif = GifAnimation::new(
        viewport.width,
        viewport.height,
        GifAnimation::delay_for(size.fps),
    )
    .map_err(|e| e.to_string())?;
    let mut rasterizer = Rasterizer::Cpu;
    for k in 0..frames {
        let (lines, _) = replay.frame(t0 + k as f64 * step, viewport);
        let image = rasterizer.draw(lines).map_err(|e| e.to_string())?;
        gif.push(&image).map_err(|e| e.to_string())?;
    }
    gif.finish().map_err(|e| e.to_string())
}
