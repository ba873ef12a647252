//! Wandering ("coloured") sensor errors for simulated flights: what a navigation filter and
//! its instruments add to a real autopilot log beyond white noise.
//!
//! A real log does not hold raw sensor readings with independent noise: its position,
//! velocity and attitude come out of a navigation filter (an EKF) whose errors wander slowly,
//! whose gyro biases drift, and whose position is corrected in steps each time a GNSS fix
//! arrives. `wireflight simulate --sensor-errors FILE.toml|PRESET` adds such errors to every
//! sample of the recorded channels ([`SensorErrors::apply`]) and then thins each channel to its
//! own rate ([`SensorErrors::rates`]). Only what *wanders* is here: a constant gyro bias, a
//! misalignment or a late navigation solution are the model's measurement effects
//! ([`crate::sensing`]), and white noise is the simulation's own `Noise`.
//!
//! The errors come from their own ChaCha8 streams of the flight's seed (one stream per axis,
//! none of them the stream the white noise uses), so adding them changes no other noise of the
//! flight, and changing one axis's parameters changes no other axis's errors. The same spec and
//! seed give the same errors, bit for bit.
//!
//! # The building block: one axis
//! Every error axis ([`AxisError`]) is the sum of three parts, each optional (0 = absent):
//!
//! * a first-order **Gauss–Markov** process of stationary standard deviation `size` and time
//!   constant `tau_s`, discretised exactly, x_{k+1} = φ·x_k + size·√(1 − φ²)·n_k with
//!   φ = exp(−Δt/τ), and started from its stationary distribution (so its statistics hold from
//!   the first sample at any step size);
//! * **white** noise of standard deviation `white`, drawn per sample;
//! * a **random walk** (an unbounded bias drift) b_{k+1} = b_k + walk·√Δt·n_k, starting at 0;
//!   `walk` is in the axis's unit per √s.
//!
//! # Models
//! ## `independent`
//! Each axis of each channel has its own, independent error. Attitude errors are small changes
//! of the aircraft's own angles (yaw + δψ, pitch + δθ, roll + δφ); rate and accelerometer
//! errors are in body axes.
//!
//! ```toml
//! model = "independent"
//!
//! [position]                # m, NED
//! rate_hz = 10              # optional: the channel's sampling rate (absent: every sample)
//! north = { size = 0.5, tau_s = 30.0, white = 0.05 }
//! east  = { size = 0.5, tau_s = 30.0, white = 0.05 }
//! down  = { size = 1.0, tau_s = 60.0, white = 0.1 }
//!
//! [velocity]                # m/s, NED
//! north = { size = 0.05, tau_s = 5.0 }
//!
//! [attitude]                # degrees
//! roll  = { size = 0.2, tau_s = 5.0 }
//! yaw   = { size = 0.5, tau_s = 30.0 }
//!
//! [rates]                   # degrees/s, body p, q, r
//! p = { size = 0.02, tau_s = 60.0, white = 0.05 }
//!
//! [airspeed]                # m/s; one axis, so its fields are the table's own
//! size = 0.3
//! tau_s = 10.0
//!
//! [accel]                   # m/s², body x, y, z
//! z = { size = 0.02, tau_s = 60.0, walk = 0.001 }
//! ```
//!
//! Every table, axis and field is optional; an absent one is 0 (no error). `tau_s` is needed
//! exactly when `size > 0` (a time constant is never guessed).
//!
//! ## `ekf-gnss`
//! What a navigation filter fusing an IMU with GNSS positions (and a heading aid such as a
//! magnetometer) outputs: errors that are kinematically consistent with the IMU it fused.
//! It is an error-state simulation at the flight's sample interval Δt:
//!
//! * **IMU errors**, body axes, the same specification on each axis: gyro
//!   δω = white + Gauss–Markov (bias instability) + walk, accelerometer δf likewise. These same
//!   draws are the errors added to the logged `rates_body` and `accel_body`: the log holds
//!   the IMU the filter fused.
//! * **Navigation error** in NED: position δp, velocity δv, attitude ψ (a small rotation
//!   vector: the logged attitude is R_meas = Exp(ψ)·R, R the true body→NED matrix). Between
//!   fixes it is propagated with Euler steps at Δt, the values of sample k giving sample k+1:
//!
//!   δp ← δp + δv·Δt,  δv ← δv + (ψ × f_n + R·δf)·Δt,  ψ ← ψ + R·δω·Δt,
//!
//!   where f_n = R·f_b is the true specific force in NED (from the flight's `accel_body` and
//!   attitude; (0, 0, −g₀) when the flight has no accelerometer, R = I when it has no
//!   attitude). The sign of the ψ equation follows from the definition of ψ: integrating the
//!   measured rates ω + δω gives R_meas = Exp(ψ)·R with ψ̇ = +R·δω (the textbook
//!   ψ̇ = −R·δω belongs to the opposite sign convention, R_meas = Exp(−ψ)·R); rotating the
//!   measured specific force with R_meas gives the ψ × f_n term.
//! * **GNSS**: the reading of the position is in error by e = white + Gauss–Markov (+ walk),
//!   horizontal and vertical specified separately, read at `gnss.rate_hz` (epochs at
//!   t₀ + j/rate). A **heading aid** reads ψ_D (the heading error) in error by its own
//!   white + Gauss–Markov process at the same epochs. At each epoch the filter corrects
//!   x ← x − K·(H·x − z), x = (δp, δv, ψ), H·x = (δp, ψ_D), z = (e, e_heading): the output
//!   follows the GNSS error, smoothed, and steps at every fix (a sawtooth at the sample
//!   rate).
//! * **The gain** K is the steady-state Kalman gain of the 9-state model of the same
//!   propagation with a constant nominal f_n = (0, 0, −g₀), computed once: the discrete
//!   Riccati equation over one GNSS interval (m = round(1/(rate·Δt)) Euler steps,
//!   P ← Φ·P·Φᵀ + Q, then the update) is iterated until K converges. Its process noise treats
//!   each IMU error as white: per step a white part adds (white·Δt)² and a Gauss–Markov part
//!   adds its low-frequency density 2·size²·τ·Δt (the filter has no bias states, as a simple
//!   EKF might not: a bias shows as a slow tilt and position error); the measurement noise is
//!   size² + white² of each GNSS axis and of the heading aid. (A walk is left out of the gain;
//!   variances have a small floor so that an all-zero spec still gives a finite gain.)
//! * **Start**: the Gauss–Markov parts start stationary; the navigation error starts from a
//!   closed-loop warm-up before the first sample (long enough for the closed loop, over one
//!   GNSS interval, to shrink any start to a thousandth; at most 200 000 steps), flown with
//!   the first sample's attitude and specific force, so that the flight starts in steady
//!   state and the first sample is a fix.
//! * **Airspeed** has its own error (white + Gauss–Markov + walk), not part of the filter.
//!
//! ```toml
//! model = "ekf-gnss"
//!
//! [gnss]                    # m; fixes at rate_hz (required)
//! rate_hz = 5
//! horizontal = { size = 0.5, tau_s = 30.0, white = 0.2 }
//! vertical   = { size = 1.0, tau_s = 30.0, white = 0.4 }
//!
//! [heading]                 # the heading aid's error, degrees, read at the GNSS rate
//! size = 0.5
//! tau_s = 30.0
//!
//! [gyro]                    # degrees/s, each body axis; rate_hz: the logged rates' rate
//! size = 0.01
//! tau_s = 60.0
//! white = 0.05
//!
//! [accel]                   # m/s², each body axis; rate_hz: the logged accelerometer's
//! size = 0.01
//! tau_s = 60.0
//! white = 0.02
//!
//! [airspeed]                # m/s
//! size = 0.3
//! tau_s = 10.0
//!
//! [position]                # the filter outputs' sampling rates, all optional
//! rate_hz = 50
//! # [velocity] rate_hz, [attitude] rate_hz likewise
//! ```
//!
//! Only `gnss.rate_hz` is required; every other field is 0 when absent (and `tau_s` is needed
//! when `size > 0`). The white part of the IMU is per sample at the flight's Δt (as logged):
//! its integrated effect, the angle or velocity random walk, is white·√Δt per √s.
//!
//! # Presets
//! [`PRESETS`], by model name; numbers are what a good small-UAV EKF output has.
//!
//! `independent` (G–M: size, τ; white; no walks):
//!
//! | channel  | axes          | G–M size   | τ, s | white    | rate   |
//! |----------|---------------|------------|------|----------|--------|
//! | position | north, east   | 0.5 m      | 30   | 0.05 m   | 10 Hz  |
//! | position | down          | 1.0 m      | 60   | 0.1 m    | 10 Hz  |
//! | velocity | north, east, down | 0.05 m/s | 5 | –        | every  |
//! | attitude | roll, pitch   | 0.2°       | 5    | –        | every  |
//! | attitude | yaw           | 0.5°       | 30   | –        | every  |
//! | rates    | p, q, r       | 0.02 °/s   | 60   | 0.05 °/s | every  |
//! | airspeed |               | 0.3 m/s    | 10   | –        | every  |
//! | accel    | x, y, z       | 0.02 m/s²  | 60   | –        | every  |
//!
//! `ekf-gnss` (every channel at every sample):
//!
//! | part             | G–M size   | τ, s | white    |
//! |------------------|------------|------|----------|
//! | GNSS, 5 Hz, horizontal | 0.5 m | 30 | 0.2 m    |
//! | GNSS vertical    | 1.0 m      | 30   | 0.4 m    |
//! | heading aid      | 0.5°       | 30   | –        |
//! | gyro (each axis) | 0.01 °/s   | 60   | 0.05 °/s |
//! | accel (each axis)| 0.01 m/s²  | 60   | 0.02 m/s²|
//! | airspeed         | 0.3 m/s    | 10   | –        |
//!
//! With it a flight's errors are (measured over 40 000 s of level flight at 10 Hz, 20 seeds,
//! standard deviations): position 0.50–0.53 m horizontal and 0.99–1.05 m vertical (the GNSS
//! error, smoothed: its Gauss–Markov part passes, its white part is mostly filtered out),
//! velocity about 0.1 m/s (the filter follows the GNSS error's wander), tilt about 0.12°,
//! heading about 0.48°.
//!
//! The gain is designed for f_n ≈ (0, 0, −g₀), which any flight has on average (an inverted
//! aircraft's accelerometer reads +g₀ down its own z axis, which is −g₀ in NED). Data whose
//! specific force stays far from it for long (an accelerometer inconsistent with the
//! attitude) can make the fixed-gain loop diverge: such errors grow, nothing panics.
//!
//! # Numbers
//! Every number must be finite. Sizes, `white` and `walk` are ≥ 0 and at most 10⁶ (in the
//! field's unit); `tau_s` is > 0 and at most 10⁹ s; every rate is > 0 and at most
//! [`MAX_RATE_HZ`]. Unknown keys are errors (a typo must not become a silent 0), and every
//! error names the file and the field's path (`position.north.tau_s`).
//!
//! # The truth record
//! [`SensorErrors::to_record`] writes one line for the flight file's metadata
//! (`# sensor_errors: …`, key [`TRUTH_KEY`]): `model=NAME seed=N` then `path=value` for every
//! field that is not 0 (or absent), paths as in the TOML file, numbers in their shortest
//! round-trip form, e.g.
//! `model=ekf-gnss seed=3 gnss.rate_hz=5 gnss.horizontal.size=0.5 gnss.horizontal.tau_s=30 …`.
//! [`SensorErrors::from_record`] reads it back, checking it as a file is checked.
//!
//! # Layout
//! This file holds the types and the API; `sensor_errors/spec.rs` the TOML, the record and
//! the presets; `process.rs` the one-axis generator; `independent.rs` and `ekf_gnss.rs` the
//! two models; `tests.rs` the tests.

use std::path::{Path, PathBuf};

use glam::DVec3;

use wireflight_data::FlightData;
use wireflight_geometry::euler::EulerZyx;

mod ekf_gnss;
mod independent;
mod process;
mod spec;
#[cfg(test)]
mod tests;

/// Key of the truth record in a flight file's metadata ([`SensorErrors::to_record`]).
pub const TRUTH_KEY: &str = "sensor_errors";

/// The presets' names (each is also the name of its model).
pub const PRESETS: [&str; 2] = ["independent", "ekf-gnss"];

/// Highest sampling rate (a channel's or the GNSS's), Hz.
pub const MAX_RATE_HZ: f64 = 10_000.0;

/// Largest `size`, `white` or `walk`, in the field's unit.
pub const MAX_SIZE: f64 = 1e6;

/// Largest `tau_s`, s.
pub const MAX_TAU_S: f64 = 1e9;

/// The error of one axis: Gauss–Markov + white + random walk (module documentation), in the
/// unit of the axis as written in the file (degrees for angles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisError {
    /// Stationary standard deviation of the Gauss–Markov part.
    pub size: f64,
    /// Time constant of the Gauss–Markov part, s; needed when `size > 0`.
    pub tau_s: Option<f64>,
    /// Standard deviation of the white part, per sample.
    pub white: f64,
    /// Random-walk rate, the axis's unit per √s.
    pub walk: f64,
}

impl AxisError {
    /// A Gauss–Markov error of `size` and time constant `tau_s`, with `white` noise.
    pub const fn gm(size: f64, tau_s: f64, white: f64) -> Self {
        Self {
            size,
            tau_s: Some(tau_s),
            white,
            walk: 0.0,
        }
    }

    /// No error.
    pub const ZERO: Self = Self {
        size: 0.0,
        tau_s: None,
        white: 0.0,
        walk: 0.0,
    };
}

/// The sampling rate of each recorded channel, Hz; `None`: every sample of the flight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelRates {
    /// Position.
    pub position: Option<f64>,
    /// NED velocity.
    pub velocity: Option<f64>,
    /// Attitude.
    pub attitude: Option<f64>,
    /// Body rates.
    pub rates: Option<f64>,
    /// Airspeed.
    pub airspeed: Option<f64>,
    /// Accelerometer.
    pub accel: Option<f64>,
}

/// The `independent` model: an independent error on each axis of each channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Independent {
    /// Position north, east, down, m.
    pub position: [AxisError; 3],
    /// NED velocity north, east, down, m/s.
    pub velocity: [AxisError; 3],
    /// Attitude roll, pitch, yaw, degrees (changes of the aircraft's own angles).
    pub attitude: [AxisError; 3],
    /// Body rates p, q, r, degrees/s.
    pub rates: [AxisError; 3],
    /// Airspeed, m/s.
    pub airspeed: AxisError,
    /// Accelerometer, body x, y, z, m/s².
    pub accel: [AxisError; 3],
    /// Each channel's sampling rate (`rate_hz` of its table).
    pub rates_hz: ChannelRates,
}

/// The `ekf-gnss` model: a navigation filter fusing an IMU with GNSS positions and a heading
/// aid (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EkfGnss {
    /// GNSS fixes (and heading-aid readings) per second.
    pub gnss_rate_hz: f64,
    /// GNSS position error north and east, each, m.
    pub gnss_horizontal: AxisError,
    /// GNSS position error down, m.
    pub gnss_vertical: AxisError,
    /// The heading aid's error, degrees.
    pub heading: AxisError,
    /// Gyro error, each body axis, degrees/s.
    pub gyro: AxisError,
    /// Accelerometer error, each body axis, m/s².
    pub accel: AxisError,
    /// Airspeed error, m/s.
    pub airspeed: AxisError,
    /// Each channel's sampling rate (`rate_hz` of its table; `gyro.rate_hz` is the rates').
    pub rates_hz: ChannelRates,
}

/// A model with its parameters.
// One spec is made per flight: plain `Copy` data matters more than the 400 bytes the smaller
// variant leaves unused.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Model {
    /// `model = "independent"`.
    Independent(Independent),
    /// `model = "ekf-gnss"`.
    EkfGnss(EkfGnss),
}

/// Wandering sensor errors to add to a flight: a model and its parameters, from a TOML file, a
/// preset or a truth record.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorErrors {
    /// The model.
    pub model: Model,
}

/// The errors [`SensorErrors::apply`] made, one entry per sample of the flight, for every
/// channel whether or not the flight has it (a channel it lacks was not changed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SensorErrorTrace {
    /// Position error, NED, m.
    pub pos: Vec<DVec3>,
    /// NED velocity error, m/s.
    pub vel: Vec<DVec3>,
    /// Attitude error as a rotation vector in NED, rad: logged R = Exp(tilt)·true R.
    pub tilt: Vec<DVec3>,
    /// Body-rate error (p, q, r), rad/s.
    pub rates: Vec<DVec3>,
    /// Airspeed error, m/s.
    pub airspeed: Vec<f64>,
    /// Accelerometer error, body axes, m/s².
    pub accel: Vec<DVec3>,
}

/// What is wrong with one field of a sensor-error file or record.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FieldProblem {
    /// A key the model does not have.
    #[error("unknown key (expected one of: {expected})")]
    Unknown {
        /// The keys allowed at that place.
        expected: String,
    },
    /// A required field that is absent.
    #[error("missing (required)")]
    Missing,
    /// A field given twice (in a record).
    #[error("given twice")]
    Duplicate,
    /// A value of the wrong type.
    #[error("must be {expected}, not {found}")]
    WrongType {
        /// What it must be.
        expected: &'static str,
        /// What it is.
        found: String,
    },
    /// NaN or infinite.
    #[error("not a finite number: {0}")]
    NotFinite(f64),
    /// Outside the field's range.
    #[error("{value} is out of range: {range}")]
    OutOfRange {
        /// The value.
        value: f64,
        /// The range, with its unit.
        range: &'static str,
    },
    /// `size > 0` without a time constant.
    #[error("needed when size > 0 (the Gauss-Markov time constant, s)")]
    TauNeeded,
    /// A `model` that is not one of [`PRESETS`].
    #[error("unknown model `{0}` (models: independent, ekf-gnss)")]
    UnknownModel(String),
}

/// A sensor-error file, preset name or record that cannot be used. Every message names the
/// file (or the record) and, where one is involved, the field's path.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SensorErrorsError {
    /// The file could not be read (the OS error is the source).
    #[error("{}: cannot read the sensor-error file", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The text is not TOML.
    #[error("{file}: not TOML: {message}")]
    Toml {
        /// The file.
        file: String,
        /// The TOML parser's message (with the line and column).
        message: String,
    },
    /// A field that is unknown, missing, of the wrong type or out of range.
    #[error("{file}: `{field}`: {problem}")]
    Field {
        /// The file (or `metadata sensor_errors` for a record).
        file: String,
        /// The field's path, e.g. `position.north.tau_s`.
        field: String,
        /// What is wrong.
        problem: FieldProblem,
    },
    /// An argument that is neither a file nor a preset.
    #[error(
        "`{0}` is neither a sensor-error file (.toml) nor a preset (presets: independent, \
         ekf-gnss)"
    )]
    Unknown(String),
}

impl SensorErrors {
    /// The preset `name` (one of [`PRESETS`]); `None` for any other name.
    pub fn preset(name: &str) -> Option<Self> {
        spec::preset(name).map(|model| Self { model })
    }

    /// A `--sensor-errors` argument: a TOML file (a name ending in `.toml` or holding a `/`,
    /// or an existing file that is not a preset's name) or a preset name.
    ///
    /// # Errors
    /// The file's errors ([`load`](Self::load)), or [`SensorErrorsError::Unknown`] (listing the
    /// presets) for a name that is neither.
    pub fn from_arg(arg: &str) -> Result<Self, SensorErrorsError> {
        let path = Path::new(arg);
        let looks_like_file = arg.ends_with(".toml") || arg.contains('/');
        if looks_like_file {
            return Self::load(path);
        }
        if let Some(p) = Self::preset(arg.trim()) {
            return Ok(p);
        }
        if path.is_file() {
            return Self::load(path);
        }
        Err(SensorErrorsError::Unknown(arg.to_string()))
    }

    /// Read a sensor-error TOML file (through [`wireflight_fsio::read_text`]: a regular file
    /// within the input size limit).
    ///
    /// # Errors
    /// The file cannot be read, or its text is refused ([`parse`](Self::parse)).
    pub fn load(path: &Path) -> Result<Self, SensorErrorsError> {
        let text = wireflight_fsio::read_config_text(path).map_err(|source| {
            SensorErrorsError::Unreadable {
                path: path.to_path_buf(),
                source,
            }
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Read a sensor-error TOML text; `file` names it in errors.
    ///
    /// # Errors
    /// Not TOML, no or an unknown `model`, an unknown key, a value of the wrong type, a number
    /// that is not finite or out of range, a missing required field.
    pub fn parse(text: &str, file: &str) -> Result<Self, SensorErrorsError> {
        spec::parse_toml(text, file).map(|model| Self { model })
    }

    /// The model's name (`independent` or `ekf-gnss`).
    pub fn name(&self) -> &'static str {
        match self.model {
            Model::Independent(_) => PRESETS[0],
            Model::EkfGnss(_) => PRESETS[1],
        }
    }

    /// Each channel's sampling rate.
    pub fn rates(&self) -> ChannelRates {
        match &self.model {
            Model::Independent(m) => m.rates_hz,
            Model::EkfGnss(m) => m.rates_hz,
        }
    }

    /// The truth record for the flight file's metadata (module documentation): the model and
    /// every parameter, and the seed.
    pub fn to_record(&self, seed: u64) -> String {
        spec::to_record(&self.model, seed)
    }

    /// Read a [`to_record`](Self::to_record) line back: the errors and the seed.
    ///
    /// # Errors
    /// As [`parse`](Self::parse), the record standing for the file; a missing or bad `seed`.
    pub fn from_record(record: &str) -> Result<(Self, u64), SensorErrorsError> {
        spec::from_record(record).map(|(model, seed)| (Self { model }, seed))
    }

    /// Add the errors to every sample of the channels `d` has (deterministic for the seed,
    /// from the errors' own random streams) and return them. Channels are only added to;
    /// samples of a channel beyond the length of `time` are left as they are, and non-finite
    /// times or channel values make no panic (a non-finite step counts as 0 s, a non-finite
    /// attitude or specific force as level flight).
    pub fn apply(&self, d: &mut FlightData, seed: u64) -> SensorErrorTrace {
        match &self.model {
            Model::Independent(m) => {
                let (trace, angles) = independent::errors(m, d, seed);
                add_trace(d, &trace, Some(&angles));
                trace
            }
            Model::EkfGnss(m) => {
                let trace = ekf_gnss::errors(m, d, seed);
                add_trace(d, &trace, None);
                trace
            }
        }
    }
}

/// Add `trace` to the channels of `d`. The attitude is changed by `angles` (roll, pitch, yaw
/// added to the aircraft's own angles, rad) where given, else rotated by the trace's tilt.
fn add_trace(d: &mut FlightData, trace: &SensorErrorTrace, angles: Option<&[DVec3]>) {
    for (p, e) in d.pos_ned.iter_mut().zip(&trace.pos) {
        *p += *e;
    }
    for (v, e) in d.vel_ned.iter_mut().flatten().zip(&trace.vel) {
        *v += *e;
    }
    match angles {
        Some(angles) => {
            for (a, e) in d.attitude.iter_mut().flatten().zip(angles) {
                *a = EulerZyx::new(a.yaw + e.z, a.pitch + e.y, a.roll + e.x);
            }
        }
        None => {
            for (a, e) in d.attitude.iter_mut().flatten().zip(&trace.tilt) {
                *a = process::rotate_attitude(*a, *e);
            }
        }
    }
    for (w, e) in d.rates_body.iter_mut().flatten().zip(&trace.rates) {
        *w += *e;
    }
    for (s, e) in d.airspeed.iter_mut().flatten().zip(&trace.airspeed) {
        *s += *e;
    }
    for (f, e) in d.accel_body.iter_mut().flatten().zip(&trace.accel) {
        *f += *e;
    }
}
