//! `wireflight simulate`: generate a flight (CSV) with a model, optionally with hidden effects.

use anyhow::Context;

use crate::app::cli::SimulateArgs;
use crate::data;
use crate::data::VehicleKind;
use crate::flight::autopilot::Manoeuvre;
use crate::flight::effects::Origin;
use crate::flight::sensor_errors::SensorErrors;
use crate::flight::simulate::{simulate_bounded, Noise, SimSpec};
use crate::flight::spec::{EffectSpec, ModelSpec};
use crate::flight::turbulence::Turbulence;

/// Run `wireflight simulate`.
///
/// # Errors
/// Bad model or effect specs, a manoeuvre for the other vehicle, no trim, divergence, write
/// errors.
pub fn run(args: &SimulateArgs) -> anyhow::Result<()> {
    let mut inputs: Vec<(&str, &std::path::Path)> = Vec::new();
    if let Some(m) = &args.model {
        inputs.push(("--model", m));
    }
    for (option, arg) in [
        ("--aircraft", Some(&args.aircraft)),
        ("--sensor-errors", args.sensor_errors.as_ref()),
    ] {
        if let Some(a) = arg {
            inputs.push((option, std::path::Path::new(a.as_str())));
        }
    }
    crate::app::outputs::check_outputs(&inputs, &[("--out", &args.out)], &[])?;
    let (spec, truth) = model_specs(args)?;
    let listed: Vec<String> = spec.effects.iter().map(EffectSpec::to_arg).collect();
    let origin = Origin {
        latitude_deg: args.latitude,
        longitude_deg: args.longitude,
        altitude_m: args.altitude,
    };
    let model = truth.build(origin).context("building the model")?;
    let manoeuvre: Manoeuvre = match &args.manoeuvre {
        Some(m) => m.parse()?,
        None if spec.vehicle == VehicleKind::PointMass => Manoeuvre::Ballistic,
        None => Manoeuvre::Level,
    };
    let sim = sim_spec(args, &spec, manoeuvre, &listed)?;
    let progress = crate::draw::progress::Progress::spinner(
        &format!("simulating {:.0} s of flight", args.duration),
        false,
    );
    // --max-samples permits a length; what the machine can hold bounds it too (a run that
    // would not fit is refused before any work instead of aborting on allocation).
    let max_bytes = crate::fsio::available_memory().map_or(u64::MAX, |free| free / 10 * 9);
    let flight = simulate_bounded(&model, &sim, args.max_samples, max_bytes)?;
    drop(progress);
    if flight.duration() + 0.5 / args.rate < args.duration && manoeuvre != Manoeuvre::Ballistic {
        eprintln!(
            "wireflight: note: the aircraft reached the ground (the origin's altitude, {} m) at \
             t = {:.2} s; the flight ends there",
            args.altitude,
            flight.duration()
        );
    }
    data::write(&args.out, &flight)?;
    println!("{}", summary(args, &spec, manoeuvre, &listed, &flight));
    Ok(())
}

/// The model the file names (`--model` or the baseline, with `--effects` and `--add`), and
/// the truth flown: that model with the `--hidden` effects too.
fn model_specs(args: &SimulateArgs) -> anyhow::Result<(ModelSpec, ModelSpec)> {
    let mut spec = match &args.model {
        Some(path) => ModelSpec::load(path)?,
        None => {
            let mut s = ModelSpec::baseline(args.vehicle);
            s.aircraft = args.aircraft.clone();
            s
        }
    };
    if let Some(list) = &args.effects {
        spec.add_effect_list(list)?;
    }
    for add in &args.add {
        spec.effects.push(EffectSpec::parse(add)?);
    }
    let mut truth = spec.clone();
    for hidden in &args.hidden {
        truth.effects.push(EffectSpec::parse(hidden)?);
    }
    Ok((spec, truth))
}

/// The flight to simulate: the manoeuvre, its length and rate, the sensors' noise, the
/// turbulence, and what the file's header says of them.
///
/// # Errors
/// A `--sensor-errors` that is neither a preset nor a readable, valid TOML file.
fn sim_spec(
    args: &SimulateArgs,
    spec: &ModelSpec,
    manoeuvre: Manoeuvre,
    listed: &[String],
) -> anyhow::Result<SimSpec> {
    let sensor_errors = args
        .sensor_errors
        .as_deref()
        .map(SensorErrors::from_arg)
        .transpose()?;
    Ok(SimSpec {
        manoeuvre,
        duration_s: args.duration,
        rate_hz: args.rate,
        airspeed_mps: args.airspeed,
        launch_speed_mps: args.launch_speed,
        height_m: args.height,
        noise: Noise {
            pos_m: args.noise_pos,
            att_deg: args.noise_att,
            vel_mps: args.noise_vel,
            rate_dps: args.noise_rate,
        },
        accelerometer: args.noise_acc,
        seed: args.seed,
        source: format!(
            "wireflight simulate --manoeuvre {manoeuvre} --seed {}{}",
            args.seed,
            args.turbulence.map_or(String::new(), |level| format!(
                " --turbulence {level} --turbulence-seed {}",
                args.turbulence_seed
            ))
        ),
        aircraft: (spec.vehicle == VehicleKind::FixedWing).then(|| spec.aircraft.clone()),
        listed_effects: listed.to_vec(),
        turbulence: args.turbulence.map(|level| Turbulence {
            level,
            seed: args.turbulence_seed,
        }),
        sensor_errors,
    })
}

/// The line that says what was written.
fn summary(
    args: &SimulateArgs,
    spec: &ModelSpec,
    manoeuvre: Manoeuvre,
    listed: &[String],
    flight: &data::FlightData,
) -> String {
    format!(
        "wrote {}: {} samples over {:.1} s at {} Hz, {} {} ({}), effects: {}{}{}{}",
        crate::app::shown(&args.out),
        flight.len(),
        flight.duration(),
        args.rate,
        spec.vehicle,
        manoeuvre,
        if spec.vehicle == VehicleKind::FixedWing {
            spec.aircraft.as_str()
        } else {
            "point mass"
        },
        if listed.is_empty() {
            "none".to_string()
        } else {
            listed.join(" ")
        },
        if args.hidden.is_empty() {
            String::new()
        } else {
            format!(" (+{} hidden, not in the file)", args.hidden.len())
        },
        args.turbulence.map_or(String::new(), |level| format!(
            ", {level} turbulence (seed {})",
            args.turbulence_seed
        )),
        args.sensor_errors
            .as_ref()
            .map_or(String::new(), |e| format!(", sensor errors {e}"))
    )
}
