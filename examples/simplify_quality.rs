//! How close each simplifier stays to the input (issue 32's quality table): the rounds
//! (midpoint and quadric placement), QEM and meshoptimizer's `simplify`, each to the same
//! face count, measured with `halfedge::surface_distance` (the input's vertices and
//! 100,000 area samples against the simplified surface, and the simplified surface's
//! vertices and samples against the input), over the diagonal of the input's bounding box.
//!
//! ```text
//! cargo run --release --example simplify_quality -- MESH... [--faces 2000]
//! ```
//!
//! Prints one markdown row per mesh and method; build times are single runs (the
//! benches measure speed, this measures quality).

use std::time::Instant;

use halfedge::hierarchy::{Hierarchy, HierarchyOptions, SurvivorPlacement};
use halfedge::surface_distance::{surface_distance, Sampling};
use halfedge::Mesh;

fn main() {
    let mut faces = 2000usize;
    let mut paths = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--faces" {
            faces = args
                .next()
                .and_then(|s| s.parse().ok())
                .expect("--faces takes a count");
        } else {
            paths.push(a);
        }
    }
    if paths.is_empty() {
        eprintln!("usage: simplify_quality MESH... [--faces N]");
        std::process::exit(2);
    }
    println!("| mesh | faces in | method | faces out | build s | mean in→out | mean out→in | Hausdorff |");
    println!("|---|---|---|---|---|---|---|---|");
    for path in &paths {
        let (mesh, _) = match halfedge::io::read(path) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{path}: {e}");
                continue;
            }
        };
        let name = std::path::Path::new(path)
            .file_name()
            .map_or(path.clone(), |n| n.to_string_lossy().into_owned());
        let rounds = HierarchyOptions::rounds()
            .with_max_normal_deviation(90f64.to_radians())
            .with_target_faces(faces);
        let runs: [(&str, Simplifier<'_>); 4] = [
            ("rounds, midpoint", Box::new(|| build(&mesh, &rounds))),
            (
                "rounds, quadric",
                Box::new(|| {
                    build(
                        &mesh,
                        &rounds.clone().with_placement(SurvivorPlacement::Quadric),
                    )
                }),
            ),
            (
                "QEM",
                Box::new(|| build(&mesh, &HierarchyOptions::qem().with_target_faces(faces))),
            ),
            ("meshoptimizer", Box::new(|| meshopt_simplify(&mesh, faces))),
        ];
        for (method, run) in runs {
            let start = Instant::now();
            let simplified = run();
            let seconds = start.elapsed().as_secs_f64();
            let d = surface_distance(&mesh, &simplified, &Sampling::default())
                .expect("both meshes have faces");
            println!(
                "| {name} | {} | {method} | {} | {seconds:.2} | {:.3e} | {:.3e} | {:.3e} |",
                mesh.n_faces(),
                simplified.n_faces(),
                d.forward.mean / d.diagonal,
                d.backward.mean / d.diagonal,
                d.hausdorff() / d.diagonal,
            );
        }
    }
}

/// One way to simplify the mesh, as the table names it.
type Simplifier<'a> = Box<dyn Fn() -> Mesh + 'a>;

/// The coarsest level of a hierarchy built with `options`.
fn build(mesh: &Mesh, options: &HierarchyOptions) -> Mesh {
    Hierarchy::build(mesh.clone(), options)
        .expect("the options are valid")
        .mesh()
        .clone()
}

/// meshoptimizer's `simplify` to `faces` triangles (target error unbounded), its output
/// made a mesh of the vertices it still uses.
fn meshopt_simplify(mesh: &Mesh, faces: usize) -> Mesh {
    let positions: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|p| p.as_vec3().to_array())
        .collect();
    let indices: Vec<u32> = mesh
        .faces()
        .flat_map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v) as u32))
        .collect();
    let adapter =
        meshopt::VertexDataAdapter::new(meshopt::typed_to_bytes(&positions), 12, 0).unwrap();
    let kept = meshopt::simplify(
        &indices,
        &adapter,
        (faces * 3).min(indices.len()),
        1e9,
        meshopt::SimplifyOptions::None,
        None,
    );
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut points = Vec::new();
    let triangles: Vec<[u32; 3]> = kept
        .chunks_exact(3)
        .map(|t| {
            [0, 1, 2].map(|k| {
                let v = t[k] as usize;
                if new_index[v] == u32::MAX {
                    new_index[v] = points.len() as u32;
                    points.push(mesh.positions()[v].to_array());
                }
                new_index[v]
            })
        })
        .collect();
    Mesh::from_arrays(&points, &triangles)
        .expect("meshoptimizer keeps a valid triangle list")
        .0
}
