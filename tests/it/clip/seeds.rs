//! The seed lectures' worked examples, for every algorithm they apply to.
//!
//! * `clipping-cohen-sutherland-and-blinn-3d.txt`: window (left, right, bottom, top) =
//!   (30, 220, 50, 240), (a) p1 = (40, 140), p2 = (100, 200): inside, drawn whole; (b) p1 =
//!   (20, 10), p2 = (20, 200): left of the window, rejected.
//! * `clipping-2d-lecture-transcript.txt`: window 2..4 × 2..4. AB has outcode 0010 at both
//!   ends: rejected. PQ from inside to the right: Q' = (4, 5/2). MN from left to right:
//!   N' = (4, 9/4), M' = (2, 11/4). The transcript gives the answers and outcodes but not
//!   the endpoints; these endpoints reproduce both: A = (5, 3), B = (6, 2); P = (3, 3),
//!   Q = (5, 2); M = (1, 3), N = (5, 2).
//! * The same MN example in clip space (the window mapped onto −w..w with w = 1) for the
//!   homogeneous algorithms.

use super::check::{clip_homogeneous, clip_planar, HOMOGENEOUS, PLANAR};
use glam::{Vec2, Vec4};
use wireflight::geometry::clip::{
    cohen_sutherland, nicholl_lee_nicholl, plane, ClipOutcome, ClipVolume, DepthRange, Window2,
};

fn v2(x: f32, y: f32) -> Vec2 {
    Vec2::new(x, y)
}

#[test]
fn seed_window_30_220_50_240() {
    let w = Window2::from_lrbt(30.0, 220.0, 50.0, 240.0).unwrap();
    let (p1, p2) = (v2(40.0, 140.0), v2(100.0, 200.0));
    assert_eq!(w.outcode(p1) | w.outcode(p2), 0);
    for algo in PLANAR {
        assert_eq!(
            clip_planar(algo, p1, p2, &w),
            ClipOutcome::Accepted(p1, p2),
            "{algo} (a)"
        );
    }
    let (p1, p2) = (v2(20.0, 10.0), v2(20.0, 200.0));
    assert_eq!(w.outcode(p1), plane::LEFT | plane::BOTTOM);
    assert_eq!(w.outcode(p2), plane::LEFT);
    for algo in PLANAR {
        let out = clip_planar(algo, p1, p2, &w);
        assert_eq!(out.segment(), None, "{algo} (b): {out:?}");
    }
    // The outcode algorithms reject it without computing an intersection.
    assert_eq!(cohen_sutherland::clip_2d(p1, p2, &w), ClipOutcome::Rejected);
    assert_eq!(
        nicholl_lee_nicholl::clip_2d(p1, p2, &w),
        ClipOutcome::Rejected
    );
}

#[test]
fn transcript_window_2_to_4() {
    let w = Window2::new(2.0, 2.0, 4.0, 4.0).unwrap();
    // AB: 0010 at both ends.
    let (a, b) = (v2(5.0, 3.0), v2(6.0, 2.0));
    assert_eq!((w.outcode(a), w.outcode(b)), (0b0010, 0b0010));
    // PQ: 0000 and 0010; MN: 0001 and 0010.
    let (p, q) = (v2(3.0, 3.0), v2(5.0, 2.0));
    assert_eq!((w.outcode(p), w.outcode(q)), (0b0000, 0b0010));
    let (m, n) = (v2(1.0, 3.0), v2(5.0, 2.0));
    assert_eq!((w.outcode(m), w.outcode(n)), (0b0001, 0b0010));
    for algo in PLANAR {
        let out = clip_planar(algo, a, b, &w);
        assert_eq!(out.segment(), None, "{algo} AB: {out:?}");
        assert_eq!(
            clip_planar(algo, p, q, &w),
            ClipOutcome::Clipped(p, v2(4.0, 2.5)),
            "{algo} PQ"
        );
        assert_eq!(
            clip_planar(algo, m, n, &w),
            ClipOutcome::Clipped(v2(2.0, 2.75), v2(4.0, 2.25)),
            "{algo} MN"
        );
        // Backwards, the same segment the other way round.
        assert_eq!(
            clip_planar(algo, n, m, &w),
            ClipOutcome::Clipped(v2(4.0, 2.25), v2(2.0, 2.75)),
            "{algo} NM"
        );
    }
}

#[test]
fn transcript_example_in_clip_space() {
    // x' = x − 3, y' = y − 3 maps the 2..4 window onto −1..1 (w = 1).
    let m = Vec4::new(-2.0, 0.0, 0.5, 1.0);
    let n = Vec4::new(2.0, -1.0, 0.5, 1.0);
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        let v = ClipVolume::new(depth);
        for algo in HOMOGENEOUS {
            assert_eq!(
                clip_homogeneous(algo, m, n, &v),
                ClipOutcome::Clipped(
                    Vec4::new(-1.0, -0.25, 0.5, 1.0),
                    Vec4::new(1.0, -0.75, 0.5, 1.0)
                ),
                "{algo} {depth:?}"
            );
        }
    }
    // The same with w = 10 (every coordinate scaled): the seed's point (5, 2, 7, 10) style.
    let (m10, n10) = (m * 10.0, n * 10.0);
    let v = ClipVolume::new(DepthRange::NegOneToOne);
    for algo in HOMOGENEOUS {
        let (p, q) = clip_homogeneous(algo, m10, n10, &v).segment().unwrap();
        for (got, want) in [
            (p, Vec4::new(-10.0, -2.5, 5.0, 10.0)),
            (q, Vec4::new(10.0, -7.5, 5.0, 10.0)),
        ] {
            assert!(
                (got - want).abs().max_element() < 1e-5,
                "{algo}: {got} vs {want}"
            );
        }
    }
}
