//! Pictures of Euler angles: the aircraft after each elementary rotation with the rotation's
//! axis and path, the gimbal rings of a convention, gimbal lock, and Euler-angle interpolation
//! against slerp. Each picture is one or more panels ([`LineScene`]s of one size) that
//! [`sheet`] lays out in a grid, through the same pipeline as every other frame.
//!
//! Every panel looks at the body origin from the same fixed point (ahead, right and above,
//! world Z up), so that panels side by side are directly comparable: a camera that followed
//! the aircraft would hide what the angles do.
//!
//! Colours: the rotation of the first angle is drawn in [`palette::EULER_FIRST`], the second in
//! [`palette::EULER_SECOND`], the third in [`palette::EULER_THIRD`] — its axis, its path and its
//! gimbal ring alike. Pure: no I/O.

use glam::{DMat3, DVec3, Mat4, Vec2, Vec3};

use super::{palette, text};
use crate::camera::{Camera, Projection};
use crate::clip::{ClipStats, Clipper, DepthRange};
use crate::euler::{compare_paths, lerp, slerp, EulerAngles, Frame, PathComparison, Step};
use crate::mesh::EdgeMesh;
use crate::pipeline::{EdgeProjector, Viewport};
use crate::render::{LineBatch, LineScene, Rgba, Segment2};

/// Vertical field of view of the panels, degrees.
const FOV_Y_DEG: f32 = 40.0;
/// Direction from the body origin to the eye: ahead and to the right (−Y) of the aircraft at
/// rest, above: a three-quarter view in which yaw, pitch and roll all show.
const EYE_DIRECTION: Vec3 = Vec3::new(0.45, -0.80, 0.42);
/// Radii of the gimbal rings, outer to inner, in bounding radii of the aircraft: the inner one
/// clears the aircraft.
pub const RING_RADII: [f32; 3] = [1.38, 1.23, 1.08];
/// Half-length of a drawn rotation axis, bounding radii.
const AXIS_HALF_LENGTH: f32 = 1.5;
/// Length of the world axes drawn at the origin, bounding radii.
const WORLD_AXIS_LENGTH: f32 = 0.45;
/// Points on a ring or an arc.
const ARC_POINTS: usize = 48;
/// Pixels per glyph-grid unit of the captions.
const CAPTION_SCALE: f32 = 2.0;

/// The colour of the rotation of angle `slot` (0, 1, 2).
pub fn slot_color(slot: usize) -> Rgba {
    match slot {
        0 => palette::EULER_FIRST,
        1 => palette::EULER_SECOND,
        _ => palette::EULER_THIRD,
    }
}

/// Model matrix of a body → world rotation about the origin.
fn model(attitude: DMat3) -> Mat4 {
    Mat4::from_mat3(attitude.as_mat3())
}

/// The angle as a caption: `+30°`, `-12.5°` (at most one decimal, no `-0`).
pub fn degrees_label(radians: f64) -> String {
    let d = (radians.to_degrees() * 10.0).round() / 10.0 + 0.0;
    let digits = if d.fract() == 0.0 {
        format!("{d:.0}")
    } else {
        format!("{d:.1}")
    };
    if d > 0.0 {
        format!("+{digits}°")
    } else {
        format!("{digits}°")
    }
}

/// `Z`, `Y'`, `X''`: the axis a rotation of `convention` turns about, primed once per earlier
/// rotation when the axes move with the body (intrinsic), plain when they are fixed.
pub fn axis_label(e: &EulerAngles, slot: usize) -> String {
    let axis = e.convention.sequence.axes()[slot]
        .name()
        .to_ascii_uppercase();
    match e.convention.frame {
        Frame::Intrinsic => format!("{axis}{}", "'".repeat(slot)),
        Frame::Extrinsic => axis.to_string(),
    }
}

/// The three angles as a caption, e.g. `Z+60° Y'+90° X''0°`.
pub fn angles_label(e: &EulerAngles) -> String {
    (0..3)
        .map(|k| format!("{}{}", axis_label(e, k), degrees_label(e.angles[k])))
        .collect::<Vec<_>>()
        .join(" ")
}

/// What a panel must show whole: the aircraft (rotation axes may run off the edges) or the
/// aircraft in its gimbal rings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reach {
    /// The aircraft's bounding sphere.
    Aircraft,
    /// The outer ring and its axles.
    Rings,
}

impl Reach {
    /// Radius to frame, in bounding radii of the aircraft.
    fn radii(self) -> f32 {
        match self {
            Reach::Aircraft => 1.05,
            Reach::Rings => RING_RADII[0] + 0.2,
        }
    }
}

/// Pixels at the top of a panel kept for two caption lines.
const CAPTION_SPACE: f32 = 2.0 * (text::CAP_HEIGHT + 4.0) * CAPTION_SCALE + 6.0;

/// One panel under construction: a fixed camera framing `mesh` with room for the rings, and
/// batches appended in drawing order.
pub struct Panel<'m> {
    mesh: &'m EdgeMesh,
    radius: f32,
    viewport: Viewport,
    clip_from_world: Mat4,
    projector: EdgeProjector,
    scene: LineScene,
    stats: ClipStats,
}

impl<'m> Panel<'m> {
    /// An empty panel of `viewport`'s size for the aircraft `mesh` (body axes, rotated about
    /// the body origin), framing `reach` (what must fit) below two caption lines.
    pub fn new(mesh: &'m EdgeMesh, viewport: Viewport, reach: Reach) -> Self {
        let (centre, r) = mesh.bounding_sphere();
        let reach = r * reach.radii() + centre.length();
        let fov = FOV_Y_DEG.to_radians();
        let tan = (0.5 * fov).tan();
        // The picture below the captions: its height as a fraction of the whole.
        let h = viewport.height as f32;
        let below = ((h - CAPTION_SPACE) / h).clamp(0.5, 1.0);
        let fit = (tan * viewport.aspect()).min(tan * below);
        let distance = reach / fit.max(1e-4);
        // Pan up by half the caption space so that the subject sits in the middle of the rest.
        let up = (1.0 - below) * distance * tan;
        let camera = Camera {
            eye: EYE_DIRECTION.normalize() * distance,
            target: Vec3::ZERO,
            up: Vec3::Z,
            projection: Projection::Perspective {
                fov_y: fov,
                near: 0.05 * r,
                far: distance + 10.0 * reach,
            },
        }
        .panned(0.0, up);
        Self {
            mesh,
            radius: r,
            viewport,
            clip_from_world: camera.clip_from_world(viewport.aspect(), DepthRange::ZeroToOne),
            projector: EdgeProjector::new(Clipper::Blinn, DepthRange::ZeroToOne),
            scene: LineScene {
                width: viewport.width,
                height: viewport.height,
                background: palette::BACKGROUND,
                batches: Vec::new(),
            },
            stats: ClipStats::default(),
        }
    }

    /// The aircraft's bounding radius (the unit of the rings and axes).
    pub fn radius(&self) -> f32 {
        self.radius
    }

    fn batch(&mut self, color: Rgba) -> &mut Vec<Segment2> {
        self.scene.batches.push(LineBatch {
            color,
            segments: Vec::new(),
        });
        &mut self.scene.batches.last_mut().expect("just pushed").segments
    }

    /// The aircraft in `attitude` (body → world about the origin).
    pub fn aircraft(&mut self, attitude: DMat3, color: Rgba) -> &mut Self {
        let clip_from_model = self.clip_from_world * model(attitude);
        let mesh = self.mesh;
        let mut segments = Vec::new();
        let stats = self
            .projector
            .project(mesh, clip_from_model, self.viewport, &mut segments);
        self.stats.merge(&stats);
        *self.batch(color) = segments;
        self
    }

    /// A polyline through `points` (world coordinates).
    pub fn polyline(&mut self, points: &[Vec3], color: Rgba) -> &mut Self {
        let mut segments = Vec::new();
        let stats = self.projector.project_polyline(
            points,
            &[],
            self.clip_from_world,
            self.viewport,
            &mut segments,
        );
        self.stats.merge(&stats);
        *self.batch(color) = segments;
        self
    }

    /// The world axes X, Y, Z as short dim lines from the origin (red, green, blue).
    pub fn world_axes(&mut self) -> &mut Self {
        let l = WORLD_AXIS_LENGTH * self.radius;
        for (axis, color) in [
            (Vec3::X, palette::WORLD_X),
            (Vec3::Y, palette::WORLD_Y),
            (Vec3::Z, palette::WORLD_Z),
        ] {
            self.polyline(&[Vec3::ZERO, axis * l], color);
        }
        self
    }

    /// A rotation axis through the body origin along `direction`, with an arrowhead at the
    /// positive end (the right-hand rule's thumb).
    pub fn rotation_axis(&mut self, direction: DVec3, color: Rgba) -> &mut Self {
        let d = direction.normalize_or_zero().as_vec3();
        if d == Vec3::ZERO {
            return self;
        }
        let tip = d * AXIS_HALF_LENGTH * self.radius;
        self.polyline(&[-tip, tip], color);
        // Arrowhead: two short strokes back from the tip, in a plane containing the axis.
        let side = d.any_orthonormal_vector() * 0.08 * self.radius;
        let back = tip - d * 0.16 * self.radius;
        self.polyline(&[back + side, tip, back - side], color);
        self
    }

    /// The path of body point `p` (body coordinates) through the attitudes `path`.
    pub fn trace(&mut self, p: Vec3, path: &[DMat3], color: Rgba) -> &mut Self {
        let points: Vec<Vec3> = path.iter().map(|m| m.as_mat3() * p).collect();
        self.polyline(&points, color)
    }

    /// The three gimbal rings of `e`, outer to inner in the order of the intrinsic reading (for
    /// an extrinsic convention that is the order of the angles reversed), each in its angle's
    /// colour, with the axles that join them (module docs of [`gimbal_rings`]).
    pub fn rings(&mut self, e: &EulerAngles) -> &mut Self {
        for ring in gimbal_rings(e) {
            let scale = self.radius;
            let points: Vec<Vec3> = ring.circle.iter().map(|p| *p * scale).collect();
            let axle: Vec<Vec3> = ring.axle.iter().map(|p| *p * scale).collect();
            self.polyline(&points, ring.color);
            self.polyline(&axle[..2], ring.color);
            self.polyline(&axle[2..], ring.color);
        }
        self
    }

    /// A caption at the top left (first line) or below the previous lines (`line` > 0).
    pub fn caption(&mut self, line: usize, words: &str, color: Rgba) -> &mut Self {
        let line_height = (text::CAP_HEIGHT + 4.0) * CAPTION_SCALE;
        let origin = Vec2::new(
            6.0,
            6.0 + line_height * line as f32 + text::CAP_HEIGHT * CAPTION_SCALE,
        );
        let mut segments = Vec::new();
        text::draw(words, origin, CAPTION_SCALE, &mut segments);
        *self.batch(color) = segments;
        self
    }

    /// The finished panel and the clipper's counts for everything in it.
    pub fn finish(self) -> (LineScene, ClipStats) {
        (self.scene, self.stats)
    }
}

/// One gimbal ring, in units of the aircraft's bounding radius, world coordinates about the
/// body origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Ring {
    /// Which angle turns it (0, 1, 2 in the convention's order).
    pub slot: usize,
    /// Its colour ([`slot_color`]).
    pub color: Rgba,
    /// Closed circle (first point repeated last).
    pub circle: Vec<Vec3>,
    /// Its two axle stubs, `[a0, a1, b0, b1]`: from this ring out to the ring (or frame)
    /// carrying it, along its rotation axis.
    pub axle: [Vec3; 4],
}

/// The gimbal that realises `e`: three nested rings, outermost first, for the intrinsic reading
/// a-b-c with angles (α, β, γ).
///
/// The outer ring turns by α about a, on axles fixed to the world; the middle ring turns by β
/// about b on axles in the outer ring; the inner ring turns by γ about c on axles in the
/// middle ring, and carries the aircraft. A ring contains its own axles and those of the ring
/// inside it, so the outer ring lies in the plane (a, b) turned by `R_a(α)`, the middle one in
/// (b, c) turned by `R_a(α)·R_b(β)`, and the inner one in (c, a) (proper Euler: c and the
/// unused axis) turned by the whole rotation. At gimbal lock the middle ring has turned into
/// the outer ring's plane, and the outer and inner rings turn about one axis.
pub fn gimbal_rings(e: &EulerAngles) -> [Ring; 3] {
    let intrinsic = e.convention.as_intrinsic();
    let reading = if e.convention.frame == Frame::Intrinsic {
        *e
    } else {
        e.other_frame()
    };
    let [a, b, c] = intrinsic.sequence.axes();
    let [alpha, beta, gamma] = reading.angles;
    let frames = [
        a.rotation(alpha),
        a.rotation(alpha) * b.rotation(beta),
        a.rotation(alpha) * b.rotation(beta) * c.rotation(gamma),
    ];
    let other = |x: DVec3, y: DVec3| {
        // The coordinate axis perpendicular to both unit axes x and y.
        x.cross(y).abs()
    };
    let in_planes = [
        (a.unit(), b.unit()),
        (b.unit(), c.unit()),
        (c.unit(), other(c.unit(), b.unit())),
    ];
    let turns = [a.unit(), b.unit(), c.unit()];
    std::array::from_fn(|k| {
        let m = frames[k];
        let (u, v) = in_planes[k];
        let r = f64::from(RING_RADII[k]);
        let outer = if k == 0 {
            r + 0.15
        } else {
            f64::from(RING_RADII[k - 1])
        };
        let mut circle: Vec<Vec3> = (0..ARC_POINTS)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / ARC_POINTS as f64;
                (m * ((u * t.cos() + v * t.sin()) * r)).as_vec3()
            })
            .collect();
        circle.push(circle[0]);
        let axis = m * turns[k];
        let axle = [axis * r, axis * outer, -axis * r, -axis * outer].map(DVec3::as_vec3);
        // Extrinsic: the intrinsic reading's ring k is the angle in slot 2 − k.
        let slot = match e.convention.frame {
            Frame::Intrinsic => k,
            Frame::Extrinsic => 2 - k,
        };
        Ring {
            slot,
            color: slot_color(slot),
            circle,
            axle,
        }
    })
}

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

#[cfg(test)]
mod tests;
