//! The `wireflight` binary end to end: outputs, printed counts, SVG contents, and errors.

use std::path::Path;

use wireflight::draw::render::Image;
use wireflight::draw::scene::attitude::from_aerospace_degrees;
use wireflight::draw::scene::{frame, ViewSpec};
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::support::cli::{ok, refused, stderr, stdout, wireflight};
use crate::support::flights::Flight;

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
    let text = ok(&[
        "render",
        "--backend",
        "cpu",
        "--size",
        "320x240",
        "--out",
        out.to_str().unwrap(),
    ]);
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
    let said = ok(&[
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
    let svg = std::fs::read_to_string(&out).unwrap();
    let lines = svg_lines(&svg);

    let spec = ViewSpec {
        attitude: from_aerospace_degrees(20.0, -10.0, 35.0),
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
        said.contains(&format!("{} segments drawn", lines.len())),
        "{said}"
    );
}

/// The nose tip of `render --camera side` (seen from the right, the nose to the right of the
/// picture): the rightmost point drawn, in pixels from the SVG.
fn side_view_nose(pitch: &str, dir: &Path) -> [f32; 2] {
    let out = dir.join(format!("side{pitch}.svg"));
    ok(&[
        "render",
        "--camera",
        "side",
        "--pitch",
        pitch,
        "--world",
        "none",
        "--size",
        "400x400",
        "--out",
        out.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&out).unwrap();
    svg_lines(&svg)
        .iter()
        .flat_map(|l| [[l[0], l[1]], [l[2], l[3]]])
        .max_by(|a, b| a[0].total_cmp(&b[0]))
        .unwrap()
}

/// Angles on the command line are aerospace: `--pitch 20` raises the nose (pixel y grows
/// downward), `--pitch -20` lowers it, as the HUD and flight data read them.
#[test]
fn render_pitch_up_draws_the_nose_up() {
    let dir = tempfile::tempdir().unwrap();
    let level = side_view_nose("0", dir.path());
    let up = side_view_nose("20", dir.path());
    let down = side_view_nose("-20", dir.path());
    assert!(
        up[1] < level[1] - 20.0,
        "nose up: {up:?} vs level {level:?}"
    );
    assert!(
        down[1] > level[1] + 20.0,
        "nose down: {down:?} vs level {level:?}"
    );
    // And the library's crossing says the same: the nose vertex goes up (+Z) in the world.
    let nose = from_aerospace_degrees(0.0, 20.0, 0.0).to_matrix() * glam::DVec3::X;
    assert!(
        (nose.z - 20f64.to_radians().sin()).abs() < 1e-12,
        "{nose:?}"
    );
}

/// One flag, one meaning: `--mesh` a wireframe, `--model` a flight model, `--flight` data.
/// The old spellings still work, with a note on stderr; `render --model` takes a mesh file
/// only, and a flight model (TOML) there is refused, saying what to use.
#[test]
fn old_spellings_work_with_a_note_and_render_model_is_a_mesh_only() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cube.svg");
    let cube = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/examples/cube.obj");
    let o = wireflight(&[
        "render",
        "--model",
        cube,
        "--world",
        "none",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--model is an old spelling of --mesh"),
        "{}",
        stderr(&o)
    );
    assert!(stdout(&o).contains("12 segments drawn"), "{}", stdout(&o));
    let o = wireflight(&["render", "--mesh", cube, "--out", out.to_str().unwrap()]);
    assert!(
        o.status.success() && stderr(&o).is_empty(),
        "{}",
        stderr(&o)
    );

    let model = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/examples/model.toml");
    let o = wireflight(&["render", "--model", model, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("not a flight model") && stderr(&o).contains("--mesh"),
        "{}",
        stderr(&o)
    );

    let missing = dir.path().join("missing.csv");
    for (args, note) in [
        (
            vec!["compare", "--data", missing.to_str().unwrap()],
            "--data is an old spelling of --flight",
        ),
        (
            vec!["diagnose", "--quiet", "--data=nothing.csv"],
            "--data is an old spelling of --flight",
        ),
        (
            vec![
                "view",
                "--flight",
                missing.to_str().unwrap(),
                "--flight-model",
                model,
            ],
            "--flight-model is an old spelling of --model",
        ),
    ] {
        let o = wireflight(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(note), "{args:?}: {}", stderr(&o));
    }
    // The new spellings get no note.
    let o = wireflight(&["compare", "--flight", missing.to_str().unwrap()]);
    assert!(!stderr(&o).contains("old spelling"), "{}", stderr(&o));
}

/// Every command's help puts the global options under their own heading, and the replays of
/// `render` and `compare` share one --fps default.
#[test]
fn global_options_have_their_heading_and_fps_one_default() {
    for command in [
        "render", "simulate", "compare", "diagnose", "identify", "view", "euler", "clip", "import",
        "keys",
    ] {
        let o = wireflight(&[command, "--help"]);
        let text = stdout(&o);
        let heading = text
            .find("Global options (every command):")
            .unwrap_or_else(|| panic!("{command}: no heading\n{text}"));
        for option in ["--max-input-mb", "--allow-external-uris", "--quiet"] {
            let at = text.find(option).unwrap();
            assert!(at > heading, "{command}: {option} outside the heading");
        }
    }
    for command in ["render", "compare"] {
        let text = stdout(&wireflight(&[command, "--help"]));
        let fps = &text[text.find("--fps").unwrap()..];
        let fps = &fps[..fps.find("\n\n").unwrap_or(fps.len())];
        assert!(fps.contains("[default: 25]"), "{command}: {fps}");
    }
}

/// `wireflight keys` lists every aircraft key with its unit and range and the set's value.
#[test]
fn keys_lists_every_aircraft_key() {
    let text = ok(&["keys"]);
    for k in wireflight::flight::params::keys::KEYS {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(k.name))
            .unwrap_or_else(|| panic!("{} missing:\n{text}", k.name));
        assert!(line.contains(k.unit) && line.contains(k.term), "{line}");
    }
    assert!(
        text.contains("-1000..1000") && text.contains("aerosonde"),
        "{text}"
    );
    let c172 = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/aircraft/c172p.toml");
    let o = wireflight(&["keys", "--aircraft", c172]);
    assert!(stdout(&o).contains("c172p"), "{}", stdout(&o));
    refused(&["keys", "--aircraft", "cesna"]);
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
    let err = refused(&["render", "--model", missing.to_str().unwrap(), "--out", out]);
    assert!(err.contains("no-such-model.obj"), "{err}");

    let err = refused(&[
        "render",
        "--out",
        dir.path().join("x.jpg").to_str().unwrap(),
    ]);
    assert!(err.contains("x.jpg") && err.contains(".png"), "{err}");

    let o = wireflight(&["render", "--pitch", "nan", "--out", out]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("finite"), "{}", stderr(&o));

    let o = wireflight(&["render", "--size", "0x10", "--out", out]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("width"), "{}", stderr(&o));

    // Writing into a directory that does not exist: error names the path, nothing is left.
    let err = refused(&[
        "render",
        "--backend",
        "cpu",
        "--out",
        dir.path().join("nope/x.png").to_str().unwrap(),
    ]);
    assert!(err.contains("nope"), "{err}");
    assert!(stray_files(dir.path(), &["no-such-model.obj"]).is_empty());
}

#[test]
fn gimbal_lock_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.svg");
    let said = ok(&[
        "render",
        "--pitch",
        "90",
        "--roll",
        "30",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(said.contains("gimbal lock"), "{said}");
}

#[test]
fn simulate_then_replay_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("test.csv");
    let flight = |seed: &str| {
        Flight::new()
            .manoeuvre("flight-test")
            .duration(12)
            .rate(20)
            .hidden("wind:north_mps=4,east_mps=-2")
            .noise_pos(0.3)
            .noise_att(0.2)
            .seed(seed)
    };
    let said = ok(&flight("7").args(&csv));
    assert!(said.contains("1 hidden"), "{said}");
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
    let again = flight("7").write(dir.path(), "again.csv");
    assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes());
    let other = flight("8").write(dir.path(), "other.csv");
    assert_ne!(std::fs::read(&other).unwrap(), text.as_bytes());

    let frames = dir.path().join("frames");
    ok(&[
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
        // Slips get the nearest name, in every command that resolves the names.
        (
            vec!["simulate", "--hidden", "wnd:north_mps=3", "--out", out],
            "unknown effect `wnd`: did you mean `wind`?",
        ),
        (
            vec!["simulate", "--add", "wind:nort_mps=3", "--out", out],
            "no parameter `nort_mps`: did you mean `north_mps`?",
        ),
        (
            vec!["simulate", "--hidden", "aircraft:c_m_alfa=-3", "--out", out],
            "is not an aircraft parameter: did you mean `c_m_alpha`?",
        ),
        (
            vec!["simulate", "--effects", "drga", "--out", out],
            "did you mean `drag`?",
        ),
    ] {
        let err = refused(&args);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    assert!(stray_files(dir.path(), &[]).is_empty());
}
