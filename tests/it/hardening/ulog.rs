//! Hostile PX4 ULog files (written by `support::ulog::UlogWriter`) through the commands: a clear
//! error naming the topic, field and time stamp, or an honest report; never a panic, a hang or
//! a flight made of interpolation.

use std::path::Path;
use std::time::Duration;

use super::{assert_ok, assert_refused, run, stderr, wireflight_in_timed};
use crate::support::ulog::UlogWriter;

const LOCAL: &str = "vehicle_local_position:uint64_t timestamp;float x;float y;float z;";
const ATT: &str = "vehicle_attitude:uint64_t timestamp;float[4] q;";
const GLOBAL: &str = "vehicle_global_position:uint64_t timestamp;double lat;double lon;double alt;";

/// 2 s of local position at 100 Hz (north at 10 m/s) and attitude at 50 Hz: sample `k` of
/// each gets the time stamp `t(k, µs)` and the quaternion `q(k)`, and the position `p(k)`.
fn log_with(
    t: impl Fn(&str, u64, u64) -> u64,
    p: impl Fn(u64) -> [f32; 3],
    q: impl Fn(u64) -> [f32; 4],
) -> UlogWriter {
    let mut w = UlogWriter::new(Some([0; 8]));
    w.format(LOCAL);
    w.format(ATT);
    let pid = w.subscribe("vehicle_local_position");
    let aid = w.subscribe("vehicle_attitude");
    for k in 0..=200u64 {
        let us = 1_000_000 + k * 10_000;
        w.data_f32(pid, t("p", k, us), &p(k));
        if k % 2 == 0 {
            w.data_f32(aid, t("a", k / 2, us), &q(k / 2));
        }
    }
    w
}

fn plain_t(_: &str, _: u64, us: u64) -> u64 {
    us
}

fn north(k: u64) -> [f32; 3] {
    [k as f32 * 0.1, 0.0, -50.0]
}

fn level(_: u64) -> [f32; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

fn write(dir: &Path, name: &str, w: &UlogWriter) {
    std::fs::write(dir.join(name), &w.bytes).unwrap();
}

/// What the command printed, stdout and stderr (the import report goes to either).
fn output(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Not a panic (exit 3 or 101), not an abort.
#[track_caller]
fn assert_no_panic(o: &std::process::Output) {
    let err = stderr(o);
    assert!(
        matches!(o.status.code(), Some(0 | 2)) && !err.contains("panicked"),
        "status {:?}, stderr: {err}",
        o.status
    );
}

#[test]
fn quaternions_far_from_unit_length_are_attitude_absent_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "zero.ulg", &log_with(plain_t, north, |_| [0.0; 4]));
    write(d, "two.ulg", &log_with(plain_t, north, |_| [2.0; 4]));
    for f in ["zero.ulg", "two.ulg"] {
        let o = run(&["import", "--flight", f, "--out", "x.csv"], d);
        assert_ok(&o);
        let out = output(&o);
        assert!(out.contains("not used: 0 of 101 samples valid"), "{out}");
        for args in [
            &["compare", "--flight", f, "--vehicle", "point-mass"][..],
            &["diagnose", "--flight", f, "--vehicle", "point-mass"][..],
            &["render", "--flight", f, "--frames-dir", "frames"][..],
        ] {
            assert_no_panic(&run(args, d));
        }
    }
}

#[test]
fn a_few_valid_quaternions_are_not_an_attitude() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let three = |k: u64| {
        if k < 3 {
            [1.0, 0.0, 0.0, 0.0]
        } else {
            [0.0; 4]
        }
    };
    write(d, "three.ulg", &log_with(plain_t, north, three));
    let o = run(&["import", "--flight", "three.ulg"], d);
    assert_ok(&o);
    let out = output(&o);
    assert!(
        out.contains("not used: 3 of 101 samples valid") && out.contains("101 samples at 50 Hz"),
        "{out}"
    );
    // Most samples valid: used, and the report says how many were dropped.
    let most = |k: u64| {
        if k % 10 == 5 {
            [0.0; 4]
        } else {
            [1.0, 0.0, 0.0, 0.0]
        }
    };
    write(d, "most.ulg", &log_with(plain_t, north, most));
    let o = run(&["import", "--flight", "most.ulg"], d);
    assert_ok(&o);
    let out = output(&o);
    assert!(out.contains("10 of 101 samples with a quaternion"), "{out}");
}

#[test]
fn scrambled_time_stamps_are_refused_not_sorted_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Position time stamps in a scrambled order (a permutation of the right ones).
    let scramble = |topic: &str, k: u64, us: u64| {
        if topic == "p" {
            1_000_000 + ((k * 37) % 201) * 10_000
        } else {
            us
        }
    };
    write(d, "scrambled.ulg", &log_with(scramble, north, level));
    let o = run(&["import", "--flight", "scrambled.ulg"], d);
    assert_refused(
        &o,
        &[
            "scrambled.ulg",
            "topic `vehicle_local_position`, field `timestamp`",
            "go back in time",
        ],
    );
    // One sample out of place is sorted, and said so.
    let swap = |topic: &str, k: u64, us: u64| match (topic, k) {
        ("p", 50) => us + 10_000,
        ("p", 51) => us - 10_000,
        _ => us,
    };
    write(d, "swap.ulg", &log_with(swap, north, level));
    let o = run(&["import", "--flight", "swap.ulg"], d);
    assert_ok(&o);
    let out = output(&o);
    assert!(
        out.contains("vehicle_local_position: 1 time stamps out of order (sorted)"),
        "{out}"
    );
}

#[test]
fn empty_formats_in_arrays_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut w = UlogWriter::new(None);
    w.format("e:");
    w.format("f:e[65535] a;");
    w.format("vehicle_local_position:f[65535] b;");
    w.subscribe("vehicle_local_position");
    assert!(w.bytes.len() < 128, "{}", w.bytes.len());
    write(d, "empty.ulg", &w);
    let o = wireflight_in_timed(
        d,
        &["import", "--flight", "empty.ulg"],
        Duration::from_secs(10),
    );
    assert_refused(&o, &["empty.ulg", "format `e`, which has no bytes"]);
    // Any subscribed topic, wanted or not.
    let mut w = UlogWriter::new(None);
    w.format("e:");
    w.format("f:e[65535] a;");
    w.format("other_topic:f[65535] b;");
    w.subscribe("other_topic");
    write(d, "other.ulg", &w);
    let o = wireflight_in_timed(
        d,
        &["import", "--flight", "other.ulg"],
        Duration::from_secs(10),
    );
    assert_refused(&o, &["other.ulg"]);
}

#[test]
fn a_time_stamp_moved_far_cannot_make_millions_of_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let moved = |topic: &str, k: u64, us: u64| match (topic, k) {
        ("p", 200) | ("a", 100) => us + 199_000_000_000,
        _ => us,
    };
    write(d, "moved.ulg", &log_with(moved, north, level));
    let o = wireflight_in_timed(
        d,
        &["import", "--flight", "moved.ulg", "--out", "x.csv"],
        Duration::from_secs(20),
    );
    assert_refused(
        &o,
        &[
            "moved.ulg",
            "samples, more than 100 for each of the 302 position and attitude samples",
            "the longest gap: 199000.0 s",
        ],
    );
    assert!(!d.join("x.csv").exists());
}

#[test]
fn ulog_values_out_of_range_are_refused_naming_topic_field_and_time() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spike = |k: u64| {
        if k == 40 {
            [1e30, 0.0, -50.0]
        } else {
            north(k)
        }
    };
    write(d, "spike.ulg", &log_with(plain_t, spike, level));
    for args in [
        &["import", "--flight", "spike.ulg", "--out", "x.csv"][..],
        &[
            "compare",
            "--flight",
            "spike.ulg",
            "--vehicle",
            "point-mass",
        ][..],
    ] {
        let o = run(args, d);
        assert_refused(
            &o,
            &[
                "spike.ulg",
                "topic `vehicle_local_position`, field `x`",
                "at time stamp 1400000 µs",
                "±1e8 m",
            ],
        );
        assert!(!stderr(&o).contains("line 7"), "{}", stderr(&o));
    }
    assert!(!d.join("x.csv").exists());
    // A jump of 1e7 m (in range) is a speed out of range: refused when read, not written.
    let jump = |k: u64| {
        if k >= 100 {
            [1e7, 0.0, -50.0]
        } else {
            north(k)
        }
    };
    write(d, "jump.ulg", &log_with(plain_t, jump, level));
    let o = run(&["import", "--flight", "jump.ulg", "--out", "x.csv"], d);
    assert_refused(
        &o,
        &["jump.ulg", "NED velocity (derived", "±1e5 m/s", "ULog time"],
    );
    assert!(!stderr(&o).contains("line "), "{}", stderr(&o));
    assert!(!d.join("x.csv").exists());
    // A global altitude of 1e250.
    let mut w = UlogWriter::new(None);
    w.format(GLOBAL);
    let g = w.subscribe("vehicle_global_position");
    for k in 0..=10u64 {
        let alt = if k == 5 { 1e250 } else { 100.0 };
        w.data_f64(g, 1_000_000 + k * 100_000, &[45.0, 7.0, alt]);
    }
    write(d, "alt.ulg", &w);
    // An origin below the metadata's range (which `import --out`'s reader applies).
    let mut low = UlogWriter::new(None);
    low.format(GLOBAL);
    let g = low.subscribe("vehicle_global_position");
    for k in 0..=10u64 {
        low.data_f64(g, 1_000_000 + k * 100_000, &[45.0, 7.0, -74_800.0]);
    }
    write(d, "low.ulg", &low);
    let o = run(&["import", "--flight", "low.ulg", "--out", "x.csv"], d);
    assert_refused(
        &o,
        &[
            "topic `vehicle_global_position`, field `alt`",
            "origin",
            "-74800",
        ],
    );
    assert!(
        !stderr(&o).contains("would not read back"),
        "{}",
        stderr(&o)
    );
    let o = run(&["import", "--flight", "alt.ulg"], d);
    assert_refused(
        &o,
        &[
            "topic `vehicle_global_position`, field `alt`",
            "at time stamp 1500000 µs",
            "-1e5..1e8 m",
        ],
    );
}

#[test]
fn one_corrupt_time_stamp_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let corrupt = |topic: &str, k: u64, us: u64| match (topic, k) {
        ("a", 30) => us | (1 << 63),
        _ => us,
    };
    write(d, "corrupt.ulg", &log_with(corrupt, north, level));
    let o = run(&["import", "--flight", "corrupt.ulg"], d);
    assert_refused(
        &o,
        &[
            "topic `vehicle_attitude`, field `timestamp`",
            "sample 30: time stamp 92233720368",
            "outside ±1e9 s",
        ],
    );
    assert!(
        !stderr(&o).contains("overlap for 0.000 s"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn max_input_mb_applies_to_ulog() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut w = log_with(plain_t, north, level);
    // Over 1 MiB of log text.
    for _ in 0..40 {
        w.message(b'L', &[b'x'; 30_000]);
    }
    write(d, "big.ulg", &w);
    let o = run(&["import", "--max-input-mb", "1", "--flight", "big.ulg"], d);
    assert_refused(&o, &["big.ulg", "--max-input-mb"]);
    assert_ok(&run(
        &["import", "--max-input-mb", "2", "--flight", "big.ulg"],
        d,
    ));
}

#[test]
fn text_from_the_log_is_escaped_in_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut w = UlogWriter::new(Some([0; 8]));
    w.info_str("sys_name", "evil\x1b]0;pwned\x07\x1b[2J\r");
    let mut rest = log_with(plain_t, north, level);
    // The info message belongs to the definitions section: before the rest of the log.
    w.bytes.extend_from_slice(&rest.bytes.split_off(16 + 43));
    write(d, "evil.ulg", &w);
    let o = run(&["import", "--flight", "evil.ulg"], d);
    assert_ok(&o);
    let out = output(&o);
    assert!(
        !out.contains('\x1b') && !out.contains('\x07') && !out.contains('\r'),
        "{out:?}"
    );
    assert!(
        out.contains("system: evil\\u{1b}]0;pwned\\u{7}\\u{1b}[2J\\u{d}"),
        "{out}"
    );
}
