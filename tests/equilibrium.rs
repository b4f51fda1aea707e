//! The rest shape as a static equilibrium: settled means the net force on
//! every free point is within the tolerance of its weight, so a tighter
//! tolerance refines the same shape instead of moving it.

use std::ops::ControlFlow;
use std::time::Instant;

use drape::shape::equilibrium::{EquilibriumReport, equilibrate};
use glam::DVec3;

mod support;

use support::equilibrium_cases::{Case, four_corners, gathered_curtain, taut_curtain, tent, tilted_corners};

/// Solves `case` from `start`, printing the figures BENCHMARKS.md quotes.
fn solve(case: &Case, n: usize, start: &[DVec3], pinned: &[bool], tolerance: f64) -> (Vec<DVec3>, EquilibriumReport) {
    let mut positions = start.to_vec();
    let began = Instant::now();
    let report =
        equilibrate(&mut positions, n, n, pinned, &case.params(n, tolerance), &mut |_| ControlFlow::Continue(()))
            .expect("never cancelled");
    eprintln!(
        "{} {n}²: tolerance {tolerance:e}: {} steps, residual {:.2e} (asked {:.2e}), {:.1} ms",
        case.name,
        report.steps,
        report.residual,
        report.tolerance,
        began.elapsed().as_secs_f64() * 1e3
    );
    (positions, report)
}

fn largest_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

/// Tolerance 1e-5 and 1e-7 both settle, within a millimetre of each other.
fn assert_tolerance_keeps_the_shape(case: &Case, n: usize) {
    let (start, pinned) = case.start(n);
    let (loose, loose_report) = solve(case, n, &start, &pinned, 1e-5);
    let (tight, tight_report) = solve(case, n, &start, &pinned, 1e-7);
    assert!(loose_report.converged, "{} {n}²: not settled at 1e-5: {loose_report:?}", case.name);
    assert!(tight_report.converged, "{} {n}²: not settled at 1e-7: {tight_report:?}", case.name);
    let moved = largest_distance(&loose, &tight);
    let describe = |x: &[DVec3]| {
        let top_mid = x[n / 2].y;
        let lowest = x.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        let rest = 1.0 / (n - 1) as f64;
        let mut strain: f64 = 0.0;
        for j in 0..n {
            for i in 0..n {
                let k = j * n + i;
                if i + 1 < n {
                    strain = strain.max(x[k].distance(x[k + 1]) / rest - 1.0);
                }
                if j + 1 < n {
                    strain = strain.max(x[k].distance(x[k + n]) / rest - 1.0);
                }
            }
        }
        format!("top middle y {top_mid:.4}, lowest y {lowest:.4}, largest strain {:.3} %", strain * 100.0)
    };
    eprintln!("{} {n}²: start: {}; equilibrium: {}", case.name, describe(&start), describe(&tight));
    eprintln!("{} {n}²: 1e-5 vs 1e-7 {:.4} mm; from the start {:.1} mm", case.name, moved * 1e3, {
        largest_distance(&start, &tight) * 1e3
    });
    assert!(moved < 1e-3, "{} {n}²: tolerance moved the shape by {:.3} mm", case.name, moved * 1e3);
}

#[test]
fn a_taut_curtain_keeps_its_shape_from_tolerance_1e5_to_1e7() {
    assert_tolerance_keeps_the_shape(&taut_curtain(), 33);
    assert_tolerance_keeps_the_shape(&taut_curtain(), 65);
}

#[test]
fn a_gathered_curtain_keeps_its_shape_from_tolerance_1e5_to_1e7() {
    assert_tolerance_keeps_the_shape(&gathered_curtain(), 33);
}

#[test]
fn four_corners_keep_their_shape_from_tolerance_1e5_to_1e7() {
    assert_tolerance_keeps_the_shape(&four_corners(), 33);
    assert_tolerance_keeps_the_shape(&four_corners(), 65);
}

#[test]
fn tilted_corners_keep_their_shape_from_tolerance_1e5_to_1e7() {
    assert_tolerance_keeps_the_shape(&tilted_corners(), 33);
    assert_tolerance_keeps_the_shape(&tilted_corners(), 65);
}

#[test]
fn a_tent_keeps_its_shape_from_tolerance_1e5_to_1e7() {
    assert_tolerance_keeps_the_shape(&tent(), 33);
    assert_tolerance_keeps_the_shape(&tent(), 65);
}

/// The relaxation only shortens the way: Newton from the bare catenary
/// approximation reaches the same equilibrium as from the relaxed shape.
#[test]
fn the_equilibrium_does_not_depend_on_the_relaxation_before_it() {
    for case in [four_corners(), tent(), taut_curtain()] {
        let n = 33;
        let (relaxed, pinned) = case.start(n);
        let (approximated, _) = case.approximation(n);
        let (from_relaxed, a) = solve(&case, n, &relaxed, &pinned, 1e-7);
        let (from_approximation, b) = solve(&case, n, &approximated, &pinned, 1e-7);
        assert!(a.converged && b.converged, "{}: {a:?} {b:?}", case.name);
        let apart = largest_distance(&from_relaxed, &from_approximation);
        assert!(apart < 1e-3, "{}: the two starts end {:.3} mm apart", case.name, apart * 1e3);
    }
}

/// Pins stay exactly where they are; a mirror-symmetric layout hangs
/// mirror-symmetric (to rounding: the factorisation's order is not symmetric).
#[test]
fn pins_stay_put_and_a_symmetric_layout_hangs_symmetric() {
    let case = four_corners();
    let n = 33;
    let (start, pinned) = case.start(n);
    let (x, report) = solve(&case, n, &start, &pinned, 1e-7);
    assert!(report.converged);
    for (k, pin) in pinned.iter().enumerate() {
        if *pin {
            assert_eq!(x[k], start[k], "pin {k} moved");
        }
    }
    let mut worst: f64 = 0.0;
    for j in 0..n {
        for i in 0..n {
            let (p, q) = (x[j * n + i], x[j * n + (n - 1 - i)]);
            worst = worst.max(p.distance(DVec3::new(-q.x, q.y, q.z)));
        }
    }
    assert!(worst < 1e-6, "{:.2e} m asymmetric", worst);
}

/// A control that breaks stops the solve with `Cancelled`, after reporting
/// progress on the grid it solves.
#[test]
fn a_breaking_control_cancels_the_solve() {
    let case = four_corners();
    let n = 33;
    let (mut x, pinned) = case.approximation(n);
    let mut calls = 0;
    let result = equilibrate(&mut x, n, n, &pinned, &case.params(n, 1e-7), &mut |progress| {
        assert_eq!((progress.cols, progress.rows), (n, n));
        calls += 1;
        if calls == 3 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    });
    assert!(result.is_err(), "a broken control must cancel");
    assert_eq!(calls, 3);
    assert!(x.iter().all(|p| p.is_finite()));
}

/// A cloth whose pins pull it tighter than it reaches still settles: the
/// stretch stiffness is finite, so every layout has an equilibrium.
#[test]
fn pins_out_of_reach_stretch_the_cloth_and_settle() {
    let case = Case {
        name: "overstretched",
        pins: vec![((0.0, 0.0), DVec3::new(-0.6, 1.0, 0.0)), ((1.0, 0.0), DVec3::new(0.6, 1.0, 0.0))],
        stiffness: 0.0,
    };
    let n = 17;
    let (start, pinned) = case.approximation(n);
    let (x, report) = solve(&case, n, &start, &pinned, 1e-7);
    assert!(report.converged, "{report:?}");
    let top = x[0].distance(x[n - 1]);
    assert!((top - 1.2).abs() < 1e-12 && x.iter().all(|p| p.is_finite()));
}
