//! Nicholl-Lee-Nicholl (1987; seed `line-clipping-cs-cyrus-beck-nln.txt`): classify the first
//! endpoint P₀ into one of the nine regions (as Cohen-Sutherland does), cast rays from P₀
//! through the window's corners, and find from the region of P₁ *between the rays* exactly
//! which edges the segment enters and leaves through, so that every intersection computed is
//! one that is kept. A drop is decided by comparisons alone. 2D only: the rays through the
//! corners of a rectangle have no counterpart in the 3D/homogeneous volume.
//!
//! By symmetry only three positions of P₀ need code: inside, in the left edge region, in the
//! bottom-left corner region. The other six are mapped onto those by swapping x and y and
//! negating coordinates (exact in floating point) and the result mapped back.
//!
//! "Between the rays" is a sign of a cross product: P₁ is counter-clockwise of the ray
//! P₀→Q when `(Q − P₀) × (P₁ − P₀) > 0`. For P₀ in the corner region NLN distinguishes two
//! sub-cases (P₀ above or below the window's diagonal) to save a comparison; here the entry
//! edge is decided by the ray through the near corner and the exit edge by the ray through
//! the far corner, which covers both sub-cases with one more comparison.

use glam::{DVec2, Vec2};

use super::{plane, ClipOutcome, ClipOutcome2, Window2};

/// A symmetry of the plane mapping the window onto itself up to its bounds: swap x and y,
/// then negate x and/or y.
#[derive(Clone, Copy)]
struct Frame {
    swap: bool,
    flip_x: bool,
    flip_y: bool,
}

impl Frame {
    fn to(self, p: DVec2) -> DVec2 {
        let p = if self.swap { DVec2::new(p.y, p.x) } else { p };
        DVec2::new(
            if self.flip_x { -p.x } else { p.x },
            if self.flip_y { -p.y } else { p.y },
        )
    }

    fn back(self, p: DVec2) -> DVec2 {
        let p = DVec2::new(
            if self.flip_x { -p.x } else { p.x },
            if self.flip_y { -p.y } else { p.y },
        );
        if self.swap {
            DVec2::new(p.y, p.x)
        } else {
            p
        }
    }

    /// The frame taking P₀'s region to inside, left edge or bottom-left corner.
    fn for_code(code: u8) -> Frame {
        let f = |swap, flip_x, flip_y| Frame {
            swap,
            flip_x,
            flip_y,
        };
        const L: u8 = plane::LEFT;
        const R: u8 = plane::RIGHT;
        const B: u8 = plane::BOTTOM;
        const T: u8 = plane::TOP;
        match code {
            R => f(false, true, false),
            B => f(true, false, false),
            T => f(true, true, false),
            c if c == R | B => f(false, true, false),
            c if c == L | T => f(false, false, true),
            c if c == R | T => f(false, true, true),
            _ => f(false, false, false), // inside, LEFT, LEFT|BOTTOM
        }
    }
}

/// The window's bounds in a frame: (L, R, B, T) as `f64`.
#[derive(Clone, Copy)]
struct Bounds {
    l: f64,
    r: f64,
    b: f64,
    t: f64,
}

impl Bounds {
    fn of(window: &Window2, frame: Frame) -> Self {
        let p = frame.to(DVec2::new(
            f64::from(window.xmin()),
            f64::from(window.ymin()),
        ));
        let q = frame.to(DVec2::new(
            f64::from(window.xmax()),
            f64::from(window.ymax()),
        ));
        Self {
            l: p.x.min(q.x),
            r: p.x.max(q.x),
            b: p.y.min(q.y),
            t: p.y.max(q.y),
        }
    }

    fn inside(&self, p: DVec2) -> bool {
        p.x >= self.l && p.x <= self.r && p.y >= self.b && p.y <= self.t
    }

    fn code(&self, p: DVec2) -> u8 {
        (u8::from(p.x < self.l) * plane::LEFT)
            | (u8::from(p.x > self.r) * plane::RIGHT)
            | (u8::from(p.y < self.b) * plane::BOTTOM)
            | (u8::from(p.y > self.t) * plane::TOP)
    }
}

/// `(q − p0) × (p1 − p0)`: > 0 when p1 is counter-clockwise of the ray p0→q.
fn turn(p0: DVec2, q: DVec2, p1: DVec2) -> f64 {
    (q - p0).perp_dot(p1 - p0)
}

/// Where the segment meets the edge x = `x` (dx ≠ 0).
fn at_x(p0: DVec2, d: DVec2, x: f64) -> DVec2 {
    DVec2::new(x, p0.y + d.y * (x - p0.x) / d.x)
}

/// Where the segment meets the edge y = `y` (dy ≠ 0).
fn at_y(p0: DVec2, d: DVec2, y: f64) -> DVec2 {
    DVec2::new(p0.x + d.x * (y - p0.y) / d.y, y)
}

enum Canonical {
    Reject,
    Accept,
    /// The visible part; `None` for an end that is the original endpoint.
    Segment(Option<DVec2>, Option<DVec2>),
}

/// P₀ inside: P₁ inside is accepted; else one exit, chosen by P₁'s region and, in a corner
/// region, by the ray through that corner.
fn from_inside(w: &Bounds, p0: DVec2, p1: DVec2) -> Canonical {
    let code = w.code(p1);
    if code == 0 {
        return Canonical::Accept;
    }
    let d = p1 - p0;
    let (tl, tr) = (DVec2::new(w.l, w.t), DVec2::new(w.r, w.t));
    let (bl, br) = (DVec2::new(w.l, w.b), DVec2::new(w.r, w.b));
    const L: u8 = plane::LEFT;
    const R: u8 = plane::RIGHT;
    const B: u8 = plane::BOTTOM;
    const T: u8 = plane::TOP;
    let exit_left = || at_x(p0, d, w.l);
    let exit_right = || at_x(p0, d, w.r);
    let exit_bottom = || at_y(p0, d, w.b);
    let exit_top = || at_y(p0, d, w.t);
    let exit = match code {
        L => exit_left(),
        R => exit_right(),
        B => exit_bottom(),
        T => exit_top(),
        c if c == L | T => {
            if turn(p0, tl, p1) > 0.0 {
                exit_left()
            } else {
                exit_top()
            }
        }
        c if c == R | T => {
            if turn(p0, tr, p1) > 0.0 {
                exit_top()
            } else {
                exit_right()
            }
        }
        c if c == L | B => {
            if turn(p0, bl, p1) > 0.0 {
                exit_bottom()
            } else {
                exit_left()
            }
        }
        _ => {
            if turn(p0, br, p1) > 0.0 {
                exit_right()
            } else {
                exit_bottom()
            }
        }
    };
    Canonical::Segment(None, Some(exit))
}

/// The exit of a segment that has entered and whose P₁ is outside: top, right or bottom,
/// by the rays through TR and BR (P₀ is left of the window).
fn exit_from_left(w: &Bounds, p0: DVec2, p1: DVec2) -> DVec2 {
    let d = p1 - p0;
    if turn(p0, DVec2::new(w.r, w.t), p1) > 0.0 {
        at_y(p0, d, w.t)
    } else if turn(p0, DVec2::new(w.r, w.b), p1) < 0.0 {
        at_y(p0, d, w.b)
    } else {
        at_x(p0, d, w.r)
    }
}

/// P₀ in the left edge region (x₀ < L, B ≤ y₀ ≤ T).
fn from_left_edge(w: &Bounds, p0: DVec2, p1: DVec2) -> Canonical {
    if p1.x < w.l {
        return Canonical::Reject;
    }
    // Between the rays through the top-left and bottom-left corners, or it misses.
    if turn(p0, DVec2::new(w.l, w.t), p1) > 0.0 || turn(p0, DVec2::new(w.l, w.b), p1) < 0.0 {
        return Canonical::Reject;
    }
    let d = p1 - p0;
    let entry = at_x(p0, d, w.l); // dx > 0: x₁ ≥ L > x₀
    if w.inside(p1) {
        return Canonical::Segment(Some(entry), None);
    }
    Canonical::Segment(Some(entry), Some(exit_from_left(w, p0, p1)))
}

/// P₀ in the bottom-left corner region (x₀ < L, y₀ < B).
fn from_corner(w: &Bounds, p0: DVec2, p1: DVec2) -> Canonical {
    if p1.x < w.l || p1.y < w.b {
        return Canonical::Reject;
    }
    // Between the rays through the top-left and bottom-right corners, or it misses.
    if turn(p0, DVec2::new(w.l, w.t), p1) > 0.0 || turn(p0, DVec2::new(w.r, w.b), p1) < 0.0 {
        return Canonical::Reject;
    }
    let d = p1 - p0; // dx > 0 and dy > 0
    let entry = if turn(p0, DVec2::new(w.l, w.b), p1) > 0.0 {
        at_x(p0, d, w.l) // above the near corner: through the left edge
    } else {
        at_y(p0, d, w.b) // below it: through the bottom edge
    };
    if w.inside(p1) {
        return Canonical::Segment(Some(entry), None);
    }
    let exit = if turn(p0, DVec2::new(w.r, w.t), p1) > 0.0 {
        at_y(p0, d, w.t)
    } else {
        at_x(p0, d, w.r)
    };
    Canonical::Segment(Some(entry), Some(exit))
}

/// Clip the segment `a`→`c` against the window by Nicholl-Lee-Nicholl.
///
/// ```
/// use glam::Vec2;
/// use wireflight_geometry::clip::{nicholl_lee_nicholl, ClipOutcome, Window2};
/// // The seed's window (left, right, bottom, top) = (30, 220, 50, 240): p1 = (40, 140),
/// // p2 = (100, 200) lies inside; p1 = (20, 10), p2 = (20, 200) is left of it.
/// let w = Window2::from_lrbt(30.0, 220.0, 50.0, 240.0).unwrap();
/// let (p1, p2) = (Vec2::new(40.0, 140.0), Vec2::new(100.0, 200.0));
/// assert_eq!(nicholl_lee_nicholl::clip_2d(p1, p2, &w), ClipOutcome::Accepted(p1, p2));
/// let (p1, p2) = (Vec2::new(20.0, 10.0), Vec2::new(20.0, 200.0));
/// assert_eq!(nicholl_lee_nicholl::clip_2d(p1, p2, &w), ClipOutcome::Rejected);
/// ```
pub fn clip_2d(a: Vec2, c: Vec2, window: &Window2) -> ClipOutcome2 {
    if !(a.is_finite() && c.is_finite()) {
        return ClipOutcome::NonFinite;
    }
    let code = window.outcode(a);
    let frame = Frame::for_code(code);
    let w = Bounds::of(window, frame);
    let (p0, p1) = (frame.to(a.as_dvec2()), frame.to(c.as_dvec2()));
    let canonical = match w.code(p0) {
        0 => from_inside(&w, p0, p1),
        plane::LEFT => from_left_edge(&w, p0, p1),
        _ => {
            debug_assert_eq!(w.code(p0), plane::LEFT | plane::BOTTOM);
            from_corner(&w, p0, p1)
        }
    };
    let finish = |p: DVec2| window.clamp(frame.back(p).as_vec2());
    match canonical {
        Canonical::Reject => ClipOutcome::Rejected,
        Canonical::Accept => ClipOutcome::Accepted(a, c),
        Canonical::Segment(s, e) => ClipOutcome::Clipped(s.map_or(a, finish), e.map_or(c, finish)),
    }
}
