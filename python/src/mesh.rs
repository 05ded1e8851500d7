//! `multires.Mesh`: a triangle mesh of the half-edge kernel, with NumPy arrays in and out.

use std::path::PathBuf;

use halfedge::Mesh;
use multires::load::{self, Weld};
use multires::progress::Silent;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{mesh_err, Fail};

/// A triangle mesh (half-edge structure, float64 positions).
///
/// Make one with :func:`multires.read` or :meth:`Mesh.from_arrays`. Vertices and faces
/// are numbered as the file writers number them: row ``k`` of :attr:`vertices` is vertex
/// ``k`` of :attr:`faces` and of a written file.
#[pyclass(name = "Mesh", module = "multires")]
#[derive(Clone)]
pub struct PyMesh {
    /// The kernel's mesh.
    pub inner: Mesh,
    /// What the reader and the welding did (counts), for `info()`.
    pub fixes: Option<Vec<(&'static str, usize)>>,
}

impl PyMesh {
    /// Wraps a mesh.
    pub fn new(inner: Mesh) -> Self {
        Self { inner, fixes: None }
    }
}

/// Parses a weld option: "auto", "off" or a fraction of the diagonal (a number).
pub fn parse_weld(weld: &Bound<'_, PyAny>) -> PyResult<Weld> {
    if let Ok(f) = weld.extract::<f64>() {
        if !(f.is_finite() && f >= 0.0) {
            return Err(mesh_err(format!(
                "weld: expected auto, off or a finite, non-negative fraction of the diagonal, got {f}"
            )));
        }
        return Ok(Weld::Within(f));
    }
    let s: String = weld
        .extract()
        .map_err(|_| mesh_err("weld: expected 'auto', 'off' or a number"))?;
    s.parse::<Weld>()
        .map_err(|e| mesh_err(format!("weld: {e}")))
}

/// Reads `path` and welds it (the CLI's loader); releases the GIL.
pub fn read_mesh(py: Python<'_>, path: PathBuf, weld: Weld) -> PyResult<PyMesh> {
    let loaded = py
        .allow_threads(|| load::load(&path, weld, &mut Silent))
        .map_err(Fail::from)?;
    let b = &loaded.build;
    let fixes = vec![
        ("duplicated_vertices", b.duplicated_vertices),
        ("duplicated_faces", b.duplicated_faces),
        ("dropped_faces", b.dropped_faces),
        ("dropped_triangles", b.dropped_triangles),
        ("unreferenced_vertices", b.unreferenced_vertices),
        ("merged_vertices", b.merged_vertices),
        (
            "welded_vertices",
            loaded.welding.as_ref().map_or(0, |w| w.merged_vertices),
        ),
    ];
    Ok(PyMesh {
        inner: loaded.mesh,
        fixes: Some(fixes),
    })
}

/// The genus from the Euler characteristic (as `multires info` computes it).
fn genus(components: usize, boundary_loops: usize, euler: i64) -> f64 {
    (2.0 * components as f64 - boundary_loops as f64 - euler as f64) / 2.0
}

/// The `multires info` report of a mesh as a dict.
pub fn info_dict<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    fixes: Option<&[(&'static str, usize)]>,
) -> PyResult<Bound<'py, PyDict>> {
    let t = py.allow_threads(|| mesh.topology_report());
    let d = PyDict::new(py);
    d.set_item("vertices", t.vertices)?;
    d.set_item("faces", t.faces)?;
    d.set_item("edges", t.edges)?;
    d.set_item("boundary_loops", t.boundary_loops)?;
    d.set_item("boundary_vertices", t.boundary_vertices)?;
    d.set_item("components", t.components)?;
    d.set_item("euler", t.euler)?;
    let g = genus(t.components, t.boundary_loops, t.euler);
    if g.fract() == 0.0 {
        d.set_item("genus", g as i64)?;
    } else {
        d.set_item("genus", g)?;
    }
    d.set_item("non_manifold_vertices", t.non_manifold_vertices)?;
    match mesh.bounding_box() {
        Some((lo, hi)) => {
            d.set_item("bbox_min", lo.to_array().to_vec())?;
            d.set_item("bbox_max", hi.to_array().to_vec())?;
            d.set_item("diagonal", lo.distance(hi))?;
        }
        None => {
            d.set_item("bbox_min", py.None())?;
            d.set_item("bbox_max", py.None())?;
            d.set_item("diagonal", 0.0)?;
        }
    }
    if let Some(fixes) = fixes {
        let f = PyDict::new(py);
        for (k, v) in fixes {
            f.set_item(*k, *v)?;
        }
        d.set_item("fixes", f)?;
    }
    Ok(d)
}

/// Builds a mesh from checked arrays, releasing the GIL.
pub fn mesh_from_arrays(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
) -> PyResult<PyMesh> {
    let points = arrays::points(vertices, "vertices")?;
    let (flat, _) = arrays::integers(faces, "faces", Some(3), points.len())?;
    let triangles: Vec<[u32; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let (mesh, build) = py
        .allow_threads(|| Mesh::from_arrays(&points, &triangles))
        .map_err(Fail::from)?;
    let fixes = vec![
        ("duplicated_vertices", build.duplicated_vertices),
        ("duplicated_faces", build.duplicated_faces),
        ("dropped_faces", build.dropped_faces),
        ("dropped_triangles", build.dropped_triangles),
        ("unreferenced_vertices", build.unreferenced_vertices),
        ("merged_vertices", build.merged_vertices),
        ("welded_vertices", 0),
    ];
    Ok(PyMesh {
        inner: mesh,
        fixes: Some(fixes),
    })
}

/// The vertex positions as an `(n, 3)` float64 array (live vertices in writer order).
pub fn vertex_array<'py>(py: Python<'py>, mesh: &Mesh) -> Bound<'py, PyArray2<f64>> {
    let positions: Vec<[f64; 3]> = mesh
        .vertices()
        .map(|v| mesh.position(v).to_array())
        .collect();
    arrays::to_points(py, &positions)
}

/// The faces as an `(m, 3)` int64 array of rows of the vertex array.
pub fn face_array<'py>(py: Python<'py>, mesh: &Mesh) -> Bound<'py, PyArray2<i64>> {
    let (_, triangles) = py.allow_threads(|| mesh.to_arrays());
    let rows: Vec<[i64; 3]> = triangles.iter().map(|t| t.map(i64::from)).collect();
    arrays::to_rows(py, &rows)
}

/// Writes new positions for the live vertices, checked (shape, finiteness).
pub fn set_positions(mesh: &mut Mesh, points: &[[f64; 3]]) -> PyResult<()> {
    let live = arrays::live(mesh);
    if points.len() != live.len() {
        return Err(mesh_err(format!(
            "vertices: expected shape ({}, 3), got ({}, 3)",
            live.len(),
            points.len()
        )));
    }
    for (&v, p) in live.iter().zip(points) {
        mesh.set_position(v, glam::DVec3::from_array(*p));
    }
    Ok(())
}

#[pymethods]
impl PyMesh {
    /// Builds a mesh from an ``(n, 3)`` float array of positions and an ``(m, 3)``
    /// integer array (any integer dtype) of triangles. Faces that would make the mesh
    /// non-manifold go onto copies of their vertices and faces with a repeated index are
    /// dropped (``info()['fixes']`` counts both), as the file readers do.
    ///
    /// Raises :class:`MeshError` for a wrong dtype or shape, a NaN or infinite
    /// coordinate, an index out of range, or no vertices.
    #[staticmethod]
    fn from_arrays(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        mesh_from_arrays(py, vertices, faces)
    }

    /// The vertex positions, an ``(n, 3)`` float64 array (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        vertex_array(py, &self.inner)
    }

    /// Sets every vertex position from an ``(n, 3)`` float array (same ``n``).
    #[setter]
    fn set_vertices(&mut self, vertices: &Bound<'_, PyAny>) -> PyResult<()> {
        let points = arrays::points(vertices, "vertices")?;
        set_positions(&mut self.inner, &points)
    }

    /// The triangles, an ``(m, 3)`` int64 array of rows of :attr:`vertices`.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        face_array(py, &self.inner)
    }

    /// Number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.inner.n_vertices()
    }

    /// Number of faces.
    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.n_faces()
    }

    /// Number of edges.
    #[getter]
    fn n_edges(&self) -> usize {
        self.inner.n_edges()
    }

    /// Writes the mesh; the format follows the extension (``.obj``, ``.ply`` binary,
    /// ``.off``, ``.stl`` binary, each also ``.gz``). Releases the GIL.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let mesh = &self.inner;
        py.allow_threads(|| halfedge::io::write(&path, mesh))
            .map_err(Fail::from)?;
        Ok(())
    }

    /// Checks every invariant of the half-edge structure; raises :class:`MeshError`
    /// naming the first broken one.
    fn check(&self, py: Python<'_>) -> PyResult<()> {
        let mesh = &self.inner;
        py.allow_threads(|| mesh.check()).map_err(Fail::from)?;
        Ok(())
    }

    /// What the mesh is made of, as ``multires info`` reports it: ``vertices``,
    /// ``faces``, ``edges``, ``boundary_loops``, ``boundary_vertices``, ``components``,
    /// ``euler``, ``genus``, ``non_manifold_vertices``, ``bbox_min``, ``bbox_max``,
    /// ``diagonal``, and ``fixes`` (what the reader changed) for a mesh read or built.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        info_dict(py, &self.inner, self.fixes.as_deref())
    }

    /// A welded copy: ``"auto"`` merges vertices at exactly the same position when that
    /// closes boundaries, a number ``F`` merges vertices within ``F`` times the
    /// bounding-box diagonal, ``"off"`` copies.
    #[pyo3(signature = (tolerance = None))]
    fn welded(&self, py: Python<'_>, tolerance: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let weld = match tolerance {
            Some(t) => parse_weld(t)?,
            None => Weld::Auto,
        };
        let mesh = self.inner.clone();
        let loaded = py
            .allow_threads(|| {
                load::apply_weld(mesh, halfedge::BuildReport::default(), weld, &mut Silent)
            })
            .map_err(Fail::from)?;
        let welded = loaded.welding.as_ref().map_or(0, |w| w.merged_vertices);
        let mut out = PyMesh::new(loaded.mesh);
        out.fixes = Some(vec![("welded_vertices", welded)]);
        Ok(out)
    }

    /// An independent copy.
    fn copy(&self) -> Self {
        self.clone()
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    /// Pickling: the vertex and face arrays.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let this = slf.borrow();
        let v = vertex_array(py, &this.inner);
        let f = face_array(py, &this.inner);
        let ctor = py.get_type::<PyMesh>().getattr("from_arrays")?;
        (ctor, (v, f)).into_pyobject(py).map(|t| t.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(vertices={}, faces={}, edges={})",
            self.inner.n_vertices(),
            self.inner.n_faces(),
            self.inner.n_edges()
        )
    }
}

/// Reads a mesh file (OBJ, PLY, OFF, STL, each also ``.gz``) as the ``multires`` command
/// reads it, then welds it: ``"auto"`` (default) merges vertices at exactly the same
/// position when that closes boundaries, ``"off"`` keeps the file's vertices, a number
/// ``F`` merges vertices within ``F`` times the bounding-box diagonal. Releases the GIL.
///
/// Raises FileNotFoundError for a missing file and :class:`MeshError` for a file that is
/// not a mesh of a known format.
#[pyfunction]
#[pyo3(signature = (path, weld = None))]
pub fn read(py: Python<'_>, path: PathBuf, weld: Option<&Bound<'_, PyAny>>) -> PyResult<PyMesh> {
    let weld = match weld {
        Some(w) => parse_weld(w)?,
        None => Weld::Auto,
    };
    read_mesh(py, path, weld)
}

/// A unit icosphere: the icosahedron subdivided ``level`` times (20·4^level faces).
#[pyfunction]
pub fn icosphere(level: usize) -> PyResult<PyMesh> {
    if level > 9 {
        return Err(mesh_err(format!("level: at most 9, got {level}")));
    }
    Ok(PyMesh::new(halfedge::generators::icosphere(level)))
}

/// How far apart the surfaces of ``a`` and ``b`` are, as Metro measures a
/// simplification's error: each surface is sampled by its vertices (unless ``vertices``
/// is false) and ``samples`` points spread over its faces by area, and each sample's
/// distance to the other surface taken. Returns a dict: ``"hausdorff"`` (the larger
/// one-sided maximum), ``"mean"`` (over both sides' samples), ``"diagonal"`` (of ``a``'s
/// bounding box, the usual unit) and per side (``"a_to_b"``, ``"b_to_a"``) a dict of
/// ``samples``, ``mean``, ``rms``, ``max``. The same meshes give the same figures on any
/// number of threads. Releases the GIL.
///
/// Raises :class:`MeshError` when a mesh has no face or a vertex that is not finite, or
/// when nothing is sampled.
#[pyfunction]
#[pyo3(signature = (a, b, samples = 100_000, vertices = true))]
pub fn surface_distance<'py>(
    py: Python<'py>,
    a: PyRef<'_, PyMesh>,
    b: PyRef<'_, PyMesh>,
    samples: usize,
    vertices: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use halfedge::surface_distance::{surface_distance, OneSided, Sampling};
    let sampling = Sampling {
        vertices,
        face_samples: samples,
    };
    let (ma, mb) = (&a.inner, &b.inner);
    let d = py
        .allow_threads(|| surface_distance(ma, mb, &sampling))
        .map_err(Fail::from)?;
    let side = |s: &OneSided| -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        dict.set_item("samples", s.samples)?;
        dict.set_item("mean", s.mean)?;
        dict.set_item("rms", s.rms)?;
        dict.set_item("max", s.max)?;
        Ok(dict)
    };
    let dict = PyDict::new(py);
    dict.set_item("hausdorff", d.hausdorff())?;
    dict.set_item("mean", d.mean())?;
    dict.set_item("diagonal", d.diagonal)?;
    dict.set_item("a_to_b", side(&d.forward)?)?;
    dict.set_item("b_to_a", side(&d.backward)?)?;
    Ok(dict)
}

/// A flat open grid of ``nx`` × ``ny`` squares (two triangles each), ``sx`` × ``sy``
/// in size, in the z = 0 plane.
#[pyfunction]
#[pyo3(signature = (nx, ny, sx = 1.0, sy = 1.0))]
pub fn grid(nx: usize, ny: usize, sx: f64, sy: f64) -> PyResult<PyMesh> {
    if nx == 0 || ny == 0 || nx.saturating_mul(ny) > 50_000_000 {
        return Err(mesh_err(format!(
            "grid: nx and ny must be positive with nx*ny at most 5e7, got {nx} x {ny}"
        )));
    }
    if !(sx.is_finite() && sy.is_finite()) {
        return Err(mesh_err("grid: sizes must be finite"));
    }
    Ok(PyMesh::new(halfedge::generators::grid(nx, ny, sx, sy)))
}

/// A closed torus of genus 1, ``nu`` × ``nv`` quads split in two.
#[pyfunction]
#[pyo3(signature = (major = 1.0, minor = 0.3, nu = 32, nv = 16))]
pub fn torus(major: f64, minor: f64, nu: usize, nv: usize) -> PyResult<PyMesh> {
    if nu.saturating_mul(nv) > 50_000_000 {
        return Err(mesh_err("torus: nu*nv at most 5e7"));
    }
    let mesh = halfedge::generators::torus(major, minor, nu, nv).map_err(Fail::from)?;
    Ok(PyMesh::new(mesh))
}
