//! The decimation's legality layer on top of [`Mesh::is_collapse_ok`], shared by the
//! rounds and the QEM decimation.
//!
//! Topological rules (OpenMesh `BaseDecimaterT::is_collapse_legal`, in its order after
//! `is_collapse_ok`):
//! - the *valence-3 tetrahedron*: `vl` and `vr` joined by an edge and both of valence 3
//!   (the collapse would leave two faces glued back to back);
//! - a boundary `v0` may only move along a boundary edge to another boundary vertex
//!   (it never leaves the boundary, and the boundary is never pinched);
//! - `v0` needs at least two incident faces (valence above 2).
//!
//! Boundaries are kept: an interior edge from an interior `v0` to a boundary `v1` places
//! the survivor at `v1`'s position (placement `AtV1`) instead of the method's choice,
//! so a boundary vertex never moves inwards; boundary edges collapse along the boundary.
//!
//! Geometric rules, tested at the survivor's new position `p` for every face around `v0`
//! or `v1` that survives the collapse: its normal must not turn by more than the flip
//! bound (45° by default; OpenMesh's `ModNormalFlipping` uses 90°) and it must not become
//! degenerate (twice its area at most `1e-10` times the sum of its squared edge lengths).

use glam::{DVec3, Vec3};

use crate::handle::{FaceId, HalfedgeId, VertexId};

use crate::mesh::Mesh;

/// Where the survivor of a legal collapse may go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Placement {
    /// Wherever the method wants (midpoint, QEM optimum).
    Free,
    /// At `v1`'s position: `v1` is on the boundary and `v0` is not.
    AtV1,
}

/// Relative area below which a triangle counts as degenerate.
const DEGENERATE: f64 = 1e-10;

/// The parts of a collapse `h = v0 → v1` the tests need.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Collapse {
    pub(crate) v0: VertexId,
    pub(crate) v1: VertexId,
    pub(crate) fl: Option<FaceId>,
    pub(crate) fr: Option<FaceId>,
}

impl Collapse {
    #[inline]
    pub(crate) fn new(mesh: &Mesh, h: HalfedgeId) -> Self {
        let o = mesh.opposite(h);
        Self {
            v0: mesh.to_vertex(o),
            v1: mesh.to_vertex(h),
            fl: mesh.face(h),
            fr: mesh.face(o),
        }
    }
}

/// The topological legality of collapsing `h`: `None` when illegal, else how the
/// survivor may be placed (see the module docs).
pub(crate) fn topology(mesh: &Mesh, h: HalfedgeId) -> Option<Placement> {
    if mesh.is_collapse_ok(h).is_err() {
        return None;
    }
    let o = mesh.opposite(h);
    let v0 = mesh.to_vertex(o);
    let v1 = mesh.to_vertex(h);
    let vl = mesh.face(h).map(|_| mesh.to_vertex(mesh.next(h)));
    let vr = mesh.face(o).map(|_| mesh.to_vertex(mesh.next(o)));
    if let (Some(vl), Some(vr)) = (vl, vr) {
        let valence_3 = |v| mesh.outgoing_halfedges(v).take(4).count() == 3;
        if valence_3(vl) && valence_3(vr) && mesh.find_halfedge(vl, vr).is_some() {
            return None;
        }
    }
    let b0 = mesh.is_boundary_vertex(v0);
    let b1 = mesh.is_boundary_vertex(v1);
    if b0 && (!b1 || (vl.is_some() && vr.is_some())) {
        return None;
    }
    // At least two faces at v0: cw(cw(h)) == h means valence 2.
    if mesh.cw_rotated(mesh.cw_rotated(o)) == o {
        return None;
    }
    Some(if b1 && !b0 {
        Placement::AtV1
    } else {
        Placement::Free
    })
}

/// [`super::rounds::choose_direction`] on slot indices, for the QEM decimation: the
/// direction of the edge of halfedge slot `e` to collapse (`e` or `e ^ 1`, preferring a
/// free placement) with the same answer, found with one walk of each endpoint's ring.
/// [`Mesh::is_collapse_ok`] gives the same answer in both directions of an edge (its
/// tests, the link condition included, are symmetric under swapping `v0` with `v1` and
/// `vl` with `vr`), and so does the valence-3 tetrahedron test; only the boundary rule
/// and `v0`'s valence depend on the direction. `labels` as for `choose_direction`.
pub(crate) fn choose_direction_ix(mesh: &Mesh, e: u32, labels: &[u32]) -> Option<(u32, Placement)> {
    use crate::handle::NONE;
    let he = &mesh.he[..];
    let o = e ^ 1;
    let (re, ro) = (he.get(e as usize)?, he.get(o as usize)?);
    // The ends, `a = from(e)` and `b = to(e)`.
    let (a, b) = (ro.to, re.to);
    if !labels.is_empty() && labels.get(b as usize) != labels.get(a as usize) {
        return None;
    }
    // `is_collapse_ok`, in its order.
    let slots = &mesh.halfedge_slots_;
    if !slots.is_live_index(e as usize) {
        return None;
    }
    let vslots = &mesh.vertex_slots_;
    if !vslots.is_live_index(a as usize) || !vslots.is_live_index(b as usize) {
        return None;
    }
    let face_of = |x: u32| he[x as usize].face;
    // The vertex opposite the edge in the face of `x` (`e` or `o`), if any, or `None`
    // when that triangle has both other edges on the boundary (a veto).
    let opposite_corner = |r: &crate::mesh::HalfedgeRec| -> Option<u32> {
        if r.face == NONE {
            return Some(NONE);
        }
        let x1 = r.next;
        let r1 = &he[x1 as usize];
        let x2 = r1.next;
        if face_of(x1 ^ 1) == NONE && face_of(x2 ^ 1) == NONE {
            return None;
        }
        Some(r1.to)
    };
    // `vl` of `e` (the corner of `e`'s face), `vr` of `e` (of `o`'s face).
    let cl = opposite_corner(re)?;
    let cr = opposite_corner(ro)?;
    if cl == cr {
        return None;
    }
    if !link_condition_ix(mesh, a, b, cl, cr) {
        return None;
    }
    let boundary = |v: u32| match mesh.vertex_conn[v as usize] {
        NONE => true,
        k => he[k as usize].face == NONE,
    };
    let (ba, bb) = (boundary(a), boundary(b));
    let interior_edge = re.face != NONE && ro.face != NONE;
    if ba && bb && interior_edge {
        return None;
    }
    // The valence-3 tetrahedron.
    if cl != NONE && cr != NONE {
        let ring = |v: u32| crate::iter::vertex_walk(he, mesh.vertex_conn[v as usize]);
        let valence_3 = |v: u32| ring(v).take(4).count() == 3;
        if valence_3(cl) && valence_3(cr) && ring(cl).any(|(_, r)| r.to == cr) {
            return None;
        }
    }
    // The direction-dependent rules for `h` (`v0 → v1`, `b0`, `b1` their boundary flags).
    let direction = |h: u32, b0: bool, b1: bool| -> Option<Placement> {
        if b0 && (!b1 || interior_edge) {
            return None;
        }
        // At least two faces at v0: cw(cw(o)) == o means valence 2 (cw(x) = next(x ^ 1)).
        let oh = h ^ 1;
        let c1 = he[(oh ^ 1) as usize].next;
        let c2 = he[(c1 ^ 1) as usize].next;
        if c2 == oh {
            return None;
        }
        Some(if b1 && !b0 {
            Placement::AtV1
        } else {
            Placement::Free
        })
    };
    match direction(e, ba, bb) {
        Some(Placement::Free) => Some((e, Placement::Free)),
        first => match direction(o, bb, ba) {
            Some(Placement::Free) => Some((o, Placement::Free)),
            second => first.map(|p| (e, p)).or(second.map(|p| (o, p))),
        },
    }
}

/// [`Mesh::is_collapse_ok`]'s link condition on slot indices: `a` and `b` share no
/// neighbour but `cl` and `cr` (`NONE` for none). Both rings are gathered into stack
/// arrays (a larger ring is compared ring against ring).
#[inline]
fn link_condition_ix(mesh: &Mesh, a: u32, b: u32, cl: u32, cr: u32) -> bool {
    use crate::iter::vertex_walk;
    const RING: usize = 32;
    let he = &mesh.he[..];
    let mut ring = [0u32; RING];
    let mut n = 0;
    for (_, r) in vertex_walk(he, mesh.vertex_conn[b as usize]) {
        if n == RING {
            return !vertex_walk(he, mesh.vertex_conn[a as usize]).any(|(_, w)| {
                w.to != cl
                    && w.to != cr
                    && vertex_walk(he, mesh.vertex_conn[b as usize]).any(|(_, u)| u.to == w.to)
            });
        }
        ring[n] = r.to;
        n += 1;
    }
    let ring = &ring[..n];
    !vertex_walk(he, mesh.vertex_conn[a as usize])
        .any(|(_, w)| w.to != cl && w.to != cr && ring.contains(&w.to))
}

/// The unit normals the faces around the survivor will have after a collapse, gathered
/// by [`geometry`] so that the normal cache is refreshed without recomputing them.
pub(crate) struct NewNormals {
    items: [(u32, DVec3); NEW_NORMALS],
    len: usize,
}

const NEW_NORMALS: usize = 64;

impl NewNormals {
    #[inline]
    pub(crate) fn new() -> Self {
        Self {
            items: [(0, DVec3::ZERO); NEW_NORMALS],
            len: 0,
        }
    }
    /// Writes the gathered normals into the cache; recomputes the normals around `v1` if
    /// there were too many to gather.
    #[inline]
    pub(crate) fn apply(&self, mesh: &Mesh, v1: VertexId, normals: &mut [Vec3]) {
        if self.len > NEW_NORMALS {
            update_normals_around(mesh, v1, normals);
        } else {
            for &(i, n) in &self.items[..self.len] {
                normals[i as usize] = n.as_vec3();
            }
        }
    }
}

/// The unit normal of the face `(p, a, b)` (the survivor moved to `p`), or `None` when
/// that face is degenerate or its normal turned away from `old` (its cached unit normal)
/// by more than the bound whose cosine is `cos_flip`: the test of one face of
/// [`geometry`] and [`Star::geometry`].
#[inline(always)]
fn moved_face_normal(p: DVec3, a: DVec3, b: DVec3, old: Vec3, cos_flip: f64) -> Option<DVec3> {
    let (ea, eb) = (a - p, b - p);
    let n = ea.cross(eb);
    let len2 = n.length_squared();
    let scale = ea.length_squared() + eb.length_squared() + (b - a).length_squared();
    if len2 <= (DEGENERATE * scale) * (DEGENERATE * scale) {
        return None;
    }
    let len = len2.sqrt();
    if n.dot(old.as_dvec3()) < cos_flip * len {
        return None;
    }
    Some(n / len)
}

/// Checks every face around `v0` and `v1` except `fl` and `fr` with the survivor moved to
/// `p`: no normal turns by more than the bound whose cosine is `cos_flip`, no face
/// becomes degenerate. `normals` holds the current unit face normals by face index; the
/// new normals go to `out`.
pub(crate) fn geometry(
    mesh: &Mesh,
    c: &Collapse,
    p: DVec3,
    normals: &[Vec3],
    cos_flip: f64,
    out: &mut NewNormals,
) -> bool {
    out.len = 0;
    // A placement that overflowed (the midpoint of two huge coordinates, a quadric's
    // optimum) would leave a non-finite position in the mesh.
    if !p.is_finite() {
        return false;
    }
    for v in [c.v0, c.v1] {
        for k in mesh.outgoing_halfedges(v) {
            let Some(f) = mesh.face(k) else { continue };
            if Some(f) == c.fl || Some(f) == c.fr {
                continue;
            }
            let n1 = mesh.next(k);
            let a = mesh.position(mesh.to_vertex(k));
            let b = mesh.position(mesh.to_vertex(n1));
            let fi = mesh.face_index(f);
            let Some(n) = moved_face_normal(p, a, b, normals[fi], cos_flip) else {
                return false;
            };
            if out.len < NEW_NORMALS {
                out.items[out.len] = (fi as u32, n);
            }
            out.len += 1;
        }
    }
    true
}

/// The faces [`geometry`] tests for one collapse, `[face, a, b]` by slot index (the face
/// is `(survivor, a, b)` after the collapse), gathered once by [`Star::gather`] with their
/// corners' positions and cached normals prefetched, so that the cache misses of a
/// star overlap instead of coming one face at a time, and so that the candidate
/// positions of an edge are tested without walking the rings again.
pub(crate) struct Star {
    faces: [[u32; 3]; STAR],
    len: usize,
}

/// The largest star [`Star`] gathers (a larger one is tested by [`geometry`]).
const STAR: usize = 64;
// Every gathered face's new normal fits in a `NewNormals`.
const _: () = assert!(STAR <= NEW_NORMALS);

impl Star {
    /// An empty star.
    #[inline]
    pub(crate) fn new() -> Self {
        Self {
            faces: [[0; 3]; STAR],
            len: 0,
        }
    }

    /// Gathers the faces around `c.v0` and `c.v1` except `c.fl` and `c.fr`, in the order
    /// [`geometry`] visits them; false (and nothing usable) when there are more than
    /// [`STAR`].
    #[inline]
    pub(crate) fn gather(&mut self, mesh: &Mesh, c: &Collapse, normals: &[Vec3]) -> bool {
        use crate::handle::NONE;
        use crate::iter::vertex_walk;
        use crate::prefetch::prefetch;
        let he = &mesh.he[..];
        let fl = c.fl.map_or(NONE, |f| mesh.face_index(f) as u32);
        let fr = c.fr.map_or(NONE, |f| mesh.face_index(f) as u32);
        self.len = 0;
        // One ring at a time, `(face, to)` of its outgoing halfedges in walk order. The
        // third corner of the face of outgoing halfedge `k` is the target of the next
        // one (`prev(k) ^ 1` runs from the centre to it), so the faces' third halfedges
        // need not be read.
        let mut ring = [(0u32, 0u32); STAR];
        for v in [c.v0, c.v1] {
            let mut n = 0;
            for (_, r) in vertex_walk(he, mesh.vertex_conn[mesh.vertex_index(v)]) {
                if n == STAR {
                    return false;
                }
                prefetch(&mesh.positions, r.to as usize);
                if r.face != NONE {
                    prefetch(normals, r.face as usize);
                }
                ring[n] = (r.face, r.to);
                n += 1;
            }
            for i in 0..n {
                let (f, a) = ring[i];
                if f == NONE || f == fl || f == fr {
                    continue;
                }
                if self.len == STAR {
                    return false;
                }
                let b = ring[if i + 1 == n { 0 } else { i + 1 }].1;
                self.faces[self.len] = [f, a, b];
                self.len += 1;
            }
        }
        true
    }

    /// [`geometry`] on the gathered faces: the same tests in the same order, the same
    /// answer and new normals.
    #[inline]
    pub(crate) fn geometry(
        &self,
        mesh: &Mesh,
        p: DVec3,
        normals: &[Vec3],
        cos_flip: f64,
        out: &mut NewNormals,
    ) -> bool {
        out.len = 0;
        // As in `geometry`: an overflowed placement is refused.
        if !p.is_finite() {
            return false;
        }
        let positions = &mesh.positions[..];
        for &[f, a, b] in &self.faces[..self.len] {
            let a = positions[a as usize];
            let b = positions[b as usize];
            let Some(n) = moved_face_normal(p, a, b, normals[f as usize], cos_flip) else {
                return false;
            };
            // (At most `STAR` = `NEW_NORMALS` faces.)
            out.items[out.len] = (f, n);
            out.len += 1;
        }
        true
    }
}

/// Recomputes the cached unit normals of the faces around `v`.
#[inline]
pub(crate) fn update_normals_around(mesh: &Mesh, v: VertexId, normals: &mut [Vec3]) {
    for f in mesh.adjacent_faces(v) {
        normals[mesh.face_index(f)] = mesh.face_normal(f).as_vec3();
    }
}

/// Unit face normals by face index, in single precision (half the memory traffic; the
/// tests they serve compare angles), computed in parallel.
pub(crate) fn cached_normals(mesh: &Mesh) -> Vec<Vec3> {
    use rayon::prelude::*;
    let mut normals = vec![Vec3::ZERO; mesh.face_slots()];
    normals.par_iter_mut().enumerate().for_each(|(i, n)| {
        if let Some(f) = mesh.face_at(i) {
            *n = mesh.face_normal(f).as_vec3();
        }
    });
    normals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{grid, icosphere};

    /// The slot-index direction choice answers as `rounds::choose_direction` for both
    /// halfedges of every edge, on closed and open meshes decimated until low valences,
    /// boundary pinches and tetrahedra appear, with and without labels.
    #[test]
    fn direction_on_slot_indices_is_the_rounds_one() {
        use crate::hierarchy::rounds::choose_direction;
        let mut tried = [0usize; 3];
        for mut mesh in [
            icosphere(1),
            icosphere(2),
            grid(5, 4, 1.0, 1.0),
            grid(9, 3, 1.0, 1.0),
        ] {
            let labels: Vec<u32> = (0..mesh.vertex_slots() as u32)
                .map(|i| u32::from(i % 5 == 0))
                .collect();
            for round in 0..40 {
                for labels in [&[][..], &labels[..]] {
                    for e in mesh.halfedges().collect::<Vec<_>>() {
                        let ix = mesh.halfedge_index(e) as u32;
                        let expected = choose_direction(&mesh, e, mesh.opposite(e), labels)
                            .map(|(g, p)| (mesh.halfedge_index(g) as u32, p));
                        assert_eq!(
                            choose_direction_ix(&mesh, ix, labels),
                            expected,
                            "round {round}"
                        );
                        match expected {
                            None => tried[0] += 1,
                            Some((_, Placement::Free)) => tried[1] += 1,
                            Some((_, Placement::AtV1)) => tried[2] += 1,
                        }
                    }
                }
                // Collapse a few edges (any that the kernel allows) and go on.
                let edges: Vec<_> = mesh.edges().collect();
                let mut collapsed = 0;
                for (k, e) in edges.into_iter().enumerate() {
                    if (k + round) % 5 == 0
                        && mesh.halfedge_slots_.is_live(e)
                        && mesh.collapse(e).is_ok()
                    {
                        collapsed += 1;
                    }
                }
                if collapsed == 0 {
                    break;
                }
            }
        }
        assert!(tried.iter().all(|&n| n > 100), "{tried:?}");
    }

    /// The gathered star's test gives what [`geometry`] gives, answer and new normals,
    /// for both directions of every edge and placements that pass and fail (far off the
    /// surface, onto a neighbour), on a closed mesh and one with a boundary, with bumps.
    #[test]
    fn gathered_star_tests_like_geometry() {
        for mut mesh in [icosphere(2), grid(6, 5, 1.0, 1.0)] {
            for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
                let k = i as f64;
                *p += 0.05 * DVec3::new((k * 1.7).sin(), (k * 2.3).cos(), (k * 0.9).sin());
            }
            let normals = cached_normals(&mesh);
            let (mut passed, mut failed) = (0, 0);
            for e in mesh.edges().collect::<Vec<_>>() {
                for h in [e, mesh.opposite(e)] {
                    let c = Collapse::new(&mesh, h);
                    let mut star = Star::new();
                    assert!(star.gather(&mesh, &c, &normals));
                    let (p0, p1) = (mesh.position(c.v0), mesh.position(c.v1));
                    let up = (p1 - p0).cross(DVec3::Z) + DVec3::Z;
                    let neighbour = mesh.position(mesh.to_vertex(mesh.next(mesh.next(h))));
                    for p in [0.5 * (p0 + p1), p0, p1, p0 + 3.0 * up, neighbour] {
                        for cos_flip in [0.0, std::f64::consts::FRAC_PI_4.cos()] {
                            let (mut a, mut b) = (NewNormals::new(), NewNormals::new());
                            let expected = geometry(&mesh, &c, p, &normals, cos_flip, &mut a);
                            assert_eq!(
                                star.geometry(&mesh, p, &normals, cos_flip, &mut b),
                                expected
                            );
                            if expected {
                                passed += 1;
                                assert_eq!(a.items[..a.len], b.items[..b.len]);
                            } else {
                                failed += 1;
                            }
                        }
                    }
                }
            }
            assert!(passed > 0 && failed > 0, "{passed} passed, {failed} failed");
        }
    }
}
