//! `diagnose` on one hour of 100 Hz data across the whole catalogue (target: < 2 s on one
//! core), and one `compare` of the same data. The data are simulated in memory (a flight-test
//! schedule with a hidden wind and realistic noise), so reading the CSV is not timed.

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
        manoeuvre: Manoeuvre::FlightTest,
        duration_s: 3600.0,
        rate_hz: 100.0,
        airspeed_mps: 25.0,
        launch_speed_mps: 150.0,
        height_m: 200.0,
        noise: Noise {
            pos_m: 0.5,
            att_deg: 0.3,
            vel_mps: 0.1,
            rate_dps: 0.5,
        },
        seed: 1,
        source: "benches/diagnose.rs".into(),
        aircraft: Some("aerosonde".into()),
        listed_effects: Vec::new(),
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
}

criterion_group!(benches, one_hour);
criterion_main!(benches);
