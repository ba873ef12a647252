//! `discover` on a point mass: the acceleration it lacks along its flight-path axes.
//!
//! A point mass has no body, attitude or moments: its equations of motion are its NED
//! acceleration, gravity plus its effects'. What it lacks is the measured acceleration (the
//! smoothing differentiator of the NED velocity) less the model's at the same position and
//! velocity, smoothed alike; it is read on the axes a point-mass force term acts along
//! ([`flight_path_axes`]: `X` along the air-relative velocity, `Y` level to its right, `Z`
//! downward normal to it), so that what is found is a term a point mass takes
//! (`--add 'term:Z=k*qbar'`). The values are accelerations (m/s²): a point mass's mass is 1.
//!
//! The regressors are what a point mass has ([`library::point_mass`]): its airspeed, the
//! dynamic pressure and density as the model has them, and its height. An angle of attack
//! is not among them: the flight's attitude, where the data carry one, is the body's, which
//! the point mass does not fly, so a term reading it could not be added to it. What it says
//! is reported beside the terms ([`Incidence`]): q̄ times the body's angle to its path, on
//! the side and normal axes — a lift, named, that the effect `incidence_lift` adds to a
//! point mass from the same recorded attitude (its k is this coefficient).

use wireflight_flight::aero::flight_path_axes;
use wireflight_flight::data::FlightData;
use wireflight_flight::derive::{Differentiator, Window};
use wireflight_flight::effects::INCIDENCE_LIFT;
use wireflight_flight::expr::{Axis, Var, VarValues, N_VARS};
use wireflight_flight::model::{Model, State};
use wireflight_flight::Controls;

use super::{
    held_integral, library, regression_rows, select, select_terms, AxisTarget, DiscoverError,
    Discovery, Incidence, MIN_SAMPLES,
};

/// The forces a point mass can lack, on its flight-path axes.
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
        let va = air.length();
        let mut row = [0.0; N_VARS];
        row[Var::Airspeed.index()] = va;
        row[Var::Qbar.index()] = 0.5 * rho * va * va;
        row[Var::Rho.index()] = rho;
        row[Var::Height.index()] = -pos.z;
        row[Var::G.index()] = wireflight_flight::G0;
        if !(d.iter().all(|x| x.is_finite()) && row.iter().all(|x| x.is_finite())) {
            return Err(too_few(i));
        }
        model_acc.push([d[3], d[4], d[5]]);
        axes.push(flight_path_axes(air));
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
    let rows = regression_rows(n_all, half);
    // The NED acceleration lacking at each row, turned to the row's flight-path axes.
    let mut targets: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(rows.len()));
    for &i in &rows {
        let ned = glam::DVec3::new(lacking[0][i], lacking[1][i], lacking[2][i]);
        let path = axes[i].transpose() * ned;
        for (t, v) in targets.iter_mut().zip(path.to_array()) {
            t.push(v);
        }
    }
    let library = library::point_mass();
    let columns: Vec<Vec<f64>> = library
        .iter()
        .map(|r| {
            let at_row: Vec<f64> = vars.iter().map(|v| r.value(v)).collect();
            let sm = smooth(&at_row);
            rows.iter().map(|&i| sm[i]).collect()
        })
        .collect();
    if targets
        .iter()
        .chain(&columns)
        .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(too_few(0));
    }
    let incidence = body_incidence(data, &axes, &vars, &rows, smooth);
    let targets: Vec<AxisTarget> = AXES
        .into_iter()
        .zip(targets)
        .map(|(axis, y)| AxisTarget {
            axis,
            y,
            columns: &columns,
        })
        .collect();
    let mut found = select_terms(&targets, &library, library::point_mass_reading, true);
    if let Some((columns, largest)) = incidence {
        found.incidence = across_the_path(&targets, &columns, largest, found.threshold);
    }
    Ok(found)
}

/// Where the flight carries an attitude: q̄ times the body's x axis across the flight path
/// (its level and its normal component: the sine of the body's angle to its path in each
/// plane), smoothed and at the rows, for `Y` and `Z`; and the largest angle, degrees.
/// None without an attitude, or with one not finite.
fn body_incidence(
    data: &FlightData,
    axes: &[glam::DMat3],
    vars: &[VarValues],
    rows: &[usize],
    smooth: impl Fn(&[f64]) -> Vec<f64>,
) -> Option<([Vec<f64>; 2], f64)> {
    let att = data.attitude.as_ref().filter(|a| a.len() == axes.len())?;
    let mut across: [Vec<f64>; 2] = std::array::from_fn(|_| Vec::with_capacity(att.len()));
    let mut largest: f64 = 0.0;
    for ((e, path), v) in att.iter().zip(axes).zip(vars) {
        let nose = path.transpose() * e.to_matrix().x_axis;
        let qbar = v[Var::Qbar.index()];
        largest = largest.max(nose.x.clamp(-1.0, 1.0).acos().to_degrees());
        across[0].push(qbar * nose.y);
        across[1].push(qbar * nose.z);
    }
    let columns = across.map(|c| {
        let sm = smooth(&c);
        rows.iter().map(|&i| sm[i]).collect::<Vec<f64>>()
    });
    let finite = columns.iter().flatten().all(|v| v.is_finite()) && largest.is_finite();
    finite.then_some((columns, largest))
}

/// The body's incidence tried on the side and normal axes alone, admitted by the selection's
/// own tests (likelihood ratio, material share, held-out fifths).
fn across_the_path(
    targets: &[AxisTarget<'_>],
    columns: &[Vec<f64>; 2],
    largest_deg: f64,
    threshold: f64,
) -> Vec<Incidence> {
    let mut out = Vec::new();
    for (target, column) in targets.iter().skip(1).zip(columns) {
        let sel = select(&target.y, std::slice::from_ref(column), threshold);
        let (Some(step), Some(&coefficient), Some(&sigma)) = (
            sel.steps.first(),
            sel.coefficients.first(),
            sel.sigmas.first(),
        ) else {
            continue;
        };
        out.push(Incidence {
            axis: target.axis,
            coefficient,
            sigma,
            rms_before: step.rms_before,
            rms_after: step.rms_after,
            likelihood_ratio: step.likelihood_ratio,
            largest_deg,
            add: INCIDENCE_LIFT.name,
        });
    }
    out
}
