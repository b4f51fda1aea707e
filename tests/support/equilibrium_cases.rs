//! The equilibrium cases the tests and the `equilibrium` bench share: a
//! 1 m square cloth hung from a few pins, its catenary approximation and
//! today's relaxation of it (the solver's start).

// Each user takes the cases and steps it needs.
#![allow(dead_code)]

use std::ops::ControlFlow;

use drape::shape::relax::relax_resolved;
use drape::shape::{GridSpec, PinPoint, Placement, RelaxParams, approximate};
use glam::DVec3;

/// A 1 m square cloth on an `n × n` grid hanging from `pins` given by
/// material fraction (0..1 along width and height) and position.
pub struct Case {
    pub name: &'static str,
    pub pins: Vec<((f64, f64), DVec3)>,
    pub stiffness: f64,
}

impl Case {
    pub fn grid(n: usize) -> GridSpec {
        GridSpec { cols: n, rows: n, spacing_u_m: 1.0 / (n - 1) as f64, spacing_v_m: 1.0 / (n - 1) as f64 }
    }

    pub fn pin_points(&self, n: usize) -> Vec<PinPoint> {
        let at = |f: f64| (f * (n - 1) as f64).round() as usize;
        self.pins.iter().map(|&((fu, fv), pos)| PinPoint { grid: (at(fu), at(fv)), pos }).collect()
    }

    pub fn params(&self, n: usize, tolerance: f64) -> RelaxParams {
        let grid = Case::grid(n);
        RelaxParams {
            rest_u_m: grid.spacing_u_m,
            rest_v_m: grid.spacing_v_m,
            stiffness: self.stiffness,
            thickness_m: 0.0,
            max_iterations: 40_000,
            tolerance,
        }
    }

    /// The catenary approximation, and which points are pinned.
    pub fn approximation(&self, n: usize) -> (Vec<DVec3>, Vec<bool>) {
        let approximation = approximate(Case::grid(n), &self.pin_points(n), 1.0);
        let pinned: Vec<bool> = approximation.placement.iter().map(|p| *p == Placement::Pin).collect();
        (approximation.positions, pinned)
    }

    /// The relaxation's shape (the start), and which points are pinned.
    pub fn start(&self, n: usize) -> (Vec<DVec3>, Vec<bool>) {
        let (mut positions, pinned) = self.approximation(n);
        let params = self.params(n, 1e-5);
        relax_resolved(&mut positions, n, n, &pinned, &params, &mut |_| ControlFlow::Continue(()))
            .expect("never cancelled");
        (positions, pinned)
    }
}

/// Two top corners as far apart as the cloth is wide.
pub fn taut_curtain() -> Case {
    Case {
        name: "taut curtain",
        pins: vec![((0.0, 0.0), DVec3::new(-0.5, 1.0, 0.0)), ((1.0, 0.0), DVec3::new(0.5, 1.0, 0.0))],
        stiffness: 0.0,
    }
}

/// Two top corners 0.8 m apart: the top row gathers and the cloth buckles.
pub fn gathered_curtain() -> Case {
    Case {
        name: "gathered curtain",
        pins: vec![((0.0, 0.0), DVec3::new(-0.4, 1.0, 0.0)), ((1.0, 0.0), DVec3::new(0.4, 1.0, 0.0))],
        stiffness: 0.2,
    }
}

/// Four corners ±0.4 m, level at 1 m.
pub fn four_corners() -> Case {
    corners("four corners", 0.0)
}

/// Four corners with one raised 0.2 m: no mirror symmetry.
pub fn tilted_corners() -> Case {
    corners("tilted corners", 0.2)
}

/// Four corners ±0.4 m at 1 m, the first `raised` higher; stiffness 0.2.
fn corners(name: &'static str, raised: f64) -> Case {
    let h = 0.4;
    Case {
        name,
        pins: vec![
            ((0.0, 0.0), DVec3::new(-h, 1.0 + raised, -h)),
            ((1.0, 0.0), DVec3::new(h, 1.0, -h)),
            ((0.0, 1.0), DVec3::new(-h, 1.0, h)),
            ((1.0, 1.0), DVec3::new(h, 1.0, h)),
        ],
        stiffness: 0.2,
    }
}

pub fn tent() -> Case {
    let h = 0.5;
    Case {
        name: "tent",
        pins: vec![
            ((0.0, 0.0), DVec3::new(-h, 0.0, -h)),
            ((1.0, 0.0), DVec3::new(h, 0.0, -h)),
            ((0.0, 1.0), DVec3::new(-h, 0.0, h)),
            ((1.0, 1.0), DVec3::new(h, 0.0, h)),
            ((0.5, 0.5), DVec3::new(0.0, 0.3, 0.0)),
        ],
        stiffness: 0.0,
    }
}
