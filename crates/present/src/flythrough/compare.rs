//! `wireflight view --compare`: the measured flight and the model's beside it, with a
//! checkbox per catalogue effect. Ticking one re-runs the model's multiple-shooting
//! comparison ([`compare_prepared`]) on a worker thread; the result (errors and the model's
//! path) replaces the current one when it arrives. The effects' parameters come from one
//! diagnosis ([`diagnose`]) run on another worker thread at start-up; until it finishes, a
//! ticked effect uses the catalogue's defaults (zero wind, ...). Terms get rows too: those a
//! model file declares, those of `--add 'term:…'`, and those `discover` finds when the panel
//! asks it ([`Compare::start_discover`], on a third worker thread: [`super::discovery`]).
//!
//! No window code: the window reads this state (the fly-through session holds it as its
//! [`ModelPanel`]), tests drive it directly ([`Compare::wait`], [`Compare::wait_fit`],
//! [`Compare::wait_discover`]).

use std::error::Error;
use std::panic::AssertUnwindSafe;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::Instant;

use super::discovery::{self, Discovered, Discovering, Found};
use crate::track::model_track;
use wireflight_analysis::compare::{
    compare_prepared, ChannelErrors, CompareConfig, Comparison, Prepared,
};
use wireflight_analysis::diagnose::{diagnose, Correction, DiagnoseConfig, Diagnosis, Verdict};
use wireflight_data::FlightData;
use wireflight_draw::flythrough::session::ModelPanel;
use wireflight_draw::scene::track::ModelTrack;
use wireflight_draw::scene::ReplayError;
use wireflight_flight::effects::term::term_of;
use wireflight_flight::effects::{Effect, Param, CATALOGUE};
use wireflight_flight::model::Model;
use wireflight_flight::spec::EffectSpec;

/// Columns of the precomputed error-over-time curve (the window's plot scales it).
pub const ERROR_BINS: usize = 600;

/// One catalogue effect that applies to the vehicle: a checkbox.
#[derive(Debug)]
pub struct EffectRow {
    /// Catalogue name.
    pub name: &'static str,
    /// Ticked: in the model now.
    pub on: bool,
    /// Already in the base model (`--flight-model` or `--effects`): always on, not a choice.
    pub in_base: bool,
    /// Parameters given on the command line (`--add name:k=v`): kept over fitted values.
    pub fixed: Vec<(String, f64)>,
    /// The effect as the diagnosis fitted it, once it has finished.
    pub fitted: Option<Box<dyn Effect>>,
    /// The diagnosis's error with this effect added (for the panel), once finished.
    pub fitted_error: Option<f64>,
    /// What `discover` said of this term, when it found it.
    pub discovered: Option<Discovered>,
    default: Box<dyn Effect>,
}

impl EffectRow {
    /// The effect as it would be added now: fitted (or default) parameters, with the
    /// command line's fixed ones on top.
    pub fn effect(&self) -> Box<dyn Effect> {
        let mut e = self.fitted.as_ref().unwrap_or(&self.default).clone();
        for (k, v) in &self.fixed {
            // Checked when the row was made.
            let _ = e.set_param(k, *v);
        }
        e
    }

    /// Its parameters as they would be added now.
    pub fn params(&self) -> Vec<Param> {
        self.effect().params()
    }

    /// Whether a parameter still waits for the diagnosis (the default stands in for it).
    fn waits_for_fit(&self) -> bool {
        self.fitted.is_none()
            && self
                .default
                .params()
                .iter()
                .any(|p| !self.fixed.iter().any(|(k, _)| k == p.name))
    }
}

/// One evaluation of a model against the data.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Effects added to the base model, in catalogue order.
    pub effects: Vec<String>,
    /// Total error (RMS of the window scores).
    pub total: f64,
    /// The misfit in units of the measured noise (1 = right model).
    pub noise_units: f64,
    /// RMS errors per channel.
    pub channels: ChannelErrors,
    /// The model's flight, for drawing.
    pub track: ModelTrack,
    /// Largest position error per time bin ([`ERROR_BINS`] over the flight), m.
    pub error_bins: Vec<f32>,
    /// Time of the comparison itself (worker thread), s.
    pub compute_s: f64,
    /// From the request to the result being taken in (thread start, comparison, hand-over), s.
    pub latency_s: f64,
}

/// Where the effect-parameter fit (the diagnosis) stands.
#[derive(Debug)]
pub enum Fit {
    /// Not started (tests).
    Off,
    /// Running on its worker thread since then.
    Running(Instant),
    /// Finished: the verdict, and how long it took.
    Done {
        /// The conclusion.
        verdict: Verdict,
        /// Error expected from the noise alone.
        noise_floor: f64,
        /// Seconds it took.
        seconds: f64,
    },
    /// The diagnosis could not run (the message says why), or its thread died.
    Failed(String),
}

/// Why a comparison could not start, or a recomputation failed.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// An `--add` that is not an effect spec (the spec's own message).
    #[error(transparent)]
    Spec(Box<dyn Error + Send + Sync>),
    /// An `--add` effect that does not apply to the vehicle.
    #[error("--add {text}: effect `{name}` does not apply to a {vehicle} model")]
    NotApplicable {
        /// The `--add` as given.
        text: String,
        /// The effect.
        name: String,
        /// The vehicle kind.
        vehicle: String,
    },
    /// An `--add` effect that the base model has already.
    #[error("--add {text}: `{name}` is already in the base model (--effects or the model file)")]
    InBase {
        /// The `--add` as given.
        text: String,
        /// The effect.
        name: String,
    },
    /// An `--add` whose parameters do not build the effect.
    #[error("--add {text}")]
    Build {
        /// The `--add` as given.
        text: String,
        /// Why.
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
    /// The base model cannot be compared with the flight.
    #[error("comparing the base model with the flight")]
    Base(#[source] ReplayError),
    /// A recomputation could not be drawn.
    #[error(transparent)]
    Track(#[from] ReplayError),
    /// The comparison's worker thread panicked (a bug; the message says so) or died.
    #[error("{0}")]
    Worker(String),
}

type Job = Receiver<Result<Outcome, CompareError>>;
type FitJob = Receiver<Result<Diagnosis, String>>;
type DiscoverJob = Receiver<Result<Found, String>>;

/// The comparison state of a `--compare` session.
pub struct Compare {
    data: Arc<FlightData>,
    base: Model,
    cfg: CompareConfig,
    /// The catalogue effects that apply to the vehicle, in catalogue order.
    pub rows: Vec<EffectRow>,
    /// The base model (nothing ticked).
    pub before: Outcome,
    /// The model with the ticked effects (the last result in).
    pub now: Outcome,
    /// The parameter fit.
    pub fit: Fit,
    /// The last discovery of missing terms.
    pub discovery: Discovering,
    /// The last recomputation's error, if it failed.
    pub error: Option<String>,
    job: Option<(Job, Instant)>,
    /// A change came in while a job ran: start another when it ends.
    stale: bool,
    fit_job: Option<FitJob>,
    discover_job: Option<DiscoverJob>,
}

impl Compare {
    /// Compare `base` with `data`, with the `adds` (`name[:k=v,...]`) ticked; start the
    /// parameter fit in the background. The first comparisons run here, synchronously.
    ///
    /// # Errors
    /// An `--add` that is not a catalogue effect, does not apply, is in the base model already
    /// or has a bad parameter; a flight too short to compare.
    pub fn new(data: Arc<FlightData>, base: Model, adds: &[String]) -> Result<Self, CompareError> {
        let cfg = CompareConfig {
            window_s: CompareConfig::default_window_s(base.vehicle.kind()),
            ..CompareConfig::default()
        };
        Self::with_config(data, base, adds, cfg, true)
    }

    /// [`new`](Self::new) with a comparison window, and the fit started or not.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_config(
        data: Arc<FlightData>,
        mut base: Model,
        adds: &[String],
        cfg: CompareConfig,
        start_fit: bool,
    ) -> Result<Self, CompareError> {
        let kind = base.vehicle.kind();
        let ctx = base.effect_context();
        // A model file's `[[term]]` without values is a choice, as a catalogue effect is.
        let declared = wireflight_analysis::diagnose::take_declared_terms(&mut base);
        let mut rows: Vec<EffectRow> = CATALOGUE
            .iter()
            .filter_map(|info| {
                let name = info.name;
                let default = info.build(&ctx);
                let usable = default.applies_to(kind) && default.lacks_channel().is_none();
                usable.then(|| EffectRow {
                    name,
                    on: base.has_effect(name),
                    in_base: base.has_effect(name),
                    fixed: Vec::new(),
                    fitted: None,
                    fitted_error: None,
                    discovered: None,
                    default,
                })
            })
            .collect();
        // Terms have no catalogue entry: those declared, and those of `--add`, get a row each.
        let term_row = |default: Box<dyn Effect>| EffectRow {
            name: default.name(),
            on: false,
            in_base: false,
            fixed: Vec::new(),
            fitted: None,
            fitted_error: None,
            discovered: None,
            default,
        };
        rows.extend(declared.into_iter().map(term_row));
        for text in adds {
            let spec = EffectSpec::parse(text).map_err(|e| CompareError::Spec(e.into()))?;
            if spec.is_term() && !rows.iter().any(|r| r.name == spec.name) {
                let effect = EffectSpec {
                    params: Vec::new(),
                    ..spec.clone()
                }
                .build(&ctx)
                .map_err(|e| CompareError::Build {
                    text: text.clone(),
                    source: e.into(),
                })?;
                rows.push(term_row(effect));
            }
            let Some(row) = rows.iter_mut().find(|r| r.name == spec.name) else {
                return Err(CompareError::NotApplicable {
                    text: text.clone(),
                    name: spec.name,
                    vehicle: kind.to_string(),
                });
            };
            if row.in_base {
                return Err(CompareError::InBase {
                    text: text.clone(),
                    name: spec.name,
                });
            }
            spec.build(&ctx).map_err(|e| CompareError::Build {
                text: text.clone(),
                source: e.into(),
            })?;
            row.on = true;
            row.fixed = spec.params;
        }
        let empty = Vec::new();
        let before =
            evaluate(&data, &base, &empty, cfg, Instant::now()).map_err(CompareError::Base)?;
        let mut s = Self {
            now: before.clone(),
            before,
            data,
            base,
            cfg,
            rows,
            fit: Fit::Off,
            discovery: Discovering::Off,
            error: None,
            job: None,
            stale: false,
            fit_job: None,
            discover_job: None,
        };
        if s.rows.iter().any(|r| r.on && !r.in_base) {
            s.request();
            s.wait();
        }
        if start_fit {
            s.start_fit();
        }
        Ok(s)
    }

    /// Length of the comparison windows (the model is restarted from the data after each), s.
    pub fn window_s(&self) -> f64 {
        self.cfg.window_s
    }

    /// The flight.
    pub fn data(&self) -> &FlightData {
        &self.data
    }

    /// The model as ticked now.
    pub fn model(&self) -> Model {
        let mut m = self.base.clone();
        for r in self.rows.iter().filter(|r| r.on && !r.in_base) {
            // Rows apply to the vehicle and are not in the base: cannot fail.
            let _ = m.add_effect(r.effect());
        }
        m
    }

    /// Tick or untick the effect in row `i` (rows in the base model stay on); the model is
    /// recomputed in the background.
    pub fn set(&mut self, i: usize, on: bool) {
        let Some(row) = self.rows.get_mut(i) else {
            return;
        };
        if row.in_base || row.on == on {
            return;
        }
        row.on = on;
        self.request();
    }

    /// Tick or untick an effect by name; false if there is no such row.
    pub fn set_by_name(&mut self, name: &str, on: bool) -> bool {
        match self.rows.iter().position(|r| r.name == name) {
            Some(i) => {
                self.set(i, on);
                true
            }
            None => false,
        }
    }

    /// Start recomputing the model as ticked (or, if a recomputation is running, start
    /// another when it ends).
    pub fn request(&mut self) {
        if self.job.is_some() {
            self.stale = true;
            return;
        }
        self.stale = false;
        let (tx, rx) = mpsc::channel();
        let data = Arc::clone(&self.data);
        let model = self.model();
        let effects = self.ticked_names();
        let cfg = self.cfg;
        let asked = Instant::now();
        std::thread::spawn(move || {
            // A panic is a bug: the panel says so (and the exit status, see `app`).
            let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
                evaluate(&data, &model, &effects, cfg, asked).map_err(CompareError::Track)
            }))
            .unwrap_or_else(|p| Err(CompareError::Worker(panic_message(&*p))));
            let _ = tx.send(outcome);
        });
        self.job = Some((rx, asked));
    }

    fn ticked_names(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter(|r| r.on && !r.in_base)
            .map(|r| r.name.to_string())
            .collect()
    }

    fn start_fit(&mut self) {
        let (tx, rx) = mpsc::channel();
        let data = Arc::clone(&self.data);
        let base = self.base.clone();
        // The terms' rows are candidates the catalogue does not know.
        let terms: Vec<Box<dyn Effect>> = self
            .rows
            .iter()
            .filter(|r| !r.in_base && term_of(r.default.info()).is_some())
            .map(|r| r.default.clone())
            .collect();
        let cfg = self.diagnose_config();
        std::thread::spawn(move || {
            let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
                diagnose(&base, &data, &terms, &cfg)
                    .map_err(|e| chain(&*Box::<dyn Error + Send + Sync>::from(e)))
            }))
            .unwrap_or_else(|p| Err(panic_message(&*p)));
            let _ = tx.send(outcome);
        });
        self.fit = Fit::Running(Instant::now());
        self.fit_job = Some(rx);
    }

    /// The diagnosis's settings: its defaults, with the panel's comparison windows.
    fn diagnose_config(&self) -> DiagnoseConfig {
        let defaults = DiagnoseConfig::default();
        DiagnoseConfig {
            compare: CompareConfig {
                max_windows: defaults.compare.max_windows,
                ..self.cfg
            },
            ..defaults
        }
    }

    /// Start `discover` on the flight against the model as ticked now, on a worker thread:
    /// the terms it finds become rows (or annotate the rows they have already), each fitted
    /// alone on top of that model ([`discovery::find`]). False, and nothing started, while one
    /// runs.
    pub fn start_discover(&mut self) -> bool {
        if self.discover_job.is_some() {
            return false;
        }
        let (tx, rx) = mpsc::channel();
        let data = Arc::clone(&self.data);
        let model = self.model();
        let cfg = self.diagnose_config();
        std::thread::spawn(move || {
            let outcome =
                std::panic::catch_unwind(AssertUnwindSafe(|| discovery::find(&model, &data, &cfg)))
                    .unwrap_or_else(|p| Err(panic_message(&*p)));
            let _ = tx.send(outcome);
        });
        self.discovery = Discovering::Running(Instant::now());
        self.discover_job = Some(rx);
        true
    }

    /// Whether a discovery is running.
    pub fn discovering(&self) -> bool {
        self.discover_job.is_some()
    }

    /// Whether a recomputation, the fit or a discovery is still running.
    pub fn busy(&self) -> bool {
        self.job.is_some() || self.fit_job.is_some() || self.discover_job.is_some()
    }

    /// Whether a recomputation is running.
    pub fn recomputing(&self) -> bool {
        self.job.is_some()
    }

    /// Take in finished work, without waiting; true if anything changed.
    pub fn poll(&mut self) -> bool {
        self.take(false)
    }

    /// Wait for the recomputations to finish (not for the fit).
    pub fn wait(&mut self) {
        while self.job.is_some() {
            self.take_job(true);
        }
    }

    /// Wait for the fit, then for the recomputation it may start.
    pub fn wait_fit(&mut self) {
        while self.fit_job.is_some() {
            self.take_fit(true);
        }
        self.wait();
    }

    /// Wait for the discovery, then for the recomputation it may start.
    pub fn wait_discover(&mut self) {
        while self.discover_job.is_some() {
            self.take_discover(true);
        }
        self.wait();
    }

    fn take(&mut self, block: bool) -> bool {
        let a = self.take_fit(block);
        let b = self.take_discover(block);
        let c = self.take_job(block);
        a || b || c
    }

    fn take_discover(&mut self, block: bool) -> bool {
        let Some(rx) = &self.discover_job else {
            return false;
        };
        let got = receive(rx, block);
        let started = match self.discovery {
            Discovering::Running(t) => t,
            _ => Instant::now(),
        };
        let found = match got {
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => Err("the discovery thread died".to_string()),
            Ok(outcome) => outcome,
        };
        self.discover_job = None;
        match found {
            Err(why) => self.discovery = Discovering::Failed(why),
            Ok(found) => {
                self.discovery = Discovering::Done {
                    proposed: found.proposed,
                    rows: found.terms.len(),
                    noise_units_before: found.noise_units_before,
                    seconds: started.elapsed().as_secs_f64(),
                };
                if self.take_found(found) {
                    self.request();
                }
            }
        }
        true
    }

    /// The terms found, as rows: a new row each, or discover's word on the row the term has
    /// already (a declared or `--add` term keeps the fit it has, or takes this one). True if a
    /// ticked row's effect changed.
    fn take_found(&mut self, found: Found) -> bool {
        let mut refresh = false;
        for term in found.terms {
            let (fitted, fitted_error) = match term.fitted {
                Some((e, error)) => (Some(e), Some(error)),
                None => (None, None),
            };
            match self.rows.iter_mut().find(|r| r.name == term.name) {
                Some(row) => {
                    if !row.in_base && row.fitted.is_none() && fitted.is_some() {
                        refresh |= row.on && row.waits_for_fit();
                        row.fitted = fitted;
                        row.fitted_error = fitted_error;
                    }
                    row.discovered = Some(term.discovered);
                }
                None => self.rows.push(EffectRow {
                    name: term.name,
                    on: false,
                    in_base: false,
                    fixed: Vec::new(),
                    fitted,
                    fitted_error,
                    discovered: Some(term.discovered),
                    default: term.estimate,
                }),
            }
        }
        refresh
    }

    fn take_fit(&mut self, block: bool) -> bool {
        let Some(rx) = &self.fit_job else {
            return false;
        };
        let got = receive(rx, block);
        let started = match self.fit {
            Fit::Running(t) => t,
            _ => Instant::now(),
        };
        match got {
            Err(TryRecvError::Empty) => false,
            Err(TryRecvError::Disconnected) => {
                self.fit_job = None;
                self.fit = Fit::Failed("the diagnosis thread died".into());
                true
            }
            Ok(Err(e)) => {
                self.fit_job = None;
                self.fit = Fit::Failed(e);
                true
            }
            Ok(Ok(d)) => {
                self.fit_job = None;
                self.fit = Fit::Done {
                    verdict: d.verdict.clone(),
                    noise_floor: d.noise_floor,
                    seconds: started.elapsed().as_secs_f64(),
                };
                let mut refresh = false;
                // The causes found carry their joint values; the rest, their values alone.
                let found: Vec<String> = d.found.iter().map(|c| c.effect.clone()).collect();
                let alone = d.ranking.into_iter().filter(|c| !found.contains(&c.effect));
                for c in d.found.into_iter().chain(alone) {
                    if let Some(r) = self.rows.iter_mut().find(|r| r.name == c.effect) {
                        refresh |= r.on && !r.in_base && r.waits_for_fit();
                        if let Correction::Effect(e) = c.correction {
                            r.fitted = Some(e);
                        }
                        r.fitted_error = Some(c.error_after);
                    }
                }
                if refresh {
                    self.request();
                }
                true
            }
        }
    }

    fn take_job(&mut self, block: bool) -> bool {
        let Some((rx, _)) = &self.job else {
            return false;
        };
        let got = receive(rx, block);
        let outcome = match got {
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => {
                Err(CompareError::Worker("the comparison thread died".into()))
            }
            Ok(o) => o,
        };
        let asked = self.job.take().map(|(_, t)| t);
        match outcome {
            Ok(mut o) => {
                if let Some(t) = asked {
                    o.latency_s = t.elapsed().as_secs_f64();
                }
                self.now = o;
                self.error = None;
            }
            Err(e) => self.error = Some(chain(&e)),
        }
        if self.stale {
            self.request();
        }
        true
    }

    /// The diagnosis's verdict as a line for the panel.
    pub fn verdict_line(&self) -> String {
        match &self.fit {
            Fit::Running(t) => format!("fitting… ({:.1} s)", t.elapsed().as_secs_f64()),
            Fit::Failed(why) => format!("diagnosis failed ({why}): catalogue defaults"),
            Fit::Off => "not fitted: catalogue defaults".into(),
            Fit::Done {
                verdict: Verdict::Found(v),
                ..
            } if v.len() > 1 => format!("diagnosis: `{}` together", v.join("` + `")),
            Fit::Done {
                verdict: Verdict::Found(v),
                ..
            } if v.iter().all(|v| v.starts_with("aircraft:")) => {
                format!("diagnosis: `{}` is wrong in the set", v.join(""))
            }
            Fit::Done {
                verdict: Verdict::Found(v),
                ..
            } => format!("diagnosis: `{}` is missing", v.join("")),
            Fit::Done {
                verdict: Verdict::None,
                ..
            } => "diagnosis: none — the error is at the noise floor".into(),
            Fit::Done {
                verdict: Verdict::Unexplained,
                ..
            } => "diagnosis: unexplained — no effect brings the error to the noise".into(),
            Fit::Done {
                verdict: v @ Verdict::Turbulence(_),
                ..
            } => format!("diagnosis: {v} — what is left is random"),
        }
    }
}

/// The panel as the fly-through session holds it: polled for finished work, the model as
/// ticked now drawn beside the replay.
impl ModelPanel for Compare {
    fn poll(&mut self) -> bool {
        Compare::poll(self)
    }

    fn track(&self) -> &ModelTrack {
        &self.now.track
    }
}

/// A worker's result: waiting for it (`block`) or only taking it if it is there.
fn receive<T>(rx: &Receiver<T>, block: bool) -> Result<T, TryRecvError> {
    if block {
        rx.recv().map_err(|_| TryRecvError::Disconnected)
    } else {
        rx.try_recv()
    }
}

/// Compare `model` with `data` and make the track and the error curve.
fn evaluate(
    data: &FlightData,
    model: &Model,
    effects: &[String],
    cfg: CompareConfig,
    asked: Instant,
) -> Result<Outcome, ReplayError> {
    let start = Instant::now();
    let prep = Prepared::new(
        data,
        CompareConfig {
            max_windows: 0,
            ..cfg
        },
    );
    let comparison: Comparison = compare_prepared(model, &prep);
    let track = model_track(data, &comparison)?;
    let error_bins = bin_max(&track.time, &track.error_m, ERROR_BINS);
    let compute_s = start.elapsed().as_secs_f64();
    Ok(Outcome {
        effects: effects.to_vec(),
        total: comparison.total,
        noise_units: comparison.noise_units(),
        channels: comparison.channels,
        track,
        error_bins,
        compute_s,
        latency_s: asked.elapsed().as_secs_f64(),
    })
}

/// The largest value in each of `bins` equal time bins (NaN where a bin has no sample).
pub fn bin_max(time: &[f64], values: &[f64], bins: usize) -> Vec<f32> {
    let mut out = vec![f32::NAN; bins.max(1)];
    let (Some(&t0), Some(&t1)) = (time.first(), time.last()) else {
        return out;
    };
    let span = (t1 - t0).max(1e-9);
    let last = out.len() - 1;
    for (t, v) in time.iter().zip(values) {
        let b = (((t - t0) / span) * out.len() as f64) as usize;
        let slot = &mut out[b.min(last)];
        let v = *v as f32;
        if slot.is_nan() || v > *slot {
            *slot = v;
        }
    }
    out
}

/// An error and its sources, joined by ": " as the command line prints them.
fn chain(error: &(dyn Error + 'static)) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(e) = source {
        text.push_str(": ");
        text.push_str(&e.to_string());
        source = e.source();
    }
    text
}

/// What a worker thread's panic said, as an error for the panel.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_string());
    format!("internal error (a bug): {what}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_keep_the_peaks() {
        let time: Vec<f64> = (0..100).map(f64::from).collect();
        let mut v = vec![1.0; 100];
        v[37] = 9.0;
        let b = bin_max(&time, &v, 10);
        assert_eq!(b.len(), 10);
        assert_eq!(b[3], 9.0);
        assert!(b.iter().filter(|&&x| x == 1.0).count() == 9);
        assert!(bin_max(&[], &[], 4).iter().all(|x| x.is_nan()));
    }
}
