//! Replaying a recorded flight offscreen: the aircraft flying its path, seen by a chase
//! camera, with the trail of where it has been and a ground grid fitted to the flight; in a
//! comparison also the flight model's aircraft and trail and a strip of the error over time.
//! One [`LineScene`] per call of [`ReplayScene::frame`]; the frames are drawn and written by
//! [`crate::output`]. Pure: no I/O.

use glam::Vec3;

use super::attitude::aerospace_degrees;
use super::builder::{FrameSpec, Layer, Placement, SceneBuilder};
use super::overlay::{
    corner_block, cut_out, edge_arrow, error_strip, locate, sample_dots, smooth_path, state_lines,
    strip_top, text_height, Corner, Rect, TextLine,
};
use super::palette;
use super::track::{model_frame, pose_at, ModelTrack};
use super::ReplayError;
use crate::figures::three_figures;
use crate::render::{LineBatch, LineScene};
use wireflight_data::FlightData;
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
    /// aircraft; chase camera; in the top corners the time, the aircraft's aerospace attitude,
    /// its speed and altitude. With a model track: also the model's trail (broken at window
    /// restarts) and aircraft (an arrow at the edge points to it when it is out of sight), the
    /// legend of the colours, and a labelled strip along the bottom plotting its position
    /// error over time (scaled to this model's errors) with a cursor at `t`. No text lies over
    /// the drawing: the 3D lines are cut away under every block of text and the strip.
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
        // In a comparison the 3D drawing takes the frame above the strip, so the strip never
        // lies over it (and the aircraft is centred in what is left).
        let view3d = if self.model.is_some() {
            Viewport {
                width: viewport.width,
                height: (strip_top(viewport).floor() as u32).clamp(1, viewport.height),
            }
        } else {
            viewport
        };
        let stats = self.builder.build(&FrameSpec {
            camera: &camera,
            viewport: view3d,
            aircraft_position: pos.as_vec3(),
            aircraft_attitude: attitude,
            ground_z: self.ground_z,
            trail: &self.smooth[..upto],
            model,
        });
        let clip_from_world = camera.clip_from_world(view3d.aspect(), DepthRange::ZeroToOne);
        let mut dots = Vec::new();
        sample_dots(
            &self.path[upto.saturating_sub(MAX_DOTS)..upto],
            clip_from_world,
            view3d,
            &mut dots,
        );
        let mut text = Vec::new();
        let mut swatches = Vec::new();
        let (t0, t1) = (self.data.time[0], self.data.time[self.data.len() - 1]);
        let altitude = pos.z + self.data.meta.altitude_m.unwrap_or(0.0);
        let (left, mut right) = state_lines(
            t - t0,
            t1 - t0,
            aerospace_degrees(attitude),
            speed_at(self.data, t),
            altitude,
        );
        if self.model.is_some() {
            right.push(TextLine {
                text: "measured".into(),
                swatch: Some(palette::AIRCRAFT),
            });
            right.push(TextLine {
                text: "model".into(),
                swatch: Some(palette::MODEL_AIRCRAFT),
            });
        }
        let mut boxes = vec![
            corner_block(&left, Corner::TopLeft, viewport, &mut text, &mut swatches),
            corner_block(&right, Corner::TopRight, viewport, &mut text, &mut swatches),
        ];
        let th = text_height(viewport);
        let mut strip = Vec::new();
        let mut arrow = Vec::new();
        if let (Some(track), Some(m)) = (&self.model, model) {
            let strip_box = error_strip(
                &track.time,
                &track.error_m,
                track.strip_scale_m,
                t,
                viewport,
                "position error, m (model − measured)",
                &mut strip,
            );
            if let Some(r) = strip_box {
                boxes.push(r);
            }
            if let Err(direction) = locate(m.position, clip_from_world, view3d) {
                let away = (m.position - pos.as_vec3()).length();
                let top = boxes[..2].iter().map(|b| b.max.y).fold(0.0, f32::max) + 0.5 * th;
                let bottom = view3d.height as f32 - 0.5 * th;
                let area = Rect {
                    min: glam::Vec2::new(0.5 * th, top),
                    max: glam::Vec2::new(viewport.width as f32 - 0.5 * th, bottom.max(top + th)),
                };
                let label = format!("model {} m", three_figures(f64::from(away)));
                boxes.push(edge_arrow(direction, &label, area, viewport, &mut arrow));
            }
        }
        // Text is never over the drawing: the 3D lines go from under the text and the strip.
        let padded: Vec<Rect> = boxes.iter().map(|b| b.grown(0.3 * th)).collect();
        let scene = self.builder.scene_mut();
        scene.height = viewport.height;
        for batch in &mut scene.batches {
            cut_out(&mut batch.segments, &padded);
        }
        cut_out(&mut dots, &padded);
        for (color, segments) in [
            (palette::SAMPLE_DOTS, dots),
            (palette::ERROR_STRIP, strip),
            (palette::MODEL_AIRCRAFT, arrow),
            (palette::TEXT, text),
        ]
        .into_iter()
        .chain(swatches)
        {
            if !segments.is_empty() {
                scene.batches.push(LineBatch { color, segments });
            }
        }
        (self.builder.scene(), stats)
    }
}

/// The aircraft's speed at `t`, m/s: from the recorded velocity where the data have it (between
/// samples linearly), else from the positions of the samples around `t`; `None` for a flight
/// of one sample without velocity.
pub fn speed_at(data: &FlightData, t: f64) -> Option<f64> {
    let n = data.len();
    let i = data
        .time
        .partition_point(|&s| s <= t)
        .clamp(1, n.max(2) - 1);
    if n < 2 {
        return data.vel_ned.as_ref().map(|v| v[0].length());
    }
    let (i0, i1) = (i - 1, i);
    let span = data.time[i1] - data.time[i0];
    let f = if span > 0.0 {
        ((t - data.time[i0]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    match &data.vel_ned {
        Some(v) => Some(v[i0].lerp(v[i1], f).length()),
        None if span > 0.0 => Some((data.pos_ned[i1] - data.pos_ned[i0]).length() / span),
        None => None,
    }
}
