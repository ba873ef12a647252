//! The geometry pipeline from a model to 2D segments:
//!
//! ```text
//! mesh (body) ──model──▶ world ──view──▶ eye ──projection──▶ clip (x, y, z, w)
//!     ──Blinn clip──▶ visible clip segment ──÷w──▶ NDC ──viewport──▶ pixels
//! ```
//!
//! Vertices are transformed once per frame into a reused buffer; edges are then clipped (for
//! Blinn's clipper from per-vertex outcodes, see [`EdgeProjector`]). Nothing here allocates
//! per edge. Pure math: no I/O.

use glam::{Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::clip::{batch, cull, ClipStats, ClipVolume, Clipper, DepthRange, PlaneSet};
use crate::euler::EulerZyx;
use crate::lines::Segment2;
use crate::mesh::{EdgeMesh, MANY_FACES, NO_FACE};

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

/// Below this many edges a call is clipped on the calling thread; from it on, the vertices
/// and edges are split across rayon's threads (the split costs a few microseconds).
pub const PARALLEL_MIN_EDGES: usize = 1 << 15;

/// A bounding sphere in model space: centre and radius ([`EdgeMesh::bounding_sphere`]).
pub type Sphere = (Vec3, f32);

/// Turns edge meshes and polylines into clipped pixel segments. It carries the clip-space
/// convention (the projection matrices given to it must be built for [`depth`](Self::depth)),
/// the clipper, extra clip planes and the hidden-line switch, and reuses its buffers across
/// frames: a steady-state frame allocates nothing.
///
/// With Blinn's clipper and no extra planes it takes the fast path of [`crate::clip::batch`]:
/// one outcode per vertex (SIMD) and per edge only an OR and an AND unless the edge crosses
/// a plane, with identical segments and counts; meshes of [`PARALLEL_MIN_EDGES`] edges or
/// more are transformed and clipped on all cores (rayon), in order.
#[derive(Debug, Default)]
pub struct EdgeProjector {
    clipper: Clipper,
    depth: DepthRange,
    planes: PlaneSet,
    hidden_line: bool,
    clip_positions: Vec<Vec4>,
    codes: Vec<u8>,
    front: Vec<bool>,
    chunks: Vec<Vec<Segment2>>,
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

    /// Extra clip planes `(a, b, c, d)`, keeping `a·x + b·y + c·z + d ≥ 0` **in the
    /// coordinates of what is projected**: a mesh's model space for [`project`](Self::project)
    /// (so a cut-away stays fixed to the model whatever its attitude), world space for
    /// [`project_polyline`](Self::project_polyline). Each call maps them to clip space with
    /// the inverse transpose of its matrix.
    pub fn set_planes(&mut self, planes: PlaneSet) {
        self.planes = planes;
    }

    /// Hidden-line mode: edges of a mesh with faces are drawn only if a face they border faces
    /// the eye (back-face culling; exact for convex closed meshes). Edges without faces are
    /// always drawn.
    pub fn set_hidden_line(&mut self, on: bool) {
        self.hidden_line = on;
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
        self.project_bounded(mesh, None, clip_from_model, viewport, out)
    }

    /// [`project`](Self::project), first rejecting the whole mesh if its bounding sphere
    /// (model space) is outside the volume ([`crate::clip::cull::sphere_outside`]), which
    /// is then counted in [`ClipStats::objects_culled`] and [`ClipStats::bounds_rejected`].
    pub fn project_bounded(
        &mut self,
        mesh: &EdgeMesh,
        sphere: Option<Sphere>,
        clip_from_model: Mat4,
        viewport: Viewport,
        out: &mut Vec<Segment2>,
    ) -> ClipStats {
        let volume = self.volume(clip_from_model);
        if let Some((centre, radius)) = sphere {
            if cull::sphere_outside(centre, radius, clip_from_model, &volume) {
                let mut stats = ClipStats::default();
                stats.record_culled_object(mesh.edges().len() as u64);
                return stats;
            }
        }
        // On the fast path each vertex's code is computed as it is transformed, while it is
        // still in a register: one pass over the clip-space positions instead of two.
        let codes = self.fast(&volume).then_some((self.depth, &mut self.codes));
        transform(
            mesh.positions(),
            clip_from_model,
            mesh.edges().len(),
            &mut self.clip_positions,
            codes,
        );
        let hidden = self.hidden_line && !mesh.faces().is_empty();
        let mut front = std::mem::take(&mut self.front);
        if hidden {
            front.clear();
            front.extend(mesh.faces().iter().map(|&[a, b, c]| {
                let p = |i: u32| self.clip_positions[i as usize];
                cull::facing(p(a), p(b), p(c)) > 0.0
            }));
        }
        let visible = hidden.then_some((mesh.edge_faces(), front.as_slice()));
        let stats = self.clip_edges(mesh.edges(), visible, &volume, viewport, out, true);
        self.front = front;
        stats
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
        let mut edges = std::mem::take(&mut self.polyline_edges);
        polyline_edges(self.clip_positions.len(), breaks, &mut edges);
        let volume = self.volume(clip_from_world);
        let stats = self.clip_edges(&edges, None, &volume, viewport, out, false);
        self.polyline_edges = edges;
        stats
    }

    /// Clip edges given by index into clip-space positions and append their pixel segments,
    /// one edge at a time with [`Clipper::clip`] (the reference the fast path is held to).
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
                out.push(segment(a, c, viewport));
            }
        }
        stats
    }

    /// The volume of a call: the depth range and the extra planes mapped to clip space.
    fn volume(&self, clip_from_model: Mat4) -> ClipVolume {
        // A singular matrix (never from a camera) cannot map planes; the view volume alone
        // is then used.
        let extra = self
            .planes
            .transformed(clip_from_model)
            .unwrap_or(PlaneSet::EMPTY);
        ClipVolume::with_planes(self.depth, extra)
    }

    /// Whether Blinn's fast path (per-vertex codes) applies to a call with this volume.
    fn fast(&self, volume: &ClipVolume) -> bool {
        self.clipper == Clipper::Blinn && volume.extra.is_empty()
    }

    /// Clip `edges` of `self.clip_positions`, skipping edges with only back faces when
    /// `visible` gives the mesh's edge faces and the faces' front flags. `coded`: the fast
    /// path's vertex codes are already in `self.codes` (computed by [`transform`]).
    fn clip_edges(
        &mut self,
        edges: &[[u32; 2]],
        visible: Option<(&[[u32; 2]], &[bool])>,
        volume: &ClipVolume,
        viewport: Viewport,
        out: &mut Vec<Segment2>,
        coded: bool,
    ) -> ClipStats {
        let fast = self.fast(volume);
        if fast && !coded {
            codes(
                &self.clip_positions,
                self.depth,
                edges.len(),
                &mut self.codes,
            );
        }
        let job = EdgeJob {
            positions: &self.clip_positions,
            codes: fast.then_some(self.codes.as_slice()),
            visible,
            clipper: self.clipper,
            volume,
            viewport,
        };
        if edges.len() < PARALLEL_MIN_EDGES || rayon::current_num_threads() < 2 {
            return job.run(edges, 0, out);
        }
        // In order: chunk k's segments go to buffer k, appended afterwards.
        let chunk = edges.len().div_ceil(4 * rayon::current_num_threads());
        let pieces = edges.len().div_ceil(chunk);
        if self.chunks.len() < pieces {
            self.chunks.resize_with(pieces, Vec::new);
        }
        let stats = edges
            .par_chunks(chunk)
            .zip(self.chunks[..pieces].par_iter_mut())
            .enumerate()
            .map(|(k, (es, buf))| {
                buf.clear();
                job.run(es, k * chunk, buf)
            })
            .reduce(ClipStats::default, |mut a, b| {
                a.merge(&b);
                a
            });
        for buf in &self.chunks[..pieces] {
            out.extend_from_slice(buf);
        }
        stats
    }
}

/// What clipping a range of edges needs, shared by the threads.
struct EdgeJob<'a> {
    positions: &'a [Vec4],
    /// Vertex codes ([`batch::vertex_code`]): Blinn's fast path.
    codes: Option<&'a [u8]>,
    visible: Option<(&'a [[u32; 2]], &'a [bool])>,
    clipper: Clipper,
    volume: &'a ClipVolume,
    viewport: Viewport,
}

impl EdgeJob<'_> {
    /// Clip `edges` (the mesh's edges from index `first` on), appending to `out`.
    fn run(&self, edges: &[[u32; 2]], first: usize, out: &mut Vec<Segment2>) -> ClipStats {
        let mut stats = ClipStats::default();
        for (k, &[i, j]) in edges.iter().enumerate() {
            if let Some((edge_faces, front)) = self.visible {
                if !edge_visible(edge_faces[first + k], front) {
                    stats.record_back_facing();
                    continue;
                }
            }
            let outcome = match self.codes {
                Some(codes) => {
                    let (ca, cc) = (codes[i as usize], codes[j as usize]);
                    // The trivial reject from the codes alone (clip_coded's order: non-finite
                    // first): most edges of a large scene are off screen, and their positions
                    // (16 B each, scattered) are then never read.
                    if ca & cc & batch::OUTCODE_BITS != 0 && (ca | cc) & batch::NON_FINITE == 0 {
                        stats.edges_in += 1;
                        stats.trivially_rejected += 1;
                        continue;
                    }
                    let (a, c) = (self.positions[i as usize], self.positions[j as usize]);
                    if ca | cc == 0 {
                        // Inside and in front of the eye: the common case, straight through.
                        stats.edges_in += 1;
                        stats.trivially_accepted += 1;
                        out.push(segment(a, c, self.viewport));
                        continue;
                    }
                    batch::clip_coded(a, c, ca, cc, self.volume.depth)
                }
                None => {
                    let (a, c) = (self.positions[i as usize], self.positions[j as usize]);
                    self.clipper.clip_in(a, c, self.volume)
                }
            };
            stats.record(&outcome);
            if let Some((a, c)) = outcome.segment() {
                out.push(segment(a, c, self.viewport));
            }
        }
        stats
    }
}

/// Whether an edge with faces `sides` is drawn in hidden-line mode.
#[inline]
fn edge_visible(sides: [u32; 2], front: &[bool]) -> bool {
    if sides == [NO_FACE; 2] || sides[0] == MANY_FACES {
        return true; // a line element, or not a 2-manifold edge
    }
    sides
        .iter()
        .any(|&f| front.get(f as usize).copied().unwrap_or(false))
}

/// The pixel segment of a clipped clip-space segment.
#[inline]
fn segment(a: Vec4, c: Vec4, viewport: Viewport) -> Segment2 {
    Segment2 {
        a: viewport.to_pixels(perspective_divide(a)),
        b: viewport.to_pixels(perspective_divide(c)),
    }
}

/// `positions` mapped by `m` into `out`, and with `codes` each one's [`batch::vertex_code`]
/// into that buffer (both cleared first), on all cores for large meshes. The buffers are
/// filled by `extend` / rayon's indexed collect, never resized with zeros first: that memset
/// cost 14% of a 1 M-edge frame.
fn transform(
    positions: &[Vec3],
    m: Mat4,
    edges: usize,
    out: &mut Vec<Vec4>,
    codes: Option<(DepthRange, &mut Vec<u8>)>,
) {
    let map = |p: &Vec3| m * p.extend(1.0);
    let parallel = edges >= PARALLEL_MIN_EDGES && rayon::current_num_threads() >= 2;
    match codes {
        None if parallel => positions.par_iter().map(map).collect_into_vec(out),
        None => {
            out.clear();
            out.extend(positions.iter().map(map));
        }
        Some((depth, codes)) => {
            let coded = |p: &Vec3| {
                let q = map(p);
                (q, batch::vertex_code(q, depth))
            };
            if parallel {
                positions.par_iter().map(coded).unzip_into_vecs(out, codes);
            } else {
                out.clear();
                codes.clear();
                let mut both = (std::mem::take(out), std::mem::take(codes));
                both.extend(positions.iter().map(coded));
                (*out, *codes) = both;
            }
        }
    }
}

/// Vertex codes of `positions` into `out`, on all cores for large meshes.
fn codes(positions: &[Vec4], depth: DepthRange, edges: usize, out: &mut Vec<u8>) {
    if edges < PARALLEL_MIN_EDGES || rayon::current_num_threads() < 2 {
        batch::vertex_codes(positions, depth, out);
        return;
    }
    positions
        .par_iter()
        .map(|&p| batch::vertex_code(p, depth))
        .collect_into_vec(out);
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
