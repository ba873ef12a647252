//! Cross-validation: every algorithm that applies to a case returns the same segment as an
//! independent `f64` reference (so all of them agree with each other), within 4 × 1e-6 of the
//! case's largest coordinate ([`super::check`]), on random and adversarial edges: endpoints
//! on planes, edges parallel to planes, through corners and edges of the volume, through the
//! eye, w ≤ 0, zero length, huge (1e30) and tiny (1e-30) coordinates, extra planes.
//!
//! Counts: `WIREFLIGHT_CLIP_CASES` edges per test (default 400 000 homogeneous edges, half
//! per depth range, and 400 000 2D edges, each checked with all five algorithms: 2 000 000
//! checks per test, a few seconds at the test profile's opt-level 1); the `*_many` tests, in
//! the validation tier (`cargo test --locked -- --ignored`), run 2 000 000 edges each.

use super::check::{check_homogeneous, check_planar, Tally, HOMOGENEOUS, PLANAR};
use crate::support::Rng;
use glam::{Vec2, Vec4};
use wireflight::geometry::clip::{ClipVolume, DepthRange, PlaneSet, Window2};

fn cases(default: usize) -> usize {
    std::env::var("WIREFLIGHT_CLIP_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// A scale spanning tiny to huge.
fn scale(rng: &mut Rng) -> f64 {
    match rng.below(12) {
        0 => rng.log_range(1e-30, 1e-20),
        1 => rng.log_range(1e20, 1e30),
        2 => rng.log_range(1e-6, 1e-2),
        3 | 4 => rng.log_range(100.0, 1e5),
        _ => rng.log_range(0.1, 10.0),
    }
}

fn inside(rng: &mut Rng, depth: DepthRange, s: f64) -> [f64; 4] {
    let w = s * rng.range(0.01, 1.0);
    let zlo = if depth == DepthRange::ZeroToOne {
        0.0
    } else {
        -w
    };
    [
        w * rng.range(-1.0, 1.0),
        w * rng.range(-1.0, 1.0),
        zlo + (w - zlo) * rng.unit(),
        w,
    ]
}

fn any_point(rng: &mut Rng, s: f64) -> [f64; 4] {
    std::array::from_fn(|_| s * rng.range(-2.0, 2.0))
}

fn f32s(p: [f64; 4]) -> Vec4 {
    Vec4::from_array(p.map(|x| x as f32))
}

/// One random or adversarial homogeneous edge.
fn homogeneous_edge(rng: &mut Rng, depth: DepthRange) -> (Vec4, Vec4) {
    let s = scale(rng);
    let zn = |w: f64| {
        if depth == DepthRange::ZeroToOne {
            0.0
        } else {
            -w
        }
    };
    let (a, c) = match rng.below(12) {
        0 => (inside(rng, depth, s), inside(rng, depth, s)),
        1 => (inside(rng, depth, s), any_point(rng, s)),
        2 => (any_point(rng, s), any_point(rng, s)),
        3 => {
            // An endpoint exactly on a plane.
            let mut a = any_point(rng, s);
            let w = a[3];
            match rng.below(6) {
                0 => a[0] = w,
                1 => a[0] = -w,
                2 => a[1] = w,
                3 => a[1] = -w,
                4 => a[2] = zn(w),
                _ => a[2] = w,
            }
            (a, any_point(rng, s))
        }
        4 => {
            // Parallel to a plane: w − x (or another BC) constant along the edge.
            let a = any_point(rng, s);
            let mut c = any_point(rng, s);
            match rng.below(3) {
                0 => c[0] = c[3] - (a[3] - a[0]),
                1 => c[1] = c[3] + (a[1] - a[3]),
                _ => c[2] = c[3] - (a[3] - a[2]),
            }
            (a, c)
        }
        5 => {
            // Through an edge or corner of the volume: an endpoint on the line x = y = w.
            let w = s * rng.range(0.1, 1.0);
            let corner = [
                w,
                if rng.chance(0.5) { w } else { -w },
                if rng.chance(0.5) { w } else { zn(w) },
                w,
            ];
            let k = rng.range(0.5, 2.0);
            let other = any_point(rng, s);
            // c on the far side of the corner from `other`.
            let c = std::array::from_fn(|i| corner[i] + k * (corner[i] - other[i]));
            (other, c)
        }
        6 => {
            // w ≤ 0 at one or both ends.
            let mut c = any_point(rng, s);
            c[3] = -c[3].abs();
            let a = if rng.chance(0.5) {
                inside(rng, depth, s)
            } else {
                any_point(rng, s)
            };
            (a, c)
        }
        7 => {
            // Through the eye: c = −k·a.
            let a = inside(rng, depth, s);
            let k = rng.range(0.1, 3.0);
            (a, a.map(|x| -k * x))
        }
        8 => {
            // Zero length.
            let a = if rng.chance(0.5) {
                inside(rng, depth, s)
            } else {
                any_point(rng, s)
            };
            (a, a)
        }
        9 => {
            // Huge on one end, ordinary on the other.
            let big = rng.log_range(1e20, 1e37);
            let mut c = any_point(rng, 1.0);
            c[rng.below(4)] = if rng.chance(0.5) { big } else { -big };
            (inside(rng, depth, 1.0), c)
        }
        10 => {
            // Small integers: exact hits on planes, corners and parallels.
            let mut r = || std::array::from_fn(|_| (rng.below(9) as f64) - 4.0);
            (r(), r())
        }
        _ => {
            // Crossing one to three planes.
            let a = inside(rng, depth, s);
            let mut c = inside(rng, depth, s);
            for _ in 0..=rng.below(3) {
                let k = 1.0 + rng.log_range(1e-7, 3.0);
                let i = rng.below(3);
                c[i] = if rng.chance(0.5) { c[3] * k } else { -c[3] * k };
            }
            (a, c)
        }
    };
    (f32s(a), f32s(c))
}

/// Sometimes an extra plane or two (random, or through the origin of clip space).
fn volume(rng: &mut Rng, depth: DepthRange) -> ClipVolume {
    let mut extra = PlaneSet::default();
    if rng.chance(0.25) {
        for _ in 0..=rng.below(2) {
            let p = Vec4::new(
                rng.range_f32(-1.0, 1.0),
                rng.range_f32(-1.0, 1.0),
                rng.range_f32(-1.0, 1.0),
                if rng.chance(0.5) {
                    0.0
                } else {
                    rng.range_f32(-1.0, 1.0)
                },
            );
            let _ = extra.push(p);
        }
    }
    ClipVolume::with_planes(depth, extra)
}

fn run_homogeneous(n: usize, seed: u64) {
    let mut failures = Vec::new();
    let mut report = String::new();
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        let mut rng = Rng::new(seed + depth as u64);
        let mut tally = Tally::default();
        for i in 0..n / 2 {
            let (a, c) = homogeneous_edge(&mut rng, depth);
            let v = volume(&mut rng, depth);
            for algo in HOMOGENEOUS {
                if let Err(e) = check_homogeneous(algo, a, c, &v, &mut tally) {
                    if failures.len() < 6 {
                        failures.push(format!("#{i}: {e}"));
                    }
                }
            }
        }
        report += &format!("{depth:?}: {tally:?}\n");
        let s = tally.stats;
        assert!(
            s.trivially_accepted > 0
                && s.clipped > 0
                && s.clipped_away > 0
                && s.trivially_rejected > 0,
            "{s:?}"
        );
    }
    println!("{report}");
    assert!(failures.is_empty(), "{}\n\n{report}", failures.join("\n\n"));
}

fn planar_edge(rng: &mut Rng, w: &Window2) -> (Vec2, Vec2) {
    let span = f64::from((w.xmax() - w.xmin()).max(w.ymax() - w.ymin()));
    let cx = f64::from(w.xmin() + w.xmax()) / 2.0;
    let cy = f64::from(w.ymin() + w.ymax()) / 2.0;
    let pt = |rng: &mut Rng, k: f64| {
        Vec2::new(
            (cx + k * span * rng.range(-1.0, 1.0)) as f32,
            (cy + k * span * rng.range(-1.0, 1.0)) as f32,
        )
    };
    let corners = w.corners();
    match rng.below(8) {
        0 => (pt(rng, 0.5), pt(rng, 0.5)),
        1 => (pt(rng, 0.5), pt(rng, 3.0)),
        2 => (pt(rng, 3.0), pt(rng, 3.0)),
        3 => {
            // Through a corner.
            let k = corners[rng.below(4)];
            let a = pt(rng, 3.0);
            (a, k + (k - a) * rng.range_f32(0.2, 2.0))
        }
        4 => {
            // On an edge line, or parallel to one.
            let mut a = pt(rng, 2.0);
            let mut c = pt(rng, 2.0);
            if rng.chance(0.5) {
                a.x = w.xmin();
                c.x = if rng.chance(0.5) { w.xmin() } else { c.x };
            } else {
                c.y = a.y;
            }
            (a, c)
        }
        5 => {
            let a = pt(rng, 1.0);
            (a, a)
        }
        6 => {
            // Huge partner.
            let big = rng.log_range(1e20, 1e37) as f32;
            (
                pt(rng, 0.5),
                Vec2::new(if rng.chance(0.5) { big } else { -big }, pt(rng, 1.0).y),
            )
        }
        _ => {
            // Small integers around a small integer window.
            let mut r = || Vec2::new(rng.below(9) as f32 - 2.0, rng.below(9) as f32 - 2.0);
            (r(), r())
        }
    }
}

fn random_window(rng: &mut Rng) -> Window2 {
    match rng.below(4) {
        0 => Window2::new(2.0, 2.0, 4.0, 4.0).unwrap(),
        1 => Window2::from_lrbt(30.0, 220.0, 50.0, 240.0).unwrap(),
        _ => {
            let s = scale(rng).min(1e15);
            let (x, y) = (s * rng.range(-2.0, 2.0), s * rng.range(-2.0, 2.0));
            let (wd, ht) = (s * rng.range(0.01, 2.0), s * rng.range(0.01, 2.0));
            Window2::new(x as f32, y as f32, (x + wd) as f32, (y + ht) as f32)
                .unwrap_or(Window2::new(-1.0, -1.0, 1.0, 1.0).unwrap())
        }
    }
}

fn run_planar(n: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut tally = Tally::default();
    let mut failures = Vec::new();
    for i in 0..n {
        let w = random_window(&mut rng);
        let (a, c) = planar_edge(&mut rng, &w);
        for algo in PLANAR {
            if let Err(e) = check_planar(algo, a, c, &w, &mut tally) {
                if failures.len() < 6 {
                    failures.push(format!("#{i}: {e}"));
                }
            }
        }
    }
    println!("{tally:?}");
    assert!(
        failures.is_empty(),
        "{}\n\n{tally:?}",
        failures.join("\n\n")
    );
    let s = tally.stats;
    assert!(
        s.trivially_accepted > 0 && s.clipped > 0 && s.trivially_rejected > 0,
        "{s:?}"
    );
}

#[test]
fn homogeneous_algorithms_agree_with_the_reference() {
    run_homogeneous(cases(400_000), 0xA61E_E000);
}

#[test]
fn planar_algorithms_agree_with_the_reference() {
    run_planar(cases(400_000), 0x2D00_0000);
}

/// 2 000 000 homogeneous edges (× 5 algorithms).
#[test]
#[ignore = "validation tier: cargo test -- --ignored"]
fn homogeneous_algorithms_agree_many() {
    run_homogeneous(2_000_000, 0xBEEF_0000);
}

/// 2 000 000 2D edges (× 5 algorithms).
#[test]
#[ignore = "validation tier: cargo test -- --ignored"]
fn planar_algorithms_agree_many() {
    run_planar(2_000_000, 0xBEEF_2D00);
}
