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
//! turn the fewest faces over are kept (the positions as they were when none turns fewer).

use glam::DVec3;

use super::{DetailMode, Hierarchy, IN_REGION};

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
    /// neighbours', keeping the round that turns the fewest faces over; vertices outside
    /// every region and vertices moved exactly by an affine or field mark stay bit for
    /// bit (see the coarse edits guide). A walk finer
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
        let mut positions = std::mem::take(&mut self.mesh.positions);
        let rest = &self.rests[k].positions;
        let mesh = &self.mesh;
        let marks = &self.marks;
        let rest_of = |i: usize| rest.get(i).map(|&p| DVec3::from_array(p));
        let movable = |i: usize| marks.of(i) == IN_REGION && rest_of(i).is_some();
        let turned = |positions: &[DVec3], f: crate::FaceId| -> bool {
            turned_at(
                positions,
                rest,
                mesh.triangle(f).map(|v| mesh.vertex_index(v)),
            )
        };
        // Every face once, on all threads: those with an interpolated vertex of a region
        // that are turned over (in face order, so the same on any number of threads).
        let flipped: Vec<crate::FaceId> = {
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
        let mut grown: Vec<usize> = flipped
            .iter()
            .flat_map(|&f| mesh.triangle(f))
            .map(|v| mesh.vertex_index(v))
            .collect();
        let mut sets: Vec<Vec<usize>> = Vec::with_capacity(DEPTHS.len());
        for ring in 1..=DEPTHS[DEPTHS.len() - 1] {
            let next: Vec<usize> = grown
                .iter()
                .filter_map(|&i| mesh.vertex_at(i))
                .flat_map(|v| mesh.adjacent_vertices(v))
                .map(|w| mesh.vertex_index(w))
                .collect();
            grown.extend(next);
            grown.sort_unstable();
            grown.dedup();
            if DEPTHS.contains(&ring) {
                sets.push(grown.iter().copied().filter(|&i| movable(i)).collect());
            }
        }
        let deepest = &sets[sets.len() - 1];
        // The faces around a set of vertices: the only ones whose turn relaxing them
        // changes.
        let around = |set: &[usize]| -> Vec<crate::FaceId> {
            let mut faces: Vec<crate::FaceId> = set
                .iter()
                .filter_map(|&i| mesh.vertex_at(i))
                .flat_map(|v| mesh.adjacent_faces(v))
                .collect();
            faces.sort_unstable_by_key(|&f| mesh.face_index(f));
            faces.dedup();
            faces
        };
        let count = |faces: &[crate::FaceId], positions: &[DVec3]| {
            faces.iter().filter(|&&f| turned(positions, f)).count()
        };
        let original: Vec<DVec3> = deepest.iter().map(|&i| positions[i]).collect();
        let put = |positions: &mut [DVec3], values: &[DVec3]| {
            for (&i, &p) in deepest.iter().zip(values) {
                positions[i] = p;
            }
        };
        // Turned faces, counted as the change from the original around each depth's set
        // (faces further out are as they were whatever the depth).
        let mut best: (isize, Vec<DVec3>) = (0, original.clone());
        let mut unfolded = false;
        for relaxed in &sets {
            put(&mut positions, &original);
            let faces = around(relaxed);
            let base = count(&faces, &positions) as isize;
            let rounds = MAX_ROUNDS.min((MAX_WORK / relaxed.len().max(1)).max(MIN_ROUNDS));
            let mut since_best = 0;
            for _ in 0..rounds {
                let moved: Vec<Option<DVec3>> = relaxed
                    .iter()
                    .map(|&i| {
                        let v = mesh.vertex_at(i)?;
                        let (mut sum, mut n) = (DVec3::ZERO, 0usize);
                        for w in mesh.adjacent_vertices(v) {
                            let j = mesh.vertex_index(w);
                            sum += positions[j] - rest_of(j)?;
                            n += 1;
                        }
                        let at_rest = rest_of(i)?;
                        (n > 0).then(|| at_rest + sum / n as f64)
                    })
                    .collect();
                for (&i, p) in relaxed.iter().zip(&moved) {
                    if let Some(p) = p.filter(|p| p.is_finite()) {
                        positions[i] = p;
                    }
                }
                let now = count(&faces, &positions);
                let change = now as isize - base;
                if change < best.0 {
                    best = (change, deepest.iter().map(|&i| positions[i]).collect());
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
            if unfolded {
                break;
            }
        }
        put(&mut positions, &best.1);
        self.mesh.positions = positions;
    }
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
