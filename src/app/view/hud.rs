//! The window's head-up display (egui): attitude, speed, clipper counts and frame timing;
//! the help overlay; and, in `--compare` mode, the comparison panel with its effect
//! checkboxes, the error-over-time plot and the discover button (its terms become rows); the
//! Euler-angle panel (a convention, sliders for its
//! three angles). Also the frame [`Meter`] the HUD and the closing report read.

use std::time::{Duration, Instant};

use super::compare::{Compare, EffectRow, Fit};
use super::gimbal::EulerPanel;
use super::session::{self, Session};
use super::KEY_HELP;
use crate::geometry::clip::ClipStats;
use crate::geometry::euler::{Convention, Frame, Gimbal, Sequence};

/// Frame timing and clipper counts for the HUD and the closing report.
#[derive(Default)]
pub(super) struct Meter {
    pub(super) frames: u64,
    pub(super) last: Option<Instant>,
    /// Smoothed frame interval, s.
    pub(super) interval: f64,
    /// Smoothed scene build time (transform + clip + project), s.
    pub(super) build: f64,
    pub(super) clip: ClipStats,
    pub(super) total: ClipStats,
    pub(super) segments: usize,
    pub(super) segments_total: u64,
    pub(super) build_total: f64,
    /// Sum and count of frame intervals while animating (gaps over 0.25 s, i.e. pauses,
    /// are left out).
    pub(super) active_time: f64,
    pub(super) active_intervals: u64,
}

impl Meter {
    pub(super) fn record(
        &mut self,
        now: Instant,
        build: Duration,
        clip: ClipStats,
        segments: usize,
    ) {
        if let Some(last) = self.last {
            let dt = (now - last).as_secs_f64();
            if dt < 0.25 {
                self.active_time += dt;
                self.active_intervals += 1;
            }
            self.interval = if self.interval > 0.0 {
                0.9 * self.interval + 0.1 * dt
            } else {
                dt
            };
        }
        self.last = Some(now);
        let b = build.as_secs_f64();
        self.build = if self.frames == 0 {
            b
        } else {
            0.9 * self.build + 0.1 * b
        };
        self.frames += 1;
        self.clip = clip;
        self.total.merge(&clip);
        self.segments = segments;
        self.segments_total += segments as u64;
        self.build_total += b;
    }

    pub(super) fn fps(&self) -> f64 {
        if self.interval > 0.0 {
            1.0 / self.interval
        } else {
            0.0
        }
    }
}

/// What the HUD reads.
pub(super) struct HudData<'a> {
    pub(super) session: &'a Session,
    pub(super) meter: &'a Meter,
    pub(super) size: (u32, u32),
    pub(super) scale: f64,
    pub(super) adapter: &'a str,
    pub(super) note: Option<&'a str>,
    pub(super) frames: Option<u64>,
}

fn thousands(v: u64) -> String {
    let s = v.to_string();
    let mut out = String::with_capacity(s.len() + s.len() / 3);
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

pub(super) fn draw_hud(ctx: &egui::Context, hud: &HudData<'_>) {
    use egui::Color32;
    let r = hud.session.readout();
    let frame = egui::Frame::NONE
        .fill(Color32::from_black_alpha(170))
        .inner_margin(8.0)
        .corner_radius(4.0);
    egui::Area::new(egui::Id::unique("wireflight-hud"))
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .interactable(false)
        .show(ctx, |ui| {
            frame.show(ui, |ui| {
                ui.style_mut().override_text_style = Some(egui::TextStyle::Monospace);
                ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
                ui.visuals_mut().override_text_color = Some(Color32::from_rgb(200, 230, 210));
                attitude_lines(ui, hud, &r);
                motion_lines(ui, &r);
                meter_lines(ui, hud);
            });
        });
}

/// The camera and what the aircraft is doing, its attitude, and a warning at or near gimbal
/// lock.
fn attitude_lines(ui: &mut egui::Ui, hud: &HudData<'_>, r: &session::Readout) {
    use egui::{Color32, RichText};
    // `+ 0.0` shows −0.0 as 0.00.
    let [yaw, pitch, roll] = crate::draw::scene::attitude::aerospace_degrees(r.angles);
    let mode = hud.session.rig.mode;
    let state = match (r.replay, hud.session.paused) {
        (Some(_), true) => "replay paused",
        (Some(_), false) => "replay playing",
        (None, true) => "PAUSED",
        (None, false) if hud.session.scripted() => "scripted",
        (None, false) => "flying",
    };
    ui.label(format!("camera {mode}  ·  {state}  ·  H: help"));
    ui.label(format!(
        "yaw {yaw:8.2}°  pitch {pitch:7.2}°  roll {roll:8.2}°  (+ nose right, nose up, right wing down)"
    ));
    match r.gimbal {
        Gimbal::LockedNoseUp | Gimbal::LockedNoseDown => {
            ui.label(
                RichText::new(
                    "GIMBAL LOCK (pitch ±90°): yaw and roll share one axis; shown as yaw, roll 0",
                )
                .color(Color32::from_rgb(255, 80, 80))
                .strong(),
            );
        }
        Gimbal::Free if r.cos_pitch < 1f64.to_radians().sin() => {
            ui.label(
                RichText::new("near gimbal lock (|θ| > 89°): yaw and roll are ill-conditioned")
                    .color(Color32::from_rgb(255, 200, 60)),
            );
        }
        Gimbal::Free => {}
    }
}

/// Speed, altitude and throttle; the replay's time or the flight's.
fn motion_lines(ui: &mut egui::Ui, r: &session::Readout) {
    let mut line = format!(
        "speed {:6.1} m/s ({:5.1} kt)  altitude {:7.1} m",
        r.speed,
        r.speed * 1.943_844,
        r.altitude
    );
    if let Some(t) = r.throttle {
        line += &format!("  throttle {:3.0}%", 100.0 * t);
    }
    ui.label(line);
    if let Some((t, t0, t1)) = r.replay {
        ui.label(format!("replay t {:7.2} s of {:.2}..{:.2} s", t, t0, t1));
    } else {
        ui.label(format!("flight time {:7.2} s", r.time));
    }
}

/// Frame timing, the clipper and its counts, the segments drawn, the frame count of a
/// counted run and the passing note.
fn meter_lines(ui: &mut egui::Ui, hud: &HudData<'_>) {
    use egui::{Color32, RichText};
    let m = hud.meter;
    ui.label(format!(
        "{:5.1} FPS  frame {:6.2} ms  scene {:5.2} ms  {}x{} px @{:.2}x",
        m.fps(),
        m.interval * 1e3,
        m.build * 1e3,
        hud.size.0,
        hud.size.1,
        hud.scale
    ));
    let c = &m.clip;
    ui.label(format!(
        "clipper {} (K)  ·  {:.0} ns/edge incl. transform and projection",
        hud.session.clipper(),
        m.build * 1e9 / c.edges_in.max(1) as f64
    ));
    ui.label(format!(
        "clip: edges in {}  accepted {}  rejected {}  clipped {}  removed {}  culled {}",
        thousands(c.edges_in),
        thousands(c.trivially_accepted),
        thousands(c.trivially_rejected),
        thousands(c.clipped),
        thousands(c.clipped_away),
        thousands(c.bounds_rejected)
    ));
    ui.label(format!(
        "segments drawn {}  ·  {}",
        thousands(m.segments as u64),
        hud.adapter
    ));
    if let Some(n) = hud.frames {
        ui.label(format!("frame {} of {n}", m.frames));
    }
    if let Some(note) = hud.note {
        ui.label(RichText::new(note).color(Color32::from_rgb(255, 220, 120)));
    }
}

pub(super) fn draw_help(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("Keys")
        .open(open)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .show(ctx, |ui| {
            egui::Grid::new("keys").striped(true).show(ui, |ui| {
                for (key, what) in KEY_HELP {
                    ui.monospace(*key);
                    ui.label(*what);
                    ui.end_row();
                }
            });
        });
}

fn fmt_channel(v: Option<f64>, unit: &str) -> String {
    v.map_or_else(|| "—".into(), |x| format!("{x:.3} {unit}"))
}

/// "base model → with effects" errors in one line, for stdout.
pub(super) fn compare_summary(c: &Compare) -> String {
    let label = |effects: &[String]| {
        if effects.is_empty() {
            "base model".to_string()
        } else {
            format!("+ {}", effects.join(" + "))
        }
    };
    let (b, n) = (&c.before, &c.now);
    format!(
        "compare: {} total {:.3} (position {}, velocity {}, attitude {}) → {} total {:.3} \
         (position {}, velocity {}, attitude {}); model run {:.1} ms; {}",
        label(&b.effects),
        b.total,
        fmt_channel(Some(b.channels.position_m), "m"),
        fmt_channel(b.channels.velocity_mps, "m/s"),
        fmt_channel(b.channels.attitude_deg, "°"),
        label(&n.effects),
        n.total,
        fmt_channel(Some(n.channels.position_m), "m"),
        fmt_channel(n.channels.velocity_mps, "m/s"),
        fmt_channel(n.channels.attitude_deg, "°"),
        1e3 * n.compute_s,
        c.verdict_line()
    )
}

/// A small square of `color` in the text line (the legend).
fn swatch(ui: &mut egui::Ui, color: egui::Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 1.0, color);
}

fn rgba(c: crate::draw::render::Rgba) -> egui::Color32 {
    egui::Color32::from_rgba_unmultiplied(c[0], c[1], c[2], c[3])
}

/// What the user did in the `--compare` panel this frame.
#[derive(Debug, Default, PartialEq)]
pub(super) struct CompareActions {
    /// The rows whose checkbox was clicked, with their new state.
    pub(super) toggles: Vec<(usize, bool)>,
    /// The discover button was pressed.
    pub(super) discover: bool,
}

/// The `--compare` panel: errors before / now, the error over time with a cursor at the replay
/// time, the discover button and its state, a checkbox per effect (a discovered term's with
/// discover's reading and estimate).
pub(super) fn draw_compare(
    ctx: &egui::Context,
    c: &Compare,
    r: session::Readout,
) -> CompareActions {
    use egui::{Color32, RichText};
    let mut actions = CompareActions::default();
    let frame = egui::Frame::NONE
        .fill(Color32::from_black_alpha(190))
        .inner_margin(8.0)
        .corner_radius(4.0);
    egui::Window::new("compare")
        .id(egui::Id::unique("wireflight-compare"))
        .frame(frame)
        .anchor(egui::Align2::LEFT_BOTTOM, [8.0, -8.0])
        .resizable(false)
        .collapsible(true)
        .title_bar(true)
        .show(ctx, |ui| {
            ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
            ui.visuals_mut().override_text_color = Some(Color32::from_rgb(200, 230, 210));
            legend_and_verdict(ui, c);
            errors_grid(ui, c);
            let n = &c.now;
            let status = if c.recomputing() {
                "model: recomputing…".to_string()
            } else {
                format!(
                    "model run {:.1} ms (toggle → shown {:.1} ms)",
                    1e3 * n.compute_s,
                    1e3 * n.latency_s
                )
            };
            ui.monospace(status);
            if let Some(e) = &c.error {
                ui.label(RichText::new(e).color(Color32::from_rgb(255, 80, 80)));
            }
            error_plot(ui, c, r.replay.map(|(t, _, _)| t));
            ui.separator();
            actions.discover = discover_row(ui, c);
            actions.toggles = effects_grid(ui, c);
        });
    actions
}

/// The colours of the measured and the model aircraft, and the verdict (highlighted while
/// the fit runs).
fn legend_and_verdict(ui: &mut egui::Ui, c: &Compare) {
    use egui::{Color32, RichText};
    let fitting = matches!(c.fit, Fit::Running(_));
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 0.0;
        ui.monospace("measured ");
        swatch(ui, rgba(crate::draw::scene::palette::AIRCRAFT));
        ui.monospace("   model ");
        swatch(ui, rgba(crate::draw::scene::palette::MODEL_AIRCRAFT));
        ui.monospace("   ");
        let verdict = RichText::new(c.verdict_line()).monospace();
        ui.label(if fitting {
            verdict.color(Color32::from_rgb(255, 220, 120))
        } else {
            verdict.strong()
        });
    });
}

/// The errors before and now, per channel, in total and in noise units.
fn errors_grid(ui: &mut egui::Ui, c: &Compare) {
    let (b, n) = (&c.before, &c.now);
    egui::Grid::new("wireflight-compare-errors")
        .num_columns(3)
        .spacing([16.0, 2.0])
        .show(ui, |ui| {
            ui.monospace("error (RMS)");
            ui.monospace("before");
            ui.monospace("now");
            ui.end_row();
            let row = |ui: &mut egui::Ui, name: &str, x: String, y: String| {
                ui.monospace(name);
                ui.monospace(x);
                ui.monospace(y);
                ui.end_row();
            };
            row(
                ui,
                "total",
                format!("{:.3}", b.total),
                format!("{:.3}", n.total),
            );
            row(
                ui,
                "position",
                fmt_channel(Some(b.channels.position_m), "m"),
                fmt_channel(Some(n.channels.position_m), "m"),
            );
            row(
                ui,
                "velocity",
                fmt_channel(b.channels.velocity_mps, "m/s"),
                fmt_channel(n.channels.velocity_mps, "m/s"),
            );
            row(
                ui,
                "attitude",
                fmt_channel(b.channels.attitude_deg, "°"),
                fmt_channel(n.channels.attitude_deg, "°"),
            );
            row(
                ui,
                "× noise",
                format!("{:.2}", b.noise_units),
                format!("{:.2}", n.noise_units),
            );
        });
}

/// The discover button and discover's state; whether the button was pressed.
fn discover_row(ui: &mut egui::Ui, c: &Compare) -> bool {
    let mut pressed = false;
    ui.horizontal(|ui| {
        let button = ui
            .add_enabled(!c.discovering(), egui::Button::new("discover"))
            .on_hover_text(
                "the force and moment the model as ticked lacks on this flight, as \
                 terms: each becomes a row, fitted",
            );
        if button.clicked() {
            pressed = true;
            button.surrender_focus();
        }
        ui.monospace(c.discovery.line());
    });
    pressed
}

/// A row per effect: its checkbox, its parameters (a discovered term's with discover's
/// reading) and its fit error; the rows whose checkbox was clicked, with their new state.
fn effects_grid(ui: &mut egui::Ui, c: &Compare) -> Vec<(usize, bool)> {
    let mut toggles = Vec::new();
    egui::Grid::new("wireflight-compare-effects")
        .num_columns(3)
        .spacing([10.0, 1.0])
        .show(ui, |ui| {
            ui.monospace("effect");
            ui.monospace(if c.rows.iter().any(|r| r.fitted.is_some()) {
                "parameters (fitted)"
            } else {
                "parameters (defaults)"
            });
            ui.monospace("fit error");
            ui.end_row();
            for (i, row) in c.rows.iter().enumerate() {
                if let Some(on) = effect_row(ui, row) {
                    toggles.push((i, on));
                }
            }
        });
    toggles
}

/// One effect's row; its checkbox's new state where it was clicked.
fn effect_row(ui: &mut egui::Ui, row: &EffectRow) -> Option<bool> {
    let mut on = row.on;
    let response = ui.add_enabled(!row.in_base, egui::Checkbox::new(&mut on, row.name));
    let toggled = response.changed().then_some(on);
    if toggled.is_some() {
        // Space and the arrows belong to the replay, not to the checkbox.
        response.surrender_focus();
    }
    let params = row.params();
    let units: Vec<String> = params
        .iter()
        .map(|p| format!("{} = {} {}", p.name, p.value, p.unit))
        .collect();
    let params: Vec<String> = params
        .iter()
        .map(|p| format!("{}={:.3}", p.name, p.value))
        .collect();
    let mut text = params.join("\n");
    if row.in_base {
        text = format!("in the base model\n{text}");
    }
    if let Some(d) = &row.discovered {
        text = format!("{text}\n{}", d.note());
    }
    let label = ui.monospace(text);
    if !units.is_empty() {
        label.on_hover_text(units.join("\n"));
    }
    ui.monospace(
        row.fitted_error
            .filter(|_| !row.in_base)
            .map_or_else(String::new, |e| format!("{e:.3}")),
    );
    ui.end_row();
    toggled
}

/// The position error over the flight: the base model in grey, the model as ticked in the
/// model's colour, one scale (the larger peak), a cursor at the replay time.
fn error_plot(ui: &mut egui::Ui, c: &Compare, t: Option<f64>) {
    use egui::{pos2, Color32, Stroke};
    let size = egui::vec2(400.0, 84.0);
    let (response, painter) = ui.allocate_painter(size, egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_black_alpha(120));
    let peak = c
        .before
        .error_bins
        .iter()
        .chain(&c.now.error_bins)
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max)
        .max(1e-6);
    let plot = rect.shrink2(egui::vec2(4.0, 14.0));
    let line = |bins: &[f32], color: Color32| {
        let n = bins.len().max(2) as f32 - 1.0;
        let points: Vec<egui::Pos2> = bins
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(|(i, v)| {
                pos2(
                    plot.left() + i as f32 / n * plot.width(),
                    plot.bottom() - (v / peak).clamp(0.0, 1.0) * plot.height(),
                )
            })
            .collect();
        painter.add(egui::Shape::line(points, Stroke::new(1.5, color)));
    };
    line(&c.before.error_bins, Color32::from_gray(150));
    line(
        &c.now.error_bins,
        rgba(crate::draw::scene::palette::MODEL_AIRCRAFT),
    );
    let track = &c.now.track;
    if let (Some(t), Some(&t0), Some(&t1)) = (t, track.time.first(), track.time.last()) {
        let f = ((t - t0) / (t1 - t0).max(1e-9)).clamp(0.0, 1.0) as f32;
        let x = plot.left() + f * plot.width();
        painter.line_segment(
            [pos2(x, rect.top() + 2.0), pos2(x, rect.bottom() - 2.0)],
            Stroke::new(1.0, Color32::from_rgb(255, 220, 120)),
        );
    }
    let font = egui::FontId::monospace(11.0);
    painter.text(
        rect.left_top() + egui::vec2(4.0, 1.0),
        egui::Align2::LEFT_TOP,
        format!(
            "position error, m (peak {peak:.1}; restarts every {:.0} s)",
            c.window_s()
        ),
        font.clone(),
        Color32::from_gray(200),
    );
    painter.text(
        rect.right_bottom() - egui::vec2(4.0, 1.0),
        egui::Align2::RIGHT_BOTTOM,
        "grey: base model   time →",
        font,
        Color32::from_gray(160),
    );
}

/// What the user changed in the Euler-angle panel this frame.
#[derive(Debug, Default)]
pub(super) struct EulerChanges {
    pub(super) convention: Option<Convention>,
    pub(super) degrees: Option<[f64; 3]>,
    pub(super) drive: Option<bool>,
}

impl EulerChanges {
    pub(super) fn any(&self) -> bool {
        self.convention.is_some() || self.degrees.is_some() || self.drive.is_some()
    }
}

/// The Euler-angle panel: the sequence and frame, the three angles as sliders coloured like
/// their gimbal rings, whether they drive the attitude, and the gimbal-lock state.
pub(super) fn draw_euler(ctx: &egui::Context, panel: &EulerPanel) -> EulerChanges {
    use egui::{Color32, RichText};
    let mut changes = EulerChanges::default();
    let convention = panel.convention();
    let frame = egui::Frame::NONE
        .fill(Color32::from_black_alpha(190))
        .inner_margin(8.0)
        .corner_radius(4.0);
    egui::Window::new("Euler angles (G)")
        .id(egui::Id::unique("wireflight-euler"))
        .frame(frame)
        .anchor(egui::Align2::RIGHT_BOTTOM, [-8.0, -8.0])
        .resizable(false)
        .collapsible(true)
        .show(ctx, |ui| {
            ui.visuals_mut().override_text_color = Some(Color32::from_rgb(200, 230, 210));
            changes.convention = convention_row(ui, convention);
            ui.monospace(rotation_product(convention));
            ui.monospace("aerospace axes: x nose, y right wing, z down (north-east-down world)");
            changes.degrees = angle_sliders(ui, panel);
            let mut drive = panel.drive;
            let label = "the sliders set the attitude (else they show it)";
            if ui.checkbox(&mut drive, label).changed() {
                changes.drive = Some(drive);
            }
            if panel.lock().is_locked() {
                ui.label(
                    RichText::new(
                        "GIMBAL LOCK: the middle ring lies in the outer ring's plane; A and C \
                         turn the aircraft about one axis",
                    )
                    .color(Color32::from_rgb(255, 80, 80))
                    .strong(),
                );
            } else {
                ui.label("rings, outer to inner: the intrinsic reading's first, second, third");
            }
        });
    changes
}

/// The sequence's menu and the extrinsic checkbox; the convention chosen where it changed.
fn convention_row(ui: &mut egui::Ui, convention: Convention) -> Option<Convention> {
    let mut changed = None;
    ui.horizontal(|ui| {
        let mut sequence = convention.sequence;
        egui::ComboBox::from_id_salt("wireflight-euler-sequence")
            .selected_text(format!("{sequence:#}"))
            .show_ui(ui, |ui| {
                for s in Sequence::ALL {
                    let kind = if s.is_tait_bryan() {
                        "Tait–Bryan"
                    } else {
                        "proper Euler"
                    };
                    ui.selectable_value(&mut sequence, s, format!("{s:#}  {kind}"));
                }
            });
        let mut extrinsic = convention.frame == Frame::Extrinsic;
        ui.checkbox(&mut extrinsic, "extrinsic (fixed axes)");
        let frame = if extrinsic {
            Frame::Extrinsic
        } else {
            Frame::Intrinsic
        };
        let chosen = Convention::new(sequence, frame);
        if chosen != convention {
            changed = Some(chosen);
        }
    });
    changed
}

/// The rotation as a product of the elementary ones, and how its axes move.
fn rotation_product(convention: Convention) -> String {
    let [a, b, c] = convention.sequence.axes().map(|x| x.name());
    match convention.frame {
        Frame::Intrinsic => format!("R = R{a}(A)·R{b}(B)·R{c}(C), axes turning with the body"),
        Frame::Extrinsic => format!("R = R{c}(C)·R{b}(B)·R{a}(A), fixed axes, A first"),
    }
}

/// A slider per angle, coloured like its gimbal ring; the three angles where one moved.
fn angle_sliders(ui: &mut egui::Ui, panel: &EulerPanel) -> Option<[f64; 3]> {
    let euler = panel.euler();
    let mut degrees = panel.degrees();
    let mut moved = false;
    for (k, (lo, hi)) in panel.ranges().into_iter().enumerate() {
        ui.horizontal(|ui| {
            swatch(ui, rgba(crate::draw::scene::euler::slot_color(k)));
            ui.monospace(format!(
                "{} {:<3}",
                ["A", "B", "C"][k],
                crate::draw::scene::euler::axis_label(&euler, k)
            ));
            let slider = egui::Slider::new(&mut degrees[k], lo..=hi)
                .suffix("°")
                .fixed_decimals(1);
            if ui.add(slider).changed() {
                moved = true;
            }
        });
    }
    moved.then_some(degrees)
}

/// The scene of a screenshot: the window's line scene with what the HUD and the compare panel
/// say written over it in the stroke font (egui's panels are drawn by the GPU and are not in
/// the line scene the CPU rasterizer draws).
pub(super) fn screenshot_scene(session: &Session) -> crate::draw::render::LineScene {
    use crate::draw::scene::font::draw_label;
    use crate::draw::scene::overlay::text_height;
    use crate::geometry::pipeline::Viewport;
    let mut scene = session.scene().clone();
    let viewport = Viewport {
        width: scene.width,
        height: scene.height,
    };
    let h = text_height(viewport);
    let r = session.readout();
    let aero = crate::draw::scene::attitude::aerospace_degrees(r.angles);
    let state = match (r.replay, session.paused) {
        (Some(_), true) => "replay paused",
        (Some(_), false) => "replay",
        (None, true) => "paused",
        (None, false) => "flying",
    };
    let mut lines = vec![
        format!("camera {}, {state}", session.rig.mode),
        format!(
            "yaw {:.1}°  pitch {:.1}°  roll {:.1}°  (aerospace, +pitch nose up)",
            aero[0], aero[1], aero[2]
        ),
    ];
    let mut speed = format!("speed {:.1} m/s  altitude {:.1} m", r.speed, r.altitude);
    if let Some(t) = r.throttle {
        speed += &format!("  throttle {:.0}%", 100.0 * t);
    }
    lines.push(speed);
    lines.push(match r.replay {
        Some((t, t0, t1)) => format!("t {:.2} s of {:.2}..{:.2} s", t, t0, t1),
        None => format!("flight time {:.2} s", r.time),
    });
    if let Some(c) = session.compare::<Compare>() {
        let label = |effects: &[String]| {
            if effects.is_empty() {
                "base model".to_string()
            } else {
                format!("+ {}", effects.join(" + "))
            }
        };
        for (what, o) in [("before", &c.before), ("now", &c.now)] {
            lines.push(format!(
                "{what} ({}): total {:.3}, position {:.3} m",
                label(&o.effects),
                o.total,
                o.channels.position_m
            ));
        }
        lines.push(c.verdict_line().replace('…', "..."));
        if !matches!(c.discovery, super::discovery::Discovering::Off) {
            lines.push(c.discovery.line().replace('…', "..."));
        }
    }
    let mut segments = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        let y = h + k as f32 * 1.6 * h;
        draw_label(line, glam::Vec2::new(h, y), h, &mut segments);
    }
    scene.batches.push(crate::draw::render::LineBatch {
        color: crate::draw::scene::palette::TEXT,
        segments,
    });
    scene
}

/// The texts the `--compare` panel of `session` draws, egui run without a window (its shapes,
/// not pixels; the passes a window takes to size itself first): what a test reads of the
/// panel. Empty without a comparison.
pub fn compare_panel_texts(session: &Session) -> Vec<String> {
    fn walk(shape: &egui::Shape, out: &mut Vec<String>) {
        match shape {
            egui::Shape::Text(t) => out.push(t.galley.text().to_string()),
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            _ => {}
        }
    }
    let Some(c) = session.compare() else {
        return Vec::new();
    };
    let ctx = egui::Context::default();
    let mut texts = Vec::new();
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1600.0, 1400.0),
            )),
            ..Default::default()
        };
        let mut out = ctx.run_pass(input, |ctx| {
            draw_compare(ctx, c, session.readout());
        });
        // No renderer takes the font atlas.
        out.textures_delta.clear();
        texts.clear();
        for s in &out.shapes {
            walk(&s.shape, &mut texts);
        }
    }
    texts
}
