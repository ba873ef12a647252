//! Weiler-Atherton's fuzz check, shared by the fuzz target (`fuzz/fuzz_targets/weiler_atherton.rs`,
//! which includes this file by path) and the corpus replay (`tests/it/clip/corpus.rs`).
//! Depends on `wireflight-geometry` (by its own name) and `glam` only.
//!
//! The bytes decode into two small polygons (3 to 10 vertices each), each either on the
//! integer grid −128..127 (`i8` coordinates: vertices on edges, collinear overlaps, shared
//! vertices and self-intersections are frequent) or in `f64` (raw bit patterns, so NaN and ∞
//! too, subnormals, and finite values reduced modulo 10⁶: a vertex 10⁻²⁰ or 10⁻³⁰⁰ from the
//! other polygon's edge beside coordinates of 10⁵, which rounded orientation tests got wrong).
//! Then [`weiler_atherton::clip`]:
//! it must not panic; an error must be one that [`weiler_atherton::validate`] gives for one of
//! the polygons (and a non-finite coordinate must be an error); on success every output
//! coordinate is finite, every ring has at least 3 vertices, and
//! |A ∩ B| + |A − B| = |A| and |A ∩ B| = |B ∩ A| ≤ min(|A|, |B|) to within 10⁻⁹ of |A| + |B|
//! plus the rounding of a shoelace sum at the coordinates' magnitude (`64 · ε · n · R²`,
//! R the largest coordinate, n the vertices: that much is noise, not a wrong piece; and
//! 10⁻²⁹⁰ for subnormal areas).

#![allow(dead_code)]

use glam::DVec2;
use wireflight_geometry::clip::weiler_atherton::{self, signed_area, total_area, Piece, Which};

/// Decode two polygons from fuzz bytes (missing bytes read as 0).
///
/// Byte 0: bits 0–2 the subject's vertex count − 3, bits 3–5 the clip polygon's, bit 6 the
/// subject in `f64` (else the `i8` grid), bit 7 the clip polygon in `f64`.
pub fn decode(data: &[u8]) -> (Vec<DVec2>, Vec<DVec2>) {
    let mode = data.first().copied().unwrap_or(0);
    let mut at = 1usize;
    let mut byte = || {
        let b = data.get(at).copied().unwrap_or(0);
        at += 1;
        b
    };
    let mut polygon = |n: usize, float: bool| -> Vec<DVec2> {
        let mut coordinate = || {
            if float {
                let mut raw = [0u8; 8];
                for r in &mut raw {
                    *r = byte();
                }
                let v = f64::from_le_bytes(raw);
                if v.is_finite() {
                    v % 1e6
                } else {
                    v
                }
            } else {
                f64::from(byte() as i8)
            }
        };
        (0..n)
            .map(|_| {
                let x = coordinate();
                let y = coordinate();
                DVec2::new(x, y)
            })
            .collect()
    };
    let subject = polygon(3 + usize::from(mode & 7), mode & 0x40 != 0);
    let clip = polygon(3 + usize::from((mode >> 3) & 7), mode & 0x80 != 0);
    (subject, clip)
}

fn rings(pieces: &[Piece]) -> impl Iterator<Item = &Vec<DVec2>> {
    pieces
        .iter()
        .flat_map(|p| std::iter::once(&p.outer).chain(&p.holes))
}

/// Run the check on two polygons (see the module docs); panics on a violation.
pub fn check(subject: &[DVec2], clip: &[DVec2]) {
    let finite = subject.iter().chain(clip).all(|p| p.is_finite());
    let result = weiler_atherton::clip(subject, clip);
    let (a, b) = (
        weiler_atherton::validate(subject, Which::Subject),
        weiler_atherton::validate(clip, Which::Clip),
    );
    let c = match result {
        Err(e) => {
            assert!(
                a.is_err() || b.is_err(),
                "clip refused two valid polygons: {e}\n{subject:?}\n{clip:?}"
            );
            return;
        }
        Ok(c) => c,
    };
    assert!(finite, "non-finite input accepted: {subject:?} {clip:?}");
    let (a, b) = (
        a.expect("clip accepted an invalid subject"),
        b.expect("clip accepted an invalid clip polygon"),
    );
    for ring in rings(&c.intersection).chain(rings(&c.difference)) {
        assert!(ring.len() >= 3, "ring of {} vertices: {ring:?}", ring.len());
        assert!(
            ring.iter().all(|p| p.is_finite()),
            "non-finite output vertex: {ring:?}"
        );
    }
    let (area_a, area_b) = (signed_area(&a), signed_area(&b));
    let (inter, diff) = (total_area(&c.intersection), total_area(&c.difference));
    let r = a
        .iter()
        .chain(&b)
        .fold(0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let n = (a.len() + b.len()) as f64;
    // The floor: areas of tiny polygons are subnormal numbers, rounded absolutely.
    let tol = 1e-9 * (area_a.abs() + area_b.abs()) + 64.0 * f64::EPSILON * n * r * r + 1e-290;
    assert!(
        (inter + diff - area_a).abs() <= tol,
        "|A∩B| + |A−B| = {inter} + {diff} = {}, |A| = {area_a} (tolerance {tol})\n{subject:?}\n{clip:?}",
        inter + diff
    );
    assert!(
        inter <= area_a.min(area_b) + tol && inter >= -tol && diff >= -tol,
        "|A∩B| = {inter}, |A−B| = {diff}, |A| = {area_a}, |B| = {area_b}\n{subject:?}\n{clip:?}"
    );
    let swapped = weiler_atherton::intersection(clip, subject).expect("valid both ways round");
    let inter_ba = total_area(&swapped);
    assert!(
        (inter_ba - inter).abs() <= tol,
        "|A∩B| = {inter}, |B∩A| = {inter_ba}\n{subject:?}\n{clip:?}"
    );
}

/// Decode and check (the fuzz target's body).
pub fn fuzz(data: &[u8]) {
    let (subject, clip) = decode(data);
    check(&subject, &clip);
}
