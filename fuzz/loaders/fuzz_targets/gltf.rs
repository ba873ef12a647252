//! Fuzz target: `harness::gltf` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::gltf(data));
