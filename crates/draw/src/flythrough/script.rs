//! Scripted control inputs for the fly-through window.
//!
//! A script is a text file of timed settings, one line each:
//!
//! ```text
//! # comments run from '#' to the end of the line; blank lines are ignored
//! 0.0  throttle=0.8
//! 1.0  pitch_rate=10 roll_rate=0
//! 2.5  roll_rate=-30 camera=orbit
//! ```
//!
//! The first field is the flight time in seconds (finite, ≥ 0, never decreasing from line to
//! line); then `key=value` pairs, at least one, each key at most once per line. A setting
//! takes effect at the first frame whose time has reached its line's time and holds until a
//! later line changes it.
//!
//! | key | value |
//! | --- | --- |
//! | `throttle` | 0 … 1 |
//! | `pitch_rate` | degrees/s, positive raises the nose (−720 … 720) |
//! | `roll_rate` | degrees/s, positive rolls right (−720 … 720) |
//! | `yaw_rate` | degrees/s, positive turns the nose right (−720 … 720) |
//! | `camera` | `chase`, `cockpit`, `orbit` or `free` |
//! | `pause` | `1` stops flight time there (Space resumes), `0` does nothing |
//!
//! Parsing is pure; [`load`] adds the file read. Every error names the file and the line.

use std::path::{Path, PathBuf};

use super::cameras::CameraMode;
use super::flight::{Controls, MAX_RATE_DPS};

/// One setting of a script line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setting {
    /// Throttle, 0..=1.
    Throttle(f64),
    /// Pitch rate, degrees/s, positive nose up.
    PitchRate(f64),
    /// Roll rate, degrees/s, positive right.
    RollRate(f64),
    /// Yaw rate, degrees/s, positive nose right.
    YawRate(f64),
    /// Switch the camera.
    Camera(CameraMode),
    /// Stop flight time (`true`); the window stays open, Space resumes.
    Pause(bool),
}

/// The settings of one line, applied at `time`.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Flight time, s.
    pub time: f64,
    /// Line number in the file (1-based), for messages.
    pub line: usize,
    /// What changes.
    pub settings: Vec<Setting>,
}

/// A parsed script: events in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    /// The events, times non-decreasing.
    pub events: Vec<Event>,
}

/// A script line that could not be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct ScriptError {
    /// The file (as given).
    pub file: String,
    /// Line number, 1-based.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Why a script file could not be used ([`load`]).
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("{}: cannot read script", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A line is bad.
    #[error(transparent)]
    Line(#[from] ScriptError),
}

/// The keys a line may set, for messages.
pub const KEYS: &str = "throttle, pitch_rate, roll_rate, yaw_rate, camera, pause";

fn number(key: &str, value: &str) -> Result<f64, String> {
    let v: f64 = value
        .parse()
        .map_err(|_| format!("{key}: `{value}` is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{key}: `{value}` is not a finite number"))
    }
}

fn rate(key: &str, value: &str) -> Result<f64, String> {
    let v = number(key, value)?;
    if v.abs() <= MAX_RATE_DPS {
        Ok(v)
    } else {
        Err(format!(
            "{key}: {v} degrees/s is outside −{MAX_RATE_DPS} … {MAX_RATE_DPS}"
        ))
    }
}

fn setting(key: &str, value: &str) -> Result<Setting, String> {
    match key {
        "throttle" => {
            let v = number(key, value)?;
            if (0.0..=1.0).contains(&v) {
                Ok(Setting::Throttle(v))
            } else {
                Err(format!("throttle: {v} is outside 0 … 1"))
            }
        }
        "pitch_rate" => rate(key, value).map(Setting::PitchRate),
        "roll_rate" => rate(key, value).map(Setting::RollRate),
        "yaw_rate" => rate(key, value).map(Setting::YawRate),
        "camera" => value
            .parse::<CameraMode>()
            .map(Setting::Camera)
            .map_err(|e| format!("camera: {e}")),
        "pause" => match value {
            "1" | "true" => Ok(Setting::Pause(true)),
            "0" | "false" => Ok(Setting::Pause(false)),
            _ => Err(format!("pause: `{value}` is not 1 or 0")),
        },
        _ => Err(format!("unknown key `{key}` (keys: {KEYS})")),
    }
}

fn same_key(a: &Setting, b: &Setting) -> bool {
    std::mem::discriminant(a) == std::mem::discriminant(b)
}

/// Parse a script; `file` names it in errors.
///
/// # Errors
/// The first bad line: its number and what is wrong with it.
pub fn parse(text: &str, file: &str) -> Result<Script, ScriptError> {
    let mut events: Vec<Event> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: String| ScriptError {
            file: file.to_string(),
            line,
            message,
        };
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let mut fields = content.split_whitespace();
        let t_text = fields.next().unwrap_or("");
        let time: f64 = t_text.parse().map_err(|_| {
            err(format!(
                "`{t_text}` is not a time in seconds (lines are `t_s key=value ...`)"
            ))
        })?;
        if !time.is_finite() || time < 0.0 {
            return Err(err(format!("time {t_text} must be finite and ≥ 0")));
        }
        if let Some(prev) = events.last() {
            if time < prev.time {
                return Err(err(format!(
                    "time {time} s is before the previous line's {} s (line {})",
                    prev.time, prev.line
                )));
            }
        }
        let mut settings: Vec<Setting> = Vec::new();
        for field in fields {
            let (key, value) = field
                .split_once('=')
                .ok_or_else(|| err(format!("`{field}` is not key=value")))?;
            let s = setting(key.trim(), value.trim()).map_err(err)?;
            if settings.iter().any(|o| same_key(o, &s)) {
                return Err(err(format!("`{key}` is set twice on one line")));
            }
            settings.push(s);
        }
        if settings.is_empty() {
            return Err(err(format!(
                "time {t_text} with nothing to set (keys: {KEYS})"
            )));
        }
        events.push(Event {
            time,
            line,
            settings,
        });
    }
    Ok(Script { events })
}

/// Read and parse a script file.
///
/// # Errors
/// The file cannot be read, or a line is bad (file and line named).
pub fn load(path: &Path) -> Result<Script, LoadError> {
    let text = wireflight_fsio::read_text(path).map_err(|source| LoadError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(parse(&text, &path.display().to_string())?)
}

/// Plays a script: applies the events whose time has come.
#[derive(Clone, Debug, Default)]
pub struct Player {
    next: usize,
}

impl Player {
    /// A player at the start of the script.
    pub fn new() -> Self {
        Self::default()
    }

    /// Apply every event with `time ≤ t` not applied yet to the controls; returns the last
    /// camera switch among them, if any, and whether one of them pauses.
    pub fn advance(
        &mut self,
        script: &Script,
        t: f64,
        controls: &mut Controls,
    ) -> (Option<CameraMode>, bool) {
        let mut camera = None;
        let mut pause = false;
        // A small slack so that accumulated time steps (k · dt) reach a line's time exactly.
        while let Some(e) = script.events.get(self.next) {
            if e.time > t + 1e-9 {
                break;
            }
            for s in &e.settings {
                match *s {
                    Setting::Throttle(v) => controls.throttle = v,
                    Setting::PitchRate(v) => controls.pitch_rate_dps = v,
                    Setting::RollRate(v) => controls.roll_rate_dps = v,
                    Setting::YawRate(v) => controls.yaw_rate_dps = v,
                    Setting::Camera(c) => camera = Some(c),
                    Setting::Pause(p) => pause |= p,
                }
            }
            self.next += 1;
        }
        (camera, pause)
    }

    /// Whether every event has been applied.
    pub fn finished(&self, script: &Script) -> bool {
        self.next >= script.events.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_documented_example() {
        let s = parse(
            "# demo\n0.0 throttle=0.8\n\n1.0 pitch_rate=10 roll_rate=0  # pull\n2.5 camera=orbit\n",
            "demo.txt",
        )
        .unwrap();
        assert_eq!(s.events.len(), 3);
        assert_eq!(s.events[0].settings, [Setting::Throttle(0.8)]);
        assert_eq!(
            s.events[1].settings,
            [Setting::PitchRate(10.0), Setting::RollRate(0.0)]
        );
        assert_eq!(s.events[1].line, 4);
        assert_eq!(s.events[2].settings, [Setting::Camera(CameraMode::Orbit)]);
    }

    #[test]
    fn bad_lines_name_the_file_and_line() {
        for (text, line, what) in [
            ("0 throttle=2", 1, "outside 0"),
            ("0 throttle=0.5\nx pitch_rate=1", 2, "not a time"),
            ("1 throttle=0.5\n0.5 throttle=1", 2, "before the previous"),
            ("0 pitch_rate", 1, "not key=value"),
            ("0 flaps=1", 1, "unknown key `flaps`"),
            ("0 roll_rate=nan", 1, "not a finite"),
            ("0 yaw_rate=1000", 1, "outside"),
            ("0 camera=tail", 1, "camera"),
            ("-1 throttle=0", 1, "≥ 0"),
            ("inf throttle=0", 1, "finite"),
            ("\n\n3", 3, "nothing to set"),
            ("0 throttle=1 throttle=0", 1, "twice"),
            ("0 pause=yes", 1, "pause"),
        ] {
            let e = parse(text, "s.txt").unwrap_err();
            assert_eq!(e.line, line, "{text}: {e}");
            let msg = e.to_string();
            assert!(msg.starts_with(&format!("s.txt:{line}: ")), "{msg}");
            assert!(msg.contains(what), "{text}: {msg}");
        }
    }

    #[test]
    fn the_player_applies_events_when_their_time_comes() {
        let s = parse(
            "0 throttle=0.8\n0.5 pitch_rate=10 camera=cockpit\n1 pitch_rate=0 pause=1",
            "s",
        )
        .unwrap();
        let mut p = Player::new();
        let mut c = Controls::default();
        assert_eq!(p.advance(&s, 0.0, &mut c), (None, false));
        assert_eq!(c.throttle, 0.8);
        assert_eq!(p.advance(&s, 0.25, &mut c), (None, false));
        assert_eq!(c.pitch_rate_dps, 0.0);
        // 30 steps of 1/60 s reach 0.5 s despite rounding.
        let t = (0..30).fold(0.0, |t, _| t + 1.0 / 60.0);
        assert_eq!(p.advance(&s, t, &mut c), (Some(CameraMode::Cockpit), false));
        assert_eq!(c.pitch_rate_dps, 10.0);
        assert!(!p.finished(&s));
        assert_eq!(p.advance(&s, 5.0, &mut c), (None, true));
        assert_eq!(c.pitch_rate_dps, 0.0);
        assert!(p.finished(&s));
    }
}
