//! `discover` on a point mass: the acceleration it lacks on the axes its force terms act along.
//!
//! A point mass has no body, attitude or moments: its equations of motion are its NED
//! acceleration, gravity plus its effects'. What it lacks is the measured acceleration (the
//! smoothing differentiator of the NED velocity) less the model's at the same position and
//! velocity, smoothed alike; it is read on the axes a point-mass force term acts along
//! ([`wireflight_flight::aero::flight_path_axes`]: `X` along the air-relative velocity, `Y`
//! level to its right, `Z` downward normal to it), so that what is found is a term a point
//! mass takes (`--add 'term:Z=k*qbar'`). The values are accelerations (m/s²): a point mass's
//! mass is 1.
//!
//! The regressors are what a point mass has ([`library::point_mass`]): its airspeed, the
//! dynamic pressure and density as the model has them, and its height. Where the flight
//! recorded the body's attitude, the model reads the body's angles of attack and sideslip
//! from it and its force terms act along the wind axes that body defines
//! ([`Model::point_mass_air`]: `Z` normal to the velocity in the body's x–z plane, its lift
//! negative, `Y` its side): the axes are those, and the library adds q̄ times the angles in
//! the forms a body's lift and side force take ([`library::point_mass_with_incidence`]), so
//! that what is found is a term the same point mass takes (`--add 'term:Y=k*qbar*beta'`).

use wireflight_data::derive::{Differentiator, Window};
use wireflight_data::{Channel, Controls, FlightData};
use wireflight_flight::expr::{Axis, Var, VarValues, N_VARS};
use wireflight_flight::model::{Model, State};

use super::{
    held_integral, library, regression_rows, select_terms, AxisTarget, DiscoverError, Discovery,
    MIN_SAMPLES,
};

/// The forces a point mass can lack, on its flight-path axes (or a recorded body's wind axes).
const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

/// [`super::discover`] for a point mass (module docs).
pub(super) fn discover(model: &Model, data: &FlightData) -> Result<Discovery, DiscoverError> {
    let too_few = DiscoverError::TooFewPointMassSamples;
    let Some(vel) = data.vel_ned.as_ref().filter(|v| v.len() == data.len()) else {
        return Err(too_few(0));
    };
    let n_all = data.len();
    let half = Window::default().half_samples(&data.time);
    if n_all < MIN_SAMPLES || n_all <= 2 * half + MIN_SAMPLES || data.pos_ned.len() != n_all {
        return Err(too_few(n_all.saturating_sub(2 * half)));
    }
    let diff = Differentiator::with_window(&data.time, Window::default());
    if diff.len() != n_all {
        return Err(too_few(0));
    }
    // At each sample: the model's acceleration, the flight-path axes and the variables.
    let cmd = Controls::default();
    let mut model_acc = Vec::with_capacity(n_all);
    let mut axes = Vec::with_capacity(n_all);
    let mut vars: Vec<VarValues> = Vec::with_capacity(n_all);
    for (i, (&t, (&pos, &v))) in data
        .time
        .iter()
        .zip(data.pos_ned.iter().zip(vel))
        .enumerate()
    {
        let mut x = State::default();
        x.set_pos_ned(pos);
        x.set_vel(v);
        let d = model.derivative(t, &x, &cmd).0;
        let (wind, rho) = model.air_at(pos, t);
        let air = v - wind;
        let (air_data, path_axes) = model.point_mass_air(t, air, rho);
        let va = air.length();
        let mut row = [0.0; N_VARS];
        row[Var::Airspeed.index()] = va;
        row[Var::Alpha.index()] = air_data.alpha;
        row[Var::Beta.index()] = air_data.beta;
        row[Var::Qbar.index()] = 0.5 * rho * va * va;
        row[Var::Rho.index()] = rho;
        row[Var::Height.index()] = -pos.z;
        row[Var::G.index()] = wireflight_data::G0;
        if !(d.iter().all(|x| x.is_finite()) && row.iter().all(|x| x.is_finite())) {
            return Err(too_few(i));
        }
        model_acc.push([d[3], d[4], d[5]]);
        axes.push(path_axes);
        vars.push(row);
    }
    // Everything through the same filter, as on a fixed wing: the measured derivative is the
    // smoothed one, and the model's acceleration and the regressors pass through the
    // differentiator of their running integral (no commands: held and at the row agree).
    let smooth = |x: &[f64]| diff.apply(&held_integral(&data.time, x, x));
    let lacking: Vec<Vec<f64>> = (0..3)
        .map(|c| {
            let measured: Vec<f64> = vel.iter().map(|v| v[c]).collect();
            let model: Vec<f64> = model_acc.iter().map(|a| a[c]).collect();
            let (measured, model) = (diff.apply(&measured), smooth(&model));
            measured.iter().zip(&model).map(|(a, b)| a - b).collect()
        })
        .collect();
    let rows = regression_rows(data, half, &[Channel::Velocity]);
    // The NED acceleration lacking at each row, turned to the row's flight-path axes.
    let mut targets: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(rows.len()));
    for &i in &rows {
        let ned = glam::DVec3::new(lacking[0][i], lacking[1][i], lacking[2][i]);
        let path = axes[i].transpose() * ned;
        for (t, v) in targets.iter_mut().zip(path.to_array()) {
            t.push(v);
        }
    }
    let library = if model.has_recorded_attitude() {
        library::point_mass_with_incidence()
    } else {
        library::point_mass()
    };
    // Each regressor as the force it would be along each axis, through the same pipeline as
    // the lacking acceleration: its NED vector smoothed, then turned to the row's axes. The
    // axes turn within the smoothing window (a body's roll turns its wind axes): a scalar
    // smoothed alone would not be what the smoothed, turned acceleration holds of it.
    let columns: Vec<Vec<Vec<f64>>> = (0..AXES.len())
        .map(|a| {
            library
                .iter()
                .map(|r| {
                    let ned: [Vec<f64>; 3] = std::array::from_fn(|c| {
                        let along: Vec<f64> = vars
                            .iter()
                            .zip(&axes)
                            .map(|(v, ax)| r.value(v) * ax.col(a)[c])
                            .collect();
                        smooth(&along)
                    });
                    rows.iter()
                        .map(|&i| {
                            let v = glam::DVec3::new(ned[0][i], ned[1][i], ned[2][i]);
                            axes[i].col(a).dot(v)
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    if targets
        .iter()
        .chain(columns.iter().flatten())
        .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(too_few(0));
    }
    let targets: Vec<AxisTarget> = AXES
        .into_iter()
        .zip(targets)
        .zip(&columns)
        .map(|((axis, y), columns)| AxisTarget { axis, y, columns })
        .collect();
    let mut found = select_terms(&targets, &library, library::point_mass_reading, true);
    found.wind_axes = model.has_recorded_attitude();
    Ok(found)
}
