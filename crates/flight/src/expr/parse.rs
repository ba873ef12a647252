//! Tokens → a tree, by precedence climbing: `+ -` < `* /` < unary `-` < `^` (right to left),
//! so `-a^2` is `-(a^2)` and `2^-a` is `2^(-a)`. Names are resolved here: a variable, a
//! function (with its number of arguments checked), or a free coefficient.

use super::error::{ParseError, Problem};
use super::lex::{tokens, Tok, Token};
use super::ops::{function, Bin, Callable, Func};
use super::vars::{Var, VARIABLES};
use super::{MAX_COEFFS, MAX_DEPTH, MAX_LEN};
use crate::params::suggest::distance;

/// A node of the tree and the column it is reported at (an operator's, a function's name's,
/// a leaf's).
#[derive(Clone, Debug, PartialEq)]
pub struct Ast {
    /// What it is.
    pub node: Node,
    /// Its 1-based column.
    pub column: usize,
}

/// What a node is.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// A number.
    Num(f64),
    /// A variable.
    Var(Var),
    /// A coefficient, by its index in order of first appearance.
    Coef(usize),
    /// −x.
    Neg(Box<Ast>),
    /// f(x).
    Call(Func, Box<Ast>),
    /// a op b (`^`, `min`, `max`).
    Bin(Bin, Box<Ast>, Box<Ast>),
    /// `a op₁ b op₂ c …` of one precedence (`+ -` or `* /`), evaluated left to right; kept
    /// flat so that a long sum is not a deep tree. Each operand carries its operator's column.
    Chain(Box<Ast>, Vec<(Bin, usize, Ast)>),
}

/// A parsed expression: its tree and its coefficients' names in order of first appearance.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The tree.
    pub ast: Ast,
    /// The coefficients.
    pub coeffs: Vec<String>,
}

/// Parses `src`; columns are reported as `offset` + the column in `src`.
pub fn parse(src: &str, offset: usize) -> Result<Parsed, ParseError> {
    if src.chars().count() > MAX_LEN {
        return Err(err(offset + MAX_LEN + 1, Problem::TooLong));
    }
    let toks = tokens(src, offset)?;
    if toks[0].tok == Tok::End {
        return Err(err(offset + 1, Problem::Empty));
    }
    let mut p = Parser {
        toks,
        pos: 0,
        coeffs: Vec::new(),
    };
    let ast = p.expr(0, 1)?;
    let t = p.peek();
    match t.tok {
        Tok::End => {}
        Tok::Close => return Err(err(t.column, Problem::Unmatched)),
        Tok::Comma => return Err(err(t.column, Problem::StrayComma)),
        _ => return Err(err(t.column, Problem::ExpectedOperator(t.text.to_string()))),
    }
    if p.coeffs.is_empty() {
        return Err(err(offset + 1, Problem::NoCoefficient));
    }
    Ok(Parsed {
        ast,
        coeffs: p.coeffs,
    })
}

/// The variable that `name` (neither a variable nor a function) is too close to, if any: within
/// 0 edits (apart from case) of a one- or two-letter variable, 1 of a three- or four-letter
/// one, 2 of a longer one. A name with a `_`-separated part that is a variable of three
/// letters or more (`k_thrust`, `alpha_0`) is deliberate and close to none.
pub fn near_variable(name: &str) -> Option<Var> {
    if name
        .split('_')
        .any(|part| part.len() >= 3 && Var::from_name(part).is_some())
    {
        return None;
    }
    let mut best: Option<(usize, Var)> = None;
    for row in &VARIABLES {
        let limit = match row.name.len() {
            0..=2 => 0,
            3 | 4 => 1,
            _ => 2,
        };
        let d = distance(name, row.name);
        if d <= limit && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, row.var));
        }
    }
    best.map(|(_, var)| var)
}

fn err(column: usize, problem: Problem) -> ParseError {
    ParseError { column, problem }
}

struct Parser<'a> {
    toks: Vec<Token<'a>>,
    pos: usize,
    coeffs: Vec<String>,
}

/// Binding powers: (left, right) of the binary operators; unary minus binds its operand at
/// `UNARY`, between `* /` and `^`.
const UNARY: u8 = 5;

fn binary(c: char) -> (Bin, u8, u8) {
    match c {
        '+' => (Bin::Add, 1, 2),
        '-' => (Bin::Sub, 1, 2),
        '*' => (Bin::Mul, 3, 4),
        '/' => (Bin::Div, 3, 4),
        _ => (Bin::Pow, 6, 5),
    }
}

impl<'a> Parser<'a> {
    fn peek(&self) -> &Token<'a> {
        &self.toks[self.pos]
    }

    fn next(&mut self) -> Token<'a> {
        let t = self.toks[self.pos].clone();
        if t.tok != Tok::End {
            self.pos += 1;
        }
        t
    }

    /// An expression whose operators bind at least `min_bp`, at nesting level `depth`.
    fn expr(&mut self, min_bp: u8, depth: usize) -> Result<Ast, ParseError> {
        if depth > MAX_DEPTH {
            return Err(err(self.peek().column, Problem::TooDeep));
        }
        let mut lhs = self.operand(depth)?;
        // Whether `lhs` is a chain built by this loop (to be extended) rather than an operand.
        let mut chained = false;
        loop {
            let t = self.peek().clone();
            let c = match t.tok {
                Tok::Op(c) => c,
                Tok::Close | Tok::Comma | Tok::End => break,
                Tok::Num(_) | Tok::Ident(_) | Tok::Open => {
                    return Err(err(t.column, Problem::ExpectedOperator(t.text.to_string())))
                }
            };
            let (op, l_bp, r_bp) = binary(c);
            if l_bp < min_bp {
                break;
            }
            self.next();
            let rhs = self.expr(r_bp, depth + 1)?;
            if op == Bin::Pow {
                lhs = Ast {
                    node: Node::Bin(op, Box::new(lhs), Box::new(rhs)),
                    column: t.column,
                };
                chained = false;
                continue;
            }
            let additive = matches!(op, Bin::Add | Bin::Sub);
            match &mut lhs.node {
                Node::Chain(_, rest)
                    if chained && matches!(rest[0].0, Bin::Add | Bin::Sub) == additive =>
                {
                    rest.push((op, t.column, rhs));
                }
                _ => {
                    let column = lhs.column;
                    lhs = Ast {
                        node: Node::Chain(Box::new(lhs), vec![(op, t.column, rhs)]),
                        column,
                    };
                    chained = true;
                }
            }
        }
        Ok(lhs)
    }

    /// A number, a name, a call, a parenthesised expression or a negation.
    fn operand(&mut self, depth: usize) -> Result<Ast, ParseError> {
        let prev = self
            .pos
            .checked_sub(1)
            .map(|i| self.toks[i].text.to_string());
        let t = self.next();
        let leaf = |node| Ast {
            node,
            column: t.column,
        };
        match t.tok {
            Tok::Num(x) => Ok(leaf(Node::Num(x))),
            Tok::Op('-') => {
                let x = self.expr(UNARY, depth + 1)?;
                Ok(leaf(Node::Neg(Box::new(x))))
            }
            Tok::Open => {
                let x = self.expr(0, depth + 1)?;
                self.close(t.column)?;
                Ok(x)
            }
            Tok::Ident(name) => self.name(name, t.column, depth),
            _ => {
                let found = t.text.to_string();
                let problem = match prev {
                    Some(after) => Problem::ExpectedOperand { after, found },
                    None => Problem::ExpectedExpression(found),
                };
                Err(err(t.column, problem))
            }
        }
    }

    /// Expects the `)` closing the `(` at `open`.
    fn close(&mut self, open: usize) -> Result<(), ParseError> {
        let t = self.next();
        match t.tok {
            Tok::Close => Ok(()),
            Tok::End => Err(err(open, Problem::Unclosed)),
            Tok::Comma => Err(err(t.column, Problem::StrayComma)),
            _ => Err(err(t.column, Problem::ExpectedOperator(t.text.to_string()))),
        }
    }

    fn name(&mut self, name: &str, column: usize, depth: usize) -> Result<Ast, ParseError> {
        let at = |node| Ast { node, column };
        if self.peek().tok == Tok::Open {
            let open = self.next().column;
            let Some(f) = function(name) else {
                let problem = if Var::from_name(name).is_some() {
                    Problem::VariableCalled(name.to_string())
                } else {
                    Problem::UnknownFunction(name.to_string())
                };
                return Err(err(column, problem));
            };
            let mut args = Vec::new();
            if self.peek().tok == Tok::Close {
                self.next();
            } else {
                loop {
                    args.push(self.expr(0, depth + 1)?);
                    if self.peek().tok == Tok::Comma {
                        self.next();
                    } else {
                        self.close(open)?;
                        break;
                    }
                }
            }
            if args.len() != f.arity() {
                return Err(err(
                    column,
                    Problem::Arity {
                        name: name.to_string(),
                        expected: f.arity(),
                        given: args.len(),
                    },
                ));
            }
            let arity = || Problem::Arity {
                name: name.to_string(),
                expected: f.arity(),
                given: 0,
            };
            let second = if f.arity() == 2 { args.pop() } else { None };
            let node = match (f, args.pop(), second) {
                (Callable::One(f), Some(a), None) => Node::Call(f, Box::new(a)),
                (Callable::Two(op), Some(a), Some(b)) => Node::Bin(op, Box::new(a), Box::new(b)),
                _ => return Err(err(column, arity())),
            };
            return Ok(at(node));
        }
        if function(name).is_some() {
            return Err(err(column, Problem::FunctionNotCalled(name.to_string())));
        }
        if let Some(v) = Var::from_name(name) {
            return Ok(at(Node::Var(v)));
        }
        if let Some(v) = near_variable(name) {
            return Err(err(
                column,
                Problem::NearVariable {
                    name: name.to_string(),
                    variable: v.name(),
                },
            ));
        }
        let index = match self.coeffs.iter().position(|c| c == name) {
            Some(i) => i,
            None if self.coeffs.len() == MAX_COEFFS => {
                return Err(err(column, Problem::TooManyCoefficients(name.to_string())))
            }
            None => {
                self.coeffs.push(name.to_string());
                self.coeffs.len() - 1
            }
        };
        Ok(at(Node::Coef(index)))
    }
}
