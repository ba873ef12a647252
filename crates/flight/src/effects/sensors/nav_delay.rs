//! `nav_delay`: the navigation solution (GNSS/EKF position and NED velocity) arrives
//! `delay_s` late: at time t it reads the position and velocity of t − delay.

use super::super::{effect_basics, Applies, Channel, Effect, EffectContext, EffectInfo, ParamSpec};

/// Longest delay accepted, s: a navigation solution a second late is a broken logger, and a
/// comparison window must be longer than the delay it reads back through.
pub const MAX_NAV_DELAY: f64 = 1.0;

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "nav_delay",
    summary: "position and NED velocity measured delay_s late",
    applies: Applies::Both,
    params: &[ParamSpec {
        absent: Some(0.0),
        start: Some(0.1),
        ..ParamSpec::new("delay_s", "s", (0.0, MAX_NAV_DELAY), 0.02)
    }],
    make: |_: &EffectContext| Box::new(NavDelay { delay_s: 0.1 }),
};

/// `nav_delay`: position and NED velocity read `delay_s` late.
#[derive(Clone, Debug, PartialEq)]
pub struct NavDelay {
    /// The delay, s (0 ≤ delay ≤ [`MAX_NAV_DELAY`]).
    pub delay_s: f64,
}

impl Effect for NavDelay {
    effect_basics! {
        info: INFO,
        values: delay_s,
        varies_in_time: false,
        varies_in_space: false,
    }
    fn is_measurement(&self) -> bool {
        true
    }
    fn channels(&self) -> &'static [Channel] {
        &[Channel::Position, Channel::Velocity]
    }
    fn nav_delay(&self) -> Option<f64> {
        Some(self.delay_s)
    }
}
