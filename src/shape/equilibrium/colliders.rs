//! Colliders in the equilibrium: every free point, and points along every
//! row and column edge, keep at least their obstacle's thickness from its
//! surface. Each such site carries a barrier energy that grows without
//! bound as its gap to the thickness closes and vanishes beyond
//! [`Colliders::reach_m`] of it (Li et al.'s incremental potential contact
//! barrier), and no step takes a site along a path that comes within its
//! thickness ([`Colliders::step_limit`]): a site that starts outside stays
//! outside through every step, and a thin solid cannot be stepped over.

use std::cell::RefCell;

use glam::DVec3;

use super::friction::{Anchor, Friction};
use super::terms::Block;
use crate::world::Obstacle;

/// Share of a site's gap it may advance by in one sphere-trace step.
pub(super) const STEP_SHARE: f64 = 0.8;

/// Where the barrier starts above the thickness (m), at most: the cloth
/// rests within this of its thickness. A tenth of the spacing on fine grids.
const REACH_M: f64 = 1e-3;

/// Most sites an edge gets between its ends: enough for a 0.5 m edge at the
/// thinnest thickness (beyond it an edge may dip into a solid between sites).
const MAX_EDGE_SITES: usize = 256;

/// A place on the cloth that keeps clear of the colliders: a grid point, or
/// a point along an edge at `share` of the way from `a` to `b`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Site {
    pub(super) a: usize,
    pub(super) b: usize,
    pub(super) share: f64,
    /// The edge's stretch term (its Hessian slots), for a site along an edge.
    pub(super) term: Option<usize>,
}

impl Site {
    #[inline]
    pub(super) fn at(&self, x: &[DVec3]) -> DVec3 {
        if self.share == 0.0 { x[self.a] } else { x[self.a].lerp(x[self.b], self.share) }
    }
}

/// One site's contact with one obstacle: the gap beyond the thickness and
/// the direction in which it grows.
#[derive(Clone, Copy, Debug)]
pub(super) struct Touch {
    pub(super) site: usize,
    pub(super) obstacle: usize,
    pub(super) gap_m: f64,
    pub(super) outward: DVec3,
}

/// The colliders of one solve, placed relative to the solve's centre.
pub(super) struct Colliders {
    obstacles: Vec<Obstacle>,
    /// Added to a solve's coordinates to reach the world's.
    centre: DVec3,
    pub(super) sites: Vec<Site>,
    /// The barrier's stiffness: a point's weight rests at half the reach.
    kappa: f64,
    pub(super) reach_m: f64,
    pub(super) friction: Friction,
    bounds: RefCell<GapBounds>,
}

/// Per site, a place it was measured at and its gap there. The distance
/// to a surface changes no faster than the point moves, so anywhere else
/// the gap is at least that gap less the distance from there: a site far
/// from every collider is passed over without measuring, and what is
/// measured (and so every answer) is the same as measuring every site.
struct GapBounds {
    at: Vec<DVec3>,
    gap_m: Vec<f64>,
}

impl GapBounds {
    fn new(sites: usize) -> GapBounds {
        GapBounds { at: vec![DVec3::ZERO; sites], gap_m: vec![f64::NEG_INFINITY; sites] }
    }

    /// A gap `site` has at least, at `p` (a nanometre less, for rounding).
    #[inline]
    fn least(&self, site: usize, p: DVec3) -> f64 {
        self.gap_m[site] - p.distance(self.at[site]) - 1e-9
    }

    #[inline]
    fn measured(&mut self, site: usize, p: DVec3, gap_m: f64) {
        self.at[site] = p;
        self.gap_m[site] = gap_m;
    }
}

impl Colliders {
    /// `edges`: each row and column edge between free points as `(a, b,
    /// its stretch term, its rest length)`; `spacing_m` the smaller rest spacing.
    pub(super) fn new(
        obstacles: &[Obstacle],
        centre: DVec3,
        free: &[usize],
        edges: &[(usize, usize, usize, f64)],
        spacing_m: f64,
    ) -> Colliders {
        let reach_m = REACH_M.min(0.1 * spacing_m);
        let mut sites: Vec<Site> = free.iter().map(|&p| Site { a: p, b: p, share: 0.0, term: None }).collect();
        if !obstacles.is_empty() {
            // Between two sites an edge can dip into a solid by at most half
            // their distance (the distance field changes no faster than the
            // point), so the sites are at most twice the thinnest thickness
            // apart (a millimetre at least).
            let thinnest = obstacles.iter().map(|o| o.thickness).fold(f64::INFINITY, f64::min).max(1e-3);
            for &(a, b, term, length) in edges {
                let between = ((length / (2.0 * thinnest)).ceil() as usize).saturating_sub(1).min(MAX_EDGE_SITES);
                for k in 1..=between {
                    let share = k as f64 / (between + 1) as f64;
                    sites.push(Site { a, b, share, term: Some(term) });
                }
            }
        }
        // −b′(reach/2) = 1.193·reach: a point's weight holds it at half the reach.
        let kappa = 1.0 / (1.193 * reach_m);
        let bounds = RefCell::new(GapBounds::new(sites.len()));
        Colliders {
            obstacles: obstacles.to_vec(),
            centre,
            sites,
            kappa,
            reach_m,
            friction: Friction::default(),
            bounds,
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.obstacles.is_empty()
    }

    /// The smallest gap of `site` to any obstacle beyond its thickness (m).
    pub(super) fn clearance(&self, x: &[DVec3], site: &Site) -> f64 {
        self.gap(site.at(x) + self.centre)
    }

    /// Every site within the barrier's reach of an obstacle.
    pub(super) fn touches(&self, x: &[DVec3], out: &mut Vec<Touch>) {
        out.clear();
        if self.is_empty() {
            return;
        }
        let mut bounds = self.bounds.borrow_mut();
        for (index, site) in self.sites.iter().enumerate() {
            let p = site.at(x) + self.centre;
            if bounds.least(index, p) >= self.reach_m {
                continue;
            }
            let mut nearest_m = f64::INFINITY;
            for (obstacle, o) in self.obstacles.iter().enumerate() {
                let s = o.shape.surface_point(p);
                let gap_m = s.distance - o.thickness;
                nearest_m = nearest_m.min(gap_m);
                if gap_m < self.reach_m {
                    out.push(Touch { site: index, obstacle, gap_m, outward: s.outward });
                }
            }
            bounds.measured(index, p, nearest_m);
        }
    }

    /// The barrier and friction energy; infinite where a site has reached its thickness.
    pub(super) fn energy(&self, x: &[DVec3]) -> f64 {
        let mut touches = Vec::new();
        self.touches(x, &mut touches);
        let barrier: f64 = touches.iter().map(|t| self.kappa * barrier(t.gap_m, self.reach_m)).sum();
        let mu = self.friction.coefficient;
        let friction: f64 =
            self.friction.anchors.iter().map(|(&(site, _), a)| a.energy(mu, self.sites[site].at(x))).sum();
        barrier + friction
    }

    /// Anchors every site touching a surface where it is (keeping the anchor
    /// of one that touched already) and takes its normal force and the
    /// surface's direction from `x`; a site that left lets go. Nothing
    /// without friction.
    pub(super) fn update_anchors(&mut self, x: &[DVec3]) {
        if self.friction.coefficient <= 0.0 {
            return;
        }
        let mut touches = Vec::new();
        self.touches(x, &mut touches);
        let mut anchors = std::collections::BTreeMap::new();
        for t in &touches {
            let press = self.push(t);
            let key = (t.site, t.obstacle);
            let at = self.friction.anchors.get(&key).map_or_else(|| self.sites[t.site].at(x), |a| a.at);
            anchors.insert(key, Anchor { at, normal: t.outward, press });
        }
        self.friction.anchors = anchors;
    }

    /// The force a touch pushes its site out with (point weights).
    pub(super) fn push(&self, touch: &Touch) -> f64 {
        -self.kappa * barrier_slope(touch.gap_m, self.reach_m)
    }

    /// The barrier's gradient at a touch, for the site's position.
    pub(super) fn gradient(&self, touch: &Touch) -> DVec3 {
        -touch.outward * self.push(touch)
    }

    /// The barrier's Hessian block at a touch, for the site's position: its
    /// curvature along the outward direction, plus (unless `definite`) the
    /// turn of that direction as the site moves (the surface's curvature,
    /// by differences of the outward direction), which makes the last
    /// steps on a curved surface converge quadratically. That part is
    /// negative (the barrier pushes less as a point rolls around a ball),
    /// so a definite block leaves it out.
    pub(super) fn hessian(&self, x: &[DVec3], touch: &Touch, definite: bool) -> Block {
        let c = self.kappa * barrier_curvature(touch.gap_m, self.reach_m);
        let n = touch.outward.to_array();
        let mut block = [[0.0; 3]; 3];
        for (r, row) in block.iter_mut().enumerate() {
            for (s, h) in row.iter_mut().enumerate() {
                *h = c * n[r] * n[s];
            }
        }
        if definite {
            return block;
        }
        let push = self.push(touch);
        let p = self.sites[touch.site].at(x) + self.centre;
        let shape = &self.obstacles[touch.obstacle].shape;
        let h = TURN_STEP_M;
        for s in 0..3 {
            let e = DVec3::from_array(std::array::from_fn(|k| if k == s { h } else { 0.0 }));
            let turn = (shape.surface_point(p + e).outward - shape.surface_point(p - e).outward) / (2.0 * h);
            for (r, row) in block.iter_mut().enumerate() {
                row[s] -= push * turn[r];
            }
        }
        // Symmetric, as the distance's Hessian is.
        for (r, s) in [(0, 1), (0, 2), (1, 2)] {
            let mean = 0.5 * (block[r][s] + block[s][r]);
            block[r][s] = mean;
            block[s][r] = mean;
        }
        block
    }

    /// The largest share (at most `cap`) of `direction` (three entries per
    /// free rank) along which every site keeps clear of every obstacle's
    /// thickness. Each site's path is sphere-traced: at a gap g nothing
    /// within g of it is inside (the distance changes no faster than the
    /// point moves), so it advances by [`STEP_SHARE`] of g at a time, which
    /// lets a resting point slide along a surface in one step and stops a
    /// point short of any surface ahead, however thin the solid.
    pub(super) fn step_limit(&self, x: &[DVec3], rank: &[Option<usize>], direction: &[f64], cap: f64) -> f64 {
        if self.is_empty() {
            return cap;
        }
        let moved = |point: usize| {
            rank[point]
                .map_or(DVec3::ZERO, |r| DVec3::new(direction[3 * r], direction[3 * r + 1], direction[3 * r + 2]))
        };
        let mut limit = cap;
        let mut bounds = self.bounds.borrow_mut();
        for (index, site) in self.sites.iter().enumerate() {
            let d = if site.share == 0.0 { moved(site.a) } else { moved(site.a).lerp(moved(site.b), site.share) };
            let speed = d.length();
            if speed == 0.0 {
                continue;
            }
            let from = site.at(x) + self.centre;
            // The trace's first stride already passes the limit: nothing to cut.
            if STEP_SHARE * bounds.least(index, from) >= limit * speed {
                continue;
            }
            let mut t = 0.0;
            let mut traces = 0;
            let mut closest = f64::INFINITY;
            while t < limit {
                let gap = self.gap(from + d * t);
                if t == 0.0 {
                    bounds.measured(index, from, gap);
                    // No step closes more than most of a site's gap: a site
                    // that dived into its barrier in one step would hold the
                    // whole cloth to tiny steps while it climbs out.
                    closest = CLOSING_SHARE * gap;
                }
                // A site this close stops where it is (a site leaving a
                // surface goes on: its gap grows as it goes).
                if (t > 0.0 && gap <= closest) || traces == MAX_TRACE_STEPS {
                    limit = t;
                    break;
                }
                t += STEP_SHARE * gap / speed;
                traces += 1;
            }
        }
        limit
    }

    /// The smallest gap of a world point to any obstacle beyond its thickness (m).
    fn gap(&self, p: DVec3) -> f64 {
        self.obstacles.iter().map(|o| o.shape.distance(p) - o.thickness).fold(f64::INFINITY, f64::min)
    }
}

/// Step of the differences that measure a surface's curvature (m).
const TURN_STEP_M: f64 = 1e-6;

/// Share of its gap a site keeps, at least, after one step.
const CLOSING_SHARE: f64 = 0.1;

/// Most sphere-trace steps along one site's path in one Newton step; a
/// path this long stops where it has reached.
const MAX_TRACE_STEPS: usize = 64;

/// The barrier b(d) = −(d − r)²·ln(d / r) for 0 < d < r, 0 beyond, +∞ at or below 0.
fn barrier(d: f64, r: f64) -> f64 {
    if d <= 0.0 {
        f64::INFINITY
    } else if d >= r {
        0.0
    } else {
        -(d - r) * (d - r) * (d / r).ln()
    }
}

fn barrier_slope(d: f64, r: f64) -> f64 {
    if d <= 0.0 || d >= r { 0.0 } else { -2.0 * (d - r) * (d / r).ln() - (d - r) * (d - r) / d }
}

fn barrier_curvature(d: f64, r: f64) -> f64 {
    if d <= 0.0 || d >= r { 0.0 } else { -2.0 * (d / r).ln() - 4.0 * (d - r) / d + (d - r) * (d - r) / (d * d) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_barriers_derivatives_match_finite_differences() {
        let r = 1e-3;
        for d in [1e-5, 2e-4, 5e-4, 9e-4] {
            let h = 1e-9;
            let slope = (barrier(d + h, r) - barrier(d - h, r)) / (2.0 * h);
            assert!((slope - barrier_slope(d, r)).abs() < 1e-5 * slope.abs().max(1e-3), "slope at {d}");
            let curvature = (barrier_slope(d + h, r) - barrier_slope(d - h, r)) / (2.0 * h);
            assert!(
                (curvature - barrier_curvature(d, r)).abs() < 1e-4 * curvature.abs().max(1.0),
                "curvature at {d}: {curvature} vs {}",
                barrier_curvature(d, r)
            );
        }
        // Half the reach under one weight with κ = 1 / (1.193·r).
        let push = -barrier_slope(0.5 * r, r) / (1.193 * r);
        assert!((push - 1.0).abs() < 1e-3, "{push}");
    }

    /// The gap bounds only skip sites that cannot touch or cut a step: a
    /// cloth moved about over a ball and the ground touches at the same
    /// places, with the same gaps, as one measured afresh, and its steps are
    /// limited alike.
    #[test]
    fn the_gap_bounds_never_change_what_is_measured() {
        use crate::world::ColliderShape;
        let obstacles = [
            Obstacle {
                shape: ColliderShape::Sphere { center: DVec3::new(0.0, 0.0, 0.0), radius: 0.3 },
                thickness: 0.003,
            },
            Obstacle { shape: ColliderShape::Ground { height: -0.31 }, thickness: 0.003 },
        ];
        let n = 9;
        let spacing = 0.08;
        let free: Vec<usize> = (0..n * n).collect();
        let mut edges = Vec::new();
        for j in 0..n {
            for i in 0..n - 1 {
                edges.push((j * n + i, j * n + i + 1, edges.len(), spacing));
                edges.push((i * n + j, (i + 1) * n + j, edges.len(), spacing));
            }
        }
        let rank: Vec<Option<usize>> = (0..n * n).map(Some).collect();
        let kept = Colliders::new(&obstacles, DVec3::ZERO, &free, &edges, spacing);
        let mut x: Vec<DVec3> = (0..n * n)
            .map(|k| DVec3::new(((k % n) as f64 - 4.0) * spacing, 0.304, ((k / n) as f64 - 4.0) * spacing))
            .collect();
        let (mut with_history, mut afresh) = (Vec::new(), Vec::new());
        let mut most_touching = 0;
        for round in 0..40 {
            // Sweeps that sink the cloth towards the ball, then lift it off again.
            let lift = if round < 25 { -0.0004 } else { 0.01 };
            for (k, p) in x.iter_mut().enumerate() {
                p.y += lift * (1.0 + 0.3 * ((k * 7 + round) % 5) as f64 / 5.0);
                p.x += 0.0003 * (((k + round) % 3) as f64 - 1.0);
            }
            let fresh = Colliders::new(&obstacles, DVec3::ZERO, &free, &edges, spacing);
            kept.touches(&x, &mut with_history);
            fresh.touches(&x, &mut afresh);
            assert_eq!(with_history.len(), afresh.len(), "round {round}");
            most_touching = most_touching.max(afresh.len());
            for (a, b) in with_history.iter().zip(&afresh) {
                assert_eq!((a.site, a.obstacle, a.gap_m, a.outward), (b.site, b.obstacle, b.gap_m, b.outward));
            }
            let direction: Vec<f64> = (0..3 * n * n).map(|k| if k % 3 == 1 { -0.05 } else { 0.001 }).collect();
            let fresh = Colliders::new(&obstacles, DVec3::ZERO, &free, &edges, spacing);
            assert_eq!(kept.step_limit(&x, &rank, &direction, 1.0), fresh.step_limit(&x, &rank, &direction, 1.0));
        }
        assert!(most_touching > 10, "the cloth reached the ball on the way: {most_touching}");
    }
}
