//! Generating flights: fly a manoeuvre with a model (which may hold effects the output does not
//! mention), sample it at the output rate, add measurement noise — white, and optionally the
//! wandering errors of a real log's sensors and navigation filter with each channel at its own
//! rate ([`crate::sensor_errors`]).
//!
//! Determinism: the same model, spec and seed give the same file, bit for bit (ChaCha8 noise,
//! fixed-step RK4, no wall-clock input).

use glam::DVec3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::autopilot::{Autopilot, Manoeuvre};
use super::model::{Model, State, Vehicle};
use super::sensor_errors::SensorErrors;
use super::trim::{trim_level, TrimError};
use super::turbulence::{GustField, GustTruth, Turbulence, TurbulenceError};
use wireflight_data::{Channel, Controls, FlightData, Metadata, VehicleKind};
use wireflight_geometry::euler::EulerZyx;

/// Standard deviations of the Gaussian measurement noise per channel (the accelerometer's is
/// [`SimSpec::accelerometer`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Noise {
    /// Position, m (each axis).
    pub pos_m: f64,
    /// Attitude angles, degrees.
    pub att_deg: f64,
    /// Velocities (NED and airspeed), m/s.
    pub vel_mps: f64,
    /// Body rates, degrees/s.
    pub rate_dps: f64,
}

/// What to fly and how to record it.
#[derive(Clone, Debug, PartialEq)]
pub struct SimSpec {
    /// The manoeuvre.
    pub manoeuvre: Manoeuvre,
    /// Length of the flight, s.
    pub duration_s: f64,
    /// Output (and autopilot) rate, Hz.
    pub rate_hz: f64,
    /// Trim airspeed, m/s (fixed-wing).
    pub airspeed_mps: f64,
    /// Starting height above the origin, m.
    pub height_m: f64,
    /// Launch speed of the point-mass `ballistic` manoeuvre (60° elevation, due north), m/s.
    pub launch_speed_mps: f64,
    /// Measurement noise.
    pub noise: Noise,
    /// Record an accelerometer (a fixed wing's specific force) with this noise (Gaussian, each
    /// axis), m/s²; None: no accelerometer. Drawn from the same generator after every other
    /// channel's noise, so the other channels of a flight are the same whatever it is.
    pub accelerometer: Option<f64>,
    /// Noise seed.
    pub seed: u64,
    /// Free text for the `source` metadata.
    pub source: String,
    /// Aircraft name for the metadata.
    pub aircraft: Option<String>,
    /// Visible effects, listed in the metadata (`effects`); hidden ones are not.
    pub listed_effects: Vec<String>,
    /// Fly through Dryden gusts (fixed wing): part of the truth's air, at the starting height
    /// and the trim airspeed; recorded in the metadata as `turbulence`
    /// ([`GustTruth::to_record`]). None: calm air.
    pub turbulence: Option<Turbulence>,
    /// The wandering errors of a real log's sensors and navigation filter, on top of the
    /// white noise, each channel at its own rate ([`SensorErrors`]); recorded in the metadata
    /// as `sensor_errors`. None: white noise alone, every channel at the output rate.
    pub sensor_errors: Option<SensorErrors>,
}

impl SimSpec {
    /// A spec for `manoeuvre` over `duration_s` with the defaults of `wireflight simulate`:
    /// 50 Hz, 25 m/s trim airspeed, 200 m above the origin, a 150 m/s launch for a point mass,
    /// no noise, seed 1.
    pub fn new(manoeuvre: Manoeuvre, duration_s: f64) -> Self {
        Self {
            manoeuvre,
            duration_s,
            rate_hz: 50.0,
            airspeed_mps: 25.0,
            height_m: 200.0,
            launch_speed_mps: 150.0,
            noise: Noise::default(),
            accelerometer: None,
            seed: 1,
            source: format!("wireflight simulate --manoeuvre {manoeuvre}"),
            aircraft: None,
            listed_effects: Vec::new(),
            turbulence: None,
            sensor_errors: None,
        }
    }
}

/// A flight that cannot be simulated: an invalid spec, a manoeuvre for the other vehicle
/// family, no trim, or a flight that diverged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// The duration is zero, negative or not finite.
    #[error("--duration {} s must be positive (a finite number > 0)", num(*.0))]
    Duration(f64),
    /// The rate is outside (0, 10000] Hz.
    #[error("--rate {} Hz must be in (0, 10000]", num(*.0))]
    Rate(f64),
    /// The duration at the rate gives a single sample.
    #[error(
        "--duration {} s at --rate {} Hz is a single sample: the rate must be at least \
         1/duration", num(*.duration_s), num(*.rate_hz)
    )]
    SingleSample {
        /// The duration, s.
        duration_s: f64,
        /// The rate, Hz.
        rate_hz: f64,
    },
    /// More samples than the limit.
    #[error(
        "{} s at {} Hz is {} samples, more than --max-samples {max_samples} (raise it, or \
         shorten --duration or lower --rate)", num(*.duration_s), num(*.rate_hz), num(*.samples)
    )]
    TooManySamples {
        /// The duration, s.
        duration_s: f64,
        /// The rate, Hz.
        rate_hz: f64,
        /// The samples it would take.
        samples: f64,
        /// The limit.
        max_samples: u64,
    },
    /// More integration steps than the limit allows.
    #[error(
        "{} s takes {} integration steps of at most {MAX_STEP} s, more than \
         {STEPS_PER_SAMPLE_LIMIT} × --max-samples {max_samples} (raise it, or shorten \
         --duration)", num(*.duration_s), num(*.steps)
    )]
    TooManySteps {
        /// The duration, s.
        duration_s: f64,
        /// The steps it would take.
        steps: f64,
        /// The limit of samples.
        max_samples: u64,
    },
    /// The flight would need more memory than the machine has free.
    #[error(
        "{} s at {} Hz is {samples} samples, which need about {} MiB of memory; only {} MiB \
         is free, so at most {most} samples can be simulated here (--max-samples does not \
         raise this bound; shorten --duration or lower --rate)",
        num(*.duration_s), num(*.rate_hz), .bytes >> 20, .available >> 20
    )]
    TooMuchMemory {
        /// The duration, s.
        duration_s: f64,
        /// The rate, Hz.
        rate_hz: f64,
        /// The samples it would take.
        samples: u64,
        /// The memory they need, bytes (about).
        bytes: u64,
        /// The memory free for them, bytes.
        available: u64,
        /// The most samples that fit.
        most: u64,
    },
    /// A noise level that is negative or not finite.
    #[error(
        "{channel} noise (--noise-{}) {} must be a finite number ≥ 0",
        noise_option(.channel), num(*.sigma)
    )]
    Noise {
        /// `position`, `attitude`, `velocity`, `rate` or `acceleration`.
        channel: &'static str,
        /// The standard deviation given.
        sigma: f64,
    },
    /// A manoeuvre for the other vehicle family.
    #[error("manoeuvre `{manoeuvre}` is not for a {vehicle} vehicle")]
    Manoeuvre {
        /// The manoeuvre.
        manoeuvre: Manoeuvre,
        /// The model's vehicle family.
        vehicle: VehicleKind,
    },
    /// No trim to start the fixed wing from.
    #[error(transparent)]
    Trim(#[from] TrimError),
    /// Turbulence for a point mass, or a gust field that cannot be made.
    #[error("turbulence: {0}")]
    Turbulence(String),
    /// A channel's rate (of the sensor errors) that is not the output rate divided by a whole
    /// number.
    #[error(
        "sensor errors: {channel} at {} Hz: --rate {} Hz is not a whole multiple of it (a \
         channel is sampled at every k-th output sample: give --rate a multiple of every \
         channel's rate)",
        num(*.channel_hz), num(*.rate_hz)
    )]
    ChannelRate {
        /// The channel.
        channel: Channel,
        /// Its rate, Hz.
        channel_hz: f64,
        /// The output rate, Hz.
        rate_hz: f64,
    },
    /// The state became non-finite.
    #[error("the simulated flight diverged at t = {0:.2} s")]
    Diverged(f64),
    /// A force or moment of the model became NaN or ∞: which, and the values that made it.
    #[error("the simulated flight stopped at t = {t:.2} s: {why}")]
    NotFinite {
        /// Time of the integration stage where it did, s.
        t: f64,
        /// The effect's account ([`Model::explain_non_finite`]).
        why: String,
    },
}

/// Longest integration step inside one output interval, s.
pub const MAX_STEP: f64 = 0.01;

/// Default most samples of one simulated flight (`--max-samples`): 11 hours at 50 Hz.
pub const DEFAULT_MAX_SAMPLES: u64 = 2_000_000;
/// Integration steps allowed per sample of the limit: a low output rate integrates several
/// steps of at most [`MAX_STEP`] per sample.
const STEPS_PER_SAMPLE_LIMIT: u64 = 10;

/// Fly `spec` with `model` and return the (noisy) recorded flight; at most
/// [`DEFAULT_MAX_SAMPLES`] samples (see [`simulate_limited`]). The ground is the origin's
/// altitude: a flight that reaches it (down > 0) ends at that sample, shorter than asked.
///
/// # Errors
/// As [`simulate_limited`].
pub fn simulate(model: &Model, spec: &SimSpec) -> Result<FlightData, SimulateError> {
    simulate_limited(model, spec, DEFAULT_MAX_SAMPLES)
}

/// Fly `spec` with `model` and return the (noisy) recorded flight, refusing flights of more
/// than `max_samples` samples (or `10 × max_samples` integration steps) before any work: the
/// memory and time of a run are bounded by the limit, whatever the duration and rate.
///
/// # Errors
/// Invalid spec (non-positive duration/rate, fewer than two samples, more than the limit,
/// negative or non-finite noise), a manoeuvre for the other vehicle family, no trim at the
/// requested airspeed, or a flight that diverged (non-finite state).
pub fn simulate_limited(
    model: &Model,
    spec: &SimSpec,
    max_samples: u64,
) -> Result<FlightData, SimulateError> {
    simulate_bounded(model, spec, max_samples, u64::MAX)
}

/// About the most memory one sample of a simulated flight takes, bytes, until its file is
/// written: the recorded channels, their CSV text (with its growth) and the read-back check of
/// that text (a fixed-wing flight peaks at about 510 bytes a sample; doubled for safety).
pub const BYTES_PER_SAMPLE: u64 = 1024;

/// [`simulate_limited`], also refusing (before any work) a flight whose samples need more
/// than `max_bytes` of memory ([`BYTES_PER_SAMPLE`] each): `--max-samples` permits a length,
/// this bound says what the machine can hold.
///
/// # Errors
/// As [`simulate_limited`], and [`SimulateError::TooMuchMemory`].
pub fn simulate_bounded(
    model: &Model,
    spec: &SimSpec,
    max_samples: u64,
    max_bytes: u64,
) -> Result<FlightData, SimulateError> {
    if !(spec.duration_s > 0.0 && spec.duration_s.is_finite()) {
        return Err(SimulateError::Duration(spec.duration_s));
    }
    if !(spec.rate_hz > 0.0 && spec.rate_hz <= 10_000.0) {
        return Err(SimulateError::Rate(spec.rate_hz));
    }
    let n = (spec.duration_s * spec.rate_hz).round() + 1.0;
    if n < 2.0 {
        return Err(SimulateError::SingleSample {
            duration_s: spec.duration_s,
            rate_hz: spec.rate_hz,
        });
    }
    if n > max_samples as f64 {
        return Err(SimulateError::TooManySamples {
            duration_s: spec.duration_s,
            rate_hz: spec.rate_hz,
            samples: n,
            max_samples,
        });
    }
    // `n` ≤ `max_samples` ≤ u64::MAX here.
    let n_u64 = n as u64;
    let bytes = n_u64.saturating_mul(BYTES_PER_SAMPLE);
    if bytes > max_bytes || usize::try_from(n_u64).is_err() {
        return Err(SimulateError::TooMuchMemory {
            duration_s: spec.duration_s,
            rate_hz: spec.rate_hz,
            samples: n_u64,
            bytes,
            available: max_bytes,
            most: max_bytes / BYTES_PER_SAMPLE,
        });
    }
    let steps = spec.duration_s / (1.0 / spec.rate_hz).min(MAX_STEP);
    let max_steps = max_samples.saturating_mul(STEPS_PER_SAMPLE_LIMIT);
    if steps > max_steps as f64 {
        return Err(SimulateError::TooManySteps {
            duration_s: spec.duration_s,
            steps,
            max_samples,
        });
    }
    let nz = &spec.noise;
    for (name, sigma) in [
        ("position", nz.pos_m),
        ("attitude", nz.att_deg),
        ("velocity", nz.vel_mps),
        ("rate", nz.rate_dps),
        ("acceleration", spec.accelerometer.unwrap_or(0.0)),
    ] {
        if !(sigma.is_finite() && sigma >= 0.0) {
            return Err(SimulateError::Noise {
                channel: name,
                sigma,
            });
        }
    }
    let strides = channel_strides(spec)?;
    let kind = model.vehicle.kind();
    if spec.manoeuvre.is_point_mass() != (kind == VehicleKind::PointMass) {
        return Err(SimulateError::Manoeuvre {
            manoeuvre: spec.manoeuvre,
            vehicle: kind,
        });
    }
    let dt_out = 1.0 / spec.rate_hz;
    let max_dt = dt_out.min(MAX_STEP);
    // The gusts fly in a copy of the model: part of the truth's air, not an effect of it.
    let gusty;
    let (model, gust_truth) = match spec.turbulence {
        None => (model, None),
        Some(_) if kind == VehicleKind::PointMass => {
            return Err(SimulateError::Turbulence(
                "only a fixed wing flies through gusts".to_string(),
            ))
        }
        Some(turbulence) => {
            let truth = GustTruth::new(turbulence, spec.height_m, spec.airspeed_mps);
            let field = GustField::new(&truth, spec.duration_s, max_dt)
                .map_err(|e: TurbulenceError| SimulateError::Turbulence(e.to_string()))?;
            let mut m = model.clone();
            m.effects.push(Box::new(field));
            gusty = m;
            (&gusty, Some(truth))
        }
    };
    // At most `max_samples` (checked above).
    let samples = n as usize;

    let mut truth = Recorder::with_capacity(samples, kind);
    match &model.vehicle {
        Vehicle::PointMass => {
            let mut x = State::default();
            x.set_pos_ned(DVec3::new(0.0, 0.0, -spec.height_m));
            let (speed, elevation) = (spec.launch_speed_mps, 60f64.to_radians());
            x.set_vel(DVec3::new(
                speed * elevation.cos(),
                0.0,
                -speed * elevation.sin(),
            ));
            for k in 0..samples {
                let t = k as f64 * dt_out;
                truth.push_point_mass(t, &x);
                if x.pos_ned().z > 0.0 && k > 0 {
                    break; // back on the ground
                }
                x = model.advance(t, &x, &Controls::default(), t + dt_out, max_dt);
                check_finite(&x, t)?;
            }
        }
        Vehicle::FixedWing(_) => {
            let trim = trim_level(
                model,
                spec.airspeed_mps,
                0.0,
                DVec3::new(0.0, 0.0, -spec.height_m),
            )?;
            let mut x = trim.state;
            let mut pilot = Autopilot::new(
                spec.manoeuvre,
                trim.controls,
                trim.state.attitude().pitch,
                spec.airspeed_mps,
            );
            for k in 0..samples {
                let t = k as f64 * dt_out;
                let air = model.air_data(t, &x);
                let cmd = pilot.commands(t, dt_out, x.attitude(), x.omega().to_array(), &air);
                // What an accelerometer reads now, under the commands given now (those held
                // until the next sample, as the controls column records them).
                let accel = model.specific_force(t, &x, &cmd);
                truth.push_fixed_wing(t, &x, air.airspeed, cmd, accel);
                if x.pos_ned().z > 0.0 {
                    break; // on the ground (the origin's altitude): the flight ends here
                }
                let next = model.advance(t, &x, &cmd, t + dt_out, max_dt);
                if !next.is_finite() {
                    return Err(model
                        .explain_advance(t, &x, &cmd, t + dt_out, max_dt)
                        .map_or(SimulateError::Diverged(t), |(t, why)| {
                            SimulateError::NotFinite { t, why }
                        }));
                }
                x = next;
            }
        }
    }

    let meta = Metadata {
        vehicle: Some(kind),
        aircraft: spec.aircraft.clone(),
        latitude_deg: Some(model.origin.latitude_deg),
        longitude_deg: Some(model.origin.longitude_deg),
        altitude_m: Some(model.origin.altitude_m),
        mass_kg: None,
        reference_area_m2: None,
        source: Some(spec.source.clone()),
        other: (!spec.listed_effects.is_empty())
            .then(|| ("effects".to_string(), spec.listed_effects.join(",")))
            .into_iter()
            .chain(gust_truth.map(|t| {
                let key = super::turbulence::TRUTH_KEY.to_string();
                (key, t.to_record())
            }))
            .chain(spec.sensor_errors.as_ref().map(|e| {
                let key = super::sensor_errors::TRUTH_KEY.to_string();
                (key, e.to_record(spec.seed))
            }))
            .collect(),
    };
    let mut flight = truth.finish(model, meta, spec);
    for (channel, stride) in strides {
        let sampled: Vec<bool> = (0..flight.len()).map(|i| i % stride == 0).collect();
        flight.keep_samples(channel, &sampled);
    }
    Ok(flight)
}

/// Each channel of the sensor errors that has its own rate, with the stride of its samples
/// among the output samples (every `stride`-th, from the first).
///
/// # Errors
/// A rate that is not the output rate divided by a whole number.
fn channel_strides(spec: &SimSpec) -> Result<Vec<(Channel, usize)>, SimulateError> {
    let Some(errors) = &spec.sensor_errors else {
        return Ok(Vec::new());
    };
    let r = errors.rates();
    let mut strides = Vec::new();
    for (channel, hz) in [
        (Channel::Position, r.position),
        (Channel::Velocity, r.velocity),
        (Channel::Attitude, r.attitude),
        (Channel::Rates, r.rates),
        (Channel::Airspeed, r.airspeed),
        (Channel::Accelerometer, r.accel),
    ] {
        let Some(hz) = hz else { continue };
        let k = spec.rate_hz / hz;
        let whole = k.round();
        if !(whole >= 1.0 && (k - whole).abs() <= 1e-9 * k) {
            return Err(SimulateError::ChannelRate {
                channel,
                channel_hz: hz,
                rate_hz: spec.rate_hz,
            });
        }
        if whole > 1.0 {
            strides.push((channel, whole as usize));
        }
    }
    Ok(strides)
}

/// The option of a noise channel's level (`position` → `pos`, as in `--noise-pos`).
fn noise_option(channel: &str) -> &str {
    match channel {
        "position" => "pos",
        "attitude" => "att",
        "velocity" => "vel",
        "acceleration" => "acc",
        other => other,
    }
}

/// A number for a message: as written when it is moderate, else in scientific notation with
/// four significant digits (never 200 digits of `1e200`).
fn num(x: f64) -> String {
    if !x.is_finite() || x == 0.0 || (x.abs() >= 1e-4 && x.abs() < 1e15) {
        format!("{x}")
    } else {
        wireflight_data::format::fmt_number(x)
    }
}

fn check_finite(x: &State, t: f64) -> Result<(), SimulateError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(SimulateError::Diverged(t))
    }
}

/// Collects the true channels sample by sample.
struct Recorder {
    kind: VehicleKind,
    time: Vec<f64>,
    pos: Vec<DVec3>,
    vel_ned: Vec<DVec3>,
    attitude: Vec<EulerZyx>,
    rates: Vec<DVec3>,
    airspeed: Vec<f64>,
    accel: Vec<DVec3>,
    controls: Vec<Controls>,
}

impl Recorder {
    fn with_capacity(n: usize, kind: VehicleKind) -> Self {
        Self {
            kind,
            time: Vec::with_capacity(n),
            pos: Vec::with_capacity(n),
            vel_ned: Vec::with_capacity(n),
            attitude: Vec::with_capacity(n),
            rates: Vec::with_capacity(n),
            airspeed: Vec::with_capacity(n),
            accel: Vec::with_capacity(if kind == VehicleKind::FixedWing { n } else { 0 }),
            controls: Vec::with_capacity(n),
        }
    }

    fn push_point_mass(&mut self, t: f64, x: &State) {
        self.time.push(t);
        self.pos.push(x.pos_ned());
        self.vel_ned.push(x.vel());
    }

    fn push_fixed_wing(&mut self, t: f64, x: &State, airspeed: f64, cmd: Controls, accel: DVec3) {
        self.time.push(t);
        self.pos.push(x.pos_ned());
        self.vel_ned.push(x.rot() * x.vel());
        self.attitude.push(x.attitude());
        self.rates.push(x.omega());
        self.airspeed.push(airspeed);
        self.accel.push(accel);
        self.controls.push(cmd);
    }

    /// Add noise (controls are exact: they are what the aircraft was given) and package.
    /// What the sensors read of the flight (the model's measurement effects,
    /// [`crate::sensing`]), then noise added (controls are exact: they are what the aircraft
    /// was given), packaged.
    fn finish(self, model: &Model, meta: Metadata, spec: &SimSpec) -> FlightData {
        let (noise, accelerometer, seed) = (&spec.noise, spec.accelerometer, spec.seed);
        let acc = accelerometer.unwrap_or(0.0);
        let fixed_wing = self.kind == VehicleKind::FixedWing;
        let mut d = FlightData {
            meta,
            time: self.time,
            pos_ned: self.pos,
            attitude: fixed_wing.then_some(self.attitude),
            vel_ned: Some(self.vel_ned),
            vel_body: None,
            rates_body: fixed_wing.then_some(self.rates),
            airspeed: fixed_wing.then_some(self.airspeed),
            accel_body: (fixed_wing && accelerometer.is_some()).then_some(self.accel),
            controls: fixed_wing.then_some(self.controls),
            derived: Vec::new(),
            sampling: Default::default(),
        };
        crate::sensing::sense(model, &mut d);
        // The wandering errors draw from their own stream: the white noise below is the
        // same with them or without.
        if let Some(errors) = &spec.sensor_errors {
            errors.apply(&mut d, seed);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut gauss = |sigma: f64| -> f64 {
            // `simulate_limited` checked every σ finite and ≥ 0, and `Normal::new` fails for
            // nothing else; 0 stands in all the same.
            if sigma > 0.0 {
                Normal::new(0.0, sigma).map_or(0.0, |d| d.sample(&mut rng))
            } else {
                0.0
            }
        };
        let att = noise.att_deg.to_radians();
        let rate = noise.rate_dps.to_radians();
        for p in &mut d.pos_ned {
            *p += DVec3::new(gauss(noise.pos_m), gauss(noise.pos_m), gauss(noise.pos_m));
        }
        for v in d.vel_ned.iter_mut().flatten() {
            *v += DVec3::new(
                gauss(noise.vel_mps),
                gauss(noise.vel_mps),
                gauss(noise.vel_mps),
            );
        }
        for e in d.attitude.iter_mut().flatten() {
            *e = EulerZyx::new(
                e.yaw + gauss(att),
                e.pitch + gauss(att),
                e.roll + gauss(att),
            );
        }
        for w in d.rates_body.iter_mut().flatten() {
            *w += DVec3::new(gauss(rate), gauss(rate), gauss(rate));
        }
        for a in d.airspeed.iter_mut().flatten() {
            *a += gauss(noise.vel_mps);
        }
        // Last, so that adding the accelerometer changed no other channel's noise.
        for a in d.accel_body.iter_mut().flatten() {
            *a += DVec3::new(gauss(acc), gauss(acc), gauss(acc));
        }
        d
    }
}
