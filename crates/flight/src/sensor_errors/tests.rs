//! Tests of the sensor errors: the statistics of the generators measured back, the
//! kinematics of the navigation-filter model, determinism, and the file and record formats.
//! Every test runs the generators alone on a synthetic flight (not the aircraft simulator).

use glam::{DMat3, DQuat};

use super::*;
use wireflight_data::{Metadata, G0};

// ---------------------------------------------------------------------------------------------
// Helpers

/// Level flight at 25 m/s, heading 0.3 rad, 0.05 rad nose up, every channel present.
fn level(n: usize, dt: f64) -> FlightData {
    let time: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let pos = time
        .iter()
        .map(|&t| DVec3::new(25.0 * t, 0.0, -100.0))
        .collect();
    let mut d = FlightData::new(Metadata::default(), time, pos);
    d.vel_ned = Some(vec![DVec3::new(25.0, 0.0, 0.0); n]);
    d.attitude = Some(vec![EulerZyx::new(0.3, 0.05, 0.0); n]);
    d.rates_body = Some(vec![DVec3::ZERO; n]);
    d.airspeed = Some(vec![25.0; n]);
    d.accel_body = Some(vec![DVec3::new(0.0, 0.0, -G0); n]);
    d
}

/// A steady banked turn: 30° of bank, body rates constant, the attitude integrated exactly
/// from them (R_{k+1} = R_k·Exp(ω·dt)), the specific force of the turn.
fn turn(n: usize, dt: f64) -> FlightData {
    let mut d = level(n, dt);
    let bank = 30f64.to_radians();
    let yaw_rate = G0 * bank.tan() / 25.0;
    let w = DVec3::new(0.0, yaw_rate * bank.sin(), yaw_rate * bank.cos());
    let r0 = EulerZyx::new(0.3, 0.0, bank).to_matrix();
    let step = DMat3::from_quat(DQuat::from_scaled_axis(w * dt));
    let mut r = r0;
    let mut att = Vec::with_capacity(n);
    for _ in 0..n {
        att.push(EulerZyx::from_matrix(r).0);
        r *= step;
    }
    d.attitude = Some(att);
    d.rates_body = Some(vec![w; n]);
    d.accel_body = Some(vec![DVec3::new(0.0, 0.0, -G0 / bank.cos()); n]);
    d
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn std(x: &[f64]) -> f64 {
    let m = mean(x);
    (x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

/// Sample autocorrelation at `lag`.
fn autocorr(x: &[f64], lag: usize) -> f64 {
    let m = mean(x);
    let num: f64 = x
        .iter()
        .zip(&x[lag..])
        .map(|(a, b)| (a - m) * (b - m))
        .sum();
    let den: f64 = x.iter().map(|a| (a - m).powi(2)).sum();
    num / den
}

fn axis(v: &[DVec3], i: usize) -> Vec<f64> {
    v.iter().map(|p| p[i]).collect()
}

fn ekf(s: &SensorErrors) -> EkfGnss {
    match s.model {
        Model::EkfGnss(m) => m,
        Model::Independent(_) => panic!("not ekf-gnss"),
    }
}

// ---------------------------------------------------------------------------------------------
// The independent model's statistics

/// (std, τ) of the independent preset's position north (G–M 0.5 m, τ 30 s, white 0.05 m)
/// and airspeed (G–M 0.3 m/s, τ 10 s), from 120 000 s at 2 s steps (4000 τ of position).
fn independent_stats(seed: u64) -> [f64; 4] {
    let dt = 2.0;
    let mut d = level(60_000, dt);
    let tr = SensorErrors::preset("independent")
        .unwrap()
        .apply(&mut d, seed);
    let north = axis(&tr.pos, 0);
    // The white part lowers every lag's correlation by one factor: the ratio of lags 15
    // (τ/dt) and 1 is φ^14 whatever it is.
    let tau_north = -14.0 * dt / (autocorr(&north, 15) / autocorr(&north, 1)).ln();
    let tau_air = -dt / autocorr(&tr.airspeed, 1).ln();
    [std(&north), tau_north, std(&tr.airspeed), tau_air]
}

#[test]
fn independent_gauss_markov_size_and_time_constant_measure_back() {
    let [sd_n, tau_n, sd_a, tau_a] = independent_stats(7);
    let within = |measured: f64, expected: f64| (measured / expected - 1.0).abs() < 0.10;
    assert!(
        within(sd_n, 0.5f64.hypot(0.05)),
        "position north std {sd_n}"
    );
    assert!(within(tau_n, 30.0), "position north τ {tau_n}");
    assert!(within(sd_a, 0.3), "airspeed std {sd_a}");
    assert!(within(tau_a, 10.0), "airspeed τ {tau_a}");
}

#[test]
fn independent_white_part_measures_back() {
    // Rates p: white 0.05 °/s on a G–M of 0.02 °/s, τ 60 s. At 10 ms steps the G–M part
    // hardly moves from one sample to the next, so var(Δx) = 2·white² (to 1e-4 relative).
    let mut d = level(40_000, 0.01);
    let tr = SensorErrors::preset("independent")
        .unwrap()
        .apply(&mut d, 3);
    let p = axis(&tr.rates, 0);
    let diffs: Vec<f64> = p.windows(2).map(|w| w[1] - w[0]).collect();
    let white = (diffs.iter().map(|v| v * v).sum::<f64>() / diffs.len() as f64 / 2.0).sqrt();
    let white_dps = white.to_degrees();
    assert!(
        (white_dps / 0.05 - 1.0).abs() < 0.10,
        "white {white_dps} °/s"
    );
}

/// Variance of the walk's growth over 10 s, over 4000 disjoint windows, and its first value.
fn walk_growth(seed: u64) -> (f64, f64) {
    let s = SensorErrors::parse(
        "model = \"independent\"\n[accel]\nx = { walk = 0.01 }\n",
        "w",
    )
    .unwrap();
    let (dt, window) = (0.1, 100);
    let mut d = level(4000 * window + 1, dt);
    let tr = s.apply(&mut d, seed);
    let x = axis(&tr.accel, 0);
    let growth: Vec<f64> = x
        .chunks_exact(window)
        .map(|c| c[c.len() - 1] - c[0])
        .collect();
    // The window spans window − 1 steps; the expected variance is walk²·(window − 1)·dt.
    let var = growth.iter().map(|g| g * g).sum::<f64>() / growth.len() as f64;
    (var / (0.01f64.powi(2) * (window - 1) as f64 * dt), x[0])
}

#[test]
fn random_walk_variance_grows_as_walk_squared_times_time() {
    let (ratio, first) = walk_growth(5);
    assert_eq!(first, 0.0, "the walk starts at 0");
    assert!((ratio - 1.0).abs() < 0.10, "variance / (walk²·T) = {ratio}");
}

// ---------------------------------------------------------------------------------------------
// The ekf-gnss model

#[test]
fn ekf_gnss_propagation_between_fixes_is_the_kinematics_of_its_imu_errors() {
    let dt = 0.01;
    let truth = turn(3000, dt);
    let mut d = truth.clone();
    let tr = SensorErrors::preset("ekf-gnss").unwrap().apply(&mut d, 11);
    let att = truth.attitude.as_ref().unwrap();
    let f_b = truth.accel_body.as_ref().unwrap();
    let (mut jumps, mut steps) = (Vec::new(), Vec::new());
    for k in 0..truth.len() - 1 {
        let dp = tr.pos[k + 1] - tr.pos[k];
        // Fixes at 5 Hz: every 20th sample.
        if (k + 1) % 20 == 0 {
            jumps.push(dp.length());
            continue;
        }
        steps.push(dp.length());
        let r = att[k].to_matrix();
        let f_n = r * f_b[k];
        let tol = 1e-12;
        // δp' = δv: Euler steps, so the step is the sample's δv times dt, to rounding.
        assert!((dp - tr.vel[k] * dt).length() < tol, "k {k}: δp step {dp}");
        // δv' = ψ × f_n + R·δf.
        let dv = tr.vel[k + 1] - tr.vel[k];
        let expected = (tr.tilt[k].cross(f_n) + r * tr.accel[k]) * dt;
        assert!(
            (dv - expected).length() < tol,
            "k {k}: δv step {dv} vs {expected}"
        );
        // ψ' = +R·δω: the sign pinned (logged R = Exp(ψ)·R).
        let dpsi = tr.tilt[k + 1] - tr.tilt[k];
        let expected = r * tr.rates[k] * dt;
        assert!((dpsi - expected).length() < tol, "k {k}: ψ step {dpsi}");
    }
    // The sawtooth: each fix moves the position far more than a step between fixes does.
    let biggest_step = steps.iter().copied().fold(0.0, f64::max);
    let median_jump = {
        let mut j = jumps.clone();
        j.sort_by(f64::total_cmp);
        j[j.len() / 2]
    };
    assert!(
        median_jump > 5.0 * biggest_step,
        "median jump {median_jump} m, biggest step {biggest_step} m"
    );
}

#[test]
fn ekf_gnss_logged_attitude_is_what_the_logged_rates_integrate_to() {
    // With a gyro error made large (1 °/s white), the logged attitude must follow the logged
    // rates between fixes: R̃_{k+1} = R̃_k·Exp(ω̃_k·dt) up to second-order terms. The other
    // sign of ψ' would miss by 2·|δω|·dt.
    let mut s = SensorErrors::preset("ekf-gnss").unwrap();
    if let Model::EkfGnss(m) = &mut s.model {
        m.gyro.white = 1.0;
    }
    let dt = 0.01;
    let mut d = turn(1000, dt);
    let tr = s.apply(&mut d, 2);
    let att = d.attitude.as_ref().unwrap();
    let rates = d.rates_body.as_ref().unwrap();
    let (mut miss, mut error) = (0.0, 0.0);
    for k in 0..d.len() - 1 {
        if (k + 1) % 20 == 0 {
            continue;
        }
        let predicted =
            att[k].to_matrix() * DMat3::from_quat(DQuat::from_scaled_axis(rates[k] * dt));
        let r = att[k + 1].to_matrix() * predicted.transpose();
        miss += DQuat::from_mat3(&r).to_scaled_axis().length();
        error += tr.rates[k].length() * dt;
    }
    assert!(
        miss < 0.02 * error,
        "miss {miss} rad against gyro error {error} rad"
    );
}

/// Standard deviations of the preset's errors over 40 000 s of level flight at 10 Hz:
/// position (mean of north and east, down), velocity (largest axis), tilt (mean of north and
/// east, down), degrees.
fn ekf_stats(seed: u64) -> [f64; 5] {
    let mut d = level(400_000, 0.1);
    let tr = SensorErrors::preset("ekf-gnss")
        .unwrap()
        .apply(&mut d, seed);
    let s = |v: &[DVec3], i| std(&axis(v, i));
    [
        (s(&tr.pos, 0) + s(&tr.pos, 1)) / 2.0,
        s(&tr.pos, 2),
        (0..3).map(|i| s(&tr.vel, i)).fold(0.0, f64::max),
        (s(&tr.tilt, 0) + s(&tr.tilt, 1)).to_degrees() / 2.0,
        s(&tr.tilt, 2).to_degrees(),
    ]
}

#[test]
fn ekf_gnss_errors_follow_the_gnss_and_stay_bounded() {
    let [horizontal, vertical, vel, tilt, heading] = ekf_stats(1);
    // The position error is the GNSS error smoothed: its G–M part (0.5 m, 1.0 m) passes, the
    // white part (0.2 m, 0.4 m) is mostly filtered out. Without the corrections it would grow
    // without bound.
    assert!(
        (horizontal / 0.5 - 1.0).abs() < 0.10,
        "horizontal {horizontal} m"
    );
    assert!((vertical / 1.0 - 1.0).abs() < 0.10, "vertical {vertical} m");
    assert!(
        (vertical / horizontal / 2.0 - 1.0).abs() < 0.10,
        "{vertical} / {horizontal}"
    );
    assert!(vel < 0.15, "velocity {vel} m/s");
    assert!((0.03..0.3).contains(&tilt), "tilt {tilt}°");
    assert!((0.3..1.0).contains(&heading), "heading {heading}°");
}

#[test]
fn ekf_gnss_yaw_stays_near_the_truth_across_turns() {
    // Inverted, heading 7 rad: the angles must not jump by a turn (without an accelerometer
    // the specific force is taken as (0, 0, −g₀), which inverted level flight has).
    let mut d = level(200, 0.01);
    d.accel_body = None;
    for a in d.attitude.iter_mut().flatten() {
        a.yaw = 7.0;
        a.roll = -3.1;
    }
    SensorErrors::preset("ekf-gnss").unwrap().apply(&mut d, 1);
    for a in d.attitude.as_ref().unwrap() {
        assert!(
            (a.yaw - 7.0).abs() < 0.1 && (a.roll + 3.1).abs() < 0.1,
            "{a:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Determinism and additivity

#[test]
fn same_seed_same_bits_other_seed_other_errors() {
    for name in PRESETS {
        let s = SensorErrors::preset(name).unwrap();
        let base = turn(500, 0.02);
        let (mut a, mut b, mut c) = (base.clone(), base.clone(), base.clone());
        let ta = s.apply(&mut a, 42);
        let tb = s.apply(&mut b, 42);
        let tc = s.apply(&mut c, 43);
        assert_eq!(ta, tb, "{name}");
        assert_eq!(a, b, "{name}");
        assert_ne!(ta.pos, tc.pos, "{name}");
        assert_ne!(a, c, "{name}");
    }
}

#[test]
fn apply_only_adds_its_errors() {
    for name in PRESETS {
        let s = SensorErrors::preset(name).unwrap();
        let before = turn(300, 0.02);
        let mut after = before.clone();
        let tr = s.apply(&mut after, 9);
        assert_eq!(after.time, before.time);
        assert_eq!(after.meta, before.meta);
        assert_eq!(after.vel_body, before.vel_body);
        assert_eq!(after.controls, before.controls);
        let pairs = |a: &Option<Vec<DVec3>>, b: &Option<Vec<DVec3>>| {
            a.iter()
                .flatten()
                .zip(b.iter().flatten())
                .map(|(x, y)| *x - *y)
                .collect::<Vec<_>>()
        };
        let dp: Vec<DVec3> = after
            .pos_ned
            .iter()
            .zip(&before.pos_ned)
            .map(|(a, b)| *a - *b)
            .collect();
        for (x, e) in dp.iter().zip(&tr.pos) {
            assert!((*x - *e).length() < 1e-9, "{name}");
        }
        for (got, want) in [
            (pairs(&after.vel_ned, &before.vel_ned), &tr.vel),
            (pairs(&after.rates_body, &before.rates_body), &tr.rates),
            (pairs(&after.accel_body, &before.accel_body), &tr.accel),
        ] {
            for (x, e) in got.iter().zip(want) {
                assert!((*x - *e).length() < 1e-12, "{name}");
            }
        }
        let airspeed = after
            .airspeed
            .as_ref()
            .unwrap()
            .iter()
            .zip(before.airspeed.as_ref().unwrap());
        for ((a, b), e) in airspeed.zip(&tr.airspeed) {
            assert!((a - b - e).abs() < 1e-12, "{name}");
        }
        // The attitude: rotated by the trace's tilt.
        let att = after
            .attitude
            .as_ref()
            .unwrap()
            .iter()
            .zip(before.attitude.as_ref().unwrap());
        for ((a, b), e) in att.zip(&tr.tilt) {
            let r = a.to_matrix() * b.to_matrix().transpose();
            let v = DQuat::from_mat3(&r).to_scaled_axis();
            assert!((v - *e).length() < 1e-9, "{name}: {v} vs {e}");
        }
    }
}

#[test]
fn an_axis_errors_do_not_depend_on_the_other_axes_parameters() {
    let mut s = SensorErrors::preset("independent").unwrap();
    let mut d = level(500, 0.02);
    let a = s.apply(&mut d.clone(), 5);
    if let Model::Independent(m) = &mut s.model {
        m.position[0].white = 3.0;
        m.attitude[2] = AxisError::ZERO;
    }
    let b = s.apply(&mut d, 5);
    assert_eq!(axis(&a.pos, 1), axis(&b.pos, 1));
    assert_eq!(a.vel, b.vel);
    assert_eq!(a.rates, b.rates);
    assert_eq!(a.airspeed, b.airspeed);
    assert_ne!(axis(&a.pos, 0), axis(&b.pos, 0));
}

#[test]
fn odd_flights_make_no_panic() {
    let mut e = SensorErrors::preset("ekf-gnss").unwrap();
    let mut models = vec![SensorErrors::preset("independent").unwrap(), e.clone()];
    if let Model::EkfGnss(m) = &mut e.model {
        m.gnss_rate_hz = 0.0;
        m.gyro.tau_s = Some(f64::NAN);
        m.gnss_horizontal = AxisError::ZERO;
        m.heading = AxisError::ZERO;
    }
    models.push(e);
    let mut flights = vec![
        FlightData::default(),
        level(1, 0.01),
        level(50, 0.01),
        level(50, 0.0),
    ];
    let mut odd = level(50, 0.01);
    odd.time[7] = f64::NAN;
    odd.time[9] = -1.0;
    odd.attitude.as_mut().unwrap()[3].yaw = f64::NAN;
    odd.accel_body.as_mut().unwrap()[4].x = f64::INFINITY;
    odd.airspeed.as_mut().unwrap().truncate(10);
    flights.push(odd);
    for s in &models {
        for f in &flights {
            let mut d = f.clone();
            let tr = s.apply(&mut d, 1);
            assert_eq!(tr.pos.len(), f.len());
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Files, presets, records

/// The module documentation's example of the independent model.
const INDEPENDENT_EXAMPLE: &str = r#"
model = "independent"

[position]                # m, NED
rate_hz = 10              # optional: the channel's sampling rate (absent: every sample)
north = { size = 0.5, tau_s = 30.0, white = 0.05 }
east  = { size = 0.5, tau_s = 30.0, white = 0.05 }
down  = { size = 1.0, tau_s = 60.0, white = 0.1 }

[velocity]                # m/s, NED
north = { size = 0.05, tau_s = 5.0 }

[attitude]                # degrees
roll  = { size = 0.2, tau_s = 5.0 }
yaw   = { size = 0.5, tau_s = 30.0 }

[rates]                   # degrees/s, body p, q, r
p = { size = 0.02, tau_s = 60.0, white = 0.05 }

[airspeed]                # m/s; one axis, so its fields are the table's own
size = 0.3
tau_s = 10.0

[accel]                   # m/s², body x, y, z
z = { size = 0.02, tau_s = 60.0, walk = 0.001 }
"#;

/// The module documentation's example of the ekf-gnss model.
const EKF_EXAMPLE: &str = r#"
model = "ekf-gnss"

[gnss]                    # m; fixes at rate_hz (required)
rate_hz = 5
horizontal = { size = 0.5, tau_s = 30.0, white = 0.2 }
vertical   = { size = 1.0, tau_s = 30.0, white = 0.4 }

[heading]                 # the heading aid's error, degrees, read at the GNSS rate
size = 0.5
tau_s = 30.0

[gyro]                    # degrees/s, each body axis; rate_hz: the logged rates' rate
size = 0.01
tau_s = 60.0
white = 0.05

[accel]                   # m/s², each body axis; rate_hz: the logged accelerometer's
size = 0.01
tau_s = 60.0
white = 0.02

[airspeed]                # m/s
size = 0.3
tau_s = 10.0

[position]                # the filter outputs' sampling rates, all optional
rate_hz = 50
"#;

#[test]
fn the_documented_examples_parse() {
    let s = SensorErrors::parse(INDEPENDENT_EXAMPLE, "ex.toml").unwrap();
    let Model::Independent(m) = s.model else {
        panic!("{s:?}")
    };
    assert_eq!(m.position[2], AxisError::gm(1.0, 60.0, 0.1));
    assert_eq!(m.velocity[1], AxisError::ZERO);
    assert_eq!(m.accel[2].walk, 0.001);
    assert_eq!(m.airspeed, AxisError::gm(0.3, 10.0, 0.0));
    assert_eq!(s.rates().position, Some(10.0));
    assert_eq!(s.rates().velocity, None);

    // The ekf-gnss example is the preset with a position rate.
    let s = SensorErrors::parse(EKF_EXAMPLE, "ex.toml").unwrap();
    let mut preset = ekf(&SensorErrors::preset("ekf-gnss").unwrap());
    preset.rates_hz.position = Some(50.0);
    assert_eq!(ekf(&s), preset);
    assert_eq!(s.rates().position, Some(50.0));
}

/// The message of the error of parsing `text` (as file `bad.toml`), checked to name the file
/// and `field`.
fn error_of(text: &str, field: &str) -> String {
    let e = SensorErrors::parse(text, "bad.toml").unwrap_err();
    let message = e.to_string();
    assert!(message.starts_with("bad.toml: "), "{message}");
    if let SensorErrorsError::Field { field: f, .. } = &e {
        assert_eq!(f, field, "{message}");
    } else {
        assert!(
            field.is_empty(),
            "{message}: expected a field error for `{field}`"
        );
    }
    assert!(message.contains(field), "{message}");
    message
}

#[test]
fn every_file_error_names_the_file_and_the_field() {
    let m = "model = \"independent\"\n";
    let msg = error_of(
        &format!("{m}[position]\nnroth = {{ size = 1, tau_s = 2 }}"),
        "position.nroth",
    );
    assert!(msg.contains("north, east, down"), "{msg}");
    error_of(&format!("{m}[positon]\nrate_hz = 1"), "positon");
    error_of(
        &format!("{m}[position]\nnorth = {{ size = -1, tau_s = 2 }}"),
        "position.north.size",
    );
    error_of(
        &format!("{m}[position]\nnorth = {{ size = nan, tau_s = 2 }}"),
        "position.north.size",
    );
    error_of(
        &format!("{m}[position]\nnorth = {{ size = 1, tau_s = 0 }}"),
        "position.north.tau_s",
    );
    error_of(
        &format!("{m}[position]\nnorth = {{ size = 1, tau_s = inf }}"),
        "position.north.tau_s",
    );
    error_of(
        &format!("{m}[position]\nnorth = {{ size = 1 }}"),
        "position.north.tau_s",
    );
    error_of(&format!("{m}[position]\nrate_hz = 0"), "position.rate_hz");
    error_of(
        &format!("{m}[position]\nrate_hz = 10001"),
        "position.rate_hz",
    );
    let msg = error_of(&format!("{m}[airspeed]\nsize = \"big\""), "airspeed.size");
    assert!(
        msg.contains("a number") && msg.contains("a string"),
        "{msg}"
    );
    error_of(
        &format!("{m}[airspeed]\nsize = {{ a = 1 }}"),
        "airspeed.size",
    );
    error_of(&format!("{m}position = 3"), "position");
    error_of(&format!("{m}[position]\nnorth = [1, 2]"), "position.north");
    error_of(
        &format!("{m}[airspeed]\nsize = 0.3\ntau_s = 10\nwite = 0.1"),
        "airspeed.wite",
    );
    error_of(
        "model = \"ekf-gnss\"\n[gnss]\nhorizontal = { size = 0.5, tau_s = 30 }",
        "gnss.rate_hz",
    );
    error_of(
        "model = \"ekf-gnss\"\n[gnss]\nrate_hz = 5\n[gyro]\np = { size = 1 }",
        "gyro.p",
    );
    let msg = error_of("model = \"kalman\"", "model");
    assert!(
        msg.contains("independent") && msg.contains("ekf-gnss"),
        "{msg}"
    );
    error_of("[position]\nrate_hz = 1", "model");
    error_of("model = 3", "model");
    error_of("model = \"independent\"\n[position\n", "");
}

#[test]
fn presets_and_arguments() {
    for name in PRESETS {
        let s = SensorErrors::preset(name).unwrap();
        assert_eq!(s.name(), name);
        assert_eq!(SensorErrors::from_arg(name).unwrap(), s);
    }
    assert!(SensorErrors::preset("gnss").is_none());
    assert_eq!(
        SensorErrors::preset("independent")
            .unwrap()
            .rates()
            .position,
        Some(10.0)
    );
    let msg = SensorErrors::from_arg("kalman").unwrap_err().to_string();
    assert!(
        msg.contains("kalman") && msg.contains("independent") && msg.contains("ekf-gnss"),
        "{msg}"
    );

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("e.toml");
    std::fs::write(&path, EKF_EXAMPLE).unwrap();
    let s = SensorErrors::from_arg(path.to_str().unwrap()).unwrap();
    assert_eq!(s.rates().position, Some(50.0));
    let missing = dir.path().join("none.toml");
    let msg = SensorErrors::from_arg(missing.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("none.toml"), "{msg}");
    std::fs::write(&path, "model = \"ekf-gnss\"\n[gnss]\nrate_hz = -5\n").unwrap();
    let msg = SensorErrors::load(&path).unwrap_err().to_string();
    assert!(
        msg.contains("e.toml") && msg.contains("gnss.rate_hz"),
        "{msg}"
    );
}

#[test]
fn records_round_trip() {
    let mut custom = SensorErrors::parse(INDEPENDENT_EXAMPLE, "ex.toml").unwrap();
    if let Model::Independent(m) = &mut custom.model {
        m.rates[1] = AxisError {
            size: 1e-7,
            tau_s: Some(1e8),
            white: 123456.789,
            walk: 0.1 + 0.2,
        };
        m.rates_hz.accel = Some(333.3);
    }
    let mut all = vec![custom];
    all.extend(PRESETS.iter().map(|n| SensorErrors::preset(n).unwrap()));
    for s in all {
        for seed in [0, 3, u64::MAX] {
            let record = s.to_record(seed);
            assert!(
                record.starts_with(&format!("model={} seed={seed} ", s.name())),
                "{record}"
            );
            assert_eq!(
                SensorErrors::from_record(&record).unwrap(),
                (s.clone(), seed),
                "{record}"
            );
        }
    }
    let record = SensorErrors::preset("ekf-gnss").unwrap().to_record(3);
    assert!(
        record.starts_with("model=ekf-gnss seed=3 gnss.rate_hz=5 gnss.horizontal.size=0.5"),
        "{record}"
    );
}

#[test]
fn bad_records_are_refused_by_field() {
    let field = |record: &str| match SensorErrors::from_record(record) {
        Err(SensorErrorsError::Field { field, file, .. }) => {
            assert!(file.contains(TRUTH_KEY));
            field
        }
        other => panic!("{record}: {other:?}"),
    };
    assert_eq!(field("model=ekf-gnss gnss.rate_hz=5"), "seed");
    assert_eq!(field("seed=1 gnss.rate_hz=5"), "model");
    assert_eq!(field("model=ekf-gnss seed=x gnss.rate_hz=5"), "seed");
    assert_eq!(field("model=ekf-gnss seed=1"), "gnss.rate_hz");
    assert_eq!(
        field("model=ekf-gnss seed=1 gnss.rate_hz=NaN"),
        "gnss.rate_hz"
    );
    assert_eq!(
        field("model=ekf-gnss seed=1 gnss.rate_hz=5 gnss.rate_hz=5"),
        "gnss.rate_hz"
    );
    assert_eq!(
        field("model=ekf-gnss seed=1 gnss.rate_hz=5 gyro.sise=1"),
        "gyro.sise"
    );
    assert_eq!(
        field("model=independent seed=1 airspeed.size=1"),
        "airspeed.tau_s"
    );
    assert_eq!(field("model=independent seed=1 junk"), "junk");
}
