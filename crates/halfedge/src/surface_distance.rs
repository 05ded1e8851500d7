//! How far apart two surfaces are: one-sided and two-sided (Hausdorff) distances between
//! meshes, measured from sample points of one surface to the nearest point of the other,
//! the way Metro (Cignoni, Rocchini and Scopigno 1998, "Metro: measuring error on
//! simplified surfaces") measures a simplification's error.
//!
//! Each surface is sampled by its live vertices and by
//! [`Sampling::face_samples`] further points spread over its faces in proportion to their
//! area (stratified along the faces' cumulative area, barycentric coordinates from the R2
//! low-discrepancy sequence): the samples are a pure function of the mesh, so the same
//! meshes give the same distances bit for bit, on any number of threads. The nearest
//! point of the other surface comes from a [`Bvh`]; the sums are made per block of 4,096
//! samples and the blocks added in order.
//!
//! ```
//! use halfedge::generators;
//! use halfedge::surface_distance::{surface_distance, Sampling};
//! let fine = generators::icosphere(4);
//! let coarse = generators::icosphere(1);
//! let d = surface_distance(&fine, &coarse, &Sampling::default()).unwrap();
//! // The coarse sphere's flat faces lie inside the fine one: at most the sagitta of its
//! // longest edge apart, and never farther than the two spheres' radii differ.
//! assert!(d.hausdorff() > 0.0 && d.hausdorff() < 0.1);
//! assert!(d.forward.mean <= d.forward.max && d.backward.mean <= d.backward.max);
//! ```

use glam::DVec3;
use rayon::prelude::*;

use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::handle::FaceId;
use crate::mesh::Mesh;

/// How a surface is sampled for [`surface_distance`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampling {
    /// Sample every live vertex (default true).
    pub vertices: bool,
    /// Points spread over the faces in proportion to their area, besides the vertices
    /// (default 100,000).
    pub face_samples: usize,
}

impl Default for Sampling {
    fn default() -> Self {
        Self {
            vertices: true,
            face_samples: 100_000,
        }
    }
}

/// Distances from the samples of one surface to the other surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneSided {
    /// Number of sample points.
    pub samples: usize,
    /// Mean distance.
    pub mean: f64,
    /// Root mean square distance.
    pub rms: f64,
    /// Largest distance (the one-sided Hausdorff distance, up to the sampling).
    pub max: f64,
}

/// How far apart surfaces `a` and `b` are ([`surface_distance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDistance {
    /// From the samples of `a` to the surface of `b`.
    pub forward: OneSided,
    /// From the samples of `b` to the surface of `a`.
    pub backward: OneSided,
    /// The diagonal of `a`'s bounding box, the usual unit for reporting these distances.
    pub diagonal: f64,
}

impl SurfaceDistance {
    /// The two-sided Hausdorff distance: the larger of the two one-sided maxima.
    pub fn hausdorff(&self) -> f64 {
        self.forward.max.max(self.backward.max)
    }
    /// The mean distance over the samples of both sides together.
    pub fn mean(&self) -> f64 {
        let n = (self.forward.samples + self.backward.samples) as f64;
        if n == 0.0 {
            return 0.0;
        }
        (self.forward.mean * self.forward.samples as f64
            + self.backward.mean * self.backward.samples as f64)
            / n
    }
}

/// Distances between the surfaces of `a` and `b`, each sampled as `sampling` says (see
/// the module docs).
///
/// # Errors
/// [`Error::InvalidArgument`] when either mesh has no face, a live vertex of either is
/// not finite, or `sampling` asks for no sample at all or for more than
/// [`MAX_FACE_SAMPLES`].
pub fn surface_distance(a: &Mesh, b: &Mesh, sampling: &Sampling) -> Result<SurfaceDistance> {
    if !sampling.vertices && sampling.face_samples == 0 {
        return Err(Error::InvalidArgument(
            "surface_distance: the sampling takes neither vertices nor face samples".into(),
        ));
    }
    if sampling.face_samples > MAX_FACE_SAMPLES {
        return Err(Error::InvalidArgument(format!(
            "surface_distance: {} face samples asked, at most {MAX_FACE_SAMPLES}",
            sampling.face_samples
        )));
    }
    for (name, mesh) in [("first", a), ("second", b)] {
        check(name, mesh)?;
    }
    let (bvh_a, bvh_b) = rayon::join(|| Bvh::build(a), || Bvh::build(b));
    let forward = one_sided(a, b, &bvh_b, sampling)?;
    let backward = one_sided(b, a, &bvh_a, sampling)?;
    let diagonal = a.bounding_box().map_or(0.0, |(lo, hi)| lo.distance(hi));
    Ok(SurfaceDistance {
        forward,
        backward,
        diagonal,
    })
}

/// Refuses a mesh without faces or with a live vertex that is not finite.
fn check(name: &str, mesh: &Mesh) -> Result<()> {
    if mesh.n_faces() == 0 {
        return Err(Error::InvalidArgument(format!(
            "surface_distance: the {name} mesh has no face"
        )));
    }
    if let Some(v) = mesh.vertices().find(|&v| !mesh.position(v).is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "surface_distance: vertex {} of the {name} mesh is at {}, not a finite point",
            mesh.vertex_index(v),
            mesh.position(v)
        )));
    }
    Ok(())
}

/// The most face samples a measure takes (2³²: about an hour of queries on one core,
/// 32 MB of block sums).
pub const MAX_FACE_SAMPLES: usize = 1 << 32;

/// Samples per block whose sums are made on one thread.
const BLOCK: usize = 4096;

/// Sums of one block of samples: count, distance, squared distance, largest.
#[derive(Clone, Copy, Default)]
struct Sums {
    n: usize,
    sum: f64,
    sum2: f64,
    max: f64,
}

impl Sums {
    fn add(&mut self, d: f64) {
        self.n += 1;
        self.sum += d;
        self.sum2 += d * d;
        self.max = self.max.max(d);
    }
    fn merge(self, o: Self) -> Self {
        Self {
            n: self.n + o.n,
            sum: self.sum + o.sum,
            sum2: self.sum2 + o.sum2,
            max: self.max.max(o.max),
        }
    }
}

/// Distances from the samples of `from` to the surface of `to` (whose hierarchy is `bvh`).
fn one_sided(from: &Mesh, to: &Mesh, bvh: &Bvh, sampling: &Sampling) -> Result<OneSided> {
    let nearest = |p: DVec3| -> Result<f64> {
        Ok(bvh
            .closest_point(to, p)?
            .map_or(f64::INFINITY, |n| n.distance))
    };
    let mut total = Sums::default();
    if sampling.vertices {
        let slots = from.vertex_slots();
        let blocks: Vec<Sums> = (0..slots.div_ceil(BLOCK))
            .into_par_iter()
            .map(|k| {
                let mut s = Sums::default();
                for i in k * BLOCK..((k + 1) * BLOCK).min(slots) {
                    if let Some(v) = from.vertex_at(i) {
                        s.add(nearest(from.position(v))?);
                    }
                }
                Ok(s)
            })
            .collect::<Result<_>>()?;
        total = blocks.into_iter().fold(total, Sums::merge);
    }
    if sampling.face_samples > 0 {
        let sampler = FaceSampler::new(from);
        let n = sampling.face_samples;
        let blocks: Vec<Sums> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|k| {
                let mut s = Sums::default();
                for j in k * BLOCK..((k + 1) * BLOCK).min(n) {
                    s.add(nearest(sampler.sample(j, n))?);
                }
                Ok(s)
            })
            .collect::<Result<_>>()?;
        total = blocks.into_iter().fold(total, Sums::merge);
    }
    let n = total.n.max(1) as f64;
    Ok(OneSided {
        samples: total.n,
        mean: total.sum / n,
        rms: (total.sum2 / n).sqrt(),
        max: total.max,
    })
}

/// Points spread over a mesh's faces in proportion to their area (see the module docs).
/// Keeps the live faces and their cumulative areas (16 bytes per face), not their corners.
struct FaceSampler<'a> {
    mesh: &'a Mesh,
    /// The live faces, in slot order.
    faces: Vec<FaceId>,
    /// Cumulative areas: `cumulative[i]` is the area of faces `0..=i`.
    cumulative: Vec<f64>,
}

impl<'a> FaceSampler<'a> {
    fn new(mesh: &'a Mesh) -> Self {
        let faces: Vec<FaceId> = mesh.faces().collect();
        let mut area = 0.0;
        let cumulative = faces
            .iter()
            .map(|&f| {
                let [a, b, c] = mesh.triangle_positions(f);
                area += 0.5 * (b - a).cross(c - a).length();
                area
            })
            .collect();
        Self {
            mesh,
            faces,
            cumulative,
        }
    }

    /// Sample `j` of `n`: the triangle where the `(j + ½) / n` quantile of the area falls,
    /// at barycentric coordinates from the R2 sequence's point `j`. On a surface of zero
    /// area the samples go to the faces in turn, at the same coordinates.
    fn sample(&self, j: usize, n: usize) -> DVec3 {
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        let t = if total > 0.0 {
            let u = (j as f64 + 0.5) / n as f64 * total;
            self.cumulative
                .partition_point(|&c| c <= u)
                .min(self.faces.len() - 1)
        } else {
            j % self.faces.len()
        };
        // R2 (Roberts 2018): the plastic number's powers give well-spread pairs.
        const A1: f64 = 0.754_877_666_246_692_8;
        const A2: f64 = 0.569_840_290_998_053_3;
        let (mut r1, mut r2) = (
            (0.5 + A1 * (j as f64 + 1.0)).fract(),
            (0.5 + A2 * (j as f64 + 1.0)).fract(),
        );
        if r1 + r2 > 1.0 {
            (r1, r2) = (1.0 - r1, 1.0 - r2);
        }
        let [a, b, c] = self.mesh.triangle_positions(self.faces[t]);
        a + r1 * (b - a) + r2 * (c - a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    fn sampling(vertices: bool, face_samples: usize) -> Sampling {
        Sampling {
            vertices,
            face_samples,
        }
    }

    #[test]
    fn a_mesh_is_at_distance_zero_from_itself() {
        let mesh = generators::icosphere(3);
        let d = surface_distance(&mesh, &mesh, &Sampling::default()).unwrap();
        // Samples on a face are projected back onto it up to rounding.
        assert!(d.hausdorff() < 1e-12, "{d:?}");
        assert_eq!(d.forward.samples, mesh.n_vertices() + 100_000);
    }

    #[test]
    fn a_translated_plane_is_at_the_translation() {
        // A flat grid moved along its normal: every sample of either side is exactly
        // that far from the other (the grid is wide, so the borders matter little;
        // the samples near a border still have a nearest point straight across).
        let a = generators::grid(20, 20, 1.0, 1.0);
        let mut b = a.clone();
        let shift = DVec3::new(0.0, 0.0, 0.25);
        for p in b.positions_mut() {
            *p += shift;
        }
        let d = surface_distance(&a, &b, &sampling(true, 10_000)).unwrap();
        for side in [d.forward, d.backward] {
            assert!((side.mean - 0.25).abs() < 1e-12, "{d:?}");
            assert!((side.rms - 0.25).abs() < 1e-12, "{d:?}");
            assert!((side.max - 0.25).abs() < 1e-12, "{d:?}");
        }
    }

    #[test]
    fn spheres_are_as_far_apart_as_their_radii() {
        // A fine sphere scaled by 1.1: its samples are 0.1 (up to the facets) from the
        // unit sphere; from the unit sphere's samples the nearest point of the larger
        // one is 0.1 away too, up to the facets.
        let a = generators::icosphere(5);
        let mut b = a.clone();
        for p in b.positions_mut() {
            *p *= 1.1;
        }
        let d = surface_distance(&a, &b, &Sampling::default()).unwrap();
        for side in [d.forward, d.backward] {
            assert!((side.mean - 0.1).abs() < 2e-3, "{d:?}");
            assert!(side.max <= 0.1 + 1e-9, "{d:?}");
        }
        assert!(
            (d.diagonal - 2.0 * 3f64.sqrt()).abs() < 1e-2,
            "{}",
            d.diagonal
        );
    }

    #[test]
    fn face_samples_find_what_vertices_miss() {
        // A bump in the middle of one face of `b`: `a`'s vertices (the grid's) see none
        // of it from one side, but `b`'s samples on the bump's faces do.
        let a = generators::grid(4, 4, 1.0, 1.0);
        let mut b = a.clone();
        let centre = b
            .vertices()
            .min_by(|&u, &v| {
                let c = DVec3::new(0.5, 0.5, 0.0);
                b.position(u)
                    .distance(c)
                    .total_cmp(&b.position(v).distance(c))
            })
            .unwrap();
        let p = b.position(centre);
        b.set_position(centre, p + DVec3::new(0.0, 0.0, 1.0));
        let only_vertices = surface_distance(&a, &b, &sampling(true, 0)).unwrap();
        let with_faces = surface_distance(&a, &b, &sampling(true, 20_000)).unwrap();
        assert!((only_vertices.backward.max - 1.0).abs() < 1e-12);
        assert!(with_faces.backward.mean > only_vertices.backward.mean);
        assert!(with_faces.backward.samples == only_vertices.backward.samples + 20_000);
    }

    #[test]
    fn face_samples_follow_the_area_and_stay_on_their_face() {
        // Two triangles sharing an edge, of areas 1/2 and 3/2: a quarter of the samples
        // on the first (x < 1), three quarters on the second, every one inside.
        let mesh = Mesh::from_arrays(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [4.0, 1.0, 0.0],
            ],
            &[[0, 1, 2], [1, 3, 2]],
        )
        .unwrap()
        .0;
        let sampler = FaceSampler::new(&mesh);
        let n = 4000;
        let points: Vec<DVec3> = (0..n).map(|j| sampler.sample(j, n)).collect();
        let first = points.iter().filter(|p| p.x < 1.0).count();
        assert_eq!(first, n / 4);
        for p in &points {
            let on_first = p.y <= p.x + 1e-12 && p.x <= 1.0;
            let on_second = p.x >= 1.0 - 1e-12 && p.y >= (p.x - 1.0) / 3.0 - 1e-12 && p.y <= 1.0;
            assert!(on_first || on_second, "{p} is off the mesh");
        }
        // Spread within each face: the samples on the second face are not all in a corner.
        let (lo, hi) = points
            .iter()
            .filter(|p| p.x >= 1.0)
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        assert!(hi.x - lo.x > 2.5 && hi.y - lo.y > 0.8, "{lo} {hi}");
    }

    #[test]
    fn the_same_on_any_number_of_threads() {
        let a = generators::icosphere(4);
        let b = generators::icosphere(2);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| surface_distance(&a, &b, &Sampling::default()).unwrap())
        };
        let one = run(1);
        for threads in [2, 3, 5] {
            let other = run(threads);
            for (x, y) in [(one.forward, other.forward), (one.backward, other.backward)] {
                assert_eq!(x.mean.to_bits(), y.mean.to_bits());
                assert_eq!(x.rms.to_bits(), y.rms.to_bits());
                assert_eq!(x.max.to_bits(), y.max.to_bits());
            }
        }
    }

    #[test]
    fn bad_input_is_refused_with_a_reason() {
        let sphere = generators::icosphere(1);
        let empty = Mesh::new();
        let e = surface_distance(&sphere, &empty, &Sampling::default()).unwrap_err();
        assert!(e.to_string().contains("second mesh has no face"), "{e}");
        let e = surface_distance(&sphere, &sphere, &sampling(false, 0)).unwrap_err();
        assert!(e.to_string().contains("neither"), "{e}");
        // Refused before anything is allocated for them.
        let e = surface_distance(&sphere, &sphere, &sampling(true, usize::MAX)).unwrap_err();
        assert!(e.to_string().contains("at most 4294967296"), "{e}");
        let mut bad = sphere.clone();
        let v = bad.vertices().nth(3).unwrap();
        bad.set_position(v, DVec3::new(f64::NAN, 0.0, 0.0));
        let e = surface_distance(&bad, &sphere, &Sampling::default()).unwrap_err();
        assert!(
            e.to_string().contains("of the first mesh is at [NaN"),
            "{e}"
        );
    }
}
