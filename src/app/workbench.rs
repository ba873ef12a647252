//! What the workbench's commands share: the reference flights read and checked, a model's
//! forces checked on the flight, `--add` fitted on it, the model written as a model file, and
//! the output names checked before any work is done.

use crate::analysis::compare::Prepared;
use crate::analysis::diagnose::{add_fitted, DiagnoseConfig};
use crate::flight::sensor_errors::SensorErrors;

/// The `--sensor-errors` argument, read (a preset or a file): None when not given.
pub(crate) fn stated_sensor_errors(arg: Option<&str>) -> anyhow::Result<Option<SensorErrors>> {
    arg.map(SensorErrors::from_arg)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--sensor-errors: {e}"))
}

/// The `--reference` flights, read as the test flight is and each checked to be one
/// ([`crate::analysis::reference::check_reference`]): refused with the reason otherwise. The
/// test flight under another name (a spelling, a link, a byte-identical copy) is refused: a
/// flight judged against itself is always normal. A reference given twice is used once,
/// with a note.
pub(crate) fn load_references(
    paths: &[std::path::PathBuf],
    flight: &std::path::Path,
    data: &crate::data::FlightData,
    how: &crate::app::cli::DataArgs,
) -> anyhow::Result<Vec<(String, crate::data::FlightData)>> {
    let one_flight = |a: &std::path::Path, b: &std::path::Path| {
        a == b || crate::fsio::is_same_file(a, b) || crate::fsio::same_contents(a, b)
    };
    let mut taken: Vec<&std::path::Path> = Vec::new();
    let mut out = Vec::new();
    for p in paths {
        if one_flight(p, flight) {
            anyhow::bail!(
                "{}: the test flight cannot be its own reference (it is {}: the same file or a \
                 byte-identical copy)",
                crate::app::shown(p),
                crate::app::shown(flight)
            );
        }
        if let Some(first) = taken.iter().find(|q| one_flight(p, q)) {
            eprintln!(
                "wireflight: note: --reference {} is {} again (the same file or a \
                 byte-identical copy): used once",
                crate::app::shown(p),
                crate::app::shown(first)
            );
            continue;
        }
        taken.push(p);
        let r = crate::app::data::load_flight(p, how)?;
        let name = crate::app::shown(p).to_string();
        crate::analysis::reference::check_reference(data, &r, &name)?;
        out.push((name, r));
    }
    Ok(out)
}

/// The input files of a workbench command, each with its option: the flights, the reference
/// (or held-out) flights, the model file.
pub(crate) fn flight_inputs<'a>(
    flights: &'a [std::path::PathBuf],
    (others_option, others): (&'static str, &'a [std::path::PathBuf]),
    model: Option<&'a std::path::Path>,
) -> Vec<(&'static str, &'a std::path::Path)> {
    flights
        .iter()
        .map(|p| ("--flight", p.as_path()))
        .chain(others.iter().map(|p| (others_option, p.as_path())))
        .chain(model.map(|m| ("--model", m)))
        .collect()
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
