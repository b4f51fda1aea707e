//! The generalized winding number, for telling inside from outside in
//! tests by a rule that does not depend on which surface is nearest.

use glam::DVec3;

/// The generalized winding number of the closed mesh `(vertices, triangles)`
/// around `p`: 1 inside, 0 outside (the sum of the triangles' signed solid
/// angles over 4π). The walker is sixteen closed parts that pass into each
/// other, and inside one, next to another's buried surface, the nearest
/// triangle's side says "outside"; this does not.
pub fn winding_number((vertices, triangles): &(Vec<DVec3>, &[[u32; 3]]), p: DVec3) -> f64 {
    let solid_angles: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize] - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let below = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            2.0 * a.dot(b.cross(c)).atan2(below)
        })
        .sum();
    solid_angles / (4.0 * std::f64::consts::PI)
}
