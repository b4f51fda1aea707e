//! Whether a segment passes through a triangle. Plain f64 geometry with no
//! division, so degenerate edges and triangles give an answer, not a NaN.

use glam::DVec3;

/// Whether segment `s → t` passes through triangle `(a, b, c)`: its end
/// points lie on opposite sides of the triangle's plane, each farther from
/// it than [`CROSSING_SLACK`] × the primitives' size, and the point where it
/// meets the plane lies inside the triangle (edges included). A segment
/// lying in the plane, touching it, or a zero-area triangle does not count.
///
/// The slack keeps nearly coplanar primitives (a flat sheet, where rounding
/// alone puts end points a few 1e-17 m on either side) from counting as
/// crossed however far apart they lie in the plane.
pub fn segment_crosses_triangle(s: DVec3, t: DVec3, a: DVec3, b: DVec3, c: DVec3) -> bool {
    let n = (b - a).cross(c - a);
    let area2 = n.length();
    if !(area2 > 0.0) {
        return false;
    }
    let (ds, dt) = ((s - a).dot(n) / area2, (t - a).dot(n) / area2);
    let size = s.distance(t).max(a.distance(b)).max(b.distance(c)).max(c.distance(a));
    let slack = CROSSING_SLACK * size;
    if !((ds > slack && dt < -slack) || (ds < -slack && dt > slack)) {
        return false;
    }
    let p = s + (t - s) * (ds / (ds - dt));
    let inside = |u: DVec3, v: DVec3| (v - u).cross(p - u).dot(n) >= 0.0;
    inside(a, b) && inside(b, c) && inside(c, a)
}

/// How far past a triangle's plane, relative to the size of the segment and
/// triangle, both ends of a segment must lie to count as crossing it.
pub const CROSSING_SLACK: f64 = 1e-9;

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
        // From a gathered curtain's approximation: a flat sheet, the segment
        // parallel to edge ab and 5 cm below the triangle, rounding alone
        // putting its ends on either side of the plane. Counted as a crossing
        // before the slack.
        let (s, t) = (
            v(6.384772328249361e-16, 1.3307032211630028, -0.16034668985273062),
            v(-0.013781870940024952, 1.3223832170881877, -0.09995598576563963),
        );
        let (a, b, c) = (
            v(-0.008700270218243628, 1.4377235816628566, -0.14758747335217545),
            v(-0.022482141158269218, 1.4294035775880416, -0.08719676926508446),
            v(-0.01124107057913429, 1.3800533993755222, -0.12377172955890754),
        );
        assert!(!segment_crosses_triangle(s, t, a, b, c));
        assert!(!segment_crosses_triangle(v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), a, b, a), "zero area");
    }
}
