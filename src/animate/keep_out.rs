//! Contact with the colliders, the last step of every frame: no free point
//! ends closer to a collider than its thickness.
//!
//! A point the layers carried into a collider leaves it on the side it came
//! in from: the path from where the point was before the layers (the blend
//! of the rest shapes, which rest outside) to where the layers put it is
//! followed to the surface, and the point slides on along the tangent plane
//! there ([`crate::world::push_out_along`]). Neighbours that went in
//! together come out together, onto one smooth surface, so a wave that dips
//! into a table top flattens on it instead of poking through its underside.
//! Pins stay where the animator put them, inside a collider or not; a pin
//! in one key only is being let go or caught, and keeps out like cloth.

use glam::DVec3;

use crate::mesh::PointArrays;
use crate::world::{Obstacle, Reach, push_out, push_out_along};

/// Where each point was when it was last found clear of every obstacle
/// (its coordinates' bits), so that asking again about a point nothing has
/// moved since costs nothing. Good for one frame's obstacles only:
/// [`ClearPoints::forget`] when they change.
#[derive(Clone, Debug, Default)]
pub struct ClearPoints {
    at: Vec<[u32; 3]>,
}

impl ClearPoints {
    /// Nothing is known clear (the obstacles changed).
    pub fn forget(&mut self) {
        self.at.clear();
    }

    fn is_clear(&self, k: usize, bits: [u32; 3]) -> bool {
        self.at.get(k) == Some(&bits)
    }

    fn set_clear(&mut self, k: usize, bits: [u32; 3], n: usize) {
        if self.at.len() != n {
            // NaN bits: no point's position, so nothing is known.
            self.at = vec![[u32::MAX; 3]; n];
        }
        self.at[k] = bits;
    }
}

/// Moves every point of `points` not `held` (pinned in both keys around
/// the frame) out of `obstacles`, the way it came from the same point of
/// `before` (equal lengths; an empty `before` means "from where it is").
/// Points outside every obstacle are left bit for bit as they are; `clear`
/// remembers them, and passes over those still where they were. Returns
/// whether any point moved.
pub fn keep_out(
    obstacles: &[Obstacle],
    held: &[bool],
    before: &PointArrays,
    clear: &mut ClearPoints,
    points: &mut PointArrays,
) -> bool {
    let n = points.len();
    if obstacles.is_empty() || n == 0 || held.len() != n {
        return false;
    }
    let Some((min, max)) = bounds(points) else { return false };
    // Only the obstacles the cloth can touch this frame.
    let near: Vec<Obstacle> = obstacles.iter().filter(|o| o.shape.may_reach(min, max, o.thickness)).cloned().collect();
    if near.is_empty() {
        return false;
    }
    let reach = Reach::of(&near);
    let mut moved = false;
    let has_before = before.len() == n;
    for (k, _) in held.iter().enumerate().filter(|(_, held)| !**held) {
        let bits = [points.x[k].to_bits(), points.y[k].to_bits(), points.z[k].to_bits()];
        if clear.is_clear(k, bits) {
            continue;
        }
        let p = DVec3::new(points.x[k].into(), points.y[k].into(), points.z[k].into());
        // Outside every obstacle's reach it stays, as pushing out would leave it.
        if !(0..near.len()).any(|i| reach.near(i, p)) {
            continue;
        }
        // Only points that end inside move: one the layers carry clean through
        // a thin collider within a frame is not caught (stopping every path at
        // the first surface, `slide_along`, tore cloth swung past a table's edge).
        let q = if has_before {
            let from = DVec3::new(before.x[k].into(), before.y[k].into(), before.z[k].into());
            push_out_along(&near, from, p)
        } else {
            push_out(&near, p)
        };
        if q == p {
            clear.set_clear(k, bits, n);
            continue;
        }
        // Rounded to f32 the point may land a hair inside; nudge it out by a micrometre.
        let q = q + (q - p).normalize_or_zero() * 1e-6;
        (points.x[k], points.y[k], points.z[k]) = (q.x as f32, q.y as f32, q.z as f32);
        moved = true;
    }
    moved
}

/// The box around the finite points, if any.
fn bounds(points: &PointArrays) -> Option<(DVec3, DVec3)> {
    let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for k in 0..points.len() {
        let p = DVec3::new(points.x[k].into(), points.y[k].into(), points.z[k].into());
        if p.is_finite() {
            min = min.min(p);
            max = max.max(p);
        }
    }
    (min.x <= max.x).then_some((min, max))
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, Vec3};

    use super::*;
    use crate::world::ColliderShape;

    fn table() -> Obstacle {
        let shape = ColliderShape::Box {
            center: DVec3::new(0.0, 0.72, 0.0),
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: DMat3::IDENTITY,
        };
        Obstacle { shape, thickness: 0.003 }
    }

    #[test]
    fn a_row_dipped_into_a_table_comes_back_onto_its_top_and_pins_stay() {
        let before: Vec<Vec3> = (0..9).map(|i| Vec3::new(i as f32 * 0.1 - 0.4, 0.745, 0.0)).collect();
        // A wave dips the row: the middle points sink past the top's middle plane.
        let after: Vec<Vec3> =
            before.iter().enumerate().map(|(i, p)| *p - Vec3::Y * 0.04 * (i as f32 * 0.39).sin()).collect();
        let mut points = PointArrays::from_vec3s(&after);
        let mut held = vec![false; 9];
        held[0] = true;
        points.y[0] = 0.7; // a pin inside the table stays there
        keep_out(&[table()], &held, &PointArrays::from_vec3s(&before), &mut ClearPoints::default(), &mut points);
        assert_eq!(points.y[0], 0.7);
        for (k, dipped) in after.iter().enumerate().skip(1) {
            let p = points.get(k);
            assert!(table().shape.distance(p.as_dvec3()) >= 0.003 - 1e-6, "point {k} at {p}");
            assert!(p.y > 0.74, "point {k} is on the top, not under it: {p}");
            assert!((p.x - dipped.x).abs() < 1e-6, "slid straight up: {p}");
        }
    }

    #[test]
    fn points_known_clear_are_passed_over_with_the_same_answer() {
        let row =
            |dip: f32| -> Vec<Vec3> { (0..9).map(|i| Vec3::new(i as f32 * 0.1 - 0.4, 0.745 - dip, 0.0)).collect() };
        let before = PointArrays::from_vec3s(&row(0.0));
        let mut clear = ClearPoints::default();
        let mut points = PointArrays::from_vec3s(&row(0.0));
        assert!(!keep_out(&[table()], &[false; 9], &before, &mut clear, &mut points), "on the top, clear");
        assert!(clear.at.iter().all(|&bits| bits[0] != u32::MAX), "all remembered");
        // Moved into the top: not passed over, pushed out as a fresh call would.
        let mut dipped = PointArrays::from_vec3s(&row(0.01));
        let mut fresh = dipped.clone();
        assert!(keep_out(&[table()], &[false; 9], &before, &mut clear, &mut dipped));
        keep_out(&[table()], &[false; 9], &before, &mut ClearPoints::default(), &mut fresh);
        assert_eq!(dipped, fresh);
        clear.forget();
        assert!(clear.at.is_empty());
    }

    #[test]
    fn points_outside_are_untouched_and_no_obstacles_change_nothing() {
        let cloth: Vec<Vec3> = (0..4).map(|i| Vec3::new(i as f32, 2.0, 0.0)).collect();
        let mut points = PointArrays::from_vec3s(&cloth);
        let before = points.clone();
        keep_out(&[table()], &[false; 4], &PointArrays::default(), &mut ClearPoints::default(), &mut points);
        assert_eq!(points, before);
        keep_out(&[], &[false; 4], &PointArrays::default(), &mut ClearPoints::default(), &mut points);
        assert_eq!(points, before);
    }
}
