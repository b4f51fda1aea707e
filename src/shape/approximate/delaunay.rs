//! Delaunay triangulation of the pins in material space, for choosing local
//! candidate catenaries when there are many pins.
//!
//! Points are grid indices; material space scales them by the grid spacing
//! per axis. Orientation tests are exact integer arithmetic on grid indices
//! (the scaling changes no orientation). The in-circle test is exact when the
//! grid cells are square; otherwise a quad is flipped only when its fourth
//! point is inside the circle by more than the rounding of the test, so
//! near-cocircular quads keep whichever diagonal they have. Either diagonal is
//! fine for the caller, which considers both.
//!
//! The points are inserted in lexicographic order of (i, j), so each new
//! point lies outside the hull so far and sees an edge at the previous point;
//! Lawson flips restore the Delaunay property after each insertion. Pins that
//! lie on a hull edge stay hull vertices, so every hull edge joins two
//! neighbouring pins.

/// No twin: the half-edge lies on the hull.
pub(super) const NONE: usize = usize::MAX;

/// Twice the signed area of (o, a, b) on integer grid points: positive when counter-clockwise, exact.
pub(super) fn cross_i64(o: (i64, i64), a: (i64, i64), b: (i64, i64)) -> i64 {
    (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
}

/// A triangulation as half-edges, three per triangle: half-edge `e` runs from
/// vertex `start[e]` to `start[next(e)]`; its triangle's vertices turn
/// counter-clockwise in (i, j) (positive [`cross_i64`]).
pub(super) struct Triangulation {
    /// Start vertex (an index into the points) of each half-edge.
    pub(super) start: Vec<usize>,
    /// The opposite half-edge, or [`NONE`] on the hull.
    pub(super) twin: Vec<usize>,
}

/// The next half-edge around the same triangle.
pub(super) fn next(e: usize) -> usize {
    if e % 3 == 2 { e - 2 } else { e + 1 }
}

/// The previous half-edge around the same triangle.
pub(super) fn prev(e: usize) -> usize {
    if e.is_multiple_of(3) { e + 2 } else { e - 1 }
}

/// The Delaunay triangulation (in material space, `spacing_v / spacing_u` the
/// cells' aspect) of distinct grid points, or `None` when they are fewer than
/// three or all on one line.
pub(super) fn triangulate(points: &[(i64, i64)], aspect: f64) -> Option<Triangulation> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_unstable_by_key(|&k| points[k]);
    if order.len() < 3 {
        return None;
    }
    let (first, second) = (points[order[0]], points[order[1]]);
    let apex_at = (2..order.len()).find(|&k| cross_i64(first, second, points[order[k]]) != 0)?;
    let mut builder = Builder::new(points, aspect * aspect);
    builder.fan(&order[..apex_at], order[apex_at]);
    for &p in &order[apex_at + 1..] {
        builder.insert(p);
    }
    Some(Triangulation { start: builder.start, twin: builder.twin })
}

impl Triangulation {
    /// The Delaunay subdivision: a face number (from 0) per triangle. Triangles
    /// that share an edge and a circumcircle are one face — a convex polygon
    /// with its vertices on that circle (four corners of a lattice cell, or of
    /// a mirror-symmetric trapezoid), which every Delaunay triangulation has
    /// and which only the choice of its diagonals tells apart.
    pub(super) fn faces(&self, points: &[(i64, i64)], aspect: f64) -> Vec<usize> {
        let triangles = self.start.len() / 3;
        let mut parent: Vec<usize> = (0..triangles).collect();
        fn root(parent: &mut [usize], mut t: usize) -> usize {
            while parent[t] != t {
                parent[t] = parent[parent[t]];
                t = parent[t];
            }
            t
        }
        for e in 0..self.start.len() {
            let twin = self.twin[e];
            if twin == NONE || twin < e {
                continue;
            }
            let quad = [self.start[e], self.start[next(e)], self.start[prev(e)], self.start[prev(twin)]];
            if in_circle(points, aspect * aspect, quad) == 0 {
                let (a, b) = (root(&mut parent, e / 3), root(&mut parent, twin / 3));
                parent[a.max(b)] = a.min(b);
            }
        }
        let mut number = vec![NONE; triangles];
        let mut faces = 0;
        (0..triangles)
            .map(|t| {
                let r = root(&mut parent, t);
                if number[r] == NONE {
                    number[r] = faces;
                    faces += 1;
                }
                number[r]
            })
            .collect()
    }
}

/// Whether `d` lies inside (1), on (0) or outside (−1) the material-space
/// circle through the counter-clockwise triangle (a, b, c), where `aspect2` =
/// (spacing_v / spacing_u)². Exact for square cells; otherwise 0 stands for
/// "within rounding of the circle".
fn in_circle(points: &[(i64, i64)], aspect2: f64, [a, b, c, d]: [usize; 4]) -> i8 {
    let pd = points[d];
    let rel = |k: usize| {
        let p = points[k];
        ((p.0 - pd.0) as i128, (p.1 - pd.1) as i128)
    };
    let (a, b, c) = (rel(a), rel(b), rel(c));
    // det[[x, y, x² + ρ·y²]] over the three rows = A + ρ·B.
    let det = |za: i128, zb: i128, zc: i128| {
        za * (b.0 * c.1 - c.0 * b.1) - zb * (a.0 * c.1 - c.0 * a.1) + zc * (a.0 * b.1 - b.0 * a.1)
    };
    let along_i = det(a.0 * a.0, b.0 * b.0, c.0 * c.0);
    let along_j = det(a.1 * a.1, b.1 * b.1, c.1 * c.1);
    if aspect2 == 1.0 {
        return (along_i + along_j).signum() as i8;
    }
    let (i, j) = (along_i as f64, along_j as f64 * aspect2);
    let rounding = 4.0 * f64::EPSILON * (i.abs() + j.abs());
    if i + j > rounding {
        1
    } else if i + j < -rounding {
        -1
    } else {
        0
    }
}

struct Builder<'a> {
    points: &'a [(i64, i64)],
    /// (spacing_v / spacing_u)²: material in-circle = grid in-circle with j² weighted by it.
    aspect2: f64,
    start: Vec<usize>,
    twin: Vec<usize>,
    /// The hull, counter-clockwise, as a linked list of vertices.
    hull_next: Vec<usize>,
    hull_prev: Vec<usize>,
    /// For a hull vertex v, the half-edge from v to `hull_next[v]`.
    hull_edge: Vec<usize>,
    /// The last point inserted (the lexicographically largest so far).
    last: usize,
    stack: Vec<usize>,
}

impl<'a> Builder<'a> {
    fn new(points: &'a [(i64, i64)], aspect2: f64) -> Self {
        let n = points.len();
        Builder {
            points,
            aspect2,
            start: Vec::with_capacity(6 * n),
            twin: Vec::with_capacity(6 * n),
            hull_next: vec![NONE; n],
            hull_prev: vec![NONE; n],
            hull_edge: vec![NONE; n],
            last: NONE,
            stack: Vec::new(),
        }
    }

    fn cross(&self, o: usize, a: usize, b: usize) -> i64 {
        cross_i64(self.points[o], self.points[a], self.points[b])
    }

    /// Adds triangle (a, b, c), counter-clockwise; returns its first half-edge (a→b).
    fn triangle(&mut self, a: usize, b: usize, c: usize) -> usize {
        debug_assert!(self.cross(a, b, c) > 0);
        let e = self.start.len();
        self.start.extend([a, b, c]);
        self.twin.extend([NONE; 3]);
        e
    }

    fn link(&mut self, a: usize, b: usize) {
        self.twin[a] = b;
        if b != NONE {
            self.twin[b] = a;
        }
    }

    /// The first triangles: `line` (two or more collinear points in
    /// lexicographic order) joined to `apex`, off their line.
    fn fan(&mut self, line: &[usize], apex: usize) {
        let left = self.cross(line[0], line[1], apex) > 0;
        let count = line.len() - 1;
        for m in 0..count {
            let (a, b) = (line[m], line[m + 1]);
            if left {
                // a→b on the hull, b→apex shared with the next triangle, apex→a.
                let e = self.triangle(a, b, apex);
                self.hull_edge[a] = e;
                if m > 0 {
                    self.link(e + 2, e - 2);
                }
            } else {
                // b→a on the hull, a→apex shared with the previous triangle, apex→b.
                let e = self.triangle(b, a, apex);
                self.hull_edge[b] = e;
                if m > 0 {
                    self.link(e + 1, e - 1);
                }
            }
        }
        let (first, last) = (line[0], line[count]);
        let last_e = 3 * (count - 1);
        if left {
            // first → … → last → apex → first.
            for m in 0..count {
                self.hull_next[line[m]] = line[m + 1];
                self.hull_prev[line[m + 1]] = line[m];
            }
            self.set_hull(last, apex, last_e + 1);
            self.set_hull(apex, first, 2);
        } else {
            // first → apex → last → … → first.
            for m in 0..count {
                self.hull_next[line[m + 1]] = line[m];
                self.hull_prev[line[m]] = line[m + 1];
            }
            self.set_hull(first, apex, 1);
            self.set_hull(apex, last, last_e + 2);
        }
        self.last = apex;
        for m in 0..count.saturating_sub(1) {
            let spoke = if left { 3 * m + 1 } else { 3 * m + 2 };
            self.legalize(spoke);
        }
    }

    fn set_hull(&mut self, from: usize, to: usize, edge: usize) {
        self.hull_next[from] = to;
        self.hull_prev[to] = from;
        self.hull_edge[from] = edge;
    }

    /// Whether hull edge v → next(v) has `p` strictly outside.
    fn sees(&self, v: usize, p: usize) -> bool {
        self.cross(v, self.hull_next[v], p) < 0
    }

    /// Adds `p`, lexicographically after every point so far (so outside the hull).
    fn insert(&mut self, p: usize) {
        // The previous point is the hull's lexicographic maximum; one of its two
        // hull edges faces p. Walk back and forth to the ends of the visible chain.
        let mut first = if self.sees(self.last, p) { self.last } else { self.hull_prev[self.last] };
        assert!(self.sees(first, p), "a point after all others sees the hull at the previous one");
        while self.sees(self.hull_prev[first], p) {
            first = self.hull_prev[first];
        }
        let mut v = first;
        let mut shared = NONE;
        let mut first_edge = NONE;
        let mut outer = Vec::new();
        loop {
            let w = self.hull_next[v];
            let e = self.triangle(v, p, w);
            let hull = self.hull_edge[v];
            self.link(e + 2, hull);
            if shared == NONE {
                first_edge = e;
            } else {
                self.link(e, shared);
            }
            shared = e + 1;
            outer.push(e + 2);
            v = w;
            if !self.sees(v, p) {
                break;
            }
        }
        self.set_hull(first, p, first_edge);
        self.set_hull(p, v, shared);
        self.last = p;
        for e in outer {
            self.legalize(e);
        }
    }

    /// Lawson flips from half-edge `e` until every edge they touch is Delaunay.
    fn legalize(&mut self, e: usize) {
        self.stack.push(e);
        while let Some(a) = self.stack.pop() {
            let b = self.twin[a];
            if b == NONE {
                continue;
            }
            // Triangle (p, q, r) on a = p→q, triangle (q, p, s) on b = q→p.
            let (an, ap, bn, bp) = (next(a), prev(a), next(b), prev(b));
            let (p, q, r, s) = (self.start[a], self.start[an], self.start[ap], self.start[bp]);
            if in_circle(self.points, self.aspect2, [p, q, r, s]) <= 0 {
                continue;
            }
            // Only a strictly convex quad can take the other diagonal.
            if self.cross(r, s, p).signum() * self.cross(r, s, q).signum() >= 0 {
                continue;
            }
            // Now (s, q, r) on a, an, ap and (r, p, s) on b, bn, bp; ap–bp is r–s.
            let (outer_ap, outer_bp) = (self.twin[ap], self.twin[bp]);
            self.start[a] = s;
            self.start[b] = r;
            self.link(a, outer_bp);
            self.link(b, outer_ap);
            self.link(ap, bp);
            if outer_bp == NONE {
                self.hull_edge[s] = a;
            }
            if outer_ap == NONE {
                self.hull_edge[r] = b;
            }
            self.stack.extend([a, an, b, bn]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Lcg(u64);
    impl Lcg {
        fn below(&mut self, n: u64) -> i64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((self.0 >> 33) % n) as i64
        }
    }

    fn distinct_points(seed: u64, count: usize, size: i64) -> Vec<(i64, i64)> {
        let mut rng = Lcg(seed);
        let mut seen = std::collections::HashSet::new();
        let mut points = Vec::new();
        while points.len() < count {
            let p = (rng.below(size as u64), rng.below(size as u64));
            if seen.insert(p) {
                points.push(p);
            }
        }
        points
    }

    /// Twice the area of the convex hull (exact).
    fn hull_area2(points: &[(i64, i64)]) -> i64 {
        let mut sorted = points.to_vec();
        sorted.sort_unstable();
        let mut hull: Vec<(i64, i64)> = Vec::new();
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &(i64, i64)>> =
                if pass == 0 { Box::new(sorted.iter()) } else { Box::new(sorted.iter().rev()) };
            for &p in iter {
                while hull.len() >= start + 2 && cross_i64(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
                    hull.pop();
                }
                hull.push(p);
            }
            hull.pop();
        }
        (1..hull.len() - 1).map(|k| cross_i64(hull[0], hull[k], hull[k + 1])).sum()
    }

    /// Checks the structure and the Delaunay property by brute force.
    fn check(points: &[(i64, i64)], aspect: f64) -> Triangulation {
        let t = triangulate(points, aspect).expect("not collinear");
        let triangles = t.start.len() / 3;
        let mut area2 = 0;
        for tri in 0..triangles {
            let [a, b, c] = [t.start[3 * tri], t.start[3 * tri + 1], t.start[3 * tri + 2]];
            let area = cross_i64(points[a], points[b], points[c]);
            assert!(area > 0, "triangle {tri} is not counter-clockwise");
            area2 += area;
            for d in 0..points.len() {
                if d != a && d != b && d != c {
                    assert!(
                        in_circle(points, aspect * aspect, [a, b, c, d]) <= 0,
                        "{d} inside the circle of {a}, {b}, {c}"
                    );
                }
            }
        }
        for e in 0..t.start.len() {
            if t.twin[e] != NONE {
                assert_eq!(t.twin[t.twin[e]], e);
                assert_eq!((t.start[t.twin[e]], t.start[next(t.twin[e])]), (t.start[next(e)], t.start[e]));
            }
        }
        assert_eq!(area2, hull_area2(points), "triangles cover the hull exactly once");
        // No edge passes through a point: every half-edge's segment holds no third point.
        for e in 0..t.start.len() {
            let (a, b) = (points[t.start[e]], points[t.start[next(e)]]);
            for &p in points {
                let inside = cross_i64(a, b, p) == 0
                    && (p.0 - a.0) * (b.0 - a.0) + (p.1 - a.1) * (b.1 - a.1) > 0
                    && (p.0 - b.0) * (a.0 - b.0) + (p.1 - b.1) * (a.1 - b.1) > 0;
                assert!(!inside, "edge {a:?}–{b:?} passes through {p:?}");
            }
        }
        t
    }

    #[test]
    fn random_points_give_a_delaunay_triangulation_of_their_hull() {
        for seed in 0..40 {
            let count = 3 + (seed as usize * 7) % 120;
            let points = distinct_points(seed, count, 12 + seed as i64);
            if points.iter().all(|&p| cross_i64(points[0], points[1], p) == 0) {
                continue;
            }
            check(&points, 1.0);
            check(&points, 1.37);
        }
    }

    #[test]
    fn a_lattice_gives_two_triangles_per_cell() {
        for (cols, rows) in [(2, 2), (5, 3), (17, 17)] {
            let points: Vec<(i64, i64)> = (0..rows).flat_map(|j| (0..cols).map(move |i| (i * 4, j * 4))).collect();
            let t = check(&points, 1.0);
            let cells = ((cols - 1) * (rows - 1)) as usize;
            assert_eq!(t.start.len() / 3, 2 * cells);
            // Each cell's four corners share a circle: one face of two triangles.
            let faces = t.faces(&points, 1.0);
            assert_eq!(faces.iter().max().unwrap() + 1, cells);
            assert!((0..cells).all(|f| faces.iter().filter(|&&g| g == f).count() == 2));
            // On cells twice as tall in material space, the corners still share a circle.
            assert_eq!(t.faces(&points, 2.0).iter().max().unwrap() + 1, cells);
        }
    }

    #[test]
    fn collinear_runs_and_points_on_hull_edges_stay_vertices() {
        // A run along the first column, then points that extend hull lines.
        let points = [(0, 0), (0, 1), (0, 2), (0, 3), (1, 1), (2, 2), (3, 3), (3, 0), (4, 0), (6, 0), (6, 3)];
        check(&points, 1.0);
        let hem: Vec<(i64, i64)> = (0..64).map(|i| (i, 0)).chain([(10, 5)]).collect();
        let t = check(&hem, 1.0);
        assert_eq!(t.start.len() / 3, 63);
        let pole: Vec<(i64, i64)> = (0..20).map(|j| (3, j)).chain([(0, 7), (9, 2)]).collect();
        check(&pole, 0.5);
    }

    #[test]
    fn collinear_or_too_few_points_have_no_triangulation() {
        assert!(triangulate(&[(0, 0), (3, 1)], 1.0).is_none());
        assert!(triangulate(&[(0, 0), (3, 1), (6, 2), (9, 3)], 1.0).is_none());
    }
}
