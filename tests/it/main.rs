//! All integration tests, built and linked as one binary (linking wgpu once instead of once
//! per file is most of the build time of `cargo test` on a small machine).
//!
//! Run one topic with `cargo test --test it <module>::`, e.g. `cargo test --test it golden::`.
//! Shared helpers (the approximate-equality macro, a seeded generator, the clipper's
//! brute-force reference, the binary's launcher and `simulate` command lines) live in
//! [`support`]; data files a test needs live in `tests/data/`.

mod support;

mod accelerometer;
mod cli;
mod clip;
mod diagnose;
mod discover;
mod discover_real;
mod effects_cmd;
mod euler;
mod euler_cli;
mod euler_pictures;
mod euler_sequences;
mod filter_error;
mod flight_data;
mod flight_model;
mod fuzz_corpus;
mod golden;
mod gpu_backend;
mod hardening;
mod identify;
mod independent;
mod layers;
mod logs;
mod mesh_loaders;
mod mk82;
mod overlay;
mod pictures;
mod plots;
mod readme;
mod reference_flights;
mod report;
mod sensor_errors;
mod sensors;
mod several_causes;
mod terms;
mod terms_window;
mod tiers;
mod turbulence;
mod turbulence_fit;
mod view;
mod view_gimbal;
mod wandering_errors;
