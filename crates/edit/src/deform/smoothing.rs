//! Taubin λ|μ smoothing (Taubin 1995).

use glam::DVec3;
use halfedge::{Mesh, VertexData};
use rayon::prelude::*;

use crate::deform::checks::{check_finite_positions, finite};
use crate::deform::error::{DeformError, Result};
use crate::deform::submesh::frontier::SubMesh;
use crate::laplace::cotan_weight;
use crate::vertices::Vertices;

/// The edge weights of the Laplacian.
///
/// Paper: Taubin 1995, *A signal processing approach to fair surface design*; Pinkall &
/// Polthier 1993.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SmoothingWeights {
    /// Every neighbour counts the same (Taubin's choice, the umbrella operator).
    #[default]
    Uniform,
    /// Cotangent weights (Pinkall & Polthier), normalised per vertex.
    Cotangent,
}

/// Parameters of Taubin smoothing.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct TaubinOptions {
    /// The shrinking factor λ > 0 (default 0.33).
    pub lambda: f64,
    /// The inflating factor μ < −λ (default −0.34).
    pub mu: f64,
    /// Uniform or cotangent weights.
    pub weights: SmoothingWeights,
    /// Keep the mesh-boundary vertices fixed (default true: smoothing them with
    /// one-sided neighbourhoods pulls holes open).
    pub fix_boundary: bool,
}

impl TaubinOptions {
    /// The same options with the shrinking factor λ set to `lambda`.
    #[must_use]
    pub fn with_lambda(mut self, lambda: f64) -> Self {
        self.lambda = lambda;
        self
    }

    /// The same options with the inflating factor μ set to `mu`.
    #[must_use]
    pub fn with_mu(mut self, mu: f64) -> Self {
        self.mu = mu;
        self
    }

    /// The same options with the edge weights set to `weights`.
    #[must_use]
    pub fn with_weights(mut self, weights: SmoothingWeights) -> Self {
        self.weights = weights;
        self
    }

    /// The same options with whether the mesh-boundary vertices stay fixed set to `fix_boundary`.
    #[must_use]
    pub fn with_fix_boundary(mut self, fix_boundary: bool) -> Self {
        self.fix_boundary = fix_boundary;
        self
    }
}

impl Default for TaubinOptions {
    fn default() -> Self {
        Self {
            lambda: 0.33,
            mu: -0.34,
            weights: SmoothingWeights::Uniform,
            fix_boundary: true,
        }
    }
}

/// Taubin's λ|μ smoothing (G. Taubin, *A signal processing approach to fair surface
/// design*, SIGGRAPH 1995), used by *Interactive editing of multiresolution meshes* §4.2
/// to smooth a sub-mesh and its frontier collar, or the whole mesh.
///
/// One iteration is two Laplacian steps, `p ← p + λ Δp` then `p ← p + μ Δp` with
/// `μ < −λ < 0`, where `Δp_i = Σ_j w_ij (p_j − p_i)` with normalised weights (`Σ_j w_ij =
/// 1`). The first step shrinks like plain Laplacian smoothing, the second inflates: the
/// pair is a low-pass filter with transfer `(1 − λk)(1 − μk)` that passes the low
/// frequencies (`k < 1/λ + 1/μ`, about 0.1 for the defaults λ = 0.33, μ = −0.34) and
/// so, unlike plain Laplacian smoothing, does not shrink the surface.
///
/// The weights are uniform (the umbrella operator) or cotangent ([`cotan_weight`]),
/// computed once from the positions at construction (Taubin's linear filter); a vertex
/// whose cotangent weights do not sum to a positive number falls back to uniform
/// weights. Only the region's vertices move; their neighbours outside stay fixed and
/// anchor the smoothing, and so do mesh-boundary vertices unless asked otherwise.
///
/// A [`Smoother`] precomputes the neighbour lists as compressed rows (CSR) with their
/// weights and runs the steps in parallel (rayon) between two position buffers.
///
/// Precomputed Laplacian of a region (CSR rows with normalised weights) and two
/// position buffers, for repeated smoothing steps.
///
/// The moving vertices are numbered in breadth-first order over the mesh (a
/// Cuthill–McKee-like ordering), so that the neighbours a row reads sit close together
/// in memory whatever the order of the mesh's vertices (subdivided meshes scatter them).
#[derive(Clone, Debug)]
pub struct Smoother {
    binding: halfedge::Binding,
    /// Local index → vertex slot: rows `0..rows` are the moving vertices, the rest the
    /// fixed neighbours that anchor them.
    local_to_slot: Vec<u32>,
    /// Vertex slot → local row for moving vertices, `u32::MAX` otherwise.
    row_of_slot: Vec<u32>,
    rows: usize,
    offsets: Vec<u32>,
    columns: Vec<u32>,
    /// Normalised weights per CSR entry; `None` for uniform weights.
    weights: Option<Vec<f64>>,
    buffers: [Vec<DVec3>; 2],
}

/// Rows per parallel block when collecting neighbour lists.
const BLOCK: usize = 4096;

/// Most iterations one call runs (a larger count is refused): a bound on the time a call
/// can take, far beyond any smoothing (Taubin's examples use tens to hundreds).
const MAX_ITERATIONS: usize = 1 << 20;

impl Smoother {
    /// Most iterations one call runs (a larger count is refused): a bound on the time a
    /// call can take, far beyond any smoothing (Taubin's examples use tens to hundreds).
    pub const MAX_ITERATIONS: usize = MAX_ITERATIONS;

    /// The Laplacian of the vertices of `region` (minus the mesh-boundary vertices when
    /// `fix_boundary`), anchored by their other neighbours.
    pub fn new(
        mesh: &Mesh,
        region: Vertices<'_>,
        weights: SmoothingWeights,
        fix_boundary: bool,
    ) -> Result<Self> {
        let resolved = region.resolve(mesh)?;
        if resolved.len() == 0 {
            return Err(DeformError::EmptySubMesh);
        }
        let slots = mesh.vertex_slots();
        let candidates = resolved.to_indices();
        let moving: Vec<u32> = if fix_boundary {
            candidates
                .par_iter()
                .copied()
                .filter(|&i| {
                    mesh.vertex_at(i as usize)
                        .is_some_and(|v| !mesh.is_boundary_vertex(v))
                })
                .collect()
        } else {
            candidates
        };
        let cotangent = weights == SmoothingWeights::Cotangent;

        // neighbour slots (and weights) of every moving vertex, in slot order, by blocks
        let blocks: Vec<(Vec<u32>, Vec<u32>, Vec<f64>)> = moving
            .par_chunks(BLOCK)
            .map(|chunk| {
                let mut degree = Vec::with_capacity(chunk.len());
                let mut cols = Vec::with_capacity(chunk.len() * 7);
                let mut w = Vec::new();
                for &i in chunk {
                    let v = mesh
                        .vertex_at(i as usize)
                        .expect("moving vertices are live");
                    let start = cols.len();
                    for h in mesh.outgoing_halfedges(v) {
                        cols.push(mesh.vertex_index(mesh.to_vertex(h)) as u32);
                        if cotangent {
                            w.push(cotan_weight(mesh, h));
                        }
                    }
                    if cotangent {
                        normalise(&mut w[start..]);
                    }
                    degree.push((cols.len() - start) as u32);
                }
                (degree, cols, w)
            })
            .collect();
        let mut first = Vec::with_capacity(moving.len() + 1); // slot-order CSR offsets
        first.push(0usize);
        for (degree, _, _) in &blocks {
            for &d in degree {
                first.push(first.last().unwrap() + d as usize);
            }
        }
        let neighbour_slots: Vec<u32> = blocks.iter().flat_map(|b| b.1.iter().copied()).collect();
        let neighbour_weights: Vec<f64> = blocks.iter().flat_map(|b| b.2.iter().copied()).collect();
        drop(blocks);

        // breadth-first numbering of the moving vertices
        let mut index_of_slot = vec![u32::MAX; slots]; // slot → index in `moving`
        for (k, &i) in moving.iter().enumerate() {
            index_of_slot[i as usize] = k as u32;
        }
        let mut order: Vec<u32> = Vec::with_capacity(moving.len());
        let mut seen = vec![false; moving.len()];
        for start in 0..moving.len() {
            if seen[start] {
                continue;
            }
            seen[start] = true;
            let mut head = order.len();
            order.push(start as u32);
            while head < order.len() {
                let k = order[head] as usize;
                head += 1;
                for &j in &neighbour_slots[first[k]..first[k + 1]] {
                    let m = index_of_slot[j as usize];
                    if m != u32::MAX && !seen[m as usize] {
                        seen[m as usize] = true;
                        order.push(m);
                    }
                }
            }
        }

        // local numbering: moving vertices in that order, then anchors as met
        let rows = moving.len();
        let mut local_to_slot: Vec<u32> = order.iter().map(|&k| moving[k as usize]).collect();
        let mut local_of_slot = vec![u32::MAX; slots];
        for (l, &i) in local_to_slot.iter().enumerate() {
            local_of_slot[i as usize] = l as u32;
        }
        let row_of_slot = local_of_slot.clone();
        let mut offsets = Vec::with_capacity(rows + 1);
        let mut columns = Vec::with_capacity(neighbour_slots.len());
        let mut entry_weights = Vec::with_capacity(neighbour_weights.len());
        offsets.push(0u32);
        for &k in &order {
            let (lo, hi) = (first[k as usize], first[k as usize + 1]);
            for &j in &neighbour_slots[lo..hi] {
                if local_of_slot[j as usize] == u32::MAX {
                    local_of_slot[j as usize] = local_to_slot.len() as u32;
                    local_to_slot.push(j);
                }
                columns.push(local_of_slot[j as usize]);
            }
            if cotangent {
                entry_weights.extend_from_slice(&neighbour_weights[lo..hi]);
            }
            offsets.push(columns.len() as u32);
        }
        let n_local = local_to_slot.len();
        Ok(Self {
            binding: mesh.binding(),
            local_to_slot,
            row_of_slot,
            rows,
            offsets,
            columns,
            weights: cotangent.then_some(entry_weights),
            buffers: [vec![DVec3::ZERO; n_local], vec![DVec3::ZERO; n_local]],
        })
    }

    /// The Laplacian of a sub-mesh and its frontier collar: the inside vertices and the
    /// outside ones up to `collar` rings beyond the frontier move (the paper's Fig. 8 a
    /// smooths "sub-meshes and their frontier collars"; `collar = 1` is the ring of faces
    /// around the frontier).
    pub fn for_submesh(
        mesh: &Mesh,
        submesh: &SubMesh,
        collar: usize,
        weights: SmoothingWeights,
        fix_boundary: bool,
    ) -> Result<Self> {
        // `collars` checks that the sub-mesh fits `mesh` (then its mask has one entry per
        // vertex slot).
        let collars = submesh.collars(mesh, collar)?;
        let mut mask = submesh.mask().to_vec();
        for ring in collars {
            for i in ring {
                mask[i as usize] = true;
            }
        }
        let mask = VertexData::new(mesh, mask)?;
        Self::new(mesh, Vertices::Mask(&mask), weights, fix_boundary)
    }

    /// Number of vertices that move (isolated vertices in the region have no
    /// neighbours and stay).
    pub fn moving(&self) -> usize {
        (0..self.rows)
            .filter(|&r| self.offsets[r] != self.offsets[r + 1])
            .count()
    }

    /// `iterations` of Taubin's λ|μ pair (λ > 0, μ < 0). Nothing changes for zero
    /// iterations or λ = μ = 0.
    ///
    /// # Errors
    /// Nothing is changed on error: [`DeformError::InvalidParameter`] for non-finite
    /// factors or more than [`MAX_ITERATIONS`](Self::MAX_ITERATIONS) iterations, [`DeformError::Overflow`] when
    /// the factors make the positions diverge (λ = 1e300), and
    /// [`DeformError::Stale`] for another mesh (or this one at another hierarchy level or
    /// with other connectivity).
    pub fn taubin(
        &mut self,
        mesh: &mut Mesh,
        lambda: f64,
        mu: f64,
        iterations: usize,
    ) -> Result<()> {
        finite("lambda", lambda)?;
        finite("mu", mu)?;
        self.run(mesh, &[lambda, mu], iterations)
    }

    /// `iterations` of plain Laplacian smoothing `p ← p + λ Δp` (for comparison: it
    /// shrinks).
    ///
    /// # Errors
    /// As [`taubin`](Self::taubin).
    pub fn laplacian(&mut self, mesh: &mut Mesh, lambda: f64, iterations: usize) -> Result<()> {
        finite("lambda", lambda)?;
        self.run(mesh, &[lambda], iterations)
    }

    fn run(&mut self, mesh: &mut Mesh, factors: &[f64], iterations: usize) -> Result<()> {
        self.binding.check(mesh, "the smoother")?;
        if iterations > MAX_ITERATIONS {
            return Err(DeformError::InvalidParameter {
                name: "iterations",
                reason: format!("{iterations} is more than {MAX_ITERATIONS}"),
            });
        }
        let steps: Vec<f64> = factors.iter().copied().filter(|&f| f != 0.0).collect();
        if iterations == 0 || steps.is_empty() {
            return Ok(());
        }
        self.gather(mesh.positions());
        let mut current = 0;
        for iteration in 0..iterations {
            // Diverging factors (λ = 1e300) overflow within a few steps: stop there.
            if iteration % 64 == 63
                && !self.buffers[current][..self.rows]
                    .par_iter()
                    .all(|p| p.is_finite())
            {
                break;
            }
            for &f in &steps {
                let [a, b] = &mut self.buffers;
                let (input, output) = if current == 0 { (&*a, b) } else { (&*b, a) };
                step(
                    &self.offsets,
                    &self.columns,
                    self.weights.as_deref(),
                    input,
                    &mut output[..self.rows],
                    f,
                );
                current = 1 - current;
            }
        }
        check_finite_positions(
            "smoothing",
            &self.local_to_slot[..self.rows],
            &self.buffers[current][..self.rows],
        )?;
        self.scatter(mesh.positions_mut(), current);
        Ok(())
    }

    fn gather(&mut self, positions: &[DVec3]) {
        let [a, b] = &mut self.buffers;
        a.par_iter_mut()
            .zip(self.local_to_slot.par_iter())
            .with_min_len(4096)
            .for_each(|(x, &i)| *x = positions[i as usize]);
        // the anchors never change; the moving rows are written by the first step
        b[self.rows..].copy_from_slice(&a[self.rows..]);
    }

    fn scatter(&self, positions: &mut [DVec3], current: usize) {
        let result = &self.buffers[current];
        if self.rows * 8 >= positions.len() {
            positions
                .par_iter_mut()
                .zip(self.row_of_slot.par_iter())
                .with_min_len(4096)
                .for_each(|(p, &r)| {
                    if r != u32::MAX {
                        *p = result[r as usize];
                    }
                });
        } else {
            for r in 0..self.rows {
                positions[self.local_to_slot[r] as usize] = result[r];
            }
        }
    }
}

/// Scales `w` to sum 1; uniform weights when the sum is not positive (obtuse triangles
/// can make cotangent sums vanish or turn negative).
fn normalise(w: &mut [f64]) {
    let sum: f64 = w.iter().sum();
    let scale: f64 = w.iter().map(|x| x.abs()).sum();
    if sum.is_finite() && sum > 1e-12 * scale && sum > 0.0 {
        for x in w.iter_mut() {
            *x /= sum;
        }
    } else {
        let u = 1.0 / w.len() as f64;
        w.iter_mut().for_each(|x| *x = u);
    }
}

/// One Laplacian step `out[r] = in[r] + f·(Σ w in[j] − in[r])` for every row; rows
/// without neighbours copy their input.
fn step(
    offsets: &[u32],
    columns: &[u32],
    weights: Option<&[f64]>,
    input: &[DVec3],
    output: &mut [DVec3],
    f: f64,
) {
    output
        .par_iter_mut()
        .with_min_len(2048)
        .enumerate()
        .for_each(|(r, out)| {
            let (lo, hi) = (offsets[r] as usize, offsets[r + 1] as usize);
            let p = input[r];
            if lo == hi {
                *out = p;
                return;
            }
            let average = match weights {
                None => {
                    let mut sum = DVec3::ZERO;
                    for &c in &columns[lo..hi] {
                        sum += input[c as usize];
                    }
                    sum / (hi - lo) as f64
                }
                Some(w) => {
                    let mut sum = DVec3::ZERO;
                    for (&c, &wc) in columns[lo..hi].iter().zip(&w[lo..hi]) {
                        sum += wc * input[c as usize];
                    }
                    sum
                }
            };
            *out = p + f * (average - p);
        });
}

/// Taubin smoothing of `region` in one call: builds a [`Smoother`] and runs
/// `iterations` λ|μ pairs.
pub fn taubin(
    mesh: &mut Mesh,
    region: Vertices<'_>,
    options: &TaubinOptions,
    iterations: usize,
) -> Result<()> {
    let mut smoother = Smoother::new(mesh, region, options.weights, options.fix_boundary)?;
    smoother.taubin(mesh, options.lambda, options.mu, iterations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    #[test]
    fn a_flat_grid_stays_put_and_a_bump_flattens() {
        let mut mesh = generators::grid(8, 8, 1.0, 1.0);
        let before = mesh.positions().to_vec();
        taubin(&mut mesh, Vertices::All, &TaubinOptions::default(), 5).unwrap();
        for (a, b) in before.iter().zip(mesh.positions()) {
            assert!(
                (a - b).length() < 1e-15,
                "planar uniform grid is a fixed point"
            );
        }
        let centre = mesh.vertex_at(4 + 4 * 9).unwrap();
        mesh.set_position(centre, mesh.position(centre) + DVec3::Z);
        let mut s = Smoother::new(&mesh, Vertices::All, SmoothingWeights::Cotangent, true).unwrap();
        s.taubin(&mut mesh, 0.33, -0.34, 20).unwrap();
        assert!(mesh.position(centre).z < 0.5);
        // the boundary did not move
        for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
            assert_eq!(mesh.position(v), before[mesh.vertex_index(v)]);
        }
    }

    #[test]
    fn zero_iterations_or_factors_change_nothing() {
        let mut mesh = generators::icosphere(2);
        let before = mesh.positions().to_vec();
        let mut s = Smoother::new(&mesh, Vertices::All, SmoothingWeights::Uniform, false).unwrap();
        s.taubin(&mut mesh, 0.0, 0.0, 10).unwrap();
        s.taubin(&mut mesh, 0.33, -0.34, 0).unwrap();
        assert_eq!(before, mesh.positions());
    }
}
