//! Scenes: what a frame shows, built from meshes, poses and cameras into a [`LineScene`] of
//! clipped pixel segments. One room for every picture the program draws:
//!
//! * [`attitude`]: the one crossing between the aerospace angles people type and read and
//!   the viewer's z-y-x math;
//! * [`frame`]: a still of one model in a given attitude ([`ViewSpec`]), for `render`, the
//!   golden images and the benchmarks;
//! * [`builder::SceneBuilder`]: a frame of a flight over layers of world — the window's 10 km
//!   world, or a grid fitted to a recorded flight — with trails and, in comparisons, the
//!   flight model's aircraft;
//! * [`replay::ReplayScene`]: offscreen replay frames of a recorded flight (and comparison
//!   frames with the error strip);
//! * [`track`]: flights in the viewer's frame (poses between samples, the model's track);
//! * [`euler`]: pictures of Euler angles (elementary rotations, gimbal rings, gimbal lock,
//!   interpolation) and the [`euler::sheet`] that lays panels out in a grid;
//! * [`font`]: the stroke font of every caption and label (text as line segments);
//! * [`palette`]: the colours.
//!
//! Pure: no I/O. Drawing the scenes is [`crate::render`]'s job, writing them
//! [`crate::output`]'s.

pub mod attitude;
pub mod builder;
pub mod euler;
pub mod font;
pub mod overlay;
pub mod palette;
pub mod replay;
pub mod still;
pub mod track;

use crate::render::{LineBatch, LineScene};
use wireflight_geometry::camera::{CameraPreset, Projection, Subject};
use wireflight_geometry::clip::{ClipStats, Clipper, DepthRange, PlaneSet};
use wireflight_geometry::euler::EulerZyx;
use wireflight_geometry::mesh::{EdgeMesh, MeshProblem};
use wireflight_geometry::pipeline::{model_matrix, EdgeProjector, Viewport};

/// Why a recorded flight (and the model's flight beside it) cannot be drawn: by
/// [`replay::ReplayScene`], the fly-through's replay, and a [`track::ModelTrack`] made from a
/// comparison (by `wireflight-present`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ReplayError {
    /// The flight has no samples.
    #[error("the flight has no samples")]
    EmptyFlight,
    /// The flight spans more than a ground grid can be built for in `f32`.
    #[error("the flight's extent cannot be drawn (no ground grid fits it)")]
    NoGround(#[source] MeshProblem),
    /// The comparison was made over some windows only, not sample by sample.
    #[error("the comparison does not predict every sample of the flight (use all windows)")]
    PartialComparison,
}

/// Everything that decides one still frame of one model, apart from the model itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSpec {
    /// Attitude of the model (body → world).
    pub attitude: EulerZyx,
    /// Camera placement.
    pub camera: CameraPreset,
    /// Parallel instead of perspective projection.
    pub orthographic: bool,
    /// Vertical field of view, degrees (perspective), in (0, 180).
    pub fov_y_deg: f64,
    /// Output image.
    pub viewport: Viewport,
    /// Clip-space depth convention (wgpu's 0..w unless testing OpenGL's −w..w).
    pub depth: DepthRange,
    /// Camera pan `[right, up]` in bounding radii (moves the model the other way in the frame).
    pub pan: [f32; 2],
    /// The line clipper.
    pub clipper: Clipper,
    /// Extra clip planes for cut-away views, in the model's (body) coordinates: each keeps
    /// `a·x + b·y + c·z + d ≥ 0`, so the cut stays fixed to the aircraft at any attitude.
    pub clip_planes: PlaneSet,
    /// Hidden-line drawing by back-face culling (meshes with faces; see
    /// [`EdgeProjector::set_hidden_line`]).
    pub hidden_line: bool,
}

impl Default for ViewSpec {
    fn default() -> Self {
        Self {
            attitude: EulerZyx::default(),
            camera: CameraPreset::Chase,
            orthographic: false,
            fov_y_deg: 50.0,
            viewport: Viewport {
                width: 800,
                height: 600,
            },
            depth: DepthRange::ZeroToOne,
            pan: [0.0, 0.0],
            clipper: Clipper::Blinn,
            clip_planes: PlaneSet::EMPTY,
            hidden_line: false,
        }
    }
}

/// Build the frame: model at the world origin in the given attitude, seen by the preset
/// camera, clipped and projected. Returns the line scene and the clipper's counts. A model
/// whose bounding sphere is wholly outside the view (e.g. panned away) is rejected whole.
pub fn frame(mesh: &EdgeMesh, spec: &ViewSpec) -> (LineScene, ClipStats) {
    let (centre, radius) = mesh.bounding_sphere();
    let subject = Subject {
        position: glam::Vec3::ZERO,
        attitude: spec.attitude,
        centre,
        radius,
    };
    let mut camera = spec
        .camera
        .camera(&subject, (spec.fov_y_deg as f32).to_radians())
        .panned(spec.pan[0] * radius, spec.pan[1] * radius);
    if spec.orthographic {
        if let Projection::Perspective { near, far, .. } = camera.projection {
            camera.projection = Projection::Orthographic {
                half_height: 1.1 * radius,
                near,
                far,
            };
        }
    }
    let clip_from_model = camera.clip_from_world(spec.viewport.aspect(), spec.depth)
        * model_matrix(subject.position, spec.attitude);
    let mut segments = Vec::with_capacity(mesh.edges().len());
    let mut projector = EdgeProjector::new(spec.clipper, spec.depth);
    projector.set_planes(spec.clip_planes);
    projector.set_hidden_line(spec.hidden_line);
    let stats = projector.project_bounded(
        mesh,
        Some((centre, radius)),
        clip_from_model,
        spec.viewport,
        &mut segments,
    );
    let scene = LineScene {
        width: spec.viewport.width,
        height: spec.viewport.height,
        background: palette::BACKGROUND,
        batches: vec![LineBatch {
            color: palette::AIRCRAFT,
            segments,
        }],
    };
    (scene, stats)
}
