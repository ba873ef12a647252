//! CPU backend: Bresenham lines into an RGBA8 buffer. Bit-exact and deterministic, so its
//! images serve as golden test images.
//!
//! A segment endpoint at pixel coordinates (x, y) lands in pixel (⌊x⌋, ⌊y⌋), clamped into the
//! image (clipped segments may touch the far image edge, x = width, or overshoot it by float
//! rounding). Lines are stepped along their major axis from the lower end, so a segment and its
//! reverse light the same pixels.

use glam::Vec2;

use super::{Image, LineScene, Rgba};

/// Draw a scene: clear to the background, then every batch in order.
pub fn render(scene: &LineScene) -> Image {
    let mut image = Image::filled(scene.width, scene.height, scene.background);
    for batch in &scene.batches {
        for s in &batch.segments {
            draw_segment(&mut image, s.a, s.b, batch.color);
        }
    }
    image
}

/// The pixel a point in pixel coordinates falls in, clamped into the image. Non-finite
/// coordinates clamp too (NaN to 0) rather than wrap; the pipeline never produces them.
#[inline]
pub fn pixel_of(p: Vec2, width: u32, height: u32) -> (i32, i32) {
    // Clamp in float before converting, so huge values cannot overflow the integer.
    let x = p.x.floor().clamp(0.0, (width - 1) as f32);
    let y = p.y.floor().clamp(0.0, (height - 1) as f32);
    (x as i32, y as i32)
}

/// Draw one segment given in pixel coordinates.
pub fn draw_segment(image: &mut Image, a: Vec2, b: Vec2, color: Rgba) {
    let (x0, y0) = pixel_of(a, image.width, image.height);
    let (x1, y1) = pixel_of(b, image.width, image.height);
    let width = image.width as usize;
    let pixels = &mut image.pixels;
    bresenham(x0, y0, x1, y1, |x, y| {
        let i = (y as usize * width + x as usize) * 4;
        pixels[i..i + 4].copy_from_slice(&color);
    });
}

/// Bresenham's integer line from (x0, y0) to (x1, y1), both ends included, calling `plot` for
/// each pixel in order of the major axis.
///
/// The decision variable starts at `p = 2·dy − dx` and steps the minor axis when `p > 0`
/// (the seed's formulation, generalised to all octants).
///
/// ```
/// // The seed's worked example: (2, 2) to (7, 6).
/// let mut pts = vec![];
/// wireflight_draw::render::cpu::bresenham(2, 2, 7, 6, |x, y| pts.push((x, y)));
/// assert_eq!(pts, [(2, 2), (3, 3), (4, 4), (5, 4), (6, 5), (7, 6)]);
/// ```
pub fn bresenham(x0: i32, y0: i32, x1: i32, y1: i32, mut plot: impl FnMut(i32, i32)) {
    let dx = (x1 - x0).abs();
    let dy = (y1 - y0).abs();
    if dx >= dy {
        // x-major: walk x upwards.
        let (x0, y0, x1, y1) = if x0 <= x1 {
            (x0, y0, x1, y1)
        } else {
            (x1, y1, x0, y0)
        };
        let sy = if y1 >= y0 { 1 } else { -1 };
        let mut p = 2 * dy - dx;
        let mut y = y0;
        for x in x0..=x1 {
            plot(x, y);
            if p > 0 {
                y += sy;
                p += 2 * dy - 2 * dx;
            } else {
                p += 2 * dy;
            }
        }
    } else {
        // y-major: walk y upwards.
        let (x0, y0, x1, y1) = if y0 <= y1 {
            (x0, y0, x1, y1)
        } else {
            (x1, y1, x0, y0)
        };
        let sx = if x1 >= x0 { 1 } else { -1 };
        let mut p = 2 * dx - dy;
        let mut x = x0;
        for y in y0..=y1 {
            plot(x, y);
            if p > 0 {
                x += sx;
                p += 2 * dx - 2 * dy;
            } else {
                p += 2 * dx;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixels(x0: i32, y0: i32, x1: i32, y1: i32) -> Vec<(i32, i32)> {
        let mut v = vec![];
        bresenham(x0, y0, x1, y1, |x, y| v.push((x, y)));
        v
    }

    #[test]
    fn every_octant_is_connected_and_hits_both_ends() {
        for (x1, y1) in [
            (9, 3),
            (3, 9),
            (-3, 9),
            (-9, 3),
            (-9, -3),
            (-3, -9),
            (3, -9),
            (9, -3),
        ] {
            let pts = pixels(0, 0, x1, y1);
            assert_eq!(pts.len() as i32, x1.abs().max(y1.abs()) + 1);
            assert!(pts.contains(&(0, 0)) && pts.contains(&(x1, y1)));
            for w in pts.windows(2) {
                let (a, b) = (w[0], w[1]);
                assert!(
                    (a.0 - b.0).abs() <= 1 && (a.1 - b.1).abs() <= 1,
                    "gap {a:?} {b:?}"
                );
            }
            let mut rev = pixels(x1, y1, 0, 0);
            let mut fwd = pts.clone();
            rev.sort();
            fwd.sort();
            assert_eq!(fwd, rev, "direction must not matter");
        }
    }

    #[test]
    fn single_pixel_and_clamping() {
        assert_eq!(pixels(4, 4, 4, 4), [(4, 4)]);
        assert_eq!(pixel_of(Vec2::new(800.0, -0.0), 800, 600), (799, 0));
        assert_eq!(pixel_of(Vec2::new(f32::NAN, 1e30), 800, 600), (0, 599));
    }
}
