//! `wireflight euler`: Euler angles in any of the 24 conventions ↔ matrix ↔ quaternion, as text
//! or JSON, and the pictures of [`crate::draw::scene::euler`] written into a directory as a whole.
//!
//! Thin: the numbers come from [`crate::geometry::euler`], the pictures from
//! [`crate::draw::scene::euler`], the files go through [`crate::fsio::write_dir_atomic`].

use std::fmt::Write as _;

use anyhow::{bail, Context};
use glam::{DMat3, DQuat};
use serde_json::{json, Value};

use crate::app::cli::{EulerArgs, EulerTarget};
use crate::draw::render::Rasterizer;
use crate::draw::scene::euler::{
    angles_label, gimbal_lock_pictures, interpolation_pictures, steps_pictures, Picture,
};
use crate::fsio::write_dir_atomic;
use crate::geometry::euler::{Convention, EulerAngles, Lock, Solution};
use crate::geometry::pipeline::Viewport;

/// How far from orthonormal a `--from-matrix` may be: max |RᵀR − I|. Nine numbers typed with
/// six significant digits are within about 1e-6; 1e-4 lets four or five digits through.
pub const MATRIX_TOLERANCE: f64 = 1e-4;
/// The manifest written with the pictures; its presence marks a directory as this command's.
pub const MANIFEST: &str = "wireflight-euler.txt";
/// Most pixels in one picture (a sheet): 50 million, 200 MB of RGBA.
const MAX_SHEET_PIXELS: u64 = 50_000_000;

/// Where the rotation came from.
enum Given {
    /// Angles in the input convention, and as typed in degrees (so that 30 is printed back as
    /// 30, not as 29.999999999999996 from a round trip through radians).
    Angles(EulerAngles, [f64; 3]),
    /// A rotation matrix (row-major as typed).
    Matrix([f64; 9]),
    /// A quaternion `[w, x, y, z]` as typed.
    Quat([f64; 4]),
}

/// Run `wireflight euler`.
///
/// # Errors
/// Bad input (named by option: wrong count, non-finite, not a rotation, zero quaternion,
/// angles not at lock for `--gimbal-lock`), unreadable meshes, unwritable output.
pub fn run(args: &EulerArgs) -> anyhow::Result<()> {
    let convention = args.convention();
    check_radians(args)?;
    let given = given(args, convention);
    if args.interpolate {
        let (Some(a), Some(b)) = (args.from_angles, args.to_angles) else {
            bail!("--interpolate needs --from-angles A,B,C and --to-angles A,B,C");
        };
        let a = EulerAngles::new(convention, typed_radians(args, a));
        let b = EulerAngles::new(convention, typed_radians(args, b));
        return interpolate(args, &a, &b);
    }
    if args.gimbal_lock {
        let locked = locked_angles(given.as_ref(), convention)?;
        return gimbal_lock(args, &locked);
    }
    let Some(given) = given else {
        bail!(
            "give the rotation: --angles A,B,C, --from-matrix R00,...,R22 or --from-quat W,X,Y,Z"
        );
    };
    let solution = solve(&given, convention)?;
    if args.steps {
        return steps(args, &solution.euler);
    }
    print_numbers(args, &given, solution)
}

/// Refuse angles typed in radians beyond [`MAX_RADIANS`].
fn check_radians(args: &EulerArgs) -> anyhow::Result<()> {
    if !args.radians {
        return Ok(());
    }
    for (option, angles) in [
        ("--angles", args.angles),
        ("--from-angles", args.from_angles),
        ("--to-angles", args.to_angles),
    ] {
        if let Some(x) = angles.iter().flatten().find(|x| x.abs() > MAX_RADIANS) {
            bail!(
                "{option}: {x:e} rad is beyond ±{MAX_RADIANS:e} rad, where a multiple of 2π \
                 cannot be taken off exactly; give the angle reduced, or in degrees \
                 (reduced exactly at any size)"
            );
        }
    }
    Ok(())
}

/// Angles as typed, in radians: as they are with `--radians`, else degrees reduced
/// ([`reduce_degrees`]) and converted.
fn typed_radians(args: &EulerArgs, a: [f64; 3]) -> [f64; 3] {
    if args.radians {
        a
    } else {
        a.map(reduce_degrees).map(f64::to_radians)
    }
}

/// Angles as typed, in degrees as printed back: converted with `--radians`, else reduced
/// ([`reduce_degrees`]).
fn typed_degrees(args: &EulerArgs, a: [f64; 3]) -> [f64; 3] {
    if args.radians {
        a.map(f64::to_degrees)
    } else {
        a.map(reduce_degrees)
    }
}

/// The rotation given: `--angles`, `--from-matrix` or `--from-quat`, if any.
fn given(args: &EulerArgs, convention: Convention) -> Option<Given> {
    if let Some(a) = args.angles {
        Some(Given::Angles(
            EulerAngles::new(convention, typed_radians(args, a)),
            typed_degrees(args, a),
        ))
    } else if let Some(m) = args.from_matrix {
        Some(Given::Matrix(m))
    } else {
        args.from_quat.map(Given::Quat)
    }
}

/// `--gimbal-lock`'s angles: those given, refused unless at lock, or the convention's
/// default lock.
fn locked_angles(given: Option<&Given>, convention: Convention) -> anyhow::Result<EulerAngles> {
    let Some(g) = given else {
        return Ok(EulerAngles::from_degrees(
            convention,
            default_lock_degrees(convention),
        ));
    };
    let e = solve(g, convention)?.euler;
    if !e.lock().is_locked() {
        bail!(
            "--gimbal-lock: the middle angle {} is not at gimbal lock (±90° for \
             Tait–Bryan {seq:#}, 0° or 180° for proper Euler); e.g. --angles {}",
            crate::draw::scene::euler::degrees_label(e.angles[1]),
            default_lock_degrees(convention)
                .map(|a| a.to_string())
                .join(","),
            seq = convention.sequence,
        );
    }
    Ok(e)
}

/// Largest angle in radians taken (`--radians`): beyond it, taking off multiples of an `f64`
/// 2π would be off by more than 1e-10 rad.
const MAX_RADIANS: f64 = 1e5;

/// An angle in degrees beyond ±360° reduced to 0..360 exactly (`rem_euclid` of a float by 360
/// is exact), so that 1e20° is the 280° it is, not whatever 1e20 · π/180 rounds to; angles
/// within ±360° are kept as typed.
fn reduce_degrees(d: f64) -> f64 {
    if d.abs() > 360.0 {
        d.rem_euclid(360.0)
    } else {
        d
    }
}

/// The middle angle at its upper lock (Tait–Bryan +90°; proper Euler 0°, where the first and
/// third rotation are about one axis from the start), the first angle 60°.
fn default_lock_degrees(c: Convention) -> [f64; 3] {
    let (first, third) = if c.frame == crate::geometry::euler::Frame::Intrinsic {
        (0, 2)
    } else {
        (2, 0)
    };
    let mut a = [0.0; 3];
    a[first] = 60.0;
    a[third] = 0.0;
    a[1] = if c.sequence.is_tait_bryan() {
        90.0
    } else {
        0.0
    };
    a
}

/// The angles of the input in `convention`: as given, or the principal solution of a matrix
/// or quaternion.
fn solve(given: &Given, convention: Convention) -> anyhow::Result<Solution> {
    match given {
        Given::Angles(e, _) => Ok(Solution {
            euler: *e,
            lock: e.lock(),
        }),
        Given::Matrix(m) => {
            // Typed row by row; glam stores columns.
            let r = DMat3::from_cols_array(m).transpose();
            EulerAngles::try_from_matrix(convention, r, MATRIX_TOLERANCE)
                .context("--from-matrix: not a rotation matrix")
        }
        Given::Quat([w, x, y, z]) => {
            // The library normalises by the largest component, so any scale works, 1e-200 and
            // 1e300 included; only all zeros is no rotation.
            if [w, x, y, z].iter().all(|c| **c == 0.0) {
                bail!(
                    "--from-quat: all four components are 0; a rotation needs a non-zero \
                     quaternion"
                );
            }
            let q = DQuat::from_xyzw(*x, *y, *z, *w);
            Ok(EulerAngles::from_quat(convention, q))
        }
    }
}

/// Degrees for text: six decimals, trailing zeros dropped (`30`, `12.5`, `-0.000001`).
fn trim(x: f64) -> String {
    let s = format!("{:.6}", clean(x));
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// `-0.0` printed as `0`.
fn clean(x: f64) -> f64 {
    x + 0.0
}

fn lock_name(lock: Lock) -> &'static str {
    match lock {
        Lock::Free => "free",
        Lock::Lower => "lower",
        Lock::Upper => "upper",
    }
}

/// The JSON answer for angles `e` (`degrees` in degrees) with gimbal state `lock`.
fn answer(e: &EulerAngles, degrees: [f64; 3], lock: Lock) -> Value {
    let m = e.to_matrix();
    let rows: Vec<Vec<f64>> = (0..3)
        .map(|i| m.row(i).to_array().map(clean).to_vec())
        .collect();
    let q = e.to_quat();
    let quaternion = [q.w, q.x, q.y, q.z].map(clean);
    json!({
        "convention": e.convention.to_string(),
        "sequence": format!("{:#}", e.convention.sequence),
        "frame": e.convention.frame.name(),
        "angles_deg": degrees.map(clean),
        "angles_rad": e.angles.map(clean),
        "gimbal_lock": lock.is_locked(),
        "lock": lock_name(lock),
        "matrix": rows,
        "quaternion": quaternion,
    })
}

fn print_numbers(args: &EulerArgs, given: &Given, solution: Solution) -> anyhow::Result<()> {
    let (shown, lock) = match args.to {
        Some(EulerTarget::Angles(to)) => {
            let s = solution.euler.convert(to);
            (s.euler, s.lock)
        }
        _ => (solution.euler, solution.lock),
    };
    let degrees = match (given, args.to) {
        (Given::Angles(_, typed), None | Some(EulerTarget::Matrix | EulerTarget::Quat)) => *typed,
        _ => shown.to_degrees(),
    };
    if args.json {
        let mut out = answer(&shown, degrees, lock);
        let input = match given {
            Given::Angles(e, typed) => json!({
                "convention": e.convention.to_string(),
                "angles_deg": typed.map(clean),
            }),
            Given::Matrix(m) => {
                let rows: Vec<Vec<f64>> = m.chunks(3).map(<[f64]>::to_vec).collect();
                json!({ "matrix": rows })
            }
            Given::Quat(q) => json!({ "quaternion": q }),
        };
        out["input"] = input;
        return emit(&(serde_json::to_string_pretty(&out)? + "\n"));
    }
    let angles = if args.radians {
        shown.angles.map(|x| format!("{:.6}", clean(x))).join(", ") + " rad"
    } else {
        degrees.map(|x| format!("{}°", trim(x))).join(", ")
    };
    let m = shown.to_matrix();
    let q = shown.to_quat();
    let matrix = || {
        (0..3)
            .map(|i| {
                m.row(i)
                    .to_array()
                    .map(|x| format!("{:>10.6}", clean(x)))
                    .join(" ")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let quat = format!(
        "{:.6} {:.6} {:.6} {:.6}",
        clean(q.w),
        clean(q.x),
        clean(q.y),
        clean(q.z)
    );
    let mut text = String::new();
    match args.to {
        Some(EulerTarget::Matrix) => writeln!(text, "{}", matrix())?,
        Some(EulerTarget::Quat) => writeln!(text, "{quat}")?,
        Some(EulerTarget::Angles(_)) => {
            writeln!(text, "{}: {angles}", describe(shown.convention))?;
        }
        None => {
            writeln!(text, "{}: {angles}", describe(shown.convention))?;
            writeln!(text, "matrix (body -> world, rows):\n{}", matrix())?;
            writeln!(text, "quaternion [w, x, y, z]: {quat}")?;
        }
    }
    if lock.is_locked() {
        writeln!(
            text,
            "note: gimbal lock: the middle angle is at {} ({} end of its range); the first and \
             third axes coincide, only one combination of those angles is determined",
            crate::draw::scene::euler::degrees_label(shown.angles[1]),
            lock_name(lock)
        )?;
    }
    emit(&text)
}

/// Write `text` to stdout. A reader that went away (`| head`) is not an error of ours: the
/// rest is dropped quietly instead of panicking as `println!` would.
fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        result => result.context("cannot write to stdout"),
    }
}

/// `intrinsic z-y-x (Tait–Bryan, R = Rz·Ry·Rx)`.
fn describe(c: Convention) -> String {
    let [a, b, d] = c.sequence.axes().map(|x| x.name());
    let product = match c.frame {
        crate::geometry::euler::Frame::Intrinsic => format!("R{a}(A)·R{b}(B)·R{d}(C)"),
        crate::geometry::euler::Frame::Extrinsic => format!("R{d}(C)·R{b}(B)·R{a}(A)"),
    };
    let kind = if c.sequence.is_tait_bryan() {
        "Tait–Bryan"
    } else {
        "proper Euler"
    };
    format!("{} {:#} ({kind}, R = {product})", c.frame, c.sequence)
}

fn viewport(args: &EulerArgs) -> Viewport {
    Viewport {
        width: args.size.0,
        height: args.size.1,
    }
}

/// Draw every picture on the CPU (bit-exact), write them with a manifest into `--out` as a
/// whole, and say so.
fn write_pictures(args: &EulerArgs, pictures: &[Picture], notes: &[String]) -> anyhow::Result<()> {
    let dir = args.out.as_deref().context("pictures need --out DIR")?;
    for p in pictures {
        let pixels = u64::from(p.scene.width) * u64::from(p.scene.height);
        if pixels > MAX_SHEET_PIXELS {
            bail!(
                "--size {}x{}: the picture {} would be {}x{} pixels, more than {MAX_SHEET_PIXELS}; \
                 use a smaller --size or fewer --frames",
                args.size.0,
                args.size.1,
                p.name,
                p.scene.width,
                p.scene.height
            );
        }
    }
    let mut rasterizer = Rasterizer::Cpu;
    let mut files = Vec::with_capacity(pictures.len() + 1);
    let mut manifest = format!(
        "# written by: wireflight {}\n",
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    );
    for note in notes {
        manifest += &format!("# {note}\n");
    }
    for p in pictures {
        let image = rasterizer.draw(&p.scene)?;
        let name = format!("{}.png", p.name);
        manifest += &format!("{name}\t{}x{}\t{}\n", p.scene.width, p.scene.height, p.what);
        files.push((name, image.encode_png().context("encoding PNG")?));
    }
    files.push((MANIFEST.to_string(), manifest.into_bytes()));
    write_dir_atomic(dir, &files, MANIFEST).context("--out")?;
    let mut text = String::new();
    for note in notes {
        writeln!(text, "{note}")?;
    }
    writeln!(
        text,
        "wrote {} pictures ({}) and {MANIFEST} to {}",
        pictures.len(),
        pictures
            .iter()
            .map(|p| format!("{}.png", p.name))
            .collect::<Vec<_>>()
            .join(", "),
        crate::app::shown(dir)
    )?;
    emit(&text)
}

fn steps(args: &EulerArgs, e: &EulerAngles) -> anyhow::Result<()> {
    let mesh = crate::draw::mesh_files::load_named(&args.mesh)?;
    let pictures = steps_pictures(&mesh, e, viewport(args));
    let note = format!("{}: {}", describe(e.convention), angles_label(e));
    write_pictures(args, &pictures, &[note])
}

fn gimbal_lock(args: &EulerArgs, locked: &EulerAngles) -> anyhow::Result<()> {
    let mesh = crate::draw::mesh_files::load_named(&args.mesh)?;
    let Some((pictures, twin)) = gimbal_lock_pictures(&mesh, locked, viewport(args)) else {
        bail!("--gimbal-lock: the angles are not at gimbal lock");
    };
    let same =
        crate::geometry::euler::rotation_between(locked.to_quat(), twin.to_quat()).to_degrees();
    let notes = [
        describe(locked.convention),
        format!(
            "A {} and B {} are the same attitude (they differ by {same:.1e}°)",
            angles_label(locked),
            angles_label(&twin)
        ),
    ];
    write_pictures(args, &pictures, &notes)
}

fn interpolate(args: &EulerArgs, a: &EulerAngles, b: &EulerAngles) -> anyhow::Result<()> {
    let mesh = crate::draw::mesh_files::load_named(&args.mesh)?;
    let frames = usize::from(args.frames);
    let (pictures, c) = interpolation_pictures(&mesh, a, b, frames, viewport(args));
    let notes = [
        format!(
            "{}: from {} to {}",
            describe(a.convention),
            angles_label(a),
            angles_label(b)
        ),
        format!(
            "Euler lerp vs slerp: largest difference {:.2}° (at t = {:.2}); total turn {:.2}° \
             (Euler) vs {:.2}° (slerp, the shortest)",
            c.max_deviation.to_degrees(),
            c.at,
            c.lerp_turn.to_degrees(),
            c.slerp_turn.to_degrees()
        ),
    ];
    write_pictures(args, &pictures, &notes)
}
