//! `wireflight diagnose`: which physical effects the flight model is missing, with evidence.
//! The diagnosis is the analysis crate's ([`crate::analysis::diagnose::run`]); this module
//! reads the inputs, writes the outputs and prints.

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::{self, DiagnoseConfig, Diagnosis, Request};
use crate::analysis::report::{
    diagnosis_json, diagnosis_text, floor_word, ladder_json, model_label, next_step_text,
    noise_text, steps_text,
};
use crate::app::cli::DiagnoseArgs;
use crate::app::shown;
use crate::app::workbench::{
    add_fitted_on, check_forces_finite, check_model_out, check_report, load_references, model_toml,
    stated_sensor_errors,
};
use crate::data::FlightData;
use crate::flight::effects::Effect;
use crate::flight::model::Model;

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
    let inputs = crate::app::workbench::flight_inputs(
        std::slice::from_ref(&args.flight),
        ("--reference", &args.reference),
        args.model.model.as_deref(),
    );
    let outputs = crate::app::outputs::given(&[
        ("--out", args.out.as_deref()),
        ("--report", args.report.as_deref()),
    ]);
    crate::app::outputs::check_outputs(&inputs, &outputs, &[])?;
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let references = load_references(&args.reference, &args.flight, &data, &args.data)?;
    let (base, declared, config) = model_and_candidates(args, &data, !references.is_empty())?;
    let named: Vec<(&str, &FlightData)> = references.iter().map(|(n, d)| (n.as_str(), d)).collect();
    let errors = stated_sensor_errors(args.sensor_errors.as_deref())?;
    let progress = crate::draw::progress::Progress::spinner(
        &format!("diagnosing {:.0} s of data", data.duration()),
        args.json,
    );
    let request = Request {
        model: &base,
        data: &data,
        references: &named,
        errors: errors.as_ref(),
        declared: &declared,
        config,
        method: args.method.into(),
    };
    let d =
        diagnose::run(&request).map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?;
    drop(progress);
    if args.json {
        let mut v = diagnosis_json(&d);
        if args.iterate {
            // The ladder with every step's candidates.
            v["ladder"] = ladder_json(&d, true);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let noise = match (&d.reference, &d.error_floor) {
            (Some(r), _) => &r.measured_noise,
            (None, Some(f)) => &f.measured_noise,
            (None, None) => &d.base_noise,
        };
        println!(
            "{}: {} samples, {:.1} s; model {}\n  {}",
            shown(&args.flight),
            data.len(),
            data.duration(),
            model_label(&base),
            noise_text(noise)
        );
        if args.iterate {
            print!("{}", steps_text(&d));
        } else {
            print!("{}", diagnosis_text(&d));
        }
        let flight = shown(&args.flight);
        print!(
            "{}",
            next_step_text(&d, base.vehicle.kind(), &flight, args.discover)
        );
    }
    keep(args, &data, &base, &d, &config)
}

/// Candidate effects beyond the catalogue.
type Candidates = Vec<Box<dyn Effect>>;

/// The model to diagnose (with the `--add` effects fitted), the candidates beyond the
/// catalogue (a model file's terms without values, and `discover`'s with `--discover`), and
/// the search's options.
fn model_and_candidates(
    args: &DiagnoseArgs,
    data: &FlightData,
    with_references: bool,
) -> anyhow::Result<(Model, Candidates, DiagnoseConfig)> {
    // A model also flown on the references must not read the test flight's record there.
    let mut base = if with_references {
        args.model.choice().build_unrecorded(&args.flight, data)?
    } else {
        args.model.choice().build(&args.flight, data)?
    };
    let cfg = DiagnoseConfig {
        compare: args.windows.config(base.vehicle.kind()),
        ..DiagnoseConfig::default()
    };
    args.windows.check_fits(&args.flight, data, &cfg.compare)?;
    // A model file's `[[term]]` without values is a candidate, not part of the model.
    let mut declared = diagnose::take_declared_terms(&mut base);
    let add = args.model.add_specs()?;
    check_forces_finite(&base, &add, &declared, &args.flight, data)?;
    if !add.is_empty() {
        let prep = Prepared::new(data, cfg.compare);
        add_fitted_on(&mut base, &prep, &add, &cfg, &args.flight)?;
    }
    if args.discover {
        let found = discovered_terms(&base, data, &args.flight, &declared)?;
        declared.extend(found);
    }
    Ok((base, declared, cfg))
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

/// `--out` and `--report`: the model with the causes found, and the page that shows them.
fn keep(
    args: &DiagnoseArgs,
    data: &FlightData,
    base: &Model,
    d: &Diagnosis,
    cfg: &DiagnoseConfig,
) -> anyhow::Result<()> {
    if args.out.is_none() && args.report.is_none() {
        return Ok(());
    }
    let model = d.model_with_causes(base)?;
    if let Some(out) = &args.out {
        let names = d.cause_names();
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
            println!("wrote {}", shown(out));
        }
    }
    if let Some(path) = &args.report {
        write_report(args, data, base, &model, d, cfg, path)?;
        if !args.json {
            println!("wrote {}", shown(path));
        }
    }
    Ok(())
}

/// `--report PAGE`: the evidence as one HTML page, with the model with the causes found.
fn write_report(
    args: &DiagnoseArgs,
    data: &FlightData,
    base: &Model,
    model: &Model,
    d: &Diagnosis,
    cfg: &DiagnoseConfig,
    path: &std::path::Path,
) -> anyhow::Result<()> {
    // The causes' comparison weighed as the diagnosis was: by the references' floor or the
    // stated errors' where it was judged against one.
    let mut compare = cfg.compare;
    let mut at_floor = cfg.at_floor;
    if let Some(r) = &d.reference {
        compare.model_error = Some(r.floor.model_error);
    }
    if let Some(f) = &d.error_floor {
        compare.model_error = Some(f.model_error);
        compare.colour_floor = Some(f.colour);
        at_floor = f.at_floor;
    }
    let prep = Prepared::new(data, compare);
    let after =
        (!d.found.is_empty()).then(|| crate::analysis::compare::compare_prepared(model, &prep));
    let label = format!(
        "+ {}",
        d.found
            .iter()
            .map(|c| c.effect.as_str())
            .collect::<Vec<_>>()
            .join(" + ")
    );
    let conditions = crate::analysis::conditions::conditions(data, &d.base, base.origin.altitude_m);
    let report = crate::present::report::Report {
        command: format!("wireflight diagnose --flight {}", args.flight.display()),
        data_name: args.flight.display().to_string(),
        data,
        model_name: model_label(base),
        before: &d.base,
        after: after.as_ref().map(|a| (a, label)),
        noise: match (&d.reference, &d.error_floor) {
            (Some(r), _) => &r.measured_noise,
            (None, Some(f)) => &f.measured_noise,
            (None, None) => &d.base_noise,
        },
        noise_floor: d.noise_floor,
        window_s: cfg.compare.window_s,
        conditions: &conditions,
        diagnosis: Some(d),
        fitted: &d.found,
        replay: Some(crate::present::report::ReplaySize::default()),
        at_floor,
        unit: floor_word(d),
        turbulence: d.turbulence.as_ref(),
    };
    crate::present::report::write_report(path, &report)?;
    Ok(())
}
