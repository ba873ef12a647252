//! An [`Identified`] as text and JSON: what `wireflight identify` prints.

use std::fmt::Write as _;

use serde_json::{json, Value};
use wireflight_data::format::{fixed, fmt_number, signed};

use super::{gusts_text, model_label, Table};
use crate::identify::turbulence::ThroughTurbulence;
use crate::identify::{Identification, Identified, CONFOUNDED, IDENTIFIED};

/// How the caller names the flights of an identification.
pub struct Flights<'a> {
    /// The flights fitted, as their files are shown, in the request's order.
    pub fitted: &'a [String],
    /// The held-out flights, as their files are shown, in the request's order.
    pub held_out: &'a [String],
    /// The samples of the flights fitted, together.
    pub samples: usize,
    /// The duration of the flights fitted, together, s.
    pub duration_s: f64,
}

/// The identification as JSON; `held_out` names the held-out flights' files.
pub fn identification_json(r: &Identified, held_out: &[String]) -> Value {
    let id = &r.identification;
    let mut v = json!({
        "estimates": id.estimates.iter().map(|e| json!({
            "key": e.key.name,
            "start": e.start,
            "equation_error": e.equation_error,
            "value": e.value,
            "sigma": e.sigma,
            "prior_sigma": e.prior_sigma,
            "change_percent": e.change_percent(),
            "identified": e.identified(),
        })).collect::<Vec<_>>(),
        "correlation": id.correlation,
        "confounded": id.confounded().iter().map(|(i, k, c)| json!({
            "keys": [id.estimates[*i].key.name, id.estimates[*k].key.name],
            "correlation": c,
        })).collect::<Vec<_>>(),
        "determined_combinations": id.determined_combinations().iter().map(|c| json!({
            "keys": [id.estimates[c.first].key.name, id.estimates[c.second].key.name],
            "coefficient": c.coefficient,
            "value": c.value,
            "sigma": c.sigma,
        })).collect::<Vec<_>>(),
        "held": id.held.iter().map(|(k, why)| json!({"key": k, "why": why})).collect::<Vec<_>>(),
        "started_from_equation_error": id.started_from_equation_error,
        "flights": id.before.iter().zip(&id.after).map(|(b, a)| json!({
            "noise_units_before": b.noise_units(),
            "noise_units_after": a.noise_units(),
            "total_before": b.total,
            "total_after": a.total,
        })).collect::<Vec<_>>(),
        "validation": held_out.iter().zip(&r.held_out).map(|(file, h)| json!({
            "file": file,
            "noise_units_before": h.before,
            "noise_units_after": h.after,
        })).collect::<Vec<_>>(),
    });
    v["turbulence"] = r.turbulence.as_ref().map_or(Value::Null, |t| {
        json!({
            "forced": t.forced,
            "flights": t.gusts.iter().map(|g| json!({
                "significant": g.significant(),
                "sigma_mps": g.sigma_mps,
                "sigma_se_mps": g.sigma_se_mps,
            })).collect::<Vec<_>>(),
            "output_error": t.output_error,
        })
    });
    v
}

/// The identification as text: the heading, the numbers with their σ, the pairs the flights
/// cannot separate and what they determine of them, the numbers held or not determined, each
/// flight's error before and after (the held-out ones too), and what the filter-error method
/// found where it ran.
pub fn identification_text(r: &Identified, flights: &Flights) -> String {
    let id = &r.identification;
    let mut out = heading(r, flights);
    out += &estimates_table(id);
    out += &confounded_text(id);
    out += &left_text(id);
    out += &errors_table(r, flights);
    if let Some(t) = &r.turbulence {
        out += &through_turbulence_text(id, t, flights);
    }
    out
}

/// What was fitted on what, and where the output-error fit started.
fn heading(r: &Identified, flights: &Flights) -> String {
    let id = &r.identification;
    let n = flights.fitted.len();
    format!(
        "identify: {n} flight{} ({:.1} s, {} samples); model {}; {} numbers free, prior ±{}% of \
         the set\n  start of the output-error fit: {}\n",
        if n == 1 { "" } else { "s" },
        flights.duration_s,
        flights.samples,
        model_label(&r.base),
        id.estimates.len(),
        prior_percent(r.config.prior),
        if id.started_from_equation_error {
            "the equation-error estimate (it fitted better than the set)"
        } else {
            "the set"
        }
    )
}

/// The prior's width in percent as given (`0.3` → `30`, `0.015` → `1.5`), not rounded to a
/// whole percent.
fn prior_percent(prior: f64) -> String {
    let p = format!("{:.4}", 100.0 * prior);
    p.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Each number: its value in the set, identified, its σ, the change and whether the flights
/// determine it.
fn estimates_table(id: &Identification) -> String {
    let mut t = Table::new([
        "parameter",
        "set",
        "identified",
        "±",
        "change",
        "determined",
    ]);
    for e in &id.estimates {
        t.row([
            e.key.name.to_string(),
            fmt_number(e.start),
            fmt_number(e.value),
            fmt_number(e.sigma),
            e.change_percent()
                .map_or("n/a".to_string(), |c| format!("{}%", signed(c, 1))),
            if e.identified() {
                "yes".to_string()
            } else {
                "no".to_string()
            },
        ]);
    }
    t.render(2)
}

/// The pairs the flights cannot separate, and what they determine of each.
fn confounded_text(id: &Identification) -> String {
    let confounded = id.confounded();
    if confounded.is_empty() {
        return String::new();
    }
    let name = |i: usize| id.estimates[i].key.name;
    let pairs: Vec<String> = confounded
        .iter()
        .map(|(i, k, c)| format!("{}/{} {}", name(*i), name(*k), signed(*c, 2)))
        .collect();
    let mut out = format!(
        "  not separable by these flights (|correlation| > {CONFOUNDED}): {}\n",
        pairs.join(", ")
    );
    let combos: Vec<String> = id
        .determined_combinations()
        .iter()
        .map(|c| {
            format!(
                "{} {} {}·{} = {} ± {}",
                name(c.first),
                if c.coefficient < 0.0 { "−" } else { "+" },
                fmt_number(c.coefficient.abs()),
                name(c.second),
                fmt_number(c.value),
                fmt_number(c.sigma)
            )
        })
        .collect();
    if !combos.is_empty() {
        let _ = writeln!(
            out,
            "  what they do determine of each pair: {}",
            combos.join(", ")
        );
    }
    out
}

/// The numbers left where they were: held out of the fit, or not determined by the flights.
fn left_text(id: &Identification) -> String {
    let mut out = String::new();
    for (key, why) in &id.held {
        let _ = writeln!(out, "  {key} {why}");
    }
    let not: Vec<&str> = id
        .estimates
        .iter()
        .filter(|e| !e.identified())
        .map(|e| e.key.name)
        .collect();
    if !not.is_empty() {
        let _ = writeln!(
            out,
            "  not determined by these flights (σ > {IDENTIFIED}× the prior's; the prior holds \
             them): {}",
            not.join(", ")
        );
    }
    out
}

/// Each flight's error before and after, in noise units, the held-out ones last.
fn errors_table(r: &Identified, flights: &Flights) -> String {
    let id = &r.identification;
    let mut f = Table::new(["flight", "× noise before", "after"]);
    for ((name, b), a) in flights.fitted.iter().zip(&id.before).zip(&id.after) {
        f.row([
            name.clone(),
            fixed(b.noise_units(), 2),
            fixed(a.noise_units(), 2),
        ]);
    }
    for (name, h) in flights.held_out.iter().zip(&r.held_out) {
        f.row([
            format!("{name} (held out)"),
            fixed(h.before, 2),
            fixed(h.after, 2),
        ]);
    }
    f.render(2)
}

/// What the filter-error method found and changed: each flight's gusts, and each number
/// against output error's value.
fn through_turbulence_text(
    id: &Identification,
    t: &ThroughTurbulence,
    flights: &Flights,
) -> String {
    let mut out = format!(
        "  through turbulence (filter-error method{}): the values above are the filter's\n",
        if t.forced { ", forced" } else { "" }
    );
    for (name, g) in flights.fitted.iter().zip(&t.gusts) {
        let _ = writeln!(
            out,
            "    {name}: {}{}",
            gusts_text(g),
            if g.significant() {
                ""
            } else {
                " (not significant)"
            }
        );
    }
    for (e, oe) in id.estimates.iter().zip(&t.output_error) {
        let _ = writeln!(
            out,
            "    {} {} ± {} (output error {})",
            e.key.name,
            fmt_number(e.value),
            fmt_number(e.sigma),
            fmt_number(*oe)
        );
    }
    out
}
