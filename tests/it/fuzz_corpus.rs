//! The loader fuzz targets' corpus (`fuzz/loaders/corpus/TARGET/`), replayed on stable through
//! the same harness (`fuzz/loaders/harness.rs`): every file must load or be refused, never
//! panic. Crashes the fuzzer found are kept there as regression inputs.

#[path = "../../fuzz/loaders/harness.rs"]
mod harness;

use std::path::Path;

fn replay(target: &str, run: fn(&[u8])) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/loaders/corpus")
        .join(target);
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let outcome = std::panic::catch_unwind(|| run(&bytes));
        assert!(outcome.is_ok(), "{} panicked", path.display());
        n += 1;
    }
    assert!(n > 0, "{}: empty corpus", dir.display());
}

#[test]
fn csv() {
    replay("csv", harness::csv);
}

#[test]
fn column_map() {
    replay("column_map", harness::column_map);
}

#[test]
fn obj() {
    replay("obj", harness::obj);
}

#[test]
fn gltf() {
    replay("gltf", harness::gltf);
}

#[test]
fn model_toml() {
    replay("model_toml", harness::model_toml);
}

#[test]
fn params_toml() {
    replay("params_toml", harness::params_toml);
}

#[test]
fn script() {
    replay("script", harness::script);
}

#[test]
fn ulog() {
    replay("ulog", harness::ulog);
}

#[test]
fn ulog_structured() {
    replay("ulog_structured", harness::ulog_structured);
}
