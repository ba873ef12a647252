//! One frame of the fly-through window as a [`LineScene`]: the world, the trail and the aircraft
//! go through the same pipeline as `wireflight render` — model matrix → clip space → Blinn's
//! clipper on the CPU → perspective divide → pixels ([`EdgeProjector`],
//! [`project_clip_edges`]).
//!
//! The scene's batches and the scratch buffers are kept between frames and only cleared, so a
//! steady-state frame allocates nothing. Pure: no I/O.

use glam::{Mat4, Vec3, Vec4};

use crate::camera::{Camera, Projection};
use crate::clip::{ClipStats, DepthRange};
use crate::euler::EulerZyx;
use crate::mesh::world::{World, WorldSpec};
use crate::mesh::EdgeMesh;
use crate::pipeline::{model_matrix, polyline_edges, project_clip_edges, EdgeProjector, Viewport};
use crate::render::{palette, LineBatch, LineScene, Rgba};

/// Colours of the world (the aircraft and the grid use [`palette`]).
pub mod colors {
    use crate::render::Rgba;
    /// Runway markings.
    pub const RUNWAY: Rgba = [235, 235, 235, 255];
    /// Masts, tower, hangars.
    pub const STRUCTURE: Rgba = [255, 150, 60, 255];
    /// Hills.
    pub const HILL: Rgba = [170, 120, 255, 255];
    /// The horizon ring.
    pub const HORIZON: Rgba = [110, 200, 255, 255];
    /// The flown trail.
    pub const TRAIL: Rgba = crate::app::replay::TRAIL;
    /// The model's trail (`--compare`).
    pub const MODEL_TRAIL: Rgba = crate::app::replay::MODEL_TRAIL;
    /// The model's aircraft (`--compare`).
    pub const MODEL_AIRCRAFT: Rgba = crate::app::replay::MODEL_AIRCRAFT;
}

/// Index of each batch in [`SceneBuilder::scene`], drawn in this order.
pub mod batch {
    /// Ground grid.
    pub const GRID: usize = 0;
    /// Horizon ring.
    pub const HORIZON: usize = 1;
    /// Hills.
    pub const HILLS: usize = 2;
    /// Runway.
    pub const RUNWAY: usize = 3;
    /// Structures.
    pub const STRUCTURES: usize = 4;
    /// Trail.
    pub const TRAIL: usize = 5;
    /// The model's trail (`--compare`; empty otherwise).
    pub const MODEL_TRAIL: usize = 6;
    /// The model's aircraft (`--compare`; empty otherwise).
    pub const MODEL_PLANE: usize = 7;
    /// The aircraft (on top).
    pub const PLANE: usize = 8;
    /// Number of batches.
    pub const COUNT: usize = 9;
}

/// Fraction of the far distance at which the horizon ring is drawn.
pub const HORIZON_FRACTION: f32 = 0.95;

/// What one frame shows.
#[derive(Clone, Copy, Debug)]
pub struct FrameSpec<'a> {
    /// The eye.
    pub camera: &'a Camera,
    /// The window, physical pixels.
    pub viewport: Viewport,
    /// Aircraft body origin, world.
    pub plane_position: Vec3,
    /// Aircraft attitude (z-y-x, viewer frame).
    pub plane_attitude: EulerZyx,
    /// Height of the ground (the world's z = 0 is moved there), m.
    pub ground_z: f32,
    /// Trail points, oldest first; the aircraft's position is appended as the last point.
    pub trail: &'a [Vec3],
    /// A second aircraft, the model's (`--compare`), drawn under the first.
    pub model: Option<ModelFrame<'a>>,
}

/// The model's aircraft in a frame (`--compare`).
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

/// Builds frames; owns the world, the aircraft mesh and every reusable buffer.
pub struct SceneBuilder {
    world: World,
    plane: EdgeMesh,
    projector: EdgeProjector,
    trail_clip: Vec<Vec4>,
    trail_edges: Vec<[u32; 2]>,
    scene: LineScene,
}

impl SceneBuilder {
    /// A builder for the aircraft `plane` (body axes) flying in a world of the given size.
    pub fn new(plane: EdgeMesh, world: &WorldSpec) -> Self {
        let colors: [Rgba; batch::COUNT] = [
            palette::GRID,
            colors::HORIZON,
            colors::HILL,
            colors::RUNWAY,
            colors::STRUCTURE,
            colors::TRAIL,
            colors::MODEL_TRAIL,
            colors::MODEL_AIRCRAFT,
            palette::MODEL,
        ];
        Self {
            world: World::new(world),
            plane,
            projector: EdgeProjector::new(),
            trail_clip: Vec::new(),
            trail_edges: Vec::new(),
            scene: LineScene {
                width: 1,
                height: 1,
                background: palette::BACKGROUND,
                batches: colors
                    .iter()
                    .map(|&color| LineBatch {
                        color,
                        segments: Vec::new(),
                    })
                    .collect(),
            },
        }
    }

    /// The aircraft mesh.
    pub fn plane(&self) -> &EdgeMesh {
        &self.plane
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Edges handed to the clipper per frame, apart from the trail.
    pub fn edges_per_frame(&self) -> usize {
        self.world.edge_count() + self.plane.edges().len()
    }

    /// The last frame built.
    pub fn scene(&self) -> &LineScene {
        &self.scene
    }

    /// Build a frame into [`scene`](Self::scene); returns the clipper's counts for all of it.
    pub fn build(&mut self, spec: &FrameSpec<'_>) -> ClipStats {
        let depth = DepthRange::ZeroToOne;
        let viewport = spec.viewport;
        let clip_from_world = spec.camera.clip_from_world(viewport.aspect(), depth);
        self.scene.width = viewport.width;
        self.scene.height = viewport.height;
        for b in &mut self.scene.batches {
            b.segments.clear();
        }
        let mut stats = ClipStats::default();
        let ground = clip_from_world * Mat4::from_translation(Vec3::Z * spec.ground_z);
        let far = match spec.camera.projection {
            Projection::Perspective { far, .. } | Projection::Orthographic { far, .. } => far,
        };
        // The horizon of a flat earth is at eye level, infinitely far: a ring around the eye,
        // at eye height, just inside the far plane.
        let horizon = clip_from_world
            * Mat4::from_translation(spec.camera.eye)
            * Mat4::from_scale(Vec3::splat(HORIZON_FRACTION * far));
        let plane = clip_from_world * model_matrix(spec.plane_position, spec.plane_attitude);

        if let Some(m) = &spec.model {
            let model_plane = clip_from_world * model_matrix(m.position, m.attitude);
            stats.merge(&self.projector.project(
                &self.plane,
                model_plane,
                depth,
                viewport,
                &mut self.scene.batches[batch::MODEL_PLANE].segments,
            ));
            if !m.trail.is_empty() {
                self.trail_clip.clear();
                self.trail_clip.extend(
                    m.trail
                        .iter()
                        .chain(std::iter::once(&m.position))
                        .map(|p| clip_from_world * p.extend(1.0)),
                );
                polyline_edges(self.trail_clip.len(), &m.breaks, &mut self.trail_edges);
                stats.merge(&project_clip_edges(
                    &self.trail_clip,
                    &self.trail_edges,
                    depth,
                    viewport,
                    &mut self.scene.batches[batch::MODEL_TRAIL].segments,
                ));
            }
        }

        let world = &self.world;
        let jobs: [(&EdgeMesh, Mat4, usize); 6] = [
            (&world.grid, ground, batch::GRID),
            (&world.horizon, horizon, batch::HORIZON),
            (&world.hills, ground, batch::HILLS),
            (&world.runway, ground, batch::RUNWAY),
            (&world.structures, ground, batch::STRUCTURES),
            (&self.plane, plane, batch::PLANE),
        ];
        for (mesh, clip_from_model, index) in jobs {
            stats.merge(&self.projector.project(
                mesh,
                clip_from_model,
                depth,
                viewport,
                &mut self.scene.batches[index].segments,
            ));
        }

        // The trail: consecutive points joined, ending at the aircraft.
        if !spec.trail.is_empty() {
            self.trail_clip.clear();
            self.trail_clip.extend(
                spec.trail
                    .iter()
                    .chain(std::iter::once(&spec.plane_position))
                    .map(|p| clip_from_world * p.extend(1.0)),
            );
            polyline_edges(self.trail_clip.len(), &[], &mut self.trail_edges);
            stats.merge(&project_clip_edges(
                &self.trail_clip,
                &self.trail_edges,
                depth,
                viewport,
                &mut self.scene.batches[batch::TRAIL].segments,
            ));
        }
        stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::view::cameras::{CameraMode, CameraRig, Target};
    use crate::mesh::plane::builtin_plane;
    use glam::DQuat;

    #[test]
    fn a_chase_frame_over_the_field_clips_against_near_far_and_sides() {
        let mut b = SceneBuilder::new(builtin_plane(), &WorldSpec::default());
        let (centre, radius) = b.plane().bounding_sphere();
        let position = Vec3::new(-1500.0, 0.0, 150.0);
        let target = Target {
            position: position.as_dvec3(),
            orientation: DQuat::IDENTITY,
            centre,
            radius,
        };
        let mut rig = CameraRig::new(CameraMode::Chase, 55f32.to_radians());
        rig.follow(&target, 0.0);
        let camera = rig.camera(&target);
        let viewport = Viewport {
            width: 640,
            height: 360,
        };
        let trail = [Vec3::new(-1600.0, 0.0, 150.0)];
        let stats = b.build(&FrameSpec {
            camera: &camera,
            viewport,
            plane_position: position,
            plane_attitude: EulerZyx::default(),
            ground_z: 0.0,
            trail: &trail,
            model: None,
        });
        assert_eq!(stats.edges_in as usize, b.edges_per_frame() + 1);
        assert!(stats.clipped > 50, "{stats}");
        assert!(stats.trivially_rejected > 1000, "{stats}");
        assert!(stats.trivially_accepted > 100, "{stats}");
        let scene = b.scene();
        assert_eq!((scene.width, scene.height), (640, 360));
        assert_eq!(
            scene.batches[batch::PLANE].segments.len(),
            b.plane().edges().len(),
            "the whole aircraft is in view"
        );
        assert!(!scene.batches[batch::GRID].segments.is_empty());
        assert!(!scene.batches[batch::HORIZON].segments.is_empty());
        assert_eq!(scene.batches[batch::TRAIL].segments.len(), 1);
        // Every segment lies in the image (the clipper's job).
        for s in scene.batches.iter().flat_map(|b| &b.segments) {
            for p in [s.a, s.b] {
                assert!(
                    (-0.01..=640.01).contains(&p.x) && (-0.01..=360.01).contains(&p.y),
                    "{p}"
                );
            }
        }
        // The horizon is level and above the middle of the picture seen from behind and above.
        let h = &scene.batches[batch::HORIZON].segments;
        let ys: Vec<f32> = h.iter().flat_map(|s| [s.a.y, s.b.y]).collect();
        let (lo, hi) = ys
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, u), &y| (l.min(y), u.max(y)));
        assert!(hi - lo < 2.0 && hi < 180.0, "{lo}..{hi}");

        // With the model's aircraft ahead: its trail is broken where the model restarts.
        let model_trail = [
            Vec3::new(-1490.0, 5.0, 150.0),
            Vec3::new(-1480.0, 5.0, 150.0),
            Vec3::new(-1470.0, 8.0, 150.0),
            Vec3::new(-1460.0, 8.0, 150.0),
        ];
        let stats = b.build(&FrameSpec {
            camera: &camera,
            viewport,
            plane_position: position,
            plane_attitude: EulerZyx::default(),
            ground_z: 0.0,
            trail: &trail,
            model: Some(ModelFrame {
                position: Vec3::new(-1450.0, 8.0, 150.0),
                attitude: EulerZyx::default(),
                trail: &model_trail,
                breaks: &[0, 2],
            }),
        });
        // 5 points, 4 joins, one of them across the restart at 2.
        let plane_edges = b.plane().edges().len();
        assert_eq!(
            stats.edges_in as usize,
            b.edges_per_frame() + 1 + plane_edges + 3
        );
        let scene = b.scene();
        assert_eq!(scene.batches[batch::MODEL_TRAIL].segments.len(), 3);
        assert!(!scene.batches[batch::MODEL_PLANE].segments.is_empty());
        assert_eq!(
            scene.batches[batch::MODEL_PLANE].color,
            colors::MODEL_AIRCRAFT
        );
    }
}
