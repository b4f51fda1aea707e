//! What a framing holds: the cloth, and the references and colliders it
//! touches or is pinned to, so a cape is framed with the character wearing
//! it and a tablecloth with its table.

use glam::Vec3;

use crate::animate::colliders_at::shape_at;
use crate::animate::references_at::reference_at;
use crate::render::OrbitCamera;
use crate::render::camera::bounds;
use crate::scene::{Collider, Scene};

/// How near (metres, beyond the key's thickness) a collider's or a
/// reference's box must come to the cloth's box to count as touching it.
pub const TOUCH_MARGIN_M: f32 = 0.05;

/// The box round `cloth` (the cloth's points at `frame`) and what it
/// touches there ([`touched_bounds`]); `None` when the cloth has no finite point.
pub fn cloth_and_touched(scene: &Scene, frame: f64, cloth: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let (min, max) = bounds(cloth)?;
    Some(match touched_bounds(scene, frame, cloth) {
        Some((lo, hi)) => (min.min(lo), max.max(hi)),
        None => (min, max),
    })
}

/// Whether `camera` shows, in a picture of `aspect`, every point of the
/// cloth (`cloth`, its points at `frame`) and the box of what it touches
/// there ([`touched_bounds`]) whole: a saved view that does is kept on
/// opening. The cloth's own points are judged, not its box, whose corners a
/// view showing all of a hanging bowl of cloth may leave out.
pub fn view_holds(camera: &OrbitCamera, scene: &Scene, frame: f64, cloth: &[Vec3], aspect: f32) -> bool {
    let sees = |p: Vec3| camera.sees_any_of([p], aspect);
    cloth.iter().filter(|p| p.is_finite()).all(|&p| sees(p))
        && touched_bounds(scene, frame, cloth).is_none_or(|touched| corners(touched).into_iter().all(sees))
}

/// The box round every visible reference and enabled collider of `scene`
/// that the cloth (its points `cloth` at `frame`) touches there: a
/// reference with a pin attached to it or that the cloth follows, or whose
/// box comes within [`TOUCH_MARGIN_M`] (plus the key's thickness) of the
/// cloth's; likewise a collider. The ground, endless, is never part of it.
/// `None` when the cloth touches nothing or has no finite point.
pub fn touched_bounds(scene: &Scene, frame: f64, cloth: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let (cloth_min, cloth_max) = bounds(cloth)?;
    let thickness_m = if scene.keys.is_empty() { 0.0 } else { scene.key_in_effect(frame).thickness };
    let reach = Vec3::splat(TOUCH_MARGIN_M + thickness_m.max(0.0) as f32);
    let (near_min, near_max) = (cloth_min - reach, cloth_max + reach);
    let overlaps = |(lo, hi): (Vec3, Vec3)| lo.cmple(near_max).all() && hi.cmpge(near_min).all();
    let mut found: Option<(Vec3, Vec3)> = None;
    let mut add = |(lo, hi): (Vec3, Vec3)| {
        found = Some(found.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
    };
    for (index, reference) in scene.references.iter().enumerate() {
        let Some(posed) = reference_at(scene, index, frame).filter(|_| reference.visible) else { continue };
        let positions: Vec<Vec3> =
            posed.meshes().iter().flat_map(|m| m.positions.iter().map(|p| p.as_vec3())).collect();
        let Some(box_m) = bounds(&positions) else { continue };
        if holds_cloth(scene, &reference.name) || overlaps(box_m) {
            add(box_m);
        }
    }
    for collider in scene.colliders.iter().filter(|c| c.enabled() && !matches!(c, Collider::Ground(_))) {
        let Some(shape) = shape_at(collider, frame) else { continue };
        let (lo, hi) = shape.bounds();
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        let box_m = (lo.as_vec3(), hi.as_vec3());
        if overlaps(box_m) {
            add(box_m);
        }
    }
    found
}

/// Whether the cloth follows reference `name` or a pin of any key is attached to it.
fn holds_cloth(scene: &Scene, name: &str) -> bool {
    let follows = scene.follow.as_ref().is_some_and(|f| f.reference == name);
    let pinned =
        scene.keys.iter().flat_map(|k| &k.pins).any(|p| p.attach.as_ref().is_some_and(|a| a.reference() == name));
    follows || pinned
}

/// The box's eight corners.
pub fn corners((min, max): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { min.x } else { max.x },
            if k & 2 == 0 { min.y } else { max.y },
            if k & 4 == 0 { min.z } else { max.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cloth hanging as a bowl from four corners at 1 m.
    fn bowl() -> Vec<Vec3> {
        (0..=20)
            .flat_map(|j| {
                (0..=20).map(move |i| {
                    let (x, z) = (i as f32 / 20.0 - 0.5, j as f32 / 20.0 - 0.5);
                    Vec3::new(x, 1.0 - 0.6 * (0.25 - x * x) * (0.25 - z * z) / 0.0625, z)
                })
            })
            .collect()
    }

    /// A view close enough to leave out the corners of the bowl's box while
    /// it shows every point of the cloth holds it; a little closer, it cuts
    /// off part of the cloth and does not.
    #[test]
    fn a_view_of_the_whole_cloth_holds_it_though_its_box_is_cut() {
        let scene = Scene::default();
        let cloth = bowl();
        let (min, max) = bounds(&cloth).unwrap();
        let aspect = 1.34;
        let mut camera = OrbitCamera::framing(min, max, aspect);
        camera.pitch_deg = 35.0;
        let sees_all = |camera: &OrbitCamera| cloth.iter().all(|&p| camera.sees_any_of([p], aspect));
        let sees_box = |camera: &OrbitCamera| corners((min, max)).into_iter().all(|c| camera.sees_any_of([c], aspect));
        while sees_box(&camera) {
            camera.distance_m *= 0.99;
        }
        assert!(sees_all(&camera), "the test's view must show the cloth and cut its box");
        assert!(view_holds(&camera, &scene, 0.0, &cloth, aspect));
        while sees_all(&camera) {
            camera.distance_m *= 0.99;
        }
        assert!(!view_holds(&camera, &scene, 0.0, &cloth, aspect));
    }
}
