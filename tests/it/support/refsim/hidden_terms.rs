//! Hidden terms: forces and moments no catalogue effect has, for `discover` to find. Each is
//! coefficient × a product of the air data, the rates and the commands, on one body axis.

use super::*;

/// The form of a hidden term's regressor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HiddenForm {
    /// q̄·α·β (a dihedral effect growing with angle of attack).
    QbarAlphaBeta,
    /// δt² (a propeller's slipstream drag).
    ThrottleSquared,
    /// r·δt (yaw damping of the slipstream over the fin).
    YawRateThrottle,
    /// The propeller's thrust T, N (a thrust line off the centre of gravity, on m).
    Thrust,
}

/// One hidden term: axis 0..3 forces X, Y, Z (N), 3..6 moments l, m, n (N·m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HiddenTerm {
    pub axis: usize,
    pub form: HiddenForm,
    pub coefficient: f64,
}

/// The hidden terms' force and moment in body axes.
pub fn hidden_force_moment(
    terms: &[HiddenTerm],
    rho: f64,
    va: f64,
    alpha: f64,
    beta: f64,
    pqr: V3,
    (throttle, thrust): (f64, f64),
) -> (V3, V3) {
    let mut fm = [0.0; 6];
    for t in terms {
        let x = match t.form {
            HiddenForm::QbarAlphaBeta => 0.5 * rho * va * va * alpha * beta,
            HiddenForm::ThrottleSquared => throttle * throttle,
            HiddenForm::YawRateThrottle => pqr[2] * throttle,
            HiddenForm::Thrust => thrust,
        };
        fm[t.axis] += t.coefficient * x;
    }
    ([fm[0], fm[1], fm[2]], [fm[3], fm[4], fm[5]])
}
