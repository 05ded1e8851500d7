//! The kernel on large meshes: for each cached input of `benches/common` (about 1, 2, 4
//! and 6 million faces: bunny ×2, nefertiti ×2, bunny ×3, horse ×3, subdivided 1-to-4),
//! loading the binary PLY, vertex normals, one-ring circulation over all vertices, and a
//! rounds hierarchy down to 2,000 faces refined back to the input.
//!
//! ```text
//! cargo run --release --example bench_cache      # prepare bench-cache/ ahead (optional)
//! cargo bench --bench large
//! MULTIRES_LARGE=1M cargo bench --bench large -- --quick   # one size
//! ```
//!
//! `MULTIRES_LARGE` (comma-separated labels `1M,2M,4M,6M`) limits the sizes, since every
//! size is loaded before criterion's own filter applies. Sample sizes are the minimum
//! (10) and measurement times short: one hierarchy round trip of a 6 M-face mesh takes
//! tens of seconds.

mod common;

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use halfedge::{Hierarchy, HierarchyOptions};

/// Sizes asked for by `MULTIRES_LARGE`, all by default.
fn sizes() -> Vec<common::Large> {
    let labels: Vec<String> = std::env::var("MULTIRES_LARGE")
        .unwrap_or_default()
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect();
    common::select(&labels).unwrap_or_else(|e| panic!("MULTIRES_LARGE: {e}"))
}

/// The hierarchy bench's rounds: planarity bound 90° so that rounds reach ~2,000 faces.
fn rounds_to_2000() -> HierarchyOptions {
    HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(2000)
}

fn large(c: &mut Criterion) {
    for input in sizes() {
        let path = input.cached();
        let mesh = input.load();
        eprintln!(
            "{}: {} vertices, {} faces ({})",
            input.label,
            common::thousands(mesh.n_vertices()),
            common::thousands(mesh.n_faces()),
            input.name()
        );
        let mut group = c.benchmark_group(format!("large_{}", input.label));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(5));
        group.throughput(Throughput::Elements(mesh.n_faces() as u64));

        group.bench_function("load binary PLY", |b| {
            b.iter_with_large_drop(|| halfedge::io::read(black_box(&path)).unwrap())
        });
        group.bench_function("vertex normals", |b| {
            b.iter_with_large_drop(|| black_box(&mesh).vertex_normals())
        });
        group.bench_function("one-ring circulation, rayon", |b| {
            b.iter(|| common::one_ring_sum_parallel(black_box(&mesh)))
        });
        group.bench_function("rounds hierarchy to 2,000 faces and back", |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| {
                    let mut h = Hierarchy::build(m, &rounds_to_2000()).unwrap();
                    h.refine_to(0).unwrap();
                    h
                },
                BatchSize::PerIteration,
            )
        });
        group.finish();
    }
}

criterion_group!(benches, large);
criterion_main!(benches);
