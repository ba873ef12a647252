//! Named physical effects added to a baseline model (the catalogue of
//! `docs/flight-model.md`), and the trait users implement for their own.
//!
//! Each effect is one file: its physics (hooks of [`Effect`]) and its [`EffectInfo`] — name,
//! the vehicles it applies to, and each parameter's [`ParamSpec`] (unit, valid range, typical
//! size for fitting, starting value). Everything else (model files, `--add`, the diagnosis,
//! the window's checkboxes) works from that metadata, so adding an effect is one new file and
//! one line in [`CATALOGUE`].
//!
//! An effect acts through hooks, each with a do-nothing default, evaluated in two stages:
//!
//! 1. **environment** at a position and time: [`Effect::wind_at`] (summed),
//!    [`Effect::density`] and [`Effect::gravity`] (applied in model order),
//!    [`Effect::actuator_tau`];
//! 2. **forces**, given the resulting [`Sample`]: [`Effect::accel_ned`] (world-frame
//!    acceleration, summed), [`Effect::force_moment_body`] (body-frame force and moment,
//!    summed), [`Effect::induced_drag_factor`] (multiplied).
//!
//! A **measurement effect** ([`sensors`]: a delay, a bias, a scale factor) acts on none of
//! these but on what the sensors read of the flight: [`Effect::measure`] and
//! [`Effect::nav_delay`], applied by the comparison after the model has flown.
//!
//! What every implementation says the same way — its [`EffectInfo`], where its parameter
//! values are stored, whether it varies in time or space — is written by [`effect_basics!`],
//! so an effect's file holds only its own physics.

mod actuator_lag;
mod density_altitude;
mod drag;
mod earth_curvature;
mod earth_rotation;
mod gravity_model;
mod ground_effect;
mod gyroscopic;
mod incidence_lift;
mod prop_torque;
mod recorded;
pub mod sensors;
pub mod term;
mod wind;

pub use actuator_lag::{ActuatorLag, MIN_ACTUATOR_TAU};
pub use density_altitude::{isa_density, DensityAltitude, RHO_SEA_LEVEL};
pub use drag::Drag;
pub use earth_curvature::{EarthCurvature, EARTH_RADIUS};
pub use earth_rotation::{earth_rotation_ned, EarthRotation, EARTH_RATE};
pub use gravity_model::{wgs84_gravity, GravityModel};
pub use ground_effect::GroundEffect;
pub use gyroscopic::Gyroscopic;
pub use incidence_lift::{IncidenceLift, INFO as INCIDENCE_LIFT};
pub use prop_torque::PropTorque;
pub use recorded::RecordedAttitude;
pub use sensors::{
    AccelBias, AirspeedBias, AirspeedScale, AttitudeOffset, GyroBias, NavDelay, MAX_NAV_DELAY,
};
pub use term::{Airframe, TermEffect};
pub use wind::Wind;

use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};

use super::aero::AirData;
use wireflight_data::{Controls, OriginError, VehicleKind};

pub use crate::effect_basics;

/// Writes the part of an `impl Effect for …` block that every effect writes the same way:
///
/// * `info: STATIC` — [`Effect::info`], returning `&STATIC`;
/// * `values: FIELD` (optional; none for an effect without parameters) —
///   [`Effect::values`] and [`Effect::values_mut`] over the field that stores the parameter
///   values in the order of the info's `params`: an `f64` (one parameter), a `DVec3` (three)
///   or an `[f64; N]` (see [`ParamValues`]);
/// * `varies_in_time: false`, `varies_in_space: false` (optional, in this order) —
///   [`Effect::varies_in_time`] and [`Effect::varies_in_space`] for an effect whose hooks do
///   not depend on the time or on the position (both are `true` when not said, the safe
///   answer).
///
/// The hooks the effect needs follow in the same block.
///
/// ```
/// use glam::DVec3;
/// use wireflight_flight::effects::{
///     effect_basics, Applies, Effect, EffectContext, EffectInfo, Origin, ParamSpec,
/// };
///
/// static UPDRAFT: EffectInfo = EffectInfo {
///     name: "updraft",
///     summary: "rising air everywhere",
///     applies: Applies::Both,
///     params: &[ParamSpec::new("w_mps", "m/s", (0.0, 20.0), 1.0)],
///     make: |_| Box::new(Updraft { w: 1.0 }),
/// };
///
/// #[derive(Clone, Debug)]
/// struct Updraft {
///     w: f64,
/// }
///
/// impl Effect for Updraft {
///     effect_basics! {
///         info: UPDRAFT,
///         values: w,
///         varies_in_time: false,
///         varies_in_space: false,
///     }
///     fn wind_at(&self, _pos_ned: DVec3, _t: f64) -> DVec3 {
///         DVec3::new(0.0, 0.0, -self.w)
///     }
/// }
///
/// let ctx = EffectContext {
///     origin: Origin::default(),
///     span_m: 0.0,
///     chord_m: 0.0,
///     ..EffectContext::default()
/// };
/// let mut e = UPDRAFT.build(&ctx);
/// e.set_param("w_mps", 3.0).unwrap();
/// assert_eq!(e.param("w_mps"), Some(3.0));
/// assert!(!e.varies_in_space());
/// ```
#[macro_export]
macro_rules! effect_basics {
    (
        info: $info:path
        $(, values: $values:tt)?
        $(, varies_in_time: $time:expr)?
        $(, varies_in_space: $space:expr)?
        $(,)?
    ) => {
        fn info(&self) -> &'static $crate::effects::EffectInfo {
            &$info
        }
        $(
            fn values(&self) -> &[f64] {
                $crate::effects::ParamValues::as_values(&self.$values)
            }
            fn values_mut(&mut self) -> &mut [f64] {
                $crate::effects::ParamValues::as_values_mut(&mut self.$values)
            }
        )?
        $(
            fn varies_in_time(&self) -> bool {
                $time
            }
        )?
        $(
            fn varies_in_space(&self) -> bool {
                $space
            }
        )?
    };
}

/// Where an effect stores its parameter values, seen as the slice of [`Effect::values`]: one
/// `f64`, a `DVec3` (three) or an array (used by [`effect_basics!`]).
pub trait ParamValues {
    /// The values.
    fn as_values(&self) -> &[f64];
    /// The values, to set.
    fn as_values_mut(&mut self) -> &mut [f64];
}

impl ParamValues for f64 {
    fn as_values(&self) -> &[f64] {
        std::slice::from_ref(self)
    }
    fn as_values_mut(&mut self) -> &mut [f64] {
        std::slice::from_mut(self)
    }
}

impl ParamValues for DVec3 {
    fn as_values(&self) -> &[f64] {
        AsRef::<[f64; 3]>::as_ref(self)
    }
    fn as_values_mut(&mut self) -> &mut [f64] {
        AsMut::<[f64; 3]>::as_mut(self)
    }
}

impl<const N: usize> ParamValues for [f64; N] {
    fn as_values(&self) -> &[f64] {
        self
    }
    fn as_values_mut(&mut self) -> &mut [f64] {
        self
    }
}

/// A parameter of an effect that cannot be set: an unknown name, or a value outside its range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParamError {
    /// A value outside the parameter's range, or not finite.
    #[error("parameter `{name}` = {value} is outside its range [{lo}, {hi}] {unit}")]
    OutOfRange {
        /// The parameter.
        name: &'static str,
        /// The value refused.
        value: f64,
        /// The least valid value.
        lo: f64,
        /// The greatest valid value.
        hi: f64,
        /// The parameter's unit.
        unit: &'static str,
    },
    /// A parameter named for an effect that has none.
    #[error("effect `{effect}` has no parameters (given `{given}`)")]
    NoParameters {
        /// The effect.
        effect: &'static str,
        /// The name given.
        given: String,
    },
    /// A name that is not one of the effect's parameters.
    #[error(
        "effect `{effect}` has no parameter `{given}`{hint} (it has {})",
        .known.join(", "),
        hint = crate::params::suggest::hint(given, known.iter().copied())
    )]
    Unknown {
        /// The effect.
        effect: &'static str,
        /// The name given.
        given: String,
        /// The effect's parameters.
        known: Vec<&'static str>,
    },
    /// An effect whose [`Effect::values_mut`] has no slot for a parameter its info lists.
    #[error("effect `{effect}` does not store `{name}`")]
    NotStored {
        /// The effect.
        effect: &'static str,
        /// The parameter.
        name: &'static str,
    },
}

/// The catalogue: every built-in effect, in the spec's order. One line per effect.
pub static CATALOGUE: &[&EffectInfo] = &[
    &wind::INFO,
    &drag::INFO,
    &incidence_lift::INFO,
    &density_altitude::INFO,
    &gravity_model::INFO,
    &earth_rotation::INFO,
    &earth_curvature::INFO,
    &prop_torque::INFO,
    &ground_effect::INFO,
    &actuator_lag::INFO,
    &gyroscopic::INFO,
    &sensors::NAV_DELAY,
    &sensors::GYRO_BIAS,
    &sensors::AIRSPEED_SCALE,
    &sensors::AIRSPEED_BIAS,
    &sensors::ACCEL_BIAS,
    &sensors::ATTITUDE_OFFSET,
];

/// The catalogue entry of that name, or the interned info of a term already read under it
/// (`term(m=k*thrust)`, see [`term`]).
pub fn find(name: &str) -> Option<&'static EffectInfo> {
    CATALOGUE
        .iter()
        .copied()
        .find(|i| i.name == name)
        .or_else(|| term::find_interned(name))
}

/// Names of the catalogue, in order (for messages and help).
pub fn catalogue_names() -> Vec<&'static str> {
    CATALOGUE.iter().map(|i| i.name).collect()
}

/// A catalogue effect with its default parameters in a context, or `None` for an unknown
/// name.
pub fn catalogue_effect(name: &str, ctx: &EffectContext) -> Option<Box<dyn Effect>> {
    find(name).map(|info| info.build(ctx))
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

impl Origin {
    /// Check one field's value (`key` as in the flight data's metadata; other keys pass)
    /// against its range, the one table of [`wireflight_data::ORIGIN_RANGES`]: latitude within
    /// ±90°, longitude −180°..360°, altitude −1e4..1e8 m.
    ///
    /// # Errors
    /// The value is outside the field's range (the message names both).
    pub fn check_field(key: &str, value: f64) -> Result<(), OriginError> {
        wireflight_data::check_origin_field(key, value)
    }

    /// Check every field ([`Origin::check_field`]).
    ///
    /// # Errors
    /// The first field out of its range.
    pub fn check(&self) -> Result<(), OriginError> {
        Self::check_field("latitude_deg", self.latitude_deg)?;
        Self::check_field("longitude_deg", self.longitude_deg)?;
        Self::check_field("altitude_m", self.altitude_m)
    }
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

/// What an effect's defaults may depend on: where the model is, the aircraft's size, and
/// what the flight the model was built for recorded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EffectContext {
    /// The geodetic origin (latitude defaults of the Earth effects).
    pub origin: Origin,
    /// Wing span, m (0 for a point mass).
    pub span_m: f64,
    /// Mean aerodynamic chord, m (0 for a point mass): with the span, the reference lengths
    /// of a term's non-dimensional rates ([`term`]).
    pub chord_m: f64,
    /// The attitude the flight recorded, where the model was built for a flight that has one
    /// (`None` otherwise, and for `simulate`): what a point mass's force from the body's
    /// incidence acts from (`incidence_lift`). Shared, not copied, by every effect.
    pub recorded_attitude: Option<Arc<RecordedAttitude>>,
}

/// Which vehicle families an effect means something for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Applies {
    /// Point mass and fixed wing.
    Both,
    /// Only the point mass.
    PointMass,
    /// Only the fixed wing.
    FixedWing,
}

impl Applies {
    /// Whether a vehicle of that family can have the effect.
    pub fn to(self, vehicle: VehicleKind) -> bool {
        match self {
            Applies::Both => true,
            Applies::PointMass => vehicle == VehicleKind::PointMass,
            Applies::FixedWing => vehicle == VehicleKind::FixedWing,
        }
    }
}

/// What is known about one parameter: enough for a model file, the command line, fitting and
/// display, so that nothing outside the effect's file keys on its name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Name, as on the command line and in model files.
    pub name: &'static str,
    /// Unit, for display.
    pub unit: &'static str,
    /// Valid values, inclusive: a value outside is an error where it is given, and the fitter
    /// stays inside.
    pub range: (f64, f64),
    /// Typical size: the fitter's scaling and finite-difference step (1% of it).
    pub scale: f64,
    /// The scale grows with the value (`max(scale, |value|)`), for parameters whose size is
    /// not known in advance (a drag coefficient may be 1e-5 or 1e-2).
    pub scale_relative: bool,
    /// Where fitting starts; `None`: from the default value.
    pub start: Option<f64>,
    /// A property of the place (a latitude), known from the data's metadata when it has one:
    /// then held, not fitted.
    pub from_origin: bool,
    /// The value at which the parameter's term vanishes, if it has one: with every parameter
    /// at it the effect changes nothing, and the model is the model without it (a wind of
    /// 0, a gyroscopic k of 0; a lag's τ has none). The diagnosis then predicts where the
    /// model without the effect starts a window from the fit with it.
    pub absent: Option<f64>,
}

impl ParamSpec {
    /// A parameter with the given name, unit, range and scale; fitted from its default.
    pub const fn new(
        name: &'static str,
        unit: &'static str,
        range: (f64, f64),
        scale: f64,
    ) -> Self {
        Self {
            name,
            unit,
            range,
            scale,
            scale_relative: false,
            start: None,
            from_origin: false,
            absent: None,
        }
    }

    /// The typical size at `value` (see [`scale_relative`](Self::scale_relative)).
    pub fn scale_at(&self, value: f64) -> f64 {
        if self.scale_relative {
            self.scale.max(value.abs())
        } else {
            self.scale
        }
    }

    /// `value` if it is finite and in range.
    ///
    /// # Errors
    /// [`ParamError::OutOfRange`], naming the parameter, the value and the range.
    pub fn check(&self, value: f64) -> Result<f64, ParamError> {
        let (lo, hi) = self.range;
        if value.is_finite() && value >= lo && value <= hi {
            Ok(value)
        } else {
            Err(ParamError::OutOfRange {
                name: self.name,
                value,
                lo,
                hi,
                unit: self.unit,
            })
        }
    }
}

/// An effect's static description (one per effect type).
#[derive(Debug)]
pub struct EffectInfo {
    /// Fixed name (catalogue names are fixed by the spec).
    pub name: &'static str,
    /// What it adds, in one line (help texts, README).
    pub summary: &'static str,
    /// The vehicles it applies to.
    pub applies: Applies,
    /// Its parameters, in the order of [`Effect::values`].
    pub params: &'static [ParamSpec],
    /// A new effect with default parameters for a context.
    pub make: fn(&EffectContext) -> Box<dyn Effect>,
}

impl EffectInfo {
    /// A new effect with default parameters.
    pub fn build(&'static self, ctx: &EffectContext) -> Box<dyn Effect> {
        term::build(self, ctx).unwrap_or_else(|| (self.make)(ctx))
    }

    /// The spec of a parameter by name.
    pub fn param(&self, name: &str) -> Option<&'static ParamSpec> {
        self.params.iter().find(|p| p.name == name)
    }
}

/// A channel a flight records: what a measurement effect changes ([`Effect::channels`]).
pub use wireflight_data::Channel;

/// What the sensors read at one sample, as the model predicts it: the channels a flight
/// records, in the data's frames. Measurement effects change it ([`Effect::measure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Position, NED, m.
    pub pos_ned: DVec3,
    /// Velocity, NED, m/s.
    pub vel_ned: DVec3,
    /// Attitude, body → NED.
    pub quat: DQuat,
    /// Body rates p, q, r, rad/s.
    pub rates: DVec3,
    /// Airspeed, m/s.
    pub airspeed: f64,
    /// Specific force (what an accelerometer reads), body axes, m/s².
    pub specific_force: DVec3,
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
    /// The air data of the air-relative velocity — airspeed, α, β — as the aerodynamic model
    /// takes them (a point mass: its airspeed alone, α = β = 0).
    pub air: AirData,
    /// The propeller's thrust, N, as the fixed-wing model takes it (0 for a point mass).
    pub thrust: f64,
}

/// A named parameter of an effect and its current value, for display.
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
/// All hooks default to "no effect"; an implementation gives [`info`](Self::info), its
/// parameter values (if any) and the hooks it needs — the first two, and whether it varies in
/// time and space, most simply through [`effect_basics!`].
pub trait Effect: Send + Sync + std::fmt::Debug + EffectClone {
    /// The static description: name, vehicles, parameters.
    fn info(&self) -> &'static EffectInfo;
    /// Current parameter values, in the order of `info().params`.
    fn values(&self) -> &[f64] {
        &[]
    }
    /// Mutable parameter values (set through [`set_param`](Self::set_param), which checks
    /// them).
    fn values_mut(&mut self) -> &mut [f64] {
        &mut []
    }

    /// Whether any hook depends on time itself, not only on the state (a gust, a schedule).
    /// None of the catalogue's does but `incidence_lift` (the attitude the flight recorded at
    /// that time). `true`, the default, is the safe answer for an effect
    /// that does not say: the comparison's tangent then takes the model's Jacobian afresh
    /// at every pair of steps instead of holding it while the state barely moves.
    fn varies_in_time(&self) -> bool {
        true
    }

    /// Whether any hook depends on the position itself (a density or gravity that changes
    /// with height, the ground's nearness, a wind that changes from place to place). `true`,
    /// the default, is the safe answer for an effect that does not say: the model's
    /// Jacobian then differences the position as well, where it would skip three columns
    /// that are zero.
    fn varies_in_space(&self) -> bool {
        true
    }

    /// Whether the effect is a steady wind, the same everywhere, whose parameters are its
    /// north, east and down components in m/s, in that order, and which does nothing but
    /// blow ([`wind_at`](Self::wind_at) alone). An airframe with such a wind alone is a
    /// frame moving with the air, and the comparison takes the wind's parameter columns from
    /// the start's instead of flying them. `false`, the default, is the safe answer.
    fn is_uniform_wind(&self) -> bool {
        false
    }

    /// Wind, NED, m/s, at a position (NED, m) and time (s); summed over effects.
    fn wind_at(&self, _pos_ned: DVec3, _t: f64) -> DVec3 {
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
    /// Whether the effect acts on what the sensors read rather than on the flight
    /// ([`sensors`]): then every hook above keeps its default, and the equations of motion
    /// pass it by.
    fn is_measurement(&self) -> bool {
        false
    }
    /// What the sensors read, changed in place (a bias, a scale factor, a misalignment):
    /// affine in each channel it changes, since the comparison's linearisation takes a
    /// reading's change per unit of the truth from two evaluations.
    fn measure(&self, _r: &mut Reading) {}
    /// How late the navigation solution (position and NED velocity) is read, s.
    fn nav_delay(&self) -> Option<f64> {
        None
    }
    /// The channels a measurement effect changes: on a flight that records none of them it
    /// can show nothing, and is no candidate.
    fn channels(&self) -> &'static [Channel] {
        &[]
    }
    /// A recorded channel the effect acts from that its context lacks (the attitude, for a
    /// point mass's force from the body's incidence on a model built without one): a model
    /// refuses the effect then, and the diagnosis does not offer it. `None`, the default:
    /// the effect needs nothing recorded.
    fn lacks_channel(&self) -> Option<Channel> {
        None
    }
    /// Whether the effect reads the body's angle of attack or sideslip ([`Sample::air`]): a
    /// point mass has them only from its flight's recorded attitude, and refuses the effect
    /// without one. `false`, the default.
    fn reads_incidence(&self) -> bool {
        false
    }

    /// Why the effect's force or moment at this sample is NaN or ∞, naming the values that
    /// made it so — `None` when it is finite, or for an effect that cannot tell (the
    /// default). Asked only after a flight has gone non-finite, to say why.
    fn explain_non_finite(&self, _s: &Sample) -> Option<String> {
        None
    }

    /// The effect's name.
    fn name(&self) -> &'static str {
        self.info().name
    }
    /// Whether the effect means anything for this vehicle family.
    fn applies_to(&self, vehicle: VehicleKind) -> bool {
        self.info().applies.to(vehicle)
    }
    /// Parameters and their current values.
    fn params(&self) -> Vec<Param> {
        self.info()
            .params
            .iter()
            .zip(self.values())
            .map(|(p, &value)| Param {
                name: p.name,
                value,
                unit: p.unit,
            })
            .collect()
    }
    /// The current value of a parameter.
    fn param(&self, name: &str) -> Option<f64> {
        let i = self.info().params.iter().position(|p| p.name == name)?;
        self.values().get(i).copied()
    }
    /// Set a parameter by name, checked against its range.
    ///
    /// # Errors
    /// Unknown name, or a value outside the parameter's range.
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), ParamError> {
        let info = self.info();
        let Some(i) = info.params.iter().position(|p| p.name == name) else {
            let known: Vec<&'static str> = info.params.iter().map(|p| p.name).collect();
            return Err(if known.is_empty() {
                ParamError::NoParameters {
                    effect: info.name,
                    given: name.to_string(),
                }
            } else {
                ParamError::Unknown {
                    effect: info.name,
                    given: name.to_string(),
                    known,
                }
            });
        };
        let value = info.params[i].check(value)?;
        match self.values_mut().get_mut(i) {
            Some(slot) => {
                *slot = value;
                Ok(())
            }
            None => Err(ParamError::NotStored {
                effect: info.name,
                name: info.params[i].name,
            }),
        }
    }
}

/// Cloning boxed effects (models are cloned for fitting); implemented for every `Clone`
/// effect, so no effect writes it.
pub trait EffectClone {
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn Effect>;
}

impl<T: Effect + Clone + 'static> EffectClone for T {
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
}

impl Clone for Box<dyn Effect> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The catalogue and two terms (a moment and a force of two coefficients): what the
    /// generic tests below hold every effect to.
    fn catalogue_and_terms() -> Vec<&'static EffectInfo> {
        let terms = ["m = k*thrust", "Y = c1*beta + c2*r_hat*qbar"]
            .map(|t| term::intern(&crate::expr::Term::parse(t).unwrap()).unwrap());
        CATALOGUE.iter().copied().chain(terms).collect()
    }

    fn ctx() -> EffectContext {
        EffectContext {
            origin: Origin::default(),
            span_m: 3.0,
            chord_m: 0.0,
            ..EffectContext::default()
        }
    }

    #[test]
    fn catalogue_names_are_the_effects_names_and_unique() {
        for info in CATALOGUE {
            let e = info.build(&ctx());
            assert_eq!(e.name(), info.name);
            assert_eq!(e.values().len(), info.params.len(), "{}", info.name);
            assert_eq!(
                CATALOGUE.iter().filter(|i| i.name == info.name).count(),
                1,
                "{} twice",
                info.name
            );
        }
        assert!(catalogue_effect("magic", &ctx()).is_none());
    }

    #[test]
    fn defaults_are_in_range_and_fit_starts_too() {
        for info in catalogue_and_terms() {
            let e = info.build(&ctx());
            for (p, v) in info.params.iter().zip(e.values()) {
                assert!(p.check(*v).is_ok(), "{}.{} = {v}", info.name, p.name);
                if let Some(s) = p.start {
                    assert!(p.check(s).is_ok(), "{}.{} starts at {s}", info.name, p.name);
                }
                assert!(p.scale > 0.0, "{}.{}", info.name, p.name);
            }
        }
    }

    /// The baseline of a vehicle family built for a flight that recorded an attitude (the nose
    /// 12° above the horizon, turning), so that every effect, those acting from it too, can
    /// be added.
    fn baseline_with_attitude(kind: wireflight_data::VehicleKind) -> crate::model::Model {
        use wireflight_geometry::euler::EulerZyx;
        let times = [0.0, 1.0, 2.0];
        let attitude = times.map(|t| EulerZyx::new(0.2 * t, 12f64.to_radians(), 0.1));
        let recorded = RecordedAttitude::new(&times, &attitude).map(Arc::new);
        crate::spec::ModelSpec::baseline(kind)
            .build_recorded(Origin::default(), recorded)
            .unwrap()
    }

    /// A fixed wing in flight (turning, climbing, rolling) and commands for it: where the
    /// effects' derivatives are compared.
    pub(crate) fn flying() -> (crate::model::State, wireflight_data::Controls) {
        let mut x = crate::model::State::default();
        x.set_pos_ned(glam::DVec3::new(10.0, -20.0, -150.0));
        x.set_vel(glam::DVec3::new(24.0, 1.5, 2.0));
        x.set_omega(glam::DVec3::new(0.3, -0.2, 0.1));
        x.set_attitude(wireflight_geometry::euler::EulerZyx::new(0.5, 0.1, -0.3));
        let cmd = wireflight_data::Controls {
            throttle: 0.7,
            elevator: -0.05,
            aileron: 0.02,
            rudder: 0.01,
        };
        (x, cmd)
    }

    /// An effect whose parameters all have an absent value changes nothing there: the model
    /// with it flies exactly as the model without it (what the diagnosis's prediction of the
    /// base model's starts takes for granted). At least wind, drag, the gyroscopic term and
    /// the propeller torque have one.
    #[test]
    fn an_effect_at_its_absent_values_changes_nothing() {
        use wireflight_data::VehicleKind;
        let mut tried = Vec::new();
        for info in catalogue_and_terms() {
            let Some(absent) = info
                .params
                .iter()
                .map(|p| p.absent)
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            if info.params.is_empty() {
                continue;
            }
            for kind in [VehicleKind::FixedWing, VehicleKind::PointMass] {
                let base = baseline_with_attitude(kind);
                let mut e = info.build(&base.effect_context());
                if !e.applies_to(kind) {
                    continue;
                }
                for (p, v) in info.params.iter().zip(&absent) {
                    e.set_param(p.name, *v).unwrap();
                }
                let mut with = base.clone();
                with.add_effect(e).unwrap();
                let (x, cmd) = flying();
                assert_eq!(
                    with.derivative(1.0, &x, &cmd).0,
                    base.derivative(1.0, &x, &cmd).0,
                    "{} at its absent values",
                    info.name
                );
                let truth = sensors::tests::reading();
                let mut read = truth;
                with.measure(&mut read);
                assert_eq!(read, truth, "{} at its absent values", info.name);
                assert_eq!(with.nav_delay(), 0.0, "{}", info.name);
                tried.push(info.name);
            }
        }
        for name in [
            "wind",
            "drag",
            "gyroscopic",
            "prop_torque",
            "gyro_bias",
            "nav_delay",
            "incidence_lift",
        ] {
            assert!(tried.contains(&name), "{name} has no absent values");
        }
    }

    /// An effect that says it does not depend on the position does not: the derivative at
    /// positions kilometres apart (and at another height) is the same to the bit, with the
    /// effect's parameters at their defaults and moved across their ranges. The position-
    /// dependent ones say so.
    #[test]
    fn an_effect_that_does_not_vary_in_space_does_not() {
        use wireflight_data::VehicleKind;
        let mut still = Vec::new();
        for info in catalogue_and_terms() {
            for kind in [VehicleKind::FixedWing, VehicleKind::PointMass] {
                let base = baseline_with_attitude(kind);
                let e = info.build(&base.effect_context());
                if !e.applies_to(kind) || e.varies_in_space() {
                    continue;
                }
                still.push(info.name);
                for at in [0.2, 0.5, 0.8] {
                    let mut e = e.clone();
                    for p in info.params {
                        let (lo, hi) = p.range;
                        let v = lo.max(-1e3) + at * (hi.min(1e3) - lo.max(-1e3));
                        e.set_param(p.name, v).unwrap();
                    }
                    let mut with = base.clone();
                    with.add_effect(e).unwrap();
                    let (mut x, cmd) = flying();
                    x.set_surfaces(glam::DVec3::new(-0.02, 0.01, 0.0));
                    let mut there = x;
                    there.set_pos_ned(glam::DVec3::new(-3000.0, 2500.0, -900.0));
                    let (here, there) = (
                        with.derivative(1.0, &x, &cmd),
                        with.derivative(1.0, &there, &cmd),
                    );
                    assert_eq!(here.0, there.0, "{} at {at}", info.name);
                }
            }
        }
        for name in [
            "wind",
            "drag",
            "gyroscopic",
            "prop_torque",
            "actuator_lag",
            "incidence_lift",
        ] {
            assert!(still.contains(&name), "{name} says it varies in space");
        }
        for name in ["density_altitude", "gravity_model", "ground_effect"] {
            assert!(
                !still.contains(&name),
                "{name} says it does not vary in space"
            );
        }
    }

    /// An effect that says it is a uniform wind is one: its parameters are the north, east
    /// and down components, and the airframe with it moves as the airframe without it
    /// would at the air-relative velocity (rates, attitude and moments alike; the body
    /// acceleration differs by ω × Rᵀw, the ground velocity by w), to rounding.
    #[test]
    fn an_effect_that_says_it_is_a_uniform_wind_is_one() {
        use crate::spec::ModelSpec;
        use wireflight_data::VehicleKind;
        let base = ModelSpec::baseline(VehicleKind::FixedWing)
            .build(Origin::default())
            .unwrap();
        let mut winds = Vec::new();
        for info in catalogue_and_terms() {
            let mut e = info.build(&base.effect_context());
            if !e.is_uniform_wind() {
                continue;
            }
            winds.push(info.name);
            let w = glam::DVec3::new(4.0, -3.0, 0.5);
            for (p, v) in info.params.iter().zip(w.to_array()) {
                e.set_param(p.name, v).unwrap();
            }
            let mut with = base.clone();
            with.add_effect(e).unwrap();
            let (x, cmd) = flying();
            let w_body = x.rot().transpose() * w;
            let mut air = x;
            air.set_vel(x.vel() - w_body);
            let (a, b) = (
                with.derivative(1.0, &x, &cmd),
                base.derivative(1.0, &air, &cmd),
            );
            let shift = x.omega().cross(w_body);
            let mut want = b.0;
            for k in 0..3 {
                want[k] += w[k];
                want[3 + k] -= shift[k];
            }
            for (k, (g, e)) in a.0.iter().zip(want).enumerate() {
                assert!(
                    (g - e).abs() < 1e-12 * (1.0 + e.abs()),
                    "{}[{k}]: {g} vs {e}",
                    info.name
                );
            }
        }
        assert_eq!(winds, ["wind"]);
    }

    #[test]
    fn set_param_checks_names_and_ranges() {
        let mut lag = find("actuator_lag").unwrap().build(&ctx());
        assert!(lag.set_param("tau_s", 0.2).is_ok());
        assert_eq!(lag.param("tau_s"), Some(0.2));
        for bad in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
            let e = lag.set_param("tau_s", bad).unwrap_err().to_string();
            assert!(e.contains("tau_s") && e.contains("range"), "{e}");
        }
        assert_eq!(
            lag.param("tau_s"),
            Some(0.2),
            "a refused value changes nothing"
        );
        let e = lag.set_param("speed", 1.0).unwrap_err().to_string();
        assert!(
            e.contains("no parameter `speed`") && e.contains("tau_s"),
            "{e}"
        );
        let mut density = find("density_altitude").unwrap().build(&ctx());
        assert!(density
            .set_param("k", 1.0)
            .unwrap_err()
            .to_string()
            .contains("no parameters"));
    }
}

/// A quiet [`Sample`] for the effects' unit tests.
#[cfg(test)]
pub(crate) mod tests_support {
    use super::*;

    /// At rest at the origin, sea-level density, standard gravity, no controls.
    pub fn sample() -> Sample {
        Sample {
            t: 0.0,
            pos_ned: DVec3::ZERO,
            vel_ned: DVec3::ZERO,
            rot: DMat3::IDENTITY,
            omega: DVec3::ZERO,
            altitude_m: 0.0,
            rho: RHO_SEA_LEVEL,
            g: wireflight_data::G0,
            air_vel_ned: DVec3::ZERO,
            controls: Controls::default(),
            mass: 1.0,
            air: AirData::default(),
            thrust: 0.0,
        }
    }
}
