//! Weiler-Atherton (1977; seed `clipping-sutherland-hodgman-liang-barsky-bresenham.txt`, its
//! end: "replace crossing points with vertices, double all edges and form linked lists of
//! edges, change links at vertices, enumerate polygon patches"): clip one simple polygon (the
//! subject) against another (the clip polygon), both possibly concave, either orientation.
//! Where Sutherland-Hodgman needs a convex clip region, this needs neither polygon convex, and
//! it returns the intersection as separate pieces instead of one polygon joined by zero-width
//! bridges.
//!
//! # How
//!
//! 1. **Validate** ([`PolygonError`]): finite coordinates; repeated consecutive vertices (and a
//!    closing copy of the first) are merged; at least 3 distinct vertices; no two edges may
//!    meet except neighbours at their shared vertex (a crossing, a touch, a vertex repeated
//!    later, a spike doubling back are all refused, with the two edges and the point named).
//!    Both polygons are then turned counter-clockwise (interior on the left of every edge).
//! 2. **Split** every edge at every point where it meets an edge of the other polygon. A vertex
//!    of one polygon lying on an edge of the other is the *same* point (the input vertex,
//!    exactly, no computed crossing), and collinear overlapping edges are split at each other's
//!    ends, so an overlap becomes the same pair of vertices in both polygons. Proper crossings
//!    are computed once per pair from orientation tests and shared by both edges. Points are
//!    identified by their exact coordinates: the graph's vertices.
//! 3. **Classify** each piece of edge ("sub-edge"): *shared* when the other polygon has the
//!    same sub-edge, in the same or the opposite direction; otherwise *inside* or *outside*
//!    the other polygon by its midpoint (which cannot lie on the other boundary: the sub-edge
//!    meets it only at its ends).
//! 4. **Select** the boundary of the result: for the intersection A ∩ B, the sub-edges of A
//!    inside B, of B inside A, and shared edges running the same way (once); for the
//!    difference A − B, those of A outside B, of B inside A *reversed*, and shared edges of A
//!    running against B. Both come from the same graph ([`clip`]).
//! 5. **Trace** the selected edges into closed loops. Where several selected edges leave a
//!    vertex (pieces touching at a point), the loop takes the one turning most sharply left
//!    of the way it came, the first clockwise from the reversed incoming direction: the
//!    smallest face. That is the "change links at vertices" of the seed.
//! 6. **Assemble**: counter-clockwise loops are pieces, clockwise loops (only the difference
//!    has them: the clip polygon strictly inside the subject) are holes of the smallest piece
//!    that contains them.
//!
//! # The boundary rule
//!
//! The result is the **closure of the interior** (the regularised set operation): a point
//! counts by the area around it, so
//!
//! * pieces of zero area are dropped: polygons touching along an edge or at a point have an
//!   empty intersection, and a shared edge is not a piece;
//! * pieces of the result that touch at a single point are **separate pieces** (each a simple
//!   loop); a hole of a difference that touches its piece's outline at one point is not a hole
//!   but part of that outline, which then visits the point twice (a weakly simple loop);
//! * equal polygons intersect in one piece equal to them, and their difference is empty.
//!
//! Pieces come out counter-clockwise (holes clockwise), starting anywhere, with the vertices of
//! both inputs kept where they lie on the result's outline (collinear vertices are not merged).
//!
//! # Supported
//!
//! Simple polygons, concave allowed, either orientation, as subject and as clip polygon. The
//! *output* has holes where a difference needs them; polygons *with* holes as input are not
//! supported (a hole is not a simple polygon's part; the graph itself would take them, as
//! extra clockwise rings, but the validation of rings against each other is not written).
//!
//! # Tests
//!
//! `crates/geometry/tests/weiler_atherton.rs`: the degenerate cases by hand, each in every
//! orientation and from every start vertex of both polygons; property tests against `geo`'s
//! boolean operations (a test-only oracle: the same number of pieces and the same areas) and,
//! for the area alone to 1e-9 relative, against Sutherland-Hodgman with a convex clip polygon;
//! `WA_CASES=300000` for the long run.
//!
//! # Numbers
//!
//! `f64` throughout. Orientation tests are the plain determinant, exact when the coordinates
//! are integers (or multiples of one power of two) below about 2²⁵, which is where the
//! degenerate cases live: a vertex on an edge, collinear overlaps and shared vertices are then
//! found exactly and handled by identity, not by tolerance. With general floating-point
//! coordinates an exact degeneracy is rare, and a near one is decided by the rounded sign,
//! consistently for each pair of edges because each test is computed once.

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::DVec2;

/// Which of the two polygons an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Which {
    /// The polygon being clipped.
    Subject,
    /// The polygon it is clipped against.
    Clip,
}

impl std::fmt::Display for Which {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Which::Subject => "subject",
            Which::Clip => "clip",
        })
    }
}

/// Why a polygon was refused. Edge `i` runs from vertex `i` to vertex `i + 1` (cyclically) of
/// the polygon *after* repeated consecutive vertices are merged.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum PolygonError {
    /// A coordinate is NaN or infinite.
    #[error("{polygon} polygon: vertex {vertex} is not finite")]
    NonFinite {
        /// Which polygon.
        polygon: Which,
        /// Index of the vertex in the input.
        vertex: usize,
    },
    /// Fewer than three distinct vertices.
    #[error("{polygon} polygon: {distinct} distinct vertices, a polygon needs at least 3")]
    TooFewVertices {
        /// Which polygon.
        polygon: Which,
        /// How many distinct consecutive vertices it has.
        distinct: usize,
    },
    /// Two edges meet other than neighbours at their shared vertex (they cross, touch, or
    /// overlap; a neighbour doubling back along its predecessor is an overlap).
    #[error("{polygon} polygon is not simple: edges {a} and {b} meet at ({x}, {y})", x = at.x, y = at.y)]
    SelfIntersecting {
        /// Which polygon.
        polygon: Which,
        /// The first edge.
        a: usize,
        /// The second edge.
        b: usize,
        /// A point where they meet.
        at: DVec2,
    },
}

/// One piece of a result: a counter-clockwise outline and clockwise holes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piece {
    /// The outline, counter-clockwise, not closed (the last vertex joins the first).
    pub outer: Vec<DVec2>,
    /// Holes, clockwise, each not closed.
    pub holes: Vec<Vec<DVec2>>,
}

impl Piece {
    /// Area: the outline's less the holes'.
    pub fn area(&self) -> f64 {
        signed_area(&self.outer) + self.holes.iter().map(|h| signed_area(h)).sum::<f64>()
    }
}

/// Both results of clipping the subject against the clip polygon, from one graph.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Clipped {
    /// subject ∩ clip.
    pub intersection: Vec<Piece>,
    /// subject − clip.
    pub difference: Vec<Piece>,
}

/// Signed area of a ring (shoelace): positive counter-clockwise.
pub fn signed_area(ring: &[DVec2]) -> f64 {
    let n = ring.len();
    if n < 3 {
        return 0.0;
    }
    // Relative to the first vertex, to keep the products small.
    let o = ring[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += (ring[i] - o).perp_dot(ring[i + 1] - o);
    }
    0.5 * twice
}

/// Total area of pieces.
pub fn total_area(pieces: &[Piece]) -> f64 {
    pieces.iter().map(Piece::area).sum()
}

/// subject ∩ clip, as pieces (see the module docs for the boundary rule).
///
/// # Errors
/// [`PolygonError`] for a polygon with a non-finite coordinate, fewer than 3 distinct vertices
/// or two edges meeting.
///
/// ```
/// use glam::DVec2;
/// use wireflight_geometry::clip::weiler_atherton;
/// let p = |x, y| DVec2::new(x, y);
/// // A U-shape cut by a bar across its arms: two pieces.
/// let u = [p(0., 0.), p(3., 0.), p(3., 3.), p(2., 3.), p(2., 1.), p(1., 1.), p(1., 3.), p(0., 3.)];
/// let bar = [p(-1., 2.), p(4., 2.), p(4., 2.5), p(-1., 2.5)];
/// let pieces = weiler_atherton::intersection(&u, &bar).unwrap();
/// assert_eq!(pieces.len(), 2);
/// assert_eq!(weiler_atherton::total_area(&pieces), 1.0);
/// ```
pub fn intersection(subject: &[DVec2], clip_polygon: &[DVec2]) -> Result<Vec<Piece>, PolygonError> {
    Ok(clip(subject, clip_polygon)?.intersection)
}

/// subject − clip, as pieces with holes.
///
/// # Errors
/// As [`intersection`].
///
/// ```
/// use glam::DVec2;
/// use wireflight_geometry::clip::weiler_atherton;
/// let square = |x0: f64, y0: f64, s: f64| {
///     [DVec2::new(x0, y0), DVec2::new(x0 + s, y0), DVec2::new(x0 + s, y0 + s), DVec2::new(x0, y0 + s)]
/// };
/// // A square with a square hole; touching the outline instead, it would be a notch.
/// let d = weiler_atherton::difference(&square(0., 0., 4.), &square(1., 1., 2.)).unwrap();
/// assert_eq!((d.len(), d[0].holes.len(), d[0].area()), (1, 1, 12.0));
/// let d = weiler_atherton::difference(&square(0., 0., 4.), &square(0., 1., 2.)).unwrap();
/// assert_eq!((d.len(), d[0].holes.len(), d[0].area()), (1, 0, 12.0));
/// ```
pub fn difference(subject: &[DVec2], clip_polygon: &[DVec2]) -> Result<Vec<Piece>, PolygonError> {
    Ok(clip(subject, clip_polygon)?.difference)
}

/// Both the intersection and the difference, from one graph.
///
/// # Errors
/// As [`intersection`].
pub fn clip(subject: &[DVec2], clip_polygon: &[DVec2]) -> Result<Clipped, PolygonError> {
    let a = prepare(subject, Which::Subject)?;
    let b = prepare(clip_polygon, Which::Clip)?;
    let graph = Graph::build(&a, &b);
    Ok(Clipped {
        intersection: graph.result(Op::Intersection),
        difference: graph.result(Op::Difference),
    })
}

/// Check a polygon and return its distinct vertices, counter-clockwise.
///
/// # Errors
/// As [`intersection`].
pub fn validate(polygon: &[DVec2], which: Which) -> Result<Vec<DVec2>, PolygonError> {
    prepare(polygon, which)
}

fn prepare(polygon: &[DVec2], which: Which) -> Result<Vec<DVec2>, PolygonError> {
    if let Some(vertex) = polygon.iter().position(|v| !v.is_finite()) {
        return Err(PolygonError::NonFinite {
            polygon: which,
            vertex,
        });
    }
    let mut ring: Vec<DVec2> = Vec::with_capacity(polygon.len());
    for &v in polygon {
        // -0.0 and 0.0 are the same point.
        let v = v + DVec2::ZERO;
        if ring.last() != Some(&v) {
            ring.push(v);
        }
    }
    while ring.len() > 1 && ring.last() == ring.first() {
        ring.pop();
    }
    if ring.len() < 3 {
        return Err(PolygonError::TooFewVertices {
            polygon: which,
            distinct: ring.len(),
        });
    }
    check_simple(&ring, which)?;
    if signed_area(&ring) < 0.0 {
        ring.reverse();
    }
    Ok(ring)
}

/// Orientation of c relative to the line a→b: > 0 left, < 0 right, 0 on it.
#[inline]
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether `p`, known collinear with segment a–b, lies on the closed segment.
#[inline]
fn within(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// How two segments p0–p1 and q0–q1 meet.
enum Meet {
    None,
    /// Cross at one point interior to both.
    Cross(DVec2),
    /// Touch or overlap: the endpoints of each lying on the other, as
    /// `[q0 on p, q1 on p, p0 on q, p1 on q]`.
    Touch([bool; 4]),
}

fn meet(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Meet {
    // Bounding boxes first: cheap, and makes `within` below a containment test.
    if p0.x.max(p1.x) < q0.x.min(q1.x)
        || q0.x.max(q1.x) < p0.x.min(p1.x)
        || p0.y.max(p1.y) < q0.y.min(q1.y)
        || q0.y.max(q1.y) < p0.y.min(p1.y)
    {
        return Meet::None;
    }
    let o1 = orient(p0, p1, q0);
    let o2 = orient(p0, p1, q1);
    let o3 = orient(q0, q1, p0);
    let o4 = orient(q0, q1, p1);
    if o1 != 0.0 && o2 != 0.0 && o3 != 0.0 && o4 != 0.0 {
        if (o1 > 0.0) != (o2 > 0.0) && (o3 > 0.0) != (o4 > 0.0) {
            let t = o3 / (o3 - o4);
            return Meet::Cross(p0 + t * (p1 - p0));
        }
        return Meet::None;
    }
    let on = [
        o1 == 0.0 && within(p0, p1, q0),
        o2 == 0.0 && within(p0, p1, q1),
        o3 == 0.0 && within(q0, q1, p0),
        o4 == 0.0 && within(q0, q1, p1),
    ];
    if on.iter().any(|&b| b) {
        Meet::Touch(on)
    } else {
        Meet::None
    }
}

fn check_simple(ring: &[DVec2], which: Which) -> Result<(), PolygonError> {
    let n = ring.len();
    let edge = |i: usize| (ring[i], ring[(i + 1) % n]);
    let err = |a, b, at| PolygonError::SelfIntersecting {
        polygon: which,
        a,
        b,
        at,
    };
    for i in 0..n {
        // The neighbour i+1 shares ring[i+1]: it may only turn, not double back.
        let (a, b) = edge(i);
        let c = ring[(i + 2) % n];
        if orient(a, b, c) == 0.0 && (c - b).dot(a - b) > 0.0 {
            // c lies back along b→a, or a lies along b→c: the nearer one is on both.
            let at = if (c - b).length_squared() <= (a - b).length_squared() {
                c
            } else {
                a
            };
            return Err(err(i, (i + 1) % n, at));
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // neighbours across the closing vertex
            }
            let (c, d) = edge(j);
            match meet(a, b, c, d) {
                Meet::None => {}
                Meet::Cross(at) => return Err(err(i, j, at)),
                Meet::Touch(on) => {
                    let at = [c, d, a, b][on.iter().position(|&x| x).unwrap_or(0)];
                    return Err(err(i, j, at));
                }
            }
        }
    }
    Ok(())
}

/// Which operation's boundary to select.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Op {
    Intersection,
    Difference,
}

/// Where a sub-edge lies relative to the other polygon.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Class {
    Inside,
    Outside,
    /// The other polygon has this sub-edge, running the same way.
    SharedSame,
    /// The other polygon has this sub-edge, running the other way.
    SharedOpposite,
}

/// A piece of an input edge between consecutive graph vertices.
#[derive(Clone, Copy, Debug)]
struct SubEdge {
    from: usize,
    to: usize,
    /// 0: subject, 1: clip.
    owner: u8,
    class: Class,
}

/// The split polygons: the seed's "crossing points replaced with vertices".
struct Graph {
    points: Vec<DVec2>,
    edges: Vec<SubEdge>,
}

/// Graph vertices by exact coordinates.
struct Points {
    points: Vec<DVec2>,
    ids: HashMap<(u64, u64), usize>,
}

impl Points {
    fn id(&mut self, p: DVec2) -> usize {
        let p = p + DVec2::ZERO; // -0.0 → 0.0
        let key = (p.x.to_bits(), p.y.to_bits());
        let next = self.points.len();
        *self.ids.entry(key).or_insert_with(|| {
            self.points.push(p);
            next
        })
    }
}

impl Graph {
    fn build(a: &[DVec2], b: &[DVec2]) -> Graph {
        let mut pts = Points {
            points: Vec::with_capacity(a.len() + b.len()),
            ids: HashMap::new(),
        };
        let ida: Vec<usize> = a.iter().map(|&p| pts.id(p)).collect();
        let idb: Vec<usize> = b.iter().map(|&p| pts.id(p)).collect();
        // Split points of every edge (besides its ends).
        let mut split_a: Vec<Vec<usize>> = vec![Vec::new(); a.len()];
        let mut split_b: Vec<Vec<usize>> = vec![Vec::new(); b.len()];
        let (na, nb) = (a.len(), b.len());
        for i in 0..na {
            let (p0, p1) = (a[i], a[(i + 1) % na]);
            for j in 0..nb {
                let (q0, q1) = (b[j], b[(j + 1) % nb]);
                match meet(p0, p1, q0, q1) {
                    Meet::None => {}
                    Meet::Cross(x) => {
                        let id = pts.id(x);
                        split_a[i].push(id);
                        split_b[j].push(id);
                    }
                    Meet::Touch(on) => {
                        if on[0] {
                            split_a[i].push(idb[j]);
                        }
                        if on[1] {
                            split_a[i].push(idb[(j + 1) % nb]);
                        }
                        if on[2] {
                            split_b[j].push(ida[i]);
                        }
                        if on[3] {
                            split_b[j].push(ida[(i + 1) % na]);
                        }
                    }
                }
            }
        }
        let mut edges = Vec::new();
        sub_edges(&pts.points, &ida, &mut split_a, 0, &mut edges);
        sub_edges(&pts.points, &idb, &mut split_b, 1, &mut edges);
        // Shared sub-edges: the same pair of vertices in both polygons.
        let mut of_b: HashMap<(usize, usize), usize> = HashMap::new();
        for (k, e) in edges.iter().enumerate() {
            if e.owner == 1 {
                of_b.insert((e.from, e.to), k);
            }
        }
        let mut shared = vec![None; edges.len()];
        for (k, e) in edges.iter().enumerate() {
            if e.owner != 0 {
                continue;
            }
            if let Some(&m) = of_b.get(&(e.from, e.to)) {
                shared[k] = Some(Class::SharedSame);
                shared[m] = Some(Class::SharedSame);
            } else if let Some(&m) = of_b.get(&(e.to, e.from)) {
                shared[k] = Some(Class::SharedOpposite);
                shared[m] = Some(Class::SharedOpposite);
            }
        }
        for (e, s) in edges.iter_mut().zip(shared) {
            e.class = s.unwrap_or_else(|| {
                let mid = 0.5 * (pts.points[e.from] + pts.points[e.to]);
                let other = if e.owner == 0 { b } else { a };
                if contains(other, mid) {
                    Class::Inside
                } else {
                    Class::Outside
                }
            });
        }
        Graph {
            points: pts.points,
            edges,
        }
    }

    /// The selected boundary of `op`, as directed (from, to) pairs.
    fn select(&self, op: Op) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for e in &self.edges {
            let keep = match (op, e.owner, e.class) {
                (Op::Intersection, _, Class::Inside) => Some(false),
                (Op::Intersection, 0, Class::SharedSame) => Some(false),
                (Op::Difference, 0, Class::Outside) => Some(false),
                (Op::Difference, 0, Class::SharedOpposite) => Some(false),
                (Op::Difference, 1, Class::Inside) => Some(true),
                _ => None,
            };
            match keep {
                Some(false) => out.push((e.from, e.to)),
                Some(true) => out.push((e.to, e.from)),
                None => {}
            }
        }
        out
    }

    fn result(&self, op: Op) -> Vec<Piece> {
        let loops = trace(&self.points, &self.select(op));
        assemble(loops)
    }
}

/// Cut each edge of a ring at its split points (sorted along it) into sub-edges.
fn sub_edges(
    points: &[DVec2],
    ids: &[usize],
    splits: &mut [Vec<usize>],
    owner: u8,
    out: &mut Vec<SubEdge>,
) {
    let n = ids.len();
    for i in 0..n {
        let (s, t) = (ids[i], ids[(i + 1) % n]);
        let (p0, p1) = (points[s], points[t]);
        let dir = p1 - p0;
        let list = &mut splits[i];
        list.retain(|&v| v != s && v != t);
        list.sort_by(|&u, &v| {
            let (du, dv) = ((points[u] - p0).dot(dir), (points[v] - p0).dot(dir));
            du.total_cmp(&dv).then(u.cmp(&v))
        });
        list.dedup();
        let mut from = s;
        for &v in list.iter().chain(std::iter::once(&t)) {
            out.push(SubEdge {
                from,
                to: v,
                owner,
                class: Class::Outside,
            });
            from = v;
        }
    }
}

/// Whether `p` lies inside a ring (crossing number; `p` is assumed off its boundary).
fn contains(ring: &[DVec2], p: DVec2) -> bool {
    let n = ring.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (ring[j], ring[i]);
        if (a.y > p.y) != (b.y > p.y) {
            // Which side of a→b, by the sign of an orientation test (no division).
            let o = orient(a, b, p);
            if (o > 0.0) == (b.y > a.y) {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Clockwise angle from direction `d` to direction `w`, in (0, 2π].
fn clockwise(d: DVec2, w: DVec2) -> f64 {
    let a = d.y.atan2(d.x) - w.y.atan2(w.x);
    let a = a.rem_euclid(TAU);
    if a <= 0.0 {
        TAU
    } else {
        a
    }
}

/// Link the selected directed edges into closed loops, taking at each vertex the edge first
/// clockwise from the way back (the smallest face).
fn trace(points: &[DVec2], edges: &[(usize, usize)]) -> Vec<Vec<DVec2>> {
    let mut out_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, &(from, _)) in edges.iter().enumerate() {
        out_of.entry(from).or_default().push(k);
    }
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut ring = vec![edges[start].0];
        let mut cur = start;
        let mut closed = false;
        for _ in 0..=edges.len() {
            let (from, v) = edges[cur];
            let back = points[from] - points[v];
            let mut best: Option<(f64, usize)> = None;
            for &k in out_of.get(&v).map(Vec::as_slice).unwrap_or(&[]) {
                if used[k] && k != start {
                    continue;
                }
                let ang = clockwise(back, points[edges[k].1] - points[v]);
                if best.is_none_or(|(b, _)| ang < b) {
                    best = Some((ang, k));
                }
            }
            let Some((_, next)) = best else { break };
            if next == start {
                closed = true;
                break;
            }
            used[next] = true;
            ring.push(v);
            cur = next;
        }
        if closed {
            loops.push(ring);
        }
    }
    loops
        .into_iter()
        .map(|ring| ring.into_iter().map(|v| points[v]).collect())
        .collect()
}

/// Counter-clockwise loops become pieces; clockwise loops the holes of the smallest piece
/// containing them. Loops of zero area are dropped.
fn assemble(loops: Vec<Vec<DVec2>>) -> Vec<Piece> {
    let mut pieces: Vec<(f64, Piece)> = Vec::new();
    let mut holes: Vec<Vec<DVec2>> = Vec::new();
    for ring in loops {
        let area = signed_area(&ring);
        if area > 0.0 {
            pieces.push((
                area,
                Piece {
                    outer: ring,
                    holes: Vec::new(),
                },
            ));
        } else if area < 0.0 {
            holes.push(ring);
        }
    }
    for hole in holes {
        // A point strictly inside the hole's outline's neighbourhood: the midpoint of an edge
        // (the hole meets no outline: it would have been linked into it).
        let probe = 0.5 * (hole[0] + hole[1]);
        let owner = pieces
            .iter_mut()
            .filter(|(_, p)| contains(&p.outer, probe))
            .min_by(|(a, _), (b, _)| a.total_cmp(b));
        if let Some((_, piece)) = owner {
            piece.holes.push(hole);
        }
    }
    pieces.into_iter().map(|(_, p)| p).collect()
}
