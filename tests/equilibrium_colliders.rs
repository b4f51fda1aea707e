//! The equilibrium among colliders: the cloth keeps every collider's
//! thickness at every step of the solve, along its edges as well as at its
//! points, and the shape it settles in is the energy's equilibrium.

use std::ops::ControlFlow;

use drape::shape::RelaxParams;
use drape::shape::equilibrium::{Among, EquilibriumReport, equilibrate_among, equilibrate_watched};
use drape::world::{ColliderShape, Obstacle};
use glam::{DMat3, DVec3};

/// A flat `n × n` sheet, 1 m square, level at height `y`, from x = −0.5..0.5
/// and z = 0..1, pinned at its two corners at z = 0.
fn sheet(n: usize, y: f64) -> (Vec<DVec3>, Vec<bool>) {
    let step = 1.0 / (n - 1) as f64;
    let positions = (0..n * n).map(|k| DVec3::new(-0.5 + step * (k % n) as f64, y, step * (k / n) as f64)).collect();
    let pinned = (0..n * n).map(|k| k == 0 || k == n - 1).collect();
    (positions, pinned)
}

fn params(n: usize, tolerance: f64) -> RelaxParams {
    let spacing = 1.0 / (n - 1) as f64;
    RelaxParams {
        rest_u_m: spacing,
        rest_v_m: spacing,
        stiffness: 0.3,
        thickness_m: 0.0,
        max_iterations: 2000,
        tolerance,
    }
}

fn solve(
    positions: &mut [DVec3],
    n: usize,
    pinned: &[bool],
    obstacles: &[Obstacle],
    tolerance: f64,
) -> EquilibriumReport {
    let among = Among { obstacles, friction: 0.0 };
    equilibrate_among(positions, n, n, pinned, &params(n, tolerance), &among, &mut |_| ControlFlow::Continue(()))
        .expect("never cancelled")
}

fn watched(
    positions: &mut [DVec3],
    n: usize,
    pinned: &[bool],
    obstacles: &[Obstacle],
    watch: &mut dyn FnMut(&[DVec3]),
) -> EquilibriumReport {
    let mut go = |_| ControlFlow::Continue(());
    let among = Among { obstacles, friction: 0.0 };
    equilibrate_watched(positions, (n, n), pinned, &params(n, 1e-7), &among, &mut go, watch).expect("never cancelled")
}

/// The deepest any point of the cloth (grid points, and `samples` points
/// along every row and column edge) reaches below an obstacle's surface
/// offset by its thickness (m; negative where everything keeps clear).
fn deepest(positions: &[DVec3], n: usize, pinned: &[bool], obstacles: &[Obstacle], samples: usize) -> f64 {
    let mut deepest = f64::NEG_INFINITY;
    let mut check = |p: DVec3| {
        for o in obstacles {
            deepest = deepest.max(o.thickness - o.shape.distance(p));
        }
    };
    for j in 0..n {
        for i in 0..n {
            let a = j * n + i;
            if !pinned[a] {
                check(positions[a]);
            }
            for b in [(i + 1 < n).then(|| a + 1), (j + 1 < n).then(|| a + n)].into_iter().flatten() {
                for s in 1..samples {
                    check(positions[a].lerp(positions[b], s as f64 / samples as f64));
                }
            }
        }
    }
    deepest
}

/// A ball the sheet hanging from its corners would pass through.
fn ball() -> Obstacle {
    Obstacle { shape: ColliderShape::Sphere { center: DVec3::new(0.0, 0.55, 0.15), radius: 0.25 }, thickness: 0.005 }
}

/// A shelf 2 cm thick and 20 cm deep across the middle of the sheet, 10 cm
/// below its pins: the sheet hung from four corners folds over its edges.
fn shelf() -> Obstacle {
    Obstacle {
        shape: ColliderShape::Box {
            center: DVec3::new(0.0, 0.89, 0.4),
            half: DVec3::new(0.8, 0.01, 0.1),
            world_from_local: DMat3::IDENTITY,
        },
        thickness: 0.003,
    }
}

/// The sheet hung from its four corners (0.8 m apart along z, 1 m along x)
/// without colliders, then turned up over its pins: a start above the shelf.
fn dome(n: usize) -> (Vec<DVec3>, Vec<bool>) {
    let (mut x, _) = sheet(n, 1.0);
    for p in &mut x {
        p.z *= 0.8;
    }
    let pinned: Vec<bool> = (0..n * n).map(|k| k == 0 || k == n - 1 || k == n * (n - 1) || k == n * n - 1).collect();
    // Sagging first, so the compressed flat start buckles downwards.
    for p in x.iter_mut().zip(&pinned).filter(|(_, pin)| !**pin).map(|(p, _)| p) {
        p.y -= 0.2 * (std::f64::consts::PI * p.z / 0.8).sin();
    }
    let report = solve(&mut x, n, &pinned, &[], 1e-7);
    assert!(report.converged, "{report:?}");
    for p in &mut x {
        p.y = 2.0 - p.y;
    }
    (x, pinned)
}

#[test]
fn a_sheet_falling_onto_a_ball_keeps_its_thickness_at_every_step() {
    let n = 13;
    let obstacles = [ball()];
    let (start, pinned) = sheet(n, 1.0);
    let mut end = start.clone();
    let mut deepest_step = f64::NEG_INFINITY;
    let report = watched(&mut end, n, &pinned, &obstacles, &mut |x| {
        deepest_step = deepest_step.max(deepest(x, n, &pinned, &obstacles, 16));
    });
    assert!(report.converged, "{report:?}");
    assert!(report.resting > 0, "the sheet comes to rest on the ball: {report:?}");
    // Along edges the cloth may enter the thickness by half the distance between its sites.
    assert!(deepest_step < 1e-4, "a step took the cloth {:.2} mm inside the thickness", deepest_step * 1e3);
    let depth = deepest(&end, n, &pinned, &obstacles, 16);
    assert!(depth < 0.0, "{depth}");
    // It rests on the ball: some point is within a millimetre of the thickness.
    assert!(depth > -1e-3, "the nearest point is {:.2} mm off the ball", -depth * 1e3);
}

#[test]
fn an_edge_never_cuts_a_thin_shelf() {
    let n = 11;
    let obstacles = [shelf()];
    let (start, pinned) = dome(n);
    let mut end = start.clone();
    let mut steps = 0;
    let report = watched(&mut end, n, &pinned, &obstacles, &mut |x| {
        steps += 1;
        // Along edges the cloth may enter the thickness by half the distance
        // between its sites, never the solid itself.
        let into_solid = deepest(x, n, &pinned, &obstacles, 64) - obstacles[0].thickness;
        assert!(into_solid < 0.0, "step {steps}: an edge is {:.2} mm inside the shelf", into_solid * 1e3);
    });
    assert!(report.converged, "{report:?}");
    assert!(report.resting > 0, "{report:?}");
    assert_eq!(steps, report.steps);
    // The middle rests on the shelf's top.
    let middle = end[(n / 2) * n + n / 2];
    assert!(middle.y > 0.903 && middle.y < 0.905, "{middle}");
}

#[test]
fn tolerance_moves_a_cloth_on_a_ball_by_less_than_a_millimetre() {
    let n = 13;
    let obstacles = [ball()];
    let (start, pinned) = sheet(n, 1.0);
    for friction in [0.0, 0.5] {
        let among = Among { obstacles: &obstacles, friction };
        let solve = |tolerance: f64| {
            let mut x = start.clone();
            let mut go = |_| ControlFlow::Continue(());
            let report = equilibrate_among(&mut x, n, n, &pinned, &params(n, tolerance), &among, &mut go);
            (x, report.expect("never cancelled"))
        };
        let (loose, loose_report) = solve(1e-5);
        let (tight, tight_report) = solve(1e-7);
        assert!(loose_report.converged && tight_report.converged, "{loose_report:?} {tight_report:?}");
        let moved = loose.iter().zip(&tight).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(moved < 1e-3, "friction {friction}: {:.3} mm", moved * 1e3);
        eprintln!("friction {friction}: {tight_report:?}, 1e-5 vs 1e-7 {:.4} mm", moved * 1e3);
    }
}

#[test]
fn a_start_through_a_collider_is_refused_and_left_as_it_was() {
    let n = 9;
    let obstacles = [ball()];
    let (start, pinned) = sheet(n, 0.6);
    let mut x = start.clone();
    let report = solve(&mut x, n, &pinned, &obstacles, 1e-7);
    assert!(report.start_inside > 0 && !report.converged, "{report:?}");
    assert_eq!(x, start);
}

/// A sheet lying on a slope `degrees` steep (descending towards +x), not
/// pinned anywhere, and the slope: 10 cm thick, 4 m square.
fn on_slope(n: usize, degrees: f64) -> (Vec<DVec3>, Vec<bool>, Obstacle) {
    let turn = DMat3::from_rotation_z(-degrees.to_radians());
    let slope = Obstacle {
        shape: ColliderShape::Box { center: DVec3::ZERO, half: DVec3::new(2.0, 0.05, 2.0), world_from_local: turn },
        thickness: 0.003,
    };
    let step = 1.0 / (n - 1) as f64;
    let lift = 0.05 + 0.003 + 0.0005;
    let positions = (0..n * n)
        .map(|k| turn * DVec3::new(-0.5 + step * (k % n) as f64, lift, -0.5 + step * (k / n) as f64))
        .collect();
    (positions, vec![false; n * n], slope)
}

fn on_slope_with(friction: f64, max_steps: u32) -> (Vec<DVec3>, Vec<DVec3>, EquilibriumReport) {
    let n = 9;
    let (start, pinned, slope) = on_slope(n, 20.0);
    let mut end = start.clone();
    let among = Among { obstacles: std::slice::from_ref(&slope), friction };
    let params = RelaxParams { max_iterations: max_steps, ..params(n, 1e-7) };
    let report = equilibrate_among(&mut end, n, n, &pinned, &params, &among, &mut |_| ControlFlow::Continue(()))
        .expect("never cancelled");
    (start, end, report)
}

#[test]
fn friction_above_the_slopes_tangent_holds_a_sheet_where_it_lies() {
    // tan 20° = 0.364.
    let (start, end, report) = on_slope_with(0.5, 2000);
    assert!(report.converged, "{report:?}");
    assert!(report.resting >= 81, "every point rests on the slope: {report:?}");
    let moved = start.iter().zip(&end).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(moved < 1e-3, "moved {:.2} mm", moved * 1e3);
}

#[test]
fn friction_below_the_slopes_tangent_lets_a_sheet_slide() {
    let (start, end, report) = on_slope_with(0.3, 150);
    assert!(!report.converged, "{report:?}");
    let downhill = end.iter().zip(&start).map(|(b, a)| b.x - a.x).sum::<f64>() / start.len() as f64;
    assert!(downhill > 0.01, "slid {:.1} mm", downhill * 1e3);
}
