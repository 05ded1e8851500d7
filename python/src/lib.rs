//! Python bindings of multires (PyO3): meshes and hierarchies with NumPy arrays in and
//! out, every editing method, recipes, the workflow and the per-mesh step of corpus
//! batches. Built by maturin as the extension `multires._multires`; the pure-Python
//! package `multires` re-exports it with its helpers (batches on Dask).
//!
//! Every array is checked before the library sees it, every library error becomes a
//! Python exception with the library's message (`MeshError`, a `ValueError`, and its
//! subclasses), and every long call releases the GIL.

mod arrays;
mod edits;
mod errors;
mod hierarchy;
mod jobs;
mod mesh;

use pyo3::prelude::*;

/// The compiled half of the `multires` package (see its docs).
#[pymodule]
fn _multires(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("MeshError", py.get_type::<errors::MeshError>())?;
    m.add("EditError", py.get_type::<errors::EditError>())?;
    m.add("RecipeError", py.get_type::<errors::RecipeError>())?;
    m.add_class::<mesh::PyMesh>()?;
    m.add_class::<hierarchy::PyHierarchy>()?;
    m.add_function(wrap_pyfunction!(mesh::read, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::icosphere, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::grid, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::torus, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::surface_distance, m)?)?;
    m.add_function(wrap_pyfunction!(edits::lee_drag, m)?)?;
    m.add_function(wrap_pyfunction!(edits::disk, m)?)?;
    m.add_function(wrap_pyfunction!(edits::blend, m)?)?;
    m.add_function(wrap_pyfunction!(edits::submesh_pull, m)?)?;
    m.add_function(wrap_pyfunction!(edits::submesh_scale, m)?)?;
    m.add_function(wrap_pyfunction!(edits::submesh_rotate, m)?)?;
    m.add_function(wrap_pyfunction!(edits::submesh_taper, m)?)?;
    m.add_function(wrap_pyfunction!(edits::submesh_twist, m)?)?;
    m.add_function(wrap_pyfunction!(edits::barr_taper, m)?)?;
    m.add_function(wrap_pyfunction!(edits::barr_twist, m)?)?;
    m.add_function(wrap_pyfunction!(edits::barr_bend, m)?)?;
    m.add_function(wrap_pyfunction!(edits::taubin, m)?)?;
    m.add_function(wrap_pyfunction!(edits::ffd, m)?)?;
    m.add_function(wrap_pyfunction!(edits::blend_image, m)?)?;
    m.add_function(wrap_pyfunction!(edits::blend_polyline, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::apply_recipe, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::workflow, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_collect_inputs, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_process, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_parse_shard, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_job_hash, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_output_path, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_blake3_file, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::_blake3_text, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
