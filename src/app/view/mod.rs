//! `wireflight view`: the fly-through window.
//!
//! This module is the I/O shell — winit window and events, the wgpu surface ([`surface`]), the
//! egui HUD, files. Everything it shows comes from a [`session::Session`] of
//! [`wireflight_draw::flythrough`] (in `--compare` mode with the compare panel of
//! [`wireflight_present::flythrough`] as its model panel), which is pure: model → transform →
//! clip (on the CPU, Blinn) → draw, one way.

mod hud;
pub mod surface;

pub use wireflight_draw::flythrough::{cameras, flight, gimbal, script, session};
pub use wireflight_present::flythrough::{compare, discovery};

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context};
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::app::cli::{ViewArgs, ViewCameraArg};
use crate::draw::render::LineScene;
use crate::draw::render::{OutputFormat, Rasterizer};
use crate::flight::spec::ModelChoice;
use crate::geometry::pipeline::Viewport;
use cameras::CameraMode;
use compare::Compare;
use flight::Start;
pub use hud::compare_panel_texts;
use hud::{
    compare_summary, draw_compare, draw_euler, draw_help, draw_hud, screenshot_scene,
    CompareActions, EulerChanges, HudData, Meter,
};
use session::{Held, Session, Source, SEEK_S};
use surface::{HudFrame, Presented, WindowRenderer};

impl From<ViewCameraArg> for CameraMode {
    fn from(c: ViewCameraArg) -> Self {
        match c {
            ViewCameraArg::Chase => CameraMode::Chase,
            ViewCameraArg::Cockpit => CameraMode::Cockpit,
            ViewCameraArg::Orbit => CameraMode::Orbit,
            ViewCameraArg::Free => CameraMode::Free,
        }
    }
}

/// The key help, shown by the help overlay (`--help` has the same list).
pub const KEY_HELP: &[(&str, &str)] = &[
    ("Up / Down", "nose down / nose up"),
    ("Left / Right", "roll left / right (replay: seek -/+ 5 s)"),
    ("Q / E", "yaw left / right"),
    ("+ / -", "throttle up / down"),
    ("C", "cycle camera: chase, cockpit, orbit, free"),
    ("G", "Euler angles: gimbal rings and sliders"),
    (
        "K",
        "cycle line clipper: blinn, cohen-sutherland, liang-barsky, cyrus-beck, sutherland-hodgman",
    ),
    ("Space", "pause / resume (replay: play / pause)"),
    ("R", "reset"),
    ("H or F1", "this help"),
    ("F12 or P", "screenshot (PNG, CPU rasterizer)"),
    ("Esc", "quit"),
    ("mouse drag", "orbit: turn around; free: look"),
    ("wheel", "orbit: zoom; free: speed"),
    ("W A S D", "free camera: move"),
    ("PgUp / PgDn", "free camera: up / down (Shift: 4× faster)"),
];

/// Run `wireflight view`.
///
/// # Errors
/// Bad model, script or flight files (named, with the line), no display, no GPU adapter that
/// can present to a window, a screenshot that cannot be written.
pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    if let Some(shot) = &args.screenshot {
        let inputs = crate::app::outputs::given(&[
            ("--script", args.script.as_deref()),
            ("--flight", args.flight.as_deref()),
            ("--model", args.model.as_deref()),
        ]);
        crate::app::outputs::check_outputs(&inputs, &[("--screenshot", shot)], &[])?;
        if OutputFormat::of(shot)? != OutputFormat::Png {
            bail!(
                "{}: screenshots are PNG files (use a .png name)",
                shot.display()
            );
        }
    }
    let mesh = crate::draw::mesh_files::load_named(&args.mesh)?;
    let fov_y = (args.fov as f32).to_radians();
    let camera = CameraMode::from(args.camera);
    let mut session = match &args.flight {
        Some(path) if args.compares() => {
            let choice = ModelChoice {
                model_file: args.model.clone(),
                vehicle: args.vehicle,
                aircraft: args.aircraft.clone(),
                effects: args.effects.clone(),
            };
            let data = crate::app::data::load_flight(path, &args.data)?;
            let base = choice.build(path, &data)?;
            let data = Arc::new(data);
            let compare = Compare::new(Arc::clone(&data), base, &args.add)
                .with_context(|| format!("{}: cannot compare", path.display()))?;
            Session::replay(mesh, (*data).clone(), camera, fov_y)
                .with_context(|| format!("{}: cannot replay", path.display()))?
                .with_compare(compare)
        }
        Some(path) => {
            let data = crate::app::data::load_flight(path, &args.data)?;
            Session::replay(mesh, data, camera, fov_y)
                .with_context(|| format!("{}: cannot replay", path.display()))?
        }
        None => {
            let script = args.script.as_deref().map(script::load).transpose()?;
            Session::fly(mesh, Start::default(), script, camera, fov_y)
        }
    };
    session.set_clipper(args.clipper);
    if let Some(convention) = args.gimbal {
        session.euler = gimbal::EulerPanel::new(convention);
        session.toggle_euler();
        if let Some(degrees) = args.gimbal_angles {
            session.set_euler_degrees(degrees);
        }
    }
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!(
            "cannot open a window: {e} (no display? set DISPLAY or WAYLAND_DISPLAY, or run under xvfb-run)"
        )
    })?;
    let mut app = App::new(args, session, event_loop.owned_display_handle());
    let result = event_loop.run_app(&mut app);
    if let Some(err) = app.error.take() {
        return Err(err);
    }
    result.context("the window's event loop failed")?;
    app.report();
    Ok(())
}

/// Run options that the window needs.
struct Options {
    size: (u32, u32),
    vsync: bool,
    frames: Option<u64>,
    screenshot: Option<PathBuf>,
    /// Fixed time step, when the run is scripted or counted.
    fixed_dt: Option<f64>,
}

/// The window and what draws into it (created on `resumed`).
struct Gfx {
    window: Arc<Window>,
    renderer: WindowRenderer,
    egui: egui_winit::State,
    // Kept alive with its surface.
    _instance: wgpu::Instance,
}

struct App {
    options: Options,
    session: Session,
    display: OwnedDisplayHandle,
    gfx: Option<Gfx>,
    egui_ctx: egui::Context,
    keys: Vec<KeyCode>,
    drag: Option<winit::dpi::PhysicalPosition<f64>>,
    dragging: bool,
    show_help: bool,
    last_tick: Option<Instant>,
    meter: Meter,
    note: Option<(String, Instant)>,
    shot_counter: u32,
    error: Option<anyhow::Error>,
    adapter: String,
    wait_until: Option<Instant>,
}

const NOTE_SECONDS: u64 = 4;

impl App {
    fn new(args: &ViewArgs, session: Session, display: OwnedDisplayHandle) -> Self {
        let fixed = args.frames.is_some() || args.script.is_some();
        Self {
            options: Options {
                size: args.size,
                vsync: !args.no_vsync,
                frames: args.frames,
                screenshot: args.screenshot.clone(),
                fixed_dt: fixed.then_some(args.dt),
            },
            session,
            display,
            gfx: None,
            egui_ctx: egui::Context::default(),
            keys: Vec::new(),
            drag: None,
            dragging: false,
            show_help: args.frames.is_none(),
            last_tick: None,
            meter: Meter::default(),
            note: None,
            shot_counter: 0,
            error: None,
            adapter: String::new(),
            wait_until: None,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, err: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(err);
        }
        event_loop.exit();
    }

    fn create_gfx(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<Gfx> {
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("wireflight view")
            .with_inner_size(LogicalSize::new(w as f64, h as f64))
            .with_resizable(true);
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(self.display.clone()),
            ));
        let renderer = WindowRenderer::new(&instance, window.clone(), self.options.vsync)?;
        self.adapter = renderer.describe();
        let egui = egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(renderer.max_texture_side()),
        );
        window.request_redraw();
        Ok(Gfx {
            window,
            renderer,
            egui,
            _instance: instance,
        })
    }

    fn held(&self) -> Held {
        let down = |codes: &[KeyCode]| codes.iter().any(|c| self.keys.contains(c));
        let flying = matches!(self.session.source, Source::Fly { .. });
        Held {
            pitch_up: flying && down(&[KeyCode::ArrowDown]),
            pitch_down: flying && down(&[KeyCode::ArrowUp]),
            roll_left: flying && down(&[KeyCode::ArrowLeft]),
            roll_right: flying && down(&[KeyCode::ArrowRight]),
            yaw_left: down(&[KeyCode::KeyQ]),
            yaw_right: down(&[KeyCode::KeyE]),
            throttle_up: down(&[KeyCode::Equal, KeyCode::NumpadAdd]),
            throttle_down: down(&[KeyCode::Minus, KeyCode::NumpadSubtract]),
            forward: down(&[KeyCode::KeyW]),
            backward: down(&[KeyCode::KeyS]),
            left: down(&[KeyCode::KeyA]),
            right: down(&[KeyCode::KeyD]),
            up: down(&[KeyCode::PageUp]),
            down: down(&[KeyCode::PageDown]),
            fast: down(&[KeyCode::ShiftLeft, KeyCode::ShiftRight]),
        }
    }

    /// Whether background work (a recomputation, the fit) will want a redraw when it ends.
    fn waiting_for_work(&self) -> bool {
        self.session.compare().is_some_and(Compare::busy)
    }

    /// Whether frames should keep coming without input.
    fn animating(&self) -> bool {
        self.options.frames.is_some() || !self.session.paused || self.held().moving_camera()
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode, pressed: bool, repeat: bool) {
        if pressed {
            if !self.keys.contains(&code) {
                self.keys.push(code);
            }
        } else {
            self.keys.retain(|&c| c != code);
            return;
        }
        let replay = matches!(self.session.source, Source::Replay(_));
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::ArrowLeft if replay => self.session.seek(-SEEK_S),
            KeyCode::ArrowRight if replay => self.session.seek(SEEK_S),
            _ if repeat => {}
            KeyCode::KeyC => self.session.cycle_camera(),
            KeyCode::KeyG => self.session.toggle_euler(),
            KeyCode::KeyK => {
                let next = self.session.clipper().next();
                self.session.set_clipper(next);
                self.note = Some((format!("clipper: {next}"), Instant::now()));
            }
            KeyCode::Space => self.session.toggle_pause(),
            KeyCode::KeyR => self.session.reset(),
            KeyCode::KeyH | KeyCode::F1 => self.show_help = !self.show_help,
            KeyCode::F12 | KeyCode::KeyP => self.interactive_screenshot(),
            _ => {}
        }
    }

    fn interactive_screenshot(&mut self) {
        let path = loop {
            self.shot_counter += 1;
            let p = PathBuf::from(format!("wireflight-{:04}.png", self.shot_counter));
            if !p.exists() || self.shot_counter >= 9999 {
                break p;
            }
        };
        let note = match write_screenshot(&screenshot_scene(&self.session), &path) {
            Ok(()) => {
                println!("wrote {}", crate::app::shown(&path));
                format!("saved {}", path.display())
            }
            Err(e) => {
                eprintln!("wireflight: screenshot failed: {e:#}");
                format!("screenshot failed: {e:#}")
            }
        };
        self.note = Some((note, Instant::now()));
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let now = Instant::now();
        self.tick(now);
        let Some(size) = self.gfx.as_ref().map(|g| g.renderer.size()) else {
            return Ok(());
        };
        self.build_scene(now, size);
        let Some(output) = self.run_hud(size) else {
            return Ok(());
        };
        self.present(output)?;
        self.finish_counted_run(event_loop, size)
    }

    /// Build the frame's scene at the window's size, timed and counted by the meter.
    fn build_scene(&mut self, now: Instant, (width, height): (u32, u32)) {
        let build_start = Instant::now();
        let clip = self.session.build(Viewport { width, height });
        let build = build_start.elapsed();
        let segments = self.session.scene().segment_count();
        self.meter.record(now, build, clip, segments);
    }

    /// Advance the flight by the time since the last frame (a fixed step when scripted or
    /// counted), and pick up finished background work.
    fn tick(&mut self, now: Instant) {
        let dt = match self.options.fixed_dt {
            Some(dt) => dt,
            None => self
                .last_tick
                .map(|t| (now - t).as_secs_f64().min(0.1))
                .unwrap_or(0.0),
        };
        self.last_tick = Some(now);
        let held = self.held();
        self.session.advance(dt, &held);
        self.session.poll();
    }

    /// One egui pass over the HUD and the panels shown, and what the user did in them
    /// applied; egui's output, to be drawn.
    fn run_hud(&mut self, size: (u32, u32)) -> Option<egui::FullOutput> {
        let gfx = self.gfx.as_mut()?;
        let raw_input = gfx.egui.take_egui_input(&gfx.window);
        let hud = HudData {
            session: &self.session,
            meter: &self.meter,
            size,
            scale: gfx.window.scale_factor(),
            adapter: &self.adapter,
            note: self
                .note
                .as_ref()
                .filter(|(_, t)| t.elapsed() < Duration::from_secs(NOTE_SECONDS))
                .map(|(n, _)| n.as_str()),
            frames: self.options.frames,
        };
        let mut show_help = self.show_help;
        let mut actions = CompareActions::default();
        let mut euler = EulerChanges::default();
        let output = self.egui_ctx.run_pass(raw_input, |ctx| {
            draw_hud(ctx, &hud);
            if let Some(c) = hud.session.compare() {
                actions = draw_compare(ctx, c, hud.session.readout());
            }
            if hud.session.euler.shown {
                euler = draw_euler(ctx, &hud.session.euler);
            }
            if show_help {
                draw_help(ctx, &mut show_help);
            }
        });
        self.show_help = show_help;
        apply_panels(&mut self.session, &gfx.window, actions, euler);
        Some(output)
    }

    /// Draw the scene with egui's output over it, and say when the next frame is wanted.
    fn present(&mut self, output: egui::FullOutput) -> anyhow::Result<()> {
        let Some(gfx) = self.gfx.as_mut() else {
            return Ok(());
        };
        gfx.egui
            .handle_platform_output(&gfx.window, output.platform_output);
        let jobs = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let mut textures = output.textures_delta;
        gfx.window.pre_present_notify();
        let drawn = gfx.renderer.draw(
            self.session.scene(),
            &mut HudFrame {
                paint_jobs: &jobs,
                textures: &mut textures,
                pixels_per_point: output.pixels_per_point,
            },
        );
        textures.clear(); // drained by `draw`; on an error, dropped unapplied
        let presented = drawn?;
        if presented == Presented::Skipped && self.options.frames.is_none() {
            gfx.window.request_redraw();
        }
        let egui_wants = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map(|v| v.repaint_delay);
        self.wait_until = match egui_wants {
            Some(d) if d.is_zero() => {
                gfx.window.request_redraw();
                None
            }
            Some(d) if d < Duration::from_secs(10) => Some(Instant::now() + d),
            _ => None,
        };
        if let Some((_, t)) = &self.note {
            let expiry = *t + Duration::from_secs(NOTE_SECONDS);
            if expiry > Instant::now() {
                self.wait_until = Some(self.wait_until.map_or(expiry, |w| w.min(expiry)));
            }
        }
        Ok(())
    }

    /// A counted run (`--frames N`) ends after its last frame, with the screenshot asked for.
    fn finish_counted_run(
        &mut self,
        event_loop: &ActiveEventLoop,
        (width, height): (u32, u32),
    ) -> anyhow::Result<()> {
        let Some(n) = self.options.frames else {
            return Ok(());
        };
        if self.meter.frames < n {
            return Ok(());
        }
        if let Some(path) = self.options.screenshot.clone() {
            write_screenshot(&screenshot_scene(&self.session), &path)?;
            println!(
                "wrote {} ({}x{}, {})",
                path.display(),
                width,
                height,
                Rasterizer::Cpu.describe()
            );
        }
        event_loop.exit();
        Ok(())
    }

    /// The closing summary on stdout.
    fn report(&self) {
        let m = &self.meter;
        if m.frames == 0 {
            return;
        }
        let wall = if m.active_intervals > 0 {
            m.active_time / m.active_intervals as f64
        } else {
            0.0
        };
        let n = m.frames as f64;
        let mean = |v: u64| v as f64 / n;
        let (w, h) = self
            .gfx
            .as_ref()
            .map(|g| g.renderer.size())
            .unwrap_or((0, 0));
        println!(
            "view: {} frames at {}x{} px on {}: {:.1} FPS ({:.2} ms/frame), scene build {:.2} ms/frame",
            m.frames,
            w,
            h,
            self.adapter,
            if wall > 0.0 { 1.0 / wall } else { 0.0 },
            wall * 1e3,
            1e3 * m.build_total / n
        );
        println!(
            "clip per frame (mean): edges in {:.0}, trivially accepted {:.0}, trivially rejected {:.0}, clipped {:.0}, removed {:.0}; segments drawn {:.0}",
            mean(m.total.edges_in),
            mean(m.total.trivially_accepted),
            mean(m.total.trivially_rejected),
            mean(m.total.clipped),
            mean(m.total.clipped_away),
            mean(m.segments_total)
        );
        println!("clip, last frame: {}", m.clip);
        if let Some(c) = self.session.compare() {
            println!("{}", compare_summary(c));
        }
    }
}

/// What the user did in the panels this frame: effects ticked, discover started, the Euler
/// panel's convention, angles and whether they drive the attitude.
fn apply_panels(
    session: &mut Session,
    window: &Window,
    actions: CompareActions,
    euler: EulerChanges,
) {
    if let Some(c) = session.compare_mut::<Compare>() {
        for (i, on) in actions.toggles {
            c.set(i, on);
        }
        if actions.discover {
            c.start_discover();
        }
    }
    if euler.any() {
        // The scene was built before the panel ran: show the change in the next frame.
        window.request_redraw();
    }
    if let Some(c) = euler.convention {
        session.set_euler_convention(c);
    }
    if let Some(d) = euler.degrees {
        session.set_euler_degrees(d);
    }
    if let Some(drive) = euler.drive {
        session.set_euler_drive(drive);
    }
}

/// Draw `scene` with the CPU rasterizer and write it as a PNG, atomically.
///
/// # Errors
/// Encoding or write errors, naming the file.
pub fn write_screenshot(scene: &LineScene, path: &Path) -> anyhow::Result<()> {
    crate::draw::output::write_still(path, scene, &mut Rasterizer::Cpu)?;
    Ok(())
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(gfx) => self.gfx = Some(gfx),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let response = gfx.egui.on_window_event(&gfx.window, &event);
        // egui answers "repaint" to RedrawRequested itself: only input events count here, or
        // a paused window would redraw forever.
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            gfx.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gfx.renderer.resize(size.width, size.height);
                gfx.window.request_redraw();
            }
            WindowEvent::ScaleFactorChanged { .. } | WindowEvent::Occluded(false) => {
                gfx.window.request_redraw()
            }
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.dragging = false;
            }
            WindowEvent::KeyboardInput { event, .. } if !response.consumed => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    let pressed = event.state == ElementState::Pressed;
                    self.key(event_loop, code, pressed, event.repeat);
                    if let Some(g) = &self.gfx {
                        g.window.request_redraw();
                    }
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.dragging = state == ElementState::Pressed && !response.consumed;
            }
            WindowEvent::CursorMoved { position, .. } => {
                if self.dragging {
                    if let Some(prev) = self.drag {
                        let scale = gfx.window.scale_factor().max(0.1);
                        self.session
                            .rig
                            .drag((position.x - prev.x) / scale, (position.y - prev.y) / scale);
                        gfx.window.request_redraw();
                    }
                }
                self.drag = Some(position);
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                let radius = self.session.target().radius;
                self.session.rig.wheel(steps, radius);
                gfx.window.request_redraw();
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = &self.gfx else {
            return;
        };
        if self.animating() {
            gfx.window.request_redraw();
            event_loop.set_control_flow(ControlFlow::Wait);
        } else {
            if self.waiting_for_work() {
                // Look for finished background work every few milliseconds.
                let soon = Instant::now() + Duration::from_millis(20);
                self.wait_until = Some(self.wait_until.map_or(soon, |w| w.min(soon)));
            }
            // Paused and idle: sleep until an event (or egui / a note needs a repaint).
            self.last_tick = None;
            match self.wait_until {
                Some(t) if t > Instant::now() => {
                    event_loop.set_control_flow(ControlFlow::WaitUntil(t))
                }
                Some(_) => {
                    self.wait_until = None;
                    gfx.window.request_redraw();
                    event_loop.set_control_flow(ControlFlow::Wait);
                }
                None => event_loop.set_control_flow(ControlFlow::Wait),
            }
        }
    }
}
