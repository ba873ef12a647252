//! One frame of a flight as a [`LineScene`]: the ground and its landmarks, the trail, the
//! aircraft, and — in comparisons — the flight model's aircraft and its trail. Everything
//! goes through the same pipeline as a still: model matrix → clip space → the clipper on the
//! CPU → perspective divide → pixels ([`EdgeProjector`]).
//!
//! The window (a 10 km world of landmarks) and the offscreen replays (a grid fitted to the
//! flight) differ only in their [`Layer`]s. The scene's batches and the scratch buffers are
//! kept between frames and only cleared, so a steady-state frame allocates nothing. Pure: no
//! I/O.

use glam::{Mat4, Vec3};

use super::palette;
use crate::render::{LineBatch, LineScene, Rgba};
use wireflight_geometry::camera::{Camera, Projection};
use wireflight_geometry::clip::{ClipStats, Clipper, DepthRange};
use wireflight_geometry::euler::EulerZyx;
use wireflight_geometry::mesh::world::World;
use wireflight_geometry::mesh::EdgeMesh;
use wireflight_geometry::pipeline::{model_matrix, EdgeProjector, Sphere, Viewport};

/// Fraction of the far distance at which the horizon ring is drawn.
pub const HORIZON_FRACTION: f32 = 0.95;

/// Where a layer's mesh sits in the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// On the ground: the mesh's z = 0 is moved to the frame's ground height.
    Ground,
    /// Around the eye at eye height, scaled to just inside the far plane: the horizon of a
    /// flat earth, which is at eye level and infinitely far (the mesh is a unit ring).
    Horizon,
}

/// A static part of the world, drawn in one colour.
#[derive(Clone, Debug)]
pub struct Layer {
    /// The edges, world coordinates (viewer frame).
    pub mesh: EdgeMesh,
    /// Where it is placed each frame.
    pub placement: Placement,
    /// Its colour.
    pub color: Rgba,
}

impl Layer {
    /// The layers of the fly-through world, in drawing order: grid, horizon, hills, runway,
    /// structures.
    pub fn world(world: World) -> Vec<Layer> {
        let ground = |mesh, color| Layer {
            mesh,
            placement: Placement::Ground,
            color,
        };
        vec![
            ground(world.grid, palette::GRID),
            Layer {
                mesh: world.horizon,
                placement: Placement::Horizon,
                color: palette::HORIZON,
            },
            ground(world.hills, palette::HILL),
            ground(world.runway, palette::RUNWAY),
            ground(world.structures, palette::STRUCTURE),
        ]
    }
}

/// The parts of a frame after the layers, each one batch of [`SceneBuilder::scene`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The trail of the aircraft.
    Trail,
    /// The flight model's trail (comparisons; empty otherwise).
    ModelTrail,
    /// The flight model's aircraft (comparisons; empty otherwise).
    ModelAircraft,
    /// The aircraft, on top.
    Aircraft,
}

const PARTS: [(Part, Rgba); 4] = [
    (Part::Trail, palette::TRAIL),
    (Part::ModelTrail, palette::MODEL_TRAIL),
    (Part::ModelAircraft, palette::MODEL_AIRCRAFT),
    (Part::Aircraft, palette::AIRCRAFT),
];

/// What one frame shows.
#[derive(Clone, Copy, Debug)]
pub struct FrameSpec<'a> {
    /// The eye.
    pub camera: &'a Camera,
    /// The image, pixels.
    pub viewport: Viewport,
    /// Aircraft body origin, world.
    pub aircraft_position: Vec3,
    /// Aircraft attitude (z-y-x, viewer frame).
    pub aircraft_attitude: EulerZyx,
    /// Height of the ground (layers placed on the ground move there), m.
    pub ground_z: f32,
    /// Trail points, oldest first; the aircraft's position is appended as the last point.
    pub trail: &'a [Vec3],
    /// A second aircraft, the flight model's (comparisons), drawn under the first.
    pub model: Option<ModelFrame<'a>>,
}

/// The flight model's aircraft in a frame (comparisons).
#[derive(Clone, Copy, Debug)]
pub struct ModelFrame<'a> {
    /// Body origin, world.
    pub position: Vec3,
    /// Attitude (z-y-x, viewer frame).
    pub attitude: EulerZyx,
    /// Trail points, oldest first; `position` is appended as the last point.
    pub trail: &'a [Vec3],
    /// Indices into `trail` where the model was restarted from the data (no edge from the
    /// point before), ascending.
    pub breaks: &'a [usize],
}

/// Builds frames; owns the layers, the aircraft mesh and every reusable buffer.
pub struct SceneBuilder {
    layers: Vec<Layer>,
    /// Bounding spheres (model space) of the layers, then of the aircraft: whole objects
    /// outside the view are rejected before their edges are clipped.
    spheres: Vec<Sphere>,
    aircraft: EdgeMesh,
    projector: EdgeProjector,
    scene: LineScene,
}

impl SceneBuilder {
    /// A builder for the aircraft mesh `aircraft` (body axes) over the given layers, clipping
    /// with `clipper` in wgpu's clip space (0 ≤ z ≤ w).
    pub fn new(aircraft: EdgeMesh, layers: Vec<Layer>, clipper: Clipper) -> Self {
        let batches = layers
            .iter()
            .map(|l| l.color)
            .chain(PARTS.iter().map(|p| p.1))
            .map(|color| LineBatch {
                color,
                segments: Vec::new(),
            })
            .collect();
        let spheres = layers
            .iter()
            .map(|l| l.mesh.bounding_sphere())
            .chain(std::iter::once(aircraft.bounding_sphere()))
            .collect();
        Self {
            layers,
            spheres,
            aircraft,
            projector: EdgeProjector::new(clipper, DepthRange::ZeroToOne),
            scene: LineScene {
                width: 1,
                height: 1,
                background: palette::BACKGROUND,
                batches,
            },
        }
    }

    /// The aircraft mesh.
    pub fn aircraft(&self) -> &EdgeMesh {
        &self.aircraft
    }

    /// The static layers.
    pub fn layers(&self) -> &[Layer] {
        &self.layers
    }

    /// Index in [`scene`](Self::scene)'s batches of a part (the layers come first, in order).
    pub fn batch(&self, part: Part) -> usize {
        self.layers.len() + PARTS.iter().position(|p| p.0 == part).unwrap_or(0)
    }

    /// The clipper in use.
    pub fn clipper(&self) -> Clipper {
        self.projector.clipper()
    }

    /// Clip with another algorithm from the next frame on.
    pub fn set_clipper(&mut self, clipper: Clipper) {
        self.projector.set_clipper(clipper);
    }

    /// Edges handed to the clipper per frame, apart from the trails and the model's aircraft.
    pub fn edges_per_frame(&self) -> usize {
        self.layers
            .iter()
            .map(|l| l.mesh.edges().len())
            .sum::<usize>()
            + self.aircraft.edges().len()
    }

    /// The last frame built.
    pub fn scene(&self) -> &LineScene {
        &self.scene
    }

    /// The last frame built, for adding overlays (e.g. an error strip) before drawing it.
    pub fn scene_mut(&mut self) -> &mut LineScene {
        &mut self.scene
    }

    /// Build a frame into [`scene`](Self::scene); returns the clipper's counts for all of it.
    pub fn build(&mut self, spec: &FrameSpec<'_>) -> ClipStats {
        let viewport = spec.viewport;
        let clip_from_world = spec
            .camera
            .clip_from_world(viewport.aspect(), self.projector.depth());
        self.scene.width = viewport.width;
        self.scene.height = viewport.height;
        self.scene.batches.truncate(self.layers.len() + PARTS.len());
        for b in &mut self.scene.batches {
            b.segments.clear();
        }
        let mut stats = ClipStats::default();
        let ground = clip_from_world * Mat4::from_translation(Vec3::Z * spec.ground_z);
        let far = match spec.camera.projection {
            Projection::Perspective { far, .. } | Projection::Orthographic { far, .. } => far,
        };
        let horizon = clip_from_world
            * Mat4::from_translation(spec.camera.eye)
            * Mat4::from_scale(Vec3::splat(HORIZON_FRACTION * far));

        if let Some(m) = &spec.model {
            let index = self.batch(Part::ModelAircraft);
            stats.merge(&self.projector.project_bounded(
                &self.aircraft,
                self.spheres.last().copied(),
                clip_from_world * model_matrix(m.position, m.attitude),
                viewport,
                &mut self.scene.batches[index].segments,
            ));
            if !m.trail.is_empty() {
                let index = self.batch(Part::ModelTrail);
                stats.merge(&self.projector.project_polyline(
                    m.trail.iter().chain(std::iter::once(&m.position)),
                    m.breaks,
                    clip_from_world,
                    viewport,
                    &mut self.scene.batches[index].segments,
                ));
            }
        }

        for (index, layer) in self.layers.iter().enumerate() {
            let clip_from_model = match layer.placement {
                Placement::Ground => ground,
                Placement::Horizon => horizon,
            };
            stats.merge(&self.projector.project_bounded(
                &layer.mesh,
                Some(self.spheres[index]),
                clip_from_model,
                viewport,
                &mut self.scene.batches[index].segments,
            ));
        }
        let index = self.batch(Part::Aircraft);
        stats.merge(&self.projector.project_bounded(
            &self.aircraft,
            self.spheres.last().copied(),
            clip_from_world * model_matrix(spec.aircraft_position, spec.aircraft_attitude),
            viewport,
            &mut self.scene.batches[index].segments,
        ));

        // The trail: consecutive points joined, ending at the aircraft.
        if !spec.trail.is_empty() {
            let index = self.batch(Part::Trail);
            stats.merge(
                &self.projector.project_polyline(
                    spec.trail
                        .iter()
                        .chain(std::iter::once(&spec.aircraft_position)),
                    &[],
                    clip_from_world,
                    viewport,
                    &mut self.scene.batches[index].segments,
                ),
            );
        }
        stats
    }
}
