//! What is wrong with the sensors, not the airplane: refsim's flights (an independent
//! implementation of the model), read by imperfect instruments made here — a navigation
//! solution that arrives late, biased gyros, a mis-scaled airspeed sensor — and then noised.
//! The diagnosis names the measurement effect, alone or together with a physical cause, with
//! the truth inside its tolerance; clean instruments give `none`.

use glam::DVec3;

use wireflight::analysis::diagnose::{diagnose, Candidate, DiagnoseConfig, Diagnosis, Verdict};
use wireflight::data::{self, FlightData};
use wireflight::flight::model::Model;
use wireflight::flight::spec::ModelChoice;

use crate::support::refsim::{self, Effects, FlightOptions, Noise, Rng, Schedule};

/// Instruments (1σ): position 0.3 m, attitude 0.2°, velocity 0.1 m/s, rates 0.3°/s,
/// airspeed 0.1 m/s — a small autopilot's.
const NOISE: [f64; 5] = [0.3, 0.2, 0.1, 0.3, 0.1];

/// A 60 s refsim flight test at 50 Hz with `effects`, exact (noise is added after the
/// sensors have read it).
fn truth(effects: Effects) -> FlightData {
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.effects = effects;
    o.noise = Noise::new(0.0, 0.0, 0.0, 0.0, 0.0);
    let csv = refsim::flight_csv(&o).expect("refsim flies");
    data::parse(&csv, "refsim.csv").expect("refsim's CSV reads")
}

/// The same flight with position and NED velocity read `delay` s late: each sample takes the
/// truth at t − delay, interpolated linearly between the samples around it; samples before
/// the first delay are dropped (nothing was measured then).
fn delayed(d: &FlightData, delay: f64) -> FlightData {
    let vel = d.vel_ned.as_ref().expect("refsim writes the NED velocity");
    let at = |series: &[DVec3], t: f64| {
        let j = d.time.partition_point(|&s| s <= t).saturating_sub(1);
        let j = j.min(d.time.len() - 2);
        let w = (t - d.time[j]) / (d.time[j + 1] - d.time[j]);
        series[j] * (1.0 - w) + series[j + 1] * w
    };
    let first = d.time.partition_point(|&t| t < d.time[0] + delay);
    let mut out = d.clone();
    let keep = first..d.len();
    out.time = d.time[keep.clone()].to_vec();
    out.pos_ned = keep
        .clone()
        .map(|i| at(&d.pos_ned, d.time[i] - delay))
        .collect();
    out.vel_ned = Some(keep.clone().map(|i| at(vel, d.time[i] - delay)).collect());
    let cut = |v: &Option<Vec<_>>| v.as_ref().map(|v: &Vec<_>| v[keep.clone()].to_vec());
    out.attitude = d.attitude.as_ref().map(|v| v[keep.clone()].to_vec());
    out.rates_body = cut(&d.rates_body);
    out.vel_body = cut(&d.vel_body);
    out.airspeed = d.airspeed.as_ref().map(|v| v[keep.clone()].to_vec());
    out.controls = d.controls.as_ref().map(|v| v[keep.clone()].to_vec());
    out.validate().expect("a delayed flight is a flight");
    out
}

/// Gaussian noise of [`NOISE`] on every measured channel, seeded.
fn noised(mut d: FlightData, seed: u64) -> FlightData {
    let mut rng = Rng::new(seed);
    let [pos, att, vel, rate, air] = NOISE;
    let mut vec3 = |v: &mut DVec3, s: f64| {
        *v += DVec3::new(rng.normal(), rng.normal(), rng.normal()) * s;
    };
    for p in &mut d.pos_ned {
        vec3(p, pos);
    }
    for v in d.vel_ned.iter_mut().flatten() {
        vec3(v, vel);
    }
    for w in d.rates_body.iter_mut().flatten() {
        vec3(w, rate.to_radians());
    }
    for a in d.attitude.iter_mut().flatten() {
        let mut e = DVec3::ZERO;
        vec3(&mut e, att.to_radians());
        a.roll += e.x;
        a.pitch += e.y;
        a.yaw += e.z;
    }
    let mut rng = Rng::new(seed ^ 0xA5A5);
    for s in d.airspeed.iter_mut().flatten() {
        *s += air * rng.normal();
    }
    d
}

fn baseline(d: &FlightData) -> Model {
    ModelChoice::default()
        .build(std::path::Path::new("refsim.csv"), d)
        .expect("model")
}

fn run(d: &FlightData) -> Diagnosis {
    diagnose(&baseline(d), d, &[], &DiagnoseConfig::default()).expect("diagnose")
}

fn found<'a>(d: &'a Diagnosis, name: &str) -> &'a Candidate {
    d.found
        .iter()
        .find(|c| c.effect == name)
        .unwrap_or_else(|| panic!("`{name}` not found: {:?} {:?}", d.verdict, d.found))
}

fn value(c: &Candidate, param: &str) -> f64 {
    c.params
        .iter()
        .find(|(k, _)| k == param)
        .map(|(_, v)| *v)
        .unwrap_or_else(|| panic!("{} has no {param}: {:?}", c.effect, c.params))
}

fn names(d: &Diagnosis) -> Vec<&str> {
    d.found.iter().map(|c| c.effect.as_str()).collect()
}

/// Position and velocity 0.25 s late: `nav_delay`, within 0.02 s.
#[test]
fn a_late_navigation_solution_is_named_with_its_delay() {
    let d = noised(delayed(&truth(Effects::default()), 0.25), 11);
    let diag = run(&d);
    assert_eq!(
        diag.verdict,
        Verdict::Found(vec!["nav_delay".into()]),
        "{diag:?}"
    );
    let delay = value(found(&diag, "nav_delay"), "delay_s");
    assert!((delay - 0.25).abs() < 0.02, "delay {delay}");
}

/// Gyro biases of (−0.3, 0.6, −0.2) °/s under 0.3 °/s of noise: `gyro_bias`, each axis
/// within 0.05 °/s.
#[test]
fn biased_gyros_are_named_with_their_biases() {
    let mut d = truth(Effects::default());
    let bias = DVec3::new(-0.3, 0.6, -0.2);
    for w in d.rates_body.iter_mut().flatten() {
        *w += bias * std::f64::consts::PI / 180.0;
    }
    let diag = run(&noised(d, 12));
    assert_eq!(
        diag.verdict,
        Verdict::Found(vec!["gyro_bias".into()]),
        "{diag:?}"
    );
    let c = found(&diag, "gyro_bias");
    for (axis, truth) in ["p_dps", "q_dps", "r_dps"].iter().zip(bias.to_array()) {
        let v = value(c, axis);
        assert!((v - truth).abs() < 0.05, "{axis}: {v} vs {truth}");
    }
}

/// An airspeed sensor reading 7% low: `airspeed_scale`, within 1%.
#[test]
fn a_mis_scaled_airspeed_sensor_is_named_with_its_factor() {
    let mut d = truth(Effects::default());
    for s in d.airspeed.iter_mut().flatten() {
        *s *= 0.93;
    }
    let diag = run(&noised(d, 13));
    assert_eq!(
        diag.verdict,
        Verdict::Found(vec!["airspeed_scale".into()]),
        "{diag:?}"
    );
    let f = value(found(&diag, "airspeed_scale"), "factor");
    assert!((f - 0.93).abs() < 0.0093, "factor {f}");
}

/// A sensor effect together with a physical one: the navigation solution 0.2 s late in a
/// steady wind of (3, −2, 0) m/s. Both are named, fitted together, and nothing else.
#[test]
fn a_late_navigation_solution_and_a_wind_are_named_together() {
    let effects = Effects {
        wind: Some([3.0, -2.0, 0.0]),
        ..Effects::default()
    };
    let d = noised(delayed(&truth(effects), 0.2), 14);
    let diag = run(&d);
    let mut got = names(&diag);
    got.sort_unstable();
    assert_eq!(got, ["nav_delay", "wind"], "{diag:?}");
    assert!(matches!(diag.verdict, Verdict::Found(_)), "{diag:?}");
    let delay = value(found(&diag, "nav_delay"), "delay_s");
    assert!((delay - 0.2).abs() < 0.02, "delay {delay}");
    let wind = found(&diag, "wind");
    for (axis, truth) in [("north_mps", 3.0), ("east_mps", -2.0)] {
        let v = value(wind, axis);
        assert!((v - truth).abs() < 0.15, "{axis}: {v} vs {truth}");
    }
}

/// Clean instruments: `none`, and no measurement effect is kept.
#[test]
fn clean_instruments_give_none() {
    let diag = run(&noised(truth(Effects::default()), 15));
    assert_eq!(diag.verdict, Verdict::None, "{diag:?}");
}

/// A gyro bias cannot show in rates the data do not measure (here: none at all), so it is no
/// candidate there; nor is an airspeed sensor's error without an airspeed.
#[test]
fn a_sensor_effect_is_a_candidate_only_where_its_channel_is_measured() {
    let mut d = noised(truth(Effects::default()), 16);
    d.rates_body = None;
    d.airspeed = None;
    let diag = run(&d);
    let tried: Vec<&str> = diag.ranking.iter().map(|c| c.effect.as_str()).collect();
    for absent in ["gyro_bias", "airspeed_scale", "airspeed_bias", "accel_bias"] {
        assert!(!tried.contains(&absent), "{absent} tried: {tried:?}");
    }
    for present in ["nav_delay", "attitude_offset"] {
        assert!(tried.contains(&present), "{present} not tried: {tried:?}");
    }
}

/// A flight `simulate` records with an accelerometer of 0.05 m/s² noise (and the truth's
/// measurement effects, `hidden`), the rest as [`NOISE`].
fn with_accelerometer(hidden: &[&str], seed: u64) -> FlightData {
    use wireflight::flight::autopilot::Manoeuvre;
    use wireflight::flight::effects::Origin;
    use wireflight::flight::simulate::{simulate, Noise as SimNoise, SimSpec};
    use wireflight::flight::spec::{EffectSpec, ModelSpec};
    let mut spec = ModelSpec::baseline(wireflight::data::VehicleKind::FixedWing);
    for h in hidden {
        spec.effects.push(EffectSpec::parse(h).unwrap());
    }
    let truth = spec.build(Origin::default()).unwrap();
    let [pos, att, vel, rate, _] = NOISE;
    let sim = SimSpec {
        noise: SimNoise {
            pos_m: pos,
            att_deg: att,
            vel_mps: vel,
            rate_dps: rate,
        },
        accelerometer: Some(0.05),
        seed,
        ..SimSpec::new(Manoeuvre::FlightTest, 60.0)
    };
    simulate(&truth, &sim).expect("simulate")
}

/// Clean instruments with an accelerometer: `none`, and each accelerometer axis's noise
/// measured within 20% of the truth (0.05 m/s²).
#[test]
fn a_clean_accelerometer_gives_none_and_its_noise() {
    let d = with_accelerometer(&[], 21);
    let diag = run(&d);
    assert_eq!(diag.verdict, Verdict::None, "{diag:?}");
    for (axis, sigma) in diag.base_noise.accel_axes.iter().enumerate() {
        assert!((sigma / 0.05 - 1.0).abs() < 0.2, "axis {axis}: {sigma}");
    }
}

/// An accelerometer biased by (0.1, 0, −0.15) m/s²: `accel_bias`, each axis within
/// 0.01 m/s².
#[test]
fn a_biased_accelerometer_is_named_with_its_bias() {
    let d = with_accelerometer(&["accel_bias:x_mps2=0.1,z_mps2=-0.15"], 22);
    let diag = run(&d);
    assert_eq!(
        diag.verdict,
        Verdict::Found(vec!["accel_bias".into()]),
        "{diag:?}"
    );
    let c = found(&diag, "accel_bias");
    for (axis, truth) in [("x_mps2", 0.1), ("y_mps2", 0.0), ("z_mps2", -0.15)] {
        let v = value(c, axis);
        assert!((v - truth).abs() < 0.01, "{axis}: {v} vs {truth}");
    }
}
