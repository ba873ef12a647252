//! `wireflight compare` and `wireflight diagnose`: model vs measurements.

use std::path::Path;

use anyhow::Context;
use serde_json::{json, Value};

use crate::analysis::compare::{
    compare_prepared, estimate_noise, noise_floor, ChannelErrors, CompareConfig, Comparison,
    Prepared,
};
use crate::analysis::conditions::{conditions, explain_growth, growth_exponent, Condition};
use crate::analysis::diagnose::{self, Candidate, DiagnoseConfig, Diagnosis};
use crate::app::cli::{CompareArgs, DiagnoseArgs, ModelArgs};
use crate::flight::data::{self, FlightData};
use crate::flight::effects::{catalogue_effect, Origin};
use crate::flight::model::Model;
use crate::flight::spec::{EffectSpec, ModelSpec};
use crate::flight::VehicleKind;

/// Load the data and build the base model: `--model FILE`, or the data's vehicle (and
/// aircraft) baseline, plus `--effects`; origin from the data's metadata.
pub fn load_data_and_model(data_path: &Path, m: &ModelArgs) -> anyhow::Result<(FlightData, Model)> {
    let data = data::read(data_path)?;
    let mut spec = match &m.model {
        Some(path) => ModelSpec::load(path)?,
        None => {
            let vehicle = data.meta.vehicle.with_context(|| {
                format!(
                    "{}: no `# vehicle:` metadata; say which model with --model FILE",
                    data_path.display()
                )
            })?;
            let mut s = ModelSpec::baseline(vehicle);
            if let Some(a) = &data.meta.aircraft {
                s.aircraft = a.clone();
            }
            s
        }
    };
    if let Some(list) = &m.effects {
        spec.add_effect_list(list).map_err(anyhow::Error::msg)?;
    }
    let origin = Origin {
        latitude_deg: data
            .meta
            .latitude_deg
            .unwrap_or(Origin::default().latitude_deg),
        longitude_deg: data.meta.longitude_deg.unwrap_or(0.0),
        altitude_m: data.meta.altitude_m.unwrap_or(0.0),
    };
    if spec.vehicle == VehicleKind::FixedWing && data.controls.is_none() {
        anyhow::bail!(
            "{}: a fixed-wing model needs the control columns",
            data_path.display()
        );
    }
    let model = spec.build(origin).context("building the model")?;
    Ok((data, model))
}

/// Add `--add` effects to `model`, fitting the parameters not given. Returns the fitted
/// candidates (in order).
fn add_effects(
    model: &mut Model,
    prep: &Prepared,
    adds: &[String],
    cfg: &DiagnoseConfig,
) -> anyhow::Result<Vec<Candidate>> {
    let mut out = Vec::new();
    for text in adds {
        let spec = EffectSpec::parse(text).map_err(anyhow::Error::msg)?;
        let mut effect = catalogue_effect(&spec.name, &model.origin, model.vehicle.span())
            .context("unknown effect")?;
        let mut fixed: Vec<String> = Vec::new();
        for (k, v) in &spec.params {
            effect.set_param(k, *v).map_err(anyhow::Error::msg)?;
            fixed.push(k.clone());
        }
        if prep.data.meta.latitude_deg.is_some() {
            fixed.push("latitude_deg".into());
        }
        let before: f64 = compare_prepared(model, prep)
            .windows
            .iter()
            .map(|w| w.score * w.score * (w.samples.1 - w.samples.0) as f64)
            .sum();
        let cand = diagnose::try_effect(model, effect, &fixed, prep, cfg, before, 0.0)
            .map_err(anyhow::Error::msg)?;
        model
            .add_effect(cand.fitted_effect.clone())
            .map_err(anyhow::Error::msg)?;
        out.push(cand);
    }
    Ok(out)
}

fn channels_json(c: &ChannelErrors) -> Value {
    json!({
        "position_m": c.position_m,
        "velocity_mps": c.velocity_mps,
        "attitude_deg": c.attitude_deg,
    })
}

fn comparison_json(c: &Comparison) -> Value {
    json!({
        "total": c.total,
        "channels": channels_json(&c.channels),
    })
}

fn windows_json(c: &Comparison) -> Value {
    Value::Array(
        c.worst_windows()
            .iter()
            .map(|w| {
                json!({
                    "t0": w.t0, "t1": w.t1, "score": w.score,
                    "dominant_channel": w.errors.dominant(),
                    "channels": channels_json(&w.errors),
                })
            })
            .collect(),
    )
}

fn candidate_json(c: &Candidate) -> Value {
    let params: serde_json::Map<String, Value> = c
        .params
        .iter()
        .map(|(k, v)| (k.clone(), json!(v)))
        .collect();
    let unc: serde_json::Map<String, Value> = c
        .params
        .iter()
        .zip(&c.uncertainty)
        .filter(|(_, u)| u.is_finite())
        .map(|((k, _), u)| (k.clone(), json!(u)))
        .collect();
    json!({
        "effect": c.effect,
        "params": params,
        "uncertainty": unc,
        "error_before": c.error_before,
        "error_after": c.error_after,
        "error_reduction": c.error_reduction,
        "excess_removed": c.excess_removed,
        "lr_statistic": c.lr_statistic,
        "significant": c.significant,
    })
}

fn fmt_opt(v: Option<f64>, unit: &str) -> String {
    v.map(|x| format!("{x:.3} {unit}"))
        .unwrap_or_else(|| "—".into())
}

/// Four significant digits, in scientific notation when small (drag's k is ~1e-4) or large.
fn fmt_number(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-2 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

fn fmt_params(c: &Candidate) -> String {
    c.params
        .iter()
        .zip(&c.uncertainty)
        .map(|((k, v), u)| {
            if u.is_finite() {
                format!("{k}={}±{}", fmt_number(*v), fmt_number(*u))
            } else {
                format!("{k}={}", fmt_number(*v))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// "baseline" or "+ a + b": the effects of a model, for titles and tables.
fn model_effects_label(model: &Model) -> String {
    if model.effects.is_empty() {
        "baseline".to_string()
    } else {
        format!("+ {}", model.effect_names().join(" + "))
    }
}

/// "fixed-wing baseline", "point-mass + drag": a model in a few words.
fn model_label(model: &Model) -> String {
    format!("{} {}", model.vehicle.kind(), model_effects_label(model))
}

/// Run `wireflight compare`.
///
/// # Errors
/// Bad data or model, bad effects, plot or output errors.
pub fn run_compare(args: &CompareArgs) -> anyhow::Result<()> {
    let (data, base) = load_data_and_model(&args.data, &args.model)?;
    let cfg = CompareConfig {
        window_s: args
            .window
            .unwrap_or(CompareConfig::default_window_s(base.vehicle.kind())),
        ..CompareConfig::default()
    };
    let prep = Prepared::new(&data, cfg);
    if prep.windows.is_empty() {
        anyhow::bail!("{}: too short to compare", args.data.display());
    }
    let before = compare_prepared(&base, &prep);
    let noise = estimate_noise(&data);
    let mut after_model = base.clone();
    let fitted = add_effects(
        &mut after_model,
        &prep,
        &args.model.add,
        &DiagnoseConfig::default(),
    )?;
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
            data_name: Some(args.data.display().to_string()),
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
        let mut track = crate::app::replay::ModelTrack::from_comparison(&data, &shown)?;
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
        let mut rasterizer = crate::app::render::Rasterizer::Cpu;
        let (frames, _) = crate::app::replay::write_frames(
            &data,
            Some(track),
            &mesh,
            viewport,
            args.fps,
            dir,
            &mut rasterizer,
        )?;
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
            "data": args.data.display().to_string(),
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
        args.data.display(),
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

fn print_diagnosis(d: &Diagnosis) {
    println!(
        "  baseline error {:.3}, noise floor {:.3}",
        d.base_error, d.noise_floor
    );
    println!(
        "  {:18} {:>9} → {:<9} {:>8} {:>8}  {}",
        "effect", "before", "after", "removed", "signif.", "fitted parameters"
    );
    for c in &d.ranking {
        println!(
            "  {:18} {:>9.3} → {:<9.3} {:>7.0}% {:>8}  {}",
            c.effect,
            c.error_before,
            c.error_after,
            100.0 * c.error_reduction,
            if c.significant { "yes" } else { "no" },
            fmt_params(c)
        );
    }
    match d.winner() {
        Some(w) => println!(
            "  verdict: `{}` is missing ({}); it removes {:.0}% of the error above the noise floor",
            w.effect,
            fmt_params(w),
            100.0 * w.excess_removed.min(1.0)
        ),
        None => println!("  verdict: none — no effect explains more than fitting noise would"),
    }
}

fn diagnosis_json(d: &Diagnosis) -> Value {
    json!({
        "verdict": d.verdict,
        "base_error": d.base_error,
        "noise_floor": d.noise_floor,
        "ranking": d.ranking.iter().map(candidate_json).collect::<Vec<_>>(),
    })
}

/// Run `wireflight diagnose`.
///
/// # Errors
/// Bad data or model.
pub fn run_diagnose(args: &DiagnoseArgs) -> anyhow::Result<()> {
    let (data, mut base) = load_data_and_model(&args.data, &args.model)?;
    let cfg = DiagnoseConfig {
        compare: CompareConfig {
            window_s: args
                .window
                .unwrap_or(CompareConfig::default_window_s(base.vehicle.kind())),
            ..DiagnoseConfig::default().compare
        },
        ..DiagnoseConfig::default()
    };
    if !args.model.add.is_empty() {
        let prep = Prepared::new(&data, cfg.compare);
        add_effects(&mut base, &prep, &args.model.add, &cfg)?;
    }
    if args.iterate {
        let (ladder, _) = diagnose::iterate(&base, &data, &[], &cfg, 5);
        let last = &ladder[ladder.len() - 1].diagnosis;
        if args.json {
            let v = json!({
                "verdict": ladder.first().and_then(|r| r.diagnosis.verdict.clone()),
                "ranking": ladder[0].diagnosis.ranking.iter().map(candidate_json).collect::<Vec<_>>(),
                "ladder": ladder.iter().map(|r| json!({
                    "effects": r.effects, "error": r.error,
                    "noise_floor": r.diagnosis.noise_floor,
                    "verdict": r.diagnosis.verdict,
                })).collect::<Vec<_>>(),
                "found": ladder.iter().filter_map(|r| r.diagnosis.verdict.clone()).collect::<Vec<_>>(),
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
            print_diagnosis(&r.diagnosis);
            println!();
        }
        println!("ladder (error vs effects added):");
        for r in &ladder {
            println!(
                "  {:40} {:9.3}   (noise floor {:.3})",
                if r.effects.is_empty() {
                    "baseline".into()
                } else {
                    format!("+ {}", r.effects.join(" + "))
                },
                r.error,
                r.diagnosis.noise_floor
            );
        }
        return Ok(());
    }
    let d = diagnose::diagnose(&base, &data, &[], &cfg);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&diagnosis_json(&d))?);
    } else {
        println!(
            "{}: {} samples, {:.1} s; model {}",
            args.data.display(),
            data.len(),
            data.duration(),
            model_label(&base)
        );
        print_diagnosis(&d);
    }
    Ok(())
}
