//! One topic's samples as a cleaned time series, and resampling onto the flight's time base
//! (linear; quaternions by slerp).

use glam::DQuat;

use super::GAP_NOTE_S;
use crate::data::report::ImportReport;
use crate::data::ulog::{Topic, UlogError, UlogErrorKind, UlogFile};

/// One topic's samples: times (s from the log's start) and columns, cleaned.
#[derive(Clone, Debug)]
pub(super) struct Series {
    pub(super) topic: String,
    pub(super) t: Vec<f64>,
    pub(super) cols: Vec<Vec<f64>>,
}

impl Series {
    /// Fields `fields` of the first instance of `topic` with samples; `None` when the log has
    /// none. Samples with a zero time stamp or a non-finite value are dropped; out-of-order
    /// samples are sorted, and of samples with equal times the last is kept.
    ///
    /// # Errors
    /// The topic has samples but not one of the fields (or no `timestamp`).
    pub(super) fn of(
        log: &UlogFile,
        file: &str,
        topic: &str,
        fields: &[&str],
        t_ref: u64,
    ) -> Result<Option<Series>, UlogError> {
        let Some(tp) = log.topic(topic) else {
            return Ok(None);
        };
        let missing = |f: &str| {
            UlogError::file(
                file,
                UlogErrorKind::Missing(format!("no such field (the topic has {})", field_list(tp))),
            )
            .in_topic(topic)
            .in_field(f)
        };
        let ts = tp.timestamps().ok_or_else(|| missing("timestamp"))?;
        let mut cols = Vec::with_capacity(fields.len());
        for f in fields {
            cols.push(if *f == "timestamp" {
                ts.iter().map(|&t| t as f64).collect()
            } else {
                tp.values(f).ok_or_else(|| missing(f))?
            });
        }
        let mut idx: Vec<usize> = (0..ts.len())
            .filter(|&i| ts[i] != 0 && cols.iter().all(|c| c[i].is_finite()))
            .collect();
        idx.sort_by_key(|&i| ts[i]);
        // Equal times: keep the last written.
        let mut keep: Vec<usize> = Vec::with_capacity(idx.len());
        for i in idx {
            match keep.last_mut() {
                Some(last) if ts[*last] == ts[i] => *last = i,
                _ => keep.push(i),
            }
        }
        if keep.is_empty() {
            return Ok(None);
        }
        Ok(Some(Series {
            topic: topic.to_string(),
            t: keep
                .iter()
                .map(|&i| ts[i].wrapping_sub(t_ref) as i64 as f64 * 1e-6)
                .collect(),
            cols: cols
                .iter()
                .map(|c| keep.iter().map(|&i| c[i]).collect())
                .collect(),
        }))
    }

    pub(super) fn len(&self) -> usize {
        self.t.len()
    }

    pub(super) fn span(&self) -> (f64, f64) {
        (self.t[0], self.t[self.t.len() - 1])
    }

    /// Median sample rate, Hz (`None` with fewer than two samples).
    pub(super) fn rate(&self) -> Option<f64> {
        let mut dt: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if dt.is_empty() {
            return None;
        }
        let mid = dt.len() / 2;
        let (_, m, _) = dt.select_nth_unstable_by(mid, f64::total_cmp);
        (*m > 0.0).then(|| 1.0 / *m)
    }

    /// Notes the longest gap when it is longer than [`GAP_NOTE_S`].
    pub(super) fn gap_note(&self, report: &mut ImportReport) {
        let gap = self
            .t
            .windows(2)
            .map(|w| (w[1] - w[0], w[0]))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((g, at)) = gap.filter(|g| g.0 > GAP_NOTE_S) {
            report.note(format!(
                "{}: a gap of {g:.1} s after {at:.1} s, interpolated across",
                self.topic
            ));
        }
    }

    /// Every column interpolated linearly at `grid` (held beyond the ends).
    pub(super) fn linear(&self, grid: &[f64]) -> Vec<Vec<f64>> {
        self.cols
            .iter()
            .map(|c| {
                walk(&self.t, grid, |i, s| match s {
                    None => c[i],
                    Some(s) => c[i] + (c[i + 1] - c[i]) * s,
                })
            })
            .collect()
    }

    /// Every column held from each sample to the next at `grid` (the first before it).
    pub(super) fn hold(&self, grid: &[f64]) -> Vec<Vec<f64>> {
        self.cols
            .iter()
            .map(|c| {
                walk(&self.t, grid, |i, s| match s {
                    Some(s) if s >= 1.0 => c[i + 1],
                    _ => c[i],
                })
            })
            .collect()
    }
}

/// For each time of the increasing `grid`, calls `f(i, s)` with the sample `i` at or before
/// it and the fraction `s` of the way to sample `i + 1` (`None` beyond the ends, where `i` is
/// the end sample). `t` is increasing and not empty.
fn walk<T>(t: &[f64], grid: &[f64], mut f: impl FnMut(usize, Option<f64>) -> T) -> Vec<T> {
    let n = t.len();
    let mut i = 0;
    grid.iter()
        .map(|&g| {
            if g <= t[0] {
                return f(0, None);
            }
            if g >= t[n - 1] {
                return f(n - 1, None);
            }
            while i + 1 < n && t[i + 1] <= g {
                i += 1;
            }
            f(i, Some((g - t[i]) / (t[i + 1] - t[i])))
        })
        .collect()
}

/// Quaternions slerped at `grid` (the shorter way round; held beyond the ends).
pub(super) fn slerp(t: &[f64], q: &[DQuat], grid: &[f64]) -> Vec<DQuat> {
    walk(t, grid, |i, s| match s {
        None => q[i],
        Some(s) => {
            let (a, mut b) = (q[i], q[i + 1]);
            if a.dot(b) < 0.0 {
                b = -b;
            }
            a.slerp(b, s).normalize()
        }
    })
}

/// The field names of a topic, for errors (at most 12).
fn field_list(t: &Topic) -> String {
    let names: Vec<&str> = t.fields.iter().map(|f| f.name.as_str()).collect();
    if names.len() > 12 {
        format!("{}, … ({} fields)", names[..12].join(", "), names.len())
    } else {
        names.join(", ")
    }
}
