//! Picking speed on real meshes: building and refitting the BVH, and casting rays.
//!
//! `cargo bench -p viewer --bench picking` (add `-- --quick` while developing). Inputs:
//! nefertiti (99,938 faces) from `shared/meshes` and its 1-to-4 subdivision (399,752
//! faces); `MULTIRES_MESHES` overrides the folder.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::DVec3;
use halfedge::{generators, Mesh};
use rand::{Rng, SeedableRng};
use viewer::camera::Ray;
use viewer::pick::Bvh;

/// Rays from a sphere around the mesh towards random points inside its box.
fn rays(mesh: &Mesh, n: usize) -> Vec<Ray> {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let centre = 0.5 * (lo + hi);
    let radius = 0.5 * (hi - lo).length();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut unit = || {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    };
    (0..n)
        .map(|_| {
            let origin = centre + 3.0 * radius * unit().normalize();
            let aim = centre + 0.5 * (hi - lo) * unit();
            Ray {
                origin,
                direction: (aim - origin).normalize(),
            }
        })
        .collect()
}

fn picking(c: &mut Criterion) {
    let (nefertiti, _) = halfedge::io::read(testkit::shared_mesh("nefertiti.obj")).unwrap();
    let subdivided = generators::subdivide(&nefertiti);
    let mut group = c.benchmark_group("picking");
    group.sample_size(10);
    for (name, mesh) in [("nefertiti", &nefertiti), ("nefertiti-x4", &subdivided)] {
        let faces = mesh.n_faces();
        group.bench_with_input(
            BenchmarkId::new("bvh_build", format!("{name}/{faces}")),
            mesh,
            |b, m| b.iter(|| Bvh::build(m)),
        );
        let mut bvh = Bvh::build(mesh);
        group.bench_with_input(
            BenchmarkId::new("bvh_refit", format!("{name}/{faces}")),
            mesh,
            |b, m| b.iter(|| bvh.refit(m)),
        );
        let rays = rays(mesh, 1000);
        group.bench_with_input(
            BenchmarkId::new("1000_rays", format!("{name}/{faces}")),
            mesh,
            |b, m| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| matches!(bvh.intersect(m, r), Ok(Some(_))))
                        .count()
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, picking);
criterion_main!(benches);
