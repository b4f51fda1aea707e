//! A key's rest shape: every stage of the modelling phase, kept for display and tests.

use std::ops::ControlFlow;

use glam::DVec3;

use super::approximate::{Approximation, CatenaryNetwork, GridSpec, PinPoint, Placement, approximate};
use super::contact::count_crossings;
use super::lay_flat::{flat_at, lay_flat};
use super::relax::{Cancelled, DrapeReport, RelaxParams, RelaxProgress, RelaxReport, drape_among, relax_resolved};
use super::through::{grid_places, through_obstacles};
use crate::scene::{Cloth, Key};
use crate::world::{ColliderShape, Obstacle, push_out};

/// The modelling result of one key: catenary network (with conflicts), the
/// approximated surface and the relaxed surface, in vertex order `j·cols + i`.
#[derive(Clone, Debug)]
pub struct RestShape {
    pub grid: GridSpec,
    pub elasticity: f64,
    pub network: CatenaryNetwork,
    pub approximated: Vec<DVec3>,
    pub placement: Vec<Placement>,
    pub relaxed: Vec<DVec3>,
    pub relax_report: RelaxReport,
    /// Relaxed keeping the fabric's thickness between its folds, because
    /// the drape without it passed through itself; in-betweens next to such
    /// a key keep it too.
    pub kept_apart: bool,
}

impl RestShape {
    /// Builds the rest shape of `key` on `cloth`. The scene must be valid
    /// (at least one pin, inside the grid, no duplicates); the output is then
    /// finite and has every pin exactly at its position.
    pub fn build(cloth: &Cloth, key: &Key) -> RestShape {
        RestShape::build_with(cloth, key, &mut |_| ControlFlow::Continue(()))
            .expect("a control that never breaks never cancels")
    }

    /// [`RestShape::build`] reporting relaxation progress to `control` after
    /// every sweep; stops with [`Cancelled`] as soon as `control` breaks.
    pub fn build_with(
        cloth: &Cloth,
        key: &Key,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RestShape, Cancelled> {
        RestShape::build_among(cloth, key, &[], control)
    }

    /// Where the solve of `key` starts, in milliseconds: its catenary
    /// approximation, or laid flat at its placement without pins. The editor
    /// shows it, greyed, while the rest shape is being solved.
    pub fn first_guess(cloth: &Cloth, key: &Key) -> Vec<DVec3> {
        let grid = grid_spec(cloth);
        if key.pins.is_empty() {
            return flat_at_placement(grid, key);
        }
        approximate(grid, &pin_points(key), key.elasticity).positions
    }

    /// [`RestShape::build_with`] among colliders (the key's frame's). If the
    /// cloth relaxed without them comes within a collider's thickness (at a
    /// point or along an edge), it is built again by falling onto them: it
    /// starts flat in its pins' plane ([`lay_flat`]) and drops
    /// ([`drape_among`]); the approximation is kept for display. Otherwise,
    /// and with no obstacles, the same as `build_with`.
    pub fn build_among(
        cloth: &Cloth,
        key: &Key,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RestShape, Cancelled> {
        let grid = grid_spec(cloth);
        let params = key_params(grid, key);
        if key.pins.is_empty() {
            return RestShape::fall_unpinned(grid, key, &params, obstacles, control);
        }
        let pins = pin_points(key);
        let Approximation { network, positions, placement } = approximate(grid, &pins, key.elasticity);
        let pinned: Vec<bool> = placement.iter().map(|p| *p == Placement::Pin).collect();
        let mut relaxed = positions.clone();
        let free_params = RelaxParams { thickness_m: 0.0, ..params };
        let relax_report = relax_resolved(&mut relaxed, grid.cols, grid.rows, &pinned, &free_params, control)?;
        let mut plain = RestShape {
            grid,
            elasticity: key.elasticity,
            network,
            approximated: positions,
            placement,
            relaxed,
            relax_report,
            kept_apart: false,
        };
        // Relaxed without contact first: most drapes never come near
        // themselves, and a catenary approximation can start with folded rows
        // (the flag's top edge) that only passing through itself unfolds.
        // Where that drape settles through itself, it is relaxed again from
        // the approximation keeping the fabric's thickness. Not where it did
        // not settle (pins out of reach keep it moving, and contact would
        // sweep to the cap again; the verdict says what to change first), nor
        // where it falls onto colliders (from flat, below).
        if params.thickness_m > 0.0
            && plain.relax_report.converged
            && !plain.touches_obstacles(obstacles)
            && count_crossings(&plain.relaxed, grid.cols, grid.rows) > 0
        {
            let mut relaxed = plain.approximated.clone();
            // Kept only where it crosses nowhere on the cloth's own grid: contact
            // cannot part an approximation that starts crossed, and a coarse
            // cloth's read-back edges are chords that can cut a fold.
            if let Some(relax_report) = relax_kept_apart(&mut relaxed, grid, &pinned, &params, control)?
                && count_crossings(&relaxed, grid.cols, grid.rows) == 0
            {
                plain = RestShape { relaxed, relax_report, kept_apart: true, ..plain };
            }
        }
        RestShape::among_from(plain, key, obstacles, control)
    }

    /// The shape among `obstacles` of a key with pins, from `plain`, its
    /// shape without them ([`RestShape::build_among`] with none): `plain`
    /// itself where the hanging cloth does not reach them (a ground far
    /// below a curtain leaves it bit for bit as without), else the fall from
    /// flat ([`lay_flat`], [`drape_among`]), the approximation kept.
    pub fn among_from(
        plain: RestShape,
        key: &Key,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RestShape, Cancelled> {
        if !plain.touches_obstacles(obstacles) {
            return Ok(plain);
        }
        let grid = plain.grid;
        let params = key_params(grid, key);
        let pinned: Vec<bool> = plain.placement.iter().map(|p| *p == Placement::Pin).collect();
        let mut flat = plain.approximated.clone();
        let spacing = (grid.spacing_u_m, grid.spacing_v_m);
        lay_flat(&mut flat, (grid.cols, grid.rows), spacing, key.elasticity, &pinned, obstacles);
        let (relaxed, fall, kept_apart) = fall_among(flat, grid, &pinned, &params, obstacles, key.friction, control)?;
        let relax_report = judged(fall_report(fall, &params), &relaxed, grid, &pinned, obstacles);
        Ok(RestShape { relaxed, relax_report, kept_apart, ..plain })
    }

    /// Whether this shape, built without colliders, comes within one of
    /// `obstacles`' thickness (at a point or along an edge): if not, the
    /// key's shape among them is this one, bit for bit
    /// ([`RestShape::build_among`] keeps a cloth the colliders do not reach).
    pub fn touches_obstacles(&self, obstacles: &[Obstacle]) -> bool {
        touches(&self.relaxed, (self.grid.cols, self.grid.rows), obstacles)
    }

    /// A key without pins: the cloth starts flat at the key's placement (its
    /// approximation), leaves the colliders it starts in the nearest way and
    /// falls onto them. With nothing to fall on it stays flat (validation
    /// keeps such keys out of scenes).
    fn fall_unpinned(
        grid: GridSpec,
        key: &Key,
        params: &RelaxParams,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RestShape, Cancelled> {
        let flat = flat_at_placement(grid, key);
        let pinned = vec![false; flat.len()];
        let out: Vec<DVec3> = flat.iter().map(|&p| push_out(obstacles, p)).collect();
        let (relaxed, relax_report, kept_apart) = if obstacles.is_empty() {
            (out, RelaxReport { converged: true, ..RelaxReport::default() }, false)
        } else {
            let (relaxed, fall, kept_apart) = fall_among(out, grid, &pinned, params, obstacles, key.friction, control)?;
            let report = judged(fall_report(fall, params), &relaxed, grid, &pinned, obstacles);
            (relaxed, report, kept_apart)
        };
        Ok(RestShape {
            grid,
            elasticity: key.elasticity,
            network: CatenaryNetwork::unpinned(),
            approximated: flat,
            placement: vec![Placement::Draped; grid.point_count()],
            relaxed,
            relax_report,
            kept_apart,
        })
    }

    pub fn rest_u_m(&self) -> f64 {
        self.grid.spacing_u_m * self.elasticity
    }

    pub fn rest_v_m(&self) -> f64 {
        self.grid.spacing_v_m * self.elasticity
    }
}

/// Steps the fall keeping the fabric's thickness between its folds may
/// take, as a multiple of the steps the fall through itself took to settle.
/// Folds that the pins press together harder than the thickness allows (a
/// carpet pinned at its corners over a ball) push and pull without end, a
/// step costing tens of milliseconds; such a key keeps the fall through
/// itself, and its verdict says it passes through itself.
const KEPT_APART_FALL_STEPS: u32 = 2;

/// The fall from `start` onto `obstacles` ([`drape_among`]): first letting
/// the cloth pass through itself, as most falls onto a table never reach
/// themselves and the check costs a pair search a step; where that one
/// settles through itself, again from `start` keeping the fabric's thickness
/// between its folds at every step, kept where it crosses nowhere (a cloth
/// lifted by its middle folds round the table). Also says whether the
/// thickness was kept, so in-betweens next to the key keep it too.
fn fall_among(
    start: Vec<DVec3>,
    grid: GridSpec,
    pinned: &[bool],
    params: &RelaxParams,
    obstacles: &[Obstacle],
    friction: f64,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<(Vec<DVec3>, DrapeReport, bool), Cancelled> {
    let sides = (grid.cols, grid.rows);
    let mut fallen = start.clone();
    let through_itself = RelaxParams { thickness_m: 0.0, ..*params };
    let fall = drape_among(&mut fallen, sides, pinned, &through_itself, obstacles, friction, control)?;
    if !(params.thickness_m > 0.0 && fall.settled && count_crossings(&fallen, grid.cols, grid.rows) > 0) {
        return Ok((fallen, fall, false));
    }
    let mut kept = start;
    let kept_params = RelaxParams { max_iterations: fall.steps.saturating_mul(KEPT_APART_FALL_STEPS), ..*params };
    let kept_fall = drape_among(&mut kept, sides, pinned, &kept_params, obstacles, friction, control)?;
    if kept_fall.settled && count_crossings(&kept, grid.cols, grid.rows) == 0 {
        return Ok((kept, kept_fall, true));
    }
    Ok((fallen, fall, false))
}

/// A fall's outcome as a relaxation's, its last move also relative to the smaller rest spacing.
fn fall_report(fall: DrapeReport, params: &RelaxParams) -> RelaxReport {
    RelaxReport {
        iterations: fall.steps,
        last_move: fall.last_move_m / params.rest_u_m.min(params.rest_v_m),
        last_move_m: fall.last_move_m,
        converged: fall.settled,
        coarse_capped: false,
        fell_off: fall.fell_off,
        stiff: params.stiffness > 0.0,
        through: None,
    }
}

/// `report` with where `positions` pass through `obstacles`: such a shape
/// is not settled, however still the fall left it.
fn judged(
    report: RelaxReport,
    positions: &[DVec3],
    grid: GridSpec,
    pinned: &[bool],
    obstacles: &[Obstacle],
) -> RelaxReport {
    let through = through_obstacles(positions, (grid.cols, grid.rows), pinned, obstacles);
    RelaxReport { converged: report.converged && through.is_none(), through, ..report }
}

/// Edges are checked against the colliders at the points cutting them into this many equal parts.
const EDGE_PARTS: usize = 4;

/// Whether any point of `positions` (a grid), or any point along one of its
/// edges, is nearer an obstacle than its thickness.
fn touches(positions: &[DVec3], grid: (usize, usize), obstacles: &[Obstacle]) -> bool {
    let near = |p: DVec3| obstacles.iter().any(|o| !o.shape.keeps_clear(p, o.thickness));
    grid_places(positions, grid, EDGE_PARTS).any(|(p, _, _)| near(p))
}

/// Sweeps each grid level may take, after its settling, to settle keeping
/// the cloth's folds apart. Gathered curtains, pleated headings and crossed
/// pins settle well within it (a pleated heading's coarse level needs more
/// than 3000; BENCHMARKS.md, "Self-contact"); a crumpled cloth
/// whose stacked folds cannot all keep the thickness can push and pull
/// without end, and is left as the drape without contact (which passes
/// through itself, and says so) instead of sweeping to the key's cap level
/// after level.
pub const KEPT_APART_SWEEPS: u32 = 10_000;

/// [`relax_resolved`] keeping the fabric's thickness between its folds, from
/// the approximation in `positions`: its report where every level settled
/// before [`KEPT_APART_SWEEPS`] (or the key's cap, if lower), `None` where
/// one did not.
fn relax_kept_apart(
    positions: &mut [DVec3],
    grid: GridSpec,
    pinned: &[bool],
    params: &RelaxParams,
    control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
) -> Result<Option<RelaxReport>, Cancelled> {
    let params = RelaxParams { max_iterations: params.max_iterations.min(KEPT_APART_SWEEPS), ..*params };
    let mut gave_up = false;
    let mut watch = |progress: RelaxProgress| {
        // A level at its last allowed sweep has not settled in time, and is
        // not worth the finer levels' time.
        if progress.iteration >= progress.max_iterations {
            gave_up = true;
            return ControlFlow::Break(());
        }
        control(progress)
    };
    match relax_resolved(positions, grid.cols, grid.rows, pinned, &params, &mut watch) {
        Ok(report) if report.converged => Ok(Some(report)),
        Ok(_) => Ok(None),
        Err(Cancelled) if gave_up => Ok(None),
        Err(Cancelled) => Err(Cancelled),
    }
}

/// The relaxation's numbers for `key` on `grid`.
fn key_params(grid: GridSpec, key: &Key) -> RelaxParams {
    RelaxParams {
        rest_u_m: grid.spacing_u_m * key.elasticity,
        rest_v_m: grid.spacing_v_m * key.elasticity,
        stiffness: key.stiffness,
        thickness_m: key.thickness,
        max_iterations: key.relax.iterations,
        tolerance: key.relax.tolerance,
    }
}

/// A key without pins laid flat at its placement, where its fall starts.
fn flat_at_placement(grid: GridSpec, key: &Key) -> Vec<DVec3> {
    let start = key.placement_or_default();
    let (x, y, z) = start.rotation_deg;
    let rotation = ColliderShape::rotation_from_deg(x, y, z);
    let spacing = (grid.spacing_u_m, grid.spacing_v_m);
    flat_at((grid.cols, grid.rows), spacing, key.elasticity, DVec3::from(start.center), rotation)
}

/// A key's pins as the approximation takes them.
pub fn pin_points(key: &Key) -> Vec<PinPoint> {
    key.pins
        .iter()
        .map(|p| PinPoint { grid: (p.grid.0 as usize, p.grid.1 as usize), pos: DVec3::new(p.pos.0, p.pos.1, p.pos.2) })
        .collect()
}

/// The grid of a cloth.
pub fn grid_spec(cloth: &Cloth) -> GridSpec {
    GridSpec {
        cols: cloth.cols(),
        rows: cloth.rows(),
        spacing_u_m: cloth.spacing_u_m(),
        spacing_v_m: cloth.spacing_v_m(),
    }
}
