//! Command-line syntax (clap derive) and the parsers that validate raw values.

mod analysis;
mod clip;
mod data;
mod effects;
mod euler;

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::analysis::compare::CompareConfig;
use crate::data::VehicleKind;
use crate::flight::spec::{EffectSpec, ModelChoice};
use crate::geometry::clip::Clipper;
use crate::geometry::euler::Convention;

pub use analysis::*;
pub use clip::*;
pub use data::*;
pub use effects::*;
pub use euler::*;

mod values;
pub use values::*;

/// The heading of the options every command takes.
const GLOBAL: &str = "Global options (every command)";

/// wireflight: a wireframe flight viewer with a CPU homogeneous clipper.
#[derive(Debug, Parser)]
#[command(name = "wireflight", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Largest input file read (flight data, meshes and their buffers, model, parameter and
    /// script files), MiB.
    #[arg(long, global = true, help_heading = GLOBAL, value_name = "MIB", default_value_t = crate::fsio::DEFAULT_MAX_INPUT_MB,
          value_parser = clap::value_parser!(u64).range(1..=1 << 24))]
    pub max_input_mb: u64,
    /// Largest configuration file read (model, parameter set, column map, sensor-error
    /// spec), MiB.
    #[arg(long, global = true, help_heading = GLOBAL, value_name = "MIB", default_value_t = crate::fsio::DEFAULT_MAX_CONFIG_MB,
          value_parser = clap::value_parser!(u64).range(1..=1 << 20))]
    pub max_config_mb: u64,
    /// Let a glTF file read buffers outside its own directory (absolute paths, `file://`
    /// URIs, `..`); by default they are refused.
    #[arg(long, global = true, help_heading = GLOBAL)]
    pub allow_external_uris: bool,
    /// No progress bars and no report of what a log held (errors and results still print).
    /// Progress is drawn only when stderr is a terminal, and never with --json.
    #[arg(long, short = 'q', global = true, help_heading = GLOBAL)]
    pub quiet: bool,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render one oriented aircraft as a wireframe into a PNG or SVG file.
    Render(RenderArgs),
    /// Generate a flight (CSV) with the flight model, optionally with hidden effects and noise.
    Simulate(SimulateArgs),
    /// Compare a model with measured flight data: errors per channel, where it fails.
    Compare(CompareArgs),
    /// Find which physical effect the model is missing, with evidence.
    Diagnose(DiagnoseArgs),
    /// Find the force or moment the model lacks, as terms to add (`--add 'term:AXIS=EXPR'`).
    Discover(DiscoverArgs),
    /// Fit many numbers of the aircraft's parameter set together over several flights.
    Identify(IdentifyArgs),
    /// Fly through a wireframe world in a window (winit + wgpu, egui HUD).
    View(ViewArgs),
    /// Euler angles in any of the 24 conventions (pure math, unlike the aerospace angles of
    /// render and view): matrices, quaternions, conversions, and pictures of the rotations,
    /// gimbal lock and interpolation.
    Euler(EulerArgs),
    /// The clipping lab: clip edges from a CSV file with a chosen line clipper, or polygons
    /// against a polygon with Weiler-Atherton.
    Clip(ClipArgs),
    /// Read a PX4 log or any CSV through a column map, say what was found, write flight data.
    Import(ImportArgs),
    /// List every `aircraft:KEY` of a fixed-wing parameter set: unit, range, meaning, value.
    Keys(KeysArgs),
    /// List the catalogue's effects: what each adds, its parameters' units, ranges and
    /// defaults, and command lines that use it.
    Effects(EffectsArgs),
}

/// `wireflight keys` options.
#[derive(Debug, Args)]
#[command(after_help = "\
Examples:
  wireflight keys
  wireflight keys --aircraft assets/aircraft/c172p.toml
  wireflight keys --json
  wireflight simulate --hidden aircraft:c_m_alpha=-3.3 --out a.csv   # a key set in the truth
  wireflight diagnose --flight a.csv --add aircraft:c_m_alpha          # a key fitted")]
pub struct KeysArgs {
    /// Parameter set whose values are listed: `aerosonde` or a .toml file.
    #[arg(long, default_value = "aerosonde", value_name = "NAME|FILE.toml")]
    pub aircraft: String,
    /// Machine-readable output (JSON) on stdout: the set's name and every key with its table,
    /// unit, range, value and meaning.
    #[arg(long)]
    pub json: bool,
}

/// Which model to run against data (shared by compare and diagnose).
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Flight model file (TOML); default: the baseline of the data's `vehicle` (and
    /// `aircraft`).
    #[arg(long, value_name = "FILE")]
    pub model: Option<std::path::PathBuf>,
    /// Vehicle family, for data without `# vehicle:` metadata (or to override it).
    #[arg(long, value_parser = parse_vehicle, conflicts_with = "model")]
    pub vehicle: Option<VehicleKind>,
    /// Parameter set of a fixed wing (`aerosonde` or a .toml file), overriding the data's
    /// `# aircraft:`.
    #[arg(long, value_name = "NAME|FILE.toml", conflicts_with = "model")]
    pub aircraft: Option<String>,
    /// Effects in the model, comma-separated (parameters at their defaults).
    #[arg(long, value_name = "A,B")]
    pub effects: Option<String>,
    /// Add an effect, `name[:k=v,...]`; parameters not given are fitted (repeatable).
    #[arg(long, value_name = "NAME[:K=V,...]")]
    pub add: Vec<String>,
}

impl ModelArgs {
    /// The flight model these options choose (built against the data by the command).
    pub fn choice(&self) -> ModelChoice {
        ModelChoice {
            model_file: self.model.clone(),
            vehicle: self.vehicle,
            aircraft: self.aircraft.clone(),
            effects: self.effects.clone(),
        }
    }

    /// The `--add` effects, parsed.
    ///
    /// # Errors
    /// Unknown effects, malformed `k=v`.
    pub fn add_specs(&self) -> anyhow::Result<Vec<EffectSpec>> {
        self.add.iter().map(|a| Ok(EffectSpec::parse(a)?)).collect()
    }
}

/// How a flight is cut into comparison windows (shared by compare and diagnose).
#[derive(Debug, Args)]
pub struct WindowArgs {
    /// Window length of the multiple-shooting comparison, s [default: 8 for a fixed wing, 60
    /// for a point mass].
    #[arg(long, value_parser = window_length)]
    pub window: Option<f64>,
    /// Start the first window this long after the first sample, s.
    #[arg(long, default_value_t = 0.0, value_parser = non_negative)]
    pub window_offset: f64,
    /// Fit each window's start state over its first S seconds only (for a model with a fast
    /// unstable mode) [default: the whole window].
    #[arg(long, value_name = "S", value_parser = positive)]
    pub start_span: Option<f64>,
}

impl WindowArgs {
    /// Refuse a flight in which `--window-offset` leaves no whole window, naming the option.
    ///
    /// # Errors
    /// The offset and a window run past the flight's end.
    pub fn check_fits(
        &self,
        path: &std::path::Path,
        data: &crate::data::FlightData,
        cfg: &CompareConfig,
    ) -> anyhow::Result<()> {
        let duration = data.duration();
        if self.window_offset > 0.0 && self.window_offset + cfg.window_s > duration {
            anyhow::bail!(
                "{}: --window-offset {} s leaves no {} s window in the flight's {:.2} s (give \
                 an offset of at most {:.2} s)",
                crate::app::shown(path),
                crate::data::format::fmt_number(self.window_offset),
                cfg.window_s,
                duration,
                (duration - cfg.window_s).max(0.0)
            );
        }
        Ok(())
    }

    /// The comparison settings for a vehicle.
    pub fn config(&self, vehicle: VehicleKind) -> CompareConfig {
        CompareConfig {
            window_s: self
                .window
                .unwrap_or(CompareConfig::default_window_s(vehicle)),
            offset_s: self.window_offset,
            start_span_s: self.start_span,
            ..CompareConfig::default()
        }
    }
}

/// A window length: at least 0.1 s (a window must hold a few samples of any real log) and at
/// most a day.
fn window_length(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if (0.1..=86_400.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("window {v} s is outside 0.1..=86400 s"))
    }
}

fn positive(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} must be positive"))
    }
}

const RENDER_EXAMPLES: &str = "\
Examples:
  wireflight render --out plane.png
  wireflight render --yaw -30 --pitch 15 --roll 40 --camera chase --out banked.png
  wireflight render --camera cockpit --size 1280x720 --backend cpu --out cockpit.png
  wireflight render --camera cockpit --roll 30 --world grid --out banked.png  # horizon tilts
  wireflight render --mesh assets/plane.gltf --camera top --out top.svg
  wireflight render --pitch -90 --roll 30 --out gimbal.png    # the angles at gimbal lock
  wireflight render --pan 1,0 --out half.png                   # half out of the frame
  wireflight render --flight test.csv --frames-dir frames --fps 10   # replay a flight
  wireflight render --clip-plane 0,1,0,0 --out left-half.png   # cut-away: keep y >= 0 (body axes)
  wireflight render --mesh docs/examples/cube.obj --hidden-line --out cube.png  # back faces culled
  wireflight render --flight tests/data/px4-sitl-hop.ulg --out hop.gif --size 480x360  # animated

Angles are aerospace yaw, pitch and roll in degrees, as in flight data and the window's HUD:
+yaw turns the nose right, +pitch raises it, +roll lowers the right wing (applied roll first,
then pitch, then yaw). The clipper's counts are printed after drawing.";

/// `wireflight render` options.
#[derive(Debug, Args)]
#[command(after_help = RENDER_EXAMPLES)]
pub struct RenderArgs {
    /// The wireframe: `plane` for the built-in aircraft, or a mesh file (.obj, .gltf, .glb).
    #[arg(long, default_value = "plane", value_name = "plane|FILE")]
    pub mesh: String,
    /// The old spelling of --mesh (a mesh file works, with a note; everywhere else --model is a
    /// flight model, which render has none of).
    #[arg(
        long = "model",
        value_name = "FILE",
        hide = true,
        conflicts_with = "mesh"
    )]
    pub old_model: Option<String>,
    /// Yaw ψ, degrees (aerospace): + turns the nose right.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = angle_deg)]
    pub yaw: f64,
    /// Pitch θ, degrees (aerospace): + raises the nose.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = angle_deg)]
    pub pitch: f64,
    /// Roll φ, degrees (aerospace): + lowers the right wing.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = angle_deg)]
    pub roll: f64,
    /// Where the eye is.
    #[arg(long, value_enum, default_value_t = CameraArg::Chase)]
    pub camera: CameraArg,
    /// Perspective or orthographic projection.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Perspective)]
    pub projection: ProjectionArg,
    /// Pan the camera by RIGHT,UP bounding radii (e.g. `1,0` puts the model half out of the
    /// frame on the left).
    #[arg(long, default_value = "0,0", value_name = "RIGHT,UP", allow_hyphen_values = true, value_parser = parse_pan)]
    pub pan: [f32; 2],
    /// Vertical field of view of the perspective projection, degrees.
    #[arg(long, default_value_t = 50.0, value_parser = fov_deg)]
    pub fov: f64,
    /// Image size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x600", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Which rasterizer draws a PNG: `auto` uses any wgpu adapter (Mesa lavapipe counts) and
    /// falls back to the CPU, saying so on stderr.
    #[arg(long, value_enum, default_value_t = BackendArg::Auto)]
    pub backend: BackendArg,
    /// Output file; the extension picks the format: `.png` raster, `.svg` vector (the exact
    /// clipped segments); with --flight, `.gif`: the replay animated. Written atomically.
    #[arg(long, value_name = "FILE", required_unless_present = "flight")]
    pub out: Option<PathBuf>,
    /// Replay a recorded flight (CSV, PX4 ULog, or CSV with --columns) instead: one PNG per
    /// frame into --frames-dir, or an animated GIF with --out FILE.gif.
    #[arg(long, value_name = "FILE")]
    pub flight: Option<PathBuf>,
    /// How to read the --flight file.
    #[command(flatten)]
    pub data: DataArgs,
    /// Directory for the replay's frames (`frame_00000.png`, ...).
    #[arg(long, value_name = "DIR", requires = "flight", conflicts_with = "out")]
    pub frames_dir: Option<PathBuf>,
    /// Frames per second of flight time for the replay (25, as `compare`'s; a GIF rounds the
    /// frame time to whole hundredths of a second).
    #[arg(long, default_value_t = crate::draw::output::DEFAULT_FPS, value_parser = finite_f64)]
    pub fps: f64,
    /// Most frames the replay writes (a flight with a long time gap would need more).
    #[arg(long, value_name = "N", default_value_t = crate::draw::output::DEFAULT_MAX_FRAMES,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub max_frames: u64,
    /// The line clipper: blinn, cohen-sutherland, liang-barsky, cyrus-beck or
    /// sutherland-hodgman (all draw the same picture).
    #[arg(long, default_value = "blinn", value_name = "NAME")]
    pub clipper: Clipper,
    /// Extra clip plane for a cut-away view, `A,B,C,D` in the model's body axes (nose +X,
    /// left wing +Y, up +Z; metres): keeps the part where A·x + B·y + C·z + D ≥ 0, fixed to
    /// the model at any attitude. Repeatable (at most 8), e.g. `--clip-plane 0,1,0,0` keeps
    /// the left half. Draws the model alone (no --world).
    #[arg(long = "clip-plane", value_name = "A,B,C,D", allow_hyphen_values = true, value_parser = parse_plane)]
    pub clip_plane: Vec<[f32; 4]>,
    /// Hidden-line drawing of a closed mesh with faces (OBJ, glTF): only edges of faces
    /// turned toward the eye are drawn (back-face culling). Draws the model alone (no
    /// --world).
    #[arg(long)]
    pub hidden_line: bool,
    /// What surrounds the model in a still: `none`, `grid` (the ground below and the
    /// horizon, so attitude shows), `full` (the window's world of landmarks).
    #[arg(long, value_enum, default_value_t = WorldArg::Grid)]
    pub world: WorldArg,
}

/// What surrounds the model in a still (see [`crate::draw::scene::still::StillWorld`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WorldArg {
    /// The model alone.
    None,
    /// Ground grid and horizon.
    Grid,
    /// The fly-through world.
    Full,
}

impl ViewArgs {
    /// Whether the window compares a flight model with the recording: --compare, or any of the
    /// options that choose the model.
    pub fn compares(&self) -> bool {
        self.flight.is_some()
            && (self.compare
                || self.model.is_some()
                || self.vehicle.is_some()
                || self.aircraft.is_some()
                || self.effects.is_some()
                || !self.add.is_empty())
    }
}

impl From<WorldArg> for crate::draw::scene::still::StillWorld {
    fn from(w: WorldArg) -> Self {
        match w {
            WorldArg::None => Self::None,
            WorldArg::Grid => Self::Grid,
            WorldArg::Full => Self::Full,
        }
    }
}

/// Parse a plane `A,B,C,D` (four finite numbers, not all of A, B, C zero).
pub fn parse_plane(s: &str) -> Result<[f32; 4], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [a, b, c, d] = parts[..] else {
        return Err(format!("`{s}` is not A,B,C,D (four numbers, e.g. 0,1,0,0)"));
    };
    let mut v = [0f32; 4];
    for (slot, t) in v.iter_mut().zip([a, b, c, d]) {
        let x = finite_f64(t.trim())?;
        if x.abs() > f64::from(f32::MAX) {
            return Err(format!("`{t}` is out of range"));
        }
        *slot = x as f32;
    }
    if v[..3] == [0.0; 3] {
        return Err(format!(
            "`{s}`: A, B and C are all zero, so it is not a plane"
        ));
    }
    Ok(v)
}

/// A `--turbulence` level; an unknown one is refused with the list.
fn parse_turbulence(s: &str) -> Result<crate::flight::turbulence::TurbulenceLevel, String> {
    s.parse()
        .map_err(|e: crate::flight::turbulence::TurbulenceError| e.to_string())
}

const SIMULATE_EXAMPLES: &str = "\
Examples:
  wireflight simulate --manoeuvre flight-test --duration 120 --out test.csv
  wireflight simulate --manoeuvre climbing-turn --hidden wind:north_mps=4,east_mps=-3 \\
      --noise-pos 0.5 --noise-att 0.3 --seed 7 --out windy.csv
  wireflight simulate --manoeuvre flight-test --turbulence moderate --turbulence-seed 3 --out gusty.csv
  wireflight simulate --vehicle point-mass --manoeuvre ballistic --add drag:k=0.0005 --out shot.csv
  wireflight simulate --vehicle point-mass --launch-speed 300 --latitude 0 --hidden earth_rotation \\
      --noise-pos 0.5 --noise-vel 0.1 --out long-shot.csv   # then: diagnose --flight long-shot.csv
  wireflight simulate --model docs/examples/model.toml --manoeuvre figure-eight --duration 140 --out f8.csv

Manoeuvres: level, climbing-turn, doublets, elevator-doublet, aileron-doublet, rudder-doublet,
figure-eight, flight-test (fixed-wing); ballistic (point-mass).";

/// `simulate --help`'s closing text: the examples and manoeuvres, then the catalogue's effects.
fn simulate_help() -> String {
    format!("{SIMULATE_EXAMPLES}\n{}", simulate_effects_help())
}

/// `wireflight simulate` options.
#[derive(Debug, Args)]
#[command(after_help = simulate_help())]
pub struct SimulateArgs {
    /// Vehicle family.
    #[arg(long, default_value = "fixed-wing", value_parser = parse_vehicle)]
    pub vehicle: VehicleKind,
    /// Parameter set of a fixed-wing: `aerosonde` or a .toml file.
    #[arg(long, default_value = "aerosonde")]
    pub aircraft: String,
    /// A model file (TOML) instead of --vehicle/--aircraft (--effects/--add still add to it).
    #[arg(long, value_name = "FILE")]
    pub model: Option<std::path::PathBuf>,
    /// Manoeuvre to fly (default: level, or ballistic for a point mass).
    #[arg(long)]
    pub manoeuvre: Option<String>,
    /// Length of the flight, s.
    #[arg(long, default_value_t = 60.0, value_parser = finite_f64)]
    pub duration: f64,
    /// Effects of the model, comma-separated names (listed in the file's metadata).
    #[arg(long, value_name = "A,B")]
    pub effects: Option<String>,
    /// Add an effect with parameters, `name[:k=v,...]` (repeatable; listed in the metadata).
    #[arg(long, value_name = "NAME[:K=V,...]")]
    pub add: Vec<String>,
    /// Add an effect to the truth only, `name[:k=v,...]` (repeatable; not in the file).
    #[arg(long, value_name = "NAME[:K=V,...]")]
    pub hidden: Vec<String>,
    /// Position noise (standard deviation), m.
    #[arg(long, default_value_t = 0.0, value_parser = noise_sigma)]
    pub noise_pos: f64,
    /// Attitude noise, degrees.
    #[arg(long, default_value_t = 0.0, value_parser = noise_sigma)]
    pub noise_att: f64,
    /// Velocity and airspeed noise, m/s.
    #[arg(long, default_value_t = 0.0, value_parser = noise_sigma)]
    pub noise_vel: f64,
    /// Body-rate noise, degrees/s.
    #[arg(long, default_value_t = 0.0, value_parser = noise_sigma)]
    pub noise_rate: f64,
    /// Record an accelerometer (the specific force, body FRD; fixed wing) with this noise on
    /// each axis, m/s² (0: exact); without it the file has no accelerometer.
    #[arg(long, value_name = "M/S²", value_parser = noise_sigma)]
    pub noise_acc: Option<f64>,
    /// The wandering errors of a real log, on top of the --noise-* white noise: a preset
    /// (`independent`, `ekf-gnss`) or a TOML file; each channel at its own rate (the truth
    /// is written to the file as `# sensor_errors:`; see docs/flight-model.md).
    #[arg(long, value_name = "FILE.toml|PRESET")]
    pub sensor_errors: Option<String>,
    /// Output and autopilot rate, Hz.
    #[arg(long, default_value_t = 50.0, value_parser = finite_f64)]
    pub rate: f64,
    /// Most samples of the flight (duration × rate); bounds the run's memory and time.
    #[arg(long, value_name = "N", default_value_t = crate::flight::simulate::DEFAULT_MAX_SAMPLES,
          value_parser = clap::value_parser!(u64).range(2..))]
    pub max_samples: u64,
    /// Noise seed (output is deterministic for a seed).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Fly through MIL-F-8785C Dryden gusts: light, moderate or severe (fixed wing; the
    /// truth is written to the file as `# turbulence:`; see docs/turbulence.md).
    #[arg(long, value_name = "LEVEL", value_parser = parse_turbulence)]
    pub turbulence: Option<crate::flight::turbulence::TurbulenceLevel>,
    /// Seed of the gusts (independent of --seed).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub turbulence_seed: u64,
    /// Trim airspeed, m/s (fixed-wing).
    #[arg(long, default_value_t = 25.0, value_parser = finite_f64)]
    pub airspeed: f64,
    /// Launch speed of the point-mass `ballistic` shot (60° elevation, due north), m/s.
    #[arg(long, default_value_t = 150.0, value_parser = positive)]
    pub launch_speed: f64,
    /// Starting height above the origin, m.
    #[arg(long, default_value_t = 200.0, value_parser = finite_f64)]
    pub height: f64,
    /// Latitude of the origin, degrees.
    #[arg(long, default_value_t = 45.0, allow_negative_numbers = true, value_parser = finite_f64)]
    pub latitude: f64,
    /// Longitude of the origin, degrees.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite_f64)]
    pub longitude: f64,
    /// Altitude of the origin above sea level, m.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite_f64)]
    pub altitude: f64,
    /// Output CSV file (written atomically).
    #[arg(long, value_name = "FILE.csv")]
    pub out: std::path::PathBuf,
}

const VIEW_HELP: &str = "\
Examples:
  wireflight view
  wireflight view --mesh assets/plane.gltf --camera orbit
  wireflight view --flight test.csv                       # replay a recorded flight
  wireflight view --flight windy.csv --compare            # and the model beside it
  wireflight view --flight windy.csv --add wind           # compare, wind ticked from the start
  wireflight view --flight windy.csv --model docs/examples/model.toml  # compare that model
  wireflight view --script assets/scripts/loop.txt --frames 600 --screenshot loop.png
  xvfb-run -a wireflight view --script assets/scripts/climb-turn.txt --frames 120 --screenshot s.png
  wireflight view --gimbal zyx --gimbal-angles 60,90,0      # the rings at gimbal lock (nose up)

Keys (flying):
  Up / Down        nose down / nose up (stick forward / back), 45°/s
  Left / Right     roll left / right, 90°/s
  Q / E            yaw (rudder) left / right, 20°/s
  + (=) / -        throttle up / down (keypad + and - too), 50%/s
Keys (replay, --flight):
  Space            play / pause
  Left / Right     seek back / forward 5 s
Compare (--flight F --compare, or --flight F with any of --model, --vehicle, --aircraft,
--effects, --add):
  The model is restarted from the data every 8 s (point mass: 60 s) and flown beside the
  recording: the measured aircraft in green, the model's in magenta with its trail (broken
  at restarts).
  A panel plots the position error over time (grey: the base model; magenta: now) with a
  cursor at the replay time, shows the total and per-channel errors before / now, and has
  a checkbox per catalogue effect: ticking one re-runs the model in the background. The
  effects' parameters are fitted once at start-up (`diagnose`, a second or two; until
  then the catalogue defaults, e.g. zero wind, stand in) and shown beside the checkboxes.
Keys (always):
  C                cycle cameras: chase → cockpit → orbit → free
  G                Euler-angle panel: pick any of the 24 conventions; its gimbal rings
                   (three rings nested in sequence order, coloured like the angles) around
                   the aircraft and three sliders, which show the attitude's angles or,
                   once moved, set it
  K                cycle line clippers: blinn → cohen-sutherland → liang-barsky →
                   cyrus-beck → sutherland-hodgman (HUD: counts and time per frame)
  Space            pause / resume
  R                reset (flight, trail and cameras back to the start)
  H or F1          help overlay on / off
  F12 or P         screenshot: the line scene drawn by the CPU rasterizer into
                   wireflight-NNNN.png in the current directory (atomic write)
  Esc              quit (closing the window too)
Mouse and free camera:
  orbit camera     drag with the left button to turn around the aircraft, wheel to zoom
  free camera      W/A/S/D move, PageUp/PageDown up/down, Shift 4× faster,
                   drag to look, wheel changes the speed

Scripts (--script FILE): one line per time, `t_s key=value ...`, e.g.
  0.0  throttle=0.8
  1.0  pitch_rate=10 roll_rate=0
  4.0  roll_rate=-30 camera=orbit      # comments start with '#'
Times are seconds of flight, never decreasing. Keys: throttle (0..1), pitch_rate
(deg/s, + nose up), roll_rate (deg/s, + right), yaw_rate (deg/s, + nose right), camera
(chase|cockpit|orbit|free), pause (1: stop flight time there; Space resumes). A setting
holds until a later line changes it. With a script
the keys do not fly the aircraft. Every frame advances the flight by --dt (fixed step, so
a run is deterministic); --frames N stops after N frames, and --screenshot writes the
last frame's line scene (CPU rasterizer, PNG, atomic) before exiting.";

/// Cameras of the fly-through window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ViewCameraArg {
    /// Behind and above, following the aircraft.
    Chase,
    /// The pilot's eye.
    Cockpit,
    /// Around the aircraft, turned with the mouse.
    Orbit,
    /// Detached, flown with W/A/S/D.
    Free,
}

/// `wireflight view` options.
#[derive(Debug, Args)]
#[command(after_help = VIEW_HELP)]
pub struct ViewArgs {
    /// The wireframe: `plane` for the built-in aircraft, or a mesh file (.obj, .gltf, .glb).
    #[arg(long, default_value = "plane", value_name = "plane|FILE")]
    pub mesh: String,
    /// The camera to start with (C cycles them).
    #[arg(long, value_enum, default_value_t = ViewCameraArg::Chase)]
    pub camera: ViewCameraArg,
    /// Window size in logical pixels, WIDTHxHEIGHT (physical pixels on HiDPI screens are
    /// this times the scale factor).
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Vertical field of view, degrees.
    #[arg(long, default_value_t = 55.0, value_parser = fov_deg)]
    pub fov: f64,
    /// Fly from a script of timed control inputs instead of the keys (format below).
    #[arg(long, value_name = "FILE", conflicts_with = "flight")]
    pub script: Option<PathBuf>,
    /// Replay a recorded flight (CSV, PX4 ULog, or CSV with --columns) with its trail.
    #[arg(long, value_name = "FILE")]
    pub flight: Option<PathBuf>,
    /// How to read the --flight file.
    #[command(flatten)]
    pub data: DataArgs,
    /// Draw this many frames, each advancing the flight by --dt, then exit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub frames: Option<u64>,
    /// With --frames: write the last frame as a PNG (CPU rasterizer, atomic write).
    #[arg(long, value_name = "FILE.png", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Fixed time step per frame, s, for --script and --frames runs (interactive runs use the
    /// wall clock).
    #[arg(long, default_value_t = 1.0 / 60.0, value_parser = time_step)]
    pub dt: f64,
    /// Present without waiting for vertical sync (for measuring frame rates).
    #[arg(long)]
    pub no_vsync: bool,
    /// With --flight: fly the flight model beside the recording (magenta), plot the error
    /// over time, and tick catalogue effects on and off to see the error fall.
    #[arg(long, requires = "flight")]
    pub compare: bool,
    /// With --flight: the flight model (TOML) flown beside the recording (implies --compare);
    /// default: the baseline of the data's vehicle. The flight without --flight is flown by
    /// the keys, not by a flight model. (`--flight-model` is an old spelling; the wireframe
    /// is --mesh.)
    #[arg(long, alias = "flight-model", value_name = "FILE", requires = "flight")]
    pub model: Option<PathBuf>,
    /// With --flight: the vehicle family of the model, for data without `# vehicle:` (e.g. a
    /// PX4 log); implies --compare.
    #[arg(long, value_parser = parse_vehicle, requires = "flight", conflicts_with = "model")]
    pub vehicle: Option<VehicleKind>,
    /// With --flight: the model's parameter set of a fixed wing (`aerosonde` or a .toml
    /// file); implies --compare.
    #[arg(
        long,
        value_name = "NAME|FILE.toml",
        requires = "flight",
        conflicts_with = "model"
    )]
    pub aircraft: Option<String>,
    /// With --flight: effects in the model, comma-separated (parameters at their defaults;
    /// always on); implies --compare.
    #[arg(long, value_name = "A,B", requires = "flight")]
    pub effects: Option<String>,
    /// With --flight: start the comparison with this effect ticked, `name[:k=v,...]`
    /// (repeatable; the parameters not given come from the fit); implies --compare.
    #[arg(long, value_name = "NAME[:K=V,...]", requires = "flight")]
    pub add: Vec<String>,
    /// The line clipper to start with (a key cycles them).
    #[arg(long, default_value = "blinn", value_name = "NAME")]
    pub clipper: Clipper,
    /// Open the Euler-angle panel (G) for this convention: gimbal rings around the aircraft,
    /// sliders for the three angles [default: zyx].
    #[arg(long, value_name = "SEQ[,extrinsic]", num_args = 0..=1, default_missing_value = "zyx", value_parser = parse_convention)]
    pub gimbal: Option<Convention>,
    /// With --gimbal: start with the sliders at these angles (degrees), setting the attitude
    /// (the flight starts paused there). Like the HUD's, they are angles of the aerospace axes
    /// (x nose, y right wing, z down; world north-east-down): for zyx, yaw + nose right, pitch
    /// + nose up, roll + right wing down.
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true, value_parser = parse_angles, requires = "gimbal")]
    pub gimbal_angles: Option<[f64; 3]>,
}

#[cfg(test)]
mod tests;
