//! `wireflight clip --algo weiler-atherton`: polygons against a polygon
//! ([`crate::geometry::clip::weiler_atherton`]). Not pure: it reads and writes files.
//!
//! A polygon file has one `x,y` vertex a line and a blank line between polygons; `#` lines are
//! comments (they do not separate polygons), a byte-order mark is skipped, and a closing copy of
//! the first vertex is allowed. Every polygon of the subject file is clipped against the first
//! polygon of the clip file. The output file has the same format: per piece of the result its
//! outline (counter-clockwise), then each of its holes (clockwise), each as a polygon of its own.
//! Every problem is reported as `FILE:LINE: problem` before anything is written; a polygon
//! that is not simple is refused with the two edges (by the lines of their ends) and the point
//! where they meet. `--demo` writes the clipping lab's pictures instead (`demo`).

mod demo;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use glam::{DVec2, Vec2};

use super::io;
use crate::app::cli::{ClipArgs, PolygonOp};
use crate::draw::render::{LineBatch, LineScene, Rgba, Segment2};
use crate::geometry::clip::weiler_atherton::{self, Piece, PolygonError, Which};

/// Largest coordinate of a polygon's vertex: products of two (areas, crossings) must stay
/// finite, and (1e150)² = 1e300 does.
pub const MAX_COORDINATE: f64 = 1e150;

/// A problem with a polygon file: the file and the line (none: the file as a whole).
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {problem}", path.display(), line.map_or_else(String::new, |l| format!(":{l}")))]
pub struct PolygonFileError {
    /// The file.
    pub path: PathBuf,
    /// The line, from 1.
    pub line: Option<usize>,
    /// What is wrong.
    pub problem: String,
}

/// One polygon of a file: its vertices and the line of each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FilePolygon {
    /// The vertices, as written.
    pub vertices: Vec<DVec2>,
    /// The line of each vertex, from 1.
    pub lines: Vec<usize>,
}

/// Parse a polygon file's text (`path` for messages).
///
/// # Errors
/// A line that is not two finite numbers `x,y`, a polygon of fewer than three vertices, a file
/// without a polygon.
pub fn parse(text: &str, path: &Path) -> Result<Vec<FilePolygon>, PolygonFileError> {
    let err = |line: Option<usize>, problem: String| PolygonFileError {
        path: path.to_path_buf(),
        line,
        problem,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut polygons: Vec<FilePolygon> = Vec::new();
    let mut current = FilePolygon::default();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let row = raw.trim();
        if row.starts_with('#') {
            continue;
        }
        if row.is_empty() {
            if !current.vertices.is_empty() {
                polygons.push(std::mem::take(&mut current));
            }
            continue;
        }
        let xy = vertex(row).map_err(|problem| err(Some(line), problem))?;
        current.vertices.push(xy);
        current.lines.push(line);
    }
    if !current.vertices.is_empty() {
        polygons.push(current);
    }
    if polygons.is_empty() {
        return Err(err(
            None,
            "no polygon (one x,y vertex a line, a blank line between polygons)".to_string(),
        ));
    }
    for (i, p) in polygons.iter().enumerate() {
        if p.vertices.len() < 3 {
            return Err(err(
                Some(p.lines[0]),
                format!(
                    "polygon {} has {} vertices, a polygon needs at least 3",
                    i + 1,
                    p.vertices.len()
                ),
            ));
        }
    }
    Ok(polygons)
}

/// Check one polygon as the clipper will ([`weiler_atherton::validate`]), naming lines.
///
/// # Errors
/// Fewer than three distinct vertices, or two edges that meet (by the lines of their ends).
pub fn validate(
    polygon: &FilePolygon,
    number: usize,
    which: Which,
    path: &Path,
) -> Result<(), PolygonFileError> {
    let Err(e) = weiler_atherton::validate(&polygon.vertices, which) else {
        return Ok(());
    };
    // The clipper's vertex i, after merging repeats and a closing copy: the line of each.
    let mut kept: Vec<(DVec2, usize)> = Vec::with_capacity(polygon.vertices.len());
    for (&v, &line) in polygon.vertices.iter().zip(&polygon.lines) {
        let v = v + DVec2::ZERO;
        if kept.last().map(|k| k.0) != Some(v) {
            kept.push((v, line));
        }
    }
    while kept.len() > 1 && kept.last().map(|k| k.0) == kept.first().map(|k| k.0) {
        kept.pop();
    }
    let line_of = |i: usize| kept.get(i % kept.len().max(1)).map_or(0, |k| k.1);
    let (line, problem) = match e {
        PolygonError::SelfIntersecting { a, b, at, .. } => (
            line_of(a),
            format!(
                "polygon {number} is not simple: the edge from line {} to line {} meets the edge \
                 from line {} to line {} at ({}, {})",
                line_of(a),
                line_of(a + 1),
                line_of(b),
                line_of(b + 1),
                at.x,
                at.y
            ),
        ),
        PolygonError::TooFewVertices { distinct, .. } => (
            polygon.lines[0],
            format!(
                "polygon {number} has {distinct} distinct vertices, a polygon needs at least 3"
            ),
        ),
        PolygonError::NonFinite { vertex, .. } => (
            polygon.lines.get(vertex).copied().unwrap_or(0),
            format!("polygon {number}: vertex is not finite"),
        ),
    };
    Err(PolygonFileError {
        path: path.to_path_buf(),
        line: Some(line),
        problem,
    })
}

/// Which rings are one piece's: the index of its outline and of each of its holes.
type PieceRings = (usize, Vec<usize>);

/// The rings of pieces, each outline followed by its holes; and per piece the index of its
/// outline and of its holes among them.
fn rings(pieces: &[Piece]) -> (Vec<&[DVec2]>, Vec<PieceRings>) {
    let mut rings: Vec<&[DVec2]> = Vec::new();
    let mut index = Vec::new();
    for p in pieces {
        let outer = rings.len();
        rings.push(&p.outer);
        let holes = p
            .holes
            .iter()
            .map(|h| {
                rings.push(h);
                rings.len() - 1
            })
            .collect();
        index.push((outer, holes));
    }
    (rings, index)
}

/// Refuses a polygon of more than `max` vertices, before the quadratic work.
fn within_vertex_limit(polygons: &[FilePolygon], path: &Path, max: u64) -> anyhow::Result<()> {
    for (i, p) in polygons.iter().enumerate() {
        let n = p.vertices.len() as u64;
        if n > max {
            bail!(
                "{}: polygon {} has {n} vertices, more than --max-vertices {max} (Weiler–\
                 Atherton's checks take time growing with the square of the vertices: 20 000 \
                 take about 2 s, 40 000 about 8 s; raise it to wait longer)",
                path.display(),
                i + 1
            );
        }
    }
    Ok(())
}

/// One `x,y` row as a vertex, or what is wrong with it.
fn vertex(row: &str) -> Result<DVec2, String> {
    let fields: Vec<&str> = row.split(',').map(str::trim).collect();
    if fields.len() != 2 {
        let hint = if row.contains(';') {
            " (separate the values with commas, not `;`)"
        } else {
            ""
        };
        return Err(format!(
            "expected 2 values (x,y), found {}{hint}",
            fields.len()
        ));
    }
    let mut xy = [0f64; 2];
    for (i, (slot, field)) in xy.iter_mut().zip(&fields).enumerate() {
        let column = format!("column {} ({})", i + 1, ["x", "y"][i]);
        let v: f64 = field
            .parse()
            .map_err(|_| format!("{column}: `{field}` is not a number"))?;
        if !v.is_finite() {
            return Err(format!("{column}: `{field}` is not a finite number"));
        }
        if v.abs() > MAX_COORDINATE {
            return Err(format!(
                "{column}: `{field}` is beyond ±1e150 (areas and crossings of such coordinates \
                 overflow: rescale the polygons)"
            ));
        }
        *slot = v;
    }
    Ok(DVec2::from_array(xy))
}

/// The output file's text: one `x,y` a line, a blank line between polygons.
pub fn format_polygons(rings: &[&[DVec2]]) -> String {
    let mut out = String::new();
    for (i, ring) in rings.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        for v in *ring {
            let _ = writeln!(out, "{},{}", number(v.x), number(v.y));
        }
    }
    out
}

/// The `--json` text (one line).
fn format_json(rings: &[&[DVec2]], index: &[PieceRings], area: f64) -> String {
    let join = |items: Vec<String>| items.join(", ");
    let polygons = join(
        rings
            .iter()
            .map(|r| {
                format!(
                    "[{}]",
                    join(
                        r.iter()
                            .map(|v| format!("[{}, {}]", number(v.x), number(v.y)))
                            .collect(),
                    )
                )
            })
            .collect(),
    );
    let pieces = join(
        index
            .iter()
            .map(|(outer, holes)| {
                format!(
                    "{{\"outer\": {outer}, \"holes\": [{}]}}",
                    join(holes.iter().map(usize::to_string).collect())
                )
            })
            .collect(),
    );
    let area = number(area);
    format!("{{\"polygons\": [{polygons}], \"pieces\": [{pieces}], \"area\": {area}}}")
}

/// A coordinate or an area as written out: Rust's shortest round-trip digits, in scientific
/// notation beyond 1e16 or below 1e-5 (never 300 digits of `1e300`); read back, the same
/// number.
fn number(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e16 || v.abs() < 1e-5) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Picture size, pixels.
const PICTURE: (u32, u32) = (640, 480);
/// Margin around the drawing, pixels.
const MARGIN: f64 = 24.0;
/// Colours: subject, clip polygon, result.
const SUBJECT: Rgba = [90, 150, 255, 255];
const CLIP: Rgba = [255, 160, 60, 255];
const RESULT: Rgba = [80, 255, 120, 255];

/// A drawing in its own units (y up) fitted into a rectangle of pixels (y down), keeping
/// its aspect, centred.
struct Fit {
    scale: f64,
    centre: DVec2,
    middle: DVec2,
}

impl Fit {
    /// Fit the bounding box of `points` into the pixel rectangle `lo`..`hi`.
    fn new<'a>(points: impl Iterator<Item = &'a DVec2>, lo: DVec2, hi: DVec2) -> Fit {
        let (min, max) = points.fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(min, max), &v| (min.min(v), max.max(v)),
        );
        // A single point (or none) still gets a finite scale.
        let size = (max - min).max(DVec2::splat(f64::MIN_POSITIVE));
        let room = hi - lo;
        Fit {
            scale: (room.x / size.x).min(room.y / size.y),
            centre: (min + max) * 0.5,
            middle: (lo + hi) * 0.5,
        }
    }

    /// Where a point lands, pixels.
    fn px(&self, v: DVec2) -> Vec2 {
        let p = (v - self.centre) * self.scale;
        Vec2::new((self.middle.x + p.x) as f32, (self.middle.y - p.y) as f32)
    }

    /// The outlines of closed rings, one colour.
    fn outlines<'a>(&self, rings: impl Iterator<Item = &'a [DVec2]>, color: Rgba) -> LineBatch {
        LineBatch {
            color,
            segments: rings
                .flat_map(|r| {
                    (0..r.len()).map(move |i| Segment2 {
                        a: self.px(r[i]),
                        b: self.px(r[(i + 1) % r.len()]),
                    })
                })
                .collect(),
        }
    }
}

/// The picture: subject, clip polygon and result outlines, fitted with a margin (y up).
fn picture(subjects: &[&[DVec2]], clip: &[DVec2], result: &[&[DVec2]]) -> LineScene {
    let (w, h) = PICTURE;
    let all = subjects
        .iter()
        .chain(std::iter::once(&clip))
        .flat_map(|r| r.iter());
    let fit = Fit::new(
        all,
        DVec2::splat(MARGIN),
        DVec2::new(f64::from(w) - MARGIN, f64::from(h) - MARGIN),
    );
    LineScene {
        width: w,
        height: h,
        background: crate::draw::scene::palette::BACKGROUND,
        batches: vec![
            fit.outlines(subjects.iter().copied(), SUBJECT),
            fit.outlines(std::iter::once(clip), CLIP),
            fit.outlines(result.iter().copied(), RESULT),
        ],
    }
}

/// Read and parse a polygon file.
fn load(path: &Path, max_bytes: u64) -> anyhow::Result<Vec<FilePolygon>> {
    let text = io::read_bounded(path, max_bytes)?;
    Ok(parse(&text, path)?)
}

/// Run `wireflight clip --algo weiler-atherton`.
///
/// # Errors
/// A missing or refused option, an unreadable or malformed polygon file (`FILE:LINE: problem`),
/// an unwritable output. Nothing is written then.
pub fn run(args: &ClipArgs) -> anyhow::Result<()> {
    if args.demo {
        // The demo's options are kept apart from the files' by clap (`conflicts_with_all`).
        return demo::run(args);
    }
    let (subject_path, clip_path) = polygon_inputs(args)?;
    let op = args.op.unwrap_or(PolygonOp::Intersection);
    let subjects = load(subject_path, args.max_bytes)?;
    let clips = load(clip_path, args.max_bytes)?;
    for (polygons, path) in [(&subjects, subject_path), (&clips, clip_path)] {
        within_vertex_limit(polygons, path, args.max_vertices)?;
    }
    for (i, s) in subjects.iter().enumerate() {
        validate(s, i + 1, Which::Subject, subject_path)?;
    }
    let clip = &clips[0];
    validate(clip, 1, Which::Clip, clip_path)?;

    let pieces = clip_all(&subjects, clip, op)?;
    // + 0.0: an empty result's −0 is 0.
    let area = weiler_atherton::total_area(&pieces) + 0.0;
    let (rings, index) = rings(&pieces);
    let body = format_polygons(&rings);
    let png = match &args.picture {
        Some(_) => Some(picture_png(&subjects, clip, &rings)?),
        None => None,
    };
    crate::fsio::write_atomic(&args.output, body.as_bytes())
        .with_context(|| format!("{}", args.output.display()))?;
    if let (Some(path), Some(png)) = (&args.picture, &png) {
        crate::fsio::write_atomic(path, png).with_context(|| format!("{}", path.display()))?;
    }
    if args.json {
        println!("{}", format_json(&rings, &index, area));
        return Ok(());
    }
    print_summary(args, op, subjects.len(), &pieces, area);
    Ok(())
}

/// `--subject` and `--clip`, after refusing the options that are the edge clippers' alone
/// and a `--picture` that is no PNG.
fn polygon_inputs(args: &ClipArgs) -> anyhow::Result<(&Path, &Path)> {
    for (given, option) in [
        (args.input.is_some(), "--input (give --subject and --clip)"),
        (args.window.is_some(), "--rect"),
        (args.depth.is_some(), "--depth"),
        (args.stats, "--stats"),
    ] {
        if given {
            bail!("weiler-atherton clips polygons: leave out {option}");
        }
    }
    let (Some(subject_path), Some(clip_path)) = (args.subject.as_deref(), args.clip.as_deref())
    else {
        bail!("weiler-atherton needs --subject FILE and --clip FILE (polygons: x,y a line)");
    };
    if let Some(p) = &args.picture {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            bail!(
                "--picture {}: the picture is a PNG (name it .png)",
                crate::app::shown(p)
            );
        }
    }
    Ok((subject_path, clip_path))
}

/// Every subject polygon clipped against `clip`: the pieces of `op`'s result, in order.
fn clip_all(
    subjects: &[FilePolygon],
    clip: &FilePolygon,
    op: PolygonOp,
) -> anyhow::Result<Vec<Piece>> {
    let mut pieces: Vec<Piece> = Vec::new();
    for (i, s) in subjects.iter().enumerate() {
        let clipped = weiler_atherton::clip(&s.vertices, &clip.vertices)
            .with_context(|| format!("subject polygon {}", i + 1))?;
        pieces.extend(match op {
            PolygonOp::Intersection => clipped.intersection,
            PolygonOp::Difference => clipped.difference,
        });
    }
    Ok(pieces)
}

/// `--picture`: the subjects, the clip polygon and the result, as PNG bytes.
fn picture_png(
    subjects: &[FilePolygon],
    clip: &FilePolygon,
    result: &[&[DVec2]],
) -> anyhow::Result<Vec<u8>> {
    let subject_rings: Vec<&[DVec2]> = subjects.iter().map(|s| s.vertices.as_slice()).collect();
    let scene = picture(&subject_rings, &clip.vertices, result);
    let image = crate::draw::render::cpu::render(&scene);
    image.encode_png().context("encoding the picture")
}

/// What was written: the result counted, and the picture.
fn print_summary(args: &ClipArgs, op: PolygonOp, subjects: usize, pieces: &[Piece], area: f64) {
    let holes: usize = pieces.iter().map(|p| p.holes.len()).sum();
    let op_name = match op {
        PolygonOp::Intersection => "intersection",
        PolygonOp::Difference => "difference",
    };
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    println!(
        "wrote {} ({op_name} of {} with the clip polygon: {}, {}, area {area})",
        crate::app::shown(&args.output),
        plural(subjects, "subject polygon", "subject polygons"),
        plural(pieces.len(), "piece", "pieces"),
        plural(holes, "hole", "holes"),
    );
    if let Some(p) = &args.picture {
        println!("wrote {}", crate::app::shown(p));
    }
}
