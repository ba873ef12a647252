//! The model: a vehicle family with its parameters plus a list of effects, its equations of
//! motion, and a fixed-step RK4 integrator.
//!
//! State vector layout ([`State`], 16 numbers, so both families share one integrator):
//!
//! | index | point-mass | fixed-wing |
//! |---|---|---|
//! | 0..3 | position NED, m | position NED, m |
//! | 3..6 | velocity NED, m/s | body velocity u, v, w (FRD), m/s |
//! | 6..10 | unused | attitude quaternion body→NED (x, y, z, w) |
//! | 10..13 | unused | body rates p, q, r, rad/s |
//! | 13..16 | unused | surface positions δe, δa, δr, rad (move only under `actuator_lag`) |
//!
//! The fixed-wing attitude is integrated as a quaternion (no singularity at θ = ±90°) and
//! reported as aerospace z-y-x angles through [`wireflight_geometry::euler::EulerZyx::from_matrix`], as the
//! spec allows. The quaternion is renormalised after every step.

use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};

use super::effects::{
    Channel, Effect, EffectContext, Origin, Reading, RecordedAttitude, Sample, RHO_SEA_LEVEL,
};
use super::params::keys::AircraftKeyError;
use super::params::{FixedWingParams, Gammas};
use wireflight_data::{Controls, VehicleKind, G0};
use wireflight_geometry::euler::EulerZyx;

pub use super::aero::{aero_force_moment, air_angles, stall_blend, AirData};
use super::aero::{flight_path_axes, propeller_thrust, stall_blend_with};

/// Number of state variables.
pub const STATE_LEN: usize = 16;

/// An effect or an aircraft number the model cannot take.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// An effect for the other vehicle family.
    #[error("effect `{effect}` does not apply to a {vehicle} model")]
    NotApplicable {
        /// The effect.
        effect: &'static str,
        /// The model's vehicle family.
        vehicle: VehicleKind,
    },
    /// An effect of that name is already in the model.
    #[error("effect `{0}` is already in the model")]
    Duplicate(&'static str),
    /// An effect that acts from a recorded channel the model was built without.
    #[error(
        "effect `{effect}` acts from the {channel} a flight recorded, and this model has none: \
         its flight records no {channel}, or it is flown without one flight's record \
         (`simulate`, reference flights)"
    )]
    LacksChannel {
        /// The effect.
        effect: &'static str,
        /// The channel it needs.
        channel: Channel,
    },
    /// A point mass has no parameter set.
    #[error("a point mass has no aircraft parameter `{0}`")]
    PointMass(String),
    /// The parameter set refuses the value.
    #[error(transparent)]
    Aircraft(#[from] AircraftKeyError),
}

/// The integrated state (layout in the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State(pub [f64; STATE_LEN]);

impl Default for State {
    fn default() -> Self {
        let mut x = [0.0; STATE_LEN];
        x[9] = 1.0; // identity quaternion
        State(x)
    }
}

impl State {
    /// Position, NED, m.
    pub fn pos_ned(&self) -> DVec3 {
        DVec3::new(self.0[0], self.0[1], self.0[2])
    }
    /// Velocity slot: NED for a point mass, body (u, v, w) for a fixed-wing.
    pub fn vel(&self) -> DVec3 {
        DVec3::new(self.0[3], self.0[4], self.0[5])
    }
    /// Attitude quaternion body → NED (fixed-wing).
    pub fn quat(&self) -> DQuat {
        DQuat::from_xyzw(self.0[6], self.0[7], self.0[8], self.0[9])
    }
    /// Body rates p, q, r, rad/s (fixed-wing).
    pub fn omega(&self) -> DVec3 {
        DVec3::new(self.0[10], self.0[11], self.0[12])
    }
    /// Surface positions δe, δa, δr, rad (fixed-wing under `actuator_lag`).
    pub fn surfaces(&self) -> DVec3 {
        DVec3::new(self.0[13], self.0[14], self.0[15])
    }
    /// Set the position.
    pub fn set_pos_ned(&mut self, p: DVec3) {
        self.0[0..3].copy_from_slice(&p.to_array());
    }
    /// Set the velocity slot.
    pub fn set_vel(&mut self, v: DVec3) {
        self.0[3..6].copy_from_slice(&v.to_array());
    }
    /// Set the attitude from aerospace angles.
    pub fn set_attitude(&mut self, e: EulerZyx) {
        let q = DQuat::from_mat3(&e.to_matrix()).normalize();
        self.0[6..10].copy_from_slice(&q.to_array());
    }
    /// Set the body rates.
    pub fn set_omega(&mut self, w: DVec3) {
        self.0[10..13].copy_from_slice(&w.to_array());
    }
    /// Set the surface positions.
    pub fn set_surfaces(&mut self, s: DVec3) {
        self.0[13..16].copy_from_slice(&s.to_array());
    }
    /// A fixed wing's state from what a flight records: position (NED), body velocity,
    /// attitude, body rates, and the surfaces where the controls put them.
    pub fn measured(
        pos_ned: DVec3,
        vel_body: DVec3,
        attitude: EulerZyx,
        omega: DVec3,
        controls: &Controls,
    ) -> State {
        let mut x = State::default();
        x.set_pos_ned(pos_ned);
        x.set_vel(vel_body);
        x.set_attitude(attitude);
        x.set_omega(omega);
        x.set_surfaces(DVec3::new(
            controls.elevator,
            controls.aileron,
            controls.rudder,
        ));
        x
    }
    /// Body → NED rotation matrix.
    pub fn rot(&self) -> DMat3 {
        DMat3::from_quat(self.quat())
    }
    /// Aerospace z-y-x angles of the attitude.
    pub fn attitude(&self) -> EulerZyx {
        EulerZyx::from_matrix(self.rot()).0
    }
    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
}

/// The surface deflections in effect under an actuator lag `tau` (the state's), or without
/// one (the commands).
#[inline]
fn surfaces_under(tau: Option<f64>, x: &State, cmd: &Controls) -> Controls {
    match tau {
        Some(_) => {
            let s = x.surfaces();
            Controls {
                throttle: cmd.throttle,
                elevator: s.x,
                aileron: s.y,
                rudder: s.z,
            }
        }
        None => *cmd,
    }
}

/// What the model's derivative at a time and state takes from the time, position, velocity
/// and attitude alone — not from the commands, the body rates or the surfaces: the rotation,
/// the environment, the air data and the stall blend (the square roots, arctangents and the
/// exponential of a derivative). Where several derivatives share one ([`Model::frame`],
/// [`Model::derivative_in`]), the others evaluate only what the commands and rates change.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    rot: DMat3,
    wind: DVec3,
    rho: f64,
    g: f64,
    /// Air-relative velocity, body axes (zero for a point mass).
    v_r: DVec3,
    air: AirData,
    stall_sigma: f64,
}

/// What a derivative asks of the effects besides their forces, asked once for all four of a
/// step's ([`Model::step`]): each is a call through the effect's vtable, and the term of the
/// benchmark `m = k*thrust` costs little more than those calls.
#[derive(Clone, Copy, Debug)]
struct EffectRoles {
    /// The actuator lag's time constant, s, if an effect adds one.
    tau: Option<f64>,
    /// Bit i set: effect i acts on the body (neither a measurement nor a uniform wind, which
    /// only blows: its air is in the frame already). Effects past the first
    /// [`EffectRoles::KNOWN`] are asked at each derivative.
    on_body: u64,
}

impl EffectRoles {
    /// How many effects' roles the mask holds.
    const KNOWN: usize = 64;

    /// Whether effect `e`, the model's `i`-th, acts on the body.
    #[inline]
    fn acts_on_body(&self, i: usize, e: &dyn Effect) -> bool {
        if i < Self::KNOWN {
            self.on_body & (1 << i) != 0
        } else {
            !e.is_measurement() && !e.is_uniform_wind()
        }
    }
}

/// The vehicle family and its parameters.
#[derive(Clone, Debug)]
pub enum Vehicle {
    /// Point mass; effects are accelerations (mass only scales nothing in the catalogue).
    PointMass,
    /// Fixed-wing aircraft.
    FixedWing(Box<FixedWingParams>),
}

impl Vehicle {
    /// The family.
    pub fn kind(&self) -> VehicleKind {
        match self {
            Vehicle::PointMass => VehicleKind::PointMass,
            Vehicle::FixedWing(_) => VehicleKind::FixedWing,
        }
    }
    /// Wing span, m (0 for a point mass).
    pub fn span(&self) -> f64 {
        match self {
            Vehicle::PointMass => 0.0,
            Vehicle::FixedWing(p) => p.geometry.b,
        }
    }
}

/// A model: vehicle + origin + effects. Cheap to clone (for fitting).
#[derive(Clone, Debug)]
pub struct Model {
    /// Vehicle family and parameters.
    pub vehicle: Vehicle,
    /// Geodetic origin of the NED frame.
    pub origin: Origin,
    /// Effects, applied in order.
    pub effects: Vec<Box<dyn Effect>>,
    gammas: Gammas,
    /// e^{M·α0} of the stall blend, taken once ([`super::aero::stall_blend_with`]).
    stall_c: f64,
    /// A wind added to the effects' winds, NED, m/s ([`Model::set_air_offset`]).
    air_offset: DVec3,
    /// The attitude of the flight the model was built for, which effects added to it may act
    /// from ([`Model::set_recorded_attitude`]).
    recorded_attitude: Option<Arc<RecordedAttitude>>,
}

/// e^{M·α0} of a fixed wing's stall blend (NaN for a point mass: never used).
fn stall_c(vehicle: &Vehicle) -> f64 {
    match vehicle {
        Vehicle::FixedWing(p) => (p.longitudinal.m_blend * p.longitudinal.alpha0).exp(),
        Vehicle::PointMass => f64::NAN,
    }
}

impl Model {
    /// A baseline model (no effects).
    pub fn new(vehicle: Vehicle, origin: Origin) -> Self {
        let gammas = match &vehicle {
            Vehicle::FixedWing(p) => Gammas::new(&p.mass),
            Vehicle::PointMass => Gammas { g: [0.0; 8] },
        };
        Self {
            stall_c: stall_c(&vehicle),
            vehicle,
            origin,
            effects: Vec::new(),
            gammas,
            air_offset: DVec3::ZERO,
            recorded_attitude: None,
        }
    }

    /// Give the model the attitude its flight recorded, for the effects added after this
    /// that act from it ([`EffectContext::recorded_attitude`]; those added before keep theirs),
    /// and for a point mass's air data and force axes, which read the model's record at every
    /// step ([`Model::point_mass_air`]): set it before a point mass's terms are added, and
    /// keep it while they act.
    pub fn set_recorded_attitude(&mut self, attitude: Option<Arc<RecordedAttitude>>) {
        self.recorded_attitude = attitude;
    }

    /// Whether the model has its flight's recorded attitude to act from
    /// ([`Model::set_recorded_attitude`]): then a point mass reads the body's α and β.
    pub fn has_recorded_attitude(&self) -> bool {
        self.recorded_attitude.is_some()
    }

    /// Add an effect.
    ///
    /// # Errors
    /// The effect does not apply to this vehicle, acts from a recorded channel it was built
    /// without ([`Effect::lacks_channel`]), or one of that name is already present.
    pub fn add_effect(&mut self, effect: Box<dyn Effect>) -> Result<(), ModelError> {
        if !effect.applies_to(self.vehicle.kind()) {
            return Err(ModelError::NotApplicable {
                effect: effect.name(),
                vehicle: self.vehicle.kind(),
            });
        }
        // A point mass reads α and β from its flight's recorded attitude, where it has one.
        let blind_incidence = matches!(self.vehicle, Vehicle::PointMass)
            && self.recorded_attitude.is_none()
            && effect.reads_incidence();
        let lacking = effect
            .lacks_channel()
            .or(blind_incidence.then_some(Channel::Attitude));
        if let Some(channel) = lacking {
            return Err(ModelError::LacksChannel {
                effect: effect.name(),
                channel,
            });
        }
        if self.has_effect(effect.name()) {
            return Err(ModelError::Duplicate(effect.name()));
        }
        self.effects.push(effect);
        Ok(())
    }

    /// Whether any effect acts on what the sensors read ([`Effect::is_measurement`]).
    pub fn has_measurement_effects(&self) -> bool {
        self.effects.iter().any(|e| e.is_measurement())
    }

    /// How late the navigation solution is read, s: the effects' delays summed (0 without).
    pub fn nav_delay(&self) -> f64 {
        self.effects.iter().filter_map(|e| e.nav_delay()).sum()
    }

    /// What the sensors read of `truth`: every measurement effect's
    /// [`Effect::measure`], in model order (the delay is the comparison's, over a flight).
    pub fn measure(&self, truth: &mut Reading) {
        for e in self.effects.iter().filter(|e| e.is_measurement()) {
            e.measure(truth);
        }
    }

    /// The value of a parameter of the aircraft's set (`c_m_alpha`, `mass_kg`, …; see
    /// [`crate::params::keys`]); `None` for a point mass or an unknown key.
    pub fn aircraft(&self, key: &str) -> Option<f64> {
        match &self.vehicle {
            Vehicle::FixedWing(p) => super::params::keys::get(p, key),
            Vehicle::PointMass => None,
        }
    }

    /// Set a parameter of the aircraft's set (checked; the inertia constants follow).
    ///
    /// # Errors
    /// A point mass, an unknown key, a value out of range or a non-physical set.
    pub fn set_aircraft(&mut self, key: &str, value: f64) -> Result<(), ModelError> {
        match &mut self.vehicle {
            Vehicle::FixedWing(p) => {
                super::params::keys::set(p, key, value)?;
                self.gammas = Gammas::new(&p.mass);
                self.stall_c = stall_c(&self.vehicle);
                Ok(())
            }
            Vehicle::PointMass => Err(ModelError::PointMass(key.to_string())),
        }
    }

    /// What the defaults of an effect added to this model depend on.
    pub fn effect_context(&self) -> EffectContext {
        EffectContext {
            origin: self.origin,
            span_m: self.vehicle.span(),
            chord_m: match &self.vehicle {
                Vehicle::PointMass => 0.0,
                Vehicle::FixedWing(p) => p.geometry.c,
            },
            recorded_attitude: self.recorded_attitude.clone(),
        }
    }

    /// Whether an effect of that name is present.
    pub fn has_effect(&self, name: &str) -> bool {
        self.effects.iter().any(|e| e.name() == name)
    }

    /// Names of the effects, in order.
    pub fn effect_names(&self) -> Vec<String> {
        self.effects.iter().map(|e| e.name().to_string()).collect()
    }

    /// Mutable access to an effect by name.
    pub fn effect_mut(&mut self, name: &str) -> Option<&mut Box<dyn Effect>> {
        self.effects.iter_mut().find(|e| e.name() == name)
    }

    fn actuator_tau(&self) -> Option<f64> {
        self.effects.iter().find_map(|e| e.actuator_tau())
    }

    /// The surface deflections in effect: the lagged state under `actuator_lag`, else the
    /// commands.
    pub fn surfaces_in_effect(&self, x: &State, cmd: &Controls) -> Controls {
        surfaces_under(self.actuator_tau(), x, cmd)
    }

    /// Altitude above sea level, m, of a NED position.
    pub fn altitude(&self, pos_ned: DVec3) -> f64 {
        self.origin.altitude_m - pos_ned.z
    }

    /// Environment at a position and time: (wind NED, density, gravity magnitude).
    fn environment(&self, pos_ned: DVec3, t: f64) -> (DVec3, f64, f64) {
        let h = self.altitude(pos_ned);
        let base_rho = match &self.vehicle {
            Vehicle::PointMass => RHO_SEA_LEVEL,
            Vehicle::FixedWing(p) => p.geometry.rho,
        };
        let mut wind = self.air_offset;
        let mut rho = base_rho;
        let mut g = G0;
        for e in &self.effects {
            wind += e.wind_at(pos_ned, t);
            rho = e.density(h, rho);
            g = e.gravity(h, g);
        }
        (wind, rho, g)
    }

    /// Wind, NED, m/s, at a position and time (the sum of the effects' winds).
    pub fn wind_at(&self, pos_ned: DVec3, t: f64) -> DVec3 {
        self.air_offset
            + self
                .effects
                .iter()
                .map(|e| e.wind_at(pos_ned, t))
                .sum::<DVec3>()
    }

    /// Add `wind` (NED, m/s) to the air everywhere, on top of the effects' winds: for a caller
    /// that estimates the air's motion itself as it goes (the filter-error method's gust
    /// states move it between steps). It is part of no effect: nothing fits it, and
    /// [`Model::wind_at`], the air data and every derivative see it. Zero for a new model.
    pub fn set_air_offset(&mut self, wind: DVec3) {
        self.air_offset = wind;
    }

    /// The wind added by [`Model::set_air_offset`], NED, m/s.
    pub fn air_offset(&self) -> DVec3 {
        self.air_offset
    }

    /// Whether the equations depend on the position itself (an effect says so, or does not
    /// say): the bare airframe's air and gravity are the same everywhere.
    pub fn varies_in_space(&self) -> bool {
        self.effects.iter().any(|e| e.varies_in_space())
    }

    /// Whether the equations depend on time itself (an effect says so, or does not say; or
    /// a point mass's force terms act along the wind axes of the attitude its flight recorded
    /// at each time, [`Model::point_mass_air`]).
    pub fn varies_in_time(&self) -> bool {
        let along_the_record = matches!(self.vehicle, Vehicle::PointMass)
            && self.recorded_attitude.is_some()
            && self
                .effects
                .iter()
                .any(|e| super::effects::term::axis_of(e.info()).is_some());
        along_the_record || self.effects.iter().any(|e| e.varies_in_time())
    }

    /// Air data of a fixed-wing state at time `t` (airspeed, α, β, ρ).
    pub fn air_data(&self, t: f64, x: &State) -> AirData {
        let (wind, rho) = self.air_at(x.pos_ned(), t);
        let v_r = x.vel() - x.rot().transpose() * wind;
        air_angles(v_r, rho)
    }

    /// The air at a position and time: (wind NED, m/s; density, kg/m³).
    pub fn air_at(&self, pos_ned: DVec3, t: f64) -> (DVec3, f64) {
        let (wind, rho, _) = self.environment(pos_ned, t);
        (wind, rho)
    }

    /// Time derivative of the state under commands `cmd` (held constant).
    pub fn derivative(&self, t: f64, x: &State, cmd: &Controls) -> State {
        self.derivative_in(t, x, cmd, &self.frame(t, x))
    }

    /// What the derivative at time `t` and state `x` takes from the time, position, velocity
    /// and attitude alone ([`Frame`]).
    pub fn frame(&self, t: f64, x: &State) -> Frame {
        let (wind, rho, g) = self.environment(x.pos_ned(), t);
        match &self.vehicle {
            Vehicle::PointMass => Frame {
                rot: DMat3::IDENTITY,
                wind,
                rho,
                g,
                v_r: DVec3::ZERO,
                air: AirData::default(),
                stall_sigma: 0.0,
            },
            Vehicle::FixedWing(p) => {
                let rot = DMat3::from_quat(x.quat());
                // In still air the body velocity is the air-relative one: the air data then
                // need not wait for the rotation (they begin the derivative's longest chain).
                let v_r = if wind == DVec3::ZERO {
                    x.vel()
                } else {
                    x.vel() - rot.transpose() * wind
                };
                let air = air_angles(v_r, rho);
                let lon = &p.longitudinal;
                Frame {
                    rot,
                    wind,
                    rho,
                    g,
                    v_r,
                    air,
                    stall_sigma: stall_blend_with(air.alpha, lon.m_blend, lon.alpha0, self.stall_c),
                }
            }
        }
    }

    /// What an accelerometer at the centre of gravity reads at time `t` and state `x` under
    /// commands `cmd`: the specific force, m/s², in body axes (FRD) for a fixed wing and in
    /// NED for a point mass — the acceleration relative to inertial space less gravity, so a
    /// level, unaccelerated airplane reads (0, 0, −g). It is the derivative's force over
    /// mass, read back from the derivative itself (u̇ + ω × v − Rᵀ·g), so it can never
    /// disagree with the dynamics the model flies.
    pub fn specific_force(&self, t: f64, x: &State, cmd: &Controls) -> DVec3 {
        let frame = self.frame(t, x);
        let d = self.derivative_in(t, x, cmd, &frame);
        let acc = DVec3::new(d.0[3], d.0[4], d.0[5]);
        let gravity = DVec3::new(0.0, 0.0, frame.g);
        match self.vehicle {
            Vehicle::PointMass => acc - gravity,
            Vehicle::FixedWing(_) => {
                acc + x.omega().cross(x.vel()) - frame.rot.transpose() * gravity
            }
        }
    }

    /// [`derivative`](Self::derivative) with its [`Frame`] given: `frame` must be
    /// [`frame`](Self::frame) of the same time and of a state that differs from `x` at most
    /// in its body rates and surfaces (RK4's first stage and a read inside its step under
    /// other commands; the rate columns of the model's Jacobian).
    pub fn derivative_in(&self, t: f64, x: &State, cmd: &Controls, frame: &Frame) -> State {
        self.derivative_with(t, x, cmd, frame, &self.roles())
    }

    /// [`derivative_in`](Self::derivative_in) with the effects' roles asked already.
    fn derivative_with(
        &self,
        t: f64,
        x: &State,
        cmd: &Controls,
        frame: &Frame,
        roles: &EffectRoles,
    ) -> State {
        match &self.vehicle {
            Vehicle::PointMass => self.point_mass_derivative(t, x, frame),
            Vehicle::FixedWing(p) => self.fixed_wing_derivative(p, t, x, cmd, frame, roles),
        }
    }

    /// What every derivative asks of the effects besides their forces, asked once: a step's
    /// four derivatives share it.
    fn roles(&self) -> EffectRoles {
        let mut on_body = 0u64;
        for (i, e) in self.effects.iter().take(EffectRoles::KNOWN).enumerate() {
            if !e.is_measurement() && !e.is_uniform_wind() {
                on_body |= 1 << i;
            }
        }
        EffectRoles {
            tau: self.actuator_tau(),
            on_body,
        }
    }

    /// A point mass's air data and the axes its force terms act along, for its air-relative
    /// velocity at time `t`. Without a recorded attitude: its airspeed alone (α = β = 0) and
    /// its flight-path axes ([`flight_path_axes`]). With one: the recorded body's α and β of
    /// that velocity, and the wind axes that body defines — `X` along the velocity, `Z`
    /// normal to it in the body's x–z plane (negative: the body's lift, toward −z_b, its bank
    /// included), `Y` completing the triad (the side force).
    pub fn point_mass_air(&self, t: f64, air_vel_ned: DVec3, rho: f64) -> (AirData, DMat3) {
        let Some(attitude) = &self.recorded_attitude else {
            let air = AirData {
                airspeed: air_vel_ned.length(),
                rho,
                ..AirData::default()
            };
            return (air, flight_path_axes(air_vel_ned));
        };
        let rot = attitude.rotation_at(t);
        let body = rot.transpose() * air_vel_ned;
        let air = air_angles(body, rho);
        if air.airspeed < 0.1 || !air.airspeed.is_finite() {
            return (air, rot);
        }
        let along = body / air.airspeed;
        // Normal to the velocity in the x–z plane, pointing to +z_b: (−sin α, 0, cos α).
        let down = DVec3::new(-air.sin_alpha, 0.0, air.cos_alpha);
        let side = down.cross(along);
        (air, rot * DMat3::from_cols(along, side, down))
    }

    fn point_mass_derivative(&self, t: f64, x: &State, frame: &Frame) -> State {
        let pos = x.pos_ned();
        let vel = x.vel();
        // The airspeed of the air-relative velocity (a term's `airspeed` and `qbar`); a point
        // mass has no body, so no α or β unless its flight recorded the body's attitude.
        let (air, axes) = self.point_mass_air(t, vel - frame.wind, frame.rho);
        let s = Sample {
            t,
            pos_ned: pos,
            vel_ned: vel,
            rot: DMat3::IDENTITY,
            omega: DVec3::ZERO,
            altitude_m: self.altitude(pos),
            rho: frame.rho,
            g: frame.g,
            air_vel_ned: vel - frame.wind,
            controls: Controls::default(),
            mass: 1.0,
            air,
            thrust: 0.0,
        };
        let mut acc = DVec3::new(0.0, 0.0, frame.g);
        // A point mass's body axes are its flight-path (or wind) axes: a force an effect
        // gives in body axes (a force term, per unit mass) is turned to NED through them.
        let mut path_force = DVec3::ZERO;
        for e in &self.effects {
            acc += e.accel_ned(&s);
            path_force += e.force_moment_body(&s).0;
        }
        if path_force != DVec3::ZERO {
            acc += axes * path_force;
        }
        let mut d = [0.0; STATE_LEN];
        d[0..3].copy_from_slice(&vel.to_array());
        d[3..6].copy_from_slice(&acc.to_array());
        State(d)
    }

    #[allow(clippy::too_many_arguments)]
    fn fixed_wing_derivative(
        &self,
        p: &FixedWingParams,
        t: f64,
        x: &State,
        cmd: &Controls,
        frame: &Frame,
        roles: &EffectRoles,
    ) -> State {
        let uvw = x.vel();
        let q = x.quat();
        let rot = frame.rot;
        let omega = x.omega();
        let tau = roles.tau;
        let ctl = surfaces_under(tau, x, cmd);
        let vel_ned = rot * uvw;

        let mut induced_factor = 1.0;
        let mut force = DVec3::ZERO;
        let mut moment = DVec3::ZERO;
        let mut acc_ned = DVec3::new(0.0, 0.0, frame.g);
        // What the effects see, made once and only when one acts on the body: the bare
        // airframe (every flight of a model without effects), a wind (it only blows: its air
        // is in the frame already) and a measurement effect have no use for it. One pass.
        let mut sample: Option<Sample> = None;
        for (i, e) in self.effects.iter().enumerate() {
            if !roles.acts_on_body(i, e.as_ref()) {
                continue;
            }
            let s = sample.get_or_insert_with(|| self.body_sample(p, t, x, vel_ned, &ctl, frame));
            induced_factor *= e.induced_drag_factor(s);
            let (f, m) = e.force_moment_body(s);
            force += f;
            moment += m;
            acc_ned += e.accel_ned(s);
        }
        let (f_aero, m_aero) = aero_force_moment(
            p,
            &frame.air,
            omega,
            &ctl,
            induced_factor,
            frame.stall_sigma,
        );
        // Gravity (and the world-frame accelerations of effects) in body axes, times mass.
        force += f_aero + p.mass.mass_kg * (rot.transpose() * acc_ned);
        moment += m_aero;

        let m = p.mass.mass_kg;
        let (pr, qr, rr) = (omega.x, omega.y, omega.z);
        let (u, v, w) = (uvw.x, uvw.y, uvw.z);
        let uvw_dot =
            DVec3::new(rr * v - qr * w, pr * w - rr * u, qr * u - pr * v) + force * (1.0 / m);
        let gm = &self.gammas.g;
        let (l, mm, n) = (moment.x, moment.y, moment.z);
        let omega_dot = DVec3::new(
            gm[0] * pr * qr - gm[1] * qr * rr + gm[2] * l + gm[3] * n,
            gm[4] * pr * rr - gm[5] * (pr * pr - rr * rr) + mm / p.mass.jy,
            gm[6] * pr * qr - gm[0] * qr * rr + gm[3] * l + gm[7] * n,
        );
        // q̇ = ½ q ⊗ (ω, 0), ω in body axes.
        let q_dot = (q * DQuat::from_xyzw(pr, qr, rr, 0.0)) * 0.5;
        let surf_dot = match tau {
            Some(tau) => (DVec3::new(cmd.elevator, cmd.aileron, cmd.rudder) - x.surfaces()) / tau,
            None => DVec3::ZERO,
        };

        let mut d = [0.0; STATE_LEN];
        d[0..3].copy_from_slice(&vel_ned.to_array());
        d[3..6].copy_from_slice(&uvw_dot.to_array());
        d[6..10].copy_from_slice(&q_dot.to_array());
        d[10..13].copy_from_slice(&omega_dot.to_array());
        d[13..16].copy_from_slice(&surf_dot.to_array());
        State(d)
    }

    /// What the body-force effects see of a fixed wing at time `t` and state `x` (whose
    /// velocity in NED is `vel_ned`, the derivative's own) under the surfaces and throttle
    /// `ctl`, in `frame`.
    fn body_sample(
        &self,
        p: &FixedWingParams,
        t: f64,
        x: &State,
        vel_ned: DVec3,
        ctl: &Controls,
        frame: &Frame,
    ) -> Sample {
        let pos = x.pos_ned();
        Sample {
            t,
            pos_ned: pos,
            vel_ned,
            rot: frame.rot,
            omega: x.omega(),
            altitude_m: self.altitude(pos),
            rho: frame.rho,
            g: frame.g,
            // In still air the air-relative velocity is the body velocity (the frame's is
            // that same vector), and its NED form the one the derivative has.
            air_vel_ned: if frame.wind == DVec3::ZERO {
                vel_ned
            } else {
                frame.rot * frame.v_r
            },
            controls: *ctl,
            mass: p.mass.mass_kg,
            air: frame.air,
            thrust: propeller_thrust(&p.propulsion, &frame.air, ctl.throttle),
        }
    }

    /// Why the forces at time `t` and state `x` under `cmd` are not finite, if an effect can
    /// tell ([`Effect::explain_non_finite`]: a term names its operation and the values that
    /// made it NaN or ∞) — asked after a flight has gone non-finite. `None` for a point mass,
    /// or where no effect says.
    pub fn explain_non_finite(&self, t: f64, x: &State, cmd: &Controls) -> Option<String> {
        let Vehicle::FixedWing(p) = &self.vehicle else {
            return None;
        };
        let frame = self.frame(t, x);
        let ctl = surfaces_under(self.actuator_tau(), x, cmd);
        let s = self.body_sample(p, t, x, frame.rot * x.vel(), &ctl, &frame);
        self.effects
            .iter()
            .filter(|e| !e.is_measurement())
            .find_map(|e| e.explain_non_finite(&s))
    }

    /// The first sample of a recorded flight at whose measured state (position, velocity,
    /// attitude, rates, controls; the surfaces at their commands) an effect's force is NaN
    /// or ∞, and why ([`explain_non_finite`](Self::explain_non_finite)): what a comparison
    /// checks before it flies, so that a term which cannot be evaluated on the flight stops
    /// it with the time and the values instead of leaving NaN in its tables. `None` for a
    /// point mass, data without attitude, or where every force is finite.
    pub fn explain_on_data(&self, d: &wireflight_data::FlightData) -> Option<(f64, String)> {
        if !matches!(self.vehicle, Vehicle::FixedWing(_))
            || !self.effects.iter().any(|e| !e.is_measurement())
        {
            return None;
        }
        let attitude = d.attitude.as_ref()?;
        for (i, &t) in d.time.iter().enumerate() {
            let cmd = d
                .controls
                .as_ref()
                .and_then(|c| c.get(i).copied())
                .unwrap_or_default();
            let omega = d.rates_body.as_ref().map_or(DVec3::ZERO, |r| r[i]);
            let mut x = State::measured(d.pos_ned[i], DVec3::ZERO, attitude[i], omega, &cmd);
            let vel_ned = d.vel_ned.as_ref().map_or(DVec3::ZERO, |v| v[i]);
            x.set_vel(match &d.vel_body {
                Some(v) => v[i],
                None => x.rot().transpose() * vel_ned,
            });
            if !x.is_finite() {
                continue;
            }
            if let Some(why) = self.explain_non_finite(t, &x, &cmd) {
                return Some((t, why));
            }
        }
        None
    }

    /// Where and why [`advance`](Self::advance) from `t0` to `t1` goes non-finite: the
    /// sub-step it does so in is flown again and the state at each of its RK4 stages asked
    /// ([`explain_non_finite`](Self::explain_non_finite)); the time of the stage and the
    /// effect's account, or `None` where no effect can tell (or the flight stays finite).
    pub fn explain_advance(
        &self,
        t0: f64,
        x: &State,
        cmd: &Controls,
        t1: f64,
        max_dt: f64,
    ) -> Option<(f64, String)> {
        let (n, dt) = Self::substeps(t1 - t0, max_dt);
        let mut s = *x;
        for i in 0..n {
            let t = t0 + i as f64 * dt;
            let next = self.step(t, &s, cmd, dt);
            if next.is_finite() {
                s = next;
                continue;
            }
            // The stages' states x + ½h·k₁, x + ½h·k₂, x + h·k₃ (the lag's surfaces aside).
            let mut probe = s;
            for frac in [0.0, 0.5, 0.5, 1.0] {
                let at = t + frac * dt;
                if frac > 0.0 {
                    let k = self.derivative(at, &probe, cmd);
                    for (p, (x0, d)) in probe.0.iter_mut().zip(s.0.iter().zip(k.0)) {
                        *p = x0 + frac * dt * d;
                    }
                }
                if let Some(why) = self.explain_non_finite(at, &probe, cmd) {
                    return Some((at, why));
                }
            }
            return None;
        }
        None
    }

    /// One RK4 step of length `dt` with commands held constant; renormalises the quaternion.
    ///
    /// Under actuator lag the surfaces are not integrated by RK4: with the command held they
    /// follow cmd + (s₀ − cmd)·e^(−t/τ) exactly, and every stage uses that value. A short lag
    /// is stiff (RK4 is unstable for dt > 2.8τ), and the exact solution is what the comparison
    /// reconstructs from the command history, so both agree for any τ.
    pub fn step(&self, t: f64, x: &State, cmd: &Controls, dt: f64) -> State {
        let roles = self.roles();
        let lag = roles.tau.map(|tau| {
            let target = DVec3::new(cmd.elevator, cmd.aileron, cmd.rudder);
            let s0 = x.surfaces();
            move |h: f64| target + (s0 - target) * (-h / tau).exp()
        });
        self.rk4(
            t,
            x,
            dt,
            [cmd; 4],
            lag.as_ref().map(|f| f as &dyn Fn(f64) -> DVec3),
            &roles,
        )
        .end
    }

    /// One RK4 step across several samples of zero-order-held commands (`held`), for data
    /// sampled faster than the integration step: the step's cost no longer grows with the
    /// data rate. The stages take the command in force at the step's start (k₁) and, for k₂ =
    /// k₃ and k₄, the values that make the step integrate the held commands like the exact
    /// solution to second order in h for a system linear in them: with m₀ = ∫u/h and m₁ =
    /// ∫(h−s)u ds/h², the stage commands satisfy u₁ + 4c + c₄ = 6m₀ and u₁ + 2c = 6m₁ (for
    /// two samples, c = ⅝u₀ + ⅜u₁ and c₄ = −½u₀ + 3/2·u₁; a constant command gives itself).
    /// A command switch inside the step then leaves an error of order h³·Δu instead of
    /// h²·Δu. Surfaces under actuator lag follow the held commands exactly, piece by piece.
    /// The result keeps the stages for [`Rk4Step::at`], the state inside the step.
    /// Without an interval of positive length, the step stays at `x`.
    pub fn step_held(&self, x: &State, held: &HeldCommands) -> Rk4Step {
        let n = held.len();
        let (t0, h) = match (held.times.first(), held.times.last()) {
            (Some(&t0), Some(&t1)) if n > 0 && t1 - t0 > 0.0 => (t0, t1 - t0),
            _ => {
                return Rk4Step {
                    t: held.times.first().copied().unwrap_or(0.0),
                    start: *x,
                    cmds: [Controls::default(); 3],
                    frame: None,
                    stages: [State([0.0; STATE_LEN]); 4],
                    dt: 0.0,
                    end: *x,
                }
            }
        };
        let first = held.command(0);
        // m₀ and m₁ per command channel.
        let mut m0 = [0.0; 4];
        let mut m1 = [0.0; 4];
        for (a, b, c) in held.segments() {
            let w0 = (b - a) / h;
            let w1 = ((h - a).powi(2) - (h - b).powi(2)) / (2.0 * h * h);
            let c = c.to_array();
            for j in 0..4 {
                m0[j] += w0 * c[j];
                m1[j] += w1 * c[j];
            }
        }
        let u1 = first.to_array();
        let middle: [f64; 4] = std::array::from_fn(|j| 0.5 * (6.0 * m1[j] - u1[j]));
        let last: [f64; 4] = std::array::from_fn(|j| 6.0 * m0[j] - u1[j] - 4.0 * middle[j]);
        let (middle, last) = (Controls::from_array(middle), Controls::from_array(last));
        let roles = self.roles();
        let lag = roles.tau.map(|tau| {
            let s0 = x.surfaces();
            move |offset: f64| held.surfaces_after(s0, tau, offset)
        });
        self.rk4(
            t0,
            x,
            h,
            [&first, &middle, &middle, &last],
            lag.as_ref().map(|f| f as &dyn Fn(f64) -> DVec3),
            &roles,
        )
    }

    /// RK4 from `x` over `dt` with stage commands `cmds` (k₁…k₄) and, under actuator lag, the
    /// surfaces at each offset into the step from `lag`; the effects' `roles` are the model's.
    fn rk4(
        &self,
        t: f64,
        x: &State,
        dt: f64,
        cmds: [&Controls; 4],
        lag: Option<&dyn Fn(f64) -> DVec3>,
        roles: &EffectRoles,
    ) -> Rk4Step {
        let stage = |a: &State, b: &State, h: f64| {
            let mut r = a.0;
            for (ri, bi) in r.iter_mut().zip(b.0.iter()) {
                *ri += h * bi;
            }
            let mut r = State(r);
            if let Some(s) = lag {
                r.set_surfaces(s(h));
            }
            r
        };
        // The first stage's frame, kept for reads inside the step (`Rk4Step::at`).
        let frame = self.frame(t, x);
        let k1 = self.derivative_with(t, x, cmds[0], &frame, roles);
        let at = |t: f64, x: &State, cmd: &Controls| {
            self.derivative_with(t, x, cmd, &self.frame(t, x), roles)
        };
        let k2 = at(t + 0.5 * dt, &stage(x, &k1, 0.5 * dt), cmds[1]);
        let k3 = at(t + 0.5 * dt, &stage(x, &k2, 0.5 * dt), cmds[2]);
        let k4 = at(t + dt, &stage(x, &k3, dt), cmds[3]);
        let mut out = x.0;
        for (i, o) in out.iter_mut().enumerate() {
            *o += dt / 6.0 * (k1.0[i] + 2.0 * k2.0[i] + 2.0 * k3.0[i] + k4.0[i]);
        }
        let mut out = State(out);
        if let Some(s) = lag {
            out.set_surfaces(s(dt));
        }
        self.renormalise(&mut out);
        Rk4Step {
            t,
            start: *x,
            cmds: [*cmds[0], *cmds[1], *cmds[3]],
            frame: Some(frame),
            stages: [k1, k2, k3, k4],
            dt,
            end: out,
        }
    }

    fn renormalise(&self, x: &mut State) {
        if matches!(self.vehicle, Vehicle::FixedWing(_)) {
            let q = x.quat().normalize();
            x.0[6..10].copy_from_slice(&q.to_array());
        }
    }

    /// The steps [`advance`](Self::advance) takes over `span` seconds: their number and
    /// length (none for a span that is not positive).
    pub fn substeps(span: f64, max_dt: f64) -> (usize, f64) {
        if span.is_nan() || span <= 0.0 {
            return (0, 0.0);
        }
        // A span a rounding error longer than `max_dt` is one step, not two: time stamps of
        // data at 50 Hz are not exact multiples of 0.02 s.
        let n = (span / max_dt * (1.0 - 1e-9)).ceil().max(1.0) as usize;
        (n, span / n as f64)
    }

    /// Integrate from `t0` to `t1` with steps of at most `max_dt`, commands held constant.
    pub fn advance(&self, t0: f64, x: &State, cmd: &Controls, t1: f64, max_dt: f64) -> State {
        let (n, dt) = Self::substeps(t1 - t0, max_dt);
        let mut s = *x;
        for i in 0..n {
            s = self.step(t0 + i as f64 * dt, &s, cmd, dt);
        }
        s
    }
}

/// Commands held over the samples one integration step spans: `controls[k]` from `times[k]`
/// to `times[k + 1]` (no controls: all zero).
#[derive(Clone, Copy, Debug)]
pub struct HeldCommands<'a> {
    /// The sample times, the step's start first and its end last (at least two).
    pub times: &'a [f64],
    /// One command per interval (`times.len() − 1`), or None for data without commands.
    pub controls: Option<&'a [Controls]>,
}

impl HeldCommands<'_> {
    /// Number of held intervals.
    pub fn len(&self) -> usize {
        self.times.len().saturating_sub(1)
    }

    /// Whether there is no interval.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn command(&self, k: usize) -> Controls {
        self.controls
            .and_then(|c| c.get(k).copied())
            .unwrap_or_default()
    }

    /// The held commands integrated over the first `offset` seconds of the step (each
    /// component in its unit times seconds).
    fn integral(&self, offset: f64) -> Controls {
        let mut sum = [0.0; 4];
        for (a, b, c) in self.segments().take_while(|&(a, _, _)| offset > a) {
            let w = offset.min(b) - a;
            sum.iter_mut()
                .zip(c.to_array())
                .for_each(|(s, c)| *s += w * c);
        }
        Controls::from_array(sum)
    }

    /// Each held interval as (start, end, command), the times from the step's start.
    fn segments(&self) -> impl Iterator<Item = (f64, f64, Controls)> + '_ {
        let t0 = self.times.first().copied().unwrap_or(0.0);
        self.times
            .windows(2)
            .enumerate()
            .map(move |(k, w)| (w[0] - t0, w[1] - t0, self.command(k)))
    }

    /// Surfaces `offset` seconds into the step, from `s0` at its start, under a lag τ: the
    /// exact first-order response to each held command in turn.
    fn surfaces_after(&self, s0: DVec3, tau: f64, offset: f64) -> DVec3 {
        let mut s = s0;
        for (a, b, c) in self.segments().take_while(|&(a, _, _)| offset > a) {
            let target = DVec3::new(c.elevator, c.aileron, c.rudder);
            s = target + (s - target) * (-(offset.min(b) - a) / tau).exp();
        }
        s
    }
}

/// One RK4 step with its stages: the end state, and any state inside the step.
#[derive(Clone, Copy, Debug)]
pub struct Rk4Step {
    t: f64,
    start: State,
    /// The stage commands (k₁, k₂ = k₃, k₄).
    cmds: [Controls; 3],
    /// The frame of the first stage (none for a step of no length).
    frame: Option<Frame>,
    stages: [State; 4],
    dt: f64,
    /// The state at the end of the step.
    pub end: State,
}

impl Rk4Step {
    /// The state `offset` seconds into the step, the commands over it `held` (the step's):
    /// RK4's continuous extension (third order, from the stages already taken), its
    /// quaternion renormalised and, under actuator lag, its surfaces exact.
    ///
    /// Where the commands switch inside the step, the extension's implied command integral
    /// up to `offset` (its weights times the stage commands) is not the held one, and a term
    /// of the derivative linear in the commands — a rate's response to its surface — would
    /// be wrong to first order in the switch. The difference is added as B·Δ, B the
    /// derivative's response to the commands at the step's start (one model evaluation:
    /// f(x₀, u₁ + Δ/h)·h − k₁·h), which leaves an error of order h²·Δu.
    pub fn at(&self, model: &Model, held: &HeldCommands, offset: f64) -> State {
        let h = self.dt;
        // NaN as well as zero: no step to be inside of.
        if h.is_nan() || h <= 0.0 {
            return self.start;
        }
        let th = offset / h;
        let (t2, t3) = (th * th, th * th * th);
        let b1 = th - 1.5 * t2 + 2.0 / 3.0 * t3;
        let b23 = t2 - 2.0 / 3.0 * t3;
        let b4 = -0.5 * t2 + 2.0 / 3.0 * t3;
        let [k1, k2, k3, k4] = &self.stages;
        let mut out = self.start.0;
        for (i, o) in out.iter_mut().enumerate() {
            *o += h * (b1 * k1.0[i] + b23 * (k2.0[i] + k3.0[i]) + b4 * k4.0[i]);
        }
        // Held minus implied command integral, over h (a command's units).
        let [c1, cm, c4] = self.cmds.map(|c| c.to_array());
        let exact = held.integral(offset).to_array();
        let delta: [f64; 4] =
            std::array::from_fn(|j| exact[j] / h - (b1 * c1[j] + 2.0 * b23 * cm[j] + b4 * c4[j]));
        // Constant commands leave only rounding here.
        if delta.iter().map(|d| d.abs()).sum::<f64>() > 1e-12 {
            let probe = Controls::from_array(std::array::from_fn(|j| c1[j] + delta[j]));
            // At the first stage's time and state: its frame.
            let kp = match &self.frame {
                Some(frame) => model.derivative_in(self.t, &self.start, &probe, frame),
                None => model.derivative(self.t, &self.start, &probe),
            };
            for (i, o) in out.iter_mut().enumerate() {
                *o += h * (kp.0[i] - k1.0[i]);
            }
        }
        let mut out = State(out);
        if let Some(tau) = model.actuator_tau() {
            out.set_surfaces(held.surfaces_after(self.start.surfaces(), tau, offset));
        }
        model.renormalise(&mut out);
        out
    }
}
