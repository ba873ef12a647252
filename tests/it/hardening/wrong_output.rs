//! Hostile-input reproductions: outputs that are never silently wrong.

use super::*;

#[test]
fn an_obj_with_a_byte_order_mark_loses_no_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nl 3 4\n";
    std::fs::write(dir.path().join("plain.obj"), text).unwrap();
    std::fs::write(dir.path().join("bom.obj"), format!("\u{feff}{text}")).unwrap();
    let plain = wireflight::draw::mesh_files::load(&dir.path().join("plain.obj")).unwrap();
    let bom = wireflight::draw::mesh_files::load(&dir.path().join("bom.obj")).unwrap();
    assert_eq!(plain.positions(), bom.positions());
    assert_eq!(plain.edges(), bom.edges());
    assert_eq!(bom.edges().len(), 4);
}

#[test]
fn a_flight_of_one_or_two_rows_is_not_compared_nor_diagnosed() {
    let dir = tempfile::tempdir().unwrap();
    let a = flight(dir.path(), "a.csv", &[]);
    let text = std::fs::read_to_string(a).unwrap();
    let header = text.lines().position(|l| l.starts_with("time_s")).unwrap();
    for rows in [1, 2] {
        let short: Vec<&str> = text.lines().take(header + 1 + rows).collect();
        std::fs::write(dir.path().join("s.csv"), short.join("\n") + "\n").unwrap();
        for cmd in ["compare", "diagnose"] {
            let o = run(&[cmd, "--flight", "s.csv"], dir.path());
            assert_refused(&o, &["s.csv", "too short"]);
        }
    }
}

#[test]
fn effect_and_origin_values_out_of_range_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "a.csv", &[]);
    for add in [
        "actuator_lag:tau_s=-1",
        "actuator_lag:tau_s=0",
        "wind:north_mps=1e308",
    ] {
        let o = run(&["compare", "--flight", "a.csv", "--add", add], d);
        assert_refused(&o, &["outside its range"]);
    }
    for (opt, v) in [
        ("--latitude", "95"),
        ("--longitude", "400"),
        ("--latitude", "-91"),
    ] {
        let o = run(
            &["simulate", "--duration", "1", opt, v, "--out", "x.csv"],
            d,
        );
        assert_refused(&o, &["origin", "outside"]);
    }
    // The same limits where a file gives them: the data's metadata and a model file.
    let text = std::fs::read_to_string(d.join("a.csv")).unwrap();
    let bad = text.replacen("# latitude_deg: 45", "# latitude_deg: 95", 1);
    assert_ne!(bad, text, "the data name their latitude");
    std::fs::write(d.join("lat.csv"), bad).unwrap();
    let o = run(&["compare", "--flight", "lat.csv"], d);
    assert_refused(&o, &["lat.csv", "latitude_deg", "95"]);
    std::fs::write(
        d.join("m.toml"),
        "vehicle = \"fixed-wing\"\n[origin]\nlongitude_deg = 400\n",
    )
    .unwrap();
    let o = run(
        &[
            "simulate",
            "--model",
            "m.toml",
            "--duration",
            "1",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_refused(&o, &["m.toml", "longitude_deg"]);
}

#[test]
fn controls_out_of_range_in_data_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let a = flight(dir.path(), "a.csv", &[]);
    for (col, v, range) in [
        ("throttle", "5", "0..1"),
        ("throttle", "-0.5", "0..1"),
        ("elevator_deg", "1e6", "±90°"),
        ("aileron_deg", "-91", "±90°"),
    ] {
        set_cell(&a, &dir.path().join("c.csv"), col, 3, v);
        let o = run(&["compare", "--flight", "c.csv"], dir.path());
        assert_refused(&o, &["c.csv", col, range]);
    }
}

/// The Aerosonde set with one line replaced.
fn aircraft_with(dir: &Path, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/aircraft/aerosonde.toml"),
    )
    .unwrap();
    let changed = text.replacen(from, to, 1);
    assert_ne!(changed, text, "{from}");
    let path = dir.join("ac.toml");
    std::fs::write(&path, changed).unwrap();
    path
}

#[test]
fn impossible_parameter_sets_and_trims_say_which_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sim = |extra: &[&str]| {
        let mut args = vec!["simulate", "--duration", "1", "--out", "x.csv"];
        args.extend_from_slice(extra);
        run(&args, d)
    };
    // Singular inertia: jxz² = jx·jz (0.824 · 1.759 = 1.449416).
    aircraft_with(d, "jxz = 0.120", "jxz = 1.2039169406");
    assert_refused(
        &sim(&["--aircraft", "ac.toml"]),
        &["ac.toml", "inertia tensor", "singular"],
    );
    aircraft_with(d, "mass_kg = 11.0", "mass_kg = 1e300");
    assert_refused(
        &sim(&["--aircraft", "ac.toml"]),
        &["ac.toml", "mass_kg", "outside its range"],
    );
    aircraft_with(d, "k_motor = 80.0", "k_motor = 0");
    assert_refused(
        &sim(&["--aircraft", "ac.toml"]),
        &["ac.toml", "k_motor", "outside its range"],
    );
    // In range but without thrust: the throttle is named.
    aircraft_with(d, "k_motor = 80.0", "k_motor = 1e-9");
    assert_refused(
        &sim(&["--aircraft", "ac.toml"]),
        &["no trim at 25 m/s", "the throttle", "k_motor"],
    );
    assert_refused(
        &sim(&["--airspeed", "0"]),
        &["airspeed 0 m/s", "positive airspeed"],
    );
    let o = sim(&["--airspeed", "-5"]);
    assert_refused(&o, &["positive airspeed"]);
}

#[test]
fn frames_dir_holds_one_runs_frames_only() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "a.csv", &[]);
    let frames = |fps: &str| {
        let args = [
            "render",
            "--flight",
            "a.csv",
            "--frames-dir",
            "frames",
            "--fps",
            fps,
            "--size",
            "64x48",
            "--backend",
            "cpu",
        ];
        run(&args, d)
    };
    let count = || std::fs::read_dir(d.join("frames")).unwrap().count();
    assert_ok(&frames("2"));
    assert_eq!(count(), 25); // 12 s at 2 fps, both ends
    assert_ok(&frames("1"));
    assert_eq!(count(), 13, "the old frames are gone");
    // A directory with other files is refused, not emptied.
    std::fs::write(d.join("frames/notes.txt"), "mine").unwrap();
    let o = frames("1");
    assert_refused(&o, &["notes.txt", "new or empty"]);
    assert!(d.join("frames/notes.txt").exists());
    let left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-") || n.contains(".old-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn an_add_the_flight_cannot_carry_is_refused_naming_the_flight() {
    // Whether `--add` applies can depend on what the flight recorded: a term in α on a point
    // mass whose flight has no attitude. The refusal names the flight and the option.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let point_mass = Flight::new().vehicle("point-mass").duration(5);
    assert_ok(&run(&point_mass.args("pm.csv"), d));
    for cmd in ["compare", "diagnose", "discover"] {
        let o = run(
            &[cmd, "--flight", "pm.csv", "--add", "term:Z=k*qbar*alpha"],
            d,
        );
        assert_refused(&o, &["pm.csv", "--add", "term(Z=k*qbar*alpha)", "attitude"]);
    }
    let o = run(
        &[
            "compare", "--flight", "pm.csv", "--add", "drag", "--add", "drag",
        ],
        d,
    );
    assert_refused(&o, &["pm.csv", "--add", "`drag` is already in the model"]);
}
