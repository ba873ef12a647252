//! `wireflight clip`'s options: the algorithm, the input's kind (homogeneous or a 2D window)
//! and the depth range.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::clip::Window2;

/// Default limit on the size of `clip`'s input file, bytes (256 MiB).
pub const DEFAULT_MAX_BYTES: u64 = 256 << 20;

const EXAMPLES: &str = "\
Examples:
  wireflight clip --algo blinn --input edges.csv --output clipped.csv --stats
  wireflight clip --algo cohen-sutherland --depth minus-one-to-one --input e.csv --output o.csv
  wireflight clip --algo nicholl-lee-nicholl --window 2,2,4,4 --input 2d.csv --output o.csv

Input: one edge per line, x0,y0,z0,w0,x1,y1,z1,w1 (homogeneous clip space, visible where
-w <= x,y <= w and 0 <= z <= w, or -w <= z <= w with --depth minus-one-to-one), or x0,y0,x1,y1
with --window XMIN,YMIN,XMAX,YMAX. Blank lines and lines starting with # are skipped; a first
line that does not start with a number is a header. Output: one line per input edge, in
order: the visible part in the same columns, or an empty line when nothing is visible.
2D only: nicholl-lee-nicholl. Homogeneous only: blinn, blinn-batch.";

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
    /// Edges to clip (CSV).
    #[arg(long, value_name = "FILE.csv")]
    pub input: PathBuf,
    /// Where to write the clipped edges (CSV, written atomically).
    #[arg(long, value_name = "FILE.csv")]
    pub output: PathBuf,
    /// Clip 2D edges (x0,y0,x1,y1) against this window.
    #[arg(long, value_name = "XMIN,YMIN,XMAX,YMAX", allow_hyphen_values = true, value_parser = parse_window, conflicts_with = "depth")]
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
