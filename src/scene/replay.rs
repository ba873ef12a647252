//! Replaying a recorded flight offscreen: the aircraft flying its path, seen by a chase
//! camera, with the trail of where it has been and a ground grid fitted to the flight; in a
//! comparison also the flight model's aircraft and trail and a strip of the error over time.
//! One [`LineScene`] per call of [`ReplayScene::frame`]; the frames are drawn and written by
//! [`crate::output`]. Pure: no I/O.

use anyhow::Context;
use glam::{Vec2, Vec3};

use super::builder::{FrameSpec, Layer, Placement, SceneBuilder};
use super::palette;
use super::track::{model_frame, pose_at, ModelTrack};
use crate::camera::{CameraPreset, Subject};
use crate::clip::{ClipStats, Clipper};
use crate::euler::viewer_from_ned;
use crate::flight::data::FlightData;
use crate::mesh::world::grid_around;
use crate::mesh::EdgeMesh;
use crate::pipeline::Viewport;
use crate::render::{LineBatch, LineScene, Segment2};

/// Cells of the ground grid along the longer side of the flight.
const GRID_CELLS: u32 = 60;
/// Vertical field of view of the chase camera, degrees.
const CHASE_FOV_DEG: f32 = 55.0;

/// Everything needed to draw frames of one flight.
pub struct ReplayScene<'a> {
    data: &'a FlightData,
    builder: SceneBuilder,
    /// Flight path in the viewer frame, one point per sample.
    path: Vec<Vec3>,
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
    ) -> anyhow::Result<Self> {
        if data.is_empty() {
            anyhow::bail!("the flight has no samples");
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
            .context("the flight's extent cannot be drawn (no ground grid fits it)")?;
        let layers = vec![Layer {
            mesh: grid,
            placement: Placement::Ground,
            color: palette::GRID,
        }];
        Ok(Self {
            data,
            builder: SceneBuilder::new(aircraft.clone(), layers, clipper),
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

    /// The frame at time `t`: grid, trail up to `t`, aircraft; chase camera. With a model
    /// track: also the model's trail (broken at window restarts) and aircraft, and a strip
    /// along the bottom plotting its position error over time with a cursor at `t`.
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
        let stats = self.builder.build(&FrameSpec {
            camera: &camera,
            viewport,
            aircraft_position: pos.as_vec3(),
            aircraft_attitude: attitude,
            ground_z: self.ground_z,
            trail: &self.path[..upto],
            model: self.model.as_ref().map(|track| model_frame(track, t)),
        });
        if let Some(track) = &self.model {
            let strip = error_strip(track, t, viewport);
            self.builder.scene_mut().batches.push(LineBatch {
                color: palette::ERROR_STRIP,
                segments: strip,
            });
        }
        (self.builder.scene(), stats)
    }
}

/// The position error over the whole flight as a polyline in the bottom sixth of the frame
/// (0 m at the bottom edge, `strip_scale_m` at the top of the strip), a baseline, and a
/// vertical cursor at `t`. Pixel coordinates; one segment per pixel column at most.
fn error_strip(track: &ModelTrack, t: f64, viewport: Viewport) -> Vec<Segment2> {
    let (w, h) = (viewport.width as f32, viewport.height as f32);
    let (top, bottom) = (h * (5.0 / 6.0), h - 2.0);
    let (left, right) = (4.0, w - 4.0);
    let (Some(&t0), Some(&t1)) = (track.time.first(), track.time.last()) else {
        return Vec::new();
    };
    let span = (t1 - t0).max(1e-9);
    let peak = track.strip_scale_m.max(1e-9);
    let x_of = |s: f64| left + ((s - t0) / span) as f32 * (right - left);
    let y_of = |e: f64| bottom - (e / peak).min(1.0) as f32 * (bottom - top);
    let mut out = Vec::with_capacity(viewport.width as usize + 2);
    out.push(Segment2 {
        a: Vec2::new(left, bottom),
        b: Vec2::new(right, bottom),
    });
    // Per pixel column, the largest error in it: spikes survive any decimation.
    let columns = (right - left).max(1.0) as usize;
    let mut column_max = vec![f64::NAN; columns + 1];
    for (s, e) in track.time.iter().zip(&track.error_m) {
        let c = ((x_of(*s) - left) as usize).min(columns);
        if column_max[c].is_nan() || *e > column_max[c] {
            column_max[c] = *e;
        }
    }
    let mut last: Option<Vec2> = None;
    for (c, e) in column_max.iter().enumerate() {
        if e.is_nan() {
            continue;
        }
        let p = Vec2::new(left + c as f32, y_of(*e));
        if let Some(q) = last {
            out.push(Segment2 { a: q, b: p });
        }
        last = Some(p);
    }
    let x = x_of(t.clamp(t0, t1));
    out.push(Segment2 {
        a: Vec2::new(x, top),
        b: Vec2::new(x, bottom),
    });
    out
}
