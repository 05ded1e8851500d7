//! Collapse / vertex split: exact inverses, `check()` after every step, Euler
//! characteristic preserved, refusals change nothing.

use halfedge::{generators, CollapseVeto, Error, HalfedgeId, Mesh};
use rand::seq::IndexedRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use testkit::check::{euler, snapshot};

/// Collapses random legal halfedges until `fraction` of the vertices are gone, moving the
/// survivor to the midpoint, then splits in reverse order; asserts the mesh is restored
/// handle for handle and bit for bit.
fn roundtrip(mut mesh: Mesh, fraction: f64, seed: u64) {
    mesh.check().unwrap();
    let before = snapshot(&mesh);
    let chi = euler(&mesh);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let target = (mesh.n_vertices() as f64 * (1.0 - fraction)) as usize;
    let mut records = Vec::new();
    let mut stalled = 0;
    while mesh.n_vertices() > target && stalled < 5 {
        let candidates: Vec<HalfedgeId> = mesh
            .halfedges()
            .filter(|&h| mesh.is_collapse_ok(h).is_ok())
            .collect();
        if candidates.is_empty() {
            break;
        }
        let batch = (candidates.len() / 20).max(1);
        let mut done = 0;
        for _ in 0..batch {
            let h = *candidates.choose(&mut rng).unwrap();
            if mesh.is_collapse_ok(h).is_err() {
                continue;
            }
            let (p0, p1) = (
                mesh.position(mesh.from_vertex(h)),
                mesh.position(mesh.to_vertex(h)),
            );
            let record = mesh.collapse(h).unwrap();
            mesh.set_position(record.v1, 0.5 * (p0 + p1));
            mesh.check()
                .unwrap_or_else(|e| panic!("after collapse {}: {e}", records.len()));
            assert_eq!(
                euler(&mesh),
                chi,
                "a legal collapse changed the Euler characteristic"
            );
            records.push(record);
            done += 1;
            if mesh.n_vertices() <= target {
                break;
            }
        }
        stalled = if done == 0 { stalled + 1 } else { 0 };
    }
    assert!(!records.is_empty());
    for record in records.iter().rev() {
        mesh.vertex_split(record).unwrap();
        mesh.check().unwrap();
    }
    assert_eq!(snapshot(&mesh), before);
}

#[test]
fn roundtrip_icosphere() {
    roundtrip(generators::icosphere(3), 0.5, 1);
}

#[test]
fn roundtrip_grid_with_boundary() {
    roundtrip(generators::grid(12, 9, 1.0, 1.0), 0.5, 2);
}

#[test]
fn roundtrip_data_meshes() {
    // Small stand-ins: `check()` runs after every collapse.
    roundtrip_real_meshes_with(&|name: &str| {
        testkit::data(match name {
            "spot.obj" => "torus.obj",
            "cow.obj" => "creature.obj",
            "suzanne.obj" => "dirty.obj",
            _ => "cup.obj",
        })
    });
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn roundtrip_real_meshes() {
    roundtrip_real_meshes_with(&testkit::load_shared);
}

fn roundtrip_real_meshes_with(load: &dyn Fn(&str) -> Mesh) {
    for (name, seed) in [
        ("spot.obj", 3),
        ("cow.obj", 4),
        ("suzanne.obj", 5),
        ("teapot.obj", 6),
    ] {
        roundtrip(load(name), 0.5, seed);
    }
}

#[test]
fn refused_collapse_changes_nothing() {
    // A single triangle: every collapse would leave a degenerate triangle.
    let p = [glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::Y];
    let mesh = Mesh::from_triangles(&p, &[[0, 1, 2]]).unwrap().0;
    let mut m = mesh.clone();
    let before = snapshot(&m);
    let mut vetoes = Vec::new();
    for h in mesh.halfedges() {
        match m.collapse(h) {
            Err(Error::CollapseRefused { reason, .. }) => vetoes.push(reason),
            Err(e) => panic!("unexpected error {e}"),
            Ok(_) => {}
        }
        assert_eq!(snapshot(&m), before);
        if m.n_vertices() != mesh.n_vertices() {
            break;
        }
    }
    assert_eq!(vetoes.len(), 6);
    assert!(vetoes.iter().all(|v| matches!(
        v,
        CollapseVeto::LeftTriangleOnBoundary | CollapseVeto::RightTriangleOnBoundary
    )));
}

#[test]
fn stale_and_removed_handles_are_refused() {
    let mut mesh = generators::icosphere(1);
    let h = mesh.halfedges().next().unwrap();
    let record = mesh.collapse(h).unwrap();
    assert_eq!(mesh.is_collapse_ok(h), Err(CollapseVeto::EdgeDeleted));
    assert!(mesh.collapse(h).is_err());
    // Splitting twice is refused and changes nothing.
    mesh.vertex_split(&record).unwrap();
    let before = snapshot(&mesh);
    assert!(mesh.vertex_split(&record).is_err());
    assert_eq!(snapshot(&mesh), before);
    // Same vertex handle comes back.
    assert!(mesh.is_valid_vertex(record.v0));
}

#[test]
fn out_of_order_split_is_refused() {
    let mut mesh = generators::icosphere(2);
    let h = mesh.halfedges().next().unwrap();
    let first = mesh.collapse(h).unwrap();
    // Collapse an edge at v1 so the neighbourhood of the first record changes.
    let g = mesh
        .outgoing_halfedges(first.v1)
        .find(|&g| mesh.is_collapse_ok(g).is_ok())
        .unwrap();
    let _second = mesh.collapse(g).unwrap();
    let before = snapshot(&mesh);
    assert!(mesh.vertex_split(&first).is_err());
    assert_eq!(snapshot(&mesh), before);
}
