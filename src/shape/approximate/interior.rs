//! Placing grid points inside a triangle of kept catenaries (the paper's
//! method), and looking kept catenaries up by their pins.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::{DVec2, DVec3};

use super::delaunay::cross_i64;
use super::{CatenaryEdge, CatenaryNetwork, GridSpec, PinPoint, Placement};
use crate::shape::catenary::Catenary;

/// Grid point positions while they are being placed: how each point was
/// placed, and by how many kept catenaries or triangles. More than one covers a
/// point only where ties kept two triangulations (see `network::survivors`).
pub(super) struct Placed {
    pub(super) positions: Vec<DVec3>,
    pub(super) placement: Vec<Option<Placement>>,
    covers: Vec<u32>,
}

impl Placed {
    /// `points` grid points, none placed yet.
    pub(super) fn new(points: usize) -> Self {
        Placed { positions: vec![DVec3::ZERO; points], placement: vec![None; points], covers: vec![0; points] }
    }

    /// Places point `k` at `position`, overriding any earlier placement.
    pub(super) fn set(&mut self, k: usize, how: Placement, position: DVec3) {
        self.positions[k] = position;
        self.placement[k] = Some(how);
        self.covers[k] = 1;
    }

    /// Places point `k` at `position` by `how`. A point placed `how` before
    /// takes the highest y of its placements and, after [`Placed::finish`], the
    /// mean of their x and z: a set function, so the result does not depend on
    /// the order of the catenaries or triangles. A single placement is kept as is.
    pub(super) fn cover(&mut self, k: usize, how: Placement, position: DVec3) {
        if self.placement[k] == Some(how) {
            let sum = &mut self.positions[k];
            *sum = DVec3::new(sum.x + position.x, sum.y.max(position.y), sum.z + position.z);
            self.covers[k] += 1;
        } else {
            self.set(k, how, position);
        }
    }

    /// Turns the x/z sums of points covered several times into means; every
    /// point must be placed.
    pub(super) fn finish(mut self) -> (Vec<DVec3>, Vec<Placement>) {
        for (position, &covers) in self.positions.iter_mut().zip(&self.covers) {
            if covers > 1 {
                position.x /= covers as f64;
                position.z /= covers as f64;
            }
        }
        (self.positions, self.placement.into_iter().map(|p| p.expect("every point placed")).collect())
    }
}

/// Lookup of kept catenaries by their (unordered) pin pair.
pub(super) struct EdgeLookup<'a> {
    kept: &'a [CatenaryEdge],
    by_pins: HashMap<(usize, usize), usize>,
}

impl<'a> EdgeLookup<'a> {
    pub(super) fn new(kept: &'a [CatenaryEdge]) -> Self {
        let by_pins = kept.iter().enumerate().map(|(k, e)| ((e.a, e.b), k)).collect();
        EdgeLookup { kept, by_pins }
    }

    /// Point at arc fraction `t` of the way from pin `from` to pin `to`.
    pub(super) fn point(&self, from: usize, to: usize, t: f64) -> DVec3 {
        self.directed(from, to).point(t)
    }

    /// The kept catenary from pin `from` to pin `to`.
    fn directed(&self, from: usize, to: usize) -> Directed<'a> {
        let key = if from < to { (from, to) } else { (to, from) };
        Directed { catenary: &self.kept[self.by_pins[&key]].catenary, reversed: from > to }
    }
}

/// A kept catenary walked from one of its pins to the other.
#[derive(Clone, Copy)]
pub(super) struct Directed<'a> {
    catenary: &'a Catenary,
    reversed: bool,
}

impl Directed<'_> {
    /// Point at arc fraction `t` of the way.
    fn point(&self, t: f64) -> DVec3 {
        self.catenary.point_at_arc_fraction(if self.reversed { 1.0 - t } else { t })
    }
}

/// Catenaries from the vertices of one triangle, by vertex and by the fraction
/// along the opposite edge they end at (as bits). Grid points on one line
/// through a vertex mostly share that fraction bit for bit, and then the
/// catenary: found once, a third of the solves are saved on the benchmark grid.
#[derive(Default)]
pub(super) struct Fans {
    /// Per vertex: fraction bits → index into `catenaries`. Small entries: with
    /// whole catenaries in the table, moving them cost what the solves saved.
    by_fraction: [HashMap<u64, u32, BuildHasherDefault<BitsHasher>>; 3],
    catenaries: Vec<Catenary>,
}

impl Fans {
    /// Empties them for a triangle of about `points` grid points.
    fn clear(&mut self, points: usize) {
        for map in &mut self.by_fraction {
            map.clear();
            map.reserve(points);
        }
        self.catenaries.clear();
    }

    /// The catenary from vertex `v` ending at fraction `t`, from `solve` the first time.
    fn get(&mut self, v: usize, t: f64, solve: impl FnOnce() -> Catenary) -> &Catenary {
        let next = self.catenaries.len() as u32;
        let k = *self.by_fraction[v].entry(t.to_bits()).or_insert(next);
        if k == next {
            self.catenaries.push(solve());
        }
        &self.catenaries[k as usize]
    }
}

/// A multiplicative hash for [`Fans`]' keys, which are whole `f64` bit
/// patterns: cheaper than the default SipHash for one-word keys.
#[derive(Default)]
pub(super) struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0 ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29);
    }
}

/// Places the grid points inside the triangles of a hull of pins.
pub(super) struct TrianglePlacer<'a> {
    grid: GridSpec,
    network: &'a CatenaryNetwork,
    lookup: EdgeLookup<'a>,
    /// Each pin's grid point.
    points: Vec<(i64, i64)>,
    elasticity: f64,
    /// Kept across triangles: allocating them afresh cost page faults.
    fans: Fans,
}

impl<'a> TrianglePlacer<'a> {
    /// A placer for `network`'s triangles, whose pins lie at grid `points`.
    pub(super) fn new(grid: GridSpec, network: &'a CatenaryNetwork, points: Vec<(i64, i64)>, elasticity: f64) -> Self {
        let lookup = EdgeLookup::new(&network.kept);
        TrianglePlacer { grid, network, lookup, points, elasticity, fans: Fans::default() }
    }

    /// Places the grid points inside triangle `tri` (pin indices).
    pub(super) fn place(&mut self, tri: [usize; 3], placed: &mut Placed) {
        let TrianglePlacer { grid, network, lookup, points, elasticity, fans } = self;
        let (grid, elasticity) = (*grid, *elasticity);
        let pins = &network.pins;
        let corners = tri.map(|k| points[k]);
        let area2 = cross_i64(corners[0], corners[1], corners[2]);
        let (min_i, max_i) = (corners.iter().map(|c| c.0).min().unwrap(), corners.iter().map(|c| c.0).max().unwrap());
        let (min_j, max_j) = (corners.iter().map(|c| c.1).min().unwrap(), corners.iter().map(|c| c.1).max().unwrap());
        let material = tri.map(|k| grid.material(pins[k].grid.0, pins[k].grid.1));
        let opposite = [0, 1, 2].map(|v| lookup.directed(tri[(v + 1) % 3], tri[(v + 2) % 3]));
        // About the triangle's grid points, an upper bound on its rays.
        fans.clear(area2.unsigned_abs() as usize / 2);
        for j in min_j..=max_j {
            for i in min_i..=max_i {
                let k = grid.index(i as usize, j as usize);
                // Pins and catenary points stay; another triangle's points are covered again.
                if !matches!(placed.placement[k], None | Some(Placement::Interior)) {
                    continue;
                }
                let p = (i, j);
                let w = [
                    cross_i64(corners[1], corners[2], p),
                    cross_i64(corners[2], corners[0], p),
                    cross_i64(corners[0], corners[1], p),
                ];
                if w.iter().any(|&x| x != 0 && x.signum() != area2.signum()) {
                    continue;
                }
                let lambda = w.map(|x| x as f64 / area2 as f64);
                let position = interior_point(&opposite, fans, pins, tri, material, lambda, elasticity);
                placed.cover(k, Placement::Interior, position);
            }
        }
    }
}

/// The paper's placement of a point with barycentric coordinates `lambda` in
/// triangle `tri`: one catenary per vertex towards the opposite edge.
pub(super) fn interior_point(
    opposite: &[Directed; 3],
    fans: &mut Fans,
    pins: &[PinPoint],
    tri: [usize; 3],
    material: [DVec2; 3],
    lambda: [f64; 3],
    elasticity: f64,
) -> DVec3 {
    let mut best_y = f64::NEG_INFINITY;
    let mut xz = DVec2::ZERO;
    for v in 0..3 {
        let (b, c) = ((v + 1) % 3, (v + 2) % 3);
        let rest = lambda[b] + lambda[c];
        let candidate = if rest <= 1e-12 {
            pins[tri[v]].pos
        } else {
            // The line from vertex v through p meets edge b–c at fraction t from b.
            let t = lambda[c] / rest;
            let catenary = fans.get(v, t, || {
                let edge_material = material[b].lerp(material[c], t);
                let length = material[v].distance(edge_material) * elasticity;
                Catenary::new(pins[tri[v]].pos, opposite[v].point(t), length)
            });
            catenary.point_at_arc_fraction(rest)
        };
        best_y = best_y.max(candidate.y);
        xz += lambda[v] * DVec2::new(candidate.x, candidate.z);
    }
    DVec3::new(xz.x, best_y, xz.y)
}
