//! What the fuzzers found, written out by value (the inputs are also in `fuzz/corpus/` as
//! `regress-*` files, replayed by `corpus`): each case goes through the full property check
//! and the specific property it broke is asserted on its own, so the test names the bug.

use super::check::{check_homogeneous, check_planar, Tally, HOMOGENEOUS, PLANAR};
use glam::{Vec2, Vec4};
use wireflight::geometry::clip::{
    clip_edge, cyrus_beck, ClipOutcome, ClipVolume, DepthRange, Window2,
};

/// Cyrus-Beck computed the rate `d₁ = D·n` as a dot product with the rounded `D`, so an end
/// inside the volume (on the planes y = w and z = w) got `t₁ = 1 − 3·10⁻⁷` and moved:
/// `(17, 18, 18, 18)` came back as `(16.999994, 17.999994, …)`. Found by the `cyrus_beck`
/// target in 57 000 executions; fixed by taking `d₁` as the difference of the boundary values
/// at the two ends.
#[test]
fn cyrus_beck_keeps_an_inside_end_on_two_planes() {
    let a = Vec4::new(-1.0, -1.5, -9.765_625e-10, 3.559_244_4e-17);
    let c = Vec4::new(17.0, 18.0, 18.0, 18.0);
    let v = ClipVolume::new(DepthRange::ZeroToOne);
    let (_, q) = cyrus_beck::clip_homogeneous(a, c, &v)
        .segment()
        .expect("C is inside: something is visible");
    assert_eq!(q, c, "the inside end moved");
    let mut tally = Tally::default();
    for algo in HOMOGENEOUS {
        check_homogeneous(algo, a, c, &v, &mut tally).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// The same property in 2D, where the fuzzer found nothing (the window's normals are exact
/// and `f32` differences mostly exact in `f64`, so the old code passed this too): an end on a
/// window edge or corner, the other far away; the inside end comes back unchanged from
/// Cyrus-Beck, and every algorithm passes the full check.
#[test]
fn planar_ends_on_an_edge_stay_put_beside_a_far_end() {
    let w = Window2::new(-3.0, -1.0, 7.0, 5.0).unwrap();
    let corners = w.corners();
    let poly = cyrus_beck::ConvexPolygon::new(&corners).unwrap();
    let mut tally = Tally::default();
    for far in [1e-9f32, 3.7e-7, 1e7, 3.3e12, 1e30] {
        for (a, c) in [
            (Vec2::new(-far, -far), Vec2::new(7.0, 5.0)),
            (Vec2::new(far, -far * 0.3), Vec2::new(-3.0, 2.0)),
            (Vec2::new(-far * 0.7, far), Vec2::new(6.999_999_5, 5.0)),
        ] {
            let (_, q) = cyrus_beck::clip_polygon(a, c, &poly)
                .segment()
                .unwrap_or_else(|| panic!("{c} is inside, yet nothing is visible (from {a})"));
            assert_eq!(q, c, "cyrus-beck moved the inside end {c} (from {a})");
            for algo in PLANAR {
                check_planar(algo, a, c, &w, &mut tally).unwrap_or_else(|e| panic!("{e}"));
            }
        }
    }
}

/// Blinn's AVX-512 lanes kept an end that the per-edge clipper's `settle()` moves. The edge
/// from `(7.2e-43, 0, 0, 0)` (x = 514 of the smallest `f32` steps, at the eye) to
/// `(5.25e-20, −1, 0, 3)` enters at t = 2.4e-43, where the new end is x = 514 steps, w = 513:
/// one step outside x = w. `settle()` (in `f64`) recomputes and clamps it to x = w; the
/// lanes' `f32` test compared w − x with −0.001·max |p|, which underflowed to one whole step
/// and let the end through. Found by the `blinn` target in 123 000 executions; fixed by
/// leaving ends smaller than 2⁻¹⁰⁰ to the scalar code.
#[test]
fn blinn_batch_settles_a_subnormal_end_as_the_per_edge_clipper_does() {
    let start = Vec4::new(7.2e-43, 0.0, 0.0, 0.0);
    let end = Vec4::new(5.249_999_7e-20, -1.0, 0.0, 3.0);
    let inside = (
        Vec4::new(0.25, -0.5, 0.5, 1.0),
        Vec4::new(-0.5, 0.25, 0.25, 1.0),
    );
    let edges: Vec<(Vec4, Vec4)> = (0..40)
        .map(|i| if i % 3 == 0 { (start, end) } else { inside })
        .collect();
    super::check::check_batch(&edges, DepthRange::ZeroToOne).unwrap_or_else(|e| panic!("{e}"));
    let ClipOutcome::Clipped(p, _) = clip_edge(start, end, DepthRange::ZeroToOne) else {
        panic!("the edge is visible");
    };
    assert_eq!(p.x, p.w, "settle() puts the new end on x = w");
}
