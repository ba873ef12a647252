//! `wireflight clip --algo weiler-atherton` end to end: intersection and difference through the
//! polygon files, several subject polygons, holes, `--json`, `--picture`; bad files
//! (`FILE:LINE: problem`, exit status 2, nothing written) and options refused with other
//! algorithms; `--demo`'s pictures. `fuzz_check.rs` is the fuzz target's check, replayed by
//! `corpus`.

pub(crate) mod fuzz_check;

use std::path::Path;
use std::process::Output;

use crate::support::cli::{stderr, stdout, wireflight};

const U: &str = "0,0\n3,0\n3,3\n2,3\n2,1\n1,1\n1,3\n0,3\n";
const BAR: &str = "-1,2\n4,2\n4,2.5\n-1,2.5\n";

/// Run weiler-atherton on two files' texts; return the run and the output file (None: absent).
fn clip(dir: &Path, subject: &str, clip: &str, extra: &[&str]) -> (Output, Option<String>) {
    let (s, c, out) = (dir.join("s.txt"), dir.join("c.txt"), dir.join("out.txt"));
    std::fs::write(&s, subject).unwrap();
    std::fs::write(&c, clip).unwrap();
    let _ = std::fs::remove_file(&out);
    let mut args = vec![
        "clip",
        "--algo",
        "weiler-atherton",
        "--subject",
        s.to_str().unwrap(),
        "--clip",
        c.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = wireflight(&args);
    (o, std::fs::read_to_string(&out).ok())
}

/// The polygons of an output file.
fn polygons(out: &str) -> Vec<Vec<(f64, f64)>> {
    out.split("\n\n")
        .filter(|p| !p.trim().is_empty())
        .map(|p| {
            p.lines()
                .map(|l| {
                    let (x, y) = l.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect()
}

fn area(p: &[(f64, f64)]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| p[i].0 * p[(i + 1) % n].1 - p[(i + 1) % n].0 * p[i].1)
        .sum::<f64>()
        / 2.0
}

#[test]
fn intersection_and_difference_of_a_u_and_a_bar() {
    let dir = tempfile::tempdir().unwrap();
    let (o, out) = clip(dir.path(), U, BAR, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = out.expect("output written");
    let p = polygons(&out);
    assert_eq!(p.len(), 2, "{out}");
    assert!(p.iter().all(|r| (area(r) - 0.5).abs() < 1e-12), "{out}");
    let s = stdout(&o);
    assert!(
        s.contains("intersection of 1 subject polygon")
            && s.contains("2 pieces")
            && s.contains("area 1)"),
        "{s}"
    );
    // Difference: the U's base and the tops of its arms; 7 − 1 = 6.
    let (o, out) = clip(dir.path(), U, BAR, &["--op", "difference"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let p = polygons(&out.unwrap());
    assert_eq!(p.len(), 3);
    let total: f64 = p.iter().map(|r| area(r)).sum();
    assert!((total - 6.0).abs() < 1e-12, "{total}");
}

#[test]
fn several_subjects_holes_and_json() {
    let dir = tempfile::tempdir().unwrap();
    // Two subject squares, one around the clip square (a hole), one beside it (untouched);
    // the clip file's second polygon is not used.
    let subjects = "# two squares\n0,0\n4,0\n4,4\n0,4\n\n\n10,0\n12,0\n12,2\n10,2\n";
    let clip_file = "1,1\n3,1\n3,3\n1,3\n\n100,100\n101,100\n101,101\n";
    let (o, out) = clip(
        dir.path(),
        subjects,
        clip_file,
        &["--op", "difference", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let p = polygons(&out.unwrap());
    assert_eq!(p.len(), 3, "outline, hole, second square");
    assert_eq!(area(&p[0]), 16.0);
    assert_eq!(area(&p[1]), -4.0, "the hole is clockwise");
    assert_eq!(area(&p[2]), 4.0);
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(json["area"], 16.0);
    assert_eq!(json["polygons"].as_array().unwrap().len(), 3);
    assert_eq!(json["polygons"][1].as_array().unwrap().len(), 4);
    assert_eq!(json["pieces"][0]["outer"], 0);
    assert_eq!(json["pieces"][0]["holes"][0], 1);
    assert_eq!(json["pieces"][1]["holes"].as_array().unwrap().len(), 0);
    // The intersection: the clip square, once; nothing of the far square.
    let (o, out) = clip(dir.path(), subjects, clip_file, &["--json"]);
    assert!(o.status.success());
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(json["area"], 4.0);
    assert_eq!(polygons(&out.unwrap()).len(), 1);
    // No overlap at all: an empty output file and area 0.
    let (o, out) = clip(
        dir.path(),
        "0,0\n1,0\n1,1\n",
        "5,5\n6,5\n6,6\n",
        &["--json"],
    );
    assert!(o.status.success());
    assert_eq!(out.as_deref(), Some(""));
    assert_eq!(
        stdout(&o).trim(),
        r#"{"polygons": [], "pieces": [], "area": 0}"#
    );
}

#[test]
fn picture_is_written_and_not_blank() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("p.png");
    let (o, out) = clip(dir.path(), U, BAR, &["--picture", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_some());
    let image = wireflight::draw::render::Image::decode_png(&std::fs::read(&png).unwrap()).unwrap();
    let background = image.pixel(0, 0);
    let mut colours = std::collections::HashSet::new();
    for y in 0..image.height {
        for x in 0..image.width {
            colours.insert(image.pixel(x, y));
        }
    }
    assert!(
        colours.len() >= 4,
        "background and three outlines: {colours:?}"
    );
    assert!(colours.contains(&background));
    // Not a PNG name: refused, nothing written.
    let (o, out) = clip(dir.path(), U, BAR, &["--picture", "p.svg"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(out.is_none());
}

#[test]
fn bad_files_name_the_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("p.png");
    let cases: [(&str, &str, &str); 8] = [
        (
            "0,0\n2,2\n2,0\n0,2\n",
            BAR,
            "s.txt:1: polygon 1 is not simple: the edge from line 1 to line 2 meets the edge from line 3 to line 4 at (1, 1)",
        ),
        (
            U,
            "# a bow tie\n0,0\n2,0\n0,2\n2,2\n",
            "c.txt:3: polygon 1 is not simple: the edge from line 3 to line 4 meets the edge from line 5 to line 2 at (1, 1)",
        ),
        (U, "0,0\n1,zero\n1,1\n", "c.txt:2: column 2 (y): `zero` is not a number"),
        (U, "0,0,0\n1,0\n1,1\n", "c.txt:1: expected 2 values (x,y), found 3"),
        ("", BAR, "s.txt: no polygon"),
        ("# only a comment\n\n", BAR, "s.txt: no polygon"),
        (U, "0,0\n1,1\n\n2,2\n3,3\n4,2\n", "c.txt:1: polygon 1 has 2 vertices"),
        (U, "0,0\n0,0\n1,1\n0,0\n", "c.txt:1: polygon 1 has 2 distinct vertices"),
    ];
    for (subject, clip_text, want) in cases {
        let (o, out) = clip(
            dir.path(),
            subject,
            clip_text,
            &["--picture", png.to_str().unwrap()],
        );
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{want}: {err}");
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "want {want}\ngot {err}"
        );
        assert!(out.is_none(), "{want}: output written");
        assert!(!png.exists(), "{want}: picture written");
    }
    // Non-finite values; a missing file.
    let (o, _) = clip(dir.path(), U, "0,0\ninf,0\n1,1\n", &[]);
    assert!(stderr(&o).contains("c.txt:2: column 1 (x): `inf` is not a finite number"));
    let o = wireflight(&[
        "clip",
        "--algo",
        "weiler-atherton",
        "--subject",
        "no/such.txt",
        "--clip",
        "no/such.txt",
        "--out",
        dir.path().join("o.txt").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("o.txt").exists());
}

#[test]
fn options_belong_to_their_algorithms() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.txt");
    let out = out.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &["--algo", "blinn", "--subject", "a", "--out", out],
            "--subject is for --algo weiler-atherton",
        ),
        (
            &[
                "--algo",
                "liang-barsky",
                "--input",
                "a",
                "--op",
                "difference",
                "--out",
                out,
            ],
            "--op is for --algo weiler-atherton",
        ),
        (
            &["--algo", "blinn", "--out", out],
            "--algo blinn clips edges: give --input",
        ),
        (
            &["--algo", "weiler-atherton", "--input", "a", "--out", out],
            "leave out --input",
        ),
        (
            &["--algo", "weiler-atherton", "--subject", "a", "--out", out],
            "needs --subject FILE and --clip FILE",
        ),
    ];
    for (args, want) in cases {
        let mut a = vec!["clip"];
        a.extend_from_slice(args);
        let o = wireflight(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert!(!Path::new(out).exists());
    }
}

/// The demo's pictures, by file name.
const DEMO: [&str; 6] = [
    "concave-pieces.png",
    "difference.png",
    "hole.png",
    "shared-vertex.png",
    "collinear-overlap.png",
    "vertex-on-edge.png",
];

fn demo(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "clip",
        "--algo",
        "weiler-atherton",
        "--demo",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    wireflight(&args)
}

#[test]
fn demo_writes_every_picture_in_its_colours() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("wa");
    let o = demo(&out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = stdout(&o);
    assert!(
        said.starts_with("wrote 6 pictures (concave-pieces.png, difference.png")
            && said.contains("and wireflight-clip-demo.txt to"),
        "{said}"
    );
    let manifest = std::fs::read_to_string(out.join("wireflight-clip-demo.txt")).unwrap();
    // The results, counted by the clipper: the cases' points.
    for line in [
        "concave-pieces.png\t640x480\tconcave comb and concave c; result: 8 pieces, 0 holes, area 8",
        "difference.png\t640x480\tconcave comb minus concave c; result: 9 pieces, 0 holes, area 15",
        "hole.png\t640x480\tone inside the other; result: 1 piece, 1 hole,",
        "shared-vertex.png\t640x480\tshared vertex; result: 1 piece, 0 holes, area 12.625",
        "collinear-overlap.png\t640x480\tcollinear overlapping edges; result: 1 piece, 0 holes, area 4",
        "vertex-on-edge.png\t640x480\tvertex on an edge; result: 2 pieces, 0 holes, area 6",
    ] {
        assert!(manifest.contains(line), "{line}\n{manifest}");
    }
    // Subject, clip polygon, result outline and hatching each drawn, in their own colours.
    let colours: [(&str, [u8; 4]); 4] = [
        ("subject", [90, 150, 255, 255]),
        ("clip polygon", [255, 160, 60, 255]),
        ("result", [80, 255, 120, 255]),
        ("hatching", [30, 110, 55, 255]),
    ];
    for name in DEMO {
        let image =
            wireflight::draw::render::Image::decode_png(&std::fs::read(out.join(name)).unwrap())
                .unwrap();
        assert_eq!((image.width, image.height), (640, 480), "{name}");
        let mut count = std::collections::HashMap::new();
        for y in 0..image.height {
            for x in 0..image.width {
                *count.entry(image.pixel(x, y)).or_insert(0usize) += 1;
            }
        }
        for (what, colour) in colours {
            // A few hundred pixels at least: an outline, not a stray dot.
            let n = count.get(&colour).copied().unwrap_or(0);
            assert!(n >= 200, "{name}: {what} has {n} pixels");
        }
    }
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), DEMO.len() + 1);
    // Run again into the same directory: replaced as a whole.
    let o = demo(&out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), DEMO.len() + 1);
}

#[test]
fn demo_refuses_what_it_would_overwrite_and_foreign_options() {
    let dir = tempfile::tempdir().unwrap();
    // Not a directory; a directory of someone else's files: refused, left as they were.
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "mine").unwrap();
    let theirs = dir.path().join("theirs");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::write(theirs.join("a.png"), "theirs").unwrap();
    for (out, want) in [
        (&file, "exists and is not a directory"),
        (&theirs, "was not written by this command"),
    ] {
        let o = demo(out, &[]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains(want) && err.contains("--out") && !err.contains("panicked"),
            "{err}"
        );
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    assert_eq!(
        std::fs::read_to_string(theirs.join("a.png")).unwrap(),
        "theirs"
    );
    assert_eq!(std::fs::read_dir(&theirs).unwrap().count(), 1);
    // The files' options do not mix with it, and other algorithms have no demo.
    let out = dir.path().join("wa");
    for (extra, want) in [
        (&["--subject", "s.txt"][..], "cannot be used with"),
        (&["--json"][..], "cannot be used with"),
        (&["--picture", "p.png"][..], "cannot be used with"),
    ] {
        let o = demo(&out, extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&o).contains(want), "{}", stderr(&o));
    }
    let o = wireflight(&[
        "clip",
        "--algo",
        "blinn",
        "--demo",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--algo blinn clips edges: give --input"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    // Nothing was left beside them (no staging directory).
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["notes.txt", "theirs"]);
}
