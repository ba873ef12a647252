//! Fuzz target: `harness::obj` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::obj(data));
