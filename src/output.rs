//! Pictures to files: a still as PNG or SVG, and the frames of a replay as numbered PNGs or
//! one animated GIF.
//! Every file is written atomically ([`crate::fsio::write_atomic`]).

use std::path::Path;

use anyhow::{bail, Context};

use crate::clip::ClipStats;
use crate::fsio::write_atomic;
use crate::pipeline::Viewport;
use crate::progress::Progress;
use crate::render::gif::GifAnimation;
use crate::render::{svg, LineScene, OutputFormat, Rasterizer};
use crate::scene::replay::ReplayScene;

/// Draw `scene` and write it to `path` in the format its extension names. Returns how it was
/// drawn (the rasterizer's description, or `svg`).
///
/// # Errors
/// Unknown extension, drawing errors, write errors.
pub fn write_still(
    path: &Path,
    scene: &LineScene,
    rasterizer: &mut Rasterizer,
) -> anyhow::Result<String> {
    let (bytes, how) = match OutputFormat::of(path)? {
        OutputFormat::Png => {
            let image = rasterizer.draw(scene)?;
            (
                image.encode_png().context("encoding PNG")?,
                rasterizer.describe(),
            )
        }
        OutputFormat::Svg => (svg::to_svg(scene).into_bytes(), "svg".to_string()),
    };
    write_atomic(path, &bytes)?;
    Ok(how)
}

/// Where the frames of a replay go.
#[derive(Clone, Copy, Debug)]
pub enum FrameOut<'a> {
    /// One PNG per frame (`frame_00000.png`, …) in this directory (created if needed).
    Pngs(&'a Path),
    /// One animated GIF (written atomically when every frame is drawn).
    Gif(&'a Path),
}

/// What [`write_frames`] did.
#[derive(Clone, Debug)]
pub struct FramesWritten {
    /// Frames drawn.
    pub frames: usize,
    /// Summed clip counts.
    pub stats: ClipStats,
    /// Frames per second as written (a GIF's frame times are whole hundredths of a second).
    pub fps: f64,
    /// Bytes written (the GIF; the PNGs together).
    pub bytes: usize,
}

/// Draws the frames of `replay`, one every 1/`fps` seconds of flight time from `t0` to `t1`,
/// into `out`, with a progress bar on stderr (hidden when `quiet_progress`, under `--quiet`,
/// or when stderr is not a terminal).
///
/// # Errors
/// Bad fps, unwritable directory or file, drawing errors.
pub fn write_frames(
    replay: &mut ReplayScene<'_>,
    (t0, t1): (f64, f64),
    viewport: Viewport,
    fps: f64,
    out: FrameOut<'_>,
    rasterizer: &mut Rasterizer,
    quiet_progress: bool,
) -> anyhow::Result<FramesWritten> {
    if !(fps > 0.0 && fps <= 1000.0) {
        bail!("--fps {fps} must be in (0, 1000]");
    }
    let frames = ((t1 - t0) * fps).floor() as usize + 1;
    let mut total = ClipStats::default();
    let progress = Progress::bar(frames as u64, "frames", quiet_progress);
    let mut bytes = 0;
    let mut gif = None;
    match out {
        FrameOut::Pngs(dir) => std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?,
        FrameOut::Gif(path) => {
            if fps > 100.0 {
                bail!(
                    "{}: a GIF shows at most 100 frames per second",
                    path.display()
                );
            }
            gif = Some(
                GifAnimation::new(
                    viewport.width,
                    viewport.height,
                    GifAnimation::delay_for(fps),
                )
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            );
        }
    }
    for k in 0..frames {
        let (lines, stats) = replay.frame(t0 + k as f64 / fps, viewport);
        total.merge(&stats);
        let image = rasterizer.draw(lines)?;
        match (out, gif.as_mut()) {
            (FrameOut::Gif(path), Some(g)) => g
                .push(&image)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
            (FrameOut::Pngs(dir), _) | (FrameOut::Gif(dir), None) => {
                let path = dir.join(format!("frame_{k:05}.png"));
                let png = image.encode_png().context("encoding PNG")?;
                bytes += png.len();
                write_atomic(&path, &png)?;
            }
        }
        progress.inc(1);
    }
    drop(progress);
    let mut fps_written = fps;
    if let (FrameOut::Gif(path), Some(g)) = (out, gif) {
        let data = g
            .finish()
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        bytes = data.len();
        write_atomic(path, &data)?;
        fps_written = 100.0 / GifAnimation::delay_for(fps) as f64;
    }
    Ok(FramesWritten {
        frames,
        stats: total,
        fps: fps_written,
        bytes,
    })
}
