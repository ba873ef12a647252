//! Named physical effects added to a baseline model (the catalogue of
//! `shared/specs/flight-model.md`), and the trait users implement for their own.
//!
//! An effect acts through hooks, each with a do-nothing default, evaluated in two stages:
//!
//! 1. **environment**: [`Effect::wind_ned`] (summed), [`Effect::density`] and
//!    [`Effect::gravity`] (applied in model order), [`Effect::actuator_tau`];
//! 2. **forces**, given the resulting [`Sample`]: [`Effect::accel_ned`] (world-frame
//!    acceleration, summed), [`Effect::force_moment_body`] (body-frame force and moment,
//!    summed), [`Effect::induced_drag_factor`] (multiplied).
//!
//! Every effect has a fixed name and named parameters, so analysis can switch, fit and rank
//! them by name.

use glam::{DMat3, DVec3};

use super::{Controls, VehicleKind};

/// Sea-level density of the ISA, kg/m³.
pub const RHO_SEA_LEVEL: f64 = 1.225;
/// Earth's rotation rate, rad/s.
pub const EARTH_RATE: f64 = 7.292115e-5;
/// Radius of the spherical Earth of `earth_curvature`, m.
pub const EARTH_RADIUS: f64 = 6_371_000.0;

/// ISA troposphere density at geopotential altitude `h` metres:
/// ρ = 1.225·(1 − 0.0065 h / 288.15)^4.2559 (clamped at the tropopause formula's zero).
pub fn isa_density(h: f64) -> f64 {
    RHO_SEA_LEVEL * (1.0 - 0.0065 * h / 288.15).max(0.0).powf(4.2559)
}

/// WGS84 normal gravity at geodetic latitude `lat_deg` and height `h` metres:
/// g = 9.7803253359·(1 + 0.00193185265241 sin²λ)/√(1 − 0.00669437999013 sin²λ) − 3.086e-6·h.
pub fn wgs84_gravity(lat_deg: f64, h: f64) -> f64 {
    let s2 = lat_deg.to_radians().sin().powi(2);
    9.780_325_335_9 * (1.0 + 0.001_931_852_652_41 * s2) / (1.0 - 0.006_694_379_990_13 * s2).sqrt()
        - 3.086e-6 * h
}

/// Earth's rotation vector in NED at latitude `lat_deg`: Ω·(cos λ, 0, −sin λ), rad/s.
pub fn earth_rotation_ned(lat_deg: f64) -> DVec3 {
    let (s, c) = lat_deg.to_radians().sin_cos();
    EARTH_RATE * DVec3::new(c, 0.0, -s)
}

/// Where the model is: the geodetic origin of the NED frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Origin {
    /// Latitude, degrees.
    pub latitude_deg: f64,
    /// Longitude, degrees.
    pub longitude_deg: f64,
    /// Altitude of the origin above sea level, m.
    pub altitude_m: f64,
}

impl Default for Origin {
    fn default() -> Self {
        Self {
            latitude_deg: 45.0,
            longitude_deg: 0.0,
            altitude_m: 0.0,
        }
    }
}

/// What an effect sees at one instant.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Position, NED, m.
    pub pos_ned: DVec3,
    /// Inertial velocity, NED, m/s.
    pub vel_ned: DVec3,
    /// Body → NED rotation (identity for a point mass).
    pub rot: DMat3,
    /// Body rates p, q, r, rad/s (zero for a point mass).
    pub omega: DVec3,
    /// Altitude above sea level, m (origin altitude − down).
    pub altitude_m: f64,
    /// Air density, kg/m³.
    pub rho: f64,
    /// Gravity magnitude, m/s².
    pub g: f64,
    /// Velocity relative to the air, NED, m/s.
    pub air_vel_ned: DVec3,
    /// Controls in effect (surfaces after any actuator dynamics), rad.
    pub controls: Controls,
    /// Mass, kg (1 for a point mass whose mass is unknown: its effects are accelerations).
    pub mass: f64,
}

/// A named parameter of an effect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// Name, as on the command line and in model files.
    pub name: &'static str,
    /// Current value.
    pub value: f64,
    /// Unit, for display.
    pub unit: &'static str,
}

/// A physical effect: named, with named parameters, acting through hooks (see module docs).
/// All hooks default to "no effect".
pub trait Effect: Send + Sync + std::fmt::Debug {
    /// Fixed name (catalogue names are fixed by the spec).
    fn name(&self) -> &str;
    /// Whether the effect means anything for this vehicle family.
    fn applies_to(&self, _vehicle: VehicleKind) -> bool {
        true
    }
    /// Parameters and their current values (empty for parameter-free effects).
    fn params(&self) -> Vec<Param> {
        Vec::new()
    }
    /// Set a parameter by name.
    ///
    /// # Errors
    /// Unknown name or a value outside the parameter's domain.
    fn set_param(&mut self, name: &str, _value: f64) -> Result<(), String> {
        Err(format!(
            "effect `{}` has no parameter `{name}`",
            self.name()
        ))
    }
    /// A boxed copy (models are cloned for fitting).
    fn clone_box(&self) -> Box<dyn Effect>;

    /// Steady wind, NED, m/s (summed over effects).
    fn wind_ned(&self) -> DVec3 {
        DVec3::ZERO
    }
    /// Air density at altitude `altitude_m` given the density so far.
    fn density(&self, _altitude_m: f64, rho: f64) -> f64 {
        rho
    }
    /// Gravity magnitude at altitude `altitude_m` given the value so far.
    fn gravity(&self, _altitude_m: f64, g: f64) -> f64 {
        g
    }
    /// Time constant of first-order control-surface lag, s, if this effect adds one.
    fn actuator_tau(&self) -> Option<f64> {
        None
    }
    /// Extra acceleration in NED, m/s² (summed).
    fn accel_ned(&self, _s: &Sample) -> DVec3 {
        DVec3::ZERO
    }
    /// Extra force (N) and moment (N·m) in body axes (summed).
    fn force_moment_body(&self, _s: &Sample) -> (DVec3, DVec3) {
        (DVec3::ZERO, DVec3::ZERO)
    }
    /// Factor on the induced-drag term of the fixed-wing drag polar (multiplied).
    fn induced_drag_factor(&self, _s: &Sample) -> f64 {
        1.0
    }
}

impl Clone for Box<dyn Effect> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

fn finite(name: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("parameter `{name}` = {value} is not finite"))
    }
}

/// `wind`: steady wind W in NED.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Wind {
    /// W, NED, m/s.
    pub ned: DVec3,
}

impl Effect for Wind {
    fn name(&self) -> &str {
        "wind"
    }
    fn params(&self) -> Vec<Param> {
        vec![
            Param {
                name: "north_mps",
                value: self.ned.x,
                unit: "m/s",
            },
            Param {
                name: "east_mps",
                value: self.ned.y,
                unit: "m/s",
            },
            Param {
                name: "down_mps",
                value: self.ned.z,
                unit: "m/s",
            },
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        let v = finite(name, value)?;
        match name {
            "north_mps" => self.ned.x = v,
            "east_mps" => self.ned.y = v,
            "down_mps" => self.ned.z = v,
            _ => return Err(format!("effect `wind` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn wind_ned(&self) -> DVec3 {
        self.ned
    }
}

/// `drag` (point mass): a += −k·(ρ/1.225)·|v_r|·v_r.
#[derive(Clone, Debug, PartialEq)]
pub struct Drag {
    /// k = ½ρC_D A/m at sea-level density, 1/m.
    pub k: f64,
}

impl Effect for Drag {
    fn name(&self) -> &str {
        "drag"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::PointMass
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "k",
            value: self.k,
            unit: "1/m",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "k" => self.k = finite(name, value)?,
            _ => return Err(format!("effect `drag` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        // The point mass's baseline density is the sea-level value; with `density_altitude`
        // on, s.rho is ρ(h) and k scales by ρ(h)/1.225, as the spec says.
        -self.k * (s.rho / RHO_SEA_LEVEL) * s.air_vel_ned.length() * s.air_vel_ned
    }
}

/// `density_altitude`: ISA troposphere density replaces the constant one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DensityAltitude;

impl Effect for DensityAltitude {
    fn name(&self) -> &str {
        "density_altitude"
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn density(&self, altitude_m: f64, _rho: f64) -> f64 {
        isa_density(altitude_m)
    }
}

/// `gravity_model`: WGS84 normal gravity at latitude and height instead of g0.
#[derive(Clone, Debug, PartialEq)]
pub struct GravityModel {
    /// Latitude, degrees.
    pub latitude_deg: f64,
}

impl Effect for GravityModel {
    fn name(&self) -> &str {
        "gravity_model"
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "latitude_deg",
            value: self.latitude_deg,
            unit: "deg",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "latitude_deg" => self.latitude_deg = finite(name, value)?.clamp(-90.0, 90.0),
            _ => return Err(format!("effect `gravity_model` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn gravity(&self, altitude_m: f64, _g: f64) -> f64 {
        wgs84_gravity(self.latitude_deg, altitude_m)
    }
}

/// `earth_rotation`: Coriolis acceleration −2 Ω×v.
#[derive(Clone, Debug, PartialEq)]
pub struct EarthRotation {
    /// Latitude, degrees.
    pub latitude_deg: f64,
}

impl Effect for EarthRotation {
    fn name(&self) -> &str {
        "earth_rotation"
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "latitude_deg",
            value: self.latitude_deg,
            unit: "deg",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "latitude_deg" => self.latitude_deg = finite(name, value)?.clamp(-90.0, 90.0),
            _ => return Err(format!("effect `earth_rotation` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        -2.0 * earth_rotation_ned(self.latitude_deg).cross(s.vel_ned)
    }
}

/// `earth_curvature`: gravity follows the sphere: (−g·n/R, −g·e/R, 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EarthCurvature;

impl Effect for EarthCurvature {
    fn name(&self) -> &str {
        "earth_curvature"
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        DVec3::new(
            -s.g * s.pos_ned.x / EARTH_RADIUS,
            -s.g * s.pos_ned.y / EARTH_RADIUS,
            0.0,
        )
    }
}

/// `prop_torque` (fixed-wing): rolling moment l += −k_torque·δt².
#[derive(Clone, Debug, PartialEq)]
pub struct PropTorque {
    /// k_torque, N·m.
    pub k_torque: f64,
}

impl Effect for PropTorque {
    fn name(&self) -> &str {
        "prop_torque"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::FixedWing
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "k_torque",
            value: self.k_torque,
            unit: "N·m",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "k_torque" => self.k_torque = finite(name, value)?,
            _ => return Err(format!("effect `prop_torque` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn force_moment_body(&self, s: &Sample) -> (DVec3, DVec3) {
        let dt = s.controls.throttle;
        (DVec3::ZERO, DVec3::new(-self.k_torque * dt * dt, 0.0, 0.0))
    }
}

/// `ground_effect` (fixed-wing): induced drag × (16h/b)²/(1 + (16h/b)²), h = −down.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundEffect {
    /// Wing span b, m (from the parameter set).
    pub span: f64,
}

impl Effect for GroundEffect {
    fn name(&self) -> &str {
        "ground_effect"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::FixedWing
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn induced_drag_factor(&self, s: &Sample) -> f64 {
        let x = 16.0 * (-s.pos_ned.z).max(0.0) / self.span;
        let x2 = x * x;
        x2 / (1.0 + x2)
    }
}

/// `actuator_lag` (fixed-wing): each surface follows its command, τ·ẋ = cmd − x.
#[derive(Clone, Debug, PartialEq)]
pub struct ActuatorLag {
    /// τ, s (> 0).
    pub tau_s: f64,
}

/// Shortest accepted actuator time constant, s: below this the lag is below any sample
/// interval of interest and the ODE becomes needlessly stiff.
pub const MIN_ACTUATOR_TAU: f64 = 1e-3;

impl Effect for ActuatorLag {
    fn name(&self) -> &str {
        "actuator_lag"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::FixedWing
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "tau_s",
            value: self.tau_s,
            unit: "s",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "tau_s" => self.tau_s = finite(name, value)?.max(MIN_ACTUATOR_TAU),
            _ => return Err(format!("effect `actuator_lag` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn actuator_tau(&self) -> Option<f64> {
        Some(self.tau_s)
    }
}

/// `gyroscopic` (fixed-wing): propeller angular momentum h = k_gyro·δt along body x;
/// moment += −ω × (h, 0, 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Gyroscopic {
    /// k_gyro, kg·m²/s.
    pub k_gyro: f64,
}

impl Effect for Gyroscopic {
    fn name(&self) -> &str {
        "gyroscopic"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::FixedWing
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "k_gyro",
            value: self.k_gyro,
            unit: "kg·m²/s",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "k_gyro" => self.k_gyro = finite(name, value)?,
            _ => return Err(format!("effect `gyroscopic` has no parameter `{name}`")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn force_moment_body(&self, s: &Sample) -> (DVec3, DVec3) {
        let h = DVec3::new(self.k_gyro * s.controls.throttle, 0.0, 0.0);
        (DVec3::ZERO, -s.omega.cross(h))
    }
}

/// Names of the catalogue, in the spec's order.
pub const CATALOGUE: [&str; 10] = [
    "wind",
    "drag",
    "density_altitude",
    "gravity_model",
    "earth_rotation",
    "earth_curvature",
    "prop_torque",
    "ground_effect",
    "actuator_lag",
    "gyroscopic",
];

/// A catalogue effect with default parameters: zero wind / torque / gyro, drag k = 1e-3 1/m,
/// τ = 0.1 s, latitude from the origin, span from the aircraft (`span_m`).
pub fn catalogue_effect(name: &str, origin: &Origin, span_m: f64) -> Option<Box<dyn Effect>> {
    Some(match name {
        "wind" => Box::new(Wind::default()),
        "drag" => Box::new(Drag { k: 1e-3 }),
        "density_altitude" => Box::new(DensityAltitude),
        "gravity_model" => Box::new(GravityModel {
            latitude_deg: origin.latitude_deg,
        }),
        "earth_rotation" => Box::new(EarthRotation {
            latitude_deg: origin.latitude_deg,
        }),
        "earth_curvature" => Box::new(EarthCurvature),
        "prop_torque" => Box::new(PropTorque { k_torque: 0.0 }),
        "ground_effect" => Box::new(GroundEffect { span: span_m }),
        "actuator_lag" => Box::new(ActuatorLag { tau_s: 0.1 }),
        "gyroscopic" => Box::new(Gyroscopic { k_gyro: 0.0 }),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Sample {
        Sample {
            t: 0.0,
            pos_ned: DVec3::ZERO,
            vel_ned: DVec3::ZERO,
            rot: DMat3::IDENTITY,
            omega: DVec3::ZERO,
            altitude_m: 0.0,
            rho: RHO_SEA_LEVEL,
            g: super::super::G0,
            air_vel_ned: DVec3::ZERO,
            controls: Controls::default(),
            mass: 1.0,
        }
    }

    #[test]
    fn isa_density_at_1000_m() {
        // The spec's formula gives 1.116 42; ISA tables give 1.1117 (the value):
        // they differ by 6e-5, the rounding of the exponent 4.2559.
        assert!(
            (isa_density(1000.0) - 1.111_642).abs() < 1e-6,
            "{}",
            isa_density(1000.0)
        );
        assert!((isa_density(1000.0) - 1.1117).abs() < 1e-4);
        assert_eq!(isa_density(0.0), RHO_SEA_LEVEL);
        assert!(isa_density(1e6) == 0.0, "no NaN above the formula's range");
    }

    #[test]
    fn wgs84_gravity_equator_and_pole() {
        assert!((wgs84_gravity(0.0, 0.0) - 9.7803).abs() < 5e-5);
        assert!((wgs84_gravity(90.0, 0.0) - 9.8322).abs() < 5e-5);
        assert!((wgs84_gravity(0.0, 1000.0) - (9.780_325_335_9 - 3.086e-3)).abs() < 1e-9);
    }

    #[test]
    fn coriolis_at_45n_deflects_northward_motion_east() {
        let e = EarthRotation { latitude_deg: 45.0 };
        let s = Sample {
            vel_ned: DVec3::new(100.0, 0.0, 0.0),
            ..sample()
        };
        let a = e.accel_ned(&s);
        // −2Ω×v with Ω = ω(cos45, 0, −sin45), v = 100 north: (0, −2ω·100·sin45·… ) worked out:
        // Ω×v = ω·(0·0 − (−s)·0, (−s)·100 − c·0, c·0 − 0·100) = ω(0, −100 s, 0) → a = (0, 200ωs, 0).
        let expected = 2.0 * EARTH_RATE * 100.0 * 45f64.to_radians().sin();
        assert!(a.x.abs() < 1e-15 && a.z.abs() < 1e-15);
        assert!((a.y - expected).abs() < 1e-12, "{a} vs {expected}");
        assert!((expected - 1.0312e-2).abs() < 1e-5); // ≈ 0.0103 m/s², eastward (right)
                                                      // Eastward motion at 45°N: deflected south and up (Eötvös).
        let s = Sample {
            vel_ned: DVec3::new(0.0, 100.0, 0.0),
            ..sample()
        };
        let a = e.accel_ned(&s);
        assert!(a.x < 0.0 && a.z < 0.0, "{a}");
    }

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

    #[test]
    fn curvature_pulls_back_toward_the_origin() {
        let c = EarthCurvature;
        let s = Sample {
            pos_ned: DVec3::new(6371.0, -637.1, 5.0),
            ..sample()
        };
        let a = c.accel_ned(&s);
        assert!(
            (a - DVec3::new(-1e-3 * super::super::G0, 1e-4 * super::super::G0, 0.0)).length()
                < 1e-12
        );
    }

    #[test]
    fn prop_torque_gyroscopic_ground_effect_formulas() {
        let controls = Controls {
            throttle: 0.5,
            ..Controls::default()
        };
        let s = Sample {
            controls,
            omega: DVec3::new(0.1, 0.2, 0.3),
            ..sample()
        };
        let (_, m) = PropTorque { k_torque: 2.0 }.force_moment_body(&s);
        assert_eq!(m, DVec3::new(-0.5, 0.0, 0.0));
        let (_, m) = Gyroscopic { k_gyro: 4.0 }.force_moment_body(&s);
        // −ω × (2, 0, 0) = −(0, 0.3·2, −0.2·2) = (0, −0.6, 0.4)
        assert!((m - DVec3::new(0.0, -0.6, 0.4)).length() < 1e-15, "{m}");
        let g = GroundEffect { span: 16.0 };
        let s = Sample {
            pos_ned: DVec3::new(0.0, 0.0, -1.0),
            ..sample()
        };
        assert!((g.induced_drag_factor(&s) - 0.5).abs() < 1e-15); // 16h/b = 1
        let s = Sample {
            pos_ned: DVec3::new(0.0, 0.0, -1000.0),
            ..sample()
        };
        assert!(g.induced_drag_factor(&s) > 0.9999);
    }

    #[test]
    fn catalogue_names_are_the_effects_names() {
        for name in CATALOGUE {
            let e = catalogue_effect(name, &Origin::default(), 3.0).unwrap();
            assert_eq!(e.name(), name);
        }
        assert!(catalogue_effect("magic", &Origin::default(), 3.0).is_none());
    }
}
