//! `ground_effect` (fixed wing): the induced-drag term multiplied by
//! φ = (16h/b)²/(1 + (16h/b)²), h = −down > 0 (ground at down = 0), b the span.

use super::{effect_basics, Applies, Effect, EffectContext, EffectInfo, Sample};

/// The catalogue entry.
pub static INFO: EffectInfo = EffectInfo {
    name: "ground_effect",
    summary: "induced drag × (16h/b)²/(1+(16h/b)²)",
    applies: Applies::FixedWing,
    params: &[],
    make: |ctx: &EffectContext| Box::new(GroundEffect { span: ctx.span_m }),
};

/// `ground_effect` (fixed wing): induced drag × (16h/b)²/(1 + (16h/b)²), h = −down.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundEffect {
    /// Wing span b, m (from the parameter set, not fitted).
    pub span: f64,
}

impl Effect for GroundEffect {
    effect_basics! {
        info: INFO,
        varies_in_time: false,
    }
    fn induced_drag_factor(&self, s: &Sample) -> f64 {
        if self.span.is_nan() || self.span <= 0.0 {
            return 1.0; // no wing, no ground effect (and no division by zero)
        }
        let x = 16.0 * (-s.pos_ned.z).max(0.0) / self.span;
        let x2 = x * x;
        x2 / (1.0 + x2)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::sample;
    use super::*;
    use glam::DVec3;

    #[test]
    fn factor_is_a_half_at_16h_equal_to_the_span_and_one_high_up() {
        let g = GroundEffect { span: 16.0 };
        let at = |down: f64| {
            g.induced_drag_factor(&Sample {
                pos_ned: DVec3::new(0.0, 0.0, down),
                ..sample()
            })
        };
        assert!((at(-1.0) - 0.5).abs() < 1e-15);
        assert!(at(-1000.0) > 0.9999);
        assert_eq!(at(1.0), 0.0, "below the ground: no induced drag");
    }
}
