//! Fuzz target: `harness::script` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::script(data));
