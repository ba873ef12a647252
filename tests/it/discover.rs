//! `discover`: refsim flights with terms the model does not have (hidden terms) give that
//! term first, on its axis, with its coefficient; a clean flight gives none.

use wireflight::analysis::discover::{discover, Discovery};
use wireflight::flight::data::{self, FlightData};
use wireflight::flight::spec::ModelChoice;

use crate::support::refsim::{
    self, Effects, FlightOptions, HiddenForm, HiddenTerm, Noise, Schedule,
};

fn flight(effects: Effects, seed: u64) -> FlightData {
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.duration_s = 40.0;
    o.effects = effects;
    o.noise = Noise::new(0.05, 0.05, 0.05, 0.2, 0.05);
    o.seed = seed;
    let csv = refsim::flight_csv(&o).expect("refsim flies");
    data::parse(&csv, "refsim.csv").expect("refsim's CSV reads")
}

fn run(d: &FlightData) -> Discovery {
    let model = ModelChoice::default()
        .build(std::path::Path::new("refsim.csv"), d)
        .expect("model");
    discover(&model, d).expect("discovers")
}

fn hidden(axis: usize, form: HiddenForm, coefficient: f64) -> Effects {
    Effects {
        hidden_terms: vec![HiddenTerm {
            axis,
            form,
            coefficient,
        }],
        ..Effects::default()
    }
}

fn check_first(d: &Discovery, axis: &str, regressors: &[&str], truth: f64) {
    let text = format!("{d:#?}");
    let first = d.terms.first().unwrap_or_else(|| panic!("no term: {text}"));
    assert_eq!(first.axis.name(), axis, "{text}");
    assert_eq!(first.regressors, regressors, "{text}");
    let rel = (first.coefficient - truth).abs() / truth.abs();
    assert!(
        rel < 0.10,
        "coefficient {} vs {truth}: {text}",
        first.coefficient
    );
    assert!(first.add.starts_with(&format!("term:{axis}=")), "{text}");
}

#[test]
#[ignore = "not yet found: in this closed-loop flight β follows the rudder, and the selection \
            takes l ∝ q̄·rudder (docs/discover.md, what it cannot do yet)"]
fn a_rolling_moment_from_alpha_times_beta_is_found_on_l() {
    let d = run(&flight(hidden(3, HiddenForm::QbarAlphaBeta, 2.0), 71));
    check_first(&d, "l", &["qbar", "alpha", "beta"], 2.0);
}

#[test]
fn a_slipstream_drag_from_throttle_squared_is_found_on_x() {
    let d = run(&flight(hidden(0, HiddenForm::ThrottleSquared, -8.0), 72));
    check_first(&d, "X", &["throttle^2"], -8.0);
}

#[test]
#[ignore = "not yet found: the selection takes n ∝ q̄·q̂·r̂ (docs/discover.md, what it cannot \
            do yet)"]
fn a_yawing_moment_from_yaw_rate_times_throttle_is_found_on_n() {
    let d = run(&flight(hidden(5, HiddenForm::YawRateThrottle, -2.0), 73));
    check_first(&d, "n", &["r", "throttle"], -2.0);
}

#[test]
fn a_clean_flight_gives_no_term() {
    let d = run(&flight(Effects::default(), 74));
    assert!(d.terms.is_empty(), "{d:#?}");
}

/// The loop `diagnose` → `discover` → `diagnose --discover` on a refsim flight whose truth
/// has a pitching moment ∝ the thrust (a thrust line 4 cm above the centre of gravity), which
/// neither the catalogue nor the parameter set has: `diagnose` alone says `unexplained` and
/// points to `discover`; with `--discover` a pitching term in the thrust is a candidate, found,
/// and the error falls to the noise. What is not pinned, because it is not yet right: on this
/// flight α barely moves and `discover` proposes thrust·α rather than thrust, and the form's
/// small mismatch is then taken up by a second cause (docs/discover.md).
#[test]
fn diagnose_with_discover_finishes_the_ladder_on_a_term_no_catalogue_has() {
    use crate::cli::{stdout, wireflight};
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.effects = hidden(4, HiddenForm::Thrust, -0.04);
    o.noise = Noise::new(0.3, 0.2, 0.1, 0.3, 0.1);
    o.seed = 41;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("thrust-line.csv");
    std::fs::write(&path, refsim::flight_csv(&o).expect("refsim flies")).unwrap();
    let f = path.to_str().unwrap();
    let verdict = |text: &str| {
        text.lines()
            .find(|l| l.contains("verdict:"))
            .unwrap_or_else(|| panic!("no verdict:\n{text}"))
            .to_string()
    };

    let alone = stdout(&wireflight(&["diagnose", "--flight", f]));
    assert!(verdict(&alone).contains("verdict: unexplained"), "{alone}");
    assert!(
        alone.contains("next: `wireflight discover --flight"),
        "{alone}"
    );

    let with = stdout(&wireflight(&["diagnose", "--flight", f, "--discover"]));
    let v = verdict(&with);
    assert!(v.contains("`term(m=k_m1*thrust"), "{with}");
    let units: f64 = v
        .rsplit('(')
        .next()
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no × noise in {v}"));
    assert!(units < 1.2, "{v}");
}
