//! Quadric error priority decimation (Garland & Heckbert 1997, "Surface Simplification
//! Using Quadric Error Metrics"), writing the same collapse records as the rounds.
//!
//! - Every vertex carries the sum of the plane quadrics of its faces, each weighted by the
//!   face's area. Boundaries are kept by **constraint planes**: every boundary edge adds,
//!   to both its endpoints, the plane through the edge perpendicular to its face, weighted
//!   by [`boundary_weight`](super::HierarchyOptions::boundary_weight) × the squared edge
//!   length; besides, a boundary vertex only moves along boundary edges and an interior
//!   edge touching the boundary collapses onto its boundary vertex (module
//!   [`super::legality`]).
//! - The survivor goes to the quadric's minimiser (solving the 3×3 system) when the system
//!   is well conditioned and the minimiser lies within one edge length of the edge's
//!   midpoint; otherwise to the best of `p0`, `p1` and the midpoint.
//! - Edges wait in a binary heap keyed by their cost with *lazy versioning*: a collapse
//!   bumps the version of every edge around the survivor and pushes it again; stale
//!   entries are skipped when popped. Legality (OpenMesh's topological rules, no normal
//!   flip, no degenerate face) is checked when an edge is popped; an illegal edge is
//!   dropped until an edge around it collapses.
//! - The error of a collapse is `sqrt(cost / area)`, the area-weighted root mean square
//!   distance of the new position to the planes gathered in the quadric; collapses above
//!   [`max_error`](super::HierarchyOptions::max_error) are skipped.
//! - Levels are cut whenever the face count drops to
//!   [`level_ratio`](super::HierarchyOptions::level_ratio) of the previous level's, so
//!   that levels remove about as much as a round does.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::legality::{self, Collapse, Placement};
use super::rounds::choose_direction;
use super::{BuildProgress, Hierarchy, HierarchyOptions};
use crate::{HalfedgeId, Mesh, Result};

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
        if !(det.abs() > 1e-9 * (trace / 3.0).powi(3)) {
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

/// A heap entry: cost, edge (smaller halfedge index of the pair), version.
#[derive(Clone, Copy, Debug)]
struct Entry {
    cost: f64,
    edge: u32,
    version: u32,
}
impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    /// Reversed: the cheapest entry is the greatest (`BinaryHeap` is a max-heap); ties
    /// by edge index for a deterministic order.
    fn cmp(&self, o: &Self) -> Ordering {
        o.cost
            .total_cmp(&self.cost)
            .then_with(|| o.edge.cmp(&self.edge))
    }
}

/// Per-vertex quadrics of `mesh`, by vertex index (see the module docs).
pub fn vertex_quadrics(mesh: &Mesh, boundary_weight: f64) -> Vec<Quadric> {
    let mut quadrics = vec![Quadric::default(); mesh.vertex_slots()];
    quadrics.par_iter_mut().enumerate().for_each(|(i, q)| {
        let Some(v) = mesh.vertex_at(i) else { return };
        let pv = mesh.position(v);
        let mut acc = Quadric::default();
        for k in mesh.outgoing_halfedges(v) {
            if let Some(f) = mesh.face(k) {
                let [a, b, c] = mesh.triangle_positions(f);
                let cross = (b - a).cross(c - a);
                let area2 = cross.length();
                if area2 > 0.0 {
                    let n = cross / area2;
                    let area = 0.5 * area2;
                    acc += Quadric::plane(n, -n.dot(pv), area, area);
                }
            }
            // Boundary constraint plane of the edge of `k`, if it is on the boundary.
            let ko = mesh.opposite(k);
            let face_side = match (mesh.face(k), mesh.face(ko)) {
                (Some(f), None) | (None, Some(f)) => Some(f),
                _ => None,
            };
            if let (Some(f), true) = (face_side, boundary_weight > 0.0) {
                let e = mesh.edge_vector(k);
                let m = e.cross(mesh.face_normal(f));
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

/// Cost, survivor position and its parameter `t` (`p ≈ p1 + t (p0 − p1)`) of collapsing
/// the edge of `e`, with the boundary rule of [`super::legality`].
#[inline]
fn evaluate(mesh: &Mesh, quadrics: &[Quadric], e: HalfedgeId) -> (f64, DVec3, f64) {
    let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
    let (pa, pb) = (mesh.position(a), mesh.position(b));
    let q = quadrics[mesh.vertex_index(a)] + quadrics[mesh.vertex_index(b)];
    let boundary_edge = mesh.is_boundary_edge(e);
    let (ba, bb) = (mesh.is_boundary_vertex(a), mesh.is_boundary_vertex(b));
    // t is measured from b towards a; the direction chosen later may swap them.
    let p = if !boundary_edge && ba && !bb {
        pa
    } else if !boundary_edge && bb && !ba {
        pb
    } else {
        let mid = 0.5 * (pa + pb);
        let len2 = (pa - pb).length_squared();
        match q.minimizer() {
            Some(p) if (p - mid).length_squared() <= len2 => p,
            _ => {
                let (ca, cb, cm) = (q.eval(pa), q.eval(pb), q.eval(mid));
                if cm <= ca && cm <= cb {
                    mid
                } else if ca <= cb {
                    pa
                } else {
                    pb
                }
            }
        }
    };
    let d = pa - pb;
    let t = if d.length_squared() > 0.0 {
        (p - pb).dot(d) / d.length_squared()
    } else {
        0.5
    };
    (q.eval(p).max(0.0), p, t)
}

/// Builds the levels of `h` by QEM decimation until a stop criterion holds.
pub(crate) fn build(
    h: &mut Hierarchy,
    options: &HierarchyOptions,
    progress: &mut dyn FnMut(BuildProgress),
) -> Result<()> {
    let input_faces = h.mesh.n_faces();
    let cos_flip = options.max_flip_angle.cos();
    let mut normals = h.mesh.face_normals();
    let mut quadrics = vertex_quadrics(&h.mesh, options.boundary_weight);
    let slots = h.mesh.halfedge_slots();
    let mut version = vec![0u32; slots];
    let entries: Vec<Entry> = {
        let mesh = &h.mesh;
        let quadrics = &quadrics;
        (0..slots)
            .into_par_iter()
            .filter_map(|i| {
                let e = mesh.halfedge_at(i)?;
                if mesh.halfedge_index(mesh.opposite(e)) < i {
                    return None;
                }
                let (cost, _, _) = evaluate(mesh, quadrics, e);
                Some(Entry {
                    cost,
                    edge: i as u32,
                    version: 0,
                })
            })
            .collect()
    };
    let mut heap = BinaryHeap::from(entries);
    let mut next_level = level_target(input_faces, options.level_ratio);
    let mut since_report = 0usize;
    while let Some(entry) = heap.pop() {
        if h.mesh.n_faces() <= options.target_faces || h.built_levels() >= options.max_levels {
            break;
        }
        let edge = entry.edge as usize;
        if version[edge] != entry.version {
            continue;
        }
        let (g, p, t, q) = {
            let mesh = &h.mesh;
            let Some(e) = mesh.halfedge_at(edge) else {
                continue;
            };
            let o = mesh.opposite(e);
            let Some((g, placement)) = choose_direction(mesh, e, o) else {
                continue;
            };
            let c = Collapse::new(mesh, g);
            let (_, p, t_e) = evaluate(mesh, &quadrics, e);
            // evaluate() measured t from to_vertex(e); flip it when collapsing o.
            let t = if g == e { t_e } else { 1.0 - t_e };
            let p = match placement {
                Placement::Free => p,
                Placement::AtV1 => mesh.position(c.v1),
            };
            let q = quadrics[mesh.vertex_index(c.v0)] + quadrics[mesh.vertex_index(c.v1)];
            if options.max_error.is_finite() && q.error(p) > options.max_error {
                continue;
            }
            if !legality::geometry(mesh, &c, p, &normals, cos_flip) {
                continue;
            }
            (g, p, t, q)
        };
        let v1 = h.mesh.to_vertex(g);
        h.record_collapse(g, p, t)?;
        let mesh = &h.mesh;
        quadrics[mesh.vertex_index(v1)] = q;
        legality::update_normals_around(mesh, v1, &mut normals);
        for k in mesh.outgoing_halfedges(v1) {
            let ki = mesh.halfedge_index(k);
            let oi = mesh.halfedge_index(mesh.opposite(k));
            let (edge, e) = if ki < oi { (ki, k) } else { (oi, mesh.opposite(k)) };
            version[edge] = version[edge].wrapping_add(1);
            let (cost, _, _) = evaluate(mesh, &quadrics, e);
            heap.push(Entry {
                cost,
                edge: edge as u32,
                version: version[edge],
            });
        }
        if mesh.n_faces() <= next_level {
            h.close_level();
            next_level = level_target(h.mesh.n_faces(), options.level_ratio);
            progress(BuildProgress {
                levels: h.built_levels(),
                faces: h.mesh.n_faces(),
                input_faces,
            });
        }
        since_report += 1;
        if since_report == 1 << 16 {
            since_report = 0;
            progress(BuildProgress {
                levels: h.built_levels(),
                faces: h.mesh.n_faces(),
                input_faces,
            });
        }
    }
    if h.built_levels() < options.max_levels {
        h.close_level();
    }
    progress(BuildProgress {
        levels: h.built_levels(),
        faces: h.mesh.n_faces(),
        input_faces,
    });
    Ok(())
}

#[inline]
fn level_target(faces: usize, ratio: f64) -> usize {
    (faces as f64 * ratio).floor() as usize
}
