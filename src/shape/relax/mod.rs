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
//! average of what its violated constraints ask (a bending bound counting
//! half, so where pins bend stiff cloth more than it allows the lengths win
//! and the sweeps settle), over-relaxed, plus momentum:
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
//! A cloth with fewer than [`SOLVER_MIN_SIDE`] points along its longer side
//! is relaxed with its cells split ([`relax_resolved`]) and read back at its
//! own points: the grid is detail, not shape.
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
//! With a thickness ([`RelaxParams::thickness_m`]), every sweep is followed
//! by the self-contact check (`self_contact`): parts of the cloth that are
//! not grid neighbours are kept apart, and no sweep carries one through
//! another. A key is relaxed with it only where its drape without it passes
//! through itself (`RestShape::build_among`).
//!
//! Convergence: a level stops after `max_iterations` sweeps, or once no
//! constraint asks any point to move by more than `tolerance` × the smaller
//! rest spacing in a sweep. The carried momentum is not counted, so a slow
//! slide along a near-isometric bend, which changes no edge length, does not
//! keep a relaxed cloth sweeping until the cap. Pins never move. Output is
//! bit-for-bit deterministic.

use std::ops::ControlFlow;

use glam::DVec3;

use super::through::Through;

mod drape;
mod kernel;
mod layout;
mod self_contact;
mod sweeper;

pub use drape::{DrapeReport, drape_among};
use sweeper::Sweeper;

/// What relaxation needs to know about the fabric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxParams {
    /// Rest distance between horizontal neighbours (spacing_u × elasticity), metres.
    pub rest_u_m: f64,
    /// Rest distance between vertical neighbours (spacing_v × elasticity), metres.
    pub rest_v_m: f64,
    /// Bending resistance in [0, 1].
    pub stiffness: f64,
    /// How far apart parts of the cloth that are not grid neighbours stay
    /// (metres; at most a quarter of the rest spacing on each grid level),
    /// so no sweep carries one through another; 0 lets the cloth pass
    /// through itself (see `self_contact`).
    pub thickness_m: f64,
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
    /// Largest move the last sweep or step made or asked for, metres (0
    /// before the first).
    pub last_move_m: f64,
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
    /// A coarser grid level stopped at the cap, so the finest one started
    /// from a shape the cap chose (the relaxation then has not converged,
    /// whatever the finest level did).
    pub coarse_capped: bool,
    /// A cloth without pins fell past every collider: nothing holds it up.
    pub fell_off: bool,
    /// The fabric has a bending limit (stiffness above 0): when it did not
    /// settle, lowering Stiffness may help where more sweeps do not.
    pub stiff: bool,
    /// Where the shape passes through a collider: such a shape is never
    /// settled, however still it lies.
    pub through: Option<Through>,
}

impl RelaxReport {
    /// A one-line verdict for a narrow panel ("Settled: last sweep moved
    /// 0.00032 mm"); [`RelaxReport::verdict`] says it in full.
    pub fn summary(&self) -> String {
        if self.through.is_some() {
            "NOT settled: passes through a collider".to_owned()
        } else if self.converged {
            format!("Settled: last sweep moved {}", format_small_mm(self.last_move_m * 1e3))
        } else if self.fell_off {
            "NOT settled: fell past every collider".to_owned()
        } else if self.stiff {
            "NOT settled: lower Stiffness or raise Iterations".to_owned()
        } else {
            "NOT settled: raise Iterations".to_owned()
        }
    }

    /// The outcome in a user's words, with what to do when the cap stopped it:
    /// "settled in 135 sweeps (last sweep moved points at most 0.00012 mm)".
    pub fn verdict(&self) -> String {
        let sweeps = format!("{} sweep{}", self.iterations, if self.iterations == 1 { "" } else { "s" });
        let moved = format_small_mm(self.last_move_m * 1e3);
        // Measured on random layouts (BENCHMARKS.md): every one settled at Stiffness
        // 0, and all that 40 000 sweeps left moving were stiff.
        let advice = if self.stiff {
            "lower Stiffness, or raise Iterations (where the pins bend stiff cloth more than it allows, it can keep \
             moving however many sweeps it gets)"
        } else {
            "raise Iterations"
        };
        if let Some(through) = self.through {
            let (i, j) = through.deepest_at;
            format!(
                "NOT settled: passes through a collider at {} place{} on the cloth, deepest {} inside it near grid \
                 point ({i}, {j}); move the pins or the collider apart, or lower Elasticity so the cloth hangs clear",
                through.places,
                if through.places == 1 { "" } else { "s" },
                format_small_mm(through.deepest_m * 1e3)
            )
        } else if self.converged {
            format!("settled in {sweeps} (last sweep moved points at most {moved})")
        } else if self.fell_off {
            format!(
                "NOT settled: with no pins the cloth fell past every collider in {sweeps}; move its placement over a \
                 collider, or add a pin"
            )
        } else if self.coarse_capped {
            format!(
                "NOT settled: a coarser level of the grid stopped at the sweep cap, so the shape depends on the cap \
                 (the finest level then ran {sweeps}, its last moving points at most {moved}); {advice}"
            )
        } else {
            format!("NOT settled: stopped by the cap of {sweeps} with points still moving {moved} a sweep; {advice}")
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

/// Largest move per sweep a point may carry on as momentum, relative to the
/// rest spacing; faster points stop.
const MAX_SPEED: f64 = 0.5;

/// Shear angle a cell may take freely (woven fabric's locking angle).
pub const MAX_SHEAR_DEG: f64 = 30.0;

/// Smallest radius of curvature the fabric allows at stiffness 1, as a
/// fraction of the cloth's longer side; it scales with stiffness, and
/// stiffness 0 allows any fold.
pub const STIFF_RADIUS_FRACTION: f64 = 0.25;

/// The fabric's distance limits on a `cols × rows` grid: how far a cell's
/// diagonals may shorten and lengthen as it shears freely, and how close
/// second neighbours along a row or column may come (the bending limit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FabricLimits {
    pub diagonal_min_m: f64,
    pub diagonal_max_m: f64,
    pub second_u_min_m: f64,
    pub second_v_min_m: f64,
}

impl FabricLimits {
    pub fn new(cols: usize, rows: usize, params: &RelaxParams) -> FabricLimits {
        let (u, v) = (params.rest_u_m, params.rest_v_m);
        let min_radius = params.stiffness.clamp(0.0, 1.0)
            * STIFF_RADIUS_FRACTION
            * (u * cols.saturating_sub(1) as f64).max(v * rows.saturating_sub(1) as f64);
        // A cell sheared by γ has diagonals √(u² + v² ± 2uv·sin γ).
        let shear_span = 2.0 * u * v * MAX_SHEAR_DEG.to_radians().sin();
        FabricLimits {
            diagonal_min_m: (u * u + v * v - shear_span).sqrt(),
            diagonal_max_m: (u * u + v * v + shear_span).sqrt(),
            second_u_min_m: sweeper::min_second_neighbour_distance(u, min_radius),
            second_v_min_m: sweeper::min_second_neighbour_distance(v, min_radius),
        }
    }
}

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
    let report = if is_coarsened(cols, rows) {
        let coarse = solve_on_coarser_grid(positions, cols, rows, pinned, params, control)?;
        let mut report = Sweeper::new(cols, rows, pinned, params).run(positions, params, Settle::No, control)?;
        // A coarse level stopped by the cap hands on a start that depends on the cap.
        report.coarse_capped = !coarse.converged;
        report.converged &= coarse.converged;
        report
    } else {
        Sweeper::new(cols, rows, pinned, params).run(positions, params, Settle::Yes, control)?
    };
    Ok(RelaxReport { stiff: params.stiffness > 0.0, ..report })
}

/// Fine-grid sweeps only, from the given positions: no coarsening and no
/// settling pull, so a nearby shape keeps its character and only its edge
/// lengths are restored. Animation uses it to re-relax an in-between blend
/// for a few sweeps. Same guarantees as [`relax`]: pins never move, output is
/// deterministic, non-finite moves are skipped.
pub fn refine(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> RelaxReport {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    let report = Sweeper::new(cols, rows, pinned, params)
        .run(positions, params, Settle::No, &mut |_| ControlFlow::Continue(()))
        .expect("a control that never breaks never cancels");
    RelaxReport { stiff: params.stiffness > 0.0, ..report }
}

/// Fewest points the solver's grid has along the cloth's longer side: cells
/// at most 1/32 of it. Stiffness sets the smallest bend as a share of that
/// side ([`STIFF_RADIUS_FRACTION`]), so this resolves the same bends on every
/// cloth; a coarser grid is drawn from it (see [`relax_resolved`]).
pub const SOLVER_MIN_SIDE: usize = 33;

/// Points per side of the grid the solver relaxes a `cols × rows` cloth on:
/// the cloth's own grid, or one with every cell split into 2ᵏ × 2ᵏ (the
/// smallest k giving [`SOLVER_MIN_SIDE`] points along the longer side), so
/// every point of the cloth's grid is one of the solver's.
pub fn solver_grid(cols: usize, rows: usize) -> (usize, usize) {
    if cols < 2 || rows < 2 {
        return (cols, rows);
    }
    let (mut c, mut r) = (cols, rows);
    while c.max(r) < SOLVER_MIN_SIDE {
        (c, r) = (2 * c - 1, 2 * r - 1);
    }
    (c, r)
}

/// [`relax_with`] on the [`solver_grid`]: a cloth with fewer points along its
/// longer side than [`SOLVER_MIN_SIDE`] is relaxed on a grid with its cells
/// split, started from its own grid interpolated, pinned at the same
/// material points, and drawn back at its own points. So a coarse grid is the
/// same cloth with less detail, not a different drape: the 2 m tent at 17²
/// relaxed on its own cells ends 28 mm from 129², too coarse for the bend
/// beside a corner pin (BENCHMARKS.md). Its edges are then chords of the
/// finer cloth's, shorter where it folds. The report is the solver grid's.
pub fn relax_resolved(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<RelaxReport, Cancelled> {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    let (fine_cols, fine_rows) = solver_grid(cols, rows);
    if (fine_cols, fine_rows) == (cols, rows) {
        return relax_with(positions, cols, rows, pinned, params, control);
    }
    let split = (fine_cols - 1) / (cols - 1);
    // The solver point at the cloth's point `f`.
    let shared = |f: usize| (f / cols) * split * fine_cols + (f % cols) * split;
    let mut fine = resample(positions, (cols, rows), (fine_cols, fine_rows));
    let mut fine_pinned = vec![false; fine_cols * fine_rows];
    for (f, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
        fine[shared(f)] = positions[f];
        fine_pinned[shared(f)] = true;
    }
    let split_f = split as f64;
    let fine_params =
        RelaxParams { rest_u_m: params.rest_u_m / split_f, rest_v_m: params.rest_v_m / split_f, ..*params };
    let report = relax_with(&mut fine, fine_cols, fine_rows, &fine_pinned, &fine_params, control)?;
    for (f, p) in positions.iter_mut().enumerate() {
        if !pinned[f] {
            *p = fine[shared(f)];
        }
    }
    Ok(report)
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
/// of two half-length ones. Plain halving would stop an even side
/// (64 → 32 → 16) at 16 and settle it there, while an odd one (65 → 33 → 17
/// → 9) settles on 9 points a side, where the same pull hangs the cloth
/// deeper: a four-corner cloth's lowest point would be 0.205 m at 63 or 64
/// points a side and 0.089 m at 65. With odd sides all three settle on 9
/// and agree within 1 cm.
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
    let mut coarse = resample(positions, (cols, rows), (coarse_cols, coarse_rows));
    let coarse_pinned =
        pin_coarse_points(positions, (cols, rows), pinned, params, &mut coarse, (coarse_cols, coarse_rows));
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

/// Pins each coarse point that a fine pin maps to (its nearest coarse point)
/// where the nearest such pin in material distance is, and returns which
/// coarse points are pinned.
///
/// Several fine pins can map to one coarse point (a pin lattice denser than
/// the coarse grid). Choosing the nearest keeps a mirror-symmetric layout
/// symmetric, where taking the first in index order would take the left-hand
/// pin on one side and the right-hand one on the other (on a 15 × 15 pin
/// lattice on 65² that makes the drape 78 mm asymmetric instead of 28 mm,
/// the 28 mm from slack between the pins buckling up or down). Pins tied
/// for nearest leave the coarse point where the fine grid has it, which is
/// just as symmetric.
fn pin_coarse_points(
    positions: &[DVec3],
    (cols, rows): (usize, usize),
    pinned: &[bool],
    params: &RelaxParams,
    coarse: &mut [DVec3],
    (coarse_cols, coarse_rows): (usize, usize),
) -> Vec<bool> {
    // Offsets in whole units of rest / (coarse side − 1): mirror-image pins are
    // at exactly the same distance.
    let unit_u = params.rest_u_m / (coarse_cols - 1) as f64;
    let unit_v = params.rest_v_m / (coarse_rows - 1) as f64;
    let offset = |at: usize, from: usize, to: usize, near: usize| (at * (to - 1)).abs_diff(near * (from - 1)) as f64;
    // Per coarse point: (squared distance, fine pin, tied with another).
    let mut nearest: Vec<Option<(f64, usize, bool)>> = vec![None; coarse_cols * coarse_rows];
    for (f, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
        let (i, j) = (f % cols, f / cols);
        let (k, l) = (nearest_index(i, cols, coarse_cols), nearest_index(j, rows, coarse_rows));
        let du = offset(i, cols, coarse_cols, k) * unit_u;
        let dv = offset(j, rows, coarse_rows, l) * unit_v;
        let distance2 = du * du + dv * dv;
        let slot = &mut nearest[l * coarse_cols + k];
        *slot = match *slot {
            None => Some((distance2, f, false)),
            Some((best, _, _)) if distance2 < best => Some((distance2, f, false)),
            Some((best, first, _)) if distance2 == best => Some((best, first, true)),
            kept => kept,
        };
    }
    let mut coarse_pinned = vec![false; coarse_cols * coarse_rows];
    for (c, near) in nearest.into_iter().enumerate() {
        let Some((_, f, tied)) = near else { continue };
        coarse_pinned[c] = true;
        if !tied {
            coarse[c] = positions[f];
        }
    }
    coarse_pinned
}

/// Index on a side of `to` points nearest to index `at` on a side of `from`
/// points (both sides spanning the same length); ties go towards the middle
/// so mirrored indices map to mirrored indices.
fn nearest_index(at: usize, from: usize, to: usize) -> usize {
    let near = |at: usize| (2 * at * (to - 1) + (from - 1)) / (2 * (from - 1));
    if 2 * at < from { near(at) } else { to - 1 - near(from - 1 - at) }
}

/// A `cols × rows` grid sampled bilinearly on a `to_cols × to_rows` grid
/// spanning the same cloth ([`sample_mirrored`] at each of its points).
fn resample(positions: &[DVec3], (cols, rows): (usize, usize), (to_cols, to_rows): (usize, usize)) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(to_cols * to_rows);
    for l in 0..to_rows {
        for k in 0..to_cols {
            out.push(sample_mirrored(positions, cols, rows, (k, to_cols), (l, to_rows)));
        }
    }
    out
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
        let params = RelaxParams {
            rest_u_m: 0.1,
            rest_v_m: 0.1,
            stiffness: 0.6,
            thickness_m: 0.0,
            max_iterations: 40,
            tolerance: 0.0,
        };
        (positions, pinned, params)
    }

    #[test]
    fn the_verdict_says_whether_it_settled_and_by_how_much() {
        let settled = RelaxReport {
            iterations: 135,
            last_move: 1e-6,
            last_move_m: 1.2e-7,
            converged: true,
            coarse_capped: false,
            fell_off: false,
            stiff: true,
            through: None,
        };
        assert_eq!(settled.verdict(), "settled in 135 sweeps (last sweep moved points at most 0.00012 mm)");
        let capped =
            RelaxReport { iterations: 1, last_move: 0.1, last_move_m: 3.71e-5, converged: false, ..Default::default() };
        assert_eq!(
            capped.verdict(),
            "NOT settled: stopped by the cap of 1 sweep with points still moving 0.037 mm a sweep; raise Iterations"
        );
        // The finest level settled, a coarser one did not: the cap is not the finest level's sweep count.
        let coarse = RelaxReport { iterations: 3977, last_move_m: 3.4e-7, coarse_capped: true, ..capped };
        assert_eq!(
            coarse.verdict(),
            "NOT settled: a coarser level of the grid stopped at the sweep cap, so the shape depends on the cap \
             (the finest level then ran 3977 sweeps, its last moving points at most 0.00034 mm); raise Iterations"
        );
        let stiff = RelaxReport { stiff: true, ..capped };
        assert_eq!(
            stiff.verdict(),
            "NOT settled: stopped by the cap of 1 sweep with points still moving 0.037 mm a sweep; lower Stiffness, \
             or raise Iterations (where the pins bend stiff cloth more than it allows, it can keep moving however many \
             sweeps it gets)"
        );
        assert_eq!(stiff.summary(), "NOT settled: lower Stiffness or raise Iterations");
        assert_eq!(capped.summary(), "NOT settled: raise Iterations");
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

    /// Soft cloth with unit rest lengths and no thickness, 2000 sweeps at most.
    fn soft_unit_params(tolerance: f64) -> RelaxParams {
        RelaxParams { rest_u_m: 1.0, rest_v_m: 1.0, stiffness: 0.0, thickness_m: 0.0, max_iterations: 2000, tolerance }
    }

    #[test]
    fn stretched_and_squeezed_edges_pull_back_towards_rest() {
        // Three points in a row, the outer two pinned: the middle one is moved
        // towards the rest distance of whichever neighbour is off.
        let params = soft_unit_params(1e-7);
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
        let params = soft_unit_params(1e-9);
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

    #[test]
    fn the_solver_grid_splits_cells_until_the_longer_side_has_33_points() {
        assert_eq!(solver_grid(17, 17), (33, 33));
        assert_eq!(solver_grid(31, 21), (61, 41));
        assert_eq!(solver_grid(2, 2), (33, 33));
        assert_eq!(solver_grid(9, 3), (33, 9));
        assert_eq!(solver_grid(33, 5), (33, 5));
        assert_eq!(solver_grid(256, 9), (256, 9));
        assert_eq!(solver_grid(1, 5), (1, 5), "a side of one point has no cells to split");
    }

    #[test]
    fn a_coarse_grid_is_drawn_from_the_solver_grid_with_its_pins_exact() {
        // A 9 × 9 sheet hung by two corners: the same as relaxing the 33 × 33
        // sheet with the same pins and reading every fourth point.
        let (cols, rows) = (9, 9);
        let params = RelaxParams {
            rest_u_m: 0.1,
            rest_v_m: 0.1,
            stiffness: 0.2,
            thickness_m: 0.0,
            max_iterations: 4000,
            tolerance: 1e-5,
        };
        let flat = |cols: usize, rows: usize, spacing: f64| -> Vec<DVec3> {
            (0..cols * rows)
                .map(|k| DVec3::new((k % cols) as f64 * spacing * 0.8, 2.0, (k / cols) as f64 * spacing * 0.8))
                .collect()
        };
        let mut coarse = flat(cols, rows, 0.1);
        let mut pinned = vec![false; cols * rows];
        pinned[0] = true;
        pinned[cols - 1] = true;
        let report = relax_resolved(&mut coarse, cols, rows, &pinned, &params, &mut |_| ControlFlow::Continue(()))
            .expect("never cancelled");
        assert!(report.converged, "{report:?}");
        assert_eq!((coarse[0], coarse[cols - 1]), (flat(cols, rows, 0.1)[0], flat(cols, rows, 0.1)[cols - 1]));

        let mut fine = flat(33, 33, 0.025);
        let mut fine_pinned = vec![false; 33 * 33];
        fine_pinned[0] = true;
        fine_pinned[32] = true;
        let fine_params = RelaxParams { rest_u_m: 0.025, rest_v_m: 0.025, ..params };
        relax(&mut fine, 33, 33, &fine_pinned, &fine_params);
        for (k, p) in coarse.iter().enumerate() {
            let shared = fine[(k / cols) * 4 * 33 + (k % cols) * 4];
            assert!(p.distance(shared) < 1e-3, "point {k}: {p} against the fine grid's {shared}");
        }
    }
}
