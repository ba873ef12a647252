//! `wireflight diagnose`: which physical effects the flight model is missing, with evidence.

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::{self, add_fitted, DiagnoseConfig};
use crate::analysis::report::{
    diagnosis_json, diagnosis_text, ladder_json, model_label, steps_text,
};
use crate::app::cli::DiagnoseArgs;

/// Run `wireflight diagnose`.
///
/// # Errors
/// Bad data or model.
pub fn run(args: &DiagnoseArgs) -> anyhow::Result<()> {
    if let Some(out) = &args.out {
        check_model_out(out)?;
    }
    if let Some(report) = &args.report {
        check_report(report)?;
    }
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let references = load_references(&args.reference, &args.flight, &data, &args.data)?;
    // A model also flown on the references must not read the test flight's record there.
    let mut base = if references.is_empty() {
        args.model.choice().build(&args.flight, &data)?
    } else {
        args.model.choice().build_unrecorded(&args.flight, &data)?
    };
    let cfg = DiagnoseConfig {
        compare: args.windows.config(base.vehicle.kind()),
        ..DiagnoseConfig::default()
    };
    args.windows.check_fits(&args.flight, &data, &cfg.compare)?;
    // A model file's `[[term]]` without values is a candidate, not part of the model.
    let declared = diagnose::take_declared_terms(&mut base);
    check_forces_finite(
        &base,
        &args.model.add_specs()?,
        &declared,
        &args.flight,
        &data,
    )?;
    if !args.model.add.is_empty() {
        let prep = Prepared::new(&data, cfg.compare);
        add_fitted_on(
            &mut base,
            &prep,
            &args.model.add_specs()?,
            &cfg,
            &args.flight,
        )?;
    }
    let mut declared = declared;
    if args.discover {
        declared.extend(discovered_terms(&base, &data, &args.flight, &declared)?);
    }
    let progress = crate::draw::progress::Progress::spinner(
        &format!("diagnosing {:.0} s of data", data.duration()),
        args.json,
    );
    let mut d = if references.is_empty() {
        diagnose::diagnose(&base, &data, &declared, &cfg)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?
    } else {
        let named: Vec<(&str, &crate::data::FlightData)> =
            references.iter().map(|(n, d)| (n.as_str(), d)).collect();
        diagnose::reference::diagnose_against(&base, &data, &named, &declared, &cfg)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?
    };
    // (Against reference flights the diagnosis's noise is their floor, the model's own
    // error included: the filter weighs its innovations by it as output error does.)
    let compare = cfg.compare;
    let named: Vec<(&str, &crate::data::FlightData)> =
        references.iter().map(|(n, d)| (n.as_str(), d)).collect();
    diagnose::turbulence::through_turbulence(
        &base,
        &mut d,
        &data,
        &named,
        &cfg,
        &compare,
        args.method.into(),
    )
    .map_err(|e| anyhow::anyhow!("{}: --method filter-error: {e}", args.flight.display()))?;
    drop(progress);
    if args.json {
        let mut v = diagnosis_json(&d);
        if args.iterate {
            // The ladder with every step's candidates.
            v["ladder"] = ladder_json(&d, true);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return keep(args, &data, &base, &d, &cfg);
    }
    println!(
        "{}: {} samples, {:.1} s; model {}\n  {}",
        crate::app::shown(&args.flight),
        data.len(),
        data.duration(),
        model_label(&base),
        crate::analysis::report::noise_text(
            d.reference
                .as_ref()
                .map_or(&d.base_noise, |r| &r.measured_noise)
        )
    );
    if args.iterate {
        print!("{}", steps_text(&d));
    } else {
        print!("{}", diagnosis_text(&d));
    }
    if d.verdict == diagnose::Verdict::Unexplained && !args.discover {
        let what = match base.vehicle.kind() {
            crate::data::VehicleKind::FixedWing => "the force and moment",
            crate::data::VehicleKind::PointMass => "the force (along and across its path)",
        };
        println!(
            "  next: `wireflight discover --flight {}` estimates {what} the model lacks and \
             proposes terms; `diagnose --discover` tries them as candidates",
            crate::app::shown(&args.flight)
        );
    }
    keep(args, &data, &base, &d, &cfg)
}

/// How many of `discover`'s terms `diagnose --discover` tries.
const DISCOVERED_CANDIDATES: usize = 5;

/// The best terms `discover` proposes for `data` against `model`, as candidate effects
/// (those not among `declared` already).
fn discovered_terms(
    model: &crate::flight::model::Model,
    data: &crate::data::FlightData,
    flight: &std::path::Path,
    declared: &[Box<dyn crate::flight::effects::Effect>],
) -> anyhow::Result<Vec<Box<dyn crate::flight::effects::Effect>>> {
    let found = crate::analysis::discover::discover(model, data)
        .map_err(|e| anyhow::anyhow!("{}: --discover: {e}", crate::app::shown(flight)))?;
    let ctx = model.effect_context();
    let mut out: Vec<Box<dyn crate::flight::effects::Effect>> = Vec::new();
    for term in found.terms.iter().take(DISCOVERED_CANDIDATES) {
        let effect = crate::flight::spec::EffectSpec::parse(&term.add)?.build(&ctx)?;
        let known = declared
            .iter()
            .chain(&out)
            .any(|e| e.name() == effect.name());
        if !known && !model.has_effect(effect.name()) {
            out.push(effect);
        }
    }
    Ok(out)
}

/// The `--reference` flights, read as the test flight is and each checked to be one
/// ([`crate::analysis::reference::check_reference`]): refused with the reason otherwise.
pub(crate) fn load_references(
    paths: &[std::path::PathBuf],
    flight: &std::path::Path,
    data: &crate::data::FlightData,
    how: &crate::app::cli::DataArgs,
) -> anyhow::Result<Vec<(String, crate::data::FlightData)>> {
    paths
        .iter()
        .map(|p| {
            if p == flight {
                anyhow::bail!(
                    "{}: the test flight cannot be its own reference",
                    crate::app::shown(p)
                );
            }
            let r = crate::app::data::load_flight(p, how)?;
            let name = crate::app::shown(p).to_string();
            crate::analysis::reference::check_reference(data, &r, &name)?;
            Ok((name, r))
        })
        .collect()
}

/// `--out` and `--report`: the model with the causes found, and the page that shows them.
fn keep(
    args: &DiagnoseArgs,
    data: &crate::data::FlightData,
    base: &crate::flight::model::Model,
    d: &diagnose::Diagnosis,
    cfg: &DiagnoseConfig,
) -> anyhow::Result<()> {
    if args.out.is_none() && args.report.is_none() {
        return Ok(());
    }
    let mut model = base.clone();
    for c in &d.found {
        c.correction.apply(&mut model)?;
    }
    // The numbers the filter's own search found in turbulence.
    let added: Vec<&diagnose::turbulence::Refit> = d
        .turbulence
        .iter()
        .flat_map(|t| t.refits.iter().filter(|r| r.added))
        .collect();
    for r in &added {
        model.set_aircraft(&r.param, r.value)?;
    }
    if let Some(out) = &args.out {
        let names: Vec<&str> = d
            .found
            .iter()
            .map(|c| c.effect.as_str())
            .chain(added.iter().map(|r| r.cause.as_str()))
            .collect();
        let comment = format!(
            "The model of `wireflight diagnose --flight {}` with the causes found: {}.\n\
             verdict: {}",
            args.flight.display(),
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(" + ")
            },
            crate::analysis::report::verdict_text(d)
        );
        let text = model_toml(&model, &args.model.choice(), &args.flight, data, &comment)?;
        crate::fsio::write_atomic(out, text.as_bytes())?;
        if !args.json {
            println!("wrote {}", crate::app::shown(out));
        }
    }
    if let Some(path) = &args.report {
        let prep = Prepared::new(data, cfg.compare);
        let after = (!d.found.is_empty())
            .then(|| crate::analysis::compare::compare_prepared(&model, &prep));
        let label = format!(
            "+ {}",
            d.found
                .iter()
                .map(|c| c.effect.as_str())
                .collect::<Vec<_>>()
                .join(" + ")
        );
        let conditions =
            crate::analysis::conditions::conditions(data, &d.base, base.origin.altitude_m);
        let report = wireflight_draw::report::Report {
            command: format!("wireflight diagnose --flight {}", args.flight.display()),
            data_name: args.flight.display().to_string(),
            data,
            model_name: model_label(base),
            before: &d.base,
            after: after.as_ref().map(|a| (a, label)),
            noise: &d.base_noise,
            noise_floor: d.noise_floor,
            window_s: cfg.compare.window_s,
            conditions: &conditions,
            diagnosis: Some(d),
            fitted: &d.found,
            replay: Some(wireflight_draw::report::ReplaySize::default()),
            at_floor: cfg.at_floor,
            turbulence: d.turbulence.as_ref(),
        };
        wireflight_draw::report::write_report(path, &report)?;
        if !args.json {
            println!("wrote {}", crate::app::shown(path));
        }
    }
    Ok(())
}

/// The parameter set a model choice starts from, as a name or an absolute path (so that a
/// model file written anywhere reads it back): `--aircraft`, the model file's, the data's
/// `# aircraft:` (relative to the data file), else the Aerosonde.
fn aircraft_source(
    choice: &crate::flight::spec::ModelChoice,
    flight: &std::path::Path,
    data: &crate::data::FlightData,
) -> anyhow::Result<String> {
    use crate::flight::spec::ModelSpec;
    let source = if let Some(a) = &choice.aircraft {
        a.clone()
    } else if let Some(m) = &choice.model_file {
        ModelSpec::load(m)?.aircraft_source()
    } else if let Some(a) = &data.meta.aircraft {
        let mut s = ModelSpec::baseline(crate::data::VehicleKind::FixedWing);
        s.aircraft = a.clone();
        s.base_dir = flight.parent().map(std::path::Path::to_path_buf);
        s.aircraft_source()
    } else {
        "aerosonde".to_string()
    };
    let path = std::path::Path::new(&source);
    Ok(if source != "aerosonde" && path.is_file() {
        std::fs::canonicalize(path)
            .map(|p| p.display().to_string())
            .unwrap_or(source)
    } else {
        source
    })
}

/// [`add_fitted`] on `flight`'s windows, its error naming the flight and the option: whether
/// an `--add` effect applies can depend on what that flight recorded (an effect that reads
/// the attitude, on a flight without one).
pub(crate) fn add_fitted_on(
    model: &mut crate::flight::model::Model,
    prep: &Prepared,
    specs: &[crate::flight::spec::EffectSpec],
    cfg: &DiagnoseConfig,
    flight: &std::path::Path,
) -> anyhow::Result<Vec<crate::analysis::diagnose::Candidate>> {
    add_fitted(model, prep, specs, cfg)
        .map_err(|e| anyhow::anyhow!("{}: --add: {e}", crate::app::shown(flight)))
}

/// Refuse to compare `model`, with `extra` effects added at their given values, on `data`
/// where a force of theirs is NaN or ∞ at a measured state (a term such as `k*ln(throttle -
/// 2)`): the error names the time, the term, the operation and the values — never a fit
/// that goes on over NaN.
pub(crate) fn check_forces_finite(
    model: &crate::flight::model::Model,
    extra: &[crate::flight::spec::EffectSpec],
    declared: &[Box<dyn crate::flight::effects::Effect>],
    flight: &std::path::Path,
    data: &crate::data::FlightData,
) -> anyhow::Result<()> {
    let mut probe = model.clone();
    let ctx = probe.effect_context();
    for spec in extra.iter().filter(|s| !s.is_aircraft()) {
        // An effect already in the model, or one that does not apply, is refused where it is
        // fitted, with its own message.
        let effect = spec
            .build(&ctx)
            .map_err(|e| anyhow::anyhow!("{}: --add: {e}", crate::app::shown(flight)))?;
        let _ = probe.add_effect(effect);
    }
    for e in declared {
        let _ = probe.add_effect(e.clone());
    }
    match probe.explain_on_data(data) {
        Some((t, why)) => anyhow::bail!(
            "{}: the model's forces are not finite at t = {t:.2} s: {why}",
            crate::app::shown(flight)
        ),
        None => Ok(()),
    }
}

/// `model` as a model file (`--model`): its vehicle, its parameter set (the one the choice
/// started from, every number that differs from it given as `aircraft:KEY=V`), its effects
/// with every parameter and its origin, headed by `comment` lines. Numbers are written so
/// that they read back exactly.
pub(crate) fn model_toml(
    model: &crate::flight::model::Model,
    choice: &crate::flight::spec::ModelChoice,
    flight: &std::path::Path,
    data: &crate::data::FlightData,
    comment: &str,
) -> anyhow::Result<String> {
    use std::fmt::Write as _;
    let mut out = String::new();
    for line in comment.lines() {
        let _ = writeln!(out, "# {line}");
    }
    let _ = writeln!(out, "vehicle = \"{}\"", model.vehicle.kind());
    let mut effects: Vec<String> = Vec::new();
    if model.vehicle.kind() == crate::data::VehicleKind::FixedWing {
        let source = aircraft_source(choice, flight, data)?;
        let set = crate::flight::params::FixedWingParams::load(&source)?;
        let _ = writeln!(out, "aircraft = {source:?}");
        let changed: Vec<String> = crate::flight::params::keys::KEYS
            .iter()
            .filter_map(|k| {
                let v = model.aircraft(k.name)?;
                let was = crate::flight::params::keys::get(&set, k.name)?;
                (v != was).then(|| format!("{}={v:?}", k.name))
            })
            .collect();
        if !changed.is_empty() {
            effects.push(format!("aircraft:{}", changed.join(",")));
        }
    }
    use crate::flight::effects::term::term_of;
    // Terms are written as `[[term]]` tables (their names are no TOML keys), the rest by name.
    let mut listed: Vec<String> = model
        .effects
        .iter()
        .filter(|e| term_of(e.info()).is_none())
        .map(|e| format!("{:?}", e.name()))
        .collect();
    listed.extend(effects.iter().map(|e| format!("{e:?}")));
    let _ = writeln!(out, "effects = [{}]", listed.join(", "));
    for e in &model.effects {
        let params = e.params();
        if let Some(term) = term_of(e.info()) {
            let _ = writeln!(
                out,
                "\n[[term]]\naxis = \"{}\"\nexpr = {:?}",
                term.axis,
                term.expr.source()
            );
        } else if params.is_empty() {
            continue;
        } else {
            let _ = writeln!(out, "\n[{}]", e.name());
        }
        for p in params {
            let _ = writeln!(out, "{} = {:?}", p.name, p.value);
        }
    }
    let o = &model.origin;
    let _ = writeln!(
        out,
        "\n[origin]\nlatitude_deg = {:?}\nlongitude_deg = {:?}\naltitude_m = {:?}",
        o.latitude_deg, o.longitude_deg, o.altitude_m
    );
    Ok(out)
}

/// Check that `path` names a model file (`.toml`).
pub(crate) fn check_model_out(path: &std::path::Path) -> anyhow::Result<()> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
    {
        Ok(())
    } else {
        anyhow::bail!(
            "{}: --out writes the model with the causes found as a model file (a .toml name)",
            path.display()
        )
    }
}

/// Check that `path` names an HTML page (`.html` or `.htm`).
pub(crate) fn check_report(path: &std::path::Path) -> anyhow::Result<()> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"))
    {
        Ok(())
    } else {
        anyhow::bail!(
            "{}: --report writes one HTML page (a .html name)",
            path.display()
        )
    }
}
