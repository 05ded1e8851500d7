//! Harmonic embedding of an editing area onto a rectangle (Lee 1999, §4, after Eck et al.
//! 1995), with mean-value weights (Floater 2003) as the fold-free option.
//!
//! The boundary loop goes onto the rectangle's border first (§4.2): four picked corners
//! with the vertices between them placed by chord length along each side, or one corner
//! and the whole loop laid by chord length. The interior vertices then minimise
//! `E(h) = ½ Σ κ_ij |h(v_i) − h(v_j)|²` with Eck's spring constants
//! `κ_ij = (l_ik1² + l_jk1² − l_ij²)/A_ijk1 + (l_ik2² + l_jk2² − l_ij²)/A_ijk2 = 4 (cot α + cot β)`:
//! one sparse symmetric system for u and v together, factored once per area by `faer`'s
//! sparse Cholesky. The cotangent weights are scaled by ¼ (the scale does not change the
//! map). A degenerate corner contributes 0 instead of an infinite cotangent, and every
//! edge gets an extra weight of `1e-10 ×` the mean weight, so that a vertex whose
//! triangles are all degenerate lands at the average of its neighbours instead of making
//! the system singular: no NaN. Negative cotangents (obtuse triangles) can make the
//! system indefinite; the solve then falls back to sparse LU, and the map may fold: the
//! flipped triangles are reported.
//!
//! Mean-value weights `w_ij = (tan(α_ij/2) + tan(β_ij/2)) / |p_j − p_i|` (angles at `v_i`
//! next to the edge) are positive, so with the convex rectangle boundary the map never
//! folds (Tutte / Floater). They are not symmetric: that system is solved by `faer`'s
//! sparse LU with partial pivoting. A row whose weights are not finite (coincident
//! vertices) falls back to uniform weights, which also cannot fold.

use glam::{DVec2, DVec3};
use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};
use rayon::prelude::*;

use super::EditingArea;
use crate::laplace::opposite_cotangent;
use crate::{EditError, Result};

/// The spring constants of the harmonic map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EmbeddingWeights {
    /// Eck et al.'s harmonic spring constants (cotangent weights), as Lee 1999 uses; the
    /// map can fold where triangles are obtuse.
    #[default]
    Cotangent,
    /// Floater's mean-value weights: positive, the map cannot fold (solved by sparse LU).
    MeanValue,
}

/// How the area's boundary loop is laid onto the rectangle (Lee 1999, §4.2).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum BoundaryMapping {
    /// Four picks of the area (see [`EditingArea::picks`]) that are on its boundary
    /// become the corners; otherwise the first pick on the boundary (or the first
    /// boundary vertex) is one corner and the loop is laid by chord length.
    #[default]
    Auto,
    /// These four boundary vertices go to the corners, in the loop's counter-clockwise
    /// order starting with the first at `(0, 0)`; the others by chord length per side.
    Corners([VertexId; 4]),
    /// This boundary vertex goes to `(0, 0)` and the loop is laid counter-clockwise by
    /// chord length around the whole border.
    OneCorner(VertexId),
}

/// Options of [`Embedding::new`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EmbeddingOptions {
    /// Spring constants.
    pub weights: EmbeddingWeights,
    /// Boundary mapping.
    pub boundary: BoundaryMapping,
    /// Width / height of the rectangle. `None`: with four corners, the mean lengths of the
    /// opposite sides of the loop; with one corner, a square. The perimeter always equals
    /// the loop's length.
    pub aspect_ratio: Option<f64>,
}

/// The linear solver that produced the interior of the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmbeddingSolver {
    /// No interior vertex: nothing to solve.
    None,
    /// Sparse Cholesky `LLᵀ` (faer).
    Cholesky,
    /// Sparse LU with partial pivoting (faer): mean-value weights, or cotangent weights
    /// whose matrix was not positive definite.
    Lu,
}

/// The embedding of an editing area onto the rectangle `[0, width] × [0, height]`: a
/// `(u, v)` per local vertex of the area (Lee 1999, §4).
#[derive(Clone, Debug)]
pub struct Embedding {
    uv: Vec<DVec2>,
    size: DVec2,
    flipped: Vec<FaceId>,
    degenerate: Vec<FaceId>,
    solver: EmbeddingSolver,
}

impl Embedding {
    /// Embeds `area` onto a rectangle.
    ///
    /// # Errors
    /// [`EditError::AreaStale`], [`EditError::CornerNotOnBoundary`],
    /// [`EditError::RepeatedCorner`], [`EditError::InvalidParameter`] for a bad aspect
    /// ratio, [`EditError::Solver`] when the sparse solve fails.
    pub fn new(mesh: &Mesh, area: &EditingArea, options: &EmbeddingOptions) -> Result<Self> {
        area.check_mesh(mesh)?;
        if let Some(a) = options.aspect_ratio {
            if !(a.is_finite() && a > 0.0) {
                return Err(EditError::InvalidParameter {
                    name: "aspect_ratio",
                    reason: format!("{a} must be positive and finite"),
                });
            }
        }
        let (boundary_uv, size) = map_boundary(mesh, area, options)?;
        let n_int = area.n_interior();
        let mut uv = vec![DVec2::ZERO; area.vertices().len()];
        uv[n_int..].copy_from_slice(&boundary_uv);
        let solver = if n_int == 0 {
            EmbeddingSolver::None
        } else {
            let rows = match options.weights {
                EmbeddingWeights::Cotangent => cotangent_rows(mesh, area),
                EmbeddingWeights::MeanValue => mean_value_rows(mesh, area),
            };
            let (interior, solver) = solve_interior(&rows, &boundary_uv, n_int, options.weights)?;
            uv[..n_int].copy_from_slice(&interior);
            solver
        };
        let triangles = area.local_triangles(mesh);
        let signed: Vec<f64> = triangles
            .par_iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| uv[i as usize]);
                (b - a).perp_dot(c - a)
            })
            .collect();
        let faces = area.faces();
        let flipped = faces
            .iter()
            .zip(&signed)
            .filter(|(_, &s)| s < 0.0)
            .map(|(&f, _)| f)
            .collect();
        let degenerate = faces
            .iter()
            .zip(&signed)
            .filter(|(_, &s)| s == 0.0)
            .map(|(&f, _)| f)
            .collect();
        Ok(Self {
            uv,
            size,
            flipped,
            degenerate,
            solver,
        })
    }

    /// `(u, v)` of every local vertex of the area (see [`EditingArea`] for the order).
    #[must_use]
    pub fn uv(&self) -> &[DVec2] {
        &self.uv
    }

    /// `(width, height)` of the rectangle; its lower corner is the origin.
    #[must_use]
    pub fn size(&self) -> DVec2 {
        self.size
    }

    /// Faces whose image is oriented clockwise: the map folds there (Eck et al.; Lee 1999
    /// §4.1 notes it is rare). Never happens with mean-value weights.
    #[must_use]
    pub fn flipped_faces(&self) -> &[FaceId] {
        &self.flipped
    }

    /// Faces whose image has zero area (for example three boundary vertices on one side
    /// of the rectangle).
    #[must_use]
    pub fn degenerate_faces(&self) -> &[FaceId] {
        &self.degenerate
    }

    /// The solver used for the interior.
    #[must_use]
    pub fn solver(&self) -> EmbeddingSolver {
        self.solver
    }
}

/// Row `i` of the system for interior vertex `i`: `(neighbour local index, weight)`.
type Row = Vec<(u32, f64)>;

fn neighbour_rows(
    mesh: &Mesh,
    area: &EditingArea,
    weight: impl Fn(HalfedgeId) -> f64 + Sync,
) -> Vec<Row> {
    let local = area.local_of_slot();
    area.interior()
        .par_iter()
        .map(|&v| {
            mesh.outgoing_halfedges(v)
                .map(|h| (local[mesh.vertex_index(mesh.to_vertex(h))], weight(h)))
                .collect()
        })
        .collect()
}

fn cotangent_rows(mesh: &Mesh, area: &EditingArea) -> Vec<Row> {
    let mut rows = neighbour_rows(mesh, area, |h| {
        // ¼ κ_ij = ¼ · 4 (cot α + cot β); both faces are in the area (interior vertex).
        let w = opposite_cotangent(mesh, h) + opposite_cotangent(mesh, mesh.opposite(h));
        if w.is_finite() {
            w
        } else {
            0.0
        }
    });
    let (sum, count) = rows
        .iter()
        .flatten()
        .fold((0.0, 0usize), |(s, c), &(_, w)| (s + w.abs(), c + 1));
    let epsilon = 1e-10 * if sum > 0.0 { sum / count as f64 } else { 1.0 };
    rows.par_iter_mut()
        .flatten()
        .for_each(|(_, w)| *w += epsilon);
    rows
}

/// `tan(θ/2)` of the angle between `a` and `b`, 0 when one is zero.
fn half_angle_tan(a: DVec3, b: DVec3) -> f64 {
    let denominator = a.length() * b.length() + a.dot(b);
    let numerator = a.cross(b).length();
    if numerator == 0.0 {
        return 0.0;
    }
    if denominator <= 0.0 {
        return f64::INFINITY;
    }
    numerator / denominator
}

fn mean_value_rows(mesh: &Mesh, area: &EditingArea) -> Vec<Row> {
    let mut rows = neighbour_rows(mesh, area, |h| {
        let p = mesh.position(mesh.from_vertex(h));
        let e = mesh.position(mesh.to_vertex(h)) - p;
        // angle at p in face(h) (next corner) and in face(opposite(h)) (previous corner)
        let k1 = mesh.position(mesh.to_vertex(mesh.next(h))) - p;
        let k2 = mesh.position(mesh.from_vertex(mesh.prev(mesh.opposite(h)))) - p;
        (half_angle_tan(e, k1) + half_angle_tan(e, k2)) / e.length()
    });
    rows.par_iter_mut().for_each(|row| {
        let total: f64 = row.iter().map(|&(_, w)| w).sum();
        if !(total.is_finite() && total > 0.0) || row.iter().any(|&(_, w)| !w.is_finite()) {
            for (_, w) in row.iter_mut() {
                *w = 1.0;
            }
        }
    });
    rows
}

/// Solves `Σ_j w_ij (x_i − x_j) = 0` for the interior, boundary values given.
fn solve_interior(
    rows: &[Row],
    boundary_uv: &[DVec2],
    n_int: usize,
    weights: EmbeddingWeights,
) -> Result<(Vec<DVec2>, EmbeddingSolver)> {
    use faer::linalg::solvers::Solve;
    use faer::sparse::{SparseColMat, SymbolicSparseColMat};
    use faer::{Mat, Side};

    // Matrix rows → CSC by a counting sort over columns (row indices come out sorted).
    let mut col_count = vec![0usize; n_int + 1];
    let mut rhs = Mat::<f64>::zeros(n_int, 2);
    let mut diagonal = vec![0.0; n_int];
    for (i, row) in rows.iter().enumerate() {
        for &(j, w) in row {
            diagonal[i] += w;
            let j = j as usize;
            if j < n_int {
                col_count[j + 1] += 1;
            } else {
                let b = boundary_uv[j - n_int];
                rhs[(i, 0)] += w * b.x;
                rhs[(i, 1)] += w * b.y;
            }
        }
        col_count[i + 1] += 1; // diagonal
    }
    for j in 0..n_int {
        col_count[j + 1] += col_count[j];
    }
    let col_ptr = col_count.clone();
    let nnz = col_ptr[n_int];
    let mut next = col_count;
    let mut row_idx = vec![0usize; nnz];
    let mut values = vec![0.0; nnz];
    for (i, row) in rows.iter().enumerate() {
        let entries = row
            .iter()
            .filter(|&&(j, _)| (j as usize) < n_int)
            .map(|&(j, w)| (j as usize, -w))
            .chain(std::iter::once((i, diagonal[i])));
        for (col, val) in entries {
            let k = next[col];
            row_idx[k] = i;
            values[k] = val;
            next[col] += 1;
        }
    }
    let symbolic = SymbolicSparseColMat::new_checked(n_int, n_int, col_ptr, None, row_idx);
    let matrix = SparseColMat::<usize, f64>::new(symbolic, values);

    let cholesky = if weights == EmbeddingWeights::Cotangent {
        matrix.sp_cholesky(Side::Lower).ok()
    } else {
        None
    };
    let (solution, solver) = match cholesky {
        Some(llt) => (llt.solve(&rhs), EmbeddingSolver::Cholesky),
        None => {
            let lu = matrix
                .sp_lu()
                .map_err(|e| EditError::Solver(format!("sparse LU of the embedding: {e:?}")))?;
            (lu.solve(&rhs), EmbeddingSolver::Lu)
        }
    };
    let mut uv = Vec::with_capacity(n_int);
    for i in 0..n_int {
        let p = DVec2::new(solution[(i, 0)], solution[(i, 1)]);
        if !p.is_finite() {
            return Err(EditError::Solver(format!(
                "the embedding of interior vertex {i} is not finite (singular system)"
            )));
        }
        uv.push(p);
    }
    Ok((uv, solver))
}

/// `(u, v)` of the boundary loop (in loop order) and the rectangle size.
fn map_boundary(
    mesh: &Mesh,
    area: &EditingArea,
    options: &EmbeddingOptions,
) -> Result<(Vec<DVec2>, DVec2)> {
    let boundary = area.boundary();
    let n = boundary.len();
    let position_in_loop = |v: VertexId| -> Result<usize> {
        if !mesh.is_valid_vertex(v) {
            return Err(EditError::InvalidVertex(v));
        }
        boundary
            .iter()
            .position(|&b| b == v)
            .ok_or(EditError::CornerNotOnBoundary { vertex: v })
    };
    let corners: Vec<usize> = match &options.boundary {
        BoundaryMapping::Corners(c) => {
            let mut positions = Vec::with_capacity(4);
            for &v in c {
                let p = position_in_loop(v)?;
                if positions.contains(&p) {
                    return Err(EditError::RepeatedCorner { vertex: v });
                }
                positions.push(p);
            }
            positions
        }
        BoundaryMapping::OneCorner(v) => vec![position_in_loop(*v)?],
        BoundaryMapping::Auto => {
            let on_loop: Vec<usize> = area
                .picks()
                .iter()
                .filter_map(|&v| boundary.iter().position(|&b| b == v))
                .collect();
            let mut distinct = on_loop.clone();
            distinct.sort_unstable();
            distinct.dedup();
            if on_loop.len() == 4 && distinct.len() == 4 && area.picks().len() == 4 {
                on_loop
            } else {
                vec![on_loop.first().copied().unwrap_or(0)]
            }
        }
    };
    // Rotate the loop so that the first corner comes first.
    let start = corners[0];
    let order: Vec<usize> = (0..n).map(|k| (start + k) % n).collect();
    let p = |k: usize| mesh.position(boundary[order[k % n]]);
    // cumulative chord length along the rotated loop, closing back to the start
    let mut cumulative = vec![0.0; n + 1];
    for k in 0..n {
        cumulative[k + 1] = cumulative[k] + (p(k + 1) - p(k)).length();
    }
    let perimeter = cumulative[n];
    let mut uv = vec![DVec2::ZERO; n];
    let size;
    if corners.len() == 4 {
        let mut rel: Vec<usize> = corners.iter().map(|&c| (c + n - start) % n).collect();
        rel.sort_unstable();
        rel.push(n);
        let side_length = |s: usize| cumulative[rel[s + 1]] - cumulative[rel[s]];
        size = match options.aspect_ratio {
            Some(a) => rectangle_with_aspect(perimeter, a),
            None => DVec2::new(
                0.5 * (side_length(0) + side_length(2)),
                0.5 * (side_length(1) + side_length(3)),
            ),
        };
        let corner_uv = [
            DVec2::ZERO,
            DVec2::new(size.x, 0.0),
            size,
            DVec2::new(0.0, size.y),
        ];
        for s in 0..4 {
            let (a, b) = (corner_uv[s], corner_uv[(s + 1) % 4]);
            let (k0, k1) = (rel[s], rel[s + 1]);
            let length = side_length(s);
            for k in k0..k1 {
                let f = if length > 0.0 {
                    (cumulative[k] - cumulative[k0]) / length
                } else {
                    (k - k0) as f64 / (k1 - k0) as f64
                };
                uv[order[k]] = a.lerp(b, f);
            }
        }
    } else {
        size = rectangle_with_aspect(perimeter, options.aspect_ratio.unwrap_or(1.0));
        let border = 2.0 * (size.x + size.y);
        for k in 0..n {
            let f = if perimeter > 0.0 {
                cumulative[k] / perimeter
            } else {
                k as f64 / n as f64
            };
            uv[order[k]] = point_on_border(f * border, size);
        }
    }
    // A degenerate loop (zero length) still needs a non-empty rectangle for the MBA.
    let size = if size.x > 0.0 && size.y > 0.0 {
        size
    } else {
        DVec2::ONE
    };
    Ok((uv, size))
}

/// The rectangle of perimeter `perimeter` (or 4 when that is zero) and `width/height = a`.
fn rectangle_with_aspect(perimeter: f64, a: f64) -> DVec2 {
    let half = if perimeter > 0.0 {
        0.5 * perimeter
    } else {
        2.0
    };
    let h = half / (1.0 + a);
    DVec2::new(a * h, h)
}

/// The point at arc length `q` along the rectangle's border, counter-clockwise from the origin.
fn point_on_border(q: f64, size: DVec2) -> DVec2 {
    let (w, h) = (size.x, size.y);
    if q <= w {
        DVec2::new(q, 0.0)
    } else if q <= w + h {
        DVec2::new(w, q - w)
    } else if q <= 2.0 * w + h {
        DVec2::new(w - (q - w - h), h)
    } else {
        DVec2::new(0.0, (h - (q - 2.0 * w - h)).max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::area::EditingArea;
    use halfedge::generators;

    fn grid_patch(mesh: &Mesh) -> EditingArea {
        let faces: Vec<FaceId> = mesh
            .faces()
            .filter(|&f| {
                let c = mesh.face_centroid(f);
                (1.0..7.0).contains(&c.x) && (1.0..5.0).contains(&c.y)
            })
            .collect();
        EditingArea::from_faces(mesh, &faces).unwrap()
    }

    #[test]
    fn planar_grid_with_its_own_rectangle_maps_to_itself() {
        let mesh = generators::grid(8, 6, 8.0, 6.0);
        let area = grid_patch(&mesh);
        let at = |x: f64, y: f64| {
            mesh.vertices()
                .find(|&v| mesh.position(v).truncate() == DVec2::new(x, y))
                .unwrap()
        };
        let corners = [at(1.0, 1.0), at(7.0, 1.0), at(7.0, 5.0), at(1.0, 5.0)];
        for weights in [EmbeddingWeights::Cotangent, EmbeddingWeights::MeanValue] {
            let options = EmbeddingOptions {
                weights,
                boundary: BoundaryMapping::Corners(corners),
                aspect_ratio: None,
            };
            let embedding = Embedding::new(&mesh, &area, &options).unwrap();
            assert_eq!(embedding.size(), DVec2::new(6.0, 4.0));
            for (i, &v) in area.vertices().iter().enumerate() {
                let expected = mesh.position(v).truncate() - DVec2::ONE;
                assert!(
                    (embedding.uv()[i] - expected).length() < 1e-9,
                    "{weights:?}: {v} at {} instead of {expected}",
                    embedding.uv()[i]
                );
            }
            assert!(embedding.flipped_faces().is_empty());
        }
    }

    #[test]
    fn one_corner_lays_the_loop_by_chord_length_on_a_square() {
        let mesh = generators::grid(8, 6, 8.0, 6.0);
        let area = grid_patch(&mesh);
        let embedding = Embedding::new(&mesh, &area, &EmbeddingOptions::default()).unwrap();
        assert!((embedding.size() - DVec2::splat(5.0)).length() < 1e-12);
        for &uv in &embedding.uv()[area.n_interior()..] {
            let on_border = uv.x.abs() < 1e-12
                || uv.y.abs() < 1e-12
                || (uv.x - 5.0).abs() < 1e-12
                || (uv.y - 5.0).abs() < 1e-12;
            assert!(on_border, "{uv}");
        }
        for &uv in embedding.uv() {
            assert!(
                uv.cmpge(DVec2::splat(-1e-12)).all() && uv.cmple(DVec2::splat(5.0 + 1e-12)).all()
            );
        }
        assert!(embedding.flipped_faces().is_empty());
    }

    #[test]
    fn degenerate_triangles_give_no_nan() {
        let mut mesh = generators::grid(6, 6, 6.0, 6.0);
        // collapse the triangles around an interior vertex onto one point
        let v = mesh
            .vertices()
            .find(|&v| mesh.position(v).truncate() == DVec2::new(3.0, 3.0))
            .unwrap();
        let neighbours: Vec<VertexId> = mesh.adjacent_vertices(v).collect();
        for w in neighbours {
            mesh.set_position(w, DVec3::new(3.0, 3.0, 0.0));
        }
        let faces: Vec<FaceId> = mesh
            .faces()
            .filter(|&f| {
                let c = mesh.face_centroid(f);
                (1.0..5.0).contains(&c.x) && (1.0..5.0).contains(&c.y)
            })
            .collect();
        let area = EditingArea::from_faces(&mesh, &faces).unwrap();
        for weights in [EmbeddingWeights::Cotangent, EmbeddingWeights::MeanValue] {
            let options = EmbeddingOptions {
                weights,
                ..Default::default()
            };
            let embedding = Embedding::new(&mesh, &area, &options).unwrap();
            assert!(embedding.uv().iter().all(|p| p.is_finite()), "{weights:?}");
        }
    }
}
