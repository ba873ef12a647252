//! Results as people and programs read them: the text tables and the JSON of comparisons,
//! diagnoses and identifications, one formatter for every command and the window. Pure:
//! builds strings and JSON values, writes nothing.

use std::fmt::Write as _;

mod assessment;
mod discovery;
mod identification;
pub use assessment::{assessment_json, assessment_text, Names};
pub use discovery::{discovery_json, discovery_text};
pub use identification::{identification_json, identification_text, Flights};

use serde_json::{json, Map, Value};

use crate::compare::{AxisError, ChannelErrors, Comparison, NoiseEstimate};
use crate::conditions::Condition;
use crate::diagnose::reference::ReferenceVerdict;
use crate::diagnose::{Candidate, Diagnosis, Verdict};
use crate::error_floor::ErrorFloor;
use crate::reference::ModelFloor;
use wireflight_data::format::{fixed, fmt_number, signed};
use wireflight_data::VehicleKind;
use wireflight_flight::model::Model;

/// A text table whose columns line up: numbers right-aligned, names and words left-aligned
/// (the first column always left; another column right when every cell under its header is
/// a number: it starts with a digit, a sign or `±`, or is `n/a`, `—` or empty), widths
/// measured in characters (so °, ± and → count as one).
#[derive(Clone, Debug, Default)]
pub struct Table {
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with a header row.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        Self {
            rows: vec![header.into_iter().map(Into::into).collect()],
        }
    }

    /// Add a row.
    pub fn row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) -> &mut Self {
        self.rows.push(cells.into_iter().map(Into::into).collect());
        self
    }

    /// The table, each line indented by `indent` spaces and ending in a newline.
    pub fn render(&self, indent: usize) -> String {
        let cols = self.rows.iter().map(Vec::len).max().unwrap_or(0);
        let mut width = vec![0; cols];
        for r in &self.rows {
            for (w, c) in width.iter_mut().zip(r) {
                *w = (*w).max(c.chars().count());
            }
        }
        let right: Vec<bool> = (0..cols)
            .map(|k| {
                let mut body = self.rows.iter().skip(1).filter_map(|r| r.get(k));
                k > 0 && body.all(|c| is_numeric_cell(c))
            })
            .collect();
        let mut out = String::new();
        for r in &self.rows {
            let mut line = " ".repeat(indent);
            for (k, w) in width.iter().enumerate() {
                let cell = r.get(k).map(String::as_str).unwrap_or("");
                let pad = w - cell.chars().count();
                if k == 0 {
                    line.push_str(cell);
                    line.push_str(&" ".repeat(pad));
                } else if !right[k] {
                    line.push_str("  ");
                    line.push_str(cell);
                    line.push_str(&" ".repeat(pad));
                } else {
                    line.push_str("  ");
                    line.push_str(&" ".repeat(pad));
                    line.push_str(cell);
                }
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }
}

/// A cell that reads as a number (for alignment): it starts with a digit, possibly after a
/// sign or `±`, or is `n/a`, `—` or empty.
fn is_numeric_cell(c: &str) -> bool {
    let c = c.trim();
    if c.is_empty() || c == "n/a" || c == "—" {
        return true;
    }
    let c = c.trim_start_matches(['+', '-', '−', '±']);
    c.starts_with(|ch: char| ch.is_ascii_digit())
}

/// A value with its unit, or "—" when the data lack the channel.
pub fn fmt_opt(v: Option<f64>, unit: &str) -> String {
    v.map(|x| format!("{} {unit}", fixed(x, 3)))
        .unwrap_or_else(|| "—".into())
}

/// `k=v±σ ...` of a candidate's parameters (held ones marked, those at a limit of their
/// range marked, the change from the set in % for aircraft numbers — "new" where the set
/// has 0), or "" without parameters.
pub fn fmt_params(c: &Candidate) -> String {
    let changes = c.changes_percent();
    c.params
        .iter()
        .enumerate()
        .map(|(i, (k, v))| {
            let change = match changes.iter().find(|(key, _)| key == k) {
                Some((_, Some(pct))) => format!(" ({}% from the set)", signed(*pct, 1)),
                Some((_, None)) => " (new: the set has 0)".to_string(),
                None => String::new(),
            };
            let u = c.uncertainty.get(i).copied().unwrap_or(f64::NAN);
            if c.held.get(i).copied().unwrap_or(false) {
                format!("{k}={} (held)", fmt_number(*v))
            } else if c.at_limit.get(i).copied().unwrap_or(false) {
                format!(
                    "{k}={} (at its limit: not an estimate){change}",
                    fmt_number(*v)
                )
            } else if u.is_finite() {
                format!("{k}={}±{}{change}", fmt_number(*v), fmt_number(u))
            } else {
                format!("{k}={} (not determined){change}", fmt_number(*v))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// "baseline" or "+ a + b": the effects of a model, for titles and tables.
pub fn model_effects_label(model: &Model) -> String {
    if model.effects.is_empty() {
        "baseline".to_string()
    } else {
        format!("+ {}", model.effect_names().join(" + "))
    }
}

/// "fixed-wing baseline", "point-mass + drag": a model in a few words.
pub fn model_label(model: &Model) -> String {
    format!("{} {}", model.vehicle.kind(), model_effects_label(model))
}

/// "1 window", "3 windows".
pub fn count(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

// ------------------------------------------------------------------------------------------
// JSON
// ------------------------------------------------------------------------------------------

/// The per-channel errors as JSON.
pub fn channels_json(c: &ChannelErrors) -> Value {
    json!({
        "position_m": c.position_m,
        "velocity_mps": c.velocity_mps,
        "attitude_deg": c.attitude_deg,
        "rate_dps": c.rate_dps,
    })
}

fn axes_json(axes: &[AxisError]) -> Value {
    Value::Array(
        axes.iter()
            .map(|a| {
                json!({"channel": a.channel, "axis": a.axis, "unit": a.unit,
                       "mean": a.mean, "rms": a.rms})
            })
            .collect(),
    )
}

/// `{"total", "channels", "noise_units", "axes", ...}` of a comparison.
pub fn comparison_json(c: &Comparison) -> Value {
    json!({
        "total": c.total,
        "channels": channels_json(&c.channels),
        "noise_units": c.noise_units(),
        "chi2": c.chi2,
        "dof": c.dof,
        "residual_autocorrelation": c.residual_autocorrelation(),
        "axes": axes_json(&c.axes),
    })
}

/// The windows, worst first, with their dominant channel.
pub fn windows_json(c: &Comparison) -> Value {
    Value::Array(
        c.worst_windows()
            .iter()
            .map(|w| {
                json!({
                    "t0": w.t0, "t1": w.t1, "score": w.score,
                    "dominant_channel": w.errors.dominant(),
                    "channels": channels_json(&w.errors),
                    "noise_units": (w.chi2 / w.residuals.max(1) as f64).sqrt(),
                })
            })
            .collect(),
    )
}

/// The measured noise, per channel (RMS over axes) and per axis.
pub fn noise_json(n: &NoiseEstimate) -> Value {
    let deg = |a: [f64; 3]| a.map(f64::to_degrees);
    json!({
        "position_m": n.pos_m,
        "velocity_mps": n.vel_mps,
        "attitude_deg": n.att_rad.to_degrees(),
        "rate_dps": n.rate_radps.to_degrees(),
        "airspeed_mps": n.airspeed_mps,
        "accel_mps2": n.accel_mps2,
        "axes": {
            "position_m": n.pos_axes,
            "velocity_mps": n.vel_axes,
            "attitude_deg": deg(n.att_axes),
            "rate_dps": deg(n.rate_axes),
            "accel_mps2": n.accel_axes,
        },
    })
}

/// Flight conditions and their correlation with the window error (`null` where undefined).
pub fn conditions_json(conds: &[Condition]) -> Value {
    Value::Array(
        conds
            .iter()
            .map(|c| json!({"name": c.name, "unit": c.unit, "correlation": c.correlation}))
            .collect(),
    )
}

/// One tried effect: parameters, uncertainty (1σ), correlations, errors, significance.
pub fn candidate_json(c: &Candidate) -> Value {
    let params: Map<String, Value> = c
        .params
        .iter()
        .map(|(k, v)| (k.clone(), json!(v)))
        .collect();
    let unc: Map<String, Value> = c
        .params
        .iter()
        .zip(&c.uncertainty)
        .filter(|(_, u)| u.is_finite())
        .map(|((k, _), u)| (k.clone(), json!(u)))
        .collect();
    let held: Vec<&String> = c
        .params
        .iter()
        .zip(&c.held)
        .filter(|(_, h)| **h)
        .map(|((k, _), _)| k)
        .collect();
    let change: Map<String, Value> = c
        .changes_percent()
        .into_iter()
        .map(|(k, v)| (k.to_string(), v.map_or(json!("new"), |v| json!(v))))
        .collect();
    let at_limit: Vec<&String> = c
        .params
        .iter()
        .zip(&c.at_limit)
        .filter(|(_, l)| **l)
        .map(|((k, _), _)| k)
        .collect();
    json!({
        "effect": c.effect,
        "params": params,
        "change_percent": change,
        "uncertainty": unc,
        "uncertainty_level": "1 sigma",
        "held": held,
        "at_limit": at_limit,
        "correlation": c.correlation,
        "error_before": c.error_before,
        "error_after": c.error_after,
        "error_reduction": c.error_reduction,
        "noise_units_before": c.noise_units_before,
        "noise_units_after": c.noise_units_after,
        "excess_removed": c.excess_removed,
        "lr_statistic": c.lr_statistic,
        "lr_critical": c.lr_critical,
        "significant": c.significant,
        "partial": c.partial,
        "windows": c.windows,
        "fitted_with_causes_kept": c.joint,
    })
}

/// `{"NAME": {"PARAM": {"value": v, "sigma": s}}}` of fitted causes (σ `null` where not
/// determined; held parameters and those at a limit say so).
pub fn fitted_json(causes: &[Candidate]) -> Value {
    let map: Map<String, Value> = causes
        .iter()
        .map(|c| {
            let params: Map<String, Value> = c
                .params
                .iter()
                .enumerate()
                .map(|(i, (k, v))| {
                    let sigma = c.uncertainty.get(i).copied().filter(|u| u.is_finite());
                    let mut p = json!({"value": v, "sigma": sigma});
                    if c.held.get(i).copied().unwrap_or(false) {
                        p["held"] = json!(true);
                    }
                    if c.at_limit.get(i).copied().unwrap_or(false) {
                        p["at_limit"] = json!(true);
                    }
                    (k.clone(), p)
                })
                .collect();
            (c.effect.clone(), Value::Object(params))
        })
        .collect();
    Value::Object(map)
}

/// The selection's steps as JSON: each rung's model (`effects`), its error, what it added
/// and dropped, and the joint values after it (`fitted`); with `rankings`, each step's
/// candidates too.
pub fn ladder_json(d: &Diagnosis, rankings: bool) -> Value {
    Value::Array(
        d.steps
            .iter()
            .map(|s| {
                let mut v = json!({
                    "effects": s.effects,
                    "error": s.error,
                    "noise_units": s.noise_units,
                    "added": s.added,
                    "dropped": s.dropped,
                    "alternatives": s.alternatives,
                    "fitted": fitted_json(&s.fitted),
                    "error_after": s.error_after,
                    "noise_units_after": s.noise_units_after,
                });
                if rankings {
                    v["ranking"] = s.ranking.iter().map(candidate_json).collect();
                }
                v
            })
            .collect(),
    )
}

/// A diagnosis as JSON: verdict (names joined by " + ", `none` or `unexplained`), the causes
/// found (`found`, with their joint values in `fitted` and full records in `causes`), errors,
/// the first step's ranking and the ladder.
pub fn diagnosis_json(d: &Diagnosis) -> Value {
    json!({
        "verdict": d.verdict.to_string(),
        "found": d.found.iter().map(|c| c.effect.clone()).collect::<Vec<_>>(),
        "fitted": fitted_json(&d.found),
        "causes": d.found.iter().map(candidate_json).collect::<Vec<_>>(),
        "base_error": d.base_error,
        "noise_floor": d.noise_floor,
        "noise_units": d.noise_units,
        "found_error": d.found_error,
        "found_noise_units": d.found_noise_units,
        "windows": d.windows.0,
        "windows_screened": d.windows.1,
        "ranking": d.ranking.iter().map(candidate_json).collect::<Vec<_>>(),
        "ladder": ladder_json(d, false),
        "evidence": d.evidence,
        "alternatives": d.alternatives,
        "reference": d.reference.as_ref().map(reference_json),
        "error_floor": d.error_floor.as_ref().map(error_floor_json),
        "turbulence": d.turbulence.as_ref().map(turbulence_json),
        "aircraft_scores": d.aircraft_scores.iter().take(10).map(|s| json!({
            "key": s.key.name, "term": s.key.term, "reduction_chi2": s.reduction,
        })).collect::<Vec<_>>(),
    })
}

/// The filter-error method's account: the gusts (σ and scale lengths, m/s and m, north,
/// east, down), the test against calm air, and the numbers refitted through the filter.
pub fn turbulence_json(t: &crate::diagnose::turbulence::TurbulenceFinding) -> Value {
    let g = &t.gusts;
    json!({
        "significant": t.significant(),
        "reference_sigma_mps": t.reference_sigma_mps.map(|r| r.0),
        "forced": t.forced,
        "aircraft_searched": t.aircraft_searched,
        "sigma_mps": g.sigma_mps,
        "sigma_se_mps": g.sigma_se_mps,
        "rotary_radps2": g.rotary_radps2,
        "rotary_se_radps2": g.rotary_se_radps2,
        "length_m": g.length_m,
        "length_se_m": g.length_se_m,
        "likelihood_ratio": g.likelihood_ratio,
        "gust_likelihood_ratio": g.gust_likelihood_ratio,
        "output_error_noise_units": g.calm.noise_units,
        "innovations_normalised": g.gusty.normalised,
        "refits": t.refits.iter().map(|r| json!({
            "cause": r.cause,
            "param": r.param,
            "value": r.value,
            "sigma": r.sigma,
            "output_error": (!r.added).then_some(r.output_error),
            "added": r.added,
        })).collect::<Vec<_>>(),
    })
}

/// A diagnosis's reference flights: their floor, and each cause's parameters on the test
/// flight against them.
fn reference_json(r: &ReferenceVerdict) -> Value {
    json!({
        "flights": r.names,
        "noise_units": r.floor.noise_units,
        "model_error": noise_json(&r.floor.model_error),
        "measured_noise": noise_json(&r.measured_noise),
        "z_critical": r.z_critical,
        "shared": r.shared,
        "changes": r.params.iter().map(|p| json!({
            "cause": p.cause,
            "param": p.param,
            "test": {"value": p.test.0, "sigma": p.test.1},
            "reference": {"value": p.reference.0, "sigma": p.reference.1},
            "percent": p.percent().map(|(v, s)| json!({"value": v, "sigma": s})),
            "z": p.z,
            "changed": p.z > r.z_critical,
        })).collect::<Vec<_>>(),
    })
}

// ------------------------------------------------------------------------------------------
// Text
// ------------------------------------------------------------------------------------------

/// The measured noise in one line.
pub fn noise_text(n: &NoiseEstimate) -> String {
    let mut parts = vec![format!("position {} m", fmt_number(n.pos_m))];
    if n.vel_mps > 0.0 {
        parts.push(format!("velocity {} m/s", fmt_number(n.vel_mps)));
    }
    if n.att_rad > 0.0 {
        parts.push(format!("attitude {}°", fmt_number(n.att_rad.to_degrees())));
    }
    if n.rate_radps > 0.0 {
        parts.push(format!(
            "rates {}°/s",
            fmt_number(n.rate_radps.to_degrees())
        ));
    }
    if n.airspeed_mps > 0.0 {
        parts.push(format!("airspeed {} m/s", fmt_number(n.airspeed_mps)));
    }
    if n.accel_mps2 > 0.0 {
        parts.push(format!("accelerometer {} m/s²", fmt_number(n.accel_mps2)));
    }
    format!("measurement noise (1σ per axis): {}", parts.join(", "))
}

/// The per-axis errors as a table: signed mean (bias) and RMS.
pub fn axes_text(before: &Comparison, after: Option<&Comparison>) -> String {
    let mut t = if after.is_some() {
        Table::new(["axis", "mean", "RMS", "→ mean", "→ RMS", "unit"])
    } else {
        Table::new(["axis", "mean", "RMS", "unit"])
    };
    for a in &before.axes {
        let mut row = vec![
            format!("{} {}", a.channel, a.axis),
            signed(a.mean, 3),
            fixed(a.rms, 3),
        ];
        if let Some(after) = after {
            match after
                .axes
                .iter()
                .find(|b| b.channel == a.channel && b.axis == a.axis)
            {
                Some(b) => row.extend([signed(b.mean, 3), fixed(b.rms, 3)]),
                None => row.extend(["—".to_string(), "—".to_string()]),
            }
        }
        row.push(a.unit.to_string());
        t.row(row);
    }
    t.render(2)
}

/// "12%", "worse" or "—": the share of the misfit above the noise a candidate removed (in
/// noise units, [`Candidate::excess_removed`]); the same quantity as the row's "× noise"
/// before and after.
fn removed_cell(c: &Candidate) -> String {
    if c.noise_units_after > c.noise_units_before {
        "worse".into()
    } else {
        format!("{}%", fixed(100.0 * c.excess_removed.clamp(0.0, 1.0), 0))
    }
}

/// A ranking of candidates as a table, misfits in units of the `unit` (noise or floor).
fn ranking_table(ranking: &[Candidate], unit: &str) -> String {
    let mut t = Table::new([
        "candidate",
        if unit == "floor" {
            "× floor"
        } else {
            "× noise"
        },
        "removed",
        "significant",
        "fitted parameters (±1σ)",
    ]);
    for c in ranking {
        t.row([
            if c.joint {
                format!("{} (with the causes kept)", c.effect)
            } else {
                c.effect.clone()
            },
            fixed(c.noise_units_after, 2),
            removed_cell(c),
            if c.any_at_limit() {
                "at limit".into()
            } else if c.partial {
                "partial".into()
            } else if c.significant {
                "yes".into()
            } else {
                "no".into()
            },
            fmt_params(c),
        ]);
    }
    t.render(2)
}

/// The causes of a joint fit as a table: values ±1σ, and each one's test given the others.
fn causes_table(causes: &[Candidate]) -> String {
    let mut t = Table::new([
        "cause",
        "LR given the others",
        "needs",
        "fitted together (±1σ)",
    ]);
    for c in causes {
        t.row([
            c.effect.clone(),
            fixed(c.lr_statistic, 1),
            format!("> {}", fixed(c.lr_critical, 1)),
            fmt_params(c),
        ]);
    }
    t.render(2)
}

/// What to do next after a diagnosis that leaves the flight unexplained (empty otherwise,
/// or where `discover`'s terms were already tried): `discover` estimates the force and moment
/// the model lacks.
pub fn next_step_text(d: &Diagnosis, vehicle: VehicleKind, flight: &str, tried: bool) -> String {
    if d.verdict != Verdict::Unexplained || tried {
        return String::new();
    }
    let what = match vehicle {
        VehicleKind::FixedWing => "the force and moment",
        VehicleKind::PointMass => "the force (along and across its path)",
    };
    format!(
        "  next: `wireflight discover --flight {flight}` estimates {what} the model lacks and \
         proposes terms; `diagnose --discover` tries them as candidates\n"
    )
}

/// The ranking table and verdict of a diagnosis, as text.
pub fn diagnosis_text(d: &Diagnosis) -> String {
    let mut out = String::new();
    if let Some(r) = &d.reference {
        out.push_str(&reference_floor_text(&r.names, &r.floor));
    }
    if let Some(f) = &d.error_floor {
        out.push_str(&error_floor_text(f));
    }
    let unit = floor_word(d);
    let _ = writeln!(
        out,
        "  error {} ({} {}; {} × the {unit}), {}{}",
        fixed(d.base_error, 3),
        if unit == "floor" {
            "floor"
        } else {
            "noise floor"
        },
        fixed(d.noise_floor, 3),
        fixed(d.noise_units, 2),
        count(d.windows.0, "window"),
        if d.windows.1 < d.windows.0 {
            format!(", candidates screened on {}", d.windows.1)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        out,
        "  each candidate alone (\"removed\": of the misfit above the {unit}):"
    );
    out.push_str(&ranking_table(&d.ranking, unit));
    if d.found.len() > 1 {
        out.push_str("  the causes kept, fitted together:\n");
        out.push_str(&causes_table(&d.found));
    }
    if let Some(r) = &d.reference {
        out.push_str(&reference_changes_text(r));
    }
    if let Some(t) = &d.turbulence {
        out.push_str(&turbulence_text(t));
    }
    let _ = writeln!(out, "  verdict: {}", verdict_text(d));
    if !d.alternatives.is_empty() {
        let _ = writeln!(
            out,
            "  as good an explanation: {} — these data cannot tell them apart; a flight that \
             varies what they differ in would",
            d.alternatives.join(", ")
        );
    }
    out.push_str(&step_alternatives_text(d));
    for e in &d.evidence {
        let _ = writeln!(out, "  evidence: {e}");
    }
    if let Some(w) = d.winner() {
        let corr = correlations_text(w);
        if !corr.is_empty() {
            let _ = writeln!(out, "  correlations of the fitted parameters: {corr}");
        }
    }
    if d.windows.1 < d.windows.0 {
        let _ = writeln!(
            out,
            "  (candidates were fitted on {} of the {} windows; the causes found again on all)",
            d.windows.1, d.windows.0
        );
    }
    out
}

/// For a verdict of several causes, the candidates each step could have added as well.
fn step_alternatives_text(d: &Diagnosis) -> String {
    let mut out = String::new();
    if d.found.len() < 2 {
        return out;
    }
    // Only for the causes the verdict keeps: one added and dropped again has no
    // alternatives worth naming.
    for s in d.steps.iter().filter(|s| {
        s.added
            .as_ref()
            .is_some_and(|a| d.found.iter().any(|c| &c.effect == a))
    }) {
        if let (Some(added), false) = (&s.added, s.alternatives.is_empty()) {
            let _ = writeln!(
                out,
                "  as good an explanation as `{added}`: {} — these data cannot tell them apart",
                s.alternatives.join(", ")
            );
        }
    }
    out
}

/// "baseline" or "+ a + b": a step's model.
fn step_model(effects: &[String]) -> String {
    if effects.is_empty() {
        "baseline".into()
    } else {
        format!("+ {}", effects.join(" + "))
    }
}

/// How the selection went, step by step: each step's candidates, what it added and
/// dropped, the joint values after it; then the ladder of errors.
pub fn steps_text(d: &Diagnosis) -> String {
    let mut out = String::new();
    for (i, s) in d.steps.iter().enumerate() {
        let _ = writeln!(
            out,
            "step {}: model {} — error {} ({} × the noise)",
            i + 1,
            step_model(&s.effects),
            fixed(s.error, 3),
            fixed(s.noise_units, 2)
        );
        out.push_str(&ranking_table(&s.ranking, floor_word(d)));
        match &s.added {
            Some(added) => {
                let _ = write!(out, "  added {added}");
                if !s.dropped.is_empty() {
                    let _ = write!(
                        out,
                        "; dropped {} (given the others, the data no longer need it)",
                        s.dropped.join(", ")
                    );
                }
                let _ = writeln!(
                    out,
                    "; refitted together: error {} ({} × the noise)",
                    fixed(s.error_after, 3),
                    fixed(s.noise_units_after, 2)
                );
                out.push_str(&causes_table(&s.fitted));
            }
            None => {
                let _ = writeln!(out, "  no candidate is significant: the selection stops");
            }
        }
        out.push('\n');
    }
    out.push_str("ladder (error as causes are added, fitted together):\n");
    let mut t = Table::new(["model", "error", "× noise"]);
    for s in &d.steps {
        t.row([
            step_model(&s.effects),
            fixed(s.error, 3),
            fixed(s.noise_units, 2),
        ]);
    }
    out.push_str(&t.render(2));
    if d.windows.1 < d.windows.0 {
        let _ = writeln!(
            out,
            "  (steps on {} of the {} windows; on all of them the causes found leave {} ({} × \
             the noise))",
            d.windows.1,
            d.windows.0,
            fixed(d.found_error, 3),
            fixed(d.found_noise_units, 2)
        );
    }
    let _ = writeln!(out, "verdict: {}", verdict_text(d));
    if !d.alternatives.is_empty() {
        let _ = writeln!(
            out,
            "as good an explanation: {} — these data cannot tell them apart",
            d.alternatives.join(", ")
        );
    }
    out.push_str(&step_alternatives_text(d));
    out
}

/// "a/b +0.12, a/c −0.40": the correlations of a candidate's fitted parameters, or "" for
/// fewer than two.
pub fn correlations_text(c: &Candidate) -> String {
    let names: Vec<&str> = c
        .params
        .iter()
        .zip(&c.held)
        .filter(|(_, h)| !**h)
        .map(|((k, _), _)| k.as_str())
        .collect();
    let n = names.len();
    if n < 2 || c.correlation.len() != n * n {
        return String::new();
    }
    let mut parts = Vec::new();
    for i in 0..n {
        for k in i + 1..n {
            parts.push(format!(
                "{}/{} {}",
                names[i],
                names[k],
                signed(c.correlation[i * n + k], 2)
            ));
        }
    }
    parts.join(", ")
}

/// "`wind` is missing (north_mps=…)", "`aircraft:c_m_q` is wrong in the set (…)": one
/// cause with its fitted values.
fn cause_text(c: &Candidate) -> String {
    let params = fmt_params(c);
    let what = if c.effect.starts_with("aircraft:") {
        "is wrong in the set"
    } else {
        "is missing"
    };
    format!(
        "`{}` {what}{}",
        c.effect,
        if params.is_empty() {
            String::new()
        } else {
            format!(" ({params})")
        }
    )
}

/// What a diagnosis's misfit is in units of: `noise`, or against reference flights `floor`
/// (noise and the model's own error).
pub fn floor_word(d: &Diagnosis) -> &'static str {
    if d.reference.is_some() || d.error_floor.is_some() {
        "floor"
    } else {
        "noise"
    }
}

/// The reference flights and the model's own error they measured, two lines.
pub fn reference_floor_text(names: &[String], floor: &ModelFloor) -> String {
    let flights: Vec<String> = names
        .iter()
        .zip(&floor.noise_units)
        .map(|(n, u)| format!("{n} ({} × its noise)", fixed(*u, 2)))
        .collect();
    format!(
        "  judged against {}: {}\n  the model's own error on them (1σ per axis, added to the \
         noise): {}\n",
        count(names.len(), "reference flight"),
        flights.join(", "),
        noise_text(&floor.model_error).trim_start_matches("measurement noise (1σ per axis): ")
    )
}

/// The stated sensor errors and the floor they leave, two lines.
pub fn error_floor_text(f: &ErrorFloor) -> String {
    let (lo, hi) = f.draw_range();
    format!(
        "  judged against the floor `{}` sensor errors leave on a right model (1σ per axis, \
         added to the noise): {}\n  a right model reads {}–{} × this floor on {}; at the floor \
         up to {}\n",
        f.errors,
        noise_text(&f.model_error).trim_start_matches("measurement noise (1σ per axis): "),
        fixed(lo, 2),
        fixed(hi, 2),
        count(f.draws.len(), "draw"),
        fixed(f.at_floor, 2)
    )
}

/// The floor stated sensor errors leave, for JSON.
pub(crate) fn error_floor_json(f: &ErrorFloor) -> Value {
    json!({
        "errors": f.errors,
        "model_error": noise_json(&f.model_error),
        "draws_noise_units": f.draws,
        "at_floor": f.at_floor,
    })
}

/// Each cause's parameters on the test flight against the references, and the causes the
/// references share.
fn reference_changes_text(r: &ReferenceVerdict) -> String {
    let mut out = String::new();
    if !r.params.is_empty() {
        let _ = writeln!(
            out,
            "  each cause on the test flight and on the reference flights:"
        );
        let mut t = Table::new([
            "cause",
            "parameter",
            "test (±1σ)",
            "references (±1σ)",
            "change",
            "σ apart",
        ]);
        for p in &r.params {
            let change = match p.percent() {
                Some((v, s)) => format!("{}% ± {}%", signed(v, 1), fixed(s, 1)),
                None => fmt_number(p.test.0 - p.reference.0),
            };
            let apart = format!(
                "{} {} {}",
                fixed(p.z, 1),
                if p.z > r.z_critical { ">" } else { "≤" },
                fixed(r.z_critical, 1)
            );
            t.row([
                p.cause.clone(),
                p.param.clone(),
                format!("{}±{}", fmt_number(p.test.0), fmt_number(p.test.1)),
                format!(
                    "{}±{}",
                    fmt_number(p.reference.0),
                    fmt_number(p.reference.1)
                ),
                change,
                apart,
            ]);
        }
        out.push_str(&t.render(2));
    }
    if !r.shared.is_empty() {
        let names: Vec<String> = r.shared.iter().map(|s| format!("`{s}`")).collect();
        let _ = writeln!(
            out,
            "  {} the reference flights as well: the model's own error, not a change",
            if names.len() == 1 {
                format!("{} fits", names[0])
            } else {
                format!("{} fit", names.join(", "))
            }
        );
    }
    out
}

/// A cause as a change from the reference flights: its parameters, test vs references.
fn change_text(c: &Candidate, r: &ReferenceVerdict) -> String {
    let parts: Vec<String> = r
        .params
        .iter()
        .filter(|p| p.cause == c.effect && p.z > r.z_critical)
        .map(|p| {
            let change = match p.percent() {
                Some((v, s)) => format!("{}% ± {}%", signed(v, 1), fixed(s, 1)),
                None => format!(
                    "{} ± {}",
                    fmt_number(p.test.0 - p.reference.0),
                    fmt_number(p.test.1.hypot(p.reference.1))
                ),
            };
            format!(
                "{} {} vs {} ({change})",
                p.param,
                fmt_number(p.test.0),
                fmt_number(p.reference.0)
            )
        })
        .collect();
    format!(
        "`{}` differs from the reference flights: {}",
        c.effect,
        parts.join(", ")
    )
}

/// The verdict in a sentence.
pub fn verdict_text(d: &Diagnosis) -> String {
    let unit = floor_word(d);
    let fall = format!(
        "{} → {} ({} × the {unit})",
        fixed(d.base_error, 3),
        fixed(d.found_error, 3),
        fixed(d.found_noise_units, 2)
    );
    match (&d.verdict, &d.reference) {
        (Verdict::Found(_), Some(r)) => {
            let parts: Vec<String> = d.found.iter().map(|c| change_text(c, r)).collect();
            format!(
                "{}; with {} the error falls {fall}",
                parts.join("; "),
                if parts.len() == 1 {
                    "it"
                } else {
                    "them, fitted together,"
                }
            )
        }
        (Verdict::None, Some(_)) => format!(
            "none — the error is at the reference flights' floor ({} × it): nothing differs \
             from them that these data can show",
            fixed(d.noise_units, 2)
        ),
        _ => verdict_against_noise(d, &fall),
    }
}

/// [`verdict_text`] of a diagnosis against the noise (or an unexplained one against
/// references).
fn verdict_against_noise(d: &Diagnosis, fall: &str) -> String {
    let unit = floor_word(d);
    match &d.verdict {
        Verdict::Found(_) if d.found.len() == 1 => {
            format!(
                "{}; with it the error falls {fall}",
                cause_text(&d.found[0])
            )
        }
        Verdict::Found(_) => {
            let parts: Vec<String> = d.found.iter().map(cause_text).collect();
            format!(
                "{} causes at once, fitted together: {}; with them the error falls {fall}",
                d.found.len(),
                parts.join("; ")
            )
        }
        Verdict::None if d.error_floor.is_some() => format!(
            "none — the error is at the floor the stated sensor errors leave ({} × it): \
             nothing is missing that these data can show",
            fixed(d.noise_units, 2)
        ),
        Verdict::None => format!(
            "none — the error is at the noise floor ({} × the noise): nothing is missing that \
             these data can show",
            fixed(d.noise_units, 2)
        ),
        Verdict::Unexplained if !d.found.is_empty() => {
            let names: Vec<String> = d.found.iter().map(|c| format!("`{}`", c.effect)).collect();
            // Most of what can be removed is, and much is left: what a model that is never
            // exact leaves, which reference flights would measure.
            let removed = (d.noise_units - d.found_noise_units) / (d.noise_units - 1.0).max(1e-9);
            let floor_hint = if d.reference.is_none() && removed >= 0.5 && d.found_noise_units > 1.5
            {
                "; the model's own error is probably the rest: give reference flights \
                 (--reference) to test a change against them"
            } else {
                ""
            };
            format!(
                "unexplained — with {}{} the error falls {fall}, still above the {unit}, and no \
                 further candidate is significant: part of the answer{floor_hint}",
                names.join(" + "),
                if names.len() > 1 {
                    " (fitted together)"
                } else {
                    ""
                }
            )
        }
        Verdict::Unexplained => format!(
            "unexplained — the error stays {} × the {unit} and no candidate is significant",
            fixed(d.noise_units, 2)
        ),
        Verdict::Turbulence(names) => {
            let gusts = d
                .turbulence
                .as_ref()
                .map(|t| gusts_text(&t.gusts))
                .unwrap_or_default();
            let searched = d.turbulence.as_ref().is_some_and(|t| t.aircraft_searched);
            if names.is_empty() && searched {
                format!("turbulence — {gusts}; no deterministic cause besides")
            } else if names.is_empty() && d.error_floor.is_some() {
                format!(
                    "turbulence — {gusts}; no cause named, and none ruled out: the filter weighs \
                     the stated sensor errors as white noise, which overstates what a number \
                     explains, so its numbers were not searched (docs/turbulence.md)"
                )
            } else if names.is_empty() {
                format!(
                    "turbulence — {gusts}; no cause named, and none ruled out: against calm \
                     reference flights the filter moves an unchanged aircraft's numbers too, so \
                     its numbers were not searched (docs/turbulence.md)"
                )
            } else {
                format!(
                    "turbulence + {} — {gusts}; the causes' numbers fitted through the filter",
                    names.join(" + ")
                )
            }
        }
    }
}

/// The gust intensities in words: `gusts σ 0.83 ± 0.03 north, … m/s`.
pub fn gusts_text(g: &crate::filter_error::flight::GustEstimate) -> String {
    let axes = ["north", "east", "down"];
    format!(
        "gusts σ {} m/s",
        per_axis(&g.sigma_mps, &g.sigma_se_mps, axes)
    )
}

/// Three values with their ± and their axes' names: `0.83 ± 0.03 north, …`.
fn per_axis(values: &[f64; 3], se: &[f64; 3], axes: [&str; 3]) -> String {
    (0..3)
        .map(|k| format!("{} ± {} {}", fixed(values[k], 2), fixed(se[k], 2), axes[k]))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The filter's innovations by channel, in units of the noise (position, velocity, attitude,
/// rates, airspeed, accelerometer: those measured): `position 1.02, velocity 0.98, … × the
/// noise`.
pub fn innovations_text(pass: &crate::filter_error::flight::Pass) -> String {
    let r = &pass.rows_noise_units;
    let channel = |rows: std::ops::Range<usize>| {
        let measured: Vec<f64> = r[rows].iter().copied().filter(|v| *v > 0.0).collect();
        (!measured.is_empty())
            .then(|| (measured.iter().map(|v| v * v).sum::<f64>() / measured.len() as f64).sqrt())
    };
    let parts: Vec<String> = [
        ("position", 0..3),
        ("velocity", 3..6),
        ("attitude", 6..9),
        ("rates", 9..12),
        ("airspeed", 12..13),
        ("accelerometer", 13..16),
    ]
    .into_iter()
    .filter_map(|(name, rows)| channel(rows).map(|v| format!("{name} {}", fixed(v, 2))))
    .collect();
    format!("{} × the noise", parts.join(", "))
}

/// The filter-error method's account of a flight: the gusts, their scale lengths, the test
/// against calm air, and the numbers refitted through the filter.
pub fn turbulence_text(t: &crate::diagnose::turbulence::TurbulenceFinding) -> String {
    use crate::filter_error::flight;
    let g = &t.gusts;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "  filter-error method{}: {}",
        if t.forced { " (forced)" } else { "" },
        gusts_text(g)
    );
    let lengths: Vec<String> = [(0, "horizontal"), (2, "vertical")]
        .iter()
        .map(|&(k, name)| match g.length_se_m[k] {
            Some(se) => format!("{name} {} ± {} m", fixed(g.length_m[k], 0), fixed(se, 0)),
            None => format!(
                "{name} not determined ({} m assumed)",
                fixed(g.length_m[k], 0)
            ),
        })
        .collect();
    // Where a length is assumed, the data fix the gusts' power at the frequencies the flight
    // shows (∝ σ²/L), not σ alone: a σ holds for its length (docs/turbulence.md).
    let assumed = if g.length_se_m.iter().any(Option::is_none) {
        "; a σ holds for its axis's assumed length and scales about as √L"
    } else {
        ""
    };
    let _ = writeln!(out, "    scale lengths: {}{assumed}", lengths.join("; "));
    let _ = writeln!(
        out,
        "    rotary disturbance σ {} rad/s²",
        per_axis(&g.rotary_radps2, &g.rotary_se_radps2, ["x", "y", "z"])
    );
    if let Some((floor, se)) = &t.reference_sigma_mps {
        let parts: Vec<String> = (0..3)
            .map(|k| format!("{} ± {}", fixed(floor[k], 2), fixed(se[k], 2)))
            .collect();
        let _ = writeln!(
            out,
            "    on the reference flights (calm: the model's own error) the filter finds gusts σ \
             {} m/s; turbulence must exceed them",
            parts.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "    likelihood ratio against calm air {} (significant above {}), of the gust \
         velocities alone {} (above {}), a gust σ of at least {} m/s, and the filter's \
         innovations {} × their expected spread (at most {}): {}; output error leaves {} × \
         the noise",
        fixed(g.likelihood_ratio, 1),
        fixed(flight::TURBULENCE_LR_BOUND, 2),
        fixed(g.gust_likelihood_ratio, 1),
        fixed(flight::GUST_LR_BOUND, 2),
        fixed(flight::MIN_TURBULENCE_MPS, 2),
        fixed(g.gusty.normalised, 2),
        fixed(flight::MAX_INNOVATION_SPREAD, 1),
        if t.significant() {
            "turbulence"
        } else if g.gusty.normalised > flight::MAX_INNOVATION_SPREAD {
            "more than gusts are wrong"
        } else {
            "calm"
        },
        fixed(g.calm.noise_units, 2),
    );
    if !t.refits.is_empty() {
        out.push_str(
            "    numbers fitted through the filter (output error's in brackets; \"—\": found by \
             the filter's own search):\n",
        );
        let mut table = Table::new(["cause", "number", "value", "±1σ", "output error"]);
        for r in &t.refits {
            table.row([
                r.cause.clone(),
                r.param.clone(),
                format!("{:.5}", r.value),
                format!("{:.5}", r.sigma),
                if r.added {
                    "—".to_string()
                } else {
                    format!("({:.5})", r.output_error)
                },
            ]);
        }
        out.push_str(&table.render(4));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_put_numbers_right_and_words_left() {
        let mut t = Table::new(["candidate", "error", "significant", "r"]);
        t.row(["wind", "0.123", "yes", "+0.50"]);
        t.row(["ground_effect", "12.5", "no", "n/a"]);
        assert_eq!(
            t.render(2),
            "  candidate      error  significant      r\n\
             \x20 wind           0.123  yes          +0.50\n\
             \x20 ground_effect   12.5  no             n/a\n"
        );
        assert_eq!(fixed(-0.0004, 2), "0.00");
        assert_eq!(signed(-0.0004, 1), "+0.0");
        assert_eq!(count(1, "window"), "1 window");
        assert_eq!(count(3, "window"), "3 windows");
    }
}
