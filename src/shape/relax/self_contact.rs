//! The cloth's thickness between its own layers, kept by the sweeps.
//!
//! Every segment (rows, columns and both diagonals of each quad) and every
//! triangle (both ways of splitting each quad, so a mirrored grid has the
//! same set) that share no point are a pair that must stay apart. After
//! each sweep the pairs near each other are checked along the axis that
//! separated them when the sweep started (the direction between their
//! closest points then): the gap along it, the segment's lowest point minus
//! the triangle's highest, must stay at least the floor (the fabric's
//! thickness, at most a share of the spacing; or the pair's distance when
//! first listed, if that was nearer).
//!
//! The gap along a fixed axis is concave along the straight path from where
//! the sweep started the points to where it left them, so a pair apart on
//! the axis at both ends was apart all the way: no sweep carries one part of
//! the cloth through another, however far it moves, and motion across the
//! axis (a fold sliding along another) is left free.
//!
//! - A pair short of its floor is pushed apart along its axis, the two sides
//!   sharing the push, one pair after another, for a few rounds. A push
//!   leaves each point within the floor of its path in the sweep (the line
//!   from where the sweep started it to where the sweep left it): a point
//!   pushed off its path is further from where its constraints want it,
//!   the next sweep's step is larger, and so is the next push (a crumpled
//!   cloth once ran off by kilometres within a hundred sweeps).
//! - After those rounds a pair still short of its floor but with a positive
//!   gap has crossed nothing and is left (the floor gives rather than jam);
//!   one whose gap is gone goes back to where the sweep started it.
//!
//! Touched points lose their momentum, and the sweep's move is then the one
//! contact let through, plus any move it refused: a cloth pressed against
//! itself settles only when the constraints stop asking. Pairs that touch or
//! cross when a sweep starts have no side to keep and are left alone.
//!
//! Which pairs are near: listed Verlet-style, every pair closer than a radius
//! when listed, again only once points may have moved far enough since then
//! (a bound kept from the sweeps' moves, measured exactly before relisting)
//! for an unlisted pair to come within the floor. A listed pair is measured
//! again only once its points have travelled (each point's path length,
//! summed over sweeps) far enough to close its last measured gap to the
//! floor, and within a sweep only once one of its points has moved since it
//! was last looked at.

use std::collections::HashMap;
use std::hash::BuildHasherDefault;

use glam::DVec3;

use super::layout::Split;
use crate::shape::contact::{BoxGrid, CellHasher, segment_triangle_closest};

/// Largest floor, as a share of the smaller rest spacing: a flat grid's
/// nearest pairs that share no vertex are half a diagonal apart.
const FLOOR_SPACING_SHARE: f64 = 0.25;
/// Margin of the pair list beyond the floor and this sweep's moves, as a
/// share of the smaller rest spacing.
const SKIN_SPACING_SHARE: f64 = 0.25;
/// Most pairs listed at once (about 170 MB with their per-sweep records): a
/// cloth crumpled so tightly that more are near each other is not kept
/// apart at all (the sweeps stop, unsettled), rather than the list growing
/// without bound (a random 256² layout once listed 20 GB).
const MAX_PAIRS: usize = 1 << 20;
/// Rounds of pushes after a sweep.
const PUSH_ROUNDS: u32 = 8;
/// Rounds, after the pushes, that send a pair whose gap is gone back only as
/// far as it must go to have one; after them it goes back all the way.
const PART_BACK_ROUNDS: u32 = 8;
/// Share of a pair's floor it may be short of: pushes end once every pair is
/// this close to its floor (exactly would take many rounds where pushes share
/// points).
const FLOOR_TOLERANCE: f64 = 0.01;

/// A segment and a triangle that share no point, listed as near.
struct Pair {
    /// The segment's two grid points, then the triangle's three.
    points: [u32; 5],
    /// Its gap when last measured (at most its distance), and each point's odometer then.
    gap_m: f64,
    odometer_m: [f64; 5],
    /// How near it may come: the floor, or its distance when first listed if that was nearer.
    floor_m: f64,
}

pub(super) struct SelfContact {
    floor_m: f64,
    skin_m: f64,
    min_rest_m: f64,
    /// Where each grid point sits in a [`Split`].
    slots: Vec<usize>,
    free: Vec<bool>,
    segments: Vec<[u32; 2]>,
    triangles: Vec<[u32; 3]>,
    pairs: Vec<Pair>,
    /// More than [`MAX_PAIRS`] were near each other at the last listing.
    overwhelmed: bool,
    /// Positions when the pairs were listed (empty before the first listing).
    listed_at: Vec<DVec3>,
    radius_m: f64,
    /// Bound on how far any point is from where the pairs were listed.
    drift_m: f64,
    /// Per grid point, the length of the path it has taken over all sweeps.
    odometer_m: Vec<f64>,
    /// Positions and velocities (when pairs are listed) at the start of the sweep.
    before: [Vec<f64>; 3],
    /// Per grid point, where the sweep left it before contact moved it.
    swept: Vec<DVec3>,
    velocity_before: [Vec<f64>; 3],
    velocities_kept: bool,
    /// Per grid point: its odometer plus how far it is from where the sweep started it.
    trip_m: Vec<f64>,
    /// Per grid point: when contact last moved it this sweep (a count of moves; 0: not).
    moved_at: Vec<u32>,
    moves: u32,
    /// Per grid point: moved by contact this sweep.
    touched: Vec<bool>,
    /// Per pair, this sweep: when it was last looked at, its gap then (NaN: not
    /// measured), and its axis (distance and direction when the sweep started;
    /// NaN: not yet found).
    looked_at: Vec<u32>,
    measured_m: Vec<f64>,
    axes: Vec<(f64, DVec3)>,
}

/// What the check after a sweep did.
pub(super) struct Kept {
    /// Largest squared move the constraints asked for and contact let
    /// through, or refused, when contact held some point (the sweep's own
    /// figure would count the moves contact took back).
    pub(super) residual2: Option<f64>,
    /// Too many pairs were near each other to keep them apart
    /// ([`MAX_PAIRS`]): the sweep was not checked, and the relaxation must stop.
    pub(super) overwhelmed: bool,
}

enum Verdict {
    Clear,
    Push {
        axis: DVec3,
        by_m: f64,
    },
    /// Back towards where the sweep started it, keeping this share of the move.
    Back {
        kept: f64,
    },
}

impl SelfContact {
    /// The check for a `cols × rows` grid, or `None` where the cloth has no
    /// thickness or no pair could meet.
    pub(super) fn new(
        cols: usize,
        rows: usize,
        pinned: &[bool],
        thickness_m: f64,
        min_rest_m: f64,
    ) -> Option<SelfContact> {
        let floor_m = thickness_m.min(FLOOR_SPACING_SHARE * min_rest_m);
        if !(thickness_m > 0.0) || !(floor_m > 0.0) || cols < 2 || rows < 2 || cols * rows < 6 {
            return None;
        }
        let layout = Split::new(cols, rows);
        let n = cols * rows;
        Some(SelfContact {
            floor_m,
            skin_m: SKIN_SPACING_SHARE * min_rest_m,
            min_rest_m,
            slots: (0..n).map(|k| layout.slot(k % cols, k / cols)).collect(),
            free: pinned.iter().map(|p| !p).collect(),
            segments: both_split_segments(cols, rows),
            triangles: both_split_triangles(cols, rows),
            pairs: Vec::new(),
            overwhelmed: false,
            listed_at: Vec::new(),
            radius_m: 0.0,
            drift_m: 0.0,
            odometer_m: vec![0.0; n],
            before: Default::default(),
            swept: vec![DVec3::ZERO; n],
            velocity_before: Default::default(),
            velocities_kept: false,
            trip_m: vec![0.0; n],
            moved_at: vec![0; n],
            moves: 0,
            touched: vec![false; n],
            looked_at: Vec::new(),
            measured_m: Vec::new(),
            axes: Vec::new(),
        })
    }

    /// Notes where the points are before a sweep.
    pub(super) fn begin(&mut self, position: &[Split; 3], velocity: &[Split; 3]) {
        for (kept, axis) in self.before.iter_mut().zip(position) {
            kept.clear();
            kept.extend_from_slice(&axis.data);
        }
        self.velocities_kept = !self.pairs.is_empty();
        if self.velocities_kept {
            for (kept, axis) in self.velocity_before.iter_mut().zip(velocity) {
                kept.clear();
                kept.extend_from_slice(&axis.data);
            }
        }
    }

    /// Checks the sweep since [`SelfContact::begin`] (see the module doc),
    /// moving points apart or back where it must.
    pub(super) fn keep_apart(&mut self, position: &mut [Split; 3], velocity: &mut [Split; 3], momentum: f64) -> Kept {
        let moved_m = self.largest_move(position).sqrt();
        // Unlisted pairs were at least the radius apart when listed; each side
        // has come at most the drift nearer since, and this sweep moves each at
        // most `moved_m` plus what pushes add (at most the allowance).
        let mut allowance_m = (self.radius_m - self.floor_m) / 2.0 - self.drift_m - moved_m;
        if allowance_m < self.floor_m / 2.0 && !self.listed_at.is_empty() {
            self.drift_m = self.drift_since_listing();
            allowance_m = (self.radius_m - self.floor_m) / 2.0 - self.drift_m - moved_m;
        }
        if allowance_m < self.floor_m / 2.0 || self.listed_at.is_empty() {
            self.list(2.0 * self.floor_m + self.skin_m + 2.0 * moved_m);
            if self.overwhelmed {
                return Kept { residual2: None, overwhelmed: true };
            }
            allowance_m = (self.radius_m - self.floor_m) / 2.0 - moved_m;
        }
        let limit_m = moved_m + allowance_m;
        for (k, &slot) in self.slots.iter().enumerate() {
            self.swept[k] = at_split(position, slot);
            self.trip_m[k] = self.odometer_m[k] + self.swept[k].distance(at(&self.before, slot));
        }
        self.moved_at.fill(0);
        self.moves = 0;
        let count = self.pairs.len();
        self.looked_at.clear();
        self.looked_at.resize(count, 0);
        self.measured_m.clear();
        self.measured_m.resize(count, f64::NAN);
        self.axes.clear();
        self.axes.resize(count, (f64::NAN, DVec3::ZERO));
        let mut touched: Vec<usize> = Vec::new();
        // Per point sent back: the move it was refused.
        let mut refused: Vec<(usize, DVec3)> = Vec::new();
        let mut round = 0;
        loop {
            let moves_before_round = self.moves;
            for i in 0..count {
                let points = self.pairs[i].points;
                // Nothing moved since it was last looked at this sweep: nothing to redo.
                if round > 0 && points.iter().all(|&k| self.moved_at[k as usize] <= self.looked_at[i]) {
                    continue;
                }
                self.looked_at[i] = self.moves;
                if self.far_enough(&self.pairs[i]) {
                    // Its last measure, from before, still bounds it.
                    self.measured_m[i] = f64::NAN;
                    continue;
                }
                if let Some(bound_m) = self.boxed_gap(&self.pairs[i], position) {
                    self.measured_m[i] = bound_m;
                    continue;
                }
                let (verdict, gap_m) = self.verdict(i, position, round);
                self.measured_m[i] = gap_m;
                match verdict {
                    Verdict::Clear => {}
                    Verdict::Push { axis, by_m } => {
                        self.push_apart(points, axis, by_m, limit_m, position, &mut touched)
                    }
                    Verdict::Back { kept } => {
                        for k in points.map(|k| k as usize) {
                            if !self.free[k] {
                                continue;
                            }
                            let slot = self.slots[k];
                            let start = at(&self.before, slot);
                            let now = at_split(position, slot);
                            let back = start + (now - start) * kept;
                            if back != now {
                                refused.push((k, now - start));
                                self.moved(k, back, position, &mut touched);
                            }
                        }
                    }
                }
            }
            // The pairs looked at since the last move were measured where the sweep leaves them.
            if self.moves == moves_before_round {
                break;
            }
            round += 1;
        }
        self.add_to_odometers(position);
        for (pair, &measured_m) in self.pairs.iter_mut().zip(&self.measured_m) {
            if !measured_m.is_nan() {
                pair.gap_m = measured_m;
                pair.odometer_m = pair.points.map(|k| self.odometer_m[k as usize]);
            }
        }
        let mut residual2 = None;
        if !touched.is_empty() {
            for &k in &touched {
                set(velocity, self.slots[k], DVec3::ZERO);
                self.touched[k] = false;
            }
            residual2 = self.residual2(position, momentum).map(|mut most| {
                // A point sent back still asks for the step it was refused.
                for &(k, moved) in &refused {
                    let step = moved - at(&self.velocity_before, self.slots[k]) * momentum;
                    most = most.max(step.length_squared());
                }
                most
            });
        }
        self.drift_m += moved_m.max(if touched.is_empty() { 0.0 } else { limit_m });
        Kept { residual2, overwhelmed: false }
    }

    /// Whether the pair's points have travelled too little since it was last
    /// measured, this sweep's move included, to have come within its floor.
    fn far_enough(&self, pair: &Pair) -> bool {
        let travel = |n: usize| self.trip_m[pair.points[n] as usize] - pair.odometer_m[n];
        let segment = travel(0).max(travel(1));
        let triangle = travel(2).max(travel(3)).max(travel(4));
        pair.gap_m - segment - triangle > pair.floor_m
    }

    /// A lower bound of the pair's distance now, where it shows the pair
    /// clear of its floor without finding its axis (most of a falling
    /// cloth's listed pairs): the distance of its points' boxes where the
    /// sweep started them (at most their distance, which is their gap along
    /// the axis), less each side's largest move since. Where this is at least
    /// the floor, so is the gap along the axis: the verdict would be Clear.
    fn boxed_gap(&self, pair: &Pair, position: &[Split; 3]) -> Option<f64> {
        let slots = pair.points.map(|k| self.slots[k as usize]);
        let start = slots.map(|slot| at(&self.before, slot));
        let moved = |n: usize| at_split(position, slots[n]).distance(start[n]);
        let bound_m = box_distance(&start) - moved(0).max(moved(1)) - moved(2).max(moved(3)).max(moved(4));
        (bound_m >= pair.floor_m).then_some(bound_m)
    }

    /// Pair `i` checked along the axis that separated it when the sweep
    /// started, with its gap along that axis now (at most its distance).
    fn verdict(&mut self, i: usize, position: &[Split; 3], round: u32) -> (Verdict, f64) {
        let pair = &self.pairs[i];
        let slots = pair.points.map(|k| self.slots[k as usize]);
        if self.axes[i].0.is_nan() {
            let start = slots.map(|slot| at(&self.before, slot));
            let (d0, on_segment, on_triangle) = closest(&start);
            self.axes[i] = (d0, if d0 > 0.0 { (on_segment - on_triangle) / d0 } else { DVec3::ZERO });
        }
        let (d0, axis) = self.axes[i];
        let end = slots.map(|slot| at_split(position, slot));
        if !(d0 > 0.0) {
            // Touching or crossed already: no side to keep.
            return (Verdict::Clear, 0.0);
        }
        let gap_m =
            end[0].dot(axis).min(end[1].dot(axis)) - end[2].dot(axis).max(end[3].dot(axis)).max(end[4].dot(axis));
        if !gap_m.is_finite() || gap_m >= pair.floor_m * (1.0 - FLOOR_TOLERANCE) {
            return (Verdict::Clear, gap_m.max(0.0));
        }
        let verdict = if round < PUSH_ROUNDS {
            Verdict::Push { axis, by_m: pair.floor_m - gap_m }
        } else if gap_m > 0.0 {
            // Short of the floor but nothing crossed: the floor gives.
            Verdict::Clear
        } else if round < PUSH_ROUNDS + PART_BACK_ROUNDS {
            let start = slots.map(|slot| at(&self.before, slot));
            Verdict::Back { kept: share_apart(&start, &end, axis, 0.5 * pair.floor_m.min(d0)) }
        } else {
            Verdict::Back { kept: 0.0 }
        };
        (verdict, gap_m.max(0.0))
    }

    /// Moves the pair's free points apart along `axis` (from the triangle
    /// to the segment) by `by_m`, shared between the two sides, each point
    /// kept within `limit_m` of where the sweep started it and within the
    /// floor of its path in the sweep.
    fn push_apart(
        &mut self,
        points: [u32; 5],
        axis: DVec3,
        by_m: f64,
        limit_m: f64,
        position: &mut [Split; 3],
        touched: &mut Vec<usize>,
    ) {
        let points = points.map(|k| k as usize);
        let (segment, triangle) = points.split_at(2);
        let segment_free = segment.iter().any(|&k| self.free[k]);
        let triangle_free = triangle.iter().any(|&k| self.free[k]);
        let (to_segment, to_triangle) = match (segment_free, triangle_free) {
            (true, true) => (0.5, 0.5),
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => return,
        };
        for (side, share) in [(segment, to_segment), (triangle, -to_triangle)] {
            for &k in side {
                if !self.free[k] {
                    continue;
                }
                let slot = self.slots[k];
                let start = at(&self.before, slot);
                let mut p = at_split(position, slot) + axis * (by_m * share);
                p = near_path(p, start, self.swept[k], self.floor_m);
                let d = p - start;
                if d.length() > limit_m {
                    p = start + d * (limit_m / d.length());
                }
                self.moved(k, p, position, touched);
            }
        }
    }

    /// Puts point `k` at `p`, noting the move.
    fn moved(&mut self, k: usize, p: DVec3, position: &mut [Split; 3], touched: &mut Vec<usize>) {
        let slot = self.slots[k];
        set(position, slot, p);
        self.moves += 1;
        self.moved_at[k] = self.moves;
        self.trip_m[k] = self.odometer_m[k] + p.distance(at(&self.before, slot));
        if !self.touched[k] {
            self.touched[k] = true;
            touched.push(k);
        }
    }

    /// Adds each point's move over this sweep to its odometer.
    fn add_to_odometers(&mut self, position: &[Split; 3]) {
        for (k, &slot) in self.slots.iter().enumerate() {
            let d = at_split(position, slot).distance(at(&self.before, slot));
            if d.is_finite() {
                self.odometer_m[k] += d;
            }
        }
    }

    /// Largest squared move of any point since [`SelfContact::begin`].
    fn largest_move(&self, position: &[Split; 3]) -> f64 {
        let [x, y, z] = position;
        let [bx, by, bz] = &self.before;
        let mut most = 0.0f64;
        for t in 0..bx.len() {
            let (dx, dy, dz) = (x.data[t] - bx[t], y.data[t] - by[t], z.data[t] - bz[t]);
            let d2 = dx * dx + dy * dy + dz * dz;
            // NaN (a point bad input left non-finite) counts as not moving.
            most = if d2 > most { d2 } else { most };
        }
        most
    }

    /// How far any point is now from where the pairs were listed.
    fn drift_since_listing(&self) -> f64 {
        let mut most = 0.0f64;
        for (k, &slot) in self.slots.iter().enumerate() {
            let d = at(&self.before, slot).distance(self.listed_at[k]);
            most = if d > most { d } else { most };
        }
        most
    }

    /// The largest squared step the constraints asked for and contact let
    /// through: a point's move minus its carried momentum.
    fn residual2(&self, position: &[Split; 3], momentum: f64) -> Option<f64> {
        if !self.velocities_kept {
            return None;
        }
        let v0 = &self.velocity_before;
        let mut most = 0.0f64;
        for &slot in &self.slots {
            let step = at_split(position, slot) - at(&self.before, slot) - at(v0, slot) * momentum;
            let d2 = step.length_squared();
            most = if d2 > most { d2 } else { most };
        }
        Some(most)
    }

    /// Lists every pair closer than `radius_m` where the points were before this sweep.
    fn list(&mut self, radius_m: f64) {
        let positions: Vec<DVec3> = self.slots.iter().map(|&slot| at(&self.before, slot)).collect();
        let mut pairs = Vec::new();
        let mut overwhelmed = false;
        // Cells about a triangle's size: a triangle spans a few of them.
        let cell_m = radius_m.max(self.min_rest_m);
        let mut grid = BoxGrid::new(&positions, &self.triangles, cell_m, radius_m);
        let floors: HashMap<[u32; 5], f64, BuildHasherDefault<CellHasher>> =
            self.pairs.iter().map(|pair| (pair.points, pair.floor_m)).collect();
        for &[a, b] in &self.segments {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            if !pa.is_finite() || !pb.is_finite() {
                continue;
            }
            let segment_free = self.free[a as usize] || self.free[b as usize];
            grid.near(pa.min(pb), pa.max(pb), &mut |t| {
                let [p, q, r] = self.triangles[t as usize];
                if [p, q, r].contains(&a) || [p, q, r].contains(&b) {
                    return;
                }
                if !segment_free && !self.free[p as usize] && !self.free[q as usize] && !self.free[r as usize] {
                    return;
                }
                let [pp, pq, pr] = [p, q, r].map(|k| positions[k as usize]);
                // Their boxes' distance is at most theirs (with room for rounding).
                if box_distance(&[pa, pb, pp, pq, pr]) > radius_m * BOX_MARGIN {
                    return;
                }
                let (d, _, _) = segment_triangle_closest(pa, pb, pp, pq, pr);
                if d < radius_m {
                    if pairs.len() >= MAX_PAIRS {
                        overwhelmed = true;
                        return;
                    }
                    let points = [a, b, p, q, r];
                    // A pair listed before keeps its floor; one nearer than the
                    // floor when first seen may not come nearer than it is.
                    let floor_m = floors.get(&points).copied().unwrap_or(self.floor_m.min(d));
                    let odometer_m = points.map(|k| self.odometer_m[k as usize]);
                    pairs.push(Pair { points, gap_m: d, odometer_m, floor_m });
                }
            });
        }
        self.overwhelmed = overwhelmed;
        self.pairs = if overwhelmed { Vec::new() } else { pairs };
        self.listed_at = positions;
        self.radius_m = radius_m;
        self.drift_m = 0.0;
    }
}

/// `p` moved, if it must be, to within `reach_m` of the segment from `start` to `end`.
fn near_path(p: DVec3, start: DVec3, end: DVec3, reach_m: f64) -> DVec3 {
    let path = end - start;
    let along = if path == DVec3::ZERO { 0.0 } else { ((p - start).dot(path) / path.length_squared()).clamp(0.0, 1.0) };
    let on_path = start + path * along;
    let off = p - on_path;
    if off.length() > reach_m { on_path + off * (reach_m / off.length()) } else { p }
}

/// The largest share t of the move from `start` to `end` (each point along
/// its straight line, all at the same t) that keeps the pair at least
/// `target_m` apart along `axis`, given it was at t = 0. The gap is the least
/// of six differences of its points' heights on the axis, each linear in t,
/// so each gives the t where it reaches the target.
fn share_apart(start: &[DVec3; 5], end: &[DVec3; 5], axis: DVec3, target_m: f64) -> f64 {
    let mut kept = 1.0f64;
    for s in 0..2 {
        for t in 2..5 {
            let from = (start[s] - start[t]).dot(axis);
            let to = (end[s] - end[t]).dot(axis);
            if to < target_m && from > target_m {
                kept = kept.min((from - target_m) / (from - to));
            } else if !(from > target_m) && to < from {
                kept = 0.0;
            }
        }
    }
    if kept.is_finite() { kept.clamp(0.0, 1.0) } else { 0.0 }
}

/// How far past the listing radius a pair's boxes must be for it to be left
/// unmeasured: rounding never puts a pair's measured distance this far below
/// its boxes'.
const BOX_MARGIN: f64 = 1.0 + 1e-9;

/// Distance between the box round a pair's segment (points 0, 1) and the box
/// round its triangle (2, 3, 4): at most the pair's distance.
fn box_distance(p: &[DVec3; 5]) -> f64 {
    let (segment_min, segment_max) = (p[0].min(p[1]), p[0].max(p[1]));
    let (triangle_min, triangle_max) = (p[2].min(p[3]).min(p[4]), p[2].max(p[3]).max(p[4]));
    (triangle_min - segment_max).max(segment_min - triangle_max).max(DVec3::ZERO).length()
}

/// Closest points of a pair's segment (points 0, 1) and triangle (2, 3, 4).
fn closest(p: &[DVec3; 5]) -> (f64, DVec3, DVec3) {
    segment_triangle_closest(p[0], p[1], p[2], p[3], p[4])
}

fn at(data: &[Vec<f64>; 3], slot: usize) -> DVec3 {
    DVec3::new(data[0][slot], data[1][slot], data[2][slot])
}

pub(super) fn at_split(data: &[Split; 3], slot: usize) -> DVec3 {
    DVec3::new(data[0].data[slot], data[1].data[slot], data[2].data[slot])
}

pub(super) fn set(data: &mut [Split; 3], slot: usize, p: DVec3) {
    data[0].data[slot] = p.x;
    data[1].data[slot] = p.y;
    data[2].data[slot] = p.z;
}

/// Segments of the grid: rows, columns and both diagonals of every quad.
fn both_split_segments(cols: usize, rows: usize) -> Vec<[u32; 2]> {
    let mut segments = Vec::with_capacity(4 * cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let a = (j * cols + i) as u32;
            let (right, down) = (i + 1 < cols, j + 1 < rows);
            if right {
                segments.push([a, a + 1]);
            }
            if down {
                segments.push([a, a + cols as u32]);
            }
            if right && down {
                segments.push([a + 1, a + cols as u32]);
                segments.push([a, a + 1 + cols as u32]);
            }
        }
    }
    segments
}

/// Triangles of both ways of splitting every quad (four per quad).
fn both_split_triangles(cols: usize, rows: usize) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity(4 * cols * rows);
    for j in 0..rows.saturating_sub(1) {
        for i in 0..cols.saturating_sub(1) {
            let a = (j * cols + i) as u32;
            let (b, c, d) = (a + 1, a + cols as u32, a + 1 + cols as u32);
            triangles.extend([[a, b, c], [b, d, c], [a, b, d], [a, d, c]]);
        }
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_are_segments_and_triangles_sharing_no_point_in_both_splits() {
        let (segments, triangles) = (both_split_segments(3, 3), both_split_triangles(3, 3));
        // 6 along rows, 6 along columns, 2 diagonals in each of 4 quads.
        assert_eq!((segments.len(), triangles.len()), (20, 16));
        let contact = SelfContact::new(3, 3, &[false; 9], 0.003, 1.0).expect("a thickness");
        assert_eq!(contact.floor_m, 0.003);
        let thin = SelfContact::new(3, 3, &[false; 9], 1.0, 0.1).expect("a thickness");
        assert_eq!(thin.floor_m, FLOOR_SPACING_SHARE * 0.1, "at most a share of the spacing");
        assert!(SelfContact::new(3, 3, &[false; 9], 0.0, 1.0).is_none());
        assert!(SelfContact::new(3, 3, &[false; 9], f64::NAN, 1.0).is_none());
    }
}
