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
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let mut base = args.model.choice().build(&args.flight, &data)?;
    let cfg = DiagnoseConfig {
        compare: args.windows.config(base.vehicle.kind()),
        ..DiagnoseConfig::default()
    };
    args.windows.check_fits(&args.flight, &data, &cfg.compare)?;
    if !args.model.add.is_empty() {
        let prep = Prepared::new(&data, cfg.compare);
        add_fitted(&mut base, &prep, &args.model.add_specs()?, &cfg)?;
    }
    let progress = crate::progress::Progress::spinner(
        &format!("diagnosing {:.0} s of data", data.duration()),
        args.json,
    );
    let d = diagnose::diagnose(&base, &data, &[], &cfg)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?;
    drop(progress);
    if args.json {
        let mut v = diagnosis_json(&d);
        if args.iterate {
            // The ladder with every step's candidates.
            v["ladder"] = ladder_json(&d, true);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "{}: {} samples, {:.1} s; model {}\n  {}",
        crate::app::shown(&args.flight),
        data.len(),
        data.duration(),
        model_label(&base),
        crate::analysis::report::noise_text(&d.base_noise)
    );
    if args.iterate {
        print!("{}", steps_text(&d));
    } else {
        print!("{}", diagnosis_text(&d));
    }
    Ok(())
}
