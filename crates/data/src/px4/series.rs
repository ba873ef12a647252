//! One topic's samples as a cleaned time series, and resampling onto the flight's time base
//! (linear; quaternions by slerp).

use glam::DQuat;

use super::GAP_NOTE_S;
use crate::columns::Quantity;
use crate::report::ImportReport;
use crate::ulog::{Topic, UlogError, UlogErrorKind, UlogFile};

/// One topic's samples: times (s from the log's start) and columns, cleaned.
#[derive(Clone, Debug)]
pub(super) struct Series {
    pub(super) topic: String,
    pub(super) t: Vec<f64>,
    /// The samples' time stamps as written, µs (for messages).
    pub(super) us: Vec<u64>,
    pub(super) cols: Vec<Vec<f64>>,
    /// The fields of `cols`, as named in the log.
    pub(super) fields: Vec<String>,
    /// Samples whose time stamp is earlier than the one written before it (sorted).
    pub(super) out_of_order: usize,
}

/// Most samples of a topic whose time stamps may go back in time (a fraction of the topic's
/// samples) before the topic is refused as not a time series: sorting a few is repair,
/// sorting more is guessing.
pub(super) const MAX_OUT_OF_ORDER: f64 = 0.01;

impl Series {
    /// Fields `fields` of the first instance of `topic` with samples; `None` when the log has
    /// none. Samples with a zero time stamp or a non-finite value are dropped; out-of-order
    /// samples are sorted (more than [`MAX_OUT_OF_ORDER`] of them is an error), and of samples
    /// with equal times the last is kept.
    ///
    /// # Errors
    /// The topic has samples but not one of the fields (or no `timestamp`); a time stamp more
    /// than 1e9 s from the log's start; time stamps out of order.
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
        let bad_time = |why: String| {
            UlogError::file(file, UlogErrorKind::BadValues(why))
                .in_topic(topic)
                .in_field("timestamp")
        };
        let (lo, hi, range) = Quantity::Time.range();
        let secs = |us: u64| (i128::from(us) - i128::from(t_ref)) as f64 * 1e-6;
        let mut idx: Vec<usize> = Vec::with_capacity(ts.len());
        let mut out_of_order = 0;
        let mut first_back: Option<(usize, usize)> = None;
        for i in 0..ts.len() {
            if ts[i] == 0 || !cols.iter().all(|c| c[i].is_finite()) {
                continue;
            }
            let t = secs(ts[i]);
            if !(lo..=hi).contains(&t) {
                return Err(bad_time(format!(
                    "sample {i}: time stamp {} µs is {t:.6e} s from the log's start ({} µs), \
                     outside {range}",
                    ts[i], t_ref
                )));
            }
            if let Some(&last) = idx.last() {
                if ts[i] < ts[last] {
                    out_of_order += 1;
                    first_back.get_or_insert((last, i));
                }
            }
            idx.push(i);
        }
        if let Some((a, b)) = first_back {
            if out_of_order as f64 > MAX_OUT_OF_ORDER * idx.len() as f64 {
                return Err(bad_time(format!(
                    "{out_of_order} of {} time stamps go back in time (the first: sample {b} at \
                     {} µs after sample {a} at {} µs): the samples are not a time series",
                    idx.len(),
                    ts[b],
                    ts[a]
                )));
            }
        }
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
            t: keep.iter().map(|&i| secs(ts[i])).collect(),
            us: keep.iter().map(|&i| ts[i]).collect(),
            cols: cols
                .iter()
                .map(|c| keep.iter().map(|&i| c[i]).collect())
                .collect(),
            fields: fields.iter().map(|f| f.to_string()).collect(),
            out_of_order,
        }))
    }

    /// Checks column `col` (times `scale`) against the range of `q`, the CSV reader's.
    ///
    /// # Errors
    /// The first value outside, naming the topic, the field and the sample's time stamp.
    pub(super) fn check(
        &self,
        file: &str,
        col: usize,
        scale: f64,
        q: Quantity,
    ) -> Result<(), UlogError> {
        let (lo, hi, range) = q.range();
        match self.cols[col]
            .iter()
            .position(|v| !(lo..=hi).contains(&(v * scale)))
        {
            None => Ok(()),
            Some(i) => Err(UlogError::file(
                file,
                UlogErrorKind::BadValues(format!(
                    "{} at time stamp {} µs ({:.3} s) is outside {range}{}",
                    self.cols[col][i],
                    self.us[i],
                    self.t[i],
                    if scale == 1.0 {
                        String::new()
                    } else {
                        format!(
                            " ({:.6} in SI units: × {scale:.6})",
                            self.cols[col][i] * scale
                        )
                    }
                )),
            )
            .in_topic(&self.topic)
            .in_field(&self.fields[col])),
        }
    }

    /// [`check`](Self::check) of the first `qs.len()` columns, unscaled.
    pub(super) fn check_all(&self, file: &str, qs: &[Quantity]) -> Result<(), UlogError> {
        for (col, &q) in qs.iter().enumerate() {
            self.check(file, col, 1.0, q)?;
        }
        Ok(())
    }

    /// The longest step between samples: (its length, s; the time before it, s).
    pub(super) fn longest_gap(&self) -> Option<(f64, f64)> {
        self.t
            .windows(2)
            .map(|w| (w[1] - w[0], w[0]))
            .max_by(|a, b| a.0.total_cmp(&b.0))
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

    /// Notes the longest gap when it is longer than [`GAP_NOTE_S`], and samples sorted.
    pub(super) fn gap_note(&self, report: &mut ImportReport) {
        if let Some((g, at)) = self.longest_gap().filter(|g| g.0 > GAP_NOTE_S) {
            report.note(format!(
                "{}: a gap of {g:.1} s after {at:.1} s, interpolated across",
                self.topic
            ));
        }
        if self.out_of_order > 0 {
            report.note(format!(
                "{}: {} time stamps out of order (sorted)",
                self.topic, self.out_of_order
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
