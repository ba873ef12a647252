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
//! * Flat edge lists in structure-of-arrays form ([`EdgesSoa`] → [`SegmentsSoa`]): blocks of
//!   [`BLOCK`] edges; the codes of a block's endpoints come from one pass of straight-line
//!   compares over the coordinate arrays, which the compiler turns into SIMD; a block that is
//!   all inside is copied out whole (nine bulk copies), any other block is compacted through
//!   a small staging area with no branch on the trivial outcomes.
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
/// use wireflight_geometry::clip::{batch, boundary_coords, outcode, DepthRange};
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

/// Edges per block of [`clip_soa`]: the codes of a block are computed in one vectorised pass,
/// then the block is either copied out whole (all inside) or compacted edge by edge. 64 edges
/// are 2 KiB of input and 2.3 KiB of staging, well inside L1, and make the per-block calls
/// (nine `extend_from_slice`) cheap per edge.
pub const BLOCK: usize = 64;

/// The code of one point ([`vertex_code`] bit for bit) from its coordinates: straight-line
/// compares that the compiler vectorises when called over slices.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(w > 0)`: NaN is not in front either
fn point_code<const ZERO_TO_ONE: bool>(x: f32, y: f32, z: f32, w: f32) -> u8 {
    let near = if ZERO_TO_ONE { z < 0.0 } else { z < -w };
    // |v| < ∞ is false for ±∞ and NaN.
    let finite = x.abs() < f32::INFINITY
        && y.abs() < f32::INFINITY
        && z.abs() < f32::INFINITY
        && w.abs() < f32::INFINITY;
    u8::from(x < -w)
        | (u8::from(x > w) << 1)
        | (u8::from(y < -w) << 2)
        | (u8::from(y > w) << 3)
        | (u8::from(near) << 4)
        | (u8::from(z > w) << 5)
        | (u8::from(!finite) << 6)
        | (u8::from(!(w > 0.0)) << 7)
}

/// Codes of the points `(x[i], y[i], z[i], w[i])` into `out[i]` (all five the same length).
#[inline(always)]
fn codes_into<const ZERO_TO_ONE: bool>(p: [&[f32]; 4], out: &mut [u8]) {
    let [x, y, z, w] = p;
    for ((((o, &x), &y), &z), &w) in out.iter_mut().zip(x).zip(y).zip(z).zip(w) {
        *o = point_code::<ZERO_TO_ONE>(x, y, z, w);
    }
}

/// Whether every point `(x[i], y[i], z[i], w[i])` is inside the volume and in front of the
/// eye, i.e. its [`vertex_code`] is 0: the block test of the trivial accept. One AND of eight
/// compares per point, with no early exit (so it vectorises; a block is 64 points), and none
/// of the packing of full codes. Finite follows: `w < ∞` and `|x|, |y|, |z| ≤ w`, and a NaN
/// fails every compare.
#[inline(always)]
fn all_inside<const ZERO_TO_ONE: bool>(p: [&[f32]; 4]) -> bool {
    let [x, y, z, w] = p;
    let mut ok = true;
    for (((&x, &y), &z), &w) in x.iter().zip(y).zip(z).zip(w) {
        let near = if ZERO_TO_ONE { 0.0 } else { -w };
        ok &= (x >= -w)
            & (x <= w)
            & (y >= -w)
            & (y <= w)
            & (z >= near)
            & (z <= w)
            & (w > 0.0)
            & (w < f32::INFINITY);
    }
    ok
}

/// Staging for one block's surviving segments: written unconditionally at the next free slot
/// (branch-free compaction), then appended to the output in nine calls.
struct Staging {
    a: [[f32; BLOCK]; 4],
    c: [[f32; BLOCK]; 4],
    edge: [u32; BLOCK],
}

/// Clip every edge of `edges` against the view volume, appending the visible segments to
/// `out` (not cleared) with their edge indices; returns the tally. Segments and counts are
/// exactly those of [`super::clip_edge`] applied edge by edge (a test holds it to that).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::batch::{clip_soa, EdgesSoa, SegmentsSoa};
/// use wireflight_geometry::clip::DepthRange;
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
    // One reservation per call: the loop below never reallocates.
    out.reserve(n);
    let mut stats = ClipStats {
        edges_in: n as u64,
        ..ClipStats::default()
    };
    let mut staging = Staging {
        a: [[0.0; BLOCK]; 4],
        c: [[0.0; BLOCK]; 4],
        edge: [0; BLOCK],
    };
    let (mut ca, mut cc) = ([0u8; BLOCK], [0u8; BLOCK]);
    // Whether to try the compare-only test first: after a block that was all inside (scenes
    // come in runs). After any other block the full codes are computed straight away, and
    // they find an all-inside block too, so a run of them is noticed one block late.
    let mut expect_inside = true;
    let mut start = 0;
    while start < n {
        let end = n.min(start + BLOCK);
        let m = end - start;
        let a: [&[f32]; 4] = std::array::from_fn(|k| &edges.a[k][start..end]);
        let c: [&[f32]; 4] = std::array::from_fn(|k| &edges.c[k][start..end]);
        let inside = expect_inside && all_inside::<ZERO_TO_ONE>(a) && all_inside::<ZERO_TO_ONE>(c);
        if !inside {
            codes_into::<ZERO_TO_ONE>(a, &mut ca[..m]);
            codes_into::<ZERO_TO_ONE>(c, &mut cc[..m]);
        }
        expect_inside = inside || ca[..m].iter().zip(&cc[..m]).all(|(&p, &q)| p | q == 0);
        if expect_inside {
            // The whole block is inside and in front of the eye: copy it out as it is.
            for k in 0..4 {
                out.a[k].extend_from_slice(a[k]);
                out.c[k].extend_from_slice(c[k]);
            }
            out.edge.extend(start as u32..end as u32);
            stats.trivially_accepted += m as u64;
            start = end;
            continue;
        }
        // Every edge finite and both ends outside one plane: the block is counted, not read.
        let all_rejected = ca[..m].iter().zip(&cc[..m]).fold(true, |acc, (&p, &q)| {
            acc & ((p | q) & NON_FINITE == 0) & (p & q & OUTCODE_BITS != 0)
        });
        if all_rejected {
            stats.trivially_rejected += m as u64;
        } else {
            compact_block(
                &a,
                &c,
                &ca[..m],
                &cc[..m],
                start,
                depth,
                &mut staging,
                out,
                &mut stats,
            );
        }
        start = end;
    }
    stats
}

/// One block with at least one edge not trivially accepted. Every edge is first written to
/// the next staging slot and the slot kept only if the edge is accepted (no branch on the
/// common outcomes, which are unpredictable in mixed data); the trivial drops are counted
/// without branches too; only crossing edges, and NaN or `w ≤ 0` ones, take the scalar path
/// ([`clip_coded`], the per-edge clipper's own code, so the results are bit-identical).
#[allow(clippy::too_many_arguments)]
#[inline]
fn compact_block(
    a: &[&[f32]; 4],
    c: &[&[f32]; 4],
    ca: &[u8],
    cc: &[u8],
    start: usize,
    depth: DepthRange,
    staging: &mut Staging,
    out: &mut SegmentsSoa,
    stats: &mut ClipStats,
) {
    let m = ca.len().min(cc.len()).min(BLOCK);
    let mut kept = 0usize;
    let (mut accepted, mut rejected) = (0u64, 0u64);
    for i in 0..m {
        let (either, both) = (ca[i] | cc[i], ca[i] & cc[i]);
        for k in 0..4 {
            staging.a[k][kept] = a[k][i];
            staging.c[k][kept] = c[k][i];
        }
        staging.edge[kept] = (start + i) as u32;
        let accept = either == 0;
        // clip_coded's order: non-finite first, then both outside one plane.
        let reject = either & NON_FINITE == 0 && both & OUTCODE_BITS != 0;
        kept += usize::from(accept);
        accepted += u64::from(accept);
        rejected += u64::from(reject);
        if !(accept || reject) {
            let p = Vec4::new(a[0][i], a[1][i], a[2][i], a[3][i]);
            let q = Vec4::new(c[0][i], c[1][i], c[2][i], c[3][i]);
            let outcome = clip_coded(p, q, ca[i], cc[i], depth);
            // Counted by the shared tally (edges_in was counted for the whole call).
            stats.record(&outcome);
            stats.edges_in -= 1;
            if let Some((p, q)) = outcome.segment() {
                for k in 0..4 {
                    staging.a[k][kept] = p[k];
                    staging.c[k][kept] = q[k];
                }
                kept += 1;
            }
        }
    }
    stats.trivially_accepted += accepted;
    stats.trivially_rejected += rejected;
    for k in 0..4 {
        out.a[k].extend_from_slice(&staging.a[k][..kept]);
        out.c[k].extend_from_slice(&staging.c[k][..kept]);
    }
    out.edge.extend_from_slice(&staging.edge[..kept]);
}
