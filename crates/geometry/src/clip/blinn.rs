//! Blinn's homogeneous line clipper (Blinn & Newell 1978; as taught in the seed lecture
//! `clipping-cohen-sutherland-and-blinn-3d.txt`).
//!
//! For an edge A→C, each endpoint gets six boundary coordinates (BCs) and a 6-bit outcode.
//! `a | c == 0` accepts the edge untouched, `a & c != 0` rejects it untouched. Otherwise the
//! edge is the parametric segment `P(t) = A + t·(C − A)`, `t ∈ [0, 1]`; every BC is linear in t,
//! so a plane the edge crosses is hit at `t_hit = BC_A / (BC_A − BC_C)`. Crossings where A is
//! outside raise `t_in`, crossings where C is outside lower `t_out`; as soon as
//! `t_in > t_out` the candidate interval is empty and the edge is gone. The survivors are
//! recomputed from the *original* A and C at `t_in` and `t_out`.
//!
//! Only planes that one endpoint is outside of are visited (the others cannot change the
//! interval), and there is no division by zero: a visited plane has one BC < 0 ≤ the other.
//!
//! The outcodes come from `f32` boundary coordinates (an overflow to ±∞ keeps its sign, so the
//! codes stay right), but the crossing parameters and the new endpoints of a non-trivial edge
//! are computed in `f64`: `BC_A − BC_C` and `C − A` overflow `f32` for coordinates near
//! `f32::MAX`, which would give t = 0 and NaN endpoints. Only edges that cross a plane pay.

use glam::Vec4;

use super::{
    boundary_coords, boundary_coords_of, outcode, settle, ClipOutcome, ClipVolume, DepthRange,
    PLANE_COUNT,
};

/// Clip the edge `a`→`c` (homogeneous clip coordinates) against the view volume.
///
/// Never panics and never allocates; non-finite input gives [`ClipOutcome::NonFinite`].
/// Points on a boundary plane count as inside.
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{clip_edge, ClipOutcome, DepthRange};
/// // From inside to beyond x = w: cut where x = w.
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(3.0, 0.0, 0.5, 1.0);
/// let ClipOutcome::Clipped(a2, c2) = clip_edge(a, c, DepthRange::ZeroToOne) else { panic!() };
/// assert_eq!(a2, a);
/// assert!((c2 - Vec4::new(1.0, 0.0, 0.5, 1.0)).abs().max_element() < 1e-6);
/// ```
#[inline]
pub fn clip_edge(a: Vec4, c: Vec4, depth: DepthRange) -> ClipOutcome {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let a_bc = boundary_coords(a, depth);
    let c_bc = boundary_coords(c, depth);
    let a_code = outcode(&a_bc);
    let c_code = outcode(&c_bc);

    if a_code & c_code != 0 {
        return ClipOutcome::Rejected;
    }
    if a_code | c_code == 0 {
        // Inside points have w ≥ 0; w = 0 only at the eye (0,0,0,0), whose segment to any
        // other point projects to a single point.
        return if a.w > 0.0 && c.w > 0.0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }

    clip_crossing(a, c, a_code, c_code, depth)
}

/// The non-trivial case of [`clip_edge`]: finite `a`, `c` with outcodes `a_code`, `c_code`
/// (six bits each, as [`outcode`] gives them) that are neither trivially accepted
/// (`a | c == 0`) nor rejected (`a & c != 0`). Shared with the batch path ([`super::batch`]),
/// so both give bit-identical segments.
#[inline]
pub fn clip_crossing(a: Vec4, c: Vec4, a_code: u8, c_code: u8, depth: DepthRange) -> ClipOutcome {
    debug_assert!(a_code & c_code == 0 && a_code | c_code != 0);
    debug_assert!(a.is_finite() && c.is_finite());
    let (a64, c64) = (a.as_dvec4(), c.as_dvec4());
    let a_bc = boundary_coords_of(a64.to_array(), depth);
    let c_bc = boundary_coords_of(c64.to_array(), depth);
    let mut t_in = 0.0f64;
    let mut t_out = 1.0f64;
    let crossed = a_code | c_code;
    for i in 0..PLANE_COUNT {
        if crossed & (1 << i) == 0 {
            continue; // both endpoints inside this plane: it cannot shorten the interval
        }
        let t_hit = a_bc[i] / (a_bc[i] - c_bc[i]);
        if c_code & (1 << i) != 0 {
            t_out = t_out.min(t_hit); // leaving: C is outside
        } else {
            t_in = t_in.max(t_hit); // entering: A is outside
        }
        if t_in > t_out {
            return ClipOutcome::ClippedAway; // empty candidate interval: early exit
        }
    }

    let d = c64 - a64;
    let a_out = if a_code != 0 {
        settle((a64 + t_in * d).as_vec4(), a64, c64, t_in, depth)
    } else {
        a
    };
    let c_out = if c_code != 0 {
        settle((a64 + t_out * d).as_vec4(), a64, c64, t_out, depth)
    } else {
        c
    };
    debug_assert!(t_in >= 0.0 && t_out <= 1.0 && t_in <= t_out);
    if a_out.w > 0.0 && c_out.w > 0.0 {
        ClipOutcome::Clipped(a_out, c_out)
    } else {
        ClipOutcome::ClippedAway
    }
}

/// [`clip_edge`] against a volume with extra planes: each extra plane's boundary coordinate is
/// the plane dotted with the point, visited like the six. With no extra planes this *is*
/// [`clip_edge`] (bit-identical).
///
/// ```
/// use glam::Vec4;
/// use wireflight_geometry::clip::{blinn, ClipOutcome, ClipVolume, DepthRange, PlaneSet};
/// // Keep x ≤ 0.5·w as well: the plane (−1, 0, 0, 0.5).
/// let mut extra = PlaneSet::default();
/// extra.push(Vec4::new(-1.0, 0.0, 0.0, 0.5)).unwrap();
/// let volume = ClipVolume::with_planes(DepthRange::ZeroToOne, extra);
/// let a = Vec4::new(0.0, 0.0, 0.5, 1.0);
/// let c = Vec4::new(1.0, 0.0, 0.5, 1.0);
/// let ClipOutcome::Clipped(_, c2) = blinn::clip_edge_in(a, c, &volume) else { panic!() };
/// assert_eq!(c2, Vec4::new(0.5, 0.0, 0.5, 1.0));
/// ```
#[inline]
pub fn clip_edge_in(a: Vec4, c: Vec4, volume: &ClipVolume) -> ClipOutcome {
    if volume.extra.is_empty() {
        return clip_edge(a, c, volume.depth);
    }
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let (a64, c64) = (a.as_dvec4(), c.as_dvec4());
    let a_bc = volume.boundary_coords(a64);
    let c_bc = volume.boundary_coords(c64);
    let n = volume.plane_count();
    let (mut a_code, mut c_code) = (0u32, 0u32);
    for i in 0..n {
        a_code |= u32::from(a_bc[i] < 0.0) << i;
        c_code |= u32::from(c_bc[i] < 0.0) << i;
    }
    if a_code & c_code != 0 {
        return ClipOutcome::Rejected;
    }
    if a_code | c_code == 0 {
        return if a.w > 0.0 && c.w > 0.0 {
            ClipOutcome::Accepted(a, c)
        } else {
            ClipOutcome::ClippedAway
        };
    }
    let mut t_in = 0.0f64;
    let mut t_out = 1.0f64;
    for i in 0..n {
        if (a_code | c_code) & (1 << i) == 0 {
            continue;
        }
        let t_hit = a_bc[i] / (a_bc[i] - c_bc[i]);
        if c_code & (1 << i) != 0 {
            t_out = t_out.min(t_hit);
        } else {
            t_in = t_in.max(t_hit);
        }
        if t_in > t_out {
            return ClipOutcome::ClippedAway;
        }
    }
    let d = c64 - a64;
    let a_out = if a_code != 0 {
        settle((a64 + t_in * d).as_vec4(), a64, c64, t_in, volume.depth)
    } else {
        a
    };
    let c_out = if c_code != 0 {
        settle((a64 + t_out * d).as_vec4(), a64, c64, t_out, volume.depth)
    } else {
        c
    };
    debug_assert!(t_in >= 0.0 && t_out <= 1.0 && t_in <= t_out);
    if a_out.w > 0.0 && c_out.w > 0.0 {
        ClipOutcome::Clipped(a_out, c_out)
    } else {
        ClipOutcome::ClippedAway
    }
}
