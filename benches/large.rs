//! The kernel and the hierarchy on large meshes: for each cached input of
//! `benches/common` (about 1, 2, 4, 6 and 18 million faces: bunny ×2, nefertiti ×2,
//! bunny ×3, horse ×3, bunny ×4, subdivided 1-to-4), loading the binary PLY, vertex
//! normals, one-ring circulation over all vertices, a rounds hierarchy down to 2,000
//! faces refined back to the input, and an edit of the coarsest level (a translation)
//! refined back to the input. After each input the process's peak resident memory so far
//! is printed (inputs go smallest first, so it is the peak of the largest input so far).
//!
//! ```text
//! cargo run --release --example bench_cache      # prepare bench-cache/ ahead (optional)
//! cargo bench --bench large
//! MULTIRES_LARGE=18M cargo bench --bench large   # one size
//! ```
//!
//! `MULTIRES_LARGE` (comma-separated labels `1M,2M,4M,6M,18M`) limits the sizes, since
//! every size is loaded before criterion's own filter applies. Sample sizes are
//! criterion's minimum (10) and measurement times short; the 18 M-face input (about
//! 4.5 minutes, 7 GB at most) runs each step ten times or so. Steps of inputs over 1.5 M
//! faces, which take a second or more, show progress on stderr (a bar for the hierarchy
//! build and refinement, a spinner for the others; silent when stderr is not a terminal).

use testkit::bench as common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::Mesh;
use multires::progress::{Bars, Progress};

/// Inputs with more faces than this show progress on every step.
const PROGRESS_FACES: usize = 1_500_000;

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

/// Current and peak resident memory of this process in bytes (`VmRSS`, `VmHWM` of
/// `/proc/self/status`; zero where that file does not exist).
fn rss() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |key: &str| {
        status
            .lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|kb| kb.parse::<u64>().ok())
            .map_or(0, |kb| kb << 10)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// Runs `f` under a spinner saying `what` when `show`.
fn step<T>(show: bool, what: &str, f: impl FnOnce() -> T) -> T {
    multires::progress::step(&mut Bars::new(show), what, f)
}

/// Builds the rounds hierarchy of `mesh` with a bar of the faces removed.
fn build(mesh: Mesh, show: bool) -> Hierarchy {
    let mut bar = Bars::new(show);
    bar.start("  hierarchy: faces removed", Some(mesh.n_faces() as u64));
    let h = Hierarchy::build_with_progress(mesh, &rounds_to_2000(), &mut |p| {
        bar.advance(
            (p.input_faces - p.faces) as u64,
            &format!("  hierarchy: faces removed, {} levels", p.levels),
        );
    })
    .unwrap();
    bar.finish();
    h
}

/// Refines `h` to the input a level at a time, with a bar of the levels.
fn refine_all(h: &mut Hierarchy, show: bool) {
    let coarsest = h.level_at_or_finer();
    let mut bar = Bars::new(show);
    bar.start("  refining: levels", Some(coarsest as u64));
    for (done, level) in (0..coarsest).rev().enumerate() {
        h.refine_to(level).unwrap();
        bar.advance(done as u64 + 1, "");
    }
    bar.finish();
}

fn large(c: &mut Criterion) {
    for input in sizes() {
        let show = input.faces > PROGRESS_FACES;
        let path = step(show, &format!("preparing {}", input.name()), || {
            input.cached()
        });
        let mesh = step(show, &format!("loading {}", input.name()), || input.load());
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
            b.iter_with_large_drop(|| {
                step(show, "  loading", || {
                    halfedge::io::read(black_box(&path)).unwrap()
                })
            })
        });
        group.bench_function("vertex normals", |b| {
            b.iter_with_large_drop(|| {
                step(show, "  vertex normals", || {
                    black_box(&mesh).vertex_normals()
                })
            })
        });
        group.bench_function("one-ring circulation, rayon", |b| {
            b.iter(|| common::one_ring_sum_parallel(black_box(&mesh)))
        });
        group.bench_function("rounds hierarchy to 2,000 faces and back", |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| {
                    let mut h = build(m, show);
                    refine_all(&mut h, show);
                    h
                },
                BatchSize::PerIteration,
            )
        });
        // The paper's use on one built hierarchy: walk back to the coarsest level
        // (untimed), translate the coarse mesh, refine to the input, which carries the
        // edit down through every split's centroid translation.
        let mut h = step(show, "building the hierarchy for the edit", || {
            let mut h = build(mesh.clone(), show);
            refine_all(&mut h, show);
            h
        });
        group.bench_function("edit at the coarsest level and refine", |b| {
            b.iter_custom(|iterations| {
                let mut total = Duration::ZERO;
                for _ in 0..iterations {
                    step(show, "  back to the coarsest level (untimed)", || {
                        h.go_to_level(h.coarsest_level()).unwrap()
                    });
                    let clock = Instant::now();
                    for p in h.mesh_mut().positions_mut() {
                        *p += DVec3::new(0.01, 0.0, 0.0);
                    }
                    refine_all(&mut h, show);
                    total += clock.elapsed();
                }
                total
            })
        });
        group.finish();
        drop(h);
        let (now, peak) = rss();
        eprintln!(
            "{}: peak resident memory so far {:.2} GiB ({} bytes per face of this input), now {:.2} GiB",
            input.label,
            peak as f64 / f64::from(1 << 30),
            peak / mesh.n_faces() as u64,
            now as f64 / f64::from(1 << 30),
        );
    }
}

criterion_group!(benches, large);
criterion_main!(benches);
