//! `diagnose` on one hour of 100 Hz data across the whole catalogue, one `compare` of the same
//! data, and `diagnose` of a 45 s flight test at 50 Hz. The data are simulated in memory (a
//! flight-test schedule with a hidden wind and realistic noise), so reading the CSV is not
//! timed.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use wireflight::analysis::compare::{compare_prepared, CompareConfig, Prepared};
use wireflight::analysis::diagnose::{diagnose, DiagnoseConfig};
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelSpec};
use wireflight::flight::VehicleKind;

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
}

criterion_group!(benches, one_hour);
criterion_main!(benches);
