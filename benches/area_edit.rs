//! Lee 1999 area editing: embedding and drag updates (issue 4 targets: embedding a
//! 100,000-vertex area < 1 s; one drag of it < 5 ms; one drag of a 300-vertex area
//! < 50 µs; the paper: 266 ms to embed 300 vertices, 31 ms per edit, Pentium II 400 MHz).
//!
//! Inputs: nefertiti subdivided twice (≈ 800k vertices) with a disk of ≈ 100k vertices
//! grown by breadth-first rings from a front vertex; spot with a ≈ 300-vertex disk around
//! its snout.

use testkit::bench as common;

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use edit::lee::{
    AreaSession, EditingArea, Embedding, EmbeddingOptions, EmbeddingWeights, SessionOptions,
};
use halfedge::{Mesh, VertexId};

/// Nefertiti subdivided twice and a ≈ 100k-vertex disk around a front vertex.
fn large_area() -> (Mesh, EditingArea, VertexId) {
    let mesh = common::nefertiti_x2();
    let seed = mesh.vertex_at(25951).unwrap();
    let area = EditingArea::disk_around(&mesh, seed, 100_000).expect("a disk");
    (mesh, area, seed)
}

/// Spot and a ≈ 300-vertex disk around its snout.
fn small_area() -> (Mesh, EditingArea, VertexId) {
    let mesh = common::load_shared("spot.obj");
    let seed = mesh.vertex_at(1855).unwrap();
    let area = EditingArea::disk_around(&mesh, seed, 260).expect("a disk");
    (mesh, area, seed)
}

fn bench_area(
    c: &mut Criterion,
    label: &str,
    (mut mesh, area, seed): (Mesh, EditingArea, VertexId),
) {
    let n = area.vertices().len();
    eprintln!(
        "{label}: area of {n} vertices ({} interior, {} faces)",
        area.n_interior(),
        area.faces().len()
    );
    let mut group = c.benchmark_group(format!("area_edit/{label}"));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(if n > 10_000 { 15 } else { 3 }));
    group.bench_function(format!("embed_cotangent_{n}"), |b| {
        b.iter(|| Embedding::new(&mesh, black_box(&area), &EmbeddingOptions::default()).unwrap())
    });
    let mean_value = EmbeddingOptions::default().with_weights(EmbeddingWeights::MeanValue);
    group.bench_function(format!("embed_mean_value_{n}"), |b| {
        b.iter(|| Embedding::new(&mesh, black_box(&area), &mean_value).unwrap())
    });
    let parallel = SessionOptions::default().with_parallel_threshold(1);
    let mut sessions = vec![
        (
            "",
            AreaSession::new(&mesh, area.clone(), &SessionOptions::default()).unwrap(),
        ),
        (
            "parallel_",
            AreaSession::new(&mesh, area, &parallel).unwrap(),
        ),
    ];
    eprintln!("{label}: {} levels", sessions[0].1.levels());
    let normal = mesh.vertex_normal(seed);
    // the primitive: the seed and its one-ring (a closed chain with its centre)
    let primitive: Vec<VertexId> = std::iter::once(seed)
        .chain(mesh.adjacent_vertices(seed))
        .collect();
    group
        .sample_size(50)
        .measurement_time(Duration::from_secs(3));
    for (name, session) in &mut sessions {
        session.set_primitive(&mesh, &primitive).unwrap();
        for s in [0.25, 0.5, 1.0] {
            if !name.is_empty() && s != 0.5 {
                continue;
            }
            session.set_scale(s).unwrap();
            let mut k = 0u32;
            group.bench_function(format!("drag_{name}s{s}_{n}"), |b| {
                b.iter(|| {
                    k = k.wrapping_add(1);
                    let d = normal * (0.001 * f64::from(k % 100));
                    session.drag(&mut mesh, black_box(d)).unwrap();
                })
            });
        }
        session.cancel(&mut mesh).unwrap();
    }
    group.finish();
}

fn area_edit(c: &mut Criterion) {
    bench_area(c, "spot_300", small_area());
    bench_area(c, "nefertiti_100k", large_area());
}

criterion_group!(benches, area_edit);
criterion_main!(benches);
