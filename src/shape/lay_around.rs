//! A start for relaxation among colliders: the approximation laid around them.
//!
//! The catenaries know nothing of colliders and pass straight through a
//! table. Relaxation alone would push each point out the nearest way, which
//! for a point sagging through a thin table top is as often its underside.
//! So the cloth is first re-laid from the pins outward, in order of material
//! distance: each point keeps its offset from the neighbour it was reached
//! from, as in the approximation, but where that step ends inside a collider
//! it stops at the surface where it entered and slides along it (a step that
//! passes clean through a thin collider is not caught yet). A cloth pinned on a table top
//! then starts on the top, bunched at the edge where it would have gone
//! through, and relaxation spreads it from there.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::world::{Obstacle, push_out_along};

/// Re-lays `positions` (a `cols × rows` grid, `spacing` (u, v) metres apart
/// in material space) from the `pinned` points outward around `obstacles`.
/// Pins stay; points no pin reaches (none, on a valid key) stay too.
pub fn lay_around(
    positions: &mut [DVec3],
    (cols, rows): (usize, usize),
    spacing: (f64, f64),
    pinned: &[bool],
    obstacles: &[Obstacle],
) {
    let n = cols * rows;
    if obstacles.is_empty() || positions.len() != n || pinned.len() != n {
        return;
    }
    let approximated = positions.to_vec();
    let mut distance = vec![f64::INFINITY; n];
    let mut from = vec![usize::MAX; n];
    let mut done = vec![false; n];
    // Distances are never negative, so their bits order as the numbers do; the index breaks ties.
    let mut queue = BinaryHeap::new();
    for k in (0..n).filter(|&k| pinned[k]) {
        distance[k] = 0.0;
        queue.push(Reverse((0u64, k)));
    }
    while let Some(Reverse((_, k))) = queue.pop() {
        if done[k] {
            continue;
        }
        done[k] = true;
        if !pinned[k] && from[k] != usize::MAX {
            let leader = from[k];
            let step = approximated[k] - approximated[leader];
            positions[k] = push_out_along(obstacles, positions[leader], positions[leader] + step);
        }
        let (i, j) = (k % cols, k / cols);
        let neighbours = [
            (i > 0, k.wrapping_sub(1), spacing.0),
            (i + 1 < cols, k + 1, spacing.0),
            (j > 0, k.wrapping_sub(cols), spacing.1),
            (j + 1 < rows, k + cols, spacing.1),
        ];
        for (exists, q, length) in neighbours {
            if !exists || done[q] || pinned[q] {
                continue;
            }
            let d = distance[k] + length;
            if d < distance[q] {
                distance[q] = d;
                from[q] = k;
                queue.push(Reverse((d.to_bits(), q)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;
    use crate::world::ColliderShape;

    #[test]
    fn a_strip_hanging_through_a_table_top_is_laid_on_it() {
        // Pinned at its left end on a table top; the approximation sags it into the top.
        let table = Obstacle {
            shape: ColliderShape::Box {
                center: DVec3::new(0.5, 0.0, 0.0),
                half: DVec3::new(0.5, 0.02, 0.5),
                world_from_local: DMat3::IDENTITY,
            },
            thickness: 0.003,
        };
        let mut positions: Vec<DVec3> =
            (0..5).map(|k| DVec3::new(0.2 + k as f64 * 0.1, 0.023 - k as f64 * 0.01, 0.0)).collect();
        let mut pinned = vec![false; 5];
        pinned[0] = true;
        lay_around(&mut positions, (5, 1), (0.1, 0.1), &pinned, &[table]);
        assert_eq!(positions[0], DVec3::new(0.2, 0.023, 0.0));
        for p in &positions[1..] {
            assert!(table.shape.distance(*p) >= 0.003 - 1e-9 && p.y > 0.0, "on the top, not under it: {p}");
        }
    }
}
