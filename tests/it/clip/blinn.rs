//! Blinn's homogeneous clipper: the seed's worked example, outcodes, trivial accept/reject,
//! edges behind the eye (with a real camera), boundary and degenerate edges, non-finite input,
//! w ≈ 0, a 10 000-edge-per-depth-range property test against an independent brute-force
//! reference, and the whole pipeline on the built-in plane. Every property is checked for both
//! depth ranges.

use crate::support::{
    assert_close, distance_from_line, edge_scale, inside_margin, recover_t, reference_ranges,
    to_f64, Rng, DEPTHS,
};
use glam::{Mat4, Vec2, Vec3, Vec4};
use wireflight::camera::{Camera, CameraPreset, Projection, Subject};
use wireflight::clip::{
    boundary_coords, clip_edge, is_inside, outcode, plane, ClipOutcome, ClipStats, Clipper,
    DepthRange, PLANE_COUNT,
};
use wireflight::euler::EulerZyx;
use wireflight::mesh::plane::builtin_plane;
use wireflight::pipeline::{model_matrix, perspective_divide, EdgeProjector, Viewport};

/// Relative tolerance of the geometric checks (relative to the edge's largest coordinate).
const REL_TOL: f64 = 1e-5;
/// Tolerance on the edge parameter t, on top of the sampling step.
const T_TOL: f64 = 1e-5;
/// Samples per edge for the brute-force reference.
const SAMPLES: usize = 20_001;

fn v(x: f32, y: f32, z: f32, w: f32) -> Vec4 {
    Vec4::new(x, y, z, w)
}

/// A z that is on the near side of the near plane by `by`·w, for either depth range.
fn z_near(depth: DepthRange, w: f32) -> f32 {
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

// ---------------------------------------------------------------------------------------------
// The property test against the brute-force reference
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    BothInside,
    SameSideOutside,
    CrossOne,
    CrossTwo,
    CrossThree,
    OutsideDifferentPlanes,
    OneBehindEye,
    BothBehindEye,
    Random,
    NearTheEye,
}

const KINDS: [Kind; 10] = [
    Kind::BothInside,
    Kind::SameSideOutside,
    Kind::CrossOne,
    Kind::CrossTwo,
    Kind::CrossThree,
    Kind::OutsideDifferentPlanes,
    Kind::OneBehindEye,
    Kind::BothBehindEye,
    Kind::Random,
    Kind::NearTheEye,
];

/// The coordinate scale of one edge: mostly around 1, some up to 1e4, some tiny.
fn random_scale(rng: &mut Rng) -> f64 {
    match rng.below(10) {
        0..=5 => rng.log_range(0.1, 10.0),
        6 | 7 => rng.log_range(100.0, 1e4),
        _ => rng.log_range(1e-6, 1e-3),
    }
}

fn inside_point(rng: &mut Rng, depth: DepthRange, s: f64) -> [f64; 4] {
    let w = s * rng.range(0.05, 1.0);
    let z_lo = match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => -w,
    };
    [
        w * rng.range(-1.0, 1.0),
        w * rng.range(-1.0, 1.0),
        z_lo + (w - z_lo) * rng.unit(),
        w,
    ]
}

/// Move `p` outside plane `i` (only that plane), by a random relative amount.
fn push_outside(rng: &mut Rng, p: &mut [f64; 4], i: usize, depth: DepthRange) {
    let w = p[3];
    let k = 1.0 + rng.log_range(1e-3, 3.0);
    match i {
        0 => p[0] = -w * k,
        1 => p[0] = w * k,
        2 => p[1] = -w * k,
        3 => p[1] = w * k,
        4 => {
            p[2] = match depth {
                DepthRange::ZeroToOne => -w * (k - 1.0),
                DepthRange::NegOneToOne => -w * k,
            }
        }
        _ => p[2] = w * k,
    }
}

fn behind_point(rng: &mut Rng, s: f64) -> [f64; 4] {
    [
        s * rng.range(-1.0, 1.0),
        s * rng.range(-1.0, 1.0),
        s * rng.range(-1.0, 1.0),
        -s * rng.range(0.001, 1.0),
    ]
}

fn to_vec4(p: [f64; 4]) -> Vec4 {
    Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32)
}

fn random_edge(rng: &mut Rng, kind: Kind, depth: DepthRange) -> (Vec4, Vec4) {
    let s = random_scale(rng);
    let (a, c) = match kind {
        Kind::BothInside => (inside_point(rng, depth, s), inside_point(rng, depth, s)),
        Kind::SameSideOutside => {
            let i = rng.below(PLANE_COUNT);
            let (mut a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            push_outside(rng, &mut a, i, depth);
            push_outside(rng, &mut c, i, depth);
            (a, c)
        }
        Kind::CrossOne | Kind::CrossTwo | Kind::CrossThree => {
            let (a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            // One plane of each opposite pair (two opposite planes cannot both be violated).
            let mut pairs = [0usize, 1, 2];
            for i in (1..3).rev() {
                pairs.swap(i, rng.below(i + 1));
            }
            let n = match kind {
                Kind::CrossOne => 1,
                Kind::CrossTwo => 2,
                _ => 3,
            };
            for &pair in &pairs[..n] {
                let i = 2 * pair + rng.below(2);
                push_outside(rng, &mut c, i, depth);
            }
            (a, c)
        }
        Kind::OutsideDifferentPlanes => {
            let i = rng.below(PLANE_COUNT);
            let j = (i + 1 + rng.below(PLANE_COUNT - 1)) % PLANE_COUNT;
            let (mut a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            push_outside(rng, &mut a, i, depth);
            push_outside(rng, &mut c, j, depth);
            (a, c)
        }
        Kind::OneBehindEye => {
            let a = if rng.chance(0.7) {
                inside_point(rng, depth, s)
            } else {
                let mut a = inside_point(rng, depth, s);
                let i = rng.below(PLANE_COUNT);
                push_outside(rng, &mut a, i, depth);
                a
            };
            (a, behind_point(rng, s))
        }
        Kind::BothBehindEye => (behind_point(rng, s), behind_point(rng, s)),
        Kind::Random => {
            let mut r = || std::array::from_fn(|_| s * rng.range(-1.0, 1.0));
            (r(), r())
        }
        Kind::NearTheEye => {
            let a = inside_point(rng, depth, s);
            let k = rng.range(0.05, 2.0);
            let noise = s * 10f64.powf(rng.range(-6.0, -1.0));
            let c = std::array::from_fn(|i| -k * a[i] + noise * rng.range(-1.0, 1.0));
            (a, c)
        }
    };
    let (a, c) = (to_vec4(a), to_vec4(c));
    if rng.chance(0.5) {
        (c, a)
    } else {
        (a, c)
    }
}

/// What the property check saw, for the summary.
#[derive(Default, Debug)]
struct Tally {
    stats: ClipStats,
    /// Clipper and strict reference disagree on "anything visible", excused as tangent (the
    /// robustly-inside part is shorter than one step) or as within the tolerance band.
    tangent_excused: u32,
    /// Largest |t_clipper − t_reference| seen against the strict reference.
    max_t_error: f64,
    /// Endpoints that pass `is_inside` only with the tolerance taken relative to the edge's
    /// scale instead of the point's own.
    needed_edge_relative_tol: u32,
}

/// Whether the part t ∈ [t0, t1] of the edge (all with w > 0) has an image shorter than 1e-4 in
/// NDC: it lies on a ray from the eye (the edge passes through the eye), so it draws nothing.
fn projects_to_a_point(a: Vec4, c: Vec4, t0: f64, t1: f64) -> bool {
    let (a, c) = (to_f64(a), to_f64(c));
    let ndc = |t: f64| {
        let p: [f64; 4] = std::array::from_fn(|k| a[k] + t * (c[k] - a[k]));
        (p[0] / p[3], p[1] / p[3])
    };
    let (p, q) = (ndc(t0), ndc(t1));
    (p.0 - q.0).hypot(p.1 - q.1) < 1e-4
}

/// Check one edge against every property; `Err` describes the violation.
fn check_edge(a: Vec4, c: Vec4, depth: DepthRange, tally: &mut Tally) -> Result<(), String> {
    let out = clip_edge(a, c, depth);
    tally.stats.record(&out);
    let scale = edge_scale(a, c);
    let slack = REL_TOL * scale;
    let reference = reference_ranges(a, c, depth, SAMPLES, slack);
    let h = reference.step;
    let fail = |what: String| {
        Err(format!(
            "{what}\n    edge: a = {a:?}, c = {c:?}, {depth:?}\n    clip_edge → {out:?}\n    \
             reference (step {h:e}): {reference:?}"
        ))
    };
    let (ma, mc) = (
        inside_margin(to_f64(a), depth),
        inside_margin(to_f64(c), depth),
    );
    let codes = (
        outcode(&boundary_coords(a, depth)),
        outcode(&boundary_coords(c, depth)),
    );

    let segment = match out {
        ClipOutcome::NonFinite => return fail("NonFinite for finite input".into()),
        ClipOutcome::Accepted(a2, c2) => {
            if (a2, c2) != (a, c) {
                return fail("Accepted but changed".into());
            }
            if ma < 0.0 || mc < 0.0 || a.w <= 0.0 || c.w <= 0.0 {
                return fail(format!(
                    "Accepted with an endpoint outside (margins {ma}, {mc})"
                ));
            }
            Some((a2, c2))
        }
        ClipOutcome::Rejected => {
            if codes.0 & codes.1 == 0 {
                return fail(format!(
                    "Rejected without a common outside plane: {:06b} {:06b}",
                    codes.0, codes.1
                ));
            }
            None
        }
        ClipOutcome::Clipped(a2, c2) => {
            if codes.0 | codes.1 == 0 || codes.0 & codes.1 != 0 {
                return fail("Clipped a trivial edge".into());
            }
            // An endpoint that was inside must be kept exactly.
            if codes.0 == 0 && a2 != a {
                return fail("inside start point moved".into());
            }
            if codes.1 == 0 && c2 != c {
                return fail("inside end point moved".into());
            }
            Some((a2, c2))
        }
        ClipOutcome::ClippedAway => None,
    };

    match segment {
        Some((a2, c2)) => {
            let mut ts = [0.0; 2];
            for (k, p) in [a2, c2].into_iter().enumerate() {
                if !p.is_finite() || p.w <= 0.0 {
                    return fail(format!("endpoint {p:?} not finite or w ≤ 0"));
                }
                let ndc = perspective_divide(p);
                if !ndc.is_finite() {
                    return fail(format!("endpoint {p:?} divides to {ndc}"));
                }
                // Inside within 1e-5 relative: first relative to the point itself (as
                // `is_inside` measures), else relative to the edge's scale, which is what f32
                // arithmetic on the edge can promise for a point much smaller than the edge.
                if !is_inside(p, depth, REL_TOL as f32) {
                    let own = f64::from(p.abs().max_element());
                    let rel = (slack / own.max(f64::MIN_POSITIVE)) as f32;
                    if !is_inside(p, depth, rel) || inside_margin(to_f64(p), depth) < -slack {
                        return fail(format!(
                            "endpoint {p:?} outside the volume by more than {slack:e} \
                             (margin {:e})",
                            inside_margin(to_f64(p), depth)
                        ));
                    }
                    tally.needed_edge_relative_tol += 1;
                }
                let Some(t) = recover_t(a, c, p) else {
                    return fail("clipped a zero-length edge".into());
                };
                if !(-T_TOL..=1.0 + T_TOL).contains(&t) {
                    return fail(format!("endpoint {p:?} at t = {t}, outside [0, 1]"));
                }
                let off = distance_from_line(a, c, t, p);
                if off > slack {
                    return fail(format!(
                        "endpoint {p:?} is {off:e} off the edge (t = {t}), tolerance {slack:e}"
                    ));
                }
                ts[k] = t;
            }
            let [t0, t1] = ts;
            if t0 > t1 + T_TOL {
                return fail(format!("direction reversed: t {t0} > {t1}"));
            }
            let Some((l0, l1)) = reference.loose else {
                return fail("drawn, but no sample is inside even with the tolerance".into());
            };
            if t0 < l0 - h - T_TOL || t1 > l1 + h + T_TOL {
                return fail(format!(
                    "drawn t-range [{t0}, {t1}] exceeds the reference's [{l0}, {l1}] (with tolerance)"
                ));
            }
            if let Some((r0, r1)) = reference.robust {
                if t0 > r0 + h + T_TOL || t1 < r1 - h - T_TOL {
                    return fail(format!(
                        "drawn t-range [{t0}, {t1}] misses part of the robustly inside \
                         [{r0}, {r1}]"
                    ));
                }
            }
            match reference.strict {
                Some((r0, r1)) => {
                    let err = (t0 - r0).abs().max((t1 - r1).abs());
                    tally.max_t_error = tally.max_t_error.max(err);
                }
                None => tally.tangent_excused += 1,
            }
        }
        None => {
            if let Some((r0, r1)) = reference.robust {
                if r1 - r0 > h && !projects_to_a_point(a, c, r0, r1) {
                    return fail(format!(
                        "nothing drawn, but t ∈ [{r0}, {r1}] is inside by at least {slack:e}"
                    ));
                }
            }
            if let Some((r0, r1)) = reference.strict {
                if r1 - r0 > h {
                    tally.tangent_excused += 1;
                }
            }
        }
    }
    Ok(())
}

/// 12 000 edges per depth range, a mix of every kind, each checked against the brute-force
/// reference (20 001 samples per edge).
#[test]
fn property_clipper_matches_brute_force_reference() {
    let per_kind = 1_200;
    let mut report = String::new();
    let mut failures = Vec::new();
    let mut total_failures = 0;
    for depth in DEPTHS {
        let mut rng = Rng::new(0xC11B_0000 + depth as u64);
        let mut tally = Tally::default();
        for &kind in &KINDS {
            for i in 0..per_kind {
                let (a, c) = random_edge(&mut rng, kind, depth);
                if let Err(e) = check_edge(a, c, depth, &mut tally) {
                    total_failures += 1;
                    if failures.len() < 8 {
                        failures.push(format!("[{kind:?} #{i}] {e}"));
                    }
                }
            }
        }
        // The mix really exercises every outcome.
        let s = tally.stats;
        assert_eq!(s.edges_in, (per_kind * KINDS.len()) as u64);
        assert!(s.trivially_accepted > 1_000, "{depth:?}: {s}");
        assert!(s.trivially_rejected > 1_000, "{depth:?}: {s}");
        assert!(s.clipped > 2_000, "{depth:?}: {s}");
        assert!(s.clipped_away > 100, "{depth:?}: {s}");
        report += &format!("{depth:?}: {s}; {tally:?}\n");
    }
    println!("{report}");
    assert!(
        failures.is_empty(),
        "{total_failures} edges violate the clipper's properties; the first {}:\n\n{}\n\n{report}",
        failures.len(),
        failures.join("\n\n")
    );
}

/// The property check on hand-picked awkward edges: tangent to a plane, along an edge or through
/// a corner of the volume, nearly parallel to a plane, very long and very short.
#[test]
fn property_holds_on_awkward_edges() {
    let mut tally = Tally::default();
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let edges = [
            (v(-2.0, 1.0, 0.5, 1.0), v(2.0, 1.0, 0.5, 1.0)), // along y = w
            (v(-2.0, -2.0, 0.5, 1.0), v(2.0, 2.0, 0.5, 1.0)), // through two corners
            (v(-2.0, -2.0, zn - 1.0, 1.0), v(2.0, 2.0, 2.0, 1.0)), // body diagonal
            (v(-1e4, 0.0, 0.5, 1.0), v(1e4, 0.0, 0.5, 1.0)), // very long in x
            (v(0.0, 0.0, 0.5, 1e-4), v(0.0, 0.0, 0.5, 1.0)), // w from tiny to 1
            (v(1.0001, -2.0, 0.5, 1.0), v(1.0001, 2.0, 0.5, 1.0)), // just outside x = w
            (v(0.9999, -2.0, 0.5, 1.0), v(0.9999, 2.0, 0.5, 1.0)), // just inside x = w
            (v(0.0, 0.0, 0.5, 1.0), v(0.0, 0.0, 0.5, -1.0)), // straight back through the eye
            (v(0.3, 0.3, 0.5, 1.0), v(-0.3, -0.3, -0.5, -1.0)), // through the eye
            (v(0.5, 0.0, 0.5, 1.0), v(-1e4, 0.0, -1e4, -1e4)), // far behind
            (v(1e-6, 1e-6, 1e-6, 2e-6), v(-3e-6, 0.0, 1e-6, 2e-6)), // tiny
        ];
        for (a, c) in edges {
            for (p, q) in [(a, c), (c, a)] {
                if let Err(e) = check_edge(p, q, depth, &mut tally) {
                    panic!("{e}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The pipeline on the built-in plane
// ---------------------------------------------------------------------------------------------

fn project_plane(
    attitude: EulerZyx,
    preset: CameraPreset,
    pan: [f32; 2],
    depth: DepthRange,
    viewport: Viewport,
) -> (Vec<wireflight::render::Segment2>, ClipStats, usize) {
    let mesh = builtin_plane();
    let (centre, radius) = mesh.bounding_sphere();
    let subject = Subject {
        position: Vec3::new(10.0, -20.0, 300.0),
        attitude,
        centre,
        radius,
    };
    let camera = preset
        .camera(&subject, 50f32.to_radians())
        .panned(pan[0] * radius, pan[1] * radius);
    let clip_from_model: Mat4 =
        camera.clip_from_world(viewport.aspect(), depth) * model_matrix(subject.position, attitude);
    let mut out = Vec::new();
    let stats = EdgeProjector::new(Clipper::Blinn, depth).project(
        &mesh,
        clip_from_model,
        viewport,
        &mut out,
    );
    (out, stats, mesh.edges().len())
}

/// Every segment lies in the image, the tally adds up to the edge count, and every drawn edge
/// gives one segment, for a range of attitudes, cameras (chase; panned half out of the picture;
/// cockpit, where much of the plane is beside and behind the eye) and both depth ranges.
#[test]
fn pipeline_segments_stay_in_the_viewport() {
    let viewport = Viewport {
        width: 640,
        height: 480,
    };
    let (w, h) = (viewport.width as f32, viewport.height as f32);
    let tol = 0.01;
    let mut clipped_somewhere = 0;
    for depth in DEPTHS {
        for (preset, pan) in [
            (CameraPreset::Chase, [0.0, 0.0]),
            (CameraPreset::Chase, [1.6, 0.0]),
            (CameraPreset::Chase, [0.0, -1.2]),
            (CameraPreset::Cockpit, [0.0, 0.0]),
            (CameraPreset::Front, [0.0, 0.0]),
            (CameraPreset::Top, [0.0, 0.0]),
            (CameraPreset::Side, [0.0, 0.0]),
        ] {
            for yaw in (-180..180).step_by(45) {
                for pitch in [-90, -60, -20, 0, 30, 90] {
                    for roll in [-150, 0, 40] {
                        let attitude =
                            EulerZyx::from_degrees(yaw.into(), pitch.into(), roll.into());
                        let (segs, stats, n_edges) =
                            project_plane(attitude, preset, pan, depth, viewport);
                        let ctx = format!("{preset:?} pan {pan:?} {attitude:?} {depth:?}: {stats}");
                        assert_eq!(stats.edges_in, n_edges as u64, "{ctx}");
                        assert_eq!(
                            stats.trivially_accepted
                                + stats.trivially_rejected
                                + stats.clipped
                                + stats.clipped_away
                                + stats.non_finite,
                            stats.edges_in,
                            "{ctx}"
                        );
                        assert_eq!(stats.non_finite, 0, "{ctx}");
                        assert_eq!(segs.len() as u64, stats.drawn(), "{ctx}");
                        if preset == CameraPreset::Chase && pan == [0.0, 0.0] {
                            // The chase camera frames the whole plane.
                            assert_eq!(stats.drawn(), stats.edges_in, "{ctx}");
                        }
                        clipped_somewhere += stats.clipped;
                        for s in &segs {
                            for p in [s.a, s.b] {
                                assert!(
                                    p.is_finite()
                                        && (-tol..=w + tol).contains(&p.x)
                                        && (-tol..=h + tol).contains(&p.y),
                                    "{ctx}: segment {s:?} leaves the {w}×{h} image"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(clipped_somewhere > 100, "the cases exercise the clipper");
}
