//! Turbulent flights: `simulate --turbulence` (MIL-F-8785C Dryden gusts in the truth's air)
//! and refsim's independent gust model, cross-checked statistically.

use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::model::{Model, Vehicle};
use wireflight::flight::params::FixedWingParams;
use wireflight::flight::simulate::{simulate, SimSpec};
use wireflight::flight::turbulence::{
    dryden_series, DrydenIntensity, GustTruth, Turbulence, TurbulenceLevel, TRUTH_KEY,
};

use crate::cli::wireflight;
use crate::support::refsim::{DrydenForm, DrydenGusts};

fn aerosonde() -> Model {
    Model::new(
        Vehicle::FixedWing(Box::new(FixedWingParams::aerosonde())),
        Origin::default(),
    )
}

fn truth_of(flight: &wireflight::flight::data::FlightData) -> GustTruth {
    let record = flight
        .meta
        .other
        .iter()
        .find(|(k, _)| k == TRUTH_KEY)
        .map(|(_, v)| v.clone())
        .expect("a turbulence record");
    GustTruth::parse(&record).unwrap()
}

/// σ and the correlation at lags 0.5·T and T of a series `dt` apart.
fn stats(x: &[f64], dt: f64, t_s: f64) -> (f64, [f64; 2]) {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let var = x.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / n as f64;
    let rho = [0.5, 1.0].map(|f| {
        let lag = (f * t_s / dt).round() as usize;
        x.iter()
            .zip(&x[lag..])
            .map(|(a, b)| (a - mean) * (b - mean))
            .sum::<f64>()
            / (n - lag) as f64
            / var
    });
    (var.sqrt(), rho)
}

#[test]
fn unknown_level_is_refused_with_the_list() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    let o = wireflight(&[
        "simulate",
        "--turbulence",
        "gale",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("unknown turbulence level `gale`: one of light, moderate, severe"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn cli_writes_the_truth_into_the_file_and_is_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, seed: &str| {
        let out = dir.path().join(name);
        let o = wireflight(&[
            "simulate",
            "--manoeuvre",
            "doublets",
            "--duration",
            "20",
            "--turbulence",
            "moderate",
            "--turbulence-seed",
            seed,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stdout).contains("moderate turbulence (seed "));
        std::fs::read_to_string(out).unwrap()
    };
    let (a, b, c) = (run("a.csv", "4"), run("b.csv", "4"), run("c.csv", "5"));
    assert_eq!(a, b, "same seed, same file");
    assert_ne!(a, c, "another gust seed, another flight");
    let line = a
        .lines()
        .find(|l| l.starts_with("# turbulence:"))
        .expect("a # turbulence: line");
    let truth = GustTruth::parse(line.trim_start_matches("# turbulence:").trim()).unwrap();
    assert_eq!(truth.turbulence.level, TurbulenceLevel::Moderate);
    assert_eq!(truth.turbulence.seed, 4);
    // 200 m (656 ft), W20 = 30 kt: σ_w = 3 kt, σ_u = σ_w/(0.177 + 0.000823·656)^0.4.
    let sw = 3.0 * 1852.0 / 3600.0;
    assert!((truth.intensity.sigma_mps[2] - sw).abs() < 1e-3);
    let h = 200.0 / 0.3048;
    let su = sw / (0.177f64 + 0.000823 * h).powf(0.4);
    assert!((truth.intensity.sigma_mps[0] - su).abs() < 1e-3);
    assert!((truth.intensity.length_m[2] - 200.0).abs() < 0.01);
    // Read back through the flight-data reader too.
    let read = wireflight::flight::data::read(&dir.path().join("a.csv")).unwrap();
    assert_eq!(truth_of(&read).turbulence.seed, 4);
}

/// A turbulent flight differs from the calm one of the same spec only by the gusts: the air
/// moves (the airspeed differs from the ground speed's projection), nothing else changed
/// (same noise seed, same manoeuvre), and moderate turbulence does not make the flight
/// unusable.
#[test]
fn turbulent_flight_differs_from_the_calm_one_only_by_gusts() {
    let model = aerosonde();
    let calm_spec = SimSpec::new(Manoeuvre::FlightTest, 60.0);
    let calm = simulate(&model, &calm_spec).unwrap();
    let spec = SimSpec {
        turbulence: Some(Turbulence {
            level: TurbulenceLevel::Moderate,
            seed: 11,
        }),
        ..calm_spec.clone()
    };
    let gusty = simulate(&model, &spec).unwrap();
    assert_eq!(gusty.time, calm.time);
    assert!(calm.meta.other.iter().all(|(k, _)| k != TRUTH_KEY));
    assert_eq!(truth_of(&gusty).turbulence.seed, 11);
    // Starts from the same trim.
    assert_eq!(gusty.pos_ned[0], calm.pos_ned[0]);
    let (ga, ca) = (
        gusty.airspeed.as_ref().unwrap(),
        calm.airspeed.as_ref().unwrap(),
    );
    let rms = |a: &[f64], b: &[f64]| -> f64 {
        (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
    };
    let d_air = rms(ga, ca);
    assert!(d_air > 0.3, "gusts move the airspeed: {d_air}");
    // Still flown: the airspeed stays near the trim's, the height within a band.
    let mean_air = ga.iter().sum::<f64>() / ga.len() as f64;
    assert!((mean_air - 25.0).abs() < 2.0, "mean airspeed {mean_air}");
    let dz = gusty
        .pos_ned
        .iter()
        .zip(&calm.pos_ned)
        .map(|(a, b)| (a.z - b.z).abs())
        .fold(0.0, f64::max);
    assert!(dz < 60.0, "height departs {dz} m from the calm flight's");
    // Adding the gusts left the calm model untouched: the calm spec flies bit for bit again.
    assert_eq!(simulate(&model, &calm_spec).unwrap().pos_ned, calm.pos_ned);
}

/// The project's filters over a long series: σ within 3 %, correlation at T/2 and T within
/// 0.04 of the Dryden forms, for a coarse and a fine step.
#[test]
fn project_gusts_have_the_dryden_statistics() {
    let truth = GustTruth::new(
        Turbulence {
            level: TurbulenceLevel::Light,
            seed: 21,
        },
        50.0,
        100.0,
    );
    // 50 m at 100 m/s: T_u = 2.0 s, T_w = 0.5 s; 10⁴ T_u of gusts.
    let scales = truth.time_scales_s();
    for dt in [0.01, 0.2] {
        let n = (10_000.0 * scales[0] / dt) as usize;
        let g = dryden_series(&truth, dt, n).unwrap();
        for (axis, form) in [
            (0, DrydenForm::Longitudinal),
            (1, DrydenForm::Transverse),
            (2, DrydenForm::Transverse),
        ] {
            let x: Vec<f64> = g.iter().map(|v| v[axis]).collect();
            let (sigma, rho) = stats(&x, dt, scales[axis]);
            let want = truth.intensity.sigma_mps[axis];
            assert!(
                (sigma / want - 1.0).abs() < 0.03,
                "dt {dt} axis {axis}: σ {sigma} vs {want}"
            );
            for (r, f) in rho.iter().zip([0.5, 1.0]) {
                let lag = (f * scales[axis] / dt).round() * dt;
                let w = form.correlation(lag, scales[axis]);
                assert!(
                    (r - w).abs() < 0.04,
                    "dt {dt} axis {axis} lag {lag}: ρ {r} vs {w}"
                );
            }
        }
    }
}

/// refsim's sum of sinusoids and the project's filters: the same σ (within 3 %) and the
/// same correlation at T/2 and T (within 0.05) for each component.
#[test]
fn refsim_gusts_agree_with_the_project_gusts() {
    let truth = GustTruth::new(
        Turbulence {
            level: TurbulenceLevel::Severe,
            seed: 5,
        },
        50.0,
        100.0,
    );
    let scales = truth.time_scales_s();
    let reference = DrydenGusts::new(truth.intensity.sigma_mps, scales, 99);
    // 5000 T_u of gusts, 0.1 s apart.
    let dt = 0.1;
    let n = (5_000.0 * scales[0] / dt) as usize;
    let ours = dryden_series(&truth, dt, n).unwrap();
    let theirs: Vec<[f64; 3]> = (0..n).map(|k| reference.wind_at(k as f64 * dt)).collect();
    for axis in 0..3 {
        let a: Vec<f64> = ours.iter().map(|v| v[axis]).collect();
        let b: Vec<f64> = theirs.iter().map(|v| v[axis]).collect();
        let (sa, ra) = stats(&a, dt, scales[axis]);
        let (sb, rb) = stats(&b, dt, scales[axis]);
        assert!(
            (sa / sb - 1.0).abs() < 0.03,
            "axis {axis}: σ {sa} vs refsim {sb}"
        );
        for (x, y) in ra.iter().zip(&rb) {
            assert!((x - y).abs() < 0.05, "axis {axis}: ρ {x} vs refsim {y}");
        }
        // refsim's band correlation is the Dryden form's.
        let c = &reference.components[axis];
        let form = if axis == 0 {
            DrydenForm::Longitudinal
        } else {
            DrydenForm::Transverse
        };
        for f in [0.25, 1.0, 3.0] {
            let tau = f * scales[axis];
            let (got, want) = (c.correlation(tau), form.correlation(tau, scales[axis]));
            assert!(
                (got - want).abs() < 0.01,
                "axis {axis} τ {tau}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn intensities_rise_with_the_level_and_meet_the_table_above_2000_ft() {
    let at = |l, h| DrydenIntensity::at(l, h);
    let levels = [
        TurbulenceLevel::Light,
        TurbulenceLevel::Moderate,
        TurbulenceLevel::Severe,
    ];
    for h in [30.0, 200.0, 450.0, 1000.0, 3000.0] {
        let s: Vec<f64> = levels.iter().map(|&l| at(l, h).sigma_mps[2]).collect();
        assert!(s[0] < s[1] && s[1] < s[2], "h {h}: {s:?}");
    }
    // Moderate at 3750 ft: 7.4 ft/s (probability of exceedance 10⁻³), L = 1750 ft.
    let m = at(TurbulenceLevel::Moderate, 3750.0 * 0.3048);
    assert!((m.sigma_mps[0] - 7.4 * 0.3048).abs() < 1e-9);
    assert!((m.length_m[2] - 1750.0 * 0.3048).abs() < 1e-9);
}

/// The JSBSim flights in light turbulence read as flights, carry their gust truth, and the
/// gust columns' σ are those of the header.
#[test]
fn jsbsim_turbulent_flights_carry_their_gust_truth() {
    for name in ["turb-light-1", "turb-light-2", "turb-cmalpha085"] {
        let path = crate::support::data_file(&format!("jsbsim-c172p-{name}.csv"));
        let flight = wireflight::flight::data::read(&path).unwrap();
        assert_eq!(flight.len(), 1251, "{name}");
        let sigma = flight
            .meta
            .other
            .iter()
            .find(|(k, _)| k == "jsbsim_gust_sigma_mps")
            .map(|(_, v)| v.clone())
            .expect("a gust σ line");
        let values: Vec<f64> = sigma
            .split_whitespace()
            .filter_map(|w| w.split_once('=')?.1.parse().ok())
            .collect();
        assert_eq!(values.len(), 3, "{sigma}");
        // Light turbulence: σ of order 1 m/s (0.5 to 3 m/s over 50 s).
        assert!(
            values.iter().all(|s| (0.5..3.0).contains(s)),
            "{name}: {sigma}"
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("# jsbsim_turbulence: Dryden milspec turbulence light"));
    }
}
