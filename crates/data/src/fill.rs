//! Filling in the channels a flight lacks: NED velocity, body rates and body velocity from the
//! channels it has ([`FlightData::derive_missing`]), with the smoothing differentiator of
//! [`crate::derive`].

use glam::DVec3;

use super::{FlightData, DERIVED_RATES_BODY, DERIVED_VEL_BODY, DERIVED_VEL_NED};
use crate::derive::{body_rates_from_attitude, Differentiator, Window};
use crate::sampling::{fill_linear, Channel};

impl FlightData {
    /// [`derive_missing_with`](Self::derive_missing_with) with the default [`Window`].
    /// [`parse`](super::parse) and [`read`](super::read) call this before returning.
    pub fn derive_missing(&mut self) {
        self.derive_missing_with(Window::default());
    }

    /// Fills absent channels that can be computed, and records them in
    /// [`derived`](Self::derived):
    ///
    /// * `vel_ned`: R·vel_body when attitude and body velocity are present (exact), else the
    ///   smoothed derivative of the positions;
    /// * `rates_body`: from the smoothed derivatives of the continuously unwrapped attitude
    ///   ([`body_rates_from_attitude`]);
    /// * `vel_body`: Rᵀ·vel_ned when attitude is present.
    ///
    /// Present channels are never changed. Does nothing with fewer than two samples or when
    /// [`validate`](Self::validate) fails. A channel sampled at its own rate
    /// ([`Sampling`](crate::Sampling)) is differentiated over its own samples, and the
    /// derivative filled in between them.
    pub fn derive_missing_with(&mut self, window: Window) {
        if self.len() < 2 || self.validate().is_err() {
            return;
        }
        let needs_diff = self.vel_ned.is_none() || self.rates_body.is_none();
        let diff =
            needs_diff.then(|| Differentiator::new(&self.time, window.half_samples(&self.time)));
        if needs_diff && !self.sampling.is_all() {
            self.derive_from_own_samples(window);
        }
        let mark = |derived: &mut Vec<&'static str>, name: &'static str| {
            if !derived.contains(&name) {
                derived.push(name);
            }
        };
        if self.vel_ned.is_none() {
            let v = match (&self.attitude, &self.vel_body) {
                (Some(att), Some(vb)) => att
                    .iter()
                    .zip(vb)
                    .map(|(e, v)| e.to_matrix() * *v)
                    .collect(),
                _ => match &diff {
                    Some(d) => d.apply_vec3(&self.pos_ned),
                    None => return,
                },
            };
            self.vel_ned = Some(v);
            mark(&mut self.derived, DERIVED_VEL_NED);
        }
        if self.rates_body.is_none() {
            if let (Some(att), Some(d)) = (&self.attitude, &diff) {
                self.rates_body = Some(body_rates_from_attitude(d, att));
                mark(&mut self.derived, DERIVED_RATES_BODY);
            }
        }
        if self.vel_body.is_none() {
            if let (Some(att), Some(vn)) = (&self.attitude, &self.vel_ned) {
                self.vel_body = Some(
                    att.iter()
                        .zip(vn)
                        .map(|(e, v)| e.to_matrix().transpose() * *v)
                        .collect(),
                );
                mark(&mut self.derived, DERIVED_VEL_BODY);
            }
        }
    }
}

impl FlightData {
    /// The velocity from positions and the rates from attitude, each channel differentiated
    /// over its own samples (module docs): what [`Self::derive_missing_with`] does first for
    /// a flight whose channels have their own rates.
    fn derive_from_own_samples(&mut self, window: Window) {
        let n = self.len();
        let own = |channel: Channel| -> (Vec<usize>, Vec<f64>) {
            let rows: Vec<usize> = self.sampling.rows(channel, n).collect();
            let t = rows.iter().map(|&i| self.time[i]).collect();
            (rows, t)
        };
        let spread = |rows: &[usize], values: Vec<DVec3>| -> Vec<DVec3> {
            let mut full = vec![DVec3::ZERO; n];
            let mut sampled = vec![false; n];
            for (&i, v) in rows.iter().zip(values) {
                full[i] = v;
                sampled[i] = true;
            }
            fill_linear(&self.time, &sampled, &mut full);
            full
        };
        if self.vel_ned.is_none() && self.vel_body.is_none() {
            let (rows, t) = own(Channel::Position);
            if rows.len() >= 2 {
                let d = Differentiator::new(&t, window.half_samples(&t));
                let p: Vec<DVec3> = rows.iter().map(|&i| self.pos_ned[i]).collect();
                self.vel_ned = Some(spread(&rows, d.apply_vec3(&p)));
                self.derived.push(DERIVED_VEL_NED);
            }
        }
        if let (None, Some(att)) = (&self.rates_body, &self.attitude) {
            let (rows, t) = own(Channel::Attitude);
            if rows.len() >= 2 {
                let d = Differentiator::new(&t, window.half_samples(&t));
                let a: Vec<_> = rows.iter().map(|&i| att[i]).collect();
                self.rates_body = Some(spread(&rows, body_rates_from_attitude(&d, &a)));
                self.derived.push(DERIVED_RATES_BODY);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use wireflight_geometry::euler::EulerZyx;

    use super::*;
    use crate::Metadata;

    #[test]
    fn derive_missing_fills_velocities_and_rates() {
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let pos: Vec<DVec3> = t.iter().map(|&t| DVec3::new(30.0 * t, 0.0, -t)).collect();
        let mut d = FlightData::new(Metadata::default(), t.clone(), pos);
        d.attitude = Some(vec![EulerZyx::from_degrees(90.0, 0.0, 0.0); t.len()]);
        d.derive_missing();
        assert_eq!(
            d.derived,
            vec![DERIVED_VEL_NED, DERIVED_RATES_BODY, DERIVED_VEL_BODY]
        );
        for v in d.vel_ned.as_ref().unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(30.0, 0.0, -1.0), 1e-9), "{v}");
        }
        // Heading east while moving north: the motion is to the left (−v) in the body.
        for v in d.vel_body.as_ref().unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(0.0, -30.0, -1.0), 1e-9), "{v}");
        }
        for r in d.rates_body.as_ref().unwrap() {
            assert!(r.abs_diff_eq(DVec3::ZERO, 1e-12));
        }
        // Idempotent, and present channels are kept.
        let before = d.clone();
        d.derive_missing();
        assert_eq!(d, before);
    }

    #[test]
    fn vel_ned_comes_from_body_velocity_when_it_can() {
        let t = vec![0.0, 1.0, 2.0];
        let mut d = FlightData::new(Metadata::default(), t, vec![DVec3::ZERO; 3]);
        d.attitude = Some(vec![EulerZyx::from_degrees(90.0, 0.0, 0.0); 3]);
        d.vel_body = Some(vec![DVec3::new(10.0, 0.0, 0.0); 3]);
        d.derive_missing();
        assert_eq!(d.derived, vec![DERIVED_VEL_NED, DERIVED_RATES_BODY]);
        for v in d.vel_ned.unwrap() {
            assert!(v.abs_diff_eq(DVec3::new(0.0, 10.0, 0.0), 1e-12));
        }
    }

    #[test]
    fn invalid_data_is_left_alone() {
        let mut d = FlightData::new(Metadata::default(), vec![0.0, 0.0], vec![DVec3::ZERO; 2]);
        d.derive_missing();
        assert!(d.vel_ned.is_none() && d.derived.is_empty());
        let mut d = FlightData::new(Metadata::default(), vec![0.0, 1.0], vec![DVec3::ZERO]);
        assert!(d.validate().is_err());
        d.derive_missing();
        assert!(d.vel_ned.is_none());
    }
}
