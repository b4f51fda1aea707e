//! A key's rest shape: every stage of the modelling phase, kept for display and tests.

use std::ops::ControlFlow;

use glam::DVec3;

use super::approximate::{Approximation, CatenaryNetwork, GridSpec, PinPoint, Placement, approximate};
use super::lay_around::lay_around;
use super::relax::{Cancelled, RelaxParams, RelaxProgress, RelaxReport, relax_among};
use crate::scene::{Cloth, Key};
use crate::world::Obstacle;

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

    /// [`RestShape::build_with`] among colliders (the key's frame's): the
    /// approximation is laid around them ([`lay_around`]) and relaxed
    /// outside them ([`relax_among`]). No obstacles: the same as `build_with`.
    pub fn build_among(
        cloth: &Cloth,
        key: &Key,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RestShape, Cancelled> {
        let grid = grid_spec(cloth);
        let pins = pin_points(key);
        let Approximation { network, positions, placement } = approximate(grid, &pins, key.elasticity);
        let pinned: Vec<bool> = placement.iter().map(|p| *p == Placement::Pin).collect();
        let mut relaxed = positions.clone();
        let spacing = (grid.spacing_u_m, grid.spacing_v_m);
        lay_around(&mut relaxed, (grid.cols, grid.rows), spacing, &pinned, obstacles);
        let params = RelaxParams {
            rest_u_m: grid.spacing_u_m * key.elasticity,
            rest_v_m: grid.spacing_v_m * key.elasticity,
            stiffness: key.stiffness,
            max_iterations: key.relax.iterations,
            tolerance: key.relax.tolerance,
        };
        let relax_report = relax_among(&mut relaxed, grid.cols, grid.rows, &pinned, &params, obstacles, control)?;
        Ok(RestShape {
            grid,
            elasticity: key.elasticity,
            network,
            approximated: positions,
            placement,
            relaxed,
            relax_report,
        })
    }

    pub fn rest_u_m(&self) -> f64 {
        self.grid.spacing_u_m * self.elasticity
    }

    pub fn rest_v_m(&self) -> f64 {
        self.grid.spacing_v_m * self.elasticity
    }
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
