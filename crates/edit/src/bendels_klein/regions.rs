//! Handle, fixed and deformable regions of a mesh (Bendels & Klein, Sec. 2).

use halfedge::{Binding, HalfedgeId, Mesh, VertexData, VertexId};

use crate::bendels_klein::error::{BendelsKleinError, RegionKind, Result, Site};

/// The role of one vertex (or point, or grid vertex) in a Bendels & Klein edit (Sec. 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// Never moves (also removed vertex slots and isolated vertices).
    Fixed,
    /// Moves by `α ⊙ A`.
    Deformable,
    /// Moves rigidly by `A`.
    Handle,
}

/// The border of the handle or of the fixed area towards the deformable area.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 4.1, eq. (1)–(2).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Border {
    /// Vertices of the region with a deformable neighbour.
    pub vertices: Vec<VertexId>,
    /// Edges between two border vertices that bound a triangle with a deformable
    /// corner; a border vertex on no such edge appears as `(v, v)`. The polylines of
    /// Bendels & Klein's eq. (1)–(2).
    pub edges: Vec<(VertexId, VertexId)>,
}

/// The three regions of a Bendels & Klein edit (Sec. 2, Fig. 1): the **handle** (moves
/// rigidly by the user's transform `A`), the **fixed area** (never moves) and the
/// **deformable area** between them (each vertex moves by `α ⊙ A`). The handle must lie
/// in the complement of the fixed area (footnote 1): they may share no vertex and no
/// edge.
///
/// Regions are given
/// - directly, as vertex sets ([`Regions::from_sets`]: handle and fixed, the rest
///   deformable) or as a role per vertex ([`Regions::from_roles`]);
/// - or by their borders drawn on the mesh, as the paper does with its 3D cursor: closed
///   edge loops ([`Regions::from_loops`]), or picked vertices joined by shortest edge
///   paths into closed loops ([`Regions::from_picks`], via the kernel's
///   `Mesh::closed_loop_through`). The faces are split along both loops
///   (`Mesh::face_regions`); the area the two loops bound together is deformable, the
///   far side of the handle loop is the handle, the far side of the fixed loop is fixed
///   (loop vertices belong to their handle or fixed area), and faces of components
///   neither loop touches are fixed.
///
/// Either way the result knows its two **borders**: the handle (fixed) vertices next to
/// the deformable area, and the edges between them that bound a deformable triangle —
/// the polylines the distance fields are measured from.
///
/// Handle, fixed and deformable vertex sets of one mesh, with their borders (Bendels &
/// Klein, Sec. 2). They keep the [`Binding`] of the mesh they were made for: a
/// [`BlendSession`](crate::bendels_klein::BlendSession) refuses them on any other mesh
/// (even one of the same size) with [`BendelsKleinError::Stale`].
#[derive(Clone, Debug)]
pub struct Regions {
    binding: Binding,
    roles: Vec<Role>,
    handle: Vec<VertexId>,
    deformable: Vec<VertexId>,
    n_fixed: usize,
    handle_border: Border,
    fixed_border: Border,
}

impl Regions {
    /// Handle and fixed vertex sets; every other vertex with an edge is deformable
    /// (isolated vertices stay fixed).
    ///
    /// # Errors
    /// [`halfedge::Error::InvalidHandle`] (as `BendelsKleinError::Mesh`) for a vertex that
    /// is not live, [`BendelsKleinError::HandleTouchesFixed`] when a vertex is in both sets
    /// or an edge joins them, [`BendelsKleinError::EmptyRegion`],
    /// [`BendelsKleinError::NoDeformableNeighbour`] when the handle or the fixed area has
    /// no deformable neighbour.
    pub fn from_sets(mesh: &Mesh, handle: &[VertexId], fixed: &[VertexId]) -> Result<Self> {
        let mut roles: Vec<Role> = (0..mesh.vertex_slots())
            .map(|i| match mesh.vertex_at(i) {
                Some(v) if !mesh.is_isolated(v) => Role::Deformable,
                _ => Role::Fixed,
            })
            .collect();
        let mut in_handle = vec![false; roles.len()];
        for &v in handle {
            mesh.ensure_vertex(v)?;
            roles[mesh.vertex_index(v)] = Role::Handle;
            in_handle[mesh.vertex_index(v)] = true;
        }
        for &v in fixed {
            mesh.ensure_vertex(v)?;
            if in_handle[mesh.vertex_index(v)] {
                return Err(BendelsKleinError::HandleTouchesFixed {
                    handle: Site::Vertex(v),
                    fixed: Site::Vertex(v),
                });
            }
            roles[mesh.vertex_index(v)] = Role::Fixed;
        }
        Self::from_role_slots(mesh, roles)
    }

    /// One role per vertex of `mesh` (per-vertex data of it, for example
    /// `VertexData::filled(mesh, Role::Deformable)` with the handle and fixed vertices
    /// set); removed slots are taken as fixed.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when `roles` was made for another mesh (or this one
    /// before a change of connectivity); [`BendelsKleinError::NoDeformableNeighbour`] for
    /// a region without deformable neighbour, [`BendelsKleinError::HandleTouchesFixed`],
    /// [`BendelsKleinError::EmptyRegion`].
    pub fn from_roles(mesh: &Mesh, roles: VertexData<Role>) -> Result<Self> {
        roles.check(mesh)?;
        Self::from_role_slots(mesh, roles.into_values())
    }

    /// [`from_roles`](Self::from_roles) on one role per vertex slot of `mesh`.
    fn from_role_slots(mesh: &Mesh, mut roles: Vec<Role>) -> Result<Self> {
        debug_assert_eq!(roles.len(), mesh.vertex_slots());
        for (i, role) in roles.iter_mut().enumerate() {
            if mesh.vertex_at(i).is_none() {
                *role = Role::Fixed;
            }
        }
        let mut handle = Vec::new();
        let mut deformable = Vec::new();
        let mut n_fixed = 0;
        for v in mesh.vertices() {
            match roles[mesh.vertex_index(v)] {
                Role::Handle => handle.push(v),
                Role::Deformable => deformable.push(v),
                Role::Fixed => n_fixed += 1,
            }
        }
        for (set, kind) in [
            (handle.len(), RegionKind::Handle),
            (n_fixed, RegionKind::Fixed),
            (deformable.len(), RegionKind::Deformable),
        ] {
            if set == 0 {
                return Err(BendelsKleinError::EmptyRegion(kind));
            }
        }
        let role = |v: VertexId| roles[mesh.vertex_index(v)];
        for &v in &handle {
            if let Some(w) = mesh.adjacent_vertices(v).find(|&w| role(w) == Role::Fixed) {
                return Err(BendelsKleinError::HandleTouchesFixed {
                    handle: Site::Vertex(v),
                    fixed: Site::Vertex(w),
                });
            }
        }
        let handle_border = border(mesh, &roles, Role::Handle);
        let fixed_border = border(mesh, &roles, Role::Fixed);
        for (b, kind) in [
            (&handle_border, RegionKind::Handle),
            (&fixed_border, RegionKind::Fixed),
        ] {
            if b.vertices.is_empty() {
                return Err(BendelsKleinError::NoDeformableNeighbour { region: kind });
            }
        }
        Ok(Self {
            binding: mesh.binding(),
            roles,
            handle,
            deformable,
            n_fixed,
            handle_border,
            fixed_border,
        })
    }

    /// Regions bounded by two closed edge loops drawn on the mesh: the handle loop and
    /// the fixed loop (see [`Regions`] for which side is which).
    ///
    /// # Errors
    /// [`BendelsKleinError::BorderNotClosed`] when a loop is not a closed chain of live
    /// halfedges, [`BendelsKleinError::BorderDoesNotSeparate`] when a loop does not split the
    /// mesh or the loops bound no common area, and the errors of
    /// [`Regions::from_roles`].
    pub fn from_loops(
        mesh: &Mesh,
        handle_loop: &[HalfedgeId],
        fixed_loop: &[HalfedgeId],
    ) -> Result<Self> {
        check_closed(mesh, handle_loop, RegionKind::Handle)?;
        check_closed(mesh, fixed_loop, RegionKind::Fixed)?;
        let cut: Vec<HalfedgeId> = handle_loop.iter().chain(fixed_loop).copied().collect();
        let (region, count) = mesh.face_regions(&cut);
        let count = count as usize;
        let sides = |lp: &[HalfedgeId]| {
            let mut left = vec![false; count];
            let mut right = vec![false; count];
            for &h in lp {
                if let Some(f) = mesh.face(h) {
                    left[region[mesh.face_index(f)] as usize] = true;
                }
                if let Some(f) = mesh.face(mesh.opposite(h)) {
                    right[region[mesh.face_index(f)] as usize] = true;
                }
            }
            (left, right)
        };
        let (h_left, h_right) = sides(handle_loop);
        let (f_left, f_right) = sides(fixed_loop);
        for (left, right, kind) in [
            (&h_left, &h_right, RegionKind::Handle),
            (&f_left, &f_right, RegionKind::Fixed),
        ] {
            if (0..count).any(|r| left[r] && right[r]) {
                return Err(BendelsKleinError::BorderDoesNotSeparate {
                    region: kind,
                    reason: "both sides of the loop are joined around it".into(),
                });
            }
        }
        let middle: Vec<bool> = (0..count)
            .map(|r| (h_left[r] || h_right[r]) && (f_left[r] || f_right[r]))
            .collect();
        if !middle.iter().any(|&m| m) {
            return Err(BendelsKleinError::BorderDoesNotSeparate {
                region: RegionKind::Deformable,
                reason: "the handle loop and the fixed loop bound no common area".into(),
            });
        }
        // The far side of each loop: the side without the middle.
        let far_side = |left: &[bool], right: &[bool], kind| -> Result<Vec<bool>> {
            let middle_left = (0..count).any(|r| middle[r] && left[r]);
            let middle_right = (0..count).any(|r| middle[r] && right[r]);
            match (middle_left, middle_right) {
                (true, false) => Ok(right.to_vec()),
                (false, true) => Ok(left.to_vec()),
                _ => Err(BendelsKleinError::BorderDoesNotSeparate {
                    region: kind,
                    reason: "the deformable area lies on both sides of the loop".into(),
                }),
            }
        };
        let handle_side = far_side(&h_left, &h_right, RegionKind::Handle)?;
        let fixed_side = far_side(&f_left, &f_right, RegionKind::Fixed)?;
        let mut seen_handle = vec![false; mesh.vertex_slots()];
        let mut seen_fixed = vec![false; mesh.vertex_slots()];
        let mut seen_middle = vec![false; mesh.vertex_slots()];
        for f in mesh.faces() {
            let r = region[mesh.face_index(f)] as usize;
            let seen = if handle_side[r] {
                &mut seen_handle
            } else if middle[r] && !fixed_side[r] {
                &mut seen_middle
            } else {
                &mut seen_fixed
            };
            for v in mesh.triangle(f) {
                seen[mesh.vertex_index(v)] = true;
            }
        }
        let mut roles = vec![Role::Fixed; mesh.vertex_slots()];
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            roles[i] = match (seen_handle[i], seen_fixed[i], seen_middle[i]) {
                (true, true, _) => {
                    return Err(BendelsKleinError::HandleTouchesFixed {
                        handle: Site::Vertex(v),
                        fixed: Site::Vertex(v),
                    })
                }
                (true, false, _) => Role::Handle,
                (false, true, _) => Role::Fixed,
                (false, false, true) => Role::Deformable,
                (false, false, false) => Role::Fixed,
            };
        }
        Self::from_role_slots(mesh, roles)
    }

    /// Regions bounded by two closed loops through picked vertices, consecutive picks
    /// joined by shortest edge paths (`Mesh::closed_loop_through`), as with the paper's
    /// 3D cursor.
    ///
    /// # Errors
    /// [`BendelsKleinError::BorderNotClosed`] when the picks do not give a closed loop, and the
    /// errors of [`Regions::from_loops`].
    pub fn from_picks(
        mesh: &Mesh,
        handle_picks: &[VertexId],
        fixed_picks: &[VertexId],
    ) -> Result<Self> {
        let loop_of = |picks: &[VertexId], kind| {
            mesh.closed_loop_through(picks)
                .map_err(|e| BendelsKleinError::BorderNotClosed {
                    region: kind,
                    reason: e.to_string(),
                })
        };
        let handle_loop = loop_of(handle_picks, RegionKind::Handle)?;
        let fixed_loop = loop_of(fixed_picks, RegionKind::Fixed)?;
        Self::from_loops(mesh, &handle_loop, &fixed_loop)
    }

    /// The mesh the regions were made for (see [`halfedge::Binding`]).
    #[must_use]
    pub fn binding(&self) -> Binding {
        self.binding
    }
    /// The role of a vertex.
    #[must_use]
    pub fn role(&self, mesh: &Mesh, v: VertexId) -> Role {
        self.roles
            .get(mesh.vertex_index(v))
            .copied()
            .unwrap_or(Role::Fixed)
    }
    /// Roles by vertex index.
    #[must_use]
    pub fn roles(&self) -> &[Role] {
        &self.roles
    }
    /// The handle vertices.
    #[must_use]
    pub fn handle(&self) -> &[VertexId] {
        &self.handle
    }
    /// The deformable vertices.
    #[must_use]
    pub fn deformable(&self) -> &[VertexId] {
        &self.deformable
    }
    /// Number of fixed live vertices.
    #[must_use]
    pub fn n_fixed(&self) -> usize {
        self.n_fixed
    }
    /// The handle's border towards the deformable area.
    #[must_use]
    pub fn handle_border(&self) -> &Border {
        &self.handle_border
    }
    /// The fixed area's border towards the deformable area.
    #[must_use]
    pub fn fixed_border(&self) -> &Border {
        &self.fixed_border
    }

    /// Records a vertex created in the deformable area (refinement), and binds the regions
    /// to `mesh` as the split left it.
    pub(crate) fn push_deformable(&mut self, mesh: &Mesh, v: VertexId) {
        self.binding = mesh.binding();
        let i = mesh.vertex_index(v);
        if self.roles.len() <= i {
            self.roles.resize(i + 1, Role::Fixed);
        }
        self.roles[i] = Role::Deformable;
        self.deformable.push(v);
    }
}

fn check_closed(mesh: &Mesh, lp: &[HalfedgeId], kind: RegionKind) -> Result<()> {
    let fail = |reason: String| {
        Err(BendelsKleinError::BorderNotClosed {
            region: kind,
            reason,
        })
    };
    if lp.len() < 3 {
        return fail(format!("a loop needs at least 3 edges, got {}", lp.len()));
    }
    if let Some(h) = lp.iter().find(|&&h| !mesh.is_valid_halfedge(h)) {
        return fail(format!("{h} is not a live halfedge"));
    }
    for (i, &h) in lp.iter().enumerate() {
        let next = lp[(i + 1) % lp.len()];
        if mesh.to_vertex(h) != mesh.from_vertex(next) {
            return fail(format!(
                "edge {i} ends at {} but edge {} starts at {}",
                mesh.to_vertex(h),
                (i + 1) % lp.len(),
                mesh.from_vertex(next)
            ));
        }
    }
    Ok(())
}

/// The border of the region with role `kind` towards the deformable area.
fn border(mesh: &Mesh, roles: &[Role], kind: Role) -> Border {
    let role = |v: VertexId| roles[mesh.vertex_index(v)];
    let mut vertices = Vec::new();
    let mut on_edge = vec![false; roles.len()];
    let mut edges = Vec::new();
    for v in mesh.vertices() {
        if role(v) == kind
            && mesh
                .adjacent_vertices(v)
                .any(|w| role(w) == Role::Deformable)
        {
            vertices.push(v);
        }
    }
    for h in mesh.edges() {
        let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
        if role(a) != kind || role(b) != kind {
            continue;
        }
        let bounds_deformable = [h, mesh.opposite(h)].iter().any(|&g| {
            mesh.face(g).is_some() && role(mesh.to_vertex(mesh.next(g))) == Role::Deformable
        });
        if bounds_deformable {
            edges.push((a, b));
            on_edge[mesh.vertex_index(a)] = true;
            on_edge[mesh.vertex_index(b)] = true;
        }
    }
    for &v in &vertices {
        if !on_edge[mesh.vertex_index(v)] {
            edges.push((v, v));
        }
    }
    Border { vertices, edges }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use halfedge::generators;

    fn nearest(mesh: &Mesh, p: DVec3) -> VertexId {
        mesh.vertices()
            .min_by(|&a, &b| {
                mesh.position(a)
                    .distance(p)
                    .total_cmp(&mesh.position(b).distance(p))
            })
            .unwrap()
    }

    fn ring_picks(mesh: &Mesh, centre: DVec3, radius: f64, n: usize) -> Vec<VertexId> {
        (0..n)
            .map(|k| {
                let t = k as f64 / n as f64 * std::f64::consts::TAU;
                nearest(mesh, centre + radius * DVec3::new(t.cos(), t.sin(), 0.0))
            })
            .collect()
    }

    #[test]
    fn picks_on_a_grid_give_nested_regions() {
        let mesh = generators::grid(40, 40, 1.0, 1.0);
        let c = DVec3::new(0.5, 0.5, 0.0);
        let regions = Regions::from_picks(
            &mesh,
            &ring_picks(&mesh, c, 0.1, 8),
            &ring_picks(&mesh, c, 0.35, 24),
        )
        .unwrap();
        // Shortest edge paths between picks cut inside the chords by up to an edge.
        for v in mesh.vertices() {
            let r = mesh.position(v).distance(c);
            let role = regions.role(&mesh, v);
            if r < 0.05 {
                assert_eq!(role, Role::Handle, "r = {r}");
            } else if r > 0.15 && r < 0.28 {
                assert_eq!(role, Role::Deformable, "r = {r}");
            } else if r > 0.4 {
                assert_eq!(role, Role::Fixed, "r = {r}");
            }
        }
        assert_eq!(
            regions.handle().len() + regions.deformable().len() + regions.n_fixed(),
            mesh.n_vertices()
        );
        // Border edges join border vertices and bound deformable triangles.
        for b in [regions.handle_border(), regions.fixed_border()] {
            assert!(b.edges.len() >= b.vertices.len() - 1);
            assert!(b.edges.iter().all(|(a, c)| a != c));
        }
        // Swapping the loops swaps the roles of the two far sides.
        let swapped = Regions::from_picks(
            &mesh,
            &ring_picks(&mesh, c, 0.35, 24),
            &ring_picks(&mesh, c, 0.1, 8),
        )
        .unwrap();
        assert_eq!(swapped.handle().len(), regions.n_fixed());
    }

    #[test]
    fn typed_errors() {
        let mesh = generators::grid(20, 20, 1.0, 1.0);
        let v = |i: usize| mesh.vertex_at(i).unwrap();
        // Touching: shared vertex, then an edge.
        assert!(matches!(
            Regions::from_sets(&mesh, &[v(100)], &[v(100)]),
            Err(BendelsKleinError::HandleTouchesFixed { .. })
        ));
        assert!(matches!(
            Regions::from_sets(&mesh, &[v(100)], &[v(101)]),
            Err(BendelsKleinError::HandleTouchesFixed { .. })
        ));
        // Empty sets.
        assert!(matches!(
            Regions::from_sets(&mesh, &[], &[v(0)]),
            Err(BendelsKleinError::EmptyRegion(RegionKind::Handle))
        ));
        assert!(matches!(
            Regions::from_sets(&mesh, &[v(200)], &[]),
            Err(BendelsKleinError::EmptyRegion(RegionKind::Fixed))
        ));
        let all_but: Vec<VertexId> = mesh.vertices().filter(|&w| w != v(0)).collect();
        assert!(matches!(
            Regions::from_sets(&mesh, &[v(0)], &all_but),
            Err(BendelsKleinError::EmptyRegion(RegionKind::Deformable))
        ));
        let roles = VertexData::filled(&mesh, Role::Fixed);
        assert!(matches!(
            Regions::from_roles(&mesh, roles),
            Err(BendelsKleinError::EmptyRegion(RegionKind::Handle))
        ));
        // Roles of another mesh of the same size are stale.
        let twin = generators::grid(20, 20, 1.0, 1.0);
        assert!(matches!(
            Regions::from_roles(&mesh, VertexData::filled(&twin, Role::Deformable)),
            Err(BendelsKleinError::Stale(_))
        ));
        // A loop that does not close.
        let open: Vec<HalfedgeId> = mesh.shortest_edge_path(v(0), v(20), None).unwrap();
        let closed = mesh.closed_loop_through(&[v(150), v(160), v(360)]).unwrap();
        assert!(matches!(
            Regions::from_loops(&mesh, &open, &closed),
            Err(BendelsKleinError::BorderNotClosed {
                region: RegionKind::Handle,
                ..
            })
        ));
        // Loops that share vertices touch.
        let inner = mesh.closed_loop_through(&[v(150), v(160), v(300)]).unwrap();
        assert!(Regions::from_loops(&mesh, &inner, &closed).is_err());
    }

    #[test]
    fn a_loop_around_a_torus_handle_does_not_separate() {
        // A cylinder closed into a torus: a loop around the tube leaves one side.
        let (n, m) = (24, 12);
        let mut positions = Vec::new();
        for i in 0..n {
            for j in 0..m {
                let (u, w) = (
                    i as f64 / n as f64 * std::f64::consts::TAU,
                    j as f64 / m as f64 * std::f64::consts::TAU,
                );
                let r = 2.0 + 0.5 * w.cos();
                positions.push(DVec3::new(r * u.cos(), r * u.sin(), 0.5 * w.sin()));
            }
        }
        let id = |i: usize, j: usize| ((i % n) * m + (j % m)) as u32;
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..m {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mesh = Mesh::from_triangles(&positions, &tris).unwrap().0;
        mesh.check().unwrap();
        let v = |i: usize, j: usize| mesh.vertex_at(id(i, j) as usize).unwrap();
        // Around the tube at i = 0 (meridian), and a small loop elsewhere.
        let meridian: Vec<VertexId> = (0..m).step_by(3).map(|j| v(0, j)).collect();
        let small = [v(12, 0), v(14, 0), v(14, 2), v(12, 2)];
        assert!(matches!(
            Regions::from_picks(&mesh, &small, &meridian),
            Err(BendelsKleinError::BorderDoesNotSeparate {
                region: RegionKind::Fixed,
                ..
            })
        ));
    }
}
