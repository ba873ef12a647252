//! The stroke font of every caption and label: glyphs as line segments, so that text goes
//! through every backend (CPU, GPU, PNG, GIF, SVG) like the wireframes do and the CPU images
//! stay bit-exact.
//!
//! Glyphs sit on a grid 4 units wide and 6 tall (capital height), y up from the baseline, and
//! advance [`ADVANCE`] units. Lower-case letters have their own glyphs, 4 units tall (the
//! x-height), with ascenders to 6 and descenders to [`DESCENDER`] below the baseline, so that
//! units read as they are written (m, s, m/s). A space is empty and a character without a
//! glyph is a small box, so a missing glyph shows. Pure: no I/O.

use glam::Vec2;

use crate::render::Segment2;

/// Grid units from one glyph's origin to the next.
pub const ADVANCE: f32 = 6.0;
/// Capital height, grid units.
pub const CAP_HEIGHT: f32 = 6.0;

/// How far descenders (g, j, p, q, y) reach below the baseline, grid units.
pub const DESCENDER: f32 = 2.0;

/// Drawn for a character without a glyph.
const MISSING: &[&str] = &["1131351511"];

/// The strokes of a glyph: polylines, each a string of points as digit pairs `xy` on the grid
/// (`/` is y = −1 and `.` is y = −2, for descenders).
fn glyph(c: char) -> &'static [&'static str] {
    if let Some(g) = lower_case(c) {
        return g;
    }
    match c.to_ascii_uppercase() {
        'A' => &["002640", "1333"],
        'B' => &["00063645443303", "3342413000"],
        'C' => &["4536160501103041"],
        'D' => &["00062644422000"],
        'E' => &["46060040", "0333"],
        'F' => &["460600", "0333"],
        'G' => &["45361605011030414323"],
        'H' => &["0006", "4640", "0343"],
        'I' => &["1636", "2620", "1030"],
        'J' => &["4641301001"],
        'K' => &["0006", "4602", "1340"],
        'L' => &["060040"],
        'M' => &["0006244640"],
        'N' => &["00064046"],
        'O' => &["100105163645413010"],
        'P' => &["00063645443303"],
        'Q' => &["100105163645413010", "2240"],
        'R' => &["00063645443303", "2340"],
        'S' => &["453616050413334241301001"],
        'T' => &["0646", "2620"],
        'U' => &["060110304146"],
        'V' => &["062046"],
        'W' => &["0610234046"],
        'X' => &["0046", "0640"],
        'Y' => &["0623", "4623", "2320"],
        'Z' => &["06460040"],
        '0' => &["100105163645413010", "0145"],
        '1' => &["152620", "1030"],
        '2' => &["05163645440040"],
        '3' => &["0516364544334241301001", "1333"],
        '4' => &["30360242"],
        '5' => &["4606033342413000"],
        '6' => &["4536160501103041423303"],
        '7' => &["064610"],
        '8' => &["13040516364544331302011030414233"],
        '9' => &["0110304145361605041343"],
        '-' | '–' | '−' => &["1333"],
        '+' => &["1333", "2224"],
        '=' => &["0242", "0444"],
        '.' => &["2021"],
        ',' => &["2110"],
        ':' => &["2122", "2425"],
        '°' => &["1526352415"],
        '\'' => &["2614"],
        '(' => &["36252130"],
        ')' => &["16252110"],
        '/' => &["0046"],
        '>' => &["153311"],
        '<' => &["351331"],
        '%' => &["0046", "0506161505", "3040413130"],
        '×' => &["1234", "1432"],
        '|' => &["2026"],
        '`' => &["1625"],
        '_' => &["0040"],
        ' ' => &[],
        _ => MISSING,
    }
}

/// The lower-case letters: x-height 4, ascenders 6, descenders −2.
fn lower_case(c: char) -> Option<&'static [&'static str]> {
    Some(match c {
        'a' => &["4440", "4334140301103041"],
        'b' => &["0600", "0314344341301001"],
        'c' => &["4334140301103041"],
        'd' => &["4640", "4334140301103041"],
        'e' => &["02424334140301103041"],
        'f' => &["4536261510", "0434"],
        'g' => &["4334140301103041", "444/3.1.0/"],
        'h' => &["0600", "0314344340"],
        'i' => &["142420", "1030", "2526"],
        'j' => &["343/2.1.0/", "3536"],
        'k' => &["0600", "3401", "1240"],
        'l' => &["16262130"],
        'm' => &["0400", "03142320", "23344340"],
        'n' => &["0400", "0314344340"],
        'o' => &["010314344341301001"],
        'p' => &["040.", "0314344341301001"],
        'q' => &["444.", "4334140301103041"],
        'r' => &["0400", "02243443"],
        's' => &["43341403123241301001"],
        't' => &["1611203041", "0434"],
        'u' => &["0401103041", "4440"],
        'v' => &["042044"],
        'w' => &["0410223044"],
        'x' => &["0044", "0440"],
        'y' => &["0420", "441."],
        'z' => &["04440040"],
        _ => return None,
    })
}

/// A grid coordinate from its character: `0`..`9`, and `/` (−1) and `.` (−2) below the
/// baseline.
fn digit(b: u8) -> f32 {
    f32::from(b) - f32::from(b'0')
}

/// Width of `text` in pixels at `unit` pixels per grid unit (the last glyph's spacing left
/// out).
pub fn width(text: &str, unit: f32) -> f32 {
    let n = text.chars().count() as f32;
    if n == 0.0 {
        0.0
    } else {
        (n * ADVANCE - 2.0) * unit
    }
}

/// Append the strokes of `text` to `out`, the first glyph's bottom-left corner at `origin`
/// (pixels, y down), `unit` pixels per grid unit.
pub fn draw(text: &str, origin: Vec2, unit: f32, out: &mut Vec<Segment2>) {
    for (i, c) in text.chars().enumerate() {
        let x0 = origin.x + i as f32 * ADVANCE * unit;
        for stroke in glyph(c) {
            let mut points = stroke
                .as_bytes()
                .chunks_exact(2)
                .map(|p| Vec2::new(x0 + digit(p[0]) * unit, origin.y - digit(p[1]) * unit));
            let Some(mut a) = points.next() else { continue };
            for b in points {
                out.push(Segment2 { a, b });
                a = b;
            }
        }
    }
}

/// [`draw`] with the glyph grid on pixel centres and a whole number of pixels per unit, so
/// that the strokes are crisp on the CPU rasterizer.
pub fn draw_crisp(text: &str, origin: Vec2, unit: f32, out: &mut Vec<Segment2>) {
    let origin = Vec2::new(origin.x.floor() + 0.5, origin.y.floor() + 0.5);
    draw(text, origin, unit.max(1.0).round(), out);
}

/// [`draw`] for a label `height` pixels tall with its top-left corner at `top_left`.
pub fn draw_label(text: &str, top_left: Vec2, height: f32, out: &mut Vec<Segment2>) {
    let unit = height / CAP_HEIGHT;
    draw(text, top_left + Vec2::new(0.0, height), unit, out);
}

/// Width of a label `height` pixels tall.
pub fn label_width(text: &str, height: f32) -> f32 {
    width(text, height / CAP_HEIGHT)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_glyph_stays_on_its_grid() {
        let chars = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-+=.,:°'()/<>%×|`_–−";
        for c in chars.chars() {
            let strokes = glyph(c);
            assert!(!strokes.is_empty() && strokes != MISSING, "{c}");
            for s in strokes {
                assert!(s.len() >= 4 && s.len() % 2 == 0, "{c}: {s}");
                for p in s.as_bytes().chunks_exact(2) {
                    assert!(digit(p[0]) <= 4.0 && digit(p[1]) <= 6.0, "{c}: {s}");
                }
            }
        }
        for c in 'a'..='z' {
            let strokes = glyph(c);
            assert!(!strokes.is_empty() && strokes != MISSING, "{c}");
            assert_ne!(
                strokes,
                glyph(c.to_ascii_uppercase()),
                "{c} has its own glyph"
            );
            for s in strokes {
                assert!(s.len() >= 4 && s.len() % 2 == 0, "{c}: {s}");
                for p in s.as_bytes().chunks_exact(2) {
                    let (x, y) = (digit(p[0]), digit(p[1]));
                    assert!((0.0..=4.0).contains(&x), "{c}: {s}");
                    assert!((-DESCENDER..=6.0).contains(&y), "{c}: {s}");
                }
            }
        }
        assert_eq!(glyph('#'), MISSING);
        assert!(glyph(' ').is_empty());
    }

    #[test]
    fn text_is_placed_left_to_right_above_the_baseline() {
        let mut out = Vec::new();
        draw_crisp("L1", Vec2::new(10.0, 50.0), 2.0, &mut out);
        // L: two strokes; 1: two polylines of 2 + 1 strokes.
        assert_eq!(out.len(), 2 + 3);
        for s in &out {
            for p in [s.a, s.b] {
                assert!(p.x >= 10.0 && p.x <= 10.5 + width("L1", 2.0), "{p}");
                assert!(p.y <= 50.5 && p.y >= 50.5 - CAP_HEIGHT * 2.0, "{p}");
            }
        }
        assert_eq!(width("", 2.0), 0.0);
        assert_eq!(width("AB", 2.0), 20.0);
    }

    #[test]
    fn labels_stay_in_their_box() {
        let all = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ.,-+=:/()%×°<>|'`_ –−?";
        let mut out = Vec::new();
        draw_label(all, Vec2::new(10.0, 20.0), 12.0, &mut out);
        let w = label_width(all, 12.0);
        for s in &out {
            for p in [s.a, s.b] {
                assert!(p.x >= 10.0 && p.x <= 10.0 + w + 1e-3, "{p}");
                assert!(p.y >= 20.0 && p.y <= 32.0 + 1e-3, "{p}");
            }
        }
        // Lower case has its own glyphs: units read m and s, not M and S; descenders reach
        // below the baseline by at most DESCENDER units.
        let (mut a, mut b) = (Vec::new(), Vec::new());
        draw_label("t = 1.5 s", Vec2::ZERO, 6.0, &mut a);
        draw_label("T = 1.5 S", Vec2::ZERO, 6.0, &mut b);
        assert_ne!(a, b);
        let mut out = Vec::new();
        draw_label("gjpqy m/s", Vec2::new(0.0, 20.0), 12.0, &mut out);
        let lowest = out.iter().flat_map(|s| [s.a.y, s.b.y]).fold(0.0, f32::max);
        assert!(
            lowest > 32.0 && lowest <= 32.0 + DESCENDER * 2.0 + 1e-3,
            "{lowest}"
        );
    }
}
