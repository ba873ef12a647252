//! `wireflight clip`: the clipping lab on the command line. Edges from a CSV file (homogeneous
//! clip space, or 2D with `--rect`) → one algorithm → the clipped edges, in input order,
//! written atomically; `--stats` prints the tally and the time per edge. Weiler-Atherton clips
//! polygons instead ([`polygons`]).

pub mod io;
pub mod polygons;

use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use clap::ValueEnum;
use glam::{Vec2, Vec4};

use super::cli::{Algo, ClipArgs, DepthArg};
use crate::geometry::clip::batch::{clip_soa, EdgesSoa, SegmentsSoa};
use crate::geometry::clip::{
    blinn, cohen_sutherland, cyrus_beck, liang_barsky, nicholl_lee_nicholl, sutherland_hodgman,
    ClipOutcome, ClipStats, ClipVolume, DepthRange, Window2,
};
use io::{HOMOGENEOUS_COLUMNS, PLANAR_COLUMNS};

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
    let inputs = crate::app::outputs::given(&[
        ("--input", args.input.as_deref()),
        ("--subject", args.subject.as_deref()),
        ("--clip", args.clip.as_deref()),
    ]);
    // `--demo` writes a directory of pictures into --out; otherwise --out is a file.
    let out = ("--out", args.output.as_path());
    let (files, dirs) = if args.demo {
        (None, Some(out))
    } else {
        (Some(out), None)
    };
    let outputs: Vec<(&str, &std::path::Path)> = files
        .into_iter()
        .chain(args.picture.as_deref().map(|p| ("--picture", p)))
        .collect();
    let dirs: Vec<(&str, &std::path::Path)> = dirs.into_iter().collect();
    crate::app::outputs::check_outputs(&inputs, &outputs, &dirs)?;
    if args.algo == Algo::WeilerAtherton {
        return polygons::run(args);
    }
    let algo = args
        .algo
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string());
    let input = edge_input(args, &algo)?;
    let text = io::read_bounded(input, args.max_bytes)?;
    let clipped = match args.window {
        Some(window) => clip_planar(args.algo, &text, input, &window)?,
        None => clip_homogeneous(args.algo, args.depth, &text, input)?,
    };
    crate::fsio::write_atomic(&args.output, clipped.body.as_bytes())
        .with_context(|| format!("{}", args.output.display()))?;
    println!(
        "wrote {} ({} edges, {algo}, {})",
        crate::app::shown(&args.output),
        clipped.edges,
        clipped.what
    );
    if args.stats {
        print_stats(&clipped);
    }
    Ok(())
}

/// `--input`, the edge file, after refusing the options that are Weiler-Atherton's alone.
fn edge_input<'a>(args: &'a ClipArgs, algo: &str) -> anyhow::Result<&'a Path> {
    for (given, option) in [
        (args.subject.is_some(), "--subject"),
        (args.clip.is_some(), "--clip"),
        (args.op.is_some(), "--op"),
        (args.json, "--json"),
        (args.picture.is_some(), "--picture"),
    ] {
        if given {
            bail!("{option} is for --algo weiler-atherton (polygons); {algo} clips edges from --input");
        }
    }
    let Some(input) = args.input.as_deref() else {
        bail!("--algo {algo} clips edges: give --input FILE.csv");
    };
    Ok(input)
}

/// An edge file clipped: the output's text, the tally, the time of one pass, how many edges
/// and what they were clipped against.
struct Clipped {
    body: String,
    stats: ClipStats,
    elapsed: Duration,
    edges: usize,
    what: String,
}

/// `--rect`: 2D edges against a window.
fn clip_planar(algo: Algo, text: &str, input: &Path, window: &Window2) -> anyhow::Result<Clipped> {
    let clip: fn(Vec2, Vec2, &Window2) -> ClipOutcome<Vec2> = match algo {
        Algo::Blinn | Algo::BlinnBatch => {
            bail!("blinn clips homogeneous edges: leave out --rect")
        }
        Algo::CohenSutherland => cohen_sutherland::clip_2d,
        Algo::LiangBarsky => liang_barsky::clip_2d,
        Algo::CyrusBeck => |a, c, w: &Window2| {
            let corners = w.corners();
            let polygon =
                cyrus_beck::ConvexPolygon::new(&corners).expect("a window is a convex polygon");
            cyrus_beck::clip_polygon(a, c, &polygon)
        },
        Algo::NichollLeeNicholl => nicholl_lee_nicholl::clip_2d,
        Algo::SutherlandHodgman => sutherland_hodgman::clip_edge_2d,
        Algo::WeilerAtherton => unreachable!("polygons::run"),
    };
    let file = io::parse_rows(text, input, &PLANAR_COLUMNS)?;
    let edges = io::planar_edges(&file.edges);
    let (outcomes, elapsed) = timed(&edges, |(a, c)| clip(a, c, window));
    let mut stats = ClipStats::default();
    let rows: Vec<Option<[f32; 4]>> = outcomes
        .iter()
        .map(|o| {
            stats.record(o);
            o.segment().map(|(a, c)| [a.x, a.y, c.x, c.y])
        })
        .collect();
    Ok(Clipped {
        body: io::format_rows(
            file.header.as_deref(),
            rows.iter().map(|r| r.as_ref().map(|v| &v[..])),
        ),
        stats,
        elapsed,
        edges: edges.len(),
        what: format!(
            "2D window {},{} .. {},{}",
            window.xmin(),
            window.ymin(),
            window.xmax(),
            window.ymax()
        ),
    })
}

/// Homogeneous edges against the clip volume of `--depth`.
fn clip_homogeneous(
    algo: Algo,
    depth: Option<DepthArg>,
    text: &str,
    input: &Path,
) -> anyhow::Result<Clipped> {
    let depth = match depth.unwrap_or(DepthArg::ZeroToOne) {
        DepthArg::ZeroToOne => DepthRange::ZeroToOne,
        DepthArg::MinusOneToOne => DepthRange::NegOneToOne,
    };
    let volume = ClipVolume::new(depth);
    let clip: fn(Vec4, Vec4, &ClipVolume) -> ClipOutcome = match algo {
        Algo::Blinn | Algo::BlinnBatch => blinn::clip_edge_in,
        Algo::CohenSutherland => cohen_sutherland::clip_homogeneous,
        Algo::LiangBarsky => liang_barsky::clip_homogeneous,
        Algo::CyrusBeck => cyrus_beck::clip_homogeneous,
        Algo::SutherlandHodgman => sutherland_hodgman::clip_edge_homogeneous,
        Algo::WeilerAtherton => unreachable!("polygons::run"),
        Algo::NichollLeeNicholl => bail!(
            "nicholl-lee-nicholl is a 2D algorithm (its regions come from the corners of a \
             rectangle): give --rect XMIN,YMIN,XMAX,YMAX and 2D edges"
        ),
    };
    let file = io::parse_rows(text, input, &HOMOGENEOUS_COLUMNS)?;
    let edges = io::homogeneous_edges(&file.edges);
    let batch = algo == Algo::BlinnBatch;
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
    let what = match depth {
        DepthRange::ZeroToOne => "homogeneous, 0 <= z <= w",
        DepthRange::NegOneToOne => "homogeneous, -w <= z <= w",
    };
    Ok(Clipped {
        body: io::format_rows(
            file.header.as_deref(),
            rows.iter().map(|r| r.as_ref().map(|v| &v[..])),
        ),
        stats,
        elapsed,
        edges: edges.len(),
        what: what.to_string(),
    })
}

/// `--stats`: the tally and the time per edge.
fn print_stats(clipped: &Clipped) {
    let Clipped {
        stats,
        elapsed,
        edges,
        ..
    } = clipped;
    let per_edge = if *edges > 0 {
        elapsed.as_secs_f64() * 1e9 / *edges as f64
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
