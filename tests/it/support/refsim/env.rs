//! refsim's environment and catalogue effects.

use super::*;

/// Geodetic origin of the local NED frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Origin {
    pub latitude_deg: f64,
    pub longitude_deg: f64,
    pub altitude_m: f64,
}

impl Default for Origin {
    fn default() -> Self {
        Origin {
            latitude_deg: 47.3977,
            longitude_deg: 8.5456,
            altitude_m: 488.0,
        }
    }
}

/// Names of the catalogue effects of `flight-model.md`.
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

/// Catalogue effects, each optional. `Effects::default()` is the baseline (none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Effects {
    /// `wind`: steady wind NED [north, east, down], m/s.
    pub wind: Option<V3>,
    /// `drag` (point mass): k = ½ρC_D A/m, 1/m.
    pub drag: Option<f64>,
    /// `density_altitude`: ISA ρ(h), h = origin altitude − down.
    pub density_altitude: bool,
    /// `gravity_model`: WGS84 normal gravity.
    pub gravity_model: bool,
    /// `earth_rotation`: Coriolis −2Ω×v.
    pub earth_rotation: bool,
    /// `earth_curvature`: (−g·n/R, −g·e/R, 0).
    pub earth_curvature: bool,
    /// `prop_torque`: k_torque, N·m (l += −k·δt²).
    pub prop_torque: Option<f64>,
    /// `ground_effect`: induced drag × (16h/b)²/(1+(16h/b)²).
    pub ground_effect: bool,
    /// `actuator_lag`: tau_s of every control surface.
    pub actuator_lag: Option<f64>,
    /// `gyroscopic`: k_gyro, kg·m²/s.
    pub gyroscopic: Option<f64>,
    /// Latitude for `gravity_model` / `earth_rotation`; None = the origin's latitude.
    pub latitude_deg: Option<f64>,
    /// `gravity_model` height: false (default) = current height altitude_m(origin) − down,
    /// true = the origin's altitude (constant).
    pub gravity_height_at_origin: bool,
    /// Terms no catalogue effect has (`hidden_terms.rs`).
    pub hidden_terms: Vec<HiddenTerm>,
}

impl Effects {
    /// Baseline: no effect.
    pub fn none() -> Self {
        Effects::default()
    }

    /// Add a catalogue effect by name with its parameters:
    /// `wind` [n, e, d]; `drag` [k]; `density_altitude` []; `gravity_model` [] or [lat_deg];
    /// `earth_rotation` [] or [lat_deg]; `earth_curvature` []; `prop_torque` [k_torque];
    /// `ground_effect` []; `actuator_lag` [tau_s]; `gyroscopic` [k_gyro].
    pub fn with(mut self, name: &str, args: &[f64]) -> Result<Self, String> {
        let need = |n: usize| -> Result<(), String> {
            if args.len() == n {
                Ok(())
            } else {
                Err(format!(
                    "effect {name}: expected {n} parameter(s), got {}",
                    args.len()
                ))
            }
        };
        match name {
            "wind" => {
                need(3)?;
                self.wind = Some([args[0], args[1], args[2]]);
            }
            "drag" => {
                need(1)?;
                self.drag = Some(args[0]);
            }
            "density_altitude" => {
                need(0)?;
                self.density_altitude = true;
            }
            "gravity_model" | "earth_rotation" => {
                if args.len() > 1 {
                    return Err(format!(
                        "effect {name}: at most one parameter (latitude_deg)"
                    ));
                }
                if let Some(&lat) = args.first() {
                    self.latitude_deg = Some(lat);
                }
                if name == "gravity_model" {
                    self.gravity_model = true;
                } else {
                    self.earth_rotation = true;
                }
            }
            "earth_curvature" => {
                need(0)?;
                self.earth_curvature = true;
            }
            "prop_torque" => {
                need(1)?;
                self.prop_torque = Some(args[0]);
            }
            "ground_effect" => {
                need(0)?;
                self.ground_effect = true;
            }
            "actuator_lag" => {
                need(1)?;
                self.actuator_lag = Some(args[0]);
            }
            "gyroscopic" => {
                need(1)?;
                self.gyroscopic = Some(args[0]);
            }
            other => return Err(format!("unknown effect `{other}`")),
        }
        Ok(self)
    }

    /// Names of the effects switched on, in catalogue order.
    pub fn names(&self) -> Vec<&'static str> {
        let on = [
            self.wind.is_some(),
            self.drag.is_some(),
            self.density_altitude,
            self.gravity_model,
            self.earth_rotation,
            self.earth_curvature,
            self.prop_torque.is_some(),
            self.ground_effect,
            self.actuator_lag.is_some(),
            self.gyroscopic.is_some(),
        ];
        CATALOGUE
            .iter()
            .zip(on)
            .filter(|(_, o)| *o)
            .map(|(n, _)| *n)
            .collect()
    }
}

/// ISA troposphere density of the catalogue, kg/m³.
pub fn isa_density(h: f64) -> f64 {
    RHO_SL * (1.0 - 0.0065 * h / 288.15).powf(4.2559)
}

/// WGS84 normal gravity of the catalogue at latitude (deg) and height h (m).
pub fn wgs84_gravity(latitude_deg: f64, h: f64) -> f64 {
    let s2 = (latitude_deg * DEG).sin().powi(2);
    9.7803253359 * (1.0 + 0.00193185265241 * s2) / (1.0 - 0.00669437999013 * s2).sqrt()
        - 3.086e-6 * h
}

/// Earth rotation vector in NED at latitude (deg): Ω·(cosλ, 0, −sinλ).
pub fn earth_rate_ned(latitude_deg: f64) -> V3 {
    let (s, c) = (latitude_deg * DEG).sin_cos();
    [EARTH_RATE * c, 0.0, -EARTH_RATE * s]
}

/// Environment derived once from effects + origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Env {
    pub wind: V3,
    pub rho_const: f64,
    pub density_altitude: bool,
    pub altitude0: f64,
    pub gravity_model: bool,
    pub gravity_latitude_deg: f64,
    pub gravity_height_at_origin: bool,
    pub omega: Option<V3>,
    pub curvature: bool,
}

impl Env {
    pub fn new(effects: &Effects, origin: &Origin, rho_const: f64) -> Env {
        let lat = effects.latitude_deg.unwrap_or(origin.latitude_deg);
        Env {
            wind: effects.wind.unwrap_or([0.0; 3]),
            rho_const,
            density_altitude: effects.density_altitude,
            altitude0: origin.altitude_m,
            gravity_model: effects.gravity_model,
            gravity_latitude_deg: lat,
            gravity_height_at_origin: effects.gravity_height_at_origin,
            omega: if effects.earth_rotation {
                Some(earth_rate_ned(lat))
            } else {
                None
            },
            curvature: effects.earth_curvature,
        }
    }

    /// Air density at `down`.
    pub fn rho(&self, down: f64) -> f64 {
        if self.density_altitude {
            isa_density(self.altitude0 - down)
        } else {
            self.rho_const
        }
    }

    /// Gravity magnitude at `down`.
    pub fn g(&self, down: f64) -> f64 {
        if self.gravity_model {
            let h = if self.gravity_height_at_origin {
                self.altitude0
            } else {
                self.altitude0 - down
            };
            wgs84_gravity(self.gravity_latitude_deg, h)
        } else {
            G0
        }
    }

    /// Coriolis + curvature accelerations in NED (gravity itself excluded).
    pub fn extra_accel_ned(&self, pos: V3, vel_ned: V3, g: f64) -> V3 {
        let mut a = [0.0; 3];
        if let Some(om) = self.omega {
            a = v_add(a, v_scale(v_cross(om, vel_ned), -2.0));
        }
        if self.curvature {
            a[0] -= g * pos[0] / EARTH_RADIUS;
            a[1] -= g * pos[1] / EARTH_RADIUS;
        }
        a
    }
}
