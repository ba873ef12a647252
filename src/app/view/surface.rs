//! The window's GPU side: a wgpu surface (vsync), a LineList pipeline drawing the frame's
//! [`LineScene`] in pixel coordinates, and egui's renderer for the HUD on top.
//!
//! The lines are drawn by the offscreen backend's [`LineDrawer`] (same shader, vertex layout
//! and growth rule: the vertex buffer grows to the next power of two and is otherwise reused,
//! so a steady-state frame allocates no GPU buffer), so the window and the offscreen images
//! snap line ends to the same pixels; here it draws into a non-sRGB view of the window's
//! surface instead of an offscreen texture.

use std::sync::Arc;

use anyhow::{anyhow, Context};
use winit::window::Window;

use crate::draw::render::gpu::LineDrawer;
use crate::draw::render::LineScene;

/// What became of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    /// Drawn and presented.
    Yes,
    /// Nothing to draw into this time (minimised, occluded, timed out, or the surface was
    /// reconfigured); try again next frame.
    Skipped,
}

/// The HUD's share of a frame: egui's tessellated output.
pub struct HudFrame<'a> {
    /// Paint jobs from `Context::tessellate`.
    pub paint_jobs: &'a [egui::ClippedPrimitive],
    /// Texture uploads and frees; drained by [`WindowRenderer::draw`].
    pub textures: &'a mut egui::TexturesDelta,
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
}

/// Everything on the GPU for one window.
pub struct WindowRenderer {
    surface: wgpu::Surface<'static>,
    adapter_info: wgpu::AdapterInfo,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    view_format: wgpu::TextureFormat,
    lines: LineDrawer,
    egui: egui_wgpu::Renderer,
    lost_in_a_row: u32,
}

impl WindowRenderer {
    /// Set up wgpu for the window: surface, adapter (any that can present to it, Mesa's
    /// lavapipe included), device, pipelines.
    ///
    /// # Errors
    /// No adapter can present to the window, or the device cannot be created.
    pub fn new(
        instance: &wgpu::Instance,
        window: Arc<Window>,
        vsync: bool,
    ) -> anyhow::Result<Self> {
        let size = window.inner_size();
        let surface = instance
            .create_surface(window)
            .context("cannot create a wgpu surface for the window")?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            apply_limit_buckets: false,
        }))
        .map_err(|e| {
            anyhow!("no GPU adapter can draw into this window ({e}); on Linux without a GPU, install Mesa's Vulkan drivers (lavapipe: apt-get install mesa-vulkan-drivers)")
        })?;
        let adapter_info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("wireflight view"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .context("cannot open the GPU device")?;

        let caps = surface.get_capabilities(&adapter);
        let surface_format = *caps
            .formats
            .iter()
            .find(|f| !f.is_srgb())
            .or(caps.formats.first())
            .ok_or_else(|| {
                anyhow!(
                    "the window surface supports no texture format on {}",
                    adapter_info.name
                )
            })?;
        // Colours are sRGB bytes: draw them unchanged through a non-sRGB view (egui wants the
        // same).
        let view_format = surface_format.remove_srgb_suffix();
        let present_mode = if vsync {
            wgpu::PresentMode::AutoVsync
        } else {
            wgpu::PresentMode::AutoNoVsync
        };
        let max_side = device.limits().max_texture_dimension_2d;
        let mut config = surface
            .get_default_config(
                &adapter,
                size.width.clamp(1, max_side),
                size.height.clamp(1, max_side),
            )
            .ok_or_else(|| {
                anyhow!(
                    "the window surface is not supported by {}",
                    adapter_info.name
                )
            })?;
        config.format = surface_format;
        config.present_mode = present_mode;
        config.desired_maximum_frame_latency = 2;
        config.view_formats = if view_format == surface_format {
            vec![]
        } else {
            vec![view_format]
        };
        surface.configure(&device, &config);

        let lines = LineDrawer::new(&device, view_format);
        let egui = egui_wgpu::Renderer::new(
            &device,
            view_format,
            egui_wgpu::RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        Ok(Self {
            surface,
            adapter_info,
            device,
            queue,
            config,
            view_format,
            lines,
            egui,
            lost_in_a_row: 0,
        })
    }

    /// The adapter, in words (name and backend).
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.adapter_info.name, self.adapter_info.backend, self.config.present_mode
        )
    }

    /// Largest texture side the device takes (for egui's font atlas).
    pub fn max_texture_side(&self) -> usize {
        self.device.limits().max_texture_dimension_2d as usize
    }

    /// Current surface size, physical pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follow a window resize (physical pixels); a zero size (minimised) is ignored, and a
    /// side larger than the device's largest texture is clamped to it.
    pub fn resize(&mut self, width: u32, height: u32) {
        let max_side = self.device.limits().max_texture_dimension_2d;
        let (width, height) = (width.min(max_side), height.min(max_side));
        if width == 0 || height == 0 || (width, height) == (self.config.width, self.config.height) {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
    }

    /// Draw the line scene (which should have the surface's size) with the HUD on top, and
    /// present.
    ///
    /// # Errors
    /// The surface stays lost after reconfiguring, or a validation error.
    pub fn draw(&mut self, scene: &LineScene, hud: &mut HudFrame<'_>) -> anyhow::Result<Presented> {
        // egui's texture changes apply whether or not there is a frame to draw into.
        for (id, deltas) in hud.textures.set.drain() {
            for delta in &deltas {
                self.egui
                    .update_texture(&self.device, &self.queue, id, delta);
            }
        }
        let result = self.acquire_and_render(scene, hud);
        for id in hud.textures.free.drain() {
            self.egui.free_texture(&id);
        }
        result
    }

    fn acquire_and_render(
        &mut self,
        scene: &LineScene,
        hud: &HudFrame<'_>,
    ) -> anyhow::Result<Presented> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => f,
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
                // Use it, reconfigure for the next one.
                self.lost_in_a_row = 0;
                let out = self.render_into(f, scene, hud);
                self.surface.configure(&self.device, &self.config);
                return out;
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(Presented::Skipped)
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.lost_in_a_row += 1;
                if self.lost_in_a_row > 10 {
                    anyhow::bail!("the window surface keeps getting lost");
                }
                self.surface.configure(&self.device, &self.config);
                return Ok(Presented::Skipped);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                anyhow::bail!("wgpu validation error while acquiring the window surface")
            }
        };
        self.lost_in_a_row = 0;
        self.render_into(frame, scene, hud)
    }

    fn render_into(
        &mut self,
        frame: wgpu::SurfaceTexture,
        scene: &LineScene,
        hud: &HudFrame<'_>,
    ) -> anyhow::Result<Presented> {
        let (width, height) = (frame.texture.width(), frame.texture.height());
        self.lines
            .prepare(&self.device, &self.queue, scene, (width, height))
            .map_err(|e| anyhow!("drawing the frame: {e}"))?;

        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [width, height],
            pixels_per_point: hud.pixels_per_point,
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view frame"),
            });
        let egui_commands = self.egui.update_buffers(
            &self.device,
            &self.queue,
            &mut encoder,
            hud.paint_jobs,
            &screen,
        );

        let view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let bg = scene.background.map(|c| f64::from(c) / 255.0);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("view lines + hud"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color {
                                r: bg[0],
                                g: bg[1],
                                b: bg[2],
                                a: bg[3],
                            }),
                            store: wgpu::StoreOp::Store,
                        },
                        depth_slice: None,
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.lines.draw(&mut pass);
            self.egui.render(&mut pass, hud.paint_jobs, &screen);
        }
        self.queue
            .submit(egui_commands.into_iter().chain([encoder.finish()]));
        self.queue.present(frame);
        Ok(Presented::Yes)
    }
}
