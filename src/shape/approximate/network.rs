//! The catenary network's combinatorics in grid space: which pins the
//! candidate catenaries join, where they cross, which survive, and the
//! layout (hull and triangles) of what is kept. Every predicate is exact
//! integer arithmetic on grid indices.
//!
//! Up to [`ALL_PAIRS_MAX_PINS`] pins every unblocked pair of pins is a
//! candidate and every two candidates are tested for a crossing, as the paper
//! describes: O(P²) candidates, O(P⁴) time and, in the worst case, memory for
//! their crossings (45 s and gigabytes for a 17 × 17 lattice of pins). Above
//! it the candidates are local (see [`local_candidates`]): the edges of the pins'
//! Delaunay subdivision and the alternatives across them — O(P) candidates
//! whose only possible crossings are known from the subdivision, so selection
//! takes O(P log P) time and O(P) memory. The paper's rule (at a crossing the
//! higher catenary stays) then decides between each edge and its
//! alternatives. Where the paper's network keeps a long catenary across many
//! shorter ones (a high pair of pins far apart over low pins between), the
//! local one keeps the short ones.

use std::collections::{HashMap, HashSet};

use glam::DVec2;

use super::delaunay::{self, NONE, cross_i64};
use super::{GridSpec, PinLayout, PinPoint};
use crate::shape::catenary::Catenary;

/// The most pins for which every pair of pins is a candidate catenary; above
/// it candidates are local (see the module doc). Up to here the network is
/// exactly the paper's; a few milliseconds at most.
pub(super) const ALL_PAIRS_MAX_PINS: usize = 24;

pub(super) fn grid_i64(p: &PinPoint) -> (i64, i64) {
    (p.grid.0 as i64, p.grid.1 as i64)
}

pub(super) fn crossing_material(grid: GridSpec, pins: &[PinPoint], (a, b): (usize, usize), t: f64) -> DVec2 {
    let ma = grid.material(pins[a].grid.0, pins[a].grid.1);
    let mb = grid.material(pins[b].grid.0, pins[b].grid.1);
    ma.lerp(mb, t)
}

/// The candidate catenaries (pin pairs `(a, b)`, `a < b`, in lexicographic
/// order) and which of them may cross.
pub(super) struct Candidates {
    pub(super) pairs: Vec<(usize, usize)>,
    /// Pairs of candidates (indices into `pairs`, first < second, sorted)
    /// that may cross; `None` when any two may.
    may_cross: Option<Vec<(usize, usize)>>,
}

/// The candidates for `pins` on `grid`: all pairs up to [`ALL_PAIRS_MAX_PINS`]
/// pins, local ones above (see the module doc).
pub(super) fn select_candidates(pins: &[PinPoint], grid: GridSpec) -> Candidates {
    if pins.len() <= ALL_PAIRS_MAX_PINS {
        Candidates { pairs: candidate_pairs(pins), may_cross: None }
    } else {
        local_candidates(pins, grid.spacing_v_m / grid.spacing_u_m)
    }
}

/// Every pair of pins (a < b) whose segment passes through no third pin.
fn candidate_pairs(pins: &[PinPoint]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for a in 0..pins.len() {
        for b in a + 1..pins.len() {
            let (pa, pb) = (grid_i64(&pins[a]), grid_i64(&pins[b]));
            let blocked = pins.iter().enumerate().any(|(k, pin)| {
                if k == a || k == b {
                    return false;
                }
                let pk = grid_i64(pin);
                let along = (pk.0 - pa.0) * (pb.0 - pa.0) + (pk.1 - pa.1) * (pb.1 - pa.1);
                let len2 = (pb.0 - pa.0).pow(2) + (pb.1 - pa.1).pow(2);
                cross_i64(pa, pb, pk) == 0 && along > 0 && along < len2
            });
            if !blocked {
                pairs.push((a, b));
            }
        }
    }
    pairs
}

/// Faces of the Delaunay subdivision with more vertices than this keep the
/// diagonals their triangulation chose rather than all of them (their chords
/// and the crossings among them grow with the square and the fourth power).
const ALL_CHORDS_MAX_FACE_VERTICES: usize = 12;

/// Local candidates, from the pins' Delaunay subdivision (material space,
/// cells of aspect `aspect` = spacing_v / spacing_u), whose faces are convex
/// polygons with their vertices on a circle, mostly triangles:
///
/// - every edge of the subdivision, and every diagonal of a face (any
///   Delaunay triangulation's edges);
/// - across each edge between two faces, each segment from a vertex of one
///   face to a vertex of the other that crosses it ("flips"; for two triangles,
///   the other diagonal of their quad).
///
/// The subdivision is unique, so mirror-symmetric pins get mirror-symmetric
/// candidates. None passes through a third pin. Each lies inside one face or
/// two neighbouring ones, so it can cross only the edge it flips and the
/// candidates through the same faces: those pairs are all that
/// [`find_crossings`] tests. Collinear pins: each joins the next on the line.
fn local_candidates(pins: &[PinPoint], aspect: f64) -> Candidates {
    let points: Vec<(i64, i64)> = pins.iter().map(grid_i64).collect();
    let Some(mesh) = delaunay::triangulate(&points, aspect) else {
        let mut order: Vec<usize> = (0..pins.len()).collect();
        order.sort_unstable_by_key(|&k| points[k]);
        let mut pairs: Vec<(usize, usize)> = order.windows(2).map(|w| (w[0].min(w[1]), w[0].max(w[1]))).collect();
        pairs.sort_unstable();
        return Candidates { pairs, may_cross: Some(Vec::new()) };
    };
    let triangles = mesh.start.len() / 3;
    let mut face_of = mesh.faces(&points, aspect);
    let mut face_vertices = vertices_by_face(&mesh.start, &face_of);
    // Faces too big for all their chords fall back to their triangles.
    if face_vertices.iter().any(|v| v.len() > ALL_CHORDS_MAX_FACE_VERTICES) {
        let mut fresh = face_vertices.len();
        for face in face_of.iter_mut() {
            if face_vertices[*face].len() > ALL_CHORDS_MAX_FACE_VERTICES {
                *face = fresh;
                fresh += 1;
            }
        }
        face_vertices = vertices_by_face(&mesh.start, &face_of);
    }

    let mut pairs = PairIndex::default();
    let mut may_cross = Vec::new();
    // Per face, the candidates through its interior.
    let mut through: Vec<Vec<usize>> = vec![Vec::new(); face_vertices.len()];
    for e in 0..3 * triangles {
        let twin = mesh.twin[e];
        let (x, y) = (mesh.start[e], mesh.start[delaunay::next(e)]);
        if twin == NONE {
            pairs.add(x, y);
            continue;
        }
        let (near, far) = (face_of[e / 3], face_of[twin / 3]);
        if twin < e || near == far {
            continue;
        }
        let edge = pairs.add(x, y);
        for &u in &face_vertices[near] {
            for &w in &face_vertices[far] {
                let (sx, sy) = (cross_i64(points[u], points[w], points[x]), cross_i64(points[u], points[w], points[y]));
                if sx.signum() * sy.signum() < 0 {
                    let flip = pairs.add(u, w);
                    may_cross.push((flip, edge));
                    through[near].push(flip);
                    through[far].push(flip);
                }
            }
        }
    }
    for (face, vertices) in face_vertices.iter().enumerate().filter(|(_, v)| v.len() > 3) {
        for (k, &a) in vertices.iter().enumerate() {
            for &b in &vertices[k + 1..] {
                let chord = pairs.add(a, b);
                through[face].push(chord);
            }
        }
    }
    for list in &through {
        for (k, &a) in list.iter().enumerate() {
            may_cross.extend(list[k + 1..].iter().map(|&b| (a, b)));
        }
    }

    // Renumber in lexicographic order of the pin pairs, as all pairs are.
    let pairs = pairs.pairs;
    let mut order: Vec<usize> = (0..pairs.len()).collect();
    order.sort_unstable_by_key(|&c| pairs[c]);
    let mut rank = vec![0; pairs.len()];
    for (r, &c) in order.iter().enumerate() {
        rank[c] = r;
    }
    let mut may_cross: Vec<(usize, usize)> = may_cross
        .into_iter()
        .filter(|&(x, y)| x != y)
        .map(|(x, y)| (rank[x].min(rank[y]), rank[x].max(rank[y])))
        .collect();
    may_cross.sort_unstable();
    may_cross.dedup();
    Candidates { pairs: order.iter().map(|&c| pairs[c]).collect(), may_cross: Some(may_cross) }
}

/// The vertices of each face (sorted), given each triangle's face.
fn vertices_by_face(start: &[usize], face_of: &[usize]) -> Vec<Vec<usize>> {
    let faces = face_of.iter().max().map_or(0, |&f| f + 1);
    let mut vertices = vec![Vec::new(); faces];
    for (t, &face) in face_of.iter().enumerate() {
        vertices[face].extend_from_slice(&start[3 * t..3 * t + 3]);
    }
    for list in &mut vertices {
        list.sort_unstable();
        list.dedup();
    }
    vertices
}

/// Pin pairs numbered as they are first added.
#[derive(Default)]
struct PairIndex {
    pairs: Vec<(usize, usize)>,
    number: HashMap<(usize, usize), usize>,
}

impl PairIndex {
    /// The number of pair {a, b}, adding it if new.
    fn add(&mut self, a: usize, b: usize) -> usize {
        let pair = (a.min(b), a.max(b));
        *self.number.entry(pair).or_insert_with(|| {
            self.pairs.push(pair);
            self.pairs.len() - 1
        })
    }
}

/// A proper crossing of two candidates in grid space.
pub(super) struct Crossing {
    pub(super) first: usize,
    pub(super) second: usize,
    pub(super) t_first: f64,
    pub(super) t_second: f64,
    /// Heights of the two catenaries at the crossing.
    pub(super) y_first: f64,
    pub(super) y_second: f64,
}

impl Crossing {
    fn lower_y(&self) -> f64 {
        self.y_first.min(self.y_second)
    }

    /// Whether the two catenaries are equally high here, within `tolerance_m`.
    pub(super) fn is_tie(&self, tolerance_m: f64) -> bool {
        (self.y_first - self.y_second).abs() <= tolerance_m
    }
}

/// Every proper crossing of two candidates in grid space, by (first, second).
pub(super) fn find_crossings(pins: &[PinPoint], candidates: &Candidates, catenaries: &[Catenary]) -> Vec<Crossing> {
    let pairs = &candidates.pairs;
    match &candidates.may_cross {
        None => (0..pairs.len())
            .flat_map(|e| (e + 1..pairs.len()).map(move |f| (e, f)))
            .filter_map(|(e, f)| crossing(pins, pairs, catenaries, e, f))
            .collect(),
        Some(may_cross) => may_cross.iter().filter_map(|&(e, f)| crossing(pins, pairs, catenaries, e, f)).collect(),
    }
}

/// The proper crossing of candidates `e` and `f` (interior points of both), if any.
fn crossing(
    pins: &[PinPoint],
    pairs: &[(usize, usize)],
    catenaries: &[Catenary],
    e: usize,
    f: usize,
) -> Option<Crossing> {
    let ((a, b), (c, d)) = (pairs[e], pairs[f]);
    if a == c || a == d || b == c || b == d {
        return None;
    }
    let (pa, pb) = (grid_i64(&pins[a]), grid_i64(&pins[b]));
    let (pc, pd) = (grid_i64(&pins[c]), grid_i64(&pins[d]));
    let (d1, d2) = (cross_i64(pa, pb, pc), cross_i64(pa, pb, pd));
    let (d3, d4) = (cross_i64(pc, pd, pa), cross_i64(pc, pd, pb));
    // Strict sign changes: a proper crossing at interior points of both.
    if !(d1.signum() * d2.signum() < 0 && d3.signum() * d4.signum() < 0) {
        return None;
    }
    // Intersection parameters: t along a→b, s along c→d.
    let t = d3 as f64 / (d3 - d4) as f64;
    let s = d1 as f64 / (d1 - d2) as f64;
    let ye = catenaries[e].point_at_arc_fraction(t).y;
    let yf = catenaries[f].point_at_arc_fraction(s).y;
    Some(Crossing { first: e, second: f, t_first: t, t_second: s, y_first: ye, y_second: yf })
}

/// The surviving candidates: each resolution's ([`resolve_conflicts`]) and
/// their union.
pub(super) struct Survivors {
    /// Candidates that survive in at least one resolution: the kept ones.
    pub(super) alive: Vec<bool>,
    /// Each resolution's survivors, a triangulation of the hull each: one
    /// resolution when no crossing ties, else the two that break ties towards
    /// one diagonal direction and towards the other.
    pub(super) resolutions: Vec<Vec<bool>>,
}

/// Resolves the conflicts of `candidates` at `crossings`. Where two are
/// equally high at their crossing (within `tie_tolerance_m`) neither is the
/// higher, and keeping either one would tilt the shape of symmetric pins:
/// mirror-symmetric pins give mirror-image candidates that meet on the mirror
/// at equal heights (up to rounding). Such ties are broken both ways — once
/// for catenaries along the grid's main diagonal direction (i and j growing
/// together), once for the other — and both resolutions are kept. A mirror in
/// i or in j swaps the two directions, so it swaps the two resolutions and
/// leaves their union as it was. Without ties there is one resolution, the
/// paper's.
pub(super) fn survivors(
    pins: &[PinPoint],
    candidates: &Candidates,
    crossings: &[Crossing],
    catenaries: &[Catenary],
    tie_tolerance_m: f64,
) -> Survivors {
    let resolve =
        |tie_break| resolve_conflicts(pins, &candidates.pairs, crossings, catenaries, tie_tolerance_m, tie_break);
    let main = resolve(TieBreak::MainDiagonal);
    let anti = if crossings.iter().any(|x| x.is_tie(tie_tolerance_m)) {
        resolve(TieBreak::AntiDiagonal)
    } else {
        main.clone()
    };
    if anti == main {
        return Survivors { alive: main.clone(), resolutions: vec![main] };
    }
    let alive = main.iter().zip(&anti).map(|(&m, &a)| m || a).collect();
    Survivors { alive, resolutions: vec![main, anti] }
}

/// Which catenary wins a tie at a crossing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TieBreak {
    /// The one along the main diagonal direction (i and j grow together), then
    /// an axis-aligned one, then the other; between two alike, the first.
    MainDiagonal,
    /// The one along the other diagonal direction, then an axis-aligned one.
    AntiDiagonal,
}

impl TieBreak {
    /// 0 for the preferred direction, 1 along an axis, 2 for the other.
    fn rank(self, a: (i64, i64), b: (i64, i64)) -> u8 {
        let slope = ((b.0 - a.0) * (b.1 - a.1)).signum();
        let towards = if self == TieBreak::MainDiagonal { slope } else { -slope };
        (1 - towards) as u8
    }
}

/// Which candidates survive: at each crossing the lower one goes, lowest
/// conflict first; then removed candidates that cross no survivor come back
/// (highest midpoint first), so the survivors are a maximal non-crossing set —
/// a triangulation of the hull.
///
/// A crossing whose two heights differ by at most `tie_tolerance_m` is a tie,
/// won by the catenary `tie_break` prefers, in both steps: of a removed
/// catenary and removed ones it ties with that could all come back, the
/// preferred one does, whichever comes first by height. Without ties the
/// result does not depend on `tie_break`.
fn resolve_conflicts(
    pins: &[PinPoint],
    pairs: &[(usize, usize)],
    crossings: &[Crossing],
    catenaries: &[Catenary],
    tie_tolerance_m: f64,
    tie_break: TieBreak,
) -> Vec<bool> {
    let count = pairs.len();
    let rank: Vec<u8> = pairs.iter().map(|&(a, b)| tie_break.rank(grid_i64(&pins[a]), grid_i64(&pins[b]))).collect();
    let preferred = |x: usize, y: usize| (rank[x], x) < (rank[y], y);
    let mut alive = vec![true; count];
    let mut order: Vec<usize> = (0..crossings.len()).collect();
    order.sort_by(|&x, &y| crossings[x].lower_y().total_cmp(&crossings[y].lower_y()).then(x.cmp(&y)));
    for &k in &order {
        let x = &crossings[k];
        if !(alive[x.first] && alive[x.second]) {
            continue;
        }
        let first_stays = if x.is_tie(tie_tolerance_m) { preferred(x.first, x.second) } else { x.y_first > x.y_second };
        if first_stays {
            alive[x.second] = false;
        } else {
            alive[x.first] = false;
        }
    }

    // Per candidate, the candidates it crosses and whether they tie there.
    let mut partners: Vec<Vec<(usize, bool)>> = vec![Vec::new(); count];
    for x in crossings {
        let tie = x.is_tie(tie_tolerance_m);
        partners[x.first].push((x.second, tie));
        partners[x.second].push((x.first, tie));
    }
    let mut removed: Vec<(f64, usize)> =
        (0..count).filter(|&c| !alive[c]).map(|c| (catenaries[c].point_at_arc_fraction(0.5).y, c)).collect();
    removed.sort_by(|&(mx, x), &(my, y)| my.total_cmp(&mx).then(x.cmp(&y)));
    for (_, c) in removed {
        let free = |c: usize, alive: &[bool]| partners[c].iter().all(|&(p, _)| !alive[p]);
        if alive[c] || !free(c, &alive) {
            continue;
        }
        let back = partners[c]
            .iter()
            .filter(|&&(p, tie)| tie && !alive[p] && free(p, &alive))
            .fold(c, |best, &(p, _)| if preferred(p, best) { p } else { best });
        alive[back] = true;
    }
    alive
}

/// The layout of `pins`; over an area, the triangles of each resolution
/// (pin pairs of its survivors), those of the first first.
pub(super) fn classify_layout(pins: &[PinPoint], resolutions: &[Vec<(usize, usize)>]) -> PinLayout {
    if pins.len() == 1 {
        return PinLayout::Single;
    }
    let points: Vec<(i64, i64)> = pins.iter().map(grid_i64).collect();
    let p0 = points[0];
    let far = (1..points.len())
        .max_by_key(|&k| (points[k].0 - p0.0).pow(2) + (points[k].1 - p0.1).pow(2))
        .expect("at least two pins");
    let pf = points[far];
    if points.iter().all(|&p| cross_i64(p0, pf, p) == 0) {
        let dir = (pf.0 - p0.0, pf.1 - p0.1);
        let mut order: Vec<usize> = (0..pins.len()).collect();
        order.sort_by_key(|&k| (points[k].0 - p0.0) * dir.0 + (points[k].1 - p0.1) * dir.1);
        return PinLayout::Collinear(order);
    }
    let boundary = convex_hull_with_collinear(&points);
    let mut triangles = Vec::new();
    let mut seen = HashSet::new();
    for edges in resolutions {
        triangles.extend(kept_triangles(&points, edges).into_iter().filter(|&triangle| seen.insert(triangle)));
    }
    PinLayout::Hull { boundary, triangles }
}

/// Andrew's monotone chain, keeping points that lie on hull edges so that each
/// boundary step is a single kept catenary. Input is not all collinear.
fn convex_hull_with_collinear(points: &[(i64, i64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_key(|&k| points[k]);
    let mut hull: Vec<usize> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &usize>> =
            if pass == 0 { Box::new(order.iter()) } else { Box::new(order.iter().rev()) };
        for &k in iter {
            while hull.len() >= start + 2
                && cross_i64(points[hull[hull.len() - 2]], points[hull[hull.len() - 1]], points[k]) < 0
            {
                hull.pop();
            }
            hull.push(k);
        }
        hull.pop();
    }
    hull
}

/// Triangles whose three edges are in `edges` (pin pairs) and that hold no other pin.
fn kept_triangles(points: &[(i64, i64)], edges: &[(usize, usize)]) -> Vec<[usize; 3]> {
    let n = points.len();
    let mut adjacent = vec![Vec::new(); n];
    for &(a, b) in edges {
        adjacent[a].push(b);
        adjacent[b].push(a);
    }
    for list in &mut adjacent {
        list.sort_unstable();
    }
    let index = PinRows::new(points);
    let mut triangles = Vec::new();
    for a in 0..n {
        for (x, &b) in adjacent[a].iter().enumerate() {
            if b <= a {
                continue;
            }
            for &c in &adjacent[a][x + 1..] {
                if adjacent[b].binary_search(&c).is_err() {
                    continue;
                }
                let area2 = cross_i64(points[a], points[b], points[c]);
                if area2 == 0 {
                    continue;
                }
                if !index.any_strictly_inside(points, [a, b, c]) {
                    triangles.push([a, b, c]);
                }
            }
        }
    }
    triangles
}

/// The pins sorted by grid row, then column: the pins in a rectangle are
/// found row by row by binary search, in O(n) memory.
struct PinRows {
    sorted: Vec<(i64, i64)>,
}

impl PinRows {
    fn new(points: &[(i64, i64)]) -> Self {
        let mut sorted: Vec<(i64, i64)> = points.iter().map(|&(i, j)| (j, i)).collect();
        sorted.sort_unstable();
        PinRows { sorted }
    }

    /// Whether any pin lies strictly inside triangle `tri` (not collinear).
    fn any_strictly_inside(&self, points: &[(i64, i64)], tri: [usize; 3]) -> bool {
        let corners = tri.map(|k| points[k]);
        let (min_i, max_i) = (corners.iter().map(|c| c.0).min().unwrap(), corners.iter().map(|c| c.0).max().unwrap());
        let (min_j, max_j) = (corners.iter().map(|c| c.1).min().unwrap(), corners.iter().map(|c| c.1).max().unwrap());
        let mut j = min_j;
        while j <= max_j {
            let from = self.sorted.partition_point(|&p| p < (j, min_i));
            let to = self.sorted.partition_point(|&p| p <= (j, max_i));
            if self.sorted[from..to].iter().any(|&(j, i)| strictly_inside(points, tri, (i, j))) {
                return true;
            }
            // On to the next row that holds a pin.
            match self.sorted.get(self.sorted.partition_point(|&p| p.0 <= j)) {
                Some(&(next_j, _)) => j = next_j,
                None => break,
            }
        }
        false
    }
}

fn strictly_inside(points: &[(i64, i64)], [a, b, c]: [usize; 3], p: (i64, i64)) -> bool {
    let s = cross_i64(points[a], points[b], points[c]).signum();
    let w =
        [cross_i64(points[b], points[c], p), cross_i64(points[c], points[a], p), cross_i64(points[a], points[b], p)];
    w.iter().all(|&x| x.signum() == s)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::*;

    fn pin(i: usize, j: usize, y: f64) -> PinPoint {
        PinPoint { grid: (i, j), pos: DVec3::new(i as f64 * 0.1, y, j as f64 * 0.1) }
    }

    fn grid(cols: usize, rows: usize) -> GridSpec {
        GridSpec { cols, rows, spacing_u_m: 0.1, spacing_v_m: 0.1 }
    }

    fn catenaries(pins: &[PinPoint], pairs: &[(usize, usize)], elasticity: f64) -> Vec<Catenary> {
        pairs
            .iter()
            .map(|&(a, b)| {
                let length = pins[a].pos.distance(pins[b].pos).max(0.1 * elasticity) * elasticity;
                Catenary::new(pins[a].pos, pins[b].pos, length)
            })
            .collect()
    }

    /// The all-pairs candidate selection and conflict resolution, without
    /// local candidates and ties: the reference small layouts must match.
    mod old {
        use super::super::{cross_i64, grid_i64};
        use crate::shape::approximate::PinPoint;
        use crate::shape::catenary::Catenary;

        /// (first, second, t_first, t_second, y_first, y_second) per crossing.
        pub type Crossing = (usize, usize, f64, f64, f64, f64);

        pub fn find_crossings(
            pins: &[PinPoint],
            candidates: &[(usize, usize)],
            catenaries: &[Catenary],
        ) -> Vec<Crossing> {
            let mut crossings = Vec::new();
            for e in 0..candidates.len() {
                let (a, b) = candidates[e];
                let (pa, pb) = (grid_i64(&pins[a]), grid_i64(&pins[b]));
                for f in e + 1..candidates.len() {
                    let (c, d) = candidates[f];
                    if a == c || a == d || b == c || b == d {
                        continue;
                    }
                    let (pc, pd) = (grid_i64(&pins[c]), grid_i64(&pins[d]));
                    let (d1, d2) = (cross_i64(pa, pb, pc), cross_i64(pa, pb, pd));
                    let (d3, d4) = (cross_i64(pc, pd, pa), cross_i64(pc, pd, pb));
                    if !(d1.signum() * d2.signum() < 0 && d3.signum() * d4.signum() < 0) {
                        continue;
                    }
                    let t = d3 as f64 / (d3 - d4) as f64;
                    let s = d1 as f64 / (d1 - d2) as f64;
                    let ye = catenaries[e].point_at_arc_fraction(t).y;
                    let yf = catenaries[f].point_at_arc_fraction(s).y;
                    crossings.push((e, f, t, s, ye, yf));
                }
            }
            crossings
        }

        pub fn resolve_conflicts(count: usize, crossings: &[Crossing], catenaries: &[Catenary]) -> Vec<bool> {
            let lower = |x: &Crossing| x.4.min(x.5);
            let mut alive = vec![true; count];
            let mut order: Vec<usize> = (0..crossings.len()).collect();
            order.sort_by(|&x, &y| lower(&crossings[x]).total_cmp(&lower(&crossings[y])).then(x.cmp(&y)));
            for &k in &order {
                let x = &crossings[k];
                if !(alive[x.0] && alive[x.1]) {
                    continue;
                }
                if x.4 >= x.5 {
                    alive[x.1] = false;
                } else {
                    alive[x.0] = false;
                }
            }
            let mut partners: Vec<Vec<usize>> = vec![Vec::new(); count];
            for x in crossings {
                partners[x.0].push(x.1);
                partners[x.1].push(x.0);
            }
            let mut removed: Vec<usize> = (0..count).filter(|&c| !alive[c]).collect();
            removed.sort_by(|&x, &y| {
                let (mx, my) = (catenaries[x].point_at_arc_fraction(0.5).y, catenaries[y].point_at_arc_fraction(0.5).y);
                my.total_cmp(&mx).then(x.cmp(&y))
            });
            for c in removed {
                if partners[c].iter().all(|&p| !alive[p]) {
                    alive[c] = true;
                }
            }
            alive
        }
    }

    /// Small layouts: the same candidates and crossings as the all-pairs selection,
    /// and, where nothing ties, the same survivors.
    fn assert_as_before(label: &str, pins: &[PinPoint], g: GridSpec, elasticity: f64) {
        assert!(pins.len() <= ALL_PAIRS_MAX_PINS);
        let candidates = select_candidates(pins, g);
        let old_pairs = candidate_pairs(pins);
        assert_eq!(candidates.pairs, old_pairs, "{label}");
        let cats = catenaries(pins, &candidates.pairs, elasticity);
        let crossings = find_crossings(pins, &candidates, &cats);
        let old_crossings = old::find_crossings(pins, &old_pairs, &cats);
        let as_tuples: Vec<old::Crossing> =
            crossings.iter().map(|x| (x.first, x.second, x.t_first, x.t_second, x.y_first, x.y_second)).collect();
        assert_eq!(as_tuples, old_crossings, "{label}");
        let tolerance = 1e-9;
        if crossings.iter().all(|x| !x.is_tie(tolerance)) {
            let survivors = survivors(pins, &candidates, &crossings, &cats, tolerance);
            assert_eq!(survivors.resolutions.len(), 1, "{label}");
            assert_eq!(survivors.alive, old::resolve_conflicts(old_pairs.len(), &old_crossings, &cats), "{label}");
        }
    }

    #[test]
    fn bundled_scenes_select_as_before() {
        for entry in std::fs::read_dir("scenes").unwrap() {
            let path = entry.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) != Some("ron") {
                continue;
            }
            let scene = crate::scene::load(&path).unwrap();
            let g = crate::shape::rest_shape::grid_spec(&scene.cloth);
            for (k, key) in scene.keys.iter().enumerate() {
                let pins = crate::shape::rest_shape::pin_points(key);
                if pins.len() <= ALL_PAIRS_MAX_PINS {
                    assert_as_before(&format!("{}#{k}", path.display()), &pins, g, key.elasticity);
                }
            }
        }
    }

    fn small_layout() -> impl Strategy<Value = (usize, usize, Vec<PinPoint>, f64)> {
        (3usize..30, 3usize..30, 1usize..=ALL_PAIRS_MAX_PINS, 1.0f64..1.5).prop_flat_map(|(cols, rows, count, e)| {
            let one = ((0..cols, 0..rows), 0.0f64..3.0);
            (Just(cols), Just(rows), prop::collection::vec(one, count), Just(e)).prop_map(|(cols, rows, raw, e)| {
                let mut seen = HashSet::new();
                let pins = raw.into_iter().filter(|&(g, _)| seen.insert(g)).map(|((i, j), y)| pin(i, j, y)).collect();
                (cols, rows, pins, e)
            })
        })
    }

    /// `count` distinct pins on a `size`² grid, heights from `height`.
    fn many_pins(seed: u64, count: usize, size: usize, height: impl Fn(usize, usize) -> f64) -> Vec<PinPoint> {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) as usize
        };
        let mut seen = HashSet::new();
        let mut pins = Vec::new();
        while pins.len() < count {
            let (i, j) = (next() % size, next() % size);
            if seen.insert((i, j)) {
                pins.push(pin(i, j, height(i, j)));
            }
        }
        pins
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, .. ProptestConfig::default() })]

        #[test]
        fn small_layouts_select_as_before((cols, rows, pins, elasticity) in small_layout()) {
            assert_as_before("random", &pins, grid(cols, rows), elasticity);
        }

        #[test]
        fn local_candidates_are_unblocked_and_their_crossings_known(
            seed in 0u64..1000, count in 25usize..160, size in 12usize..40,
        ) {
            let size = size.max((count as f64).sqrt() as usize + 2);
            let pins = many_pins(seed, count, size, |i, j| ((i * 7 + j * 3) % 5) as f64 * 0.1);
            let candidates = select_candidates(&pins, grid(size, size));
            let all: HashSet<(usize, usize)> = candidate_pairs(&pins).into_iter().collect();
            prop_assert!(candidates.pairs.iter().all(|p| all.contains(p)), "a local candidate passes through a pin");
            prop_assert!(candidates.pairs.windows(2).all(|w| w[0] < w[1]));
            let cats = catenaries(&pins, &candidates.pairs, 1.1);
            let known: HashSet<(usize, usize)> =
                find_crossings(&pins, &candidates, &cats).iter().map(|x| (x.first, x.second)).collect();
            for e in 0..candidates.pairs.len() {
                for f in e + 1..candidates.pairs.len() {
                    if crossing(&pins, &candidates.pairs, &cats, e, f).is_some() {
                        prop_assert!(known.contains(&(e, f)), "crossing {e}–{f} not found");
                    }
                }
            }
        }

        #[test]
        fn every_resolution_of_local_candidates_tiles_the_hull(
            seed in 0u64..1000, count in 25usize..160, size in 12usize..40, levels in 1usize..4, mirrored: bool,
        ) {
            // Few height levels and mirrored layouts make ties.
            let size = size.max((count as f64).sqrt() as usize + 2);
            let mut pins = many_pins(seed, count, size, |i, j| ((i * 7 + j * 3) % levels) as f64 * 0.1);
            if mirrored {
                let mut seen: HashSet<(usize, usize)> = pins.iter().map(|p| p.grid).collect();
                let images: Vec<PinPoint> =
                    pins.iter().filter(|p| seen.insert((size - 1 - p.grid.0, p.grid.1))).map(|p| pin(size - 1 - p.grid.0, p.grid.1, p.pos.y)).collect();
                pins.extend(images);
            }
            let candidates = select_candidates(&pins, grid(size, size));
            let cats = catenaries(&pins, &candidates.pairs, 1.1);
            let crossings = find_crossings(&pins, &candidates, &cats);
            let survivors = survivors(&pins, &candidates, &crossings, &cats, 1e-9);
            let points: Vec<(i64, i64)> = pins.iter().map(grid_i64).collect();
            let hull = convex_hull_with_collinear(&points);
            let hull_area2: i64 = (1..hull.len() - 1).map(|k| cross_i64(points[hull[0]], points[hull[k]], points[hull[k + 1]])).sum();
            for survives in &survivors.resolutions {
                let edges: Vec<(usize, usize)> =
                    candidates.pairs.iter().zip(survives).filter(|&(_, &s)| s).map(|(&p, _)| p).collect();
                let area2: i64 =
                    kept_triangles(&points, &edges).iter().map(|t| cross_i64(points[t[0]], points[t[1]], points[t[2]]).abs()).sum();
                prop_assert_eq!(area2, hull_area2, "a resolution leaves a hole or overlaps itself");
            }
        }
    }

    #[test]
    fn mirror_symmetric_pins_get_mirror_symmetric_local_candidates() {
        for seed in 0..20 {
            let size = 21;
            let half = many_pins(seed, 30, size, |_, _| 0.0);
            let mut seen = HashSet::new();
            let pins: Vec<PinPoint> = half
                .iter()
                .flat_map(|p| [p.grid, (size - 1 - p.grid.0, p.grid.1)])
                .filter(|&g| seen.insert(g))
                .map(|(i, j)| pin(i, j, 0.0))
                .collect();
            let candidates = select_candidates(&pins, grid(size, size));
            let at: HashMap<(usize, usize), usize> = pins.iter().enumerate().map(|(k, p)| (p.grid, k)).collect();
            let set: HashSet<(usize, usize)> = candidates.pairs.iter().copied().collect();
            for &(a, b) in &candidates.pairs {
                let mirror = |k: usize| at[&(size - 1 - pins[k].grid.0, pins[k].grid.1)];
                let (ma, mb) = (mirror(a), mirror(b));
                assert!(set.contains(&(ma.min(mb), ma.max(mb))), "seed {seed}: {a}–{b} has no mirror image");
            }
        }
    }

    #[test]
    fn crossings_are_proper_and_exact() {
        // A plus sign, a T (touching), a shared end and collinear overlap.
        let pins = [pin(0, 2, 1.0), pin(4, 2, 1.0), pin(2, 0, 1.0), pin(2, 4, 1.0), pin(6, 2, 1.0), pin(2, 2, 0.5)];
        let pairs = [(0, 1), (2, 3), (1, 4), (2, 5), (0, 4)];
        let cats = catenaries(&pins, &pairs, 1.1);
        let x = crossing(&pins, &pairs, &cats, 0, 1).expect("the plus crosses");
        assert_eq!((x.t_first, x.t_second), (0.5, 0.5));
        assert!(crossing(&pins, &pairs, &cats, 0, 2).is_none(), "a shared end is no crossing");
        assert!(crossing(&pins, &pairs, &cats, 0, 3).is_none(), "touching at a pin is no crossing");
        assert!(crossing(&pins, &pairs, &cats, 0, 4).is_none(), "collinear overlap is no crossing");
        // Far from the origin the predicate stays exact (integer arithmetic).
        let far = [pin(100_000, 0, 1.0), pin(100_003, 1, 1.0), pin(100_001, 1, 1.0), pin(100_002, 0, 1.0)];
        let pairs = [(0, 1), (2, 3)];
        let cats = catenaries(&far, &pairs, 1.1);
        let x = crossing(&far, &pairs, &cats, 0, 1).expect("crosses");
        assert_eq!((x.t_first, x.t_second), (0.5, 0.5));
    }

    #[test]
    fn the_hull_keeps_pins_on_its_edges_counter_clockwise() {
        let points = [(0, 0), (2, 0), (4, 0), (4, 4), (2, 2), (0, 4), (0, 2), (1, 1), (4, 2)];
        let hull = convex_hull_with_collinear(&points);
        let on_hull: Vec<(i64, i64)> = hull.iter().map(|&k| points[k]).collect();
        assert_eq!(on_hull, [(0, 0), (2, 0), (4, 0), (4, 2), (4, 4), (0, 4), (0, 2)]);
        for k in 0..hull.len() {
            let (a, b, c) = (on_hull[k], on_hull[(k + 1) % hull.len()], on_hull[(k + 2) % hull.len()]);
            assert!(cross_i64(a, b, c) >= 0);
        }
    }

    #[test]
    fn pins_strictly_inside_a_triangle_are_found_row_by_row() {
        let points: Vec<(i64, i64)> = (0..12).flat_map(|j| (0..12).map(move |i| (i, j))).step_by(5).collect();
        let index = PinRows::new(&points);
        for a in 0..points.len() {
            for b in a + 1..points.len() {
                for c in (b + 1..points.len()).step_by(3) {
                    if cross_i64(points[a], points[b], points[c]) == 0 {
                        continue;
                    }
                    let brute = points.iter().any(|&p| strictly_inside(&points, [a, b, c], p));
                    assert_eq!(index.any_strictly_inside(&points, [a, b, c]), brute, "{a}, {b}, {c}");
                }
            }
        }
    }

    #[test]
    fn ties_keep_both_diagonals_of_a_level_square() {
        let pins = [pin(0, 0, 1.0), pin(8, 0, 1.0), pin(0, 8, 1.0), pin(8, 8, 1.0)];
        let candidates = select_candidates(&pins, grid(9, 9));
        let cats = catenaries(&pins, &candidates.pairs, 1.1);
        let crossings = find_crossings(&pins, &candidates, &cats);
        let survivors = survivors(&pins, &candidates, &crossings, &cats, 1e-9);
        assert!(survivors.alive.iter().all(|&a| a));
        assert_eq!(survivors.resolutions.len(), 2);
        // Each resolution is one triangulation: the main diagonal (0–3) or the other (1–2).
        let diagonal = |r: &Vec<bool>| {
            (
                r[candidates.pairs.iter().position(|&p| p == (0, 3)).unwrap()],
                r[candidates.pairs.iter().position(|&p| p == (1, 2)).unwrap()],
            )
        };
        assert_eq!(diagonal(&survivors.resolutions[0]), (true, false));
        assert_eq!(diagonal(&survivors.resolutions[1]), (false, true));
    }
}
