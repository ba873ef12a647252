//! Terms in the window's compare panel without a window: `discover` run from the panel's
//! state on a flight whose truth has a pitching moment ∝ the thrust (a thrust line 4 cm above
//! the centre of gravity) that neither the catalogue nor the parameter set has; the term it
//! finds becomes a checkbox row with its reading and estimate, the panel draws it (egui
//! without a window), and ticking it brings the flight's error to the noise.

use std::sync::Arc;

use wireflight::analysis::compare::CompareConfig;
use wireflight::app::view::cameras::CameraMode;
use wireflight::app::view::compare::Compare;
use wireflight::app::view::compare_panel_texts;
use wireflight::app::view::discovery::Discovering;
use wireflight::app::view::session::Session;
use wireflight::data::FlightData;
use wireflight::data::VehicleKind;
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::term::term_of;
use wireflight::flight::effects::Origin;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelChoice, ModelSpec};
use wireflight::geometry::mesh::plane::builtin_plane;

/// The truth's coefficient: N·m of pitching moment per N of thrust.
const TRUE_K: f64 = -0.04;

/// `simulate --manoeuvre flight-test --duration 60 --hidden 'term(m=k*thrust):k=-0.04'
/// --noise-pos 0.3 --noise-att 0.2 --noise-vel 0.1 --noise-rate 0.3 --seed 5`, the flight of
/// docs/discover.md, made through the library and read back from its CSV as `view` reads it
/// (the body velocity and rates derived where the file lacks them).
fn thrust_line_flight() -> FlightData {
    let mut truth = ModelSpec::baseline(VehicleKind::FixedWing);
    truth
        .effects
        .push(EffectSpec::parse(&format!("term(m=k*thrust):k={TRUE_K}")).unwrap());
    let spec = SimSpec {
        manoeuvre: Manoeuvre::FlightTest,
        duration_s: 60.0,
        rate_hz: 50.0,
        airspeed_mps: 25.0,
        launch_speed_mps: 150.0,
        height_m: 200.0,
        noise: Noise {
            pos_m: 0.3,
            att_deg: 0.2,
            vel_mps: 0.1,
            rate_dps: 0.3,
        },
        accelerometer: None,
        seed: 5,
        source: "tests/terms_window.rs".into(),
        aircraft: Some("aerosonde".into()),
        listed_effects: Vec::new(),
        turbulence: None,
        sensor_errors: None,
    };
    let data = simulate(&truth.build(Origin::default()).unwrap(), &spec).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("thrust-line.csv");
    wireflight::data::write(&path, &data).unwrap();
    wireflight::data::read(&path).unwrap()
}

#[test]
fn a_discovered_term_is_a_row_and_ticking_it_brings_the_error_to_the_noise() {
    let data = thrust_line_flight();
    let base = ModelChoice::default()
        .build(std::path::Path::new("thrust-line.csv"), &data)
        .unwrap();
    let cfg = CompareConfig {
        window_s: CompareConfig::default_window_s(VehicleKind::FixedWing),
        ..CompareConfig::default()
    };
    let mut c = Compare::with_config(Arc::new(data), base, &[], cfg, false).unwrap();
    assert!(matches!(c.discovery, Discovering::Off));
    let rows_before = c.rows.len();
    let before = c.before.noise_units;
    assert!(
        before > 2.0,
        "the model without the term: {before} × the noise"
    );

    assert!(c.start_discover());
    assert!(c.busy() && c.discovering());
    assert!(!c.start_discover(), "one discovery at a time");
    assert!(c.discovery.line().starts_with("discovering…"));
    c.wait_discover();
    assert!(!c.busy());
    let line = c.discovery.line();
    assert!(
        matches!(c.discovery, Discovering::Done { rows, .. } if rows >= 1),
        "{line}"
    );
    let names: Vec<&str> = c.rows.iter().map(|r| r.name).collect();
    let i = c
        .rows
        .iter()
        .position(|r| r.name == "term(m=k_m1*thrust)")
        .unwrap_or_else(|| panic!("no row for the thrust term: {names:?}; {line}"));
    assert!(
        i >= rows_before,
        "a new row, after the catalogue's: {names:?}"
    );
    let row = &c.rows[i];
    assert!(!row.on && !row.in_base);
    assert!(term_of(row.effect().info()).is_some());
    let d = row.discovered.as_ref().expect("discover's word on the row");
    assert!(d.reading.contains("thrust line"), "{}", d.reading);
    assert_eq!(d.add, "term:m=k_m1*thrust");
    assert!(
        (d.estimate - TRUE_K).abs() < 0.1 * TRUE_K.abs(),
        "discover's estimate {}",
        d.estimate
    );
    assert!(d.note().contains("k_m1 = -0.0"), "{}", d.note());
    let k = row.params()[0].value;
    assert!(
        (k - TRUE_K).abs() < 0.05 * TRUE_K.abs(),
        "the fitted coefficient {k}"
    );
    let fitted_units = d.noise_units_after.expect("fitted");
    assert!(fitted_units < 1.1, "{fitted_units} × the noise");

    assert!(c.set_by_name("term(m=k_m1*thrust)", true));
    c.wait();
    assert_eq!(c.now.effects, ["term(m=k_m1*thrust)"]);
    let now = c.now.noise_units;
    eprintln!("{line}; ticked: {before:.2} → {now:.2} × the noise");
    assert!(now < 1.1, "{before} → {now} × the noise");
    assert!(c.model().has_effect("term(m=k_m1*thrust)"));

    // The panel, drawn offscreen: the button, the discovery's line, the row with discover's
    // reading and estimate, the misfit in units of the noise.
    let session = Session::replay(builtin_plane(), c.data().clone(), CameraMode::Chase, 1.0)
        .unwrap()
        .with_compare(c);
    let drawn = compare_panel_texts(&session);
    let all = drawn.join("\n");
    assert!(drawn.iter().any(|t| t == "discover"), "{all}");
    assert!(drawn.iter().any(|t| t == &line), "{all}");
    assert!(drawn.iter().any(|t| t == "term(m=k_m1*thrust)"), "{all}");
    assert!(all.contains("pitching moment ∝ thrust"), "{all}");
    assert!(all.contains("discover: k_m1 = -0.0"), "{all}");
    assert!(drawn.iter().any(|t| t == "× noise"), "{all}");
    let mut session = session;
    let c = session.compare_mut::<Compare>().unwrap();

    // Unticked, the base model's error again; a second discovery on it annotates the same
    // row rather than adding another.
    c.set_by_name("term(m=k_m1*thrust)", false);
    c.wait();
    assert!((c.now.noise_units - before).abs() < 1e-9 * before);
    let rows = c.rows.len();
    assert!(c.start_discover());
    c.wait_discover();
    assert_eq!(c.rows.len(), rows, "the same terms, the same rows");
}
