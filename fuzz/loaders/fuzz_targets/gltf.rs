#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| wireflight::harness::gltf(data));
