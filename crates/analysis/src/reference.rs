//! Reference flights: flights of the same aircraft, sensors and model, believed normal. A
//! model is never exact; what it leaves on them beyond their measurement noise is its own
//! error, and a test flight is judged against that floor instead of against noise alone.
//!
//! **The floor.** On each reference the model is compared as on any flight; per axis of
//! every channel, the model's own error is what the residual's mean square holds beyond the
//! reference's measured noise, σ²_model = max(0, RMS² − σ²_noise), pooled over the references
//! by their samples. The test flight's residuals are then weighted by
//! 1/√(σ²_noise + σ²_model) per axis (its own noise, the references' model error): a test
//! flight like the references reads about 1 "× the floor", a change of the aircraft more.
//! Everything downstream — noise units, the likelihood-ratio tests (whose effective number of
//! residuals already follows the residuals' autocorrelation), the verdict's threshold — works
//! in those units unchanged.
//!
//! Why weights and not a joint fit of references and test flight: the model's error is
//! structured (tables and a propeller a linear set cannot represent), so it does not cancel
//! between flights; what carries over is its size per axis, which is what the weights use.
//! It costs one comparison per reference, where a joint fit would refit every reference for
//! every candidate.
//!
//! **What can be a reference.** One of the same vehicle and aircraft (when the metadata say),
//! recording at least the channels the test flight records, flown in an overlapping envelope
//! (airspeed, height). Anything else is refused with the reason ([`ReferenceError`]).

use crate::compare::{compare_prepared, CompareConfig, NoiseEstimate, Prepared};
use wireflight_data::FlightData;
use wireflight_flight::model::Model;

/// The model's own error per axis, measured on reference flights (standard deviations, in
/// the units of [`NoiseEstimate`]; its RMS fields over the axes).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFloor {
    /// The model's own error per axis.
    pub model_error: NoiseEstimate,
    /// How many reference flights measured it.
    pub flights: usize,
    /// Their samples, together.
    pub samples: usize,
    /// Each reference's error against its noise alone (× its noise).
    pub noise_units: Vec<f64>,
}

/// A flight that cannot be a reference for the test flight, and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ReferenceError {
    /// Its metadata name another vehicle or aircraft.
    #[error(
        "reference `{name}` is another {field} (`{reference}`, the test flight's is `{test}`)"
    )]
    OtherAircraft {
        /// The reference's name.
        name: String,
        /// `vehicle` or `aircraft`.
        field: &'static str,
        /// What the reference says.
        reference: String,
        /// What the test flight says.
        test: String,
    },
    /// It lacks a channel the test flight records.
    #[error(
        "reference `{name}` does not record {channel}, which the test flight does: its model \
         error there is unknown"
    )]
    MissingChannel {
        /// The reference's name.
        name: String,
        /// The channel.
        channel: &'static str,
    },
    /// Its envelope does not overlap the test flight's.
    #[error(
        "reference `{name}` was flown at {quantity} {ref_lo:.1}–{ref_hi:.1} {unit}, the test \
         flight at {test_lo:.1}–{test_hi:.1} {unit}: no overlap, so its model error says \
         nothing about the test flight's"
    )]
    NoOverlap {
        /// The reference's name.
        name: String,
        /// `airspeed` or `height`.
        quantity: &'static str,
        /// Its unit.
        unit: &'static str,
        /// The reference's range (5–95% of its samples).
        ref_lo: f64,
        /// Upper end.
        ref_hi: f64,
        /// The test flight's range.
        test_lo: f64,
        /// Upper end.
        test_hi: f64,
    },
    /// Too short for one comparison window.
    #[error("reference `{name}` is too short for one comparison window")]
    TooShort {
        /// The reference's name.
        name: String,
    },
}

/// The 5% and 95% quantiles of `v` (finite values only); None when empty.
fn range(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    Some((at(0.05), at(0.95)))
}

/// Airspeed of each sample: measured, else the ground speed (m/s).
fn speeds(d: &FlightData) -> Vec<f64> {
    match (&d.airspeed, &d.vel_ned) {
        (Some(a), _) => a.clone(),
        (None, Some(v)) => v.iter().map(|v| v.length()).collect(),
        (None, None) => Vec::new(),
    }
}

/// Whether `reference` (named `name`) can be a reference for `test` (module docs).
///
/// # Errors
/// The reason it cannot.
pub fn check_reference(
    test: &FlightData,
    reference: &FlightData,
    name: &str,
) -> Result<(), ReferenceError> {
    let (t, r) = (&test.meta, &reference.meta);
    if let (Some(a), Some(b)) = (t.vehicle, r.vehicle) {
        if a != b {
            return Err(ReferenceError::OtherAircraft {
                name: name.into(),
                field: "vehicle",
                reference: b.to_string(),
                test: a.to_string(),
            });
        }
    }
    if let (Some(a), Some(b)) = (&t.aircraft, &r.aircraft) {
        if a != b {
            return Err(ReferenceError::OtherAircraft {
                name: name.into(),
                field: "aircraft",
                reference: b.clone(),
                test: a.clone(),
            });
        }
    }
    let channels: [(&'static str, bool, bool); 6] = [
        (
            "NED velocity",
            test.vel_ned.is_some() && !test.is_derived("vel_ned"),
            reference.vel_ned.is_some() && !reference.is_derived("vel_ned"),
        ),
        (
            "attitude",
            test.attitude.is_some(),
            reference.attitude.is_some(),
        ),
        (
            "body rates",
            test.rates_body.is_some() && !test.is_derived("rates_body"),
            reference.rates_body.is_some() && !reference.is_derived("rates_body"),
        ),
        (
            "airspeed",
            test.airspeed.is_some(),
            reference.airspeed.is_some(),
        ),
        (
            "the accelerometer",
            test.accel_body.is_some(),
            reference.accel_body.is_some(),
        ),
        (
            "controls",
            test.controls.is_some(),
            reference.controls.is_some(),
        ),
    ];
    if let Some((channel, _, _)) = channels.iter().find(|(_, t, r)| *t && !*r) {
        return Err(ReferenceError::MissingChannel {
            name: name.into(),
            channel,
        });
    }
    let height = |d: &FlightData| d.pos_ned.iter().map(|p| -p.z).collect::<Vec<_>>();
    for (quantity, unit, a, b) in [
        ("airspeed", "m/s", speeds(test), speeds(reference)),
        ("height", "m", height(test), height(reference)),
    ] {
        if let (Some((test_lo, test_hi)), Some((ref_lo, ref_hi))) =
            (range(a.into_iter()), range(b.into_iter()))
        {
            // Ranges that do not meet, with a little slack for a level flight's noise.
            let slack = 0.05 * (test_hi - test_lo).max(ref_hi - ref_lo).max(1.0);
            if test_lo > ref_hi + slack || ref_lo > test_hi + slack {
                return Err(ReferenceError::NoOverlap {
                    name: name.into(),
                    quantity,
                    unit,
                    ref_lo,
                    ref_hi,
                    test_lo,
                    test_hi,
                });
            }
        }
    }
    Ok(())
}

/// The axes of a [`NoiseEstimate`], by the (channel, axis) names of a comparison's per-axis
/// errors, with the factor from the comparison's unit to the estimate's (degrees → radians).
fn axis_slot<'a>(
    n: &'a mut NoiseEstimate,
    channel: &str,
    axis: &str,
) -> Option<(&'a mut f64, f64)> {
    let k = match axis {
        "north" | "roll" | "p" | "x" => 0,
        "east" | "pitch" | "q" | "y" => 1,
        "down" | "yaw" | "r" | "z" => 2,
        "airspeed" if channel == "air" => return Some((&mut n.airspeed_mps, 1.0)),
        _ => return None,
    };
    let deg = 1f64.to_radians();
    match channel {
        "position" => Some((&mut n.pos_axes[k], 1.0)),
        "velocity" => Some((&mut n.vel_axes[k], 1.0)),
        "attitude" => Some((&mut n.att_axes[k], deg)),
        "rates" => Some((&mut n.rate_axes[k], deg)),
        "accel" => Some((&mut n.accel_axes[k], 1.0)),
        _ => None,
    }
}

/// The model's own error on the reference flights (module docs). Each reference must have
/// passed [`check_reference`].
///
/// # Errors
/// A reference too short for one window.
pub fn model_floor(
    model: &Model,
    references: &[(&str, &FlightData)],
    cfg: CompareConfig,
) -> Result<ModelFloor, ReferenceError> {
    let mut sum = NoiseEstimate::default();
    let mut samples = 0usize;
    let mut noise_units = Vec::with_capacity(references.len());
    for (name, d) in references {
        let prep = Prepared::new(
            d,
            CompareConfig {
                model_error: None,
                ..cfg
            },
        );
        if prep.windows.is_empty() {
            return Err(ReferenceError::TooShort {
                name: (*name).into(),
            });
        }
        let cmp = compare_prepared(model, &prep);
        noise_units.push(cmp.noise_units());
        let n: usize = prep.windows.iter().map(|w| w.1 - w.0).sum();
        let w = n as f64;
        let mut noise = prep.noise;
        for a in &cmp.axes {
            let (Some((sigma, to)), Some((acc, _))) = (
                axis_slot(&mut noise, a.channel, a.axis).map(|(s, to)| (*s, to)),
                axis_slot(&mut sum, a.channel, a.axis),
            ) else {
                continue;
            };
            let rms = a.rms * to;
            *acc += w * (rms * rms - sigma * sigma).max(0.0);
        }
        samples += n;
    }
    let total = samples.max(1) as f64;
    let root = |v: &mut f64| *v = (*v / total).sqrt();
    let mut e = sum;
    for a in [
        &mut e.pos_axes,
        &mut e.vel_axes,
        &mut e.att_axes,
        &mut e.rate_axes,
        &mut e.accel_axes,
    ] {
        a.iter_mut().for_each(root);
    }
    root(&mut e.airspeed_mps);
    Ok(ModelFloor {
        model_error: e.with_rms(),
        flights: references.len(),
        samples,
        noise_units,
    })
}
