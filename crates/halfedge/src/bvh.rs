//! Picking along a ray and projecting onto a surface: a bounding volume hierarchy over
//! the triangles of a mesh, in `f64` (what the viewer uses to turn a click into a vertex,
//! and what a program uses to shoot rays at a mesh or find the nearest point of it).
//!
//! The hierarchy is built top-down by median splits of triangle centroids along the
//! longest axis of their bounds (subtrees built in parallel with `rayon::join` above a
//! size threshold) and stored flat in depth-first order: the left child of node `i` is
//! `i + 1`, the right child is stored in the node. After an edit that moves vertices but
//! keeps the connectivity, [`Bvh::refit`] recomputes the boxes bottom-up in `O(n)`
//! instead of rebuilding; [`Bvh::update`] does whichever of nothing, refit or rebuild the
//! mesh needs. Rays are tested with Möller–Trumbore and the traversal visits the nearer
//! child first and prunes boxes beyond the closest hit so far.
//! [`Bvh::closest_point`] visits the nearer box first too and prunes boxes farther than
//! the nearest point so far; the point–triangle test finds the Voronoi region of the
//! query among the triangle's corners, edges and inside ([`closest_point_on_triangle`]).
//!
//! A hierarchy keeps the [`Binding`] of the mesh it was built or refitted for: asked
//! about another mesh, or about its own mesh after a connectivity change or a move it was
//! not refitted for, it returns [`Error::Stale`] instead of a wrong answer.
//!
//! ```
//! use halfedge::bvh::{Bvh, Ray};
//! use glam::DVec3;
//! use halfedge::generators;
//! let mesh = generators::icosphere(3);
//! let bvh = Bvh::build(&mesh);
//! let ray = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z).unwrap();
//! let hit = bvh.intersect(&mesh, &ray).unwrap().expect("the sphere is in front");
//! assert!((hit.t - 4.0).abs() < 0.01); // the unit sphere's surface, up to its facets
//! assert!(mesh.triangle(hit.face).contains(&hit.nearest_vertex));
//! ```

use glam::DVec3;

use crate::binding::{Binding, Stale};
use crate::error::{Error, Result};
use crate::handle::{FaceId, VertexId};
use crate::mesh::Mesh;

/// Triangles per leaf at most.
const LEAF_SIZE: usize = 4;
/// Subtrees with more triangles than this are built in parallel.
const PARALLEL_THRESHOLD: usize = 16_384;

/// A ray `origin + t·direction`, `t > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point (an eye, a point above the surface).
    pub origin: DVec3,
    /// Direction; [`Ray::new`] makes it a unit vector, so that `t` is a distance.
    pub direction: DVec3,
}

impl Ray {
    /// A ray from `origin` along `direction` (normalised here).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a non-finite origin or a zero or non-finite
    /// direction.
    pub fn new(origin: DVec3, direction: DVec3) -> Result<Self> {
        match direction.try_normalize() {
            Some(d) if origin.is_finite() => Ok(Self {
                origin,
                direction: d,
            }),
            _ => Err(Error::InvalidArgument(format!(
                "a ray needs a finite origin and a non-zero finite direction, got {origin} and {direction}"
            ))),
        }
    }
    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.direction
    }
    /// Where the ray meets the plane through `point` with normal `normal` (dragging a
    /// point in a view plane); `None` when the ray is parallel to the plane, the plane is
    /// behind the origin, or an input is not finite.
    pub fn intersect_plane(&self, point: DVec3, normal: DVec3) -> Option<DVec3> {
        let denom = self.direction.dot(normal);
        if denom.is_nan() || denom.abs() < 1e-12 {
            return None;
        }
        let t = (point - self.origin).dot(normal) / denom;
        (t >= 0.0 && t.is_finite()).then(|| self.at(t))
    }
}

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The face hit first.
    pub face: FaceId,
    /// Ray parameter of the hit (a distance when the ray's direction is a unit vector).
    pub t: f64,
    /// The hit point.
    pub point: DVec3,
    /// Barycentric coordinates of the hit point for the corners of [`Mesh::triangle`],
    /// in order.
    pub barycentric: DVec3,
    /// The corner of the face nearest to the hit point: the picked vertex.
    pub nearest_vertex: VertexId,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first triangle in leaf order; inner: index of the right child.
    index: u32,
    /// Leaf: number of triangles (> 0); inner: 0.
    count: u32,
}

/// A bounding volume hierarchy over the live faces of a mesh (see the module docs).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Faces in leaf order.
    faces: Vec<FaceId>,
    /// Vertex indices (into `Mesh::positions`) of the faces in leaf order.
    corners: Vec<[u32; 3]>,
    /// The mesh as it was when built or last refitted (positions included).
    binding: Binding,
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
            binding: mesh.binding(),
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

    /// True when the hierarchy answers for `mesh` as it is now (same mesh, same
    /// connectivity, no position change since it was built or refitted).
    pub fn is_current(&self, mesh: &Mesh) -> bool {
        self.binding.fits_exactly(mesh)
    }

    /// `Ok` when the hierarchy is current for `mesh`, else [`Error::Stale`].
    fn check(&self, mesh: &Mesh) -> Result<()> {
        Ok(self.binding.check_exactly(mesh, "the BVH")?)
    }

    /// Recomputes every box for the current positions of the mesh it was built for.
    ///
    /// # Errors
    /// [`Error::Stale`] when `mesh` is another mesh or its connectivity changed since the
    /// build ([`build`](Self::build) again); the hierarchy is unchanged then.
    pub fn refit(&mut self, mesh: &Mesh) -> Result<()> {
        if !self.binding.same_connectivity(mesh) {
            return Err(Stale::new("the BVH", self.binding, mesh.binding()).into());
        }
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
        self.binding = mesh.binding();
        Ok(())
    }

    /// Makes the hierarchy current for `mesh`: nothing when it is, a
    /// [`refit`](Self::refit) when only positions changed, a new [`build`](Self::build)
    /// otherwise (another mesh, or changed connectivity).
    pub fn update(&mut self, mesh: &Mesh) {
        if self.is_current(mesh) {
            return;
        }
        if self.refit(mesh).is_err() {
            *self = Self::build(mesh);
        }
    }

    /// The nearest face hit by `ray` (front or back side), if any.
    ///
    /// # Errors
    /// [`Error::Stale`] when the hierarchy is not current for `mesh` (see
    /// [`is_current`](Self::is_current); [`update`](Self::update) makes it so).
    pub fn intersect(&self, mesh: &Mesh, ray: &Ray) -> Result<Option<Hit>> {
        self.check(mesh)?;
        if self.nodes.is_empty() {
            return Ok(None);
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
                let (l, r) = (&self.nodes[left], &self.nodes[right]);
                let dl = slab(l.lo, l.hi, ray.origin, inv, t_max);
                let dr = slab(r.lo, r.hi, ray.origin, inv, t_max);
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
        let Some((t, k, u, v)) = best else {
            return Ok(None);
        };
        let face = self.faces[k];
        let barycentric = DVec3::new(1.0 - u - v, u, v);
        let corners = mesh.triangle(face);
        let point = ray.at(t);
        let mut nearest_vertex = corners[0];
        for &c in &corners[1..] {
            if mesh.position(c).distance_squared(point)
                < mesh.position(nearest_vertex).distance_squared(point)
            {
                nearest_vertex = c;
            }
        }
        Ok(Some(Hit {
            face,
            t,
            point,
            barycentric,
            nearest_vertex,
        }))
    }

    /// The point of the mesh's surface nearest to `query`: the face it lies on, the
    /// point, its barycentric coordinates for the corners of [`Mesh::triangle`] and its
    /// distance (projecting a point onto a mesh, e.g. to carry values given at a mesh's
    /// vertices to points near its surface). Ties between faces go to the face met first
    /// by the traversal; faces with a corner that is not finite are never nearest;
    /// `None` for a mesh without any other face.
    ///
    /// # Errors
    /// [`Error::Stale`] when the hierarchy is not current for `mesh` (see
    /// [`is_current`](Self::is_current)); [`Error::InvalidArgument`] when `query` is not
    /// finite.
    pub fn closest_point(&self, mesh: &Mesh, query: DVec3) -> Result<Option<Nearest>> {
        self.check(mesh)?;
        if !query.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "closest_point: the query point {query} is not finite"
            )));
        }
        if self.nodes.is_empty() {
            return Ok(None);
        }
        let positions = mesh.positions();
        let mut best: Option<(f64, usize, DVec3, DVec3)> = None;
        let mut best_d2 = f64::INFINITY;
        let mut stack: Vec<(usize, f64)> = Vec::with_capacity(64);
        stack.push((
            0,
            box_distance_squared(self.nodes[0].lo, self.nodes[0].hi, query),
        ));
        while let Some((i, d2)) = stack.pop() {
            if d2 >= best_d2 {
                continue;
            }
            let node = &self.nodes[i];
            if node.count > 0 {
                let start = node.index as usize;
                for k in start..start + node.count as usize {
                    let [a, b, c] = self.corners[k].map(|j| positions[j as usize]);
                    let (point, barycentric) = closest_point_on_triangle(query, a, b, c);
                    let d2 = point.distance_squared(query);
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some((d2, k, point, barycentric));
                    }
                }
            } else {
                let (left, right) = (i + 1, node.index as usize);
                let dl = box_distance_squared(self.nodes[left].lo, self.nodes[left].hi, query);
                let dr = box_distance_squared(self.nodes[right].lo, self.nodes[right].hi, query);
                // The nearer child is popped first.
                if dl <= dr {
                    stack.push((right, dr));
                    stack.push((left, dl));
                } else {
                    stack.push((left, dl));
                    stack.push((right, dr));
                }
            }
        }
        Ok(best.map(|(d2, k, point, barycentric)| Nearest {
            face: self.faces[k],
            point,
            barycentric,
            distance: d2.sqrt(),
        }))
    }
}

/// The point of a surface nearest to a query ([`Bvh::closest_point`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// The face the point lies on.
    pub face: FaceId,
    /// The nearest point.
    pub point: DVec3,
    /// Barycentric coordinates of the point for the corners of [`Mesh::triangle`], in
    /// order (non-negative, summing to 1 up to rounding).
    pub barycentric: DVec3,
    /// Distance from the query to the point.
    pub distance: f64,
}

/// Squared distance from `p` to the box `[lo, hi]` (0 inside).
#[inline]
fn box_distance_squared(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    let d = (lo - p).max(p - hi).max(DVec3::ZERO);
    d.length_squared()
}

/// The point of triangle `abc` nearest to `p` and its barycentric coordinates, found by
/// the Voronoi region of `p` among the triangle's corners, edges and interior. A
/// degenerate triangle (a segment or a point) is handled by the same regions: its
/// nearest corner or edge point is returned.
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, DVec3::X);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, DVec3::Y);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + v * ab, DVec3::new(1.0 - v, v, 0.0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, DVec3::Z);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + w * ac, DVec3::new(1.0 - w, 0.0, w));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + w * (c - b), DVec3::new(0.0, 1.0 - w, w));
    }
    let sum = va + vb + vc;
    if !(sum > 0.0 && sum.is_finite()) {
        // Degenerate (collinear corners): the nearest of the three edges' points.
        let candidates = [
            segment_point(p, a, b).map(|t| (a + t * ab, DVec3::new(1.0 - t, t, 0.0))),
            segment_point(p, a, c).map(|t| (a + t * ac, DVec3::new(1.0 - t, 0.0, t))),
            segment_point(p, b, c).map(|t| (b + t * (c - b), DVec3::new(0.0, 1.0 - t, t))),
        ];
        return candidates
            .into_iter()
            .flatten()
            .min_by(|x, y| x.0.distance_squared(p).total_cmp(&y.0.distance_squared(p)))
            .unwrap_or((a, DVec3::X));
    }
    let denom = 1.0 / sum;
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, DVec3::new(1.0 - v - w, v, w))
}

/// Parameter in `[0, 1]` of the point of segment `ab` nearest to `p` (0 for a point
/// segment); `None` when it is not finite.
fn segment_point(p: DVec3, a: DVec3, b: DVec3) -> Option<f64> {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    t.is_finite().then_some(t)
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

/// Möller–Trumbore ray–triangle intersection, both sides: `(t, u, v)` with the hit at
/// `ray.at(t) = (1 − u − v)·a + u·b + v·c`, `t > 0`; `None` when the ray misses, runs
/// parallel to the triangle, or the triangle is degenerate.
#[inline]
pub fn ray_triangle(ray: &Ray, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = ray.direction.cross(e2);
    let det = e1.dot(p);
    if det.is_nan() || det.abs() < 1e-300 {
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
    if !(v >= 0.0 && u + v <= 1.0) {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    (t > 0.0).then_some((t, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    /// A small deterministic generator (no dev-dependency needed inside the crate).
    struct Lcg(u64);
    impl Lcg {
        fn unit(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
        fn vec(&mut self) -> DVec3 {
            DVec3::new(self.unit(), self.unit(), self.unit())
        }
    }

    fn brute_force(mesh: &Mesh, ray: &Ray) -> Option<(FaceId, f64)> {
        mesh.faces()
            .filter_map(|f| {
                let [a, b, c] = mesh.triangle_positions(f);
                ray_triangle(ray, a, b, c).map(|(t, _, _)| (f, t))
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
    }

    /// Random rays from a sphere around the mesh towards points inside its box; the BVH
    /// must find the brute-force nearest hit on every one.
    fn agrees_with_brute_force(mesh: &Mesh, bvh: &Bvh, rays: usize, seed: u64) {
        let mut rng = Lcg(seed);
        let (lo, hi) = mesh.bounding_box().unwrap();
        let centre = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length();
        let mut hits = 0;
        for _ in 0..rays {
            let origin = centre + 3.0 * radius * rng.vec().normalize();
            let aim = centre + 0.5 * (hi - lo) * rng.vec();
            let ray = Ray::new(origin, aim - origin).unwrap();
            let expected = brute_force(mesh, &ray);
            let got = bvh.intersect(mesh, &ray).unwrap();
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

    /// Random points around a mesh: the BVH's nearest point is as near as the brute
    /// force's over every face, lies on its face at its barycentric coordinates, and
    /// those are a convex combination.
    fn nearest_agrees_with_brute_force(mesh: &Mesh, bvh: &Bvh, queries: usize, seed: u64) {
        let mut rng = Lcg(seed);
        let (lo, hi) = mesh.bounding_box().unwrap();
        let centre = 0.5 * (lo + hi);
        let scale = (hi - lo).length();
        for _ in 0..queries {
            let q = centre + 0.8 * scale * rng.vec();
            let expected = mesh
                .faces()
                .map(|f| {
                    let [a, b, c] = mesh.triangle_positions(f);
                    closest_point_on_triangle(q, a, b, c).0.distance(q)
                })
                .fold(f64::INFINITY, f64::min);
            let got = bvh.closest_point(mesh, q).unwrap().unwrap();
            assert!(
                (got.distance - expected).abs() <= 1e-12 * scale,
                "{} vs {expected}",
                got.distance
            );
            let [a, b, c] = mesh.triangle_positions(got.face);
            let w = got.barycentric;
            assert!(w.min_element() >= 0.0 && (w.element_sum() - 1.0).abs() < 1e-12);
            assert!((w.x * a + w.y * b + w.z * c - got.point).length() < 1e-12 * scale);
            assert!((got.point.distance(q) - got.distance).abs() < 1e-12 * scale);
        }
    }

    #[test]
    fn closest_point_matches_brute_force_and_finds_vertices_exactly() {
        let mut mesh = generators::icosphere(3);
        for p in mesh.positions_mut() {
            *p = DVec3::new(p.x * 2.0, p.y + 0.3 * p.x * p.x, p.z * 0.5);
        }
        let bvh = Bvh::build(&mesh);
        nearest_agrees_with_brute_force(&mesh, &bvh, 300, 7);
        // A vertex is its own nearest point, with all its weight on it.
        for v in mesh.vertices().step_by(7) {
            let p = mesh.position(v);
            let got = bvh.closest_point(&mesh, p).unwrap().unwrap();
            assert_eq!(got.distance, 0.0);
            let corners = mesh.triangle(got.face);
            let k = corners
                .iter()
                .position(|&c| c == v)
                .expect("a face of the vertex");
            assert_eq!(got.barycentric[k], 1.0);
        }
        // Bad queries are refused, not answered.
        assert!(bvh
            .closest_point(&mesh, DVec3::new(f64::NAN, 0.0, 0.0))
            .is_err());
        // Faces with a corner that is not finite are skipped; with none left, no answer.
        let mut broken = mesh.clone();
        let far = DVec3::new(3.0, 0.0, 0.0);
        for p in broken.positions_mut() {
            if p.x > 0.0 {
                *p = DVec3::NAN;
            }
        }
        let nan_bvh = Bvh::build(&broken);
        let got = nan_bvh.closest_point(&broken, far).unwrap().unwrap();
        assert!(got.point.is_finite() && got.distance.is_finite());
        for p in broken.positions_mut() {
            *p = DVec3::INFINITY;
        }
        let inf_bvh = Bvh::build(&broken);
        assert_eq!(inf_bvh.closest_point(&broken, far).unwrap(), None);
        let other = generators::icosphere(2);
        assert!(bvh.closest_point(&other, DVec3::ZERO).is_err());
    }

    #[test]
    fn closest_point_on_degenerate_triangles_is_on_their_segment() {
        let (a, b) = (DVec3::ZERO, DVec3::X);
        // Collinear corners: the nearest point of the segment a–b.
        let (p, w) = closest_point_on_triangle(DVec3::new(0.25, 1.0, 0.0), a, b, 0.5 * b);
        assert!((p - DVec3::new(0.25, 0.0, 0.0)).length() < 1e-15);
        assert!((w.element_sum() - 1.0).abs() < 1e-15 && w.min_element() >= 0.0);
        // All corners at one point.
        let (p, _) = closest_point_on_triangle(DVec3::ONE, a, a, a);
        assert_eq!(p, a);
    }

    #[test]
    fn bvh_matches_brute_force_on_a_sphere() {
        let mesh = generators::icosphere(3);
        let bvh = Bvh::build(&mesh);
        assert_eq!(bvh.len(), mesh.n_faces());
        agrees_with_brute_force(&mesh, &bvh, 400, 1);
    }

    #[test]
    fn parallel_build_matches_brute_force() {
        // 20·4^5 = 20,480 faces: above the parallel threshold.
        let mesh = generators::icosphere(5);
        let bvh = Bvh::build(&mesh);
        agrees_with_brute_force(&mesh, &bvh, 200, 2);
    }

    #[test]
    fn refit_follows_moved_vertices_and_update_rebuilds_after_a_collapse() {
        let mut mesh = generators::icosphere(5);
        let mut bvh = Bvh::build(&mesh);
        for p in mesh.positions_mut() {
            *p = DVec3::new(p.x * 2.0, p.y + 0.3 * p.x * p.x, p.z * 0.5);
        }
        assert!(!bvh.is_current(&mesh));
        let ray = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z).unwrap();
        assert!(matches!(bvh.intersect(&mesh, &ray), Err(Error::Stale(_))));
        bvh.refit(&mesh).unwrap();
        agrees_with_brute_force(&mesh, &bvh, 200, 3);
        // A collapse changes the connectivity: refit is refused, update rebuilds.
        let e = mesh.halfedges().next().unwrap();
        mesh.collapse(e).unwrap();
        assert!(bvh.refit(&mesh).is_err());
        bvh.update(&mesh);
        assert_eq!(bvh.len(), mesh.n_faces());
        agrees_with_brute_force(&mesh, &bvh, 200, 5);
        // Another mesh is refused too.
        let other = generators::icosphere(5);
        assert!(bvh.intersect(&other, &ray).is_err());
    }

    #[test]
    fn grid_hit_from_above_picks_the_nearest_corner() {
        let mesh = generators::grid(10, 10, 1.0, 1.0);
        let bvh = Bvh::build(&mesh);
        let target = mesh.vertices().nth(37).unwrap();
        let p = mesh.position(target);
        let ray = Ray::new(p + DVec3::new(0.01, 0.015, 5.0), DVec3::NEG_Z).unwrap();
        let hit = bvh
            .intersect(&mesh, &ray)
            .unwrap()
            .expect("the grid is below");
        assert_eq!(hit.nearest_vertex, target);
        assert!((hit.t - 5.0).abs() < 1e-12);
        let miss = Ray::new(DVec3::new(5.0, 5.0, 5.0), DVec3::Z).unwrap();
        assert!(bvh.intersect(&mesh, &miss).unwrap().is_none());
    }

    #[test]
    fn empty_mesh_and_bad_rays() {
        let mesh = Mesh::new();
        let bvh = Bvh::build(&mesh);
        assert!(bvh.is_empty());
        let ray = Ray::new(DVec3::ZERO, DVec3::X).unwrap();
        assert!(bvh.intersect(&mesh, &ray).unwrap().is_none());
        assert!(Ray::new(DVec3::ZERO, DVec3::ZERO).is_err());
        assert!(Ray::new(DVec3::NAN, DVec3::X).is_err());
        assert!(Ray::new(DVec3::ZERO, DVec3::new(f64::INFINITY, 0.0, 0.0)).is_err());
        // A hand-made ray with a zero direction hits nothing and does not panic.
        let grid = generators::grid(4, 4, 1.0, 1.0);
        let bvh = Bvh::build(&grid);
        let zero = Ray {
            origin: DVec3::new(0.5, 0.5, 1.0),
            direction: DVec3::ZERO,
        };
        assert!(bvh.intersect(&grid, &zero).unwrap().is_none());
    }
}
