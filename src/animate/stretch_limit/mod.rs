//! The stretch limit: after the layer stack, no structural edge (along a row
//! or a column) is longer than (1 + limit) × its reach, so layers bend the
//! fabric but never tear it.
//!
//! A layer displaces points independently: a wave along the normal adds arc
//! length, a follow-through lag leaves points behind their pins. The limit
//! walks the cloth outward from the pins in the order of the blended
//! d_cp/d_max field (the one the layers attenuate by), and pulls each point
//! back within reach of every neighbour it has already placed ("follow the
//! leader"). Points nearer the pins are settled first and never move again,
//! so every edge is checked once from its later end and, where the reaches
//! allow a place at all, ends within its limit. The layers' intent stays: a
//! wave still waves and its free edge draws in, as a real flag's does; a
//! lagging point still lags, swung round its leaders instead of torn away.
//!
//! An edge may be (1 + limit) × its rest length (material spacing ×
//! elasticity, the larger of the two keys around the frame), or as long as
//! it is in either key shape if that is longer: a key whose pins stretch the
//! cloth beyond the limit (out of its reach) keeps its shape, and only what
//! the layers and overshooting easings add is limited.
//!
//! The walk cannot place a point whose placed neighbours were pulled apart
//! from two sides (where the chains from two pins meet, under a layer that
//! drags the whole cloth), so Gauss–Seidel passes over the edges still too
//! long follow, over-relaxed, until every edge is within its limit: one
//! check on most frames, tens of cheap passes where a layer asks the
//! impossible of a taut cloth (the magic carpet's drag at full speed).
//! Such a gap has to be shared out along both chains, which passes on the
//! grid itself do one cell at a time; so on grids of [`COARSEN_FROM_SIDE`]
//! points a side or more, the same evening runs first on the grid of every
//! other point (each coarse edge allowed the reach of the fine edges it
//! spans, recursively down to a small grid), and its moves, interpolated,
//! carry the fine grid most of the way before its own passes.
//!
//! Among colliders, every point the limit moves is kept out of them, and
//! every edge the evening passes shorten is lifted off a rim it would cut
//! ([`StretchLimiter::set_obstacles`]).
//!
//! Pins (ratio 0: the layers never move them) stay exactly in place. The
//! result depends on the frame alone, like every other step of `evaluate`.

use glam::DVec3;

use super::keep_out::{EdgeOut, edge_kept_out};
use crate::mesh::PointArrays;
use crate::world::{ColliderShape, Obstacle, Reach, push_out};

mod coarse;

use coarse::Coarse;

/// Passes of cyclic projection onto a point's leaders' reach: one suffices
/// with one leader; two or more leaders rarely need more than three.
const MAX_PASSES: usize = 8;

/// Most passes spent evening out what the walk from the pins left over the
/// limit on one grid, and most edge checks in all those passes (so a large
/// grid under an impossible layer still evaluates in tens of milliseconds).
/// The `evaluate` benchmark's 128² cloth needs 33 passes on its own grid
/// after the coarser ones (63 without them, BENCHMARKS.md).
const MAX_EVEN_PASSES: usize = 2000;
const MAX_EVEN_EDGE_VISITS: usize = 1 << 22;
/// Among colliders the passes can go on for ever where a collider holds an
/// edge longer than its limit (cloth stretched over a ball by a sway): the
/// shortening pulls a point in, keeping it out lengthens the edge again.
/// So among colliders the passes stop once this many in a row have not
/// lowered the edges' summed excess by [`STALL_GAIN`]: the excess then stays
/// where the collider holds it. Passes that keep gaining go on to the cap
/// (a tablecloth falling back onto its table under a follow-through).
const STALLED_PASSES_AMONG_OBSTACLES: usize = 32;
/// The share of the summed excess a pass must take off to count as progress.
const STALL_GAIN: f32 = 1e-2;
/// Over-relaxation of the evening passes: an edge over its limit is cut by
/// this many times its excess. Measured on the bundled scenes: 1.0 needs up
/// to 1579 passes, 1.5 up to 600, 1.8 about 200; the 128² benchmark does not
/// settle within 128 passes at 1.5, and 1.9 oscillates on one carpet frame.
const OMEGA: f32 = 1.8;

/// How far past its limit an edge may end, relative (0.25 %): the evening
/// passes approach the limit gradually and stop once no edge is longer.
const SLACK: f32 = 2.5e-3;

/// The walk order and reach limits, kept between frames so the order is
/// only sorted again when the ratio field changes.
#[derive(Clone, Debug, Default)]
pub struct StretchLimiter {
    /// The ratio field `order` was sorted for, by bits.
    ratio_bits: Vec<u32>,
    /// Point indices by increasing ratio, ties by index.
    order: Vec<u32>,
    /// Position of each point in `order`.
    rank: Vec<u32>,
    /// Each point's structural neighbours, left, right, up, down ([`NONE`]
    /// past the grid's edge), for the grid `neighbours_grid`.
    neighbours: Vec<[u32; 4]>,
    neighbours_grid: (usize, usize),
    /// Per point, a bit for each side whose neighbour comes earlier in the
    /// walk (lower rank): its leaders, for `order` and `neighbours`.
    placed_before: Vec<u8>,
    /// Squared longest allowed length of the edge from point k to k + 1 (along u).
    allowed2_u: Vec<f32>,
    /// The same for the edge from k to k + cols (along v).
    allowed2_v: Vec<f32>,
    /// Points whose edges the next evening pass checks, one bit per rank in
    /// `order`: a pass visits the set bits in walk order (the order a scan
    /// of all of `order` skipping the rest would take) without scanning
    /// every point. `marks` is the current pass's set.
    next_marks: Vec<u64>,
    marks: Vec<u64>,
    /// Colliders the limit keeps points out of as it moves them (see
    /// [`StretchLimiter::set_obstacles`]); none by default.
    obstacles: Vec<Obstacle>,
    /// Each obstacle's box, swollen by its thickness, in f32: most points are
    /// outside every one, and are passed over without measuring a distance.
    obstacle_bounds: Vec<([f32; 3], [f32; 3])>,
    /// The obstacles the evening passes lift edges out of, and where they
    /// reach (see [`StretchLimiter::set_obstacles`]).
    edge_obstacles: Vec<Obstacle>,
    edge_reach: Option<Reach>,
    /// The evening on the grid of every other point, run first (see
    /// [`StretchLimiter::even`]); made on first use, with these obstacles.
    coarse: Option<Box<Coarse>>,
}

/// No neighbour on that side of a point.
const NONE: u32 = u32::MAX;

/// Grids with fewer points than this on a side are limited directly; larger
/// ones first on their coarser grid (so 128² runs 65², 33², 17² and 9² first).
const COARSEN_FROM_SIDE: usize = 12;

/// What one key shape allows its edges: the rest lengths, and the length of
/// the edge from each point to its right (`u_m`) and lower (`v_m`)
/// neighbour in the shape. The last column's `u_m` and last row's `v_m`
/// entries are unused (0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeReach {
    pub rest_u_m: f32,
    pub rest_v_m: f32,
    pub u_m: Vec<f32>,
    pub v_m: Vec<f32>,
}

impl EdgeReach {
    /// The edges of a `cols × rows` shape whose rest lengths are `rest_u_m` and `rest_v_m`.
    pub fn of(points: &PointArrays, cols: usize, rows: usize, rest_u_m: f32, rest_v_m: f32) -> EdgeReach {
        let n = cols * rows;
        let (mut u_m, mut v_m) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..n {
            let (i, j) = (k % cols, k / cols);
            if i + 1 < cols {
                u_m[k] = points.get(k).distance(points.get(k + 1));
            }
            if j + 1 < rows {
                v_m[k] = points.get(k).distance(points.get(k + cols));
            }
        }
        EdgeReach { rest_u_m, rest_v_m, u_m, v_m }
    }
}

impl StretchLimiter {
    /// The colliders every point the limit moves is kept out of (the nearest
    /// way), so that pulling an edge short never pulls it into a table: the
    /// limit and the contact agree instead of undoing each other. The
    /// evening passes on this grid also lift each edge they shorten out of
    /// the analytic colliders (not meshes: against a walker's body the
    /// passes fought it, and the contact rounds lift its edges as before).
    /// Empty: none, and the result is exactly as without.
    pub fn set_obstacles(&mut self, obstacles: &[Obstacle]) {
        self.set_point_obstacles(obstacles);
        self.edge_obstacles.clear();
        self.edge_obstacles
            .extend(obstacles.iter().filter(|o| !matches!(o.shape, ColliderShape::Mesh { .. })).cloned());
        self.edge_reach = (!self.edge_obstacles.is_empty()).then(|| Reach::of(&self.edge_obstacles));
    }

    /// The colliders the moved points are kept out of, on this grid and the
    /// coarser ones. A coarse edge spans two of the cloth's: its chord is no
    /// edge to lift, so the coarser grids get no edge obstacles.
    fn set_point_obstacles(&mut self, obstacles: &[Obstacle]) {
        self.obstacles.clear();
        self.obstacles.extend_from_slice(obstacles);
        self.obstacle_bounds.clear();
        self.obstacle_bounds.extend(obstacles.iter().map(|o| {
            let (lo, hi) = o.shape.bounds();
            let margin = o.thickness + 1e-3;
            ((lo - margin).as_vec3().to_array(), (hi + margin).as_vec3().to_array())
        }));
        if let Some(coarse) = &mut self.coarse {
            coarse.limiter.set_point_obstacles(obstacles);
        }
    }

    /// `p` moved out of the obstacles the nearest way (unchanged if outside).
    fn kept_out(&self, p: [f32; 3]) -> [f32; 3] {
        let inside = |(lo, hi): &([f32; 3], [f32; 3])| (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]);
        if !self.obstacle_bounds.iter().any(inside) {
            return p;
        }
        kept_out(&self.obstacles, p)
    }

    /// Pulls `points` (a `cols × rows` grid) so that every structural edge
    /// is at most `(1 + limit)` × the larger rest length in `reaches` (the
    /// key shapes around the frame), or as long as it is in one of those
    /// shapes, within [`SLACK`]. `ratio` is the blended d_cp/d_max field:
    /// points where it is 0 (pins) never move, the others are placed in
    /// increasing ratio. A limit that is 0, negative or not finite turns it
    /// off. Where pins hold an edge longer than that in no key (only a
    /// Between blend with other pins can), the passes stop at their cap with
    /// the excess spread as evenly as they got.
    pub fn apply(
        &mut self,
        limit: f32,
        (cols, rows): (usize, usize),
        ratio: &[f32],
        reaches: &[&EdgeReach],
        points: &mut PointArrays,
    ) {
        let n = cols * rows;
        if !(limit > 0.0 && limit.is_finite()) || n == 0 || ratio.len() != n || points.len() != n {
            return;
        }
        self.allowed(limit, reaches, n);
        self.limit_grid((cols, rows), ratio, points);
    }

    /// The limit with this grid's `allowed2_u`/`allowed2_v` set: the walk
    /// from the pins, then evening out what it could not place.
    fn limit_grid(&mut self, (cols, rows): (usize, usize), ratio: &[f32], points: &mut PointArrays) {
        // Gentle layers leave every edge within its limit: then the walk
        // would move nothing, and a scan in memory order is all it costs.
        if !self.mark_over(cols, rows, ratio, points, 1.0, false) {
            return;
        }
        self.sort_for((cols, rows), ratio);
        self.mark_over(cols, rows, ratio, points, 1.0, true);
        self.lead(ratio, points);
        self.even((cols, rows), ratio, points);
    }

    /// Evening passes until no edge is over its limit by more than
    /// [`SLACK`] (the ranks must be sorted). Where one is, on a grid large
    /// enough, the same evening on the coarser grid runs first and its moves,
    /// spread bilinearly over the points between (pins keep still), carry
    /// the fine grid most of the way: a gap where the chains from two pins
    /// meet is shared out along the whole chains in a few coarse passes
    /// instead of crawling out one cell a pass on the fine grid.
    fn even(&mut self, (cols, rows): (usize, usize), ratio: &[f32], points: &mut PointArrays) {
        let slack2 = (1.0 + SLACK) * (1.0 + SLACK);
        if !self.mark_over(cols, rows, ratio, points, slack2, false) {
            return;
        }
        if cols.min(rows) >= COARSEN_FROM_SIDE {
            self.even_coarse((cols, rows), ratio, points);
        }
        if !self.mark_over(cols, rows, ratio, points, slack2, true) {
            return;
        }
        let (mut least_excess, mut since_fewer, mut visits) = (f32::INFINITY, 0, 0);
        for pass in 0..MAX_EVEN_PASSES {
            let (excess, visited) = self.even_out(ratio, points, pass % 2 == 1);
            visits += visited;
            if !(excess > 0.0) || visits >= MAX_EVEN_EDGE_VISITS {
                break;
            }
            if self.obstacles.is_empty() {
                continue;
            }
            if excess < least_excess * (1.0 - STALL_GAIN) {
                (least_excess, since_fewer) = (excess, 0);
            } else {
                since_fewer += 1;
                if since_fewer >= STALLED_PASSES_AMONG_OBSTACLES {
                    break;
                }
            }
        }
    }

    /// Whether any edge is longer than `scale2` × its squared limit (and not
    /// held by pins at both ends); with `mark`, marks the ends of every such
    /// edge, and no other point, for the walk or the next evening pass (the
    /// ranks must be sorted).
    fn mark_over(
        &mut self,
        cols: usize,
        rows: usize,
        ratio: &[f32],
        points: &PointArrays,
        scale2: f32,
        mark: bool,
    ) -> bool {
        let PointArrays { x, y, z } = points;
        let n = cols * rows;
        if mark {
            self.next_marks.clear();
            self.next_marks.resize(n.div_ceil(64), 0);
        }
        let over = |k: usize, q: usize, allowed2: f32| {
            let d = [x[q] - x[k], y[q] - y[k], z[q] - z[k]];
            d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > allowed2 * scale2 && (ratio[k] > 0.0 || ratio[q] > 0.0)
        };
        // The edges along rows (k to k + 1), then along columns (k to k + cols).
        let along_u = (0..rows).flat_map(|j| j * cols..(j + 1) * cols - 1).map(|k| (k, k + 1, self.allowed2_u[k]));
        let along_v = (0..n.saturating_sub(cols)).map(|k| (k, k + cols, self.allowed2_v[k]));
        let mut any = false;
        for (k, q, allowed2) in along_u.chain(along_v) {
            if !over(k, q, allowed2) {
                continue;
            }
            // The marks are by rank, which `sort` sets: the first call only asks.
            if !mark {
                return true;
            }
            any = true;
            for p in [k, q] {
                mark_rank(&mut self.next_marks, self.rank[p] as usize);
            }
        }
        any
    }

    /// The walk from the pins outward: each point pulled within reach of the
    /// neighbours placed before it. Only the points [`mark_over`] marked (an
    /// edge over its limit) and those whose leaders moved are visited: any
    /// other point has every leader where it was and within reach, so the
    /// walk would leave it as it is, bit for bit (on the `evaluate`
    /// benchmark's frame the walk moves one point in four).
    ///
    /// [`mark_over`]: StretchLimiter::mark_over
    fn lead(&mut self, ratio: &[f32], points: &mut PointArrays) {
        let PointArrays { x, y, z } = points;
        std::mem::swap(&mut self.marks, &mut self.next_marks);
        for w in 0..self.marks.len() {
            // A moved point marks its followers, which come later in the walk:
            // later in this word (read again) or in a later one.
            while self.marks[w] != 0 {
                let bits = self.marks[w];
                self.marks[w] = bits & (bits - 1);
                let r = w * 64 + bits.trailing_zeros() as usize;
                let k = self.order[r] as usize;
                if !(ratio[k] > 0.0) {
                    continue;
                }
                // The already placed neighbours and the squared reach to each.
                let mut leaders = [(0usize, 0.0f32); 4];
                let mut count = 0;
                let placed_before = self.placed_before[k];
                for (slot, q) in self.neighbours[k].into_iter().enumerate() {
                    if placed_before & (1 << slot) != 0 {
                        leaders[count] = (q as usize, self.reach2(k, q as usize, slot));
                        count += 1;
                    }
                }
                let start = [x[k], y[k], z[k]];
                let mut p = start;
                let moved = count > 0;
                for _ in 0..MAX_PASSES {
                    let mut within = true;
                    for &(q, allowed2) in &leaders[..count] {
                        let d = [p[0] - x[q], p[1] - y[q], p[2] - z[q]];
                        let length2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        if length2 > allowed2 {
                            let scale = (allowed2 / length2).sqrt();
                            p = [x[q] + d[0] * scale, y[q] + d[1] * scale, z[q] + d[2] * scale];
                            within = false;
                        }
                    }
                    if moved && !within && !self.obstacles.is_empty() {
                        p = self.kept_out(p);
                    }
                    if within {
                        break;
                    }
                }
                let changed = p.iter().zip(&start).any(|(a, b)| a.to_bits() != b.to_bits());
                if !changed || !p.iter().all(|c| c.is_finite()) {
                    continue;
                }
                (x[k], y[k], z[k]) = (p[0], p[1], p[2]);
                for q in self.neighbours[k] {
                    if q == NONE {
                        continue;
                    }
                    let later = self.rank[q as usize] as usize;
                    if later > r {
                        mark_rank(&mut self.marks, later);
                    }
                }
            }
        }
    }

    /// One Gauss–Seidel pass over the edges still longer than their limit
    /// (by more than [`SLACK`]), shortening each to its limit by moving both
    /// ends (a pin's share goes to the other end); `backwards` runs the
    /// edges in the opposite order. Where the walk from the pins could not
    /// place a point (leaders pulled apart from two sides, as where the
    /// chains from two pins meet), this spreads the gap over both sides.
    /// Returns the summed excess of the edges that were over, relative to
    /// their limits (without colliders, how many were over; 0 when none
    /// was), and how many edges it checked.
    fn even_out(&mut self, ratio: &[f32], points: &mut PointArrays, backwards: bool) -> (f32, usize) {
        let PointArrays { x, y, z } = points;
        let slack2 = (1.0 + SLACK) * (1.0 + SLACK);
        let (mut over, mut checked) = (0.0, 0);
        // This pass's points in walk order (reversed when `backwards`); the
        // marks start empty for the next pass.
        std::mem::swap(&mut self.marks, &mut self.next_marks);
        self.next_marks.clear();
        self.next_marks.resize(self.marks.len(), 0);
        let words = self.marks.len();
        for w in 0..words {
            let w = if backwards { words - 1 - w } else { w };
            let mut bits = self.marks[w];
            while bits != 0 {
                let bit = if backwards { 63 - bits.leading_zeros() } else { bits.trailing_zeros() };
                bits &= !(1u64 << bit);
                let k = self.order[w * 64 + bit as usize] as usize;
                let placed_before = self.placed_before[k];
                // Each edge once, from its later end.
                for (slot, q) in self.neighbours[k].into_iter().enumerate() {
                    if placed_before & (1 << slot) == 0 {
                        continue;
                    }
                    checked += 1;
                    let q = q as usize;
                    let allowed2 = self.reach2(k, q, slot);
                    let d = [x[q] - x[k], y[q] - y[k], z[q] - z[k]];
                    let length2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if !(length2 > allowed2 * slack2) {
                        continue;
                    }
                    let (free_k, free_q) = (ratio[k] > 0.0, ratio[q] > 0.0);
                    let share_k = match (free_k, free_q) {
                        (true, true) => 0.5,
                        (true, false) => 1.0,
                        (false, true) => 0.0,
                        (false, false) => continue,
                    };
                    let shrink = 1.0 - (allowed2 / length2).sqrt();
                    // Measured only where the stall rule needs it (among colliders).
                    over += if self.obstacles.is_empty() { 1.0 } else { (length2 / allowed2).sqrt() - 1.0 };
                    let cut = (OMEGA * shrink).min(1.0);
                    let (cut_k, cut_q) = (cut * share_k, cut * (1.0 - share_k));
                    for (axis, a) in [&mut *x, &mut *y, &mut *z].into_iter().enumerate() {
                        a[k] += d[axis] * cut_k;
                        a[q] -= d[axis] * cut_q;
                    }
                    if !self.obstacles.is_empty() {
                        for end in [k, q].into_iter().filter(|&end| ratio[end] > 0.0) {
                            [x[end], y[end], z[end]] = self.kept_out([x[end], y[end], z[end]]);
                        }
                    }
                    self.lift_edge(k, q, ratio, [&mut *x, &mut *y, &mut *z]);
                    // Both ends moved: every edge of theirs is checked again next pass.
                    for moved in [k, q] {
                        let around = self.neighbours[moved];
                        for p in std::iter::once(moved as u32).chain(around.into_iter().filter(|&p| p != NONE)) {
                            mark_rank(&mut self.next_marks, self.rank[p as usize] as usize);
                        }
                    }
                }
            }
        }
        (over, checked)
    }

    /// Lifts the edge `k`–`q` a pass just shortened out of the analytic
    /// colliders ([`edge_kept_out`]), moving both its ends (both free): the
    /// shortening then never pulls a chord across a table's rim for the
    /// contact rounds to lift again, round after round. An edge through a
    /// solid is left to those rounds. Its ends are marked for the next
    /// pass already.
    fn lift_edge(&self, k: usize, q: usize, ratio: &[f32], [x, y, z]: [&mut [f32]; 3]) {
        let Some(reach) = &self.edge_reach else { return };
        if !(ratio[k] > 0.0 && ratio[q] > 0.0) {
            return;
        }
        let at = |x: &[f32], y: &[f32], z: &[f32], k: usize| DVec3::new(x[k].into(), y[k].into(), z[k].into());
        let (a0, b0) = (at(x, y, z, k), at(x, y, z, q));
        let EdgeOut::Lifted(a, b) = edge_kept_out(&self.edge_obstacles, reach, a0, b0) else { return };
        if (a, b) == (a0, b0) || !a.is_finite() || !b.is_finite() {
            return;
        }
        [x[k], y[k], z[k]] = a.as_vec3().to_array();
        [x[q], y[q], z[q]] = b.as_vec3().to_array();
    }

    /// The walk order for `ratio`, sorted again only when the field changed
    /// (on a held key it never does).
    fn sort(&mut self, ratio: &[f32]) -> bool {
        let same =
            self.ratio_bits.len() == ratio.len() && self.ratio_bits.iter().zip(ratio).all(|(b, r)| *b == r.to_bits());
        if same {
            return false;
        }
        self.ratio_bits.clear();
        self.ratio_bits.extend(ratio.iter().map(|r| r.to_bits()));
        // Ratios are never negative (a NaN sorts last and is never moved), so
        // their bits order as the numbers do; the index breaks ties.
        let mut keyed: Vec<u64> = ratio
            .iter()
            .enumerate()
            .map(|(k, r)| (u64::from(if *r >= 0.0 { r.to_bits() } else { 0 }) << 32) | k as u64)
            .collect();
        keyed.sort_unstable();
        self.order.clear();
        self.order.extend(keyed.iter().map(|key| *key as u32));
        self.rank.resize(ratio.len(), 0);
        for (position, &k) in self.order.iter().enumerate() {
            self.rank[k as usize] = position as u32;
        }
        true
    }

    /// The squared reach of the edge from `k` to its neighbour `q` on side
    /// `slot` (left, right, up, down).
    fn reach2(&self, k: usize, q: usize, slot: usize) -> f32 {
        match slot {
            0 => self.allowed2_u[q],
            1 => self.allowed2_u[k],
            2 => self.allowed2_v[q],
            _ => self.allowed2_v[k],
        }
    }

    /// The walk order, each point's neighbours and which of them lead it,
    /// for `ratio` on a `cols × rows` grid; made again only when one changed.
    fn sort_for(&mut self, grid: (usize, usize), ratio: &[f32]) {
        let (sorted, neighboured) = (self.sort(ratio), self.neighbours_of(grid));
        if sorted || neighboured {
            let (neighbours, rank) = (&self.neighbours, &self.rank);
            self.placed_before.clear();
            self.placed_before.extend(neighbours.iter().zip(rank).map(|(around, &r)| {
                around.iter().enumerate().fold(0u8, |bits, (slot, &q)| {
                    if q != NONE && rank[q as usize] < r { bits | (1 << slot) } else { bits }
                })
            }));
        }
    }

    /// Each point's neighbours on a `cols × rows` grid, made again only
    /// when the grid changed (then true).
    fn neighbours_of(&mut self, (cols, rows): (usize, usize)) -> bool {
        if self.neighbours_grid == (cols, rows) {
            return false;
        }
        self.neighbours_grid = (cols, rows);
        self.neighbours.clear();
        self.neighbours.extend((0..rows).flat_map(|j| {
            (0..cols).map(move |i| {
                let k = (j * cols + i) as u32;
                let at = |exists: bool, q: u32| if exists { q } else { NONE };
                [
                    at(i > 0, k.wrapping_sub(1)),
                    at(i + 1 < cols, k + 1),
                    at(j > 0, k.wrapping_sub(cols as u32)),
                    at(j + 1 < rows, k + cols as u32),
                ]
            })
        }));
        true
    }

    fn allowed(&mut self, limit: f32, reaches: &[&EdgeReach], n: usize) {
        for (allowed2, along_v) in [(&mut self.allowed2_u, false), (&mut self.allowed2_v, true)] {
            let rest = reaches.iter().map(|r| if along_v { r.rest_v_m } else { r.rest_u_m }).fold(0.0, f32::max);
            let limited = rest * (1.0 + limit);
            allowed2.clear();
            allowed2.resize(n, limited * limited);
            for reach in reaches {
                let lengths = if along_v { &reach.v_m } else { &reach.u_m };
                for (a, l) in allowed2.iter_mut().zip(lengths) {
                    *a = a.max(l * l);
                }
            }
        }
    }
}

/// Sets the bit of walk rank `r` in `marks` (one bit per rank).
#[inline(always)]
fn mark_rank(marks: &mut [u64], r: usize) {
    marks[r / 64] |= 1 << (r % 64);
}

/// `p` moved out of `obstacles` the nearest way (unchanged if outside).
fn kept_out(obstacles: &[Obstacle], p: [f32; 3]) -> [f32; 3] {
    let at = glam::DVec3::new(p[0].into(), p[1].into(), p[2].into());
    if obstacles.iter().all(|o| o.shape.keeps_clear(at, o.thickness)) {
        return p;
    }
    let q = push_out(obstacles, at);
    let q = q + (q - at).normalize_or_zero() * 1e-6;
    [q.x as f32, q.y as f32, q.z as f32]
}

/// The longest structural edge of a `cols × rows` grid against its rest
/// length, as a ratio (1.1: 10 % stretched): the measure the limit keeps.
pub fn longest_stretch(points: &[glam::Vec3], (cols, rows): (usize, usize), rest_u_m: f64, rest_v_m: f64) -> f64 {
    let mut longest = 0.0f64;
    for k in 0..cols * rows {
        let (i, j) = (k % cols, k / cols);
        if i + 1 < cols {
            longest = longest.max(f64::from(points[k].distance(points[k + 1])) / rest_u_m);
        }
        if j + 1 < rows {
            longest = longest.max(f64::from(points[k].distance(points[k + cols])) / rest_v_m);
        }
    }
    longest
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// A straight strip of `n` points 1 m apart along x, pinned at point 0.
    fn strip(n: usize) -> (PointArrays, Vec<f32>, EdgeReach) {
        let flat: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let points = PointArrays::from_vec3s(&flat);
        let ratio = (0..n).map(|i| i as f32 / (n - 1) as f32).collect();
        let reach = EdgeReach::of(&points, n, 1, 1.0, 1.0);
        (points, ratio, reach)
    }

    #[test]
    fn a_stretched_strip_is_pulled_back_towards_its_pin() {
        let (mut points, ratio, reach) = strip(5);
        // A layer pushed the free end 3 m further out along x and lifted it.
        for k in 1..5 {
            points.set(k, Vec3::new(k as f32 * 1.75, k as f32 * 0.5, 0.0));
        }
        StretchLimiter::default().apply(0.1, (5, 1), &ratio, &[&reach], &mut points);
        let positions: Vec<Vec3> = (0..5).map(|k| points.get(k)).collect();
        assert_eq!(positions[0], Vec3::ZERO, "the pin stays");
        assert!(longest_stretch(&positions, (5, 1), 1.0, 1.0) <= 1.1 + 1e-6);
        // Each edge keeps its direction: the strip still rises the way the layer lifted it.
        for k in 1..5 {
            let d = positions[k] - positions[k - 1];
            assert!((d.length() - 1.1).abs() < 1e-5, "edge {k} is at the limit: {}", d.length());
            assert!((d.y / d.x - 0.5 / 1.75).abs() < 1e-5, "edge {k} keeps its slope");
        }
    }

    #[test]
    fn edges_within_the_limit_are_left_alone() {
        let (mut points, ratio, reach) = strip(4);
        points.set(3, Vec3::new(3.05, 0.3, 0.0));
        let before = points.clone();
        StretchLimiter::default().apply(0.1, (4, 1), &ratio, &[&reach], &mut points);
        assert_eq!(points, before);
    }

    #[test]
    fn zero_negative_and_nan_limits_are_off() {
        let (mut points, ratio, reach) = strip(3);
        points.set(2, Vec3::new(9.0, 0.0, 0.0));
        let before = points.clone();
        for limit in [0.0, -0.5, f32::NAN, f32::INFINITY] {
            StretchLimiter::default().apply(limit, (3, 1), &ratio, &[&reach], &mut points);
            assert_eq!(points, before, "limit {limit}");
        }
    }

    #[test]
    fn a_key_stretched_by_its_pins_keeps_its_shape() {
        // Pins 4 m apart on a 3 m strip: the rest shape itself is stretched past the limit.
        let flat: Vec<Vec3> = (0..4).map(|i| Vec3::new(i as f32 * 4.0 / 3.0, 0.0, 0.0)).collect();
        let mut points = PointArrays::from_vec3s(&flat);
        let reach = EdgeReach::of(&points, 4, 1, 1.0, 1.0);
        let ratio = [0.0, 1.0, 1.0, 0.0];
        let before = points.clone();
        StretchLimiter::default().apply(0.1, (4, 1), &ratio, &[&reach], &mut points);
        assert_eq!(points, before, "the key's own stretch is its reach");
    }

    #[test]
    fn a_grid_pulled_apart_by_a_wave_ends_within_the_limit_and_the_pins_stay() {
        let (cols, rows) = (17, 9);
        let flat: Vec<Vec3> =
            (0..rows).flat_map(|j| (0..cols).map(move |i| Vec3::new(i as f32 * 0.1, -(j as f32) * 0.1, 0.0))).collect();
        let mut points = PointArrays::from_vec3s(&flat);
        let reach = EdgeReach::of(&points, cols, rows, 0.1, 0.1);
        // Pinned along the left edge; a steep wave along z grows away from it.
        let ratio: Vec<f32> = (0..cols * rows).map(|k| (k % cols) as f32 / (cols - 1) as f32).collect();
        for (k, a) in ratio.iter().enumerate() {
            let (u, v) = ((k % cols) as f32 * 0.1, (k / cols) as f32 * 0.1);
            let mut p = points.get(k);
            p.z += a * 0.3 * (u * 20.0 + v * 7.0).sin();
            points.set(k, p);
        }
        let waved: Vec<Vec3> = (0..cols * rows).map(|k| points.get(k)).collect();
        assert!(longest_stretch(&waved, (cols, rows), 0.1, 0.1) > 1.5, "the test wave tears the cloth");
        let mut limiter = StretchLimiter::default();
        limiter.apply(0.1, (cols, rows), &ratio, &[&reach], &mut points);
        let limited: Vec<Vec3> = (0..cols * rows).map(|k| points.get(k)).collect();
        assert!(longest_stretch(&limited, (cols, rows), 0.1, 0.1) <= 1.1 + 1e-5);
        for j in 0..rows {
            assert_eq!(limited[j * cols], flat[j * cols], "pin row {j}");
        }
        // Still a wave: the free edge swings in z.
        let swing = (0..rows).map(|j| limited[j * cols + cols - 1].z.abs()).fold(0.0, f32::max);
        assert!(swing > 0.05, "the wave survives: {swing}");
        // The same input twice gives the same output (the cached order).
        let mut again = PointArrays::from_vec3s(&waved);
        limiter.apply(0.1, (cols, rows), &ratio, &[&reach], &mut again);
        assert_eq!(again, points);
    }

    #[test]
    fn nan_points_are_not_spread() {
        let (mut points, ratio, reach) = strip(3);
        points.set(1, Vec3::new(f32::NAN, 0.0, 0.0));
        points.set(2, Vec3::new(5.0, 0.0, 0.0));
        StretchLimiter::default().apply(0.1, (3, 1), &ratio, &[&reach], &mut points);
        assert_eq!(points.get(0), Vec3::ZERO);
        assert!(points.get(2).is_finite(), "{}", points.get(2));
    }

    /// A `side × side` cloth 2 m wide, flat and level, held at its four
    /// corners, swayed along x by `sway` times each point's ratio (its
    /// distance to the nearest corner over the largest such distance), as
    /// the `evaluate` benchmark's sway drags its cloth: the rest grid, the
    /// ratios, the reach and the swayed grid.
    fn swayed_square(side: usize, sway: f32) -> (Vec<Vec3>, Vec<f32>, EdgeReach, PointArrays) {
        let h = 2.0 / (side - 1) as f32;
        let flat: Vec<Vec3> =
            (0..side * side).map(|k| Vec3::new((k % side) as f32 * h, 1.0, (k / side) as f32 * h)).collect();
        let corners = [flat[0], flat[side - 1], flat[side * (side - 1)], flat[side * side - 1]];
        let nearest: Vec<f32> =
            flat.iter().map(|p| corners.iter().map(|c| c.distance(*p)).fold(f32::INFINITY, f32::min)).collect();
        let far = nearest.iter().copied().fold(0.0, f32::max);
        let ratio: Vec<f32> = nearest.iter().map(|d| d / far).collect();
        let reach = EdgeReach::of(&PointArrays::from_vec3s(&flat), side, side, h, h);
        let swayed: Vec<Vec3> = flat.iter().zip(&ratio).map(|(p, r)| *p + Vec3::X * sway * r).collect();
        (flat, ratio, reach, PointArrays::from_vec3s(&swayed))
    }

    #[test]
    fn a_cloth_dragged_away_from_four_pins_ends_within_its_limit_on_any_grid() {
        // 257 a side ran out of passes before the coarse grids shared the gaps out.
        for side in [9, 17, 64, 129, 257] {
            let (flat, ratio, reach, mut points) = swayed_square(side, 0.3);
            let h = 2.0 / (side - 1) as f64;
            let swayed: Vec<Vec3> = (0..side * side).map(|k| points.get(k)).collect();
            assert!(longest_stretch(&swayed, (side, side), h, h) > 1.2, "{side}: the sway tears the cloth");
            StretchLimiter::default().apply(0.1, (side, side), &ratio, &[&reach], &mut points);
            let limited: Vec<Vec3> = (0..side * side).map(|k| points.get(k)).collect();
            let longest = longest_stretch(&limited, (side, side), h, h);
            assert!(longest <= 1.1 * (1.0 + f64::from(SLACK)) + 1e-5, "{side}: longest edge {longest}");
            for corner in [0, side - 1, side * (side - 1), side * side - 1] {
                assert_eq!(limited[corner], flat[corner], "{side}: corner {corner} is a pin");
            }
            // Still a sway: the middle is carried along x, less than asked.
            let middle = side / 2 * side + side / 2;
            let carried = limited[middle].x - flat[middle].x;
            assert!(carried > 0.05 && carried < 0.3, "{side}: the middle moved {carried} m");
        }
    }

    #[test]
    fn a_gentle_sway_leaves_a_large_grid_bit_for_bit() {
        let (_, ratio, reach, mut points) = swayed_square(65, 0.02);
        let before = points.clone();
        StretchLimiter::default().apply(0.1, (65, 65), &ratio, &[&reach], &mut points);
        assert_eq!(points, before);
    }

    #[test]
    fn the_same_drag_twice_gives_the_same_cloth() {
        // The coarse grids and the walk order are kept between frames.
        let (_, ratio, reach, swayed) = swayed_square(33, 0.3);
        let mut limiter = StretchLimiter::default();
        let (mut first, mut second) = (swayed.clone(), swayed.clone());
        limiter.apply(0.1, (33, 33), &ratio, &[&reach], &mut first);
        limiter.apply(0.1, (33, 33), &ratio, &[&reach], &mut second);
        assert_eq!(first, second);
        let mut fresh = swayed;
        StretchLimiter::default().apply(0.1, (33, 33), &ratio, &[&reach], &mut fresh);
        assert_eq!(fresh, first);
    }
}
