//! Colliders end to end: rest shapes lie on them and every animated frame
//! keeps out of them, with the cloth whole (no edge past 1.5 × its rest
//! length), for a table top, a ball and a round table.

use drape::animate::{Evaluator, colliders_at::obstacles_at};
use drape::scene::{self, Scene};
use glam::Vec3;

/// A 0.9 × 0.7 m cloth on a 19 × 15 grid pinned near the middle of a top at
/// `top_m`, with a wave and a sway that push it about, and `colliders`.
fn scene_with(pins_y_m: f64, colliders: &str) -> Scene {
    let text = format!(
        "(
    version: 1,
    cloth: (size: (0.9, 0.7), grid: (19, 15)),
    timeline: (fps: 24.0, start: 0, end: 120),
    keys: [
        (frame: 0, pins: [
            (grid: (6, 5), pos: (-0.15, {pins_y_m}, -0.1)),
            (grid: (12, 5), pos: (0.15, {pins_y_m}, -0.1)),
            (grid: (6, 9), pos: (-0.15, {pins_y_m}, 0.1)),
            (grid: (12, 9), pos: (0.15, {pins_y_m}, 0.1)),
        ], elasticity: 1.02),
    ],
    layers: [
        Wave((name: \"ripple\", magnitude: 0.04, frequency: 14.0, speed: 4.0)),
        Sway((name: \"breeze\", magnitude: 0.12, direction: (1.0, -0.5, 0.3), frequency: 0.5)),
    ],
    colliders: [{colliders}],
)"
    );
    match scene::parse(&text, "test scene") {
        Ok(scene) => scene,
        Err(error) => panic!("{error}"),
    }
}

/// Every frame 0..=120: no vertex nearer a collider than its thickness
/// (less 0.5 mm) and no edge longer than 1.5 × its rest length.
fn assert_kept_out_and_whole(scene: &Scene) {
    let (cols, rows) = (scene.cloth.cols(), scene.cloth.rows());
    let rest = (scene.cloth.spacing_u_m() * 1.02, scene.cloth.spacing_v_m() * 1.02);
    let mut evaluator = Evaluator::new();
    for frame in 0..=120 {
        let mesh = evaluator.evaluate_frame(scene, f64::from(frame));
        let obstacles = obstacles_at(scene, f64::from(frame));
        for (k, p) in mesh.positions.iter().enumerate() {
            for obstacle in &obstacles {
                let distance = obstacle.shape.distance(p.as_dvec3());
                assert!(
                    distance >= obstacle.thickness - 5e-4,
                    "frame {frame}: vertex {k} at {p} is {:.2} mm from {:?}",
                    distance * 1e3,
                    obstacle.shape
                );
            }
        }
        let stretch = drape::animate::stretch_limit::longest_stretch(&mesh.positions, (cols, rows), rest.0, rest.1);
        assert!(stretch <= 1.5, "frame {frame}: an edge is {stretch:.2} × its rest length");
    }
}

#[test]
fn a_tablecloth_pinned_on_a_box_lies_on_it_in_every_frame() {
    let scene = scene_with(
        0.743,
        "Box((name: \"table\", center: (0.0, 0.72, 0.0), size: (0.6, 0.04, 0.4))), Ground((name: \"floor\"))",
    );
    assert_kept_out_and_whole(&scene);
    // The rest shape lies on the top and hangs over its sides: the cloth's
    // corners are below the top, outside the table.
    let mut evaluator = Evaluator::new();
    let shape = evaluator.key_shape(&scene, &scene.keys[0]);
    let corner = shape.positions[0];
    assert!(corner.y < 0.65, "the corner hangs down over the side: {corner}");
    let middle = shape.positions[7 * 19 + 9];
    // Slack between the pins may rise in a soft wrinkle, never sink into the top.
    assert!(middle.y > 0.74 && middle.y < 0.78, "the middle lies on the top: {middle}");
}

#[test]
fn a_cloth_pinned_on_a_ball_drapes_over_it_in_every_frame() {
    let scene = scene_with(1.0 + 0.3 + 0.003, "Sphere((name: \"ball\", center: (0.0, 1.0, 0.0), radius: 0.3))");
    assert_kept_out_and_whole(&scene);
}

#[test]
fn a_cloth_on_a_round_table_keeps_out_while_the_table_slides() {
    let scene = scene_with(
        0.743,
        "Cylinder((name: \"round table\", center: ([(frame: 0, value: 0.0), (frame: 120, value: 0.05)], 0.72, 0.0), \
         radius: 0.3, height: 0.04))",
    );
    assert_kept_out_and_whole(&scene);
}

#[test]
fn colliders_leave_a_scene_without_them_bit_for_bit_alone() {
    let with =
        scene_with(0.743, "Box((name: \"table\", center: (0.0, 0.72, 0.0), size: (0.6, 0.04, 0.4), enabled: false))");
    let without = scene_with(0.743, "");
    let (mut a, mut b) = (Evaluator::new(), Evaluator::new());
    for frame in [0.0, 17.0, 60.5] {
        let (ma, mb) = (a.evaluate_frame(&with, frame), b.evaluate_frame(&without, frame));
        let same = ma.positions.iter().zip(&mb.positions).all(|(p, q): (&Vec3, &Vec3)| p.to_array() == q.to_array());
        assert!(same, "frame {frame}: a disabled collider changed the cloth");
    }
}
