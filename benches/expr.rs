//! Force and moment terms written as formulas (`flight::expr`): nanoseconds per evaluation of
//! typical terms, the value alone, with the gradient in the coefficients, and checked; the
//! same formulas written in Rust as the floor; and the one-off cost of reading a term.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};

use wireflight::flight::expr::{Expr, Var, VarValues, N_VARS};

const TERMS: [&str; 4] = [
    "k*thrust",
    "k*alpha*beta*qbar",
    "k1*throttle^2 + k2*r*throttle",
    "k1*qbar*sin(alpha) + k2*p_hat + k3*max(0, 1 - height/10)",
];

fn vars() -> VarValues {
    let mut v = [0.0; N_VARS];
    for (var, x) in [
        (Var::Alpha, 0.08),
        (Var::Beta, -0.02),
        (Var::PHat, 0.01),
        (Var::R, 0.05),
        (Var::Throttle, 0.6),
        (Var::Thrust, 25.0),
        (Var::Qbar, 380.0),
        (Var::Height, 4.0),
    ] {
        v[var.index()] = x;
    }
    v
}

/// The terms in Rust, as the compiler would have them.
fn native(i: usize, v: &VarValues, c: &[f64]) -> f64 {
    match i {
        0 => c[0] * v[Var::Thrust.index()],
        1 => c[0] * v[Var::Alpha.index()] * v[Var::Beta.index()] * v[Var::Qbar.index()],
        2 => {
            let t = v[Var::Throttle.index()];
            c[0] * t * t + c[1] * v[Var::R.index()] * t
        }
        _ => {
            c[0] * v[Var::Qbar.index()] * v[Var::Alpha.index()].sin()
                + c[1] * v[Var::PHat.index()]
                + c[2] * (1.0 - v[Var::Height.index()] / 10.0).max(0.0)
        }
    }
}

fn evaluation(c: &mut Criterion) {
    let mut group = c.benchmark_group("expr");
    group.sample_size(30);
    group.warm_up_time(std::time::Duration::from_millis(500));
    group.measurement_time(std::time::Duration::from_secs(2));
    let vars = vars();
    let coeffs = [0.3, -0.2, 0.1];
    for (i, src) in TERMS.into_iter().enumerate() {
        let e = Expr::parse(src).unwrap();
        let n = e.coefficients().len();
        group.bench_function(format!("{src}: eval"), |b| {
            b.iter(|| e.eval(black_box(&vars), black_box(&coeffs[..n])))
        });
        let mut grad = [0.0; 3];
        group.bench_function(format!("{src}: eval_with_gradient"), |b| {
            b.iter(|| {
                let v = e.eval_with_gradient(black_box(&vars), black_box(&coeffs[..n]), &mut grad);
                black_box(&grad);
                v
            })
        });
        group.bench_function(format!("{src}: eval_checked"), |b| {
            b.iter(|| e.eval_checked(black_box(&vars), black_box(&coeffs[..n])))
        });
        group.bench_function(format!("{src}: written in Rust"), |b| {
            b.iter(|| native(i, black_box(&vars), black_box(&coeffs[..n])))
        });
        group.bench_function(format!("{src}: parse and compile"), |b| {
            b.iter(|| Expr::parse(black_box(src)))
        });
    }
    group.finish();
}

criterion_group!(benches, evaluation);
criterion_main!(benches);
