//! Choosing a rasterizer: the wgpu backend when an adapter exists (Mesa lavapipe counts), the
//! bit-exact CPU one otherwise or on request, and the output formats by file name.
//!
//! Without the `gpu` feature the CPU backend is the only one: [`Backend::Auto`] chooses it
//! and [`Backend::Gpu`] is an error ([`RenderError::GpuNotBuilt`]).

use std::path::{Path, PathBuf};

use thiserror::Error;

#[cfg(feature = "gpu")]
use super::gpu::{GpuError, GpuRenderer};
use super::{Image, LineScene};

/// Which rasterizer draws a raster image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// GPU if any wgpu adapter exists, else CPU (with a note on stderr). Always the CPU in a
    /// build without the `gpu` feature.
    #[default]
    Auto,
    /// wgpu only; fails without an adapter, and in a build without the `gpu` feature.
    Gpu,
    /// Bresenham on the CPU (bit-exact).
    Cpu,
}

/// Why a rasterizer could not be chosen or could not draw.
#[derive(Debug, Error)]
pub enum RenderError {
    /// [`Backend::Gpu`] without a usable adapter.
    #[cfg(feature = "gpu")]
    #[error("--backend gpu")]
    GpuUnavailable(#[source] GpuError),
    /// [`Backend::Gpu`] in a build without the `gpu` feature (never made with it).
    #[error("--backend gpu: built without the gpu feature (only the CPU backend draws PNGs)")]
    GpuNotBuilt,
    /// A GPU frame failed under [`Backend::Gpu`] (under `Auto` the CPU draws it instead).
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    GpuFrame(GpuError),
}

/// A rasterizer chosen by [`Backend`]. Create it once and draw every frame with it: the GPU
/// one opens its device and builds its pipeline on creation.
pub enum Rasterizer {
    /// Bresenham on the CPU.
    Cpu,
    /// wgpu (any adapter, Mesa lavapipe included).
    #[cfg(feature = "gpu")]
    Gpu {
        /// The renderer (device, pipeline, frame buffers).
        renderer: Box<GpuRenderer>,
        /// Chosen by `auto`: a failing frame falls back to the CPU instead of failing the run.
        fallback: bool,
    },
}

impl Rasterizer {
    /// Pick a backend and say which on stderr: `GPU: <adapter> (<backend>)`, or for `Auto`
    /// without a usable adapter one line with the reason and that the CPU draws instead.
    /// Without the `gpu` feature `Auto` is the CPU, silently.
    ///
    /// # Errors
    /// `Gpu` without a usable adapter, or in a build without the `gpu` feature.
    #[cfg(feature = "gpu")]
    pub fn choose(choice: Backend) -> Result<Self, RenderError> {
        if choice == Backend::Cpu {
            return Ok(Rasterizer::Cpu);
        }
        match GpuRenderer::new() {
            Ok(renderer) => {
                eprintln!("GPU: {}", renderer.adapter());
                Ok(Rasterizer::Gpu {
                    renderer: Box::new(renderer),
                    fallback: choice == Backend::Auto,
                })
            }
            Err(err) if choice == Backend::Auto => {
                eprintln!("wireflight: GPU backend unavailable ({err}); drawing on the CPU");
                Ok(Rasterizer::Cpu)
            }
            Err(err) => Err(RenderError::GpuUnavailable(err)),
        }
    }

    /// Pick a backend: without the `gpu` feature, the CPU for `Auto` and `Cpu`.
    ///
    /// # Errors
    /// `Gpu` ([`RenderError::GpuNotBuilt`]).
    #[cfg(not(feature = "gpu"))]
    pub fn choose(choice: Backend) -> Result<Self, RenderError> {
        match choice {
            Backend::Auto | Backend::Cpu => Ok(Rasterizer::Cpu),
            Backend::Gpu => Err(RenderError::GpuNotBuilt),
        }
    }

    /// Short name for messages.
    pub fn describe(&self) -> String {
        match self {
            Rasterizer::Cpu => "cpu (Bresenham)".to_string(),
            #[cfg(feature = "gpu")]
            Rasterizer::Gpu { renderer, .. } => format!("gpu: {}", renderer.adapter()),
        }
    }

    /// Draw a scene. Under `auto`, a GPU failure switches to the CPU for this and every later
    /// frame, with a note on stderr.
    ///
    /// # Errors
    /// GPU failures (`--backend gpu`).
    pub fn draw(&mut self, scene: &LineScene) -> Result<Image, RenderError> {
        match self {
            Rasterizer::Cpu => Ok(super::cpu::render(scene)),
            #[cfg(feature = "gpu")]
            Rasterizer::Gpu { renderer, fallback } => match renderer.render(scene) {
                Ok(image) => Ok(image),
                Err(err) if *fallback => {
                    eprintln!("wireflight: GPU frame failed ({err}); drawing on the CPU");
                    *self = Rasterizer::Cpu;
                    Ok(super::cpu::render(scene))
                }
                Err(err) => Err(RenderError::GpuFrame(err)),
            },
        }
    }
}

/// Output formats, by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// Raster PNG.
    Png,
    /// Vector SVG.
    Svg,
}

/// An output file name whose extension names no [`OutputFormat`].
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("{}: unknown output format (use a .png or .svg file name)", path.display())]
pub struct UnknownFormat {
    /// The file name.
    pub path: PathBuf,
}

impl OutputFormat {
    /// The format of an output path (`.png` or `.svg`, case-insensitive).
    ///
    /// # Errors
    /// Any other extension.
    pub fn of(path: &Path) -> Result<Self, UnknownFormat> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(OutputFormat::Png),
            Some("svg") => Ok(OutputFormat::Svg),
            _ => Err(UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(OutputFormat::of(Path::new("a.PNG")), Ok(OutputFormat::Png));
        assert_eq!(OutputFormat::of(Path::new("a.svg")), Ok(OutputFormat::Svg));
        let err = OutputFormat::of(Path::new("a.jpg")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "a.jpg: unknown output format (use a .png or .svg file name)"
        );
    }

    #[test]
    fn the_cpu_is_always_there() {
        assert!(matches!(
            Rasterizer::choose(Backend::Cpu),
            Ok(Rasterizer::Cpu)
        ));
    }

    #[cfg(not(feature = "gpu"))]
    #[test]
    fn without_the_gpu_feature_auto_is_the_cpu_and_gpu_an_error() {
        assert!(matches!(
            Rasterizer::choose(Backend::Auto),
            Ok(Rasterizer::Cpu)
        ));
        let err = Rasterizer::choose(Backend::Gpu).err().expect("an error");
        assert!(
            err.to_string().contains("built without the gpu feature"),
            "{err}"
        );
    }
}
