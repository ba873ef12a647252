//! `wireflight render`: one oriented mesh → clipped wireframe → PNG or SVG; or, with
//! `--flight`, the frames of a recorded flight.

use anyhow::Context;

use crate::app::cli::{ProjectionArg, RenderArgs};
use crate::clip::DepthRange;
use crate::euler::EulerZyx;
use crate::output::{write_frames, write_still};
use crate::pipeline::Viewport;
use crate::render::{OutputFormat, Rasterizer};
use crate::scene::replay::ReplayScene;
use crate::scene::{frame, ViewSpec};

/// Run `wireflight render`.
///
/// # Errors
/// Bad mesh files, unknown output format, GPU failures with `--backend gpu`, write errors.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mesh = crate::mesh::load_named(&args.mesh)?;
    let viewport = Viewport {
        width: args.size.0,
        height: args.size.1,
    };
    if let (Some(flight), Some(dir)) = (&args.flight, &args.frames_dir) {
        let data = crate::app::data::load_flight(flight, &args.data)?;
        let mut rasterizer = Rasterizer::choose(args.backend.into())?;
        let mut replay = ReplayScene::new(&data, &mesh, args.clipper)
            .with_context(|| format!("{}", flight.display()))?;
        let span = (data.time[0], data.time[data.len() - 1]);
        let (frames, stats) =
            write_frames(&mut replay, span, viewport, args.fps, dir, &mut rasterizer)?;
        println!(
            "wrote {frames} frames of {} ({:.1} s at {} fps, {}x{}, {}) to {}",
            flight.display(),
            data.duration(),
            args.fps,
            viewport.width,
            viewport.height,
            rasterizer.describe(),
            dir.display()
        );
        println!("clip, all frames: {stats}");
        return Ok(());
    }
    let out = args.out.as_deref().context("--out is required")?;
    let spec = ViewSpec {
        attitude: EulerZyx::from_degrees(args.yaw, args.pitch, args.roll),
        camera: args.camera.into(),
        orthographic: args.projection == ProjectionArg::Ortho,
        fov_y_deg: args.fov,
        viewport,
        depth: DepthRange::ZeroToOne,
        pan: args.pan,
        clipper: args.clipper,
    };
    let (scene, stats) = frame(&mesh, &spec);
    // Only a raster image needs a rasterizer (and the GPU's start-up).
    let mut rasterizer = match OutputFormat::of(out)? {
        OutputFormat::Png => Rasterizer::choose(args.backend.into())?,
        OutputFormat::Svg => Rasterizer::Cpu,
    };
    let how = write_still(out, &scene, &mut rasterizer)?;
    let (_, gimbal) = spec.attitude.canonical();
    println!(
        "wrote {} ({}x{}, {how}); {} segments drawn",
        out.display(),
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
