//! Fuzz target: Blinn's homogeneous clipper, per edge and the batch paths (exactly equal). See `../../tests/it/clip/check.rs` for the properties.
#![no_main]

#[path = "../../tests/it/clip/check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz_homogeneous(data, &["blinn"]);
});
