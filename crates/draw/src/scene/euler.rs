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

use super::{font, palette};
use crate::render::{LineBatch, LineScene, Rgba, Segment2};
use wireflight_data::format::signed;
use wireflight_geometry::camera::{Camera, Projection};
use wireflight_geometry::clip::{ClipStats, Clipper, DepthRange};
use wireflight_geometry::euler::{EulerAngles, Frame};
use wireflight_geometry::mesh::EdgeMesh;
use wireflight_geometry::pipeline::{EdgeProjector, Viewport};

mod pictures;
pub use pictures::{
    attitude_panel, gimbal_lock_pictures, gimbal_panel, interpolation_panels,
    interpolation_pictures, lock_partner, lock_sweep_panels, sheet, step_panels, steps_pictures,
    Picture, SWEEP_DEG,
};

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

/// The angle as a caption: `+30°`, `-12.5°`, `0°` (at most one decimal, none when it is 0;
/// zero unsigned).
pub fn degrees_label(radians: f64) -> String {
    let d = (radians.to_degrees() * 10.0).round() / 10.0;
    if d == 0.0 {
        return "0°".to_string();
    }
    let decimals = if d.fract() == 0.0 { 0 } else { 1 };
    format!("{}°", signed(d, decimals))
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
const CAPTION_SPACE: f32 = 2.0 * (font::CAP_HEIGHT + 4.0) * CAPTION_SCALE + 6.0;

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
        let line_height = (font::CAP_HEIGHT + 4.0) * CAPTION_SCALE;
        let origin = Vec2::new(
            6.0,
            6.0 + line_height * line as f32 + font::CAP_HEIGHT * CAPTION_SCALE,
        );
        let mut segments = Vec::new();
        font::draw_crisp(words, origin, CAPTION_SCALE, &mut segments);
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

#[cfg(test)]
mod tests;
