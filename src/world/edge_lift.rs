//! Keeping a straight edge between two cloth points out of a collider: the
//! places along it that come nearer than the thickness are lifted to it,
//! each by moving the edge's ends.

use glam::DVec3;

use super::Obstacle;

/// Places along an edge where contact is kept, as shares of its length
/// from `a`: a straight edge between points resting either side of a
/// table's rim passes closest to the rim anywhere along it, not only at its
/// middle (kept at the middle alone, edges of a 33² tablecloth cut a round
/// table's rim by up to 6 mm at a quarter of their length).
pub const EDGE_SHARES: [f64; 5] = [1.0 / 6.0, 2.0 / 6.0, 0.5, 4.0 / 6.0, 5.0 / 6.0];

/// How far past what is kept an edge's bound must lie for its places to go
/// unmeasured: far above rounding, far below any push.
const CLEAR_MARGIN_M: f64 = 1e-9;

/// Whether every place of the edge `a`–`b` surely keeps farther than
/// `keep_m` from `obstacle`, by one test at its middle: the distance
/// changes no faster than the place moves.
pub fn edge_surely_clear(obstacle: &Obstacle, a: DVec3, b: DVec3, keep_m: f64) -> bool {
    let (first, last) = (EDGE_SHARES[0], EDGE_SHARES[EDGE_SHARES.len() - 1]);
    let way_m = a.distance(b) * (0.5 - first).max(last - 0.5);
    obstacle.shape.keeps_clear(a.lerp(b, 0.5), keep_m + CLEAR_MARGIN_M + way_m)
}

/// The moves of the ends `a` and `b` that carry the edge's place at share
/// `t` out to `obstacle`'s thickness, if that place is nearer than
/// `keep_m`: each end by its share of the place (the position-based rule
/// for a point between two: the nearer end moves more).
pub fn edge_place_lift(obstacle: &Obstacle, a: DVec3, b: DVec3, t: f64, keep_m: f64) -> Option<(DVec3, DVec3)> {
    let s = obstacle.shape.surface_point(a.lerp(b, t));
    if !(s.distance < keep_m) {
        return None;
    }
    let lift = s.outward * ((obstacle.thickness - s.distance) / ((1.0 - t) * (1.0 - t) + t * t));
    Some((lift * (1.0 - t), lift * t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::ColliderShape;

    #[test]
    fn a_chord_through_a_ball_is_lifted_to_the_thickness_at_its_place() {
        let ball = Obstacle { shape: ColliderShape::Sphere { center: DVec3::ZERO, radius: 1.0 }, thickness: 0.01 };
        let (a, b) = (DVec3::new(-0.3, 0.99, 0.0), DVec3::new(0.3, 0.99, 0.0));
        assert!(!edge_surely_clear(&ball, a, b, ball.thickness));
        let Some((lift_a, lift_b)) = edge_place_lift(&ball, a, b, 0.5, ball.thickness) else { panic!("inside") };
        let middle = (a + lift_a).lerp(b + lift_b, 0.5);
        assert!((middle.length() - 1.01).abs() < 1e-12, "{middle}");
        assert!(edge_place_lift(&ball, a + lift_a, b + lift_b, 0.5, ball.thickness - 1e-9).is_none());
        let far = DVec3::Y * 2.0;
        assert!(edge_surely_clear(&ball, far, far + DVec3::X * 0.3, ball.thickness));
    }
}
