//! The comparison's residual rows: what each sample of a flight contributes to the misfit,
//! weighted by the measured noise, and how those rows move when the predictions drift.

use super::attitude::attitude_residuals;
use super::predict::Predicted;
use super::Prepared;
use wireflight_flight::model::Model;

impl Prepared<'_> {
    /// Append the weighted residual rows of sample `i` for prediction `p`.
    pub(crate) fn residual_rows(&self, model: &Model, i: usize, p: &Predicted, out: &mut Vec<f64>) {
        let d = self.data;
        let m = self.measured.for_vehicle(model);
        let [wp, wv, wa, wr] = &self.weights;
        let e = p.pos_ned - d.pos_ned[i];
        out.extend([e.x * wp[0], e.y * wp[1], e.z * wp[2]]);
        if let (true, Some(v)) = (m.velocity, &d.vel_ned) {
            let e = p.vel_ned - v[i];
            out.extend([e.x * wv[0], e.y * wv[1], e.z * wv[2]]);
        }
        if let (true, Some(a)) = (m.attitude, &d.attitude) {
            let e = attitude_residuals(p, &a[i], self.attitude_trig.get(i));
            out.extend([e[0] * wa[0], e[1] * wa[1], e[2] * wa[2]]);
        }
        if let (true, Some(w)) = (m.rates, &d.rates_body) {
            let e = p.rates - w[i];
            out.extend([e.x * wr[0], e.y * wr[1], e.z * wr[2]]);
        }
        if let (true, Some(s)) = (m.airspeed, &d.airspeed) {
            out.push((p.airspeed() - s[i]) * self.airspeed_weight);
        }
        if let (true, Some(a)) = (m.accel, &d.accel_body) {
            let e = p.specific_force - a[i];
            let w = &self.accel_weights;
            out.extend([e.x * w[0], e.y * w[1], e.z * w[2]]);
        }
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
        for (rows, i) in out.chunks_exact_mut(count).zip(start..end) {
            rows[axis] = wp[axis] * (d.time[i] - t0);
            if velocity {
                rows[3 + axis] = wv[axis];
            }
        }
        true
    }
}
