//! After a walk finer that carried an edit: faces the refinement turned over are unfolded.
//!
//! Each split places its two vertices from the neighbourhood it has then (see
//! [`super::detail`]), and a split's own fold test looks only at that neighbourhood. A
//! vertex placed early (its cluster spread far from its coarse ancestor, as QEM's
//! clusters along a flat feature do) can end up beside the exactly moved vertices of a
//! handle split later, and the fine faces between the two motions turn over: the coarse
//! edit turned none, the refinement did. So at the end of a walk, every face turned over
//! against where it was before the edit and touching a vertex of an edit's region that
//! is placed by interpolation (not an exact affine or field mark, not outside every
//! region: those stay bit for bit) has those vertices, and their interpolated neighbours
//! a few rings deep ([`DEPTHS`], tried in turn), relaxed: each displacement (from where
//! the vertex was before the edit) moves to the mean of its neighbours' (a Jacobi step of
//! the displacement's uniform Laplacian, the exact and outside vertices its boundary),
//! for at most [`MAX_ROUNDS`] rounds per depth (fewer when the neighbourhoods are so large
//! that they would take more than [`MAX_WORK`] vertex updates, and a depth is given up
//! after [`STALLED_ROUNDS`] rounds that turn no fewer faces over). The depth and round that
//! turn the fewest faces over are kept (the positions as they were when none turns fewer);
//! the deeper depths are not tried once a depth turns no fewer faces over than the one
//! before it.
//!
//! A face the edit itself turned over at its level is the edit's: when a walk finer leaves
//! the level of an edit, the corners of the faces the edit turned over there (against the
//! positions before it) are noted, and their descendants are neither counted as turned nor
//! moved. (A workflow's handle rotation and taper turn thousands of coarse faces; the
//! unfolding spent most of a refinement fighting them at every level, and moved the edit.)
//! Faces the relaxation leaves turned (a step too steep for it: a coarse vertex moved by a
//! coarse edge's share next to fine vertices that stay or land exactly) are then drawn
//! back by ramps: from their exactly moved corners towards those corners' motion
//! ([`retreat_from_exact`]), then around each face towards where it was
//! ([`retreat_around`]); and last each interpolated corner of a face still turned is
//! moved towards its neighbours' centroid or into the kernel of its star
//! ([`untangle`]). Each step is kept only if it turns fewer faces over.

use glam::DVec3;

use super::marks::{IN_REGION, UNMARKED};
use super::{DetailMode, Hierarchy};

/// Rounds of relaxation at most.
const MAX_ROUNDS: usize = 200;
/// Rings of movable neighbours around the turned faces relaxed with them: each depth in
/// turn, from the turned faces' own vertices outwards, until one unfolds everything (the
/// depth that turns the fewest faces over is kept).
const DEPTHS: [usize; 4] = [2, 4, 8, 16];
/// Vertex updates at most over all rounds (a refinement that turned faces over
/// everywhere gets fewer rounds, at least [`MIN_ROUNDS`]).
const MAX_WORK: usize = 20_000_000;
/// Rounds at least, whatever the size of the relaxed neighbourhoods.
const MIN_ROUNDS: usize = 8;
/// A depth is given up after this many rounds without turning fewer faces over.
const STALLED_ROUNDS: usize = 60;

impl Hierarchy {
    /// Unfolds the faces a refinement after an edit turned over against where they were
    /// before the edit: the vertices of an edit's region placed by interpolation around
    /// them (up to sixteen rings deep) have their displacements relaxed towards their
    /// neighbours', keeping the round that turns the fewest faces over; what that leaves
    /// turned is drawn back by ramps from the exactly moved vertices beside it and then
    /// untangled, a vertex at a time, towards its neighbours' centroid or into the kernel
    /// of its star (each step kept only if it turns fewer faces over); vertices outside
    /// every region and vertices moved exactly by an affine
    /// or field mark stay bit for bit (see the coarse edits guide). A walk finer
    /// ([`seek`](Self::seek), [`go_to_level`](Self::go_to_level),
    /// [`refine_to`](Self::refine_to)) does this at its end; after refining one
    /// [`split_next`](Self::split_next) at a time, call it once at the level reached.
    /// Nothing to do (and nothing done) while no position was edited, with the paper's
    /// translations, or when no region was marked.
    pub fn unfold_refinement(&mut self) {
        if self.marks.is_empty()
            || self.details.mode() != DetailMode::LocalFrame
            || self.positions_are_clean()
        {
            return;
        }
        let r = self.applied;
        let Some(k) = self.rests.iter().rposition(|rest| rest.serves(r)) else {
            return;
        };
        self.placer().sync_rest(k, r);
        let by_edit = self.descendants_turned_by_edit(k);
        let mut positions = std::mem::take(&mut self.mesh.positions);
        let rest = &self.rests[k].positions;
        let mesh = &self.mesh;
        let marks = &self.marks;
        let rest_of = |i: usize| rest.get(i).map(|&p| DVec3::from_array(p));
        let by_edit_at = |i: usize| by_edit.get(i).copied().unwrap_or(false);
        let movable = |i: usize| marks.of(i) == IN_REGION && rest_of(i).is_some() && !by_edit_at(i);
        let turned = |positions: &[DVec3], f: crate::handle::FaceId| -> bool {
            turned_at(
                positions,
                rest,
                mesh.triangle(f).map(|v| mesh.vertex_index(v)),
            )
        };
        // Every face once, on all threads: those with an interpolated vertex of a region
        // that are turned over (in face order, so the same on any number of threads).
        let flipped: Vec<crate::handle::FaceId> = {
            use rayon::prelude::*;
            let (he, of_vertex) = (&mesh.he[..], &marks.of_vertex[..]);
            let now = &positions[..];
            (0..mesh.face_slots())
                .into_par_iter()
                .filter(|&f| {
                    if !mesh.face_slots_.is_live_index(f) {
                        return false;
                    }
                    let r0 = &he[mesh.face_conn[f] as usize];
                    let r1 = &he[r0.next as usize];
                    let r2 = &he[r1.next as usize];
                    let corners = [r0.to, r1.to, r2.to].map(|v| v as usize);
                    corners
                        .iter()
                        .any(|&i| of_vertex.get(i) == Some(&IN_REGION))
                        && !corners.iter().any(|&i| by_edit_at(i))
                        && turned_at(now, rest, corners)
                })
                .map(|f| mesh.fh(f as u32))
                .collect()
        };
        if flipped.is_empty() {
            self.mesh.positions = positions;
            return;
        }
        // The vertices relaxed: the movable ones of the turned faces and their movable
        // neighbours some rings deep (so that the step spreads), for each depth of
        // [`DEPTHS`] (the deepest set holds the others).
        // (Breadth first, through every vertex: a ring is the unvisited neighbours of
        // the one before.)
        // (The mesh's positions are out of it here: its vertex slots are `positions`'.)
        let mut visited = vec![false; positions.len()];
        let mut frontier: Vec<usize> = Vec::new();
        let mut visit = |i: usize| {
            visited
                .get_mut(i)
                .is_some_and(|seen| !std::mem::replace(seen, true))
        };
        for i in flipped.iter().flat_map(|&f| corners(mesh, f)) {
            if visit(i) {
                frontier.push(i);
            }
        }
        let mut grown = frontier.clone();
        let mut sets: Vec<Vec<usize>> = Vec::with_capacity(DEPTHS.len());
        for ring in 1..=DEPTHS[DEPTHS.len() - 1] {
            let mut next = Vec::new();
            for v in frontier.iter().filter_map(|&i| mesh.vertex_at(i)) {
                for w in mesh.adjacent_vertices(v) {
                    let j = mesh.vertex_index(w);
                    if visit(j) {
                        next.push(j);
                    }
                }
            }
            grown.extend_from_slice(&next);
            frontier = next;
            if DEPTHS.contains(&ring) {
                let mut set: Vec<usize> = grown.iter().copied().filter(|&i| movable(i)).collect();
                set.sort_unstable();
                sets.push(set);
            }
        }
        let deepest = &sets[sets.len() - 1];
        // The faces around a set of vertices: the only ones whose turn relaxing them
        // changes.
        let around = |set: &[usize]| faces_around(mesh, set.iter().copied());
        // Turned faces, counted as the change from the original around each depth's set
        // (faces further out are as they were whatever the depth). The positions stay as
        // they are while the relaxation runs on its own copy of the stepping vertices'.
        let mut best: (isize, Option<(Relaxation, Vec<DVec3>)>) = (0, None);
        let mut unfolded = false;
        for relaxed in &sets {
            let relaxation = Relaxation::new(mesh, &positions, rest, relaxed, &around(relaxed));
            let mut now_at = relaxation.start(&positions);
            let base = relaxation.count(&now_at) as isize;
            let rounds = MAX_ROUNDS.min((MAX_WORK / relaxed.len().max(1)).max(MIN_ROUNDS));
            let mut since_best = 0;
            let mut improved: Option<Vec<DVec3>> = None;
            for _ in 0..rounds {
                relaxation.step(&mut now_at);
                let now = relaxation.count(&now_at);
                let change = now as isize - base;
                if change < best.0 {
                    best.0 = change;
                    improved = Some(now_at.clone());
                    since_best = 0;
                } else {
                    since_best += 1;
                }
                if now == 0 {
                    unfolded = true;
                    break;
                }
                if since_best >= STALLED_ROUNDS {
                    break;
                }
            }
            let deeper_helped = improved.is_some();
            if let Some(at) = improved {
                best.1 = Some((relaxation, at));
            }
            if unfolded || (!deeper_helped && best.1.is_some()) {
                // Unfolded, or this depth turned no fewer faces over than the one before:
                // deeper ones spread the same steps wider (what is left goes to the ramps).
                break;
            }
        }
        if let Some((relaxation, at)) = &best.1 {
            relaxation.write(&mut positions, at);
        }
        if !unfolded {
            // What the relaxation left turned: ramps, then the untangling step.
            let watched = around(deepest);
            let left: Vec<crate::handle::FaceId> = watched
                .iter()
                .copied()
                .filter(|&f| turned(&positions, f))
                .collect();
            // The corners of those faces that moved exactly: still (unmarked, where they
            // were) or where their affine or field mark takes them (their mark's index).
            let mut kinds: std::collections::BTreeMap<usize, Option<usize>> = Default::default();
            for &f in &left {
                for v in mesh.triangle(f) {
                    let i = mesh.vertex_index(v);
                    let Some(at_rest) = rest_of(i) else { continue };
                    let mark = marks.of(i);
                    let kind = if mark == UNMARKED {
                        (positions[i] == at_rest).then_some(None)
                    } else if mark == IN_REGION {
                        None
                    } else {
                        marks.maps.get(mark as usize).and_then(|map| {
                            let at = super::detail::Collapsed {
                                p0: at_rest,
                                p1: at_rest,
                                placed: at_rest,
                            };
                            super::detail::Details::motion_placement(map, positions[i], at)
                                .map(|_| Some(mark as usize))
                        })
                    };
                    if let Some(kind) = kind {
                        kinds.insert(i, kind);
                    }
                }
            }
            let exact = |i: usize, p: DVec3| -> Option<DVec3> {
                match kinds.get(&i)? {
                    None => Some(p),
                    Some(k) => Some(marks.maps.get(*k)?.apply(p)),
                }
            };
            untangle_what_is_left(mesh, &mut positions, rest, &movable, &exact, watched);
        }
        self.mesh.positions = positions;
    }
}

impl Hierarchy {
    /// Notes, on the copy of the positions before the edits that serves the next split,
    /// which vertices of the current level are corners of faces the edits turned over
    /// (against that copy): called when a walk finer or a [`split_next`](Self::split_next)
    /// starts, it does so once, at the level the copy was taken at (so that refining one
    /// split at a time and unfolding at the end does what a walk does).
    pub(super) fn note_turned_by_edit(&mut self) {
        let r = self.applied;
        if r == 0 || self.marks.is_empty() || self.details.mode() != DetailMode::LocalFrame {
            return;
        }
        let Some(k) = self.rests.iter().rposition(|rest| rest.serves(r - 1)) else {
            return;
        };
        let rest = &self.rests[k];
        if rest.ceil != r || rest.turned_by_edit.is_some() {
            return;
        }
        let mesh = &self.mesh;
        let mut turned: Vec<u32> = mesh
            .faces()
            .map(|f| corners(mesh, f))
            .filter(|&c| turned_at(&mesh.positions, &rest.positions, c))
            .flatten()
            .map(|i| i as u32)
            .collect();
        turned.sort_unstable();
        turned.dedup();
        self.rests[k].turned_by_edit = Some(turned);
    }

    /// By vertex slot: whether the vertex descends (through the splits made since) from
    /// a corner of a face the edits turned over at the level of `self.rests[k]` (see
    /// [`note_turned_by_edit`](Self::note_turned_by_edit)); empty when none was noted.
    fn descendants_turned_by_edit(&self, k: usize) -> Vec<bool> {
        let rest = &self.rests[k];
        let Some(turned) = rest.turned_by_edit.as_deref().filter(|t| !t.is_empty()) else {
            return Vec::new();
        };
        let mut corner = vec![false; self.mesh.vertex_slots()];
        for &i in turned {
            if let Some(x) = corner.get_mut(i as usize) {
                *x = true;
            }
        }
        self.ancestors_through(self.applied..rest.ceil)
            .into_iter()
            .map(|a| corner.get(a as usize).copied().unwrap_or(false))
            .collect()
    }
}

/// The relaxation of one set of vertices on a compact copy: the vertices that take a
/// step ("stepping": a position before the edit, at least one neighbour, and every
/// neighbour with one) numbered `0..n`; every other vertex stays where it is while the
/// relaxation runs, so its displacement (for the steps) and position (for the turn
/// tests) are gathered once. Neighbours are kept in the circulators' order and every
/// value is computed as walking the mesh would, so the results are the same bit for bit.
struct Relaxation {
    /// The stepping vertices' slots.
    vertices: Vec<usize>,
    /// Where each was before the edit.
    at_rest: Vec<DVec3>,
    /// `neighbours[start[k]..start[k + 1]]`: vertex `k`'s neighbours, a stepping vertex
    /// by its number below `n`, another as `n + s` (its index `s` in the still arrays).
    start: Vec<usize>,
    neighbours: Vec<u32>,
    /// Displacements (from before the edit) and positions of the vertices read that do
    /// not step.
    still_displacement: Vec<DVec3>,
    still_position: Vec<DVec3>,
    /// The faces around the set that can turn over (every corner has a position before
    /// the edit), corners numbered as `neighbours`, and their normals before the edit.
    corners: Vec<[u32; 3]>,
    before: Vec<DVec3>,
}

impl Relaxation {
    fn new(
        mesh: &crate::mesh::Mesh,
        positions: &[DVec3],
        rest: &[[f64; 3]],
        set: &[usize],
        faces: &[crate::handle::FaceId],
    ) -> Self {
        // Which vertices step, and their numbers; then the other vertices the steps and
        // the turn tests read, numbered from `n` on (one dense table over the slots).
        const UNSEEN: u32 = u32::MAX;
        let mut number = vec![UNSEEN; positions.len()];
        let mut vertices = Vec::with_capacity(set.len());
        let mut start = vec![0];
        let mut rings: Vec<usize> = Vec::with_capacity(6 * set.len());
        for &i in set {
            let (Some(v), Some(_)) = (mesh.vertex_at(i), rest_of(rest, i)) else {
                continue;
            };
            let mark = rings.len();
            rings.extend(mesh.adjacent_vertices(v).map(|w| mesh.vertex_index(w)));
            if rings.len() == mark || rings[mark..].iter().any(|&j| j >= rest.len()) {
                rings.truncate(mark);
                continue;
            }
            number[i] = vertices.len() as u32;
            vertices.push(i);
            start.push(rings.len());
        }
        let n = vertices.len() as u32;
        let (mut still_displacement, mut still_position) = (Vec::new(), Vec::new());
        let mut numbered = |i: usize| -> u32 {
            if number[i] == UNSEEN {
                number[i] = n + still_position.len() as u32;
                still_position.push(positions[i]);
                still_displacement.push(rest_of(rest, i).map_or(DVec3::ZERO, |r| positions[i] - r));
            }
            number[i]
        };
        let neighbours: Vec<u32> = rings.iter().map(|&j| numbered(j)).collect();
        let mut corners = Vec::with_capacity(faces.len());
        let mut before = Vec::with_capacity(faces.len());
        for &f in faces {
            let [a, b, c] = self::corners(mesh, f);
            let (Some(ra), Some(rb), Some(rc)) =
                (rest_of(rest, a), rest_of(rest, b), rest_of(rest, c))
            else {
                continue;
            };
            corners.push([numbered(a), numbered(b), numbered(c)]);
            before.push((rb - ra).cross(rc - ra));
        }
        let at_rest = vertices
            .iter()
            .map(|&i| DVec3::from_array(rest[i]))
            .collect();
        Relaxation {
            vertices,
            at_rest,
            start,
            neighbours,
            still_displacement,
            corners,
            before,
            still_position,
        }
    }

    /// The stepping vertices' positions when the relaxation starts (the positions are
    /// not written until the best round is).
    fn start(&self, positions: &[DVec3]) -> Vec<DVec3> {
        self.vertices.iter().map(|&i| positions[i]).collect()
    }

    /// One Jacobi step: each stepping vertex's displacement from where it was before the
    /// edit becomes the mean of its neighbours' (all computed from `at` as it is, then
    /// written; a value that is not finite is not written).
    fn step(&self, at: &mut [DVec3]) {
        use rayon::prelude::*;
        let n = self.vertices.len();
        let now = &*at;
        let moved: Vec<DVec3> = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|k| {
                let ring = &self.neighbours[self.start[k]..self.start[k + 1]];
                let mut sum = DVec3::ZERO;
                for &j in ring {
                    let j = j as usize;
                    sum += if j < n {
                        now[j] - self.at_rest[j]
                    } else {
                        self.still_displacement[j - n]
                    };
                }
                self.at_rest[k] + sum / ring.len() as f64
            })
            .collect();
        for (p, q) in at.iter_mut().zip(moved) {
            if q.is_finite() {
                *p = q;
            }
        }
    }

    /// How many of the faces are turned over (as [`turned_at`]) with the stepping
    /// vertices `at`.
    fn count(&self, at: &[DVec3]) -> usize {
        use rayon::prelude::*;
        let n = self.vertices.len();
        let position = |k: u32| {
            let k = k as usize;
            if k < n {
                at[k]
            } else {
                self.still_position[k - n]
            }
        };
        self.corners
            .par_iter()
            .with_min_len(4096)
            .zip(&self.before)
            .filter(|&(&[a, b, c], then)| {
                let (pa, pb, pc) = (position(a), position(b), position(c));
                (pb - pa).cross(pc - pa).dot(*then) < 0.0
            })
            .count()
    }

    /// Puts the stepping vertices at `at`.
    fn write(&self, positions: &mut [DVec3], at: &[DVec3]) {
        for (&i, &p) in self.vertices.iter().zip(at) {
            positions[i] = p;
        }
    }
}

/// The steps after the relaxation, on the faces of `watched` (the faces it could change)
/// that are still turned over: [`retreat_from_exact`], [`retreat_around`], [`untangle`].
/// A step may turn a face over further out while it unfolds more (what it keeps turns
/// fewer over in all), so each one takes every face still turned among `watched` and
/// the faces the steps before it could change.
fn untangle_what_is_left(
    mesh: &crate::mesh::Mesh,
    positions: &mut [DVec3],
    rest: &[[f64; 3]],
    movable: &dyn Fn(usize) -> bool,
    exact: &dyn Fn(usize, DVec3) -> Option<DVec3>,
    mut watched: Vec<crate::handle::FaceId>,
) {
    let mut still_turned = |positions: &[DVec3], touched: Vec<crate::handle::FaceId>| {
        watched.extend(touched);
        sort_faces(mesh, &mut watched);
        let mut left = watched.clone();
        left.retain(|&f| turned_at(positions, rest, corners(mesh, f)));
        left
    };
    let left = still_turned(positions, Vec::new());
    let touched = retreat_from_exact(mesh, positions, rest, movable, exact, &left);
    let left = still_turned(positions, touched);
    let touched = retreat_around(mesh, positions, rest, movable, &left);
    let left = still_turned(positions, touched);
    untangle(mesh, positions, rest, movable, &left);
}

/// Rings of the ramps [`retreat_from_exact`] tries.
const RETREAT_RINGS: [usize; 4] = [2, 4, 8, 16];
/// Rings of the ramps [`retreat_around`] tries: shorter, since they draw the edit's
/// motion back towards where the vertices were (sixteen rings changed a Lee drag on one
/// test mesh by half a percent of its diagonal to unfold two faces).
const AROUND_RINGS: [usize; 3] = [2, 4, 8];
/// Vertices [`retreat_around`] ramps at most over all faces (a refinement that left
/// faces turned everywhere is not ramped face by face beyond that).
const MAX_RETREAT_WORK: usize = 2_000_000;

/// The faces of `faces` still turned over with a corner that moved exactly (stayed where
/// it was before the edit, or follows its affine or field mark) are where the motion
/// steps from that corner's to an edge's length more or less, too steep for the
/// relaxation to unfold (a coarse vertex moved by a coarse edge's share next to fine
/// vertices that stay or land exactly). `exact` gives such a corner's motion at a point
/// (`p` ↦ where its mark takes `p`, or `p` for a still vertex), `None` for the others.
/// The movable vertices up to `k` rings from those corners are drawn towards the motion
/// of the nearest one (breadth first), all of the way next to it and not at all `k`
/// rings out, for each `k` of [`RETREAT_RINGS`] (see [`ramp_best`]). Returns the faces
/// that could have changed.
fn retreat_from_exact(
    mesh: &crate::mesh::Mesh,
    positions: &mut [DVec3],
    rest: &[[f64; 3]],
    movable: &dyn Fn(usize) -> bool,
    exact: &dyn Fn(usize, DVec3) -> Option<DVec3>,
    faces: &[crate::handle::FaceId],
) -> Vec<crate::handle::FaceId> {
    let mut sources: Vec<usize> = faces
        .iter()
        .filter(|&&f| turned_at(positions, rest, corners(mesh, f)))
        .flat_map(|&f| corners(mesh, f))
        .filter(|&i| !movable(i) && rest_of(rest, i).is_some_and(|r| exact(i, r).is_some()))
        .collect();
    sources.sort_unstable();
    sources.dedup();
    let depth = RETREAT_RINGS[RETREAT_RINGS.len() - 1];
    let reached = rings(mesh, sources, movable, rest, depth);
    // Where each vertex goes all of the way: its nearest source's motion of its rest.
    let targets: Vec<DVec3> = reached
        .iter()
        .map(|&(i, _, source)| {
            let at_rest = rest_of(rest, i).unwrap_or(positions[i]);
            exact(source, at_rest)
                .filter(|t| t.is_finite())
                .unwrap_or(positions[i])
        })
        .collect();
    ramp_best(mesh, positions, rest, &reached, &targets, &RETREAT_RINGS)
}

/// For each face of `faces` still turned over (in order): the movable vertices up to `k`
/// rings from its movable corners are drawn back towards where they were before the
/// edit, all of the way at the corners and not at all `k` rings out, for each `k` of
/// [`AROUND_RINGS`] (see [`ramp_best`]), until [`MAX_RETREAT_WORK`] vertices were
/// ramped. What [`retreat_from_exact`] leaves: a fold beside vertices that moved
/// exactly, or between interpolated ones. Returns the faces that could have changed.
fn retreat_around(
    mesh: &crate::mesh::Mesh,
    positions: &mut [DVec3],
    rest: &[[f64; 3]],
    movable: &dyn Fn(usize) -> bool,
    faces: &[crate::handle::FaceId],
) -> Vec<crate::handle::FaceId> {
    let depth = AROUND_RINGS[AROUND_RINGS.len() - 1];
    let mut work = 0usize;
    let mut touched = Vec::new();
    for &face in faces {
        if work > MAX_RETREAT_WORK {
            break;
        }
        if !turned_at(positions, rest, corners(mesh, face)) {
            continue;
        }
        let from: Vec<usize> = corners(mesh, face)
            .into_iter()
            .filter(|&i| movable(i) && rest_of(rest, i).is_some())
            .collect();
        let reached = rings(mesh, from, movable, rest, depth);
        work += reached.len();
        let targets: Vec<DVec3> = reached
            .iter()
            .map(|&(i, _, _)| rest_of(rest, i).unwrap_or(positions[i]))
            .collect();
        touched.extend(ramp_best(
            mesh,
            positions,
            rest,
            &reached,
            &targets,
            &AROUND_RINGS,
        ));
    }
    touched
}

/// For each face of `faces` still turned over (in order), each of its movable corners is
/// moved towards the centroid of its neighbours (a quarter, half, three quarters or all
/// of the way) or to a point of its star's kernel near it ([`into_kernel`]; the
/// centroid is outside it when the star is not convex), keeping the move that turns the
/// fewest faces around it over if fewer than before: the untangling step, for a fold
/// that no displacement ramp undoes.
fn untangle(
    mesh: &crate::mesh::Mesh,
    positions: &mut [DVec3],
    rest: &[[f64; 3]],
    movable: &dyn Fn(usize) -> bool,
    faces: &[crate::handle::FaceId],
) {
    for &face in faces {
        if !turned_at(positions, rest, corners(mesh, face)) {
            continue;
        }
        for i in corners(mesh, face) {
            let Some(v) = mesh.vertex_at(i).filter(|_| movable(i)) else {
                continue;
            };
            let (mut sum, mut n) = (DVec3::ZERO, 0usize);
            for w in mesh.adjacent_vertices(v) {
                sum += positions[mesh.vertex_index(w)];
                n += 1;
            }
            let centroid = sum / n.max(1) as f64;
            if n == 0 || !centroid.is_finite() {
                continue;
            }
            let fan: Vec<crate::handle::FaceId> = mesh.adjacent_faces(v).collect();
            let count = |positions: &[DVec3]| count_turned(mesh, positions, rest, &fan);
            let now = positions[i];
            let mut best = (count(positions), now);
            let kernel = into_kernel(mesh, positions, rest, i, &fan);
            let candidates = [0.25, 0.5, 0.75, 1.0]
                .map(|t| now + t * (centroid - now))
                .into_iter()
                .chain(kernel);
            for candidate in candidates {
                positions[i] = candidate;
                let turned = count(positions);
                if turned < best.0 {
                    best = (turned, candidate);
                }
            }
            positions[i] = best.1;
        }
    }
}

/// A point near vertex `i`'s position (reached from it by cyclic projections, at most
/// [`KERNEL_SWEEPS`] sweeps) where every face of its `fan` points the way it did before
/// the edit, with a small margin. With its neighbours fixed, face `(i, a, b)`'s normal
/// dotted with its normal before the edit `r` is `r · (a × b) + (r × (b − a)) · p`,
/// linear in `i`'s position `p`: each face is a half-space, and the point is in their
/// intersection (the kernel of the vertex's star). `None` when the projections do not
/// reach it (the kernel is empty or thin) or a value is not finite.
fn into_kernel(
    mesh: &crate::mesh::Mesh,
    positions: &[DVec3],
    rest: &[[f64; 3]],
    i: usize,
    fan: &[crate::handle::FaceId],
) -> Option<DVec3> {
    // Each face as (g, h): g · p + h is its normal now dotted with its normal before.
    let mut halfspaces = Vec::with_capacity(fan.len());
    for &f in fan {
        let c = corners(mesh, f);
        let k = c.iter().position(|&j| j == i)?;
        let (a, b) = (c[(k + 1) % 3], c[(k + 2) % 3]);
        // The normal before the edit: (a − i) × (b − i), the order of the face's corners.
        let (ri, ra, rb) = (rest_of(rest, i)?, rest_of(rest, a)?, rest_of(rest, b)?);
        let r = (ra - ri).cross(rb - ri);
        let (pa, pb) = (positions[a], positions[b]);
        let g = r.cross(pb - pa);
        let h = r.dot(pa.cross(pb));
        // Margin: a fortieth of the face's size now, in the dot product's units.
        let margin = 0.025 * r.length() * (pb - pa).length_squared();
        halfspaces.push((g, h, margin));
    }
    let mut p = positions[i];
    for _ in 0..KERNEL_SWEEPS {
        let mut inside = true;
        for &(g, h, margin) in &halfspaces {
            let value = g.dot(p) + h;
            if value < margin {
                inside = false;
                // Onto twice the margin, so that rounding does not leave it just short.
                let g2 = g.length_squared();
                if g2 > 0.0 {
                    p += ((2.0 * margin - value) / g2) * g;
                }
            }
        }
        if inside {
            return p.is_finite().then_some(p);
        }
    }
    None
}

/// Sweeps of cyclic projections [`into_kernel`] makes at most.
const KERNEL_SWEEPS: usize = 64;

/// The faces around the vertex slots `vertices`, each once, in face order.
fn faces_around(
    mesh: &crate::mesh::Mesh,
    vertices: impl Iterator<Item = usize>,
) -> Vec<crate::handle::FaceId> {
    let mut faces: Vec<crate::handle::FaceId> = vertices
        .filter_map(|i| mesh.vertex_at(i))
        .flat_map(|v| mesh.adjacent_faces(v))
        .collect();
    sort_faces(mesh, &mut faces);
    faces
}

/// Sorts `faces` by face index and drops repeats: for a list that is a large part of
/// the mesh, by a bit per face slot (linear), else by sorting.
fn sort_faces(mesh: &crate::mesh::Mesh, faces: &mut Vec<crate::handle::FaceId>) {
    let slots = mesh.face_slots();
    if faces.len() < slots / 16 {
        faces.sort_unstable_by_key(|&f| mesh.face_index(f));
        faces.dedup();
        return;
    }
    let mut bits = vec![0u64; slots.div_ceil(64)];
    for &f in faces.iter() {
        let i = mesh.face_index(f);
        bits[i / 64] |= 1 << (i % 64);
    }
    faces.clear();
    for (w, &word) in bits.iter().enumerate() {
        let mut word = word;
        while word != 0 {
            let i = 64 * w + word.trailing_zeros() as usize;
            word &= word - 1;
            faces.extend(mesh.face_at(i));
        }
    }
}

/// How many of `faces` are turned over at `positions` against `rest`.
fn count_turned(
    mesh: &crate::mesh::Mesh,
    positions: &[DVec3],
    rest: &[[f64; 3]],
    faces: &[crate::handle::FaceId],
) -> usize {
    faces
        .iter()
        .filter(|&&f| turned_at(positions, rest, corners(mesh, f)))
        .count()
}

/// The vertex slots of face `f`'s corners.
#[inline]
fn corners(mesh: &crate::mesh::Mesh, f: crate::handle::FaceId) -> [usize; 3] {
    mesh.triangle(f).map(|v| mesh.vertex_index(v))
}

/// Where vertex `i` was before the edit.
#[inline]
fn rest_of(rest: &[[f64; 3]], i: usize) -> Option<DVec3> {
    rest.get(i).map(|&p| DVec3::from_array(p))
}

/// The movable vertices (with a position in `rest`) up to `depth` rings from the
/// vertices `from`, breadth first: `(vertex, ring, the vertex of from it was reached
/// from)`, a movable vertex of `from` itself at ring 0.
fn rings(
    mesh: &crate::mesh::Mesh,
    from: Vec<usize>,
    movable: &dyn Fn(usize) -> bool,
    rest: &[[f64; 3]],
    depth: usize,
) -> Vec<(usize, usize, usize)> {
    let mut origin: std::collections::HashMap<usize, usize> =
        from.iter().map(|&i| (i, i)).collect();
    let mut reached: Vec<(usize, usize, usize)> = from
        .iter()
        .filter(|&&i| movable(i))
        .map(|&i| (i, 0, i))
        .collect();
    let mut frontier = from;
    for ring in 1..=depth {
        let mut next = Vec::new();
        for &i in &frontier {
            let Some(v) = mesh.vertex_at(i) else { continue };
            let source = origin[&i];
            for w in mesh.adjacent_vertices(v) {
                let j = mesh.vertex_index(w);
                if movable(j) && j < rest.len() && !origin.contains_key(&j) {
                    origin.insert(j, source);
                    next.push(j);
                    reached.push((j, ring, source));
                }
            }
        }
        next.sort_unstable();
        frontier = next;
    }
    reached
}

/// Draws the vertices `reached` (from [`rings`]) towards their `targets` by a ramp: at
/// ring `r < k` a vertex keeps `r / k` of the way from its target to where it is, beyond
/// it stays. Tries each `k` of `depths` and keeps the one that turns the fewest faces
/// around those vertices over, if fewer than before; else nothing changes. Returns the
/// faces around the vertices `reached` (those counted).
fn ramp_best(
    mesh: &crate::mesh::Mesh,
    positions: &mut [DVec3],
    rest: &[[f64; 3]],
    reached: &[(usize, usize, usize)],
    targets: &[DVec3],
    depths: &[usize],
) -> Vec<crate::handle::FaceId> {
    if reached.is_empty() {
        return Vec::new();
    }
    let fan = faces_around(mesh, reached.iter().map(|&(i, _, _)| i));
    let count = |positions: &[DVec3]| count_turned(mesh, positions, rest, &fan);
    let original: Vec<DVec3> = reached.iter().map(|&(i, _, _)| positions[i]).collect();
    let ramp = |positions: &mut [DVec3], k: Option<usize>| {
        for ((&(i, ring, _), &p), &t) in reached.iter().zip(&original).zip(targets) {
            positions[i] = match k {
                Some(k) if ring < k => t + (ring as f64 / k as f64) * (p - t),
                _ => p,
            };
        }
    };
    let mut best = (count(positions), None);
    for &k in depths {
        ramp(positions, Some(k));
        let now = count(positions);
        if now < best.0 {
            best = (now, Some(k));
        }
    }
    ramp(positions, best.1);
    fan
}

/// True when the triangle of vertex slots `[a, b, c]` is turned over at `positions`
/// against `rest`: its normals now and before the edit point apart (false when a
/// position before the edit is missing).
#[inline]
fn turned_at(positions: &[DVec3], rest: &[[f64; 3]], [a, b, c]: [usize; 3]) -> bool {
    let rest_of = |i: usize| rest.get(i).map(|&p| DVec3::from_array(p));
    let (Some(ra), Some(rb), Some(rc)) = (rest_of(a), rest_of(b), rest_of(c)) else {
        return false;
    };
    let now = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
    let then = (rb - ra).cross(rc - ra);
    now.dot(then) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps after the relaxation, in the order the unfolding runs them.
    fn retreat(
        mesh: &crate::mesh::Mesh,
        positions: &mut [DVec3],
        rest: &[[f64; 3]],
        movable: &dyn Fn(usize) -> bool,
        faces: &[crate::handle::FaceId],
    ) {
        let still = |i: usize, p: DVec3| (!movable(i)).then_some(p);
        untangle_what_is_left(mesh, positions, rest, movable, &still, faces.to_vec());
    }

    /// Faces of `mesh` turned over at `positions` against `rest`.
    fn turned(
        mesh: &crate::mesh::Mesh,
        positions: &[DVec3],
        rest: &[[f64; 3]],
    ) -> Vec<crate::handle::FaceId> {
        mesh.faces()
            .filter(|&f| turned_at(positions, rest, corners(mesh, f)))
            .collect()
    }

    /// Asserts that the vertices `movable` rejects are bit for bit as in `before`.
    fn assert_unmoved(positions: &[DVec3], before: &[DVec3], movable: &dyn Fn(usize) -> bool) {
        for (i, (&p, &q)) in positions.iter().zip(before).enumerate() {
            if !movable(i) {
                assert_eq!(
                    p.to_array().map(f64::to_bits),
                    q.to_array().map(f64::to_bits),
                    "{i}"
                );
            }
        }
    }

    #[test]
    fn a_steep_step_next_to_still_vertices_is_spread_over_a_ramp() {
        // A flat grid of spacing 1/40: the strip x < 0.25 stays, everything else is
        // pushed by 0.3 (twelve columns) towards it: the faces between the two turn
        // over, and only a ramp of more than twelve rings unfolds them.
        let mesh = crate::generators::grid(41, 41, 1.0, 1.0);
        let rest: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
        let movable = |i: usize| rest[i][0] >= 0.25;
        let mut positions: Vec<DVec3> = mesh
            .positions()
            .iter()
            .map(|&p| if p.x >= 0.25 { p - DVec3::X * 0.3 } else { p })
            .collect();
        let faces = turned(&mesh, &positions, &rest);
        assert!(!faces.is_empty());
        let still: Vec<DVec3> = positions.clone();
        retreat(&mesh, &mut positions, &rest, &movable, &faces);
        assert_eq!(
            turned(&mesh, &positions, &rest).len(),
            0,
            "{} turned before",
            faces.len()
        );
        assert_unmoved(&positions, &still, &movable);
        // Beyond the ramp (sixteen rings, x < 0.65) the push is kept.
        let far = positions
            .iter()
            .zip(&rest)
            .filter(|(_, r)| r[0] > 0.9)
            .all(|(p, r)| (p.x - (r[0] - 0.3)).abs() < 1e-12);
        assert!(far);
    }

    #[test]
    fn faces_a_ramp_turns_over_further_out_are_worked_on_too() {
        // The steep step of the test above, and further out (x in 0.45..0.5, on the row
        // y = 0.5 and the one beside it) a push that grows by 0.9 of the distance, which
        // leaves the faces there thin but not turned. The ramp that unfolds the step
        // scales the push down by ring, which turns some of those faces over (fewer than
        // it unfolds): the later steps must take them too, not only the faces turned
        // before the ramp.
        let mesh = crate::generators::grid(41, 41, 1.0, 1.0);
        let rest: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
        let movable = |i: usize| rest[i][0] >= 0.25;
        let push = |p: DVec3| {
            let bump = if (p.y - 0.5).abs() < 0.02 {
                0.9 * (p.x.clamp(0.45, 0.5) - 0.45)
            } else {
                0.0
            };
            -(0.3 + bump)
        };
        let edited: Vec<DVec3> = mesh
            .positions()
            .iter()
            .map(|&p| {
                if p.x >= 0.25 {
                    p + DVec3::X * push(p)
                } else {
                    p
                }
            })
            .collect();
        let faces = turned(&mesh, &edited, &rest);
        assert!(!faces.is_empty());
        // The ramp alone: the step unfolds, faces further out turn over.
        let mut ramped = edited.clone();
        let still = |i: usize, p: DVec3| (!movable(i)).then_some(p);
        retreat_from_exact(&mesh, &mut ramped, &rest, &movable, &still, &faces);
        let after_ramp = turned(&mesh, &ramped, &rest);
        assert!(after_ramp.iter().all(|f| !faces.contains(f)));
        assert!(!after_ramp.is_empty() && after_ramp.len() < faces.len());
        // All the steps: the later ones unfold some of those.
        let mut positions = edited.clone();
        retreat(&mesh, &mut positions, &rest, &movable, &faces);
        let left = turned(&mesh, &positions, &rest).len();
        assert!(
            left < after_ramp.len(),
            "{left} turned at the end, {} after the ramp",
            after_ramp.len()
        );
        assert_unmoved(&positions, &edited, &movable);
    }

    #[test]
    fn a_fold_no_ramp_can_undo_is_left_as_it_is() {
        // The vertices that may not move (x <= 0.5) are the ones mirrored across: no
        // ramp of the movable ones undoes that; the count never grows and the others
        // stay bit for bit.
        let mesh = crate::generators::grid(6, 6, 1.0, 1.0);
        let rest: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
        let movable = |i: usize| rest[i][0] > 0.5;
        let mut positions: Vec<DVec3> = mesh
            .positions()
            .iter()
            .map(|&p| {
                if p.x <= 0.5 {
                    DVec3::new(1.5 - p.x, p.y, p.z)
                } else {
                    p
                }
            })
            .collect();
        let faces = turned(&mesh, &positions, &rest);
        assert!(!faces.is_empty());
        let edited = positions.clone();
        retreat(&mesh, &mut positions, &rest, &movable, &faces);
        assert!(turned(&mesh, &positions, &rest).len() <= faces.len());
        assert_unmoved(&positions, &edited, &movable);
    }

    #[test]
    fn a_vertex_thrown_across_its_ring_far_from_where_it_was_is_untangled() {
        // Everything moved far (5 units) and is movable, and one vertex is thrown across
        // its ring: drawing it back towards where it was before the edit folds more, but
        // its neighbours' centroid unfolds it. Nothing else moves.
        let mesh = crate::generators::grid(10, 10, 1.0, 1.0);
        let rest: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
        let movable = |_: usize| true;
        let shift = DVec3::new(5.0, 0.0, 0.0);
        let mut positions: Vec<DVec3> = mesh.positions().iter().map(|&p| p + shift).collect();
        let thrown = 5 * 11 + 5;
        positions[thrown] += DVec3::new(0.25, 0.0, 0.0);
        let faces = turned(&mesh, &positions, &rest);
        assert!(!faces.is_empty());
        let edited = positions.clone();
        retreat(&mesh, &mut positions, &rest, &movable, &faces);
        assert!(turned(&mesh, &positions, &rest).is_empty());
        assert_unmoved(&positions, &edited, &|i| i == thrown);
    }

    #[test]
    fn a_vertex_whose_star_turned_reflex_is_projected_into_its_kernel() {
        // A hexagon fan; now one neighbour is pulled in past the centre, so the star is
        // no longer convex and its centroid lies outside the kernel: the centre vertex,
        // at rest or at the centroid, turns a face over. Projecting it into the kernel
        // (the half-spaces of its faces) unfolds the fan; the ring stays.
        let rest: Vec<DVec3> = std::iter::once(DVec3::ZERO)
            .chain((0..6).map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 6.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            }))
            .collect();
        let triangles: Vec<[u32; 3]> = (0..6u32).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let mesh = crate::mesh::Mesh::from_triangles(&rest, &triangles)
            .unwrap()
            .0;
        let rest: Vec<[f64; 3]> = rest.iter().map(|p| p.to_array()).collect();
        let mut positions: Vec<DVec3> = rest.iter().map(|&p| DVec3::from_array(p)).collect();
        positions[6] = DVec3::new(0.3, 0.5, 0.0);
        let faces = turned(&mesh, &positions, &rest);
        assert_eq!(faces.len(), 1);
        let movable = |i: usize| i == 0;
        let centroid = positions[1..].iter().sum::<DVec3>() / 6.0;
        let mut at_centroid = positions.clone();
        at_centroid[0] = centroid;
        assert!(!turned(&mesh, &at_centroid, &rest).is_empty());
        let edited = positions.clone();
        untangle(&mesh, &mut positions, &rest, &movable, &faces);
        assert!(
            turned(&mesh, &positions, &rest).is_empty(),
            "{}",
            positions[0]
        );
        assert_unmoved(&positions, &edited, &movable);
    }
}
