//! Hostile-input reproductions, one test each: hostile inputs and options give a clear error
//! (exit 2) naming the input and the limit, or work; never a panic (101), an abort (134), a
//! hang, unbounded memory, or a silently wrong result.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

use crate::support::cli::{command, stderr, wait_timed, wireflight_in_timed};
use crate::support::flights::Flight;

mod commands;
mod extremes;
mod files;
mod messages;
mod outputs;
mod ranges;
mod ulog;
mod wrong_output;

/// The longest any of these runs may take: past it, the test fails as a hang.
const HANG: Duration = Duration::from_secs(120);

/// `wireflight ARGS` in `dir`, failing the test as a hang past [`HANG`].
fn run<S: AsRef<OsStr>>(args: &[S], dir: &Path) -> Output {
    wireflight_in_timed(dir, args, HANG)
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
    let mut args = Flight::new().duration(12).noise_pos(0.2).args(name);
    args.extend(extra.iter().map(|a| a.to_string()));
    assert_ok(&wireflight_in_timed(dir, &args, HANG));
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
    // Refused as an option now; the read-back check below it stays for what no option bounds.
    assert_refused(&o, &["--noise-pos", "more noise"]);
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
    assert_refused(&o, &["--noise-rate", "more noise"]);
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
        let mut child = command()
            .args(args)
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // `| head -0`: the reader is gone before anything is written.
        drop(child.stdout.take());
        let o = wait_timed(child, args, HANG);
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
    let o = wireflight_in_timed(
        d,
        &["simulate", "--duration", "1e9", "--out", "x.csv"],
        limit,
    );
    assert_refused(&o, &["50000000001 samples", "--max-samples 2000000"]);
    let o = wireflight_in_timed(
        d,
        &["simulate", "--duration", "1e5", "--out", "x.csv"],
        limit,
    );
    assert_refused(&o, &["--max-samples"]);
    // The option raises (and lowers) the limit.
    let o = wireflight_in_timed(
        d,
        &[
            "simulate",
            "--duration",
            "10",
            "--max-samples",
            "100",
            "--out",
            "x.csv",
        ],
        limit,
    );
    assert_refused(&o, &["501 samples", "--max-samples 100"]);
    let o = wireflight_in_timed(
        d,
        &[
            "simulate",
            "--duration",
            "10",
            "--max-samples",
            "501",
            "--out",
            "x.csv",
        ],
        limit,
    );
    assert_ok(&o);
}

#[test]
fn a_tiny_rate_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = wireflight_in_timed(
        dir.path(),
        &[
            "simulate",
            "--duration",
            "10",
            "--rate",
            "1e-6",
            "--out",
            "x.csv",
        ],
        Duration::from_secs(10),
    );
    assert_refused(&o, &["single sample", "1/duration"]);
    // Low but sensible rates integrate in bounded steps.
    let o = wireflight_in_timed(
        dir.path(),
        &[
            "simulate",
            "--duration",
            "1e6",
            "--rate",
            "0.01",
            "--out",
            "x.csv",
        ],
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
    let o = wireflight_in_timed(
        dir.path(),
        &["render", "--flight", "gap.csv", "--frames-dir", "frames"],
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
    let o = wireflight_in_timed(d, &["compare", "--data", "/dev/zero"], limit);
    assert_refused(&o, &["/dev/zero", "not a regular file"]);
    let o = wireflight_in_timed(
        d,
        &["render", "--mesh", "/dev/zero", "--out", "x.svg"],
        limit,
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    std::fs::create_dir(d.join("dir.csv")).unwrap();
    let o = wireflight_in_timed(d, &["compare", "--flight", "dir.csv"], limit);
    assert_refused(&o, &["dir.csv", "is a directory"]);
    // Over the size limit, naming the option that raises it.
    std::fs::write(d.join("big.obj"), vec![b'#'; 3 << 20]).unwrap();
    let o = wireflight_in_timed(
        d,
        &[
            "render",
            "--max-input-mb",
            "2",
            "--mesh",
            "big.obj",
            "--out",
            "x.svg",
        ],
        limit,
    );
    assert_refused(&o, &["big.obj", "3145728 bytes", "--max-input-mb"]);
    // Every reader takes the same limit: a column-mapped CSV and a ULog too.
    std::fs::write(d.join("big.csv"), vec![b'#'; 3 << 20]).unwrap();
    let o = wireflight_in_timed(
        d,
        &[
            "import",
            "--max-input-mb",
            "2",
            "--flight",
            "big.csv",
            "--columns",
            "time=t,north=n,east=e,down=d",
        ],
        limit,
    );
    assert_refused(&o, &["big.csv", "3145728 bytes", "--max-input-mb"]);
    std::fs::write(d.join("big.ulg"), vec![0u8; 3 << 20]).unwrap();
    let o = wireflight_in_timed(
        d,
        &["import", "--max-input-mb", "2", "--flight", "big.ulg"],
        limit,
    );
    assert_refused(&o, &["big.ulg", "--max-input-mb"]);
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
    let o = wireflight_in_timed(dir.path(), &args, Duration::from_secs(10));
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
