//! `drag` (point mass): a += −k·(ρ/1.225)·|v_r|·v_r, k = ½ρC_D·A/m at sea-level density.

use glam::DVec3;

use super::{
    effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec, Sample, RHO_SEA_LEVEL,
};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "drag",
    summary: "−k·|v_r|·v_r, k = ½ρC_D·A/m (1/m)",
    applies: Applies::PointMass,
    params: &[ParamSpec {
        // A drag coefficient may be 1e-5 or 1e-2: the scale follows the value.
        scale_relative: true,
        absent: Some(0.0),
        start: Some(1e-4),
        ..ParamSpec::new("k", "1/m", (0.0, 1.0), 1e-4)
    }],
    make: |_: &EffectContext| Box::new(Drag { k: 1e-3 }),
};

/// `drag` (point mass): a += −k·(ρ/1.225)·|v_r|·v_r.
#[derive(Clone, Debug, PartialEq)]
pub struct Drag {
    /// k = ½ρC_D A/m at sea-level density, 1/m.
    pub k: f64,
}

impl Effect for Drag {
    effect_basics! {
        info: INFO,
        values: k,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        // The point mass's baseline density is the sea-level value; with `density_altitude`
        // on, s.rho is ρ(h) and k scales by ρ(h)/1.225, as the spec says.
        -self.k * (s.rho / RHO_SEA_LEVEL) * s.air_vel_ned.length() * s.air_vel_ned
    }
}

#[cfg(test)]
mod tests {
    use super::super::{isa_density, tests_support::sample};
    use super::*;

    #[test]
    fn drag_opposes_air_relative_velocity_and_scales_with_density() {
        let d = Drag { k: 0.01 };
        let s = Sample {
            air_vel_ned: DVec3::new(30.0, 40.0, 0.0),
            ..sample()
        };
        let a = d.accel_ned(&s);
        assert!((a - DVec3::new(-15.0, -20.0, 0.0)).length() < 1e-12, "{a}");
        let s = Sample {
            rho: isa_density(1000.0),
            ..s
        };
        let ratio = d.accel_ned(&s).length() / a.length();
        assert!((ratio - isa_density(1000.0) / RHO_SEA_LEVEL).abs() < 1e-12);
    }
}
