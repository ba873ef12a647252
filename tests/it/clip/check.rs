//! The clippers' property check, shared by the property tests (`tests/it/clip/`), the fuzz
//! targets (`fuzz/fuzz_targets/`, which include this file by path) and the corpus replay.
//! Depends on `wireflight-geometry` (by its own name, so that the fuzz crate, which has no
//! `wireflight`, compiles it too) and `glam` only.
//!
//! For one case and one algorithm: no panic; non-finite input gives `NonFinite`; an accepted
//! edge is the input unchanged with both ends inside; every segment has finite ends with
//! w > 0 (homogeneous), lies inside the volume and on the input line to within
//! `REL_TOL × scale`, runs the input's way, and keeps an inside endpoint exactly; and it is
//! the same segment as an independent `f64` reference (the interval of t where every
//! boundary coordinate, computed here from scratch, is ≥ 0), to within `REL_TOL × scale`.
//! A segment may be missing on one side only when the other is degenerate at that scale:
//! shorter than the tolerance, inside by no more than the tolerance anywhere (grazing a
//! plane, edge or corner), or ending within the tolerance of the eye (w ≈ 0, where the
//! projection is singular).

#![allow(dead_code)]

use glam::{Vec2, Vec4};
use wireflight_geometry::clip::batch::{self, EdgesSoa, SegmentsSoa};
use wireflight_geometry::clip::{
    blinn, clip_edge, cohen_sutherland, cyrus_beck, liang_barsky, nicholl_lee_nicholl,
    sutherland_hodgman, ClipOutcome, ClipStats, ClipVolume, Clipper, DepthRange, PlaneSet, Window2,
};

/// Relative tolerance of every geometric comparison (relative to the case's largest
/// coordinate): a few `f32` ulps.
pub const REL_TOL: f64 = 1e-6;

/// Absolute floor of every tolerance: eight of the smallest `f32` steps (subnormal numbers
/// have no more precision than that, whatever the scale).
pub const ABS_TOL: f64 = 8.0 * 1.401_298_464_324_817e-45;

/// The homogeneous algorithms, by name.
pub const HOMOGENEOUS: [&str; 5] = [
    "blinn",
    "cohen-sutherland",
    "liang-barsky",
    "cyrus-beck",
    "sutherland-hodgman",
];

/// The 2D algorithms, by name.
pub const PLANAR: [&str; 5] = [
    "cohen-sutherland",
    "liang-barsky",
    "cyrus-beck",
    "nicholl-lee-nicholl",
    "sutherland-hodgman",
];

/// Clip a homogeneous edge with the named algorithm.
pub fn clip_homogeneous(algo: &str, a: Vec4, c: Vec4, v: &ClipVolume) -> ClipOutcome {
    match algo {
        "blinn" => blinn::clip_edge_in(a, c, v),
        "cohen-sutherland" => cohen_sutherland::clip_homogeneous(a, c, v),
        "liang-barsky" => liang_barsky::clip_homogeneous(a, c, v),
        "cyrus-beck" => cyrus_beck::clip_homogeneous(a, c, v),
        "sutherland-hodgman" => sutherland_hodgman::clip_edge_homogeneous(a, c, v),
        _ => panic!("unknown algorithm {algo}"),
    }
}

/// Clip a 2D edge with the named algorithm.
pub fn clip_planar(algo: &str, a: Vec2, c: Vec2, w: &Window2) -> ClipOutcome<Vec2> {
    match algo {
        "cohen-sutherland" => cohen_sutherland::clip_2d(a, c, w),
        "liang-barsky" => liang_barsky::clip_2d(a, c, w),
        "cyrus-beck" => {
            let corners = w.corners();
            let poly = cyrus_beck::ConvexPolygon::new(&corners).expect("a window is convex");
            cyrus_beck::clip_polygon(a, c, &poly)
        }
        "nicholl-lee-nicholl" => nicholl_lee_nicholl::clip_2d(a, c, w),
        "sutherland-hodgman" => sutherland_hodgman::clip_edge_2d(a, c, w),
        _ => panic!("unknown algorithm {algo}"),
    }
}

// ---------------------------------------------------------------------------------------------
// The independent reference: planes written out here, boundary coordinates in f64.
// ---------------------------------------------------------------------------------------------

/// The planes of a volume as `(a, b, c, d)` in f64, written out independently of the library.
fn planes(v: &ClipVolume) -> Vec<[f64; 4]> {
    let near_w = match v.depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => 1.0,
    };
    let mut p = vec![
        [1.0, 0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 1.0],
        [0.0, -1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, near_w],
        [0.0, 0.0, -1.0, 1.0],
    ];
    for e in v.extra.as_slice() {
        p.push(e.to_array().map(f64::from));
    }
    p
}

fn dot(p: &[f64; 4], x: &[f64; 4]) -> f64 {
    p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3] * x[3]
}

/// The t-interval where every boundary coordinate of `A + t(C − A)` is ≥ 0.
fn reference_interval(values: &[(f64, f64)]) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for &(va, vc) in values {
        // v(t) = va + t (vc − va) ≥ 0
        let d = vc - va;
        if d == 0.0 {
            if va < 0.0 {
                return None;
            }
        } else if d > 0.0 {
            lo = lo.max(-va / d);
        } else {
            hi = hi.min(-va / d);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

fn lerp4(a: &[f64; 4], c: &[f64; 4], t: f64) -> [f64; 4] {
    std::array::from_fn(|k| a[k] + t * (c[k] - a[k]))
}

/// What the check measured, for the tests' summaries.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tally {
    /// Cases checked (algorithm × edge).
    pub cases: u64,
    /// Segments compared with the reference.
    pub compared: u64,
    /// One side had a segment and the other none, excused as degenerate.
    pub excused: u64,
    /// Largest difference from the reference, relative to the scale.
    pub max_rel_diff: f64,
    /// The outcomes seen.
    pub stats: ClipStats,
}

/// The scale of a homogeneous case: the largest coordinate (at least the smallest normal
/// f32, so that a tolerance is never exactly zero for non-zero input).
fn scale4(a: Vec4, c: Vec4) -> f64 {
    f64::from(a.abs().max_element().max(c.abs().max_element()))
}

/// Check one homogeneous edge with one algorithm (see the module docs).
pub fn check_homogeneous(
    algo: &str,
    a: Vec4,
    c: Vec4,
    volume: &ClipVolume,
    tally: &mut Tally,
) -> Result<(), String> {
    let out = clip_homogeneous(algo, a, c, volume);
    tally.cases += 1;
    tally.stats.record(&out);
    let ctx = || format!("{algo}: a = {a:?}, c = {c:?}, {volume:?}\n    → {out:?}");
    let fail = |what: String| Err(format!("{what}\n    {}", ctx()));
    // The enum names the same function.
    let via_enum = Clipper::ALL
        .iter()
        .find(|k| k.name() == algo)
        .map(|k| k.clip_in(a, c, volume));
    if via_enum.is_some_and(|o| o != out) {
        return fail(format!("Clipper::clip_in gives {via_enum:?}"));
    }
    if !(a.is_finite() && c.is_finite()) {
        return match out {
            ClipOutcome::NonFinite => Ok(()),
            _ => fail("non-finite input not reported".into()),
        };
    }
    if out == ClipOutcome::NonFinite {
        return fail("NonFinite for finite input".into());
    }
    let planes = planes(volume);
    let (a64, c64) = (a.to_array().map(f64::from), c.to_array().map(f64::from));
    let scale = scale4(a, c);
    // Tolerance on a boundary coordinate: the plane's size times the scale.
    let bc_tol = |p: &[f64; 4]| {
        (REL_TOL * scale + ABS_TOL) * p.iter().map(|x| x.abs()).sum::<f64>().max(1.0)
    };
    let tol = REL_TOL * scale + ABS_TOL;
    let inside_exact = |p: &[f64; 4]| planes.iter().all(|pl| dot(pl, p) >= 0.0);
    let margin = |p: &[f64; 4]| {
        planes
            .iter()
            .map(|pl| dot(pl, p) + bc_tol(pl))
            .fold(f64::INFINITY, f64::min)
    };

    let segment = out.segment();
    if let ClipOutcome::Accepted(p, q) = out {
        if (p, q) != (a, c) {
            return fail("Accepted but changed".into());
        }
        if !(inside_exact(&a64) && inside_exact(&c64)) {
            return fail("Accepted with an endpoint outside".into());
        }
    }
    if let Some((p, q)) = segment {
        for (e, orig, orig64) in [(p, a, &a64), (q, c, &c64)] {
            if !e.is_finite() || e.w <= 0.0 {
                return fail(format!("endpoint {e:?}: not finite or w ≤ 0"));
            }
            let ndc = (e.x / e.w, e.y / e.w);
            if !(ndc.0.is_finite() && ndc.1.is_finite()) {
                return fail(format!("endpoint {e:?} divides to {ndc:?}"));
            }
            let e64 = e.to_array().map(f64::from);
            if margin(&e64) < 0.0 {
                return fail(format!(
                    "endpoint {e:?} is outside the volume beyond the tolerance"
                ));
            }
            if inside_exact(orig64) && e != orig && orig.w > 0.0 {
                return fail(format!("inside endpoint {orig:?} moved to {e:?}"));
            }
        }
    }

    // The reference.
    let values: Vec<(f64, f64)> = planes
        .iter()
        .map(|pl| (dot(pl, &a64), dot(pl, &c64)))
        .collect();
    let reference = reference_interval(&values).and_then(|(lo, hi)| {
        let (p, q) = (lerp4(&a64, &c64, lo), lerp4(&a64, &c64, hi));
        (p[3] > 0.0 || q[3] > 0.0).then_some((lo, hi, p, q))
    });
    // Degenerate at this scale: short, grazing, or ending at the eye.
    let degenerate = |p: [f64; 4], q: [f64; 4]| {
        let short = (0..4).all(|k| (p[k] - q[k]).abs() <= 4.0 * tol);
        let at_eye = p[3] <= 4.0 * tol || q[3] <= 4.0 * tol;
        let grazing = (0..=32).all(|s| {
            let x = lerp4(&p, &q, f64::from(s) / 32.0);
            planes
                .iter()
                .map(|pl| dot(pl, &x) - 4.0 * bc_tol(pl))
                .fold(f64::INFINITY, f64::min)
                <= 0.0
        });
        short || at_eye || grazing
    };
    match (segment, reference) {
        (None, None) => {}
        (Some((p, q)), None) => {
            let (p, q) = (p.to_array().map(f64::from), q.to_array().map(f64::from));
            if !degenerate(p, q) {
                return fail("a segment where the reference has none".into());
            }
            tally.excused += 1;
        }
        (None, Some((lo, hi, p, q))) => {
            if !degenerate(p, q) {
                return fail(format!(
                    "nothing, where the reference keeps t ∈ [{lo}, {hi}]: {p:?} → {q:?}"
                ));
            }
            tally.excused += 1;
        }
        (Some((p, q)), Some((_, _, rp, rq))) => {
            let d = (0..4)
                .map(|k| {
                    (f64::from(p[k]) - rp[k])
                        .abs()
                        .max((f64::from(q[k]) - rq[k]).abs())
                })
                .fold(0.0, f64::max);
            tally.compared += 1;
            if scale > 0.0 {
                tally.max_rel_diff = tally.max_rel_diff.max(d / scale);
            }
            if d > 4.0 * tol {
                // The reference may end at w ≤ 0 (the eye) where the clippers stop short.
                if !(degenerate(rp, rq) || rp[3] <= 4.0 * tol || rq[3] <= 4.0 * tol) {
                    return fail(format!(
                        "differs from the reference {rp:?} → {rq:?} by {d:e} (tolerance {:e})",
                        4.0 * tol
                    ));
                }
                tally.excused += 1;
            }
        }
    }
    Ok(())
}

/// Check one 2D edge with one algorithm (see the module docs).
pub fn check_planar(
    algo: &str,
    a: Vec2,
    c: Vec2,
    w: &Window2,
    tally: &mut Tally,
) -> Result<(), String> {
    let out = clip_planar(algo, a, c, w);
    tally.cases += 1;
    tally.stats.record(&out);
    let fail = |what: String| {
        Err(format!(
            "{what}\n    {algo}: a = {a:?}, c = {c:?}, {w:?}\n    → {out:?}"
        ))
    };
    if !(a.is_finite() && c.is_finite()) {
        return match out {
            ClipOutcome::NonFinite => Ok(()),
            _ => fail("non-finite input not reported".into()),
        };
    }
    if out == ClipOutcome::NonFinite {
        return fail("NonFinite for finite input".into());
    }
    let bounds = [w.xmin(), w.ymin(), w.xmax(), w.ymax()].map(f64::from);
    let scale = [a.x, a.y, c.x, c.y]
        .iter()
        .map(|v| f64::from(v.abs()))
        .chain(bounds.iter().map(|b| b.abs()))
        .fold(0.0, f64::max);
    let tol = REL_TOL * scale + ABS_TOL;
    let bc = |p: [f64; 2]| {
        [
            p[0] - bounds[0],
            p[1] - bounds[1],
            bounds[2] - p[0],
            bounds[3] - p[1],
        ]
    };
    let inside = |p: [f64; 2]| bc(p).iter().all(|&b| b >= 0.0);
    let (a64, c64) = (
        [f64::from(a.x), f64::from(a.y)],
        [f64::from(c.x), f64::from(c.y)],
    );
    if let ClipOutcome::Accepted(p, q) = out {
        if (p, q) != (a, c) || !(inside(a64) && inside(c64)) {
            return fail("Accepted, but changed or not inside".into());
        }
    }
    let segment = out.segment();
    if let Some((p, q)) = segment {
        for (e, orig, orig64) in [(p, a, a64), (q, c, c64)] {
            if !e.is_finite() {
                return fail(format!("endpoint {e:?} not finite"));
            }
            let e64 = [f64::from(e.x), f64::from(e.y)];
            if bc(e64).iter().any(|&b| b < -tol) {
                return fail(format!("endpoint {e:?} outside the window"));
            }
            if inside(orig64) && e != orig {
                return fail(format!("inside endpoint {orig:?} moved to {e:?}"));
            }
        }
    }
    let values: Vec<(f64, f64)> = (0..4).map(|k| (bc(a64)[k], bc(c64)[k])).collect();
    let lerp =
        |p: [f64; 2], q: [f64; 2], t: f64| [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
    let reference =
        reference_interval(&values).map(|(lo, hi)| (lerp(a64, c64, lo), lerp(a64, c64, hi)));
    let degenerate = |p: [f64; 2], q: [f64; 2]| {
        let short = (p[0] - q[0]).abs().max((p[1] - q[1]).abs()) <= 4.0 * tol;
        let grazing = (0..=32).all(|s| {
            let x = lerp(p, q, f64::from(s) / 32.0);
            bc(x).iter().fold(f64::INFINITY, |m, &b| m.min(b)) <= 4.0 * tol
        });
        short || grazing
    };
    match (segment, reference) {
        (None, None) => {}
        (Some((p, q)), None) => {
            if !degenerate([p.x.into(), p.y.into()], [q.x.into(), q.y.into()]) {
                return fail("a segment where the reference has none".into());
            }
            tally.excused += 1;
        }
        (None, Some((p, q))) => {
            if !degenerate(p, q) {
                return fail(format!("nothing, where the reference keeps {p:?} → {q:?}"));
            }
            tally.excused += 1;
        }
        (Some((p, q)), Some((rp, rq))) => {
            let d = [
                (f64::from(p.x) - rp[0]).abs(),
                (f64::from(p.y) - rp[1]).abs(),
                (f64::from(q.x) - rq[0]).abs(),
                (f64::from(q.y) - rq[1]).abs(),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            tally.compared += 1;
            if scale > 0.0 {
                tally.max_rel_diff = tally.max_rel_diff.max(d / scale);
            }
            if d > 4.0 * tol {
                if !degenerate(rp, rq) {
                    return fail(format!(
                        "differs from the reference {rp:?} → {rq:?} by {d:e} (tolerance {:e})",
                        4.0 * tol
                    ));
                }
                tally.excused += 1;
            }
        }
    }
    Ok(())
}

/// Blinn's batch paths give exactly the per-edge clipper's segments and counts.
pub fn check_batch(edges: &[(Vec4, Vec4)], depth: DepthRange) -> Result<(), String> {
    let mut expected_stats = ClipStats::default();
    let mut expected = SegmentsSoa::default();
    for (i, &(a, c)) in edges.iter().enumerate() {
        let out = clip_edge(a, c, depth);
        expected_stats.record(&out);
        if let Some((p, q)) = out.segment() {
            expected.push(i as u32, p, q);
        }
        let coded = batch::clip_coded(
            a,
            c,
            batch::vertex_code(a, depth),
            batch::vertex_code(c, depth),
            depth,
        );
        if coded != out {
            return Err(format!(
                "clip_coded {coded:?} ≠ clip_edge {out:?} for {a:?} → {c:?} {depth:?}"
            ));
        }
        // NaN-free comparison by bits (a NaN never reaches a segment).
        let bits = |o: &ClipOutcome| {
            o.segment().map(|(p, q)| {
                (
                    p.to_array().map(f32::to_bits),
                    q.to_array().map(f32::to_bits),
                )
            })
        };
        if bits(&coded) != bits(&out) {
            return Err(format!("clip_coded differs in bits for {a:?} → {c:?}"));
        }
    }
    let mut got = SegmentsSoa::default();
    let stats = batch::clip_soa(&EdgesSoa::from_pairs(edges), depth, &mut got);
    if stats != expected_stats {
        return Err(format!(
            "batch tally {stats:?} ≠ per-edge {expected_stats:?}"
        ));
    }
    let bits = |s: &SegmentsSoa| {
        (
            s.edge.clone(),
            s.a.clone()
                .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>()),
            s.c.clone()
                .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>()),
        )
    };
    if bits(&got) != bits(&expected) {
        return Err(format!("batch segments differ: {got:?} vs {expected:?}"));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Decoding fuzz input (also used by the corpus replay)
// ---------------------------------------------------------------------------------------------

/// Reads values from fuzz bytes: each value is a tag byte choosing how to read it.
pub struct Bytes<'a>(pub &'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }

    /// A float: small integers and halves (to hit planes, corners and parallels exactly),
    /// raw bits (NaN, ∞, subnormals, huge), or a scaled value.
    pub fn f32(&mut self) -> Option<f32> {
        let tag = self.byte()?;
        Some(match tag % 4 {
            0 => f32::from(self.byte()? as i8) / 2.0,
            1 => {
                let b = [self.byte()?, self.byte()?, self.byte()?, self.byte()?];
                f32::from_le_bytes(b)
            }
            2 => {
                let m = f32::from(i16::from_le_bytes([self.byte()?, self.byte()?])) / 1024.0;
                m * 10f32.powi(i32::from(self.byte()? % 77) - 38)
            }
            _ => f32::from(self.byte()? as i8),
        })
    }

    /// A homogeneous point.
    pub fn vec4(&mut self) -> Option<Vec4> {
        Some(Vec4::new(
            self.f32()?,
            self.f32()?,
            self.f32()?,
            self.f32()?,
        ))
    }

    /// A 2D point.
    pub fn vec2(&mut self) -> Option<Vec2> {
        Some(Vec2::new(self.f32()?, self.f32()?))
    }

    /// Whether any byte is left.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A homogeneous case from fuzz bytes: depth range, up to two extra planes, two points, and
/// a "snap" byte that may put an endpoint exactly on a plane, on the line through a corner,
/// parallel to a plane, or make the edge pass through the eye.
pub fn decode_homogeneous(data: &[u8]) -> Option<(Vec4, Vec4, ClipVolume)> {
    let mut b = Bytes(data);
    let flags = b.byte()?;
    let depth = if flags & 1 == 0 {
        DepthRange::ZeroToOne
    } else {
        DepthRange::NegOneToOne
    };
    let mut extra = PlaneSet::default();
    for _ in 0..(flags >> 1) % 3 {
        let p = b.vec4()?;
        let _ = extra.push(p); // invalid planes are skipped
    }
    let mut a = b.vec4()?;
    let mut c = b.vec4()?;
    let snap = b.byte().unwrap_or(0);
    match snap % 8 {
        1 => a.x = a.w,                          // on the right plane
        2 => c = Vec4::new(c.w, c.w, c.z, c.w),  // on a corner line
        3 => c = -a * (c.w.abs().fract() + 0.5), // through the eye (c = −k·a)
        4 => c.x = c.w + (a.x - a.w),            // parallel to the right plane (w − x constant)
        5 => {
            a.z = if depth == DepthRange::ZeroToOne {
                0.0
            } else {
                -a.w
            };
        }
        6 => c = a, // zero length
        _ => {}
    }
    Some((a, c, ClipVolume::with_planes(depth, extra)))
}

/// A 2D case from fuzz bytes: a window (skipped if not valid), two points, a snap byte.
pub fn decode_planar(data: &[u8]) -> Option<(Vec2, Vec2, Window2)> {
    let mut b = Bytes(data);
    let (x0, y0, x1, y1) = (b.f32()?, b.f32()?, b.f32()?, b.f32()?);
    let w = Window2::new(x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1))?;
    let mut a = b.vec2()?;
    let mut c = b.vec2()?;
    match b.byte().unwrap_or(0) % 6 {
        1 => a.x = w.xmin(),
        2 => c = Vec2::new(w.xmax(), w.ymax()),
        3 => c.y = a.y,
        4 => c = a,
        5 => {
            // Through a corner from outside.
            let k = w.corners()[usize::from(b.byte().unwrap_or(0) % 4)];
            c = k + (k - a);
        }
        _ => {}
    }
    Some((a, c, w))
}

/// Check a homogeneous fuzz case with the named algorithms (and Blinn's batch paths when
/// `blinn` is among them and there are no extra planes).
pub fn fuzz_homogeneous(data: &[u8], algos: &[&str]) {
    let Some((a, c, v)) = decode_homogeneous(data) else {
        return;
    };
    let mut tally = Tally::default();
    for algo in algos {
        if let Err(e) = check_homogeneous(algo, a, c, &v, &mut tally) {
            panic!("{e}");
        }
    }
    if algos.contains(&"blinn") && v.extra.is_empty() {
        // The case among its variants and an inside edge, over more than one block of the
        // SoA batch, so that accepted, dropped and clipped edges share blocks in every order.
        let inside = (
            Vec4::new(0.25, -0.5, 0.5, 1.0),
            Vec4::new(-0.5, 0.25, 0.25, 1.0),
        );
        let kinds = [(a, c), inside, (c, a), inside, (a, a), (c, c), inside];
        let edges: Vec<(Vec4, Vec4)> = (0..70).map(|i| kinds[(i * i + i / 7) % 7]).collect();
        if let Err(e) = check_batch(&edges, v.depth) {
            panic!("{e}");
        }
    }
}

/// Check a 2D fuzz case with the named algorithms.
pub fn fuzz_planar(data: &[u8], algos: &[&str]) {
    let Some((a, c, w)) = decode_planar(data) else {
        return;
    };
    let mut tally = Tally::default();
    for algo in algos {
        if let Err(e) = check_planar(algo, a, c, &w, &mut tally) {
            panic!("{e}");
        }
    }
}

/// Sutherland-Hodgman on polygons from fuzz bytes: never a panic; every output vertex inside
/// (2D: exactly; clip space: within the tolerance, w > 0); every input vertex inside the
/// window is in the output unchanged.
pub fn fuzz_polygons(data: &[u8]) {
    let mut b = Bytes(data);
    let Some(flags) = b.byte() else { return };
    if flags & 1 == 0 {
        let Some((x0, y0, x1, y1)) = (|| Some((b.f32()?, b.f32()?, b.f32()?, b.f32()?)))() else {
            return;
        };
        let Some(w) = Window2::new(x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)) else {
            return;
        };
        let mut poly = Vec::new();
        while poly.len() < 12 {
            match b.vec2() {
                Some(p) => poly.push(p),
                None => break,
            }
        }
        let (mut out, mut scratch) = ([Vec2::ZERO; 64], [Vec2::ZERO; 64]);
        match sutherland_hodgman::clip_polygon_2d(&poly, &w, &mut out, &mut scratch) {
            Err(sutherland_hodgman::PolygonError::NonFinite) => {
                assert!(poly.iter().any(|p| !p.is_finite()))
            }
            Err(e) => panic!("{e} for {poly:?}"),
            Ok(n) => {
                for p in &out[..n] {
                    assert!(w.contains(*p), "{p:?} outside {w:?} from {poly:?}");
                }
                for p in &poly {
                    if w.contains(*p) {
                        assert!(
                            out[..n].contains(p),
                            "inside vertex {p:?} lost from {poly:?}"
                        );
                    }
                }
            }
        }
    } else {
        let depth = if flags & 2 == 0 {
            DepthRange::ZeroToOne
        } else {
            DepthRange::NegOneToOne
        };
        let v = ClipVolume::new(depth);
        let mut poly = Vec::new();
        while poly.len() < 8 {
            match b.vec4() {
                Some(p) => poly.push(p),
                None => break,
            }
        }
        let (mut out, mut scratch) = ([Vec4::ZERO; 64], [Vec4::ZERO; 64]);
        match sutherland_hodgman::clip_polygon_homogeneous(&poly, &v, &mut out, &mut scratch) {
            Err(sutherland_hodgman::PolygonError::NonFinite) => {
                assert!(poly.iter().any(|p| !p.is_finite()))
            }
            Err(e) => panic!("{e} for {poly:?}"),
            Ok(n) => {
                let scale = poly
                    .iter()
                    .map(|p| p.abs().max_element())
                    .fold(0.0f32, f32::max);
                for p in &out[..n] {
                    assert!(p.is_finite() && p.w > 0.0, "{p:?} from {poly:?}");
                    assert!(
                        v.contains(*p, 0.0) || {
                            let bc = v.boundary_coords(p.as_dvec4());
                            bc[..6]
                                .iter()
                                .all(|&x| x >= -8.0 * REL_TOL * f64::from(scale))
                        },
                        "{p:?} outside from {poly:?}"
                    );
                }
                for p in &poly {
                    if v.outcode(*p) == 0 && p.w > 0.0 {
                        assert!(
                            out[..n].contains(p),
                            "inside vertex {p:?} lost from {poly:?}"
                        );
                    }
                }
            }
        }
    }
}
