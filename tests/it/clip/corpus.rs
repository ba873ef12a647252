//! The fuzz corpus replayed as ordinary tests on stable: every file in `fuzz/corpus/<target>/`
//! goes through the same decoding and property check as the fuzz target of that name.

use super::check::{fuzz_homogeneous, fuzz_planar, fuzz_polygons, HOMOGENEOUS, PLANAR};
use std::path::PathBuf;

/// Run a target's check on some input (the same dispatch as `fuzz/fuzz_targets/*.rs`).
fn run(target: &str, data: &[u8]) {
    match target {
        "blinn" => fuzz_homogeneous(data, &["blinn"]),
        "cohen_sutherland" => {
            fuzz_homogeneous(data, &["cohen-sutherland"]);
            fuzz_planar(data, &["cohen-sutherland"]);
        }
        "liang_barsky" => {
            fuzz_homogeneous(data, &["liang-barsky"]);
            fuzz_planar(data, &["liang-barsky"]);
        }
        "cyrus_beck" => {
            fuzz_homogeneous(data, &["cyrus-beck"]);
            fuzz_planar(data, &["cyrus-beck"]);
        }
        "nicholl_lee_nicholl" => fuzz_planar(data, &["nicholl-lee-nicholl"]),
        "sutherland_hodgman" => {
            fuzz_homogeneous(data, &["sutherland-hodgman"]);
            fuzz_planar(data, &["sutherland-hodgman"]);
            fuzz_polygons(data);
        }
        "weiler_atherton" => super::polygons::fuzz_check::fuzz(data),
        other => panic!("fuzz/corpus/{other}: no such target"),
    }
}

/// The fuzz targets, as named in `fuzz/Cargo.toml` and as folders of `fuzz/corpus/`.
const TARGETS: [&str; 7] = [
    "blinn",
    "cohen_sutherland",
    "liang_barsky",
    "cyrus_beck",
    "nicholl_lee_nicholl",
    "sutherland_hodgman",
    "weiler_atherton",
];

#[test]
fn fuzz_corpus_replays_clean() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    let mut failures = Vec::new();
    for target in TARGETS {
        let dir = root.join(target);
        let mut files = 0;
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.unwrap().path();
            let data = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            if std::panic::catch_unwind(|| run(target, &data)).is_err() {
                failures.push(path.display().to_string());
            }
            files += 1;
        }
        // The committed corpus is the minimized one plus seeds: an empty folder means it was
        // lost, and the replay would then check nothing.
        assert!(files >= 5, "{}: only {files} inputs", dir.display());
    }
    // Every folder is a target this test knows (a new target needs a line in `run`).
    for entry in std::fs::read_dir(&root).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            TARGETS.contains(&name.as_str()),
            "fuzz/corpus/{name}: no such target"
        );
    }
    assert!(
        failures.is_empty(),
        "inputs failing their check:\n{}",
        failures.join("\n")
    );
}

/// The fuzz crate declares exactly the targets replayed here.
#[test]
fn fuzz_targets_match_the_replay() {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz/Cargo.toml");
    let text = std::fs::read_to_string(&manifest).unwrap();
    let mut declared: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("name = \""))
        .filter_map(|l| l.strip_suffix('"'))
        .filter(|n| *n != "wireflight-fuzz" && *n != "wireflight")
        .collect();
    declared.sort_unstable();
    let mut known = TARGETS.to_vec();
    known.sort_unstable();
    assert_eq!(declared, known, "{}", manifest.display());
}

/// Every algorithm on the empty input and a few hand-made ones (the corpus may be empty on
/// a fresh checkout of a target).
#[test]
fn fuzz_checks_accept_hand_made_inputs() {
    let inputs: [&[u8]; 4] = [
        b"",
        &[0u8; 40],
        &[3u8; 64],
        b"\x01\x00\x02\x00\x04\x00\x06\x00\x08\x00\x03\x00\x05\x00\x07\x00\x09\x00\x0b\x00\x03",
    ];
    for data in inputs {
        fuzz_homogeneous(data, &HOMOGENEOUS);
        fuzz_planar(data, &PLANAR);
        fuzz_polygons(data);
        super::polygons::fuzz_check::fuzz(data);
    }
}
