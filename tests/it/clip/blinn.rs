//! Blinn's homogeneous clipper: the seed's worked example, outcodes, trivial accept/reject,
//! edges behind the eye (with a real camera), boundary and degenerate edges, non-finite input,
//! w ≈ 0. Every property is checked for both depth ranges.

use crate::support::{
    assert_close, distance_from_line, edge_scale, inside_margin, recover_t, to_f64, Rng, DEPTHS,
};
use glam::{Vec2, Vec3, Vec4};
use wireflight::geometry::camera::{Camera, Projection};
use wireflight::geometry::clip::{
    boundary_coords, clip_edge, is_inside, outcode, plane, ClipOutcome, ClipStats, DepthRange,
};
use wireflight::geometry::pipeline::perspective_divide;

/// Relative tolerance of the geometric checks (relative to the edge's largest coordinate).
pub(super) const REL_TOL: f64 = 1e-5;
/// Tolerance on the edge parameter t, on top of the sampling step.
pub(super) const T_TOL: f64 = 1e-5;
/// Samples per edge for the brute-force reference.
pub(super) const SAMPLES: usize = 20_001;

pub(super) fn v(x: f32, y: f32, z: f32, w: f32) -> Vec4 {
    Vec4::new(x, y, z, w)
}

/// A z that is on the near side of the near plane by `by`·w, for either depth range.
pub(super) fn z_near(depth: DepthRange, w: f32) -> f32 {
    match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => -w,
    }
}

/// The visible part of an edge, with both endpoints checked to have w > 0 and a finite image.
fn visible(a: Vec4, c: Vec4, depth: DepthRange) -> Option<(Vec4, Vec4)> {
    let out = clip_edge(a, c, depth);
    let seg = out.segment();
    if let Some((p, q)) = seg {
        for e in [p, q] {
            assert!(e.w > 0.0, "{a} → {c} ({depth:?}): {out:?} has w ≤ 0");
            let ndc = perspective_divide(e);
            assert!(
                ndc.is_finite(),
                "{a} → {c} ({depth:?}): {out:?} divides to {ndc}"
            );
        }
    }
    seg
}

// ---------------------------------------------------------------------------------------------
// Boundary coordinates and outcodes
// ---------------------------------------------------------------------------------------------

/// The seed's worked example: (5, 2, 7, 10) has BCs 15, 5, 12, 8, 17, 3 (CVV −1..1); with depth
/// 0..1 the near BC is z itself, 7.
#[test]
fn seed_worked_example_boundary_coords() {
    let p = v(5.0, 2.0, 7.0, 10.0);
    assert_eq!(
        boundary_coords(p, DepthRange::NegOneToOne),
        [15.0, 5.0, 12.0, 8.0, 17.0, 3.0]
    );
    assert_eq!(
        boundary_coords(p, DepthRange::ZeroToOne),
        [15.0, 5.0, 12.0, 8.0, 7.0, 3.0]
    );
    for depth in DEPTHS {
        assert_eq!(outcode(&boundary_coords(p, depth)), 0);
        assert!(is_inside(p, depth, 0.0));
    }
}

/// One point per plane, outside that plane only: its outcode is exactly that plane's bit, in the
/// seed's order (BC0 x = −1 … BC5 far).
#[test]
fn outcode_one_bit_per_plane() {
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let cases = [
            (v(-1.5, 0.0, 0.5, 1.0), plane::LEFT, 0),
            (v(1.5, 0.0, 0.5, 1.0), plane::RIGHT, 1),
            (v(0.0, -1.5, 0.5, 1.0), plane::BOTTOM, 2),
            (v(0.0, 1.5, 0.5, 1.0), plane::TOP, 3),
            (v(0.0, 0.0, zn - 0.25, 1.0), plane::NEAR, 4),
            (v(0.0, 0.0, 1.25, 1.0), plane::FAR, 5),
        ];
        for (p, bit, index) in cases {
            assert_eq!(bit, 1 << index);
            let bc = boundary_coords(p, depth);
            assert_eq!(outcode(&bc), bit, "{p} {depth:?}: bc {bc:?}");
            assert!(bc[index] < 0.0);
            assert!(!is_inside(p, depth, 0.0));
        }
        // A point on every plane at once is impossible, but each plane's boundary is inside.
        for p in [
            v(-1.0, 0.0, 0.5, 1.0),
            v(1.0, 0.0, 0.5, 1.0),
            v(0.0, -1.0, 0.5, 1.0),
            v(0.0, 1.0, 0.5, 1.0),
            v(0.0, 0.0, zn, 1.0),
            v(0.0, 0.0, 1.0, 1.0),
            v(1.0, -1.0, 1.0, 1.0), // a corner
        ] {
            assert_eq!(outcode(&boundary_coords(p, depth)), 0, "{p} {depth:?}");
        }
        // Several planes at once: a corner region.
        let p = v(2.0, 2.0, 2.0, 1.0);
        assert_eq!(
            outcode(&boundary_coords(p, depth)),
            plane::RIGHT | plane::TOP | plane::FAR
        );
    }
    // z = −0.5w is outside the near plane for 0..1 but inside for −1..1.
    let p = v(0.0, 0.0, -0.5, 1.0);
    assert_eq!(
        outcode(&boundary_coords(p, DepthRange::ZeroToOne)),
        plane::NEAR
    );
    assert_eq!(outcode(&boundary_coords(p, DepthRange::NegOneToOne)), 0);
}

/// A point behind the eye (w < 0) is outside at least one of each opposite pair of planes.
#[test]
fn points_behind_the_eye_are_outside() {
    let mut rng = Rng::new(3);
    for depth in DEPTHS {
        for _ in 0..10_000 {
            let p = Vec4::new(
                rng.range_f32(-5.0, 5.0),
                rng.range_f32(-5.0, 5.0),
                rng.range_f32(-5.0, 5.0),
                rng.range_f32(-5.0, -1e-6),
            );
            let code = outcode(&boundary_coords(p, depth));
            assert_ne!(code & (plane::LEFT | plane::RIGHT), 0, "{p}");
            assert_ne!(code & (plane::BOTTOM | plane::TOP), 0, "{p}");
            assert_ne!(code & (plane::NEAR | plane::FAR), 0, "{p}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Trivial accept / reject and the tally
// ---------------------------------------------------------------------------------------------

#[test]
fn trivial_accept_returns_the_edge_unchanged() {
    for depth in DEPTHS {
        let a = v(-0.3, 0.2, 0.4, 1.0);
        let c = v(7.0, -9.0, 9.5, 10.0);
        assert_eq!(clip_edge(a, c, depth), ClipOutcome::Accepted(a, c));
        assert_eq!(clip_edge(c, a, depth), ClipOutcome::Accepted(c, a));
        assert_eq!(clip_edge(a, c, depth).segment(), Some((a, c)));
    }
}

#[test]
fn trivial_reject_when_both_ends_outside_one_plane() {
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let pairs = [
            (v(-2.0, 0.0, 0.5, 1.0), v(-3.0, 5.0, 0.5, 1.0)), // left
            (v(2.0, -5.0, 0.5, 1.0), v(3.0, 5.0, 0.5, 1.0)),  // right, crossing y
            (v(0.0, -2.0, 0.5, 1.0), v(9.0, -3.0, 0.5, 1.0)), // bottom (and right)
            (v(0.0, 2.0, 0.5, 1.0), v(-9.0, 3.0, 0.5, 1.0)),  // top (and left)
            (v(0.0, 0.0, zn - 1.0, 1.0), v(0.5, 0.5, zn - 0.1, 1.0)), // near
            (v(0.0, 0.0, 2.0, 1.0), v(0.5, 0.5, 1.1, 1.0)),   // far
            (v(1.0, 1.0, 0.5, -1.0), v(-1.0, -1.0, -0.5, -2.0)), // behind the eye
        ];
        for (a, c) in pairs {
            let (ca, cc) = (
                outcode(&boundary_coords(a, depth)),
                outcode(&boundary_coords(c, depth)),
            );
            assert_ne!(ca & cc, 0, "{a} {c} {depth:?}");
            assert_eq!(clip_edge(a, c, depth), ClipOutcome::Rejected, "{a} {c}");
            assert_eq!(clip_edge(c, a, depth), ClipOutcome::Rejected, "{c} {a}");
        }
    }
}

#[test]
fn clip_stats_count_each_category() {
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let batch = [
            // 2 trivially accepted
            (v(0.0, 0.0, 0.5, 1.0), v(0.5, 0.5, 0.5, 1.0)),
            (v(-1.0, -1.0, 1.0, 1.0), v(1.0, 1.0, zn, 1.0)),
            // 3 trivially rejected
            (v(-2.0, 0.0, 0.5, 1.0), v(-3.0, 0.0, 0.5, 1.0)),
            (v(0.0, 0.0, 3.0, 1.0), v(0.0, 0.0, 2.0, 1.0)),
            (v(0.0, 3.0, 0.5, 1.0), v(0.0, 4.0, 0.5, 1.0)),
            // 2 clipped
            (v(0.0, 0.0, 0.5, 1.0), v(3.0, 0.0, 0.5, 1.0)),
            (v(-3.0, 0.0, 0.5, 1.0), v(3.0, 0.0, 0.5, 1.0)),
            // 1 clipped away: outside left only, then top only, passing outside the corner
            (v(-1.5, 0.9, 0.5, 1.0), v(-0.9, 1.5, 0.5, 1.0)),
            // 2 non-finite
            (v(f32::NAN, 0.0, 0.5, 1.0), v(0.0, 0.0, 0.5, 1.0)),
            (v(0.0, 0.0, 0.5, 1.0), v(0.0, f32::INFINITY, 0.5, 1.0)),
        ];
        let mut stats = ClipStats::default();
        let mut halves = [ClipStats::default(), ClipStats::default()];
        for (i, &(a, c)) in batch.iter().enumerate() {
            let out = clip_edge(a, c, depth);
            stats.record(&out);
            halves[i % 2].record(&out);
        }
        let expected = ClipStats {
            edges_in: 10,
            trivially_accepted: 2,
            trivially_rejected: 3,
            clipped: 2,
            clipped_away: 1,
            non_finite: 2,
            ..ClipStats::default()
        };
        assert_eq!(stats, expected, "{depth:?}");
        assert_eq!(stats.drawn(), 4);
        let mut merged = halves[0];
        merged.merge(&halves[1]);
        assert_eq!(merged, expected);
        let text = stats.to_string();
        assert_eq!(
            text,
            "edges in 10, trivially accepted 2, trivially rejected 3, clipped 2, clipped away 1, \
             non-finite 2"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// A real camera: edges passing behind the eye
// ---------------------------------------------------------------------------------------------

const NEAR: f32 = 0.1;

/// Eye at the origin looking along world +X (Z up), 60° vertical field of view, square image.
/// In clip space w is the world x coordinate (distance ahead of the eye).
fn forward_camera() -> Camera {
    Camera {
        eye: Vec3::ZERO,
        target: Vec3::X,
        up: Vec3::Z,
        projection: Projection::Perspective {
            fov_y: 60f32.to_radians(),
            near: NEAR,
            far: 100.0,
        },
    }
}

/// Distance from `p` to the 2D segment s0–s1, and the parameter of the nearest point (unclamped).
fn point_segment(p: Vec2, s0: Vec2, s1: Vec2) -> (f32, f32) {
    let d = s1 - s0;
    let u = if d.length_squared() > 0.0 {
        (p - s0).dot(d) / d.length_squared()
    } else {
        0.0
    };
    (p.distance(s0 + u.clamp(0.0, 1.0) * d), u)
}

/// Clip a world edge from `front` (visible) to `behind` (w < 0) and compare its image with the
/// images of densely sampled visible points (w > near and inside the volume).
fn check_edge_through_eye_plane(front: Vec3, behind: Vec3, depth: DepthRange) -> (Vec2, Vec2) {
    let m = forward_camera().clip_from_world(1.0, depth);
    let a = m * front.extend(1.0);
    let c = m * behind.extend(1.0);
    assert!(a.w > NEAR && c.w < 0.0, "{a} {c}");
    let ctx = format!("{front} → {behind} ({depth:?}): clip {a} → {c}");
    let (a2, c2) = visible(a, c, depth).unwrap_or_else(|| panic!("{ctx}: nothing visible"));
    assert_eq!(a2, a, "{ctx}: the visible end must not move");
    let scale = edge_scale(a, c);
    let mut ts = [0.0; 2];
    for (k, p) in [a2, c2].into_iter().enumerate() {
        assert!(p.w > 0.0, "{ctx}: {p}");
        assert!(is_inside(p, depth, 1e-5), "{ctx}: {p} outside");
        let t = recover_t(a, c, p).unwrap();
        assert!((-T_TOL..=1.0 + T_TOL).contains(&t), "{ctx}: t = {t}");
        assert_close!(
            distance_from_line(a, c, t, p),
            0.0,
            REL_TOL * scale,
            "{ctx}: {p}"
        );
        ts[k] = t;
    }
    assert!(ts[0] <= ts[1], "{ctx}: direction {ts:?}");

    let (s0, s1) = (perspective_divide(a2), perspective_divide(c2));
    // Reference: sample the world segment, keep the visible points.
    let n = 10_001;
    let mut images = Vec::new();
    for k in 0..n {
        let t = k as f32 / (n - 1) as f32;
        let p = m * front.lerp(behind, t).extend(1.0);
        if f64::from(p.w) > f64::from(NEAR) && inside_margin(to_f64(p), depth) >= 0.0 {
            images.push(Vec2::new(p.x / p.w, p.y / p.w));
        }
    }
    assert!(
        images.len() > 100,
        "{ctx}: {} visible samples",
        images.len()
    );
    for &img in &images {
        let (dist, u) = point_segment(img, s0, s1);
        assert!(
            dist < 1e-4 && (-1e-4..=1.0 + 1e-4).contains(&u),
            "{ctx}: visible sample image {img} is not on the drawn segment {s0} → {s1} \
             (distance {dist}, u {u})"
        );
    }
    // The drawn segment spans the sampled visible part (up to one sample's movement).
    let (first, last) = (images[0], images[images.len() - 1]);
    assert_close!(s0, first, 1e-5, "{ctx}: start");
    assert_close!(s1, last, 0.05, "{ctx}: end");
    assert!(
        (s1 - s0).dot(last - first) > 0.0,
        "{ctx}: drawn the wrong way"
    );
    // NDC of the drawn segment stays in the square.
    for s in [s0, s1] {
        assert!(s.abs().max_element() <= 1.0 + 1e-5, "{ctx}: {s}");
    }
    (s0, s1)
}

/// An edge from in front of the eye to behind it, leaving through the side (left) plane: the
/// image runs from the front point to the left border, not "wrapped around" to the right as a
/// naive divide of the unclipped endpoints would draw it.
#[test]
fn edge_behind_the_eye_leaving_through_the_side() {
    let front = Vec3::new(5.0, 0.5, 0.3);
    let behind = Vec3::new(-5.0, 1.0, -0.4);
    for depth in DEPTHS {
        let (s0, s1) = check_edge_through_eye_plane(front, behind, depth);
        assert_close!(s1.x, -1.0, 1e-5, "{depth:?}: ends on the left border");
        assert!(s1.x < s0.x);
        // What a naive divide would have drawn: towards the right half.
        let m = forward_camera().clip_from_world(1.0, depth);
        let naive = perspective_divide_unchecked(m * behind.extend(1.0));
        assert!(naive.x > 0.0 && naive.x > s0.x, "naive image {naive}");
    }
}

/// An edge from in front to behind, passing close beside the eye: it leaves through the near
/// plane (w = near), and the image goes left while a naive divide would go right.
#[test]
fn edge_behind_the_eye_leaving_through_the_near_plane() {
    let front = Vec3::new(5.0, 0.2, 0.1);
    let behind = Vec3::new(-5.0, -0.1, -0.05);
    for depth in DEPTHS {
        let m = forward_camera().clip_from_world(1.0, depth);
        let (s0, s1) = check_edge_through_eye_plane(front, behind, depth);
        let c2 = clip_edge(m * front.extend(1.0), m * behind.extend(1.0), depth)
            .segment()
            .unwrap()
            .1;
        assert_close!(c2.w, NEAR, 1e-5, "{depth:?}: cut at the near plane: {c2}");
        assert!(s1.x < s0.x, "{s0} {s1}");
        let naive = perspective_divide_unchecked(m * behind.extend(1.0));
        assert!(naive.x > s0.x, "naive image {naive}");
    }
}

/// x/w, y/w without the pipeline's w > 0 debug assertion: what a clipper-less renderer does.
fn perspective_divide_unchecked(p: Vec4) -> Vec2 {
    Vec2::new(p.x / p.w, p.y / p.w)
}

/// Both ends behind the eye: nothing, including when a naive divide would draw a line across
/// the middle of the screen.
#[test]
fn edges_entirely_behind_the_eye_give_nothing() {
    for depth in DEPTHS {
        let m = forward_camera().clip_from_world(1.0, depth);
        for (p, q) in [
            (Vec3::new(-1.0, 0.2, 0.1), Vec3::new(-3.0, -0.4, 0.3)),
            // Naively divided, these two land on opposite sides of the centre: a line right
            // across the screen.
            (Vec3::new(-5.0, 1.0, 0.5), Vec3::new(-5.0, -1.0, -0.5)),
            (Vec3::new(-0.01, 0.0, 0.0), Vec3::new(-100.0, 0.0, 0.0)),
        ] {
            let (a, c) = (m * p.extend(1.0), m * q.extend(1.0));
            assert!(a.w < 0.0 && c.w < 0.0);
            assert_eq!(visible(a, c, depth), None, "{p} → {q} {depth:?}");
            assert_eq!(visible(c, a, depth), None, "{q} → {p} {depth:?}");
        }
        let naive = (
            perspective_divide_unchecked(m * Vec3::new(-5.0, 1.0, 0.5).extend(1.0)),
            perspective_divide_unchecked(m * Vec3::new(-5.0, -1.0, -0.5).extend(1.0)),
        );
        assert!(
            naive.0.x * naive.1.x < 0.0 && naive.0.y * naive.1.y < 0.0,
            "{naive:?}"
        );
    }
}

/// Both ends behind the eye but outside *different* planes (a & c == 0, so not trivially
/// rejected); naively divided it crosses the screen. Blinn's interval must come out empty.
#[test]
fn behind_the_eye_not_trivially_rejected_gives_nothing() {
    for depth in DEPTHS {
        // A: outside left, bottom, near; C: outside right, top, far. Both w = −1.
        let a = v(-2.0, -2.0, -2.0, -1.0);
        let c = v(2.0, 2.0, 0.5, -1.0);
        let c = if depth == DepthRange::NegOneToOne {
            v(2.0, 2.0, 2.0, -1.0)
        } else {
            c
        };
        let (ca, cc) = (
            outcode(&boundary_coords(a, depth)),
            outcode(&boundary_coords(c, depth)),
        );
        assert_eq!(ca & cc, 0, "{depth:?}: {ca:06b} {cc:06b}");
        assert_ne!(ca, 0);
        assert_ne!(cc, 0);
        let naive = (
            perspective_divide_unchecked(a),
            perspective_divide_unchecked(c),
        );
        assert!(naive.0.x * naive.1.x < 0.0, "{naive:?}");
        assert_eq!(
            clip_edge(a, c, depth),
            ClipOutcome::ClippedAway,
            "{depth:?}"
        );
        assert_eq!(
            clip_edge(c, a, depth),
            ClipOutcome::ClippedAway,
            "{depth:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Boundary planes, zero-length edges, non-finite input, w ≈ 0
// ---------------------------------------------------------------------------------------------

/// An edge lying in a boundary plane is inside and accepted; one in a plane but running out
/// through another is cut where it leaves.
#[test]
fn edges_on_a_boundary_plane() {
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let zn2 = z_near(depth, 2.0);
        for (a, c) in [
            (v(1.0, 0.0, 0.5, 1.0), v(2.0, 0.5, 1.0, 2.0)), // x = w
            (v(-1.0, 0.0, 0.5, 1.0), v(-3.0, -3.0, 3.0, 3.0)), // x = −w (and a corner)
            (v(0.0, 1.0, 0.5, 1.0), v(-0.5, 2.0, 0.0, 2.0)), // y = w
            (v(0.0, -1.0, 0.5, 1.0), v(0.5, -2.0, 1.0, 2.0)), // y = −w
            (v(0.0, 0.0, zn, 1.0), v(1.0, -1.0, zn2, 2.0)), // near
            (v(0.0, 0.0, 1.0, 1.0), v(0.3, 0.1, 2.0, 2.0)), // far
        ] {
            assert_eq!(
                clip_edge(a, c, depth),
                ClipOutcome::Accepted(a, c),
                "{a} → {c} {depth:?}"
            );
        }
        // In the plane x = w, running out through y = w: cut at (1, 1, 0.5, 1).
        let (a, c) = (v(1.0, 0.0, 0.5, 1.0), v(1.0, 3.0, 0.5, 1.0));
        let (a2, c2) = visible(a, c, depth).expect("visible");
        assert_eq!(a2, a);
        assert_close!(c2, v(1.0, 1.0, 0.5, 1.0), 1e-6, "{depth:?}");
        // The same backwards: the start moves.
        let (a2, c2) = visible(c, a, depth).expect("visible");
        assert_close!(a2, v(1.0, 1.0, 0.5, 1.0), 1e-6, "{depth:?}");
        assert_eq!(c2, a);
        // In the near plane, running out through the far side of x.
        let (a, c) = (v(0.0, 0.0, zn, 1.0), v(4.0, 0.0, zn, 1.0));
        let (_, c2) = visible(a, c, depth).expect("visible");
        assert_close!(c2, v(1.0, 0.0, zn, 1.0), 1e-6, "{depth:?}");
        // Touching the volume only along an edge of it (two planes at once): a single line.
        let (a, c) = (v(1.0, -3.0, 0.5, 1.0), v(1.0, 3.0, 0.5, 1.0));
        let (a2, c2) = visible(a, c, depth).expect("visible");
        assert_close!(a2, v(1.0, -1.0, 0.5, 1.0), 1e-6);
        assert_close!(c2, v(1.0, 1.0, 0.5, 1.0), 1e-6);
        // Grazing a corner from outside: a single point (or nothing) — never a real segment.
        let (a, c) = (v(2.0, 0.0, 0.5, 1.0), v(0.0, 2.0, 0.5, 1.0));
        if let Some((a2, c2)) = visible(a, c, depth) {
            assert_close!(a2, v(1.0, 1.0, 0.5, 1.0), 1e-6);
            assert_close!(c2, v(1.0, 1.0, 0.5, 1.0), 1e-6);
        }
    }
}

#[test]
fn zero_length_edges() {
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        for p in [
            v(0.2, -0.3, 0.5, 1.0),
            v(1e-6, 0.0, 1e-6, 1e-5),
            v(1e4, -1e4, 1e4, 1e4),
        ] {
            assert_eq!(clip_edge(p, p, depth), ClipOutcome::Accepted(p, p), "{p}");
        }
        for p in [
            v(2.0, 0.0, 0.5, 1.0),
            v(0.0, 0.0, zn - 0.5, 1.0),
            v(0.0, 0.0, 2.0, 1.0),
            v(0.0, 0.0, 0.5, -1.0),
        ] {
            assert_eq!(clip_edge(p, p, depth), ClipOutcome::Rejected, "{p}");
        }
        for p in [
            v(1.0, 0.0, 0.5, 1.0),
            v(-1.0, 1.0, 1.0, 1.0),
            v(0.0, 0.0, zn, 1.0),
        ] {
            assert_eq!(clip_edge(p, p, depth), ClipOutcome::Accepted(p, p), "{p}");
        }
    }
}

/// NaN, +∞ or −∞ in any of the eight coordinates → NonFinite, for inside and outside partners.
#[test]
fn non_finite_input_is_reported_not_clipped() {
    for depth in DEPTHS {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for partner in [
                v(0.0, 0.0, 0.5, 1.0),
                v(5.0, 0.0, 0.5, 1.0),
                v(0.0, 0.0, 0.0, 0.0),
            ] {
                for k in 0..8 {
                    let mut coords = [partner.to_array(), v(0.1, 0.2, 0.3, 1.0).to_array()];
                    coords[k / 4][k % 4] = bad;
                    let (a, c) = (Vec4::from(coords[0]), Vec4::from(coords[1]));
                    assert_eq!(clip_edge(a, c, depth), ClipOutcome::NonFinite, "{a} {c}");
                    assert_eq!(clip_edge(c, a, depth), ClipOutcome::NonFinite, "{c} {a}");
                }
            }
            let p = Vec4::splat(bad);
            assert_eq!(clip_edge(p, p, depth), ClipOutcome::NonFinite);
        }
    }
}

/// The eye (0, 0, 0, 0) and points with tiny w: no NaN or ∞ after the divide, w > 0 at both ends
/// of anything returned, and an edge from the eye draws nothing (it projects to a point).
#[test]
fn w_near_zero() {
    let eye = Vec4::ZERO;
    let mut partners = vec![
        v(0.0, 0.0, 0.5, 1.0),
        v(0.5, -0.5, 0.9, 1.0),
        v(3.0, 0.0, 0.5, 1.0),
        v(0.0, 0.0, 0.5, -1.0),
        v(0.0, 0.0, 0.0, 0.0),
        v(1.0, 1.0, 1.0, 1.0),
    ];
    for w in [1e-3f32, 1e-7, 1e-20, 1e-38, 1e-42, f32::MIN_POSITIVE] {
        partners.push(v(0.0, 0.0, 0.5 * w, w));
        partners.push(v(w, -w, w, w));
        partners.push(v(0.0, 0.0, 0.5 * w, -w));
        partners.push(v(2.0 * w, 0.0, 0.5 * w, w));
        partners.push(v(0.0, 0.0, 0.5, w));
    }
    for depth in DEPTHS {
        for &p in &partners {
            assert_eq!(visible(eye, p, depth), None, "eye → {p} {depth:?}");
            assert_eq!(visible(p, eye, depth), None, "{p} → eye {depth:?}");
            for &q in &partners {
                // `visible` checks w > 0 and a finite image for whatever comes back.
                let _ = visible(p, q, depth);
            }
        }
        // The eye to itself.
        assert_eq!(visible(eye, eye, depth), None);
        // A long edge passing exactly through the eye projects to a single point: nothing.
        let a = v(-1.0, -0.5, -0.5, -1.0);
        let c = v(1.0, 0.5, 0.5, 1.0);
        assert_eq!(visible(a, c, depth), None, "{depth:?}");
    }
}

/// Huge but finite coordinates (a far-away vertex, or a near-singular projection): the clipper
/// must still return finite segments with w > 0, never NaN or ∞.
#[test]
fn huge_finite_coordinates_give_finite_segments() {
    let inside = v(0.0, 0.0, 0.5, 1.0);
    let mut failures = Vec::new();
    for depth in DEPTHS {
        for big in [1e20f32, 1e30, 1e37, 1e38, f32::MAX] {
            for far in [
                v(big, 0.0, 0.5, 1.0),
                v(big, big, 0.0, 1.0),
                v(-big, 0.0, big, big),
                v(0.0, 0.0, 0.5, -big),
                v(big, -big, big, -big),
                v(-big, -big, -big, big),
            ] {
                for (a, c) in [(inside, far), (far, inside), (far, -far)] {
                    if a == c {
                        continue;
                    }
                    let out = clip_edge(a, c, depth);
                    if let Some((p, q)) = out.segment() {
                        let ok = [p, q].iter().all(|e| {
                            e.is_finite() && e.w > 0.0 && perspective_divide(*e).is_finite()
                        });
                        if !ok {
                            failures.push(format!("{depth:?}: {a:?} → {c:?} gave {out:?}"));
                        }
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} non-finite segments:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
