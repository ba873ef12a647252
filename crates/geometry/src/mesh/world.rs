//! The world of the fly-through window, as wire meshes in world coordinates (viewer frame:
//! X north, Y west, Z up, metres, ground at z = 0): a ground grid reaching several kilometres,
//! a runway outline with its markings, landmarks (lattice radio masts, a control tower,
//! hangars, hills) and a unit horizon ring that the viewer places around the eye.
//!
//! Pure data building: no I/O. Every mesh goes through [`EdgeMeshBuilder`], so shared edges
//! are drawn once. The builder's `expect("finite")`s below cannot fail: every point is made
//! from constants of this file (and the finite, positive sizes of [`WorldSpec`]).

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::{EdgeMesh, EdgeMeshBuilder, MeshProblem};

/// Size of the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldSpec {
    /// The grid covers `−half_extent..half_extent` in x and y, metres.
    pub half_extent_m: f32,
    /// Grid spacing, metres.
    pub spacing_m: f32,
    /// Runway length (along X, centred on the origin), metres.
    pub runway_length_m: f32,
    /// Runway width, metres.
    pub runway_width_m: f32,
}

impl Default for WorldSpec {
    /// A 10 km × 10 km grid of 100 m cells (20 200 edges) and a 1200 m × 30 m runway.
    fn default() -> Self {
        Self {
            half_extent_m: 5000.0,
            spacing_m: 100.0,
            runway_length_m: 1200.0,
            runway_width_m: 30.0,
        }
    }
}

/// The world's meshes, one per colour.
#[derive(Clone, Debug)]
pub struct World {
    /// Ground grid at z = 0.
    pub grid: EdgeMesh,
    /// Runway outline, threshold bars, centreline dashes, touchdown marks.
    pub runway: EdgeMesh,
    /// Masts, control tower and hangars.
    pub structures: EdgeMesh,
    /// Hills: rings of equal height and spokes down their slopes.
    pub hills: EdgeMesh,
    /// Unit circle in the z = 0 plane (radius 1, centred on the origin). The viewer scales it
    /// to just inside the far plane and centres it on the eye at eye height, where the horizon
    /// of a flat earth appears.
    pub horizon: EdgeMesh,
}

impl World {
    /// Build the world.
    ///
    /// # Panics
    /// Never for a spec with finite, positive sizes (the builders only see finite points);
    /// non-finite or non-positive sizes are replaced by the defaults.
    pub fn new(spec: &WorldSpec) -> Self {
        let d = WorldSpec::default();
        let pick = |v: f32, def: f32| if v.is_finite() && v > 0.0 { v } else { def };
        let half = pick(spec.half_extent_m, d.half_extent_m);
        let spacing = pick(spec.spacing_m, d.spacing_m).min(half);
        Self {
            grid: ground_grid(half, spacing),
            runway: runway(
                pick(spec.runway_length_m, d.runway_length_m),
                pick(spec.runway_width_m, d.runway_width_m),
            ),
            structures: structures(),
            hills: hills(),
            horizon: horizon_ring(256),
        }
    }

    /// Edges of all meshes together.
    pub fn edge_count(&self) -> usize {
        [
            &self.grid,
            &self.runway,
            &self.structures,
            &self.hills,
            &self.horizon,
        ]
        .iter()
        .map(|m| m.edges().len())
        .sum()
    }
}

/// A square grid at z = 0 from `−half` to `half` in x and y with cells of about `spacing`
/// (a whole number of them).
pub fn ground_grid(half: f32, spacing: f32) -> EdgeMesh {
    let n = (2.0 * half / spacing).round().max(1.0) as u32;
    let step = 2.0 * half / n as f32;
    // `World::new` passes sizes it replaced by defaults unless finite and positive; the cell
    // count is at least 1, so the grid has edges.
    grid_cells(Vec2::splat(-half), step, n, n).expect("a finite, positive grid has edges")
}

/// The ground grid under a flight: covering the rectangle `min..max` (x, y) plus a margin of a
/// quarter of its larger side (at least 50 m), with about `cells` cells along that side.
///
/// # Errors
/// Bounds that are not finite, or so large that a cell would not be distinguishable from its
/// neighbours in `f32` (the grid would be degenerate).
pub fn grid_around(min: Vec2, max: Vec2, cells: u32) -> Result<EdgeMesh, MeshProblem> {
    let margin = 0.25 * (max - min).max_element().max(200.0);
    let (lo, hi) = (min - margin, max + margin);
    let step = ((hi - lo).max_element() / cells.max(1) as f32).max(1.0);
    let nx = ((hi.x - lo.x) / step).ceil();
    let ny = ((hi.y - lo.y) / step).ceil();
    if !(nx.is_finite() && ny.is_finite() && lo.is_finite()) {
        return Err(MeshProblem::NonFinite(lo.extend(0.0)));
    }
    grid_cells(lo, step, nx as u32, ny as u32)
}

/// `nx` × `ny` square cells of side `step` at z = 0, from corner `lo`. Every cell side is its
/// own edge, so the clipper sees each short piece (and clips those crossing the near, far and
/// side planes).
fn grid_cells(lo: Vec2, step: f32, nx: u32, ny: u32) -> Result<EdgeMesh, MeshProblem> {
    let p = |i: u32, j: u32| Vec3::new(lo.x + i as f32 * step, lo.y + j as f32 * step, 0.0);
    let mut b = EdgeMeshBuilder::new();
    for i in 0..=nx {
        for j in 0..=ny {
            if i < nx {
                b.edge_between(p(i, j), p(i + 1, j))?;
            }
            if j < ny {
                b.edge_between(p(i, j), p(i, j + 1))?;
            }
        }
    }
    b.build()
}

/// A runway along X centred on the origin, at z = 0: outline, threshold bars at both ends,
/// centreline dashes (30 m with 20 m gaps) and touchdown-zone marks.
pub fn runway(length: f32, width: f32) -> EdgeMesh {
    let (hl, hw) = (0.5 * length, 0.5 * width);
    let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
    let mut b = EdgeMeshBuilder::new();
    b.polygon(&[p(-hl, -hw), p(hl, -hw), p(hl, hw), p(-hl, hw)])
        .expect("finite");
    for end in [-1.0f32, 1.0] {
        // Threshold: eight bars along the runway, 30 m long, starting 6 m in from the end.
        let x0 = end * (hl - 6.0);
        let x1 = end * (hl - 36.0);
        for k in 0..8 {
            let y = -hw + width * (k as f32 + 0.5) / 8.0;
            b.edge_between(p(x0, y), p(x1, y)).expect("finite");
        }
        // Touchdown marks: pairs of short bars either side of the centreline.
        for k in 0..3 {
            let x = end * (hl - 150.0 - 150.0 * k as f32);
            for side in [-1.0f32, 1.0] {
                let y = side * 0.3 * width;
                b.polygon(&[
                    p(x, y),
                    p(x - end * 22.0, y),
                    p(x - end * 22.0, y + side * 3.0),
                    p(x, y + side * 3.0),
                ])
                .expect("finite");
            }
        }
    }
    // Centreline dashes between the thresholds.
    let mut x = -hl + 60.0;
    while x + 30.0 <= hl - 60.0 {
        b.edge_between(p(x, 0.0), p(x + 30.0, 0.0)).expect("finite");
        x += 50.0;
    }
    b.build().expect("the runway has edges")
}

/// A square lattice mast: four legs from a `base_half`-wide square at the ground tapering to a
/// quarter of it at the top, a horizontal square every `height / levels`, and one diagonal
/// brace per face per level. A cross of guy-wire-like stays at the top makes it read as a mast.
pub fn lattice_mast(b: &mut EdgeMeshBuilder, base: Vec3, height: f32, base_half: f32, levels: u32) {
    let levels = levels.max(1);
    let corner = |level: u32, k: usize| {
        let f = level as f32 / levels as f32;
        let half = base_half * (1.0 - 0.75 * f);
        let (sx, sy) = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)][k];
        base + Vec3::new(sx * half, sy * half, f * height)
    };
    for level in 0..=levels {
        let ring: Vec<Vec3> = (0..4).map(|k| corner(level, k)).collect();
        b.polygon(&ring).expect("finite");
        if level < levels {
            for k in 0..4 {
                b.edge_between(corner(level, k), corner(level + 1, k))
                    .expect("finite");
                // Zig-zag bracing: alternate diagonals level by level.
                let (a, c) = if level % 2 == 0 {
                    (corner(level, k), corner(level + 1, (k + 1) % 4))
                } else {
                    (corner(level, (k + 1) % 4), corner(level + 1, k))
                };
                b.edge_between(a, c).expect("finite");
            }
        }
    }
    // Antenna spike.
    let top = base + Vec3::Z * height;
    b.edge_between(top, top + Vec3::Z * 0.15 * height)
        .expect("finite");
}

/// An axis-aligned box outline with its lower face at `base.z`.
pub fn box_outline(b: &mut EdgeMeshBuilder, base: Vec3, half: Vec3) {
    let lo = base - Vec3::new(half.x, half.y, 0.0);
    let hi = base + Vec3::new(half.x, half.y, 2.0 * half.z);
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    for z in [false, true] {
        b.polygon(&[
            c(false, false, z),
            c(true, false, z),
            c(true, true, z),
            c(false, true, z),
        ])
        .expect("finite");
    }
    for (x, y) in [(false, false), (true, false), (true, true), (false, true)] {
        b.edge_between(c(x, y, false), c(x, y, true))
            .expect("finite");
    }
}

/// A control tower: a square shaft with an octagonal glass cab on top, its windows' mullions
/// and a roof cone.
fn control_tower(b: &mut EdgeMeshBuilder, base: Vec3) {
    let shaft_h = 28.0;
    box_outline(b, base, Vec3::new(3.0, 3.0, 0.5 * shaft_h));
    let octagon = |r: f32, z: f32| -> Vec<Vec3> {
        (0..8)
            .map(|k| {
                let a = TAU * (k as f32 + 0.5) / 8.0;
                base + Vec3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    let floor = octagon(6.0, shaft_h);
    let glass_top = octagon(7.0, shaft_h + 5.0);
    b.polygon(&floor).expect("finite");
    b.polygon(&glass_top).expect("finite");
    for k in 0..8 {
        b.edge_between(floor[k], glass_top[k]).expect("finite");
    }
    let apex = base + Vec3::Z * (shaft_h + 8.0);
    for p in &glass_top {
        b.edge_between(*p, apex).expect("finite");
    }
}

/// Structures: three lattice masts of different heights, the control tower beside the runway
/// and a row of hangars.
pub fn structures() -> EdgeMesh {
    let mut b = EdgeMeshBuilder::new();
    lattice_mast(&mut b, Vec3::new(1500.0, 800.0, 0.0), 180.0, 8.0, 12);
    lattice_mast(&mut b, Vec3::new(-2200.0, -1200.0, 0.0), 120.0, 6.0, 8);
    lattice_mast(&mut b, Vec3::new(3000.0, -2500.0, 0.0), 250.0, 10.0, 16);
    lattice_mast(&mut b, Vec3::new(-900.0, 1400.0, 0.0), 90.0, 5.0, 6);
    control_tower(&mut b, Vec3::new(100.0, -120.0, 0.0));
    for k in 0..4 {
        let x = -300.0 + 70.0 * k as f32;
        box_outline(
            &mut b,
            Vec3::new(x, -110.0, 0.0),
            Vec3::new(25.0, 18.0, 6.0),
        );
    }
    b.build().expect("structures have edges")
}

/// A smooth hill (raised cosine profile) centred at `centre` (on the ground), with `rings`
/// contour rings and `spokes` lines running down from the top.
pub fn hill(
    b: &mut EdgeMeshBuilder,
    centre: Vec3,
    radius: f32,
    height: f32,
    rings: u32,
    spokes: u32,
) {
    let rings = rings.max(1);
    let spokes = spokes.max(3);
    let point = |ring: u32, spoke: u32| {
        let r = radius * ring as f32 / rings as f32;
        let a = TAU * spoke as f32 / spokes as f32;
        let z = height * 0.5 * (1.0 + (PI * r / radius).cos());
        centre + Vec3::new(r * a.cos(), r * a.sin(), z)
    };
    for ring in 1..=rings {
        let loop_points: Vec<Vec3> = (0..spokes).map(|s| point(ring, s)).collect();
        b.polygon(&loop_points).expect("finite");
    }
    for s in 0..spokes {
        let line: Vec<Vec3> = (0..=rings).map(|ring| point(ring, s)).collect();
        b.polyline(&line).expect("finite");
    }
}

/// Three hills around the airfield.
pub fn hills() -> EdgeMesh {
    let mut b = EdgeMeshBuilder::new();
    hill(&mut b, Vec3::new(2500.0, 2500.0, 0.0), 900.0, 300.0, 8, 24);
    hill(
        &mut b,
        Vec3::new(-3000.0, 2000.0, 0.0),
        1200.0,
        450.0,
        10,
        32,
    );
    hill(&mut b, Vec3::new(800.0, -3500.0, 0.0), 700.0, 220.0, 7, 20);
    b.build().expect("hills have edges")
}

/// A unit circle in the z = 0 plane with `segments` edges (at least 3).
pub fn horizon_ring(segments: u32) -> EdgeMesh {
    let n = segments.max(3);
    let points: Vec<Vec3> = (0..n)
        .map(|k| {
            let a = TAU * k as f32 / n as f32;
            Vec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    let mut b = EdgeMeshBuilder::new();
    b.polygon(&points).expect("finite");
    b.build().expect("the ring has edges")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_covers_the_extent_with_one_edge_per_cell_side() {
        let g = ground_grid(5000.0, 100.0);
        // 101 lines each way, 100 pieces per line.
        assert_eq!(g.edges().len(), 2 * 101 * 100);
        let (min, max) = g.bounds();
        assert_eq!(
            (min.x, min.y, max.x, max.y),
            (-5000.0, -5000.0, 5000.0, 5000.0)
        );
        assert_eq!((min.z, max.z), (0.0, 0.0));
    }

    #[test]
    fn world_has_landmarks_on_or_above_the_ground() {
        let w = World::new(&WorldSpec::default());
        assert!(w.edge_count() > 20_000, "{}", w.edge_count());
        for m in [&w.runway, &w.structures, &w.hills, &w.horizon] {
            let (min, _) = m.bounds();
            assert!(min.z >= 0.0, "{min}");
        }
        let (_, max) = w.structures.bounds();
        assert!(max.z > 250.0, "the tallest mast with its spike: {max}");
        let (min, max) = w.runway.bounds();
        assert_eq!((min.x, max.x, min.y, max.y), (-600.0, 600.0, -15.0, 15.0));
        assert_eq!(w.horizon.edges().len(), 256);
        assert!(w
            .horizon
            .positions()
            .iter()
            .all(|p| (p.length() - 1.0).abs() < 1e-6));
    }

    #[test]
    fn bad_sizes_fall_back_to_the_defaults() {
        let w = World::new(&WorldSpec {
            half_extent_m: f32::NAN,
            spacing_m: -1.0,
            runway_length_m: 0.0,
            runway_width_m: f32::INFINITY,
        });
        assert_eq!(w.grid.edges().len(), 2 * 101 * 100);
    }
}
