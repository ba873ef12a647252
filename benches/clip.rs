//! The clipping lab's benchmarks: every algorithm on the same edge sets in one run, in edges
//! per second, beside a memory-bandwidth reference measured in the same run.
//!
//! Homogeneous edge sets, 1 048 576 edges each (32 MiB of input, more than any cache here),
//! made once from fixed seeds:
//!
//! * `inside`: every edge inside the volume (trivial accept);
//! * `outside`: every edge outside one plane (trivial reject);
//! * `crossing`: half inside, half crossing one to three planes;
//! * `behind`: half inside, half from inside to behind the eye (w < 0: out through four to
//!   six planes at once), the crossing set's layout with the mixed set's slowest kind;
//! * `mixed`: 40% inside, 25% outside one plane, 25% crossing, 10% through the eye plane (the
//!   set of the earlier benchmark);
//! * `flythrough`: the clip-space edges of 40 frames of a flight around the window's world
//!   (ground grid, hills, runway, structures, horizon), about 1 M edges.
//!
//! `copy` is a streaming copy of the same bytes (the eight coordinate arrays, 32 B per edge,
//! into eight others): the bandwidth reference. `copy-blocks` copies them the way the batch
//! writes: 64 edges at a time into nine vectors (the eight and the edge indices), 36 B out. `blinn-batch` is the structure-of-arrays
//! path ([`wireflight::geometry::clip::batch::clip_soa`]: its AVX-512 build where the CPU has
//! one, the portable build elsewhere, chosen at run time); every other line is the
//! straightforward per-edge loop (clip, tally, push the segment). 2D algorithms run on 2D sets of the same
//! kinds. `scene_1m` transforms, clips and projects a 1 M-edge mesh through
//! [`EdgeProjector`] (rayon on all cores, and on one thread for comparison).
//!
//! `clip-cached/*` repeat the homogeneous sets with their first 8 192 edges (cache-resident:
//! the clippers' own cost, where `clip/*` at 1 M edges is bound by DRAM for the fast paths).
//!
//! `WIREFLIGHT_BENCH_EDGES` overrides the set size (e.g. 65536 for a quick run).
//! `WIREFLIGHT_BENCH_CPU_TIME=1` times the single-threaded `clip/*` and `clip-cached/*`
//! benchmarks by the thread's CPU time instead of the wall clock (Linux only; elsewhere it is
//! ignored): on a machine whose cores are shared, the wall clock also counts the slices the
//! scheduler gave to other processes, which swings a ratio to the copy more than the code does.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Bencher, BenchmarkGroup, Criterion, Throughput};
use glam::{Mat4, Vec2, Vec3, Vec4};

use wireflight::geometry::camera::{Camera, Projection};
use wireflight::geometry::clip::batch::{clip_soa, EdgesSoa, SegmentsSoa};
use wireflight::geometry::clip::{
    cohen_sutherland, cyrus_beck, liang_barsky, nicholl_lee_nicholl, sutherland_hodgman,
    ClipOutcome, ClipStats, ClipVolume, Clipper, DepthRange, Window2,
};
use wireflight::geometry::mesh::world::{World, WorldSpec};
use wireflight::geometry::mesh::{EdgeMesh, EdgeMeshBuilder};
use wireflight::geometry::pipeline::{EdgeProjector, Viewport};

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40;
        bits as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }
}

const DEPTH: DepthRange = DepthRange::ZeroToOne;

fn inside(rng: &mut Rng) -> Vec4 {
    let w = rng.range(0.5, 50.0);
    Vec4::new(rng.range(-w, w), rng.range(-w, w), rng.range(0.0, w), w)
}

fn beyond_right(rng: &mut Rng) -> Vec4 {
    let p = inside(rng);
    Vec4::new(p.w * rng.range(1.01, 4.0), p.y, p.z, p.w)
}

fn crossing(rng: &mut Rng) -> (Vec4, Vec4) {
    let a = inside(rng);
    let mut c = inside(rng);
    let k = rng.range(1.05, 3.0);
    c.x = c.w * k;
    if rng.next_f32() < 0.5 {
        c.y = -c.w * k;
    }
    if rng.next_f32() < 0.3 {
        c.z = c.w * k;
    }
    (a, c)
}

fn behind(rng: &mut Rng) -> Vec4 {
    Vec4::new(
        rng.range(-20.0, 20.0),
        rng.range(-20.0, 20.0),
        rng.range(-20.0, 20.0),
        -rng.range(0.1, 20.0),
    )
}

fn set(kind: &str, n: usize) -> Vec<(Vec4, Vec4)> {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    (0..n)
        .map(|i| match kind {
            "inside" => (inside(&mut rng), inside(&mut rng)),
            "outside" => (beyond_right(&mut rng), beyond_right(&mut rng)),
            "crossing" if i % 2 == 0 => (inside(&mut rng), inside(&mut rng)),
            "crossing" => crossing(&mut rng),
            "behind" if i % 2 == 0 => (inside(&mut rng), inside(&mut rng)),
            "behind" => (inside(&mut rng), behind(&mut rng)),
            _ => match i % 20 {
                0..=7 => (inside(&mut rng), inside(&mut rng)),
                8..=12 => (beyond_right(&mut rng), beyond_right(&mut rng)),
                13..=17 => crossing(&mut rng),
                _ => (inside(&mut rng), behind(&mut rng)),
            },
        })
        .collect()
}

/// Clip-space edges of 40 frames circling the world at 120 m.
fn flythrough(target: usize) -> Vec<(Vec4, Vec4)> {
    let world = World::new(&WorldSpec::default());
    let far = 12_000.0;
    let mut edges = Vec::with_capacity(target);
    let mut frame = 0;
    while edges.len() < target {
        let a = frame as f32 * 0.157;
        let eye = Vec3::new(900.0 * a.cos(), 900.0 * a.sin(), 120.0);
        let ahead = Vec3::new(-a.sin(), a.cos(), -0.15);
        let camera = Camera {
            eye,
            target: eye + ahead,
            up: Vec3::Z,
            projection: Projection::Perspective {
                fov_y: 55f32.to_radians(),
                near: 0.5,
                far,
            },
        };
        let m = camera.clip_from_world(16.0 / 9.0, DEPTH);
        let horizon = m * Mat4::from_translation(eye) * Mat4::from_scale(Vec3::splat(0.95 * far));
        for (mesh, mm) in [
            (&world.grid, m),
            (&world.hills, m),
            (&world.runway, m),
            (&world.structures, m),
            (&world.horizon, horizon),
        ] {
            let clip: Vec<Vec4> = mesh
                .positions()
                .iter()
                .map(|p| mm * p.extend(1.0))
                .collect();
            edges.extend(
                mesh.edges()
                    .iter()
                    .map(|&[i, j]| (clip[i as usize], clip[j as usize])),
            );
        }
        frame += 1;
    }
    edges.truncate(target);
    edges
}

/// The straightforward per-edge loop: clip, tally, keep the segment.
fn per_edge<P: Copy>(
    edges: &[(P, P)],
    out: &mut Vec<(P, P)>,
    clip: impl Fn(P, P) -> ClipOutcome<P>,
) -> ClipStats {
    out.clear();
    let mut stats = ClipStats::default();
    for &(a, c) in edges {
        let o = clip(black_box(a), black_box(c));
        stats.record(&o);
        if let Some(s) = o.segment() {
            out.push(s);
        }
    }
    stats
}

/// The calling thread's CPU time so far (`CLOCK_THREAD_CPUTIME_ID`).
#[cfg(target_os = "linux")]
fn thread_cpu_time() -> Duration {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: glibc's (and musl's) `clock_gettime` on 64-bit Linux writes one `timespec`
    // (two 64-bit fields, as declared) through the pointer, which is valid and exclusive.
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    Duration::new(t.sec as u64, t.nsec as u32)
}

/// Whether to time by the thread's CPU time (`WIREFLIGHT_BENCH_CPU_TIME=1`, Linux only).
fn cpu_time() -> bool {
    cfg!(all(target_os = "linux", target_pointer_width = "64"))
        && std::env::var("WIREFLIGHT_BENCH_CPU_TIME").is_ok_and(|v| v == "1")
}

/// Criterion's `iter` timed by the wall clock or, with `cpu` set, by the thread's CPU time
/// (the time this thread spent on a core, whoever else shares it).
fn timed<R>(b: &mut Bencher<'_>, cpu: bool, mut routine: impl FnMut() -> R) {
    b.iter_custom(|iters| {
        let clock = || -> Duration {
            #[cfg(target_os = "linux")]
            if cpu {
                return thread_cpu_time();
            }
            Duration::ZERO
        };
        let (wall, start) = (Instant::now(), clock());
        for _ in 0..iters {
            black_box(routine());
        }
        if cpu {
            clock() - start
        } else {
            wall.elapsed()
        }
    });
}

fn configure(g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>, n: usize) {
    g.throughput(Throughput::Elements(n as u64));
}

fn edges_count() -> usize {
    std::env::var("WIREFLIGHT_BENCH_EDGES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1 << 20)
}

/// One group: the copy reference, Blinn's batch, and the per-edge loop of every clipper in
/// `clippers`, on the same edges.
fn homogeneous_group(c: &mut Criterion, name: &str, edges: &[(Vec4, Vec4)], clippers: &[Clipper]) {
    let volume = ClipVolume::new(DEPTH);
    let soa = EdgesSoa::from_pairs(edges);
    let cpu = cpu_time();
    let mut g = c.benchmark_group(name);
    configure(&mut g, edges.len());
    // The bandwidth reference: the same 32 B per edge read and written.
    let mut copy = EdgesSoa::from_pairs(edges);
    g.bench_function("copy", |b| {
        timed(b, cpu, || {
            for k in 0..4 {
                copy.a[k].copy_from_slice(&soa.a[k]);
                copy.c[k].copy_from_slice(&soa.c[k]);
            }
            black_box(&copy);
        })
    });
    // The same copy shaped like the batch's output: 64 edges at a time from the eight arrays
    // into nine (the eight and the edge indices), appended to reserved vectors: 8 streams in
    // and 9 out, 32 B read and 36 B written per edge, as the batch does when it draws every
    // edge (and does when a block is all inside).
    let mut out_copy = SegmentsSoa::default();
    g.bench_function("copy-blocks", |b| {
        timed(b, cpu, || {
            out_copy.clear();
            out_copy.reserve(soa.len());
            let n = soa.len();
            for start in (0..n).step_by(64) {
                let end = n.min(start + 64);
                for k in 0..4 {
                    out_copy.a[k].extend_from_slice(&soa.a[k][start..end]);
                    out_copy.c[k].extend_from_slice(&soa.c[k][start..end]);
                }
                out_copy.edge.extend(start as u32..end as u32);
            }
            black_box(&out_copy);
        })
    });
    let mut out_soa = SegmentsSoa::default();
    g.bench_function("blinn-batch", |b| {
        timed(b, cpu, || {
            out_soa.clear();
            clip_soa(black_box(&soa), DEPTH, &mut out_soa)
        })
    });
    let mut out = Vec::with_capacity(edges.len());
    for &clipper in clippers {
        g.bench_function(clipper.name(), |b| {
            timed(b, cpu, || {
                per_edge(edges, &mut out, |a, c| clipper.clip_in(a, c, &volume))
            })
        });
    }
    g.finish();
}

/// Edges per set of the cache-resident groups: 256 KiB of input and at most 288 KiB of
/// output, inside this machine's 1 MiB L2, so that the clippers' own cost shows instead of
/// DRAM's.
const CACHED_EDGES: usize = 8192;

fn homogeneous(c: &mut Criterion) {
    let n = edges_count();
    for kind in [
        "inside",
        "outside",
        "crossing",
        "behind",
        "mixed",
        "flythrough",
    ] {
        let edges = if kind == "flythrough" {
            flythrough(n)
        } else {
            set(kind, n)
        };
        let mut tally = ClipStats::default();
        for &(a, b) in &edges {
            tally.record(&wireflight::geometry::clip::clip_edge(a, b, DEPTH));
        }
        eprintln!("{kind}: {tally}");
        homogeneous_group(c, &format!("clip/{kind}"), &edges, &Clipper::ALL);
        // The same kind of edges, few enough to stay in cache: Blinn's batch against the
        // per-edge Blinn where memory is not the limit.
        let small: Vec<_> = edges.iter().copied().take(CACHED_EDGES).collect();
        homogeneous_group(c, &format!("clip-cached/{kind}"), &small, &[Clipper::Blinn]);
    }
}

fn planar_set(kind: &str, n: usize) -> Vec<(Vec2, Vec2)> {
    let mut rng = Rng(0x2D2D_2D2D_1234_5678);
    let inside = |rng: &mut Rng| Vec2::new(rng.range(30.0, 220.0), rng.range(50.0, 240.0));
    (0..n)
        .map(|i| match kind {
            "inside" => (inside(&mut rng), inside(&mut rng)),
            "outside" => (
                Vec2::new(rng.range(230.0, 900.0), rng.range(-500.0, 800.0)),
                Vec2::new(rng.range(230.0, 900.0), rng.range(-500.0, 800.0)),
            ),
            _ if i % 2 == 0 => (inside(&mut rng), inside(&mut rng)),
            _ => (
                inside(&mut rng),
                Vec2::new(rng.range(-400.0, 700.0), rng.range(260.0, 900.0)),
            ),
        })
        .collect()
}

fn planar(c: &mut Criterion) {
    let n = edges_count();
    let w = Window2::from_lrbt(30.0, 220.0, 50.0, 240.0).unwrap();
    let corners = w.corners();
    let polygon = cyrus_beck::ConvexPolygon::new(&corners).unwrap();
    for kind in ["inside", "outside", "crossing"] {
        let edges = planar_set(kind, n);
        let mut g = c.benchmark_group(format!("clip2d/{kind}"));
        configure(&mut g, edges.len());
        let src: Vec<f32> = edges
            .iter()
            .flat_map(|(a, b)| [a.x, a.y, b.x, b.y])
            .collect();
        let mut dst = src.clone();
        g.bench_function("copy", |b| {
            b.iter(|| {
                dst.copy_from_slice(&src);
                black_box(&dst);
            })
        });
        let mut out = Vec::with_capacity(edges.len());
        type Planar<'a> = &'a dyn Fn(Vec2, Vec2) -> ClipOutcome<Vec2>;
        let algos: [(&str, Planar<'_>); 5] = [
            ("cohen-sutherland", &|a, b| {
                cohen_sutherland::clip_2d(a, b, &w)
            }),
            ("liang-barsky", &|a, b| liang_barsky::clip_2d(a, b, &w)),
            ("cyrus-beck", &|a, b| {
                cyrus_beck::clip_polygon(a, b, &polygon)
            }),
            ("nicholl-lee-nicholl", &|a, b| {
                nicholl_lee_nicholl::clip_2d(a, b, &w)
            }),
            ("sutherland-hodgman", &|a, b| {
                sutherland_hodgman::clip_edge_2d(a, b, &w)
            }),
        ];
        for (name, f) in algos {
            g.bench_function(name, |b| b.iter(|| per_edge(&edges, &mut out, f)));
        }
        g.finish();
    }
}

/// A mesh of about 1 M edges: the world's grid, hills and structures tiled.
fn million_edge_mesh() -> EdgeMesh {
    let world = World::new(&WorldSpec::default());
    let mut b = EdgeMeshBuilder::new();
    let mut k = 0;
    while b.edge_count() < 1_000_000 {
        let off = Vec3::new(
            10_000.0 * (k % 7) as f32 - 30_000.0,
            10_000.0 * (k / 7) as f32 - 30_000.0,
            0.0,
        );
        for mesh in [&world.grid, &world.hills, &world.structures] {
            for &[i, j] in mesh.edges() {
                let (p, q) = (mesh.positions()[i as usize], mesh.positions()[j as usize]);
                b.edge_between(p + off, q + off).expect("finite");
            }
        }
        k += 1;
    }
    b.build().expect("edges")
}

fn scene(c: &mut Criterion) {
    let mesh = million_edge_mesh();
    let viewport = Viewport {
        width: 1280,
        height: 720,
    };
    let camera = Camera {
        eye: Vec3::new(-2000.0, -1500.0, 400.0),
        target: Vec3::new(3000.0, 2000.0, 0.0),
        up: Vec3::Z,
        projection: Projection::Perspective {
            fov_y: 60f32.to_radians(),
            near: 1.0,
            far: 60_000.0,
        },
    };
    let m = camera.clip_from_world(viewport.aspect(), DEPTH);
    let mut out = Vec::with_capacity(mesh.edges().len());
    let mut projector = EdgeProjector::new(Clipper::Blinn, DEPTH);
    out.clear();
    eprintln!(
        "scene_1m: {} edges, {} vertices: {}",
        mesh.edges().len(),
        mesh.positions().len(),
        projector.project(&mesh, m, viewport, &mut out)
    );
    let mut g = c.benchmark_group("scene_1m");
    configure(&mut g, mesh.edges().len());
    g.bench_function(
        format!(
            "transform+clip+project, blinn, {} threads",
            rayon::current_num_threads()
        ),
        |b| {
            b.iter(|| {
                out.clear();
                projector.project(&mesh, m, viewport, &mut out)
            })
        },
    );
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    g.bench_function("transform+clip+project, blinn, 1 thread", |b| {
        b.iter(|| {
            one.install(|| {
                out.clear();
                projector.project(&mesh, m, viewport, &mut out)
            })
        })
    });
    let mut slow = EdgeProjector::new(Clipper::CohenSutherland, DEPTH);
    g.bench_function("transform+clip+project, cohen-sutherland (per edge)", |b| {
        b.iter(|| {
            out.clear();
            slow.project(&mesh, m, viewport, &mut out)
        })
    });
    g.finish();
}

// Short defaults (about 100 benchmarks); the command line overrides them, e.g.
// `cargo bench --bench clip -- --warm-up-time 1 --measurement-time 3` (settings made on a
// group would not be overridable).
criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = homogeneous, planar, scene
}
criterion_main!(benches);
