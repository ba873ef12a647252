//! Flying the model through one window: from a start state, open loop on the recorded
//! commands (zero-order hold), recording what every measured channel would read.
//!
//! Surface positions under `actuator_lag` are states no sensor measures: they follow from the
//! command history alone ([`SurfaceTracker`]), carried from window to window in O(samples).

use glam::{DMat3, DQuat, DVec3};

use super::sensors::delay_weights;
use wireflight_data::{Controls, FlightData};
use wireflight_flight::effects::Reading;
use wireflight_flight::model::{air_angles, AirData, HeldCommands, Model, State, Vehicle};
use wireflight_geometry::euler::EulerZyx;

/// What the model predicts at one sample, in the data's frames (NED, aerospace angles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Predicted {
    /// Position, NED, m.
    pub pos_ned: DVec3,
    /// Velocity, NED, m/s.
    pub vel_ned: DVec3,
    /// Attitude, body to NED, as the state carries it (identity for a point mass). Its Euler
    /// angles follow when they are reported ([`Predicted::attitude`]); a fit's flights
    /// compare it with the measured angles without the three `atan2` per sample they take
    /// (a tenth of a flight).
    pub quat: DQuat,
    /// Body rates p, q, r, rad/s (zero for a point mass).
    pub rates: DVec3,
    /// Velocity relative to the model's air, body axes, m/s (zero for a point mass). α and β
    /// follow from it ([`Predicted::air`]) when a prediction is reported; the start fits'
    /// flights need the airspeed alone, and not two inverse trigonometric functions per
    /// sample.
    pub air_velocity_body: DVec3,
    /// Air density, kg/m³ (zero for a point mass).
    pub rho: f64,
    /// What the airspeed sensor reads, m/s: the length of the air-relative velocity, changed
    /// by the model's measurement effects (`apply_sensors`).
    pub airspeed: f64,
    /// What the accelerometer reads (specific force, body axes), m/s²: predicted only where
    /// the data have an accelerometer (zero elsewhere).
    pub specific_force: DVec3,
}

impl Predicted {
    /// The attitude as aerospace Euler angles (exactly those of the state's rotation matrix,
    /// [`EulerZyx::from_matrix`]).
    pub fn attitude(&self) -> EulerZyx {
        EulerZyx::from_matrix(DMat3::from_quat(self.quat)).0
    }

    /// Airspeed as the sensor reads it, m/s.
    pub fn airspeed(&self) -> f64 {
        self.airspeed
    }

    /// Airspeed, angle of attack and sideslip in the model's air (zero for a point mass); the
    /// airspeed as the sensor reads it (the truth's without measurement effects), the rest
    /// as the air is.
    pub fn air(&self) -> AirData {
        if self.rho == 0.0 && self.air_velocity_body == DVec3::ZERO {
            return AirData::default();
        }
        AirData {
            airspeed: self.airspeed,
            ..air_angles(self.air_velocity_body, self.rho)
        }
    }
}

/// Commands in force from sample i (zero for data without controls).
pub fn controls_at(d: &FlightData, i: usize) -> Controls {
    d.controls
        .as_ref()
        .and_then(|c| c.get(i).copied())
        .unwrap_or_default()
}

/// What a state reads as, at time `t`.
pub fn read_out(model: &Model, t: f64, x: &State) -> Predicted {
    match model.vehicle {
        Vehicle::PointMass => Predicted {
            pos_ned: x.pos_ned(),
            vel_ned: x.vel(),
            ..Predicted::default()
        },
        Vehicle::FixedWing(_) => {
            let rot = x.rot();
            let (wind, rho) = model.air_at(x.pos_ned(), t);
            let air_velocity_body = x.vel() - rot.transpose() * wind;
            Predicted {
                pos_ned: x.pos_ned(),
                vel_ned: rot * x.vel(),
                quat: x.quat(),
                rates: x.omega(),
                air_velocity_body,
                rho,
                airspeed: air_velocity_body.length(),
                specific_force: DVec3::ZERO,
            }
        }
    }
}

/// Fly `model` from `x0` at sample `start` through the samples `start..end`, writing one
/// prediction per sample into `out` and, into `states`, the state after every step the
/// tangent-linear flight takes (`sample_steps`): after every integration step and at every
/// sample (both cleared; `states` begins with `x0`). Samples closer together than `max_dt`
/// are flown in one integration step across them ([`Model::step_held`], its end no more than
/// `max_dt` after its start), and the states at the samples inside it are read from the
/// step's stages: the integration steps no longer double with the data rate. A diverging
/// model holds its last finite prediction (scored as the large error it is) and its states
/// stop there. The predictions are what the sensors read, under the model's measurement
/// effects (`apply_sensors`); the states are the truth.
pub fn fly_window(
    model: &Model,
    d: &FlightData,
    (start, end): (usize, usize),
    x0: &State,
    max_dt: f64,
    out: &mut Vec<Predicted>,
    states: &mut Vec<State>,
) {
    fly_truth(model, d, (start, end), x0, max_dt, out, states);
    if let Some(time) = d.time.get(start..end) {
        let delay = model.nav_delay();
        let before = if delay > 0.0 && end > start {
            fly_back(model, d, start, x0, max_dt, delay)
        } else {
            Vec::new()
        };
        apply_sensors(model, time, &before, out);
    }
}

/// The truth before a window's first sample that a navigation solution `delay` s late still
/// reads inside it: the model flown backwards from the window's start `x0`, under the
/// commands held then, to `delay` before it, recorded (position, NED velocity; earliest
/// first) at the data's samples there. Before the flight's first sample nothing is known of
/// it: the aircraft is taken to have flown straight on at its velocity there (as one that
/// starts trimmed did, and as `simulate` records it). Empty where the backward flight does
/// not stay finite (the readings then extrapolate the window's own,
/// [`super::sensors::delay_weights`]).
pub(crate) fn fly_back(
    model: &Model,
    d: &FlightData,
    start: usize,
    x0: &State,
    max_dt: f64,
    delay: f64,
) -> Vec<(f64, DVec3, DVec3)> {
    let t0 = d.time[start];
    let spacing = d.time.get(start + 1).map_or(max_dt, |t1| t1 - t0).max(1e-6);
    let mut out = Vec::new();
    let (mut t, mut x, mut k) = (t0, *x0, start);
    // Bounded: every step goes back at least `spacing` (or a sample), and no further than
    // one sample beyond the delay.
    let most = (delay / spacing).ceil() as usize + 2 + start.min(1 << 20);
    for _ in 0..most {
        if t <= t0 - delay {
            break;
        }
        if k == 0 {
            // Before the flight: straight on, back to the delay in one step.
            let p = read_out(model, t, &x);
            let earlier = t0 - delay;
            out.push((earlier, p.pos_ned - p.vel_ned * (t - earlier), p.vel_ned));
            break;
        }
        let (earlier, cmd) = (d.time[k - 1], controls_at(d, k - 1));
        let (n, h) = Model::substeps(t - earlier, max_dt);
        for i in 0..n {
            x = model.step(t - i as f64 * h, &x, &cmd, -h);
        }
        if !x.is_finite() {
            return Vec::new();
        }
        let p = read_out(model, earlier, &x);
        out.push((earlier, p.pos_ned, p.vel_ned));
        t = earlier;
        k = k.saturating_sub(1);
    }
    out.reverse();
    out
}

/// [`fly_window`] before the sensors: the predictions of the true flight.
fn fly_truth(
    model: &Model,
    d: &FlightData,
    (start, end): (usize, usize),
    x0: &State,
    max_dt: f64,
    out: &mut Vec<Predicted>,
    states: &mut Vec<State>,
) {
    out.clear();
    states.clear();
    // The accelerometer costs one more evaluation of the forces per sample: only where the
    // data have one.
    let accel = d.accel_body.is_some() && matches!(model.vehicle, Vehicle::FixedWing(_));
    let read = |i: usize, x: &State| {
        let mut p = read_out(model, d.time[i], x);
        if accel {
            p.specific_force = model.specific_force(d.time[i], x, &controls_at(d, i));
        }
        p
    };
    // A sample each, and a state each where steps span samples (more where they are
    // sub-stepped): room for them at once, not grown and copied flight after flight.
    let samples = end.saturating_sub(start);
    out.reserve(samples);
    states.reserve(samples + 1);
    let mut x = *x0;
    states.push(x);
    let mut i = start;
    while i < end {
        let p = read(i, &x);
        out.push(p);
        if i + 1 >= end {
            break;
        }
        let j = step_end(&d.time, i, end, max_dt);
        if j == i + 1 {
            // `Model::advance`, its steps recorded.
            let cmd = controls_at(d, i);
            let (steps, h) = Model::substeps(d.time[i + 1] - d.time[i], max_dt);
            for k in 0..steps {
                x = model.step(d.time[i] + k as f64 * h, &x, &cmd, h);
                if !x.is_finite() {
                    out.resize(end - start, p);
                    return;
                }
                states.push(x);
            }
        } else {
            let held = held_commands(d, i, j);
            let step = model.step_held(&x, &held);
            if !step.end.is_finite() {
                out.resize(end - start, p);
                return;
            }
            for k in i + 1..j {
                let inside = step.at(model, &held, d.time[k] - d.time[i]);
                out.push(read(k, &inside));
                states.push(inside);
            }
            x = step.end;
            states.push(x);
        }
        i = j;
    }
}

/// The reading of a prediction.
fn reading_of(p: &Predicted) -> Reading {
    Reading {
        pos_ned: p.pos_ned,
        vel_ned: p.vel_ned,
        quat: p.quat,
        rates: p.rates,
        airspeed: p.airspeed,
        specific_force: p.specific_force,
    }
}

/// Turn a window's predictions of the truth (sampled at `time`, with `before` the truth the
/// model flew back to before it, [`fly_back`]) into what the sensors read under the model's
/// measurement effects: the navigation delay first, then every effect's [`Reading`] change.
/// Nothing to do for a model without them.
fn apply_sensors(
    model: &Model,
    time: &[f64],
    before: &[(f64, DVec3, DVec3)],
    out: &mut [Predicted],
) {
    if !model.has_measurement_effects() || out.is_empty() {
        return;
    }
    let delay = model.nav_delay();
    if delay > 0.0 && time.len() == out.len() {
        // The truth on one time line: what was flown back to, then the window.
        let times: Vec<f64> = before
            .iter()
            .map(|b| b.0)
            .chain(time.iter().copied())
            .collect();
        let truth: Vec<(DVec3, DVec3)> = before
            .iter()
            .map(|b| (b.1, b.2))
            .chain(out.iter().map(|p| (p.pos_ned, p.vel_ned)))
            .collect();
        let first = before.len();
        for (k, p) in out.iter_mut().enumerate() {
            let w = delay_weights(&times, first + k, delay);
            p.pos_ned = w.iter().map(|&(j, c)| truth[j].0 * c).sum();
            p.vel_ned = w.iter().map(|&(j, c)| truth[j].1 * c).sum();
        }
    }
    for p in out.iter_mut() {
        let mut r = reading_of(p);
        model.measure(&mut r);
        p.pos_ned = r.pos_ned;
        p.vel_ned = r.vel_ned;
        p.quat = r.quat;
        p.rates = r.rates;
        p.airspeed = r.airspeed;
        p.specific_force = r.specific_force;
    }
}

/// The sample an integration step from sample `i` ends at: the last one before `end` no more
/// than `max_dt` after it, and at least the next.
pub(crate) fn step_end(time: &[f64], i: usize, end: usize, max_dt: f64) -> usize {
    let limit = time[i] + max_dt * (1.0 + 1e-9);
    let mut j = i + 1;
    while j + 1 < end && time[j + 1] <= limit {
        j += 1;
    }
    j
}

/// The commands held over samples `i..j`.
pub(crate) fn held_commands(d: &FlightData, i: usize, j: usize) -> HeldCommands<'_> {
    HeldCommands {
        times: &d.time[i..=j],
        controls: d.controls.as_ref().and_then(|c| c.get(i..j)),
    }
}

/// The steps the tangent-linear flight takes from sample `i` to the next, as [`fly_window`]
/// records its states: the integration's sub-steps where samples are further apart than
/// `max_dt`, else one (a sample inside an integration step is a state too).
pub(crate) fn sample_steps(time: &[f64], i: usize, max_dt: f64) -> (usize, f64) {
    Model::substeps(time[i + 1] - time[i], max_dt)
}

/// Surface positions at sample `upto` under the model's actuator lag (the commands
/// themselves without one): the exact zero-order-hold discretisation of τẋ = cmd − x,
/// started at the first command.
pub fn surfaces_at(model: &Model, d: &FlightData, upto: usize) -> DVec3 {
    SurfaceTracker::new(model, d).at(upto)
}

/// [`surfaces_at`] for increasing sample indices in O(total samples): the lag filter carries
/// its state from one window start to the next instead of starting over from the first
/// command.
pub struct SurfaceTracker<'a> {
    data: &'a FlightData,
    tau: Option<f64>,
    index: usize,
    state: DVec3,
    /// (dt, 1 − e^(−dt/τ)) of the last step: uniform sampling needs one `exp`.
    gain_cache: (f64, f64),
}

fn surfaces_of(c: &Controls) -> DVec3 {
    DVec3::new(c.elevator, c.aileron, c.rudder)
}

impl<'a> SurfaceTracker<'a> {
    /// A tracker at the first sample.
    pub fn new(model: &Model, data: &'a FlightData) -> Self {
        let state = data
            .controls
            .as_ref()
            .and_then(|c| c.first())
            .map(surfaces_of)
            .unwrap_or(DVec3::ZERO);
        Self {
            data,
            tau: model.effects.iter().find_map(|e| e.actuator_tau()),
            index: 0,
            state,
            gain_cache: (f64::NAN, 0.0),
        }
    }

    /// Surface positions at sample `upto` (≥ every earlier call's).
    pub fn at(&mut self, upto: usize) -> DVec3 {
        let Some(controls) = &self.data.controls else {
            return DVec3::ZERO;
        };
        let upto = upto.min(controls.len().saturating_sub(1));
        let Some(tau) = self.tau else {
            return controls.get(upto).map(surfaces_of).unwrap_or_default();
        };
        let time = &self.data.time;
        for (i, c) in controls.iter().enumerate().take(upto).skip(self.index) {
            let dt = time[i + 1] - time[i];
            if dt != self.gain_cache.0 {
                self.gain_cache = (dt, 1.0 - (-dt / tau).exp());
            }
            self.state += self.gain_cache.1 * (surfaces_of(c) - self.state);
        }
        self.index = self.index.max(upto);
        self.state
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wireflight_flight::effects::{ActuatorLag, Origin};
    use wireflight_flight::params::FixedWingParams;

    /// A prediction's air data (taken from the air-relative velocity it carries) are the
    /// model's, exactly; a point mass reads still air.
    #[test]
    fn a_predictions_air_is_the_models_air_data() {
        let mut model = Model::new(
            Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
            Origin::default(),
        );
        model
            .add_effect(
                wireflight_flight::spec::EffectSpec::parse(
                    "wind:north_mps=4,east_mps=-3,down_mps=1",
                )
                .unwrap()
                .build(&model.effect_context())
                .unwrap(),
            )
            .unwrap();
        let mut x = State::default();
        x.set_pos_ned(DVec3::new(10.0, -20.0, -100.0));
        x.set_vel(DVec3::new(24.0, 1.5, 2.0));
        x.set_attitude(EulerZyx::new(0.7, 0.1, -0.3));
        x.set_omega(DVec3::new(0.1, -0.05, 0.02));
        let p = read_out(&model, 3.0, &x);
        let air = model.air_data(3.0, &x);
        assert_eq!(p.air(), air);
        assert_eq!(p.airspeed(), air.airspeed);
        assert!(air.alpha != 0.0 && air.beta != 0.0 && p.rho > 0.0);
        let point = Model::new(Vehicle::PointMass, Origin::default());
        assert_eq!(read_out(&point, 3.0, &x).air(), AirData::default());
    }

    /// The incremental tracker gives exactly the from-the-start filter, on uneven sampling.
    #[test]
    fn surface_tracker_matches_filtering_from_the_start() {
        let mut data = FlightData::default();
        let mut controls = Vec::new();
        let mut t = 0.0;
        for i in 0..400 {
            data.time.push(t);
            data.pos_ned.push(DVec3::ZERO);
            t += if i % 7 == 0 { 0.03 } else { 0.02 };
            let step = if (i / 50) % 2 == 0 { 0.1 } else { -0.1 };
            controls.push(Controls {
                throttle: 0.5,
                elevator: step,
                aileron: -step,
                rudder: 0.5 * step,
            });
        }
        data.controls = Some(controls);
        let mut model = Model::new(
            Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
            Origin::default(),
        );
        for lagged in [false, true] {
            if lagged {
                model
                    .add_effect(Box::new(ActuatorLag { tau_s: 0.15 }))
                    .unwrap();
            }
            let mut tracker = SurfaceTracker::new(&model, &data);
            for upto in [0, 1, 13, 13, 50, 51, 200, 399] {
                let fast = tracker.at(upto);
                // From the start, one sample at a time.
                let slow = {
                    let c = data.controls.as_ref().unwrap();
                    match model.effects.iter().find_map(|e| e.actuator_tau()) {
                        None => surfaces_of(&c[upto]),
                        Some(tau) => {
                            let mut s = surfaces_of(&c[0]);
                            for (i, ci) in c.iter().enumerate().take(upto) {
                                let a = 1.0 - (-(data.time[i + 1] - data.time[i]) / tau).exp();
                                s += a * (surfaces_of(ci) - s);
                            }
                            s
                        }
                    }
                };
                assert!((fast - slow).length() < 1e-12, "{upto}: {fast} vs {slow}");
            }
        }
    }
}
