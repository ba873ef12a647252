//! What a flight recorded that an effect may act from: the body's attitude, for a model that
//! does not fly one (a point mass) but whose force depends on where the body points.

use glam::{DMat3, DQuat, DVec3};
use wireflight_geometry::euler::EulerZyx;

/// The body's x axis (its nose) in NED at each recorded time, shared by every effect of a
/// model built for the flight (an `Arc` in [`super::EffectContext`]: not copied per effect).
#[derive(Clone, PartialEq)]
pub struct RecordedAttitude {
    /// Sample times, s, strictly increasing.
    times: Vec<f64>,
    /// The body x axis in NED at each time (unit length).
    nose_ned: Vec<DVec3>,
    /// The body → NED rotation at each time, each quaternion on the side of its
    /// predecessor's (q and −q are the same rotation: interpolation takes the shorter way).
    body_to_ned: Vec<DQuat>,
}

impl std::fmt::Debug for RecordedAttitude {
    // The samples are thousands of vectors: a model's debug print names their span only.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let span = self.times.first().zip(self.times.last());
        f.debug_struct("RecordedAttitude")
            .field("samples", &self.times.len())
            .field("span_s", &span)
            .finish()
    }
}

impl RecordedAttitude {
    /// The nose direction of each recorded attitude at its time; `None` where there is
    /// nothing to act from: no samples, lengths that differ, times not finite and strictly
    /// increasing, or an angle not finite.
    pub fn new(times: &[f64], attitude: &[EulerZyx]) -> Option<Self> {
        let increasing = times.windows(2).all(|w| w[1] > w[0]);
        let finite = times.iter().all(|t| t.is_finite())
            && attitude
                .iter()
                .all(|e| e.yaw.is_finite() && e.pitch.is_finite() && e.roll.is_finite());
        if times.is_empty() || times.len() != attitude.len() || !increasing || !finite {
            return None;
        }
        let mut body_to_ned: Vec<DQuat> = Vec::with_capacity(attitude.len());
        for e in attitude {
            let q = DQuat::from_mat3(&e.to_matrix()).normalize();
            let same_side = body_to_ned.last().is_none_or(|p| p.dot(q) >= 0.0);
            body_to_ned.push(if same_side { q } else { -q });
        }
        Some(Self {
            times: times.to_vec(),
            nose_ned: attitude.iter().map(|e| e.to_matrix().x_axis).collect(),
            body_to_ned,
        })
    }

    /// How many samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether there are none (never, for one [`new`](Self::new) made).
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The body x axis in NED at time `t`: interpolated between the samples around it (and
    /// made unit length again), the first or last sample's outside the record. A binary
    /// search: no allocation, O(log n).
    pub fn nose_at(&self, t: f64) -> DVec3 {
        let n = self.times.len();
        let after = self.times.partition_point(|&s| s <= t);
        if after == 0 {
            return self.nose_ned.first().copied().unwrap_or(DVec3::X);
        }
        if after >= n {
            return self.nose_ned.last().copied().unwrap_or(DVec3::X);
        }
        let (t0, t1) = (self.times[after - 1], self.times[after]);
        let w = (t - t0) / (t1 - t0);
        let (a, b) = (self.nose_ned[after - 1], self.nose_ned[after]);
        // Two unit vectors a sample apart are nearly parallel: their chord's midpoint is far
        // from zero, and normalising it is the nearby great-circle point to first order.
        (a + w * (b - a)).try_normalize().unwrap_or(a)
    }

    /// The body → NED rotation at time `t` (its columns the body axes in NED): interpolated
    /// between the samples around it, the first or last sample's outside the record — the
    /// whole attitude, roll included, where [`nose_at`](Self::nose_at) is the nose alone.
    /// A binary search: no allocation, O(log n).
    pub fn rotation_at(&self, t: f64) -> DMat3 {
        let n = self.body_to_ned.len();
        let after = self.times.partition_point(|&s| s <= t);
        let q = if after == 0 {
            self.body_to_ned.first().copied().unwrap_or(DQuat::IDENTITY)
        } else if after >= n {
            self.body_to_ned.last().copied().unwrap_or(DQuat::IDENTITY)
        } else {
            let (t0, t1) = (self.times[after - 1], self.times[after]);
            let w = (t - t0) / (t1 - t0);
            let (a, b) = (self.body_to_ned[after - 1], self.body_to_ned[after]);
            // Neighbouring samples are close rotations on the same side: the normalised
            // chord is the slerp to first order, without its trigonometry.
            let mixed = a * (1.0 - w) + b * w;
            if mixed.length_squared() > 0.0 {
                mixed.normalize()
            } else {
                a
            }
        };
        DMat3::from_quat(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nose_is_interpolated_between_samples_and_held_outside() {
        let level = EulerZyx::new(0.0, 0.0, 0.0);
        let up = EulerZyx::new(0.0, std::f64::consts::FRAC_PI_2, 0.0);
        let r = RecordedAttitude::new(&[1.0, 2.0], &[level, up]).unwrap();
        assert!((r.nose_at(0.0) - DVec3::X).length() < 1e-12);
        assert!((r.nose_at(1.0) - DVec3::X).length() < 1e-12);
        assert!((r.nose_at(9.0) - DVec3::NEG_Z).length() < 1e-12);
        let half = r.nose_at(1.5);
        let want = DVec3::new(1.0, 0.0, -1.0).normalize();
        assert!((half - want).length() < 1e-12, "{half}");
        assert!(RecordedAttitude::new(&[1.0, 1.0], &[level, up]).is_none());
        assert!(RecordedAttitude::new(&[1.0], &[level, up]).is_none());
        assert!(RecordedAttitude::new(&[], &[]).is_none());
        // The whole rotation: half way from level to nose up, the nose is 45° up and the
        // right wing stays level.
        let rot = r.rotation_at(1.5);
        assert!((rot.x_axis - want).length() < 1e-12, "{}", rot.x_axis);
        assert!((rot.y_axis - DVec3::Y).length() < 1e-12, "{}", rot.y_axis);
        let rolled = EulerZyx::new(0.4, 0.1, 2.0);
        let held = RecordedAttitude::new(&[0.0], &[rolled]).unwrap();
        let diff = held.rotation_at(3.0) - rolled.to_matrix();
        assert!(diff.to_cols_array().iter().all(|d| d.abs() < 1e-12));
        let bad = EulerZyx::new(f64::NAN, 0.0, 0.0);
        assert!(RecordedAttitude::new(&[1.0], &[bad]).is_none());
    }
}
