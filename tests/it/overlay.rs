//! The comparison overlay of the replay: the model's aircraft and trail beside the measured
//! ones, and the error strip. With the missing effect added, the model's aircraft flies on
//! top of the measured one; without it, it drifts away.

use glam::Vec2;

use wireflight::analysis::compare::{compare, CompareConfig};
use wireflight::clip::Clipper;
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelSpec};
use wireflight::flight::VehicleKind;
use wireflight::mesh::plane::builtin_plane;
use wireflight::pipeline::Viewport;
use wireflight::render::{cpu, Image, Rgba};
use wireflight::scene::palette::{self, ERROR_STRIP, MODEL_AIRCRAFT, TRAIL};
use wireflight::scene::replay::ReplayScene;
use wireflight::scene::track::ModelTrack;

const VIEW: Viewport = Viewport {
    width: 480,
    height: 360,
};

/// Centroid of the pixels of one colour, and how many there are.
fn pixels_of(image: &Image, color: Rgba) -> (Vec2, usize) {
    let mut sum = Vec2::ZERO;
    let mut n = 0;
    for (k, p) in image.pixels.chunks_exact(4).enumerate() {
        if p == color {
            sum += Vec2::new(
                (k as u32 % image.width) as f32,
                (k as u32 / image.width) as f32,
            );
            n += 1;
        }
    }
    (sum / n.max(1) as f32, n)
}

#[test]
fn model_aircraft_drifts_without_the_effect_and_flies_on_top_with_it() {
    let base = ModelSpec::baseline(VehicleKind::FixedWing);
    let mut truth = base.clone();
    truth
        .effects
        .push(EffectSpec::parse("wind:north_mps=6,east_mps=-4").unwrap());
    let spec = SimSpec {
        noise: Noise {
            pos_m: 0.2,
            att_deg: 0.1,
            vel_mps: 0.05,
            rate_dps: 0.2,
        },
        seed: 5,
        ..SimSpec::new(Manoeuvre::ClimbingTurn, 30.0)
    };
    let data = simulate(&truth.build(Origin::default()).unwrap(), &spec).unwrap();
    let mesh = builtin_plane();
    let cfg = CompareConfig {
        window_s: 10.0,
        ..CompareConfig::default()
    };

    // Late in a window (t = 19 s: 9 s after the restart at 10 s) the models have drifted most.
    let gap_at = |model_spec: &ModelSpec| {
        let model = model_spec.build(Origin::default()).unwrap();
        let comparison = compare(&model, &data, cfg);
        let track = ModelTrack::from_comparison(&data, &comparison).unwrap();
        assert_eq!(track.window_starts, [0, 500, 1000]);
        let mut scene = ReplayScene::new(&data, &mesh, Clipper::Blinn)
            .unwrap()
            .with_model(track);
        let (lines, _) = scene.frame(19.0, VIEW);
        let image = cpu::render(lines);
        let (measured, n_measured) = pixels_of(&image, palette::AIRCRAFT);
        let (modelled, n_modelled) = pixels_of(&image, MODEL_AIRCRAFT);
        let (_, n_strip) = pixels_of(&image, ERROR_STRIP);
        let (_, n_trail) = pixels_of(&image, TRAIL);
        assert!(
            n_measured > 50 && n_trail > 20 && n_strip > 100,
            "{n_measured} {n_trail} {n_strip}"
        );
        (measured.distance(modelled), n_modelled)
    };
    let (gap_baseline, n_baseline) = gap_at(&base);
    let mut with_wind = base.clone();
    with_wind
        .effects
        .push(EffectSpec::parse("wind:north_mps=6,east_mps=-4").unwrap());
    let (gap_wind, n_wind) = gap_at(&with_wind);
    eprintln!("model aircraft {gap_baseline:.1} px from the measured one without wind, {gap_wind:.1} px with");
    // Without wind the model's aircraft is off to one side (or out of the frame entirely).
    assert!(
        n_baseline == 0 || gap_baseline > 40.0,
        "{gap_baseline} px, {n_baseline} pixels"
    );
    assert!(n_wind > 50, "the model aircraft is drawn ({n_wind} pixels)");
    assert!(
        gap_wind < 8.0,
        "with wind the model flies on top of the data: {gap_wind} px"
    );
}
