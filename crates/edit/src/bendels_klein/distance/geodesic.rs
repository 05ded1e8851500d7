//! Geodesic distances by fast marching (Kimmel & Sethian 1998; Bendels & Klein, Sec. 4.2).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::{DVec2, DVec3};
use halfedge::{Binding, HalfedgeId, Mesh, VertexData, VertexId};
use rayon::prelude::*;

use crate::bendels_klein::error::{BendelsKleinError, Result};

/// The two-point update rule of [`FastMarching`].
///
/// Paper: Kimmel & Sethian 1998, *Computing geodesic paths on manifolds*; Bendels & Klein
/// 2003, *Image and 3D-object editing with precisely specified editing regions*, Sec. 4.2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FastMarchingUpdate {
    /// Planar wavefront across the triangle everywhere (Kimmel & Sethian 1998), whatever
    /// the sources' radii.
    KimmelSethian,
    /// Virtual source with a source radius (Novotni & Klein 2002, generalised): exact
    /// for point sources and for straight lines on developable surfaces. Default.
    #[default]
    VirtualSource,
}

/// A fast-marching source: a vertex (by [`Mesh::vertex_index`]), its start value, and
/// the radius of the front it emits: 0 for an isolated point, `∞` for a vertex of a
/// border curve (its front is locally straight).
///
/// Paper: Kimmel & Sethian 1998, *Computing geodesic paths on manifolds*; Bendels & Klein
/// 2003, *Image and 3D-object editing with precisely specified editing regions*, Sec. 4.2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSource {
    /// Vertex index.
    pub vertex: usize,
    /// Start value (usually 0).
    pub distance: f64,
    /// Front radius at the source.
    pub radius: f64,
}

impl MarchSource {
    /// An isolated point source at distance 0.
    #[must_use]
    pub fn point(vertex: usize) -> Self {
        Self {
            vertex,
            distance: 0.0,
            radius: 0.0,
        }
    }
    /// A vertex of a source curve (a region border) at distance 0.
    #[must_use]
    pub fn on_curve(vertex: usize) -> Self {
        Self {
            vertex,
            distance: 0.0,
            radius: f64::INFINITY,
        }
    }
}

/// A triangle (real or unfolded) seen from the vertex it updates: the other corners
/// `a`, `b`, the lengths `|ya|`, `|yb|` and `(a − y)·(b − y)`, in the unfolded plane.
#[derive(Clone, Copy, Debug)]
struct Stencil {
    a: u32,
    b: u32,
    la: f64,
    lb: f64,
    dab: f64,
}

const NO_VERTEX: u32 = u32::MAX;
const MAX_UNFOLD: usize = 12;

/// Geodesic distance on a triangle mesh by fast marching (Kimmel & Sethian 1998,
/// *Computing geodesic paths on manifolds*; Bendels & Klein, Sec. 4.2), multi-source.
///
/// Vertices are accepted in order of distance from a binary heap (lazy deletion: a
/// vertex may sit in the heap several times, stale entries are skipped). When a vertex
/// `x` is accepted, every vertex `y` that depends on it is updated: along the edge,
/// `T(y) ≤ T(x) + |xy|`, and across each triangle `(y, x, z)` with `z` accepted by the
/// two-point update below; the smallest value wins.
///
/// Two-point updates ([`FastMarchingUpdate`]):
///
/// - **Planar wavefront** (Kimmel & Sethian): the solution is linear over the triangle
///   with unit gradient: with `X = [e_a e_b]` the edges from `y`, `Q = (XᵀX)⁻¹` and
///   `δ = (T_a − t, T_b − t)`, solve `δᵀ Q δ = 1` for the larger `t`, accepted when the
///   characteristic enters through the opposite edge (`−Qδ ≥ 0`). Exact for straight
///   fronts (distance to a straight border), but 1.5 % off on average from a single
///   vertex of an icosphere of level 4, and 20 % next to the source.
/// - **Virtual source** (Novotni & Klein 2002, the "improved version" of Kimmel–Sethian
///   the paper uses), generalised with a *source radius*: the front near `y` is taken
///   as the set of points at distance `T` from a circle of radius `R` (`R = 0`: a point
///   source, `R = ∞`: a straight line). In the unfolded triangle, the centre lies at
///   `T_a + R` from `a` and `T_b + R` from `b`, beyond the edge; `t = |centre − y| − R`
///   when the ray from the centre to `y` crosses the edge. Each vertex carries the `R`
///   of the update that set it (a source's own `R` for its neighbours): point sources
///   give `R = 0` (Novotni & Klein's update, exact for a point source on a developable
///   surface), border curves give `R = ∞`, where the update is the planar one (exact for
///   a straight border). This is the default: 0.3 % mean error at icosphere level 4,
///   0.07 % at level 6, and exact on planar grids for points and straight lines alike.
///
/// **Obtuse triangles** break causality (the update of the obtuse corner can use a
/// value from the wrong side). As Kimmel & Sethian propose, the obtuse corner's
/// triangle is unfolded across its opposite edge, strip after strip, until a vertex `d`
/// lands in the corner's "acute section" (both angles `∠(a y d)` and `∠(d y b)` at most
/// 90°); the two virtual acute triangles `(y, a, d)` and `(y, d, b)` then replace the
/// obtuse one (which is kept as a third stencil: its update is exact whenever causal).
/// Corners where no such vertex is found within 12 strips keep their triangle only.
/// That happens at slivers with an angle near 180°, whose section is a sliver too: the
/// vertex is then set from a less upwind triangle, a first-order error that spreads
/// downstream (on a planar grid with vertices jittered by ±0.35 edge lengths, one such
/// corner gives a 0.24-edge-length error; at ±0.2 the result is exact).
///
/// Everything the updates need is precomputed once per mesh ([`FastMarching::new`], in
/// parallel): per vertex, its stencils (the two other corners and the unfolded edge
/// lengths and dot product) and the list of vertices that depend on it. A solve
/// allocates its value, radius, state and heap arrays once; an update allocates nothing.
///
/// Precomputed fast marching on one mesh (geometry frozen at construction): build once,
/// then [`FastMarching::distances`] from any sources.
#[derive(Clone, Debug)]
pub struct FastMarching {
    update: FastMarchingUpdate,
    stencil_start: Vec<u32>,
    stencils: Vec<Stencil>,
    dependent_start: Vec<u32>,
    dependents: Vec<u32>,
    dependent_lengths: Vec<f64>,
    obtuse_unfolded: usize,
    obtuse_kept: usize,
    /// The vertices with stencils when the solver was made [`within`](Self::within) a
    /// region (`None`: all): a march leaves the others out whatever its mask.
    region: Option<Vec<bool>>,
    /// The mesh the stencils were made for: the distances carry it, masks and meshes
    /// passed in are checked against it.
    binding: Binding,
}

/// What one parallel task computes for a run of consecutive vertices: their stencils,
/// their edge neighbours with lengths, and the (virtual vertex, vertex) pairs of their
/// unfolded stencils.
#[derive(Default)]
struct Chunk {
    first: usize,
    stencil_counts: Vec<u32>,
    stencils: Vec<Stencil>,
    neighbour_counts: Vec<u32>,
    neighbours: Vec<u32>,
    lengths: Vec<f64>,
    virtual_pairs: Vec<(u32, u32)>,
    unfolded: usize,
    kept: usize,
}

/// Splits `data` into consecutive mutable pieces of the given lengths.
fn split_lengths<'a, T>(mut data: &'a mut [T], lengths: &[usize]) -> Vec<&'a mut [T]> {
    let mut pieces = Vec::with_capacity(lengths.len());
    for &len in lengths {
        let (piece, rest) = data.split_at_mut(len);
        pieces.push(piece);
        data = rest;
    }
    pieces
}

impl FastMarching {
    /// Precomputes stencils (obtuse corners unfolded) and dependency lists for `mesh`
    /// with the default [`FastMarchingUpdate::VirtualSource`] rule. Indices are
    /// [`Mesh::vertex_index`]; removed vertex slots are inert.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        Self::with_update(mesh, FastMarchingUpdate::default())
    }

    /// As [`FastMarching::new`] with a chosen update rule.
    #[must_use]
    pub fn with_update(mesh: &Mesh, update: FastMarchingUpdate) -> Self {
        Self::build(mesh, update, None)
    }

    /// A solver for marches within `region` (default update rule): stencils and
    /// dependents are made for the region's vertices only, so a march whose `active`
    /// mask and sources lie in the region gives the same distances as
    /// [`FastMarching::new`]'s, bit for bit (it reads no stencil of an inactive
    /// vertex), at the region's cost instead of the mesh's. Every march of this solver
    /// stays within the region whatever mask it is given (vertices outside are `+∞`),
    /// sources outside it included.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when `region` was made for another mesh (or this one
    /// in another state).
    pub(crate) fn within(mesh: &Mesh, region: &VertexData<bool>) -> Result<Self> {
        region.binding().check(mesh, "the region")?;
        Ok(Self::build(
            mesh,
            FastMarchingUpdate::default(),
            Some(region.values()),
        ))
    }

    /// [`FastMarching::with_update`], limited to `region`'s vertices when given.
    fn build(mesh: &Mesh, update: FastMarchingUpdate, region: Option<&[bool]>) -> Self {
        let n = mesh.vertex_slots();
        let vertex_at = |i: usize| {
            if region.is_some_and(|r| !r.get(i).copied().unwrap_or(false)) {
                None
            } else {
                mesh.vertex_at(i)
            }
        };
        const CHUNK: usize = 4096;
        // First pass over the vertices, in parallel runs: the number of stencils and
        // neighbours of every vertex, and the virtual dependents. The stencils themselves
        // are dropped vertex by vertex: kept until copied into place they would double the
        // solver's memory while it is made; the second pass computes them again straight
        // into their place.
        let mut chunks: Vec<Chunk> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut chunk = Chunk {
                    first: c * CHUNK,
                    ..Chunk::default()
                };
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    if let Some(v) = vertex_at(i) {
                        vertex_stencils(mesh, v, &mut chunk);
                    }
                    chunk.stencil_counts.push(chunk.stencils.len() as u32);
                    chunk.neighbour_counts.push(chunk.neighbours.len() as u32);
                    chunk.stencils.clear();
                    chunk.neighbours.clear();
                    chunk.lengths.clear();
                }
                chunk
            })
            .collect();
        let (obtuse_unfolded, obtuse_kept) = chunks
            .iter()
            .fold((0, 0), |(u, k), c| (u + c.unfolded, k + c.kept));
        // Virtual dependents: (d, y) when y's unfolded stencil uses d; grouped by d.
        let mut virtual_pairs: Vec<(u32, u32)> = chunks
            .iter_mut()
            .flat_map(|c| std::mem::take(&mut c.virtual_pairs))
            .collect();
        virtual_pairs.par_sort_unstable();
        virtual_pairs.dedup();
        let mut virtual_count = vec![0u32; n];
        for &(d, _) in &virtual_pairs {
            virtual_count[d as usize] += 1;
        }
        // Offsets.
        let mut stencil_start = Vec::with_capacity(n + 1);
        let mut dependent_start = Vec::with_capacity(n + 1);
        stencil_start.push(0u32);
        dependent_start.push(0u32);
        for chunk in &chunks {
            for (k, (&sc, &nc)) in chunk
                .stencil_counts
                .iter()
                .zip(&chunk.neighbour_counts)
                .enumerate()
            {
                let i = chunk.first + k;
                stencil_start.push(stencil_start[i] + sc);
                dependent_start.push(dependent_start[i] + nc + virtual_count[i]);
            }
        }
        // Fill in parallel, each run into its own contiguous range.
        let total_stencils = stencil_start[n] as usize;
        let total_dependents = dependent_start[n] as usize;
        let mut stencils = vec![
            Stencil {
                a: NO_VERTEX,
                b: NO_VERTEX,
                la: 0.0,
                lb: 0.0,
                dab: 0.0
            };
            total_stencils
        ];
        let mut dependents = vec![NO_VERTEX; total_dependents];
        let mut dependent_lengths = vec![f64::INFINITY; total_dependents];
        let range_of = |start: &[u32], c: &Chunk| {
            let end = c.first + c.stencil_counts.len();
            (start[c.first] as usize, start[end] as usize)
        };
        let stencil_lengths: Vec<usize> = chunks
            .iter()
            .map(|c| {
                let (lo, hi) = range_of(&stencil_start, c);
                hi - lo
            })
            .collect();
        let dependent_lengths_per_chunk: Vec<usize> = chunks
            .iter()
            .map(|c| {
                let (lo, hi) = range_of(&dependent_start, c);
                hi - lo
            })
            .collect();
        let stencil_pieces = split_lengths(&mut stencils, &stencil_lengths);
        let vertex_pieces = split_lengths(&mut dependents, &dependent_lengths_per_chunk);
        let length_pieces = split_lengths(&mut dependent_lengths, &dependent_lengths_per_chunk);
        // Second pass: each run computes its vertices' stencils again (the same function
        // of the same mesh: the same values, in the same order) into its own pieces.
        chunks
            .par_iter()
            .zip(stencil_pieces)
            .zip(vertex_pieces.into_par_iter().zip(length_pieces))
            .for_each_init(Chunk::default, |scratch, ((chunk, st), (dv, dl))| {
                let stencil_base = stencil_start[chunk.first] as usize;
                let base = dependent_start[chunk.first] as usize;
                let end_vertex = chunk.first + chunk.stencil_counts.len();
                // Virtual pairs of this run's vertices: a contiguous range (sorted by d).
                let lo = virtual_pairs.partition_point(|&(d, _)| (d as usize) < chunk.first);
                let hi = virtual_pairs.partition_point(|&(d, _)| (d as usize) < end_vertex);
                let mut virtuals = virtual_pairs[lo..hi].iter().peekable();
                for k in 0..chunk.neighbour_counts.len() {
                    let i = chunk.first + k;
                    scratch.stencils.clear();
                    scratch.neighbours.clear();
                    scratch.lengths.clear();
                    scratch.virtual_pairs.clear();
                    if let Some(v) = vertex_at(i) {
                        vertex_stencils(mesh, v, scratch);
                    }
                    let s0 = stencil_start[i] as usize - stencil_base;
                    st[s0..s0 + scratch.stencils.len()].copy_from_slice(&scratch.stencils);
                    let mut write = dependent_start[i] as usize - base;
                    let count = scratch.neighbours.len();
                    dv[write..write + count].copy_from_slice(&scratch.neighbours);
                    dl[write..write + count].copy_from_slice(&scratch.lengths);
                    write += count;
                    while let Some(&&(d, y)) = virtuals.peek() {
                        if d as usize != i {
                            break;
                        }
                        dv[write] = y;
                        write += 1;
                        virtuals.next();
                    }
                }
            });
        Self {
            update,
            stencil_start,
            stencils,
            dependent_start,
            dependents,
            dependent_lengths,
            obtuse_unfolded,
            obtuse_kept,
            region: region.map(<[bool]>::to_vec),
            binding: mesh.binding(),
        }
    }

    /// The mesh this solver was made for (see [`halfedge::Binding`]).
    #[must_use]
    pub fn binding(&self) -> Binding {
        self.binding
    }

    /// Number of vertex slots covered (the mesh's `vertex_slots()` at construction).
    #[must_use]
    pub fn len(&self) -> usize {
        self.stencil_start.len() - 1
    }
    /// True for an empty mesh.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The update rule.
    #[must_use]
    pub fn update_rule(&self) -> FastMarchingUpdate {
        self.update
    }
    /// Obtuse corners split by unfolding, and obtuse corners left as they are (no
    /// acute-section vertex within reach).
    #[must_use]
    pub fn obtuse_corners(&self) -> (usize, usize) {
        (self.obtuse_unfolded, self.obtuse_kept)
    }

    /// Geodesic distances from `sources` to every vertex, by vertex index, bound to the
    /// mesh the solver was made for; `+∞` where unreachable. With `active`, only
    /// vertices with `active[i]` are marched (sources always are), and only triangles of
    /// active vertices are used: distances within a region.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when `active` was made for another mesh (or this one in
    /// another state) than the solver; [`BendelsKleinError::InvalidParameter`] for a source
    /// index out of range or a NaN start value.
    pub fn distances(
        &self,
        sources: &[MarchSource],
        active: Option<&VertexData<bool>>,
    ) -> Result<VertexData<f64>> {
        Ok(self.distances_and_radii(sources, active)?.0)
    }

    /// [`FastMarching::distances`] together with the front radius each vertex was
    /// reached with (0 from point sources, `∞` from curves; see [`FastMarching`]): what
    /// refinement needs to place a virtual origin.
    ///
    /// # Errors
    /// As [`FastMarching::distances`].
    pub fn distances_and_radii(
        &self,
        sources: &[MarchSource],
        active: Option<&VertexData<bool>>,
    ) -> Result<(VertexData<f64>, VertexData<f64>)> {
        const FAR: u8 = 0;
        const DONE: u8 = 1;
        const OFF: u8 = 2;
        let n = self.len();
        if let Some(mask) = active {
            // The same binding as the solver's: one entry per vertex slot.
            self.binding
                .check_same(&mask.binding(), "the active mask")?;
        }
        for source in sources {
            if source.vertex >= n {
                return Err(BendelsKleinError::InvalidParameter {
                    name: "source vertex",
                    reason: format!("index {} is outside the {n} vertex slots", source.vertex),
                });
            }
            if source.distance.is_nan() || source.radius.is_nan() {
                return Err(BendelsKleinError::InvalidParameter {
                    name: "source",
                    reason: format!("{source:?} has a NaN start value or radius"),
                });
            }
        }
        let mut t = vec![f64::INFINITY; n];
        let mut radius = vec![f64::INFINITY; n];
        let mut state: Vec<u8> = match active {
            Some(mask) => mask.iter().map(|&a| if a { FAR } else { OFF }).collect(),
            None => vec![FAR; n],
        };
        if let Some(region) = &self.region {
            for (s, &inside) in state.iter_mut().zip(region) {
                if !inside {
                    *s = OFF;
                }
            }
        }
        let mut heap: BinaryHeap<Reverse<(u64, u32)>> = BinaryHeap::with_capacity(1024);
        for source in sources {
            let i = source.vertex;
            if self.region.as_ref().is_some_and(|region| !region[i]) {
                continue;
            }
            state[i] = FAR;
            let value = source.distance.max(0.0);
            if value < t[i] || (value == t[i] && source.radius < radius[i]) {
                t[i] = value;
                radius[i] = source.radius.max(0.0);
                heap.push(Reverse((value.to_bits(), i as u32)));
            }
        }
        let planar_only = self.update == FastMarchingUpdate::KimmelSethian;
        while let Some(Reverse((bits, x))) = heap.pop() {
            let x = x as usize;
            if state[x] == DONE || bits != t[x].to_bits() {
                continue;
            }
            state[x] = DONE;
            let tx = t[x];
            let (lo, hi) = (
                self.dependent_start[x] as usize,
                self.dependent_start[x + 1] as usize,
            );
            for k in lo..hi {
                let y = self.dependents[k] as usize;
                if state[y] != FAR {
                    continue;
                }
                let mut best = t[y];
                let mut best_radius = radius[y];
                let along_edge = tx + self.dependent_lengths[k];
                if along_edge < best {
                    best = along_edge;
                    best_radius = radius[x];
                }
                let (s0, s1) = (
                    self.stencil_start[y] as usize,
                    self.stencil_start[y + 1] as usize,
                );
                for s in &self.stencils[s0..s1] {
                    let other = if s.a as usize == x {
                        s.b
                    } else if s.b as usize == x {
                        s.a
                    } else {
                        continue;
                    } as usize;
                    if state[other] != DONE {
                        continue;
                    }
                    let (a, b) = (s.a as usize, s.b as usize);
                    let r = if planar_only {
                        f64::INFINITY
                    } else {
                        0.5 * (radius[a] + radius[b])
                    };
                    let value = if r.is_finite() && r < 1e6 * (s.la + s.lb) {
                        virtual_source(s, t[a], t[b], r)
                    } else {
                        kimmel_sethian(s, t[a], t[b])
                    };
                    if let Some(value) = value {
                        if value < best {
                            best = value;
                            best_radius = r;
                        }
                    }
                }
                if best < t[y] {
                    t[y] = best;
                    radius[y] = best_radius;
                    heap.push(Reverse((best.to_bits(), y as u32)));
                }
            }
        }
        Ok((
            VertexData::with_binding(t, self.binding),
            VertexData::with_binding(radius, self.binding),
        ))
    }

    /// [`FastMarching::distances`] from isolated point sources at distance 0.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when the solver was made for another mesh (or this one
    /// before a change of connectivity); [`halfedge::Error::InvalidHandle`] (as `BendelsKleinError::Mesh`) for a source that
    /// is not a live vertex of `mesh`; as [`FastMarching::distances`].
    pub fn distances_from_points(
        &self,
        mesh: &Mesh,
        sources: &[VertexId],
        active: Option<&VertexData<bool>>,
    ) -> Result<VertexData<f64>> {
        self.binding.check(mesh, "the fast-marching solver")?;
        let sources = live_sources(mesh, sources, MarchSource::point)?;
        self.distances(&sources, active)
    }

    /// [`FastMarching::distances`] from the vertices of a curve (a region border) at
    /// distance 0.
    ///
    /// # Errors
    /// As [`FastMarching::distances_from_points`].
    pub fn distances_from_curve(
        &self,
        mesh: &Mesh,
        sources: &[VertexId],
        active: Option<&VertexData<bool>>,
    ) -> Result<VertexData<f64>> {
        self.binding.check(mesh, "the fast-marching solver")?;
        let sources = live_sources(mesh, sources, MarchSource::on_curve)?;
        self.distances(&sources, active)
    }
}

/// Sources at the given vertices, which must be live vertices of `mesh`.
fn live_sources(
    mesh: &Mesh,
    vertices: &[VertexId],
    source: fn(usize) -> MarchSource,
) -> Result<Vec<MarchSource>> {
    vertices
        .iter()
        .map(|&v| {
            mesh.ensure_vertex(v)?;
            Ok(source(mesh.vertex_index(v)))
        })
        .collect()
}

/// Planar-wavefront update; `None` when not causal.
#[inline]
fn kimmel_sethian(s: &Stencil, ta: f64, tb: f64) -> Option<f64> {
    let (la2, lb2) = (s.la * s.la, s.lb * s.lb);
    let det = la2 * lb2 - s.dab * s.dab;
    if det <= 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let (qaa, qab, qbb) = (lb2 * inv, -s.dab * inv, la2 * inv);
    let alpha = qaa + 2.0 * qab + qbb;
    let beta = (qaa + qab) * ta + (qab + qbb) * tb;
    let gamma = qaa * ta * ta + 2.0 * qab * ta * tb + qbb * tb * tb - 1.0;
    let disc = beta * beta - alpha * gamma;
    if disc < 0.0 {
        return None;
    }
    let t = (beta + disc.sqrt()) / alpha;
    let (da, db) = (ta - t, tb - t);
    let mu_a = -(qaa * da + qab * db);
    let mu_b = -(qab * da + qbb * db);
    (mu_a >= 0.0 && mu_b >= 0.0 && t >= ta.max(tb)).then_some(t)
}

/// Virtual source update with source radius `r`; `None` when the
/// ray from the centre misses the edge or the circles do not meet.
#[inline]
fn virtual_source(s: &Stencil, ta: f64, tb: f64, r: f64) -> Option<f64> {
    let (ta, tb) = (ta + r, tb + r);
    let a = DVec2::new(s.la, 0.0);
    let bx = s.dab / s.la;
    let b = DVec2::new(bx, (s.lb * s.lb - bx * bx).max(0.0).sqrt());
    let e = b - a;
    let l = e.length();
    if l == 0.0 {
        return None;
    }
    let u = e / l;
    let x = (ta * ta - tb * tb + l * l) / (2.0 * l);
    let h2 = ta * ta - x * x;
    if h2 < 0.0 {
        return None;
    }
    // The vertex y sits at the origin, left of a → b; the source lies to the right.
    let source = a + u * x + DVec2::new(u.y, -u.x) * h2.sqrt();
    let cross_ab = a.perp_dot(b);
    if cross_ab <= 0.0 {
        return None;
    }
    let sa = source.perp_dot(b) / cross_ab;
    let sb = a.perp_dot(source) / cross_ab;
    let t = source.length();
    (sa >= 0.0 && sb >= 0.0 && t >= ta.max(tb)).then_some(t - r)
}

/// Stencils of vertex `y`: one per incident triangle, or two virtual ones for an obtuse
/// corner whose section was reached by unfolding.
fn vertex_stencils(mesh: &Mesh, y: VertexId, chunk: &mut Chunk) {
    let yi = mesh.vertex_index(y) as u32;
    let py = mesh.position(y);
    for h in mesh.outgoing_halfedges(y) {
        let to = mesh.to_vertex(h);
        chunk.neighbours.push(mesh.vertex_index(to) as u32);
        chunk.lengths.push(py.distance(mesh.position(to)));
        if mesh.is_boundary_halfedge(h) {
            continue;
        }
        // Triangle (y, a, b), counter-clockwise: h = y → a, next(h) = a → b.
        let hab = mesh.next(h);
        let (a, b) = (mesh.to_vertex(h), mesh.to_vertex(hab));
        let (ea, eb) = (mesh.position(a) - py, mesh.position(b) - py);
        let (la, lb) = (ea.length(), eb.length());
        let dab = ea.dot(eb);
        let (ai, bi) = (mesh.vertex_index(a) as u32, mesh.vertex_index(b) as u32);
        if dab >= 0.0 || la == 0.0 || lb == 0.0 {
            chunk.stencils.push(Stencil {
                a: ai,
                b: bi,
                la,
                lb,
                dab,
            });
            continue;
        }
        // Obtuse at y: unfold across a → b until a vertex lands in the acute section.
        let a2 = DVec2::new(la, 0.0);
        let bx = dab / la;
        let b2 = DVec2::new(bx, (lb * lb - bx * bx).max(0.0).sqrt());
        match unfold_to_section(mesh, yi, hab, (ai, a2), (bi, b2)) {
            Some((di, d2)) => {
                chunk.unfolded += 1;
                let ld = d2.length();
                chunk.stencils.push(Stencil {
                    a: ai,
                    b: di,
                    la,
                    lb: ld,
                    dab: a2.dot(d2),
                });
                chunk.stencils.push(Stencil {
                    a: di,
                    b: bi,
                    la: ld,
                    lb,
                    dab: d2.dot(b2),
                });
                // The obtuse triangle itself stays too: its update is exact whenever it
                // is causal, which matters when d is accepted after y.
                chunk.stencils.push(Stencil {
                    a: ai,
                    b: bi,
                    la,
                    lb,
                    dab,
                });
                chunk.virtual_pairs.push((di, yi));
            }
            None => {
                chunk.kept += 1;
                chunk.stencils.push(Stencil {
                    a: ai,
                    b: bi,
                    la,
                    lb,
                    dab,
                });
            }
        }
    }
}

/// Walks the strip of triangles beyond the edge `left → right` (halfedge `h`, whose face
/// holds `y`), unfolded into the plane of `y`'s triangle, until a vertex falls in the
/// acute section of the corner at `y` (origin) between `a2` and `b2`.
fn unfold_to_section(
    mesh: &Mesh,
    y: u32,
    mut h: HalfedgeId,
    (mut left, mut left2): (u32, DVec2),
    (mut right, mut right2): (u32, DVec2),
) -> Option<(u32, DVec2)> {
    let (a2, b2) = (left2, right2);
    let theta_b = a2.perp_dot(b2).atan2(a2.dot(b2));
    let section = (
        theta_b - std::f64::consts::FRAC_PI_2,
        std::f64::consts::FRAC_PI_2,
    );
    for _ in 0..MAX_UNFOLD {
        let o = mesh.opposite(h);
        if mesh.is_boundary_halfedge(o) {
            return None;
        }
        // Triangle (right, left, r): o = right → left, next(o) = left → r, prev(o) = r → right.
        let to_r = mesh.next(o);
        let from_r = mesh.prev(o);
        let r = mesh.vertex_index(mesh.to_vertex(to_r)) as u32;
        if r == y || r == left || r == right {
            return None;
        }
        let (l_left, l_right) = (mesh.edge_length(to_r), mesh.edge_length(from_r));
        let e = right2 - left2;
        let l = e.length();
        if l == 0.0 {
            return None;
        }
        let u = e / l;
        let x = (l_left * l_left - l_right * l_right + l * l) / (2.0 * l);
        let hh = (l_left * l_left - x * x).max(0.0).sqrt();
        // Right of left → right, away from the previous triangle.
        let r2 = left2 + u * x + DVec2::new(u.y, -u.x) * hh;
        // Angle of r from the direction of a; the section is [θ_b − π/2, π/2].
        let angle = a2.perp_dot(r2).atan2(a2.dot(r2));
        if angle >= section.0 && angle <= section.1 {
            return Some((r, r2));
        }
        if angle < section.0 {
            // The section lies between r and right: cross r → right.
            h = from_r;
            left = r;
            left2 = r2;
        } else {
            // Cross left → r.
            h = to_r;
            right = r;
            right2 = r2;
        }
    }
    None
}

/// Great-circle helper for tests and benches: the angle between two unit vectors.
///
/// Paper: the reference for the fast-marching distances of Kimmel & Sethian 1998,
/// *Computing geodesic paths on manifolds*.
#[doc(hidden)]
#[must_use]
pub fn sphere_distance(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    #[test]
    fn line_source_on_a_planar_grid_is_exact() {
        let mesh = generators::grid(40, 30, 4.0, 3.0);
        let fm = FastMarching::new(&mesh);
        let sources: Vec<VertexId> = mesh
            .vertices()
            .filter(|&v| mesh.position(v).x == 0.0)
            .collect();
        let d = fm.distances_from_curve(&mesh, &sources, None).unwrap();
        for v in mesh.vertices() {
            let x = mesh.position(v).x;
            assert!((d[mesh.vertex_index(v)] - x).abs() < 1e-12, "{x}");
        }
    }

    #[test]
    fn active_mask_limits_the_march() {
        let mesh = generators::grid(10, 10, 1.0, 1.0);
        let fm = FastMarching::new(&mesh);
        let active = VertexData::from_fn(&mesh, false, |v| mesh.position(v).x <= 0.5);
        let source = mesh.vertices().next().unwrap();
        let d = fm
            .distances_from_points(&mesh, &[source], Some(&active))
            .unwrap();
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            assert_eq!(d[i].is_finite(), active[i]);
        }
    }

    /// A solver made within a region marches as the whole mesh's does, bit for bit, for
    /// point and curve sources in it (on a jittered grid with obtuse corners, so that
    /// unfolded stencils and their virtual dependents are in play), and reaches nothing
    /// outside it.
    #[test]
    fn a_solver_within_the_region_marches_as_the_whole_meshs() {
        let mut mesh = generators::grid(24, 18, 4.0, 3.0);
        let vertices: Vec<VertexId> = mesh.vertices().collect();
        for (k, &v) in vertices.iter().enumerate() {
            // Deterministic jitter, up to 0.4 of a cell.
            let a = ((k * 7919) % 101) as f64 / 101.0 - 0.5;
            let b = ((k * 104_729) % 103) as f64 / 103.0 - 0.5;
            let p = mesh.position(v);
            mesh.set_position(v, p + DVec3::new(0.07 * a, 0.07 * b, 0.05 * a * b));
        }
        let centre = DVec3::new(2.0, 1.5, 0.0);
        let region = VertexData::from_fn(&mesh, false, |v| {
            mesh.position(v).truncate().distance(centre.truncate()) < 1.1
        });
        let whole = FastMarching::new(&mesh);
        let within = FastMarching::within(&mesh, &region).unwrap();
        assert!(whole.obtuse_corners().0 > within.obtuse_corners().0);
        assert!(
            within.obtuse_corners().0 > 0,
            "no unfolded corner in the region"
        );
        let inside: Vec<usize> = (0..region.len()).filter(|&i| region[i]).collect();
        let point = [MarchSource::point(inside[inside.len() / 2])];
        let curve: Vec<MarchSource> = inside[..5]
            .iter()
            .map(|&i| MarchSource::on_curve(i))
            .collect();
        for sources in [&point[..], &curve[..]] {
            let (d0, r0) = whole.distances_and_radii(sources, Some(&region)).unwrap();
            let (d1, r1) = within.distances_and_radii(sources, Some(&region)).unwrap();
            for i in 0..region.len() {
                assert_eq!(d0[i].to_bits(), d1[i].to_bits(), "distance of vertex {i}");
                assert_eq!(r0[i].to_bits(), r1[i].to_bits(), "radius of vertex {i}");
            }
            assert!(inside.iter().all(|&i| d1[i].is_finite()));
            let (everywhere, _) = within.distances_and_radii(sources, None).unwrap();
            for i in 0..region.len() {
                assert_eq!(everywhere[i].is_finite(), region[i], "vertex {i}");
            }
            let outside = (0..region.len()).find(|&i| !region[i]).unwrap();
            let (from_outside, _) = within
                .distances_and_radii(&[MarchSource::point(outside)], None)
                .unwrap();
            assert!(from_outside.iter().all(|d| d.is_infinite()));
        }
    }
}
