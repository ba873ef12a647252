//! `wireflight clip --algo weiler-atherton --demo --out DIR`: the clipping lab's pictures of
//! Weiler-Atherton, written into a directory as a whole. Each shows what a convex clipper
//! cannot do, or a degenerate case decided exactly: concave against concave in several
//! pieces, a difference in several pieces, a hole, a shared vertex, collinear overlapping
//! edges, a vertex on an edge. The result is drawn green, its outline 5 pixels wide and its
//! inside hatched, the subject (blue) and the clip polygon (orange) dashed on top of it: the
//! result's outline always runs along theirs, and lines of one width would hide each other. A legend names the colours; a title
//! names the case and the operation, a second line what came out (counted, not written in
//! here), a third the point of the case; white squares mark its special points.

use std::fmt::Write as _;

use anyhow::Context;
use glam::{DVec2, Vec2};

use super::{rings, Fit, CLIP, PICTURE, RESULT, SUBJECT};
use crate::app::cli::ClipArgs;
use crate::draw::render::{LineBatch, LineScene, Rgba, Segment2};
use crate::draw::scene::font;
use crate::fsio::write_dir_atomic;
use crate::geometry::clip::weiler_atherton::{self, Piece};

/// The list of pictures written with them; its presence marks a directory as this command's.
pub const MANIFEST: &str = "wireflight-clip-demo.txt";

/// Text colour of the titles.
const TEXT: Rgba = [220, 220, 220, 255];
/// The hatching inside the result: the result's green, dimmed, so its outline stays on top.
const HATCH: Rgba = [30, 110, 55, 255];
/// The marks on special points.
const MARK: Rgba = [255, 255, 255, 255];
/// Pixels between hatch lines (along the normal).
const HATCH_STEP: f64 = 7.0;
/// Pixels per font grid unit (a capital is 6 units tall); a line too wide for the picture at
/// that size is drawn at half of it.
const FONT_UNIT: f32 = 2.0;
/// Left margin of the text, pixels.
const TEXT_LEFT: f32 = 16.0;
/// Dashes of the inputs' outlines, pixels: drawn, then skipped.
const DASH: (f32, f32) = (7.0, 5.0);
/// Wide lines: one-pixel lines drawn again at these offsets, pixels. The result's outline is
/// 5 pixels wide, the inputs' dashes 2.
const RESULT_WIDTH: [(f32, f32); 9] = [
    (0., 0.),
    (1., 0.),
    (-1., 0.),
    (0., 1.),
    (0., -1.),
    (2., 0.),
    (-2., 0.),
    (0., 2.),
    (0., -2.),
];
const DASH_WIDTH: [(f32, f32); 3] = [(0., 0.), (1., 0.), (0., 1.)];
/// Baselines of the three title lines and the legend, pixels from the top.
const TITLE_BASELINES: [f32; 3] = [22.0, 42.0, 62.0];
const LEGEND_BASELINE: f32 = PICTURE.1 as f32 - 12.0;
/// The drawing's rectangle, pixels: below the titles, above the legend.
const DRAWING: (DVec2, DVec2) = (
    DVec2::new(40.0, 84.0),
    DVec2::new(PICTURE.0 as f64 - 40.0, PICTURE.1 as f64 - 44.0),
);

/// Which result a case shows.
#[derive(Clone, Copy)]
enum Op {
    Intersection,
    Difference,
}

/// One picture.
struct Case {
    /// File name without `.png`.
    name: &'static str,
    /// The first title line (the operation is added).
    title: &'static str,
    /// The third line: what the case shows.
    point: &'static str,
    subject: Vec<DVec2>,
    clip: Vec<DVec2>,
    op: Op,
    /// Points to mark (shared vertices, touching points).
    marks: Vec<DVec2>,
}

fn p(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

/// A comb of four teeth, 7 wide and 5 tall.
fn comb() -> Vec<DVec2> {
    vec![
        p(0., 0.),
        p(7., 0.),
        p(7., 5.),
        p(6., 5.),
        p(6., 1.),
        p(5., 1.),
        p(5., 5.),
        p(4., 5.),
        p(4., 1.),
        p(3., 1.),
        p(3., 5.),
        p(2., 5.),
        p(2., 1.),
        p(1., 1.),
        p(1., 5.),
        p(0., 5.),
    ]
}

/// A C opening to the right, its two arms across the comb's teeth.
fn c_shape() -> Vec<DVec2> {
    vec![
        p(-1., 1.5),
        p(8., 1.5),
        p(8., 2.5),
        p(-0.5, 2.5),
        p(-0.5, 3.5),
        p(8., 3.5),
        p(8., 4.5),
        p(-1., 4.5),
    ]
}

/// A five-pointed star, strictly inside the L.
fn star() -> Vec<DVec2> {
    (0..10)
        .map(|k| {
            let r = if k % 2 == 0 { 1.3 } else { 0.55 };
            let a = std::f64::consts::FRAC_PI_2 + f64::from(k) * std::f64::consts::PI / 5.0;
            p(1.6, 1.6) + r * DVec2::new(a.cos(), a.sin())
        })
        .collect()
}

/// An L, 6 wide and 6 tall, its arms 3 thick.
fn l_shape() -> Vec<DVec2> {
    vec![
        p(0., 0.),
        p(6., 0.),
        p(6., 3.),
        p(3., 3.),
        p(3., 6.),
        p(0., 6.),
    ]
}

/// A U, 3 wide and 3 tall, its gap 1 wide.
fn u_shape() -> Vec<DVec2> {
    vec![
        p(0., 0.),
        p(3., 0.),
        p(3., 3.),
        p(2., 3.),
        p(2., 1.),
        p(1., 1.),
        p(1., 3.),
        p(0., 3.),
    ]
}

/// A 4 × 4 square with a V cut into its top, the V's tip at (2, 2).
fn notched_square() -> Vec<DVec2> {
    vec![
        p(0., 0.),
        p(4., 0.),
        p(4., 4.),
        p(3., 4.),
        p(2., 2.),
        p(1., 4.),
        p(0., 4.),
    ]
}

/// The cases, in the order their pictures are written.
fn cases() -> Vec<Case> {
    let square = vec![p(0., 0.), p(4., 0.), p(4., 4.), p(0., 4.)];
    vec![
        Case {
            name: "concave-pieces",
            title: "CONCAVE COMB AND CONCAVE C",
            point: "EACH ARM CUTS EACH TOOTH: PIECES, NOT BRIDGES",
            subject: comb(),
            clip: c_shape(),
            op: Op::Intersection,
            marks: vec![],
        },
        Case {
            name: "difference",
            title: "CONCAVE COMB MINUS CONCAVE C",
            point: "SAME GRAPH, OTHER EDGES: THE BASE, THE TEETH'S ENDS",
            subject: comb(),
            clip: c_shape(),
            op: Op::Difference,
            marks: vec![],
        },
        Case {
            name: "hole",
            title: "ONE INSIDE THE OTHER",
            point: "NO EDGES CROSS: THE STAR IS A CLOCKWISE HOLE",
            subject: l_shape(),
            clip: star(),
            op: Op::Difference,
            marks: vec![],
        },
        Case {
            name: "shared-vertex",
            title: "SHARED VERTEX",
            point: "TOUCHING AT (4, 4): A NOTCH, NOT A HOLE",
            subject: square,
            clip: vec![p(4., 4.), p(1., 2.5), p(2.5, 1.)],
            op: Op::Difference,
            marks: vec![p(4., 4.)],
        },
        Case {
            name: "collinear-overlap",
            title: "COLLINEAR OVERLAPPING EDGES",
            point: "EDGES SPLIT AT EACH OTHER'S ENDS, SHARED ONCE",
            subject: u_shape(),
            clip: vec![p(0.5, 0.), p(3., 0.), p(3., 2.), p(0.5, 2.)],
            op: Op::Intersection,
            marks: vec![p(0.5, 0.), p(3., 0.), p(3., 2.)],
        },
        Case {
            name: "vertex-on-edge",
            title: "VERTEX ON AN EDGE",
            point: "THE TIP ON THE BAND'S EDGE: 2 PIECES MEET AT (2, 2)",
            subject: notched_square(),
            clip: vec![p(-1., 2.), p(5., 2.), p(5., 5.), p(-1., 5.)],
            op: Op::Intersection,
            marks: vec![p(2., 2.)],
        },
    ]
}

/// A number for a caption: at most 3 decimals, without trailing zeros.
fn number(x: f64) -> String {
    let s = format!("{:.3}", x + 0.0);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// What came out, counted.
fn summary(pieces: &[Piece]) -> String {
    let holes: usize = pieces.iter().map(|p| p.holes.len()).sum();
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    format!(
        "RESULT: {}, {}, AREA {}",
        plural(pieces.len(), "PIECE", "PIECES"),
        plural(holes, "HOLE", "HOLES"),
        number(weiler_atherton::total_area(pieces))
    )
}

/// Hatch the inside of `rings` (pixels; even-odd, so holes stay clear) with lines at 45°.
fn hatch(rings: &[Vec<Vec2>]) -> Vec<Segment2> {
    let n = DVec2::new(1.0, 1.0).normalize();
    let d = DVec2::new(1.0, -1.0).normalize();
    let edges: Vec<(DVec2, DVec2)> = rings
        .iter()
        .flat_map(|r| (0..r.len()).map(move |i| (r[i].as_dvec2(), r[(i + 1) % r.len()].as_dvec2())))
        .collect();
    let (lo, hi) = edges
        .iter()
        .map(|(a, _)| a.dot(n))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s), hi.max(s))
        });
    let mut out = Vec::new();
    if !(lo.is_finite() && hi.is_finite()) {
        return out;
    }
    // Lines on a fixed grid of offsets, so neighbouring pieces' hatching lines up.
    let mut s = (lo / HATCH_STEP).ceil() * HATCH_STEP;
    while s <= hi {
        let mut along: Vec<f64> = edges
            .iter()
            .filter_map(|&(a, b)| {
                let (sa, sb) = (a.dot(n), b.dot(n));
                // Half-open, so a vertex on the line counts once.
                ((sa < s) != (sb < s)).then(|| {
                    let t = (s - sa) / (sb - sa);
                    (a + t * (b - a)).dot(d)
                })
            })
            .collect();
        along.sort_by(f64::total_cmp);
        for pair in along.chunks_exact(2) {
            let at = |u: f64| (s * n + u * d).as_vec2();
            out.push(Segment2 {
                a: at(pair[0]),
                b: at(pair[1]),
            });
        }
        s += HATCH_STEP;
    }
    out
}

/// A small square around a point, pixels.
fn mark(at: Vec2, out: &mut Vec<Segment2>) {
    let r = 4.0;
    let c = [
        at + Vec2::new(-r, -r),
        at + Vec2::new(r, -r),
        at + Vec2::new(r, r),
        at + Vec2::new(-r, r),
    ];
    for i in 0..4 {
        out.push(Segment2 {
            a: c[i],
            b: c[(i + 1) % 4],
        });
    }
}

/// Text at a baseline, `x` pixels from the left; smaller if it would not fit.
fn text(s: &str, x: f32, baseline: f32, out: &mut Vec<Segment2>) {
    let room = PICTURE.0 as f32 - x - TEXT_LEFT;
    let unit = if font::label_width(s, font::CAP_HEIGHT * FONT_UNIT) <= room {
        FONT_UNIT
    } else {
        FONT_UNIT / 2.0
    };
    font::draw_crisp(s, Vec2::new(x, baseline), unit, out);
}

/// Segments drawn again at each offset, pixels: a wide line from one-pixel ones.
fn widened(segments: &[Segment2], offsets: &[(f32, f32)]) -> Vec<Segment2> {
    offsets
        .iter()
        .flat_map(|&o| {
            let o = Vec2::from(o);
            segments.iter().map(move |s| Segment2 {
                a: s.a + o,
                b: s.b + o,
            })
        })
        .collect()
}

/// The outline of a ring, pixels, dashed; the dash pattern runs on round the corners.
fn dashed(ring: &[Vec2], out: &mut Vec<Segment2>) {
    let period = DASH.0 + DASH.1;
    let mut phase = 0.0f32;
    for i in 0..ring.len() {
        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
        let length = a.distance(b);
        if length <= 0.0 {
            continue;
        }
        // From the edge's start: the rest of the current dash or gap, then whole periods.
        let mut at = -phase;
        while at < length {
            let (on, off) = (at.max(0.0), (at + DASH.0).min(length));
            if off > on {
                out.push(Segment2 {
                    a: a.lerp(b, on / length),
                    b: a.lerp(b, off / length),
                });
            }
            at += period;
        }
        phase = (phase + length) % period;
    }
}

/// The picture of one case.
fn scene(case: &Case, pieces: &[Piece]) -> LineScene {
    let fit = Fit::new(case.subject.iter().chain(&case.clip), DRAWING.0, DRAWING.1);
    let (result, _) = rings(pieces);
    let in_pixels: Vec<Vec<Vec2>> = result
        .iter()
        .map(|r| r.iter().map(|&v| fit.px(v)).collect())
        .collect();
    let op = match case.op {
        Op::Intersection => "INTERSECTION",
        Op::Difference => "DIFFERENCE",
    };
    let mut words = Vec::new();
    for (line, baseline) in [
        format!("{}: {op}", case.title),
        summary(pieces),
        case.point.to_string(),
    ]
    .iter()
    .zip(TITLE_BASELINES)
    {
        text(line, TEXT_LEFT, baseline, &mut words);
    }
    // The legend: each name in its colour.
    let mut legend: [Vec<Segment2>; 3] = Default::default();
    let mut x = TEXT_LEFT;
    for (name, out) in ["SUBJECT", "CLIP POLYGON", "RESULT"]
        .iter()
        .zip(legend.iter_mut())
    {
        text(name, x, LEGEND_BASELINE, out);
        x += font::label_width(name, font::CAP_HEIGHT * FONT_UNIT) + 24.0;
    }
    let [subject_word, clip_word, result_word] = legend;
    let mut marks = Vec::new();
    for &m in &case.marks {
        mark(fit.px(m), &mut marks);
    }
    let outline = |ring: &[DVec2], mut out: Vec<Segment2>| {
        let pixels: Vec<Vec2> = ring.iter().map(|&v| fit.px(v)).collect();
        let mut dashes = Vec::new();
        dashed(&pixels, &mut dashes);
        out.extend(widened(&dashes, &DASH_WIDTH));
        out
    };
    // The result's outline 5 pixels wide, the inputs' dashes 2: the green shows either side
    // of the dashes where they run along it.
    let thin = fit.outlines(result.iter().copied(), RESULT);
    let mut result_batch = LineBatch {
        color: RESULT,
        segments: widened(&thin.segments, &RESULT_WIDTH),
    };
    result_batch.segments.extend(result_word);
    LineScene {
        width: PICTURE.0,
        height: PICTURE.1,
        background: crate::draw::scene::palette::BACKGROUND,
        batches: vec![
            LineBatch {
                color: HATCH,
                segments: hatch(&in_pixels),
            },
            result_batch,
            LineBatch {
                color: SUBJECT,
                segments: outline(&case.subject, subject_word),
            },
            LineBatch {
                color: CLIP,
                segments: outline(&case.clip, clip_word),
            },
            LineBatch {
                color: MARK,
                segments: marks,
            },
            LineBatch {
                color: TEXT,
                segments: words,
            },
        ],
    }
}

/// Write the pictures and the manifest into `--out` as a whole.
///
/// # Errors
/// `--out` is a file, or a directory that an earlier run of this command did not write;
/// I/O errors. Nothing is left half-written.
pub fn run(args: &ClipArgs) -> anyhow::Result<()> {
    let dir = &args.output;
    let mut manifest = format!(
        "# written by: wireflight {}\n# result green (solid, hatched), subject blue and clip polygon orange (dashed)\n",
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    );
    let mut files = Vec::new();
    let mut names = Vec::new();
    for case in cases() {
        let clipped = weiler_atherton::clip(&case.subject, &case.clip)
            .with_context(|| format!("the demo case {}", case.name))?;
        let pieces = match case.op {
            Op::Intersection => clipped.intersection,
            Op::Difference => clipped.difference,
        };
        let image = crate::draw::render::cpu::render(&scene(&case, &pieces));
        let name = format!("{}.png", case.name);
        writeln!(
            manifest,
            "{name}\t{}x{}\t{}; {}",
            PICTURE.0,
            PICTURE.1,
            case.title.to_lowercase(),
            summary(&pieces).to_lowercase()
        )?;
        files.push((name.clone(), image.encode_png().context("encoding PNG")?));
        names.push(name);
    }
    files.push((MANIFEST.to_string(), manifest.into_bytes()));
    write_dir_atomic(dir, &files, MANIFEST).context("--out")?;
    println!(
        "wrote {} pictures ({}) and {MANIFEST} to {}",
        names.len(),
        names.join(", "),
        crate::app::shown(dir)
    );
    Ok(())
}
