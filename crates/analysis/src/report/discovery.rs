//! `discover`'s text and JSON.

use std::fmt::Write as _;

use serde_json::{json, Value};
use wireflight_data::format::fmt_number;

use crate::discover::Discovery;
use wireflight_flight::expr::Axis;

/// An axis's unit in a discovery: the force's or moment's, or on a point mass (mass 1) m/s².
fn unit(d: &Discovery, axis: Axis) -> &'static str {
    if d.point_mass {
        "m/s²"
    } else {
        axis.unit()
    }
}

/// The table of terms, best first, and each axis's missing force or moment.
pub fn discovery_text(d: &Discovery) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "  what the model lacks at the measured states ({} samples; {} candidate terms per axis, \
         a term passes at likelihood ratio {:.1} on the effective samples):",
        d.samples, d.candidates, d.threshold
    );
    if d.point_mass {
        let axes = if d.wind_axes {
            "the wind axes of the body the flight recorded: X along the air velocity, Z normal \
             to it in the body's x–z plane (negative toward its top), Y its side"
        } else {
            "the flight path's: X along the air velocity, Y level to its right, Z downward \
             normal to it"
        };
        let _ = writeln!(s, "  point mass, per unit mass, on {axes}");
    }
    let _ = writeln!(
        s,
        "  axis  unit   RMS missing  after terms  effective samples"
    );
    for a in &d.axes {
        let _ = writeln!(
            s,
            "  {:4}  {:4}  {:>11}  {:>11}  {:>17.0}",
            a.axis.name(),
            unit(d, a.axis),
            fmt_number(a.rms),
            fmt_number(a.rms_after),
            a.effective_samples
        );
    }
    if d.terms.is_empty() {
        let _ = writeln!(
            s,
            "  no term is significant: nothing the library can say is missing"
        );
        return s;
    }
    match d.error_before {
        Some(e) => {
            let _ = writeln!(
                s,
                "  terms found, best first (the flight's error without them: {e:.2} × the noise):"
            );
        }
        None => {
            let _ = writeln!(s, "  terms found, best first:");
        }
    }
    for (i, t) in d.terms.iter().enumerate() {
        let _ = writeln!(s, "  {}. {}: {}", i + 1, t.axis.name(), t.reading);
        let _ = writeln!(
            s,
            "     {} = {} ± {} ({} per unit); removes {:.0}% of the axis's missing {} (RMS {} → {} {}), \
             likelihood ratio {:.1}, lower on {} of 5 held-out fifths",
            t.coefficient_name,
            fmt_number(t.coefficient),
            fmt_number(t.sigma),
            unit(d, t.axis),
            100.0 * (1.0 - (t.rms_after / t.rms_before).powi(2)),
            match (d.point_mass, t.axis.is_force()) {
                (true, _) => "acceleration",
                (false, true) => "force",
                (false, false) => "moment",
            },
            fmt_number(t.rms_before),
            fmt_number(t.rms_after),
            unit(d, t.axis),
            t.likelihood_ratio,
            t.folds_better
        );
        if let Some(e) = t.error_after {
            let which = if i == 0 {
                "it".to_string()
            } else {
                format!("terms 1–{}", i + 1)
            };
            let _ = writeln!(
                s,
                "     error with {which} added and fitted: {e:.2} × the noise"
            );
        }
        let _ = writeln!(s, "     add: --add '{}'", t.add);
    }
    s
}

/// The JSON of a discovery: `{"terms": [...], "axes": [...], ...}`, terms best first.
pub fn discovery_json(d: &Discovery) -> Value {
    json!({
        "terms": d.terms.iter().map(|t| json!({
            "axis": t.axis.name(),
            "regressors": t.regressors,
            "expression": t.expression,
            "coefficient_name": t.coefficient_name,
            "coefficient": t.coefficient,
            "sigma": t.sigma,
            "reading": t.reading,
            "rms_before": t.rms_before,
            "rms_after": t.rms_after,
            "likelihood_ratio": t.likelihood_ratio,
            "folds_better": t.folds_better,
            "error_after": t.error_after,
            "add": t.add,
        })).collect::<Vec<_>>(),
        "axes": d.axes.iter().map(|a| json!({
            "axis": a.axis.name(),
            "unit": unit(d, a.axis),
            "rms": a.rms,
            "mean": a.mean,
            "rms_after": a.rms_after,
            "effective_samples": a.effective_samples,
        })).collect::<Vec<_>>(),
        "samples": d.samples,
        "candidates": d.candidates,
        "threshold": d.threshold,
        "error_before": d.error_before,
        "point_mass": d.point_mass,
        "point_mass_axes": d.point_mass.then_some(if d.wind_axes { "wind" } else { "flight_path" }),
    })
}
