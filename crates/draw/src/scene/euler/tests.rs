use super::*;
use wireflight_geometry::mesh::plane::builtin_plane;

const VIEW: Viewport = Viewport {
    width: 320,
    height: 240,
};

fn e(c: &str, a: [f64; 3]) -> EulerAngles {
    EulerAngles::from_degrees(c.parse().unwrap(), a)
}

#[test]
fn labels() {
    assert_eq!(degrees_label(30f64.to_radians()), "+30°");
    assert_eq!(degrees_label(-12.25f64.to_radians()), "-12.3°");
    assert_eq!(degrees_label(-1e-9), "0°");
    let z = e("zyx", [60.0, 90.0, 0.0]);
    assert_eq!(angles_label(&z), "Z+60° Y'+90° X''0°");
    assert_eq!(axis_label(&e("zyx,extrinsic", [0.0; 3]), 2), "X");
}

#[test]
fn rings_nest_and_the_middle_one_lies_in_the_outer_ones_plane_at_lock() {
    let normal = |r: &Ring| {
        let c = &r.circle;
        (c[1] - c[0]).cross(c[ARC_POINTS / 4] - c[0]).normalize()
    };
    for c in wireflight_geometry::euler::Convention::ALL {
        let lock = if c.sequence.is_tait_bryan() {
            90.0
        } else {
            0.0
        };
        let free = e(&c.to_string(), [20.0, 40.0, -30.0]);
        let locked = e(&c.to_string(), [20.0, lock, -30.0]);
        let rings = gimbal_rings(&free);
        for (k, ring) in rings.iter().enumerate() {
            let r = ring.circle[0].length();
            assert!((r - RING_RADII[k]).abs() < 1e-5, "{c}");
            assert_eq!(ring.circle.first(), ring.circle.last());
        }
        assert!(normal(&rings[0]).dot(normal(&rings[1])).abs() < 0.99, "{c}");
        let rings = gimbal_rings(&locked);
        assert!(
            (normal(&rings[0]).dot(normal(&rings[1])).abs() - 1.0).abs() < 1e-5,
            "{c}: coplanar at lock"
        );
        // The slots cover 0, 1, 2, in reverse for extrinsic conventions.
        let slots: Vec<usize> = rings.iter().map(|r| r.slot).collect();
        let expected = if c.frame == Frame::Intrinsic {
            [0, 1, 2]
        } else {
            [2, 1, 0]
        };
        assert_eq!(slots, expected);
    }
}

#[test]
fn panels_draw_the_aircraft_whole_and_sheets_keep_them_apart() {
    let mesh = builtin_plane();
    let panels = step_panels(&mesh, &e("zyx", [30.0, 60.0, 45.0]), VIEW);
    assert_eq!(panels.len(), 4);
    for p in &panels {
        assert_eq!((p.width, p.height), (320, 240));
        let plane = p
            .batches
            .iter()
            .filter(|b| b.color == palette::AIRCRAFT)
            .map(|b| b.segments.len())
            .sum::<usize>();
        assert_eq!(plane, mesh.edges().len(), "the whole aircraft is in view");
    }
    let s = sheet(&panels, 2);
    assert_eq!((s.width, s.height), (643, 483));
    // Every segment of panel 3 (bottom right) lies in its quarter.
    let n: usize = panels[..3].iter().map(|p| p.batches.len()).sum();
    for b in &s.batches[1 + n..] {
        for seg in &b.segments {
            for q in [seg.a, seg.b] {
                assert!(
                    q.x >= 323.0 && q.x < 643.0 && q.y >= 243.0 && q.y < 483.0,
                    "{q}"
                );
            }
        }
    }
    assert_eq!(sheet(&[], 3).width, 1);
}
