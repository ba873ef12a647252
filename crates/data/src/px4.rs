//! PX4 flight logs as [`FlightData`]: the topics a flight needs, taken out of a ULog file
//! ([`super::ulog`]), cleaned, each kept at its own samples' times.
//!
//! | channel | topic and fields | between its samples |
//! |---|---|---|
//! | position | `vehicle_local_position` `x, y, z` (NED about `ref_lat, ref_lon, ref_alt`); without it `vehicle_global_position` `lat, lon, alt`, then `vehicle_gps_position` (`lat, lon, alt` in 1e-7°, mm, or `latitude_deg, longitude_deg, altitude_msl_m`), made local NED about the first sample on a flat earth | linear |
//! | NED velocity | `vehicle_local_position` `vx, vy, vz` | linear |
//! | attitude | `vehicle_attitude` `q[0..4]` (w, x, y, z; FRD body → NED) → z-y-x angles | slerp |
//! | body rates | `vehicle_angular_velocity` `xyz[0..3]`; older logs `vehicle_attitude` `rollspeed, pitchspeed, yawspeed` | linear |
//! | airspeed | `airspeed` `true_airspeed_m_s`, else `airspeed_validated` | linear |
//! | accelerometer | `sensor_combined` `accelerometer_m_s2[0..3]` (the sensor's specific force, FRD), else `vehicle_acceleration` `xyz[0..3]` (the estimator's, bias-corrected) | linear |
//! | controls | `actuator_controls_0` `control[0..4]` (roll, pitch, yaw, throttle), else `vehicle_torque_setpoint` `xyz` with `vehicle_thrust_setpoint` `xyz[0]` | held (zero-order) |
//!
//! PX4's normalised commands (−1..1) become surface deflections of ±[`UlogOptions::surface_max_deg`]
//! in Beard & McLain's signs: aileron = +roll, elevator = −pitch (PX4's positive pitch is nose
//! up, a positive elevator pitches nose down), rudder = −yaw. `actuator_outputs` (PWM per
//! output) are reported but not used: which output drives which surface is in the mixer, not
//! the log.
//!
//! The flight runs over the span where position and attitude both have samples. Each
//! measured channel keeps its own samples there, at most [`UlogOptions::rate_hz`] of them a
//! second — by default a round rate ([`nice_rate`]) not above the faster of the position's
//! and the attitude's median rates (at most [`DEFAULT_MAX_RATE_HZ`]); a faster topic is
//! thinned to samples it has, never interpolated. The flight's rows are the union of those
//! times, and each row says which channels it is a sample of ([`crate::Sampling`]); between
//! its samples a channel is filled in as the table says. Time 0 is the first row, whose ULog
//! time stamp is kept in the metadata as `ulog_time_zero_us`. A channel other than position
//! and attitude is used when it covers at least [`MIN_COVERAGE`] of that span (held at its
//! ends); otherwise it is left out and the report says so. Samples with a zero time stamp or non-finite values are dropped; samples out of time
//! order are sorted and noted (more than 1 % of a topic's is an error: not a time series),
//! repeated time stamps keep the last; a time stamp more than 1e9 s from the log's start is an
//! error. Values are held to the CSV reader's ranges (positions ±1e8 m, velocities ±1e5 m/s,
//! rates ±1e4 rad/s, accelerations ±50 g, latitude, longitude, altitude, surfaces ±90°), derived channels too, the
//! error naming the topic, field and time stamp. Attitude is used only when at least half its
//! quaternions are near unit length (the report says how many are). The span may hold at
//! most [`MAX_SAMPLES_PER_SAMPLE`] intervals of the rate per position and attitude sample of
//! the log (at least [`MIN_SAMPLES_BOUND`]): a time stamp moved far from the others is
//! refused, not bridged by a straight line over hours. The origin (latitude, longitude,
//! altitude) comes from the local position's reference when it is global, else from the first
//! global sample. `MAV_TYPE` 1 (fixed wing) with attitude and controls makes the data
//! `vehicle: fixed-wing`; other vehicle types leave the vehicle to `--vehicle`.

use std::path::Path;

use glam::{DMat3, DQuat, DVec3};

use super::columns::Quantity;
use super::read::flat_earth_ned;
use super::report::{rate_text, ImportReport};
use super::ulog::{UlogError, UlogErrorKind, UlogFile};
use super::{FlightData, Metadata};
use crate::{Channel, Controls, VehicleKind};
use wireflight_geometry::euler::EulerZyx;

mod series;
use series::{slerp, Series};

/// The format's name in reports.
pub const FORMAT: &str = "PX4 ULog";

/// Highest default rate of the time base, Hz (a log's 100–250 Hz estimates are resampled to
/// this unless [`UlogOptions::rate_hz`] says otherwise).
pub const DEFAULT_MAX_RATE_HZ: f64 = 50.0;

/// Most samples of the time base.
pub const MAX_SAMPLES: usize = 10_000_000;

/// Most samples of the time base for each position and attitude sample the log holds: a
/// flight resampled far beyond its samples is a time stamp out of place, not a flight.
pub const MAX_SAMPLES_PER_SAMPLE: usize = 100;

/// The bound of [`MAX_SAMPLES_PER_SAMPLE`] is never below this (a short log at a chosen rate).
pub const MIN_SAMPLES_BOUND: usize = 10_000;

/// Least fraction of the time base's span a channel must cover to be used.
pub const MIN_COVERAGE: f64 = 0.9;

/// A gap in a topic longer than this is reported, s.
pub const GAP_NOTE_S: f64 = 1.0;

/// The topics read (others are only counted).
pub const TOPICS: [&str; 13] = [
    "vehicle_local_position",
    "vehicle_global_position",
    "vehicle_gps_position",
    "vehicle_attitude",
    "vehicle_angular_velocity",
    "airspeed",
    "airspeed_validated",
    "sensor_combined",
    "vehicle_acceleration",
    "actuator_controls_0",
    "vehicle_torque_setpoint",
    "vehicle_thrust_setpoint",
    "actuator_outputs",
];

/// Settings of the ULog reader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UlogOptions {
    /// Rate of the time base, Hz (default: [`nice_rate`] of the faster of the position's and
    /// the attitude's median rates).
    pub rate_hz: Option<f64>,
    /// Surface deflection of a full (±1) PX4 command, degrees.
    pub surface_max_deg: f64,
}

impl Default for UlogOptions {
    fn default() -> Self {
        Self {
            rate_hz: None,
            surface_max_deg: 25.0,
        }
    }
}

/// Reads a PX4 ULog file as flight data (derived channels filled in) and says what was found.
///
/// # Errors
/// [`UlogError`] naming the file and the byte, topic or field: an unreadable or malformed
/// file, no position topic, a topic without the fields it needs, too short a flight.
pub fn read(path: &Path, options: &UlogOptions) -> Result<(FlightData, ImportReport), UlogError> {
    let log = UlogFile::read(path, |t| TOPICS.contains(&t))?;
    from_ulog(&log, &path.display().to_string(), options)
}

/// [`read`] for a file already parsed; `file` names it in errors and in the report.
///
/// # Errors
/// As [`read`], less the reading.
pub fn from_ulog(
    log: &UlogFile,
    file: &str,
    options: &UlogOptions,
) -> Result<(FlightData, ImportReport), UlogError> {
    let mut report = ImportReport::new(file, FORMAT);
    about(log, &mut report);
    let err = |kind| UlogError::file(file, kind);
    if let Some(r) = options.rate_hz {
        if !(r.is_finite() && r > 0.0 && r <= 10_000.0) {
            return Err(err(UlogErrorKind::BadValues(format!(
                "resampling rate {r} Hz is outside (0, 10000]"
            ))));
        }
    }
    let t_ref = log.start_us;
    let get = |topic: &str, fields: &[&str]| Series::of(log, file, topic, fields, t_ref);

    // Position: the estimator's local frame, else global positions made local.
    let (pos, origin) = position(log, file, &get, &mut report)?;
    let attitude = match get("vehicle_attitude", &["q[0]", "q[1]", "q[2]", "q[3]"])? {
        Some(a) => unit_quaternions(a),
        None => Err((0, 0)),
    };
    // The time base: where position and attitude both are.
    let (mut t0, mut t1) = pos.span();
    if let Ok(a) = &attitude {
        let (a0, a1) = (a.t[0], a.t[a.t.len() - 1]);
        t0 = t0.max(a0);
        t1 = t1.min(a1);
    }
    let rate = options.rate_hz.unwrap_or_else(|| {
        let own = [pos.rate(), attitude.as_ref().ok().and_then(|a| a.rate)];
        nice_rate(own.into_iter().flatten().fold(1.0, f64::max))
    });
    let n = if t1 > t0 {
        ((t1 - t0) * rate + 1e-9).floor() + 1.0
    } else {
        0.0
    };
    let spans = || {
        let (p0, p1) = pos.span();
        let att = match &attitude {
            Ok(a) => format!("attitude {:.3}–{:.3} s", a.t[0], a.t[a.t.len() - 1]),
            Err(_) => "no attitude".into(),
        };
        format!("position {p0:.3}–{p1:.3} s ({} samples), {att}", pos.len())
    };
    if n < 2.0 {
        return Err(err(UlogErrorKind::Missing(format!(
            "too short: position and attitude overlap for {:.3} s ({}): fewer than two \
             samples at {}",
            (t1 - t0).max(0.0),
            spans(),
            rate_text(rate)
        ))));
    }
    // The flight may not be longer than the log's samples justify: a time stamp moved far
    // from the others would otherwise make millions of interpolated samples out of a few.
    let held = pos.len() + attitude.as_ref().map_or(0, |a| a.t.len());
    let bound = (MAX_SAMPLES_PER_SAMPLE * held).max(MIN_SAMPLES_BOUND);
    if n > bound as f64 {
        let gap = [pos.longest_gap().map(|g| (g, pos.topic.as_str()))]
            .into_iter()
            .chain([attitude
                .as_ref()
                .ok()
                .and_then(|a| a.longest_gap())
                .map(|g| (g, "vehicle_attitude"))])
            .flatten()
            .max_by(|a, b| a.0 .0.total_cmp(&b.0 .0));
        let gap = gap.map_or(String::new(), |((g, at), topic)| {
            format!("; the longest gap: {g:.1} s after {at:.3} s in {topic}")
        });
        return Err(err(UlogErrorKind::BadValues(format!(
            "{:.0} s at {} spans {n:.0} samples, more than {MAX_SAMPLES_PER_SAMPLE} for each \
             of the {held} position and attitude samples the log holds ({bound}): a time stamp \
             far from the others, or too high a rate? ({}{gap})",
            t1 - t0,
            rate_text(rate),
            spans()
        ))));
    }
    if n > MAX_SAMPLES as f64 {
        return Err(err(UlogErrorKind::BadValues(format!(
            "{:.0} s at {} spans {n:.0} samples, more than {MAX_SAMPLES}: choose a lower \
             rate (--resample)",
            t1 - t0,
            rate_text(rate)
        ))));
    }
    // The measured channels' series, fetched before the rows are laid out: the rows are
    // their samples' times.
    let vel = get("vehicle_local_position", &["vx", "vy", "vz"])
        .ok()
        .flatten()
        .filter(|_| pos.topic == "vehicle_local_position");
    let rates = match get("vehicle_angular_velocity", &["xyz[0]", "xyz[1]", "xyz[2]"])? {
        Some(r) => Some((r, "xyz[0..3]")),
        None => get("vehicle_attitude", &["rollspeed", "pitchspeed", "yawspeed"])
            .ok()
            .flatten()
            .map(|r| (r, "rollspeed, pitchspeed, yawspeed")),
    };
    let airspeed = match get("airspeed", &["true_airspeed_m_s"])? {
        Some(a) => Some(a),
        None => get("airspeed_validated", &["true_airspeed_m_s"])?,
    };
    let accel = match get(
        "sensor_combined",
        &[
            "accelerometer_m_s2[0]",
            "accelerometer_m_s2[1]",
            "accelerometer_m_s2[2]",
        ],
    )? {
        Some(a) => Some((a, "accelerometer_m_s2[0..3]")),
        None => {
            get("vehicle_acceleration", &["xyz[0]", "xyz[1]", "xyz[2]"])?.map(|a| (a, "xyz[0..3]"))
        }
    };
    // Each channel keeps its own samples over the span, at most `rate` a second (a faster
    // topic is thinned to samples it has, never interpolated); the rows are their union.
    let within = (t0, t1);
    let own = |t: &[f64]| own_times(t, within, rate);
    let covered = |s: &Series| covers(s, within);
    let kept = OwnTimes {
        position: own(&pos.t),
        velocity: vel
            .as_ref()
            .filter(|v| covered(v))
            .map_or_else(Vec::new, |v| own(&v.t)),
        attitude: attitude.as_ref().map_or_else(|_| Vec::new(), |a| own(&a.t)),
        rates: rates
            .as_ref()
            .filter(|r| covered(&r.0))
            .map_or_else(Vec::new, |r| own(&r.0.t)),
        airspeed: airspeed
            .as_ref()
            .filter(|a| covered(a))
            .map_or_else(Vec::new, |a| own(&a.t)),
        accel: accel
            .as_ref()
            .filter(|a| covered(&a.0))
            .map_or_else(Vec::new, |a| own(&a.0.t)),
    };
    let grid = kept.union();
    if grid.len() < 2 {
        return Err(err(UlogErrorKind::Missing(format!(
            "too short: fewer than two samples where position and attitude overlap ({})",
            spans()
        ))));
    }
    let span = (t0, grid[grid.len() - 1]);

    let pos_ned: Vec<DVec3> = {
        let c = pos.linear(&grid);
        (0..grid.len())
            .map(|k| DVec3::new(c[0][k], c[1][k], c[2][k]))
            .collect()
    };
    let mut data = FlightData::new(Metadata::default(), Vec::new(), pos_ned);
    if let Some((lat, lon, alt)) = origin {
        data.meta.latitude_deg = Some(lat);
        data.meta.longitude_deg = Some(lon);
        data.meta.altitude_m = Some(alt);
    }

    // NED velocity, from the local position when it has it.
    if let Some(v) = vel {
        v.check_all(file, &[Quantity::Vn, Quantity::Ve, Quantity::Vd])?;
        if use_channel(&mut report, "NED velocity", &v, "vx, vy, vz", within, "") {
            let c = v.linear(&grid);
            data.vel_ned = Some(
                (0..grid.len())
                    .map(|k| DVec3::new(c[0][k], c[1][k], c[2][k]))
                    .collect(),
            );
        }
    }

    // Attitude: quaternions, slerped.
    match &attitude {
        Ok(a) => {
            let note = if a.bad > 0 {
                format!(
                    "slerped; {} of {} samples with a quaternion far from unit length dropped",
                    a.bad,
                    a.bad + a.t.len()
                )
            } else {
                "slerped".to_string()
            };
            report.channel(
                "attitude",
                "vehicle_attitude q[0..4]",
                a.t.len(),
                a.rate,
                true,
                note,
            );
            let att = slerp(&a.t, &a.q, &grid)
                .into_iter()
                .map(|q| EulerZyx::from_matrix(DMat3::from_quat(q)).0)
                .collect();
            data.attitude = Some(att);
        }
        Err((0, 0)) => report.channel(
            "attitude",
            "vehicle_attitude",
            0,
            None,
            false,
            "not in the log",
        ),
        Err((good, all)) => report.channel(
            "attitude",
            "vehicle_attitude q[0..4]",
            *good,
            None,
            false,
            format!(
                "{good} of {all} samples valid (the others' quaternions are far from unit \
                 length; at least half must be valid)"
            ),
        ),
    }

    // Body rates.
    match rates {
        Some((r, fields)) => {
            r.check_all(file, &[Quantity::P, Quantity::Q, Quantity::R])?;
            if use_channel(&mut report, "body rates", &r, fields, within, "") {
                let c = r.linear(&grid);
                data.rates_body = Some(
                    (0..grid.len())
                        .map(|k| DVec3::new(c[0][k], c[1][k], c[2][k]))
                        .collect(),
                );
            }
        }
        None => report.channel(
            "body rates",
            "vehicle_angular_velocity",
            0,
            None,
            false,
            "not in the log (derived from attitude)",
        ),
    }

    // Airspeed.
    match airspeed {
        Some(a) => {
            a.check_all(file, &[Quantity::Airspeed])?;
            let lowest = a.cols[0].iter().copied().fold(f64::INFINITY, f64::min);
            let note = if lowest < 0.0 {
                format!("readings down to {lowest:.1} m/s (a sensor offset at rest?)")
            } else {
                String::new()
            };
            if use_channel(
                &mut report,
                "airspeed",
                &a,
                "true_airspeed_m_s",
                within,
                &note,
            ) {
                data.airspeed = Some(a.linear(&grid).swap_remove(0));
            }
        }
        None => report.channel("airspeed", "airspeed", 0, None, false, "not in the log"),
    }

    // Accelerometer: the sensor's, else the estimator's; PX4's body axes are FRD already.
    match accel {
        Some((a, fields)) => {
            a.check_all(file, &[Quantity::Ax, Quantity::Ay, Quantity::Az])?;
            if use_channel(&mut report, "accelerometer", &a, fields, within, "") {
                let c = a.linear(&grid);
                data.accel_body = Some(
                    (0..grid.len())
                        .map(|k| DVec3::new(c[0][k], c[1][k], c[2][k]))
                        .collect(),
                );
            }
        }
        None => report.channel(
            "accelerometer",
            "sensor_combined",
            0,
            None,
            false,
            "not in the log",
        ),
    }

    // Controls.
    controls(file, &get, options, &grid, span, &mut data, &mut report)?;
    if let Some(o) = log.topic("actuator_outputs") {
        report.channel(
            "outputs",
            "actuator_outputs output[..]",
            o.len(),
            Series::of(log, file, "actuator_outputs", &["timestamp"], t_ref)
                .ok()
                .flatten()
                .and_then(|s| s.rate()),
            false,
            "PWM per output; which drives which surface is in the mixer, not the log",
        );
    }

    // The vehicle.
    match log.param("MAV_TYPE").map(|v| v as i64) {
        Some(1) if data.attitude.is_some() && data.controls.is_some() => {
            data.meta.vehicle = Some(VehicleKind::FixedWing);
        }
        Some(1) => report.note(
            "a fixed wing, but without attitude and controls the fixed-wing model cannot be run \
             (--vehicle point-mass compares against a point mass)",
        ),
        Some(t) => report.note(format!(
            "MAV_TYPE {t} ({}): no model family of wireflight is this vehicle; give --vehicle \
             (point-mass: a ballistic body, fixed-wing: needs controls) to compare",
            mav_type_name(t)
        )),
        None => {}
    }

    // File-level notes.
    if let Some(at) = log.truncated_at {
        report.note(format!(
            "the file is cut short at byte {at} (the last message is incomplete); what came \
             before it is used"
        ));
    }
    if let Some(at) = log.unreadable_from {
        report.note(format!(
            "unreadable bytes from byte {at} with no sync marker after them; the rest is ignored"
        ));
    }
    if log.corrupt_messages > 0 {
        report.note(format!("{} corrupt messages skipped", log.corrupt_messages));
    }
    if log.dropouts > 0 {
        report.note(format!(
            "{} logger dropouts, {} ms in all",
            log.dropouts, log.dropout_ms
        ));
    }
    if log.appended {
        report.note("data appended after a crash were read");
    }

    kept.mark(&grid, &mut data);
    data.time = grid.iter().map(|t| t - t0).collect();
    let zero_us = t_ref as f64 + t0 * 1e6;
    data.meta.source = Some(format!(
        "PX4 ULog {}",
        Path::new(file)
            .file_name()
            .map_or(file.to_string(), |n| n.to_string_lossy().into_owned())
    ));
    data.meta
        .other
        .push(("ulog_time_zero_us".into(), format!("{zero_us:.0}")));
    data.derive_missing();
    if let Err(why) = data.validate() {
        return Err(err(UlogErrorKind::BadValues(why.to_string())));
    }
    // What the CSV reader would refuse is refused here, naming the channel and time, not
    // when `import --out` writes it (derived channels: a jump of the positions is a speed).
    derived_in_range(&data, zero_us).map_err(|why| err(UlogErrorKind::BadValues(why)))?;
    report.samples = data.len();
    report.sampled = super::report::sampled_channels(&data);
    report.rate_hz = data.sampling.is_all().then_some(rate);
    report.duration_s = data.duration();
    Ok((data, report))
}

/// The times of a topic's samples kept as the flight's samples: those within `(t0, t1)`, at
/// most `rate` a second — of a faster topic, the first sample at or after each tick of a
/// clock at `rate` from `t0` (so 50 Hz thinned to 20 Hz keeps 20 samples a second, not every
/// third), each sample once.
fn own_times(t: &[f64], (t0, t1): (f64, f64), rate: f64) -> Vec<f64> {
    let period = 1.0 / rate;
    let mut kept: Vec<f64> = Vec::new();
    let mut next_tick = t0;
    for &ti in t.iter().filter(|&&ti| ti >= t0 && ti <= t1) {
        // A topic logged at the rate with jitter keeps every sample: a tick is due a tenth
        // of a period early.
        if ti >= next_tick - 0.1 * period {
            kept.push(ti);
            let ticks = ((ti - t0) / period + 0.1).floor() + 1.0;
            next_tick = t0 + ticks * period;
        }
    }
    kept
}

/// Whether `series` covers enough of `span` to be used ([`MIN_COVERAGE`]).
fn covers(series: &Series, span: (f64, f64)) -> bool {
    coverage(series, span) >= MIN_COVERAGE
}

/// The fraction of `span` that `series` covers.
fn coverage(series: &Series, (t0, t1): (f64, f64)) -> f64 {
    let (a, b) = series.span();
    (b.min(t1) - a.max(t0)).max(0.0) / (t1 - t0).max(f64::MIN_POSITIVE)
}

/// The sample times kept of each measured channel (empty: not used).
struct OwnTimes {
    position: Vec<f64>,
    velocity: Vec<f64>,
    attitude: Vec<f64>,
    rates: Vec<f64>,
    airspeed: Vec<f64>,
    accel: Vec<f64>,
}

impl OwnTimes {
    fn each(&self) -> [(Channel, &[f64]); 6] {
        [
            (Channel::Position, &self.position),
            (Channel::Velocity, &self.velocity),
            (Channel::Attitude, &self.attitude),
            (Channel::Rates, &self.rates),
            (Channel::Airspeed, &self.airspeed),
            (Channel::Accelerometer, &self.accel),
        ]
    }

    /// Every kept time, once, in order: the flight's rows.
    fn union(&self) -> Vec<f64> {
        let mut all: Vec<f64> = self
            .each()
            .iter()
            .flat_map(|(_, t)| t.iter().copied())
            .collect();
        all.sort_by(f64::total_cmp);
        all.dedup();
        all
    }

    /// Marks in `data` which rows (`grid`) are samples of each channel it has.
    fn mark(&self, grid: &[f64], data: &mut FlightData) {
        for (channel, times) in self.each() {
            let mut at = times.iter().peekable();
            let sampled: Vec<bool> = grid
                .iter()
                .map(|g| {
                    while at.next_if(|&&t| t < *g).is_some() {}
                    at.next_if(|&&t| t == *g).is_some()
                })
                .collect();
            if sampled.iter().any(|&s| s) {
                data.sampling.set(channel, &sampled);
            }
        }
    }
}

/// Attitude quaternions near unit length (normalised), with their times.
struct Quats {
    t: Vec<f64>,
    q: Vec<DQuat>,
    /// Samples dropped: quaternions far from unit length.
    bad: usize,
    /// Median rate of the valid samples, Hz.
    rate: Option<f64>,
}

impl Quats {
    fn longest_gap(&self) -> Option<(f64, f64)> {
        self.t
            .windows(2)
            .map(|w| (w[1] - w[0], w[0]))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

/// The quaternions of `a` (w, x, y, z) whose length is within 0.5..1.5, normalised. Fewer
/// than two of them, or fewer than half the samples, is `Err((valid, all))`: the attitude is
/// not used (a few valid samples held across a flight would be a made-up attitude).
fn unit_quaternions(a: Series) -> Result<Quats, (usize, usize)> {
    let all = a.len();
    let (t, q): (Vec<f64>, Vec<DQuat>) = (0..all)
        .filter_map(|i| {
            let q = DQuat::from_xyzw(a.cols[1][i], a.cols[2][i], a.cols[3][i], a.cols[0][i]);
            let n = q.length();
            (n > 0.5 && n < 1.5).then(|| (a.t[i], q / n))
        })
        .unzip();
    if t.len() < 2 || 2 * t.len() < all {
        return Err((t.len(), all.max(1)));
    }
    let rate = Series {
        topic: a.topic,
        t: t.clone(),
        us: Vec::new(),
        cols: Vec::new(),
        fields: Vec::new(),
        out_of_order: 0,
    }
    .rate();
    Ok(Quats {
        bad: all - t.len(),
        t,
        q,
        rate,
    })
}

/// Checks every channel against the CSV reader's ranges ([`Quantity::range`]).
///
/// # Errors
/// The first value outside: the channel, whether it was derived, the time (s and the ULog
/// time stamp, `zero_us` being the time base's start) and the range.
fn derived_in_range(data: &FlightData, zero_us: f64) -> Result<(), String> {
    use Quantity as Q;
    let att: Option<Vec<DVec3>> = data.attitude.as_ref().map(|a| {
        a.iter()
            .map(|e| DVec3::new(e.roll, e.pitch, e.yaw))
            .collect()
    });
    let air: Option<Vec<DVec3>> = data
        .airspeed
        .as_ref()
        .map(|a| a.iter().map(|&v| DVec3::new(v, 0.0, 0.0)).collect());
    // (channel, its key in `derived`, values, their quantities)
    type Channel<'a> = (&'a str, &'a str, Option<&'a Vec<DVec3>>, [Q; 3]);
    let channels: [Channel<'_>; 7] = [
        (
            "position",
            "pos_ned",
            Some(&data.pos_ned),
            [Q::North, Q::East, Q::Down],
        ),
        (
            "NED velocity",
            "vel_ned",
            data.vel_ned.as_ref(),
            [Q::Vn, Q::Ve, Q::Vd],
        ),
        (
            "body velocity",
            "vel_body",
            data.vel_body.as_ref(),
            [Q::U, Q::V, Q::W],
        ),
        (
            "body rates",
            "rates_body",
            data.rates_body.as_ref(),
            [Q::P, Q::Q, Q::R],
        ),
        (
            "attitude",
            "attitude",
            att.as_ref(),
            [Q::Roll, Q::Pitch, Q::Yaw],
        ),
        ("airspeed", "airspeed", air.as_ref(), [Q::Airspeed; 3]),
        (
            "accelerometer",
            "accel_body",
            data.accel_body.as_ref(),
            [Q::Ax, Q::Ay, Q::Az],
        ),
    ];
    for (name, key, values, qs) in channels {
        let Some(values) = values else { continue };
        for (i, v) in values.iter().enumerate() {
            for (x, q) in v.to_array().into_iter().zip(qs) {
                let (lo, hi, range) = q.range();
                if (lo..=hi).contains(&x) {
                    continue;
                }
                let how = if data.is_derived(key) {
                    " (derived from the log's other channels: a jump in them?)"
                } else {
                    ""
                };
                let t = data.time[i];
                return Err(format!(
                    "{name}{how}: {x:.6e} at {t:.3} s (ULog time {:.0} µs) is outside {range}",
                    zero_us + t * 1e6
                ));
            }
        }
    }
    Ok(())
}

/// The default rate of the time base for channels sampled at up to `hz`: the largest of
/// 1, 2, 5, 10, 20, 25, 50 Hz not above it (and not above [`DEFAULT_MAX_RATE_HZ`]).
pub fn nice_rate(hz: f64) -> f64 {
    [50.0, 25.0, 20.0, 10.0, 5.0, 2.0, 1.0]
        .into_iter()
        .find(|&r| r <= hz.min(DEFAULT_MAX_RATE_HZ) + 1e-9)
        .unwrap_or(1.0)
}

/// The system, hardware and vehicle type, for the report.
fn about(log: &UlogFile, report: &mut ImportReport) {
    let sys = [log.info("sys_name"), log.info("ver_hw")]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(" ");
    if !sys.is_empty() {
        report.about.push(("system".into(), sys));
    }
    if let Some(t) = log.param("MAV_TYPE") {
        report.about.push((
            "vehicle type".into(),
            format!("MAV_TYPE {t} ({})", mav_type_name(t as i64)),
        ));
    }
    let others = log
        .topics
        .iter()
        .filter(|t| !TOPICS.contains(&t.name.as_str()) && t.count > 0)
        .count();
    report.about.push((
        "topics".into(),
        format!(
            "{} with data ({} of them not looked at)",
            log.topics.iter().filter(|t| t.count > 0).count(),
            others
        ),
    ));
}

/// MAVLink's `MAV_TYPE` names of the common vehicles.
fn mav_type_name(t: i64) -> &'static str {
    match t {
        1 => "fixed wing",
        2 => "quadrotor",
        3 => "coaxial",
        4 => "helicopter",
        10 => "ground rover",
        12 => "submarine",
        13 => "hexarotor",
        14 => "octorotor",
        15 => "tricopter",
        19..=22 => "VTOL",
        _ => "other",
    }
}

/// How a topic's fields are fetched ([`Series::of`] on the log being read).
type Getter<'a> = &'a dyn Fn(&str, &[&str]) -> Result<Option<Series>, UlogError>;

/// A geodetic origin: latitude °, longitude °, altitude m.
type LatLonAlt = (f64, f64, f64);

/// The position: local NED from `vehicle_local_position`, else a global position made local.
/// Returns the series (NED, m) and the origin (latitude °, longitude °, altitude m) if known.
fn position(
    log: &UlogFile,
    file: &str,
    get: Getter<'_>,
    report: &mut ImportReport,
) -> Result<(Series, Option<LatLonAlt>), UlogError> {
    if let Some(p) = get("vehicle_local_position", &["x", "y", "z"])? {
        p.check_all(file, &[Quantity::North, Quantity::East, Quantity::Down])?;
        let lp = log.topic("vehicle_local_position");
        let col = |f: &str| lp.and_then(|t| t.values(f));
        let mut note = Vec::new();
        if let Some(v) = col("xy_valid") {
            let bad = v.iter().filter(|&&x| x == 0.0).count();
            if bad > 0 {
                note.push(format!(
                    "xy_valid false in {:.0} % of samples",
                    100.0 * bad as f64 / v.len().max(1) as f64
                ));
            }
        }
        if let Some(r) = col("xy_reset_counter") {
            let resets = r.windows(2).filter(|w| w[1] != w[0]).count();
            if resets > 0 {
                let s = if resets == 1 { "" } else { "s" };
                note.push(format!("{resets} estimator reset{s} (jumps)"));
            }
        }
        let origin = match (
            col("ref_lat"),
            col("ref_lon"),
            col("ref_alt"),
            col("xy_global"),
        ) {
            (Some(la), Some(lo), alt, global) => (0..la.len())
                .find(|&i| {
                    global
                        .as_ref()
                        .map_or(la[i] != 0.0 || lo[i] != 0.0, |g| g[i] != 0.0)
                })
                .map(|i| (la[i], lo[i], alt.as_ref().map_or(0.0, |a| a[i]))),
            _ => None,
        };
        if let Some(o) = origin {
            check_origin(
                file,
                "vehicle_local_position",
                ["ref_lat", "ref_lon", "ref_alt"],
                o,
            )?;
        } else {
            note.push("no global reference: origin unknown".into());
        }
        report.channel(
            "position",
            "vehicle_local_position x, y, z",
            p.len(),
            p.rate(),
            true,
            note.join("; "),
        );
        p.gap_note(report);
        return Ok((p, origin));
    }
    // Global positions: degrees and metres, or the GPS driver's integers.
    let global = match get("vehicle_global_position", &["lat", "lon", "alt"])? {
        Some(g) => Some((g, "vehicle_global_position lat, lon, alt", 1.0, 1.0)),
        None => match get("vehicle_gps_position", &["lat", "lon", "alt"])
            .ok()
            .flatten()
        {
            Some(g) => Some((g, "vehicle_gps_position lat, lon, alt", 1e-7, 1e-3)),
            None => get(
                "vehicle_gps_position",
                &["latitude_deg", "longitude_deg", "altitude_msl_m"],
            )?
            .map(|g| {
                (
                    g,
                    "vehicle_gps_position latitude_deg, longitude_deg, altitude_msl_m",
                    1.0,
                    1.0,
                )
            }),
        },
    };
    let Some((mut g, source, deg, metres)): Option<(Series, &str, f64, f64)> = global else {
        return Err(UlogError::file(
            file,
            UlogErrorKind::Missing(
                "no position: the log has none of vehicle_local_position, \
                 vehicle_global_position, vehicle_gps_position with samples"
                    .into(),
            ),
        ));
    };
    // The ranges apply to the values in radians and metres; errors show the values as read.
    g.check(file, 0, deg.to_radians(), Quantity::Lat)?;
    g.check(file, 1, deg.to_radians(), Quantity::Lon)?;
    g.check(file, 2, metres, Quantity::Alt)?;
    for v in &mut g.cols[0] {
        *v = (*v * deg).to_radians();
    }
    for v in &mut g.cols[1] {
        *v = (*v * deg).to_radians();
    }
    for v in &mut g.cols[2] {
        *v *= metres;
    }
    let origin = (
        g.cols[0][0].to_degrees(),
        g.cols[1][0].to_degrees(),
        g.cols[2][0],
    );
    let [la, lo, alt] = [0, 1, 2].map(|c| g.fields[c].clone());
    check_origin(file, &g.topic, [&la, &lo, &alt], origin)?;
    let ned = flat_earth_ned(&g.cols[0], &g.cols[1], &g.cols[2]);
    report.channel(
        "position",
        source,
        g.len(),
        g.rate(),
        true,
        "local NED about the first sample (flat earth)",
    );
    g.gap_note(report);
    g.cols = vec![
        ned.iter().map(|p| p.x).collect(),
        ned.iter().map(|p| p.y).collect(),
        ned.iter().map(|p| p.z).collect(),
    ];
    Ok((g, Some(origin)))
}

/// Checks the origin (latitude °, longitude °, altitude m, from `topic`'s `fields`) against
/// the ranges of the flight data's metadata ([`crate::ORIGIN_RANGES`]), which the CSV reader
/// applies to what `import --out` writes.
///
/// # Errors
/// The first value outside, naming the topic and field.
fn check_origin(
    file: &str,
    topic: &str,
    fields: [&str; 3],
    (lat, lon, alt): LatLonAlt,
) -> Result<(), UlogError> {
    let keys = ["latitude_deg", "longitude_deg", "altitude_m"];
    for ((key, field), v) in keys.into_iter().zip(fields).zip([lat, lon, alt]) {
        if let Err(e) = crate::check_origin_field(key, v) {
            return Err(UlogError::file(
                file,
                UlogErrorKind::BadValues(format!("the flight's origin: {e}")),
            )
            .in_topic(topic)
            .in_field(field));
        }
    }
    Ok(())
}

/// The controls: `actuator_controls_0`, else the torque and thrust setpoints; held.
fn controls(
    file: &str,
    get: Getter<'_>,
    options: &UlogOptions,
    grid: &[f64],
    span: (f64, f64),
    data: &mut FlightData,
    report: &mut ImportReport,
) -> Result<(), UlogError> {
    let found = match get(
        "actuator_controls_0",
        &["control[0]", "control[1]", "control[2]", "control[3]"],
    )? {
        Some(c) => Some((c, "control[0..4]")),
        None => {
            let torque = get("vehicle_torque_setpoint", &["xyz[0]", "xyz[1]", "xyz[2]"])?;
            let thrust = get("vehicle_thrust_setpoint", &["xyz[0]"])?;
            match (torque, thrust) {
                (Some(mut tq), Some(th)) => {
                    // Thrust onto the torque's times, held.
                    let t = th.hold(&tq.t).swap_remove(0);
                    tq.cols.push(t);
                    tq.topic = "vehicle_torque_setpoint".into();
                    Some((tq, "xyz + vehicle_thrust_setpoint xyz[0]"))
                }
                _ => None,
            }
        }
    };
    let Some((c, fields)) = found else {
        report.channel(
            "controls",
            "actuator_controls_0",
            0,
            None,
            false,
            "not in the log",
        );
        return Ok(());
    };
    let note = format!(
        "held; ±1 → ±{}° (aileron +roll, elevator −pitch, rudder −yaw)",
        options.surface_max_deg
    );
    let k = options.surface_max_deg.to_radians();
    for (col, q) in [
        (0, Quantity::Aileron),
        (1, Quantity::Elevator),
        (2, Quantity::Rudder),
    ] {
        c.check(file, col, k, q)?;
    }
    if use_channel(report, "controls", &c, fields, span, &note) {
        let h = c.hold(grid);
        let over = h[3].iter().filter(|t| !(0.0..=1.0).contains(*t)).count();
        if over > 0 {
            report.note(format!("throttle outside 0..1 in {over} samples (clamped)"));
        }
        data.controls = Some(
            (0..grid.len())
                .map(|i| Controls {
                    throttle: h[3][i].clamp(0.0, 1.0),
                    elevator: -k * h[1][i],
                    aileron: k * h[0][i],
                    rudder: -k * h[2][i],
                })
                .collect(),
        );
    }
    Ok(())
}

/// Reports channel `name` from `series`; true when it covers enough of the span to be used.
fn use_channel(
    report: &mut ImportReport,
    name: &str,
    series: &Series,
    fields: &str,
    (t0, t1): (f64, f64),
    note: &str,
) -> bool {
    let (a, b) = series.span();
    let covered = coverage(series, (t0, t1));
    let source = format!("{} {fields}", series.topic);
    let used = covered >= MIN_COVERAGE;
    let note = if used {
        note.to_string()
    } else {
        format!(
            "covers {:.0} % of the flight ({a:.1}–{b:.1} s of {t0:.1}–{t1:.1} s)",
            100.0 * covered
        )
    };
    report.channel(name, source, series.len(), series.rate(), used, note);
    if used {
        series.gap_note(report);
    }
    used
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_hold_and_slerp_on_a_grid() {
        let s = Series {
            topic: "x".into(),
            t: vec![0.0, 1.0, 3.0],
            us: vec![0, 1_000_000, 3_000_000],
            cols: vec![vec![0.0, 10.0, 30.0]],
            fields: vec!["x".into()],
            out_of_order: 0,
        };
        let grid = [-1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(s.linear(&grid)[0], [0.0, 0.0, 5.0, 10.0, 20.0, 30.0, 30.0]);
        assert_eq!(s.hold(&grid)[0], [0.0, 0.0, 0.0, 10.0, 10.0, 30.0, 30.0]);
        assert_eq!(s.rate(), Some(0.5)); // median of 1 s and 2 s steps: the upper
                                         // Slerp goes the short way even when the signs of the samples differ.
        let a = DQuat::from_rotation_z(0.0);
        let b = -DQuat::from_rotation_z(1.0);
        let q = slerp(&[0.0, 1.0], &[a, b], &[0.5]);
        let (e, _) = EulerZyx::from_matrix(DMat3::from_quat(q[0]));
        assert!((e.yaw - 0.5).abs() < 1e-12, "{e:?}");
        assert_eq!(nice_rate(404.0), 50.0);
        assert_eq!(nice_rate(20.8), 20.0);
        assert_eq!(nice_rate(10.4), 10.0);
        assert_eq!(nice_rate(0.3), 1.0);
    }
}
