//! Clipping edges against the canonical view volume in homogeneous clip space.
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
//! outcodes, the outcome of clipping one edge ([`ClipOutcome`]) and the tally of a batch
//! ([`ClipStats`]). Each algorithm is one file; [`Clipper`] names them, and the projector
//! ([`crate::pipeline::EdgeProjector`]) carries the choice. Drawing uses Blinn's ([`blinn`]).
//! Pure math: no I/O, no allocation.

pub mod blinn;

pub use blinn::clip_edge;

use std::fmt;
use std::ops::{Add, Sub};
use std::str::FromStr;

use glam::Vec4;

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
/// use wireflight::clip::{boundary_coords, DepthRange};
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

/// What happened to one edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClipOutcome {
    /// Both endpoints inside: the edge, unchanged.
    Accepted(Vec4, Vec4),
    /// Both endpoints outside the same plane: nothing visible.
    Rejected,
    /// The visible part `[P(t_in), P(t_out)]`, in the original direction A→C.
    Clipped(Vec4, Vec4),
    /// Not trivially rejected, but no part is visible (empty candidate interval), or what
    /// survived is the single point w = 0, the eye itself, which has no image.
    ClippedAway,
    /// An endpoint had a NaN or infinite coordinate; the edge is dropped.
    NonFinite,
}

impl ClipOutcome {
    /// The visible segment, if any (homogeneous clip coordinates, w > 0 at both ends).
    #[inline]
    pub fn segment(&self) -> Option<(Vec4, Vec4)> {
        match *self {
            ClipOutcome::Accepted(a, c) | ClipOutcome::Clipped(a, c) => Some((a, c)),
            _ => None,
        }
    }
}

/// The line clippers that can draw a frame. Each takes an edge in homogeneous clip space and
/// returns a [`ClipOutcome`] under the same contract (see [`blinn`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Clipper {
    /// Blinn's homogeneous clipper: boundary coordinates, outcodes, `[t_in, t_out]`.
    #[default]
    Blinn,
}

impl Clipper {
    /// Every clipper, in the order a key cycles them.
    pub const ALL: [Clipper; 1] = [Clipper::Blinn];

    /// The name used on the command line and in the HUD.
    pub fn name(self) -> &'static str {
        match self {
            Clipper::Blinn => "blinn",
        }
    }

    /// Clip the edge `a`→`c` against the view volume of `depth`.
    #[inline]
    pub fn clip(self, a: Vec4, c: Vec4, depth: DepthRange) -> ClipOutcome {
        match self {
            Clipper::Blinn => blinn::clip_edge(a, c, depth),
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

impl FromStr for Clipper {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s.trim())
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
                format!("unknown clipper `{s}` (known: {})", names.join(", "))
            })
    }
}

/// Tally of what the clipper did to a batch of edges (one frame).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipStats {
    /// Edges handed to the clipper.
    pub edges_in: u64,
    /// Both endpoints inside: drawn unchanged (`a | c == 0`).
    pub trivially_accepted: u64,
    /// Both endpoints outside one plane: dropped without arithmetic (`a & c != 0`).
    pub trivially_rejected: u64,
    /// Not trivial, and a visible part remained: drawn shortened.
    pub clipped: u64,
    /// Not trivial, and the candidate interval came out empty: dropped.
    pub clipped_away: u64,
    /// An endpoint had a NaN or infinite coordinate: dropped.
    pub non_finite: u64,
}

impl ClipStats {
    /// Count one outcome.
    #[inline]
    pub fn record(&mut self, outcome: &ClipOutcome) {
        self.edges_in += 1;
        match outcome {
            ClipOutcome::Accepted(..) => self.trivially_accepted += 1,
            ClipOutcome::Rejected => self.trivially_rejected += 1,
            ClipOutcome::Clipped(..) => self.clipped += 1,
            ClipOutcome::ClippedAway => self.clipped_away += 1,
            ClipOutcome::NonFinite => self.non_finite += 1,
        }
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
        Ok(())
    }
}
