//! Blinn's clipper throughput, in edges per second, on a reproducible random edge set.
//!
//! The set mixes the cases a real frame has, in fixed proportions: edges wholly inside the
//! view volume (trivial accept), wholly outside one plane (trivial reject), crossing one or
//! more planes (the t_in/t_out interval), and crossing the eye plane (one endpoint behind the
//! eye, w < 0). A tiny xorshift generator with a fixed seed makes every run clip the same
//! edges, so numbers are comparable between commits. Each benchmark also reports the mix's
//! outcome tally once, so a change in the mix is visible.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec4;

use wireflight::clip::{clip_edge, ClipStats, DepthRange};

/// xorshift64*: deterministic, no dependency, good enough to spread test edges.
struct Rng(u64);

impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40; // 24 bits
        bits as f32 / (1u64 << 24) as f32
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }
}

/// A point inside the wgpu volume (−w ≤ x, y ≤ w, 0 ≤ z ≤ w), w in [0.5, 50).
fn inside(rng: &mut Rng) -> Vec4 {
    let w = rng.range(0.5, 50.0);
    Vec4::new(rng.range(-w, w), rng.range(-w, w), rng.range(0.0, w), w)
}

/// A point outside, scaled up to 4× beyond the side planes.
fn outside(rng: &mut Rng) -> Vec4 {
    let w = rng.range(0.5, 50.0);
    let s = 4.0 * w;
    let mut p = Vec4::new(
        rng.range(-s, s),
        rng.range(-s, s),
        rng.range(-w, 2.0 * w),
        w,
    );
    if p.x.abs() <= w && p.y.abs() <= w {
        p.x += 2.0 * w; // push it out through the right plane
    }
    p
}

/// A point behind the eye (w < 0).
fn behind(rng: &mut Rng) -> Vec4 {
    let w = -rng.range(0.1, 20.0);
    Vec4::new(
        rng.range(-20.0, 20.0),
        rng.range(-20.0, 20.0),
        rng.range(-20.0, 20.0),
        w,
    )
}

/// 40% inside, 25% outside the same plane, 25% crossing, 10% through the eye plane.
fn edge_set(n: usize) -> Vec<(Vec4, Vec4)> {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    (0..n)
        .map(|i| match i % 20 {
            0..=7 => (inside(&mut rng), inside(&mut rng)),
            8..=12 => {
                // Both beyond x = w: trivially rejected.
                let (a, c) = (outside(&mut rng), outside(&mut rng));
                (
                    Vec4::new(a.w + 1.0 + a.x.abs(), a.y, a.z, a.w),
                    Vec4::new(c.w + 1.0 + c.x.abs(), c.y, c.z, c.w),
                )
            }
            13..=17 => (inside(&mut rng), outside(&mut rng)),
            _ => (inside(&mut rng), behind(&mut rng)),
        })
        .collect()
}

fn clipper(c: &mut Criterion) {
    const N: usize = 100_000;
    let edges = edge_set(N);
    let mut group = c.benchmark_group("blinn_clip");
    group.throughput(Throughput::Elements(N as u64));
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        let mut tally = ClipStats::default();
        for &(a, b) in &edges {
            tally.record(&clip_edge(a, b, depth));
        }
        eprintln!("{depth:?} mix: {tally:?}");
        group.bench_function(format!("{depth:?}: mixed edges"), |b| {
            b.iter(|| {
                let mut stats = ClipStats::default();
                for &(a, c) in &edges {
                    stats.record(&clip_edge(
                        std::hint::black_box(a),
                        std::hint::black_box(c),
                        depth,
                    ));
                }
                stats
            })
        });
    }
    group.finish();
}

criterion_group!(benches, clipper);
criterion_main!(benches);
