//! Blinn's output equals clipping the 3D segment against the frustum in `f64`: random
//! perspective cameras (field of view, aspect, near, far), random view-space segments (in
//! front, behind the eye, crossing the eye plane, beside it), each clipped in view space
//! against the six frustum planes written from the camera's parameters (|x| ≤ −z·tan(fov/2)·
//! aspect, |y| ≤ −z·tan(fov/2), near ≤ −z ≤ far), then projected in `f64`; Blinn clips the
//! `f32` clip-space edge. The two agree within 1e-5 of the clip-space scale, except where
//! the visible part is degenerate at that scale. 100 000 segments per depth range.

use crate::support::Rng;
use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};
use wireflight::geometry::camera::Projection;
use wireflight::geometry::clip::{clip_edge, DepthRange};

fn frustum_interval(
    a: DVec3,
    c: DVec3,
    tan_y: f64,
    aspect: f64,
    near: f64,
    far: f64,
) -> Option<(f64, f64)> {
    let tan_x = tan_y * aspect;
    // Each plane as f(p) ≥ 0, linear in p.
    let planes: [&dyn Fn(DVec3) -> f64; 6] = [
        &|p| -p.z * tan_x - p.x,
        &|p| -p.z * tan_x + p.x,
        &|p| -p.z * tan_y - p.y,
        &|p| -p.z * tan_y + p.y,
        &|p| -p.z - near,
        &|p| far + p.z,
    ];
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for f in planes {
        let (fa, fc) = (f(a), f(c));
        let d = fc - fa;
        if d == 0.0 {
            if fa < 0.0 {
                return None;
            }
        } else if d > 0.0 {
            lo = lo.max(-fa / d);
        } else {
            hi = hi.min(-fa / d);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// The project's perspective matrix (`camera::Projection`), f32.
fn projection(fov: f64, aspect: f64, near: f64, far: f64, depth: DepthRange) -> Mat4 {
    Projection::Perspective {
        fov_y: fov as f32,
        near: near as f32,
        far: far as f32,
    }
    .matrix(aspect as f32, depth)
}

#[test]
fn blinn_equals_the_3d_frustum_clip() {
    let mut rng = Rng::new(0xF2u64 << 32);
    let mut compared = 0;
    let mut excused = 0;
    let mut worst = 0.0f64;
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        for i in 0..100_000 {
            let fov = rng.range(20.0, 120.0).to_radians();
            let aspect = rng.range(0.5, 2.5);
            let near = rng.log_range(0.01, 2.0);
            let far = near * rng.log_range(10.0, 1e4);
            let p = projection(fov, aspect, near, far, depth);
            let s = far * rng.range(0.05, 1.5);
            let mut pt = || {
                let z = match rng.below(4) {
                    0 => s * rng.range(0.0, 1.0),     // behind the eye
                    1 => -near * rng.range(0.0, 2.0), // around the near plane
                    _ => -s * rng.range(0.0, 1.2),
                };
                DVec3::new(s * rng.range(-1.5, 1.5), s * rng.range(-1.5, 1.5), z)
            };
            let (a, c) = (pt(), pt());
            let (af, cf) = (a.as_vec3(), c.as_vec3());
            let (ca, cc) = (p * af.extend(1.0), p * cf.extend(1.0));
            let scale = f64::from(ca.abs().max_element().max(cc.abs().max_element()));
            let got = clip_edge(ca, cc, depth).segment();
            // The reference: the f32-rounded view-space points, clipped against the frustum
            // in f64, then projected in f64.
            let (a64, c64) = (af.as_dvec3(), cf.as_dvec3());
            let pm: DMat4 = p.as_dmat4();
            let at = |t: f64| pm * (a64 + t * (c64 - a64)).extend(1.0);
            let reference = frustum_interval(a64, c64, (fov / 2.0).tan(), aspect, near, far);
            // Blinn sees the f32 product P·p, a few ulps off the exact clip coordinates; where
            // the edge meets its limiting plane at a grazing angle, that moves the cut along
            // the edge by (ulps of BC)/(BC's slope) in t. The tolerance includes that term.
            let (ea, ec) = (at(0.0), at(1.0));
            let bcs = |q: DVec4| {
                let zn = if depth == DepthRange::ZeroToOne {
                    q.z
                } else {
                    q.w + q.z
                };
                [q.w + q.x, q.w - q.x, q.w + q.y, q.w - q.y, zn, q.w - q.z]
            };
            let (ba, bc) = (bcs(ea), bcs(ec));
            let len = (ec - ea).abs().max_element();
            let tol_at = |t: f64| {
                // The plane whose BC is nearest zero at t is the one limiting there.
                let v = |k: usize| (ba[k] + t * (bc[k] - ba[k])).abs();
                let k = (0..6).min_by(|&i, &j| v(i).total_cmp(&v(j))).unwrap();
                let slope = (bc[k] - ba[k]).abs().max(f64::MIN_POSITIVE);
                1e-5 * scale + 16.0 * f64::from(f32::EPSILON) * scale * len / slope
            };
            let reference = reference.map(|(lo, hi)| (at(lo), at(hi), tol_at(lo), tol_at(hi)));
            let ctx = || {
                format!(
                    "#{i} {depth:?}: a = {af}, c = {cf}, fov {fov}, aspect {aspect}, near {near}, \
                     far {far}\n  clip {ca} → {cc}\n  blinn {got:?}\n  reference {reference:?}"
                )
            };
            let short = |p: DVec4, q: DVec4, tol: f64| (p - q).abs().max_element() <= 2.0 * tol;
            let tol = 1e-5 * scale;
            match (got, reference) {
                (None, None) => {}
                (Some((g0, g1)), Some((r0, r1, t0, t1))) => {
                    let d0 = (g0.as_dvec4() - r0).abs().max_element();
                    let d1 = (g1.as_dvec4() - r1).abs().max_element();
                    worst = worst.max(d0.max(d1) / scale);
                    compared += 1;
                    assert!(
                        (d0 <= t0 && d1 <= t1) || short(r0, r1, t0.max(t1)),
                        "differs by {d0:e}, {d1:e} > {t0:e}, {t1:e}\n{}",
                        ctx()
                    );
                }
                (Some((g0, g1)), None) => {
                    excused += 1;
                    assert!(
                        short(g0.as_dvec4(), g1.as_dvec4(), 10.0 * tol),
                        "blinn draws, reference does not\n{}",
                        ctx()
                    );
                }
                (None, Some((r0, r1, t0, t1))) => {
                    excused += 1;
                    assert!(
                        short(r0, r1, 10.0 * t0.max(t1)),
                        "reference draws, blinn does not\n{}",
                        ctx()
                    );
                }
            }
        }
    }
    println!(
        "compared {compared}, excused (degenerate) {excused}, worst relative difference {worst:e}"
    );
    assert!(compared > 50_000, "{compared}");
}

/// The same in the camera's own terms: a segment from in front of the eye to behind it ends
/// exactly where the 3D segment meets the near plane.
#[test]
fn near_plane_cut_matches_3d() {
    let near = 0.1f32;
    let p = projection(
        60f64.to_radians(),
        1.0,
        near.into(),
        100.0,
        DepthRange::ZeroToOne,
    );
    let (a, c) = (Vec3::new(0.01, 0.02, -5.0), Vec3::new(-0.01, 0.01, 5.0));
    let (_, end) = clip_edge(p * a.extend(1.0), p * c.extend(1.0), DepthRange::ZeroToOne)
        .segment()
        .unwrap();
    // On the near plane: w = near, z = 0.
    assert!((end.w - near).abs() < 1e-6 && end.z.abs() < 1e-6, "{end}");
}
