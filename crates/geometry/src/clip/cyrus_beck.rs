//! Cyrus-Beck (1978; seed `line-clipping-cs-cyrus-beck-nln.txt`): clip a line against any
//! convex region given as half-spaces with inward normals. For the edge `P(t) = P₀ + t·D` and
//! a boundary with normal `n` through `Q`: `d₁ = D·n`, `d_q = (Q − P₀)·n`, `t = d_q/d₁`;
//! `d₁ > 0` (out to in) raises `t₀`, `d₁ < 0` (in to out) lowers `t₁`, and `d₁ = 0` with
//! `(P₀ − Q)·n < 0` means parallel and outside. As in the seed, every boundary is visited
//! (no early exit) and the points are computed once at the end, if `t₀ ≤ t₁`.
//!
//! One routine serves every dimension, over homogeneous half-spaces `π·P ≥ 0`:
//!
//! * [`clip_homogeneous`]: the clip volume as a convex polyhedron of clip space (its six
//!   planes, [`super::view_plane`], and any extra ones);
//! * [`clip_polyhedron`]: a convex polyhedron of 3D given by planes `(n, d)`, inside where
//!   `n·p + d ≥ 0` (a point is `(p, 1)`);
//! * [`clip_polygon`]: a convex polygon of 2D ([`ConvexPolygon`], either winding).
//!
//! Edges wholly inside leave `[t₀, t₁] = [0, 1]` and come back unchanged; there is no
//! outcode test, so its tallies count nearly every drop as clipped away.
//!
//! `d₁ = D·n` is computed as `n·P₁ − n·P₀`, the difference of the boundary values at the two
//! ends, not as the dot product of `n` with the rounded `D`: the two are equal in exact
//! arithmetic, but only the difference guarantees `t = −v₀/d₁ ≥ 1` (≤ 0) for an end that is
//! inside the boundary by the exact test, so an inside end is kept bit for bit (`D·n` rounded
//! `P₀ + D` and once moved an inside end on a plane by 3·10⁻⁷ of its size; the fuzzer found
//! it).

use glam::{DVec2, Vec2, Vec3, Vec4};

use super::{settle, ClipOutcome, ClipOutcome2, ClipVolume};

/// The Cyrus-Beck interval of `P₀ + t·D` against half-spaces given by their values at `P₀`
/// and at `P₁` (the rate along `D` is their difference, see the module docs):
/// `Ok((t₀, t₁))` with `t₀ ≤ t₁`, or the drop.
fn interval<P>(boundaries: impl Iterator<Item = (f64, f64)>) -> Result<(f64, f64), ClipOutcome<P>> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let mut divided = false;
    for (value, value1) in boundaries {
        let d1 = value1 - value;
        if d1 > 0.0 {
            t0 = t0.max(-value / d1);
            divided = true;
        } else if d1 < 0.0 {
            t1 = t1.min(-value / d1);
            divided = true;
        } else if value < 0.0 {
            return Err(if divided {
                ClipOutcome::ClippedAway
            } else {
                ClipOutcome::Rejected
            });
        }
    }
    if t0 <= t1 {
        Ok((t0, t1))
    } else {
        Err(ClipOutcome::ClippedAway)
    }
}

/// Clip the homogeneous edge `a`→`c` against the clip volume as a convex polyhedron of
/// half-spaces `π_i·P ≥ 0` (the six planes, then the extra ones).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{cyrus_beck, ClipOutcome, ClipVolume, DepthRange};
/// let v = ClipVolume::new(DepthRange::ZeroToOne);
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(0.0, 4.0, 0.5, 1.0);
/// let out = cyrus_beck::clip_homogeneous(a, c, &v);
/// assert_eq!(out, ClipOutcome::Clipped(a, Vec4::new(0.0, 1.0, 0.5, 1.0)));
/// ```
pub fn clip_homogeneous(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.as_dvec4(), c.as_dvec4());
    let d = p1 - p0;
    let boundaries = (0..volume.plane_count())
        .map(|i| (volume.boundary_coord(i, p0), volume.boundary_coord(i, p1)));
    let (t0, t1) = match interval(boundaries) {
        Err(out) => return out,
        Ok(t) => t,
    };
    let at = |t: f64| settle((p0 + t * d).as_vec4(), p0, p1, t, volume.depth);
    // At t = 0 or 1 the end is the input's, guarded too (see liang_barsky).
    let a2 = if t0 == 0.0 {
        settle(a, p0, p1, 0.0, volume.depth)
    } else {
        at(t0)
    };
    let c2 = if t1 == 1.0 {
        settle(c, p0, p1, 1.0, volume.depth)
    } else {
        at(t1)
    };
    // t rounds to 0 or 1 for an end outside by less than its last bit: only the exact test
    // says accepted (the edge is then returned as clipped, unchanged).
    let inside =
        |p: glam::DVec4| (0..volume.plane_count()).all(|i| volume.boundary_coord(i, p) >= 0.0);
    if !(a2.w > 0.0 && c2.w > 0.0) {
        ClipOutcome::ClippedAway
    } else if t0 == 0.0 && t1 == 1.0 && inside(p0) && inside(p1) {
        ClipOutcome::Accepted(a, c)
    } else {
        ClipOutcome::Clipped(a2, c2)
    }
}

/// Clip the 3D segment `a`→`c` against the convex polyhedron `∩ {p : n·p + d ≥ 0}` of the
/// planes `(n.x, n.y, n.z, d)` (any number; none means all of space).
///
/// ```
/// use glam::{Vec3, Vec4};
/// use wireflight_geometry::clip::{cyrus_beck, ClipOutcome};
/// // The slab 0 ≤ x ≤ 1: planes x ≥ 0 and −x + 1 ≥ 0.
/// let slab = [Vec4::new(1.0, 0.0, 0.0, 0.0), Vec4::new(-1.0, 0.0, 0.0, 1.0)];
/// let out = cyrus_beck::clip_polyhedron(Vec3::new(-1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 0.0), &slab);
/// assert_eq!(out, ClipOutcome::Clipped(Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0)));
/// ```
pub fn clip_polyhedron(a: Vec3, c: Vec3, planes: &[Vec4]) -> ClipOutcome<Vec3> {
    if !(a.is_finite() && c.is_finite() && planes.iter().all(|p| p.is_finite())) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.extend(1.0).as_dvec4(), c.extend(1.0).as_dvec4());
    let d = p1 - p0;
    let boundaries = planes.iter().map(|pl| {
        let n = pl.as_dvec4();
        (n.dot(p0), n.dot(p1))
    });
    let inside = |p: glam::DVec4| planes.iter().all(|pl| pl.as_dvec4().dot(p) >= 0.0);
    match interval(boundaries) {
        Err(out) => out,
        Ok((t0, t1)) if t0 == 0.0 && t1 == 1.0 && inside(p0) && inside(p1) => {
            ClipOutcome::Accepted(a, c)
        }
        Ok((t0, t1)) => ClipOutcome::Clipped(
            if t0 == 0.0 {
                a
            } else {
                (p0 + t0 * d).truncate().as_vec3()
            },
            if t1 == 1.0 {
                c
            } else {
                (p0 + t1 * d).truncate().as_vec3()
            },
        ),
    }
}

/// A convex polygon of 2D to clip against: at least three finite vertices in either winding,
/// every turn the same way (no three consecutive vertices collinear). Borrows the vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexPolygon<'v> {
    vertices: &'v [Vec2],
    /// +1 for counter-clockwise, −1 for clockwise.
    winding: f64,
}

impl<'v> ConvexPolygon<'v> {
    /// The polygon through `vertices`, or `None` unless it is strictly convex (see the type).
    ///
    /// ```
    /// use glam::Vec2;
    /// use wireflight_geometry::clip::cyrus_beck::ConvexPolygon;
    /// let square = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    /// assert!(ConvexPolygon::new(&square).is_some());
    /// let bow_tie = [Vec2::ZERO, Vec2::ONE, Vec2::X, Vec2::Y];
    /// assert!(ConvexPolygon::new(&bow_tie).is_none());
    /// ```
    pub fn new(vertices: &'v [Vec2]) -> Option<Self> {
        let n = vertices.len();
        if n < 3 || !vertices.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mut sign = 0.0f64;
        let mut turning = 0.0f64;
        for i in 0..n {
            let (p, q, r) = (
                vertices[i].as_dvec2(),
                vertices[(i + 1) % n].as_dvec2(),
                vertices[(i + 2) % n].as_dvec2(),
            );
            let cross = (q - p).perp_dot(r - q);
            if cross == 0.0 || (sign != 0.0 && cross.signum() != sign) {
                return None;
            }
            sign = cross.signum();
            // The exterior angle; a convex polygon turns once in total (a star turns more).
            turning += (q - p).angle_to(r - q);
        }
        (turning.abs() < 1.5 * std::f64::consts::TAU).then_some(Self {
            vertices,
            winding: sign,
        })
    }

    /// The vertices, as given.
    pub fn vertices(&self) -> &'v [Vec2] {
        self.vertices
    }

    /// Edge i as (a point on it, inward normal), in `f64`.
    fn edge(&self, i: usize) -> (DVec2, DVec2) {
        let n = self.vertices.len();
        let p = self.vertices[i].as_dvec2();
        let q = self.vertices[(i + 1) % n].as_dvec2();
        // Left of the direction is inside for a counter-clockwise polygon.
        (p, self.winding * (q - p).perp())
    }
}

/// Clip the segment `a`→`c` against a convex polygon.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::cyrus_beck::{clip_polygon, ConvexPolygon};
/// use wireflight_geometry::clip::ClipOutcome;
/// let triangle = [Vec2::ZERO, Vec2::new(4.0, 0.0), Vec2::new(0.0, 4.0)];
/// let poly = ConvexPolygon::new(&triangle).unwrap();
/// let out = clip_polygon(Vec2::new(-1.0, 1.0), Vec2::new(5.0, 1.0), &poly);
/// assert_eq!(out, ClipOutcome::Clipped(Vec2::new(0.0, 1.0), Vec2::new(3.0, 1.0)));
/// ```
pub fn clip_polygon(a: Vec2, c: Vec2, polygon: &ConvexPolygon<'_>) -> ClipOutcome2 {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.as_dvec2(), c.as_dvec2());
    let d = p1 - p0;
    let boundaries = (0..polygon.vertices.len()).map(|i| {
        let (q, n) = polygon.edge(i);
        // The seed's d_q = (Q − P₀)·n, t = d_q/d₁: our value is (P₀ − Q)·n = −d_q.
        ((p0 - q).dot(n), (p1 - q).dot(n))
    });
    let inside = |p: DVec2| {
        (0..polygon.vertices.len()).all(|i| {
            let (q, n) = polygon.edge(i);
            (p - q).dot(n) >= 0.0
        })
    };
    match interval(boundaries) {
        Err(out) => out,
        Ok((t0, t1)) if t0 == 0.0 && t1 == 1.0 && inside(p0) && inside(p1) => {
            ClipOutcome::Accepted(a, c)
        }
        Ok((t0, t1)) => ClipOutcome::Clipped(
            if t0 == 0.0 {
                a
            } else {
                (p0 + t0 * d).as_vec2()
            },
            if t1 == 1.0 {
                c
            } else {
                (p0 + t1 * d).as_vec2()
            },
        ),
    }
}
