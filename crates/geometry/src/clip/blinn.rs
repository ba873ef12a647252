//! Blinn's homogeneous line clipper (Blinn & Newell 1978; as taught in the seed lecture
//! `clipping-cohen-sutherland-and-blinn-3d.txt`).
//!
//! For an edge A→C, each endpoint gets six boundary coordinates (BCs) and a 6-bit outcode.
//! `a | c == 0` accepts the edge untouched, `a & c != 0` rejects it untouched. Otherwise the
//! edge is the parametric segment `P(t) = A + t·(C − A)`, `t ∈ [0, 1]`; every BC is linear in t,
//! so a plane the edge crosses is hit at `t_hit = BC_A / (BC_A − BC_C)`. Crossings where A is
//! outside raise `t_in`, crossings where C is outside lower `t_out`; as soon as
//! `t_in > t_out` the candidate interval is empty and the edge is gone. The survivors are
//! recomputed from the *original* A and C at `t_in` and `t_out`.
//!
//! Only planes that one endpoint is outside of are visited (the others cannot change the
//! interval), and there is no division by zero: a visited plane has one BC < 0 ≤ the other.
//!
//! The outcodes come from `f32` boundary coordinates (an overflow to ±∞ keeps its sign, so the
//! codes stay right). The crossing parameters and new endpoints of a non-trivial edge are
//! computed in `f32` where every coordinate of both ends is at most [`SINGLE_LIMIT`] (2⁶⁰) in
//! magnitude, and in `f64` beyond: there `BC_A − BC_C` and `C − A` could overflow `f32`
//! (near `f32::MAX` they would give t = 0 and NaN endpoints). Below the limit no operation can
//! overflow, each is one rounding (relative 2⁻²⁴), and there is no cancellation to amplify
//! it: a boundary coordinate is one rounded sum of two exact inputs, and the two in
//! `BC_A − BC_C` have opposite signs. So t is within a few units in the last place, and a new
//! endpoint within 2⁻²⁰ of the edge's largest coordinate of where the `f64` computation
//! puts it (the tests measure it), far below a pixel; `settle()` guards both alike. `f32`
//! lets the batch path clip sixteen edges per vector instead of eight ([`super::batch`]).

use glam::Vec4;

use super::{
    boundary_coords, boundary_coords_of, outcode, settle, ClipOutcome, ClipVolume, DepthRange,
    PLANE_COUNT,
};

/// Clip the edge `a`→`c` (homogeneous clip coordinates) against the view volume.
///
/// Never panics and never allocates; non-finite input gives [`ClipOutcome::NonFinite`].
/// Points on a boundary plane count as inside.
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{clip_edge, ClipOutcome, DepthRange};
/// // From inside to beyond x = w: cut where x = w.
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(3.0, 0.0, 0.5, 1.0);
/// let ClipOutcome::Clipped(a2, c2) = clip_edge(a, c, DepthRange::ZeroToOne) else { panic!() };
/// assert_eq!(a2, a);
/// assert!((c2 - Vec4::new(1.0, 0.0, 0.5, 1.0)).abs().max_element() < 1e-6);
/// ```
#[inline]
pub fn clip_edge(a: Vec4, c: Vec4, depth: DepthRange) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let a_bc = boundary_coords(a, depth);
    let c_bc = boundary_coords(c, depth);
    let a_code = outcode(&a_bc);
    let c_code = outcode(&c_bc);

    if a_code & c_code != 0 {
        return ClipOutcome::Rejected;
    }
    if a_code | c_code == 0 {
        // Inside points have w ≥ 0; w = 0 only at the eye (0,0,0,0), whose segment to any
        // other point projects to a single point.
        return if a.w > 0.0 && c.w > 0.0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }

    clip_crossing(a, c, a_code, c_code, depth)
}

/// The non-trivial case of [`clip_edge`]: finite `a`, `c` with outcodes `a_code`, `c_code`
/// (six bits each, as [`outcode`] gives them) that are neither trivially accepted
/// (`a | c == 0`) nor rejected (`a & c != 0`). Shared with the batch path ([`super::batch`]),
/// so both give bit-identical segments.
#[inline]
pub fn clip_crossing(a: Vec4, c: Vec4, a_code: u8, c_code: u8, depth: DepthRange) -> ClipOutcome {
    debug_assert!(a_code & c_code == 0 && a_code | c_code != 0);
    debug_assert!(a.is_finite() && c.is_finite());
    if a.abs().max(c.abs()).max_element() <= SINGLE_LIMIT {
        crossing_in::<f32>(a, c, a_code, c_code, depth)
    } else {
        crossing_in::<f64>(a, c, a_code, c_code, depth)
    }
}

/// The largest coordinate magnitude whose edges [`clip_crossing`] clips in `f32` (2⁶⁰): the
/// boundary coordinates, their differences, `C − A` and `t·(C − A)` then stay below 2⁶³,
/// far from overflow.
pub const SINGLE_LIMIT: f32 = (1u64 << 60) as f32;

/// The arithmetic [`clip_crossing`] computes in: `f32` or `f64`.
trait Arith:
    Copy
    + PartialOrd
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    fn of(x: f32) -> Self;
    fn to_f32(self) -> f32;
    fn to_f64(self) -> f64;
    fn min(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
}

macro_rules! arith {
    ($t:ty) => {
        impl Arith for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn of(x: f32) -> Self {
                Self::from(x)
            }
            #[inline(always)]
            #[allow(clippy::cast_possible_truncation)]
            fn to_f32(self) -> f32 {
                self as f32
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                f64::from(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                <$t>::min(self, o)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                <$t>::max(self, o)
            }
        }
    };
}
arith!(f32);
arith!(f64);

/// [`clip_crossing`] in the arithmetic `T`: per plane crossed `t_hit = BC_A / (BC_A − BC_C)`,
/// the new ends `A + t·(C − A)` rounded to `f32`, each through `settle()`.
#[inline(always)]
fn crossing_in<T: Arith>(
    a: Vec4,
    c: Vec4,
    a_code: u8,
    c_code: u8,
    depth: DepthRange,
) -> ClipOutcome {
    let (at, ct) = (a.to_array().map(T::of), c.to_array().map(T::of));
    let a_bc = boundary_coords_of(at, depth);
    let c_bc = boundary_coords_of(ct, depth);
    let mut t_in = T::ZERO;
    let mut t_out = T::ONE;
    let crossed = a_code | c_code;
    for i in 0..PLANE_COUNT {
        if crossed & (1 << i) == 0 {
            continue; // both endpoints inside this plane: it cannot shorten the interval
        }
        let t_hit = a_bc[i] / (a_bc[i] - c_bc[i]);
        if c_code & (1 << i) != 0 {
            t_out = t_out.min(t_hit); // leaving: C is outside
        } else {
            t_in = t_in.max(t_hit); // entering: A is outside
        }
        if t_in > t_out {
            return ClipOutcome::ClippedAway; // empty candidate interval: early exit
        }
    }

    let (a64, c64) = (a.as_dvec4(), c.as_dvec4());
    let at_t = |t: T| {
        Vec4::from_array(std::array::from_fn(|k| {
            (at[k] + t * (ct[k] - at[k])).to_f32()
        }))
    };
    let a_out = if a_code != 0 {
        settle(at_t(t_in), a64, c64, t_in.to_f64(), depth)
    } else {
        a
    };
    let c_out = if c_code != 0 {
        settle(at_t(t_out), a64, c64, t_out.to_f64(), depth)
    } else {
        c
    };
    debug_assert!(t_in >= T::ZERO && t_out <= T::ONE && t_in <= t_out);
    if a_out.w > 0.0 && c_out.w > 0.0 {
        ClipOutcome::Clipped(a_out, c_out)
    } else {
        ClipOutcome::ClippedAway
    }
}

/// [`clip_edge`] against a volume with extra planes: each extra plane's boundary coordinate is
/// the plane dotted with the point, visited like the six. With no extra planes this *is*
/// [`clip_edge`] (bit-identical).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{blinn, ClipOutcome, ClipVolume, DepthRange, PlaneSet};
/// // Keep x ≤ 0.5·w as well: the plane (−1, 0, 0, 0.5).
/// let mut extra = PlaneSet::default();
/// extra.push(Vec4::new(-1.0, 0.0, 0.0, 0.5)).unwrap();
/// let volume = ClipVolume::with_planes(DepthRange::ZeroToOne, extra);
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(1.0, 0.0, 0.5, 1.0);
/// let ClipOutcome::Clipped(_, c2) = blinn::clip_edge_in(a, c, &volume) else { panic!() };
/// assert_eq!(c2, Vec4::new(0.5, 0.0, 0.5, 1.0));
/// ```
#[inline]
pub fn clip_edge_in(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if volume.extra.is_empty() {
        return clip_edge(a, c, volume.depth);
    }
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (a64, c64) = (a.as_dvec4(), c.as_dvec4());
    let a_bc = volume.boundary_coords(a64);
    let c_bc = volume.boundary_coords(c64);
    let n = volume.plane_count();
    let (mut a_code, mut c_code) = (0u32, 0u32);
    for i in 0..n {
        a_code |= u32::from(a_bc[i] < 0.0) << i;
        c_code |= u32::from(c_bc[i] < 0.0) << i;
    }
    if a_code & c_code != 0 {
        return ClipOutcome::Rejected;
    }
    if a_code | c_code == 0 {
        return if a.w > 0.0 && c.w > 0.0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }
    let mut t_in = 0.0f64;
    let mut t_out = 1.0f64;
    for i in 0..n {
        if (a_code | c_code) & (1 << i) == 0 {
            continue;
        }
        let t_hit = a_bc[i] / (a_bc[i] - c_bc[i]);
        if c_code & (1 << i) != 0 {
            t_out = t_out.min(t_hit);
        } else {
            t_in = t_in.max(t_hit);
        }
        if t_in > t_out {
            return ClipOutcome::ClippedAway;
        }
    }
    let d = c64 - a64;
    let a_out = if a_code != 0 {
        settle((a64 + t_in * d).as_vec4(), a64, c64, t_in, volume.depth)
    } else {
        a
    };
    let c_out = if c_code != 0 {
        settle((a64 + t_out * d).as_vec4(), a64, c64, t_out, volume.depth)
    } else {
        c
    };
    debug_assert!(t_in >= 0.0 && t_out <= 1.0 && t_in <= t_out);
    if a_out.w > 0.0 && c_out.w > 0.0 {
        ClipOutcome::Clipped(a_out, c_out)
    } else {
        ClipOutcome::ClippedAway
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clip::{boundary_coords, outcode};

    /// xorshift64: deterministic, no dependency.
    struct Rng(u64);

    impl Rng {
        fn unit(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * self.unit()
        }
        /// A point of scale `w`, inside or up to three times outside the volume, or behind
        /// the eye.
        fn point(&mut self, scale: f32) -> Vec4 {
            let w = scale * self.range(-0.5, 1.0);
            let r = 3.0 * w.abs().max(scale * 0.1);
            Vec4::new(self.range(-r, r), self.range(-r, r), self.range(-r, r), w)
        }
    }

    /// Random crossing edges (neither trivially accepted nor rejected) over twelve decades
    /// of scale, with their outcodes.
    fn crossing_edges(n: usize) -> Vec<(Vec4, Vec4, u8, u8)> {
        let depth = DepthRange::ZeroToOne;
        let mut rng = Rng(0x5EED_F32F_64C0_FFEE);
        let mut out = Vec::with_capacity(n);
        while out.len() < n {
            let scale = 10f32.powf(rng.range(-6.0, 6.0));
            let (a, c) = (rng.point(scale), rng.point(scale));
            let (ac, cc) = (
                outcode(&boundary_coords(a, depth)),
                outcode(&boundary_coords(c, depth)),
            );
            if ac & cc == 0 && ac | cc != 0 {
                out.push((a, c, ac, cc));
            }
        }
        out
    }

    /// The `f32` arithmetic against the `f64` one on the same crossing edges: the same
    /// outcome but where the interval is empty to within rounding, and new ends within 2⁻²⁰
    /// of the edge's largest coordinate (the bound the module docs give).
    #[test]
    fn single_and_double_crossings_agree_to_the_documented_bound() {
        let depth = DepthRange::ZeroToOne;
        let (mut worst, mut differ, mut both) = (0f64, 0usize, 0usize);
        let edges = crossing_edges(200_000);
        for &(a, c, ac, cc) in &edges {
            let single = crossing_in::<f32>(a, c, ac, cc, depth);
            let double = crossing_in::<f64>(a, c, ac, cc, depth);
            let m = f64::from(a.abs().max(c.abs()).max_element());
            match (single, double) {
                (ClipOutcome::Clipped(p, q), ClipOutcome::Clipped(p2, q2)) => {
                    both += 1;
                    let d = (p.as_dvec4() - p2.as_dvec4())
                        .abs()
                        .max((q.as_dvec4() - q2.as_dvec4()).abs())
                        .max_element();
                    worst = worst.max(d / m);
                }
                (s, d) if std::mem::discriminant(&s) != std::mem::discriminant(&d) => {
                    differ += 1;
                }
                _ => {}
            }
        }
        eprintln!(
            "{both} clipped both ways; worst end difference {worst:.3e} of the largest \
             coordinate (bound 2^-20 = {:.3e}); {differ} of {} outcomes differ",
            2f64.powi(-20),
            edges.len()
        );
        assert!(both > 50_000, "{both}");
        assert!(worst <= 2f64.powi(-20), "{worst:e}");
        assert!(differ * 10_000 <= edges.len(), "{differ}");
    }

    /// `clip_crossing` computes in `f32` up to [`SINGLE_LIMIT`] and in `f64` beyond, on an
    /// edge whose two results differ: scaled by powers of two (exact), it lands at the limit
    /// and just beyond it.
    #[test]
    fn the_arithmetic_follows_the_largest_coordinate() {
        let depth = DepthRange::ZeroToOne;
        let (a, c, ac, cc) = crossing_edges(20_000)
            .into_iter()
            .find(|&(a, c, ac, cc)| {
                crossing_in::<f32>(a, c, ac, cc, depth) != crossing_in::<f64>(a, c, ac, cc, depth)
                    && matches!(
                        crossing_in::<f64>(a, c, ac, cc, depth),
                        ClipOutcome::Clipped(..)
                    )
            })
            .expect("an edge whose single and double results differ");
        let m = a.abs().max(c.abs()).max_element();
        // The power of two that puts the largest coordinate just at or below the limit.
        let k = (SINGLE_LIMIT / m).log2().floor() as i32;
        for (scale, single) in [(2f32.powi(k), true), (2f32.powi(k + 2), false)] {
            let (a, c) = (a * scale, c * scale);
            let got = clip_crossing(a, c, ac, cc, depth);
            let want = if single {
                crossing_in::<f32>(a, c, ac, cc, depth)
            } else {
                crossing_in::<f64>(a, c, ac, cc, depth)
            };
            assert_eq!(got, want, "scale 2^{}", scale.log2());
            assert_ne!(
                crossing_in::<f32>(a, c, ac, cc, depth),
                crossing_in::<f64>(a, c, ac, cc, depth),
                "the scaled edge still tells the two apart"
            );
        }
    }
}
