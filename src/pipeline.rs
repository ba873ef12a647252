//! The geometry pipeline from a model to 2D segments:
//!
//! ```text
//! mesh (body) ──model──▶ world ──view──▶ eye ──projection──▶ clip (x, y, z, w)
//!     ──Blinn clip──▶ visible clip segment ──÷w──▶ NDC ──viewport──▶ pixels
//! ```
//!
//! Vertices are transformed once per frame into a reused buffer; edges are then clipped one by
//! one. Nothing here allocates per edge. Pure math: no I/O.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::clip::{ClipStats, Clipper, DepthRange};
use crate::euler::EulerZyx;
use crate::mesh::EdgeMesh;
use crate::render::Segment2;

/// Model (body → world) matrix: rotate by the z-y-x attitude, then translate.
pub fn model_matrix(position: Vec3, attitude: EulerZyx) -> Mat4 {
    Mat4::from_translation(position) * Mat4::from_mat3(attitude.to_mat3())
}

/// The image the clip volume maps onto.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Viewport {
    /// Width, pixels (≥ 1).
    pub width: u32,
    /// Height, pixels (≥ 1).
    pub height: u32,
}

impl Viewport {
    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Pixel coordinates of a point in normalised device coordinates: x ∈ [−1, 1] maps to
    /// [0, width] left to right, y ∈ [−1, 1] to [height, 0] (pixel rows run downwards).
    #[inline]
    pub fn to_pixels(&self, ndc: Vec2) -> Vec2 {
        Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.width as f32,
            (1.0 - ndc.y) * 0.5 * self.height as f32,
        )
    }
}

/// Turns edge meshes and polylines into clipped pixel segments. It carries the clip-space
/// convention (the projection matrices given to it must be built for [`depth`](Self::depth))
/// and the clipper, and reuses its buffers across frames.
#[derive(Debug, Default)]
pub struct EdgeProjector {
    clipper: Clipper,
    depth: DepthRange,
    clip_positions: Vec<Vec4>,
    polyline_edges: Vec<[u32; 2]>,
}

impl EdgeProjector {
    /// A projector for one clip-space convention, with empty scratch space.
    pub fn new(clipper: Clipper, depth: DepthRange) -> Self {
        Self {
            clipper,
            depth,
            ..Self::default()
        }
    }

    /// The clip-space depth range every matrix handed in must be built for.
    pub fn depth(&self) -> DepthRange {
        self.depth
    }

    /// The clipper in use.
    pub fn clipper(&self) -> Clipper {
        self.clipper
    }

    /// Clip with another algorithm from now on.
    pub fn set_clipper(&mut self, clipper: Clipper) {
        self.clipper = clipper;
    }

    /// Transform, clip and project every edge of `mesh`, appending the visible segments to
    /// `out` (which is not cleared). Returns the clipper's tally for these edges.
    pub fn project(
        &mut self,
        mesh: &EdgeMesh,
        clip_from_model: Mat4,
        viewport: Viewport,
        out: &mut Vec<Segment2>,
    ) -> ClipStats {
        self.clip_positions.clear();
        self.clip_positions.extend(
            mesh.positions()
                .iter()
                .map(|p| clip_from_model * p.extend(1.0)),
        );
        self.clip_indexed(&self.clip_positions, mesh.edges(), viewport, out)
    }

    /// Project the polyline through `points` (world coordinates), with a break before each
    /// index in `breaks` (sorted; see [`polyline_edges`]), appending to `out`.
    pub fn project_polyline<'p>(
        &mut self,
        points: impl IntoIterator<Item = &'p Vec3>,
        breaks: &[usize],
        clip_from_world: Mat4,
        viewport: Viewport,
        out: &mut Vec<Segment2>,
    ) -> ClipStats {
        self.clip_positions.clear();
        self.clip_positions
            .extend(points.into_iter().map(|p| clip_from_world * p.extend(1.0)));
        polyline_edges(self.clip_positions.len(), breaks, &mut self.polyline_edges);
        self.clip_indexed(&self.clip_positions, &self.polyline_edges, viewport, out)
    }

    /// Clip edges given by index into clip-space positions and append their pixel segments.
    pub fn clip_indexed(
        &self,
        clip_positions: &[Vec4],
        edges: &[[u32; 2]],
        viewport: Viewport,
        out: &mut Vec<Segment2>,
    ) -> ClipStats {
        let mut stats = ClipStats::default();
        for &[i, j] in edges {
            let outcome = self.clipper.clip(
                clip_positions[i as usize],
                clip_positions[j as usize],
                self.depth,
            );
            stats.record(&outcome);
            if let Some((a, c)) = outcome.segment() {
                out.push(Segment2 {
                    a: viewport.to_pixels(perspective_divide(a)),
                    b: viewport.to_pixels(perspective_divide(c)),
                });
            }
        }
        stats
    }
}

/// Edges of a polyline through points `0..points`, joining each point to the one before it
/// except at the indices in `breaks` (sorted; a break at i starts a new piece there, e.g. a
/// model restarted from the data). Written into `out` (cleared).
pub fn polyline_edges(points: usize, breaks: &[usize], out: &mut Vec<[u32; 2]>) {
    out.clear();
    let mut breaks = breaks.iter().peekable();
    for i in 1..points {
        while breaks.next_if(|&&b| b < i).is_some() {}
        if breaks.peek().is_some_and(|&&b| b == i) {
            continue;
        }
        out.push([i as u32 - 1, i as u32]);
    }
}

/// NDC (x, y) of a clipped homogeneous point (w > 0 is guaranteed by the clipper).
#[inline]
pub fn perspective_divide(p: Vec4) -> Vec2 {
    debug_assert!(p.w > 0.0, "clipper let through w = {}", p.w);
    Vec2::new(p.x / p.w, p.y / p.w)
}
