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
