//! `drape.Scene`: a loaded scene file and an evaluator that keeps its rest
//! shapes, so each frame after the first costs only the animation phase.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use drape::animate::{EvaluateOptions, Evaluator};
use drape::mesh::Mesh;
use drape::scene::{self as document, Collider};
use glam::DVec3;
use pyo3::buffer::PyBuffer;
use pyo3::exceptions::{PyException, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::axes::{Axes, write_flat, y_up_from_z_up_f64, z_up_from_y_up_f64};
use crate::pin_targets::{self, PinTarget};

pyo3::create_exception!(
    drape,
    SceneError,
    PyException,
    "A scene file that cannot be read or is not a valid scene; the message reads FILE:LINE:COL: what is wrong."
);
pyo3::create_exception!(
    drape,
    EvaluationError,
    PyException,
    "The evaluator failed on a valid scene (a bug in Drape); the scene object stays usable."
);

/// A scene file loaded and validated by Drape, ready to evaluate at any time.
///
/// Safe to share between threads (Blender renders on its own thread):
/// evaluations take turns, and run without the GIL.
#[pyclass(frozen, module = "drape")]
pub struct Scene {
    path: PathBuf,
    scene: document::Scene,
    state: Mutex<State>,
}

/// What evaluations reuse: the rest shapes and the buffers.
#[derive(Default)]
struct State {
    evaluator: Evaluator,
    mesh: Mesh,
    flat: Vec<f32>,
}

impl State {
    /// Evaluates into `self.flat`; a panic inside the library becomes an error
    /// message, and the caches it may have left half-written are dropped.
    fn evaluate(&mut self, scene: &document::Scene, t_secs: f64, axes: Axes, pins: &[PinTarget]) -> Result<(), String> {
        let result = catch_unwind(AssertUnwindSafe(|| {
            if pins.is_empty() {
                self.evaluator.evaluate_into(scene, t_secs, EvaluateOptions::default(), &mut self.mesh);
            } else {
                let posed = pin_targets::scene_with_targets(scene, pins, t_secs);
                self.evaluator.evaluate_into(&posed, t_secs, EvaluateOptions::default(), &mut self.mesh);
            }
            write_flat(&self.mesh.positions, axes, &mut self.flat);
        }));
        result.map_err(|payload| {
            *self = State::default();
            panic_message(payload.as_ref())
        })
    }
}

fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_owned()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "unknown failure".to_owned()
    }
}

/// A pin's grid (i, j) and a point.
type GridAndPoint = ((u32, u32), (f64, f64, f64));

/// One pin placed by the caller: its grid (i, j), where it is now, and where it is at each key's frame.
type PinArgument = ((u32, u32), (f64, f64, f64), Vec<Option<(f64, f64, f64)>>);

fn axes(z_up: bool) -> Axes {
    if z_up { Axes::ZUp } else { Axes::YUp }
}

/// `array.array(typecode)` holding `values`' bytes.
fn new_array<'py, T: bytemuck::Pod>(py: Python<'py>, typecode: &str, values: &[T]) -> PyResult<Bound<'py, PyAny>> {
    let array = py.import("array")?.getattr("array")?.call1((typecode,))?;
    array.call_method1("frombytes", (PyBytes::new(py, bytemuck::cast_slice(values)),))?;
    Ok(array)
}

impl Scene {
    fn point_count(&self) -> usize {
        self.scene.cloth.cols() * self.scene.cloth.rows()
    }

    /// The caller's pins in Drape's axes, checked against the scene.
    fn pin_targets(&self, pins: Vec<PinArgument>, z_up: bool) -> PyResult<Vec<PinTarget>> {
        let to_drape = |(x, y, z): (f64, f64, f64)| {
            let p = DVec3::new(x, y, z);
            if z_up { y_up_from_z_up_f64(p) } else { p }
        };
        let targets: Vec<PinTarget> = pins
            .into_iter()
            .map(|(grid, now, at_keys)| PinTarget {
                grid,
                now: to_drape(now),
                at_keys: at_keys.into_iter().map(|at| at.map(to_drape)).collect(),
            })
            .collect();
        pin_targets::check(&self.scene, &targets).map_err(PyValueError::new_err)?;
        Ok(targets)
    }

    /// Evaluates at `t_seconds` and hands the flat positions to `use_flat`.
    /// The evaluation (and any wait for another thread's) runs without the GIL.
    fn evaluate_then<R>(
        &self,
        py: Python<'_>,
        t_seconds: f64,
        z_up: bool,
        pins: Option<Vec<PinArgument>>,
        use_flat: impl FnOnce(&[f32]) -> PyResult<R>,
    ) -> PyResult<R> {
        if !t_seconds.is_finite() {
            return Err(PyValueError::new_err(format!(
                "t_seconds must be a finite number of seconds, not {t_seconds}"
            )));
        }
        let pins = self.pin_targets(pins.unwrap_or_default(), z_up)?;
        let scene = &self.scene;
        let flat = py.detach(|| {
            let mut state = self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            state.evaluate(scene, t_seconds, axes(z_up), &pins).map(|()| std::mem::take(&mut state.flat))
        });
        let flat = flat.map_err(|message| {
            EvaluationError::new_err(format!(
                "{}: evaluating the cloth at {t_seconds} s failed: {message}",
                self.path.display()
            ))
        })?;
        let result = use_flat(&flat);
        // Hand the buffer back for the next frame, unless another evaluation is under way.
        if let Ok(mut state) = self.state.try_lock() {
            state.flat = flat;
        }
        result
    }
}

#[pymethods]
impl Scene {
    /// Loads and validates a scene file (and the mesh and glTF files it names).
    /// Raises `drape.SceneError` with `FILE:LINE:COL: message` when it cannot.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        let loaded = py.detach(|| catch_unwind(|| document::load(&path)));
        match loaded {
            Ok(Ok(scene)) => Ok(Scene { path, scene, state: Mutex::new(State::default()) }),
            Ok(Err(error)) => Err(SceneError::new_err(error.to_string())),
            Err(payload) => Err(SceneError::new_err(format!(
                "{}: reading the scene failed inside Drape: {}",
                path.display(),
                panic_message(payload.as_ref())
            ))),
        }
    }

    /// The scene file as given to `load`.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// The scene's name (may be empty).
    #[getter]
    fn name(&self) -> String {
        self.scene.name.clone()
    }

    /// Points of the cloth: columns × rows.
    #[getter(point_count)]
    fn point_count_py(&self) -> usize {
        self.point_count()
    }

    /// (columns, rows) of the cloth's grid; point (i, j) has index j·columns + i.
    #[getter]
    fn grid(&self) -> (usize, usize) {
        (self.scene.cloth.cols(), self.scene.cloth.rows())
    }

    /// The cloth's (width, height) in metres.
    #[getter]
    fn size(&self) -> (f64, f64) {
        (self.scene.cloth.width_m(), self.scene.cloth.height_m())
    }

    /// Frames per second of the scene's timeline.
    #[getter]
    fn fps(&self) -> f64 {
        self.scene.timeline.fps
    }

    /// (start, end) frames of the scene's timeline, both included.
    #[getter]
    fn frame_range(&self) -> (i32, i32) {
        (self.scene.timeline.start, self.scene.timeline.end)
    }

    /// The frame of each key, in order.
    #[getter]
    fn key_frames(&self) -> Vec<i32> {
        self.scene.keys.iter().map(|key| key.frame).collect()
    }

    /// Key `index`'s pins as ((i, j), (x, y, z)) in file order, in Drape's axes or Blender's with `z_up=True`.
    #[pyo3(signature = (index, z_up = false))]
    fn key_pins(&self, index: usize, z_up: bool) -> PyResult<Vec<GridAndPoint>> {
        let key = self.scene.keys.get(index).ok_or_else(|| {
            PyValueError::new_err(format!("the scene has {} keys; there is no key {index}", self.scene.keys.len()))
        })?;
        let axes = |p: (f64, f64, f64)| if z_up { z_up_from_y_up_f64(p.into()).into() } else { p };
        Ok(key.pins.iter().map(|pin| (pin.grid, axes(pin.pos))).collect())
    }

    /// The grid index (i, j) of every pin of any key, each once, sorted.
    fn pin_grids(&self) -> Vec<(u32, u32)> {
        let mut grids: Vec<(u32, u32)> = self.scene.keys.iter().flat_map(|k| k.pins.iter().map(|p| p.grid)).collect();
        grids.sort_unstable_by_key(|&(i, j)| (j, i));
        grids.dedup();
        grids
    }

    /// Triangle corners as a flat `array('I')`, three per triangle, two triangles
    /// per grid quad, wound as in every Drape export.
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (cols, rows) = (self.scene.cloth.cols(), self.scene.cloth.rows());
        new_array(py, "I", &drape::mesh::grid_triangle_indices(cols, rows))
    }

    /// Per-point UVs as a flat `array('f')` of (u, v) pairs: (i/(columns−1), j/(rows−1)),
    /// v = 0 on the top edge (Drape's convention; Blender's v runs the other way).
    fn uvs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (cols, rows) = (self.scene.cloth.cols(), self.scene.cloth.rows());
        let uvs = drape::mesh::grid_uvs(cols, rows);
        new_array(py, "f", bytemuck::cast_slice::<_, f32>(&uvs))
    }

    /// The files the scene reads besides itself (mesh colliders, referenced glTF
    /// files, the background plate's pattern), as paths beside the scene file.
    fn referenced_files(&self) -> Vec<PathBuf> {
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let meshes = self.scene.colliders.iter().filter_map(|collider| match collider {
            Collider::Mesh(mesh) => Some(&mesh.file),
            _ => None,
        });
        meshes
            .chain(self.scene.references.iter().map(|reference| &reference.file))
            .chain(self.scene.plate.iter().map(|plate| &plate.file))
            .map(|file| folder.join(file))
            .collect()
    }

    /// Writes the cloth at `t_seconds` into `buffer` (any writable buffer of
    /// `point_count * 3` float32s: `array('f')`, a numpy float32 array, a
    /// memoryview) as x, y, z triples in vertex order, in Drape's Y-up metres,
    /// or Blender's Z-up ones with `z_up=True`. The same t always gives the same
    /// floats, however it was reached.
    ///
    /// `pins` places pins from outside (Blender's bones): a sequence of
    /// `((i, j), now_xyz, [xyz at each key's frame, or None])`, in the axes
    /// `z_up` names. Every key is relaxed with those pins at their key
    /// positions, and the cloth is carried so each sits exactly at `now_xyz`.
    #[pyo3(signature = (t_seconds, buffer, z_up = false, pins = None))]
    fn evaluate_into(
        &self,
        py: Python<'_>,
        t_seconds: f64,
        buffer: &Bound<'_, PyAny>,
        z_up: bool,
        pins: Option<Vec<PinArgument>>,
    ) -> PyResult<()> {
        let expected = self.point_count() * 3;
        let target = PyBuffer::<f32>::get(buffer).map_err(|error| {
            PyTypeError::new_err(format!(
                "evaluate_into needs a writable buffer of float32 (e.g. array('f')) with {expected} items: {error}"
            ))
        })?;
        if target.readonly() {
            return Err(PyTypeError::new_err("evaluate_into needs a writable buffer; this one is read-only"));
        }
        if target.item_count() != expected {
            return Err(PyValueError::new_err(format!(
                "the buffer holds {} float32s; this cloth needs {expected} (point_count {} × 3)",
                target.item_count(),
                self.point_count()
            )));
        }
        self.evaluate_then(py, t_seconds, z_up, pins, |flat| target.copy_from_slice(py, flat))
    }

    /// The cloth at `t_seconds` as a new `array('f')` of x, y, z triples (see `evaluate_into`).
    #[pyo3(signature = (t_seconds, z_up = false, pins = None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        t_seconds: f64,
        z_up: bool,
        pins: Option<Vec<PinArgument>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.evaluate_then(py, t_seconds, z_up, pins, |flat| new_array(py, "f", flat))
    }

    fn __repr__(&self) -> String {
        let (cols, rows) = (self.scene.cloth.cols(), self.scene.cloth.rows());
        format!("<drape.Scene {:?} {cols}×{rows} at {} fps>", self.path.display().to_string(), self.scene.timeline.fps)
    }
}
