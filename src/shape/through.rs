//! Where a rest shape passes through a collider: grid points and points
//! along its edges deeper inside a solid than [`THROUGH_DEPTH_M`]. Such a
//! shape is never reported settled.

use glam::DVec3;

use crate::world::{Obstacle, Reach};

/// How deep inside a solid a place must be to count as through it (m):
/// more than rounding and the fall's own tolerance of its thickness.
pub const THROUGH_DEPTH_M: f64 = 1e-3;

/// Each row and column edge is measured at the points that cut it into this
/// many equal parts (seven points between its ends).
const EDGE_PARTS: usize = 8;

/// How a shape passes through the colliders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Through {
    /// Grid points and points along edges deeper than [`THROUGH_DEPTH_M`] inside a solid.
    pub places: usize,
    /// The deepest of them (m).
    pub deepest_m: f64,
    /// The grid point (column, row) at or nearest the deepest place.
    pub deepest_at: (usize, usize),
    /// The obstacle (index) with the most of them.
    pub collider: usize,
}

/// Where `positions` (a `cols × rows` grid) pass through `obstacles`; pins
/// are exempt (a pin may sit inside a collider) but the edges from them are not.
pub fn through_obstacles(
    positions: &[DVec3],
    (cols, rows): (usize, usize),
    pinned: &[bool],
    obstacles: &[Obstacle],
) -> Option<Through> {
    if obstacles.is_empty() || positions.len() != cols * rows || pinned.len() != positions.len() {
        return None;
    }
    let reach = Reach::of(obstacles);
    let mut counts = vec![0usize; obstacles.len()];
    let mut deepest_m: f64 = 0.0;
    let mut deepest_at = 0;
    let mut measure = |p: DVec3, nearest: usize| {
        for (index, o) in obstacles.iter().enumerate() {
            if !reach.near(index, p) {
                continue;
            }
            let depth = -o.shape.distance(p);
            if depth > THROUGH_DEPTH_M {
                counts[index] += 1;
                if depth > deepest_m {
                    (deepest_m, deepest_at) = (depth, nearest);
                }
            }
        }
    };
    for (p, nearest, is_point) in grid_places(positions, (cols, rows), EDGE_PARTS) {
        if !(is_point && pinned[nearest]) {
            measure(p, nearest);
        }
    }
    let places: usize = counts.iter().sum();
    let collider = (0..counts.len()).max_by_key(|&i| (counts[i], std::cmp::Reverse(i)))?;
    let deepest_at = (deepest_at % cols, deepest_at / cols);
    (places > 0).then_some(Through { places, deepest_m, deepest_at, collider })
}

/// Every place of a `cols × rows` grid where contact is measured, in grid
/// order: each grid point, then the points cutting its row and column
/// edges into `parts` equal parts. Each comes with the grid point at or
/// nearest it, and whether it is that grid point.
pub(super) fn grid_places(
    positions: &[DVec3],
    (cols, rows): (usize, usize),
    parts: usize,
) -> impl Iterator<Item = (DVec3, usize, bool)> + '_ {
    (0..cols * rows).flat_map(move |k| {
        let (i, j) = (k % cols, k / cols);
        let ends = [(i + 1 < cols).then(|| k + 1), (j + 1 < rows).then(|| k + cols)];
        let along = ends.into_iter().flatten().flat_map(move |q| {
            (1..parts).map(move |t| {
                let share = t as f64 / parts as f64;
                (positions[k].lerp(positions[q], share), if share <= 0.5 { k } else { q }, false)
            })
        });
        std::iter::once((positions[k], k, true)).chain(along)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::ColliderShape;

    #[test]
    fn a_grid_through_a_ball_is_found_and_one_beside_it_is_not() {
        let ball = Obstacle { shape: ColliderShape::Sphere { center: DVec3::ZERO, radius: 0.2 }, thickness: 0.003 };
        let grid = |y: f64| -> Vec<DVec3> {
            (0..25).map(|k| DVec3::new(-0.4 + 0.2 * (k % 5) as f64, y, -0.4 + 0.2 * (k / 5) as f64)).collect()
        };
        let pinned = vec![false; 25];
        let through = through_obstacles(&grid(0.0), (5, 5), &pinned, std::slice::from_ref(&ball));
        let Some(through) = through else { panic!("a grid through the ball's middle passes through it") };
        assert_eq!(through.collider, 0);
        assert!((through.deepest_m - 0.2).abs() < 1e-12, "{through:?}");
        assert_eq!(through_obstacles(&grid(0.21), (5, 5), &pinned, &[ball]), None);
    }
}
