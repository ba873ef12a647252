//! `wireflight euler` options and the parsers of conventions, angles, matrices and quaternions.

use std::path::PathBuf;

use clap::{ArgGroup, Args};

use super::finite_f64;
use crate::geometry::euler::{Convention, Sequence};

pub(super) fn parse_convention(s: &str) -> Result<Convention, String> {
    s.parse().map_err(|e| format!("{e}"))
}

const EULER_EXAMPLES: &str = "\
Examples:
  wireflight euler --seq zyx --angles 30,20,10 --json
  wireflight euler --seq zyx --angles 30,20,10 --to xyz,extrinsic       # the same rotation
  wireflight euler --seq zxz --extrinsic --angles -45,30,10 --to quat
  wireflight euler --seq zyx --angles 0.5,-0.2,1 --radians --to matrix
  wireflight euler --seq zyx --from-matrix 0,-1,0,1,0,0,0,0,1
  wireflight euler --seq zyz --from-quat 0.9239,0,0,0.3827 --json
  wireflight euler --seq zyx --angles 30,60,45 --steps --out steps/
  wireflight euler --seq zyx --gimbal-lock --out lock/
  wireflight euler --seq zyx --interpolate --from-angles 0,0,0 --to-angles 90,60,90 \\
      --frames 5 --out interp/

Pure-math conventions: unlike render, view and flight data (aerospace angles: + nose right,
+ nose up, + right wing down), the lab takes right-hand rotations about the axes it names,
in the pictures nose +X, left wing +Y, up +Z, so zyx pitch +20 lowers the nose there.
The sequence names the axes in the order the angles are given (zyx: yaw about
Z, pitch about Y, roll about X). Intrinsic (default): each rotation about the axes as the
earlier ones turned them, R = Ra(A)·Rb(B)·Rc(C). Extrinsic: about the fixed axes, A first,
R = Rc(C)·Rb(B)·Ra(A); intrinsic a-b-c equals extrinsic c-b-a with the angles reversed.
Matrices are active, body -> world (world = R·body), printed and read row by row;
quaternions are [w, x, y, z] with w >= 0. Angles are degrees unless --radians.
Matrix/quaternion -> angles gives the principal solution: Tait-Bryan B in [-90°, 90°],
proper Euler B in [0°, 180°], A and C in (-180°, 180°]; at gimbal lock (B at an end) the
first and third axes coincide, and the third angle (extrinsic: the first) is set to 0.

Pictures (--out DIR, written as a whole; a DIR from an earlier run is replaced):
  --steps        step_0..3.png after each elementary rotation, with its axis and path,
                 and steps.png (all four)
  --gimbal-lock  lock_a.png and lock_b.png: one attitude from two angle triples at lock;
                 lock_pair.png: both in their gimbal rings; lock_sweep.png: the first and
                 the third angle turn the aircraft about the same axis
  --interpolate  euler_NN.png and slerp_NN.png, and interpolation.png: linear Euler-angle
                 interpolation (top) against quaternion slerp (bottom)";

/// `wireflight euler` options.
#[derive(Debug, Args)]
#[command(after_help = EULER_EXAMPLES)]
#[command(group(ArgGroup::new("input").args(["angles", "from_matrix", "from_quat"])))]
#[command(group(ArgGroup::new("picture").args(["steps", "gimbal_lock", "interpolate"])))]
pub struct EulerArgs {
    /// Rotation sequence: three axes, no two neighbours equal (zyx, z-y-x, zxz, ...).
    #[arg(long, default_value = "zyx", value_name = "SEQ", value_parser = parse_sequence)]
    pub seq: Sequence,
    /// The axes stay fixed in the world (extrinsic) instead of turning with the body.
    #[arg(long)]
    pub extrinsic: bool,
    /// The three angles, in the order of --seq's axes.
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true, value_parser = parse_angles)]
    pub angles: Option<[f64; 3]>,
    /// Angles are in degrees (the default).
    #[arg(long, conflicts_with = "radians")]
    pub degrees: bool,
    /// Angles are in radians.
    #[arg(long)]
    pub radians: bool,
    /// What to print: the matrix, the quaternion, or the angles in another convention
    /// (`SEQ[,extrinsic]`); by default all of them in the input convention.
    #[arg(long, value_name = "matrix|quat|SEQ[,extrinsic]", value_parser = parse_euler_target, conflicts_with = "picture")]
    pub to: Option<EulerTarget>,
    /// Machine-readable output on stdout: matrix, quaternion, angles_deg, gimbal_lock, ...
    #[arg(long, conflicts_with = "picture")]
    pub json: bool,
    /// Start from a rotation matrix (body -> world), nine numbers row by row.
    #[arg(long, value_name = "R00,R01,...,R22", allow_hyphen_values = true, value_parser = parse_matrix)]
    pub from_matrix: Option<[f64; 9]>,
    /// Start from a quaternion W,X,Y,Z (normalised if it is not a unit one).
    #[arg(long, value_name = "W,X,Y,Z", allow_hyphen_values = true, value_parser = parse_quat)]
    pub from_quat: Option<[f64; 4]>,
    /// Pictures of the aircraft after each elementary rotation (needs --out).
    #[arg(long, requires = "out")]
    pub steps: bool,
    /// Pictures of gimbal lock (needs --out); --angles, if given, must be at lock.
    #[arg(long, requires = "out")]
    pub gimbal_lock: bool,
    /// Pictures of Euler-angle lerp against slerp from --from-angles to --to-angles (needs
    /// --out).
    #[arg(long, requires_all = ["out", "from_angles", "to_angles"], conflicts_with = "input")]
    pub interpolate: bool,
    /// Start attitude of --interpolate, in the --seq convention.
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true, value_parser = parse_angles, requires = "interpolate")]
    pub from_angles: Option<[f64; 3]>,
    /// End attitude of --interpolate, in the --seq convention.
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true, value_parser = parse_angles, requires = "interpolate")]
    pub to_angles: Option<[f64; 3]>,
    /// Frames per row of --interpolate, the two ends included.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u16).range(2..=25))]
    pub frames: u16,
    /// Directory for the pictures (PNG), created or replaced as a whole.
    #[arg(long, value_name = "DIR", requires = "picture")]
    pub out: Option<PathBuf>,
    /// Size of each picture, WIDTHxHEIGHT (sheets are several of them).
    #[arg(long, default_value = "320x240", value_parser = parse_panel_size)]
    pub size: (u32, u32),
    /// The wireframe: `plane` for the built-in aircraft, or a mesh file (.obj, .gltf, .glb).
    #[arg(long, default_value = "plane", value_name = "plane|FILE")]
    pub mesh: String,
}

impl EulerArgs {
    /// The convention of the input angles.
    pub fn convention(&self) -> Convention {
        if self.extrinsic {
            Convention::extrinsic(self.seq)
        } else {
            Convention::intrinsic(self.seq)
        }
    }
}

/// What `wireflight euler --to` prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EulerTarget {
    /// The rotation matrix.
    Matrix,
    /// The unit quaternion.
    Quat,
    /// The angles in another convention.
    Angles(Convention),
}

pub(super) fn parse_sequence(s: &str) -> Result<Sequence, String> {
    s.parse().map_err(|e| format!("{e}"))
}

pub(super) fn parse_euler_target(s: &str) -> Result<EulerTarget, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "matrix" => Ok(EulerTarget::Matrix),
        "quat" | "quaternion" => Ok(EulerTarget::Quat),
        _ => s
            .parse()
            .map(EulerTarget::Angles)
            .map_err(|e| format!("{e}; or `matrix` or `quat`")),
    }
}

/// `N` comma-separated finite numbers.
pub fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers ({what}), got {}",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (i, p) in parts.iter().enumerate() {
        out[i] = finite_f64(p.trim())?;
    }
    Ok(out)
}

pub(super) fn parse_angles(s: &str) -> Result<[f64; 3], String> {
    parse_numbers(s, "A,B,C")
}

pub(super) fn parse_matrix(s: &str) -> Result<[f64; 9], String> {
    parse_numbers(s, "R00,R01,R02,R10,R11,R12,R20,R21,R22, row by row")
}

pub(super) fn parse_quat(s: &str) -> Result<[f64; 4], String> {
    parse_numbers(s, "W,X,Y,Z")
}

/// Largest side of one Euler picture: sheets hold up to 50 of them.
pub const MAX_PANEL_SIDE: u32 = 2048;

pub(super) fn parse_panel_size(s: &str) -> Result<(u32, u32), String> {
    // The panel's own range, stated for every side out of it (not the general 1..=16384 of
    // other sizes, which a panel is not allowed).
    let range = || format!("each side must be in 64..={MAX_PANEL_SIDE} pixels");
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT (e.g. 320x240); {}", range()))?;
    let side = |t: &str, name: &str| -> Result<u32, String> {
        let v: u64 = t
            .trim()
            .parse()
            .map_err(|_| format!("{name} `{t}` is not a whole number; {}", range()))?;
        u32::try_from(v)
            .ok()
            .filter(|v| (64..=MAX_PANEL_SIDE).contains(v))
            .ok_or_else(|| format!("{name} {v} is outside 64..={MAX_PANEL_SIDE} pixels"))
    };
    Ok((side(w, "width")?, side(h, "height")?))
}
