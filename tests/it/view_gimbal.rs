//! The window's Euler-angle panel (`wireflight view`, key G, `--gimbal`): the gimbal rings
//! around the aircraft and the sliders that set or show the angles of any convention.
//!
//! Most of it drives the viewer's session directly (no display needed); one test opens the
//! window under the X display (see `view.rs` for how those run and skip).

use std::time::Duration;

use glam::{DMat3, DVec3};
use wireflight::app::view::cameras::CameraMode;
use wireflight::app::view::flight::Start;
use wireflight::app::view::gimbal::EulerPanel;
use wireflight::app::view::session::{Held, Session};
use wireflight::draw::render::{cpu, Image, Rgba};
use wireflight::draw::scene::attitude::{aerospace_degrees, viewer_from_aerospace};
use wireflight::draw::scene::palette::{EULER_FIRST, EULER_SECOND, EULER_THIRD};
use wireflight::geometry::euler::{Convention, EulerAngles, Gimbal, Lock};
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::support::cli::wireflight_timed;
use crate::view::{display, WINDOW_TIMEOUT};

const VIEW: Viewport = Viewport {
    width: 640,
    height: 360,
};

fn session() -> Session {
    Session::fly(
        builtin_plane(),
        Start::default(),
        None,
        CameraMode::Chase,
        55f32.to_radians(),
    )
}

fn pixels(image: &Image, color: Rgba) -> usize {
    image.pixels.chunks_exact(4).filter(|p| *p == color).count()
}

fn ring_pixels(image: &Image) -> [usize; 3] {
    [EULER_FIRST, EULER_SECOND, EULER_THIRD].map(|c| pixels(image, c))
}

/// Sliders set the attitude: the aircraft takes the rotation of the angles, the rings are
/// drawn in the three colours, the flight pauses; at z-y-x pitch 90° the HUD and the panel
/// report gimbal lock; hiding the panel removes the rings.
#[test]
fn sliders_set_the_attitude_and_the_rings_are_drawn() {
    let mut s = session();
    s.build(VIEW);
    assert_eq!(ring_pixels(&cpu::render(s.scene())), [0, 0, 0], "hidden");

    s.set_euler_degrees([60.0, 90.0, 0.0]);
    assert!(s.paused);
    s.advance(1.0 / 60.0, &Held::default());
    s.build(VIEW);
    // The panel's angles are aerospace: pitch +90° is nose straight up.
    let expected = viewer_from_aerospace(
        EulerAngles::from_degrees(Convention::VIEWER, [60.0, 90.0, 0.0]).to_matrix(),
    );
    assert!(s.attitude_matrix().abs_diff_eq(expected, 1e-9));
    assert!((s.attitude_matrix() * DVec3::X).z > 0.999_999, "nose up");
    let r = s.readout();
    assert_eq!(r.gimbal, Gimbal::LockedNoseUp);
    assert_eq!(s.euler.lock(), Lock::Upper);
    let image = cpu::render(s.scene());
    let rings = ring_pixels(&image);
    assert!(rings.iter().all(|&n| n > 100), "{rings:?}");

    // The keys do not turn an aircraft the sliders hold, even flying.
    s.toggle_pause();
    let held = Held {
        roll_right: true,
        ..Held::default()
    };
    for _ in 0..30 {
        s.advance(1.0 / 60.0, &held);
    }
    assert!(s.attitude_matrix().abs_diff_eq(expected, 1e-9));

    s.toggle_euler();
    s.build(VIEW);
    assert_eq!(ring_pixels(&cpu::render(s.scene())), [0, 0, 0]);
}

/// `--gimbal zyx --gimbal-angles A,B,C` are the aerospace yaw, pitch and roll that the HUD
/// reads back (also at gimbal lock, where the HUD puts the heading in yaw), and the sliders
/// following the flight show the HUD's numbers.
#[test]
fn gimbal_angles_round_trip_to_what_the_hud_shows() {
    for angles in [
        [60.0, 90.0, 0.0],
        [30.0, 20.0, 10.0],
        [-120.0, -45.0, 170.0],
    ] {
        let mut s = session();
        s.set_euler_degrees(angles);
        s.advance(1.0 / 60.0, &Held::default());
        let hud = aerospace_degrees(s.readout().angles);
        for (a, b) in hud.iter().zip(angles) {
            assert!((a - b).abs() < 1e-6, "{angles:?}: the HUD shows {hud:?}");
        }
        // Let go: the sliders follow the attitude and show the same numbers.
        s.set_euler_drive(false);
        s.advance(1.0 / 60.0, &Held::default());
        for (a, b) in s.euler.degrees().iter().zip(angles) {
            assert!(
                (a - b).abs() < 1e-6,
                "{angles:?}: the sliders show {:?}",
                s.euler.degrees()
            );
        }
    }
}

/// Following: the sliders show the attitude's angles in the chosen convention (its principal
/// decomposition), the rings realise exactly that attitude, and letting go of the sliders
/// leaves the aircraft where they put it.
#[test]
fn the_panel_follows_the_flight_in_any_convention() {
    let mut s = session();
    s.toggle_euler();
    let held = Held {
        pitch_up: true,
        roll_left: true,
        ..Held::default()
    };
    for _ in 0..40 {
        s.advance(1.0 / 60.0, &held);
    }
    for c in ["zxz", "xyz,extrinsic", "yxy", "zyx"] {
        let c: Convention = c.parse().unwrap();
        s.set_euler_convention(c);
        s.advance(1.0 / 60.0, &Held::default());
        assert_eq!(s.euler.convention(), c);
        assert!(!s.euler.drive);
        let shown =
            viewer_from_aerospace(EulerAngles::from_degrees(c, s.euler.degrees()).to_matrix());
        assert!(
            shown.abs_diff_eq(s.attitude_matrix(), 1e-9),
            "{c}: {:?}",
            s.euler.degrees()
        );
    }
    // Drive, then let go: the attitude stays, the sliders follow it again.
    s.set_euler_degrees([10.0, 20.0, 30.0]);
    let held_attitude = s.attitude_matrix();
    s.set_euler_drive(false);
    assert!(!s.euler.drive);
    assert!(s.attitude_matrix().abs_diff_eq(held_attitude, 1e-9));
    assert!(!s.attitude_matrix().abs_diff_eq(DMat3::IDENTITY, 1e-3));
}

/// The panel on its own: the middle angle is clamped into its principal range, and the lock
/// is reported at its end.
#[test]
fn the_panel_clamps_and_reports_lock() {
    let mut p = EulerPanel::new("zyz,extrinsic".parse().unwrap());
    p.set_degrees([-30.0, 200.0, 10.0]);
    assert_eq!(
        p.degrees(),
        [-30.0, 180.0, 10.0],
        "β clamped into [0°, 180°]"
    );
    assert_eq!(p.lock(), Lock::Upper);
}

/// The window opened with `--gimbal zxz --gimbal-angles 30,45,60`: the screenshot shows the
/// three rings; without `--gimbal` none of their colours appears.
#[test]
fn window_with_the_gimbal_panel_shows_the_rings() {
    if display().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = |name: &str, extra: &[&str]| -> Image {
        let path = dir.path().join(name);
        let mut args = vec![
            "view",
            "--frames",
            "3",
            "--size",
            "640x360",
            "--screenshot",
            path.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = wireflight_timed(&args, WINDOW_TIMEOUT);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        Image::decode_png(&std::fs::read(&path).unwrap()).unwrap()
    };
    let with = shot(
        "rings.png",
        &["--gimbal", "zxz", "--gimbal-angles", "30,45,60"],
    );
    let rings = ring_pixels(&with);
    assert!(rings.iter().all(|&n| n > 100), "{rings:?}");
    let without = shot("plain.png", &[]);
    assert_eq!(ring_pixels(&without), [0, 0, 0]);
}

/// Bad `--gimbal` values fail before any window opens.
#[test]
fn bad_gimbal_options_fail_before_the_window() {
    for args in [
        &["view", "--gimbal", "zzx"][..],
        &["view", "--gimbal-angles", "1,2,3"][..],
        &["view", "--gimbal", "--gimbal-angles", "1,2"][..],
    ] {
        let out = wireflight_timed(args, Duration::from_secs(60));
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--gimbal"), "{args:?}: {err}");
    }
}
