//! Hostile-input reproductions: files written whole (temporaries removed on signals and by the next
//! run, outputs written as a set, modes and links kept).

use super::*;

#[test]
fn temporaries_of_a_killed_run_are_removed_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // PIDs beyond any pid_max: their processes are gone.
    std::fs::write(
        d.join(".old.csv.wireflight.tmp-4294967295"),
        vec![0u8; 1000],
    )
    .unwrap();
    let staged = d.join(".frames.wireflight.tmp-4294967294");
    std::fs::create_dir(&staged).unwrap();
    std::fs::write(staged.join(".wireflight-staged"), b"").unwrap();
    flight(d, "a.csv", &[]);
    let names: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["a.csv"]);
}

#[test]
fn sigterm_and_sigint_remove_the_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert_ok(&run(&Flight::new().duration(600).args("a.csv"), d));
    for (signal, status) in [(libc::SIGTERM, 143), (libc::SIGINT, 130)] {
        let child = command()
            .args([
                "render",
                "--flight",
                "a.csv",
                "--frames-dir",
                "frames",
                "--size",
                "320x240",
                "--backend",
                "cpu",
            ])
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until it writes frames into its temporary directory.
        let tmp = d.join(format!(".frames.wireflight.tmp-{}", child.id()));
        let start = Instant::now();
        while std::fs::read_dir(&tmp).map_or(0, Iterator::count) < 2 {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "no frames appeared"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        // SAFETY: sending a signal to our own child.
        unsafe { libc::kill(child.id() as i32, signal) };
        let o = wait_timed(child, &["render"], Duration::from_secs(30));
        assert_eq!(
            o.status.code(),
            Some(status),
            "{:?} {}",
            o.status,
            stderr(&o)
        );
        assert!(!tmp.exists(), "the temporary directory is left");
        assert!(!d.join("frames").exists(), "a partial set of frames");
    }
}

#[test]
fn plots_are_written_as_a_set() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "a.csv", &[]);
    std::fs::create_dir(d.join("plots")).unwrap();
    std::fs::write(d.join("plots/keep.txt"), "mine").unwrap();
    assert_ok(&run(
        &["compare", "--flight", "a.csv", "--plots", "plots"],
        d,
    ));
    let mut names: Vec<String> = std::fs::read_dir(d.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.contains(&"keep.txt".to_string()), "{names:?}");
    assert!(
        names.iter().filter(|n| n.ends_with(".png")).count() >= 2,
        "{names:?}"
    );
    let stray: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");
}

#[test]
fn replacing_an_output_keeps_its_mode_and_writes_through_a_link() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("real")).unwrap();
    std::fs::write(d.join("real/out.csv"), "old").unwrap();
    std::fs::set_permissions(
        d.join("real/out.csv"),
        std::fs::Permissions::from_mode(0o600),
    )
    .unwrap();
    std::os::unix::fs::symlink("real/out.csv", d.join("out.csv")).unwrap();
    flight(d, "out.csv", &[]);
    assert!(std::fs::symlink_metadata(d.join("out.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    let text = std::fs::read_to_string(d.join("real/out.csv")).unwrap();
    assert!(text.contains("time_s"));
    let mode = std::fs::metadata(d.join("real/out.csv"))
        .unwrap()
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o600);
}

/// A configuration file (model, parameter set, column map, sensor errors) past
/// `--max-config-mb` (16 MiB) is refused by its size before it is read: a TOML reader takes
/// several times a file's size in memory, and such files are a few kB.
#[test]
fn a_huge_configuration_file_is_refused_by_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let big = std::fs::File::create(d.join("big.toml")).unwrap();
    big.set_len(17 << 20).unwrap(); // sparse: nothing is written
    for args in [
        vec!["simulate", "--model", "big.toml", "--out", "x.csv"],
        vec!["simulate", "--aircraft", "big.toml", "--out", "x.csv"],
        vec!["simulate", "--sensor-errors", "big.toml", "--out", "x.csv"],
    ] {
        let o = run(&args, d);
        assert_refused(&o, &["big.toml", "--max-config-mb"]);
    }
    let o = run(
        &[
            "--max-config-mb",
            "32",
            "simulate",
            "--model",
            "big.toml",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert!(!crate::support::cli::stderr(&o).contains("--max-config-mb"));
    assert!(!d.join("x.csv").exists());
}

/// Every output is checked before any work: an output that cannot be written (a directory
/// where a page goes) stops the run before another output is written.
#[test]
fn outputs_are_checked_before_any_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "q.csv", &[]);
    std::fs::create_dir(d.join("isdir.html")).unwrap();
    let o = run(
        &[
            "diagnose",
            "--flight",
            "q.csv",
            "--out",
            "m.toml",
            "--report",
            "isdir.html",
        ],
        d,
    );
    assert_refused(
        &o,
        &[
            "isdir.html",
            "--report writes a file, and this is a directory",
        ],
    );
    assert!(
        !d.join("m.toml").exists(),
        "m.toml written before the refusal"
    );
    let o = run(
        &[
            "compare",
            "--flight",
            "q.csv",
            "--report",
            "no/such/dir/r.html",
        ],
        d,
    );
    assert_refused(&o, &["--report: no directory no/such/dir to write it in"]);
    std::fs::write(d.join("plots"), "a file").unwrap();
    let o = run(&["compare", "--flight", "q.csv", "--plots", "plots"], d);
    assert_refused(
        &o,
        &["--plots writes a directory: it exists and is not a directory"],
    );
}

/// A header of more columns than any log has is refused by counting its separators, before
/// its names are taken apart (30 million names would take gigabytes).
#[test]
fn a_header_of_millions_of_columns_is_refused_before_it_is_split() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut text = String::from("time_s,north_m,east_m,down_m");
    text.push_str(&",x".repeat(200_000));
    text.push('\n');
    std::fs::write(d.join("wide.csv"), &text).unwrap();
    let o = run(&["import", "--flight", "wide.csv"], d);
    assert_refused(
        &o,
        &["wide.csv: line 1", "200004 columns, more than 100000"],
    );
    let o = run(
        &[
            "import",
            "--flight",
            "wide.csv",
            "--columns",
            "time=time_s,north=north_m,east=east_m,down=down_m",
        ],
        d,
    );
    assert_refused(&o, &["wide.csv: line 1", "more than 100000"]);
}

/// `simulate` bounds its flight by the process's address-space limit (`ulimit -v`) as well
/// as by the machine's free memory: refused before any work, never an abort.
#[test]
fn simulate_respects_the_address_space_limit() {
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 2000000 && exec {} simulate --max-samples 10000000 --duration 199999 --out x.csv",
            env!("CARGO_BIN_EXE_wireflight")
        ))
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_refused(
        &o,
        &[
            "samples",
            "MiB is free",
            "--max-samples does not raise this bound",
        ],
    );
    assert!(!dir.path().join("x.csv").exists());
}

/// A directory an earlier run wrote (its marker file there) that now also holds a file of the
/// user's is refused, not replaced: the marker lists the files the run wrote, and only those
/// may be lost.
#[test]
fn a_marked_directory_holding_the_users_files_is_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, marker) in [
        (
            vec![
                "clip",
                "--algo",
                "weiler-atherton",
                "--demo",
                "--out",
                "pics",
            ],
            "wireflight-clip-demo.txt",
        ),
        (
            vec![
                "euler", "--seq", "zyx", "--angles", "30,60,45", "--steps", "--out", "pics2",
            ],
            "wireflight-euler.txt",
        ),
    ] {
        let out = d.join(args[args.len() - 1]);
        assert_ok(&run(&args, d));
        assert!(out.join(marker).is_file());
        // Run again over its own outputs: fine.
        assert_ok(&run(&args, d));
        // With a file of the user's beside them: refused, the file kept.
        std::fs::write(out.join("mine.png"), "my picture").unwrap();
        let o = run(&args, d);
        assert_refused(&o, &["holds `mine.png`", marker]);
        assert_eq!(
            std::fs::read_to_string(out.join("mine.png")).unwrap(),
            "my picture"
        );
    }
}
