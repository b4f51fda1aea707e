//! Which side of a triangle mesh a point is on, from the feature nearest
//! it: the angle-weighted pseudo-normals of Bærentzen and Aanæs, worked
//! out from the current vertices when a query needs one rather than for
//! the whole mesh at every pose (a posed body is queried near a few
//! hundred of its twenty thousand triangles).

use std::collections::HashMap;

use glam::DVec3;

/// Where on its triangle the nearest point lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    Face,
    /// Edge `i` runs from corner `i` to corner `(i + 1) % 3`.
    Edge(u8),
    Vertex(u8),
}

/// The triangles around each edge and each vertex, fixed by the topology
/// alone, so one table serves every pose of a mesh. Lists are in
/// triangle order, so sums come out the same bit for bit.
#[derive(Debug)]
pub struct MeshSides {
    /// Each triangle's three edges, as indices into `edge_start`.
    triangle_edges: Vec<[u32; 3]>,
    /// The triangles along edge e: `edge_triangles[edge_start[e]..edge_start[e + 1]]`.
    edge_start: Vec<u32>,
    edge_triangles: Vec<u32>,
    /// The corners at vertex v (triangle · 3 + corner):
    /// `vertex_corners[vertex_start[v]..vertex_start[v + 1]]`.
    vertex_start: Vec<u32>,
    vertex_corners: Vec<u32>,
    /// Every edge joins two triangles that run along it in opposite
    /// directions: the mesh bounds a solid with no hole.
    closed: bool,
}

impl MeshSides {
    pub fn new(vertex_count: usize, indices: &[[u32; 3]]) -> MeshSides {
        let mut edge_of: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() * 3 / 2);
        let mut triangle_edges = Vec::with_capacity(indices.len());
        // Per edge: triangles running from its lower vertex, and from its higher.
        let mut runs: Vec<[u32; 2]> = Vec::with_capacity(indices.len() * 3 / 2);
        for t in indices {
            let edges = [0, 1, 2].map(|i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let next = edge_of.len() as u32;
                let e = *edge_of.entry((a.min(b), a.max(b))).or_insert(next);
                if e == next {
                    runs.push([0, 0]);
                }
                runs[e as usize][usize::from(a > b)] += 1;
                e
            });
            triangle_edges.push(edges);
        }
        let closed = runs.iter().all(|&r| r == [1, 1]);
        let edge_count = edge_of.len();
        let (edge_start, edge_triangles) =
            compressed(edge_count, triangle_edges.iter().enumerate().flat_map(|(t, es)| es.map(|e| (e, t as u32))));
        let corners =
            indices.iter().enumerate().flat_map(|(t, c)| (0..3).map(move |i| (c[i], t as u32 * 3 + i as u32)));
        let (vertex_start, vertex_corners) = compressed(vertex_count, corners);
        MeshSides { triangle_edges, edge_start, edge_triangles, vertex_start, vertex_corners, closed }
    }

    /// Every edge joins two triangles running along it in opposite
    /// directions: a closed, consistently wound surface.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The pseudo-normal at `feature` of triangle `triangle` (not unit
    /// length; `vertex` gives each vertex's position): a point is inside
    /// where its offset from its nearest surface point has a negative dot
    /// product with it.
    pub fn pseudo_normal(
        &self,
        vertex: &impl Fn(u32) -> DVec3,
        indices: &[[u32; 3]],
        triangle: usize,
        feature: Feature,
    ) -> DVec3 {
        let corner = |t: usize, i: usize| vertex(indices[t][i]);
        let normal = |t: usize| (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0));
        let unit_normal = |t: usize| normal(t).try_normalize();
        match feature {
            Feature::Face => normal(triangle),
            Feature::Edge(i) => {
                let e = self.triangle_edges[triangle][usize::from(i)] as usize;
                let around = &self.edge_triangles[self.edge_start[e] as usize..self.edge_start[e + 1] as usize];
                around.iter().filter_map(|&t| unit_normal(t as usize)).sum()
            }
            Feature::Vertex(i) => {
                let v = indices[triangle][usize::from(i)] as usize;
                let around = &self.vertex_corners[self.vertex_start[v] as usize..self.vertex_start[v + 1] as usize];
                around
                    .iter()
                    .filter_map(|&c| {
                        let (t, i) = ((c / 3) as usize, (c % 3) as usize);
                        let n = unit_normal(t)?;
                        let at = corner(t, i);
                        Some(n * (corner(t, (i + 1) % 3) - at).angle_between(corner(t, (i + 2) % 3) - at))
                    })
                    .sum()
            }
        }
    }
}

/// A list of `(key, value)` pairs as offsets and values grouped by key
/// (`keys` keys), each group in the order given.
fn compressed(keys: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; keys + 1];
    for (key, _) in pairs.clone() {
        start[key as usize + 1] += 1;
    }
    for k in 0..keys {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut values = vec![0u32; start[keys] as usize];
    for (key, value) in pairs {
        values[fill[key as usize] as usize] = value;
        fill[key as usize] += 1;
    }
    (start, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_corner_points_out_along_its_diagonal() {
        let vertices = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        // Wound outwards.
        let indices = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let sides = MeshSides::new(4, &indices);
        let vertex = |i: u32| vertices[i as usize];
        let at_origin = sides.pseudo_normal(&vertex, &indices, 0, Feature::Vertex(0));
        assert!(at_origin.normalize().abs_diff_eq(-DVec3::ONE.normalize(), 1e-12), "{at_origin}");
        // The edge along x between the faces facing -y and -z.
        let on_x = sides.pseudo_normal(&vertex, &indices, 1, Feature::Edge(0));
        assert!(on_x.abs_diff_eq(DVec3::new(0.0, -1.0, -1.0), 1e-12), "{on_x}");
        let face = sides.pseudo_normal(&vertex, &indices, 3, Feature::Face);
        assert!(face.normalize().abs_diff_eq(DVec3::ONE.normalize(), 1e-12), "{face}");
        assert!(sides.is_closed());
        assert!(!MeshSides::new(4, &indices[..3]).is_closed(), "a face missing");
        let flipped = [[0, 1, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        assert!(!MeshSides::new(4, &flipped).is_closed(), "a face wound the wrong way");
    }
}
