//! Fuzz target: `harness::csv` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::csv(data));
