//! What imperfect instruments make of a flight: the model's measurement effects
//! ([`crate::effects::sensors`]) applied to a recorded, noise-free truth, so that `simulate`
//! writes what biased, scaled, misaligned or late sensors would have logged (its noise is
//! added after).
//!
//! A late navigation solution reads at t the position and NED velocity of t − delay,
//! interpolated linearly between the recorded samples; before the first sample it reads the
//! first state flown back at its own velocity — exact for a flight that starts trimmed, as a
//! simulated one does.

use glam::{DMat3, DQuat, DVec3};

use crate::effects::Reading;
use crate::model::Model;
use wireflight_data::FlightData;
use wireflight_geometry::euler::EulerZyx;

/// Turn the noise-free `truth` into what the model's measurement effects read of it. A model
/// without them leaves it as it is.
pub fn sense(model: &Model, truth: &mut FlightData) {
    if !model.has_measurement_effects() || truth.is_empty() {
        return;
    }
    let delay = model.nav_delay();
    if delay > 0.0 {
        delay_navigation(truth, delay);
    }
    for i in 0..truth.len() {
        let mut r = Reading {
            pos_ned: truth.pos_ned[i],
            vel_ned: truth.vel_ned.as_ref().map_or(DVec3::ZERO, |v| v[i]),
            quat: truth.attitude.as_ref().map_or(DQuat::IDENTITY, |a| {
                DQuat::from_mat3(&a[i].to_matrix()).normalize()
            }),
            rates: truth.rates_body.as_ref().map_or(DVec3::ZERO, |w| w[i]),
            airspeed: truth.airspeed.as_ref().map_or(0.0, |s| s[i]),
            specific_force: truth.accel_body.as_ref().map_or(DVec3::ZERO, |a| a[i]),
        };
        model.measure(&mut r);
        truth.pos_ned[i] = r.pos_ned;
        if let Some(v) = &mut truth.vel_ned {
            v[i] = r.vel_ned;
        }
        if let Some(a) = &mut truth.attitude {
            a[i] = EulerZyx::from_matrix(DMat3::from_quat(r.quat)).0;
        }
        if let Some(w) = &mut truth.rates_body {
            w[i] = r.rates;
        }
        if let Some(s) = &mut truth.airspeed {
            s[i] = r.airspeed;
        }
        if let Some(a) = &mut truth.accel_body {
            a[i] = r.specific_force;
        }
    }
}

/// Position and NED velocity read `delay` s late (module docs).
fn delay_navigation(d: &mut FlightData, delay: f64) {
    let pos = d.pos_ned.clone();
    let vel = d.vel_ned.clone();
    let v0 = vel
        .as_ref()
        .and_then(|v| v.first().copied())
        .unwrap_or_else(|| match (pos.len(), d.time.len()) {
            (n, m) if n > 1 && m > 1 => (pos[1] - pos[0]) / (d.time[1] - d.time[0]),
            _ => DVec3::ZERO,
        });
    let t0 = d.time[0];
    for i in 0..d.len() {
        let tau = d.time[i] - delay;
        let (p, v) = if tau <= t0 {
            (pos[0] - v0 * (t0 - tau), v0)
        } else {
            let j = d.time[..=i]
                .partition_point(|&t| t <= tau)
                .saturating_sub(1);
            let j = j.min(d.len().saturating_sub(2));
            let w = (tau - d.time[j]) / (d.time[j + 1] - d.time[j]);
            let lerp = |a: DVec3, b: DVec3| a * (1.0 - w) + b * w;
            (
                lerp(pos[j], pos[j + 1]),
                vel.as_ref().map_or(v0, |v| lerp(v[j], v[j + 1])),
            )
        };
        d.pos_ned[i] = p;
        if let Some(velocities) = &mut d.vel_ned {
            velocities[i] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Origin;
    use crate::spec::{EffectSpec, ModelSpec};
    use wireflight_data::VehicleKind;

    fn model(effects: &[&str]) -> Model {
        let mut spec = ModelSpec::baseline(VehicleKind::FixedWing);
        for e in effects {
            spec.effects.push(EffectSpec::parse(e).unwrap());
        }
        spec.build(Origin::default()).unwrap()
    }

    /// A straight, level flight at 25 m/s north: what each instrument reads of it.
    fn straight() -> FlightData {
        let n = 101;
        let time: Vec<f64> = (0..n).map(|i| 0.02 * i as f64).collect();
        let mut d = FlightData::new(
            Default::default(),
            time.clone(),
            time.iter()
                .map(|&t| DVec3::new(25.0 * t, 0.0, -100.0))
                .collect(),
        );
        d.vel_ned = Some(vec![DVec3::new(25.0, 0.0, 0.0); n]);
        d.attitude = Some(vec![EulerZyx::new(0.0, 0.05, 0.0); n]);
        d.rates_body = Some(vec![DVec3::ZERO; n]);
        d.airspeed = Some(vec![25.0; n]);
        d
    }

    #[test]
    fn sensors_read_the_truth_as_their_effects_say() {
        let mut d = straight();
        sense(
            &model(&[
                "nav_delay:delay_s=0.1",
                "gyro_bias:p_dps=1,q_dps=-2",
                "airspeed_scale:factor=0.9",
                "attitude_offset:pitch_deg=2",
            ]),
            &mut d,
        );
        // 0.1 s late at 25 m/s: 2.5 m behind, everywhere (before the start too).
        for (t, p) in d.time.iter().zip(&d.pos_ned) {
            assert!((p.x - (25.0 * t - 2.5)).abs() < 1e-9, "{t} {p}");
        }
        let w = d.rates_body.as_ref().unwrap()[7];
        assert!((w.x.to_degrees() - 1.0).abs() < 1e-12 && (w.y.to_degrees() + 2.0).abs() < 1e-12);
        assert!((d.airspeed.as_ref().unwrap()[3] - 22.5).abs() < 1e-12);
        let a = d.attitude.as_ref().unwrap()[5];
        assert!(
            (a.pitch - (0.05 + 2f64.to_radians())).abs() < 1e-12,
            "{a:?}"
        );
    }

    #[test]
    fn without_measurement_effects_nothing_changes() {
        let mut d = straight();
        let before = d.clone();
        sense(&model(&["wind:north_mps=3"]), &mut d);
        assert_eq!(d, before);
    }
}
