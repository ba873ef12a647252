//! The `wireflight euler` pictures: golden images of the README's pictures (the README shows
//! exactly these files), pixel checks that would fail if the pictures were wrong (the two
//! gimbal-lock frames identical, each sweep column one attitude, the Euler-lerp frames apart
//! from the slerp ones in the middle and equal at the ends, the steps ending at the attitude),
//! and the README commands writing those same pictures into a directory as a whole.
//!
//! To re-bless after an intended change: `WIREFLIGHT_BLESS=1 cargo test --test it
//! euler_pictures::` and look at every `tests/images/golden/euler_*.png` before committing.

use std::path::{Path, PathBuf};

use wireflight::draw::render::{cpu, Image, LineScene};
use wireflight::draw::scene::euler::{
    attitude_panel, gimbal_lock_pictures, interpolation_pictures, steps_pictures, Picture,
};
use wireflight::draw::scene::palette;
use wireflight::geometry::euler::{rotation_between, EulerAngles};
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;

use crate::golden::check_image;
use crate::support::cli::wireflight;

const VIEW: Viewport = Viewport {
    width: 320,
    height: 240,
};

/// The README's pictures: (golden name, `wireflight euler` arguments, file in `--out`).
const README: [(&str, &[&str], &str); 4] = [
    (
        "euler_steps_zyx_30_60_45",
        &["--seq", "zyx", "--angles", "30,60,45", "--steps"],
        "steps.png",
    ),
    (
        "euler_lock_pair_zyx",
        &["--seq", "zyx", "--gimbal-lock"],
        "lock_pair.png",
    ),
    (
        "euler_lock_sweep_zyx",
        &["--seq", "zyx", "--gimbal-lock"],
        "lock_sweep.png",
    ),
    (
        "euler_interpolation_zyx",
        &[
            "--seq",
            "zyx",
            "--interpolate",
            "--from-angles",
            "0,0,0",
            "--to-angles",
            "120,-75,-120",
            "--frames",
            "5",
        ],
        "interpolation.png",
    ),
];

fn zyx(deg: [f64; 3]) -> EulerAngles {
    EulerAngles::from_degrees("zyx".parse().unwrap(), deg)
}

fn picture<'p>(pictures: &'p [Picture], name: &str) -> &'p LineScene {
    &pictures
        .iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("no picture {name}"))
        .scene
}

fn draw(scene: &LineScene) -> Image {
    cpu::render(scene)
}

/// Pixels of exactly `color`, as a mask.
fn mask(image: &Image, color: [u8; 4]) -> Vec<bool> {
    image.pixels.chunks_exact(4).map(|p| p == color).collect()
}

fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&b| b).count()
}

/// Pixels set in one mask and not in the other.
fn mask_difference(a: &[bool], b: &[bool]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

fn library_pictures() -> Vec<Picture> {
    let mesh = builtin_plane();
    let mut all = steps_pictures(&mesh, &zyx([30.0, 60.0, 45.0]), VIEW);
    all.extend(
        gimbal_lock_pictures(&mesh, &zyx([60.0, 90.0, 0.0]), VIEW)
            .expect("at lock")
            .0,
    );
    all.extend(
        interpolation_pictures(
            &mesh,
            &zyx([0.0, 0.0, 0.0]),
            &zyx([120.0, -75.0, -120.0]),
            5,
            VIEW,
        )
        .0,
    );
    all
}

/// The README's four pictures, drawn from the library, against the golden images.
#[test]
fn readme_pictures_match_the_golden_images() {
    let all = library_pictures();
    for (golden, _, file) in README {
        let name = file.trim_end_matches(".png");
        let image = draw(picture(&all, name));
        check_image(golden, &image);
        // Not blank: the aircraft is drawn.
        assert!(count(&mask(&image, palette::AIRCRAFT)) > 500, "{golden}");
    }
}

/// At z-y-x pitch 90°, (60°, 90°, 0°) and (0°, 90°, −60°) are one attitude: the two plain
/// frames are identical, pixel for pixel; and the pair picture says which angles.
#[test]
fn the_two_gimbal_lock_frames_are_identical() {
    let mesh = builtin_plane();
    let (pictures, twin) = gimbal_lock_pictures(&mesh, &zyx([60.0, 90.0, 0.0]), VIEW).unwrap();
    let expected = [0.0, 90.0, -60.0];
    for (got, want) in twin.to_degrees().into_iter().zip(expected) {
        assert!((got - want).abs() < 1e-12, "{:?}", twin.to_degrees());
    }
    let a = draw(picture(&pictures, "lock_a"));
    let b = draw(picture(&pictures, "lock_b"));
    assert!(a == b, "lock_a and lock_b differ");
    assert!(count(&mask(&a, palette::AIRCRAFT)) > 500);
    // Away from lock the same change of angles is a different attitude: the check can fail.
    let free_a = draw(&attitude_panel(&mesh, &zyx([60.0, 80.0, 0.0]), VIEW));
    let free_b = draw(&attitude_panel(&mesh, &zyx([0.0, 80.0, -60.0]), VIEW));
    let differ = mask_difference(
        &mask(&free_a, palette::AIRCRAFT),
        &mask(&free_b, palette::AIRCRAFT),
    );
    assert!(differ > 200, "{differ} pixels differ away from lock");
    // The pair: the rings differ (different angles), the aircraft does not.
    let pair = draw(picture(&pictures, "lock_pair"));
    let half = |image: &Image, right: bool, color| -> Vec<bool> {
        let w = (image.width - 3) / 2;
        let x0 = if right { w + 3 } else { 0 };
        let m = mask(image, color);
        (0..image.height)
            .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
            .map(|(x, y)| m[(y * image.width + x) as usize])
            .collect()
    };
    assert_eq!(
        mask_difference(
            &half(&pair, false, palette::AIRCRAFT),
            &half(&pair, true, palette::AIRCRAFT)
        ),
        0
    );
    let rings = mask_difference(
        &half(&pair, false, palette::EULER_FIRST),
        &half(&pair, true, palette::EULER_FIRST),
    );
    assert!(rings > 100, "the outer rings differ: {rings}");
}

/// The sweep: the top row turns the first angle, the bottom row the third; each column is one
/// attitude (same aircraft pixels), and the attitude changes along the row.
#[test]
fn the_gimbal_lock_sweep_turns_yaw_and_roll_about_one_axis() {
    let mesh = builtin_plane();
    let (pictures, _) = gimbal_lock_pictures(&mesh, &zyx([60.0, 90.0, 0.0]), VIEW).unwrap();
    let sheet = draw(picture(&pictures, "lock_sweep"));
    let columns = 4u32;
    assert_eq!(sheet.width, columns * 320 + (columns - 1) * 3);
    assert_eq!(sheet.height, 2 * 240 + 3);
    let panel = |col: u32, row: u32| -> Vec<bool> {
        let m = mask(&sheet, palette::AIRCRAFT);
        let (x0, y0) = (col * 323, row * 243);
        (y0..y0 + 240)
            .flat_map(|y| (x0..x0 + 320).map(move |x| (x, y)))
            .map(|(x, y)| m[(y * sheet.width + x) as usize])
            .collect()
    };
    for col in 0..columns {
        let (top, bottom) = (panel(col, 0), panel(col, 1));
        assert!(count(&top) > 300, "column {col}");
        // Rounding may move a pixel or two where two lines cross; the attitude is the same.
        let d = mask_difference(&top, &bottom);
        assert!(d <= 4, "column {col}: {d} aircraft pixels differ");
        if col > 0 {
            let moved = mask_difference(&top, &panel(col - 1, 0));
            assert!(moved > 200, "column {col} turned: {moved}");
        }
    }
}

/// Linear interpolation of the angles leaves the slerp path in the middle (by tens of degrees
/// for this pair) and meets it at the ends.
#[test]
fn euler_lerp_frames_differ_from_slerp_in_the_middle_only() {
    let mesh = builtin_plane();
    let (pictures, c) = interpolation_pictures(
        &mesh,
        &zyx([0.0, 0.0, 0.0]),
        &zyx([120.0, -75.0, -120.0]),
        5,
        VIEW,
    );
    assert!(c.max_deviation.to_degrees() > 35.0, "{c:?}");
    assert!(c.lerp_turn > c.slerp_turn + 20f64.to_radians(), "{c:?}");
    let plane = |name: &str| mask(&draw(picture(&pictures, name)), palette::AIRCRAFT);
    for k in 0..5 {
        let d = mask_difference(
            &plane(&format!("euler_{k:02}")),
            &plane(&format!("slerp_{k:02}")),
        );
        if k == 0 || k == 4 {
            assert!(d <= 4, "frame {k}: the ends agree, {d} pixels differ");
        } else {
            assert!(d > 300, "frame {k}: only {d} pixels differ");
        }
    }
    // One angle at a time, the two agree all the way.
    let (pictures, c) = interpolation_pictures(
        &mesh,
        &zyx([0.0, 0.0, 0.0]),
        &zyx([0.0, 70.0, 0.0]),
        3,
        VIEW,
    );
    assert!(c.max_deviation < 1e-9, "{c:?}");
    let d = mask_difference(
        &mask(&draw(picture(&pictures, "euler_01")), palette::AIRCRAFT),
        &mask(&draw(picture(&pictures, "slerp_01")), palette::AIRCRAFT),
    );
    assert!(d <= 4, "{d}");
}

/// The steps end at the attitude of all three angles, each step moves the aircraft, and the
/// order matters: x-y-z with the same numbers ends elsewhere.
#[test]
fn steps_end_at_the_attitude_and_order_matters() {
    let mesh = builtin_plane();
    let e = zyx([30.0, 60.0, 45.0]);
    let pictures = steps_pictures(&mesh, &e, VIEW);
    let names: Vec<&str> = pictures.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["step_0", "step_1", "step_2", "step_3", "steps"]);
    let plane = |s: &LineScene| mask(&draw(s), palette::AIRCRAFT);
    let last = plane(picture(&pictures, "step_3"));
    let whole = plane(&attitude_panel(&mesh, &e, VIEW));
    assert!(mask_difference(&last, &whole) <= 4);
    for k in 1..4 {
        let a = plane(picture(&pictures, &format!("step_{}", k - 1)));
        let b = plane(picture(&pictures, &format!("step_{k}")));
        assert!(mask_difference(&a, &b) > 200, "step {k} moved the aircraft");
    }
    let xyz = EulerAngles::from_degrees("xyz".parse().unwrap(), [30.0, 60.0, 45.0]);
    assert!(rotation_between(xyz.to_quat(), e.to_quat()) > 0.5);
    let other = steps_pictures(&mesh, &xyz, VIEW);
    let d = mask_difference(&last, &plane(picture(&other, "step_3")));
    assert!(d > 200, "{d}");
}

// ---------------------------------------------------------------------------------------------
// The command
// ---------------------------------------------------------------------------------------------

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn golden(name: &str) -> Image {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/images/golden")
        .join(format!("{name}.png"));
    Image::decode_png(&std::fs::read(&path).unwrap()).unwrap()
}

/// The README's commands write the README's pictures (the golden images), with the frames and
/// a manifest, into `--out` as a whole; a second run replaces the directory; a directory that
/// is someone else's is refused.
#[test]
fn readme_commands_write_the_golden_pictures() {
    if std::env::var_os("WIREFLIGHT_BLESS").is_some() {
        return; // the goldens are being rewritten by the library test
    }
    let root = tempfile::tempdir().unwrap();
    for (i, (name, args, file)) in README.iter().enumerate() {
        let out = root.path().join(format!("run{i}"));
        let mut all = vec!["euler"];
        all.extend_from_slice(args);
        all.extend(["--out", out.to_str().unwrap()]);
        let o = wireflight(&all);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{all:?}: {stderr}");
        let image = Image::decode_png(&std::fs::read(out.join(file)).unwrap()).unwrap();
        assert!(
            image == golden(name),
            "{all:?}: {file} is not the golden {name}"
        );
        assert!(out.join("wireflight-euler.txt").is_file());
    }
    assert_eq!(
        listing(&root.path().join("run0")),
        [
            "step_0.png",
            "step_1.png",
            "step_2.png",
            "step_3.png",
            "steps.png",
            "wireflight-euler.txt"
        ]
    );
    assert_eq!(
        listing(&root.path().join("run1")),
        [
            "lock_a.png",
            "lock_b.png",
            "lock_pair.png",
            "lock_sweep.png",
            "wireflight-euler.txt"
        ]
    );
    let interp = listing(&root.path().join("run3"));
    assert_eq!(interp.len(), 5 + 5 + 2, "{interp:?}");
    // The two gimbal-lock frames as files: the same pixels.
    let a = std::fs::read(root.path().join("run1/lock_a.png")).unwrap();
    let b = std::fs::read(root.path().join("run1/lock_b.png")).unwrap();
    assert_eq!(a, b);
    let manifest = std::fs::read_to_string(root.path().join("run3/wireflight-euler.txt")).unwrap();
    assert!(manifest.contains("largest difference"), "{manifest}");

    // Again into run0, with other pictures: the old files are gone, nothing is left beside it.
    let out = root.path().join("run0");
    let o = wireflight(&[
        "euler",
        "--seq",
        "zxz",
        "--gimbal-lock",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!out.join("steps.png").exists());
    assert!(out.join("lock_pair.png").exists());
    assert_eq!(listing(root.path()), ["run0", "run1", "run2", "run3"]);

    // Someone else's directory: refused, untouched.
    let theirs = root.path().join("theirs");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::write(theirs.join("notes.txt"), "mine").unwrap();
    let o = wireflight(&[
        "euler",
        "--angles",
        "1,2,3",
        "--steps",
        "--out",
        theirs.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("--out") && stderr.contains("not written by this command"),
        "{stderr}"
    );
    assert_eq!(listing(&theirs), ["notes.txt"]);
}

/// Every convention can be pictured: steps for all 24, gimbal lock at both ends of β for all
/// 24 (the two plain frames identical), with a proper Euler sequence's lock at 0° and 180°.
#[test]
fn every_convention_pictures_its_steps_and_its_lock() {
    let mesh = builtin_plane();
    let small = Viewport {
        width: 160,
        height: 120,
    };
    for c in wireflight::geometry::euler::Convention::ALL {
        let e = EulerAngles::from_degrees(c, [25.0, 40.0, -35.0]);
        let pictures = steps_pictures(&mesh, &e, small);
        assert_eq!(pictures.len(), 5, "{c}");
        assert!(gimbal_lock_pictures(&mesh, &e, small).is_none(), "{c}");
        let locks = if c.sequence.is_tait_bryan() {
            [90.0, -90.0]
        } else {
            [0.0, 180.0]
        };
        for beta in locks {
            let locked = EulerAngles::from_degrees(c, [25.0, beta, -35.0]);
            let (pictures, twin) = gimbal_lock_pictures(&mesh, &locked, small).expect("lock");
            assert!(
                rotation_between(twin.to_quat(), locked.to_quat()) < 1e-12,
                "{c}"
            );
            assert_ne!(twin.angles, locked.angles);
            let a = draw(picture(&pictures, "lock_a"));
            let b = draw(picture(&pictures, "lock_b"));
            let d = mask_difference(&mask(&a, palette::AIRCRAFT), &mask(&b, palette::AIRCRAFT));
            assert!(d <= 4, "{c} β = {beta}: {d}");
        }
    }
}
