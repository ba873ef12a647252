//! Fuzz target: Nicholl-Lee-Nicholl (2D). See `../../tests/it/clip/check.rs` for the properties.
#![no_main]

#[path = "../../tests/it/clip/check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz_planar(data, &["nicholl-lee-nicholl"]);
});
