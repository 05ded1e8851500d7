//! The facade's jobs from Python: recipes (`multires::recipe`), the workflow
//! (`multires::workflow`) and the per-mesh step of a batch (`multires::batch::process`),
//! so that a Python or Dask batch writes exactly the rows the `multires batch` command
//! writes.

use std::path::{Path, PathBuf};

use halfedge::hierarchy::Method;
use multires::batch::{self, BatchOptions, Input};
use multires::load::{self, Weld};
use multires::progress::Silent;
use multires::recipe::{self, Recipe};
use multires::workflow::{self as wf, WorkflowOptions};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::edits::{Guard, Target};
use crate::errors::{mesh_err, Fail, Res};
use crate::mesh::{parse_weld, PyMesh};

/// A recipe from a file path or from TOML text.
fn recipe_of(source: &str) -> Res<Recipe> {
    let path = Path::new(source);
    if !source.contains('\n') && path.is_file() {
        Ok(Recipe::read(path)?)
    } else if !source.contains('\n') && !source.contains('=') {
        Err(Fail::Io {
            message: format!("{source}: no such recipe file"),
            not_found: true,
        })
    } else {
        Ok(Recipe::from_toml(source, Path::new("<recipe>"))?)
    }
}

/// Applies an edit recipe (a path to a ``.toml`` file, or TOML text) to a
/// :class:`Hierarchy` (each step at its level, marked; the hierarchy is left at the last
/// step's level: call :meth:`Hierarchy.refine` for the full-resolution result) or to a
/// :class:`Mesh` (every step at level 0). Returns one dict per step: ``step``,
/// ``method``, ``level``, ``moved``, ``detail``, ``seconds``. Releases the GIL.
///
/// Raises :class:`RecipeError` naming the step and the key.
#[pyfunction]
pub fn apply_recipe<'py>(
    py: Python<'py>,
    target: &Bound<'py, PyAny>,
    recipe: &str,
) -> PyResult<Bound<'py, PyList>> {
    let recipe = recipe_of(recipe)?;
    let mut guard = Guard::of(target)?;
    let t = guard.target();
    let outcomes = py.allow_threads(move || -> Res<Vec<recipe::StepOutcome>> {
        Ok(match t {
            Target::Hierarchy(h) => recipe::apply(h, &recipe, &mut Silent)?,
            Target::Mesh(m) => recipe::apply_to_mesh(m, &recipe, &mut Silent)?,
        })
    })?;
    let list = PyList::empty(py);
    for o in outcomes {
        let d = PyDict::new(py);
        d.set_item("step", o.step)?;
        d.set_item("method", o.method)?;
        d.set_item("level", o.level)?;
        d.set_item("moved", o.moved)?;
        d.set_item("detail", o.detail)?;
        d.set_item("seconds", o.seconds)?;
        list.append(d)?;
    }
    Ok(list)
}

fn method_of(method: &str) -> PyResult<Method> {
    match method {
        "rounds" => Ok(Method::Rounds),
        "qem" => Ok(Method::Qem),
        other => Err(mesh_err(format!(
            "method: {other:?} is not 'rounds' or 'qem'"
        ))),
    }
}

fn workflow_options(level: usize, method: &str) -> PyResult<WorkflowOptions> {
    Ok(WorkflowOptions::default()
        .with_level(level)
        .with_method(method_of(method)?))
}

/// The ``multires workflow`` job on one file: reads and welds it, builds the
/// hierarchy, makes one edit of each family at ``level`` (a Lee drag, a Bendels & Klein
/// rotation, a sub-mesh taper) and refines back. Returns ``(mesh, steps)``: the edited
/// full-resolution :class:`Mesh` and one dict per step (``step``, ``detail``,
/// ``seconds``, ``peak_bytes``: the process's peak resident memory during the step, or
/// ``None`` where the platform does not report it). Releases the GIL.
#[pyfunction]
#[pyo3(signature = (path, *, level = 3, method = "rounds", weld = None))]
pub fn workflow<'py>(
    py: Python<'py>,
    path: PathBuf,
    level: usize,
    method: &str,
    weld: Option<&Bound<'py, PyAny>>,
) -> PyResult<(PyMesh, Bound<'py, PyList>)> {
    let weld = match weld {
        Some(w) => parse_weld(w)?,
        None => Weld::Auto,
    };
    let options = workflow_options(level, method)?;
    let done = py.allow_threads(|| -> Res<wf::Workflow> {
        let loaded = load::load(&path, weld, &mut Silent)?;
        Ok(wf::run(loaded, &path, &options, &mut Silent)?)
    })?;
    let list = PyList::empty(py);
    for r in &done.rows {
        let d = PyDict::new(py);
        d.set_item("step", r.step)?;
        d.set_item("detail", &r.detail)?;
        d.set_item("seconds", r.seconds)?;
        d.set_item("peak_bytes", r.peak_bytes)?;
        list.append(d)?;
    }
    Ok((PyMesh::new(done.result), list))
}

/// The meshes named by folders, globs, manifests and files, sorted and deduplicated, as
/// ``multires batch`` collects them; with ``shard="I/N"`` only that shard's (the
/// command's deterministic split by path hash).
#[pyfunction]
#[pyo3(signature = (inputs, shard = None))]
pub fn _collect_inputs(
    inputs: Vec<String>,
    shard: Option<&str>,
) -> PyResult<Vec<(String, String)>> {
    let mut found = batch::collect_inputs(&inputs).map_err(Fail::from)?;
    if let Some(s) = shard {
        let (i, n) = batch::parse_shard(s).map_err(Fail::from)?;
        found = batch::shard(found, i, n);
    }
    Ok(found
        .into_iter()
        .map(|i| {
            (
                i.path.display().to_string(),
                i.relative.display().to_string(),
            )
        })
        .collect())
}

/// ``"I/N"`` parsed as ``(I, N)`` (1 <= I <= N); :class:`MeshError` otherwise.
#[pyfunction]
pub fn _parse_shard(shard: &str) -> PyResult<(usize, usize)> {
    Ok(batch::parse_shard(shard).map_err(Fail::from)?)
}

fn batch_options(
    out: &str,
    recipe: Option<&str>,
    format: &str,
    weld: Option<&Bound<'_, PyAny>>,
    level: usize,
    method: &str,
    shard: Option<(usize, usize)>,
) -> PyResult<BatchOptions> {
    let mut options = BatchOptions::new(out).with_format(format);
    if let Some(r) = recipe {
        options = options.with_recipe(recipe_of(r)?);
    }
    options.workflow = workflow_options(level, method)?;
    options.weld = match weld {
        Some(w) => parse_weld(w)?,
        None => Weld::Auto,
    };
    options.shard = shard;
    if !["ply", "obj", "off", "stl"].contains(&format) {
        return Err(mesh_err(format!(
            "format: {format:?} is not ply, obj, off or stl"
        )));
    }
    Ok(options)
}

/// ``multires::batch::process`` on one mesh: reads it, runs the recipe (or the
/// workflow), writes the output and its sidecar, or skips it when up to date. Returns
/// the report row as JSON text (exactly the line ``multires batch`` writes). Never
/// raises for the mesh's own failure (its row says ``error``). Releases the GIL.
#[pyfunction]
#[pyo3(signature = (path, relative, out, recipe = None, format = "ply", weld = None, level = 3, method = "rounds", shard = None))]
#[allow(clippy::too_many_arguments)]
pub fn _process(
    py: Python<'_>,
    path: PathBuf,
    relative: PathBuf,
    out: &str,
    recipe: Option<&str>,
    format: &str,
    weld: Option<&Bound<'_, PyAny>>,
    level: usize,
    method: &str,
    shard: Option<(usize, usize)>,
) -> PyResult<String> {
    let options = batch_options(out, recipe, format, weld, level, method, shard)?;
    let input = Input { path, relative };
    let row = py.allow_threads(|| batch::process(&input, &options));
    serde_json::to_string(&row).map_err(|e| mesh_err(e.to_string()))
}

/// The job hash the sidecars record for these options.
#[pyfunction]
#[pyo3(signature = (out, recipe = None, format = "ply", weld = None, level = 3, method = "rounds"))]
pub fn _job_hash(
    out: &str,
    recipe: Option<&str>,
    format: &str,
    weld: Option<&Bound<'_, PyAny>>,
    level: usize,
    method: &str,
) -> PyResult<String> {
    Ok(batch_options(out, recipe, format, weld, level, method, None)?.job_hash())
}

/// Where a batch writes the output of the mesh at ``relative``.
#[pyfunction]
#[pyo3(signature = (relative, out, format = "ply"))]
pub fn _output_path(relative: PathBuf, out: &str, format: &str) -> String {
    let options = BatchOptions::new(out).with_format(format);
    let input = Input {
        path: relative.clone(),
        relative,
    };
    batch::output_path(&input, &options).display().to_string()
}

/// The BLAKE3 hex digest of a file's bytes (the batch's input hash). Releases the GIL.
#[pyfunction]
pub fn _blake3_file(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    let bytes = py.allow_threads(|| std::fs::read(&path)).map_err(|e| {
        let not_found = e.kind() == std::io::ErrorKind::NotFound;
        Fail::Io {
            message: format!("{}: {e}", path.display()),
            not_found,
        }
    })?;
    Ok(py.allow_threads(|| blake3::hash(&bytes).to_hex().to_string()))
}

/// The BLAKE3 hex digest of a text.
#[pyfunction]
pub fn _blake3_text(text: &str) -> String {
    blake3::hash(text.as_bytes()).to_hex().to_string()
}
