//! Whole frames at 1280×720: build (transform + clip + project) and draw, per backend.
//!
//! The scene is the built-in plane plus a ground grid of a few thousand edges around it, so
//! that every clipper path (accept, reject, clip, behind the eye) runs every frame.
//!
//! The GPU cases (wgpu, any adapter, Mesa lavapipe included) time what a caller gets: vertex
//! upload, the draw, and the readback into an `Image`, with the renderer created once outside
//! the loop. Without an adapter they are skipped with a message.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;

use wireflight::draw::render::gpu::GpuRenderer;
use wireflight::draw::render::{cpu, LineBatch, LineScene};
use wireflight::draw::scene::palette;
use wireflight::draw::scene::{frame, ViewSpec};
use wireflight::geometry::camera::{CameraPreset, Subject};
use wireflight::geometry::euler::EulerZyx;
use wireflight::geometry::mesh::{plane::builtin_plane, EdgeMesh, EdgeMeshBuilder};
use wireflight::geometry::pipeline::{model_matrix, EdgeProjector, Viewport};

const VIEWPORT: Viewport = Viewport {
    width: 1280,
    height: 720,
};

/// A square ground grid, `n` lines each way, `spacing` metres apart, `below` under the origin.
fn ground_grid(n: i32, spacing: f32, below: f32) -> EdgeMesh {
    let mut b = EdgeMeshBuilder::new();
    let half = n as f32 * spacing / 2.0;
    for i in 0..=n {
        let t = -half + i as f32 * spacing;
        // Split each line into segments so the grid has many edges, like a real terrain mesh.
        for k in 0..n {
            let s0 = -half + k as f32 * spacing;
            let s1 = s0 + spacing;
            b.edge_between(Vec3::new(t, s0, -below), Vec3::new(t, s1, -below))
                .unwrap();
            b.edge_between(Vec3::new(s0, t, -below), Vec3::new(s1, t, -below))
                .unwrap();
        }
    }
    b.build().unwrap()
}

/// One 1280×720 frame: the plane banked over a 60×60-cell grid, chase camera.
fn build_scene(projector: &mut EdgeProjector, plane: &EdgeMesh, grid: &EdgeMesh) -> LineScene {
    let attitude = EulerZyx::from_degrees(25.0, -10.0, 30.0);
    let (centre, radius) = plane.bounding_sphere();
    let subject = Subject {
        position: Vec3::ZERO,
        attitude,
        centre,
        radius,
    };
    let camera = CameraPreset::Chase.camera(&subject, 50f32.to_radians());
    let clip_from_world = camera.clip_from_world(VIEWPORT.aspect(), projector.depth());
    let mut grid_segments = Vec::with_capacity(grid.edges().len());
    projector.project(grid, clip_from_world, VIEWPORT, &mut grid_segments);
    let mut plane_segments = Vec::with_capacity(plane.edges().len());
    projector.project(
        plane,
        clip_from_world * model_matrix(Vec3::ZERO, attitude),
        VIEWPORT,
        &mut plane_segments,
    );
    LineScene {
        width: VIEWPORT.width,
        height: VIEWPORT.height,
        background: palette::BACKGROUND,
        batches: vec![
            LineBatch {
                color: palette::GRID,
                segments: grid_segments,
            },
            LineBatch {
                color: palette::AIRCRAFT,
                segments: plane_segments,
            },
        ],
    }
}

fn frames(c: &mut Criterion) {
    let plane = builtin_plane();
    let grid = ground_grid(60, 4.0, 6.0);
    let mut projector = EdgeProjector::default();
    let scene = build_scene(&mut projector, &plane, &grid);

    let mut group = c.benchmark_group("frame_1280x720");
    group.sample_size(20);
    group.measurement_time(std::time::Duration::from_secs(3));
    group.throughput(Throughput::Elements(1));
    group.bench_function("geometry (transform+clip+project)", |b| {
        b.iter(|| build_scene(&mut projector, &plane, &grid))
    });
    group.bench_function("cpu draw (Bresenham)", |b| b.iter(|| cpu::render(&scene)));
    group.bench_function("single plane frame, cpu end to end", |b| {
        let spec = ViewSpec {
            viewport: VIEWPORT,
            ..ViewSpec::default()
        };
        b.iter(|| cpu::render(&frame(&plane, &spec).0))
    });
    match GpuRenderer::new() {
        Ok(mut gpu) => {
            eprintln!("GPU: {}", gpu.adapter());
            group.bench_function("gpu draw+readback (wgpu)", |b| {
                b.iter(|| gpu.render(&scene).expect("GPU frame"))
            });
            group.bench_function("single plane frame, gpu end to end", |b| {
                let spec = ViewSpec {
                    viewport: VIEWPORT,
                    ..ViewSpec::default()
                };
                b.iter(|| gpu.render(&frame(&plane, &spec).0).expect("GPU frame"))
            });
        }
        Err(e) => eprintln!("skipping the GPU benchmarks: {e}"),
    }
    group.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
