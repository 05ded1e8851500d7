use glam::DVec3;

use crate::add_face::{add_face, Connectivity, Refusal, Scratch};
use crate::compact_build::Compact;
use crate::error::{Error, Result};
use crate::handle::{FaceId, VertexId};
use crate::mesh::Mesh;

/// What [`Mesh::from_polygons`] had to do to turn the input into a manifold triangle mesh.
///
/// Building a mesh from indexed polygons, with OpenMesh's importer policy so that the
/// topology matches OpenMesh's on every file.
///
/// - Faces are added in input order by the classic add-face algorithm (OpenMesh
///   `PolyConnectivity::add_face`, pmp `SurfaceMesh::add_face`), which refuses a
///   *complex vertex* (a face vertex not on the boundary), a *complex edge* (a face edge
///   whose halfedge already has a face) and a failed patch re-linking.
/// - A polygon is fan-triangulated from its first vertex and its triangles added in order
///   (OpenMesh `TriConnectivity::add_face`).
/// - A face with fewer than three vertices or a repeated vertex index is dropped.
/// - When a face cannot be added (for a polygon: when its last fan triangle fails), it is
///   added again on fresh copies of its vertices (same positions); the copies are counted.
/// - Out-of-range indices, non-finite coordinates and empty input are errors, checked
///   before anything is built. Unreferenced vertices stay as isolated vertices, and
///   vertex `i` of the input is the vertex with [`Mesh::vertex_index`] `i`.
///
/// For speed the faces are added on bare `u32` connectivity arrays, which are then moved
/// into the [`Mesh`] whole (see `compact_build.rs`). The result is the very mesh that
/// adding the faces to it one by one gives (same handles, links and order; a unit test
/// compares both on non-manifold input).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildReport {
    /// Input polygons.
    pub input_faces: usize,
    /// Vertices added as copies for faces that would have made an edge or a vertex
    /// non-manifold (OpenMesh's importer does the same).
    pub duplicated_vertices: usize,
    /// Faces added on duplicated vertices.
    pub duplicated_faces: usize,
    /// Input faces dropped: fewer than three vertices or a repeated vertex index.
    pub dropped_faces: usize,
    /// Fan triangles of polygons that could not be added although the polygon's last
    /// triangle could, so the polygon was not re-added on copies (OpenMesh loses them
    /// silently; we count them).
    pub dropped_triangles: usize,
    /// Vertices no face refers to (kept as isolated vertices).
    pub unreferenced_vertices: usize,
    /// Vertices merged into another one at exactly the same position by a reader that
    /// welds: an STL file is a triangle soup, welded on reading (see
    /// [`io::stl`](crate::io::stl)); its vertex `i` is then no file vertex. 0 for every
    /// other format and for in-memory input.
    pub merged_vertices: usize,
}

/// Why the add-face algorithm refused a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AddFaceError {
    /// A vertex of the face is already surrounded by faces.
    ComplexVertex(VertexId),
    /// An edge of the face already has a face on this side.
    ComplexEdge(VertexId, VertexId),
    /// The fans around a vertex could not be re-linked to make room for the face.
    PatchRelinkingFailed(VertexId),
    /// A vertex of the face is not a live vertex of this mesh (removed by a collapse,
    /// freed, or a handle of another mesh).
    InvalidVertex(VertexId),
    /// The face names this vertex twice.
    RepeatedVertex(VertexId),
}

impl std::fmt::Display for AddFaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ComplexVertex(v) => write!(f, "complex vertex {v}"),
            Self::ComplexEdge(a, b) => write!(f, "complex edge {a}-{b}"),
            Self::PatchRelinkingFailed(v) => write!(f, "patch re-linking failed at {v}"),
            Self::InvalidVertex(v) => write!(f, "{v} is not a live vertex of this mesh"),
            Self::RepeatedVertex(v) => write!(f, "the face names {v} twice"),
        }
    }
}
impl std::error::Error for AddFaceError {}

/// # Building
impl Mesh {
    /// Builds a mesh from positions and indexed polygons (0-based indices), with the
    /// policy of the [`BuildReport`](crate::BuildReport) docs. Returns the mesh and a report of what was
    /// duplicated and dropped.
    ///
    /// ```
    /// use glam::DVec3;
    /// let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    /// let (mesh, report) = halfedge::Mesh::from_polygons(&p, [[0u32, 1, 3, 2]]).unwrap();
    /// assert_eq!((mesh.n_faces(), report.dropped_faces), (2, 0));
    /// ```
    pub fn from_polygons<I, F>(positions: &[DVec3], polygons: I) -> Result<(Mesh, BuildReport)>
    where
        I: IntoIterator<Item = F>,
        I::IntoIter: Clone,
        F: AsRef<[u32]>,
    {
        check_positions(positions)?;
        Self::build(positions, polygons, true)
    }

    /// [`from_polygons`](Self::from_polygons), on the compact arrays when `compact` and
    /// the input fits them, else on the mesh itself (same algorithm, same result).
    fn build<I, F>(positions: &[DVec3], polygons: I, compact: bool) -> Result<(Mesh, BuildReport)>
    where
        I: IntoIterator<Item = F>,
        I::IntoIter: Clone,
        F: AsRef<[u32]>,
    {
        let polygons = polygons.into_iter();
        let mut survey = Survey::new(positions.len());
        survey.add(polygons.clone())?;
        let (n_faces, mut report) = survey.finish()?;
        if compact {
            let mut compact = Compact::new(positions.len(), n_faces);
            add_polygons(&mut compact, |i| i, polygons, &mut report);
            return Ok((compact.into_mesh(positions.to_vec()), report));
        }
        // The same algorithm on the mesh itself (tests compare the two).
        let mut mesh = Mesh::with_capacity(positions.len(), n_faces);
        let vertices: Vec<VertexId> = positions.iter().map(|&p| mesh.add_vertex(p)).collect();
        add_polygons(&mut mesh, |i| vertices[i as usize], polygons, &mut report);
        Ok((mesh, report))
    }

    /// [`from_polygons`](Self::from_polygons) for the loaders: positions by value (they
    /// become the mesh's), polygons in blocks, each freed as soon as its faces are in the
    /// mesh, so that the memory peak of a load is about the mesh's own size.
    pub(crate) fn from_polygon_blocks(
        positions: Vec<DVec3>,
        blocks: Vec<PolygonBlock>,
    ) -> Result<(Mesh, BuildReport)> {
        check_positions(&positions)?;
        let mut survey = Survey::new(positions.len());
        for block in &blocks {
            survey.add(block.polygons())?;
        }
        let (n_faces, mut report) = survey.finish()?;
        let mut compact = Compact::new(positions.len(), n_faces);
        for block in blocks {
            add_polygons(&mut compact, |i| i, block.polygons(), &mut report);
        }
        Ok((compact.into_mesh(positions), report))
    }

    /// Builds a mesh from triangles; see [`from_polygons`](Self::from_polygons).
    pub fn from_triangles(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
    ) -> Result<(Mesh, BuildReport)> {
        Self::from_polygons(positions, triangles.iter())
    }

    /// Adds a triangle on existing vertices by the add-face algorithm; on error nothing
    /// is changed.
    ///
    /// # Errors
    /// [`AddFaceError::InvalidVertex`] for a vertex that is not live in this mesh,
    /// [`AddFaceError::RepeatedVertex`] for a vertex named twice, and the add-face
    /// algorithm's refusals.
    pub fn add_triangle(
        &mut self,
        a: VertexId,
        b: VertexId,
        c: VertexId,
    ) -> Result<FaceId, AddFaceError> {
        if let Some(&v) = [a, b, c].iter().find(|&&v| !self.is_valid_vertex(v)) {
            return Err(AddFaceError::InvalidVertex(v));
        }
        if a == b || a == c {
            return Err(AddFaceError::RepeatedVertex(a));
        }
        if b == c {
            return Err(AddFaceError::RepeatedVertex(b));
        }
        add_face(self, &[a, b, c], &mut Scratch::default()).map_err(AddFaceError::from)
    }
}

impl From<Refusal<VertexId>> for AddFaceError {
    fn from(r: Refusal<VertexId>) -> Self {
        match r {
            Refusal::ComplexVertex(v) => Self::ComplexVertex(v),
            Refusal::ComplexEdge(a, b) => Self::ComplexEdge(a, b),
            Refusal::PatchRelinkingFailed(v) => Self::PatchRelinkingFailed(v),
        }
    }
}

/// `Err` for no positions or a non-finite coordinate.
fn check_positions(positions: &[DVec3]) -> Result<()> {
    if positions.is_empty() {
        return Err(Error::EmptyInput);
    }
    for (i, p) in positions.iter().enumerate() {
        if let Some(&value) = p.to_array().iter().find(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate { vertex: i, value });
        }
    }
    Ok(())
}

/// The first pass over the input polygons, before anything is built: indices in range,
/// number of triangles, vertices no polygon refers to.
struct Survey {
    referenced: Vec<bool>,
    polygons: usize,
    triangles: usize,
}

impl Survey {
    fn new(n_vertices: usize) -> Self {
        Self {
            referenced: vec![false; n_vertices],
            polygons: 0,
            triangles: 0,
        }
    }

    /// Surveys the next polygons (numbered on from those surveyed before).
    fn add<F: AsRef<[u32]>>(&mut self, polygons: impl Iterator<Item = F>) -> Result<()> {
        let n = self.referenced.len();
        for poly in polygons {
            self.triangles += poly.as_ref().len().saturating_sub(2);
            for &i in poly.as_ref() {
                match self.referenced.get_mut(i as usize) {
                    Some(r) => *r = true,
                    None => {
                        return Err(Error::IndexOutOfRange {
                            face: self.polygons,
                            index: u64::from(i),
                            vertex_count: n,
                        })
                    }
                }
            }
            self.polygons += 1;
        }
        Ok(())
    }

    /// The number of triangles to make room for and the report so far; `Err` when they
    /// are more than `u32` slot indices can address.
    fn finish(self) -> Result<(usize, BuildReport)> {
        let n = self.referenced.len();
        let report = BuildReport {
            unreferenced_vertices: self.referenced.iter().filter(|&&r| !r).count(),
            ..BuildReport::default()
        };
        // At most 2 halfedges per triangle edge, twice over when a face is re-added on
        // copies of its vertices.
        let max_halfedges = self.triangles.saturating_mul(12);
        if max_halfedges > Compact::MAX_HALFEDGES || n > Compact::MAX_HALFEDGES {
            return Err(Error::InvalidArgument(format!(
                "{n} vertices and {} triangles are more than 32-bit slot indices can address",
                self.triangles
            )));
        }
        Ok((self.triangles, report))
    }
}

/// A block of indexed polygons as a loader reads them: all indices one polygon after
/// another, and the start of every polygon unless all are triangles.
#[derive(Debug, Default)]
pub(crate) struct PolygonBlock {
    /// All polygon indices, one polygon after another.
    pub(crate) indices: Vec<u32>,
    /// Start of every polygon in `indices`, plus the end of the last one; `None` while all
    /// polygons are triangles (the common case, which then needs no offsets).
    pub(crate) offsets: Option<Vec<usize>>,
}

impl PolygonBlock {
    /// Records that the polygon starting at `start` in `indices` ends at their end.
    pub(crate) fn end_polygon(&mut self, start: usize) {
        let end = self.indices.len();
        match &mut self.offsets {
            Some(offsets) => offsets.push(end),
            None if end - start == 3 => {}
            None => {
                let mut offsets: Vec<usize> = (0..=start).step_by(3).collect();
                offsets.push(end);
                self.offsets = Some(offsets);
            }
        }
    }

    /// The polygons, in order.
    fn polygons(&self) -> Polygons<'_> {
        Polygons {
            indices: &self.indices,
            offsets: self.offsets.as_deref(),
            next: 0,
        }
    }
}

/// Iterator over the polygons of a [`PolygonBlock`].
#[derive(Clone)]
struct Polygons<'a> {
    indices: &'a [u32],
    offsets: Option<&'a [usize]>,
    /// Number of the next polygon.
    next: usize,
}

impl<'a> Iterator for Polygons<'a> {
    type Item = &'a [u32];
    #[inline]
    fn next(&mut self) -> Option<&'a [u32]> {
        let k = self.next;
        let polygon = match self.offsets {
            None => self.indices.get(3 * k..3 * k + 3)?,
            Some(offsets) => self.indices.get(*offsets.get(k)?..*offsets.get(k + 1)?)?,
        };
        self.next += 1;
        Some(polygon)
    }
}

/// What the builder needs besides the add-face algorithm: copies of vertices.
trait BuildTarget: Connectivity {
    /// Adds a vertex at the position of `v`.
    fn copy_vertex(&mut self, v: Self::V) -> Self::V;
}

impl BuildTarget for Mesh {
    fn copy_vertex(&mut self, v: VertexId) -> VertexId {
        let p = self.position(v);
        self.add_vertex(p)
    }
}

impl BuildTarget for Compact {
    fn copy_vertex(&mut self, v: u32) -> u32 {
        Compact::copy_vertex(self, v)
    }
}

/// The importer policy of the [docs above](Self), on any build target. Indices have
/// been checked.
fn add_polygons<M, I, F>(
    m: &mut M,
    vertex: impl Fn(u32) -> M::V,
    polygons: I,
    report: &mut BuildReport,
) where
    M: BuildTarget,
    I: Iterator<Item = F>,
    F: AsRef<[u32]>,
{
    let mut scratch = Scratch::default();
    let mut face_vertices: Vec<M::V> = Vec::new();
    for poly in polygons {
        let poly = poly.as_ref();
        report.input_faces += 1;
        if poly.len() < 3 || has_repeated_index(poly) {
            report.dropped_faces += 1;
            continue;
        }
        face_vertices.clear();
        face_vertices.extend(poly.iter().map(|&i| vertex(i)));
        let (last_ok, failed) = add_polygon(m, &face_vertices, &mut scratch);
        if last_ok {
            report.dropped_triangles += failed;
            continue;
        }
        // The face would make the mesh non-manifold: add it (all its fan triangles)
        // again on fresh vertices, as OpenMesh's importer does.
        for v in face_vertices.iter_mut() {
            *v = m.copy_vertex(*v);
        }
        report.duplicated_vertices += face_vertices.len();
        report.duplicated_faces += 1;
        let (ok, _) = add_polygon(m, &face_vertices, &mut scratch);
        debug_assert!(ok, "a face on fresh vertices always fits");
    }
}

/// Fan-triangulates a polygon from its first vertex and adds its triangles in order
/// (OpenMesh's `TriConnectivity::add_face`); returns whether the last one was added and
/// how many failed.
fn add_polygon<M: Connectivity>(
    m: &mut M,
    vs: &[M::V],
    scratch: &mut Scratch<M::H>,
) -> (bool, usize) {
    let mut failed = 0;
    let mut last_ok = false;
    for i in 1..vs.len() - 1 {
        last_ok = add_face(m, &[vs[0], vs[i], vs[i + 1]], scratch).is_ok();
        if !last_ok {
            failed += 1;
        }
    }
    (last_ok, failed)
}

fn has_repeated_index(poly: &[u32]) -> bool {
    if poly.len() <= 8 {
        (1..poly.len()).any(|i| poly[..i].contains(&poly[i]))
    } else {
        let mut sorted = poly.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).any(|w| w[0] == w[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// `../shared/meshes` above the crate, or `$MULTIRES_MESHES` (real-mesh tier).
    fn shared_meshes() -> PathBuf {
        if let Some(dir) = std::env::var_os("MULTIRES_MESHES") {
            return PathBuf::from(dir);
        }
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .ancestors()
            .map(|a| a.join("shared/meshes"))
            .find(|d| d.is_dir())
            .expect("the real-mesh tier needs `shared/meshes` above the workspace, or MULTIRES_MESHES=DIR")
    }

    /// The positions and polygons of an OBJ file as they are (quads, pentagons,
    /// non-manifold faces), with a minimal reader of `v` and `f` lines.
    fn obj_polygons(path: &std::path::Path) -> (Vec<DVec3>, Vec<Vec<u32>>) {
        let text = std::fs::read_to_string(path).unwrap();
        let mut positions = Vec::new();
        let mut polygons: Vec<Vec<u32>> = Vec::new();
        for line in text.lines() {
            let mut tokens = line.split_whitespace();
            match tokens.next() {
                Some("v") => {
                    let c: Vec<f64> = tokens.take(3).map(|t| t.parse().unwrap()).collect();
                    positions.push(DVec3::new(c[0], c[1], c[2]));
                }
                Some("f") => polygons.push(
                    tokens
                        .map(|t| t.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                        .collect(),
                ),
                _ => {}
            }
        }
        (positions, polygons)
    }

    /// Both builds agree on the file's polygons, and again with every seventh face
    /// flipped (plenty of conflicts).
    fn same_build_of_file(path: &std::path::Path) {
        let (positions, mut polygons) = obj_polygons(path);
        same_build(&positions, &polygons);
        for (k, p) in polygons.iter_mut().enumerate() {
            if k % 7 == 3 {
                p.reverse();
            }
        }
        same_build(&positions, &polygons);
    }

    /// Every link of both meshes, by element index.
    fn links(m: &Mesh) -> Vec<[usize; 6]> {
        let face = |f: Option<FaceId>| f.map_or(usize::MAX, |f| m.face_index(f));
        let mut all: Vec<[usize; 6]> = m
            .halfedges()
            .map(|h| {
                [
                    m.halfedge_index(h),
                    m.halfedge_index(m.next(h)),
                    m.halfedge_index(m.prev(h)),
                    m.halfedge_index(m.opposite(h)),
                    m.vertex_index(m.to_vertex(h)),
                    face(m.face(h)),
                ]
            })
            .collect();
        all.extend(m.vertices().map(|v| {
            let h = m
                .vertex_halfedge(v)
                .map_or(usize::MAX, |h| m.halfedge_index(h));
            [usize::MAX, m.vertex_index(v), h, 0, 0, 0]
        }));
        all.extend(m.faces().map(|f| {
            [
                usize::MAX - 1,
                m.face_index(f),
                m.halfedge_index(m.face_halfedge(f)),
                0,
                0,
                0,
            ]
        }));
        all
    }

    fn same_build(positions: &[DVec3], polygons: &[Vec<u32>]) {
        let (a, ra) = Mesh::build(positions, polygons, true).unwrap();
        let (b, rb) = Mesh::build(positions, polygons, false).unwrap();
        a.check().unwrap();
        assert_eq!(ra, rb);
        assert_eq!(a.positions(), b.positions());
        assert_eq!(links(&a), links(&b));
        let counts = |m: &Mesh| {
            [
                m.n_vertices(),
                m.n_halfedges(),
                m.n_faces(),
                m.vertex_slots(),
                m.halfedge_slots(),
                m.face_slots(),
            ]
        };
        assert_eq!(counts(&a), counts(&b));
    }

    #[test]
    fn compact_build_equals_building_on_the_mesh() {
        // Non-manifold input of every kind: shared edges of three faces, bow-ties,
        // flipped faces, polygons, degenerate faces.
        let positions: Vec<DVec3> = (0..12)
            .map(|i| DVec3::new(i as f64, (i * i % 7) as f64, 0.0))
            .collect();
        let polygons: Vec<Vec<u32>> = vec![
            vec![0, 1, 2],
            vec![1, 0, 3],
            vec![0, 1, 4],
            vec![2, 1, 5, 6],
            vec![0, 2, 7],
            vec![0, 8, 9],
            vec![0, 9, 10],
            vec![0, 10, 8],
            vec![2, 2, 3],
            vec![3, 1, 2],
            vec![5, 11, 6],
            vec![6, 11, 5],
        ];
        same_build(&positions, &polygons);
        // The project's own meshes: dirty input (a fin, a bow-tie, a face twice, a
        // pentagon), quads with a hole, several components.
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
        for name in ["dirty.obj", "quads_hole.obj", "creature.obj"] {
            same_build_of_file(&data.join(name));
        }
    }

    #[test]
    #[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
    fn compact_build_equals_building_on_the_mesh_on_real_meshes() {
        let dir = shared_meshes();
        for name in [
            "cow.obj",
            "suzanne.obj",
            "teapot.obj",
            "beast.obj",
            "stanford-bunny.obj",
        ] {
            same_build_of_file(&dir.join(name));
        }
    }

    /// Blocks of `polygons` cut before the polygons numbered in `cuts`.
    fn blocks(polygons: &[Vec<u32>], cuts: &[usize]) -> Vec<PolygonBlock> {
        let mut blocks = vec![PolygonBlock::default()];
        for (k, poly) in polygons.iter().enumerate() {
            if cuts.contains(&k) {
                blocks.push(PolygonBlock::default());
            }
            let block = blocks.last_mut().unwrap();
            let start = block.indices.len();
            block.indices.extend_from_slice(poly);
            block.end_polygon(start);
        }
        blocks
    }

    /// Polygons in blocks (cut anywhere, empty blocks included; triangles-only blocks
    /// without offsets, others with) build the very mesh the same polygons in one piece
    /// build; an out-of-range index is reported with its polygon's number in the whole
    /// input, and bad positions are refused as by `from_polygons`.
    #[test]
    fn blocks_build_what_one_piece_builds() {
        let positions: Vec<DVec3> = (0..12)
            .map(|i| DVec3::new(i as f64, (i * i % 7) as f64, 0.0))
            .collect();
        let polygons: Vec<Vec<u32>> = vec![
            vec![0, 1, 2],
            vec![1, 0, 3],
            vec![0, 1, 4],
            vec![2, 1, 5, 6],
            vec![0, 2, 7],
            vec![0, 8, 9],
            vec![0, 9, 10],
            vec![0, 10, 8],
            vec![2, 2, 3],
            vec![3, 1],
            vec![3, 1, 2],
            vec![5, 11, 6],
            vec![6, 11, 5],
        ];
        let (whole, whole_report) = Mesh::from_polygons(&positions, &polygons).unwrap();
        let n = polygons.len();
        for a in 0..=n {
            for b in a..=n {
                let blocks = blocks(&polygons, &[a, b]);
                let (mesh, report) = Mesh::from_polygon_blocks(positions.clone(), blocks).unwrap();
                mesh.check().unwrap();
                assert_eq!(report, whole_report, "cuts {a}, {b}");
                assert_eq!(mesh.positions(), whole.positions());
                assert_eq!(links(&mesh), links(&whole), "cuts {a}, {b}");
            }
        }
        let mut bad = polygons.clone();
        bad[11][1] = 12;
        for cut in [0, 5, 11, 12] {
            let e = Mesh::from_polygon_blocks(positions.clone(), blocks(&bad, &[cut])).unwrap_err();
            assert!(
                matches!(
                    e,
                    Error::IndexOutOfRange {
                        face: 11,
                        index: 12,
                        vertex_count: 12
                    }
                ),
                "{e:?}"
            );
        }
        let mut nan = positions.clone();
        nan[3].y = f64::NAN;
        assert!(matches!(
            Mesh::from_polygon_blocks(nan, blocks(&polygons, &[4])),
            Err(Error::NonFiniteCoordinate { vertex: 3, .. })
        ));
        assert!(matches!(
            Mesh::from_polygon_blocks(Vec::new(), Vec::new()),
            Err(Error::EmptyInput)
        ));
    }

    /// A binary PLY of several soup blocks (a 700 × 600 grid: 840,000 triangles, 2.5 M
    /// indices) reads back as the mesh written, face for face.
    #[test]
    fn a_ply_of_several_blocks_reads_back() {
        let grid = crate::generators::grid(700, 600, 1.0, 1.0);
        assert!(3 * grid.n_faces() > 2 * crate::io::ply_layout::PolygonSoup::BLOCK);
        let mut bytes = Vec::new();
        crate::io::write_ply_to(&mut bytes, &grid, crate::io::PlyFormat::BinaryLittleEndian)
            .unwrap();
        let (back, report) =
            crate::io::read_ply_from_bytes(&bytes, std::path::Path::new("grid.ply")).unwrap();
        assert_eq!(report.input_faces, grid.n_faces());
        assert_eq!(back.positions(), grid.positions());
        let triangles = |m: &Mesh| -> Vec<[usize; 3]> {
            m.faces()
                .map(|f| m.triangle(f).map(|v| m.vertex_index(v)))
                .collect()
        };
        assert_eq!(triangles(&back), triangles(&grid));
        back.check().unwrap();
    }
}
