//! Symmetric in, symmetric out: mirror-symmetric pins give a mirror-symmetric
//! rest shape at default settings, for both mirrors, on even and odd grids.

use drape::scene::{Cloth, Ease, Key, Pin, RelaxSettings};
use drape::shape::RestShape;
use glam::DVec3;

/// A pin: where on the material (fractions of width and height) and where in the world (metres).
type MaterialPin = ((f64, f64), (f64, f64, f64));

/// A cloth of `size` metres on a `grid`, hanging from `pins` given by their
/// material fraction (0..1 along width and height) and position.
struct Setup {
    size: (f64, f64),
    pins: Vec<MaterialPin>,
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
                Pin { grid: (i as u32, j as u32), pos }
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
        }
    }

    fn shape(&self, cols: u32, rows: u32, relax: RelaxSettings) -> RestShape {
        let cloth = Cloth::new(self.size, (cols, rows));
        RestShape::build(&cloth, &self.key(cols, rows, relax))
    }
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
