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
use drape::shape::RelaxParams;
use drape::shape::equilibrium::equilibrate;
use glam::DVec3;

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

criterion_group!(benches, equilibrium);
criterion_main!(benches);
