//! The seed's "other ways to reject" (`clipping-sutherland-hodgman-liang-barsky-bresenham.txt`):
//!
//! * **Bounding volumes**: a whole object whose bounding sphere lies outside one plane of the
//!   volume is dropped before any per-edge work ([`sphere_outside`]). The test runs in model
//!   space: clip-space plane `π` is the model-space plane `Mᵀπ` (since `π·(M p) = (Mᵀπ)·p`),
//!   and the sphere is outside when its centre is more than its radius behind that plane.
//! * **Back faces**: in a closed mesh no face turned away from the eye is visible, so in a
//!   hidden-line drawing an edge is kept only if one of its faces faces the eye
//!   ([`facing`]). Back-face culling alone is exact hidden-line removal for convex meshes; in
//!   a concave one a front face can still hide another front face's edges.

use glam::{DVec3, Mat4, Vec3, Vec4};

use super::ClipVolume;

/// Whether the sphere `centre`, `radius` (model space) lies wholly outside some plane of
/// `volume` once mapped by `clip_from_model`, so nothing of the object inside it can be
/// visible. Conservative: a sphere that touches the volume, or is within a relative 1e-5 of
/// touching it, is kept. Computed in `f64`.
///
/// ```
/// use glam::{Mat4, Vec3};
/// use wireflight_geometry::clip::{cull, ClipVolume, DepthRange};
/// let v = ClipVolume::new(DepthRange::ZeroToOne);
/// // Clip space itself as "model" space (identity): a unit sphere at x = 5 (w = 1) is out.
/// assert!(cull::sphere_outside(Vec3::new(5.0, 0.0, 0.5), 1.0, Mat4::IDENTITY, &v));
/// assert!(!cull::sphere_outside(Vec3::new(1.5, 0.0, 0.5), 1.0, Mat4::IDENTITY, &v));
/// ```
pub fn sphere_outside(
    centre: Vec3,
    radius: f32,
    clip_from_model: Mat4,
    volume: &ClipVolume,
) -> bool {
    if !(centre.is_finite() && radius.is_finite() && clip_from_model.is_finite()) {
        return false; // nothing can be concluded; the clipper will see the edges
    }
    let m_t = clip_from_model.as_dmat4().transpose();
    let c = centre.as_dvec3().extend(1.0);
    let r = f64::from(radius.max(0.0));
    (0..volume.plane_count()).any(|i| {
        let plane = m_t * volume.plane(i).as_dvec4();
        let n = plane.truncate().length();
        let value = plane.dot(c);
        value < -(r * n) * (1.0 + 1e-5) - 1e-12 * value.abs()
    })
}

/// Which way triangle `a, b, c` (clip space, before the divide) faces the eye:
/// `det[x y w]` of its vertices, which is `w_a·w_b·w_c` times twice its signed area on the
/// screen and, for a perspective projection, a positive multiple of `n·(eye − a)`. Positive:
/// counter-clockwise on the screen (y up), i.e. facing the eye for a face wound
/// counter-clockwise seen from outside (OBJ's and glTF's convention). Needs no divide, so it
/// is right for vertices behind the eye too (Olano & Greer's homogeneous rasterisation).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::cull::facing;
/// let (a, b, c) = (Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(1.0, 0.0, 0.5, 1.0), Vec4::new(0.0, 1.0, 0.5, 1.0));
/// assert!(facing(a, b, c) > 0.0); // counter-clockwise: front
/// assert!(facing(a, c, b) < 0.0);
/// ```
pub fn facing(a: Vec4, b: Vec4, c: Vec4) -> f64 {
    let xyw = |p: Vec4| DVec3::new(f64::from(p.x), f64::from(p.y), f64::from(p.w));
    xyw(a).dot(xyw(b).cross(xyw(c)))
}
