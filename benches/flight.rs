//! Flight-model integrator throughput: fixed-wing RK4 steps per second (baseline, with one
//! expression term `m = k*thrust`, and with every applicable effect on), and one hour of
//! flight at 100 Hz with all effects. The term's step should cost at most 1.3× the
//! baseline's.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;

use wireflight::data::VehicleKind;
use wireflight::flight::effects::{Origin, CATALOGUE};
use wireflight::flight::model::{Model, Vehicle};
use wireflight::flight::params::FixedWingParams;
use wireflight::flight::spec::EffectSpec;
use wireflight::flight::trim::trim_level;

fn aerosonde(all_effects: bool) -> Model {
    let params = FixedWingParams::aerosonde();
    let mut m = Model::new(Vehicle::FixedWing(Box::new(params)), Origin::default());
    if all_effects {
        let ctx = m.effect_context();
        for info in CATALOGUE {
            let e = info.build(&ctx);
            if e.applies_to(VehicleKind::FixedWing) {
                m.add_effect(e).unwrap();
            }
        }
        for (name, param, value) in [
            ("wind", "north_mps", 3.0),
            ("prop_torque", "k_torque", 0.2),
            ("gyroscopic", "k_gyro", 0.05),
        ] {
            m.effect_mut(name).unwrap().set_param(param, value).unwrap();
        }
    }
    m
}

/// The baseline with one term, `m = k*thrust` (k = 0.01 N·m/N): read and compiled once, here.
fn aerosonde_with_term() -> Model {
    let mut m = aerosonde(false);
    let spec = EffectSpec::parse("term(m=k*thrust):k=0.01").unwrap();
    let e = spec.build(&m.effect_context()).unwrap();
    m.add_effect(e).unwrap();
    m
}

fn integrator(c: &mut Criterion) {
    let mut group = c.benchmark_group("fixed_wing_rk4");
    group.sample_size(20);
    group.measurement_time(std::time::Duration::from_secs(3));
    for (label, model) in [
        ("baseline", aerosonde(false)),
        ("one term", aerosonde_with_term()),
        ("all effects", aerosonde(true)),
    ] {
        let trim = trim_level(&model, 25.0, 0.0, DVec3::new(0.0, 0.0, -200.0)).unwrap();
        const STEPS: u64 = 10_000;
        group.throughput(Throughput::Elements(STEPS));
        group.bench_function(format!("{label}: steps (dt = 0.01 s)"), |b| {
            b.iter(|| {
                let mut x = trim.state;
                for k in 0..STEPS {
                    x = model.step(k as f64 * 0.01, &x, &trim.controls, 0.01);
                }
                x
            })
        });
    }
    let model = aerosonde(true);
    let trim = trim_level(&model, 25.0, 0.0, DVec3::new(0.0, 0.0, -200.0)).unwrap();
    group.throughput(Throughput::Elements(1));
    group.sample_size(10);
    group.bench_function("one hour at 100 Hz, all effects", |b| {
        b.iter(|| model.advance(0.0, &trim.state, &trim.controls, 3600.0, 0.01))
    });
    group.finish();
}

criterion_group!(benches, integrator);
criterion_main!(benches);
