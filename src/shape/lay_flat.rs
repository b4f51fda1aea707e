//! A start for a rest shape among colliders: the cloth laid out flat.
//!
//! The catenaries know nothing of colliders: they pass straight through a
//! table, and a single pin's approximation hangs the whole cloth in one
//! vertical line. Pushing such a start out of the colliders sends a point
//! sagging through a thin table top out of its underside, and a fall from a
//! cloth bunched in a line crumples. So among colliders the cloth starts
//! flat, in the plane that best fits its pins (the level plane, u along +X
//! and v along +Z, with fewer than three pins or pins in a line), placed so
//! the pins' material positions land on average on their world positions,
//! with the fabric at its rest length; points that start inside a collider
//! leave it the nearest way. The fall ([`super::relax::drape_among`]) then
//! drapes it: a cloth pinned on a table top starts flat on the top and out
//! past its edges, and its overhang falls.

use glam::{DMat3, DVec3};

use crate::world::{Obstacle, push_out};

/// A key without pins starts here: the `cols × rows` grid flat, `spacing`
/// (u, v) metres apart in material space and `elasticity` times as long in
/// the fabric, u along +X and v along +Z, its middle at `center`, turned by
/// `rotation` about the middle (vertex order `j·cols + i`).
pub fn flat_at(
    (cols, rows): (usize, usize),
    spacing: (f64, f64),
    elasticity: f64,
    center: DVec3,
    rotation: DMat3,
) -> Vec<DVec3> {
    let middle = (cols.saturating_sub(1) as f64 * spacing.0 / 2.0, rows.saturating_sub(1) as f64 * spacing.1 / 2.0);
    (0..cols * rows)
        .map(|k| {
            let (u, v) = ((k % cols) as f64 * spacing.0, (k / cols) as f64 * spacing.1);
            center + rotation * DVec3::new(u - middle.0, 0.0, v - middle.1) * elasticity
        })
        .collect()
}

/// Lays `positions` (a `cols × rows` grid, `spacing` (u, v) metres apart in
/// material space, `elasticity` times as long in the fabric) out flat as
/// the module says; pins stay where they are. Nothing changes without
/// obstacles.
pub fn lay_flat(
    positions: &mut [DVec3],
    (cols, rows): (usize, usize),
    spacing: (f64, f64),
    elasticity: f64,
    pinned: &[bool],
    obstacles: &[Obstacle],
) {
    let n = cols * rows;
    if obstacles.is_empty() || positions.len() != n || pinned.len() != n {
        return;
    }
    let material = |k: usize| ((k % cols) as f64 * spacing.0, (k / cols) as f64 * spacing.1);
    let pins: Vec<((f64, f64), DVec3)> = (0..n).filter(|&k| pinned[k]).map(|k| (material(k), positions[k])).collect();
    if pins.is_empty() {
        return;
    }
    let (along_u, along_v) = pin_plane(&pins);
    let count = pins.len() as f64;
    let (mu, mv) = pins.iter().fold((0.0, 0.0), |(a, b), ((u, v), _)| (a + u / count, b + v / count));
    let centre = pins.iter().fold(DVec3::ZERO, |a, (_, p)| a + *p / count);
    for k in (0..n).filter(|&k| !pinned[k]) {
        let (u, v) = material(k);
        let flat = centre + (along_u * (u - mu) + along_v * (v - mv)) * elasticity;
        positions[k] = push_out(obstacles, flat);
    }
}

/// Unit directions in space of the material's u and v in the plane that
/// best fits the pins (least squares of world against material position);
/// with fewer than three pins, or pins in a line in material space, the
/// level plane with u along +X and v along +Z.
fn pin_plane(pins: &[((f64, f64), DVec3)]) -> (DVec3, DVec3) {
    let level = (DVec3::X, DVec3::Z);
    if pins.len() < 3 {
        return level;
    }
    let count = pins.len() as f64;
    let (mu, mv) = pins.iter().fold((0.0, 0.0), |(a, b), ((u, v), _)| (a + u / count, b + v / count));
    let mp = pins.iter().fold(DVec3::ZERO, |a, (_, p)| a + *p / count);
    let (mut suu, mut suv, mut svv, mut sup, mut svp) = (0.0, 0.0, 0.0, DVec3::ZERO, DVec3::ZERO);
    for ((u, v), p) in pins {
        let (du, dv, dp) = (u - mu, v - mv, *p - mp);
        suu += du * du;
        suv += du * dv;
        svv += dv * dv;
        sup += dp * du;
        svp += dp * dv;
    }
    let det = suu * svv - suv * suv;
    if !(det.abs() > 1e-12 * (suu * svv).max(1e-30)) {
        return level;
    }
    let along_u = (sup * svv - svp * suv) / det;
    let along_v = (svp * suu - sup * suv) / det;
    match (along_u.try_normalize(), along_v.try_normalize()) {
        (Some(u), Some(v)) => (u, v),
        _ => level,
    }
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;
    use crate::world::ColliderShape;

    #[test]
    fn a_cloth_pinned_on_a_table_top_starts_flat_on_it() {
        let table = Obstacle {
            shape: ColliderShape::Box {
                center: DVec3::ZERO,
                half: DVec3::new(0.5, 0.02, 0.5),
                world_from_local: DMat3::IDENTITY,
            },
            thickness: 0.003,
        };
        // A 5 × 5 cloth 0.1 m apart, pinned at three corners of its middle square on the top.
        let (cols, rows) = (5, 5);
        let mut positions = vec![DVec3::new(0.0, -3.0, 0.0); cols * rows];
        let mut pinned = vec![false; cols * rows];
        for (k, p) in
            [(6, DVec3::new(-0.1, 0.023, -0.1)), (8, DVec3::new(0.1, 0.023, -0.1)), (16, DVec3::new(-0.1, 0.023, 0.1))]
        {
            pinned[k] = true;
            positions[k] = p;
        }
        lay_flat(&mut positions, (cols, rows), (0.1, 0.1), 1.0, &pinned, &[table]);
        assert_eq!(positions[6], DVec3::new(-0.1, 0.023, -0.1));
        for (k, p) in positions.iter().enumerate() {
            let (i, j) = ((k % cols) as f64, (k / cols) as f64);
            let want = DVec3::new(-0.2 + 0.1 * i, 0.023, -0.2 + 0.1 * j);
            assert!((*p - want).length() < 1e-9, "point {k} at {p}, not {want}");
        }
        assert!(lay_flat_is_a_no_op_without_obstacles());
    }

    fn lay_flat_is_a_no_op_without_obstacles() -> bool {
        let mut positions = vec![DVec3::ONE; 4];
        lay_flat(&mut positions, (2, 2), (0.1, 0.1), 1.0, &[true, false, false, false], &[]);
        positions == vec![DVec3::ONE; 4]
    }
}
