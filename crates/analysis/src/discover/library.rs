//! The candidate regressors: products of the term language's variables, each one a term the
//! language takes as written (`k*qbar*alpha*beta`), so that what is found can be added.
//!
//! Normalisation: a regressor is the product exactly as printed, in SI units and radians; its
//! coefficient is in N or N·m per unit of that product. Aerodynamic shapes are multiplied by
//! the dynamic pressure (`qbar*alpha*beta`: the coefficient is S·b·C, a force or moment that
//! grows with q̄ as an airframe's does); propulsive ones are not (`throttle^2`, `r*throttle`,
//! `thrust`). The selection itself works on each column divided by its RMS over the flight,
//! so the choice does not depend on the units.

use wireflight_flight::expr::{Var, VarValues};

/// One factor of a regressor: a variable, or a function of one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Factor {
    /// The variable itself.
    Plain(Var),
    /// Its sine.
    Sin(Var),
    /// Its cosine.
    Cos(Var),
    /// Its magnitude.
    Abs(Var),
    /// Its positive part, max(x, 0).
    Above(Var),
    /// Its negative part, min(x, 0).
    Below(Var),
}

impl Factor {
    fn value(self, v: &VarValues) -> f64 {
        match self {
            Factor::Plain(x) => v[x.index()],
            Factor::Sin(x) => v[x.index()].sin(),
            Factor::Cos(x) => v[x.index()].cos(),
            Factor::Abs(x) => v[x.index()].abs(),
            Factor::Above(x) => v[x.index()].max(0.0),
            Factor::Below(x) => v[x.index()].min(0.0),
        }
    }

    fn text(self) -> String {
        match self {
            Factor::Plain(x) => x.name().to_string(),
            Factor::Sin(x) => format!("sin({})", x.name()),
            Factor::Cos(x) => format!("cos({})", x.name()),
            Factor::Abs(x) => format!("abs({})", x.name()),
            Factor::Above(x) => format!("max({},0)", x.name()),
            Factor::Below(x) => format!("min({},0)", x.name()),
        }
    }
}

/// A candidate regressor: the product of up to three factors (none: a constant).
#[derive(Clone, Debug, PartialEq)]
pub struct Regressor {
    factors: Vec<Factor>,
}

impl Regressor {
    /// Its value for these variables.
    pub fn value(&self, v: &VarValues) -> f64 {
        self.factors.iter().map(|f| f.value(v)).product()
    }

    /// Its factors as the term language writes them (`["qbar", "alpha", "beta"]`); a square
    /// is written once with `^2` (`["throttle^2"]`); empty for the constant.
    pub fn names(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let mut i = 0;
        while i < self.factors.len() {
            let f = self.factors[i];
            let t = f.text();
            if self.factors.get(i + 1) == Some(&f) {
                out.push(format!("{t}^2"));
                i += 2;
            } else {
                out.push(t);
                i += 1;
            }
        }
        out
    }

    /// The expression `coefficient*f1*f2…` (or the coefficient alone for the constant).
    pub fn expression(&self, coefficient: &str) -> String {
        std::iter::once(coefficient.to_string())
            .chain(self.names())
            .collect::<Vec<_>>()
            .join("*")
    }

    /// Whether it reads variable `v` (plain or through a function).
    pub fn uses(&self, v: Var) -> bool {
        self.factors.iter().any(|f| match *f {
            Factor::Plain(x)
            | Factor::Sin(x)
            | Factor::Cos(x)
            | Factor::Abs(x)
            | Factor::Above(x)
            | Factor::Below(x) => x == v,
        })
    }
}

/// Angles, non-dimensional rates and surfaces: the shapes an airframe's coefficients take.
const SHAPES: [Var; 8] = [
    Var::Alpha,
    Var::Beta,
    Var::PHat,
    Var::QHat,
    Var::RHat,
    Var::Elevator,
    Var::Aileron,
    Var::Rudder,
];

/// The candidates of a fixed wing: q̄ times a constant, each shape, each product and square
/// of two shapes and sin/cos of α; the propulsive forms (throttle, its square, the thrust,
/// body rates times throttle, angles times thrust); airspeed and its square.
pub fn fixed_wing() -> Vec<Regressor> {
    use Factor::{Cos, Plain, Sin};
    let q = Plain(Var::Qbar);
    let mut out = vec![
        Regressor { factors: vec![] },
        Regressor { factors: vec![q] },
    ];
    for (i, &a) in SHAPES.iter().enumerate() {
        out.push(Regressor {
            factors: vec![q, Plain(a)],
        });
        for &b in &SHAPES[i..] {
            out.push(Regressor {
                factors: vec![q, Plain(a), Plain(b)],
            });
        }
    }
    for f in [Sin(Var::Alpha), Cos(Var::Alpha)] {
        out.push(Regressor {
            factors: vec![q, f],
        });
    }
    let t = Plain(Var::Throttle);
    let thrust = Plain(Var::Thrust);
    out.push(Regressor { factors: vec![t] });
    out.push(Regressor {
        factors: vec![t, t],
    });
    out.push(Regressor {
        factors: vec![thrust],
    });
    for r in [Var::P, Var::Q, Var::R, Var::Airspeed] {
        out.push(Regressor {
            factors: vec![Plain(r), t],
        });
    }
    for a in [Var::Alpha, Var::Beta] {
        out.push(Regressor {
            factors: vec![thrust, Plain(a)],
        });
    }
    let v = Plain(Var::Airspeed);
    out.push(Regressor { factors: vec![v] });
    out.push(Regressor {
        factors: vec![v, v],
    });
    out
}

/// The candidates of a point mass, what it has (its flight-path axes carry no angle, rate,
/// surface or propeller): a constant; the airspeed, its square; q̄ and q̄ times the airspeed
/// and its square (a drag that grows faster than V², as compressibility makes it with the
/// Mach number: the data carry no temperature, so no Mach number); q̄ times the height and
/// its square (a drag whose density the model has wrong with height); the height; ρ.
pub fn point_mass() -> Vec<Regressor> {
    use Factor::Plain;
    let (v, q, h) = (Plain(Var::Airspeed), Plain(Var::Qbar), Plain(Var::Height));
    [
        vec![],
        vec![v],
        vec![v, v],
        vec![q],
        vec![q, v],
        vec![q, v, v],
        vec![q, h],
        vec![q, h, h],
        vec![h],
        vec![Plain(Var::Rho)],
    ]
    .into_iter()
    .map(|factors| Regressor { factors })
    .collect()
}

/// The candidates of a point mass whose flight recorded the body's attitude: its own
/// ([`point_mass`]) and q̄ times the body's incidence. For each of α and β: the angle (a
/// linear lift or side force); the angle times its magnitude (the crossflow force of a body
/// of revolution, odd like the angle); its square (even: a force that does not change sign
/// with the angle, and along the path a drag growing with incidence); and the square of its
/// positive and of its negative part — a force on one side of the angle only, as a table
/// whose rows begin at α = 0 gives (max(α, 0)² = (α·|α| + α²)/2). The one-sided forms are
/// candidates of their own because the stepwise selection adds one column at a time: on the
/// way to the pair α·|α| and α², its first step's residual can fail the tests that the pair
/// would pass.
pub fn point_mass_with_incidence() -> Vec<Regressor> {
    use Factor::{Above, Abs, Below, Plain};
    let q = Plain(Var::Qbar);
    let mut out = point_mass();
    for angle in [Var::Alpha, Var::Beta] {
        let (a, up, down) = (Plain(angle), Above(angle), Below(angle));
        for factors in [
            vec![q, a],
            vec![q, a, Abs(angle)],
            vec![q, a, a],
            vec![q, up, up],
            vec![q, down, down],
        ] {
            out.push(Regressor { factors });
        }
    }
    out
}

/// "what ∝ its form: why" (the form `constant` without factors; no why where `why` of the
/// product, written as `qbar*alpha`, is empty).
fn worded(what: &str, r: &Regressor, why: impl FnOnce(&str) -> &'static str) -> String {
    let names = r.names();
    let form = if names.is_empty() {
        "constant".to_string()
    } else {
        names.join("·")
    };
    match why(&names.join("*")) {
        "" => format!("{what} ∝ {form}"),
        why => format!("{what} ∝ {form}: {why}"),
    }
}

/// A physical reading of a point mass's term on its axes: the flight path's (`X` along the
/// velocity, `Y` level to its right, `Z` downward normal to it) or a recorded body's wind
/// axes (`Z` normal to the velocity in the body's x–z plane, `Y` its side).
pub fn point_mass_reading(axis: wireflight_flight::expr::Axis, r: &Regressor) -> String {
    use wireflight_flight::expr::Axis;
    let what = match axis {
        Axis::X => "acceleration along the flight path",
        Axis::Y => "side acceleration",
        Axis::Z => "acceleration normal to the flight path",
        Axis::L | Axis::M | Axis::N => "moment",
    };
    worded(what, r, |product| {
        match (axis, product) {
            (Axis::X, "qbar") | (Axis::X, "airspeed^2") => "drag mis-estimated (negative: more drag)",
            (Axis::X, "qbar*airspeed") | (Axis::X, "qbar*airspeed^2") => {
                "drag growing faster than V² (compressibility, with the Mach number)"
            }
            (Axis::X, "qbar*height") | (Axis::X, "qbar*height^2") => {
                "drag's density wrong with height (density_altitude)"
            }
            (Axis::Z, "qbar") | (Axis::Z, "airspeed^2") => {
                "a lift at constant incidence (negative: up)"
            }
            (Axis::Y, "qbar") | (Axis::Y, "airspeed^2") => "a side force at constant sideslip",
            (Axis::Z, "qbar*alpha") => "the body's lift, linear in its angle of attack (negative: up)",
            (Axis::Z, "qbar*alpha*abs(alpha)") => {
                "the crossflow lift of a body at incidence, odd in α (negative: up at α > 0)"
            }
            (Axis::Z, "qbar*alpha^2") => {
                "a lift that does not change sign with α; beside an odd one, a lift on one side of α only"
            }
            (Axis::Z, "qbar*max(alpha,0)^2") => {
                "a lift at positive α only, growing as α² (negative: up), as from a lift table whose rows begin at α = 0"
            }
            (Axis::Z, "qbar*min(alpha,0)^2") => {
                "a normal force at negative α only, growing as α² (positive: down)"
            }
            (Axis::Y, "qbar*beta") => "the body's side force in sideslip",
            (Axis::Y, "qbar*beta*abs(beta)") => "the crossflow side force of a body, odd in β",
            (Axis::Y, "qbar*beta^2") => {
                "a side force that does not change sign with β; beside an odd one, on one side of β only"
            }
            (Axis::X, "qbar*alpha^2") | (Axis::X, "qbar*beta^2") => {
                "drag growing with the body's incidence (negative: more drag)"
            }
            _ => "",
        }
    })
}

/// A physical reading of a term on an axis, where one is known; otherwise a plain
/// description of its form.
pub fn reading(axis: wireflight_flight::expr::Axis, r: &Regressor) -> String {
    use wireflight_flight::expr::Axis;
    let what = match axis {
        Axis::X => "axial force",
        Axis::Y => "side force",
        Axis::Z => "normal force",
        Axis::L => "rolling moment",
        Axis::M => "pitching moment",
        Axis::N => "yawing moment",
    };
    worded(what, r, |product| match (axis, product) {
        (Axis::L, "qbar*alpha*beta") => "dihedral effect growing with angle of attack",
        (Axis::L, "qbar*beta") => "dihedral effect",
        (Axis::L, "throttle^2") | (Axis::L, "thrust") | (Axis::L, "throttle") => {
            "the propeller's torque"
        }
        (Axis::L, "") => "an asymmetry: a constant roll (rigging, fuel, torque)",
        (Axis::X, "throttle^2") | (Axis::X, "throttle") => {
            "drag of the propeller's slipstream (sign: negative drags)"
        }
        (Axis::X, "thrust") => "thrust mis-scaled",
        (Axis::X, "airspeed^2") | (Axis::X, "qbar") => "parasite drag mis-estimated",
        (Axis::M, "thrust") | (Axis::M, "throttle^2") | (Axis::M, "throttle") => {
            "a thrust line off the centre of gravity (positive: below it)"
        }
        (Axis::M, "qbar*alpha") => "static stability mis-estimated",
        (Axis::M, "qbar*alpha^2") => "pitch stability changing with angle of attack",
        (Axis::N, "r*throttle") => "yaw damping from the propeller's slipstream over the fin",
        (Axis::N, "throttle^2") | (Axis::N, "thrust") => "the propeller's asymmetric blade load",
        (Axis::N, "qbar*beta") => "weathercock stability mis-estimated",
        (Axis::N, "qbar*alpha*beta") => "directional stability changing with angle of attack",
        (Axis::Y, "qbar*beta") => "side force of the fuselage and fin",
        (Axis::Z, "qbar*alpha") | (Axis::Z, "qbar*sin(alpha)") => "lift slope mis-estimated",
        (Axis::Z, "qbar*alpha^2") => "lift curve bending before the stall",
        _ => "",
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use wireflight_flight::expr::{Expr, Var, N_VARS};

    /// Every candidate, read back as the term language reads its printed expression, has the
    /// value the regression gave it: what `discover` prints to add is what it measured — on
    /// both sides of zero, where `abs`, `max(…,0)` and `min(…,0)` differ.
    #[test]
    fn every_printed_candidate_evaluates_to_its_regressor() {
        let libraries = [fixed_wing(), point_mass(), point_mass_with_incidence()];
        for sign in [1.0, -1.0] {
            let mut v = [0.0; N_VARS];
            for (i, var) in Var::ALL.into_iter().enumerate() {
                // Distinct, of either sign, none zero.
                let alternate = if i % 2 == 0 { 1.0 } else { -1.0 };
                v[var.index()] = sign * alternate * (0.05 + 0.013 * i as f64);
            }
            for r in libraries.iter().flatten() {
                let text = r.expression("k");
                let e = Expr::parse(&text).unwrap_or_else(|err| panic!("{text}: {err}"));
                let (got, want) = (e.eval(&v, &[1.0]), r.value(&v));
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1e-12),
                    "{text}: {got} against {want}"
                );
            }
        }
    }
}
