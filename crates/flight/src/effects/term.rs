//! `term(AXIS=EXPR)`: a body-axis force or moment given by a formula of the expression
//! language ([`crate::expr`]), its free coefficients the effect's parameters —
//! `--add 'term:m=k*thrust'`, or a model file's `[[term]] axis = "m" expr = "k * thrust"`.
//!
//! A point mass takes a force term (`X`, `Y`, `Z`) that reads only what a point mass has
//! ([`POINT_MASS_VARIABLES`]): its body axes are its flight-path axes
//! ([`crate::aero::flight_path_axes`]: `X` along the air-relative velocity, `Z` downward
//! normal to it), and the term's value is an acceleration (its mass is 1). Where its flight
//! recorded the body's attitude, `alpha` and `beta` are that body's angles to the
//! air-relative velocity and the axes are the wind axes it defines
//! ([`crate::model::Model::point_mass_air`]: `Z` normal to the velocity in the body's x–z
//! plane, negative toward the body's top — its lift, bank included — and `Y` its side):
//! `--add 'term:Z=k1*qbar*alpha*abs(alpha)+k2*qbar*alpha^2'` is a body's lift from its
//! incidence. Without a recorded attitude a point mass refuses a term reading them.
//!
//! A term's parameters are known only when its text is read, while an effect's
//! [`EffectInfo`] is `&'static` (every other effect's is a `static`, and the model file, the
//! diagnosis, the window and the fitter all hold `&'static` infos and parameter names).
//! Rather than make the info dynamic through the trait — which every caller holding a
//! `&'static EffectInfo` or a `&'static str` parameter name would have to follow — one
//! `EffectInfo` is interned per distinct term, keyed by its canonical name
//! `term(m=k*thrust)` (the text without blanks), in a registry bounded by
//! [`MAX_DISTINCT_TERMS`]: the same term read again, from a file or a command line, gets
//! the same info, so what leaks is bounded by the number of distinct terms a process reads.
//!
//! The expression is parsed and compiled once, when the term is read; a step fills the
//! variables it uses from the [`Sample`] and runs the compiled program — no string work, no
//! allocation.

use std::sync::{Arc, Mutex};

use glam::DVec3;

use super::{Applies, Effect, EffectContext, EffectInfo, ParamSpec, Sample};
use crate::expr::{Axis, EvalError, Term, Var, VarValues, MAX_COEFFS, N_VARS};

/// The most distinct terms one process may read (each keeps one interned [`EffectInfo`]).
pub const MAX_DISTINCT_TERMS: usize = 256;

/// The spec prefix: `term:AXIS=EXPR`.
pub const PREFIX: &str = "term";

/// A coefficient's valid range: wide, but finite so that the fitter stays in numbers.
pub const COEFF_RANGE: (f64, f64) = (-1e9, 1e9);

/// The size of force (N) or moment (N·m) a coefficient's typical size is taken to give at
/// typical flight values (see [`coefficient_scale`]).
const TYPICAL_OUTPUT: f64 = 1.0;

/// The variables a point mass has: the air-relative velocity's size and the air, and the
/// angles of attack and sideslip of the body its flight recorded (a model built without a
/// recorded attitude refuses a term reading those: [`Effect::reads_incidence`]). No rates,
/// surfaces or propeller.
pub const POINT_MASS_VARIABLES: [Var; 7] = [
    Var::Airspeed,
    Var::Qbar,
    Var::Rho,
    Var::Height,
    Var::G,
    Var::Alpha,
    Var::Beta,
];

/// The vehicles a term means something for: a force that reads only
/// [`POINT_MASS_VARIABLES`] both, anything else the fixed wing alone.
pub fn applies(term: &Term) -> Applies {
    if term.axis.is_force()
        && term
            .expr
            .variables()
            .all(|v| POINT_MASS_VARIABLES.contains(&v))
    {
        Applies::Both
    } else {
        Applies::FixedWing
    }
}

/// A term that cannot be an effect.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TermError {
    /// The registry of distinct terms is full.
    #[error("more than {MAX_DISTINCT_TERMS} distinct terms in one run")]
    TooMany,
}

/// The canonical effect name of a term: `term(m=k*thrust)` — its axis and expression without
/// blanks, the name `--free`/`--fix` style options and reports use, and a model's key for
/// refusing the same term twice.
pub fn effect_name(term: &Term) -> String {
    let expr: String = term
        .expr
        .source()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    format!("{PREFIX}({}={expr})", term.axis)
}

/// The name of a term's parameter as options and reports write it: `term(m=k*thrust).k`.
pub fn qualified_param(term: &Term, coefficient: &str) -> String {
    format!("{}.{coefficient}", effect_name(term))
}

struct Interned {
    info: &'static EffectInfo,
    term: Arc<Term>,
}

static REGISTRY: Mutex<Vec<Interned>> = Mutex::new(Vec::new());

/// The interned [`EffectInfo`] of a term (made on first use; the same for the same term).
///
/// # Errors
/// [`TermError::TooMany`] past [`MAX_DISTINCT_TERMS`] distinct terms.
pub fn intern(term: &Term) -> Result<&'static EffectInfo, TermError> {
    let name = effect_name(term);
    // A poisoned lock only means another thread panicked while holding it; the vector is
    // still whole (entries are pushed complete).
    let mut reg = REGISTRY.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(found) = reg.iter().find(|i| i.info.name == name) {
        return Ok(found.info);
    }
    if reg.len() >= MAX_DISTINCT_TERMS {
        return Err(TermError::TooMany);
    }
    let params: Vec<ParamSpec> = term
        .expr
        .coefficients()
        .iter()
        .enumerate()
        .map(|(i, c)| ParamSpec {
            absent: vanishes_at_zero(term).then_some(0.0),
            scale_relative: true,
            ..ParamSpec::new(
                Box::leak(c.clone().into_boxed_str()),
                term.axis.unit(),
                COEFF_RANGE,
                coefficient_scale(term, i),
            )
        })
        .collect();
    let summary = format!("{} += {} ({})", term.axis, term.expr, term.axis.unit());
    let info: &'static EffectInfo = Box::leak(Box::new(EffectInfo {
        name: Box::leak(name.into_boxed_str()),
        summary: Box::leak(summary.into_boxed_str()),
        applies: applies(term),
        params: Box::leak(params.into_boxed_slice()),
        make: unbound,
    }));
    reg.push(Interned {
        info,
        term: Arc::new(term.clone()),
    });
    Ok(info)
}

/// The interned info of a term by its effect name (`term(m=k*thrust)`): read and interned
/// now if it was not before; `None` for a name that is not a term's.
pub fn find_interned(name: &str) -> Option<&'static EffectInfo> {
    {
        let reg = REGISTRY.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(found) = reg.iter().find(|i| i.info.name == name) {
            return Some(found.info);
        }
    }
    let inner = name
        .strip_prefix(PREFIX)?
        .strip_prefix('(')?
        .strip_suffix(')')?;
    intern(&Term::parse(inner).ok()?).ok()
}

/// The term whose interned info this is, if it is one.
pub fn term_of(info: &EffectInfo) -> Option<Arc<Term>> {
    let reg = REGISTRY.lock().unwrap_or_else(|e| e.into_inner());
    reg.iter()
        .find(|i| std::ptr::eq(i.info, info))
        .map(|i| Arc::clone(&i.term))
}

/// The term's effect, coefficients at 0, if `info` is a term's ([`EffectInfo::build`]
/// comes here first: an interned info's `make` cannot know its term).
pub(super) fn build(info: &'static EffectInfo, ctx: &EffectContext) -> Option<Box<dyn Effect>> {
    term_of(info).map(|term| Box::new(TermEffect::new(info, term, ctx)) as Box<dyn Effect>)
}

/// The `make` of an interned info, reached only by calling the field directly:
/// [`EffectInfo::build`] builds terms itself. A term of no coefficients' worth: nothing.
fn unbound(_: &EffectContext) -> Box<dyn Effect> {
    Box::new(super::GroundEffect { span: 0.0 })
}

/// Typical flight values of the variables: where a coefficient's fitting scale is taken and
/// where a term is checked to vanish with its coefficients.
fn typical_values() -> [VarValues; 2] {
    let mut a = [0.0; N_VARS];
    let mut b = [0.0; N_VARS];
    for (v, x, y) in [
        (Var::Alpha, 0.08, -0.03),
        (Var::Beta, 0.02, -0.05),
        (Var::PHat, 0.01, -0.02),
        (Var::QHat, 0.01, 0.005),
        (Var::RHat, 0.005, -0.01),
        (Var::P, 0.2, -0.3),
        (Var::Q, 0.1, 0.05),
        (Var::R, 0.05, -0.1),
        (Var::Elevator, -0.05, 0.03),
        (Var::Aileron, 0.02, -0.04),
        (Var::Rudder, 0.01, -0.02),
        (Var::Throttle, 0.6, 0.3),
        (Var::Thrust, 30.0, 12.0),
        (Var::Airspeed, 25.0, 18.0),
        (Var::Qbar, 380.0, 200.0),
        (Var::Rho, 1.225, 1.1),
        (Var::Height, 150.0, 40.0),
        (Var::G, 9.80665, 9.80665),
    ] {
        a[v.index()] = x;
        b[v.index()] = y;
    }
    [a, b]
}

/// Whether the term is 0 with every coefficient at 0 (at two sets of typical values): then
/// 0 is each coefficient's absent value. `k*thrust + 0.3` has none.
fn vanishes_at_zero(term: &Term) -> bool {
    let zero = [0.0; MAX_COEFFS];
    typical_values()
        .iter()
        .all(|vars| term.expr.eval(vars, &zero) == 0.0)
}

/// A coefficient's typical size: the value that makes the term change by [`TYPICAL_OUTPUT`]
/// (1 N or 1 N·m) at typical flight values, from the derivative with respect to it there
/// (with every coefficient at 1) — `k*thrust` gets 1/30, `k*qbar*alpha` 1/30. The fitter
/// steps 1% of it and scales by it, and it grows with the value; 1 where the derivative is
/// 0 or not finite there.
fn coefficient_scale(term: &Term, i: usize) -> f64 {
    let ones = [1.0; MAX_COEFFS];
    let mut grad = [0.0; MAX_COEFFS];
    let [vars, _] = typical_values();
    term.expr.eval_with_gradient(&vars, &ones, &mut grad);
    let d = grad[i].abs();
    if d.is_finite() && d > 0.0 {
        (TYPICAL_OUTPUT / d).clamp(1e-9, 1e6)
    } else {
        1.0
    }
}

/// What a term needs of the airframe beyond the [`Sample`]: the reference lengths of the
/// non-dimensional rates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Airframe {
    /// Wing span b, m.
    pub span_m: f64,
    /// Mean chord c, m.
    pub chord_m: f64,
}

/// Airspeed below which the non-dimensional rates are 0, as the aerodynamic model takes them.
const MIN_AIRSPEED: f64 = 0.1;

/// A term as an effect: its compiled expression, its coefficients and the airframe numbers
/// its variables need.
#[derive(Clone, Debug)]
pub struct TermEffect {
    info: &'static EffectInfo,
    term: Arc<Term>,
    coeffs: [f64; MAX_COEFFS],
    n_coeffs: usize,
    airframe: Airframe,
    /// The variables the expression reads, one bit per [`Var::index`]: only those are filled.
    used: u32,
}

impl TermEffect {
    fn new(info: &'static EffectInfo, term: Arc<Term>, ctx: &EffectContext) -> Self {
        let used = term
            .expr
            .variables()
            .fold(0u32, |m, v| m | (1 << v.index()));
        let n_coeffs = term.expr.coefficients().len().min(MAX_COEFFS);
        Self {
            info,
            term,
            coeffs: [0.0; MAX_COEFFS],
            n_coeffs,
            airframe: Airframe {
                span_m: ctx.span_m,
                chord_m: ctx.chord_m,
            },
            used,
        }
    }

    /// The term.
    pub fn term(&self) -> &Term {
        &self.term
    }

    /// The variables' values at a sample: those the expression reads (the rest 0). The air
    /// data and the thrust are the sample's, as the aerodynamic model took them.
    #[inline]
    pub fn variables(&self, s: &Sample) -> VarValues {
        let mut v = [0.0; N_VARS];
        let mut left = self.used;
        // Bounded: one pass per bit set, at most N_VARS.
        while left != 0 {
            let i = left.trailing_zeros() as usize;
            left &= left - 1;
            v[i] = self.value_of(Var::ALL[i], s);
        }
        v
    }

    #[inline(always)]
    fn value_of(&self, var: Var, s: &Sample) -> f64 {
        let va = s.air.airspeed;
        // p·L/(2V): zero at (almost) zero airspeed, where it is undefined.
        let hat = |rate: f64, length: f64| {
            if va > MIN_AIRSPEED {
                rate * length * (0.5 / va)
            } else {
                0.0
            }
        };
        match var {
            Var::Alpha => s.air.alpha,
            Var::Beta => s.air.beta,
            Var::PHat => hat(s.omega.x, self.airframe.span_m),
            Var::QHat => hat(s.omega.y, self.airframe.chord_m),
            Var::RHat => hat(s.omega.z, self.airframe.span_m),
            Var::P => s.omega.x,
            Var::Q => s.omega.y,
            Var::R => s.omega.z,
            Var::Elevator => s.controls.elevator,
            Var::Aileron => s.controls.aileron,
            Var::Rudder => s.controls.rudder,
            Var::Throttle => s.controls.throttle,
            Var::Thrust => s.thrust,
            Var::Airspeed => va,
            Var::Qbar => 0.5 * s.rho * va * va,
            Var::Rho => s.rho,
            Var::Height => -s.pos_ned.z,
            Var::G => s.g,
        }
    }

    /// The term's value at a sample, or what made it NaN or ∞ (the variable or coefficient,
    /// or the operation and its operands, at its column).
    ///
    /// # Errors
    /// The value is not finite.
    pub fn value_checked(&self, s: &Sample) -> Result<f64, EvalError> {
        self.term
            .expr
            .eval_checked(&self.variables(s), &self.coeffs[..self.n_coeffs])
    }
}

impl Effect for TermEffect {
    fn info(&self) -> &'static EffectInfo {
        self.info
    }
    fn values(&self) -> &[f64] {
        &self.coeffs[..self.n_coeffs]
    }
    fn values_mut(&mut self) -> &mut [f64] {
        &mut self.coeffs[..self.n_coeffs]
    }
    fn varies_in_time(&self) -> bool {
        false
    }
    fn reads_incidence(&self) -> bool {
        self.term.expr.uses(Var::Alpha) || self.term.expr.uses(Var::Beta)
    }
    fn varies_in_space(&self) -> bool {
        self.term.expr.uses(Var::Height)
    }
    fn force_moment_body(&self, s: &Sample) -> (DVec3, DVec3) {
        let value = self
            .term
            .expr
            .eval_from(|v| self.value_of(v, s), &self.coeffs[..self.n_coeffs]);
        let mut out = DVec3::ZERO;
        out[self.term.axis.component()] = value;
        if self.term.axis.is_force() {
            (out, DVec3::ZERO)
        } else {
            (DVec3::ZERO, out)
        }
    }
    fn explain_non_finite(&self, s: &Sample) -> Option<String> {
        let vars = self.variables(s);
        let err = self
            .term
            .expr
            .eval_checked(&vars, &self.coeffs[..self.n_coeffs])
            .err()?;
        let shown: Vec<String> = self
            .term
            .expr
            .variables()
            .map(|v| format!("{} = {}", v.name(), vars[v.index()]))
            .chain(
                self.term
                    .expr
                    .coefficients()
                    .iter()
                    .zip(&self.coeffs)
                    .map(|(c, x)| format!("{c} = {x}")),
            )
            .collect();
        Some(format!(
            "term `{}` is not finite: {err} (at {})",
            self.term,
            shown.join(", ")
        ))
    }
}

/// The axis a term acts on (for display).
pub fn axis_of(info: &EffectInfo) -> Option<Axis> {
    term_of(info).map(|t| t.axis)
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use crate::aero::air_angles;
    use wireflight_data::Controls;

    fn ctx() -> EffectContext {
        EffectContext {
            origin: super::super::Origin::default(),
            span_m: 3.0,
            chord_m: 0.3,
            ..EffectContext::default()
        }
    }

    #[test]
    fn the_same_term_is_interned_once_and_its_name_has_no_blanks() {
        let a = intern(&Term::parse("m = k * thrust").unwrap()).unwrap();
        let b = intern(&Term::parse("m=k*thrust").unwrap()).unwrap();
        assert!(std::ptr::eq(a, b));
        assert_eq!(a.name, "term(m=k*thrust)");
        assert_eq!(a.params[0].name, "k");
        assert_eq!(a.params[0].absent, Some(0.0));
        let c = intern(&Term::parse("m=k*thrust+0.3").unwrap()).unwrap();
        assert_eq!(
            c.params[0].absent, None,
            "k*thrust+0.3 does not vanish at k = 0"
        );
    }

    #[test]
    fn a_moment_term_acts_on_its_axis_with_the_models_thrust() {
        let info = intern(&Term::parse("m = k*thrust*throttle").unwrap()).unwrap();
        let mut e = info.build(&ctx());
        e.set_param("k", 0.5).unwrap();
        let s = Sample {
            controls: Controls {
                throttle: 0.5,
                ..Controls::default()
            },
            thrust: 40.0,
            ..sample()
        };
        let (f, m) = e.force_moment_body(&s);
        assert_eq!(f, DVec3::ZERO);
        assert_eq!(m, DVec3::new(0.0, 0.5 * 40.0 * 0.5, 0.0));
    }

    /// The non-dimensional rates take the span and the chord of the airframe, and the air
    /// data's airspeed; they are 0 where the airspeed is (almost) zero.
    #[test]
    fn the_non_dimensional_rates_take_the_airframes_lengths() {
        let info = intern(&Term::parse("n = k*r_hat + k2*q_hat").unwrap()).unwrap();
        let mut e = info.build(&ctx());
        e.set_param("k", 1.0).unwrap();
        e.set_param("k2", 10.0).unwrap();
        let mut s = Sample {
            omega: DVec3::new(0.0, 0.2, 0.4),
            air: air_angles(DVec3::new(20.0, 0.0, 0.0), 1.2),
            ..sample()
        };
        let want = 0.4 * 3.0 / 40.0 + 10.0 * 0.2 * 0.3 / 40.0;
        assert!((e.force_moment_body(&s).1.z - want).abs() < 1e-12);
        s.air = air_angles(DVec3::ZERO, 1.2);
        assert_eq!(e.force_moment_body(&s).1.z, 0.0);
    }

    #[test]
    fn a_force_term_and_its_scale_follow_the_variables() {
        let info = intern(&Term::parse("Y = c*beta").unwrap()).unwrap();
        assert!((info.params[0].scale - 1.0 / 0.02).abs() < 1e-9);
        let mut e = info.build(&ctx());
        e.set_param("c", -10.0).unwrap();
        let s = Sample {
            air: air_angles(DVec3::new(20.0, 2.0, 0.0), 1.2),
            ..sample()
        };
        let (f, m) = e.force_moment_body(&s);
        let beta = (2.0f64).atan2(20.0);
        assert!((f.y + 10.0 * beta).abs() < 1e-9, "{f}");
        assert_eq!((f.x, f.z, m), (0.0, 0.0, DVec3::ZERO));
    }

    /// In the model, a pitching-moment term changes the pitch acceleration by m/J_y and
    /// nothing else: what the tangent's differences of the derivative then carry.
    #[test]
    fn a_pitching_term_enters_the_models_pitch_acceleration() {
        use crate::model::Vehicle;
        use crate::spec::{EffectSpec, ModelSpec};
        let base = ModelSpec::baseline(wireflight_data::VehicleKind::FixedWing)
            .build(super::super::Origin::default())
            .unwrap();
        let Vehicle::FixedWing(p) = &base.vehicle else {
            unreachable!("a fixed wing")
        };
        let jy = p.mass.jy;
        let spec = EffectSpec::parse("term(m=k*airspeed):k=2").unwrap();
        let mut with = base.clone();
        with.add_effect(spec.build(&base.effect_context()).unwrap())
            .unwrap();
        let (x, cmd) = super::super::tests::flying();
        let (a, b) = (
            with.derivative(1.0, &x, &cmd).0,
            base.derivative(1.0, &x, &cmd).0,
        );
        let va = base.air_data(1.0, &x).airspeed;
        for (k, (ga, gb)) in a.iter().zip(b).enumerate() {
            let want = if k == 11 { gb + 2.0 * va / jy } else { gb };
            assert!(
                (ga - want).abs() < 1e-12 * (1.0 + want.abs()),
                "[{k}]: {ga} vs {want}"
            );
        }
    }

    /// On a point mass a force term acts along its flight-path axes: `Z` negative is a lift,
    /// normal to the air-relative velocity and upward; a term reading a body variable is
    /// the fixed wing's alone.
    #[test]
    fn a_force_term_on_a_point_mass_acts_along_its_flight_path() {
        use crate::model::{Model, State, Vehicle};
        use crate::spec::EffectSpec;
        let base = Model::new(Vehicle::PointMass, super::super::Origin::default());
        let spec = EffectSpec::parse("term(Z=k*qbar):k=-0.01").unwrap();
        let mut with = base.clone();
        with.add_effect(spec.build(&base.effect_context()).unwrap())
            .unwrap();
        let mut x = State::default();
        // Climbing north-east at 45°, 40 m/s.
        let v = DVec3::new(20.0, 20.0, -20.0 * 2f64.sqrt());
        x.set_vel(v);
        let cmd = Controls::default();
        let d = |m: &Model| {
            let s = m.derivative(0.0, &x, &cmd).0;
            DVec3::new(s[3], s[4], s[5])
        };
        let lift = d(&with) - d(&base);
        let qbar = 0.5 * crate::effects::RHO_SEA_LEVEL * v.length_squared();
        assert!((lift.length() - 0.01 * qbar).abs() < 1e-9, "{lift}");
        assert!(lift.dot(v).abs() < 1e-9, "normal to the velocity: {lift}");
        assert!(
            lift.z < 0.0 && lift.x < 0.0 && (lift.x - lift.y).abs() < 1e-9,
            "{lift}"
        );
        let body = EffectSpec::parse("term(Z=k*qbar*alpha):k=-0.01").unwrap();
        assert!(base
            .clone()
            .add_effect(body.build(&base.effect_context()).unwrap())
            .is_err());
        let moment = EffectSpec::parse("term(m=k*qbar):k=1").unwrap();
        assert!(base
            .clone()
            .add_effect(moment.build(&base.effect_context()).unwrap())
            .is_err());
    }

    /// On a point mass whose flight recorded the body's attitude, `alpha` and `beta` are that
    /// body's and `Z` is normal to the velocity in its x–z plane: a body banked 90° and 10°
    /// nose-left of a northward path has a sideslip and its `Z` points west. Without the
    /// record the same term is refused for the attitude it lacks.
    #[test]
    fn a_point_mass_reads_the_recorded_bodys_incidence_and_axes() {
        use crate::effects::RecordedAttitude;
        use crate::model::{Model, ModelError, State, Vehicle};
        use crate::spec::EffectSpec;
        use wireflight_geometry::euler::EulerZyx;
        let spec = EffectSpec::parse("term(Z=k*qbar*alpha+c*qbar*beta):k=-0.01,c=0").unwrap();
        let blind = Model::new(Vehicle::PointMass, super::super::Origin::default());
        let refused = blind
            .clone()
            .add_effect(spec.build(&blind.effect_context()).unwrap());
        assert!(
            matches!(refused, Err(ModelError::LacksChannel { channel, .. })
                if channel == super::super::Channel::Attitude),
            "{refused:?}"
        );
        let mut base = blind.clone();
        // Yawed 10° left of north, pitched 5° up, banked 90° right: the body's z points west.
        let body = EulerZyx::new(-10f64.to_radians(), 5f64.to_radians(), 90f64.to_radians());
        let record = RecordedAttitude::new(&[0.0, 1.0], &[body, body]).unwrap();
        base.set_recorded_attitude(Some(Arc::new(record)));
        let mut with = base.clone();
        with.add_effect(spec.build(&base.effect_context()).unwrap())
            .unwrap();
        let mut x = State::default();
        let v = DVec3::new(50.0, 0.0, 0.0);
        x.set_vel(v);
        let rho = crate::effects::RHO_SEA_LEVEL;
        let (air, axes) = base.point_mass_air(0.5, v, rho);
        let u = body.to_matrix().transpose() * v;
        assert!((air.alpha - u.z.atan2(u.x)).abs() < 1e-12, "{}", air.alpha);
        assert!(
            (air.beta - (u.y / 50.0).asin()).abs() < 1e-12,
            "{}",
            air.beta
        );
        assert!((axes.x_axis - DVec3::X).length() < 1e-12);
        assert!(
            axes.z_axis.dot(body.to_matrix().y_axis).abs() < 1e-12,
            "in the x–z plane"
        );
        // Signs, not only directions: Z toward the body's belly (west here, the body rolled
        // onto its right wing), the triad right-handed, the side axis the wind axes' own.
        assert!(
            axes.z_axis.dot(body.to_matrix().z_axis) > 0.0,
            "{}",
            axes.z_axis
        );
        assert!(axes.z_axis.dot(-DVec3::Y) > 0.9, "west: {}", axes.z_axis);
        assert!((axes.determinant() - 1.0).abs() < 1e-12);
        let (sa, ca) = air.alpha.sin_cos();
        let (sb, cb) = air.beta.sin_cos();
        let side_body = body.to_matrix().transpose() * axes.y_axis;
        assert!(
            (side_body - DVec3::new(-ca * sb, cb, -sa * sb)).length() < 1e-12,
            "{side_body}"
        );
        let cmd = Controls::default();
        let d = |m: &Model| {
            let s = m.derivative(0.5, &x, &cmd).0;
            DVec3::new(s[3], s[4], s[5])
        };
        let lift = d(&with) - d(&base);
        let want = -0.01 * 0.5 * rho * 2500.0 * air.alpha * axes.z_axis;
        assert!(
            (lift - want).length() < 1e-9 * want.length(),
            "{lift} vs {want}"
        );
        assert!(lift.dot(v).abs() < 1e-9, "normal to the velocity: {lift}");
    }

    #[test]
    fn a_non_finite_term_says_why_with_the_values() {
        let info = intern(&Term::parse("m = k*ln(throttle - 2)").unwrap()).unwrap();
        let mut e = info.build(&ctx());
        e.set_param("k", 1.0).unwrap();
        let s = sample();
        assert!(e.force_moment_body(&s).1.y.is_nan());
        let why = e.explain_non_finite(&s).unwrap();
        assert!(why.contains("ln") && why.contains("throttle = 0"), "{why}");
        let fine = intern(&Term::parse("m = k*throttle").unwrap()).unwrap();
        assert_eq!(fine.build(&ctx()).explain_non_finite(&s), None);
    }
}
