//! `density_altitude`: ISA troposphere density ρ(h) = 1.225·(1 − 0.0065 h/288.15)^4.2559
//! replaces the constant one (for `drag`, k scales by ρ(h)/1.225).

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo};

/// Sea-level density of the ISA, kg/m³.
pub const RHO_SEA_LEVEL: f64 = 1.225;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "density_altitude",
    summary: "ISA troposphere density instead of a constant",
    applies: Applies::Both,
    params: &[],
    make: |_: &EffectContext| Box::new(DensityAltitude),
};

/// ISA troposphere density at geopotential altitude `h` metres:
/// ρ = 1.225·(1 − 0.0065 h / 288.15)^4.2559 (clamped at the tropopause formula's zero).
pub fn isa_density(h: f64) -> f64 {
    RHO_SEA_LEVEL * (1.0 - 0.0065 * h / 288.15).max(0.0).powf(4.2559)
}

/// `density_altitude`: ISA troposphere density replaces the constant one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DensityAltitude;

impl Effect for DensityAltitude {
    effect_basics! {
        info: INFO,
        varies_in_time: false,
    }
    fn density(&self, altitude_m: f64, _rho: f64) -> f64 {
        isa_density(altitude_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isa_density_at_1000_m() {
        // The spec's formula gives 1.116 42; ISA tables give 1.1117: they differ by 6e-5, the
        // rounding of the exponent 4.2559.
        assert!(
            (isa_density(1000.0) - 1.111_642).abs() < 1e-6,
            "{}",
            isa_density(1000.0)
        );
        assert!((isa_density(1000.0) - 1.1117).abs() < 1e-4);
        assert_eq!(isa_density(0.0), RHO_SEA_LEVEL);
        assert!(isa_density(1e6) == 0.0, "no NaN above the formula's range");
    }
}
