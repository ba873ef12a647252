//! The pure part of wireflight, for the loader fuzz targets (see `../Cargo.toml`), and the
//! harness they share with the corpus replay test.
#![allow(missing_docs, dead_code, unused_imports, rustdoc::broken_intra_doc_links)]

// The harness names the library `wireflight::…`, as the integration tests do.
extern crate self as wireflight;

#[path = "../../../src/camera.rs"]
pub mod camera;
#[path = "../../../src/clip/mod.rs"]
pub mod clip;
#[path = "../../../src/euler/mod.rs"]
pub mod euler;
#[path = "../../../src/flight/mod.rs"]
pub mod flight;
#[path = "../../../src/fsio.rs"]
pub mod fsio;
#[path = "../../../src/mesh/mod.rs"]
pub mod mesh;
#[path = "../../../src/numeric.rs"]
pub mod numeric;

pub mod app;

#[path = "../harness.rs"]
pub mod harness;
