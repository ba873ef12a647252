//! Sutherland-Hodgman (1974; seed `clipping-sutherland-hodgman-liang-barsky-bresenham.txt`):
//! clip a polygon against each boundary of a convex region in turn, rewriting its vertex list
//! one edge s→p at a time: in→in emits p, in→out emits the crossing, out→in emits the crossing
//! and p, out→out emits nothing. Each stage needs only the current edge and the last output,
//! which is why it suits hardware (a pipeline of one stage per plane).
//!
//! * [`clip_polygon_2d`]: a polygon (filled face) against the 2D window;
//! * [`clip_polygon_homogeneous`]: a polygon in clip space against the view volume and extra
//!   planes, before the divide, for filled faces;
//! * [`clip_edge_2d`], [`clip_edge_homogeneous`]: a *line* as the degenerate polygon A, C.
//!
//! The caller gives the output and scratch arrays (no allocation); a stage can at most double
//! the vertex count, and [`PolygonError::Capacity`] says when the arrays are too small.
//!
//! **Crossings are computed from the inside vertex toward the outside one**, whichever way
//! the edge runs, so the two traversals of a shared edge (and the two edges of the 2-vertex
//! polygon A, C) give bit-identical points. That keeps the degenerate polygon of a line at
//! two distinct vertices after every stage (equal neighbours are merged), and its segment is
//! the vertex pair with the smallest and largest edge parameter t, carried as an attribute
//! and interpolated like a colour would be.
//!
//! Clip-space polygons: after the six planes every vertex has w ≥ 0, and w = 0 only at the
//! eye (0, 0, 0, 0), which a polygon reaches only if its plane contains the eye (it then
//! projects to a line); such vertices are dropped so that the divide is always defined.

use glam::{DVec2, DVec4, Vec2, Vec4};

use super::{settle, ClipOutcome, ClipOutcome2, ClipVolume, Window2, EDGE_COUNT};

/// Why a polygon could not be clipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PolygonError {
    /// A vertex has a NaN or infinite coordinate.
    #[error("a polygon vertex is not finite")]
    NonFinite,
    /// The output or scratch array is shorter than a stage's output (this many vertices).
    #[error("the clipped polygon needs room for {0} vertices")]
    Capacity(usize),
}

/// One stage: `input` clipped against the half-space `bc(v) ≥ 0` into `out`; returns the
/// vertex count.
fn stage<V: Copy>(
    input: &[V],
    out: &mut [V],
    bc: impl Fn(&V) -> f64,
    mut lerp: impl FnMut(&V, &V, f64) -> V,
) -> Result<usize, PolygonError> {
    let Some(&last) = input.last() else {
        return Ok(0);
    };
    let mut k = 0;
    let mut emit = |v: V| -> Result<(), PolygonError> {
        let slot = out
            .get_mut(k)
            .ok_or(PolygonError::Capacity(2 * input.len()))?;
        *slot = v;
        k += 1;
        Ok(())
    };
    let (mut s, mut s_bc) = (last, bc(&last));
    for &p in input {
        let p_bc = bc(&p);
        let (p_in, s_in) = (p_bc >= 0.0, s_bc >= 0.0);
        if p_in != s_in {
            // From the inside vertex toward the outside one: t ∈ [0, 1), no division by zero
            // (the two values have opposite signs).
            let (i, o, bi, bo) = if p_in {
                (p, s, p_bc, s_bc)
            } else {
                (s, p, s_bc, p_bc)
            };
            let t = bi / (bi - bo);
            debug_assert!((0.0..=1.0).contains(&t), "crossing at t = {t}");
            emit(lerp(&i, &o, t))?;
        }
        if p_in {
            emit(p)?;
        }
        (s, s_bc) = (p, p_bc);
    }
    Ok(k)
}

/// Run `planes` stages ping-ponging between `out` and `scratch`; the result ends in `out`.
fn all_stages<V: Copy>(
    polygon: &[V],
    planes: usize,
    out: &mut [V],
    scratch: &mut [V],
    bc: impl Fn(usize, &V) -> f64,
    lerp: impl Fn(usize, &V, &V, f64) -> V,
) -> Result<usize, PolygonError> {
    let mut len = stage(polygon, out, |v| bc(0, v), |a, b, t| lerp(0, a, b, t))?;
    for k in 1..planes {
        len = if k % 2 == 1 {
            stage(
                &out[..len],
                scratch,
                |v| bc(k, v),
                |a, b, t| lerp(k, a, b, t),
            )?
        } else {
            stage(
                &scratch[..len],
                out,
                |v| bc(k, v),
                |a, b, t| lerp(k, a, b, t),
            )?
        };
    }
    if planes.is_multiple_of(2) {
        out[..len].copy_from_slice(&scratch[..len]);
    }
    Ok(len)
}

/// The crossing on window edge `k`, its coordinate set exactly on the boundary.
fn lerp_2d(window: &Window2, k: usize, a: DVec2, b: DVec2, t: f64) -> DVec2 {
    let mut p = a + t * (b - a);
    match k {
        0 => p.x = f64::from(window.xmin()),
        1 => p.x = f64::from(window.xmax()),
        2 => p.y = f64::from(window.ymin()),
        _ => p.y = f64::from(window.ymax()),
    }
    p
}

/// Clip a polygon (vertices in order, either winding) against the window into `out`, using
/// `scratch` between stages; returns the number of vertices written (0: nothing visible).
/// The output can be longer than the input: give each array 2·n + 4 entries to be safe.
///
/// # Errors
/// [`PolygonError::NonFinite`] for a NaN or infinite vertex, [`PolygonError::Capacity`] when
/// an array is too short.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::{sutherland_hodgman, Window2};
/// // A triangle poking out of the right side of the unit window: the tip is cut off.
/// let w = Window2::new(0.0, 0.0, 1.0, 1.0).unwrap();
/// let tri = [Vec2::new(0.5, 0.25), Vec2::new(1.5, 0.5), Vec2::new(0.5, 0.75)];
/// let (mut out, mut scratch) = ([Vec2::ZERO; 10], [Vec2::ZERO; 10]);
/// let n = sutherland_hodgman::clip_polygon_2d(&tri, &w, &mut out, &mut scratch).unwrap();
/// assert_eq!(&out[..n], &[
///     Vec2::new(0.5, 0.25), Vec2::new(1.0, 0.375), Vec2::new(1.0, 0.625), Vec2::new(0.5, 0.75),
/// ]);
/// ```
pub fn clip_polygon_2d(
    polygon: &[Vec2],
    window: &Window2,
    out: &mut [Vec2],
    scratch: &mut [Vec2],
) -> Result<usize, PolygonError> {
    if !polygon.iter().all(|v| v.is_finite()) {
        return Err(PolygonError::NonFinite);
    }
    let len = all_stages(
        polygon,
        EDGE_COUNT,
        out,
        scratch,
        |k, v| window.boundary_coords(v.as_dvec2())[k],
        |k, a, b, t| lerp_2d(window, k, a.as_dvec2(), b.as_dvec2(), t).as_vec2(),
    )?;
    for v in &mut out[..len] {
        *v = window.clamp(*v);
    }
    Ok(len)
}

/// Clip a polygon in clip space (before the divide) against the view volume and extra
/// planes; as [`clip_polygon_2d`], with 2·n + 2·planes entries to be safe. Vertices at the
/// eye (w ≤ 0 after clipping) are dropped (see the module docs).
///
/// # Errors
/// As [`clip_polygon_2d`].
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{sutherland_hodgman, ClipVolume, DepthRange};
/// // A triangle reaching through the near plane is cut at z = 0.
/// let tri = [Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(0.5, 0.0, -0.5, 1.0), Vec4::new(0.0, 0.5, -0.5, 1.0)];
/// let (mut out, mut scratch) = ([Vec4::ZERO; 18], [Vec4::ZERO; 18]);
/// let v = ClipVolume::new(DepthRange::ZeroToOne);
/// let n = sutherland_hodgman::clip_polygon_homogeneous(&tri, &v, &mut out, &mut scratch).unwrap();
/// assert_eq!(n, 3); // the inside corner and the two crossings of z = 0
/// assert!(out[..n].iter().all(|p| p.z >= 0.0 && p.w > 0.0));
/// ```
pub fn clip_polygon_homogeneous(
    polygon: &[Vec4],
    volume: &ClipVolume,
    out: &mut [Vec4],
    scratch: &mut [Vec4],
) -> Result<usize, PolygonError> {
    if !polygon.iter().all(|v| v.is_finite()) {
        return Err(PolygonError::NonFinite);
    }
    let len = all_stages(
        polygon,
        volume.plane_count(),
        out,
        scratch,
        |k, v| volume.boundary_coord(k, v.as_dvec4()),
        |_, a, b, t| {
            let (a, b) = (a.as_dvec4(), b.as_dvec4());
            (a + t * (b - a)).as_vec4()
        },
    )?;
    let mut kept = 0;
    for i in 0..len {
        if out[i].w > 0.0 {
            out[kept] = out[i];
            kept += 1;
        }
    }
    Ok(kept)
}

/// A vertex of the degenerate polygon of a line: a point and its edge parameter t.
type Tagged<P> = (P, f64);

/// What the 2-vertex polygon A, C became.
enum TwoGon<P> {
    /// Empty: `true` if a crossing was computed on the way.
    Empty(bool),
    /// Vertices with the smallest and largest t; `true` if a crossing was computed.
    Segment(Tagged<P>, Tagged<P>, bool),
}

/// Clip the polygon A, C stage by stage, merging equal neighbours, in fixed arrays of 4.
fn two_gon<P: Copy + PartialEq>(
    a: P,
    c: P,
    planes: usize,
    bc: impl Fn(usize, &P) -> f64,
    lerp: impl Fn(usize, &P, &P, f64) -> P,
) -> TwoGon<P> {
    let mut buf = [(a, 0.0), (c, 1.0), (a, 0.0), (a, 0.0)];
    let mut next = buf;
    let mut len = if a == c { 1 } else { 2 };
    let mut crossed = false;
    for k in 0..planes {
        let n = stage(
            &buf[..len],
            &mut next,
            |v| bc(k, &v.0),
            |i, o, t| {
                crossed = true;
                (lerp(k, &i.0, &o.0, t), i.1 + t * (o.1 - i.1))
            },
        );
        // Two vertices give at most four; the arrays hold four.
        let n = n.unwrap_or(0);
        // Merge equal neighbours (cyclically): the shared crossings are bit-identical.
        len = 0;
        for &v in &next[..n] {
            if len == 0 || v != buf[len - 1] {
                buf[len] = v;
                len += 1;
            }
        }
        while len > 1 && buf[len - 1] == buf[0] {
            len -= 1;
        }
        debug_assert!(len <= 2, "a clipped line has two ends, found {len}");
        if len == 0 {
            return TwoGon::Empty(crossed);
        }
    }
    // Smallest and largest t. A crossing interpolated from a vertex at t = 1 (or 0) can
    // round to exactly 1 (or 0) although it lies strictly inside the edge: on a tie the
    // input's own vertex is the end.
    let original = |v: &Tagged<P>| *v == (a, 0.0) || *v == (c, 1.0);
    let (lo, hi) = buf[..len].iter().fold((buf[0], buf[0]), |(lo, hi), &v| {
        (
            if v.1 < lo.1 || (v.1 == lo.1 && original(&v)) {
                v
            } else {
                lo
            },
            if v.1 > hi.1 || (v.1 == hi.1 && original(&v)) {
                v
            } else {
                hi
            },
        )
    });
    TwoGon::Segment(lo, hi, crossed)
}

/// Clip the segment `a`→`c` against the window as the 2-vertex polygon A, C.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::{sutherland_hodgman, ClipOutcome, Window2};
/// let w = Window2::new(2.0, 2.0, 4.0, 4.0).unwrap();
/// let out = sutherland_hodgman::clip_edge_2d(Vec2::new(1.0, 3.0), Vec2::new(5.0, 2.0), &w);
/// assert_eq!(out, ClipOutcome::Clipped(Vec2::new(2.0, 2.75), Vec2::new(4.0, 2.25)));
/// ```
pub fn clip_edge_2d(a: Vec2, c: Vec2, window: &Window2) -> ClipOutcome2 {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    match two_gon(
        a.as_dvec2(),
        c.as_dvec2(),
        EDGE_COUNT,
        |k, p| window.boundary_coords(*p)[k],
        |k, p, q, t| lerp_2d(window, k, *p, *q, t),
    ) {
        TwoGon::Empty(false) => ClipOutcome::Rejected,
        TwoGon::Empty(true) => ClipOutcome::ClippedAway,
        TwoGon::Segment(..) if window.outcode(a) | window.outcode(c) == 0 => {
            ClipOutcome::Accepted(a, c)
        }
        TwoGon::Segment(lo, hi, _) => ClipOutcome::Clipped(
            if lo == (a.as_dvec2(), 0.0) {
                a
            } else {
                window.clamp(lo.0.as_vec2())
            },
            if hi == (c.as_dvec2(), 1.0) {
                c
            } else {
                window.clamp(hi.0.as_vec2())
            },
        ),
    }
}

/// Clip the homogeneous edge `a`→`c` against `volume` as the 2-vertex polygon A, C.
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{sutherland_hodgman, ClipOutcome, ClipVolume, DepthRange};
/// let v = ClipVolume::new(DepthRange::ZeroToOne);
/// let a = Vec4::new(-3.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let out = sutherland_hodgman::clip_edge_homogeneous(a, c, &v);
/// assert_eq!(out, ClipOutcome::Clipped(Vec4::new(-1.0, 0.0, 0.5, 1.0), c));
/// ```
pub fn clip_edge_homogeneous(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let gon = two_gon(
        a.as_dvec4(),
        c.as_dvec4(),
        volume.plane_count(),
        |k, p: &DVec4| volume.boundary_coord(k, *p),
        |_, p, q, t| *p + t * (*q - *p),
    );
    let (lo, hi, crossed) = match gon {
        TwoGon::Empty(false) => return ClipOutcome::Rejected,
        TwoGon::Empty(true) => return ClipOutcome::ClippedAway,
        TwoGon::Segment(lo, hi, crossed) => (lo, hi, crossed),
    };
    // The guard against cancellation, recomputing from t (carried as an attribute) if need be.
    let (a64, c64) = (a.as_dvec4(), c.as_dvec4());
    let end = |v: (DVec4, f64)| settle(v.0.as_vec4(), a64, c64, v.1, volume.depth);
    // An end is the input's only if it is the input's vertex: t itself, interpolated from the
    // inside vertex, can round to 0 or 1 at a crossing near an enormous far end.
    let a2 = if lo == (a64, 0.0) { a } else { end(lo) };
    let c2 = if hi == (c64, 1.0) { c } else { end(hi) };
    if !(a2.w > 0.0 && c2.w > 0.0) {
        ClipOutcome::ClippedAway
    } else if !crossed {
        ClipOutcome::Accepted(a, c)
    } else {
        ClipOutcome::Clipped(a2, c2)
    }
}
