//! Euler angles: the viewer's z-y-x attitude ([`EulerZyx`]) and all 24 conventions
//! ([`Convention`], [`EulerAngles`]) ↔ rotation matrices and unit quaternions.
//!
//! [`EulerZyx`] is the attitude used everywhere in the viewer and the flight model: yaw ψ about
//! Z, pitch θ about Y, roll φ about X, `R = Rz(ψ)·Ry(θ)·Rx(φ)`, body → world, with its
//! gimbal-lock rule and the NED/FRD ↔ viewer conversion. [`EulerAngles`] generalises it to the
//! twelve sequences of the seed lecture, about rotating or fixed axes; its intrinsic z-y-x is
//! [`EulerZyx`] exactly (the same floating-point operations, tested bit for bit).
//!
//! # Conventions
//!
//! * Angles are in **radians**, right-hand rule, in the order of the sequence's axes:
//!   `angles = [α, β, γ]` for sequence a-b-c. Only [`EulerAngles::from_degrees`] /
//!   [`to_degrees`](EulerAngles::to_degrees) (and the command line) use degrees.
//! * Rotations are **active**: the matrix turns the body, mapping body coordinates to world
//!   coordinates (`world = R·body`), as in the README. Its transpose is the passive
//!   (world → body) change of coordinates.
//! * **Intrinsic** a-b-c (rotating axes, a, b′, c″): `R = R_a(α)·R_b(β)·R_c(γ)`.
//!   **Extrinsic** a-b-c (fixed axes, a then b then c): `R = R_c(γ)·R_b(β)·R_a(α)`. Hence
//!   intrinsic a-b-c with (α, β, γ) is extrinsic c-b-a with (γ, β, α)
//!   ([`EulerAngles::other_frame`]).
//! * glam 0.34's `EulerRot` uses the same definitions and argument order, name for name:
//!
//! | sequence | kind | intrinsic `R` | glam intrinsic | glam extrinsic (`R` reversed) |
//! |---|---|---|---|---|
//! | z-x-z | proper Euler | Rz(α)·Rx(β)·Rz(γ) | `ZXZ` | `ZXZEx` |
//! | x-y-x | proper Euler | Rx(α)·Ry(β)·Rx(γ) | `XYX` | `XYXEx` |
//! | y-z-y | proper Euler | Ry(α)·Rz(β)·Ry(γ) | `YZY` | `YZYEx` |
//! | z-y-z | proper Euler | Rz(α)·Ry(β)·Rz(γ) | `ZYZ` | `ZYZEx` |
//! | x-z-x | proper Euler | Rx(α)·Rz(β)·Rx(γ) | `XZX` | `XZXEx` |
//! | y-x-y | proper Euler | Ry(α)·Rx(β)·Ry(γ) | `YXY` | `YXYEx` |
//! | x-y-z | Tait–Bryan | Rx(α)·Ry(β)·Rz(γ) | `XYZ` | `XYZEx` |
//! | y-z-x | Tait–Bryan | Ry(α)·Rz(β)·Rx(γ) | `YZX` | `YZXEx` |
//! | z-x-y | Tait–Bryan | Rz(α)·Rx(β)·Ry(γ) | `ZXY` | `ZXYEx` |
//! | x-z-y | Tait–Bryan | Rx(α)·Rz(β)·Ry(γ) | `XZY` | `XZYEx` |
//! | z-y-x | Tait–Bryan | Rz(α)·Ry(β)·Rx(γ) — [`EulerZyx`] (ψ, θ, φ) | `ZYX` | `ZYXEx` |
//! | y-x-z | Tait–Bryan | Ry(α)·Rx(β)·Rz(γ) | `YXZ` | `YXZEx` |
//!
//! ([`Convention::to_glam`]; glam's extrinsic `XYZEx` with (α, β, γ) is Rz(γ)·Ry(β)·Rx(α).)
//!
//! # Inverse: ranges and gimbal lock
//!
//! Matrix or quaternion → angles ([`EulerAngles::from_matrix`], [`from_quat`](EulerAngles::from_quat),
//! [`convert`](EulerAngles::convert)) gives the principal solution:
//!
//! | kind | α and γ | β | lock (β singular) |
//! |---|---|---|---|
//! | Tait–Bryan | (−π, π] | [−π/2, π/2] | β = ±π/2 ([`Lock::Upper`] / [`Lock::Lower`]) |
//! | proper Euler | (−π, π] | [0, π] | β = 0 ([`Lock::Lower`]) or π ([`Lock::Upper`]) |
//!
//! At lock the first and third axes line up, so only one combination of α and γ is
//! determined. The answer, as [`EulerZyx::from_matrix`] gives it (roll = 0, yaw takes the whole
//! heading): **in the intrinsic reading, the third angle is 0 and the first takes the whole
//! turn** — for intrinsic a-b-c, γ = 0 and α carries α + ε·sin β·γ (Tait–Bryan) or
//! α + cos β·γ (proper Euler), where ε = +1 when a → b is cyclic (x → y → z → x) and −1
//! otherwise. An extrinsic convention is its intrinsic mirror with the angles reversed, so there
//! it is the **first** angle that is 0 and the third that carries the turn (the angle of the
//! rotation applied to the body first is 0 in both frames; glam's `…Ex` orders do the same).
//! The result's [`Solution::lock`] says whether this happened; the threshold is
//! [`LOCK_TOLERANCE`] (cos β or |sin β| below 1e-9).
//!
//! # Pitfalls
//!
//! * **Order**: z-y-x and x-y-z are different rotations for the same three numbers; the
//!   sequence names the axes in the order the angles are *given*.
//! * **Intrinsic vs extrinsic**: the same sequence about fixed axes is the reverse product;
//!   intrinsic z-y-x (yaw, pitch, roll) is extrinsic x-y-z (roll, pitch, yaw).
//! * **Active vs passive**: these matrices rotate the body (body → world). Libraries and papers
//!   that rotate the frame instead (world → body) give the transpose, i.e. all angles negated
//!   and the order reversed.
//! * **Degrees vs radians**: everything here is radians; convert at the boundary.
//! * **Ranges**: the same rotation has two solutions away from lock (Tait–Bryan: (α+π, π−β,
//!   γ+π); proper Euler: (α+π, −β, γ+π)); only the principal one is returned, so compare
//!   rotations, not angles, unless the input was already principal.
//!
//! # What the angles do
//!
//! [`EulerAngles::steps`] splits a rotation into its three elementary rotations in the order
//! they turn the body; [`EulerAngles::lock_coupling`] and [`EulerAngles::lock_twin`] say what
//! is left at gimbal lock; [`lerp`], [`slerp`] and [`compare_paths`] set interpolating the
//! angles against interpolating the rotation (the `wireflight euler` pictures).
//!
//! Pure math: no I/O.

mod convert;
mod sequence;
mod stages;
mod zyx;

pub use convert::{EulerAngles, Lock, NotRotation, Solution, LOCK_TOLERANCE};
pub use sequence::{Axis, Convention, Frame, ParseConventionError, Sequence};
pub use stages::{compare_paths, lerp, rotation_between, slerp, LockedPair, PathComparison, Step};
pub use zyx::{
    ned_from_viewer, rot_x, rot_y, rot_z, viewer_from_ned, EulerZyx, Gimbal, GIMBAL_LOCK_COS,
};
