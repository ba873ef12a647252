//! Clipping edges against the canonical view volume in homogeneous clip space, and the
//! clipping lab: every line clipper of the seed lectures, one file each, over shared types.
//!
//! Clip space is what the projection matrix produces: a point `(x, y, z, w)` is visible when
//!
//! * `−w ≤ x ≤ w` and `−w ≤ y ≤ w`, and
//! * `0 ≤ z ≤ w` ([`DepthRange::ZeroToOne`], wgpu / Direct3D / Vulkan: the default), or
//!   `−w ≤ z ≤ w` ([`DepthRange::NegOneToOne`], OpenGL, the seed lecture's CVV).
//!
//! Clipping happens **before** the perspective divide: that is what keeps an edge that passes
//! behind the eye (one endpoint with w < 0) from being drawn "wrapped around" through infinity.
//! Every inequality above implies w ≥ 0, so points behind the eye are outside by construction.
//!
//! What every clipper shares lives here: the depth convention, the boundary coordinates and
//! outcodes, the outcome of clipping one edge ([`ClipOutcome`], in clip space or in 2D) and
//! the tally of a batch ([`ClipStats`]); the 2D window ([`Window2`]) and the volume with extra
//! planes ([`ClipVolume`]). Each algorithm is one file:
//!
//! | file | algorithm | 2D window | homogeneous (draws) | other |
//! |---|---|---|---|---|
//! | [`blinn`] | Blinn: BCs, outcodes, `[t_in, t_out]` | — | yes | [`batch`]: SoA fast path |
//! | [`cohen_sutherland`] | outcodes, iterative chopping | yes | yes | |
//! | [`liang_barsky`] | parametric `p_k t ≤ q_k` | yes | yes | 3D box |
//! | [`cyrus_beck`] | parametric, any convex region | any convex polygon | yes | convex polyhedron |
//! | [`nicholl_lee_nicholl`] | regions from rays through the corners | yes | — | |
//! | [`sutherland_hodgman`] | polygon against one plane at a time | polygons, lines | polygons, lines | |
//! | [`weiler_atherton`] | polygon against polygon, both may be concave | polygons | — | pieces with holes |
//!
//! [`Clipper`] names those that can draw a frame; the projector
//! ([`crate::pipeline::EdgeProjector`]) carries the choice. [`cull`] has the "other ways to
//! reject": bounding spheres against the frustum and back faces.
//!
//! # The shared contract
//!
//! Every clipper: never panics, never allocates, returns [`ClipOutcome::NonFinite`] for a NaN
//! or infinite coordinate, counts a point on a boundary as inside, returns an edge whose
//! endpoints are both inside *unchanged* ([`ClipOutcome::Accepted`]), keeps the direction
//! A→C, computes crossings in `f64` from the original `f32` input, and (homogeneous) returns
//! only segments with w > 0 at both ends. Drops are [`ClipOutcome::Rejected`] when no
//! intersection was computed (trivial reject) and [`ClipOutcome::ClippedAway`] otherwise, so
//! the tallies show what each algorithm spent. Pure math: no I/O.

pub mod batch;
pub mod blinn;
pub mod cohen_sutherland;
pub mod cull;
pub mod cyrus_beck;
pub mod liang_barsky;
pub mod nicholl_lee_nicholl;
pub mod sutherland_hodgman;
mod volume;
pub mod weiler_atherton;
mod window;

pub use blinn::clip_edge;
pub use volume::{view_plane, ClipVolume, PlaneError, PlaneSet, MAX_USER_PLANES};
pub use window::{Window2, EDGE_COUNT};

use std::fmt;
use std::ops::{Add, Sub};
use std::str::FromStr;

use glam::{Vec2, Vec4};

/// Depth range of the clip volume: which z values, relative to w, are visible.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DepthRange {
    /// `0 ≤ z ≤ w`: wgpu, Vulkan, Direct3D, Metal. The project's default.
    #[default]
    ZeroToOne,
    /// `−w ≤ z ≤ w`: OpenGL and the seed lecture's canonical view volume.
    NegOneToOne,
}

/// Number of clip planes (and boundary coordinates, and outcode bits).
pub const PLANE_COUNT: usize = 6;

/// Outcode bit per plane, in the seed's order: BC0 x=−1, BC1 x=1, BC2 y=−1, BC3 y=1,
/// BC4 near (z=−1 or z=0), BC5 far (z=1).
pub mod plane {
    /// Outside x = −w (left).
    pub const LEFT: u8 = 1 << 0;
    /// Outside x = +w (right).
    pub const RIGHT: u8 = 1 << 1;
    /// Outside y = −w (bottom).
    pub const BOTTOM: u8 = 1 << 2;
    /// Outside y = +w (top).
    pub const TOP: u8 = 1 << 3;
    /// Outside the near plane (z = −w or z = 0).
    pub const NEAR: u8 = 1 << 4;
    /// Outside the far plane (z = w).
    pub const FAR: u8 = 1 << 5;
}

/// The six boundary coordinates of a homogeneous point: each is ≥ 0 exactly when the point is
/// on the visible side of its plane, and is linear in the point (so linear along an edge).
///
/// Order as in the seed: `[w+x, w−x, w+y, w−y, near, w−z]` with near = `w+z`
/// ([`DepthRange::NegOneToOne`]) or `z` ([`DepthRange::ZeroToOne`]).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{boundary_coords, DepthRange};
/// // The seed's worked example.
/// let bc = boundary_coords(Vec4::new(5.0, 2.0, 7.0, 10.0), DepthRange::NegOneToOne);
/// assert_eq!(bc, [15.0, 5.0, 12.0, 8.0, 17.0, 3.0]);
/// ```
#[inline]
pub fn boundary_coords(p: Vec4, depth: DepthRange) -> [f32; PLANE_COUNT] {
    boundary_coords_of(p.to_array(), depth)
}

/// [`boundary_coords`] of `[x, y, z, w]` in any number type (the clippers compute crossing
/// parameters in `f64`).
#[inline]
pub fn boundary_coords_of<T>([x, y, z, w]: [T; 4], depth: DepthRange) -> [T; PLANE_COUNT]
where
    T: Copy + Add<Output = T> + Sub<Output = T>,
{
    let near = match depth {
        DepthRange::ZeroToOne => z,
        DepthRange::NegOneToOne => w + z,
    };
    [w + x, w - x, w + y, w - y, near, w - z]
}

/// 6-bit outcode of boundary coordinates: bit i set when BC_i < 0 (outside plane i).
/// A point on a plane (BC = 0) counts as inside.
#[inline]
pub fn outcode(bc: &[f32; PLANE_COUNT]) -> u8 {
    let mut code = 0u8;
    for (i, &b) in bc.iter().enumerate() {
        code |= u8::from(b < 0.0) << i;
    }
    code
}

/// Whether a homogeneous point lies in the view volume, with a relative tolerance:
/// every boundary coordinate ≥ −`rel_tol`·max(|x|,|y|,|z|,|w|).
pub fn is_inside(p: Vec4, depth: DepthRange, rel_tol: f32) -> bool {
    let slack = rel_tol * p.abs().max_element();
    boundary_coords(p, depth).iter().all(|&b| b >= -slack)
}

/// Largest violation of a plane, relative to the point's own largest coordinate, that a
/// computed endpoint may show before [`settle`] recomputes it (0.1%: far beyond rounding
/// in any ordinary edge, so it changes nothing there).
pub const SETTLE_REL: f64 = 1e-3;

/// `a + t·(c − a)` computed from the nearer end, so that it is exact at t = 0 and t = 1 even
/// when one end is enormous next to the other.
#[inline]
pub fn lerp_from_nearer(a: glam::DVec4, c: glam::DVec4, t: f64) -> glam::DVec4 {
    if t <= 0.5 {
        a + t * (c - a)
    } else {
        c + (1.0 - t) * (a - c)
    }
}

/// The guard on a computed endpoint `p` (at parameter `t` of `a`→`c`): returned unchanged
/// when it is inside the six view planes to within [`SETTLE_REL`] of its own size, which is
/// every ordinary case. Otherwise rounding has ruined it: when the far end is enormous (say
/// w = −1e37 against an inside point with w = 1.5), `a + t·(c − a)` cancels to a point whose
/// own coordinates are garbage, e.g. x = −1 with w = 5e−40, which would divide to −∞ while
/// being well inside the tolerance *of the edge*. It is then recomputed from the nearer end
/// and clamped into the six planes (moving it by no more than its error), so that every
/// returned point with w > 0 divides to a point within the square. w ≤ 0 is left for the
/// caller to drop.
#[inline]
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(w > 0)`: a NaN w is not in front either
pub fn settle(p: Vec4, a: glam::DVec4, c: glam::DVec4, t: f64, depth: DepthRange) -> Vec4 {
    let within = |q: Vec4| {
        let slack = SETTLE_REL * f64::from(q.abs().max_element());
        boundary_coords_of(q.as_dvec4().to_array(), depth)
            .iter()
            .all(|&b| b >= -slack)
    };
    if within(p) || !(p.w > 0.0) {
        return p;
    }
    let q = lerp_from_nearer(a, c, t).as_vec4();
    if within(q) || !(q.w > 0.0) {
        return q;
    }
    let w = q.w;
    let near = match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => -w,
    };
    Vec4::new(q.x.clamp(-w, w), q.y.clamp(-w, w), q.z.clamp(near, w), w)
}

/// What happened to one edge. `P` is the point type: [`Vec4`] in clip space (the default),
/// [`Vec2`] for the 2D window ([`ClipOutcome2`]), `Vec3` for 3D polyhedra.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClipOutcome<P = Vec4> {
    /// Both endpoints inside: the edge, unchanged.
    Accepted(P, P),
    /// Dropped without computing an intersection: both endpoints outside one plane (the
    /// outcode test `a & c != 0`), or parallel to and outside a plane.
    Rejected,
    /// The visible part `[P(t_in), P(t_out)]`, in the original direction A→C.
    Clipped(P, P),
    /// Dropped after computing intersections: no part is visible (e.g. an empty candidate
    /// interval), or what survived is the single point w = 0, the eye itself, which has no
    /// image.
    ClippedAway,
    /// An endpoint had a NaN or infinite coordinate; the edge is dropped.
    NonFinite,
}

/// The outcome of clipping a 2D segment against a [`Window2`].
pub type ClipOutcome2 = ClipOutcome<Vec2>;

impl<P: Copy> ClipOutcome<P> {
    /// The visible segment, if any (in clip space: w > 0 at both ends).
    #[inline]
    pub fn segment(&self) -> Option<(P, P)> {
        match *self {
            ClipOutcome::Accepted(a, c) | ClipOutcome::Clipped(a, c) => Some((a, c)),
            _ => None,
        }
    }
}

/// The line clippers that can draw a frame: those that clip a homogeneous edge against the
/// view volume (and extra planes). Each returns a [`ClipOutcome`] under the same contract.
/// Nicholl-Lee-Nicholl is 2D only (its regions are cut by rays through the window's corners,
/// which have no counterpart in clip space), so it is not here; the `clip` command and the
/// tests reach the 2D algorithms directly.
///
/// Sutherland-Hodgman is here as a line clipper by clipping the degenerate 2-vertex polygon
/// A, C, carrying the edge parameter t as a vertex attribute (as hardware clippers carry
/// varyings): every output vertex lies on the edge, and the ones with the smallest and largest
/// t are the segment. That is how a pipeline that clips only polygons clips lines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Clipper {
    /// Blinn's homogeneous clipper: boundary coordinates, outcodes, `[t_in, t_out]`.
    #[default]
    Blinn,
    /// Cohen-Sutherland with 6-bit homogeneous outcodes, chopping one plane at a time.
    CohenSutherland,
    /// Liang-Barsky with `p_k = BC_k(A) − BC_k(C)`, `q_k = BC_k(A)`.
    LiangBarsky,
    /// Cyrus-Beck on the clip volume as a convex polyhedron of homogeneous half-spaces.
    CyrusBeck,
    /// Sutherland-Hodgman on the 2-vertex polygon A, C.
    SutherlandHodgman,
}

impl Clipper {
    /// Every clipper, in the order a key cycles them.
    pub const ALL: [Clipper; 5] = [
        Clipper::Blinn,
        Clipper::CohenSutherland,
        Clipper::LiangBarsky,
        Clipper::CyrusBeck,
        Clipper::SutherlandHodgman,
    ];

    /// The name used on the command line and in the HUD.
    pub fn name(self) -> &'static str {
        match self {
            Clipper::Blinn => "blinn",
            Clipper::CohenSutherland => "cohen-sutherland",
            Clipper::LiangBarsky => "liang-barsky",
            Clipper::CyrusBeck => "cyrus-beck",
            Clipper::SutherlandHodgman => "sutherland-hodgman",
        }
    }

    /// Clip the edge `a`→`c` against the view volume of `depth`.
    #[inline]
    pub fn clip(self, a: Vec4, c: Vec4, depth: DepthRange) -> ClipOutcome {
        match self {
            Clipper::Blinn => blinn::clip_edge(a, c, depth),
            _ => self.clip_in(a, c, &ClipVolume::new(depth)),
        }
    }

    /// Clip the edge `a`→`c` against a volume with extra planes.
    #[inline]
    pub fn clip_in(self, a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
        match self {
            Clipper::Blinn => blinn::clip_edge_in(a, c, volume),
            Clipper::CohenSutherland => cohen_sutherland::clip_homogeneous(a, c, volume),
            Clipper::LiangBarsky => liang_barsky::clip_homogeneous(a, c, volume),
            Clipper::CyrusBeck => cyrus_beck::clip_homogeneous(a, c, volume),
            Clipper::SutherlandHodgman => sutherland_hodgman::clip_edge_homogeneous(a, c, volume),
        }
    }

    /// The next clipper after this one (wrapping), for a key that cycles them.
    pub fn next(self) -> Clipper {
        let i = Self::ALL.iter().position(|&c| c == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }
}

impl fmt::Display for Clipper {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no [`Clipper`]'s.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown clipper `{0}` (known: {known})", known = Clipper::names())]
pub struct ParseClipperError(pub String);

impl Clipper {
    /// Every clipper's name, comma-separated, for messages.
    fn names() -> String {
        let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
        names.join(", ")
    }
}

impl FromStr for Clipper {
    type Err = ParseClipperError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s.trim())
            .ok_or_else(|| ParseClipperError(s.to_string()))
    }
}

/// Tally of what the clipper did to a batch of edges (one frame).
///
/// Every edge handed in lands in exactly one category, so `edges_in` is the sum of
/// `trivially_accepted`, `trivially_rejected`, `clipped`, `clipped_away`, `non_finite`,
/// `bounds_rejected` and `back_facing`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipStats {
    /// Edges handed to the clipper.
    pub edges_in: u64,
    /// Both endpoints inside: drawn unchanged (`a | c == 0`).
    pub trivially_accepted: u64,
    /// Dropped without computing an intersection (for Blinn: both endpoints outside one
    /// plane, `a & c != 0`).
    pub trivially_rejected: u64,
    /// Not trivial, and a visible part remained: drawn shortened.
    pub clipped: u64,
    /// Not trivial, and nothing visible remained: dropped.
    pub clipped_away: u64,
    /// An endpoint had a NaN or infinite coordinate: dropped.
    pub non_finite: u64,
    /// Objects whose bounding sphere lies wholly outside the volume: none of their edges
    /// reached the clipper.
    pub objects_culled: u64,
    /// Edges of those objects (dropped with them).
    pub bounds_rejected: u64,
    /// Edges whose faces all face away from the eye (hidden-line mode): dropped before
    /// clipping.
    pub back_facing: u64,
}

impl ClipStats {
    /// Count one outcome.
    #[inline]
    pub fn record<P>(&mut self, outcome: &ClipOutcome<P>) {
        self.edges_in += 1;
        match outcome {
            ClipOutcome::Accepted(..) => self.trivially_accepted += 1,
            ClipOutcome::Rejected => self.trivially_rejected += 1,
            ClipOutcome::Clipped(..) => self.clipped += 1,
            ClipOutcome::ClippedAway => self.clipped_away += 1,
            ClipOutcome::NonFinite => self.non_finite += 1,
        }
    }

    /// Count an object of `edges` edges rejected whole by its bounding sphere.
    #[inline]
    pub fn record_culled_object(&mut self, edges: u64) {
        self.objects_culled += 1;
        self.bounds_rejected += edges;
        self.edges_in += edges;
    }

    /// Count an edge dropped because it borders only back faces.
    #[inline]
    pub fn record_back_facing(&mut self) {
        self.back_facing += 1;
        self.edges_in += 1;
    }

    /// Edges that produce a drawn segment.
    pub fn drawn(&self) -> u64 {
        self.trivially_accepted + self.clipped
    }

    /// Add another tally to this one.
    pub fn merge(&mut self, other: &ClipStats) {
        self.edges_in += other.edges_in;
        self.trivially_accepted += other.trivially_accepted;
        self.trivially_rejected += other.trivially_rejected;
        self.clipped += other.clipped;
        self.clipped_away += other.clipped_away;
        self.non_finite += other.non_finite;
        self.objects_culled += other.objects_culled;
        self.bounds_rejected += other.bounds_rejected;
        self.back_facing += other.back_facing;
    }
}

impl std::fmt::Display for ClipStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "edges in {}, trivially accepted {}, trivially rejected {}, clipped {}, clipped away {}",
            self.edges_in,
            self.trivially_accepted,
            self.trivially_rejected,
            self.clipped,
            self.clipped_away
        )?;
        if self.non_finite > 0 {
            write!(f, ", non-finite {}", self.non_finite)?;
        }
        if self.objects_culled > 0 {
            write!(
                f,
                ", culled by bounding sphere {} ({} objects)",
                self.bounds_rejected, self.objects_culled
            )?;
        }
        if self.back_facing > 0 {
            write!(f, ", back-facing {}", self.back_facing)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clippers_parse_by_name() {
        for c in Clipper::ALL {
            assert_eq!(c.name().parse::<Clipper>(), Ok(c));
        }
        let err = "bresenham".parse::<Clipper>().unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.starts_with("unknown clipper `bresenham` (known: blinn, "),
            "{msg}"
        );
    }
}
