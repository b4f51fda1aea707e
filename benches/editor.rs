//! The editor's response to an edit: from moving a pin to the new shape on
//! screen (relaxed on the worker thread, taken by the UI, evaluated into the
//! mesh the viewport draws). A tablecloth hung from four corners, one corner
//! lifted a little further each iteration so no shape is ever cached.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::editor::DrapeApp;
use drape::scene::{Cloth, Ease, Key, Pin, RelaxSettings, Scene, Timeline};

fn tablecloth(n: u32) -> Scene {
    let last = n - 1;
    Scene {
        version: 1,
        name: "tablecloth".to_owned(),
        cloth: Cloth::new((2.0, 2.0), (n, n)),
        timeline: Timeline::default(),
        keys: vec![Key {
            frame: 0,
            pins: vec![
                Pin { grid: (0, 0), pos: (-0.9, 1.0, -0.9) },
                Pin { grid: (last, 0), pos: (0.9, 1.0, -0.9) },
                Pin { grid: (0, last), pos: (-0.9, 1.0, 0.9) },
                Pin { grid: (last, last), pos: (0.9, 1.0, 0.9) },
            ],
            elasticity: 1.05,
            stiffness: 0.2,
            relax: RelaxSettings::default(),
            ease: Ease::EaseInOut,
            inbetween_relax: 0,
        }],
        layers: Vec::new(),
        view: None,
    }
}

fn edit_to_shape(c: &mut Criterion) {
    let mut group = c.benchmark_group("edit_to_shape");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(4));
    for n in [32u32, 64, 128] {
        let mut app = DrapeApp::new(tablecloth(n), None, None).with_file_dirs(None, None);
        let mut lift = 0u32;
        group.bench_with_input(BenchmarkId::from_parameter(format!("{n}x{n}")), &n, |b, _| {
            b.iter(|| {
                lift += 1;
                app.apply("Move pin", |s| s.keys[0].pins[0].pos.1 = 1.0 + f64::from(lift) * 1e-4);
                assert!(app.wait_for_shapes(Duration::from_secs(60)));
                black_box(app.mesh().positions[0])
            })
        });
    }
    group.finish();
}

criterion_group!(benches, edit_to_shape);
criterion_main!(benches);
