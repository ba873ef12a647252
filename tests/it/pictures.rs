//! Pictures that explain themselves, held byte for byte (CPU backend): a still with the
//! horizon, a replay of a real PX4 log with its time stamp, and a comparison GIF with both
//! aircraft and the labelled error strip. The README shows these files. To re-bless after an
//! intended change: `WIREFLIGHT_BLESS=1 cargo test --test it pictures::`, then look at them.

use std::path::{Path, PathBuf};

use wireflight::draw::render::cpu;
use wireflight::draw::scene::attitude::from_aerospace_degrees;
use wireflight::draw::scene::still::{still, StillWorld};
use wireflight::draw::scene::ViewSpec;
use wireflight::geometry::camera::CameraPreset;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::support::cli::{ok, ok_with_stderr, stderr, wireflight};
use crate::support::data_file;
use crate::support::flights::Flight;

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/images/golden")
        .join(name)
}

/// `bytes` must equal the golden file `name` (written instead under `WIREFLIGHT_BLESS`).
fn check_golden_bytes(name: &str, bytes: &[u8]) {
    let path = golden_path(name);
    if std::env::var_os("WIREFLIGHT_BLESS").is_some() {
        std::fs::write(&path, bytes).unwrap();
        return;
    }
    let golden = std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (run with WIREFLIGHT_BLESS=1 to create)",
            path.display()
        )
    });
    if golden != bytes {
        let out = std::env::temp_dir().join(format!("wireflight-actual-{name}"));
        std::fs::write(&out, bytes).unwrap();
        panic!(
            "{name} differs from {}; actual written to {}",
            path.display(),
            out.display()
        );
    }
}

fn gif_frames(path: &Path) -> (usize, u16, (u16, u16)) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let size = (d.width(), d.height());
    let mut n = 0;
    let mut delay = 0;
    while let Some(f) = d.read_next_frame().unwrap() {
        delay = f.delay;
        n += 1;
    }
    (n, delay, size)
}

/// `render --camera cockpit --roll 30` shows the roll: the horizon is tilted by 30°.
#[test]
fn still_with_horizon_and_ground() {
    let spec = ViewSpec {
        attitude: from_aerospace_degrees(0.0, 0.0, 30.0),
        camera: CameraPreset::Cockpit,
        viewport: Viewport {
            width: 480,
            height: 360,
        },
        ..ViewSpec::default()
    };
    let (scene, _) = still(&builtin_plane(), &spec, StillWorld::Grid);
    let image = cpu::render(&scene);
    check_golden_bytes("world_cockpit_roll30.png", &image.encode_png().unwrap());
}

/// A real PX4 log replayed to a GIF with one command; frames carry the time stamp; no progress
/// bar on a stderr that is not a terminal.
#[test]
fn px4_log_replayed_to_a_gif() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hop.gif");
    let log = data_file("px4-sitl-hop.ulg");
    let (stdout, stderr) = ok_with_stderr(&[
        "render",
        "--flight",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--fps",
        "2",
        "--size",
        "256x192",
        "--backend",
        "cpu",
    ]);
    assert!(stdout.contains("wrote 62 GIF frames"), "{stdout}");
    assert!(!stderr.contains("frames ["), "progress on a pipe: {stderr}");
    assert!(stderr.contains("PX4 ULog"), "the report: {stderr}");
    assert_eq!(gif_frames(&out), (62, 50, (256, 192)));
    check_golden_bytes("px4_hop_replay.gif", &std::fs::read(&out).unwrap());
    // --quiet leaves only the result.
    let (_, stderr) = ok_with_stderr(&[
        "render",
        "--flight",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--fps",
        "1",
        "--size",
        "64x48",
        "--backend",
        "cpu",
        "--quiet",
    ]);
    assert!(stderr.is_empty(), "{stderr}");
}

/// `compare --out FILE.gif`: both aircraft, the trail, the labelled error strip, the time.
#[test]
fn comparison_gif() {
    let dir = tempfile::tempdir().unwrap();
    let csv = Flight::new()
        .manoeuvre("climbing-turn")
        .duration(24)
        .hidden("wind:north_mps=4,east_mps=-3")
        .noise_pos(0.5)
        .noise_att(0.3)
        .seed(7)
        .write(dir.path(), "windy.csv");
    let out = dir.path().join("compare.gif");
    let said = ok(&[
        "compare",
        "--flight",
        csv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--fps",
        "2",
        "--size",
        "400x300",
        "--json",
    ]);
    // JSON alone on stdout.
    let v: serde_json::Value = serde_json::from_str(&said).expect("JSON");
    assert!(v["error"]["total"].as_f64().unwrap() > 0.0);
    assert_eq!(gif_frames(&out), (49, 50, (400, 300)));
    check_golden_bytes("windy_compare.gif", &std::fs::read(&out).unwrap());
    let o = wireflight(&[
        "compare",
        "--flight",
        csv.to_str().unwrap(),
        "--out",
        "x.png",
    ]);
    assert!(
        stderr(&o).contains("x.png: --out writes an animated GIF"),
        "{}",
        stderr(&o)
    );
}
