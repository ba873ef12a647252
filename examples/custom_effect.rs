//! Writing your own physical effect without touching the library.
//!
//! An effect is a type implementing `wireflight::flight::effects::Effect` plus a static
//! `EffectInfo`: its name, the vehicles it applies to, and each parameter's metadata (unit,
//! valid range, typical size for fitting). `effect_basics!` writes the parts every effect
//! writes the same way (the info, where the parameter values are stored, what they do not vary
//! with); the hooks it needs do the physics; everything else (checking `set_param`, fitting,
//! display) works from the metadata. A catalogue effect is exactly this, as one file in
//! `crates/flight/src/effects/` plus one line in `CATALOGUE`.
//!
//! Here: a **thermal**, a column of rising air of radius `radius_m` around a point, with a
//! Gaussian profile of updraft speed — wind that depends on position, which the catalogue's
//! steady `wind` cannot express.
//!
//! Run: `cargo run --release --example custom_effect`. It flies the Aerosonde straight
//! through the thermal with and without the effect and prints the height gained; then it
//! records a flight through a hidden thermal and lets `diagnose` find it among the catalogue.

use glam::DVec3;
use wireflight::analysis::diagnose::{diagnose, DiagnoseConfig};
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::{
    effect_basics, Applies, Effect, EffectContext, EffectInfo, Origin, ParamSpec,
};
use wireflight::flight::model::{Model, Vehicle};
use wireflight::flight::params::FixedWingParams;
use wireflight::flight::simulate::{simulate, SimSpec};
use wireflight::flight::trim::trim_level;

/// The thermal's metadata: two parameters, both fittable.
static THERMAL: EffectInfo = EffectInfo {
    name: "thermal",
    summary: "a Gaussian column of rising air at (300 m N, 0 m E)",
    applies: Applies::FixedWing,
    params: &[
        ParamSpec::new("updraft_mps", "m/s", (-20.0, 20.0), 1.0),
        ParamSpec::new("radius_m", "m", (5.0, 2000.0), 20.0),
    ],
    make: |_: &EffectContext| {
        Box::new(Thermal {
            values: [0.0, 80.0],
        })
    },
};

/// Rising air around (300 m north, 0 m east): wind (0, 0, −w·exp(−r²/R²)) NED (up is −down).
#[derive(Clone, Debug)]
struct Thermal {
    /// `[updraft_mps, radius_m]`, in the order of `THERMAL.params`.
    values: [f64; 2],
}

impl Effect for Thermal {
    // The column stands still: the wind depends on where, not when.
    effect_basics! {
        info: THERMAL,
        values: values,
        varies_in_time: false,
    }
    fn wind_at(&self, pos_ned: DVec3, _t: f64) -> DVec3 {
        let [updraft, radius] = self.values;
        let d2 = (pos_ned.x - 300.0).powi(2) + pos_ned.y.powi(2);
        DVec3::new(0.0, 0.0, -updraft * (-d2 / (radius * radius)).exp())
    }
}

fn main() -> anyhow::Result<()> {
    let params = FixedWingParams::aerosonde();
    let base = Model::new(Vehicle::FixedWing(Box::new(params)), Origin::default());
    let mut thermal = THERMAL.build(&base.effect_context());
    thermal.set_param("updraft_mps", 3.0)?;
    let mut with_thermal = base.clone();
    with_thermal.add_effect(thermal)?;

    let start = DVec3::new(0.0, 0.0, -200.0);
    for (label, model) in [("baseline", &base), ("with thermal", &with_thermal)] {
        let trim = trim_level(model, 25.0, 0.0, start)?;
        let end = model.advance(0.0, &trim.state, &trim.controls, 24.0, 0.01);
        println!(
            "{label:>13}: effects {:?}, height after 24 s: {:.1} m",
            model.effect_names(),
            -end.pos_ned().z
        );
    }

    // A level flight through the hidden thermal, diagnosed with the thermal as a candidate
    // beside the catalogue.
    let flight = simulate(&with_thermal, &SimSpec::new(Manoeuvre::Level, 30.0))?;
    let candidate = THERMAL.build(&base.effect_context());
    let d = diagnose(&base, &flight, &[candidate], &DiagnoseConfig::default())
        .map_err(anyhow::Error::msg)?;
    println!(
        "diagnosis of a flight through a hidden thermal: {}",
        d.verdict
    );
    for c in d
        .ranking
        .iter()
        .filter(|c| c.effect == "thermal" || c.effect.starts_with("aircraft:c_m_q"))
    {
        println!(
            "  {:<22} error {:.4} → {:.4} ({:.2} × noise) {:?}",
            c.effect, c.error_before, c.error_after, c.noise_units_after, c.params
        );
    }
    Ok(())
}
