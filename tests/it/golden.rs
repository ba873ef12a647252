//! Golden images of the CPU backend: exact, byte for byte.
//!
//! Each case names its parameters: aerospace yaw, pitch and roll (+ nose right, + nose up, +
//! right wing down), as `render` takes them. To re-bless after an intended change, run
//! `WIREFLIGHT_BLESS=1 cargo test --test it golden::` and look at every image in
//! `tests/images/golden/` before committing.

use std::path::PathBuf;

use wireflight::draw::render::{cpu, Image};
use wireflight::draw::scene::attitude::from_aerospace_degrees;
use wireflight::draw::scene::palette;
use wireflight::draw::scene::{frame, ViewSpec};
use wireflight::geometry::camera::CameraPreset;
use wireflight::geometry::clip::{ClipStats, DepthRange};
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

/// A view of the built-in aircraft at aerospace yaw, pitch and roll (degrees).
fn spec(yaw: f64, pitch: f64, roll: f64, camera: CameraPreset) -> ViewSpec {
    ViewSpec {
        attitude: from_aerospace_degrees(yaw, pitch, roll),
        camera,
        viewport: Viewport {
            width: 480,
            height: 360,
        },
        ..ViewSpec::default()
    }
}

/// Render on the CPU and compare with (or, when blessing, write) the golden image.
fn check(name: &str, spec: ViewSpec) -> ClipStats {
    let (scene, stats) = frame(&builtin_plane(), &spec);
    check_image(name, &cpu::render(&scene));
    stats
}

/// Compare `image` with the golden image `tests/images/golden/{name}.png`, pixel for pixel (or,
/// when blessing, write it there).
pub(crate) fn check_image(name: &str, image: &Image) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/images/golden")
        .join(format!("{name}.png"));
    if std::env::var_os("WIREFLIGHT_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, image.encode_png().unwrap()).unwrap();
        return;
    }
    let bytes = std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (run with WIREFLIGHT_BLESS=1 to create)",
            path.display()
        )
    });
    let golden = Image::decode_png(&bytes).unwrap();
    assert_eq!((image.width, image.height), (golden.width, golden.height));
    if *image != golden {
        let diff = image
            .pixels
            .chunks_exact(4)
            .zip(golden.pixels.chunks_exact(4))
            .filter(|(a, b)| a != b)
            .count();
        let out = std::env::temp_dir().join(format!("wireflight-{name}-actual.png"));
        std::fs::write(&out, image.encode_png().unwrap()).unwrap();
        panic!(
            "{name}: {diff} pixels differ from {}; actual image written to {}",
            path.display(),
            out.display()
        );
    }
}

fn lit_pixels(image: &Image) -> usize {
    image
        .pixels
        .chunks_exact(4)
        .filter(|p| *p != palette::BACKGROUND)
        .count()
}

#[test]
fn level_chase_yaw0_pitch0_roll0() {
    let stats = check(
        "level_chase_yaw0_pitch0_roll0",
        spec(0.0, 0.0, 0.0, CameraPreset::Chase),
    );
    // The default frame shows the whole aircraft: nothing is clipped.
    assert_eq!(stats.trivially_accepted, stats.edges_in);
}

#[test]
fn banked_climbing_turn_chase_yawm30_pitch15_roll40() {
    check(
        "banked_chase_yaw-30_pitch15_roll40",
        spec(-30.0, 15.0, 40.0, CameraPreset::Chase),
    );
}

#[test]
fn top_view_yawm45() {
    check(
        "top_yaw-45_pitch0_roll0",
        spec(-45.0, 0.0, 0.0, CameraPreset::Top),
    );
}

#[test]
fn side_view_nose_up_pitch20() {
    check(
        "side_yaw0_pitch20_roll0",
        spec(0.0, 20.0, 0.0, CameraPreset::Side),
    );
}

#[test]
fn front_view_roll30() {
    check(
        "front_yaw0_pitch0_roll30",
        spec(0.0, 0.0, 30.0, CameraPreset::Front),
    );
}

#[test]
fn gimbal_lock_pitchm90_roll30_side() {
    check(
        "side_yaw0_pitch-90_roll30",
        spec(0.0, -90.0, 30.0, CameraPreset::Side),
    );
}

#[test]
fn half_out_of_frame_pan_right() {
    let mut s = spec(0.0, 0.0, 0.0, CameraPreset::Chase);
    s.pan = [1.6, 0.0];
    let stats = check("chase_pan1.6_half_out", s);
    assert!(stats.clipped > 0, "{stats}");
    assert!(stats.trivially_rejected > 0, "{stats}");
}

#[test]
fn camera_inside_the_plane_cockpit_near_plane_cuts() {
    let stats = check(
        "cockpit_yaw0_pitch0_roll0",
        spec(0.0, 0.0, 0.0, CameraPreset::Cockpit),
    );
    // Edges around the pilot's head cross the near plane or the sides.
    assert!(stats.clipped > 0, "{stats}");
    assert!(stats.trivially_rejected > 0, "{stats}");
}

#[test]
fn orthographic_top() {
    let mut s = spec(20.0, 0.0, 0.0, CameraPreset::Top);
    s.orthographic = true;
    check("top_ortho_yaw20", s);
}

#[test]
fn both_depth_conventions_draw_the_same_picture() {
    // OpenGL's −w..w volume and wgpu's 0..w volume differ only in the depth mapping; with the
    // projection built for each, the 2D segments agree (to float rounding).
    for camera in [CameraPreset::Chase, CameraPreset::Cockpit] {
        let a = spec(10.0, -5.0, 20.0, camera);
        let b = ViewSpec {
            depth: DepthRange::NegOneToOne,
            ..a
        };
        let (sa, stats_a) = frame(&builtin_plane(), &a);
        let (sb, stats_b) = frame(&builtin_plane(), &b);
        assert_eq!(stats_a.drawn(), stats_b.drawn(), "{camera:?}");
        for (x, y) in sa.batches[0].segments.iter().zip(&sb.batches[0].segments) {
            assert!(
                x.a.distance(y.a) < 1e-2 && x.b.distance(y.b) < 1e-2,
                "{camera:?}: {x:?} vs {y:?}"
            );
        }
    }
}

#[test]
fn images_are_not_blank() {
    let (scene, _) = frame(&builtin_plane(), &spec(0.0, 0.0, 0.0, CameraPreset::Chase));
    let lit = lit_pixels(&cpu::render(&scene));
    assert!(lit > 1500, "only {lit} lit pixels");
}
