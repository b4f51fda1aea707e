//! The equilibrium solve (Newton on the rest-shape energy) on a 1 m cloth
//! hung from four corners ±0.4 m (mirror-symmetric), the same with one
//! corner raised 0.2 m (no symmetry) and as a taut curtain (two corners as
//! far apart as the cloth is wide), from the relaxation's shape and from the bare
//! catenary approximation, to tolerance 1e-7. Every case settles (checked
//! before measuring). Single-threaded.
//!
//! Among colliders: the bundled round table's 1.6 m tablecloth dropped flat
//! from 6 cm above the top (friction 0.5, thickness 3 mm, tolerance 1e-5),
//! solved as an equilibrium and, beside it, by today's fall (`drape_among`).

use std::hint::black_box;
use std::ops::ControlFlow;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::shape::RelaxParams;
use drape::shape::equilibrium::{Among, equilibrate, equilibrate_among};
use drape::shape::lay_flat::flat_at;
use drape::shape::relax::drape_among;
use drape::world::{ColliderShape, Obstacle};
use glam::{DMat3, DVec3};

#[path = "../tests/support/equilibrium_cases.rs"]
mod equilibrium_cases;

use equilibrium_cases::{Case, four_corners, taut_curtain, tilted_corners};

/// The approximation, the relaxed shape, the pins and the parameters on `n × n`.
fn setup(case: &Case, n: usize) -> (Vec<DVec3>, Vec<DVec3>, Vec<bool>, RelaxParams) {
    let (approximated, _) = case.approximation(n);
    let (relaxed, pinned) = case.start(n);
    (approximated, relaxed, pinned, case.params(n, 1e-7))
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
    for case in [four_corners(), tilted_corners(), taut_curtain()] {
        for n in [33usize, 65] {
            let (approximated, relaxed, pinned, params) = setup(&case, n);
            let id = |start: &str| {
                BenchmarkId::new(format!("{}_from_{start}", case.name.replace(' ', "_")), format!("{n}x{n}"))
            };
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

/// The round table's colliders: the top, the leg and the floor.
fn round_table() -> Vec<Obstacle> {
    let cylinder = |center: DVec3, radius: f64, half_height: f64| Obstacle {
        shape: ColliderShape::Cylinder { center, radius, half_height, world_from_local: DMat3::IDENTITY },
        thickness: 0.003,
    };
    vec![
        cylinder(DVec3::new(0.0, 0.72, 0.0), 0.5, 0.02),
        cylinder(DVec3::new(0.0, 0.35, 0.0), 0.05, 0.35),
        Obstacle { shape: ColliderShape::Ground { height: 0.0 }, thickness: 0.003 },
    ]
}

fn tablecloth(c: &mut Criterion) {
    let mut group = c.benchmark_group("tablecloth_on_round_table");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(10));
    let obstacles = round_table();
    let among = Among { obstacles: &obstacles, friction: 0.5 };
    // 33² takes seconds a solve: measured once by hand (BENCHMARKS.md).
    let n = 17;
    let spacing = 1.6 / (n - 1) as f64;
    let flat = flat_at((n, n), (spacing, spacing), 1.0, DVec3::new(0.0, 0.8, 0.0), DMat3::IDENTITY);
    let pinned = vec![false; n * n];
    let params = RelaxParams {
        rest_u_m: spacing,
        rest_v_m: spacing,
        stiffness: 0.25,
        thickness_m: 0.0,
        max_iterations: 3000,
        tolerance: 1e-5,
    };
    let size = format!("{n}x{n}");
    group.bench_function(BenchmarkId::new("equilibrium", &size), |b| {
        b.iter(|| {
            let mut x = flat.clone();
            let report = equilibrate_among(&mut x, n, n, &pinned, &params, &among, &mut |_| ControlFlow::Continue(()));
            assert!(report.is_ok_and(|r| r.converged), "must settle to be measured");
            black_box(x)
        })
    });
    group.bench_function(BenchmarkId::new("todays_fall", &size), |b| {
        b.iter(|| {
            let mut x = flat.clone();
            let report =
                drape_among(&mut x, (n, n), &pinned, &params, &obstacles, 0.5, &mut |_| ControlFlow::Continue(()));
            assert!(report.is_ok_and(|r| r.settled), "must settle to be measured");
            black_box(x)
        })
    });
    group.finish();
}

criterion_group!(benches, equilibrium, tablecloth);
criterion_main!(benches);
