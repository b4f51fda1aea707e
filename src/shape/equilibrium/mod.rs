//! The rest shape as a static equilibrium: the grid's positions where the
//! net force on every free point vanishes, found by Newton's method.
//!
//! The energy, in units of one point's weight (every point weighs the same):
//! - stretch: a spring along every row and column edge, rest length
//!   spacing × elasticity, ½·k·(l − L)²; the stiffness is set by
//!   [`STRETCH_MODULUS`]: a strip as wide as the cloth (√area) stretches by
//!   1/`STRETCH_MODULUS` under the whole cloth's weight;
//! - shear: a cell's diagonals move freely within the range the fabric's
//!   shear angle allows ([`super::relax::MAX_SHEAR_DEG`]) and are held by a
//!   spring [`SHEAR_SHARE`] as stiff outside it;
//! - bending: second neighbours along a row or column stay at least as far
//!   apart as the smallest radius of curvature *Stiffness* allows, held by a
//!   spring half as stiff as the stretch inside that limit (none at stiffness 0);
//! - gravity: every free point weighs 1 (−Y);
//! - pins are fixed.
//!
//! The residual is the largest net force on a free point, relative to its
//! weight; a shape is settled when it is at most the key's *Tolerance*. It
//! never gets below what rounding allows (the stiffest spring times the
//! spacing of doubles at the cloth's size), so a tolerance under that floor
//! is raised to it, and the report says so.
//!
//! Newton's method with a Levenberg–Marquardt shift and a line search on the
//! energy: every step factors the Hessian (a sparse Cholesky factorisation,
//! its pattern analysed once) and moves downhill. Where a compressed spring
//! makes the exact Hessian indefinite, the step uses its projection (each
//! term's block positive semi-definite) instead; near the answer the exact
//! one factors and the last steps converge quadratically. A step moves no point
//! further than [`MAX_STEP_SHARE`] of a rest spacing, so the solve stays on
//! the equilibrium nearest its start: the start chooses among the many a
//! slack cloth has. A mirror-symmetric layout stays exactly symmetric
//! (`mirror`), so rounding cannot tip it one way, and its steps are solved
//! for one point of each mirror orbit (`orbits`).

mod colliders;
mod friction;
mod hessian;
mod mirror;
mod orbits;
mod terms;

use std::ops::ControlFlow;

use glam::DVec3;

use super::relax::{Cancelled, FabricLimits, RelaxParams, RelaxProgress};
use crate::world::Obstacle;
use colliders::Colliders;
use hessian::Hessian;
use mirror::Mirror;
use orbits::Orbits;
use terms::Term;

/// A strip of the cloth as wide as the cloth stretches by the inverse of this
/// under the whole cloth's weight (5 000: 0.02 %).
pub const STRETCH_MODULUS: f64 = 5000.0;

/// Shear stiffness outside the free range, as a share of the stretch modulus.
pub const SHEAR_SHARE: f64 = 0.1;

/// Largest move of any point in one Newton step, as a share of the smaller rest spacing.
const MAX_STEP_SHARE: f64 = 0.25;

/// Newton steps a solve may take before it is reported not settled: a
/// safety cap (a gathered curtain at 33² takes about 1 000, every other
/// measured case under 160).
pub const MAX_NEWTON_STEPS: u32 = 2000;

/// How an equilibrium solve ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EquilibriumReport {
    /// Newton steps taken.
    pub steps: u32,
    /// Largest net force on a free point at the end, relative to its weight.
    pub residual: f64,
    /// The residual asked for: the key's tolerance, or the rounding floor where that is higher.
    pub tolerance: f64,
    pub converged: bool,
    /// Places on the cloth (grid points, or points along its edges) that
    /// started within a collider's thickness: the solve then never starts,
    /// as a start through a solid has no way out that keeps contact.
    pub start_inside: usize,
    /// Places resting on a collider at the end (within the barrier's reach of its thickness).
    pub resting: usize,
}

/// The equilibrium problem on one grid.
struct Problem {
    terms: Vec<Term>,
    /// Free rank of each point; `None` for a pin.
    rank: Vec<Option<usize>>,
    free: Vec<usize>,
    /// Each row and column edge between free points: `(a, b, its stretch term, its rest length)`.
    edges: Vec<(usize, usize, usize, f64)>,
    colliders: Colliders,
    /// The stiffest spring, for the rounding floor.
    stiffest: f64,
    /// Largest move a step may make.
    max_step_m: f64,
}

impl Problem {
    fn new(cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> Problem {
        let (u, v) = (params.rest_u_m, params.rest_v_m);
        let limits = FabricLimits::new(cols, rows, params);
        let weight = (cols * rows) as f64;
        let area = u * (cols - 1).max(1) as f64 * v * (rows - 1).max(1) as f64;
        let modulus = STRETCH_MODULUS * weight / area.sqrt();
        let (k_u, k_v) = (modulus * v / u, modulus * u / v);
        let k_shear = SHEAR_SHARE * modulus;
        let mut terms = Vec::new();
        let mut edges = Vec::new();
        let index = |i: usize, j: usize| j * cols + i;
        let pair = |terms: &mut Vec<Term>, a: usize, b: usize, min_m: f64, max_m: f64, k: f64| {
            if !(pinned[a] && pinned[b]) {
                terms.push(Term { a, b, min_m, max_m, k });
            }
        };
        for j in 0..rows {
            for i in 0..cols {
                let at = index(i, j);
                let mut edge = |terms: &mut Vec<Term>, b: usize, rest_m: f64, k: f64| {
                    if !pinned[at] && !pinned[b] {
                        edges.push((at, b, terms.len(), rest_m));
                    }
                    pair(terms, at, b, rest_m, rest_m, k);
                };
                if i + 1 < cols {
                    edge(&mut terms, index(i + 1, j), u, k_u);
                }
                if j + 1 < rows {
                    edge(&mut terms, index(i, j + 1), v, k_v);
                }
                if i + 1 < cols && j + 1 < rows {
                    let (lo, hi) = (limits.diagonal_min_m, limits.diagonal_max_m);
                    pair(&mut terms, at, index(i + 1, j + 1), lo, hi, k_shear);
                    pair(&mut terms, index(i + 1, j), index(i, j + 1), lo, hi, k_shear);
                }
                if i + 2 < cols && limits.second_u_min_m > 0.0 {
                    pair(&mut terms, at, index(i + 2, j), limits.second_u_min_m, f64::INFINITY, 0.5 * k_u);
                }
                if j + 2 < rows && limits.second_v_min_m > 0.0 {
                    pair(&mut terms, at, index(i, j + 2), limits.second_v_min_m, f64::INFINITY, 0.5 * k_v);
                }
            }
        }
        let mut rank = vec![None; pinned.len()];
        let mut free = Vec::new();
        for (point, _) in pinned.iter().enumerate().filter(|(_, p)| !**p) {
            rank[point] = Some(free.len());
            free.push(point);
        }
        let colliders = Colliders::new(&[], DVec3::ZERO, &free, &edges, u.min(v));
        Problem { terms, rank, free, edges, colliders, stiffest: k_u.max(k_v), max_step_m: MAX_STEP_SHARE * u.min(v) }
    }

    /// Places `obstacles` around the solve's coordinates (`centre` added reaches the world's).
    fn set_obstacles(&mut self, among: &Among, centre: DVec3) {
        let spacing_m = self.max_step_m / MAX_STEP_SHARE;
        self.colliders = Colliders::new(among.obstacles, centre, &self.free, &self.edges, spacing_m);
        self.colliders.friction.coefficient = among.friction.max(0.0);
    }

    fn energy(&self, x: &[DVec3]) -> f64 {
        let springs: f64 = self.terms.iter().map(|t| t.energy(x)).sum();
        let height: f64 = self.free.iter().map(|&p| x[p].y).sum();
        springs + height + self.colliders.energy(x)
    }

    /// Adds `g`, the gradient for site `site`'s position, to the site's ends.
    fn add_site_gradient(&self, site: usize, g: DVec3, out: &mut [f64]) {
        let site = self.colliders.sites[site];
        for (point, weight) in [(site.a, 1.0 - site.share), (site.b, site.share)] {
            let Some(p) = self.rank[point].filter(|_| weight != 0.0) else { continue };
            for axis in 0..3 {
                out[3 * p + axis] += weight * g[axis];
            }
        }
    }

    /// The energy's gradient over the free points (three entries a point).
    fn gradient(&self, x: &[DVec3], out: &mut [f64]) {
        out.fill(0.0);
        for rank in 0..self.free.len() {
            out[3 * rank + 1] = 1.0;
        }
        for t in &self.terms {
            let Some(g) = t.gradient(x) else { continue };
            self.add_gradient(t, g, out);
        }
        let mut touches = Vec::new();
        self.colliders.touches(x, &mut touches);
        for touch in &touches {
            self.add_site_gradient(touch.site, self.colliders.gradient(touch), out);
        }
        let mu = self.colliders.friction.coefficient;
        for (&(site, _), anchor) in &self.colliders.friction.anchors {
            self.add_site_gradient(site, anchor.gradient(mu, self.colliders.sites[site].at(x)), out);
        }
    }

    fn add_gradient(&self, t: &Term, g: DVec3, out: &mut [f64]) {
        if let Some(p) = self.rank[t.a] {
            for axis in 0..3 {
                out[3 * p + axis] += g[axis];
            }
        }
        if let Some(q) = self.rank[t.b] {
            for axis in 0..3 {
                out[3 * q + axis] -= g[axis];
            }
        }
    }

    /// Fills `hessian` (exact, or with every block projected definite; the
    /// colliders' blocks leave out the surfaces' curvature either way).
    fn assemble(&self, x: &[DVec3], hessian: &mut Hessian, orbits: &Orbits, definite: bool) {
        hessian.clear();
        for (index, t) in self.terms.iter().enumerate() {
            if let Some(block) = t.hessian(x, definite) {
                hessian.add(index, &block);
            }
        }
        let mut touches = Vec::new();
        self.colliders.touches(x, &mut touches);
        let blocks = touches.iter().map(|touch| (touch.site, self.colliders.hessian(x, touch, definite)));
        let mu = self.colliders.friction.coefficient;
        let anchors = self.colliders.friction.anchors.iter();
        let blocks =
            blocks.chain(anchors.map(|(&(site, _), a)| (site, a.hessian(mu, self.colliders.sites[site].at(x)))));
        for (site, block) in blocks {
            let site = self.colliders.sites[site];
            match site.term {
                Some(term) => hessian.add_along(term, site.share, &block),
                None => {
                    let Some(unknown) = orbits.unknown[site.a] else { continue };
                    hessian.add_point(unknown, orbits.sign[site.a], &block);
                }
            }
        }
    }

    /// The smallest residual rounding lets a solve reach at these positions.
    fn rounding_floor(&self, x: &[DVec3]) -> f64 {
        let size = x.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
        // Each term's force is off by its stiffness times a rounding of its length.
        4.0 * f64::EPSILON * size * self.stiffest
    }
}

/// Largest net force on a free point (its gradient's length), relative to its weight.
fn residual(gradient: &[f64]) -> f64 {
    gradient.chunks_exact(3).map(|g| (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()).fold(0.0, f64::max)
}

/// Moves the free points of `positions` (a `cols × rows` grid) to the
/// equilibrium nearest them (see the module doc); pins stay exactly where
/// they are. `control` is called before every Newton step and cancels the
/// solve when it breaks (`positions` then hold the last step's shape).
pub fn equilibrate(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<EquilibriumReport, Cancelled> {
    equilibrate_among(positions, cols, rows, pinned, params, &Among::NOTHING, control)
}

/// What the cloth rests among: colliders, and the friction on them (the
/// key's `friction`, a Coulomb coefficient).
#[derive(Clone, Copy, Debug)]
pub struct Among<'a> {
    pub obstacles: &'a [Obstacle],
    pub friction: f64,
}

impl Among<'_> {
    pub const NOTHING: Among<'static> = Among { obstacles: &[], friction: 0.0 };
}

/// [`equilibrate`] among colliders: every free point and every point along
/// an edge between free points keeps its obstacle's thickness from the
/// solid through every step ([`colliders`]). The start must keep it too
/// (else [`EquilibriumReport::start_inside`] counts where it does not, and
/// nothing moves). A resting place holds with static Coulomb friction
/// ([`friction`]): its force along the surface is at most `friction` times
/// the force it presses the surface with.
pub fn equilibrate_among(
    positions: &mut [DVec3],
    cols: usize,
    rows: usize,
    pinned: &[bool],
    params: &RelaxParams,
    among: &Among,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<EquilibriumReport, Cancelled> {
    equilibrate_watched(positions, (cols, rows), pinned, params, among, control, &mut |_| ())
}

/// [`equilibrate_among`], handing `watch` the whole shape (world
/// coordinates, pins included) after every step: what a view shows while a
/// solve runs, and how the tests see that every step keeps contact.
pub fn equilibrate_watched(
    positions: &mut [DVec3],
    (cols, rows): (usize, usize),
    pinned: &[bool],
    params: &RelaxParams,
    among: &Among,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    watch: &mut dyn FnMut(&[DVec3]),
) -> Result<EquilibriumReport, Cancelled> {
    assert_eq!(positions.len(), cols * rows);
    assert_eq!(pinned.len(), cols * rows);
    let mut problem = Problem::new(cols, rows, pinned, params);
    let unknowns = 3 * problem.free.len();
    if unknowns == 0 || positions.iter().any(|p| !p.is_finite()) {
        return Ok(EquilibriumReport { converged: unknowns == 0, ..EquilibriumReport::default() });
    }
    // Solved about the cloth's centre, so rounding is relative to its size, not its place.
    let centre = positions.iter().copied().sum::<DVec3>() / positions.len() as f64;
    let mut x: Vec<DVec3> = positions.iter().map(|p| *p - centre).collect();
    problem.set_obstacles(among, centre);
    let start_inside = problem.colliders.sites.iter().filter(|s| problem.colliders.clearance(&x, s) <= 0.0).count();
    if start_inside > 0 {
        return Ok(EquilibriumReport { start_inside, ..EquilibriumReport::default() });
    }
    // Colliders need not be symmetric where the pins are.
    let mirrors = if among.obstacles.is_empty() { Mirror::find(&x, cols, rows, pinned) } else { Vec::new() };
    for mirror in &mirrors {
        mirror.apply(&mut x, pinned);
    }
    let tolerance = params.tolerance.max(problem.rounding_floor(&x));
    let max_steps = MAX_NEWTON_STEPS.min(params.max_iterations.max(1));
    let orbits = Orbits::new(pinned, &mirrors);
    let mut linear = Linear {
        hessian: Hessian::new(&orbits.unknown, &orbits.sign, orbits.count, &problem.terms),
        reduced: vec![0.0; 3 * orbits.count],
        orbits,
    };
    let mut gradient = vec![0.0; unknowns];
    let mut step = vec![0.0; unknowns];
    let mut trial = x.clone();
    let mut watched = positions.to_vec();
    let mut trial_gradient = vec![0.0; unknowns];
    problem.colliders.update_anchors(&x);
    problem.gradient(&x, &mut gradient);
    let mut energy = problem.energy(&x);
    let mut report = EquilibriumReport { tolerance, residual: residual(&gradient), ..EquilibriumReport::default() };
    // Levenberg–Marquardt shift relative to the largest diagonal entry.
    let mut shift_share = 1e-9;
    let mut last_move_m = 0.0;
    while report.residual > tolerance && report.steps < max_steps {
        control(RelaxProgress { cols, rows, iteration: report.steps, max_iterations: max_steps, last_move_m })
            .is_continue()
            .then_some(())
            .ok_or(Cancelled)?;
        report.steps += 1;
        let Some(direction) = newton_direction(&problem, &x, &gradient, &mut linear, &mut step, &mut shift_share)
        else {
            break;
        };
        // Along the direction: no point further than the step limit, then halved until the energy drops.
        let longest = direction.chunks_exact(3).map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        let longest = longest.fold(0.0, f64::max);
        let mut alpha = if longest > problem.max_step_m { problem.max_step_m / longest } else { 1.0 };
        alpha = problem.colliders.step_limit(&x, &problem.rank, direction, alpha);
        let slope: f64 = gradient.iter().zip(direction.iter()).map(|(g, d)| g * d).sum();
        let mut accepted = false;
        for _ in 0..40 {
            for (rank, &point) in problem.free.iter().enumerate() {
                let d = DVec3::new(direction[3 * rank], direction[3 * rank + 1], direction[3 * rank + 2]);
                trial[point] = x[point] + d * alpha;
            }
            for mirror in &mirrors {
                mirror.apply(&mut trial, pinned);
            }
            let trial_energy = problem.energy(&trial);
            let drop = energy - trial_energy;
            // Near the answer the energy's change drowns in rounding: a step
            // that lowers the residual is taken there.
            let noise = 1e-13 * energy.abs().max(1.0);
            if drop >= -1e-4 * alpha * slope || drop.abs() <= noise {
                problem.gradient(&trial, &mut trial_gradient);
                if drop > noise || residual(&trial_gradient) < report.residual {
                    energy = trial_energy;
                    accepted = true;
                    break;
                }
            }
            alpha *= 0.5;
        }
        if !accepted {
            // No lower energy along this direction: a larger shift turns it towards the gradient.
            if shift_share >= LARGEST_SHIFT {
                break;
            }
            shift_share = (shift_share * 100.0).min(LARGEST_SHIFT);
            continue;
        }
        std::mem::swap(&mut x, &mut trial);
        last_move_m = alpha * longest;
        watched.iter_mut().zip(&x).for_each(|(w, p)| *w = *p + centre);
        watch(&watched);
        std::mem::swap(&mut gradient, &mut trial_gradient);
        if among.friction > 0.0 && !among.obstacles.is_empty() {
            // Friction's normal forces and anchors follow the step: the
            // energy the next step lowers, and the residual, are up to date.
            problem.colliders.update_anchors(&x);
            problem.gradient(&x, &mut gradient);
            energy = problem.energy(&x);
        }
        report.residual = residual(&gradient);
        shift_share =
            if alpha == 1.0 { (shift_share * 0.25).max(1e-15) } else { (shift_share * 4.0).min(LARGEST_SHIFT) };
    }
    report.converged = report.residual <= tolerance;
    let mut touches = Vec::new();
    problem.colliders.touches(&x, &mut touches);
    report.resting = touches.len();
    for (p, q) in positions.iter_mut().zip(&x).zip(pinned).filter(|(_, pin)| !**pin).map(|(pq, _)| pq) {
        *p = *q + centre;
    }
    Ok(report)
}

/// The linear algebra of a solve: the Hessian over the orbits' unknowns
/// and the right-hand side it solves in place.
struct Linear {
    orbits: Orbits,
    hessian: Hessian,
    reduced: Vec<f64>,
}

/// The Newton direction `−(H + λ·I)⁻¹·g` (in `step`), with `H` the exact
/// Hessian and `λ` the shift (`shift_share` of its largest diagonal entry).
/// Where compressed springs make the exact `H` indefinite, its projection
/// (every term's block semi-definite) takes its place at the same shift:
/// raising the shift until the exact one factors would have to outweigh
/// the stiffest compressed spring and turns the step into a crawl along the
/// gradient (measured: the tent at 65² took 77 steps that way, 41 this way).
/// The shift grows only if even the projection does not factor.
fn newton_direction<'a>(
    problem: &Problem,
    x: &[DVec3],
    gradient: &[f64],
    linear: &mut Linear,
    step: &'a mut [f64],
    shift_share: &mut f64,
) -> Option<&'a [f64]> {
    let Linear { hessian, reduced, orbits } = linear;
    let orbits = &*orbits;
    let assemble = |hessian: &mut Hessian, definite: bool| {
        problem.assemble(x, hessian, orbits, definite);
        let scale = hessian.largest_diagonal().max(1.0);
        for &(orbit, axis) in &orbits.fixed {
            hessian.add_diagonal(orbit, axis, scale);
        }
        scale
    };
    let mut solve = |hessian: &mut Hessian, shift: f64| {
        hessian.shift_diagonal(shift);
        orbits.reduce(&problem.free, gradient, reduced);
        for r in reduced.iter_mut() {
            *r = -*r;
        }
        hessian.solve(reduced).is_ok()
    };
    let scale = assemble(hessian, false);
    let mut solved = solve(hessian, *shift_share * scale);
    for share in [*shift_share, 1e-9, 1e-6, 1e-3, 1.0] {
        if solved {
            break;
        }
        let scale = assemble(hessian, true);
        solved = solve(hessian, share.max(*shift_share) * scale);
    }
    if !solved {
        return None;
    }
    orbits.expand(&problem.free, reduced, step);
    Some(step)
}

/// Largest Levenberg–Marquardt shift, as a share of the largest diagonal
/// entry: a direction along which no step lowers the energy raises the
/// shift up to this, then the solve stops (not settled).
const LARGEST_SHIFT: f64 = 1e-3;
