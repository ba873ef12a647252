//! The Jacobian of a window's residuals with respect to its start parameters, along a flight
//! already flown: the trajectory's sensitivity to its start state carried along it by the
//! tangent-linear equations ([`wireflight_flight::linear`]), read out through the derivative of
//! each measured channel. It replaces one flight per start parameter (forward differences)
//! at the cost of one model Jacobian per pair of integration steps.
//!
//! Read-out derivatives, for a column of the error state (δp, δv, δθ, δω):
//! position δp; NED velocity R(δv + δθ × v); attitude W(φ, θ)·δθ, W the matrix that turns
//! body rates into Euler-angle rates; body rates δω; airspeed v̂ᵣ·(δv + δθ × Rᵀw − Rᵀ·∂w/∂p·δp)
//! with vᵣ = v − Rᵀw the air-relative velocity and w the model's wind.

use glam::{DMat3, DVec3};

use super::predict::fly_back;
use super::predict::{controls_at, sample_steps};
use super::sensors::{airspeed_gain, attitude_read, delay_weights};
use super::start::{param_count, state_of, step_of};
use super::Prepared;
use wireflight_data::{Channel, Controls};
use wireflight_flight::linear::{free_columns, propagate, transition, ErrorMatrix, ERROR_MAX};
use wireflight_flight::model::{Model, State, Vehicle};

/// Most residual rows of one sample: position, velocity, attitude, rates and the
/// accelerometer (3 each) and the airspeed.
const ROWS_MAX: usize = 16;

/// Step of the wind's position derivative, m.
const WIND_STEP: f64 = 1e-2;

impl Prepared<'_> {
    /// The Jacobian of the weighted residuals `r` over `span` with respect to the start
    /// parameters `q` (and their surface positions) into `jac` (column-major, `r.len()`
    /// rows), by the tangent-linear equations along `trajectory`: the states after every
    /// integration step of the flight from `q` that `r` came from (`fly_window`'s). False
    /// when that flight diverged or does not fit (the caller falls back to differences).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn tangent_jacobian(
        &self,
        model: &Model,
        (start, end): (usize, usize),
        q: &[f64],
        surfaces: DVec3,
        trajectory: &[State],
        r: &[f64],
        jac: &mut Vec<f64>,
    ) -> bool {
        let d = self.data;
        let n = model.error_dim();
        let np = param_count(model);
        let samples = end.saturating_sub(start);
        if samples == 0 || !r.len().is_multiple_of(samples) || trajectory.is_empty() {
            return false;
        }
        let per_sample = r.len() / samples;
        let m = r.len();
        let x0 = state_of(model, q, surfaces);
        if trajectory[0] != x0 {
            return false;
        }
        // The sensitivity and the next one, alternating (`cur` holds the current one).
        let mut sens = [
            start_sensitivity(model, q, &x0),
            [[0.0; ERROR_MAX]; ERROR_MAX],
        ];
        let mut cur = 0;
        // Every entry is written below: a Jacobian of the right size (the one a fit replaces)
        // is overwritten, not cleared first.
        if jac.len() != np * m {
            jac.clear();
            jac.resize(np * m, 0.0);
        }
        let mut a: ErrorMatrix = [[0.0; ERROR_MAX]; ERROR_MAX];
        // exp(h·a), and the h it is for.
        let mut phi = a;
        let mut phi_h = f64::NAN;
        let mut free = 0;
        // Index of the current state in `trajectory` (= integration steps taken).
        let mut step_count = 0usize;
        let mut hold = Hold::new(model);
        let mut finite = true;
        for i in start..end {
            let x = &trajectory[step_count];
            let row0 = (i - start) * per_sample;
            match self.jacobian_rows(model, i, x, &sens[cur], per_sample, (m, row0), jac) {
                Some(ok) => finite &= ok,
                None => return false,
            }
            if i + 1 == end {
                break;
            }
            // The steps of `fly_window`'s states.
            let t = d.time[i];
            let cmd = controls_at(d, i);
            let (steps, h) = sample_steps(&d.time, i, self.cfg.max_dt);
            for k in 0..steps {
                let Some(next) = trajectory.get(step_count + 1) else {
                    return false; // the flight diverged here
                };
                // One model Jacobian per pair of steps, at the state between them (on the
                // trajectory) under the mean of the two steps' commands: the midpoint rule
                // over the pair, second order (the first step's commands alone would make it
                // first order wherever they change every sample, as under an autopilot). The
                // state between is read out with a first-order error that does not
                // accumulate.
                //
                // In steady flight the Jacobian is held instead (see `Hold`).
                if step_count.is_multiple_of(2) {
                    let following = if k + 1 < steps || i + 2 >= end {
                        cmd
                    } else {
                        controls_at(d, i + 1)
                    };
                    let c = mean(&cmd, &following);
                    if !hold.keeps(free, next, &c) {
                        let tk = t + k as f64 * h;
                        a = model.error_jacobian(tk + h, next, &c);
                        free = free_columns(&a, n);
                        phi_h = f64::NAN;
                        hold.taken(next, &c);
                    }
                }
                step_count += 1;
                if h != phi_h {
                    transition(&a, n, h, free, &mut phi);
                    phi_h = h;
                }
                let [s0, s1] = &mut sens;
                let (from, to) = if cur == 0 { (s0, s1) } else { (s1, s0) };
                propagate(&phi, n, from, to, free);
                cur = 1 - cur;
            }
        }
        let delay = model.nav_delay();
        if delay > 0.0 && !self.delay_rows(model, (start, end), q, surfaces, per_sample, jac) {
            return false;
        }
        finite
    }

    /// A late navigation solution's rows of the Jacobian `jac` (laid out as
    /// [`Self::tangent_jacobian`]'s, its rows still undelayed): each delayed reading is the
    /// combination of the truth before and inside the window that [`delay_weights`] makes.
    /// Inside the window those are the tangent's rows; before it, where the model is flown
    /// back ([`fly_back`]), a forward difference per start parameter of that short flight
    /// (a few samples, not a window). False when the flight back does not stay finite.
    fn delay_rows(
        &self,
        model: &Model,
        (start, end): (usize, usize),
        q: &[f64],
        surfaces: DVec3,
        per_sample: usize,
        jac: &mut [f64],
    ) -> bool {
        let d = self.data;
        let delay = model.nav_delay();
        let m = (end - start) * per_sample;
        if m == 0 || jac.len() != q.len() * m {
            return false;
        }
        let x0 = state_of(model, q, surfaces);
        let before = fly_back(model, d, start, &x0, self.cfg.max_dt, delay);
        if before.is_empty() {
            return false;
        }
        let times: Vec<f64> = before
            .iter()
            .map(|b| b.0)
            .chain(d.time[start..end].iter().copied())
            .collect();
        let velocity = self.measured.for_vehicle(model).velocity && d.vel_ned.is_some();
        let [wp, wv, _, _] = &self.weights;
        let pre = before.len();
        let mut undelayed = vec![0.0; m];
        for (k, col) in jac.chunks_exact_mut(m).enumerate() {
            let h = step_of(k);
            let mut qk = q.to_vec();
            qk[k] += h;
            let moved = fly_back(
                model,
                d,
                start,
                &state_of(model, &qk, surfaces),
                self.cfg.max_dt,
                delay,
            );
            if moved.len() != pre {
                return false;
            }
            // The derivative of the truth before the window, weighted as its rows are.
            let back = |j: usize, o: usize| -> f64 {
                let (a, b) = (&before[j], &moved[j]);
                if o < 3 {
                    wp[o] * (b.1[o] - a.1[o]) / h
                } else {
                    wv[o - 3] * (b.2[o - 3] - a.2[o - 3]) / h
                }
            };
            undelayed.copy_from_slice(col);
            let offsets: &[usize] = if velocity {
                &[0, 1, 2, 3, 4, 5]
            } else {
                &[0, 1, 2]
            };
            for i in 0..end - start {
                let w = delay_weights(&times, pre + i, delay);
                for &o in offsets {
                    col[i * per_sample + o] = w
                        .iter()
                        .map(|&(j, c)| {
                            c * if j < pre {
                                back(j, o)
                            } else {
                                undelayed[(j - pre) * per_sample + o]
                            }
                        })
                        .sum();
                }
            }
        }
        true
    }

    /// The derivatives of sample `i`'s residual rows (in the order of `residual_rows`) along
    /// the error-state columns of `s`, at state `x`, written into the column-major `jac` of
    /// `m` rows per column from row `row0` on: each column's rows of the sample together, as
    /// they are computed. None when the sample has other than `per_sample` rows; else whether
    /// every value is finite.
    #[allow(clippy::too_many_arguments)]
    fn jacobian_rows(
        &self,
        model: &Model,
        i: usize,
        x: &State,
        s: &ErrorMatrix,
        per_sample: usize,
        (m_rows, row0): (usize, usize),
        jac: &mut [f64],
    ) -> Option<bool> {
        let np = jac.len() / m_rows.max(1);
        let d = self.data;
        let m = self.measured.for_vehicle(model);
        let [wp, wv, wa, wr] = &self.weights;
        let fixed_wing = matches!(model.vehicle, Vehicle::FixedWing(_));
        let velocity = m.velocity && d.vel_ned.is_some();
        let attitude = fixed_wing && m.attitude && d.attitude.is_some();
        let rates = fixed_wing && m.rates && d.rates_body.is_some();
        let airspeed = fixed_wing && m.airspeed && d.airspeed.is_some();
        let accel = fixed_wing && m.accel && d.accel_body.is_some();
        let count = 3
            * (1 + [velocity, attitude, rates, accel]
                .iter()
                .filter(|&&b| b)
                .count())
            + usize::from(airspeed);
        if count != per_sample || np == 0 || count > ROWS_MAX {
            return None;
        }
        let rot = x.rot();
        let v = x.vel();
        // A misaligned attitude reference reads R·R₀: a body-frame error δθ reads R₀ᵀ·δθ.
        let w = if attitude {
            let (read, r0) = attitude_read(model, &rot);
            euler_rates_matrix(x, &read) * r0.transpose()
        } else {
            DMat3::IDENTITY
        };
        // The airspeed row: v̂ᵣ·(δv + δθ × Rᵀw − Rᵀ·∂w/∂p·δp).
        let air = airspeed.then(|| {
            let t = d.time[i];
            let p = x.pos_ned();
            let wind = model.wind_at(p, t);
            // ∂w/∂p, a column per NED axis (zero where nothing depends on the position).
            let grad = if model.varies_in_space() {
                DMat3::from_cols(
                    (model.wind_at(p + DVec3::X * WIND_STEP, t) - wind) / WIND_STEP,
                    (model.wind_at(p + DVec3::Y * WIND_STEP, t) - wind) / WIND_STEP,
                    (model.wind_at(p + DVec3::Z * WIND_STEP, t) - wind) / WIND_STEP,
                )
            } else {
                DMat3::ZERO
            };
            let wind_body = rot.transpose() * wind;
            let v_r = v - wind_body;
            let va = v_r.length();
            let gain = if va > 0.0 {
                self.airspeed_weight * airspeed_gain(model, va) / va
            } else {
                0.0
            };
            (v_r * gain, wind_body, rot.transpose() * grad)
        });
        // Each residual row is a combination of rows of the sensitivity (all its columns at
        // once, twelve lanes wide): rows[r] = Σₖ c·s[k] over the (k, c) of that row, summed
        // in registers and stored once.
        let mut out = [[0.0; ERROR_MAX]; ROWS_MAX];
        let mut k = 0;
        let mut row = |terms: &[(usize, f64)]| {
            out[k] = combine(s, terms);
            k += 1;
        };
        for (a, &c) in wp.iter().enumerate() {
            row(&[(a, c)]);
        }
        if !fixed_wing {
            if velocity {
                for (a, &c) in wv.iter().enumerate() {
                    row(&[(3 + a, c)]);
                }
            }
        } else {
            if velocity {
                // R·(δv + δθ × v), δθ × v = (θy·vz − θz·vy, θz·vx − θx·vz, θx·vy − θy·vx).
                for (a, &c) in wv.iter().enumerate() {
                    let r = rot.row(a);
                    row(&[
                        (3, c * r.x),
                        (4, c * r.y),
                        (5, c * r.z),
                        (6, c * (r.z * v.y - r.y * v.z)),
                        (7, c * (r.x * v.z - r.z * v.x)),
                        (8, c * (r.y * v.x - r.x * v.y)),
                    ]);
                }
            }
            if attitude {
                for (a, &c) in wa.iter().enumerate() {
                    let r = w.row(a);
                    row(&[(6, c * r.x), (7, c * r.y), (8, c * r.z)]);
                }
            }
            if rates {
                for (a, &c) in wr.iter().enumerate() {
                    row(&[(9 + a, c)]);
                }
            }
            if let Some((dir, wind_body, grad_body)) = air {
                // v̂ᵣ·(δv + δθ × Rᵀw − Rᵀ·∂w/∂p·δp): δθ × u with u = Rᵀw as above, and
                // the position columns through −(Rᵀ·∂w/∂p)ᵀ·v̂ᵣ.
                let u = wind_body;
                let g = -(grad_body.transpose() * dir);
                row(&[
                    (0, g.x),
                    (1, g.y),
                    (2, g.z),
                    (3, dir.x),
                    (4, dir.y),
                    (5, dir.z),
                    (6, dir.z * u.y - dir.y * u.z),
                    (7, dir.x * u.z - dir.z * u.x),
                    (8, dir.y * u.x - dir.x * u.y),
                ]);
            }
            if accel {
                // ∂f/∂e of the specific force, by differences of the model's own forces
                // (an accelerometer's bias or any measurement effect adds a constant).
                let jf = model.specific_force_jacobian(d.time[i], x, &controls_at(d, i));
                let n = model.error_dim();
                for (a, &c) in self.accel_weights.iter().enumerate() {
                    let mut terms = [(0, 0.0); ERROR_MAX];
                    for (k, t) in terms.iter_mut().enumerate().take(n) {
                        *t = (k, c * jf[a][k]);
                    }
                    row(&terms[..n]);
                }
            }
        }
        if !d.sampling.is_all() {
            // A row that is not a sample of a channel has no residual, so no derivative
            // ([`Prepared::residual_rows`]).
            let mut k = 0;
            for (on, channel, axes) in [
                (true, Channel::Position, 3),
                (velocity, Channel::Velocity, 3),
                (fixed_wing && attitude, Channel::Attitude, 3),
                (fixed_wing && rates, Channel::Rates, 3),
                (fixed_wing && airspeed, Channel::Airspeed, 1),
                (fixed_wing && accel, Channel::Accelerometer, 3),
            ] {
                if on {
                    let w = d.sampling.weight(channel, i);
                    for r in &mut out[k..k + axes] {
                        r.iter_mut().for_each(|v| *v *= w);
                    }
                    k += axes;
                }
            }
        }
        let finite = out[..count].iter().flatten().all(|v| v.is_finite());
        for j in 0..np {
            let at = j * m_rows + row0;
            let dest = jac.get_mut(at..at + count)?;
            for (d, o) in dest.iter_mut().zip(&out) {
                *d = o[j];
            }
        }
        Some(finite)
    }
}

/// Σₖ c·s[k] over the terms (k, c): a residual row's derivative along every column of the
/// sensitivity `s` at once.
#[inline(always)]
fn combine(s: &ErrorMatrix, terms: &[(usize, f64)]) -> [f64; ERROR_MAX] {
    let mut acc = [0.0; ERROR_MAX];
    for &(from, c) in terms {
        for (a, v) in acc.iter_mut().zip(&s[from]) {
            *a += c * v;
        }
    }
    acc
}

/// Where the model Jacobian was last taken, and whether it may be held instead of taken
/// again. Its finite differences cost ten model evaluations, and its transition two matrix
/// products: half the tangent. In steady flight (between manoeuvres, on a long leg) the state
/// hardly moves from one pair of steps to the next, and neither does the Jacobian.
///
/// It is held while the state has moved less than [`HOLD_VELOCITY`], [`HOLD_RATE`] and
/// [`HOLD_TURN`] from where it was taken and the commands and surfaces less than
/// [`HOLD_COMMAND`] — never when the equations depend on position (an effect that varies with
/// height or place: the Jacobian's position columns are not zero) or on time itself. On an
/// hour of 100 Hz flight tests this skips half the Jacobians without a flight more in the
/// start fits; the tangent stays within its bound of the forward differences (a test checks).
struct Hold {
    /// The model's equations depend on time itself: never hold.
    timed: bool,
    /// Where the Jacobian was taken: state and commands.
    at: Option<(State, Controls)>,
}

/// Body-velocity change, m/s (0.4% of 25 m/s), that ends a hold.
const HOLD_VELOCITY: f64 = 0.1;
/// Body-rate change, rad/s (0.6°/s), that ends a hold.
const HOLD_RATE: f64 = 0.01;
/// Attitude change, rad (0.6°), that ends a hold.
const HOLD_TURN: f64 = 0.01;
/// Command or surface change (rad, or throttle fraction) that ends a hold.
const HOLD_COMMAND: f64 = 0.01;

impl Hold {
    fn new(model: &Model) -> Self {
        Self {
            timed: model.varies_in_time(),
            at: None,
        }
    }

    /// Whether the Jacobian taken last (with `free` leading zero columns) still serves at
    /// state `x` under commands `c`.
    fn keeps(&self, free: usize, x: &State, c: &Controls) -> bool {
        let Some((x0, c0)) = &self.at else {
            return false;
        };
        let command = c
            .to_array()
            .iter()
            .zip(c0.to_array())
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        !self.timed
            && free == 3
            && (x.vel() - x0.vel()).length() < HOLD_VELOCITY
            && (x.omega() - x0.omega()).length() < HOLD_RATE
            && x.quat().angle_between(x0.quat()) < HOLD_TURN
            && (x.surfaces() - x0.surfaces()).length() < HOLD_COMMAND
            && command < HOLD_COMMAND
    }

    /// The Jacobian was taken at `x` under `c`.
    fn taken(&mut self, x: &State, c: &Controls) {
        self.at = Some((*x, *c));
    }
}

/// The mean of two commands.
fn mean(a: &Controls, b: &Controls) -> Controls {
    Controls {
        throttle: 0.5 * (a.throttle + b.throttle),
        elevator: 0.5 * (a.elevator + b.elevator),
        aileron: 0.5 * (a.aileron + b.aileron),
        rudder: 0.5 * (a.rudder + b.rudder),
    }
}

/// W(φ, θ): Euler-angle rates (roll, pitch, yaw) of body rates, at state `x` whose
/// body-to-NED rotation is `rot`. Roll and pitch come from R's last row, (−sin θ, cos θ sin φ,
/// cos θ cos φ), without inverse trigonometry; near θ = ±90° from the Euler angles as
/// reported.
fn euler_rates_matrix(x: &State, rot: &DMat3) -> DMat3 {
    let (r20, r21, r22) = (rot.x_axis.z, rot.y_axis.z, rot.z_axis.z);
    // Entries of a rotation: no overflow for `hypot` to guard against.
    let ct = (r21 * r21 + r22 * r22).sqrt();
    let (sf, cf, st, ct) = if ct > 1e-6 {
        (r21 / ct, r22 / ct, -r20, ct)
    } else {
        let e = x.attitude();
        let (sf, cf) = e.roll.sin_cos();
        let (st, ct) = e.pitch.sin_cos();
        (
            sf,
            cf,
            st,
            if ct.abs() < 1e-9 {
                1e-9f64.copysign(ct)
            } else {
                ct
            },
        )
    };
    DMat3::from_cols(
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(sf * st / ct, cf, sf / ct),
        DVec3::new(cf * st / ct, -sf, cf / ct),
    )
}

/// ∂e/∂q at the start: the error state's change per start parameter (position, NED
/// velocity, roll/pitch/yaw, body rates; position and velocity for a point mass), columns in
/// the parameters' order. Turning the attitude at a fixed NED velocity turns the body
/// velocity the other way: δv = v × δθ.
fn start_sensitivity(model: &Model, q: &[f64], x0: &State) -> ErrorMatrix {
    let mut s = [[0.0; ERROR_MAX]; ERROR_MAX];
    match model.vehicle {
        Vehicle::PointMass => {
            for (k, row) in s.iter_mut().enumerate().take(6) {
                row[k] = 1.0;
            }
        }
        Vehicle::FixedWing(_) => {
            let rt = x0.rot().transpose();
            let v = x0.vel();
            let (sf, cf) = q[6].sin_cos();
            let (st, ct) = q[7].sin_cos();
            // Body rotation per Euler-angle change (columns roll, pitch, yaw).
            let m = DMat3::from_cols(
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(0.0, cf, -sf),
                DVec3::new(-st, ct * sf, ct * cf),
            );
            for c in 0..3 {
                s[c][c] = 1.0;
                s[9 + c][9 + c] = 1.0;
                let dv = v.cross(m.col(c));
                for r in 0..3 {
                    s[3 + r][3 + c] = rt.col(c)[r];
                    s[3 + r][6 + c] = dv[r];
                    s[6 + r][6 + c] = m.col(c)[r];
                }
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare::start::{params_of, Scratch};
    use crate::compare::CompareConfig;
    use wireflight_data::VehicleKind;
    use wireflight_flight::autopilot::Manoeuvre;
    use wireflight_flight::effects::Origin;
    use wireflight_flight::simulate::{simulate, Noise, SimSpec};
    use wireflight_flight::spec::{EffectSpec, ModelSpec};

    fn model(kind: VehicleKind, effects: &[&str]) -> Model {
        let mut spec = ModelSpec::baseline(kind);
        for e in effects {
            spec.effects.push(EffectSpec::parse(e).unwrap());
        }
        spec.build(Origin::default()).unwrap()
    }

    /// Largest difference between the tangent-linear and the forward-difference Jacobian,
    /// relative to the largest entry of the column it is in.
    fn worst_column_error(m: &Model, prep: &Prepared, window: (usize, usize), offset: f64) -> f64 {
        let x0 = prep.warm_start(m, window, DVec3::ZERO);
        // Not only at the warm start: the Jacobian must hold anywhere nearby.
        let mut q = params_of(m, &x0);
        q[0] += offset;
        q[3] += 0.1 * offset;
        if q.len() > 6 {
            q[6] += 0.01 * offset;
        }
        let surfaces = x0.surfaces();
        let mut r = Vec::new();
        let mut scratch = Scratch::default();
        prep.window_residuals(m, window, &state_of(m, &q, surfaces), &mut scratch, &mut r);
        let mut jac = Vec::new();
        assert!(prep.tangent_jacobian(m, window, &q, surfaces, &scratch.states, &r, &mut jac));
        // Along a flight from elsewhere, it declines.
        let mut other = q.clone();
        other[1] += 1.0;
        let mut r_other = Vec::new();
        let mut elsewhere = Scratch::default();
        prep.window_residuals(
            m,
            window,
            &state_of(m, &other, surfaces),
            &mut elsewhere,
            &mut r_other,
        );
        assert!(!prep.tangent_jacobian(
            m,
            window,
            &q,
            surfaces,
            &elsewhere.states,
            &r,
            &mut Vec::new()
        ));
        let rows = r.len();
        let mut fd = vec![0.0; jac.len()];
        prep.difference_jacobian(m, window, &q, surfaces, &r, &mut scratch, &mut fd);
        let mut worst = 0.0f64;
        for (c, (a, b)) in jac.chunks(rows).zip(fd.chunks(rows)).enumerate() {
            let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let err = a
                .iter()
                .zip(b)
                .fold(0.0f64, |s, (u, v)| s.max((u - v).abs()));
            assert!(scale > 0.0, "column {c} is zero");
            worst = worst.max(err / scale);
        }
        worst
    }

    /// What an accelerometer reads along a flight, from its recorded (noisy) states: values
    /// the size and shape of a real one's.
    fn accelerometer(truth: &Model, d: &wireflight_data::FlightData) -> Vec<DVec3> {
        (0..d.len())
            .map(|i| {
                let mut x = State::default();
                let att = d.attitude.as_ref().unwrap()[i];
                x.set_pos_ned(d.pos_ned[i]);
                x.set_attitude(att);
                x.set_vel(att.to_matrix().transpose() * d.vel_ned.as_ref().unwrap()[i]);
                x.set_omega(d.rates_body.as_ref().unwrap()[i]);
                truth.specific_force(d.time[i], &x, &controls_at(d, i))
            })
            .collect()
    }

    /// On flight tests with every channel measured (airspeed and the accelerometer included), under an autopilot
    /// and through control steps, with wind, actuator lag and effects that vary with height,
    /// the tangent-linear Jacobian is the forward-difference one to within 2% of each
    /// column's largest entry (measured: 1.5e-2 at worst, at 50 Hz through a control step,
    /// at the sample between two steps of a pair; 4.6e-3 at 20 Hz, 2.6e-3 at 100 Hz; a sign
    /// error in any read-out or kinematic term gives 0.09 or more).
    #[test]
    fn tangent_jacobian_matches_differences() {
        for (kind, truth_effects, model_effects, rate, accel) in [
            (VehicleKind::FixedWing, vec![], vec![], 50.0, false),
            (
                VehicleKind::FixedWing,
                vec!["wind:north_mps=4,east_mps=-3"],
                vec!["wind:north_mps=4,east_mps=-3", "actuator_lag:tau_s=0.12"],
                100.0,
                true,
            ),
            (
                VehicleKind::FixedWing,
                vec![],
                vec!["gyroscopic", "density_altitude", "ground_effect"],
                20.0,
                true,
            ),
            (
                VehicleKind::PointMass,
                vec!["drag"],
                vec!["drag"],
                50.0,
                false,
            ),
            (
                VehicleKind::PointMass,
                vec!["drag"],
                vec!["drag", "nav_delay:delay_s=0.3"],
                50.0,
                false,
            ),
            // What the sensors read: a late navigation solution, biased gyros, a scaled and
            // offset airspeed, a misaligned attitude reference, a biased accelerometer.
            (
                VehicleKind::FixedWing,
                vec![],
                vec![
                    "nav_delay:delay_s=0.23",
                    "gyro_bias:p_dps=0.5,r_dps=-0.3",
                    "airspeed_scale:factor=0.93",
                    "airspeed_bias:bias_mps=0.8",
                    "attitude_offset:roll_deg=4,pitch_deg=-3",
                    "accel_bias:x_mps2=0.2",
                ],
                50.0,
                true,
            ),
        ] {
            let truth = model(kind, &truth_effects);
            let spec = SimSpec {
                rate_hz: rate,
                noise: Noise {
                    pos_m: 0.05,
                    att_deg: 0.05,
                    vel_mps: 0.05,
                    rate_dps: 0.2,
                },
                ..SimSpec::new(
                    match kind {
                        VehicleKind::FixedWing => Manoeuvre::FlightTest,
                        VehicleKind::PointMass => Manoeuvre::Ballistic,
                    },
                    30.0,
                )
            };
            let mut data = simulate(&truth, &spec).unwrap();
            if accel {
                data.accel_body = Some(accelerometer(&truth, &data));
            }
            let prep = Prepared::new(&data, CompareConfig::default());
            let m = model(kind, &model_effects);
            for &w in prep.windows.iter().take(3) {
                for offset in [0.0, 3.0] {
                    let err = worst_column_error(&m, &prep, w, offset);
                    assert!(err < 2e-2, "{kind:?} {model_effects:?} {w:?}: {err:e}");
                }
            }
        }
    }

    /// A gust that varies in time only: its effect does not say it is steady.
    #[derive(Clone, Debug)]
    struct Gust;

    static GUST: wireflight_flight::effects::EffectInfo = wireflight_flight::effects::EffectInfo {
        name: "test_gust",
        summary: "a 3 m/s gust from the east, every 2 s",
        applies: wireflight_flight::effects::Applies::FixedWing,
        params: &[],
        make: |_| Box::new(Gust),
    };

    impl wireflight_flight::effects::Effect for Gust {
        fn info(&self) -> &'static wireflight_flight::effects::EffectInfo {
            &GUST
        }
        fn wind_at(&self, _pos_ned: DVec3, t: f64) -> DVec3 {
            DVec3::new(0.0, -3.0 * (std::f64::consts::PI * t).sin(), 0.0)
        }
    }

    /// The model Jacobian is held only while the state, the commands and the surfaces stay
    /// within the hold's bounds of where it was taken, only for equations that depend
    /// neither on position nor on time, and never before one was taken.
    #[test]
    fn the_jacobian_is_held_only_in_steady_flight_of_time_free_equations() {
        use wireflight_flight::trim::trim_level;
        let m = model(VehicleKind::FixedWing, &[]);
        let trim = trim_level(&m, 25.0, 0.0, DVec3::new(0.0, 0.0, -200.0)).unwrap();
        let (x0, c0) = (trim.state, trim.controls);
        let mut hold = Hold::new(&m);
        assert!(!hold.keeps(3, &x0, &c0), "nothing taken yet");
        hold.taken(&x0, &c0);
        assert!(hold.keeps(3, &x0, &c0));
        assert!(
            !hold.keeps(2, &x0, &c0),
            "equations that depend on position"
        );
        let moved = |f: &dyn Fn(&mut State)| {
            let mut x = x0;
            f(&mut x);
            x
        };
        let near = 0.5;
        let far = 2.0;
        for (what, scale) in [("near", near), ("far", far)] {
            let cases = [
                moved(&|x: &mut State| x.set_vel(x.vel() + DVec3::X * scale * HOLD_VELOCITY)),
                moved(&|x: &mut State| x.set_omega(x.omega() + DVec3::Y * scale * HOLD_RATE)),
                moved(&|x: &mut State| {
                    let turned = m.perturbed(x, &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, scale * HOLD_TURN]);
                    *x = turned;
                }),
                moved(&|x: &mut State| {
                    x.set_surfaces(x.surfaces() + DVec3::Z * scale * HOLD_COMMAND)
                }),
            ];
            for (k, x) in cases.iter().enumerate() {
                assert_eq!(hold.keeps(3, x, &c0), what == "near", "{what} case {k}");
            }
            let mut c = c0;
            c.elevator += scale * HOLD_COMMAND;
            assert_eq!(hold.keeps(3, &x0, &c), what == "near", "{what} command");
        }
        let mut gusty = m.clone();
        gusty.add_effect(Box::new(Gust)).unwrap();
        let mut timed = Hold::new(&gusty);
        timed.taken(&x0, &c0);
        assert!(!timed.keeps(3, &x0, &c0), "equations that depend on time");
        // Only the effect that reads the flight's recorded attitude at the time does.
        for effect in wireflight_flight::effects::CATALOGUE {
            let e = effect.build(&m.effect_context());
            let reads_the_record = e.name() == "incidence_lift";
            assert_eq!(e.varies_in_time(), reads_the_record, "{}", e.name());
        }
    }

    /// Where the Jacobian is held (a level leg) and with a wind that changes in time, the
    /// tangent stays on the forward differences as it does through manoeuvres (measured:
    /// 8.1e-4 on the level leg, 8.7e-4 in the gusts, 8.0e-3 through the flight test at
    /// 100 Hz).
    #[test]
    fn a_held_jacobian_keeps_the_tangent_on_the_differences() {
        let level = model(VehicleKind::FixedWing, &[]);
        let mut gusty = level.clone();
        gusty.add_effect(Box::new(Gust)).unwrap();
        for (m, manoeuvre) in [
            (&level, Manoeuvre::Level),
            (&gusty, Manoeuvre::Level),
            (&level, Manoeuvre::FlightTest),
        ] {
            let spec = SimSpec {
                rate_hz: 100.0,
                noise: Noise::default(),
                ..SimSpec::new(manoeuvre, 20.0)
            };
            let data = simulate(m, &spec).unwrap();
            let prep = Prepared::new(&data, CompareConfig::default());
            for &w in prep.windows.iter().take(2) {
                let err = worst_column_error(m, &prep, w, 0.0);
                assert!(
                    err < 2e-2,
                    "{manoeuvre:?} {:?} {w:?}: {err:e}",
                    m.effect_names()
                );
            }
        }
    }
}
