//! What a rest shape converges to: the scene alone decides it. The same
//! cloth hangs the same from any sweep cap that converges, mirror-symmetric
//! pins give a mirror-symmetric drape, and a finer grid is the same cloth
//! in more detail.

use drape::scene::{Cloth, Ease, Key, Pin, RelaxSettings};
use drape::shape::RestShape;
use glam::DVec3;

/// A pin at a material fraction (0..1 along width and height) and a position.
type PinAt = ((f64, f64), (f64, f64, f64));

/// A cloth of `size` metres on a `grid`, hanging from `pins` given by their
/// material fraction (0..1 along width and height) and position.
struct Setup {
    size: (f64, f64),
    pins: Vec<PinAt>,
    elasticity: f64,
    stiffness: f64,
}

impl Setup {
    /// Pin grid indices on a `cols × rows` grid; fractions must land on grid points.
    fn key(&self, cols: u32, rows: u32, relax: RelaxSettings) -> Key {
        let pins = self
            .pins
            .iter()
            .map(|&((fu, fv), pos)| {
                let (i, j) = (fu * (cols - 1) as f64, fv * (rows - 1) as f64);
                assert!(
                    i.fract() == 0.0 && j.fract() == 0.0,
                    "pin fraction ({fu}, {fv}) is off the {cols} × {rows} grid"
                );
                Pin::at((i as u32, j as u32), pos)
            })
            .collect();
        Key {
            frame: 0,
            pins,
            elasticity: self.elasticity,
            stiffness: self.stiffness,
            relax,
            ease: Ease::EaseInOut,
            inbetween_relax: 0,
            thickness: drape::scene::DEFAULT_THICKNESS_M,
            friction: drape::scene::DEFAULT_FRICTION,
            placement: None,
        }
    }

    fn shape(&self, cols: u32, rows: u32, relax: RelaxSettings) -> RestShape {
        let cloth = Cloth::new(self.size, (cols, rows));
        RestShape::build(&cloth, &self.key(cols, rows, relax))
    }
}

fn settings(iterations: u32, tolerance: f64) -> RelaxSettings {
    RelaxSettings { iterations, tolerance }
}

/// A 1 m square held at its four corners, level, 0.8 m apart.
fn four_corners(elasticity: f64) -> Setup {
    let h = 0.4;
    Setup {
        size: (1.0, 1.0),
        pins: vec![
            ((0.0, 0.0), (-h, 1.0, -h)),
            ((1.0, 0.0), (h, 1.0, -h)),
            ((0.0, 1.0), (-h, 1.0, h)),
            ((1.0, 1.0), (h, 1.0, h)),
        ],
        elasticity,
        stiffness: 0.2,
    }
}

/// A 1 m square curtain hung from its two top corners 0.8 m apart.
fn curtain() -> Setup {
    Setup {
        size: (1.0, 1.0),
        pins: vec![((0.0, 0.0), (-0.4, 2.0, 0.0)), ((1.0, 0.0), (0.4, 2.0, 0.0))],
        elasticity: 1.1,
        stiffness: 0.2,
    }
}

/// The bundled tent: four low corners and a raised centre.
fn tent() -> Setup {
    Setup {
        size: (2.0, 2.0),
        pins: vec![
            ((0.0, 0.0), (-0.8, 0.0, -0.8)),
            ((1.0, 0.0), (0.8, 0.0, -0.8)),
            ((0.0, 1.0), (-0.8, 0.0, 0.8)),
            ((1.0, 1.0), (0.8, 0.0, 0.8)),
            ((0.5, 0.5), (0.0, 0.8, 0.0)),
        ],
        elasticity: 1.05,
        stiffness: 0.3,
    }
}

fn largest_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

fn lowest(shape: &RestShape) -> f64 {
    shape.relaxed.iter().map(|p| p.y).fold(f64::INFINITY, f64::min)
}

/// The sweep cap only stops a relaxation that has not settled: every cap it
/// settles within gives the same shape, bit for bit, and one too small to
/// settle says so. (Before, the coarsest level's settling pull lasted half the
/// cap, and a four-corner drape moved by up to 189 mm from 200 to 5000 sweeps.)
#[test]
fn the_same_drape_from_any_sweep_cap_that_converges() {
    for (name, setup, side) in
        [("four corners", four_corners(1.2), 33), ("curtain", curtain(), 33), ("tent", tent(), 33)]
    {
        let reference = setup.shape(side, side, settings(5000, 1e-5));
        assert!(reference.relax_report.converged, "{name}: {:?}", reference.relax_report);
        for cap in [reference.relax_report.iterations, 1000, 2000] {
            let shape = setup.shape(side, side, settings(cap, 1e-5));
            assert!(shape.relax_report.converged, "{name}, cap {cap}: {:?}", shape.relax_report);
            eprintln!("{name}, cap {cap}: {} sweeps, lowest {:.4} m", shape.relax_report.iterations, lowest(&shape));
            assert_eq!(shape.relaxed, reference.relaxed, "{name}, cap {cap}: not the shape cap 5000 gives");
        }
        let short = setup.shape(side, side, settings(reference.relax_report.iterations / 2, 1e-5));
        assert!(!short.relax_report.converged, "{name}: half the sweeps it needs cannot have settled it");
    }
}

/// A tighter tolerance refines the shape a little; it does not move it. Not
/// yet for the tent: momentum carries a slow slide that the per-sweep moves
/// do not count, and 1e-5 ends 14 mm from 1e-7 (BENCHMARKS.md).
#[test]
fn a_tighter_tolerance_moves_a_settled_drape_by_little() {
    for (name, setup) in [("four corners", four_corners(1.2)), ("curtain", curtain())] {
        let settled = setup.shape(33, 33, settings(20_000, 1e-5));
        let tight = setup.shape(33, 33, settings(20_000, 1e-7));
        assert!(settled.relax_report.converged && tight.relax_report.converged, "{name}");
        let apart = largest_distance(&settled.relaxed, &tight.relaxed);
        eprintln!("{name}: tolerance 1e-5 is {:.3} mm from 1e-7", apart * 1e3);
        assert!(apart < 2e-3, "{name}: tolerance 1e-5 is {:.2} mm from 1e-7", apart * 1e3);
    }
}

/// Largest distance between a point and the mirror image of its mirror
/// point, for the mirror across i and the one across j (mirroring world x
/// and world z, the pins' symmetry planes through the origin).
fn mirror_asymmetry(shape: &RestShape) -> (f64, f64) {
    let (cols, rows) = (shape.grid.cols, shape.grid.rows);
    let at = |i: usize, j: usize| shape.relaxed[j * cols + i];
    let (mut across_i, mut across_j) = (0.0f64, 0.0f64);
    for j in 0..rows {
        for i in 0..cols {
            let p = at(i, j);
            let mi = at(cols - 1 - i, j);
            across_i = across_i.max(p.distance(DVec3::new(-mi.x, mi.y, mi.z)));
            let mj = at(i, rows - 1 - j);
            across_j = across_j.max(p.distance(DVec3::new(mj.x, mj.y, -mj.z)));
        }
    }
    (across_i, across_j)
}

#[test]
fn mirror_symmetric_pins_give_a_mirror_symmetric_drape() {
    let default = RelaxSettings::default();
    for (name, setup, side, both) in [
        ("four corners, even", four_corners(1.2), 32, true),
        ("four corners, odd", four_corners(1.2), 33, true),
        ("four corners, level tablecloth", four_corners(1.05), 40, true),
        ("tent", tent(), 33, true),
        ("curtain", curtain(), 33, false),
    ] {
        let shape = setup.shape(side, side, default.clone());
        let (across_i, across_j) = mirror_asymmetry(&shape);
        eprintln!("{name}: {:.4} mm across i, {:.4} mm across j", across_i * 1e3, across_j * 1e3);
        assert!(across_i < 1e-4, "{name}: {:.3} mm asymmetric across i", across_i * 1e3);
        if both {
            assert!(across_j < 1e-4, "{name}: {:.3} mm asymmetric across j", across_j * 1e3);
        }
    }
}

/// Largest distance between the points two grids share (the coarse grid's
/// points, which the fine grid has too when (fine − 1) is a multiple of
/// (coarse − 1)).
fn shared_point_distance(coarse: &RestShape, fine: &RestShape) -> f64 {
    let step = (fine.grid.cols - 1) / (coarse.grid.cols - 1);
    let mut largest = 0.0f64;
    for j in 0..coarse.grid.rows {
        for i in 0..coarse.grid.cols {
            let p = coarse.relaxed[j * coarse.grid.cols + i];
            let q = fine.relaxed[j * step * fine.grid.cols + i * step];
            largest = largest.max(p.distance(q));
        }
    }
    largest
}

#[test]
fn a_finer_grid_is_the_same_cloth_in_more_detail() {
    let relax = settings(4000, 1e-5);
    // A grid coarser than the solver's (fewer than 33 points a side) is drawn
    // from a relaxation with its cells split: on its own 13 cm cells the tent
    // at 17² would be 28 mm off, worst beside a corner pin.
    for (name, setup, sides) in [("tablecloth", four_corners(1.05), &[17, 33, 65][..]), ("tent", tent(), &[17, 33, 65])]
    {
        let finest = setup.shape(129, 129, relax.clone());
        assert!(finest.relax_report.converged, "{name}: {:?}", finest.relax_report);
        for &side in sides {
            let shape = setup.shape(side, side, relax.clone());
            assert!(shape.relax_report.converged, "{name} at {side}²: {:?}", shape.relax_report);
            let apart = shared_point_distance(&shape, &finest);
            eprintln!("{name} at {side}²: {:.2} mm from 129² at shared points", apart * 1e3);
            assert!(apart < 0.01, "{name} at {side}²: {:.1} mm from 129²", apart * 1e3);
        }
    }
}

#[test]
fn a_curtain_hangs_as_deep_and_as_wide_on_any_grid() {
    let relax = settings(4000, 1e-5);
    let measure = |shape: &RestShape| {
        let xs = shape.relaxed.iter().map(|p| p.x);
        let width = xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min);
        (lowest(shape), width)
    };
    let (depth, width) = measure(&curtain().shape(129, 129, relax.clone()));
    for side in [17, 33, 65] {
        let (d, w) = measure(&curtain().shape(side, side, relax.clone()));
        eprintln!("curtain at {side}²: lowest {d:.4} m (129²: {depth:.4}), width {w:.4} m (129²: {width:.4})");
        assert!((d - depth).abs() < 0.01, "curtain at {side}²: lowest point {d:.4} m, 129² {depth:.4} m");
        assert!((w - width).abs() < 0.01, "curtain at {side}²: width {w:.4} m, 129² {width:.4} m");
    }
}
