//! Framing a whole scene: the box its keys' rest shapes fill, and the camera
//! and ground that show it through the animation.

use glam::{Vec2, Vec3};

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
}

impl Framing {
    /// The scene's saved view if it has one; otherwise a camera framing all
    /// the keys, so the view holds still through the animation, for pictures
    /// of `aspect` (width / height). The ground lies under every key.
    /// When the cloth travels much farther than its own size (a flying carpet),
    /// a fixed view would show it tiny: the camera then keeps the framing of
    /// the largest single key and follows the cloth's centre ([`Framing::follow`]),
    /// the ground grid showing the travel.
    pub fn of_scene(evaluator: &mut Evaluator, scene: &Scene, aspect: f32) -> Framing {
        let (rest_min, rest_max) = scene_bounds(evaluator, scene);
        let (min, max) = padded((rest_min, rest_max));
        let key_extent_m = largest_key_extent(evaluator, scene);
        let follow = scene.view.is_none() && (max - min).max_element() > FOLLOW_TRAVEL_RATIO * key_extent_m;
        let ground_height_m = Ground::under(rest_min, rest_max).height_m;
        let (camera, mut ground) = if let Some(view) = &scene.view {
            (OrbitCamera::from_view(view), Ground::under(min, max))
        } else if follow {
            let half = Vec3::splat(key_extent_m * 0.5);
            let center = (min + max) * 0.5;
            let mut camera = OrbitCamera::framing(min, max, aspect);
            camera.frame_bounds(center - half, center + half, aspect);
            (camera, Ground::under(center - half, center + half))
        } else {
            (OrbitCamera::framing(min, max, aspect), Ground::under(min, max))
        };
        ground.height_m = ground_height_m;
        Framing { camera, ground, follow }
    }

    /// When following, centres the camera's target and the ground on `mesh`.
    pub fn follow(&mut self, mesh: &Mesh) {
        if self.follow
            && let Some((lo, hi)) = bounds(&mesh.positions)
        {
            let center = (lo + hi) * 0.5;
            self.camera.target = center;
            self.ground.center = Vec2::new(center.x, center.z);
        }
    }
}

/// The box holding every key's relaxed rest shape; `(0, 1)` when there is none.
pub fn scene_bounds(evaluator: &mut Evaluator, scene: &Scene) -> (Vec3, Vec3) {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for key in &scene.keys {
        let shape = evaluator.key_shape(&scene.cloth, key);
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

/// The largest side of any single key's rest shape box.
fn largest_key_extent(evaluator: &mut Evaluator, scene: &Scene) -> f32 {
    let mut extent_m: f32 = 0.0;
    for key in &scene.keys {
        if let Some((lo, hi)) = bounds(&evaluator.key_shape(&scene.cloth, key).positions) {
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
