//! The editor's response to an edit: from moving a pin to the new shape on
//! screen (relaxed on the worker thread, taken by the UI, evaluated into the
//! mesh the viewport draws). A tablecloth hung from four corners, one corner
//! lifted a little further each iteration so no shape is ever cached.
//!
//! And scrubbing: the editor's whole CPU time for one frame (egui's layout of
//! every panel plus evaluating the cloth at the new frame), run headless by
//! egui_kittest without a GPU, a 128² cloth with two keys and four layers,
//! the playhead moved one frame per iteration; and the bundled cape at 128²,
//! its pins attached to the walking glTF character.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::editor::DrapeApp;
use drape::scene::{
    Cloth, Ease, FollowThrough, Gusts, Key, Layer, Param, Pin, RelaxSettings, Scene, Sway, Wave, WaveAxis,
};
use egui_kittest::Harness;

fn tablecloth(n: u32) -> Scene {
    let last = n - 1;
    Scene {
        name: "tablecloth".to_owned(),
        cloth: Cloth::new((2.0, 2.0), (n, n)),
        keys: vec![Key {
            frame: 0,
            pins: vec![
                Pin::at((0, 0), (-0.9, 1.0, -0.9)),
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
        }],
        ..Scene::default()
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

/// The tablecloth with a second key (one corner lifted) and four layers.
fn animated_tablecloth(n: u32) -> Scene {
    let mut scene = tablecloth(n);
    let mut lifted = scene.keys[0].clone();
    lifted.frame = 48;
    lifted.pins[0].pos.1 = 1.4;
    scene.keys.push(lifted);
    let c = Param::Constant;
    scene.layers = vec![
        Layer::Sway(Sway {
            name: "sway".to_owned(),
            weight: c(1.0),
            magnitude: c(0.05),
            direction: (1.0, 0.0, 0.0),
            speed: c(1.0),
            frequency: c(0.5),
            phase: c(0.0),
            falloff: c(1.0),
            ..Sway::with_start_values()
        }),
        Layer::Wave(Wave {
            name: "wave".to_owned(),
            weight: c(1.0),
            magnitude: c(0.02),
            frequency: c(8.0),
            phase: c(0.0),
            speed: c(4.0),
            direction_deg: c(30.0),
            axis: WaveAxis::Normal,
            falloff: c(1.0),
            ..Wave::with_start_values()
        }),
        Layer::Gusts(Gusts {
            name: "gusts".to_owned(),
            weight: c(1.0),
            amplitude: c(0.03),
            scale: c(0.5),
            speed: c(1.0),
            direction: (1.0, 0.0, 0.3),
            turbulence: c(0.3),
            octaves: 2,
            seed: 1,
            falloff: c(1.0),
            ..Gusts::with_start_values()
        }),
        Layer::FollowThrough(FollowThrough {
            name: "follow".to_owned(),
            weight: c(1.0),
            lag: c(0.25),
            falloff: c(1.0),
            ..FollowThrough::with_start_values()
        }),
    ];
    scene
}

fn scrub_frame(c: &mut Criterion) {
    let mut group = c.benchmark_group("scrub_frame");
    group.sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(4));
    for n in [64u32, 128] {
        let scene = animated_tablecloth(n);
        let mut harness = Harness::builder()
            .with_size([1400.0, 860.0])
            .build_eframe(move |_| DrapeApp::new(scene, None, None).with_file_dirs(None, None));
        harness.step();
        let mut frame = 0.0;
        group.bench_with_input(BenchmarkId::from_parameter(format!("{n}x{n}")), &n, |b, _| {
            b.iter(|| {
                frame = (frame + 1.0) % 121.0;
                harness.state_mut().set_frame(frame);
                harness.step();
                black_box(harness.state().mesh().positions[0])
            })
        });
    }
    // The bundled cape at 128 × 128, its pins
    // attached to the 10 072-vertex walker (posed every frame), the walker not a collider.
    let cape = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cape.ron");
    let mut scene = drape::scene::load(&cape).expect("the bundled cape");
    scene.cloth.grid = (128, 128);
    for (pin, i) in scene.keys[0].pins.iter_mut().zip([0, 28, 64, 99, 127]) {
        pin.grid = (i, 0);
    }
    scene.references[0].collider = false;
    let mut harness = Harness::builder()
        .with_size([1400.0, 860.0])
        .build_eframe(move |_| DrapeApp::new(scene, None, None).with_file_dirs(None, None));
    harness.step();
    let mut frame = 0.0;
    group.bench_function("128x128 cape on a walker", |b| {
        b.iter(|| {
            frame = (frame + 1.0) % 49.0;
            harness.state_mut().set_frame(frame);
            harness.step();
            black_box(harness.state().mesh().positions[0])
        })
    });
    group.finish();
}

criterion_group!(benches, edit_to_shape, scrub_frame);
criterion_main!(benches);
