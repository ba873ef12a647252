//! Flight-data CSV: the shared JSBSim sample, every kind of bad file, round trips, JSBSim's own
//! output, unit variants, and random input (which must never panic).

use glam::DVec3;
use proptest::prelude::*;
use wireflight::data::{
    self, DataError, DataErrorKind, FlightData, Metadata, DERIVED_RATES_BODY, DERIVED_VEL_BODY,
    DERIVED_VEL_NED,
};
use wireflight::data::{Controls, VehicleKind};
use wireflight::geometry::euler::EulerZyx;

use crate::support::mk82;

fn err(text: &str) -> DataError {
    match data::parse(text, "bad.csv") {
        Ok(d) => panic!("parsed {} rows from bad input:\n{text}", d.len()),
        Err(e) => e,
    }
}

/// The error names the file, the line and (when given) the column, and contains `words`.
fn check(e: &DataError, line: usize, column: Option<&str>, words: &[&str]) {
    let msg = e.to_string();
    assert!(msg.starts_with("bad.csv: "), "{msg}");
    assert_eq!(e.line, Some(line), "{msg}");
    assert!(msg.contains(&format!("line {line}")), "{msg}");
    if let Some(c) = column {
        assert_eq!(e.column.as_deref(), Some(c), "{msg}");
        assert!(msg.contains(&format!("column `{c}`")), "{msg}");
    }
    for w in words {
        assert!(msg.contains(w), "`{w}` not in: {msg}");
    }
}

const HEAD: &str =
    "# vehicle: point-mass\ntime_s,north_m,east_m,down_m,pitch_deg,roll_deg,yaw_deg\n";

// ---------------------------------------------------------------------------------------------
// The shared JSBSim sample

#[test]
fn mk82_sample_reads() {
    let d = mk82();
    assert_eq!(d.meta.vehicle, Some(VehicleKind::PointMass));
    assert_eq!(d.meta.latitude_deg, Some(0.0));
    assert_eq!(d.meta.longitude_deg, Some(0.0));
    assert_eq!(d.meta.altitude_m, Some(2010.0));
    assert!(d.meta.source.as_deref().unwrap().contains("JSBSim"));
    // 875 lines: 5 metadata lines, the header and 869 rows (0 to 43.4 s in steps of 0.04/0.06).
    assert_eq!(d.len(), 869);
    assert_eq!(d.time[0], 0.0);
    assert!((d.duration() - 43.4).abs() < 1e-9);
    assert!(d.time.windows(2).all(|w| w[1] > w[0]));
    d.validate().unwrap();
    let v0 = d.vel_ned.as_ref().unwrap()[0];
    assert!(
        v0.abs_diff_eq(DVec3::new(-57.912, 0.0, -170.956), 1e-3),
        "{v0}"
    );
    let att = d.attitude.as_ref().expect("attitude");
    assert!((att[0].pitch.to_degrees() - 89.994817).abs() < 1e-9);
    assert!(d.controls.is_none() && d.vel_body.is_some() && d.rates_body.is_some());
    assert_eq!(d.derived, vec![DERIVED_RATES_BODY, DERIVED_VEL_BODY]);
}

#[test]
fn mk82_derived_channels_are_sane() {
    let d = mk82();
    // Velocity derived from the (noisy) positions agrees with the recorded velocity.
    let mut from_pos = FlightData::new(d.meta.clone(), d.time.clone(), d.pos_ned.clone());
    from_pos.derive_missing();
    assert_eq!(from_pos.derived, vec![DERIVED_VEL_NED]);
    let recorded = d.vel_ned.as_ref().unwrap();
    let derived = from_pos.vel_ned.as_ref().unwrap();
    let n = d.len();
    let rms = |f: &dyn Fn(usize) -> f64, r: std::ops::Range<usize>| {
        let len = r.len() as f64;
        (r.map(|i| f(i).powi(2)).sum::<f64>() / len).sqrt()
    };
    let rms_smooth = rms(&|i| (derived[i] - recorded[i]).length(), 1..n - 1);
    let rms_central = rms(
        &|i| {
            let c = (d.pos_ned[i + 1] - d.pos_ned[i - 1]) / (d.time[i + 1] - d.time[i - 1]);
            (c - recorded[i]).length()
        },
        1..n - 1,
    );
    println!("mk82 velocity from positions: RMS error {rms_smooth:.3} m/s (central differences {rms_central:.3} m/s)");
    assert!(rms_smooth < 1.0, "{rms_smooth}");
    assert!(rms_smooth < rms_central / 2.0);
    // Body rates derived from attitude: the angles flip by 180° in yaw and roll as the bomb
    // pitches over the vertical at the start, and wrap at ±180° as it spins (up to about
    // 270°/s in roll); neither may spike.
    let rates = d.rates_body.as_ref().unwrap();
    let max = rates
        .iter()
        .map(|r| r.abs().max_element())
        .fold(0.0, f64::max);
    let max_step = rates
        .windows(2)
        .map(|w| (w[1] - w[0]).abs().max_element())
        .fold(0.0, f64::max);
    println!(
        "mk82 derived body rates: max {:.1} deg/s, max change between samples {:.1} deg/s",
        max.to_degrees(),
        max_step.to_degrees()
    );
    assert!(max < 300f64.to_radians(), "max body rate {max} rad/s");
    // A wrap or flip left in would jump by hundreds of degrees per second.
    assert!(max_step < 40f64.to_radians(), "max step {max_step} rad/s");
    // Over the vertical (first 0.5 s) the bomb only pitches: q ≈ 0…20°/s, p and r ≈ 0.
    for (t, r) in d.time.iter().zip(rates).take_while(|(t, _)| **t <= 0.5) {
        assert!(r.x.abs() < 0.01 && r.z.abs() < 0.01, "t {t}: {r}");
        assert!((0.0..0.4).contains(&r.y), "t {t}: {r}");
    }
    // Body velocity: same speed as the NED velocity.
    for (vb, vn) in d.vel_body.as_ref().unwrap().iter().zip(recorded) {
        assert!((vb.length() - vn.length()).abs() < 1e-9);
    }
}

// ---------------------------------------------------------------------------------------------
// Bad files

#[test]
fn non_numeric_cell() {
    let e = err(&format!("{HEAD}0,0,0,0,1,2,3\n0.1,0,0,0,abc,2,3\n"));
    check(&e, 4, Some("pitch_deg"), &["not a number", "abc"]);
    assert!(matches!(e.kind, DataErrorKind::NonNumeric { .. }));
    // An empty cell is a channel not sampled then: all of its set or none.
    let e = err(&format!("{HEAD}0,0,,0,1,2,3\n"));
    check(
        &e,
        3,
        Some("east_m"),
        &["empty while `north_m` has a value", "position"],
    );
    assert!(matches!(e.kind, DataErrorKind::PartlyEmpty { .. }));
}

#[test]
fn nan_and_infinite_cells() {
    let e = err(&format!("{HEAD}0,0,0,0,1,2,3\n0.1,0,0,NaN,1,2,3\n"));
    check(&e, 4, Some("down_m"), &["not a finite number", "NaN"]);
    assert!(matches!(e.kind, DataErrorKind::NonFinite { .. }));
    let e = err(&format!("{HEAD}0,0,0,0,1,2,-inf\n"));
    check(&e, 3, Some("yaw_deg"), &["not a finite number", "-inf"]);
    let e = err(&format!("{HEAD}0,1e999,0,0,1,2,3\n"));
    check(&e, 3, Some("north_m"), &["not a finite number"]);
}

#[test]
fn rows_of_the_wrong_length() {
    let e = err(&format!("{HEAD}0,0,0,0,1,2,3\n\n0.1,0,0,0,1,2\n"));
    check(&e, 5, None, &["6 cells", "header has 7"]);
    let e = err(&format!("{HEAD}0,0,0,0,1,2,3,4\n"));
    check(&e, 3, None, &["8 cells"]);
}

#[test]
fn non_increasing_time() {
    let e = err(&format!(
        "{HEAD}0,0,0,0,1,2,3\n0.5,0,0,0,1,2,3\n0.5,0,0,0,1,2,3\n"
    ));
    check(
        &e,
        5,
        Some("time_s"),
        &["0.5 s is not after 0.5 s on line 4"],
    );
    let e = err(&format!("{HEAD}1,0,0,0,1,2,3\n0.25,0,0,0,1,2,3\n"));
    check(&e, 4, Some("time_s"), &["0.25", "1 s", "line 3"]);
}

#[test]
fn missing_columns() {
    // Fixed-wing needs attitude and controls.
    let e = err(
        "# vehicle: fixed-wing\ntime_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,\
         throttle,elevator_deg,rudder_deg\n0,0,0,0,0,0,0,0.5,0,0\n",
    );
    check(
        &e,
        2,
        None,
        &["missing required column aileron_deg", "fixed-wing"],
    );
    assert!(matches!(e.kind, DataErrorKind::MissingColumn { .. }));
    // Time and position always.
    let e = err("# source: x\n\nnorth_m,east_m,time\n0,0,0\n");
    check(&e, 3, None, &["columns time_s, down_m"]);
    // Sets come whole.
    let e = err("time_s,north_m,east_m,down_m,vn_mps,vd_mps\n0,0,0,0,1,1\n");
    check(
        &e,
        1,
        None,
        &["ve_mps", "NED velocity", "`vn_mps` is present"],
    );
    // Point-mass data need neither attitude nor controls.
    let d = data::parse("time_s,north_m,east_m,down_m\n0,0,0,0\n1,1,0,0\n", "ok.csv").unwrap();
    assert!(d.attitude.is_none() && d.controls.is_none());
}

#[test]
fn empty_and_header_only() {
    for text in ["", "\n\n  \n", "# vehicle: point-mass\n# source: nothing\n"] {
        let e = err(text);
        assert!(matches!(e.kind, DataErrorKind::Empty), "{e}");
        assert!(e.to_string().contains("empty file"), "{e}");
        assert!(e.to_string().starts_with("bad.csv: line "), "{e}");
    }
    let e = err("# vehicle: point-mass\ntime_s,north_m,east_m,down_m\n\n# nothing\n");
    check(&e, 2, None, &["header only", "no data rows"]);
}

#[test]
fn duplicate_columns() {
    let e = err("time_s,north_m,east_m,down_m,north_m\n0,0,0,0,0\n");
    check(
        &e,
        1,
        Some("north_m"),
        &["duplicate column", "column 2 `north_m`"],
    );
    let e = err("time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,roll_rad\n");
    check(&e, 1, Some("roll_rad"), &["duplicate column", "`roll_deg`"]);
    let e = err("time_s,north_m,east_m,down_m,note,note\n0,0,0,0,a,b\n");
    check(&e, 1, Some("note"), &["duplicate column"]);
}

#[test]
fn bad_metadata() {
    let e = err("# source: test\n# altitude_m: high\ntime_s,north_m,east_m,down_m\n0,0,0,0\n");
    check(&e, 2, None, &["altitude_m", "high", "not a number"]);
    let e = err("# vehicle: rocket\n");
    check(&e, 1, None, &["vehicle", "rocket"]);
}

#[test]
fn unreadable_and_non_utf8_files() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.csv");
    let e = data::read(&missing).unwrap_err();
    assert!(matches!(e.kind, DataErrorKind::Unreadable(_)));
    assert!(e.to_string().contains("nope.csv"), "{e}");
    assert!(e.to_string().contains("cannot read"), "{e}");
    assert!(std::error::Error::source(&e).is_some());

    let bin = dir.path().join("bin.csv");
    std::fs::write(&bin, b"time_s,north_m,east_m,down_m\n0,0,0,0\n1,\xff,0,0\n").unwrap();
    let e = data::read(&bin).unwrap_err();
    assert_eq!(e.line, Some(3));
    assert!(e.to_string().contains("bin.csv: line 3: not UTF-8"), "{e}");

    // Errors from read name the path.
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "time_s,north_m,east_m,down_m\n0,0,0,x\n").unwrap();
    let e = data::read(&bad).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("{}: line 2, column `down_m`", bad.display())),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// Leniency

#[test]
fn unknown_columns_order_comments_crlf_and_bom_are_accepted() {
    let text = "\u{feff}# vehicle: point-mass\r\n# a plain comment\r\n\r\n\
                note, down_m ,time_s,east_m,north_m,extra\r\n\
                first,3,0,2,1,\r\n# a comment between rows\r\n\
                second,6,1.5,4,2,x\r\n";
    let d = data::parse(text, "lenient.csv").unwrap();
    assert_eq!(d.time, vec![0.0, 1.5]);
    assert_eq!(d.pos_ned[0], DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(d.pos_ned[1], DVec3::new(2.0, 4.0, 6.0));
    assert_eq!(d.derived, vec![DERIVED_VEL_NED]);
    let v = d.vel_ned.unwrap();
    assert!(v[0].abs_diff_eq(DVec3::new(2.0, 4.0, 6.0) / 3.0, 1e-12));
}

#[test]
fn radian_variants_equal_degrees() {
    let deg = "time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,p_dps,q_dps,r_dps,\
               throttle,elevator_deg,aileron_deg,rudder_deg\n\
               0,0,0,0,10,-20,170,5,-6,7,0.5,-3,4,-5\n\
               0.1,1,0,0,11,-21,-179,5,-6,7,0.6,-2,3,-4\n";
    let rad = format!(
        "time_s,north_m,east_m,down_m,roll_rad,pitch_rad,yaw_rad,p_radps,q_radps,r_radps,\
         throttle,elevator_rad,aileron_rad,rudder_rad\n\
         0,0,0,0,{},{},{},{},{},{},0.5,{},{},{}\n\
         0.1,1,0,0,{},{},{},{},{},{},0.6,{},{},{}\n",
        10f64.to_radians(),
        (-20f64).to_radians(),
        170f64.to_radians(),
        5f64.to_radians(),
        (-6f64).to_radians(),
        7f64.to_radians(),
        (-3f64).to_radians(),
        4f64.to_radians(),
        (-5f64).to_radians(),
        11f64.to_radians(),
        (-21f64).to_radians(),
        (-179f64).to_radians(),
        5f64.to_radians(),
        (-6f64).to_radians(),
        7f64.to_radians(),
        (-2f64).to_radians(),
        3f64.to_radians(),
        (-4f64).to_radians(),
    );
    let a = data::parse(deg, "deg.csv").unwrap();
    let b = data::parse(&rad, "rad.csv").unwrap();
    let att = a.attitude.as_ref().unwrap();
    assert!((att[0].roll - 10f64.to_radians()).abs() < 1e-15);
    assert!((att[0].pitch + 20f64.to_radians()).abs() < 1e-15);
    assert!((att[1].yaw + 179f64.to_radians()).abs() < 1e-15);
    assert!((a.rates_body.as_ref().unwrap()[0].y + 6f64.to_radians()).abs() < 1e-15);
    assert_eq!(
        a.controls.as_ref().unwrap()[1],
        Controls {
            throttle: 0.6,
            elevator: (-2f64).to_radians(),
            aileron: 3f64.to_radians(),
            rudder: (-4f64).to_radians(),
        }
    );
    close(&a, &b, 1e-15);
    // Rates and body velocity present or derived as expected.
    assert_eq!(a.derived, vec![DERIVED_VEL_NED, DERIVED_VEL_BODY]);
}

// ---------------------------------------------------------------------------------------------
// Round trips

fn close(a: &FlightData, b: &FlightData, tol: f64) {
    assert_eq!(a.meta, b.meta);
    assert_eq!(a.derived, b.derived);
    assert_eq!(a.len(), b.len());
    let near = |x: f64, y: f64| (x - y).abs() <= tol * (1.0 + x.abs().max(y.abs()));
    let near3 = |x: DVec3, y: DVec3| near(x.x, y.x) && near(x.y, y.y) && near(x.z, y.z);
    for i in 0..a.len() {
        assert!(near(a.time[i], b.time[i]));
        assert!(near3(a.pos_ned[i], b.pos_ned[i]), "{i}");
    }
    let v3 = |x: &Option<Vec<DVec3>>, y: &Option<Vec<DVec3>>, what: &str| {
        assert_eq!(x.is_some(), y.is_some(), "{what}");
        if let (Some(x), Some(y)) = (x, y) {
            for (p, q) in x.iter().zip(y) {
                assert!(near3(*p, *q), "{what}: {p} vs {q}");
            }
        }
    };
    v3(&a.vel_ned, &b.vel_ned, "vel_ned");
    v3(&a.vel_body, &b.vel_body, "vel_body");
    v3(&a.rates_body, &b.rates_body, "rates_body");
    v3(&a.accel_body, &b.accel_body, "accel_body");
    let att = |x: &Option<Vec<EulerZyx>>| {
        x.as_ref().map(|v| {
            v.iter()
                .map(|e| DVec3::new(e.yaw, e.pitch, e.roll))
                .collect()
        })
    };
    v3(&att(&a.attitude), &att(&b.attitude), "attitude");
    assert_eq!(a.airspeed.is_some(), b.airspeed.is_some());
    if let (Some(x), Some(y)) = (&a.airspeed, &b.airspeed) {
        assert!(x.iter().zip(y).all(|(p, q)| near(*p, *q)));
    }
    let ctl = |x: &Option<Vec<Controls>>| {
        x.as_ref().map(|v| {
            v.iter()
                .flat_map(|c| [c.throttle, c.elevator, c.aileron, c.rudder])
                .collect::<Vec<f64>>()
        })
    };
    assert_eq!(a.controls.is_some(), b.controls.is_some());
    if let (Some(x), Some(y)) = (ctl(&a.controls), ctl(&b.controls)) {
        assert!(x.iter().zip(&y).all(|(p, q)| near(*p, *q)));
    }
}

fn full_sample() -> FlightData {
    let n = 40;
    let time: Vec<f64> = (0..n)
        .map(|i| 0.1 * i as f64 + 0.013 * (i % 3) as f64)
        .collect();
    let f = |i: usize, k: f64| ((i as f64) * 0.37 + k).sin() * 10.0 + k;
    let v = |i: usize, k: f64| DVec3::new(f(i, k), f(i, k + 1.0), f(i, k + 2.0));
    FlightData {
        meta: Metadata {
            vehicle: Some(VehicleKind::FixedWing),
            aircraft: Some("aerosonde".into()),
            latitude_deg: Some(47.123456789),
            longitude_deg: Some(-122.5),
            altitude_m: Some(1234.5),
            mass_kg: Some(13.5),
            reference_area_m2: Some(0.55),
            source: Some("round-trip test".into()),
            other: vec![("weather".into(), "gusty: 5 m/s".into())],
        },
        pos_ned: (0..n).map(|i| v(i, 100.0)).collect(),
        attitude: Some(
            (0..n)
                .map(|i| EulerZyx::new(f(i, 0.1) / 4.0, f(i, 0.2) / 20.0, f(i, 0.3) / 12.0))
                .collect(),
        ),
        vel_ned: Some((0..n).map(|i| v(i, 3.0)).collect()),
        vel_body: Some((0..n).map(|i| v(i, 5.0)).collect()),
        rates_body: Some((0..n).map(|i| v(i, 0.01) / 30.0).collect()),
        airspeed: Some((0..n).map(|i| f(i, 20.0)).collect()),
        accel_body: Some(
            (0..n)
                .map(|i| v(i, 0.4) - DVec3::new(0.0, 0.0, 9.8))
                .collect(),
        ),
        controls: Some(
            (0..n)
                .map(|i| Controls {
                    throttle: (f(i, 0.0) / 20.0 + 0.5).clamp(0.0, 1.0),
                    elevator: f(i, 0.5) / 100.0,
                    aileron: -f(i, 0.6) / 100.0,
                    rudder: f(i, 0.7) / 200.0,
                })
                .collect(),
        ),
        derived: vec![],
        sampling: Default::default(),
        time,
    }
}

#[test]
fn round_trip_all_channels() {
    let d = full_sample();
    d.validate().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("all.csv");
    data::write(&path, &d).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.starts_with("# vehicle: fixed-wing\n# aircraft: aerosonde\n"),
        "{text}"
    );
    assert!(text.contains(
        "\ntime_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps,\
         u_mps,v_mps,w_mps,p_dps,q_dps,r_dps,airspeed_mps,ax_mps2,ay_mps2,az_mps2,throttle,\
         elevator_deg,aileron_deg,rudder_deg\n"
    ));
    let back = data::read(&path).unwrap();
    close(&d, &back, 1e-14);
    // Channels in native units come back bit for bit.
    assert_eq!(d.time, back.time);
    assert_eq!(d.pos_ned, back.pos_ned);
    assert_eq!(d.vel_ned, back.vel_ned);
    assert_eq!(d.accel_body, back.accel_body);
    // No temporaries left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn round_trip_skips_derived_channels_and_rederives_them() {
    let d = mk82();
    let text = data::to_csv_string(&d);
    let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
    assert_eq!(
        header,
        "time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps"
    );
    let back = data::parse(&text, "again.csv").unwrap();
    close(&d, &back, 1e-12);
}

#[test]
fn writing_invalid_data_fails() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.csv");
    let d = FlightData::new(Metadata::default(), vec![1.0, 1.0], vec![DVec3::ZERO; 2]);
    let e = data::write(&path, &d).unwrap_err();
    assert!(e.to_string().contains("x.csv"), "{e}");
    assert!(data::write(&path, &FlightData::default()).is_err());
    assert!(!path.exists());
}

// ---------------------------------------------------------------------------------------------
// JSBSim output

const FT: f64 = 0.3048;

#[test]
fn jsbsim_header_is_understood() {
    let lat0: f64 = 0.6;
    let lon0: f64 = -2.1;
    let text = format!(
        "Time, /fdm/jsbsim/position/lat-gc-rad, /fdm/jsbsim/position/long-gc-rad, \
         /fdm/jsbsim/position/h-sl-ft, /fdm/jsbsim/attitude/phi-rad, \
         /fdm/jsbsim/attitude/theta-rad, /fdm/jsbsim/attitude/psi-rad, \
         /fdm/jsbsim/velocities/v-north-fps, /fdm/jsbsim/velocities/v-east-fps, \
         /fdm/jsbsim/velocities/v-down-fps, /fdm/jsbsim/velocities/p-rad_sec, \
         /fdm/jsbsim/velocities/q-rad_sec, /fdm/jsbsim/velocities/r-rad_sec, \
         /fdm/jsbsim/velocities/u-fps, /fdm/jsbsim/velocities/v-fps, \
         /fdm/jsbsim/velocities/w-fps, /fdm/jsbsim/aero/alpha-deg\n\
         0, {lat0}, {lon0}, 1000, 0.1, 0.2, -3.1, 100, 10, -5, 0.01, 0.02, 0.03, 90, 1, 2, 4.5\n\
         0.5, {}, {}, 990, 0.11, 0.21, 3.1, 101, 11, -4, 0.011, 0.021, 0.031, 91, 2, 3, 4.6\n\
         1.0, {}, {}, 980, 0.12, 0.22, 3.0, 102, 12, -3, 0.012, 0.022, 0.032, 92, 3, 4, 4.7\n",
        lat0 + 1e-5,
        lon0 + 2e-5,
        lat0 + 2e-5,
        lon0 + 4e-5,
    );
    let d = data::parse(&text, "jsb.csv").unwrap();
    let r = 6_371_000.0;
    assert_eq!(d.len(), 3);
    assert_eq!(d.time, vec![0.0, 0.5, 1.0]);
    assert!((d.meta.latitude_deg.unwrap() - lat0.to_degrees()).abs() < 1e-12);
    assert!((d.meta.longitude_deg.unwrap() - lon0.to_degrees()).abs() < 1e-12);
    assert!((d.meta.altitude_m.unwrap() - 1000.0 * FT).abs() < 1e-9);
    assert!(d.meta.source.is_some());
    assert_eq!(d.pos_ned[0], DVec3::ZERO);
    let want = DVec3::new(2e-5 * r, 4e-5 * r * lat0.cos(), 20.0 * FT);
    assert!(d.pos_ned[2].abs_diff_eq(want, 1e-6), "{}", d.pos_ned[2]);
    let att = d.attitude.as_ref().unwrap();
    assert_eq!(att[1], EulerZyx::new(3.1, 0.21, 0.11));
    let vn = d.vel_ned.as_ref().unwrap();
    assert!(vn[0].abs_diff_eq(DVec3::new(100.0, 10.0, -5.0) * FT, 1e-12));
    let vb = d.vel_body.as_ref().unwrap();
    assert!(vb[2].abs_diff_eq(DVec3::new(92.0, 3.0, 4.0) * FT, 1e-12));
    assert_eq!(
        d.rates_body.as_ref().unwrap()[1],
        DVec3::new(0.011, 0.021, 0.031)
    );
    assert!(d.derived.is_empty());
}

#[test]
fn jsbsim_degrees_metres_and_short_names() {
    let text = "Time,attitude/phi-deg,attitude/theta-deg,attitude/psi-deg,\
                /fdm/jsbsim/position/lat-geod-deg,/fdm/jsbsim/position/long-gc-deg,\
                /fdm/jsbsim/position/h-sl-meters\n\
                0,10,20,30,45,7,100\n0.1,11,21,31,45,7,99\n";
    let d = data::parse(text, "jsb.csv").unwrap();
    assert_eq!(d.meta.latitude_deg, Some(45.0));
    assert_eq!(d.meta.altitude_m, Some(100.0));
    assert!(d.pos_ned[1].abs_diff_eq(DVec3::new(0.0, 0.0, 1.0), 1e-9));
    let e = d.attitude.as_ref().unwrap()[0];
    assert!((e.roll - 10f64.to_radians()).abs() < 1e-15);
    assert!((e.yaw - 30f64.to_radians()).abs() < 1e-15);
    assert_eq!(
        d.derived,
        vec![DERIVED_VEL_NED, DERIVED_RATES_BODY, DERIVED_VEL_BODY]
    );
}

#[test]
fn jsbsim_without_position_is_an_error() {
    let e = err("Time,/fdm/jsbsim/attitude/phi-rad,/fdm/jsbsim/position/h-sl-ft\n0,0,0\n");
    check(&e, 1, None, &["lat-geod-rad", "long-gc-rad", "JSBSim"]);
    assert!(!e.to_string().contains("h-sl-ft (or"), "{e}");
    let e = err("Time,/fdm/jsbsim/position/lat-gc-rad,/fdm/jsbsim/position/long-gc-rad,/fdm/jsbsim/position/h-sl-ft\n0,0,0,0\n0,0,0,0\n");
    check(&e, 3, Some("Time"), &["not after"]);
}

// ---------------------------------------------------------------------------------------------
// Random input never panics

const VOCAB: &[&str] = &[
    "time_s",
    "north_m",
    "east_m",
    "down_m",
    "roll_deg",
    "pitch_rad",
    "yaw_deg",
    "p_radps",
    "q_dps",
    "r_dps",
    "vn_mps",
    "ve_mps",
    "vd_mps",
    "u_mps",
    "throttle",
    "elevator_deg",
    "aileron_rad",
    "rudder_deg",
    "Time",
    "/fdm/jsbsim/position/lat-gc-rad",
    "/fdm/jsbsim/position/long-gc-deg",
    "/fdm/jsbsim/position/h-sl-ft",
    "/fdm/jsbsim/attitude/psi-rad",
    "# vehicle: fixed-wing",
    "# vehicle: point-mass",
    "# altitude_m: 1e308",
    "#",
    ":",
    "",
    ",",
    "0",
    "1",
    "-1",
    "1e308",
    "-1e308",
    "5e-324",
    "NaN",
    "inf",
    "0.5",
    "180",
    "-180",
    "90",
    "\n",
    "\r\n",
    " ",
    "\u{feff}",
    "é",
];

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = data::parse(&text, "fuzz.csv");
    }

    #[test]
    fn random_tokens_never_panic(tokens in proptest::collection::vec(0..VOCAB.len(), 0..120)) {
        let text: String = tokens.iter().map(|&i| VOCAB[i]).collect::<Vec<_>>().join(",");
        let _ = data::parse(&text, "fuzz.csv");
        let text: String = tokens.iter().map(|&i| VOCAB[i]).collect::<Vec<_>>().join("\n");
        let _ = data::parse(&text, "fuzz.csv");
    }

    #[test]
    fn random_numeric_files_parse_or_fail_cleanly(
        cells in proptest::collection::vec(
            prop_oneof![any::<f64>(), -1e6f64..1e6, Just(0.0)], 0..200),
        header in proptest::collection::vec(0..22usize, 1..12),
    ) {
        let names: Vec<&str> = header.iter().map(|&i| VOCAB[i]).collect();
        let mut text = names.join(",");
        text.push('\n');
        for row in cells.chunks(names.len()) {
            let row: Vec<String> = row.iter().map(|v| v.to_string()).collect();
            text.push_str(&row.join(","));
            text.push('\n');
        }
        if let Ok(d) = data::parse(&text, "fuzz.csv") {
            prop_assert!(d.validate().is_ok() || d.len() < 2);
            let again = data::to_csv_string(&d);
            let _ = data::parse(&again, "again.csv");
        }
    }

    #[test]
    fn valid_random_data_round_trips(
        steps in proptest::collection::vec(1e-6f64..10.0, 1..40),
        start in -1e6f64..1e6,
        seed in -1e4f64..1e4,
    ) {
        let mut time = vec![start];
        for s in &steps {
            let t = time.last().unwrap() + s;
            time.push(t);
        }
        prop_assume!(time.windows(2).all(|w| w[1] > w[0]));
        let pos = time.iter().enumerate()
            .map(|(i, t)| DVec3::new(seed * i as f64, t.sin(), -seed / (1.0 + i as f64)))
            .collect();
        let mut d = FlightData::new(Metadata::default(), time, pos);
        d.attitude = Some(d.time.iter().map(|t| EulerZyx::new(t.sin() * 3.0, t.cos(), seed.sin())).collect());
        d.derive_missing();
        let back = data::parse(&data::to_csv_string(&d), "rt.csv").unwrap();
        prop_assert_eq!(&back.time, &d.time);
        prop_assert_eq!(&back.pos_ned, &d.pos_ned);
        prop_assert_eq!(&back.derived, &d.derived);
        let (a, b) = (d.attitude.unwrap(), back.attitude.unwrap());
        for (x, y) in a.iter().zip(&b) {
            prop_assert!((x.yaw - y.yaw).abs() < 1e-14 && (x.pitch - y.pitch).abs() < 1e-14
                && (x.roll - y.roll).abs() < 1e-14);
        }
    }
}
