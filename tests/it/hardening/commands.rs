//! Hostile-input reproductions: commands' options and messages (simulate, euler, clip,
//! identify, import).

use super::*;

// ---------------------------------------------------------------------------------------------
// simulate

#[test]
fn simulate_refuses_what_the_machine_cannot_hold_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let o = wireflight_in_timed(
        dir.path(),
        &[
            "simulate",
            "--max-samples",
            "18446744073709551615",
            "--duration",
            "1e9",
            "--out",
            "a.csv",
        ],
        Duration::from_secs(20),
    );
    assert_refused(
        &o,
        &["50000000001 samples", "MiB of memory", "--max-samples"],
    );
    assert!(!dir.path().join("a.csv").exists());
}

#[test]
fn simulate_bounded_refuses_beyond_its_memory_bound() {
    use wireflight::flight::autopilot::Manoeuvre;
    use wireflight::flight::simulate::{
        simulate_bounded, SimSpec, SimulateError, BYTES_PER_SAMPLE,
    };
    let model =
        wireflight::flight::spec::ModelSpec::baseline(wireflight::data::VehicleKind::FixedWing)
            .build(wireflight::flight::effects::Origin {
                latitude_deg: 0.0,
                longitude_deg: 0.0,
                altitude_m: 0.0,
            })
            .unwrap();
    let spec = SimSpec::new(Manoeuvre::Level, 10.0);
    // 501 samples: refused with room for 500, flown with room for 501.
    let err = simulate_bounded(&model, &spec, 1_000, 500 * BYTES_PER_SAMPLE).unwrap_err();
    assert!(
        matches!(
            err,
            SimulateError::TooMuchMemory {
                samples: 501,
                most: 500,
                ..
            }
        ),
        "{err}"
    );
    assert!(simulate_bounded(&model, &spec, 1_000, 501 * BYTES_PER_SAMPLE).is_ok());
}

#[test]
fn simulate_refusals_name_the_option_in_a_short_number() {
    let dir = tempfile::tempdir().unwrap();
    for (args, words) in [
        (
            &["--duration", "1e200"][..],
            &["1.000e200 s", "--max-samples 2000000", "--duration"][..],
        ),
        (
            &["--duration", "1e-300"][..],
            &["--duration", "1.000e-300", "single sample"][..],
        ),
        (&["--rate", "1e300"][..], &["--rate", "1.000e300 Hz"][..]),
        (
            &["--noise-pos", "1e300"][..],
            &["--noise-pos", "1.000e300"][..],
        ),
        (
            &["--noise-rate", "1e5"][..],
            &["--noise-rate", "1.000e5"][..],
        ),
    ] {
        let mut all = vec!["simulate", "--out", "a.csv"];
        all.extend_from_slice(args);
        let o = run(&all, dir.path());
        assert_refused(&o, words);
        let err = stderr(&o);
        assert!(!err.contains("0000000000"), "a long number in: {err}");
    }
}

// ---------------------------------------------------------------------------------------------
// euler

#[test]
fn euler_reduces_huge_degrees_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let matrix = |angles: &str| {
        let o = run(&["euler", "--angles", angles, "--to", "matrix"], d);
        assert_ok(&o);
        String::from_utf8(o.stdout).unwrap()
    };
    // 1e20 is exactly 10^20 in f64, and 10^20 ≡ 280 (mod 360).
    assert_eq!(matrix("1e20,45,0"), matrix("280,45,0"));
    assert_eq!(matrix("0,45,-1e20"), matrix("0,45,80"));
    assert_eq!(matrix("720.5,0,0"), matrix("0.5,0,0"));
    let o = run(
        &[
            "euler",
            "--angles",
            "1e20,0,0",
            "--radians",
            "--to",
            "matrix",
        ],
        d,
    );
    assert_refused(&o, &["--angles", "1e20 rad", "degrees"]);
}

#[test]
fn euler_size_states_the_panel_range() {
    let dir = tempfile::tempdir().unwrap();
    for size in ["0x100", "99999x100", "3000x240", "10x10"] {
        let o = run(
            &[
                "euler", "--angles", "1,2,3", "--steps", "--out", "s", "--size", size,
            ],
            dir.path(),
        );
        assert_refused(&o, &["--size", "64..=2048"]);
        assert!(!stderr(&o).contains("16384"), "{}", stderr(&o));
    }
}

// ---------------------------------------------------------------------------------------------
// clip

/// `clip` of `text` (2D edges in the window 0,0,10,10): the output, or the refusal.
fn clip_2d(dir: &Path, text: &str) -> Output {
    std::fs::write(dir.join("in.csv"), text).unwrap();
    run(
        &[
            "clip",
            "--algo",
            "cohen-sutherland",
            "--input",
            "in.csv",
            "--out",
            "out.csv",
            "--rect",
            "0,0,10,10",
        ],
        dir,
    )
}

#[test]
fn clip_loses_no_first_edge_to_a_mistaken_header() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A byte-order mark before the first edge: the edge is read, not taken for a header.
    assert_ok(&clip_2d(d, "\u{feff}1,1,2,2\n3,3,4,4\n"));
    let out = std::fs::read_to_string(d.join("out.csv")).unwrap();
    assert_eq!(out.lines().count(), 2, "{out}");
    // With a header after the mark, the header is kept (without the mark).
    assert_ok(&clip_2d(d, "\u{feff}x0,y0,x1,y1\n1,1,2,2\n"));
    let out = std::fs::read_to_string(d.join("out.csv")).unwrap();
    assert_eq!(out.lines().collect::<Vec<_>>(), ["x0,y0,x1,y1", "1,1,2,2"]);
    // Semicolons or a hex number in the first row: an error naming the file and line.
    let o = clip_2d(d, "1;1;2;2\n3,3,4,4\n");
    assert_refused(&o, &["in.csv:1:", "expected 4 values", "commas"]);
    let o = clip_2d(d, "0x10,1,2,2\n3,3,4,4\n");
    assert_refused(&o, &["in.csv:1:", "`0x10` is not a number"]);
}

// ---------------------------------------------------------------------------------------------
// identify

/// A fixed-wing flight `f.csv` and a point-mass flight `p.csv` in `dir`.
fn two_vehicles(dir: &Path) {
    flight(dir, "f.csv", &["--manoeuvre", "flight-test"]);
    let point_mass = Flight::new().vehicle("point-mass").duration(20);
    assert_ok(&run(&point_mass.args("p.csv"), dir));
}

#[test]
fn identify_refuses_flights_of_another_vehicle_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    two_vehicles(d);
    let o = run(
        &[
            "identify",
            "--flight",
            "f.csv",
            "--flight",
            "p.csv",
            "--free",
            "c_m_alpha",
        ],
        d,
    );
    assert_refused(&o, &["--flight p.csv", "point-mass", "f.csv"]);
    let o = run(
        &[
            "identify",
            "--flight",
            "f.csv",
            "--validate",
            "p.csv",
            "--free",
            "c_m_alpha",
        ],
        d,
    );
    assert_refused(&o, &["--validate p.csv", "point-mass", "f.csv"]);
}

#[test]
fn identify_prior_has_a_stated_range_and_is_printed_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "f.csv", &["--manoeuvre", "flight-test"]);
    for prior in ["30", "1e-6", "0"] {
        let o = run(&["identify", "--flight", "f.csv", "--prior", prior], d);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains("--prior"), "{}", stderr(&o));
    }
    let o = run(&["identify", "--flight", "f.csv", "--prior", "30"], d);
    assert!(stderr(&o).contains("0.01..=3"), "{}", stderr(&o));
    let o = run(
        &[
            "identify",
            "--flight",
            "f.csv",
            "--free",
            "c_m_alpha",
            "--prior",
            "0.015",
        ],
        d,
    );
    assert_ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("prior ±1.5% of the set"), "{out}");
}

#[test]
fn identify_reads_ulog_like_compare() {
    let o = run(
        &["identify", "--flight", "tests/data/px4-sitl-hop.ulg"],
        Path::new(env!("CARGO_MANIFEST_DIR")),
    );
    assert_refused(&o, &["px4-sitl-hop.ulg"]);
    assert!(!stderr(&o).contains("UTF-8"), "{}", stderr(&o));
}

#[test]
fn identify_and_compare_name_the_option_that_leaves_nothing_to_fit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "f.csv", &["--manoeuvre", "flight-test"]);
    for cmd in ["identify", "compare", "diagnose"] {
        let o = run(&[cmd, "--flight", "f.csv", "--window-offset", "1e9"], d);
        assert_refused(&o, &["f.csv", "--window-offset", "1.000e9 s"]);
    }
    std::fs::create_dir(d.join("dir")).unwrap();
    for out in ["dir/", "dir"] {
        let o = run(
            &[
                "identify",
                "--flight",
                "f.csv",
                "--free",
                "c_m_alpha",
                "--out",
                out,
            ],
            d,
        );
        assert_refused(&o, &["dir"]);
        assert!(!stderr(&o).contains("Not a directory"), "{}", stderr(&o));
    }
}

// ---------------------------------------------------------------------------------------------
// import

#[test]
fn import_reports_on_stderr_and_quiet_silences_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "f.csv", &[]);
    let ulog = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/px4-sitl-hop.ulg");
    let ulog = ulog.to_str().unwrap();
    for input in ["f.csv", ulog] {
        let o = run(&["import", "--flight", input], d);
        assert_ok(&o);
        assert!(
            o.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&o.stdout)
        );
        assert!(!stderr(&o).is_empty());
        let o = run(&["import", "-q", "--flight", input, "--out", "g.csv"], d);
        assert_ok(&o);
        assert!(stderr(&o).is_empty(), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.starts_with("wrote g.csv"), "{out}");
    }
}
