//! The comparison overlay of the replay: the model's aircraft and trail beside the measured
//! ones, and the error strip. With the missing effect added, the model's aircraft flies on
//! top of the measured one; without it, it drifts away.

use glam::Vec2;

use wireflight::analysis::compare::{compare, CompareConfig};
use wireflight::data::VehicleKind;
use wireflight::draw::render::{cpu, Image, Rgba};
use wireflight::draw::scene::palette::{self, ERROR_STRIP, MODEL_AIRCRAFT, TRAIL};
use wireflight::draw::scene::replay::ReplayScene;
use wireflight::flight::autopilot::Manoeuvre;
use wireflight::flight::effects::Origin;
use wireflight::flight::simulate::{simulate, Noise, SimSpec};
use wireflight::flight::spec::{EffectSpec, ModelSpec};
use wireflight::geometry::clip::Clipper;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::Viewport;
use wireflight::present::track::model_track;

const VIEW: Viewport = Viewport {
    width: 480,
    height: 360,
};

/// Centroid of the pixels of one colour, and how many there are, between the text of the top
/// corners (the legend's swatches are in the aircraft's colours) and the strip.
fn pixels_of(image: &Image, color: Rgba) -> (Vec2, usize) {
    let mut sum = Vec2::ZERO;
    let mut n = 0;
    let rows = 80..(image.height * 7 / 10);
    for (k, p) in image.pixels.chunks_exact(4).enumerate() {
        if p == color && rows.contains(&(k as u32 / image.width)) {
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
        let track = model_track(&data, &comparison).unwrap();
        assert_eq!(track.window_starts, [0, 500, 1000]);
        let mut scene = ReplayScene::new(&data, &mesh, Clipper::Blinn)
            .unwrap()
            .with_model(track);
        let (lines, _) = scene.frame(19.0, VIEW);
        let image = cpu::render(lines);
        let (measured, n_measured) = pixels_of(&image, palette::AIRCRAFT);
        let (modelled, n_modelled) = pixels_of(&image, MODEL_AIRCRAFT);
        let n_strip = image
            .pixels
            .chunks_exact(4)
            .skip((VIEW.width * VIEW.height * 7 / 10) as usize)
            .filter(|p| *p == ERROR_STRIP)
            .count();
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

/// Every comparison frame explains itself: a legend top right with a swatch of each aircraft's
/// colour, the time and attitude top left, the speed and altitude top right, and no line of
/// the 3D drawing under any text or under the strip.
#[test]
fn comparison_frames_have_a_legend_and_no_text_over_the_drawing() {
    let base = ModelSpec::baseline(VehicleKind::FixedWing);
    let mut truth = base.clone();
    truth
        .effects
        .push(EffectSpec::parse("wind:north_mps=6,east_mps=-4").unwrap());
    let spec = SimSpec {
        seed: 3,
        ..SimSpec::new(Manoeuvre::ClimbingTurn, 16.0)
    };
    let data = simulate(&truth.build(Origin::default()).unwrap(), &spec).unwrap();
    let cfg = CompareConfig {
        window_s: 8.0,
        ..CompareConfig::default()
    };
    let comparison = compare(&base.build(Origin::default()).unwrap(), &data, cfg);
    let track = model_track(&data, &comparison).unwrap();
    let mut scene = ReplayScene::new(&data, &builtin_plane(), Clipper::Blinn)
        .unwrap()
        .with_model(track);
    let drawing = [
        palette::GRID,
        palette::TRAIL,
        palette::AIRCRAFT,
        palette::MODEL_AIRCRAFT,
        palette::MODEL_TRAIL,
        palette::SAMPLE_DOTS,
    ];
    for t in [0.5, 6.0, 12.0, 15.5] {
        let (lines, _) = scene.frame(t, VIEW);
        let image = cpu::render(lines);
        let at = |x: u32, y: u32| -> Rgba {
            let k = 4 * (y * image.width + x) as usize;
            image.pixels[k..k + 4].try_into().unwrap()
        };
        // The text of each top corner: the bounding box of the text-coloured pixels there.
        let (w, h) = (image.width, image.height);
        for (xs, name) in [(0..w / 2, "left"), (w / 2..w, "right")] {
            let mut lo = (u32::MAX, u32::MAX);
            let mut hi = (0, 0);
            for y in 0..h / 4 {
                for x in xs.clone() {
                    if at(x, y) == palette::TEXT {
                        lo = (lo.0.min(x), lo.1.min(y));
                        hi = (hi.0.max(x), hi.1.max(y));
                    }
                }
            }
            assert!(
                hi.0 > lo.0 + 40 && hi.1 > lo.1 + 15,
                "t {t}: no {name} text"
            );
            for y in lo.1..=hi.1 {
                for x in lo.0..=hi.0 {
                    let p = at(x, y);
                    // The legend's swatches are the aircraft's colours, drawn on purpose.
                    // (A swatch is a short horizontal bar: most of its row neighbours match.)
                    let swatch = name == "right"
                        && (p == palette::AIRCRAFT || p == palette::MODEL_AIRCRAFT)
                        && (x.saturating_sub(6)..(x + 7).min(w))
                            .filter(|&u| at(u, y) == p)
                            .count()
                            >= 7;
                    assert!(
                        swatch || !drawing.contains(&p),
                        "t {t}: the drawing ({p:?}) under the {name} text at ({x}, {y})"
                    );
                }
            }
        }
        // The legend: a swatch of each colour in the top right.
        for color in [palette::AIRCRAFT, palette::MODEL_AIRCRAFT] {
            let n = (0..h / 4)
                .flat_map(|y| (w / 2..w).map(move |x| (x, y)))
                .filter(|&(x, y)| at(x, y) == color)
                .count();
            assert!(n >= 20, "t {t}: legend swatch {color:?}: {n} pixels");
        }
        // Nothing of the drawing in the strip (the bottom quarter).
        for y in h * 3 / 4..h {
            for x in 0..w {
                assert!(
                    !drawing.contains(&at(x, y)),
                    "t {t}: the drawing under the strip at ({x}, {y})"
                );
            }
        }
    }
}
