//! Fuzz target: Weiler-Atherton polygon clipping (two small polygons, on the `i8` grid or in
//! `f64`). See `../../tests/it/clip/polygons/fuzz_check.rs` for the decoding and the properties.
#![no_main]

#[path = "../../tests/it/clip/polygons/fuzz_check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz(data);
});
