//! Sub-mesh labels (the seed paper "Interactive Editing of Multiresolution Meshes",
//! section 4.1, Figs. 2 and 4).
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
//! **Which side is which.** A frontier cut by a plane is walked so that its *left* side
//! is the side the plane's normal points to: `label_sides(&frontier, above, below)`.
//! Every frontier has a *side plane* ([`Frontier::side_plane`]) whose normal points to
//! its left side: the cutting plane, or for a loop through picks or around a collar the
//! plane through the loop's centroid along its vector area. Components of the mesh the
//! frontier does not cross (separate eyes, nails, teeth) go to the side their centroid
//! lies on, so cutting off a character's head takes its eyes along.
//!
//! **Several sub-meshes.** [`Mesh::label_sides_with`] writes only the labels it is given
//! and leaves the others alone: cut off the head with `label_sides_with(&neck,
//! Some(HEAD), None)`, then an arm with `label_sides_with(&shoulder, Some(ARM), None)`,
//! and the mesh holds both sub-meshes (and the rest keeps its label). Each cut seals its
//! part off with frontier vertices, so no edge ever joins two sub-meshes.
//!
//! **Faces** derive their label from their vertices ([`Mesh::face_label`]): a face belongs
//! to the sub-mesh of its non-frontier vertices when they all agree; a face whose three
//! vertices are on the frontier, or whose vertices disagree, is [`FRONTIER`].
//!
//! **Levels.** Labels are a vertex attribute, so a collapsed vertex keeps its label (the
//! attribute persists on the tombstone) and labels defined at a fine level hold at every
//! coarser level and come back unchanged on refinement. Labels defined at a coarse level
//! reach the re-inserted vertices through the paper's Fig. 4 rule
//! ([`classify_split`], applied by [`crate::hierarchy::Hierarchy`] when labels are attached): the new
//! vertex is on the frontier when its neighbours include vertices of two different
//! sub-meshes, otherwise it takes the label of its non-frontier neighbours (and is on the
//! frontier when all its neighbours are). The rule never creates an edge between two
//! different sub-meshes, so the frontier keeps separating them at every level.

use glam::DVec3;

use crate::attributes::Attribute;
use crate::error::{Error, Result};
use crate::handle::{FaceId, HalfedgeId, VertexId};
use crate::mesh::Mesh;

/// A sub-mesh label.
pub type Label = u32;

/// The label of vertices (and faces) on a frontier, between sub-meshes.
pub const FRONTIER: Label = u32::MAX;

/// Name of the vertex attribute holding the labels.
pub const LABEL_ATTRIBUTE: &str = "submesh";

/// A closed loop of edges separating sub-meshes: halfedges in walking order, each
/// starting where the previous one ends; with the plane it was cut by, if any.
#[derive(Clone, Debug)]
pub struct Frontier {
    halfedges: Vec<HalfedgeId>,
    /// The cutting plane (point, unit normal towards the left side), for frontiers made
    /// by [`Mesh::frontier_from_plane`].
    plane: Option<(DVec3, DVec3)>,
}

/// Frontiers are equal when they walk the same halfedges and were cut by the same plane
/// (bit for bit), or both by none.
impl PartialEq for Frontier {
    fn eq(&self, other: &Self) -> bool {
        let bits = |p: &Option<(DVec3, DVec3)>| {
            p.map(|(a, b)| {
                (
                    a.to_array().map(f64::to_bits),
                    b.to_array().map(f64::to_bits),
                )
            })
        };
        self.halfedges == other.halfedges && bits(&self.plane) == bits(&other.plane)
    }
}
impl Eq for Frontier {}

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
        Ok(Self {
            halfedges,
            plane: None,
        })
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
    /// The same loop walked the other way (left and right swap; a cutting plane's
    /// normal is flipped with them).
    pub fn reversed(&self, mesh: &Mesh) -> Self {
        Self {
            halfedges: self
                .halfedges
                .iter()
                .rev()
                .map(|&h| mesh.opposite(h))
                .collect(),
            plane: self.plane.map(|(p, n)| (p, -n)),
        }
    }
    /// The plane the frontier was cut by ([`Mesh::frontier_from_plane`]): a point and
    /// the unit normal, which points to the frontier's left side.
    pub fn plane(&self) -> Option<(DVec3, DVec3)> {
        self.plane
    }
    /// The plane that tells the frontier's sides apart in space: the cutting
    /// [`plane`](Self::plane), else the plane through the centroid of the loop's
    /// vertices whose normal is the loop's vector area `½ Σ pᵢ × pᵢ₊₁` (for a loop walked
    /// around a tube or a cap, it points to the loop's left side). Its normal points to
    /// the left side. `None` when the loop has no vector area (it is folded onto itself)
    /// or a halfedge is stale.
    pub fn side_plane(&self, mesh: &Mesh) -> Option<(DVec3, DVec3)> {
        if self.plane.is_some() {
            return self.plane;
        }
        if self.halfedges.iter().any(|&h| !mesh.is_valid_halfedge(h)) {
            return None;
        }
        let points: Vec<DVec3> = self
            .vertices(mesh)
            .iter()
            .map(|&v| mesh.position(v))
            .collect();
        let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
        let mut area = DVec3::ZERO;
        let mut length = 0.0;
        for (i, &p) in points.iter().enumerate() {
            let q = points[(i + 1) % points.len()];
            area += 0.5 * (p - centroid).cross(q - centroid);
            length += p.distance(q);
        }
        let normal = area.try_normalize()?;
        (area.length() > 1e-9 * length * length).then_some((centroid, normal))
    }
}

/// What [`Mesh::label_sides`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SideCounts {
    /// Faces left of the frontier, components it does not cross included (see
    /// [`Mesh::label_sides`]).
    pub left_faces: usize,
    /// Faces right of the frontier, components it does not cross included (see
    /// [`Mesh::label_sides`]).
    pub right_faces: usize,
    /// Vertices given the left label (0 when [`Mesh::label_sides_with`] leaves that
    /// side alone).
    pub left_vertices: usize,
    /// Vertices given the right label (0 when that side is left alone).
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
    /// The loop is walked so that its **left side is the side `normal` points to**
    /// (`label_sides(&frontier, above, below)`), and it remembers the plane
    /// ([`Frontier::plane`]).
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
        let mut frontier = Frontier::new(self, halfedges)?;
        // Left is the normal's side: each loop edge votes with how much higher (along the
        // normal) the far corner of its left face lies than that of its right face.
        let far = |h: HalfedgeId| -> f64 {
            self.face(h).map_or(0.0, |_| {
                dist[self.vertex_index(self.to_vertex(self.next(h)))]
            })
        };
        let vote: f64 = frontier
            .halfedges()
            .iter()
            .map(|&h| far(h) - far(self.opposite(h)))
            .sum();
        if vote < 0.0 {
            frontier = frontier.reversed(self);
        }
        frontier.plane = Some((point, n));
        Ok(frontier)
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
    /// the others `right`, the loop's vertices [`FRONTIER`]. Components of the mesh the
    /// loop does not cross go to the side of the frontier's
    /// [`side_plane`](Frontier::side_plane) their area-weighted centroid lies on (to the
    /// right when the loop has no side plane); isolated vertices (no face, such as a
    /// scan's unreferenced points) go to the right. For a frontier cut by a plane the
    /// left side is the side its normal points to. Returns the label attribute
    /// ([`Mesh::label_attribute`]) and the counts.
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
        if left == right {
            return Err(Error::InvalidArgument(format!(
                "the two sides need distinct labels, got {left} twice"
            )));
        }
        self.label_sides_with(frontier, Some(left), Some(right))
    }

    /// [`label_sides`](Self::label_sides) writing only the labels given: `None` leaves
    /// the labels of that side's vertices as they are. The loop's vertices always become
    /// [`FRONTIER`]. This keeps several sub-meshes in one mesh: cut each part off with
    /// `label_sides_with(&frontier, Some(part), None)` (see the module docs); the new
    /// part is sealed by its frontier whatever was labelled before.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when both labels are `None`, equal, or [`FRONTIER`];
    /// otherwise as [`label_sides`](Self::label_sides). Nothing is changed on error.
    pub fn label_sides_with(
        &mut self,
        frontier: &Frontier,
        left: Option<Label>,
        right: Option<Label>,
    ) -> Result<(Attribute<VertexId, Label>, SideCounts)> {
        if left.is_none() && right.is_none()
            || left == Some(FRONTIER)
            || right == Some(FRONTIER)
            || (left.is_some() && left == right)
        {
            return Err(Error::InvalidArgument(format!(
                "the sides need labels other than FRONTIER, distinct, at least one of them, got {left:?} and {right:?}"
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
        // Regions the loop does not touch go by their centroid.
        let plane = frontier.side_plane(self);
        let on_left = |p: DVec3| plane.is_some_and(|(o, n)| n.dot(p - o) > 0.0);
        if sides.contains(&0) {
            let mut weighted = vec![(DVec3::ZERO, 0.0f64, DVec3::ZERO, 0usize); sides.len()];
            for f in self.faces() {
                let r = region[self.face_index(f)] as usize;
                if sides[r] == 0 {
                    let area = self.face_area(f);
                    let c = self.face_centroid(f);
                    let w = &mut weighted[r];
                    w.0 += area * c;
                    w.1 += area;
                    w.2 += c;
                    w.3 += 1;
                }
            }
            for (r, s) in sides.iter_mut().enumerate() {
                if *s == 0 {
                    let (sum, area, plain, n) = weighted[r];
                    let centroid = if area > 0.0 {
                        sum / area
                    } else {
                        plain / n.max(1) as f64
                    };
                    *s = if on_left(centroid) { 1 } else { 2 };
                }
            }
        }
        let label_of = |side: u8| if side == 1 { left } else { right };
        let attribute = self.label_attribute()?;
        let mut labels: Vec<Option<Label>> = vec![None; self.vertex_slots()];
        let mut counts = SideCounts {
            left_faces: 0,
            right_faces: 0,
            left_vertices: 0,
            right_vertices: 0,
            frontier_vertices: 0,
        };
        for v in self.vertices() {
            if self.is_isolated(v) {
                labels[self.vertex_index(v)] = right;
            }
        }
        for f in self.faces() {
            let side = sides[region[self.face_index(f)] as usize];
            if side == 1 {
                counts.left_faces += 1;
            } else {
                counts.right_faces += 1;
            }
            if let Some(l) = label_of(side) {
                for v in self.face_vertices(f) {
                    labels[self.vertex_index(v)] = Some(l);
                }
            }
        }
        for &h in frontier.halfedges() {
            labels[self.vertex_index(self.from_vertex(h))] = Some(FRONTIER);
        }
        let values = self.attribute_values_mut(attribute)?;
        for (value, label) in values.iter_mut().zip(&labels) {
            if let Some(l) = *label {
                *value = l;
            }
        }
        for v in self.vertices() {
            match labels[self.vertex_index(v)] {
                Some(FRONTIER) => counts.frontier_vertices += 1,
                Some(l) if Some(l) == left => counts.left_vertices += 1,
                Some(_) => counts.right_vertices += 1,
                None => {}
            }
        }
        Ok((attribute, counts))
    }

    /// The label of face `f` derived from its vertices (see the module docs).
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh;
    /// [`Error::InvalidHandle`] when `f` is not a live face.
    pub fn face_label(&self, attribute: Attribute<VertexId, Label>, f: FaceId) -> Result<Label> {
        let values = self.attribute_values(attribute)?;
        self.ensure_face(f)?;
        let mut label = FRONTIER;
        for v in self.face_vertices(f) {
            let l = values[self.vertex_index(v)];
            if l == FRONTIER {
                continue;
            }
            if label == FRONTIER {
                label = l;
            } else if label != l {
                return Ok(FRONTIER);
            }
        }
        Ok(label)
    }

    /// The live vertices labelled `label`.
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh.
    pub fn vertices_labelled(
        &self,
        attribute: Attribute<VertexId, Label>,
        label: Label,
    ) -> Result<Vec<VertexId>> {
        let values = self.attribute_values(attribute)?;
        Ok(self
            .vertices()
            .filter(|&v| values[self.vertex_index(v)] == label)
            .collect())
    }
}

/// The paper's Fig. 4 rule for the vertex `v` just re-inserted by a split: on the
/// frontier when its neighbours include two different sub-meshes, else the label of its
/// non-frontier neighbours; on the frontier when all its neighbours are.
///
/// # Errors
/// [`Error::Stale`] when `attribute` is not an attribute of `mesh`;
/// [`Error::InvalidHandle`] when `v` is not a live vertex. Nothing is changed then.
pub fn classify_split(
    mesh: &mut Mesh,
    attribute: Attribute<VertexId, Label>,
    v: VertexId,
) -> Result<()> {
    mesh.ensure_vertex(v)?;
    let values = mesh.attribute_values(attribute)?;
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
    mesh.attribute_values_mut(attribute)?[i] = if mixed { FRONTIER } else { label };
    Ok(())
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
