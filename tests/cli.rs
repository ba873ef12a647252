//! The `wireflight` binary end to end: outputs, printed counts, SVG contents, and errors.

use std::path::Path;
use std::process::{Command, Output};

use wireflight::app::render::{frame, ViewSpec};
use wireflight::euler::EulerZyx;
use wireflight::mesh::plane::builtin_plane;
use wireflight::pipeline::Viewport;
use wireflight::render::Image;

fn wireflight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wireflight"))
        .args(args)
        .output()
        .expect("run wireflight")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
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
