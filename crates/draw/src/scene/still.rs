//! A still with a world around the model, so that attitude can be seen: the ground as a grid
//! below and the horizon ring at eye height (`--world grid`), or the window's whole world of
//! landmarks (`--world full`). `--world none` is [`super::frame`], the model alone. Pure: no
//! I/O.

use glam::Vec3;

use super::builder::{FrameSpec, Layer, Placement, SceneBuilder};
use super::{frame, palette, ViewSpec};
use crate::render::LineScene;
use wireflight_geometry::camera::Projection;
use wireflight_geometry::camera::Subject;
use wireflight_geometry::clip::ClipStats;
use wireflight_geometry::mesh::world::{ground_grid, horizon_ring, World, WorldSpec};
use wireflight_geometry::mesh::EdgeMesh;

/// What surrounds the model in a still.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StillWorld {
    /// The model alone.
    None,
    /// A ground grid below and the horizon.
    #[default]
    Grid,
    /// The fly-through window's world: grid, horizon, hills, runway, masts, hangars.
    Full,
}

/// How far below the model the ground is, in bounding radii (grid world).
pub const GROUND_RADII: f32 = 8.0;

/// Height above the ground of the full world's model, m (about a circuit's height).
pub const FULL_WORLD_HEIGHT_M: f32 = 120.0;

/// The still of `mesh` as `spec` says, in `world`. Returns the line scene (the world's
/// batches first, the model on top) and the clipper's counts for all of it.
///
/// The depth range and clipper of `spec` are used for the model alone ([`StillWorld::None`]);
/// with a world the frame is built like the window's, for wgpu's 0 ≤ z ≤ w.
pub fn still(mesh: &EdgeMesh, spec: &ViewSpec, world: StillWorld) -> (LineScene, ClipStats) {
    let (centre, radius) = mesh.bounding_sphere();
    let (layers, ground_z) = match world {
        StillWorld::None => return frame(mesh, spec),
        StillWorld::Grid => {
            let spacing = 4.0 * radius;
            (
                vec![
                    Layer {
                        mesh: ground_grid(60.0 * spacing, spacing),
                        placement: Placement::Ground,
                        color: palette::GRID,
                    },
                    Layer {
                        mesh: horizon_ring(256),
                        placement: Placement::Horizon,
                        color: palette::HORIZON,
                    },
                ],
                -GROUND_RADII * radius,
            )
        }
        StillWorld::Full => (
            Layer::world(World::new(&WorldSpec::default())),
            -FULL_WORLD_HEIGHT_M,
        ),
    };
    let subject = Subject {
        position: Vec3::ZERO,
        attitude: spec.attitude,
        centre,
        radius,
    };
    let mut camera = spec
        .camera
        .camera(&subject, (spec.fov_y_deg as f32).to_radians())
        .panned(spec.pan[0] * radius, spec.pan[1] * radius);
    // Far enough to see the horizon over the whole world.
    let far_needed = match world {
        StillWorld::Full => 20_000.0,
        _ => 2_000.0 * radius,
    };
    camera.projection = match camera.projection {
        Projection::Perspective { fov_y, near, far } => {
            if spec.orthographic {
                Projection::Orthographic {
                    half_height: 1.1 * radius,
                    near,
                    far: far.max(far_needed),
                }
            } else {
                Projection::Perspective {
                    fov_y,
                    near,
                    far: far.max(far_needed),
                }
            }
        }
        other => other,
    };
    let mut builder = SceneBuilder::new(mesh.clone(), layers, spec.clipper);
    let stats = builder.build(&FrameSpec {
        camera: &camera,
        viewport: spec.viewport,
        aircraft_position: Vec3::ZERO,
        aircraft_attitude: spec.attitude,
        ground_z,
        trail: &[],
        model: None,
    });
    let mut scene = builder.scene().clone();
    scene.batches.retain(|b| !b.segments.is_empty());
    (scene, stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wireflight_geometry::camera::CameraPreset;
    use wireflight_geometry::euler::EulerZyx;
    use wireflight_geometry::mesh::plane::builtin_plane;

    /// The horizon's tilt in the picture: the angle of the longest horizon-coloured segment.
    fn horizon_tilt_deg(scene: &LineScene) -> f32 {
        let b = scene
            .batches
            .iter()
            .find(|b| b.color == palette::HORIZON)
            .expect("a horizon");
        let s = b
            .segments
            .iter()
            .max_by(|a, c| (a.b - a.a).length().total_cmp(&(c.b - c.a).length()))
            .unwrap();
        let d = s.b - s.a;
        let d = if d.x < 0.0 { -d } else { d };
        d.y.atan2(d.x).to_degrees()
    }

    #[test]
    fn a_cockpit_still_shows_the_roll_on_the_horizon() {
        let plane = builtin_plane();
        let spec = |roll: f64| ViewSpec {
            attitude: EulerZyx::from_degrees(0.0, 0.0, roll),
            camera: CameraPreset::Cockpit,
            ..ViewSpec::default()
        };
        let (level, _) = still(&plane, &spec(0.0), StillWorld::Grid);
        let (banked, _) = still(&plane, &spec(30.0), StillWorld::Grid);
        assert!(
            horizon_tilt_deg(&level).abs() < 1.0,
            "{}",
            horizon_tilt_deg(&level)
        );
        let tilt = horizon_tilt_deg(&banked);
        assert!((tilt.abs() - 30.0).abs() < 2.0, "{tilt}");
        assert_ne!(level, banked);
        // Without a world the model is alone: one batch, as `frame` draws it.
        let (alone, _) = still(&plane, &spec(30.0), StillWorld::None);
        assert_eq!(alone, frame(&plane, &spec(30.0)).0);
        let (full, _) = still(&plane, &ViewSpec::default(), StillWorld::Full);
        assert!(full.batches.len() > 3);
    }
}
