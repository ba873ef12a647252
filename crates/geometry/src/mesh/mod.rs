//! Wireframe models: vertex positions and deduplicated edges, in model (body) coordinates.
//!
//! Every source (the built-in plane, OBJ, glTF) goes through [`EdgeMeshBuilder`], which welds
//! vertices with bit-identical positions and keeps each undirected edge once, so an edge
//! shared by two faces, or by two copies of a vertex that differ only in normal or UV, is drawn
//! once. Degenerate edges (both ends the same welded vertex) are dropped.
//!
//! Loaders that read polygons (OBJ faces, glTF triangles) also record **faces**, for
//! hidden-line drawing by back-face culling: each face as one counter-clockwise triangle of
//! its corners (enough to tell which way it faces), and for each edge the faces it borders.
//! Meshes built from outlines (the built-in plane, the world) have none.

pub mod plane;
pub mod world;

use std::collections::HashMap;

use glam::Vec3;

/// An edge list over shared vertices. Invariants (checked by the builder): at least one edge,
/// all positions finite, indices in range, no degenerate or repeated edge, `a < b`; faces
/// (optional) index the same vertices, and `edge_faces` is empty or one entry per edge.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeMesh {
    positions: Vec<Vec3>,
    edges: Vec<[u32; 2]>,
    faces: Vec<[u32; 3]>,
    edge_faces: Vec<[u32; 2]>,
}

/// In [`EdgeMesh::edge_faces`]: no face on this side (a line element, or an open boundary).
pub const NO_FACE: u32 = u32::MAX;

/// In [`EdgeMesh::edge_faces`] (both entries): the edge borders more than two faces; it is
/// always drawn.
pub const MANY_FACES: u32 = u32::MAX - 1;

impl EdgeMesh {
    /// Vertex positions in model coordinates.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Edges as index pairs into [`positions`](Self::positions), `a < b`, each once.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Faces, each as a triangle of vertex indices wound counter-clockwise seen from the
    /// side it faces (for a polygon, the corner triangle that best shows its winding). Empty
    /// for meshes made of outlines.
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }

    /// Per edge, the (up to two) faces it borders, [`NO_FACE`] for none; empty when the mesh
    /// has no faces.
    pub fn edge_faces(&self) -> &[[u32; 2]] {
        &self.edge_faces
    }

    /// Axis-aligned bounds `(min, max)` of the vertices used by edges.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut min = Vec3::splat(f32::INFINITY);
        let mut max = Vec3::splat(f32::NEG_INFINITY);
        for p in &self.positions {
            min = min.min(*p);
            max = max.max(*p);
        }
        (min, max)
    }

    /// Centre of the bounding box and the radius of the bounding sphere about it; used to frame
    /// cameras so that a model of any size fills the picture.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let (min, max) = self.bounds();
        let centre = 0.5 * (min + max);
        let radius = self
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0f32, f32::max);
        (centre, radius.max(f32::MIN_POSITIVE))
    }
}

/// Builds an [`EdgeMesh`], welding equal positions and deduplicating edges.
#[derive(Default)]
pub struct EdgeMeshBuilder {
    positions: Vec<Vec3>,
    index_of: HashMap<[u32; 3], u32>,
    edges: Vec<[u32; 2]>,
    seen: HashMap<[u32; 2], u32>,
    faces: Vec<[u32; 3]>,
    edge_faces: Vec<[u32; 2]>,
}

impl EdgeMeshBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Index of the vertex at `p`, adding it if no vertex has bit-identical coordinates.
    /// `-0.0` and `0.0` are the same vertex.
    ///
    /// # Errors
    /// [`MeshProblem::NonFinite`] if a coordinate is NaN or infinite.
    pub fn vertex(&mut self, p: Vec3) -> Result<u32, MeshProblem> {
        if !p.is_finite() {
            return Err(MeshProblem::NonFinite(p));
        }
        let key = (p + Vec3::ZERO).to_array().map(f32::to_bits); // + 0.0 turns −0.0 into 0.0
        if let Some(&i) = self.index_of.get(&key) {
            return Ok(i);
        }
        let i = u32::try_from(self.positions.len()).map_err(|_| MeshProblem::TooLarge)?;
        self.positions.push(p);
        self.index_of.insert(key, i);
        Ok(i)
    }

    /// Add the edge between two vertex indices from [`vertex`](Self::vertex). Repeated edges
    /// (either direction) and degenerate ones (`a == b`) are ignored; returns whether it was new.
    pub fn edge(&mut self, a: u32, b: u32) -> bool {
        debug_assert!((a as usize) < self.positions.len() && (b as usize) < self.positions.len());
        if a == b {
            return false;
        }
        let key = [a.min(b), a.max(b)];
        if let std::collections::hash_map::Entry::Vacant(slot) = self.seen.entry(key) {
            slot.insert(self.edges.len() as u32);
            self.edges.push(key);
            self.edge_faces.push([NO_FACE; 2]);
            true
        } else {
            false
        }
    }

    /// Add a face: a polygon given by vertex indices from [`vertex`](Self::vertex), in order,
    /// counter-clockwise seen from the side it faces. Its edges are added as by
    /// [`polygon`](Self::polygon), and each edge records the face. A face with fewer than
    /// three distinct corners or no area adds its edges only.
    pub fn face_indices(&mut self, corners: &[u32]) {
        let n = corners.len();
        for i in 0..n {
            self.edge(corners[i], corners[(i + 1) % n]);
        }
        let p = |i: u32| self.positions[i as usize].as_dvec3();
        // Newell's normal, then the fan triangle that best agrees with it (for a planar
        // polygon, any with a positive agreement has the polygon's winding).
        let mut normal = glam::DVec3::ZERO;
        for i in 0..n {
            normal += p(corners[i]).cross(p(corners[(i + 1) % n]));
        }
        let mut best: Option<([u32; 3], f64)> = None;
        for i in 1..n.saturating_sub(1) {
            let tri = [corners[0], corners[i], corners[i + 1]];
            let area = (p(tri[1]) - p(tri[0]))
                .cross(p(tri[2]) - p(tri[0]))
                .dot(normal);
            if area > 0.0 && best.is_none_or(|(_, a)| area > a) {
                best = Some((tri, area));
            }
        }
        let Some((tri, _)) = best else {
            return;
        };
        let face = self.faces.len() as u32;
        self.faces.push(tri);
        for i in 0..n {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            let Some(&e) = self.seen.get(&[a.min(b), a.max(b)]) else {
                continue; // degenerate (a == b)
            };
            let sides = &mut self.edge_faces[e as usize];
            if sides.contains(&face) || sides[0] == MANY_FACES {
                continue;
            }
            if sides[0] == NO_FACE {
                sides[0] = face;
            } else if sides[1] == NO_FACE {
                sides[1] = face;
            } else {
                // A third face: not a closed 2-manifold here; the edge is always drawn.
                *sides = [MANY_FACES; 2];
            }
        }
    }

    /// Add a face given by its corner positions (see [`face_indices`](Self::face_indices)).
    ///
    /// # Errors
    /// As [`vertex`](Self::vertex).
    pub fn face(&mut self, corners: &[Vec3]) -> Result<(), MeshProblem> {
        let ids = corners
            .iter()
            .map(|&p| self.vertex(p))
            .collect::<Result<Vec<u32>, _>>()?;
        self.face_indices(&ids);
        Ok(())
    }

    /// Add the edge between two positions.
    ///
    /// # Errors
    /// As [`vertex`](Self::vertex).
    pub fn edge_between(&mut self, a: Vec3, b: Vec3) -> Result<bool, MeshProblem> {
        let a = self.vertex(a)?;
        let b = self.vertex(b)?;
        Ok(self.edge(a, b))
    }

    /// Add a closed polygon's edges (v0→v1→…→vn−1→v0).
    ///
    /// # Errors
    /// As [`vertex`](Self::vertex).
    pub fn polygon(&mut self, corners: &[Vec3]) -> Result<(), MeshProblem> {
        for (i, &p) in corners.iter().enumerate() {
            self.edge_between(p, corners[(i + 1) % corners.len()])?;
        }
        Ok(())
    }

    /// Add an open polyline's edges (v0→v1→…→vn−1).
    ///
    /// # Errors
    /// As [`vertex`](Self::vertex).
    pub fn polyline(&mut self, points: &[Vec3]) -> Result<(), MeshProblem> {
        for pair in points.windows(2) {
            self.edge_between(pair[0], pair[1])?;
        }
        Ok(())
    }

    /// Number of distinct edges so far.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// The finished mesh, keeping only vertices that some edge uses.
    ///
    /// # Errors
    /// [`MeshProblem::NoEdges`] if there is nothing to draw.
    pub fn build(self) -> Result<EdgeMesh, MeshProblem> {
        if self.edges.is_empty() {
            return Err(MeshProblem::NoEdges);
        }
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut edges = self.edges;
        for e in &mut edges {
            for i in e.iter_mut() {
                let slot = &mut remap[*i as usize];
                if *slot == u32::MAX {
                    *slot = positions.len() as u32;
                    positions.push(self.positions[*i as usize]);
                }
                *i = *slot;
            }
            *e = [e[0].min(e[1]), e[0].max(e[1])];
        }
        // Every corner of a face is on one of its edges, so it has been remapped.
        let mut faces = self.faces;
        for f in &mut faces {
            *f = f.map(|i| remap[i as usize]);
        }
        let edge_faces = if faces.is_empty() {
            Vec::new()
        } else {
            self.edge_faces
        };
        Ok(EdgeMesh {
            positions,
            edges,
            faces,
            edge_faces,
        })
    }
}

/// What is wrong with a model, independent of where it came from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshProblem {
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex position {0} is not finite")]
    NonFinite(Vec3),
    /// No drawable edge (empty file, only points, or only degenerate edges).
    #[error("the model has no edges to draw (empty, or only points/degenerate edges)")]
    NoEdges,
    /// More than 2³² vertices.
    #[error("the model has more than 4294967295 vertices")]
    TooLarge,
    /// A model too large or too small to be drawn in `f32` by every camera.
    #[error(
        "the model's bounding radius {0:e} m is outside {MIN_RADIUS_M:e}..={MAX_RADIUS_M:e} m, \
         the sizes every camera can draw in f32: rescale it"
    )]
    OutOfScale(f32),
}

/// Smallest bounding radius of a loaded model, m (below about 1e-20 the projection underflows).
pub const MIN_RADIUS_M: f32 = 1e-9;
/// Largest bounding radius of a loaded model, m (the cockpit camera loses the model near 1e8,
/// the chase camera near 1e18).
pub const MAX_RADIUS_M: f32 = 1e6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builder_welds_and_dedups() {
        let mut b = EdgeMeshBuilder::new();
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        b.polygon(&tri).unwrap();
        b.polygon(&[Vec3::Y, Vec3::X, Vec3::ZERO]).unwrap(); // same edges, reversed
        b.edge_between(Vec3::new(-0.0, 0.0, 0.0), Vec3::ZERO)
            .unwrap(); // degenerate via −0
        let m = b.build().unwrap();
        assert_eq!(m.edges().len(), 3);
        assert_eq!(m.positions().len(), 3);
    }

    #[test]
    fn builder_rejects_nan_and_empty() {
        let mut b = EdgeMeshBuilder::new();
        assert!(matches!(
            b.vertex(Vec3::new(f32::NAN, 0.0, 0.0)),
            Err(MeshProblem::NonFinite(_))
        ));
        assert_eq!(b.build(), Err(MeshProblem::NoEdges));
    }
}
