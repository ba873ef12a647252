//! Cameras: where the eye is (view matrix) and how it projects (into homogeneous clip space).
//!
//! World frame of the viewer: right-handed, **Z up** (X north/forward, Y west/left), metres.
//! View space is glam's right-handed convention: the eye looks down −Z with +Y up. The
//! projection maps view space into clip space with the depth range of [`DepthRange`]
//! (wgpu's `0 ≤ z ≤ w` by default; OpenGL's `−w ≤ z ≤ w` on request), where the clipper works.
//!
//! Pure math: no I/O.

use glam::{Mat4, Vec3, Vec4};

use crate::clip::DepthRange;
use crate::euler::EulerZyx;

/// How view space is projected.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole perspective.
    Perspective {
        /// Vertical field of view, radians, in (0, π).
        fov_y: f32,
        /// Near plane distance, > 0.
        near: f32,
        /// Far plane distance, > near.
        far: f32,
    },
    /// Parallel projection.
    Orthographic {
        /// Half the visible height at any distance, world units.
        half_height: f32,
        /// Near plane distance (may be negative: behind the eye).
        near: f32,
        /// Far plane distance, > near.
        far: f32,
    },
}

impl Projection {
    /// Clip-from-view matrix for an image of the given aspect ratio (width / height).
    ///
    /// Perspective, with `f = 1 / tan(fov_y / 2)` and n, F the near and far distances:
    /// `x_c = f/aspect · x`, `y_c = f · y`, `w_c = −z` (distance ahead of the eye), and
    /// `z_c = (F·z + n·F)/(n − F)` for depth 0..1 (z_c/w_c = 0 at the near plane, 1 at the far),
    /// `z_c = ((F + n)·z + 2·n·F)/(n − F)` for depth −1..1.
    pub fn matrix(&self, aspect: f32, depth: DepthRange) -> Mat4 {
        match *self {
            Projection::Perspective { fov_y, near, far } => {
                let f = 1.0 / (0.5 * fov_y).tan();
                let (zz, zw) = match depth {
                    DepthRange::ZeroToOne => (far / (near - far), near * far / (near - far)),
                    DepthRange::NegOneToOne => {
                        ((far + near) / (near - far), 2.0 * near * far / (near - far))
                    }
                };
                Mat4::from_cols(
                    Vec4::new(f / aspect, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, f, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, zz, -1.0),
                    Vec4::new(0.0, 0.0, zw, 0.0),
                )
            }
            Projection::Orthographic {
                half_height,
                near,
                far,
            } => {
                let half_width = half_height * aspect;
                let (zz, zw) = match depth {
                    DepthRange::ZeroToOne => (1.0 / (near - far), near / (near - far)),
                    DepthRange::NegOneToOne => (2.0 / (near - far), (far + near) / (near - far)),
                };
                Mat4::from_cols(
                    Vec4::new(1.0 / half_width, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, 1.0 / half_height, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, zz, 0.0),
                    Vec4::new(0.0, 0.0, zw, 1.0),
                )
            }
        }
    }
}

/// An eye looking at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position, world.
    pub eye: Vec3,
    /// Point looked at, world.
    pub target: Vec3,
    /// Up direction, world (need not be unit; must not be parallel to the view direction).
    pub up: Vec3,
    /// Projection.
    pub projection: Projection,
}

impl Camera {
    /// View-from-world matrix (right-handed look-at).
    ///
    /// The rows of its rotation are the camera's right `s = normalize(f × up)`, up `u = s × f`
    /// and backward `−f`, where `f` is the unit direction from eye to target.
    pub fn view(&self) -> Mat4 {
        let f = (self.target - self.eye).normalize();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        Mat4::from_cols(
            Vec4::new(s.x, u.x, -f.x, 0.0),
            Vec4::new(s.y, u.y, -f.y, 0.0),
            Vec4::new(s.z, u.z, -f.z, 0.0),
            Vec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        )
    }

    /// The same camera moved sideways by `right` and `up` (world units, along its own axes),
    /// looking in the same direction: the subject slides the other way in the picture.
    pub fn panned(&self, right: f32, up: f32) -> Camera {
        let f = (self.target - self.eye).normalize();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        let shift = s * right + u * up;
        Camera {
            eye: self.eye + shift,
            target: self.target + shift,
            ..*self
        }
    }

    /// Clip-from-world matrix: projection · view.
    pub fn clip_from_world(&self, aspect: f32, depth: DepthRange) -> Mat4 {
        self.projection.matrix(aspect, depth) * self.view()
    }
}

/// Named camera placements around an aircraft.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CameraPreset {
    /// Behind and above, following the heading (yaw) but not pitch or roll.
    #[default]
    Chase,
    /// Ahead of the aircraft on the world +X axis, looking back at it.
    Front,
    /// Above, looking down, world +X up the picture.
    Top,
    /// From the right (world −Y), looking left.
    Side,
    /// The pilot's eye inside the canopy, fixed to the body: it pitches and rolls with it.
    Cockpit,
}

/// The pose of the model the camera frames: world position of the body origin, attitude, and
/// the model's bounding sphere in body coordinates (so any model size frames well).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Subject {
    /// Body origin in world coordinates.
    pub position: Vec3,
    /// Attitude (body → world).
    pub attitude: EulerZyx,
    /// Bounding-sphere centre, body coordinates.
    pub centre: Vec3,
    /// Bounding-sphere radius, > 0.
    pub radius: f32,
}

/// Pilot's eye position in body coordinates, as a fraction of the bounding radius
/// (for the built-in plane: just under the canopy top).
const COCKPIT_EYE: Vec3 = Vec3::new(0.18, 0.0, 0.13);

impl CameraPreset {
    /// Place a perspective camera (vertical field of view `fov_y`, radians) for the subject.
    pub fn camera(self, subject: &Subject, fov_y: f32) -> Camera {
        let r = subject.radius;
        let rot = subject.attitude.to_mat3();
        let centre = subject.position + rot * subject.centre;
        // Distance at which the bounding sphere's diameter spans about 85% of the image height;
        // aircraft are flat, so this frames them large without cutting them.
        let dist = 1.15 * r / (0.5 * fov_y).tan().max(1e-3);
        let persp = |near: f32| Projection::Perspective {
            fov_y,
            near,
            far: dist + 1000.0 * r,
        };
        match self {
            CameraPreset::Chase => {
                let (sin_yaw, cos_yaw) = (subject.attitude.yaw as f32).sin_cos();
                let heading = Vec3::new(cos_yaw, sin_yaw, 0.0);
                let right = Vec3::new(sin_yaw, -cos_yaw, 0.0);
                // Mostly behind, a little to the right and above: a three-quarter view reads
                // better than a pure tail-on one.
                let back_up = (-heading * 0.85 + right * 0.3 + Vec3::Z * 0.42).normalize();
                Camera {
                    eye: centre + back_up * dist,
                    target: centre,
                    up: Vec3::Z,
                    projection: persp(0.05 * r),
                }
            }
            CameraPreset::Front => Camera {
                eye: centre + Vec3::new(dist, 0.0, 0.12 * dist),
                target: centre,
                up: Vec3::Z,
                projection: persp(0.05 * r),
            },
            CameraPreset::Top => Camera {
                eye: centre + Vec3::Z * dist,
                target: centre,
                up: Vec3::X,
                projection: persp(0.05 * r),
            },
            CameraPreset::Side => Camera {
                eye: centre - Vec3::Y * dist,
                target: centre,
                up: Vec3::Z,
                projection: persp(0.05 * r),
            },
            CameraPreset::Cockpit => {
                let eye = subject.position + rot * (subject.centre + COCKPIT_EYE * r);
                Camera {
                    eye,
                    target: eye + rot * Vec3::X,
                    up: rot * Vec3::Z,
                    // The near plane at ~3% of the size cuts the canopy frame around the head.
                    projection: persp(0.03 * r),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_puts_the_target_straight_ahead_and_up_up() {
        let cam = Camera {
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(11.0, 2.0, 3.0),
            up: Vec3::Z,
            projection: Projection::Perspective {
                fov_y: 1.0,
                near: 0.1,
                far: 100.0,
            },
        };
        let v = cam.view();
        assert!(
            (v * Vec4::new(11.0, 2.0, 3.0, 1.0)).abs_diff_eq(Vec4::new(0.0, 0.0, -10.0, 1.0), 1e-5)
        );
        assert!(
            (v * Vec4::new(1.0, 2.0, 4.0, 1.0)).abs_diff_eq(Vec4::new(0.0, 1.0, 0.0, 1.0), 1e-5)
        );
        // World +Y is to the left when looking along +X with Z up.
        assert!((v * Vec4::new(1.0, 3.0, 3.0, 1.0)).x < 0.0);
    }

    #[test]
    fn orthographic_maps_the_box_onto_the_volume() {
        let p = Projection::Orthographic {
            half_height: 2.0,
            near: 1.0,
            far: 9.0,
        };
        for (depth, z_near) in [
            (DepthRange::ZeroToOne, 0.0),
            (DepthRange::NegOneToOne, -1.0),
        ] {
            let m = p.matrix(2.0, depth);
            let corner = m * Vec4::new(4.0, 2.0, -1.0, 1.0);
            assert!(
                corner.abs_diff_eq(Vec4::new(1.0, 1.0, z_near, 1.0), 1e-6),
                "{corner}"
            );
            let far = m * Vec4::new(-4.0, -2.0, -9.0, 1.0);
            assert!(
                far.abs_diff_eq(Vec4::new(-1.0, -1.0, 1.0, 1.0), 1e-6),
                "{far}"
            );
        }
    }

    #[test]
    fn perspective_maps_near_and_far_to_the_depth_range() {
        let p = Projection::Perspective {
            fov_y: 1.0,
            near: 2.0,
            far: 50.0,
        };
        for (depth, z_near) in [
            (DepthRange::ZeroToOne, 0.0),
            (DepthRange::NegOneToOne, -1.0),
        ] {
            let m = p.matrix(1.5, depth);
            let near = m * Vec4::new(0.0, 0.0, -2.0, 1.0);
            let far = m * Vec4::new(0.0, 0.0, -50.0, 1.0);
            assert!((near.z / near.w - z_near).abs() < 1e-6, "{depth:?} {near}");
            assert!((far.z / far.w - 1.0).abs() < 1e-5, "{depth:?} {far}");
            // w is the distance in front of the eye: positive ahead, negative behind.
            assert!(near.w > 0.0 && (m * Vec4::new(0.0, 0.0, 3.0, 1.0)).w < 0.0);
        }
    }

    #[test]
    fn chase_camera_is_behind_and_above_along_the_heading() {
        let subject = Subject {
            position: Vec3::new(100.0, 0.0, 50.0),
            attitude: EulerZyx::from_degrees(90.0, 0.0, 0.0), // nose towards +Y
            centre: Vec3::ZERO,
            radius: 5.0,
        };
        let cam = CameraPreset::Chase.camera(&subject, 50f32.to_radians());
        let rel = cam.eye - subject.position;
        assert!(rel.y < -5.0, "behind means −Y when heading +Y: {rel}");
        assert!(rel.y.abs() > 2.0 * rel.x.abs() && rel.z > 1.0, "{rel}");
    }

    #[test]
    fn cockpit_camera_looks_along_the_nose() {
        let subject = Subject {
            position: Vec3::ZERO,
            attitude: EulerZyx::from_degrees(0.0, -30.0, 0.0), // nose up 30° (Z-up world)
            centre: Vec3::ZERO,
            radius: 5.0,
        };
        let cam = CameraPreset::Cockpit.camera(&subject, 1.0);
        let dir = (cam.target - cam.eye).normalize();
        assert!(
            (dir - Vec3::new(30f32.to_radians().cos(), 0.0, 30f32.to_radians().sin())).length()
                < 1e-5
        );
    }
}
