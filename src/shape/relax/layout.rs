//! Where the relaxation keeps a grid: each coordinate split by column
//! parity so that the points of one colour along a row, and each of their
//! neighbours, sit next to each other; runs and edge chunks of those points.

/// Neighbours in mirror-image pairs, grouped as structural, shear and
/// bending; sums run over pairs first so that a mirrored neighbourhood gives
/// the mirrored sum exactly.
pub(super) const NEIGHBOURS: usize = 12;

/// Points computed side by side: one AVX-512 vector, or two AVX2 ones.
pub(super) const LANES: usize = 8;
pub(super) type Lanes = [f64; LANES];

/// Grid steps (di, dj) of each neighbour.
pub(super) const STEPS: [(isize, isize); NEIGHBOURS] =
    [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1), (-2, 0), (2, 0), (0, -2), (0, 2)];

/// One coordinate of every grid point, split by column parity: point (i, j)
/// is at `slot(i, j)` = `(i % 2)·len + j·half + i / 2`. Points of one colour
/// along a row then sit next to each other, and so do each of their
/// neighbours, so a sweep over them reads and writes whole vectors.
pub(super) struct Split {
    pub(super) half: usize,
    /// Length of one parity's part.
    pub(super) len: usize,
    pub(super) data: Vec<f64>,
}

impl Split {
    pub(super) fn new(cols: usize, rows: usize) -> Split {
        let half = cols.div_ceil(2);
        // Padding so that the last chunk of a run may read a few lanes past the grid.
        let len = half * rows + LANES;
        Split { half, len, data: vec![0.0; 2 * len] }
    }

    pub(super) fn slot(&self, i: usize, j: usize) -> usize {
        (i % 2) * self.len + j * self.half + i / 2
    }

    pub(super) fn get(&self, i: usize, j: usize) -> f64 {
        self.data[self.slot(i, j)]
    }

    pub(super) fn get_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        let at = self.slot(i, j);
        &mut self.data[at]
    }

    /// `len` consecutive same-parity points from (i, j) on.
    pub(super) fn run(&self, i: usize, j: usize, len: usize) -> &[f64] {
        let at = self.slot(i, j);
        &self.data[at..at + len]
    }

    pub(super) fn run_mut(&mut self, i: usize, j: usize, len: usize) -> &mut [f64] {
        let at = self.slot(i, j);
        &mut self.data[at..at + len]
    }
}

/// Up to [`LANES`] points near an edge, computed side by side, and where they
/// and their neighbours sit in a [`Split`], found once and laid out lane by
/// lane: an absent neighbour is the point itself, masked out by `present`;
/// spare lanes repeat the last point. (Gathered from per-point slots and
/// flags instead, the lanes cost a tenth of a 64² build.)
#[derive(Clone, Copy)]
pub(super) struct BorderChunk {
    pub(super) len: usize,
    pub(super) centre: [u32; LANES],
    pub(super) around: [[u32; LANES]; NEIGHBOURS],
    pub(super) present: [Lanes; NEIGHBOURS],
}

impl BorderChunk {
    /// Slots of the chunk's points, in order.
    pub(super) fn centres(&self) -> impl Iterator<Item = usize> + '_ {
        self.centre[..self.len].iter().map(|&at| at as usize)
    }
}

/// `len` interior free points of one colour: (i, j), (i + 2, j), …
#[derive(Clone, Copy)]
pub(super) struct Run {
    pub(super) i: usize,
    pub(super) j: usize,
    pub(super) len: usize,
}

/// A run of points near the top or bottom edge whose neighbours along the
/// row all exist: the neighbours above or below it that do not are missing
/// for every point of the run alike, so it is computed like an interior run,
/// with those neighbours read as the points themselves and masked out by
/// `present` (gathered into chunks instead, these points had cost three times
/// an interior one).
#[derive(Clone, Copy)]
pub(super) struct EdgeRun {
    pub(super) run: Run,
    pub(super) present: [f64; NEIGHBOURS],
}
