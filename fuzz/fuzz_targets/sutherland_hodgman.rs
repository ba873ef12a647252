//! Fuzz target: Sutherland-Hodgman: lines as 2-vertex polygons (homogeneous and 2D) and polygons. See `../../tests/it/clip/check.rs` for the properties.
#![no_main]

#[path = "../../tests/it/clip/check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz_homogeneous(data, &["sutherland-hodgman"]);
    check::fuzz_planar(data, &["sutherland-hodgman"]);
    check::fuzz_polygons(data);
});
