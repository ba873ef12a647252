//! Fuzz target: `harness::column_map` (../harness.rs): a column map and a CSV read through it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::column_map(data));
