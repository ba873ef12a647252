//! The clip volume as a set of half-spaces of homogeneous space: the six planes of the view
//! volume plus up to [`MAX_USER_PLANES`] extra ones (cut-away views).
//!
//! Every boundary coordinate is a plane dotted with the point: BC0 = w + x is
//! `(1, 0, 0, 1)·(x, y, z, w)`, BC1 = w − x is `(−1, 0, 0, 1)·P`, and so on ([`view_plane`]).
//! An extra plane `(a, b, c, d)` adds BC = `a·x + b·y + c·z + d·w`, visible where ≥ 0: Blinn's
//! boundary coordinate generalised, so every homogeneous clipper handles extra planes with
//! the code it uses for the six. Planes here are in **clip space**; a plane given in model
//! space `π` becomes `M⁻ᵀ·π` for `M` = clip_from_model ([`PlaneSet::transformed`]), since
//! `π·p = (M⁻ᵀπ)·(M p)`.

use glam::{DVec4, Mat4, Vec4};

use super::{boundary_coords_of, DepthRange, PLANE_COUNT};

/// Most extra clip planes a [`PlaneSet`] holds.
pub const MAX_USER_PLANES: usize = 8;

/// Why a plane could not be added.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlaneError {
    /// A coefficient is NaN or infinite.
    #[error("the plane's coefficients must be finite numbers")]
    NonFinite,
    /// `a = b = c = 0`: not a plane.
    #[error("a, b and c are all zero: that is not a plane")]
    NoNormal,
    /// More than [`MAX_USER_PLANES`].
    #[error("at most {MAX_USER_PLANES} clip planes")]
    TooMany,
}

/// Up to [`MAX_USER_PLANES`] planes `(a, b, c, d)`, each keeping the points with
/// `a·x + b·y + c·z + d·w ≥ 0`. Fixed capacity and `Copy`: no allocation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlaneSet {
    planes: [Vec4; MAX_USER_PLANES],
    len: u8,
}

impl PlaneSet {
    /// No planes.
    pub const EMPTY: PlaneSet = PlaneSet {
        planes: [Vec4::ZERO; MAX_USER_PLANES],
        len: 0,
    };

    /// Add a plane `(a, b, c, d)`: keep `a·x + b·y + c·z + d·w ≥ 0`.
    ///
    /// # Errors
    /// Non-finite coefficients, `a = b = c = 0`, or a full set.
    pub fn push(&mut self, plane: Vec4) -> Result<(), PlaneError> {
        if !plane.is_finite() {
            return Err(PlaneError::NonFinite);
        }
        if plane.truncate() == glam::Vec3::ZERO {
            return Err(PlaneError::NoNormal);
        }
        let i = usize::from(self.len);
        if i == MAX_USER_PLANES {
            return Err(PlaneError::TooMany);
        }
        self.planes[i] = plane;
        self.len += 1;
        Ok(())
    }

    /// The planes, in the order added.
    pub fn as_slice(&self) -> &[Vec4] {
        &self.planes[..usize::from(self.len)]
    }

    /// Number of planes.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The planes in the space that `m` maps into: `π' = M⁻ᵀ·π` (computed in `f64`), so that
    /// `π'·(M p) = π·p`. A plane given in model space and `m` = clip_from_model gives the plane
    /// in clip space. `None` if `m` is not invertible (or a result is not finite).
    pub fn transformed(&self, m: Mat4) -> Option<PlaneSet> {
        if self.is_empty() {
            return Some(*self);
        }
        let inv_t = m.as_dmat4().inverse().transpose();
        let mut out = PlaneSet::EMPTY;
        for p in self.as_slice() {
            let q = (inv_t * p.as_dvec4()).as_vec4();
            if !q.is_finite() || q == Vec4::ZERO {
                return None;
            }
            out.planes[usize::from(out.len)] = q;
            out.len += 1;
        }
        inv_t.is_finite().then_some(out)
    }
}

/// The plane vector of view-volume plane `i` (0..6): BC_i = `view_plane(i, depth)·P`.
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{boundary_coords, view_plane, DepthRange, PLANE_COUNT};
/// let p = Vec4::new(5.0, 2.0, 7.0, 10.0);
/// let bc = boundary_coords(p, DepthRange::NegOneToOne);
/// for i in 0..PLANE_COUNT {
///     assert_eq!(view_plane(i, DepthRange::NegOneToOne).dot(p), bc[i]);
/// }
/// ```
pub fn view_plane(i: usize, depth: DepthRange) -> Vec4 {
    let near_w = match depth {
        DepthRange::ZeroToOne => 0.0,
        DepthRange::NegOneToOne => 1.0,
    };
    match i {
        0 => Vec4::new(1.0, 0.0, 0.0, 1.0),
        1 => Vec4::new(-1.0, 0.0, 0.0, 1.0),
        2 => Vec4::new(0.0, 1.0, 0.0, 1.0),
        3 => Vec4::new(0.0, -1.0, 0.0, 1.0),
        4 => Vec4::new(0.0, 0.0, 1.0, near_w),
        _ => Vec4::new(0.0, 0.0, -1.0, 1.0),
    }
}

/// The view volume of a depth range, cut by extra planes (clip space): what the homogeneous
/// clippers clip against. `Copy`, fixed size.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClipVolume {
    /// Depth convention of the six view planes.
    pub depth: DepthRange,
    /// Extra planes, clip space.
    pub extra: PlaneSet,
}

impl ClipVolume {
    /// The view volume alone.
    pub const fn new(depth: DepthRange) -> Self {
        Self {
            depth,
            extra: PlaneSet::EMPTY,
        }
    }

    /// The view volume cut by `extra` (clip-space planes).
    pub const fn with_planes(depth: DepthRange, extra: PlaneSet) -> Self {
        Self { depth, extra }
    }

    /// Six plus the number of extra planes.
    #[inline]
    pub fn plane_count(&self) -> usize {
        PLANE_COUNT + self.extra.len()
    }

    /// Plane `i` as a vector: the view planes first (in the outcode order), then the extras.
    #[inline]
    pub fn plane(&self, i: usize) -> Vec4 {
        if i < PLANE_COUNT {
            view_plane(i, self.depth)
        } else {
            self.extra.as_slice()[i - PLANE_COUNT]
        }
    }

    /// Boundary coordinate `i` of `p` in `f64`. For the six view planes it is the same
    /// expression as [`boundary_coords_of`] (so the same rounding); for an extra plane the
    /// dot product `a·x + b·y + c·z + d·w`.
    #[inline]
    pub fn boundary_coord(&self, i: usize, p: DVec4) -> f64 {
        if i < PLANE_COUNT {
            boundary_coords_of(p.to_array(), self.depth)[i]
        } else {
            self.extra.as_slice()[i - PLANE_COUNT].as_dvec4().dot(p)
        }
    }

    /// All boundary coordinates of `p` (`f64`), the first [`plane_count`](Self::plane_count)
    /// entries used.
    #[inline]
    pub fn boundary_coords(&self, p: DVec4) -> [f64; PLANE_COUNT + MAX_USER_PLANES] {
        let mut bc = [0.0; PLANE_COUNT + MAX_USER_PLANES];
        let six = boundary_coords_of(p.to_array(), self.depth);
        bc[..PLANE_COUNT].copy_from_slice(&six);
        for (k, e) in self.extra.as_slice().iter().enumerate() {
            bc[PLANE_COUNT + k] = e.as_dvec4().dot(p);
        }
        bc
    }

    /// Outcode over every plane: bit i set when BC_i < 0. The six view-plane bits are
    /// exactly [`super::outcode`]'s (the sign of an `f64` sum of two `f32`s is exact).
    #[inline]
    pub fn outcode(&self, p: Vec4) -> u32 {
        let bc = self.boundary_coords(p.as_dvec4());
        let mut code = 0u32;
        for (i, &b) in bc[..self.plane_count()].iter().enumerate() {
            code |= u32::from(b < 0.0) << i;
        }
        code
    }

    /// Whether `p` is inside every plane, each boundary coordinate ≥ −`rel_tol`·max|p_k|.
    pub fn contains(&self, p: Vec4, rel_tol: f64) -> bool {
        let slack = rel_tol * f64::from(p.abs().max_element());
        let bc = self.boundary_coords(p.as_dvec4());
        bc[..self.plane_count()].iter().all(|&b| b >= -slack)
    }
}
