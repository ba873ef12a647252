//! `wireflight render`: one oriented model → clipped wireframe → PNG or SVG.

use std::path::Path;

use anyhow::{bail, Context};

use crate::app::cli::{BackendArg, ProjectionArg, RenderArgs};
use crate::camera::{CameraPreset, Projection, Subject};
use crate::clip::{ClipStats, DepthRange};
use crate::euler::EulerZyx;
use crate::mesh::{self, EdgeMesh};
use crate::pipeline::{model_matrix, EdgeProjector, Viewport};
use crate::render::{self, palette, Image, LineBatch, LineScene};

/// Everything that decides one still frame of one model, apart from the model itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSpec {
    /// Attitude of the model (body → world).
    pub attitude: EulerZyx,
    /// Camera placement.
    pub camera: CameraPreset,
    /// Parallel instead of perspective projection.
    pub orthographic: bool,
    /// Vertical field of view, degrees (perspective), in (0, 180).
    pub fov_y_deg: f64,
    /// Output image.
    pub viewport: Viewport,
    /// Clip-space depth convention (wgpu's 0..w unless testing OpenGL's −w..w).
    pub depth: DepthRange,
    /// Camera pan `[right, up]` in bounding radii (moves the model the other way in the frame).
    pub pan: [f32; 2],
}

impl Default for ViewSpec {
    fn default() -> Self {
        Self {
            attitude: EulerZyx::default(),
            camera: CameraPreset::Chase,
            orthographic: false,
            fov_y_deg: 50.0,
            viewport: Viewport {
                width: 800,
                height: 600,
            },
            depth: DepthRange::ZeroToOne,
            pan: [0.0, 0.0],
        }
    }
}

/// Build the frame: model at the world origin in the given attitude, seen by the preset
/// camera, clipped and projected. Returns the line scene and the clipper's counts.
pub fn frame(mesh: &EdgeMesh, spec: &ViewSpec) -> (LineScene, ClipStats) {
    let (centre, radius) = mesh.bounding_sphere();
    let subject = Subject {
        position: glam::Vec3::ZERO,
        attitude: spec.attitude,
        centre,
        radius,
    };
    let mut camera = spec
        .camera
        .camera(&subject, (spec.fov_y_deg as f32).to_radians())
        .panned(spec.pan[0] * radius, spec.pan[1] * radius);
    if spec.orthographic {
        if let Projection::Perspective { near, far, .. } = camera.projection {
            camera.projection = Projection::Orthographic {
                half_height: 1.1 * radius,
                near,
                far,
            };
        }
    }
    let clip_from_model = camera.clip_from_world(spec.viewport.aspect(), spec.depth)
        * model_matrix(subject.position, spec.attitude);
    let mut segments = Vec::with_capacity(mesh.edges().len());
    let stats = EdgeProjector::new().project(
        mesh,
        clip_from_model,
        spec.depth,
        spec.viewport,
        &mut segments,
    );
    let scene = LineScene {
        width: spec.viewport.width,
        height: spec.viewport.height,
        background: palette::BACKGROUND,
        batches: vec![LineBatch {
            color: palette::MODEL,
            segments,
        }],
    };
    (scene, stats)
}

/// The model named on the command line: `plane` is the built-in aircraft, anything else a file.
///
/// # Errors
/// Loading errors naming the file.
pub fn load_model(name: &str) -> anyhow::Result<EdgeMesh> {
    if name == "plane" {
        return Ok(mesh::plane::builtin_plane());
    }
    Ok(mesh::load(Path::new(name))?)
}

/// A rasterizer chosen by `--backend`. Create it once and draw every frame with it: the GPU
/// one opens its device and builds its pipeline on creation.
pub enum Rasterizer {
    /// Bresenham on the CPU.
    Cpu,
    /// wgpu (any adapter, Mesa lavapipe included).
    Gpu {
        /// The renderer (device, pipeline, frame buffers).
        renderer: Box<render::gpu::GpuRenderer>,
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
    pub fn choose(choice: BackendArg) -> anyhow::Result<Self> {
        let gpu = match choice {
            BackendArg::Cpu => return Ok(Rasterizer::Cpu),
            BackendArg::Gpu | BackendArg::Auto => render::gpu::GpuRenderer::new(),
        };
        match gpu {
            Ok(renderer) => {
                eprintln!("GPU: {}", renderer.adapter());
                Ok(Rasterizer::Gpu {
                    renderer: Box::new(renderer),
                    fallback: choice == BackendArg::Auto,
                })
            }
            Err(err) if choice == BackendArg::Auto => {
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
            Rasterizer::Cpu => Ok(render::cpu::render(scene)),
            Rasterizer::Gpu { renderer, fallback } => match renderer.render(scene) {
                Ok(image) => Ok(image),
                Err(err) if *fallback => {
                    eprintln!("wireflight: GPU frame failed ({err}); drawing on the CPU");
                    *self = Rasterizer::Cpu;
                    Ok(render::cpu::render(scene))
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

/// Run `wireflight render`.
///
/// # Errors
/// Bad model files, unknown output format, GPU failures with `--backend gpu`, write errors.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mesh = load_model(&args.model)?;
    let viewport = Viewport {
        width: args.size.0,
        height: args.size.1,
    };
    if let (Some(flight), Some(dir)) = (&args.flight, &args.frames_dir) {
        let data = crate::flight::data::read(flight)?;
        let mut rasterizer = Rasterizer::choose(args.backend)?;
        let (frames, stats) = super::replay::write_frames(
            &data,
            None,
            &mesh,
            viewport,
            args.fps,
            dir,
            &mut rasterizer,
        )?;
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
    let format = OutputFormat::of(out)?;
    let spec = ViewSpec {
        attitude: EulerZyx::from_degrees(args.yaw, args.pitch, args.roll),
        camera: args.camera.into(),
        orthographic: args.projection == ProjectionArg::Ortho,
        fov_y_deg: args.fov,
        viewport,
        depth: DepthRange::ZeroToOne,
        pan: args.pan,
    };
    let (scene, stats) = frame(&mesh, &spec);
    let (bytes, how) = match format {
        OutputFormat::Png => {
            let mut rasterizer = Rasterizer::choose(args.backend)?;
            let image = rasterizer.draw(&scene)?;
            let png = image.encode_png().context("encoding PNG")?;
            (png, rasterizer.describe())
        }
        OutputFormat::Svg => (render::svg::to_svg(&scene).into_bytes(), "svg".to_string()),
    };
    crate::fsio::write_atomic(out, &bytes)?;
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
