//! Fuzz target: `harness::params_toml` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::params_toml(data));
