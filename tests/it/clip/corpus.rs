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
        other => panic!("fuzz/corpus/{other}: no such target"),
    }
}

#[test]
fn fuzz_corpus_replays_clean() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    let mut files = 0;
    let mut targets = 0;
    for dir in std::fs::read_dir(&root).unwrap_or_else(|e| panic!("{}: {e}", root.display())) {
        let dir = dir.unwrap().path();
        let target = dir.file_name().unwrap().to_string_lossy().into_owned();
        targets += 1;
        for f in std::fs::read_dir(&dir).unwrap() {
            let path = f.unwrap().path();
            let data = std::fs::read(&path).unwrap();
            let result = std::panic::catch_unwind(|| run(&target, &data));
            assert!(result.is_ok(), "{} fails its check", path.display());
            files += 1;
        }
    }
    assert!(
        targets >= 6 && files >= 6,
        "{targets} targets, {files} files"
    );
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
    }
}
