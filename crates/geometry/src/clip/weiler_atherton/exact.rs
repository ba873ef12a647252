//! Exact arithmetic on the numbers `f64` coordinates generate: a [`Dyadic`] is `m · 2^e`, `m` a
//! signed integer of any size. Every finite `f64` is one, and sums, differences and products
//! of dyadic numbers are dyadic, so a polynomial in the input coordinates (an orientation
//! determinant, a crossing's parameter compared with another's) is evaluated without any
//! rounding, underflow or overflow: its sign is the true sign.
//!
//! It is the slow path of the predicates ([`super::predicates`]): they decide in `f64` with an
//! error bound and come here only when the rounded result is too close to zero to trust. A
//! hand-written magnitude of 64-bit limbs is enough for that (tens of limbs at most: the
//! exponents of `f64` span about 2100 bits, and the predicates multiply at most four such
//! numbers), and keeps the geometry crate's dependencies as they are.

use std::cmp::Ordering;
use std::ops::{Add, Mul, Neg, Sub};

/// An exact number `±magnitude · 2^exp`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Dyadic {
    negative: bool,
    /// The magnitude, little-endian 64-bit limbs, without high zero limbs; empty for zero
    /// (which is never negative).
    limbs: Vec<u64>,
    exp: i64,
}

impl Dyadic {
    /// Zero.
    pub(super) fn zero() -> Dyadic {
        Dyadic {
            negative: false,
            limbs: Vec::new(),
            exp: 0,
        }
    }

    /// The exact value of a finite `f64` (NaN and ∞ have none: callers reject them first; they
    /// read as zero here rather than panic).
    pub(super) fn from_f64(x: f64) -> Dyadic {
        if !x.is_finite() || x == 0.0 {
            return Dyadic::zero();
        }
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i64;
        let fraction = bits & ((1u64 << 52) - 1);
        // Subnormals have no hidden bit and the smallest exponent.
        let (m, e) = if biased == 0 {
            (fraction, -1074)
        } else {
            (fraction | (1u64 << 52), biased - 1075)
        };
        // Trailing zero bits moved into the exponent keep the sums' alignment shifts short.
        let tz = m.trailing_zeros();
        Dyadic {
            negative: x < 0.0,
            limbs: vec![m >> tz],
            exp: e + i64::from(tz),
        }
    }

    /// The sign: `Less` for negative, `Equal` for zero, `Greater` for positive.
    pub(super) fn sign(&self) -> Ordering {
        match (self.limbs.is_empty(), self.negative) {
            (true, _) => Ordering::Equal,
            (false, true) => Ordering::Less,
            (false, false) => Ordering::Greater,
        }
    }

    /// The value as `f · 2^e`, `f` the magnitude's top 64 bits (and a sticky bit for the rest)
    /// rounded to `f64`: within 2⁻⁵³ relative, whatever the exponent, so ratios of numbers far
    /// outside `f64`'s range still come out right. `None` for zero.
    pub(super) fn scaled(&self) -> Option<(f64, i64)> {
        let bits = bit_length(&self.limbs);
        if bits == 0 {
            return None;
        }
        let shift = bits.saturating_sub(64);
        let mut top = bits_at(&self.limbs, shift);
        if shift > 0 && any_below(&self.limbs, shift) {
            top |= 1;
        }
        let f = top as f64;
        // bits ≤ 64 · limbs: far inside i64.
        let e = self.exp + shift as i64;
        Some((if self.negative { -f } else { f }, e))
    }

    /// The nearest `f64` (0 for zero; ±∞ or a subnormal where it is out of range). The
    /// predicates need only signs and [`Dyadic::ratio`]; the tests read values with it.
    #[cfg(test)]
    pub(super) fn to_f64(&self) -> f64 {
        self.scaled().map_or(0.0, |(f, e)| ldexp(f, e))
    }

    /// `a / b` as an `f64`, within a few units in the last place whatever the sizes of `a` and
    /// `b` (0 when `b` is zero: callers divide by nonzero numbers).
    pub(super) fn ratio(a: &Dyadic, b: &Dyadic) -> f64 {
        match (a.scaled(), b.scaled()) {
            (Some((fa, ea)), Some((fb, eb))) => ldexp(fa / fb, ea - eb),
            _ => 0.0,
        }
    }

    fn from_parts(negative: bool, mut limbs: Vec<u64>, exp: i64) -> Dyadic {
        while limbs.last() == Some(&0) {
            limbs.pop();
        }
        if limbs.is_empty() {
            return Dyadic::zero();
        }
        Dyadic {
            negative,
            limbs,
            exp,
        }
    }
}

/// `f · 2^e`, in steps that stay within `f64`'s exponent range (each step is exact until the
/// result leaves the normal range).
fn ldexp(mut f: f64, mut e: i64) -> f64 {
    const STEP: i64 = 1000;
    while e > STEP && f.is_finite() {
        f *= pow2(STEP);
        e -= STEP;
    }
    while e < -STEP && f != 0.0 {
        f *= pow2(-STEP);
        e += STEP;
    }
    f * pow2(e.clamp(-STEP, STEP))
}

/// 2^k for |k| ≤ 1000, exactly (a normal number).
fn pow2(k: i64) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// The number of significant bits of a magnitude.
fn bit_length(limbs: &[u64]) -> u64 {
    match limbs.last() {
        None => 0,
        Some(&top) => 64 * limbs.len() as u64 - u64::from(top.leading_zeros()),
    }
}

/// The 64 bits of a magnitude starting at bit `from`.
fn bits_at(limbs: &[u64], from: u64) -> u64 {
    let (limb, bit) = ((from / 64) as usize, (from % 64) as u32);
    let lo = limbs.get(limb).copied().unwrap_or(0) >> bit;
    let hi = if bit == 0 {
        0
    } else {
        limbs.get(limb + 1).copied().unwrap_or(0) << (64 - bit)
    };
    lo | hi
}

/// Whether any bit below `below` is set.
fn any_below(limbs: &[u64], below: u64) -> bool {
    let (limb, bit) = ((below / 64) as usize, (below % 64) as u32);
    limbs[..limb.min(limbs.len())].iter().any(|&l| l != 0)
        || (bit > 0
            && limbs
                .get(limb)
                .is_some_and(|&l| l & ((1u64 << bit) - 1) != 0))
}

/// A magnitude shifted left by `by` bits.
fn shifted(limbs: &[u64], by: u64) -> Vec<u64> {
    let (whole, bit) = ((by / 64) as usize, (by % 64) as u32);
    let mut out = vec![0u64; whole];
    out.reserve(limbs.len() + 1);
    if bit == 0 {
        out.extend_from_slice(limbs);
    } else {
        let mut carry = 0u64;
        for &l in limbs {
            out.push((l << bit) | carry);
            carry = l >> (64 - bit);
        }
        out.push(carry);
    }
    out
}

fn compare_magnitudes(a: &[u64], b: &[u64]) -> Ordering {
    // Callers pass magnitudes without high zero limbs, except just after a shift: trim.
    let trim = |v: &[u64]| v.len() - v.iter().rev().take_while(|&&l| l == 0).count();
    let (la, lb) = (trim(a), trim(b));
    la.cmp(&lb).then_with(|| {
        for i in (0..la).rev() {
            match a[i].cmp(&b[i]) {
                Ordering::Equal => {}
                other => return other,
            }
        }
        Ordering::Equal
    })
}

fn add_magnitudes(a: &[u64], b: &[u64]) -> Vec<u64> {
    let (long, short) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    let mut out = Vec::with_capacity(long.len() + 1);
    let mut carry = false;
    for (i, &l) in long.iter().enumerate() {
        let (s, c1) = l.overflowing_add(short.get(i).copied().unwrap_or(0));
        let (s, c2) = s.overflowing_add(u64::from(carry));
        out.push(s);
        carry = c1 || c2;
    }
    if carry {
        out.push(1);
    }
    out
}

/// `a − b` for `a ≥ b`.
fn sub_magnitudes(a: &[u64], b: &[u64]) -> Vec<u64> {
    let mut out = Vec::with_capacity(a.len());
    let mut borrow = false;
    for (i, &l) in a.iter().enumerate() {
        let (d, b1) = l.overflowing_sub(b.get(i).copied().unwrap_or(0));
        let (d, b2) = d.overflowing_sub(u64::from(borrow));
        out.push(d);
        borrow = b1 || b2;
    }
    out
}

impl Add for &Dyadic {
    type Output = Dyadic;

    fn add(self, other: &Dyadic) -> Dyadic {
        if other.limbs.is_empty() {
            return self.clone();
        }
        if self.limbs.is_empty() {
            return other.clone();
        }
        // Align to the smaller exponent: the other magnitude moves left, exactly.
        let exp = self.exp.min(other.exp);
        let a = shifted(&self.limbs, (self.exp - exp) as u64);
        let b = shifted(&other.limbs, (other.exp - exp) as u64);
        if self.negative == other.negative {
            return Dyadic::from_parts(self.negative, add_magnitudes(&a, &b), exp);
        }
        match compare_magnitudes(&a, &b) {
            Ordering::Equal => Dyadic::zero(),
            Ordering::Greater => Dyadic::from_parts(self.negative, sub_magnitudes(&a, &b), exp),
            Ordering::Less => Dyadic::from_parts(other.negative, sub_magnitudes(&b, &a), exp),
        }
    }
}

impl Neg for &Dyadic {
    type Output = Dyadic;

    fn neg(self) -> Dyadic {
        Dyadic {
            negative: !self.negative && !self.limbs.is_empty(),
            limbs: self.limbs.clone(),
            exp: self.exp,
        }
    }
}

impl Sub for &Dyadic {
    type Output = Dyadic;

    fn sub(self, other: &Dyadic) -> Dyadic {
        self + &(-other)
    }
}

impl Mul for &Dyadic {
    type Output = Dyadic;

    fn mul(self, other: &Dyadic) -> Dyadic {
        if self.limbs.is_empty() || other.limbs.is_empty() {
            return Dyadic::zero();
        }
        let mut out = vec![0u64; self.limbs.len() + other.limbs.len()];
        for (i, &a) in self.limbs.iter().enumerate() {
            let mut carry = 0u128;
            for (j, &b) in other.limbs.iter().enumerate() {
                let t = u128::from(a) * u128::from(b) + u128::from(out[i + j]) + carry;
                out[i + j] = t as u64;
                carry = t >> 64;
            }
            out[i + other.limbs.len()] = carry as u64;
        }
        Dyadic::from_parts(self.negative != other.negative, out, self.exp + other.exp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(x: f64) -> Dyadic {
        Dyadic::from_f64(x)
    }

    #[test]
    fn round_trips_every_kind_of_double() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.5,
            0.1,
            1e300,
            -1e-300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -2.5e-320,
            7.791398095360777e-20,
        ] {
            assert_eq!(d(x).to_f64(), x + 0.0, "{x}");
        }
    }

    #[test]
    fn sums_and_products_are_exact() {
        // 1e16 + 1 − 1e16 is 0 in f64 and 1 here.
        let big = d(1e16);
        assert_eq!((&(&big + &d(1.0)) - &big).to_f64(), 1.0);
        // Across the whole exponent range: (MAX + 2^-1074) − MAX = 2^-1074.
        let tiny = d(5e-324);
        let r = &(&d(f64::MAX) + &tiny) - &d(f64::MAX);
        assert_eq!(r, tiny);
        // A product that underflows in f64 keeps its sign here.
        let p = &d(1e-200) * &d(-1e-200);
        assert_eq!(p.sign(), Ordering::Less);
        assert_eq!((1e-200f64 * -1e-200f64), -0.0);
        // (2^64 + 1)² = 2^128 + 2^65 + 1: carries across limbs.
        let a = &d(18446744073709551616.0) + &d(1.0);
        let sq = &a * &a;
        let want = &(&(&d(2f64.powi(64)) * &d(2f64.powi(64))) + &d(2f64.powi(65))) + &d(1.0);
        assert_eq!((&sq - &want).sign(), Ordering::Equal);
        assert_eq!((&sq - &(&want + &d(1.0))).sign(), Ordering::Less);
        // Signs of differences.
        assert_eq!((&d(-3.0) - &d(-2.0)).sign(), Ordering::Less);
        assert_eq!((&d(-3.0) + &d(3.0)).sign(), Ordering::Equal);
        assert_eq!((&d(2.0) - &d(-3.0)).to_f64(), 5.0);
    }

    #[test]
    fn rounding_to_f64_is_to_nearest_with_a_sticky_bit() {
        // 2^53 + 1 + 2^-60: just above the tie between 2^53 and 2^53 + 2, rounds up.
        let x = &(&d(2f64.powi(53)) + &d(1.0)) + &d(2f64.powi(-60));
        assert_eq!(x.to_f64(), 2f64.powi(53) + 2.0);
        let tie = &d(2f64.powi(53)) + &d(1.0);
        assert_eq!(tie.to_f64(), 2f64.powi(53), "ties to even");
        // Ratios of numbers outside f64's range.
        let huge = &d(1e300) * &d(1e300);
        let small = &d(1e300) * &d(3e299);
        let r = Dyadic::ratio(&small, &huge);
        assert!((r - 0.3).abs() < 1e-15, "{r}");
        assert_eq!(huge.to_f64(), f64::INFINITY);
    }
}
