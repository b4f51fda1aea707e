//! Drape as the Python module `drape`: the library's own scene loader and
//! evaluator behind a small API (DESIGN.md, "Drape from Python and inside
//! Blender"), with no math of its own beyond the axis conversion in [`axes`].
//!
//! ```python
//! import drape
//! scene = drape.Scene.load("scenes/magic_carpet.ron")   # drape.SceneError: FILE:LINE:COL: …
//! buffer = array.array("f", bytes(4 * 3 * scene.point_count))
//! scene.evaluate_into(37.5 / scene.fps, buffer, z_up=True)
//! ```
//!
//! Nothing panics across the boundary: a failure inside the evaluator is
//! caught and raised as `drape.EvaluationError`.

pub mod axes;
pub mod pin_targets;
mod scene;

use pyo3::prelude::*;

/// The module Python imports as `drape`.
#[pymodule(name = "drape")]
mod drape_module {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::scene::{EvaluationError, Scene, SceneError};

    /// A point (x, y, z) in Drape's Y-up axes as Blender's Z-up: (x, −z, y).
    #[pyfunction]
    fn z_up_from_y_up(point: (f64, f64, f64)) -> (f64, f64, f64) {
        crate::axes::z_up_from_y_up_f64(point.into()).into()
    }

    /// A point (x, y, z) in Blender's Z-up axes as Drape's Y-up: (x, z, −y).
    #[pyfunction]
    fn y_up_from_z_up(point: (f64, f64, f64)) -> (f64, f64, f64) {
        crate::axes::y_up_from_z_up_f64(point.into()).into()
    }

    #[pymodule_init]
    fn init(module: &Bound<'_, PyModule>) -> PyResult<()> {
        module.add("__version__", env!("CARGO_PKG_VERSION"))
    }
}
