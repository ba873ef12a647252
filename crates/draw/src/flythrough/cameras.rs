//! The cameras of the fly-through window: chase (default), cockpit, orbit (mouse) and free-fly.
//! Each produces a [`Camera`] (hand-written look-at and projection, see [`wireflight_geometry::camera`]).
//!
//! Pure math: no I/O.

use std::fmt;
use std::str::FromStr;

use glam::{DQuat, DVec3, Vec3};

use wireflight_geometry::camera::{Camera, CameraPreset, Projection, Subject};
use wireflight_geometry::euler::EulerZyx;

/// Far plane of the world cameras, m: closer than the grid's edge, so the far plane clips
/// grid edges in every frame.
pub const FAR_M: f32 = 4000.0;
/// Near plane of the outside cameras, m.
pub const NEAR_M: f32 = 0.5;
/// Time constant of the chase camera following the aircraft's attitude, s.
pub const CHASE_TAU: f64 = 0.35;

/// Which camera is looking.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CameraMode {
    /// Behind and above the aircraft, following its attitude with a short lag.
    #[default]
    Chase,
    /// The pilot's eye, fixed to the body ([`CameraPreset::Cockpit`]).
    Cockpit,
    /// Around the aircraft; drag with the mouse to turn, wheel to zoom. World up stays up.
    Orbit,
    /// Detached; W/A/S/D and PageUp/PageDown move, mouse drag looks.
    Free,
}

impl CameraMode {
    /// All modes in cycling order.
    pub const ALL: [CameraMode; 4] = [
        CameraMode::Chase,
        CameraMode::Cockpit,
        CameraMode::Orbit,
        CameraMode::Free,
    ];

    /// The next mode in the cycle chase → cockpit → orbit → free → chase.
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|&m| m == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            CameraMode::Chase => "chase",
            CameraMode::Cockpit => "cockpit",
            CameraMode::Orbit => "orbit",
            CameraMode::Free => "free",
        }
    }
}

impl fmt::Display for CameraMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no [`CameraMode`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("`{0}` is not a camera (chase, cockpit, orbit, free)")]
pub struct ParseCameraModeError(pub String);

impl FromStr for CameraMode {
    type Err = ParseCameraModeError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| ParseCameraModeError(s.to_string()))
    }
}

/// Where the aircraft is and how big it is, for placing cameras.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// Body origin, world.
    pub position: DVec3,
    /// Body → world rotation.
    pub orientation: DQuat,
    /// Bounding-sphere centre, body coordinates.
    pub centre: Vec3,
    /// Bounding-sphere radius, m.
    pub radius: f32,
}

impl Target {
    /// The bounding-sphere centre in world coordinates.
    pub fn world_centre(&self) -> DVec3 {
        self.position + self.orientation * self.centre.as_dvec3()
    }
}

/// Orbit camera state: the eye on a sphere around the aircraft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Direction from the aircraft to the eye, radians from world +X towards +Y.
    pub azimuth: f64,
    /// Elevation of the eye above the aircraft's horizontal plane, radians.
    pub elevation: f64,
    /// Distance, m.
    pub distance: f64,
}

/// Free camera state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Free {
    /// Eye, world.
    pub eye: DVec3,
    /// Look direction: radians from +X towards +Y.
    pub yaw: f64,
    /// Look direction: radians above the horizontal.
    pub pitch: f64,
    /// Flying speed, m/s.
    pub speed: f64,
}

/// All cameras and which one is active.
#[derive(Clone, Debug)]
pub struct CameraRig {
    /// The active camera.
    pub mode: CameraMode,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// The chase camera's smoothed attitude; `None` until the first update (then it snaps).
    chase: Option<DQuat>,
    /// Orbit camera.
    pub orbit: Orbit,
    /// Free camera.
    pub free: Free,
}

const ELEVATION_LIMIT: f64 = 85.0 * std::f64::consts::PI / 180.0;
const LOOK_PITCH_LIMIT: f64 = 89.0 * std::f64::consts::PI / 180.0;
/// Mouse drag: radians per pixel.
const DRAG_RAD_PER_PX: f64 = 0.3 * std::f64::consts::PI / 180.0;

impl CameraRig {
    /// A rig in the given mode; `fov_y` in radians.
    pub fn new(mode: CameraMode, fov_y: f32) -> Self {
        Self {
            mode,
            fov_y,
            chase: None,
            orbit: Orbit {
                azimuth: std::f64::consts::PI,
                elevation: 20f64.to_radians(),
                distance: 30.0,
            },
            free: Free {
                eye: DVec3::new(-1600.0, -60.0, 170.0),
                yaw: 0.0,
                pitch: 0.0,
                speed: 50.0,
            },
        }
    }

    /// Distance of the chase camera from the aircraft's centre, m: the bounding sphere spans
    /// about a third of the picture height.
    pub fn chase_distance(&self, radius: f32) -> f64 {
        3.2 * radius as f64 / (0.5 * self.fov_y as f64).tan().max(1e-3)
    }

    /// Let the chase camera follow the aircraft's attitude for `dt` seconds (first call, or
    /// `dt` ≤ 0 after a reset: snap to it).
    pub fn follow(&mut self, target: &Target, dt: f64) {
        let q = target.orientation;
        self.chase = Some(match self.chase {
            Some(c) if dt.is_finite() && dt > 0.0 => {
                c.slerp(q, 1.0 - (-dt / CHASE_TAU).exp()).normalize()
            }
            Some(c) if dt == 0.0 => c,
            _ => q,
        });
    }

    /// Snap the chase camera to the aircraft at the next [`follow`](Self::follow).
    pub fn reset_chase(&mut self) {
        self.chase = None;
    }

    /// The active camera for the aircraft.
    pub fn camera(&self, target: &Target) -> Camera {
        let centre = target.world_centre();
        let persp = |near: f32| Projection::Perspective {
            fov_y: self.fov_y,
            near,
            far: FAR_M,
        };
        match self.mode {
            CameraMode::Chase => {
                let q = self.chase.unwrap_or(target.orientation);
                let d = self.chase_distance(target.radius);
                let eye = centre + q * DVec3::new(-0.95 * d, 0.0, 0.3 * d);
                Camera {
                    eye: eye.as_vec3(),
                    target: centre.as_vec3(),
                    up: (q * DVec3::Z).as_vec3(),
                    projection: persp(NEAR_M),
                }
            }
            CameraMode::Cockpit => {
                let subject = Subject {
                    position: target.position.as_vec3(),
                    attitude: EulerZyx::from_matrix(glam::DMat3::from_quat(target.orientation)).0,
                    centre: target.centre,
                    radius: target.radius,
                };
                let mut cam = CameraPreset::Cockpit.camera(&subject, self.fov_y);
                if let Projection::Perspective { near, .. } = cam.projection {
                    cam.projection = persp(near);
                }
                cam
            }
            CameraMode::Orbit => {
                let o = self.orbit;
                let dir = DVec3::new(
                    o.elevation.cos() * o.azimuth.cos(),
                    o.elevation.cos() * o.azimuth.sin(),
                    o.elevation.sin(),
                );
                Camera {
                    eye: (centre + dir * o.distance).as_vec3(),
                    target: centre.as_vec3(),
                    up: Vec3::Z,
                    projection: persp(NEAR_M),
                }
            }
            CameraMode::Free => {
                let f = self.free;
                Camera {
                    eye: f.eye.as_vec3(),
                    target: (f.eye + look_dir(f.yaw, f.pitch)).as_vec3(),
                    up: Vec3::Z,
                    projection: persp(NEAR_M),
                }
            }
        }
    }

    /// Switch to `mode`, starting the orbit and free cameras where the current camera is so
    /// that the picture does not jump.
    pub fn switch_to(&mut self, mode: CameraMode, target: &Target) {
        if mode == self.mode {
            return;
        }
        let current = self.camera(target);
        let eye = current.eye.as_dvec3();
        let dir = (current.target - current.eye)
            .as_dvec3()
            .normalize_or(DVec3::X);
        match mode {
            CameraMode::Orbit => {
                // Start where the chase camera is (from the cockpit, the current eye is inside
                // the aircraft).
                let previous = std::mem::replace(&mut self.mode, CameraMode::Chase);
                let chase_eye = self.camera(target).eye.as_dvec3();
                self.mode = previous;
                let rel = chase_eye - target.world_centre();
                let distance = rel.length();
                if distance > 1e-3 && rel.x.hypot(rel.y) > 1e-6 {
                    self.orbit.azimuth = rel.y.atan2(rel.x);
                    self.orbit.elevation = (rel.z / distance)
                        .asin()
                        .clamp(-ELEVATION_LIMIT, ELEVATION_LIMIT);
                    self.orbit.distance = self.clamp_distance(distance, target.radius);
                }
            }
            CameraMode::Free => {
                self.free.eye = eye;
                self.free.yaw = dir.y.atan2(dir.x);
                self.free.pitch = dir
                    .z
                    .clamp(-1.0, 1.0)
                    .asin()
                    .clamp(-LOOK_PITCH_LIMIT, LOOK_PITCH_LIMIT);
            }
            CameraMode::Chase | CameraMode::Cockpit => {}
        }
        self.mode = mode;
    }

    fn clamp_distance(&self, d: f64, radius: f32) -> f64 {
        d.clamp(1.2 * radius as f64, 3000.0)
    }

    /// A mouse drag of (dx, dy) pixels: turns the orbit or the free camera's look.
    pub fn drag(&mut self, dx: f64, dy: f64) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        match self.mode {
            CameraMode::Orbit => {
                self.orbit.azimuth -= dx * DRAG_RAD_PER_PX;
                self.orbit.elevation = (self.orbit.elevation + dy * DRAG_RAD_PER_PX)
                    .clamp(-ELEVATION_LIMIT, ELEVATION_LIMIT);
            }
            CameraMode::Free => {
                self.free.yaw -= dx * DRAG_RAD_PER_PX;
                self.free.pitch = (self.free.pitch - dy * DRAG_RAD_PER_PX)
                    .clamp(-LOOK_PITCH_LIMIT, LOOK_PITCH_LIMIT);
            }
            CameraMode::Chase | CameraMode::Cockpit => {}
        }
    }

    /// Mouse wheel `steps` (positive: away from the user / zoom in): orbit distance, or the
    /// free camera's speed.
    pub fn wheel(&mut self, steps: f64, radius: f32) {
        if !steps.is_finite() {
            return;
        }
        let factor = 0.9f64.powf(steps.clamp(-20.0, 20.0));
        match self.mode {
            CameraMode::Orbit => {
                self.orbit.distance = self.clamp_distance(self.orbit.distance * factor, radius)
            }
            CameraMode::Free => self.free.speed = (self.free.speed / factor).clamp(1.0, 2000.0),
            CameraMode::Chase | CameraMode::Cockpit => {}
        }
    }

    /// Move the free camera: `forward`, `right`, `up` in −1..=1 (times its speed) for `dt` s.
    pub fn fly_free(&mut self, forward: f64, right: f64, up: f64, dt: f64) {
        if self.mode != CameraMode::Free || !(dt.is_finite() && dt > 0.0) {
            return;
        }
        let f = look_dir(self.free.yaw, self.free.pitch);
        let r = DVec3::new(self.free.yaw.sin(), -self.free.yaw.cos(), 0.0);
        let v = (f * forward + r * right + DVec3::Z * up) * self.free.speed;
        if v.is_finite() {
            self.free.eye += v * dt;
        }
    }
}

fn look_dir(yaw: f64, pitch: f64) -> DVec3 {
    DVec3::new(
        pitch.cos() * yaw.cos(),
        pitch.cos() * yaw.sin(),
        pitch.sin(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;
    use wireflight_geometry::clip::DepthRange;

    fn target(orientation: DQuat) -> Target {
        Target {
            position: DVec3::new(100.0, 50.0, 300.0),
            orientation,
            centre: Vec3::ZERO,
            radius: 5.0,
        }
    }

    /// The aircraft centre in NDC for a camera.
    fn ndc_of_centre(cam: &Camera, t: &Target) -> Vec4 {
        let p = cam.clip_from_world(16.0 / 9.0, DepthRange::ZeroToOne)
            * t.world_centre().as_vec3().extend(1.0);
        p / p.w
    }

    #[test]
    fn every_camera_but_the_cockpit_puts_the_aircraft_in_the_middle() {
        // Including straight up, where yaw-following chase cameras flip.
        for q in [
            DQuat::IDENTITY,
            DQuat::from_rotation_y(-std::f64::consts::FRAC_PI_2),
            DQuat::from_rotation_x(2.5) * DQuat::from_rotation_z(1.0),
        ] {
            let t = target(q);
            let mut rig = CameraRig::new(CameraMode::Chase, 55f32.to_radians());
            rig.follow(&t, 0.0);
            for mode in [CameraMode::Chase, CameraMode::Orbit, CameraMode::Free] {
                rig.switch_to(mode, &t);
                let cam = rig.camera(&t);
                let c = ndc_of_centre(&cam, &t);
                assert!(c.x.abs() < 1e-3 && c.y.abs() < 1e-3, "{mode} {q}: {c}");
                assert!(
                    c.z > 0.0 && c.z < 1.0,
                    "{mode}: in front, within depth: {c}"
                );
            }
        }
    }

    #[test]
    fn chase_is_behind_and_above_in_body_axes() {
        let t = target(DQuat::IDENTITY);
        let mut rig = CameraRig::new(CameraMode::Chase, 55f32.to_radians());
        rig.follow(&t, 0.1);
        let cam = rig.camera(&t);
        let rel = cam.eye.as_dvec3() - t.world_centre();
        assert!(rel.x < -20.0 && rel.z > 5.0 && rel.y.abs() < 1e-6, "{rel}");
    }

    #[test]
    fn cockpit_looks_along_the_nose() {
        let q = DQuat::from_rotation_z(0.7) * DQuat::from_rotation_y(-0.3);
        let t = target(q);
        let mut rig = CameraRig::new(CameraMode::Cockpit, 1.0);
        rig.follow(&t, 0.0);
        let cam = rig.camera(&t);
        let dir = (cam.target - cam.eye).normalize().as_dvec3();
        assert!(dir.abs_diff_eq(q * DVec3::X, 1e-4), "{dir}"); // f32 positions ~300 m
        assert!(matches!(cam.projection, Projection::Perspective { far, .. } if far == FAR_M));
    }

    #[test]
    fn modes_cycle_and_parse() {
        let mut m = CameraMode::Chase;
        for expected in ["cockpit", "orbit", "free", "chase"] {
            m = m.next();
            assert_eq!(m.to_string(), expected);
            assert_eq!(expected.parse::<CameraMode>(), Ok(m));
        }
        assert_eq!(
            "tail".parse::<CameraMode>().unwrap_err().to_string(),
            "`tail` is not a camera (chase, cockpit, orbit, free)"
        );
    }

    #[test]
    fn drag_wheel_and_free_flight() {
        let t = target(DQuat::IDENTITY);
        let mut rig = CameraRig::new(CameraMode::Orbit, 1.0);
        let el = rig.orbit.elevation;
        rig.drag(0.0, 1e6);
        assert!(rig.orbit.elevation > el && rig.orbit.elevation <= ELEVATION_LIMIT);
        rig.wheel(100.0, t.radius);
        assert!(rig.orbit.distance >= 6.0);
        rig.switch_to(CameraMode::Free, &t);
        let eye = rig.free.eye;
        rig.fly_free(1.0, 0.0, 0.0, 1.0);
        assert!((rig.free.eye - eye).length() > 1.0);
        rig.drag(f64::NAN, 0.0);
        assert!(rig.free.yaw.is_finite());
    }
}
