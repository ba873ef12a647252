//! Fuzz target: Cyrus-Beck, the clip-space polyhedron and the window as a convex polygon. See `../../tests/it/clip/check.rs` for the properties.
#![no_main]

#[path = "../../tests/it/clip/check.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check::fuzz_homogeneous(data, &["cyrus-beck"]);
    check::fuzz_planar(data, &["cyrus-beck"]);
});
