//! `wireflight identify`: many numbers of the aircraft's parameter set fitted together over
//! several flights, checked on held-out ones, written as a parameter-set TOML.

use anyhow::{bail, Context};
use serde_json::json;

use crate::analysis::compare::{compare, Prepared};
use crate::analysis::diagnose::DiagnoseConfig;
use crate::analysis::identify::{free_keys, identify, Identification, IdentifyConfig};
use crate::analysis::report::{model_label, Table};
use crate::app::cli::IdentifyArgs;
use crate::app::workbench::add_fitted_on;
use crate::data::FlightData;
use crate::data::VehicleKind;
use crate::flight::model::{Model, Vehicle};
use crate::flight::numeric::format::{fixed, fmt_number, signed};
use crate::flight::params::keys;

/// A held-out flight's error before and after, in noise units.
struct Validation {
    path: std::path::PathBuf,
    before: f64,
    after: f64,
}

/// Run `wireflight identify`.
///
/// # Errors
/// Bad data, model or keys; a point mass; a flight too short for a window.
pub fn run(args: &IdentifyArgs) -> anyhow::Result<()> {
    // Every file through the one reader of the commands (CSV, ULog, column maps), as compare.
    let flights: Vec<FlightData> = args
        .flight
        .iter()
        .map(|p| crate::app::data::load_flight(p, &args.data))
        .collect::<anyhow::Result<_>>()?;
    let first = &args.flight[0];
    let mut base = args.model.choice().build(first, &flights[0])?;
    if !matches!(base.vehicle, Vehicle::FixedWing(_)) {
        bail!("identify fits an aircraft's parameter set: the model is a point mass");
    }
    for (path, data) in args.flight.iter().zip(&flights) {
        same_vehicle(path, data, first, "--flight")?;
    }
    let cfg = IdentifyConfig {
        compare: args.windows.config(base.vehicle.kind()),
        prior: args.prior,
        equation_error: !args.no_equation_error,
        ..IdentifyConfig::default()
    };
    if !args.model.add.is_empty() {
        let dcfg = DiagnoseConfig {
            compare: cfg.compare,
            ..DiagnoseConfig::default()
        };
        let prep = Prepared::new(&flights[0], cfg.compare);
        add_fitted_on(
            &mut base,
            &prep,
            &args.model.add_specs()?,
            &dcfg,
            &args.flight[0],
        )?;
    }
    for (path, data) in args.flight.iter().zip(&flights) {
        args.windows.check_fits(path, data, &cfg.compare)?;
    }
    let validating: Vec<FlightData> = args
        .validate
        .iter()
        .map(|p| {
            let d = crate::app::data::load_flight(p, &args.data)?;
            same_vehicle(p, &d, first, "--validate")?;
            args.windows.check_fits(p, &d, &cfg.compare)?;
            Ok(d)
        })
        .collect::<anyhow::Result<_>>()?;
    let free = free_keys(&args.free)?;
    let mut id = identify(&base, &flights, &free, &cfg)?;
    let turbulent = crate::analysis::identify::turbulence::through_turbulence(
        &flights,
        &mut id,
        &cfg,
        args.method.into(),
    )
    .map_err(|e| anyhow::anyhow!("--method filter-error: {e}"))?;
    let validations: Vec<Validation> = args
        .validate
        .iter()
        .zip(&validating)
        .map(|(p, d)| {
            let before = compare(&base, d, cfg.compare).noise_units();
            let after = compare(&id.model, d, cfg.compare).noise_units();
            Ok(Validation {
                path: p.clone(),
                before,
                after,
            })
        })
        .collect::<anyhow::Result<_>>()?;
    if let Some(out) = &args.out {
        let Vehicle::FixedWing(p) = &id.model.vehicle else {
            unreachable!("checked above: a fixed wing");
        };
        let names: Vec<String> = args
            .flight
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        let comment = format!(
            "Identified by `wireflight identify` from {} (numbers fitted: {}; the others as in the \
             starting set).",
            names.join(", "),
            id.estimates
                .iter()
                .map(|e| e.key.name)
                .collect::<Vec<_>>()
                .join(", ")
        );
        crate::fsio::write_atomic(out, keys::to_toml(p, &comment).as_bytes())
            .with_context(|| format!("writing {}", out.display()))?;
    }
    if args.json {
        let mut v = identification_json(&id, &validations);
        v["turbulence"] = turbulent.as_ref().map_or(serde_json::Value::Null, |t| {
            serde_json::json!({
                "forced": t.forced,
                "flights": t.gusts.iter().map(|g| serde_json::json!({
                    "significant": g.significant(),
                    "sigma_mps": g.sigma_mps,
                    "sigma_se_mps": g.sigma_se_mps,
                })).collect::<Vec<_>>(),
                "output_error": t.output_error,
            })
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    print!(
        "{}",
        identification_text(args, &base, &flights, &id, &validations)
    );
    if let Some(t) = &turbulent {
        print!("{}", turbulence_text(args, &id, t));
    }
    if let Some(out) = &args.out {
        println!("  wrote {}", crate::app::shown(out));
    }
    Ok(())
}

/// Refuse a flight that is not of the fixed-wing aircraft being identified (a point mass, or
/// data without the controls a fixed-wing model is flown by), naming it and the first flight.
fn same_vehicle(
    path: &std::path::Path,
    data: &FlightData,
    first: &std::path::Path,
    option: &str,
) -> anyhow::Result<()> {
    let name = crate::app::shown;
    if data.meta.vehicle == Some(VehicleKind::PointMass) || data.attitude.is_none() {
        bail!(
            "{option} {}: a point-mass flight, but {} is a fixed-wing one: identify fits one \
             aircraft's parameter set to flights of that aircraft",
            name(path),
            name(first)
        );
    }
    if data.controls.is_none() {
        bail!(
            "{option} {}: no control channels, which a fixed-wing model is flown by (as {} is)",
            name(path),
            name(first)
        );
    }
    Ok(())
}

fn identification_json(id: &Identification, validations: &[Validation]) -> serde_json::Value {
    json!({
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
        "validation": validations.iter().map(|v| json!({
            "file": v.path.display().to_string(),
            "noise_units_before": v.before,
            "noise_units_after": v.after,
        })).collect::<Vec<_>>(),
    })
}

fn identification_text(
    args: &IdentifyArgs,
    base: &Model,
    flights: &[FlightData],
    id: &Identification,
    validations: &[Validation],
) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let seconds: f64 = flights.iter().map(FlightData::duration).sum();
    let samples: usize = flights.iter().map(FlightData::len).sum();
    let _ = writeln!(
        out,
        "identify: {} flight{} ({seconds:.1} s, {samples} samples); model {}; {} numbers free, \
         prior ±{}% of the set",
        flights.len(),
        if flights.len() == 1 { "" } else { "s" },
        model_label(base),
        id.estimates.len(),
        fmt_prior_percent(args.prior)
    );
    let _ = writeln!(
        out,
        "  start of the output-error fit: {}",
        if id.started_from_equation_error {
            "the equation-error estimate (it fitted better than the set)"
        } else {
            "the set"
        }
    );
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
    out.push_str(&t.render(2));
    let confounded = id.confounded();
    if !confounded.is_empty() {
        let pairs: Vec<String> = confounded
            .iter()
            .map(|(i, k, c)| {
                format!(
                    "{}/{} {}",
                    id.estimates[*i].key.name,
                    id.estimates[*k].key.name,
                    signed(*c, 2)
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "  not separable by these flights (|correlation| > {}): {}",
            crate::analysis::identify::CONFOUNDED,
            pairs.join(", ")
        );
        let combos: Vec<String> = id
            .determined_combinations()
            .iter()
            .map(|c| {
                format!(
                    "{} {} {}·{} = {} ± {}",
                    id.estimates[c.first].key.name,
                    if c.coefficient < 0.0 { "−" } else { "+" },
                    fmt_number(c.coefficient.abs()),
                    id.estimates[c.second].key.name,
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
    }
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
            "  not determined by these flights (σ > {}× the prior's; the prior holds them): {}",
            crate::analysis::identify::IDENTIFIED,
            not.join(", ")
        );
    }
    let mut f = Table::new(["flight", "× noise before", "after"]);
    for ((p, b), a) in args.flight.iter().zip(&id.before).zip(&id.after) {
        f.row([
            crate::app::shown(p),
            fixed(b.noise_units(), 2),
            fixed(a.noise_units(), 2),
        ]);
    }
    for v in validations {
        f.row([
            format!("{} (held out)", crate::app::shown(&v.path)),
            fixed(v.before, 2),
            fixed(v.after, 2),
        ]);
    }
    out.push_str(&f.render(2));
    out
}

/// The prior's width in percent as given (`0.3` → `30`, `0.015` → `1.5`), not rounded to a
/// whole percent.
fn fmt_prior_percent(prior: f64) -> String {
    let p = format!("{:.4}", 100.0 * prior);
    p.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// What the filter-error method found and changed: each flight's gusts, and each number
/// against output error's value.
fn turbulence_text(
    args: &IdentifyArgs,
    id: &Identification,
    t: &crate::analysis::identify::turbulence::ThroughTurbulence,
) -> String {
    use std::fmt::Write as _;
    let mut out = format!(
        "  through turbulence (filter-error method{}): the values above are the filter's\n",
        if t.forced { ", forced" } else { "" }
    );
    for (path, g) in args.flight.iter().zip(&t.gusts) {
        let _ = writeln!(
            out,
            "    {}: {}{}",
            crate::app::shown(path),
            crate::analysis::report::gusts_text(g),
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
            crate::flight::numeric::format::fmt_number(e.value),
            crate::flight::numeric::format::fmt_number(e.sigma),
            crate::flight::numeric::format::fmt_number(*oe)
        );
    }
    out
}
