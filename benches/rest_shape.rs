//! Building a rest shape (approximate + relax) for square grids hung from four
//! corners, at the sizes the README's targets name: 32², 64², 128², 256²,
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
            Pin::at((0, 0), (-0.9, 1.2, -0.9)),
            Pin::at((last, 0), (0.9, 1.0, -0.9)),
            Pin::at((0, last), (-0.9, 1.0, 0.9)),
            Pin::at((last, last), (0.9, 1.0, 0.9)),
        ],
        elasticity: 1.05,
        stiffness: 0.2,
        relax: RelaxSettings::default(),
        ease: Ease::EaseInOut,
        inbetween_relax: 0,
        thickness: drape::scene::DEFAULT_THICKNESS_M,
        friction: drape::scene::DEFAULT_FRICTION,
        placement: None,
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
            pins.push(Pin::at((i, j), (x, 0.75, z)));
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

/// A 1.6 × 1.2 m tablecloth on a 64 × 64 grid pinned at four points on a
/// 1.2 × 0.8 m table top: the key falls onto the table (the README's
/// "rest shape of a tablecloth falling onto a table").
fn on_a_table(c: &mut Criterion) {
    let mut group = c.benchmark_group("rest_shape_on_a_table");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
    let n = 64u32;
    let cloth = Cloth::new((1.6, 1.2), (n, n));
    let at = |i: u32, j: u32, x: f64, z: f64| Pin::at((i, j), (x, 0.743, z));
    let (a, b) = (n * 3 / 8, n * 5 / 8);
    let key = Key {
        pins: vec![at(a, a, -0.2, -0.15), at(b, a, 0.2, -0.15), at(a, b, -0.2, 0.15), at(b, b, 0.2, 0.15)],
        ..four_corner_key(n)
    };
    let colliders = "[Box((center: (0.0, 0.72, 0.0), size: (1.2, 0.04, 0.8))), Ground(())]";
    let text = format!(
        "(version: 1, cloth: (size: (1.6, 1.2), grid: ({n}, {n})), keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0, 1, 0))])], colliders: {colliders})"
    );
    let scene = drape::scene::parse(&text, "bench").expect("a valid scene");
    let obstacles = drape::animate::key_obstacles(&scene, &key);
    let build = || drape::animate::KeyShape::build(&cloth, &key, &obstacles);
    assert!(build().rest.relax_report.converged, "the tablecloth must settle to be measured");
    group.bench_function("64x64 four pins", |b| b.iter(|| black_box(build())));
    group.finish();
}

criterion_group!(benches, rest_shape, many_pins, approximation, on_a_table);
criterion_main!(benches);
