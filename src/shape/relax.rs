//! Relaxation (paper §3.1): fine-tunes the approximated surface into a rest shape.
//!
//! Constraints, as the paper lists them after Weil:
//! (i) every point keeps its grid neighbours at their rest distance:
//!     structural neighbours (along rows and columns) at spacing × elasticity,
//!     and shear diagonals within the range a woven fabric allows — the cell
//!     may shear up to [`MAX_SHEAR_DEG`] before its diagonals resist, which is
//!     what lets a curtain keep its sagging top edge instead of being pulled
//!     flat into rectangles — and
//! (ii) the angle with consecutive neighbours along a row or a column is
//!     limited by the fabric's stiffness ∈ [0, 1] (a smallest radius of
//!     curvature, enforced as a minimum distance between second neighbours).
//!
//! Solver: nonlinear Gauss–Seidel in gather form. Each free point moves by the
//! average of what its violated constraints ask, over-relaxed, plus momentum:
//! a share of the previous sweep's move is carried on (heavy-ball
//! acceleration), which speeds up the slow, cloth-wide modes that plain
//! Gauss–Seidel crawls through; a point faster than half a cell per sweep
//! drops it, so pins out of the cloth's reach cannot build up a runaway.
//! Constraints use squared lengths, so a sweep needs no square roots.
//!
//! Points are visited in four colours by the parity of their distance to the
//! nearest edge in i and in j; the points of one colour all move at once from
//! the same positions, so the result does not depend on a visiting order and
//! a mirror-symmetric input (in i or in j) relaxes to a bit-for-bit
//! mirror-symmetric shape. Interior points of one colour along a row are
//! stored next to each other and computed eight at a time (AVX-512 or AVX2
//! when the CPU has it; the same IEEE operations in the same order either
//! way, so the output is identical on every x86-64 machine).
//!
//! Cascadic multigrid: a grid with about half the points per side is relaxed
//! first (recursively, each level to the same tolerance), and the fine grid
//! starts from its interpolation; the coarsest level also settles the cloth
//! under a fading downward pull so slack hangs. Coarse grids always have an
//! odd number of points per side (see [`coarser_side`]), so a cloth of 2m
//! and one of 2m + 1 points a side settle on the same coarsest grid.
//!
//! The settling is a fixed schedule ([`SETTLE_SWEEPS`] sweeps before the
//! constraint-only ones), not a share of the sweep cap: what the cloth
//! settles to depends on the scene alone, and `max_iterations` only stops a
//! relaxation that has not converged. The schedule is long enough that
//! doubling it moves a drape by about a millimetre (BENCHMARKS.md). This is
//! not yet a static equilibrium under gravity: a coarse level that settles
//! deeper than the fine grid would hang is refined without weight.
//!
//! Free edges settle more slowly than the interior (fewer neighbours pull on
//! them): after a sweep whose largest move was near an edge, one more sweep
//! over just the points near the edges, without momentum, follows.
//!
//! Convergence: a level stops after `max_iterations` sweeps, or once no
//! constraint asks any point to move by more than `tolerance` × the smaller
//! rest spacing in a sweep. The carried momentum is not counted, so a slow
//! slide along a near-isometric bend, which changes no edge length, does not
//! keep a relaxed cloth sweeping until the cap. A level whose largest move
//! has not fallen for 500 sweeps (constraints that cannot all
//! hold, trading over-relaxed moves in a cycle) finishes without momentum
//! and with shorter steps, still judged on the whole step the constraints
//! ask. Pins never move. Output is bit-for-bit deterministic.

use std::ops::ControlFlow;

use glam::DVec3;

/// What relaxation needs to know about the fabric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxParams {
    /// Rest distance between horizontal neighbours (spacing_u × elasticity), metres.
    pub rest_u_m: f64,
    /// Rest distance between vertical neighbours (spacing_v × elasticity), metres.
    pub rest_v_m: f64,
    /// Bending resistance in [0, 1].
    pub stiffness: f64,
    /// Sweep cap per grid level, after the coarsest level's fixed settling
    /// sweeps: it stops a relaxation that has not converged and never
    /// changes one that has.
    pub max_iterations: u32,
    /// Convergence threshold, relative to the smaller rest spacing of each
    /// level: a level stops after the first sweep in which no point's
    /// constraints asked it to move further than `tolerance` × that spacing
    /// (momentum not counted). 0 never stops early; the coarsest level's
    /// settling sweeps never stop early.
    pub tolerance: f64,
}

/// Where a running relaxation is, for a progress display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxProgress {
    /// The grid level being swept (coarse levels come first).
    pub cols: usize,
    pub rows: usize,
    /// Sweeps done on this level so far.
    pub iteration: u32,
    pub max_iterations: u32,
}

/// A relaxation stopped from outside (a newer edit made it stale).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled;

/// How a relaxation ended (on the finest grid).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelaxReport {
    pub iterations: u32,
    /// Largest move the constraints asked for in the last sweep, relative to
    /// the smaller rest spacing.
    pub last_move: f64,
    /// The same in metres.
    pub last_move_m: f64,
    pub converged: bool,
}

impl RelaxReport {
    /// The outcome in a user's words, with what to do when the cap stopped it:
    /// "settled in 135 sweeps (last sweep moved points at most 0.00012 mm)".
    pub fn verdict(&self) -> String {
        let sweeps = format!("{} sweep{}", self.iterations, if self.iterations == 1 { "" } else { "s" });
        let moved = format_small_mm(self.last_move_m * 1e3);
        if self.converged {
            format!("settled in {sweeps} (last sweep moved points at most {moved})")
        } else {
            format!(
                "NOT settled: stopped by the cap of {sweeps} with points still moving {moved} a sweep; raise Iterations"
            )
        }
    }
}

/// A small length in millimetres with two significant digits ("0.0012 mm").
fn format_small_mm(mm: f64) -> String {
    if !mm.is_finite() {
        return "an unknown distance".to_string();
    }
    if mm == 0.0 {
        return "0 mm".to_string();
    }
    let digits = if mm >= 10.0 { 0 } else { (1.0 - mm.max(1e-12).log10().floor()) as usize };
    format!("{mm:.digits$} mm")
}

/// Downward pull per settling sweep, relative to the rest spacing.
const GRAVITY_BIAS: f64 = 1e-3;
/// Sweeps of the coarsest level spent settling under the fading pull: a fixed
/// part of what defines the drape, never a share of the sweep cap, so raising
/// the cap cannot change the shape a converged relaxation reaches. Measured
/// on a two-pin curtain: the lowest point moves 9 mm from 1000 to 3000
/// sweeps and 1 mm from 3000 to 8000.
const SETTLE_SWEEPS: u32 = 3000;

/// Over-relaxation of the constraints' average move.
const OVER_RELAXATION: f64 = 1.3;
/// Share of a point's previous move carried into the next sweep. Measured on
/// the four-corner benchmark: 0.95 needs about a third of the sweeps of 0.9
/// on 128² and more than ten times fewer than none; much higher oscillates.
const MOMENTUM: f64 = 0.95;

/// Sweeps without progress (the largest move not falling below
/// [`STALL_PROGRESS`] of its smallest yet, squared) after which the carried
/// momentum is dropped. Converging relaxations make progress far more often
/// (bundled scenes' shapes are unchanged), so only a cycle that momentum
/// keeps up is cut.
const STALL_SWEEPS: u32 = 500;
const STALL_PROGRESS: f64 = 0.9;
/// Share of its step a point takes once the level has stalled.
const CALM_STEP: f64 = 0.5;

/// Largest move per sweep a point may carry on as momentum, relative to the
/// rest spacing; faster points stop.
const MAX_SPEED: f64 = 0.5;

/// Shear angle a cell may take freely (woven fabric's locking angle).
pub const MAX_SHEAR_DEG: f64 = 30.0;

/// Smallest radius of curvature the fabric allows at stiffness 1, as a
/// fraction of the cloth's longer side; it scales with stiffness, and
/// stiffness 0 allows any fold.
pub const STIFF_RADIUS_FRACTION: f64 = 0.25;

/// Grids are coarsened while both sides keep at least this many points.
const MIN_COARSENED_SIDE: usize = 9;

/// Relaxes a `cols × rows` grid in place (see the module doc). `pinned[k]`
/// points never move.
///
/// Non-finite positions are left where they are (they only arise from bad
/// input, which validation rejects); a zero-length edge asks for no move
/// instead of producing a NaN.
pub fn relax(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> RelaxReport {
    relax_with(positions, cols, rows, pinned, params, &mut |_| ControlFlow::Continue(()))
        .expect("a control that never breaks never cancels")
}

/// [`relax`] that calls `control` after every sweep of every level; when it
/// breaks, relaxation stops at once and `positions` hold a partly relaxed
/// shape (pins still exactly in place). The editor uses it to show progress
/// and to drop a relaxation a newer edit has made stale.
pub fn relax_with(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<RelaxReport, Cancelled> {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    if is_coarsened(cols, rows) {
        let coarse = solve_on_coarser_grid(positions, cols, rows, pinned, params, control)?;
        let mut report = Sweeper::new(cols, rows, pinned, params).run(positions, params, Settle::No, control)?;
        // A coarse level stopped by the cap hands on a start that depends on the cap.
        report.converged &= coarse.converged;
        Ok(report)
    } else {
        Sweeper::new(cols, rows, pinned, params).run(positions, params, Settle::Yes, control)
    }
}

/// Fine-grid sweeps only, from the given positions: no coarsening and no
/// settling pull, so a nearby shape keeps its character and only its edge
/// lengths are restored. Animation uses it to re-relax an in-between blend
/// for a few sweeps. Same guarantees as [`relax`]: pins never move, output is
/// deterministic, non-finite moves are skipped.
pub fn refine(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> RelaxReport {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    Sweeper::new(cols, rows, pinned, params)
        .run(positions, params, Settle::No, &mut |_| ControlFlow::Continue(()))
        .expect("a control that never breaks never cancels")
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Settle {
    Yes,
    No,
}

fn is_coarsened(cols: usize, rows: usize) -> bool {
    cols >= MIN_COARSENED_SIDE * 2 - 1 && rows >= MIN_COARSENED_SIDE * 2 - 1
}

/// Points per side of the next coarser grid: about half, and always odd.
///
/// An odd side 2m + 1 halves exactly to m + 1 (every other point), so below
/// the first coarse grid all levels nest; and an odd side has no middle where
/// the colouring flips, so a row's points of one colour form one run instead
/// of two half-length ones. With plain halving an even side (64 → 32 → 16)
/// stopped coarsening at 16 and settled there, while an odd one (65 → 33 → 17
/// → 9) settled on 9 points a side, where the same pull hangs the cloth
/// deeper: a four-corner cloth's lowest point was 0.205 m at 63 or 64 points
/// a side and 0.089 m at 65. Now all three settle on 9 and agree within 1 cm.
fn coarser_side(side: usize) -> usize {
    side.div_ceil(2) | 1
}

/// Cascadic multigrid: relax a grid with about half the points per side first
/// (recursively, to the same tolerance), then start the fine grid from its
/// interpolation. Smooth, large-scale moves that take Gauss–Seidel thousands
/// of fine sweeps cost a few cheap coarse ones; the fine sweeps only fix local
/// detail. A coarse level that is not converged leaves more to the fine one,
/// which costs four times as much per sweep.
fn solve_on_coarser_grid(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<RelaxReport, Cancelled> {
    let (coarse_cols, coarse_rows) = (coarser_side(cols), coarser_side(rows));
    let mut coarse = Vec::with_capacity(coarse_cols * coarse_rows);
    for l in 0..coarse_rows {
        for k in 0..coarse_cols {
            coarse.push(sample_mirrored(positions, cols, rows, (k, coarse_cols), (l, coarse_rows)));
        }
    }
    let mut coarse_pinned = vec![false; coarse_cols * coarse_rows];
    for (f, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
        let (k, l) = (nearest_index(f % cols, cols, coarse_cols), nearest_index(f / cols, rows, coarse_rows));
        let c = l * coarse_cols + k;
        if !coarse_pinned[c] {
            coarse_pinned[c] = true;
            coarse[c] = positions[f];
        }
    }
    let ratio_u = (cols - 1) as f64 / (coarse_cols - 1) as f64;
    let ratio_v = (rows - 1) as f64 / (coarse_rows - 1) as f64;
    let coarse_params =
        RelaxParams { rest_u_m: params.rest_u_m * ratio_u, rest_v_m: params.rest_v_m * ratio_v, ..*params };
    let report = relax_with(&mut coarse, coarse_cols, coarse_rows, &coarse_pinned, &coarse_params, control)?;
    for j in 0..rows {
        for i in 0..cols {
            let f = j * cols + i;
            if !pinned[f] {
                let p = sample_mirrored(&coarse, coarse_cols, coarse_rows, (i, cols), (j, rows));
                if p.is_finite() {
                    positions[f] = p;
                }
            }
        }
    }
    Ok(report)
}

/// Index on a side of `to` points nearest to index `at` on a side of `from`
/// points (both sides spanning the same length); ties go away from the middle
/// so mirrored indices map to mirrored indices.
fn nearest_index(at: usize, from: usize, to: usize) -> usize {
    let near = |at: usize| (2 * at * (to - 1) + (from - 1)) / (2 * (from - 1));
    if 2 * at < from { near(at) } else { to - 1 - near(from - 1 - at) }
}

/// The grid sampled where point `k` of a `samples`-point side falls, along
/// each axis (`(k, samples)` along i, then along j), bilinearly.
///
/// Points in the far half of a side are computed from the far edge, exactly
/// as their mirror image is from the near edge, so a mirror-symmetric grid
/// gives bit-for-bit mirror-symmetric samples.
fn sample_mirrored(
    positions: &[DVec3],
    cols: usize,
    rows: usize,
    (k, samples_u): (usize, usize),
    (l, samples_v): (usize, usize),
) -> DVec3 {
    let (x, flip_i) = mirrored_coordinate(k, samples_u, cols);
    let (y, flip_j) = mirrored_coordinate(l, samples_v, rows);
    let at = |i: usize, j: usize| {
        let i = if flip_i { cols - 1 - i } else { i };
        let j = if flip_j { rows - 1 - j } else { j };
        positions[j * cols + i]
    };
    let (i0, j0) = ((x.floor() as usize).min(cols - 2), (y.floor() as usize).min(rows - 2));
    let (fx, fy) = (x - i0 as f64, y - j0 as f64);
    let top = at(i0, j0).lerp(at(i0 + 1, j0), fx);
    let bottom = at(i0, j0 + 1).lerp(at(i0 + 1, j0 + 1), fx);
    top.lerp(bottom, fy)
}

/// Fractional index on a side of `points` of sample `k` out of `samples`,
/// measured from the nearer end, and whether that is the far end.
fn mirrored_coordinate(k: usize, samples: usize, points: usize) -> (f64, bool) {
    let flip = 2 * k > samples - 1;
    let k = if flip { samples - 1 - k } else { k };
    // One rounding: exact for sample points that fall on grid points or halfway.
    ((k * (points - 1)) as f64 / (samples - 1) as f64, flip)
}

/// One distance constraint: the neighbour stays between `min2` and `max2`
/// squared distance (equal bounds make an equality).
#[derive(Clone, Copy)]
struct Bound {
    min2: f64,
    max2: f64,
}

impl Bound {
    fn new(min: f64, max: f64) -> Bound {
        Bound { min2: min * min, max2: max * max }
    }
}

/// Neighbours in mirror-image pairs, grouped as structural, shear and
/// bending; sums run over pairs first so that a mirrored neighbourhood gives
/// the mirrored sum exactly.
const NEIGHBOURS: usize = 12;

/// Points computed side by side: one AVX-512 vector, or two AVX2 ones.
const LANES: usize = 8;
type Lanes = [f64; LANES];

/// Grid steps (di, dj) of each neighbour.
const STEPS: [(isize, isize); NEIGHBOURS] =
    [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1), (-2, 0), (2, 0), (0, -2), (0, 2)];

/// One coordinate of every grid point, split by column parity: point (i, j)
/// is at `slot(i, j)` = `(i % 2)·len + j·half + i / 2`. Points of one colour
/// along a row then sit next to each other, and so do each of their
/// neighbours, so a sweep over them reads and writes whole vectors.
struct Split {
    half: usize,
    /// Length of one parity's part.
    len: usize,
    data: Vec<f64>,
}

impl Split {
    fn new(cols: usize, rows: usize) -> Split {
        let half = cols.div_ceil(2);
        // Padding so that the last chunk of a run may read a few lanes past the grid.
        let len = half * rows + LANES;
        Split { half, len, data: vec![0.0; 2 * len] }
    }

    fn slot(&self, i: usize, j: usize) -> usize {
        (i % 2) * self.len + j * self.half + i / 2
    }

    fn get(&self, i: usize, j: usize) -> f64 {
        self.data[self.slot(i, j)]
    }

    fn get_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        let at = self.slot(i, j);
        &mut self.data[at]
    }

    /// `len` consecutive same-parity points from (i, j) on.
    fn run(&self, i: usize, j: usize, len: usize) -> &[f64] {
        let at = self.slot(i, j);
        &self.data[at..at + len]
    }

    fn run_mut(&mut self, i: usize, j: usize, len: usize) -> &mut [f64] {
        let at = self.slot(i, j);
        &mut self.data[at..at + len]
    }
}

/// Up to [`LANES`] points near an edge, computed side by side, and where they
/// and their neighbours sit in a [`Split`], found once and laid out lane by
/// lane: an absent neighbour is the point itself, masked out by `present`;
/// spare lanes repeat the last point. (Gathered from per-point slots and
/// flags instead, the lanes cost a tenth of a 64² build.)
#[derive(Clone, Copy)]
struct BorderChunk {
    len: usize,
    centre: [u32; LANES],
    around: [[u32; LANES]; NEIGHBOURS],
    present: [Lanes; NEIGHBOURS],
}

impl BorderChunk {
    /// Slots of the chunk's points, in order.
    fn centres(&self) -> impl Iterator<Item = usize> + '_ {
        self.centre[..self.len].iter().map(|&at| at as usize)
    }
}

/// `len` interior free points of one colour: (i, j), (i + 2, j), …
#[derive(Clone, Copy)]
struct Run {
    i: usize,
    j: usize,
    len: usize,
}

/// A run of points near the top or bottom edge whose neighbours along the
/// row all exist: the neighbours above or below it that do not are missing
/// for every point of the run alike, so it is computed like an interior run,
/// with those neighbours read as the points themselves and masked out by
/// `present` (gathered into chunks instead, these points had cost three times
/// an interior one).
#[derive(Clone, Copy)]
struct EdgeRun {
    run: Run,
    present: [f64; NEIGHBOURS],
}

/// The free points of one grid split by colour into runs of interior points
/// (every neighbour present), runs along the top and bottom edges, and chunks
/// of the other points near an edge.
struct Sweeper {
    cols: usize,
    rows: usize,
    bounds: [Bound; NEIGHBOURS],
    bends: bool,
    position: [Split; 3],
    velocity: [Split; 3],
    runs: [Vec<Run>; 4],
    edge_runs: [Vec<EdgeRun>; 4],
    border: [Vec<BorderChunk>; 4],
    /// This colour's steps: interior runs first, then edge runs, then chunks;
    /// one vector's worth of spare room for the last run's throwaway lanes.
    steps: [Vec<f64>; 3],
}

impl Sweeper {
    fn new(cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> Sweeper {
        let min_radius = params.stiffness.clamp(0.0, 1.0)
            * STIFF_RADIUS_FRACTION
            * (params.rest_u_m * (cols - 1) as f64).max(params.rest_v_m * (rows - 1) as f64);
        let second_u = min_second_neighbour_distance(params.rest_u_m, min_radius);
        let second_v = min_second_neighbour_distance(params.rest_v_m, min_radius);
        let (u, v) = (params.rest_u_m, params.rest_v_m);
        // A cell sheared by γ has diagonals √(u² + v² ± 2uv·sin γ).
        let shear_span = 2.0 * u * v * MAX_SHEAR_DEG.to_radians().sin();
        let diag = Bound::new((u * u + v * v - shear_span).sqrt(), (u * u + v * v + shear_span).sqrt());
        let (bend_u, bend_v) = (Bound::new(second_u, f64::INFINITY), Bound::new(second_v, f64::INFINITY));
        let (along_u, along_v) = (Bound::new(u, u), Bound::new(v, v));
        let bounds = [along_u, along_u, along_v, along_v, diag, diag, diag, diag, bend_u, bend_u, bend_v, bend_v];
        let bends = second_u > 0.0 || second_v > 0.0;
        let reach = if bends { 2 } else { 1 };
        let mut runs: [Vec<Run>; 4] = Default::default();
        let mut border: [Vec<(usize, usize)>; 4] = Default::default();
        for j in 0..rows {
            let mut open: [Option<Run>; 4] = [None; 4];
            for i in 0..cols {
                if pinned[j * cols + i] {
                    continue;
                }
                let colour = i.min(cols - 1 - i) % 2 + 2 * (j.min(rows - 1 - j) % 2);
                // Rows near the top and bottom edges make runs too (edge runs, below).
                let in_row = i >= reach && i + reach < cols;
                if !in_row {
                    border[colour].push((i, j));
                    continue;
                }
                match &mut open[colour] {
                    Some(run) if run.i + 2 * run.len == i => run.len += 1,
                    slot => {
                        runs[colour].extend(slot.take());
                        *slot = Some(Run { i, j, len: 1 });
                    }
                }
            }
            for (colour, run) in open.into_iter().enumerate() {
                runs[colour].extend(run);
            }
        }
        let near_edge = |run: &Run| run.j < reach || run.j + reach >= rows;
        let edge_runs = runs.each_ref().map(|runs| {
            let edge = runs.iter().filter(|run| near_edge(run)).map(|&run| EdgeRun {
                run,
                present: STEPS.map(|(_, dj)| if run.j.wrapping_add_signed(dj) < rows { 1.0 } else { 0.0 }),
            });
            edge.collect::<Vec<_>>()
        });
        for runs in &mut runs {
            runs.retain(|run| !near_edge(run));
        }
        let most = (0..4)
            .map(|c| {
                let in_runs = runs[c].iter().chain(edge_runs[c].iter().map(|e| &e.run)).map(|r| r.len).sum::<usize>();
                in_runs + border[c].len()
            })
            .max()
            .unwrap_or(0);
        let split = || [Split::new(cols, rows), Split::new(cols, rows), Split::new(cols, rows)];
        let layout = Split { half: cols.div_ceil(2), len: cols.div_ceil(2) * rows + LANES, data: Vec::new() };
        let border = border.each_ref().map(|points| {
            let chunks = points.chunks(LANES).map(|points| {
                let mut chunk = BorderChunk {
                    len: points.len(),
                    centre: [0; LANES],
                    around: [[0; LANES]; NEIGHBOURS],
                    present: [[0.0; LANES]; NEIGHBOURS],
                };
                for lane in 0..LANES {
                    let (i, j) = points[lane.min(points.len() - 1)];
                    chunk.centre[lane] = layout.slot(i, j) as u32;
                    for (n, &(di, dj)) in STEPS.iter().enumerate() {
                        let (ni, nj) = (i.wrapping_add_signed(di), j.wrapping_add_signed(dj));
                        let inside = ni < cols && nj < rows;
                        let (qi, qj) = if inside { (ni, nj) } else { (i, j) };
                        chunk.around[n][lane] = layout.slot(qi, qj) as u32;
                        chunk.present[n][lane] = if inside { 1.0 } else { 0.0 };
                    }
                }
                chunk
            });
            chunks.collect::<Vec<_>>()
        });
        Sweeper {
            cols,
            rows,
            bounds,
            bends,
            position: split(),
            velocity: split(),
            runs,
            edge_runs,
            border,
            steps: [vec![0.0; most + LANES], vec![0.0; most + LANES], vec![0.0; most + LANES]],
        }
    }

    fn run(
        &mut self,
        positions: &mut [DVec3],
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.load(positions);
        #[cfg(target_arch = "x86_64")]
        let report = if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU supports AVX-512F, checked just above.
            unsafe { self.sweeps_avx512(params, settle, control) }
        } else if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { self.sweeps_avx2(params, settle, control) }
        } else {
            self.sweeps(params, settle, control)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let report = self.sweeps(params, settle, control);
        self.store(positions);
        report
    }

    fn load(&mut self, positions: &[DVec3]) {
        for j in 0..self.rows {
            for i in 0..self.cols {
                let p = positions[j * self.cols + i];
                for (axis, value) in self.position.iter_mut().zip([p.x, p.y, p.z]) {
                    *axis.get_mut(i, j) = value;
                }
            }
        }
    }

    fn store(&self, positions: &mut [DVec3]) {
        let [x, y, z] = &self.position;
        for j in 0..self.rows {
            for i in 0..self.cols {
                positions[j * self.cols + i] = DVec3::new(x.get(i, j), y.get(i, j), z.get(i, j));
            }
        }
    }

    /// The same sweeps with eight points per vector: about 12% faster than
    /// AVX2 on the benchmark (Xeon, 64² and 128²), bit-for-bit the same result.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn sweeps_avx512(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.sweeps(params, settle, control)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn sweeps_avx2(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.sweeps(params, settle, control)
    }

    #[inline(always)]
    fn sweeps(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        let min_rest = params.rest_u_m.min(params.rest_v_m);
        let max_speed2 = (MAX_SPEED * min_rest).powi(2);
        let mut report = RelaxReport::default();
        // Settling: the first sweeps also pull every free point down a little, fading
        // to nothing, so slack cloth hangs instead of staying where the approximation
        // left it; the remaining sweeps enforce the constraints alone.
        let settle_sweeps = if settle == Settle::Yes { SETTLE_SWEEPS } else { 0 };
        // The smallest largest-move after settling, and sweeps since it fell.
        let (mut best_move2, mut stalled) = (f64::INFINITY, 0u32);
        // After a stall: no momentum, shorter steps, for the rest of the level.
        let mut calm = false;
        for iteration in 0..settle_sweeps.saturating_add(params.max_iterations) {
            let settling = iteration < settle_sweeps;
            let gravity =
                if settling { -GRAVITY_BIAS * min_rest * (1.0 - iteration as f64 / settle_sweeps as f64) } else { 0.0 };
            if calm {
                for axis in &mut self.velocity {
                    axis.data.fill(0.0);
                }
            }
            for colour in 0..4 {
                for run in self.runs[colour].iter().chain(self.edge_runs[colour].iter().map(|e| &e.run)) {
                    coast(&mut self.position, &self.velocity, run);
                }
                for at in self.border[colour].iter().flat_map(BorderChunk::centres) {
                    for (p, v) in self.position.iter_mut().zip(&self.velocity) {
                        p.data[at] += v.data[at] * MOMENTUM;
                    }
                }
            }
            // Largest squared step of an interior point and of a point near an edge.
            let (mut max_step2, mut max_edge2) = (0.0f64, 0.0f64);
            for colour in 0..4 {
                // Every point of a colour moves from the same positions: its neighbours
                // are of other colours, or mirror images of each other.
                let mut filled = 0;
                for r in 0..self.runs[colour].len() {
                    let run = self.runs[colour][r];
                    self.run_steps(&run, &[1.0; NEIGHBOURS], gravity, filled);
                    filled += run.len;
                }
                filled = self.edge_run_steps_from(colour, gravity, filled);
                self.border_steps_from(colour, gravity, filled);
                if calm {
                    for steps in &mut self.steps {
                        steps.iter_mut().for_each(|d| *d *= CALM_STEP);
                    }
                }
                let mut done = 0;
                for run in &self.runs[colour] {
                    let step2 = apply(&mut self.position, &mut self.velocity, run, &self.steps, done, max_speed2);
                    max_step2 = max_step2.max(step2);
                    done += run.len;
                }
                for EdgeRun { run, .. } in &self.edge_runs[colour] {
                    let step2 = apply(&mut self.position, &mut self.velocity, run, &self.steps, done, max_speed2);
                    max_edge2 = max_edge2.max(step2);
                    done += run.len;
                }
                // Points near an edge one by one, straight from their slots.
                let [px, py, pz] = &mut self.position;
                let [vx, vy, vz] = &mut self.velocity;
                let [sx, sy, sz] = &self.steps;
                for (k, at) in self.border[colour].iter().flat_map(BorderChunk::centres).enumerate() {
                    let t = done + k;
                    let step2 = move_point(
                        [&mut px.data[at], &mut py.data[at], &mut pz.data[at]],
                        [&mut vx.data[at], &mut vy.data[at], &mut vz.data[at]],
                        [sx[t], sy[t], sz[t]],
                        max_speed2,
                    );
                    max_edge2 = max_edge2.max(step2);
                }
            }
            // The settling sweeps are part of what the shape is, not of the cap's budget.
            report.iterations = (iteration + 1).saturating_sub(settle_sweeps);
            // A calm step is a share of what the constraints ask; convergence is judged on the ask.
            report.last_move_m = max_step2.max(max_edge2).sqrt() / if calm { CALM_STEP } else { 1.0 };
            report.last_move = report.last_move_m / min_rest;
            let progress = RelaxProgress {
                cols: self.cols,
                rows: self.rows,
                iteration: iteration + 1,
                max_iterations: settle_sweeps.saturating_add(params.max_iterations),
            };
            if control(progress).is_break() {
                return Err(Cancelled);
            }
            if !settling && report.last_move < params.tolerance {
                report.converged = true;
                break;
            }
            if !settling {
                let moved2 = max_step2.max(max_edge2);
                if moved2 < best_move2 * STALL_PROGRESS {
                    (best_move2, stalled) = (moved2, 0);
                } else {
                    stalled += 1;
                }
                if stalled >= STALL_SWEEPS {
                    // Constraints that cannot all hold (a stiff cloth hung from one
                    // pin) trade over-relaxed moves in a cycle: settle them calmly.
                    calm = true;
                    (best_move2, stalled) = (moved2, 0);
                }
            }
            // Only with an interior to compare against: on a grid that is all edge
            // (a lone cell) the extra sweeps would just fight the momentum.
            let has_interior = self.runs.iter().any(|runs| !runs.is_empty());
            if !settling && !calm && has_interior && max_edge2 > max_step2 {
                self.edge_sweep();
            }
        }
        Ok(report)
    }

    /// One extra sweep over the points near an edge, without momentum (their
    /// velocity is left as it is). Where the largest move is at an edge, the
    /// free edge settles more slowly than the interior (fewer neighbours pull
    /// on it), and the whole grid would keep sweeping for it: on 256² the
    /// finest level ran into its 200-sweep cap without this and now converges
    /// in 86 sweeps. Its moves do not count towards convergence; the next full
    /// sweep's do. Inlined so that it is compiled for the vector unit of the
    /// sweeps that call it (not inlined it ran scalar: 5% of a 64² build).
    #[inline(always)]
    fn edge_sweep(&mut self) {
        for colour in 0..4 {
            let filled = self.edge_run_steps_from(colour, 0.0, 0);
            self.border_steps_from(colour, 0.0, filled);
            let [px, py, pz] = &mut self.position;
            let [sx, sy, sz] = &self.steps;
            let mut done = 0;
            for EdgeRun { run, .. } in &self.edge_runs[colour] {
                let (i, j, len) = (run.i, run.j, run.len);
                let (px, py, pz) = (px.run_mut(i, j, len), py.run_mut(i, j, len), pz.run_mut(i, j, len));
                for t in 0..len {
                    let k = done + t;
                    nudge([&mut px[t], &mut py[t], &mut pz[t]], [sx[k], sy[k], sz[k]]);
                }
                done += len;
            }
            for (k, at) in self.border[colour].iter().flat_map(BorderChunk::centres).enumerate() {
                let k = done + k;
                nudge([&mut px.data[at], &mut py.data[at], &mut pz.data[at]], [sx[k], sy[k], sz[k]]);
            }
        }
    }

    /// Steps of the points of one run, into `steps` from `first` on; neighbours
    /// with `present` 0 are read as the points themselves.
    #[inline(always)]
    fn run_steps(&mut self, run: &Run, present: &[f64; NEIGHBOURS], gravity: f64, first: usize) {
        if self.bends {
            run_steps::<true>(&self.position, run, present, &self.bounds, gravity, &mut self.steps, first);
        } else {
            run_steps::<false>(&self.position, run, present, &self.bounds, gravity, &mut self.steps, first);
        }
    }

    /// Steps of the edge runs of `colour`, into `steps` from `first` on; returns
    /// where they end.
    #[inline(always)]
    fn edge_run_steps_from(&mut self, colour: usize, gravity: f64, first: usize) -> usize {
        let mut filled = first;
        for e in 0..self.edge_runs[colour].len() {
            let EdgeRun { run, present } = self.edge_runs[colour][e];
            self.run_steps(&run, &present, gravity, filled);
            filled += run.len;
        }
        filled
    }

    /// Steps of the points of `colour` near an edge, into `steps` from `first` on.
    #[inline(always)]
    fn border_steps_from(&mut self, colour: usize, gravity: f64, first: usize) {
        for (c, chunk) in self.border[colour].iter().enumerate() {
            let step = self.border_steps(chunk, gravity);
            let at = first + c * LANES;
            for (steps, lanes) in self.steps.iter_mut().zip(step) {
                steps[at..at + chunk.len].copy_from_slice(&lanes[..chunk.len]);
            }
        }
    }

    /// Steps of the points of `chunk`, side by side.
    #[inline(always)]
    fn border_steps(&self, chunk: &BorderChunk, gravity: f64) -> [Lanes; 3] {
        let mut p = [[0.0; LANES]; 3];
        let mut q = [[[0.0; LANES]; 3]; NEIGHBOURS];
        for (p, axis) in p.iter_mut().zip(&self.position) {
            for (p, &at) in p.iter_mut().zip(&chunk.centre) {
                *p = axis.data[at as usize];
            }
        }
        for (q, around) in q.iter_mut().zip(&chunk.around) {
            for (q, axis) in q.iter_mut().zip(&self.position) {
                for (q, &at) in q.iter_mut().zip(around) {
                    *q = axis.data[at as usize];
                }
            }
        }
        let present = &chunk.present;
        if self.bends {
            point_steps::<true, LANES>(&p, &|n| q[n], &|n| present[n], &self.bounds, gravity)
        } else {
            point_steps::<false, LANES>(&p, &|n| q[n], &|n| present[n], &self.bounds, gravity)
        }
    }
}

/// Moves the points of `run` by their steps (`steps[axis][first..]`) and
/// keeps their velocity (this sweep's whole move: the carried momentum plus
/// the step); returns the largest squared step. A non-finite step is skipped.
///
/// A velocity above `max_speed2` (squared) is dropped: where the constraints
/// cannot all hold (pins out of the cloth's reach) they can trade moves back
/// and forth, and momentum would build that up without bound.
#[inline(always)]
fn apply(
    position: &mut [Split; 3],
    velocity: &mut [Split; 3],
    run: &Run,
    steps: &[Vec<f64>; 3],
    first: usize,
    max_speed2: f64,
) -> f64 {
    let len = run.len;
    // Whole vectors, the last one partly past the run: its spare lanes are
    // computed and then written back as they were (the slots exist: every run
    // reads a vector's worth past its end). A scalar tail had been three in
    // eight points of a 64² sweep.
    let padded = len.next_multiple_of(LANES);
    let [sx, sy, sz] = steps;
    let (sx, sy, sz) = (&sx[first..first + padded], &sy[first..first + padded], &sz[first..first + padded]);
    let [px, py, pz] = position;
    let [vx, vy, vz] = velocity;
    let (i, j) = (run.i, run.j);
    let (px, py, pz) = (px.run_mut(i, j, padded), py.run_mut(i, j, padded), pz.run_mut(i, j, padded));
    let (vx, vy, vz) = (vx.run_mut(i, j, padded), vy.run_mut(i, j, padded), vz.run_mut(i, j, padded));
    // A running maximum per lane, so that the loop vectorises; the steps are
    // finite and non-negative, so the maximum does not depend on the order.
    let mut lane_max = [0.0f64; LANES];
    let mut t = 0;
    while t < len {
        let live = len - t;
        // Copied in and out as whole vectors: through per-lane references the
        // loop stayed scalar (perf: a quarter of a sweep at 64²).
        let load = |s: &[f64]| -> Lanes { *<&Lanes>::try_from(&s[t..t + LANES]).expect("whole lanes") };
        let (old_p, old_v) = ([load(px), load(py), load(pz)], [load(vx), load(vy), load(vz)]);
        let (mut p, mut v) = (old_p, old_v);
        let d = [load(sx), load(sy), load(sz)];
        for lane in 0..LANES {
            let [p0, p1, p2] = &mut p;
            let [v0, v1, v2] = &mut v;
            let step2 = move_point(
                [&mut p0[lane], &mut p1[lane], &mut p2[lane]],
                [&mut v0[lane], &mut v1[lane], &mut v2[lane]],
                [d[0][lane], d[1][lane], d[2][lane]],
                max_speed2,
            );
            let counts = lane < live && step2 > lane_max[lane];
            lane_max[lane] = if counts { step2 } else { lane_max[lane] };
        }
        for axis in 0..3 {
            for lane in 0..LANES {
                p[axis][lane] = if lane < live { p[axis][lane] } else { old_p[axis][lane] };
                v[axis][lane] = if lane < live { v[axis][lane] } else { old_v[axis][lane] };
            }
        }
        for (out, lanes) in [&mut *px, &mut *py, &mut *pz].into_iter().zip(p) {
            out[t..t + LANES].copy_from_slice(&lanes);
        }
        for (out, lanes) in [&mut *vx, &mut *vy, &mut *vz].into_iter().zip(v) {
            out[t..t + LANES].copy_from_slice(&lanes);
        }
        t += LANES;
    }
    lane_max.into_iter().fold(0.0, f64::max)
}

/// Moves a point by `step` without touching its velocity (the edge sweep);
/// a non-finite step is skipped.
#[inline(always)]
fn nudge(p: [&mut f64; 3], step: [f64; 3]) {
    if step.iter().all(|d| d.is_finite()) {
        for (p, d) in p.into_iter().zip(step) {
            *p += d;
        }
    }
}

/// [`apply`] for one point; returns its squared step (0 if not finite).
#[inline(always)]
fn move_point(p: [&mut f64; 3], v: [&mut f64; 3], step: [f64; 3], max_speed2: f64) -> f64 {
    let finite = step[0].is_finite() && step[1].is_finite() && step[2].is_finite();
    let [dx, dy, dz] = if finite { step } else { [0.0; 3] };
    let [px, py, pz] = p;
    *px += dx;
    *py += dy;
    *pz += dz;
    let [vx, vy, vz] = v;
    let w = (*vx * MOMENTUM + dx, *vy * MOMENTUM + dy, *vz * MOMENTUM + dz);
    let keep = w.0 * w.0 + w.1 * w.1 + w.2 * w.2 <= max_speed2;
    (*vx, *vy, *vz) = if keep { w } else { (0.0, 0.0, 0.0) };
    dx * dx + dy * dy + dz * dz
}

/// Carries the points of `run` on by their momentum before a sweep.
#[inline(always)]
fn coast(position: &mut [Split; 3], velocity: &[Split; 3], run: &Run) {
    for axis in 0..3 {
        let p = position[axis].run_mut(run.i, run.j, run.len);
        let v = velocity[axis].run(run.i, run.j, run.len);
        for t in 0..run.len {
            p[t] += v[t] * MOMENTUM;
        }
    }
}

/// Steps of the points of one run, into `steps` from `first` on: one flat
/// loop over contiguous slices, so that it vectorises across points.
/// Neighbours with `present` 0 are read as the points themselves.
#[inline(always)]
fn run_steps<const BENDS: bool>(
    position: &[Split; 3],
    run: &Run,
    present: &[f64; NEIGHBOURS],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
    steps: &mut [Vec<f64>; 3],
    first: usize,
) {
    // Whole chunks of lanes: spare lanes past the run compute throwaway steps.
    let padded = run.len.next_multiple_of(LANES);
    // Without bending the second neighbours are never read (they may lie past the edge).
    let mut at = [0; NEIGHBOURS];
    for (n, at) in at.iter_mut().enumerate() {
        let (di, dj) = if (n < 8 || BENDS) && present[n] != 0.0 { STEPS[n] } else { (0, 0) };
        *at = position[0].slot(run.i.wrapping_add_signed(di), run.j.wrapping_add_signed(dj));
    }
    // Plain loops rather than `array::map`, whose closures were not inlined:
    // setting up the slices cost 5% of a sweep.
    let centre_at = position[0].slot(run.i, run.j);
    let mut centre: [&[f64]; 3] = [&[]; 3];
    let mut around: [[&[f64]; NEIGHBOURS]; 3] = [[&[]; NEIGHBOURS]; 3];
    for axis in 0..3 {
        let data = &position[axis].data;
        centre[axis] = &data[centre_at..centre_at + padded];
        for n in 0..NEIGHBOURS {
            around[axis][n] = &data[at[n]..at[n] + padded];
        }
    }
    let [sx, sy, sz] = steps;
    let out = first..first + padded;
    let out = [&mut sx[out.clone()], &mut sy[out.clone()], &mut sz[out]];
    run_kernel::<BENDS>(centre, &around, present, bounds, gravity, out);
}

/// The loop of [`run_steps`], [`LANES`] points at a time; the outputs are
/// separate `&mut` slices so the compiler knows they alias no input.
#[inline(always)]
fn run_kernel<const BENDS: bool>(
    centre: [&[f64]; 3],
    around: &[[&[f64]; NEIGHBOURS]; 3],
    present: &[f64; NEIGHBOURS],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
    [sx, sy, sz]: [&mut [f64]; 3],
) {
    let mut t = 0;
    while t + LANES <= centre[0].len() {
        let load = |s: &[f64]| -> Lanes { *<&Lanes>::try_from(&s[t..t + LANES]).expect("whole lanes") };
        let q = |n: usize| [load(around[0][n]), load(around[1][n]), load(around[2][n])];
        let p = [load(centre[0]), load(centre[1]), load(centre[2])];
        let step = point_steps::<BENDS, LANES>(&p, &q, &|n| [present[n]; LANES], bounds, gravity);
        sx[t..t + LANES].copy_from_slice(&step[0]);
        sy[t..t + LANES].copy_from_slice(&step[1]);
        sz[t..t + LANES].copy_from_slice(&step[2]);
        t += LANES;
    }
}

/// The move of one point: the average of what its violated constraints ask,
/// over-relaxed, plus the settling pull. `present[n]` is 0 for a neighbour
/// outside the grid (then `q[n]` is the point itself).
///
/// For an edge d of squared length l² outside its bounds, with r² the nearer
/// bound, a constraint asks for d·(l² − r²)/(l² + r²): the exact d·(l − r)/l
/// to first order near rest, within 21% of it for any stretch, bounded by the
/// edge itself, and without a square root. Branch-free, so that runs of
/// points vectorise and unpredictable long-or-short edges cost nothing.
#[inline(always)]
fn point_steps<const BENDS: bool, const L: usize>(
    p: &[[f64; L]; 3],
    q: &impl Fn(usize) -> [[f64; L]; 3],
    present: &impl Fn(usize) -> [f64; L],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
) -> [[f64; L]; 3] {
    // Mirror-image neighbours are summed in pairs first, so that a mirrored
    // neighbourhood gives the mirrored sum exactly.
    let mut total = add(four(p, q, present, bounds, 0), four(p, q, present, bounds, 4));
    if BENDS {
        total = add(total, four(p, q, present, bounds, 8));
    }
    let mut step = [[0.0; L]; 3];
    for lane in 0..L {
        let count = total[3][lane];
        let scale = if count > 0.0 { OVER_RELAXATION / count } else { 0.0 };
        for axis in 0..3 {
            step[axis][lane] = total[axis][lane] * scale;
        }
        step[1][lane] += gravity;
    }
    step
}

/// Pull along x, y, z and the number of violated constraints, per lane.
type Pull<const L: usize> = [[f64; L]; 4];

/// Neighbours `o..o + 4` (two mirror-image pairs), each pair summed first.
#[inline(always)]
fn four<const L: usize>(
    p: &[[f64; L]; 3],
    q: &impl Fn(usize) -> [[f64; L]; 3],
    present: &impl Fn(usize) -> [f64; L],
    bounds: &[Bound; NEIGHBOURS],
    o: usize,
) -> Pull<L> {
    let (a, b) =
        (constraint(p, &q(o), &present(o), &bounds[o]), constraint(p, &q(o + 1), &present(o + 1), &bounds[o + 1]));
    let (c, d) = (
        constraint(p, &q(o + 2), &present(o + 2), &bounds[o + 2]),
        constraint(p, &q(o + 3), &present(o + 3), &bounds[o + 3]),
    );
    add(add(a, b), add(c, d))
}

#[inline(always)]
fn add<const L: usize>(a: Pull<L>, b: Pull<L>) -> Pull<L> {
    let mut out = a;
    for c in 0..4 {
        for lane in 0..L {
            out[c][lane] += b[c][lane];
        }
    }
    out
}

/// One constraint on `L` points side by side.
///
/// The division is skipped when the constraint holds on every lane (then f is
/// exactly 0 anyway): shear and bending bounds are mostly slack, and the
/// division is the costliest operation of a sweep.
#[inline(always)]
fn constraint<const L: usize>(p: &[[f64; L]; 3], q: &[[f64; L]; 3], present: &[f64; L], b: &Bound) -> Pull<L> {
    let mut d = [[0.0; L]; 3];
    let (mut l2, mut r2) = ([0.0; L], [0.0; L]);
    let mut holds = true;
    for lane in 0..L {
        for axis in 0..3 {
            d[axis][lane] = q[axis][lane] - p[axis][lane];
        }
        let [dx, dy, dz] = [d[0][lane], d[1][lane], d[2][lane]];
        l2[lane] = dx * dx + dy * dy + dz * dz;
        let r = if l2[lane] < b.min2 { b.min2 } else { l2[lane] };
        r2[lane] = if r > b.max2 { b.max2 } else { r };
        holds &= l2[lane] == r2[lane];
    }
    let mut f = [0.0; L];
    if !holds {
        for lane in 0..L {
            // MIN_POSITIVE only matters for l = r = 0 (0, not NaN).
            f[lane] = (l2[lane] - r2[lane]) / (l2[lane] + r2[lane] + f64::MIN_POSITIVE);
        }
    }
    let mut out = [[0.0; L]; 4];
    for lane in 0..L {
        for axis in 0..3 {
            out[axis][lane] = d[axis][lane] * f[lane];
        }
        out[3][lane] = if l2[lane] == r2[lane] { 0.0 } else { present[lane] };
    }
    out
}

/// Distance between second neighbours (spacing `rest` apart along a line) when
/// the line bends on a circle of radius `radius`: 2·rest·√(1 − (rest/2r)²);
/// 0 when the radius allows any fold.
fn min_second_neighbour_distance(rest: f64, radius: f64) -> f64 {
    let half_ratio = rest / (2.0 * radius);
    if !(half_ratio < 1.0) {
        return 0.0;
    }
    2.0 * rest * (1.0 - half_ratio * half_ratio).sqrt()
}

/// Mean of |length − rest| / rest over structural edges (rows and columns).
pub fn mean_structural_error(positions: &[DVec3], cols: usize, rows: usize, rest_u_m: f64, rest_v_m: f64) -> f64 {
    let mut total = 0.0;
    let mut count = 0usize;
    for j in 0..rows {
        for i in 0..cols {
            let k = j * cols + i;
            if i + 1 < cols {
                total += (positions[k].distance(positions[k + 1]) - rest_u_m).abs() / rest_u_m;
                count += 1;
            }
            if j + 1 < rows {
                total += (positions[k].distance(positions[k + cols]) - rest_v_m).abs() / rest_v_m;
                count += 1;
            }
        }
    }
    total / count.max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wavy sheet, pinned at two corners and one inner point, with bending on.
    fn wavy_sheet(cols: usize, rows: usize) -> (Vec<DVec3>, Vec<bool>, RelaxParams) {
        let positions = (0..rows)
            .flat_map(|j| {
                (0..cols).map(move |i| {
                    let (u, v) = (i as f64 * 0.1, j as f64 * 0.1);
                    DVec3::new(u * 0.9, 2.0 - v + 0.05 * (3.0 * u).sin(), 0.04 * (5.0 * v).cos() * u)
                })
            })
            .collect();
        let mut pinned = vec![false; cols * rows];
        pinned[0] = true;
        pinned[cols - 1] = true;
        pinned[(rows / 2) * cols + cols / 3] = true;
        let params = RelaxParams { rest_u_m: 0.1, rest_v_m: 0.1, stiffness: 0.6, max_iterations: 40, tolerance: 0.0 };
        (positions, pinned, params)
    }

    #[test]
    fn the_verdict_says_whether_it_settled_and_by_how_much() {
        let settled = RelaxReport { iterations: 135, last_move: 1e-6, last_move_m: 1.2e-7, converged: true };
        assert_eq!(settled.verdict(), "settled in 135 sweeps (last sweep moved points at most 0.00012 mm)");
        let capped = RelaxReport { iterations: 1, last_move: 0.1, last_move_m: 3.71e-5, converged: false };
        assert_eq!(
            capped.verdict(),
            "NOT settled: stopped by the cap of 1 sweep with points still moving 0.037 mm a sweep; raise Iterations"
        );
        assert_eq!(format_small_mm(f64::NAN), "an unknown distance");
        assert_eq!(format_small_mm(25.4), "25 mm");
        assert_eq!(format_small_mm(0.0), "0 mm");
    }

    #[test]
    fn progress_comes_coarse_level_first_and_does_not_change_the_result() {
        let (start, pinned, params) = wavy_sheet(33, 21);
        let mut plain = start.clone();
        let plain_report = relax(&mut plain, 33, 21, &pinned, &params);
        let mut watched = start.clone();
        let mut levels = Vec::new();
        let report = relax_with(&mut watched, 33, 21, &pinned, &params, &mut |p| {
            assert!(p.iteration >= 1 && p.iteration <= p.max_iterations);
            if levels.last() != Some(&(p.cols, p.rows)) {
                levels.push((p.cols, p.rows));
            }
            ControlFlow::Continue(())
        });
        assert_eq!(report, Ok(plain_report));
        assert_eq!(watched, plain);
        assert_eq!(levels, [(17, 11), (33, 21)]);
    }

    #[test]
    fn a_cancelled_relaxation_stops_at_once_and_keeps_the_pins() {
        let (start, pinned, params) = wavy_sheet(33, 21);
        let mut positions = start.clone();
        let mut sweeps = 0;
        let result = relax_with(&mut positions, 33, 21, &pinned, &params, &mut |_| {
            sweeps += 1;
            if sweeps == 3 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        });
        assert_eq!(result, Err(Cancelled));
        assert_eq!(sweeps, 3, "no sweep after the break");
        for (k, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
            assert_eq!(positions[k], start[k]);
        }
        assert!(positions.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn vectorised_and_portable_sweeps_agree_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        for (cols, rows) in [(23, 14), (16, 9), (5, 5)] {
            let (start, pinned, params) = wavy_sheet(cols, rows);
            let mut go_on = |_| ControlFlow::Continue(());
            let mut portable = start.clone();
            let mut sweeper = Sweeper::new(cols, rows, &pinned, &params);
            sweeper.load(&portable);
            let a = sweeper.sweeps(&params, Settle::Yes, &mut go_on);
            sweeper.store(&mut portable);
            assert_ne!(portable, start, "the sweeps moved something");
            let features = [
                ("avx2", std::arch::is_x86_feature_detected!("avx2")),
                ("avx512f", std::arch::is_x86_feature_detected!("avx512f")),
            ];
            for (feature, _) in features.into_iter().filter(|(_, has)| *has) {
                let avx512 = feature == "avx512f";
                let mut vectorised = start.clone();
                let mut sweeper = Sweeper::new(cols, rows, &pinned, &params);
                sweeper.load(&vectorised);
                // SAFETY: the CPU supports the feature, checked above.
                let b = unsafe {
                    if avx512 {
                        sweeper.sweeps_avx512(&params, Settle::Yes, &mut go_on)
                    } else {
                        sweeper.sweeps_avx2(&params, Settle::Yes, &mut go_on)
                    }
                };
                sweeper.store(&mut vectorised);
                assert_eq!(a, b, "{feature}");
                assert_eq!(portable, vectorised, "{feature}, {cols} × {rows}");
            }
        }
    }

    #[test]
    fn stretched_and_squeezed_edges_pull_back_towards_rest() {
        // Three points in a row, the outer two pinned: the middle one is moved
        // towards the rest distance of whichever neighbour is off.
        let params =
            RelaxParams { rest_u_m: 1.0, rest_v_m: 1.0, stiffness: 0.0, max_iterations: 2000, tolerance: 1e-7 };
        let mut positions = vec![DVec3::ZERO, DVec3::new(0.3, 0.0, 0.0), DVec3::new(2.0, 0.0, 0.0)];
        let report = refine(&mut positions, 3, 1, &[true, false, true], &params);
        assert!(report.converged, "{report:?}");
        assert!((positions[1].x - 1.0).abs() < 1e-5, "{}", positions[1]);
        assert_eq!((positions[0], positions[2]), (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0)));
    }

    #[test]
    fn shear_is_free_up_to_the_limit_and_resisted_beyond() {
        // One cell pinned along its bottom edge: the top edge may lean either
        // way, and the cell keeps any shear up to the limit. (Beyond it, the
        // diagonals and edges of a lone cell settle on a compromise near the limit.)
        let params =
            RelaxParams { rest_u_m: 1.0, rest_v_m: 1.0, stiffness: 0.0, max_iterations: 2000, tolerance: 1e-9 };
        let pinned = [true, true, false, false];
        let sheared = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            vec![DVec3::ZERO, DVec3::X, DVec3::new(s, c, 0.0), DVec3::new(1.0 + s, c, 0.0)]
        };
        let shear_deg = |cell: &[DVec3]| (cell[2].x - cell[0].x).atan2(cell[2].y - cell[0].y).to_degrees();
        let mut free = sheared(20.0);
        refine(&mut free, 2, 2, &pinned, &params);
        assert!(free.iter().zip(sheared(20.0)).all(|(a, b)| a.distance(b) < 1e-9), "20° is within the limit: {free:?}");
        let mut locked = sheared(40.0);
        refine(&mut locked, 2, 2, &pinned, &params);
        let shear = shear_deg(&locked);
        assert!(shear < 36.0 && shear > MAX_SHEAR_DEG - 5.0, "40° is pulled back towards the limit: {shear}°");
    }
}
