//! Real flight logs in: PX4 ULog (real sample logs from PX4's pyulog, cut down; synthetic
//! files for the paths the samples do not take) and CSV through a column map. Good files give
//! the numbers an independent reader gives; broken files give errors naming the file and the
//! place, never a panic.

use std::f64::consts::PI;
use std::path::Path;

use wireflight::data::mapped::ColumnMap;
use wireflight::data::px4::{self, UlogOptions};
use wireflight::data::ulog::UlogFile;
use wireflight::data::{load, Channel, LoadOptions, VehicleKind, EARTH_RADIUS_M};

use crate::support::cli::{ok_with_stderr, stderr, stdout, wireflight};
use crate::support::data_file;
use crate::support::ulog::UlogWriter;
use crate::support::Rng;

fn ulog_bytes(name: &str) -> Vec<u8> {
    std::fs::read(data_file(name)).unwrap()
}

fn from_bytes(bytes: &[u8]) -> Result<wireflight::data::FlightData, String> {
    let log =
        UlogFile::parse(bytes, "x.ulg", |t| px4::TOPICS.contains(&t)).map_err(|e| e.to_string())?;
    px4::from_ulog(&log, "x.ulg", &UlogOptions::default())
        .map(|(d, _)| d)
        .map_err(|e| e.to_string())
}

// ---------------------------------------------------------------------------------------------
// Real PX4 logs

/// PX4 SITL quadrotor taking off to about 2 m and landing (pyulog's `sample_px4_events.ulg`).
/// The values at 5, 15 and 25 s are pyulog's, interpolated linearly at the same times.
#[test]
fn px4_sitl_log_matches_pyulog() {
    let loaded = load(&data_file("px4-sitl-hop.ulg"), &LoadOptions::default()).unwrap();
    let d = &loaded.data;
    // Position and attitude overlap from 0.088 s to 31.088 s. Each topic keeps its own
    // samples there: position at 10.4 Hz, attitude at 20.8 Hz (thinned to at most 20 a
    // second, the default), rates at 50 Hz (thinned likewise); the rows are their times.
    let own = |c: Channel| d.sampling.count(c, d.len());
    assert_eq!(
        [
            own(Channel::Position),
            own(Channel::Attitude),
            own(Channel::Rates)
        ],
        [310, 621, 621]
    );
    assert_eq!(d.len(), 1241);
    for i in 0..d.len() {
        assert!(
            Channel::ALL.iter().any(|&c| d.sampling.at(c, i)),
            "row {i} is no channel's sample"
        );
    }
    for (t, z, x) in [
        (5.0, -0.033887953425829224, -7.202928617726484e-05),
        (15.0, -0.04205239392243899, 0.019029540941119194),
        (25.0, -0.4834666561621884, 0.00759859755635261),
    ] {
        let p = d.position_at(t).unwrap();
        assert!((p.z - z).abs() < 1e-6, "{t}: {} vs {z}", p.z);
        assert!((p.x - x).abs() < 1e-6, "{t}: {} vs {x}", p.x);
    }
    let lowest = d.pos_ned.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    assert!((-2.16..-1.9).contains(&lowest), "{lowest}");
    assert_eq!(d.meta.latitude_deg, Some(47.3977418));
    assert_eq!(d.meta.longitude_deg, Some(8.5455939));
    assert!((d.meta.altitude_m.unwrap() - 487.957).abs() < 1e-3);
    // Measured attitude, rates and velocity: nothing derived.
    assert!(d.attitude.is_some() && d.rates_body.is_some() && d.vel_ned.is_some());
    assert_eq!(d.derived, ["vel_body"]);
    let yaw_max = d
        .attitude
        .as_ref()
        .unwrap()
        .iter()
        .map(|a| a.yaw.to_degrees())
        .fold(f64::MIN, f64::max);
    assert!((1.4..1.6).contains(&yaw_max), "{yaw_max}");
    assert_eq!(d.meta.vehicle, None, "a quadrotor is no model family");
    let report = loaded.report.unwrap().to_string();
    for want in [
        "MAV_TYPE 2 (quadrotor)",
        "vehicle_local_position x, y, z",
        "xy_valid false in 31 % of samples; 1 estimator reset (jumps)",
        "vehicle_attitude q[0..4]",
        "vehicle_angular_velocity xyz[0..3]",
        "not used: PWM per output",
        "1241 rows (the times anything was sampled) over 31.0 s",
        "position      310 samples    10 Hz  filled in at 931 rows between",
        "give --vehicle",
    ] {
        assert!(report.contains(want), "{want}\n{report}");
    }
}

/// A VTOL on the ground (pyulog's `sample_log_small.ulg`): airspeed and actuator controls, a
/// dropout, 400 Hz rates resampled to 50 Hz, no global reference.
#[test]
fn px4_vtol_log_has_airspeed_controls_and_notes() {
    let (d, report) =
        px4::read(&data_file("px4-vtol-ground.ulg"), &UlogOptions::default()).unwrap();
    // Position (102 Hz), attitude (205 Hz), rates (404 Hz) and airspeed (94 Hz), each
    // thinned to at most 50 samples a second at their own times.
    assert_eq!(d.len(), 1193);
    assert_eq!(d.sampling.count(Channel::Attitude, d.len()), 318);
    assert!(d.airspeed.is_some() && d.controls.is_some());
    assert_eq!(d.meta.latitude_deg, None);
    let r = report.to_string();
    for want in [
        "MAV_TYPE 22 (VTOL)",
        "readings down to -3.6 m/s",
        "actuator_controls_0 control[0..4]",
        "no global reference: origin unknown",
        "1 logger dropout",
        "1193 rows (the times anything was sampled) over 6.5 s",
    ] {
        assert!(r.contains(want), "{want}\n{r}");
    }
    // A slower time base on request.
    let (slow, _) = px4::read(
        &data_file("px4-vtol-ground.ulg"),
        &UlogOptions {
            rate_hz: Some(10.0),
            ..UlogOptions::default()
        },
    )
    .unwrap();
    assert_eq!(slow.sampling.count(Channel::Position, slow.len()), 65);
    assert_eq!(slow.len(), 228);
}

/// Every prefix of a real log: a header or definitions section cut short is an error naming
/// the byte; a data section cut short keeps what came before and says so. Never a panic.
#[test]
fn truncated_ulog_files() {
    let bytes = ulog_bytes("px4-sitl-hop.ulg");
    let e = from_bytes(&bytes[..10]).unwrap_err();
    assert_eq!(
        e,
        "x.ulg: byte 0: the file is cut short in the header: the 16-byte header needs 16 bytes, 10 are left"
    );
    let e = from_bytes(&bytes[..500]).unwrap_err();
    assert!(
        e.starts_with("x.ulg: byte ") && e.contains("cut short in the definitions section"),
        "{e}"
    );
    // Cut in the data: the flight up to the cut, with a note.
    let cut = bytes.len() * 2 / 3;
    let log = UlogFile::parse(&bytes[..cut], "x.ulg", |t| px4::TOPICS.contains(&t)).unwrap();
    assert!(log.truncated_at.is_some());
    let (d, report) = px4::from_ulog(&log, "x.ulg", &UlogOptions::default()).unwrap();
    assert!((15.0..25.0).contains(&d.duration()), "{}", d.duration());
    assert!(report.to_string().contains("the file is cut short at byte"));
    // Many cut points, none panics.
    for k in 0..300 {
        let _ = from_bytes(&bytes[..k * bytes.len() / 300]);
    }
}

/// Random bytes overwritten: errors or notes, never a panic.
#[test]
fn corrupted_ulog_files_never_panic() {
    let bytes = ulog_bytes("px4-vtol-ground.ulg");
    let mut rng = Rng::new(16);
    for _ in 0..60 {
        let mut b = bytes.clone();
        for _ in 0..1 + rng.below(20) {
            let i = rng.below(b.len());
            b[i] = rng.next_u64() as u8;
        }
        let _ = from_bytes(&b);
    }
    let e = from_bytes(b"time_s,north_m\n0,0\n").unwrap_err();
    assert!(e.contains("not a ULog file"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// Synthetic ULog files for the other paths

const LOCAL: &str = "vehicle_local_position:uint64_t timestamp;float x;float y;float z;";
const ATT: &str = "vehicle_attitude:uint64_t timestamp;float[4] q;";

/// A file with local position at 100 Hz (moving north at 10 m/s) and level attitude at 50 Hz,
/// heading `yaw_deg`.
fn simple_log(yaw_deg: f64) -> UlogWriter {
    let mut w = UlogWriter::new(Some([0; 8]));
    w.format(LOCAL);
    w.format(ATT);
    w.param_i32("MAV_TYPE", 1);
    let p = w.subscribe("vehicle_local_position");
    let a = w.subscribe("vehicle_attitude");
    let h = (yaw_deg.to_radians() / 2.0) as f32;
    for k in 0..=200u64 {
        let t = 1_000_000 + k * 10_000;
        w.data_f32(p, t, &[(k as f32) * 0.1, 0.0, -50.0]);
        if k % 2 == 0 {
            w.data_f32(a, t, &[h.cos(), 0.0, 0.0, h.sin()]);
        }
    }
    w
}

#[test]
fn synthetic_ulog_resampled_onto_one_time_base() {
    let d = from_bytes(&simple_log(90.0).bytes).unwrap();
    // 2 s at 50 Hz (the faster of 100 Hz and 50 Hz, capped): 101 samples.
    assert_eq!(d.len(), 101);
    for k in [0, 37, 100] {
        assert!((d.pos_ned[k].x - 10.0 * d.time[k]).abs() < 1e-5);
        assert!((d.attitude.as_ref().unwrap()[k].yaw - PI / 2.0).abs() < 1e-6);
    }
    // Velocity derived from positions; no controls, so MAV_TYPE 1 stays without a vehicle.
    assert!(d.is_derived("vel_ned"));
    assert_eq!(d.meta.vehicle, None);
}

/// A log as a navigation filter and its sensors write one: position at 5 Hz, attitude at
/// 50 Hz and rates at 250 Hz, each topic at its own (offset) times, over 4 s.
fn multi_rate_log() -> UlogWriter {
    let mut w = UlogWriter::new(None);
    w.format(LOCAL);
    w.format(ATT);
    w.format("vehicle_angular_velocity:uint64_t timestamp;float[3] xyz;");
    let p = w.subscribe("vehicle_local_position");
    let a = w.subscribe("vehicle_attitude");
    let r = w.subscribe("vehicle_angular_velocity");
    // In time order, as a logger writes them: rates every 4 ms from 1 s, attitude every
    // 20 ms from 1.001 s, position every 200 ms from 1.0025 s.
    let mut messages: Vec<(u64, u16, Vec<f32>)> = Vec::new();
    for k in 0..1000u64 {
        let t = 1_000_000 + k * 4_000;
        messages.push((t, r, vec![0.1, 0.0, (k as f32) * 1e-3]));
    }
    for k in 0..200u64 {
        let t = 1_001_000 + k * 20_000;
        messages.push((t, a, vec![1.0, 0.0, 0.0, 0.0]));
    }
    for k in 0..20u64 {
        let t = 1_002_500 + k * 200_000;
        messages.push((t, p, vec![(k as f32) * 5.0, 0.0, -50.0]));
    }
    messages.sort_by_key(|m| m.0);
    for (t, id, fields) in messages {
        w.data_f32(id, t, &fields);
    }
    w
}

#[test]
fn a_multi_rate_ulog_keeps_every_channel_at_its_own_times() {
    let log = UlogFile::parse(&multi_rate_log().bytes, "m.ulg", |t| {
        px4::TOPICS.contains(&t)
    })
    .unwrap();
    let options = UlogOptions {
        rate_hz: Some(250.0),
        ..UlogOptions::default()
    };
    let (d, report) = px4::from_ulog(&log, "m.ulg", &options).unwrap();
    // Where position and attitude overlap: from the first position (1.0025 s) to the last
    // (4.8025 s), attitude from 1.021 s to 4.801 s, rates from 1.004 s to 4.8 s.
    let own = |c: Channel| d.sampling.count(c, d.len());
    assert_eq!(own(Channel::Position), 20);
    assert_eq!(own(Channel::Attitude), 190);
    assert_eq!(own(Channel::Rates), 950);
    // Every row is a sample of some channel: no time was invented.
    assert_eq!(d.len(), 20 + 190 + 950);
    // The samples are at their own times, with their own values.
    let t_of = |us: u64| (us as f64 - 1_002_500.0) * 1e-6;
    let rows: Vec<usize> = d.sampling.rows(Channel::Position, d.len()).collect();
    for (k, &i) in rows.iter().enumerate() {
        assert!((d.time[i] - t_of(1_002_500 + k as u64 * 200_000)).abs() < 1e-9);
        assert!((d.pos_ned[i].x - 5.0 * k as f64).abs() < 1e-9);
    }
    let rates = d.rates_body.as_ref().unwrap();
    for i in d.sampling.rows(Channel::Rates, d.len()) {
        let k = ((d.time[i] - t_of(1_000_000)) / 0.004).round();
        assert!((rates[i].z - k * 1e-3).abs() < 1e-6, "{i}: {}", rates[i]);
    }
    // Through the project's CSV and back: the same samples, none invented.
    let back = wireflight::data::parse(&wireflight::data::to_csv_string(&d), "back.csv").unwrap();
    assert_eq!(back.sampling, d.sampling);
    assert_eq!(back.len(), d.len());
    for i in d.sampling.rows(Channel::Position, d.len()) {
        assert!((back.pos_ned[i] - d.pos_ned[i]).length() < 1e-9);
    }
    // The report says each channel's samples and rate.
    let text = report.to_string();
    for want in [
        "1160 rows (the times anything was sampled)",
        "position     20 samples     5 Hz  filled in at 1140 rows between",
        "attitude    190 samples    50 Hz",
        "body rates  950 samples   250 Hz",
    ] {
        assert!(text.contains(want), "{want}\n{text}");
    }
    // At the default rate (the faster of position and attitude, 50 Hz) the rates are
    // thinned to samples they have, 50 a second.
    let (thin, _) = px4::from_ulog(&log, "m.ulg", &UlogOptions::default()).unwrap();
    let r = thin.rates_body.as_ref().unwrap();
    let kept: Vec<usize> = thin.sampling.rows(Channel::Rates, thin.len()).collect();
    assert_eq!(kept.len(), 190);
    for &i in &kept {
        let k = ((thin.time[i] + 0.0025) / 0.004).round();
        assert!(
            (r[i].z - k * 1e-3).abs() < 1e-6,
            "a thinned sample is one the log has"
        );
    }
}

#[test]
fn synthetic_ulog_errors_name_topic_and_field() {
    // A local position without `z`.
    let mut w = UlogWriter::new(None);
    w.format("vehicle_local_position:uint64_t timestamp;float x;float y;");
    let p = w.subscribe("vehicle_local_position");
    w.data_f32(p, 1000, &[0.0, 0.0]);
    let e = from_bytes(&w.bytes).unwrap_err();
    assert_eq!(
        e,
        "x.ulg: topic `vehicle_local_position`, field `z`: no such field (the topic has timestamp, x, y)"
    );
    // No position at all.
    let mut w = UlogWriter::new(None);
    w.format(ATT);
    let a = w.subscribe("vehicle_attitude");
    w.data_f32(a, 1000, &[1.0, 0.0, 0.0, 0.0]);
    let e = from_bytes(&w.bytes).unwrap_err();
    assert!(
        e.contains("no position: the log has none of vehicle_local_position"),
        "{e}"
    );
    // Incompatible flags this reader does not know.
    let w = UlogWriter::new(Some([2, 0, 0, 0, 0, 0, 0, 0]));
    let e = from_bytes(&w.bytes).unwrap_err();
    assert!(e.contains("incompatible flag bits 0x02 in byte 0"), "{e}");
    // A subscription to a topic whose format is not defined.
    let mut w = UlogWriter::new(None);
    w.subscribe("vehicle_attitude");
    let e = from_bytes(&w.bytes).unwrap_err();
    assert!(
        e.contains("topic `vehicle_attitude`: bad format: no format definition `vehicle_attitude`"),
        "{e}"
    );
    // One sample only.
    let mut w = UlogWriter::new(None);
    w.format(LOCAL);
    let p = w.subscribe("vehicle_local_position");
    w.data_f32(p, 1000, &[0.0, 0.0, 0.0]);
    let e = from_bytes(&w.bytes).unwrap_err();
    assert!(e.contains("too short"), "{e}");
}

#[test]
fn synthetic_ulog_global_position_becomes_local_ned() {
    let mut w = UlogWriter::new(None);
    w.format("vehicle_global_position:uint64_t timestamp;double lat;double lon;float alt;");
    let g = w.subscribe("vehicle_global_position");
    for k in 0..=10u64 {
        let mut p = g.to_le_bytes().to_vec();
        p.extend_from_slice(&(1_000_000 + k * 100_000).to_le_bytes());
        p.extend_from_slice(&(45.0 + k as f64 * 1e-5).to_le_bytes());
        p.extend_from_slice(&(7.0f64).to_le_bytes());
        p.extend_from_slice(&(100.0f32 + k as f32).to_le_bytes());
        w.message(b'D', &p);
    }
    let d = from_bytes(&w.bytes).unwrap();
    assert_eq!(d.meta.latitude_deg, Some(45.0));
    let last = d.pos_ned[d.len() - 1];
    let north = (1e-4f64).to_radians() * EARTH_RADIUS_M;
    assert!((last.x - north).abs() < 1e-6, "{last}");
    assert!((last.z + 10.0).abs() < 1e-4, "{last}");
}

#[test]
fn synthetic_ulog_rates_and_control_signs() {
    let mut w = simple_log(0.0);
    w.format("vehicle_angular_velocity:uint64_t timestamp;float[3] xyz;");
    w.format("actuator_controls_0:uint64_t timestamp;float[8] control;");
    let r = w.subscribe("vehicle_angular_velocity");
    let c = w.subscribe("actuator_controls_0");
    for k in 0..=20u64 {
        let t = 1_000_000 + k * 100_000;
        w.data_f32(r, t, &[0.1, 0.2, 0.3]);
        // Roll right, pitch up, yaw right, 60 % throttle.
        w.data_f32(c, t, &[0.5, 0.5, 0.5, 0.6, 0.0, 0.0, 0.0, 0.0]);
    }
    let d = from_bytes(&w.bytes).unwrap();
    let ctl = d.controls.as_ref().unwrap()[50];
    let k = 25f64.to_radians();
    assert!((ctl.aileron - 0.5 * k).abs() < 1e-7, "{ctl:?}");
    assert!((ctl.elevator + 0.5 * k).abs() < 1e-7, "{ctl:?}");
    assert!((ctl.rudder + 0.5 * k).abs() < 1e-7, "{ctl:?}");
    assert!((ctl.throttle - 0.6).abs() < 1e-7, "{ctl:?}");
    assert!((d.rates_body.as_ref().unwrap()[10].y - 0.2).abs() < 1e-7);
    // MAV_TYPE 1 with attitude and controls: a fixed wing.
    assert_eq!(d.meta.vehicle, Some(VehicleKind::FixedWing));
}

// ---------------------------------------------------------------------------------------------
// CSV through a column map

const LOGGER_CSV: &str = "\
# vehicle: point-mass
stamp_us;x_ft;y_ft;alt_ft;speed_kt;extra
5000000;0;0;1000;100;a
5100000;10;0;1001;100;b
5200000;20;0;1002;100;c
5300000;30;0;1003;100;d
";

#[test]
fn column_map_reads_units_offsets_and_delimiter() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("logger.csv");
    std::fs::write(&csv, LOGGER_CSV).unwrap();
    let map = ColumnMap::parse(
        "time=stamp_us:us:-5,north=x_ft:ft,east=y_ft:ft,height=alt_ft:ft,airspeed=speed_kt:kt",
    )
    .unwrap();
    let loaded = load(
        &csv,
        &LoadOptions {
            columns: Some(map),
            ..LoadOptions::default()
        },
    )
    .unwrap();
    let d = loaded.data;
    assert_eq!(d.time[0], 0.0);
    assert!((d.time[3] - 0.3).abs() < 1e-9);
    assert!((d.pos_ned[3].x - 30.0 * 0.3048).abs() < 1e-12);
    assert!((d.pos_ned[3].z + 1003.0 * 0.3048).abs() < 1e-9);
    assert!((d.airspeed.unwrap()[0] - 100.0 * 1852.0 / 3600.0).abs() < 1e-9);
    assert_eq!(d.meta.vehicle, Some(VehicleKind::PointMass));
    let r = loaded.report.unwrap().to_string();
    assert!(r.contains("stamp_us [us] -5"), "{r}");
    assert!(r.contains("1 column not mapped"), "{r}");
}

#[test]
fn column_map_errors_name_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("logger.csv");
    let opts = |spec: &str| LoadOptions {
        columns: Some(ColumnMap::parse(spec).unwrap()),
        ..LoadOptions::default()
    };
    std::fs::write(&csv, LOGGER_CSV).unwrap();
    let e = load(&csv, &opts("time=t,north=x_ft,east=y_ft,down=alt_ft"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("logger.csv: line 2, column `t`: missing required column `t` (for time): the column map names it but the header has stamp_us, x_ft"),
        "{e}"
    );
    std::fs::write(&csv, LOGGER_CSV.replace("5200000;20", "5200000;2O")).unwrap();
    let e = load(
        &csv,
        &opts("time=stamp_us,north=x_ft,east=y_ft,down=alt_ft"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("logger.csv: line 5, column `x_ft`: not a number: `2O`"),
        "{e}"
    );
    std::fs::write(&csv, LOGGER_CSV.replace("5300000", "5100000")).unwrap();
    let e = load(
        &csv,
        &opts("time=stamp_us,north=x_ft,east=y_ft,down=alt_ft"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("line 6, column `stamp_us`: time 5100000 s is not after 5200000 s"),
        "{e}"
    );
    // Latitudes in degrees read as radians.
    std::fs::write(&csv, "t,la,lo,h\n0,47.1,8.5,400\n1,47.2,8.5,400\n").unwrap();
    let e = load(&csv, &opts("time=t,lat=la,lon=lo,alt=h"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("map it as lat=la:deg"), "{e}");
    let d = load(&csv, &opts("time=t,lat=la:deg,lon=lo:deg,alt=h"))
        .unwrap()
        .data;
    assert!((d.pos_ned[1].x - 0.1f64.to_radians() * EARTH_RADIUS_M).abs() < 1e-6);
    // A column map on a ULog file.
    let e = load(
        &data_file("px4-sitl-hop.ulg"),
        &opts("time=t,north=a,east=b,down=c"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("a column map is for CSV files"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// The commands

#[test]
fn commands_read_ulog_and_mapped_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hop.csv");
    let hop = data_file("px4-sitl-hop.ulg");
    let (so, se) = ok_with_stderr(&[
        "import",
        "--flight",
        hop.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    // The report of what the log held goes to stderr (as every command's); the result to
    // stdout.
    assert!(se.contains("1241 rows"), "{se}");
    assert!(so.starts_with("wrote"), "{so}");
    let back = wireflight::data::read(&out).unwrap();
    assert_eq!(back.len(), 1241);
    assert_eq!(back.sampling.count(Channel::Position, back.len()), 310);

    // compare and diagnose need a vehicle for a quadrotor log; the report goes to stderr.
    let o = wireflight(&["compare", "--flight", hop.to_str().unwrap(), "--json"]);
    let se = stderr(&o);
    assert!(!o.status.success());
    assert!(
        se.contains("no `# vehicle:` metadata; say which model with --vehicle"),
        "{se}"
    );
    let (so, se) = ok_with_stderr(&[
        "compare",
        "--flight",
        hop.to_str().unwrap(),
        "--vehicle",
        "point-mass",
        "--json",
    ]);
    assert!(se.contains("PX4 ULog"), "{se}");
    let v: serde_json::Value = serde_json::from_str(&so).expect("stdout is JSON only");
    assert!(v["error"]["total"].as_f64().unwrap() > 0.0, "{v}");

    let csv = dir.path().join("logger.csv");
    std::fs::write(&csv, LOGGER_CSV).unwrap();
    let o = wireflight(&[
        "diagnose",
        "--flight",
        csv.to_str().unwrap(),
        "--columns",
        "time=stamp_us:us,north=x_ft:ft,east=y_ft:ft,height=alt_ft:ft",
        "--window",
        "0.2",
        "--json",
    ]);
    let (so, se) = (stdout(&o), stderr(&o));
    assert!(
        so.is_empty() || serde_json::from_str::<serde_json::Value>(&so).is_ok(),
        "{so}"
    );
    assert!(se.contains("CSV with a column map"), "{se}");

    // A bad column map is refused before anything is read, naming the entry.
    let o = wireflight(&[
        "render",
        "--flight",
        csv.to_str().unwrap(),
        "--frames-dir",
        dir.path().join("f").to_str().unwrap(),
        "--columns",
        "time=stamp_us:furlongs,north=x_ft",
    ]);
    let se = stderr(&o);
    assert!(!o.status.success());
    assert!(
        se.contains("column map: entry `time=stamp_us:furlongs`: unknown unit `furlongs`"),
        "{se}"
    );
    assert!(!Path::new(&dir.path().join("f")).exists());
}
