//! Taubin λ|μ smoothing (Taubin 1995) as used by *Interactive editing of
//! multiresolution meshes* §4.2.

use edit::deform::SubMesh;
use edit::deform::{taubin, Smoother, SmoothingWeights, TaubinOptions};
use edit::Vertices;
use glam::DVec3;
use halfedge::generators;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use testkit::check::{bit_identical, volume};

/// A unit icosphere with radial noise.
fn noisy_sphere(level: usize, noise: f64) -> halfedge::Mesh {
    let mut mesh = generators::icosphere(level);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for p in mesh.positions_mut() {
        *p *= 1.0 + noise * rng.random_range(-1.0..1.0);
    }
    mesh
}

#[test]
fn taubin_keeps_sphere_volume_where_laplacian_shrinks_it() {
    for weights in [SmoothingWeights::Uniform, SmoothingWeights::Cotangent] {
        let original = noisy_sphere(4, 0.02);
        let v0 = volume(&original);
        let iterations = 50;

        let mut t = original.clone();
        let mut s = Smoother::new(&t, Vertices::All, weights, true).unwrap();
        s.taubin(&mut t, 0.33, -0.34, iterations).unwrap();
        let vt = volume(&t);

        let mut l = original.clone();
        let mut s = Smoother::new(&l, Vertices::All, weights, true).unwrap();
        // the same number of steps of plain Laplacian smoothing with λ
        s.laplacian(&mut l, 0.33, 2 * iterations).unwrap();
        let vl = volume(&l);

        let taubin_change = (vt / v0 - 1.0).abs();
        let laplace_loss = 1.0 - vl / v0;
        println!("{weights:?}: Taubin volume change {taubin_change:.4}, Laplacian loss {laplace_loss:.4}");
        assert!(
            taubin_change < 0.01,
            "{weights:?}: Taubin changed the volume by {taubin_change}"
        );
        assert!(
            laplace_loss > 0.2,
            "{weights:?}: Laplacian lost only {laplace_loss}"
        );

        // and Taubin did smooth: the radial noise went down (the part of the noise in
        // the pass band, k < 1/λ + 1/μ, stays: a low-pass filter)
        let spread = |m: &halfedge::Mesh| {
            let r: Vec<f64> = m.positions().iter().map(|p| p.length()).collect();
            let mean = r.iter().sum::<f64>() / r.len() as f64;
            (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64).sqrt() / mean
        };
        println!("spread {} -> {}", spread(&original), spread(&t));
        assert!(spread(&t) < 0.5 * spread(&original));
        t.check().unwrap();
    }
}

#[test]
fn identity_parameters_leave_positions_bit_identical() {
    identity_parameters_leave_positions_bit_identical_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn identity_parameters_leave_positions_bit_identical_on_real_meshes() {
    identity_parameters_leave_positions_bit_identical_with(&testkit::load_shared);
}

fn identity_parameters_leave_positions_bit_identical_with(load: &dyn Fn(&str) -> halfedge::Mesh) {
    let mut mesh = load("stanford-bunny.obj");
    let before = mesh.positions().to_vec();
    let zero = TaubinOptions::default().with_lambda(0.0).with_mu(0.0);
    taubin(&mut mesh, Vertices::All, &zero, 5).unwrap();
    taubin(&mut mesh, Vertices::All, &TaubinOptions::default(), 0).unwrap();
    assert!(bit_identical(&before, mesh.positions()));
}

#[test]
fn submesh_smoothing_moves_only_the_submesh_and_its_collar() {
    submesh_smoothing_moves_only_the_submesh_and_its_collar_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn submesh_smoothing_moves_only_the_submesh_and_its_collar_on_real_meshes() {
    submesh_smoothing_moves_only_the_submesh_and_its_collar_with(&testkit::load_shared);
}

fn submesh_smoothing_moves_only_the_submesh_and_its_collar_with(
    load: &dyn Fn(&str) -> halfedge::Mesh,
) {
    let mut mesh = load("stanford-bunny.obj");
    let before = mesh.positions().to_vec();
    let ear = testkit::regions::bunny_ear(&mesh);
    let sub = SubMesh::from_mask(
        &mesh,
        &halfedge::VertexData::new(&mesh, (ear).to_vec()).unwrap(),
    )
    .unwrap();
    let collar = sub.collars(&mesh, 1).unwrap().remove(0);
    let mut region = ear.clone();
    for &i in &collar {
        region[i as usize] = true;
    }
    let mut s = Smoother::for_submesh(&mesh, &sub, 1, SmoothingWeights::Cotangent, true).unwrap();
    s.taubin(&mut mesh, 0.33, -0.34, 10).unwrap();
    let mut moved = 0;
    for (i, (a, b)) in before.iter().zip(mesh.positions()).enumerate() {
        if region[i] {
            moved += (a != b) as usize;
        } else {
            assert_eq!(a, b, "vertex {i} outside the sub-mesh and its collar moved");
        }
    }
    assert!(moved > ear.iter().filter(|&&b| b).count() / 2);
    mesh.check().unwrap();
}

#[test]
fn whole_mesh_with_free_boundary_moves_boundary_vertices() {
    let mut mesh = generators::grid(6, 6, 1.0, 1.0);
    let corner = mesh.vertex_at(0).unwrap();
    mesh.set_position(corner, DVec3::new(0.0, 0.0, 0.3));
    let options = TaubinOptions::default().with_fix_boundary(false);
    taubin(&mut mesh, Vertices::All, &options, 3).unwrap();
    assert!(mesh.position(corner).z < 0.3);
}
