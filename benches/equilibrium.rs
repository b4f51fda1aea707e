//! The equilibrium solve (Newton on the rest-shape energy) on a 1 m cloth
//! hung from four corners ±0.4 m (mirror-symmetric), the same with one
//! corner raised 0.2 m (no symmetry) and as a taut curtain (two corners as
//! far apart as the cloth is wide), from the relaxation's shape and from the bare
//! catenary approximation, to tolerance 1e-7. Every case settles (checked
//! before measuring). Single-threaded.

use std::hint::black_box;
use std::ops::ControlFlow;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::shape::equilibrium::equilibrate;
use drape::shape::relax::relax_resolved;
use drape::shape::{GridSpec, PinPoint, Placement, RelaxParams, approximate};
use glam::DVec3;

struct Case {
    name: &'static str,
    pins: Vec<((f64, f64), DVec3)>,
    stiffness: f64,
}

fn cases() -> [Case; 3] {
    let h = 0.4;
    [
        Case {
            name: "four_corners",
            pins: vec![
                ((0.0, 0.0), DVec3::new(-h, 1.0, -h)),
                ((1.0, 0.0), DVec3::new(h, 1.0, -h)),
                ((0.0, 1.0), DVec3::new(-h, 1.0, h)),
                ((1.0, 1.0), DVec3::new(h, 1.0, h)),
            ],
            stiffness: 0.2,
        },
        Case {
            name: "tilted_corners",
            pins: vec![
                ((0.0, 0.0), DVec3::new(-h, 1.2, -h)),
                ((1.0, 0.0), DVec3::new(h, 1.0, -h)),
                ((0.0, 1.0), DVec3::new(-h, 1.0, h)),
                ((1.0, 1.0), DVec3::new(h, 1.0, h)),
            ],
            stiffness: 0.2,
        },
        Case {
            name: "taut_curtain",
            pins: vec![((0.0, 0.0), DVec3::new(-0.5, 1.0, 0.0)), ((1.0, 0.0), DVec3::new(0.5, 1.0, 0.0))],
            stiffness: 0.0,
        },
    ]
}

/// The approximation, the relaxed shape, the pins and the parameters on `n × n`.
fn setup(case: &Case, n: usize) -> (Vec<DVec3>, Vec<DVec3>, Vec<bool>, RelaxParams) {
    let spacing = 1.0 / (n - 1) as f64;
    let grid = GridSpec { cols: n, rows: n, spacing_u_m: spacing, spacing_v_m: spacing };
    let at = |f: f64| (f * (n - 1) as f64).round() as usize;
    let pins: Vec<PinPoint> =
        case.pins.iter().map(|&((fu, fv), pos)| PinPoint { grid: (at(fu), at(fv)), pos }).collect();
    let approximation = approximate(grid, &pins, 1.0);
    let pinned: Vec<bool> = approximation.placement.iter().map(|p| *p == Placement::Pin).collect();
    let params = RelaxParams {
        rest_u_m: spacing,
        rest_v_m: spacing,
        stiffness: case.stiffness,
        thickness_m: 0.0,
        max_iterations: 40_000,
        tolerance: 1e-7,
    };
    let mut relaxed = approximation.positions.clone();
    let relax_params = RelaxParams { tolerance: 1e-5, ..params };
    relax_resolved(&mut relaxed, n, n, &pinned, &relax_params, &mut |_| ControlFlow::Continue(()))
        .expect("never cancelled");
    (approximation.positions, relaxed, pinned, params)
}

fn solve(start: &[DVec3], n: usize, pinned: &[bool], params: &RelaxParams) -> Vec<DVec3> {
    let mut x = start.to_vec();
    let report =
        equilibrate(&mut x, n, n, pinned, params, &mut |_| ControlFlow::Continue(())).expect("never cancelled");
    assert!(report.converged, "must settle to be measured: {report:?}");
    x
}

fn equilibrium(c: &mut Criterion) {
    let mut group = c.benchmark_group("equilibrium");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
    for case in cases() {
        for n in [33usize, 65] {
            let (approximated, relaxed, pinned, params) = setup(&case, n);
            let id = |start: &str| BenchmarkId::new(format!("{}_from_{start}", case.name), format!("{n}x{n}"));
            group.bench_function(id("relaxed"), |b| b.iter(|| black_box(solve(&relaxed, n, &pinned, &params))));
            // From the approximation the path is longer (seconds at 65²): measured at 33² only.
            if n == 33 {
                group.bench_function(id("approximation"), |b| {
                    b.iter(|| black_box(solve(&approximated, n, &pinned, &params)))
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, equilibrium);
criterion_main!(benches);
