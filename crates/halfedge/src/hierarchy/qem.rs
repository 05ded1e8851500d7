//! Quadric error priority decimation (Garland & Heckbert 1997, "Surface Simplification
//! Using Quadric Error Metrics"), writing the same collapse records as the rounds.
//!
//! - Every vertex carries the sum of the plane quadrics of its faces, each weighted by the
//!   face's area. Boundaries are kept by **constraint planes**: every boundary edge adds,
//!   to both its endpoints, the plane through the edge perpendicular to its face, weighted
//!   by [`boundary_weight`](super::HierarchyOptions::boundary_weight) × the squared edge
//!   length; besides, a boundary vertex only moves along boundary edges and an interior
//!   edge touching the boundary collapses onto its boundary vertex (module
//!   `legality`).
//! - The survivor goes to the quadric's minimiser (solving the 3×3 system) when the system
//!   is well conditioned and the minimiser lies within one edge length of the edge's
//!   midpoint; when there is no such minimiser, or it would flip or flatten a face, to
//!   the better legal one of `p0` and `p1` (candidates in order of cost). The midpoint
//!   is no candidate: where the quadric is singular (a flat region, a crease) it costs
//!   no more than an endpoint and moved vertices off the input along it (the rounds
//!   placed by the quadric are 11–33 % nearer the input without it; QEM's own results
//!   hardly change, see `benches/README.md`).
//! - Edges wait in a heap keyed by their cost (module `heap`) with *lazy
//!   versioning*: every edge has one entry; a collapse marks the entries of the edges
//!   around the survivor stale instead of re-queuing them, and a stale entry that reaches
//!   the top is re-evaluated and re-queued unless it is still the cheapest. This is exact
//!   because quadrics only accumulate, so an edge's cost never drops. An edge costs
//!   what its cheapest *legal* place costs: when cheaper places would flip or flatten a
//!   face, it goes back into the heap with that cost unless it is still the cheapest
//!   (collapsing it at the cheaper place's turn cut borders' corners and concave
//!   creases: a CAD part's Hausdorff distance to the input was 100 × larger). Legality
//!   (OpenMesh's topological rules, no normal flip, no degenerate face, the error bound)
//!   is checked when an edge is popped; an illegal edge is *parked* out of the heap and
//!   comes back when a collapse happens at one of its endpoints or their neighbours.
//! - The error of a collapse is `sqrt(cost / area)`, the area-weighted root mean square
//!   distance of the new position to the planes gathered in the quadric; collapses above
//!   [`max_error`](super::HierarchyOptions::max_error) are parked like illegal ones.
//! - Levels are cut whenever the face count drops to
//!   [`level_ratio`](super::HierarchyOptions::level_ratio) of the previous level's, so
//!   that levels remove about as much as a round does.

use std::ops::ControlFlow;

use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;

use super::heap::{self, Queue};
use super::legality::{self, Collapse, NewNormals, Star};
use super::options::report;
use super::{BuildProgress, Hierarchy, HierarchyOptions};
use crate::error::Result;
use crate::handle::NONE;
use crate::iter::vertex_walk;
use crate::mesh::Mesh;

/// A symmetric 4×4 quadric `Σ w (n·x + d)²` and the total face area it gathered.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric {
    /// Upper triangle: xx xy xz xd yy yz yd zz zd dd.
    m: [f64; 10],
    /// Total face area gathered (boundary constraint planes not included).
    area: f64,
}

impl std::ops::Add for Quadric {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        let mut m = self.m;
        for (a, b) in m.iter_mut().zip(o.m) {
            *a += b;
        }
        Self {
            m,
            area: self.area + o.area,
        }
    }
}

impl std::ops::AddAssign for Quadric {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Quadric {
    /// `w (n·x + d)²` for the plane `n·x + d = 0`; `area` is what the plane counts for in
    /// the error normalisation.
    #[inline]
    pub fn plane(n: DVec3, d: f64, w: f64, area: f64) -> Self {
        let (a, b, c) = (n.x, n.y, n.z);
        Self {
            m: [
                w * a * a,
                w * a * b,
                w * a * c,
                w * a * d,
                w * b * b,
                w * b * c,
                w * b * d,
                w * c * c,
                w * c * d,
                w * d * d,
            ],
            area,
        }
    }

    /// The quadric's value at `p`.
    #[inline]
    pub fn eval(&self, p: DVec3) -> f64 {
        let m = &self.m;
        let (x, y, z) = (p.x, p.y, p.z);
        x * (m[0] * x + 2.0 * (m[1] * y + m[2] * z + m[3]))
            + y * (m[4] * y + 2.0 * (m[5] * z + m[6]))
            + z * (m[7] * z + 2.0 * m[8])
            + m[9]
    }

    /// The minimiser of the quadric when its 3×3 part is well conditioned.
    #[inline]
    pub fn minimizer(&self) -> Option<DVec3> {
        let m = &self.m;
        let a = DMat3::from_cols(
            DVec3::new(m[0], m[1], m[2]),
            DVec3::new(m[1], m[4], m[5]),
            DVec3::new(m[2], m[5], m[7]),
        );
        let det = a.determinant();
        let trace = m[0] + m[4] + m[7];
        if det.is_nan() || det.abs() <= 1e-9 * (trace / 3.0).powi(3) {
            return None;
        }
        let p = a.inverse() * -DVec3::new(m[3], m[6], m[8]);
        p.is_finite().then_some(p)
    }

    /// The error at `p`: root mean square distance to the gathered planes.
    #[inline]
    pub fn error(&self, p: DVec3) -> f64 {
        (self.eval(p).max(0.0) / self.area.max(f64::MIN_POSITIVE)).sqrt()
    }
}

/// Unit normal and area of every face, by face index (zero for removed or degenerate
/// faces), in parallel.
pub fn face_planes(mesh: &Mesh) -> Vec<(DVec3, f64)> {
    let mut planes = vec![(DVec3::ZERO, 0.0); mesh.face_slots()];
    let (he, positions) = (&mesh.he[..], &mesh.positions[..]);
    mesh.face_slots_.par_for_each_live(&mut planes, |i, plane| {
        let r0 = &he[mesh.face_conn[i] as usize];
        let r1 = &he[r0.next as usize];
        let r2 = &he[r1.next as usize];
        let [a, b, c] = [r0.to, r1.to, r2.to].map(|v| positions[v as usize]);
        let cross = (b - a).cross(c - a);
        let len = cross.length();
        if len > 0.0 {
            *plane = (cross / len, 0.5 * len);
        }
    });
    planes
}

/// Per-vertex quadrics of `mesh`, by vertex index (see the module docs), from the face
/// planes of [`face_planes`].
pub fn vertex_quadrics(mesh: &Mesh, planes: &[(DVec3, f64)], boundary_weight: f64) -> Vec<Quadric> {
    let mut quadrics = vec![Quadric::default(); mesh.vertex_slots()];
    let (he, positions) = (&mesh.he[..], &mesh.positions[..]);
    mesh.vertex_slots_.par_for_each_live(&mut quadrics, |i, q| {
        // The ring 16 vertices on starts where (see `crate::prefetch`).
        if let Some(&h) = mesh.vertex_conn.get(i + 16) {
            crate::prefetch::prefetch(he, h as usize);
        }
        let pv = positions[i];
        let mut acc = Quadric::default();
        for (k, r) in vertex_walk(he, mesh.vertex_conn[i]) {
            if r.face != NONE {
                let (n, area) = planes[r.face as usize];
                if area > 0.0 {
                    acc += Quadric::plane(n, -n.dot(pv), area, area);
                }
            }
            // Boundary constraint plane of the edge of `k`, if it is on the boundary.
            let fo = he[(k ^ 1) as usize].face;
            let face_side = match (r.face, fo) {
                (NONE, NONE) => None,
                (f, NONE) | (NONE, f) => Some(f),
                _ => None,
            };
            if let (Some(f), true) = (face_side, boundary_weight > 0.0) {
                let e = positions[r.to as usize] - pv;
                let m = e.cross(planes[f as usize].0);
                if let Some(m) = m.try_normalize() {
                    let w = boundary_weight * e.length_squared();
                    acc += Quadric::plane(m, -m.dot(pv), w, 0.0);
                }
            }
        }
        *q = acc;
    });
    quadrics
}

/// Candidate survivor positions of an edge with their quadric costs (in the order of
/// [`candidates`] until [`sort`](Self::sort)ed).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidates {
    items: [(f64, DVec3); 3],
    len: usize,
}

impl Candidates {
    #[inline]
    pub(crate) fn as_slice(&self) -> &[(f64, DVec3)] {
        &self.items[..self.len]
    }
    /// The cheapest cost (costs are never NaN).
    #[inline]
    fn cost(&self) -> f64 {
        self.as_slice()
            .iter()
            .fold(f64::INFINITY, |m, &(c, _)| m.min(c))
    }
    /// Orders the candidates cheapest first, ties in their first order (what the
    /// collapse tries them in; the heap only needs [`cost`](Self::cost)).
    #[inline]
    pub(crate) fn sort(&mut self) {
        self.items[..self.len].sort_by(|x, y| x.0.total_cmp(&y.0));
    }
}

/// True when vertex slot `v` is on the boundary or isolated
/// ([`Mesh::is_boundary_vertex`] on a slot index).
#[inline]
fn is_boundary_vertex(mesh: &Mesh, v: u32) -> bool {
    match mesh.vertex_conn[v as usize] {
        NONE => true,
        h => mesh.he[h as usize].face == NONE,
    }
}

/// The summed quadric of the edge of halfedge slot `e` and its candidate survivor
/// positions (unsorted, see [`Candidates::sort`]): the quadric's minimiser (when well
/// conditioned and within one edge length of the midpoint) and both endpoints (no
/// midpoint: see the module docs); only the boundary vertex's position when the edge is
/// interior and exactly one endpoint is on the boundary (the boundary rule of
/// `legality`).
#[inline]
pub(crate) fn candidates(mesh: &Mesh, quadrics: &[Quadric], e: u32) -> (Quadric, Candidates) {
    let (r, ro) = (&mesh.he[e as usize], &mesh.he[(e ^ 1) as usize]);
    let (a, b) = (ro.to, r.to);
    let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
    let q = quadrics[a as usize] + quadrics[b as usize];
    let boundary_edge = r.face == NONE || ro.face == NONE;
    let (ba, bb) = (is_boundary_vertex(mesh, a), is_boundary_vertex(mesh, b));
    let mut c = Candidates {
        items: [(0.0, DVec3::ZERO); 3],
        len: 0,
    };
    let mut add = |p: DVec3| {
        c.items[c.len] = (q.eval(p).max(0.0), p);
        c.len += 1;
    };
    if !boundary_edge && ba != bb {
        add(if ba { pa } else { pb });
        return (q, c);
    }
    let mid = 0.5 * (pa + pb);
    if let Some(p) = q.minimizer() {
        if (p - mid).length_squared() <= (pa - pb).length_squared() {
            add(p);
        }
    }
    add(pa);
    add(pb);
    (q, c)
}

/// The parameter of `p` along the edge from `p1` (0) to `p0` (1), as a record keeps it
/// with its placement (`0.5` for an edge of length zero).
#[inline]
pub(crate) fn parameter_along(p0: DVec3, p1: DVec3, p: DVec3) -> f64 {
    let d = p0 - p1;
    if d.length_squared() > 0.0 {
        (p - p1).dot(d) / d.length_squared()
    } else {
        0.5
    }
}

/// The heap cost of the edge of halfedge slot `e`: its cheapest candidate's.
#[inline]
fn edge_cost(mesh: &Mesh, quadrics: &[Quadric], e: u32) -> f64 {
    candidates(mesh, quadrics, e).1.cost()
}

/// Puts `edge` back into the queue at `cost` unless that is still the cheapest of the
/// queue's live keys; true when it went back (its turn comes later).
#[inline]
fn requeued(heap: &mut Queue, state: &EdgeStates, cost: f64, edge: usize) -> bool {
    let key = heap::pack(cost, edge as u32);
    let live = |k| state.get(heap::unpack(k).1 as usize) != DEAD;
    if heap.peek(live).is_some_and(|top| top < key) {
        heap.push(key);
        true
    } else {
        false
    }
}

/// Builds the levels of `h` by QEM decimation until a stop criterion holds.
pub(crate) fn build(
    h: &mut Hierarchy,
    options: &HierarchyOptions,
    progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
) -> Result<()> {
    let input_faces = h.mesh.n_faces();
    let cos_flip = options.max_flip_angle.cos();
    let labels = h.label_constraint(options);
    let planes = face_planes(&h.mesh);
    let mut quadrics = vertex_quadrics(&h.mesh, &planes, options.boundary_weight);
    let mut normals: Vec<glam::Vec3> = planes.into_iter().map(|(n, _)| n.as_vec3()).collect();
    let slots = h.mesh.halfedge_slots();
    // Every edge (by its smaller halfedge index) has at most one heap entry; its state
    // says whether that entry's cost is current, stale, or the edge is parked (illegal,
    // out of the heap until its neighbourhood changes).
    let mut state = EdgeStates::new(slots);
    // Vertices that may have parked edges around them.
    let mut parked_near = Bits::new(h.mesh.vertex_slots());
    // One key per live edge, by its even halfedge.
    let keys: Vec<u64> = {
        let mesh = &h.mesh;
        let quadrics = &quadrics;
        (0..slots / 2)
            .into_par_iter()
            .map(|j| 2 * j as u32)
            .filter(|&e| mesh.halfedge_slots_.is_live_index(e as usize))
            .map(|e| {
                prefetch_ends(mesh, quadrics, e as usize + 32);
                prefetch_ring_starts(mesh, e as usize + 16);
                heap::pack(edge_cost(mesh, quadrics, e), e)
            })
            .collect()
    };
    let mut heap = Queue::new(keys, AHEAD);
    // The output buffers' memory is written on another thread while the (sequential)
    // decimation runs; each collapse removes two faces of a closed mesh.
    let mut prefaulting = h.prefault(input_faces.saturating_sub(options.target_faces) / 2);
    let mut next_level = level_target(input_faces, options.level_ratio);
    let mut since_report = 0usize;
    let mut new_normals = NewNormals::new();
    let mut star = Star::new();
    // Keys of dead edges are dropped as they come out of the heap, before the lookahead.
    while let Some(key) = heap.pop(|k| state.get(heap::unpack(k).1 as usize) != DEAD) {
        if h.mesh.n_faces() <= options.target_faces || h.built_levels() >= options.max_levels {
            break;
        }
        prefetch_ahead(&h.mesh, &quadrics, &state, &normals, &heap);
        let edge = heap::unpack(key).1 as usize;
        if state.get(edge) == DEAD {
            continue;
        }
        let (g, p, t, q) = {
            let mesh = &h.mesh;
            // Edges die only by collapses, which mark them DEAD: this one is live.
            debug_assert!(mesh.halfedge_at(edge).is_some());
            let e = mesh.hh(edge as u32);
            // A stale edge's cost first (most go back into the heap); a clean one's
            // candidates once it is topologically legal.
            let mut computed = None;
            if state.get(edge) == STALE {
                let (q, cands) = candidates(mesh, &quadrics, edge as u32);
                computed = Some((q, cands));
                // Costs only grow as quadrics accumulate: re-queue with the current cost
                // unless it is still the cheapest.
                state.set(edge, CLEAN);
                if requeued(&mut heap, &state, cands.cost(), edge) {
                    continue;
                }
            }
            let park = |state: &mut EdgeStates, parked_near: &mut Bits| {
                state.set(edge, PARKED);
                parked_near.insert(mesh.vertex_index(mesh.from_vertex(e)));
                parked_near.insert(mesh.vertex_index(mesh.to_vertex(e)));
            };
            let Some((g, _)) = legality::choose_direction_ix(mesh, edge as u32, &labels) else {
                park(&mut state, &mut parked_near);
                continue;
            };
            prefetch_collapse(mesh, g);
            let (q, mut cands) =
                computed.unwrap_or_else(|| candidates(mesh, &quadrics, edge as u32));
            cands.sort();
            let g = mesh.hh(g);
            let c = Collapse::new(mesh, g);
            // The cheapest candidate that is within the error bound and legal (the star
            // gathered once for all candidates).
            let gathered = star.gather(mesh, &c, &normals);
            let chosen = cands.as_slice().iter().find(|&&(_, p)| {
                !(options.max_error.is_finite() && q.error(p) > options.max_error)
                    && if gathered {
                        star.geometry(mesh, p, &normals, cos_flip, &mut new_normals)
                    } else {
                        legality::geometry(mesh, &c, p, &normals, cos_flip, &mut new_normals)
                    }
            });
            let Some(&(cost, p)) = chosen else {
                park(&mut state, &mut parked_near);
                continue;
            };
            // Cheaper candidates were illegal: the edge costs what this one costs, and
            // waits in the heap for its turn unless it is still the cheapest.
            if cost > cands.cost() && requeued(&mut heap, &state, cost, edge) {
                continue;
            }
            let t = parameter_along(mesh.position(c.v0), mesh.position(c.v1), p);
            (g, p, t, q)
        };
        let v0 = h.mesh.from_vertex(g);
        let v1 = h.mesh.to_vertex(g);
        h.record_collapse(g, p, t);
        let mesh = &h.mesh;
        // The collapse removed v0v1 and, with the faces, vl–v0 and v0–vr.
        if let Some(record) = h.records.last() {
            for x in mesh.sides(record.v0v1).removed(record.v0v1) {
                state.set((x & !1) as usize, DEAD);
            }
        }
        let (i0, i1) = (mesh.vertex_index(v0), mesh.vertex_index(v1));
        quadrics[i1] = q;
        if parked_near.contains(i0) {
            parked_near.insert(i1);
        }
        new_normals.apply(mesh, v1, &mut normals);
        // Edges around v1 changed cost; parked edges around v1 and its neighbours may
        // have become legal. (An edge is known by its even halfedge, `k & !1`.)
        for (k, r) in vertex_walk(&mesh.he, mesh.vertex_conn[i1]) {
            let edge = (k & !1) as usize;
            match state.get(edge) {
                CLEAN => state.set(edge, STALE),
                PARKED => unpark(mesh, &quadrics, k, edge, &mut state, &mut heap),
                _ => {}
            }
            if parked_near.take(r.to as usize) {
                for (kw, _) in vertex_walk(&mesh.he, mesh.vertex_conn[r.to as usize]) {
                    let ew = (kw & !1) as usize;
                    if state.get(ew) == PARKED {
                        unpark(mesh, &quadrics, kw, ew, &mut state, &mut heap);
                    }
                }
            }
        }
        parked_near.take(i1);
        if mesh.n_faces() <= next_level {
            h.close_level();
            next_level = level_target(h.mesh.n_faces(), options.level_ratio);
            report(h.built_levels(), h.mesh.n_faces(), input_faces, progress)?;
        }
        since_report += 1;
        if since_report % 1024 == 0 && prefaulting.as_ref().is_some_and(|t| t.is_finished()) {
            if let Some(Ok(buffers)) = prefaulting.take().map(std::thread::JoinHandle::join) {
                h.adopt_prefaulted(buffers);
            }
        }
        if since_report == 1 << 16 {
            since_report = 0;
            report(h.built_levels(), h.mesh.n_faces(), input_faces, progress)?;
        }
    }
    if h.built_levels() < options.max_levels {
        h.close_level();
    }
    h.details.shrink_to_fit();
    Ok(())
}

/// How many pops ahead the decimation knows its next edges (see [`prefetch_ahead`]).
const AHEAD: usize = 8;

/// Prefetches what the next pops will touch, in stages a few pops apart, each reading
/// only what the stage before brought in (see [`crate::prefetch`]): the edge's state
/// and halfedges 7 pops ahead; its endpoints' positions, quadrics and first outgoing
/// halfedges 4 ahead; the records of those and of the two opposite corners' halfedges,
/// and the two faces' normals, 2 ahead. (Walking the rings ahead as well, a step per
/// stage, measured no faster.) Keys pushed meanwhile may change the order; prefetching
/// never changes what is computed.
#[inline]
fn prefetch_ahead(
    mesh: &Mesh,
    quadrics: &[Quadric],
    state: &EdgeStates,
    normals: &[Vec3],
    queue: &Queue,
) {
    use crate::prefetch::prefetch;
    let he = &mesh.he[..];
    let edge = |i| queue.upcoming(i).map(|k| heap::unpack(k).1 as usize);
    if let Some(e) = edge(AHEAD - 1) {
        state.prefetch(e);
        prefetch(he, e);
    }
    // The endpoints of a live edge.
    let ends = |e: usize| -> Option<[usize; 2]> {
        if e >= he.len() || state.get(e) == DEAD {
            return None;
        }
        Some([he.get(e ^ 1)?.to as usize, he.get(e)?.to as usize])
    };
    if let Some(e) = edge(4) {
        if e < mesh.he.len() && state.get(e) != DEAD {
            prefetch_ends(mesh, quadrics, e);
        }
    }
    if let Some(e) = edge(2) {
        if ends(e).is_some() {
            prefetch_ring_starts(mesh, e);
            for h in [e, e ^ 1] {
                let r = &he[h];
                prefetch(he, r.next as usize);
                prefetch(normals, r.face as usize);
            }
        }
    }
}

/// Prefetches what collapsing halfedge slot `h` writes beyond the rings its legality
/// tests walk (see [`crate::prefetch`]): the slot states of the removed elements, the
/// halfedges of the removed faces (which the record's fingerprint reads), the outer
/// neighbours of the removed edges `vl → v0` and `v0 → vr` and their faces'
/// halfedges, the outgoing halfedge of `vr`. Called as soon as the edge is known to be
/// topologically legal, so that the loads overlap the geometric tests.
#[inline]
fn prefetch_collapse(mesh: &Mesh, h: u32) {
    use crate::prefetch::prefetch;
    let s = mesh.sides(h);
    mesh.halfedge_slots_.prefetch_state(h as usize);
    if let Some(r) = mesh.he.get((h ^ 1) as usize) {
        mesh.vertex_slots_.prefetch_state(r.to as usize);
    }
    for f in [s.fl, s.fr] {
        if f != NONE {
            mesh.face_slots_.prefetch_state(f as usize);
            prefetch(&mesh.face_conn, f as usize);
        }
    }
    for x in [s.vlv0, s.v0vr] {
        if x == NONE {
            continue;
        }
        mesh.halfedge_slots_.prefetch_state(x as usize);
        if let Some(r) = mesh.he.get((x ^ 1) as usize) {
            prefetch(&mesh.he, r.prev as usize);
            prefetch(&mesh.he, r.next as usize);
            prefetch(&mesh.face_conn, r.face as usize);
        }
    }
    if s.v0vr != NONE {
        if let Some(r) = mesh.he.get(s.v0vr as usize) {
            prefetch(&mesh.vertex_conn, r.to as usize);
        }
    }
}

/// Prefetches the positions, quadrics and first outgoing halfedges of the endpoints of
/// halfedge slot `e` (nothing if `e` is out of range).
#[inline]
fn prefetch_ends(mesh: &Mesh, quadrics: &[Quadric], e: usize) {
    use crate::prefetch::prefetch;
    let (Some(r), Some(o)) = (mesh.he.get(e), mesh.he.get(e ^ 1)) else {
        return;
    };
    for v in [o.to as usize, r.to as usize] {
        prefetch(&mesh.positions, v);
        prefetch(&mesh.vertex_conn, v);
        if let Some(q) = quadrics.get(v) {
            prefetch(&q.m, 0);
            prefetch(&q.m, 8);
        }
    }
}

/// Prefetches the records of the first outgoing halfedges of the endpoints of halfedge
/// slot `e` (after [`prefetch_ends`] brought in which they are).
#[inline]
fn prefetch_ring_starts(mesh: &Mesh, e: usize) {
    let (Some(r), Some(o)) = (mesh.he.get(e), mesh.he.get(e ^ 1)) else {
        return;
    };
    for v in [o.to as usize, r.to as usize] {
        if let Some(&h) = mesh.vertex_conn.get(v) {
            crate::prefetch::prefetch(&mesh.he, h as usize);
        }
    }
}

/// The [`CLEAN`] / [`STALE`] / [`PARKED`] / [`DEAD`] state of every edge, two bits an
/// edge, addressed by either of its halfedge slots: 0.6 MB for a 1.6 M-face mesh, so the
/// states stay in the second-level cache while the decimation reads them around every
/// collapse.
struct EdgeStates(Vec<u64>);

impl EdgeStates {
    /// `CLEAN` edges for `halfedges` halfedge slots.
    fn new(halfedges: usize) -> Self {
        Self(vec![0; halfedges.div_ceil(64)])
    }
    #[inline]
    fn get(&self, h: usize) -> u8 {
        let e = h >> 1;
        (self.0[e / 32] >> (2 * (e % 32)) & 3) as u8
    }
    #[inline]
    fn set(&mut self, h: usize, state: u8) {
        let e = h >> 1;
        let word = &mut self.0[e / 32];
        let shift = 2 * (e % 32);
        *word = (*word & !(3 << shift)) | (u64::from(state) << shift);
    }
    #[inline]
    fn prefetch(&self, h: usize) {
        crate::prefetch::prefetch(&self.0, (h >> 1) / 32);
    }
}

/// A set of vertex slots, a bit each.
struct Bits(Vec<u64>);

impl Bits {
    fn new(n: usize) -> Self {
        Self(vec![0; n.div_ceil(64)])
    }
    #[inline]
    fn contains(&self, i: usize) -> bool {
        self.0[i / 64] >> (i % 64) & 1 != 0
    }
    #[inline]
    fn insert(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    /// Removes `i`, returning whether it was there.
    #[inline]
    fn take(&mut self, i: usize) -> bool {
        let was = self.contains(i);
        self.0[i / 64] &= !(1 << (i % 64));
        was
    }
}

/// Edge states: in the heap with its current cost, in the heap with a stale (lower)
/// cost, out of the heap because it was illegal, removed.
const CLEAN: u8 = 0;
const STALE: u8 = 1;
const PARKED: u8 = 2;
/// Removed by a collapse (its heap entry is skipped without touching the mesh).
const DEAD: u8 = 3;

/// Puts a parked edge back into the heap with its current cost.
#[inline]
fn unpark(
    mesh: &Mesh,
    quadrics: &[Quadric],
    k: u32,
    edge: usize,
    state: &mut EdgeStates,
    heap: &mut Queue,
) {
    heap.push(heap::pack(edge_cost(mesh, quadrics, k), edge as u32));
    state.set(edge, CLEAN);
}

#[inline]
fn level_target(faces: usize, ratio: f64) -> usize {
    (faces as f64 * ratio).floor() as usize
}
