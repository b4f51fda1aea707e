//! Whether a segment passes through a triangle. Plain f64 geometry with no
//! division, so degenerate edges and triangles give an answer, not a NaN.

use glam::DVec3;

/// Whether segment `s → t` passes through triangle `(a, b, c)`: its end
/// points lie strictly on opposite sides of the triangle's plane and the
/// crossing point lies inside the triangle (edges included). A segment
/// lying in the plane, or touching it at an end, does not count.
pub fn segment_crosses_triangle(s: DVec3, t: DVec3, a: DVec3, b: DVec3, c: DVec3) -> bool {
    let n = (b - a).cross(c - a);
    let (ds, dt) = ((s - a).dot(n), (t - a).dot(n));
    if !(ds * dt < 0.0) {
        return false;
    }
    // Signed volumes of the segment against each edge: one sign for all three
    // means the line passes inside.
    let d = t - s;
    let side = |u: DVec3, v: DVec3| (u - s).cross(v - s).dot(d);
    let (x, y, z) = (side(a, b), side(b, c), side(c, a));
    (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn a_segment_through_a_triangle_crosses_it_and_one_beside_it_does_not() {
        let (a, b, c) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
        assert!(segment_crosses_triangle(v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), a, b, c));
        assert!(!segment_crosses_triangle(v(0.8, 0.8, -1.0), v(0.8, 0.8, 1.0), a, b, c));
        assert!(!segment_crosses_triangle(v(0.2, 0.2, 0.5), v(0.2, 0.2, 1.0), a, b, c));
        assert!(!segment_crosses_triangle(v(0.2, 0.2, 0.0), v(0.2, 0.2, 1.0), a, b, c), "touching is not crossing");
    }
}
