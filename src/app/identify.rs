//! `wireflight identify`: many numbers of the aircraft's parameter set fitted together over
//! several flights, checked on held-out ones, written as a parameter-set TOML. The
//! identification is the analysis crate's ([`crate::analysis::identify::run`]); this module
//! reads the inputs, writes the parameter set and prints.

use std::path::Path;

use anyhow::{bail, Context};

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::DiagnoseConfig;
use crate::analysis::identify::{self, free_keys, Identified, IdentifyConfig, Request, RunError};
use crate::analysis::report::{identification_json, identification_text, Flights};
use crate::app::cli::IdentifyArgs;
use crate::app::shown;
use crate::app::workbench::add_fitted_on;
use crate::data::FlightData;
use crate::data::VehicleKind;
use crate::flight::model::{Model, Vehicle};
use crate::flight::params::keys;

/// Run `wireflight identify`.
///
/// # Errors
/// Bad data, model or keys; a point mass; a flight too short for a window.
pub fn run(args: &IdentifyArgs) -> anyhow::Result<()> {
    let inputs = crate::app::workbench::flight_inputs(
        &args.flight,
        ("--validate", &args.validate),
        args.model.model.as_deref(),
    );
    if let Some(out) = &args.out {
        crate::app::outputs::check_outputs(&inputs, &[("--out", out)], &[])?;
    }
    // Every file through the one reader of the commands (CSV, ULog, column maps), as compare.
    let flights: Vec<FlightData> = args
        .flight
        .iter()
        .map(|p| crate::app::data::load_flight(p, &args.data))
        .collect::<anyhow::Result<_>>()?;
    let (base, config) = starting_model(args, &flights)?;
    let held_out = load_held_out(args, &config)?;
    let free = free_keys(&args.free)?;
    let request = Request {
        model: &base,
        flights: &flights,
        held_out: &held_out,
        free: &free,
        config,
        method: args.method.into(),
    };
    let r = identify::run(&request).map_err(|e| match e {
        RunError::Identify(e) => anyhow::Error::new(e),
        RunError::Filter(_) => anyhow::anyhow!("{e}"),
    })?;
    if let Some(out) = &args.out {
        write_parameter_set(args, &r, out)?;
    }
    if args.json {
        let files: Vec<String> = args
            .validate
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        let v = identification_json(&r, &files);
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    let fitted: Vec<String> = args.flight.iter().map(|p| shown(p)).collect();
    let held_out: Vec<String> = args.validate.iter().map(|p| shown(p)).collect();
    let names = Flights {
        fitted: &fitted,
        held_out: &held_out,
        samples: flights.iter().map(FlightData::len).sum(),
        duration_s: flights.iter().map(FlightData::duration).sum(),
    };
    print!("{}", identification_text(&r, &names));
    if let Some(out) = &args.out {
        println!("  wrote {}", shown(out));
    }
    Ok(())
}

/// The model to start from, a fixed wing, with the `--add` effects fitted on the first
/// flight, and the identification's settings; every flight checked to be of that aircraft
/// and to hold a window.
fn starting_model(
    args: &IdentifyArgs,
    flights: &[FlightData],
) -> anyhow::Result<(Model, IdentifyConfig)> {
    let first = &args.flight[0];
    let mut base = args.model.choice().build(first, &flights[0])?;
    if !matches!(base.vehicle, Vehicle::FixedWing(_)) {
        bail!("identify fits an aircraft's parameter set: the model is a point mass");
    }
    for (path, data) in args.flight.iter().zip(flights) {
        same_vehicle(path, data, first, "--flight")?;
    }
    let config = IdentifyConfig {
        compare: args.windows.config(base.vehicle.kind()),
        prior: args.prior,
        equation_error: !args.no_equation_error,
        ..IdentifyConfig::default()
    };
    if !args.model.add.is_empty() {
        let dcfg = DiagnoseConfig {
            compare: config.compare,
            ..DiagnoseConfig::default()
        };
        let prep = Prepared::new(&flights[0], config.compare);
        add_fitted_on(&mut base, &prep, &args.model.add_specs()?, &dcfg, first)?;
    }
    for (path, data) in args.flight.iter().zip(flights) {
        args.windows.check_fits(path, data, &config.compare)?;
    }
    Ok((base, config))
}

/// The `--validate` flights, each checked to be of the aircraft identified and to hold a
/// window.
fn load_held_out(args: &IdentifyArgs, config: &IdentifyConfig) -> anyhow::Result<Vec<FlightData>> {
    args.validate
        .iter()
        .map(|p| {
            let d = crate::app::data::load_flight(p, &args.data)?;
            same_vehicle(p, &d, &args.flight[0], "--validate")?;
            args.windows.check_fits(p, &d, &config.compare)?;
            Ok(d)
        })
        .collect()
}

/// Refuse a flight that is not of the fixed-wing aircraft being identified (a point mass, or
/// data without the controls a fixed-wing model is flown by), naming it and the first flight.
fn same_vehicle(path: &Path, data: &FlightData, first: &Path, option: &str) -> anyhow::Result<()> {
    if data.meta.vehicle == Some(VehicleKind::PointMass) || data.attitude.is_none() {
        bail!(
            "{option} {}: a point-mass flight, but {} is a fixed-wing one: identify fits one \
             aircraft's parameter set to flights of that aircraft",
            shown(path),
            shown(first)
        );
    }
    if data.controls.is_none() {
        bail!(
            "{option} {}: no control channels, which a fixed-wing model is flown by (as {} is)",
            shown(path),
            shown(first)
        );
    }
    Ok(())
}

/// `--out`: the identified parameter set, headed by the flights and the numbers fitted.
fn write_parameter_set(args: &IdentifyArgs, r: &Identified, out: &Path) -> anyhow::Result<()> {
    let id = &r.identification;
    let Vehicle::FixedWing(p) = &id.model.vehicle else {
        unreachable!("the starting model is checked to be a fixed wing");
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
    Ok(())
}
