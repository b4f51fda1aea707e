//! Moving a point out of the colliders, keeping a thickness from each surface.

use glam::DVec3;

use super::ColliderShape;

/// A collider at one moment and the distance the cloth keeps from its surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    pub shape: ColliderShape,
    /// Metres; at least 0.
    pub thickness: f64,
}

/// How far beyond its thickness an obstacle's box is swollen for
/// [`Reach`] (m): more than rounding and the trace's [`CONTACT_M`].
const REACH_MARGIN_M: f64 = 1e-6;

/// Where each obstacle can touch: its box swollen by its thickness. A point
/// outside an obstacle's box keeps more than its thickness from it, so a
/// contact test may pass it over without measuring, with the same answer.
#[derive(Clone, Debug, Default)]
pub struct Reach {
    boxes: Vec<(DVec3, DVec3)>,
}

impl Reach {
    pub fn of(obstacles: &[Obstacle]) -> Reach {
        let boxes = obstacles
            .iter()
            .map(|o| {
                let (lo, hi) = o.shape.bounds();
                let margin = DVec3::splat(o.thickness + REACH_MARGIN_M);
                (lo - margin, hi + margin)
            })
            .collect();
        Reach { boxes }
    }

    /// Whether obstacle `index` may be within its thickness of `p` (false
    /// for a non-finite `p`, which no obstacle pushes).
    pub fn near(&self, index: usize, p: DVec3) -> bool {
        self.boxes.get(index).is_some_and(|(lo, hi)| lo.cmple(p).all() && hi.cmpge(p).all())
    }

    /// Whether obstacle `index` may be within its thickness of a point of
    /// the segment `a` → `b`.
    pub fn near_segment(&self, index: usize, a: DVec3, b: DVec3) -> bool {
        let (lo, hi) = (a.min(b), a.max(b));
        self.boxes.get(index).is_some_and(|(l, h)| l.cmple(hi).all() && h.cmpge(lo).all())
    }

    /// Whether any obstacle may be within its thickness of a point of the
    /// segment `a` → `b` (false if either end is not finite).
    pub fn near_path(&self, a: DVec3, b: DVec3) -> bool {
        a.is_finite() && b.is_finite() && (0..self.boxes.len()).any(|index| self.near_segment(index, a, b))
    }
}

/// Rounds over every obstacle: a point pushed out of one into another is
/// pushed again; three rounds settle any two touching solids.
const ROUNDS: usize = 3;

/// Steps of a sphere trace along a path; a path grazing a surface at a
/// shallow angle may need many, and stops short of it after this many.
const TRACE_STEPS: usize = 64;

/// Bisection steps to find where a path enters an obstacle: 2⁻³² of the path.
const ENTRY_STEPS: usize = 32;

/// A point this close to the thickness counts as touching (m).
const CONTACT_M: f64 = 1e-7;

/// `to` moved out of every obstacle the way it came from `from`: where the
/// straight path from `from` first comes within an obstacle's thickness
/// (found by sphere tracing, so a thin table top is not stepped over), `to`
/// is slid onto the tangent plane there, and the rest of the path is
/// followed again from that point (a few times, for corners). A point that
/// a wave pushed through a table top therefore comes back on the side it
/// went in, not out of the underside, and one carried clean through stops on
/// the near side. What is still inside (`from` inside too) leaves the
/// nearest way. A path that touches nothing returns `to` unchanged.
pub fn slide_along(obstacles: &[Obstacle], from: DVec3, to: DVec3) -> DVec3 {
    if !from.is_finite() || !to.is_finite() {
        return to;
    }
    let (mut start, mut p) = (from, to);
    for _ in 0..ROUNDS {
        let Some((contact, outward)) = first_contact(obstacles, start, p, |o| o.thickness) else { break };
        let into = (p - contact).dot(outward);
        if into >= 0.0 {
            break;
        }
        // A path that ends clear and only dips into a thickness, touching no
        // solid, is not stopped: between two places resting on a curved
        // surface it dips by its sagitta, and the tangent plane where it
        // entered lies off the surface there (a point resting on a table's
        // rim was lifted 0.7 µm off it every other step and never settled).
        if clear(obstacles, p) && first_contact(obstacles, contact, p, |_| 0.0).is_none() {
            break;
        }
        p -= outward * into;
        start = contact;
    }
    push_out(obstacles, p)
}

/// `to` moved out of every obstacle the way it came from `from`, if it ends
/// inside one: where the straight path from `from` enters that obstacle, `to`
/// is slid onto the surface's tangent plane there (so a point a wave pushed
/// through a thin table top comes back on the side it went in, not out of
/// the underside); what is still inside (`from` inside too, or a curved
/// surface) leaves the nearest way. A `to` outside every obstacle is
/// returned unchanged. Unlike [`slide_along`], a path that passes clean
/// through an obstacle is not stopped.
pub fn push_out_along(obstacles: &[Obstacle], from: DVec3, to: DVec3) -> DVec3 {
    let mut p = to;
    for _ in 0..ROUNDS {
        let mut moved = false;
        for obstacle in obstacles {
            let (shape, keep) = (&obstacle.shape, obstacle.thickness);
            if shape.keeps_clear(p, keep) {
                continue;
            }
            moved = true;
            if from != p && shape.keeps_clear(from, keep) {
                let entry = entry_point(shape, keep, from, p);
                let n = shape.surface_point(entry).outward;
                p -= n * (p - entry).dot(n).min(0.0);
            }
            let s = shape.surface_point(p);
            if s.distance < keep {
                p += s.outward * (keep - s.distance);
            }
        }
        if !moved {
            break;
        }
    }
    if p.is_finite() { p } else { to }
}

/// The last point of the path `from` → `to` still `keep` or more from the
/// surface (`from` is, `to` is not).
fn entry_point(shape: &ColliderShape, keep: f64, from: DVec3, to: DVec3) -> DVec3 {
    let (mut outside, mut inside) = (0.0, 1.0);
    for _ in 0..ENTRY_STEPS {
        let mid = 0.5 * (outside + inside);
        if shape.keeps_clear(from.lerp(to, mid), keep) {
            outside = mid;
        } else {
            inside = mid;
        }
    }
    from.lerp(to, outside)
}

/// `p` moved to at least its thickness from every obstacle, the nearest way
/// out (along the outward direction). A point already outside is returned
/// unchanged, bit for bit.
pub fn push_out(obstacles: &[Obstacle], p: DVec3) -> DVec3 {
    let mut p = p;
    for _ in 0..ROUNDS {
        let mut moved = false;
        for obstacle in obstacles {
            let s = obstacle.shape.surface_point(p);
            if s.distance < obstacle.thickness {
                p += s.outward * (obstacle.thickness - s.distance);
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    p
}

/// Whether `p` keeps every obstacle's thickness, or touches it ([`CONTACT_M`]).
fn clear(obstacles: &[Obstacle], p: DVec3) -> bool {
    obstacles.iter().all(|o| o.shape.keeps_clear(p, o.thickness - CONTACT_M))
}

/// Where the path `from` → `to` first comes within `keep` of an obstacle
/// (its thickness, or 0 for the solid itself), and that obstacle's outward
/// direction there; `None` if it never does. The distances are exact, so
/// each step of the trace may go as far as the nearest surface and no
/// contact is stepped over.
fn first_contact(
    obstacles: &[Obstacle],
    from: DVec3,
    to: DVec3,
    keep: impl Fn(&Obstacle) -> f64,
) -> Option<(DVec3, DVec3)> {
    let length = from.distance(to);
    let direction = if length > 0.0 { (to - from) / length } else { DVec3::ZERO };
    let (lo, hi) = (from.min(to), from.max(to));
    let mut best: Option<(f64, DVec3, DVec3)> = None;
    for obstacle in obstacles.iter().filter(|o| o.shape.may_reach(lo, hi, keep(o))) {
        let keep = keep(obstacle);
        let mut t = 0.0;
        for _ in 0..TRACE_STEPS {
            let at = from + direction * t;
            let s = obstacle.shape.surface_point(at);
            let gap = s.distance - keep;
            if gap <= CONTACT_M {
                if best.is_none_or(|(t_best, _, _)| t < t_best) {
                    best = Some((t, at, s.outward));
                }
                break;
            }
            t += gap;
            if t > length {
                break;
            }
        }
    }
    best.map(|(_, at, outward)| (at, outward))
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;

    fn table() -> Obstacle {
        let shape = ColliderShape::Box {
            center: DVec3::new(0.0, 0.72, 0.0),
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: DMat3::IDENTITY,
        };
        Obstacle { shape, thickness: 0.005 }
    }

    #[test]
    fn what_reach_passes_over_is_farther_than_the_thickness() {
        let obstacles = [
            table(),
            Obstacle {
                shape: ColliderShape::Sphere { center: DVec3::new(2.0, 1.0, 0.0), radius: 0.3 },
                thickness: 0.01,
            },
            Obstacle { shape: ColliderShape::Ground { height: 0.0 }, thickness: 0.002 },
        ];
        let reach = Reach::of(&obstacles);
        let mut state = 12345u64;
        let mut unit = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let p = DVec3::new(unit() * 4.0 - 1.0, unit() * 2.0 - 0.2, unit() * 2.0 - 1.0);
            for (index, o) in obstacles.iter().enumerate() {
                if !reach.near(index, p) {
                    assert!(o.shape.distance(p) >= o.thickness, "{p} is within {index}'s thickness");
                }
            }
            let q = p + DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) * 0.2;
            if !reach.near_path(p, q) {
                assert_eq!(slide_along(&obstacles, p, q), q, "{p} → {q} touches nothing");
            }
        }
        assert!(!reach.near(0, DVec3::NAN) && !reach.near_path(DVec3::ZERO, DVec3::NAN));
        assert!(reach.near(2, DVec3::new(5.0, 0.001, 5.0)), "the ground reaches everywhere below its thickness");
    }

    #[test]
    fn a_point_outside_is_untouched() {
        let p = DVec3::new(0.1, 0.9, 0.2);
        assert_eq!(push_out(&[table()], p), p);
        assert_eq!(push_out_along(&[table()], DVec3::ZERO, p), p);
        assert_eq!(slide_along(&[table()], DVec3::new(0.0, 1.2, 0.0), p), p);
    }

    #[test]
    fn a_point_pushed_through_a_thin_top_comes_back_on_top() {
        // A layer moved the point from just above the top to below its middle plane.
        let (from, to) = (DVec3::new(0.1, 0.75, 0.0), DVec3::new(0.12, 0.705, 0.0));
        assert!(push_out(&[table()], to).y < 0.7, "the nearest way out is the underside");
        let p = push_out_along(&[table()], from, to);
        assert!((p.y - 0.745).abs() < 1e-6, "{p}");
        assert!((p.x - 0.12).abs() < 1e-6, "slid along the top, not back along the path: {p}");
    }

    #[test]
    fn a_path_through_a_thin_top_stops_on_the_near_side() {
        // From above the table to clean below it: the end is outside, the path is not.
        let p = slide_along(&[table()], DVec3::new(0.0, 0.8, 0.0), DVec3::new(0.05, 0.6, 0.0));
        assert_eq!(push_out_along(&[table()], DVec3::new(0.0, 0.8, 0.0), DVec3::new(0.05, 0.6, 0.0)).y, 0.6);
        assert!((p.y - 0.745).abs() < 1e-6 && (p.x - 0.05).abs() < 1e-6, "{p}");
    }

    #[test]
    fn a_point_sliding_round_a_rim_stays_on_it() {
        // Two places at the thickness round the top's long front edge, 0.05 rad
        // apart: the chord between them dips 1.4 µm into the thickness.
        let rim = DVec3::new(0.0, 0.74, 0.4);
        let at = |angle: f64| rim + DVec3::new(0.0, angle.cos(), angle.sin()) * 0.005;
        let (from, to) = (at(0.4), at(0.45));
        let p = slide_along(&[table()], from, to);
        assert!((table().shape.distance(p) - 0.005).abs() < 1e-12, "lifted off the rim to {p}");
        assert!(p.distance(to) < 1e-12, "{p}");
        // A path that only grazes a flat top keeps its end too.
        let flat = |x: f64| DVec3::new(x, 0.745, 0.0);
        assert_eq!(slide_along(&[table()], flat(0.1), flat(0.11)), flat(0.11));
    }

    #[test]
    fn the_thickness_is_kept_from_every_obstacle() {
        let ball = Obstacle {
            shape: ColliderShape::Sphere { center: DVec3::new(0.0, 1.0, 0.0), radius: 0.3 },
            thickness: 0.01,
        };
        let floor = Obstacle { shape: ColliderShape::Ground { height: 0.0 }, thickness: 0.002 };
        for p in [DVec3::new(0.05, 0.9, 0.1), DVec3::new(0.0, -0.5, 3.0), DVec3::new(0.0, 1.0, 0.0)] {
            let q = push_out(&[ball.clone(), floor.clone()], p);
            assert!(ball.shape.distance(q) >= 0.01 - 1e-12, "{p} → {q}");
            assert!(floor.shape.distance(q) >= 0.002 - 1e-12, "{p} → {q}");
        }
    }
}
