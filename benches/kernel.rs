//! Kernel benches: building from indexed triangles (bunny, and nefertiti subdivided twice
//! ≈ 1.6 M faces), loading that mesh from a binary PLY and the bunny from OBJ, one-ring
//! circulation over all vertices, vertex normals.
//!
//! ```text
//! cargo bench --bench kernel
//! python3 benches/openmesh_reference.py   # OpenMesh on the same work, for comparison
//! ```
//!
//! The 1.6 M-face PLY is generated once into `bench-cache/` (git-ignored) at the
//! workspace root by `benches/common` (`cargo run --release --example bench_cache` prepares
//! it ahead). Builds and loads are timed without dropping the result
//! (`iter_with_large_drop`), as `openmesh_reference.py` times OpenMesh.

use std::hint::black_box;

mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::DVec3;
use halfedge::io;
use halfedge::Mesh;

fn soup(mesh: &Mesh) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let index = io::file_vertex_indices(mesh);
    let positions = mesh.vertices().map(|v| mesh.position(v)).collect();
    let triangles = mesh
        .faces()
        .map(|f| mesh.triangle(f).map(|v| index[mesh.vertex_index(v)]))
        .collect();
    (positions, triangles)
}

fn one_ring_sum(mesh: &Mesh) -> usize {
    mesh.vertices()
        .map(|v| {
            mesh.adjacent_vertices(v)
                .map(|w| mesh.vertex_index(w))
                .sum::<usize>()
        })
        .sum()
}

fn benches(c: &mut Criterion) {
    let bunny_path = common::meshes_dir().join("stanford-bunny.obj");
    let (bunny, _) = io::read(&bunny_path).unwrap();
    let big_path = common::NEFERTITI_X2.cached();
    let (big, _) = io::read(&big_path).unwrap();
    assert_eq!(big.n_faces(), 1_599_008);

    let mut group = c.benchmark_group("kernel");
    group.sample_size(10);

    let (positions, triangles) = soup(&bunny);
    group.bench_function("build bunny (69 k faces)", |b| {
        b.iter_with_large_drop(|| {
            Mesh::from_triangles(black_box(&positions), black_box(&triangles)).unwrap()
        })
    });
    let (positions, triangles) = soup(&big);
    group.bench_function("build nefertiti×2 (1.6 M faces)", |b| {
        b.iter_with_large_drop(|| {
            Mesh::from_triangles(black_box(&positions), black_box(&triangles)).unwrap()
        })
    });
    drop((positions, triangles));
    group.bench_function("load bunny OBJ", |b| {
        b.iter_with_large_drop(|| io::read(black_box(&bunny_path)).unwrap())
    });
    group.bench_function("load nefertiti×2 binary PLY (1.6 M faces)", |b| {
        b.iter_with_large_drop(|| io::read(black_box(&big_path)).unwrap())
    });
    group.bench_function("one-ring circulation, all vertices (0.8 M)", |b| {
        b.iter(|| one_ring_sum(black_box(&big)))
    });
    group.bench_function("one-ring circulation, all vertices (0.8 M), rayon", |b| {
        b.iter(|| common::one_ring_sum_parallel(black_box(&big)))
    });
    group.bench_function("vertex normals (0.8 M vertices)", |b| {
        b.iter(|| black_box(&big).vertex_normals())
    });
    group.bench_function("vertex normals bunny", |b| {
        b.iter(|| black_box(&bunny).vertex_normals())
    });
    group.finish();
}

criterion_group!(kernel, benches);
criterion_main!(kernel);
