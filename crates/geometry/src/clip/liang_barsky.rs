//! Liang-Barsky (1984; seed `clipping-sutherland-hodgman-liang-barsky-bresenham.txt`): the
//! edge `P(t) = A + t·(C − A)` is inside boundary k where `p_k·t ≤ q_k`. `p_k < 0`: the line
//! enters there, `t_in = max(t_in, q_k/p_k)`; `p_k > 0`: it leaves, `t_out = min(t_out,
//! q_k/p_k)`; `p_k = 0`: parallel, and outside altogether if `q_k < 0`. Each boundary is
//! taken in turn and the edge dropped as soon as `t_in > t_out` ("the actual Liang-Barsky":
//! some rejects occur early). Only the final endpoints are computed, once.
//!
//! * [`clip_2d`]: the window: `p = (−Δx, Δx, −Δy, Δy)`, `q = (x₀ − x_min, x_max − x₀,
//!   y₀ − y_min, y_max − y₀)`.
//! * [`clip_homogeneous`]: clip space: `q_k = BC_k(A)`, `p_k = BC_k(A) − BC_k(C)`, so
//!   `BC_k(P(t)) = q_k − p_k·t` (and extra planes the same way).
//! * [`clip_box`]: an axis-aligned box in 3D.
//!
//! There is no outcode pass, so Liang-Barsky divides for every boundary the line is not
//! parallel to, even for an edge wholly inside: its tallies show no trivial rejects except
//! edges parallel to and outside a boundary seen before any division.

use glam::{DVec3, Vec2, Vec3, Vec4};

use super::window::finish_2d;
use super::{settle, ClipOutcome, ClipOutcome2, ClipVolume, Window2};

/// The candidate interval after the boundaries `(p_k, q_k)`: `Ok((t_in, t_out))`, or the
/// outcome of an early drop.
#[inline]
fn interval<P>(pq: impl Iterator<Item = (f64, f64)>) -> Result<(f64, f64), ClipOutcome<P>> {
    let (mut t_in, mut t_out) = (0.0f64, 1.0f64);
    let mut divided = false;
    for (p, q) in pq {
        if p == 0.0 {
            if q < 0.0 {
                // Parallel to the boundary and outside it.
                return Err(if divided {
                    ClipOutcome::ClippedAway
                } else {
                    ClipOutcome::Rejected
                });
            }
            continue;
        }
        let r = q / p;
        divided = true;
        if p < 0.0 {
            if r > t_out {
                return Err(ClipOutcome::ClippedAway);
            }
            t_in = t_in.max(r);
        } else {
            if r < t_in {
                return Err(ClipOutcome::ClippedAway);
            }
            t_out = t_out.min(r);
        }
    }
    debug_assert!((0.0..=1.0).contains(&t_in) && (0.0..=1.0).contains(&t_out) && t_in <= t_out);
    Ok((t_in, t_out))
}

/// Clip the segment `a`→`c` against the window.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::{liang_barsky, ClipOutcome, Window2};
/// // The transcript's second example: M (left of the window) to N (right of it), cut at
/// // M' = (2, 11/4) and N' = (4, 9/4).
/// let w = Window2::new(2.0, 2.0, 4.0, 4.0).unwrap();
/// let out = liang_barsky::clip_2d(Vec2::new(1.0, 3.0), Vec2::new(5.0, 2.0), &w);
/// assert_eq!(out, ClipOutcome::Clipped(Vec2::new(2.0, 2.75), Vec2::new(4.0, 2.25)));
/// ```
pub fn clip_2d(a: Vec2, c: Vec2, window: &Window2) -> ClipOutcome2 {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.as_dvec2(), c.as_dvec2());
    let d = p1 - p0;
    let q = window.boundary_coords(p0);
    let p = [-d.x, d.x, -d.y, d.y];
    match interval(p.into_iter().zip(q)) {
        Err(out) => out,
        // t rounds to 0 or 1 for an end outside by less than its last bit: only the exact
        // test says accepted.
        Ok((t_in, t_out)) if t_in == 0.0 && t_out == 1.0 => {
            if window.outcode(a) | window.outcode(c) == 0 {
                ClipOutcome::Accepted(a, c)
            } else {
                ClipOutcome::Clipped(window.clamp(a), window.clamp(c))
            }
        }
        Ok((t_in, t_out)) => {
            let (s, e) = finish_2d(window, p0 + t_in * d, p0 + t_out * d);
            ClipOutcome::Clipped(
                if t_in == 0.0 { a } else { s },
                if t_out == 1.0 { c } else { e },
            )
        }
    }
}

/// Clip the homogeneous edge `a`→`c` against `volume` (view volume and extra planes).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{liang_barsky, ClipOutcome, ClipVolume, DepthRange};
/// let v = ClipVolume::new(DepthRange::NegOneToOne);
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(0.0, 0.0, 0.5, -1.0); // straight back through the eye plane
/// // The far plane z = w cuts it first (t = 1/4), well before w reaches 0.
/// let out = liang_barsky::clip_homogeneous(a, c, &v);
/// assert_eq!(out, ClipOutcome::Clipped(a, Vec4::new(0.0, 0.0, 0.5, 0.5)));
/// ```
pub fn clip_homogeneous(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.as_dvec4(), c.as_dvec4());
    let bc_a = volume.boundary_coords(p0);
    let bc_c = volume.boundary_coords(p1);
    let n = volume.plane_count();
    let pq = (0..n).map(|k| (bc_a[k] - bc_c[k], bc_a[k]));
    let (t_in, t_out) = match interval(pq) {
        Err(out) => return out,
        Ok(t) => t,
    };
    let d = p1 - p0;
    let at = |t: f64| settle((p0 + t * d).as_vec4(), p0, p1, t, volume.depth);
    // At t = 0 or 1 the end is the input's, guarded too: t can round to 1 for an end
    // outside by less than t's last bit, which may still be far outside for its own size.
    let a2 = if t_in == 0.0 {
        settle(a, p0, p1, 0.0, volume.depth)
    } else {
        at(t_in)
    };
    let c2 = if t_out == 1.0 {
        settle(c, p0, p1, 1.0, volume.depth)
    } else {
        at(t_out)
    };
    let inside = |bc: &[f64]| bc[..n].iter().all(|&b| b >= 0.0);
    if !(a2.w > 0.0 && c2.w > 0.0) {
        ClipOutcome::ClippedAway // only the eye (0, 0, 0, 0) is inside with w = 0
    } else if t_in == 0.0 && t_out == 1.0 && inside(&bc_a) && inside(&bc_c) {
        ClipOutcome::Accepted(a, c)
    } else {
        // (With t at 0 and 1 but an end outside by less than t's last bit: the edge itself.)
        ClipOutcome::Clipped(a2, c2)
    }
}

/// Clip the 3D segment `a`→`c` against the axis-aligned box `[min, max]` (edges included).
/// A box with `min > max` on some axis contains nothing; the segment is then dropped.
///
/// ```
/// use glam::Vec3;
/// use wireflight_geometry::clip::{liang_barsky, ClipOutcome};
/// let out = liang_barsky::clip_box(Vec3::ZERO, Vec3::splat(4.0), Vec3::splat(-1.0), Vec3::ONE);
/// assert_eq!(out, ClipOutcome::Clipped(Vec3::ZERO, Vec3::ONE));
/// ```
pub fn clip_box(a: Vec3, c: Vec3, min: Vec3, max: Vec3) -> ClipOutcome<Vec3> {
    if !(a.is_finite() && c.is_finite() && min.is_finite() && max.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (p0, p1) = (a.as_dvec3(), c.as_dvec3());
    let (lo, hi) = (min.as_dvec3(), max.as_dvec3());
    let d = p1 - p0;
    let p = [-d.x, d.x, -d.y, d.y, -d.z, d.z];
    let q = [
        p0.x - lo.x,
        hi.x - p0.x,
        p0.y - lo.y,
        hi.y - p0.y,
        p0.z - lo.z,
        hi.z - p0.z,
    ];
    if lo.cmpgt(hi).any() {
        return ClipOutcome::Rejected;
    }
    let clamp = |v: DVec3| v.clamp(lo, hi).as_vec3();
    match interval(p.into_iter().zip(q)) {
        Err(out) => out,
        Ok((t_in, t_out)) if t_in == 0.0 && t_out == 1.0 && clamp(p0) == a && clamp(p1) == c => {
            ClipOutcome::Accepted(a, c)
        }
        Ok((t_in, t_out)) => ClipOutcome::Clipped(
            clamp(p0 + t_in * d),
            if t_out == 1.0 {
                clamp(p1)
            } else {
                clamp(p0 + t_out * d)
            },
        ),
    }
}
