//! Hierarchy speed (issue 3): the full hierarchy of nefertiti subdivided twice
//! (1.6 M faces) down to about 2,000 faces with every record kept, by rounds and by QEM,
//! coarsening and refining all the way back (as built, and after an edit of the
//! coarsest mesh, which makes every split compute its centroid translations), walking
//! back down to the coarsest level again, against meshoptimizer's `simplify` to 2,000
//! faces on the same mesh, in one group; saving the built hierarchy to a `.mrh` file and
//! loading it back (issue 30), against the build in the same group.
//!
//! Run: `cargo bench --bench hierarchy`.

use testkit::bench as common;

use std::sync::OnceLock;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions, SurvivorPlacement};
use halfedge::Mesh;

const TARGET_FACES: usize = 2000;

/// Nefertiti subdivided twice (from `bench-cache/`), loaded once per bench run.
fn big_mesh() -> &'static Mesh {
    static MESH: OnceLock<Mesh> = OnceLock::new();
    MESH.get_or_init(common::nefertiti_x2)
}

/// Rounds as the bench runs them: planarity bound 90° so that rounds reach ~2,000 faces.
fn rounds_options() -> HierarchyOptions {
    HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(TARGET_FACES)
}

fn qem_options() -> HierarchyOptions {
    HierarchyOptions::qem().with_target_faces(TARGET_FACES)
}

fn soup(mesh: &Mesh) -> (Vec<[f32; 3]>, Vec<u32>) {
    let positions: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|p| p.as_vec3().to_array())
        .collect();
    let indices = mesh
        .faces()
        .flat_map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v) as u32))
        .collect();
    (positions, indices)
}

fn bench(c: &mut Criterion) {
    let mesh = big_mesh();
    let mut group = c.benchmark_group("hierarchy_nefertiti_1.6M");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(30));

    let (positions, indices) = soup(mesh);
    let bytes: &[u8] = meshopt::typed_to_bytes(&positions);
    group.bench_function("meshopt_simplify_to_2000", |b| {
        b.iter(|| {
            let adapter = meshopt::VertexDataAdapter::new(bytes, 12, 0).unwrap();
            meshopt::simplify(
                &indices,
                &adapter,
                TARGET_FACES * 3,
                1e9,
                meshopt::SimplifyOptions::None,
                None,
            )
        })
    });

    for (name, options) in [("rounds", rounds_options()), ("qem", qem_options())] {
        let built = Hierarchy::build(mesh.clone(), &options).unwrap();
        eprintln!(
            "{name}: levels {:?}, {} records, {} MB of records ({:.1} bytes per collapse)",
            built.level_face_counts(),
            built.n_records(),
            built.record_bytes() >> 20,
            built.record_bytes() as f64 / built.n_records().max(1) as f64
        );
        group.bench_function(format!("{name}_coarsen_to_2000"), |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| Hierarchy::build(m, &options).unwrap(),
                BatchSize::LargeInput,
            )
        });
        // Issue 32: the same build on a one-thread pool (the parallel set-up on one
        // thread; the output buffers are still prefaulted by a thread of their own), so
        // that the scaling from one to all threads shows beside the row above.
        let one_thread = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        group.bench_function(format!("{name}_coarsen_to_2000, one thread"), |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| one_thread.install(|| Hierarchy::build(m, &options).unwrap()),
                BatchSize::LargeInput,
            )
        });
        // Issue 30: the hierarchy in a `.mrh` file and back, against the build above in
        // this group (load target ≤ 0.2 × the build).
        let file = std::env::temp_dir().join(format!("multires-bench-{name}.mrh"));
        group.bench_function(format!("{name}_save"), |b| {
            b.iter(|| built.save(&file).unwrap())
        });
        eprintln!(
            "{name}: .mrh file {} bytes ({:.1} per input face)",
            std::fs::metadata(&file).map_or(0, |m| m.len()),
            std::fs::metadata(&file).map_or(0, |m| m.len()) as f64 / mesh.n_faces() as f64
        );
        group.bench_function(format!("{name}_load"), |b| {
            b.iter_with_large_drop(|| Hierarchy::load(&file).unwrap())
        });
        group.bench_function(format!("{name}_refine_all"), |b| {
            b.iter_batched(
                || built.clone(),
                |mut h| {
                    h.refine_to(0).unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        });
        // Walking back to the coarsest level of a built hierarchy (what a level slider
        // does): the records are collapsed again, without the build's decisions.
        group.bench_function(format!("{name}_coarsen_again"), |b| {
            b.iter_batched(
                || {
                    let mut h = built.clone();
                    h.refine_to(0).unwrap();
                    h
                },
                |mut h| {
                    h.go_to_level(h.coarsest_level()).unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        });
        // The paper's use: an edit at the coarsest level (here a translation of the
        // whole coarse mesh), then refining carries it down through every record's
        // local frame (the worst case: every survivor moved).
        group.bench_function(format!("{name}_refine_all_after_coarse_edit"), |b| {
            b.iter_batched(
                || {
                    let mut h = built.clone();
                    for p in h.mesh_mut().positions_mut() {
                        *p += glam::DVec3::new(0.01, 0.0, 0.0);
                    }
                    h
                },
                |mut h| {
                    h.refine_to(0).unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        });
    }
    // Issue 32: rounds placing their survivors by the quadric (`SurvivorPlacement::Quadric`),
    // against `rounds_coarsen_to_2000` and meshoptimizer in this group (its quality
    // against theirs: `examples/simplify_quality.rs`).
    {
        let options = rounds_options().with_placement(SurvivorPlacement::Quadric);
        group.bench_function("rounds_quadric_placement_coarsen_to_2000", |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| Hierarchy::build(m, &options).unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    // A region edit of the coarsest mesh (half of it lifted by a ramp, marked as the
    // edit's region): refinement interpolates between moved and still parts, and the walk
    // ends by unfolding what it turned over (`Hierarchy::unfold_refinement`).
    {
        let built = Hierarchy::build(mesh.clone(), &rounds_options()).unwrap();
        let (lo, hi) = mesh.bounding_box().unwrap();
        let mid = 0.5 * (lo + hi);
        group.bench_function("rounds_refine_all_after_coarse_region_edit", |b| {
            b.iter_batched(
                || {
                    let mut h = built.clone();
                    let m = h.mesh();
                    let region: Vec<halfedge::VertexId> =
                        m.vertices().filter(|&v| m.position(v).x > mid.x).collect();
                    for &v in &region {
                        let p = h.mesh().position(v);
                        let ramp = ((p.x - mid.x) / (hi.x - mid.x)).powi(2);
                        let q = p + glam::DVec3::Z * (0.05 * (hi.z - lo.z) * ramp);
                        h.mesh_mut().set_position(v, q);
                    }
                    h.mark_region(&region).unwrap();
                    h
                },
                |mut h| {
                    h.refine_to(0).unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        });
    }
    // Issue 13: a frontier defined on the full mesh and made to hold at every level
    // (label the two sides of a plane through the middle, `constrain_to_labels`: the
    // records replayed, those near the frontier planned again), against
    // `rounds_coarsen_to_2000` (one build) in this group.
    {
        let options = rounds_options();
        let mut at_input = Hierarchy::build(mesh.clone(), &options).unwrap();
        at_input.refine_to(0).unwrap();
        let (lo, hi) = mesh.bounding_box().unwrap();
        let centre = 0.5 * (lo + hi);
        let axis = (hi - lo).max_position();
        let normal =
            glam::DVec3::from_array(std::array::from_fn(|k| f64::from(u8::from(k == axis))));
        group.bench_function("rounds_frontier_defined_and_held_at_every_level", |b| {
            b.iter_batched(
                || at_input.clone(),
                |mut h| {
                    let m = h.mesh_mut();
                    let frontier = m.frontier_from_plane(centre, normal).unwrap();
                    let (labels, _) = m.label_sides(&frontier, 3, 4).unwrap();
                    h.attach_labels(labels).unwrap();
                    h.constrain_to_labels().unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        });
    }
    // The same edit carried by the paper's centroid translations, for comparison.
    let mut paper = Hierarchy::build(
        mesh.clone(),
        &rounds_options().with_detail_mode(halfedge::hierarchy::DetailMode::Translation),
    )
    .unwrap();
    for p in paper.mesh_mut().positions_mut() {
        *p += glam::DVec3::new(0.01, 0.0, 0.0);
    }
    group.bench_function(
        "rounds_refine_all_after_coarse_edit_paper_translations",
        |b| {
            b.iter_batched(
                || paper.clone(),
                |mut h| {
                    h.refine_to(0).unwrap();
                    h
                },
                BatchSize::LargeInput,
            )
        },
    );
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
