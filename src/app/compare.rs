//! `wireflight compare`: where and how a flight model fails against measured data, before
//! and after adding effects.

use serde_json::{json, Value};

use crate::analysis::compare::{
    compare_prepared, estimate_noise, noise_floor, CompareConfig, Prepared,
};
use crate::analysis::conditions::{conditions, explain_growth, growth_exponent, Condition};
use crate::analysis::diagnose::{add_fitted, DiagnoseConfig};
use crate::analysis::report::{
    candidate_json, comparison_json, fmt_opt, fmt_params, model_label, windows_json,
};
use crate::app::cli::CompareArgs;
use crate::clip::Clipper;
use crate::output::write_frames;
use crate::render::Rasterizer;
use crate::scene::replay::ReplayScene;
use crate::scene::track::ModelTrack;

/// Run `wireflight compare`.
///
/// # Errors
/// Bad data or model, bad effects, plot or output errors.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let data = crate::flight::data::read(&args.flight)?;
    let base = args.model.choice().build(&args.flight, &data)?;
    let cfg = CompareConfig {
        window_s: args
            .window
            .unwrap_or(CompareConfig::default_window_s(base.vehicle.kind())),
        ..CompareConfig::default()
    };
    let prep = Prepared::new(&data, cfg);
    if prep.windows.is_empty() {
        anyhow::bail!("{}: too short to compare", args.flight.display());
    }
    let before = compare_prepared(&base, &prep);
    let noise = estimate_noise(&data);
    let mut after_model = base.clone();
    let fitted = add_fitted(
        &mut after_model,
        &prep,
        &args.model.add_specs()?,
        &DiagnoseConfig::default(),
    )
    .map_err(anyhow::Error::msg)?;
    let after = (!fitted.is_empty()).then(|| compare_prepared(&after_model, &prep));
    let final_model = if after.is_some() { &after_model } else { &base };
    let floor = noise_floor(final_model, &prep, &noise, 0x5eed);
    let conds = conditions(&data, &before, base.origin.altitude_m);
    let growth = growth_exponent(&data, &before);
    let label = format!("+ {}", args.model.add.join(" + "));

    if let Some(dir) = &args.plots {
        let best: Option<&Condition> = conds.first();
        let series = best.map(|c| crate::analysis::plots::ConditionSeries {
            name: c.name.to_string(),
            unit: c.unit.to_string(),
            per_window: c.per_window.clone(),
        });
        let info = crate::analysis::plots::PlotInfo {
            data_name: Some(args.flight.display().to_string()),
            model_name: Some(model_label(&base)),
            noise_floor: Some(floor),
        };
        let files = crate::analysis::plots::write_plots_with(
            dir,
            &data,
            &before,
            after.as_ref().map(|a| (a, label.as_str())),
            series.as_ref(),
            &info,
        )?;
        if !args.json {
            for f in &files {
                println!("plot: {}", f.display());
            }
        }
    }

    if let Some(dir) = &args.frames_dir {
        // The overlay needs every sample predicted: compare over all windows (prep may be
        // the same already).
        let shown_model = if after.is_some() { &after_model } else { &base };
        let shown = compare_prepared(shown_model, &prep);
        let mut track = ModelTrack::from_comparison(&data, &shown)?;
        // One scale for before and after, so the strip shows the error fall.
        track.strip_scale_m = before
            .prediction
            .pos_ned
            .iter()
            .zip(&before.prediction.index)
            .map(|(p, &i)| (*p - data.pos_ned[i]).length())
            .fold(track.strip_scale_m, f64::max);
        let mesh = crate::mesh::plane::builtin_plane();
        let viewport = crate::pipeline::Viewport {
            width: args.size.0,
            height: args.size.1,
        };
        let mut rasterizer = Rasterizer::Cpu;
        let mut replay = ReplayScene::new(&data, &mesh, Clipper::Blinn)?.with_model(track);
        let span = (data.time[0], data.time[data.len() - 1]);
        let (frames, _) =
            write_frames(&mut replay, span, viewport, args.fps, dir, &mut rasterizer)?;
        if !args.json {
            println!(
                "wrote {frames} overlay frames to {} (measured: green, model {}: magenta)",
                dir.display(),
                model_label(shown_model)
            );
        }
    }

    if args.json {
        let mut v = json!({
            "data": args.flight.display().to_string(),
            "model": base.effect_names(),
            "error": comparison_json(&before),
            "noise_floor": floor,
            "noise": {"position_m": noise.pos_m, "velocity_mps": noise.vel_mps,
                      "attitude_deg": noise.att_rad.to_degrees(),
                      "rate_dps": noise.rate_radps.to_degrees()},
            "windows": windows_json(&before),
            "conditions": conds.iter().map(|c| json!({
                "name": c.name, "unit": c.unit, "correlation": c.correlation})).collect::<Vec<_>>(),
            "growth_exponent": growth,
        });
        if let Some(a) = &after {
            v["added"] = Value::Array(fitted.iter().map(candidate_json).collect());
            v["after"] = comparison_json(a);
            v["after_windows"] = windows_json(a);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }

    println!(
        "{}: {} samples, {:.1} s, {} windows of {:.0} s; model: {}",
        args.flight.display(),
        data.len(),
        data.duration(),
        before.windows.len(),
        cfg.window_s,
        model_label(&base)
    );
    let b = &before.channels;
    match &after {
        None => {
            println!("\n  channel            error");
            println!("  position     {:>14}", fmt_opt(Some(b.position_m), "m"));
            println!("  velocity     {:>14}", fmt_opt(b.velocity_mps, "m/s"));
            println!("  attitude     {:>14}", fmt_opt(b.attitude_deg, "deg"));
            println!(
                "  total        {:>14.3}   (noise floor {floor:.3})",
                before.total
            );
        }
        Some(a) => {
            let c = &a.channels;
            println!("\n  channel            before  →  after {label}");
            println!(
                "  position     {:>14}  →  {}",
                fmt_opt(Some(b.position_m), "m"),
                fmt_opt(Some(c.position_m), "m")
            );
            println!(
                "  velocity     {:>14}  →  {}",
                fmt_opt(b.velocity_mps, "m/s"),
                fmt_opt(c.velocity_mps, "m/s")
            );
            println!(
                "  attitude     {:>14}  →  {}",
                fmt_opt(b.attitude_deg, "deg"),
                fmt_opt(c.attitude_deg, "deg")
            );
            println!(
                "  total        {:>14.3}  →  {:.3}   (noise floor {floor:.3})",
                before.total, a.total
            );
            for f in &fitted {
                println!("  fitted {}: {}", f.effect, fmt_params(f));
            }
        }
    }
    println!("\nworst windows:");
    for w in before.worst_windows().iter().take(3) {
        println!(
            "  {:7.1}–{:7.1} s  score {:8.3}  dominated by {}",
            w.t0,
            w.t1,
            w.score,
            w.errors.dominant()
        );
    }
    println!("\nerror correlates with:");
    for c in conds.iter().take(3) {
        println!(
            "  {:36} r = {}",
            format!("{} ({})", c.name, c.unit),
            c.correlation
                .map_or("n/a".to_string(), |r| format!("{r:+.2}"))
        );
    }
    if let Some(k) = growth {
        println!("\nwithin a window, {} (exponent {k:.1})", explain_growth(k));
    }
    if before.total < 1.2 * floor && after.is_none() {
        println!("the error is at the noise floor: nothing left to find with this data");
    }
    Ok(())
}
