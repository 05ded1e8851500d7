//! Sub-mesh labels (the seed paper "Interactive Editing of Multiresolution Meshes",
//! section 4.1, Figs. 2 and 4; DESIGN.md §2).
//!
//! A sub-mesh is a set of vertices with the same [`Label`], kept in the vertex attribute
//! named [`LABEL_ATTRIBUTE`]. Sub-meshes are separated by a **frontier**, a closed loop of
//! edges whose vertices carry the label [`FRONTIER`]. A frontier is made from
//! - (a) picked vertices joined by shortest edge paths ([`Mesh::frontier_through`]);
//! - (b) a picked collar of faces ([`Mesh::frontier_from_collar`]): the collar's border
//!   loop on the side of the smaller part it cuts off;
//! - (c) the edge loop that approximates the section of the mesh by a plane
//!   ([`Mesh::frontier_from_plane`]).
//!
//! [`Mesh::label_sides`] gives the faces left of the loop one label and those right of it
//! another, and fails with [`Error::InvalidFrontier`] when the loop does not separate the
//! mesh (a face region touches both of its sides).
//!
//! **Faces** derive their label from their vertices ([`Mesh::face_label`]): a face belongs
//! to the sub-mesh of its non-frontier vertices when they all agree; a face whose three
//! vertices are on the frontier, or whose vertices disagree, is [`FRONTIER`].
//!
//! **Levels.** Labels are a vertex attribute, so a collapsed vertex keeps its label (the
//! attribute persists on the tombstone) and labels defined at a fine level hold at every
//! coarser level and come back unchanged on refinement. Labels defined at a coarse level
//! reach the re-inserted vertices through the paper's Fig. 4 rule
//! ([`classify_split`], applied by [`crate::Hierarchy`] when labels are attached): the new
//! vertex is on the frontier when its neighbours include vertices of two different
//! sub-meshes, otherwise it takes the label of its non-frontier neighbours (and is on the
//! frontier when all its neighbours are). The rule never creates an edge between two
//! different sub-meshes, so the frontier keeps separating them at every level.

use glam::DVec3;

use crate::attributes::Attribute;
use crate::{Error, FaceId, HalfedgeId, Mesh, Result, VertexId};

/// A sub-mesh label.
pub type Label = u32;

/// The label of vertices (and faces) on a frontier, between sub-meshes.
pub const FRONTIER: Label = u32::MAX;

/// Name of the vertex attribute holding the labels.
pub const LABEL_ATTRIBUTE: &str = "submesh";

/// A closed loop of edges separating sub-meshes: halfedges in walking order, each
/// starting where the previous one ends.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frontier {
    halfedges: Vec<HalfedgeId>,
}

impl Frontier {
    /// A frontier from halfedges in walking order.
    ///
    /// # Errors
    /// [`Error::InvalidFrontier`] unless the halfedges are live and form one closed loop
    /// of at least three edges that does not use an edge twice.
    pub fn new(mesh: &Mesh, halfedges: Vec<HalfedgeId>) -> Result<Self> {
        if halfedges.len() < 3 {
            return Err(Error::InvalidFrontier(format!(
                "a frontier needs at least 3 edges, got {}",
                halfedges.len()
            )));
        }
        let mut used = vec![false; mesh.halfedge_slots()];
        for (i, &h) in halfedges.iter().enumerate() {
            mesh.ensure_halfedge(h)?;
            let next = halfedges[(i + 1) % halfedges.len()];
            mesh.ensure_halfedge(next)?;
            if mesh.to_vertex(h) != mesh.from_vertex(next) {
                return Err(Error::InvalidFrontier(format!(
                    "edge {i} ends at {} but edge {} starts at {}: not a closed loop",
                    mesh.to_vertex(h),
                    (i + 1) % halfedges.len(),
                    mesh.from_vertex(next)
                )));
            }
            let e = mesh
                .halfedge_index(h)
                .min(mesh.halfedge_index(mesh.opposite(h)));
            if std::mem::replace(&mut used[e], true) {
                return Err(Error::InvalidFrontier(format!(
                    "the loop uses the edge {}–{} twice",
                    mesh.from_vertex(h),
                    mesh.to_vertex(h)
                )));
            }
        }
        Ok(Self { halfedges })
    }
    /// The loop's halfedges in walking order.
    pub fn halfedges(&self) -> &[HalfedgeId] {
        &self.halfedges
    }
    /// The loop's vertices in walking order (`from_vertex` of each halfedge).
    pub fn vertices(&self, mesh: &Mesh) -> Vec<VertexId> {
        self.halfedges
            .iter()
            .map(|&h| mesh.from_vertex(h))
            .collect()
    }
    /// The same loop walked the other way (left and right swap).
    pub fn reversed(&self, mesh: &Mesh) -> Self {
        Self {
            halfedges: self
                .halfedges
                .iter()
                .rev()
                .map(|&h| mesh.opposite(h))
                .collect(),
        }
    }
}

/// What [`Mesh::label_sides`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SideCounts {
    /// Faces left of the frontier.
    pub left_faces: usize,
    /// Faces right of the frontier (and of components the frontier does not touch).
    pub right_faces: usize,
    /// Vertices labelled with the left label.
    pub left_vertices: usize,
    /// Vertices labelled with the right label.
    pub right_vertices: usize,
    /// Vertices on the frontier.
    pub frontier_vertices: usize,
}

/// # Sub-mesh frontiers and labels
impl Mesh {
    /// (a) The frontier through picked vertices, consecutive picks (and the last with the
    /// first) joined by shortest edge paths ([`Mesh::closed_loop_through`]).
    ///
    /// # Errors
    /// [`Error::InvalidFrontier`] when fewer than two vertices are picked, when no path
    /// joins two picks, or when the loop is not simple.
    pub fn frontier_through(&self, picks: &[VertexId]) -> Result<Frontier> {
        let loop_halfedges = self.closed_loop_through(picks)?;
        Frontier::new(self, loop_halfedges)
    }

    /// (b) The frontier of a picked collar of faces (a band around the part to cut off):
    /// the border between the collar and the smallest (by faces) of the parts the collar
    /// separates; collar faces go to the other side.
    ///
    /// # Errors
    /// [`Error::InvalidFrontier`] when the collar is empty, when the faces outside it are
    /// not split into at least two parts (the collar does not go around), or when the
    /// border with the smallest part is not one closed loop.
    pub fn frontier_from_collar(&self, collar: &[FaceId]) -> Result<Frontier> {
        if collar.is_empty() {
            return Err(Error::InvalidFrontier("the collar has no faces".into()));
        }
        let mut in_collar = vec![false; self.face_slots()];
        for &f in collar {
            self.ensure_face(f)?;
            in_collar[self.face_index(f)] = true;
        }
        // Parts: connected components of the faces outside the collar.
        let mut part = vec![u32::MAX; self.face_slots()];
        let mut sizes: Vec<usize> = Vec::new();
        let mut stack = Vec::new();
        for f in self.faces() {
            let fi = self.face_index(f);
            if in_collar[fi] || part[fi] != u32::MAX {
                continue;
            }
            let id = sizes.len() as u32;
            part[fi] = id;
            stack.push(f);
            let mut size = 0;
            while let Some(g) = stack.pop() {
                size += 1;
                for n in self.face_neighbors(g) {
                    let ni = self.face_index(n);
                    if !in_collar[ni] && part[ni] == u32::MAX {
                        part[ni] = id;
                        stack.push(n);
                    }
                }
            }
            sizes.push(size);
        }
        // Only parts that touch the collar count.
        let mut touches = vec![false; sizes.len()];
        for &f in collar {
            for n in self.face_neighbors(f) {
                let p = part[self.face_index(n)];
                if p != u32::MAX {
                    touches[p as usize] = true;
                }
            }
        }
        let touching: Vec<usize> = (0..sizes.len()).filter(|&p| touches[p]).collect();
        if touching.len() < 2 {
            return Err(Error::InvalidFrontier(format!(
                "the collar of {} faces does not separate the mesh: the faces around it form {} part(s)",
                collar.len(),
                touching.len()
            )));
        }
        let small = *touching
            .iter()
            .min_by_key(|&&p| (sizes[p], p))
            .expect("two parts at least");
        // Border halfedges: collar face on the left, small part on the right, walked so
        // that the small part is on the left of the frontier.
        let mut next_of = vec![None; self.vertex_slots()];
        let mut count = 0;
        let mut start = None;
        for &f in collar {
            for h in self.face_halfedges(f) {
                let o = self.opposite(h);
                let Some(n) = self.face(o) else { continue };
                if part[self.face_index(n)] as usize == small {
                    let from = self.vertex_index(self.from_vertex(o));
                    if next_of[from].replace(o).is_some() {
                        return Err(Error::InvalidFrontier(format!(
                            "the border of the collar with the part it cuts off passes twice through {}",
                            self.from_vertex(o)
                        )));
                    }
                    count += 1;
                    start.get_or_insert(o);
                }
            }
        }
        let start = start.expect("a touching part has a border");
        let mut loop_halfedges = Vec::with_capacity(count);
        let mut h = start;
        loop {
            loop_halfedges.push(h);
            let to = self.vertex_index(self.to_vertex(h));
            match next_of[to] {
                Some(n) if n == start => break,
                Some(n) if loop_halfedges.len() < count => h = n,
                _ => {
                    return Err(Error::InvalidFrontier(
                        "the border of the collar with the part it cuts off is not a closed loop"
                            .into(),
                    ))
                }
            }
        }
        if loop_halfedges.len() != count {
            return Err(Error::InvalidFrontier(format!(
                "the border of the collar with the part it cuts off is {} loops, not one",
                if loop_halfedges.len() < count {
                    "several"
                } else {
                    "broken"
                }
            )));
        }
        Frontier::new(self, loop_halfedges)
    }

    /// (c) The edge loop approximating the section of the mesh by the plane through
    /// `point` with normal `normal`: the faces the plane crosses are walked in order
    /// along the section curve nearest to `point`, each crossed edge contributes its
    /// endpoint nearest to the plane, consecutive vertices (which share a face) are joined
    /// by their edge, and back-and-forth spikes and small side loops are cut away.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a zero or non-finite normal or point;
    /// [`Error::InvalidFrontier`] when the plane misses the mesh, or when the section
    /// curve nearest to `point` runs into the mesh boundary (it is not closed).
    pub fn frontier_from_plane(&self, point: DVec3, normal: DVec3) -> Result<Frontier> {
        let Some(n) = normal.try_normalize().filter(|_| point.is_finite()) else {
            return Err(Error::InvalidArgument(format!(
                "plane needs a finite point and a non-zero normal, got {point} and {normal}"
            )));
        };
        let dist: Vec<f64> = self.positions().iter().map(|&p| n.dot(p - point)).collect();
        let side = |v: VertexId| dist[self.vertex_index(v)] >= 0.0;
        let crosses = |h: HalfedgeId| side(self.from_vertex(h)) != side(self.to_vertex(h));
        // Walk every section curve once; keep the closed one nearest to `point`.
        let mut seen = vec![false; self.halfedge_slots()];
        let mut best: Option<(f64, Vec<HalfedgeId>)> = None;
        let mut open_nearest: Option<f64> = None;
        for e in self.edges() {
            if seen[self.halfedge_index(e)] || !crosses(e) {
                continue;
            }
            let (chain, closed) = self.section_chain(e, &crosses, &mut seen);
            let d = chain
                .iter()
                .map(|&h| {
                    let (a, b) = (self.from_vertex(h), self.to_vertex(h));
                    let (da, db) = (dist[self.vertex_index(a)], dist[self.vertex_index(b)]);
                    let s = da / (da - db);
                    let x = self.position(a).lerp(self.position(b), s);
                    x.distance_squared(point)
                })
                .fold(f64::INFINITY, f64::min);
            if closed {
                if best.as_ref().is_none_or(|(bd, _)| d < *bd) {
                    best = Some((d, chain));
                }
            } else if open_nearest.is_none_or(|od| d < od) {
                open_nearest = Some(d);
            }
        }
        let Some((best_d, chain)) = best else {
            return Err(Error::InvalidFrontier(if open_nearest.is_some() {
                "the plane's section runs into the mesh boundary: it is not a closed loop".into()
            } else {
                "the plane does not cut the mesh".into()
            }));
        };
        if open_nearest.is_some_and(|od| od < best_d) {
            return Err(Error::InvalidFrontier(
                "the plane's section nearest to the point runs into the mesh boundary: it is not a closed loop"
                    .into(),
            ));
        }
        // Nearest endpoint of each crossed edge, in walking order, without repeats.
        let mut cycle: Vec<VertexId> = Vec::with_capacity(chain.len());
        for &h in &chain {
            let (a, b) = (self.from_vertex(h), self.to_vertex(h));
            let v = if dist[self.vertex_index(a)].abs() <= dist[self.vertex_index(b)].abs() {
                a
            } else {
                b
            };
            if cycle.last() != Some(&v) {
                cycle.push(v);
            }
        }
        while cycle.len() > 1 && cycle.first() == cycle.last() {
            cycle.pop();
        }
        let cycle = simple_cycle(cycle, self.vertex_slots(), |v| self.vertex_index(v));
        if cycle.len() < 3 {
            return Err(Error::InvalidFrontier(
                "the plane's section is too small to make a loop of at least 3 edges".into(),
            ));
        }
        let mut halfedges = Vec::with_capacity(cycle.len());
        for i in 0..cycle.len() {
            let (a, b) = (cycle[i], cycle[(i + 1) % cycle.len()]);
            match self.find_halfedge(a, b) {
                Some(h) => halfedges.push(h),
                None => halfedges.extend(self.shortest_edge_path(a, b, None).ok_or_else(|| {
                    Error::InvalidFrontier(format!("no edge path from {a} to {b}"))
                })?),
            }
        }
        Frontier::new(self, halfedges)
    }

    /// Walks the section curve through crossing edge `e`: the crossed edges in order
    /// (each oriented as met), and whether the curve closes.
    fn section_chain(
        &self,
        e: HalfedgeId,
        crosses: &impl Fn(HalfedgeId) -> bool,
        seen: &mut [bool],
    ) -> (Vec<HalfedgeId>, bool) {
        let mark = |seen: &mut [bool], h: HalfedgeId| {
            seen[self.halfedge_index(h)] = true;
            seen[self.halfedge_index(self.opposite(h))] = true;
        };
        // Walk forward through the faces left of the crossed halfedges.
        let walk = |start: HalfedgeId, seen: &mut [bool], out: &mut Vec<HalfedgeId>| -> bool {
            let mut h = start;
            loop {
                if self.face(h).is_none() {
                    return false;
                }
                // The other crossing edge of the face.
                let n1 = self.next(h);
                let other = if crosses(n1) { n1 } else { self.next(n1) };
                let g = self.opposite(other);
                if g == start || self.opposite(g) == start {
                    return true;
                }
                if seen[self.halfedge_index(g)] {
                    return false;
                }
                mark(seen, g);
                out.push(g);
                h = g;
            }
        };
        mark(seen, e);
        let mut forward = vec![e];
        if walk(e, seen, &mut forward) {
            return (forward, true);
        }
        // Open: walk the other way too, to mark the whole curve.
        let mut backward = Vec::new();
        walk(self.opposite(e), seen, &mut backward);
        forward.extend(backward);
        (forward, false)
    }

    /// The label attribute ([`LABEL_ATTRIBUTE`]), created with every vertex labelled `0`
    /// if the mesh has none.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when the mesh has a vertex attribute of that name with
    /// values of another type than [`Label`] (nothing is changed).
    pub fn label_attribute(&mut self) -> Result<Attribute<VertexId, Label>> {
        if let Some(a) = self.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) {
            return Ok(a);
        }
        self.add_vertex_attribute(LABEL_ATTRIBUTE, 0).map_err(|_| {
            Error::InvalidArgument(format!(
                "the mesh has a vertex attribute named {LABEL_ATTRIBUTE:?} whose values \
                     are not sub-mesh labels (u32)"
            ))
        })
    }

    /// Labels the two sides of `frontier`: vertices of faces left of the loop get `left`,
    /// the others `right` (components the loop does not touch included), the loop's
    /// vertices [`FRONTIER`]. Returns the label attribute ([`Mesh::label_attribute`]) and
    /// the counts.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when `left == right` or either is [`FRONTIER`], or when
    /// an attribute named [`LABEL_ATTRIBUTE`] holds values of another type;
    /// [`Error::InvalidFrontier`] when the loop does not separate the mesh (some part of
    /// the mesh lies on both of its sides) or a frontier halfedge is stale. Nothing is
    /// changed on error.
    pub fn label_sides(
        &mut self,
        frontier: &Frontier,
        left: Label,
        right: Label,
    ) -> Result<(Attribute<VertexId, Label>, SideCounts)> {
        if left == right || left == FRONTIER || right == FRONTIER {
            return Err(Error::InvalidArgument(format!(
                "the two sides need distinct labels other than FRONTIER, got {left} and {right}"
            )));
        }
        for &h in frontier.halfedges() {
            self.ensure_halfedge(h)?;
        }
        let (region, n_regions) = self.face_regions(frontier.halfedges());
        // 1: left, 2: right, 3: both.
        let mut sides = vec![0u8; n_regions as usize];
        for &h in frontier.halfedges() {
            if let Some(f) = self.face(h) {
                sides[region[self.face_index(f)] as usize] |= 1;
            }
            if let Some(f) = self.face(self.opposite(h)) {
                sides[region[self.face_index(f)] as usize] |= 2;
            }
        }
        if let Some(r) = sides.iter().position(|&s| s == 3) {
            let faces = region.iter().filter(|&&x| x == r as u32).count();
            return Err(Error::InvalidFrontier(format!(
                "the loop of {} edges does not separate the mesh: a part of {faces} faces lies on both of its sides",
                frontier.halfedges().len()
            )));
        }
        if !sides.contains(&1) {
            return Err(Error::InvalidFrontier(
                "the loop has no face on its left side".into(),
            ));
        }
        let attribute = self.label_attribute()?;
        let mut labels = vec![right; self.vertex_slots()];
        let mut counts = SideCounts {
            left_faces: 0,
            right_faces: 0,
            left_vertices: 0,
            right_vertices: 0,
            frontier_vertices: 0,
        };
        for f in self.faces() {
            if sides[region[self.face_index(f)] as usize] == 1 {
                counts.left_faces += 1;
                for v in self.face_vertices(f) {
                    labels[self.vertex_index(v)] = left;
                }
            } else {
                counts.right_faces += 1;
            }
        }
        for &h in frontier.halfedges() {
            labels[self.vertex_index(self.from_vertex(h))] = FRONTIER;
        }
        let values = self.attribute_values_mut(attribute);
        values[..labels.len()].copy_from_slice(&labels);
        for v in self.vertices() {
            match labels[self.vertex_index(v)] {
                FRONTIER => counts.frontier_vertices += 1,
                l if l == left => counts.left_vertices += 1,
                _ => counts.right_vertices += 1,
            }
        }
        Ok((attribute, counts))
    }

    /// The label of face `f` derived from its vertices (see the module docs).
    pub fn face_label(&self, attribute: Attribute<VertexId, Label>, f: FaceId) -> Label {
        let mut label = FRONTIER;
        for v in self.face_vertices(f) {
            let l = *self.attribute(attribute, v);
            if l == FRONTIER {
                continue;
            }
            if label == FRONTIER {
                label = l;
            } else if label != l {
                return FRONTIER;
            }
        }
        label
    }

    /// The live vertices labelled `label`.
    pub fn vertices_labelled(
        &self,
        attribute: Attribute<VertexId, Label>,
        label: Label,
    ) -> Vec<VertexId> {
        let values = self.attribute_values(attribute);
        self.vertices()
            .filter(|&v| values[self.vertex_index(v)] == label)
            .collect()
    }
}

/// The paper's Fig. 4 rule for the vertex `v` just re-inserted by a split: on the
/// frontier when its neighbours include two different sub-meshes, else the label of its
/// non-frontier neighbours; on the frontier when all its neighbours are.
pub fn classify_split(mesh: &mut Mesh, attribute: Attribute<VertexId, Label>, v: VertexId) {
    let values = mesh.attribute_values(attribute);
    let mut label = FRONTIER;
    let mut mixed = false;
    for w in mesh.adjacent_vertices(v) {
        let l = values[mesh.vertex_index(w)];
        if l == FRONTIER {
            continue;
        }
        if label == FRONTIER {
            label = l;
        } else if label != l {
            mixed = true;
            break;
        }
    }
    let i = mesh.vertex_index(v);
    mesh.attribute_values_mut(attribute)[i] = if mixed { FRONTIER } else { label };
}

/// Makes a closed walk of vertices simple: while a vertex repeats, the walk is split at
/// the two visits into two closed walks and the longer one is kept (this removes
/// back-and-forth spikes and small side loops). Consecutive vertices stay adjacent.
fn simple_cycle(
    mut cycle: Vec<VertexId>,
    slots: usize,
    index: impl Fn(VertexId) -> usize,
) -> Vec<VertexId> {
    let mut last_seen = vec![usize::MAX; slots];
    'again: loop {
        for &v in &cycle {
            last_seen[index(v)] = usize::MAX;
        }
        for j in 0..cycle.len() {
            let vi = index(cycle[j]);
            let i = last_seen[vi];
            if i != usize::MAX {
                // cycle[i] == cycle[j]: inner walk i..j, outer walk j..end + 0..i.
                let inner = j - i;
                let outer = cycle.len() - inner;
                for &v in &cycle {
                    last_seen[index(v)] = usize::MAX;
                }
                if inner > outer {
                    cycle = cycle[i..j].to_vec();
                } else {
                    cycle.drain(i..j);
                }
                continue 'again;
            }
            last_seen[vi] = j;
        }
        return cycle;
    }
}
