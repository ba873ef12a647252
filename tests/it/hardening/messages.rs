//! Hostile-input reproductions: messages that say what is wrong once and name the input.

use super::*;

#[test]
fn negative_numbers_reach_the_options_own_check() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["render", "--fov", "-10", "--out", "x.svg"], dir.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.contains("field of view -10° is outside"), "{err}");
    let o = run(
        &["simulate", "--duration", "-5", "--out", "x.csv"],
        dir.path(),
    );
    assert!(
        stderr(&o).contains("duration -5 s must be positive"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &[
            "simulate",
            "--height",
            "-50",
            "--duration",
            "1",
            "--out",
            "x.csv",
        ],
        dir.path(),
    );
    assert_ok(&o);
}

#[test]
fn a_model_files_aircraft_is_found_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("models")).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/aircraft/aerosonde.toml"),
        d.join("models/mine.toml"),
    )
    .unwrap();
    std::fs::write(
        d.join("models/model.toml"),
        "vehicle = \"fixed-wing\"\naircraft = \"mine.toml\"\n",
    )
    .unwrap();
    let o = run(
        &[
            "simulate",
            "--model",
            "models/model.toml",
            "--duration",
            "1",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_ok(&o);
}

#[test]
fn read_handle_is_not_left_open_on_a_fifo() {
    // A FIFO is refused before anything waits on its writer.
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("f.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid C string; mkfifo only creates the file.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let o = wireflight_in_timed(
        dir.path(),
        &["compare", "--flight", "f.csv"],
        Duration::from_secs(10),
    );
    assert_refused(&o, &["f.csv", "not a regular file"]);
}

/// The drawn segment count `render` prints.
fn segments_drawn(o: &Output) -> usize {
    let text = String::from_utf8_lossy(&o.stdout);
    let before = text.split(" segments drawn").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap()
}

#[test]
fn no_blank_images_from_huge_angles_or_scales() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = run(&["render", "--out", "a.svg"], d);
    assert_ok(&base);
    let o = run(
        &[
            "render", "--yaw", "1e100", "--camera", "chase", "--out", "b.svg",
        ],
        d,
    );
    assert_ok(&o);
    assert!(
        segments_drawn(&o) > 0,
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let o = run(
        &[
            "render", "--yaw", "360", "--pitch", "-720", "--out", "c.svg",
        ],
        d,
    );
    assert_eq!(segments_drawn(&o), segments_drawn(&base));
    // Models beyond the sizes the cameras can draw are refused, naming the limit.
    let plane =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/plane.obj"))
            .unwrap();
    for (scale, ok) in [(1e20, false), (1e-31, false), (1e-6, true), (1e5, true)] {
        let scaled: Vec<String> = plane
            .lines()
            .map(|l| match l.strip_prefix("v ") {
                Some(v) => {
                    let p: Vec<String> = v
                        .split_whitespace()
                        .map(|c| format!("{:e}", c.parse::<f64>().unwrap() * scale))
                        .collect();
                    format!("v {}", p.join(" "))
                }
                None => l.to_string(),
            })
            .collect();
        std::fs::write(d.join("s.obj"), scaled.join("\n")).unwrap();
        for camera in ["chase", "cockpit", "top"] {
            let o = run(
                &[
                    "render", "--mesh", "s.obj", "--camera", camera, "--out", "s.svg",
                ],
                d,
            );
            if ok {
                assert_ok(&o);
                assert!(segments_drawn(&o) > 0, "scale {scale} {camera}: blank");
            } else {
                assert_refused(&o, &["s.obj", "bounding radius", "rescale"]);
            }
        }
    }
}

/// Text from input is quoted in an excerpt, never whole: a TOML error on a 300 000-character
/// line, a 100 kB `--add`, a 5 MB CSV cell give messages of a few hundred bytes that still
/// say where and what.
#[test]
fn long_input_is_quoted_in_an_excerpt() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let long = "a".repeat(300_000);
    std::fs::write(
        d.join("long.toml"),
        format!("vehicle = \"fixed-wing\"\naircraft = \"{long}\n"),
    )
    .unwrap();
    let o = run(&["simulate", "--model", "long.toml", "--out", "x.csv"], d);
    assert_refused(
        &o,
        &["long.toml", "line 2, column 300013", "invalid basic string"],
    );
    assert!(stderr(&o).len() < 1000, "{} bytes", stderr(&o).len());
    let add = "w".repeat(100_000);
    let o = run(&["simulate", "--add", add.as_str(), "--out", "x.csv"], d);
    assert_refused(&o, &["unknown effect", "more characters"]);
    assert!(stderr(&o).len() < 2000, "{} bytes", stderr(&o).len());
    let value = format!("wind:north_mps={}x", "1".repeat(100_000));
    let o = run(&["simulate", "--add", value.as_str(), "--out", "x.csv"], d);
    assert_refused(&o, &["north_mps", "not a finite number"]);
    assert!(stderr(&o).len() < 1000, "{} bytes", stderr(&o).len());
    let cell = "z".repeat(5_000_000);
    std::fs::write(
        d.join("cell.csv"),
        format!("time_s,north_m,east_m,down_m\n0,0,0,0\n1,{cell},0,0\n"),
    )
    .unwrap();
    let o = run(&["import", "--flight", "cell.csv"], d);
    assert_refused(&o, &["cell.csv: line 3, column `north_m`", "not a number"]);
    assert!(stderr(&o).len() < 1000, "{} bytes", stderr(&o).len());
}
