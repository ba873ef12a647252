//! Issue 15's reproductions, one test each: hostile inputs and options give a clear error
//! (exit 2) naming the input and the limit, or work; never a panic (101), an abort (134), a
//! hang, unbounded memory, or a silently wrong result.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wireflight"))
}

/// Run with a time limit; panics (failing the test) if the command is still running then.
fn run_for(args: &[&str], dir: &Path, limit: Duration) -> Output {
    let child = bin()
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run wireflight");
    wait_for(child, limit, args)
}

fn wait_for(mut child: Child, limit: Duration, what: &[&str]) -> Output {
    let start = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let o = child.wait_with_output().expect("output");
            panic!(
                "`wireflight {}` ran longer than {limit:?}\nstderr: {}",
                what.join(" "),
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn run(args: &[&str], dir: &Path) -> Output {
    run_for(args, dir, Duration::from_secs(120))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2 with a message on stderr that contains every one of `words`.
#[track_caller]
fn assert_refused(o: &Output, words: &[&str]) {
    let err = stderr(o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "status {:?}, stderr: {err}",
        o.status
    );
    assert!(!err.contains("panicked"), "{err}");
    for w in words {
        assert!(err.contains(w), "`{w}` not in: {err}");
    }
}

#[track_caller]
fn assert_ok(o: &Output) {
    assert!(
        o.status.success(),
        "status {:?}, stderr: {}",
        o.status,
        stderr(o)
    );
}

/// A short simulated fixed-wing flight, `name` in `dir`.
fn flight(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let mut args = vec![
        "simulate",
        "--duration",
        "12",
        "--noise-pos",
        "0.2",
        "--out",
        name,
    ];
    args.extend_from_slice(extra);
    assert_ok(&run(&args, dir));
    dir.join(name)
}

/// Rewrite one cell (`column`, data row `row`) of a wireflight CSV.
fn set_cell(src: &Path, dst: &Path, column: &str, row: usize, value: &str) {
    let text = std::fs::read_to_string(src).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header = lines.iter().position(|l| l.starts_with("time_s")).unwrap();
    let col = lines[header].split(',').position(|c| c == column).unwrap();
    let mut cells: Vec<String> = lines[header + 1 + row]
        .split(',')
        .map(str::to_string)
        .collect();
    cells[col] = value.to_string();
    lines[header + 1 + row] = cells.join(",");
    std::fs::write(dst, lines.join("\n") + "\n").unwrap();
}

// ---------------------------------------------------------------------------------------------
// Panics and aborts

#[test]
fn positions_of_1e200_are_refused_by_the_reader_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let a = flight(dir.path(), "a.csv", &[]);
    for v in ["1e200", "1e300", "-1e50"] {
        set_cell(&a, &dir.path().join("big.csv"), "north_m", 40, v);
        for cmd in ["compare", "diagnose"] {
            let o = run(&[cmd, "--flight", "big.csv"], dir.path());
            assert_refused(&o, &["big.csv", "north_m", v, "±1e8 m"]);
        }
        let o = run(
            &["render", "--flight", "big.csv", "--frames-dir", "f"],
            dir.path(),
        );
        assert_refused(&o, &["north_m", "±1e8 m"]);
    }
}

#[test]
fn simulate_never_writes_what_its_reader_rejects() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = run(
        &[
            "simulate",
            "--duration",
            "2",
            "--noise-pos",
            "1e200",
            "--out",
            "n.csv",
        ],
        d,
    );
    assert_refused(&o, &["would not read back", "north_m"]);
    let o = run(
        &[
            "simulate",
            "--duration",
            "2",
            "--noise-rate",
            "1e308",
            "--out",
            "r.csv",
        ],
        d,
    );
    assert_refused(&o, &["would not read back"]);
    let o = run(
        &[
            "simulate",
            "--vehicle",
            "point-mass",
            "--duration",
            "2",
            "--launch-speed",
            "1e200",
            "--out",
            "p.csv",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!d.join("n.csv").exists() && !d.join("r.csv").exists() && !d.join("p.csv").exists());
}

#[test]
fn a_closed_stdout_ends_the_program_quietly() {
    let dir = tempfile::tempdir().unwrap();
    flight(dir.path(), "a.csv", &[]);
    for args in [
        &["compare", "--flight", "a.csv", "--json"][..],
        &["diagnose", "--flight", "a.csv"][..],
    ] {
        let mut child = bin()
            .args(args)
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // `| head -0`: the reader is gone before anything is written.
        drop(child.stdout.take());
        let o = wait_for(child, Duration::from_secs(120), args);
        let err = stderr(&o);
        assert!(
            err.is_empty(),
            "`{}` wrote to stderr: {err}",
            args.join(" ")
        );
        assert!(
            o.status.success() || o.status.code().is_none(),
            "{:?}",
            o.status
        );
    }
}

#[test]
fn simulate_sample_count_is_bounded_by_an_option() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let limit = Duration::from_secs(10);
    let o = run_for(
        &["simulate", "--duration", "1e9", "--out", "x.csv"],
        d,
        limit,
    );
    assert_refused(&o, &["50000000001 samples", "--max-samples 2000000"]);
    let o = run_for(
        &["simulate", "--duration", "1e5", "--out", "x.csv"],
        d,
        limit,
    );
    assert_refused(&o, &["--max-samples"]);
    // The option raises (and lowers) the limit.
    let o = run_for(
        &[
            "simulate",
            "--duration",
            "10",
            "--max-samples",
            "100",
            "--out",
            "x.csv",
        ],
        d,
        limit,
    );
    assert_refused(&o, &["501 samples", "--max-samples 100"]);
    let o = run_for(
        &[
            "simulate",
            "--duration",
            "10",
            "--max-samples",
            "501",
            "--out",
            "x.csv",
        ],
        d,
        limit,
    );
    assert_ok(&o);
}

#[test]
fn a_tiny_rate_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_for(
        &[
            "simulate",
            "--duration",
            "10",
            "--rate",
            "1e-6",
            "--out",
            "x.csv",
        ],
        dir.path(),
        Duration::from_secs(10),
    );
    assert_refused(&o, &["single sample", "1/duration"]);
    // Low but sensible rates integrate in bounded steps.
    let o = run_for(
        &[
            "simulate",
            "--duration",
            "1e6",
            "--rate",
            "0.01",
            "--out",
            "x.csv",
        ],
        dir.path(),
        Duration::from_secs(10),
    );
    assert_refused(&o, &["integration steps", "--max-samples"]);
}

// ---------------------------------------------------------------------------------------------
// Unbounded work and reading where it must not

#[test]
fn a_time_gap_cannot_make_endless_frames() {
    let dir = tempfile::tempdir().unwrap();
    let a = flight(dir.path(), "a.csv", &[]);
    let text = std::fs::read_to_string(&a).unwrap();
    // Shift the last row to 1e8 s: a gap of about three years.
    let mut lines: Vec<&str> = text.lines().collect();
    let last = lines.pop().unwrap();
    let rest = last.split_once(',').unwrap().1;
    let shifted = format!("100000000,{rest}");
    lines.push(&shifted);
    std::fs::write(dir.path().join("gap.csv"), lines.join("\n") + "\n").unwrap();
    let o = run_for(
        &["render", "--flight", "gap.csv", "--frames-dir", "frames"],
        dir.path(),
        Duration::from_secs(60),
    );
    assert_refused(&o, &["frames", "--max-frames 100000"]);
    assert!(!dir.path().join("frames").exists());
    // A time of 1e12 s is not a flight at all.
    let far = format!("1e12,{rest}");
    lines.pop();
    lines.push(&far);
    std::fs::write(dir.path().join("far.csv"), lines.join("\n") + "\n").unwrap();
    let o = run(
        &["render", "--flight", "far.csv", "--frames-dir", "frames"],
        dir.path(),
    );
    assert_refused(&o, &["time_s", "±1e9 s"]);
}

#[test]
fn devices_directories_and_huge_files_are_not_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let limit = Duration::from_secs(10);
    let o = run_for(&["compare", "--data", "/dev/zero"], d, limit);
    assert_refused(&o, &["/dev/zero", "not a regular file"]);
    let o = run_for(
        &["render", "--mesh", "/dev/zero", "--out", "x.svg"],
        d,
        limit,
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    std::fs::create_dir(d.join("dir.csv")).unwrap();
    let o = run_for(&["compare", "--flight", "dir.csv"], d, limit);
    assert_refused(&o, &["dir.csv", "is a directory"]);
    // Over the size limit, naming the option that raises it.
    std::fs::write(d.join("big.obj"), vec![b'#'; 3 << 20]).unwrap();
    let o = run_for(
        &[
            "render",
            "--max-input-mb",
            "2",
            "--mesh",
            "big.obj",
            "--out",
            "x.svg",
        ],
        d,
        limit,
    );
    assert_refused(&o, &["big.obj", "3145728 bytes", "--max-input-mb"]);
}

#[test]
fn an_os_error_is_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["compare", "--flight", "missing.csv"], dir.path());
    assert_refused(&o, &["missing.csv"]);
    assert_eq!(
        stderr(&o).matches("os error 2").count(),
        1,
        "{}",
        stderr(&o)
    );
    let o = run(
        &["render", "--mesh", "missing.obj", "--out", "x.svg"],
        dir.path(),
    );
    assert_eq!(
        stderr(&o).matches("os error 2").count(),
        1,
        "{}",
        stderr(&o)
    );
}

/// A glTF with one triangle whose buffer is `uri` (12 floats: three positions).
fn gltf_with_buffer(uri: &str, byte_length: usize) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},
            "buffers":[{{"uri":"{uri}","byteLength":{byte_length}}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}]}}"#
    )
}

fn triangle_bytes() -> Vec<u8> {
    [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

#[test]
fn gltf_buffers_stay_in_the_models_directory() {
    let dir = tempfile::tempdir().unwrap();
    let models = dir.path().join("models");
    std::fs::create_dir(&models).unwrap();
    std::fs::write(dir.path().join("outside.bin"), triangle_bytes()).unwrap();
    std::fs::write(models.join("inside.bin"), triangle_bytes()).unwrap();
    let outside = dir.path().join("outside.bin");
    let outside_uri = format!("file://{}", outside.display());
    let absolute = outside.display().to_string();
    for uri in [
        "../outside.bin",
        "../../../../etc/passwd",
        "/etc/passwd",
        "file:///etc/passwd",
        outside_uri.as_str(),
        absolute.as_str(),
        "/dev/zero",
    ] {
        std::fs::write(models.join("m.gltf"), gltf_with_buffer(uri, 36)).unwrap();
        let o = run(
            &["render", "--mesh", "models/m.gltf", "--out", "x.svg"],
            dir.path(),
        );
        assert_refused(
            &o,
            &[
                "m.gltf",
                "outside the model's directory",
                "--allow-external-uris",
            ],
        );
    }
    // A symbolic link inside that leads out is refused too.
    std::os::unix::fs::symlink(&outside, models.join("link.bin")).unwrap();
    std::fs::write(models.join("m.gltf"), gltf_with_buffer("link.bin", 36)).unwrap();
    let o = run(
        &["render", "--mesh", "models/m.gltf", "--out", "x.svg"],
        dir.path(),
    );
    assert_refused(&o, &["symbolic link", "--allow-external-uris"]);
    // Inside the directory: read; outside with the option: read, but never a device.
    std::fs::write(models.join("m.gltf"), gltf_with_buffer("inside.bin", 36)).unwrap();
    assert_ok(&run(
        &["render", "--mesh", "models/m.gltf", "--out", "x.svg"],
        dir.path(),
    ));
    std::fs::write(
        models.join("m.gltf"),
        gltf_with_buffer("../outside.bin", 36),
    )
    .unwrap();
    let args = [
        "render",
        "--allow-external-uris",
        "--mesh",
        "models/m.gltf",
        "--out",
        "x.svg",
    ];
    assert_ok(&run(&args, dir.path()));
    std::fs::write(models.join("m.gltf"), gltf_with_buffer("/dev/zero", 36)).unwrap();
    let o = run_for(&args, dir.path(), Duration::from_secs(10));
    assert_refused(&o, &["/dev/zero", "not a regular file"]);
}

#[test]
fn gltf_lengths_that_lie_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A byteLength smaller than the data: accessors would read past it.
    let mut data = triangle_bytes();
    data.extend_from_slice(&[0u8; 64]);
    std::fs::write(d.join("b.bin"), &data).unwrap();
    std::fs::write(d.join("m.gltf"), gltf_with_buffer("b.bin", 24)).unwrap();
    let o = run(&["render", "--mesh", "m.gltf", "--out", "x.svg"], d);
    assert_refused(
        &o,
        &["m.gltf", "buffer view 0 runs past the end of buffer 0"],
    );

    // GLB: a header length that does not match the file.
    let glb = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/loaders/corpus/gltf/triangle.glb"),
    )
    .unwrap();
    std::fs::write(d.join("ok.glb"), &glb).unwrap();
    assert_ok(&run(&["render", "--mesh", "ok.glb", "--out", "x.svg"], d));
    for length in [0u32, 11, 20, glb.len() as u32 - 1, glb.len() as u32 + 1] {
        let mut bad = glb.clone();
        bad[8..12].copy_from_slice(&length.to_le_bytes());
        std::fs::write(d.join("bad.glb"), &bad).unwrap();
        let o = run(&["render", "--mesh", "bad.glb", "--out", "x.svg"], d);
        assert_refused(&o, &["bad.glb", "not a valid GLB file"]);
    }
    // A bad magic is said to be a bad magic, not bad JSON.
    let mut bad = glb.clone();
    bad[..4].copy_from_slice(b"glTX");
    std::fs::write(d.join("magic.glb"), &bad).unwrap();
    let o = run(&["render", "--mesh", "magic.glb", "--out", "x.svg"], d);
    assert_refused(
        &o,
        &[
            "magic.glb",
            "not a glTF file",
            "magic `glTF`",
            "[67 6c 54 58]",
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Silent wrong output

#[test]
fn an_obj_with_a_byte_order_mark_loses_no_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nl 3 4\n";
    std::fs::write(dir.path().join("plain.obj"), text).unwrap();
    std::fs::write(dir.path().join("bom.obj"), format!("\u{feff}{text}")).unwrap();
    let plain = wireflight::mesh::load(&dir.path().join("plain.obj")).unwrap();
    let bom = wireflight::mesh::load(&dir.path().join("bom.obj")).unwrap();
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

// ---------------------------------------------------------------------------------------------
// Files

#[test]
fn temporaries_of_a_killed_run_are_removed_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // PIDs beyond any pid_max: their processes are gone.
    std::fs::write(d.join(".old.csv.tmp-4294967295"), vec![0u8; 1000]).unwrap();
    std::fs::create_dir(d.join(".frames.tmp-4294967294")).unwrap();
    flight(d, "a.csv", &[]);
    let names: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["a.csv"]);
}

#[test]
fn sigterm_and_sigint_remove_the_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert_ok(&run(
        &["simulate", "--duration", "600", "--out", "a.csv"],
        d,
    ));
    for (signal, status) in [(libc::SIGTERM, 143), (libc::SIGINT, 130)] {
        let child = bin()
            .args([
                "render",
                "--flight",
                "a.csv",
                "--frames-dir",
                "frames",
                "--size",
                "320x240",
                "--backend",
                "cpu",
            ])
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until it writes frames into its temporary directory.
        let tmp = d.join(format!(".frames.tmp-{}", child.id()));
        let start = Instant::now();
        while std::fs::read_dir(&tmp).map_or(0, Iterator::count) < 2 {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "no frames appeared"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        // SAFETY: sending a signal to our own child.
        unsafe { libc::kill(child.id() as i32, signal) };
        let o = wait_for(child, Duration::from_secs(30), &["render"]);
        assert_eq!(
            o.status.code(),
            Some(status),
            "{:?} {}",
            o.status,
            stderr(&o)
        );
        assert!(!tmp.exists(), "the temporary directory is left");
        assert!(!d.join("frames").exists(), "a partial set of frames");
    }
}

#[test]
fn plots_are_written_as_a_set() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "a.csv", &[]);
    std::fs::create_dir(d.join("plots")).unwrap();
    std::fs::write(d.join("plots/keep.txt"), "mine").unwrap();
    assert_ok(&run(
        &["compare", "--flight", "a.csv", "--plots", "plots"],
        d,
    ));
    let mut names: Vec<String> = std::fs::read_dir(d.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.contains(&"keep.txt".to_string()), "{names:?}");
    assert!(
        names.iter().filter(|n| n.ends_with(".png")).count() >= 2,
        "{names:?}"
    );
    let stray: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");
}

#[test]
fn replacing_an_output_keeps_its_mode_and_writes_through_a_link() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("real")).unwrap();
    std::fs::write(d.join("real/out.csv"), "old").unwrap();
    std::fs::set_permissions(
        d.join("real/out.csv"),
        std::fs::Permissions::from_mode(0o600),
    )
    .unwrap();
    std::os::unix::fs::symlink("real/out.csv", d.join("out.csv")).unwrap();
    flight(d, "out.csv", &[]);
    assert!(std::fs::symlink_metadata(d.join("out.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    let text = std::fs::read_to_string(d.join("real/out.csv")).unwrap();
    assert!(text.contains("time_s"));
    let mode = std::fs::metadata(d.join("real/out.csv"))
        .unwrap()
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o600);
}

// ---------------------------------------------------------------------------------------------
// Messages

#[test]
fn negative_numbers_reach_the_options_own_check() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["render", "--fov", "-10", "--out", "x.svg"], dir.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.contains("field of view -10° is outside"), "{err}");
    let o = run(
        &["simulate", "--duration", "-5", "--out", "x.csv"],
        dir.path(),
    );
    assert!(
        stderr(&o).contains("duration -5 s must be positive"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &[
            "simulate",
            "--height",
            "-50",
            "--duration",
            "1",
            "--out",
            "x.csv",
        ],
        dir.path(),
    );
    assert_ok(&o);
}

#[test]
fn a_model_files_aircraft_is_found_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("models")).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/aircraft/aerosonde.toml"),
        d.join("models/mine.toml"),
    )
    .unwrap();
    std::fs::write(
        d.join("models/model.toml"),
        "vehicle = \"fixed-wing\"\naircraft = \"mine.toml\"\n",
    )
    .unwrap();
    let o = run(
        &[
            "simulate",
            "--model",
            "models/model.toml",
            "--duration",
            "1",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_ok(&o);
}

#[test]
fn read_handle_is_not_left_open_on_a_fifo() {
    // A FIFO is refused before anything waits on its writer.
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("f.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid C string; mkfifo only creates the file.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let o = run_for(
        &["compare", "--flight", "f.csv"],
        dir.path(),
        Duration::from_secs(10),
    );
    assert_refused(&o, &["f.csv", "not a regular file"]);
}

/// The drawn segment count `render` prints.
fn segments_drawn(o: &Output) -> usize {
    let text = String::from_utf8_lossy(&o.stdout);
    let before = text.split(" segments drawn").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap()
}

#[test]
fn no_blank_images_from_huge_angles_or_scales() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = run(&["render", "--out", "a.svg"], d);
    assert_ok(&base);
    let o = run(
        &[
            "render", "--yaw", "1e100", "--camera", "chase", "--out", "b.svg",
        ],
        d,
    );
    assert_ok(&o);
    assert!(
        segments_drawn(&o) > 0,
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let o = run(
        &[
            "render", "--yaw", "360", "--pitch", "-720", "--out", "c.svg",
        ],
        d,
    );
    assert_eq!(segments_drawn(&o), segments_drawn(&base));
    // Models beyond the sizes the cameras can draw are refused, naming the limit.
    let plane =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/plane.obj"))
            .unwrap();
    for (scale, ok) in [(1e20, false), (1e-31, false), (1e-6, true), (1e5, true)] {
        let scaled: Vec<String> = plane
            .lines()
            .map(|l| match l.strip_prefix("v ") {
                Some(v) => {
                    let p: Vec<String> = v
                        .split_whitespace()
                        .map(|c| format!("{:e}", c.parse::<f64>().unwrap() * scale))
                        .collect();
                    format!("v {}", p.join(" "))
                }
                None => l.to_string(),
            })
            .collect();
        std::fs::write(d.join("s.obj"), scaled.join("\n")).unwrap();
        for camera in ["chase", "cockpit", "top"] {
            let o = run(
                &[
                    "render", "--mesh", "s.obj", "--camera", camera, "--out", "s.svg",
                ],
                d,
            );
            if ok {
                assert_ok(&o);
                assert!(segments_drawn(&o) > 0, "scale {scale} {camera}: blank");
            } else {
                assert_refused(&o, &["s.obj", "bounding radius", "rescale"]);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Random extreme options: simulate → compare / diagnose

mod extremes {
    use super::*;
    use proptest::prelude::*;
    use proptest::sample::select;

    /// Exit 0 or 2 (never a panic, abort or signal) within `limit`; the status.
    fn status_of(args: &[String], dir: &Path, limit: Duration) -> i32 {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run_for(&args, dir, limit);
        let code = o.status.code();
        assert!(
            matches!(code, Some(0 | 2)),
            "`wireflight {}`: status {:?}\nstderr: {}",
            args.join(" "),
            o.status,
            stderr(&o)
        );
        code.unwrap_or(-1)
    }

    /// Mostly ordinary values, one time in six an extreme one (so that a third of the
    /// flights are made and analysed).
    fn mix(ordinary: Vec<f64>, extreme: Vec<f64>) -> impl Strategy<Value = f64> {
        prop_oneof![5 => select(ordinary), 1 => select(extreme)]
    }

    fn opt(name: &str, v: f64) -> [String; 2] {
        [format!("--{name}"), format!("{v:e}")]
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 16,
            failure_persistence: None,
            ..ProptestConfig::default()
        })]

        #[test]
        fn simulate_then_compare_and_diagnose_exit_0_or_2_in_bounded_time(
            point_mass in any::<bool>(),
            duration in mix(vec![0.5, 4.0, 20.0], vec![1e-3, 1e9, 1e300]),
            rate in mix(vec![0.5, 20.0, 50.0], vec![1e-6, 1e5]),
            noise_pos in mix(vec![0.0, 0.3], vec![1e6, 1e200]),
            noise_other in mix(vec![0.0, 0.5], vec![1e308]),
            speed in mix(vec![25.0], vec![0.0, 1e6, 1e200]),
            latitude in mix(vec![-90.0, 45.0], vec![95.0]),
            window in select(vec![0.1, 1.0, 8.0, 86_400.0]),
            offset in select(vec![0.0, 1.0, 1e9]),
            start_span in select(vec![None, Some(1e-3), Some(5.0)]),
            add in select(vec![None, Some("wind"), Some("actuator_lag:tau_s=0.001"), Some("drag:k=1e9")]),
        ) {
            let dir = tempfile::tempdir().unwrap();
            let d = dir.path();
            let mut sim: Vec<String> = vec!["simulate".into(), "--out".into(), "f.csv".into()];
            if point_mass {
                sim.extend(["--vehicle".into(), "point-mass".into()]);
                sim.extend(opt("launch-speed", speed.max(1.0) * 6.0));
            } else {
                sim.extend(opt("airspeed", speed));
            }
            sim.extend(opt("duration", duration));
            sim.extend(opt("rate", rate));
            sim.extend(opt("noise-pos", noise_pos));
            sim.extend(opt("noise-vel", noise_other));
            sim.extend(opt("noise-rate", noise_other));
            sim.extend(opt("latitude", latitude));
            if status_of(&sim, d, Duration::from_secs(60)) != 0 {
                return Ok(());
            }
            for cmd in ["compare", "diagnose"] {
                let mut args: Vec<String> = vec![cmd.into(), "--flight".into(), "f.csv".into()];
                args.extend(opt("window", window));
                args.extend(opt("window-offset", offset));
                if let Some(s) = start_span {
                    args.extend(opt("start-span", s));
                }
                if let (Some(a), "compare") = (add, cmd) {
                    args.extend(["--add".into(), a.into()]);
                }
                status_of(&args, d, Duration::from_secs(120));
            }
        }
    }
}
