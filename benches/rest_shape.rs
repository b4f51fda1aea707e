//! Building a rest shape (approximate + relax) for square grids hung from four
//! corners, as the modelling issue's targets state them: 32², 64², 128², 256²,
//! and a table top held by 300 pins on 65². Every case runs at the default
//! relaxation settings and settles (checked before measuring), so the figures
//! are for the converged shape. The approximation alone is measured too: it
//! is the fixed part of the cost.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::scene::{Cloth, Ease, Key, Pin, RelaxSettings};
use drape::shape::rest_shape::{grid_spec, pin_points};
use drape::shape::{RestShape, approximate};
use std::hint::black_box;
use std::time::Duration;

fn four_corner_key(n: u32) -> Key {
    let last = n - 1;
    Key {
        frame: 0,
        pins: vec![
            Pin { grid: (0, 0), pos: (-0.9, 1.2, -0.9) },
            Pin { grid: (last, 0), pos: (0.9, 1.0, -0.9) },
            Pin { grid: (0, last), pos: (-0.9, 1.0, 0.9) },
            Pin { grid: (last, last), pos: (0.9, 1.0, 0.9) },
        ],
        elasticity: 1.05,
        stiffness: 0.2,
        relax: RelaxSettings::default(),
        ease: Ease::EaseInOut,
        inbetween_relax: 0,
        thickness: drape::scene::DEFAULT_THICKNESS_M,
    }
}

fn rest_shape(c: &mut Criterion) {
    let mut group = c.benchmark_group("rest_shape");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for n in [32u32, 64, 128, 256] {
        let cloth = Cloth::new((2.0, 2.0), (n, n));
        let key = four_corner_key(n);
        assert!(RestShape::build(&cloth, &key).relax_report.converged, "{n}² must settle to be measured");
        group.bench_with_input(BenchmarkId::from_parameter(format!("{n}x{n}")), &n, |b, _| {
            b.iter(|| black_box(RestShape::build(&cloth, &key)))
        });
    }
    group.finish();
}

/// A table top on 65 × 65 points, 2 cm apart, held by a 15 × 20 lattice of
/// pins (every fourth column, every third row, inside a one-pin-spacing
/// overhang), the pins 2% closer together than the cloth so it sags between.
fn table_top_key() -> Key {
    let spacing_m = 0.02;
    let mut pins = Vec::new();
    for j in (3..=60u32).step_by(3) {
        for i in (4..=60u32).step_by(4) {
            let (x, z) = (f64::from(i) * spacing_m * 0.98, f64::from(j) * spacing_m * 0.98);
            pins.push(Pin { grid: (i, j), pos: (x, 0.75, z) });
        }
    }
    assert_eq!(pins.len(), 300);
    Key { pins, ..four_corner_key(65) }
}

fn many_pins(c: &mut Criterion) {
    let mut group = c.benchmark_group("rest_shape_many_pins");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    let cloth = Cloth::new((1.28, 1.28), (65, 65));
    let key = table_top_key();
    assert!(RestShape::build(&cloth, &key).relax_report.converged, "the table top must settle to be measured");
    group.bench_function("300 pins 65x65", |b| b.iter(|| black_box(RestShape::build(&cloth, &key))));
    group.finish();
}

fn approximation(c: &mut Criterion) {
    let mut group = c.benchmark_group("approximate");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for n in [32u32, 64, 128, 256] {
        let grid = grid_spec(&Cloth::new((2.0, 2.0), (n, n)));
        let key = four_corner_key(n);
        let pins = pin_points(&key);
        group.bench_with_input(BenchmarkId::from_parameter(format!("{n}x{n}")), &n, |b, _| {
            b.iter(|| black_box(approximate(grid, &pins, key.elasticity)))
        });
    }
    group.finish();
}

criterion_group!(benches, rest_shape, many_pins, approximation);
criterion_main!(benches);
