//! One function per loader fuzz target: feed it bytes, it must return (an error is fine) and
//! never panic, hang or allocate without bound; what loads must keep the type's promises.
//!
//! Shared by the fuzz targets (`fuzz_targets/*.rs`, whose library this file is) and the corpus
//! replay test (`tests/it/fuzz_corpus.rs`, stable), which includes it by path. It names the
//! library crates by their own names (`wireflight_flight`, `wireflight_draw`,
//! `wireflight_geometry`) and `glam`: both the fuzz crate and the root package depend on them,
//! so the same paths resolve in both.

use std::path::Path;

use wireflight_draw::flythrough::script::parse as parse_script;
use wireflight_draw::mesh_files::{gltf::parse as parse_gltf, obj::parse as parse_obj};
use wireflight_flight::data::parse as parse_flight_data;
use wireflight_flight::effects::Origin;
use wireflight_flight::model::{Model, Vehicle};
use wireflight_flight::params::FixedWingParams;
use wireflight_flight::spec::ModelSpec;
use wireflight_flight::trim::trim_level;
use wireflight_geometry::mesh::EdgeMesh;

/// Text as a loader sees it after reading a file (lossy, as for OBJ; the strict readers reject
/// non-UTF-8 before parsing, so this only widens what the parsers are shown).
fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// Flight-data CSV: parse (derives missing channels); what loads validates.
pub fn csv(data: &[u8]) {
    if let Ok(d) = parse_flight_data(&text(data), "fuzz.csv") {
        assert!(!d.is_empty());
        d.validate().expect("parsed data validate");
        let _ = d.controls_at(d.duration() * 0.5);
    }
}

/// An edge mesh keeps its promises: at least one edge, finite positions, indices in range.
fn check_mesh(m: &EdgeMesh) {
    assert!(!m.edges().is_empty());
    assert!(m.positions().iter().all(|p| p.is_finite()));
    let n = m.positions().len() as u32;
    assert!(m.edges().iter().all(|&[a, b]| a < n && b < n && a != b));
}

/// Wavefront OBJ.
pub fn obj(data: &[u8]) {
    if let Ok(m) = parse_obj(data, Path::new("fuzz.obj")) {
        check_mesh(&m);
    }
}

/// glTF (JSON) or GLB; external URIs resolve under a directory that does not exist.
pub fn gltf(data: &[u8]) {
    let path = Path::new("/nonexistent-wireflight-fuzz/model.gltf");
    if let Ok(m) = parse_gltf(data, path) {
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
    if let Ok(p) = FixedWingParams::from_toml(&text(data), "fuzz.toml") {
        let model = Model::new(Vehicle::FixedWing(Box::new(p)), Origin::default());
        let _ = trim_level(&model, 25.0, 0.0, glam::DVec3::new(0.0, 0.0, -100.0));
    }
}

/// The fly-through window's control script.
pub fn script(data: &[u8]) {
    let _ = parse_script(&text(data), "fuzz.txt");
}
