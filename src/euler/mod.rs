//! Euler angles and their rotation matrices.
//!
//! [`EulerZyx`] (in `zyx.rs`) is the z-y-x Tait-Bryan attitude used everywhere in the viewer and
//! the flight model: yaw ψ about Z, pitch θ about Y, roll φ about X, `R = Rz(ψ)·Ry(θ)·Rx(φ)`,
//! body → world, with its gimbal-lock rule and the NED/FRD ↔ viewer conversion.
//! [`Convention`] names any of the 24 Euler-angle conventions (twelve [`Sequence`]s, intrinsic
//! or extrinsic [`Frame`]).
//!
//! Pure math: no I/O.

mod sequence;
mod zyx;

pub use sequence::{Axis, Convention, Frame, ParseConventionError, Sequence};
pub use zyx::{
    ned_from_viewer, rot_x, rot_y, rot_z, viewer_from_ned, EulerZyx, Gimbal, GIMBAL_LOCK_COS,
};
