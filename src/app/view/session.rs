//! What the fly-through window shows, without the window: the aircraft (flown kinematically
//! from keys or a script, or replayed from a recorded flight), the cameras, the trail, and the
//! frame built from them. The window code feeds it time steps and held keys and draws
//! [`Session::scene`]; tests drive it directly.
//!
//! Pure: no I/O.

use glam::{DQuat, DVec3, Vec3};

use super::cameras::{CameraMode, CameraRig, Target};
use super::compare::Compare;
use super::flight::{Controls, Kinematic, Start};
use super::scene::{FrameSpec, ModelFrame, SceneBuilder};
use super::script::{Player, Script};
use crate::app::replay::{pose_at, ModelTrack};
use crate::clip::ClipStats;
use crate::euler::{viewer_from_ned, EulerZyx, Gimbal};
use crate::flight::data::FlightData;
use crate::mesh::world::WorldSpec;
use crate::mesh::EdgeMesh;
use crate::pipeline::Viewport;
use crate::render::LineScene;

/// Pitch rate commanded by the pitch keys, degrees/s.
pub const KEY_PITCH_RATE: f64 = 45.0;
/// Roll rate commanded by the roll keys, degrees/s.
pub const KEY_ROLL_RATE: f64 = 90.0;
/// Yaw rate commanded by the yaw keys, degrees/s.
pub const KEY_YAW_RATE: f64 = 20.0;
/// Throttle change per second while a throttle key is held.
pub const KEY_THROTTLE_RATE: f64 = 0.5;
/// Seconds of flight between trail points.
pub const TRAIL_INTERVAL_S: f64 = 0.25;
/// Most trail points kept for a kinematic flight (the oldest half goes when it is reached).
pub const TRAIL_MAX_POINTS: usize = 4000;
/// Seek step of the replay, s.
pub const SEEK_S: f64 = 5.0;

/// Keys held down this frame (the window translates key codes into these).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Held {
    /// Stick back: nose up.
    pub pitch_up: bool,
    /// Stick forward: nose down.
    pub pitch_down: bool,
    /// Roll left.
    pub roll_left: bool,
    /// Roll right.
    pub roll_right: bool,
    /// Rudder left.
    pub yaw_left: bool,
    /// Rudder right.
    pub yaw_right: bool,
    /// More throttle.
    pub throttle_up: bool,
    /// Less throttle.
    pub throttle_down: bool,
    /// Free camera: forward.
    pub forward: bool,
    /// Free camera: backward.
    pub backward: bool,
    /// Free camera: left.
    pub left: bool,
    /// Free camera: right.
    pub right: bool,
    /// Free camera: up.
    pub up: bool,
    /// Free camera: down.
    pub down: bool,
    /// Free camera: four times faster.
    pub fast: bool,
}

impl Held {
    /// Whether any free-camera movement key is held (the window keeps drawing while so, even
    /// when paused).
    pub fn moving_camera(&self) -> bool {
        self.forward || self.backward || self.left || self.right || self.up || self.down
    }
}

fn axis(plus: bool, minus: bool) -> f64 {
    f64::from(u8::from(plus)) - f64::from(u8::from(minus))
}

/// A recorded flight being replayed.
pub struct Replay {
    data: FlightData,
    path: Vec<Vec3>,
    /// Current time, s.
    pub t: f64,
    /// First sample time, s.
    pub t0: f64,
    /// Last sample time, s.
    pub t1: f64,
    ground_z: f32,
}

impl Replay {
    /// Prepare a flight for replay.
    ///
    /// # Errors
    /// A flight without samples.
    pub fn new(data: FlightData) -> anyhow::Result<Self> {
        if data.is_empty() {
            anyhow::bail!("the flight has no samples");
        }
        let path: Vec<Vec3> = data
            .pos_ned
            .iter()
            .map(|p| viewer_from_ned(*p).as_vec3())
            .collect();
        let lowest = path.iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
        let (t0, t1) = (data.time[0], data.time[data.len() - 1]);
        Ok(Self {
            data,
            path,
            t: t0,
            t0,
            t1,
            // The ground at the origin's height, or under the lowest point of the flight.
            ground_z: lowest.min(0.0) - 1.0,
        })
    }

    fn pose(&self) -> (DVec3, EulerZyx) {
        pose_at(&self.data, self.t)
    }
}

/// Where the aircraft comes from.
// One per session: the size of the flying variant costs nothing worth a box.
#[allow(clippy::large_enum_variant)]
pub enum Source {
    /// Flown by the keys or a script.
    Fly {
        /// The aircraft.
        flight: Kinematic,
        /// Where it starts (reset).
        start: Start,
        /// Controls held between frames (throttle persists; rates come from keys each frame).
        controls: Controls,
        /// Scripted inputs: when present they, not the keys, fly the aircraft.
        script: Option<(Script, Player)>,
    },
    /// Replayed from a recording.
    Replay(Box<Replay>),
}

/// What the HUD shows about the aircraft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readout {
    /// z-y-x angles (viewer frame) read back from the attitude matrix.
    pub angles: EulerZyx,
    /// Gimbal state of those angles.
    pub gimbal: Gimbal,
    /// |cos θ|: how far the angles are from gimbal lock (0 at lock).
    pub cos_pitch: f64,
    /// Speed, m/s.
    pub speed: f64,
    /// Height above the ground, m.
    pub altitude: f64,
    /// Throttle 0..1 (kinematic flight only).
    pub throttle: Option<f64>,
    /// Replay: (t, t0, t1) in seconds.
    pub replay: Option<(f64, f64, f64)>,
    /// Flight time, s.
    pub time: f64,
}

/// The whole non-window state of the viewer.
pub struct Session {
    /// Where the aircraft comes from.
    pub source: Source,
    /// The cameras.
    pub rig: CameraRig,
    /// Whether flight time stands still (replay: not playing).
    pub paused: bool,
    builder: SceneBuilder,
    trail: Vec<Vec3>,
    trail_clock: f64,
    initial_camera: CameraMode,
    compare: Option<Box<Compare>>,
}

impl Session {
    /// A session flying `plane` kinematically from `start`, optionally scripted.
    pub fn fly(
        plane: EdgeMesh,
        start: Start,
        script: Option<Script>,
        camera: CameraMode,
        fov_y: f32,
    ) -> Self {
        let flight = Kinematic::new(&start);
        let controls = flight.controls;
        Self::with_source(
            plane,
            Source::Fly {
                flight,
                start,
                controls,
                script: script.map(|s| (s, Player::new())),
            },
            camera,
            fov_y,
        )
    }

    /// A session replaying a recorded flight.
    ///
    /// # Errors
    /// A flight without samples.
    pub fn replay(
        plane: EdgeMesh,
        data: FlightData,
        camera: CameraMode,
        fov_y: f32,
    ) -> anyhow::Result<Self> {
        Ok(Self::with_source(
            plane,
            Source::Replay(Box::new(Replay::new(data)?)),
            camera,
            fov_y,
        ))
    }

    fn with_source(plane: EdgeMesh, source: Source, camera: CameraMode, fov_y: f32) -> Self {
        let mut s = Self {
            source,
            rig: CameraRig::new(CameraMode::Chase, fov_y),
            paused: false,
            builder: SceneBuilder::new(plane, &WorldSpec::default()),
            trail: Vec::new(),
            trail_clock: 0.0,
            initial_camera: camera,
            compare: None,
        };
        s.reset();
        s
    }

    /// Show the model's flight beside the replayed one (`--compare`; a replay session only,
    /// of the same flight).
    pub fn with_compare(mut self, compare: Compare) -> Self {
        self.compare = Some(Box::new(compare));
        self
    }

    /// The comparison, in `--compare` mode.
    pub fn compare(&self) -> Option<&Compare> {
        self.compare.as_deref()
    }

    /// The comparison, to tick effects.
    pub fn compare_mut(&mut self) -> Option<&mut Compare> {
        self.compare.as_deref_mut()
    }

    /// Take in finished background work of the comparison; true if anything changed.
    pub fn poll(&mut self) -> bool {
        self.compare.as_mut().is_some_and(|c| c.poll())
    }

    /// Back to the start: the flight (or the replay's beginning), the trail, the cameras.
    pub fn reset(&mut self) {
        match &mut self.source {
            Source::Fly {
                flight,
                start,
                controls,
                script,
            } => {
                *flight = Kinematic::new(start);
                *controls = flight.controls;
                if let Some((_, player)) = script {
                    *player = Player::new();
                }
            }
            Source::Replay(r) => r.t = r.t0,
        }
        self.trail.clear();
        self.trail_clock = 0.0;
        self.rig = CameraRig::new(CameraMode::Chase, self.rig.fov_y);
        let target = self.target();
        self.rig.follow(&target, 0.0);
        self.rig.switch_to(self.initial_camera, &target);
        if let Source::Fly { .. } = self.source {
            self.apply_script(0.0);
        }
    }

    /// Pause or resume (replay: play / pause; at the end, play restarts from the beginning).
    pub fn toggle_pause(&mut self) {
        if let Source::Replay(r) = &mut self.source {
            if self.paused && r.t >= r.t1 {
                r.t = r.t0;
            }
        }
        self.paused = !self.paused;
    }

    /// Replay: jump by `delta` seconds (clamped to the recording). Nothing for a flight.
    pub fn seek(&mut self, delta: f64) {
        if let Source::Replay(r) = &mut self.source {
            if delta.is_finite() {
                r.t = (r.t + delta).clamp(r.t0, r.t1);
            }
        }
    }

    /// Whether the aircraft is flown by a script.
    pub fn scripted(&self) -> bool {
        matches!(
            self.source,
            Source::Fly {
                script: Some(_),
                ..
            }
        )
    }

    /// Switch to the next camera.
    pub fn cycle_camera(&mut self) {
        let target = self.target();
        self.rig.switch_to(self.rig.mode.next(), &target);
    }

    /// Apply the script's events up to flight time `t`.
    fn apply_script(&mut self, t: f64) {
        let mut switch = None;
        if let Source::Fly {
            controls,
            script: Some((script, player)),
            ..
        } = &mut self.source
        {
            let (camera, pause) = player.advance(script, t, controls);
            switch = camera;
            self.paused |= pause;
        }
        if let Some(mode) = switch {
            let target = self.target();
            self.rig.switch_to(mode, &target);
        }
    }

    /// Advance by `dt` seconds of wall (or fixed-step) time with the given keys held: the
    /// aircraft (unless paused), the chase camera, the free camera.
    pub fn advance(&mut self, dt: f64, held: &Held) {
        let dt = if dt.is_finite() {
            dt.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let sim_dt = if self.paused { 0.0 } else { dt };
        let scripted = self.scripted();
        match &mut self.source {
            Source::Fly {
                flight, controls, ..
            } => {
                if !scripted {
                    controls.pitch_rate_dps = KEY_PITCH_RATE * axis(held.pitch_up, held.pitch_down);
                    controls.roll_rate_dps = KEY_ROLL_RATE * axis(held.roll_right, held.roll_left);
                    controls.yaw_rate_dps = KEY_YAW_RATE * axis(held.yaw_right, held.yaw_left);
                    controls.throttle = (controls.throttle
                        + KEY_THROTTLE_RATE * sim_dt * axis(held.throttle_up, held.throttle_down))
                    .clamp(0.0, 1.0);
                }
                if sim_dt > 0.0 {
                    flight.step(*controls, sim_dt);
                    self.trail_clock += sim_dt;
                    if self.trail_clock >= TRAIL_INTERVAL_S || self.trail.is_empty() {
                        self.trail_clock = 0.0;
                        if self.trail.len() >= TRAIL_MAX_POINTS {
                            self.trail.drain(..TRAIL_MAX_POINTS / 2);
                        }
                        self.trail.push(flight.position.as_vec3());
                    }
                }
                let t = flight.time;
                if scripted && sim_dt > 0.0 {
                    self.apply_script(t);
                }
            }
            Source::Replay(r) => {
                r.t = (r.t + sim_dt).min(r.t1);
                if r.t >= r.t1 && !self.paused && sim_dt > 0.0 {
                    self.paused = true;
                }
            }
        }
        let target = self.target();
        self.rig.follow(&target, dt);
        let speed = if held.fast { 4.0 } else { 1.0 };
        self.rig.fly_free(
            speed * axis(held.forward, held.backward),
            speed * axis(held.right, held.left),
            speed * axis(held.up, held.down),
            dt,
        );
    }

    fn pose(&self) -> (DVec3, EulerZyx) {
        match &self.source {
            Source::Fly { flight, .. } => (flight.position, flight.attitude().0),
            Source::Replay(r) => r.pose(),
        }
    }

    fn orientation(&self) -> DQuat {
        match &self.source {
            Source::Fly { flight, .. } => flight.orientation,
            Source::Replay(r) => DQuat::from_mat3(&r.pose().1.to_matrix()).normalize(),
        }
    }

    /// The aircraft as the cameras see it.
    pub fn target(&self) -> Target {
        let (centre, radius) = self.builder.plane().bounding_sphere();
        Target {
            position: self.pose().0,
            orientation: self.orientation(),
            centre,
            radius,
        }
    }

    /// Build the frame for a window of the given size; returns the clipper's counts.
    pub fn build(&mut self, viewport: Viewport) -> ClipStats {
        let (position, attitude) = self.pose();
        let camera = self.rig.camera(&self.target());
        let (trail, ground_z, t): (&[Vec3], f32, f64) = match &self.source {
            Source::Fly { .. } => (&self.trail, 0.0, 0.0),
            Source::Replay(r) => {
                let upto = r.data.time.partition_point(|&s| s <= r.t);
                (&r.path[..upto], r.ground_z, r.t)
            }
        };
        let model = match (&self.compare, &self.source) {
            (Some(c), Source::Replay(_)) => Some(model_frame(&c.now.track, t)),
            _ => None,
        };
        self.builder.build(&FrameSpec {
            camera: &camera,
            viewport,
            plane_position: position.as_vec3(),
            plane_attitude: attitude,
            ground_z,
            trail,
            model,
        })
    }

    /// The last frame built.
    pub fn scene(&self) -> &LineScene {
        self.builder.scene()
    }

    /// Edges clipped per frame apart from the trail.
    pub fn edges_per_frame(&self) -> usize {
        self.builder.edges_per_frame()
    }

    /// What the HUD shows about the aircraft.
    pub fn readout(&self) -> Readout {
        let (position, attitude) = self.pose();
        let (angles, gimbal) = EulerZyx::from_matrix(attitude.to_matrix());
        let cos_pitch = angles.pitch.cos().abs();
        match &self.source {
            Source::Fly { flight, .. } => Readout {
                angles,
                gimbal,
                cos_pitch,
                speed: flight.speed,
                altitude: position.z,
                throttle: Some(flight.controls.throttle),
                replay: None,
                time: flight.time,
            },
            Source::Replay(r) => {
                let h = 0.05;
                let (a, b) = ((r.t - h).max(r.t0), (r.t + h).min(r.t1));
                let speed = if b > a {
                    (pose_at(&r.data, b).0 - pose_at(&r.data, a).0).length() / (b - a)
                } else {
                    0.0
                };
                Readout {
                    angles,
                    gimbal,
                    cos_pitch,
                    speed,
                    altitude: position.z - r.ground_z as f64 - 1.0,
                    throttle: None,
                    replay: Some((r.t, r.t0, r.t1)),
                    time: r.t - r.t0,
                }
            }
        }
    }
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
    use crate::mesh::plane::builtin_plane;

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

    #[test]
    fn keys_fly_and_pause_stops_time() {
        let mut s = Session::fly(
            builtin_plane(),
            Start::default(),
            None,
            CameraMode::Chase,
            1.0,
        );
        let x0 = s.readout();
        let held = Held {
            pitch_up: true,
            throttle_up: true,
            ..Held::default()
        };
        for _ in 0..60 {
            s.advance(1.0 / 60.0, &held);
        }
        let r = s.readout();
        assert!(r.angles.pitch.to_degrees() < -40.0, "nose up 45°: {r:?}");
        assert!(r.throttle.unwrap() > x0.throttle.unwrap());
        s.toggle_pause();
        s.advance(1.0, &held);
        assert_eq!(s.readout().time, r.time);
        s.reset();
        assert_eq!(s.readout().time, 0.0);
    }

    #[test]
    fn scripted_flight_ignores_keys_and_is_deterministic() {
        let script =
            super::super::script::parse("0 throttle=1 pitch_rate=10\n0.5 camera=orbit", "t")
                .unwrap();
        let run = || {
            let mut s = Session::fly(
                builtin_plane(),
                Start::default(),
                Some(script.clone()),
                CameraMode::Chase,
                1.0,
            );
            let held = Held {
                roll_left: true,
                ..Held::default()
            };
            for _ in 0..60 {
                s.advance(1.0 / 60.0, &held);
                s.build(Viewport {
                    width: 320,
                    height: 200,
                });
            }
            s
        };
        let (a, b) = (run(), run());
        assert_eq!(a.readout(), b.readout());
        assert_eq!(a.scene(), b.scene());
        let r = a.readout();
        assert!(r.angles.roll.abs() < 1e-9, "keys ignored: {r:?}");
        assert!((r.angles.pitch.to_degrees() + 10.0).abs() < 1e-6, "{r:?}");
        assert_eq!(a.rig.mode, CameraMode::Orbit);
    }
}
