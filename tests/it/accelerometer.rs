//! The accelerometer channel: the specific force at the centre of gravity in body axes (FRD),
//! m/s². Read from the project's CSV, column maps and PX4 ULog, written back, refused where
//! it is not a number or beyond 50 g; written by `simulate` for a fixed wing, checked against
//! `support::refsim`'s own force over mass and against the flight's own velocities; and
//! `identify` reading a column-mapped CSV and a ULog as `compare` does.

use std::path::Path;

use glam::{DQuat, DVec3};
use wireflight::data::mapped::ColumnMap;
use wireflight::data::px4::{self, UlogOptions};
use wireflight::data::ulog::UlogFile;
use wireflight::data::{self, FlightData, Metadata, G0, MAX_ACCEL_MPS2};

use crate::support::cli::{ok, ok_with_stderr, refused};
use crate::support::flights::Flight;
use crate::support::refsim::{self, Effects, FlightOptions, FwModel, Params, Schedule};
use crate::support::ulog::UlogWriter;

/// `flight` simulated into `dir/name`, read back.
fn simulate(flight: &Flight, dir: &Path, name: &str) -> FlightData {
    data::read(&flight.write(dir, name)).expect("simulate's CSV reads")
}

// ---------------------------------------------------------------------------------------------
// The project's CSV

#[test]
fn csv_round_trip_keeps_the_accelerometer_bit_for_bit() {
    let n = 25;
    let time: Vec<f64> = (0..n).map(|i| 0.02 * i as f64).collect();
    let mut d = FlightData::new(
        Metadata::default(),
        time,
        (0..n).map(|i| DVec3::new(i as f64, 0.0, -100.0)).collect(),
    );
    d.accel_body = Some(
        (0..n)
            .map(|i| DVec3::new(0.1 * (i as f64).sin(), -0.37 / 3.0, -G0 + 1e-3 * i as f64))
            .collect(),
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("acc.csv");
    data::write(&path, &d).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.starts_with("time_s,north_m,east_m,down_m,ax_mps2,ay_mps2,az_mps2\n"),
        "{text}"
    );
    let back = data::read(&path).unwrap();
    assert_eq!(back.accel_body, d.accel_body);
    // Validation knows the channel: a short one, a non-finite one.
    let mut bad = d.clone();
    bad.accel_body.as_mut().unwrap().pop();
    assert_eq!(
        bad.validate().unwrap_err().to_string(),
        "accel_body has 24 samples but time has 25"
    );
    let mut bad = d.clone();
    bad.accel_body.as_mut().unwrap()[3].y = f64::NAN;
    assert_eq!(
        bad.validate().unwrap_err().to_string(),
        "accel_body[3] is not finite"
    );
    // A reading beyond 50 g is not written (it would not read back).
    let mut bad = d;
    bad.accel_body.as_mut().unwrap()[7].x = 1.01 * MAX_ACCEL_MPS2;
    let e = data::write(&dir.path().join("no.csv"), &bad).unwrap_err();
    assert!(e.to_string().contains("column `ax_mps2`"), "{e}");
    assert!(!dir.path().join("no.csv").exists());
}

#[test]
fn bad_accelerometer_columns_are_refused_naming_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let import = |path: &str| {
        let out = dir.path().join("out.csv");
        refused(&["import", "--flight", path, "--out", out.to_str().unwrap()])
    };
    let head = "# source: a logger\ntime_s,north_m,east_m,down_m,ax_mps2,ay_mps2,az_mps2\n";
    // Part of the set: the file, the header's line, the missing columns.
    let p = file(
        "partial.csv",
        "time_s,north_m,east_m,down_m,ax_mps2\n0,0,0,0,0\n1,0,0,0,0\n",
    );
    let e = import(&p);
    assert!(
        e.contains(&format!(
            "{p}: line 1: missing required columns ay_mps2, az_mps2: accelerometer columns come \
             as a set and `ax_mps2` is present"
        )),
        "{e}"
    );
    for (cell, line, problem) in [
        ("nan", 4, "not a finite number: `nan`"),
        ("-inf", 4, "not a finite number: `-inf`"),
        (
            "600",
            4,
            "`600` is outside the range of a flight: ±490.3 m/s² (50 g)",
        ),
    ] {
        let p = file(
            "bad.csv",
            &format!("{head}0,0,0,0,0,0,-9.8\n1,0,0,0,0,0,{cell}\n"),
        );
        let e = import(&p);
        assert!(
            e.contains(&format!("{p}: line {line}, column `az_mps2`: {problem}")),
            "{e}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Column maps

#[test]
fn a_column_map_reads_the_accelerometer_in_g() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("imu.csv");
    std::fs::write(
        &csv,
        "t_ms;x;y;z;acc_x;acc_y;acc_z\n0;0;0;-10;0.01;0;-1\n100;1;0;-10;0.02;-0.01;-1.01\n\
         200;2;0;-10;0.03;0;-0.99\n",
    )
    .unwrap();
    let map = "time=t_ms:ms,north=x,east=y,down=z,ax=acc_x:g,ay=acc_y:g,az=acc_z:g";
    let loaded = data::load(
        &csv,
        &data::LoadOptions {
            columns: Some(ColumnMap::parse(map).unwrap()),
            ..Default::default()
        },
    )
    .unwrap();
    let a = loaded.data.accel_body.as_ref().unwrap();
    assert!(
        (a[1] - DVec3::new(0.02, -0.01, -1.01) * G0).length() < 1e-12,
        "{}",
        a[1]
    );
    let report = loaded.report.unwrap().to_string();
    let line = report
        .lines()
        .find(|l| l.contains("accelerometer  acc_x [g], acc_y [g], acc_z [g]"))
        .unwrap_or_else(|| panic!("{report}"));
    assert!(line.contains(" 3  10 Hz"), "{report}");
    // And through import, written in m/s².
    let out = dir.path().join("out.csv");
    ok(&[
        "import",
        "--flight",
        csv.to_str().unwrap(),
        "--columns",
        map,
        "--out",
        out.to_str().unwrap(),
    ]);
    let back = data::read(&out).unwrap();
    assert_eq!(back.accel_body.as_ref(), Some(a));
}

// ---------------------------------------------------------------------------------------------
// PX4 ULog

const LOCAL: &str = "vehicle_local_position:uint64_t timestamp;float x;float y;float z;";
const ATT: &str = "vehicle_attitude:uint64_t timestamp;float[4] q;";

/// Level flight north at 10 m/s for 2 s (position 100 Hz, attitude 50 Hz) with an
/// accelerometer topic at 200 Hz reading a slow sine on x and −g on z.
fn log_with(topic: &str, format: &str) -> UlogWriter {
    let mut w = UlogWriter::new(Some([0; 8]));
    w.format(LOCAL);
    w.format(ATT);
    w.format(format);
    let p = w.subscribe("vehicle_local_position");
    let a = w.subscribe("vehicle_attitude");
    let s = w.subscribe(topic);
    for k in 0..=400u64 {
        let t = 1_000_000 + k * 5_000;
        if k % 2 == 0 {
            w.data_f32(p, t, &[(k as f32) * 0.05, 0.0, -50.0]);
        }
        if k % 4 == 0 {
            w.data_f32(a, t, &[1.0, 0.0, 0.0, 0.0]);
        }
        let secs = (t - 1_000_000) as f32 * 1e-6;
        let acc = [secs.sin(), 0.25, -9.81];
        if topic == "sensor_combined" {
            // gyro_rad[3], gyro_integral_dt, accelerometer_timestamp_relative,
            // accelerometer_m_s2[3]
            let mut f = vec![0.0f32; 3];
            f.extend([4000.0, 0.0]);
            f.extend(acc);
            w.data_f32(s, t, &f);
        } else {
            w.data_f32(s, t, &acc);
        }
    }
    w
}

fn from_ulog(bytes: &[u8]) -> Result<(FlightData, String), String> {
    let log =
        UlogFile::parse(bytes, "a.ulg", |t| px4::TOPICS.contains(&t)).map_err(|e| e.to_string())?;
    px4::from_ulog(&log, "a.ulg", &UlogOptions::default())
        .map(|(d, r)| (d, r.to_string()))
        .map_err(|e| e.to_string())
}

#[test]
fn ulog_accelerometer_from_sensor_combined_or_vehicle_acceleration_resampled() {
    for (topic, format, fields) in [
        (
            "sensor_combined",
            "sensor_combined:uint64_t timestamp;float[3] gyro_rad;float gyro_integral_dt;\
             float accelerometer_timestamp_relative;float[3] accelerometer_m_s2;",
            "accelerometer_m_s2[0..3]",
        ),
        (
            "vehicle_acceleration",
            "vehicle_acceleration:uint64_t timestamp;float[3] xyz;",
            "xyz[0..3]",
        ),
    ] {
        let (d, report) = from_ulog(&log_with(topic, format).bytes).unwrap();
        // 2 s at 50 Hz; the 200 Hz readings taken at the grid's times (linear).
        assert_eq!(d.len(), 101, "{topic}");
        let a = d.accel_body.as_ref().unwrap();
        for k in [0, 33, 100] {
            let t = d.time[k];
            let want = DVec3::new(t.sin(), 0.25, -9.81);
            assert!(
                (a[k] - want).length() < 1e-5,
                "{topic} {k}: {} vs {want}",
                a[k]
            );
        }
        let line = report
            .lines()
            .find(|l| l.contains(&format!("accelerometer  {topic} {fields}")))
            .unwrap_or_else(|| panic!("{report}"));
        assert!(line.contains(" 401  200 Hz"), "{report}");
    }
    // Neither topic: no accelerometer, and the report says so.
    let mut w = UlogWriter::new(Some([0; 8]));
    w.format(LOCAL);
    w.format(ATT);
    let p = w.subscribe("vehicle_local_position");
    let a = w.subscribe("vehicle_attitude");
    for k in 0..=20u64 {
        w.data_f32(p, 1_000_000 + k * 20_000, &[k as f32, 0.0, -5.0]);
        w.data_f32(a, 1_000_000 + k * 20_000, &[1.0, 0.0, 0.0, 0.0]);
    }
    let (d, report) = from_ulog(&w.bytes).unwrap();
    assert!(d.accel_body.is_none());
    assert!(
        report.contains("accelerometer  sensor_combined") && report.contains("not in the log"),
        "{report}"
    );
}

#[test]
fn ulog_accelerometer_beyond_fifty_g_names_topic_field_and_time() {
    let format = "vehicle_acceleration:uint64_t timestamp;float[3] xyz;";
    let mut w = log_with("vehicle_acceleration", format);
    // A reading of 1000 m/s² on z (a raw count, not m/s²) — id 2 is the accelerometer.
    w.data_f32(2, 1_500_000, &[0.0, 0.0, 1000.0]);
    let e = from_ulog(&w.bytes).unwrap_err();
    assert!(
        e.contains("topic `vehicle_acceleration`, field `xyz[2]`")
            && e.contains("1000 at time stamp 1500000 µs")
            && e.contains("±490.3 m/s² (50 g)"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// simulate

/// simulate writes the accelerometer of a fixed wing (never of a point mass) when asked with
/// --noise-acc, with Gaussian noise of that σ on each axis, and nothing else of the file
/// changes with it.
#[test]
fn simulate_noise_acc_is_gaussian_of_its_sigma_and_leaves_the_other_channels_alone() {
    let dir = tempfile::tempdir().unwrap();
    let common = Flight::new()
        .manoeuvre("climbing-turn")
        .duration(60)
        .seed(11)
        .noise_pos(0.1)
        .noise_att(0.1)
        .noise_vel(0.05)
        .noise_rate(0.2);
    // Without --noise-acc no accelerometer is recorded; with 0, an exact one.
    let none = simulate(&common, dir.path(), "none.csv");
    assert!(none.accel_body.is_none());
    let quiet = simulate(&common.clone().noise_acc(0), dir.path(), "quiet.csv");
    assert_eq!(
        none,
        FlightData {
            accel_body: None,
            ..quiet.clone()
        }
    );
    let noisy = simulate(&common.noise_acc(0.05), dir.path(), "noisy.csv");
    // Every other channel is the same, bit for bit: the accelerometer's noise is drawn last.
    let strip = |d: &FlightData| FlightData {
        accel_body: None,
        ..d.clone()
    };
    assert_eq!(strip(&quiet), strip(&noisy));
    let header = std::fs::read_to_string(dir.path().join("noisy.csv")).unwrap();
    assert!(
        header.contains(
            "\ntime_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps,\
             p_dps,q_dps,r_dps,airspeed_mps,ax_mps2,ay_mps2,az_mps2,throttle,elevator_deg,\
             aileron_deg,rudder_deg\n"
        ),
        "{}",
        &header[..600]
    );
    let (q, n) = (
        quiet.accel_body.as_ref().unwrap(),
        noisy.accel_body.as_ref().unwrap(),
    );
    assert_eq!(q.len(), 3001);
    for axis in 0..3 {
        let e: Vec<f64> = q.iter().zip(n).map(|(a, b)| (b - a)[axis]).collect();
        let mean = e.iter().sum::<f64>() / e.len() as f64;
        let sd = (e.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (e.len() - 1) as f64).sqrt();
        assert!(
            (sd / 0.05 - 1.0).abs() < 0.1 && mean.abs() < 0.01,
            "axis {axis}: σ {sd}, mean {mean}"
        );
    }
    // The axes' noises are not one draw repeated.
    let cross: f64 = q
        .iter()
        .zip(n)
        .map(|(a, b)| {
            let e = b - a;
            e.x * e.y
        })
        .sum::<f64>()
        / q.len() as f64;
    assert!(cross.abs() < 0.1 * 0.05 * 0.05, "{cross}");
    // A point mass has no accelerometer column; a bad σ is refused.
    let shot = simulate(
        &Flight::new().vehicle("point-mass").duration(5),
        dir.path(),
        "shot.csv",
    );
    assert!(shot.accel_body.is_none());
    let e = refused(&[
        "simulate",
        "--noise-acc=-1",
        "--out",
        dir.path().join("x.csv").to_str().unwrap(),
    ]);
    assert!(
        e.contains("--noise-acc") && e.contains("must not be negative"),
        "{e}"
    );
}

/// Steady level flight: the accelerometer reads gravity's answer, −g along NED down seen in
/// body axes, (g·sinθ, 0, −g·cosθ) at pitch θ and no roll.
#[test]
fn a_trimmed_level_flight_reads_g_along_its_own_vertical() {
    let dir = tempfile::tempdir().unwrap();
    let level = Flight::new().manoeuvre("level").duration(20).noise_acc(0);
    let d = simulate(&level, dir.path(), "level.csv");
    let a = d.accel_body.as_ref().unwrap();
    let att = d.attitude.as_ref().unwrap();
    let mut worst = 0.0f64;
    for (a, e) in a.iter().zip(att) {
        let want = DVec3::new(
            G0 * e.pitch.sin(),
            -G0 * e.pitch.cos() * e.roll.sin(),
            -G0 * e.pitch.cos() * e.roll.cos(),
        );
        worst = worst.max((*a - want).length());
        assert!(e.roll.abs() < 1e-6, "{e:?}");
    }
    assert!(worst < 1e-3, "worst {worst} m/s²");
    let theta = att[0].pitch;
    assert!(theta > 0.0 && (a[0].x - G0 * theta.sin()).abs() < 1e-3);
    assert!(a[0].y.abs() < 1e-6 && (a[0].z + G0 * theta.cos()).abs() < 1e-3);
}

/// refsim's state of a recorded row: position, body velocity from the NED velocity and
/// attitude, Euler angles, rates; surfaces at their commands (no actuator lag).
fn refsim_state(d: &FlightData, i: usize) -> refsim::FwState {
    let e = d.attitude.as_ref().unwrap()[i];
    let r = refsim::rot_body_to_ned(e.roll, e.pitch, e.yaw);
    let v = d.vel_ned.as_ref().unwrap()[i];
    let uvw = refsim::m_t_vec(&r, [v.x, v.y, v.z]);
    let p = d.pos_ned[i];
    let w = d.rates_body.as_ref().unwrap()[i];
    let c = d.controls.as_ref().unwrap()[i];
    [
        p.x, p.y, p.z, uvw[0], uvw[1], uvw[2], e.roll, e.pitch, e.yaw, w.x, w.y, w.z, c.elevator,
        c.aileron, c.rudder,
    ]
}

/// A 40 s flight test by `simulate` with an exact accelerometer.
fn flight_test_40s(dir: &Path) -> FlightData {
    let flight = Flight::new()
        .manoeuvre("flight-test")
        .duration(40)
        .noise_acc(0);
    simulate(&flight, dir, "ft.csv")
}

/// simulate's accelerometer on a manoeuvring flight is refsim's force over mass (its own
/// aerodynamics and thrust) at every recorded state and command, to the rounding of the file.
#[test]
fn simulate_accelerometer_is_refsims_force_over_mass_at_every_sample() {
    let dir = tempfile::tempdir().unwrap();
    let d = flight_test_40s(dir.path());
    let model = FwModel::new(
        &Params::aerosonde(),
        &Effects::none(),
        &refsim::Origin::default(),
    );
    let mass = Params::aerosonde().mass_kg;
    let a = d.accel_body.as_ref().unwrap();
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for (i, reading) in a.iter().enumerate() {
        let c = d.controls.as_ref().unwrap()[i];
        let cmd = refsim::Controls {
            throttle: c.throttle,
            elevator: c.elevator,
            aileron: c.aileron,
            rudder: c.rudder,
        };
        let (f, _) = model.force_moment(&refsim_state(&d, i), &cmd);
        let theirs = DVec3::from_array(f) / mass;
        worst = worst.max((*reading - theirs).length());
        largest = largest.max((*reading + DVec3::Z * G0).length());
    }
    // A manoeuvring flight: the reading moves well away from level flight's.
    assert!(largest > 2.0, "largest departure from −g·z: {largest} m/s²");
    assert!(worst < 1e-6, "worst difference {worst} m/s²");
}

/// The velocity that both simulators record follows from their accelerometer, gravity and
/// attitude: Δv_NED over a sample ≈ ∫ (R·a + g·ẑ) dt (trapezoid), to the integration's
/// tolerance — for simulate's flight and for refsim's, which integrates its own Euler-angle
/// state with its own autopilot.
#[test]
fn both_simulators_accelerometers_integrate_to_their_recorded_velocities() {
    let dir = tempfile::tempdir().unwrap();
    let ours = flight_test_40s(dir.path());
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.duration_s = 40.0;
    o.effects = Effects::none();
    let csv = refsim::flight_csv_with_accelerometer(&o).expect("refsim flies");
    let theirs = data::parse(&csv, "refsim.csv").expect("refsim's CSV reads");
    assert!(theirs.accel_body.is_some());
    for (name, d) in [("simulate", &ours), ("refsim", &theirs)] {
        let a = d.accel_body.as_ref().unwrap();
        let att = d.attitude.as_ref().unwrap();
        let v = d.vel_ned.as_ref().unwrap();
        let inertial = |i: usize| att[i].to_matrix() * a[i] + DVec3::Z * G0;
        let mut errors: Vec<f64> = (0..d.len() - 1)
            .map(|i| {
                let dt = d.time[i + 1] - d.time[i];
                let dv = v[i + 1] - v[i];
                (dv / dt - 0.5 * (inertial(i) + inertial(i + 1))).length()
            })
            .collect();
        errors.sort_by(f64::total_cmp);
        let median = errors[errors.len() / 2];
        let p95 = errors[errors.len() * 95 / 100];
        eprintln!("{name}: median {median:.2e}, 95th percentile {p95:.2e} m/s²");
        // The trapezoid's error, and the commands changing at each sample (the reading at
        // i + 1 is under the next command): small against the manoeuvre's accelerations.
        assert!(median < 0.02 && p95 < 0.1, "{name}: {median} {p95}");
    }
}

// ---------------------------------------------------------------------------------------------
// identify reads every flight format

/// A flight with a wrong c_m_alpha flown by simulate, with the noise of the command tests.
fn flight_for_identify(dir: &Path) -> std::path::PathBuf {
    Flight::new()
        .manoeuvre("flight-test")
        .duration(30)
        .hidden("aircraft:c_m_alpha=-3.3")
        .noise_pos(0.05)
        .noise_att(0.05)
        .noise_vel(0.05)
        .noise_rate(0.2)
        .noise_acc(0.05)
        .seed(1)
        .write(dir, "a.csv")
}

fn identified_c_m_alpha(stdout: &str) -> f64 {
    let v: serde_json::Value = serde_json::from_str(stdout).expect("JSON on stdout");
    let est = v["estimates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["key"] == "c_m_alpha")
        .expect("c_m_alpha estimated")
        .clone();
    est["value"].as_f64().unwrap()
}

#[test]
fn identify_reads_a_column_mapped_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = flight_for_identify(dir.path());
    // The same flight in a logger's names and units: ms, degrees, deg/s, g.
    let d = data::read(&csv).unwrap();
    // The same metadata (vehicle, aircraft, origin).
    let mut text: String = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    text.push_str("t_ms,n,e,d,phi,theta,psi,vn,ve,vd,P,Q,R,tas,fx,fy,fz,thr,de,da,dr\n");
    for i in 0..d.len() {
        let (p, e, v) = (
            d.pos_ned[i],
            d.attitude.as_ref().unwrap()[i],
            d.vel_ned.as_ref().unwrap()[i],
        );
        let w = d.rates_body.as_ref().unwrap()[i];
        let a = d.accel_body.as_ref().unwrap()[i] / G0;
        let c = d.controls.as_ref().unwrap()[i];
        let cells = [
            d.time[i] * 1e3,
            p.x,
            p.y,
            p.z,
            e.roll.to_degrees(),
            e.pitch.to_degrees(),
            e.yaw.to_degrees(),
            v.x,
            v.y,
            v.z,
            w.x.to_degrees(),
            w.y.to_degrees(),
            w.z.to_degrees(),
            d.airspeed.as_ref().unwrap()[i],
            a.x,
            a.y,
            a.z,
            c.throttle,
            c.elevator.to_degrees(),
            c.aileron.to_degrees(),
            c.rudder.to_degrees(),
        ];
        let row: Vec<String> = cells.iter().map(|x| x.to_string()).collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    let logger = dir.path().join("logger.csv");
    std::fs::write(&logger, text).unwrap();
    let map = "time=t_ms:ms,north=n,east=e,down=d,roll=phi:deg,pitch=theta:deg,yaw=psi:deg,\
               vn=vn,ve=ve,vd=vd,p=P:deg/s,q=Q:deg/s,r=R:deg/s,airspeed=tas,ax=fx:g,ay=fy:g,\
               az=fz:g,throttle=thr,elevator=de:deg,aileron=da:deg,rudder=dr:deg";
    let args = ["--free", "c_m_alpha,c_m_0", "--json"];
    let plain = ok(&[
        &["identify", "--flight", csv.to_str().unwrap()][..],
        &args[..],
    ]
    .concat());
    let (mapped, report) = ok_with_stderr(
        &[
            &[
                "identify",
                "--flight",
                logger.to_str().unwrap(),
                "--columns",
                map,
            ][..],
            &args[..],
        ]
        .concat(),
    );
    assert!(
        report.contains("CSV with a column map") && report.contains("accelerometer  fx [g]"),
        "{report}"
    );
    let (a, b) = (identified_c_m_alpha(&plain), identified_c_m_alpha(&mapped));
    assert!((a / -3.3 - 1.0).abs() < 0.05, "{plain}");
    // The same numbers to the rounding of the units' conversions.
    assert!((a - b).abs() < 1e-6 * a.abs(), "{a} vs {b}");
}

#[test]
fn identify_reads_a_px4_ulog() {
    let dir = tempfile::tempdir().unwrap();
    let csv = flight_for_identify(dir.path());
    let d = data::read(&csv).unwrap();
    // The flight as PX4 logs it: local position and velocity, the attitude quaternion, body
    // rates, normalised commands (±1 = ±25°: aileron +roll, elevator −pitch, rudder −yaw),
    // the accelerometer; MAV_TYPE 1, a fixed wing.
    let mut w = UlogWriter::new(Some([0; 8]));
    w.format(
        "vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;float vy;\
         float vz;",
    );
    w.format(ATT);
    w.format("vehicle_angular_velocity:uint64_t timestamp;float[3] xyz;");
    w.format("actuator_controls_0:uint64_t timestamp;float[8] control;");
    w.format("vehicle_acceleration:uint64_t timestamp;float[3] xyz;");
    w.param_i32("MAV_TYPE", 1);
    let ids = [
        "vehicle_local_position",
        "vehicle_attitude",
        "vehicle_angular_velocity",
        "actuator_controls_0",
        "vehicle_acceleration",
    ]
    .map(|t| w.subscribe(t));
    let k = 25f64.to_radians();
    for i in 0..d.len() {
        let t = 1_000_000 + (d.time[i] * 1e6).round() as u64;
        let (p, v) = (d.pos_ned[i], d.vel_ned.as_ref().unwrap()[i]);
        w.data_f32(ids[0], t, &[p.x, p.y, p.z, v.x, v.y, v.z].map(|x| x as f32));
        let q = DQuat::from_mat3(&d.attitude.as_ref().unwrap()[i].to_matrix());
        w.data_f32(ids[1], t, &[q.w, q.x, q.y, q.z].map(|x| x as f32));
        let r = d.rates_body.as_ref().unwrap()[i];
        w.data_f32(ids[2], t, &[r.x, r.y, r.z].map(|x| x as f32));
        let c = d.controls.as_ref().unwrap()[i];
        let mut control = [c.aileron / k, -c.elevator / k, -c.rudder / k, c.throttle]
            .map(|x| x as f32)
            .to_vec();
        control.extend([0.0; 4]);
        // Logged as the autopilot sends them, a moment before the states they lead to.
        w.data_f32(ids[3], t - 1000, &control);
        let a = d.accel_body.as_ref().unwrap()[i];
        w.data_f32(ids[4], t, &[a.x, a.y, a.z].map(|x| x as f32));
    }
    let ulg = dir.path().join("flight.ulg");
    std::fs::write(&ulg, &w.bytes).unwrap();
    let (out, report) = ok_with_stderr(&[
        "identify",
        "--flight",
        ulg.to_str().unwrap(),
        "--free",
        "c_m_alpha,c_m_0",
        "--json",
    ]);
    assert!(
        report.contains("PX4 ULog") && report.contains("accelerometer  vehicle_acceleration"),
        "{report}"
    );
    let c_m_alpha = identified_c_m_alpha(&out);
    assert!((c_m_alpha / -3.3 - 1.0).abs() < 0.05, "{out}");
}
