//! `diagnose` on one hour of 100 Hz data across the whole catalogue (one cause hidden, and
//! two), one `compare` of the same data, and `diagnose` of a 45 s flight test at 50 Hz. The
//! data are simulated in memory (a flight-test schedule with a hidden wind and realistic
//! noise), so reading the CSV is not timed.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use wireflight::analysis::compare::{compare_prepared, CompareConfig, Prepared};
use wireflight::analysis::diagnose::{diagnose, DiagnoseConfig};
use wireflight::analysis::identify::{free_keys, identify, IdentifyConfig};
use wireflight::data::VehicleKind;
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelSpec};

fn one_hour(c: &mut Criterion) {
    let base = ModelSpec::baseline(VehicleKind::FixedWing);
    let mut truth = base.clone();
    truth
        .effects
        .push(EffectSpec::parse("wind:north_mps=4,east_mps=-3").unwrap());
    let truth = truth.build(Origin::default()).unwrap();
    let spec = SimSpec {
        rate_hz: 100.0,
        noise: Noise {
            pos_m: 0.5,
            att_deg: 0.3,
            vel_mps: 0.1,
            rate_dps: 0.5,
        },
        ..SimSpec::new(Manoeuvre::FlightTest, 3600.0)
    };
    let data = simulate(&truth, &spec).unwrap();
    let model = base.build(Origin::default()).unwrap();

    let mut group = c.benchmark_group("one_hour_100hz");
    group.sample_size(10);
    group.throughput(Throughput::Elements(data.len() as u64));
    group.bench_function("diagnose (whole catalogue)", |b| {
        b.iter(|| diagnose(&model, &data, &[], &DiagnoseConfig::default()))
    });
    let prep = Prepared::new(&data, CompareConfig::default());
    group.bench_function("compare (all windows)", |b| {
        b.iter(|| compare_prepared(&model, &prep))
    });
    // Two causes at once: the wind and a pitch damping 40% stronger than the set's.
    let mut two = truth.clone();
    two.set_aircraft("c_m_q", -38.21 * 1.4).unwrap();
    let two_data = simulate(&two, &spec).unwrap();
    group.bench_function("diagnose two causes (wind + c_m_q)", |b| {
        b.iter(|| diagnose(&model, &two_data, &[], &DiagnoseConfig::default()))
    });
    group.finish();

    let short = simulate(
        &truth,
        &SimSpec {
            noise: Noise {
                pos_m: 0.05,
                att_deg: 0.05,
                vel_mps: 0.05,
                rate_dps: 0.2,
            },
            ..SimSpec::new(Manoeuvre::FlightTest, 45.0)
        },
    )
    .unwrap();
    let mut group = c.benchmark_group("flight_test_45s_50hz");
    group.sample_size(10);
    group.throughput(Throughput::Elements(short.len() as u64));
    group.bench_function("diagnose (whole catalogue)", |b| {
        b.iter(|| diagnose(&model, &short, &[], &DiagnoseConfig::default()))
    });
    group.finish();

    // identify: two 45 s flight tests of an aircraft whose c_m_alpha and c_ell_p are off,
    // every aerodynamic coefficient free (31 numbers).
    let mut wrong = ModelSpec::baseline(VehicleKind::FixedWing);
    wrong
        .effects
        .push(EffectSpec::parse("aircraft:c_m_alpha=-3.3").unwrap());
    wrong
        .effects
        .push(EffectSpec::parse("aircraft:c_ell_p=-0.4").unwrap());
    let wrong = wrong.build(Origin::default()).unwrap();
    let flights: Vec<_> = [1, 2]
        .map(|seed| {
            simulate(
                &wrong,
                &SimSpec {
                    noise: Noise {
                        pos_m: 0.05,
                        att_deg: 0.05,
                        vel_mps: 0.05,
                        rate_dps: 0.2,
                    },
                    seed,
                    ..SimSpec::new(Manoeuvre::FlightTest, 45.0)
                },
            )
            .unwrap()
        })
        .into();
    let samples: usize = flights.iter().map(|f| f.len()).sum();
    let mut group = c.benchmark_group("identify_2x45s_50hz");
    group.sample_size(10);
    group.throughput(Throughput::Elements(samples as u64));
    for (label, patterns) in [
        (
            "2 numbers",
            vec!["c_m_alpha".to_string(), "c_ell_p".to_string()],
        ),
        ("31 aerodynamic coefficients", Vec::new()),
    ] {
        let keys = free_keys(&patterns).unwrap();
        group.bench_function(label, |b| {
            b.iter(|| identify(&model, &flights, &keys, &IdentifyConfig::default()))
        });
    }
    group.finish();
}

/// The filter-error method on a minute of 50 Hz flight in light turbulence: one pass of the
/// filter (the unit every estimate is made of), and the estimate of the six intensities.
fn filter_error(c: &mut Criterion) {
    use wireflight::analysis::compare::estimate_noise;
    use wireflight::analysis::filter_error::flight::{FlightFilter, GustModel};
    use wireflight::flight::turbulence::{Turbulence, TurbulenceLevel};
    let model = ModelSpec::baseline(VehicleKind::FixedWing)
        .build(Origin::default())
        .unwrap();
    let spec = SimSpec {
        noise: Noise {
            pos_m: 0.5,
            att_deg: 0.2,
            vel_mps: 0.1,
            rate_dps: 0.2,
        },
        turbulence: Some(Turbulence {
            level: TurbulenceLevel::Light,
            seed: 3,
        }),
        ..SimSpec::new(Manoeuvre::FlightTest, 60.0)
    };
    let data = simulate(&model, &spec).unwrap();
    let filter = FlightFilter::new(
        &model,
        &data,
        &estimate_noise(&data),
        &CompareConfig::default(),
    )
    .unwrap();
    let mut gusts = GustModel::CALM;
    gusts.sigma_mps = [0.88, 0.88, 0.77];
    let mut group = c.benchmark_group("filter_error_60s_50hz");
    group.sample_size(10);
    group.throughput(Throughput::Elements(data.len() as u64));
    group.bench_function("one pass", |b| b.iter(|| filter.pass(&model, &gusts)));
    group.bench_function("estimate the intensities", |b| {
        b.iter(|| filter.estimate_gusts(&model))
    });
    group.finish();
}

/// `diagnose` of a 120 s flight test at 50 Hz with a navigation filter's wandering errors
/// (`ekf-gnss`), aircraft unchanged: against the white noise alone (auto: output error ends
/// unexplained and the filter-error method runs; and output error alone), and against the
/// floor the stated errors leave (`--sensor-errors ekf-gnss`).
fn wandering_errors(c: &mut Criterion) {
    use wireflight::analysis::diagnose::turbulence::Method;
    use wireflight::analysis::diagnose::{run, Request};
    use wireflight::flight::sensor_errors::SensorErrors;

    let base = ModelSpec::baseline(VehicleKind::FixedWing);
    let model = base.build(Origin::default()).unwrap();
    let errors = SensorErrors::preset("ekf-gnss").unwrap();
    let spec = SimSpec {
        sensor_errors: Some(errors.clone()),
        ..SimSpec::new(Manoeuvre::FlightTest, 120.0)
    };
    let data = simulate(&model, &spec).unwrap();
    let mut group = c.benchmark_group("flight_test_120s_50hz_ekf_gnss");
    group.sample_size(10);
    group.throughput(Throughput::Elements(data.len() as u64));
    for (label, stated, method) in [
        ("against the noise (auto)", None, Method::Auto),
        (
            "against the noise (output error)",
            None,
            Method::OutputError,
        ),
        (
            "against the stated errors' floor",
            Some(&errors),
            Method::Auto,
        ),
    ] {
        let request = Request {
            model: &model,
            data: &data,
            references: &[],
            errors: stated,
            declared: &[],
            config: DiagnoseConfig::default(),
            method,
        };
        group.bench_function(label, |b| b.iter(|| run(&request)));
    }
    group.finish();
}

criterion_group!(benches, one_hour, filter_error, wandering_errors);
criterion_main!(benches);
