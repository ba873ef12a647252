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
