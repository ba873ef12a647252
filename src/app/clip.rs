//! `wireflight clip`: the clipping lab on the command line. Edges from a CSV file (homogeneous
//! clip space, or 2D with `--window`) → one algorithm → the clipped edges, in input order,
//! written atomically; `--stats` prints the tally and the time per edge.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use glam::{Vec2, Vec4};

use crate::clip::batch::{clip_soa, EdgesSoa, SegmentsSoa};
use crate::clip::{
    blinn, cohen_sutherland, cyrus_beck, liang_barsky, nicholl_lee_nicholl, sutherland_hodgman,
    ClipOutcome, ClipStats, ClipVolume, DepthRange, Window2,
};
use crate::clip_io::{self, HOMOGENEOUS_COLUMNS, PLANAR_COLUMNS};

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
    #[arg(long, value_name = "BYTES", default_value_t = clip_io::DEFAULT_MAX_BYTES)]
    pub max_bytes: u64,
}

fn parse_window(s: &str) -> Result<Window2, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| {
            crate::app::cli::finite_f64(t.trim()).and_then(|x| {
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

/// Clip every edge; return the outcomes and the time of one pass.
fn timed<E: Copy, P>(
    edges: &[E],
    clip: impl Fn(E) -> ClipOutcome<P>,
) -> (Vec<ClipOutcome<P>>, Duration) {
    let start = Instant::now();
    let outcomes: Vec<ClipOutcome<P>> = edges.iter().map(|&e| clip(e)).collect();
    let mut elapsed = start.elapsed();
    // Small files: repeat to time something measurable (≥ 20 ms or 1000 passes).
    let mut passes = 1u32;
    let mut total = elapsed;
    while total < Duration::from_millis(20) && passes < 1000 && !edges.is_empty() {
        let t = Instant::now();
        for &e in edges {
            std::hint::black_box(clip(std::hint::black_box(e)));
        }
        total += t.elapsed();
        passes += 1;
    }
    if passes > 1 {
        elapsed = total / passes;
    }
    (outcomes, elapsed)
}

/// Run `wireflight clip`.
///
/// # Errors
/// Unreadable or oversized input, a malformed line (`FILE:LINE: problem`), an algorithm that
/// does not apply to the input's kind, an unwritable output.
pub fn run(args: &ClipArgs) -> anyhow::Result<()> {
    let text = clip_io::read_bounded(&args.input, args.max_bytes)?;
    let (body, stats, elapsed, n, what) = match args.window {
        Some(window) => {
            let clip: fn(Vec2, Vec2, &Window2) -> ClipOutcome<Vec2> = match args.algo {
                Algo::Blinn | Algo::BlinnBatch => {
                    bail!("blinn clips homogeneous edges: leave out --window")
                }
                Algo::CohenSutherland => cohen_sutherland::clip_2d,
                Algo::LiangBarsky => liang_barsky::clip_2d,
                Algo::CyrusBeck => |a, c, w: &Window2| {
                    let corners = w.corners();
                    let polygon = cyrus_beck::ConvexPolygon::new(&corners)
                        .expect("a window is a convex polygon");
                    cyrus_beck::clip_polygon(a, c, &polygon)
                },
                Algo::NichollLeeNicholl => nicholl_lee_nicholl::clip_2d,
                Algo::SutherlandHodgman => sutherland_hodgman::clip_edge_2d,
            };
            let file = clip_io::parse_rows(&text, &args.input, &PLANAR_COLUMNS)?;
            let edges = clip_io::planar_edges(&file.edges);
            let (outcomes, elapsed) = timed(&edges, |(a, c)| clip(a, c, &window));
            let mut stats = ClipStats::default();
            let rows: Vec<Option<[f32; 4]>> = outcomes
                .iter()
                .map(|o| {
                    stats.record(o);
                    o.segment().map(|(a, c)| [a.x, a.y, c.x, c.y])
                })
                .collect();
            let body = clip_io::format_rows(
                file.header.as_deref(),
                rows.iter().map(|r| r.as_ref().map(|v| &v[..])),
            );
            let what = format!(
                "2D window {},{} .. {},{}",
                window.xmin(),
                window.ymin(),
                window.xmax(),
                window.ymax()
            );
            (body, stats, elapsed, edges.len(), what)
        }
        None => {
            let depth = match args.depth.unwrap_or(DepthArg::ZeroToOne) {
                DepthArg::ZeroToOne => DepthRange::ZeroToOne,
                DepthArg::MinusOneToOne => DepthRange::NegOneToOne,
            };
            let volume = ClipVolume::new(depth);
            let clip: fn(Vec4, Vec4, &ClipVolume) -> ClipOutcome = match args.algo {
                Algo::Blinn | Algo::BlinnBatch => blinn::clip_edge_in,
                Algo::CohenSutherland => cohen_sutherland::clip_homogeneous,
                Algo::LiangBarsky => liang_barsky::clip_homogeneous,
                Algo::CyrusBeck => cyrus_beck::clip_homogeneous,
                Algo::SutherlandHodgman => sutherland_hodgman::clip_edge_homogeneous,
                Algo::NichollLeeNicholl => bail!(
                    "nicholl-lee-nicholl is a 2D algorithm (its regions come from the corners of a \
                     rectangle): give --window XMIN,YMIN,XMAX,YMAX and 2D edges"
                ),
            };
            let file = clip_io::parse_rows(&text, &args.input, &HOMOGENEOUS_COLUMNS)?;
            let edges = clip_io::homogeneous_edges(&file.edges);
            let batch = args.algo == Algo::BlinnBatch;
            let (outcomes, mut stats, elapsed) = if batch {
                batch_outcomes(&edges, depth)
            } else {
                let (o, t) = timed(&edges, |(a, c)| clip(a, c, &volume));
                (o, ClipStats::default(), t)
            };
            let rows: Vec<Option<[f32; 8]>> = outcomes
                .iter()
                .map(|o| {
                    if !batch {
                        stats.record(o);
                    }
                    o.segment().map(|(a, c)| {
                        let mut r = [0f32; 8];
                        r[..4].copy_from_slice(&a.to_array());
                        r[4..].copy_from_slice(&c.to_array());
                        r
                    })
                })
                .collect();
            let body = clip_io::format_rows(
                file.header.as_deref(),
                rows.iter().map(|r| r.as_ref().map(|v| &v[..])),
            );
            let what = match depth {
                DepthRange::ZeroToOne => "homogeneous, 0 <= z <= w",
                DepthRange::NegOneToOne => "homogeneous, -w <= z <= w",
            };
            (body, stats, elapsed, edges.len(), what.to_string())
        }
    };
    crate::fsio::write_atomic(&args.output, body.as_bytes())
        .with_context(|| format!("{}", args.output.display()))?;
    let algo = args
        .algo
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string());
    println!(
        "wrote {} ({n} edges, {algo}, {what})",
        args.output.display()
    );
    if args.stats {
        let per_edge = if n > 0 {
            elapsed.as_secs_f64() * 1e9 / n as f64
        } else {
            0.0
        };
        println!(
            "accepted {}, rejected {}, clipped {} ({} of them to nothing), non-finite {}; \
             {per_edge:.1} ns per edge",
            stats.trivially_accepted,
            stats.trivially_rejected,
            stats.clipped + stats.clipped_away,
            stats.clipped_away,
            stats.non_finite
        );
        println!("clip: {stats}");
    }
    Ok(())
}

/// The batch path: per-edge outcomes for the output file (its segments, in place; the drops
/// all as `Rejected`, the tally telling them apart), its tally, and its time per pass.
fn batch_outcomes(
    edges: &[(Vec4, Vec4)],
    depth: DepthRange,
) -> (Vec<ClipOutcome>, ClipStats, Duration) {
    let soa = EdgesSoa::from_pairs(edges);
    let mut out = SegmentsSoa::default();
    let start = Instant::now();
    let stats = clip_soa(&soa, depth, &mut out);
    let mut total = start.elapsed();
    let mut passes = 1u32;
    let mut scratch = SegmentsSoa::default();
    while total < Duration::from_millis(20) && passes < 1000 && !edges.is_empty() {
        scratch.clear();
        let t = Instant::now();
        std::hint::black_box(clip_soa(std::hint::black_box(&soa), depth, &mut scratch));
        total += t.elapsed();
        passes += 1;
    }
    let mut outcomes = vec![ClipOutcome::Rejected; edges.len()];
    for i in 0..out.len() {
        let (e, a, c) = out.get(i);
        outcomes[e as usize] = ClipOutcome::Clipped(a, c);
    }
    (outcomes, stats, total / passes)
}
