//! The catenary network's combinatorics in grid space: which pins the
//! candidate catenaries join, where they cross, which survive, and the
//! layout (hull and triangles) of what is kept. Every predicate is exact
//! integer arithmetic on grid indices.
//!

use std::collections::HashSet;

use glam::DVec2;

use super::{GridSpec, PinLayout, PinPoint};
use crate::shape::catenary::Catenary;

pub(super) fn grid_i64(p: &PinPoint) -> (i64, i64) {
    (p.grid.0 as i64, p.grid.1 as i64)
}

pub(super) fn cross_i64(o: (i64, i64), a: (i64, i64), b: (i64, i64)) -> i64 {
    (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
}

pub(super) fn crossing_material(grid: GridSpec, pins: &[PinPoint], (a, b): (usize, usize), t: f64) -> DVec2 {
    let ma = grid.material(pins[a].grid.0, pins[a].grid.1);
    let mb = grid.material(pins[b].grid.0, pins[b].grid.1);
    ma.lerp(mb, t)
}

/// Every pair of pins (a < b) whose segment passes through no third pin.
pub(super) fn candidate_pairs(pins: &[PinPoint]) -> Vec<(usize, usize)> {
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
pub(super) fn find_crossings(
    pins: &[PinPoint],
    candidates: &[(usize, usize)],
    catenaries: &[Catenary],
) -> Vec<Crossing> {
    (0..candidates.len())
        .flat_map(|e| (e + 1..candidates.len()).map(move |f| (e, f)))
        .filter_map(|(e, f)| crossing(pins, candidates, catenaries, e, f))
        .collect()
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
    candidates: &[(usize, usize)],
    crossings: &[Crossing],
    catenaries: &[Catenary],
    tie_tolerance_m: f64,
) -> Survivors {
    let resolve = |tie_break| resolve_conflicts(pins, candidates, crossings, catenaries, tie_tolerance_m, tie_break);
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
                let empty =
                    (0..n).all(|k| k == a || k == b || k == c || !strictly_inside(points, [a, b, c], points[k]));
                if empty {
                    triangles.push([a, b, c]);
                }
            }
        }
    }
    triangles
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

    use super::*;

    fn pin(i: usize, j: usize, y: f64) -> PinPoint {
        PinPoint { grid: (i, j), pos: DVec3::new(i as f64 * 0.1, y, j as f64 * 0.1) }
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
    fn ties_keep_both_diagonals_of_a_level_square() {
        let pins = [pin(0, 0, 1.0), pin(8, 0, 1.0), pin(0, 8, 1.0), pin(8, 8, 1.0)];
        let candidates = candidate_pairs(&pins);
        let cats = catenaries(&pins, &candidates, 1.1);
        let crossings = find_crossings(&pins, &candidates, &cats);
        let survivors = survivors(&pins, &candidates, &crossings, &cats, 1e-9);
        assert!(survivors.alive.iter().all(|&a| a));
        assert_eq!(survivors.resolutions.len(), 2);
        // Each resolution is one triangulation: the main diagonal (0–3) or the other (1–2).
        let diagonal = |r: &Vec<bool>| {
            (
                r[candidates.iter().position(|&p| p == (0, 3)).unwrap()],
                r[candidates.iter().position(|&p| p == (1, 2)).unwrap()],
            )
        };
        assert_eq!(diagonal(&survivors.resolutions[0]), (true, false));
        assert_eq!(diagonal(&survivors.resolutions[1]), (false, true));
    }
}
