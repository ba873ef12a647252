//! `wireflight clip`'s options: the algorithm, the input's kind (homogeneous or a 2D window)
//! and the depth range; for Weiler-Atherton, the polygon files, the operation and the outputs.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::geometry::clip::Window2;

/// Default limit on the size of `clip`'s input file, bytes (256 MiB).
pub const DEFAULT_MAX_BYTES: u64 = 256 << 20;

const EXAMPLES: &str = "\
Examples:
  wireflight clip --algo blinn --input edges.csv --out clipped.csv --stats
  wireflight clip --algo cohen-sutherland --depth minus-one-to-one --input e.csv --out o.csv
  wireflight clip --algo nicholl-lee-nicholl --rect 2,2,4,4 --input 2d.csv --out o.csv
  wireflight clip --algo weiler-atherton --subject s.txt --clip c.txt --out o.txt --json
  wireflight clip --algo weiler-atherton --demo --out wa-pictures/

Input: one edge per line, x0,y0,z0,w0,x1,y1,z1,w1 (homogeneous clip space, visible where
-w <= x,y <= w and 0 <= z <= w, or -w <= z <= w with --depth minus-one-to-one), or x0,y0,x1,y1
with --rect XMIN,YMIN,XMAX,YMAX. Blank lines and lines starting with # are skipped; a first
line that does not start with a number is a header. Output: one line per input edge, in
order: the visible part in the same columns, or an empty line when nothing is visible.
2D only: nicholl-lee-nicholl. Homogeneous only: blinn, blinn-batch.

Weiler-Atherton clips polygons: --subject and --clip instead of --input. Polygon files: one
x,y vertex a line, a blank line between polygons, # comments; each polygon simple (no edge
meets another but its neighbours at their shared vertex), concave allowed, either way round.
Every polygon of the subject file is clipped against the first polygon of the clip file (its
other polygons are not used). --op intersection (default) or difference. The output has the
same format: each piece of the result as its outline (counter-clockwise), then each of its
holes (clockwise) as a polygon of its own; --json prints the same polygons, which of them are
holes, and the area. --picture draws subject, clip polygon and result (PNG). --demo writes
the clipping lab's pictures of the degenerate cases into --out DIR instead.";

/// Line clipping algorithms of the `clip` command.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Algo {
    /// Blinn's homogeneous clipper, edge by edge (homogeneous only).
    Blinn,
    /// Blinn's clipper on structure-of-arrays batches (homogeneous only).
    BlinnBatch,
    /// Cohen-Sutherland: outcodes and iterative chopping.
    CohenSutherland,
    /// Liang-Barsky: parametric, one boundary at a time.
    LiangBarsky,
    /// Cyrus-Beck: parametric against convex half-spaces (the window or the clip volume).
    CyrusBeck,
    /// Nicholl-Lee-Nicholl: regions between rays through the corners (2D only).
    NichollLeeNicholl,
    /// Sutherland-Hodgman on the 2-vertex polygon of the edge.
    SutherlandHodgman,
    /// Weiler-Atherton: polygons against a polygon (--subject, --clip; no edges).
    WeilerAtherton,
}

/// The result `clip --algo weiler-atherton` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PolygonOp {
    /// subject ∩ clip polygon.
    Intersection,
    /// subject − clip polygon.
    Difference,
}

/// Clip-space depth ranges, as named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DepthArg {
    /// 0 ≤ z ≤ w (wgpu, Vulkan, Direct3D).
    ZeroToOne,
    /// −w ≤ z ≤ w (OpenGL, the seed's canonical view volume).
    MinusOneToOne,
}

/// `wireflight clip` options.
#[derive(Debug, Args)]
#[command(after_help = EXAMPLES)]
pub struct ClipArgs {
    /// The algorithm.
    #[arg(long, value_enum, value_name = "NAME")]
    pub algo: Algo,
    /// Edges to clip (CSV); every algorithm but weiler-atherton.
    #[arg(long, value_name = "FILE.csv")]
    pub input: Option<PathBuf>,
    /// Where to write the clipped edges (CSV), or the clipped polygons; written atomically.
    /// (`--output` is an old spelling of this option.)
    #[arg(long = "out", alias = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// weiler-atherton: the polygons to clip (x,y a line, a blank line between polygons).
    #[arg(long, value_name = "FILE")]
    pub subject: Option<PathBuf>,
    /// weiler-atherton: the clip polygon (the file's first polygon).
    #[arg(long, value_name = "FILE")]
    pub clip: Option<PathBuf>,
    /// weiler-atherton: which result [default: intersection].
    #[arg(long, value_enum)]
    pub op: Option<PolygonOp>,
    /// weiler-atherton: print the result as JSON instead of the summary line:
    /// `{"polygons": [[[x, y], ...], ...], "pieces": [{"outer": 0, "holes": [1]}], "area": A}`.
    #[arg(long)]
    pub json: bool,
    /// weiler-atherton: draw subject (blue), clip polygon (orange) and result (green) to this
    /// PNG, written atomically.
    #[arg(long, value_name = "FILE.png")]
    pub picture: Option<PathBuf>,
    /// weiler-atherton: refuse a polygon of more vertices than this (its checks take time
    /// growing with the square of the vertices: 20 000 take about 2 s, 40 000 about 8 s).
    #[arg(long, value_name = "N", default_value_t = 20_000,
          value_parser = clap::value_parser!(u64).range(3..))]
    pub max_vertices: u64,
    /// weiler-atherton: instead of clipping files, write the clipping lab's pictures
    /// (concave pieces, a difference, a hole, a shared vertex, collinear edges, a vertex on an
    /// edge) and a list of them into --out DIR, as a whole (a DIR from an earlier run is
    /// replaced).
    #[arg(long, conflicts_with_all = ["input", "subject", "clip", "op", "json", "picture", "window", "depth", "stats", "max_vertices"])]
    pub demo: bool,
    /// Clip 2D edges (x0,y0,x1,y1) against this rectangle. (`--window` is an old spelling of
    /// this option.)
    #[arg(long = "rect", alias = "window", value_name = "XMIN,YMIN,XMAX,YMAX", allow_hyphen_values = true, value_parser = parse_window, conflicts_with = "depth")]
    pub window: Option<Window2>,
    /// Depth range of the homogeneous clip volume [default: zero-to-one].
    #[arg(long, value_enum)]
    pub depth: Option<DepthArg>,
    /// Print the counts of accepted, rejected and clipped edges and the time per edge.
    #[arg(long)]
    pub stats: bool,
    /// Refuse input files larger than this, bytes.
    #[arg(long, value_name = "BYTES", default_value_t = DEFAULT_MAX_BYTES)]
    pub max_bytes: u64,
}

fn parse_window(s: &str) -> Result<Window2, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| {
            super::finite_f64(t.trim()).and_then(|x| {
                if x.abs() <= f64::from(f32::MAX) {
                    Ok(x as f32)
                } else {
                    Err(format!("`{t}` is out of range"))
                }
            })
        })
        .collect::<Result<_, _>>()?;
    let [xmin, ymin, xmax, ymax] = v[..] else {
        return Err(format!("`{s}` is not XMIN,YMIN,XMAX,YMAX (e.g. 2,2,4,4)"));
    };
    Window2::new(xmin, ymin, xmax, ymax)
        .ok_or_else(|| format!("window `{s}` needs XMIN < XMAX and YMIN < YMAX"))
}
