//! The model linearised about its own trajectory: how a small change of the state grows or
//! decays along a flight (tangent-linear equations). The comparison uses it for the
//! sensitivity of a flown window to its start state — one flight instead of one per start
//! parameter.
//!
//! **Error state** e, a change of the state in coordinates where every direction is free:
//!
//! | index | point mass | fixed wing |
//! |---|---|---|
//! | 0..3 | δp, NED, m | δp, NED, m |
//! | 3..6 | δv, NED, m/s | δv, body u, v, w, m/s |
//! | 6..9 | — | δθ, a small rotation in body axes: R' = R·(I + \[δθ\]×), rad |
//! | 9..12 | — | δω, body rates, rad/s |
//!
//! (the quaternion's four numbers have three degrees of freedom; surface positions are not
//! in it: they follow from the commands alone.)
//!
//! **Its equations** ė = A(t)·e. The kinematic rows are exact: δṗ = R(δv + δθ × v) for a
//! fixed wing (δv for a point mass), δθ̇ = δω − ω × δθ. The rows of the forces and moments
//! (δv̇, δω̇) are forward differences of [`Model::derivative`] along each error direction, so
//! every effect, the user's included, is linearised without code of its own.
//!
//! **Propagation** over a step of length h: e(t + h) = exp(h·A)·e(t) with A held over the
//! step ([`transition`], [`propagate`]; the caller chooses where A is taken), exp by its
//! Taylor series to 4th order (the order of the RK4 step that flies the trajectory itself).

use glam::{DMat3, DQuat, DVec3};

use super::model::{Model, State, Vehicle};
use crate::numeric::{mul12, Mat12};
use wireflight_data::{Controls, G0};

/// Largest error-state dimension (a fixed wing).
pub const ERROR_MAX: usize = 12;

/// A square matrix over the error state (row-major; a point mass uses the top-left 6×6): the
/// 12×12 matrix the products of [`crate::numeric::mul12`] work on.
pub type ErrorMatrix = Mat12;

/// Forward-difference steps of the force rows, per error block: position m (the
/// environment changes over tens of metres), velocity m/s, rotation rad, rates rad/s.
const STEPS: [f64; 4] = [1e-2, 1e-5, 1e-7, 1e-7];

/// The skew matrix \[a\]×, with \[a\]×·b = a × b.
pub fn skew(a: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, a.z, -a.y),
        DVec3::new(-a.z, 0.0, a.x),
        DVec3::new(a.y, -a.x, 0.0),
    )
}

impl Model {
    /// Dimension of the error state (12 for a fixed wing, 6 for a point mass).
    pub fn error_dim(&self) -> usize {
        match self.vehicle {
            Vehicle::PointMass => 6,
            Vehicle::FixedWing(_) => 12,
        }
    }

    /// The state `x` moved by the error `e` (module docs; `e` shorter than the error state
    /// leaves the rest unchanged).
    pub fn perturbed(&self, x: &State, e: &[f64]) -> State {
        let at = |k: usize| e.get(k).copied().unwrap_or(0.0);
        let v3 = |k: usize| DVec3::new(at(k), at(k + 1), at(k + 2));
        let mut out = *x;
        out.set_pos_ned(x.pos_ned() + v3(0));
        out.set_vel(x.vel() + v3(3));
        if matches!(self.vehicle, Vehicle::FixedWing(_)) {
            // Only a rotation turns the quaternion: renormalising an unturned one would add
            // rounding to every other column's difference.
            let turn = v3(6);
            if turn != DVec3::ZERO {
                let q = (x.quat() * DQuat::from_scaled_axis(turn)).normalize();
                out.0[6..10].copy_from_slice(&q.to_array());
            }
            out.set_omega(x.omega() + v3(9));
        }
        out
    }

    /// The error-state Jacobian A = ∂ė/∂e at time `t`, state `x`, commands `cmd` (module
    /// docs).
    pub fn error_jacobian(&self, t: f64, x: &State, cmd: &Controls) -> ErrorMatrix {
        let n = self.error_dim();
        let mut a = [[0.0; ERROR_MAX]; ERROR_MAX];
        let frame = self.frame(t, x);
        let f0 = self.derivative_in(t, x, cmd, &frame);
        // Rows of the forces: the velocity block's state slots, and for a fixed wing the
        // rates' (state 10..13 → error 9..12).
        let force_rows: &[(usize, usize)] = match self.vehicle {
            Vehicle::PointMass => &[(3, 3), (4, 4), (5, 5)],
            Vehicle::FixedWing(_) => &[(3, 3), (4, 4), (5, 5), (9, 10), (10, 11), (11, 12)],
        };
        let mut e = [0.0; ERROR_MAX];
        // Equations that do not depend on the position (uniform air, constant gravity: the
        // bare airframe, and effects such as a steady wind) have those columns zero, not
        // worth three evaluations.
        let first = if self.varies_in_space() { 0 } else { 3 };
        // Nor does anything but gravity turn with the body: R' = R·(I + [δθ]×) makes the
        // body's gravity Rᵀg + Rᵀg × δθ, so the forces' rotation columns are [Rᵀg]× and the
        // moments' zero — three more evaluations saved. (Not in moving air: turning the body
        // turns the air-relative velocity.)
        let bare = self.effects.is_empty()
            && self.air_offset() == DVec3::ZERO
            && matches!(self.vehicle, Vehicle::FixedWing(_));
        for j in first..n {
            if bare && (6..9).contains(&j) {
                continue;
            }
            let h = STEPS[j / 3];
            e[j] = h;
            let moved = self.perturbed(x, &e[..n]);
            // A change of the body rates leaves the frame (environment, air data, stall
            // blend) as it was: only what the rates change is evaluated again.
            let f = if j >= 9 {
                self.derivative_in(t, &moved, cmd, &frame)
            } else {
                self.derivative(t, &moved, cmd)
            };
            e[j] = 0.0;
            for &(row, slot) in force_rows {
                a[row][j] = (f.0[slot] - f0.0[slot]) / h;
            }
        }
        match self.vehicle {
            Vehicle::PointMass => {
                for k in 0..3 {
                    a[k][3 + k] = 1.0;
                }
            }
            Vehicle::FixedWing(_) => {
                let rot = x.rot();
                // δṗ = R·δv − R·[v]×·δθ
                let r_v = rot * -skew(x.vel());
                // δθ̇ = −[ω]×·δθ + δω
                let w = -skew(x.omega());
                let turn = skew(rot.transpose() * DVec3::new(0.0, 0.0, G0));
                for r in 0..3 {
                    for c in 0..3 {
                        a[r][3 + c] = rot.col(c)[r];
                        a[r][6 + c] = r_v.col(c)[r];
                        a[6 + r][6 + c] = w.col(c)[r];
                        if bare {
                            a[3 + r][6 + c] = turn.col(c)[r];
                        }
                    }
                    a[6 + r][9 + r] = 1.0;
                }
            }
        }
        a
    }
}

impl Model {
    /// ∂f/∂e, the specific force's ([`Model::specific_force`]) change per error-state
    /// component at time `t`, state `x`, commands `cmd`: 3 rows of `error_dim` columns, by
    /// forward differences like the force rows of [`Model::error_jacobian`]. Its position
    /// columns are zero where nothing depends on the position, and so are its rotation
    /// columns on the bare airframe (only gravity turns with the body, and the specific force
    /// leaves gravity out).
    pub fn specific_force_jacobian(
        &self,
        t: f64,
        x: &State,
        cmd: &Controls,
    ) -> [[f64; ERROR_MAX]; 3] {
        let n = self.error_dim();
        let mut out = [[0.0; ERROR_MAX]; 3];
        let f0 = self.specific_force(t, x, cmd);
        let first = if self.varies_in_space() { 0 } else { 3 };
        let bare = self.effects.iter().all(|e| e.is_measurement())
            && self.air_offset() == DVec3::ZERO
            && matches!(self.vehicle, Vehicle::FixedWing(_));
        let mut e = [0.0; ERROR_MAX];
        for j in first..n {
            if bare && (6..9).contains(&j) {
                continue;
            }
            let h = STEPS[j / 3];
            e[j] = h;
            let f = self.specific_force(t, &self.perturbed(x, &e[..n]), cmd);
            e[j] = 0.0;
            for (r, row) in out.iter_mut().enumerate() {
                row[j] = (f[r] - f0[r]) / h;
            }
        }
        out
    }
}

/// How many leading columns of `a` (the position block at most) are zero: the equations do
/// not depend on those error components, and products may skip them.
pub fn free_columns(a: &ErrorMatrix, n: usize) -> usize {
    let zero = |c: usize| a.iter().take(n).all(|row| row[c] == 0.0);
    (0..3.min(n)).take_while(|&c| zero(c)).count()
}

/// exp(h·a) over the first `n` rows and columns, into `phi`, by its Taylor series to 4th order,
/// grouped as Paterson and Stockmeyer do so that it takes two matrix products instead of
/// three: I + ha + (ha)²·(I/2 + ha/6 + (ha)²/24). `free`: leading columns of `a` that are
/// zero ([`free_columns`]); they are zero in (ha)² too.
pub fn transition(a: &ErrorMatrix, n: usize, h: f64, free: usize, phi: &mut ErrorMatrix) {
    let mut a2 = [[0.0; ERROR_MAX]; ERROR_MAX];
    mul12(a, a, n, free, false, &mut a2);
    let (c2, c3, c4) = (h * h, h * h * h / 6.0, h * h * h * h / 24.0);
    // I/2 + ha/6 + (ha)²/24, times h²: the factor the square multiplies. Whole matrices
    // elementwise (outside the first n rows and columns a and a² are zero), so the loops
    // vectorise.
    let mut tail = [[0.0; ERROR_MAX]; ERROR_MAX];
    for ((t, &x), &x2) in tail
        .as_flattened_mut()
        .iter_mut()
        .zip(a.as_flattened())
        .zip(a2.as_flattened())
    {
        *t = c3 * x + c4 * x2;
    }
    for (r, row) in tail.iter_mut().enumerate().take(n) {
        row[r] += 0.5 * c2;
    }
    mul12(&a2, &tail, n, free, false, phi);
    for (p, &x) in phi.as_flattened_mut().iter_mut().zip(a.as_flattened()) {
        *p += h * x;
    }
    for (r, row) in phi.iter_mut().enumerate().take(n) {
        row[r] += 1.0;
    }
}

/// The columns of `from` carried over a step with transition matrix `phi` into `to`: phi·from.
/// `free`: leading columns of the step's Jacobian that are zero, so that the same columns of
/// `phi` are unit vectors. (Into another matrix, not in place: the tangent alternates two,
/// where returning the product would copy it at every step.)
pub fn propagate(
    phi: &ErrorMatrix,
    n: usize,
    from: &ErrorMatrix,
    to: &mut ErrorMatrix,
    free: usize,
) {
    mul12(phi, from, n, free, true, to);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain sum I + ha + (ha)²/2 + (ha)³/6 + (ha)⁴/24 over the first `n` rows/columns.
    fn taylor4(a: &ErrorMatrix, n: usize, h: f64) -> ErrorMatrix {
        let mut out = [[0.0; ERROR_MAX]; ERROR_MAX];
        let mut term = [[0.0; ERROR_MAX]; ERROR_MAX];
        for k in 0..n {
            out[k][k] = 1.0;
            term[k][k] = 1.0;
        }
        for order in 1..=4 {
            let mut next = [[0.0; ERROR_MAX]; ERROR_MAX];
            for r in 0..n {
                for c in 0..n {
                    next[r][c] =
                        (0..n).map(|k| term[r][k] * a[k][c]).sum::<f64>() * h / order as f64;
                }
            }
            term = next;
            for r in 0..n {
                for c in 0..n {
                    out[r][c] += term[r][c];
                }
            }
        }
        out
    }

    /// The grouped transition is the 4th-order Taylor polynomial of exp(h·a), with and
    /// without leading zero columns, and as close to the exponential as that order allows.
    #[test]
    fn transition_is_the_fourth_order_taylor_polynomial() {
        let n = ERROR_MAX;
        let mut a = [[0.0; ERROR_MAX]; ERROR_MAX];
        for (r, row) in a.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate().skip(3) {
                *v = ((r * 7 + c * 3) % 11) as f64 * 0.9 - 4.0;
            }
        }
        let h = 0.02;
        for free in [free_columns(&a, n), 0] {
            assert_eq!(free_columns(&a, n), 3);
            let mut got = [[0.0; ERROR_MAX]; ERROR_MAX];
            transition(&a, n, h, free, &mut got);
            let want = taylor4(&a, n, h);
            for r in 0..n {
                for c in 0..n {
                    assert!(
                        (got[r][c] - want[r][c]).abs() < 1e-13,
                        "free {free}, ({r}, {c}): {} vs {}",
                        got[r][c],
                        want[r][c]
                    );
                }
            }
        }
        // A turn at rate w: exp is the rotation by wh; the truncated series is off by about
        // (wh)⁵/120.
        let w = 20.0;
        let mut turn = [[0.0; ERROR_MAX]; ERROR_MAX];
        turn[3][4] = -w;
        turn[4][3] = w;
        let mut phi = [[0.0; ERROR_MAX]; ERROR_MAX];
        transition(&turn, n, h, free_columns(&turn, n), &mut phi);
        let (s, c) = (w * h).sin_cos();
        let err = (phi[3][3] - c)
            .abs()
            .max((phi[3][4] + s).abs())
            .max((phi[4][3] - s).abs());
        let bound = (w * h).powi(5) / 120.0;
        assert!(err < 1.1 * bound && err > 0.5 * bound, "{err} vs {bound}");
        assert_eq!(phi[0][0], 1.0, "a still direction stays put");
    }
}
