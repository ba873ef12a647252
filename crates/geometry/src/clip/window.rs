//! The 2D clip window: an axis-aligned rectangle `xmin ≤ x ≤ xmax, ymin ≤ y ≤ ymax`, with the
//! 2D counterparts of the boundary coordinates and outcodes of clip space.
//!
//! The bits are the seed's (`clipping-and-euler-angles.txt`: LEFT 1, RIGHT 2, BELOW 4,
//! ABOVE 8; the lecture transcript writes them b3 b2 b1 b0 = above, below, right, left), and
//! the same bits as the first four planes of clip space ([`super::plane`]). A point on an
//! edge of the window is inside.

use glam::{DVec2, Vec2};

use super::plane;

/// Number of window edges (boundary coordinates, outcode bits) in 2D.
pub const EDGE_COUNT: usize = 4;

/// An axis-aligned clip window with finite bounds, `xmin < xmax` and `ymin < ymax`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window2 {
    xmin: f32,
    ymin: f32,
    xmax: f32,
    ymax: f32,
}

impl Window2 {
    /// The window `[xmin, xmax] × [ymin, ymax]`; `None` unless every bound is finite,
    /// `xmin < xmax` and `ymin < ymax`.
    ///
    /// ```
    /// use wireflight_geometry::clip::Window2;
    /// assert!(Window2::new(2.0, 2.0, 4.0, 4.0).is_some());
    /// assert!(Window2::new(4.0, 2.0, 2.0, 4.0).is_none());
    /// assert!(Window2::new(0.0, 0.0, f32::INFINITY, 1.0).is_none());
    /// ```
    pub fn new(xmin: f32, ymin: f32, xmax: f32, ymax: f32) -> Option<Self> {
        let finite = [xmin, ymin, xmax, ymax].iter().all(|v| v.is_finite());
        (finite && xmin < xmax && ymin < ymax).then_some(Self {
            xmin,
            ymin,
            xmax,
            ymax,
        })
    }

    /// The window in the seed's order (left, right, bottom, top), e.g. `(30, 220, 50, 240)`.
    pub fn from_lrbt(left: f32, right: f32, bottom: f32, top: f32) -> Option<Self> {
        Self::new(left, bottom, right, top)
    }

    /// Smallest x (the left edge).
    pub fn xmin(&self) -> f32 {
        self.xmin
    }
    /// Smallest y (the bottom edge).
    pub fn ymin(&self) -> f32 {
        self.ymin
    }
    /// Largest x (the right edge).
    pub fn xmax(&self) -> f32 {
        self.xmax
    }
    /// Largest y (the top edge).
    pub fn ymax(&self) -> f32 {
        self.ymax
    }

    /// The corners counter-clockwise from bottom-left: BL, BR, TR, TL.
    pub fn corners(&self) -> [Vec2; 4] {
        [
            Vec2::new(self.xmin, self.ymin),
            Vec2::new(self.xmax, self.ymin),
            Vec2::new(self.xmax, self.ymax),
            Vec2::new(self.xmin, self.ymax),
        ]
    }

    /// 4-bit outcode of `p`: LEFT (x < xmin), RIGHT (x > xmax), BOTTOM (y < ymin), TOP
    /// (y > ymax), the bits of [`super::plane`]. NaN coordinates give no bit: check finiteness
    /// first.
    ///
    /// ```
    /// use glam::Vec2;
    /// use wireflight_geometry::clip::{plane, Window2};
    /// // The lecture's 2..4 window: (5, 3) is right of it (0010), (1, 5) above-left (1001).
    /// let w = Window2::new(2.0, 2.0, 4.0, 4.0).unwrap();
    /// assert_eq!(w.outcode(Vec2::new(5.0, 3.0)), plane::RIGHT);
    /// assert_eq!(w.outcode(Vec2::new(1.0, 5.0)), 0b1001);
    /// assert_eq!(w.outcode(Vec2::new(4.0, 2.0)), 0); // a corner is inside
    /// ```
    #[inline]
    pub fn outcode(&self, p: Vec2) -> u8 {
        (u8::from(p.x < self.xmin) * plane::LEFT)
            | (u8::from(p.x > self.xmax) * plane::RIGHT)
            | (u8::from(p.y < self.ymin) * plane::BOTTOM)
            | (u8::from(p.y > self.ymax) * plane::TOP)
    }

    /// Whether `p` is in the window (edges included).
    #[inline]
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.xmin && p.x <= self.xmax && p.y >= self.ymin && p.y <= self.ymax
    }

    /// Boundary coordinates of a point in `f64`: `[x − xmin, xmax − x, y − ymin, ymax − y]`,
    /// each ≥ 0 exactly when the point is inside that edge (the 2D form of clip space's
    /// `w ± x`), in the order of the outcode bits. The sign of each is exact.
    #[inline]
    pub fn boundary_coords(&self, p: DVec2) -> [f64; EDGE_COUNT] {
        [
            p.x - f64::from(self.xmin),
            f64::from(self.xmax) - p.x,
            p.y - f64::from(self.ymin),
            f64::from(self.ymax) - p.y,
        ]
    }

    /// `p` moved into the window coordinate by coordinate. The clippers apply it to computed
    /// intersection points, which rounding can leave a hair outside.
    #[inline]
    pub fn clamp(&self, p: Vec2) -> Vec2 {
        Vec2::new(
            p.x.clamp(self.xmin, self.xmax),
            p.y.clamp(self.ymin, self.ymax),
        )
    }
}

/// The 2D outcome of a computed segment: both ends cast to `f32` and clamped into the window
/// (they are on the segment to within rounding, which clamping cannot make worse by more
/// than the rounding itself).
#[inline]
pub(crate) fn finish_2d(window: &Window2, p: DVec2, q: DVec2) -> (Vec2, Vec2) {
    (window.clamp(p.as_vec2()), window.clamp(q.as_vec2()))
}
