//! The comparison's residual rows: what each sample of a flight contributes to the misfit,
//! weighted by the measured noise, and how those rows move when the predictions drift.

use super::attitude::attitude_residuals;
use super::predict::Predicted;
use super::{AxisSums, Prepared, LAG_FAR, MAX_ROWS};
use wireflight_data::Channel;
use wireflight_flight::model::Model;

impl Prepared<'_> {
    /// Append the weighted residual rows of sample `i` for prediction `p`.
    ///
    /// The layout is the same at every sample ([`Self::residual_layout`]); a row that is not a
    /// sample of a channel ([`wireflight_data::Sampling`]) has zeros for it: a value filled
    /// in between samples is not a measurement.
    pub(crate) fn residual_rows(&self, model: &Model, i: usize, p: &Predicted, out: &mut Vec<f64>) {
        let d = self.data;
        let m = self.measured.for_vehicle(model);
        let on = |channel: Channel| d.sampling.weight(channel, i);
        let [wp, wv, wa, wr] = &self.weights;
        let e = (p.pos_ned - d.pos_ned[i]) * on(Channel::Position);
        out.extend([e.x * wp[0], e.y * wp[1], e.z * wp[2]]);
        if let (true, Some(v)) = (m.velocity, &d.vel_ned) {
            let e = (p.vel_ned - v[i]) * on(Channel::Velocity);
            out.extend([e.x * wv[0], e.y * wv[1], e.z * wv[2]]);
        }
        if let (true, Some(a)) = (m.attitude, &d.attitude) {
            let e = attitude_residuals(p, &a[i], self.attitude_trig.get(i));
            let w = on(Channel::Attitude);
            out.extend([e[0] * wa[0] * w, e[1] * wa[1] * w, e[2] * wa[2] * w]);
        }
        if let (true, Some(w)) = (m.rates, &d.rates_body) {
            let e = (p.rates - w[i]) * on(Channel::Rates);
            out.extend([e.x * wr[0], e.y * wr[1], e.z * wr[2]]);
        }
        if let (true, Some(s)) = (m.airspeed, &d.airspeed) {
            out.push((p.airspeed() - s[i]) * self.airspeed_weight * on(Channel::Airspeed));
        }
        if let (true, Some(a)) = (m.accel, &d.accel_body) {
            let e = (p.specific_force - a[i]) * on(Channel::Accelerometer);
            let w = &self.accel_weights;
            out.extend([e.x * w[0], e.y * w[1], e.z * w[2]]);
        }
    }

    /// The channel of each residual row of a sample, in [`Self::residual_rows`]' order.
    pub(crate) fn residual_layout(&self, model: &Model) -> Vec<Channel> {
        let d = self.data;
        let m = self.measured.for_vehicle(model);
        let mut layout = vec![Channel::Position; 3];
        for (on, channel, axes) in [
            (m.velocity && d.vel_ned.is_some(), Channel::Velocity, 3),
            (m.attitude && d.attitude.is_some(), Channel::Attitude, 3),
            (m.rates && d.rates_body.is_some(), Channel::Rates, 3),
            (m.airspeed && d.airspeed.is_some(), Channel::Airspeed, 1),
            (m.accel && d.accel_body.is_some(), Channel::Accelerometer, 3),
        ] {
            if on {
                layout.extend(std::iter::repeat_n(channel, axes));
            }
        }
        layout
    }

    /// Of the residual rows `rows` of `window` ([`Self::residual_rows`] per sample): how
    /// many are measurements, Σ r_k·r_k+1 over consecutive samples of each residual channel
    /// (consecutive samples of the channel, where it has its own rate), and the sums of
    /// each row of a sample on its own ([`AxisSums`]).
    pub(crate) fn measured_rows(
        &self,
        model: &Model,
        (start, end): (usize, usize),
        rows: &[f64],
    ) -> (usize, f64, AxisSums) {
        let per_sample = rows.len() / (end - start).max(1);
        let sampling = &self.data.sampling;
        let mut axes = AxisSums::default();
        if per_sample == 0 {
            return (rows.len(), 0.0, axes);
        }
        let all = sampling.is_all();
        let layout = if all {
            Vec::new()
        } else {
            self.residual_layout(model)
        };
        let mut count = 0;
        for j in 0..per_sample {
            let channel = layout.get(j).copied();
            let mut previous: Option<f64> = None;
            // The row's last LAG_FAR own samples (a ring), for the longer lag.
            let mut recent = [0.0; LAG_FAR];
            let (mut chi2, mut lag1, mut lag_far, mut sum, mut seen) = (0.0, 0.0, 0.0, 0.0, 0usize);
            for (k, i) in (start..end).enumerate() {
                if let Some(c) = channel {
                    if !sampling.at(c, i) {
                        continue;
                    }
                }
                let Some(&r) = rows.get(k * per_sample + j) else {
                    break;
                };
                count += 1;
                chi2 += r * r;
                sum += r;
                if let Some(p) = previous {
                    lag1 += p * r;
                }
                previous = Some(r);
                let slot = seen % LAG_FAR;
                if seen >= LAG_FAR {
                    lag_far += recent[slot] * r;
                }
                recent[slot] = r;
                seen += 1;
            }
            if j < MAX_ROWS {
                axes.chi2[j] = chi2;
                axes.lag1[j] = lag1;
                axes.lag_far[j] = lag_far;
                axes.sum[j] = sum;
                axes.count[j] = seen as f64;
            }
        }
        let lag1 = axes.lag1.iter().sum();
        if all {
            count = rows.len();
        }
        (count, lag1, axes)
    }

    /// The change of the residual rows over `span` (laid out as `out`, [`Self::residual_rows`]
    /// per sample) when every predicted position drifts along NED `axis` by the time since
    /// the span's start and every predicted NED velocity by one along it: the read-out of a
    /// frame moving at unit speed (the air, the attitude, the rates and the accelerometer do
    /// not change). False when `out` is not the span's rows.
    pub(crate) fn drift_rows(
        &self,
        model: &Model,
        (start, end): (usize, usize),
        axis: usize,
        out: &mut [f64],
    ) -> bool {
        let d = self.data;
        let m = self.measured.for_vehicle(model);
        let velocity = m.velocity && d.vel_ned.is_some();
        let count = 3
            + 3 * [
                velocity,
                m.attitude && d.attitude.is_some(),
                m.rates && d.rates_body.is_some(),
            ]
            .iter()
            .filter(|&&b| b)
            .count()
            + usize::from(m.airspeed && d.airspeed.is_some())
            + 3 * usize::from(m.accel && d.accel_body.is_some());
        let samples = end.saturating_sub(start);
        if axis > 2 || samples == 0 || out.len() != count * samples {
            return false;
        }
        let [wp, wv, _, _] = &self.weights;
        let t0 = d.time[start];
        out.fill(0.0);
        let on = |channel: Channel, i: usize| d.sampling.weight(channel, i);
        for (rows, i) in out.chunks_exact_mut(count).zip(start..end) {
            rows[axis] = wp[axis] * (d.time[i] - t0) * on(Channel::Position, i);
            if velocity {
                rows[3 + axis] = wv[axis] * on(Channel::Velocity, i);
            }
        }
        true
    }
}
