//! Blinn's batch paths give exactly the per-edge clipper's segments and counts: the SoA
//! batch and the coded per-vertex path on random and adversarial edges (NaN and ∞ included),
//! and the projector's fast path (sequential and on rayon's threads) against
//! [`EdgeProjector::clip_indexed`], edge by edge.

use super::check::check_batch;
use crate::support::Rng;
use glam::{Mat4, Vec3, Vec4};
use wireflight::geometry::camera::{Camera, Projection};
use wireflight::geometry::clip::{ClipStats, Clipper, DepthRange};
use wireflight::geometry::mesh::world::{World, WorldSpec};
use wireflight::geometry::mesh::EdgeMesh;
use wireflight::geometry::pipeline::{EdgeProjector, Viewport, PARALLEL_MIN_EDGES};

fn random_edges(rng: &mut Rng, n: usize) -> Vec<(Vec4, Vec4)> {
    let specials = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e-40,
        3e38,
    ];
    (0..n)
        .map(|_| {
            let same = rng.chance(0.05);
            let mut p = || {
                Vec4::from_array(std::array::from_fn(|_| {
                    if rng.chance(0.03) {
                        specials[rng.below(specials.len())]
                    } else {
                        rng.range_f32(-2.0, 2.0)
                    }
                }))
            };
            let a = p();
            let c = if same { a } else { p() };
            (a, c)
        })
        .collect()
}

#[test]
fn soa_batch_and_coded_path_match_the_per_edge_clipper_exactly() {
    let mut rng = Rng::new(0xBA7C);
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        // Lengths around the block size, then a big batch.
        for n in [0usize, 1, 7, 8, 9, 63, 64, 65, 127, 128, 129, 100_003] {
            let edges = random_edges(&mut rng, n);
            check_batch(&edges, depth).unwrap_or_else(|e| panic!("{depth:?} n = {n}: {e}"));
        }
        // Blocks that are mostly inside with one edge of every other kind here and there:
        // the compaction path, where an accepted edge's slot is kept and a dropped one's
        // reused (a wrong slot count shows as shifted or stale segments).
        for every in [2usize, 9, 64, 200] {
            let odd = random_edges(&mut rng, 5000);
            let edges: Vec<_> = (0..5000)
                .map(|i| {
                    if i % every == 0 {
                        odd[i]
                    } else {
                        let t = (i % 97) as f32 / 97.0;
                        (
                            Vec4::new(t - 0.5, 0.2, 0.5, 1.0),
                            Vec4::new(0.1, 0.5 - t, 0.25, 1.0),
                        )
                    }
                })
                .collect();
            check_batch(&edges, depth).unwrap_or_else(|e| panic!("{depth:?} 1 in {every}: {e}"));
        }
        // Small-integer ends: edges through the volume's corners and along its faces, where
        // two planes give equal or nearly equal parameters and ends land exactly on planes
        // (the masked max/min of the lanes must pick what the per-edge loop picks).
        let grid = |rng: &mut Rng| {
            let mut v = || [-3.0f32, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 3.0][rng.below(9)];
            Vec4::new(v(), v(), v(), [0.5f32, 1.0, 2.0][rng.below(3)])
        };
        let ties: Vec<_> = (0..20_000)
            .map(|_| (grid(&mut rng), grid(&mut rng)))
            .collect();
        check_batch(&ties, depth).unwrap_or_else(|e| panic!("{depth:?} grid: {e}"));
        let near: Vec<_> = ties
            .iter()
            .map(|&(a, c)| {
                (
                    a,
                    c * (1.0 + f32::EPSILON * rng.range_f32(-4.0, 4.0).round()),
                )
            })
            .collect();
        check_batch(&near, depth).unwrap_or_else(|e| panic!("{depth:?} near-grid: {e}"));
        // All inside (the copy-out path) and all outside.
        let inside: Vec<_> = (0..1000)
            .map(|i| {
                let t = i as f32 / 1000.0;
                (
                    Vec4::new(t - 0.5, 0.2, 0.5, 1.0),
                    Vec4::new(0.1, -t + 0.5, 0.25, 1.0),
                )
            })
            .collect();
        check_batch(&inside, depth).unwrap();
        let outside: Vec<_> = inside
            .iter()
            .map(|&(a, c)| (a + Vec4::X * 3.0, c + Vec4::X * 3.0))
            .collect();
        check_batch(&outside, depth).unwrap();
    }
}

/// Steps with few crossing edges that cross many planes each (an edge from inside to behind
/// the eye leaves through four to six): where the lanes pack their (lane, plane) pairs side by
/// side before dividing. Inside edges, edges out through one to three planes and edges
/// through the eye plane, in random order and proportions, against the per-edge clipper.
#[test]
fn soa_batch_matches_the_per_edge_clipper_on_edges_through_the_eye_plane() {
    let mut rng = Rng::new(0xE7E);
    let inside = |rng: &mut Rng| {
        let w = rng.range_f32(0.5, 50.0);
        Vec4::new(
            rng.range_f32(-w, w),
            rng.range_f32(-w, w),
            rng.range_f32(0.0, w),
            w,
        )
    };
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        for behind_share in [0.02, 0.1, 0.3] {
            let edges: Vec<_> = (0..20_000)
                .map(|_| {
                    let a = inside(&mut rng);
                    let mut c = inside(&mut rng);
                    if rng.chance(behind_share) {
                        // Behind the eye: w < 0.
                        c = Vec4::new(
                            rng.range_f32(-20.0, 20.0),
                            rng.range_f32(-20.0, 20.0),
                            rng.range_f32(-20.0, 20.0),
                            -rng.range_f32(0.0, 20.0),
                        );
                    } else if rng.chance(0.3) {
                        // Out through x = w, sometimes y = −w and z = w too.
                        let k = rng.range_f32(1.0, 3.0);
                        c.x = c.w * k;
                        if rng.chance(0.5) {
                            c.y = -c.w * k;
                        }
                        if rng.chance(0.3) {
                            c.z = c.w * k;
                        }
                    }
                    if rng.chance(0.3) {
                        (c, a)
                    } else {
                        (a, c)
                    }
                })
                .collect();
            check_batch(&edges, depth)
                .unwrap_or_else(|e| panic!("{depth:?} behind {behind_share}: {e}"));
        }
    }
}

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(-50.0, 20.0, 30.0),
        target: Vec3::new(200.0, 0.0, 0.0),
        up: Vec3::Z,
        projection: Projection::Perspective {
            fov_y: 60f32.to_radians(),
            near: 0.5,
            far: 3000.0,
        },
    }
}

/// The projector's fast path equals clipping edge by edge, on the world's grid (big enough
/// to run on rayon's threads) and the structures, for every clipper.
#[test]
fn projector_fast_path_matches_edge_by_edge() {
    let world = World::new(&WorldSpec::default());
    let viewport = Viewport {
        width: 1280,
        height: 720,
    };
    let meshes: [&EdgeMesh; 3] = [&world.grid, &world.structures, &world.hills];
    assert!(world.grid.edges().len() < PARALLEL_MIN_EDGES);
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        let m: Mat4 = camera().clip_from_world(viewport.aspect(), depth);
        for clipper in Clipper::ALL {
            let mut projector = EdgeProjector::new(clipper, depth);
            for mesh in meshes {
                let mut fast = Vec::new();
                let stats = projector.project(mesh, m, viewport, &mut fast);
                let clip: Vec<Vec4> = mesh.positions().iter().map(|p| m * p.extend(1.0)).collect();
                let mut slow = Vec::new();
                let expected = projector.clip_indexed(&clip, mesh.edges(), viewport, &mut slow);
                assert_eq!(stats, expected, "{clipper} {depth:?}");
                assert_eq!(fast, slow, "{clipper} {depth:?}");
                if clipper == Clipper::Blinn && std::ptr::eq(mesh, &world.grid) {
                    assert!(stats.clipped > 0 && stats.trivially_rejected > 0, "{stats}");
                }
            }
        }
    }
}

/// A mesh large enough for the parallel path: the grid repeated with offsets, 1 M edges.
pub(super) fn big_mesh(copies: usize) -> EdgeMesh {
    let world = World::new(&WorldSpec::default());
    let mut b = wireflight::geometry::mesh::EdgeMeshBuilder::new();
    let grid = &world.grid;
    for k in 0..copies {
        let off = Vec3::new(0.0, 0.0, 3.0 * k as f32);
        for &[i, j] in grid.edges() {
            b.edge_between(
                grid.positions()[i as usize] + off,
                grid.positions()[j as usize] + off,
            )
            .unwrap();
        }
    }
    b.build().unwrap()
}

#[test]
fn parallel_fast_path_matches_sequential_in_order() {
    let mesh = big_mesh(3);
    assert!(
        mesh.edges().len() >= PARALLEL_MIN_EDGES,
        "{}",
        mesh.edges().len()
    );
    let viewport = Viewport {
        width: 800,
        height: 600,
    };
    let depth = DepthRange::ZeroToOne;
    let m = camera().clip_from_world(viewport.aspect(), depth);
    let mut projector = EdgeProjector::new(Clipper::Blinn, depth);
    let mut fast = Vec::new();
    let stats = projector.project(&mesh, m, viewport, &mut fast);
    let clip: Vec<Vec4> = mesh.positions().iter().map(|p| m * p.extend(1.0)).collect();
    let mut slow = Vec::new();
    let expected: ClipStats = projector.clip_indexed(&clip, mesh.edges(), viewport, &mut slow);
    assert_eq!(stats, expected);
    assert_eq!(fast, slow);
    // Again, with the buffers reused.
    let mut again = Vec::new();
    assert_eq!(projector.project(&mesh, m, viewport, &mut again), expected);
    assert_eq!(again, slow);
}
