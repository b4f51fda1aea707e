//! Framing a whole scene: the box its keys' rest shapes fill, and the camera
//! and ground that show it through the animation.

use glam::{Vec2, Vec3};

use super::framed::{corners, touched_bounds};
use crate::animate::Evaluator;
use crate::mesh::Mesh;
use crate::render::camera::bounds;
use crate::render::{Ground, OrbitCamera};
use crate::scene::Scene;

/// The camera follows the cloth when its keys span more than this many times the largest key's own size.
pub const FOLLOW_TRAVEL_RATIO: f32 = 2.5;

/// The camera and ground of a scene's pictures.
#[derive(Clone, Debug, PartialEq)]
pub struct Framing {
    pub camera: OrbitCamera,
    pub ground: Ground,
    /// Whether the camera and ground move with the cloth (see [`Framing::of_scene`]).
    pub follow: bool,
    /// While following, the camera's target minus the cloth's centre (m).
    follow_offset: Vec3,
}

impl Framing {
    /// The scene's saved view if it has one; otherwise a camera framing all
    /// the keys, so the view holds still through the animation, for pictures
    /// of `aspect` (width / height). What is framed is the cloth with the
    /// references and colliders it touches ([`framed_bounds`]): a cape with
    /// its wearer, head to feet. A saved view of a cloth that stays in place
    /// and cuts off part of that is widened to hold it all, keeping its
    /// angles (a travelling cloth's saved view frames part of its way on
    /// purpose and is kept). The ground lies under every key.
    /// When the cloth travels much farther than its own size (a flying carpet,
    /// see [`travels`]), a fixed view would show it tiny: the camera then keeps
    /// the framing of the largest single key and follows the cloth's centre
    /// ([`Framing::follow`]), the ground grid showing the travel. A saved view
    /// follows when its `follow` is set, keeping the offset from the cloth it
    /// had at its saved frame (the timeline's start when it has none).
    pub fn of_scene(evaluator: &mut Evaluator, scene: &Scene, aspect: f32) -> Framing {
        let (rest_min, rest_max) = scene_bounds(evaluator, scene);
        let framed = framed_bounds(evaluator, scene);
        let (min, max) = padded(framed);
        let key_extent_m = largest_key_extent(evaluator, scene);
        let ground_height_m = Ground::under(rest_min, rest_max).height_m;
        // The cloth's own travel: a character it is pinned to makes it no traveller.
        let (cloth_min, cloth_max) = padded((rest_min, rest_max));
        let travelling = (cloth_max - cloth_min).max_element() > FOLLOW_TRAVEL_RATIO * key_extent_m;
        let mut follow_offset = Vec3::ZERO;
        let (camera, mut ground, follow) = if let Some(view) = &scene.view {
            let mut camera = OrbitCamera::from_view(view);
            if view.follow {
                let frame = view.frame.unwrap_or(scene.timeline.start).clamp(scene.timeline.start, scene.timeline.end);
                let mesh = evaluator.evaluate_frame(scene, f64::from(frame));
                if let Some((lo, hi)) = bounds(&mesh.positions) {
                    follow_offset = camera.target - (lo + hi) * 0.5;
                }
            } else if !travelling && !corners(framed).into_iter().all(|corner| camera.sees_any_of([corner], aspect)) {
                camera.frame_bounds(framed.0, framed.1, aspect);
            }
            (camera, Ground::under(min, max), view.follow)
        } else if travelling {
            let half = Vec3::splat(key_extent_m * 0.5);
            let center = (min + max) * 0.5;
            let mut camera = OrbitCamera::framing(min, max, aspect);
            camera.frame_bounds(center - half, center + half, aspect);
            (camera, Ground::under(center - half, center + half), true)
        } else {
            (OrbitCamera::framing(min, max, aspect), Ground::under(min, max), false)
        };
        ground.height_m = ground_height_m;
        Framing { camera, ground, follow, follow_offset }
    }

    /// When following, keeps the camera's target at its offset from `mesh`'s
    /// centre and centres the ground under it.
    pub fn follow(&mut self, mesh: &Mesh) {
        if self.follow
            && let Some((lo, hi)) = bounds(&mesh.positions)
        {
            let center = (lo + hi) * 0.5;
            self.camera.target = center + self.follow_offset;
            self.ground.center = Vec2::new(center.x, center.z);
        }
    }
}

/// Whether the cloth travels much farther than its own size: its keys'
/// rest shapes span more than [`FOLLOW_TRAVEL_RATIO`] times the largest
/// key's own size. Views without a saved camera follow such a cloth.
pub fn travels(evaluator: &mut Evaluator, scene: &Scene) -> bool {
    let (min, max) = padded(scene_bounds(evaluator, scene));
    (max - min).max_element() > FOLLOW_TRAVEL_RATIO * largest_key_extent(evaluator, scene)
}

/// The box holding every key's relaxed rest shape; `(0, 1)` when there is none.
pub fn scene_bounds(evaluator: &mut Evaluator, scene: &Scene) -> (Vec3, Vec3) {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for key in &scene.keys {
        let shape = evaluator.key_shape(scene, key);
        if let Some((lo, hi)) = bounds(&shape.positions) {
            min = min.min(lo);
            max = max.max(hi);
        }
    }
    if !(min.is_finite() && max.is_finite()) {
        return (Vec3::ZERO, Vec3::ONE);
    }
    (min, max)
}

/// The box round every key's rest shape ([`scene_bounds`]) and what the
/// cloth touches ([`touched_bounds`]) at each key, from its rest shape,
/// and at the timeline's ends.
pub fn framed_bounds(evaluator: &mut Evaluator, scene: &Scene) -> (Vec3, Vec3) {
    let (mut min, mut max) = scene_bounds(evaluator, scene);
    if scene.references.is_empty() && scene.colliders.is_empty() {
        return (min, max);
    }
    let mut add = |touched: Option<(Vec3, Vec3)>| {
        if let Some((lo, hi)) = touched {
            min = min.min(lo);
            max = max.max(hi);
        }
    };
    for key in &scene.keys {
        let shape = evaluator.key_shape(scene, key);
        add(touched_bounds(scene, f64::from(key.frame), &shape.positions));
    }
    for frame in [scene.timeline.start, scene.timeline.end] {
        let mesh = evaluator.evaluate_frame(scene, f64::from(frame));
        add(touched_bounds(scene, f64::from(frame), &mesh.positions));
    }
    (min, max)
}

/// The largest side of any single key's rest shape box.
fn largest_key_extent(evaluator: &mut Evaluator, scene: &Scene) -> f32 {
    let mut extent_m: f32 = 0.0;
    for key in &scene.keys {
        if let Some((lo, hi)) = bounds(&evaluator.key_shape(scene, key).positions) {
            extent_m = extent_m.max((hi - lo).max_element());
        }
    }
    extent_m.max(0.1)
}

/// `min..max` widened by 10% of its largest side all round: room for the layers' motion.
fn padded((min, max): (Vec3, Vec3)) -> (Vec3, Vec3) {
    let margin = Vec3::splat((max - min).max_element() * 0.1);
    (min - margin, max + margin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::references_at::reference_at;
    use crate::scene;

    fn carpet() -> Scene {
        scene::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/magic_carpet.ron"))).unwrap()
    }

    fn centre(mesh: &Mesh) -> Vec3 {
        let (lo, hi) = bounds(&mesh.positions).unwrap();
        (lo + hi) * 0.5
    }

    /// The cape's saved view, made for the editor's window, cuts off the
    /// walker's feet: a render widens it to hold him, head to feet, at
    /// every frame, from the same angles.
    #[test]
    fn a_saved_view_is_widened_to_hold_what_the_cloth_is_pinned_to() {
        let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cape.ron"));
        let scene = scene::load(path).unwrap();
        let view = scene.view.clone().expect("the cape has a saved view");
        let mut evaluator = Evaluator::new();
        let framing = Framing::of_scene(&mut evaluator, &scene, 16.0 / 9.0);
        assert_eq!((framing.camera.yaw_deg, framing.camera.pitch_deg), (view.yaw_deg as f32, view.pitch_deg as f32));
        for frame in (0..=48).step_by(3) {
            let posed = reference_at(&scene, 0, f64::from(frame)).expect("the walker was read");
            let points: Vec<Vec3> =
                posed.meshes().iter().flat_map(|m| m.positions.iter().map(|p| p.as_vec3())).collect();
            let walker = bounds(&points).unwrap();
            for corner in corners(walker) {
                assert!(framing.camera.sees_any_of([corner], 16.0 / 9.0), "frame {frame}: {corner} cut off");
            }
        }
    }

    #[test]
    fn a_travelling_cloth_without_a_view_is_followed_and_a_still_one_is_not() {
        let mut evaluator = Evaluator::new();
        let mut scene = carpet();
        assert!(travels(&mut evaluator, &scene));
        assert!(Framing::of_scene(&mut evaluator, &scene, 1.5).follow);
        scene.keys.truncate(1);
        assert!(!travels(&mut evaluator, &scene));
        assert!(!Framing::of_scene(&mut evaluator, &scene, 1.5).follow);
    }

    #[test]
    fn a_saved_view_that_follows_keeps_its_offset_from_the_cloth() {
        let mut evaluator = Evaluator::new();
        let mut scene = carpet();
        let target = Vec3::new(0.3, 1.0, -0.2);
        let view = scene::View {
            target: (0.3, 1.0, -0.2),
            yaw_deg: 40.0,
            pitch_deg: 15.0,
            distance_m: 4.0,
            fov_y_deg: 35.0,
            frame: Some(36),
            follow: true,
            through_camera: false,
        };
        scene.view = Some(view.clone());
        let mut framing = Framing::of_scene(&mut evaluator, &scene, 1.5);
        assert!(framing.follow);
        let at_36 = evaluator.evaluate_frame(&scene, 36.0);
        framing.follow(&at_36);
        assert!(framing.camera.target.distance(target) < 1e-5, "{}", framing.camera.target);
        let at_100 = evaluator.evaluate_frame(&scene, 100.0);
        framing.follow(&at_100);
        let moved = centre(&at_100) - centre(&at_36);
        assert!(moved.length() > 1.0, "the carpet flies");
        assert!(framing.camera.target.distance(target + moved) < 1e-4);
        assert_eq!((framing.camera.yaw_deg, framing.camera.pitch_deg), (40.0, 15.0));

        // Not following: the saved camera stays put.
        scene.view = Some(scene::View { follow: false, ..view });
        let mut framing = Framing::of_scene(&mut evaluator, &scene, 1.5);
        framing.follow(&at_100);
        assert_eq!(framing.camera.target, target);
    }
}
