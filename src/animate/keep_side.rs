//! Bodies that move through the cloth push it aside instead of passing
//! through it. The side of a moving collider a point belongs on is the side
//! it had at the nearer key, carried with the collider: the path from the
//! point glued to the collider since that key to where the frame puts it
//! must not pass through the collider, and where it would, the point stops
//! on the near side. No history, so a frame stays a pure function of the
//! scene and the time.

use super::blend::Segment;
use super::colliders_at::shape_at;
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::Scene;
use crate::world::{ColliderShape, Obstacle, carried_with, slide_along};

/// The key whose sides a frame in `segment` keeps: the nearer one.
pub fn side_key(segment: Segment) -> usize {
    match segment {
        Segment::Hold(index) => index,
        Segment::Between { from, eased } => {
            if eased < 0.5 {
                from
            } else {
                from + 1
            }
        }
    }
}

/// A collider that moved rigidly since the side key: where it was then,
/// and the obstacle it is now.
pub struct Moved {
    then: ColliderShape,
    now: [Obstacle; 1],
}

/// The enabled colliders of `scene` that are somewhere else at `frame`
/// than at key `key`, and moved there rigidly ([`carried_with`]).
pub fn moved_since_key(scene: &Scene, key: usize, frame: f64) -> Vec<Moved> {
    let Some(key_frame) = scene.keys.get(key).map(|k| f64::from(k.frame)) else { return Vec::new() };
    if key_frame == frame {
        return Vec::new();
    }
    let thickness = scene.key_in_effect(frame).thickness;
    let moved = scene.colliders.iter().filter(|c| c.enabled() && !c.is_still()).filter_map(|collider| {
        let (then, now) = (shape_at(collider, key_frame)?, shape_at(collider, frame)?);
        carried_with(&then, &now, glam::DVec3::ZERO)?;
        let keep = collider.thickness().map_or(thickness, |t| sample(t, frame)).max(0.0);
        (then != now).then(|| Moved { then, now: [Obstacle { shape: now, thickness: keep }] })
    });
    moved.collect()
}

/// Moves every point of `points` not `held` that a `moved` collider has
/// passed through since the side key (whose rest shape is `key_points`)
/// back to the collider's side it had at the key (see the module doc).
/// Returns whether any point moved.
pub fn keep_sides(moved: &[Moved], key_points: &PointArrays, held: &[bool], points: &mut PointArrays) -> bool {
    let n = points.len();
    if moved.is_empty() || key_points.len() != n || held.len() != n {
        return false;
    }
    let mut any = false;
    for Moved { then, now } in moved {
        let [Obstacle { shape, thickness }] = now;
        for k in (0..n).filter(|&k| !held[k]) {
            let p = points.get(k).as_dvec3();
            let Some(glued) = carried_with(then, shape, key_points.get(k).as_dvec3()) else { break };
            // The distance is 1-Lipschitz: a path shorter than the gap cannot reach the collider.
            let gap = shape.distance(p) - thickness;
            if !glued.is_finite() || gap > glued.distance(p) {
                continue;
            }
            let q = slide_along(now, glued, p);
            if q != p && q.is_finite() {
                // Rounded to f32 the point may land a hair inside; nudge it out by a micrometre.
                let q = q + (q - p).normalize_or_zero() * 1e-6;
                points.set(k, q.as_vec3());
                any = true;
            }
        }
    }
    any
}
