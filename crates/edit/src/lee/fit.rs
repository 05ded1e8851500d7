//! The multilevel B-spline fit of an editing session: Lee 1999 §5 (multilevel B-splines,
//! the continuous scale parameter, boundary fixing) in the form the session uses.
//!
//! Three choices make the paper's intent hold on areas of any size (the generic
//! [`crate::lee::mba::Mba`] keeps the paper's literal form):
//!
//! - **Boundary fixing at every level** (§5.3 asks that the border stays fixed and the
//!   result stays C²). The paper zeroes the three border rows and columns of the *finest*
//!   lattice only, so however wide the edit, the offsets fall to zero within three finest
//!   cells of the border: at a large scale that is a crease one or two rings wide. Here
//!   every level's lattice has its three border rows and columns held at zero (a data
//!   point's requests to them are dropped), so each level's contribution vanishes with
//!   its first and second derivatives on the border over three cells *of its own size*:
//!   a wide edit falls off over a wide band. B-spline refinement keeps zero border rows
//!   zero, so the summed lattice is fixed as in §5.3.
//! - **Scale ↔ coarsest lattice independent of the level count** (§3.6: the influence
//!   area is proportional to `s`; §5.2: `s` selects the coarsest lattice). Level `k` has
//!   `m_k = 2^{k−1}` cells; level 3 (`m = 4`) is the coarsest with a free control point
//!   once the border is fixed. The fit `f_k` over levels `k ..= l` belongs to
//!   `s_k = 4 / m_k = 2^{3−k}` (`s = 1` ↔ `m = 4`, `1/2` ↔ 8, `1/4` ↔ 16, …), and
//!   `f_{l+1}`, the data-only function, to `s = 0`; between two nodes the two functions
//!   are interpolated linearly (`f_s = (1 − t) f_k + t f_{k+1}`,
//!   `t = (s_k − s)/(s_k − s_{k+1})`). The coarsest cell is then `s/4` of the rectangle
//!   whatever `l` is, so a given `s` reaches the same fraction of the area on a coarse
//!   and on a fine mesh; `l` (the resolution) only decides where `f_s` turns into the
//!   data-only function (below `s_l`, less than one finest cell).
//! - **Detail levels at the primitive** (MBA interpolates as levels are added, Lee,
//!   Wolberg & Shin 1997 §4). After the dense levels, up to [`DETAIL_LEVELS`] finer
//!   levels approximate what is left at the primitive's points; they are sparse (only the
//!   primitive's control points, evaluated only at the vertices they reach), so a
//!   primitive of close vertices is interpolated without a larger dense lattice. They
//!   stop once the residual is below `1e-9` of the largest offset.
//!
//! Everything that depends only on the points (which control points each point touches,
//! its weights, the `Σ w²` of every control point) is computed once per primitive
//! ([`FitPlan`]); a drag costs one pass over the primitive per level plus the dense
//! refinement.

use glam::{DVec2, DVec3};

use crate::lee::mba::{cubic_bspline_weights, level_size, refine, ScaleSplit};

/// The coarsest level the session uses: `m_3 = 4` cells, one free control point once the
/// three border rows on each side are fixed (levels 1 and 2 would be all border).
pub(crate) const FIRST_LEVEL: usize = 3;
/// Most sparse levels added below the dense lattice at the primitive's points (each
/// halves the cell: 64 × finer than the dense lattice).
pub(crate) const DETAIL_LEVELS: usize = 6;
/// Residual (relative to the largest offset) below which no further detail level runs.
const DETAIL_TOLERANCE: f64 = 1e-9;
const NONE: u32 = u32::MAX;

/// The scale value `s_k = 2^{3−k}` of the fit starting at level `k ≥ 3`.
#[must_use]
pub(crate) fn scale_of_level(k: usize) -> f64 {
    0.5f64.powi(k as i32 - FIRST_LEVEL as i32)
}

/// Which functions `s ∈ [0, 1]` blends with `levels` dense levels (see the module docs):
/// `k ∈ 3 ..= levels + 1`, `k = levels + 1` the data-only function.
#[must_use]
pub(crate) fn scale_split(s: f64, levels: usize) -> ScaleSplit {
    let s = s.clamp(0.0, 1.0);
    if s == 0.0 {
        return ScaleSplit {
            k: levels + 1,
            t: 0.0,
        };
    }
    // s_k ≥ s > s_{k+1}: k = 3 + ⌊log2(1/s)⌋, snapped onto a node within 1e-12
    let mut x = -s.log2();
    if (x - x.round()).abs() < 1e-12 {
        x = x.round();
    }
    let k = FIRST_LEVEL + x.floor() as usize;
    if k >= levels {
        let sl = scale_of_level(levels);
        return ScaleSplit {
            k: levels,
            t: ((sl - s) / sl).clamp(0.0, 1.0),
        };
    }
    let sk = scale_of_level(k);
    ScaleSplit {
        k,
        t: (2.0 - 2.0 * s / sk).clamp(0.0, 1.0),
    }
}

/// Cell `(i, j)` of `p` in a lattice of `m × m` cells over `[0, size]` and its B-spline
/// weights along u and v (the arithmetic of [`crate::lee::mba::LatticeBasis::locate`], with
/// 64-bit cells for the fine detail levels).
#[inline]
pub(crate) fn locate(p: DVec2, size: DVec2, m: usize) -> (usize, usize, [f64; 4], [f64; 4]) {
    let extent = size.max(DVec2::splat(f64::MIN_POSITIVE));
    let x = (p.x / extent.x).clamp(0.0, 1.0) * m as f64;
    let y = (p.y / extent.y).clamp(0.0, 1.0) * m as f64;
    let i = (x.floor() as usize).min(m - 1);
    let j = (y.floor() as usize).min(m - 1);
    let s = (x - i as f64).clamp(0.0, 1.0);
    let t = (y - j as f64).clamp(0.0, 1.0);
    (i, j, cubic_bspline_weights(s), cubic_bspline_weights(t))
}

/// True for storage rows / columns `0, 1, 2, m, m+1, m+2` (lattice `−1, 0, 1, m−1, m,
/// m+1`), the ones boundary fixing holds at zero.
#[inline]
fn is_border(storage: usize, m: usize) -> bool {
    storage <= 2 || storage >= m
}

/// One level of the fit for a fixed set of points: the free control points they touch
/// and, per point, its 16 control points' slots and coefficients.
#[derive(Clone, Debug, Default)]
struct LevelPlan {
    /// Cells per axis.
    m: usize,
    /// Storage index `b·(m+3) + a` of every touched free control point, ascending.
    keys: Vec<u64>,
    /// `1 / Σ w²` over the points touching each key.
    inv_omega: Vec<f64>,
    /// Per point: slot in `keys` of each of its 16 control points (`NONE`: fixed or zero
    /// weight), row by row along v.
    slots: Vec<[u32; 16]>,
    /// Per point: `w_ab` of each of its 16 control points.
    weights: Vec<[f64; 16]>,
    /// Per point: `w³ / Σ_{all 16} w²`, the share of `z` it asks of each control point,
    /// times its averaging weight `w²`.
    requests: Vec<[f64; 16]>,
}

impl LevelPlan {
    fn new(points: &[DVec2], size: DVec2, m: usize, fixed_border: bool) -> Self {
        let n = m as u64 + 3;
        let mut entries: Vec<(u64, u32, u8)> = Vec::with_capacity(16 * points.len());
        let mut weights = vec![[0.0; 16]; points.len()];
        let mut requests = vec![[0.0; 16]; points.len()];
        for (c, &p) in points.iter().enumerate() {
            let (i, j, wu, wv) = locate(p, size, m);
            let mut w = [0.0; 16];
            for (b, &y) in wv.iter().enumerate() {
                for (a, &x) in wu.iter().enumerate() {
                    w[4 * b + a] = x * y;
                }
            }
            let sum2: f64 = w.iter().map(|x| x * x).sum();
            for b in 0..4 {
                for a in 0..4 {
                    let x = w[4 * b + a];
                    let (ii, jj) = (i + a, j + b);
                    if x == 0.0 || (fixed_border && (is_border(ii, m) || is_border(jj, m))) {
                        continue;
                    }
                    entries.push((jj as u64 * n + ii as u64, c as u32, (4 * b + a) as u8));
                    requests[c][4 * b + a] = x * x * x / sum2;
                }
            }
            weights[c] = w;
        }
        entries.sort_unstable();
        let mut keys = Vec::new();
        let mut omega: Vec<f64> = Vec::new();
        let mut slots = vec![[NONE; 16]; points.len()];
        for &(key, c, a) in &entries {
            if keys.last() != Some(&key) {
                keys.push(key);
                omega.push(0.0);
            }
            let s = keys.len() - 1;
            slots[c as usize][a as usize] = s as u32;
            let w = weights[c as usize][a as usize];
            omega[s] += w * w;
        }
        Self {
            m,
            keys,
            inv_omega: omega.into_iter().map(|o| 1.0 / o).collect(),
            slots,
            weights,
            requests,
        }
    }

    /// One level of B-spline approximation (Lee, Wolberg & Shin 1997 §3.2) of `residual`:
    /// the control points into `phi` (one per key), their values at the points
    /// subtracted from `residual`.
    fn approximate(&self, residual: &mut [DVec3], delta: &mut Vec<DVec3>, phi: &mut Vec<DVec3>) {
        delta.clear();
        delta.resize(self.keys.len(), DVec3::ZERO);
        for ((slots, requests), &z) in self.slots.iter().zip(&self.requests).zip(&*residual) {
            for (&s, &r) in slots.iter().zip(requests) {
                if s != NONE {
                    delta[s as usize] += z * r;
                }
            }
        }
        phi.clear();
        phi.extend(delta.iter().zip(&self.inv_omega).map(|(&d, &w)| d * w));
        for ((slots, weights), r) in self.slots.iter().zip(&self.weights).zip(residual) {
            let mut value = DVec3::ZERO;
            for (&s, &w) in slots.iter().zip(weights) {
                if s != NONE {
                    value += phi[s as usize] * w;
                }
            }
            *r -= value;
        }
    }
}

/// The vertices a detail level reaches, with their slots and weights in it.
#[derive(Clone, Debug, Default)]
struct DetailReach {
    /// Index into [`FitPlan::detail_vertices`].
    target: Vec<u32>,
    slots: Vec<[u32; 16]>,
    weights: Vec<[f64; 16]>,
}

/// Everything of the fit that depends only on the primitive's embedded points.
#[derive(Clone, Debug, Default)]
pub(crate) struct FitPlan {
    levels: usize,
    /// Levels `FIRST_LEVEL ..= levels`.
    dense: Vec<LevelPlan>,
    /// Levels `levels + 1 ..= levels + DETAIL_LEVELS`.
    detail: Vec<LevelPlan>,
    reach: Vec<DetailReach>,
    /// Local indices of the interior vertices some detail level reaches.
    detail_vertices: Vec<u32>,
}

/// The interior vertices' cells in the finest dense lattice, to find the vertices near a
/// point: `(j·m + i, local index)`, ascending.
#[derive(Clone, Debug, Default)]
pub(crate) struct CellIndex {
    m: usize,
    cells: Vec<(u64, u32)>,
}

impl CellIndex {
    /// Buckets the interior vertices `uv` by their cell in a lattice of `m × m` cells.
    pub(crate) fn new(uv: &[DVec2], size: DVec2, m: usize) -> Self {
        let mut cells: Vec<(u64, u32)> = uv
            .iter()
            .enumerate()
            .map(|(v, &p)| {
                let (i, j, _, _) = locate(p, size, m);
                (j as u64 * m as u64 + i as u64, v as u32)
            })
            .collect();
        cells.sort_unstable();
        Self { m, cells }
    }

    /// Calls `f` for every vertex in cells `i0 ..= i1` × `j0 ..= j1` (clamped).
    fn for_each_in(
        &self,
        (i0, i1): (isize, isize),
        (j0, j1): (isize, isize),
        mut f: impl FnMut(u32),
    ) {
        let last = self.m as isize - 1;
        let (i0, i1) = (i0.clamp(0, last) as u64, i1.clamp(0, last) as u64);
        for j in j0.clamp(0, last)..=j1.clamp(0, last) {
            let lo = j as u64 * self.m as u64 + i0;
            let hi = j as u64 * self.m as u64 + i1;
            let start = self.cells.partition_point(|&(c, _)| c < lo);
            for &(c, v) in &self.cells[start..] {
                if c > hi {
                    break;
                }
                f(v);
            }
        }
    }
}

impl FitPlan {
    /// The plan for data at `points` (embedded primitive vertices) with `levels` dense
    /// levels over `[0, size]`; `uv` are the interior vertices' embedded positions and
    /// `cells` their index in the finest dense lattice. `fixed_border`: boundary fixing
    /// (Lee 1999 §5.3) at every level.
    pub(crate) fn new(
        points: &[DVec2],
        size: DVec2,
        levels: usize,
        uv: &[DVec2],
        cells: &CellIndex,
        fixed_border: bool,
    ) -> Self {
        let dense = (FIRST_LEVEL..=levels)
            .map(|k| LevelPlan::new(points, size, level_size(k), fixed_border))
            .collect();
        let detail: Vec<LevelPlan> = (levels + 1..=levels + DETAIL_LEVELS)
            .map(|k| LevelPlan::new(points, size, level_size(k), fixed_border))
            .collect();
        // Candidates: a vertex shares a control point with a point at a detail level only
        // if it is less than 4 detail cells (2 dense cells) away along each axis.
        let m = cells.m;
        let mut seen = vec![false; uv.len()];
        let mut candidates = Vec::new();
        for &p in points {
            let (i, j, _, _) = locate(p, size, m);
            let (i, j) = (i as isize, j as isize);
            cells.for_each_in((i - 2, i + 2), (j - 2, j + 2), |v| {
                if !std::mem::replace(&mut seen[v as usize], true) {
                    candidates.push(v);
                }
            });
        }
        candidates.sort_unstable();
        let mut target_of = vec![NONE; candidates.len()];
        let mut detail_vertices = Vec::new();
        let reach = detail
            .iter()
            .map(|level| {
                let n = level.m as u64 + 3;
                let mut reach = DetailReach::default();
                for (ci, &v) in candidates.iter().enumerate() {
                    let (i, j, wu, wv) = locate(uv[v as usize], size, level.m);
                    let mut slots = [NONE; 16];
                    let mut weights = [0.0; 16];
                    let mut any = false;
                    for b in 0..4 {
                        for a in 0..4 {
                            let key = (j + b) as u64 * n + (i + a) as u64;
                            if let Ok(s) = level.keys.binary_search(&key) {
                                slots[4 * b + a] = s as u32;
                                weights[4 * b + a] = wu[a] * wv[b];
                                any = true;
                            }
                        }
                    }
                    if any {
                        if target_of[ci] == NONE {
                            target_of[ci] = detail_vertices.len() as u32;
                            detail_vertices.push(v);
                        }
                        reach.target.push(target_of[ci]);
                        reach.slots.push(slots);
                        reach.weights.push(weights);
                    }
                }
                reach
            })
            .collect();
        Self {
            levels,
            dense,
            detail,
            reach,
            detail_vertices,
        }
    }

    /// Local indices of the interior vertices the detail levels may move.
    pub(crate) fn detail_vertices(&self) -> &[u32] {
        &self.detail_vertices
    }
}

/// Reusable buffers and the result of the last fit.
#[derive(Clone, Debug, Default)]
pub(crate) struct FitState {
    delta: Vec<DVec3>,
    phi: Vec<DVec3>,
    ra: Vec<DVec3>,
    rb: Vec<DVec3>,
    refined: Vec<DVec3>,
    scratch: Vec<DVec3>,
    detail_phi: Vec<Vec<DVec3>>,
    detail_used: usize,
    /// Per entry of [`FitPlan::detail_vertices`]: the detail levels' offset there.
    detail_offsets: Vec<DVec3>,
}

impl FitState {
    /// Fits `values` at the plan's points for scale split `split` (from [`scale_split`]):
    /// the dense part `(1 − t) Ψ_k + t Ψ_{k+1}` as one lattice of the finest dense level
    /// into `out` (the data-only part `data_weight · z` is the caller's), then the detail
    /// levels on what is left at the points ([`detail_offsets`](Self::detail_offsets)).
    pub(crate) fn fit(
        &mut self,
        plan: &FitPlan,
        split: ScaleSplit,
        values: &[DVec3],
        out: &mut Vec<DVec3>,
    ) {
        let l = plan.levels;
        self.detail_used = 0;
        self.detail_offsets.clear();
        self.detail_offsets
            .resize(plan.detail_vertices.len(), DVec3::ZERO);
        out.clear();
        if split.k > l {
            let n = level_size(l) + 3;
            out.resize(n * n, DVec3::ZERO);
            return;
        }
        let k = split.k.max(FIRST_LEVEL);
        let wa = 1.0 - split.t;
        let wb = if k < l { split.t } else { 0.0 };
        self.ra.clear();
        self.ra.extend_from_slice(values);
        self.rb.clear();
        self.rb.extend_from_slice(values);
        let n0 = level_size(k) + 3;
        out.resize(n0 * n0, DVec3::ZERO);
        for j in k..=l {
            let level = &plan.dense[j - FIRST_LEVEL];
            if j > k {
                refine(out, level.m / 2, &mut self.refined, &mut self.scratch);
                std::mem::swap(out, &mut self.refined);
            }
            level.approximate(&mut self.ra, &mut self.delta, &mut self.phi);
            for (&key, &phi) in level.keys.iter().zip(&self.phi) {
                out[key as usize] += phi * wa;
            }
            if wb > 0.0 && j > k {
                level.approximate(&mut self.rb, &mut self.delta, &mut self.phi);
                for (&key, &phi) in level.keys.iter().zip(&self.phi) {
                    out[key as usize] += phi * wb;
                }
            }
        }
        // What f_s misses at the points: z − (wa (z − ra) + wb (z − rb) + dw z), where
        // the data-only weight dw is wb's when k = l.
        let rb_weight = if k < l { wb } else { 0.0 };
        for (a, &b) in self.ra.iter_mut().zip(&self.rb) {
            *a = *a * wa + b * rb_weight;
        }
        let largest = values.iter().map(|z| z.length()).fold(0.0, f64::max);
        let tolerance = DETAIL_TOLERANCE * largest;
        if self.detail_phi.len() < plan.detail.len() {
            self.detail_phi.resize(plan.detail.len(), Vec::new());
        }
        for (d, level) in plan.detail.iter().enumerate() {
            if self.ra.iter().all(|r| r.length() <= tolerance) {
                break;
            }
            let mut phi = std::mem::take(&mut self.detail_phi[d]);
            level.approximate(&mut self.ra, &mut self.delta, &mut phi);
            self.detail_phi[d] = phi;
            self.detail_used = d + 1;
        }
        for (reach, phi) in plan
            .reach
            .iter()
            .zip(&self.detail_phi)
            .take(self.detail_used)
        {
            for ((&t, slots), weights) in reach.target.iter().zip(&reach.slots).zip(&reach.weights)
            {
                let mut value = DVec3::ZERO;
                for (&s, &w) in slots.iter().zip(weights) {
                    if s != NONE {
                        value += phi[s as usize] * w;
                    }
                }
                self.detail_offsets[t as usize] += value;
            }
        }
    }

    /// Number of detail levels the last fit used (0 when the dense levels already met
    /// the tolerance).
    pub(crate) fn detail_used(&self) -> usize {
        self.detail_used
    }

    /// The detail levels' offsets at [`FitPlan::detail_vertices`] from the last fit.
    pub(crate) fn detail_offsets(&self) -> &[DVec3] {
        &self.detail_offsets
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_nodes_halve_the_coarsest_cell() {
        assert_eq!(scale_split(1.0, 8), ScaleSplit { k: 3, t: 0.0 });
        assert_eq!(scale_split(0.5, 8), ScaleSplit { k: 4, t: 0.0 });
        assert_eq!(scale_split(0.25, 8), ScaleSplit { k: 5, t: 0.0 });
        let s = scale_split(0.375, 8);
        assert_eq!(s.k, 4);
        assert!((s.t - 0.5).abs() < 1e-12);
        // below the finest node: towards the data-only function
        assert_eq!(
            scale_split(scale_of_level(8), 8),
            ScaleSplit { k: 8, t: 0.0 }
        );
        let s = scale_split(0.5 * scale_of_level(8), 8);
        assert_eq!(s.k, 8);
        assert!((s.t - 0.5).abs() < 1e-12);
        assert_eq!(scale_split(0.0, 8), ScaleSplit { k: 9, t: 0.0 });
        // the same s selects the same coarsest lattice for any level count above it
        for l in [5, 9, 12] {
            assert_eq!(scale_split(0.3, l), scale_split(0.3, 5));
        }
    }

    #[test]
    fn refinement_keeps_fixed_border_rows_zero() {
        // every level fixed ⇒ the summed, refined lattice is fixed as in Lee 1999 §5.3
        let points = [
            DVec2::new(0.1, 0.5),
            DVec2::new(0.5, 0.5),
            DVec2::new(0.93, 0.2),
        ];
        let values = [DVec3::X, DVec3::Y, DVec3::Z];
        let uv: Vec<DVec2> = points.to_vec();
        let cells = CellIndex::new(&uv, DVec2::ONE, level_size(7));
        let plan = FitPlan::new(&points, DVec2::ONE, 7, &uv, &cells, true);
        let mut state = FitState::default();
        let mut out = Vec::new();
        state.fit(&plan, scale_split(1.0, 7), &values, &mut out);
        let m = level_size(7);
        let n = m + 3;
        for j in 0..n {
            for i in 0..n {
                if is_border(i, m) || is_border(j, m) {
                    assert_eq!(out[j * n + i], DVec3::ZERO, "({i}, {j})");
                }
            }
        }
        assert!(out.iter().any(|p| *p != DVec3::ZERO));
    }
}
