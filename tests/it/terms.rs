//! Terms as effects: a force or moment written as a formula (`--add 'term:m=k*thrust'`, a
//! model file's `[[term]]`), flown in a hidden truth, found by the diagnosis with its
//! coefficient, refused with the column and the problem when it does not read, and stopping a
//! flight with the time and the values when it cannot be evaluated.

use std::path::Path;
use std::sync::Arc;

use wireflight::data;
use wireflight::flight::effects::term::term_of;
use wireflight::flight::effects::Origin;
use wireflight::flight::spec::ModelSpec;

use crate::support::cli::{ok, stderr, stdout, wireflight};
use crate::support::flights::Flight;

/// The hidden truth: a pitching moment of 0.05 N·m per newton of thrust.
const TRUE_K: f64 = 0.05;

/// A noisy climbing turn of the Aerosonde with the pitching term hidden in its truth.
fn flight_with_hidden_term(dir: &Path) -> std::path::PathBuf {
    Flight::new()
        .manoeuvre("climbing-turn")
        .duration(40)
        .hidden(&format!("term(m=k*thrust):k={TRUE_K}"))
        .noise_pos(0.3)
        .noise_att(0.2)
        .seed(3)
        .write(dir, "a.csv")
}

/// The coefficient `k` of the term `m = k*thrust` in a model file.
fn fitted_k(model_file: &Path) -> f64 {
    let spec = ModelSpec::load(model_file).expect("the written model reads back");
    let term = spec
        .effects
        .iter()
        .find(|e| e.name == "term(m=k*thrust)")
        .unwrap_or_else(|| panic!("no term in {spec:?}"));
    term.params
        .iter()
        .find(|(k, _)| k == "k")
        .map(|(_, v)| *v)
        .expect("k is written")
}

#[test]
fn a_hidden_term_added_on_the_command_line_is_fitted_and_the_error_falls_to_the_noise() {
    let dir = tempfile::tempdir().unwrap();
    let flight = flight_with_hidden_term(dir.path());
    let out = dir.path().join("m.toml");
    let text = ok(&[
        "diagnose",
        "--flight",
        flight.to_str().unwrap(),
        "--add",
        "term:m=k*thrust",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        text.contains("model fixed-wing + term(m=k*thrust)"),
        "{text}"
    );
    assert!(text.contains("at the noise floor"), "{text}");
    let k = fitted_k(&out);
    assert!((k - TRUE_K).abs() < 0.03 * TRUE_K, "k = {k}");
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(
        written.contains("[[term]]\naxis = \"m\"\nexpr = \"k*thrust\""),
        "{written}"
    );
}

#[test]
fn a_term_declared_in_a_model_file_is_a_candidate_found_with_its_coefficient() {
    let dir = tempfile::tempdir().unwrap();
    let flight = flight_with_hidden_term(dir.path());
    let model = dir.path().join("model.toml");
    std::fs::write(
        &model,
        "vehicle = \"fixed-wing\"\naircraft = \"aerosonde\"\n\n[[term]]\naxis = \"m\"\nexpr = \"k * thrust\"\n",
    )
    .unwrap();
    let out = dir.path().join("fit.toml");
    let text = ok(&[
        "diagnose",
        "--flight",
        flight.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(text.contains("model fixed-wing baseline"), "{text}");
    let row = text
        .lines()
        .find(|l| l.trim_start().starts_with("term(m=k*thrust)"))
        .unwrap_or_else(|| panic!("the term is no candidate: {text}"));
    assert!(row.contains("yes"), "{row}");
    assert!(
        text.contains("verdict: `term(m=k*thrust)` is missing"),
        "{text}"
    );
    let k = fitted_k(&out);
    assert!((k - TRUE_K).abs() < 0.03 * TRUE_K, "k = {k}");
    // The written model, with its term's value, is the model compare takes.
    let said = ok(&[
        "compare",
        "--flight",
        flight.to_str().unwrap(),
        "--model",
        out.to_str().unwrap(),
    ]);
    assert!(
        said.contains("model: fixed-wing + term(m=k*thrust)"),
        "{said}"
    );
}

#[test]
fn a_bad_expression_is_refused_with_its_column_and_problem_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    for (spec, want) in [
        (
            "term:m=k*trhust",
            &[
                "`term:m=k*trhust`: column 10:",
                "did you mean `thrust`?",
                "variables: alpha, beta,",
            ][..],
        ),
        (
            "term:m=k*(thrust",
            &["column 10: this `(` is never closed"][..],
        ),
        (
            "term:m=k*sinn(alpha)",
            &["column 10: unknown function `sinn`: did you mean `sin`?"][..],
        ),
        ("term:w=k*alpha", &["column 6: unknown axis `w`"][..]),
        ("term:m=2*thrust", &["no free coefficient"][..]),
    ] {
        let o = wireflight(&["simulate", "--hidden", spec, "--out", out.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{spec}: {err}");
        for w in want {
            assert!(err.contains(w), "{spec}: {err}");
        }
        assert!(!out.exists(), "{spec} wrote a file");
    }
}

#[test]
fn a_bad_term_in_a_model_file_names_the_file_and_the_column() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.toml");
    std::fs::write(
        &model,
        "vehicle = \"fixed-wing\"\n[[term]]\naxis = \"m\"\nexpr = \"k * alfa\"\n",
    )
    .unwrap();
    let e = ModelSpec::load(&model).unwrap_err();
    let chain = format!("{e}: {}", std::error::Error::source(&e).unwrap());
    assert!(chain.contains("model.toml: bad model file"), "{chain}");
    assert!(
        chain.contains("`k * alfa`: column 5:") && chain.contains("did you mean `alpha`?"),
        "{chain}"
    );
}

#[test]
fn a_term_that_goes_non_finite_stops_the_flight_with_the_time_and_the_values() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("n.csv");
    // √(0.1 − |p|) is NaN once the roll rate passes 0.1 rad/s, in the turn's entry.
    let o = wireflight(&[
        "simulate",
        "--manoeuvre",
        "climbing-turn",
        "--hidden",
        "term(l=k*sqrt(0.1-abs(p))):k=0.001",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the simulated flight stopped at t = "),
        "{err}"
    );
    assert!(
        err.contains("term `l = k*sqrt(0.1-abs(p))` is not finite")
            && err.contains("sqrt of a negative number")
            && err.contains("(at p = 0.100")
            && err.contains("k = 0.001"),
        "{err}"
    );
    assert!(!out.exists());

    // Against a flight: refused before any fit, never NaN in a table.
    let flight = flight_with_hidden_term(dir.path());
    for (cmd, add) in [
        ("compare", "term(m=k*ln(throttle-2)):k=1"),
        ("diagnose", "term:m=k/(alpha-alpha)"),
    ] {
        let o = wireflight(&[cmd, "--flight", flight.to_str().unwrap(), "--add", add]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {err}");
        assert!(
            err.contains("the model's forces are not finite at t = 0.00 s: term `"),
            "{cmd}: {err}"
        );
        assert!(
            err.contains("ln of a non-positive number") || err.contains("division by zero"),
            "{cmd}: {err}"
        );
        assert!(
            err.contains("throttle = ") || err.contains("alpha = "),
            "{err}"
        );
        assert!(stdout(&o).is_empty(), "{cmd}: {}", stdout(&o));
    }
}

#[test]
fn the_same_term_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    let o = wireflight(&[
        "simulate",
        "--hidden",
        "term:m=k*thrust",
        "--hidden",
        "term:m = k * thrust",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("term(m=k*thrust)"), "{err}");
    assert!(!out.exists());
}

#[test]
fn terms_are_rows_of_the_windows_effect_checkboxes() {
    use wireflight::analysis::compare::CompareConfig;
    use wireflight::app::view::compare::Compare;
    let dir = tempfile::tempdir().unwrap();
    let flight = flight_with_hidden_term(dir.path());
    let data = data::read(&flight).unwrap();
    let spec = ModelSpec::from_toml(
        "vehicle = \"fixed-wing\"\n[[term]]\naxis = \"m\"\nexpr = \"k * thrust\"\n",
    )
    .unwrap();
    let base = spec.build(Origin::default()).unwrap();
    let cfg = CompareConfig {
        window_s: 8.0,
        ..CompareConfig::default()
    };
    let compare = Compare::with_config(
        Arc::new(data),
        base,
        &["term:Y=c*beta".to_string()],
        cfg,
        false,
    )
    .unwrap();
    let names: Vec<&str> = compare.rows.iter().map(|r| r.name).collect();
    assert!(names.contains(&"wind"), "{names:?}");
    let declared = compare
        .rows
        .iter()
        .find(|r| r.name == "term(m=k*thrust)")
        .unwrap_or_else(|| panic!("{names:?}"));
    assert!(!declared.on && !declared.in_base);
    assert!(term_of(declared.effect().info()).is_some());
    let added = compare
        .rows
        .iter()
        .find(|r| r.name == "term(Y=c*beta)")
        .unwrap_or_else(|| panic!("{names:?}"));
    assert!(added.on);
    assert!(
        !compare.model().has_effect("term(m=k*thrust)"),
        "a declared term is a choice, not the base"
    );
    assert!(compare.model().has_effect("term(Y=c*beta)"));
}
