//! A scene's colliders at a frame: every animated number sampled, as the
//! geometry `world` measures against.

use glam::DVec3;

use super::posed_solids::PosedSolids;
use super::references_at::reference_at;
use super::track::{sample, sample_vec3};
use crate::scene::{Collider, Param, ParamVec3, Scene};
use crate::world::{ColliderShape, Obstacle};

/// The enabled colliders of `scene` at `frame`, each with the thickness the
/// cloth keeps from it: its own, else that of the key in effect. Sizes
/// that an overshooting easing takes below 0 read as 0; thicknesses too. A
/// mesh collider whose file has not been read (a scene parsed from text,
/// without its folder) is left out. References marked as colliders come
/// last, posed at `frame` ([`reference_obstacles`]), their solids from
/// `solids` when that pose was built lately.
pub fn obstacles_at(scene: &Scene, frame: f64, solids: &PosedSolids) -> Vec<Obstacle> {
    let colliding_references = scene.references.iter().any(|r| r.collider);
    if (scene.colliders.is_empty() && !colliding_references) || scene.keys.is_empty() {
        return Vec::new();
    }
    let key_thickness = scene.key_in_effect(frame).thickness;
    let mut obstacles: Vec<Obstacle> = scene
        .colliders
        .iter()
        .filter(|collider| collider.enabled())
        .filter_map(|collider| {
            let thickness = collider.thickness().map_or(key_thickness, |t| sample(t, frame));
            Some(Obstacle { shape: shape_at(collider, frame)?, thickness: thickness.max(0.0) })
        })
        .collect();
    if colliding_references {
        obstacles.extend(reference_obstacles(scene, frame, key_thickness, solids));
    }
    obstacles
}

/// The enabled colliders of `scene` that never move ([`Collider::is_still`]),
/// each with the thickness the cloth keeps from it: its own, else
/// `key_thickness`. References are left out: they move with their poses.
pub fn still_obstacles(scene: &Scene, key_thickness: f64) -> Vec<Obstacle> {
    scene
        .colliders
        .iter()
        .filter(|collider| collider.enabled() && collider.is_still())
        .filter_map(|collider| {
            let thickness = collider.thickness().map_or(key_thickness, |t| sample(t, 0.0));
            Some(Obstacle { shape: shape_at(collider, 0.0)?, thickness: thickness.max(0.0) })
        })
        .collect()
}

/// The references of `scene` that keep the cloth out, posed at `frame`,
/// each with the thickness the cloth keeps from it: its own, else
/// `key_thickness`. One solid per reference, of all its meshes, from
/// `solids` when that pose was built lately.
pub fn reference_obstacles(scene: &Scene, frame: f64, key_thickness: f64, solids: &PosedSolids) -> Vec<Obstacle> {
    let mut obstacles = Vec::new();
    for (index, reference) in scene.references.iter().enumerate() {
        if !reference.collider {
            continue;
        }
        let Some(solid) = reference_at(scene, index, frame).and_then(|posed| solids.solid(&posed)) else { continue };
        let thickness = reference.thickness.as_ref().map_or(key_thickness, |t| sample(t, frame)).max(0.0);
        let shape =
            ColliderShape::Mesh { solid, center: DVec3::ZERO, world_from_local: glam::DMat3::IDENTITY, scale: 1.0 };
        obstacles.push(Obstacle { shape, thickness });
    }
    obstacles
}

/// One collider's solid at `frame`; `None` for a mesh not read yet. A mesh's
/// scale that easing takes to 0 or below reads as a micrometre.
pub fn shape_at(collider: &Collider, frame: f64) -> Option<ColliderShape> {
    let at = |param: &Param| sample(param, frame);
    let length = |param: &Param| sample(param, frame).max(0.0);
    let vector = |v: &ParamVec3| sample_vec3(v, frame);
    let rotation = |v: &ParamVec3| ColliderShape::rotation_from_deg(at(&v.0), at(&v.1), at(&v.2));
    Some(match collider {
        Collider::Mesh(m) => ColliderShape::Mesh {
            solid: m.solid.0.clone()?,
            center: vector(&m.center),
            world_from_local: rotation(&m.rotation_deg),
            scale: at(&m.scale).max(1e-6),
        },
        Collider::Ground(g) => ColliderShape::Ground { height: at(&g.height) },
        Collider::Box(b) => ColliderShape::Box {
            center: vector(&b.center),
            half: vector(&b.size).max(DVec3::ZERO) * 0.5,
            world_from_local: rotation(&b.rotation_deg),
        },
        Collider::Cylinder(c) => ColliderShape::Cylinder {
            center: vector(&c.center),
            radius: length(&c.radius),
            half_height: length(&c.height) * 0.5,
            world_from_local: rotation(&c.rotation_deg),
        },
        Collider::Sphere(s) => ColliderShape::Sphere { center: vector(&s.center), radius: length(&s.radius) },
        Collider::Capsule(c) => ColliderShape::Capsule { a: vector(&c.a), b: vector(&c.b), radius: length(&c.radius) },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Ease, ParamKey};

    #[test]
    fn a_keyed_centre_moves_and_disabled_colliders_are_left_out() {
        let Some(mut ball) = Collider::with_start_values("Sphere") else { panic!("a sphere") };
        if let Collider::Sphere(s) = &mut ball {
            s.center.0 = Param::Keys(vec![
                ParamKey { frame: 0, value: 0.0, ease: Ease::Linear },
                ParamKey { frame: 10, value: 1.0, ease: Ease::Linear },
            ]);
        }
        let text = "(version: 1, cloth: (size: (1.0, 1.0), grid: (9, 9)), keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])])";
        let Ok(mut scene) = ron::from_str::<Scene>(text) else { panic!("a scene") };
        scene.colliders = vec![ball.clone(), ball];
        *scene.colliders[1].enabled_mut() = false;
        let obstacles = obstacles_at(&scene, 5.0, &PosedSolids::new());
        assert_eq!(obstacles.len(), 1);
        let ColliderShape::Sphere { center, radius } = obstacles[0].shape else { panic!("a sphere") };
        assert_eq!((center, radius), (DVec3::new(0.5, 1.0, 0.0), 0.3));
        assert_eq!(obstacles[0].thickness, scene.keys[0].thickness, "the key's thickness");
    }
}
