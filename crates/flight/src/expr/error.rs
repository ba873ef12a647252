//! What can be wrong with an expression or a term (refused when read), and what can go wrong
//! when one is evaluated ([`super::Expr::eval_checked`]).

use super::ops::FUNCTIONS;
use super::vars;
use super::{MAX_COEFFS, MAX_DEPTH, MAX_LEN};

/// An expression or term refused: where (the 1-based column, in characters, of the text as
/// given) and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("column {column}: {problem}")]
pub struct ParseError {
    /// The 1-based column, in characters, where the problem is (one past the end for a
    /// problem at the end).
    pub column: usize,
    /// What is wrong.
    pub problem: Problem,
}

/// What is wrong with an expression or a term.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Problem {
    /// Nothing but blanks.
    #[error("the expression is empty")]
    Empty,
    /// Longer than [`MAX_LEN`] characters.
    #[error("the expression is longer than {MAX_LEN} characters")]
    TooLong,
    /// Nested more than [`MAX_DEPTH`] levels deep.
    #[error("the expression is nested more than {MAX_DEPTH} levels deep")]
    TooDeep,
    /// A character that no token begins with.
    #[error("unexpected character `{0}`{hint}", hint = char_hint(*.0))]
    BadChar(char),
    /// A number that does not parse.
    #[error("the number `{0}` does not parse")]
    BadNumber(String),
    /// A number too large for a 64-bit float.
    #[error("the number `{0}` is not finite")]
    NonFiniteNumber(String),
    /// An operand missing after an operator, `(` or `,`.
    #[error("expected an expression after `{after}`{found}", found = found_text(.found))]
    ExpectedOperand {
        /// The token after which an operand was expected.
        after: String,
        /// The token found instead (empty at the end).
        found: String,
    },
    /// An operand missing at the start.
    #[error("expected an expression, found `{0}`")]
    ExpectedExpression(String),
    /// Two operands with no operator between them.
    #[error("expected an operator before `{0}` (a product is written with `*`)")]
    ExpectedOperator(String),
    /// A `(` never closed.
    #[error("this `(` is never closed")]
    Unclosed,
    /// A `)` that closes nothing.
    #[error("this `)` closes nothing")]
    Unmatched,
    /// A `,` outside a function's arguments.
    #[error("`,` outside a function's arguments")]
    StrayComma,
    /// A call of something that is not a function.
    #[error(
        "unknown function `{0}`{hint} (functions: {list}; a product is written with `*`)",
        hint = super::super::params::suggest::hint(.0, FUNCTIONS.iter().map(|f| f.0)),
        list = function_list()
    )]
    UnknownFunction(String),
    /// A variable written like a function.
    #[error("`{0}` is a variable, not a function (a product is written with `*`)")]
    VariableCalled(String),
    /// A function named without its argument.
    #[error("`{0}` is a function: write `{0}(…)`")]
    FunctionNotCalled(String),
    /// A function given the wrong number of arguments.
    #[error(
        "`{name}` takes {expected} argument{s}, given {given}",
        s = if *.expected == 1 { "" } else { "s" }
    )]
    Arity {
        /// The function.
        name: String,
        /// How many it takes.
        expected: usize,
        /// How many were given.
        given: usize,
    },
    /// A name too close to a variable's to be taken for a free coefficient.
    #[error(
        "`{name}` is not a variable, and too close to one to be taken for a free coefficient: \
         did you mean `{variable}`? (variables: {list}; to name a coefficient after a \
         variable, join them with `_`, e.g. `k_{variable}`)",
        list = variable_list()
    )]
    NearVariable {
        /// The name as written.
        name: String,
        /// The variable it is close to.
        variable: &'static str,
    },
    /// More than [`MAX_COEFFS`] coefficients.
    #[error("`{0}` is one coefficient too many: a term has at most {MAX_COEFFS}")]
    TooManyCoefficients(String),
    /// An expression without a free coefficient.
    #[error(
        "the term has no free coefficient, so nothing to fit: write one, e.g. `k * (…)` \
         (every name that is neither a variable nor a function is a coefficient)"
    )]
    NoCoefficient,
    /// A part made of numbers only whose value is not finite.
    #[error("this constant part is {value} ({why})", value = num(*.value))]
    NonFiniteConstant {
        /// Its value.
        value: f64,
        /// Which operation made it so.
        why: EvalProblem,
    },
    /// A term's axis that is none of the six.
    #[error(
        "unknown axis `{0}`: a term acts along X, Y or Z (body force, N) or about l, m or n \
         (body moment, N·m)"
    )]
    UnknownAxis(String),
    /// A term without `=`.
    #[error("expected `AXIS = EXPRESSION`, e.g. `m = k*thrust`")]
    MissingEquals,
}

fn found_text(found: &str) -> String {
    if found.is_empty() {
        String::new()
    } else {
        format!(", found `{found}`")
    }
}

fn char_hint(c: char) -> String {
    let name = match c {
        'α' => "alpha",
        'β' => "beta",
        'ρ' => "rho",
        '·' | '×' => "*",
        '−' => "-",
        '÷' => "/",
        _ => return String::new(),
    };
    format!(" (write `{name}`)")
}

fn function_list() -> String {
    FUNCTIONS.iter().map(|f| f.0).collect::<Vec<_>>().join(", ")
}

/// Every variable's name, for the messages.
pub(crate) fn variable_list() -> String {
    vars::names().collect::<Vec<_>>().join(", ")
}

/// A non-finite value found by [`super::Expr::eval_checked`]: where in the expression and
/// which operation made it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("column {column}: {problem}")]
pub struct EvalError {
    /// The 1-based column of the operation (or name) in the expression's text.
    pub column: usize,
    /// The operation and the values that made it non-finite.
    pub problem: EvalProblem,
}

/// The operation that gave a non-finite value, with the values it was given.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvalProblem {
    /// A variable given a non-finite value.
    #[error("variable `{name}` is {value}", value = num(*.value))]
    Variable {
        /// The variable.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A coefficient given a non-finite value.
    #[error("coefficient `{name}` is {value}", value = num(*.value))]
    Coefficient {
        /// The coefficient.
        name: String,
        /// Its value.
        value: f64,
    },
    /// x / 0.
    #[error("division by zero ({} / 0)", num(*.0))]
    DivisionByZero(f64),
    /// ln x with x ≤ 0.
    #[error("ln of a non-positive number (ln({}))", num(*.0))]
    LnOfNonPositive(f64),
    /// √x with x < 0.
    #[error("sqrt of a negative number (sqrt({}))", num(*.0))]
    SqrtOfNegative(f64),
    /// aᵇ undefined: a negative base with a non-integer exponent, or 0 to a negative power.
    #[error("`^` undefined for {} ^ {}", num(*.0), num(*.1))]
    PowUndefined(f64, f64),
    /// A result too large for a 64-bit float, or ∞ − ∞ and the like.
    #[error("`{op}` of {a}{b} gives {value}", a = num(*.a), b = second(.b), value = num(*.value))]
    Overflow {
        /// The operation.
        op: &'static str,
        /// Its first operand.
        a: f64,
        /// Its second operand, if it has one.
        b: Option<f64>,
        /// What it gave.
        value: f64,
    },
}

fn second(b: &Option<f64>) -> String {
    b.map(|b| format!(" and {}", num(b))).unwrap_or_default()
}

/// A value in full (the shortest text that reads back the same), in scientific notation when
/// very large or small.
fn num(x: f64) -> String {
    if x.is_finite() && x != 0.0 && (x.abs() >= 1e6 || x.abs() < 1e-4) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}
