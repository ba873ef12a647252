//! GPU backend: a wgpu `LineList` pipeline drawing into an offscreen texture, read back into an
//! [`Image`].
//!
//! [`GpuRenderer::new`] does everything expensive once: instance, adapter, device, shader
//! (`shaders/line.wgsl`), pipeline. [`GpuRenderer::render`] then only uploads vertices and
//! records one pass per frame; the target texture and the readback buffer are kept while the
//! frame size stays the same, and the vertex buffer only grows (to the next power of two), so a
//! steady stream of frames allocates no GPU resources.
//!
//! Choices that keep the two backends' pictures the same:
//!
//! * **`Rgba8Unorm`, not `Rgba8UnormSrgb`.** Scene colours are plain bytes (not sRGB-encoded
//!   light); an sRGB target would re-encode them on store and the bytes read back would differ
//!   from the CPU backend's. With a unorm target `c/255` round-trips to `c` exactly, and blending
//!   is off (lines replace what is below, as on the CPU).
//! * **No MSAA, 1-pixel lines** (wgpu lines are always one pixel wide): lit pixels are either
//!   the line colour or untouched background, never a blend.
//! * **Endpoints snap to pixel centres** in the vertex shader, in the CPU backend's convention
//!   (an endpoint lands in pixel (⌊x⌋, ⌊y⌋), clamped into the image). That also keeps segments
//!   that the clipper leaves exactly on the right or bottom edge (x = width) inside the image.
//!   What remains different is how the hardware steps between the endpoints (diamond-exit rule,
//!   tie-breaking, the last pixel of a line being left out), which moves a pixel by at most one;
//!   `tests/gpu_backend.rs` holds the backends to that.
//!
//! Readback: `copy_texture_to_buffer` requires `bytes_per_row` to be a multiple of
//! [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`] (256 bytes = 64 RGBA8 pixels), so the readback buffer
//! holds rows padded to that size; [`GpuRenderer::render`] strips the padding row by row into the
//! tightly packed [`Image`]. (Copying the padded buffer as one block would shear every image whose
//! width is not a multiple of 64.)
//!
//! Failures (no adapter, device lost, validation or out-of-memory errors, map failures) are
//! [`GpuError`]s, never panics: the device's uncaptured-error handler and device-lost callback
//! record them and the next call reports them.

use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use bytemuck::{Pod, Zeroable};
use thiserror::Error;

use super::{Image, LineScene, Rgba};

/// The WGSL source of the pipeline.
const SHADER: &str = include_str!("../../../../shaders/line.wgsl");

/// Format of the offscreen target (see the module docs for why not sRGB).
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Bytes per pixel of [`FORMAT`].
const BYTES_PER_PIXEL: u32 = 4;

/// How long one frame may take on the device before it counts as hung.
const FRAME_TIMEOUT: Duration = Duration::from_secs(60);

/// Why the GPU backend could not draw.
#[derive(Debug, Error)]
pub enum GpuError {
    /// No wgpu adapter on this machine (not even a software one such as Mesa lavapipe).
    #[error("no GPU adapter found ({0}); for a software one install Mesa's Vulkan driver (apt-get install mesa-vulkan-drivers)")]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("cannot open the GPU device: {0}")]
    RequestDevice(#[from] wgpu::RequestDeviceError),
    /// The frame does not fit the device's limits.
    #[error("{width}x{height} does not fit the GPU's limits ({limit})")]
    TooLarge {
        /// Requested width, pixels.
        width: u32,
        /// Requested height, pixels.
        height: u32,
        /// The limit that is exceeded.
        limit: String,
    },
    /// The device was lost (driver reset, removal) or reported an error.
    #[error("GPU device error: {0}")]
    Device(String),
    /// Waiting for the frame failed or timed out.
    #[error("waiting for the GPU: {0}")]
    Poll(#[from] wgpu::PollError),
    /// Mapping the readback buffer failed.
    #[error("reading the frame back from the GPU: {0}")]
    Map(String),
}

/// The vertices of a scene do not fit one GPU buffer ([`LineDrawer::prepare`]).
#[derive(Debug, Error)]
#[error("{segments} segments need {bytes} bytes of vertices, max_buffer_size {max}")]
pub struct TooManyVertices {
    /// Segments in the scene.
    pub segments: usize,
    /// Bytes their vertices need.
    pub bytes: u64,
    /// The device's `max_buffer_size`.
    pub max: u64,
}

/// One line endpoint: position in pixels and colour as bytes (read as unorm8x4 by the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LineVertex {
    /// Pixel coordinates (top-left origin, y down).
    pub pixel: [f32; 2],
    /// RGBA, 8 bits each.
    pub color: Rgba,
}

/// The shader's `Viewport` uniform.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ViewportUniform {
    size: [f32; 2],
    pad: [f32; 2],
}

/// The line pipeline (`shaders/line.wgsl`, `LineList`, no blending) with its viewport uniform
/// and a growing vertex buffer: everything needed to draw a [`LineScene`] into a render pass of
/// one colour format. Shared by [`GpuRenderer`] (offscreen) and the window's surface
/// (`app::view`), so the two draw lines the same way.
pub struct LineDrawer {
    pipeline: wgpu::RenderPipeline,
    viewport_uniform: wgpu::Buffer,
    /// The size the uniform holds (rewritten only when it changes).
    viewport: (u32, u32),
    bind_group: wgpu::BindGroup,
    /// Vertex buffer; its size is its capacity (a power of two of vertices, at least 1024).
    vertex_buffer: wgpu::Buffer,
    /// CPU-side vertices of the current frame (kept to reuse the allocation).
    vertices: Vec<LineVertex>,
}

impl LineDrawer {
    /// Build the pipeline for render targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("line.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewport"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(
                        std::mem::size_of::<ViewportUniform>() as u64
                    ),
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lines"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x2, 1 => Unorm8x4];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lines"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineList,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let viewport_uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewport"),
            size: std::mem::size_of::<ViewportUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport"),
            layout: &bind_group_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: viewport_uniform.as_entire_binding(),
            }],
        });
        Self {
            pipeline,
            viewport_uniform,
            viewport: (0, 0),
            bind_group,
            vertex_buffer: Self::vertex_buffer(device, 1024),
            vertices: Vec::new(),
        }
    }

    /// A vertex buffer for `vertices` vertices.
    fn vertex_buffer(device: &wgpu::Device, vertices: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("line vertices"),
            size: vertices * std::mem::size_of::<LineVertex>() as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Upload the scene's segments (two vertices each, in batch order, so later batches land on
    /// top) and the target size, `width`×`height` pixels. Grows the vertex buffer when needed.
    ///
    /// # Errors
    /// More vertex bytes than the device's `max_buffer_size` (the message says how many).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &LineScene,
        (width, height): (u32, u32),
    ) -> Result<(), TooManyVertices> {
        self.vertices.clear();
        self.vertices.reserve(2 * scene.segment_count());
        for batch in &scene.batches {
            for s in &batch.segments {
                for p in [s.a, s.b] {
                    self.vertices.push(LineVertex {
                        pixel: p.to_array(),
                        color: batch.color,
                    });
                }
            }
        }
        let bytes = std::mem::size_of_val(self.vertices.as_slice()) as u64;
        if bytes > self.vertex_buffer.size() {
            let max = device.limits().max_buffer_size;
            if bytes > max {
                return Err(TooManyVertices {
                    segments: scene.segment_count(),
                    bytes,
                    max,
                });
            }
            let stride = std::mem::size_of::<LineVertex>() as u64;
            let capacity = (self.vertices.len() as u64).next_power_of_two() * stride;
            self.vertex_buffer = Self::vertex_buffer(device, capacity.min(max) / stride);
        }
        if bytes > 0 {
            queue.write_buffer(&self.vertex_buffer, 0, bytemuck::cast_slice(&self.vertices));
        }
        if self.viewport != (width, height) {
            self.viewport = (width, height);
            let uniform = ViewportUniform {
                size: [width as f32, height as f32],
                pad: [0.0; 2],
            };
            queue.write_buffer(&self.viewport_uniform, 0, bytemuck::bytes_of(&uniform));
        }
        Ok(())
    }

    /// Record the draw of what [`prepare`](Self::prepare) uploaded into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.vertices.is_empty() {
            return;
        }
        let bytes = std::mem::size_of_val(self.vertices.as_slice()) as u64;
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..bytes));
        pass.draw(0..self.vertices.len() as u32, 0..1);
    }
}

/// Size-dependent resources: the target texture and the readback buffer.
struct Target {
    width: u32,
    height: u32,
    /// `width * 4` rounded up to [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`].
    padded_bytes_per_row: u32,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    readback: wgpu::Buffer,
}

/// Errors reported by wgpu outside any call's return value.
#[derive(Default)]
struct ErrorSlots {
    /// Set once when the device is lost; every later frame fails with it.
    lost: Option<String>,
    /// First uncaptured validation / out-of-memory / internal error since the last check.
    error: Option<String>,
}

/// The adapter a [`GpuRenderer`] runs on, for messages.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. `llvmpipe (LLVM 19.1.7, 256 bits)`.
    pub name: String,
    /// Graphics API, e.g. `vulkan`.
    pub backend: String,
    /// `DiscreteGpu`, `IntegratedGpu`, `Cpu` (software rasterizers such as lavapipe), ...
    pub device_type: String,
    /// Driver name and version, if the backend reports them.
    pub driver: String,
}

impl std::fmt::Display for AdapterSummary {
    /// `name (backend)`, e.g. `llvmpipe (LLVM 19.1.7, 256 bits) (vulkan)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.name, self.backend)
    }
}

/// A wgpu line renderer: create once, then [`render`](Self::render) any number of frames.
pub struct GpuRenderer {
    adapter: AdapterSummary,
    device: wgpu::Device,
    queue: wgpu::Queue,
    lines: LineDrawer,
    target: Option<Target>,
    errors: Arc<Mutex<ErrorSlots>>,
}

impl GpuRenderer {
    /// Open a device and build the pipeline.
    ///
    /// Any adapter will do, software ones such as Mesa lavapipe included, but hardware is
    /// preferred (wgpu ranks discrete, integrated, other, virtual, then CPU adapters). The
    /// backends can be chosen with wgpu's `WGPU_BACKEND` environment variable (e.g. `vulkan`).
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] when none exists; device creation and pipeline errors.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let adapter = Self::request_adapter().await?;
        let info = adapter.get_info();
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: info.backend.to_string(),
            device_type: format!("{:?}", info.device_type),
            driver: [info.driver.as_str(), info.driver_info.as_str()]
                .iter()
                .filter(|s| !s.is_empty())
                .copied()
                .collect::<Vec<_>>()
                .join(" "),
        };
        // All the adapter offers: large frames need its full texture and buffer sizes.
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("wireflight"),
                required_features: wgpu::Features::empty(),
                required_limits: adapter.limits(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await?;

        let errors = Arc::new(Mutex::new(ErrorSlots::default()));
        {
            let errors = Arc::clone(&errors);
            device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                let mut slots = errors.lock().unwrap_or_else(|p| p.into_inner());
                slots.error.get_or_insert_with(|| e.to_string());
            }));
        }
        {
            let errors = Arc::clone(&errors);
            device.set_device_lost_callback(move |reason, message| {
                let mut slots = errors.lock().unwrap_or_else(|p| p.into_inner());
                slots
                    .lost
                    .get_or_insert_with(|| format!("device lost ({reason:?}): {message}"));
            });
        }

        let lines = LineDrawer::new(&device, FORMAT);

        let renderer = Self {
            adapter: summary,
            device,
            queue,
            lines,
            target: None,
            errors,
        };
        renderer.check_errors()?;
        Ok(renderer)
    }

    /// The first adapter found: primary backends (Vulkan, Metal, DX12) before OpenGL, which is
    /// only probed when they have none (probing EGL prints noise on headless machines); within
    /// each, any adapter before explicitly a fallback one. `WGPU_BACKEND` overrides the order.
    async fn request_adapter() -> Result<wgpu::Adapter, GpuError> {
        let tiers = match wgpu::Backends::from_env() {
            Some(backends) => vec![backends],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
        let mut why = Vec::new();
        for backends in tiers {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            for force_fallback_adapter in [false, true] {
                let options = wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    force_fallback_adapter,
                    compatible_surface: None,
                    apply_limit_buckets: false,
                };
                match instance.request_adapter(&options).await {
                    Ok(adapter) => return Ok(adapter),
                    Err(e) if !force_fallback_adapter => why.push(e.to_string()),
                    Err(_) => {}
                }
            }
        }
        Err(GpuError::NoAdapter(why.join("; ")))
    }

    /// The adapter this renderer draws with.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    /// Draw a scene: clear to its background, then its batches in order (one draw call; the
    /// GPU keeps primitive order, so later batches lie on top as on the CPU).
    ///
    /// # Errors
    /// Frames larger than the device allows, device loss, wgpu errors, readback failures.
    pub fn render(&mut self, scene: &LineScene) -> Result<Image, GpuError> {
        self.check_errors()?;
        self.ensure_target(scene.width, scene.height)?;
        let result = self.draw(scene);
        if result.is_err() {
            // The readback buffer may be left mapped or pending: start the next frame afresh.
            self.target = None;
        }
        result
    }

    /// [`render`](Self::render) once the target exists.
    fn draw(&mut self, scene: &LineScene) -> Result<Image, GpuError> {
        self.lines
            .prepare(
                &self.device,
                &self.queue,
                scene,
                (scene.width, scene.height),
            )
            .map_err(|e| GpuError::TooLarge {
                width: scene.width,
                height: scene.height,
                limit: e.to_string(),
            })?;
        let target = self.target.as_ref().expect("ensure_target made one");
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        {
            let [r, g, b, a] = scene.background.map(|c| f64::from(c) / 255.0);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("lines"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.lines.draw(&mut pass);
        }
        encoder.copy_texture_to_buffer(
            target.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &target.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(target.padded_bytes_per_row),
                    rows_per_image: Some(target.height),
                },
            },
            wgpu::Extent3d {
                width: target.width,
                height: target.height,
                depth_or_array_layers: 1,
            },
        );
        let submission = self.queue.submit([encoder.finish()]);

        let (sender, receiver) = mpsc::channel();
        let slice = target.readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        self.device.poll(wgpu::PollType::Wait {
            submission_index: Some(submission),
            timeout: Some(FRAME_TIMEOUT),
        })?;
        self.check_errors()?;
        match receiver.try_recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(GpuError::Map(e.to_string())),
            Err(_) => {
                return Err(GpuError::Map(
                    "the buffer was not mapped after the frame completed".into(),
                ))
            }
        }

        // Strip the row padding (see the module docs); unmap whatever happens.
        let row_bytes = (target.width * BYTES_PER_PIXEL) as usize;
        let pixels = slice.get_mapped_range().map(|mapped| {
            let mut pixels = Vec::with_capacity(row_bytes * target.height as usize);
            for row in mapped.chunks_exact(target.padded_bytes_per_row as usize) {
                pixels.extend_from_slice(&row[..row_bytes]);
            }
            pixels
        });
        target.readback.unmap();
        Ok(Image {
            width: target.width,
            height: target.height,
            pixels: pixels.map_err(|e| GpuError::Map(e.to_string()))?,
        })
    }

    /// Make the target texture and readback buffer `width`×`height`, keeping them if they
    /// already are.
    fn ensure_target(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        if self
            .target
            .as_ref()
            .is_some_and(|t| (t.width, t.height) == (width, height))
        {
            return Ok(());
        }
        let limits = self.device.limits();
        let too_large = |limit: String| GpuError::TooLarge {
            width,
            height,
            limit,
        };
        let side = limits.max_texture_dimension_2d;
        if width == 0 || height == 0 || width > side || height > side {
            return Err(too_large(format!("sides 1..={side}")));
        }
        let padded_bytes_per_row =
            (width * BYTES_PER_PIXEL).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback_size = u64::from(padded_bytes_per_row) * u64::from(height);
        if readback_size > limits.max_buffer_size {
            return Err(too_large(format!(
                "readback of {readback_size} bytes, max_buffer_size {}",
                limits.max_buffer_size
            )));
        }
        // Free the old frame's memory before allocating the new one.
        self.target = None;
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("frame"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: readback_size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        self.target = Some(Target {
            width,
            height,
            padded_bytes_per_row,
            texture,
            view,
            readback,
        });
        self.check_errors()
    }

    /// Report a lost device (every time) or an uncaptured error (once).
    fn check_errors(&self) -> Result<(), GpuError> {
        let mut slots = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(lost) = &slots.lost {
            return Err(GpuError::Device(lost.clone()));
        }
        match slots.error.take() {
            Some(e) => Err(GpuError::Device(e)),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_layout_matches_the_shader() {
        // Float32x2 at offset 0, Unorm8x4 at offset 8, stride 12.
        assert_eq!(std::mem::size_of::<LineVertex>(), 12);
        assert_eq!(std::mem::size_of::<ViewportUniform>(), 16);
    }
}
