//! `wireflight render`: one oriented mesh → clipped wireframe → PNG or SVG; or, with
//! `--flight`, the frames of a recorded flight.

use std::path::Path;

use anyhow::{bail, Context};

use crate::app::cli::{ProjectionArg, RenderArgs};
use crate::draw::output::{write_frames, write_still, FrameOut};
use crate::draw::render::{OutputFormat, Rasterizer};
use crate::draw::scene::replay::ReplayScene;
use crate::draw::scene::still::still;
use crate::draw::scene::{frame, ViewSpec};
use crate::geometry::clip::{DepthRange, PlaneSet};
use crate::geometry::mesh::EdgeMesh;
use crate::geometry::pipeline::Viewport;
use glam::Vec4;

/// Run `wireflight render`.
///
/// # Errors
/// Bad mesh files, unknown output format, GPU failures with `--backend gpu`, write errors.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mut inputs: Vec<(&str, &std::path::Path)> =
        vec![("--mesh", std::path::Path::new(&args.mesh))];
    if let Some(f) = &args.flight {
        inputs.push(("--flight", f));
    }
    let outputs: Vec<(&str, &std::path::Path)> =
        args.out.iter().map(|o| ("--out", o.as_path())).collect();
    let dirs: Vec<(&str, &std::path::Path)> = args
        .frames_dir
        .iter()
        .map(|d| ("--frames-dir", d.as_path()))
        .collect();
    crate::app::outputs::check_outputs(&inputs, &outputs, &dirs)?;
    let mesh_name = mesh_name(args)?;
    let mesh = crate::draw::mesh_files::load_named(&mesh_name)?;
    let viewport = Viewport {
        width: args.size.0,
        height: args.size.1,
    };
    match &args.flight {
        Some(flight) => replay(args, flight, &mesh, viewport),
        None => still_image(args, &mesh_name, &mesh, viewport),
    }
}

/// `--flight`: the recorded flight's frames, as PNGs or an animated GIF.
fn replay(
    args: &RenderArgs,
    flight: &Path,
    mesh: &EdgeMesh,
    viewport: Viewport,
) -> anyhow::Result<()> {
    let out = match (&args.frames_dir, &args.out) {
        (Some(dir), _) => FrameOut::Pngs(dir),
        (None, Some(gif)) if is_gif(gif) => FrameOut::Gif(gif),
        (None, Some(other)) => bail!(
            "{}: a replay is written as frames (--frames-dir DIR) or an animated GIF (--out \
             FILE.gif)",
            other.display()
        ),
        (None, None) => bail!("--flight needs --frames-dir DIR or --out FILE.gif"),
    };
    let data = crate::app::data::load_flight(flight, &args.data)?;
    let mut rasterizer = Rasterizer::choose(args.backend.into())?;
    let mut replay = ReplayScene::new(&data, mesh, args.clipper)
        .with_context(|| format!("{}", flight.display()))?;
    let span = (data.time[0], data.time[data.len() - 1]);
    let w = write_frames(
        &mut replay,
        span,
        viewport,
        args.fps,
        args.max_frames,
        out,
        &mut rasterizer,
        false,
    )?;
    let (what, to) = match out {
        FrameOut::Pngs(dir) => ("frames", dir),
        FrameOut::Gif(gif) => ("GIF frames", gif),
    };
    println!(
        "wrote {} {what} of {} ({:.1} s at {} fps, {}x{}, {}) to {}{}",
        w.frames,
        crate::app::shown(flight),
        data.duration(),
        w.fps,
        viewport.width,
        viewport.height,
        rasterizer.describe(),
        crate::app::shown(to),
        if matches!(out, FrameOut::Gif(_)) {
            format!(" ({} kB)", w.bytes.div_ceil(1000))
        } else {
            String::new()
        }
    );
    println!("clip, all frames: {}", w.stats);
    Ok(())
}

/// One picture of the mesh, PNG or SVG by `--out`'s extension.
fn still_image(
    args: &RenderArgs,
    mesh_name: &str,
    mesh: &EdgeMesh,
    viewport: Viewport,
) -> anyhow::Result<()> {
    let out = args.out.as_deref().context("--out is required")?;
    let spec = view_spec(args, mesh_name, mesh, viewport)?;
    // A cut-away or hidden-line view is of the model alone: the world's ground and horizon
    // are not cut by the model's planes nor made of faces.
    let (scene, stats) = if spec.clip_planes.is_empty() && !spec.hidden_line {
        still(mesh, &spec, args.world.into())
    } else {
        frame(mesh, &spec)
    };
    // Only a raster image needs a rasterizer (and the GPU's start-up).
    let mut rasterizer = match OutputFormat::of(out)? {
        OutputFormat::Png => Rasterizer::choose(args.backend.into())?,
        OutputFormat::Svg => Rasterizer::Cpu,
    };
    let how = write_still(out, &scene, &mut rasterizer)?;
    let (_, gimbal) = spec.attitude.canonical();
    println!(
        "wrote {} ({}x{}, {how}); {} segments drawn",
        crate::app::shown(out),
        spec.viewport.width,
        spec.viewport.height,
        scene.segment_count()
    );
    println!("clip: {stats}");
    if gimbal.is_locked() {
        println!(
            "note: pitch is ±90°: z-y-x angles are at gimbal lock (yaw and roll share one axis)"
        );
    }
    Ok(())
}

/// The view the options ask for: attitude, camera, projection, the `--clip-plane`s and
/// hidden lines (refused for a mesh without faces).
fn view_spec(
    args: &RenderArgs,
    mesh_name: &str,
    mesh: &EdgeMesh,
    viewport: Viewport,
) -> anyhow::Result<ViewSpec> {
    let mut clip_planes = PlaneSet::EMPTY;
    for p in &args.clip_plane {
        clip_planes
            .push(Vec4::from_array(*p))
            .with_context(|| format!("--clip-plane {p:?}"))?;
    }
    if args.hidden_line && mesh.faces().is_empty() {
        anyhow::bail!(
            "--hidden-line needs a mesh with faces (an OBJ or glTF model); `{}` has only edges",
            mesh_name
        );
    }
    Ok(ViewSpec {
        attitude: crate::draw::scene::attitude::from_aerospace_degrees(
            args.yaw, args.pitch, args.roll,
        ),
        camera: args.camera.into(),
        orthographic: args.projection == ProjectionArg::Ortho,
        fov_y_deg: args.fov,
        viewport,
        depth: DepthRange::ZeroToOne,
        pan: args.pan,
        clipper: args.clipper,
        clip_planes,
        hidden_line: args.hidden_line,
    })
}

/// The wireframe to draw: `--mesh`, or the old spelling `--model` with a note on stderr — but
/// only for a mesh file: `--model` names a flight model (TOML) in every other command, and one
/// given here is refused, saying what to use.
///
/// # Errors
/// `--model FILE.toml`.
fn mesh_name(args: &RenderArgs) -> anyhow::Result<String> {
    let Some(old) = &args.old_model else {
        return Ok(args.mesh.clone());
    };
    if Path::new(old)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
    {
        bail!(
            "--model {}: render draws a wireframe, not a flight model; give the mesh with --mesh              (plane, FILE.obj, FILE.gltf, FILE.glb), or fly a model with `simulate --model` and              replay it with `render --flight`",
            crate::fsio::printable(old)
        );
    }
    crate::app::deprecated("--model", "--mesh");
    Ok(old.clone())
}

/// True for a `.gif` file name (any case).
fn is_gif(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
}
