use super::*;
use crate::compare::start::Scratch;
use crate::compare::CompareConfig;
use crate::profile::{perturbed_models, window_normal_towards, Normal};
use wireflight_data::VehicleKind;
use wireflight_flight::autopilot::Manoeuvre;
use wireflight_flight::effects::Origin;
use wireflight_flight::numeric::solve_in_place;
use wireflight_flight::simulate::{simulate, Noise, SimSpec};
use wireflight_flight::spec::{EffectSpec, ModelSpec};

/// The airframe, the airframe with the effect `wind` (a spec), and a 45 s flight test of the
/// latter at 50 Hz with survey-grade noise.
fn windy(wind: &str) -> (Model, Model, wireflight_data::FlightData) {
    let airframe = ModelSpec::baseline(VehicleKind::FixedWing)
        .build(Origin::default())
        .unwrap();
    let mut with = airframe.clone();
    let wind = EffectSpec::parse(wind).unwrap();
    with.add_effect(wind.build(&airframe.effect_context()).unwrap())
        .unwrap();
    let spec = SimSpec {
        noise: Noise {
            pos_m: 0.05,
            att_deg: 0.05,
            vel_mps: 0.05,
            rate_dps: 0.2,
        },
        ..SimSpec::new(Manoeuvre::FlightTest, 45.0)
    };
    let data = simulate(&with, &spec).unwrap();
    (airframe, with, data)
}

/// Where the model without a wind starts a window, predicted from the fit of the model
/// with it: within a twentieth of the way from the warm start to the base's own fitted
/// start, in misfit (0.1–2.4% on this flight's six windows; the full pass then fits the
/// base's start from there); and the normal equations are those of `window_normal` all
/// the same.
#[test]
fn the_base_start_predicted_from_a_corrections_fit_is_near_the_base_fit() {
    let (base, with, data) = windy("wind:north_mps=4,east_mps=-3");
    let prep = Prepared::new(&data, CompareConfig::default());
    let free = effect_free(&mut with.clone(), "wind", &[], &prep, false).unwrap();
    let theta = values(&with, &free);
    let perturbed = perturbed_models(&with, &free, &theta);
    // The base is the model with the wind at its absent values (what the full pass moves
    // towards).
    let info = effect(&with, "wind").unwrap().info();
    let absent: Vec<f64> = free
        .iter()
        .map(|f| info.param(f.name).and_then(|p| p.absent).unwrap())
        .collect();
    assert_eq!(absent, vec![0.0; 3]);
    let towards: Vec<f64> = absent
        .iter()
        .zip(&theta)
        .zip(&free)
        .map(|((b, t), f)| (b - t) / f.scale)
        .collect();
    let mut scratch = Scratch::default();
    let sse = |model: &Model, w: (usize, usize), x: &State, scratch: &mut Scratch| {
        let mut r = Vec::new();
        prep.window_residuals(model, w, x, scratch, &mut r);
        r.iter().map(|v| v * v).sum::<f64>()
    };
    for &w in &prep.windows {
        let surfaces = glam::DVec3::ZERO;
        let fit = prep.fit_start(&with, w, prep.warm_start(&with, w, surfaces), &mut scratch);
        let lin = Linearised::of(&with, &fit);
        let plain = crate::profile::window_normal(
            &with,
            (&perturbed, &free, false),
            &prep,
            w,
            &lin,
            Some(&fit.residuals),
        );
        // Flown columns, and the wind's own (its fit being the model's own).
        let mut shares = Vec::new();
        for own in [false, true] {
            let (share, q) = window_normal_towards(
                &with,
                &perturbed,
                &free,
                &prep,
                w,
                &lin,
                Some(&fit.residuals),
                (Some(&towards), own),
            );
            let predicted = crate::compare::start::state_of(&base, &q.unwrap(), surfaces);
            let warm = prep.warm_start(&base, w, surfaces);
            let best = prep.fit_start(&base, w, warm, &mut scratch);
            let best_sse: f64 = best.residuals.iter().map(|v| v * v).sum();
            let (at_warm, at_predicted) = (
                sse(&base, w, &warm, &mut scratch),
                sse(&base, w, &predicted, &mut scratch),
            );
            assert!(
                at_predicted - best_sse < 0.05 * (at_warm - best_sse),
                "window {w:?}, own {own}: χ² {at_predicted:.6e} predicted, {at_warm:.6e} \
                 warm, {best_sse:.6e} fitted"
            );
            shares.push(share);
        }
        assert_eq!(shares[0], plain);
        // The wind's columns are the flown ones: with the Jacobian of differences at the
        // fitted start, where neither is off by the projection's own error (the fit's
        // updated tangent Jacobian projects both to within ~1% of these).
        let q = crate::compare::start::params_of(&with, &fit.state);
        let mut exact = fit.clone();
        prep.difference_jacobian(
            &with,
            w,
            &q,
            fit.state.surfaces(),
            &fit.residuals,
            &mut scratch,
            &mut exact.jacobian,
        );
        let lin = Linearised::of(&with, &exact);
        let [flown, own] = [false, true].map(|own| {
            let r = Some(fit.residuals.as_slice());
            window_normal_towards(&with, &perturbed, &free, &prep, w, &lin, r, (None, own)).0
        });
        assert_wind_columns_are_flown(&flown, &own, w);
    }
    // Beside an effect of height the wind is no longer a moving frame (the drift changes
    // the height): its columns are flown.
    let mut high = with.clone();
    let density = EffectSpec::parse("density_altitude").unwrap();
    high.add_effect(density.build(&base.effect_context()).unwrap())
        .unwrap();
    let w = prep.windows[0];
    let fit = prep.fit_start(
        &high,
        w,
        prep.warm_start(&high, w, glam::DVec3::ZERO),
        &mut scratch,
    );
    let lin = Linearised::of(&high, &fit);
    let perturbed = perturbed_models(&high, &free, &theta);
    let [flown, own] = [false, true].map(|own| {
        let r = Some(fit.residuals.as_slice());
        window_normal_towards(&high, &perturbed, &free, &prep, w, &lin, r, (None, own)).0
    });
    assert_eq!(flown, own);
}

/// The wind's normal equations without flights are the flown ones: the information
/// matrix to 2e-3 of its diagonal (measured: 5.9e-4 at most, the forward differences'
/// and RK4's own error), the Newton step within 0.5% of a standard deviation (0.05%).
fn assert_wind_columns_are_flown(flown: &Normal, own: &Normal, w: (usize, usize)) {
    let np = flown.1.len();
    let (a, b) = (&flown.0, &own.0);
    for i in 0..np {
        for k in 0..np {
            let scale = (a[i * np + i] * a[k * np + k]).sqrt();
            let off = (a[i * np + k] - b[i * np + k]).abs() / scale;
            assert!(
                off < 2e-3,
                "window {w:?} A({i}, {k}): {} vs {}",
                a[i * np + k],
                b[i * np + k]
            );
        }
    }
    let step = |n: &Normal| {
        let mut s = n.1.clone();
        let mut m = n.0.clone();
        solve_in_place(&mut m, &mut s, np).unwrap();
        s
    };
    let (sa, sb) = (step(flown), step(own));
    let cov = invert(a, np).unwrap();
    for i in 0..np {
        let sigma = cov[i * np + i].sqrt();
        let off = (sa[i] - sb[i]).abs() / sigma;
        assert!(
            off < 5e-3,
            "window {w:?} step {i}: {} vs {} (σ {sigma})",
            sa[i],
            sb[i]
        );
    }
}

/// The moving frame changes what a wind's fit costs, not what it finds: fitted on the
/// airframe (its columns without flights, its first round cut to one step) and on the
/// airframe with an inert gyroscopic term (k_gyro = 0: the same equations, every column
/// flown, every round to convergence), the wind agrees to 0.3σ (measured 0.17σ: two fits
/// each stopped within the fit's tolerance), its ± to 5% (0.6%, 2.9%, 1.3%: both
/// project with the fits' updated Jacobians, each ~1% from the differences' in a
/// window) and the misfit left to 2e-4 (8e-5).
#[test]
fn a_wind_fitted_as_a_moving_frame_is_the_wind_fitted_with_flights() {
    let (airframe, truth, data) = windy("wind:north_mps=4,east_mps=-3,down_mps=0.5");
    let prep = Prepared::new(&data, CompareConfig::default());
    let mut inert = airframe.clone();
    let gyro = EffectSpec::parse("gyroscopic:k_gyro=0").unwrap();
    inert
        .add_effect(gyro.build(&airframe.effect_context()).unwrap())
        .unwrap();
    let cfg = DiagnoseConfig::default();
    let [framed, flown] = [&airframe, &inert].map(|base| {
        let before = Baseline::of(base, &prep);
        let wind = wireflight_flight::effects::find("wind")
            .unwrap()
            .build(&base.effect_context());
        try_effect(base, wind, &[], &prep, &before, &cfg, 1).unwrap()
    });
    assert!(moving_frame(&truth, &[]).is_some() && inert.effects.len() == 1);
    for k in 0..3 {
        let (a, b) = (framed.params[k].1, flown.params[k].1);
        let sigma = flown.uncertainty[k];
        assert!((a - b).abs() < 0.3 * sigma, "{k}: {a} vs {b} (σ {sigma})");
        let ratio = framed.uncertainty[k] / sigma;
        assert!(
            (ratio - 1.0).abs() < 0.05,
            "{k}: σ {} vs {sigma}",
            framed.uncertainty[k]
        );
    }
    let (a, b) = (framed.error_after, flown.error_after);
    assert!((a - b).abs() < 2e-4 * b, "misfit left {a} vs {b}");
}

fn comparison(chi2: f64, dof: f64) -> Comparison {
    Comparison {
        total: 1.0,
        channels: Default::default(),
        windows: Vec::new(),
        prediction: Default::default(),
        axes: Vec::new(),
        chi2,
        dof,
        colour_floor: [1.0; crate::compare::MAX_ROWS],
    }
}

/// A number is fitted when four times its score would remove a fifth of the misfit above
/// the noise and pass the likelihood-ratio test; never without misfit above the noise.
#[test]
fn only_numbers_that_could_be_significant_are_fitted() {
    let cfg = DiagnoseConfig::default();
    // Twelve times the noise: χ²/ν = 144 over 10⁴ residuals, an excess of 11 noise units.
    let far = comparison(1.44e6, 1e4);
    // A fifth of the excess: the noise units fall from 12 to 9.8, χ² to 9.6e5.
    let needed = (1.44e6 - 9.8f64.powi(2) * 1e4) / SCORE_ALLOWANCE;
    assert!(could_be_significant(&far, 1.05 * needed, &cfg, 30));
    assert!(!could_be_significant(&far, 0.95 * needed, &cfg, 30));
    assert!(!could_be_significant(&far, 0.0, &cfg, 30));
    assert!(!could_be_significant(&far, f64::NAN, &cfg, 30));
    // At the noise (and below it) nothing could be material.
    assert!(!could_be_significant(&comparison(1e4, 1e4), 5e3, &cfg, 30));
    assert!(!could_be_significant(
        &comparison(0.9e4, 1e4),
        5e3,
        &cfg,
        30
    ));
    // Just above the noise a material reduction is small, but the test must be passed:
    // 1.1 × noise over 100 residuals is an excess of 21 χ² units.
    let near = comparison(121.0, 100.0);
    assert!(could_be_significant(&near, 20.0, &cfg, 30));
    assert!(!could_be_significant(&near, 0.5, &cfg, 30));
}
