//! A quick proof that a cloth does not pass through itself: a drape that is
//! the graph of a function over some plane cannot.
//!
//! Projected along the mean of its triangles' normals, if every triangle
//! keeps its orientation and the cloth's border is a simple closed curve,
//! the projection is one to one (each point inside the border has exactly
//! one preimage, as the border winds once around it and every triangle over
//! it counts +1), so no two parts of the cloth share a point. Most drapes
//! pass (a tablecloth, a table top, a curtain without overlapping folds),
//! and then the crossing count costs one pass over the triangles and the
//! border instead of a spatial search.

use glam::{DVec2, DVec3};

use super::broad_phase::grid_triangles;

/// Whether the grid's mesh projects one to one onto a plane (see the module
/// doc); `false` also for anything it cannot show: a non-finite or flat
/// point set, a triangle seen edge-on, a border that touches itself.
pub fn projects_one_to_one(positions: &[DVec3], cols: usize, rows: usize) -> bool {
    if cols < 2 || rows < 2 || positions.len() != cols * rows {
        return false;
    }
    let triangles = grid_triangles(cols, rows);
    let normal = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|k| positions[k as usize]);
        (b - a).cross(c - a)
    };
    let Some(axis) = triangles.iter().map(normal).sum::<DVec3>().try_normalize() else {
        return false;
    };
    // NaN compares false: a non-finite point fails here.
    if !triangles.iter().all(|t| normal(t).dot(axis) > 0.0) {
        return false;
    }
    let (u, v) = axis.any_orthonormal_pair();
    let border: Vec<DVec2> = border_loop(cols, rows)
        .map(|k| {
            let p = positions[k];
            DVec2::new(p.dot(u), p.dot(v))
        })
        .collect();
    is_simple_loop(&border)
}

/// The grid's border points in order round the cloth, each once.
fn border_loop(cols: usize, rows: usize) -> impl Iterator<Item = usize> {
    let top = 0..cols - 1;
    let right = (0..rows - 1).map(move |j| j * cols + cols - 1);
    let bottom = (1..cols).rev().map(move |i| (rows - 1) * cols + i);
    let left = (1..rows).rev().map(move |j| j * cols);
    top.chain(right).chain(bottom).chain(left)
}

/// Whether the closed polygon through `points` never meets itself: no two
/// sides that are not neighbours touch (touching counts as meeting).
fn is_simple_loop(points: &[DVec2]) -> bool {
    let n = points.len();
    if n < 3 {
        return false;
    }
    let side = |s: usize| (points[s], points[(s + 1) % n]);
    for s in 0..n {
        let (a, b) = side(s);
        let (lo, hi) = (a.min(b), a.max(b));
        for t in s + 2..n {
            if s == 0 && t == n - 1 {
                continue;
            }
            let (c, d) = side(t);
            if c.max(d).cmplt(lo).any() || c.min(d).cmpgt(hi).any() {
                continue;
            }
            if segments_meet(a, b, c, d) {
                return false;
            }
        }
    }
    true
}

/// Whether closed segments a–b and c–d share a point.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (side(c, d, a), side(c, d, b));
    let (d3, d4) = (side(a, b, c), side(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    // Collinear or touching: a point of one on the other.
    let on = |p: DVec2, q: DVec2, r: DVec2| side(p, q, r) == 0.0 && r.cmpge(p.min(q)).all() && r.cmple(p.max(q)).all();
    on(c, d, a) || on(c, d, b) || on(a, b, c) || on(a, b, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet(n: usize, height: impl Fn(f64, f64) -> f64) -> Vec<DVec3> {
        (0..n * n)
            .map(|k| {
                let (x, z) = ((k % n) as f64 / (n - 1) as f64, (k / n) as f64 / (n - 1) as f64);
                DVec3::new(x, height(x, z), z)
            })
            .collect()
    }

    #[test]
    fn a_flat_or_rolling_sheet_projects_one_to_one() {
        assert!(projects_one_to_one(&sheet(9, |_, _| 0.0), 9, 9));
        assert!(projects_one_to_one(&sheet(17, |x, z| (6.0 * x).sin() * 0.3 + z * z), 17, 17));
    }

    #[test]
    fn a_sheet_folded_back_over_itself_does_not() {
        // Rows past the middle come back over the first half.
        let mut p = sheet(9, |_, _| 0.0);
        for q in &mut p[45..81] {
            q.z = 1.0 - q.z;
            q.y = 0.1;
        }
        assert!(!projects_one_to_one(&p, 9, 9));
    }

    #[test]
    fn a_border_that_meets_itself_is_not_simple() {
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        assert!(is_simple_loop(&square));
        let bow_tie = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE];
        assert!(!is_simple_loop(&bow_tie));
        let touching = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0)];
        assert!(!is_simple_loop(&touching));
    }

    #[test]
    fn non_finite_or_flat_points_prove_nothing() {
        let mut p = sheet(5, |_, _| 0.0);
        p[12] = DVec3::NAN;
        assert!(!projects_one_to_one(&p, 5, 5));
        let line: Vec<DVec3> = (0..25).map(|k| DVec3::new(k as f64, 0.0, 0.0)).collect();
        assert!(!projects_one_to_one(&line, 5, 5));
    }

    #[test]
    fn the_border_loop_visits_each_border_point_once() {
        let border: Vec<usize> = border_loop(4, 3).collect();
        assert_eq!(border, [0, 1, 2, 3, 7, 11, 10, 9, 8, 4]);
    }
}
