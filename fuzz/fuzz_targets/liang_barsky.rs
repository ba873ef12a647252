//! Fuzz target: Liang-Barsky, homogeneous and 2D. See `../../tests/it/clip/check.rs` for the properties.
#![no_main]

#[path = "../../tests/it/clip/check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz_homogeneous(data, &["liang-barsky"]);
    check::fuzz_planar(data, &["liang-barsky"]);
});
