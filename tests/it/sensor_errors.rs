//! `simulate --sensor-errors`: the wandering errors of a real log, each channel at its own
//! rate, written with their truth in the file's metadata. The generator's statistics are
//! measured in `crates/flight/src/sensor_errors/tests.rs`; here, that the file holds exactly
//! what the recorded spec and seed make, at each channel's own samples, over an unchanged
//! white noise, and that bad specs are refused with the file and field named.

use std::path::Path;

use glam::{DQuat, DVec3};
use wireflight::data::{self, Channel, FlightData};
use wireflight::flight::sensor_errors::{SensorErrors, TRUTH_KEY};
use wireflight::geometry::euler::rotation_between;

use crate::support::cli::refused;
use crate::support::flights::Flight;

/// `flight` simulated into `dir/name`, read back.
fn simulate(flight: &Flight, dir: &Path, name: &str) -> FlightData {
    data::read(&flight.write(dir, name)).expect("simulate's CSV reads")
}

/// A minute of the flight test with an accelerometer, seed 5.
fn base() -> Flight {
    Flight::new()
        .quiet()
        .manoeuvre("flight-test")
        .duration(60)
        .noise_acc(0)
        .seed(5)
}

/// The record of the flight's truth, read back.
fn truth(d: &FlightData) -> (SensorErrors, u64) {
    let (_, record) = d
        .meta
        .other
        .iter()
        .find(|(k, _)| k == TRUTH_KEY)
        .expect("a sensor_errors record");
    SensorErrors::from_record(record).expect("the record reads back")
}

#[test]
fn the_file_holds_what_its_recorded_truth_makes_at_each_channels_own_samples() {
    let dir = tempfile::tempdir().unwrap();
    for preset in ["independent", "ekf-gnss"] {
        let exact = simulate(&base(), dir.path(), "exact.csv");
        let logged = simulate(&base().sensor_errors(preset), dir.path(), "logged.csv");
        let (spec, seed) = truth(&logged);
        assert_eq!(spec, SensorErrors::preset(preset).unwrap(), "{preset}");
        assert_eq!(seed, 5);
        // The recorded spec and seed, applied to the flight without them, make the file.
        let mut remade = exact.clone();
        spec.apply(&mut remade, seed);
        let n = logged.len();
        assert_eq!(n, exact.len());
        let s = &logged.sampling;
        for i in s.rows(Channel::Position, n) {
            let e = (logged.pos_ned[i] - remade.pos_ned[i]).length();
            assert!(e < 1e-9, "{preset}: position at row {i} off by {e}");
        }
        let (got, want) = (logged.rates_body.as_ref(), remade.rates_body.as_ref());
        for i in s.rows(Channel::Rates, n) {
            let e = (got.unwrap()[i] - want.unwrap()[i]).length();
            assert!(e < 1e-9, "{preset}: rates at row {i} off by {e}");
        }
        let (got, want) = (logged.attitude.as_ref(), remade.attitude.as_ref());
        for i in s.rows(Channel::Attitude, n) {
            let q = |e: &wireflight::geometry::euler::EulerZyx| DQuat::from_mat3(&e.to_matrix());
            let e = rotation_between(q(&got.unwrap()[i]), q(&want.unwrap()[i]));
            assert!(e < 1e-9, "{preset}: attitude at row {i} off by {e} rad");
        }
        // And they are errors worth the name: decimetres, not nothing.
        let rms = (s
            .rows(Channel::Position, n)
            .map(|i| (logged.pos_ned[i] - exact.pos_ned[i]).length_squared())
            .sum::<f64>()
            / s.count(Channel::Position, n) as f64)
            .sqrt();
        assert!(
            (0.3..3.0).contains(&rms),
            "{preset}: position error {rms} m"
        );
    }
}

#[test]
fn each_channel_is_sampled_at_its_own_rate_and_filled_in_between() {
    let dir = tempfile::tempdir().unwrap();
    // The independent preset logs position at 10 Hz; everything else at the 50 Hz output.
    let d = simulate(&base().sensor_errors("independent"), dir.path(), "i.csv");
    let n = d.len();
    let s = &d.sampling;
    assert_eq!(n, 3001);
    assert_eq!(s.count(Channel::Position, n), 601);
    assert!((s.rate_hz(Channel::Position, &d.time).unwrap() - 10.0).abs() < 1e-9);
    assert!(s.rows(Channel::Position, n).all(|i| i % 5 == 0));
    for c in [Channel::Attitude, Channel::Rates, Channel::Airspeed] {
        assert!(s.is_complete(c), "{c}");
    }
    // Between two samples the position is the straight line between them: filled in, not
    // measured (the file leaves those cells empty).
    let mid = d.pos_ned[7];
    let line = d.pos_ned[5].lerp(d.pos_ned[10], 0.4);
    assert!((mid - line).length() < 1e-9, "{mid} vs {line}");

    // Navigation at 5 Hz, attitude at 50 Hz, rates at 250 Hz: a real log's shape.
    let spec = dir.path().join("rates.toml");
    std::fs::write(
        &spec,
        "model = \"independent\"\n[position]\nrate_hz = 5\n[velocity]\nrate_hz = 5\n\
         [attitude]\nrate_hz = 50\n[rates]\nrate_hz = 250\n",
    )
    .unwrap();
    let flight = Flight::new()
        .quiet()
        .manoeuvre("flight-test")
        .duration(4)
        .rate(250)
        .sensor_errors(spec.display());
    let d = simulate(&flight, dir.path(), "m.csv");
    let n = d.len();
    let own = |c: Channel| d.sampling.count(c, n);
    assert_eq!(n, 1001);
    assert_eq!(
        [
            own(Channel::Position),
            own(Channel::Velocity),
            own(Channel::Attitude),
            own(Channel::Rates)
        ],
        [21, 21, 201, 1001]
    );
}

#[test]
fn the_white_noise_is_the_same_with_the_errors_or_without() {
    let dir = tempfile::tempdir().unwrap();
    let noisy = |f: Flight| f.noise_pos(0.3).noise_rate(0.1);
    let plain = simulate(&base(), dir.path(), "a.csv");
    let white = simulate(&noisy(base()), dir.path(), "b.csv");
    let wander = simulate(&base().sensor_errors("ekf-gnss"), dir.path(), "c.csv");
    let both = simulate(
        &noisy(base().sensor_errors("ekf-gnss")),
        dir.path(),
        "d.csv",
    );
    for i in (0..plain.len()).step_by(97) {
        let noise = white.pos_ned[i] - plain.pos_ned[i];
        let on_top = both.pos_ned[i] - wander.pos_ned[i];
        assert!(
            (noise - on_top).length() < 1e-9,
            "row {i}: {noise} vs {on_top}"
        );
        let r = |d: &FlightData| d.rates_body.as_ref().unwrap()[i];
        let (noise, on_top) = (r(&white) - r(&plain), r(&both) - r(&wander));
        assert!((noise - on_top).length() < 1e-12, "row {i}");
        assert!(noise != DVec3::ZERO);
    }
}

#[test]
fn bad_sensor_error_specs_are_refused_with_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    let run = |arg: &str, extra: &[&str]| {
        let mut args = base().sensor_errors(arg).extra(extra).args(&out);
        args.retain(|a| a != "-q");
        refused(&args)
    };
    let e = run("nope", &[]);
    assert!(
        e.contains("`nope`") && e.contains("independent, ekf-gnss"),
        "{e}"
    );
    let toml = dir.path().join("typo.toml");
    std::fs::write(
        &toml,
        "model = \"independent\"\n[position]\nnorht = { size = 1 }\n",
    )
    .unwrap();
    let e = run(toml.to_str().unwrap(), &[]);
    assert!(
        e.contains("typo.toml") && e.contains("position.norht"),
        "{e}"
    );
    std::fs::write(
        &toml,
        "model = \"independent\"\n[position]\nnorth = { size = -1 }\n",
    )
    .unwrap();
    let e = run(toml.to_str().unwrap(), &[]);
    assert!(e.contains("position.north.size"), "{e}");
    // A channel's rate must divide the output rate: its samples are output samples.
    let e = run("independent", &["--rate", "25"]);
    assert!(
        e.contains("position at 10 Hz: --rate 25 Hz is not a whole multiple of it"),
        "{e}"
    );
    assert!(!out.exists(), "nothing written");
}

/// Position at 5 Hz on a 50 Hz flight, as a log holds GNSS: its noise read from its own
/// samples, and a right model's error in units of that noise about 1 — where the same
/// numbers taken as 50 Hz measurements (interpolated between the fixes, as a resampling
/// importer makes them) read as almost noise-free and the model as far off. (Measured:
/// 0.489 m of the 0.5 m noise, 0.99 × the noise; between the fixes 0 m and 174 ×.)
#[test]
fn a_slow_channel_is_weighed_at_its_own_samples_not_between_them() {
    use wireflight::analysis::compare::{compare, estimate_noise, CompareConfig};
    use wireflight::data::{Sampling, VehicleKind};
    use wireflight::flight::autopilot::Manoeuvre;
    use wireflight::flight::effects::Origin;
    use wireflight::flight::simulate::{simulate, Noise, SimSpec};
    use wireflight::flight::spec::ModelSpec;

    let model = ModelSpec::baseline(VehicleKind::FixedWing)
        .build(Origin::default())
        .unwrap();
    let spec = SimSpec {
        noise: Noise {
            pos_m: 0.5,
            att_deg: 0.1,
            vel_mps: 0.05,
            rate_dps: 0.1,
        },
        seed: 11,
        ..SimSpec::new(Manoeuvre::FlightTest, 60.0)
    };
    let mut gnss = simulate(&model, &spec).unwrap();
    let fixes: Vec<bool> = (0..gnss.len()).map(|i| i % 10 == 0).collect();
    gnss.keep_samples(Channel::Position, &fixes);
    let mut resampled = gnss.clone();
    resampled.sampling = Sampling::all();

    let own = estimate_noise(&gnss).pos_m;
    let between = estimate_noise(&resampled).pos_m;
    assert!(
        (own / 0.5 - 1.0).abs() < 0.1,
        "read from its samples: {own} m"
    );
    assert!(between < 0.05, "read between them: {between} m");

    let cfg = CompareConfig::default();
    let right = compare(&model, &gnss, cfg);
    assert!(
        (0.85..1.2).contains(&right.noise_units()),
        "a right model: {} × the noise",
        right.noise_units()
    );
    // Only the fixes count: a tenth of the position rows.
    let full = compare(&model, &simulate(&model, &spec).unwrap(), cfg);
    let dropped = full.dof - right.dof;
    let position_rows: usize = full.windows.iter().map(|w| w.samples.1 - w.samples.0).sum();
    let expected = 3.0 * (position_rows - position_rows.div_ceil(10)) as f64;
    assert!(
        (dropped - expected).abs() <= 3.0 * full.windows.len() as f64,
        "{dropped} rows dropped, {expected} expected"
    );
    let wrong = compare(&model, &resampled, cfg).noise_units();
    assert!(wrong > 3.0, "between the fixes: {wrong} × the noise");
    eprintln!(
        "position noise {own:.3} m at its fixes, {between:.4} m between; a right model \
         {:.2} × the noise, {wrong:.1} × read between the fixes",
        right.noise_units()
    );
}
