//! The `independent` model: one independent [`Process`] per axis of each channel.

use glam::DVec3;

use wireflight_data::FlightData;
use wireflight_geometry::euler::EulerZyx;

use super::process::{tilt_between, Process};
use super::{AxisError, Independent, SensorErrorTrace};

/// Three axes' generators; `first` is the stream number of the first axis.
fn three(axes: &[AxisError; 3], scale: f64, seed: u64, first: u64) -> [Process; 3] {
    [0, 1, 2].map(|i| Process::new(&axes[i], scale, seed, first + i as u64))
}

/// One step of three axes, as a vector.
fn step3(p: &mut [Process; 3], dt: f64) -> DVec3 {
    DVec3::new(p[0].step(dt), p[1].step(dt), p[2].step(dt))
}

/// The errors of every channel of `d` (whether present or not), and the attitude errors as
/// changes of the angles (roll, pitch, yaw), rad. Stream numbers: position 1–3, velocity
/// 4–6, attitude 7–9, rates 10–12, airspeed 13, accelerometer 14–16.
pub(super) fn errors(m: &Independent, d: &FlightData, seed: u64) -> (SensorErrorTrace, Vec<DVec3>) {
    let deg = 1f64.to_radians();
    let mut pos = three(&m.position, 1.0, seed, 1);
    let mut vel = three(&m.velocity, 1.0, seed, 4);
    let mut att = three(&m.attitude, deg, seed, 7);
    let mut rates = three(&m.rates, deg, seed, 10);
    let mut airspeed = Process::new(&m.airspeed, 1.0, seed, 13);
    let mut accel = three(&m.accel, 1.0, seed, 14);
    let n = d.len();
    let mut t = SensorErrorTrace {
        pos: Vec::with_capacity(n),
        vel: Vec::with_capacity(n),
        tilt: Vec::with_capacity(n),
        rates: Vec::with_capacity(n),
        airspeed: Vec::with_capacity(n),
        accel: Vec::with_capacity(n),
    };
    let mut angles = Vec::with_capacity(n);
    for k in 0..n {
        let dt = if k == 0 {
            0.0
        } else {
            d.time[k] - d.time[k - 1]
        };
        t.pos.push(step3(&mut pos, dt));
        t.vel.push(step3(&mut vel, dt));
        let e = step3(&mut att, dt);
        angles.push(e);
        // The tilt of the angle changes, about the flight's attitude (level where it has
        // none): the same error seen as a rotation, as the trace reports it.
        let a = d
            .attitude
            .as_ref()
            .and_then(|a| a.get(k))
            .copied()
            .unwrap_or_default();
        t.tilt.push(tilt_between(
            a,
            EulerZyx::new(a.yaw + e.z, a.pitch + e.y, a.roll + e.x),
        ));
        t.rates.push(step3(&mut rates, dt));
        t.airspeed.push(airspeed.step(dt));
        t.accel.push(step3(&mut accel, dt));
    }
    (t, angles)
}
