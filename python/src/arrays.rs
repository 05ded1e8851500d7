//! NumPy arrays in and out: every array the user gives is checked here (dtype, shape,
//! finiteness, index range) so that the library only ever sees valid input, and every
//! refusal is a `MeshError` naming the argument.

use glam::{DMat3, DMat4, DVec3};
use halfedge::{Mesh, VertexId};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors::mesh_err;

/// `numpy.asarray(obj)`.
fn asarray<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    obj.py().import("numpy")?.call_method1("asarray", (obj,))
}

/// The dtype kind letter and the shape of a NumPy array.
fn kind_and_shape(arr: &Bound<'_, PyAny>) -> PyResult<(String, Vec<usize>, String)> {
    let dtype = arr.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let name: String = dtype.getattr("name")?.extract()?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    Ok((kind, shape, name))
}

/// A contiguous copy as `dtype`.
fn contiguous<'py>(arr: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    arr.py()
        .import("numpy")?
        .call_method1("ascontiguousarray", (arr, dtype))
}

/// An `(n, 3)` array of real numbers (any float dtype), all finite, as points.
pub fn points(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f64; 3]>> {
    let arr = asarray(obj)?;
    let (kind, shape, name) = kind_and_shape(&arr)?;
    if kind != "f" {
        return Err(mesh_err(format!(
            "{what}: expected a float array of shape (n, 3), got dtype {name}"
        )));
    }
    if shape.len() != 2 || shape[1] != 3 {
        return Err(mesh_err(format!(
            "{what}: expected shape (n, 3), got {shape:?}"
        )));
    }
    let arr = contiguous(&arr, "float64")?;
    let arr = arr.downcast::<PyArray2<f64>>()?.readonly();
    let flat = arr.as_slice()?;
    let mut out = Vec::with_capacity(shape[0]);
    for (i, c) in flat.chunks_exact(3).enumerate() {
        if let Some(bad) = c.iter().find(|x| !x.is_finite()) {
            return Err(mesh_err(format!(
                "{what}: row {i} has the non-finite coordinate {bad}"
            )));
        }
        out.push([c[0], c[1], c[2]]);
    }
    Ok(out)
}

/// An array of non-negative integers (any integer dtype) of `shape` (`None`: any length),
/// each below `bound`, flattened.
pub fn integers(
    obj: &Bound<'_, PyAny>,
    what: &str,
    columns: Option<usize>,
    bound: usize,
) -> PyResult<(Vec<u32>, usize)> {
    let arr = asarray(obj)?;
    let (kind, shape, name) = kind_and_shape(&arr)?;
    // An empty list is float64 to NumPy: take it as no indices.
    let empty = shape.iter().product::<usize>() == 0;
    let arr = if empty && kind != "i" && kind != "u" {
        arr.call_method1("astype", ("int64",))?
    } else {
        arr
    };
    let kind = if empty { "i".to_owned() } else { kind };
    if kind != "i" && kind != "u" {
        return Err(mesh_err(format!(
            "{what}: expected an integer array, got dtype {name}"
        )));
    }
    let rows = match (columns, shape.as_slice()) {
        (Some(c), [n, k]) if *k == c => *n,
        (None, [n]) => *n,
        (Some(c), _) => {
            return Err(mesh_err(format!(
                "{what}: expected shape (m, {c}), got {shape:?}"
            )))
        }
        (None, _) => {
            return Err(mesh_err(format!(
                "{what}: expected a 1-D array, got shape {shape:?}"
            )))
        }
    };
    let arr = contiguous(&arr, "int64")?;
    let arr = arr.downcast::<PyArray1<i64>>().map(|a| a.readonly());
    let values: Vec<i64> = match arr {
        Ok(a) => a.as_slice()?.to_vec(),
        Err(_) => {
            let a = contiguous(&asarray(obj)?, "int64")?;
            let a = a.downcast::<PyArray2<i64>>()?.readonly();
            a.as_slice()?.to_vec()
        }
    };
    let width = columns.unwrap_or(1);
    let mut out = Vec::with_capacity(values.len());
    for (k, &v) in values.iter().enumerate() {
        if v < 0 || v as u64 >= bound as u64 {
            let place = if columns.is_some() {
                format!("row {} has the index {v}", k / width)
            } else {
                format!("the index {v} (position {k})")
            };
            return Err(mesh_err(format!(
                "{what}: {place}, out of range for {bound} vertices"
            )));
        }
        out.push(v as u32);
    }
    Ok((out, rows))
}

/// The live vertices in the order the writers number them (row `k` of `Mesh.vertices`).
pub fn live(mesh: &Mesh) -> Vec<VertexId> {
    mesh.vertices().collect()
}

/// Indices into `n` items: an index array (any integer dtype) or a boolean mask of
/// length `n`; sorted as given (a mask gives increasing indices).
pub fn index_set(obj: &Bound<'_, PyAny>, what: &str, n: usize) -> PyResult<Vec<u32>> {
    let arr = asarray(obj)?;
    let (kind, shape, _) = kind_and_shape(&arr)?;
    if kind == "b" {
        if shape != [n] {
            return Err(mesh_err(format!(
                "{what}: a boolean mask needs shape ({n},), got {shape:?}"
            )));
        }
        let mask = contiguous(&arr, "bool")?;
        let mask = mask.downcast::<PyArray1<bool>>()?.readonly();
        return Ok(mask
            .as_slice()?
            .iter()
            .enumerate()
            .filter_map(|(i, &m)| m.then_some(i as u32))
            .collect());
    }
    let arr = if shape.is_empty() {
        arr.call_method1("reshape", (1,))?
    } else {
        arr
    };
    Ok(integers(&arr, what, None, n)?.0)
}

/// A vertex region: an index array (any integer dtype, indices into the rows of the
/// mesh's vertex array) or a boolean mask with one entry per vertex.
pub fn region(obj: &Bound<'_, PyAny>, what: &str, live: &[VertexId]) -> PyResult<Vec<VertexId>> {
    Ok(index_set(obj, what, live.len())?
        .into_iter()
        .map(|i| live[i as usize])
        .collect())
}

/// A point or direction of three finite numbers.
pub fn vec3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v: Vec<f64> = asarray(obj)?
        .call_method1("astype", ("float64",))
        .map_err(|_| mesh_err(format!("{what}: expected three numbers")))?
        .call_method0("ravel")?
        .call_method0("tolist")?
        .extract()
        .map_err(|_| mesh_err(format!("{what}: expected three numbers")))?;
    if v.len() != 3 {
        return Err(mesh_err(format!(
            "{what}: expected three numbers, got {}",
            v.len()
        )));
    }
    let p = DVec3::new(v[0], v[1], v[2]);
    if !p.is_finite() {
        return Err(mesh_err(format!("{what}: {p} is not finite")));
    }
    Ok(p)
}

/// A matrix of real numbers of `rows` × `cols`, row by row, all finite.
fn matrix(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let arr = asarray(obj)?;
    let (kind, shape, name) = kind_and_shape(&arr)?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(mesh_err(format!(
            "{what}: expected a matrix of numbers, got dtype {name}"
        )));
    }
    if shape.len() != 2 {
        return Err(mesh_err(format!(
            "{what}: expected a matrix, got shape {shape:?}"
        )));
    }
    let values: Vec<f64> = arr
        .call_method1("astype", ("float64",))?
        .call_method0("ravel")?
        .call_method0("tolist")?
        .extract()?;
    if let Some(bad) = values.iter().find(|x| !x.is_finite()) {
        return Err(mesh_err(format!("{what}: the entry {bad} is not finite")));
    }
    Ok((values, shape[0], shape[1]))
}

/// An affine map of space: a 4×4 matrix (last row `0 0 0 1`) or a 3×4 one, acting on
/// column vectors (`p' = M @ [x, y, z, 1]`).
pub fn affine3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DMat4> {
    let (v, r, c) = matrix(obj, what)?;
    if c != 4 || !(r == 3 || r == 4) {
        return Err(mesh_err(format!(
            "{what}: expected a 4x4 or 3x4 matrix, got {r}x{c}"
        )));
    }
    let mut rows = [[0.0; 4]; 4];
    for i in 0..r {
        rows[i].copy_from_slice(&v[i * 4..i * 4 + 4]);
    }
    if r == 3 {
        rows[3] = [0.0, 0.0, 0.0, 1.0];
    } else if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(mesh_err(format!(
            "{what}: the last row of a 4x4 affine matrix must be [0, 0, 0, 1], got {:?}",
            rows[3]
        )));
    }
    Ok(DMat4::from_cols_array_2d(&rows).transpose())
}

/// An affine map of the plane: a 3×3 matrix (last row `0 0 1`) or a 2×3 one.
pub fn affine2(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DMat3> {
    let (v, r, c) = matrix(obj, what)?;
    if c != 3 || !(r == 2 || r == 3) {
        return Err(mesh_err(format!(
            "{what}: expected a 3x3 or 2x3 matrix, got {r}x{c}"
        )));
    }
    let mut rows = [[0.0; 3]; 3];
    for i in 0..r {
        rows[i].copy_from_slice(&v[i * 3..i * 3 + 3]);
    }
    if r == 2 {
        rows[2] = [0.0, 0.0, 1.0];
    } else if rows[2] != [0.0, 0.0, 1.0] {
        return Err(mesh_err(format!(
            "{what}: the last row of a 3x3 affine matrix must be [0, 0, 1], got {:?}",
            rows[2]
        )));
    }
    Ok(DMat3::from_cols_array_2d(&rows).transpose())
}

/// An `(n, 3)` float64 array.
pub fn to_points<'py>(py: Python<'py>, points: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    Array2::from_shape_vec((points.len(), 3), flat)
        .expect("n x 3 values")
        .into_pyarray(py)
}

/// An `(n, k)` array of `T`.
pub fn to_rows<'py, T: numpy::Element + Copy, const K: usize>(
    py: Python<'py>,
    rows: &[[T; K]],
) -> Bound<'py, PyArray2<T>> {
    let flat: Vec<T> = rows.iter().flatten().copied().collect();
    Array2::from_shape_vec((rows.len(), K), flat)
        .expect("n x k values")
        .into_pyarray(py)
}
