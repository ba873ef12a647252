//! Fuzz target: `harness::ulog` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::ulog(data));
