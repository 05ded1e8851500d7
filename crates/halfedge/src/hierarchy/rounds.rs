//! The seed paper's simplification in rounds ("Interactive Editing of Multiresolution
//! Meshes", section 3).
//!
//! A round visits every live edge once, in index order. An edge `v0v1` collapses when
//! - it is not locked: neither endpoint is the survivor of a collapse made earlier in
//!   this round (after a collapse every edge incident to the survivor is locked until the
//!   round ends);
//! - its star (the faces around `v0` and `v1`) passes the planarity criterion: every face
//!   normal lies within [`max_normal_deviation`](super::HierarchyOptions::max_normal_deviation)
//!   of the normalised average of the star's unit face normals;
//! - the collapse is legal ([`super::legality`]): topologically (OpenMesh's rules), with
//!   no face flipped or made degenerate at the new position, and within the error bound
//!   (the new position's distance to the plane of every star face).
//!
//! The survivor goes to the edge's midpoint (the paper), except that an interior edge
//! from an interior vertex to a boundary vertex collapses onto the boundary vertex, so
//! boundaries are kept. With [`SurvivorPlacement::Quadric`] it goes instead where QEM
//! would put it (module [`super::qem`]: the quadric's minimiser or, when that is
//! ill-conditioned or flips a face, the cheaper legal one of the endpoints), the
//! quadrics summed at every collapse; the order and the tests stay the
//! rounds'. A round is a level; on real meshes a round removes about 45 % of
//! the faces, as the paper reports. Face normals are cached by face index and refreshed
//! around each survivor.
//!
//! When the rounds stall short of a face target, the bounds are widened step by step and
//! the rounds go on ([`HierarchyOptions::relax_when_stalled`]); every widening and, when
//! the target is still not reached, what refused the last round's edges are recorded in
//! the build's outcome ([`super::outcome`]).

use std::ops::ControlFlow;

use glam::{DVec3, Vec3};

use super::legality::{self, Collapse, NewNormals, Placement};
use super::options::{report, SurvivorPlacement};
use super::outcome::{self, Refusals, Relaxation};
use super::qem::{self, Quadric};
use super::{BuildProgress, Hierarchy, HierarchyOptions};
use crate::error::Result;
use crate::handle::HalfedgeId;
use crate::labels::Label;
use crate::mesh::Mesh;

/// Minimum over the star of `v0v1` of the cosine between a face normal and the star's
/// average normal (1 for a planar star). `fl` and `fr` are counted once.
#[inline]
pub(crate) fn star_planarity(mesh: &Mesh, c: &Collapse, normals: &[Vec3]) -> f64 {
    const CAP: usize = 64;
    let mut star = [DVec3::ZERO; CAP];
    let mut n = 0;
    let mut sum = DVec3::ZERO;
    for (i, v) in [c.v0, c.v1].into_iter().enumerate() {
        for f in mesh.adjacent_faces(v) {
            if i == 1 && (Some(f) == c.fl || Some(f) == c.fr) {
                continue;
            }
            let normal = normals[mesh.face_index(f)].as_dvec3();
            sum += normal;
            if n < CAP {
                star[n] = normal;
            }
            n += 1;
        }
    }
    let Some(avg) = sum.try_normalize() else {
        return -1.0;
    };
    if n > CAP {
        // A huge star: walk it again.
        let mut min = 1.0f64;
        for v in [c.v0, c.v1] {
            for f in mesh.adjacent_faces(v) {
                min = min.min(normals[mesh.face_index(f)].as_dvec3().dot(avg));
            }
        }
        return min;
    }
    star[..n].iter().fold(1.0f64, |m, s| m.min(s.dot(avg)))
}

/// Largest distance from `p` to the plane of a face around `v0` or `v1`.
#[inline]
pub(crate) fn star_plane_distance(mesh: &Mesh, c: &Collapse, p: DVec3, normals: &[Vec3]) -> f64 {
    let mut max = 0.0f64;
    for v in [c.v0, c.v1] {
        let q = p - mesh.position(v);
        for f in mesh.adjacent_faces(v) {
            max = max.max(normals[mesh.face_index(f)].as_dvec3().dot(q).abs());
        }
    }
    max
}

/// Builds the levels of `h` by rounds until a stop criterion holds.
pub(crate) fn build(
    h: &mut Hierarchy,
    options: &HierarchyOptions,
    progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
) -> Result<()> {
    let input_faces = h.mesh.n_faces();
    let relax = options.relax_when_stalled && options.target_faces > 0;
    let mut deviation = options.max_normal_deviation;
    let mut flip = options.max_flip_angle;
    let mut cos_planar = deviation.cos();
    let mut cos_flip = flip.cos();
    let mut refusals = Refusals::default();
    let mut normals = legality::cached_normals(&h.mesh);
    let labels = h.label_constraint(options);
    // Placing by the quadric: every vertex's quadric, summed into the survivor's after
    // each collapse, as in the QEM build.
    let mut quadrics = (options.placement == SurvivorPlacement::Quadric).then(|| {
        let planes = qem::face_planes(&h.mesh);
        qem::vertex_quadrics(&h.mesh, &planes, options.boundary_weight)
    });
    let mut lock = vec![0u32; h.mesh.vertex_slots()];
    // The live edges (smaller halfedge index of each pair), in index order; rounds walk
    // this list, which shrinks after every round, rather than every halfedge slot.
    let mut edges: Vec<u32> = {
        let mesh = &h.mesh;
        (0..mesh.halfedge_slots())
            .filter(|&i| {
                mesh.halfedge_at(i)
                    .is_some_and(|e| mesh.halfedge_index(mesh.opposite(e)) > i)
            })
            .map(|i| i as u32)
            .collect()
    };
    // The output buffers' memory is written on another thread while the (sequential)
    // rounds run, as in the QEM build; each collapse removes two faces of a closed mesh.
    let mut prefaulting = h.prefault(input_faces.saturating_sub(options.target_faces) / 2);
    let mut round = 0u32;
    let mut since_report = 0usize;
    let mut new_normals = NewNormals::new();
    'rounds: while h.built_levels() < options.max_levels && h.mesh.n_faces() > options.target_faces
    {
        round += 1;
        refusals = Refusals::default();
        let faces_before = h.mesh.n_faces();
        for (j, &i) in edges.iter().enumerate() {
            // The edges' data is scattered over arrays larger than the caches: ask for
            // it a few edges ahead, in two stages (where the rings start, then the rings).
            if let Some(&ahead) = edges.get(j + 12) {
                prefetch_endpoints(&h.mesh, &lock, ahead as usize);
            }
            if let Some(&ahead) = edges.get(j + 6) {
                prefetch_rings(&h.mesh, &normals, ahead as usize);
            }
            let (g, p, t) = {
                let mesh = &h.mesh;
                let Some(e) = mesh.halfedge_at(i as usize) else {
                    continue;
                };
                let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
                if lock[mesh.vertex_index(a)] == round || lock[mesh.vertex_index(b)] == round {
                    refusals.locked += 1;
                    continue;
                }
                let test = EdgeTest {
                    cos_planar,
                    cos_flip,
                    max_error: options.max_error,
                    labels: &labels,
                    quadrics: quadrics.as_deref(),
                };
                match test_edge(mesh, e, &test, &normals, &mut new_normals) {
                    Ok(planned) => planned,
                    Err(refused) => {
                        refusals.count(refused);
                        continue;
                    }
                }
            };
            let (v0, v1) = (h.mesh.from_vertex(g), h.mesh.to_vertex(g));
            if let Some(quadrics) = quadrics.as_mut() {
                let (i0, i1) = (h.mesh.vertex_index(v0), h.mesh.vertex_index(v1));
                quadrics[i1] = quadrics[i0] + quadrics[i1];
            }
            h.record_collapse(g, p, t);
            lock[h.mesh.vertex_index(v1)] = round;
            new_normals.apply(&h.mesh, v1, &mut normals);
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
            if h.mesh.n_faces() <= options.target_faces {
                h.close_level();
                break 'rounds;
            }
        }
        let mesh = &h.mesh;
        edges.retain(|&i| mesh.halfedge_at(i as usize).is_some());
        let removed = faces_before - h.mesh.n_faces();
        let stalled =
            removed == 0 || (removed as f64) < options.min_level_reduction * faces_before as f64;
        if stalled && relax {
            if let Some((d, f)) = widen(deviation, flip) {
                // The level stays open: the next round, with the wider bounds, adds to it.
                (deviation, flip) = (d, f);
                (cos_planar, cos_flip) = (d.cos(), f.cos());
                h.outcome.relaxations.push(Relaxation {
                    level: h.built_levels() + 1,
                    faces: h.mesh.n_faces(),
                    max_normal_deviation: d,
                    max_flip_angle: f,
                });
                continue;
            }
        }
        h.close_level();
        report(h.built_levels(), h.mesh.n_faces(), input_faces, progress)?;
        if stalled {
            break;
        }
    }
    outcome::finish(h, options, Some(refusals));
    h.details.shrink_to_fit();
    Ok(())
}

/// What a round tests an edge against: the level's planarity and flip bounds (cosines),
/// the error bound, the sub-mesh labels by vertex index (empty for none) and, when the
/// survivor is placed by the quadric, the vertex quadrics.
pub(crate) struct EdgeTest<'a> {
    pub(crate) cos_planar: f64,
    pub(crate) cos_flip: f64,
    pub(crate) max_error: f64,
    pub(crate) labels: &'a [Label],
    /// The vertex quadrics by vertex index when the survivor is placed by the quadric
    /// ([`SurvivorPlacement::Quadric`]), `None` for the paper's midpoint.
    pub(crate) quadrics: Option<&'a [Quadric]>,
}

/// Which of the rounds' tests refused an edge (see [`test_edge`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Refused {
    Planarity,
    Topology,
    ErrorBound,
    Geometry,
}

impl Refusals {
    /// Counts one refusal.
    #[inline]
    pub(crate) fn count(&mut self, refused: Refused) {
        match refused {
            Refused::Planarity => self.planarity += 1,
            Refused::Topology => self.topology += 1,
            Refused::ErrorBound => self.error_bound += 1,
            Refused::Geometry => self.geometry += 1,
        }
    }
}

/// The seed paper's tests of edge `e` (locks aside, see the module docs): the star's
/// planarity, the direction that is topologically legal (and keeps the labels), the
/// survivor's place (the midpoint, or `v1` on a boundary), the error bound, no flip nor
/// degenerate face. Returns the halfedge to collapse, the survivor's place and its
/// parameter along the edge; the new normals of the faces around the survivor are left
/// in `new_normals`. `normals` holds the current unit face normals by face index.
#[inline]
pub(crate) fn test_edge(
    mesh: &Mesh,
    e: HalfedgeId,
    test: &EdgeTest<'_>,
    normals: &[Vec3],
    new_normals: &mut NewNormals,
) -> std::result::Result<(HalfedgeId, DVec3, f64), Refused> {
    if star_planarity(mesh, &Collapse::new(mesh, e), normals) < test.cos_planar {
        return Err(Refused::Planarity);
    }
    let o = mesh.opposite(e);
    let (g, placement) = choose_direction(mesh, e, o, test.labels).ok_or(Refused::Topology)?;
    let c = Collapse::new(mesh, g);
    let p1 = mesh.position(c.v1);
    let (p, t) = match placement {
        Placement::Free => {
            if let Some(quadrics) = test.quadrics {
                return place_by_quadric(mesh, g, &c, quadrics, test, normals, new_normals);
            }
            (0.5 * (mesh.position(c.v0) + p1), 0.5)
        }
        Placement::AtV1 => (p1, 0.0),
    };
    if test.max_error.is_finite() && star_plane_distance(mesh, &c, p, normals) > test.max_error {
        return Err(Refused::ErrorBound);
    }
    if !legality::geometry(mesh, &c, p, normals, test.cos_flip, new_normals) {
        return Err(Refused::Geometry);
    }
    Ok((g, p, t))
}

/// The survivor's place by the quadric ([`SurvivorPlacement::Quadric`]): the cheapest of
/// QEM's candidates (the quadric's minimiser, `p0`, `p1`; module
/// [`super::qem`]) that is within the error bound and flips no face.
#[inline]
fn place_by_quadric(
    mesh: &Mesh,
    g: HalfedgeId,
    c: &Collapse,
    quadrics: &[Quadric],
    test: &EdgeTest<'_>,
    normals: &[Vec3],
    new_normals: &mut NewNormals,
) -> std::result::Result<(HalfedgeId, DVec3, f64), Refused> {
    let (_, mut candidates) = qem::candidates(mesh, quadrics, mesh.halfedge_index(g) as u32);
    candidates.sort();
    let mut refused = Refused::Geometry;
    for &(_, p) in candidates.as_slice() {
        if test.max_error.is_finite() && star_plane_distance(mesh, c, p, normals) > test.max_error {
            refused = Refused::ErrorBound;
            continue;
        }
        if legality::geometry(mesh, c, p, normals, test.cos_flip, new_normals) {
            let t = qem::parameter_along(mesh.position(c.v0), mesh.position(c.v1), p);
            return Ok((g, p, t));
        }
    }
    Err(refused)
}

/// The step by which [`widen`] opens a bound: 15°.
const WIDEN_STEP: f64 = std::f64::consts::PI / 12.0;

/// The next bounds after a stall: the planarity bound 15° wider, up to 180°; once it is
/// there, the flip bound 15° wider, up to 90° (a face may turn, never fold over). `None`
/// when both are at their ends.
fn widen(deviation: f64, flip: f64) -> Option<(f64, f64)> {
    use std::f64::consts::{FRAC_PI_2, PI};
    if deviation < PI - 1e-9 {
        Some(((deviation + WIDEN_STEP).min(PI), flip))
    } else if flip < FRAC_PI_2 - 1e-9 {
        Some((deviation, (flip + WIDEN_STEP).min(FRAC_PI_2)))
    } else {
        None
    }
}

/// Prefetches, for the edge of halfedge slot `i` (visited a few edges later), what tells
/// whether it is locked and where its endpoints' rings start (see [`crate::prefetch`]).
#[inline]
fn prefetch_endpoints(mesh: &Mesh, lock: &[u32], i: usize) {
    use crate::prefetch::prefetch;
    for k in [i, i ^ 1] {
        if let Some(rec) = mesh.he.get(k) {
            let v = rec.to as usize;
            prefetch(&mesh.vertex_conn, v);
            prefetch(lock, v);
            prefetch(&mesh.positions, v);
        }
    }
}

/// Prefetches the first halfedge of each endpoint's ring and the normal of its face, for
/// the edge of halfedge slot `i` (after [`prefetch_endpoints`] brought in where they are).
#[inline]
fn prefetch_rings(mesh: &Mesh, normals: &[Vec3], i: usize) {
    use crate::prefetch::prefetch;
    for k in [i, i ^ 1] {
        let Some(rec) = mesh.he.get(k) else {
            continue;
        };
        if let Some(&out) = mesh.vertex_conn.get(rec.to as usize) {
            prefetch(&mesh.he, out as usize);
            if let Some(first) = mesh.he.get(out as usize) {
                prefetch(normals, first.face as usize);
            }
        }
    }
}

/// The direction of edge `e`/`o` to collapse: the first of `e`, `o` that is
/// topologically legal, preferring a free placement. `None` as well when `labels`
/// (sub-mesh labels by vertex index, empty for none) differ at its two ends.
#[inline]
pub(crate) fn choose_direction(
    mesh: &Mesh,
    e: HalfedgeId,
    o: HalfedgeId,
    labels: &[u32],
) -> Option<(HalfedgeId, Placement)> {
    if !labels.is_empty() {
        let label = |h: HalfedgeId| labels.get(mesh.vertex_index(mesh.to_vertex(h)));
        if label(e) != label(o) {
            return None;
        }
    }
    match legality::topology(mesh, e) {
        Some(Placement::Free) => Some((e, Placement::Free)),
        first => match legality::topology(mesh, o) {
            Some(Placement::Free) => Some((o, Placement::Free)),
            second => first.map(|p| (e, p)).or(second.map(|p| (o, p))),
        },
    }
}
