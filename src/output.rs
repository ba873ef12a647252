//! Pictures to files: a still as PNG or SVG, and the frames of a replay as numbered PNGs.
//! Every file is written atomically ([`crate::fsio::write_atomic`]).

use std::path::Path;

use anyhow::{bail, Context};

use crate::clip::ClipStats;
use crate::fsio::write_atomic;
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

/// Write one PNG per frame (`frame_00000.png`, …) of `replay` into `dir` (created if needed),
/// one frame every 1/`fps` seconds of flight time from `t0` to `t1`. Returns the number of
/// frames and the summed clip counts.
///
/// # Errors
/// Bad fps, unwritable directory, drawing errors.
pub fn write_frames(
    replay: &mut ReplayScene<'_>,
    (t0, t1): (f64, f64),
    viewport: Viewport,
    fps: f64,
    dir: &Path,
    rasterizer: &mut Rasterizer,
) -> anyhow::Result<(usize, ClipStats)> {
    if !(fps > 0.0 && fps <= 1000.0) {
        bail!("--fps {fps} must be in (0, 1000]");
    }
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let frames = ((t1 - t0) * fps).floor() as usize + 1;
    let mut total = ClipStats::default();
    for k in 0..frames {
        let (lines, stats) = replay.frame(t0 + k as f64 / fps, viewport);
        total.merge(&stats);
        let image = rasterizer.draw(lines)?;
        let path = dir.join(format!("frame_{k:05}.png"));
        write_atomic(&path, &image.encode_png().context("encoding PNG")?)?;
    }
    Ok((frames, total))
}
