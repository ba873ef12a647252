//! Writing your own physical effect without touching the library.
//!
//! An effect implements `wireflight::flight::effects::Effect`: a name, optional named
//! parameters, and one or more hooks (wind, density, gravity, world-frame acceleration,
//! body-frame force and moment, induced-drag factor, actuator lag). Here: a **thermal**, a
//! column of rising air of radius `radius_m` around a point, with a smooth Gaussian profile of
//! updraft speed — something the catalogue does not have.
//!
//! Run: `cargo run --example custom_effect`. It flies the Aerosonde straight through the
//! thermal with and without the effect and prints the height gained.

use glam::DVec3;
use wireflight::flight::effects::{Effect, Origin, Param, Sample};
use wireflight::flight::model::{Model, Vehicle};
use wireflight::flight::params::FixedWingParams;
use wireflight::flight::trim::trim_level;
use wireflight::flight::VehicleKind;

/// Rising air around (north_m, east_m): vertical wind −w·exp(−r²/R²) (NED: up is −down).
#[derive(Clone, Debug)]
struct Thermal {
    north_m: f64,
    east_m: f64,
    updraft_mps: f64,
    radius_m: f64,
}

impl Effect for Thermal {
    fn name(&self) -> &str {
        "thermal"
    }
    fn applies_to(&self, v: VehicleKind) -> bool {
        v == VehicleKind::FixedWing
    }
    fn params(&self) -> Vec<Param> {
        vec![
            Param {
                name: "updraft_mps",
                value: self.updraft_mps,
                unit: "m/s",
            },
            Param {
                name: "radius_m",
                value: self.radius_m,
                unit: "m",
            },
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "updraft_mps" => self.updraft_mps = value,
            "radius_m" if value > 0.0 => self.radius_m = value,
            _ => return Err(format!("thermal: bad parameter {name} = {value}")),
        }
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    /// The hooks see the whole state. The catalogue's `wind_ned` hook is for steady, uniform
    /// wind, so this non-uniform updraft is modelled kinematically instead: inside the column
    /// the aircraft's vertical speed relaxes toward the updraft with a 2 s time constant.
    fn accel_ned(&self, s: &Sample) -> DVec3 {
        let d2 = (s.pos_ned.x - self.north_m).powi(2) + (s.pos_ned.y - self.east_m).powi(2);
        let w = self.updraft_mps * (-d2 / (self.radius_m * self.radius_m)).exp();
        DVec3::new(0.0, 0.0, -(w + s.vel_ned.z) / 2.0)
    }
}

fn main() -> anyhow::Result<()> {
    let params = FixedWingParams::aerosonde();
    let base = Model::new(Vehicle::FixedWing(Box::new(params)), Origin::default());
    let mut with_thermal = base.clone();
    with_thermal
        .add_effect(Box::new(Thermal {
            north_m: 300.0,
            east_m: 0.0,
            updraft_mps: 3.0,
            radius_m: 80.0,
        }))
        .map_err(anyhow::Error::msg)?;

    let start = DVec3::new(0.0, 0.0, -200.0);
    for (label, model) in [("baseline", &base), ("with thermal", &with_thermal)] {
        let trim = trim_level(model, 25.0, 0.0, start).map_err(anyhow::Error::msg)?;
        let end = model.advance(0.0, &trim.state, &trim.controls, 24.0, 0.01);
        println!(
            "{label:>13}: effects {:?}, height after 24 s: {:.1} m",
            model.effect_names(),
            -end.pos_ned().z
        );
    }
    Ok(())
}
