//! Results as people and programs read them: the text tables and the JSON of comparisons and
//! diagnoses, one formatter for every command and the window. Pure: builds strings and JSON
//! values, writes nothing.

use serde_json::{json, Value};

use super::compare::{ChannelErrors, Comparison};
use super::diagnose::{Candidate, Diagnosis};
use crate::flight::model::Model;

/// The per-channel errors as JSON.
pub fn channels_json(c: &ChannelErrors) -> Value {
    json!({
        "position_m": c.position_m,
        "velocity_mps": c.velocity_mps,
        "attitude_deg": c.attitude_deg,
    })
}

/// `{"total", "channels"}` of a comparison.
pub fn comparison_json(c: &Comparison) -> Value {
    json!({
        "total": c.total,
        "channels": channels_json(&c.channels),
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
                })
            })
            .collect(),
    )
}

/// One tried effect: parameters, uncertainty, errors, significance.
pub fn candidate_json(c: &Candidate) -> Value {
    let params: serde_json::Map<String, Value> = c
        .params
        .iter()
        .map(|(k, v)| (k.clone(), json!(v)))
        .collect();
    let unc: serde_json::Map<String, Value> = c
        .params
        .iter()
        .zip(&c.uncertainty)
        .filter(|(_, u)| u.is_finite())
        .map(|((k, _), u)| (k.clone(), json!(u)))
        .collect();
    json!({
        "effect": c.effect,
        "params": params,
        "uncertainty": unc,
        "error_before": c.error_before,
        "error_after": c.error_after,
        "error_reduction": c.error_reduction,
        "excess_removed": c.excess_removed,
        "lr_statistic": c.lr_statistic,
        "significant": c.significant,
    })
}

/// A value with its unit, or a dash when the data lack the channel.
pub fn fmt_opt(v: Option<f64>, unit: &str) -> String {
    v.map(|x| format!("{x:.3} {unit}"))
        .unwrap_or_else(|| "—".into())
}

/// Four significant digits, in scientific notation when small (drag's k is ~1e-4) or large.
pub fn fmt_number(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-2 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

/// `k=v±σ ...` of a candidate.
pub fn fmt_params(c: &Candidate) -> String {
    c.params
        .iter()
        .zip(&c.uncertainty)
        .map(|((k, v), u)| {
            if u.is_finite() {
                format!("{k}={}±{}", fmt_number(*v), fmt_number(*u))
            } else {
                format!("{k}={}", fmt_number(*v))
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

/// The ranking table and verdict of a diagnosis, as text.
pub fn diagnosis_text(d: &Diagnosis) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "  baseline error {:.3}, noise floor {:.3}",
        d.base_error, d.noise_floor
    );
    let _ = writeln!(
        out,
        "  {:18} {:>9} → {:<9} {:>8} {:>8}  {}",
        "effect", "before", "after", "removed", "signif.", "fitted parameters"
    );
    for c in &d.ranking {
        let _ = writeln!(
            out,
            "  {:18} {:>9.3} → {:<9.3} {:>7.0}% {:>8}  {}",
            c.effect,
            c.error_before,
            c.error_after,
            100.0 * c.error_reduction,
            if c.significant { "yes" } else { "no" },
            fmt_params(c)
        );
    }
    let _ = match d.winner() {
        Some(w) => writeln!(
            out,
            "  verdict: `{}` is missing ({}); it removes {:.0}% of the error above the noise floor",
            w.effect,
            fmt_params(w),
            100.0 * w.excess_removed.min(1.0)
        ),
        None => writeln!(
            out,
            "  verdict: none — no effect explains more than fitting noise would"
        ),
    };
    out
}

/// A diagnosis as JSON: verdict, errors, ranking.
pub fn diagnosis_json(d: &Diagnosis) -> Value {
    json!({
        "verdict": d.verdict,
        "base_error": d.base_error,
        "noise_floor": d.noise_floor,
        "ranking": d.ranking.iter().map(candidate_json).collect::<Vec<_>>(),
    })
}
