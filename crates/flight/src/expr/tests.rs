//! The language's tests: what parses to what, what is refused and how it is said, the
//! compiled program against a reference interpreter of the tree, the gradient against
//! central differences, and random input that must never panic.

use proptest::prelude::*;

use super::compile::{Instr, Leaf, STACK};
use super::parse::{parse, Ast, Node};
use super::*;

/// The tree, fully parenthesised, coefficients by name.
fn show(ast: &Ast, coeffs: &[String]) -> String {
    match &ast.node {
        Node::Num(x) => format!("{x}"),
        Node::Var(v) => v.name().to_string(),
        Node::Coef(i) => coeffs[*i].clone(),
        Node::Neg(x) => format!("(-{})", show(x, coeffs)),
        Node::Call(f, x) => format!("{}({})", f.name(), show(x, coeffs)),
        Node::Bin(op, a, b) => match op {
            ops::Bin::Min | ops::Bin::Max => {
                format!("{}({}, {})", op.name(), show(a, coeffs), show(b, coeffs))
            }
            _ => format!("({}{}{})", show(a, coeffs), op.name(), show(b, coeffs)),
        },
        Node::Chain(first, rest) => rest.iter().fold(show(first, coeffs), |acc, (op, _, x)| {
            format!("({acc}{}{})", op.name(), show(x, coeffs))
        }),
    }
}

fn tree(src: &str) -> String {
    let p = parse(src, 0).unwrap();
    show(&p.ast, &p.coeffs)
}

/// The reference: the tree evaluated directly, left to right, nothing folded or reordered.
fn reference(ast: &Ast, vars: &VarValues, coeffs: &[f64]) -> f64 {
    let r = |x: &Ast| reference(x, vars, coeffs);
    match &ast.node {
        Node::Num(x) => *x,
        Node::Var(v) => vars[v.index()],
        Node::Coef(i) => coeffs[*i],
        Node::Neg(x) => -r(x),
        Node::Call(f, x) => f.apply(r(x)),
        Node::Bin(op, a, b) => op.apply(r(a), r(b)),
        Node::Chain(first, rest) => rest
            .iter()
            .fold(r(first), |acc, (op, _, x)| op.apply(acc, r(x))),
    }
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn message(src: &str) -> String {
    Expr::parse(src).unwrap_err().to_string()
}

fn vars_with(pairs: &[(Var, f64)]) -> VarValues {
    let mut v = [0.0; N_VARS];
    for &(var, x) in pairs {
        v[var.index()] = x;
    }
    v
}

#[test]
fn the_table_is_in_index_order_and_names_are_distinct() {
    assert_eq!(VARIABLES.len(), N_VARS);
    for (i, row) in VARIABLES.iter().enumerate() {
        assert_eq!(row.var.index(), i);
        assert_eq!(Var::ALL[i], row.var);
        assert_eq!(Var::from_name(row.name), Some(row.var));
        assert!(
            ops::function(row.name).is_none(),
            "{} is also a function",
            row.name
        );
    }
    let mut names: Vec<_> = VARIABLES.iter().map(|r| r.name).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), N_VARS);
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(tree("-k^2"), "(-(k^2))");
    assert_eq!(tree("k^2^3"), "(k^(2^3))");
    assert_eq!(tree("2^-k"), "(2^(-k))");
    assert_eq!(tree("-k*alpha"), "((-k)*alpha)");
    assert_eq!(tree("k - alpha - beta"), "((k-alpha)-beta)");
    assert_eq!(tree("k / alpha / beta"), "((k/alpha)/beta)");
    assert_eq!(tree("k + alpha*beta - q"), "((k+(alpha*beta))-q)");
    assert_eq!(tree("k*(alpha+beta)"), "(k*(alpha+beta))");
    assert_eq!(tree("(k+alpha)+beta"), "((k+alpha)+beta)");
    assert_eq!(tree("k*alpha^2/beta"), "((k*(alpha^2))/beta)");
    assert_eq!(
        tree("min(k, alpha) + sin(-beta)"),
        "(min(k, alpha)+sin((-beta)))"
    );
    assert_eq!(tree("1.5e-3*k + .5E+1"), "((0.0015*k)+5)");
    assert_eq!(tree("  k\t*\nthrust "), "(k*thrust)");
}

#[test]
fn a_long_sum_is_a_flat_chain() {
    let src = vec!["k"; 2000].join("+");
    let p = parse(&src, 0).unwrap();
    match &p.ast.node {
        Node::Chain(_, rest) => assert_eq!(rest.len(), 1999),
        other => panic!("{other:?}"),
    }
    let e = Expr::parse(&src).unwrap();
    assert_eq!(e.eval(&[0.0; N_VARS], &[1.5]), 3000.0);
}

#[test]
fn names_resolve_to_variables_functions_or_coefficients() {
    let e =
        Expr::parse("c_thrust*thrust + k1*alpha + k_alpha*beta + c_thrust*k1 + alpha_0").unwrap();
    assert_eq!(e.coefficients(), ["c_thrust", "k1", "k_alpha", "alpha_0"]);
    assert_eq!(
        e.variables().collect::<Vec<_>>(),
        [Var::Alpha, Var::Beta, Var::Thrust]
    );
    assert!(e.uses(Var::Thrust) && !e.uses(Var::Qbar));
    // Short names are coefficients even next to one-letter variables.
    for name in [
        "k", "c", "a", "b", "k2", "kq", "cd", "theta", "gamma", "delta", "mass",
    ] {
        let e = Expr::parse(&format!("{name}*q")).unwrap();
        assert_eq!(e.coefficients(), [name], "{name}");
    }
}

#[test]
fn typos_of_variables_are_refused() {
    for (typo, var) in [
        ("trhust", "thrust"),
        ("thrst", "thrust"),
        ("alfa", "alpha"),
        ("Alpha", "alpha"),
        ("bta", "beta"),
        ("q_bar", "qbar"),
        ("phat", "p_hat"),
        ("airspeeed", "airspeed"),
        ("throtle", "throttle"),
        ("alpha2", "alpha"),
        ("P", "p"),
        ("ro", "rho"),
    ] {
        let e = Expr::parse(&format!("k*{typo}")).unwrap_err();
        assert_eq!(e.column, 3, "{typo}");
        match &e.problem {
            Problem::NearVariable { name, variable } => {
                assert_eq!((name.as_str(), *variable), (typo, var))
            }
            other => panic!("{typo}: {other:?}"),
        }
    }
}

#[test]
fn messages_name_the_column_and_the_problem() {
    let known = "variables: alpha, beta, p_hat, q_hat, r_hat, p, q, r, elevator, aileron, \
                 rudder, throttle, thrust, airspeed, qbar, rho, height, g";
    assert_eq!(
        message("k * trhust"),
        format!(
            "column 5: `trhust` is not a variable, and too close to one to be taken for a free \
             coefficient: did you mean `thrust`? ({known}; to name a coefficient after a \
             variable, join them with `_`, e.g. `k_thrust`)"
        )
    );
    assert_eq!(
        message("k * sinn(alpha)"),
        "column 5: unknown function `sinn`: did you mean `sin`? (functions: sin, cos, tan, \
         abs, sqrt, exp, ln, min, max, sign; a product is written with `*`)"
    );
    assert_eq!(message("k*"), "column 3: expected an expression after `*`");
    assert_eq!(
        message("k*)"),
        "column 3: expected an expression after `*`, found `)`"
    );
    assert_eq!(message(")"), "column 1: expected an expression, found `)`");
    assert_eq!(message("k*(alpha+1"), "column 3: this `(` is never closed");
    assert_eq!(message("k*alpha)"), "column 8: this `)` closes nothing");
    assert_eq!(
        message("k alpha"),
        "column 3: expected an operator before `alpha` (a product is written with `*`)"
    );
    assert_eq!(
        message("2k"),
        "column 2: expected an operator before `k` (a product is written with `*`)"
    );
    assert_eq!(
        message("k, alpha"),
        "column 2: `,` outside a function's arguments"
    );
    assert_eq!(message(""), "column 1: the expression is empty");
    assert_eq!(message("   "), "column 1: the expression is empty");
    assert_eq!(
        message("k*1.2.3"),
        "column 3: the number `1.2.3` does not parse"
    );
    assert_eq!(message("k*2e"), "column 3: the number `2e` does not parse");
    assert_eq!(
        message("k*1e999"),
        "column 3: the number `1e999` is not finite"
    );
    assert_eq!(
        message("k*α"),
        "column 3: unexpected character `α` (write `alpha`)"
    );
    assert_eq!(message("k*$"), "column 3: unexpected character `$`");
    assert_eq!(
        message("k*min(alpha)"),
        "column 3: `min` takes 2 arguments, given 1"
    );
    assert_eq!(
        message("k*sin(alpha, beta)"),
        "column 3: `sin` takes 1 argument, given 2"
    );
    assert_eq!(
        message("k*sin()"),
        "column 3: `sin` takes 1 argument, given 0"
    );
    assert_eq!(
        message("k*sin"),
        "column 3: `sin` is a function: write `sin(…)`"
    );
    assert_eq!(
        message("k*alpha(2)"),
        "column 3: `alpha` is a variable, not a function (a product is written with `*`)"
    );
    assert_eq!(
        message("0.5*thrust"),
        "column 1: the term has no free coefficient, so nothing to fit: write one, e.g. \
         `k * (…)` (every name that is neither a variable nor a function is a coefficient)"
    );
    assert_eq!(
        message("a+b+c+d+e+f+h+i+j"),
        "column 17: `j` is one coefficient too many: a term has at most 8"
    );
    assert_eq!(
        message("k*ln(0)"),
        "column 3: this constant part is -inf (ln of a non-positive number (ln(0)))"
    );
    assert_eq!(
        message("k + 1/(2-2)"),
        "column 6: this constant part is inf (division by zero (1 / 0))"
    );
    assert_eq!(
        message("k*exp(1000)"),
        "column 3: this constant part is inf (`exp` of 1000 gives inf)"
    );
    // Columns count characters, not bytes.
    assert_eq!(message("k*ρ*ρ").split(':').next(), Some("column 3"));
    assert_eq!(
        message("k·α"),
        "column 2: unexpected character `·` (write `*`)"
    );
}

#[test]
fn sizes_and_depths_are_bounded() {
    let deep = |n: usize| format!("{}k{}", "(".repeat(n), ")".repeat(n));
    assert!(Expr::parse(&deep(63)).is_ok());
    assert_eq!(
        Expr::parse(&deep(64)).unwrap_err().to_string(),
        "column 65: the expression is nested more than 64 levels deep"
    );
    assert_eq!(
        Expr::parse(&deep(2000)).unwrap_err().problem,
        Problem::TooDeep
    );
    assert_eq!(
        Expr::parse(&format!("{}k", "-".repeat(200)))
            .unwrap_err()
            .problem,
        Problem::TooDeep
    );
    assert_eq!(
        Expr::parse(&format!("{}k", "k^".repeat(2000)))
            .unwrap_err()
            .problem,
        Problem::TooDeep
    );
    assert_eq!(
        Expr::parse(&format!("{}k", "sin(".repeat(1000)))
            .unwrap_err()
            .problem,
        Problem::TooDeep
    );
    let long = "k".repeat(MAX_LEN + 1);
    assert_eq!(
        Expr::parse(&long).unwrap_err().to_string(),
        "column 4097: the expression is longer than 4096 characters"
    );
    assert!(Expr::parse(&"k".repeat(MAX_LEN)).is_ok(), "one long name");
}

/// A balanced tree of `2^levels` leaves: the program's stack stays logarithmic.
fn balanced(levels: u32, op: &str) -> String {
    if levels == 0 {
        "k".to_string()
    } else {
        let half = balanced(levels - 1, op);
        format!("({half}){op}({half})")
    }
}

#[test]
fn the_stack_stays_small() {
    for op in ["+", "-", "*", "/", "^"] {
        let src = balanced(9, op);
        assert!(src.len() <= MAX_LEN, "{}", src.len());
        let e = Expr::parse(&src).unwrap();
        assert!(e.code.depth() <= 10, "{op}: {}", e.code.depth());
        let p = parse(&src, 0).unwrap();
        let vars = [0.3; N_VARS];
        assert!(same(
            e.eval(&vars, &[1.1]),
            reference(&p.ast, &vars, &[1.1])
        ));
        let mut g = [0.0];
        let v = e.eval_with_gradient(&vars, &[1.1], &mut g);
        assert!(same(v, e.eval(&vars, &[1.1])));
        if op == "+" {
            assert_eq!(g[0], 512.0);
        }
    }
    // Deep on the right: evaluated right operand first.
    let src = format!("{}k{}", "alpha-(".repeat(30), ")".repeat(30));
    let e = Expr::parse(&src).unwrap();
    assert!(e.code.depth() <= 2, "{}", e.code.depth());
    let p = parse(&src, 0).unwrap();
    let vars = vars_with(&[(Var::Alpha, 0.7)]);
    assert!(same(
        e.eval(&vars, &[0.2]),
        reference(&p.ast, &vars, &[0.2])
    ));
}

#[test]
fn constants_fold_and_pushes_fuse() {
    use ops::Bin::{Pow, Sub};
    use Instr::*;
    let program = |src: &str| Expr::parse(src).unwrap().code.fast().to_vec();
    let thrust = Var::Thrust as u8;
    assert_eq!(program("k*thrust"), [Push(Leaf::Coef(0)), MulVar(thrust)]);
    assert_eq!(program("thrust*k"), [Push(Leaf::Var(thrust)), MulCoef(0)]);
    assert_eq!(
        program("k * (2*3 - sqrt(4)) ^ 2"),
        [Push(Leaf::Coef(0)), MulConst(16.0)]
    );
    assert_eq!(
        program("k*(alpha+beta)"),
        [Push(Leaf::Var(0)), AddVar(1), MulCoef(0)]
    );
    assert_eq!(
        program("k1*throttle^2"),
        [Push(Leaf::Var(Var::Throttle as u8)), Square, MulCoef(0)]
    );
    // The right operand first when it needs more of the stack; the order is kept in the
    // instruction.
    assert_eq!(
        program("k - alpha*beta"),
        [Push(Leaf::Var(0)), MulVar(1), LeafBin(Sub, Leaf::Coef(0))]
    );
    assert_eq!(
        program("2^(k*alpha) - k2"),
        [
            Push(Leaf::Coef(0)),
            MulVar(0),
            LeafBin(Pow, Leaf::Const(2.0)),
            BinLeaf(Sub, Leaf::Coef(1))
        ]
    );
}

#[test]
fn typical_terms_evaluate_with_their_gradient() {
    let vars = vars_with(&[
        (Var::Thrust, 20.0),
        (Var::Alpha, 0.1),
        (Var::Beta, -0.05),
        (Var::Qbar, 400.0),
        (Var::Throttle, 0.6),
        (Var::R, 0.2),
    ]);
    let mut g = [0.0; 2];
    let e = Expr::parse("k*thrust").unwrap();
    assert_eq!(e.eval(&vars, &[0.1]), 2.0);
    assert_eq!(e.eval_with_gradient(&vars, &[0.1], &mut g), 2.0);
    assert_eq!(g[0], 20.0);
    let e = Expr::parse("k*alpha*beta*qbar").unwrap();
    assert_eq!(e.eval(&vars, &[2.0]), 2.0 * 0.1 * -0.05 * 400.0);
    let e = Expr::parse("k1*throttle^2 + k2*r*throttle").unwrap();
    let v = e.eval_with_gradient(&vars, &[3.0, -1.0], &mut g);
    assert_eq!(v, 3.0 * 0.36 - 0.2 * 0.6);
    assert_eq!(g, [0.36, 0.2 * 0.6]);
    // The exponent a coefficient: d/dk 2^k = 2^k ln 2.
    let e = Expr::parse("2^k").unwrap();
    let mut g1 = [0.0];
    let v = e.eval_with_gradient(&vars, &[3.0], &mut g1);
    assert_eq!(v, 8.0);
    assert!((g1[0] - 8.0 * 2f64.ln()).abs() < 1e-12);
    // A derivative that does not flow is 0, even beside an infinite one.
    let e = Expr::parse("k + sqrt(alpha)").unwrap();
    let v = e.eval_with_gradient(&vars_with(&[]), &[1.0], &mut g1);
    assert_eq!((v, g1[0]), (1.0, 1.0));
}

#[test]
fn terms_read_axis_and_expression() {
    let t = Term::parse("m = k*thrust").unwrap();
    assert_eq!((t.axis, t.expr.source()), (Axis::M, "k*thrust"));
    assert_eq!(t.to_string(), "m = k*thrust");
    for (s, axis) in [
        ("X=k", Axis::X),
        ("x =k", Axis::X),
        (" L= k", Axis::L),
        ("n=k", Axis::N),
    ] {
        assert_eq!(Term::parse(s).unwrap().axis, axis, "{s}");
    }
    assert_eq!(Term::new("Z", "k*qbar").unwrap().axis, Axis::Z);
    assert!(Axis::M.unit() == "N·m" && Axis::Y.unit() == "N" && Axis::N.component() == 2);
    // Columns count in the text as given.
    assert_eq!(
        Term::parse("m = k*trhust")
            .unwrap_err()
            .to_string()
            .split(':')
            .next(),
        Some("column 7")
    );
    assert_eq!(
        Term::parse("m=").unwrap_err().to_string(),
        "column 3: the expression is empty"
    );
    assert_eq!(
        Term::parse("k*thrust").unwrap_err().to_string(),
        "column 1: expected `AXIS = EXPRESSION`, e.g. `m = k*thrust`"
    );
    assert_eq!(
        Term::parse(" q = k").unwrap_err().to_string(),
        "column 2: unknown axis `q`: a term acts along X, Y or Z (body force, N) or about l, m \
         or n (body moment, N·m)"
    );
    assert_eq!(Term::new("m", "k*").unwrap_err().column, 3);
}

#[test]
fn checked_evaluation_names_the_operation() {
    let coeffs = [1.0];
    let check = |src: &str, vars: &VarValues, coeffs: &[f64]| {
        Term::parse(src).unwrap().expr.eval_checked(vars, coeffs)
    };
    let v = vars_with(&[(Var::Alpha, -0.2), (Var::Thrust, 0.0)]);
    assert_eq!(
        check("m = k*ln(alpha)", &v, &coeffs)
            .unwrap_err()
            .to_string(),
        "column 7: ln of a non-positive number (ln(-0.2))"
    );
    assert_eq!(
        check("m = k/thrust", &v, &coeffs).unwrap_err().to_string(),
        "column 6: division by zero (1 / 0)"
    );
    assert_eq!(
        check("m = k*sqrt(alpha)", &v, &coeffs)
            .unwrap_err()
            .to_string(),
        "column 7: sqrt of a negative number (sqrt(-0.2))"
    );
    assert_eq!(
        check("m = alpha^k", &v, &[0.5]).unwrap_err().to_string(),
        "column 10: `^` undefined for -0.2 ^ 0.5"
    );
    assert_eq!(
        check("m = exp(k)", &v, &[1000.0]).unwrap_err().to_string(),
        "column 5: `exp` of 1000 gives inf"
    );
    assert_eq!(
        check(
            "m = k*qbar*qbar",
            &vars_with(&[(Var::Qbar, 1e200)]),
            &coeffs
        )
        .unwrap_err()
        .to_string(),
        "column 11: `*` of 1e200 and 1e200 gives inf"
    );
    let mut nan = vars_with(&[]);
    nan[Var::Height.index()] = f64::NAN;
    assert_eq!(
        check("m = k*height", &nan, &coeffs)
            .unwrap_err()
            .to_string(),
        "column 7: variable `height` is NaN"
    );
    assert_eq!(
        check("m = c_x*alpha", &v, &[f64::INFINITY])
            .unwrap_err()
            .to_string(),
        "column 5: coefficient `c_x` is inf"
    );
    // Unused variables are not looked at; a finite value is the fast path's.
    assert_eq!(check("m = k*alpha", &nan, &[2.0]), Ok(0.0));
    let e = Expr::parse("k*ln(alpha)").unwrap();
    assert!(e.eval(&v, &coeffs).is_nan());
}

/// A random expression over every construct, most often with a coefficient.
fn expression() -> impl Strategy<Value = String> {
    let names: Vec<&'static str> = VARIABLES.iter().map(|r| r.name).collect();
    let leaf = prop_oneof![
        (0.0f64..20.0).prop_map(|x| format!("{x}")),
        prop::sample::select(vec!["0", "1", "2", "0.5", "1e-3", "3.5e2"]).prop_map(String::from),
        prop::sample::select(names).prop_map(String::from),
        prop::sample::select(vec!["k", "k1", "k2", "c_thrust", "a0", "b"]).prop_map(String::from),
    ];
    leaf.prop_recursive(6, 40, 3, |inner| {
        let op = prop::sample::select(vec!["+", "-", "*", "/", "^"]);
        let f = prop::sample::select(vec![
            "sin", "cos", "tan", "abs", "sqrt", "exp", "ln", "sign",
        ]);
        prop_oneof![
            (inner.clone(), op.clone(), inner.clone()).prop_map(|(a, o, b)| format!("{a} {o} {b}")),
            (inner.clone(), op, inner.clone()).prop_map(|(a, o, b)| format!("({a}){o}({b})")),
            inner.clone().prop_map(|a| format!("-{a}")),
            (f, inner.clone()).prop_map(|(f, a)| format!("{f}({a})")),
            (prop::bool::ANY, inner.clone(), inner)
                .prop_map(|(m, a, b)| format!("{}({a}, {b})", if m { "min" } else { "max" })),
        ]
    })
}

const TOKENS: &[&str] = &[
    "k", "k1", "alpha", "thrust", "trhust", "qbar", "p_hat", "g", "sin", "sinn", "min", "max", "(",
    ")", ",", "+", "-", "*", "/", "^", "2", "0", "1.5e-3", "1e999", ".", "e", "1.2.3", "α", "=",
    " ", "m", "m=", "\t", "_", "9e", "(((", ")))", "---", "^^",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_text_never_panics(s in "\\PC{0,120}") {
        let _ = Expr::parse(&s);
        let _ = Term::parse(&s);
        let _ = Term::parse(&format!("m={s}"));
    }

    #[test]
    fn token_soup_never_panics(
        toks in prop::collection::vec(prop::sample::select(TOKENS), 0..40),
        x in prop::collection::vec(-3.0f64..3.0, N_VARS + MAX_COEFFS),
    ) {
        let s: String = toks.concat();
        let _ = Term::parse(&s);
        if let Ok(e) = Expr::parse(&s) {
            let vars: VarValues = x[..N_VARS].try_into().unwrap();
            let coeffs = &x[N_VARS..];
            let v = e.eval(&vars, coeffs);
            let mut g = [0.0; MAX_COEFFS];
            prop_assert!(same(v, e.eval_with_gradient(&vars, coeffs, &mut g)));
            match e.eval_checked(&vars, coeffs) {
                Ok(c) => prop_assert!(same(c, v)),
                Err(_) => prop_assert!(!v.is_finite()),
            }
        }
    }

    #[test]
    fn the_program_matches_the_reference_and_the_gradient_differences(
        body in expression(),
        wrap in 0..3u8,
        x in prop::collection::vec(-2.0f64..2.0, N_VARS + MAX_COEFFS),
    ) {
        let src = match wrap {
            0 => body,
            1 => format!("k*({body})"),
            _ => format!("{body} + c0*alpha"),
        };
        let parsed = match parse(&src, 0) {
            Ok(p) => p,
            Err(e) => {
                prop_assert_eq!(e.problem, Problem::NoCoefficient, "{}", src);
                return Ok(());
            }
        };
        let e = match Expr::parse(&src) {
            Ok(e) => e,
            Err(err) => {
                // Only a constant part may still be refused.
                prop_assert!(matches!(err.problem, Problem::NonFiniteConstant { .. }), "{}: {}", src, err);
                return Ok(());
            }
        };
        prop_assert!(e.code.depth() <= STACK);
        let vars: VarValues = x[..N_VARS].try_into().unwrap();
        let coeffs = &x[N_VARS..N_VARS + e.coefficients().len()];
        let v = e.eval(&vars, coeffs);
        let r = reference(&parsed.ast, &vars, coeffs);
        prop_assert!(same(v, r), "{}: program {} reference {}", src, v, r);
        let asked = e.eval_from(|var| vars[var.index()], coeffs);
        prop_assert!(same(v, asked), "{}: program {} asking {}", src, v, asked);
        let mut g = [0.0; MAX_COEFFS];
        prop_assert!(same(v, e.eval_with_gradient(&vars, coeffs, &mut g)));
        match e.eval_checked(&vars, coeffs) {
            Ok(c) => prop_assert!(same(c, v)),
            Err(err) => prop_assert!(!v.is_finite(), "{}: {} but {}", src, err, v),
        }
        if !v.is_finite() {
            return Ok(());
        }
        for j in 0..coeffs.len() {
            let at = |c: f64| {
                let mut cs = coeffs.to_vec();
                cs[j] = c;
                e.eval(&vars, &cs)
            };
            let h = 1e-6 * coeffs[j].abs().max(1.0);
            let fd = |h: f64| (at(coeffs[j] + h) - at(coeffs[j] - h)) / (2.0 * h);
            let (d1, d2) = (fd(h), fd(2.0 * h));
            if !d1.is_finite() || !d2.is_finite() || !g[j].is_finite() {
                continue;
            }
            let scale = 1f64.max(d1.abs()).max(d2.abs());
            // Only where the function is smooth at this scale (no kink, no pole nearby) and
            // the differences are not lost in the value's rounding.
            let rounding = f64::EPSILON * v.abs() / h;
            if (d1 - d2).abs() > 1e-4 * scale || rounding > 1e-5 * scale {
                continue;
            }
            // A step absorbed by rounding inside (k + 7e14): the value does not move at all,
            // so the differences say nothing of the derivative.
            if at(coeffs[j] + 2.0 * h) == at(coeffs[j] - 2.0 * h) {
                continue;
            }
            prop_assert!((g[j] - d1).abs() <= 1e-3 * scale, "{}: d/d{} = {} but differences give {}", src, e.coefficients()[j], g[j], d1);
        }
    }
}

/// The products most terms are (a value times variables, coefficients, numbers and squares)
/// are walked without the table of variables and ask only for the variables they read; the
/// value is the program's, bit for bit, as is any other expression's.
#[test]
fn products_ask_only_for_their_variables_and_give_the_programs_value() {
    let vars = vars_with(&[
        (Var::Qbar, 381.7),
        (Var::Alpha, 0.0731),
        (Var::Beta, -0.0413),
        (Var::Throttle, 0.613),
        (Var::Thrust, 29.3),
    ]);
    for src in [
        "k*thrust",
        "k*qbar*alpha*beta",
        "k*throttle^2",
        "0.5*k*alpha*k2",
        "k",
        "k*sin(alpha)",
        "k*thrust + c*alpha",
    ] {
        let e = Expr::parse(src).unwrap();
        let coeffs = [0.0123, -4.56];
        let asked = std::cell::RefCell::new(Vec::new());
        let v = e.eval_from(
            |var| {
                asked.borrow_mut().push(var);
                vars[var.index()]
            },
            &coeffs,
        );
        assert!(same(v, e.eval(&vars, &coeffs)), "{src}");
        let mut asked = asked.into_inner();
        asked.sort();
        asked.dedup();
        assert_eq!(asked, e.variables().collect::<Vec<_>>(), "{src}");
    }
    assert!(Expr::parse("k*thrust").unwrap().code.is_product());
    assert!(Expr::parse("k*throttle^2").unwrap().code.is_product());
    assert!(!Expr::parse("k*sin(alpha)").unwrap().code.is_product());
    assert!(!Expr::parse("k*thrust + c").unwrap().code.is_product());
}

#[test]
fn the_documented_examples_read() {
    for term in [
        "X = k*thrust",
        "m = k*thrust",
        "m = k*qbar*alpha*beta",
        "n = k1*throttle^2 + k2*r*throttle",
        "Z = k*qbar*max(0, 1 - height/10)",
        "l = k*qbar*sin(2*beta)",
        "m = c_m_ab * qbar * 0.55 * 0.19 * alpha * beta",
        "m = k * 2E+4 * .5 * -alpha^2",
    ] {
        assert!(Term::parse(term).is_ok(), "{term}");
    }
    for name in ["G", "ro", "eta", "zeta", "q_bar", "phat", "throtle"] {
        assert!(Expr::parse(&format!("k*{name}")).is_err(), "{name}");
    }
    for name in ["thrust_k", "c_alpha", "theta", "gamma", "delta", "mass"] {
        assert!(Expr::parse(&format!("k*{name}")).is_ok(), "{name}");
    }
    let e = Expr::parse("max(0, -1/thrust) + k").unwrap();
    assert_eq!(e.eval_checked(&[0.0; N_VARS], &[0.5]), Ok(0.5));
}
