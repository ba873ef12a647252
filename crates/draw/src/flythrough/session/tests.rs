use super::*;
use wireflight_geometry::mesh::plane::builtin_plane;

#[test]
fn keys_fly_and_pause_stops_time() {
    let mut s = Session::fly(
        builtin_plane(),
        Start::default(),
        None,
        CameraMode::Chase,
        1.0,
    );
    let x0 = s.readout();
    let held = Held {
        pitch_up: true,
        throttle_up: true,
        ..Held::default()
    };
    for _ in 0..60 {
        s.advance(1.0 / 60.0, &held);
    }
    let r = s.readout();
    assert!(r.angles.pitch.to_degrees() < -40.0, "nose up 45°: {r:?}");
    assert!(r.throttle.unwrap() > x0.throttle.unwrap());
    s.toggle_pause();
    s.advance(1.0, &held);
    assert_eq!(s.readout().time, r.time);
    s.reset();
    assert_eq!(s.readout().time, 0.0);
}

#[test]
fn scripted_flight_ignores_keys_and_is_deterministic() {
    let script =
        super::super::script::parse("0 throttle=1 pitch_rate=10\n0.5 camera=orbit", "t").unwrap();
    let run = || {
        let mut s = Session::fly(
            builtin_plane(),
            Start::default(),
            Some(script.clone()),
            CameraMode::Chase,
            1.0,
        );
        let held = Held {
            roll_left: true,
            ..Held::default()
        };
        for _ in 0..60 {
            s.advance(1.0 / 60.0, &held);
            s.build(Viewport {
                width: 320,
                height: 200,
            });
        }
        s
    };
    let (a, b) = (run(), run());
    assert_eq!(a.readout(), b.readout());
    assert_eq!(a.scene(), b.scene());
    let r = a.readout();
    assert!(r.angles.roll.abs() < 1e-9, "keys ignored: {r:?}");
    assert!((r.angles.pitch.to_degrees() + 10.0).abs() < 1e-6, "{r:?}");
    assert_eq!(a.rig.mode, CameraMode::Orbit);
}

#[test]
fn a_chase_frame_over_the_field_clips_against_near_far_and_sides() {
    use crate::scene::builder::{ModelFrame, Part};
    use crate::scene::palette;
    use glam::DQuat;
    let mut b = SceneBuilder::new(
        builtin_plane(),
        Layer::world(World::new(&WorldSpec::default())),
        Clipper::Blinn,
    );
    let (centre, radius) = b.aircraft().bounding_sphere();
    let position = Vec3::new(-1500.0, 0.0, 150.0);
    let target = Target {
        position: position.as_dvec3(),
        orientation: DQuat::IDENTITY,
        centre,
        radius,
    };
    let mut rig = CameraRig::new(CameraMode::Chase, 55f32.to_radians());
    rig.follow(&target, 0.0);
    let camera = rig.camera(&target);
    let viewport = Viewport {
        width: 640,
        height: 360,
    };
    let trail = [Vec3::new(-1600.0, 0.0, 150.0)];
    let stats = b.build(&FrameSpec {
        camera: &camera,
        viewport,
        aircraft_position: position,
        aircraft_attitude: EulerZyx::default(),
        ground_z: 0.0,
        trail: &trail,
        model: None,
    });
    assert_eq!(stats.edges_in as usize, b.edges_per_frame() + 1);
    assert!(stats.clipped > 50, "{stats}");
    assert!(stats.trivially_rejected > 1000, "{stats}");
    assert!(stats.trivially_accepted > 100, "{stats}");
    let scene = b.scene();
    assert_eq!((scene.width, scene.height), (640, 360));
    assert_eq!(
        scene.batches[b.batch(Part::Aircraft)].segments.len(),
        b.aircraft().edges().len(),
        "the whole aircraft is in view"
    );
    assert!(!scene.batches[0].segments.is_empty());
    assert!(!scene.batches[1].segments.is_empty());
    assert_eq!(scene.batches[b.batch(Part::Trail)].segments.len(), 1);
    // Every segment lies in the image (the clipper's job).
    for s in scene.batches.iter().flat_map(|b| &b.segments) {
        for p in [s.a, s.b] {
            assert!(
                (-0.01..=640.01).contains(&p.x) && (-0.01..=360.01).contains(&p.y),
                "{p}"
            );
        }
    }
    // The horizon is level and above the middle of the picture seen from behind and above.
    let h = &scene.batches[1].segments;
    let ys: Vec<f32> = h.iter().flat_map(|s| [s.a.y, s.b.y]).collect();
    let (lo, hi) = ys
        .iter()
        .fold((f32::MAX, f32::MIN), |(l, u), &y| (l.min(y), u.max(y)));
    assert!(hi - lo < 2.0 && hi < 180.0, "{lo}..{hi}");

    // With the model's aircraft ahead: its trail is broken where the model restarts.
    let model_trail = [
        Vec3::new(-1490.0, 5.0, 150.0),
        Vec3::new(-1480.0, 5.0, 150.0),
        Vec3::new(-1470.0, 8.0, 150.0),
        Vec3::new(-1460.0, 8.0, 150.0),
    ];
    let stats = b.build(&FrameSpec {
        camera: &camera,
        viewport,
        aircraft_position: position,
        aircraft_attitude: EulerZyx::default(),
        ground_z: 0.0,
        trail: &trail,
        model: Some(ModelFrame {
            position: Vec3::new(-1450.0, 8.0, 150.0),
            attitude: EulerZyx::default(),
            trail: &model_trail,
            breaks: &[0, 2],
        }),
    });
    // 5 points, 4 joins, one of them across the restart at 2.
    let plane_edges = b.aircraft().edges().len();
    assert_eq!(
        stats.edges_in as usize,
        b.edges_per_frame() + 1 + plane_edges + 3
    );
    let scene = b.scene();
    assert_eq!(scene.batches[b.batch(Part::ModelTrail)].segments.len(), 3);
    assert!(!scene.batches[b.batch(Part::ModelAircraft)]
        .segments
        .is_empty());
    assert_eq!(
        scene.batches[b.batch(Part::ModelAircraft)].color,
        palette::MODEL_AIRCRAFT
    );
}
