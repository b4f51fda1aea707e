//! A path between two points outside the colliders that goes round them
//! instead of through: where the straight line from one to the other cuts
//! a solid, it bends out at the middle of the cut to the nearest clear
//! place from which both new legs are clear (further corners where they are
//! not), and is then pulled taut round the solids like a string. A cloth
//! lifted off a table's edge therefore comes up beside the rim and over it
//! rather than through the top; neighbouring points, whose lines are alike,
//! take alike paths.

use glam::DVec3;

use super::{Obstacle, push_out, slide_along};

/// A path counts as cutting a solid where it comes closer to its surface
/// than its thickness less this share of it (or less [`MIN_GRAZE_M`]), so a
/// point resting on a surface may slide along it.
const GRAZE_SHARE: f64 = 0.5;

/// The least allowance below the thickness before a path cuts a solid (m).
const MIN_GRAZE_M: f64 = 5e-4;

/// The most corners the first path gets before it is pulled taut.
const MAX_CORNERS: usize = 8;

/// Sideways directions tried besides the one the surface faces.
const SIDEWAYS_TRIES: usize = 8;

/// How far sideways a corner may go (m).
const MAX_SIDEWAYS_M: f64 = 4.0;

/// Halvings that find where a sideways test starts to pass: 2⁻¹⁶ of the step.
const EDGE_STEPS: usize = 16;

/// Points a path is drawn through once pulled taut, ends included: close
/// enough that no leg is as long as a table top is thick.
const TAUT_POINTS: usize = 32;

/// Passes that pull a path taut, at most; they stop sooner once no point
/// moves more than [`TAUT_STILL_M`] in a pass.
const TAUT_PASSES: usize = 300;
const TAUT_STILL_M: f64 = 1e-5;

/// A path through points, measured along its length.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    points: Vec<DVec3>,
    /// The length of the path up to each of its points (m), from 0.
    length_to: Vec<f64>,
}

impl Polyline {
    /// The path through `points` (at least one), in order.
    pub fn through(points: Vec<DVec3>) -> Polyline {
        let mut length_to = vec![0.0];
        for leg in points.windows(2) {
            length_to.push(length_to[length_to.len() - 1] + leg[0].distance(leg[1]));
        }
        Polyline { points, length_to }
    }

    /// Its whole length (m).
    pub fn length(&self) -> f64 {
        self.length_to.last().copied().unwrap_or(0.0)
    }

    /// The point `share` (0 to 1) of the way along it.
    pub fn at(&self, share: f64) -> DVec3 {
        self.at_length(self.length() * share.clamp(0.0, 1.0))
    }

    /// The point `wanted` metres along it.
    pub fn at_length(&self, wanted: f64) -> DVec3 {
        let Some(&first) = self.points.first() else { return DVec3::NAN };
        if self.points.len() == 1 {
            return first;
        }
        let leg = self.length_to.partition_point(|&l| l <= wanted).clamp(1, self.points.len() - 1);
        let (start, end) = (self.length_to[leg - 1], self.length_to[leg]);
        let within = if end > start { (wanted - start) / (end - start) } else { 0.0 };
        self.points[leg - 1].lerp(self.points[leg], within)
    }
}

/// The inner points of a path from `a` to `b` round `obstacles` that keeps
/// their thickness (less a share of it: see [`GRAZE_SHARE`]) along every
/// leg: `None` when the straight line already does, when `a` or `b` is
/// itself that near a solid, or when no path was found (the caller keeps
/// the line then).
pub fn path_around(obstacles: &[Obstacle], a: DVec3, b: DVec3) -> Option<Vec<DVec3>> {
    if !a.is_finite() || !b.is_finite() || cuts_at(obstacles, a) || cuts_at(obstacles, b) {
        return None;
    }
    first_cut(obstacles, a, b)?;
    let mut path = vec![a, b];
    loop {
        let cut = path
            .windows(2)
            .enumerate()
            .find_map(|(leg, ends)| first_cut(obstacles, ends[0], ends[1]).map(|c| (leg, c)));
        let Some((leg, (obstacle, enter))) = cut else { break };
        if path.len() - 2 == MAX_CORNERS {
            return None;
        }
        let (from, to) = (path[leg], path[leg + 1]);
        let leave = leave_along(&obstacles[obstacle], from, to, enter);
        let middle = from.lerp(to, 0.5 * (enter + leave));
        let corner = corner_for(obstacles, &obstacles[obstacle], middle, (from, to))?;
        path.insert(leg + 1, corner);
    }
    let taut = taut(obstacles, &path);
    let clear = taut.windows(2).all(|leg| !enters_any(obstacles, leg[0], leg[1]));
    let path = if clear { taut } else { path };
    Some(path[1..path.len() - 1].to_vec())
}

/// A corner for the leg `from` → `to` sideways from `middle` (clear of every
/// obstacle by the thickness plus the allowance, so both new legs have
/// room), the way `obstacle`'s surface nearest `middle` faces or any of
/// [`SIDEWAYS_TRIES`] directions round the leg: the nearest clear place
/// whose legs are both clear, the shortest way round; else the nearest
/// place farther out from which they are; else the nearest clear place
/// with the fewest cut legs, which are bent in turn.
fn corner_for(obstacles: &[Obstacle], obstacle: &Obstacle, middle: DVec3, (from, to): (DVec3, DVec3)) -> Option<DVec3> {
    let along = (to - from).normalize_or_zero();
    let outward = obstacle.shape.surface_point(middle).outward;
    let facing = outward - along * outward.dot(along);
    let (u, v) = along.any_orthonormal_pair();
    let turns = (0..SIDEWAYS_TRIES).map(|k| {
        let angle = std::f64::consts::TAU * k as f64 / SIDEWAYS_TRIES as f64;
        u * angle.cos() + v * angle.sin()
    });
    let facing = (facing.length() > 1e-9).then(|| facing.normalize());
    let directions: Vec<DVec3> = facing.into_iter().chain(turns).collect();
    let clear = |p: DVec3| obstacles.iter().all(|o| o.shape.keeps_clear(p, o.thickness + allowance(o)));
    let cut_legs =
        |p: DVec3| [(from, p), (p, to)].iter().filter(|(a, b)| first_cut(obstacles, *a, *b).is_some()).count();
    let around = |p: &DVec3| from.distance(*p) + p.distance(to);
    let shortest = |corners: Vec<DVec3>| corners.into_iter().min_by(|p, q| around(p).total_cmp(&around(q)));
    let nearest: Vec<(DVec3, DVec3)> = directions
        .iter()
        .filter_map(|&sideways| {
            edge_of(0.0, MIN_GRAZE_M, &|d| clear(middle + sideways * d)).map(|d| (sideways, middle + sideways * d))
        })
        .collect();
    let cuts: Vec<usize> = nearest.iter().map(|&(_, p)| cut_legs(p)).collect();
    if let Some(corner) = shortest(nearest.iter().zip(&cuts).filter(|(_, c)| **c == 0).map(|((_, p), _)| *p).collect())
    {
        return Some(corner);
    }
    let farther: Vec<DVec3> = nearest
        .iter()
        .filter_map(|&(sideways, near)| {
            let pass = |d: f64| {
                let p = middle + sideways * d;
                clear(p) && cut_legs(p) == 0
            };
            let mut d = middle.distance(near);
            while d < MAX_SIDEWAYS_M {
                let inside = d;
                d *= 1.5;
                if pass(d) {
                    return edge_of(inside, d, &pass).map(|d| middle + sideways * d);
                }
            }
            None
        })
        .collect();
    if let Some(corner) = shortest(farther) {
        return Some(corner);
    }
    let fewest = cuts.iter().copied().min()?;
    shortest(nearest.iter().zip(&cuts).filter(|(_, c)| **c == fewest).map(|((_, p), _)| *p).collect())
}

/// The least distance, from `inside` (where `pass` fails) on, where `pass`
/// holds: doubling from `step` until it does (within [`MAX_SIDEWAYS_M`] × 4),
/// then halving back.
fn edge_of(inside: f64, step: f64, pass: &dyn Fn(f64) -> bool) -> Option<f64> {
    let (mut inside, mut outside) = (inside, step);
    while !pass(outside) {
        inside = outside;
        outside *= 2.0;
        if outside > 4.0 * MAX_SIDEWAYS_M {
            return None;
        }
    }
    for _ in 0..EDGE_STEPS {
        let mid = 0.5 * (inside + outside);
        if pass(mid) {
            outside = mid;
        } else {
            inside = mid;
        }
    }
    Some(outside)
}

/// `path` (clear of the solids, ends included) pulled taut round them like
/// a string: redrawn through [`TAUT_POINTS`] points evenly along it, each
/// point in turn moved toward the middle of its neighbours but stopped
/// where it meets a surface and slid on along it ([`slide_along`]). The
/// points never enter a solid, and their legs are too short to pass over a
/// table top; where a leg still cuts a solid's edge, a point is put at the
/// edge. The caller checks that no leg enters a solid all the same.
fn taut(obstacles: &[Obstacle], path: &[DVec3]) -> Vec<DVec3> {
    let line = Polyline::through(path.to_vec());
    let total = line.length();
    let mut points: Vec<DVec3> =
        (0..=TAUT_POINTS).map(|i| line.at_length(total * i as f64 / TAUT_POINTS as f64)).collect();
    points[0] = path[0];
    points[TAUT_POINTS] = path[path.len() - 1];
    // Kept a little off the surfaces, so the legs between them keep clear.
    let kept: Vec<Obstacle> =
        obstacles.iter().map(|o| Obstacle { shape: o.shape.clone(), thickness: o.thickness + allowance(o) }).collect();
    for _ in 0..TAUT_PASSES {
        let mut largest: f64 = 0.0;
        for i in 1..TAUT_POINTS {
            let middle = (points[i - 1] + points[i + 1]) * 0.5;
            let moved = slide_along(&kept, points[i], middle);
            largest = largest.max(moved.distance(points[i]));
            points[i] = moved;
        }
        if largest < TAUT_STILL_M {
            break;
        }
    }
    // A leg from one face to the next cuts the edge between them unless a
    // point stands at that edge: put one there, a few times over.
    for _ in 0..CORNER_ROUNDS {
        let mut rounded = Vec::with_capacity(points.len() + 8);
        rounded.push(points[0]);
        for leg in points.windows(2) {
            if enters_any(obstacles, leg[0], leg[1]) {
                rounded.push(push_out(&kept, leg[0].lerp(leg[1], 0.5)));
            }
            rounded.push(leg[1]);
        }
        if rounded.len() == points.len() {
            break;
        }
        points = rounded;
    }
    points
}

/// The most steps of one trace; a leg gliding along a surface steps by
/// [`MIN_GRAZE_M`] at least, so a few metres of it fit.
const TRACE_STEPS: usize = 8192;

/// Where the segment `a` → `b` first comes nearer `obstacle`'s surface than
/// `level_m` (a share of it; a negative level is inside), by sphere tracing:
/// every step goes as far as the surface allows, so no solid, however
/// thin, is stepped over (a place within [`MIN_GRAZE_M`] past the level
/// may be).
fn comes_within(obstacle: &Obstacle, a: DVec3, b: DVec3, level_m: f64) -> Option<f64> {
    let length = a.distance(b);
    if !length.is_finite() {
        return None;
    }
    let mut t = 0.0;
    for _ in 0..TRACE_STEPS {
        let share = if length > 0.0 { t / length } else { 0.0 };
        let gap = obstacle.shape.distance(a.lerp(b, share)) - level_m;
        if gap < 0.0 {
            return Some(share);
        }
        t += gap.max(MIN_GRAZE_M);
        if t > length {
            return None;
        }
    }
    None
}

/// Rounds of putting points where a taut path's legs cut a solid's edge.
const CORNER_ROUNDS: usize = 3;

/// Whether the segment `a` → `b` enters any of `obstacles` (a point of it inside a solid).
fn enters_any(obstacles: &[Obstacle], a: DVec3, b: DVec3) -> bool {
    obstacles.iter().any(|o| comes_within(o, a, b, 0.0).is_some())
}

/// How far below its thickness a path may come to an obstacle (m).
fn allowance(obstacle: &Obstacle) -> f64 {
    (obstacle.thickness * GRAZE_SHARE).max(MIN_GRAZE_M)
}

/// How close to an obstacle's surface a path may come (m).
fn level(obstacle: &Obstacle) -> f64 {
    obstacle.thickness - allowance(obstacle)
}

/// Whether `p` is nearer a solid than a path may come.
fn cuts_at(obstacles: &[Obstacle], p: DVec3) -> bool {
    obstacles.iter().any(|o| !o.shape.keeps_clear(p, level(o)))
}

/// The obstacle the straight path `from` → `to` first cuts, and where (a share of the path).
fn first_cut(obstacles: &[Obstacle], from: DVec3, to: DVec3) -> Option<(usize, f64)> {
    let (lo, hi) = (from.min(to), from.max(to));
    obstacles
        .iter()
        .enumerate()
        .filter(|(_, o)| o.shape.may_reach(lo, hi, o.thickness))
        .filter_map(|(index, o)| comes_within(o, from, to, level(o)).map(|share| (index, share)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
}

/// Where the path `from` → `to`, within `obstacle`'s level from share
/// `enter` on, comes back out (a share of the path; 1 if it never does):
/// traced back from `to`.
fn leave_along(obstacle: &Obstacle, from: DVec3, to: DVec3, enter: f64) -> f64 {
    match comes_within(obstacle, to, from, level(obstacle)) {
        Some(back) => (1.0 - back).max(enter),
        None => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;
    use crate::world::ColliderShape;

    fn top() -> Obstacle {
        let shape = ColliderShape::Cylinder {
            center: DVec3::new(0.0, 0.72, 0.0),
            radius: 0.5,
            half_height: 0.02,
            world_from_local: DMat3::IDENTITY,
        };
        Obstacle { shape, thickness: 0.003 }
    }

    /// The path through `corners` never enters the top (sampled finely), and
    /// its points keep the thickness from it.
    fn assert_clear(a: DVec3, corners: &[DVec3], b: DVec3) {
        let path: Vec<DVec3> = std::iter::once(a).chain(corners.iter().copied()).chain(std::iter::once(b)).collect();
        let least = path
            .windows(2)
            .flat_map(|leg| (0..=200).map(move |s| leg[0].lerp(leg[1], s as f64 / 200.0)))
            .map(|p| top().shape.distance(p))
            .fold(f64::INFINITY, f64::min);
        assert!(least >= 0.0, "the path enters the top by {:.2} mm: {corners:?}", -least * 1e3);
        for c in corners {
            assert!(top().shape.distance(*c) >= 0.003 - 1e-9, "{c} is nearer the top than its thickness");
        }
    }

    #[test]
    fn a_move_from_beside_a_top_to_onto_it_comes_up_over_the_rim() {
        // Hanging beside the rim, below the top; then lying on the top.
        let (a, b) = (DVec3::new(0.524, 0.548, 0.0), DVec3::new(0.167, 0.752, 0.0));
        assert!(top().shape.distance(a.lerp(b, 0.85)) < 0.0, "the straight line cuts the top");
        let Some(corners) = path_around(&[top()], a, b) else { panic!("a path over the rim") };
        assert_clear(a, &corners, b);
        // Taut: it hugs the rim, so no point of it is far beyond it or high above it.
        for c in &corners {
            assert!(c.x < 0.53 && c.y < 0.76, "{c}");
        }
    }

    #[test]
    fn a_clear_line_and_an_end_inside_get_no_path() {
        let b = DVec3::new(-0.3, 0.9, 0.1);
        assert_eq!(path_around(&[top()], DVec3::new(0.2, 0.8, 0.0), b), None);
        // Resting on the top and sliding along it is not a cut.
        assert_eq!(path_around(&[top()], DVec3::new(0.2, 0.743, 0.0), DVec3::new(-0.3, 0.743, 0.1)), None);
        assert_eq!(path_around(&[top()], DVec3::new(0.0, 0.72, 0.0), b), None);
    }

    #[test]
    fn a_move_from_under_a_top_to_over_it_goes_round_its_edge() {
        let (a, b) = (DVec3::new(0.3, 0.6, 0.0), DVec3::new(0.35, 0.9, 0.0));
        let Some(corners) = path_around(&[top()], a, b) else { panic!("a path round the edge") };
        assert_clear(a, &corners, b);
    }
}
