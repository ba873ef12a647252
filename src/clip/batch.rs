//! Blinn's clipper over batches: the same segments and counts as [`super::clip_edge`] edge by
//! edge, faster.
//!
//! Two shapes of input, one principle: **the trivial cases are decided from outcodes computed
//! without branches, many at a time, and only the crossing edges take the scalar path** (the
//! very function the per-edge clipper uses, [`super::blinn::clip_crossing`], so a crossing
//! edge gives bit-identical results either way).
//!
//! * Indexed meshes (the projector): [`vertex_code`] once per *vertex* (glam's SIMD compare of
//!   `(x, y, z)` against `±w`, two movemasks), then per edge two byte loads, an OR and an AND
//!   ([`clip_coded`]). A vertex shared by four edges is classified once instead of four times.
//! * Flat edge lists in structure-of-arrays form ([`EdgesSoa`] → [`SegmentsSoa`]): eight edges
//!   per step, the outcodes of all sixteen endpoints computed by straight-line code over
//!   `[f32; 8]` lanes that the compiler turns into SIMD compares; a step whose eight edges are
//!   all inside is copied out with no per-edge branch.
//!
//! Why the outcodes can skip the boundary coordinates: `w + x < 0` (rounded in `f32`) holds
//! exactly when `x < −w` (rounding keeps the sign of a sum, and a sum of two floats is zero
//! only when they cancel exactly), and likewise for every plane, so comparing coordinates with
//! `±w` gives bit for bit the codes of [`super::outcode`] with no additions.
//!
//! Never allocates per edge: the output vectors are reserved once per call. Pure math.

use glam::Vec4;

use super::blinn::clip_crossing;
use super::{ClipOutcome, ClipStats, DepthRange};

/// Flag in a vertex code: a coordinate is NaN or infinite.
pub const NON_FINITE: u8 = 1 << 6;
/// Flag in a vertex code: `w ≤ 0` (or NaN): the point is at or behind the eye.
pub const NOT_IN_FRONT: u8 = 1 << 7;
/// The six outcode bits of a vertex code.
pub const OUTCODE_BITS: u8 = 0x3F;

/// Bits 0, 1, 2 (x, y, z) moved to 0, 2, 4: the "below" bit of each pair.
const SPREAD: [u8; 8] = [0, 1, 4, 5, 16, 17, 20, 21];

/// The outcode of `p` ([`super::outcode`] of its boundary coordinates, bit for bit) with
/// [`NON_FINITE`] and [`NOT_IN_FRONT`] flags, by two SIMD compares.
///
/// ```
/// use glam::Vec4;
/// use wireflight::clip::{batch, boundary_coords, outcode, DepthRange};
/// let p = Vec4::new(2.0, -0.5, -0.1, 1.0);
/// let code = batch::vertex_code(p, DepthRange::ZeroToOne);
/// assert_eq!(code & batch::OUTCODE_BITS, outcode(&boundary_coords(p, DepthRange::ZeroToOne)));
/// ```
#[inline]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(w > 0)`: NaN is not in front either
pub fn vertex_code(p: Vec4, depth: DepthRange) -> u8 {
    let w = p.w;
    let near = match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => -w,
    };
    let below = p
        .cmplt(Vec4::new(-w, -w, near, f32::NEG_INFINITY))
        .bitmask() as usize;
    let above = p.cmpgt(Vec4::new(w, w, w, f32::INFINITY)).bitmask() as usize;
    let code = SPREAD[below & 7] | (SPREAD[above & 7] << 1);
    code | (u8::from(!p.is_finite()) * NON_FINITE) | (u8::from(!(w > 0.0)) * NOT_IN_FRONT)
}

/// [`vertex_code`] of every position into `codes` (resized to match).
pub fn vertex_codes(positions: &[Vec4], depth: DepthRange, codes: &mut Vec<u8>) {
    codes.clear();
    codes.extend(positions.iter().map(|&p| vertex_code(p, depth)));
}

/// Clip `a`→`c` given their [`vertex_code`]s: exactly [`super::clip_edge`]'s outcome.
#[inline]
pub fn clip_coded(a: Vec4, c: Vec4, a_code: u8, c_code: u8, depth: DepthRange) -> ClipOutcome {
    let both = a_code | c_code;
    if both & NON_FINITE != 0 {
        return ClipOutcome::NonFinite;
    }
    if a_code & c_code & OUTCODE_BITS != 0 {
        return ClipOutcome::Rejected;
    }
    if both & OUTCODE_BITS == 0 {
        return if both & NOT_IN_FRONT == 0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }
    clip_crossing(a, c, a_code & OUTCODE_BITS, c_code & OUTCODE_BITS, depth)
}

/// Edges A→C in structure-of-arrays form: one array per coordinate of each endpoint.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgesSoa {
    /// Start points' x, y, z, w.
    pub a: [Vec<f32>; 4],
    /// End points' x, y, z, w.
    pub c: [Vec<f32>; 4],
}

impl EdgesSoa {
    /// The edges of `(a, c)` pairs.
    pub fn from_pairs(pairs: &[(Vec4, Vec4)]) -> Self {
        let mut e = Self::default();
        for &(a, c) in pairs {
            e.push(a, c);
        }
        e
    }

    /// Append one edge.
    pub fn push(&mut self, a: Vec4, c: Vec4) {
        for k in 0..4 {
            self.a[k].push(a[k]);
            self.c[k].push(c[k]);
        }
    }

    /// Number of edges (the length of the shortest array).
    pub fn len(&self) -> usize {
        self.a
            .iter()
            .chain(&self.c)
            .map(Vec::len)
            .min()
            .unwrap_or(0)
    }

    /// Whether there are no edges.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Edge `i` as two points.
    pub fn get(&self, i: usize) -> (Vec4, Vec4) {
        (
            Vec4::new(self.a[0][i], self.a[1][i], self.a[2][i], self.a[3][i]),
            Vec4::new(self.c[0][i], self.c[1][i], self.c[2][i], self.c[3][i]),
        )
    }
}

/// The visible segments of a batch, structure-of-arrays, with the index of the edge each came
/// from (ascending).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SegmentsSoa {
    /// Start points' x, y, z, w.
    pub a: [Vec<f32>; 4],
    /// End points' x, y, z, w.
    pub c: [Vec<f32>; 4],
    /// Index of the input edge of each segment.
    pub edge: Vec<u32>,
}

impl SegmentsSoa {
    /// Empty every array, keeping the capacity.
    pub fn clear(&mut self) {
        for v in self.a.iter_mut().chain(self.c.iter_mut()) {
            v.clear();
        }
        self.edge.clear();
    }

    /// Reserve room for `n` more segments.
    pub fn reserve(&mut self, n: usize) {
        for v in self.a.iter_mut().chain(self.c.iter_mut()) {
            v.reserve(n);
        }
        self.edge.reserve(n);
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.edge.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.edge.is_empty()
    }

    /// Segment `i`: (edge index, start, end).
    pub fn get(&self, i: usize) -> (u32, Vec4, Vec4) {
        (
            self.edge[i],
            Vec4::new(self.a[0][i], self.a[1][i], self.a[2][i], self.a[3][i]),
            Vec4::new(self.c[0][i], self.c[1][i], self.c[2][i], self.c[3][i]),
        )
    }

    /// Append one segment.
    #[inline]
    pub fn push(&mut self, edge: u32, a: Vec4, c: Vec4) {
        for k in 0..4 {
            self.a[k].push(a[k]);
            self.c[k].push(c[k]);
        }
        self.edge.push(edge);
    }
}

/// Lanes per step of [`clip_soa`].
pub const LANES: usize = 8;

/// Vertex codes of eight points given as coordinate lanes: straight-line code the compiler
/// vectorises.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(w > 0)`: NaN is not in front either
fn lane_codes<const ZERO_TO_ONE: bool>(
    x: &[f32; LANES],
    y: &[f32; LANES],
    z: &[f32; LANES],
    w: &[f32; LANES],
) -> [u8; LANES] {
    let mut code = [0u8; LANES];
    for i in 0..LANES {
        let (x, y, z, w) = (x[i], y[i], z[i], w[i]);
        let near = if ZERO_TO_ONE { z < 0.0 } else { z < -w };
        // |v| < ∞ is false for ±∞ and NaN.
        let finite = x.abs() < f32::INFINITY
            && y.abs() < f32::INFINITY
            && z.abs() < f32::INFINITY
            && w.abs() < f32::INFINITY;
        code[i] = u8::from(x < -w)
            | (u8::from(x > w) << 1)
            | (u8::from(y < -w) << 2)
            | (u8::from(y > w) << 3)
            | (u8::from(near) << 4)
            | (u8::from(z > w) << 5)
            | (u8::from(!finite) << 6)
            | (u8::from(!(w > 0.0)) << 7);
    }
    code
}

#[inline(always)]
fn lanes(v: &[f32], start: usize) -> &[f32; LANES] {
    v[start..start + LANES]
        .try_into()
        .expect("a slice of LANES elements")
}

/// Clip every edge of `edges` against the view volume, appending the visible segments to
/// `out` (not cleared) with their edge indices; returns the tally. Segments and counts are
/// exactly those of [`super::clip_edge`] applied edge by edge (a test holds it to that).
///
/// ```
/// use glam::Vec4;
/// use wireflight::clip::batch::{clip_soa, EdgesSoa, SegmentsSoa};
/// use wireflight::clip::DepthRange;
/// let edges = EdgesSoa::from_pairs(&[
///     (Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(0.5, 0.5, 0.5, 1.0)), // inside
///     (Vec4::new(2.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.0, 0.5, 1.0)), // outside
///     (Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.0, 0.5, 1.0)), // crossing
/// ]);
/// let mut out = SegmentsSoa::default();
/// let stats = clip_soa(&edges, DepthRange::ZeroToOne, &mut out);
/// assert_eq!((stats.trivially_accepted, stats.trivially_rejected, stats.clipped), (1, 1, 1));
/// assert_eq!(out.edge, [0, 2]);
/// ```
pub fn clip_soa(edges: &EdgesSoa, depth: DepthRange, out: &mut SegmentsSoa) -> ClipStats {
    match depth {
        DepthRange::ZeroToOne => clip_soa_impl::<true>(edges, out),
        DepthRange::NegOneToOne => clip_soa_impl::<false>(edges, out),
    }
}

fn clip_soa_impl<const ZERO_TO_ONE: bool>(edges: &EdgesSoa, out: &mut SegmentsSoa) -> ClipStats {
    let depth = if ZERO_TO_ONE {
        DepthRange::ZeroToOne
    } else {
        DepthRange::NegOneToOne
    };
    let n = edges.len();
    out.reserve(n);
    let mut stats = ClipStats {
        edges_in: n as u64,
        ..ClipStats::default()
    };
    let [ax, ay, az, aw] = &edges.a;
    let [cx, cy, cz, cw] = &edges.c;
    let full = n - n % LANES;
    let mut start = 0;
    while start < full {
        let ca = lane_codes::<ZERO_TO_ONE>(
            lanes(ax, start),
            lanes(ay, start),
            lanes(az, start),
            lanes(aw, start),
        );
        let cc = lane_codes::<ZERO_TO_ONE>(
            lanes(cx, start),
            lanes(cy, start),
            lanes(cz, start),
            lanes(cw, start),
        );
        let mut any = 0u8;
        for i in 0..LANES {
            any |= ca[i] | cc[i];
        }
        if any == 0 {
            // Eight edges inside and in front of the eye: copy them out as they are.
            let end = start + LANES;
            for k in 0..4 {
                out.a[k].extend_from_slice(&edges.a[k][start..end]);
                out.c[k].extend_from_slice(&edges.c[k][start..end]);
            }
            out.edge.extend(start as u32..end as u32);
            stats.trivially_accepted += LANES as u64;
        } else {
            for i in 0..LANES {
                lane(edges, start + i, ca[i], cc[i], depth, out, &mut stats);
            }
        }
        start += LANES;
    }
    for i in full..n {
        let (a, c) = edges.get(i);
        let (ca, cc) = (vertex_code(a, depth), vertex_code(c, depth));
        lane(edges, i, ca, cc, depth, out, &mut stats);
    }
    stats
}

#[inline(always)]
fn lane(
    edges: &EdgesSoa,
    i: usize,
    ca: u8,
    cc: u8,
    depth: DepthRange,
    out: &mut SegmentsSoa,
    stats: &mut ClipStats,
) {
    // The common drops first, without touching the coordinates again.
    if (ca | cc) & NON_FINITE != 0 {
        stats.non_finite += 1;
        return;
    }
    if ca & cc & OUTCODE_BITS != 0 {
        stats.trivially_rejected += 1;
        return;
    }
    let (a, c) = edges.get(i);
    let outcome = clip_coded(a, c, ca, cc, depth);
    match outcome {
        ClipOutcome::Accepted(p, q) => {
            stats.trivially_accepted += 1;
            out.push(i as u32, p, q);
        }
        ClipOutcome::Clipped(p, q) => {
            stats.clipped += 1;
            out.push(i as u32, p, q);
        }
        ClipOutcome::ClippedAway => stats.clipped_away += 1,
        ClipOutcome::Rejected => stats.trivially_rejected += 1,
        ClipOutcome::NonFinite => stats.non_finite += 1,
    }
}
