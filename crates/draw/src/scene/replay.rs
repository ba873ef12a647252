//! Replaying a recorded flight offscreen: the aircraft flying its path, seen by a chase
//! camera, with the trail of where it has been and a ground grid fitted to the flight; in a
//! comparison also the flight model's aircraft and trail and a strip of the error over time.
//! One [`LineScene`] per call of [`ReplayScene::frame`]; the frames are drawn and written by
//! [`crate::output`]. Pure: no I/O.

use glam::Vec3;

use super::builder::{FrameSpec, Layer, Placement, SceneBuilder};
use super::overlay::{edge_arrow, error_strip, locate, sample_dots, smooth_path, time_stamp};
use super::palette;
use super::track::{model_frame, pose_at, ModelTrack};
use super::ReplayError;
use crate::figures::three_figures;
use crate::render::{LineBatch, LineScene};
use wireflight_flight::data::FlightData;
use wireflight_geometry::camera::{CameraPreset, Subject};
use wireflight_geometry::clip::{ClipStats, Clipper, DepthRange};
use wireflight_geometry::euler::viewer_from_ned;
use wireflight_geometry::mesh::world::grid_around;
use wireflight_geometry::mesh::EdgeMesh;
use wireflight_geometry::pipeline::Viewport;

/// Cells of the ground grid along the longer side of the flight.
const GRID_CELLS: u32 = 60;
/// Vertical field of view of the chase camera, degrees.
const CHASE_FOV_DEG: f32 = 55.0;
/// Half-width of the trail's smoothing window, s.
const TRAIL_SMOOTHING_S: f64 = 0.3;
/// Most raw samples drawn as dots (the latest).
const MAX_DOTS: usize = 3000;

/// Everything needed to draw frames of one flight.
pub struct ReplayScene<'a> {
    data: &'a FlightData,
    builder: SceneBuilder,
    /// Flight path in the viewer frame, one point per sample, as measured.
    path: Vec<Vec3>,
    /// The same smoothed (the trail follows it; the raw samples are dots).
    smooth: Vec<Vec3>,
    ground_z: f32,
    model: Option<ModelTrack>,
}

impl<'a> ReplayScene<'a> {
    /// Prepare a flight for drawing: path in the viewer frame, a grid on the ground (down = 0,
    /// or under the lowest point of the flight if it goes below).
    ///
    /// # Errors
    /// Empty flights; flights whose extent cannot be drawn in `f32` (a grid cannot be built).
    pub fn new(
        data: &'a FlightData,
        aircraft: &EdgeMesh,
        clipper: Clipper,
    ) -> Result<Self, ReplayError> {
        if data.is_empty() {
            return Err(ReplayError::EmptyFlight);
        }
        let path: Vec<Vec3> = data
            .pos_ned
            .iter()
            .map(|p| viewer_from_ned(*p).as_vec3())
            .collect();
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in &path {
            min = min.min(*p);
            max = max.max(*p);
        }
        let grid = grid_around(min.truncate(), max.truncate(), GRID_CELLS)
            .map_err(ReplayError::NoGround)?;
        let layers = vec![Layer {
            mesh: grid,
            placement: Placement::Ground,
            color: palette::GRID,
        }];
        Ok(Self {
            data,
            builder: SceneBuilder::new(aircraft.clone(), layers, clipper),
            smooth: smooth_path(&data.time, &path, TRAIL_SMOOTHING_S),
            path,
            ground_z: min.z.min(0.0) - 1.0,
            model: None,
        })
    }

    /// Draw the flight model's flight beside the measured one (see [`ModelTrack`]).
    pub fn with_model(mut self, track: ModelTrack) -> Self {
        self.model = Some(track);
        self
    }

    /// The frame at time `t`: grid, trail up to `t` (smoothed, the raw samples as faint dots),
    /// aircraft; chase camera; the time stamp. With a model track: also the model's trail
    /// (broken at window restarts) and aircraft (an arrow at the edge points to it when it is
    /// out of sight), and a labelled strip along the bottom plotting its position error over
    /// time with a cursor at `t`.
    pub fn frame(&mut self, t: f64, viewport: Viewport) -> (&LineScene, ClipStats) {
        let (pos, attitude) = pose_at(self.data, t);
        let (centre, radius) = self.builder.aircraft().bounding_sphere();
        let subject = Subject {
            position: pos.as_vec3(),
            attitude,
            centre,
            radius,
        };
        let camera = CameraPreset::Chase.camera(&subject, CHASE_FOV_DEG.to_radians());
        let upto = self.data.time.partition_point(|&s| s <= t);
        let model = self.model.as_ref().map(|track| model_frame(track, t));
        let stats = self.builder.build(&FrameSpec {
            camera: &camera,
            viewport,
            aircraft_position: pos.as_vec3(),
            aircraft_attitude: attitude,
            ground_z: self.ground_z,
            trail: &self.smooth[..upto],
            model,
        });
        let clip_from_world = camera.clip_from_world(viewport.aspect(), DepthRange::ZeroToOne);
        let mut dots = Vec::new();
        sample_dots(
            &self.path[upto.saturating_sub(MAX_DOTS)..upto],
            clip_from_world,
            viewport,
            &mut dots,
        );
        let mut text = Vec::new();
        let (t0, t1) = (self.data.time[0], self.data.time[self.data.len() - 1]);
        time_stamp(t - t0, t1 - t0, viewport, &mut text);
        let mut strip = Vec::new();
        let mut arrow = Vec::new();
        if let (Some(track), Some(m)) = (&self.model, model) {
            error_strip(
                &track.time,
                &track.error_m,
                track.strip_scale_m,
                t,
                viewport,
                "POSITION ERROR, M (MODEL - MEASURED)",
                &mut strip,
            );
            if let Err(direction) = locate(m.position, clip_from_world, viewport) {
                let away = (m.position - pos.as_vec3()).length();
                edge_arrow(
                    direction,
                    &format!("MODEL {} M", three_figures(f64::from(away))),
                    viewport,
                    &mut arrow,
                );
            }
        }
        let scene = self.builder.scene_mut();
        for (color, segments) in [
            (palette::SAMPLE_DOTS, dots),
            (palette::ERROR_STRIP, strip),
            (palette::MODEL_AIRCRAFT, arrow),
            (palette::TEXT, text),
        ] {
            if !segments.is_empty() {
                scene.batches.push(LineBatch { color, segments });
            }
        }
        (self.builder.scene(), stats)
    }
}
