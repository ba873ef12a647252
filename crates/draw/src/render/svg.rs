//! Vector output: the exact clipped segments as SVG `<line>` elements, in pixel coordinates.
//!
//! Coordinates are printed with Rust's shortest round-trip formatting of `f32`, so parsing the
//! file gives back bit-identical segments: useful for papers and for tests.

use std::fmt::Write;

use super::{LineScene, Rgba};

fn hex(c: Rgba) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The scene as an SVG document: a background rectangle, then one `<g>` per batch holding one
/// `<line>` per segment.
pub fn to_svg(scene: &LineScene) -> String {
    let mut s = String::with_capacity(128 + 80 * scene.segment_count());
    let (w, h) = (scene.width, scene.height);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="{w}" height="{h}" fill="{}"/>"#,
        hex(scene.background)
    );
    for batch in &scene.batches {
        let _ = writeln!(
            s,
            r#"<g stroke="{}" stroke-width="1" stroke-linecap="square">"#,
            hex(batch.color)
        );
        for seg in &batch.segments {
            let _ = writeln!(
                s,
                r#"<line x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
                seg.a.x, seg.a.y, seg.b.x, seg.b.y
            );
        }
        s.push_str("</g>\n");
    }
    s.push_str("</svg>\n");
    s
}
