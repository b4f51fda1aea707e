//! Closest points between a segment and a triangle: how far apart two parts
//! of the cloth are, and which way to move them to part them.

use glam::DVec3;

/// The closest points of segment `s → t` and triangle `(a, b, c)`:
/// (distance, point on the segment, point on the triangle). Where they meet
/// the distance is 0 and both points are where the segment passes the
/// triangle. A zero-area triangle is treated as its edges; a zero-length
/// segment as its point.
///
/// Between a segment and a triangle that do not meet, the closest points
/// are an end of the segment and its nearest point on the triangle, or the
/// segment and one of the triangle's edges, so those are all that is looked at.
pub fn segment_triangle_closest(s: DVec3, t: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (f64, DVec3, DVec3) {
    if let Some(p) = segment_meets_triangle(s, t, a, b, c) {
        return (0.0, p, p);
    }
    let mut best = (f64::INFINITY, s, a);
    let mut keep = |(p, q): (DVec3, DVec3)| {
        let d2 = p.distance_squared(q);
        if d2 < best.0 {
            best = (d2, p, q);
        }
    };
    keep((s, point_triangle_closest(s, a, b, c)));
    keep((t, point_triangle_closest(t, a, b, c)));
    keep(segment_segment_closest(s, t, a, b));
    keep(segment_segment_closest(s, t, b, c));
    keep(segment_segment_closest(s, t, c, a));
    (best.0.sqrt(), best.1, best.2)
}

/// Where the segment meets the triangle's interior or boundary, if it
/// crosses the triangle's plane there (a segment lying in the plane is left
/// to the edge distances).
fn segment_meets_triangle(s: DVec3, t: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<DVec3> {
    let n = (b - a).cross(c - a);
    let (ds, dt) = ((s - a).dot(n), (t - a).dot(n));
    if !((ds >= 0.0 && dt <= 0.0) || (ds <= 0.0 && dt >= 0.0)) || ds == dt {
        return None;
    }
    let p = s + (t - s) * (ds / (ds - dt));
    let side = |u: DVec3, v: DVec3| (v - u).cross(p - u).dot(n) >= 0.0;
    (side(a, b) && side(b, c) && side(c, a)).then_some(p)
}

/// The point of triangle `(a, b, c)` nearest to `p`.
fn point_triangle_closest(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let n = (b - a).cross(c - a);
    let n2 = n.length_squared();
    if n2 > 0.0 {
        let q = p - n * ((p - a).dot(n) / n2);
        let side = |u: DVec3, v: DVec3| (v - u).cross(q - u).dot(n) >= 0.0;
        if side(a, b) && side(b, c) && side(c, a) {
            return q;
        }
    }
    let on_edges = [segment_point_closest(a, b, p), segment_point_closest(b, c, p), segment_point_closest(c, a, p)];
    on_edges
        .into_iter()
        .fold(on_edges[0], |best, q| if q.distance_squared(p) < best.distance_squared(p) { q } else { best })
}

/// The point of segment `a → b` nearest to `p`.
fn segment_point_closest(a: DVec3, b: DVec3, p: DVec3) -> DVec3 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let u = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    a + ab * u
}

/// The closest points of segments `p1 → q1` and `p2 → q2`.
fn segment_segment_closest(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    if a <= 0.0 && e <= 0.0 {
        return (p1, p2);
    }
    if a <= 0.0 {
        return (p1, segment_point_closest(p2, q2, p1));
    }
    if e <= 0.0 {
        return (segment_point_closest(p1, q1, p2), p2);
    }
    let (b, c) = (d1.dot(d2), d1.dot(r));
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (p1 + d1 * s, p2 + d2 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    fn distance(s: DVec3, t: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let (d, p, q) = segment_triangle_closest(s, t, a, b, c);
        assert!((p.distance(q) - d).abs() < 1e-15, "the points are the distance apart");
        d
    }

    #[test]
    fn distances_between_segments_and_triangles_match_hand_computed_ones() {
        let (a, b, c) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
        // Above the interior, along the normal: the nearer end and its foot.
        let (d, p, q) = segment_triangle_closest(v(0.2, 0.2, 0.5), v(0.2, 0.2, 2.0), a, b, c);
        assert!((d - 0.5).abs() < 1e-15);
        assert_eq!((p, q), (v(0.2, 0.2, 0.5), v(0.2, 0.2, 0.0)));
        // Through the interior: where it passes.
        let (d, p, q) = segment_triangle_closest(v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), a, b, c);
        assert_eq!((d, p, q), (0.0, v(0.2, 0.2, 0.0), v(0.2, 0.2, 0.0)));
        // Beside edge ab, parallel to it, in the plane: 0.3 away.
        assert!((distance(v(0.2, -0.3, 0.0), v(0.8, -0.3, 0.0), a, b, c) - 0.3).abs() < 1e-15);
        // Across the hypotenuse, 0.4 above the plane.
        assert!((distance(v(1.0, 1.0, 0.4), v(0.0, 0.0, 0.4), a, b, c) - 0.4).abs() < 1e-12);
        // Skew to edge bc, passing 0.3 beyond it.
        let m = v(0.5, 0.5, 0.0) + v(1.0, 1.0, 0.0).normalize() * 0.3;
        assert!((distance(m - v(0.0, 0.0, 1.0), m + v(0.0, 0.0, 1.0), a, b, c) - 0.3).abs() < 1e-12);
        // Beyond a corner: point distance.
        assert!((distance(v(-0.3, -0.4, 0.0), v(-3.0, -4.0, 0.0), a, b, c) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn degenerate_segments_and_triangles_give_distances_not_nans() {
        let (a, b) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        assert!((distance(v(0.5, 0.2, -1.0), v(0.5, 0.2, 1.0), a, b, b) - 0.2).abs() < 1e-15, "zero area");
        let p = v(0.3, 0.3, 0.7);
        assert!((distance(p, p, a, b, v(0.0, 1.0, 0.0)) - 0.7).abs() < 1e-15, "zero length");
    }
}
