//! The window's Euler-angle panel, without the window: a chosen convention, its three angles
//! (read from the aircraft's attitude, or set by the sliders and then setting it), and the
//! gimbal rings drawn around the aircraft ([`crate::scene::euler::gimbal_rings`]: three rings
//! nested in the order of the sequence, each in its angle's colour).
//!
//! The angles are those people read everywhere else (the HUD, `render`, flight data): of the
//! attitude in the aerospace frames, world north-east-down and body forward-right-down, so
//! z-y-x is yaw (+ nose right), pitch (+ nose up), roll (+ right wing down). The crossing to
//! the viewer's Z-up frame is [`crate::scene::attitude::viewer_from_aerospace`], here and for
//! the rings.
//!
//! Pure: no I/O, no egui (the sliders are in `hud.rs` and hand their values here).

use glam::{DMat3, DVec3, Mat4, Vec3};

use crate::render::{LineBatch, LineScene};
use crate::scene::attitude::{viewer_from_aerospace, D};
use crate::scene::euler::gimbal_rings;
use wireflight_geometry::camera::Camera;
use wireflight_geometry::clip::{ClipStats, Clipper, DepthRange};
use wireflight_geometry::euler::{Convention, EulerAngles, Lock};
use wireflight_geometry::pipeline::{EdgeProjector, Viewport};

/// The panel's state.
#[derive(Debug)]
pub struct EulerPanel {
    /// Whether the panel and the rings are shown.
    pub shown: bool,
    /// Whether the sliders set the aircraft's attitude (otherwise they show its angles).
    pub drive: bool,
    convention: Convention,
    degrees: [f64; 3],
    lock: Lock,
    projector: EdgeProjector,
}

impl Default for EulerPanel {
    fn default() -> Self {
        Self::new(Convention::VIEWER)
    }
}

impl EulerPanel {
    /// A hidden panel for `convention`, all angles 0, following the aircraft.
    pub fn new(convention: Convention) -> Self {
        Self {
            shown: false,
            drive: false,
            convention,
            degrees: [0.0; 3],
            lock: Lock::Free,
            projector: EdgeProjector::new(Clipper::Blinn, DepthRange::ZeroToOne),
        }
    }

    /// The convention of the sliders.
    pub fn convention(&self) -> Convention {
        self.convention
    }

    /// The three angles, degrees, in the convention's order.
    pub fn degrees(&self) -> [f64; 3] {
        self.degrees
    }

    /// The angles as [`EulerAngles`].
    pub fn euler(&self) -> EulerAngles {
        EulerAngles::from_degrees(self.convention, self.degrees)
    }

    /// Whether the middle angle is at gimbal lock (from the attitude's decomposition when
    /// following it, from the sliders when driving).
    pub fn lock(&self) -> Lock {
        self.lock
    }

    /// The slider ranges, degrees: the principal ranges of the convention (the middle angle
    /// [−90°, 90°] for Tait–Bryan, [0°, 180°] for proper Euler; the others (−180°, 180°]).
    pub fn ranges(&self) -> [(f64, f64); 3] {
        let (lo, hi) = self.convention.sequence.middle_range();
        [
            (-180.0, 180.0),
            (lo.to_degrees(), hi.to_degrees()),
            (-180.0, 180.0),
        ]
    }

    /// The rotation the sliders describe (body → world), in the viewer's frames.
    pub fn attitude(&self) -> DMat3 {
        viewer_from_aerospace(self.euler().to_matrix())
    }

    /// Show the angles of `attitude` (viewer frames; when not driving): the principal
    /// decomposition of its aerospace rotation, with the lock rule at gimbal lock.
    pub fn follow(&mut self, attitude: DMat3) {
        if self.drive {
            return;
        }
        let s = EulerAngles::from_matrix(self.convention, viewer_from_aerospace(attitude));
        if s.euler.is_finite() {
            self.degrees = s.euler.to_degrees();
            self.lock = s.lock;
        }
    }

    /// Set the angles (degrees; clamped into the ranges, non-finite ones ignored) and let them
    /// drive the attitude.
    pub fn set_degrees(&mut self, degrees: [f64; 3]) {
        for (k, (lo, hi)) in self.ranges().into_iter().enumerate() {
            if degrees[k].is_finite() {
                self.degrees[k] = degrees[k].clamp(lo, hi);
            }
        }
        self.drive = true;
        self.lock = self.euler().lock();
    }

    /// Change the convention, keeping the attitude `current` (viewer frames): the angles become
    /// its decomposition in the new convention.
    pub fn set_convention(&mut self, convention: Convention, current: DMat3) {
        if convention == self.convention {
            return;
        }
        self.convention = convention;
        let s = EulerAngles::from_matrix(convention, viewer_from_aerospace(current));
        if s.euler.is_finite() {
            self.degrees = s.euler.to_degrees();
            self.lock = s.lock;
        }
    }

    /// Append the rings around an aircraft at `position` with bounding radius `radius`, seen by
    /// `camera`, to `scene` (one batch per ring and its axles). Returns the clipper's counts.
    pub fn draw_rings(
        &mut self,
        scene: &mut LineScene,
        camera: &Camera,
        viewport: Viewport,
        position: DVec3,
        radius: f32,
    ) -> ClipStats {
        let clip_from_world = camera.clip_from_world(viewport.aspect(), self.projector.depth())
            * Mat4::from_translation(position.as_vec3())
            * Mat4::from_scale(Vec3::splat(radius))
            // The rings are of the aerospace angles: drawn in the NED axes, turned into the
            // viewer's by the half-turn D.
            * Mat4::from_mat3(D.as_mat3());
        let mut stats = ClipStats::default();
        for ring in gimbal_rings(&self.euler()) {
            let mut segments = Vec::new();
            for piece in [&ring.circle[..], &ring.axle[..2], &ring.axle[2..]] {
                stats.merge(&self.projector.project_polyline(
                    piece,
                    &[],
                    clip_from_world,
                    viewport,
                    &mut segments,
                ));
            }
            scene.batches.push(LineBatch {
                color: ring.color,
                segments,
            });
        }
        stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wireflight_geometry::euler::{Frame, Sequence};

    #[test]
    fn following_decomposes_and_driving_sets() {
        let mut p = EulerPanel::new("zxz".parse().unwrap());
        let r = viewer_from_aerospace(
            EulerAngles::from_degrees(p.convention(), [30.0, 45.0, -60.0]).to_matrix(),
        );
        p.follow(r);
        let d = p.degrees();
        assert!(
            (d[0] - 30.0).abs() < 1e-9 && (d[1] - 45.0).abs() < 1e-9,
            "{d:?}"
        );
        assert!(p.attitude().abs_diff_eq(r, 1e-12));
        // Out of range and NaN: clamped, ignored.
        p.set_degrees([500.0, f64::NAN, -10.0]);
        assert_eq!(p.degrees(), [180.0, 45.0, -10.0]);
        assert!(p.drive);
        // While driving the attitude does not move the sliders.
        p.follow(DMat3::IDENTITY);
        assert_eq!(p.degrees(), [180.0, 45.0, -10.0]);
        // A new convention keeps the attitude.
        let before = p.attitude();
        p.set_convention(Convention::new(Sequence::XYZ, Frame::Extrinsic), before);
        assert!(p.attitude().abs_diff_eq(before, 1e-12));
        p.set_degrees([0.0, 90.0, 0.0]);
        assert_eq!(p.lock(), Lock::Upper);
        assert_eq!(p.ranges()[1], (-90.0, 90.0));
    }
}
