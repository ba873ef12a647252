//! `wireflight compare`: where and how a flight model fails against measured data, before
//! and after adding effects. The assessment is the analysis crate's
//! ([`crate::analysis::assess`]); this module reads the inputs, writes the outputs and prints.

use std::path::Path;

use crate::analysis::assess::{assess, AssessError, Assessment, Request};
use crate::analysis::report::{assessment_json, assessment_text, model_label, Names};
use crate::app::cli::CompareArgs;
use crate::app::shown;
use crate::app::workbench::{
    check_forces_finite, check_report, load_references, model_toml, stated_sensor_errors,
};
use crate::data::FlightData;
use crate::draw::output::{write_frames, FrameOut};
use crate::draw::render::Rasterizer;
use crate::draw::scene::replay::ReplayScene;
use crate::geometry::clip::Clipper;
use crate::present::track::model_track;

/// Run `wireflight compare`.
///
/// # Errors
/// Bad data or model, bad effects, plot or output errors.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let (gif_out, model_out) = outputs(args)?;
    let inputs = crate::app::workbench::flight_inputs(
        std::slice::from_ref(&args.flight),
        ("--reference", &args.reference),
        args.model.model.as_deref(),
    );
    use crate::app::outputs::{check_outputs, given};
    check_outputs(
        &inputs,
        &given(&[
            ("--out", args.out.as_deref()),
            ("--report", args.report.as_deref()),
        ]),
        &given(&[
            ("--plots", args.plots.as_deref()),
            ("--frames-dir", args.frames_dir.as_deref()),
        ]),
    )?;
    let data = crate::app::data::load_flight(&args.flight, &args.data)?;
    let references = load_references(&args.reference, &args.flight, &data, &args.data)?;
    // A model also flown on the references must not read the test flight's record there.
    let base = if references.is_empty() {
        args.model.choice().build(&args.flight, &data)?
    } else {
        args.model.choice().build_unrecorded(&args.flight, &data)?
    };
    let add = args.model.add_specs()?;
    check_forces_finite(&base, &add, &[], &args.flight, &data)?;
    let compare = args.windows.config(base.vehicle.kind());
    args.windows.check_fits(&args.flight, &data, &compare)?;
    let named: Vec<(&str, &FlightData)> = references.iter().map(|(n, d)| (n.as_str(), d)).collect();
    let errors = stated_sensor_errors(args.sensor_errors.as_deref())?;
    let progress = crate::draw::progress::Progress::spinner(
        &format!("comparing over {:.0} s of data", data.duration()),
        args.json,
    );
    let request = Request {
        model: &base,
        data: &data,
        references: &named,
        errors: errors.as_ref(),
        add: &add,
        compare,
        method: args.method.into(),
    };
    let a = assess(&request).map_err(|e| match e {
        AssessError::Reference(_) => anyhow::Error::new(e),
        AssessError::Add(_) => anyhow::anyhow!("{}: {e}", shown(&args.flight)),
        _ => anyhow::anyhow!("{}: {e}", args.flight.display()),
    })?;
    drop(progress);
    let added = format!("+ {}", args.model.add.join(" + "));
    write_outputs(args, &data, &a, &added, gif_out, model_out)?;
    if args.json {
        let v = assessment_json(&a, &args.flight.display().to_string());
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let names = Names {
            flight: &shown(&args.flight),
            samples: data.len(),
            own_rates: !data.sampling.is_all(),
            duration_s: data.duration(),
            added: &added,
        };
        print!("{}", assessment_text(&a, &names));
    }
    Ok(())
}

/// `--out` by its extension (a .gif the replay, a .toml the model with the `--add` effects),
/// and `--report`'s name, checked before any work.
fn outputs(args: &CompareArgs) -> anyhow::Result<(Option<&Path>, Option<&Path>)> {
    let ext = |p: &Path, e: &str| p.extension().is_some_and(|x| x.eq_ignore_ascii_case(e));
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
        check_report(report)?;
    }
    Ok((gif_out, model_out))
}

/// The plots, replay frames, model file and report page asked for, each named as written.
fn write_outputs(
    args: &CompareArgs,
    data: &FlightData,
    a: &Assessment,
    added: &str,
    gif_out: Option<&Path>,
    model_out: Option<&Path>,
) -> anyhow::Result<()> {
    // Each output is named as soon as it is written (a later one may still fail).
    let say = |line: String| {
        if !args.json {
            println!("{line}");
        }
    };
    if let Some(dir) = &args.plots {
        for f in write_plots(args, dir, data, a, added)? {
            say(format!("plot: {}", shown(&f)));
        }
    }
    let frame_outs = [
        args.frames_dir.as_deref().map(FrameOut::Pngs),
        gif_out.map(FrameOut::Gif),
    ];
    for out in frame_outs.into_iter().flatten() {
        say(write_replay(args, data, a, out)?);
    }
    if let Some(out) = model_out {
        write_model(args, data, a, added, out)?;
        say(format!("wrote {}", shown(out)));
    }
    if let Some(path) = &args.report {
        write_report(args, data, a, added, path)?;
        say(format!("wrote {}", shown(path)));
    }
    Ok(())
}

/// `--plots DIR`: the error over time before and after, and against the condition the text
/// names first.
fn write_plots(
    args: &CompareArgs,
    dir: &Path,
    data: &FlightData,
    a: &Assessment,
    added: &str,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    let series = a
        .quoted()
        .conditions
        .first()
        .map(|c| crate::present::plots::ConditionSeries {
            name: c.name.to_string(),
            unit: c.unit.to_string(),
            per_window: c.per_window.clone(),
        });
    let info = crate::present::plots::PlotInfo {
        data_name: Some(args.flight.display().to_string()),
        model_name: Some(model_label(&a.base)),
        noise_floor: Some(a.floor),
        window_s: Some(a.config.window_s),
    };
    Ok(crate::present::plots::write_plots_with(
        dir,
        data,
        &a.before.comparison,
        a.after.as_ref().map(|f| (&f.comparison, added)),
        series.as_ref(),
        &info,
    )?)
}

/// `--frames-dir` or `--out X.gif`: the replay with the model's track, and its line.
fn write_replay(
    args: &CompareArgs,
    data: &FlightData,
    a: &Assessment,
    out: FrameOut,
) -> anyhow::Result<String> {
    let mut track = model_track(data, &a.last().comparison)?;
    // One scale for before and after, so the strip shows the error fall.
    let b = &a.before.comparison.prediction;
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
    let mut replay = ReplayScene::new(data, &mesh, Clipper::Blinn)?.with_model(track);
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
    let (what, to) = match out {
        FrameOut::Pngs(dir) => ("overlay frames", dir),
        FrameOut::Gif(gif) => ("GIF frames", gif),
    };
    Ok(format!(
        "wrote {} {what} to {} (measured: green, model {}: magenta)",
        w.frames,
        shown(to),
        model_label(&a.final_model)
    ))
}

/// `--out X.toml`: the model with the added effects, with the filter's values where it ran.
fn write_model(
    args: &CompareArgs,
    data: &FlightData,
    a: &Assessment,
    added: &str,
    out: &Path,
) -> anyhow::Result<()> {
    let comment = format!(
        "The model of `wireflight compare --flight {}`{}.",
        args.flight.display(),
        match (&a.turbulence, a.fitted.is_empty()) {
            (_, true) => String::new(),
            (Some(_), false) => format!(" with {added}, fitted through the filter-error method"),
            (None, false) => format!(" with {added}, fitted"),
        }
    );
    let text = model_toml(
        a.kept_model(),
        &args.model.choice(),
        &args.flight,
        data,
        &comment,
    )?;
    crate::fsio::write_atomic(out, text.as_bytes())?;
    Ok(())
}

/// `--report PAGE`: the evidence as one HTML page.
fn write_report(
    args: &CompareArgs,
    data: &FlightData,
    a: &Assessment,
    added: &str,
    path: &Path,
) -> anyhow::Result<()> {
    let report = crate::present::report::Report {
        command: format!("wireflight compare --flight {}", args.flight.display()),
        data_name: args.flight.display().to_string(),
        data,
        model_name: model_label(&a.base),
        before: &a.before.comparison,
        after: a.after.as_ref().map(|f| (&f.comparison, added.to_string())),
        noise: &a.noise,
        noise_floor: a.floor,
        window_s: a.config.window_s,
        conditions: &a.quoted().conditions,
        diagnosis: None,
        fitted: &a.fitted,
        replay: Some(crate::present::report::ReplaySize::default()),
        at_floor: a.error_floor.as_ref().map_or(
            crate::analysis::diagnose::DiagnoseConfig::default().at_floor,
            |f| f.at_floor,
        ),
        unit: a.unit(),
        turbulence: a.turbulence.as_ref().map(|(t, _)| t),
    };
    crate::present::report::write_report(path, &report)?;
    Ok(())
}
