//! Hostile-input reproductions: random extreme options from simulate to compare and diagnose.

use super::*;

use proptest::prelude::*;
use proptest::sample::select;

/// Exit 0 or 2 (never a panic, abort or signal) within `limit`; the status.
fn status_of(args: &[String], dir: &Path, limit: Duration) -> i32 {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = wireflight_in_timed(dir, &args, limit);
    let code = o.status.code();
    assert!(
        matches!(code, Some(0 | 2)),
        "`wireflight {}`: status {:?}\nstderr: {}",
        args.join(" "),
        o.status,
        stderr(&o)
    );
    code.unwrap_or(-1)
}

/// Mostly ordinary values, one time in six an extreme one (so that a third of the
/// flights are made and analysed).
fn mix(ordinary: Vec<f64>, extreme: Vec<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![5 => select(ordinary), 1 => select(extreme)]
}

fn opt(name: &str, v: f64) -> [String; 2] {
    [format!("--{name}"), format!("{v:e}")]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 16,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn simulate_then_compare_and_diagnose_exit_0_or_2_in_bounded_time(
        point_mass in any::<bool>(),
        duration in mix(vec![0.5, 4.0, 20.0], vec![1e-3, 1e9, 1e300]),
        rate in mix(vec![0.5, 20.0, 50.0], vec![1e-6, 1e5]),
        noise_pos in mix(vec![0.0, 0.3], vec![1e6, 1e200]),
        noise_other in mix(vec![0.0, 0.5], vec![1e308]),
        speed in mix(vec![25.0], vec![0.0, 1e6, 1e200]),
        latitude in mix(vec![-90.0, 45.0], vec![95.0]),
        window in select(vec![0.1, 1.0, 8.0, 86_400.0]),
        offset in select(vec![0.0, 1.0, 1e9]),
        start_span in select(vec![None, Some(1e-3), Some(5.0)]),
        add in select(vec![None, Some("wind"), Some("actuator_lag:tau_s=0.001"), Some("drag:k=1e9")]),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let mut sim: Vec<String> = vec!["simulate".into(), "--out".into(), "f.csv".into()];
        if point_mass {
            sim.extend(["--vehicle".into(), "point-mass".into()]);
            sim.extend(opt("launch-speed", speed.max(1.0) * 6.0));
        } else {
            sim.extend(opt("airspeed", speed));
        }
        sim.extend(opt("duration", duration));
        sim.extend(opt("rate", rate));
        sim.extend(opt("noise-pos", noise_pos));
        sim.extend(opt("noise-vel", noise_other));
        sim.extend(opt("noise-rate", noise_other));
        sim.extend(opt("latitude", latitude));
        if status_of(&sim, d, Duration::from_secs(60)) != 0 {
            return Ok(());
        }
        for cmd in ["compare", "diagnose"] {
            let mut args: Vec<String> = vec![cmd.into(), "--flight".into(), "f.csv".into()];
            args.extend(opt("window", window));
            args.extend(opt("window-offset", offset));
            if let Some(s) = start_span {
                args.extend(opt("start-span", s));
            }
            if let (Some(a), "compare") = (add, cmd) {
                args.extend(["--add".into(), a.into()]);
            }
            status_of(&args, d, Duration::from_secs(120));
        }
    }
}

/// Weiler–Atherton's coordinates are held to ±1e150 where they enter (`FILE:LINE`): beyond, an
/// area or a crossing overflows and the JSON would carry `NaN` or `inf`, which is no JSON.
#[test]
fn polygon_coordinates_beyond_1e150_are_refused_at_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("unit.txt"), "0,0\n1,0\n1,1\n0,1\n").unwrap();
    let square = |s: &str| format!("-{s},-{s}\n{s},-{s}\n{s},{s}\n-{s},{s}\n");
    std::fs::write(d.join("huge.txt"), square("1.7e308")).unwrap();
    let o = run(
        &[
            "clip",
            "--algo",
            "weiler-atherton",
            "--op",
            "difference",
            "--subject",
            "huge.txt",
            "--clip",
            "unit.txt",
            "--json",
            "--out",
            "x.json",
        ],
        d,
    );
    assert_refused(&o, &["huge.txt:1", "beyond ±1e150"]);
    assert!(!d.join("x.json").exists());
    std::fs::write(d.join("big.txt"), square("1e150")).unwrap();
    let o = run(
        &[
            "clip",
            "--algo",
            "weiler-atherton",
            "--op",
            "difference",
            "--subject",
            "big.txt",
            "--clip",
            "unit.txt",
            "--json",
            "--out",
            "x.json",
        ],
        d,
    );
    assert_ok(&o);
    let json = crate::support::cli::stdout(&o);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let area = v["area"].as_f64().expect("a finite area");
    assert!((area / 4e300 - 1.0).abs() < 1e-9, "{area}");
    // Numbers that size are written as 1e150, not 151 digits, and read back the same.
    assert!(
        json.contains("[-1e150, -1e150]") && json.len() < 400,
        "{json}"
    );
    let text = std::fs::read_to_string(d.join("x.json")).unwrap();
    assert!(text.starts_with("-1e150,-1e150\n"), "{text}");
}

/// Weiler–Atherton's checks are quadratic in a polygon's vertices: a polygon past
/// `--max-vertices` (20 000, about 2 s) is refused at once, naming the file and polygon,
/// rather than running for minutes; the option raises it.
#[test]
fn a_polygon_past_the_vertex_limit_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 20_001;
    let circle: String = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            format!("{},{}\n", a.cos(), a.sin())
        })
        .collect();
    std::fs::write(d.join("circle.txt"), circle).unwrap();
    std::fs::write(d.join("square.txt"), "0,0\n2,0\n2,2\n0,2\n").unwrap();
    let args = [
        "clip",
        "--algo",
        "weiler-atherton",
        "--subject",
        "circle.txt",
        "--clip",
        "square.txt",
        "--out",
        "o.txt",
    ];
    let started = Instant::now();
    let o = run(&args, d);
    assert_refused(
        &o,
        &["circle.txt: polygon 1 has 20001 vertices, more than --max-vertices 20000"],
    );
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "{:?}",
        started.elapsed()
    );
    let mut raised = args.to_vec();
    raised.extend(["--max-vertices", "30000"]);
    assert_ok(&run(&raised, d));
}
