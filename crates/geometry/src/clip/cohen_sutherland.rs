//! Cohen-Sutherland (1967, for a flight simulator; seeds `clipping-and-euler-angles.txt`,
//! `clipping-2d-lecture-transcript.txt`, `clipping-cohen-sutherland-and-blinn-3d.txt`):
//! outcodes decide the trivial cases; otherwise an endpoint that is outside is *chopped* to
//! the boundary of one plane it is outside of, its outcode recomputed, and the tests repeated.
//!
//! * [`clip_2d`]: the 2D window, 4-bit outcodes (LEFT 1, RIGHT 2, BELOW 4, ABOVE 8), chopping
//!   by similar triangles, `y = y1 + (y2 − y1)(x_min − x1)/(x2 − x1)`, with the chopped
//!   coordinate set *exactly* to the boundary as in the seed's code (`x = xMin`).
//! * [`clip_homogeneous`]: clip space with 6-bit outcodes (and a bit per extra plane);
//!   a chop moves the end to `P + t(Q − P)` with `t = BC(P)/(BC(P) − BC(Q))`.
//!
//! Chopping starts from A when A is outside (the seed: "if p1 is outside … chop p1"), then C,
//! against the lowest outcode bit. Unlike Blinn's and Liang-Barsky's single interval, each
//! chop starts from the *already chopped* points, in `f64`.
//!
//! **Termination.** In 2D a chopped coordinate sits exactly on its boundary and, moving later
//! only toward the other end, never leaves it (floating-point interpolation between two
//! values stays between them), so each end is chopped at most once per edge of the window:
//! at most 8 chops. In clip space a chopped point is only *near* its plane, so each end
//! remembers the planes it was chopped against and is not chopped against them again: at most
//! one chop per plane and end. Both loops are bounded by those counts.

use glam::{DVec2, Vec2, Vec4};

use super::window::finish_2d;
use super::{
    lerp_from_nearer, settle, ClipOutcome, ClipOutcome2, ClipVolume, Window2, EDGE_COUNT,
    MAX_USER_PLANES, PLANE_COUNT,
};

fn code_2d(w: &Window2, p: DVec2) -> u8 {
    let bc = w.boundary_coords(p);
    let mut code = 0u8;
    for (i, &b) in bc.iter().enumerate() {
        code |= u8::from(b < 0.0) << i;
    }
    code
}

/// Clip the segment `a`→`c` against the window by Cohen-Sutherland's iterative chopping.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::{cohen_sutherland, ClipOutcome, Window2};
/// // The lecture transcript's example: window 2..4 × 2..4, P inside, Q right of it; the
/// // right boundary cuts PQ at (4, 5/2).
/// let w = Window2::new(2.0, 2.0, 4.0, 4.0).unwrap();
/// let out = cohen_sutherland::clip_2d(Vec2::new(3.0, 3.0), Vec2::new(5.0, 2.0), &w);
/// assert_eq!(out, ClipOutcome::Clipped(Vec2::new(3.0, 3.0), Vec2::new(4.0, 2.5)));
/// ```
pub fn clip_2d(a: Vec2, c: Vec2, window: &Window2) -> ClipOutcome2 {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (mut code_a, mut code_c) = (window.outcode(a), window.outcode(c));
    if code_a & code_c != 0 {
        return ClipOutcome::Rejected;
    }
    if code_a | code_c == 0 {
        return ClipOutcome::Accepted(a, c);
    }
    let (xmin, ymin) = (f64::from(window.xmin()), f64::from(window.ymin()));
    let (xmax, ymax) = (f64::from(window.xmax()), f64::from(window.ymax()));
    let (mut p, mut q) = (a.as_dvec2(), c.as_dvec2());
    // At most one chop per window edge and end, then one last test.
    for _ in 0..=2 * EDGE_COUNT {
        if code_a & code_c != 0 {
            return ClipOutcome::ClippedAway;
        }
        if code_a | code_c == 0 {
            let (p2, q2) = finish_2d(window, p, q);
            // An end never chopped is returned as it came in.
            let p2 = if p == a.as_dvec2() { a } else { p2 };
            let q2 = if q == c.as_dvec2() { c } else { q2 };
            return ClipOutcome::Clipped(p2, q2);
        }
        let (point, code, other) = if code_a != 0 {
            (&mut p, &mut code_a, q)
        } else {
            (&mut q, &mut code_c, p)
        };
        let bit = *code & code.wrapping_neg(); // the lowest set bit
                                               // The other end is inside this edge (no common bit), so the denominators below are
                                               // differences of numbers on opposite sides of the boundary: never zero.
        let chopped = match bit {
            1 => DVec2::new(
                xmin,
                point.y + (other.y - point.y) * (xmin - point.x) / (other.x - point.x),
            ),
            2 => DVec2::new(
                xmax,
                point.y + (other.y - point.y) * (xmax - point.x) / (other.x - point.x),
            ),
            4 => DVec2::new(
                point.x + (other.x - point.x) * (ymin - point.y) / (other.y - point.y),
                ymin,
            ),
            _ => DVec2::new(
                point.x + (other.x - point.x) * (ymax - point.y) / (other.y - point.y),
                ymax,
            ),
        };
        debug_assert!(
            chopped.is_finite(),
            "chop of {point} toward {other} against bit {bit}"
        );
        *point = chopped;
        *code = code_2d(window, chopped);
        debug_assert!(
            *code & bit == 0,
            "a chopped coordinate lies on its boundary"
        );
    }
    debug_assert!(
        false,
        "Cohen-Sutherland did not settle after {} chops",
        2 * EDGE_COUNT
    );
    ClipOutcome::ClippedAway
}

/// Clip the homogeneous edge `a`→`c` against `volume` by iterative chopping with outcodes.
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{cohen_sutherland, ClipOutcome, ClipVolume, DepthRange};
/// let v = ClipVolume::new(DepthRange::ZeroToOne);
/// let a = Vec4::new(-3.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(3.0, 0.0, 0.5, 1.0);
/// let ClipOutcome::Clipped(a2, c2) = cohen_sutherland::clip_homogeneous(a, c, &v) else { panic!() };
/// assert_eq!((a2, c2), (Vec4::new(-1.0, 0.0, 0.5, 1.0), Vec4::new(1.0, 0.0, 0.5, 1.0)));
/// ```
pub fn clip_homogeneous(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let n = volume.plane_count();
    let (mut p, mut q) = (a.as_dvec4(), c.as_dvec4());
    let mut bc_p = volume.boundary_coords(p);
    let mut bc_q = volume.boundary_coords(q);
    let code = |bc: &[f64; PLANE_COUNT + MAX_USER_PLANES], done: u32| -> u32 {
        let mut code = 0u32;
        for (i, &b) in bc[..n].iter().enumerate() {
            code |= u32::from(b < 0.0) << i;
        }
        code & !done
    };
    let (mut done_p, mut done_q) = (0u32, 0u32);
    let (mut code_p, mut code_q) = (code(&bc_p, 0), code(&bc_q, 0));
    if code_p & code_q != 0 {
        return ClipOutcome::Rejected;
    }
    if code_p | code_q == 0 {
        return if a.w > 0.0 && c.w > 0.0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }
    for _ in 0..2 * n {
        let (point, bc, done, other, bc_other) = if code_p != 0 {
            (&mut p, &mut bc_p, &mut done_p, q, &bc_q)
        } else {
            (&mut q, &mut bc_q, &mut done_q, p, &bc_p)
        };
        let this_code = if code_p != 0 { code_p } else { code_q };
        let i = this_code.trailing_zeros() as usize;
        let den = bc[i] - bc_other[i];
        if den >= 0.0 || den.is_nan() {
            // The other end was chopped onto this plane and rounding left it a hair outside
            // too: what remains touches the volume at most in that point.
            return ClipOutcome::ClippedAway;
        }
        let t = (bc[i] / den).min(1.0);
        debug_assert!((0.0..=1.0).contains(&t), "t = {t}");
        *point = lerp_from_nearer(*point, other, t);
        *bc = volume.boundary_coords(*point);
        *done |= 1 << i;
        code_p = code(&bc_p, done_p);
        code_q = code(&bc_q, done_q);
        if code_p & code_q != 0 {
            return ClipOutcome::ClippedAway;
        }
        if code_p | code_q == 0 {
            // Chopped ends get the guard against cancellation that Blinn's get (the chops
            // are from the nearer end already, so it can only clamp).
            let a2 = if done_p == 0 {
                a
            } else {
                settle(p.as_vec4(), p, p, 0.0, volume.depth)
            };
            let c2 = if done_q == 0 {
                c
            } else {
                settle(q.as_vec4(), q, q, 0.0, volume.depth)
            };
            return if a2.w > 0.0 && c2.w > 0.0 {
                ClipOutcome::Clipped(a2, c2)
            } else {
                ClipOutcome::ClippedAway
            };
        }
    }
    debug_assert!(
        false,
        "Cohen-Sutherland did not settle after {} chops",
        2 * n
    );
    ClipOutcome::ClippedAway
}
