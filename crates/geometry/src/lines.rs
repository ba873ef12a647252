//! What a frame is once projected: coloured batches of 2D segments in pixel coordinates
//! (origin at the top-left corner of the image, x right, y down; pixel (i, j) covers
//! [i, i+1)×[j, j+1), its centre is (i + ½, j + ½)). The projector produces them, the scene
//! builders collect them, every backend draws them.

use glam::Vec2;

/// An RGBA colour, 8 bits per channel, straight (not premultiplied) alpha.
pub type Rgba = [u8; 4];

/// A line segment in pixel coordinates (see the module docs for the pixel convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment2 {
    /// Start point, pixels.
    pub a: Vec2,
    /// End point, pixels.
    pub b: Vec2,
}

/// Segments drawn in one colour.
#[derive(Clone, Debug, PartialEq)]
pub struct LineBatch {
    /// Line colour.
    pub color: Rgba,
    /// The segments, pixels.
    pub segments: Vec<Segment2>,
}

/// Everything one frame draws: a background and coloured line batches, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct LineScene {
    /// Image width, pixels (≥ 1).
    pub width: u32,
    /// Image height, pixels (≥ 1).
    pub height: u32,
    /// Clear colour.
    pub background: Rgba,
    /// Batches, drawn first to last (later ones on top).
    pub batches: Vec<LineBatch>,
}

impl LineScene {
    /// Total number of segments in all batches.
    pub fn segment_count(&self) -> usize {
        self.batches.iter().map(|b| b.segments.len()).sum()
    }
}
