//! The built-in aircraft: a light high-performance single, about 9 m long with an 11 m span,
//! in body axes nose **+X**, left wing **+Y**, rudder **+Z** (metres, origin near the centre of
//! gravity). Also shipped as `assets/plane.obj` and `assets/plane.gltf`. The builder's
//! `expect`s below cannot fail: every point is a constant of this file.

use glam::Vec3;

use super::{EdgeMesh, EdgeMeshBuilder};

/// Fuselage stations: (x, half-width, half-height, centre z). The cross-section at each is a
/// hexagon; the nose and the tail close to a point.
const STATIONS: [(f32, f32, f32, f32); 5] = [
    (3.4, 0.35, 0.35, 0.0),
    (2.2, 0.55, 0.55, 0.05),
    (0.2, 0.60, 0.60, 0.05),
    (-2.6, 0.40, 0.42, 0.12),
    (-4.6, 0.16, 0.20, 0.30),
];
const NOSE_TIP: Vec3 = Vec3::new(4.3, 0.0, -0.05);
const TAIL_TIP: Vec3 = Vec3::new(-5.1, 0.0, 0.35);
const HEX: usize = 6;

fn ring(x: f32, half_w: f32, half_h: f32, zc: f32) -> [Vec3; HEX] {
    std::array::from_fn(|i| {
        // Start at the top so the top longeron (and the fin root) sits on a vertex.
        let a = std::f32::consts::TAU * i as f32 / HEX as f32;
        Vec3::new(x, half_w * a.sin(), zc + half_h * a.cos())
    })
}

/// Both halves of a left-wing-side polygon: the given corners (y ≥ 0) and their mirror in y.
fn mirrored(b: &mut EdgeMeshBuilder, corners: &[Vec3]) {
    b.polygon(corners).expect("finite constants");
    let mirror: Vec<Vec3> = corners.iter().map(|p| Vec3::new(p.x, -p.y, p.z)).collect();
    b.polygon(&mirror).expect("finite constants");
}

/// The built-in plane as an edge mesh (≈ 110 edges).
pub fn builtin_plane() -> EdgeMesh {
    let mut b = EdgeMeshBuilder::new();

    // Fuselage: hexagonal rings joined by longerons, closed by nose and tail points.
    let rings: Vec<[Vec3; HEX]> = STATIONS
        .iter()
        .map(|&(x, w, h, z)| ring(x, w, h, z))
        .collect();
    for r in &rings {
        b.polygon(r).expect("finite constants");
    }
    for pair in rings.windows(2) {
        for (&a, &c) in pair[0].iter().zip(&pair[1]) {
            b.edge_between(a, c).expect("finite");
        }
    }
    for (&front, &back) in rings[0].iter().zip(&rings[rings.len() - 1]) {
        b.edge_between(NOSE_TIP, front).expect("finite");
        b.edge_between(back, TAIL_TIP).expect("finite");
    }

    // Propeller: a two-blade cross in front of the nose.
    let hub = NOSE_TIP + Vec3::new(0.05, 0.0, 0.0);
    b.edge_between(
        hub + Vec3::new(0.0, 0.0, 0.9),
        hub - Vec3::new(0.0, 0.0, 0.9),
    )
    .expect("finite");
    b.edge_between(
        hub + Vec3::new(0.0, 0.25, 0.0),
        hub - Vec3::new(0.0, 0.25, 0.0),
    )
    .expect("finite");

    // Canopy: a wedge on top of the fuselage ahead of the wing.
    let front = Vec3::new(2.0, 0.0, 0.62);
    let top = Vec3::new(1.0, 0.0, 0.95);
    let rear = Vec3::new(-0.6, 0.0, 0.66);
    let sill_l = Vec3::new(1.0, 0.42, 0.55);
    let sill_r = Vec3::new(1.0, -0.42, 0.55);
    b.polyline(&[front, top, rear]).expect("finite");
    for sill in [sill_l, sill_r] {
        b.polyline(&[front, sill, rear]).expect("finite");
        b.edge_between(top, sill).expect("finite");
    }

    // Wings: low wing with 4° dihedral, tapered; each half is a polygon with a rib at
    // mid-span and the aileron hinge line.
    let dihedral = 4f32.to_radians().tan();
    let wing = |x: f32, y: f32| Vec3::new(x, y, -0.35 + dihedral * y);
    let (root_le, root_te) = (wing(1.0, 0.55), wing(-0.7, 0.55));
    let (tip_le, tip_te) = (wing(0.35, 5.6), wing(-0.45, 5.6));
    mirrored(&mut b, &[root_le, tip_le, tip_te, root_te]);
    let (mid_le, mid_te) = (wing(0.68, 3.0), wing(-0.58, 3.0));
    let hinge_in = wing(-0.3, 3.0);
    let hinge_out = wing(-0.2, 5.6);
    for (p, q) in [(mid_le, mid_te), (hinge_in, hinge_out)] {
        b.edge_between(p, q).expect("finite");
        b.edge_between(Vec3::new(p.x, -p.y, p.z), Vec3::new(q.x, -q.y, q.z))
            .expect("finite");
    }

    // Tailplane at the tail cone.
    let tail = |x: f32, y: f32| Vec3::new(x, y, 0.25);
    mirrored(
        &mut b,
        &[
            tail(-3.9, 0.25),
            tail(-4.3, 2.0),
            tail(-4.8, 2.0),
            tail(-4.8, 0.25),
        ],
    );
    // Elevator hinge across both halves.
    b.edge_between(tail(-4.5, 2.0), tail(-4.5, -2.0))
        .expect("finite");

    // Fin and rudder, on the top longeron.
    let fin_root_le = Vec3::new(-3.4, 0.0, 0.55);
    let fin_root_te = Vec3::new(-5.0, 0.0, 0.5);
    let fin_tip_le = Vec3::new(-4.5, 0.0, 2.0);
    let fin_tip_te = Vec3::new(-5.15, 0.0, 2.0);
    b.polygon(&[fin_root_le, fin_tip_le, fin_tip_te, fin_root_te])
        .expect("finite");
    b.edge_between(Vec3::new(-4.7, 0.0, 0.52), Vec3::new(-4.85, 0.0, 2.0))
        .expect("finite");

    b.build().expect("the built-in plane has edges")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_has_the_seed_axes_and_a_sensible_size() {
        let m = builtin_plane();
        let n = m.edges().len();
        assert!((50..=200).contains(&n), "{n} edges");
        let (min, max) = m.bounds();
        // Nose forward along +X, wings along ±Y (symmetric), rudder up along +Z.
        assert!(max.x > 4.0 && min.x < -5.0);
        assert!((max.y + min.y).abs() < 1e-6 && max.y > 5.0);
        assert!(max.z >= 2.0 && min.z > -1.0);
        // The highest point is the fin, behind the centre.
        let top = m
            .positions()
            .iter()
            .max_by(|a, b| a.z.total_cmp(&b.z))
            .unwrap();
        assert!(top.x < -4.0);
    }
}
