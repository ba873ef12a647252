//! Comparison plots: real comparisons of short simulated flights drawn to PNG; the files exist,
//! decode, have the documented size, carry a drawing (not a blank or near-blank image), and
//! bad directories are reported with their path.
//!
//! Set `WIREFLIGHT_PLOTS_KEEP=DIR` to keep the plots for looking at.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use wireflight::analysis::compare::{
    compare_prepared, noise_floor, CompareConfig, Comparison, Prepared,
};
use wireflight::analysis::conditions::conditions;
use wireflight::data::FlightData;
use wireflight::data::VehicleKind;
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::model::Model;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelSpec};
use wireflight::present::plots::{
    write_plots, write_plots_with, ConditionSeries, PlotInfo, ERROR_VS_CONDITION,
    ERROR_VS_CONDITION_SIZE, MEASURED_VS_MODEL, MEASURED_VS_MODEL_SIZE, RESIDUALS,
    RESIDUALS_PER_AXIS, RESIDUALS_PER_AXIS_ROW, RESIDUALS_PER_AXIS_WIDTH, RESIDUALS_SIZE,
};

use crate::support::cli::ok_in;
use crate::support::flights::Flight;

fn model(vehicle: VehicleKind, effects: &[&str]) -> Model {
    let mut spec = ModelSpec::baseline(vehicle);
    for e in effects {
        spec.effects.push(EffectSpec::parse(e).unwrap());
    }
    spec.build(Origin::default()).unwrap()
}

fn flight(truth: &Model, manoeuvre: Manoeuvre, duration_s: f64) -> FlightData {
    let spec = SimSpec {
        manoeuvre,
        duration_s,
        rate_hz: 20.0,
        airspeed_mps: 25.0,
        height_m: 300.0,
        launch_speed_mps: 150.0,
        noise: Noise {
            pos_m: 0.5,
            att_deg: 0.3,
            vel_mps: 0.1,
            rate_dps: 0.2,
        },
        accelerometer: None,
        seed: 7,
        source: format!("simulated {manoeuvre}"),
        aircraft: None,
        listed_effects: Vec::new(),
        turbulence: None,
        sensor_errors: None,
    };
    simulate(truth, &spec).unwrap()
}

/// A fixed-wing flight with a hidden wind; the baseline before, baseline + wind after.
struct Case {
    data: FlightData,
    before: Comparison,
    after: Comparison,
    series: ConditionSeries,
    floor: f64,
}

fn windy_case() -> Case {
    let truth = model(VehicleKind::FixedWing, &["wind:north_mps=4,east_mps=-3"]);
    let data = flight(&truth, Manoeuvre::FlightTest, 64.0);
    let prep = Prepared::new(
        &data,
        CompareConfig {
            window_s: 8.0,
            ..CompareConfig::default()
        },
    );
    let base = model(VehicleKind::FixedWing, &[]);
    let before = compare_prepared(&base, &prep);
    let after = compare_prepared(&truth, &prep);
    let floor = noise_floor(&truth, &prep);
    let c = conditions(&data, &before, 0.0).remove(0);
    let series = ConditionSeries {
        name: c.name.to_string(),
        unit: c.unit.to_string(),
        per_window: c.per_window,
    };
    Case {
        data,
        before,
        after,
        series,
        floor,
    }
}

struct Decoded {
    width: u32,
    height: u32,
    rgb: Vec<[u8; 3]>,
}

fn decode(path: &Path) -> Decoded {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap_or_else(|e| panic!("{}: not a PNG: {e}", path.display()));
    let mut buf = vec![0; dec.output_buffer_size().unwrap()];
    let info = dec.next_frame(&mut buf).unwrap();
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("{}: unexpected colour type {other:?}", path.display()),
    };
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    Decoded {
        width: info.width,
        height: info.height,
        rgb,
    }
}

/// Size as documented, mostly white background, yet a real drawing: many distinct colours
/// (anti-aliased text and lines), a good share of drawn pixels, some of the series colours.
fn check_png(path: &Path, size: (u32, u32)) {
    let img = decode(path);
    assert_eq!((img.width, img.height), size, "{}", path.display());
    let white = img.rgb.iter().filter(|p| **p == [255, 255, 255]).count();
    let drawn = img.rgb.len() - white;
    let share = drawn as f64 / img.rgb.len() as f64;
    assert!(
        (0.02..0.6).contains(&share),
        "{}: {:.1}% of pixels drawn",
        path.display(),
        100.0 * share
    );
    let distinct: HashSet<[u8; 3]> = img.rgb.iter().copied().collect();
    assert!(
        distinct.len() > 200,
        "{}: only {} colours",
        path.display(),
        distinct.len()
    );
    // The "before" series colour (blue, light behind an "after" model) is drawn.
    let blue = img
        .rgb
        .iter()
        .filter(|p| p[2] > 150 && i32::from(p[2]) - i32::from(p[0]) > 40 && p[2] > p[1])
        .count();
    assert!(blue > 500, "{}: {blue} blue pixels", path.display());
}

fn keep(files: &[PathBuf], sub: &str) {
    if let Ok(dir) = std::env::var("WIREFLIGHT_PLOTS_KEEP") {
        let dir = Path::new(&dir).join(sub);
        std::fs::create_dir_all(&dir).unwrap();
        for f in files {
            std::fs::copy(f, dir.join(f.file_name().unwrap())).unwrap();
        }
    }
}

#[test]
fn before_after_and_condition_plots_are_written_and_drawn() {
    let case = windy_case();
    assert!(case.after.total < case.before.total);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("plots"); // created on demand
    let info = PlotInfo {
        data_name: Some("windy.csv".into()),
        model_name: Some("fixed-wing aerosonde".into()),
        noise_floor: Some(case.floor),
        window_s: Some(8.0),
    };
    let files = write_plots_with(
        &dir,
        &case.data,
        &case.before,
        Some((&case.after, "+ wind")),
        Some(&case.series),
        &info,
    )
    .unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            MEASURED_VS_MODEL,
            RESIDUALS,
            RESIDUALS_PER_AXIS,
            ERROR_VS_CONDITION
        ]
    );
    for f in &files {
        assert_eq!(f.parent().unwrap(), dir);
        assert!(f.is_file(), "{}", f.display());
    }
    check_png(&files[0], MEASURED_VS_MODEL_SIZE);
    check_png(&files[1], RESIDUALS_SIZE);
    // Position, velocity, attitude, rates and air data: five rows of three axes.
    check_png(&files[2], per_axis_size(5));
    check_png(&files[3], ERROR_VS_CONDITION_SIZE);
    // One window count, as `compare` prints it.
    for f in &files {
        let text = png_text(f);
        assert!(text.contains("8 windows of 8 s"), "{}: {text}", f.display());
    }
    // The "after" colour (green) appears where an after-model is given.
    for f in &files {
        let img = decode(f);
        let green = img
            .rgb
            .iter()
            .filter(|p| p[1] > 130 && p[0] < 90 && p[2] < 90)
            .count();
        assert!(green > 300, "{}: {green} green pixels", f.display());
    }
    // No temporary files are left behind.
    let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(entries.len(), 4);
    keep(&files, "fixed-wing");

    // Written again into the same directory: replaced, same result.
    let again = write_plots_with(
        &dir,
        &case.data,
        &case.before,
        Some((&case.after, "+ wind")),
        Some(&case.series),
        &info,
    )
    .unwrap();
    assert_eq!(again, files);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 4);
}

/// The size of `residuals_per_axis.png` with `rows` channels.
fn per_axis_size(rows: u32) -> (u32, u32) {
    (RESIDUALS_PER_AXIS_WIDTH, 92 + rows * RESIDUALS_PER_AXIS_ROW)
}

/// The UTF-8 text chunks of a PNG (its title and subtitle), one per line.
fn png_text(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap();
    let dec = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    dec.info()
        .utf8_text
        .iter()
        .map(|c| format!("{}: {}", c.keyword, c.get_text().unwrap()))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `compare`'s text and its plots agree: the conditions plot shows the condition the text
/// names first, with the same r (with `--add` bringing the error to the noise, the text names
/// none, and the plot shows the model as given's, which `compare` without `--add` names), and
/// every plot counts the windows as the text does ("5 windows of 8 s"). The plots' titles are
/// read from their PNG text chunks.
#[test]
fn the_text_and_the_plots_name_the_same_condition_and_windows() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("a.csv");
    let flight = Flight::new()
        .manoeuvre("flight-test")
        .duration(40)
        .hidden("aircraft:c_m_alpha=-3.3")
        .noise_pos(0.05)
        .noise_att(0.05)
        .noise_vel(0.05)
        .noise_rate(0.2);
    ok_in(tmp.path(), &flight.args(&csv));
    let plain = ok_in(
        tmp.path(),
        &["compare", "--flight", "a.csv", "--plots", "p1"],
    );
    let with = ok_in(
        tmp.path(),
        &[
            "compare",
            "--flight",
            "a.csv",
            "--add",
            "aircraft:c_m_alpha",
            "--plots",
            "p2",
        ],
    );
    // The first condition of "error correlates with" and its r, as the text prints them.
    let first = plain
        .lines()
        .skip_while(|l| !l.starts_with("error correlates with"))
        .nth(2)
        .unwrap_or_else(|| panic!("no condition table: {plain}"))
        .trim()
        .to_string();
    let (name_unit, r) = first.rsplit_once("  ").unwrap();
    let name = name_unit.trim().rsplit_once(" (").unwrap().0;
    let r = r.trim();
    // The window count of the text's first line.
    let windows = plain
        .lines()
        .find(|l| l.starts_with("a.csv: "))
        .unwrap()
        .split(", ")
        .find(|p| p.contains("windows of"))
        .unwrap()
        .split(';')
        .next()
        .unwrap()
        .to_string();
    for dir in ["p1", "p2"] {
        let title =
            png_text(&tmp.path().join(dir).join(ERROR_VS_CONDITION)).replace('\u{2212}', "-");
        assert!(
            title.contains(&format!("Window error vs {name} — r = {r}")),
            "{dir}: the plot says {title:?}, the text {first:?}"
        );
        for f in [RESIDUALS, RESIDUALS_PER_AXIS, MEASURED_VS_MODEL] {
            let text = png_text(&tmp.path().join(dir).join(f));
            assert!(
                text.contains(&windows),
                "{dir}/{f}: {text:?} vs {windows:?}"
            );
        }
    }
    assert!(with.contains(&windows), "{with}");
}

#[test]
fn before_only_without_condition_writes_three_plots() {
    let truth = model(VehicleKind::PointMass, &["drag:k=0.0004"]);
    let data = flight(&truth, Manoeuvre::Ballistic, 30.0);
    let prep = Prepared::new(
        &data,
        CompareConfig {
            window_s: 4.0,
            ..CompareConfig::default()
        },
    );
    let before = compare_prepared(&model(VehicleKind::PointMass, &[]), &prep);
    assert!(before.channels.attitude_deg.is_none());
    let tmp = tempfile::tempdir().unwrap();
    let files = write_plots(tmp.path(), &data, &before, None, None).unwrap();
    assert_eq!(
        files,
        [
            tmp.path().join(MEASURED_VS_MODEL),
            tmp.path().join(RESIDUALS),
            tmp.path().join(RESIDUALS_PER_AXIS)
        ]
    );
    check_png(&files[0], MEASURED_VS_MODEL_SIZE);
    check_png(&files[1], RESIDUALS_SIZE);
    // A point mass: position and velocity only.
    check_png(&files[2], per_axis_size(2));
    keep(&files, "point-mass");
}

#[test]
fn unusable_directories_and_inputs_are_errors_naming_the_path() {
    let truth = model(VehicleKind::PointMass, &[]);
    let data = flight(&truth, Manoeuvre::Ballistic, 12.0);
    let prep = Prepared::new(&data, CompareConfig::default());
    let cmp = compare_prepared(&truth, &prep);
    let tmp = tempfile::tempdir().unwrap();

    // A directory below a regular file can neither exist nor be created.
    let file = tmp.path().join("not-a-dir");
    std::fs::write(&file, b"x").unwrap();
    let bad = file.join("plots");
    let err = write_plots(&bad, &data, &cmp, None, None).unwrap_err();
    let msg = format!("{err:#}");
    assert!(msg.contains(&bad.display().to_string()), "{msg}");

    // The path itself is a file.
    let err = write_plots(&file, &data, &cmp, None, None).unwrap_err();
    assert!(
        format!("{err:#}").contains(&file.display().to_string()),
        "{err:#}"
    );

    // A condition series that does not match the windows.
    let wrong = ConditionSeries {
        name: "airspeed".into(),
        unit: "m/s".into(),
        per_window: vec![1.0; cmp.windows.len() + 1],
    };
    let dir = tmp.path().join("plots");
    let err = write_plots(&dir, &data, &cmp, None, Some(&wrong)).unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains(ERROR_VS_CONDITION) && msg.contains("airspeed"),
        "{msg}"
    );
    assert!(!dir.join(MEASURED_VS_MODEL).exists());
}

#[cfg(unix)]
#[test]
fn read_only_directory_is_an_error_naming_the_file() {
    use std::os::unix::fs::PermissionsExt;
    let truth = model(VehicleKind::PointMass, &[]);
    let data = flight(&truth, Manoeuvre::Ballistic, 12.0);
    let prep = Prepared::new(&data, CompareConfig::default());
    let cmp = compare_prepared(&truth, &prep);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ro");
    std::fs::create_dir(&dir).unwrap();
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).unwrap();
    // Privileged users write anyway; then there is nothing to check.
    let probe = dir.join(".probe");
    if std::fs::write(&probe, b"").is_ok() {
        let _ = std::fs::remove_file(&probe);
        return;
    }
    let err = write_plots(&dir, &data, &cmp, None, None).unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains(&dir.join(MEASURED_VS_MODEL).display().to_string()),
        "{msg}"
    );
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// Several full turns: the heading is drawn wrapped to ±180°; a long, dense flight still
/// renders quickly.
#[test]
fn long_flight_with_full_turns() {
    let truth = model(VehicleKind::FixedWing, &["wind:north_mps=3"]);
    let data = flight(&truth, Manoeuvre::ClimbingTurn, 160.0);
    let prep = Prepared::new(&data, CompareConfig::default());
    let before = compare_prepared(&model(VehicleKind::FixedWing, &[]), &prep);
    let tmp = tempfile::tempdir().unwrap();
    let started = std::time::Instant::now();
    let files = write_plots(tmp.path(), &data, &before, None, None).unwrap();
    eprintln!("plots in {:?}", started.elapsed());
    check_png(&files[0], MEASURED_VS_MODEL_SIZE);
    check_png(&files[1], RESIDUALS_SIZE);
    keep(&files, "climbing-turn");
}
