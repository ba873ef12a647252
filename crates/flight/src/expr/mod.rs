//! Force and moment terms written as formulas: the expression language of
//! `--add 'term:m=k*thrust'` and a model file's `[[term]] axis = "m" expr = "k * thrust"`
//! (see `docs/expressions.md`).
//!
//! An expression is read once ([`Expr::parse`]), compiled to a flat program and then
//! evaluated without allocation or name lookup: the caller fills a [`VarValues`] array by
//! [`Var::index`] and passes the coefficients in the order of [`Expr::coefficients`].
//!
//! * Numbers (`2`, `0.5`, `1.5e-3`), `+ - * / ^`, unary `-`, parentheses. `^` binds tighter
//!   than unary minus and groups right to left: `-a^2` is `-(a^2)`, `2^3^2` is `2^9`.
//! * Functions `sin cos tan abs sqrt exp ln sign` (one argument) and `min max` (two).
//! * The variables of [`VARIABLES`] (angles in radians, SI units).
//! * Every other name is a free **coefficient**, fitted like any parameter (at most
//!   [`MAX_COEFFS`], listed in order of first appearance) — except a name close to a
//!   variable's (`trhust`, `alfa`), refused so that a typo does not become a coefficient
//!   (the rule is [`near_variable`]'s).
//!
//! The value is the force (N) or moment (N·m) itself: the formula is taken literally, with
//! no q̄S or q̄Sc factor added. Errors name the 1-based column (in characters) and the
//! problem: `column 7: unknown function `sinn`: did you mean `sin`? …`.
//!
//! ```
//! use wireflight_flight::expr::{Axis, Term, Var, N_VARS};
//!
//! let term = Term::parse("m = k1*throttle^2 + k2*r*throttle").unwrap();
//! assert_eq!(term.axis, Axis::M);
//! assert_eq!(term.expr.coefficients(), ["k1", "k2"]);
//!
//! let mut vars = [0.0; N_VARS];
//! vars[Var::Throttle.index()] = 0.5;
//! vars[Var::R.index()] = 0.1;
//! let coeffs = [2.0, 3.0];
//! assert_eq!(term.expr.eval(&vars, &coeffs), 2.0 * 0.25 + 3.0 * 0.1 * 0.5);
//!
//! let mut grad = [0.0; 2];
//! term.expr.eval_with_gradient(&vars, &coeffs, &mut grad);
//! assert_eq!(grad, [0.25, 0.1 * 0.5]);
//!
//! let err = Term::parse("m = k*trhust").unwrap_err();
//! assert!(err.to_string().starts_with("column 7: `trhust` is not a variable"));
//! ```

mod compile;
mod error;
mod lex;
mod ops;
mod parse;
mod vars;

#[cfg(test)]
mod tests;

use std::fmt;
use std::str::FromStr;

pub use error::{EvalError, EvalProblem, ParseError, Problem};
pub use parse::near_variable;
pub use vars::{Var, VarValues, Variable, N_VARS, VARIABLES};

/// The longest expression accepted, in characters.
pub const MAX_LEN: usize = 4096;
/// The deepest nesting accepted (parentheses, operators, function calls).
pub const MAX_DEPTH: usize = 64;
/// The most coefficients a term may have.
pub const MAX_COEFFS: usize = 8;

/// The functions: each name and its number of arguments.
pub fn functions() -> impl Iterator<Item = (&'static str, usize)> {
    ops::FUNCTIONS.iter().map(|&(name, f)| (name, f.arity()))
}

/// A compiled expression: its text, its coefficients and its program.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    source: String,
    coeffs: Vec<String>,
    code: compile::Code,
}

impl Expr {
    /// Reads and compiles an expression. It must have at least one coefficient and at most
    /// [`MAX_COEFFS`]; parts made of numbers only are computed now and must be finite.
    pub fn parse(src: &str) -> Result<Expr, ParseError> {
        Self::parse_at(src, 0)
    }

    /// As [`Expr::parse`], for text that begins at column `offset + 1` of what the user wrote.
    fn parse_at(src: &str, offset: usize) -> Result<Expr, ParseError> {
        let parsed = parse::parse(src, offset)?;
        let code = compile::compile(&parsed.ast, parsed.coeffs.len())?;
        Ok(Expr {
            source: src.trim().to_string(),
            coeffs: parsed.coeffs,
            code,
        })
    }

    /// The expression's text (without surrounding blanks).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The coefficients' names, in order of first appearance: the order of the `coeffs`
    /// every evaluation takes.
    pub fn coefficients(&self) -> &[String] {
        &self.coeffs
    }

    /// Whether the expression reads variable `v` (a caller may skip computing the others).
    pub fn uses(&self, v: Var) -> bool {
        self.code.uses(v)
    }

    /// The variables the expression reads, in index order.
    pub fn variables(&self) -> impl Iterator<Item = Var> + '_ {
        Var::ALL.into_iter().filter(|&v| self.uses(v))
    }

    /// The value for these variables and coefficients (`coeffs` in the order of
    /// [`Expr::coefficients`]). A NaN or ∞ is returned as it comes; [`Expr::eval_checked`]
    /// says where it came from.
    ///
    /// # Panics
    ///
    /// If `coeffs` is shorter than [`Expr::coefficients`].
    #[inline]
    pub fn eval(&self, vars: &VarValues, coeffs: &[f64]) -> f64 {
        self.code.eval(vars, coeffs)
    }

    /// The value with each variable's value asked of `var`, only for the variables the
    /// expression reads ([`Expr::uses`]): the same as [`Expr::eval`]'s on a table of those
    /// values, bit for bit, without the table where it can. A product of variables,
    /// coefficients and numbers (`k*thrust`, `k*qbar*alpha*beta`, `k*throttle^2`: most
    /// terms) asks for each variable where it multiplies; any other expression fills a table
    /// of those it reads and runs its program.
    ///
    /// # Panics
    ///
    /// If `coeffs` is shorter than [`Expr::coefficients`].
    #[inline]
    pub fn eval_from(&self, var: impl Fn(Var) -> f64, coeffs: &[f64]) -> f64 {
        self.code.eval_from(var, coeffs)
    }

    /// The value (the same as [`Expr::eval`]'s, bit for bit), and in `grad` its derivative with
    /// respect to each coefficient. Where the derivative is not defined it follows one side:
    /// `abs` has derivative 0 at 0, `min(a, b)` follows `a` when a = b. A derivative that
    /// does not flow is 0 even through an infinite one (`k + sqrt(alpha)` at alpha = 0 has
    /// derivative 1 with respect to `k`).
    ///
    /// # Panics
    ///
    /// If `coeffs` or `grad` is shorter than [`Expr::coefficients`].
    #[inline]
    pub fn eval_with_gradient(&self, vars: &VarValues, coeffs: &[f64], grad: &mut [f64]) -> f64 {
        self.code.eval_with_gradient(vars, coeffs, grad)
    }

    /// The value, or an error naming the first variable or coefficient that is not finite,
    /// or the first operation that gave a NaN or ∞ from finite operands (`ln of a
    /// non-positive number (ln(-0.2))`, `division by zero (3 / 0)`), at its column. Slower
    /// than [`Expr::eval`]: for finding out why a value was not finite.
    ///
    /// # Panics
    ///
    /// If `coeffs` is shorter than [`Expr::coefficients`].
    pub fn eval_checked(&self, vars: &VarValues, coeffs: &[f64]) -> Result<f64, EvalError> {
        self.code.eval_checked(vars, coeffs, &self.coeffs)
    }
}

impl FromStr for Expr {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, ParseError> {
        Expr::parse(s)
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.source)
    }
}

/// Where a term acts: a body-axis force (N) or a moment about a body axis (N·m), FRD.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// Force along body x (forward), N.
    X,
    /// Force along body y (right), N.
    Y,
    /// Force along body z (down), N.
    Z,
    /// Rolling moment about body x, N·m.
    L,
    /// Pitching moment about body y, N·m.
    M,
    /// Yawing moment about body z, N·m.
    N,
}

impl Axis {
    /// Every axis: the forces, then the moments.
    pub const ALL: [Axis; 6] = [Axis::X, Axis::Y, Axis::Z, Axis::L, Axis::M, Axis::N];

    /// Its name: `X`, `Y`, `Z`, `l`, `m` or `n`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "X",
            Axis::Y => "Y",
            Axis::Z => "Z",
            Axis::L => "l",
            Axis::M => "m",
            Axis::N => "n",
        }
    }

    /// Whether it is a force (else a moment).
    pub fn is_force(self) -> bool {
        matches!(self, Axis::X | Axis::Y | Axis::Z)
    }

    /// Its unit: `N` or `N·m`.
    pub fn unit(self) -> &'static str {
        if self.is_force() {
            "N"
        } else {
            "N·m"
        }
    }

    /// The body axis, 0 (x), 1 (y) or 2 (z), of the force or moment.
    pub fn component(self) -> usize {
        match self {
            Axis::X | Axis::L => 0,
            Axis::Y | Axis::M => 1,
            Axis::Z | Axis::N => 2,
        }
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Axis {
    type Err = ParseError;
    /// `X Y Z l m n`, in either case (no two differ by case alone), blanks around ignored.
    fn from_str(s: &str) -> Result<Self, ParseError> {
        let t = s.trim();
        Axis::ALL
            .into_iter()
            .find(|a| a.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| ParseError {
                column: s.chars().take_while(|c| c.is_whitespace()).count() + 1,
                problem: Problem::UnknownAxis(t.to_string()),
            })
    }
}

/// A force or moment term: an axis and the expression giving its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// Where it acts.
    pub axis: Axis,
    /// Its value, N or N·m.
    pub expr: Expr,
}

impl Term {
    /// Reads `AXIS = EXPRESSION` (the command line's `--add 'term:m=k*thrust'` after
    /// `term:`); columns count from the start of `s`.
    pub fn parse(s: &str) -> Result<Term, ParseError> {
        let Some((axis, expr)) = s.split_once('=') else {
            return Err(ParseError {
                column: 1,
                problem: Problem::MissingEquals,
            });
        };
        let axis = axis.parse()?;
        let expr = Expr::parse_at(expr, axis_chars(s))?;
        Ok(Term { axis, expr })
    }

    /// A term from its axis and expression given apart (a model file's `axis` and `expr`);
    /// each error's column counts in the text it is about.
    pub fn new(axis: &str, expr: &str) -> Result<Term, ParseError> {
        Ok(Term {
            axis: axis.parse()?,
            expr: Expr::parse(expr)?,
        })
    }
}

/// The characters up to and including the first `=`.
fn axis_chars(s: &str) -> usize {
    s.chars().take_while(|&c| c != '=').count() + 1
}

impl FromStr for Term {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, ParseError> {
        Term::parse(s)
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.axis, self.expr)
    }
}
