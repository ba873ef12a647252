//! `wireflight compare`: where and how a flight model fails against measured data, before
//! and after adding effects.

use serde_json::{json, Value};

use crate::analysis::compare::{
    compare_prepared, noise_floor, CompareConfig, Comparison, Prepared,
};
use crate::analysis::conditions::{conditions, explain_growth, growth_exponent, Condition};
use crate::analysis::diagnose::reference::diagnose_against;
use crate::analysis::diagnose::turbulence::{compare_through_turbulence, Method};
use crate::analysis::diagnose::{diagnose, promising_numbers, DiagnoseConfig, Verdict};
use crate::analysis::report::{
    axes_text, candidate_json, comparison_json, conditions_json, count, fmt_opt, fmt_params,
    innovations_text, model_label, noise_json, noise_text, turbulence_json, turbulence_text,
    windows_json, Table,
};
use crate::app::cli::CompareArgs;
use crate::data::FlightData;
use crate::draw::output::{write_frames, FrameOut};
use crate::draw::render::Rasterizer;
use crate::draw::scene::replay::ReplayScene;
use crate::draw::scene::track::ModelTrack;
use crate::flight::model::Model;
use crate::flight::numeric::format::fixed;
use crate::geometry::clip::Clipper;

/// Where and how one model fails: its comparison, the conditions its error follows and how
/// the error grows inside a window.
struct Findings {
    comparison: Comparison,
    conditions: Vec<Condition>,
    growth: Option<f64>,
}

impl Findings {
    fn of(model: &Model, data: &FlightData, prep: &Prepared) -> Self {
        let comparison = compare_prepared(model, prep);
        // The growth law needs the model on its own: starts fitted over the first quarter of
        // each window, the drift measured over the rest.
        let cfg = prep.config();
        let fit_span = 0.25 * cfg.window_s;
        let drift_prep = Prepared::new(
            data,
            CompareConfig {
                start_span_s: Some(fit_span),
                ..cfg
            },
        );
        let drift = compare_prepared(model, &drift_prep);
        let noise_m2: f64 = prep.noise.pos_axes.iter().map(|s| s * s).sum();
        Self {
            conditions: conditions(data, &comparison, model.origin.altitude_m),
            growth: growth_exponent(data, &drift, fit_span, noise_m2),
            comparison,
        }
    }
}

/// Run `wireflight compare`.
///
/// # Errors
/// Bad data or model, bad effects, plot or output errors.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    // --out by its extension: .gif the replay, .toml the model with the --add effects.
    let ext =
        |p: &std::path::Path, e: &str| p.extension().is_some_and(|x| x.eq_ignore_ascii_case(e));
    let gif_out = args.out.as_deref().filter(|o| ext(o, "gif"));
    let model_out = args.out.as_deref().filter(|o| ext(o, "toml"));
    if let Some(out) = &args.out {
        if gif_out.is_none() && model_out.is_none() {
            anyhow::bail!(
                "{}: --out writes an animated GIF (a .gif name) or the model as a model file \
                 (a .toml name)",
                out.display()
            );
        }
    }
    if let Some(report) = &args.report {
        crate::app::diagnose::check_report(report)?;
    }
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let references =
        crate::app::diagnose::load_references(&args.reference, &args.flight, &data, &args.data)?;
    // A model also flown on the references must not read the test flight's record there.
    let base = if references.is_empty() {
        args.model.choice().build(&args.flight, &data)?
    } else {
        args.model.choice().build_unrecorded(&args.flight, &data)?
    };
    crate::app::diagnose::check_forces_finite(
        &base,
        &args.model.add_specs()?,
        &[],
        &args.flight,
        &data,
    )?;
    let mut cfg = args.windows.config(base.vehicle.kind());
    args.windows.check_fits(&args.flight, &data, &cfg)?;
    let reference_floor = if references.is_empty() {
        None
    } else {
        let named: Vec<(&str, &crate::data::FlightData)> =
            references.iter().map(|(n, d)| (n.as_str(), d)).collect();
        let f = crate::analysis::reference::model_floor(&base, &named, cfg)?;
        cfg.model_error = Some(f.model_error);
        Some((
            named.iter().map(|(n, _)| n.to_string()).collect::<Vec<_>>(),
            f,
        ))
    };
    let unit = if reference_floor.is_some() {
        "floor"
    } else {
        "noise"
    };
    let prep = Prepared::new(&data, cfg);
    if prep.windows.is_empty() {
        anyhow::bail!(
            "{}: too short to compare ({} samples over {:.2} s; a window is {} s)",
            args.flight.display(),
            data.len(),
            data.duration(),
            cfg.window_s
        );
    }
    let progress = crate::draw::progress::Progress::spinner(
        &format!("comparing over {:.0} s of data", data.duration()),
        args.json,
    );
    let before = Findings::of(&base, &data, &prep);
    let mut after_model = base.clone();
    let fitted = crate::app::diagnose::add_fitted_on(
        &mut after_model,
        &prep,
        &args.model.add_specs()?,
        &DiagnoseConfig {
            compare: cfg,
            ..DiagnoseConfig::default()
        },
        &args.flight,
    )?;
    let after = (!fitted.is_empty()).then(|| Findings::of(&after_model, &data, &prep));
    // What is said about where the model fails describes the model as it ends up.
    let (final_model, last) = match &after {
        Some(a) => (&after_model, a),
        None => (&base, &before),
    };
    let floor = noise_floor(final_model, &prep);
    let at_floor = last.comparison.noise_units() <= DiagnoseConfig::default().at_floor;
    // The filter-error method where a diagnosis of the model as it ends up leaves the flight
    // unexplained (a comparison searches no cause, and the filter would take a missing
    // steady wind for gusts): the gusts, and the --add effects fitted again through the
    // filter (their output-error values are the ones printed with the table; the filter's
    // are in its own section and --out).
    let named: Vec<(&str, &FlightData)> = references.iter().map(|(n, d)| (n.as_str(), d)).collect();
    let method: Method = args.method.into();
    let unexplained = method == Method::Auto
        && !at_floor
        && final_model.vehicle.kind() == crate::data::VehicleKind::FixedWing
        && {
            let dcfg = DiagnoseConfig {
                compare: cfg,
                ..DiagnoseConfig::default()
            };
            let verdict = if named.is_empty() {
                diagnose(final_model, &data, &[], &dcfg)
                    .ok()
                    .map(|d| d.verdict)
            } else {
                diagnose_against(final_model, &data, &named, &[], &dcfg)
                    .ok()
                    .map(|d| d.verdict)
            };
            verdict == Some(Verdict::Unexplained)
        };
    let mut refitted = fitted.clone();
    let turbulence =
        compare_through_turbulence(&base, &mut refitted, &prep, &named, method, unexplained)
            .map_err(|e| {
                anyhow::anyhow!("{}: --method filter-error: {e}", args.flight.display())
            })?;
    drop(progress);
    let label = format!("+ {}", args.model.add.join(" + "));
    // The model --out writes: with the filter's values where it ran.
    let out_model = turbulence.as_ref().map_or(&after_model, |(_, m)| m);
    // The condition the text names first: the final model's when the text lists them (above
    // the floor), else the model as given's, which `compare` without --add lists.
    let quoted = if at_floor { &before } else { last };
    if let Some(dir) = &args.plots {
        let series = quoted
            .conditions
            .first()
            .map(|c| crate::draw::plots::ConditionSeries {
                name: c.name.to_string(),
                unit: c.unit.to_string(),
                per_window: c.per_window.clone(),
            });
        let info = crate::draw::plots::PlotInfo {
            data_name: Some(args.flight.display().to_string()),
            model_name: Some(model_label(&base)),
            noise_floor: Some(floor),
            window_s: Some(cfg.window_s),
        };
        let files = crate::draw::plots::write_plots_with(
            dir,
            &data,
            &before.comparison,
            after.as_ref().map(|a| (&a.comparison, label.as_str())),
            series.as_ref(),
            &info,
        )?;
        if !args.json {
            for f in &files {
                println!("plot: {}", crate::app::shown(f));
            }
        }
    }

    let frame_outs = [
        args.frames_dir.as_deref().map(FrameOut::Pngs),
        gif_out.map(FrameOut::Gif),
    ];
    for out in frame_outs.into_iter().flatten() {
        let mut track = ModelTrack::from_comparison(&data, &last.comparison)?;
        // One scale for before and after, so the strip shows the error fall.
        let b = &before.comparison.prediction;
        track.strip_scale_m = b
            .pos_ned
            .iter()
            .zip(&b.index)
            .map(|(p, &i)| (*p - data.pos_ned[i]).length())
            .fold(track.strip_scale_m, f64::max);
        let mesh = crate::geometry::mesh::plane::builtin_plane();
        let viewport = crate::geometry::pipeline::Viewport {
            width: args.size.0,
            height: args.size.1,
        };
        let mut rasterizer = Rasterizer::Cpu;
        let mut replay = ReplayScene::new(&data, &mesh, Clipper::Blinn)?.with_model(track);
        let span = (data.time[0], data.time[data.len() - 1]);
        let w = write_frames(
            &mut replay,
            span,
            viewport,
            args.fps,
            args.max_frames,
            out,
            &mut rasterizer,
            args.json,
        )?;
        if !args.json {
            let (what, to) = match out {
                FrameOut::Pngs(dir) => ("overlay frames", dir),
                FrameOut::Gif(gif) => ("GIF frames", gif),
            };
            println!(
                "wrote {} {what} to {} (measured: green, model {}: magenta)",
                w.frames,
                crate::app::shown(to),
                model_label(final_model)
            );
        }
    }

    if let Some(out) = model_out {
        let comment = format!(
            "The model of `wireflight compare --flight {}`{}.",
            args.flight.display(),
            match (&turbulence, fitted.is_empty()) {
                (_, true) => String::new(),
                (Some(_), false) => {
                    format!(" with {label}, fitted through the filter-error method")
                }
                (None, false) => format!(" with {label}, fitted"),
            }
        );
        let text = crate::app::diagnose::model_toml(
            out_model,
            &args.model.choice(),
            &args.flight,
            &data,
            &comment,
        )?;
        crate::fsio::write_atomic(out, text.as_bytes())?;
        if !args.json {
            println!("wrote {}", crate::app::shown(out));
        }
    }
    if let Some(path) = &args.report {
        let report = wireflight_draw::report::Report {
            command: format!("wireflight compare --flight {}", args.flight.display()),
            data_name: args.flight.display().to_string(),
            data: &data,
            model_name: model_label(&base),
            before: &before.comparison,
            after: after.as_ref().map(|a| (&a.comparison, label.clone())),
            noise: &prep.noise,
            noise_floor: floor,
            window_s: cfg.window_s,
            conditions: &quoted.conditions,
            diagnosis: None,
            fitted: &fitted,
            replay: Some(wireflight_draw::report::ReplaySize::default()),
            at_floor: DiagnoseConfig::default().at_floor,
            turbulence: turbulence.as_ref().map(|(t, _)| t),
        };
        wireflight_draw::report::write_report(path, &report)?;
        if !args.json {
            println!("wrote {}", crate::app::shown(path));
        }
    }

    if args.json {
        let mut v = json!({
            "data": args.flight.display().to_string(),
            "model": base.effect_names(),
            "error": comparison_json(&before.comparison),
            "noise_floor": floor,
            "noise": noise_json(&prep.measured_noise),
            "reference": reference_floor.as_ref().map(|(names, f)| json!({
                "flights": names,
                "noise_units": f.noise_units,
                "model_error": noise_json(&f.model_error),
            })),
            "windows": windows_json(&before.comparison),
            "conditions": conditions_json(&before.conditions),
            "growth_exponent": before.growth,
            "turbulence": turbulence.as_ref().map(|(t, _)| {
                let mut v = turbulence_json(t);
                v["innovations_noise_units"] = json!(t.gusts.gusty.rows_noise_units);
                v
            }),
        });
        if let Some(a) = &after {
            v["added"] = Value::Array(fitted.iter().map(candidate_json).collect());
            v["after"] = comparison_json(&a.comparison);
            v["after_windows"] = windows_json(&a.comparison);
            v["after_conditions"] = conditions_json(&a.conditions);
            v["after_growth_exponent"] = json!(a.growth);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }

    let b = &before.comparison;
    println!(
        "{}: {} samples, {:.1} s, {} of {} s; model: {}",
        crate::app::shown(&args.flight),
        data.len(),
        data.duration(),
        count(b.windows.len(), "window"),
        cfg.window_s,
        model_label(&base)
    );
    println!("  {}", noise_text(&prep.measured_noise));
    if let Some((names, f)) = &reference_floor {
        print!(
            "{}",
            crate::analysis::report::reference_floor_text(names, f)
        );
    }
    println!();
    let a = after.as_ref().map(|a| &a.comparison);
    let mut t = match a {
        Some(_) => Table::new(["channel", "error", &format!("→ {label}")]),
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
        if let Some(a) = a {
            row.push(fmt_opt(get(a), unit));
        }
        t.row(row);
    }
    let mut total = vec!["total".to_string(), fixed(b.total, 3)];
    let mut units = vec![format!("× {unit}"), fixed(b.noise_units(), 2)];
    if let Some(a) = a {
        total.push(fixed(a.total, 3));
        units.push(fixed(a.noise_units(), 2));
    }
    t.row(total);
    t.row(units);
    print!("{}", t.render(2));
    if reference_floor.is_some() {
        println!(
            "  floor {} (the total the model leaves on these data when it errs as on the \
             reference flights)",
            fixed(floor, 3)
        );
    } else {
        println!(
            "  noise floor {} (the total a right model leaves on these data)",
            fixed(floor, 3)
        );
    }
    for f in &fitted {
        let params = fmt_params(f);
        if params.is_empty() {
            println!("  added {} (no parameters to fit)", f.effect);
        } else {
            println!("  fitted {}: {params}", f.effect);
        }
    }
    if let Some((t, _)) = &turbulence {
        println!();
        print!("{}", turbulence_text(t));
        println!(
            "    the filter's innovations: {}",
            innovations_text(&t.gusts.gusty)
        );
        if t.significant() {
            println!(
                "    output error's errors above include the gusts' response; the gusts are \
                 estimated on the model as compared, so they include what it lacks: `wireflight \
                 diagnose` fits the causes first"
            );
        }
    }
    println!("\nwhere (predicted − measured, over all windows):");
    print!("{}", axes_text(b, a));

    let title = |what: &str| match &after {
        Some(_) => format!("{what} (model {label}):"),
        None => format!("{what}:"),
    };
    println!("\n{}", title("worst windows"));
    let unit_header = format!("× {unit}");
    let mut t = Table::new(["window", "score", unit_header.as_str(), "dominated by"]);
    for w in last.comparison.worst_windows().iter().take(3) {
        t.row([
            format!("{}–{} s", fixed(w.t0, 1), fixed(w.t1, 1)),
            fixed(w.score, 3),
            fixed((w.chi2 / w.residuals.max(1) as f64).sqrt(), 2),
            w.errors.dominant().to_string(),
        ]);
    }
    print!("{}", t.render(2));
    let final_units = last.comparison.noise_units();
    if at_floor {
        // Near the floor the totals alone cannot tell a right model from one with a small
        // wrong number: the score test of `diagnose` can, at the cost of one flight per
        // number and window.
        let dcfg = DiagnoseConfig {
            compare: cfg,
            ..DiagnoseConfig::default()
        };
        let promising = promising_numbers(final_model, &prep, &dcfg);
        if promising.is_empty() {
            println!(
                "\nthe error is at the {unit} floor ({} × the {unit}), and the score test finds \
                 no number of the aircraft's set that could explain what is left; `wireflight \
                 diagnose` also tries the catalogue's effects",
                fixed(final_units, 2)
            );
        } else {
            let named: Vec<String> = promising
                .iter()
                .take(3)
                .map(|s| format!("{} ({})", s.key.name, s.key.term))
                .collect();
            println!(
                "\nthe error is {} × the {unit}, near the floor, but the score test says {} could \
                 still explain a significant part of it: run `wireflight diagnose` to fit and test",
                fixed(final_units, 2),
                named.join(", ")
            );
        }
        return Ok(());
    }
    println!("\n{}", title("error correlates with"));
    let mut t = Table::new(["condition", "r", ""]);
    for c in last.conditions.iter().take(4) {
        t.row([
            format!("{} ({})", c.name, c.unit),
            c.correlation.map_or("n/a".to_string(), |r| {
                crate::flight::numeric::format::signed(r, 2)
            }),
            c.note.clone().unwrap_or_default(),
        ]);
    }
    print!("{}", t.render(2));
    if last.comparison.windows.len() < 3 {
        println!("  (correlations need at least 3 windows)");
    }
    if let Some(k) = last.growth {
        println!(
            "\nwithin a window, {} (exponent {})",
            explain_growth(k),
            fixed(k, 1)
        );
    }
    Ok(())
}
