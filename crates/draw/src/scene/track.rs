//! Flights in the viewer's frame: the pose of a recorded aircraft at any time (interpolated
//! between samples), and the flight model's track beside it — the multiple-shooting
//! prediction, restarted from the data at each window start — with the pose of the model's
//! aircraft at any time (never interpolated across a restart). A track is made from a
//! comparison by `wireflight-present`'s `track::model_track`; here it is only drawn.
//!
//! Flight data are in NED/FRD; the viewer is Z-up. Positions map by
//! [`wireflight_geometry::euler::viewer_from_ned`], attitudes by [`EulerZyx::from_aerospace`]. Pure: no I/O.

use glam::{DQuat, DVec3, Vec3};

use super::builder::ModelFrame;
use wireflight_data::FlightData;
use wireflight_geometry::euler::{viewer_from_ned, EulerZyx};

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
    /// The largest error of the model this one corrects (the base model before `--add`), m;
    /// default: this track's own largest error. The strip is always scaled to this track's own
    /// errors; when this is larger, the strip's title line gives it (`before: peak 18.2 m`).
    pub strip_scale_m: f64,
}

impl ModelTrack {
    /// Index of the last sample at or before `t`.
    pub fn sample_at(&self, t: f64) -> usize {
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

/// The model's aircraft at time `t`: position and attitude interpolated between its samples
/// (not across a restart), its trail up to there.
pub fn model_frame(track: &ModelTrack, t: f64) -> ModelFrame<'_> {
    let n = track
        .path
        .len()
        .min(track.attitude.len())
        .min(track.time.len());
    if n == 0 {
        return ModelFrame {
            position: Vec3::ZERO,
            attitude: EulerZyx::default(),
            trail: &[],
            breaks: &[],
        };
    }
    let k = track.time[..n].partition_point(|&s| s <= t).clamp(1, n) - 1;
    let next = k + 1;
    let restart = track.window_starts.binary_search(&next).is_ok();
    let (position, attitude) = if next < n && !restart && t > track.time[k] {
        let span = track.time[next] - track.time[k];
        let f = if span > 0.0 {
            ((t - track.time[k]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = |e: EulerZyx| DQuat::from_mat3(&e.to_matrix());
        let q = q(track.attitude[k]).slerp(q(track.attitude[next]), f);
        (
            track.path[k].lerp(track.path[next], f as f32),
            EulerZyx::from_matrix(glam::DMat3::from_quat(q)).0,
        )
    } else {
        (track.path[k], track.attitude[k])
    };
    ModelFrame {
        position,
        attitude,
        trail: &track.path[..=k],
        breaks: &track.window_starts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four samples a second apart, the model restarted at the third.
    fn track() -> ModelTrack {
        ModelTrack {
            time: vec![0.0, 1.0, 2.0, 3.0],
            path: vec![
                Vec3::ZERO,
                Vec3::X * 10.0,
                Vec3::new(20.0, 5.0, 0.0),
                Vec3::new(30.0, 5.0, 0.0),
            ],
            attitude: vec![
                EulerZyx::default(),
                EulerZyx::new(0.2, 0.0, 0.0),
                EulerZyx::default(),
                EulerZyx::default(),
            ],
            window_starts: vec![0, 2],
            error_m: vec![0.0; 4],
            strip_scale_m: 1.0,
        }
    }

    #[test]
    fn the_model_aircraft_moves_between_samples_but_not_across_a_restart() {
        let t = track();
        let m = model_frame(&t, 0.5);
        assert_eq!(m.position, Vec3::X * 5.0);
        assert!((m.attitude.yaw - 0.1).abs() < 1e-9, "{:?}", m.attitude);
        assert_eq!(m.trail.len(), 1);
        // Between the last sample of a window and the restart: held, not slid across.
        let m = model_frame(&t, 1.5);
        assert_eq!(m.position, Vec3::X * 10.0);
        assert_eq!(m.trail.len(), 2);
        assert_eq!(m.breaks, [0, 2]);
        let m = model_frame(&t, 2.5);
        assert_eq!(m.position, Vec3::new(25.0, 5.0, 0.0));
        // Before the start and after the end: the end samples.
        assert_eq!(model_frame(&t, -1.0).position, Vec3::ZERO);
        assert_eq!(model_frame(&t, 9.0).position, Vec3::new(30.0, 5.0, 0.0));
        assert_eq!(model_frame(&t, 9.0).trail.len(), 4);
    }
}
