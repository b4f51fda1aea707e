//! Relaxation (paper §3.1): fine-tunes the approximated surface into a rest shape.
//!
//! Constraints, as the paper lists them after Weil:
//! (i) every point keeps its grid neighbours at their rest distance —
//!     structural neighbours at spacing × elasticity, shear diagonals at the
//!     diagonal of that — and
//! (ii) the angle with consecutive neighbours along a row or a column is pulled
//!     towards straight, weighted by the fabric's stiffness ∈ [0, 1].
//!
//! The solver is a nonlinear Gauss–Seidel iteration in gather form: each free
//! point in turn moves by the average of what its constraints ask, over-relaxed;
//! sweeps alternate direction so neither side of the cloth is favoured. It is
//! bit-for-bit deterministic. Pins never move. Iteration stops after `max_iterations`
//! sweeps or once the largest move of a sweep is below `tolerance` × the
//! smaller rest spacing.

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
    pub max_iterations: u32,
    /// Relative to the smaller rest spacing.
    pub tolerance: f64,
}

/// How a relaxation ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelaxReport {
    pub iterations: u32,
    /// Largest move in the last sweep, relative to the smaller rest spacing.
    pub last_move: f64,
    pub converged: bool,
}

/// Successive over-relaxation factor of the per-point moves (stable below 2).
const OVER_RELAXATION: f64 = 1.6;

/// Downward pull per settling sweep, relative to the rest spacing.
const GRAVITY_BIAS: f64 = 1e-3;
/// Share of the sweep budget spent settling under the fading pull.
const SETTLE_FRACTION: f64 = 0.5;

/// Smallest radius of curvature the fabric allows at stiffness 1, as a
/// fraction of the cloth's longer side; it scales with stiffness, and
/// stiffness 0 allows any fold.
pub const STIFF_RADIUS_FRACTION: f64 = 0.25;

/// Relaxes a `cols × rows` grid in place. `pinned[k]` points never move.
///
/// Each sweep visits the free points in order — forwards on even sweeps,
/// backwards on odd ones, so no side of the cloth is favoured — and moves each
/// point by the average of what its constraints ask, over-relaxed. Bending is
/// an inequality: a row or column may curve no tighter than the fabric's
/// smallest radius, enforced as a minimum distance between second neighbours,
/// so it never fights the distance constraints on gently curved cloth.
///
/// Non-finite positions are left where they are (they only arise from bad
/// input, which validation rejects); a zero-length edge asks for no move
/// instead of producing a NaN.
pub fn relax(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> RelaxReport {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    if cols >= MIN_COARSENED_SIDE * 2 - 1 && rows >= MIN_COARSENED_SIDE * 2 - 1 {
        solve_on_coarser_grid(positions, cols, rows, pinned, params);
    }
    sweep_until_converged(positions, cols, rows, pinned, params, Settle::Yes)
}

/// Fine-grid sweeps only, from the given positions: no coarsening and no
/// settling pull, so a nearby shape keeps its character and only its edge
/// lengths are restored. Animation uses it to re-relax an in-between blend
/// for a few sweeps. Same guarantees as [`relax`]: pins never move, output is
/// deterministic, non-finite moves are skipped.
pub fn refine(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> RelaxReport {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    sweep_until_converged(positions, cols, rows, pinned, params, Settle::No)
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Settle {
    Yes,
    No,
}

/// Grids are coarsened while both sides keep at least this many points.
const MIN_COARSENED_SIDE: usize = 9;

/// Cascadic multigrid: relax a grid with about half the points per side first
/// (recursively), then start the fine grid from its interpolation. Smooth,
/// large-scale moves that take Gauss–Seidel thousands of fine sweeps cost a
/// few cheap coarse ones; the fine sweeps only fix local detail.
fn solve_on_coarser_grid(positions: &mut [DVec3], cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) {
    let (coarse_cols, coarse_rows) = (cols.div_ceil(2), rows.div_ceil(2));
    // Fine grid steps per coarse step (2 for odd sides, a little less for even ones).
    let ratio_u = (cols - 1) as f64 / (coarse_cols - 1) as f64;
    let ratio_v = (rows - 1) as f64 / (coarse_rows - 1) as f64;
    let mut coarse = Vec::with_capacity(coarse_cols * coarse_rows);
    for l in 0..coarse_rows {
        for k in 0..coarse_cols {
            coarse.push(sample_bilinear(positions, cols, rows, k as f64 * ratio_u, l as f64 * ratio_v));
        }
    }
    let mut coarse_pinned = vec![false; coarse_cols * coarse_rows];
    for (f, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
        let (i, j) = (f % cols, f / cols);
        let (k, l) = ((i as f64 / ratio_u).round() as usize, (j as f64 / ratio_v).round() as usize);
        let c = l * coarse_cols + k;
        if !coarse_pinned[c] {
            coarse_pinned[c] = true;
            coarse[c] = positions[f];
        }
    }
    let coarse_params =
        RelaxParams { rest_u_m: params.rest_u_m * ratio_u, rest_v_m: params.rest_v_m * ratio_v, ..*params };
    relax(&mut coarse, coarse_cols, coarse_rows, &coarse_pinned, &coarse_params);
    for j in 0..rows {
        for i in 0..cols {
            let f = j * cols + i;
            if !pinned[f] {
                let p = sample_bilinear(&coarse, coarse_cols, coarse_rows, i as f64 / ratio_u, j as f64 / ratio_v);
                if p.is_finite() {
                    positions[f] = p;
                }
            }
        }
    }
}

/// Bilinear interpolation of a grid at fractional index (x along i, y along j).
fn sample_bilinear(positions: &[DVec3], cols: usize, rows: usize, x: f64, y: f64) -> DVec3 {
    let (x, y) = (x.clamp(0.0, (cols - 1) as f64), y.clamp(0.0, (rows - 1) as f64));
    let (i0, j0) = ((x.floor() as usize).min(cols - 2), (y.floor() as usize).min(rows - 2));
    let (fx, fy) = (x - i0 as f64, y - j0 as f64);
    let at = |i: usize, j: usize| positions[j * cols + i];
    let top = at(i0, j0).lerp(at(i0 + 1, j0), fx);
    let bottom = at(i0, j0 + 1).lerp(at(i0 + 1, j0 + 1), fx);
    top.lerp(bottom, fy)
}

/// Gauss–Seidel sweeps on one grid until the tolerance or the iteration cap.
fn sweep_until_converged(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    settle: Settle,
) -> RelaxReport {
    let rest_diag = (params.rest_u_m * params.rest_u_m + params.rest_v_m * params.rest_v_m).sqrt();
    let min_rest = params.rest_u_m.min(params.rest_v_m);
    let min_radius = params.stiffness.clamp(0.0, 1.0)
        * STIFF_RADIUS_FRACTION
        * (params.rest_u_m * (cols - 1) as f64).max(params.rest_v_m * (rows - 1) as f64);
    let second_u = min_second_neighbour_distance(params.rest_u_m, min_radius);
    let second_v = min_second_neighbour_distance(params.rest_v_m, min_radius);
    let mut report = RelaxReport::default();

    // Settling: the first sweeps also pull every free point down a little, fading
    // to nothing, so slack cloth hangs instead of staying where the approximation
    // left it; the remaining sweeps enforce the constraints alone.
    let settle_sweeps = if settle == Settle::Yes { (params.max_iterations as f64 * SETTLE_FRACTION) as u32 } else { 0 };
    for iteration in 0..params.max_iterations {
        let mut max_move2 = 0.0f64;
        let forwards = iteration % 2 == 0;
        let settling = iteration < settle_sweeps;
        let gravity = if settling {
            DVec3::new(0.0, -GRAVITY_BIAS * min_rest * (1.0 - iteration as f64 / settle_sweeps as f64), 0.0)
        } else {
            DVec3::ZERO
        };
        for step in 0..cols * rows {
            let k = if forwards { step } else { cols * rows - 1 - step };
            if pinned[k] {
                continue;
            }
            let (i, j) = (k % cols, k / cols);
            let p = positions[k];
            let mut sum = DVec3::ZERO;
            let mut count = 0.0;
            let mut pull = |n: usize, rest: f64, at_least: bool| {
                let d = positions[n] - p;
                let len = d.length();
                if at_least && len >= rest {
                    return;
                }
                if len > 1e-12 {
                    sum += d * ((len - rest) / len);
                }
                count += 1.0;
            };
            let (left, right, up, down) = (i > 0, i + 1 < cols, j > 0, j + 1 < rows);
            if left {
                pull(k - 1, params.rest_u_m, false);
            }
            if right {
                pull(k + 1, params.rest_u_m, false);
            }
            if up {
                pull(k - cols, params.rest_v_m, false);
            }
            if down {
                pull(k + cols, params.rest_v_m, false);
            }
            if left && up {
                pull(k - cols - 1, rest_diag, false);
            }
            if right && up {
                pull(k - cols + 1, rest_diag, false);
            }
            if left && down {
                pull(k + cols - 1, rest_diag, false);
            }
            if right && down {
                pull(k + cols + 1, rest_diag, false);
            }
            if second_u > 0.0 {
                if i >= 2 {
                    pull(k - 2, second_u, true);
                }
                if i + 2 < cols {
                    pull(k + 2, second_u, true);
                }
            }
            if second_v > 0.0 {
                if j >= 2 {
                    pull(k - 2 * cols, second_v, true);
                }
                if j + 2 < rows {
                    pull(k + 2 * cols, second_v, true);
                }
            }
            if count == 0.0 {
                continue;
            }
            let step = sum * (OVER_RELAXATION / count) + gravity;
            if step.is_finite() {
                positions[k] = p + step;
                max_move2 = max_move2.max(step.length_squared());
            }
        }
        report.iterations = iteration + 1;
        report.last_move = max_move2.sqrt() / min_rest;
        if !settling && report.last_move < params.tolerance {
            report.converged = true;
            break;
        }
    }
    report
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
