//! The workbench on flights it did not make: `support::refsim` is an independent
//! implementation of the spec (Euler-angle state, RK4 at 1 ms or Dormand–Prince 5(4), its own
//! trim, autopilot and noise), and its flights put control steps anywhere in a window — the
//! case where reading a start state off the data biases it and a right model looks wrong.

use wireflight::analysis::compare::{compare, noise_floor, CompareConfig, Prepared};
use wireflight::analysis::diagnose::{diagnose, Candidate, DiagnoseConfig, Diagnosis, Verdict};
use wireflight::data::{self, FlightData};
use wireflight::flight::model::Model;
use wireflight::flight::spec::ModelChoice;

use crate::support::refsim::{self, Effects, FlightOptions, Integrator, Noise, Schedule};

/// GPS-RTK-grade position, good AHRS attitude, air data and rate gyros (1σ): 0.05 m, 0.05°,
/// 0.05 m/s, 0.2°/s, airspeed 0.05 m/s.
fn survey_noise() -> Noise {
    Noise::new(0.05, 0.05, 0.05, 0.2, 0.05)
}

fn flight(opts: &FlightOptions) -> FlightData {
    let csv = refsim::flight_csv(opts).expect("refsim flies");
    data::parse(&csv, "refsim.csv").expect("refsim's CSV reads")
}

/// The model the data's metadata name (the Aerosonde baseline).
fn baseline(d: &FlightData) -> Model {
    ModelChoice::default()
        .build(std::path::Path::new("refsim.csv"), d)
        .expect("model")
}

/// A 45 s flight test at 50 Hz: turns both ways, a climb, doublets on every surface.
fn flight_test(effects: Effects, seed: u64) -> FlightOptions {
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.duration_s = 45.0;
    o.effects = effects;
    o.noise = survey_noise();
    o.seed = seed;
    o
}

#[test]
fn noise_free_flights_of_another_integrator_compare_at_zero_for_every_window_and_offset() {
    let mut worst = 0.0f64;
    let mut report = String::new();
    // At 100 and 200 Hz one integration step spans two and four samples, through the
    // autopilot's commands and the control steps.
    for (schedule, integrator, rate_hz, windows) in [
        (
            Schedule::steps_8_18_24_34_36_41(),
            Integrator::rk4_1ms(),
            50.0,
            &[4.0, 6.0, 8.0, 9.0, 10.0, 12.0][..],
        ),
        (
            Schedule::window_steps(4.0),
            Integrator::rk4_1ms(),
            50.0,
            &[4.0, 8.0, 12.0][..],
        ),
        (
            Schedule::steps_8_18_24_34_36_41(),
            Integrator::dopri(1e-10),
            50.0,
            &[8.0][..],
        ),
        (
            Schedule::steps_8_18_24_34_36_41(),
            Integrator::rk4_1ms(),
            100.0,
            &[4.0, 8.0][..],
        ),
        (
            Schedule::window_steps(4.0),
            Integrator::rk4_1ms(),
            200.0,
            &[8.0][..],
        ),
    ] {
        let mut o = FlightOptions::new(schedule);
        o.integrator = integrator;
        o.rate_hz = rate_hz;
        let d = flight(&o);
        let model = baseline(&d);
        for &window_s in windows {
            for offset_s in [0.0, 1.3, 2.7] {
                let cfg = CompareConfig {
                    window_s,
                    offset_s,
                    ..CompareConfig::default()
                };
                let c = compare(&model, &d, cfg);
                report += &format!(
                    "{} {} {rate_hz} Hz: window {window_s} s, offset {offset_s} s: total {:.5}\n",
                    o.schedule.name,
                    integrator.describe(),
                    c.total
                );
                worst = worst.max(c.total);
            }
        }
    }
    eprint!("{report}");
    // Before the start states were fitted: 0.30 to 2.10 on the steps flight; the issue asks
    // 0.05. Measured 0.00054-0.00062 at 50 Hz and 0.0011-0.0012 at 100 Hz (commands that
    // change every sample inside an integration step).
    assert!(worst <= 0.005, "worst total {worst}\n{report}");
}

#[test]
fn noise_is_told_from_manoeuvres_and_a_right_model_sits_at_its_floor() {
    // At 100 Hz, every other sample lies inside an integration step.
    for rate_hz in [50.0, 100.0] {
        let mut o = FlightOptions::new(Schedule::steps_8_18_24_34_36_41());
        o.noise = survey_noise();
        o.seed = 11;
        o.rate_hz = rate_hz;
        let d = flight(&o);
        let model = baseline(&d);
        let prep = Prepared::new(&d, CompareConfig::default());
        let n = prep.noise;
        let truth = [
            ("position", n.pos_m, 0.05),
            ("velocity", n.vel_mps, 0.05),
            ("attitude", n.att_rad.to_degrees(), 0.05),
            ("rates", n.rate_radps.to_degrees(), 0.2),
            ("airspeed", n.airspeed_mps, 0.05),
        ];
        for (what, got, want) in truth {
            assert!(
                (got / want - 1.0).abs() <= 0.3,
                "{rate_hz} Hz: {what} noise estimated {got}, true {want}"
            );
        }
        for window_s in [4.0, 8.0, 12.0] {
            let cfg = CompareConfig {
                window_s,
                ..CompareConfig::default()
            };
            let c = compare(&model, &d, cfg);
            let floor = noise_floor(&model, &Prepared::new(&d, cfg));
            eprintln!(
                "{rate_hz} Hz, window {window_s}: total {:.4}, floor {floor:.4}, {:.3} × noise",
                c.total,
                c.noise_units()
            );
            assert!(c.total <= 1.5 * floor, "{} vs floor {floor}", c.total);
            assert!(c.noise_units() < 1.1, "{}", c.noise_units());
        }
    }
}

fn report(d: &Diagnosis) -> String {
    let mut s = format!(
        "verdict {}: error {:.3} ({:.2} × noise), floor {:.3}\n",
        d.verdict, d.base_error, d.noise_units, d.noise_floor
    );
    for c in &d.ranking {
        s += &format!(
            "  {:16} {:.2} × noise, LR {:.1} > {:.1}: {} {}, {:?} ± {:?}\n",
            c.effect,
            c.noise_units_after,
            c.lr_statistic,
            c.lr_critical,
            c.significant,
            c.partial,
            c.params,
            c.uncertainty
        );
    }
    s
}

/// The verdict is `effect`, and its parameter `name` is within 2σ of `truth`.
fn assert_found(d: &Diagnosis, effect: &str, name: &str, truth: f64) -> Candidate {
    let text = report(d);
    eprint!("{text}");
    assert_eq!(d.verdict, Verdict::Found(vec![effect.into()]), "{text}");
    let w = d.winner().expect("a winner").clone();
    assert!(w.significant && !w.partial, "{text}");
    let k = w.params.iter().position(|(n, _)| n == name).expect(name);
    let (value, sigma) = (w.params[k].1, w.uncertainty[k]);
    assert!(
        sigma.is_finite() && (value - truth).abs() <= 2.0 * sigma,
        "{name}: {value} ± {sigma} (1σ) vs truth {truth}\n{text}"
    );
    w
}

#[test]
fn hidden_gyroscopic_effect_is_found_with_its_value() {
    let o = flight_test(Effects::none().with("gyroscopic", &[2.5]).unwrap(), 21);
    let d = flight(&o);
    let dg = diagnose(&baseline(&d), &d, &[], &DiagnoseConfig::default()).unwrap();
    assert_found(&dg, "gyroscopic", "k_gyro", 2.5);
}

#[test]
fn hidden_actuator_lag_is_found_with_its_value() {
    let o = flight_test(Effects::none().with("actuator_lag", &[0.12]).unwrap(), 22);
    let d = flight(&o);
    let dg = diagnose(&baseline(&d), &d, &[], &DiagnoseConfig::default()).unwrap();
    assert_found(&dg, "actuator_lag", "tau_s", 0.12);
}

#[test]
fn clean_independent_flights_give_none() {
    for seed in [31, 32] {
        let d = flight(&flight_test(Effects::none(), seed));
        let dg = diagnose(&baseline(&d), &d, &[], &DiagnoseConfig::default()).unwrap();
        let text = report(&dg);
        eprint!("{text}");
        assert_eq!(dg.verdict, Verdict::None, "{text}");
    }
}

/// A refsim flight test whose aircraft differs from the set in one number.
fn wrong_number(key: &str, factor: f64, seed: u64) -> FlightData {
    let mut o = flight_test(Effects::none(), seed);
    let p = &mut o.params;
    let slot = match key {
        "c_m_alpha" => &mut p.c_m_alpha,
        "c_ell_p" => &mut p.c_ell_p,
        "c_n_beta" => &mut p.c_n_beta,
        "c_d_p" => &mut p.c_d_p,
        "mass_kg" => &mut p.mass_kg,
        other => panic!("no such key in this test: {other}"),
    };
    *slot *= factor;
    flight(&o)
}

#[test]
fn a_wrong_coefficient_is_named_with_its_value_never_a_catalogue_effect() {
    let aerosonde = wireflight::flight::params::FixedWingParams::aerosonde();
    for (key, factor) in [
        ("c_m_alpha", 0.8),
        ("c_ell_p", 1.25),
        ("c_n_beta", 0.7),
        ("c_d_p", 1.5),
    ] {
        let d = wrong_number(key, factor, 41);
        let dg = diagnose(&baseline(&d), &d, &[], &DiagnoseConfig::default()).unwrap();
        let text = report(&dg);
        eprintln!("{key} × {factor}:\n{text}");
        let truth = wireflight::flight::params::keys::get(&aerosonde, key).unwrap() * factor;
        assert_eq!(
            dg.verdict,
            Verdict::Found(vec![format!("aircraft:{key}")]),
            "{text}"
        );
        let w = dg.winner().unwrap();
        let fitted = w.params[0].1;
        assert!(
            (fitted / truth - 1.0).abs() <= 0.05,
            "{key}: fitted {fitted}, truth {truth}"
        );
        // Applying the named correction brings the error to the noise floor.
        assert!(w.noise_units_after <= 1.1, "{text}");
        assert!(w.error_after <= 1.1 * dg.noise_floor, "{text}");
    }
}

#[test]
fn a_wrong_mass_is_named_or_unexplained_never_a_catalogue_effect() {
    let d = wrong_number("mass_kg", 0.9, 42);
    let dg = diagnose(&baseline(&d), &d, &[], &DiagnoseConfig::default()).unwrap();
    let text = report(&dg);
    eprintln!("{text}");
    let catalogue = wireflight::flight::effects::catalogue_names();
    match &dg.verdict {
        Verdict::Found(names) => {
            for name in names {
                assert!(!catalogue.contains(&name.as_str()), "{text}");
                assert!(name.starts_with("aircraft:"), "{text}");
            }
        }
        Verdict::Unexplained => {}
        Verdict::None => panic!("a 10% heavier model is not at the noise floor\n{text}"),
        // `diagnose` itself never says turbulence: the filter-error method is a later step.
        Verdict::Turbulence(_) => panic!("the library's diagnosis said turbulence\n{text}"),
    }
}

/// A window's start refitted for a model that differs by an effect, beginning with the base
/// model's Jacobian (what diagnose and identify do), reaches the misfit of a fit from a fresh
/// Jacobian; a Jacobian that points the wrong way is replaced, not followed.
#[test]
fn a_borrowed_start_jacobian_reaches_the_fresh_fits_misfit() {
    use wireflight::analysis::compare::start::{self, Scratch};
    use wireflight::flight::effects::Origin;
    use wireflight::flight::spec::EffectSpec;

    let mut o = FlightOptions::new(Schedule::steps_8_18_24_34_36_41());
    o.effects = Effects {
        gyroscopic: Some(2.5),
        ..Effects::default()
    };
    o.noise = survey_noise();
    o.seed = 5;
    let d = flight(&o);
    let base = baseline(&d);
    let mut spec =
        wireflight::flight::spec::ModelSpec::baseline(wireflight::data::VehicleKind::FixedWing);
    spec.effects
        .push(EffectSpec::parse("gyroscopic:k_gyro=2.5").unwrap());
    let with_effect = spec.build(Origin::default()).unwrap();
    let prep = Prepared::new(&d, CompareConfig::default());
    let chi2 = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let mut scratch = Scratch::default();
    // Windows that start in a transient (steps at 8, 18, 24 s) as well as quiet ones.
    for &w in prep.windows.iter().take(4) {
        let x0 = prep.warm_start(&base, w, glam::DVec3::ZERO);
        let base_fit = prep.fit_start(&base, w, x0, &mut scratch);
        let fresh = prep.fit_start(&with_effect, w, base_fit.state, &mut scratch);
        let borrowed = prep.fit_start_with(
            &with_effect,
            w,
            base_fit.state,
            Some(&base_fit.jacobian),
            &mut scratch,
        );
        let wrong: Vec<f64> = base_fit.jacobian.iter().map(|v| -v).collect();
        let misled =
            prep.fit_start_with(&with_effect, w, base_fit.state, Some(&wrong), &mut scratch);
        let (f, b, m) = (
            chi2(&fresh.residuals),
            chi2(&borrowed.residuals),
            chi2(&misled.residuals),
        );
        let n = fresh.residuals.len() as f64;
        eprintln!("window {w:?}: χ² fresh {f:.3}, borrowed {b:.3}, misled {m:.3} ({n} residuals)");
        // Within the fits' own tolerance (a few times what a last step may still promise:
        // ABS_TOL, or REL_TOL of the misfit) and far below one noise unit.
        let tol = 10.0 * start::ABS_TOL + 2.0 * start::REL_TOL * f;
        for (what, got) in [("borrowed", b), ("misled", m)] {
            assert!(
                (got - f).abs() <= tol,
                "window {w:?}: {what} χ² {got} vs fresh {f}"
            );
        }
        // With the right model the misfit is the noise's: about one per residual.
        assert!(f / n < 1.3, "window {w:?}: χ²/n = {}", f / n);
    }
}
