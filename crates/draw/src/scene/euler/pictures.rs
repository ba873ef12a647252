//! The panels and pictures of Euler angles built from [`Panel`]s: the elementary steps, a
//! convention's gimbal rings, the gimbal-lock pair and sweep, and Euler-angle interpolation
//! against slerp; [`sheet`] lays panels out in a grid. Pure: no I/O.
//!
//! The parent module holds the building blocks (the captions' labels, [`Panel`], the gimbal
//! rings); this one what is drawn with them.

use glam::{DMat3, DVec3, Vec2, Vec3};

use super::{angles_label, axis_label, degrees_label, slot_color, Panel, Reach, ARC_POINTS};
use crate::render::{LineBatch, LineScene, Segment2};
use crate::scene::palette;
use wireflight_geometry::euler::{
    compare_paths, lerp, slerp, EulerAngles, Frame, PathComparison, Step,
};
use wireflight_geometry::mesh::EdgeMesh;
use wireflight_geometry::pipeline::Viewport;

/// `count + 1` attitudes evenly along a step, `before` to `after`.
fn step_path(step: &Step, count: usize) -> Vec<DMat3> {
    (0..=count)
        .map(|i| step.partial(i as f64 / count as f64))
        .collect()
}

/// The body point whose path shows a rotation about `axis` (through the origin) best: the nose
/// tip, unless it lies near the axis, then the left wing tip.
fn tracer(mesh: &EdgeMesh, attitude: DMat3, axis: DVec3) -> Vec3 {
    let extreme = |f: fn(&Vec3) -> f32| {
        mesh.positions()
            .iter()
            .copied()
            .max_by(|p, q| f(p).total_cmp(&f(q)))
            .unwrap_or(Vec3::X)
    };
    let nose = extreme(|p| p.x);
    let wing = extreme(|p| p.y);
    let off_axis = |p: Vec3| {
        let w = attitude * p.as_dvec3();
        (w - axis * w.dot(axis)).length()
    };
    if off_axis(nose) >= 0.5 * off_axis(wing) {
        nose
    } else {
        wing
    }
}

/// The step pictures of `e`: panel 0 the aircraft at rest with the world axes, then one panel
/// per elementary rotation: the aircraft before it (dim) and after it, the rotation's axis, and
/// the path of a tracer point (nose or wing tip) during it, captioned with the axis and angle.
pub fn step_panels(mesh: &EdgeMesh, e: &EulerAngles, viewport: Viewport) -> Vec<LineScene> {
    let mut panels = Vec::with_capacity(4);
    let mut first = Panel::new(mesh, viewport, Reach::Aircraft);
    first
        .world_axes()
        .aircraft(DMat3::IDENTITY, palette::AIRCRAFT)
        .caption(0, "0 START", palette::CAPTION)
        .caption(1, &convention_label(e), palette::CAPTION_DIM);
    panels.push(first.finish().0);
    for (k, step) in e.steps().iter().enumerate() {
        let color = slot_color(step.slot);
        let mut p = Panel::new(mesh, viewport, Reach::Aircraft);
        let point = tracer(mesh, step.before, step.axis_world);
        p.world_axes()
            .aircraft(step.before, palette::GHOST)
            .rotation_axis(step.axis_world, color)
            .trace(point, &step_path(step, ARC_POINTS), color)
            .aircraft(step.after, palette::AIRCRAFT)
            .caption(
                0,
                &format!(
                    "{} {} {}",
                    k + 1,
                    axis_label(e, step.slot),
                    degrees_label(step.angle)
                ),
                color,
            )
            .caption(1, &angles_label(e), palette::CAPTION_DIM);
        panels.push(p.finish().0);
    }
    panels
}

/// `intrinsic z-y-x` or `extrinsic z-y-x` in capitals for captions.
fn convention_label(e: &EulerAngles) -> String {
    format!("{} {:#}", e.convention.frame, e.convention.sequence).to_ascii_uppercase()
}

/// A plain frame of the aircraft in `e`'s attitude with the world axes and nothing that
/// depends on how the attitude was written: two angle triples of the same rotation give the
/// same picture.
pub fn attitude_panel(mesh: &EdgeMesh, e: &EulerAngles, viewport: Viewport) -> LineScene {
    let mut p = Panel::new(mesh, viewport, Reach::Aircraft);
    p.world_axes().aircraft(e.to_matrix(), palette::AIRCRAFT);
    p.finish().0
}

/// The aircraft in `e`'s attitude inside its gimbal rings, captioned with the angles.
pub fn gimbal_panel(
    mesh: &EdgeMesh,
    e: &EulerAngles,
    viewport: Viewport,
    title: &str,
) -> LineScene {
    let mut p = Panel::new(mesh, viewport, Reach::Rings);
    p.world_axes()
        .rings(e)
        .aircraft(e.to_matrix(), palette::AIRCRAFT)
        .caption(0, title, palette::CAPTION)
        .caption(1, &angles_label(e), palette::CAPTION_DIM);
    p.finish().0
}

/// The gimbal-lock sweep: for each shift `d`, two panels of the same attitude, one reached by
/// turning the first angle of `locked` by `d` (top row), the other by turning the third angle
/// by `coupling·d` (bottom row, see [`EulerAngles::lock_coupling`]). Each shows the rings, the
/// swept angle's axis and the path of the tracer from the start. Returns the top row, then the
/// bottom row; `None` when `locked` is not at gimbal lock.
pub fn lock_sweep_panels(
    mesh: &EdgeMesh,
    locked: &EulerAngles,
    shifts: &[f64],
    viewport: Viewport,
) -> Option<Vec<LineScene>> {
    let pair = locked.lock_coupling()?;
    // In the convention's own order: which slots are the first and third of the intrinsic
    // reading.
    let (first, third) = match locked.convention.frame {
        Frame::Intrinsic => (0, 2),
        Frame::Extrinsic => (2, 0),
    };
    let start = locked.to_matrix();
    let mut rows = Vec::with_capacity(2 * shifts.len());
    for (slot, factor) in [(first, 1.0), (third, pair.coupling)] {
        for &d in shifts {
            let mut e = *locked;
            e.angles[slot] += factor * d;
            let color = slot_color(slot);
            let axis = pair.axis_world;
            let path: Vec<DMat3> = (0..=ARC_POINTS)
                .map(|i| DMat3::from_axis_angle(axis, d * i as f64 / ARC_POINTS as f64) * start)
                .collect();
            let point = tracer(mesh, start, axis);
            let mut p = Panel::new(mesh, viewport, Reach::Rings);
            p.world_axes()
                .rings(&e)
                .aircraft(start, palette::GHOST)
                .rotation_axis(axis * factor, color)
                .trace(point, &path, color)
                .aircraft(e.to_matrix(), palette::AIRCRAFT)
                .caption(
                    0,
                    &format!(
                        "{} {}",
                        axis_label(&e, slot),
                        degrees_label(e.angles[slot] - locked.angles[slot])
                    ),
                    color,
                )
                .caption(1, &angles_label(&e), palette::CAPTION_DIM);
            rows.push(p.finish().0);
        }
    }
    Some(rows)
}

/// Euler-angle interpolation against slerp from `a` to `b` (same convention) in `frames`
/// frames (at least 2): the top row Euler lerp, the bottom row slerp, each panel the aircraft
/// at its `t` with the paths of the nose and wing tips over the whole interpolation (the
/// row's method bright, the other dim), and the comparison numbers.
pub fn interpolation_panels(
    mesh: &EdgeMesh,
    a: &EulerAngles,
    b: &EulerAngles,
    frames: usize,
    viewport: Viewport,
) -> (Vec<LineScene>, PathComparison) {
    let frames = frames.max(2);
    let samples = 96;
    let ts: Vec<f64> = (0..=samples).map(|i| i as f64 / samples as f64).collect();
    let euler_path: Vec<DMat3> = ts.iter().map(|&t| lerp(*a, *b, t).to_matrix()).collect();
    let slerp_path: Vec<DMat3> = ts
        .iter()
        .map(|&t| DMat3::from_quat(slerp(*a, *b, t)))
        .collect();
    let nose = tracer(mesh, DMat3::IDENTITY, DVec3::Z);
    let wing = tracer(mesh, DMat3::IDENTITY, DVec3::X);
    let mut panels = Vec::with_capacity(2 * frames);
    for euler_row in [true, false] {
        let (mine, theirs, color, dim, name) = if euler_row {
            (
                &euler_path,
                &slerp_path,
                palette::EULER_FIRST,
                palette::EULER_THIRD_DIM,
                "EULER",
            )
        } else {
            (
                &slerp_path,
                &euler_path,
                palette::EULER_THIRD,
                palette::EULER_FIRST_DIM,
                "SLERP",
            )
        };
        for i in 0..frames {
            let t = i as f64 / (frames - 1) as f64;
            let attitude = if euler_row {
                lerp(*a, *b, t).to_matrix()
            } else {
                DMat3::from_quat(slerp(*a, *b, t))
            };
            let mut p = Panel::new(mesh, viewport, Reach::Aircraft);
            p.world_axes()
                .trace(nose, theirs, dim)
                .trace(wing, theirs, dim)
                .trace(nose, mine, color)
                .trace(wing, mine, color)
                .aircraft(attitude, palette::AIRCRAFT)
                .caption(0, &format!("{name} T={t:.2}"), color);
            if euler_row {
                p.caption(1, &angles_label(&lerp(*a, *b, t)), palette::CAPTION_DIM);
            }
            panels.push(p.finish().0);
        }
    }
    (panels, compare_paths(*a, *b, samples))
}

/// Lay `panels` (all of the first one's size) out in rows of `columns`, left to right and top
/// to bottom, with a thin separator between them, as one scene. Segments are kept inside their
/// panel. An empty list gives a 1×1 scene.
pub fn sheet(panels: &[LineScene], columns: usize) -> LineScene {
    const GAP: u32 = 3;
    let Some(first) = panels.first() else {
        return LineScene {
            width: 1,
            height: 1,
            background: palette::BACKGROUND,
            batches: Vec::new(),
        };
    };
    let (w, h) = (first.width, first.height);
    let columns = columns.clamp(1, panels.len());
    let rows = panels.len().div_ceil(columns);
    let width = columns as u32 * w + (columns as u32 - 1) * GAP;
    let height = rows as u32 * h + (rows as u32 - 1) * GAP;
    let mut batches = Vec::new();
    let mut separators = Vec::new();
    let (wf, hf) = (width as f32, height as f32);
    for c in 1..columns {
        let x = (c as u32 * (w + GAP) - GAP / 2 - 1) as f32 + 0.5;
        separators.push(Segment2 {
            a: Vec2::new(x, 0.5),
            b: Vec2::new(x, hf - 0.5),
        });
    }
    for r in 1..rows {
        let y = (r as u32 * (h + GAP) - GAP / 2 - 1) as f32 + 0.5;
        separators.push(Segment2 {
            a: Vec2::new(0.5, y),
            b: Vec2::new(wf - 0.5, y),
        });
    }
    batches.push(LineBatch {
        color: palette::SEPARATOR,
        segments: separators,
    });
    for (i, panel) in panels.iter().enumerate() {
        let offset = Vec2::new(
            ((i % columns) as u32 * (w + GAP)) as f32,
            ((i / columns) as u32 * (h + GAP)) as f32,
        );
        // A segment touching the panel's far edge (x = w) would land in the next pixel column.
        let inside = Vec2::new(w as f32 - 1e-3, h as f32 - 1e-3);
        let keep = |p: Vec2| p.clamp(Vec2::ZERO, inside) + offset;
        for b in &panel.batches {
            batches.push(LineBatch {
                color: b.color,
                segments: b
                    .segments
                    .iter()
                    .map(|s| Segment2 {
                        a: keep(s.a),
                        b: keep(s.b),
                    })
                    .collect(),
            });
        }
    }
    LineScene {
        width,
        height,
        background: first.background,
        batches,
    }
}

/// One picture of a set: its file name (without extension), what it shows, and the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// File name without extension, e.g. `step_1`.
    pub name: String,
    /// One line on what it shows.
    pub what: String,
    /// The picture.
    pub scene: LineScene,
}

impl Picture {
    fn new(name: impl Into<String>, what: impl Into<String>, scene: LineScene) -> Self {
        Self {
            name: name.into(),
            what: what.into(),
            scene,
        }
    }
}

/// The step pictures of `e` ([`step_panels`]): `step_0` … `step_3` and the contact sheet
/// `steps` (the four in a row).
pub fn steps_pictures(mesh: &EdgeMesh, e: &EulerAngles, viewport: Viewport) -> Vec<Picture> {
    let panels = step_panels(mesh, e, viewport);
    let mut pictures: Vec<Picture> = panels
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let what = if k == 0 {
                "the aircraft at rest, world axes X (red), Y (green), Z (blue)".to_string()
            } else {
                format!(
                    "after rotation {k}: {} by {}",
                    axis_label(e, k - 1),
                    degrees_label(e.angles[k - 1])
                )
            };
            Picture::new(format!("step_{k}"), what, p.clone())
        })
        .collect();
    pictures.push(Picture::new(
        "steps",
        "contact sheet: the four steps left to right",
        sheet(&panels, panels.len()),
    ));
    pictures
}

/// The second angle triple of the gimbal-lock pair: `locked` with its whole turn moved into
/// the other one of the two coupled angles (or, when that one already holds it, 60° moved
/// back). `None` away from lock.
pub fn lock_partner(locked: &EulerAngles) -> Option<EulerAngles> {
    let first = match locked.convention.frame {
        Frame::Intrinsic => 0,
        Frame::Extrinsic => 2,
    };
    let shift = if locked.angles[first].abs() > 1e-3 {
        -locked.angles[first]
    } else {
        60f64.to_radians()
    };
    locked.lock_twin(shift)
}

/// Angle shifts of the gimbal-lock sweep, degrees.
pub const SWEEP_DEG: [f64; 4] = [0.0, 30.0, 60.0, 90.0];

/// The gimbal-lock pictures of `locked` (which must be at lock, else `None`):
/// `lock_a` and `lock_b`, the plain attitude of `locked` and of its [`lock_partner`] (the same
/// picture, from different angles); `lock_pair`, both inside their gimbal rings side by side;
/// and `lock_sweep`, the first angle swept (top row) against the third (bottom row,
/// [`lock_sweep_panels`]). Also returns the partner.
pub fn gimbal_lock_pictures(
    mesh: &EdgeMesh,
    locked: &EulerAngles,
    viewport: Viewport,
) -> Option<(Vec<Picture>, EulerAngles)> {
    let twin = lock_partner(locked)?;
    let shifts = SWEEP_DEG.map(f64::to_radians);
    let sweep = lock_sweep_panels(mesh, locked, &shifts, viewport)?;
    let pair = [
        gimbal_panel(mesh, locked, viewport, "A: GIMBAL LOCK"),
        gimbal_panel(mesh, &twin, viewport, "B: THE SAME ATTITUDE"),
    ];
    let pictures = vec![
        Picture::new(
            "lock_a",
            format!("the aircraft at {}", angles_label(locked)),
            attitude_panel(mesh, locked, viewport),
        ),
        Picture::new(
            "lock_b",
            format!(
                "the aircraft at {} (identical to lock_a)",
                angles_label(&twin)
            ),
            attitude_panel(mesh, &twin, viewport),
        ),
        Picture::new(
            "lock_pair",
            "A and B side by side inside their gimbal rings: different rings, one attitude",
            sheet(&pair, 2),
        ),
        Picture::new(
            "lock_sweep",
            "top: the first angle swept; bottom: the third angle swept; column by column the \
             same attitude, turned about the same axis",
            sheet(&sweep, shifts.len()),
        ),
    ];
    Some((pictures, twin))
}

/// The interpolation pictures from `a` to `b` ([`interpolation_panels`]): `euler_00` … and
/// `slerp_00` … one per frame, and the sheet `interpolation` (Euler lerp on top, slerp below).
pub fn interpolation_pictures(
    mesh: &EdgeMesh,
    a: &EulerAngles,
    b: &EulerAngles,
    frames: usize,
    viewport: Viewport,
) -> (Vec<Picture>, PathComparison) {
    let frames = frames.max(2);
    let (panels, comparison) = interpolation_panels(mesh, a, b, frames, viewport);
    let mut pictures = Vec::with_capacity(panels.len() + 1);
    for (i, p) in panels.iter().enumerate() {
        let (method, k) = if i < frames {
            ("euler", i)
        } else {
            ("slerp", i - frames)
        };
        let t = k as f64 / (frames - 1) as f64;
        let what = if method == "euler" {
            format!(
                "Euler-angle lerp at t = {t:.3}: {}",
                angles_label(&lerp(*a, *b, t))
            )
        } else {
            format!("quaternion slerp at t = {t:.3}")
        };
        pictures.push(Picture::new(format!("{method}_{k:02}"), what, p.clone()));
    }
    pictures.push(Picture::new(
        "interpolation",
        "top: Euler-angle lerp; bottom: slerp; paths of the nose and wing tips",
        sheet(&panels, frames),
    ));
    (pictures, comparison)
}
