//! Making sub-mesh labels hold at every level by re-planning only the collapses near a
//! frontier (issue 13), instead of building the hierarchy again.
//!
//! A hierarchy built without a frontier has records that collapse an edge across it (its
//! two ends carry different labels), and after such a collapse an edge can join a vertex
//! labelled inside to one labelled outside. [`respecting_labels`] replays the records of
//! the hierarchy, level by level, on a copy of its input, and keeps every record the
//! frontier cannot have affected. It tracks the *touched* vertices, whose neighbourhood
//! may differ from the one the build saw, and the vertices *near* them (touched or next
//! to a touched vertex):
//!
//! - a record whose ends carry different labels is dropped, and its ends are touched;
//! - a record with neither end near has the one-rings, positions and hence the legality
//!   the build saw: it is collapsed again, and when no vertex of its one-rings is near
//!   either (its whole star is the build's) its record, placement and detail
//!   coefficients are copied rather than computed;
//! - a record with an end near is tested again where it now is (topology, the level's
//!   flip bound, the error bound, the record's placement) and made if it passes; its
//!   ends are touched either way.
//!
//! After the kept records of a level, the touched band is simplified further by a round
//! of the seed paper's rules ([`super::rounds`]: locks, planarity, legality, error bound,
//! with the bounds the build used at that level) over the edges at touched vertices,
//! collapsing only edges whose ends carry the same label: this stands in for the dropped
//! records, so the levels keep about their face counts. When the old levels are replayed
//! and the face target is not reached, further rounds over the band follow until it is or
//! they stall. So the new hierarchy differs from the old one only in a band along the
//! frontier, and costs a fraction of a build: almost every record is a collapse made
//! again with its coefficients copied, nothing is planned again away from the frontier.
//! For a QEM hierarchy the band is re-planned by the rounds' rules as well (midpoint
//! placement), the replayed records keep their QEM placements.

use glam::{DVec3, Vec3};

use super::ahead::{
    COLLAPSE_LINKS_PREFETCH_DISTANCE, COLLAPSE_PREFETCH_DISTANCE, COLLAPSE_SIDES_PREFETCH_DISTANCE,
    RING_PREFETCH_DISTANCES,
};
use super::legality::{self, Collapse, NewNormals, Placement};
use super::records::Storage;
use super::rounds::{star_plane_distance, test_edge, EdgeTest};
use super::{check_positions, outcome, Hierarchy, HierarchyOptions};
use crate::attributes::Attribute;
use crate::error::{Error, Result};
use crate::handle::VertexId;
use crate::labels::Label;
use crate::mesh::Mesh;
use crate::prefetch::prefetch;

/// The hierarchy of `input` (a copy of `source`'s mesh at level 0) whose collapses never
/// join two different labels: `source`'s records replayed where the labels cannot have
/// changed them, the band along the frontier planned again (see the module docs). The
/// labels are the values of `labels` (a vertex attribute of `input`); `options` are
/// `source`'s with [`HierarchyOptions::respect_labels`] set.
///
/// # Errors
/// [`Error::NonFiniteCoordinate`] for a non-finite input position; [`Error::Overflow`]
/// when a replayed placement is not finite.
pub(crate) fn respecting_labels(
    source: &Hierarchy,
    input: Mesh,
    labels: Attribute<VertexId, Label>,
    options: &HierarchyOptions,
) -> Result<Hierarchy> {
    debug_assert_eq!(source.applied, 0);
    check_positions(&input)?;
    let labels = input.attribute_values(labels)?.to_vec();
    let mut h = Hierarchy::unbuilt(input, options, Storage::default());
    let mut band = Band::new(&h.mesh, labels, options.max_error);
    // Every cached normal starts stale (`Band::moved`): only the band's are computed.
    let mut normals = vec![Vec3::ZERO; h.mesh.face_slots()];
    let mut bounds = Bounds::new(options);
    let mut new_normals = NewNormals::new();
    let clean = source.positions_clean();
    let mut round = 0u32;
    let last_level = source.coarsest_level();
    for level in 1..=last_level {
        if h.mesh.n_faces() <= options.target_faces {
            break;
        }
        round += 1;
        bounds.at_level(source, level);
        let (start, end) = (source.level_ends[level - 1], source.level_ends[level]);
        for r in start..end {
            if h.mesh.n_faces() <= options.target_faces {
                break;
            }
            // The records' elements are scattered over arrays far larger than the caches:
            // ask for them a few records ahead, as `Hierarchy::collapse_next` does.
            if let Some(ahead) = source.records.get(r + COLLAPSE_PREFETCH_DISTANCE) {
                h.mesh.prefetch_step(ahead, true);
                prefetch(&band.near, ahead.v0 as usize);
                prefetch(&band.near, ahead.v1 as usize);
            }
            if let Some(ahead) = source.records.get(r + COLLAPSE_SIDES_PREFETCH_DISTANCE) {
                h.mesh.prefetch_sides(ahead);
            }
            if let Some(ahead) = source.records.get(r + COLLAPSE_LINKS_PREFETCH_DISTANCE) {
                h.mesh.prefetch_links(ahead, true);
            }
            for (step, distance) in RING_PREFETCH_DISTANCES.into_iter().enumerate() {
                if let Some(ahead) = source.records.get(r + distance) {
                    h.mesh.prefetch_collapse_ring(ahead, step as u32);
                }
            }
            replay(
                &mut h,
                source,
                r,
                &mut band,
                &bounds,
                &mut normals,
                &mut new_normals,
                round,
                clean,
            )?;
        }
        band.round(&mut h, options, &bounds, &mut normals, round);
        h.close_level();
    }
    // The band is finer than the rest: while the face target is not reached, more
    // rounds over the band, until they stall as the build's rounds would.
    while h.built_levels() < options.max_levels && h.mesh.n_faces() > options.target_faces {
        round += 1;
        let before = h.mesh.n_faces();
        band.round(&mut h, options, &bounds, &mut normals, round);
        let removed = before - h.mesh.n_faces();
        h.close_level();
        if removed == 0 || (removed as f64) < options.min_level_reduction * before as f64 {
            break;
        }
    }
    outcome::finish(&mut h, options, None);
    h.outcome.relaxations = source.outcome.relaxations.clone();
    h.finish_build();
    Ok(h)
}

/// Collapses `source`'s record `r` again on `h`'s mesh, or drops it (and touches its
/// ends). `clean`: the positions are the ones `source`'s details were computed from.
///
/// - Both ends away from the band (neither touched nor next to a touched vertex): their
///   one-rings and positions are the build's, so is the collapse's legality; the record
///   is copied when the whole star is the build's too, made again otherwise.
/// - An end in the band: the collapse is tested again where it now is (topology, the
///   flip bound and the error bound of the level, the record's placement) and made if it
///   passes; its ends are touched either way (their neighbourhoods now differ from the
///   build's).
/// - Ends with different labels: dropped.
#[allow(clippy::too_many_arguments)]
fn replay(
    h: &mut Hierarchy,
    source: &Hierarchy,
    r: usize,
    band: &mut Band,
    bounds: &Bounds,
    normals: &mut [Vec3],
    new_normals: &mut NewNormals,
    round: u32,
    clean: bool,
) -> Result<()> {
    let record = &source.records[r];
    let mesh = &h.mesh;
    let (i0, i1) = (record.v0 as usize, record.v1 as usize);
    let (Some(v0), Some(v1)) = (mesh.vertex_at(i0), mesh.vertex_at(i1)) else {
        return Ok(());
    };
    let same = band.labels.is_empty() || band.labels.get(i0) == band.labels.get(i1);
    let e = mesh.halfedge_at(record.v0v1 as usize);
    let edge = same && e.is_some_and(|e| mesh.from_vertex(e) == v0 && mesh.to_vertex(e) == v1);
    let e = e.unwrap_or_default();
    let place = |mesh: &Mesh| -> Result<(DVec3, f64)> {
        // Where `Hierarchy::collapse_next` would put the survivor.
        let (p0, p1) = (mesh.position(v0), mesh.position(v1));
        let p = source.placements.again(r, record, p0, p1);
        let t = source.placements.parameter(r);
        if p.is_finite() {
            Ok((p, t))
        } else {
            Err(Error::Overflow(format!(
                "collapsing {v0} → {v1} again would put {v1} at {p} (positions {p0} and {p1})"
            )))
        }
    };
    if edge && !band.near[i0] && !band.near[i1] {
        // No vertex of the two one-rings next to a touched one either: the whole star
        // (the links and outgoing halfedges the record keeps) is the build's.
        let star_untouched = clean
            && [v0, v1].into_iter().all(|v| {
                mesh.adjacent_vertices(v)
                    .all(|w| !band.near[mesh.vertex_index(w)])
            });
        if star_untouched {
            h.replay_collapse(source, r);
        } else if mesh.is_collapse_ok(e).is_ok() {
            let (p, t) = place(mesh)?;
            h.record_collapse(e, p, t);
        } else {
            band.touch(mesh, i0);
            band.touch(mesh, i1);
            return Ok(());
        }
        band.lock[i1] = round;
        band.moved[i1] = true;
        return Ok(());
    }
    if edge && band.lock[i0] != round && band.lock[i1] != round {
        if let Some(placement) = legality::topology(mesh, e) {
            let (p, t) = match placement {
                Placement::Free => place(mesh)?,
                Placement::AtV1 => (mesh.position(v1), 0.0),
            };
            band.refresh_normals(mesh, v0, normals);
            band.refresh_normals(mesh, v1, normals);
            let c = Collapse::new(mesh, e);
            let within_error = !band.max_error.is_finite()
                || star_plane_distance(mesh, &c, p, normals) <= band.max_error;
            if within_error
                && legality::geometry(mesh, &c, p, normals, bounds.cos_flip, new_normals)
            {
                h.record_collapse(e, p, t);
                band.lock[i1] = round;
                new_normals.apply(&h.mesh, v1, normals);
            }
        }
    }
    band.touch(&h.mesh, i0);
    band.touch(&h.mesh, i1);
    Ok(())
}

/// The planarity and flip bounds of the level being replayed (the build's, widened where
/// the build widened them), as cosines.
struct Bounds {
    cos_planar: f64,
    cos_flip: f64,
}

impl Bounds {
    fn new(options: &HierarchyOptions) -> Self {
        Self {
            cos_planar: options.max_normal_deviation.cos(),
            cos_flip: options.max_flip_angle.cos(),
        }
    }

    /// The bounds of `level`: the last widening the build made at or below it.
    fn at_level(&mut self, source: &Hierarchy, level: usize) {
        if let Some(r) = source
            .outcome
            .relaxations
            .iter()
            .rev()
            .find(|r| r.level <= level)
        {
            self.cos_planar = r.max_normal_deviation.cos();
            self.cos_flip = r.max_flip_angle.cos();
        }
    }
}

/// The touched vertices (see the module docs), the labels and the rounds' locks.
struct Band {
    /// Labels by vertex index (empty: none).
    labels: Vec<Label>,
    /// The build's error bound.
    max_error: f64,
    touched: Vec<bool>,
    /// Touched or next to a touched vertex.
    near: Vec<bool>,
    /// Survivors of replayed collapses whose faces' cached normals are stale.
    moved: Vec<bool>,
    /// The touched vertices, in the order they were touched.
    list: Vec<u32>,
    /// The round in which each vertex last survived a collapse (rounds' locks).
    lock: Vec<u32>,
}

impl Band {
    fn new(mesh: &Mesh, labels: Vec<Label>, max_error: f64) -> Self {
        Self {
            labels,
            max_error,
            touched: vec![false; mesh.vertex_slots()],
            near: vec![false; mesh.vertex_slots()],
            moved: vec![true; mesh.vertex_slots()],
            list: Vec::new(),
            lock: vec![0; mesh.vertex_slots()],
        }
    }

    /// Touches vertex slot `i`: it and its neighbours are near from now on.
    #[inline]
    fn touch(&mut self, mesh: &Mesh, i: usize) {
        if !self.touched[i] {
            self.touched[i] = true;
            self.list.push(i as u32);
        }
        self.near[i] = true;
        if let Some(v) = mesh.vertex_at(i) {
            for w in mesh.adjacent_vertices(v) {
                self.near[mesh.vertex_index(w)] = true;
            }
        }
    }

    /// Brings the cached normals of the faces around `v` up to date: a face's normal is
    /// stale when one of its vertices survived a replayed collapse since.
    #[inline]
    fn refresh_normals(&mut self, mesh: &Mesh, v: VertexId, normals: &mut [Vec3]) {
        for x in std::iter::once(v).chain(mesh.adjacent_vertices(v)) {
            let i = mesh.vertex_index(x);
            if self.moved[i] {
                self.moved[i] = false;
                legality::update_normals_around(mesh, x, normals);
            }
        }
    }

    /// One round of the seed paper's rules over the edges at touched vertices: at most
    /// one collapse per touched vertex, whose survivor is then locked for the round.
    fn round(
        &mut self,
        h: &mut Hierarchy,
        options: &HierarchyOptions,
        bounds: &Bounds,
        normals: &mut [Vec3],
        round: u32,
    ) {
        // Collapsed vertices never come back while building: walk only the live ones.
        let mesh = &h.mesh;
        self.list.retain(|&i| mesh.vertex_at(i as usize).is_some());
        let mut new_normals = NewNormals::new();
        let mut k = 0;
        // Collapses touch more vertices: the list grows while it is walked.
        while k < self.list.len() {
            let i = self.list[k] as usize;
            k += 1;
            if h.mesh.n_faces() <= options.target_faces {
                return;
            }
            let Some(v) = h.mesh.vertex_at(i) else {
                continue;
            };
            if self.lock[i] == round || h.mesh.is_isolated(v) {
                continue;
            }
            let planned = self.plan(&h.mesh, v, bounds, normals, &mut new_normals, round);
            let Some((g, p, t)) = planned else {
                continue;
            };
            let (v0, v1) = (h.mesh.from_vertex(g), h.mesh.to_vertex(g));
            let (i0, i1) = (h.mesh.vertex_index(v0), h.mesh.vertex_index(v1));
            h.record_collapse(g, p, t);
            self.lock[i1] = round;
            new_normals.apply(&h.mesh, v1, normals);
            // The survivor has new neighbours: they are near now.
            self.touch(&h.mesh, i0);
            self.touch(&h.mesh, i1);
        }
    }

    /// The first edge at `v` that passes the rounds' tests, its direction and the
    /// survivor's place (see [`super::rounds`]).
    fn plan(
        &mut self,
        mesh: &Mesh,
        v: VertexId,
        bounds: &Bounds,
        normals: &mut [Vec3],
        new_normals: &mut NewNormals,
        round: u32,
    ) -> Option<(crate::handle::HalfedgeId, DVec3, f64)> {
        for e in mesh.outgoing_halfedges(v) {
            let w = mesh.to_vertex(e);
            if self.lock[mesh.vertex_index(w)] == round {
                continue;
            }
            // The tests read the normals of the faces around `v` and `w`.
            self.refresh_normals(mesh, v, normals);
            self.refresh_normals(mesh, w, normals);
            let test = EdgeTest {
                cos_planar: bounds.cos_planar,
                cos_flip: bounds.cos_flip,
                max_error: self.max_error,
                labels: &self.labels,
                // Collapses made again after an edit go to the midpoint: their places
                // are stored with the record whatever they are.
                quadrics: None,
            };
            if let Ok(planned) = test_edge(mesh, e, &test, normals, new_normals) {
                return Some(planned);
            }
        }
        None
    }
}
