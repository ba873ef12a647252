//! refsim's manoeuvre schedules and autopilot.

use super::*;

/// Autopilot target step: from `t_s` on, bank `bank_deg` and pitch `pitch_deg` above trim θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetStep {
    pub t_s: f64,
    pub bank_deg: f64,
    pub pitch_deg: f64,
}

/// Open-loop doublet: +amplitude on [start, start+width), −amplitude on [start+width, start+2·width).
/// Amplitude in degrees for surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Doublet {
    pub start_s: f64,
    pub width_s: f64,
    pub amplitude: f64,
}

impl Doublet {
    pub fn new(start_s: f64, width_s: f64, amplitude: f64) -> Self {
        Doublet {
            start_s,
            width_s,
            amplitude,
        }
    }
    pub fn value(&self, t: f64) -> f64 {
        let t = t + TIME_EPS;
        if t >= self.start_s && t < self.start_s + self.width_s {
            self.amplitude
        } else if t >= self.start_s + self.width_s && t < self.start_s + 2.0 * self.width_s {
            -self.amplitude
        } else {
            0.0
        }
    }
}

/// A manoeuvre schedule. All times are flight time (trim at t = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    pub name: String,
    pub duration_s: f64,
    /// Closed loop (autopilot) or open loop from the trim commands.
    pub autopilot: bool,
    /// Bank / pitch target steps (autopilot only). Before the first step: 0, 0.
    pub targets: Vec<TargetStep>,
    /// (t, airspeed above trim m/s) from t on (autopilot only).
    pub airspeed_steps: Vec<(f64, f64)>,
    pub elevator_doublets: Vec<Doublet>,
    pub aileron_doublets: Vec<Doublet>,
    pub rudder_doublets: Vec<Doublet>,
    /// (t, throttle offset) added to the throttle from t on (latest entry wins; before: 0).
    pub throttle_steps: Vec<(f64, f64)>,
}

/// Schedule times are compared with this tolerance, so a change at time T takes effect at the
/// sample whose time is T even when k/rate and T round differently.
pub const TIME_EPS: f64 = 1e-9;

fn latest<T: Copy>(items: &[(f64, T)], t: f64, default: T) -> T {
    let mut out = default;
    let mut best = f64::NEG_INFINITY;
    for &(ti, v) in items {
        if ti <= t + TIME_EPS && ti >= best {
            best = ti;
            out = v;
        }
    }
    out
}

impl Schedule {
    /// Trim held, autopilot on, nothing else.
    pub fn level(duration_s: f64) -> Self {
        Schedule {
            name: "level".into(),
            duration_s,
            autopilot: true,
            targets: vec![],
            airspeed_steps: vec![],
            elevator_doublets: vec![],
            aileron_doublets: vec![],
            rudder_doublets: vec![],
            throttle_steps: vec![],
        }
    }

    /// Trim commands held open loop.
    pub fn trim_hold(duration_s: f64) -> Self {
        Schedule {
            name: "trim_hold".into(),
            autopilot: false,
            ..Schedule::level(duration_s)
        }
    }

    /// Bank/pitch steps at t = 8, 18, 24, 34, 36, 41 s, 45 s long.
    pub fn steps_8_18_24_34_36_41() -> Self {
        let st = |t_s, bank_deg, pitch_deg| TargetStep {
            t_s,
            bank_deg,
            pitch_deg,
        };
        Schedule {
            name: "steps_8_18_24_34_36_41".into(),
            targets: vec![
                st(8.0, 25.0, 0.0),
                st(18.0, 0.0, 4.0),
                st(24.0, -25.0, 4.0),
                st(34.0, 0.0, 0.0),
                st(36.0, 0.0, 5.0),
                st(41.0, 0.0, -2.0),
            ],
            ..Schedule::level(45.0)
        }
    }

    /// Flight test, 60 s: right and left turns, a climb, doublets on every surface, throttle steps.
    pub fn flight_test() -> Self {
        let st = |t_s, bank_deg, pitch_deg| TargetStep {
            t_s,
            bank_deg,
            pitch_deg,
        };
        Schedule {
            name: "flight_test".into(),
            targets: vec![
                st(3.0, 30.0, 0.0),
                st(11.0, 0.0, 0.0),
                st(16.0, -30.0, 0.0),
                st(24.0, 0.0, 0.0),
                st(27.0, 0.0, 6.0),
                st(35.0, 0.0, 0.0),
            ],
            airspeed_steps: vec![(50.0, 3.0), (56.0, 0.0)],
            elevator_doublets: vec![Doublet::new(38.0, 0.6, 3.0)],
            aileron_doublets: vec![Doublet::new(41.0, 0.6, 4.0)],
            rudder_doublets: vec![Doublet::new(44.0, 0.6, 5.0)],
            throttle_steps: vec![(47.0, 0.15), (52.0, -0.1), (57.0, 0.0)],
            ..Schedule::level(60.0)
        }
    }

    /// Open loop from trim, 20 s: doublets on elevator, aileron, rudder and a throttle step.
    pub fn open_loop_doublets() -> Self {
        Schedule {
            name: "open_loop_doublets".into(),
            autopilot: false,
            elevator_doublets: vec![Doublet::new(2.0, 0.5, 3.0)],
            aileron_doublets: vec![Doublet::new(5.0, 0.5, 3.0)],
            rudder_doublets: vec![Doublet::new(8.0, 0.5, 4.0)],
            throttle_steps: vec![(11.0, 0.05), (13.0, 0.0)],
            ..Schedule::level(20.0)
        }
    }

    /// Open loop, 12 windows of `period_s`; every control change falls on a multiple of
    /// `period_s` (window k = [kP, (k+1)P)): aileron ±0.5° in windows 1–2, elevator ±1° in 3–4,
    /// rudder ±1° in 5–6, throttle +0.03 / −0.03 in 7 / 8, aileron ∓0.5° with elevator ∓0.5° in 9–10.
    pub fn window_steps(period_s: f64) -> Self {
        let p = period_s;
        Schedule {
            name: format!("window_steps_{p}"),
            autopilot: false,
            aileron_doublets: vec![Doublet::new(p, p, 0.5), Doublet::new(9.0 * p, p, -0.5)],
            elevator_doublets: vec![
                Doublet::new(3.0 * p, p, 1.0),
                Doublet::new(9.0 * p, p, -0.5),
            ],
            rudder_doublets: vec![Doublet::new(5.0 * p, p, 1.0)],
            throttle_steps: vec![(7.0 * p, 0.03), (8.0 * p, -0.03), (9.0 * p, 0.0)],
            ..Schedule::level(12.0 * p)
        }
    }

    /// Preset by name: `steps_8_18_24_34_36_41`, `flight_test`, `open_loop_doublets`,
    /// `window_steps_<period>` (e.g. `window_steps_4`), `level_<duration>`, `trim_hold_<duration>`.
    pub fn preset(name: &str) -> Option<Schedule> {
        match name {
            "steps_8_18_24_34_36_41" => Some(Schedule::steps_8_18_24_34_36_41()),
            "flight_test" => Some(Schedule::flight_test()),
            "open_loop_doublets" => Some(Schedule::open_loop_doublets()),
            _ => {
                let num = |prefix: &str| -> Option<f64> {
                    name.strip_prefix(prefix)?
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite() && *v > 0.0)
                };
                if let Some(p) = num("window_steps_") {
                    Some(Schedule::window_steps(p))
                } else if let Some(d) = num("level_") {
                    Some(Schedule::level(d))
                } else {
                    num("trim_hold_").map(Schedule::trim_hold)
                }
            }
        }
    }

    /// Every time at which the schedule changes something.
    pub fn change_times(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.targets.iter().map(|s| s.t_s).collect();
        v.extend(self.airspeed_steps.iter().map(|s| s.0));
        v.extend(self.throttle_steps.iter().map(|s| s.0));
        for d in self
            .elevator_doublets
            .iter()
            .chain(&self.aileron_doublets)
            .chain(&self.rudder_doublets)
        {
            v.extend([
                d.start_s,
                d.start_s + d.width_s,
                d.start_s + 2.0 * d.width_s,
            ]);
        }
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// (bank rad, pitch above trim rad) at t.
    pub fn target(&self, t: f64) -> (f64, f64) {
        let items: Vec<(f64, (f64, f64))> = self
            .targets
            .iter()
            .map(|s| (s.t_s, (s.bank_deg * DEG, s.pitch_deg * DEG)))
            .collect();
        latest(&items, t, (0.0, 0.0))
    }

    /// Open-loop offsets at t: (δe, δa, δr in rad, throttle).
    pub fn offsets(&self, t: f64) -> (f64, f64, f64, f64) {
        let s = |ds: &[Doublet]| ds.iter().map(|d| d.value(t)).sum::<f64>() * DEG;
        (
            s(&self.elevator_doublets),
            s(&self.aileron_doublets),
            s(&self.rudder_doublets),
            latest(&self.throttle_steps, t, 0.0),
        )
    }
}

/// Rudder law of the autopilot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RudderMode {
    /// δr = δr_trim − k_beta·β.
    Beta,
    /// δr = δr_trim − k_r·(r_c − r), r_c = g·sinφ·cosθ/Va (coordinated-turn yaw rate).
    YawRate,
}

/// Autopilot gains (surfaces in rad, angles in rad, rates in rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains {
    pub k_phi: f64,
    pub k_phi_i: f64,
    pub k_p: f64,
    pub k_theta: f64,
    pub k_q: f64,
    pub k_theta_i: f64,
    pub k_v: f64,
    pub k_v_i: f64,
    pub k_beta: f64,
    pub k_r: f64,
    pub rudder_mode: RudderMode,
    /// Surface command limit, deg.
    pub max_surface_deg: f64,
}

impl Default for Gains {
    fn default() -> Self {
        Gains {
            k_phi: 0.6,
            k_phi_i: 0.2,
            k_p: 0.03,
            k_theta: 2.5,
            k_q: 0.2,
            k_theta_i: 0.5,
            k_v: 0.05,
            k_v_i: 0.02,
            k_beta: 1.0,
            k_r: 0.5,
            rudder_mode: RudderMode::Beta,
            max_surface_deg: 30.0,
        }
    }
}

/// Autopilot integrator states.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ApState {
    pub i_phi: f64,
    pub i_theta: f64,
    pub i_v: f64,
}

/// Command for flight time `t` given the true state and the wind (NED, m/s) it flies in now:
/// autopilot (if on) + open-loop offsets. The autopilot holds the airspeed and β of the air
/// it is in, gusts included, as its air-data sensors would read them. `dt` is the sample
/// period (integrators advance by one sample per call).
#[allow(clippy::too_many_arguments)]
pub fn command_at(
    model: &FwModel,
    sched: &Schedule,
    gains: &Gains,
    tr: &Trim,
    ap: &mut ApState,
    t: f64,
    x: &FwState,
    wind: V3,
    dt: f64,
) -> Controls {
    let mut c = tr.controls;
    if sched.autopilot {
        let (va, _alpha, beta) = air_data_in(x, wind);
        let (bank_c, pitch_c) = sched.target(t);
        let theta_c = tr.theta + pitch_c;
        let va_c = tr.airspeed + latest(&sched.airspeed_steps, t, 0.0);
        let (phi, theta) = (x[ix::PHI], x[ix::THETA]);
        let (p, q, r) = (x[ix::P], x[ix::Q], x[ix::R]);
        let g = model.env.g(x[ix::D]);
        let e_phi = bank_c - phi;
        // Conditional integration (only near the target) against wind-up during bank steps.
        if e_phi.abs() < 5.0 * DEG {
            ap.i_phi = (ap.i_phi + e_phi * dt).clamp(-0.5, 0.5);
        }
        c.aileron += gains.k_phi * e_phi + gains.k_phi_i * ap.i_phi - gains.k_p * p;
        let e_th = theta_c - theta;
        ap.i_theta = (ap.i_theta + e_th * dt).clamp(-0.5, 0.5);
        // q damping relative to the pitch rate of a steady coordinated turn, g·tanφ·sinφ·cosθ/Va.
        let q_turn = if va > 1.0 {
            g * phi.tan() * phi.sin() * theta.cos() / va
        } else {
            0.0
        };
        c.elevator +=
            -(gains.k_theta * e_th + gains.k_theta_i * ap.i_theta) + gains.k_q * (q - q_turn);
        let e_v = va_c - va;
        ap.i_v = (ap.i_v + e_v * dt).clamp(-20.0, 20.0);
        c.throttle += gains.k_v * e_v + gains.k_v_i * ap.i_v;
        match gains.rudder_mode {
            RudderMode::Beta => c.rudder += -gains.k_beta * beta,
            RudderMode::YawRate => {
                let r_c = if va > 1.0 {
                    g * phi.sin() * theta.cos() / va
                } else {
                    0.0
                };
                c.rudder += -gains.k_r * (r_c - r);
            }
        }
    }
    let (de, da, dr, dth) = sched.offsets(t);
    c.elevator += de;
    c.aileron += da;
    c.rudder += dr;
    c.throttle += dth;
    let lim = gains.max_surface_deg * DEG;
    c.elevator = c.elevator.clamp(-lim, lim);
    c.aileron = c.aileron.clamp(-lim, lim);
    c.rudder = c.rudder.clamp(-lim, lim);
    c.throttle = c.throttle.clamp(0.0, 1.0);
    c
}
