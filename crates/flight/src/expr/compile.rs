//! The tree → a flat postfix program over a small fixed stack, and its evaluators.
//!
//! Parts made of numbers only are folded to one number. Each operation evaluates its deeper
//! operand first (Sethi–Ullman order, with the operands' order recorded in the instruction,
//! so every operation still gets the same operands), which bounds the stack by
//! log₂(leaves) + 1: 12 for the longest expression accepted, within [`STACK`]. A last pass
//! fuses a push into the operation that follows it, and the commonest of those — a product
//! or a sum with a variable, a coefficient or a number, a square — have an instruction of
//! their own: `k*thrust` is two instructions, `k*alpha*beta*qbar` four, each one dispatch.
//! The top of the stack is held apart from the rest, so most instructions touch only it.
//!
//! Three evaluators walk the program: the value alone; the value and its derivatives with
//! respect to the coefficients (forward mode: each stack entry carries its gradient, as wide
//! as the number of coefficients); and the checked one, which names the first operation to
//! give a non-finite value. None allocates.

use super::error::{EvalError, EvalProblem, ParseError, Problem};
use super::ops::{Bin, Func};
use super::parse::{Ast, Node};
use super::vars::{Var, VarValues, N_VARS, VARIABLES};

/// The stack's depth: more than any accepted expression needs (see the module's notes).
pub const STACK: usize = 16;

/// The stack of the gradient's evaluator for the usual short terms.
const SHORT: usize = 4;

// At most MAX_LEN / 2 + 1 leaves, so a need of log₂ of that + 1; variables in a u32 mask.
const _: () = assert!(STACK >= 13 && super::MAX_LEN <= 1 << 13 && super::vars::N_VARS <= 32);

/// A value pushed: a number, a variable or a coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Leaf {
    /// A number.
    Const(f64),
    /// A variable, by index.
    Var(u8),
    /// A coefficient, by index.
    Coef(u8),
}

/// One instruction. The top of the stack is held apart (in a register), so most
/// instructions touch only it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Instr {
    /// Push a value.
    Push(Leaf),
    /// top ← −top.
    Neg,
    /// top ← f(top).
    Call(Func),
    /// Pop a, then top ← a op top.
    Bin(Bin),
    /// Pop b, then top ← top op b (the right operand was computed first).
    BinRev(Bin),
    /// top ← top op leaf.
    BinLeaf(Bin, Leaf),
    /// top ← leaf op top.
    LeafBin(Bin, Leaf),
    /// top ← top · variable (the commonest fused operations, with one dispatch each).
    MulVar(u8),
    /// top ← top · coefficient.
    MulCoef(u8),
    /// top ← top · constant.
    MulConst(f64),
    /// top ← top + variable.
    AddVar(u8),
    /// top ← top + coefficient.
    AddCoef(u8),
    /// top ← top + constant.
    AddConst(f64),
    /// top ← top².
    Square,
}

/// A compiled expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Code {
    /// The fused program, for [`Code::eval`] and [`Code::eval_with_gradient`].
    fast: Vec<Instr>,
    /// The program before fusion (pushes and operations only), for [`Code::eval_checked`].
    plain: Vec<Instr>,
    /// Each plain instruction's column.
    columns: Vec<usize>,
    /// How many coefficients.
    n_coeffs: usize,
    /// How many values the program holds at once (the top included).
    need: usize,
    /// Bit i set if variable i is used.
    uses: u32,
    /// The program as a product, when it is one (see [`Product`]).
    product: Option<Product>,
}

/// A program that is one product, left to right: a first value, then multiplications by a
/// variable, a coefficient or a number, and squares — `k*thrust`, `k*qbar*alpha*beta`,
/// `k*throttle^2`, the form of most terms (every regressor `discover` proposes but the sines).
/// Walked without the stack and with each variable asked for where it multiplies, it gives
/// the fused program's value bit for bit: the same multiplications in the same order.
#[derive(Clone, Debug, PartialEq)]
struct Product {
    first: Factor,
    /// Each multiplies what came before (a square squares it).
    factors: Vec<Factor>,
}

/// A value of a [`Product`], with its variable resolved when the program is compiled.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Factor {
    Var(Var),
    Coef(u8),
    Const(f64),
    /// What came before, again (top ← top²).
    Square,
}

impl Factor {
    fn of(leaf: Leaf) -> Option<Factor> {
        Some(match leaf {
            Leaf::Var(i) => Factor::Var(*Var::ALL.get(i as usize)?),
            Leaf::Coef(j) => Factor::Coef(j),
            Leaf::Const(c) => Factor::Const(c),
        })
    }

    /// `top` times this factor.
    #[inline(always)]
    fn times<F: Fn(Var) -> f64>(self, top: f64, var: &F, coeffs: &[f64]) -> f64 {
        match self {
            Factor::Var(v) => top * var(v),
            Factor::Coef(j) => top * coeffs[j as usize],
            Factor::Const(c) => top * c,
            Factor::Square => top * top,
        }
    }

    /// This factor's value as the product's first (a square has none: 0, never made).
    #[inline(always)]
    fn value<F: Fn(Var) -> f64>(self, var: &F, coeffs: &[f64]) -> f64 {
        match self {
            Factor::Var(v) => var(v),
            Factor::Coef(j) => coeffs[j as usize],
            Factor::Const(c) => c,
            Factor::Square => 0.0,
        }
    }
}

impl Product {
    /// The fused program as a product, if it is one.
    fn of(fast: &[Instr]) -> Option<Product> {
        let (Instr::Push(first), rest) = fast.split_first()? else {
            return None;
        };
        let factors = rest
            .iter()
            .map(|ins| match *ins {
                Instr::MulVar(i) => Factor::of(Leaf::Var(i)),
                Instr::MulCoef(j) => Factor::of(Leaf::Coef(j)),
                Instr::MulConst(c) => Factor::of(Leaf::Const(c)),
                Instr::Square => Some(Factor::Square),
                _ => None,
            })
            .collect::<Option<Vec<Factor>>>()?;
        Some(Product {
            first: Factor::of(*first)?,
            factors,
        })
    }
}

/// A piece of program under construction.
struct Piece {
    code: Vec<(Instr, usize)>,
    need: usize,
    constant: Option<f64>,
}

impl Piece {
    fn leaf(leaf: Leaf, column: usize) -> Piece {
        Piece {
            code: vec![(Instr::Push(leaf), column)],
            need: 1,
            constant: match leaf {
                Leaf::Const(c) => Some(c),
                _ => None,
            },
        }
    }
}

/// Compiles a tree with `n_coeffs` coefficients.
pub fn compile(ast: &Ast, n_coeffs: usize) -> Result<Code, ParseError> {
    let piece = piece(ast)?;
    if piece.need > STACK {
        // Not reachable within MAX_LEN (see the module's notes); refused rather than trusted.
        return Err(ParseError {
            column: ast.column,
            problem: Problem::TooDeep,
        });
    }
    let (plain, columns): (Vec<Instr>, Vec<usize>) = piece.code.into_iter().unzip();
    let mut uses = 0u32;
    for ins in &plain {
        if let Instr::Push(Leaf::Var(i)) = ins {
            uses |= 1 << i;
        }
    }
    let fast = fuse(&plain);
    Ok(Code {
        product: Product::of(&fast),
        fast,
        plain,
        columns,
        n_coeffs,
        need: piece.need,
        uses,
    })
}

fn piece(ast: &Ast) -> Result<Piece, ParseError> {
    let col = ast.column;
    Ok(match &ast.node {
        Node::Num(x) => Piece::leaf(Leaf::Const(*x), col),
        Node::Var(v) => Piece::leaf(Leaf::Var(*v as u8), col),
        Node::Coef(i) => Piece::leaf(Leaf::Coef(*i as u8), col),
        Node::Neg(x) => {
            let mut p = piece(x)?;
            match p.constant {
                Some(c) => Piece::leaf(Leaf::Const(-c), col),
                None => {
                    p.code.push((Instr::Neg, col));
                    p
                }
            }
        }
        Node::Call(f, x) => {
            let mut p = piece(x)?;
            match p.constant {
                Some(c) => {
                    let y = f.apply(c);
                    if !y.is_finite() {
                        return Err(non_finite(col, y, call_problem(*f, c, y)));
                    }
                    Piece::leaf(Leaf::Const(y), col)
                }
                None => {
                    p.code.push((Instr::Call(*f), col));
                    p
                }
            }
        }
        Node::Bin(op, a, b) => binary(*op, col, piece(a)?, piece(b)?)?,
        Node::Chain(first, rest) => {
            let mut acc = piece(first)?;
            for (op, col, x) in rest {
                acc = binary(*op, *col, acc, piece(x)?)?;
            }
            acc
        }
    })
}

fn binary(op: Bin, col: usize, a: Piece, b: Piece) -> Result<Piece, ParseError> {
    if let (Some(x), Some(y)) = (a.constant, b.constant) {
        let v = op.apply(x, y);
        if !v.is_finite() {
            return Err(non_finite(col, v, bin_problem(op, x, y, v)));
        }
        return Ok(Piece::leaf(Leaf::Const(v), col));
    }
    let (first, second, ins) = if b.need > a.need {
        (b, a, Instr::BinRev(op))
    } else {
        (a, b, Instr::Bin(op))
    };
    let need = first.need.max(second.need + 1);
    let mut code = first.code;
    code.extend(second.code);
    code.push((ins, col));
    Ok(Piece {
        code,
        need,
        constant: None,
    })
}

fn non_finite(column: usize, value: f64, why: EvalProblem) -> ParseError {
    ParseError {
        column,
        problem: Problem::NonFiniteConstant { value, why },
    }
}

/// Why f(x) = y is not finite (x finite).
fn call_problem(f: Func, x: f64, y: f64) -> EvalProblem {
    match f {
        Func::Ln if x <= 0.0 => EvalProblem::LnOfNonPositive(x),
        Func::Sqrt if x < 0.0 => EvalProblem::SqrtOfNegative(x),
        _ => EvalProblem::Overflow {
            op: f.name(),
            a: x,
            b: None,
            value: y,
        },
    }
}

/// Why a op b = y is not finite (a, b finite).
fn bin_problem(op: Bin, a: f64, b: f64, y: f64) -> EvalProblem {
    match op {
        Bin::Div if b == 0.0 => EvalProblem::DivisionByZero(a),
        Bin::Pow if (a < 0.0 && b.fract() != 0.0) || (a == 0.0 && b < 0.0) => {
            EvalProblem::PowUndefined(a, b)
        }
        _ => EvalProblem::Overflow {
            op: op.name(),
            a,
            b: Some(b),
            value: y,
        },
    }
}

/// A push followed by a binary operation becomes one instruction; the commonest become
/// specialised ones. (`a + b` and `b + a` are the same number in floating point, as are
/// `a * b` and `b * a`, so a reversed sum or product is an ordinary one.)
fn fuse(plain: &[Instr]) -> Vec<Instr> {
    let mut out: Vec<Instr> = Vec::with_capacity(plain.len());
    for &ins in plain {
        let fused = match (out.last(), ins) {
            // The push must not be the program's first value: the operation needs another
            // operand below it.
            (Some(&Instr::Push(leaf)), Instr::Bin(op) | Instr::BinRev(op)) if out.len() >= 2 => {
                let reversed = matches!(ins, Instr::BinRev(_));
                Some(match (op, leaf) {
                    (Bin::Mul, Leaf::Var(i)) => Instr::MulVar(i),
                    (Bin::Mul, Leaf::Coef(j)) => Instr::MulCoef(j),
                    (Bin::Mul, Leaf::Const(c)) => Instr::MulConst(c),
                    (Bin::Add, Leaf::Var(i)) => Instr::AddVar(i),
                    (Bin::Add, Leaf::Coef(j)) => Instr::AddCoef(j),
                    (Bin::Add, Leaf::Const(c)) => Instr::AddConst(c),
                    (Bin::Pow, Leaf::Const(c)) if c == 2.0 && !reversed => Instr::Square,
                    _ if reversed => Instr::LeafBin(op, leaf),
                    _ => Instr::BinLeaf(op, leaf),
                })
            }
            _ => None,
        };
        match fused {
            Some(f) => *out.last_mut().expect("matched a last instruction") = f,
            None => out.push(ins),
        }
    }
    out
}

#[inline(always)]
fn leaf(l: Leaf, vars: &VarValues, coeffs: &[f64]) -> f64 {
    match l {
        Leaf::Const(c) => c,
        Leaf::Var(i) => vars[i as usize],
        Leaf::Coef(j) => coeffs[j as usize],
    }
}

/// A value and its derivatives with respect to the coefficients (`W` ≥ their number).
#[derive(Clone, Copy)]
struct Dual<const W: usize> {
    v: f64,
    d: [f64; W],
}

impl<const W: usize> Dual<W> {
    const ZERO: Self = Dual {
        v: 0.0,
        d: [0.0; W],
    };

    #[inline(always)]
    fn leaf(l: Leaf, vars: &VarValues, coeffs: &[f64]) -> Self {
        let mut x = Dual {
            v: leaf(l, vars, coeffs),
            d: [0.0; W],
        };
        if let Leaf::Coef(j) = l {
            x.d[j as usize] = 1.0;
        }
        x
    }
}

/// g·d, with 0 where d is 0 (a derivative that does not flow is 0, even through ∞).
#[inline(always)]
fn scale<const W: usize>(g: f64, d: &[f64; W]) -> [f64; W] {
    let mut out = [0.0; W];
    for (o, &x) in out.iter_mut().zip(d) {
        *o = if x == 0.0 { 0.0 } else { g * x };
    }
    out
}

#[inline(always)]
fn add<const W: usize>(a: [f64; W], b: [f64; W]) -> [f64; W] {
    let mut out = a;
    for (o, x) in out.iter_mut().zip(b) {
        *o += x;
    }
    out
}

#[inline(always)]
fn call_dual<const W: usize>(f: Func, x: Dual<W>) -> Dual<W> {
    let v = f.apply(x.v);
    let d = if x.d.iter().all(|&d| d == 0.0) {
        [0.0; W]
    } else {
        scale(f.derivative(x.v, v), &x.d)
    };
    Dual { v, d }
}

#[inline(always)]
fn bin_dual<const W: usize>(op: Bin, a: Dual<W>, b: Dual<W>) -> Dual<W> {
    let v = op.apply(a.v, b.v);
    let d = match op {
        Bin::Add => add(a.d, b.d),
        Bin::Sub => add(a.d, scale(-1.0, &b.d)),
        Bin::Mul => add(scale(b.v, &a.d), scale(a.v, &b.d)),
        Bin::Div => add(scale(1.0 / b.v, &a.d), scale(-v / b.v, &b.d)),
        Bin::Pow => {
            let da = if a.d.iter().all(|&d| d == 0.0) {
                [0.0; W]
            } else if b.v == 2.0 {
                scale(2.0 * a.v, &a.d)
            } else {
                scale(b.v * a.v.powf(b.v - 1.0), &a.d)
            };
            let db = if b.d.iter().all(|&d| d == 0.0) {
                [0.0; W]
            } else {
                scale(v * a.v.ln(), &b.d)
            };
            add(da, db)
        }
        Bin::Min => {
            if a.v <= b.v {
                a.d
            } else {
                b.d
            }
        }
        Bin::Max => {
            if a.v >= b.v {
                a.d
            } else {
                b.d
            }
        }
    };
    Dual { v, d }
}

impl Code {
    /// Whether variable `v` is used.
    pub fn uses(&self, v: Var) -> bool {
        self.uses & (1 << v.index()) != 0
    }

    /// The fused program (for the tests).
    #[cfg(test)]
    pub fn fast(&self) -> &[Instr] {
        &self.fast
    }

    /// Whether the program is walked as a product (for the tests).
    #[cfg(test)]
    pub fn is_product(&self) -> bool {
        self.product.is_some()
    }

    /// The stack depth the program needs (for the tests).
    #[cfg(test)]
    pub fn depth(&self) -> usize {
        let (mut n, mut most) = (0usize, 0usize);
        for ins in &self.fast {
            match ins {
                Instr::Push(_) => n += 1,
                Instr::Bin(_) | Instr::BinRev(_) => n -= 1,
                _ => {}
            }
            most = most.max(n);
        }
        most
    }

    /// The value.
    #[inline]
    pub fn eval(&self, vars: &VarValues, coeffs: &[f64]) -> f64 {
        // `s[1..n]` holds the values below the top (`s[0]` what was the top before the first).
        let mut s = [0.0f64; STACK];
        let mut n = 0usize;
        let mut top = 0.0f64;
        for &ins in &self.fast {
            match ins {
                Instr::Push(l) => {
                    s[n] = top;
                    n += 1;
                    top = leaf(l, vars, coeffs);
                }
                Instr::MulVar(i) => top *= vars[i as usize],
                Instr::MulCoef(j) => top *= coeffs[j as usize],
                Instr::MulConst(c) => top *= c,
                Instr::AddVar(i) => top += vars[i as usize],
                Instr::AddCoef(j) => top += coeffs[j as usize],
                Instr::AddConst(c) => top += c,
                Instr::Square => top *= top,
                Instr::Neg => top = -top,
                Instr::Call(f) => top = f.apply(top),
                Instr::Bin(op) => {
                    n -= 1;
                    top = op.apply(s[n], top);
                }
                Instr::BinRev(op) => {
                    n -= 1;
                    top = op.apply(top, s[n]);
                }
                Instr::BinLeaf(op, l) => top = op.apply(top, leaf(l, vars, coeffs)),
                Instr::LeafBin(op, l) => top = op.apply(leaf(l, vars, coeffs), top),
            }
        }
        top
    }

    /// The value, each variable's asked of `var` and only for the variables used: a product
    /// asks for each where it multiplies, with no table filled; any other program is run on
    /// a table filled with those it reads. The same as [`Code::eval`]'s, bit for bit.
    #[inline]
    pub fn eval_from(&self, var: impl Fn(Var) -> f64, coeffs: &[f64]) -> f64 {
        let Some(product) = &self.product else {
            return self.eval_filled(&var, coeffs);
        };
        let mut top = product.first.value(&var, coeffs);
        for f in &product.factors {
            top = f.times(top, &var, coeffs);
        }
        top
    }

    /// [`Code::eval_from`] of a program that is no product: a table filled with the
    /// variables it reads, then the program. Apart, so that a product's walk stays short
    /// where it is inlined.
    #[inline(never)]
    fn eval_filled<F: Fn(Var) -> f64>(&self, var: &F, coeffs: &[f64]) -> f64 {
        let mut vars = [0.0; N_VARS];
        let mut left = self.uses;
        // Bounded: one pass per bit set, at most N_VARS.
        while left != 0 {
            let i = left.trailing_zeros() as usize;
            left &= left - 1;
            vars[i] = var(Var::ALL[i]);
        }
        self.eval(&vars, coeffs)
    }

    /// The value, and its derivative with respect to each coefficient in `grad[..n_coeffs]`.
    #[inline]
    pub fn eval_with_gradient(&self, vars: &VarValues, coeffs: &[f64], grad: &mut [f64]) -> f64 {
        // A short stack for the usual terms: nothing to clear but a few entries.
        if self.need <= SHORT {
            match self.n_coeffs {
                0 | 1 => self.dual::<1, SHORT>(vars, coeffs, grad),
                2 => self.dual::<2, SHORT>(vars, coeffs, grad),
                3 | 4 => self.dual::<4, SHORT>(vars, coeffs, grad),
                _ => self.dual::<{ super::MAX_COEFFS }, SHORT>(vars, coeffs, grad),
            }
        } else {
            match self.n_coeffs {
                0..=4 => self.dual::<4, STACK>(vars, coeffs, grad),
                _ => self.dual::<{ super::MAX_COEFFS }, STACK>(vars, coeffs, grad),
            }
        }
    }

    /// The gradient's evaluator, `W` wide, for programs that hold at most `S` values.
    fn dual<const W: usize, const S: usize>(
        &self,
        vars: &VarValues,
        coeffs: &[f64],
        grad: &mut [f64],
    ) -> f64 {
        let mut s = [Dual::<W>::ZERO; S];
        let mut n = 0usize;
        let mut top = Dual::<W>::ZERO;
        for &ins in &self.fast {
            match ins {
                Instr::Push(l) => {
                    s[n] = top;
                    n += 1;
                    top = Dual::leaf(l, vars, coeffs);
                }
                Instr::MulVar(i) => {
                    let x = vars[i as usize];
                    top.d = scale(x, &top.d);
                    top.v *= x;
                }
                Instr::MulCoef(j) => {
                    let c = coeffs[j as usize];
                    top.d = scale(c, &top.d);
                    top.d[j as usize] += top.v;
                    top.v *= c;
                }
                Instr::MulConst(c) => {
                    top.d = scale(c, &top.d);
                    top.v *= c;
                }
                Instr::AddVar(i) => top.v += vars[i as usize],
                Instr::AddCoef(j) => {
                    top.v += coeffs[j as usize];
                    top.d[j as usize] += 1.0;
                }
                Instr::AddConst(c) => top.v += c,
                Instr::Square => {
                    top.d = scale(2.0 * top.v, &top.d);
                    top.v *= top.v;
                }
                Instr::Neg => {
                    top = Dual {
                        v: -top.v,
                        d: scale(-1.0, &top.d),
                    };
                }
                Instr::Call(f) => top = call_dual(f, top),
                Instr::Bin(op) => {
                    n -= 1;
                    top = bin_dual(op, s[n], top);
                }
                Instr::BinRev(op) => {
                    n -= 1;
                    top = bin_dual(op, top, s[n]);
                }
                Instr::BinLeaf(op, l) => top = bin_dual(op, top, Dual::leaf(l, vars, coeffs)),
                Instr::LeafBin(op, l) => top = bin_dual(op, Dual::leaf(l, vars, coeffs), top),
            }
        }
        let k = self.n_coeffs;
        grad[..k].copy_from_slice(&top.d[..k]);
        top.v
    }

    /// The value if it is finite; else the first operation (in evaluation order) to give a
    /// non-finite value from finite operands, or the first non-finite variable or
    /// coefficient read.
    pub fn eval_checked(
        &self,
        vars: &VarValues,
        coeffs: &[f64],
        coeff_names: &[String],
    ) -> Result<f64, EvalError> {
        let mut s = [0.0f64; STACK];
        let mut n = 0usize;
        let mut first: Option<EvalError> = None;
        for (&ins, &column) in self.plain.iter().zip(&self.columns) {
            let mut note = |problem| {
                first.get_or_insert(EvalError { column, problem });
            };
            match ins {
                Instr::Push(l) => {
                    let x = leaf(l, vars, coeffs);
                    if !x.is_finite() {
                        note(match l {
                            Leaf::Var(i) => EvalProblem::Variable {
                                name: VARIABLES[i as usize].name,
                                value: x,
                            },
                            Leaf::Coef(j) => EvalProblem::Coefficient {
                                name: coeff_names[j as usize].clone(),
                                value: x,
                            },
                            Leaf::Const(_) => unreachable_constant(x),
                        });
                    }
                    s[n] = x;
                    n += 1;
                }
                Instr::Neg => s[n - 1] = -s[n - 1],
                Instr::Call(f) => {
                    let x = s[n - 1];
                    let y = f.apply(x);
                    if x.is_finite() && !y.is_finite() {
                        note(call_problem(f, x, y));
                    }
                    s[n - 1] = y;
                }
                Instr::Bin(op) | Instr::BinRev(op) => {
                    n -= 1;
                    let (a, b) = match ins {
                        Instr::Bin(_) => (s[n - 1], s[n]),
                        _ => (s[n], s[n - 1]),
                    };
                    let y = op.apply(a, b);
                    if a.is_finite() && b.is_finite() && !y.is_finite() {
                        note(bin_problem(op, a, b, y));
                    }
                    s[n - 1] = y;
                }
                // The plain program has no fused instructions.
                _ => {}
            }
        }
        match first {
            Some(err) if !s[0].is_finite() => Err(err),
            _ if !s[0].is_finite() => Err(EvalError {
                column: self.columns.last().copied().unwrap_or(1),
                problem: unreachable_constant(s[0]),
            }),
            _ => Ok(s[0]),
        }
    }
}

/// Constants are finite when compiled, and a non-finite value starts somewhere; should that
/// fail, the value is reported as it is.
fn unreachable_constant(x: f64) -> EvalProblem {
    EvalProblem::Overflow {
        op: "constant",
        a: x,
        b: None,
        value: x,
    }
}
