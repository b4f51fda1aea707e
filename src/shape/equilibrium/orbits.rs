//! The unknowns of a solve: one set of three for each orbit of the mirrors.
//! A mirror-symmetric cloth moves symmetrically, so a point's step is its
//! orbit's first point's step with the mirrored coordinates flipped; solving
//! for one point of each orbit keeps every step exactly symmetric and makes
//! the symmetric problem smaller instead of larger. A point on a mirror's
//! plane moves only along it.

use super::mirror::Mirror;

pub(super) struct Orbits {
    /// Each point's orbit's unknown (three entries from `3 ×` it); `None` for a pin.
    pub(super) unknown: Vec<Option<usize>>,
    /// Each point's step is its orbit's with these signs.
    pub(super) sign: Vec<[f64; 3]>,
    /// Orbits of free points.
    pub(super) count: usize,
    /// Unknowns held at zero, `(orbit, axis)`: a point on a mirror's plane.
    pub(super) fixed: Vec<(usize, usize)>,
}

impl Orbits {
    pub(super) fn new(pinned: &[bool], mirrors: &[Mirror]) -> Orbits {
        let points = pinned.len();
        let mut unknown = vec![None; points];
        let mut sign = vec![[1.0; 3]; points];
        let mut fixed = Vec::new();
        let mut count = 0;
        for first in 0..points {
            if pinned[first] || unknown[first].is_some() {
                continue;
            }
            // The orbit of `first`, each point with the flips that reach it.
            let mut orbit = vec![(first, [1.0; 3])];
            for mirror in mirrors {
                for at in 0..orbit.len() {
                    let (point, mut flips) = orbit[at];
                    let image = mirror.partner(point);
                    flips[mirror.axis()] = -flips[mirror.axis()];
                    if !orbit.iter().any(|(p, _)| *p == image) {
                        orbit.push((image, flips));
                    }
                }
                if mirror.partner(first) == first {
                    fixed.push((count, mirror.axis()));
                }
            }
            for (point, flips) in orbit {
                unknown[point] = Some(count);
                sign[point] = flips;
            }
            count += 1;
        }
        Orbits { unknown, sign, count, fixed }
    }

    /// The orbits' share of a gradient over the free points (`free[rank]`
    /// is the point of free rank `rank`).
    pub(super) fn reduce(&self, free: &[usize], full: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (rank, &point) in free.iter().enumerate() {
            let Some(orbit) = self.unknown[point] else { continue };
            for axis in 0..3 {
                out[3 * orbit + axis] += self.sign[point][axis] * full[3 * rank + axis];
            }
        }
        for &(orbit, axis) in &self.fixed {
            out[3 * orbit + axis] = 0.0;
        }
    }

    /// Every free point's step from its orbit's.
    pub(super) fn expand(&self, free: &[usize], reduced: &[f64], out: &mut [f64]) {
        for (rank, &point) in free.iter().enumerate() {
            let Some(orbit) = self.unknown[point] else { continue };
            for axis in 0..3 {
                out[3 * rank + axis] = self.sign[point][axis] * reduced[3 * orbit + axis];
            }
        }
    }
}
