//! [`super::clip_soa`] with AVX-512: every block that is not trivially accepted is clipped
//! with masks in one pass of 16-edge steps, with no branch per edge and nothing but the
//! output written to memory.
//!
//! Per step: **classify** (`f32`): the twelve boundary coordinates of both ends; the least of
//! them (< 0: outside some plane), the least over the planes of the greater of each pair
//! (< 0: both ends outside one plane), one test that every coordinate is finite and within
//! the per-edge clipper's `f32` limit (an unsigned maximum of the bit patterns), and from
//! them the lane masks: trivially accepted and drawn, trivially rejected, non-finite,
//! crossing (finite, neither trivial). **Pack** the crossing edges into the low lanes of
//! registers (one compress of the lane numbers, then one permute per coordinate). **Clip the
//! lanes** (all sixteen at once, `f32`): [`super::super::blinn::clip_crossing`]'s arithmetic
//! in the same operations and order, all six planes at once with masks (a plane no lane
//! crosses is skipped), `t_in`/`t_out` by masked max/min, the new ends, and `settle()`'s test
//! (both only for the side some lane moves: mostly the start points are inside, and then
//! they are passed through). The rare lanes whose result could depend on the order of ties
//! (an exit parameter of ±0), that `settle()` might recompute, or that the per-edge clipper
//! computes in `f64` (a coordinate beyond [`SINGLE_LIMIT`]) take the scalar code.
//! **Compact**: each drawn edge's own ends, or for a crossing edge its lane's clipped ends,
//! picked by one two-table permute per coordinate and stored straight into the output's
//! spare capacity. The inputs are
//! prefetched two blocks ahead (the pass reads each step's lines only when it gets there).
//!
//! Every arithmetic instruction here is exact and deterministic (IEEE add, subtract, multiply,
//! divide, min/max without ties that matter, compares), so the lanes give bit for bit what
//! the per-edge clipper gives; the tests hold this path and the portable one to it.
//!
//! `unsafe` here: the intrinsics (each function is compiled for AVX-512F, BMI2 and POPCNT and
//! entered only after [`available`] said yes), their loads and stores (masked to the live
//! lanes of a slice, or within fixed-size arrays), and the stores into `out`'s spare
//! capacity followed by `set_len` (room reserved for every edge plus one step up front).

use std::arch::x86_64::*;

use glam::Vec4;

use super::super::blinn::{clip_crossing, SINGLE_LIMIT};
use super::super::{boundary_coords, outcode, ClipOutcome, ClipStats, DepthRange, SETTLE_REL};
use super::{all_inside, EdgesSoa, SegmentsSoa, BLOCK};

/// Edges per step (one `zmm` of `f32`).
const STEP: usize = 16;
/// How far ahead (in edges) [`clip_soa`] prefetches its inputs.
const PREFETCH: usize = 2 * BLOCK;

/// Whether this CPU can run [`clip_soa`] (checked at run time, cached by the standard
/// library).
pub(super) fn available() -> bool {
    std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("bmi2")
        && std::is_x86_feature_detected!("popcnt")
}

/// [`super::clip_soa`] on this path: the same segments, order and tally.
///
/// # Safety
/// The CPU must have AVX-512F, BMI2 and POPCNT ([`available`]).
#[target_feature(enable = "avx512f,bmi2,popcnt")]
pub(super) unsafe fn clip_soa<const ZERO_TO_ONE: bool>(
    edges: &EdgesSoa,
    out: &mut SegmentsSoa,
) -> ClipStats {
    let n = edges.len();
    // Every vector of `out` gets room for all the edges plus one step: each step stores 16
    // lanes at the current end, past the segments it keeps.
    for v in out.a.iter_mut().chain(out.c.iter_mut()) {
        v.reserve(n + STEP);
    }
    out.edge.reserve(n + STEP);
    let mut stats = ClipStats {
        edges_in: n as u64,
        ..ClipStats::default()
    };
    // As in the portable path: after an all-inside block, try the compare-only test first.
    let mut expect_inside = true;
    let mut start = 0;
    while start < n {
        let end = n.min(start + BLOCK);
        let [ax, ay, az, aw] = &edges.a;
        let [cx, cy, cz, cw] = &edges.c;
        let r = start..end;
        let a = [
            &ax[r.clone()],
            &ay[r.clone()],
            &az[r.clone()],
            &aw[r.clone()],
        ];
        let c = [&cx[r.clone()], &cy[r.clone()], &cz[r.clone()], &cw[r]];
        // The inputs two blocks ahead, into L1: the single pass reads each step's lines
        // only when it gets to them.
        let ahead = start + PREFETCH;
        if ahead < n {
            for v in edges.a.iter().chain(&edges.c) {
                for line in (0..BLOCK).step_by(16) {
                    // A prefetch never faults; the address is inside the slice or at most
                    // a block past its end (`wrapping_add`: no pointer rules broken).
                    _mm_prefetch::<_MM_HINT_T0>(v.as_ptr().wrapping_add(ahead + line).cast());
                }
            }
        }
        if expect_inside && all_inside::<ZERO_TO_ONE>(a) && all_inside::<ZERO_TO_ONE>(c) {
            copy_out(&a, &c, start, out);
            stats.trivially_accepted += (end - start) as u64;
        } else {
            // SAFETY: the features are the caller's promise; `out` has room for every edge
            // left plus one step (reserved above, never shrunk).
            expect_inside = unsafe { block::<ZERO_TO_ONE>(&a, &c, start, out, &mut stats) };
        }
        start = end;
    }
    stats
}

/// Append a block that is wholly accepted (nine bulk copies).
#[inline(always)]
fn copy_out(a: &[&[f32]; 4], c: &[&[f32]; 4], start: usize, out: &mut SegmentsSoa) {
    for k in 0..4 {
        out.a[k].extend_from_slice(a[k]);
        out.c[k].extend_from_slice(c[k]);
    }
    out.edge.extend(start as u32..(start + a[0].len()) as u32);
}

/// The six boundary coordinates of 16 points in `f32` (`[w+x, w−x, w+y, w−y, near, w−z]`).
/// For finite coordinates each is < 0 exactly when the point is outside that plane, as
/// [`super::vertex_code`]'s compares say: a rounded sum has the sign of the exact one and is
/// zero only when that is (an overflow to ±∞ keeps the sign).
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn bc_ps<const ZERO_TO_ONE: bool>([x, y, z, w]: [__m512; 4]) -> [__m512; 6] {
    let near = if ZERO_TO_ONE { z } else { _mm512_add_ps(w, z) };
    [
        _mm512_add_ps(w, x),
        _mm512_sub_ps(w, x),
        _mm512_add_ps(w, y),
        _mm512_sub_ps(w, y),
        near,
        _mm512_sub_ps(w, z),
    ]
}

/// 0, 1, …, 15.
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn iota() -> __m512i {
    _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
}

/// Lanes (of 16) whose eight coordinates are all finite: `v − v` is 0 for a finite `v` and
/// NaN for ±∞ and NaN, and a sum of them is NaN when any is.
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn finite_mask(a: [__m512; 4], c: [__m512; 4]) -> u16 {
    // Summed as a tree (depth four, not a chain of sixteen dependent operations).
    let [d0, d1, d2, d3] = a.map(|v| _mm512_sub_ps(v, v));
    let [d4, d5, d6, d7] = c.map(|v| _mm512_sub_ps(v, v));
    let sa = _mm512_add_ps(_mm512_add_ps(d0, d1), _mm512_add_ps(d2, d3));
    let sc = _mm512_add_ps(_mm512_add_ps(d4, d5), _mm512_add_ps(d6, d7));
    let z = _mm512_add_ps(sa, sc);
    _mm512_cmp_ps_mask::<_CMP_ORD_Q>(z, z)
}

/// Lanes (of 16) whose eight coordinates are all at most [`SINGLE_LIMIT`] in magnitude, and
/// so finite: the edges the per-edge clipper clips in `f32`. A float's bits with the sign
/// shifted out order as its magnitude (±∞ above every finite value, NaN above ∞), so one
/// unsigned maximum of them per lane and one compare say it.
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn ordinary_mask(a: [__m512; 4], c: [__m512; 4]) -> u16 {
    let key = |v: __m512| _mm512_slli_epi32::<1>(_mm512_castps_si512(v));
    let [k0, k1, k2, k3] = a.map(key);
    let [k4, k5, k6, k7] = c.map(key);
    let m = _mm512_max_epu32(
        _mm512_max_epu32(_mm512_max_epu32(k0, k1), _mm512_max_epu32(k2, k3)),
        _mm512_max_epu32(_mm512_max_epu32(k4, k5), _mm512_max_epu32(k6, k7)),
    );
    _mm512_cmple_epu32_mask(m, _mm512_set1_epi32((SINGLE_LIMIT.to_bits() << 1) as i32))
}

/// One block (`1..=BLOCK` edges) that the compare-only test did not accept whole, in one
/// pass of 16-edge steps; returns whether every edge was trivially accepted and drawn.
///
/// # Safety
/// AVX-512F, BMI2 and POPCNT; every vector of `out` has spare capacity for the block's
/// edges plus [`STEP`].
#[target_feature(enable = "avx512f,bmi2,popcnt")]
unsafe fn block<const ZERO_TO_ONE: bool>(
    a: &[&[f32]; 4],
    c: &[&[f32]; 4],
    start: usize,
    out: &mut SegmentsSoa,
    stats: &mut ClipStats,
) -> bool {
    let m = a[0].len();
    debug_assert!(m > 0 && m <= BLOCK && a.iter().chain(c).all(|s| s.len() == m));
    let steps = m.div_ceil(STEP);
    let [ax, ay, az, aw] = &mut out.a;
    let [cx, cy, cz, cw] = &mut out.c;
    let ends: [&mut Vec<f32>; 8] = [ax, ay, az, aw, cx, cy, cz, cw];
    let len: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7].map(|k| ends[k].len());
    let len_edge = out.edge.len();
    let mut dst = [std::ptr::null_mut::<f32>(); 8];
    for k in 0..8 {
        // SAFETY: `len[k]` is the vector's length: one past its last element.
        dst[k] = unsafe { ends[k].as_mut_ptr().add(len[k]) };
    }
    // SAFETY: as above.
    let dst_edge = unsafe { out.edge.as_mut_ptr().add(len_edge) };
    let mut kept = 0usize;
    let mut all_accepted = true;
    let mut tally = Tally::default();
    for s in 0..steps {
        let base = s * STEP;
        let live: u16 = if m - base >= STEP {
            0xFFFF
        } else {
            (1u16 << (m - base)) - 1
        };
        let mut v = [_mm512_setzero_ps(); 8];
        for k in 0..4 {
            // SAFETY: masked loads read only the live lanes, which are inside the slices.
            unsafe {
                v[k] = _mm512_maskz_loadu_ps(live, a[k].as_ptr().add(base));
                v[4 + k] = _mm512_maskz_loadu_ps(live, c[k].as_ptr().add(base));
            }
        }
        let mut clipped = [_mm512_setzero_ps(); 8];
        // SAFETY: the features are this function's.
        let (keep, drawn, cross) =
            unsafe { step::<ZERO_TO_ONE>(&v, live, &mut clipped, &mut tally) };
        all_accepted &= drawn == live;
        if keep != 0 {
            // Slot o of the output takes edge `kept_at[o]` of the step, whose ends are its
            // own (table 0, index = its place) or, for a crossing edge, its lane's clipped
            // ends (table 1, index = 16 + its rank among the step's crossing edges): one
            // compress, one expand and one permute per step, then one two-table permute
            // per coordinate.
            let kept_at = _mm512_maskz_compress_epi32(keep, iota());
            let table = _mm512_mask_expand_epi32(
                iota(),
                cross,
                _mm512_add_epi32(iota(), _mm512_set1_epi32(16)),
            );
            let from = _mm512_permutexvar_epi32(kept_at, table);
            for k in 0..8 {
                // SAFETY: the store writes 16 floats at `kept` ≤ the edges before this
                // step, inside the spare capacity.
                unsafe {
                    _mm512_storeu_ps(
                        dst[k].add(kept),
                        _mm512_permutex2var_ps(v[k], from, clipped[k]),
                    );
                }
            }
            let index = _mm512_add_epi32(kept_at, _mm512_set1_epi32((start + base) as i32));
            // SAFETY: as the stores above.
            unsafe { _mm512_storeu_si512(dst_edge.add(kept).cast(), index) };
            kept += keep.count_ones() as usize;
        }
    }
    // SAFETY: the first `kept` slots past each length were written above.
    unsafe {
        for k in 0..8 {
            ends[k].set_len(len[k] + kept);
        }
        out.edge.set_len(len_edge + kept);
    }
    stats.trivially_accepted += u64::from(tally.accepted);
    stats.trivially_rejected += u64::from(tally.rejected);
    stats.clipped += u64::from(tally.clipped);
    stats.clipped_away += u64::from(tally.away);
    stats.non_finite += u64::from(tally.non_finite);
    all_accepted
}

/// A block's counts, summed step by step.
#[derive(Default)]
struct Tally {
    accepted: u32,
    rejected: u32,
    clipped: u32,
    away: u32,
    non_finite: u32,
}

/// One step of 16 edges (`ends`: A's x, y, z, w, then C's; the lanes outside `live` zero):
/// classified and counted, its crossing edges packed into lanes and clipped there (their
/// clipped ends into `clipped`, lane for lane, in the order of the edges). Returns the masks
/// of edges drawn (trivially accepted, or clipped and visible), of those trivially accepted
/// and drawn, and of the crossing edges.
///
/// # Safety
/// AVX-512F, BMI2 and POPCNT.
#[target_feature(enable = "avx512f,bmi2,popcnt")]
#[inline]
unsafe fn step<const ZERO_TO_ONE: bool>(
    ends: &[__m512; 8],
    live: u16,
    clipped: &mut [__m512; 8],
    tally: &mut Tally,
) -> (u16, u16, u16) {
    let pa = [ends[0], ends[1], ends[2], ends[3]];
    let pc = [ends[4], ends[5], ends[6], ends[7]];
    // Outside some plane: the least of the twelve boundary coordinates is < 0. Both ends
    // outside one plane: the least over the planes of the greater of the two is.
    let (ba, bc) = (bc_ps::<ZERO_TO_ONE>(pa), bc_ps::<ZERO_TO_ONE>(pc));
    let (mut lowest_a, mut lowest_c) = (ba[0], bc[0]);
    let mut shared = _mm512_max_ps(ba[0], bc[0]);
    for i in 1..6 {
        lowest_a = _mm512_min_ps(lowest_a, ba[i]);
        lowest_c = _mm512_min_ps(lowest_c, bc[i]);
        shared = _mm512_min_ps(shared, _mm512_max_ps(ba[i], bc[i]));
    }
    let zero = _mm512_setzero_ps();
    // Nearly always every lane is ordinary (finite, nothing beyond the `f32` limit), and
    // that one test is all; otherwise the lanes are sorted into non-finite and `f64` ones.
    let ordinary = ordinary_mask(pa, pc) & live;
    let finite = if ordinary == live {
        live
    } else {
        finite_mask(pa, pc) & live
    };
    // A outside some plane (the same signs as the lanes' `f64` boundary coordinates).
    let a_out = _mm512_mask_cmp_ps_mask::<_CMP_LT_OQ>(finite, lowest_a, zero);
    let either = a_out | _mm512_mask_cmp_ps_mask::<_CMP_LT_OQ>(finite, lowest_c, zero);
    let both = _mm512_mask_cmp_ps_mask::<_CMP_LT_OQ>(finite, shared, zero);
    let in_front = _mm512_mask_cmp_ps_mask::<_CMP_GT_OQ>(
        _mm512_cmp_ps_mask::<_CMP_GT_OQ>(pa[3], zero),
        pc[3],
        zero,
    );
    // `clip_edge`'s order: non-finite, then both outside one plane, then both inside
    // (drawn only with w > 0 at both ends: else the eye, clipped away), then crossing.
    let reject = finite & both;
    let inside = finite & !either;
    let drawn = inside & in_front;
    let cross = finite & either & !both;
    tally.accepted += drawn.count_ones();
    tally.away += (inside & !in_front).count_ones();
    tally.rejected += reject.count_ones();
    tally.non_finite += (live & !finite).count_ones();
    if cross == 0 {
        return (drawn, drawn, 0);
    }
    // Pack the crossing edges into the low lanes: one compress of the lane numbers, then one
    // permute per coordinate.
    let pick = _mm512_maskz_compress_epi32(cross, iota());
    let mut packed = [_mm512_setzero_ps(); 8];
    for k in 0..8 {
        packed[k] = _mm512_permutexvar_ps(pick, ends[k]);
    }
    let n = cross.count_ones();
    // The packed lanes whose A is outside some plane: where none is, no lane enters.
    let a_out = _pext_u32(u32::from(a_out), u32::from(cross));
    // Clip them, all sixteen lanes at once in `f32`.
    let live = if n >= 16 { 0xFFFF } else { (1u16 << n) - 1 };
    let double = _pext_u32(u32::from(!ordinary), u32::from(cross)) as u16;
    let (p, q, mut visible, scalar) =
        clip_lanes::<ZERO_TO_ONE>(&packed, live, a_out as u16, double);
    clipped[..4].copy_from_slice(&p);
    clipped[4..].copy_from_slice(&q);
    if scalar != 0 {
        // SAFETY: the features are this function's.
        visible |= unsafe { scalar_lanes::<ZERO_TO_ONE>(&packed, clipped, scalar) };
    }
    let visible_count = visible.count_ones();
    tally.clipped += visible_count;
    tally.away += n - visible_count;
    // The drawn lanes, spread to their edges' places.
    let vis = _pdep_u32(u32::from(visible), u32::from(cross)) as u16;
    (drawn | vis, drawn, cross)
}

/// The lanes (bit j of `scalar`) that [`clip_lanes`] leaves to the per-edge code: clipped by
/// [`clip_crossing`] from the packed inputs, their ends put into `clipped`; returns which of
/// them are drawn.
///
/// # Safety
/// AVX-512F.
#[target_feature(enable = "avx512f")]
#[cold]
#[inline(never)]
unsafe fn scalar_lanes<const ZERO_TO_ONE: bool>(
    packed: &[__m512; 8],
    clipped: &mut [__m512; 8],
    mut scalar: u16,
) -> u16 {
    let depth = if ZERO_TO_ONE {
        DepthRange::ZeroToOne
    } else {
        DepthRange::NegOneToOne
    };
    let mut input = [[0f32; STEP]; 8];
    let mut result = [[0f32; STEP]; 8];
    for k in 0..8 {
        // SAFETY: 16 floats into arrays of 16.
        unsafe {
            _mm512_storeu_ps(input[k].as_mut_ptr(), packed[k]);
            _mm512_storeu_ps(result[k].as_mut_ptr(), clipped[k]);
        }
    }
    let mut visible = 0u16;
    while scalar != 0 {
        let j = scalar.trailing_zeros() as usize;
        scalar &= scalar - 1;
        let p = Vec4::from_array(std::array::from_fn(|k| input[k][j]));
        let q = Vec4::from_array(std::array::from_fn(|k| input[4 + k][j]));
        let (pc, qc) = (
            outcode(&boundary_coords(p, depth)),
            outcode(&boundary_coords(q, depth)),
        );
        if let ClipOutcome::Clipped(p, q) = clip_crossing(p, q, pc, qc, depth) {
            for k in 0..4 {
                result[k][j] = p[k];
                result[4 + k][j] = q[k];
            }
            visible |= 1 << j;
        }
    }
    for k in 0..8 {
        // SAFETY: 16 floats from arrays of 16.
        clipped[k] = unsafe { _mm512_loadu_ps(result[k].as_ptr()) };
    }
    visible
}

/// Sixteen packed crossing edges (`e`: A's x, y, z, w, then C's; bit l of `live`: lane l
/// holds an edge; `may_enter` zero: no lane's A is outside a plane, so none enters, and the
/// entry tests are skipped): their clipped ends; returns them with the masks of lanes drawn
/// and of lanes left to the scalar code.
///
/// Operation for operation [`clip_crossing`]'s `f32` arithmetic: the boundary coordinates
/// (`[w+x, w−x, w+y, w−y, near, w−z]`), whose signs are the outcode bits; per plane crossed,
/// `t_hit = bc_A / (bc_A − bc_C)`, raising `t_in` where A is outside and lowering `t_out` where
/// C is; the early exit as one final test (`t_in` only rises and `t_out` only falls); the new
/// ends `a + t·(c − a)`; `settle()`'s test of each new end, made conservatively in `f32`.
/// Entry parameters are > 0, so the maximum has no ties of signed zeros; an exit parameter can
/// be ±0. Such lanes go to the scalar code, as do ends that `settle()` might recompute and
/// edges with a coordinate beyond [`SINGLE_LIMIT`], which the per-edge clipper clips in `f64`.
#[target_feature(enable = "avx512f")]
#[inline]
#[allow(clippy::type_complexity)]
unsafe fn clip_lanes<const ZERO_TO_ONE: bool>(
    e: &[__m512; 8],
    live: u16,
    may_enter: u16,
    double: u16,
) -> ([__m512; 4], [__m512; 4], u16, u16) {
    let a = [e[0], e[1], e[2], e[3]];
    let c = [e[4], e[5], e[6], e[7]];
    let double = double & live;
    let a_bc = bc_ps::<ZERO_TO_ONE>(a);
    let c_bc = bc_ps::<ZERO_TO_ONE>(c);
    let zero = _mm512_setzero_ps();
    let mut t_in = zero;
    let mut t_out = _mm512_set1_ps(1.0);
    let (mut enters, mut leaves) = (0u16, 0u16);
    for i in 0..6 {
        let enter = if may_enter != 0 {
            _mm512_cmp_ps_mask::<_CMP_LT_OQ>(a_bc[i], zero) & live
        } else {
            0
        };
        let leave = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(c_bc[i], zero) & live;
        if enter | leave != 0 {
            let t_hit = _mm512_div_ps(a_bc[i], _mm512_sub_ps(a_bc[i], c_bc[i]));
            t_in = _mm512_mask_max_ps(t_in, enter, t_in, t_hit);
            t_out = _mm512_mask_min_ps(t_out, leave, t_out, t_hit);
        }
        enters |= enter;
        leaves |= leave;
    }
    let open = _mm512_cmp_ps_mask::<_CMP_LE_OQ>(t_in, t_out);
    // Where no lane moves an end (no lane enters: every A inside, the common case; or none
    // leaves), that end is the input's in every lane: no new ends to compute, nothing for
    // `settle()` to check, only its w > 0 test.
    let moved = |ends: &[__m512; 4], t: __m512, mask: u16, k: usize| {
        let step = _mm512_mul_ps(t, _mm512_sub_ps(c[k], a[k]));
        _mm512_mask_add_ps(ends[k], mask, a[k], step)
    };
    let (mut p, mut q) = (a, c);
    for k in 0..4 {
        if enters != 0 {
            p[k] = moved(&a, t_in, enters, k);
        }
        if leaves != 0 {
            q[k] = moved(&c, t_out, leaves, k);
        }
    }
    let front = |w: __m512| _mm512_cmp_ps_mask::<_CMP_GT_OQ>(w, zero);
    let (p_ok, p_front) = if enters != 0 {
        settles_as_is::<ZERO_TO_ONE>(p)
    } else {
        (0xFFFF, front(a[3]))
    };
    let (q_ok, q_front) = if leaves != 0 {
        settles_as_is::<ZERO_TO_ONE>(q)
    } else {
        (0xFFFF, front(c[3]))
    };
    let zero_exit = _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(t_out, zero);
    let scalar = (leaves & zero_exit) | (enters & !p_ok) | (leaves & !q_ok);
    let open = open & live;
    // An edge for `f64` goes to the scalar code whatever its `f32` lanes say.
    (
        p,
        q,
        open & !scalar & !double & p_front & q_front,
        (open & scalar) | double,
    )
}

/// `settle()`'s test in `f32`, conservatively: lanes where it certainly returns the computed
/// end as it is (w > 0 and every boundary coordinate ≥ −`SETTLE_REL`·max |pᵢ| in `f64`, or
/// w ≤ 0), and the lanes where w > 0. Where max |pᵢ| ≥ 2⁻¹⁰⁰ the bound −`SETTLE_FLOOR`·max |pᵢ|
/// is a normal `f32` (no underflow: its rounding is relative, 2⁻²⁴), and each `f32` boundary
/// coordinate is within 2⁻²⁴ of twice max |pᵢ| of the `f64` one, or within 2⁻¹⁵⁰ where it is
/// subnormal; so a bound 2⁻⁸·`SETTLE_REL` tighter (≈ 4·10⁻⁶ of max |pᵢ|, against at most
/// 1.2·10⁻⁷ of error) never passes an end that `settle()` would recompute. The few ends
/// between the two bounds, and ends smaller than 2⁻¹⁰⁰ (where a subnormal bound would round
/// by more than the margin), go to the scalar code, which decides exactly.
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn settles_as_is<const ZERO_TO_ONE: bool>(p: [__m512; 4]) -> (u16, u16) {
    let abs = p.map(|v| _mm512_abs_ps(v));
    let [_, _, z, w] = p;
    let m = _mm512_max_ps(_mm512_max_ps(abs[0], abs[1]), _mm512_max_ps(abs[2], abs[3]));
    let floor = _mm512_mul_ps(_mm512_set1_ps(SETTLE_FLOOR), m);
    // The least boundary coordinate. min(w + x, w − x) is w − |x| rounded (rounding is
    // monotonic), so four subtractions and three minima give what the six do.
    let near = if ZERO_TO_ONE { z } else { _mm512_add_ps(w, z) };
    let least = _mm512_min_ps(
        _mm512_min_ps(_mm512_sub_ps(w, abs[0]), _mm512_sub_ps(w, abs[1])),
        _mm512_min_ps(near, _mm512_sub_ps(w, z)),
    );
    let within = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(least, floor)
        & _mm512_cmp_ps_mask::<_CMP_GE_OQ>(m, _mm512_set1_ps(SETTLE_SMALLEST));
    let front = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(w, _mm512_setzero_ps());
    (within | !front, front)
}

/// −`SETTLE_REL`·(1 − 2⁻⁸) in `f32`: [`settles_as_is`]'s bound.
#[allow(clippy::cast_possible_truncation)]
const SETTLE_FLOOR: f32 = (-SETTLE_REL * (1.0 - 1.0 / 256.0)) as f32;

/// 2⁻¹⁰⁰: the least max |pᵢ| whose end [`settles_as_is`] decides.
const SETTLE_SMALLEST: f32 = 1.0 / (1u128 << 100) as f32;
