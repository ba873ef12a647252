//! Blinn's clipper against an independent brute-force reference (dense sampling of each
//! edge, 20 001 samples), on 12 000 random edges per depth range and on hand-picked awkward
//! edges; and the whole pipeline on the built-in plane.

use super::blinn::{v, z_near, REL_TOL, SAMPLES, T_TOL};
use crate::support::{
    distance_from_line, edge_scale, inside_margin, recover_t, reference_ranges, to_f64, Rng, DEPTHS,
};
use glam::{Mat4, Vec3, Vec4};
use wireflight::geometry::camera::{CameraPreset, Subject};
use wireflight::geometry::clip::{
    boundary_coords, clip_edge, is_inside, outcode, ClipOutcome, ClipStats, Clipper, DepthRange,
    PLANE_COUNT,
};
use wireflight::geometry::euler::EulerZyx;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::pipeline::{model_matrix, perspective_divide, EdgeProjector, Viewport};

// ---------------------------------------------------------------------------------------------
// The property test against the brute-force reference
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    BothInside,
    SameSideOutside,
    CrossOne,
    CrossTwo,
    CrossThree,
    OutsideDifferentPlanes,
    OneBehindEye,
    BothBehindEye,
    Random,
    NearTheEye,
}

const KINDS: [Kind; 10] = [
    Kind::BothInside,
    Kind::SameSideOutside,
    Kind::CrossOne,
    Kind::CrossTwo,
    Kind::CrossThree,
    Kind::OutsideDifferentPlanes,
    Kind::OneBehindEye,
    Kind::BothBehindEye,
    Kind::Random,
    Kind::NearTheEye,
];

/// The coordinate scale of one edge: mostly around 1, some up to 1e4, some tiny.
fn random_scale(rng: &mut Rng) -> f64 {
    match rng.below(10) {
        0..=5 => rng.log_range(0.1, 10.0),
        6 | 7 => rng.log_range(100.0, 1e4),
        _ => rng.log_range(1e-6, 1e-3),
    }
}

fn inside_point(rng: &mut Rng, depth: DepthRange, s: f64) -> [f64; 4] {
    let w = s * rng.range(0.05, 1.0);
    let z_lo = match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => -w,
    };
    [
        w * rng.range(-1.0, 1.0),
        w * rng.range(-1.0, 1.0),
        z_lo + (w - z_lo) * rng.unit(),
        w,
    ]
}

/// Move `p` outside plane `i` (only that plane), by a random relative amount.
fn push_outside(rng: &mut Rng, p: &mut [f64; 4], i: usize, depth: DepthRange) {
    let w = p[3];
    let k = 1.0 + rng.log_range(1e-3, 3.0);
    match i {
        0 => p[0] = -w * k,
        1 => p[0] = w * k,
        2 => p[1] = -w * k,
        3 => p[1] = w * k,
        4 => {
            p[2] = match depth {
                DepthRange::ZeroToOne => -w * (k - 1.0),
                DepthRange::NegOneToOne => -w * k,
            }
        }
        _ => p[2] = w * k,
    }
}

fn behind_point(rng: &mut Rng, s: f64) -> [f64; 4] {
    [
        s * rng.range(-1.0, 1.0),
        s * rng.range(-1.0, 1.0),
        s * rng.range(-1.0, 1.0),
        -s * rng.range(0.001, 1.0),
    ]
}

fn to_vec4(p: [f64; 4]) -> Vec4 {
    Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32)
}

fn random_edge(rng: &mut Rng, kind: Kind, depth: DepthRange) -> (Vec4, Vec4) {
    let s = random_scale(rng);
    let (a, c) = match kind {
        Kind::BothInside => (inside_point(rng, depth, s), inside_point(rng, depth, s)),
        Kind::SameSideOutside => {
            let i = rng.below(PLANE_COUNT);
            let (mut a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            push_outside(rng, &mut a, i, depth);
            push_outside(rng, &mut c, i, depth);
            (a, c)
        }
        Kind::CrossOne | Kind::CrossTwo | Kind::CrossThree => {
            let (a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            // One plane of each opposite pair (two opposite planes cannot both be violated).
            let mut pairs = [0usize, 1, 2];
            for i in (1..3).rev() {
                pairs.swap(i, rng.below(i + 1));
            }
            let n = match kind {
                Kind::CrossOne => 1,
                Kind::CrossTwo => 2,
                _ => 3,
            };
            for &pair in &pairs[..n] {
                let i = 2 * pair + rng.below(2);
                push_outside(rng, &mut c, i, depth);
            }
            (a, c)
        }
        Kind::OutsideDifferentPlanes => {
            let i = rng.below(PLANE_COUNT);
            let j = (i + 1 + rng.below(PLANE_COUNT - 1)) % PLANE_COUNT;
            let (mut a, mut c) = (inside_point(rng, depth, s), inside_point(rng, depth, s));
            push_outside(rng, &mut a, i, depth);
            push_outside(rng, &mut c, j, depth);
            (a, c)
        }
        Kind::OneBehindEye => {
            let a = if rng.chance(0.7) {
                inside_point(rng, depth, s)
            } else {
                let mut a = inside_point(rng, depth, s);
                let i = rng.below(PLANE_COUNT);
                push_outside(rng, &mut a, i, depth);
                a
            };
            (a, behind_point(rng, s))
        }
        Kind::BothBehindEye => (behind_point(rng, s), behind_point(rng, s)),
        Kind::Random => {
            let mut r = || std::array::from_fn(|_| s * rng.range(-1.0, 1.0));
            (r(), r())
        }
        Kind::NearTheEye => {
            let a = inside_point(rng, depth, s);
            let k = rng.range(0.05, 2.0);
            let noise = s * 10f64.powf(rng.range(-6.0, -1.0));
            let c = std::array::from_fn(|i| -k * a[i] + noise * rng.range(-1.0, 1.0));
            (a, c)
        }
    };
    let (a, c) = (to_vec4(a), to_vec4(c));
    if rng.chance(0.5) {
        (c, a)
    } else {
        (a, c)
    }
}

/// What the property check saw, for the summary.
#[derive(Default, Debug)]
struct Tally {
    stats: ClipStats,
    /// Clipper and strict reference disagree on "anything visible", excused as tangent (the
    /// robustly-inside part is shorter than one step) or as within the tolerance band.
    tangent_excused: u32,
    /// Largest |t_clipper − t_reference| seen against the strict reference.
    max_t_error: f64,
    /// Endpoints that pass `is_inside` only with the tolerance taken relative to the edge's
    /// scale instead of the point's own.
    needed_edge_relative_tol: u32,
}

/// Whether the part t ∈ [t0, t1] of the edge (all with w > 0) has an image shorter than 1e-4 in
/// NDC: it lies on a ray from the eye (the edge passes through the eye), so it draws nothing.
fn projects_to_a_point(a: Vec4, c: Vec4, t0: f64, t1: f64) -> bool {
    let (a, c) = (to_f64(a), to_f64(c));
    let ndc = |t: f64| {
        let p: [f64; 4] = std::array::from_fn(|k| a[k] + t * (c[k] - a[k]));
        (p[0] / p[3], p[1] / p[3])
    };
    let (p, q) = (ndc(t0), ndc(t1));
    (p.0 - q.0).hypot(p.1 - q.1) < 1e-4
}

/// Check one edge against every property; `Err` describes the violation.
fn check_edge(a: Vec4, c: Vec4, depth: DepthRange, tally: &mut Tally) -> Result<(), String> {
    let out = clip_edge(a, c, depth);
    tally.stats.record(&out);
    let scale = edge_scale(a, c);
    let slack = REL_TOL * scale;
    let reference = reference_ranges(a, c, depth, SAMPLES, slack);
    let h = reference.step;
    let fail = |what: String| {
        Err(format!(
            "{what}\n    edge: a = {a:?}, c = {c:?}, {depth:?}\n    clip_edge → {out:?}\n    \
             reference (step {h:e}): {reference:?}"
        ))
    };
    let (ma, mc) = (
        inside_margin(to_f64(a), depth),
        inside_margin(to_f64(c), depth),
    );
    let codes = (
        outcode(&boundary_coords(a, depth)),
        outcode(&boundary_coords(c, depth)),
    );

    let segment = match out {
        ClipOutcome::NonFinite => return fail("NonFinite for finite input".into()),
        ClipOutcome::Accepted(a2, c2) => {
            if (a2, c2) != (a, c) {
                return fail("Accepted but changed".into());
            }
            if ma < 0.0 || mc < 0.0 || a.w <= 0.0 || c.w <= 0.0 {
                return fail(format!(
                    "Accepted with an endpoint outside (margins {ma}, {mc})"
                ));
            }
            Some((a2, c2))
        }
        ClipOutcome::Rejected => {
            if codes.0 & codes.1 == 0 {
                return fail(format!(
                    "Rejected without a common outside plane: {:06b} {:06b}",
                    codes.0, codes.1
                ));
            }
            None
        }
        ClipOutcome::Clipped(a2, c2) => {
            if codes.0 | codes.1 == 0 || codes.0 & codes.1 != 0 {
                return fail("Clipped a trivial edge".into());
            }
            // An endpoint that was inside must be kept exactly.
            if codes.0 == 0 && a2 != a {
                return fail("inside start point moved".into());
            }
            if codes.1 == 0 && c2 != c {
                return fail("inside end point moved".into());
            }
            Some((a2, c2))
        }
        ClipOutcome::ClippedAway => None,
    };

    match segment {
        Some((a2, c2)) => {
            let mut ts = [0.0; 2];
            for (k, p) in [a2, c2].into_iter().enumerate() {
                if !p.is_finite() || p.w <= 0.0 {
                    return fail(format!("endpoint {p:?} not finite or w ≤ 0"));
                }
                let ndc = perspective_divide(p);
                if !ndc.is_finite() {
                    return fail(format!("endpoint {p:?} divides to {ndc}"));
                }
                // Inside within 1e-5 relative: first relative to the point itself (as
                // `is_inside` measures), else relative to the edge's scale, which is what f32
                // arithmetic on the edge can promise for a point much smaller than the edge.
                if !is_inside(p, depth, REL_TOL as f32) {
                    let own = f64::from(p.abs().max_element());
                    let rel = (slack / own.max(f64::MIN_POSITIVE)) as f32;
                    if !is_inside(p, depth, rel) || inside_margin(to_f64(p), depth) < -slack {
                        return fail(format!(
                            "endpoint {p:?} outside the volume by more than {slack:e} \
                             (margin {:e})",
                            inside_margin(to_f64(p), depth)
                        ));
                    }
                    tally.needed_edge_relative_tol += 1;
                }
                let Some(t) = recover_t(a, c, p) else {
                    return fail("clipped a zero-length edge".into());
                };
                if !(-T_TOL..=1.0 + T_TOL).contains(&t) {
                    return fail(format!("endpoint {p:?} at t = {t}, outside [0, 1]"));
                }
                let off = distance_from_line(a, c, t, p);
                if off > slack {
                    return fail(format!(
                        "endpoint {p:?} is {off:e} off the edge (t = {t}), tolerance {slack:e}"
                    ));
                }
                ts[k] = t;
            }
            let [t0, t1] = ts;
            if t0 > t1 + T_TOL {
                return fail(format!("direction reversed: t {t0} > {t1}"));
            }
            let Some((l0, l1)) = reference.loose else {
                return fail("drawn, but no sample is inside even with the tolerance".into());
            };
            if t0 < l0 - h - T_TOL || t1 > l1 + h + T_TOL {
                return fail(format!(
                    "drawn t-range [{t0}, {t1}] exceeds the reference's [{l0}, {l1}] (with tolerance)"
                ));
            }
            if let Some((r0, r1)) = reference.robust {
                if t0 > r0 + h + T_TOL || t1 < r1 - h - T_TOL {
                    return fail(format!(
                        "drawn t-range [{t0}, {t1}] misses part of the robustly inside \
                         [{r0}, {r1}]"
                    ));
                }
            }
            match reference.strict {
                Some((r0, r1)) => {
                    let err = (t0 - r0).abs().max((t1 - r1).abs());
                    tally.max_t_error = tally.max_t_error.max(err);
                }
                None => tally.tangent_excused += 1,
            }
        }
        None => {
            if let Some((r0, r1)) = reference.robust {
                if r1 - r0 > h && !projects_to_a_point(a, c, r0, r1) {
                    return fail(format!(
                        "nothing drawn, but t ∈ [{r0}, {r1}] is inside by at least {slack:e}"
                    ));
                }
            }
            if let Some((r0, r1)) = reference.strict {
                if r1 - r0 > h {
                    tally.tangent_excused += 1;
                }
            }
        }
    }
    Ok(())
}

/// 12 000 edges per depth range, a mix of every kind, each checked against the brute-force
/// reference (20 001 samples per edge).
#[test]
fn property_clipper_matches_brute_force_reference() {
    let per_kind = 1_200;
    let mut report = String::new();
    let mut failures = Vec::new();
    let mut total_failures = 0;
    for depth in DEPTHS {
        let mut rng = Rng::new(0xC11B_0000 + depth as u64);
        let mut tally = Tally::default();
        for &kind in &KINDS {
            for i in 0..per_kind {
                let (a, c) = random_edge(&mut rng, kind, depth);
                if let Err(e) = check_edge(a, c, depth, &mut tally) {
                    total_failures += 1;
                    if failures.len() < 8 {
                        failures.push(format!("[{kind:?} #{i}] {e}"));
                    }
                }
            }
        }
        // The mix really exercises every outcome.
        let s = tally.stats;
        assert_eq!(s.edges_in, (per_kind * KINDS.len()) as u64);
        assert!(s.trivially_accepted > 1_000, "{depth:?}: {s}");
        assert!(s.trivially_rejected > 1_000, "{depth:?}: {s}");
        assert!(s.clipped > 2_000, "{depth:?}: {s}");
        assert!(s.clipped_away > 100, "{depth:?}: {s}");
        report += &format!("{depth:?}: {s}; {tally:?}\n");
    }
    println!("{report}");
    assert!(
        failures.is_empty(),
        "{total_failures} edges violate the clipper's properties; the first {}:\n\n{}\n\n{report}",
        failures.len(),
        failures.join("\n\n")
    );
}

/// The property check on hand-picked awkward edges: tangent to a plane, along an edge or through
/// a corner of the volume, nearly parallel to a plane, very long and very short.
#[test]
fn property_holds_on_awkward_edges() {
    let mut tally = Tally::default();
    for depth in DEPTHS {
        let zn = z_near(depth, 1.0);
        let edges = [
            (v(-2.0, 1.0, 0.5, 1.0), v(2.0, 1.0, 0.5, 1.0)), // along y = w
            (v(-2.0, -2.0, 0.5, 1.0), v(2.0, 2.0, 0.5, 1.0)), // through two corners
            (v(-2.0, -2.0, zn - 1.0, 1.0), v(2.0, 2.0, 2.0, 1.0)), // body diagonal
            (v(-1e4, 0.0, 0.5, 1.0), v(1e4, 0.0, 0.5, 1.0)), // very long in x
            (v(0.0, 0.0, 0.5, 1e-4), v(0.0, 0.0, 0.5, 1.0)), // w from tiny to 1
            (v(1.0001, -2.0, 0.5, 1.0), v(1.0001, 2.0, 0.5, 1.0)), // just outside x = w
            (v(0.9999, -2.0, 0.5, 1.0), v(0.9999, 2.0, 0.5, 1.0)), // just inside x = w
            (v(0.0, 0.0, 0.5, 1.0), v(0.0, 0.0, 0.5, -1.0)), // straight back through the eye
            (v(0.3, 0.3, 0.5, 1.0), v(-0.3, -0.3, -0.5, -1.0)), // through the eye
            (v(0.5, 0.0, 0.5, 1.0), v(-1e4, 0.0, -1e4, -1e4)), // far behind
            (v(1e-6, 1e-6, 1e-6, 2e-6), v(-3e-6, 0.0, 1e-6, 2e-6)), // tiny
        ];
        for (a, c) in edges {
            for (p, q) in [(a, c), (c, a)] {
                if let Err(e) = check_edge(p, q, depth, &mut tally) {
                    panic!("{e}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The pipeline on the built-in plane
// ---------------------------------------------------------------------------------------------

fn project_plane(
    attitude: EulerZyx,
    preset: CameraPreset,
    pan: [f32; 2],
    depth: DepthRange,
    viewport: Viewport,
) -> (Vec<wireflight::draw::render::Segment2>, ClipStats, usize) {
    let mesh = builtin_plane();
    let (centre, radius) = mesh.bounding_sphere();
    let subject = Subject {
        position: Vec3::new(10.0, -20.0, 300.0),
        attitude,
        centre,
        radius,
    };
    let camera = preset
        .camera(&subject, 50f32.to_radians())
        .panned(pan[0] * radius, pan[1] * radius);
    let clip_from_model: Mat4 =
        camera.clip_from_world(viewport.aspect(), depth) * model_matrix(subject.position, attitude);
    let mut out = Vec::new();
    let stats = EdgeProjector::new(Clipper::Blinn, depth).project(
        &mesh,
        clip_from_model,
        viewport,
        &mut out,
    );
    (out, stats, mesh.edges().len())
}

/// Every segment lies in the image, the tally adds up to the edge count, and every drawn edge
/// gives one segment, for a range of attitudes, cameras (chase; panned half out of the picture;
/// cockpit, where much of the plane is beside and behind the eye) and both depth ranges.
#[test]
fn pipeline_segments_stay_in_the_viewport() {
    let viewport = Viewport {
        width: 640,
        height: 480,
    };
    let (w, h) = (viewport.width as f32, viewport.height as f32);
    let tol = 0.01;
    let mut clipped_somewhere = 0;
    for depth in DEPTHS {
        for (preset, pan) in [
            (CameraPreset::Chase, [0.0, 0.0]),
            (CameraPreset::Chase, [1.6, 0.0]),
            (CameraPreset::Chase, [0.0, -1.2]),
            (CameraPreset::Cockpit, [0.0, 0.0]),
            (CameraPreset::Front, [0.0, 0.0]),
            (CameraPreset::Top, [0.0, 0.0]),
            (CameraPreset::Side, [0.0, 0.0]),
        ] {
            for yaw in (-180..180).step_by(45) {
                for pitch in [-90, -60, -20, 0, 30, 90] {
                    for roll in [-150, 0, 40] {
                        let attitude =
                            EulerZyx::from_degrees(yaw.into(), pitch.into(), roll.into());
                        let (segs, stats, n_edges) =
                            project_plane(attitude, preset, pan, depth, viewport);
                        let ctx = format!("{preset:?} pan {pan:?} {attitude:?} {depth:?}: {stats}");
                        assert_eq!(stats.edges_in, n_edges as u64, "{ctx}");
                        assert_eq!(
                            stats.trivially_accepted
                                + stats.trivially_rejected
                                + stats.clipped
                                + stats.clipped_away
                                + stats.non_finite,
                            stats.edges_in,
                            "{ctx}"
                        );
                        assert_eq!(stats.non_finite, 0, "{ctx}");
                        assert_eq!(segs.len() as u64, stats.drawn(), "{ctx}");
                        if preset == CameraPreset::Chase && pan == [0.0, 0.0] {
                            // The chase camera frames the whole plane.
                            assert_eq!(stats.drawn(), stats.edges_in, "{ctx}");
                        }
                        clipped_somewhere += stats.clipped;
                        for s in &segs {
                            for p in [s.a, s.b] {
                                assert!(
                                    p.is_finite()
                                        && (-tol..=w + tol).contains(&p.x)
                                        && (-tol..=h + tol).contains(&p.y),
                                    "{ctx}: segment {s:?} leaves the {w}×{h} image"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(clipped_somewhere > 100, "the cases exercise the clipper");
}
