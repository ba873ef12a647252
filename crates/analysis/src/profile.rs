//! The misfit of a model on prepared flight data, profiled over every window's start state:
//! the machinery shared by fitting one candidate (`diagnose::fit`) and identifying many
//! numbers (`identify`).
//!
//! The profile is linearised around fitted starts (variable projection): the change of a
//! window's residuals with a parameter, less what a change of the start could absorb. Normal
//! equations are summed over windows in parallel; no window's Jacobian outlives its turn.
//! The parameters are `free`'s; the step taken on these equations is `lm`'s.

use std::borrow::Cow;

use glam::DVec3;
use rayon::prelude::*;

use crate::compare::start::{
    param_count, params_of, project_column, project_out, state_of, Scratch, StartFit,
};
use crate::compare::Prepared;
use crate::free::{set_values, Free, Owner};
use wireflight_flight::model::{Model, State};
use wireflight_flight::numeric::{axpy, dot, gram, solve_in_place};

/// One window's start state and the linearisation of its residuals around it: what a change
/// of the start can absorb (the columns of `jac`), projected out of every residual change.
///
/// The Jacobian is borrowed from the start fit while that lives on (a baseline's, shared by
/// every candidate), or owned when the fit is spent: a window's Jacobian is a megabyte at
/// 100 Hz, and copying one per candidate and window cost more than the arithmetic on it.
pub(crate) struct Linearised<'a> {
    pub(crate) q: Vec<f64>,
    surfaces: DVec3,
    pub(crate) jac: Cow<'a, [f64]>,
    gram: Vec<f64>,
    pub(crate) params: usize,
}

impl<'a> Linearised<'a> {
    /// The linearisation of a start fit, borrowing its Jacobian.
    pub(crate) fn of(model: &Model, fit: &'a StartFit) -> Self {
        Self::with(model, fit, Cow::Borrowed(&fit.jacobian))
    }

    fn with(model: &Model, fit: &StartFit, jac: Cow<'a, [f64]>) -> Self {
        let m = fit.residuals.len();
        let np = fit.params;
        Self {
            q: params_of(model, &fit.state),
            surfaces: fit.state.surfaces(),
            gram: gram(&jac, np, m),
            jac,
            params: np,
        }
    }
}

impl Linearised<'static> {
    /// The linearisation of a start fit that is spent, taking its Jacobian.
    pub(crate) fn owned(model: &Model, mut fit: StartFit) -> Self {
        let jac = std::mem::take(&mut fit.jacobian);
        Self::with(model, &fit, Cow::Owned(jac))
    }
}

impl Linearised<'_> {
    /// Project the start directions out of each column of `cols` ([`project_out`]).
    pub(crate) fn project_out(&self, cols: &mut [f64], m: usize) {
        project_out(&self.jac, &self.gram, self.params, cols, m);
    }

    /// The start parameters whose change from this start absorbs what it can of `r` (another
    /// model's residuals at this start), to first order: q − (JᵀJ)⁻¹Jᵀr. `r` is left
    /// projected.
    pub(crate) fn start_absorbing(&self, r: &mut [f64]) -> Vec<f64> {
        let dq = self.project(r);
        self.q.iter().zip(&dq).map(|(q, d)| q + d).collect()
    }

    pub(crate) fn state(&self, model: &Model) -> State {
        state_of(model, &self.q, self.surfaces)
    }

    /// The products d̃ᵀr and d̃ᵀd̃ of d's part that no start change can absorb, d̃ = d −
    /// J·(JᵀJ)⁻¹Jᵀd, without forming it: d̃ᵀr = dᵀr − (Jᵀd)ᵀ(JᵀJ)⁻¹Jᵀr and d̃ᵀd̃ = dᵀd −
    /// (Jᵀd)ᵀ(JᵀJ)⁻¹Jᵀd — twelve dot products with d where the projection takes twelve more
    /// passes to subtract. `jtr`: Jᵀr. A d that a start change absorbs all but a
    /// hundred-millionth of (in d̃ᵀd̃/dᵀd, beyond what the subtraction resolves) gives (0, 0):
    /// it explains nothing. Without a Jacobian, d's own products.
    pub(crate) fn projected_products(&self, d: &[f64], r: &[f64], jtr: &[f64]) -> (f64, f64) {
        let (np, m) = (self.params, d.len());
        let (dr, dd) = (dot(d, r), dot(d, d));
        if np == 0 || self.jac.len() != np * m || jtr.len() != np {
            return (dr, dd);
        }
        let jtd = self.jt(d);
        let mut y = jtd.clone();
        let mut g = self.gram.clone();
        if solve_in_place(&mut g, &mut y, np).is_none() {
            return (dr, dd);
        }
        let (dr_p, dd_p) = (dr - dot(&y, jtr), dd - dot(&y, &jtd));
        if dd_p > 1e-8 * dd {
            (dr_p, dd_p)
        } else {
            (0.0, 0.0)
        }
    }

    /// Jᵀr, for [`projected_products`](Self::projected_products).
    pub(crate) fn jt(&self, r: &[f64]) -> Vec<f64> {
        let m = r.len();
        if self.params == 0 || self.jac.len() != self.params * m {
            return Vec::new();
        }
        self.jac.chunks(m).map(|col| dot(col, r)).collect()
    }

    /// Replace `r` by what no start change can absorb, r − J·(JᵀJ)⁻¹Jᵀr, and return the start
    /// change that absorbs the rest, −(JᵀJ)⁻¹Jᵀr.
    fn project(&self, r: &mut [f64]) -> Vec<f64> {
        let (np, m) = (self.params, r.len());
        if np == 0 || self.jac.len() != np * m {
            return vec![0.0; np];
        }
        match project_column(&self.jac, &self.gram, np, r) {
            Some(y) => y.iter().map(|v| -v).collect(),
            None => vec![0.0; np],
        }
    }
}

/// The profiled misfit in the linearisation at the model's parameters: χ² of the projected
/// residuals of every window, each window's start change, and each window's residuals as
/// flown from its start (before projection: the model's own residuals at `lin`'s starts,
/// which [`normal_equations`] can take instead of flying them again).
pub(crate) fn linear_profile(
    model: &Model,
    prep: &Prepared,
    lin: &[Linearised],
) -> (f64, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let parts: Vec<(f64, Vec<f64>, Vec<f64>)> = prep
        .windows
        .par_iter()
        .zip(lin.par_iter())
        .map(|(&w, l)| {
            let mut scratch = Scratch::default();
            let mut r = Vec::new();
            prep.window_residuals(
                model,
                prep.fit_range(w),
                &l.state(model),
                &mut scratch,
                &mut r,
            );
            let flown = r.clone();
            let dq = l.project(&mut r);
            (r.iter().map(|v| v * v).sum(), dq, flown)
        })
        .collect();
    let chi2 = parts.iter().map(|p| p.0).sum();
    let mut dq = Vec::with_capacity(parts.len());
    let mut flown = Vec::with_capacity(parts.len());
    for (_, d, r) in parts {
        dq.push(d);
        flown.push(r);
    }
    (chi2, dq, flown)
}

/// Forward-difference step of the parameters, in units of each one's scale.
const PARAM_STEP: f64 = 0.01;

/// The model with each free parameter in turn moved by one difference step.
pub(crate) fn perturbed_models(model: &Model, free: &[Free], theta: &[f64]) -> Vec<Model> {
    (0..free.len())
        .map(|j| {
            let mut m = model.clone();
            let mut t = theta.to_vec();
            t[j] += PARAM_STEP * free[j].scale;
            set_values(&mut m, free, &t);
            m
        })
        .collect()
}

/// Normal equations (A row-major, g), of one window or summed over windows.
pub(crate) type Normal = (Vec<f64>, Vec<f64>);

/// One window's share of the normal equations: A = D̃ᵀD̃ and g = D̃ᵀr, D̃ the change of the
/// residuals per scaled parameter with the start directions projected out. `at_start`: the
/// window's residuals of `model` from `l`'s start when they are at hand (a start fit's own),
/// saving that flight.
pub(crate) fn window_normal(
    model: &Model,
    (perturbed, free, own): (&[Model], &[Free], bool),
    prep: &Prepared,
    window: (usize, usize),
    l: &Linearised,
    at_start: Option<&[f64]>,
) -> Normal {
    window_normal_towards(
        model,
        perturbed,
        free,
        prep,
        window,
        l,
        at_start,
        (None, own),
    )
    .0
}

/// The NED axis of each free parameter where the model is a moving frame — the airframe (or
/// point mass) with a steady, uniform wind alone ([`Effect::is_uniform_wind`]) — and every
/// free parameter is a component of that wind ([`wind_columns`]); None otherwise.
pub(crate) fn moving_frame(model: &Model, free: &[Free]) -> Option<Vec<usize>> {
    let [wind] = model.effects.as_slice() else {
        return None;
    };
    if !wind.is_uniform_wind() || wind.varies_in_space() || wind.varies_in_time() {
        return None;
    }
    let params = wind.info().params;
    free.iter()
        .map(|f| match f.owner {
            Owner::Effect(name) if name == wind.name() => params
                .iter()
                .position(|p| p.name == f.name)
                .filter(|&axis| axis < 3),
            _ => None,
        })
        .collect()
}

/// A steady, uniform wind's columns of the normal equations without a flight, where the
/// model is the airframe (or point mass) with that wind alone and `l` its own start fit of
/// `m` residuals over `span`: None otherwise, or when a free parameter is not the wind's.
///
/// Such a wind is a moving frame. The flight from start velocity v₀ in wind W and the one
/// from v₀ + δW in wind W + δW move the same through the air — the same air-relative
/// velocity, attitude and rates — and differ by δW·t in position and δW in velocity over
/// the ground (Galilean invariance; RK4 keeps it to its truncation error). So the residuals
/// change per wind component by E − J_v: E that drift of the position and velocity rows
/// ([`Prepared::drift_rows`]), J_v the start Jacobian's column of that velocity component.
/// What the normal equations take is the columns with the start directions projected out,
/// among which J_v lies: the projected columns are E's. These and the flown ones are both
/// projected with the fit's Jacobian: with one of forward differences they agree to 6e-4,
/// with the fit's updated tangent one each is within ~1% of that (tests).
fn wind_columns(
    model: &Model,
    free: &[Free],
    prep: &Prepared,
    span: (usize, usize),
    l: &Linearised,
    m: usize,
) -> Option<Vec<f64>> {
    let axes = moving_frame(model, free)?;
    let starts = param_count(model);
    if l.params != starts || l.jac.len() != starts * m || starts < 6 {
        return None;
    }
    let mut cols = vec![0.0; free.len() * m];
    for ((f, col), axis) in free.iter().zip(cols.chunks_exact_mut(m.max(1))).zip(axes) {
        if !prep.drift_rows(model, span, axis, col) {
            return None;
        }
        // Start parameters 3..6 are the NED velocity.
        let j_v = &l.jac[(3 + axis) * m..(4 + axis) * m];
        for (c, v) in col.iter_mut().zip(j_v) {
            *c = f.scale * (*c - v);
        }
    }
    Some(cols)
}

/// [`window_normal`], and where the window's start would be with the parameters moved by
/// `towards` (scaled, one per parameter), to first order: the start parameters that absorb
/// what they can of the residuals r + D·towards (D before projection), `l.q` −
/// (JᵀJ)⁻¹Jᵀ(r + D·towards). None without `towards`, or when a flight does not fit.
///
/// With `towards` the change to the model without a correction (an effect's parameters to
/// their absent values, a number back to the set's), it predicts that model's fitted start
/// from the corrected one's: far closer than the warm start when the model lacks what the
/// correction adds (the base model's start is pulled away from the data's to make up for
/// it), and at no flight more, the columns being the normal equations' own.
///
/// `own`: `l` is `model`'s own start fit, its Jacobian the model's at `l`'s start. A wind's
/// columns then need no flight ([`wind_columns`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn window_normal_towards(
    model: &Model,
    perturbed: &[Model],
    free: &[Free],
    prep: &Prepared,
    window: (usize, usize),
    l: &Linearised,
    at_start: Option<&[f64]>,
    (towards, own): (Option<&[f64]>, bool),
) -> (Normal, Option<Vec<f64>>) {
    let np = perturbed.len();
    let nothing = || ((vec![0.0; np * np], vec![0.0; np]), None);
    let span = prep.fit_range(window);
    let mut scratch = Scratch::default();
    let x = l.state(model);
    let mut flown = Vec::new();
    let r = match at_start {
        Some(r) if !r.is_empty() => r,
        _ => {
            prep.window_residuals(model, span, &x, &mut scratch, &mut flown);
            &flown
        }
    };
    let m = r.len();
    let wind = own
        .then(|| wind_columns(model, free, prep, span, l, m))
        .flatten()
        .filter(|_| free.len() == np);
    let cols = match wind {
        Some(cols) => cols,
        None => {
            let mut cols = vec![0.0; np * m];
            let mut rj = Vec::with_capacity(m);
            for (j, pm) in perturbed.iter().enumerate() {
                prep.window_residuals(pm, span, &x, &mut scratch, &mut rj);
                if rj.len() != m {
                    return nothing();
                }
                for ((c, a), b) in cols[j * m..(j + 1) * m].iter_mut().zip(&rj).zip(r) {
                    *c = (a - b) / PARAM_STEP;
                }
            }
            cols
        }
    };
    let mut cols = cols;
    let start = towards.filter(|t| t.len() == np).map(|t| {
        let mut target = r.to_vec();
        for (j, tj) in t.iter().enumerate() {
            axpy(*tj, &cols[j * m..(j + 1) * m], &mut target);
        }
        l.start_absorbing(&mut target)
    });
    l.project_out(&mut cols, m);
    // D̃ is orthogonal to the start directions, so D̃ᵀr = D̃ᵀr̃.
    let g = (0..np).map(|i| dot(&cols[i * m..(i + 1) * m], r)).collect();
    ((gram(&cols, np, m), g), start)
}

/// Add one share of the normal equations (a window's, a flight's) to a sum.
pub(crate) fn add_into(sum: &mut Normal, part: &Normal) {
    sum.0.iter_mut().zip(&part.0).for_each(|(s, v)| *s += v);
    sum.1.iter_mut().zip(&part.1).for_each(|(s, v)| *s += v);
}

/// Normal equations of the profiled misfit in the scaled free parameters, summed over windows
/// (see [`window_normal`]). `at_starts`: each window's residuals of `model` from `lin`'s
/// starts, when they are at hand ([`linear_profile`]'s, or the start fits' own). `own`:
/// `lin` are `model`'s own start fits ([`window_normal_towards`]).
pub(crate) fn normal_equations(
    model: &Model,
    (free, own): (&[Free], bool),
    theta: &[f64],
    prep: &Prepared,
    lin: &[Linearised],
    at_starts: Option<&[Vec<f64>]>,
) -> Normal {
    normal_equations_by_window(model, (free, own), theta, prep, lin, at_starts).0
}

/// [`normal_equations`], and each window's gradient share D̃ᵀr (for the windows' scatter:
/// [`crate::diagnose`]'s sandwich covariance).
pub(crate) fn normal_equations_by_window(
    model: &Model,
    (free, own): (&[Free], bool),
    theta: &[f64],
    prep: &Prepared,
    lin: &[Linearised],
    at_starts: Option<&[Vec<f64>]>,
) -> (Normal, Vec<Vec<f64>>) {
    let np = free.len();
    let perturbed = perturbed_models(model, free, theta);
    let parts: Vec<Normal> = prep
        .windows
        .par_iter()
        .zip(lin.par_iter())
        .enumerate()
        .map(|(k, (&w, l))| {
            let r = at_starts.and_then(|r| r.get(k)).map(|r| r.as_slice());
            window_normal(model, (&perturbed, free, own), prep, w, l, r)
        })
        .collect();
    let mut sum = (vec![0.0; np * np], vec![0.0; np]);
    for p in &parts {
        add_into(&mut sum, p);
    }
    (sum, parts.into_iter().map(|p| p.1).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The products of the projected column, taken without forming it, are those of the
    /// projection itself; a column inside the start directions gives none.
    #[test]
    fn projected_products_are_those_of_the_projected_column() {
        let (np, m) = (3, 50);
        let jac: Vec<f64> = (0..np * m)
            .map(|i| ((i * 7919 % 101) as f64 - 50.0) / 25.0)
            .collect();
        let fit = StartFit {
            state: State::default(),
            iterations: 1,
            jacobian: jac.clone(),
            residuals: (0..m).map(|i| (i as f64 * 0.37).sin()).collect(),
            params: np,
        };
        let model =
            wireflight_flight::spec::ModelSpec::baseline(wireflight_data::VehicleKind::PointMass)
                .build(wireflight_flight::effects::Origin::default())
                .unwrap();
        let lin = Linearised::of(&model, &fit);
        let r = &fit.residuals;
        let jtr = lin.jt(r);
        let d: Vec<f64> = (0..m)
            .map(|i| (i as f64 * 0.11).cos() + 0.01 * i as f64)
            .collect();
        let mut projected = d.clone();
        lin.project_out(&mut projected, m);
        let (dr, dd) = lin.projected_products(&d, r, &jtr);
        let (want_dr, want_dd) = (dot(&projected, r), dot(&projected, &projected));
        assert!(
            (dr - want_dr).abs() < 1e-10 * want_dr.abs().max(1.0),
            "{dr} vs {want_dr}"
        );
        assert!((dd - want_dd).abs() < 1e-10 * want_dd, "{dd} vs {want_dd}");
        // A combination of the start directions: absorbed entirely.
        let inside: Vec<f64> = (0..m).map(|i| 2.0 * jac[i] - jac[m + i]).collect();
        assert_eq!(lin.projected_products(&inside, r, &jtr), (0.0, 0.0));
    }
}
