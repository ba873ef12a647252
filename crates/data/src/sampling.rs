//! Channels at their own rates: which rows of a flight hold a sample of each channel.
//!
//! A real log's topics are sampled at their own rates (GNSS position at 5–10 Hz, attitude at
//! 50 Hz, body rates at 250 Hz) and at their own times. [`FlightData`](crate::FlightData)
//! keeps one time base — the union of the channels' sample times — and, per row and channel,
//! whether that row is a sample of the channel ([`Sampling`]). Between its samples a channel
//! is filled in (linearly; attitude along the shortest rotation; held before the first sample
//! and after the last) so that drawing and driving a model have a value at every row, but a
//! filled-in value is never a measurement: the analysis weighs and counts only sampled rows.
//!
//! A flight read from a one-rate file has every channel sampled at every row; [`Sampling`]
//! then holds nothing and costs nothing.

use glam::DQuat;

use wireflight_geometry::euler::EulerZyx;

/// A channel a flight records and the analysis scores: what a measurement effect changes,
/// and what can be sampled at its own rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Position, NED.
    Position,
    /// Velocity, NED.
    Velocity,
    /// Attitude angles.
    Attitude,
    /// Body rates.
    Rates,
    /// Airspeed.
    Airspeed,
    /// Specific force, body axes.
    Accelerometer,
}

impl Channel {
    /// Every channel, in the order of their bits in [`Sampling`].
    pub const ALL: [Channel; 6] = [
        Channel::Position,
        Channel::Velocity,
        Channel::Attitude,
        Channel::Rates,
        Channel::Airspeed,
        Channel::Accelerometer,
    ];

    /// The channel's bit in a row of [`Sampling`].
    const fn bit(self) -> u8 {
        1 << self as u8
    }

    /// Short name, as reports and the CSV's column sets say it.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Position => "position",
            Channel::Velocity => "NED velocity",
            Channel::Attitude => "attitude",
            Channel::Rates => "body rates",
            Channel::Airspeed => "airspeed",
            Channel::Accelerometer => "accelerometer",
        }
    }
}

impl std::fmt::Display for Channel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Channel::Position => "position",
            Channel::Velocity => "velocity",
            Channel::Attitude => "attitude (roll, pitch, yaw)",
            Channel::Rates => "body rates",
            Channel::Airspeed => "airspeed",
            Channel::Accelerometer => "accelerometer",
        })
    }
}

/// Which rows of a flight are samples of each [`Channel`] (see the module docs): one bit per
/// channel and row. Empty — the default — means every row of every channel is a sample.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Sampling {
    /// Per row, the bits ([`Channel::bit`]) of the channels sampled there; empty: all.
    rows: Vec<u8>,
}

impl Sampling {
    /// Every channel sampled at every row.
    pub fn all() -> Self {
        Self::default()
    }

    /// True when every row of every channel is a sample (a one-rate flight).
    pub fn is_all(&self) -> bool {
        self.rows.is_empty()
    }

    /// Rows held (0 for a one-rate flight, else the flight's length).
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True when no row is held (every row is a sample).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Whether row `i` is a sample of `channel` (true for every row of a one-rate flight and
    /// beyond the rows held).
    #[inline]
    pub fn at(&self, channel: Channel, i: usize) -> bool {
        self.rows.get(i).is_none_or(|b| b & channel.bit() != 0)
    }

    /// 1 where row `i` is a sample of `channel`, else 0: the weight of its residual.
    #[inline]
    pub fn weight(&self, channel: Channel, i: usize) -> f64 {
        f64::from(u8::from(self.at(channel, i)))
    }

    /// Whether every row is a sample of `channel`.
    pub fn is_complete(&self, channel: Channel) -> bool {
        self.rows.iter().all(|b| b & channel.bit() != 0)
    }

    /// Marks which of the flight's `n` rows are samples of `channel` (`sampled[i]`). Other
    /// channels keep theirs; a flight that was one-rate becomes per-row with every other
    /// channel sampled at every row.
    pub fn set(&mut self, channel: Channel, sampled: &[bool]) {
        if self.rows.is_empty() {
            if sampled.iter().all(|&s| s) {
                return;
            }
            self.rows = vec![u8::MAX; sampled.len()];
        }
        for (row, &s) in self.rows.iter_mut().zip(sampled) {
            if s {
                *row |= channel.bit();
            } else {
                *row &= !channel.bit();
            }
        }
        if self.rows.iter().all(|&b| b == u8::MAX) {
            self.rows.clear();
        }
    }

    /// The rows that are samples of `channel`, of `n` rows.
    pub fn rows(&self, channel: Channel, n: usize) -> impl Iterator<Item = usize> + '_ {
        (0..n).filter(move |&i| self.at(channel, i))
    }

    /// How many of `n` rows are samples of `channel`.
    pub fn count(&self, channel: Channel, n: usize) -> usize {
        if self.rows.is_empty() {
            n
        } else {
            self.rows
                .iter()
                .take(n)
                .filter(|b| *b & channel.bit() != 0)
                .count()
        }
    }

    /// Keeps the rows `keep` says (a flight cut to some of its rows keeps their bits).
    pub fn retain(&mut self, mut keep: impl FnMut(usize) -> bool) {
        if self.rows.is_empty() {
            return;
        }
        let mut i = 0;
        self.rows.retain(|_| {
            let k = keep(i);
            i += 1;
            k
        });
    }

    /// The mean rate of `channel`'s samples over `time`, Hz: samples less one over the time
    /// from the first to the last (None with fewer than two). The mean, not the median
    /// interval: a topic thinned to 20 a second alternates 40 and 60 ms.
    pub fn rate_hz(&self, channel: Channel, time: &[f64]) -> Option<f64> {
        let mut rows = self.rows(channel, time.len());
        let first = rows.next()?;
        let (count, last) = rows.fold((0usize, first), |(k, _), i| (k + 1, i));
        let span = time[last] - time[first];
        (count > 0 && span > 0.0).then(|| count as f64 / span)
    }
}

/// Fills the rows of `values` that are not samples (`sampled[i]` false) from the samples
/// around them: linearly in time between two samples, held before the first and after the
/// last. Does nothing without a sample.
pub fn fill_linear<T>(time: &[f64], sampled: &[bool], values: &mut [T])
where
    T: Copy
        + std::ops::Sub<Output = T>
        + std::ops::Add<Output = T>
        + std::ops::Mul<f64, Output = T>,
{
    fill_with(time, sampled, values, |a, b, s| a + (b - a) * s);
}

/// Fills the rows of `values` that are not samples by holding each sample over the rows
/// after it (and the first over those before it): commands, which stay as given until the
/// next.
pub fn fill_held(sampled: &[bool], values: &mut [f64]) {
    let Some(first) = sampled.iter().position(|&s| s) else {
        return;
    };
    let mut last = values[first];
    for (v, &s) in values.iter_mut().zip(sampled) {
        if s {
            last = *v;
        } else {
            *v = last;
        }
    }
}

/// [`fill_linear`] for attitude: along the shortest rotation between two samples.
pub fn fill_attitude(time: &[f64], sampled: &[bool], values: &mut [EulerZyx]) {
    fill_with(time, sampled, values, |a, b, s| {
        let qa = DQuat::from_mat3(&a.to_matrix()).normalize();
        let qb = DQuat::from_mat3(&b.to_matrix()).normalize();
        // The shorter way round: q and −q are one rotation.
        let qb = if qa.dot(qb) < 0.0 { -qb } else { qb };
        let q = qa.lerp(qb, s).normalize();
        let slerped = if qa.dot(qb) > 0.9995 {
            q
        } else {
            qa.slerp(qb, s)
        };
        EulerZyx::from_matrix(glam::DMat3::from_quat(slerped)).0
    });
}

/// Fills with `between(a, b, s)` for a row a fraction `s` of the way from sample a to b.
fn fill_with<T: Copy>(
    time: &[f64],
    sampled: &[bool],
    values: &mut [T],
    between: impl Fn(T, T, f64) -> T,
) {
    let n = values.len().min(time.len()).min(sampled.len());
    let Some(first) = (0..n).find(|&i| sampled[i]) else {
        return;
    };
    let mut prev = first;
    for i in 0..first {
        values[i] = values[first];
    }
    for i in first + 1..n {
        if !sampled[i] {
            continue;
        }
        let (t0, t1) = (time[prev], time[i]);
        for j in prev + 1..i {
            let s = if t1 > t0 {
                (time[j] - t0) / (t1 - t0)
            } else {
                0.0
            };
            values[j] = between(values[prev], values[i], s);
        }
        prev = i;
    }
    for j in prev + 1..n {
        values[j] = values[prev];
    }
}

impl crate::FlightData {
    /// Keeps only the rows `sampled` says as samples of `channel` (one flag per row), and
    /// fills its other rows in from them as a reader would (module docs): what a log with
    /// the channel at its own rate holds. Does nothing for a channel the flight lacks, or a
    /// `sampled` of the wrong length or without a sample.
    pub fn keep_samples(&mut self, channel: Channel, sampled: &[bool]) {
        let n = self.len();
        if sampled.len() != n || !sampled.contains(&true) {
            return;
        }
        let time = &self.time;
        let present = match channel {
            Channel::Position => {
                fill_linear(time, sampled, &mut self.pos_ned);
                true
            }
            Channel::Velocity => self
                .vel_ned
                .as_mut()
                .map(|v| fill_linear(time, sampled, v))
                .is_some(),
            Channel::Attitude => self
                .attitude
                .as_mut()
                .map(|a| fill_attitude(time, sampled, a))
                .is_some(),
            Channel::Rates => self
                .rates_body
                .as_mut()
                .map(|v| fill_linear(time, sampled, v))
                .is_some(),
            Channel::Airspeed => self
                .airspeed
                .as_mut()
                .map(|v| fill_linear(time, sampled, v))
                .is_some(),
            Channel::Accelerometer => self
                .accel_body
                .as_mut()
                .map(|v| fill_linear(time, sampled, v))
                .is_some(),
        };
        if present {
            self.sampling.set(channel, sampled);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_rate_holds_nothing_and_every_row_is_a_sample() {
        let s = Sampling::all();
        assert!(s.is_all() && s.at(Channel::Position, 7));
        assert_eq!(s.count(Channel::Rates, 5), 5);
        let mut s = Sampling::all();
        s.set(Channel::Position, &[true, true, true]);
        assert!(s.is_all(), "a full mask keeps the flight one-rate");
    }

    #[test]
    fn each_channel_keeps_its_own_rows() {
        let mut s = Sampling::all();
        s.set(Channel::Position, &[true, false, false, true, false]);
        s.set(Channel::Rates, &[false, true, true, true, true]);
        assert_eq!(s.len(), 5);
        assert_eq!(s.rows(Channel::Position, 5).collect::<Vec<_>>(), [0, 3]);
        assert_eq!(s.rows(Channel::Rates, 5).collect::<Vec<_>>(), [1, 2, 3, 4]);
        assert_eq!(s.count(Channel::Attitude, 5), 5);
        assert!(s.is_complete(Channel::Attitude) && !s.is_complete(Channel::Position));
        assert_eq!(s.weight(Channel::Position, 1), 0.0);
        assert_eq!(s.weight(Channel::Position, 3), 1.0);
        let t = [0.0, 0.1, 0.2, 0.3, 0.4];
        assert!((s.rate_hz(Channel::Rates, &t).unwrap() - 10.0).abs() < 1e-9);
        assert!(s.rate_hz(Channel::Position, &t).is_some());
        s.retain(|i| i != 0);
        assert_eq!(s.rows(Channel::Position, 4).collect::<Vec<_>>(), [2]);
        // Every channel at every row again: one-rate.
        s.set(Channel::Position, &[true; 4]);
        s.set(Channel::Rates, &[true; 4]);
        assert!(s.is_all());
    }

    #[test]
    fn filling_is_linear_between_samples_and_held_at_the_ends() {
        let t = [0.0, 1.0, 2.0, 4.0, 5.0];
        let sampled = [false, true, false, true, false];
        let mut v = [9.0, 1.0, 9.0, 4.0, 9.0];
        fill_linear(&t, &sampled, &mut v);
        assert_eq!(v, [1.0, 1.0, 2.0, 4.0, 4.0]);
        let mut none = [1.0, 2.0];
        fill_linear(&t[..2], &[false, false], &mut none);
        assert_eq!(none, [1.0, 2.0]);
    }

    #[test]
    fn attitude_is_filled_the_short_way_round() {
        let t = [0.0, 1.0, 2.0];
        let mut a = [
            EulerZyx::from_degrees(170.0, 0.0, 0.0),
            EulerZyx::default(),
            EulerZyx::from_degrees(-170.0, 0.0, 0.0),
        ];
        fill_attitude(&t, &[true, false, true], &mut a);
        assert!(
            (a[1].yaw.abs() - std::f64::consts::PI).abs() < 1e-9,
            "{:?}",
            a[1]
        );
    }
}
