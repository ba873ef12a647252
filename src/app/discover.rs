//! `wireflight discover`: the force or moment the model lacks, as terms to add.

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::DiagnoseConfig;
use crate::analysis::discover::discover;
use crate::analysis::discover::error_after::measure_errors;
use crate::analysis::report::model_label;
use crate::analysis::report::{discovery_json, discovery_text};
use crate::app::cli::DiscoverArgs;
use crate::app::workbench::add_fitted_on;

/// Run `wireflight discover`.
///
/// # Errors
/// Bad data or model, or a flight discover cannot read.
pub fn run(args: &DiscoverArgs) -> anyhow::Result<()> {
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let mut model = args.model.choice().build(&args.flight, &data)?;
    let cfg = DiagnoseConfig {
        compare: args.windows.config(model.vehicle.kind()),
        ..DiagnoseConfig::default()
    };
    args.windows.check_fits(&args.flight, &data, &cfg.compare)?;
    let prep = Prepared::new(&data, cfg.compare);
    if !args.model.add.is_empty() {
        add_fitted_on(
            &mut model,
            &prep,
            &args.model.add_specs()?,
            &cfg,
            &args.flight,
        )?;
    }
    let mut found = discover(&model, &data)
        .map_err(|e| anyhow::anyhow!("{}: {e}", crate::app::shown(&args.flight)))?;
    // The error the terms leave, as `compare --add` would report it: worth its fits only
    // where there are terms, and where the flight makes windows.
    if !found.terms.is_empty() && !prep.windows.is_empty() {
        let progress = crate::draw::progress::Progress::spinner(
            &format!("fitting the {} terms found", found.terms.len()),
            args.json,
        );
        measure_errors(&model, &prep, &mut found, &cfg);
        drop(progress);
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&discovery_json(&found))?);
        return Ok(());
    }
    println!(
        "{}: {} samples, {:.1} s; model {}",
        crate::app::shown(&args.flight),
        data.len(),
        data.duration(),
        model_label(&model)
    );
    print!("{}", discovery_text(&found));
    Ok(())
}
