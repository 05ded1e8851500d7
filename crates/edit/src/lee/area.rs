//! The editing area (Lee 1999, §3.2): a closed region of the mesh homeomorphic to a disk,
//! given by picked boundary vertices joined by shortest edge paths, filled on one side,
//! and optionally grown by picked adjacent faces.

use std::collections::{HashMap, HashSet, VecDeque};

use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};
use rayon::prelude::*;

use crate::lee::error::{LeeError, Result};

/// Which side of the boundary loop is the editing area.
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes* §3.2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AreaSide {
    /// The side with the smaller surface area (the default).
    #[default]
    Smaller,
    /// The side containing this vertex (not on the loop).
    Vertex(VertexId),
    /// The side containing this face.
    Face(FaceId),
}

/// An editing area: a set of faces forming a topological disk that does not touch the
/// mesh boundary (Lee 1999, §3.2), with a dense local numbering of its vertices.
///
/// Local vertex order: the interior vertices first, sorted by
/// [`Mesh::vertex_index`], then the boundary vertices in loop order, counter-clockwise
/// around the area (the area on the left, as the faces are oriented).
#[derive(Clone, Debug)]
pub struct EditingArea {
    faces: Vec<FaceId>,
    vertices: Vec<VertexId>,
    n_interior: usize,
    local_of_slot: Vec<u32>,
    picks: Vec<VertexId>,
    binding: halfedge::Binding,
}

const NONE: u32 = u32::MAX;

impl EditingArea {
    /// The area bounded by the closed loop of shortest edge paths through `picks` (in
    /// order, the last joined to the first), filled on `side` (Lee 1999, §3.2).
    ///
    /// # Errors
    /// Kernel errors for bad picks or an impossible loop; [`LeeError::LoopDoesNotSeparate`],
    /// [`LeeError::SeedOnLoop`], [`LeeError::SeedNotBesideLoop`], and every error of
    /// [`from_faces`](Self::from_faces) when the filled side is not a disk.
    pub fn from_picks(mesh: &Mesh, picks: &[VertexId], side: AreaSide) -> Result<Self> {
        for &v in picks {
            mesh.ensure_vertex(v)?;
        }
        let loop_halfedges = mesh.closed_loop_through(picks)?;
        let (region, count) = mesh.face_regions(&loop_halfedges);
        let region_of = |h: HalfedgeId| mesh.face(h).map(|f| region[mesh.face_index(f)]);
        let mut left = Vec::new();
        let mut right = Vec::new();
        for &h in &loop_halfedges {
            if let Some(r) = region_of(h) {
                if !left.contains(&r) {
                    left.push(r);
                }
            }
            if let Some(r) = region_of(mesh.opposite(h)) {
                if !right.contains(&r) {
                    right.push(r);
                }
            }
        }
        if left.iter().any(|r| right.contains(r)) {
            return Err(LeeError::LoopDoesNotSeparate);
        }
        let candidates: Vec<u32> = left.iter().chain(&right).copied().collect();
        let chosen = match side {
            AreaSide::Vertex(v) => {
                mesh.ensure_vertex(v)?;
                let on_loop = loop_halfedges.iter().any(|&h| mesh.from_vertex(h) == v);
                if on_loop {
                    return Err(LeeError::SeedOnLoop(v));
                }
                let f = mesh
                    .adjacent_faces(v)
                    .next()
                    .ok_or(LeeError::SeedNotBesideLoop)?;
                region[mesh.face_index(f)]
            }
            AreaSide::Face(f) => {
                mesh.ensure_face(f)?;
                region[mesh.face_index(f)]
            }
            AreaSide::Smaller => {
                let mut area = vec![0.0; count as usize];
                for f in mesh.faces() {
                    area[region[mesh.face_index(f)] as usize] += mesh.face_area(f);
                }
                *candidates
                    .iter()
                    .min_by(|&&a, &&b| area[a as usize].total_cmp(&area[b as usize]))
                    .ok_or(LeeError::LoopDoesNotSeparate)?
            }
        };
        if !candidates.contains(&chosen) {
            return Err(LeeError::SeedNotBesideLoop);
        }
        let faces: Vec<FaceId> = mesh
            .faces()
            .filter(|&f| region[mesh.face_index(f)] == chosen)
            .collect();
        let mut area = Self::from_faces(mesh, &faces)?;
        area.picks = picks.to_vec();
        Ok(area)
    }

    /// The area made of `faces` (duplicates ignored), checked to be a topological disk
    /// that does not touch the mesh boundary.
    ///
    /// # Errors
    /// [`halfedge::Error::InvalidHandle`] (as `LeeError::Mesh`), [`LeeError::AreaEmpty`],
    /// [`LeeError::AreaTouchesMeshBoundary`], [`LeeError::AreaPinched`],
    /// [`LeeError::AreaNotDisk`].
    pub fn from_faces(mesh: &Mesh, faces: &[FaceId]) -> Result<Self> {
        let mut in_area = vec![false; mesh.face_slots()];
        let mut list = Vec::with_capacity(faces.len());
        for &f in faces {
            mesh.ensure_face(f)?;
            let slot = &mut in_area[mesh.face_index(f)];
            if !*slot {
                *slot = true;
                list.push(f);
            }
        }
        if list.is_empty() {
            return Err(LeeError::AreaEmpty);
        }
        let inside = |h: HalfedgeId| mesh.face(h).is_some_and(|f| in_area[mesh.face_index(f)]);

        // Vertices, and the inner halfedges of the area's boundary (area face on the left).
        let mut seen = vec![false; mesh.vertex_slots()];
        let mut all_vertices = Vec::new();
        let mut boundary_out: Vec<Option<HalfedgeId>> = vec![None; mesh.vertex_slots()];
        let mut n_boundary_halfedges = 0usize;
        for &f in &list {
            for h in mesh.face_halfedges(f) {
                let v = mesh.from_vertex(h);
                let vi = mesh.vertex_index(v);
                if !seen[vi] {
                    seen[vi] = true;
                    all_vertices.push(v);
                }
                let o = mesh.opposite(h);
                if mesh.is_boundary_halfedge(o) {
                    return Err(LeeError::AreaTouchesMeshBoundary { vertex: v });
                }
                if !inside(o) {
                    if boundary_out[vi].is_some() {
                        return Err(LeeError::AreaPinched { vertex: v });
                    }
                    boundary_out[vi] = Some(h);
                    n_boundary_halfedges += 1;
                }
            }
        }

        // Boundary loops.
        let mut loops: Vec<Vec<VertexId>> = Vec::new();
        let mut walked = vec![false; mesh.vertex_slots()];
        for &v in &all_vertices {
            let vi = mesh.vertex_index(v);
            if boundary_out[vi].is_none() || walked[vi] {
                continue;
            }
            let mut boundary = Vec::new();
            let mut u = v;
            loop {
                let ui = mesh.vertex_index(u);
                if walked[ui] {
                    break;
                }
                walked[ui] = true;
                boundary.push(u);
                match boundary_out[ui] {
                    Some(h) => u = mesh.to_vertex(h),
                    None => break,
                }
            }
            loops.push(boundary);
        }

        // Edge-connected components of the faces.
        let mut component_seen = vec![false; mesh.face_slots()];
        let mut components = 0usize;
        let mut stack = Vec::new();
        for &f in &list {
            if component_seen[mesh.face_index(f)] {
                continue;
            }
            components += 1;
            component_seen[mesh.face_index(f)] = true;
            stack.push(f);
            while let Some(g) = stack.pop() {
                for h in mesh.face_halfedges(g) {
                    let o = mesh.opposite(h);
                    if let Some(n) = mesh.face(o).filter(|n| in_area[mesh.face_index(*n)]) {
                        let s = &mut component_seen[mesh.face_index(n)];
                        if !*s {
                            *s = true;
                            stack.push(n);
                        }
                    }
                }
            }
        }

        let n_faces = list.len();
        let n_edges = (3 * n_faces + n_boundary_halfedges) / 2;
        let euler = all_vertices.len() as i64 - n_edges as i64 + n_faces as i64;
        if loops.len() != 1 || components != 1 || euler != 1 {
            return Err(LeeError::AreaNotDisk {
                boundary_loops: loops.len(),
                components,
                euler,
            });
        }
        let boundary = loops.pop().expect("one loop");

        let mut interior: Vec<VertexId> = all_vertices
            .iter()
            .copied()
            .filter(|&v| boundary_out[mesh.vertex_index(v)].is_none())
            .collect();
        interior.sort_unstable_by_key(|&v| mesh.vertex_index(v));
        let n_interior = interior.len();
        let mut vertices = interior;
        vertices.extend(boundary);
        let mut local_of_slot = vec![NONE; mesh.vertex_slots()];
        for (i, &v) in vertices.iter().enumerate() {
            local_of_slot[mesh.vertex_index(v)] = i as u32;
        }
        Ok(Self {
            faces: list,
            vertices,
            n_interior,
            local_of_slot,
            picks: Vec::new(),
            binding: mesh.binding(),
        })
    }

    /// A geodesic-ish disk around `seed`: rings of vertices are added breadth-first until
    /// at least `vertex_count` vertices are reached; the area is the faces around the
    /// vertices of all rings but the last, with holes (pockets of faces the rings enclose)
    /// filled. Handy for examples and benches.
    ///
    /// # Errors
    /// [`halfedge::Error::InvalidHandle`] (as `LeeError::Mesh`); the errors of [`from_faces`](Self::from_faces) when
    /// the rings wrap around a handle or reach the mesh boundary.
    pub fn disk_around(mesh: &Mesh, seed: VertexId, vertex_count: usize) -> Result<Self> {
        mesh.ensure_vertex(seed)?;
        // Rings and faces kept by slot in hash maps: the work and memory follow the disk,
        // not the mesh (at a coarse level of a large hierarchy the slots are many times
        // the live elements).
        let mut ring: HashMap<usize, u32> = HashMap::from([(mesh.vertex_index(seed), 0)]);
        let mut queue = VecDeque::from([seed]);
        let mut order = Vec::new();
        let mut last_ring = 0;
        while let Some(v) = queue.pop_front() {
            let r = ring[&mesh.vertex_index(v)];
            if order.len() >= vertex_count.max(1) && r > last_ring {
                break;
            }
            last_ring = r;
            order.push(v);
            for w in mesh.adjacent_vertices(v) {
                ring.entry(mesh.vertex_index(w)).or_insert_with(|| {
                    queue.push_back(w);
                    r + 1
                });
            }
        }
        let mut in_area: HashSet<usize> = HashSet::new();
        for &v in &order {
            if ring[&mesh.vertex_index(v)] < last_ring.max(1) {
                in_area.extend(mesh.adjacent_faces(v).map(|f| mesh.face_index(f)));
            }
        }
        fill_pockets(mesh, &mut in_area);
        let mut slots: Vec<usize> = in_area.into_iter().collect();
        slots.sort_unstable();
        let faces: Vec<FaceId> = slots.into_iter().filter_map(|i| mesh.face_at(i)).collect();
        Self::from_faces(mesh, &faces)
    }

    /// This area grown by `faces`, each of which must share an edge with the area or with
    /// a face added before it in the list (Lee 1999, §3.2). Picks are kept.
    ///
    /// # Errors
    /// [`LeeError::FaceNotAdjacent`], and the errors of [`from_faces`](Self::from_faces)
    /// when the result is not a disk.
    pub fn grown(&self, mesh: &Mesh, faces: &[FaceId]) -> Result<Self> {
        self.check_mesh(mesh)?;
        let mut in_area = vec![false; mesh.face_slots()];
        for &f in &self.faces {
            in_area[mesh.face_index(f)] = true;
        }
        let mut all = self.faces.clone();
        for &f in faces {
            mesh.ensure_face(f)?;
            if in_area[mesh.face_index(f)] {
                continue;
            }
            let adjacent = mesh.face_neighbors(f).any(|g| in_area[mesh.face_index(g)]);
            if !adjacent {
                return Err(LeeError::FaceNotAdjacent { face: f });
            }
            in_area[mesh.face_index(f)] = true;
            all.push(f);
        }
        let mut area = Self::from_faces(mesh, &all)?;
        area.picks = self.picks.clone();
        Ok(area)
    }

    /// The faces of the area.
    #[must_use]
    pub fn faces(&self) -> &[FaceId] {
        &self.faces
    }

    /// All vertices in local order: interior ones, then the boundary loop.
    #[must_use]
    pub fn vertices(&self) -> &[VertexId] {
        &self.vertices
    }

    /// The interior vertices (sorted by vertex index): the ones an edit may move.
    #[must_use]
    pub fn interior(&self) -> &[VertexId] {
        &self.vertices[..self.n_interior]
    }

    /// The boundary loop, counter-clockwise around the area.
    #[must_use]
    pub fn boundary(&self) -> &[VertexId] {
        &self.vertices[self.n_interior..]
    }

    /// Number of interior vertices.
    #[must_use]
    pub fn n_interior(&self) -> usize {
        self.n_interior
    }

    /// The picked vertices the area was made from (empty for other constructors).
    #[must_use]
    pub fn picks(&self) -> &[VertexId] {
        &self.picks
    }

    /// The local index of `v` (see the type docs), if it is in the area.
    #[must_use]
    pub fn local_index(&self, mesh: &Mesh, v: VertexId) -> Option<usize> {
        if !mesh.is_valid_vertex(v) {
            return None;
        }
        match self.local_of_slot.get(mesh.vertex_index(v)) {
            Some(&i) if i != NONE && self.vertices[i as usize] == v => Some(i as usize),
            _ => None,
        }
    }

    /// True when `v` is in the area (interior or boundary).
    #[must_use]
    pub fn contains(&self, mesh: &Mesh, v: VertexId) -> bool {
        self.local_index(mesh, v).is_some()
    }

    /// True when `v` is on the area's boundary loop.
    #[must_use]
    pub fn is_boundary(&self, mesh: &Mesh, v: VertexId) -> bool {
        self.local_index(mesh, v)
            .is_some_and(|i| i >= self.n_interior)
    }

    /// Checks that `mesh` is the mesh the area was made on, at the same hierarchy level and
    /// with the same connectivity (see [`halfedge::Binding`]).
    ///
    /// # Errors
    /// [`LeeError::Stale`].
    pub fn check_mesh(&self, mesh: &Mesh) -> Result<()> {
        Ok(self.binding.check(mesh, "the editing area")?)
    }

    /// What the area was made for.
    pub(crate) fn binding(&self) -> halfedge::Binding {
        self.binding
    }

    /// Local triangles (three local indices each, in face orientation).
    pub(crate) fn local_triangles(&self, mesh: &Mesh) -> Vec<[u32; 3]> {
        self.faces
            .par_iter()
            .with_min_len(4096)
            .map(|&f| {
                mesh.triangle(f)
                    .map(|v| self.local_of_slot[mesh.vertex_index(v)])
            })
            .collect()
    }

    /// Local index by vertex slot, `u32::MAX` outside the area.
    pub(crate) fn local_of_slot(&self) -> &[u32] {
        &self.local_of_slot
    }
}

/// Adds to the area (face slots) its pockets: the groups of faces outside it (joined
/// through edges) that border it, all but the largest (ties to the group whose first
/// face slot comes last), which is the rest of the mesh. Groups that do not border the
/// area (other components) are left out.
///
/// The groups grow breadth-first from the faces beside the area, a few faces each in
/// turn, and merge where they meet; the growth stops once every group but one has no
/// face left to add and that one is already larger than each of the others. So the work
/// is about twice the pockets' faces, not the mesh's.
fn fill_pockets(mesh: &Mesh, in_area: &mut HashSet<usize>) {
    let mut seeds: Vec<usize> = in_area
        .iter()
        .filter_map(|&a| mesh.face_at(a))
        .flat_map(|f| mesh.face_neighbors(f))
        .map(|n| mesh.face_index(n))
        .filter(|n| !in_area.contains(n))
        .collect();
    seeds.sort_unstable();
    seeds.dedup();
    let mut groups: Vec<Pocket> = Vec::new();
    let mut label: HashMap<usize, usize> = HashMap::with_capacity(4 * seeds.len());
    for &s in &seeds {
        label.insert(s, groups.len());
        groups.push(Pocket {
            parent: groups.len(),
            queue: VecDeque::from([s]),
            faces: vec![s],
            first: s,
        });
    }
    fn root(groups: &mut [Pocket], mut g: usize) -> usize {
        while groups[g].parent != g {
            let up = groups[groups[g].parent].parent;
            groups[g].parent = up;
            g = up;
        }
        g
    }
    /// Faces a group adds in its turn.
    const TURN: usize = 32;
    let outside = loop {
        let roots: Vec<usize> = (0..groups.len())
            .filter(|&g| groups[g].parent == g)
            .collect();
        let growing: Vec<usize> = roots
            .iter()
            .copied()
            .filter(|&g| !groups[g].queue.is_empty())
            .collect();
        let done = roots
            .iter()
            .filter(|&&g| groups[g].queue.is_empty())
            .map(|&g| groups[g].faces.len())
            .max()
            .unwrap_or(0);
        match growing[..] {
            [] => {
                // Every group is whole: the largest, ties to the one whose first face
                // slot comes last.
                break roots
                    .iter()
                    .copied()
                    .max_by_key(|&g| (groups[g].faces.len(), groups[g].first));
            }
            [g] if groups[g].faces.len() > done => break Some(g),
            _ => {}
        }
        for g in growing {
            for _ in 0..TURN {
                // Merged into another group meanwhile: that one grows in its own turn.
                if groups[g].parent != g {
                    break;
                }
                let Some(f) = groups[g].queue.pop_front() else {
                    break;
                };
                let Some(face) = mesh.face_at(f) else {
                    continue;
                };
                // The group the face's neighbours join: `g`, or the group `g` joins.
                let mut into = g;
                for n in mesh.face_neighbors(face).map(|n| mesh.face_index(n)) {
                    if in_area.contains(&n) {
                        continue;
                    }
                    match label.get(&n) {
                        None => {
                            label.insert(n, into);
                            let group = &mut groups[into];
                            group.queue.push_back(n);
                            group.faces.push(n);
                            group.first = group.first.min(n);
                        }
                        Some(&h) => {
                            let h = root(&mut groups, h);
                            if h != into {
                                // The smaller group joins the larger.
                                let (big, small) =
                                    if groups[h].faces.len() > groups[into].faces.len() {
                                        (h, into)
                                    } else {
                                        (into, h)
                                    };
                                let moved = std::mem::take(&mut groups[small]);
                                let group = &mut groups[big];
                                group.queue.extend(moved.queue);
                                group.faces.extend(moved.faces);
                                group.first = group.first.min(moved.first);
                                groups[small].parent = big;
                                into = big;
                            }
                        }
                    }
                }
            }
        }
    };
    for (g, group) in groups.iter().enumerate() {
        if group.parent == g && Some(g) != outside {
            in_area.extend(group.faces.iter().copied());
        }
    }
}

/// A group of faces outside an area, growing from the faces beside it (see
/// [`fill_pockets`]).
#[derive(Default)]
struct Pocket {
    /// The group it was merged into (itself while it is a group of its own).
    parent: usize,
    /// Faces whose neighbours are still to be looked at.
    queue: VecDeque<usize>,
    /// Its faces (slots).
    faces: Vec<usize>,
    /// Its smallest face slot.
    first: usize,
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use halfedge::generators;

    /// The pocket fill as it was: flood fills of every face outside the area.
    fn fill_pockets_everywhere(mesh: &Mesh, in_area: &mut [bool]) {
        let mut group = vec![u32::MAX; mesh.face_slots()];
        let mut sizes: Vec<usize> = Vec::new();
        // Whether a group borders the area: groups that do not (other components of the
        // mesh) are neither pockets nor the outside.
        let mut touches: Vec<bool> = Vec::new();
        let mut stack = Vec::new();
        for f in mesh.faces() {
            let fi = mesh.face_index(f);
            if in_area[fi] || group[fi] != u32::MAX {
                continue;
            }
            let id = sizes.len() as u32;
            sizes.push(0);
            touches.push(false);
            group[fi] = id;
            stack.push(f);
            while let Some(g) = stack.pop() {
                sizes[id as usize] += 1;
                for n in mesh.face_neighbors(g) {
                    let ni = mesh.face_index(n);
                    if in_area[ni] {
                        touches[id as usize] = true;
                    } else if group[ni] == u32::MAX {
                        group[ni] = id;
                        stack.push(n);
                    }
                }
            }
        }
        let Some(largest) = (0..sizes.len())
            .filter(|&i| touches[i])
            .max_by_key(|&i| sizes[i])
        else {
            return;
        };
        for f in mesh.faces() {
            let fi = mesh.face_index(f);
            let g = group[fi];
            if !in_area[fi] && g != largest as u32 && touches[g as usize] {
                in_area[fi] = true;
            }
        }
    }

    /// The local pocket fill adds exactly the faces of the flood fill of every face
    /// outside the area: on a sphere, a torus, a bow-tie, a mesh with loose parts and a
    /// grid, for areas of random faces grown a few steps (many groups of every size,
    /// ties among them, areas that cut the mesh in two, areas of one face).
    #[test]
    fn pockets_filled_locally_are_those_of_flooding_every_outside_face() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut below = move |n: usize| -> usize {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let loose = {
            let mut small = generators::icosphere(1);
            for p in small.positions_mut() {
                *p = *p * 0.2 + DVec3::new(3.0, 0.0, 0.0);
            }
            generators::disjoint_union(&[&generators::icosphere(2), &small]).unwrap()
        };
        let meshes = [
            generators::icosphere(3),
            generators::torus(1.0, 0.4, 24, 12).unwrap(),
            generators::bow_tie(4),
            loose,
            generators::grid(12, 9, 1.0, 1.0),
        ];
        let mut filled = 0;
        for mesh in &meshes {
            let n = mesh.face_slots();
            for trial in 0..150 {
                let mut area: HashSet<usize> = HashSet::new();
                for _ in 0..1 + below(1 + trial % 40) {
                    let mut f = mesh.face_at(below(n)).unwrap();
                    for _ in 0..below(6) {
                        area.insert(mesh.face_index(f));
                        let next: Vec<_> = mesh.face_neighbors(f).collect();
                        f = next[below(next.len())];
                    }
                    area.insert(mesh.face_index(f));
                }
                let mut everywhere = vec![false; n];
                for &a in &area {
                    everywhere[a] = true;
                }
                fill_pockets_everywhere(mesh, &mut everywhere);
                let before = area.len();
                fill_pockets(mesh, &mut area);
                let mut local: Vec<usize> = area.iter().copied().collect();
                local.sort_unstable();
                let expected: Vec<usize> = (0..n).filter(|&i| everywhere[i]).collect();
                assert_eq!(local, expected, "trial {trial}");
                filled += usize::from(area.len() > before);
            }
        }
        assert!(filled > 50, "only {filled} areas had pockets");
        // Two equal halves: a torus cut by two opposite rings of faces. The tie goes to
        // the half whose first face slot comes last; the other is filled.
        let torus = generators::torus(1.0, 0.4, 24, 12).unwrap();
        let ring_at = |angle: f64| -> Vec<usize> {
            torus
                .faces()
                .filter(|&f| {
                    let c = torus.face_centroid(f);
                    let pi = std::f64::consts::PI;
                    let off = (c.y.atan2(c.x) - angle + pi).rem_euclid(2.0 * pi) - pi;
                    off.abs() < 0.13
                })
                .map(|f| torus.face_index(f))
                .collect()
        };
        let mut area: HashSet<usize> = ring_at(0.0).into_iter().collect();
        area.extend(ring_at(std::f64::consts::PI));
        let mut everywhere = vec![false; torus.face_slots()];
        for &a in &area {
            everywhere[a] = true;
        }
        fill_pockets_everywhere(&torus, &mut everywhere);
        let cut = area.len();
        fill_pockets(&torus, &mut area);
        let mut local: Vec<usize> = area.iter().copied().collect();
        local.sort_unstable();
        let expected: Vec<usize> = (0..torus.face_slots()).filter(|&i| everywhere[i]).collect();
        assert_eq!(local, expected);
        assert_eq!(
            2 * (area.len() - cut),
            torus.n_faces() - cut,
            "one half filled"
        );
    }

    #[test]
    fn a_disk_on_one_component_leaves_the_other_components_out() {
        // A head and two separate eyes: the eyes are not pockets of a disk on the head.
        let head = generators::icosphere(3);
        let mut eye = generators::icosphere(1);
        for p in eye.positions_mut() {
            *p = *p * 0.1 + DVec3::new(0.3, 0.3, 0.85);
        }
        let mut other = eye.clone();
        for p in other.positions_mut() {
            p.x -= 0.6;
        }
        let mesh = generators::disjoint_union(&[&head, &eye, &other]).unwrap();
        let front = mesh.extreme_vertex(DVec3::Z).unwrap().unwrap();
        let area = EditingArea::disk_around(&mesh, front, 60).unwrap();
        assert!(area.vertices().len() >= 60);
        let head_vertices = head.n_vertices();
        assert!(area
            .vertices()
            .iter()
            .all(|&v| mesh.vertex_index(v) < head_vertices));
    }

    fn vertex(mesh: &Mesh, i: usize) -> VertexId {
        mesh.vertex_at(i).unwrap()
    }

    #[test]
    fn picks_on_a_sphere_make_a_disk_on_the_smaller_side() {
        let mesh = generators::icosphere(3);
        // four vertices around the north pole region
        let mut near: Vec<VertexId> = mesh
            .vertices()
            .filter(|&v| mesh.position(v).z > 0.6)
            .collect();
        near.sort_by(|&a, &b| {
            let (pa, pb) = (mesh.position(a), mesh.position(b));
            pa.y.atan2(pa.x).total_cmp(&pb.y.atan2(pb.x))
        });
        let picks: Vec<VertexId> = (0..4).map(|k| near[k * near.len() / 4]).collect();
        let area = EditingArea::from_picks(&mesh, &picks, AreaSide::Smaller).unwrap();
        assert!(area.faces().len() < mesh.n_faces() / 2);
        assert!(area.n_interior() > 0);
        for &p in &picks {
            assert!(area.is_boundary(&mesh, p));
        }
        let top = mesh
            .vertices()
            .max_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z))
            .unwrap();
        assert!(area.contains(&mesh, top) && !area.is_boundary(&mesh, top));
        // the other side through a seed
        let bottom = mesh
            .vertices()
            .min_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z))
            .unwrap();
        let other = EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(bottom)).unwrap();
        assert_eq!(other.faces().len() + area.faces().len(), mesh.n_faces());
        assert!(matches!(
            EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(picks[0])),
            Err(LeeError::SeedOnLoop(_))
        ));
    }

    #[test]
    fn boundary_loop_runs_counter_clockwise() {
        let mesh = generators::grid(6, 6, 6.0, 6.0);
        let faces: Vec<FaceId> = mesh
            .faces()
            .filter(|&f| {
                let c = mesh.face_centroid(f);
                (1.0..5.0).contains(&c.x) && (1.0..5.0).contains(&c.y)
            })
            .collect();
        let area = EditingArea::from_faces(&mesh, &faces).unwrap();
        assert_eq!(area.n_interior(), 9);
        assert_eq!(area.boundary().len(), 16);
        // signed area of the boundary polygon is positive
        let b = area.boundary();
        let mut twice = 0.0;
        for i in 0..b.len() {
            let (p, q) = (mesh.position(b[i]), mesh.position(b[(i + 1) % b.len()]));
            twice += p.x * q.y - q.x * p.y;
        }
        assert!((twice - 2.0 * 16.0).abs() < 1e-9);
        assert_eq!(area.local_index(&mesh, vertex(&mesh, 0)), None);
    }

    #[test]
    fn annulus_and_mesh_boundary_are_refused() {
        let mesh = generators::grid(6, 6, 6.0, 6.0);
        let ring: Vec<FaceId> = mesh
            .faces()
            .filter(|&f| {
                let c = mesh.face_centroid(f);
                let inside = |a: f64, b: f64| (a..b).contains(&c.x) && (a..b).contains(&c.y);
                inside(1.0, 5.0) && !inside(2.0, 4.0)
            })
            .collect();
        assert!(matches!(
            EditingArea::from_faces(&mesh, &ring),
            Err(LeeError::AreaNotDisk {
                boundary_loops: 2,
                ..
            })
        ));
        let corner: Vec<FaceId> = mesh.faces().take(4).collect();
        assert!(matches!(
            EditingArea::from_faces(&mesh, &corner),
            Err(LeeError::AreaTouchesMeshBoundary { .. })
        ));
        assert!(matches!(
            EditingArea::from_faces(&mesh, &[]),
            Err(LeeError::AreaEmpty)
        ));
    }

    #[test]
    fn growing_by_adjacent_faces() {
        let mesh = generators::grid(8, 8, 8.0, 8.0);
        let pick = |x: f64, y: f64| {
            mesh.vertices()
                .find(|&v| mesh.position(v).truncate() == glam::DVec2::new(x, y))
                .unwrap()
        };
        let picks = [
            pick(2.0, 2.0),
            pick(5.0, 2.0),
            pick(5.0, 5.0),
            pick(2.0, 5.0),
        ];
        let area =
            EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(pick(3.0, 3.0))).unwrap();
        assert_eq!(area.faces().len(), 18);
        let outside = mesh
            .faces()
            .find(|&f| {
                let c = mesh.face_centroid(f);
                c.x > 5.0 && c.x < 5.5 && c.y > 3.0 && c.y < 4.0
            })
            .unwrap();
        let grown = area.grown(&mesh, &[outside]).unwrap();
        assert_eq!(grown.faces().len(), 19);
        let far = mesh
            .faces()
            .find(|&f| mesh.face_centroid(f).x > 7.0)
            .unwrap();
        assert!(matches!(
            area.grown(&mesh, &[far]),
            Err(LeeError::FaceNotAdjacent { .. })
        ));
    }

    #[test]
    fn disk_around_a_vertex() {
        let mesh = generators::icosphere(4);
        let area = EditingArea::disk_around(&mesh, vertex(&mesh, 0), 200).unwrap();
        assert!(area.vertices().len() >= 150);
        assert!(area.contains(&mesh, vertex(&mesh, 0)));
        assert!(!area.is_boundary(&mesh, vertex(&mesh, 0)));
    }
}
