//! Surface approximation (paper §3.1): the first 3D shape of the cloth, built
//! from catenaries between the pins before relaxation.
//!
//! 1. A candidate catenary joins every pair of pins; its arc length is the pins'
//!    material distance × elasticity. A candidate that passes through a third
//!    pin in grid space is covered by the two shorter ones and dropped. Above
//!    24 pins only local pairs are candidates — the edges of the pins' Delaunay
//!    subdivision and the alternatives across them — so that hundreds or
//!    thousands of pins (a table top pinned on a lattice) take milliseconds and
//!    memory linear in the pins rather than O(P⁴) (see `network`).
//! 2. Where two candidates cross in grid space, the lower one at the crossing is
//!    removed ("conflicting"), lowest conflict first; removed candidates that no
//!    longer cross anything come back. What is kept triangulates the pins'
//!    convex hull. Two candidates equally high at their crossing (within a
//!    billionth of the pins' spread, `TIE_TOLERANCE_OF_SPREAD`) tie: neither
//!    is higher, and keeping either would tilt the shape of mirror-symmetric
//!    pins. Ties are broken both ways — once for catenaries along the grid's
//!    main diagonal direction (i and j growing together), once for the other,
//!    which a mirror in i or in j swaps — and the catenaries and triangles of
//!    both triangulations are kept: both diagonals of a level four-corner
//!    cloth and both triangulations of their quad, overlapping.
//! 3. Grid points on a kept catenary sit on it at their arc-length fraction.
//! 4. A point p inside a triangle T is placed as the paper describes: the line
//!    from each vertex of T through p meets the opposite edge at vᵢ (on that
//!    edge's catenary); a catenary from the vertex to vᵢ gives a candidate
//!    point; p's height is the highest candidate's, x/z the candidates' blend
//!    weighted by p's barycentric coordinates. On T's edges all three
//!    candidates coincide with the edge catenary, so the surface is continuous.
//!    Points on one line through a vertex share its catenary when their edge
//!    fractions agree bit for bit; it is then solved once (same output).
//!    A point covered by several kept triangles (or on several kept catenaries),
//!    which happens only where ties gave two triangulations, takes the highest
//!    of its placements' heights and the mean of their x/z: a set function, so the
//!    result does not depend on the order of the triangles and mirror-symmetric
//!    pins give a mirror-symmetric surface. Without ties every such point lies
//!    in exactly one triangle.
//! 5. Points outside the hull, and every point when the pins are collinear or a
//!    single pin, hang down from the nearest part of the hull by their material
//!    distance × elasticity (see [`drape_direction`] for the exact rule).
//!
//! Grid-space predicates (crossings, collinearity, containment) use exact
//! integer arithmetic on grid indices: material space is grid space scaled per
//! axis, which changes no crossing, collinearity or containment.

mod delaunay;
mod interior;
mod network;

use glam::{DVec2, DVec3};

use super::catenary::Catenary;
use interior::{EdgeLookup, Placed, TrianglePlacer};
use network::{classify_layout, crossing_material, find_crossings, grid_i64, select_candidates, survivors};

/// A pinned grid point: grid index (i, j) held at `pos` (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinPoint {
    pub grid: (usize, usize),
    pub pos: DVec3,
}

/// The grid the cloth is sampled on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    pub cols: usize,
    pub rows: usize,
    /// Material spacing along u (between columns), metres.
    pub spacing_u_m: f64,
    /// Material spacing along v (between rows), metres.
    pub spacing_v_m: f64,
}

impl GridSpec {
    pub fn point_count(&self) -> usize {
        self.cols * self.rows
    }
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.cols + i
    }
    /// Material coordinates (u, v) of grid point (i, j), metres.
    pub fn material(&self, i: usize, j: usize) -> DVec2 {
        DVec2::new(i as f64 * self.spacing_u_m, j as f64 * self.spacing_v_m)
    }
}

/// A catenary between two pins (indices into [`CatenaryNetwork::pins`], `a < b`).
#[derive(Clone, Debug)]
pub struct CatenaryEdge {
    pub a: usize,
    pub b: usize,
    pub catenary: Catenary,
}

/// Where a kept catenary and a removed one crossed in grid space (tied
/// crossings, where both stay, are not conflicts).
#[derive(Clone, Copy, Debug)]
pub struct ConflictPoint {
    /// Material coordinates of the crossing, metres.
    pub material_m: DVec2,
    /// Index into [`CatenaryNetwork::kept`].
    pub kept: usize,
    /// Index into [`CatenaryNetwork::conflicting`].
    pub removed: usize,
    /// The crossing on the kept (higher) catenary.
    pub kept_pos: DVec3,
    /// The crossing on the removed (lower) catenary.
    pub removed_pos: DVec3,
}

/// How the pins are laid out in grid space.
#[derive(Clone, Debug, PartialEq)]
pub enum PinLayout {
    /// No pins: colliders hold the cloth up (see [`CatenaryNetwork::unpinned`]).
    Unpinned,
    /// One pin: the cloth hangs from a point.
    Single,
    /// All pins on one line; pin indices sorted along it.
    Collinear(Vec<usize>),
    /// Pins span an area: hull vertices (pin indices, counter-clockwise in
    /// (u, v), including pins lying on hull edges) and the kept triangles.
    /// The triangles cover the hull; they overlap only where candidates tied
    /// at a crossing and both triangulations were kept (see the module doc).
    Hull { boundary: Vec<usize>, triangles: Vec<[usize; 3]> },
}

/// The catenary network of the paper's Fig. 3b–c.
#[derive(Clone, Debug)]
pub struct CatenaryNetwork {
    pub pins: Vec<PinPoint>,
    /// The surviving catenaries. No two cross, except where ties kept two
    /// triangulations (see the module doc): catenaries of different ones may.
    pub kept: Vec<CatenaryEdge>,
    /// The catenaries removed at a crossing with a higher one.
    pub conflicting: Vec<CatenaryEdge>,
    pub conflict_points: Vec<ConflictPoint>,
    pub layout: PinLayout,
}

impl CatenaryNetwork {
    /// The network of a key without pins: nothing to hang from, no catenaries.
    pub fn unpinned() -> Self {
        CatenaryNetwork {
            pins: Vec::new(),
            kept: Vec::new(),
            conflicting: Vec::new(),
            conflict_points: Vec::new(),
            layout: PinLayout::Unpinned,
        }
    }
}

/// How a grid point got its approximated position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    Pin,
    /// On a kept catenary, at its arc-length fraction.
    OnCatenary,
    /// Inside a triangle of kept catenaries (paper's method); inside several
    /// overlapping ones where ties kept two triangulations, their highest y
    /// and mean x/z.
    Interior,
    /// Outside the pins' hull: hangs from its nearest part.
    Draped,
}

/// The approximated surface: one position per grid point in vertex order.
#[derive(Clone, Debug)]
pub struct Approximation {
    pub network: CatenaryNetwork,
    pub positions: Vec<DVec3>,
    pub placement: Vec<Placement>,
}

/// Tilt from vertical of cloth hanging below a hull edge, so it hangs just
/// outside the surface inside the hull rather than through it.
const EDGE_TILT_RAD: f64 = 8.0 * std::f64::consts::PI / 180.0;
/// Tilt of the two halves of a cloth pinned along a line through its middle,
/// so the halves do not coincide.
const FOLD_TILT_RAD: f64 = 6.0 * std::f64::consts::PI / 180.0;
/// Fold seed of draped points: amplitude in grid cells, wavelength in cells or
/// as a fraction of the cloth's width, whichever is longer.
const FOLD_SEED_AMPLITUDE_CELLS: f64 = 0.25;
const FOLD_SEED_WAVELENGTH_CELLS: f64 = 6.0;
const FOLD_SEED_WAVELENGTH_FRACTION: f64 = 0.1;
/// Largest tilt, reached in the middle of a hull corner's fan, so the material
/// around a corner spreads out instead of collapsing onto one vertical line.
const CORNER_TILT_RAD: f64 = 45.0 * std::f64::consts::PI / 180.0;

/// Two catenaries whose heights at their crossing differ by at most this
/// fraction of the pins' spread (the diagonal of their bounding box) are
/// equally high: rounding in mirrored computations stays far below it.
const TIE_TOLERANCE_OF_SPREAD: f64 = 1e-9;

/// Approximates the cloth's surface from its pins.
///
/// `pins` must be non-empty, inside the grid and without duplicate grid points
/// (scene validation guarantees it); `elasticity` ≥ 1. Every output position
/// is finite for finite pins; pins keep their positions exactly.
pub fn approximate(grid: GridSpec, pins: &[PinPoint], elasticity: f64) -> Approximation {
    assert!(!pins.is_empty(), "approximate needs at least one pin");
    let pins = pins.to_vec();
    let length_of = |a: usize, b: usize| {
        let (ma, mb) = (grid.material(pins[a].grid.0, pins[a].grid.1), grid.material(pins[b].grid.0, pins[b].grid.1));
        ma.distance(mb) * elasticity
    };

    let candidates = select_candidates(&pins, grid);
    let catenaries: Vec<Catenary> =
        candidates.pairs.iter().map(|&(a, b)| Catenary::new(pins[a].pos, pins[b].pos, length_of(a, b))).collect();
    let crossings = find_crossings(&pins, &candidates, &catenaries);
    let survivors = survivors(&pins, &candidates, &crossings, &catenaries, tie_tolerance_m(&pins));
    let alive = &survivors.alive;

    let mut kept = Vec::new();
    let mut conflicting = Vec::new();
    let mut slot = vec![0usize; candidates.pairs.len()];
    for (c, &(a, b)) in candidates.pairs.iter().enumerate() {
        let edge = CatenaryEdge { a, b, catenary: catenaries[c].clone() };
        if alive[c] {
            slot[c] = kept.len();
            kept.push(edge);
        } else {
            slot[c] = conflicting.len();
            conflicting.push(edge);
        }
    }
    let conflict_points = crossings
        .iter()
        .filter(|x| alive[x.first] != alive[x.second])
        .map(|x| {
            let (k, r, tk, tr) = if alive[x.first] {
                (x.first, x.second, x.t_first, x.t_second)
            } else {
                (x.second, x.first, x.t_second, x.t_first)
            };
            ConflictPoint {
                material_m: crossing_material(grid, &pins, candidates.pairs[k], tk),
                kept: slot[k],
                removed: slot[r],
                kept_pos: catenaries[k].point_at_arc_fraction(tk),
                removed_pos: catenaries[r].point_at_arc_fraction(tr),
            }
        })
        .collect();

    let resolutions: Vec<Vec<(usize, usize)>> = survivors
        .resolutions
        .iter()
        .map(|survives| candidates.pairs.iter().zip(survives).filter(|&(_, &s)| s).map(|(&pair, _)| pair).collect())
        .collect();
    let layout = classify_layout(&pins, &resolutions);
    let network = CatenaryNetwork { pins, kept, conflicting, conflict_points, layout };
    let (positions, placement) = place_points(grid, &network, elasticity);
    Approximation { network, positions, placement }
}

fn place_points(grid: GridSpec, network: &CatenaryNetwork, elasticity: f64) -> (Vec<DVec3>, Vec<Placement>) {
    let mut placed = Placed::new(grid.point_count());
    let pins = &network.pins;

    for pin in pins {
        placed.set(grid.index(pin.grid.0, pin.grid.1), Placement::Pin, pin.pos);
    }
    for edge in &network.kept {
        let (pa, pb) = (grid_i64(&pins[edge.a]), grid_i64(&pins[edge.b]));
        let (di, dj) = (pb.0 - pa.0, pb.1 - pa.1);
        let steps = gcd(di.unsigned_abs(), dj.unsigned_abs()) as i64;
        for s in 1..steps {
            let (i, j) = ((pa.0 + di * s / steps) as usize, (pa.1 + dj * s / steps) as usize);
            // Two kept catenaries share a grid point only where ties kept two triangulations.
            let position = edge.catenary.point_at_arc_fraction(s as f64 / steps as f64);
            placed.cover(grid.index(i, j), Placement::OnCatenary, position);
        }
    }

    if let PinLayout::Hull { triangles, .. } = &network.layout {
        let mut placer = TrianglePlacer::new(grid, network, pins.iter().map(grid_i64).collect(), elasticity);
        for tri in triangles {
            placer.place(*tri, &mut placed);
        }
    }

    let drape = DrapeFrame::new(grid, network);
    let sheet_normal = drape.world_per_u.cross(drape.world_per_v).normalize_or(DVec3::Z);
    let fold_wavelength_m = (FOLD_SEED_WAVELENGTH_CELLS * grid.spacing_u_m)
        .max(FOLD_SEED_WAVELENGTH_FRACTION * grid.spacing_u_m * (grid.cols - 1) as f64);
    for j in 0..grid.rows {
        for i in 0..grid.cols {
            let k = grid.index(i, j);
            if placed.placement[k].is_none() {
                let m = grid.material(i, j);
                let (hang, distance_m) = drape.position(m, elasticity);
                // A flat sheet squeezed in its own plane cannot fold out of it during
                // relaxation; a faint ripple across it lets slack buckle into folds.
                // Even about the middle column (measured from it in exact half
                // cells), so a mirror-symmetric cloth gets a mirror-symmetric seed.
                let from_middle_m = (2.0 * i as f64 - (grid.cols - 1) as f64) * (0.5 * grid.spacing_u_m);
                let ripple = (std::f64::consts::TAU * from_middle_m / fold_wavelength_m).cos()
                    * FOLD_SEED_AMPLITUDE_CELLS
                    * grid.spacing_u_m
                    * (distance_m / fold_wavelength_m).min(1.0);
                placed.set(k, Placement::Draped, hang + sheet_normal * ripple);
            }
        }
    }
    placed.finish()
}

/// Heights at a crossing closer than this are a tie (see [`TIE_TOLERANCE_OF_SPREAD`]).
fn tie_tolerance_m(pins: &[PinPoint]) -> f64 {
    let (low, high) = pins
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(low, high), pin| (low.min(pin.pos), high.max(pin.pos)));
    TIE_TOLERANCE_OF_SPREAD * (high - low).length()
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The frame that hangs points outside the pins' hull.
///
/// A point p at material distance r from its nearest hull point q hangs from q
/// by r × elasticity along [`drape_direction`]. Below a hull edge it hangs
/// straight down, tilted slightly outwards; around a hull corner the tilt grows
/// towards the middle of the corner's fan so the corner's material spreads out
/// instead of collapsing onto one line. A single pin hangs the cloth flat in a
/// vertical plane with its centroid straight below the pin.
struct DrapeFrame<'a> {
    grid: GridSpec,
    network: &'a CatenaryNetwork,
    lookup: EdgeLookup<'a>,
    /// Hull boundary (closed) or the pins along their line (open), as pin indices.
    boundary: Vec<usize>,
    /// Material-to-world linear map: world offset per metre along u and v.
    world_per_u: DVec3,
    world_per_v: DVec3,
    /// Tilt of cloth hanging from the middle of a boundary segment.
    edge_tilt_rad: f64,
    /// Centroid of the pins in material space (orients outward normals).
    pin_centroid: DVec2,
}

impl<'a> DrapeFrame<'a> {
    fn new(grid: GridSpec, network: &'a CatenaryNetwork) -> Self {
        let pins = &network.pins;
        let material: Vec<DVec2> = pins.iter().map(|p| grid.material(p.grid.0, p.grid.1)).collect();
        let pin_centroid = material.iter().copied().sum::<DVec2>() / pins.len() as f64;
        let (boundary, world_per_u, world_per_v, edge_tilt_rad) = match &network.layout {
            // `approximate` never builds a frame without pins; a level sheet if it did.
            PinLayout::Unpinned => (Vec::new(), DVec3::X, DVec3::Z, 0.0),
            PinLayout::Single => (vec![0], DVec3::X, DVec3::NEG_Y, 0.0),
            PinLayout::Collinear(order) => {
                let (first, last) = (order[0], order[order.len() - 1]);
                let along_m = (material[last] - material[first]).normalize();
                let along_world = (pins[last].pos - pins[first].pos).normalize_or(DVec3::X);
                // The flat sheet through the pin line that hangs lowest: material
                // offsets across the line go to the downward direction across it.
                let down_across = (DVec3::NEG_Y - along_world * along_world.dot(DVec3::NEG_Y))
                    .try_normalize()
                    .unwrap_or_else(|| horizontal_perpendicular(along_world));
                let across_m = along_m.perp();
                let world_per_u = along_world * along_m.x + down_across * across_m.x;
                let world_per_v = along_world * along_m.y + down_across * across_m.y;
                // Cloth on both sides of the line: tilt the halves apart.
                let sides = grid_corners(grid).map(|c| (c - material[first]).perp_dot(along_m));
                let two_sided = sides.iter().any(|&s| s > 1e-9) && sides.iter().any(|&s| s < -1e-9);
                (order.clone(), world_per_u, world_per_v, if two_sided { FOLD_TILT_RAD } else { 0.0 })
            }
            PinLayout::Hull { boundary, .. } => {
                let (u, v) = fit_linear_map(&material, pins);
                (boundary.clone(), u, v, EDGE_TILT_RAD)
            }
        };
        DrapeFrame {
            grid,
            network,
            lookup: EdgeLookup::new(&network.kept),
            boundary,
            world_per_u,
            world_per_v,
            edge_tilt_rad,
            pin_centroid,
        }
    }

    fn pin_material(&self, pin: usize) -> DVec2 {
        let g = self.network.pins[pin].grid;
        self.grid.material(g.0, g.1)
    }

    /// Horizontal world direction of a material direction (unit), or any
    /// horizontal unit vector when the map sends it straight up or down.
    fn horizontal_of(&self, material_dir: DVec2) -> DVec3 {
        let world = self.world_per_u * material_dir.x + self.world_per_v * material_dir.y;
        let normal = self.world_per_u.cross(self.world_per_v);
        [world, normal, DVec3::X]
            .into_iter()
            .map(|w| DVec3::new(w.x, 0.0, w.z))
            .find(|h| h.length() > 1e-9)
            .map_or(DVec3::X, DVec3::normalize)
    }

    /// The draped position of material point `m` and its material distance
    /// from the point it hangs from.
    fn position(&self, m: DVec2, elasticity: f64) -> (DVec3, f64) {
        match self.network.layout {
            PinLayout::Unpinned => {
                return ((self.world_per_u * m.x + self.world_per_v * m.y) * elasticity, 0.0);
            }
            PinLayout::Single => return self.single_pin_position(m, elasticity),
            PinLayout::Collinear(_) => return self.collinear_position(m, elasticity),
            PinLayout::Hull { .. } => {}
        }
        let segments = self.boundary.len();
        // Nearest point on the boundary: (distance², segment, fraction).
        let mut best = (f64::INFINITY, 0usize, 0.0f64);
        for s in 0..segments {
            let (a, b) = (self.boundary[s], self.boundary[(s + 1) % self.boundary.len()]);
            let (ma, mb) = (self.pin_material(a), self.pin_material(b));
            let d = mb - ma;
            let t = ((m - ma).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            let dist2 = m.distance_squared(ma + d * t);
            if dist2 < best.0 - 1e-15 {
                best = (dist2, s, t);
            }
        }
        let (_, s, t) = best;
        let (a, b) = (self.boundary[s], self.boundary[(s + 1) % self.boundary.len()]);
        let (ma, mb) = (self.pin_material(a), self.pin_material(b));
        let q_material = ma.lerp(mb, t);
        let offset = m - q_material;
        let r = offset.length();
        if r < 1e-12 {
            return (self.lookup.point(a, b, t), 0.0);
        }
        let w = offset / r;
        let at_start = t <= 0.0;
        let at_end = t >= 1.0;
        let is_corner = at_start || at_end;
        let (q, tilt) = if is_corner {
            let corner_pos = if at_start { s } else { (s + 1) % self.boundary.len() };
            let corner = self.boundary[corner_pos];
            (self.network.pins[corner].pos, self.corner_tilt(corner_pos, w))
        } else {
            (self.lookup.point(a, b, t), self.edge_tilt_rad)
        };
        (q + drape_direction(self.horizontal_of(w), tilt) * (r * elasticity), r)
    }

    /// Tilt around hull corner `boundary[pos]`: the edge tilt at the fan's sides,
    /// [`CORNER_TILT_RAD`] in its middle.
    fn corner_tilt(&self, pos: usize, w: DVec2) -> f64 {
        let n = self.boundary.len();
        let corner = self.pin_material(self.boundary[pos]);
        let outward = |from: DVec2, to: DVec2| {
            let normal = (to - from).perp().normalize();
            if normal.dot((from + to) * 0.5 - self.pin_centroid) < 0.0 { -normal } else { normal }
        };
        let prev = self.pin_material(self.boundary[(pos + n - 1) % n]);
        let next = self.pin_material(self.boundary[(pos + 1) % n]);
        let (n1, n2) = (outward(prev, corner), outward(corner, next));
        let fan = n1.angle_to(n2).abs();
        let fraction = if fan < 1e-9 { 0.0 } else { (n1.angle_to(w).abs() / fan).clamp(0.0, 1.0) };
        let fan_weight = (std::f64::consts::PI * fraction).sin();
        self.edge_tilt_rad + (CORNER_TILT_RAD - self.edge_tilt_rad) * fan_weight
    }

    /// Pins on one line: the cloth is the flat sheet through the line that
    /// hangs lowest (straight down from a horizontal line, flying out
    /// horizontally from a vertical pole), each point hanging from its foot on
    /// the pins' catenaries; beyond the line's ends the sheet continues flat.
    fn collinear_position(&self, m: DVec2, elasticity: f64) -> (DVec3, f64) {
        let pins = &self.network.pins;
        let (first, last) = (self.boundary[0], self.boundary[self.boundary.len() - 1]);
        let (m_first, m_last) = (self.pin_material(first), self.pin_material(last));
        let span_m = m_first.distance(m_last);
        let along_m = (m_last - m_first) / span_m;
        let along_world = (pins[last].pos - pins[first].pos).normalize_or(DVec3::X);
        let down_across = self.world_per_u * along_m.perp().x + self.world_per_v * along_m.perp().y;
        let a = (m - m_first).dot(along_m);
        let across = (m - m_first).dot(along_m.perp());
        let foot = if a <= 0.0 {
            pins[first].pos + along_world * (a * elasticity)
        } else if a >= span_m {
            pins[last].pos + along_world * ((a - span_m) * elasticity)
        } else {
            // The first segment whose far end is at or past `a` (pins are sorted along the line).
            let segment = self.boundary[1..]
                .partition_point(|&pin| (self.pin_material(pin) - m_first).dot(along_m) < a)
                .min(self.boundary.len() - 2);
            let (sa, sb) = (self.boundary[segment], self.boundary[segment + 1]);
            let (a0, a1) =
                ((self.pin_material(sa) - m_first).dot(along_m), (self.pin_material(sb) - m_first).dot(along_m));
            self.lookup.point(sa, sb, ((a - a0) / (a1 - a0)).clamp(0.0, 1.0))
        };
        // Rotate each half about the line by the fold tilt so two halves never coincide.
        let tilt = self.edge_tilt_rad * across.signum();
        let hang = down_across * tilt.cos() + along_world.cross(down_across) * tilt.sin();
        (foot + hang * (across.abs() * elasticity), across.abs())
    }

    /// One pin: a flat vertical sheet whose material centroid hangs straight
    /// below the pin; fans wider than a half-turn are squeezed into it.
    fn single_pin_position(&self, m: DVec2, elasticity: f64) -> (DVec3, f64) {
        let pin = &self.network.pins[0];
        let anchor = self.pin_material(0);
        let offset = m - anchor;
        let r = offset.length();
        if r < 1e-12 {
            return (pin.pos, 0.0);
        }
        let centre = (grid_corners(self.grid).iter().copied().sum::<DVec2>() / 4.0) - anchor;
        let down_m = if centre.length() > 1e-9 { centre.normalize() } else { DVec2::Y };
        let widest = grid_corners(self.grid)
            .iter()
            .map(|&c| c - anchor)
            .filter(|c| c.length() > 1e-12)
            .map(|c| down_m.angle_to(c).abs())
            .fold(0.0f64, f64::max);
        let squeeze = if widest > std::f64::consts::FRAC_PI_2 { std::f64::consts::FRAC_PI_2 / widest } else { 1.0 };
        let angle = down_m.angle_to(offset) * squeeze;
        (pin.pos + (DVec3::NEG_Y * angle.cos() + DVec3::X * angle.sin()) * (r * elasticity), r)
    }
}

/// Unit direction that points down, tilted by `tilt_rad` towards the horizontal `outward`.
pub fn drape_direction(outward: DVec3, tilt_rad: f64) -> DVec3 {
    DVec3::NEG_Y * tilt_rad.cos() + outward * tilt_rad.sin()
}

fn grid_corners(grid: GridSpec) -> [DVec2; 4] {
    [
        grid.material(0, 0),
        grid.material(grid.cols - 1, 0),
        grid.material(0, grid.rows - 1),
        grid.material(grid.cols - 1, grid.rows - 1),
    ]
}

/// A horizontal unit vector perpendicular to `along` (X when `along` is vertical).
fn horizontal_perpendicular(along: DVec3) -> DVec3 {
    along.cross(DVec3::Y).try_normalize().unwrap_or(DVec3::X)
}

/// Least-squares affine fit world ≈ U·u + V·v + c from the pins (≥ 3, not
/// collinear); returns (U, V), the world offset per material metre along u, v.
fn fit_linear_map(material: &[DVec2], pins: &[PinPoint]) -> (DVec3, DVec3) {
    let n = material.len() as f64;
    let mean_m = material.iter().copied().sum::<DVec2>() / n;
    let mean_w = pins.iter().map(|p| p.pos).sum::<DVec3>() / n;
    let (mut suu, mut suv, mut svv) = (0.0, 0.0, 0.0);
    let (mut su_w, mut sv_w) = (DVec3::ZERO, DVec3::ZERO);
    for (m, p) in material.iter().zip(pins) {
        let (dm, dw) = (*m - mean_m, p.pos - mean_w);
        suu += dm.x * dm.x;
        suv += dm.x * dm.y;
        svv += dm.y * dm.y;
        su_w += dw * dm.x;
        sv_w += dw * dm.y;
    }
    let det = suu * svv - suv * suv;
    if det.abs() < 1e-18 {
        return (DVec3::X, DVec3::NEG_Y);
    }
    ((su_w * svv - sv_w * suv) / det, (sv_w * suu - su_w * suv) / det)
}
