//! Blinn's clipper over batches: the same segments and counts as [`super::clip_edge`] edge by
//! edge, faster.
//!
//! Two shapes of input, one principle: **the trivial cases are decided from outcodes computed
//! without branches, many at a time, and only the crossing edges are clipped**, with the
//! arithmetic of the function the per-edge clipper uses ([`super::blinn::clip_crossing`]):
//! the same operations in the same order, in lanes, or that very function for an edge alone
//! and for the rare lanes whose result could depend on the order of ties or that `settle()`
//! would recompute. So a crossing edge gives bit-identical results either way.
//!
//! * Indexed meshes (the projector): [`vertex_code`] once per *vertex* (glam's SIMD compare of
//!   `(x, y, z)` against `±w`, two movemasks), then per edge two byte loads, an OR and an AND
//!   ([`clip_coded`]). A vertex shared by four edges is classified once instead of four times.
//! * Flat edge lists in structure-of-arrays form ([`EdgesSoa`] → [`SegmentsSoa`]): blocks of
//!   [`BLOCK`] edges; a block that is all inside is copied out whole (nine bulk copies). Any
//!   other block, where the CPU has AVX-512 (`batch/avx512.rs`): one pass of 16-edge steps,
//!   each classified with masks, its crossing edges packed into lanes and clipped sixteen at
//!   a time in `f32` (all six planes at once, [`clip_crossing`]'s arithmetic operation for
//!   operation), and compacted straight into the output. Elsewhere (the portable build,
//!   and its crossing lanes compiled for AVX2 where the CPU has it): the codes of the
//!   block's endpoints from straight-line compares, the crossing edges gathered into lanes
//!   and clipped there, and the block compacted through a small staging area with no branch
//!   on the trivial outcomes. Both builds give the same bits; the tests run every build
//!   the CPU has.
//!
//! Why the outcodes can skip the boundary coordinates: `w + x < 0` (rounded in `f32`) holds
//! exactly when `x < −w` (rounding keeps the sign of a sum, and a sum of two floats is zero
//! only when they cancel exactly), and likewise for every plane, so comparing coordinates with
//! `±w` gives bit for bit the codes of [`super::outcode`] with no additions.
//!
//! Never allocates per edge: the output vectors are reserved once per call. Pure math.

use glam::Vec4;

use super::blinn::{clip_crossing, SINGLE_LIMIT};
use super::{ClipOutcome, ClipStats, DepthRange, PLANE_COUNT, SETTLE_REL};

#[cfg(target_arch = "x86_64")]
mod avx512;

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
    clip_soa_on(Path::best(), edges, depth, out)
}

/// The builds of [`clip_soa`], best first where the CPU has them (the tests run each one
/// this machine can).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    /// One masked pass per block (`batch/avx512.rs`): classify 16 edges, pack the crossing
    /// ones into lanes, clip them sixteen at a time in `f32`, compact by permutes.
    /// AVX-512F, BMI2, POPCNT.
    #[cfg(target_arch = "x86_64")]
    Avx512,
    /// The portable code with its crossing lanes compiled for AVX2.
    Avx2,
    /// The portable code as the target allows (SSE2 on x86-64).
    Portable,
}

impl Path {
    /// The best build this CPU runs (asked once per call; the standard library caches it).
    fn best() -> Path {
        #[cfg(target_arch = "x86_64")]
        if avx512::available() {
            return Path::Avx512;
        }
        if has_avx2() {
            Path::Avx2
        } else {
            Path::Portable
        }
    }

    /// Every build this CPU runs.
    #[cfg(test)]
    fn all_available() -> Vec<Path> {
        let mut paths = vec![Path::Portable];
        if has_avx2() {
            paths.push(Path::Avx2);
        }
        #[cfg(target_arch = "x86_64")]
        if avx512::available() {
            paths.push(Path::Avx512);
        }
        paths
    }
}

/// [`clip_soa`] on the build `path`, which must be one this CPU runs ([`Path::best`] or
/// below).
fn clip_soa_on(
    path: Path,
    edges: &EdgesSoa,
    depth: DepthRange,
    out: &mut SegmentsSoa,
) -> ClipStats {
    let zero_to_one = depth == DepthRange::ZeroToOne;
    match path {
        #[cfg(target_arch = "x86_64")]
        Path::Avx512 => {
            assert!(avx512::available(), "AVX-512 path on a CPU without it");
            // SAFETY: checked just above.
            unsafe {
                if zero_to_one {
                    avx512::clip_soa::<true>(edges, out)
                } else {
                    avx512::clip_soa::<false>(edges, out)
                }
            }
        }
        Path::Avx2 | Path::Portable => {
            let avx2 = path == Path::Avx2 && has_avx2();
            if zero_to_one {
                clip_soa_impl::<true>(edges, out, avx2)
            } else {
                clip_soa_impl::<false>(edges, out, avx2)
            }
        }
    }
}

fn clip_soa_impl<const ZERO_TO_ONE: bool>(
    edges: &EdgesSoa,
    out: &mut SegmentsSoa,
    avx2: bool,
) -> ClipStats {
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
    let mut crossing = Crossing {
        idx: [0; BLOCK],
        a: [[0.0; BLOCK]; 4],
        c: [[0.0; BLOCK]; 4],
        state: [0; BLOCK],
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
            compact_block::<ZERO_TO_ONE>(
                &a,
                &c,
                &ca[..m],
                &cc[..m],
                start,
                avx2,
                &mut crossing,
                &mut staging,
                out,
                &mut stats,
            );
        }
        start = end;
    }
    stats
}

/// One block with at least one edge not trivially accepted, in three passes:
///
/// 1. the crossing edges (finite, neither trivially accepted nor rejected) are gathered into
///    lanes ([`Crossing`]);
/// 2. all of them are clipped at once ([`crossing_lanes`]: the entry and exit parameters of
///    every plane, `t_in`/`t_out`, the new ends, in `f32` lanes as [`clip_crossing`] computes
///    them, so bit for bit its results); the few lanes it leaves to the scalar code get it;
/// 3. every edge is written to the next staging slot (its own ends, or its lane's clipped
///    ends) and the slot kept if the edge is drawn: no branch on the common outcomes, which
///    are unpredictable in mixed data. NaN or `w ≤ 0` edges with no outcode bit take
///    [`clip_coded`] (the per-edge clipper's own code).
#[allow(clippy::too_many_arguments)]
#[inline]
fn compact_block<const ZERO_TO_ONE: bool>(
    a: &[&[f32]; 4],
    c: &[&[f32]; 4],
    ca: &[u8],
    cc: &[u8],
    start: usize,
    avx2: bool,
    x: &mut Crossing,
    staging: &mut Staging,
    out: &mut SegmentsSoa,
    stats: &mut ClipStats,
) {
    let depth = if ZERO_TO_ONE {
        DepthRange::ZeroToOne
    } else {
        DepthRange::NegOneToOne
    };
    let m = ca.len().min(cc.len()).min(BLOCK);
    let crosses = |p: u8, q: u8| {
        let (either, both) = (p | q, p & q);
        (either & NON_FINITE == 0) & (both & OUTCODE_BITS == 0) & (either & OUTCODE_BITS != 0)
    };
    // 1. Gather.
    let mut n = 0usize;
    for i in 0..m {
        x.idx[n] = i as u8; // n ≤ i < BLOCK
        n += usize::from(crosses(ca[i], cc[i]));
    }
    for j in 0..n {
        let i = usize::from(x.idx[j]);
        for k in 0..4 {
            x.a[k][j] = a[k][i];
            x.c[k][j] = c[k][i];
        }
    }
    // 2. Clip the lanes.
    if n > 0 {
        crossing_lanes::<ZERO_TO_ONE>(x, n, avx2);
    }
    let mut clipped = 0u64;
    for j in 0..n {
        if x.state[j] == LANE_SCALAR {
            let i = usize::from(x.idx[j]);
            let p = Vec4::new(a[0][i], a[1][i], a[2][i], a[3][i]);
            let q = Vec4::new(c[0][i], c[1][i], c[2][i], c[3][i]);
            let outcome = clip_crossing(p, q, ca[i] & OUTCODE_BITS, cc[i] & OUTCODE_BITS, depth);
            x.state[j] = LANE_AWAY;
            if let Some((p, q)) = outcome.segment() {
                for k in 0..4 {
                    x.a[k][j] = p[k];
                    x.c[k][j] = q[k];
                }
                x.state[j] = LANE_VISIBLE;
            }
        }
        clipped += u64::from(x.state[j]);
    }
    stats.clipped += clipped;
    stats.clipped_away += n as u64 - clipped;
    // 3. Compact.
    let mut kept = 0usize;
    let mut lane = 0usize;
    let (mut accepted, mut rejected) = (0u64, 0u64);
    for i in 0..m {
        let (either, both) = (ca[i] | cc[i], ca[i] & cc[i]);
        let cross = crosses(ca[i], cc[i]);
        let l = lane & (BLOCK - 1); // the lane of a crossing edge (< n ≤ BLOCK)
        for k in 0..4 {
            staging.a[k][kept] = if cross { x.a[k][l] } else { a[k][i] };
            staging.c[k][kept] = if cross { x.c[k][l] } else { c[k][i] };
        }
        staging.edge[kept] = (start + i) as u32;
        let accept = either == 0;
        // clip_coded's order: non-finite first, then both outside one plane.
        let reject = either & NON_FINITE == 0 && both & OUTCODE_BITS != 0;
        kept += usize::from(accept | (cross & (x.state[l] == LANE_VISIBLE)));
        lane += usize::from(cross);
        accepted += u64::from(accept);
        rejected += u64::from(reject);
        if !(accept || reject || cross) {
            // A NaN or ∞, or the eye: the per-edge code.
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

/// The crossing edges of one block, gathered into lanes (structure of arrays), and their
/// results: [`crossing_lanes`] clips them all at once.
struct Crossing {
    /// Index in the block of each lane's edge.
    idx: [u8; BLOCK],
    /// The lanes' start and end points, x, y, z, w; after [`crossing_lanes`], the clipped
    /// ends.
    a: [[f32; BLOCK]; 4],
    c: [[f32; BLOCK]; 4],
    /// Per lane: [`LANE_AWAY`], [`LANE_VISIBLE`] or [`LANE_SCALAR`].
    state: [u8; BLOCK],
}

/// Lane state: nothing visible (the per-edge clipper's `ClippedAway`).
const LANE_AWAY: u8 = 0;
/// Lane state: the clipped segment is in the lane (`Clipped`).
const LANE_VISIBLE: u8 = 1;
/// Lane state: a rare case the lanes leave to the per-edge code ([`clip_crossing`]): an exit
/// parameter of zero (its sign would depend on the order of ties), or an end that `settle()`
/// would recompute.
const LANE_SCALAR: u8 = 2;

/// Lanes per step of [`crossing_lanes`]: one AVX2 vector of `f32`, two SSE2 ones.
const LANES: usize = 8;

/// The boundary coordinates of `[x, y, z, w]` in [`super::boundary_coords_of`]'s order and
/// with its operations.
#[inline(always)]
fn bc_of<T, const ZERO_TO_ONE: bool>([x, y, z, w]: [T; 4]) -> [T; PLANE_COUNT]
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Sub<Output = T>,
{
    let near = if ZERO_TO_ONE { z } else { w + z };
    [w + x, w - x, w + y, w - y, near, w - z]
}

/// Whether `settle()` keeps the computed end `p` as it is: every boundary coordinate ≥
/// −`SETTLE_REL`·max |pᵢ| (in `f64`, as `settle()` computes it), or `p.w ≤ 0`.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(w > 0)`, as settle() has it
fn settles_as_is<const ZERO_TO_ONE: bool>(p: [f32; 4]) -> bool {
    // Finite, non-negative values: the maximum does not depend on the order.
    let m = p[0].abs().max(p[1].abs()).max(p[2].abs()).max(p[3].abs());
    let slack = SETTLE_REL * f64::from(m);
    let bc = bc_of::<f64, ZERO_TO_ONE>(p.map(f64::from));
    let mut within = true;
    for b in bc {
        within &= b >= -slack;
    }
    within | !(p[3] > 0.0)
}

/// One lane of [`crossing_lanes`]: [`clip_crossing`]'s `f32` arithmetic, operation for
/// operation, with selects instead of branches (so that the compiler can run lanes side by
/// side). The outcode bits are recovered from the signs of the boundary coordinates (a
/// rounded sum has the sign of the exact one, and is zero only when that is), every plane is
/// visited and its parameter kept only where it crosses, and the early exit becomes one
/// final test (`t_in` only rises and `t_out` only falls, so they cross at the end if they
/// ever do). `max`/`min` become compares: the only ties where they could differ are exit
/// parameters of ±0, which go to the scalar code, as do edges with a coordinate beyond
/// [`SINGLE_LIMIT`] (the per-edge clipper computes those in `f64`).
#[inline(always)]
fn crossing_lane<const ZERO_TO_ONE: bool>(a: [f32; 4], c: [f32; 4]) -> ([f32; 4], [f32; 4], u8) {
    let mut largest = 0f32;
    for v in a.iter().chain(&c) {
        largest = largest.max(v.abs());
    }
    let a_bc = bc_of::<f32, ZERO_TO_ONE>(a);
    let c_bc = bc_of::<f32, ZERO_TO_ONE>(c);
    let (mut t_in, mut t_out) = (0.0f32, 1.0f32);
    let (mut enters, mut leaves) = (false, false);
    for i in 0..PLANE_COUNT {
        let t_hit = a_bc[i] / (a_bc[i] - c_bc[i]);
        let (enter, leave) = (a_bc[i] < 0.0, c_bc[i] < 0.0);
        t_in = if enter & (t_hit > t_in) { t_hit } else { t_in };
        t_out = if leave & (t_hit < t_out) {
            t_hit
        } else {
            t_out
        };
        enters |= enter;
        leaves |= leave;
    }
    let visible = t_in <= t_out; // never NaN below the limit (and beyond it not used)
    let p: [f32; 4] = std::array::from_fn(|k| {
        if enters {
            a[k] + t_in * (c[k] - a[k])
        } else {
            a[k]
        }
    });
    let q: [f32; 4] = std::array::from_fn(|k| {
        if leaves {
            a[k] + t_out * (c[k] - a[k])
        } else {
            c[k]
        }
    });
    let scalar = (leaves & (t_out == 0.0))
        | (enters & !settles_as_is::<ZERO_TO_ONE>(p))
        | (leaves & !settles_as_is::<ZERO_TO_ONE>(q));
    let drawn = (p[3] > 0.0) & (q[3] > 0.0);
    let state = if largest > SINGLE_LIMIT {
        LANE_SCALAR
    } else if !visible {
        LANE_AWAY
    } else if scalar {
        LANE_SCALAR
    } else {
        u8::from(drawn) // LANE_VISIBLE or LANE_AWAY
    };
    (p, q, state)
}

/// [`crossing_lane`] over the first `n` lanes of `x` (rounded up to [`LANES`]; the lanes
/// past `n` hold stale values, computed and ignored), in place.
#[inline(always)]
fn crossing_lanes_body<const ZERO_TO_ONE: bool>(x: &mut Crossing, n: usize) {
    let steps = n.div_ceil(LANES).min(BLOCK / LANES);
    for s in 0..steps {
        let base = s * LANES;
        let mut pa = [[0f32; LANES]; 4];
        let mut pc = [[0f32; LANES]; 4];
        let mut st = [0u8; LANES];
        for l in 0..LANES {
            let a = std::array::from_fn(|k| x.a[k][base + l]);
            let c = std::array::from_fn(|k| x.c[k][base + l]);
            let (p, q, state) = crossing_lane::<ZERO_TO_ONE>(a, c);
            for k in 0..4 {
                pa[k][l] = p[k];
                pc[k][l] = q[k];
            }
            st[l] = state;
        }
        for k in 0..4 {
            x.a[k][base..base + LANES].copy_from_slice(&pa[k]);
            x.c[k][base..base + LANES].copy_from_slice(&pc[k]);
        }
        x.state[base..base + LANES].copy_from_slice(&st);
    }
}

/// [`crossing_lanes_body`] compiled for AVX2 (eight `f32` per instruction instead of four).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn crossing_lanes_avx2<const ZERO_TO_ONE: bool>(x: &mut Crossing, n: usize) {
    crossing_lanes_body::<ZERO_TO_ONE>(x, n);
}

/// Whether [`crossing_lanes`] may take the AVX2 build (asked once per call of `clip_soa`).
#[inline]
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Clip the first `n` lanes of `x` (see [`crossing_lane`]).
#[inline]
fn crossing_lanes<const ZERO_TO_ONE: bool>(x: &mut Crossing, n: usize, avx2: bool) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is `has_avx2()`, true only where the CPU has AVX2.
        unsafe { crossing_lanes_avx2::<ZERO_TO_ONE>(x, n) };
        return;
    }
    let _ = avx2;
    crossing_lanes_body::<ZERO_TO_ONE>(x, n);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clip::clip_edge;

    /// The per-edge clipper's segments (appended to `prefix`) and tally for `pairs`.
    fn per_edge(
        pairs: &[(Vec4, Vec4)],
        depth: DepthRange,
        prefix: &SegmentsSoa,
    ) -> (SegmentsSoa, ClipStats) {
        let mut expected = prefix.clone();
        let mut tally = ClipStats::default();
        for (i, &(a, c)) in pairs.iter().enumerate() {
            let o = clip_edge(a, c, depth);
            tally.record(&o);
            if let Some((p, q)) = o.segment() {
                expected.push(i as u32, p, q);
            }
        }
        (expected, tally)
    }

    fn bits(v: &[f32]) -> Vec<u32> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// Every build this CPU runs gives the per-edge clipper's segments, bit for bit, and its
    /// tally, appended after what `out` already holds.
    fn check_paths_after(
        pairs: &[(Vec4, Vec4)],
        depth: DepthRange,
        prefix: &SegmentsSoa,
        what: &str,
    ) {
        let (expected, tally) = per_edge(pairs, depth, prefix);
        let edges = EdgesSoa::from_pairs(pairs);
        for path in Path::all_available() {
            let mut got = prefix.clone();
            let stats = clip_soa_on(path, &edges, depth, &mut got);
            assert_eq!(stats, tally, "{what} {path:?} {depth:?}");
            assert_eq!(got.edge, expected.edge, "{what} {path:?} {depth:?}");
            for k in 0..4 {
                assert_eq!(
                    bits(&got.a[k]),
                    bits(&expected.a[k]),
                    "{what} {path:?} {depth:?} a[{k}]"
                );
                assert_eq!(
                    bits(&got.c[k]),
                    bits(&expected.c[k]),
                    "{what} {path:?} {depth:?} c[{k}]"
                );
            }
        }
    }

    fn check_paths(pairs: &[(Vec4, Vec4)], what: &str) {
        for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
            check_paths_after(pairs, depth, &SegmentsSoa::default(), what);
        }
    }

    /// xorshift64: deterministic, no dependency.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n as u64) as usize
        }
        fn unit(&mut self) -> f32 {
            (self.next() >> 40) as f32 / (1u64 << 24) as f32
        }
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * self.unit()
        }
        fn pick<T: Copy>(&mut self, v: &[T]) -> T {
            v[self.below(v.len())]
        }
    }

    const SPECIALS: [f32; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MIN_POSITIVE,
        1e-40,
        -1e-45,
        3e38,
        -3e38,
        f32::MAX,
        1e-30,
        1e30,
    ];

    /// A point of one of many kinds: inside, outside by a little or a lot, behind the eye,
    /// near w = 0, on a plane, huge, tiny, or with special values in any coordinate.
    fn point(rng: &mut Rng) -> Vec4 {
        let w = match rng.below(8) {
            0 => rng.range(-1e-6, 1e-6), // w ≈ 0
            1 => -rng.range(0.01, 50.0), // behind the eye
            2 => rng.pick(&SPECIALS),
            3 => rng.range(1e3, 1e6),
            _ => rng.range(0.01, 50.0),
        };
        let mut p = match rng.below(6) {
            // Inside (for w > 0).
            0 | 1 => Vec4::new(rng.range(-w, w), rng.range(-w, w), rng.range(0.0, w), w),
            // Outside by a factor.
            2 => {
                let k = rng.range(1.0, 4.0);
                Vec4::new(
                    w * k * rng.range(-1.0, 1.0).signum(),
                    rng.range(-w, w) * k,
                    rng.range(-w, w) * k,
                    w,
                )
            }
            // On a plane exactly.
            3 => Vec4::new(
                rng.pick(&[w, -w, 0.0]),
                rng.pick(&[w, -w, 0.5 * w]),
                rng.pick(&[w, -w, 0.0]),
                w,
            ),
            // Anywhere.
            _ => Vec4::new(
                rng.range(-60.0, 60.0),
                rng.range(-60.0, 60.0),
                rng.range(-60.0, 60.0),
                w,
            ),
        };
        if rng.below(20) == 0 {
            p[rng.below(4)] = rng.pick(&SPECIALS);
        }
        p
    }

    /// `n` random edges: runs of one kind (so whole blocks are inside, outside or crossing)
    /// mixed with random edges, some degenerate (A = C) or reversed.
    fn random_edges(rng: &mut Rng, n: usize) -> Vec<(Vec4, Vec4)> {
        let inside = |rng: &mut Rng| {
            let w = rng.range(0.5, 50.0);
            Vec4::new(rng.range(-w, w), rng.range(-w, w), rng.range(0.0, w), w)
        };
        let mut edges = Vec::with_capacity(n);
        while edges.len() < n {
            let run = 1 + rng.below(150);
            let kind = rng.below(5);
            for _ in 0..run {
                let e = match kind {
                    0 => (inside(rng), inside(rng)),
                    1 => {
                        // Crossing: inside to beyond one to three planes.
                        let a = inside(rng);
                        let mut c = inside(rng);
                        let k = rng.range(1.01, 3.0);
                        c.x = c.w * k;
                        if rng.below(2) == 0 {
                            c.y = -c.w * k;
                        }
                        if rng.below(3) == 0 {
                            c.z = c.w * k;
                        }
                        if rng.below(2) == 0 {
                            (c, a)
                        } else {
                            (a, c)
                        }
                    }
                    2 => {
                        // Inside to behind the eye.
                        let b = Vec4::new(
                            rng.range(-20.0, 20.0),
                            rng.range(-20.0, 20.0),
                            rng.range(-20.0, 20.0),
                            -rng.range(0.0, 20.0),
                        );
                        (inside(rng), b)
                    }
                    _ => {
                        let a = point(rng);
                        let c = if rng.below(20) == 0 { a } else { point(rng) };
                        (a, c)
                    }
                };
                edges.push(e);
            }
        }
        edges.truncate(n);
        edges
    }

    /// The batch-vs-per-edge property on random edges of every kind, every build this CPU
    /// runs, both depth ranges. `WIREFLIGHT_BATCH_CASES` sets the number of batches (default
    /// 300; each 1 to 700 edges, so every tail length of a block comes up).
    #[test]
    fn every_build_matches_the_per_edge_clipper_on_random_batches() {
        let cases: usize = std::env::var("WIREFLIGHT_BATCH_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(300);
        let mut rng = Rng(0x0005_EED0_FBA7_C4E5);
        for case in 0..cases {
            let n = 1 + rng.below(700);
            let edges = random_edges(&mut rng, n);
            check_paths(&edges, &format!("case {case}, n = {n}"));
        }
    }

    /// Every block length, and every tail: 1 to 3 blocks plus 0 to 63 edges, of all-crossing
    /// edges (every lane of pass 2 full, and partial in the tail), and of crossing edges
    /// alternating with inside ones.
    #[test]
    fn block_tails_and_all_crossing_blocks() {
        let mut rng = Rng(0x7A11);
        let crossing: Vec<(Vec4, Vec4)> = random_edges(&mut Rng(3), 4000)
            .into_iter()
            .filter(|&(a, c)| {
                let (p, q) = (
                    vertex_code(a, DepthRange::ZeroToOne),
                    vertex_code(c, DepthRange::ZeroToOne),
                );
                (p | q) & NON_FINITE == 0
                    && p & q & OUTCODE_BITS == 0
                    && (p | q) & OUTCODE_BITS != 0
            })
            .collect();
        assert!(crossing.len() > 4 * BLOCK, "{}", crossing.len());
        for n in 1..=3 * BLOCK + BLOCK / 2 {
            let start = rng.below(crossing.len() - n);
            check_paths(
                &crossing[start..start + n],
                &format!("all crossing, n = {n}"),
            );
            let alternating: Vec<_> = (0..n)
                .map(|i| {
                    if i % 2 == 0 {
                        crossing[(start + i) % crossing.len()]
                    } else {
                        (
                            Vec4::new(0.1, 0.2, 0.3, 1.0),
                            Vec4::new(-0.5, 0.5, 0.9, 1.0),
                        )
                    }
                })
                .collect();
            check_paths(&alternating, &format!("alternating, n = {n}"));
        }
    }

    /// w ≈ 0 and w ≤ 0 (the eye, behind it), NaN and ±∞ in every coordinate, huge and
    /// subnormal values: each alone in a block of inside edges and in runs.
    #[test]
    fn eye_behind_the_eye_and_non_finite_edges() {
        let mut specials = vec![
            (Vec4::ZERO, Vec4::ZERO),
            (Vec4::ZERO, Vec4::new(0.1, 0.1, 0.5, 1.0)),
            (
                Vec4::new(-0.0, 0.0, -0.0, -0.0),
                Vec4::new(0.0, -0.0, 0.0, 0.0),
            ),
            (
                Vec4::new(0.0, 0.0, 0.0, 1e-45),
                Vec4::new(0.5, 0.0, 0.5, 1.0),
            ),
            (
                Vec4::new(1e-45, 0.0, 0.0, 1e-45),
                Vec4::new(2.0, 0.0, 0.5, 1.0),
            ),
            (
                Vec4::new(0.0, 0.0, 0.5, 1.0),
                Vec4::new(0.0, 0.0, 0.5, -1.0),
            ),
            (
                Vec4::new(0.3, -0.2, 0.5, 1.0),
                Vec4::new(0.5, 0.5, -0.5, -1e-7),
            ),
            (
                Vec4::new(0.3, -0.2, 0.5, 1e-7),
                Vec4::new(5.0, 5.0, 5.0, -1e-7),
            ),
            (
                Vec4::new(0.3, -0.2, 0.5, 1.0),
                Vec4::new(3e38, -3e38, 3e38, -1e37),
            ),
            (
                Vec4::new(0.5, 0.5, 0.5, 1.5),
                Vec4::new(-1e37, 1e37, 1e37, -1e37),
            ),
            (
                Vec4::new(0.0, 0.0, 0.5, 1.0),
                Vec4::new(0.0, 0.0, -f32::MAX, f32::MAX),
            ),
            (
                Vec4::new(1e-40, -1e-40, 1e-40, 1e-40),
                Vec4::new(1.0, 1.0, 1.0, 1e-40),
            ),
        ];
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for k in 0..8 {
                let mut a = Vec4::new(0.1, 0.2, 0.3, 1.0);
                let mut c = Vec4::new(2.0, 0.2, 0.3, 1.0); // crossing x = w
                if k < 4 {
                    a[k] = bad;
                } else {
                    c[k - 4] = bad;
                }
                specials.push((a, c));
                specials.push((Vec4::new(0.1, 0.2, 0.3, 1.0), a)); // otherwise inside
            }
        }
        let inside = (
            Vec4::new(0.1, 0.2, 0.3, 1.0),
            Vec4::new(-0.5, 0.5, 0.9, 1.0),
        );
        for (i, &e) in specials.iter().enumerate() {
            for at in [0, 1, 15, 16, 17, 63] {
                let mut edges = vec![inside; BLOCK + 5];
                edges[at] = e;
                check_paths(&edges, &format!("special {i} at {at}"));
            }
            check_paths(&vec![e; 2 * BLOCK + 3], &format!("run of special {i}"));
            check_paths(&[e], &format!("special {i} alone"));
        }
        check_paths(&specials, "all specials");
    }

    /// Segments are appended after what `out` holds (the vectors' lengths may differ, and
    /// their capacity may be exactly their length).
    #[test]
    fn segments_are_appended_after_existing_ones() {
        let edges = random_edges(&mut Rng(99), 1000);
        let mut prefix = SegmentsSoa::default();
        prefix.push(7, Vec4::ONE, Vec4::NEG_ONE);
        prefix.a[2].push(5.0);
        prefix.edge.push(3);
        for v in prefix.a.iter_mut().chain(prefix.c.iter_mut()) {
            v.shrink_to_fit();
        }
        prefix.edge.shrink_to_fit();
        for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
            check_paths_after(&edges, depth, &prefix, "appended");
        }
    }

    /// Edges on and around the planes, with signed zeros: where the lanes' ties and
    /// `settle()` cases are; the batch must equal the per-edge clipper bit for bit.
    #[test]
    fn crossing_lanes_match_the_per_edge_clipper_on_ties_and_signed_zeros() {
        let vals = [
            0.0f32, -0.0, 1.0, -1.0, 0.5, -0.5, 2.0, -2.0, 3e38, -3e38, 1e-40, 0.25,
        ];
        let mut s = 0x1234_5678_9abc_def1u64;
        let mut pick = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            vals[(s % vals.len() as u64) as usize]
        };
        let pairs: Vec<(Vec4, Vec4)> = (0..200_000)
            .map(|_| {
                let a = Vec4::new(pick(), pick(), pick(), pick());
                let c = Vec4::new(pick(), pick(), pick(), pick());
                (a, c)
            })
            .collect();
        check_paths(&pairs, "ties and signed zeros");
    }
}
