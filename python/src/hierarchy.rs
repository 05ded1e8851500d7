//! `multires.Hierarchy`: the progressive hierarchy of a mesh (levels of edge collapses
//! with detail coefficients), walked, edited and saved from Python.

use std::ops::ControlFlow;
use std::path::PathBuf;

use halfedge::hierarchy::{
    BuildProgress, DetailMode, Hierarchy, HierarchyOptions, SurvivorPlacement,
};
use numpy::ndarray::Array1;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::arrays;
use crate::errors::{mesh_err, Fail};
use crate::mesh::{face_array, info_dict, set_positions, vertex_array, PyMesh};

/// A mesh with its progressive hierarchy (seed paper, section 3): levels of edge
/// collapses, level 0 the input, higher levels coarser, with detail coefficients so that
/// an edit made at a coarse level comes back at full resolution.
///
/// ``Hierarchy(mesh, method="rounds", target_faces=2000, ...)`` builds it from a copy of
/// ``mesh`` and leaves it at the coarsest level. Vertex arrays of a level
/// (:attr:`vertices`, :attr:`faces`, regions of the editing methods) number the vertices
/// live at that level in order; :attr:`input_indices` gives each one's index in the
/// input mesh, the numbering of :meth:`ancestors` and :meth:`records`.
#[pyclass(name = "Hierarchy", module = "multires")]
pub struct PyHierarchy {
    /// The kernel's hierarchy.
    pub inner: Hierarchy,
}

fn level_of(h: &Hierarchy, level: i64) -> PyResult<usize> {
    if level < 0 || level as usize > h.coarsest_level() {
        return Err(mesh_err(format!(
            "level {level} does not exist: the hierarchy has levels 0 to {}",
            h.coarsest_level()
        )));
    }
    Ok(level as usize)
}

/// Walks `h` to `level` with the GIL released.
pub fn walk(py: Python<'_>, h: &mut Hierarchy, level: usize) -> PyResult<()> {
    py.allow_threads(|| h.go_to_level(level))
        .map_err(Fail::from)?;
    Ok(())
}

#[pymethods]
impl PyHierarchy {
    /// Builds the hierarchy of a copy of ``mesh``: ``method`` is ``"rounds"`` (the
    /// paper's rounds of planar-star collapses, one level per round) or ``"qem"``
    /// (quadric decimation cut into levels); the build stops at ``target_faces`` faces,
    /// ``max_levels`` levels or the error bound ``max_error``. ``detail`` is ``"local"``
    /// (local-frame detail coefficients, the default) or ``"translation"``. ``placement``
    /// (rounds only) is ``"midpoint"`` (the paper's, the default) or ``"quadric"``
    /// (survivors where QEM would put them: nearer the input, about 20 % slower). ``progress``,
    /// if given, is called as ``progress(levels, faces, input_faces)`` while it builds;
    /// an exception it raises stops the build and is raised here, and so does Ctrl-C
    /// (KeyboardInterrupt). Releases the GIL.
    #[new]
    #[pyo3(signature = (mesh, method = "rounds", target_faces = 2000, max_levels = None, max_error = None, detail = "local", placement = "midpoint", progress = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        mesh: PyRef<'_, PyMesh>,
        method: &str,
        target_faces: usize,
        max_levels: Option<usize>,
        max_error: Option<f64>,
        detail: &str,
        placement: &str,
        progress: Option<PyObject>,
    ) -> PyResult<Self> {
        let mut options = match method {
            "rounds" => HierarchyOptions::rounds(),
            "qem" => HierarchyOptions::qem(),
            other => {
                return Err(mesh_err(format!(
                    "method: {other:?} is not 'rounds' or 'qem'"
                )))
            }
        };
        options = options.with_target_faces(target_faces);
        if let Some(l) = max_levels {
            options = options.with_max_levels(l);
        }
        if let Some(e) = max_error {
            options = options.with_max_error(e);
        }
        options = options.with_detail_mode(match detail {
            "local" => DetailMode::LocalFrame,
            "translation" => DetailMode::Translation,
            other => {
                return Err(mesh_err(format!(
                    "detail: {other:?} is not 'local' or 'translation'"
                )))
            }
        });
        options = options.with_placement(match placement {
            "midpoint" => SurvivorPlacement::Midpoint,
            "quadric" => SurvivorPlacement::Quadric,
            other => {
                return Err(mesh_err(format!(
                    "placement: {other:?} is not 'midpoint' or 'quadric'"
                )))
            }
        });
        let input = {
            let m = &mesh.inner;
            py.allow_threads(|| m.clone())
        };
        drop(mesh);
        let mut raised: Option<PyErr> = None;
        // The build asks every level and every 65,536 collapses whether to go on: the
        // callback is called then, and Ctrl-C (a pending signal) stops the build too.
        let built = py.allow_threads(|| {
            Hierarchy::build_cancellable(input, &options, &mut |p: BuildProgress| {
                Python::with_gil(|py| {
                    let called = match &progress {
                        Some(callback) => callback
                            .call1(py, (p.levels, p.faces, p.input_faces))
                            .map(drop),
                        None => Ok(()),
                    };
                    match called.and_then(|()| py.check_signals()) {
                        Ok(()) => ControlFlow::Continue(()),
                        Err(e) => {
                            raised = Some(e);
                            ControlFlow::Break(())
                        }
                    }
                })
            })
        });
        if let Some(e) = raised {
            return Err(e);
        }
        Ok(Self {
            inner: built.map_err(Fail::from)?,
        })
    }

    /// The current level, or ``None`` between two levels.
    #[getter]
    fn level(&self) -> Option<usize> {
        self.inner.current_level()
    }

    /// The index of the coarsest level (levels are ``0 .. coarsest_level``).
    #[getter]
    fn coarsest_level(&self) -> usize {
        self.inner.coarsest_level()
    }

    /// Number of levels, the input included.
    #[getter]
    fn n_levels(&self) -> usize {
        self.inner.n_levels()
    }

    /// Face count of every level, the input first.
    #[getter]
    fn level_face_counts(&self) -> Vec<usize> {
        self.inner.level_face_counts().to_vec()
    }

    /// Number of collapse records (input to coarsest level).
    #[getter]
    fn n_records(&self) -> usize {
        self.inner.n_records()
    }

    /// ``"rounds"`` or ``"qem"``.
    #[getter]
    fn method(&self) -> String {
        format!("{:?}", self.inner.method()).to_lowercase()
    }

    /// Walks to ``level`` (coarser or finer), carrying every edit along. Raises
    /// :class:`MeshError` for a level that does not exist. Releases the GIL.
    fn go_to_level(&mut self, py: Python<'_>, level: i64) -> PyResult<()> {
        let level = level_of(&self.inner, level)?;
        walk(py, &mut self.inner, level)
    }

    /// Walks to level 0 (full resolution, every edit carried there) and returns that
    /// mesh (a copy). Releases the GIL.
    fn refine(&mut self, py: Python<'_>) -> PyResult<PyMesh> {
        walk(py, &mut self.inner, 0)?;
        let m = self.inner.mesh();
        Ok(PyMesh::new(py.allow_threads(|| m.clone())))
    }

    /// The mesh at the current level (a copy).
    #[getter]
    fn mesh(&self, py: Python<'_>) -> PyMesh {
        let m = self.inner.mesh();
        PyMesh::new(py.allow_threads(|| m.clone()))
    }

    /// The positions of the vertices live at the current level, ``(n, 3)`` float64.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        vertex_array(py, self.inner.mesh())
    }

    /// The faces of the current level, ``(m, 3)`` int64 rows of :attr:`vertices`.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        face_array(py, self.inner.mesh())
    }

    /// For every row of :attr:`vertices`, that vertex's index in the input mesh.
    #[getter]
    fn input_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let m = self.inner.mesh();
        let v: Vec<i64> = m.vertices().map(|v| m.vertex_index(v) as i64).collect();
        Array1::from(v).into_pyarray(py)
    }

    /// Moves the vertices of the current level to ``vertices`` (``(n, 3)``, rows as
    /// :attr:`vertices`): the user's own edit, carried to the finer levels by the
    /// detail coefficients when the hierarchy is refined (vertices whose position did not
    /// change keep their fine detail exactly).
    fn set_vertices(&mut self, vertices: &Bound<'_, PyAny>) -> PyResult<()> {
        let points = arrays::points(vertices, "vertices")?;
        let n = self.inner.mesh().n_vertices();
        if points.len() != n {
            return Err(mesh_err(format!(
                "vertices: expected shape ({n}, 3), got ({}, 3)",
                points.len()
            )));
        }
        set_positions(self.inner.mesh_mut(), &points)
    }

    /// For every input vertex (index ``i`` of the input mesh), the input index of its
    /// representative at ``level``: the vertex it is collapsed into there (itself when it
    /// is live at that level). An int64 array. Raises :class:`MeshError` for a level
    /// that does not exist.
    fn ancestors<'py>(&self, py: Python<'py>, level: i64) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let level = level_of(&self.inner, level)?;
        let h = &self.inner;
        let a = py
            .allow_threads(|| h.ancestors(level))
            .map_err(Fail::from)?;
        let a: Vec<i64> = a.into_iter().map(i64::from).collect();
        Ok(Array1::from(a).into_pyarray(py))
    }

    /// The collapse history, in collapse order, as a dict of arrays (input numbering):
    /// ``v0`` (the removed vertex), ``v1`` (the survivor), ``vl``, ``vr`` (the third
    /// vertices of the two faces, -1 on a boundary), ``p0``, ``p1`` (``(n, 3)``
    /// positions of ``v0`` and ``v1`` when collapsed) and ``level`` (the level each
    /// record's collapse leads to). Copies the whole history: call it only when needed.
    fn records<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let h = &self.inner;
        let (v0, v1, vl, vr, p0, p1) = py.allow_threads(|| {
            let m = h.mesh();
            let records = h.records();
            let idx = |v: halfedge::VertexId| m.vertex_index(v) as i64;
            (
                records.iter().map(|r| idx(r.v0)).collect::<Vec<_>>(),
                records.iter().map(|r| idx(r.v1)).collect::<Vec<_>>(),
                records
                    .iter()
                    .map(|r| r.vl.map_or(-1, idx))
                    .collect::<Vec<_>>(),
                records
                    .iter()
                    .map(|r| r.vr.map_or(-1, idx))
                    .collect::<Vec<_>>(),
                records.iter().map(|r| r.p0.to_array()).collect::<Vec<_>>(),
                records.iter().map(|r| r.p1.to_array()).collect::<Vec<_>>(),
            )
        });
        let ends = h.level_ends();
        let level: Vec<i64> = (0..v0.len())
            .map(|k| ends.partition_point(|&e| e <= k) as i64)
            .collect();
        let d = PyDict::new(py);
        d.set_item("v0", Array1::from(v0).into_pyarray(py))?;
        d.set_item("v1", Array1::from(v1).into_pyarray(py))?;
        d.set_item("vl", Array1::from(vl).into_pyarray(py))?;
        d.set_item("vr", Array1::from(vr).into_pyarray(py))?;
        d.set_item("p0", arrays::to_points(py, &p0))?;
        d.set_item("p1", arrays::to_points(py, &p1))?;
        d.set_item("level", Array1::from(level).into_pyarray(py))?;
        Ok(d)
    }

    /// The ``multires info`` report of the current level's mesh, with a ``hierarchy``
    /// entry (method, levels, coarsest level, faces per level, current level, records).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = info_dict(py, self.inner.mesh(), None)?;
        let h = PyDict::new(py);
        h.set_item("method", self.method())?;
        h.set_item("levels", self.inner.n_levels())?;
        h.set_item("coarsest_level", self.inner.coarsest_level())?;
        h.set_item("level_face_counts", self.level_face_counts())?;
        h.set_item("current_level", self.inner.current_level())?;
        h.set_item("records", self.inner.n_records())?;
        d.set_item("hierarchy", h)?;
        Ok(d)
    }

    /// Saves everything the hierarchy holds (levels, records, details, edits, the
    /// current level) to a ``.mrh`` file. Releases the GIL.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let h = &self.inner;
        py.allow_threads(|| h.save(&path)).map_err(Fail::from)?;
        Ok(())
    }

    /// Loads a hierarchy saved with :meth:`save` (or ``multires simplify``). Raises
    /// FileNotFoundError for a missing file and :class:`MeshError` for a corrupt one.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .allow_threads(|| Hierarchy::load(&path))
            .map_err(Fail::from)?;
        Ok(Self { inner })
    }

    /// The ``.mrh`` file's bytes.
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let h = &self.inner;
        let bytes = py
            .allow_threads(|| {
                let mut out = Vec::new();
                h.write_to(&mut out).map(|()| out)
            })
            .map_err(Fail::from)?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// A hierarchy from ``.mrh`` bytes (:meth:`to_bytes`). Raises :class:`MeshError`
    /// for corrupt bytes.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let inner = py
            .allow_threads(|| Hierarchy::read_from(data, "<bytes>"))
            .map_err(Fail::from)?;
        Ok(Self { inner })
    }

    /// An independent copy (edits and current level included).
    fn copy(&self) -> Self {
        Self {
            inner: self.inner.clone(),
        }
    }

    fn __copy__(&self) -> Self {
        self.copy()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.copy()
    }

    /// Pickling through the ``.mrh`` bytes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let bytes = slf.borrow().to_bytes(py)?;
        let ctor = py.get_type::<PyHierarchy>().getattr("from_bytes")?;
        (ctor, (bytes,)).into_pyobject(py).map(|t| t.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "Hierarchy(method={:?}, level={:?}, level_face_counts={:?})",
            self.method(),
            self.inner.current_level(),
            self.inner.level_face_counts()
        )
    }
}
