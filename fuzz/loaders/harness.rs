//! One function per loader fuzz target: feed it bytes, it must return (an error is fine) and
//! never panic, hang or allocate without bound; what loads must keep the type's promises.
//!
//! Shared by the fuzz targets (`fuzz_targets/*.rs`, nightly) and the corpus replay test
//! (`tests/it/fuzz_corpus.rs`, stable), which includes this file by path.

use std::path::Path;

use wireflight::flight::effects::Origin;
use wireflight::flight::spec::ModelSpec;

/// Text as a loader sees it after reading a file (lossy, as for OBJ; the strict readers reject
/// non-UTF-8 before parsing, so this only widens what the parsers are shown).
fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// Flight-data CSV: parse (derives missing channels); what loads validates.
pub fn csv(data: &[u8]) {
    if let Ok(d) = wireflight::flight::data::parse(&text(data), "fuzz.csv") {
        assert!(!d.is_empty());
        d.validate().expect("parsed data validate");
        let _ = d.controls_at(d.duration() * 0.5);
    }
}

/// An edge mesh keeps its promises: at least one edge, finite positions, indices in range.
fn check_mesh(m: &wireflight::mesh::EdgeMesh) {
    assert!(!m.edges().is_empty());
    assert!(m.positions().iter().all(|p| p.is_finite()));
    let n = m.positions().len() as u32;
    assert!(m.edges().iter().all(|&[a, b]| a < n && b < n && a != b));
}

/// Wavefront OBJ.
pub fn obj(data: &[u8]) {
    if let Ok(m) = wireflight::mesh::obj::parse(data, Path::new("fuzz.obj")) {
        check_mesh(&m);
    }
}

/// glTF (JSON) or GLB; external URIs resolve under a directory that does not exist.
pub fn gltf(data: &[u8]) {
    let path = Path::new("/nonexistent-wireflight-fuzz/model.gltf");
    if let Ok(m) = wireflight::mesh::gltf::parse(data, path) {
        check_mesh(&m);
    }
}

/// A model file (TOML): parse, then build (which loads a named parameter set and checks every
/// effect parameter).
pub fn model_toml(data: &[u8]) {
    if let Ok(spec) = ModelSpec::from_toml(&text(data)) {
        let _ = spec.build(Origin::default());
    }
}

/// A fixed-wing parameter set (TOML): parse, then trim the aircraft in level flight.
pub fn params_toml(data: &[u8]) {
    use wireflight::flight::params::FixedWingParams;
    if let Ok(p) = FixedWingParams::from_toml(&text(data), "fuzz.toml") {
        let model = wireflight::flight::model::Model::new(
            wireflight::flight::model::Vehicle::FixedWing(Box::new(p)),
            Origin::default(),
        );
        let _ = wireflight::flight::trim::trim_level(
            &model,
            25.0,
            0.0,
            glam::DVec3::new(0.0, 0.0, -100.0),
        );
    }
}

/// The view's control script.
pub fn script(data: &[u8]) {
    let _ = wireflight::app::view::script::parse(&text(data), "fuzz.txt");
}
