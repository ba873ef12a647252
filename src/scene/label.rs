//! Labels as line segments: a small stroke font (capitals, digits and the signs labels need)
//! so that time stamps, axis labels and units go through the same [`LineScene`] as
//! everything else and come out the same on every backend, PNG, GIF or SVG.
//! (The Euler pictures' captions use `text.rs`, written at the same time; the two fonts
//! should become one.)
//!
//! Each glyph is drawn in a box 4 units wide and 6 high (y up), one unit being a sixth of the
//! text height; glyphs advance 6 units. Lower-case letters are drawn as capitals; characters
//! without a glyph as a small box. Pure: no I/O.
//!
//! [`LineScene`]: crate::render::LineScene

use glam::Vec2;

use crate::render::Segment2;

/// The glyph of `c`: polylines separated by spaces, each a run of `xy` points joined by `-`
/// (x in 0..=4, y in 0..=6, y up).
fn glyph(c: char) -> Option<&'static str> {
    Some(match c.to_ascii_uppercase() {
        '0' => "00-40-46-06-00 05-41",
        '1' => "15-26-20 10-30",
        '2' => "06-46-43-03-00-40",
        '3' => "06-46-40-00 13-43",
        '4' => "06-03-43 46-40",
        '5' => "46-06-03-43-40-00",
        '6' => "46-06-00-40-43-03",
        '7' => "06-46-40",
        '8' => "00-40-46-06-00 03-43",
        '9' => "43-03-06-46-40-00",
        'A' => "00-04-26-44-40 02-42",
        'B' => "00-06-36-45-44-33-03 33-42-41-30-00",
        'C' => "40-00-06-46",
        'D' => "00-06-26-45-41-20-00",
        'E' => "40-00-06-46 03-33",
        'F' => "00-06-46 03-33",
        'G' => "46-06-00-40-43-23",
        'H' => "00-06 40-46 03-43",
        'I' => "10-30 20-26 16-36",
        'J' => "06-46 36-31-20-10-01",
        'K' => "00-06 46-03-40",
        'L' => "06-00-40",
        'M' => "00-06-23-46-40",
        'N' => "00-06-40-46",
        'O' => "00-40-46-06-00",
        'P' => "00-06-46-43-03",
        'Q' => "00-40-46-06-00 21-40",
        'R' => "00-06-46-43-03 23-40",
        'S' => "45-36-16-05-04-13-33-42-41-30-10-01",
        'T' => "06-46 26-20",
        'U' => "06-00-40-46",
        'V' => "06-20-46",
        'W' => "06-00-23-40-46",
        'X' => "00-46 06-40",
        'Y' => "06-23-46 23-20",
        'Z' => "06-46-00-40",
        '.' => "10-20-21-11-10",
        ',' => "21-10",
        '-' | '–' | '−' => "13-33",
        '+' => "03-43 21-25",
        '=' => "02-42 04-44",
        ':' => "21-22 24-25",
        '/' => "00-46",
        '(' => "36-24-22-30",
        ')' => "16-24-22-10",
        '%' => "00-46 05-06-16-15-05 30-40-41-31-30",
        '×' => "12-34 14-32",
        '°' => "25-26-36-35-25",
        '>' => "05-43-01",
        '<' => "45-03-41",
        '|' => "20-26",
        '\'' => "25-26",
        '`' => "16-25",
        '_' => "00-40",
        ' ' => "",
        _ => return None,
    })
}

/// Width of `text` at `height` pixels, pixels (the last glyph without its gap).
pub fn text_width(text: &str, height: f32) -> f32 {
    let n = text.chars().count();
    if n == 0 {
        0.0
    } else {
        (n as f32 * 6.0 - 2.0) * height / 6.0
    }
}

/// Appends the strokes of `text` with its top-left corner at `at` (pixels, y down),
/// `height` pixels tall, to `out`.
pub fn draw_text(text: &str, at: Vec2, height: f32, out: &mut Vec<Segment2>) {
    let u = height / 6.0;
    for (i, c) in text.chars().enumerate() {
        let x0 = at.x + i as f32 * 6.0 * u;
        let point = |p: &[u8]| -> Vec2 {
            let (gx, gy) = ((p[0] - b'0') as f32, (p[1] - b'0') as f32);
            Vec2::new(x0 + gx * u, at.y + (6.0 - gy) * u)
        };
        match glyph(c) {
            Some(strokes) => {
                for line in strokes.split(' ').filter(|l| !l.is_empty()) {
                    let pts: Vec<Vec2> = line.split('-').map(|p| point(p.as_bytes())).collect();
                    for w in pts.windows(2) {
                        out.push(Segment2 { a: w[0], b: w[1] });
                    }
                }
            }
            None => {
                let b = [point(b"11"), point(b"31"), point(b"35"), point(b"15")];
                for k in 0..4 {
                    out.push(Segment2 {
                        a: b[k],
                        b: b[(k + 1) % 4],
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_glyph_stays_in_its_box() {
        let all = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ.,-+=:/()%×°<>|'`_ –−?";
        let mut out = Vec::new();
        draw_text(all, Vec2::new(10.0, 20.0), 12.0, &mut out);
        let w = text_width(all, 12.0);
        for s in &out {
            for p in [s.a, s.b] {
                assert!(p.x >= 10.0 && p.x <= 10.0 + w + 1e-3, "{p}");
                assert!(p.y >= 20.0 && p.y <= 32.0 + 1e-3, "{p}");
            }
        }
        // Lower case is drawn as capitals.
        let (mut a, mut b) = (Vec::new(), Vec::new());
        draw_text("t = 1.5 s", Vec2::ZERO, 6.0, &mut a);
        draw_text("T = 1.5 S", Vec2::ZERO, 6.0, &mut b);
        assert_eq!(a, b);
        assert_eq!(text_width("", 10.0), 0.0);
    }
}
