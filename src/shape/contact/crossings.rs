//! Where the cloth passes through itself: grid edges that cross a triangle
//! they do not touch (share no vertex with).

use glam::DVec3;

use super::broad_phase::{BoxGrid, grid_edges, grid_triangles};
use super::geometry::segment_crosses_triangle;
use super::one_to_one::projects_one_to_one;

/// The number of (edge, triangle) pairs of the grid's mesh (rows, columns and
/// the b–c diagonal of each quad) where the edge passes through a triangle it
/// shares no vertex with. 0 for a cloth that never passes through itself.
/// Non-finite points take part in no crossing.
pub fn count_crossings(positions: &[DVec3], cols: usize, rows: usize) -> usize {
    assert_eq!(positions.len(), cols * rows);
    // Most drapes are a graph over some plane, which cannot cross itself.
    if cols < 2 || rows < 2 || projects_one_to_one(positions, cols, rows) {
        return 0;
    }
    search_crossings(positions, cols, rows)
}

/// [`count_crossings`] by a search of every edge against the triangles near it.
fn search_crossings(positions: &[DVec3], cols: usize, rows: usize) -> usize {
    let triangles = grid_triangles(cols, rows);
    let edges = grid_edges(cols, rows);
    let mean_edge = mean_edge_length(positions, &edges);
    if !(mean_edge > 0.0) {
        return 0;
    }
    let mut grid = BoxGrid::new(positions, &triangles, mean_edge, 0.0);
    let mut count = 0;
    for &[s, t] in &edges {
        let (ps, pt) = (positions[s as usize], positions[t as usize]);
        if !ps.is_finite() || !pt.is_finite() {
            continue;
        }
        grid.near(ps.min(pt), ps.max(pt), &mut |tri| {
            let tri = triangles[tri as usize];
            if tri.contains(&s) || tri.contains(&t) {
                return;
            }
            let [a, b, c] = tri.map(|k| positions[k as usize]);
            if segment_crosses_triangle(ps, pt, a, b, c) {
                count += 1;
            }
        });
    }
    count
}

/// Mean length of the finite edges (0 when there are none).
fn mean_edge_length(positions: &[DVec3], edges: &[[u32; 2]]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for &[s, t] in edges {
        let d = positions[s as usize].distance(positions[t as usize]);
        if d.is_finite() {
            sum += d;
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat `n × n` sheet in z = 0, folded along row `fold` so that the rows
    /// below come back over it at height `gap` (negative: through it).
    fn folded(n: usize, fold: usize, gap: f64, shift: f64) -> Vec<DVec3> {
        let mut p = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let x = i as f64 / (n - 1) as f64;
                let y = j as f64 / (n - 1) as f64;
                let yf = fold as f64 / (n - 1) as f64;
                p.push(if j <= fold { DVec3::new(x, y, 0.0) } else { DVec3::new(x + shift, 2.0 * yf - y, gap) });
            }
        }
        p
    }

    #[test]
    fn a_flat_sheet_does_not_cross_itself() {
        assert_eq!(count_crossings(&folded(9, 8, 0.0, 0.0), 9, 9), 0);
    }

    #[test]
    fn a_fold_above_the_sheet_does_not_cross_and_one_through_it_does() {
        assert_eq!(count_crossings(&folded(9, 5, 0.05, 0.0), 9, 9), 0);
        // The fold's far row tilts through the sheet: its edges cross triangles.
        let mut through = folded(9, 5, 0.05, 0.0);
        for i in 0..9 {
            through[8 * 9 + i].z = -0.05;
        }
        assert!(count_crossings(&through, 9, 9) > 0);
    }

    #[test]
    fn a_cloth_proved_one_to_one_is_one_the_search_finds_no_crossing_in() {
        // Folds at every height and shift, and rippled sheets: where the quick
        // proof says no crossing, the search agrees; where they cross, the
        // proof does not claim otherwise.
        let mut proved = 0;
        for fold in 3..8 {
            for gap in [-0.2, -0.05, 0.0, 0.05, 0.2] {
                for shift in [0.0, 0.3] {
                    let p = folded(9, fold, gap, shift);
                    let found = search_crossings(&p, 9, 9);
                    if projects_one_to_one(&p, 9, 9) {
                        proved += 1;
                        assert_eq!(found, 0, "fold {fold}, gap {gap}, shift {shift}");
                    }
                    assert_eq!(count_crossings(&p, 9, 9), found);
                }
            }
        }
        for amplitude in [0.0, 0.1, 0.5, 2.0] {
            let mut p = folded(9, 8, 0.0, 0.0);
            for (k, q) in p.iter_mut().enumerate() {
                q.z = amplitude * ((k % 9) as f64 * 1.3).sin() * ((k / 9) as f64 * 0.7).cos();
            }
            // A height field over z = 0 always; steep enough (amplitude 2), some
            // triangles turn away from the mean normal and the proof gives up.
            if amplitude <= 0.5 {
                assert!(projects_one_to_one(&p, 9, 9), "a gentle height field, amplitude {amplitude}");
                proved += 1;
            }
            assert_eq!(search_crossings(&p, 9, 9), 0);
            assert_eq!(count_crossings(&p, 9, 9), 0);
        }
        assert!(proved >= 3);
    }

    #[test]
    fn non_finite_points_cross_nothing() {
        let mut p = folded(5, 4, 0.0, 0.0);
        p[7] = DVec3::NAN;
        assert_eq!(count_crossings(&p, 5, 5), 0);
    }
}
