//! Hostile-input reproductions: outputs onto things that are not files, the sweep of dead runs'
//! temporaries, and text from input printed on a terminal.

use super::*;
use std::os::unix::fs::FileTypeExt;

#[test]
fn an_output_onto_a_fifo_or_a_device_is_refused_and_left_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("pipe.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let o = run(&["simulate", "--duration", "2", "--out", "pipe.csv"], d);
    assert_refused(&o, &["pipe.csv", "not a regular file", "a FIFO"]);
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    // /dev/null must stay a character device whoever runs this (root could rename over it).
    let o = run(&["simulate", "--duration", "2", "--out", "/dev/null"], d);
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    assert_refused(&o, &["/dev/null", "not a regular file", "a device"]);
    // A link to it too.
    std::os::unix::fs::symlink("/dev/null", d.join("null.csv")).unwrap();
    let o = run(&["simulate", "--duration", "2", "--out", "null.csv"], d);
    assert_refused(&o, &["null.csv", "not a regular file"]);
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
}

#[test]
fn the_sweep_removes_only_wireflights_own_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Another program's temporaries with dead PIDs: not wireflight's to delete.
    std::fs::write(d.join(".notes.tmp-999999"), "x\n").unwrap();
    std::fs::write(d.join(".notes.tmp-4294967295"), "x\n").unwrap();
    std::fs::create_dir(d.join(".build.tmp-4294967294")).unwrap();
    std::fs::write(d.join(".build.tmp-4294967294/keep"), "x\n").unwrap();
    // wireflight's name on a directory it did not stage.
    std::fs::create_dir(d.join(".x.wireflight.tmp-4294967293")).unwrap();
    flight(d, "new.csv", &[]);
    for kept in [
        ".notes.tmp-999999",
        ".notes.tmp-4294967295",
        ".build.tmp-4294967294/keep",
        ".x.wireflight.tmp-4294967293",
    ] {
        assert!(d.join(kept).exists(), "{kept} was deleted");
    }
}

#[test]
fn control_characters_from_input_are_escaped_in_messages() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A file name that would set the terminal's title and clear the screen.
    let name = "evil\u{1b}]0;pwned\u{7}\u{1b}[2J.csv";
    std::fs::write(d.join(name), "not,a,flight\n1,2\n").unwrap();
    let o = run(&["compare", "--flight", name], d);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert!(
        err.contains(r"evil\u{1b}]0;pwned\u{7}\u{1b}[2J.csv"),
        "{err}"
    );
}

/// No output may be an input: the flight under its own name, another spelling or a hard
/// link, for every command that writes over a file it reads; an output directory replaced
/// whole that holds an input. Refused before any work, the input left as it was.
#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let f = flight(d, "f.csv", &[]);
    let before = std::fs::read(&f).unwrap();
    std::fs::hard_link(&f, d.join("linked.csv")).unwrap();
    // The flight under the names of other outputs: a page, a model file.
    std::fs::hard_link(&f, d.join("f.html")).unwrap();
    std::fs::hard_link(&f, d.join("m.toml")).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    for (args, words) in [
        (
            vec!["import", "--flight", "f.csv", "--out", "f.csv"],
            vec!["f.csv", "--out names the --flight file"],
        ),
        (
            vec!["import", "--flight", "f.csv", "--out", "./sub/../f.csv"],
            vec!["--out names the --flight file (as f.csv)"],
        ),
        (
            vec!["import", "--flight", "f.csv", "--out", "linked.csv"],
            vec!["linked.csv", "--out names the --flight file"],
        ),
        (
            vec!["compare", "--flight", "f.html", "--report", "f.html"],
            vec!["f.html", "--report names the --flight file"],
        ),
        (
            vec!["compare", "--flight", "f.csv", "--report", "f.html"],
            vec!["--report names the --flight file (as f.csv)"],
        ),
        (
            vec!["diagnose", "--flight", "f.csv", "--out", "m.toml"],
            vec!["--out names the --flight file (as f.csv)"],
        ),
        (
            vec!["simulate", "--model", "f.csv", "--out", "f.csv"],
            vec!["--out names the --model file"],
        ),
        (
            vec!["render", "--flight", "f.csv", "--frames-dir", "."],
            vec!["--frames-dir is replaced whole", "f.csv"],
        ),
        (
            vec!["compare", "--flight", "f.csv", "--plots", "."],
            vec!["--plots is replaced whole"],
        ),
    ] {
        let o = run(&args, d);
        assert_refused(&o, &words);
        assert_eq!(
            std::fs::read(&f).unwrap(),
            before,
            "{args:?} changed the flight"
        );
    }
}

/// The test flight as its own reference under any name — a spelling, a link, a byte-identical
/// copy — is refused: judged against itself a flight is always normal. The same reference
/// twice is used once, with a note.
#[test]
fn a_flight_is_never_its_own_reference_and_a_reference_counts_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let f = flight(d, "q.csv", &["--hidden", "aircraft:c_m_q=-20"]);
    std::fs::copy(&f, d.join("copy.csv")).unwrap();
    std::os::unix::fs::symlink(&f, d.join("sym.csv")).unwrap();
    for reference in ["./q.csv", "copy.csv", "sym.csv"] {
        let o = run(
            &["diagnose", "--flight", "q.csv", "--reference", reference],
            d,
        );
        assert_refused(&o, &[reference, "cannot be its own reference"]);
    }
    let r = flight(d, "r.csv", &["--seed", "2"]);
    std::fs::copy(&r, d.join("r2.csv")).unwrap();
    let o = run(
        &[
            "compare",
            "--flight",
            "q.csv",
            "--reference",
            "r.csv",
            "--reference",
            "r2.csv",
            "--json",
        ],
        d,
    );
    assert_ok(&o);
    assert!(
        stderr(&o).contains("--reference r2.csv is r.csv again"),
        "{}",
        stderr(&o)
    );
}
