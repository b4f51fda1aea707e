//! Dropping the cloth onto colliders: a short, damped fall under gravity.
//!
//! The sweeps of [`super::relax`] only hold the fabric's constraints, with a
//! fading pull on the coarsest grid to let slack hang; they have no weight
//! that would carry a cloth over a table's edge, and a coarse grid cannot
//! see a 4 cm table top. So a key among colliders first falls: position-
//! based dynamics on the finest grid (gravity, the same structural, shear
//! and bending bounds as the sweeps, Gauss–Seidel with alternating
//! direction, every point's move followed so it stops on a surface instead
//! of passing through), damped until no point moves more than the
//! tolerance in a step. Where a point rests on a surface, Coulomb friction
//! (the key's `friction` × how hard it presses) holds it, so a tablecloth
//! does not creep off a level table. Deterministic: a fixed order and
//! fixed steps.
//! (Running the sweeps after it to make the lengths exact was tried: their
//! momentum, with nothing pulling down, crumpled the draped cloth on the
//! table top and never settled.)

use std::ops::ControlFlow;

use glam::DVec3;

use super::sweeper::min_second_neighbour_distance;
use super::{Cancelled, MAX_SHEAR_DEG, RelaxParams, RelaxProgress, STIFF_RADIUS_FRACTION};
use crate::world::{Obstacle, push_out, slide_along};

/// Seconds per step: a point falls 0.7 mm in its first step.
const STEP_SECS: f64 = 1.0 / 120.0;
/// Share of the velocity a step keeps: the fall is over in about a second of cloth time.
const DAMPING: f64 = 0.95;
/// Constraint passes per step.
const PASSES: usize = 16;
/// Steps in a row with every move under the tolerance before the fall counts as over.
const CALM_STEPS: usize = 20;
const GRAVITY: DVec3 = DVec3::new(0.0, -9.81, 0.0);

/// How a fall ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrapeReport {
    pub steps: u32,
    /// The largest move of a point in the last step (m).
    pub last_move_m: f64,
    /// Whether it came to rest before `max_steps`.
    pub settled: bool,
}

/// One bound on the distance between two points.
struct Link {
    a: usize,
    b: usize,
    min: f64,
    max: f64,
}

/// Lets the free points of `positions` (a `cols × rows` grid) fall among
/// `obstacles` until they rest or `params.max_iterations` steps pass; pins never move.
pub fn drape_among(
    positions: &mut [DVec3],
    (cols, rows): (usize, usize),
    pinned: &[bool],
    params: &RelaxParams,
    obstacles: &[Obstacle],
    friction: f64,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<DrapeReport, Cancelled> {
    let n = cols * rows;
    assert_eq!(positions.len(), n);
    let max_steps = params.max_iterations;
    let links = links((cols, rows), params);
    let min_rest = params.rest_u_m.min(params.rest_v_m);
    let max_move = 0.5 * min_rest;
    let calm = params.tolerance * min_rest;
    let mut velocity = vec![DVec3::ZERO; n];
    let mut before = positions.to_vec();
    let mut calm_steps = 0;
    let mut last_move_m = 0.0;
    for step in 0..max_steps {
        before.copy_from_slice(positions);
        for k in (0..n).filter(|&k| !pinned[k]) {
            velocity[k] = velocity[k] * DAMPING + GRAVITY * STEP_SECS;
            positions[k] += velocity[k] * STEP_SECS;
        }
        for pass in 0..PASSES {
            let project = |link: &Link, positions: &mut [DVec3]| {
                let (wa, wb) = (if pinned[link.a] { 0.0 } else { 1.0 }, if pinned[link.b] { 0.0 } else { 1.0 });
                if wa + wb == 0.0 {
                    return;
                }
                let d = positions[link.b] - positions[link.a];
                let length = d.length();
                let target = length.clamp(link.min, link.max);
                if length == target || length == 0.0 || !length.is_finite() {
                    return;
                }
                let correction = d * ((length - target) / (length * (wa + wb)));
                positions[link.a] += correction * wa;
                positions[link.b] -= correction * wb;
            };
            if pass % 2 == 0 {
                links.iter().for_each(|link| project(link, positions));
            } else {
                links.iter().rev().for_each(|link| project(link, positions));
            }
            // Contact inside the passes, so the fabric and the surfaces agree
            // (applied only after them, the push stretched the edges round a
            // table's corner to 1.39× their length); the step's path is
            // checked below.
            for k in (0..n).filter(|&k| !pinned[k]) {
                if obstacles.iter().any(|o| o.shape.distance(positions[k]) < o.thickness) {
                    positions[k] = push_out(obstacles, positions[k]);
                }
            }
        }
        let mut largest = 0.0f64;
        for k in (0..n).filter(|&k| !pinned[k]) {
            let mut p = slide_along(obstacles, before[k], positions[k]);
            if p != positions[k] && friction > 0.0 {
                p = with_friction(obstacles, friction, before[k], positions[k], p);
            }
            let moved = p - before[k];
            if moved.length() > max_move {
                p = before[k] + moved * (max_move / moved.length());
                p = slide_along(obstacles, before[k], p);
            }
            if !p.is_finite() {
                p = before[k];
            }
            positions[k] = p;
            velocity[k] = (p - before[k]) / STEP_SECS;
            largest = largest.max((p - before[k]).length());
        }
        calm_steps = if largest < calm { calm_steps + 1 } else { 0 };
        let progress = RelaxProgress { cols, rows, iteration: step + 1, max_iterations: max_steps };
        if control(progress).is_break() {
            return Err(Cancelled);
        }
        if calm_steps >= CALM_STEPS {
            return Ok(DrapeReport { steps: step + 1, last_move_m: largest, settled: true });
        }
        last_move_m = largest;
    }
    Ok(DrapeReport { steps: max_steps, last_move_m, settled: false })
}

/// Coulomb friction on a point the collider pushed from `wanted` to
/// `pushed`: its move along the surface since `before` shrinks by
/// `friction` × how hard it presses, and stops if it was smaller (the cloth
/// sticks). It presses with its weight at most (one step's fall): a point
/// the fabric drags into a table's corner is pushed out further, but that
/// push is the fabric's pull, not weight, and holding against it would
/// stretch the cloth instead.
fn with_friction(obstacles: &[Obstacle], friction: f64, before: DVec3, wanted: DVec3, pushed: DVec3) -> DVec3 {
    let push = pushed - wanted;
    let depth = push.length();
    if !(depth > 0.0) {
        return pushed;
    }
    let normal = push / depth;
    let moved = pushed - before;
    let along = moved - normal * moved.dot(normal);
    let length = along.length();
    let weight = GRAVITY.length() * STEP_SECS * STEP_SECS;
    let held = (friction * depth.min(weight)).min(length);
    if !(length > 0.0) {
        return pushed;
    }
    push_out(obstacles, pushed - along * (held / length))
}

/// Every structural, shear and bending bound of the grid, row by row.
fn links((cols, rows): (usize, usize), params: &RelaxParams) -> Vec<Link> {
    let (u, v) = (params.rest_u_m, params.rest_v_m);
    let min_radius =
        params.stiffness.clamp(0.0, 1.0) * STIFF_RADIUS_FRACTION * (u * (cols - 1) as f64).max(v * (rows - 1) as f64);
    let (bend_u, bend_v) = (min_second_neighbour_distance(u, min_radius), min_second_neighbour_distance(v, min_radius));
    let shear_span = 2.0 * u * v * MAX_SHEAR_DEG.to_radians().sin();
    let (diag_min, diag_max) = ((u * u + v * v - shear_span).sqrt(), (u * u + v * v + shear_span).sqrt());
    let mut links = Vec::new();
    for j in 0..rows {
        for i in 0..cols {
            let k = j * cols + i;
            if i + 1 < cols {
                links.push(Link { a: k, b: k + 1, min: u, max: u });
            }
            if j + 1 < rows {
                links.push(Link { a: k, b: k + cols, min: v, max: v });
            }
            if i + 1 < cols && j + 1 < rows {
                links.push(Link { a: k, b: k + cols + 1, min: diag_min, max: diag_max });
                links.push(Link { a: k + 1, b: k + cols, min: diag_min, max: diag_max });
            }
            if bend_u > 0.0 && i + 2 < cols {
                links.push(Link { a: k, b: k + 2, min: bend_u, max: f64::INFINITY });
            }
            if bend_v > 0.0 && j + 2 < rows {
                links.push(Link { a: k, b: k + 2 * cols, min: bend_v, max: f64::INFINITY });
            }
        }
    }
    links
}
