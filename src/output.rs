//! Pictures to files: a still as PNG or SVG, and the frames of a replay as numbered PNGs.
//! Every file is written atomically ([`crate::fsio::write_atomic`]).

use std::path::Path;

use anyhow::{bail, Context};

use crate::clip::ClipStats;
use crate::fsio::{write_atomic, StagedDir};
use crate::pipeline::Viewport;
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

/// Default most frames of one replay (`--max-frames`).
pub const DEFAULT_MAX_FRAMES: u64 = 100_000;

/// Whether a file name is one of [`write_frames`]' frames (`frame_NNNNN.png`).
pub fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|n| n.strip_suffix(".png"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// Write one PNG per frame (`frame_00000.png`, …) of `replay` into `dir`, one frame every
/// 1/`fps` seconds of flight time from `t0` to `t1`, at most `max_frames` of them. The frames
/// are written into a temporary directory that then replaces `dir` as a whole, so `dir` never
/// holds frames of two runs, nor a partial set; `dir` may hold only earlier frames (anything
/// else is refused, not deleted). Returns the number of frames and the summed clip counts.
///
/// # Errors
/// Bad fps, more frames than `max_frames` (naming the span and `--max-frames`), a `dir`
/// holding other files, unwritable directory, drawing errors.
pub fn write_frames(
    replay: &mut ReplayScene<'_>,
    (t0, t1): (f64, f64),
    viewport: Viewport,
    fps: f64,
    max_frames: u64,
    dir: &Path,
    rasterizer: &mut Rasterizer,
) -> anyhow::Result<(usize, ClipStats)> {
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
    let staged = StagedDir::new(dir)?;
    let mut total = ClipStats::default();
    for k in 0..frames {
        let (lines, stats) = replay.frame(t0 + k as f64 / fps, viewport);
        total.merge(&stats);
        let image = rasterizer.draw(lines)?;
        let path = staged.path().join(format!("frame_{k:05}.png"));
        write_atomic(&path, &image.encode_png().context("encoding PNG")?)?;
    }
    staged.commit_replace(is_frame_name)?;
    Ok((frames, total))
}
