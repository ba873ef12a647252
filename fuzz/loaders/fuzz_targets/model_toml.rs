//! Fuzz target: `harness::model_toml` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::model_toml(data));
