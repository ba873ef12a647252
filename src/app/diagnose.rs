//! `wireflight diagnose`: which physical effect the flight model is missing, with evidence.

use serde_json::json;

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::{self, add_fitted, DiagnoseConfig};
use crate::analysis::report::{candidate_json, diagnosis_json, diagnosis_text, model_label, Table};
use crate::app::cli::DiagnoseArgs;
use crate::numeric::format::fixed;

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
    if args.iterate {
        let (ladder, _) = diagnose::iterate(&base, &data, &[], &cfg, 5)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?;
        drop(progress);
        let last = &ladder[ladder.len() - 1].diagnosis;
        if args.json {
            let v = json!({
                "verdict": ladder.first().map(|r| r.diagnosis.verdict.to_string()),
                "ranking": ladder[0].diagnosis.ranking.iter().map(candidate_json).collect::<Vec<_>>(),
                "ladder": ladder.iter().map(|r| json!({
                    "effects": r.effects, "error": r.error,
                    "noise_floor": r.diagnosis.noise_floor,
                    "verdict": r.diagnosis.verdict.to_string(),
                })).collect::<Vec<_>>(),
                "found": ladder.iter().filter_map(|r| r.diagnosis.winner().map(|w| w.effect.clone())).collect::<Vec<_>>(),
                "final": diagnosis_json(last),
            });
            println!("{}", serde_json::to_string_pretty(&v)?);
            return Ok(());
        }
        for (i, r) in ladder.iter().enumerate() {
            println!(
                "step {}: model {}",
                i + 1,
                if r.effects.is_empty() {
                    "baseline".into()
                } else {
                    format!("+ {}", r.effects.join(" + "))
                }
            );
            print!("{}", diagnosis_text(&r.diagnosis));
            println!();
        }
        println!("ladder (error vs effects added):");
        let mut t = Table::new(["model", "error", "× noise", "noise floor"]);
        for r in &ladder {
            t.row([
                if r.effects.is_empty() {
                    "baseline".into()
                } else {
                    format!("+ {}", r.effects.join(" + "))
                },
                fixed(r.error, 3),
                fixed(r.diagnosis.noise_units, 2),
                fixed(r.diagnosis.noise_floor, 3),
            ]);
        }
        print!("{}", t.render(2));
        return Ok(());
    }
    let d = diagnose::diagnose(&base, &data, &[], &cfg)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.flight.display()))?;
    drop(progress);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&diagnosis_json(&d))?);
    } else {
        println!(
            "{}: {} samples, {:.1} s; model {}\n  {}",
            crate::app::shown(&args.flight),
            data.len(),
            data.duration(),
            model_label(&base),
            crate::analysis::report::noise_text(&d.base_noise)
        );
        print!("{}", diagnosis_text(&d));
    }
    Ok(())
}
