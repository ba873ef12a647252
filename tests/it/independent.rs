//! The workbench on flights it did not make: an independent implementation of the spec
//! (`support::refsim`: Euler-angle state, RK4 at 1 ms or Dormand–Prince, its own trim and
//! autopilot, its own noise), with control steps anywhere in a window.

use wireflight::analysis::compare::{
    compare, estimate_noise, noise_floor, CompareConfig, Prepared,
};
use wireflight::flight::data::{self, FlightData};
use wireflight::flight::spec::ModelChoice;

use crate::support::refsim::{self, FlightOptions, Noise, Schedule};

fn flight(opts: &FlightOptions) -> FlightData {
    let csv = refsim::flight_csv(opts).expect("refsim flies");
    data::parse(&csv, "refsim.csv").expect("refsim's CSV reads")
}

fn model_for(d: &FlightData) -> wireflight::flight::model::Model {
    ModelChoice::default()
        .build(std::path::Path::new("refsim.csv"), d)
        .expect("model")
}

#[test]
#[ignore]
fn explore_noise_free_steps() {
    let opts = FlightOptions::new(Schedule::steps_8_18_24_34_36_41());
    let d = flight(&opts);
    let m = model_for(&d);
    for w in [4.0, 6.0, 8.0, 9.0, 10.0, 12.0] {
        let t = std::time::Instant::now();
        let c = compare(
            &m,
            &d,
            CompareConfig {
                window_s: w,
                ..CompareConfig::default()
            },
        );
        eprintln!(
            "window {w}: total {:.5} nu {:.3} ({} windows, {:.2} s)",
            c.total,
            c.noise_units(),
            c.windows.len(),
            t.elapsed().as_secs_f64()
        );
    }
    let mut o = opts.clone();
    o.noise = Noise::new(0.05, 0.05, 0.05, 0.2, 0.05);
    o.seed = 3;
    let d = flight(&o);
    let n = estimate_noise(&d);
    eprintln!(
        "noise: pos {:.4} vel {:.4} att {:.4} deg rate {:.4} dps air {:.4}",
        n.pos_m,
        n.vel_mps,
        n.att_rad.to_degrees(),
        n.rate_radps.to_degrees(),
        n.airspeed_mps
    );
    for w in [4.0, 8.0, 12.0] {
        let cfg = CompareConfig {
            window_s: w,
            ..CompareConfig::default()
        };
        let c = compare(&m, &d, cfg);
        let floor = noise_floor(&m, &Prepared::new(&d, cfg));
        eprintln!(
            "noisy window {w}: total {:.4} floor {:.4} nu {:.3} rho {:.3}",
            c.total,
            floor,
            c.noise_units(),
            c.residual_autocorrelation()
        );
    }
}

#[test]
#[ignore]
fn explore_diagnose_speed() {
    use wireflight::analysis::diagnose::{diagnose, DiagnoseConfig};
    let mut o = FlightOptions::new(Schedule::flight_test());
    o.noise = Noise::new(0.05, 0.05, 0.05, 0.2, 0.05);
    o.effects = refsim::Effects::none().with("gyroscopic", &[2.5]).unwrap();
    let d = flight(&o);
    let m = model_for(&d);
    let t = std::time::Instant::now();
    let c = compare(&m, &d, CompareConfig::default());
    eprintln!(
        "compare {:.3} s, flights {}",
        t.elapsed().as_secs_f64(),
        wireflight::analysis::compare::predict::flights()
    );
    let prep = Prepared::new(&d, CompareConfig::default());
    for (k, w) in prep.windows.iter().enumerate() {
        let f0 = wireflight::analysis::compare::predict::flights();
        let mut s = wireflight::analysis::compare::start::Scratch::default();
        let x = prep.warm_start(&m, *w, glam::DVec3::ZERO);
        let fit = prep.fit_start(&m, *w, x, &mut s);
        eprintln!(
            "window {k}: {} iterations, {} flights, chi2/row {:.3}",
            fit.iterations,
            wireflight::analysis::compare::predict::flights() - f0,
            fit.residuals.iter().map(|r| r * r).sum::<f64>() / fit.residuals.len() as f64
        );
    }
    let t = std::time::Instant::now();
    let dg = diagnose(&m, &d, &[], &DiagnoseConfig::default()).unwrap();
    eprintln!(
        "diagnose {:.3} s, flights {}; verdict {}",
        t.elapsed().as_secs_f64(),
        wireflight::analysis::compare::predict::flights(),
        dg.verdict
    );
    eprint!("{}", wireflight::analysis::report::diagnosis_text(&dg));
    let _ = c;
}
