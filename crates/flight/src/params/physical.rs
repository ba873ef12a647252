//! The values a fit may give each number of a fixed-wing parameter set: the physically
//! plausible ones, narrower than what a parameter file may hold ([`super::keys`]'s ranges).
//!
//! A file may describe an unusual aircraft (a positive pitch stiffness, a heavy payload); a
//! fit on noisy or incomplete data may not wander there unnoticed. A fit that ends on one of
//! these bounds has not found a value: the data pushed it to the edge of what is physical,
//! which says the model lacks something else, and it is reported as "at its limit".
//! Damping derivatives and the main control powers keep their physical sign; slopes,
//! efficiencies and densities stay in the span of real aircraft; sizes stay within a factor
//! of the set's own value.

use super::keys::{find, AircraftKey};

/// Bounds of a fitted number: absolute, or factors of the set's value (for sizes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FitBounds {
    /// Between these values.
    Absolute(f64, f64),
    /// Between these multiples of the set's value (which is positive).
    Relative(f64, f64),
}

/// The physical bounds of a key (None for an unknown key).
pub fn fit_bounds(name: &str) -> Option<FitBounds> {
    use FitBounds::{Absolute as A, Relative as R};
    let key = find(name)?;
    Some(match key.name {
        "mass_kg" => R(0.25, 4.0),
        "jx" | "jy" | "jz" => R(0.1, 10.0),
        "jxz" => A(-1e9, 1e9),
        "s_wing" | "b" | "c" => R(0.5, 2.0),
        "e" => A(0.3, 1.0),
        "rho" => A(0.3, 1.5),
        "c_l_0" => A(-1.0, 1.5),
        // Thin-aerofoil theory gives 2π per radian; finite wings less, never 1 or 8.
        "c_l_alpha" => A(1.0, 8.0),
        "c_l_q" => A(0.0, 40.0),
        "c_m_q" => A(-150.0, 0.0),
        "c_m_alpha" => A(-10.0, 2.0),
        "c_m_0" => A(-0.5, 0.5),
        "c_d_p" => A(0.0, 0.5),
        "c_y_beta" => A(-3.0, 0.0),
        "c_ell_beta" => A(-1.0, 0.3),
        "c_ell_p" => A(-2.0, 0.0),
        "c_n_r" => A(-1.0, 0.0),
        "c_n_beta" => A(-0.3, 1.0),
        "c_y_0" | "c_ell_0" | "c_n_0" => A(-0.2, 0.2),
        "m_blend" => A(1.0, 500.0),
        // The stall angle of attack, rad (≈ 6°–46°).
        "alpha0" => A(0.1, 0.8),
        // Control powers whose sign the surfaces' conventions fix (Beard & McLain): the
        // elevator down lifts the tail (more lift, nose down), the aileron rolls right,
        // the rudder yaws left with a side force to the right; deflecting a surface adds
        // drag at trim.
        "c_l_delta_e" | "c_ell_delta_a" | "c_y_delta_r" | "c_d_delta_e" => A(0.0, 5.0),
        "c_m_delta_e" | "c_n_delta_r" => A(-5.0, 0.0),
        "s_prop" | "c_prop" | "k_motor" => R(0.2, 5.0),
        // Every other coefficient: a control power or cross term, a few per radian at most.
        _ => A(-5.0, 5.0),
    })
}

/// The range a fit may move the key in, given its value in the set: the physical bounds
/// within the key's valid range. A set value outside the physical bounds widens them to
/// include it (the set is the user's statement about the aircraft).
pub fn fit_range(key: &AircraftKey, set_value: f64) -> (f64, f64) {
    let (lo, hi) = match fit_bounds(key.name) {
        Some(FitBounds::Absolute(lo, hi)) => (lo, hi),
        Some(FitBounds::Relative(lo, hi)) if set_value > 0.0 => (lo * set_value, hi * set_value),
        _ => key.range,
    };
    let lo = lo.min(set_value).max(key.range.0);
    let hi = hi.max(set_value).min(key.range.1);
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::keys::{get, KEYS};
    use crate::params::FixedWingParams;

    /// Every key has bounds inside its valid range that hold the Aerosonde's value, and the
    /// damping derivatives keep their sign.
    #[test]
    fn bounds_hold_the_reference_aircraft_and_keep_damping_signs() {
        let p = FixedWingParams::aerosonde();
        for key in KEYS {
            let v = get(&p, key.name).unwrap();
            let (lo, hi) = fit_range(key, v);
            assert!(
                lo < hi && lo >= key.range.0 && hi <= key.range.1,
                "{}",
                key.name
            );
            assert!(lo <= v && v <= hi, "{}: {v} outside [{lo}, {hi}]", key.name);
        }
        for damping in ["c_m_q", "c_ell_p", "c_n_r", "c_m_delta_e", "c_n_delta_r"] {
            let (_, hi) = fit_range(find(damping).unwrap(), -1.0);
            assert_eq!(hi, 0.0, "{damping}");
        }
        for power in ["c_l_delta_e", "c_ell_delta_a", "c_y_delta_r", "c_d_delta_e"] {
            let (lo, _) = fit_range(find(power).unwrap(), 0.1);
            assert_eq!(lo, 0.0, "{power}");
        }
        let (lo, hi) = fit_range(find("c_l_alpha").unwrap(), 5.61);
        assert_eq!((lo, hi), (1.0, 8.0));
        // A set value outside the physical bounds is kept reachable.
        let (lo, _) = fit_range(find("c_l_alpha").unwrap(), 0.5);
        assert_eq!(lo, 0.5);
        assert_eq!(fit_range(find("mass_kg").unwrap(), 10.0), (2.5, 40.0));
    }
}
