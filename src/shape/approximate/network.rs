//! The catenary network's combinatorics in grid space: which pins the
//! candidate catenaries join, where they cross, which survive, and the
//! layout (hull and triangles) of what is kept. Every predicate is exact
//! integer arithmetic on grid indices.

use glam::DVec2;

use super::{CatenaryEdge, GridSpec, PinLayout, PinPoint};
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

pub(super) fn find_crossings(
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
            // Strict sign changes: a proper crossing at interior points of both.
            if !(d1.signum() * d2.signum() < 0 && d3.signum() * d4.signum() < 0) {
                continue;
            }
            // Intersection parameters: t along a→b, s along c→d.
            let t = d3 as f64 / (d3 - d4) as f64;
            let s = d1 as f64 / (d1 - d2) as f64;
            let ye = catenaries[e].point_at_arc_fraction(t).y;
            let yf = catenaries[f].point_at_arc_fraction(s).y;
            crossings.push(Crossing { first: e, second: f, t_first: t, t_second: s, y_first: ye, y_second: yf });
        }
    }
    crossings
}

/// Which candidates survive: at each crossing the lower one goes, lowest
/// conflict first; then removed candidates that cross no survivor come back
/// (highest midpoint first), so the survivors are a maximal non-crossing set —
/// a triangulation of the hull.
///
/// A crossing whose two heights differ by at most `tie_tolerance_m` is a tie
/// and removes neither: both stay, and neither keeps the other from coming
/// back. Mirror-symmetric pins give mirror-image candidates that meet on the
/// mirror at equal heights (up to rounding), and breaking such a tie either way
/// would tilt the whole shape. Tied survivors cross; the triangles on both
/// sides are then kept and overlap. Without ties the result is as above.
pub(super) fn resolve_conflicts(
    count: usize,
    crossings: &[Crossing],
    catenaries: &[Catenary],
    tie_tolerance_m: f64,
) -> Vec<bool> {
    let mut alive = vec![true; count];
    let mut order: Vec<usize> = (0..crossings.len()).collect();
    order.sort_by(|&x, &y| crossings[x].lower_y().total_cmp(&crossings[y].lower_y()).then(x.cmp(&y)));
    for &k in &order {
        let x = &crossings[k];
        if !(alive[x.first] && alive[x.second]) || x.is_tie(tie_tolerance_m) {
            continue;
        }
        if x.y_first > x.y_second {
            alive[x.second] = false;
        } else {
            alive[x.first] = false;
        }
    }

    let mut partners: Vec<Vec<usize>> = vec![Vec::new(); count];
    for x in crossings.iter().filter(|x| !x.is_tie(tie_tolerance_m)) {
        partners[x.first].push(x.second);
        partners[x.second].push(x.first);
    }
    let mut removed: Vec<(f64, usize)> =
        (0..count).filter(|&c| !alive[c]).map(|c| (catenaries[c].point_at_arc_fraction(0.5).y, c)).collect();
    removed.sort_by(|&(mx, x), &(my, y)| my.total_cmp(&mx).then(x.cmp(&y)));
    for (_, c) in removed {
        if partners[c].iter().all(|&p| !alive[p]) {
            alive[c] = true;
        }
    }
    alive
}

pub(super) fn classify_layout(pins: &[PinPoint], kept: &[CatenaryEdge]) -> PinLayout {
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
    let triangles = kept_triangles(&points, kept);
    PinLayout::Hull { boundary, triangles }
}

/// Andrew's monotone chain, keeping points that lie on hull edges so that each
/// boundary step is a single kept catenary. Input is not all collinear.
pub(super) fn convex_hull_with_collinear(points: &[(i64, i64)]) -> Vec<usize> {
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

/// Triangles whose three edges are kept and that hold no other pin.
pub(super) fn kept_triangles(points: &[(i64, i64)], kept: &[CatenaryEdge]) -> Vec<[usize; 3]> {
    let n = points.len();
    let mut adjacent = vec![Vec::new(); n];
    for e in kept {
        adjacent[e.a].push(e.b);
        adjacent[e.b].push(e.a);
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

pub(super) fn strictly_inside(points: &[(i64, i64)], [a, b, c]: [usize; 3], p: (i64, i64)) -> bool {
    let s = cross_i64(points[a], points[b], points[c]).signum();
    let w =
        [cross_i64(points[b], points[c], p), cross_i64(points[c], points[a], p), cross_i64(points[a], points[b], p)];
    w.iter().all(|&x| x.signum() == s)
}
