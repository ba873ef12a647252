//! The kinematic flight of the fly-through window: the aircraft flies along its nose at a speed
//! set by the throttle, and turns at the body rates the pilot commands. No aerodynamics.
//!
//! The attitude is integrated as a unit quaternion (body → world, viewer frame Z up):
//! `q ← q · exp(½ ω dt)` with ω the body rates, renormalised every step. Angles are never
//! integrated, so flying through pitch ±90° (a loop, a vertical climb) is smooth; the z-y-x
//! angles shown are read back from the matrix with [`EulerZyx::from_matrix`], which reports
//! gimbal lock there.
//!
//! Pure math: no I/O.

use glam::{DMat3, DQuat, DVec3};

use wireflight_geometry::euler::{EulerZyx, Gimbal};

/// Slowest speed (throttle 0), m/s.
pub const MIN_SPEED: f64 = 20.0;
/// Fastest speed (throttle 1), m/s.
pub const MAX_SPEED: f64 = 90.0;
/// Time constant of the speed following the throttle, s.
pub const SPEED_TAU: f64 = 2.0;
/// Lowest height of the body origin above the ground (z = 0), m: the aircraft skims the ground
/// instead of going through it.
pub const GROUND_CLEARANCE: f64 = 1.5;
/// Largest body rate accepted, degrees per second.
pub const MAX_RATE_DPS: f64 = 720.0;

/// What the pilot commands, in pilot terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controls {
    /// Throttle, 0..=1.
    pub throttle: f64,
    /// Pitch rate, degrees/s; positive raises the nose.
    pub pitch_rate_dps: f64,
    /// Roll rate, degrees/s; positive rolls right (right wing down).
    pub roll_rate_dps: f64,
    /// Yaw rate, degrees/s; positive turns the nose right.
    pub yaw_rate_dps: f64,
}

impl Default for Controls {
    fn default() -> Self {
        Self {
            throttle: 0.5,
            pitch_rate_dps: 0.0,
            roll_rate_dps: 0.0,
            yaw_rate_dps: 0.0,
        }
    }
}

impl Controls {
    /// The same controls with every value forced into its valid range (NaN becomes 0).
    pub fn sanitized(self) -> Self {
        let rate = |r: f64| {
            if r.is_finite() {
                r.clamp(-MAX_RATE_DPS, MAX_RATE_DPS)
            } else {
                0.0
            }
        };
        Self {
            throttle: if self.throttle.is_finite() {
                self.throttle.clamp(0.0, 1.0)
            } else {
                0.0
            },
            pitch_rate_dps: rate(self.pitch_rate_dps),
            roll_rate_dps: rate(self.roll_rate_dps),
            yaw_rate_dps: rate(self.yaw_rate_dps),
        }
    }

    /// Body angular velocity in rad/s about the body axes (nose +X, left wing +Y, up +Z).
    ///
    /// Right-hand rotations about those axes: +X drops the right wing (roll right), +Y lowers
    /// the nose, +Z turns it left; so pitch-up and nose-right are negative about Y and Z.
    pub fn body_rates(&self) -> DVec3 {
        DVec3::new(
            self.roll_rate_dps.to_radians(),
            -self.pitch_rate_dps.to_radians(),
            -self.yaw_rate_dps.to_radians(),
        )
    }
}

/// Where a flight starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    /// Position, world (viewer frame), m.
    pub position: DVec3,
    /// Attitude.
    pub attitude: EulerZyx,
    /// Speed, m/s.
    pub speed: f64,
    /// Throttle, 0..=1.
    pub throttle: f64,
}

impl Default for Start {
    /// 1.5 km south of the runway's middle, 150 m up, heading north along it.
    fn default() -> Self {
        Self {
            position: DVec3::new(-1500.0, 0.0, 150.0),
            attitude: EulerZyx::default(),
            speed: 45.0,
            throttle: 0.5,
        }
    }
}

/// State of the kinematic aircraft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematic {
    /// Body origin, world (viewer frame), m.
    pub position: DVec3,
    /// Body → world rotation, unit quaternion.
    pub orientation: DQuat,
    /// Speed along the nose, m/s.
    pub speed: f64,
    /// Current controls (sanitised).
    pub controls: Controls,
    /// Flight time, s.
    pub time: f64,
}

impl Kinematic {
    /// A flight at its start.
    pub fn new(start: &Start) -> Self {
        let orientation = DQuat::from_mat3(&start.attitude.to_matrix()).normalize();
        Self {
            position: start.position,
            orientation,
            speed: start.speed.clamp(MIN_SPEED, MAX_SPEED),
            controls: Controls {
                throttle: start.throttle,
                ..Controls::default()
            }
            .sanitized(),
            time: 0.0,
        }
    }

    /// Advance by `dt` seconds with the given controls (`dt ≤ 0` or non-finite does nothing
    /// but take the controls).
    pub fn step(&mut self, controls: Controls, dt: f64) {
        self.controls = controls.sanitized();
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        // Rotation: body rates compose on the right (they are about the body axes).
        let turn = DQuat::from_scaled_axis(self.controls.body_rates() * dt);
        self.orientation = (self.orientation * turn).normalize();
        // Speed follows the throttle with a first-order lag (exact for constant throttle).
        let target = MIN_SPEED + self.controls.throttle * (MAX_SPEED - MIN_SPEED);
        self.speed += (target - self.speed) * (1.0 - (-dt / SPEED_TAU).exp());
        self.position += self.velocity() * dt;
        if self.position.z < GROUND_CLEARANCE {
            self.position.z = GROUND_CLEARANCE;
        }
        self.time += dt;
    }

    /// Body → world rotation matrix.
    pub fn matrix(&self) -> DMat3 {
        DMat3::from_quat(self.orientation)
    }

    /// The nose direction, world.
    pub fn nose(&self) -> DVec3 {
        self.orientation * DVec3::X
    }

    /// Velocity, world, m/s.
    pub fn velocity(&self) -> DVec3 {
        self.nose() * self.speed
    }

    /// z-y-x angles of the attitude, read back from the matrix, with the gimbal state.
    pub fn attitude(&self) -> (EulerZyx, Gimbal) {
        EulerZyx::from_matrix(self.matrix())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level() -> Kinematic {
        Kinematic::new(&Start {
            position: DVec3::new(0.0, 0.0, 1000.0),
            speed: 0.5 * (MIN_SPEED + MAX_SPEED), // steady at throttle 0.5
            ..Start::default()
        })
    }

    #[test]
    fn a_loop_passes_through_the_vertical_and_comes_back_level() {
        let mut k = level();
        let dt = 1.0 / 64.0;
        let pull = Controls {
            pitch_rate_dps: 45.0,
            ..Controls::default()
        };
        // A quarter loop: 2 s at 45°/s puts the nose straight up (z-y-x pitch −90° in the
        // Z-up viewer frame, where positive pitch lowers the nose) — gimbal lock.
        for _ in 0..128 {
            k.step(pull, dt);
        }
        assert!(k.nose().abs_diff_eq(DVec3::Z, 1e-9), "{}", k.nose());
        let (angles, gimbal) = k.attitude();
        assert_eq!(gimbal, Gimbal::LockedNoseUp);
        assert!((angles.pitch.to_degrees() + 90.0).abs() < 1e-6);
        assert!(angles.to_matrix().abs_diff_eq(k.matrix(), 1e-9));
        // Past the vertical: on its back, heading south, angles free again and finite.
        for _ in 0..64 {
            k.step(pull, dt);
            assert!(k.orientation.is_finite());
        }
        let (angles, gimbal) = k.attitude();
        assert_eq!(gimbal, Gimbal::Free);
        assert!(
            (angles.yaw.abs().to_degrees() - 180.0).abs() < 1e-6,
            "{angles:?}"
        );
        assert!(
            (angles.roll.abs().to_degrees() - 180.0).abs() < 1e-6,
            "{angles:?}"
        );
        // The rest of the loop: level again, heading north, near where it started in x.
        for _ in 0..320 {
            k.step(pull, dt);
        }
        assert!(k.nose().abs_diff_eq(DVec3::X, 1e-9), "{}", k.nose());
        assert!((k.orientation.length() - 1.0).abs() < 1e-12);
        assert!((k.position.z - 1000.0).abs() < 1.0, "{}", k.position);
    }

    #[test]
    fn pilot_senses_of_the_controls() {
        let dt = 0.01;
        let mut k = level();
        k.step(
            Controls {
                yaw_rate_dps: 30.0,
                ..Controls::default()
            },
            dt,
        );
        assert!(
            k.nose().y < 0.0,
            "nose right is towards −Y (Y is west/left)"
        );
        let mut k = level();
        k.step(
            Controls {
                roll_rate_dps: 30.0,
                ..Controls::default()
            },
            dt,
        );
        let right_wing = k.orientation * -DVec3::Y;
        assert!(right_wing.z < 0.0, "roll right drops the right wing");
        assert!(k.attitude().0.roll > 0.0, "and is positive z-y-x roll");
        let mut k = level();
        k.step(
            Controls {
                pitch_rate_dps: 30.0,
                ..Controls::default()
            },
            dt,
        );
        assert!(k.nose().z > 0.0 && k.attitude().0.pitch < 0.0);
    }

    #[test]
    fn speed_follows_the_throttle_and_the_ground_stops_a_dive() {
        let mut k = level();
        let full = Controls {
            throttle: 1.0,
            ..Controls::default()
        };
        for _ in 0..2000 {
            k.step(full, 0.01);
        }
        assert!((k.speed - MAX_SPEED).abs() < 0.1, "{}", k.speed);
        let dive = Controls {
            pitch_rate_dps: -90.0,
            ..full
        };
        for _ in 0..100 {
            k.step(dive, 0.01); // nose straight down after 1 s
        }
        for _ in 0..3000 {
            k.step(Controls::default(), 0.01);
        }
        assert_eq!(k.position.z, GROUND_CLEARANCE);
    }

    #[test]
    fn bad_inputs_are_tamed() {
        let mut k = level();
        k.step(
            Controls {
                throttle: f64::NAN,
                pitch_rate_dps: f64::INFINITY,
                roll_rate_dps: 1e9,
                yaw_rate_dps: -1e9,
            },
            0.01,
        );
        assert!(k.orientation.is_finite() && k.position.is_finite());
        assert_eq!(k.controls.throttle, 0.0);
        assert_eq!(k.controls.roll_rate_dps, MAX_RATE_DPS);
        let before = k;
        k.step(Controls::default(), f64::NAN);
        assert_eq!(k.position, before.position);
    }
}
