//! Measurement effects: what is wrong with the sensors rather than with the airplane.
//!
//! They act on what the model predicts the sensors *read* ([`Effect::measure`](super::Effect::measure),
//! [`Effect::nav_delay`](super::Effect::nav_delay)), never on the flight: every hook of the
//! dynamics keeps its default, and [`Effect::is_measurement`](super::Effect::is_measurement)
//! says so, so the equations of motion skip them. The
//! comparison flies the model, then applies them to its readings; a diagnosis screens and fits
//! them like any other effect, and joins them with physical causes.
//!
//! [`Effect::measure`](super::Effect::measure) must be affine in each channel it changes (a bias, a scale factor, a
//! fixed misalignment): the comparison's linearisation takes the change of a reading per
//! unit change of the truth from two evaluations.

mod accel_bias;
mod airspeed_bias;
mod airspeed_scale;
mod attitude_offset;
mod gyro_bias;
mod nav_delay;

pub use accel_bias::AccelBias;
pub use airspeed_bias::AirspeedBias;
pub use airspeed_scale::AirspeedScale;
pub use attitude_offset::AttitudeOffset;
pub use gyro_bias::GyroBias;
pub use nav_delay::{NavDelay, MAX_NAV_DELAY};

pub(super) use accel_bias::INFO as ACCEL_BIAS;
pub(super) use airspeed_bias::INFO as AIRSPEED_BIAS;
pub(super) use airspeed_scale::INFO as AIRSPEED_SCALE;
pub(super) use attitude_offset::INFO as ATTITUDE_OFFSET;
pub(super) use gyro_bias::INFO as GYRO_BIAS;
pub(super) use nav_delay::INFO as NAV_DELAY;

#[cfg(test)]
pub(crate) mod tests {
    use glam::{DQuat, DVec3};

    use super::super::{Origin, Reading, CATALOGUE};
    use crate::spec::ModelSpec;
    use wireflight_data::VehicleKind;

    /// A reading with every channel non-zero.
    pub(crate) fn reading() -> Reading {
        Reading {
            pos_ned: DVec3::new(120.0, -40.0, -200.0),
            vel_ned: DVec3::new(22.0, 5.0, -1.0),
            quat: DQuat::from_euler(glam::EulerRot::ZYX, 0.7, 0.1, -0.3),
            rates: DVec3::new(0.05, -0.02, 0.1),
            airspeed: 24.0,
            specific_force: DVec3::new(0.8, 0.3, -9.6),
        }
    }

    /// Every measurement effect, its parameters away from their absent values: it leaves the
    /// flight alone to the bit, and what it does to a reading is affine in each channel
    /// (the comparison's linearisation relies on it).
    #[test]
    fn measurement_effects_change_the_readings_only_and_affinely() {
        let base = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let (x, cmd) = super::super::tests::flying();
        let mut seen = 0;
        for info in CATALOGUE {
            let mut e = info.build(&base.effect_context());
            if !e.is_measurement() {
                continue;
            }
            seen += 1;
            for p in info.params {
                let v = p.absent.unwrap_or(0.0) + 0.3 * (p.range.1 - p.range.0) / 2.0;
                e.set_param(p.name, p.check(v).unwrap()).unwrap();
            }
            let mut with = base.clone();
            with.add_effect(e).unwrap();
            assert_eq!(
                with.derivative(1.0, &x, &cmd).0,
                base.derivative(1.0, &x, &cmd).0,
                "{}",
                info.name
            );
            // f(a + 2δ) − f(a + δ) = f(a + δ) − f(a) for the vector channels and airspeed.
            let at = |k: f64| {
                let mut r = reading();
                r.rates += DVec3::splat(0.01 * k);
                r.airspeed += 0.5 * k;
                r.specific_force += DVec3::splat(0.2 * k);
                with.measure(&mut r);
                r
            };
            let (r0, r1, r2) = (at(0.0), at(1.0), at(2.0));
            assert!(((r2.rates - r1.rates) - (r1.rates - r0.rates)).length() < 1e-15);
            assert!(((r2.airspeed - r1.airspeed) - (r1.airspeed - r0.airspeed)).abs() < 1e-12);
            let df =
                (r2.specific_force - r1.specific_force) - (r1.specific_force - r0.specific_force);
            assert!(df.length() < 1e-12, "{}", info.name);
        }
        assert_eq!(seen, 6);
    }

    /// The misalignment reads as the offsets in level flight.
    #[test]
    fn an_attitude_offset_reads_as_its_roll_and_pitch_in_level_flight() {
        let e = super::AttitudeOffset { deg: [2.0, -1.5] };
        let mut r = reading();
        r.quat = DQuat::IDENTITY;
        crate::effects::Effect::measure(&e, &mut r);
        let (_, pitch, roll) = r.quat.to_euler(glam::EulerRot::ZYX);
        assert!(
            (roll.to_degrees() - 2.0).abs() < 1e-12 && (pitch.to_degrees() + 1.5).abs() < 1e-12
        );
    }
}
