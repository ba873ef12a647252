//! The fly-through window (`wireflight view`).
//!
//! The window tests run the real binary with a script under the X display in `$DISPLAY`
//! (CI: `xvfb-run` with Mesa's lavapipe) and look at the screenshot it writes. Without a
//! display they print why and pass, unless `WIREFLIGHT_REQUIRE_DISPLAY=1` makes the display
//! mandatory. The other tests need no display: they drive the viewer's session (the same code
//! the window draws from) directly, or check errors that come before any window opens.

use std::path::Path;
use std::time::Duration;

use std::sync::Arc;

use wireflight::app::view::cameras::CameraMode;
use wireflight::app::view::compare::{Compare, Fit};
use wireflight::app::view::flight::Start;
use wireflight::app::view::script;
use wireflight::app::view::session::{Held, Session};
use wireflight::draw::render::{Image, Rgba};
use wireflight::draw::scene::builder::Part;
use wireflight::draw::scene::palette::{self, MODEL_AIRCRAFT, MODEL_TRAIL};
use wireflight::flight::spec::ModelChoice;
use wireflight::geometry::euler::Gimbal;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::support::cli::wireflight_timed;

pub(crate) const WINDOW_TIMEOUT: Duration = Duration::from_secs(300);

/// Whether a display is there to open windows on; `None` (after saying why) to skip.
pub(crate) fn display() -> Option<String> {
    let required = std::env::var("WIREFLIGHT_REQUIRE_DISPLAY").is_ok_and(|v| v == "1");
    match std::env::var("DISPLAY") {
        Ok(d) if !d.is_empty() => Some(d),
        _ if required => panic!("WIREFLIGHT_REQUIRE_DISPLAY=1 but DISPLAY is not set"),
        _ => {
            eprintln!(
                "skipping the window test: no DISPLAY (run under `xvfb-run -a`, and set \
                 WIREFLIGHT_REQUIRE_DISPLAY=1 to make this a failure)"
            );
            None
        }
    }
}

/// The longest a run that ends before any window opens may take.
const NO_WINDOW_TIMEOUT: Duration = Duration::from_secs(60);

fn count(image: &Image, x0: u32, y0: u32, x1: u32, y1: u32, color: Rgba) -> usize {
    let mut n = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            n += usize::from(image.pixel(x, y) == color);
        }
    }
    n
}

const SCRIPT: &str = "\
# a gentle climbing right turn
0.0  throttle=0.8
0.2  pitch_rate=5 roll_rate=20
0.7  roll_rate=0
";

/// Run the scripted flight in a window and return the screenshot and stdout.
fn scripted_screenshot(dir: &Path, name: &str) -> (Image, String) {
    let script = dir.join("turn.txt");
    std::fs::write(&script, SCRIPT).unwrap();
    let shot = dir.join(name);
    let out = wireflight_timed(
        &[
            "view",
            "--script",
            script.to_str().unwrap(),
            "--frames",
            "60",
            "--size",
            "960x540",
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        WINDOW_TIMEOUT,
    );
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "wireflight view failed: {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
        out.status
    );
    let image = Image::decode_png(&std::fs::read(&shot).expect("the screenshot exists")).unwrap();
    (image, stdout)
}

#[test]
fn scripted_window_run_shows_the_plane_and_the_grid_deterministically() {
    let Some(display) = display() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (image, stdout) = scripted_screenshot(dir.path(), "a.png");
    println!("DISPLAY={display}\n{stdout}");
    let (w, h) = (image.width, image.height);
    // Physical pixels: the logical size times the display's scale factor.
    assert!(w >= 960 && h >= 540 && w * 540 == h * 960, "{w}x{h}");
    assert!(
        stdout.contains("frames at") && stdout.contains("clip per frame"),
        "{stdout}"
    );

    // The aircraft (model colour) in the middle third of the picture.
    let plane = count(
        &image,
        w / 3,
        h / 3,
        2 * w / 3,
        2 * h / 3,
        palette::AIRCRAFT,
    );
    assert!(plane > 200, "{plane} model-colour pixels near the centre");
    // The ground grid, and not a blank or black frame.
    let grid = count(&image, 0, 0, w, h, palette::GRID);
    assert!(grid > 2000, "{grid} grid-colour pixels");
    let background = count(&image, 0, 0, w, h, palette::BACKGROUND);
    let total = (w * h) as usize;
    assert!(
        background < total * 97 / 100,
        "{background} of {total} are background"
    );
    assert!(
        background > total / 3,
        "mostly sky and ground: {background} of {total}"
    );
    let black = count(&image, 0, 0, w, h, [0, 0, 0, 255]);
    assert_eq!(black, 0, "black pixels: nothing should be black");

    // A fixed time step per frame: the same script gives the same picture.
    let (again, _) = scripted_screenshot(dir.path(), "b.png");
    assert!(again == image, "two runs of one script differ");
    let stray: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !["turn.txt", "a.png", "b.png"].contains(&n.as_str()))
        .collect();
    assert!(stray.is_empty(), "leftover files: {stray:?}");
}

#[test]
fn a_bad_script_line_names_the_file_and_line_before_any_window_opens() {
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("bad.txt");
    std::fs::write(&script, "0 throttle=0.5\n# fine so far\n1.0 elevator=3\n").unwrap();
    let out = wireflight_timed(
        &[
            "view",
            "--script",
            script.to_str().unwrap(),
            "--frames",
            "5",
        ],
        NO_WINDOW_TIMEOUT,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("{}:3: unknown key `elevator`", script.display())),
        "{err}"
    );

    let missing = dir.path().join("missing.txt");
    let out = wireflight_timed(
        &["view", "--script", missing.to_str().unwrap()],
        NO_WINDOW_TIMEOUT,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.txt: cannot read script"));
}

#[test]
fn screenshot_needs_frames_and_a_png_name() {
    let out = wireflight_timed(&["view", "--screenshot", "x.png"], NO_WINDOW_TIMEOUT);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--frames"));
    let out = wireflight_timed(
        &["view", "--frames", "3", "--screenshot", "x.svg"],
        NO_WINDOW_TIMEOUT,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("PNG"));
}

#[test]
fn shipped_demo_scripts_parse() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scripts");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "txt") {
            let s = script::load(&path).unwrap_or_else(|e| panic!("{e:#}"));
            assert!(!s.events.is_empty(), "{}", path.display());
            n += 1;
        }
    }
    assert!(n >= 2, "{n} scripts in {}", dir.display());
}

/// The loop script, headless: 12 s at 60 frames a second through both vertical points.
#[test]
fn looping_through_the_vertical_clips_every_frame_and_reports_gimbal_lock() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scripts/loop.txt");
    let script = script::load(&path).unwrap();
    let mut s = Session::fly(
        builtin_plane(),
        Start::default(),
        Some(script),
        CameraMode::Chase,
        55f32.to_radians(),
    );
    let viewport = Viewport {
        width: 640,
        height: 360,
    };
    let plane_edges = builtin_plane().edges().len();
    let (mut locked, mut min_clipped) = (0, u64::MAX);
    for frame in 0..720 {
        s.advance(1.0 / 60.0, &Held::default());
        let stats = s.build(viewport);
        min_clipped = min_clipped.min(stats.clipped);
        assert!(stats.trivially_rejected > 0, "frame {frame}: {stats}");
        assert_eq!(stats.non_finite, 0, "frame {frame}: {stats}");
        let r = s.readout();
        assert!(
            r.angles.is_finite() && r.speed.is_finite(),
            "frame {frame}: {r:?}"
        );
        locked += usize::from(r.gimbal != Gimbal::Free);
        // The chase camera keeps the whole aircraft in the picture all the way round.
        let plane = &s.scene().batches[s.builder().batch(Part::Aircraft)].segments;
        assert_eq!(plane.len(), plane_edges, "frame {frame}");
    }
    assert!(min_clipped > 0, "some edge is clipped in every frame");
    assert!(
        locked >= 2,
        "the HUD's gimbal lock: {locked} frames at ±90°"
    );
    // Back level after the full loop.
    let r = s.readout();
    assert!(r.angles.pitch.abs() < 1e-6, "{r:?}");
}

/// A windy climbing turn (the wind hidden: not in the file), written as CSV.
fn windy_flight(dir: &Path, duration_s: f64) -> std::path::PathBuf {
    use wireflight::data::VehicleKind;
    use wireflight::flight::autopilot::Manoeuvre;
    use wireflight::flight::effects::Origin;
    use wireflight::flight::simulate::{simulate, Noise, SimSpec};
    use wireflight::flight::spec::{EffectSpec, ModelSpec};
    let mut truth = ModelSpec::baseline(VehicleKind::FixedWing);
    truth
        .effects
        .push(EffectSpec::parse("wind:north_mps=6,east_mps=-4").unwrap());
    let spec = SimSpec {
        manoeuvre: Manoeuvre::ClimbingTurn,
        duration_s,
        rate_hz: 50.0,
        airspeed_mps: 25.0,
        launch_speed_mps: 150.0,
        height_m: 200.0,
        noise: Noise {
            pos_m: 0.2,
            att_deg: 0.1,
            vel_mps: 0.05,
            rate_dps: 0.2,
        },
        accelerometer: None,
        seed: 5,
        source: "tests/view.rs".into(),
        aircraft: Some("aerosonde".into()),
        listed_effects: Vec::new(),
        turbulence: None,
        sensor_errors: None,
    };
    let data = simulate(&truth.build(Origin::default()).unwrap(), &spec).unwrap();
    let path = dir.join("windy.csv");
    wireflight::data::write(&path, &data).unwrap();
    path
}

/// `--compare` without a window: the session loads the flight and the base model, the fit
/// names the hidden wind, and ticking `wind` (fitted parameters) makes the error fall.
#[test]
fn compare_mode_ticking_the_fitted_wind_makes_the_error_fall() {
    let dir = tempfile::tempdir().unwrap();
    let path = windy_flight(dir.path(), 40.0);
    let data = wireflight::data::read(&path).unwrap();
    let base = ModelChoice::default().build(&path, &data).unwrap();
    let data = Arc::new(data);
    let compare = Compare::new(Arc::clone(&data), base, &[]).unwrap();
    assert!(
        matches!(compare.fit, Fit::Running(_)),
        "the fit runs in the background"
    );
    assert_eq!(compare.verdict_line().split(' ').next(), Some("fitting…"));
    let names: Vec<&str> = compare.rows.iter().map(|r| r.name).collect();
    assert!(
        names.contains(&"wind") && names.contains(&"actuator_lag"),
        "{names:?}"
    );
    assert!(
        !names.contains(&"drag"),
        "point-mass drag does not apply: {names:?}"
    );
    let mut s = Session::replay(
        builtin_plane(),
        (*data).clone(),
        CameraMode::Chase,
        55f32.to_radians(),
    )
    .unwrap()
    .with_compare(compare);
    let viewport = Viewport {
        width: 640,
        height: 360,
    };
    // 1.5 s in: the model has not drifted out of the chase camera's view yet.
    for _ in 0..90 {
        s.advance(1.0 / 60.0, &Held::default());
    }
    s.build(viewport);
    let scene = s.scene();
    assert!(!scene.batches[s.builder().batch(Part::ModelAircraft)]
        .segments
        .is_empty());
    assert!(!scene.batches[s.builder().batch(Part::ModelTrail)]
        .segments
        .is_empty());
    assert_eq!(
        scene.batches[s.builder().batch(Part::ModelAircraft)].color,
        MODEL_AIRCRAFT
    );
    assert_eq!(
        scene.batches[s.builder().batch(Part::ModelTrail)].color,
        MODEL_TRAIL
    );

    // Ticking `wind` before the fit is in: the default (zero) wind changes nothing.
    let c = s.compare_mut::<Compare>().unwrap();
    let before = c.before.total;
    assert!(c.set_by_name("wind", true));
    c.wait();
    assert_eq!(c.now.effects, ["wind"]);
    assert!((c.now.total - before).abs() < 1e-9 * before.max(1.0));

    // The fit names the wind and re-runs the ticked model with the fitted wind.
    c.wait_fit();
    assert_eq!(c.verdict_line(), "diagnosis: `wind` is missing");
    let wind = c.rows.iter().find(|r| r.name == "wind").unwrap();
    let p = wind.params();
    let north = p.iter().find(|p| p.name == "north_mps").unwrap().value;
    let east = p.iter().find(|p| p.name == "east_mps").unwrap().value;
    assert!(
        (north - 6.0).abs() < 0.5 && (east + 4.0).abs() < 0.5,
        "{p:?}"
    );
    let now = c.now.total;
    eprintln!(
        "total error {before:.3} → {now:.3} with the fitted wind (model run {:.1} ms)",
        1e3 * c.now.compute_s
    );
    assert!(now * 5.0 < before, "{before} → {now}");
    assert!(c.now.channels.position_m * 5.0 < c.before.channels.position_m);

    // Unticking goes back to the base model's error.
    c.set_by_name("wind", false);
    c.wait();
    assert!(c.now.effects.is_empty());
    assert!((c.now.total - before).abs() < 1e-9 * before.max(1.0));
}

#[test]
fn compare_rejects_an_add_that_does_not_apply() {
    let dir = tempfile::tempdir().unwrap();
    let path = windy_flight(dir.path(), 12.0);
    let out = wireflight_timed(
        &[
            "view",
            "--flight",
            path.to_str().unwrap(),
            "--compare",
            "--add",
            "drag",
            "--frames",
            "1",
        ],
        NO_WINDOW_TIMEOUT,
    );
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`drag` does not apply"), "{err}");
    let out = wireflight_timed(&["view", "--compare", "--frames", "1"], NO_WINDOW_TIMEOUT);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--flight"));
}

/// `--compare` in a window: the screenshot shows the measured aircraft and the model's.
#[test]
fn compare_window_run_shows_both_aircraft() {
    let Some(display) = display() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let path = windy_flight(dir.path(), 40.0);
    let shot = dir.path().join("compare.png");
    let out = wireflight_timed(
        &[
            "view",
            "--flight",
            path.to_str().unwrap(),
            "--compare",
            "--frames",
            "120",
            "--size",
            "960x540",
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        WINDOW_TIMEOUT,
    );
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "wireflight view --compare failed: {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
        out.status
    );
    println!("DISPLAY={display}\n{stdout}");
    assert!(stdout.contains("compare: base model total"), "{stdout}");
    let image = Image::decode_png(&std::fs::read(&shot).expect("the screenshot exists")).unwrap();
    let (w, h) = (image.width, image.height);
    let measured = count(&image, 0, 0, w, h, palette::AIRCRAFT);
    let model = count(&image, 0, 0, w, h, MODEL_AIRCRAFT);
    let model_trail = count(&image, 0, 0, w, h, MODEL_TRAIL);
    assert!(measured > 200, "{measured} measured-aircraft pixels");
    assert!(model > 100, "{model} model-aircraft pixels");
    assert!(model_trail > 20, "{model_trail} model-trail pixels");
}
