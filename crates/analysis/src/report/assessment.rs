//! An [`Assessment`] as text and JSON: what `wireflight compare` prints.

use serde_json::{json, Value};
use wireflight_data::format::{fixed, signed};

use super::{
    axes_text, candidate_json, comparison_json, conditions_json, count, error_floor_json,
    error_floor_text, fmt_opt, fmt_params, innovations_text, model_label, noise_json, noise_text,
    reference_floor_text, turbulence_json, turbulence_text, windows_json, Table,
};
use crate::assess::Assessment;
use crate::compare::Comparison;
use crate::conditions::explain_growth;

/// How the caller names what was assessed.
pub struct Names<'a> {
    /// The flight, as its file is shown.
    pub flight: &'a str,
    /// Its samples (rows, where its channels have their own rates).
    pub samples: usize,
    /// Whether its channels have their own rates: then `samples` counts rows, the times
    /// anything was sampled.
    pub own_rates: bool,
    /// Its duration, s.
    pub duration_s: f64,
    /// The added effects as one label, `+ wind + drag`.
    pub added: &'a str,
}

/// The assessment as JSON.
pub fn assessment_json(a: &Assessment, flight: &str) -> Value {
    let before = &a.before;
    let mut v = json!({
        "data": flight,
        "model": a.base.effect_names(),
        "error": comparison_json(&before.comparison),
        "noise_floor": a.floor,
        "noise": noise_json(&a.measured_noise),
        "reference": a.reference_floor.as_ref().map(|r| json!({
            "flights": r.names,
            "noise_units": r.floor.noise_units,
            "model_error": noise_json(&r.floor.model_error),
        })),
        "error_floor": a.error_floor.as_ref().map(error_floor_json),
        "windows": windows_json(&before.comparison),
        "conditions": conditions_json(&before.conditions),
        "growth_exponent": before.growth,
        "turbulence": a.turbulence.as_ref().map(|(t, _)| {
            let mut v = turbulence_json(t);
            v["innovations_noise_units"] = json!(t.gusts.gusty.rows_noise_units);
            v
        }),
    });
    if let Some(after) = &a.after {
        v["added"] = Value::Array(a.fitted.iter().map(candidate_json).collect());
        v["after"] = comparison_json(&after.comparison);
        v["after_windows"] = windows_json(&after.comparison);
        v["after_conditions"] = conditions_json(&after.conditions);
        v["after_growth_exponent"] = json!(after.growth);
    }
    v
}

/// The assessment as text: the error before and after, the floor, the fitted effects, the
/// turbulence, where the error lies, the worst windows, and what the error follows — or, at
/// the floor, what the score test says.
pub fn assessment_text(a: &Assessment, names: &Names) -> String {
    let mut out = error_table(a, names);
    out += &turbulence_section(a);
    out += "\nwhere (predicted − measured, over all windows):\n";
    out += &axes_text(
        &a.before.comparison,
        a.after.as_ref().map(|f| &f.comparison),
    );
    out += &worst_windows(a, names);
    if a.at_floor {
        out += &at_floor_text(a);
    } else {
        out += &follows_text(a, names);
    }
    out
}

/// The heading, the noise, the error per channel before and after, the floor and the
/// fitted effects.
fn error_table(a: &Assessment, names: &Names) -> String {
    let b = &a.before.comparison;
    let mut out = format!(
        "{}: {} {}, {:.1} s, {} of {} s; model: {}\n  {}\n",
        names.flight,
        names.samples,
        if names.own_rates { "rows" } else { "samples" },
        names.duration_s,
        count(b.windows.len(), "window"),
        a.config.window_s,
        model_label(&a.base),
        noise_text(&a.measured_noise)
    );
    if let Some(r) = &a.reference_floor {
        out += &reference_floor_text(&r.names, &r.floor);
    }
    if let Some(f) = &a.error_floor {
        out += &error_floor_text(f);
    }
    out += "\n";
    let after = a.after.as_ref().map(|f| &f.comparison);
    let mut t = match after {
        Some(_) => Table::new(["channel", "error", &format!("→ {}", names.added)]),
        None => Table::new(["channel", "error"]),
    };
    type Channel = fn(&Comparison) -> Option<f64>;
    let rows: [(&str, Channel, &str); 4] = [
        ("position", |c| Some(c.channels.position_m), "m"),
        ("velocity", |c| c.channels.velocity_mps, "m/s"),
        ("attitude", |c| c.channels.attitude_deg, "°"),
        ("rates", |c| c.channels.rate_dps, "°/s"),
    ];
    for (name, get, unit) in rows {
        let mut row = vec![name.to_string(), fmt_opt(get(b), unit)];
        if let Some(c) = after {
            row.push(fmt_opt(get(c), unit));
        }
        t.row(row);
    }
    let mut total = vec!["total".to_string(), fixed(b.total, 3)];
    let mut units = vec![format!("× {}", a.unit()), fixed(b.noise_units(), 2)];
    if let Some(c) = after {
        total.push(fixed(c.total, 3));
        units.push(fixed(c.noise_units(), 2));
    }
    t.row(total);
    t.row(units);
    out += &t.render(2);
    out += &if a.reference_floor.is_some() {
        format!(
            "  floor {} (the total the model leaves on these data when it errs as on the \
             reference flights)\n",
            fixed(a.floor, 3)
        )
    } else if a.error_floor.is_some() {
        format!(
            "  floor {} (the total a right model leaves on these data with the stated sensor \
             errors)\n",
            fixed(a.floor, 3)
        )
    } else {
        format!(
            "  noise floor {} (the total a right model leaves on these data)\n",
            fixed(a.floor, 3)
        )
    };
    for f in &a.fitted {
        let params = fmt_params(f);
        out += &if params.is_empty() {
            format!("  added {} (no parameters to fit)\n", f.effect)
        } else {
            format!("  fitted {}: {params}\n", f.effect)
        };
    }
    out
}

/// The filter-error method's account, where it ran.
fn turbulence_section(a: &Assessment) -> String {
    let Some((t, _)) = &a.turbulence else {
        return String::new();
    };
    let mut out = format!("\n{}", turbulence_text(t));
    out += &format!(
        "    the filter's innovations: {}\n",
        innovations_text(&t.gusts.gusty)
    );
    if t.significant() {
        out += "    output error's errors above include the gusts' response; the gusts are \
                estimated on the model as compared, so they include what it lacks: `wireflight \
                diagnose` fits the causes first\n";
    }
    out
}

/// A section title, naming the model with the added effects where there is one.
fn title(a: &Assessment, names: &Names, what: &str) -> String {
    match &a.after {
        Some(_) => format!("{what} (model {}):", names.added),
        None => format!("{what}:"),
    }
}

/// The three worst windows of the model as it ends up.
fn worst_windows(a: &Assessment, names: &Names) -> String {
    let mut out = format!("\n{}\n", title(a, names, "worst windows"));
    let unit_header = format!("× {}", a.unit());
    let mut t = Table::new(["window", "score", unit_header.as_str(), "dominated by"]);
    for w in a.last().comparison.worst_windows().iter().take(3) {
        t.row([
            format!("{}–{} s", fixed(w.t0, 1), fixed(w.t1, 1)),
            fixed(w.score, 3),
            fixed((w.chi2 / w.residuals.max(1) as f64).sqrt(), 2),
            w.errors.dominant().to_string(),
        ]);
    }
    out += &t.render(2);
    out
}

/// At the floor: whether the score test finds a number that could still explain a
/// significant part of what is left.
fn at_floor_text(a: &Assessment) -> String {
    let unit = a.unit();
    let units = fixed(a.last().comparison.noise_units(), 2);
    if a.promising.is_empty() {
        format!(
            "\nthe error is at the {unit} floor ({units} × the {unit}), and the score test finds \
             no number of the aircraft's set that could explain what is left; `wireflight \
             diagnose` also tries the catalogue's effects\n"
        )
    } else {
        let named: Vec<String> = a
            .promising
            .iter()
            .take(3)
            .map(|s| format!("{} ({})", s.key.name, s.key.term))
            .collect();
        format!(
            "\nthe error is {units} × the {unit}, near the floor, but the score test says {} \
             could still explain a significant part of it: run `wireflight diagnose` to fit \
             and test\n",
            named.join(", ")
        )
    }
}

/// Above the floor: the conditions the error follows and how it grows inside a window.
fn follows_text(a: &Assessment, names: &Names) -> String {
    let last = a.last();
    let mut out = format!("\n{}\n", title(a, names, "error correlates with"));
    let mut t = Table::new(["condition", "r", ""]);
    for c in last.conditions.iter().take(4) {
        t.row([
            format!("{} ({})", c.name, c.unit),
            c.correlation.map_or("n/a".to_string(), |r| signed(r, 2)),
            c.note.clone().unwrap_or_default(),
        ]);
    }
    out += &t.render(2);
    if last.comparison.windows.len() < 3 {
        out += "  (correlations need at least 3 windows)\n";
    }
    if let Some(k) = last.growth {
        out += &format!(
            "\nwithin a window, {} (exponent {})\n",
            explain_growth(k),
            fixed(k, 1)
        );
    }
    out
}
