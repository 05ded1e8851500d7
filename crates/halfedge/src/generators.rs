//! Simple meshes for tests and benches — a grid (open), a bow-tie (two grids sharing a
//! corner), an icosphere (closed, genus 0), a torus (genus 1), several meshes as one
//! (several components) — and 1-to-4 midpoint
//! subdivision (used to make meshes of millions of triangles from real ones).

use glam::DVec3;

use crate::mesh::Mesh;

/// A planar `nx × ny` grid of quads, each split into two triangles, covering
/// `[0, sx] × [0, sy]` in the `z = 0` plane, faces facing `+z`. Vertex `i + j (nx + 1)`
/// sits at `(i sx / nx, j sy / ny, 0)`.
///
/// # Panics
/// If `nx` or `ny` is zero.
pub fn grid(nx: usize, ny: usize, sx: f64, sy: f64) -> Mesh {
    assert!(nx > 0 && ny > 0, "a grid needs at least one cell");
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(DVec3::new(
                i as f64 * sx / nx as f64,
                j as f64 * sy / ny as f64,
                0.0,
            ));
        }
    }
    let id = |i: usize, j: usize| (i + j * (nx + 1)) as u32;
    let mut triangles = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_triangles(&positions, &triangles)
        .expect("a grid is a valid mesh")
        .0
}

/// Two `n × n` grids of the unit square (`n` at least 1), the second moved by `(1, 1, 0)`,
/// sharing the corner `(1, 1, 0)`: a vertex where two fans meet, which OpenMesh's
/// add-face accepts too (see [`Mesh::is_manifold_vertex`]). One boundary loop passes
/// through it twice. For tests of code that must take such vertices.
pub fn bow_tie(n: usize) -> Mesh {
    let n = n.max(1);
    let g = grid(n, n, 1.0, 1.0);
    let corner = ((n + 1) * (n + 1) - 1) as u32;
    let (mut positions, mut triangles) = g.to_arrays();
    // The second grid without its vertex 0, which is the first grid's corner.
    let base = positions.len() as u32 - 1;
    positions.extend(
        g.positions()[1..]
            .iter()
            .map(|p| (*p + DVec3::new(1.0, 1.0, 0.0)).to_array()),
    );
    let first = triangles.clone();
    triangles.extend(
        first
            .iter()
            .map(|t| t.map(|i| if i == 0 { corner } else { i + base })),
    );
    Mesh::from_arrays(&positions, &triangles)
        .expect("two grids sharing a corner are a valid mesh")
        .0
}

/// The unit icosahedron subdivided `level` times (1-to-4, new vertices projected to the
/// unit sphere): `10·4^level + 2` vertices, `20·4^level` faces.
pub fn icosphere(level: usize) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let positions: Vec<DVec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| DVec3::from_array(p).normalize())
    .collect();
    let triangles: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mesh = Mesh::from_triangles(&positions, &triangles)
        .expect("the icosahedron is valid")
        .0;
    for _ in 0..level {
        mesh = subdivide(&mesh);
        for p in mesh.positions_mut() {
            *p = p.normalize();
        }
    }
    mesh
}

/// A torus around the z axis: tube centre radius `major`, tube radius `minor`, `nu`
/// quads around the axis and `nv` around the tube, each split into two triangles,
/// faces facing outwards; genus 1, closed. Vertex `i + j nu` sits at angle `2π i / nu`
/// around the axis and `2π j / nv` around the tube (`j = 0` on the outer equator).
///
/// # Errors
/// [`Error::InvalidArgument`](crate::Error::InvalidArgument) when `nu` or `nv` is below
/// 3, a radius is not finite, or `minor` is not in `(0, major)`.
pub fn torus(major: f64, minor: f64, nu: usize, nv: usize) -> crate::error::Result<Mesh> {
    if nu < 3 || nv < 3 || !(minor > 0.0 && minor < major && major.is_finite()) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "a torus needs nu, nv ≥ 3 and 0 < minor < major, got {nu}, {nv}, {minor}, {major}"
        )));
    }
    let (n, m) = (nu, nv);
    let count = n.checked_mul(m).filter(|&c| c < u32::MAX as usize / 2);
    let Some(count) = count else {
        return Err(crate::error::Error::InvalidArgument(format!(
            "a torus of {nu} × {nv} quads is too large"
        )));
    };
    let mut positions = Vec::with_capacity(count);
    for j in 0..m {
        for i in 0..n {
            let u = i as f64 / n as f64 * std::f64::consts::TAU;
            let v = j as f64 / m as f64 * std::f64::consts::TAU;
            let r = major + minor * v.cos();
            positions.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % n) + (j % m) * n) as u32;
    let mut triangles = Vec::with_capacity(2 * count);
    for j in 0..m {
        for i in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Ok(Mesh::from_triangles(&positions, &triangles)?.0)
}

/// Several meshes as one, each a component of its own: the live vertices of each mesh
/// in order (the first mesh's first), the faces likewise. A mesh with separate eyes,
/// teeth or nails is made this way in tests.
///
/// # Errors
/// [`Error::EmptyInput`](crate::Error::EmptyInput) when the meshes have no vertex;
/// [`Error::InvalidArgument`](crate::Error::InvalidArgument) for more vertices than
/// 32-bit indices address.
pub fn disjoint_union(meshes: &[&Mesh]) -> crate::error::Result<Mesh> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for mesh in meshes {
        let Ok(base) =
            u32::try_from(positions.len() + mesh.n_vertices()).map(|_| positions.len() as u32)
        else {
            return Err(crate::error::Error::InvalidArgument(
                "the meshes have more vertices than 32-bit indices address".into(),
            ));
        };
        let (p, t) = mesh.to_arrays();
        positions.extend(p);
        triangles.extend(t.into_iter().map(|t| t.map(|i| i + base)));
    }
    Ok(Mesh::from_arrays(&positions, &triangles)?.0)
}

/// 1-to-4 midpoint subdivision: a new vertex at the midpoint of every edge, every
/// triangle split into four; old positions unchanged. The result is compact (no
/// tombstones); old vertices keep their order and come first.
pub fn subdivide(mesh: &Mesh) -> Mesh {
    let mut index = vec![u32::MAX; mesh.vertex_slots()];
    let mut positions: Vec<DVec3> = Vec::with_capacity(mesh.n_vertices() + mesh.n_edges());
    for v in mesh.vertices() {
        index[mesh.vertex_index(v)] = positions.len() as u32;
        positions.push(mesh.position(v));
    }
    let mut midpoint = vec![u32::MAX; mesh.halfedge_slots()];
    for h in mesh.edges() {
        let m = positions.len() as u32;
        positions
            .push(0.5 * (mesh.position(mesh.from_vertex(h)) + mesh.position(mesh.to_vertex(h))));
        midpoint[mesh.halfedge_index(h)] = m;
        midpoint[mesh.halfedge_index(mesh.opposite(h))] = m;
    }
    let mut triangles = Vec::with_capacity(4 * mesh.n_faces());
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let h1 = mesh.next(h0);
        let h2 = mesh.next(h1);
        // corners: v0 = from(h0) = to(h2), v1 = to(h0), v2 = to(h1)
        let [v1, v2, v0] = [h0, h1, h2].map(|h| index[mesh.vertex_index(mesh.to_vertex(h))]);
        let [m01, m12, m20] = [h0, h1, h2].map(|h| midpoint[mesh.halfedge_index(h)]);
        triangles.push([v0, m01, m20]);
        triangles.push([v1, m12, m01]);
        triangles.push([v2, m20, m12]);
        triangles.push([m01, m12, m20]);
    }
    Mesh::from_triangles(&positions, &triangles)
        .expect("subdividing a valid mesh gives a valid mesh")
        .0
}

/// Welds vertices with identical positions (bit-for-bit, `-0.0` and `0.0` alike) and
/// returns the triangles of `mesh` re-indexed onto the welded vertices, without building
/// a mesh: a helper for tests that build meshes from pieces ([`Mesh::welded`] builds
/// the welded mesh).
pub fn weld_exact(mesh: &Mesh) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (positions, triangles) = mesh.to_arrays();
    let points: Vec<DVec3> = positions.iter().map(|&p| DVec3::from_array(p)).collect();
    let (kept, index) = crate::weld::weld_exact(&points);
    let triangles = triangles
        .iter()
        .map(|t| t.map(|i| index[i as usize]))
        .collect();
    (
        kept.iter().map(|&i| points[i as usize]).collect(),
        triangles,
    )
}

/// `mesh` as a triangle soup, as STL files and some exporters write meshes: every face
/// on its own three copies of its corners (positions and triangles, faces in
/// [`Mesh::faces`] order). [`Mesh::welded`] makes the mesh again.
pub fn triangle_soup(mesh: &Mesh) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (positions, triangles) = mesh.to_arrays();
    let corners = triangles
        .iter()
        .flatten()
        .map(|&i| positions[i as usize])
        .collect();
    let faces = (0..triangles.len() as u32)
        .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
        .collect();
    (corners, faces)
}
