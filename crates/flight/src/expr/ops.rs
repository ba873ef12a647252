//! The operations of the language, each defined once as a function on `f64`: the constant
//! folder, the evaluators and the tests' reference interpreter all call these, so a value
//! does not depend on where or in which order it was computed.

/// A function of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    /// sin x (x in rad).
    Sin,
    /// cos x.
    Cos,
    /// tan x.
    Tan,
    /// |x|.
    Abs,
    /// √x.
    Sqrt,
    /// eˣ.
    Exp,
    /// ln x.
    Ln,
    /// −1, 0 or 1.
    Sign,
}

/// An operation on two values: the operators and the functions of two arguments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bin {
    /// a + b.
    Add,
    /// a − b.
    Sub,
    /// a · b.
    Mul,
    /// a / b.
    Div,
    /// aᵇ.
    Pow,
    /// The smaller of a and b.
    Min,
    /// The larger of a and b.
    Max,
}

/// A function as named in expressions, with its number of arguments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Callable {
    /// One argument.
    One(Func),
    /// Two arguments.
    Two(Bin),
}

/// The functions, by name, in the order the messages list them.
pub const FUNCTIONS: [(&str, Callable); 10] = [
    ("sin", Callable::One(Func::Sin)),
    ("cos", Callable::One(Func::Cos)),
    ("tan", Callable::One(Func::Tan)),
    ("abs", Callable::One(Func::Abs)),
    ("sqrt", Callable::One(Func::Sqrt)),
    ("exp", Callable::One(Func::Exp)),
    ("ln", Callable::One(Func::Ln)),
    ("min", Callable::Two(Bin::Min)),
    ("max", Callable::Two(Bin::Max)),
    ("sign", Callable::One(Func::Sign)),
];

/// The function of this exact name, if any.
pub fn function(name: &str) -> Option<Callable> {
    FUNCTIONS.iter().find(|(n, _)| *n == name).map(|&(_, c)| c)
}

impl Callable {
    /// How many arguments it takes.
    pub fn arity(self) -> usize {
        match self {
            Callable::One(_) => 1,
            Callable::Two(_) => 2,
        }
    }
}

impl Func {
    /// Its name in expressions.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Abs => "abs",
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sign => "sign",
        }
    }

    /// The function's value.
    #[inline(always)]
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Abs => x.abs(),
            Func::Sqrt => x.sqrt(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Sign => sign(x),
        }
    }

    /// The derivative at `x`, given the value `y = f(x)` already computed. `abs` has
    /// derivative 0 at 0 and `sign` everywhere.
    #[inline(always)]
    pub fn derivative(self, x: f64, y: f64) -> f64 {
        match self {
            Func::Sin => x.cos(),
            Func::Cos => -x.sin(),
            Func::Tan => 1.0 + y * y,
            Func::Abs => sign(x),
            Func::Sqrt => 0.5 / y,
            Func::Exp => y,
            Func::Ln => 1.0 / x,
            Func::Sign => 0.0,
        }
    }
}

impl Bin {
    /// Its symbol or name in expressions.
    pub fn name(self) -> &'static str {
        match self {
            Bin::Add => "+",
            Bin::Sub => "-",
            Bin::Mul => "*",
            Bin::Div => "/",
            Bin::Pow => "^",
            Bin::Min => "min",
            Bin::Max => "max",
        }
    }

    /// The operation's value.
    #[inline(always)]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Bin::Add => a + b,
            Bin::Sub => a - b,
            Bin::Mul => a * b,
            Bin::Div => a / b,
            Bin::Pow => pow(a, b),
            Bin::Min => min(a, b),
            Bin::Max => max(a, b),
        }
    }
}

/// −1, 0 or 1 by the sign of `x` (0 at ±0, NaN for NaN).
#[inline(always)]
pub fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else if x == 0.0 {
        0.0
    } else {
        f64::NAN
    }
}

/// aᵇ; `a^2` is exactly `a*a`.
#[inline(always)]
pub fn pow(a: f64, b: f64) -> f64 {
    if b == 2.0 {
        a * a
    } else {
        a.powf(b)
    }
}

/// The smaller value; NaN if either is NaN (unlike `f64::min`, so that a NaN is seen).
#[inline(always)]
pub fn min(a: f64, b: f64) -> f64 {
    if a <= b {
        a
    } else if b < a {
        b
    } else {
        f64::NAN
    }
}

/// The larger value; NaN if either is NaN.
#[inline(always)]
pub fn max(a: f64, b: f64) -> f64 {
    if a >= b {
        a
    } else if b > a {
        b
    } else {
        f64::NAN
    }
}
