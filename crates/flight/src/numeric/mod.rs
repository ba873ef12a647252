//! Small numerical helpers shared by the flight model, the comparison and the diagnosis:
//! dense linear solves and inverses of small systems, correlation, local polynomial fits and
//! the angle between two attitudes. Pure math: no I/O, no allocation beyond the results.

use wireflight_geometry::euler::EulerZyx;

/// A pivot smaller than this times the largest entry of the matrix counts as zero.
const SINGULAR_REL: f64 = 1e-14;

/// Solve `a·x = b` for a square `n×n` matrix stored row-major in `a` (overwritten by its
/// elimination); the solution replaces `b`. Gaussian elimination with partial pivoting.
///
/// Returns `None` when the matrix is singular to working precision (a pivot below 1e-14 of
/// the largest entry), or holds non-finite numbers.
///
/// # Panics
/// When `a.len() != n·n` or `b.len() != n`.
pub fn solve_in_place(a: &mut [f64], b: &mut [f64], n: usize) -> Option<()> {
    assert!(
        a.len() == n * n && b.len() == n,
        "solve: a is not n×n or b not n"
    );
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !scale.is_finite() || b.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let tiny = SINGULAR_REL * scale;
    for col in 0..n {
        let piv =
            (col..n).max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))?;
        // Written so that a NaN pivot counts as singular.
        let pivot = a[piv * n + col].abs();
        if pivot.is_nan() || pivot <= tiny {
            return None;
        }
        if piv != col {
            for k in 0..n {
                a.swap(col * n + k, piv * n + k);
            }
            b.swap(col, piv);
        }
        for row in col + 1..n {
            let f = a[row * n + col] / a[col * n + col];
            if f == 0.0 {
                continue;
            }
            for k in col..n {
                a[row * n + k] -= f * a[col * n + k];
            }
            b[row] -= f * b[col];
        }
    }
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| a[row * n + k] * b[k]).sum();
        b[row] = (b[row] - s) / a[row * n + row];
    }
    b.iter().all(|v| v.is_finite()).then_some(())
}

mod kernels;

pub use kernels::{axpy, dot, gram, mul12, Mat12};

/// Solve `a·x = b` for a fixed-size system (rows of `a`); `None` when singular.
pub fn solve<const N: usize>(a: [[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
    let mut flat: Vec<f64> = a.iter().flatten().copied().collect();
    let mut x = b;
    solve_in_place(&mut flat, &mut x, N)?;
    Some(x)
}

/// Solve `a·x = b` for a system given as rows; `None` when singular or not square.
pub fn solve_rows(a: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    if a.len() != n || a.iter().any(|r| r.len() != n) {
        return None;
    }
    let mut flat: Vec<f64> = a.iter().flatten().copied().collect();
    let mut x = b.to_vec();
    solve_in_place(&mut flat, &mut x, n)?;
    Some(x)
}

/// Inverse of an `n×n` matrix given row-major; `None` when singular.
pub fn invert(a: &[f64], n: usize) -> Option<Vec<f64>> {
    if a.len() != n * n {
        return None;
    }
    let mut inv = vec![0.0; n * n];
    let mut col = vec![0.0; n];
    for j in 0..n {
        let mut work = a.to_vec();
        col.iter_mut()
            .enumerate()
            .for_each(|(i, c)| *c = f64::from(u8::from(i == j)));
        solve_in_place(&mut work, &mut col, n)?;
        for i in 0..n {
            inv[i * n + j] = col[i];
        }
    }
    Some(inv)
}

/// Pearson correlation of paired samples, skipping pairs with a non-finite member.
/// `None` when fewer than three pairs remain or either side does not vary: the statistic has
/// no meaning there (print "n/a", not 0).
pub fn pearson(x: &[f64], y: &[f64]) -> Option<f64> {
    let pairs = || {
        x.iter()
            .zip(y)
            .filter(|(a, b)| a.is_finite() && b.is_finite())
    };
    let n = pairs().count();
    if n < 3 {
        return None;
    }
    let n = n as f64;
    let mx = pairs().map(|p| p.0).sum::<f64>() / n;
    let my = pairs().map(|p| p.1).sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in pairs() {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx).powi(2);
        syy += (b - my).powi(2);
    }
    let r = sxy / (sxx * syy).sqrt();
    (sxx > 0.0 && syy > 0.0 && r.is_finite()).then(|| r.clamp(-1.0, 1.0))
}

/// Least-squares quadratic through `(t_i, y_i)` around `t0`: the fitted value and slope at
/// `t0`. Two points give the line through them, one point its value with zero slope, none
/// (0, 0); a degenerate spread of times falls back to the first value.
pub fn quad_fit(t: &[f64], y: &[f64], t0: f64) -> (f64, f64) {
    let n = t.len().min(y.len());
    if n == 0 {
        return (0.0, 0.0);
    }
    if n < 3 {
        let slope = if n == 2 && t[1] != t[0] {
            (y[1] - y[0]) / (t[1] - t[0])
        } else {
            0.0
        };
        return (y[0] + slope * (t0 - t[0]), slope);
    }
    // Normal equations in s = t − t0 for y = a + b s + c s².
    let mut m = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for (&ti, &yi) in t.iter().zip(y) {
        let s = ti - t0;
        let basis = [1.0, s, s * s];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += basis[i] * basis[j];
            }
            r[i] += basis[i] * yi;
        }
    }
    match solve(m, r) {
        Some([a, b, _]) => (a, b),
        None => (y[0], 0.0),
    }
}

/// atan2(y, x), by its series where |y| ≤ x/8 (an angle of attack, a sideslip and a
/// residual's angle mostly are): z − z³/3 + … + z¹⁷/17 with z = y/x, whose next term is below
/// 10⁻¹⁷·|z| there; the library's `atan2` elsewhere. A division and a polynomial evaluated by
/// Estrin's scheme (powers of z² side by side, not one long chain of multiply-adds): in the
/// model's derivative, α's atan2 lies on the path from the state to the lift, and the
/// library's function saves and restores the rounding mode at every call.
#[inline]
pub fn small_atan2(y: f64, x: f64) -> f64 {
    if !(x > 0.0 && y.abs() <= 0.125 * x) {
        return y.atan2(x);
    }
    const C: [f64; 9] = [
        1.0,
        -1.0 / 3.0,
        1.0 / 5.0,
        -1.0 / 7.0,
        1.0 / 9.0,
        -1.0 / 11.0,
        1.0 / 13.0,
        -1.0 / 15.0,
        1.0 / 17.0,
    ];
    let z = y / x;
    let s = z * z;
    let (s2, s4) = (s * s, s * s * (s * s));
    let p01 = C[0] + C[1] * s;
    let p23 = C[2] + C[3] * s;
    let p45 = C[4] + C[5] * s;
    let p67 = C[6] + C[7] * s;
    let p47 = p45 + p67 * s2 + C[8] * s4;
    z * ((p01 + p23 * s2) + p47 * s4)
}

/// The angle between two attitudes, degrees: the rotation angle of R_aᵀ·R_b. It does not
/// depend on how either is split into angles, so it has no trouble at gimbal lock or ±180°.
pub fn attitude_error_deg(a: &EulerZyx, b: &EulerZyx) -> f64 {
    let r = a.to_matrix().transpose() * b.to_matrix();
    let c = ((r.x_axis.x + r.y_axis.y + r.z_axis.z - 1.0) / 2.0).clamp(-1.0, 1.0);
    c.acos().to_degrees()
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms: ~15 digits).
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1−x) = π / sin(πx).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).abs().ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised lower incomplete gamma function P(a, x) = γ(a, x)/Γ(a), a > 0, x ≥ 0: the
/// series below a + 1, Lentz's continued fraction above (Numerical Recipes §6.2).
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if a.is_nan() || a <= 0.0 || x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 0.0;
    }
    let front = (a * x.ln() - x - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (sum * front).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (1.0 - front * h).clamp(0.0, 1.0)
    }
}

/// The χ² distribution's quantile: the x with P(χ²_dof ≤ x) = `p` (0 < p < 1, dof > 0), by
/// bisection on [`gamma_p`] to a relative 1e-12. NaN outside the domain.
pub fn chi2_quantile(p: f64, dof: f64) -> f64 {
    if !(p > 0.0 && p < 1.0 && dof > 0.0 && dof.is_finite()) {
        return f64::NAN;
    }
    let cdf = |x: f64| gamma_p(0.5 * dof, 0.5 * x);
    let mut hi = dof.max(1.0);
    while cdf(hi) < p {
        hi *= 2.0;
        if !hi.is_finite() {
            return f64::NAN;
        }
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if cdf(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series atan2 is the library's to a few units in the last place where it is used,
    /// and the library's elsewhere.
    #[test]
    fn small_atan2_is_atan2() {
        for i in -1000..=1000 {
            for x in [1e-300, 1e-8, 0.3, 1.0, 7.0, 1e8] {
                let y = x * (i as f64) * 2e-4;
                let (got, want) = (small_atan2(y, x), y.atan2(x));
                assert!(
                    (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                    "atan2({y}, {x}): {got} vs {want}"
                );
            }
        }
        for (y, x) in [
            (1.0, -1.0),
            (-0.1, -1.0),
            (0.0, -1.0),
            (1.0, 0.0),
            (0.5, 1.0),
        ] {
            assert_eq!(small_atan2(y, x), f64::atan2(y, x));
        }
    }

    /// The four-lane dot product and the Gram matrix are the plain sums, for every length
    /// remainder.
    #[test]
    fn dot_and_gram_are_the_plain_sums() {
        for n in [0, 1, 3, 4, 5, 11, 400] {
            let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos() - 0.2).collect();
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert!((dot(&a, &b) - plain).abs() < 1e-12, "{n}");
        }
        let cols: Vec<f64> = (0..3 * 7).map(|i| (i as f64).sqrt() - 2.0).collect();
        let g = gram(&cols, 3, 7);
        for i in 0..3 {
            for k in 0..3 {
                let plain: f64 = (0..7).map(|r| cols[i * 7 + r] * cols[k * 7 + r]).sum();
                assert!((g[i * 3 + k] - plain).abs() < 1e-12);
            }
        }
        assert_eq!(
            gram(&cols, 3, 6),
            vec![0.0; 9],
            "wrong size: zeros, no panic"
        );
    }

    #[test]
    fn solves_a_pivoting_system_and_refuses_a_singular_one() {
        // The first pivot is zero: only partial pivoting solves it.
        let x = solve(
            [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [2.0, 0.0, 3.0]],
            [7.0, 3.0, 11.0],
        );
        let x = x.expect("regular");
        for (got, want) in x.iter().zip([1.0, 2.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{x:?}");
        }
        assert!(solve([[1.0, 2.0], [2.0, 4.0]], [1.0, 2.0]).is_none());
        assert!(solve([[f64::NAN, 0.0], [0.0, 1.0]], [1.0, 2.0]).is_none());
        // Scale does not matter: a well-conditioned tiny matrix is regular.
        assert!(solve([[1e-20, 0.0], [0.0, 2e-20]], [1.0, 1.0]).is_some());
    }

    #[test]
    fn inverse_times_matrix_is_identity() {
        let a = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0];
        let inv = invert(&a, 3).expect("regular");
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..3).map(|k| a[i * 3 + k] * inv[k * 3 + j]).sum();
                assert!(
                    (s - f64::from(u8::from(i == j))).abs() < 1e-12,
                    "{i},{j}: {s}"
                );
            }
        }
    }

    #[test]
    fn pearson_of_lines_and_of_nothing() {
        let x = [1.0, 2.0, 3.0, 4.0];
        assert!((pearson(&x, &[2.0, 4.0, 6.0, 8.0]).unwrap() - 1.0).abs() < 1e-12);
        assert!((pearson(&x, &[8.0, 6.0, 4.0, 2.0]).unwrap() + 1.0).abs() < 1e-12);
        assert_eq!(pearson(&x, &[1.0, 1.0, 1.0, 1.0]), None, "no variation");
        assert_eq!(pearson(&x[..2], &[1.0, 2.0]), None, "two points");
        assert_eq!(
            pearson(&x, &[1.0, f64::NAN, 3.0, 4.0]),
            Some(1.0),
            "NaN pair skipped"
        );
    }

    #[test]
    fn quadratic_fit_is_exact_on_a_parabola() {
        let t: Vec<f64> = (0..10).map(|i| 0.1 * f64::from(i)).collect();
        let y: Vec<f64> = t.iter().map(|s| 1.0 + 2.0 * s - 3.0 * s * s).collect();
        let (v, d) = quad_fit(&t, &y, 0.0);
        assert!(
            (v - 1.0).abs() < 1e-12 && (d - 2.0).abs() < 1e-11,
            "{v} {d}"
        );
    }

    #[test]
    fn chi2_quantiles_match_the_tables() {
        // (p, dof, table value): the 1% and 5% upper points used by the diagnosis and more.
        for (p, dof, want) in [
            (0.99, 1.0, 6.635),
            (0.99, 2.0, 9.210),
            (0.99, 4.0, 13.277),
            (0.95, 1.0, 3.841),
            (0.95, 3.0, 7.815),
            (0.99, 10.0, 23.209),
            (0.99, 30.0, 50.892),
            (0.5, 2.0, 1.386),
        ] {
            let got = chi2_quantile(p, dof);
            assert!(
                (got - want).abs() < 1e-3,
                "p {p}, dof {dof}: {got} vs {want}"
            );
        }
        assert!(chi2_quantile(1.0, 3.0).is_nan());
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-12);
    }

    #[test]
    fn attitude_error_ignores_the_angle_split() {
        let a = EulerZyx::new(0.3, std::f64::consts::FRAC_PI_2, 0.1);
        let b = EulerZyx::new(0.5, std::f64::consts::FRAC_PI_2, 0.3); // same attitude at lock
        assert!(attitude_error_deg(&a, &b) < 1e-6);
        let c = EulerZyx::new(0.0, 0.0, 10f64.to_radians());
        assert!((attitude_error_deg(&EulerZyx::default(), &c) - 10.0).abs() < 1e-9);
    }
}
