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
//!
//! Edges keep out too ([`keep_edges_out`]): between two points each clear
//! of a table's rounded rim, one on the top and one over its side, the
//! straight edge cuts the rim; its places are lifted to the thickness by
//! moving its ends, as a key's fall does.

use glam::DVec3;

use crate::mesh::PointArrays;
use crate::world::{
    EDGE_SHARES, Obstacle, Reach, edge_place_lift, edge_surely_clear, push_out, push_out_along, slide_along,
};

/// What was found clear of every obstacle (a point, or an edge by its two
/// ends), with where it was then (its coordinates' bits, `W` of them), so
/// that asking again about something nothing has moved since costs
/// nothing. Good for one frame's obstacles only: [`ClearAt::forget`] when
/// they change.
#[derive(Clone, Debug, Default)]
pub struct ClearAt<const W: usize> {
    at: Vec<[u32; W]>,
}

/// Points found clear, each by its position.
pub type ClearPoints = ClearAt<3>;

/// Edges found clear, two slots a point (its edge to the right, its edge
/// below), each by both its ends' positions.
pub type ClearEdges = ClearAt<6>;

impl<const W: usize> ClearAt<W> {
    /// Nothing is known clear (the obstacles changed).
    pub fn forget(&mut self) {
        self.at.clear();
    }

    fn is_clear(&self, slot: usize, bits: [u32; W]) -> bool {
        self.at.get(slot) == Some(&bits)
    }

    fn set_clear(&mut self, slot: usize, bits: [u32; W], slots: usize) {
        if self.at.len() != slots {
            // NaN bits: no position, so nothing is known.
            self.at = vec![[u32::MAX; W]; slots];
        }
        self.at[slot] = bits;
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
    let near = near_obstacles(obstacles, points);
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

/// Stops each point's move from the same point of `from` (equal lengths)
/// where it first comes within an obstacle's thickness, sliding the rest
/// along the surface ([`slide_along`]): for a move that must not carry a
/// point through anything, however thin, such as the in-between
/// relaxation's (which knows no colliders). Points that did not move, or
/// met nothing, are left bit for bit.
pub fn stop_at_surfaces(obstacles: &[Obstacle], from: &PointArrays, points: &mut PointArrays) {
    let n = points.len();
    if obstacles.is_empty() || from.len() != n {
        return;
    }
    let (Some((min_a, max_a)), Some((min_b, max_b))) = (bounds(from), bounds(points)) else { return };
    let near = obstacles_reaching(obstacles, min_a.min(min_b), max_a.max(max_b));
    for k in 0..n {
        let (a, b) = (from.get(k), points.get(k));
        if a == b {
            continue;
        }
        let q = slide_along(&near, a.as_dvec3(), b.as_dvec3());
        if q != b.as_dvec3() && q.is_finite() {
            points.set(k, q.as_vec3());
        }
    }
}

/// How much nearer than its thickness a place along an edge may come before
/// it is lifted (m): a key's fall keeps its edges at the thickness only to
/// within rounding, and a frame that holds a key leaves it as it is.
const EDGE_SLACK_M: f64 = 2.5e-4;

/// Lifts every edge of the `cols × rows` grid `points` that comes nearer an
/// obstacle than its thickness (less [`EDGE_SLACK_M`]) back to it, moving
/// the edge's ends ([`edge_place_lift`]), edges in grid order, each place
/// in turn. An edge whose ends lie on opposite faces (one over a table top,
/// one under it) is through the solid, and a lift would carry one end into
/// it: its ends go back towards where they were in `before` (equal lengths,
/// or empty for nowhere), each stopping where its way back first meets a
/// surface ([`slide_along`]), so an end the layers carried round a rim
/// returns to its own side. An edge with a `held` end is left to its free
/// point's own contact, as in a key's fall (moving the free end alone
/// stretches the edge). Edges left as they were are remembered in `clear`
/// and passed over while their ends stay where they were. Returns whether
/// any point moved.
pub fn keep_edges_out(
    obstacles: &[Obstacle],
    held: &[bool],
    before: &PointArrays,
    (cols, rows): (usize, usize),
    clear: &mut ClearEdges,
    points: &mut PointArrays,
) -> bool {
    let n = points.len();
    if obstacles.is_empty() || n == 0 || n != cols * rows || held.len() != n {
        return false;
    }
    let near = near_obstacles(obstacles, points);
    if near.is_empty() {
        return false;
    }
    let reach = Reach::of(&near);
    let bits = |points: &PointArrays, k: usize| [points.x[k], points.y[k], points.z[k]].map(f32::to_bits);
    let mut moved = false;
    for k in (0..n).filter(|&k| !held[k]) {
        let (i, j) = (k % cols, k / cols);
        let ends = [(i + 1 < cols).then(|| k + 1), (j + 1 < rows).then(|| k + cols)];
        for (slot, q) in ends.into_iter().enumerate().filter_map(|(side, q)| Some((2 * k + side, q?))) {
            if held[q] {
                continue;
            }
            let ([ax, ay, az], [bx, by, bz]) = (bits(points, k), bits(points, q));
            let ends_bits = [ax, ay, az, bx, by, bz];
            if clear.is_clear(slot, ends_bits) {
                continue;
            }
            let (a0, b0) = (points.get(k).as_dvec3(), points.get(q).as_dvec3());
            let (a, b) = match edge_kept_out(&near, &reach, a0, b0) {
                EdgeOut::Lifted(a, b) => (a, b),
                EdgeOut::Through if before.len() == n => {
                    (slide_along(&near, before.get(k).as_dvec3(), a0), slide_along(&near, before.get(q).as_dvec3(), b0))
                }
                EdgeOut::Through => (a0, b0),
            };
            if (a, b) == (a0, b0) {
                clear.set_clear(slot, ends_bits, 2 * n);
            } else if a.is_finite() && b.is_finite() {
                (points.x[k], points.y[k], points.z[k]) = (a.x as f32, a.y as f32, a.z as f32);
                (points.x[q], points.y[q], points.z[q]) = (b.x as f32, b.y as f32, b.z as f32);
                moved = true;
            }
        }
    }
    moved
}

/// An edge after [`edge_kept_out`].
pub(super) enum EdgeOut {
    /// Its ends, lifted where a place came too near (bit for bit as they were where none did).
    Lifted(DVec3, DVec3),
    /// It cuts an obstacle between opposite faces, and no lift takes it out.
    Through,
}

/// The ends of the edge `a`–`b` moved so that no place along it comes
/// nearer an obstacle than its thickness less [`EDGE_SLACK_M`] (to the
/// thickness), each place in turn; unchanged, bit for bit, where none does;
/// [`EdgeOut::Through`] where the edge cuts through the solid, not over its
/// rim: its ends lie on opposite faces (one over a table top, one under it;
/// their outward directions more than 120° apart) and a lift would carry
/// one of them into the solid. `reach` is [`Reach::of`] `obstacles`.
pub(super) fn edge_kept_out(obstacles: &[Obstacle], reach: &Reach, a: DVec3, b: DVec3) -> EdgeOut {
    let (mut a, mut b) = (a, b);
    for (index, obstacle) in obstacles.iter().enumerate() {
        let keep_m = obstacle.thickness - EDGE_SLACK_M;
        if !reach.near_segment(index, a, b) || edge_surely_clear(obstacle, a, b, keep_m) {
            continue;
        }
        let outward = |p: DVec3| obstacle.shape.surface_point(p).outward;
        let outside = |p: DVec3| obstacle.shape.distance(p) >= 0.0;
        // Asked of the ends as they came, before the first lift.
        let mut opposite = None;
        for t in EDGE_SHARES {
            let Some((lift_a, lift_b)) = edge_place_lift(obstacle, a, b, t, keep_m) else { continue };
            let (lifted_a, lifted_b) = (a + lift_a, b + lift_b);
            let into = (outside(a) && !outside(lifted_a)) || (outside(b) && !outside(lifted_b));
            if into && *opposite.get_or_insert_with(|| outward(a).dot(outward(b)) < OPPOSITE_FACES_COS) {
                return EdgeOut::Through;
            }
            (a, b) = (lifted_a, lifted_b);
        }
    }
    EdgeOut::Lifted(a, b)
}

/// Ends whose outward directions are further apart than this cosine lie on
/// opposite faces (over and under a table top). Over a rim they are up to
/// 90° apart, and a little more where one end hangs by the rim's lower
/// corner (round table: −0.02 to −0.5).
const OPPOSITE_FACES_COS: f64 = -0.5;

/// The obstacles the cloth `points` can touch: those whose box, swollen by
/// the thickness, meets the points' box.
fn near_obstacles(obstacles: &[Obstacle], points: &PointArrays) -> Vec<Obstacle> {
    let Some((min, max)) = bounds(points) else { return Vec::new() };
    obstacles_reaching(obstacles, min, max)
}

/// The obstacles whose box, swollen by their thickness, meets the box `min`–`max`.
fn obstacles_reaching(obstacles: &[Obstacle], min: DVec3, max: DVec3) -> Vec<Obstacle> {
    obstacles.iter().filter(|o| o.shape.may_reach(min, max, o.thickness)).cloned().collect()
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

    /// A 2 × 2 grid folded over the table's front edge: the back row on the
    /// top, the front row down the side, each point clear of the table, the
    /// edges between them 13.5 mm deep in it at their middle.
    fn folded_over_the_front_edge() -> Vec<Vec3> {
        vec![
            Vec3::new(-0.1, 0.743, 0.37),
            Vec3::new(0.1, 0.743, 0.37),
            Vec3::new(-0.1, 0.71, 0.403),
            Vec3::new(0.1, 0.71, 0.403),
        ]
    }

    #[test]
    fn an_edge_cutting_a_table_s_edge_is_lifted_round_it() {
        let cloth = folded_over_the_front_edge();
        for p in &cloth {
            assert!(table().shape.distance(p.as_dvec3()) >= 0.003 - 1e-6, "each point is clear: {p}");
        }
        let deepest = |points: &PointArrays| {
            (1..40)
                .map(|t| {
                    let (a, b) = (points.get(0).as_dvec3(), points.get(2).as_dvec3());
                    table().shape.distance(a.lerp(b, f64::from(t) / 40.0))
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut points = PointArrays::from_vec3s(&cloth);
        assert!(deepest(&points) < -0.005, "the straight edge cuts the table's edge");
        let mut clear = ClearEdges::default();
        assert!(keep_edges_out(&[table()], &[false; 4], &PointArrays::default(), (2, 2), &mut clear, &mut points));
        // Lifted to the thickness at its five places; between them, over the
        // table's square edge, the chord dips by a fraction of a millimetre.
        for (t, q) in [(0, 2), (1, 3)].into_iter().flat_map(|e| EDGE_SHARES.map(|t| (t, e))) {
            let place = points.get(q.0).as_dvec3().lerp(points.get(q.1).as_dvec3(), t);
            assert!(table().shape.distance(place) > 0.003 - EDGE_SLACK_M, "{t} along {q:?}");
        }
        assert!(deepest(&points) > -0.5e-3, "{}", deepest(&points));
        for (k, was) in cloth.iter().enumerate() {
            assert!(points.get(k).y >= was.y && points.get(k).z >= was.z, "lifted up and out: {k}");
        }
        // Lifted, it is clear: a second pass leaves it bit for bit, and remembers it.
        let lifted = points.clone();
        assert!(!keep_edges_out(&[table()], &[false; 4], &PointArrays::default(), (2, 2), &mut clear, &mut points));
        assert_eq!(points, lifted);
        // Two slots a point (right, down): the grid's four edges are in 0, 1, 3 and 4.
        assert!([0, 1, 3, 4].iter().all(|&slot| clear.at[slot][0] != u32::MAX), "{:?}", clear.at);
    }

    #[test]
    fn an_edge_through_a_table_top_from_above_to_below_is_not_lifted() {
        // The front row carried under the top: lifting either way tears the cloth.
        let mut cloth = folded_over_the_front_edge();
        for p in &mut cloth[2..] {
            (p.y, p.z) = (0.69, 0.3);
        }
        let mut points = PointArrays::from_vec3s(&cloth);
        assert!(!keep_edges_out(
            &[table()],
            &[false; 4],
            &PointArrays::default(),
            (2, 2),
            &mut ClearEdges::default(),
            &mut points
        ));
        assert_eq!(points, PointArrays::from_vec3s(&cloth));
    }

    #[test]
    fn an_edge_carried_through_a_table_top_goes_back_round_its_edge() {
        // Folded over the front edge before the layers; the layers carry the
        // front row under the top, so each edge runs from over it to under it.
        let before = PointArrays::from_vec3s(&folded_over_the_front_edge());
        let mut cloth = folded_over_the_front_edge();
        for p in &mut cloth[2..] {
            (p.y, p.z) = (0.69, 0.3);
        }
        let mut points = PointArrays::from_vec3s(&cloth);
        let mut clear = ClearEdges::default();
        let mut rounds = 0;
        while keep_edges_out(&[table()], &[false; 4], &before, (2, 2), &mut clear, &mut points) {
            rounds += 1;
            assert!(rounds < 4, "settles in a few rounds");
        }
        for k in 2..4 {
            assert!(points.get(k).z >= 0.4, "the front row is back in front of the top: {}", points.get(k));
        }
        for (t, (a, b)) in (1..10).flat_map(|t| [(0, 2), (1, 3)].map(|e| (f64::from(t) / 10.0, e))) {
            let place = points.get(a).as_dvec3().lerp(points.get(b).as_dvec3(), t);
            assert!(table().shape.distance(place) > 0.0, "{t} along {a}-{b} is out of the top: {place}");
        }
    }

    #[test]
    fn an_edge_with_a_held_end_is_left_to_its_free_point() {
        let cloth = folded_over_the_front_edge();
        let mut points = PointArrays::from_vec3s(&cloth);
        let held = [true, true, false, false];
        assert!(!keep_edges_out(
            &[table()],
            &held,
            &PointArrays::default(),
            (2, 2),
            &mut ClearEdges::default(),
            &mut points
        ));
        assert_eq!(points, PointArrays::from_vec3s(&cloth));
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
