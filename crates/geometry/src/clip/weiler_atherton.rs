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
//!    of one polygon lying on an edge of the other is the *same* node (the input vertex,
//!    exactly, no computed crossing), and collinear overlapping edges are split at each other's
//!    ends, so an overlap becomes the same pair of nodes in both polygons. A proper crossing is
//!    a node of its own, named by its pair of edges (no other edge of two simple polygons
//!    passes through it), shared by both edges; its rounded coordinates are only for the
//!    output. Input vertices are identified by their exact coordinates. The split points of an
//!    edge are ordered along it exactly.
//! 3. **Classify** each piece of edge ("sub-edge"): *shared* when the other polygon has the
//!    same sub-edge, in the same or the opposite direction; otherwise *inside* or *outside*
//!    the other polygon as a whole (its open interior meets the other boundary nowhere),
//!    decided where it starts, from the input coordinates alone: at a vertex of the other
//!    polygon, whether the edge points into its angle there; inside an edge of the other
//!    polygon (a crossing, a vertex on that edge), whether it points to that edge's left; off
//!    the other boundary (a vertex of its own polygon), whether that vertex is inside.
//! 4. **Select** the boundary of the result: for the intersection A ∩ B, the sub-edges of A
//!    inside B, of B inside A, and shared edges running the same way (once); for the
//!    difference A − B, those of A outside B, of B inside A *reversed*, and shared edges of A
//!    running against B. Both come from the same graph ([`clip`]).
//! 5. **Trace** the selected edges into closed loops. Where several selected edges leave a
//!    vertex (pieces touching at a point), the loop takes the one turning most sharply left
//!    of the way it came, the first clockwise from the reversed incoming direction: the
//!    smallest face. That is the "change links at vertices" of the seed. Directions are those
//!    of the input edges, compared exactly.
//! 6. **Assemble**: loops are pieces, counter-clockwise, except a loop made only of reversed
//!    clip edges: only a difference has them (the clip polygon strictly inside the subject),
//!    and they are holes of the smallest piece that contains them.
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
//! Every decision is exact for any finite `f64` input, however near-degenerate: the tests are
//! orientations and turns of input points and directions, and the order of split points along
//! an edge, all computed in `f64` with an error bound and recomputed in exact arithmetic when
//! the rounded value is within it (`weiler_atherton/predicates.rs`: Shewchuk's filter;
//! `weiler_atherton/exact.rs`: dyadic numbers). A vertex 10⁻²⁰ from an edge 10⁶ long is off it, and on the side it is on, in
//! every test; an exact touch is a touch. Rounding enters only where a crossing's coordinates
//! are written out (to within a few units in the last place of the coordinates, inside both
//! edges' bounding boxes); the topology of the result never depends on them. A piece thinner
//! than that rounding may come out with an area of 0 or of the wrong sign, and one whose
//! rounded vertices collapse below 3 distinct points is dropped.
//!
//! Before the exact predicates, near-degenerate input (found by the fuzz target, e.g. the
//! vertex (7.8·10⁻²⁰, 0) of an edge ending at (0, 4·10⁵) beside a triangle with a vertex at the
//! origin) was decided by rounded signs that contradicted each other, and whole pieces were
//! lost, or B ∩ A came out empty while A ∩ B did not.

mod exact;
mod predicates;

use std::cmp::Ordering;
use std::collections::HashMap;

use glam::DVec2;

use predicates::{
    compare_along, cross, crossing_parameter, orient, point_at, same_direction, within, Split,
};

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
    if clockwise_ring(&ring) {
        ring.reverse();
    }
    Ok(ring)
}

/// Whether a simple ring runs clockwise, by the exact turn at its lowest (then leftmost)
/// vertex: a simple polygon is convex there, and the turn is never straight (a neighbour
/// in line would be lower or further left). The sign of the shoelace sum would do in exact
/// arithmetic; rounded, it is 0 or wrong for slivers.
fn clockwise_ring(ring: &[DVec2]) -> bool {
    let n = ring.len();
    let lowest = (0..n)
        .min_by(|&i, &j| {
            let (a, b) = (ring[i], ring[j]);
            a.y.total_cmp(&b.y).then(a.x.total_cmp(&b.x))
        })
        .unwrap_or(0);
    let (u, v, w) = (
        ring[(lowest + n - 1) % n],
        ring[lowest],
        ring[(lowest + 1) % n],
    );
    orient(u, v, w) == Ordering::Less
}

/// How two segments p0–p1 and q0–q1 meet.
enum Meet {
    None,
    /// Cross at one point interior to both.
    Cross,
    /// Touch or overlap: the endpoints of each lying on the other, as
    /// `[q0 on p, q1 on p, p0 on q, p1 on q]`.
    Touch([bool; 4]),
}

/// How two segments meet, from exact orientations: a touch is a touch however close the
/// numbers, and a crossing is interior to both segments.
fn meet(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Meet {
    // Bounding boxes first: cheap, exact, and makes `within` below a containment test.
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
    let zero = Ordering::Equal;
    if o1 != zero && o2 != zero && o3 != zero && o4 != zero {
        if o1 != o2 && o3 != o4 {
            return Meet::Cross;
        }
        return Meet::None;
    }
    let on = [
        o1 == zero && within(p0, p1, q0),
        o2 == zero && within(p0, p1, q1),
        o3 == zero && within(q0, q1, p0),
        o4 == zero && within(q0, q1, p1),
    ];
    if on.iter().any(|&b| b) {
        Meet::Touch(on)
    } else {
        Meet::None
    }
}

/// Where p0–p1 crosses q0–q1 (they do), rounded.
fn crossing_point(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> DVec2 {
    point_at(p0, p1, crossing_parameter(p0, p1, q0, q1)).clamp(q0.min(q1), q0.max(q1))
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
        if orient(a, b, c) == Ordering::Equal && same_direction(b, c, b, a) {
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
                Meet::Cross => return Err(err(i, j, crossing_point(a, b, c, d))),
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

/// A point of the graph: an input vertex (of one polygon or both) or a crossing, with where
/// it lies on each polygon's boundary. Index 0 is the subject, 1 the clip polygon.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Its coordinates: exact for a vertex, rounded for a crossing (which is identified by
    /// its pair of edges, never by its coordinates).
    at: DVec2,
    /// Which vertex of each polygon it is.
    vertex: [Option<usize>; 2],
    /// Which edge of each polygon it lies inside of (strictly between the edge's ends).
    edge: [Option<usize>; 2],
}

/// A piece of an input edge between consecutive graph nodes; it runs the way its edge does.
#[derive(Clone, Copy, Debug)]
struct SubEdge {
    from: usize,
    to: usize,
    /// 0: subject, 1: clip.
    owner: usize,
    /// The input edge it is part of.
    edge: usize,
    class: Class,
}

/// A selected edge of a result's boundary, directed as the result runs.
#[derive(Clone, Copy, Debug)]
struct Directed {
    from: usize,
    to: usize,
    /// Two input points whose difference is its direction (exact, unlike the rounded ends
    /// of a piece between crossings).
    dir: (DVec2, DVec2),
    /// Whether it runs against its input edge (the clip polygon's, in a difference).
    reversed: bool,
}

/// The split polygons: the seed's "crossing points replaced with vertices".
struct Graph<'a> {
    rings: [&'a [DVec2]; 2],
    nodes: Vec<Node>,
    edges: Vec<SubEdge>,
}

impl<'a> Graph<'a> {
    fn build(a: &'a [DVec2], b: &'a [DVec2]) -> Graph<'a> {
        let rings = [a, b];
        let mut nodes: Vec<Node> = Vec::with_capacity(a.len() + b.len());
        // Input vertices by exact coordinates: a vertex of both polygons is one node.
        let mut by_point: HashMap<(u64, u64), usize> = HashMap::new();
        let mut ids: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
        for (k, ring) in rings.iter().enumerate() {
            for (i, &p) in ring.iter().enumerate() {
                let next = nodes.len();
                let id = *by_point
                    .entry((p.x.to_bits(), p.y.to_bits()))
                    .or_insert(next);
                if id == next {
                    nodes.push(Node {
                        at: p,
                        vertex: [None, None],
                        edge: [None, None],
                    });
                }
                nodes[id].vertex[k] = Some(i);
                ids[k].push(id);
            }
        }
        // Split points of every edge (besides its ends), with where they lie along it.
        let mut splits: [Vec<Vec<(usize, Split, f64)>>; 2] =
            [vec![Vec::new(); a.len()], vec![Vec::new(); b.len()]];
        let (na, nb) = (a.len(), b.len());
        for i in 0..na {
            let (p0, p1) = (a[i], a[(i + 1) % na]);
            for j in 0..nb {
                let (q0, q1) = (b[j], b[(j + 1) % nb]);
                match meet(p0, p1, q0, q1) {
                    Meet::None => {}
                    Meet::Cross => {
                        // A crossing is interior to both edges, so no other pair of edges
                        // (of simple polygons) passes through it: a node of its own.
                        let (ta, tb) = (
                            crossing_parameter(p0, p1, q0, q1),
                            crossing_parameter(q0, q1, p0, p1),
                        );
                        let id = nodes.len();
                        nodes.push(Node {
                            at: point_at(p0, p1, ta).clamp(q0.min(q1), q0.max(q1)),
                            vertex: [None, None],
                            edge: [Some(i), Some(j)],
                        });
                        splits[0][i].push((id, Split::Crossing(q0, q1), ta));
                        splits[1][j].push((id, Split::Crossing(p0, p1), tb));
                    }
                    Meet::Touch(on) => {
                        // A vertex of one polygon on an edge of the other: the same node in
                        // both, splitting that edge unless it is one of the edge's ends.
                        let touching = [
                            (on[0], 1, j, 0, i),
                            (on[1], 1, (j + 1) % nb, 0, i),
                            (on[2], 0, i, 1, j),
                            (on[3], 0, (i + 1) % na, 1, j),
                        ];
                        for (is_on, kv, v, ke, e) in touching {
                            if !is_on {
                                continue;
                            }
                            let id = ids[kv][v];
                            let ring = rings[ke];
                            let (e0, e1) = (ring[e], ring[(e + 1) % ring.len()]);
                            if id == ids[ke][e] || id == ids[ke][(e + 1) % ring.len()] {
                                continue;
                            }
                            nodes[id].edge[ke] = Some(e);
                            let at = Split::Vertex(rings[kv][v]);
                            splits[ke][e].push((id, at, at.approximate(e0, e1)));
                        }
                    }
                }
            }
        }
        let mut edges = Vec::new();
        for (k, ring) in rings.iter().enumerate() {
            sub_edges(ring, &ids[k], &mut splits[k], k, &mut edges);
        }
        let mut graph = Graph {
            rings,
            nodes,
            edges,
        };
        graph.classify();
        graph
    }

    /// Classify every sub-edge: shared when the other polygon has the same pair of nodes;
    /// otherwise by where it starts ([`Graph::leaves_into`]).
    fn classify(&mut self) {
        let mut of_b: HashMap<(usize, usize), usize> = HashMap::new();
        for (k, e) in self.edges.iter().enumerate() {
            if e.owner == 1 {
                of_b.insert((e.from, e.to), k);
            }
        }
        let mut classes: Vec<Option<Class>> = vec![None; self.edges.len()];
        for (k, e) in self.edges.iter().enumerate() {
            if e.owner != 0 {
                continue;
            }
            if let Some(&m) = of_b.get(&(e.from, e.to)) {
                classes[k] = Some(Class::SharedSame);
                classes[m] = Some(Class::SharedSame);
            } else if let Some(&m) = of_b.get(&(e.to, e.from)) {
                classes[k] = Some(Class::SharedOpposite);
                classes[m] = Some(Class::SharedOpposite);
            }
        }
        for (k, class) in classes.into_iter().enumerate() {
            let e = self.edges[k];
            self.edges[k].class = class.unwrap_or_else(|| {
                if self.leaves_into(&e) {
                    Class::Inside
                } else {
                    Class::Outside
                }
            });
        }
    }

    /// The ends of edge `e` of polygon `k`.
    fn ends(&self, k: usize, e: usize) -> (DVec2, DVec2) {
        let ring = self.rings[k];
        (ring[e], ring[(e + 1) % ring.len()])
    }

    /// Whether a sub-edge (not shared) runs inside the other polygon. Its open interior meets
    /// the other boundary nowhere (every meeting is a node), so it is inside or outside as a
    /// whole, as just after its start. Decided there, from input coordinates only:
    ///
    /// * the start is a vertex of the other polygon: whether the edge's direction points into
    ///   the angle of the other polygon at that vertex;
    /// * it lies inside an edge of the other polygon (a crossing, or a vertex on that edge):
    ///   whether the direction points to the left of that edge (both run counter-clockwise);
    /// * it is off the other boundary (a vertex of this polygon): whether it is inside.
    fn leaves_into(&self, e: &SubEdge) -> bool {
        let other = 1 - e.owner;
        let (d0, d1) = self.ends(e.owner, e.edge);
        let start = &self.nodes[e.from];
        if let Some(v) = start.vertex[other] {
            let ring = self.rings[other];
            let n = ring.len();
            let (u, v, w) = (ring[(v + n - 1) % n], ring[v], ring[(v + 1) % n]);
            // The angle runs counter-clockwise from v→w round to v→u.
            let left_of_out = cross(v, w, d0, d1) == Ordering::Greater;
            let right_of_in = cross(d0, d1, v, u) == Ordering::Greater;
            match orient(u, v, w) {
                // Convex: inside both half-planes. Reflex: inside either.
                Ordering::Greater => left_of_out && right_of_in,
                Ordering::Less => left_of_out || right_of_in,
                // Straight through: the half-plane left of the line.
                Ordering::Equal => left_of_out,
            }
        } else if let Some(g) = start.edge[other] {
            let (g0, g1) = self.ends(other, g);
            cross(g0, g1, d0, d1) == Ordering::Greater
        } else {
            contains(self.rings[other], start.at)
        }
    }

    /// The selected boundary of `op`, directed.
    fn select(&self, op: Op) -> Vec<Directed> {
        let mut out = Vec::new();
        for e in &self.edges {
            let reverse = match (op, e.owner, e.class) {
                (Op::Intersection, _, Class::Inside) => Some(false),
                (Op::Intersection, 0, Class::SharedSame) => Some(false),
                (Op::Difference, 0, Class::Outside) => Some(false),
                (Op::Difference, 0, Class::SharedOpposite) => Some(false),
                (Op::Difference, 1, Class::Inside) => Some(true),
                _ => None,
            };
            let (d0, d1) = self.ends(e.owner, e.edge);
            match reverse {
                Some(false) => out.push(Directed {
                    from: e.from,
                    to: e.to,
                    dir: (d0, d1),
                    reversed: false,
                }),
                Some(true) => out.push(Directed {
                    from: e.to,
                    to: e.from,
                    dir: (d1, d0),
                    reversed: true,
                }),
                None => {}
            }
        }
        out
    }

    fn result(&self, op: Op) -> Vec<Piece> {
        let loops = trace(&self.select(op));
        let points =
            |ring: &[usize]| -> Vec<DVec2> { ring.iter().map(|&v| self.nodes[v].at).collect() };
        assemble(
            loops
                .iter()
                .map(|(ring, forward)| (points(ring), *forward))
                .collect(),
        )
    }
}

/// Cut each edge of a ring at its split points (sorted along it) into sub-edges.
fn sub_edges(
    ring: &[DVec2],
    ids: &[usize],
    splits: &mut [Vec<(usize, Split, f64)>],
    owner: usize,
    out: &mut Vec<SubEdge>,
) {
    let n = ids.len();
    for i in 0..n {
        let (s, t) = (ids[i], ids[(i + 1) % n]);
        let (e0, e1) = (ring[i], ring[(i + 1) % n]);
        let list = &mut splits[i];
        list.sort_by(|x, y| compare_along(e0, e1, (x.1, x.2), (y.1, y.2)).then(x.0.cmp(&y.0)));
        // A vertex on two edges of the other polygon (their shared end) is listed twice.
        list.dedup_by_key(|x| x.0);
        let mut from = s;
        for v in list.iter().map(|x| x.0).chain(std::iter::once(t)) {
            out.push(SubEdge {
                from,
                to: v,
                owner,
                edge: i,
                class: Class::Outside,
            });
            from = v;
        }
    }
}

/// Whether `p` lies inside a ring (crossing number with exact orientations; `p` is assumed
/// off its boundary).
fn contains(ring: &[DVec2], p: DVec2) -> bool {
    let n = ring.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (ring[j], ring[i]);
        if (a.y > p.y) != (b.y > p.y) {
            // The ray to the right of p crosses a→b when p is on the side of it that faces
            // the ray: left of an upward edge, right of a downward one.
            let left = orient(a, b, p) == Ordering::Greater;
            if left == (b.y > a.y) {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Where direction `w` lies going clockwise from `back`, coarsely: in (0, π), at π, in
/// (π, 2π), or at 2π (the same direction as `back`).
fn clockwise_quarter(back: (DVec2, DVec2), w: (DVec2, DVec2)) -> u8 {
    match cross(back.0, back.1, w.0, w.1) {
        Ordering::Less => 0,
        Ordering::Equal if !same_direction(back.0, back.1, w.0, w.1) => 1,
        Ordering::Greater => 2,
        Ordering::Equal => 3,
    }
}

/// The order of directions `x` and `y` going clockwise from `back` (from just past it, round
/// to itself), with exact turn tests.
fn clockwise_order(back: (DVec2, DVec2), x: (DVec2, DVec2), y: (DVec2, DVec2)) -> Ordering {
    clockwise_quarter(back, x)
        .cmp(&clockwise_quarter(back, y))
        .then_with(|| {
            // Within one half-turn, y comes later when it is clockwise from x (x × y < 0).
            cross(x.0, x.1, y.0, y.1)
        })
}

/// Link the selected directed edges into closed loops, taking at each node the edge first
/// clockwise from the way back (the smallest face). Each loop comes with whether it has an
/// edge running the way of its input edge.
fn trace(edges: &[Directed]) -> Vec<(Vec<usize>, bool)> {
    let mut out_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, e) in edges.iter().enumerate() {
        out_of.entry(e.from).or_default().push(k);
    }
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut ring = vec![edges[start].from];
        let mut forward = !edges[start].reversed;
        let mut cur = start;
        let mut closed = false;
        for _ in 0..=edges.len() {
            let here = edges[cur];
            let back = (here.dir.1, here.dir.0);
            let next = out_of
                .get(&here.to)
                .map(Vec::as_slice)
                .unwrap_or(&[])
                .iter()
                .copied()
                .filter(|&k| !used[k] || k == start)
                .min_by(|&x, &y| clockwise_order(back, edges[x].dir, edges[y].dir).then(x.cmp(&y)));
            let Some(next) = next else { break };
            if next == start {
                closed = true;
                break;
            }
            used[next] = true;
            forward |= !edges[next].reversed;
            ring.push(here.to);
            cur = next;
        }
        if closed {
            loops.push((ring, forward));
        }
    }
    loops
}

/// Loops with an edge running its input edge's way become pieces (counter-clockwise: both
/// inputs are, and the regions lie on the left). A loop of reversed edges alone is made of
/// the clip polygon's edges in a difference: its whole boundary, clockwise, strictly inside
/// the subject (touching it, the tracing joins it to the outline): a hole, of the smallest
/// piece containing it. Decided by the graph, not by the sign of a rounded area.
/// A ring whose rounded crossings collapse it below 3 distinct points (a piece far thinner
/// than the coordinates' last bit) is dropped.
fn assemble(loops: Vec<(Vec<DVec2>, bool)>) -> Vec<Piece> {
    let mut pieces: Vec<(f64, Piece)> = Vec::new();
    let mut holes: Vec<Vec<DVec2>> = Vec::new();
    for (mut ring, forward) in loops {
        ring.dedup();
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            continue;
        }
        if forward {
            let area = signed_area(&ring);
            pieces.push((
                area,
                Piece {
                    outer: ring,
                    holes: Vec::new(),
                },
            ));
        } else {
            holes.push(ring);
        }
    }
    for hole in holes {
        // Its vertices are the clip polygon's, none on the subject's boundary.
        let probe = hole[0];
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
