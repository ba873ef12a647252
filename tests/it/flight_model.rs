//! Physics checks of the flight model: closed-form motion, conservation, trim, kinematics.

use glam::DVec3;

use wireflight::data::{Controls, VehicleKind, G0};
use wireflight::flight::effects::{
    catalogue_effect, isa_density, ActuatorLag, DensityAltitude, Drag, EarthRotation,
    EffectContext, GravityModel, Origin, Wind, CATALOGUE,
};
use wireflight::flight::model::{HeldCommands, Model, State, Vehicle};
use wireflight::flight::params::FixedWingParams;
use wireflight::flight::trim::trim_level;
use wireflight::geometry::euler::EulerZyx;

fn point_mass() -> Model {
    Model::new(Vehicle::PointMass, Origin::default())
}

fn aerosonde() -> Model {
    Model::new(
        Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
        Origin::default(),
    )
}

fn launch(v: DVec3) -> State {
    let mut x = State::default();
    x.set_vel(v);
    x
}

#[test]
fn point_mass_gravity_only_matches_the_parabola_and_conserves_energy() {
    let m = point_mass();
    let v0 = DVec3::new(80.0, -20.0, -60.0);
    let x0 = launch(v0);
    let energy = |x: &State| 0.5 * x.vel().length_squared() - G0 * x.pos_ned().z;
    let e0 = energy(&x0);
    let mut x = x0;
    let dt = 0.01;
    for k in 0..2000 {
        x = m.step(k as f64 * dt, &x, &Controls::default(), dt);
        let rel = (energy(&x) - e0).abs() / e0;
        assert!(rel < 1e-12, "energy drift {rel:e} at step {k}");
    }
    // RK4 is exact for this quadratic motion.
    let t = 20.0;
    let expected = v0 * t + DVec3::new(0.0, 0.0, 0.5 * G0 * t * t);
    assert!(
        (x.pos_ned() - expected).length() < 1e-8,
        "{} vs {expected}",
        x.pos_ned()
    );
}

#[test]
fn drag_reaches_terminal_velocity_sqrt_g_over_k() {
    let mut m = point_mass();
    m.add_effect(Box::new(Drag { k: 0.004 })).unwrap();
    let x = m.advance(0.0, &launch(DVec3::ZERO), &Controls::default(), 60.0, 0.01);
    let terminal = (G0 / 0.004).sqrt();
    assert!(
        (x.vel().z - terminal).abs() < 1e-6,
        "{} vs {terminal}",
        x.vel().z
    );
}

#[test]
fn wind_only_matters_for_a_point_mass_with_drag() {
    let x0 = launch(DVec3::new(50.0, 0.0, -30.0));
    let run = |m: &Model| m.advance(0.0, &x0, &Controls::default(), 5.0, 0.01);
    let mut with_wind = point_mass();
    with_wind
        .add_effect(Box::new(Wind {
            ned: DVec3::new(0.0, 10.0, 0.0),
        }))
        .unwrap();
    assert_eq!(run(&with_wind), run(&point_mass()));
    with_wind.add_effect(Box::new(Drag { k: 0.002 })).unwrap();
    let drifted = run(&with_wind);
    assert!(
        drifted.pos_ned().y > 0.5,
        "drag in an east wind drifts east: {}",
        drifted.pos_ned()
    );
}

#[test]
fn density_altitude_scales_drag_by_isa_ratio() {
    let mut m = point_mass();
    m.origin.altitude_m = 1000.0;
    m.add_effect(Box::new(Drag { k: 0.01 })).unwrap();
    m.add_effect(Box::new(DensityAltitude)).unwrap();
    let x = launch(DVec3::new(10.0, 0.0, 0.0));
    let d = m.derivative(0.0, &x, &Controls::default());
    let expected = -0.01 * isa_density(1000.0) / 1.225 * 100.0;
    assert!(
        (d.0[3] - expected).abs() < 1e-12,
        "{} vs {expected}",
        d.0[3]
    );
}

#[test]
fn gravity_model_and_coriolis_enter_the_point_mass_equations() {
    let mut m = point_mass();
    m.add_effect(Box::new(GravityModel { latitude_deg: 0.0 }))
        .unwrap();
    let d = m.derivative(0.0, &State::default(), &Controls::default());
    assert!((d.0[5] - 9.7803).abs() < 5e-5, "{}", d.0[5]);
    m.add_effect(Box::new(EarthRotation { latitude_deg: 45.0 }))
        .unwrap();
    let d = m.derivative(
        0.0,
        &launch(DVec3::new(100.0, 0.0, 0.0)),
        &Controls::default(),
    );
    assert!(
        d.0[4] > 0.0103 && d.0[4] < 0.0104,
        "eastward Coriolis {}",
        d.0[4]
    );
}

#[test]
fn effects_are_rejected_on_the_wrong_vehicle_and_twice() {
    let mut pm = point_mass();
    let mut fw = aerosonde();
    let ctx = EffectContext {
        origin: Origin::default(),
        span_m: 2.9,
        chord_m: 0.0,
        ..EffectContext::default()
    };
    for info in CATALOGUE {
        let name = info.name;
        let e = catalogue_effect(name, &ctx).unwrap();
        // Without a recorded attitude, an effect that acts from one is refused too.
        let for_pm = e.applies_to(VehicleKind::PointMass) && e.lacks_channel().is_none();
        assert_eq!(pm.add_effect(e.clone()).is_ok(), for_pm, "{name}");
        assert_eq!(
            fw.add_effect(e.clone()).is_ok(),
            e.applies_to(VehicleKind::FixedWing),
            "{name}"
        );
    }
    assert!(
        pm.add_effect(Box::new(Wind::default())).is_err(),
        "duplicate"
    );
    assert!(!fw.has_effect("drag") && pm.has_effect("drag"));
    let blind = catalogue_effect("incidence_lift", &ctx).unwrap();
    let refused = pm.add_effect(blind).unwrap_err().to_string();
    assert!(
        refused.contains("incidence_lift") && refused.contains("attitude (roll, pitch, yaw)"),
        "{refused}"
    );
}

/// The spec's tolerance for "trimmed level flight stays level for 60 s": the open-loop
/// aircraft, started at the trim point, keeps its height within 0.5 m, airspeed within
/// 0.05 m/s and attitude within 0.1°.
#[test]
fn trimmed_aerosonde_flies_level_for_60_s() {
    let m = aerosonde();
    let trim = trim_level(&m, 25.0, 0.5, DVec3::new(0.0, 0.0, -200.0)).unwrap();
    let e0 = trim.state.attitude();
    let mut x = trim.state;
    let dt = 0.01;
    for k in 0..6000 {
        x = m.step(k as f64 * dt, &x, &trim.controls, dt);
    }
    let e = x.attitude();
    assert!(
        (x.pos_ned().z + 200.0).abs() < 0.5,
        "height {}",
        -x.pos_ned().z
    );
    assert!((m.air_data(0.0, &x).airspeed - 25.0).abs() < 0.05);
    for (a, b) in [(e.yaw, e0.yaw), (e.pitch, e0.pitch), (e.roll, e0.roll)] {
        assert!((a - b).abs().to_degrees() < 0.1, "{e:?} vs {e0:?}");
    }
    // It went 1500 m along its heading.
    let travelled = x.pos_ned() - trim.state.pos_ned();
    assert!((travelled.length() - 1500.0).abs() < 1.0, "{travelled}");
}

/// The quaternion attitude reports the same z-y-x angles as integrating the spec's Euler-rate
/// equations: φ̇ = p + (q sinφ + r cosφ) tanθ, θ̇ = q cosφ − r sinφ, ψ̇ = (q sinφ + r cosφ)/cosθ.
#[test]
fn quaternion_attitude_follows_the_euler_rate_equations() {
    let m = aerosonde();
    let trim = trim_level(&m, 25.0, 0.0, DVec3::new(0.0, 0.0, -300.0)).unwrap();
    let mut x = trim.state;
    x.set_omega(DVec3::new(0.3, 0.1, -0.2));
    x.set_attitude(EulerZyx::new(0.4, 0.3, -0.5));
    let cmd = trim.controls;
    let dt = 1e-4;
    let e0 = x.attitude();
    let d = m.derivative(0.0, &x, &cmd);
    let x1 = m.step(0.0, &x, &cmd, dt);
    let e1 = x1.attitude();
    let w = x.omega();
    let (sphi, cphi) = e0.roll.sin_cos();
    let (p, q, r) = (w.x, w.y, w.z);
    // Rates change during the step; use the mid-step rates for the comparison.
    let (pm, qm, rm) = (
        p + 0.5 * dt * d.0[10],
        q + 0.5 * dt * d.0[11],
        r + 0.5 * dt * d.0[12],
    );
    let phi_dot = pm + (qm * sphi + rm * cphi) * e0.pitch.tan();
    let theta_dot = qm * cphi - rm * sphi;
    let psi_dot = (qm * sphi + rm * cphi) / e0.pitch.cos();
    let tol = 2e-3; // rad/s: the first-order difference over dt
    assert!(((e1.roll - e0.roll) / dt - phi_dot).abs() < tol);
    assert!(((e1.pitch - e0.pitch) / dt - theta_dot).abs() < tol);
    assert!(((e1.yaw - e0.yaw) / dt - psi_dot).abs() < tol);
}

#[test]
fn gravity_in_body_axes_matches_the_spec_formula() {
    // m·g0·(−sinθ, cosθ sinφ, cosθ cosφ): check through a zero-airspeed, zero-throttle state
    // where gravity is the only force.
    let m = aerosonde();
    let mut x = State::default();
    let e = EulerZyx::new(0.7, 0.4, -0.3);
    x.set_attitude(e);
    let d = m.derivative(0.0, &x, &Controls::default());
    let g = G0
        * DVec3::new(
            -e.pitch.sin(),
            e.pitch.cos() * e.roll.sin(),
            e.pitch.cos() * e.roll.cos(),
        );
    // At zero airspeed the propeller still pulls back nothing (δt = 0, Va = 0): f = m g.
    assert!((DVec3::new(d.0[3], d.0[4], d.0[5]) - g).length() < 1e-12);
}

/// Commands an autopilot might send at `rate_hz`: smooth sweeps on every channel, with a step
/// of the aileron and the throttle at 0.5 s.
fn busy_commands(trim: &Controls, rate_hz: f64, samples: usize) -> Vec<Controls> {
    (0..samples)
        .map(|k| {
            let t = k as f64 / rate_hz;
            let step = if t >= 0.5 { 1.0 } else { 0.0 };
            Controls {
                throttle: (trim.throttle + 0.1 * (7.0 * t).sin() - 0.15 * step).clamp(0.0, 1.0),
                elevator: trim.elevator + 0.05 * (5.0 * t).sin(),
                aileron: trim.aileron + 0.08 * (9.0 * t).cos() + 0.1 * step,
                rudder: trim.rudder - 0.04 * (3.0 * t).sin(),
            }
        })
        .collect()
}

/// Largest difference of two states in the numbers a comparison reads: position m, body
/// velocity m/s, body rates rad/s (quaternion components, dimensionless, ×10).
fn state_gap(a: &State, b: &State) -> f64 {
    let q = (a.quat() - b.quat())
        .length()
        .min((a.quat() + b.quat()).length());
    (a.pos_ned() - b.pos_ned())
        .length()
        .max((a.vel() - b.vel()).length())
        .max((a.omega() - b.omega()).length())
        .max(10.0 * q)
}

/// Over 1.5 s of busy commands from trim: the largest state error at every sample, against a
/// 0.1 ms integration of the same zero-order hold, of RK4 steps `per_step` samples long
/// (`Model::step_held`, samples inside a step read by `Rk4Step::at`), and of steps of that
/// length that hold their first command (the switches inside ignored).
fn held_step_errors(
    m: &Model,
    trim: &Controls,
    x0: &State,
    rate_hz: f64,
    per_step: usize,
) -> (f64, f64) {
    let samples = (1.5 * rate_hz) as usize + 1;
    let time: Vec<f64> = (0..samples).map(|k| k as f64 / rate_hz).collect();
    let cmds = busy_commands(trim, rate_hz, samples);
    let mut truth = vec![*x0];
    for k in 0..samples - 1 {
        let x = m.advance(time[k], &truth[k], &cmds[k], time[k + 1], 1e-4);
        truth.push(x);
    }
    let (mut worst, mut worst_naive) = (0.0f64, 0.0f64);
    let (mut x, mut naive) = (*x0, *x0);
    let mut i = 0;
    while i + per_step < samples {
        let j = i + per_step;
        let held = HeldCommands {
            times: &time[i..=j],
            controls: Some(&cmds[i..j]),
        };
        let step = m.step_held(&x, &held);
        for k in i + 1..j {
            let inside = step.at(m, &held, time[k] - time[i]);
            worst = worst.max(state_gap(&inside, &truth[k]));
        }
        x = step.end;
        naive = m.step(time[i], &naive, &cmds[i], time[j] - time[i]);
        worst = worst.max(state_gap(&x, &truth[j]));
        worst_naive = worst_naive.max(state_gap(&naive, &truth[j]));
        i = j;
    }
    (worst, worst_naive)
}

/// One 20 ms RK4 step across several samples (data faster than the integration step) is as
/// accurate as a 20 ms step over one sample: at 100 and 200 Hz, with commands that change at
/// every sample, its states at and between the step's ends stay within twice the error of
/// 20 ms steps on 50 Hz commands (RK4's own error on the fast roll mode, ~1e-4), and below a
/// twentieth of what steps that ignore the switches give.
#[test]
fn one_step_across_several_samples_follows_the_held_commands() {
    let m = aerosonde();
    let trim = trim_level(&m, 25.0, 0.0, DVec3::new(0.0, 0.0, -200.0)).unwrap();
    let (rk4, _) = held_step_errors(&m, &trim.controls, &trim.state, 50.0, 1);
    for (rate_hz, per_step) in [(100.0, 2usize), (200.0, 4)] {
        let (worst, naive) = held_step_errors(&m, &trim.controls, &trim.state, rate_hz, per_step);
        eprintln!(
            "{rate_hz} Hz: {worst:e}; 20 ms RK4 at 50 Hz {rk4:e}; first command held {naive:e}"
        );
        assert!(worst < 2.0 * rk4, "{rate_hz} Hz: {worst:e} vs {rk4:e}");
        assert!(worst < 0.05 * naive, "{worst:e} vs {naive:e}");
    }
}

/// Constant commands over a step across samples give the ordinary RK4 step; under actuator
/// lag the surfaces inside and at the end of the step are the exact response to the held
/// commands.
#[test]
fn a_step_across_samples_is_rk4_for_constant_commands_and_exact_for_surfaces() {
    let mut m = aerosonde();
    let trim = trim_level(&m, 25.0, 0.0, DVec3::new(0.0, 0.0, -200.0)).unwrap();
    let time = [0.0, 0.01, 0.02];
    let same = [trim.controls; 2];
    let held = HeldCommands {
        times: &time,
        controls: Some(&same),
    };
    let plain = m.step(0.0, &trim.state, &trim.controls, 0.02);
    let across = m.step_held(&trim.state, &held).end;
    assert!(
        state_gap(&plain, &across) < 1e-12,
        "{plain:?} vs {across:?}"
    );

    let tau = 0.05;
    m.add_effect(Box::new(ActuatorLag { tau_s: tau })).unwrap();
    let time = [0.0, 0.005, 0.01, 0.015, 0.02];
    let cmds = busy_commands(&trim.controls, 200.0, 4);
    let mut x0 = trim.state;
    x0.set_surfaces(DVec3::new(0.02, -0.03, 0.01));
    let held = HeldCommands {
        times: &time,
        controls: Some(&cmds),
    };
    let step = m.step_held(&x0, &held);
    let mut s = x0.surfaces();
    for k in 0..4 {
        let c = DVec3::new(cmds[k].elevator, cmds[k].aileron, cmds[k].rudder);
        s = c + (s - c) * (-(time[k + 1] - time[k]) / tau).exp();
        let got = if k == 3 {
            step.end.surfaces()
        } else {
            step.at(&m, &held, time[k + 1]).surfaces()
        };
        assert!((got - s).length() < 1e-14, "sample {}: {got} vs {s}", k + 1);
    }
}

/// A sample interval a rounding error longer than the longest step is one step: the time
/// stamps of 50 Hz data are not exact multiples of 0.02 s (i·0.02 differs from its
/// neighbour by 0.02 ± a few ulp), and each such interval used to cost two RK4 steps of
/// 10 ms instead of one of 20 ms. Longer intervals still split into equal steps no longer
/// than `max_dt`.
#[test]
fn a_sample_interval_a_rounding_error_over_the_step_is_one_step() {
    let max_dt = 0.02;
    let mut two_step_intervals = 0;
    for i in 0..100_000 {
        let (t0, t1) = (i as f64 * 0.02, (i + 1) as f64 * 0.02);
        let (n, h) = Model::substeps(t1 - t0, max_dt);
        if n != 1 {
            two_step_intervals += 1;
        }
        assert!((h - 0.02).abs() < 1e-9, "{i}: {h}");
    }
    assert_eq!(
        two_step_intervals, 0,
        "50 Hz time stamps split into two steps"
    );
    assert_eq!(Model::substeps(0.03, max_dt), (2, 0.015));
    assert_eq!(Model::substeps(0.04, max_dt), (2, 0.02));
    let (n, h) = Model::substeps(0.0400001, max_dt);
    assert_eq!(n, 3);
    assert!(h <= max_dt);
    assert_eq!(Model::substeps(0.0, max_dt).0, 0);
    assert_eq!(Model::substeps(f64::NAN, max_dt).0, 0);
}
