//! Helpers shared by the integration tests: one approximate-equality assertion that prints
//! both values, the tolerance and the difference; a seeded random generator; angle wrapping;
//! an independent brute-force reference for the clipper; the binary's launcher ([`cli`]) and
//! `simulate` command lines ([`flights`]).
//!
//! Each test crate uses a different subset, hence `dead_code` is allowed here.

#![allow(dead_code)]

use std::fmt;
use std::path::PathBuf;

use glam::{DMat3, DVec3, Vec2, Vec3, Vec4};
use wireflight::geometry::clip::DepthRange;

/// Largest absolute component-wise difference between two values of the same shape.
pub trait MaxAbsDiff {
    /// `max |self_i − other_i|`; NaN if any component is NaN.
    fn max_abs_diff(&self, other: &Self) -> f64;
}

/// Max of a sequence of differences that propagates NaN (unlike `f64::max`).
fn nan_max(it: impl IntoIterator<Item = f64>) -> f64 {
    it.into_iter().fold(0.0f64, |m, d| {
        if d.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(d)
        }
    })
}

impl MaxAbsDiff for f64 {
    fn max_abs_diff(&self, other: &Self) -> f64 {
        if self == other {
            0.0 // also equal infinities
        } else {
            (self - other).abs()
        }
    }
}

impl MaxAbsDiff for f32 {
    fn max_abs_diff(&self, other: &Self) -> f64 {
        f64::from(*self).max_abs_diff(&f64::from(*other))
    }
}

macro_rules! impl_max_abs_diff_via_array {
    ($($t:ty),*) => {$(
        impl MaxAbsDiff for $t {
            fn max_abs_diff(&self, other: &Self) -> f64 {
                nan_max(
                    self.to_array()
                        .iter()
                        .zip(other.to_array().iter())
                        .map(|(a, b)| a.max_abs_diff(b)),
                )
            }
        }
    )*};
}
impl_max_abs_diff_via_array!(Vec2, Vec3, Vec4, DVec3);

impl MaxAbsDiff for DMat3 {
    fn max_abs_diff(&self, other: &Self) -> f64 {
        nan_max(
            self.to_cols_array()
                .iter()
                .zip(other.to_cols_array().iter())
                .map(|(a, b)| a.max_abs_diff(b)),
        )
    }
}

impl<T: MaxAbsDiff, const N: usize> MaxAbsDiff for [T; N] {
    fn max_abs_diff(&self, other: &Self) -> f64 {
        nan_max(
            self.iter()
                .zip(other.iter())
                .map(|(a, b)| a.max_abs_diff(b)),
        )
    }
}

/// The body of [`assert_close!`]: panics with both values, the tolerance and the difference.
#[track_caller]
pub fn assert_close_impl<T: MaxAbsDiff + fmt::Debug>(
    actual: &T,
    expected: &T,
    tol: f64,
    context: fmt::Arguments<'_>,
) {
    let diff = actual.max_abs_diff(expected);
    // Written so that a NaN difference fails.
    if diff.is_nan() || diff > tol {
        panic!(
            "values differ: {context}\n    actual:     {actual:?}\n    expected:   {expected:?}\n    \
             tolerance:  {tol:e}\n    difference: {diff:e} (max abs, component-wise)"
        );
    }
}

/// `assert_close!(actual, expected, tol)` or `assert_close!(actual, expected, tol, "fmt", args…)`:
/// max absolute component-wise difference ≤ `tol` (scalars, vectors, matrices, arrays of them).
/// On failure prints both values, the tolerance, the difference and the context.
macro_rules! assert_close {
    ($actual:expr, $expected:expr, $tol:expr $(,)?) => {
        $crate::support::assert_close_impl(&$actual, &$expected, ($tol) as f64, format_args!(""))
    };
    ($actual:expr, $expected:expr, $tol:expr, $($ctx:tt)+) => {
        $crate::support::assert_close_impl(
            &$actual,
            &$expected,
            ($tol) as f64,
            format_args!($($ctx)+),
        )
    };
}
#[allow(unused_imports)]
pub(crate) use assert_close;

/// SplitMix64: a tiny, fixed, seedable generator, so that every run sees the same cases.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in [lo, hi) as f32.
    pub fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        self.range(f64::from(lo), f64::from(hi)) as f32
    }

    /// Log-uniform in [lo, hi), both > 0.
    pub fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        (self.range(lo.ln(), hi.ln())).exp()
    }

    /// Uniform integer in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
}

/// An angle wrapped into (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = a.rem_euclid(TAU); // [0, 2π)
    if r > PI {
        r - TAU
    } else {
        r
    }
}

/// Distance between two angles on the circle, in [0, π].
pub fn angle_distance(a: f64, b: f64) -> f64 {
    wrap_angle(a - b).abs()
}

// ---------------------------------------------------------------------------------------------
// Brute-force clipping reference (f64, no shared code with the library).
// ---------------------------------------------------------------------------------------------

/// A homogeneous point in f64.
pub fn to_f64(p: Vec4) -> [f64; 4] {
    p.to_array().map(f64::from)
}

/// Signed distance-like "inside margin" of a homogeneous point: the smallest of its six
/// boundary coordinates, computed here from scratch in f64. ≥ 0 ⇔ in the view volume.
pub fn inside_margin(p: [f64; 4], depth: DepthRange) -> f64 {
    let [x, y, z, w] = p;
    let near = match depth {
        DepthRange::ZeroToOne => z,
        DepthRange::NegOneToOne => w + z,
    };
    [w + x, w - x, w + y, w - y, near, w - z]
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// `max(|x|, |y|, |z|, |w|)` of both endpoints: the scale that f32 rounding errors are relative to.
pub fn edge_scale(a: Vec4, c: Vec4) -> f64 {
    f64::from(a.abs().max_element().max(c.abs().max_element()))
}

/// The inside t-ranges of the edge `A + t (C − A)`, found by dense sampling.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReferenceRanges {
    /// Sampling step in t.
    pub step: f64,
    /// Samples strictly usable: margin ≥ 0 and w > 0 (the eye itself has no image).
    pub strict: Option<(f64, f64)>,
    /// Samples inside within the slack: margin ≥ −slack.
    pub loose: Option<(f64, f64)>,
    /// Samples robustly inside: margin ≥ +slack.
    pub robust: Option<(f64, f64)>,
}

fn widen(r: &mut Option<(f64, f64)>, t: f64) {
    *r = Some(match *r {
        None => (t, t),
        Some((lo, hi)) => (lo.min(t), hi.max(t)),
    });
}

/// Sample `samples` equally spaced points t ∈ [0, 1] of the edge (in f64 from the f32 inputs) and
/// report the t-ranges where it is inside strictly, within `slack` and by at least `slack`.
///
/// The inside set of a segment is convex (an intersection of half-spaces), so each range is an
/// interval; the min and max sampled t bracket it to within one step.
pub fn reference_ranges(
    a: Vec4,
    c: Vec4,
    depth: DepthRange,
    samples: usize,
    slack: f64,
) -> ReferenceRanges {
    assert!(samples >= 2);
    let a = to_f64(a);
    let c = to_f64(c);
    let d = [c[0] - a[0], c[1] - a[1], c[2] - a[2], c[3] - a[3]];
    let step = 1.0 / (samples - 1) as f64;
    let mut out = ReferenceRanges {
        step,
        ..Default::default()
    };
    for k in 0..samples {
        let t = k as f64 * step;
        let p = [
            a[0] + t * d[0],
            a[1] + t * d[1],
            a[2] + t * d[2],
            a[3] + t * d[3],
        ];
        let m = inside_margin(p, depth);
        if m >= -slack {
            widen(&mut out.loose, t);
            if m >= 0.0 && p[3] > 0.0 {
                widen(&mut out.strict, t);
            }
            if m >= slack {
                widen(&mut out.robust, t);
            }
        }
    }
    out
}

/// The parameter t with `p ≈ A + t (C − A)`, taken from the component of `C − A` with the
/// largest magnitude (the best-conditioned one). `None` for a zero-length edge.
pub fn recover_t(a: Vec4, c: Vec4, p: Vec4) -> Option<f64> {
    let (a, c, p) = (to_f64(a), to_f64(c), to_f64(p));
    let mut best = 0;
    for k in 1..4 {
        if (c[k] - a[k]).abs() > (c[best] - a[best]).abs() {
            best = k;
        }
    }
    let d = c[best] - a[best];
    (d != 0.0).then(|| (p[best] - a[best]) / d)
}

/// `max_k |A_k + t (C_k − A_k) − p_k|` in f64.
pub fn distance_from_line(a: Vec4, c: Vec4, t: f64, p: Vec4) -> f64 {
    let (a, c, p) = (to_f64(a), to_f64(c), to_f64(p));
    (0..4)
        .map(|k| (a[k] + t * (c[k] - a[k]) - p[k]).abs())
        .fold(0.0, f64::max)
}

/// Both depth ranges, for tests that must hold for each.
pub const DEPTHS: [DepthRange; 2] = [DepthRange::ZeroToOne, DepthRange::NegOneToOne];

// ---------------------------------------------------------------------------------------------
// Data files (tests/data/, sources in tests/data/README.md).
// ---------------------------------------------------------------------------------------------

/// Path of a file in `tests/data/`.
pub fn data_file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// JSBSim's Mk-82 flight (`tests/data/jsbsim-mk82.csv`): data no one here made.
pub fn mk82() -> wireflight::data::FlightData {
    let path = data_file("jsbsim-mk82.csv");
    wireflight::data::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}
pub mod cli;
pub mod flights;
pub mod refsim;
pub mod ulog;
