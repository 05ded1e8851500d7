//! Picking by ray casting against the `f64` mesh, accelerated by a bounding volume
//! hierarchy over the triangles.
//!
//! The BVH is built top-down by median splits of triangle centroids along the longest
//! axis of their bounds (subtrees built in parallel with `rayon::join` above a size
//! threshold), stored flat in depth-first order: the left child of node `i` is `i + 1`,
//! the right child is stored in the node. After an edit that moves vertices but keeps the
//! connectivity, [`Bvh::refit`] recomputes the boxes bottom-up in `O(n)` instead of
//! rebuilding. Rays are tested with Möller–Trumbore in `f64` and the traversal visits the
//! nearer child first and prunes boxes beyond the closest hit so far.
//!
//! A picked vertex is the corner of the hit triangle nearest to the hit point.

use glam::DVec3;
use halfedge::{FaceId, Mesh, VertexId};

use crate::camera::Ray;

/// Triangles per leaf at most.
const LEAF_SIZE: usize = 4;
/// Subtrees with more triangles than this are built in parallel.
const PARALLEL_THRESHOLD: usize = 16_384;

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The face hit first.
    pub face: FaceId,
    /// Ray parameter (distance along the unit ray direction).
    pub t: f64,
    /// The hit point.
    pub point: DVec3,
    /// Barycentric coordinates of the hit point for the corners of
    /// [`Mesh::triangle`] in order.
    pub barycentric: DVec3,
    /// The corner of the face nearest to the hit point.
    pub nearest_vertex: VertexId,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first triangle in `order`; inner: index of the right child.
    index: u32,
    /// Leaf: number of triangles (> 0); inner: 0.
    count: u32,
}

/// A bounding volume hierarchy over the live faces of a mesh (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Faces in leaf order.
    faces: Vec<FaceId>,
    /// Vertex indices (into `Mesh::positions`) of the faces in leaf order.
    corners: Vec<[u32; 3]>,
}

fn triangle_bounds(p: &[DVec3], c: [u32; 3]) -> (DVec3, DVec3) {
    let [a, b, d] = c.map(|i| p[i as usize]);
    (a.min(b).min(d), a.max(b).max(d))
}

impl Bvh {
    /// Builds the hierarchy over the live faces of `mesh`.
    pub fn build(mesh: &Mesh) -> Self {
        let faces: Vec<FaceId> = mesh.faces().collect();
        let corners: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| mesh.triangle(f).map(|v| mesh.vertex_index(v) as u32))
            .collect();
        let positions = mesh.positions();
        let mut items: Vec<(DVec3, u32)> = corners
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let (lo, hi) = triangle_bounds(positions, *c);
                (0.5 * (lo + hi), i as u32)
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
        if !items.is_empty() {
            build_recursive(positions, &corners, &mut items, 0, &mut nodes);
        }
        let order: Vec<u32> = items.iter().map(|&(_, i)| i).collect();
        Self {
            nodes,
            faces: order.iter().map(|&i| faces[i as usize]).collect(),
            corners: order.iter().map(|&i| corners[i as usize]).collect(),
        }
    }

    /// Number of triangles in the hierarchy.
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    /// True when the hierarchy holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// Recomputes every box for new positions of the same mesh (connectivity unchanged).
    pub fn refit(&mut self, mesh: &Mesh) {
        let positions = mesh.positions();
        // Children come after their parent in depth-first order: walk backwards.
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let (lo, hi) = if node.count > 0 {
                let start = node.index as usize;
                self.corners[start..start + node.count as usize]
                    .iter()
                    .map(|&c| triangle_bounds(positions, c))
                    .fold(
                        (DVec3::INFINITY, DVec3::NEG_INFINITY),
                        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
                    )
            } else {
                let (l, r) = (self.nodes[i + 1], self.nodes[node.index as usize]);
                (l.lo.min(r.lo), l.hi.max(r.hi))
            };
            self.nodes[i].lo = lo;
            self.nodes[i].hi = hi;
        }
    }

    /// The nearest face hit by `ray` (front or back side), if any.
    pub fn intersect(&self, mesh: &Mesh, ray: &Ray) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let positions = mesh.positions();
        let inv = DVec3::ONE / ray.direction;
        let mut best: Option<(f64, usize, f64, f64)> = None;
        let mut t_max = f64::INFINITY;
        let mut stack: Vec<usize> = Vec::with_capacity(64);
        stack.push(0);
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i];
            if slab(node.lo, node.hi, ray.origin, inv, t_max).is_none() {
                continue;
            }
            if node.count > 0 {
                let start = node.index as usize;
                for k in start..start + node.count as usize {
                    let [a, b, c] = self.corners[k].map(|j| positions[j as usize]);
                    if let Some((t, u, v)) = ray_triangle(ray, a, b, c) {
                        if t < t_max {
                            t_max = t;
                            best = Some((t, k, u, v));
                        }
                    }
                }
            } else {
                let (left, right) = (i + 1, node.index as usize);
                let dl = slab(
                    self.nodes[left].lo,
                    self.nodes[left].hi,
                    ray.origin,
                    inv,
                    t_max,
                );
                let dr = slab(
                    self.nodes[right].lo,
                    self.nodes[right].hi,
                    ray.origin,
                    inv,
                    t_max,
                );
                match (dl, dr) {
                    (Some(l), Some(r)) if l <= r => {
                        stack.push(right);
                        stack.push(left);
                    }
                    (Some(_), Some(_)) => {
                        stack.push(left);
                        stack.push(right);
                    }
                    (Some(_), None) => stack.push(left),
                    (None, Some(_)) => stack.push(right),
                    (None, None) => {}
                }
            }
        }
        let (t, k, u, v) = best?;
        let face = self.faces[k];
        let barycentric = DVec3::new(1.0 - u - v, u, v);
        let corners = mesh.triangle(face);
        let point = ray.at(t);
        let nearest_vertex = *corners
            .iter()
            .min_by(|&&a, &&b| {
                let da = mesh.position(a).distance_squared(point);
                let db = mesh.position(b).distance_squared(point);
                da.total_cmp(&db)
            })
            .expect("three corners");
        Some(Hit {
            face,
            t,
            point,
            barycentric,
            nearest_vertex,
        })
    }
}

fn build_recursive(
    positions: &[DVec3],
    corners: &[[u32; 3]],
    items: &mut [(DVec3, u32)],
    offset: usize,
    nodes: &mut Vec<Node>,
) {
    let (lo, hi) = items
        .iter()
        .map(|&(_, i)| triangle_bounds(positions, corners[i as usize]))
        .fold(
            (DVec3::INFINITY, DVec3::NEG_INFINITY),
            |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
        );
    let me = nodes.len();
    nodes.push(Node {
        lo,
        hi,
        index: offset as u32,
        count: items.len() as u32,
    });
    if items.len() <= LEAF_SIZE {
        return;
    }
    let (clo, chi) = items.iter().fold(
        (DVec3::INFINITY, DVec3::NEG_INFINITY),
        |(lo, hi), &(c, _)| (lo.min(c), hi.max(c)),
    );
    let extent = chi - clo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.0[axis].total_cmp(&b.0[axis]));
    let (left_items, right_items) = items.split_at_mut(mid);
    nodes[me].count = 0;
    if left_items.len() + right_items.len() > PARALLEL_THRESHOLD {
        // Each half is built into its own vector (indices relative to it), then shifted.
        let (left_nodes, right_nodes) = rayon::join(
            || {
                let mut n = Vec::new();
                build_recursive(positions, corners, left_items, offset, &mut n);
                n
            },
            || {
                let mut n = Vec::new();
                build_recursive(positions, corners, right_items, offset + mid, &mut n);
                n
            },
        );
        append_shifted(nodes, left_nodes);
        nodes[me].index = nodes.len() as u32;
        append_shifted(nodes, right_nodes);
    } else {
        build_recursive(positions, corners, left_items, offset, nodes);
        nodes[me].index = nodes.len() as u32;
        build_recursive(positions, corners, right_items, offset + mid, nodes);
    }
}

/// Appends a subtree built in its own vector, shifting its child indices.
fn append_shifted(nodes: &mut Vec<Node>, subtree: Vec<Node>) {
    let base = nodes.len() as u32;
    nodes.extend(subtree.into_iter().map(|mut n| {
        if n.count == 0 {
            n.index += base;
        }
        n
    }));
}

/// Entry distance of the ray into the box, if it enters before `t_max`.
#[inline]
fn slab(lo: DVec3, hi: DVec3, origin: DVec3, inv: DVec3, t_max: f64) -> Option<f64> {
    let t1 = (lo - origin) * inv;
    let t2 = (hi - origin) * inv;
    // NaN (0 · ∞ for a ray in a box face plane) is dropped by min/max.
    let tmin = t1.min(t2).max_element().max(0.0);
    let tmax = t1.max(t2).min_element().min(t_max);
    (tmin <= tmax).then_some(tmin)
}

/// Möller–Trumbore: `(t, u, v)` with the hit at `(1-u-v)·a + u·b + v·c`, both sides.
#[inline]
pub fn ray_triangle(ray: &Ray, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = ray.direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - a;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.direction.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    (t > 0.0).then_some((t, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;
    use rand::{Rng, SeedableRng};

    fn brute_force(mesh: &Mesh, ray: &Ray) -> Option<(FaceId, f64)> {
        mesh.faces()
            .filter_map(|f| {
                let [a, b, c] = mesh.triangle_positions(f);
                ray_triangle(ray, a, b, c).map(|(t, _, _)| (f, t))
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
    }

    /// A ray from a sphere around the box `(lo, hi)` towards a random point inside it.
    fn random_ray(rng: &mut impl Rng, lo: DVec3, hi: DVec3) -> Ray {
        let mut unit = || {
            DVec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
        };
        let centre = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length();
        let origin = centre + 3.0 * radius * unit().normalize();
        let aim = centre + 0.5 * (hi - lo) * unit();
        Ray {
            origin,
            direction: (aim - origin).normalize(),
        }
    }

    fn agrees_with_brute_force(mesh: &Mesh, bvh: &Bvh, rays: usize, seed: u64) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let (lo, hi) = mesh.bounding_box().unwrap();
        let radius = 0.5 * (hi - lo).length();
        let mut hits = 0;
        for _ in 0..rays {
            let ray = random_ray(&mut rng, lo, hi);
            let expected = brute_force(mesh, &ray);
            let got = bvh.intersect(mesh, &ray);
            match (expected, got) {
                (None, None) => {}
                (Some((_, t)), Some(hit)) => {
                    hits += 1;
                    assert!((hit.t - t).abs() <= 1e-9 * t.max(1.0), "{} vs {t}", hit.t);
                    let [a, b, c] = mesh.triangle_positions(hit.face);
                    let p = hit.barycentric.x * a + hit.barycentric.y * b + hit.barycentric.z * c;
                    assert!((p - hit.point).length() < 1e-9 * radius);
                    assert!(mesh.triangle(hit.face).contains(&hit.nearest_vertex));
                }
                (e, g) => panic!("brute force {e:?}, bvh {g:?}"),
            }
        }
        assert!(hits > rays / 4, "too few hits ({hits}) to test anything");
    }

    #[test]
    fn bvh_matches_brute_force_on_a_sphere() {
        let mesh = generators::icosphere(3);
        let bvh = Bvh::build(&mesh);
        assert_eq!(bvh.len(), mesh.n_faces());
        agrees_with_brute_force(&mesh, &bvh, 400, 1);
    }

    #[test]
    fn bvh_matches_brute_force_on_the_bunny() {
        // A real scan with holes and 1,113 isolated vertices (shared/meshes).
        let dir = std::env::var("MULTIRES_MESHES").map_or_else(
            |_| {
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .ancestors()
                    .map(|a| a.join("shared/meshes"))
                    .find(|p| p.is_dir())
                    .expect("shared/meshes not found above the crate; set MULTIRES_MESHES")
            },
            std::path::PathBuf::from,
        );
        let (mesh, _) = halfedge::io::read(dir.join("stanford-bunny.obj")).unwrap();
        let bvh = Bvh::build(&mesh);
        assert_eq!(bvh.len(), 69_451);
        agrees_with_brute_force(&mesh, &bvh, 100, 4);
    }

    #[test]
    fn parallel_build_matches_brute_force() {
        // 20·4^5 = 20,480 faces: above the parallel threshold.
        let mesh = generators::icosphere(5);
        let bvh = Bvh::build(&mesh);
        agrees_with_brute_force(&mesh, &bvh, 200, 2);
    }

    #[test]
    fn refit_follows_moved_vertices() {
        let mut mesh = generators::icosphere(5);
        let mut bvh = Bvh::build(&mesh);
        for p in mesh.positions_mut() {
            *p = DVec3::new(p.x * 2.0, p.y + 0.3 * p.x * p.x, p.z * 0.5);
        }
        bvh.refit(&mesh);
        agrees_with_brute_force(&mesh, &bvh, 200, 3);
    }

    #[test]
    fn grid_hit_from_above_picks_the_nearest_corner() {
        let mesh = generators::grid(10, 10, 1.0, 1.0);
        let bvh = Bvh::build(&mesh);
        let target = mesh.vertices().nth(37).unwrap();
        let p = mesh.position(target);
        let ray = Ray {
            origin: p + DVec3::new(0.01, 0.015, 5.0),
            direction: DVec3::NEG_Z,
        };
        let hit = bvh.intersect(&mesh, &ray).expect("the grid is below");
        assert_eq!(hit.nearest_vertex, target);
        assert!((hit.t - 5.0).abs() < 1e-12);
        let miss = Ray {
            origin: DVec3::new(5.0, 5.0, 5.0),
            direction: DVec3::Z,
        };
        assert!(bvh.intersect(&mesh, &miss).is_none());
    }

    #[test]
    fn empty_mesh_has_no_hits() {
        let mesh = Mesh::new();
        let bvh = Bvh::build(&mesh);
        assert!(bvh.is_empty());
        let ray = Ray {
            origin: DVec3::ZERO,
            direction: DVec3::X,
        };
        assert!(bvh.intersect(&mesh, &ray).is_none());
    }
}
