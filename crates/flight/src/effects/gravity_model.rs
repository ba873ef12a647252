//! `gravity_model`: WGS84 normal gravity at the origin's latitude λ and the height h instead
//! of g0: g = 9.7803253359·(1 + 0.00193185265241 sin²λ)/√(1 − 0.00669437999013 sin²λ)
//! − 3.086e-6·h.

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, ParamSpec};

/// The latitude parameter shared by the Earth effects: held when the data's metadata give it.
pub(super) const LATITUDE: ParamSpec = ParamSpec {
    from_origin: true,
    ..ParamSpec::new("latitude_deg", "deg", (-90.0, 90.0), 10.0)
};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "gravity_model",
    summary: "WGS84 normal gravity at the origin's latitude and the height",
    applies: Applies::Both,
    params: &[LATITUDE],
    make: |ctx: &EffectContext| {
        Box::new(GravityModel {
            latitude_deg: ctx.origin.latitude_deg.clamp(-90.0, 90.0),
        })
    },
};

/// WGS84 normal gravity at geodetic latitude `lat_deg` and height `h` metres (formula above).
pub fn wgs84_gravity(lat_deg: f64, h: f64) -> f64 {
    let s2 = lat_deg.to_radians().sin().powi(2);
    9.780_325_335_9 * (1.0 + 0.001_931_852_652_41 * s2) / (1.0 - 0.006_694_379_990_13 * s2).sqrt()
        - 3.086e-6 * h
}

/// `gravity_model`: WGS84 normal gravity at latitude and height instead of g0.
#[derive(Clone, Debug, PartialEq)]
pub struct GravityModel {
    /// Latitude, degrees.
    pub latitude_deg: f64,
}

impl Effect for GravityModel {
    effect_basics! {
        info: INFO,
        values: latitude_deg,
        varies_in_time: false,
    }
    fn gravity(&self, altitude_m: f64, _g: f64) -> f64 {
        wgs84_gravity(self.latitude_deg, altitude_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wgs84_gravity_equator_and_pole() {
        assert!((wgs84_gravity(0.0, 0.0) - 9.7803).abs() < 5e-5);
        assert!((wgs84_gravity(90.0, 0.0) - 9.8322).abs() < 5e-5);
        assert!((wgs84_gravity(0.0, 1000.0) - (9.780_325_335_9 - 3.086e-3)).abs() < 1e-9);
    }
}
