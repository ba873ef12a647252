//! What a reader found in a file ([`ImportReport`]): per channel, where it came from, how many
//! samples and at what rate, and what was done to it (resampled, held, dropped), with notes on
//! anything doubtful in the file. The ULog and column-mapped readers ([`super::px4`],
//! [`super::mapped`]) fill one in; [`super::load`] hands it on.

use std::fmt;

use crate::{Channel, FlightData};

/// One channel of an import: where it came from and what became of it.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelFound {
    /// The channel, e.g. `position`, `attitude`.
    pub channel: String,
    /// Where it came from: topic and fields, or columns.
    pub source: String,
    /// Samples in the file (after dropping unusable ones).
    pub samples: usize,
    /// Median sample rate in the file, Hz, where meaningful.
    pub rate_hz: Option<f64>,
    /// Whether it is in the flight data.
    pub used: bool,
    /// What was done, or why it is not used.
    pub note: String,
}

/// What a reader found in a file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportReport {
    /// The file.
    pub file: String,
    /// The format, e.g. `PX4 ULog`.
    pub format: String,
    /// Facts about the file: (what, value), e.g. (`system`, `PX4 PX4_SITL`).
    pub about: Vec<(String, String)>,
    /// The channels looked for, found or not.
    pub channels: Vec<ChannelFound>,
    /// Samples of the flight data.
    pub samples: usize,
    /// Its uniform rate when resampled, Hz.
    pub rate_hz: Option<f64>,
    /// Its duration, s.
    pub duration_s: f64,
    /// Anything doubtful.
    pub notes: Vec<String>,
    /// Each measured channel of the flight data: its own samples and rate
    /// ([`sampled_channels`]; filled in by the reader).
    pub sampled: Vec<ChannelSampled>,
}

/// A measured channel of flight data as read: how many of the rows are its own samples, at
/// what rate, and how many rows were filled in between them (never measurements).
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelSampled {
    /// The channel.
    pub channel: Channel,
    /// Rows that are its samples.
    pub samples: usize,
    /// Median rate of its samples, Hz.
    pub rate_hz: Option<f64>,
    /// Rows filled in between its samples.
    pub filled: usize,
}

/// Each measured channel of `data` (present and not derived): its samples, their rate and
/// the rows filled in between.
pub fn sampled_channels(data: &FlightData) -> Vec<ChannelSampled> {
    let n = data.len();
    let present = |channel: Channel| match channel {
        Channel::Position => true,
        Channel::Velocity => data.vel_ned.is_some() && !data.is_derived(crate::DERIVED_VEL_NED),
        Channel::Attitude => data.attitude.is_some(),
        Channel::Rates => data.rates_body.is_some() && !data.is_derived(crate::DERIVED_RATES_BODY),
        Channel::Airspeed => data.airspeed.is_some(),
        Channel::Accelerometer => data.accel_body.is_some(),
    };
    Channel::ALL
        .into_iter()
        .filter(|&c| present(c))
        .map(|channel| {
            let samples = data.sampling.count(channel, n);
            ChannelSampled {
                channel,
                samples,
                rate_hz: data.sampling.rate_hz(channel, &data.time),
                filled: n - samples,
            }
        })
        .collect()
}

/// The lines that say, per channel, its own samples when the flight's channels have their
/// own rates (nothing for a one-rate flight): `    position  6 samples  5 Hz  filled in at
/// 245 rows (not measurements)`.
pub fn sampling_lines(sampled: &[ChannelSampled]) -> String {
    if sampled.iter().all(|c| c.filled == 0) {
        return String::new();
    }
    let name_w = sampled
        .iter()
        .map(|c| c.channel.name().len())
        .max()
        .unwrap_or(0);
    let count_w = sampled
        .iter()
        .map(|c| c.samples.to_string().len())
        .max()
        .unwrap_or(0);
    let mut out = String::from("  each channel at its own times:\n");
    for c in sampled {
        let rate = c.rate_hz.map_or_else(|| "–".to_string(), rate_text);
        let filled = match c.filled {
            0 => String::new(),
            k => format!("  filled in at {k} rows between (not measurements)"),
        };
        out += &format!(
            "    {:<name_w$}  {:>count_w$} samples  {rate:>7}{filled}\n",
            c.channel.name(),
            c.samples
        );
    }
    out
}

impl ImportReport {
    /// A report of `format` for `file`.
    pub fn new(file: &str, format: &str) -> Self {
        Self {
            file: file.to_string(),
            format: format.to_string(),
            ..Self::default()
        }
    }

    /// Adds a channel.
    pub fn channel(
        &mut self,
        channel: &str,
        source: impl Into<String>,
        samples: usize,
        rate_hz: Option<f64>,
        used: bool,
        note: impl Into<String>,
    ) {
        self.channels.push(ChannelFound {
            channel: channel.to_string(),
            source: source.into(),
            samples,
            rate_hz,
            used,
            note: note.into(),
        });
    }

    /// Adds a note.
    pub fn note(&mut self, note: impl Into<String>) {
        self.notes.push(note.into());
    }

    /// The report as JSON.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "file": self.file,
            "format": self.format,
            "about": self.about.iter().map(|(k, v)| serde_json::json!({"what": k, "value": v})).collect::<Vec<_>>(),
            "channels": self.channels.iter().map(|c| serde_json::json!({
                "channel": c.channel, "source": c.source, "samples": c.samples,
                "rate_hz": c.rate_hz, "used": c.used, "note": c.note,
            })).collect::<Vec<_>>(),
            "samples": self.samples,
            "rate_hz": self.rate_hz,
            "sampled": sampled_json(&self.sampled),
            "duration_s": self.duration_s,
            "notes": self.notes,
        })
    }
}

/// [`ChannelSampled`]s as JSON: `[{"channel", "samples", "rate_hz", "filled"}]`.
pub fn sampled_json(sampled: &[ChannelSampled]) -> serde_json::Value {
    sampled
        .iter()
        .map(|c| {
            serde_json::json!({
                "channel": c.channel.name(), "samples": c.samples,
                "rate_hz": c.rate_hz, "filled": c.filled,
            })
        })
        .collect()
}

/// Text taken from a file, safe to print: control characters (ESC, CR, BEL, …, and the C1
/// controls) are shown as `\u{1b}`, so that a log's `sys_name` cannot move the cursor, clear
/// the screen or retitle the terminal. Text without them is returned as it is.
pub fn escape(s: &str) -> String {
    if !s.chars().any(char::is_control) {
        return s.to_string();
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        } else {
            out.push(c);
        }
    }
    out
}

/// A sample rate for people: `250 Hz`, `12.5 Hz`, `0.2 Hz`.
pub fn rate_text(hz: f64) -> String {
    if hz >= 99.5 {
        format!("{hz:.0} Hz")
    } else if hz >= 0.995 {
        let s = format!("{hz:.1}");
        format!("{} Hz", s.strip_suffix(".0").unwrap_or(&s))
    } else {
        format!("{hz:.2} Hz")
    }
}

impl fmt::Display for ImportReport {
    /// A few lines: the file and format, the facts, a table of channels (text left-aligned,
    /// numbers right-aligned), the result, the notes.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Everything here may hold text from the file (info strings, column names): escaped.
        writeln!(f, "{} ({})", escape(&self.file), escape(&self.format))?;
        for (k, v) in &self.about {
            writeln!(f, "  {}: {}", escape(k), escape(v))?;
        }
        let rows: Vec<[String; 5]> = self
            .channels
            .iter()
            .map(|c| {
                [
                    escape(&c.channel),
                    escape(&c.source),
                    c.samples.to_string(),
                    c.rate_hz.map_or_else(|| "–".to_string(), rate_text),
                    if c.used {
                        escape(&c.note)
                    } else if c.note.is_empty() {
                        "not used".to_string()
                    } else {
                        format!("not used: {}", escape(&c.note))
                    },
                ]
            })
            .collect();
        let header = ["channel", "from", "samples", "rate", "note"];
        let width = |i: usize| {
            rows.iter()
                .map(|r| r[i].chars().count())
                .chain([header[i].chars().count()])
                .max()
                .unwrap_or(0)
        };
        let w: Vec<usize> = (0..5).map(width).collect();
        let line = |f: &mut fmt::Formatter<'_>, r: [&str; 5]| {
            let pad = |s: &str, n: usize| " ".repeat(n.saturating_sub(s.chars().count()));
            let text = format!(
                "  {}{}  {}{}  {}{}  {}{}  {}",
                r[0],
                pad(r[0], w[0]),
                r[1],
                pad(r[1], w[1]),
                pad(r[2], w[2]),
                r[2],
                pad(r[3], w[3]),
                r[3],
                r[4]
            );
            writeln!(f, "{}", text.trim_end())
        };
        if !rows.is_empty() {
            line(f, header)?;
            for r in &rows {
                line(f, [&r[0], &r[1], &r[2], &r[3], &r[4]])?;
            }
        }
        let lines = sampling_lines(&self.sampled);
        match self.rate_hz {
            _ if !lines.is_empty() => writeln!(
                f,
                "  flight data: {} rows (the times anything was sampled) over {:.1} s",
                self.samples, self.duration_s
            )?,
            Some(hz) => writeln!(
                f,
                "  flight data: {} samples at {} over {:.1} s",
                self.samples,
                rate_text(hz),
                self.duration_s
            )?,
            None => writeln!(
                f,
                "  flight data: {} samples over {:.1} s",
                self.samples, self.duration_s
            )?,
        }
        f.write_str(&lines)?;
        for n in &self.notes {
            writeln!(f, "  note: {}", escape(n))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_aligns_text_left_and_numbers_right() {
        let mut r = ImportReport::new("f.ulg", "PX4 ULog");
        r.channel(
            "position",
            "vehicle_local_position x, y, z",
            313,
            Some(10.0),
            true,
            "",
        );
        r.channel(
            "airspeed",
            "airspeed true_airspeed_m_s",
            7,
            Some(0.5),
            false,
            "covers 2 %",
        );
        r.samples = 776;
        r.rate_hz = Some(25.0);
        r.duration_s = 31.04;
        r.note("xy_valid is false");
        let text = r.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "f.ulg (PX4 ULog)");
        assert_eq!(
            lines[2],
            "  position  vehicle_local_position x, y, z      313    10 Hz"
        );
        assert_eq!(
            lines[3],
            "  airspeed  airspeed true_airspeed_m_s            7  0.50 Hz  not used: covers 2 %"
        );
        assert_eq!(lines[4], "  flight data: 776 samples at 25 Hz over 31.0 s");
        assert_eq!(lines[5], "  note: xy_valid is false");
        assert_eq!(rate_text(250.0), "250 Hz");
        assert_eq!(escape("PX4\x1b[2J\r\u{9b}x"), "PX4\\u{1b}[2J\\u{d}\\u{9b}x");
        assert_eq!(escape("plain ü"), "plain ü");
        let mut r = ImportReport::new("f.ulg", "PX4 ULog");
        r.about
            .push(("system".into(), "evil\x1b]0;title\x07".into()));
        assert!(r
            .to_string()
            .contains("  system: evil\\u{1b}]0;title\\u{7}"));
        assert_eq!(rate_text(12.5), "12.5 Hz");
    }
}
