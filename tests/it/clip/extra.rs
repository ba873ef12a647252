//! Beyond the view volume: extra clip planes (given in model space, fixed to the model),
//! whole-object rejection by bounding sphere, hidden-line drawing by back-face culling (and
//! the faces the loaders now record), and Sutherland-Hodgman's polygons.

use glam::{Mat4, Vec2, Vec3, Vec4};
use wireflight::draw::scene::{frame, ViewSpec};
use wireflight::geometry::camera::{Camera, CameraPreset, Projection};
use wireflight::geometry::clip::{
    cull, sutherland_hodgman, ClipOutcome, ClipStats, ClipVolume, Clipper, DepthRange, PlaneSet,
    Window2,
};
use wireflight::geometry::euler::EulerZyx;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::mesh::{EdgeMesh, EdgeMeshBuilder, MANY_FACES, NO_FACE};
use wireflight::geometry::pipeline::{EdgeProjector, Viewport};

fn planes(list: &[[f32; 4]]) -> PlaneSet {
    let mut p = PlaneSet::default();
    for &q in list {
        p.push(Vec4::from_array(q)).unwrap();
    }
    p
}

/// A plane like `--clip-plane 0.2,1,0.1,-0.2` keeps the same part of the aircraft (mostly its
/// left wing, body +Y) at every attitude: the cut is in model space. (Not a plane that
/// contains edges of the model, such as y = 0: an edge lying in the plane is inside only to
/// within rounding once mapped to clip space.) Checked against clipping the model-space edges by the plane
/// first (Cyrus-Beck in 3D) and drawing them with no extra plane.
#[test]
fn model_space_plane_cuts_the_model_at_any_attitude() {
    let mesh = builtin_plane();
    let plane = [0.2, 1.0, 0.1, -0.2];
    for (yaw, pitch, roll) in [
        (0.0, 0.0, 0.0),
        (30.0, -15.0, 40.0),
        (120.0, 60.0, -90.0),
        (-45.0, 10.0, 180.0),
    ] {
        for clipper in Clipper::ALL {
            let spec = ViewSpec {
                attitude: EulerZyx::from_degrees(yaw, pitch, roll),
                clip_planes: planes(&[plane]),
                clipper,
                ..ViewSpec::default()
            };
            let (cut, stats) = frame(&mesh, &spec);
            let full = frame(
                &mesh,
                &ViewSpec {
                    clip_planes: PlaneSet::EMPTY,
                    ..spec
                },
            )
            .1;
            assert!(stats.drawn() < full.drawn(), "{stats} vs {full}");
            // The reference: cut the mesh in model space, then draw it whole.
            let mut b = EdgeMeshBuilder::new();
            for &[i, j] in mesh.edges() {
                let (p, q) = (mesh.positions()[i as usize], mesh.positions()[j as usize]);
                if let Some((p, q)) = wireflight::geometry::clip::cyrus_beck::clip_polyhedron(
                    p,
                    q,
                    &[Vec4::from_array(plane)],
                )
                .segment()
                {
                    if p != q {
                        b.edge_between(p, q).unwrap();
                    }
                }
            }
            let half = b.build().unwrap();
            // Frame the half with the whole model's camera: same matrices.
            let segs_ref = project_like_frame(&mesh, &half, &spec);
            let segs = &cut.batches[0].segments;
            // Every drawn segment of the cut matches a reference segment within 0.05 px.
            for s in segs {
                let close = segs_ref.iter().any(|r| {
                    (s.a.distance(r.a) < 0.05 && s.b.distance(r.b) < 0.05)
                        || (s.a.distance(r.b) < 0.05 && s.b.distance(r.a) < 0.05)
                });
                let on_cut = s.a.distance(s.b) < 0.05;
                assert!(
                    close || on_cut,
                    "{clipper} {yaw},{pitch},{roll}: {s:?} not in the model-space cut"
                );
            }
        }
    }
}

/// Project `part` with the camera and matrices `frame` would use for `whole`.
fn project_like_frame(
    whole: &EdgeMesh,
    part: &EdgeMesh,
    spec: &ViewSpec,
) -> Vec<wireflight::draw::render::Segment2> {
    let (centre, radius) = whole.bounding_sphere();
    let subject = wireflight::geometry::camera::Subject {
        position: Vec3::ZERO,
        attitude: spec.attitude,
        centre,
        radius,
    };
    let camera = spec
        .camera
        .camera(&subject, (spec.fov_y_deg as f32).to_radians());
    let m = camera.clip_from_world(spec.viewport.aspect(), spec.depth)
        * wireflight::geometry::pipeline::model_matrix(Vec3::ZERO, spec.attitude);
    let mut out = Vec::new();
    EdgeProjector::new(Clipper::Blinn, spec.depth).project(part, m, spec.viewport, &mut out);
    out
}

#[test]
fn plane_set_limits_and_transform() {
    let mut p = PlaneSet::default();
    assert!(p.push(Vec4::new(0.0, 0.0, 0.0, 1.0)).is_err());
    assert!(p.push(Vec4::new(f32::NAN, 0.0, 1.0, 0.0)).is_err());
    for _ in 0..wireflight::geometry::clip::MAX_USER_PLANES {
        p.push(Vec4::X).unwrap();
    }
    assert!(p.push(Vec4::X).is_err());
    // π' = M⁻ᵀπ: π'·(M p) = π·p.
    let m = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_rotation_z(0.7);
    let q = planes(&[[0.3, -1.0, 2.0, 0.5]]).transformed(m).unwrap();
    for x in [Vec3::ZERO, Vec3::new(1.0, -2.0, 0.5), Vec3::splat(7.0)] {
        let a = Vec4::new(0.3, -1.0, 2.0, 0.5).dot(x.extend(1.0));
        let b = q.as_slice()[0].dot(m * x.extend(1.0));
        assert!((a - b).abs() < 1e-4, "{a} {b}");
    }
}

/// Extra planes with every algorithm: the visible part satisfies them.
#[test]
fn extra_planes_with_every_clipper() {
    let v = ClipVolume::with_planes(
        DepthRange::ZeroToOne,
        planes(&[[-1.0, 0.0, 0.0, 0.5], [0.0, 1.0, 0.0, 0.25]]),
    );
    let (a, c) = (
        Vec4::new(-2.0, 0.0, 0.5, 1.0),
        Vec4::new(2.0, 0.0, 0.5, 1.0),
    );
    for clipper in Clipper::ALL {
        let (p, q) = clipper.clip_in(a, c, &v).segment().unwrap();
        assert!(
            (p - Vec4::new(-1.0, 0.0, 0.5, 1.0)).abs().max_element() < 1e-6,
            "{clipper}: {p}"
        );
        assert!(
            (q - Vec4::new(0.5, 0.0, 0.5, 1.0)).abs().max_element() < 1e-6,
            "{clipper}: {q}"
        );
        assert_eq!(
            clipper
                .clip_in(
                    Vec4::new(0.0, -0.5, 0.5, 1.0),
                    Vec4::new(0.5, -0.6, 0.5, 1.0),
                    &v
                )
                .segment(),
            None
        );
    }
}

#[test]
fn bounding_sphere_rejects_whole_objects_and_counts_them() {
    let mesh = builtin_plane();
    // Panned far off the picture: rejected whole, nothing clipped.
    let spec = ViewSpec {
        pan: [20.0, 0.0],
        ..ViewSpec::default()
    };
    let (scene, stats) = frame(&mesh, &spec);
    assert_eq!(scene.segment_count(), 0);
    assert_eq!(stats.objects_culled, 1);
    assert_eq!(stats.bounds_rejected, mesh.edges().len() as u64);
    assert_eq!(stats.edges_in, mesh.edges().len() as u64);
    assert_eq!(
        stats.trivially_rejected + stats.clipped_away + stats.clipped + stats.trivially_accepted,
        0
    );
    assert!(
        stats.to_string().contains("culled by bounding sphere"),
        "{stats}"
    );
    // Half in the picture: not culled.
    let (_, stats) = frame(
        &mesh,
        &ViewSpec {
            pan: [1.0, 0.0],
            ..ViewSpec::default()
        },
    );
    assert_eq!(stats.objects_culled, 0);
    assert!(stats.drawn() > 0);
    // The sphere test is conservative: never culls an object that has a visible edge.
    for pan in [1.5f32, 2.0, 2.5, 3.0, 4.0, 6.0] {
        for pitch in [-60.0, 0.0, 45.0] {
            let s = ViewSpec {
                pan: [pan, pan / 3.0],
                attitude: EulerZyx::from_degrees(10.0, pitch, 20.0),
                ..ViewSpec::default()
            };
            let (_, with) = frame(&mesh, &s);
            if with.objects_culled == 1 {
                let m = Mat4::IDENTITY;
                let _ = m;
                // Re-draw without culling: nothing visible either.
                let mut out = Vec::new();
                let (c, r) = mesh.bounding_sphere();
                let _ = (c, r);
                let subject = wireflight::geometry::camera::Subject {
                    position: Vec3::ZERO,
                    attitude: s.attitude,
                    centre: c,
                    radius: r,
                };
                let camera = CameraPreset::Chase
                    .camera(&subject, 50f32.to_radians())
                    .panned(s.pan[0] * r, s.pan[1] * r);
                let m = camera.clip_from_world(s.viewport.aspect(), s.depth)
                    * wireflight::geometry::pipeline::model_matrix(Vec3::ZERO, s.attitude);
                let st = EdgeProjector::new(Clipper::Blinn, s.depth)
                    .project(&mesh, m, s.viewport, &mut out);
                assert_eq!(st.drawn(), 0, "culled at pan {pan} pitch {pitch}, but {st}");
            }
        }
    }
    assert!(cull::sphere_outside(
        Vec3::new(0.0, 0.0, -10.0),
        1.0,
        Mat4::IDENTITY,
        &ClipVolume::new(DepthRange::ZeroToOne)
    ));
}

/// A cube with outward counter-clockwise faces.
pub(super) fn cube() -> EdgeMesh {
    let mut b = EdgeMeshBuilder::new();
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let faces = [
        [
            v(-1., -1., 1.),
            v(1., -1., 1.),
            v(1., 1., 1.),
            v(-1., 1., 1.),
        ], // +z
        [
            v(-1., -1., -1.),
            v(-1., 1., -1.),
            v(1., 1., -1.),
            v(1., -1., -1.),
        ], // −z
        [
            v(1., -1., -1.),
            v(1., 1., -1.),
            v(1., 1., 1.),
            v(1., -1., 1.),
        ], // +x
        [
            v(-1., -1., -1.),
            v(-1., -1., 1.),
            v(-1., 1., 1.),
            v(-1., 1., -1.),
        ], // −x
        [
            v(-1., 1., -1.),
            v(-1., 1., 1.),
            v(1., 1., 1.),
            v(1., 1., -1.),
        ], // +y
        [
            v(-1., -1., -1.),
            v(1., -1., -1.),
            v(1., -1., 1.),
            v(-1., -1., 1.),
        ], // −y
    ];
    for f in faces {
        b.face(&f).unwrap();
    }
    b.build().unwrap()
}

#[test]
fn builder_records_faces_and_edge_adjacency() {
    let c = cube();
    assert_eq!(c.edges().len(), 12);
    assert_eq!(c.faces().len(), 6);
    assert_eq!(c.edge_faces().len(), 12);
    for sides in c.edge_faces() {
        assert!(
            sides.iter().all(|&f| f != NO_FACE && f != MANY_FACES),
            "{sides:?}"
        );
        assert_ne!(sides[0], sides[1]);
    }
    // Outward: each face's triangle normal points away from the centre.
    for f in c.faces() {
        let p = f.map(|i| c.positions()[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        assert!(n.dot(p[0]) > 0.0);
    }
    // Outline meshes have none.
    assert!(builtin_plane().faces().is_empty() && builtin_plane().edge_faces().is_empty());
}

/// The view matrix of an eye at `eye` looking at `target`.
fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    Camera {
        eye,
        target,
        up,
        projection: Projection::Perspective {
            fov_y: 1.0,
            near: 0.1,
            far: 100.0,
        },
    }
    .view()
}

#[test]
fn hidden_line_draws_the_edges_of_front_faces_only() {
    let c = cube();
    let viewport = Viewport {
        width: 400,
        height: 400,
    };
    let proj = Projection::Perspective {
        fov_y: 50f32.to_radians(),
        near: 0.1,
        far: 100.0,
    }
    .matrix(1.0, DepthRange::ZeroToOne);
    // A general view sees three faces: 9 of the 12 edges.
    let view = look_at(Vec3::new(4.0, 3.0, 5.0), Vec3::ZERO, Vec3::Y);
    let mut p = EdgeProjector::new(Clipper::Blinn, DepthRange::ZeroToOne);
    p.set_hidden_line(true);
    let mut out = Vec::new();
    let stats = p.project(&c, proj * view, viewport, &mut out);
    assert_eq!(
        (stats.drawn(), stats.back_facing, stats.edges_in),
        (9, 3, 12),
        "{stats}"
    );
    // Straight at a face: one face, its 4 edges.
    let view = look_at(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, Vec3::Y);
    out.clear();
    let stats = p.project(&c, proj * view, viewport, &mut out);
    assert_eq!((stats.drawn(), stats.back_facing), (4, 8), "{stats}");
    // From inside the cube every face turns away (its back is toward the eye).
    let view = look_at(Vec3::ZERO, Vec3::X, Vec3::Y);
    out.clear();
    let stats = p.project(&c, proj * view, viewport, &mut out);
    assert_eq!(stats.back_facing, 12, "{stats}");
    // Off: all 12 edges go to the clipper.
    p.set_hidden_line(false);
    let view = look_at(Vec3::new(4.0, 3.0, 5.0), Vec3::ZERO, Vec3::Y);
    out.clear();
    assert_eq!(p.project(&c, proj * view, viewport, &mut out).drawn(), 12);
}

#[test]
fn sutherland_hodgman_polygons() {
    let w = Window2::new(0.0, 0.0, 1.0, 1.0).unwrap();
    let (mut out, mut scratch) = ([Vec2::ZERO; 16], [Vec2::ZERO; 16]);
    // A big square around the window becomes the window.
    let big = [
        Vec2::new(-1.0, -1.0),
        Vec2::new(2.0, -1.0),
        Vec2::new(2.0, 2.0),
        Vec2::new(-1.0, 2.0),
    ];
    let n = sutherland_hodgman::clip_polygon_2d(&big, &w, &mut out, &mut scratch).unwrap();
    let mut got: Vec<_> = out[..n].to_vec();
    got.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    assert_eq!(got, [Vec2::ZERO, Vec2::Y, Vec2::X, Vec2::ONE]);
    // Wholly outside: nothing.
    let away = big.map(|p| p + Vec2::splat(10.0));
    assert_eq!(
        sutherland_hodgman::clip_polygon_2d(&away, &w, &mut out, &mut scratch),
        Ok(0)
    );
    // Too small an output array: an error, not a panic.
    let (mut tiny, mut tiny2) = ([Vec2::ZERO; 2], [Vec2::ZERO; 2]);
    assert!(sutherland_hodgman::clip_polygon_2d(&big, &w, &mut tiny, &mut tiny2).is_err());
    // Clip space: a quad crossing the eye plane keeps w > 0 everywhere.
    let quad = [
        Vec4::new(-0.5, -0.5, 0.5, 1.0),
        Vec4::new(0.5, -0.5, 0.5, 1.0),
        Vec4::new(0.5, 0.5, -0.5, -1.0),
        Vec4::new(-0.5, 0.5, -0.5, -1.0),
    ];
    let (mut o4, mut s4) = ([Vec4::ZERO; 24], [Vec4::ZERO; 24]);
    for depth in [DepthRange::ZeroToOne, DepthRange::NegOneToOne] {
        let n = sutherland_hodgman::clip_polygon_homogeneous(
            &quad,
            &ClipVolume::new(depth),
            &mut o4,
            &mut s4,
        )
        .unwrap();
        assert!(n >= 3, "{depth:?}: {n}");
        assert!(
            o4[..n]
                .iter()
                .all(|p| p.w > 0.0 && ClipVolume::new(depth).contains(*p, 1e-6)),
            "{:?}",
            &o4[..n]
        );
    }
}

#[test]
fn stats_display_and_merge_with_the_new_counts() {
    let mut s = ClipStats::default();
    s.record(&ClipOutcome::<Vec4>::Rejected);
    s.record_culled_object(10);
    s.record_back_facing();
    assert_eq!(s.edges_in, 12);
    let mut t = s;
    t.merge(&s);
    assert_eq!(
        (
            t.edges_in,
            t.objects_culled,
            t.bounds_rejected,
            t.back_facing
        ),
        (24, 2, 20, 2)
    );
    assert_eq!(
        s.to_string(),
        "edges in 12, trivially accepted 0, trivially rejected 1, clipped 0, clipped away 0, \
         culled by bounding sphere 10 (1 objects), back-facing 1"
    );
}
