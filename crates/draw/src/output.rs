//! Pictures to files: a still as PNG or SVG, and the frames of a replay as numbered PNGs or
//! one animated GIF.
//! Every file is written atomically ([`wireflight_fsio::write_atomic`]).

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::progress::Progress;
use crate::render::gif::{GifAnimation, GifError};
use crate::render::{svg, LineScene, OutputFormat, Rasterizer, RenderError, UnknownFormat};
use crate::scene::replay::ReplayScene;
use wireflight_fsio::{write_atomic, FsError, StagedDir};
use wireflight_geometry::clip::ClipStats;
use wireflight_geometry::pipeline::Viewport;

/// Why pictures could not be written.
#[derive(Debug, Error)]
pub enum OutputError {
    /// The file name names no format.
    #[error(transparent)]
    Format(#[from] UnknownFormat),
    /// The rasterizer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The PNG encoder failed.
    #[error("encoding PNG")]
    EncodePng(#[source] png::EncodingError),
    /// A file or directory could not be written (the error names it).
    #[error(transparent)]
    Fs(#[from] FsError),
    /// Frames per second outside (0, 1000].
    #[error("--fps {fps} must be in (0, 1000]")]
    Fps {
        /// The frame rate asked for.
        fps: f64,
    },
    /// More frames than allowed.
    #[error(
        "{span_s:.6e} s of flight at {fps} fps is {frames:.3e} frames, more than --max-frames \
         {max_frames} (raise it, or lower --fps)"
    )]
    TooManyFrames {
        /// Flight time to draw, s.
        span_s: f64,
        /// Frames per second.
        fps: f64,
        /// Frames that would take (not finite for a span that is not).
        frames: f64,
        /// The most allowed.
        max_frames: u64,
    },
    /// A GIF asked for at more than 100 frames per second.
    #[error("{}: a GIF shows at most 100 frames per second", path.display())]
    GifFps {
        /// The GIF file.
        path: PathBuf,
    },
    /// The GIF could not be encoded.
    #[error("{}", path.display())]
    Gif {
        /// The GIF file.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: GifError,
    },
}

/// Draw `scene` and write it to `path` in the format its extension names. Returns how it was
/// drawn (the rasterizer's description, or `svg`).
///
/// # Errors
/// Unknown extension, drawing errors, write errors.
pub fn write_still(
    path: &Path,
    scene: &LineScene,
    rasterizer: &mut Rasterizer,
) -> Result<String, OutputError> {
    let (bytes, how) = match OutputFormat::of(path)? {
        OutputFormat::Png => {
            let image = rasterizer.draw(scene)?;
            (
                image.encode_png().map_err(OutputError::EncodePng)?,
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

/// Frames per second of flight time of every replay and comparison (`render --flight`,
/// `compare --frames-dir/--out`) unless `--fps` says otherwise.
pub const DEFAULT_FPS: f64 = 25.0;

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
) -> Result<FramesWritten, OutputError> {
    if !(fps > 0.0 && fps <= 1000.0) {
        return Err(OutputError::Fps { fps });
    }
    let count = ((t1 - t0) * fps).floor() + 1.0;
    if !(count.is_finite() && count >= 1.0 && count <= max_frames as f64) {
        return Err(OutputError::TooManyFrames {
            span_s: t1 - t0,
            fps,
            frames: count,
            max_frames,
        });
    }
    let frames = count as usize;
    let gif_error = |path: &Path| {
        let path = path.to_path_buf();
        move |source: GifError| OutputError::Gif { path, source }
    };
    // Where the frames go: a staging directory, or the animation being encoded.
    let mut sink = match out {
        FrameOut::Pngs(dir) => Sink::Pngs(StagedDir::new(dir)?),
        FrameOut::Gif(path) => {
            if fps > 100.0 {
                return Err(OutputError::GifFps {
                    path: path.to_path_buf(),
                });
            }
            let delay = GifAnimation::delay_for(fps);
            let gif = GifAnimation::new(viewport.width, viewport.height, delay)
                .map_err(gif_error(path))?;
            Sink::Gif(path, gif)
        }
    };
    let mut total = ClipStats::default();
    let progress = Progress::bar(frames as u64, "frames", quiet_progress);
    let mut bytes = 0;
    for k in 0..frames {
        let (lines, stats) = replay.frame(t0 + k as f64 / fps, viewport);
        total.merge(&stats);
        let image = rasterizer.draw(lines)?;
        match &mut sink {
            Sink::Gif(path, gif) => gif.push(&image).map_err(gif_error(path))?,
            Sink::Pngs(staged) => {
                let path = staged.path().join(format!("frame_{k:05}.png"));
                let png = image.encode_png().map_err(OutputError::EncodePng)?;
                bytes += png.len();
                write_atomic(&path, &png)?;
            }
        }
        progress.inc(1);
    }
    drop(progress);
    let fps_written = match sink {
        Sink::Pngs(staged) => {
            staged.commit_replace(is_frame_name)?;
            fps
        }
        Sink::Gif(path, gif) => {
            let data = gif.finish().map_err(gif_error(path))?;
            bytes = data.len();
            write_atomic(path, &data)?;
            100.0 / GifAnimation::delay_for(fps) as f64
        }
    };
    Ok(FramesWritten {
        frames,
        stats: total,
        fps: fps_written,
        bytes,
    })
}

/// Where [`write_frames`] puts the frames while it draws them.
enum Sink<'a> {
    /// PNG files in a staging directory that replaces the output directory at the end.
    Pngs(StagedDir),
    /// The animation, written to its file at the end.
    Gif(&'a Path, GifAnimation),
}
