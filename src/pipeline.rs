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

use crate::clip::{clip_edge, ClipStats, DepthRange};
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

/// Turns an edge mesh into clipped pixel segments, reusing its vertex buffer across frames.
#[derive(Default)]
pub struct EdgeProjector {
    clip_positions: Vec<Vec4>,
}

impl EdgeProjector {
    /// A projector with empty scratch space.
    pub fn new() -> Self {
        Self::default()
    }

    /// Transform, clip and project every edge of `mesh`, appending the visible segments to
    /// `out` (which is not cleared). Returns the clipper's tally for these edges.
    pub fn project(
        &mut self,
        mesh: &EdgeMesh,
        clip_from_model: Mat4,
        depth: DepthRange,
        viewport: Viewport,
        out: &mut Vec<Segment2>,
    ) -> ClipStats {
        self.clip_positions.clear();
        self.clip_positions.extend(
            mesh.positions()
                .iter()
                .map(|p| clip_from_model * p.extend(1.0)),
        );
        project_clip_edges(&self.clip_positions, mesh.edges(), depth, viewport, out)
    }
}

/// Clip edges given by index into clip-space positions and append their pixel segments.
pub fn project_clip_edges(
    clip_positions: &[Vec4],
    edges: &[[u32; 2]],
    depth: DepthRange,
    viewport: Viewport,
    out: &mut Vec<Segment2>,
) -> ClipStats {
    let mut stats = ClipStats::default();
    for &[i, j] in edges {
        let outcome = clip_edge(
            clip_positions[i as usize],
            clip_positions[j as usize],
            depth,
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

/// Edges of a polyline through points `0..points`, joining each point to the one before it
/// except at the indices in `breaks` (sorted; a break at i starts a new piece there, e.g. a
/// model restarted from the data). Written into `out` (cleared), for [`project_clip_edges`].
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
