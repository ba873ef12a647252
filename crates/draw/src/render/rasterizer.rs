//! Choosing a rasterizer: the wgpu backend when an adapter exists (Mesa lavapipe counts), the
//! bit-exact CPU one otherwise or on request, and the output formats by file name.

use std::path::Path;

use anyhow::bail;

use super::{Image, LineScene};

/// Which rasterizer draws a raster image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// GPU if any wgpu adapter exists, else CPU (with a note on stderr).
    #[default]
    Auto,
    /// wgpu only; fails without an adapter.
    Gpu,
    /// Bresenham on the CPU (bit-exact).
    Cpu,
}

/// A rasterizer chosen by [`Backend`]. Create it once and draw every frame with it: the GPU
/// one opens its device and builds its pipeline on creation.
pub enum Rasterizer {
    /// Bresenham on the CPU.
    Cpu,
    /// wgpu (any adapter, Mesa lavapipe included).
    Gpu {
        /// The renderer (device, pipeline, frame buffers).
        renderer: Box<super::gpu::GpuRenderer>,
        /// Chosen by `auto`: a failing frame falls back to the CPU instead of failing the run.
        fallback: bool,
    },
}

impl Rasterizer {
    /// Pick a backend and say which on stderr: `GPU: <adapter> (<backend>)`, or for `Auto`
    /// without a usable adapter one line with the reason and that the CPU draws instead.
    ///
    /// # Errors
    /// `Gpu` without a usable adapter.
    pub fn choose(choice: Backend) -> anyhow::Result<Self> {
        let gpu = match choice {
            Backend::Cpu => return Ok(Rasterizer::Cpu),
            Backend::Gpu | Backend::Auto => super::gpu::GpuRenderer::new(),
        };
        match gpu {
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
            Err(err) => Err(anyhow::Error::new(err).context("--backend gpu")),
        }
    }

    /// Short name for messages.
    pub fn describe(&self) -> String {
        match self {
            Rasterizer::Cpu => "cpu (Bresenham)".to_string(),
            Rasterizer::Gpu { renderer, .. } => format!("gpu: {}", renderer.adapter()),
        }
    }

    /// Draw a scene. Under `auto`, a GPU failure switches to the CPU for this and every later
    /// frame, with a note on stderr.
    ///
    /// # Errors
    /// GPU failures (`--backend gpu`).
    pub fn draw(&mut self, scene: &LineScene) -> anyhow::Result<Image> {
        match self {
            Rasterizer::Cpu => Ok(super::cpu::render(scene)),
            Rasterizer::Gpu { renderer, fallback } => match renderer.render(scene) {
                Ok(image) => Ok(image),
                Err(err) if *fallback => {
                    eprintln!("wireflight: GPU frame failed ({err}); drawing on the CPU");
                    *self = Rasterizer::Cpu;
                    Ok(super::cpu::render(scene))
                }
                Err(err) => Err(err.into()),
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

impl OutputFormat {
    /// The format of an output path (`.png` or `.svg`, case-insensitive).
    ///
    /// # Errors
    /// Any other extension.
    pub fn of(path: &Path) -> anyhow::Result<Self> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(OutputFormat::Png),
            Some("svg") => Ok(OutputFormat::Svg),
            _ => bail!(
                "{}: unknown output format (use a .png or .svg file name)",
                path.display()
            ),
        }
    }
}
