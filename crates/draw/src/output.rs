//! Pictures to files: a still as PNG or SVG, and the frames of a replay as numbered PNGs or
//! one animated GIF.
//! Every file is written atomically ([`wireflight_fsio::write_atomic`]).

use std::path::Path;

use anyhow::{bail, Context};

use crate::progress::Progress;
use crate::render::gif::GifAnimation;
use crate::render::{svg, LineScene, OutputFormat, Rasterizer};
use crate::scene::replay::ReplayScene;
use wireflight_fsio::{write_atomic, StagedDir};
use wireflight_geometry::clip::ClipStats;
use wireflight_geometry::pipeline::Viewport;

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

/// Default most frames of one replay (`--max-frames`).
pub const DEFAULT_MAX_FRAMES: u64 = 100_000;

/// Whether a file name is one of [`write_frames`]' frames (`frame_NNNNN.png`).
pub fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|n| n.strip_suffix(".png"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
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

/// Draws the frames of `replay`, one every 1/`fps` seconds of flight time from `t0` to `t1`
/// (at most `max_frames` of them), into `out`, with a progress bar on stderr (hidden when
/// `quiet_progress`, under `--quiet`, or when stderr is not a terminal). PNG frames are
/// written into a temporary directory that then replaces the directory as a whole, so it
/// never holds frames of two runs, nor a partial set; it may hold only earlier frames
/// (anything else is refused, not deleted). A GIF is written atomically.
///
/// # Errors
/// Bad fps, more frames than `max_frames` (naming the span and `--max-frames`), a directory
/// holding other files, unwritable directory or file, drawing errors.
#[allow(clippy::too_many_arguments)] // each is one of the replay's independent settings
pub fn write_frames(
    replay: &mut ReplayScene<'_>,
    (t0, t1): (f64, f64),
    viewport: Viewport,
    fps: f64,
    max_frames: u64,
    out: FrameOut<'_>,
    rasterizer: &mut Rasterizer,
    quiet_progress: bool,
) -> anyhow::Result<FramesWritten> {
    if !(fps > 0.0 && fps <= 1000.0) {
        bail!("--fps {fps} must be in (0, 1000]");
    }
    let count = ((t1 - t0) * fps).floor() + 1.0;
    if !(count.is_finite() && count >= 1.0 && count <= max_frames as f64) {
        bail!(
            "{:.6e} s of flight at {fps} fps is {count:.3e} frames, more than --max-frames \
             {max_frames} (raise it, or lower --fps)",
            t1 - t0
        );
    }
    let frames = count as usize;
    let mut total = ClipStats::default();
    let progress = Progress::bar(frames as u64, "frames", quiet_progress);
    let mut bytes = 0;
    let mut gif = None;
    let mut staged = None;
    match out {
        FrameOut::Pngs(dir) => staged = Some(StagedDir::new(dir)?),
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
            (FrameOut::Pngs(_), _) | (FrameOut::Gif(_), None) => {
                let Some(staged) = staged.as_ref() else {
                    bail!("internal: no staging directory for PNG frames");
                };
                let path = staged.path().join(format!("frame_{k:05}.png"));
                let png = image.encode_png().context("encoding PNG")?;
                bytes += png.len();
                write_atomic(&path, &png)?;
            }
        }
        progress.inc(1);
    }
    drop(progress);
    if let Some(staged) = staged {
        staged.commit_replace(is_frame_name)?;
    }
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
