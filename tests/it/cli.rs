//! The `wireflight` binary end to end: outputs, printed counts, SVG contents, and errors.

use std::path::Path;
use std::process::{Command, Output};

use wireflight::euler::EulerZyx;
use wireflight::mesh::plane::builtin_plane;
use wireflight::pipeline::Viewport;
use wireflight::render::Image;
use wireflight::scene::{frame, ViewSpec};

pub(crate) fn wireflight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wireflight"))
        .args(args)
        .output()
        .expect("run wireflight")
}

pub(crate) fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Files in `dir` other than the expected outputs (e.g. leftover temporaries).
fn stray_files(dir: &Path, expected: &[&str]) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !expected.contains(&n.as_str()))
        .collect()
}

#[test]
fn render_png_on_cpu_writes_the_image_and_prints_counts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plane.png");
    let o = wireflight(&[
        "render",
        "--backend",
        "cpu",
        "--size",
        "320x240",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("edges in") && text.contains("trivially accepted"),
        "{text}"
    );
    let image = Image::decode_png(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((image.width, image.height), (320, 240));
    assert!(stray_files(dir.path(), &["plane.png"]).is_empty());
}

/// Parse the `<line>` elements of our SVG output.
fn svg_lines(svg: &str) -> Vec<[f32; 4]> {
    svg.lines()
        .filter(|l| l.trim_start().starts_with("<line"))
        .map(|l| {
            let attr = |name: &str| -> f32 {
                let key = format!("{name}=\"");
                let start = l.find(&key).unwrap() + key.len();
                let end = start + l[start..].find('"').unwrap();
                l[start..end].parse().unwrap()
            };
            [attr("x1"), attr("y1"), attr("x2"), attr("y2")]
        })
        .collect()
}

#[test]
fn svg_lists_exactly_the_clipped_segments() {
    // A view that clips: half out of frame and banked.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("half.svg");
    let o = wireflight(&[
        "render",
        "--yaw",
        "20",
        "--pitch",
        "-10",
        "--roll",
        "35",
        "--pan",
        "1.4,0.3",
        "--world",
        "none",
        "--size",
        "640x480",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&out).unwrap();
    let lines = svg_lines(&svg);

    let spec = ViewSpec {
        attitude: EulerZyx::from_degrees(20.0, -10.0, 35.0),
        viewport: Viewport {
            width: 640,
            height: 480,
        },
        pan: [1.4, 0.3],
        ..ViewSpec::default()
    };
    let (scene, stats) = frame(&builtin_plane(), &spec);
    assert!(stats.clipped > 0 && stats.trivially_rejected > 0, "{stats}");
    let segments = &scene.batches[0].segments;
    assert_eq!(lines.len() as u64, stats.drawn());
    assert_eq!(lines.len(), segments.len());
    for (l, s) in lines.iter().zip(segments) {
        // Shortest round-trip formatting: bit-identical after parsing.
        assert_eq!(*l, [s.a.x, s.a.y, s.b.x, s.b.y]);
    }
    // The printed count of drawn segments matches the file.
    assert!(
        stdout(&o).contains(&format!("{} segments drawn", lines.len())),
        "{}",
        stdout(&o)
    );
}

#[test]
fn help_has_examples() {
    let o = wireflight(&["render", "--help"]);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(
        text.contains("Examples:") && text.contains("--camera cockpit"),
        "{text}"
    );
}

#[test]
fn bad_inputs_fail_cleanly_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();

    let missing = dir.path().join("no-such-model.obj");
    let o = wireflight(&["render", "--model", missing.to_str().unwrap(), "--out", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no-such-model.obj"), "{}", stderr(&o));

    let o = wireflight(&[
        "render",
        "--out",
        dir.path().join("x.jpg").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("x.jpg") && stderr(&o).contains(".png"),
        "{}",
        stderr(&o)
    );

    let o = wireflight(&["render", "--pitch", "nan", "--out", out]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("finite"), "{}", stderr(&o));

    let o = wireflight(&["render", "--size", "0x10", "--out", out]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("width"), "{}", stderr(&o));

    // Writing into a directory that does not exist: error names the path, nothing is left.
    let o = wireflight(&[
        "render",
        "--backend",
        "cpu",
        "--out",
        dir.path().join("nope/x.png").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("nope"), "{}", stderr(&o));
    assert!(stray_files(dir.path(), &["no-such-model.obj"]).is_empty());
}

#[test]
fn gimbal_lock_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.svg");
    let o = wireflight(&[
        "render",
        "--pitch",
        "90",
        "--roll",
        "30",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("gimbal lock"), "{}", stdout(&o));
}

#[test]
fn simulate_then_replay_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("test.csv");
    let args = |out: &Path, seed: &str| {
        vec![
            "simulate".to_string(),
            "--manoeuvre".into(),
            "flight-test".into(),
            "--duration".into(),
            "12".into(),
            "--rate".into(),
            "20".into(),
            "--hidden".into(),
            "wind:north_mps=4,east_mps=-2".into(),
            "--noise-pos".into(),
            "0.3".into(),
            "--noise-att".into(),
            "0.2".into(),
            "--seed".into(),
            seed.into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ]
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        wireflight(&a)
    };
    let o = run(args(&csv, "7"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("1 hidden"), "{}", stdout(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        !text.contains("wind"),
        "a hidden effect must leave no trace in the file"
    );
    assert_eq!(
        text.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 241
    );

    // Deterministic for a seed, different for another.
    let again = dir.path().join("again.csv");
    assert!(run(args(&again, "7")).status.success());
    assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes());
    let other = dir.path().join("other.csv");
    assert!(run(args(&other, "8")).status.success());
    assert_ne!(std::fs::read(&other).unwrap(), text.as_bytes());

    let frames = dir.path().join("frames");
    let o = wireflight(&[
        "render",
        "--flight",
        csv.to_str().unwrap(),
        "--frames-dir",
        frames.to_str().unwrap(),
        "--fps",
        "2",
        "--size",
        "160x120",
        "--backend",
        "cpu",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 25, "{names:?}");
    assert_eq!(names[0], "frame_00000.png");
    let img = Image::decode_png(&std::fs::read(frames.join("frame_00012.png")).unwrap()).unwrap();
    assert_eq!((img.width, img.height), (160, 120));
}

#[test]
fn simulate_rejects_bad_requests_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    let out = out.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["simulate", "--manoeuvre", "loop", "--out", out],
            "unknown manoeuvre",
        ),
        (
            vec!["simulate", "--manoeuvre", "ballistic", "--out", out],
            "not for a fixed-wing",
        ),
        (
            vec!["simulate", "--hidden", "magic", "--out", out],
            "unknown effect",
        ),
        (
            vec![
                "simulate",
                "--vehicle",
                "point-mass",
                "--add",
                "prop_torque",
                "--out",
                out,
            ],
            "does not apply",
        ),
        (
            vec!["simulate", "--add", "wind:speed=3", "--out", out],
            "no parameter `speed`",
        ),
        (vec!["simulate", "--airspeed", "3", "--out", out], "trim"),
    ] {
        let o = wireflight(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
    assert!(stray_files(dir.path(), &[]).is_empty());
}
