//! The few loops the start fits spend their linear algebra in — dot products and `y += a·x`
//! over columns ten thousand rows long, the Gram matrix of a start Jacobian, and the 12×12
//! products of the tangent-linear flight — with an AVX2 + FMA path chosen at run time.
//!
//! The portable build targets baseline x86-64 (SSE2: two doubles per instruction, no fused
//! multiply-add), which leaves these loops at half or less of what a CPU with AVX2 does
//! (measured here: the Gram matrix of a start Jacobian 170 → 82 µs, a 12×12 product 208 →
//! 74 ns). Each kernel checks once per call whether the CPU has AVX2 and FMA
//! (`is_x86_feature_detected!` caches the answer) and runs a version compiled for them;
//! elsewhere, and on other architectures, the portable loop. The two differ only in rounding
//! (a fused multiply-add rounds once), well inside every tolerance that uses them.

#[cfg(target_arch = "x86_64")]
fn has_avx2_fma() -> bool {
    std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
}

/// Dot product over the shorter length.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    #[cfg(target_arch = "x86_64")]
    if has_avx2_fma() {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { avx::dot(a, b) };
    }
    portable::dot(a, b)
}

/// `y += alpha·x` over the shorter length.
pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &mut y[..n]);
    #[cfg(target_arch = "x86_64")]
    if has_avx2_fma() {
        // SAFETY: as in `dot`.
        unsafe { avx::axpy(alpha, x, y) };
        return;
    }
    y.iter_mut().zip(x).for_each(|(y, x)| *y += alpha * x);
}

/// Rows of a column-major matrix [`gram`] takes at a time: a block of all its columns (12 ×
/// 256 × 8 bytes = 24 KiB) stays in the first-level cache while every pair of columns is
/// multiplied over it, instead of each pair streaming two whole columns from further out.
const GRAM_BLOCK: usize = 256;

/// The Gram matrix AᵀA (row-major, `cols`×`cols`) of a column-major matrix of `cols` columns
/// of `rows` rows each; zero when the sizes do not match.
pub fn gram(a: &[f64], cols: usize, rows: usize) -> Vec<f64> {
    let mut g = vec![0.0; cols * cols];
    if a.len() != cols * rows {
        return g;
    }
    let mut start = 0;
    while start < rows {
        let end = (start + GRAM_BLOCK).min(rows);
        let col = |i: usize| &a[i * rows + start..i * rows + end];
        for i in 0..cols {
            let mut k = i;
            while k < cols {
                let take = (cols - k).min(4);
                let mut ys: [&[f64]; 4] = [&[]; 4];
                for (j, y) in ys.iter_mut().enumerate().take(take) {
                    *y = col(k + j);
                }
                let sums = dot4(col(i), &ys[..take]);
                for (j, s) in sums.iter().enumerate().take(take) {
                    g[i * cols + k + j] += s;
                }
                k += take;
            }
        }
        start = end;
    }
    for i in 0..cols {
        for k in 0..i {
            g[i * cols + k] = g[k * cols + i];
        }
    }
    g
}

/// The dot products of `x` with up to four slices of its length, reading `x` once.
fn dot4(x: &[f64], ys: &[&[f64]]) -> [f64; 4] {
    #[cfg(target_arch = "x86_64")]
    if has_avx2_fma() && ys.len() == 4 && ys.iter().all(|y| y.len() == x.len()) {
        // SAFETY: as in `dot`; every slice has x's length.
        return unsafe { avx::dot4(x, [ys[0], ys[1], ys[2], ys[3]]) };
    }
    let mut out = [0.0; 4];
    for (o, y) in out.iter_mut().zip(ys) {
        *o = dot(x, y);
    }
    out
}

/// A 12×12 matrix, row-major (the tangent-linear flight's error state of a fixed wing).
pub type Mat12 = [[f64; 12]; 12];

/// a·b over the first `n` rows and columns of `a` (all twelve columns of `b`), for `a` whose
/// first `skip` columns are zero (`unit`: unit vectors instead, so that row r < `skip` of the
/// product starts as b's row r). Rows of the product at and past `n` are zero.
pub fn mul12(a: &Mat12, b: &Mat12, n: usize, skip: usize, unit: bool, out: &mut Mat12) {
    #[cfg(target_arch = "x86_64")]
    if n == 12 && has_avx2_fma() {
        // SAFETY: as in `dot`.
        unsafe { avx::mul12(a, b, skip, unit, out) };
        return;
    }
    portable::mul12(a, b, n, skip, unit, out);
}

mod portable {
    use super::Mat12;

    /// Summed in four independent lanes: a single running sum is a chain of dependent
    /// additions the compiler may not reorder.
    pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
        let mut lanes = [0.0; 4];
        let mut ca = a.chunks_exact(4);
        let mut cb = b.chunks_exact(4);
        for (x, y) in (&mut ca).zip(&mut cb) {
            for k in 0..4 {
                lanes[k] += x[k] * y[k];
            }
        }
        let tail: f64 = ca
            .remainder()
            .iter()
            .zip(cb.remainder())
            .map(|(x, y)| x * y)
            .sum();
        (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
    }

    /// Each row of the product is summed in a local array the compiler keeps in registers.
    pub(super) fn mul12(a: &Mat12, b: &Mat12, n: usize, skip: usize, unit: bool, out: &mut Mat12) {
        for (r, (out_r, a_r)) in out.iter_mut().zip(a).enumerate() {
            if r >= n {
                *out_r = [0.0; 12];
                continue;
            }
            let mut acc = if unit && r < skip { b[r] } else { [0.0; 12] };
            for (&a_rk, b_k) in a_r.iter().zip(b).take(n).skip(skip) {
                for (s, &bv) in acc.iter_mut().zip(b_k) {
                    *s += a_rk * bv;
                }
            }
            *out_r = acc;
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;

    use super::Mat12;

    /// The four lanes of a register, summed.
    #[target_feature(enable = "avx2,fma")]
    fn sum(v: __m256d) -> f64 {
        let pair = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd::<1>(v));
        _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)))
    }

    /// Four running sums of four lanes each: enough independent chains to keep both FMA
    /// units busy through their latency.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn dot(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len().min(b.len());
        let (pa, pb) = (a.as_ptr(), b.as_ptr());
        let mut acc = [_mm256_setzero_pd(); 4];
        let mut i = 0;
        while i + 16 <= n {
            for (k, s) in acc.iter_mut().enumerate() {
                // SAFETY: i + 4k + 4 ≤ n for both slices.
                let (x, y) = unsafe {
                    (
                        _mm256_loadu_pd(pa.add(i + 4 * k)),
                        _mm256_loadu_pd(pb.add(i + 4 * k)),
                    )
                };
                *s = _mm256_fmadd_pd(x, y, *s);
            }
            i += 16;
        }
        while i + 4 <= n {
            // SAFETY: i + 4 ≤ n.
            let (x, y) = unsafe { (_mm256_loadu_pd(pa.add(i)), _mm256_loadu_pd(pb.add(i))) };
            acc[0] = _mm256_fmadd_pd(x, y, acc[0]);
            i += 4;
        }
        let mut s = sum(_mm256_add_pd(
            _mm256_add_pd(acc[0], acc[1]),
            _mm256_add_pd(acc[2], acc[3]),
        ));
        for k in i..n {
            s = a[k].mul_add(b[k], s);
        }
        s
    }

    /// x·y₀ … x·y₃, x read once per four products.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn dot4(x: &[f64], ys: [&[f64]; 4]) -> [f64; 4] {
        let n = x.len();
        let px = x.as_ptr();
        let py = ys.map(|y| y.as_ptr());
        let mut acc = [_mm256_setzero_pd(); 4];
        let mut i = 0;
        while i + 4 <= n {
            // SAFETY: every slice has n ≥ i + 4 elements (the caller checked the lengths).
            unsafe {
                let v = _mm256_loadu_pd(px.add(i));
                for (s, p) in acc.iter_mut().zip(py) {
                    *s = _mm256_fmadd_pd(v, _mm256_loadu_pd(p.add(i)), *s);
                }
            }
            i += 4;
        }
        let mut out = [0.0; 4];
        for (k, o) in out.iter_mut().enumerate() {
            let mut s = sum(acc[k]);
            for j in i..n {
                s = x[j].mul_add(ys[k][j], s);
            }
            *o = s;
        }
        out
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
        let n = x.len().min(y.len());
        let a = _mm256_set1_pd(alpha);
        let (px, py) = (x.as_ptr(), y.as_mut_ptr());
        let mut i = 0;
        while i + 4 <= n {
            // SAFETY: i + 4 ≤ n for both slices.
            unsafe {
                let v = _mm256_fmadd_pd(a, _mm256_loadu_pd(px.add(i)), _mm256_loadu_pd(py.add(i)));
                _mm256_storeu_pd(py.add(i), v);
            }
            i += 4;
        }
        for k in i..n {
            y[k] = alpha.mul_add(x[k], y[k]);
        }
    }

    /// Two rows of the product at a time: each row of b is loaded once for both, and their
    /// six running sums fill the FMA units.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn mul12(a: &Mat12, b: &Mat12, skip: usize, unit: bool, out: &mut Mat12) {
        let load = |row: &[f64; 12]| -> [__m256d; 3] {
            let p = row.as_ptr();
            // SAFETY: a row has 12 elements: offsets 0, 4 and 8 leave four each.
            unsafe {
                [
                    _mm256_loadu_pd(p),
                    _mm256_loadu_pd(p.add(4)),
                    _mm256_loadu_pd(p.add(8)),
                ]
            }
        };
        let start = |r: usize| -> [__m256d; 3] {
            if unit && r < skip {
                load(&b[r])
            } else {
                [_mm256_setzero_pd(); 3]
            }
        };
        for r in (0..12).step_by(2) {
            let mut s0 = start(r);
            let mut s1 = start(r + 1);
            for k in skip..12 {
                let bk = load(&b[k]);
                let (x0, x1) = (_mm256_set1_pd(a[r][k]), _mm256_set1_pd(a[r + 1][k]));
                for c in 0..3 {
                    s0[c] = _mm256_fmadd_pd(x0, bk[c], s0[c]);
                    s1[c] = _mm256_fmadd_pd(x1, bk[c], s1[c]);
                }
            }
            for (row, s) in [(r, s0), (r + 1, s1)] {
                let p = out[row].as_mut_ptr();
                // SAFETY: as in `load`.
                unsafe {
                    _mm256_storeu_pd(p, s[0]);
                    _mm256_storeu_pd(p.add(4), s[1]);
                    _mm256_storeu_pd(p.add(8), s[2]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbers(n: usize, seed: usize) -> Vec<f64> {
        (0..n)
            .map(|i| (((i * 7919 + seed * 104_729) % 1000) as f64 - 500.0) / 97.0)
            .collect()
    }

    /// Every kernel, whichever path this CPU takes, agrees with the plain sums to rounding, on
    /// lengths with and without remainders.
    #[test]
    fn kernels_agree_with_plain_sums() {
        for n in [0, 1, 3, 4, 15, 16, 17, 33, 257, 600] {
            let (a, b) = (numbers(n, 1), numbers(n, 2));
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let scale: f64 = a.iter().zip(&b).map(|(x, y)| (x * y).abs()).sum::<f64>() + 1.0;
            assert!((dot(&a, &b) - plain).abs() < 1e-13 * scale, "dot, n {n}");
            assert!((portable::dot(&a, &b) - plain).abs() < 1e-13 * scale);
            let mut y = b.clone();
            axpy(-0.7, &a, &mut y);
            for k in 0..n {
                assert!((y[k] - (b[k] - 0.7 * a[k])).abs() < 1e-13 * (1.0 + b[k].abs()));
            }
        }
        for (cols, rows) in [(12, 600), (5, 3), (12, 257), (1, 9), (4, 0)] {
            let a = numbers(cols * rows, 3);
            let g = gram(&a, cols, rows);
            for i in 0..cols {
                for k in 0..cols {
                    let ci = &a[i * rows..(i + 1) * rows];
                    let ck = &a[k * rows..(k + 1) * rows];
                    let plain: f64 = ci.iter().zip(ck).map(|(x, y)| x * y).sum();
                    let scale: f64 = ci.iter().zip(ck).map(|(x, y)| (x * y).abs()).sum();
                    let got = g[i * cols + k];
                    assert!(
                        (got - plain).abs() <= 1e-13 * scale,
                        "gram {cols}×{rows} ({i}, {k})"
                    );
                }
            }
        }
        assert_eq!(
            gram(&[1.0; 5], 2, 3),
            vec![0.0; 4],
            "sizes that do not match"
        );
    }

    /// The 12×12 product, both paths, with leading zero and unit columns and a smaller n.
    #[test]
    fn mul12_is_the_matrix_product() {
        let v = numbers(144, 4);
        let w = numbers(144, 5);
        let mut a: Mat12 = [[0.0; 12]; 12];
        let mut b: Mat12 = [[0.0; 12]; 12];
        for r in 0..12 {
            for c in 0..12 {
                a[r][c] = v[r * 12 + c];
                b[r][c] = w[r * 12 + c];
            }
        }
        for (n, skip, unit) in [
            (12, 0, false),
            (12, 3, false),
            (12, 3, true),
            (6, 3, true),
            (6, 0, false),
        ] {
            let mut full = a;
            for (r, row) in full.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate().take(skip) {
                    *x = if unit && r == c { 1.0 } else { 0.0 };
                }
            }
            let mut fast = [[f64::NAN; 12]; 12];
            let mut slow = [[f64::NAN; 12]; 12];
            mul12(&full, &b, n, skip, unit, &mut fast);
            portable::mul12(&full, &b, n, skip, unit, &mut slow);
            for r in 0..12 {
                for c in 0..12 {
                    let want: f64 = if r < n {
                        (0..n).map(|k| full[r][k] * b[k][c]).sum()
                    } else {
                        0.0
                    };
                    for got in [fast[r][c], slow[r][c]] {
                        assert!(
                            (got - want).abs() < 1e-12,
                            "n {n} skip {skip} unit {unit} ({r}, {c}): {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}
