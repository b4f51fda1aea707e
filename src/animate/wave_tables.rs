//! The tables behind the Wave layer's sine. Its argument is a column term
//! plus a row term, so sin(A + B) = sin A cos B + cos A sin B comes from one
//! table per column and one per row: two multiplies per vertex instead of a
//! sine.

/// Per-column and per-row sines and cosines of a wave's argument.
#[derive(Debug, Default)]
pub struct WaveTables {
    column_sin: Vec<f32>,
    column_cos: Vec<f32>,
    row_sin: Vec<f32>,
    row_cos: Vec<f32>,
}

impl WaveTables {
    /// Fills the tables of a `cols × rows` grid: column i's angle is
    /// i·`column_step`, row j's is j·`row_step` + `row_offset` (radians).
    #[inline(always)]
    pub fn fill(&mut self, (cols, rows): (usize, usize), column_step: f64, row_step: f64, row_offset: f64) {
        let fill = |sin: &mut Vec<f32>, cos: &mut Vec<f32>, n: usize, step: f64, offset: f64| {
            sin.clear();
            cos.clear();
            for k in 0..n {
                let (s, c) = (k as f64 * step + offset).sin_cos();
                sin.push(s as f32);
                cos.push(c as f32);
            }
        };
        fill(&mut self.column_sin, &mut self.column_cos, cols, column_step, 0.0);
        fill(&mut self.row_sin, &mut self.row_cos, rows, row_step, row_offset);
    }

    /// Row j of the wave at `amplitude`.
    #[inline(always)]
    pub fn row(&self, j: usize, amplitude: f32) -> RowWave<'_> {
        RowWave {
            column_sin: &self.column_sin,
            column_cos: &self.column_cos,
            row_sin: self.row_sin[j],
            row_cos: self.row_cos[j],
            amplitude,
        }
    }
}

/// One row's share of the wave: the column tables, the row's sine and
/// cosine and the amplitude.
#[derive(Clone, Copy)]
pub struct RowWave<'a> {
    column_sin: &'a [f32],
    column_cos: &'a [f32],
    row_sin: f32,
    row_cos: f32,
    amplitude: f32,
}

impl RowWave<'_> {
    /// p += axis · (amplitude · sin(A + B) · a) along the row. Each output
    /// is its own argument, so the loop needs no overlap checks to vectorise.
    #[inline(always)]
    pub fn displace(self, a: &[f32], [ax, ay, az]: [&[f32]; 3], x: &mut [f32], y: &mut [f32], z: &mut [f32]) {
        let cols = a.len();
        let RowWave { row_sin, row_cos, amplitude, .. } = self;
        let (column_sin, column_cos) = (&self.column_sin[..cols], &self.column_cos[..cols]);
        let (ax, ay, az) = (&ax[..cols], &ay[..cols], &az[..cols]);
        let (x, y, z) = (&mut x[..cols], &mut y[..cols], &mut z[..cols]);
        for i in 0..cols {
            let wave_sin = column_sin[i] * row_cos + column_cos[i] * row_sin;
            let s = amplitude * wave_sin * a[i];
            x[i] += ax[i] * s;
            y[i] += ay[i] * s;
            z[i] += az[i] * s;
        }
    }
}
