//! The `clip` module of wireflight on its own, for the fuzz targets (see `../Cargo.toml`).
#![allow(missing_docs, rustdoc::broken_intra_doc_links)]

#[path = "../../src/clip/mod.rs"]
pub mod clip;
