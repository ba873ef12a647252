//! Options of the analysis commands: `compare`, `diagnose`, `identify`.

use clap::Args;

use super::{parse_size, positive, DataArgs, ModelArgs, WindowArgs};

const COMPARE_EXAMPLES: &str = "\
Examples:
  wireflight compare --flight windy.csv
  wireflight compare --flight windy.csv --add wind --plots plots/
  wireflight compare --flight windy.csv --add wind --frames-dir frames/   # both aircraft, replayed
  wireflight compare --flight windy.csv --add wind --out compare.gif --fps 5 --size 480x360
  wireflight compare --flight test.csv --model docs/examples/model.toml --json
  wireflight compare --flight a.csv --add aircraft:c_m_alpha --report report.html --out model.toml

The model is restarted from the data every --window seconds (multiple shooting) from a
least-squares estimate of the state, and its prediction compared with the measurements.
--add shows before → after for every channel, fitting the effect's unknown parameters.";

/// `wireflight compare` options.
#[derive(Debug, Args)]
#[command(after_help = COMPARE_EXAMPLES)]
pub struct CompareArgs {
    /// Flight data: CSV, a PX4 ULog (.ulg), or any CSV with --columns. (`--data` is an old
    /// spelling of this option.)
    #[arg(long, alias = "data", value_name = "FILE")]
    pub flight: std::path::PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub data: DataArgs,
    /// The model.
    #[command(flatten)]
    pub model: ModelArgs,
    /// How the flight is cut into windows.
    #[command(flatten)]
    pub windows: WindowArgs,
    /// A reference flight (repeatable): the same aircraft, sensors and model, believed
    /// normal. The flight is judged against the error the model leaves on them (its own, as
    /// well as the noise).
    #[arg(long, value_name = "FILE")]
    pub reference: Vec<std::path::PathBuf>,
    /// The log's wandering sensor errors as you know them: a preset (`independent`,
    /// `ekf-gnss`) or a TOML file as `simulate --sensor-errors` takes. The flight is judged
    /// against the error such errors leave on a right model (measured by flying the model's
    /// own path with them), not against the white noise alone (docs/workbench.md).
    #[arg(long, value_name = "FILE.toml|PRESET", conflicts_with = "reference")]
    pub sensor_errors: Option<String>,
    /// Write plots (PNG) into this directory.
    #[arg(long, value_name = "DIR")]
    pub plots: Option<std::path::PathBuf>,
    /// Write replay frames (PNG) of the measured aircraft and the model's beside it (the model
    /// with the `--add` effects when given), with the error over time, into this directory.
    #[arg(long, value_name = "DIR")]
    pub frames_dir: Option<std::path::PathBuf>,
    /// FILE.gif: the replay (as --frames-dir draws it) as one animated GIF; FILE.toml: the
    /// model with the --add effects and their fitted values, as a model file for --model.
    #[arg(long, value_name = "FILE.gif|FILE.toml")]
    pub out: Option<std::path::PathBuf>,
    /// Write one self-contained HTML page: the error per channel and axis before and after,
    /// the fitted values, the plots and a small replay, inline.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<std::path::PathBuf>,
    /// How model and measurements are compared: `auto` adds the filter-error method (a
    /// Kalman filter with Dryden gust states inside the fit) where output error leaves the
    /// model above the floor and the gusts are significant, the --add effects then fitted
    /// through it; `output-error` assumes calm air; `filter-error` always runs the filter
    /// (docs/turbulence.md).
    #[arg(long, value_enum, default_value_t = FitMethod::Auto)]
    pub method: FitMethod,
    /// Frames per second of flight time for --frames-dir and --out (25, as `render`'s).
    #[arg(long, default_value_t = crate::draw::output::DEFAULT_FPS, value_parser = positive)]
    pub fps: f64,
    /// Frame size for --frames-dir and --out, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x600", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Most frames --frames-dir writes (a flight with a long time gap would need more).
    #[arg(long, value_name = "N", default_value_t = crate::draw::output::DEFAULT_MAX_FRAMES,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub max_frames: u64,
    /// Machine-readable output (JSON) on stdout.
    #[arg(long)]
    pub json: bool,
}

const DIAGNOSE_EXAMPLES: &str = "\
Examples:
  wireflight diagnose --flight windy.csv
  wireflight diagnose --flight two-effects.csv --iterate
  wireflight diagnose --flight tests/data/jsbsim-mk82.csv --iterate --json
  wireflight diagnose --flight a.csv --report report.html --out model.toml
  wireflight diagnose --flight test.csv --aircraft identified.toml --reference r1.csv --reference r2.csv

Every catalogue effect that applies to the vehicle, and every promising number of the
aircraft's set, is added in turn, its parameters fitted, and ranked by how much error it
removes; a likelihood-ratio test decides whether that is more than fitting noise would give.
The best significant one is kept and the search repeats on top of it, every cause kept being
refitted together with the new one (and dropped when the others make it unnecessary), until
no candidate is significant. The verdict names every cause kept.";

/// `wireflight diagnose` options.
#[derive(Debug, Args)]
#[command(after_help = DIAGNOSE_EXAMPLES)]
pub struct DiagnoseArgs {
    /// Flight data: CSV, a PX4 ULog (.ulg), or any CSV with --columns. (`--data` is an old
    /// spelling of this option.)
    #[arg(long, alias = "data", value_name = "FILE")]
    pub flight: std::path::PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub data: DataArgs,
    /// The model to start from.
    #[command(flatten)]
    pub model: ModelArgs,
    /// How the flight is cut into windows.
    #[command(flatten)]
    pub windows: WindowArgs,
    /// A reference flight (repeatable): the same aircraft, sensors and model, believed
    /// normal. The flight is judged against the error the model leaves on them (its own, as
    /// well as the noise), and causes are reported as changes from them.
    #[arg(long, value_name = "FILE")]
    pub reference: Vec<std::path::PathBuf>,
    /// The log's wandering sensor errors as you know them: a preset (`independent`,
    /// `ekf-gnss`) or a TOML file as `simulate --sensor-errors` takes. The flight is judged
    /// against the error such errors leave on a right model (measured by flying the model's
    /// own path with them), not against the white noise alone (docs/workbench.md).
    #[arg(long, value_name = "FILE.toml|PRESET", conflicts_with = "reference")]
    pub sensor_errors: Option<String>,
    /// Show every step of the search: the candidates at each step, what was added and
    /// dropped, and the causes' joint values after it.
    #[arg(long)]
    pub iterate: bool,
    /// Also try, as candidates, the formula terms `wireflight discover` proposes for this
    /// flight (its best five), fitted and tested like every other candidate.
    #[arg(long)]
    pub discover: bool,
    /// How model and measurements are compared: `auto` uses output error, and the
    /// filter-error method (a Kalman filter with Dryden gust states inside the fit) where
    /// output error leaves the error unexplained and gusts are significant; `output-error`
    /// assumes calm air; `filter-error` always runs the filter (docs/turbulence.md).
    #[arg(long, value_enum, default_value_t = FitMethod::Auto)]
    pub method: FitMethod,
    /// Write the model with the causes found (effects with their fitted parameters, the
    /// aircraft's numbers changed) as a model file for --model (FILE.toml).
    #[arg(long, value_name = "FILE.toml")]
    pub out: Option<std::path::PathBuf>,
    /// Write one self-contained HTML page: the verdict, the ladder, the error per channel and
    /// axis before and after, the fitted values, the plots and a small replay, inline.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<std::path::PathBuf>,
    /// Machine-readable output (JSON) on stdout.
    #[arg(long)]
    pub json: bool,
}

const IDENTIFY_EXAMPLES: &str = "\
Examples:
  wireflight identify --flight a.csv --flight b.csv --free 'c_m_*,c_ell_p' --out identified.toml
  wireflight identify --flight tests/data/jsbsim-c172p-doublets.csv \\
      --flight tests/data/jsbsim-c172p-steps.csv \\
      --validate tests/data/jsbsim-c172p-validation.csv --out c172p-identified.toml
  wireflight compare --flight c.csv --aircraft identified.toml

The numbers are fitted jointly by output error over every window of every flight (each
window's start state estimated with them), pulled toward the starting set by a prior of
relative width --prior, so that a number the flights do not determine stays where it was and
is reported as not identified. An equation-error regression on the measured accelerations is
tried as the starting point. The output is an ordinary parameter-set TOML.";

/// `wireflight identify` options.
#[derive(Debug, Args)]
#[command(after_help = IDENTIFY_EXAMPLES)]
pub struct IdentifyArgs {
    /// Flight data: CSV, a PX4 ULog (.ulg), or any CSV with --columns; repeat for several
    /// flights of one fixed-wing aircraft. (`--data` is another spelling.)
    #[arg(long, alias = "data", value_name = "FILE", required = true)]
    pub flight: Vec<std::path::PathBuf>,
    /// How the flight files are read (for every --flight and --validate).
    #[command(flatten)]
    pub data: DataArgs,
    /// The model to start from (its aircraft set is the prior's centre).
    #[command(flatten)]
    pub model: ModelArgs,
    /// How each flight is cut into windows.
    #[command(flatten)]
    pub windows: WindowArgs,
    /// The numbers to fit, comma-separated keys or prefixes ending in `*` (`c_m_*,c_ell_p,
    /// mass_kg`) [default: every aerodynamic coefficient].
    #[arg(long, value_name = "K1,K2*,...", value_delimiter = ',')]
    pub free: Vec<String>,
    /// Relative width (1σ) of the prior toward the starting set, in 0.01..=3 (1 % to 300 %
    /// of each number).
    #[arg(long, default_value_t = 0.3, value_parser = prior_width)]
    pub prior: f64,
    /// Held-out flights of the same aircraft: their error before and after is printed
    /// (repeatable).
    #[arg(long, value_name = "FILE")]
    pub validate: Vec<std::path::PathBuf>,
    /// Skip the equation-error starting point.
    #[arg(long)]
    pub no_equation_error: bool,
    /// Write the identified parameter set here (TOML).
    #[arg(long, value_name = "FILE.toml")]
    pub out: Option<std::path::PathBuf>,
    /// Machine-readable output (JSON) on stdout.
    #[arg(long)]
    pub json: bool,
    /// How the numbers are fitted: `output-error` assumes calm air; `auto` refits them
    /// through the filter-error method where a flight's gusts are significant; `filter-error`
    /// always does (docs/turbulence.md). Not `auto` by default: without reference flights a
    /// model that is not exact leaves what the filter can take for gusts.
    #[arg(long, value_enum, default_value_t = FitMethod::OutputError)]
    pub method: FitMethod,
}

/// Narrowest and widest `--prior`: below 1 % the prior pins the numbers (the fit cannot move
/// them, and their ± would be the prior's alone); beyond 300 % it no longer regularises and
/// numbers the flights do not determine get no finite ±.
pub const PRIOR_RANGE: (f64, f64) = (0.01, 3.0);

/// `--prior`: a relative width in [`PRIOR_RANGE`].
fn prior_width(s: &str) -> Result<f64, String> {
    let v = positive(s)?;
    let (lo, hi) = PRIOR_RANGE;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{v} is outside {lo}..={hi}: the prior's relative width is 1 % to 300 % of each \
             number"
        ))
    }
}

const DISCOVER_EXAMPLES: &str = "\
Examples:
  wireflight discover --flight test.csv
  wireflight discover --flight test.csv --add prop_torque --json

What the model lacks is read through the equations of motion at the measured states (the
measured accelerations less the model's, times the mass and inertia), on each body axis (a
point mass: its forces per unit mass along and across its flight path), and regressed on a
library of candidate terms by stepwise selection; each term found is printed with its
reading, its coefficient ± σ, the flight's error (× the noise) with it and the terms before
it added and fitted, as compare --add reports it, and the --add spec that adds it.";

/// `wireflight discover` options.
#[derive(Debug, Args)]
#[command(after_help = DISCOVER_EXAMPLES)]
pub struct DiscoverArgs {
    /// Flight data: CSV, a PX4 ULog (.ulg), or any CSV with --columns.
    #[arg(long, alias = "data", value_name = "FILE")]
    pub flight: std::path::PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub data: DataArgs,
    /// The model to start from (--add effects are fitted to the flight first).
    #[command(flatten)]
    pub model: ModelArgs,
    /// How the flight is cut into windows (for fitting the --add effects and the terms found).
    #[command(flatten)]
    pub windows: WindowArgs,
    /// Machine-readable output (JSON) on stdout.
    #[arg(long)]
    pub json: bool,
}

/// `--method`: how a fit compares model and measurements.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FitMethod {
    /// Output error; the filter-error method where turbulence is significant.
    Auto,
    /// Output error alone (calm air).
    OutputError,
    /// The filter-error method always.
    FilterError,
}

impl From<FitMethod> for wireflight_analysis::diagnose::turbulence::Method {
    fn from(m: FitMethod) -> Self {
        use wireflight_analysis::diagnose::turbulence::Method;
        match m {
            FitMethod::Auto => Method::Auto,
            FitMethod::OutputError => Method::OutputError,
            FitMethod::FilterError => Method::FilterError,
        }
    }
}
