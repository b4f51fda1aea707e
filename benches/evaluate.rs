//! `evaluate` with the rest shapes cached, at the sizes the README's targets
//! name: a 128² and a 256² cloth with a sway, two waves and a gusts
//! layer, and frame 100 000 against frame 1 (the cost must not grow with t),
//! also timed in alternation for a ratio the machine's drift cannot skew.
//! On a CPU with AVX2 this times evaluate's AVX2 build of its per-vertex
//! passes (bit-identical to the portable one, see `animate::evaluate`).

use criterion::measurement::WallTime;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drape::animate::{EvaluateOptions, Evaluator};
use drape::mesh::Mesh;
use drape::scene::{Cloth, Ease, Gusts, Key, Layer, Param, ParamKey, Pin, RelaxSettings, Scene, Sway, Wave, WaveAxis};
use std::hint::black_box;
use std::time::Duration;

fn key(frame: i32, n: u32, lift: f64) -> Key {
    let last = n - 1;
    Key {
        frame,
        pins: vec![
            Pin::at((0, 0), (-0.9, 1.2 + lift, -0.9)),
            Pin::at((last, 0), (0.9, 1.0, -0.9)),
            Pin::at((0, last), (-0.9, 1.0, 0.9)),
            Pin::at((last, last), (0.9, 1.0 + lift, 0.9)),
        ],
        elasticity: 1.05,
        stiffness: 0.2,
        relax: RelaxSettings { iterations: 200, tolerance: 1e-5 },
        ease: Ease::EaseInOut,
        inbetween_relax: 0,
        thickness: drape::scene::DEFAULT_THICKNESS_M,
        friction: drape::scene::DEFAULT_FRICTION,
        placement: None,
    }
}

fn wave(name: &str, magnitude: f64, frequency: f64, direction_deg: f64) -> Layer {
    Layer::Wave(Wave {
        name: name.into(),
        enabled: true,
        weight: 1.0.into(),
        magnitude: Param::Keys(vec![
            ParamKey { frame: 0, value: 0.0, ease: Ease::Linear },
            ParamKey { frame: 24, value: magnitude, ease: Ease::EaseIn },
        ]),
        frequency: frequency.into(),
        phase: 0.0.into(),
        speed: 2.0.into(),
        direction_deg: direction_deg.into(),
        axis: WaveAxis::Normal,
        falloff: 1.0.into(),
    })
}

/// Keys far apart so that frames 1 and 100 000 are both in-betweens.
fn scene(n: u32) -> Scene {
    Scene {
        name: format!("bench {n}"),
        cloth: Cloth::new((2.0, 2.0), (n, n)),
        keys: vec![key(0, n, 0.0), key(200_000, n, 0.3)],
        layers: vec![
            Layer::Sway(Sway {
                name: "sway".into(),
                enabled: true,
                weight: 1.0.into(),
                magnitude: 0.2.into(),
                direction: (1.0, 0.0, 0.0),
                speed: 1.0.into(),
                frequency: 0.5.into(),
                phase: 0.0.into(),
                falloff: 1.0.into(),
            }),
            wave("long", 0.05, 4.0, 0.0),
            wave("short", 0.01, 15.0, 30.0),
            Layer::Gusts(Gusts {
                name: "gusts".into(),
                enabled: true,
                weight: 1.0.into(),
                amplitude: 0.05.into(),
                scale: 0.5.into(),
                speed: 1.0.into(),
                direction: (1.0, 0.0, 0.2),
                turbulence: 0.3.into(),
                octaves: 2,
                seed: 1,
                falloff: 1.0.into(),
            }),
        ],
        ..Scene::default()
    }
}

fn evaluate(c: &mut Criterion) {
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(100).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(6));
    for n in [128u32, 256] {
        let scene = scene(n);
        let mut built = None;
        for frame in [1i32, 100_000] {
            let t_secs = f64::from(frame) / scene.timeline.fps;
            let id = BenchmarkId::new(format!("{n}x{n}"), format!("frame {frame}"));
            group.bench_with_input(id, &t_secs, |b, &t_secs| {
                let (evaluator, mesh) = built_on_first_use(&mut built, &scene);
                b.iter(|| {
                    evaluator.evaluate_into(&scene, black_box(t_secs), EvaluateOptions::default(), mesh);
                    black_box(&*mesh);
                })
            });
        }
    }
    group.finish();
}

/// Frame 100 000 against frame 1, timed in alternation so that the machine's
/// drift (other work, clock changes) hits both alike: the median of each and
/// their ratio, which must stay within 10% of 1. The stretch limit is off:
/// the two frames differ in what the layers ask of the cloth (the waves ramp
/// up over the first second), and the limit's cost follows that, not t.
fn late_frame_ratio(_: &mut Criterion) {
    let mut scene = scene(128);
    scene.cloth.stretch_limit = 0.0;
    let mut evaluator = Evaluator::new();
    let mut mesh = evaluator.evaluate(&scene, 0.0);
    let mut time = |frame: i32| {
        let t_secs = f64::from(frame) / scene.timeline.fps;
        let start = std::time::Instant::now();
        for _ in 0..10 {
            evaluator.evaluate_into(&scene, black_box(t_secs), EvaluateOptions::default(), &mut mesh);
        }
        start.elapsed().as_secs_f64() / 10.0
    };
    let (mut early, mut late) = (Vec::new(), Vec::new());
    for _ in 0..200 {
        early.push(time(1));
        late.push(time(100_000));
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (early, late) = (median(&mut early), median(&mut late));
    println!(
        "evaluate/128x128 interleaved: frame 1 {:.3} ms, frame 100000 {:.3} ms, ratio {:.3}",
        early * 1e3,
        late * 1e3,
        late / early
    );
}

/// Among colliders: the same 128² cloth with three primitive
/// colliders it touches (a ball under its middle, a capsule across it and
/// the ground), frame 1 and frame 100 000.
fn with_colliders(c: &mut Criterion) {
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(50).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(4));
    let mut scene = scene(128);
    let colliders = "[Sphere((center: (0.0, 0.55, 0.0), radius: 0.35)), \
                     Capsule((a: (-1.0, 0.75, 0.5), b: (1.0, 0.75, 0.5), radius: 0.05)), Ground((height: 0.0))]";
    scene.colliders = ron::from_str(colliders).expect("three colliders");
    bench_frames_1_and_100000(&mut group, "128x128 three colliders", &scene);
    group.finish();
}

/// Frames 1 and 100 000 of `scene` under `name`, its rest shapes built first.
fn bench_frames_1_and_100000(group: &mut criterion::BenchmarkGroup<'_, WallTime>, name: &str, scene: &Scene) {
    let mut built = None;
    for frame in [1i32, 100_000] {
        let t_secs = f64::from(frame) / scene.timeline.fps;
        group.bench_with_input(BenchmarkId::new(name, format!("frame {frame}")), &t_secs, |b, &t_secs| {
            let (evaluator, mesh) = built_on_first_use(&mut built, scene);
            b.iter(|| {
                evaluator.evaluate_into(scene, black_box(t_secs), EvaluateOptions::default(), mesh);
                black_box(&*mesh);
            })
        });
    }
}

/// An evaluator with `scene`'s rest shapes built, and a mesh it wrote, made
/// on the first call: criterion calls a bench's routine only when the bench
/// passes the command line's filter, so a filtered run skips the seconds
/// that relaxing among colliders takes.
fn built_on_first_use<'a>(
    built: &'a mut Option<(Evaluator, Mesh)>,
    scene: &Scene,
) -> (&'a mut Evaluator, &'a mut Mesh) {
    let (evaluator, mesh) = built.get_or_insert_with(|| {
        let mut evaluator = Evaluator::new();
        let mesh = evaluator.evaluate(scene, 0.0);
        (evaluator, mesh)
    });
    (evaluator, mesh)
}

/// Over a mesh collider: the same 128² cloth over a 20 480-triangle ball
/// (a subdivided icosahedron, built here) where the primitive ball was.
fn with_a_mesh_collider(c: &mut Criterion) {
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(4));
    let mut scene = scene(128);
    let ball = "[Mesh((name: \"ball\", file: \"ball.obj\", center: (0.0, 0.55, 0.0), scale: 0.35))]";
    scene.colliders = ron::from_str(ball).expect("a mesh collider");
    let (vertices, triangles) = icosphere(5);
    let solid = drape::world::MeshSolid::new(&vertices, &triangles).expect("a solid ball");
    assert_eq!(solid.triangle_count(), 20_480);
    if let Some(drape::scene::Collider::Mesh(mesh)) = scene.colliders.first_mut() {
        mesh.solid = drape::scene::Loaded(Some(std::sync::Arc::new(solid)));
    }
    bench_frames_1_and_100000(&mut group, "128x128 20k-triangle mesh", &scene);
    group.finish();
}

/// A character: `scenes/cape.ron` at 64 × 64 (its pins
/// attached to the 10 072-vertex skinned walker's chest) with two layers (its
/// wave and a sway), every call the next frame of the walk, so each one
/// poses the character afresh; then the same with the walker a collider
/// (posing its solid every frame).
fn on_a_character(c: &mut Criterion) {
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(4));
    let cape = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cape.ron");
    let mut scene = drape::scene::load(&cape).expect("the bundled cape");
    scene.cloth.grid = (64, 64);
    for (pin, i) in scene.keys[0].pins.iter_mut().zip([0, 14, 32, 49, 63]) {
        pin.grid = (i, 0);
    }
    let sway = "Sway((name: \"breeze\", magnitude: 0.05, direction: (0.0, 0.0, -1.0), speed: 1.0, frequency: 0.5))";
    scene.layers.push(ron::from_str(sway).expect("a sway"));
    assert_eq!(scene.layers.len(), 2);
    for collider in [false, true] {
        scene.references[0].collider = collider;
        let name = if collider { "64x64 cape on a walker, a collider" } else { "64x64 cape on a walker" };
        let (mut built, mut frame) = (None, 0u32);
        group.bench_function(name, |b| {
            let (evaluator, mesh) = built_on_first_use(&mut built, &scene);
            b.iter(|| {
                frame = (frame + 1) % 48;
                let t_secs = f64::from(frame) / scene.timeline.fps;
                evaluator.evaluate_into(&scene, black_box(t_secs), EvaluateOptions::default(), mesh);
                black_box(&*mesh);
            })
        });
    }
    group.finish();
}

/// A unit sphere: an icosahedron split `levels` times (20 · 4^levels triangles), wound outwards.
fn icosphere(levels: u32) -> (Vec<glam::DVec3>, Vec<[u32; 3]>) {
    use glam::DVec3;
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut middles = std::collections::HashMap::new();
        let mut middle = |a: u32, b: u32, vertices: &mut Vec<DVec3>| {
            *middles.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) / 2.0).normalize());
                vertices.len() as u32 - 1
            })
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) =
                    (middle(a, b, &mut vertices), middle(b, c, &mut vertices), middle(c, a, &mut vertices));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    (vertices, faces)
}

criterion_group!(benches, evaluate, late_frame_ratio, with_colliders, with_a_mesh_collider, on_a_character);
criterion_main!(benches);
