//! `wireflight simulate` command lines from named options: a flight test reads as the flight it
//! flies, and the numbers a test's assertions depend on stay in one place.
//!
//! The options go on the command line in the order they are set, each as given (a number as
//! Rust prints it: `0.05` is `0.05`, `30` is `30`); an option not set is the simulator's default.
//!
//! ```ignore
//! let a = Flight::new()
//!     .manoeuvre("flight-test")
//!     .duration(30)
//!     .hidden("aircraft:c_m_alpha=-3.3")
//!     .noise_pos(0.05)
//!     .seed(1)
//!     .write(dir, "a.csv");
//! ```

use std::fmt::Display;
use std::path::{Path, PathBuf};

use super::cli::ok;

/// A `simulate` command line under construction.
#[derive(Clone, Debug, Default)]
pub struct Flight {
    quiet: bool,
    options: Vec<String>,
}

impl Flight {
    /// Nothing set: the simulator's defaults (the aerosonde fixed wing, 60 s at 50 Hz, no
    /// manoeuvre, no noise).
    pub fn new() -> Self {
        Self::default()
    }

    /// `-q`: no report on stderr.
    pub fn quiet(mut self) -> Self {
        self.quiet = true;
        self
    }

    /// `--vehicle`: `fixed-wing` or `point-mass`.
    pub fn vehicle(self, kind: &str) -> Self {
        self.option("--vehicle", kind)
    }

    /// `--manoeuvre`.
    pub fn manoeuvre(self, name: &str) -> Self {
        self.option("--manoeuvre", name)
    }

    /// `--duration`, seconds.
    pub fn duration(self, s: impl Display) -> Self {
        self.option("--duration", s)
    }

    /// `--rate`, samples per second.
    pub fn rate(self, hz: impl Display) -> Self {
        self.option("--rate", hz)
    }

    /// `--hidden`: an effect flown but not written in the file (repeat for more).
    pub fn hidden(self, spec: &str) -> Self {
        self.option("--hidden", spec)
    }

    /// `--add`: an effect flown and written in the file (repeat for more).
    pub fn add(self, spec: &str) -> Self {
        self.option("--add", spec)
    }

    /// `--noise-pos`, metres.
    pub fn noise_pos(self, sigma: impl Display) -> Self {
        self.option("--noise-pos", sigma)
    }

    /// `--noise-att`, degrees.
    pub fn noise_att(self, sigma: impl Display) -> Self {
        self.option("--noise-att", sigma)
    }

    /// `--noise-vel`, m/s (velocity and airspeed).
    pub fn noise_vel(self, sigma: impl Display) -> Self {
        self.option("--noise-vel", sigma)
    }

    /// `--noise-rate`, degrees per second.
    pub fn noise_rate(self, sigma: impl Display) -> Self {
        self.option("--noise-rate", sigma)
    }

    /// `--noise-acc`, m/s²: also records the accelerometer.
    pub fn noise_acc(self, sigma: impl Display) -> Self {
        self.option("--noise-acc", sigma)
    }

    /// `--seed` of the noise.
    pub fn seed(self, seed: impl Display) -> Self {
        self.option("--seed", seed)
    }

    /// `--turbulence`: `light`, `moderate` or `severe`.
    pub fn turbulence(self, level: &str) -> Self {
        self.option("--turbulence", level)
    }

    /// `--turbulence-seed`.
    pub fn turbulence_seed(self, seed: impl Display) -> Self {
        self.option("--turbulence-seed", seed)
    }

    /// `--sensor-errors`: a preset or a TOML file.
    pub fn sensor_errors(self, arg: impl Display) -> Self {
        self.option("--sensor-errors", arg)
    }

    /// Further arguments, as they are.
    pub fn extra(mut self, args: &[&str]) -> Self {
        self.options.extend(args.iter().map(|a| a.to_string()));
        self
    }

    fn option(mut self, name: &str, value: impl Display) -> Self {
        self.options.push(name.to_string());
        self.options.push(value.to_string());
        self
    }

    /// The arguments of `wireflight`: `[-q] simulate OPTIONS… --out OUT`.
    pub fn args(&self, out: impl AsRef<Path>) -> Vec<String> {
        let out = out.as_ref();
        let out = out
            .to_str()
            .unwrap_or_else(|| panic!("{}: not UTF-8", out.display()));
        let quiet = self.quiet.then(|| "-q".to_string());
        quiet
            .into_iter()
            .chain(["simulate".to_string()])
            .chain(self.options.iter().cloned())
            .chain(["--out".to_string(), out.to_string()])
            .collect()
    }

    /// Simulates the flight into `dir/name`, which must succeed: the file's path.
    #[track_caller]
    pub fn write(&self, dir: &Path, name: &str) -> PathBuf {
        let out = dir.join(name);
        ok(&self.args(&out));
        out
    }
}
