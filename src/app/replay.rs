//! Replaying recorded flights: the aircraft flying its path, seen by a chase camera, with the
//! trail of where it has been and a ground grid, one frame per 1/fps seconds.
//!
//! Flight data are in NED/FRD; the viewer is Z-up. Positions map by
//! [`crate::euler::viewer_from_ned`], attitudes by [`EulerZyx::from_aerospace`].

use std::path::Path;

use anyhow::{bail, Context};
use glam::{DQuat, DVec3, Vec2, Vec3, Vec4};

use crate::app::render::Rasterizer;
use crate::camera::{CameraPreset, Subject};
use crate::clip::{ClipStats, DepthRange};
use crate::euler::{viewer_from_ned, EulerZyx};
use crate::flight::data::FlightData;
use crate::mesh::{EdgeMesh, EdgeMeshBuilder};
use crate::pipeline::{model_matrix, polyline_edges, project_clip_edges, EdgeProjector, Viewport};
use crate::render::{palette, LineBatch, LineScene, Rgba, Segment2};

/// Colour of the flown trail.
pub const TRAIL: Rgba = [255, 200, 60, 255];
/// The model's aircraft in a comparison overlay.
pub const MODEL_AIRCRAFT: Rgba = [255, 90, 200, 255];
/// The model's trail.
pub const MODEL_TRAIL: Rgba = [170, 60, 140, 255];
/// The error-over-time strip at the bottom of an overlay frame.
pub const ERROR_STRIP: Rgba = [220, 220, 220, 255];

/// The model's flight beside the measured one, for comparison overlays: the multiple-shooting
/// prediction (the model restarted from the data at each window start), in the viewer frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelTrack {
    /// Sample times, s (the data's).
    pub time: Vec<f64>,
    /// Predicted positions, viewer frame.
    pub path: Vec<Vec3>,
    /// Predicted attitudes, viewer angles.
    pub attitude: Vec<EulerZyx>,
    /// Sample indices where a window starts (the prediction jumps back to the data there).
    pub window_starts: Vec<usize>,
    /// Position error |predicted − measured| per sample, m.
    pub error_m: Vec<f64>,
    /// Error at the top of the error strip, m (default: the largest error). Give two tracks
    /// the same scale to see the error fall between them.
    pub strip_scale_m: f64,
}

impl ModelTrack {
    /// From a comparison of `data` made over all its windows (every sample predicted).
    ///
    /// # Errors
    /// A comparison that does not cover the flight sample by sample.
    pub fn from_comparison(
        data: &FlightData,
        comparison: &crate::analysis::compare::Comparison,
    ) -> anyhow::Result<Self> {
        let prediction = &comparison.prediction;
        let n = prediction.index.len();
        if n == 0 || n > data.len() || prediction.index.iter().enumerate().any(|(k, &i)| k != i) {
            bail!("the comparison does not predict every sample of the flight (use all windows)");
        }
        let window_starts = comparison.windows.iter().map(|w| w.samples.0).collect();
        let path: Vec<Vec3> = prediction
            .pos_ned
            .iter()
            .map(|p| viewer_from_ned(*p).as_vec3())
            .collect();
        let error_m: Vec<f64> = (0..n)
            .map(|k| (prediction.pos_ned[k] - data.pos_ned[k]).length())
            .collect();
        Ok(Self {
            strip_scale_m: error_m.iter().copied().fold(0.0, f64::max),
            time: data.time[..n].to_vec(),
            path,
            attitude: prediction
                .attitude
                .iter()
                .map(|a| EulerZyx::from_aerospace(*a))
                .collect(),
            window_starts,
            error_m,
        })
    }

    /// Index of the last sample at or before `t`.
    fn sample_at(&self, t: f64) -> usize {
        self.time
            .partition_point(|&s| s <= t)
            .clamp(1, self.time.len())
            - 1
    }
}

/// Position (viewer frame) and attitude (viewer angles) of the aircraft at time `t`,
/// interpolated between samples (attitude by quaternion slerp). Without attitude in the data,
/// the nose points along the velocity, wings level.
pub fn pose_at(data: &FlightData, t: f64) -> (DVec3, EulerZyx) {
    let n = data.len();
    let i = data
        .time
        .partition_point(|&s| s <= t)
        .clamp(1, n.max(2) - 1);
    let (i0, i1) = if n < 2 { (0, 0) } else { (i - 1, i) };
    let span = data.time[i1] - data.time[i0];
    let f = if span > 0.0 {
        ((t - data.time[i0]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let pos_ned = data.pos_ned[i0].lerp(data.pos_ned[i1], f);
    let attitude_ned = match &data.attitude {
        Some(att) => {
            let q0 = DQuat::from_mat3(&att[i0].to_matrix());
            let q1 = DQuat::from_mat3(&att[i1].to_matrix());
            EulerZyx::from_matrix(glam::DMat3::from_quat(q0.slerp(q1, f))).0
        }
        None => {
            let v = match &data.vel_ned {
                Some(v) => v[i0].lerp(v[i1], f),
                None => data.pos_ned[i1] - data.pos_ned[i0],
            };
            EulerZyx::new(v.y.atan2(v.x), (-v.z).atan2(v.x.hypot(v.y)), 0.0)
        }
    };
    (
        viewer_from_ned(pos_ned),
        EulerZyx::from_aerospace(attitude_ned),
    )
}

/// A square ground grid at z = `z` (viewer frame) covering `min..max` (x, y) plus a margin,
/// with about `cells` cells along the longer side; each cell side is its own edge so the
/// clipper sees a realistic edge count.
pub fn ground_grid(min: Vec3, max: Vec3, z: f32, cells: u32) -> EdgeMesh {
    let margin = 0.25 * (max - min).max_element().max(200.0);
    let (lo, hi) = (min - margin, max + margin);
    let step = ((hi - lo).max_element() / cells as f32).max(1.0);
    let nx = ((hi.x - lo.x) / step).ceil() as i32;
    let ny = ((hi.y - lo.y) / step).ceil() as i32;
    let mut b = EdgeMeshBuilder::new();
    let p = |i: i32, j: i32| Vec3::new(lo.x + i as f32 * step, lo.y + j as f32 * step, z);
    for i in 0..=nx {
        for j in 0..=ny {
            if i < nx {
                b.edge_between(p(i, j), p(i + 1, j)).expect("finite grid");
            }
            if j < ny {
                b.edge_between(p(i, j), p(i, j + 1)).expect("finite grid");
            }
        }
    }
    b.build().expect("grid has edges")
}

/// Everything needed to draw frames of one flight.
pub struct FlightScene<'a> {
    /// The flight.
    pub data: &'a FlightData,
    /// The aircraft model (body axes: nose +X, left wing +Y, up +Z).
    pub mesh: &'a EdgeMesh,
    /// Ground grid (viewer frame).
    pub grid: EdgeMesh,
    /// Flight path in the viewer frame, one point per sample.
    pub path: Vec<Vec3>,
    /// The model's flight, drawn beside the measured one when present.
    pub model: Option<ModelTrack>,
    projector: EdgeProjector,
    clip_scratch: Vec<Vec4>,
    edge_scratch: Vec<[u32; 2]>,
}

impl<'a> FlightScene<'a> {
    /// Prepare a flight for drawing: path in the viewer frame, grid at the ground (down = 0,
    /// or under the lowest point of the flight if it goes below).
    ///
    /// # Errors
    /// Empty flights.
    pub fn new(data: &'a FlightData, mesh: &'a EdgeMesh) -> anyhow::Result<Self> {
        if data.is_empty() {
            bail!("the flight has no samples");
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
        let ground = min.z.min(0.0) - 1.0;
        Ok(Self {
            data,
            mesh,
            grid: ground_grid(min, max, ground, 60),
            path,
            model: None,
            projector: EdgeProjector::new(),
            clip_scratch: Vec::new(),
            edge_scratch: Vec::new(),
        })
    }

    /// Draw the model's flight beside the measured one (see [`ModelTrack`]).
    pub fn with_model(mut self, track: ModelTrack) -> Self {
        self.model = Some(track);
        self
    }

    /// The frame at time `t`: grid, trail up to `t`, aircraft; chase camera. With a model
    /// track: also the model's trail (broken at window restarts) and aircraft, and a strip
    /// along the bottom plotting its position error over time with a cursor at `t`.
    pub fn frame(&mut self, t: f64, viewport: Viewport) -> (LineScene, ClipStats) {
        let (pos, attitude) = pose_at(self.data, t);
        let (centre, radius) = self.mesh.bounding_sphere();
        let subject = Subject {
            position: pos.as_vec3(),
            attitude,
            centre,
            radius,
        };
        let camera = CameraPreset::Chase.camera(&subject, 55f32.to_radians());
        let depth = DepthRange::ZeroToOne;
        let clip_from_world = camera.clip_from_world(viewport.aspect(), depth);

        let mut stats = ClipStats::default();
        let mut grid = Vec::new();
        stats.merge(&self.projector.project(
            &self.grid,
            clip_from_world,
            depth,
            viewport,
            &mut grid,
        ));

        // Trail: the recorded path up to now, ending at the aircraft.
        let upto = self.data.time.partition_point(|&s| s <= t);
        self.clip_scratch.clear();
        self.clip_scratch.extend(
            self.path[..upto]
                .iter()
                .chain(std::iter::once(&pos.as_vec3()))
                .map(|p| clip_from_world * p.extend(1.0)),
        );
        polyline_edges(self.clip_scratch.len(), &[], &mut self.edge_scratch);
        let mut trail = Vec::new();
        stats.merge(&project_clip_edges(
            &self.clip_scratch,
            &self.edge_scratch,
            depth,
            viewport,
            &mut trail,
        ));

        let mut plane = Vec::new();
        let clip_from_model = clip_from_world * model_matrix(pos.as_vec3(), attitude);
        stats.merge(&self.projector.project(
            self.mesh,
            clip_from_model,
            depth,
            viewport,
            &mut plane,
        ));

        let mut batches = vec![
            LineBatch {
                color: palette::GRID,
                segments: grid,
            },
            LineBatch {
                color: TRAIL,
                segments: trail,
            },
        ];
        if let Some(track) = &self.model {
            let k = track.sample_at(t);
            // The model's trail: consecutive predicted samples, not across a restart.
            self.clip_scratch.clear();
            self.clip_scratch.extend(
                track.path[..=k]
                    .iter()
                    .map(|p| clip_from_world * p.extend(1.0)),
            );
            polyline_edges(k + 1, &track.window_starts, &mut self.edge_scratch);
            let mut model_trail = Vec::new();
            stats.merge(&project_clip_edges(
                &self.clip_scratch,
                &self.edge_scratch,
                depth,
                viewport,
                &mut model_trail,
            ));
            let mut model_plane = Vec::new();
            let clip_from_model = clip_from_world * model_matrix(track.path[k], track.attitude[k]);
            stats.merge(&self.projector.project(
                self.mesh,
                clip_from_model,
                depth,
                viewport,
                &mut model_plane,
            ));
            batches.push(LineBatch {
                color: MODEL_TRAIL,
                segments: model_trail,
            });
            batches.push(LineBatch {
                color: MODEL_AIRCRAFT,
                segments: model_plane,
            });
            batches.push(LineBatch {
                color: ERROR_STRIP,
                segments: error_strip(track, t, viewport),
            });
        }
        batches.push(LineBatch {
            color: palette::MODEL,
            segments: plane,
        });
        let scene = LineScene {
            width: viewport.width,
            height: viewport.height,
            background: palette::BACKGROUND,
            batches,
        };
        (scene, stats)
    }
}

/// The position error over the whole flight as a polyline in the bottom sixth of the frame
/// (0 m at the bottom edge, `strip_scale_m` at the top of the strip), a baseline, and a
/// vertical cursor at `t`. Pixel coordinates; one segment per pixel column at most.
fn error_strip(track: &ModelTrack, t: f64, viewport: Viewport) -> Vec<Segment2> {
    let (w, h) = (viewport.width as f32, viewport.height as f32);
    let (top, bottom) = (h * (5.0 / 6.0), h - 2.0);
    let (left, right) = (4.0, w - 4.0);
    let (t0, t1) = (track.time[0], *track.time.last().expect("non-empty"));
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

/// Write one PNG per frame (`frame_00000.png`, …) into `dir` (created if needed).
/// Returns the number of frames and the summed clip counts.
///
/// # Errors
/// Bad fps, unwritable directory, drawing errors.
pub fn write_frames(
    data: &FlightData,
    model: Option<ModelTrack>,
    mesh: &EdgeMesh,
    viewport: Viewport,
    fps: f64,
    dir: &Path,
    rasterizer: &mut Rasterizer,
) -> anyhow::Result<(usize, ClipStats)> {
    if !(fps > 0.0 && fps <= 1000.0) {
        bail!("--fps {fps} must be in (0, 1000]");
    }
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let mut scene = FlightScene::new(data, mesh)?;
    if let Some(track) = model {
        scene = scene.with_model(track);
    }
    let (t0, t1) = (data.time[0], data.time[data.len() - 1]);
    let frames = ((t1 - t0) * fps).floor() as usize + 1;
    let mut total = ClipStats::default();
    for k in 0..frames {
        let (lines, stats) = scene.frame(t0 + k as f64 / fps, viewport);
        total.merge(&stats);
        let image = rasterizer.draw(&lines)?;
        let path = dir.join(format!("frame_{k:05}.png"));
        crate::fsio::write_atomic(&path, &image.encode_png().context("encoding PNG")?)?;
    }
    Ok((frames, total))
}
