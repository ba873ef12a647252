//! `wireflight euler` end to end: the JSON answer checked against an independent computation
//! (plain arrays, no glam, no library code), `--to` conversions, `--from-matrix` and
//! `--from-quat`, negative numbers, and bad input (exit status 2, the option named, no panic).

use serde_json::Value;

use crate::support::cli::{stderr, stdout, wireflight};

/// Run `wireflight euler ARGS --json` and parse the answer.
fn euler_json(args: &[&str]) -> Value {
    let mut all = vec!["euler"];
    all.extend_from_slice(args);
    all.push("--json");
    let o = wireflight(&all);
    assert!(o.status.success(), "{all:?}: {}", stderr(&o));
    serde_json::from_str(&stdout(&o)).unwrap_or_else(|e| panic!("{e}: {}", stdout(&o)))
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(numbers).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("not numbers: {other}"),
    }
}

fn matrix_of(v: &Value) -> M {
    let rows = v["matrix"].as_array().expect("matrix rows");
    assert_eq!(rows.len(), 3);
    let mut m = [[0.0; 3]; 3];
    for (i, row) in rows.iter().enumerate() {
        let r = numbers(row);
        assert_eq!(r.len(), 3, "{row}");
        m[i].copy_from_slice(&r);
    }
    m
}

fn assert_near(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{what}: {a:?} vs {b:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// An independent computation: row-major 3×3 arrays, written from the definitions.
// ---------------------------------------------------------------------------------------------

type M = [[f64; 3]; 3];

/// The active rotation about axis `x`, `y` or `z` by `deg` degrees (right-hand rule).
fn elementary(axis: char, deg: f64) -> M {
    let (s, c) = deg.to_radians().sin_cos();
    match axis {
        'x' => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        'y' => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        'z' => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        _ => panic!("{axis}"),
    }
}

fn mul(a: M, b: M) -> M {
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

/// Intrinsic a-b-c: `R_a(α)·R_b(β)·R_c(γ)`; extrinsic: `R_c(γ)·R_b(β)·R_a(α)`.
fn rotation(seq: &str, extrinsic: bool, deg: [f64; 3]) -> M {
    let axes: Vec<char> = seq.chars().collect();
    let r: Vec<M> = (0..3).map(|k| elementary(axes[k], deg[k])).collect();
    if extrinsic {
        mul(mul(r[2], r[1]), r[0])
    } else {
        mul(mul(r[0], r[1]), r[2])
    }
}

fn flat(m: M) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

/// The quaternion [w, x, y, z] of a rotation matrix (Shepperd's method), with w ≥ 0.
fn quaternion(m: M) -> [f64; 4] {
    let t = m[0][0] + m[1][1] + m[2][2];
    let q = if t > 0.0 {
        let s = 2.0 * (1.0 + t).sqrt();
        [
            s / 4.0,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = 2.0 * (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt();
        [
            (m[2][1] - m[1][2]) / s,
            s / 4.0,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = 2.0 * (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt();
        [
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            s / 4.0,
            (m[1][2] + m[2][1]) / s,
        ]
    } else {
        let s = 2.0 * (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt();
        [
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            s / 4.0,
        ]
    };
    if q[0] < 0.0 {
        q.map(|x| -x)
    } else {
        q
    }
}

// ---------------------------------------------------------------------------------------------
// The JSON answer
// ---------------------------------------------------------------------------------------------

/// The example: every field of the specified JSON, values from the definitions.
#[test]
fn json_has_the_specified_fields_with_independent_values() {
    let v = euler_json(&["--seq", "zyx", "--angles", "30,20,10"]);
    let expected = rotation("zyx", false, [30.0, 20.0, 10.0]);
    assert_near(&flat(matrix_of(&v)), &flat(expected), 1e-15, "matrix");
    // Spot values: r20 = −sin θ, r00 = cos ψ cos θ.
    assert!((v["matrix"][2][0].as_f64().unwrap() + 20f64.to_radians().sin()).abs() < 1e-15);
    let q = numbers(&v["quaternion"]);
    assert_near(&q, &quaternion(expected), 1e-15, "quaternion");
    assert!(q[0] >= 0.0);
    assert_eq!(numbers(&v["angles_deg"]), [30.0, 20.0, 10.0]);
    assert_eq!(v["gimbal_lock"], Value::Bool(false));
    assert_eq!(v["convention"], "zyx");
    assert_eq!(v["frame"], "intrinsic");
}

/// All 24 conventions, negative angles, degrees and radians: the matrix and quaternion are the
/// definitions'.
#[test]
fn every_convention_matches_the_definition() {
    let seqs = [
        "zxz", "xyx", "yzy", "zyz", "xzx", "yxy", "xyz", "yzx", "zxy", "xzy", "zyx", "yxz",
    ];
    let deg = [-35.0, 25.0, 140.0];
    for seq in seqs {
        for extrinsic in [false, true] {
            let mut args = vec!["--seq", seq, "--angles", "-35,25,140"];
            if extrinsic {
                args.push("--extrinsic");
            }
            let v = euler_json(&args);
            let expected = rotation(seq, extrinsic, deg);
            let what = format!("{seq} extrinsic={extrinsic}");
            assert_near(&flat(matrix_of(&v)), &flat(expected), 1e-15, &what);
            assert_near(
                &numbers(&v["quaternion"]),
                &quaternion(expected),
                1e-14,
                &what,
            );
            let frame = if extrinsic { "extrinsic" } else { "intrinsic" };
            assert_eq!(v["frame"], frame, "{what}");
        }
    }
    // Radians: the same rotation.
    let rad = deg.map(f64::to_radians).map(|x| x.to_string()).join(",");
    let v = euler_json(&["--seq", "zxz", "--angles", &rad, "--radians"]);
    assert_near(
        &flat(matrix_of(&v)),
        &flat(rotation("zxz", false, deg)),
        1e-15,
        "radians",
    );
    assert_near(&numbers(&v["angles_deg"]), &deg, 1e-12, "radians → degrees");
}

/// Gimbal lock reported for the middle angle at ±90° (Tait–Bryan) and 0°/180° (proper Euler).
#[test]
fn json_reports_gimbal_lock() {
    for (seq, angles, locked) in [
        ("zyx", "10,90,20", true),
        ("zyx", "10,-90,20", true),
        ("zyx", "10,89,20", false),
        ("zyz", "10,0,20", true),
        ("zyz", "10,180,20", true),
        ("zyz", "10,90,20", false),
    ] {
        let v = euler_json(&["--seq", seq, "--angles", angles]);
        assert_eq!(v["gimbal_lock"], Value::Bool(locked), "{seq} {angles}");
    }
}

// ---------------------------------------------------------------------------------------------
// Conversions
// ---------------------------------------------------------------------------------------------

/// `--to SEQ`: intrinsic z-y-x (ψ, θ, φ) is extrinsic x-y-z (φ, θ, ψ); any target gives angles
/// whose rotation (by the definition) is the input's.
#[test]
fn to_another_convention_keeps_the_rotation() {
    let v = euler_json(&[
        "--seq",
        "zyx",
        "--angles",
        "30,20,10",
        "--to",
        "xyz,extrinsic",
    ]);
    assert_near(
        &numbers(&v["angles_deg"]),
        &[10.0, 20.0, 30.0],
        1e-12,
        "xyz,extrinsic",
    );
    assert_eq!(v["convention"], "xyz,extrinsic");
    assert_eq!(v["input"]["convention"], "zyx");
    let given = rotation("zyx", false, [30.0, 20.0, 10.0]);
    for to in ["zxz", "yxy,extrinsic", "x-z-y", "YZX,extrinsic"] {
        let v = euler_json(&["--seq", "zyx", "--angles", "30,20,10", "--to", to]);
        let a = numbers(&v["angles_deg"]);
        let conv = v["convention"].as_str().unwrap().to_string();
        let (seq, extrinsic) = match conv.split_once(',') {
            Some((s, _)) => (s.to_string(), true),
            None => (conv.clone(), false),
        };
        let back = rotation(&seq, extrinsic, [a[0], a[1], a[2]]);
        assert_near(&flat(back), &flat(given), 1e-12, to);
        // Principal ranges: proper Euler β ∈ [0°, 180°], Tait–Bryan β ∈ [−90°, 90°].
        let proper = seq.as_bytes()[0] == seq.as_bytes()[2];
        let beta_ok = if proper {
            (0.0..=180.0).contains(&a[1])
        } else {
            (-90.0..=90.0).contains(&a[1])
        };
        assert!(beta_ok, "{to}: {a:?}");
    }
}

/// `--to matrix` and `--to quat` print just the numbers.
#[test]
fn to_matrix_and_to_quat_print_the_numbers() {
    let o = wireflight(&["euler", "--angles", "-90,0,0", "--to", "matrix"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let m: Vec<f64> = stdout(&o)
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    assert_near(&m, &flat(elementary('z', -90.0)), 1e-6, "matrix");
    let o = wireflight(&[
        "euler", "--seq", "x-y-z", "--angles", "0,0,-90", "--to", "quat",
    ]);
    let q: Vec<f64> = stdout(&o)
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    let h = 0.5f64.sqrt();
    assert_near(&q, &[h, 0.0, 0.0, -h], 1e-6, "quaternion");
}

/// `--from-matrix` (row by row) and `--from-quat` back to angles, principal solution; a
/// non-unit quaternion is normalised; the answer's matrix is the input's.
#[test]
fn from_matrix_and_from_quat() {
    let r = rotation("zyx", false, [-120.0, 35.0, 75.0]);
    let text = flat(r)
        .iter()
        .map(|x| format!("{x:.12}"))
        .collect::<Vec<_>>()
        .join(",");
    let v = euler_json(&["--seq", "zyx", "--from-matrix", &text]);
    assert_near(
        &numbers(&v["angles_deg"]),
        &[-120.0, 35.0, 75.0],
        1e-8,
        "angles",
    );
    assert_near(&flat(matrix_of(&v)), &flat(r), 1e-11, "matrix");
    assert_near(&numbers(&v["input"]["matrix"]), &flat(r), 1e-11, "input");

    // Yaw 45° as a quaternion, scaled by −3: zyz at lock (β = 0), the turn in α.
    let h = (22.5f64).to_radians();
    let q = format!("{},0,0,{}", -3.0 * h.cos(), -3.0 * h.sin());
    let v = euler_json(&["--seq", "zyz", "--from-quat", &q]);
    assert_near(&numbers(&v["angles_deg"]), &[45.0, 0.0, 0.0], 1e-12, "zyz");
    assert_eq!(v["gimbal_lock"], Value::Bool(true));
    assert_near(
        &numbers(&v["quaternion"]),
        &[h.cos(), 0.0, 0.0, h.sin()],
        1e-15,
        "unit",
    );
    // The same quaternion into extrinsic x-y-z.
    let v = euler_json(&["--seq", "xyz", "--extrinsic", "--from-quat", &q]);
    assert_near(
        &numbers(&v["angles_deg"]),
        &[0.0, 0.0, 45.0],
        1e-12,
        "xyz,extrinsic",
    );
}

/// Values typed with four decimals are a rotation to about 1e-4: accepted.
#[test]
fn a_rounded_matrix_is_accepted() {
    let v = euler_json(&[
        "--from-matrix",
        "0.8138,-0.4410,0.3785,0.4698,0.8826,0.0180,-0.3420,0.1632,0.9254",
    ]);
    assert_near(
        &numbers(&v["angles_deg"]),
        &[30.0, 20.0, 10.0],
        0.02,
        "rounded",
    );
}

// ---------------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------------

/// Each bad request fails with status 2 and a message naming the option and the problem,
/// before anything is printed on stdout, and never with a panic.
#[test]
fn bad_input_fails_cleanly() {
    let cases: &[(&[&str], &str)] = &[
        (&["--angles", "1,2"], "expected 3"),
        (&["--angles", "1,2,3,4"], "expected 3"),
        (&["--angles", "1,nan,3"], "not a finite number"),
        (&["--angles", "1,inf,3"], "not a finite number"),
        (&["--angles", "a,b,c"], "not a number"),
        (&["--from-matrix", "1,0,0,0,1,0,0,0,2"], "not orthonormal"),
        (&["--from-matrix", "1,0,0,0,1,0,0,0,-1"], "reflection"),
        (&["--from-matrix", "1,0,0"], "expected 9"),
        (&["--from-quat", "0,0,0,0"], "non-zero quaternion"),
        (&["--from-quat", "0,-0,0,0"], "non-zero quaternion"),
        (&["--from-quat", "1,0,0"], "expected 4"),
        (&["--from-quat", "NaN,0,0,1"], "not a finite number"),
        (
            &["--seq", "zzx", "--angles", "1,2,3"],
            "not a rotation sequence",
        ),
        (
            &["--to", "sideways", "--angles", "1,2,3"],
            "not a rotation sequence",
        ),
        (&["--to", "zyx,upside", "--angles", "1,2,3"], "not a frame"),
        (
            &["--angles", "1,2,3", "--from-quat", "1,0,0,0"],
            "cannot be used with",
        ),
        (
            &["--angles", "1,2,3", "--degrees", "--radians"],
            "cannot be used with",
        ),
        (&[], "give the rotation"),
        (&["--steps", "--out", "x"], "give the rotation"),
        (&["--steps"], "--out"),
        (
            &["--gimbal-lock", "--angles", "10,20,30", "--out", "x"],
            "not at gimbal lock",
        ),
        (&["--interpolate", "--out", "x"], "--from-angles"),
        (
            &[
                "--interpolate",
                "--from-angles",
                "0,0,0",
                "--to-angles",
                "1,2,3",
                "--frames",
                "1",
                "--out",
                "x",
            ],
            "--frames",
        ),
        (
            &[
                "--steps", "--angles", "1,2,3", "--out", "x", "--size", "10000x10",
            ],
            "--size",
        ),
        (
            &["--steps", "--angles", "1,2,3", "--out", "x", "--to", "quat"],
            "cannot be used with",
        ),
    ];
    for (args, expected) in cases {
        let mut all = vec!["euler"];
        all.extend_from_slice(args);
        let o = wireflight(&all);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{all:?}: {err}");
        assert!(err.contains(expected), "{all:?}: {err}");
        assert!(!err.contains("panicked"), "{all:?}: {err}");
        assert!(stdout(&o).is_empty(), "{all:?}: {}", stdout(&o));
    }
    // The option is named in the value errors.
    let o = wireflight(&["euler", "--angles", "1,2"]);
    assert!(stderr(&o).contains("--angles"), "{}", stderr(&o));
    let o = wireflight(&["euler", "--from-quat", "0,0,0,0"]);
    assert!(stderr(&o).contains("--from-quat"), "{}", stderr(&o));
}

/// Negative numbers as values: `--angles -30,-20,-10` is a value, not an option.
#[test]
fn negative_angles_are_values() {
    let v = euler_json(&["--angles", "-30,-20,-10"]);
    assert_eq!(numbers(&v["angles_deg"]), [-30.0, -20.0, -10.0]);
    let v = euler_json(&["--from-quat", "-1,0,0,0"]);
    assert_eq!(numbers(&v["quaternion"]), [1.0, 0.0, 0.0, 0.0]);
    // Any scale is one rotation, even where |q|² under- or overflows: yaw 90°.
    for q in ["1e-200,0,0,1e-200", "1e300,0,0,1e300"] {
        let v = euler_json(&["--from-quat", q]);
        assert_near(&numbers(&v["angles_deg"]), &[90.0, 0.0, 0.0], 1e-12, q);
    }
}
