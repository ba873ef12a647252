//! One error axis as a generator (Gauss–Markov + white + random walk, see the module
//! documentation of [`super`]), and the attitude helpers the models share.

use std::f64::consts::{PI, TAU};

use glam::{DMat3, DQuat, DVec3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use wireflight_geometry::euler::EulerZyx;

use super::AxisError;

/// First ChaCha8 stream of the sensor errors ("SENS" in ASCII, shifted up). Each axis draws from
/// stream `STREAM_BASE + its number`, never stream 0, which the simulation's white noise and
/// the turbulence use with their seeds: the errors are independent of both.
const STREAM_BASE: u64 = 0x5345_4E53 << 16;

/// A time step as the generators use it: a step that is not a positive finite number (times
/// that do not increase, or are not numbers) is 0 s, so that nothing wanders across it.
pub(super) fn clean_dt(dt: f64) -> f64 {
    if dt.is_finite() && dt > 0.0 {
        dt
    } else {
        0.0
    }
}

/// The random stream of axis number `axis` of the flight seeded `seed`.
pub(super) fn stream(seed: u64, axis: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(STREAM_BASE + axis);
    rng
}

/// One axis's error as it is drawn, sample by sample. It always draws three numbers a
/// sample (the Gauss–Markov, walk and white increments), whichever parts are zero, so that
/// the draws of one part do not depend on the others' parameters.
pub(super) struct Process {
    size: f64,
    tau_s: f64,
    white: f64,
    walk: f64,
    gm: f64,
    bias: f64,
    rng: ChaCha8Rng,
}

impl Process {
    /// The generator of `spec` (its numbers times `scale`, e.g. degrees to radians) on its own
    /// stream `axis` of `seed`; the Gauss–Markov part starts from a draw of its stationary
    /// distribution, the walk at 0.
    pub(super) fn new(spec: &AxisError, scale: f64, seed: u64, axis: u64) -> Self {
        let mut rng = stream(seed, axis);
        let tau_s = spec.tau_s.unwrap_or(0.0);
        // A Gauss–Markov part needs a time constant; the parser guarantees one when size > 0.
        let size = if tau_s > 0.0 { spec.size * scale } else { 0.0 };
        let gm = size * normal(&mut rng);
        Self {
            size,
            tau_s,
            white: spec.white * scale,
            walk: spec.walk * scale,
            gm,
            bias: 0.0,
            rng,
        }
    }

    /// Advance by `dt` (0 for the first sample) and return the error at the new sample.
    pub(super) fn step(&mut self, dt: f64) -> f64 {
        let dt = clean_dt(dt);
        let [n_gm, n_walk, n_white] = [(); 3].map(|()| normal(&mut self.rng));
        if self.size > 0.0 && dt > 0.0 {
            let phi = (-dt / self.tau_s).exp();
            // √(1 − φ²) through expm1, exact for steps far below τ too.
            let q = (-(-2.0 * dt / self.tau_s).exp_m1()).sqrt();
            self.gm = phi * self.gm + self.size * q * n_gm;
        }
        self.bias += self.walk * dt.sqrt() * n_walk;
        self.gm + self.bias + self.white * n_white
    }
}

/// One standard normal draw.
pub(super) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

/// `angle` moved by whole turns to within half a turn of `reference`: an error of a fraction of
/// a degree must not turn a yaw of 370° into 10°.
fn near(angle: f64, reference: f64) -> f64 {
    let d = angle - reference;
    if d.is_finite() && d.abs() > PI {
        angle - TAU * (d / TAU).round()
    } else {
        angle
    }
}

/// `a` rotated by the small rotation vector `tilt` (NED) on the left: R' = Exp(tilt)·R, as
/// z-y-x angles kept near the original ones (no jump of a turn in yaw or roll).
pub(super) fn rotate_attitude(a: EulerZyx, tilt: DVec3) -> EulerZyx {
    let r = DMat3::from_quat(DQuat::from_scaled_axis(tilt)) * a.to_matrix();
    let b = EulerZyx::from_matrix(r).0;
    if !(b.yaw.is_finite() && b.pitch.is_finite() && b.roll.is_finite()) {
        return a;
    }
    EulerZyx::new(near(b.yaw, a.yaw), b.pitch, near(b.roll, a.roll))
}

/// The rotation vector (NED) of the change from angles `a` to angles `b`: Exp(v)·R(a) = R(b).
pub(super) fn tilt_between(a: EulerZyx, b: EulerZyx) -> DVec3 {
    let r = b.to_matrix() * a.to_matrix().transpose();
    let q = DQuat::from_mat3(&r).normalize();
    // q and −q are the same rotation; the one with w ≥ 0 has the angle within ±π.
    let v = if q.w < 0.0 { -q } else { q }.to_scaled_axis();
    if v.is_finite() {
        v
    } else {
        DVec3::ZERO
    }
}

/// The body→NED matrix of `a`, or the identity (level, heading north) where `a` is absent or
/// not finite.
pub(super) fn attitude_matrix(a: Option<&EulerZyx>) -> DMat3 {
    a.map(|a| a.to_matrix())
        .filter(DMat3::is_finite)
        .unwrap_or(DMat3::IDENTITY)
}
