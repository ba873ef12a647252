//! Weiler-Atherton: the degenerate cases by hand, then property tests against an independent
//! polygon-boolean implementation (`geo`'s `BooleanOps`, built on `i_overlay`), used only here
//! as an oracle.
//!
//! The property tests run `WA_CASES` cases per generator (default 3000):
//! `WA_CASES=300000 cargo test -p wireflight-geometry --test weiler_atherton --release -- --nocapture`.

use std::cell::Cell;

use geo::{Area, BooleanOps};
use glam::DVec2;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use wireflight_geometry::clip::weiler_atherton::{
    self as wa, clip, difference, intersection, total_area, Piece, PolygonError, Which,
};

fn p(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<DVec2> {
    vec![p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1)]
}

fn reversed(v: &[DVec2]) -> Vec<DVec2> {
    v.iter().rev().copied().collect()
}

fn rotated(v: &[DVec2], k: usize) -> Vec<DVec2> {
    let mut v = v.to_vec();
    let n = v.len();
    v.rotate_left(k % n);
    v
}

/// Every orientation and start vertex of both polygons gives the same areas and piece counts.
fn check_all_ways(a: &[DVec2], b: &[DVec2], inter: (usize, f64), diff: (usize, f64)) {
    for ra in [false, true] {
        for rb in [false, true] {
            for ka in 0..a.len() {
                for kb in 0..b.len() {
                    let aa = rotated(&if ra { reversed(a) } else { a.to_vec() }, ka);
                    let bb = rotated(&if rb { reversed(b) } else { b.to_vec() }, kb);
                    let r = clip(&aa, &bb).unwrap();
                    let got_i = (r.intersection.len(), total_area(&r.intersection));
                    let got_d = (r.difference.len(), total_area(&r.difference));
                    assert_eq!(got_i, inter, "intersection of {aa:?} and {bb:?}");
                    assert_eq!(got_d, diff, "difference of {aa:?} and {bb:?}");
                    for piece in r.intersection.iter().chain(&r.difference) {
                        assert!(wa::signed_area(&piece.outer) > 0.0, "outline is ccw");
                        for h in &piece.holes {
                            assert!(wa::signed_area(h) < 0.0, "hole is cw");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn overlapping_squares() {
    check_all_ways(
        &rect(0., 0., 2., 2.),
        &rect(1., 1., 3., 3.),
        (1, 1.0),
        (1, 3.0),
    );
}

#[test]
fn disjoint() {
    check_all_ways(
        &rect(0., 0., 1., 1.),
        &rect(2., 2., 3., 3.),
        (0, 0.0),
        (1, 1.0),
    );
}

#[test]
fn equal_polygons() {
    let l = vec![
        p(0., 0.),
        p(2., 0.),
        p(2., 1.),
        p(1., 1.),
        p(1., 2.),
        p(0., 2.),
    ];
    check_all_ways(&l, &l, (1, 3.0), (0, 0.0));
    let r = intersection(&l, &reversed(&l)).unwrap();
    assert_eq!(r.len(), 1);
    assert_eq!(r[0].outer.len(), 6, "{r:?}");
}

#[test]
fn one_inside_the_other() {
    let outer = rect(0., 0., 4., 4.);
    let inner = rect(1., 1., 2., 2.);
    check_all_ways(&outer, &inner, (1, 1.0), (1, 15.0));
    check_all_ways(&inner, &outer, (1, 1.0), (0, 0.0));
    let d = difference(&outer, &inner).unwrap();
    assert_eq!(d[0].holes.len(), 1, "a hole: {d:?}");
}

#[test]
fn inside_touching_along_an_edge() {
    // The inner square sits on the outer's bottom edge: the difference is a U, no hole.
    let outer = rect(0., 0., 4., 4.);
    let inner = rect(1., 0., 2., 1.);
    check_all_ways(&outer, &inner, (1, 1.0), (1, 15.0));
    let d = difference(&outer, &inner).unwrap();
    assert!(d[0].holes.is_empty(), "{d:?}");
}

#[test]
fn inside_touching_at_a_vertex() {
    // A diamond inside the square, its bottom corner on the square's bottom edge: the
    // difference is one piece whose outline visits that point twice (no hole).
    let outer = rect(0., 0., 4., 4.);
    let diamond = vec![p(2., 0.), p(3., 1.), p(2., 2.), p(1., 1.)];
    check_all_ways(&outer, &diamond, (1, 2.0), (1, 14.0));
    let d = difference(&outer, &diamond).unwrap();
    assert!(d[0].holes.is_empty(), "{d:?}");
    assert_eq!(d[0].outer.iter().filter(|&&v| v == p(2., 0.)).count(), 2);
}

#[test]
fn touching_along_an_edge() {
    check_all_ways(
        &rect(0., 0., 2., 2.),
        &rect(2., 0., 4., 2.),
        (0, 0.0),
        (1, 4.0),
    );
    // Partly: the edges overlap collinearly over [1, 2].
    check_all_ways(
        &rect(0., 0., 2., 2.),
        &rect(2., 1., 4., 3.),
        (0, 0.0),
        (1, 4.0),
    );
}

#[test]
fn collinear_overlapping_edges() {
    // Both bottoms on y = 0, overlapping over [1, 2]; the tops too.
    check_all_ways(
        &rect(0., 0., 2., 2.),
        &rect(1., 0., 3., 2.),
        (1, 2.0),
        (1, 2.0),
    );
    // Only the bottoms overlap.
    check_all_ways(
        &rect(0., 0., 2., 2.),
        &rect(1., 0., 3., 1.),
        (1, 1.0),
        (1, 3.0),
    );
}

#[test]
fn shared_vertices() {
    // Corner to corner: nothing in common.
    check_all_ways(
        &rect(0., 0., 1., 1.),
        &rect(1., 1., 2., 2.),
        (0, 0.0),
        (1, 1.0),
    );
    // A triangle sharing two corners of the square (its diagonal), inside it.
    let tri = vec![p(0., 0.), p(2., 0.), p(2., 2.)];
    check_all_ways(&rect(0., 0., 2., 2.), &tri, (1, 2.0), (1, 2.0));
    // Edges crossing exactly at a shared vertex: an X through (1, 1).
    let a = vec![p(0., 0.), p(1., 1.), p(0., 2.), p(-1., 1.)];
    let b = vec![p(1., 1.), p(2., 0.), p(3., 1.), p(2., 2.)];
    check_all_ways(&a, &b, (0, 0.0), (1, 2.0));
}

#[test]
fn vertex_on_an_edge() {
    let sq = rect(0., 0., 4., 4.);
    // A triangle outside, its tip on the square's top edge.
    let out = vec![p(1., 6.), p(2., 4.), p(3., 6.)];
    check_all_ways(&sq, &out, (0, 0.0), (1, 16.0));
    // A triangle crossing the top edge, one vertex on it.
    let across = vec![p(2., 4.), p(3., 2.), p(3., 6.)];
    check_all_ways(&sq, &across, (1, 1.0), (1, 15.0));
    // A triangle inside with one vertex on the right edge.
    let inner = vec![p(1., 1.), p(4., 2.), p(1., 3.)];
    check_all_ways(&sq, &inner, (1, 3.0), (1, 13.0));
}

#[test]
fn pieces_touching_at_a_point_are_separate() {
    // A square with a V notch down to (2, 2), cut by the band y ≥ 2: two pieces meeting at
    // (2, 2).
    let notched = vec![
        p(0., 0.),
        p(4., 0.),
        p(4., 4.),
        p(3., 4.),
        p(2., 2.),
        p(1., 4.),
        p(0., 4.),
    ];
    let band = rect(-1., 2., 5., 5.);
    check_all_ways(&notched, &band, (2, 6.0), (1, 8.0));
}

#[test]
fn concave_both() {
    // Two combs crossing: a U and an upside-down U make a ring of four pieces... two pieces.
    let u = vec![
        p(0., 0.),
        p(3., 0.),
        p(3., 3.),
        p(2., 3.),
        p(2., 1.),
        p(1., 1.),
        p(1., 3.),
        p(0., 3.),
    ];
    let bar = rect(-1., 2., 4., 2.5);
    check_all_ways(&u, &bar, (2, 1.0), (3, 6.0));
}

#[test]
fn refusals() {
    let bowtie = vec![p(0., 0.), p(2., 2.), p(2., 0.), p(0., 2.)];
    let err = intersection(&bowtie, &rect(0., 0., 1., 1.)).unwrap_err();
    assert_eq!(
        err,
        PolygonError::SelfIntersecting {
            polygon: Which::Subject,
            a: 0,
            b: 2,
            at: p(1., 1.)
        }
    );
    assert_eq!(
        err.to_string(),
        "subject polygon is not simple: edges 0 and 2 meet at (1, 1)"
    );
    // A vertex repeated (figure eight touching itself).
    let eight = vec![
        p(0., 0.),
        p(1., 1.),
        p(2., 0.),
        p(2., 2.),
        p(1., 1.),
        p(0., 2.),
    ];
    assert!(matches!(
        intersection(&rect(0., 0., 1., 1.), &eight),
        Err(PolygonError::SelfIntersecting {
            polygon: Which::Clip,
            ..
        })
    ));
    // A vertex on a non-adjacent edge.
    let touch = vec![p(0., 0.), p(4., 0.), p(4., 4.), p(2., 0.), p(0., 4.)];
    assert!(matches!(
        wa::validate(&touch, Which::Subject),
        Err(PolygonError::SelfIntersecting { at, .. }) if at == p(2., 0.)
    ));
    // A spike doubling back; all collinear.
    let spike = vec![
        p(0., 0.),
        p(2., 0.),
        p(2., 2.),
        p(2., 3.),
        p(2., 1.),
        p(0., 2.),
    ];
    assert!(matches!(
        wa::validate(&spike, Which::Subject),
        Err(PolygonError::SelfIntersecting { .. })
    ));
    let flat = vec![p(0., 0.), p(1., 0.), p(2., 0.)];
    assert!(matches!(
        wa::validate(&flat, Which::Subject),
        Err(PolygonError::SelfIntersecting { .. })
    ));
    // Two edges crossing within 2e-18 of the origin, 4e5 away from the rest: rounded
    // orientation tests called this simple (found by the fuzz target).
    let near = vec![
        p(-395968., 2.000000000010776),
        p(-188672., -181440.),
        p(3.24107e-319, 1.5306383733243713e-18),
        p(1.5308501193928198e-18, 1.6725e-319),
    ];
    let err = wa::validate(&near, Which::Subject).unwrap_err();
    assert!(
        matches!(err, PolygonError::SelfIntersecting { a: 1, b: 3, at, .. } if at.length() < 1e-17),
        "{err}"
    );
    // Too few distinct vertices, after merging repeats and the closing copy.
    let few = vec![p(0., 0.), p(0., 0.), p(1., 0.), p(0., 0.)];
    assert_eq!(
        wa::validate(&few, Which::Clip),
        Err(PolygonError::TooFewVertices {
            polygon: Which::Clip,
            distinct: 2
        })
    );
    // Non-finite.
    let nan = vec![p(0., 0.), p(1., 0.), p(f64::NAN, 1.)];
    assert_eq!(
        intersection(&rect(0., 0., 1., 1.), &nan),
        Err(PolygonError::NonFinite {
            polygon: Which::Clip,
            vertex: 2
        })
    );
    let inf = vec![p(0., 0.), p(f64::INFINITY, 0.), p(0., 1.)];
    assert!(matches!(
        wa::validate(&inf, Which::Subject),
        Err(PolygonError::NonFinite { vertex: 1, .. })
    ));
    // A closed ring (first vertex repeated at the end) is accepted.
    let mut closed = rect(0., 0., 1., 1.);
    closed.push(closed[0]);
    assert_eq!(wa::validate(&closed, Which::Subject).unwrap().len(), 4);
}

/// Polygons with `f64` coordinates where one comes within about 10⁻¹⁶ of its size of the
/// other's edge or vertex, or has subnormal coordinates: inputs the fuzz target found (its
/// decoding, written out by value). Rounded orientation tests contradicted each other on them
/// and `clip` lost whole pieces: |A∩B| + |A−B| = 0, or |A∩B| = 3294 and |B∩A| = 0.
fn fuzz_found() -> Vec<(Vec<DVec2>, Vec<DVec2>)> {
    let z = p(0., 0.);
    vec![
        // A∩B was right (B less a sliver), B∩A empty.
        (
            vec![p(542272., 0.), p(7.791398095360777e-20, 0.), p(0., 407040.)],
            vec![p(108., 108.), p(108., 47.), z],
        ),
        // Touching along 7.8e-20 of an edge: A − B is A, and was empty.
        (
            vec![
                p(7.792688190771286e-20, 0.),
                p(0., -819584.),
                p(-353536., 0.),
            ],
            vec![p(113., 9.), z, p(4., 0.)],
        ),
        (
            vec![
                p(-2.6151483756335134e-11, -266624.),
                p(565376., -3.886321732286099e-16),
                p(-391424., -3.245647755627273e-12),
            ],
            vec![p(-14., -68.), p(-116., -116.), p(-52., 0.)],
        ),
        // A sliver 7e-15 thick and 7.6e5 long across a small quadrilateral; repeated vertices.
        (
            vec![p(49., 0.), p(38., 41.), p(21., 1.), p(0., -3.)],
            vec![
                p(755872.4931621552, -7.21664617170734e-15),
                p(-3264., 0.),
                z,
                z,
                z,
                z,
                z,
            ],
        ),
        (
            vec![p(49., 0.), p(38., 41.), p(21., 1.), p(0., -3.)],
            vec![
                p(364384.4956035614, -2.8706429594516234e-12),
                p(768832., 768832.),
                p(768832., 768832.),
                z,
                z,
            ],
        ),
        (
            vec![p(-88., -88.), p(63., -102.), p(58., 0.)],
            vec![
                z,
                p(353984., -6.350048437320642e-20),
                p(0., 937280.),
                p(-311360., 0.),
                z,
                z,
            ],
        ),
        // Subnormal coordinates beside ordinary ones.
        (
            vec![
                p(-3.3469338411939194e-10, 2.44453914799134e-310),
                p(402304., 21376.),
                p(454720., 21376.),
            ],
            vec![p(106., 17.), p(-36., 0.), z],
        ),
        (
            vec![p(63., -102.), z, p(60., 60.), p(60., 60.)],
            vec![
                p(1.5306383611530364e-18, 5.17826075452e-312),
                p(2.53e-321, 1.53063836039573e-18),
                p(4.563297340194817e-304, 1.6578092e-316),
            ],
        ),
        (
            vec![z, p(66., 61.), p(61., 61.), p(61., 57.)],
            vec![
                p(1.0387856152602562e-13, 0.),
                p(5.41108926696e-312, 1.038785615299637e-13),
                p(1.0387856152602562e-13, 1.0387856152602562e-13),
            ],
        ),
        (
            vec![
                p(7.792357379110818e-20, 3.725e-321),
                p(1.251836274629365e-308, 1.543355739542625e-128),
                p(560896., 560896.),
                p(560896., -1.1427628509582581e-248),
            ],
            vec![p(-117., -117.), p(-113., -87.), p(116., 116.)],
        ),
        (
            vec![
                p(7.792687605120985e-20, 5.12767350717e-311),
                p(-1.208264317244006e-179, -892928.),
                p(-916096., 2.481042622579877e-265),
                p(1.6171836809598453e-304, -763392.),
            ],
            vec![p(3., 0.), p(0., -1.), p(-55., -102.)],
        ),
    ]
}

/// Every fuzz-found case, both ways round: our books balance (|A∩B| + |A−B| = |A|, A∩B =
/// B∩A, to 1e-12) and the oracle's total areas agree (its pieces need not: see
/// [`Detail::Totals`]; the fourth case is one).
#[test]
fn near_degenerate_cases_found_by_fuzzing() {
    let tally = Tally::default();
    for (a, b) in fuzz_found() {
        for (x, y) in [(&a, &b), (&b, &a)] {
            if let Err(e) = compare(x, y, &tally, Detail::Totals) {
                panic!("{e}");
            }
        }
    }
    assert_eq!(
        tally.skipped.get(),
        0,
        "every case is a pair of simple polygons"
    );
    // The first case by hand: B's vertex (0, 0) is 7.8e-20 outside A, the rest of B inside,
    // so either way round the intersection is B less a sliver, one piece.
    let (a, b) = &fuzz_found()[0];
    for r in [intersection(a, b).unwrap(), intersection(b, a).unwrap()] {
        assert_eq!(r.len(), 1, "{r:?}");
        assert!((total_area(&r) - 3294.0).abs() < 1e-9, "{r:?}");
    }
}

/// A vertex 10⁻³⁰⁰ inside an edge of the other polygon: the exact tests see the crossings, but
/// their coordinates round onto one point, so the piece between them (area 10⁻³⁰⁰) has fewer
/// than 3 distinct vertices and is dropped; the difference keeps the whole square, once.
#[test]
fn a_piece_thinner_than_rounding_is_dropped_cleanly() {
    let square = rect(0., 0., 4., 4.);
    let tip = vec![p(1., -1.), p(3., -1.), p(2., 1e-300)];
    check_all_ways(&square, &tip, (0, 0.0), (1, 16.0));
    let below = difference(&tip, &square).unwrap();
    assert_eq!(below.len(), 1);
    assert!((total_area(&below) - 1.0).abs() < 1e-15, "{below:?}");
}

// ---------------------------------------------------------------------------------------
// The oracle.

fn to_geo(v: &[DVec2]) -> geo::Polygon<f64> {
    geo::Polygon::new(
        geo::LineString::from(v.iter().map(|q| (q.x, q.y)).collect::<Vec<_>>()),
        vec![],
    )
}

/// Piece areas above `floor`, sorted.
fn ours(pieces: &[Piece], floor: f64) -> Vec<f64> {
    let mut kept: Vec<f64> = pieces
        .iter()
        .map(Piece::area)
        .filter(|&a| a > floor)
        .collect();
    kept.sort_by(f64::total_cmp);
    kept
}

fn theirs(m: &geo::MultiPolygon<f64>, floor: f64) -> Vec<f64> {
    let mut kept: Vec<f64> =
        m.0.iter()
            .map(|q| q.unsigned_area())
            .filter(|&a| a > floor)
            .collect();
    kept.sort_by(f64::total_cmp);
    kept
}

/// What one run saw.
#[derive(Default)]
struct Tally {
    compared: Cell<u64>,
    skipped: Cell<u64>,
    degenerate: Cell<u64>,
    worst: Cell<f64>,
}

/// Whether a vertex of one polygon lies on the other's boundary (a shared vertex, a vertex on
/// an edge, collinear overlapping edges all have one).
fn degenerate(a: &[DVec2], b: &[DVec2]) -> bool {
    let on = |v: DVec2, ring: &[DVec2]| {
        (0..ring.len()).any(|i| {
            let (p0, p1) = (ring[i], ring[(i + 1) % ring.len()]);
            (p1 - p0).perp_dot(v - p0) == 0.0
                && v.x >= p0.x.min(p1.x)
                && v.x <= p0.x.max(p1.x)
                && v.y >= p0.y.min(p1.y)
                && v.y <= p0.y.max(p1.y)
        })
    };
    a.iter().any(|&v| on(v, b)) || b.iter().any(|&v| on(v, a))
}

/// The oracle's own error in area. `i_overlay` (under `geo`) snaps every coordinate, input
/// vertices included, to an integer grid of step 2^(⌊log₂ h⌋ − 29), h the larger half-extent
/// of the pair's bounding box (`i_float`'s `FloatPointAdapter`), and computes crossings on
/// that grid: each vertex of its answer is off by up to about one step, which moves an area
/// by up to step × perimeter. So its areas agree with exact ones only to about 1e-9 *of the
/// extent²*, not 1e-9 relative; the tolerance is that bound (twice, over both perimeters),
/// on top of 1e-9 relative. Our own areas are checked to 1e-12 by the identities above.
fn oracle_error(a: &[DVec2], b: &[DVec2]) -> f64 {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &q in a.iter().chain(b) {
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let h = 0.5 * (hi - lo).max_element();
    let step = (h.log2().floor() - 29.0).exp2();
    let perimeter = |v: &[DVec2]| -> f64 {
        (0..v.len())
            .map(|i| v[i].distance(v[(i + 1) % v.len()]))
            .sum()
    };
    2.0 * step * (perimeter(a) + perimeter(b))
}

/// Compare one pair with the oracle; `Err` describes a disagreement.
fn against_oracle(a: &[DVec2], b: &[DVec2], tally: &Tally) -> Result<(), String> {
    compare(a, b, tally, Detail::PieceByPiece)
}

/// How closely [`compare`] holds us to the oracle.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Detail {
    /// The same pieces (count and areas) and totals.
    PieceByPiece,
    /// The totals only: for polygons that come closer than the oracle's grid step (see
    /// [`oracle_error`]), where a sliver of the clip polygon that exactly cuts a piece in two
    /// is, on the oracle's grid, no cut at all.
    Totals,
}

fn compare(a: &[DVec2], b: &[DVec2], tally: &Tally, detail: Detail) -> Result<(), String> {
    let (Ok(_), Ok(_)) = (
        wa::validate(a, Which::Subject),
        wa::validate(b, Which::Clip),
    ) else {
        tally.skipped.set(tally.skipped.get() + 1);
        return Ok(());
    };
    tally.compared.set(tally.compared.get() + 1);
    if degenerate(a, b) {
        tally.degenerate.set(tally.degenerate.get() + 1);
    }
    let r = clip(a, b).map_err(|e| e.to_string())?;
    let (ga, gb) = (to_geo(a), to_geo(b));
    let scale = ga.unsigned_area() + gb.unsigned_area();
    // Our own books first, to 1e-12: the intersection and the difference split the subject,
    // and the intersection is symmetric.
    let (ai, ad) = (total_area(&r.intersection), total_area(&r.difference));
    let area_a = ga.unsigned_area();
    if (ai + ad - area_a).abs() > 1e-12 * scale {
        return Err(format!(
            "|A∩B| + |A−B| = {ai} + {ad} ≠ |A| = {area_a}\na = {a:?}\nb = {b:?}\nours = {r:?}"
        ));
    }
    let ba = intersection(b, a).map_err(|e| e.to_string())?;
    if ba.len() != r.intersection.len() || (total_area(&ba) - ai).abs() > 1e-12 * scale {
        return Err(format!(
            "A∩B ≠ B∩A\na = {a:?}\nb = {b:?}\nA∩B = {:?}\nB∩A = {ba:?}",
            r.intersection
        ));
    }
    // Both sides normalised the same way: pieces below 1e-12 of the inputs' area dropped.
    let floor = 1e-12 * scale;
    let tol = 1e-9 * scale + oracle_error(a, b);
    for (name, mine, oracle) in [
        ("intersection", &r.intersection, ga.intersection(&gb)),
        ("difference", &r.difference, ga.difference(&gb)),
    ] {
        let (l1, l2) = (ours(mine, floor), theirs(&oracle, floor));
        let (n1, n2) = (l1.len(), l2.len());
        let (a1, a2) = (l1.iter().sum::<f64>(), l2.iter().sum::<f64>());
        tally
            .worst
            .set(tally.worst.get().max((a1 - a2).abs() / scale));
        // The same count, the same total, and piece by piece (sorted by area) the same areas.
        let each = l1.iter().zip(&l2).all(|(x, y)| (x - y).abs() <= tol);
        let pieces_agree = detail == Detail::Totals || (n1 == n2 && each);
        if !pieces_agree || (a1 - a2).abs() > tol {
            return Err(format!(
                "{name}: ours {n1} pieces, area {a1}; oracle {n2} pieces, area {a2}\n\
                 a = {a:?}\nb = {b:?}\nours = {mine:?}\noracle = {oracle:?}"
            ));
        }
    }
    Ok(())
}

fn cases() -> u32 {
    std::env::var("WA_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000)
}

/// A star-shaped polygon about `c`: `n` angles, sorted, with radii; reversed half the time.
fn star(c: DVec2, mut parts: Vec<(f64, f64)>, rev: bool, round: Option<f64>) -> Vec<DVec2> {
    parts.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut v: Vec<DVec2> = parts
        .iter()
        .map(|&(ang, r)| {
            let q = c + r * DVec2::new(ang.cos(), ang.sin());
            match round {
                Some(g) => (q / g).round() * g,
                None => q,
            }
        })
        .collect();
    if rev {
        v.reverse();
    }
    v
}

fn star_strategy(span: f64, round: Option<f64>) -> impl Strategy<Value = Vec<DVec2>> {
    star_n(span, round, 3..12)
}

fn star_n(
    span: f64,
    round: Option<f64>,
    n: std::ops::Range<usize>,
) -> impl Strategy<Value = Vec<DVec2>> {
    (
        (-span..span, -span..span),
        prop::collection::vec((0.0..std::f64::consts::TAU, 0.1 * span..span), n),
        any::<bool>(),
    )
        .prop_map(move |((cx, cy), parts, rev)| star(DVec2::new(cx, cy), parts, rev, round))
}

/// A polygon with integer vertices on a small grid: random points, kept if simple.
fn grid_strategy(size: i32) -> impl Strategy<Value = Vec<DVec2>> {
    (
        prop::collection::vec((0..=size, 0..=size), 3..9),
        any::<bool>(),
    )
        .prop_map(|(pts, star_sort)| {
            let mut v: Vec<DVec2> = pts
                .into_iter()
                .map(|(x, y)| DVec2::new(f64::from(x), f64::from(y)))
                .collect();
            if star_sort {
                // Sorted by angle about their mean: usually simple.
                let c = v.iter().copied().sum::<DVec2>() / v.len() as f64;
                v.sort_by(|a, b| {
                    let (ta, tb) = ((*a - c).to_angle(), (*b - c).to_angle());
                    ta.total_cmp(&tb)
                });
            }
            v
        })
}

/// A grid polygon and a neighbour: its vertices moved by -1, 0 or 1 on each axis (most stay),
/// so that the two share vertices and overlap along edges.
fn neighbours_strategy(size: i32) -> impl Strategy<Value = (Vec<DVec2>, Vec<DVec2>)> {
    (
        grid_strategy(size),
        prop::collection::vec((-1i32..=1, -1i32..=1, 0u8..3), 9),
        0usize..9,
        any::<bool>(),
    )
        .prop_map(|(a, moves, k, rev)| {
            let mut b: Vec<DVec2> = a
                .iter()
                .zip(&moves)
                .map(|(&v, &(dx, dy, keep))| {
                    if keep == 0 {
                        v + DVec2::new(f64::from(dx), f64::from(dy))
                    } else {
                        v
                    }
                })
                .collect();
            let n = b.len();
            b.rotate_left(k % n);
            if rev {
                b.reverse();
            }
            (a, b)
        })
}

fn run_property(name: &str, strat: impl Strategy<Value = (Vec<DVec2>, Vec<DVec2>)>) {
    let n = cases();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: n,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let tally = Tally::default();
    let t = std::time::Instant::now();
    let result = runner.run(&strat, |(a, b)| {
        against_oracle(&a, &b, &tally).map_err(TestCaseError::fail)
    });
    eprintln!(
        "{name}: {n} cases in {:.1?}: {} compared with the oracle ({} with a vertex on the \
         other's boundary), {} not simple, skipped; largest area difference {:.2e} of |A|+|B|",
        t.elapsed(),
        tally.compared.get(),
        tally.degenerate.get(),
        tally.skipped.get(),
        tally.worst.get(),
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

#[test]
fn oracle_small_grid() {
    run_property("grid 0..=4", (grid_strategy(4), grid_strategy(4)));
}

#[test]
fn oracle_grid() {
    run_property("grid 0..=10", (grid_strategy(10), grid_strategy(10)));
}

#[test]
fn oracle_star_rounded_to_grid() {
    run_property(
        "stars on a 0.5 grid",
        (star_strategy(4.0, Some(0.5)), star_strategy(4.0, Some(0.5))),
    );
}

#[test]
fn oracle_float_stars() {
    run_property(
        "float stars",
        (star_strategy(10.0, None), star_strategy(10.0, None)),
    );
}

#[test]
fn oracle_grid_neighbours() {
    run_property("grid neighbours", neighbours_strategy(6));
}

#[test]
fn oracle_many_vertices_on_a_grid() {
    run_property(
        "stars of 12-40 vertices on an integer grid",
        (
            star_n(12.0, Some(1.0), 12..40),
            star_n(12.0, Some(1.0), 12..40),
        ),
    );
}

// ---------------------------------------------------------------------------------------
// A second oracle for the area alone, exact to rounding: against a *convex* clip polygon,
// Sutherland-Hodgman (in f64, written here) gives the intersection as one polygon whose
// zero-width bridges carry no area, so its area is the intersection's, to 1e-12.

fn sutherland_hodgman(subject: &[DVec2], convex_ccw: &[DVec2]) -> Vec<DVec2> {
    let mut poly = subject.to_vec();
    let n = convex_ccw.len();
    for i in 0..n {
        let (e0, e1) = (convex_ccw[i], convex_ccw[(i + 1) % n]);
        let side = |q: DVec2| (e1 - e0).perp_dot(q - e0);
        let mut out = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (s, q) = (poly[(k + poly.len() - 1) % poly.len()], poly[k]);
            let (ds, dq) = (side(s), side(q));
            if (ds >= 0.0) != (dq >= 0.0) {
                out.push(s + (ds / (ds - dq)) * (q - s));
            }
            if dq >= 0.0 {
                out.push(q);
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// Points on a circle, sorted by angle: a convex polygon, counter-clockwise.
fn convex_strategy(span: f64) -> impl Strategy<Value = Vec<DVec2>> {
    (
        (-span..span, -span..span),
        0.2 * span..span,
        prop::collection::vec(0.0..std::f64::consts::TAU, 3..10),
    )
        .prop_map(|((cx, cy), r, mut angles)| {
            angles.sort_by(f64::total_cmp);
            angles
                .into_iter()
                .map(|t| DVec2::new(cx, cy) + r * DVec2::new(t.cos(), t.sin()))
                .collect()
        })
}

fn run_exact(name: &str, strat: impl Strategy<Value = (Vec<DVec2>, Vec<DVec2>, bool)>) {
    let n = cases();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: n,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let (compared, worst) = (Cell::new(0u64), Cell::new(0.0f64));
    let t = std::time::Instant::now();
    let result = runner.run(&strat, |(a, b, rev)| {
        let (Ok(_), Ok(_)) = (
            wa::validate(&a, Which::Subject),
            wa::validate(&b, Which::Clip),
        ) else {
            return Ok(());
        };
        compared.set(compared.get() + 1);
        let sh = wa::signed_area(&sutherland_hodgman(&a, &b)).abs();
        let b = if rev { reversed(&b) } else { b };
        let ours = total_area(&intersection(&a, &b).unwrap());
        let scale = wa::signed_area(&a).abs() + wa::signed_area(&b).abs();
        let rel = (ours - sh).abs() / scale;
        worst.set(worst.get().max(rel));
        prop_assert!(
            rel <= 1e-9,
            "ours {ours}, Sutherland-Hodgman {sh}\na = {a:?}\nb = {b:?}"
        );
        Ok(())
    });
    eprintln!(
        "{name}: {n} cases in {:.1?}: {} compared with Sutherland-Hodgman; largest area \
         difference {:.2e} of |A|+|B|",
        t.elapsed(),
        compared.get(),
        worst.get()
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

#[test]
fn exact_area_against_sutherland_hodgman() {
    run_exact(
        "float stars against convex polygons",
        (
            star_strategy(10.0, None),
            convex_strategy(10.0),
            any::<bool>(),
        ),
    );
}

#[test]
fn exact_area_against_sutherland_hodgman_on_a_grid() {
    let grid_rect = ((0..=8i32, 0..=8i32), (1..=8i32, 1..=8i32)).prop_map(|((x, y), (w, h))| {
        let (x, y, w, h) = (f64::from(x), f64::from(y), f64::from(w), f64::from(h));
        vec![
            DVec2::new(x, y),
            DVec2::new(x + w, y),
            DVec2::new(x + w, y + h),
            DVec2::new(x, y + h),
        ]
    });
    run_exact(
        "grid stars against grid rectangles",
        (
            star_strategy(4.0, Some(1.0)).prop_map(|v| v.iter().map(|&q| q + 4.0).collect()),
            grid_rect,
            any::<bool>(),
        ),
    );
}
