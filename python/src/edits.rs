//! The editing methods, each on a `Mesh` or on a `Hierarchy` at its current level (then
//! marked in the hierarchy, exactly as the Rust API and the recipes do, so that refining
//! brings the edit to full resolution), with regions as index arrays or boolean masks
//! and transforms as 4×4 / 3×4 matrices. Every call releases the GIL while it computes.

use edit::bendels_klein::image::{ImageOptions, ImageSessionOf, Mask, RasterOf, Sample};
use edit::bendels_klein::polyline::{
    CurveDistance, CurveRegions, Polyline, PolylineOptions, PolylineSession,
};
use edit::bendels_klein::{
    BlendOptions, BlendPoint, BlendSession, DistanceKind, RefineOptions, Regions, Role,
    ShapeFunction,
};
use edit::deform::{
    apply_deformer, AttachOptions, Axis, Bend, Deformer, Ffd, LatticeFrame, Propagation,
    SmoothingWeights, SubMesh, SubmeshEdit, Taper, TaubinOptions, Twist, Variation,
};
use edit::lee::{AreaSession, EditingArea, FrameKind, SessionOptions};
use edit::{HierarchyEdit, Vertices};
use glam::{DMat3, DMat4, DVec2, DVec3};
use halfedge::hierarchy::Hierarchy;
use halfedge::{FaceId, Mesh, VertexId};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{mesh_err, Fail, Res};
use crate::hierarchy::PyHierarchy;
use crate::mesh::PyMesh;

/// What an edit acts on, borrowed for the call.
pub enum Guard<'py> {
    /// A plain mesh.
    Mesh(PyRefMut<'py, PyMesh>),
    /// A hierarchy at its current level.
    Hierarchy(PyRefMut<'py, PyHierarchy>),
}

impl<'py> Guard<'py> {
    /// Borrows `target` (a `Mesh` or a `Hierarchy`) mutably.
    pub fn of(target: &Bound<'py, PyAny>) -> PyResult<Self> {
        if let Ok(m) = target.downcast::<PyMesh>() {
            return Ok(Guard::Mesh(m.try_borrow_mut()?));
        }
        if let Ok(h) = target.downcast::<PyHierarchy>() {
            return Ok(Guard::Hierarchy(h.try_borrow_mut()?));
        }
        Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "expected a multires.Mesh or multires.Hierarchy, got {}",
            target.get_type().name()?
        )))
    }
    /// The mesh edited.
    pub fn mesh(&self) -> &Mesh {
        match self {
            Guard::Mesh(m) => &m.inner,
            Guard::Hierarchy(h) => h.inner.mesh(),
        }
    }
    /// The target, to move into a closure run without the GIL.
    pub fn target(&mut self) -> Target<'_> {
        match self {
            Guard::Mesh(m) => Target::Mesh(&mut m.inner),
            Guard::Hierarchy(h) => Target::Hierarchy(&mut h.inner),
        }
    }
}

/// A mesh or a hierarchy, mutably (sendable: runs without the GIL).
pub enum Target<'a> {
    /// A plain mesh.
    Mesh(&'a mut Mesh),
    /// A hierarchy at its current level.
    Hierarchy(&'a mut Hierarchy),
}

impl Target<'_> {
    fn mesh(&self) -> &Mesh {
        match self {
            Target::Mesh(m) => m,
            Target::Hierarchy(h) => h.mesh(),
        }
    }
    fn mesh_mut(&mut self) -> &mut Mesh {
        match self {
            Target::Mesh(m) => m,
            Target::Hierarchy(h) => h.mesh_mut(),
        }
    }
    /// Tells the hierarchy what the edit did (nothing for a plain mesh).
    fn mark(&mut self, edit: &dyn HierarchyEdit) -> Res<()> {
        if let Target::Hierarchy(h) = self {
            edit.mark(h)?;
        }
        Ok(())
    }
}

fn shape_function(shape: &str) -> PyResult<ShapeFunction> {
    Ok(match shape {
        "smoothstep" => ShapeFunction::Smoothstep,
        "linear" => ShapeFunction::Linear,
        "smootherstep" | "c2" => ShapeFunction::Smootherstep,
        other => {
            return Err(mesh_err(format!(
                "shape: {other:?} is not 'smoothstep', 'linear' or 'smootherstep'"
            )))
        }
    })
}

fn refine_options(max_edge_length: f64, max_new_vertices: Option<usize>) -> RefineOptions {
    let o = RefineOptions::new(max_edge_length);
    match max_new_vertices {
        Some(n) => o.with_max_new_vertices(n),
        None => o,
    }
}

/// The region's vertices, or every live vertex.
fn region_or_all(
    obj: Option<&Bound<'_, PyAny>>,
    what: &str,
    live: &[VertexId],
) -> PyResult<Vec<VertexId>> {
    match obj {
        Some(o) if !o.is_none() => arrays::region(o, what, live),
        _ => Ok(live.to_vec()),
    }
}

/// Lee 1999 area editing: the editing area (``area``: the faces whose three vertices
/// are all in this region, index array or mask; or ``disk=(seed, vertex_count)``: rings
/// around ``seed`` until that many vertices) is parametrised, its ``primitive`` vertices
/// are dragged by ``displacement`` (three numbers) and the rest of the area follows by
/// multilevel B-spline interpolation at scale ``scale`` in [0, 1]. ``frames`` is
/// ``"global"`` or ``"normal"`` (detail in local normal frames). On a hierarchy the edit
/// is made at the current level and marked for refinement. Returns the number of area
/// vertices.
#[pyfunction]
#[pyo3(signature = (target, primitive, displacement, *, area = None, disk = None, scale = 0.5, frames = "global"))]
#[allow(clippy::too_many_arguments)]
pub fn lee_drag(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    primitive: &Bound<'_, PyAny>,
    displacement: &Bound<'_, PyAny>,
    area: Option<&Bound<'_, PyAny>>,
    disk: Option<(i64, usize)>,
    scale: f64,
    frames: &str,
) -> PyResult<usize> {
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let primitive = arrays::region(primitive, "primitive", &live)?;
    let displacement = arrays::vec3(displacement, "displacement")?;
    if !(0.0..=1.0).contains(&scale) {
        return Err(mesh_err(format!("scale: must be in [0, 1], got {scale}")));
    }
    let frames = match frames {
        "global" => FrameKind::Global,
        "normal" => FrameKind::Normal {
            seed: None,
            x_axis: None,
        },
        other => {
            return Err(mesh_err(format!(
                "frames: {other:?} is not 'global' or 'normal'"
            )))
        }
    };
    enum AreaSpec {
        Vertices(Vec<VertexId>),
        Disk(VertexId, usize),
    }
    let spec = match (area, disk) {
        (Some(a), None) => AreaSpec::Vertices(arrays::region(a, "area", &live)?),
        (None, Some((seed, count))) => {
            if seed < 0 || seed as usize >= live.len() {
                return Err(mesh_err(format!(
                    "disk: the seed {seed} is out of range for {} vertices",
                    live.len()
                )));
            }
            AreaSpec::Disk(live[seed as usize], count)
        }
        _ => return Err(mesh_err("give exactly one of area and disk")),
    };
    let mut t = guard.target();
    let n = py.allow_threads(move || -> Res<usize> {
        let mesh = t.mesh();
        let area = match spec {
            AreaSpec::Disk(seed, count) => EditingArea::disk_around(mesh, seed, count)?,
            AreaSpec::Vertices(vs) => {
                let mut inside = vec![false; mesh.vertex_slots()];
                for v in vs {
                    inside[mesh.vertex_index(v)] = true;
                }
                let faces: Vec<FaceId> = mesh
                    .faces()
                    .filter(|&f| {
                        mesh.triangle(f)
                            .iter()
                            .all(|&v| inside[mesh.vertex_index(v)])
                    })
                    .collect();
                EditingArea::from_faces(mesh, &faces)?
            }
        };
        let n_area = area.vertices().len();
        let options = SessionOptions::default()
            .with_scale(scale)
            .with_frames(frames);
        let mut session = AreaSession::new(mesh, area, &options)?;
        session.set_primitive(t.mesh(), &primitive)?;
        session.drag(t.mesh_mut(), displacement)?;
        t.mark(&session)?;
        session.commit(t.mesh())?;
        Ok(n_area)
    })?;
    Ok(n)
}

/// Bendels & Klein editing regions: the ``handle`` vertices move rigidly by
/// ``transform`` (4×4 or 3×4 affine matrix acting on column vectors), the ``fixed``
/// ones stay, and every other vertex moves by the transform's power ``alpha``, blended
/// by the shape function (``"smoothstep"``, ``"linear"``, ``"smootherstep"``) of its
/// ``distance`` (``"geodesic"`` or ``"euclidean"``) to both. ``refine``: a maximum edge
/// length; longer deformed edges are split afterwards (on a hierarchy the hierarchy is
/// rebuilt with the new vertices and returns to its level). Returns a dict with
/// ``handle``, ``deformable`` and ``new_vertices`` counts.
#[pyfunction]
#[pyo3(signature = (target, handle, fixed, transform, *, distance = "geodesic", shape = "smoothstep", refine = None, max_new_vertices = None))]
#[allow(clippy::too_many_arguments)]
pub fn blend<'py>(
    py: Python<'py>,
    target: &Bound<'py, PyAny>,
    handle: &Bound<'py, PyAny>,
    fixed: &Bound<'py, PyAny>,
    transform: &Bound<'py, PyAny>,
    distance: &str,
    shape: &str,
    refine: Option<f64>,
    max_new_vertices: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let handle = arrays::region(handle, "handle", &live)?;
    let fixed = arrays::region(fixed, "fixed", &live)?;
    let a = arrays::affine3(transform, "transform")?;
    let distance = match distance {
        "geodesic" => DistanceKind::Geodesic,
        "euclidean" => DistanceKind::Euclidean,
        other => {
            return Err(mesh_err(format!(
                "distance: {other:?} is not 'geodesic' or 'euclidean'"
            )))
        }
    };
    let shape = shape_function(shape)?;
    let mut t = guard.target();
    let (n_handle, n_deformable, new_vertices) =
        py.allow_threads(move || -> Res<(usize, usize, usize)> {
            let regions = Regions::from_sets(t.mesh(), &handle, &fixed)?;
            let counts = (regions.handle().len(), regions.deformable().len());
            let options = BlendOptions::default()
                .with_distance(distance)
                .with_shape(shape);
            let mut session = BlendSession::new(t.mesh(), regions, options)?;
            session.apply(t.mesh_mut(), a)?;
            t.mark(&session)?;
            let mut new_vertices = 0;
            if let Some(length) = refine {
                let options = refine_options(length, max_new_vertices);
                let report = match &mut t {
                    Target::Mesh(m) => session.refine(m, options)?,
                    Target::Hierarchy(h) => session.refine_in_hierarchy(h, options)?,
                };
                new_vertices = report.new_vertices;
            }
            Ok((counts.0, counts.1, new_vertices))
        })?;
    let d = PyDict::new(py);
    d.set_item("handle", n_handle)?;
    d.set_item("deformable", n_deformable)?;
    d.set_item("new_vertices", new_vertices)?;
    Ok(d)
}

fn propagation(levels: usize, falloff: &str) -> PyResult<Propagation> {
    match falloff {
        "linear" => Ok(Propagation::linear(levels)),
        "smooth" => Ok(Propagation::smooth(levels)),
        other => Err(mesh_err(format!(
            "falloff: {other:?} is not 'linear' or 'smooth'"
        ))),
    }
}

fn variation(v: Option<&Bound<'_, PyAny>>) -> PyResult<Variation> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(Variation::Levels(None));
    };
    if let Ok(s) = v.extract::<String>() {
        return match s.as_str() {
            "uniform" => Ok(Variation::Uniform),
            "levels" => Ok(Variation::Levels(None)),
            other => Err(mesh_err(format!(
                "variation: {other:?} is not 'uniform', 'levels', a level count or (start, end)"
            ))),
        };
    }
    if let Ok(l) = v.extract::<usize>() {
        return Ok(Variation::Levels(Some(l)));
    }
    if let Ok((start, end)) = v.extract::<(f64, f64)>() {
        return Ok(Variation::Along { start, end });
    }
    Err(mesh_err(
        "variation: expected 'uniform', 'levels', a level count or (start, end)",
    ))
}

fn axis(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Axis>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let (p, d): (Bound<'_, PyAny>, Bound<'_, PyAny>) = obj
        .extract()
        .map_err(|_| mesh_err("axis: expected (point, direction)"))?;
    let axis = Axis::new(
        arrays::vec3(&p, "axis point")?,
        arrays::vec3(&d, "axis direction")?,
    )
    .map_err(|e| mesh_err(format!("axis: {e}")))?;
    Ok(Some(axis))
}

/// The edit to make once the sub-mesh is known (some defaults depend on it).
enum SubmeshSpec {
    Ready(SubmeshEdit),
    /// Scale about the sub-mesh's centroid.
    ScaleAtCentroid(f64),
    /// Rotation about the frontier plane's normal through its centre.
    RotateAtFrontier {
        angle: f64,
        bounded: bool,
    },
}

fn run_submesh(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    spec: SubmeshSpec,
    propagation: Propagation,
) -> PyResult<usize> {
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let region = arrays::region(region, "region", &live)?;
    let mut t = guard.target();
    let n = py.allow_threads(move || -> Res<usize> {
        let sub = SubMesh::from_vertices(t.mesh(), &region)?;
        let mesh = t.mesh();
        let edit = match spec {
            SubmeshSpec::Ready(e) => e,
            SubmeshSpec::ScaleAtCentroid(factor) => SubmeshEdit::Scale {
                centre: sub
                    .vertex_indices()
                    .iter()
                    .map(|&i| mesh.positions()[i as usize])
                    .sum::<DVec3>()
                    / sub.len().max(1) as f64,
                factor,
            },
            SubmeshSpec::RotateAtFrontier { angle, bounded } => {
                let plane = sub.frontier_plane(mesh)?;
                SubmeshEdit::Rotate {
                    axis: Axis::new(plane.point, plane.normal)?,
                    angle,
                    bounded,
                }
            }
        };
        let applied = sub.apply_with_marks(t.mesh_mut(), &edit, propagation)?;
        t.mark(&applied)?;
        Ok(sub.len())
    })?;
    Ok(n)
}

/// Sub-mesh edit: translates the sub-mesh ``region`` by ``offset``; the change fades
/// over ``propagation`` rings of the host (``falloff`` ``"linear"`` or ``"smooth"``).
/// Returns the sub-mesh's vertex count.
#[pyfunction]
#[pyo3(signature = (target, region, offset, *, propagation = 2, falloff = "linear"))]
pub fn submesh_pull(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    offset: &Bound<'_, PyAny>,
    propagation: usize,
    falloff: &str,
) -> PyResult<usize> {
    let offset = arrays::vec3(offset, "offset")?;
    let p = self::propagation(propagation, falloff)?;
    run_submesh(
        py,
        target,
        region,
        SubmeshSpec::Ready(SubmeshEdit::Pull { offset }),
        p,
    )
}

/// Sub-mesh edit: scales ``region`` by ``factor`` about ``centre`` (default: its
/// centroid). Returns the sub-mesh's vertex count.
#[pyfunction]
#[pyo3(signature = (target, region, factor, *, centre = None, propagation = 2, falloff = "linear"))]
pub fn submesh_scale(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    factor: f64,
    centre: Option<&Bound<'_, PyAny>>,
    propagation: usize,
    falloff: &str,
) -> PyResult<usize> {
    let p = self::propagation(propagation, falloff)?;
    let spec = match centre.filter(|c| !c.is_none()) {
        Some(c) => SubmeshSpec::Ready(SubmeshEdit::Scale {
            centre: arrays::vec3(c, "centre")?,
            factor,
        }),
        None => SubmeshSpec::ScaleAtCentroid(factor),
    };
    run_submesh(py, target, region, spec, p)
}

/// Sub-mesh edit: rotates ``region`` by ``degrees`` about ``axis`` (``(point,
/// direction)``; default: the normal of the plane fitted to its frontier, through the
/// frontier's centre). Returns the sub-mesh's vertex count.
#[pyfunction]
#[pyo3(signature = (target, region, degrees, *, axis = None, bounded = false, propagation = 2, falloff = "linear"))]
#[allow(clippy::too_many_arguments)]
pub fn submesh_rotate(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    degrees: f64,
    axis: Option<&Bound<'_, PyAny>>,
    bounded: bool,
    propagation: usize,
    falloff: &str,
) -> PyResult<usize> {
    let p = self::propagation(propagation, falloff)?;
    let angle = degrees.to_radians();
    let spec = match self::axis(axis)? {
        Some(axis) => SubmeshSpec::Ready(SubmeshEdit::Rotate {
            axis,
            angle,
            bounded,
        }),
        None => SubmeshSpec::RotateAtFrontier { angle, bounded },
    };
    run_submesh(py, target, region, spec, p)
}

/// Sub-mesh edit: Barr's taper of ``region`` by ``factor`` about ``axis`` (``(point,
/// direction)``, default the sub-mesh's own axis); ``variation`` is ``None``/"levels"
/// (progressive from the frontier), a level count, ``"uniform"`` or ``(start, end)``
/// along the axis. Returns the sub-mesh's vertex count.
#[pyfunction]
#[pyo3(signature = (target, region, factor, *, axis = None, variation = None, propagation = 2, falloff = "linear"))]
#[allow(clippy::too_many_arguments)]
pub fn submesh_taper(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    factor: f64,
    axis: Option<&Bound<'_, PyAny>>,
    variation: Option<&Bound<'_, PyAny>>,
    propagation: usize,
    falloff: &str,
) -> PyResult<usize> {
    let p = self::propagation(propagation, falloff)?;
    let edit = SubmeshEdit::Taper {
        axis: self::axis(axis)?,
        factor,
        variation: self::variation(variation)?,
    };
    run_submesh(py, target, region, SubmeshSpec::Ready(edit), p)
}

/// Sub-mesh edit: Barr's twist of ``region`` by ``degrees`` about ``axis`` (as
/// :func:`submesh_taper`). Returns the sub-mesh's vertex count.
#[pyfunction]
#[pyo3(signature = (target, region, degrees, *, axis = None, variation = None, propagation = 2, falloff = "linear"))]
#[allow(clippy::too_many_arguments)]
pub fn submesh_twist(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    region: &Bound<'_, PyAny>,
    degrees: f64,
    axis: Option<&Bound<'_, PyAny>>,
    variation: Option<&Bound<'_, PyAny>>,
    propagation: usize,
    falloff: &str,
) -> PyResult<usize> {
    let p = self::propagation(propagation, falloff)?;
    let edit = SubmeshEdit::Twist {
        axis: self::axis(axis)?,
        angle: degrees.to_radians(),
        variation: self::variation(variation)?,
    };
    run_submesh(py, target, region, SubmeshSpec::Ready(edit), p)
}

/// Applies a Barr deformer to `vertices` (all when `None`) and, on a hierarchy, marks it
/// as a field so that the fine vertices land on the same deformation of the input.
fn run_deformer<D: Deformer + Clone + Send + Sync + 'static>(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    vertices: Option<&Bound<'_, PyAny>>,
    deformer: D,
) -> PyResult<()> {
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let vertices = region_or_all(vertices, "vertices", &live)?;
    let mut t = guard.target();
    py.allow_threads(move || -> Res<()> {
        apply_deformer(t.mesh_mut(), &deformer, Vertices::List(&vertices))?;
        if let Target::Hierarchy(h) = &mut t {
            let d = deformer.clone();
            h.mark_field(&vertices, move |p| d.deform_point(p))?;
        }
        Ok(())
    })?;
    Ok(())
}

/// Barr's global taper: scales across ``axis`` (through ``centre``) by a factor going
/// linearly from 1 at axial coordinate ``start`` to ``factor`` at ``end`` (held beyond).
/// ``vertices``: index array or mask (default all). On a hierarchy the deformation is
/// marked as a field: refined, the fine vertices land on the taper of the input.
#[pyfunction]
#[pyo3(signature = (target, centre, axis, start, end, factor, *, vertices = None))]
#[allow(clippy::too_many_arguments)]
pub fn barr_taper(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    centre: &Bound<'_, PyAny>,
    axis: &Bound<'_, PyAny>,
    start: f64,
    end: f64,
    factor: f64,
    vertices: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let d = Taper::linear(
        arrays::vec3(centre, "centre")?,
        arrays::vec3(axis, "axis")?,
        start,
        end,
        factor,
    )
    .map_err(Fail::from)?;
    run_deformer(py, target, vertices, d)
}

/// Barr's twist about ``axis`` through ``centre``: the angle goes linearly from 0 at
/// axial coordinate ``start`` to ``degrees`` at ``end``. As :func:`barr_taper`.
#[pyfunction]
#[pyo3(signature = (target, centre, axis, start, end, degrees, *, vertices = None))]
#[allow(clippy::too_many_arguments)]
pub fn barr_twist(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    centre: &Bound<'_, PyAny>,
    axis: &Bound<'_, PyAny>,
    start: f64,
    end: f64,
    degrees: f64,
    vertices: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let d = Twist::linear(
        arrays::vec3(centre, "centre")?,
        arrays::vec3(axis, "axis")?,
        start,
        end,
        degrees.to_radians(),
    )
    .map_err(Fail::from)?;
    run_deformer(py, target, vertices, d)
}

/// Barr's bend: the region along ``axis`` (through ``centre``) bends towards
/// ``direction`` with curvature ``rate`` (1 / radius), within the axial ``range``
/// ``(lo, hi)`` (default unbounded). As :func:`barr_taper`.
#[pyfunction]
#[pyo3(signature = (target, centre, axis, direction, rate, *, range = None, vertices = None))]
#[allow(clippy::too_many_arguments)]
pub fn barr_bend(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    centre: &Bound<'_, PyAny>,
    axis: &Bound<'_, PyAny>,
    direction: &Bound<'_, PyAny>,
    rate: f64,
    range: Option<(f64, f64)>,
    vertices: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let d = Bend::new(
        arrays::vec3(centre, "centre")?,
        arrays::vec3(axis, "axis")?,
        arrays::vec3(direction, "direction")?,
        rate,
        range,
    )
    .map_err(Fail::from)?;
    run_deformer(py, target, vertices, d)
}

/// Taubin λ|μ smoothing of ``vertices`` (index array or mask, default all; the others
/// stay), ``iterations`` pairs of steps, ``weights`` ``"uniform"`` or ``"cotangent"``.
/// On a hierarchy the smoothed vertices are marked as the edit's region.
#[pyfunction]
#[pyo3(signature = (target, *, vertices = None, iterations = 10, lambda_ = 0.33, mu = -0.34, weights = "uniform", fix_boundary = true))]
#[allow(clippy::too_many_arguments)]
pub fn taubin(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    vertices: Option<&Bound<'_, PyAny>>,
    iterations: usize,
    lambda_: f64,
    mu: f64,
    weights: &str,
    fix_boundary: bool,
) -> PyResult<()> {
    let weights = match weights {
        "uniform" => SmoothingWeights::Uniform,
        "cotangent" => SmoothingWeights::Cotangent,
        other => {
            return Err(mesh_err(format!(
                "weights: {other:?} is not 'uniform' or 'cotangent'"
            )))
        }
    };
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let vertices = region_or_all(vertices, "vertices", &live)?;
    let mut options = TaubinOptions::default()
        .with_lambda(lambda_)
        .with_mu(mu)
        .with_weights(weights);
    options.fix_boundary = fix_boundary;
    let mut t = guard.target();
    py.allow_threads(move || -> Res<()> {
        edit::deform::taubin(
            t.mesh_mut(),
            Vertices::List(&vertices),
            &options,
            iterations,
        )?;
        if let Target::Hierarchy(h) = &mut t {
            h.mark_region(&vertices)?;
        }
        Ok(())
    })?;
    Ok(())
}

/// Shape/height-surface free-form deformation: ``vertices`` are attached to B-spline
/// surfaces laid over their footprint in the frame at ``origin`` (``up`` its y axis,
/// ``x_direction`` its x), grids given as ``((degree_u, degree_v), (count_u,
/// count_v))`` and grown by ``margin``; then the surfaces are changed by ``translate``
/// (three numbers), ``bend`` (radians), ``twist`` (radians), ``taper`` (``(start,
/// end)`` factors) and ``scale_heights`` (a factor), in that order, and the vertices
/// follow. On a hierarchy the footprint is marked as the edit's region. Returns the
/// number of vertices attached.
#[pyfunction]
#[pyo3(signature = (target, vertices, origin, x_direction, up, *, shape_grid = ((3, 3), (4, 4)), height_grid = ((1, 1), (2, 2)), margin = 0.1, translate = None, bend = None, twist = None, taper = None, scale_heights = None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn ffd(
    py: Python<'_>,
    target: &Bound<'_, PyAny>,
    vertices: Option<&Bound<'_, PyAny>>,
    origin: &Bound<'_, PyAny>,
    x_direction: &Bound<'_, PyAny>,
    up: &Bound<'_, PyAny>,
    shape_grid: ((usize, usize), (usize, usize)),
    height_grid: ((usize, usize), (usize, usize)),
    margin: f64,
    translate: Option<&Bound<'_, PyAny>>,
    bend: Option<f64>,
    twist: Option<f64>,
    taper: Option<(f64, f64)>,
    scale_heights: Option<f64>,
) -> PyResult<usize> {
    let frame = LatticeFrame::new(
        arrays::vec3(origin, "origin")?,
        arrays::vec3(x_direction, "x_direction")?,
        arrays::vec3(up, "up")?,
    )
    .map_err(Fail::from)?;
    let translate = match translate.filter(|t| !t.is_none()) {
        Some(t) => Some(arrays::vec3(t, "translate")?),
        None => None,
    };
    let mut guard = Guard::of(target)?;
    let live = arrays::live(guard.mesh());
    let vertices = region_or_all(vertices, "vertices", &live)?;
    let grid = |g: ((usize, usize), (usize, usize))| ([g.0 .0, g.0 .1], [g.1 .0, g.1 .1]);
    let mut t = guard.target();
    let n = py.allow_threads(move || -> Res<usize> {
        let mut ffd = Ffd::covering(
            t.mesh(),
            Vertices::List(&vertices),
            frame,
            grid(shape_grid),
            grid(height_grid),
            margin,
            AttachOptions::default(),
        )?;
        if let Some(v) = translate {
            ffd.translate(v)?;
        }
        if let Some(a) = bend {
            ffd.bend(a)?;
        }
        if let Some(a) = twist {
            ffd.twist(a)?;
        }
        if let Some((s, e)) = taper {
            ffd.taper(s, e)?;
        }
        if let Some(k) = scale_heights {
            ffd.scale_heights(k)?;
        }
        ffd.deform(t.mesh_mut())?;
        t.mark(&ffd)?;
        Ok(ffd.attached())
    })?;
    Ok(n)
}

/// A boolean mask of `(h, w)` as a picture mask.
fn picture_mask(obj: &Bound<'_, PyAny>, what: &str, w: usize, h: usize) -> PyResult<Mask> {
    let flat = arrays::index_set(
        &obj.py().import("numpy")?.call_method1(
            "ravel",
            (obj.py().import("numpy")?.call_method1("asarray", (obj,))?,),
        )?,
        what,
        w * h,
    )?;
    let shape: Vec<usize> = obj
        .py()
        .import("numpy")?
        .call_method1("shape", (obj,))?
        .extract()?;
    if shape != [h, w] {
        return Err(mesh_err(format!(
            "{what}: expected a boolean mask of shape ({h}, {w}), got {shape:?}"
        )));
    }
    let mut mask = Mask::empty(w as u32, h as u32).map_err(Fail::from)?;
    for i in flat {
        mask.set(i % w as u32, i / w as u32, true);
    }
    Ok(mask)
}

#[allow(clippy::too_many_arguments)]
fn blend_picture<'py, S: Sample + numpy::Element>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    shape3: (usize, usize, usize),
    handle: Mask,
    fixed: Mask,
    a: DMat3,
    options: ImageOptions,
    squeeze: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let (h, w, c) = shape3;
    let data: Vec<S> = py
        .import("numpy")?
        .call_method1("ascontiguousarray", (image,))?
        .call_method0("ravel")?
        .downcast_into::<numpy::PyArray1<S>>()?
        .readonly()
        .as_slice()?
        .to_vec();
    let raster = RasterOf::<S>::new(w as u32, h as u32, c as u8, data).map_err(Fail::from)?;
    let out = py.allow_threads(move || -> Res<Vec<S>> {
        let mut session = ImageSessionOf::new(raster, handle, fixed, options)?;
        session.apply(a)?;
        Ok(session.render().data().to_vec())
    })?;
    let arr = Array3::from_shape_vec((h, w, c), out).map_err(|e| mesh_err(e.to_string()))?;
    let arr = arr.into_pyarray(py).into_any();
    if squeeze {
        arr.call_method1("reshape", ((h, w),))
    } else {
        Ok(arr)
    }
}

/// Bendels & Klein on a picture: ``image`` is an ``(h, w)`` or ``(h, w, c)`` uint8 or
/// uint16 array (``c`` 1 to 4), ``handle`` and ``fixed`` ``(h, w)`` boolean masks,
/// ``transform`` a 3×3 or 2×3 affine matrix of pixel coordinates (x right, y down). The
/// handle moves by the transform, the fixed part stays, the rest blends over a grid of
/// ``grid_step`` pixels. Returns the rendered picture, same shape and dtype.
#[pyfunction]
#[pyo3(signature = (image, handle, fixed, transform, *, grid_step = 4, shape = "smoothstep"))]
pub fn blend_image<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    handle: &Bound<'py, PyAny>,
    fixed: &Bound<'py, PyAny>,
    transform: &Bound<'py, PyAny>,
    grid_step: u32,
    shape: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    let image = np.call_method1("asarray", (image,))?;
    let dims: Vec<usize> = image.getattr("shape")?.extract()?;
    let dtype: String = image.getattr("dtype")?.getattr("name")?.extract()?;
    let (h, w, c, squeeze) = match dims.as_slice() {
        [h, w] => (*h, *w, 1, true),
        [h, w, c] if (1..=4).contains(c) => (*h, *w, *c, false),
        _ => {
            return Err(mesh_err(format!(
                "image: expected shape (h, w) or (h, w, c) with c in 1..4, got {dims:?}"
            )))
        }
    };
    let handle = picture_mask(handle, "handle", w, h)?;
    let fixed = picture_mask(fixed, "fixed", w, h)?;
    let a = arrays::affine2(transform, "transform")?;
    let options = ImageOptions::default()
        .with_grid_step(grid_step)
        .with_shape(shape_function(shape)?);
    match dtype.as_str() {
        "uint8" => blend_picture::<u8>(py, &image, (h, w, c), handle, fixed, a, options, squeeze),
        "uint16" => blend_picture::<u16>(py, &image, (h, w, c), handle, fixed, a, options, squeeze),
        other => Err(mesh_err(format!(
            "image: expected dtype uint8 or uint16, got {other}"
        ))),
    }
}

fn blend_curve<'py, P: BlendPoint>(
    py: Python<'py>,
    points: Vec<P>,
    closed: bool,
    roles: Vec<Role>,
    a: P::Affine,
    options: PolylineOptions,
    refine: Option<f64>,
) -> PyResult<Vec<P>> {
    let out = py.allow_threads(move || -> Res<Vec<P>> {
        let curve = Polyline::new(points, closed)?;
        let regions = CurveRegions::from_roles(&curve, roles)?;
        let mut session = PolylineSession::new(&curve, &regions, options)?;
        session.apply(a)?;
        if let Some(length) = refine {
            session.refine(RefineOptions::new(length))?;
        }
        Ok(session.points().to_vec())
    })?;
    Ok(out)
}

/// Bendels & Klein on a polyline: ``points`` is ``(n, 2)`` or ``(n, 3)``, ``handle``
/// and ``fixed`` index arrays or masks of points, ``transform`` a 3×3 / 2×3 matrix for
/// 2-D points or a 4×4 / 3×4 one for 3-D points. ``distance`` is ``"arclength"`` or
/// ``"euclidean"``; ``refine`` a maximum segment length (longer deformed segments are
/// split). Returns the new points, ``(m, 2|3)`` float64.
#[pyfunction]
#[pyo3(signature = (points, handle, fixed, transform, *, closed = false, distance = "arclength", shape = "smoothstep", refine = None))]
#[allow(clippy::too_many_arguments)]
pub fn blend_polyline<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    handle: &Bound<'py, PyAny>,
    fixed: &Bound<'py, PyAny>,
    transform: &Bound<'py, PyAny>,
    closed: bool,
    distance: &str,
    shape: &str,
    refine: Option<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let np = py.import("numpy")?;
    let arr = np.call_method1("asarray", (points,))?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    let dims: Vec<usize> = arr.getattr("shape")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(mesh_err("points: expected an array of numbers"));
    }
    let d = match dims.as_slice() {
        [_, 2] => 2,
        [_, 3] => 3,
        _ => {
            return Err(mesh_err(format!(
                "points: expected shape (n, 2) or (n, 3), got {dims:?}"
            )))
        }
    };
    let n = dims[0];
    let flat: Vec<f64> = arr
        .call_method1("astype", ("float64",))?
        .call_method0("ravel")?
        .call_method0("tolist")?
        .extract()?;
    if let Some(bad) = flat.iter().find(|x| !x.is_finite()) {
        return Err(mesh_err(format!(
            "points: the coordinate {bad} is not finite"
        )));
    }
    let handle = arrays::index_set(handle, "handle", n)?;
    let fixed = arrays::index_set(fixed, "fixed", n)?;
    let mut roles = vec![Role::Deformable; n];
    for &i in &fixed {
        roles[i as usize] = Role::Fixed;
    }
    for &i in &handle {
        if roles[i as usize] == Role::Fixed {
            return Err(mesh_err(format!("handle and fixed overlap at point {i}")));
        }
        roles[i as usize] = Role::Handle;
    }
    let distance = match distance {
        "arclength" => CurveDistance::ArcLength,
        "euclidean" => CurveDistance::Euclidean,
        other => {
            return Err(mesh_err(format!(
                "distance: {other:?} is not 'arclength' or 'euclidean'"
            )))
        }
    };
    let options = PolylineOptions::default()
        .with_distance(distance)
        .with_shape(shape_function(shape)?);
    let rows: Vec<f64> = if d == 2 {
        let pts: Vec<DVec2> = flat
            .chunks_exact(2)
            .map(|c| DVec2::new(c[0], c[1]))
            .collect();
        let a = arrays::affine2(transform, "transform")?;
        blend_curve(py, pts, closed, roles, a, options, refine)?
            .iter()
            .flat_map(|p| [p.x, p.y])
            .collect()
    } else {
        let pts: Vec<DVec3> = flat
            .chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect();
        let a: DMat4 = arrays::affine3(transform, "transform")?;
        blend_curve(py, pts, closed, roles, a, options, refine)?
            .iter()
            .flat_map(|p| p.to_array())
            .collect()
    };
    let m = rows.len() / d;
    let arr = Array2::from_shape_vec((m, d), rows).map_err(|e| mesh_err(e.to_string()))?;
    Ok(arr.into_pyarray(py))
}

/// The vertices (rows of ``vertices``, sorted, int64) of the Lee editing area grown in
/// rings around the vertex ``seed`` until it holds at least ``vertex_count`` vertices:
/// the area ``lee_drag(..., disk=(seed, vertex_count))`` edits, to preview or reuse.
#[pyfunction]
#[pyo3(signature = (target, seed, vertex_count))]
pub fn disk<'py>(
    py: Python<'py>,
    target: &Bound<'py, PyAny>,
    seed: i64,
    vertex_count: usize,
) -> PyResult<Bound<'py, numpy::PyArray1<i64>>> {
    let guard = Guard::of(target)?;
    let mesh = guard.mesh();
    let live = arrays::live(mesh);
    if seed < 0 || seed as usize >= live.len() {
        return Err(mesh_err(format!(
            "seed {seed} is out of range for {} vertices",
            live.len()
        )));
    }
    let area = py
        .allow_threads(|| EditingArea::disk_around(mesh, live[seed as usize], vertex_count))
        .map_err(Fail::from)?;
    let index = halfedge::io::file_vertex_indices(mesh);
    let mut out: Vec<i64> = area
        .vertices()
        .iter()
        .map(|&v| i64::from(index[mesh.vertex_index(v)]))
        .collect();
    out.sort_unstable();
    Ok(numpy::ndarray::Array1::from(out).into_pyarray(py))
}
