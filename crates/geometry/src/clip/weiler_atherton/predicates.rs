//! The geometric questions Weiler-Atherton asks, answered exactly for any finite `f64` input:
//! which side of a line a point is on, which way one direction turns from another, and in
//! which order points lie along an edge.
//!
//! Each is a polynomial in the input coordinates. It is evaluated in `f64` first with a bound
//! on its rounding error (Shewchuk's, "Adaptive precision floating-point arithmetic and fast
//! robust geometric predicates", 1997: the error of `l − r` with `l`, `r` products of rounded
//! differences is at most (3 + 16ε)ε·(|l| + |r|), ε = 2⁻⁵³; we take 4ε, and add the smallest
//! normal number for products that underflow). When the result is farther from zero than the
//! bound, its sign is the true sign, which is almost always; otherwise the polynomial is
//! evaluated again in exact dyadic arithmetic ([`Dyadic`]). So the answers are never
//! contradictory, which rounded signs are: a vertex 10⁻²⁰ from an edge 10⁶ long could be
//! "on" the edge for one test and "off" it for the next.

use std::cmp::Ordering;

use glam::DVec2;

use super::exact::Dyadic;

/// Relative error bound of `l − r` (see the module docs): 4ε, ε = 2⁻⁵³ = `f64::EPSILON` / 2.
const ERR: f64 = 2.0 * f64::EPSILON;

/// The rounded value of (a1 − a0) × (b1 − b0) and a bound on its error (∞ where the
/// arithmetic overflowed, NaN never compares greater than it).
fn cross_filter(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> (f64, f64) {
    let (ux, uy) = (a1.x - a0.x, a1.y - a0.y);
    let (vx, vy) = (b1.x - b0.x, b1.y - b0.y);
    let (l, r) = (ux * vy, uy * vx);
    let bound = ERR * (l.abs() + r.abs()) + f64::MIN_POSITIVE;
    (
        l - r,
        if bound.is_finite() {
            bound
        } else {
            f64::INFINITY
        },
    )
}

/// (a1 − a0) × (b1 − b0), exactly.
pub(super) fn cross_exact(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> Dyadic {
    let d = |p: f64, q: f64| &Dyadic::from_f64(q) - &Dyadic::from_f64(p);
    let (ux, uy) = (d(a0.x, a1.x), d(a0.y, a1.y));
    let (vx, vy) = (d(b0.x, b1.x), d(b0.y, b1.y));
    &(&ux * &vy) - &(&uy * &vx)
}

/// The sign of (a1 − a0) × (b1 − b0): `Greater` when the direction b0→b1 turns left
/// (counter-clockwise) from a0→a1, `Equal` when they are parallel (or one is zero).
pub(super) fn cross(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> Ordering {
    let (det, bound) = cross_filter(a0, a1, b0, b1);
    if det > bound {
        Ordering::Greater
    } else if -det > bound {
        Ordering::Less
    } else {
        cross_exact(a0, a1, b0, b1).sign()
    }
}

/// Orientation of `c` relative to the line a→b: `Greater` left, `Less` right, `Equal` on it.
pub(super) fn orient(a: DVec2, b: DVec2, c: DVec2) -> Ordering {
    cross(a, b, a, c)
}

/// Whether the directions a0→a1 and b0→b1, known to be parallel and nonzero, point the same
/// way: the signs of their coordinates agree (compared, not subtracted: exact).
pub(super) fn same_direction(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> bool {
    let signs = |p: DVec2, q: DVec2| (q.x.total_cmp(&p.x), q.y.total_cmp(&p.y));
    signs(a0 + DVec2::ZERO, a1 + DVec2::ZERO) == signs(b0 + DVec2::ZERO, b1 + DVec2::ZERO)
}

/// (a1 − a0) × (b1 − b0) to about 2⁻⁴⁰ relative, or `None` where the filter's value is not
/// that good (then the exact value is needed).
fn cross_accurate(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> Option<f64> {
    let (det, bound) = cross_filter(a0, a1, b0, b1);
    (bound <= det.abs() * 2f64.powi(-40)).then_some(det)
}

/// Where the segment p0→p1 crosses the line through q0, q1, as the parameter t along p
/// (0 at p0, 1 at p1), to about 2⁻³⁸ relative. The caller knows they cross: p0 and p1 lie
/// strictly on opposite sides of the line.
pub(super) fn crossing_parameter(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> f64 {
    // t = a / (a − b), a and b the sides of p0 and p1: opposite signs, so no cancellation.
    if let (Some(a), Some(b)) = (
        cross_accurate(q0, q1, q0, p0),
        cross_accurate(q0, q1, q0, p1),
    ) {
        // a − b can overflow (both near ±f64::MAX), and a / ∞ would be a finite, wrong 0.
        let den = a - b;
        if den.is_finite() {
            return a / den;
        }
    }
    let a = cross_exact(q0, q1, q0, p0);
    let b = cross_exact(q0, q1, q0, p1);
    Dyadic::ratio(&a, &(&a - &b))
}

/// The point at parameter `t` of p0→p1, kept within the segment's bounding box (so within
/// both crossing segments' boxes) and finite for any finite ends.
pub(super) fn point_at(p0: DVec2, p1: DVec2, t: f64) -> DVec2 {
    let d = p1 - p0;
    let p = if d.is_finite() {
        p0 + t * d
    } else {
        // Ends near ±f64::MAX: their difference overflows, a weighted sum does not.
        p0 * (1.0 - t) + p1 * t
    };
    p.clamp(p0.min(p1), p0.max(p1))
}

/// A point splitting an edge e0→e1: a vertex of the other polygon lying on it, or where an
/// edge q0→q1 of the other polygon crosses it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Split {
    /// A vertex on the edge.
    Vertex(DVec2),
    /// A crossing with the edge q0→q1.
    Crossing(DVec2, DVec2),
}

impl Split {
    /// The parameter along e0→e1, approximately: to a few units in the last place for a
    /// vertex, 2⁻³⁸ for a crossing; NaN where an intermediate overflowed.
    pub(super) fn approximate(self, e0: DVec2, e1: DVec2) -> f64 {
        match self {
            Split::Vertex(v) => {
                let (num, den) = if (e1.x - e0.x).abs() >= (e1.y - e0.y).abs() {
                    (v.x - e0.x, e1.x - e0.x)
                } else {
                    (v.y - e0.y, e1.y - e0.y)
                };
                if num.is_finite() && den.is_finite() {
                    num / den
                } else {
                    f64::NAN
                }
            }
            Split::Crossing(q0, q1) => crossing_parameter(e0, e1, q0, q1),
        }
    }

    /// The parameter along e0→e1 exactly, as `num / den` with `den > 0`.
    fn exact(self, e0: DVec2, e1: DVec2) -> (Dyadic, Dyadic) {
        let (num, den) = match self {
            // On the edge: one coordinate that changes along it gives the parameter.
            Split::Vertex(v) => {
                let d = |p: f64, q: f64| &Dyadic::from_f64(q) - &Dyadic::from_f64(p);
                if e1.x != e0.x {
                    (d(e0.x, v.x), d(e0.x, e1.x))
                } else {
                    (d(e0.y, v.y), d(e0.y, e1.y))
                }
            }
            Split::Crossing(q0, q1) => {
                let a = cross_exact(q0, q1, q0, e0);
                let b = cross_exact(q0, q1, q0, e1);
                let den = &a - &b;
                (a, den)
            }
        };
        if den.sign() == Ordering::Less {
            (-&num, -&den)
        } else {
            (num, den)
        }
    }
}

/// The order of two split points along e0→e1, given their [`Split::approximate`] parameters:
/// decided from those when they are far enough apart, exactly otherwise.
pub(super) fn compare_along(
    e0: DVec2,
    e1: DVec2,
    (x, tx): (Split, f64),
    (y, ty): (Split, f64),
) -> Ordering {
    // The approximations are within 2⁻³⁸ relative (or 2⁻¹⁰⁷⁴ absolute if subnormal) of the
    // truth: a gap of 2⁻³⁶ of the larger cannot be their error.
    if tx.is_finite() && ty.is_finite() {
        let tol = 2f64.powi(-36) * tx.abs().max(ty.abs()) + 2f64.powi(-1000);
        if ty - tx > tol {
            return Ordering::Less;
        }
        if tx - ty > tol {
            return Ordering::Greater;
        }
    }
    let (nx, dx) = x.exact(e0, e1);
    let (ny, dy) = y.exact(e0, e1);
    (&(&nx * &dy) - &(&ny * &dx)).sign()
}

/// Whether a point lies on the closed segment a–b, knowing it is on the line through them:
/// within their bounding box (comparisons only: exact).
pub(super) fn within(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn orientation_is_exact_where_f64_rounds() {
        // Shewchuk's example family: points nearly on the line y = x, 12 ulps apart around 0.5.
        let (b, c) = (p(12.0, 12.0), p(24.0, 24.0));
        for i in 0..64 {
            for j in 0..64 {
                let a = p(
                    0.5 + f64::from(i) * f64::EPSILON,
                    0.5 + f64::from(j) * f64::EPSILON,
                );
                let want = f64::from(j).total_cmp(&f64::from(i));
                assert_eq!(orient(b, c, a), want, "{i} {j}");
            }
        }
        // Around 1e6 the differences round away a gap of one ulp of 0.3.
        let (b, c) = (p(1e6, 1e6), p(-1e6, -1e6));
        let a = p(0.3, 0.3f64.next_up());
        assert_eq!((c - b).perp_dot(a - b), 0.0, "f64 cannot tell");
        assert_eq!(orient(b, c, a), Ordering::Less);
        assert_eq!(orient(b, c, p(0.3, 0.3)), Ordering::Equal);
        // Products below the subnormal range still have a sign.
        let t = 1e-300;
        assert_eq!(orient(p(0., 0.), p(t, 0.), p(0., t)), Ordering::Greater);
        assert_eq!(
            orient(p(0., 0.), p(t, 0.), p(5e-324, -5e-324)),
            Ordering::Less
        );
        // Differences that overflow.
        let m = f64::MAX;
        assert_eq!(orient(p(-m, -m), p(m, m), p(-m, m)), Ordering::Greater);
        assert_eq!(orient(p(-m, -m), p(m, m), p(0.0, 0.0)), Ordering::Equal);
    }

    #[test]
    fn crossings_are_placed_and_ordered() {
        let (e0, e1) = (p(0., 0.), p(4., 0.));
        let t = crossing_parameter(e0, e1, p(1., -1.), p(1., 1.));
        assert_eq!(t, 0.25);
        assert_eq!(point_at(e0, e1, t), p(1., 0.));
        // Two crossings 2⁻⁴⁶ apart: the approximate parameters tie, the exact ones do not.
        let g = Split::Crossing(p(1., -1.), p(1., 1.));
        let h = Split::Crossing(
            p(1. - 2f64.powi(-10), -1.),
            p(1. + 2f64.powi(-10) + 2f64.powi(-45), 1.),
        );
        let (tg, th) = (g.approximate(e0, e1), h.approximate(e0, e1));
        assert!((th - tg).abs() < 2f64.powi(-38) * tg, "{tg} {th}");
        assert_eq!(compare_along(e0, e1, (g, tg), (h, th)), Ordering::Less);
        assert_eq!(compare_along(e0, e1, (h, th), (g, tg)), Ordering::Greater);
        assert_eq!(compare_along(e0, e1, (g, tg), (g, tg)), Ordering::Equal);
        // A vertex on the edge exactly at a crossing's parameter compares equal.
        let v = Split::Vertex(p(1., 0.));
        assert_eq!(
            compare_along(e0, e1, (v, v.approximate(e0, e1)), (g, tg)),
            Ordering::Equal
        );
        // Sides of ±0.9·f64::MAX: each finite, their difference not.
        let m = 0.9 * f64::MAX;
        assert_eq!(
            crossing_parameter(p(-m, 0.), p(m, 0.), p(0., 0.), p(0., 1.)),
            0.5
        );
        // Ends near f64::MAX: still finite and on the segment.
        let (m0, m1) = (p(-f64::MAX, 0.), p(f64::MAX, 0.));
        let x = point_at(m0, m1, crossing_parameter(m0, m1, p(1., -1.), p(1., 1.)));
        assert!(x.is_finite() && x.y == 0.0, "{x}");
    }
}
