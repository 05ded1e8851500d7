//! Bendels & Klein editing at scale: fast marching on ~1 M vertices, the blend of a
//! 1 M-vertex deformable area, Euclidean fields for 10,000 border edges over 1 M
//! vertices, and one `α ⊙ A` (table and Padé).
//!
//! `cargo bench --bench blend` (add `-- <filter>` for one group). Inputs are built once
//! per group; sample sizes are small on purpose (whole-field operations take 0.1–1 s).

use testkit::bench as common;

use std::hint::black_box;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use edit::bendels_klein::affine_power::AffinePower;
use edit::bendels_klein::{
    BlendOptions, BlendSession, BorderGrid, DistanceKind, FastMarching, MarchSource, QueryPoints,
    Regions, Role, ShapeFunction,
};
use glam::{DMat4, DQuat, DVec3};
use halfedge::{generators, Mesh};

/// A 1000 × 1000 grid (≈ 1 M vertices) over the unit square, gently waved in z.
fn wavy_grid(n: usize) -> Mesh {
    let mut mesh = generators::grid(n, n, 1.0, 1.0);
    for p in mesh.positions_mut() {
        p.z = 0.05 * (6.0 * p.x).sin() * (4.0 * p.y).cos();
    }
    mesh
}

/// CPU time of all threads of this process in ns (Linux `schedstat`; 0 elsewhere).
fn process_cpu_ns() -> u64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

/// Runs `f` `iterations` times and prints wall and CPU time per run: on a loaded machine
/// the CPU time (divided by the cores in use) is what an idle machine would show.
/// Criterion calls a benchmark's closure once per sample: report only the first time.
fn cpu_report<T>(label: &str, iterations: u32, mut f: impl FnMut() -> T) {
    static DONE: Mutex<Vec<String>> = Mutex::new(Vec::new());
    {
        let mut done = DONE.lock().unwrap();
        if done.iter().any(|l| l == label) {
            return;
        }
        done.push(label.to_owned());
    }
    let (c0, w0) = (process_cpu_ns(), Instant::now());
    for _ in 0..iterations {
        black_box(f());
    }
    let wall = w0.elapsed().as_secs_f64() * 1e3 / f64::from(iterations);
    let cpu = (process_cpu_ns() - c0) as f64 / 1e6 / f64::from(iterations);
    eprintln!("[cpu] {label}: wall {wall:.2} ms, cpu {cpu:.2} ms per run");
}

fn timed<T>(label: &str, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    eprintln!("[setup] {label}: {:.3} s", start.elapsed().as_secs_f64());
    out
}

type MeshMaker = fn() -> Mesh;

fn fast_marching(c: &mut Criterion) {
    let mut group = c.benchmark_group("fast_marching");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(12));
    let inputs: [(&str, MeshMaker); 2] = [
        ("nefertiti_x2", common::nefertiti_x2),
        ("grid_1001x1001", || wavy_grid(1000)),
    ];
    for (name, make) in inputs {
        // Built on first use, so that filtered-out groups cost nothing.
        let mesh: OnceLock<Mesh> = OnceLock::new();
        let marching: OnceLock<FastMarching> = OnceLock::new();
        let mesh = || {
            mesh.get_or_init(|| {
                let m = timed(name, make);
                eprintln!("{name}: {} vertices, {} faces", m.n_vertices(), m.n_faces());
                m
            })
        };
        group.throughput(Throughput::Elements(if name == "nefertiti_x2" {
            799_506
        } else {
            1_002_001
        }));
        group.bench_function(BenchmarkId::new("precompute", name), |b| {
            let mesh = mesh();
            cpu_report(&format!("fast marching precompute, {name}"), 3, || {
                FastMarching::new(mesh)
            });
            b.iter(|| black_box(FastMarching::new(mesh)))
        });
        group.bench_function(BenchmarkId::new("march_from_a_vertex", name), |b| {
            let mesh = mesh();
            let marching = marching.get_or_init(|| {
                let m = FastMarching::new(mesh);
                let (unfolded, kept) = m.obtuse_corners();
                eprintln!("{name}: obtuse corners unfolded {unfolded}, kept {kept}");
                m
            });
            let source = MarchSource::point(mesh.vertex_index(mesh.vertices().next().unwrap()));
            cpu_report(&format!("fast marching from a vertex, {name}"), 3, || {
                marching.distances(&[source], None).unwrap()
            });
            b.iter(|| black_box(marching.distances(&[source], None).unwrap()))
        });
    }
    group.finish();
}

/// Grid regions: a small handle disc in the middle, a thin fixed frame at the border,
/// everything else (≈ 1 M vertices) deformable.
fn big_session(mesh: &Mesh) -> BlendSession {
    let centre = DVec3::new(0.5, 0.5, 0.0);
    let roles: Vec<Role> = mesh
        .positions()
        .iter()
        .map(|p| {
            let flat = DVec3::new(p.x, p.y, 0.0);
            if flat.distance(centre) < 0.02 {
                Role::Handle
            } else if p.x < 0.002 || p.x > 0.998 || p.y < 0.002 || p.y > 0.998 {
                Role::Fixed
            } else {
                Role::Deformable
            }
        })
        .collect();
    let roles = halfedge::VertexData::new(mesh, roles).expect("one role per vertex slot");
    let regions = Regions::from_roles(mesh, roles).expect("regions");
    BlendSession::new(
        mesh,
        regions,
        BlendOptions::default()
            .with_distance(DistanceKind::Euclidean)
            .with_shape(ShapeFunction::Smoothstep),
    )
    .expect("session")
}

fn blend(c: &mut Criterion) {
    let mut group = c.benchmark_group("blend");
    group.sample_size(20);
    let state: OnceLock<Mutex<(Mesh, BlendSession)>> = OnceLock::new();
    let state = || {
        state.get_or_init(|| {
            let mesh = wavy_grid(1000);
            let session = timed("session (Euclidean fields) on 1 M vertices", || {
                big_session(&mesh)
            });
            eprintln!(
                "blend: {} deformable vertices",
                session.regions().deformable().len()
            );
            Mutex::new((mesh, session))
        })
    };
    group.throughput(Throughput::Elements(992_764));
    let a = DMat4::from_translation(DVec3::new(0.1, 0.0, 0.3))
        * DMat4::from_quat(DQuat::from_axis_angle(
            DVec3::new(1.0, 2.0, 0.5).normalize(),
            1.1,
        ))
        * DMat4::from_scale(DVec3::new(1.2, 0.9, 1.1));
    group.bench_function("apply_1M_deformable", |b| {
        let mut guard = state().lock().unwrap();
        let (mesh, session) = &mut *guard;
        cpu_report("blend apply, 1 M deformable", 20, || {
            session.apply(mesh, a).unwrap()
        });
        b.iter(|| session.apply(black_box(mesh), black_box(a)).unwrap())
    });
    group.bench_function("set_shape_1M", |b| {
        let mut guard = state().lock().unwrap();
        let (_, session) = &mut *guard;
        b.iter(|| session.set_shape(black_box(ShapeFunction::Smootherstep)))
    });
    group.finish();
}

fn euclidean(c: &mut Criterion) {
    let mut group = c.benchmark_group("euclidean");
    group.sample_size(10);
    // The vertices of the waved 1001² grid, computed directly (no mesh needed).
    let n = 1000;
    let lift = |x: f64, y: f64| DVec3::new(x, y, 0.05 * (6.0 * x).sin() * (4.0 * y).cos());
    let points: Vec<DVec3> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| (i as f64 / n as f64, j as f64 / n as f64)))
        .map(|(x, y)| lift(x, y))
        .collect();
    // Mean edge length of the grid: (2 h + h√2) / 3.
    let h = 1.0 / n as f64;
    let cell = 2.0 * h * (2.0 + 2f64.sqrt()) / 3.0;
    // Two closed, wiggly border loops on the surface: 6,000 + 4,000 = 10,000 edges.
    let loop_of = |n: usize, r: f64, wiggle: f64, k: f64| -> Vec<(DVec3, DVec3)> {
        let at = |i: usize| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            let rr = r * (1.0 + wiggle * (k * t).sin());
            lift(0.5 + rr * t.cos(), 0.5 + rr * t.sin())
        };
        (0..n).map(|i| (at(i), at(i + 1))).collect()
    };
    let fixed_loop = loop_of(6000, 0.45, 0.05, 17.0);
    let handle_loop = loop_of(4000, 0.1, 0.2, 9.0);
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("build_grids_10k_edges", |b| {
        b.iter(|| {
            let f = BorderGrid::from_segments(cell, fixed_loop.iter().copied()).unwrap();
            let h = BorderGrid::from_segments(cell, handle_loop.iter().copied()).unwrap();
            black_box((f, h))
        })
    });
    let fixed = BorderGrid::from_segments(cell, fixed_loop.iter().copied()).unwrap();
    let handle = BorderGrid::from_segments(cell, handle_loop.iter().copied()).unwrap();
    group.bench_function("two_fields_10k_edges_1M_points", |b| {
        cpu_report("Euclidean fields, 10k edges, 1 M points", 5, || {
            let queries = QueryPoints::new(&points, cell);
            fixed.distances_to_pair(&handle, &queries)
        });
        b.iter(|| {
            let queries = QueryPoints::new(black_box(&points), cell);
            black_box(fixed.distances_to_pair(&handle, &queries))
        })
    });
    let queries = QueryPoints::new(&points, cell);
    // Exactness spot check against brute force.
    let d = fixed.distances_to(&queries);
    for i in (0..points.len()).step_by(99_991) {
        assert_eq!(d[i], fixed.distance_brute_force(points[i]));
    }
    group.bench_function("bucket_1M_points", |b| {
        b.iter(|| black_box(QueryPoints::new(black_box(&points), cell)))
    });
    group.bench_function("two_fields_prepared_two_walks", |b| {
        b.iter(|| black_box((fixed.distances_to(&queries), handle.distances_to(&queries))))
    });
    group.bench_function("two_fields_prepared_one_walk", |b| {
        b.iter(|| black_box(fixed.distances_to_pair(&handle, &queries)))
    });
    group.bench_function("one_field_6k_edges_prepared", |b| {
        b.iter(|| black_box(fixed.distances_to(&queries)))
    });
    group.finish();
}

fn exponential(c: &mut Criterion) {
    let mut group = c.benchmark_group("exp");
    let a = DMat4::from_translation(DVec3::new(0.3, -0.2, 0.5))
        * DMat4::from_quat(DQuat::from_axis_angle(
            DVec3::new(1.0, 2.0, 0.5).normalize(),
            2.5,
        ))
        * DMat4::from_scale(DVec3::new(1.5, 0.7, 1.2));
    group.bench_function("log_and_tables", |b| {
        b.iter(|| black_box(AffinePower::new(black_box(a)).unwrap()))
    });
    let power = AffinePower::new(a).unwrap();
    eprintln!("exp: table of (pieces, order) = {:?}", power.table_size());
    // 1024 points and weights, one exponentiation each per iteration.
    let alphas: Vec<f64> = (0..1024)
        .map(|k| (0.5 + k as f64 * 0.618_034) % 1.0)
        .collect();
    let points: Vec<DVec3> = (0..1024)
        .map(|k| DVec3::new(k as f64 * 1e-3, 0.2, 0.3))
        .collect();
    group.throughput(Throughput::Elements(1024));
    group.bench_function("1024_points_table", |b| {
        cpu_report("1024 × α ⊙ A on points, table", 2000, || {
            let mut sum = DVec3::ZERO;
            for (&alpha, &p) in alphas.iter().zip(&points) {
                sum += power.transform_point(black_box(alpha), p);
            }
            sum
        });
        b.iter(|| {
            let mut sum = DVec3::ZERO;
            for (&alpha, &p) in alphas.iter().zip(&points) {
                sum += power.transform_point(black_box(alpha), p);
            }
            black_box(sum)
        })
    });
    group.bench_function("1024_matrices_pade", |b| {
        cpu_report("1024 × exp(α log A), Padé", 500, || {
            let mut sum = DMat4::ZERO;
            for &alpha in &alphas {
                sum += power.matrix_pade(black_box(alpha));
            }
            sum
        });
        b.iter(|| {
            let mut sum = DMat4::ZERO;
            for &alpha in &alphas {
                sum += power.matrix_pade(black_box(alpha));
            }
            black_box(sum)
        })
    });
    group.finish();
}

criterion_group!(benches, exponential, blend, euclidean, fast_marching);
criterion_main!(benches);
