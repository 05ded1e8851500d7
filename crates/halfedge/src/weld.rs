use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash};

use glam::DVec3;

use crate::build::BuildReport;

use crate::error::{Error, Result};

use crate::mesh::Mesh;

/// What [`Mesh::welded`] did.
///
/// Welding: vertices at the same place merged into one.
///
/// Meshes exported as triangle soups (every face on its own three vertices, as STL
/// files and some converters write them) or with seams (every texture chart on its own
/// copies of its border vertices) read as many small open pieces: nothing can be
/// simplified across their cuts, and the editing methods see boundaries everywhere.
/// [`Mesh::welded`] merges vertices that lie within a tolerance of each other and
/// builds the mesh again (the policy of [`Mesh::from_polygons`]: a face that would make
/// an edge or a vertex non-manifold goes onto copies of its vertices).
///
/// ```
/// use halfedge::{generators, Mesh};
/// // An icosphere as a soup: every triangle on its own copies of its corners.
/// let sphere = generators::icosphere(1);
/// let (corners, triangles) = generators::triangle_soup(&sphere);
/// let (soup, _) = Mesh::from_arrays(&corners, &triangles).unwrap();
/// assert_eq!(soup.topology_report().components, 80);
///
/// let (welded, report) = soup.welded(0.0).unwrap();
/// assert_eq!((welded.n_vertices(), welded.n_faces()), (42, 80));
/// assert_eq!(report.merged_vertices, 240 - 42);
/// assert_eq!(welded.topology_report().components, 1);
/// assert_eq!(welded.topology_report().boundary_loops, 0);
///
/// // What a file loader calls: the welded mesh only when welding closes boundaries.
/// assert!(soup.welded_seams().unwrap().is_some());
/// assert!(welded.welded_seams().unwrap().is_none());
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WeldReport {
    /// For every live vertex of the mesh welded, in [`Mesh::to_arrays`] numbering (its
    /// [`Mesh::vertex_index`] for a mesh without removed vertices), the vertex index it
    /// became in the welded mesh.
    pub vertex_map: Vec<u32>,
    /// Vertices merged into another one: the live vertices before minus the vertices
    /// the welding kept.
    pub merged_vertices: usize,
    /// Faces dropped because welding put two of their corners on one vertex (faces
    /// thinner than the tolerance).
    pub collapsed_faces: usize,
    /// How the welded mesh was built (faces put on copies of their vertices where
    /// welding made an edge or a vertex non-manifold).
    pub build: BuildReport,
}

/// Largest coordinate over tolerance that the grid of [`Mesh::welded`] numbers cells
/// for (cell indices stay exact in `f64` and fit `i64`).
const MAX_CELLS_PER_AXIS: f64 = 9.0e15;

/// # Welding
impl Mesh {
    /// A copy of this mesh with the vertices within `tolerance` of each other merged:
    /// each vertex, in [`to_arrays`](Self::to_arrays) order, joins the first earlier
    /// kept vertex within `tolerance` (Euclidean distance, ties to the lowest index),
    /// else it is kept. Kept vertices keep their positions (nothing is averaged), in
    /// their order, so a mesh with nothing to weld comes back with the same numbering.
    /// With `tolerance` 0, vertices are merged only at exactly the same position
    /// (`-0.0` and `0.0` are the same). Faces that end up with a repeated vertex are
    /// dropped ([`WeldReport::collapsed_faces`]); the others are built again by
    /// [`Mesh::from_polygons`]. Attributes, labels and removed slots are not carried
    /// over: the welded mesh is a new mesh, and [`WeldReport::vertex_map`] carries
    /// per-vertex data across.
    ///
    /// Merging is by a grid of cells `tolerance` wide, so the work is linear in the
    /// number of vertices; a chain of vertices each within `tolerance` of the next is
    /// not merged transitively beyond the first one's reach.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a tolerance that is negative or not finite, or so
    /// small against the coordinates that the grid's cells cannot be numbered
    /// (coordinates over tolerance beyond 9e15); [`Error::EmptyInput`] for a mesh
    /// without vertices. The mesh itself is never changed.
    pub fn welded(&self, tolerance: f64) -> Result<(Mesh, WeldReport)> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(Error::InvalidArgument(format!(
                "the welding tolerance must be finite and not negative, got {tolerance}"
            )));
        }
        let (positions, triangles) = self.to_arrays();
        if positions.is_empty() {
            return Err(Error::EmptyInput);
        }
        let points: Vec<DVec3> = positions.iter().map(|&p| DVec3::from_array(p)).collect();
        let (kept, vertex_map) = if tolerance == 0.0 {
            weld_exact(&points)
        } else {
            weld_within(&points, tolerance)?
        };
        let mut collapsed_faces = 0;
        let faces: Vec<[u32; 3]> = triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| vertex_map[i as usize]);
                if a == b || b == c || a == c {
                    collapsed_faces += 1;
                    None
                } else {
                    Some([a, b, c])
                }
            })
            .collect();
        let kept_positions: Vec<DVec3> = kept.iter().map(|&i| points[i as usize]).collect();
        let (mesh, build) = Mesh::from_triangles(&kept_positions, &faces)?;
        Ok((
            mesh,
            WeldReport {
                merged_vertices: points.len() - kept.len(),
                vertex_map,
                collapsed_faces,
                build,
            },
        ))
    }

    /// The mesh with its seams closed, if it has any: [`welded`](Self::welded) at
    /// exactly the same positions, returned only when that leaves fewer boundary loops
    /// (a triangle soup, or an export that cut the surface along texture seams or
    /// patch borders); `None` when welding closes nothing (no vertices share a
    /// position, or only copies the builder made for non-manifold faces, which the
    /// welded mesh would make again). What applications loading files call to offer
    /// the surface rather than the file's pieces.
    ///
    /// # Errors
    /// [`Error::EmptyInput`] for a mesh without vertices.
    pub fn welded_seams(&self) -> Result<Option<(Mesh, WeldReport)>> {
        // Most meshes have no two vertices at one place: answered without a rebuild.
        let positions: Vec<DVec3> = self.vertices().map(|v| self.position(v)).collect();
        if positions.is_empty() {
            return Err(Error::EmptyInput);
        }
        if weld_exact(&positions).0.len() == positions.len() {
            return Ok(None);
        }
        let (welded, report) = self.welded(0.0)?;
        let loops = |mesh: &Mesh| mesh.topology_report().boundary_loops;
        Ok(
            (report.merged_vertices > 0 && loops(&welded) < loops(self))
                .then_some((welded, report)),
        )
    }
}

/// Vertices at bit-identical positions (up to the sign of zero) merged: the kept
/// vertices (indices into `points`, in order) and every point's kept vertex's new
/// index (see [`weld_by_key`]).
pub(crate) fn weld_exact(points: &[DVec3]) -> (Vec<u32>, Vec<u32>) {
    // `+ 0.0` turns -0.0 into 0.0 and leaves every other value as it is.
    // A mesh's vertices are mostly distinct: room for all of them, no rehashing.
    weld_by_key(points.len(), points.len(), |i| {
        (points[i] + DVec3::ZERO).to_array().map(f64::to_bits)
    })
}

/// Items with equal keys merged, the one exact weld of the crate (vertices of a mesh,
/// corners of an STL soup): the kept items (the first of each key, in order) and every
/// item's kept item's new index. One pass through a hash map of the keys
/// ([`KeyHasher`]), with room for `expected` distinct keys.
pub(crate) fn weld_by_key<K: Eq + Hash>(
    n: usize,
    expected: usize,
    key: impl Fn(usize) -> K,
) -> (Vec<u32>, Vec<u32>) {
    let mut first: HashMap<K, u32, BuildHasherDefault<KeyHasher>> =
        HashMap::with_capacity_and_hasher(expected.min(n), BuildHasherDefault::default());
    let mut kept = Vec::new();
    let map = (0..n)
        .map(|i| {
            *first.entry(key(i)).or_insert_with(|| {
                kept.push(i as u32);
                (kept.len() - 1) as u32
            })
        })
        .collect();
    (kept, map)
}

/// A hasher for keys of a few machine words (position bits): multiply-rotate over the
/// words, then a full 64-bit finalizer (murmur3's), so that keys that differ only in high
/// bits (coordinates on a coarse grid) spread over the table as well.
#[derive(Default)]
pub(crate) struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(26) ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
    fn write_usize(&mut self, _: usize) {
        // The length of an array key: always the same.
    }
}

/// A hasher for grid cells (three `i64`s): multiply and rotate, far quicker than the
/// standard library's keyed hash for the 27 lookups per point of [`weld_within`].
#[derive(Default)]
struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(23) ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// Grid cells: the last kept vertex put in each (the others by [`weld_within`]'s links).
type Cells = HashMap<[i64; 3], u32, std::hash::BuildHasherDefault<CellHasher>>;

/// Vertices within `tolerance` (positive) of an earlier kept vertex merged into the
/// first such one, found in the 27 grid cells around each point.
fn weld_within(points: &[DVec3], tolerance: f64) -> Result<(Vec<u32>, Vec<u32>)> {
    let cell_of = |p: DVec3| -> Option<[i64; 3]> {
        let c = (p / tolerance).floor();
        (c.abs().max_element() <= MAX_CELLS_PER_AXIS).then(|| c.to_array().map(|x| x as i64))
    };
    let mut cells = Cells::with_capacity_and_hasher(points.len(), Default::default());
    // For each kept vertex, the kept vertex put in its cell before it (`NONE`: none).
    let mut earlier_in_cell: Vec<u32> = Vec::with_capacity(points.len());
    const NONE: u32 = u32::MAX;
    let mut kept: Vec<u32> = Vec::new();
    let mut map = Vec::with_capacity(points.len());
    let squared = tolerance * tolerance;
    for (i, &p) in points.iter().enumerate() {
        let cell = cell_of(p).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "the welding tolerance {tolerance} is too small for vertex {i} at {p}: \
                 its coordinates are more than {MAX_CELLS_PER_AXIS:e} tolerances from the origin"
            ))
        })?;
        let mut found: Option<u32> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                    let mut k = cells.get(&near).copied().unwrap_or(NONE);
                    while k != NONE {
                        let q = points[kept[k as usize] as usize];
                        if q.distance_squared(p) <= squared && found.is_none_or(|f| k < f) {
                            found = Some(k);
                        }
                        k = earlier_in_cell[k as usize];
                    }
                }
            }
        }
        let k = found.unwrap_or_else(|| {
            kept.push(i as u32);
            let k = (kept.len() - 1) as u32;
            earlier_in_cell.push(cells.insert(cell, k).unwrap_or(NONE));
            k
        });
        map.push(k);
    }
    Ok((kept, map))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    /// `mesh` as a triangle soup ([`generators::triangle_soup`]), each coordinate moved
    /// by a deterministic offset of at most `jitter`.
    fn soup(mesh: &Mesh, jitter: f64) -> Mesh {
        let (corners, faces) = generators::triangle_soup(mesh);
        let mut k = 0u64;
        let points: Vec<[f64; 3]> = corners
            .iter()
            .map(|p| {
                k = k
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let unit = (k >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                p.map(|x| x + 2.0 * jitter * unit)
            })
            .collect();
        Mesh::from_arrays(&points, &faces).unwrap().0
    }

    #[test]
    fn a_soup_welds_back_to_the_mesh_it_came_from() {
        let sphere = generators::icosphere(3);
        let (welded, report) = soup(&sphere, 0.0).welded(0.0).unwrap();
        welded.check().unwrap();
        assert_eq!(welded.n_vertices(), sphere.n_vertices());
        assert_eq!(welded.n_faces(), sphere.n_faces());
        assert_eq!(report.collapsed_faces, 0);
        assert_eq!(report.build.duplicated_vertices, 0);
        let topology = welded.topology_report();
        assert_eq!((topology.components, topology.boundary_loops), (1, 0));
        assert_eq!(topology.euler, 2);
        // Every soup corner maps to a vertex at its own position.
        let (positions, _) = soup(&sphere, 0.0).to_arrays();
        for (i, &k) in report.vertex_map.iter().enumerate() {
            let v = welded.vertex_at(k as usize).unwrap();
            assert_eq!(welded.position(v).to_array(), positions[i]);
        }
    }

    #[test]
    fn a_jittered_soup_welds_within_the_tolerance_and_not_below_it() {
        let sphere = generators::icosphere(2);
        let edge = sphere
            .edges()
            .map(|e| sphere.edge_length(e))
            .fold(f64::INFINITY, f64::min);
        let jittered = soup(&sphere, 1e-4 * edge);
        // Corners of one vertex are at most 2·√3·1e-4 edges apart.
        let (welded, report) = jittered.welded(1e-3 * edge).unwrap();
        welded.check().unwrap();
        assert_eq!(welded.n_vertices(), sphere.n_vertices());
        assert_eq!(
            report.merged_vertices,
            jittered.n_vertices() - sphere.n_vertices()
        );
        assert_eq!(welded.topology_report().boundary_loops, 0);
        // Exact welding merges none of them.
        let (unwelded, report) = jittered.welded(0.0).unwrap();
        assert_eq!(report.merged_vertices, 0);
        assert_eq!(unwelded.n_vertices(), jittered.n_vertices());
    }

    #[test]
    fn nothing_to_weld_keeps_the_mesh_and_its_numbering() {
        let mesh = generators::grid(5, 4, 1.0, 1.0);
        let (welded, report) = mesh.welded(1e-6).unwrap();
        assert_eq!(welded.to_arrays(), mesh.to_arrays());
        assert_eq!(report.merged_vertices, 0);
        assert!(report
            .vertex_map
            .iter()
            .enumerate()
            .all(|(i, &k)| k as usize == i));
    }

    #[test]
    fn faces_thinner_than_the_tolerance_are_dropped() {
        // Two triangles, the second a sliver 1e-9 wide.
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1e-9, 0.0],
        ];
        let (mesh, _) = Mesh::from_arrays(&positions, &[[0, 1, 2], [0, 3, 1]]).unwrap();
        let (welded, report) = mesh.welded(1e-6).unwrap();
        assert_eq!(report.collapsed_faces, 1);
        assert_eq!((welded.n_vertices(), welded.n_faces()), (3, 1));
        assert_eq!(report.vertex_map, vec![0, 1, 2, 1]);
    }

    #[test]
    fn a_bad_tolerance_is_refused_and_the_mesh_is_unchanged() {
        let mesh = generators::icosphere(1);
        let before = mesh.to_arrays();
        for tolerance in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                mesh.welded(tolerance),
                Err(Error::InvalidArgument(_))
            ));
        }
        // A tolerance too small for the coordinates to be put in cells.
        let far: Vec<[f64; 3]> = before.0.iter().map(|p| p.map(|x| x + 1e10)).collect();
        let (far, _) = Mesh::from_arrays(&far, &before.1).unwrap();
        let refused = far.welded(1e-7);
        assert!(
            matches!(&refused, Err(Error::InvalidArgument(m)) if m.contains("too small")),
            "{refused:?}"
        );
        assert_eq!(mesh.to_arrays(), before);
    }

    #[test]
    fn seams_are_welded_only_when_that_closes_boundaries() {
        let sphere = generators::icosphere(2);
        assert!(sphere.welded_seams().unwrap().is_none());
        let (closed, report) = soup(&sphere, 0.0).welded_seams().unwrap().unwrap();
        assert_eq!(closed.n_vertices(), sphere.n_vertices());
        assert_eq!(report.build.duplicated_vertices, 0);
        // Two cones touching at their apex: the builder puts the second cone's faces
        // on copies of their vertices; welding them back closes nothing.
        let mut positions = vec![DVec3::ZERO];
        let mut triangles = Vec::new();
        for (side, z) in [(0u32, 1.0), (1, -1.0)] {
            let first = positions.len() as u32;
            for k in 0..5 {
                let a = k as f64 * std::f64::consts::TAU / 5.0;
                positions.push(DVec3::new(a.cos(), a.sin(), z));
            }
            for k in 0..5u32 {
                let (b, c) = (first + k, first + (k + 1) % 5);
                triangles.push(if side == 0 { [0, b, c] } else { [0, c, b] });
            }
        }
        let (cones, built) = Mesh::from_triangles(&positions, &triangles).unwrap();
        assert!(built.duplicated_vertices > 0);
        assert!(cones.welded_seams().unwrap().is_none());
    }

    #[test]
    fn opposite_signs_of_zero_weld() {
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-0.0, 0.0, -0.0],
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0],
        ];
        let (mesh, _) = Mesh::from_arrays(&positions, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        let (welded, report) = mesh.welded(0.0).unwrap();
        assert_eq!(report.merged_vertices, 2);
        assert_eq!(welded.n_vertices(), 4);
        assert_eq!(welded.topology_report().components, 1);
    }
}
