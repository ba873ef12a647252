//! Fuzz target: `harness::ulog_structured` (../harness.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::ulog_structured(data));
