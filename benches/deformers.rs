//! Speed of the deformers of issue 6 on a million vertices: Barr taper / twist / bend,
//! Taubin steps, FFD attach and deform, on nefertiti subdivided twice (0.8 M vertices,
//! a real scan) and on a waved 1001² grid (1.002 M vertices). Run with
//! `cargo bench --bench deformers`.

use testkit::bench as common;

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use edit::deform::{
    apply_deformer, AttachOptions, Bend, Ffd, LatticeFrame, Profile, Smoother, SmoothingWeights,
    Taper, Twist,
};
use edit::Vertices;
use glam::DVec3;
use halfedge::Mesh;

/// A 1001 × 1001 grid over the unit square, waved so that normals vary.
fn waved_grid() -> Mesh {
    let mut mesh = halfedge::generators::grid(1000, 1000, 1.0, 1.0);
    for p in mesh.positions_mut() {
        p.z = 0.05 * (6.0 * p.x).sin() * (4.0 * p.y).cos();
    }
    mesh
}

fn deformers(c: &mut Criterion) {
    for (name, mesh) in [
        ("nefertiti_x2", common::nefertiti_x2()),
        ("grid_1001", waved_grid()),
    ] {
        eprintln!(
            "bench mesh {name}: {} vertices, {} faces",
            mesh.n_vertices(),
            mesh.n_faces()
        );
        deformers_on(c, name, mesh);
    }
}

fn deformers_on(c: &mut Criterion, name: &str, mut mesh: Mesh) {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let centre = 0.5 * (lo + hi);
    let axis = DVec3::Y;
    let half = 0.5 * (hi.y - lo.y);

    let mut group = c.benchmark_group(format!("barr/{name}"));
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(4));
    let taper = Taper::new(
        centre,
        axis,
        Profile::local(-half, half, 1.0, 1.0001).unwrap(),
    )
    .unwrap();
    group.bench_function("taper", |b| {
        b.iter(|| apply_deformer(&mut mesh, &taper, Vertices::All).unwrap())
    });
    let twist = Twist::linear(centre, axis, -half, half, 1e-4).unwrap();
    group.bench_function("twist", |b| {
        b.iter(|| apply_deformer(&mut mesh, &twist, Vertices::All).unwrap())
    });
    let bend = Bend::new(centre, axis, DVec3::Z, 1e-4 / half, Some((-half, half))).unwrap();
    group.bench_function("bend", |b| {
        b.iter(|| apply_deformer(&mut mesh, &bend, Vertices::All).unwrap())
    });
    let inverse = bend.inverse();
    group.bench_function("bend inverse", |b| {
        b.iter(|| apply_deformer(&mut mesh, &inverse, Vertices::All).unwrap())
    });
    group.finish();

    let mut group = c.benchmark_group(format!("taubin/{name}"));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(4));
    group.bench_function("setup uniform (CSR)", |b| {
        b.iter(|| Smoother::new(&mesh, Vertices::All, SmoothingWeights::Uniform, true).unwrap())
    });
    group.bench_function("setup cotangent (CSR + weights)", |b| {
        b.iter(|| Smoother::new(&mesh, Vertices::All, SmoothingWeights::Cotangent, true).unwrap())
    });
    for weights in [SmoothingWeights::Uniform, SmoothingWeights::Cotangent] {
        let mut smoother = Smoother::new(&mesh, Vertices::All, weights, true).unwrap();
        group.bench_function(format!("one Laplacian step {weights:?}"), |b| {
            b.iter(|| smoother.laplacian(&mut mesh, 0.33, 1).unwrap())
        });
        group.bench_function(format!("one lambda|mu pair {weights:?}"), |b| {
            b.iter(|| smoother.taubin(&mut mesh, 0.33, -0.34, 1).unwrap())
        });
        group.bench_function(format!("ten lambda|mu pairs {weights:?}"), |b| {
            b.iter(|| smoother.taubin(&mut mesh, 0.33, -0.34, 10).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group(format!("ffd/{name}"));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    let attach = || {
        Ffd::covering(
            &mesh,
            Vertices::All,
            LatticeFrame::WORLD,
            ([3, 3], [6, 6]),
            ([2, 2], [4, 4]),
            0.05,
            AttachOptions::default(),
        )
        .unwrap()
    };
    group.bench_function("attach (cubic 6x6 shape, quadratic 4x4 height)", |b| {
        b.iter(attach)
    });
    let mut ffd = attach();
    ffd.bend(0.5).unwrap();
    ffd.scale_heights(1.1).unwrap();
    group.measurement_time(Duration::from_secs(4));
    group.sample_size(20);
    group.bench_function("deform", |b| b.iter(|| ffd.deform(&mut mesh).unwrap()));
    group.finish();
}

criterion_group!(benches, deformers);
criterion_main!(benches);
