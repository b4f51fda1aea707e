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
//! does not creep off a level table. With a thickness, every step is
//! followed by the sweeps' self-contact check (`self_contact`), so no step
//! carries one part of the cloth through another: a cloth lifted by its
//! middle folds round the table without its folds crossing. Deterministic:
//! a fixed order and fixed steps.
//! No sweeps follow it to make the lengths exact: their momentum, with
//! nothing pulling down, crumples the draped cloth on the table top and it
//! never settles.

use std::ops::ControlFlow;

use glam::DVec3;

use super::layout::Split;
use super::self_contact::{SelfContact, at_split, set};
use super::sweeper::min_second_neighbour_distance;
use super::{Cancelled, MAX_SHEAR_DEG, RelaxParams, RelaxProgress, STIFF_RADIUS_FRACTION};
use crate::world::{EDGE_SHARES, Obstacle, Reach, edge_place_lift, edge_surely_clear, push_out, slide_along};

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
    /// Whether a cloth without pins fell past every obstacle (the fall then stops).
    pub fell_off: bool,
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
    let lengths_from = links.partition_point(|link| link.min != link.max);
    let tethers = tethers((cols, rows), pinned, params);
    let min_rest = params.rest_u_m.min(params.rest_v_m);
    let max_move = 0.5 * min_rest;
    let calm = params.tolerance * min_rest;
    let mut velocity = vec![DVec3::ZERO; n];
    // How far the colliders pushed each point this step: the direction and
    // the pressure friction works with.
    let mut pushed = vec![DVec3::ZERO; n];
    let mut before = positions.to_vec();
    let mut calm_steps = 0;
    let mut last_move_m = 0.0;
    // A cloth with no pins that has fallen below every obstacle falls for ever: stop.
    let lowest_catch = obstacles.iter().map(|o| o.shape.bounds().0.y - o.thickness).fold(f64::INFINITY, f64::min);
    let unpinned = !pinned.iter().any(|&p| p);
    // Most points are far from every obstacle: passed over without measuring.
    let reach = Reach::of(obstacles);
    let mut contact = FallContact::new((cols, rows), pinned, params);
    for step in 0..max_steps {
        if unpinned && positions.iter().all(|p| p.y < lowest_catch) {
            return Ok(DrapeReport { steps: step, last_move_m, settled: false, fell_off: true });
        }
        before.copy_from_slice(positions);
        if let Some(contact) = &mut contact {
            contact.begin(&before);
        }
        pushed.fill(DVec3::ZERO);
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
            // The bounds first, the fabric's length after them, each group in
            // alternating order; the tethers between.
            let (bounds, lengths) = links.split_at(lengths_from);
            for (group, tether_after) in [(bounds, true), (lengths, false)] {
                if pass % 2 == 0 {
                    group.iter().for_each(|link| project(link, positions));
                } else {
                    group.iter().rev().for_each(|link| project(link, positions));
                }
                if tether_after {
                    tethers.iter().for_each(|tether| tether.hold(positions));
                }
            }
            // Contact inside the passes, so the fabric and the surfaces agree
            // (applied only after them, the push stretched the edges round a
            // table's corner to 1.39× their length); the step's path is
            // checked below.
            for k in (0..n).filter(|&k| !pinned[k]) {
                let p = positions[k];
                if obstacles.iter().enumerate().any(|(i, o)| reach.near(i, p) && !o.shape.keeps_clear(p, o.thickness)) {
                    let out = push_out(obstacles, positions[k]);
                    pushed[k] += out - positions[k];
                    positions[k] = out;
                }
            }
            // Along every edge too: between points resting on either side of
            // a table's rim, the straight edge would cut the rim.
            for link in links.iter().filter(|link| link.min == link.max) {
                keep_edge_out(link, positions, pinned, obstacles, &reach, &mut pushed);
            }
        }
        let mut largest = 0.0f64;
        for k in (0..n).filter(|&k| !pinned[k]) {
            let near = reach.near_path(before[k], positions[k]);
            let mut p = if near { slide_along(obstacles, before[k], positions[k]) } else { positions[k] };
            let push = pushed[k] + (p - positions[k]);
            if push != DVec3::ZERO && friction > 0.0 {
                p = with_friction(obstacles, friction, before[k], p, push);
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
        }
        // Too many folds near each other to keep apart: the fall goes on
        // without, and the shape's crossings say so.
        if contact.as_mut().is_some_and(|contact| contact.keep_apart(positions, &mut velocity)) {
            contact = None;
        }
        for k in (0..n).filter(|&k| !pinned[k]) {
            largest = largest.max((positions[k] - before[k]).length());
        }
        calm_steps = if largest < calm { calm_steps + 1 } else { 0 };
        let progress =
            RelaxProgress { cols, rows, iteration: step + 1, max_iterations: max_steps, last_move_m: largest };
        if control(progress).is_break() {
            return Err(Cancelled);
        }
        if calm_steps >= CALM_STEPS {
            return Ok(DrapeReport { steps: step + 1, last_move_m: largest, settled: true, fell_off: false });
        }
        last_move_m = largest;
    }
    Ok(DrapeReport { steps: max_steps, last_move_m, settled: false, fell_off: false })
}

/// The sweeps' self-contact check on the fall's steps: the positions laid
/// out as the sweeps keep them, the check's own state kept between steps.
struct FallContact {
    contact: SelfContact,
    position: [Split; 3],
    /// Zero throughout: a fall step carries no momentum of the sweeps' kind.
    velocity: [Split; 3],
    slots: Vec<usize>,
}

impl FallContact {
    /// The check for a `cols × rows` grid, or `None` without a thickness.
    fn new((cols, rows): (usize, usize), pinned: &[bool], params: &RelaxParams) -> Option<FallContact> {
        let min_rest = params.rest_u_m.min(params.rest_v_m);
        let contact = SelfContact::new(cols, rows, pinned, params.thickness_m, min_rest)?;
        let layout = Split::new(cols, rows);
        let slots = (0..cols * rows).map(|k| layout.slot(k % cols, k / cols)).collect();
        let split = || [Split::new(cols, rows), Split::new(cols, rows), Split::new(cols, rows)];
        Some(FallContact { contact, position: split(), velocity: split(), slots })
    }

    /// Notes where the step starts.
    fn begin(&mut self, before: &[DVec3]) {
        self.put(before);
        self.contact.begin(&self.position, &self.velocity);
    }

    /// Checks the step since [`FallContact::begin`], moving points apart or
    /// back where it must; a point contact moved stops. True where too many
    /// pairs were near each other to check.
    fn keep_apart(&mut self, positions: &mut [DVec3], velocity: &mut [DVec3]) -> bool {
        self.put(positions);
        if self.contact.keep_apart(&mut self.position, &mut self.velocity, 0.0).overwhelmed {
            return true;
        }
        for (k, &slot) in self.slots.iter().enumerate() {
            let p = at_split(&self.position, slot);
            if p != positions[k] {
                positions[k] = p;
                velocity[k] = DVec3::ZERO;
            }
        }
        false
    }

    fn put(&mut self, positions: &[DVec3]) {
        for (&slot, &p) in self.slots.iter().zip(positions) {
            set(&mut self.position, slot, p);
        }
    }
}

/// Moves the ends of `link` so that its deepest place in each obstacle
/// keeps the obstacle's thickness, each end by its share of that place (the
/// position-based rule for a point between two: the nearer end moves more).
/// Links with a pinned end are left to their free point's own contact:
/// moving that alone fought the link and stretched it (1.22× next to a
/// cape's pins on a shoulder).
fn keep_edge_out(
    link: &Link,
    positions: &mut [DVec3],
    pinned: &[bool],
    obstacles: &[Obstacle],
    reach: &Reach,
    pushed: &mut [DVec3],
) {
    if pinned[link.a] || pinned[link.b] {
        return;
    }
    for (index, obstacle) in obstacles.iter().enumerate() {
        let (a, b) = (positions[link.a], positions[link.b]);
        if !reach.near_segment(index, a, b) {
            continue;
        }
        if edge_surely_clear(obstacle, a, b, obstacle.thickness) {
            continue;
        }
        // Each place in turn, from the ends as they are after the last: every
        // place's push is zero at the thickness, so the passes stay smooth
        // (fixing only the deepest place jumped between places and kept the
        // fall from coming to rest).
        for t in EDGE_SHARES {
            let (a, b) = (positions[link.a], positions[link.b]);
            if let Some((lift_a, lift_b)) = edge_place_lift(obstacle, a, b, t, obstacle.thickness) {
                positions[link.a] += lift_a;
                positions[link.b] += lift_b;
                pushed[link.a] += lift_a;
                pushed[link.b] += lift_b;
            }
        }
    }
}

/// Coulomb friction on a point the colliders pushed by `push` this step,
/// ending at `pushed`: its move along the surface since `before` shrinks by
/// `friction` × how hard it presses, and stops if it was smaller (the cloth
/// sticks). It presses with its weight at most (one step's fall): a point
/// the fabric drags into a table's corner is pushed out further, but that
/// push is the fabric's pull, not weight, and holding against it would
/// stretch the cloth instead.
fn with_friction(obstacles: &[Obstacle], friction: f64, before: DVec3, pushed: DVec3, push: DVec3) -> DVec3 {
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

/// A free point's leash to a pin: it may be no farther from the pin than
/// the fabric between them is long (the straight line in the material,
/// times the elasticity). Without it a long hanging cloth stretches under
/// its own weight, as position-based steps do: the edges by a cape's pins,
/// holding a metre of cloth, stayed 1.2× long after 16 passes a step.
struct Tether {
    point: usize,
    pin: usize,
    length: f64,
}

impl Tether {
    fn hold(&self, positions: &mut [DVec3]) {
        let d = positions[self.point] - positions[self.pin];
        let distance = d.length();
        if distance > self.length && distance.is_finite() {
            positions[self.point] = positions[self.pin] + d * (self.length / distance);
        }
    }
}

/// Pins each free point is tethered to: its nearest ones in the material.
const TETHERS_PER_POINT: usize = 4;

/// The tethers of every free point to its [`TETHERS_PER_POINT`] nearest pins.
fn tethers((cols, rows): (usize, usize), pinned: &[bool], params: &RelaxParams) -> Vec<Tether> {
    let pins: Vec<usize> = (0..cols * rows).filter(|&k| pinned[k]).collect();
    let material = |k: usize| ((k % cols) as f64 * params.rest_u_m, (k / cols) as f64 * params.rest_v_m);
    let mut tethers = Vec::new();
    let mut nearest: Vec<(f64, usize)> = Vec::with_capacity(pins.len());
    for point in (0..cols * rows).filter(|&k| !pinned[k]) {
        let (u, v) = material(point);
        nearest.clear();
        nearest.extend(pins.iter().map(|&pin| {
            let (pu, pv) = material(pin);
            (((u - pu).powi(2) + (v - pv).powi(2)).sqrt(), pin)
        }));
        nearest.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        tethers.extend(nearest.iter().take(TETHERS_PER_POINT).map(|&(length, pin)| Tether { point, pin, length }));
    }
    tethers
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
    // The fabric's lengths after the shear and bending bounds, so where they
    // fight (pins gathered closer than the cloth between them, against the
    // bending bound) the length wins: mixed in, edges by a cape's gathered
    // top stayed 1.21× long.
    links.sort_by_key(|link| link.min == link.max);
    links
}
