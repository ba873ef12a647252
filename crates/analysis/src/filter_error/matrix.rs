//! Small dense row-major matrices for the filter: the augmented systems here have a few tens
//! of states at most, so plain loops beat a dependency.

/// A dense row-major matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Mat {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Entries, row after row.
    pub data: Vec<f64>,
}

impl Mat {
    /// A `rows` × `cols` matrix of zeros.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![0.0; rows * cols],
        }
    }

    /// The `n` × `n` identity.
    pub fn identity(n: usize) -> Self {
        let mut m = Self::zeros(n, n);
        for i in 0..n {
            m.data[i * n + i] = 1.0;
        }
        m
    }

    /// A matrix from its rows; `None` when the rows differ in length.
    pub fn from_rows(rows: &[&[f64]]) -> Option<Self> {
        let cols = rows.first().map_or(0, |r| r.len());
        if rows.iter().any(|r| r.len() != cols) {
            return None;
        }
        Some(Self {
            rows: rows.len(),
            cols,
            data: rows.iter().flat_map(|r| r.iter().copied()).collect(),
        })
    }

    /// Entry (i, j).
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.data[i * self.cols + j]
    }

    /// Mutable entry (i, j).
    pub fn at_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.data[i * self.cols + j]
    }

    /// The product `self · other` (dimensions are the caller's invariant).
    pub fn mul(&self, other: &Mat) -> Mat {
        let mut out = Mat::zeros(self.rows, other.cols);
        for i in 0..self.rows {
            for k in 0..self.cols {
                let a = self.at(i, k);
                if a == 0.0 {
                    continue;
                }
                for j in 0..other.cols {
                    out.data[i * other.cols + j] += a * other.at(k, j);
                }
            }
        }
        out
    }

    /// The transpose.
    pub fn t(&self) -> Mat {
        let mut out = Mat::zeros(self.cols, self.rows);
        for i in 0..self.rows {
            for j in 0..self.cols {
                out.data[j * self.rows + i] = self.at(i, j);
            }
        }
        out
    }

    /// `self + s · other`.
    pub fn add_scaled(&self, other: &Mat, s: f64) -> Mat {
        Mat {
            rows: self.rows,
            cols: self.cols,
            data: self
                .data
                .iter()
                .zip(&other.data)
                .map(|(a, b)| a + s * b)
                .collect(),
        }
    }

    /// `self · s`.
    pub fn scaled(&self, s: f64) -> Mat {
        Mat {
            rows: self.rows,
            cols: self.cols,
            data: self.data.iter().map(|a| a * s).collect(),
        }
    }

    /// `y = self · x` into a caller's buffer (no allocation in the filter's loop).
    pub fn mul_vec_into(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate().take(self.rows) {
            *yi = self.data[i * self.cols..(i + 1) * self.cols]
                .iter()
                .zip(x)
                .map(|(a, b)| a * b)
                .sum();
        }
    }

    /// Largest absolute entry.
    pub fn max_abs(&self) -> f64 {
        self.data.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// The inverse and log-determinant of a symmetric positive-definite matrix by Cholesky;
    /// `None` when it is not positive definite.
    pub fn spd_inverse_logdet(&self) -> Option<(Mat, f64)> {
        let n = self.rows;
        let mut l = Mat::zeros(n, n);
        for j in 0..n {
            let mut d = self.at(j, j);
            for k in 0..j {
                d -= l.at(j, k) * l.at(j, k);
            }
            if d.is_nan() || d <= 0.0 || !d.is_finite() {
                return None;
            }
            let ljj = d.sqrt();
            *l.at_mut(j, j) = ljj;
            for i in j + 1..n {
                let mut s = self.at(i, j);
                for k in 0..j {
                    s -= l.at(i, k) * l.at(j, k);
                }
                *l.at_mut(i, j) = s / ljj;
            }
        }
        let logdet = 2.0 * (0..n).map(|i| l.at(i, i).ln()).sum::<f64>();
        // Columns of L⁻¹ by forward substitution, then A⁻¹ = L⁻ᵀ L⁻¹.
        let mut linv = Mat::zeros(n, n);
        for c in 0..n {
            for i in c..n {
                let mut s = if i == c { 1.0 } else { 0.0 };
                for k in c..i {
                    s -= l.at(i, k) * linv.at(k, c);
                }
                *linv.at_mut(i, c) = s / l.at(i, i);
            }
        }
        Some((linv.t().mul(&linv), logdet))
    }

    /// The matrix exponential `exp(self)` by scaling and squaring of a Taylor series.
    pub fn expm(&self) -> Mat {
        let norm = self.max_abs() * self.rows as f64;
        let mut squarings = 0;
        let mut scale = 1.0;
        while norm * scale > 0.25 && squarings < 60 {
            scale *= 0.5;
            squarings += 1;
        }
        let a = self.scaled(scale);
        let mut term = Mat::identity(self.rows);
        let mut sum = Mat::identity(self.rows);
        for k in 1..=14 {
            term = term.mul(&a).scaled(1.0 / k as f64);
            sum = sum.add_scaled(&term, 1.0);
        }
        for _ in 0..squarings {
            sum = sum.mul(&sum);
        }
        sum
    }
}
