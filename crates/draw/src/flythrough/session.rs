//! What the fly-through window shows, without the window: the aircraft (flown kinematically
//! from keys or a script, or replayed from a recorded flight), the cameras, the trail, and the
//! frame built from them. The window code feeds it time steps and held keys and draws
//! [`Session::scene`]; tests drive it directly. In `--compare` mode the model's flight is
//! drawn beside a replay from a [`ModelPanel`], which the session holds without knowing what
//! computes it.
//!
//! Pure: no I/O.

use std::any::Any;

use glam::{DMat3, DQuat, DVec3, Vec3};

use super::cameras::{CameraMode, CameraRig, Target};
use super::flight::{Controls, Kinematic, Start};
use super::gimbal::EulerPanel;
use super::script::{Player, Script};
use crate::render::LineScene;
use crate::scene::builder::{FrameSpec, Layer, SceneBuilder};
use crate::scene::track::{model_frame, pose_at, ModelTrack};
use crate::scene::ReplayError;
use wireflight_data::FlightData;
use wireflight_geometry::clip::{ClipStats, Clipper};
use wireflight_geometry::euler::{viewer_from_ned, Convention, EulerZyx, Gimbal};
use wireflight_geometry::mesh::world::{World, WorldSpec};
use wireflight_geometry::mesh::EdgeMesh;
use wireflight_geometry::pipeline::Viewport;

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
    pub fn new(data: FlightData) -> Result<Self, ReplayError> {
        if data.is_empty() {
            return Err(ReplayError::EmptyFlight);
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

/// The model's flight beside a replay and what computes it: the one seam through which a
/// comparison joins the viewer, which knows neither the flight model nor the analysis.
/// `wireflight-present`'s compare panel implements it (its comparisons, fit and discovery run
/// on worker threads); the session polls it for finished work, draws its track, and hands it
/// back by its type ([`Session::compare`]).
pub trait ModelPanel: Any {
    /// Take in finished background work, without waiting; true if anything changed.
    fn poll(&mut self) -> bool;
    /// The model's flight as it stands now.
    fn track(&self) -> &ModelTrack;
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
    compare: Option<Box<dyn ModelPanel>>,
    /// The Euler-angle panel: a convention's angles of the attitude, its gimbal rings, and
    /// sliders that can set the attitude.
    pub euler: EulerPanel,
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
    ) -> Result<Self, ReplayError> {
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
            builder: SceneBuilder::new(
                plane,
                Layer::world(World::new(&WorldSpec::default())),
                Clipper::Blinn,
            ),
            trail: Vec::new(),
            trail_clock: 0.0,
            initial_camera: camera,
            compare: None,
            euler: EulerPanel::default(),
        };
        s.reset();
        s
    }

    /// Show the model's flight beside the replayed one (`--compare`; a replay session only,
    /// of the same flight), as the panel computes it.
    pub fn with_compare(mut self, compare: impl ModelPanel) -> Self {
        self.compare = Some(Box::new(compare));
        self
    }

    /// The comparison panel, in `--compare` mode (`None` too if it is not a `P`).
    pub fn compare<P: ModelPanel>(&self) -> Option<&P> {
        let panel: &dyn Any = self.compare.as_deref()?;
        panel.downcast_ref()
    }

    /// The comparison panel, to tick effects.
    pub fn compare_mut<P: ModelPanel>(&mut self) -> Option<&mut P> {
        let panel: &mut dyn Any = self.compare.as_deref_mut()?;
        panel.downcast_mut()
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
        // The sliders hold the attitude while they drive it; otherwise they show its angles.
        if let Some(attitude) = self.driven() {
            if let Source::Fly { flight, .. } = &mut self.source {
                flight.orientation = DQuat::from_mat3(&attitude).normalize();
            }
        } else if self.euler.shown {
            let attitude = self.attitude_matrix();
            self.euler.follow(attitude);
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

    /// The attitude the Euler sliders impose, when they are shown and drive it.
    fn driven(&self) -> Option<DMat3> {
        (self.euler.shown && self.euler.drive).then(|| self.euler.attitude())
    }

    fn pose(&self) -> (DVec3, EulerZyx) {
        let (position, attitude) = match &self.source {
            Source::Fly { flight, .. } => (flight.position, flight.attitude().0),
            Source::Replay(r) => r.pose(),
        };
        match self.driven() {
            Some(m) => (position, EulerZyx::from_matrix(m).0),
            None => (position, attitude),
        }
    }

    fn orientation(&self) -> DQuat {
        if let Some(m) = self.driven() {
            return DQuat::from_mat3(&m).normalize();
        }
        match &self.source {
            Source::Fly { flight, .. } => flight.orientation,
            Source::Replay(r) => DQuat::from_mat3(&r.pose().1.to_matrix()).normalize(),
        }
    }

    /// The aircraft's body → world rotation as shown.
    pub fn attitude_matrix(&self) -> DMat3 {
        DMat3::from_quat(self.orientation())
    }

    /// Show or hide the Euler-angle panel and the gimbal rings.
    pub fn toggle_euler(&mut self) {
        self.euler.shown = !self.euler.shown;
        if self.euler.shown && !self.euler.drive {
            let attitude = self.attitude_matrix();
            self.euler.follow(attitude);
        }
    }

    /// Choose the panel's convention; the attitude stays, the angles are its decomposition.
    pub fn set_euler_convention(&mut self, convention: Convention) {
        let attitude = self.attitude_matrix();
        self.euler.set_convention(convention, attitude);
    }

    /// Set the panel's angles (degrees): they now drive the attitude, and a flight pauses so
    /// that the aircraft stays where it can be looked at (Space flies on, in that attitude).
    pub fn set_euler_degrees(&mut self, degrees: [f64; 3]) {
        self.euler.shown = true;
        self.euler.set_degrees(degrees);
        if matches!(self.source, Source::Fly { .. }) {
            self.paused = true;
        }
        if let (Some(attitude), Source::Fly { flight, .. }) = (self.driven(), &mut self.source) {
            flight.orientation = DQuat::from_mat3(&attitude).normalize();
        }
    }

    /// Let the sliders drive the attitude, or let go of it (the aircraft keeps the attitude
    /// it has and the sliders follow it again).
    pub fn set_euler_drive(&mut self, drive: bool) {
        self.euler.drive = drive;
        if !drive {
            let attitude = self.attitude_matrix();
            self.euler.follow(attitude);
        }
    }

    /// The aircraft as the cameras see it.
    pub fn target(&self) -> Target {
        let (centre, radius) = self.builder.aircraft().bounding_sphere();
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
            (Some(c), Source::Replay(_)) => Some(model_frame(c.track(), t)),
            _ => None,
        };
        let mut stats = self.builder.build(&FrameSpec {
            camera: &camera,
            viewport,
            aircraft_position: position.as_vec3(),
            aircraft_attitude: attitude,
            ground_z,
            trail,
            model,
        });
        if self.euler.shown {
            let radius = self.builder.aircraft().bounding_sphere().1;
            stats.merge(&self.euler.draw_rings(
                self.builder.scene_mut(),
                &camera,
                viewport,
                position,
                radius,
            ));
        }
        stats
    }

    /// The last frame built.
    pub fn scene(&self) -> &LineScene {
        self.builder.scene()
    }

    /// The scene builder (its layers, batch indices and clipper).
    pub fn builder(&self) -> &SceneBuilder {
        &self.builder
    }

    /// The clipper in use.
    pub fn clipper(&self) -> Clipper {
        self.builder.clipper()
    }

    /// Clip with another algorithm from the next frame on.
    pub fn set_clipper(&mut self, clipper: Clipper) {
        self.builder.set_clipper(clipper);
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

#[cfg(test)]
mod tests;
