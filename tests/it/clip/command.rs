//! `wireflight clip` end to end: the seed's examples through the CSV interface, homogeneous
//! and 2D, `--stats`, the batch path, and bad input (FILE:LINE, exit status 2, no panic, no
//! partial output); plus `render --clip-plane` and `--hidden-line`.

use std::path::Path;
use std::process::Output;

use crate::support::cli::{stderr, stdout, wireflight};

fn clip(dir: &Path, input: &str, extra: &[&str]) -> (Output, String) {
    let (inp, out) = (dir.join("in.csv"), dir.join("out.csv"));
    std::fs::write(&inp, input).unwrap();
    let _ = std::fs::remove_file(&out);
    let mut args = vec![
        "clip",
        "--input",
        inp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = wireflight(&args);
    let written = std::fs::read_to_string(&out).unwrap_or_default();
    (o, written)
}

#[test]
fn planar_seed_examples_through_the_csv_interface() {
    let dir = tempfile::tempdir().unwrap();
    let input = "x0,y0,x1,y1\n# the transcript's window 2..4\n5,3,6,2\n3,3,5,2\n\n1,3,5,2\n2.5,2.5,3.5,3.5\n";
    for algo in [
        "cohen-sutherland",
        "liang-barsky",
        "cyrus-beck",
        "nicholl-lee-nicholl",
        "sutherland-hodgman",
    ] {
        let (o, out) = clip(
            dir.path(),
            input,
            &["--algo", algo, "--rect", "2,2,4,4", "--stats"],
        );
        assert!(o.status.success(), "{algo}: {}", stderr(&o));
        assert_eq!(
            out, "x0,y0,x1,y1\n\n3,3,4,2.5\n2,2.75,4,2.25\n2.5,2.5,3.5,3.5\n",
            "{algo}"
        );
        let s = stdout(&o);
        assert!(
            s.contains("accepted 1,") && s.contains("ns per edge"),
            "{algo}: {s}"
        );
        assert!(
            std::fs::read_dir(dir.path()).unwrap().count() == 2,
            "stray files"
        );
    }
}

/// `--output` and `--window`, the old spellings of `--out` and `--rect`, still work, with a
/// note on stderr.
#[test]
fn old_spellings_of_out_and_rect_work_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let (inp, out) = (dir.path().join("in.csv"), dir.path().join("old.csv"));
    std::fs::write(&inp, "x0,y0,x1,y1\n1,3,5,2\n").unwrap();
    let o = wireflight(&[
        "clip",
        "--algo",
        "cohen-sutherland",
        "--input",
        inp.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--window",
        "2,2,4,4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "x0,y0,x1,y1\n2,2.75,4,2.25\n"
    );
    let e = stderr(&o);
    assert!(e.contains("--output is an old spelling of --out"), "{e}");
    assert!(e.contains("--window is an old spelling of --rect"), "{e}");
}

#[test]
fn homogeneous_edges_every_algorithm_and_the_batch() {
    let dir = tempfile::tempdir().unwrap();
    // Inside; outside (x > w); crossing x = w; behind the eye; NaN.
    let input = "0,0,0.5,1,0.5,0.5,0.5,1\n2,0,0.5,1,3,0,0.5,1\n0,0,0.5,1,3,0,0.5,1\n0,0,0.5,-1,1,1,0.5,-2\nnan,0,0,1,0,0,0.5,1\n";
    for algo in [
        "blinn",
        "blinn-batch",
        "cohen-sutherland",
        "liang-barsky",
        "cyrus-beck",
        "sutherland-hodgman",
    ] {
        let (o, out) = clip(dir.path(), input, &["--algo", algo, "--stats"]);
        assert!(o.status.success(), "{algo}: {}", stderr(&o));
        assert_eq!(
            out, "0,0,0.5,1,0.5,0.5,0.5,1\n\n0,0,0.5,1,1,0,0.5,1\n\n\n",
            "{algo}"
        );
        assert!(
            stdout(&o).contains("non-finite 1"),
            "{algo}: {}",
            stdout(&o)
        );
    }
    // −w ≤ z ≤ w keeps z = −0.5w, which 0 ≤ z ≤ w drops.
    let input = "0,0,-0.5,1,0.5,0,-0.5,1\n";
    let (_, out) = clip(
        dir.path(),
        input,
        &["--algo", "liang-barsky", "--depth", "minus-one-to-one"],
    );
    assert_eq!(out, "0,0,-0.5,1,0.5,0,-0.5,1\n");
    let (_, out) = clip(
        dir.path(),
        input,
        &["--algo", "liang-barsky", "--depth", "zero-to-one"],
    );
    assert_eq!(out, "\n");
}

#[test]
fn bad_input_names_the_line_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str], &str); 7] = [
        (
            "0,0,0,1,1,1,0,1\n0,0,0,1,1,x,0,1\n",
            &["--algo", "blinn"],
            "in.csv:2: column 6 (y1): `x` is not a number",
        ),
        // A first line of text that is not an edge's header is an error, not a header that
        // leaves the file without edges.
        (
            "abc\n0,0,0,1,1,1,0,1\n",
            &["--algo", "blinn"],
            "in.csv:1: expected 8 values",
        ),
        (
            "0,0,0,1\n",
            &["--algo", "blinn"],
            "in.csv:1: expected 8 values",
        ),
        (
            "0,0,0,1,1,1,0,1\n",
            &["--algo", "cohen-sutherland", "--rect", "0,0,1,1"],
            "in.csv:1: expected 4 values",
        ),
        (
            "0,0,0,1e50,1,1,0,1\n",
            &["--algo", "blinn"],
            "outside the f32 range",
        ),
        (
            "0,0,1,1\n",
            &["--algo", "nicholl-lee-nicholl"],
            "nicholl-lee-nicholl is a 2D algorithm",
        ),
        (
            "0,0,1,1\n",
            &["--algo", "blinn", "--rect", "0,0,1,1"],
            "blinn clips homogeneous edges",
        ),
    ];
    for (input, args, want) in cases {
        let (o, out) = clip(dir.path(), input, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
        assert!(out.is_empty(), "no output file on error");
    }
    // Over the size limit.
    let (o, _) = clip(
        dir.path(),
        "0,0,0,1,1,1,0,1\n",
        &["--algo", "blinn", "--max-bytes", "8"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("more than the limit of 8"),
        "{}",
        stderr(&o)
    );
    // Not UTF-8; a missing file; a bad window.
    std::fs::write(dir.path().join("bin.csv"), b"0,0,0,1\n\xff\xfe\n").unwrap();
    let o = wireflight(&[
        "clip",
        "--algo",
        "blinn",
        "--input",
        dir.path().join("bin.csv").to_str().unwrap(),
        "--out",
        dir.path().join("o.csv").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bin.csv:2: not UTF-8"),
        "{}",
        stderr(&o)
    );
    let (o, _) = clip(dir.path(), "", &["--algo", "blinn", "--rect", "4,0,1,1"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn render_with_clip_plane_and_hidden_line() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("half.png");
    let o = wireflight(&[
        "render",
        "--backend",
        "cpu",
        "--size",
        "160x120",
        "--clip-plane",
        "0,1,0,0",
        "--clipper",
        "cyrus-beck",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = wireflight(&[
        "render",
        "--clip-plane",
        "0,0,0,1",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "not a plane");
    // Hidden-line needs faces: the built-in plane has none; a cube OBJ has six.
    let o = wireflight(&["render", "--hidden-line", "--out", png.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("needs a mesh with faces"),
        "{}",
        stderr(&o)
    );
    let obj = dir.path().join("cube.obj");
    std::fs::write(
        &obj,
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    )
    .unwrap();
    let o = wireflight(&[
        "render",
        "--mesh",
        obj.to_str().unwrap(),
        "--hidden-line",
        "--yaw",
        "-30",
        "--pitch",
        "20",
        "--backend",
        "cpu",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(
        s.contains("back-facing 3") && s.contains("9 segments drawn"),
        "{s}"
    );
}
