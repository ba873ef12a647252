//! The variables an expression may name: a fixed table, the contract between the expression
//! language and the flight model that fills it. The caller fills a [`VarValues`] array by
//! [`Var::index`] before each evaluation; no name is looked up while evaluating.

/// How many variables there are: the length of [`VarValues`].
pub const N_VARS: usize = 18;

/// The values of every variable, indexed by [`Var::index`] (in the order of [`VARIABLES`]).
pub type VarValues = [f64; N_VARS];

/// One variable of the table: its name in expressions, its unit and what it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variable {
    /// The variable as [`Var`].
    pub var: Var,
    /// Its name in expressions.
    pub name: &'static str,
    /// Its unit (`1` for a dimensionless number).
    pub unit: &'static str,
    /// What it is, in a few words.
    pub meaning: &'static str,
}

/// A variable of the table, by index: `Var::Thrust.index()` is where the caller writes the
/// thrust in [`VarValues`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Var {
    /// Angle of attack α, rad.
    Alpha,
    /// Sideslip angle β, rad.
    Beta,
    /// Non-dimensional roll rate p·b/(2V).
    PHat,
    /// Non-dimensional pitch rate q·c/(2V).
    QHat,
    /// Non-dimensional yaw rate r·b/(2V).
    RHat,
    /// Body roll rate p, rad/s.
    P,
    /// Body pitch rate q, rad/s.
    Q,
    /// Body yaw rate r, rad/s.
    R,
    /// Elevator deflection δe, rad.
    Elevator,
    /// Aileron deflection δa, rad.
    Aileron,
    /// Rudder deflection δr, rad.
    Rudder,
    /// Throttle δt, 0..1.
    Throttle,
    /// The model's thrust, N.
    Thrust,
    /// Airspeed V, m/s.
    Airspeed,
    /// Dynamic pressure q̄ = ½ρV², Pa.
    Qbar,
    /// Air density ρ, kg/m³.
    Rho,
    /// Height above the ground, m.
    Height,
    /// The magnitude of gravity, m/s².
    G,
}

/// The table of variables, in [`Var::index`] order.
pub static VARIABLES: [Variable; N_VARS] = [
    v(
        Var::Alpha,
        "alpha",
        "rad",
        "angle of attack α = atan2(w_r, u_r)",
    ),
    v(Var::Beta, "beta", "rad", "sideslip angle β = asin(v_r / V)"),
    v(
        Var::PHat,
        "p_hat",
        "1",
        "non-dimensional roll rate p·b/(2V)",
    ),
    v(
        Var::QHat,
        "q_hat",
        "1",
        "non-dimensional pitch rate q·c/(2V)",
    ),
    v(Var::RHat, "r_hat", "1", "non-dimensional yaw rate r·b/(2V)"),
    v(Var::P, "p", "rad/s", "body roll rate"),
    v(Var::Q, "q", "rad/s", "body pitch rate"),
    v(Var::R, "r", "rad/s", "body yaw rate"),
    v(Var::Elevator, "elevator", "rad", "elevator deflection δe"),
    v(Var::Aileron, "aileron", "rad", "aileron deflection δa"),
    v(Var::Rudder, "rudder", "rad", "rudder deflection δr"),
    v(Var::Throttle, "throttle", "1", "throttle δt, 0..1"),
    v(Var::Thrust, "thrust", "N", "the model's propeller thrust"),
    v(Var::Airspeed, "airspeed", "m/s", "airspeed V"),
    v(Var::Qbar, "qbar", "Pa", "dynamic pressure q̄ = ½ρV²"),
    v(Var::Rho, "rho", "kg/m³", "air density ρ"),
    v(Var::Height, "height", "m", "height above the ground"),
    v(Var::G, "g", "m/s²", "the magnitude of gravity"),
];

const fn v(var: Var, name: &'static str, unit: &'static str, meaning: &'static str) -> Variable {
    Variable {
        var,
        name,
        unit,
        meaning,
    }
}

impl Var {
    /// Every variable, in index order.
    pub const ALL: [Var; N_VARS] = [
        Var::Alpha,
        Var::Beta,
        Var::PHat,
        Var::QHat,
        Var::RHat,
        Var::P,
        Var::Q,
        Var::R,
        Var::Elevator,
        Var::Aileron,
        Var::Rudder,
        Var::Throttle,
        Var::Thrust,
        Var::Airspeed,
        Var::Qbar,
        Var::Rho,
        Var::Height,
        Var::G,
    ];

    /// Where this variable's value goes in [`VarValues`].
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Its row of [`VARIABLES`].
    pub fn info(self) -> &'static Variable {
        &VARIABLES[self.index()]
    }

    /// Its name in expressions.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Its unit.
    pub fn unit(self) -> &'static str {
        self.info().unit
    }

    /// The variable of this exact name (case matters), if any.
    pub fn from_name(name: &str) -> Option<Var> {
        VARIABLES
            .iter()
            .find(|row| row.name == name)
            .map(|row| row.var)
    }
}

/// Every variable's name, in index order.
pub fn names() -> impl Iterator<Item = &'static str> + Clone {
    VARIABLES.iter().map(|row| row.name)
}
